"""A bauble where a crown tier meets the trunk sits in the tier's notch and is filled behind (issue 24)."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.trees import billboard_cards as bc


def _scene(n=40):
    """Card 1 (a tier, rows 4-19) over a trunk (rows 20-37, columns 12-27, label 0 but opaque),
    shape 2 a disc of radius 5 (centre row 17) on the tier's bottom edge above the trunk: its ring is tier and
    trunk, no sky."""
    yy, xx = np.mgrid[:n, :n]
    labels = np.zeros((n, n), np.int32)
    labels[4:20, 2:38] = 1
    trunk = (yy >= 20) & (yy < 38) & (xx >= 12) & (xx < 28)
    disc = np.hypot(yy - 17, xx - 20) <= 5
    labels[disc] = 2
    trunk &= ~disc
    opaque = (labels > 0) | trunk
    return labels, trunk, opaque


@pytest.mark.parametrize("flag", [True, False])
def test_notch_counts_trunk(flag, monkeypatch):
    labels, trunk, opaque = _scene()
    monkeypatch.setattr(bc, "_TRUNK_NOTCH", flag)
    got = bc._notch_shapes(labels, 1, [2], opaque, ndi.find_objects(labels), trunk=trunk)
    assert got == ([2] if flag else [])
    # Without a trunk mask the rule is the earlier one.
    assert bc._notch_shapes(labels, 1, [2], opaque, ndi.find_objects(labels)) == []


def test_notch_still_rejects_shape_mostly_on_trunk():
    labels, trunk, opaque = _scene()
    labels[labels == 2] = 0
    disc = np.hypot(*np.mgrid[-20:20, -20:20] - np.array([10, 0])[:, None, None]) <= 5   # centre (30, 20)
    labels[disc] = 2
    trunk = trunk & ~disc
    opaque = (labels > 0) | trunk
    assert bc._notch_shapes(labels, 1, [2], opaque, ndi.find_objects(labels), trunk=trunk) == []


def test_underpaint_fills_from_nearer_of_tier_and_trunk():
    labels, trunk, opaque = _scene()
    H, W = labels.shape
    img = np.zeros((H, W, 4), np.float32)
    img[labels == 1] = (0.2, 0.6, 0.2, 1)
    img[trunk] = (0.55, 0.35, 0.15, 1)
    img[labels == 2] = (0.9, 0.1, 0.1, 1)
    keep = labels == 1
    sl = (slice(0, H), slice(0, W))
    tex = img.copy()
    tex[..., 3] *= keep
    hole = labels == 2
    lines = np.zeros((H, W), bool)
    for t, tr in ((None, None), ("trunk", trunk)):
        out = bc._underpaint(tex, keep, opaque, sl, lines, 1.5, hole=hole, trunk=tr)
        assert np.all(out[hole, 3] == 1.0)
        yy, xx = np.mgrid[:H, :W]
        top = hole & (yy < 16)
        low = hole & (yy >= 20) & (abs(xx - 20) <= 2)
        assert top.sum() >= 20 and low.sum() >= 5
        assert np.allclose(out[top, :3], (0.2, 0.6, 0.2))          # nearer the tier: green
        want = (0.2, 0.6, 0.2) if t is None else (0.55, 0.35, 0.15)
        assert np.allclose(out[low, :3], want)                     # nearer the trunk: brown
        assert not np.isclose(out[hole, 0], 0.9).any()             # no red left behind
