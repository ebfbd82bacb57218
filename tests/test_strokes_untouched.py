"""An edit changes only what the user touched: strokes given unchanged do not steer the others (issue 25).

The automatic patch radius (and with it the direction window, the junction
tolerance and the depth a tip is pushed under its parent) was the median over
all strokes: re-stroking one arm gave other patches depending on whether the
strokes of the rest of the object were also given, unchanged. It is now the
median over the moved strokes, the strokes they join and the strokes they
were copied from.
"""
import os
import sys

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.strokes import edit_structure, fetch_patches
from branchnb.strokes.procedural import figure

sys.path.insert(0, os.path.dirname(__file__))
from test_strokes_elbows import _LEFT, _RIGHT, _RIGHT_RAISED, _TRUNK, _cactus  # noqa: E402


def _near(pts, shape, reach):
    """Pixels within ``reach`` px of the polyline ``pts`` (sampled every 0.5 px)."""
    pts = np.asarray(pts, float)
    seg = [np.linspace(a, b, max(2, int(np.hypot(*(b - a)) * 2))) for a, b in zip(pts[:-1], pts[1:])]
    p = np.round(np.concatenate(seg)).astype(int)
    on = np.zeros(shape, bool)
    ok = (p[:, 0] >= 0) & (p[:, 0] < shape[1]) & (p[:, 1] >= 0) & (p[:, 1] < shape[0])
    on[p[ok, 1], p[ok, 0]] = True
    return ndi.distance_transform_edt(~on) < reach


def _turned(st, ang):
    c, s = np.cos(ang), np.sin(ang)
    return (st - st[0]) @ np.array([[c, -s], [s, c]]).T + st[0]


@pytest.mark.parametrize("size", [300, 600])
def test_a_cactus_arms_patches_do_not_depend_on_the_other_arms_stroke(size):
    # trunk + raised arm vs trunk + both arms (the left one unchanged);
    # before: patch size 62.0 vs 52.4 px at 300 px (114.8 vs 93.2 at 600 px), now equal
    s = size / 400
    img, _ = _cactus(size, (_TRUNK, _LEFT, _RIGHT))
    src = [np.array(p, float) * s for p in (_TRUNK, _LEFT, _RIGHT)]
    raised = np.array(_RIGHT_RAISED, float) * s
    two = fetch_patches(img, [src[0], src[2]], [src[0], raised])
    three = fetch_patches(img, src, [src[0], src[1], raised])
    assert abs(two.radius - three.radius) < 0.05 and two._auto == three._auto


@pytest.mark.parametrize("size", [400, 800])
def test_a_figures_arm_patches_barely_depend_on_the_other_limbs_strokes(size):
    # body + raised right arm vs body + all four limbs (three unchanged): before 68.6 vs 40.3 px
    # at 400 px, 130.7 vs 70.8 at 800; now 68.6 vs 64.4, 130.7 vs 120.8 (the arm is measured
    # wider with the other arm's root unstroked beside it)
    obj = figure(size, rng=0)
    st = [obj.strokes[k] for k in (0, 2, 3, 4, 5)]
    arm = _turned(st[2], -0.9)
    two = fetch_patches(obj.image, [st[0], st[2]], [st[0], arm])
    five = fetch_patches(obj.image, st, st[:2] + [arm] + st[3:])
    assert abs(two.radius / five.radius - 1) < 0.1, (two.radius, five.radius)


def test_an_unchanged_arm_stays_the_sources():
    s = 300 / 400
    img, _ = _cactus(300, (_TRUNK, _LEFT, _RIGHT))
    src = [np.array(p, float) * s for p in (_TRUNK, _LEFT, _RIGHT)]
    raised = np.array(_RIGHT_RAISED, float) * s
    left = _near(src[1][1:], img.shape[:2], 21 * s + 3) & ~_near(src[0], img.shape[:2], 35 * s + 8)
    # its stroke given unchanged: re-synthesized as it was; not given: carried (5 of its 4099
    # pixels differ, by 0.1)
    for res in (edit_structure(img, src, [src[0], src[1], raised]).image,
                edit_structure(img, [src[0], src[2]], [src[0], raised]).image):
        assert int((np.abs(res - img).max(axis=2)[left] > 0.02).sum()) <= 10
