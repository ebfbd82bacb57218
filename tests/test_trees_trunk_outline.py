"""A drawn trunk keeps its side outline in side views (issue 24): its strokes go with the trunk."""

import numpy as np
import pytest

from branchnb import data
from branchnb.trees import billboard as bb
from branchnb.trees._measure_sides import _resized
from branchnb.trees.billboard import BillboardParams, billboard_cloud
from branchnb.trees.billboard_lines import trunk_outline
from branchnb.trees.lod import engine_view
from branchnb.trees.outline import rim_ink_share


def _drawn_tree(size=160):
    """A flat green crown and a brown trunk, each outlined in black (3 px); the trunk mask is its
    fill only, as the segmentation of a drawing often gives it (and the drawn trunk with strokes)."""
    H = W = size
    yy, xx = np.mgrid[:H, :W]
    img = np.zeros((H, W, 4), np.float32)
    trunk_out = (abs(xx - W / 2) <= 0.09 * W) & (yy >= 0.5 * H) & (yy <= 0.95 * H)
    trunk_in = (abs(xx - W / 2) <= 0.09 * W - 3) & (yy >= 0.5 * H) & (yy <= 0.95 * H - 3)
    crown_out = ((xx - W / 2) / (0.4 * W)) ** 2 + ((yy - 0.35 * H) / (0.28 * H)) ** 2 <= 1
    crown_in = ((xx - W / 2) / (0.4 * W - 3)) ** 2 + ((yy - 0.35 * H) / (0.28 * H - 3)) ** 2 <= 1
    img[trunk_out] = (0, 0, 0, 1)
    img[trunk_in] = (0.55, 0.35, 0.15, 1)
    img[crown_out] = (0, 0, 0, 1)
    img[crown_in] = (0.2, 0.6, 0.2, 1)
    for cx in (0.35, 0.65):      # two outlined fruits: inner outlines, so the crown is drawn cards
        d = np.hypot(xx - cx * W, yy - 0.3 * H)
        img[d <= 8] = (0, 0, 0, 1)
        img[d <= 5] = (0.9, 0.1, 0.1, 1)
    trunk = trunk_in & ~crown_out
    return img, trunk, trunk_out & ~crown_out


def _trunk_rows_rim(cloud, yaw):
    """Rim ink share of an engine's view below the crown's wide rows (the trunk's sides)."""
    wide = (cloud.image[..., 3] >= 0.5).sum(axis=1)
    top = int(np.flatnonzero(wide > 0.5 * wide.max()).max()) + 3
    return rim_ink_share(engine_view(cloud, yaw, crop="image")[top:], (0, 0, 0))


@pytest.mark.parametrize("flag", [True, False])
def test_drawn_trunk_keeps_side_outline(flag, monkeypatch):
    # christmas_tree_root_flare at 512 px: the segmentation's trunk stops at its fill, so its
    # side strokes were crown pieces 27-30 px in front of it that slid off it from the side.
    img = _resized(data.load("christmas_tree_root_flare"), 512)
    monkeypatch.setattr(bb, "_TRUNK_OUTLINE", flag)
    cloud = billboard_cloud(img, params=BillboardParams(max_size=512, drawn_cards=False), rng=0)
    front, r45, r90 = (_trunk_rows_rim(cloud, y) for y in (0.0, 45.0, 90.0))
    assert front > 0.6
    if flag:   # measured 0.663, 0.617, 0.597
        assert r45 >= front - 0.07 and r90 >= front - 0.09
    else:      # measured 0.663, 0.434, 0.358: the reference the rule fixes
        assert r45 < front - 0.15


def test_trunk_outline_known_answer():
    img, trunk, drawn = _drawn_tree(96)
    opaque = img[..., 3] >= 0.5
    lines = opaque & (img[..., :3].sum(axis=2) < 0.1)
    grown = trunk_outline(trunk, opaque, lines, 4.0)
    assert not (grown & ~drawn).any()              # no crown pixel
    assert (grown & drawn).sum() >= 0.98 * drawn.sum()   # the fill and its strokes (not where they meet the crown)
    assert not trunk_outline(np.zeros_like(trunk), opaque, lines, 4.0).any()


def test_trunk_outline_keeps_a_shared_fill():
    # A crown's thick band in the trunk's colour (one fill region, half of it crown) stays the crown's.
    opaque = np.zeros((40, 40), bool)
    opaque[5:35, 15:25] = True
    opaque[5:10, 5:35] = True
    trunk = np.zeros_like(opaque)
    trunk[10:35, 15:25] = True
    lines = np.zeros_like(opaque)
    assert np.array_equal(trunk_outline(trunk, opaque, lines, 2.0), trunk)
