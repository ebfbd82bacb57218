"""Children's roots at their parents (issue 25): no notch, no floating copy, no flaps.

Procedural objects (:mod:`branchnb.strokes.procedural`) whose truth is
known: a bare tree whose limb is raised about its root, a starfish given
a sixth arm (a copy of one of its arms), a figure raising its arms.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.strokes import Stroke, edit_structure
from branchnb.strokes.procedural import bare_tree, figure, starfish

EIGHT = np.ones((3, 3))


def _turn(st, th, about):
    c, s = np.cos(th), np.sin(th)
    return (np.asarray(st, float) - about) @ np.array([[c, -s], [s, c]]).T + about


def _holes(alpha):
    m = alpha > 0.5
    return int((ndi.binary_fill_holes(m) & ~m).sum())


@pytest.mark.parametrize("size", [400, 700])
def test_a_raised_limb_leaves_no_notch_at_its_root(size):
    """Before: the wedge between the raised limb's cut face and the trunk was nobody's,
    an enclosed notch outlined like a hole (19 / 163 px open in the limb's root tube
    at 400 / 1000 px)."""
    obj = bare_tree(size, rng=1)
    trunk, limb = obj.strokes[0], obj.strokes[2]
    up = _turn(limb, -0.35, limb[0])
    res = edit_structure(obj.image, [trunk, limb], [trunk, up])
    a = res.image[..., 3]
    # the limb's own tube (its half width less the outline and 1.5 px), from the trunk's
    # side to half way along, must be opaque
    st = Stroke(up)
    hw = obj.widths[2] * 0.75 - obj.outline - 1.5     # the tapered limb's width half way
    yy, xx = np.nonzero(np.ones(a.shape, bool))
    s, d = st.project(np.c_[xx, yy].astype(float))
    _, d_trunk = Stroke(trunk).project(np.c_[xx, yy].astype(float))
    tube = (d <= hw) & (s <= 0.5 * st.length) & (d_trunk > obj.widths[0] * 0.8)
    assert int((tube & (a.ravel() < 0.5)).sum()) == 0
    assert _holes(a) <= _holes(obj.image[..., 3])
    assert ndi.label(a > 0.02, structure=EIGHT)[1] == 1


@pytest.mark.parametrize("size", [150, 300])
def test_a_sixth_arm_is_joined_and_the_others_are_not_copied(size):
    """A starfish's arm drawn twice (kept, and copied between arms 1 and 2). Before:
    the copy floated off the disk (held back over empty background within the parent's
    width) and the three unstroked arms came twice (8 arms); at 150 px the arms'
    tubes swallowed the disk and the unstroked arms were cut."""
    obj = starfish(size, rng=1)
    c = obj.strokes[1][0]
    arm1, arm2 = obj.strokes[1], obj.strokes[2]
    new = _turn(arm2, -0.63, c)
    res = edit_structure(obj.image, [arm1, arm2, arm2], [arm1, arm2, new])
    a = res.image[..., 3]
    assert ndi.label(a > 0.02, structure=EIGHT)[1] == 1
    # one arm more, not four: the area grows by about one arm (0.12 of the star)
    grow = (a > 0.5).sum() / (obj.image[..., 3] > 0.5).sum()
    assert 1.05 <= grow <= 1.2
    # the new arm is opaque along its stroke from the centre to near its tip
    st = Stroke(new)
    p = st.point_at(np.linspace(0, 0.9 * st.length, 40))
    assert (a[np.rint(p[:, 1]).astype(int), np.rint(p[:, 0]).astype(int)] > 0.5).all()
    # the unstroked arms are where they were (80 % of the way to their tips)
    for k in (3, 4, 5):
        x, y = np.rint(obj.strokes[k][0] + 0.8 * (obj.strokes[k][-1] - obj.strokes[k][0])).astype(int)
        assert a[y, x] > 0.5, obj.names[k]


def test_raised_arms_pull_no_flaps_of_the_body():
    """The roots are filled with the arm's own texture: nothing of the body's colour
    outside the body's silhouette above the hips (before a first try: flaps of the
    body's stripes along the raised arms' roots)."""
    size = 300
    obj = figure(size, rng=0)
    body = obj.strokes[0]
    src, tgt = [body], [body]
    for k, ang in ((2, 0.9), (3, -1.0)):
        src.append(obj.strokes[k])
        tgt.append(_turn(obj.strokes[k], ang, obj.strokes[k][0]))
    res = edit_structure(obj.image, src, tgt)
    r, g, b, a = np.moveaxis(res.image, -1, 0)
    blue = (a > 0.5) & (b > r + 0.15)
    body_mask = ndi.binary_dilation(obj.labels == 0, iterations=2)
    yy = np.arange(size)[:, None]
    assert int((blue & ~body_mask & (yy < 0.55 * size)).sum()) <= 3  # a flap is hundreds
    assert _holes(a) == 0 and ndi.label(a > 0.02, structure=EIGHT)[1] == 1
