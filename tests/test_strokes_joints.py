"""Junctions that stay attached when a limb turns (issue 25).

A turned limb's root lies inside its parent's body (a starfish's arm in
its disk): the body stays whole (no notch, no wedge), no hairline or
outline is left inside the object where the turned root meets a kept
limb, and the object stays one piece. Procedural starfish
(:func:`branchnb.strokes.procedural.starfish`) of several sizes, flat
and outlined, the truth known.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.strokes import edit_structure
from branchnb.strokes.joints import close_hairlines, hold_joint_bodies
from branchnb.strokes.procedural import starfish

EIGHT = np.ones((3, 3))


def _turn(st, th, about):
    c, s = np.cos(th), np.sin(th)
    return (st - about) @ np.array([[c, -s], [s, c]]).T + about


def _edit(obj, th=0.5, arm=3):
    """Arm 1 and ``arm`` stroked from the centre, ``arm`` turned by ``th`` about it."""
    c = obj.strokes[1][0]
    src = [obj.strokes[1], obj.strokes[arm]]
    return edit_structure(obj.image, src, [src[0], _turn(src[1], th, c)]), c


def _disk(obj, c, margin):
    n = obj.image.shape[0]
    yy, xx = np.mgrid[0:n, 0:n]
    return np.hypot(xx - c[0], yy - c[1]) <= 0.12 * n - margin


def _flat(obj):
    """The starfish in one flat colour, no outline (its alpha kept)."""
    img = obj.image.copy()
    img[..., :3] = (0.85, 0.45, 0.2)
    return img


@pytest.mark.parametrize("size,th", [(160, 0.5), (300, 0.5), (240, -0.6)])
def test_a_turned_arm_leaves_the_disk_whole(size, th):
    """Before: the turned arm took the part of the disk its source tube covered,
    13 and 114 px of the disk open at 160 and 300 px (a notch)."""
    obj = starfish(size, rng=1)
    res, c = _edit(obj, th)
    disk = _disk(obj, c, obj.outline + 1)
    assert int((disk & (res.image[..., 3] < 0.5)).sum()) == 0
    assert ndi.label(res.image[..., 3] > 0.02, structure=EIGHT)[1] == 1
    # the turned arm is there, the kept ones too
    tip = _turn(obj.strokes[3], th, c)[-2]
    assert res.image[int(round(tip[1])), int(round(tip[0])), 3] > 0.5
    for k in (2, 4, 5):
        x, y = np.rint(obj.strokes[k][-2]).astype(int)
        assert res.image[y, x, 3] > 0.5, obj.names[k]


@pytest.mark.parametrize("size", [160, 300])
def test_no_hairline_where_a_turned_root_meets_a_kept_arm(size):
    """A flat starfish: no partly transparent pixel inside the disk (before: a faint
    line where the turned arm's anti-aliased edge met the kept arm's)."""
    obj = starfish(size, rng=0)
    obj.image = _flat(obj)
    res, c = _edit(obj)
    disk = _disk(obj, c, 1.5)
    assert int((disk & (res.image[..., 3] < 0.9)).sum()) == 0


@pytest.mark.parametrize("size", [160, 300])
def test_outline_does_not_run_into_a_turned_joint(size):
    """Outline-coloured pixels more than the outline width + 2 px inside the silhouette
    (the source has none): before 20 and 19 at 160 and 300 px."""
    obj = starfish(size, rng=0)
    res, _ = _edit(obj)
    m = res.image[..., 3] > 0.5
    deep = ndi.distance_transform_edt(m) > obj.outline + 2
    ink = int((deep & (res.image[..., :3].mean(axis=2) < 0.2)).sum())
    assert ink <= 0.07 * size


def test_hold_joint_bodies_fills_only_open_pixels():
    layer = np.zeros((11, 11, 4), np.float32)
    layer[:, :5] = (1.0, 0.0, 0.0, 1.0)
    layer[:, 5] = (1.0, 0.0, 0.0, 0.7)          # an edge: kept as it is
    src = np.zeros((11, 11, 4), np.float32)
    src[...] = (0.0, 0.0, 1.0, 1.0)
    ident = np.array([[1.0, 0, 0], [0, 1.0, 0]])
    depth = np.zeros((11, 11), np.float32)
    out, held = hold_joint_bodies(layer, src, np.full((11, 11), 5.0), [(np.array([5.0, 5.0]), ident, 4.0)],
                                  depth)
    assert out[5, 5, 3] == pytest.approx(0.7) and out[5, 7].tolist() == [0.0, 0.0, 1.0, 1.0]
    assert out[5, 2].tolist() == [1.0, 0.0, 0.0, 1.0]
    assert held[5, 7] and not held[5, 5] and not held[0, 10] and depth[5, 7] == 5.0


def test_close_hairlines_keeps_smooth_edges():
    lay = np.zeros((20, 20, 4), np.float32)
    lay[:, :10] = (0.5, 0.5, 0.5, 1.0)
    lay[:, 10, 3] = 0.5                          # a soft edge, open on one side
    out = close_hairlines(lay, [(np.array([10.0, 10.0]), 8.0)])
    assert out is lay
    lay[:, 11:] = (0.5, 0.5, 0.5, 1.0)           # now a line between two opaque sides
    out = close_hairlines(lay, [(np.array([10.0, 10.0]), 5.0)])
    assert (out[5:16, 10, 3] == 1.0).all() and out[0, 10, 3] == 0.5  # only within the zone
