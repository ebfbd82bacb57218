"""Crowns of flat discs without outlines: dark slivers are fill, not strokes (issue 24)."""

import numpy as np
import pytest

from branchnb import data
from branchnb.trees import billboard as bb
from branchnb.trees.billboard import BillboardParams, billboard_cloud
from branchnb.trees.billboard_lines import fill_slivers, flat_slivers, line_art


def cartoon(size=256):
    """cartoon_tree (flat discs in three greens, no outlines) at ``size`` px."""
    from branchnb.trees._measure_sides import _resized

    return _resized(data.load("cartoon_tree"), size)


def test_fill_slivers_known_sliver():
    img = np.ones((40, 40, 4), np.float32)
    img[:, :, :3] = (0.3, 0.8, 0.2)
    img[5:35, 5:35, :3] = (0.1, 0.4, 0.1)
    img[20:35, 8:35, :3] = (0.3, 0.8, 0.2)          # a 3 px sliver of the dark fill shows below
    lines = line_art(img, width=0.2)
    sl = fill_slivers(img, lines, width=0.2)
    assert lines[20:35, 5:8].mean() > 0.9
    assert sl[20:35, 5:8].mean() > 0.9
    assert not (sl & ~lines).any()


def test_fill_slivers_keep_strokes():
    # A green square with a 2 px black outline: the outline stays a stroke.
    img = np.zeros((60, 60, 4), np.float32)
    img[8:52, 8:52] = (0, 0, 0, 1)
    img[10:50, 10:50] = (0.1, 0.7, 0.2, 1)
    lines = line_art(img)
    assert lines.sum() > 100
    assert fill_slivers(img, lines).sum() == 0


def test_flat_slivers_not_on_gradients():
    img = cartoon()
    ramp = np.linspace(0.6, 1.2, img.shape[1], dtype=np.float32)[None, :, None]
    shaded = img.copy()
    shaded[..., :3] = np.clip(img[..., :3] * ramp, 0, 1)
    crown = img[..., 3] > 0.5
    assert flat_slivers(img, line_art(img), crown).any()
    assert not flat_slivers(shaded, line_art(shaded), crown).any()


def test_flat_slivers_bad_input():
    with pytest.raises(ValueError, match="rgba"):
        fill_slivers(np.zeros((5, 5, 3)), np.zeros((5, 5), bool))
    with pytest.raises(ValueError, match="lines"):
        fill_slivers(np.zeros((5, 5, 4)), np.zeros((4, 5), bool))


@pytest.mark.parametrize("size", [256])
def test_cartoon_tree_gets_tone_cards(size, monkeypatch):
    # Before: the slivers were strokes, the tone cards lost them at 90 degrees (recall 0.47-0.60)
    # and the crown fell back to one flat card (2 billboards); now 12-14 cards.
    from branchnb.trees.billboard_cards import _side_figures

    img = cartoon(size)
    params = BillboardParams(max_size=size)
    cloud = billboard_cloud(img, params=params, rng=0)
    f = _side_figures(cloud)
    assert cloud.n_billboards >= 10
    assert f["recall45"] >= 0.95 and f["recall90"] >= 0.95
    assert f["psnr"] >= 40 and min(f["closed45"], f["closed90"]) >= 0.99
    monkeypatch.setattr(bb, "_FILL_SLIVERS", False)
    assert billboard_cloud(img, params=params, rng=0).n_billboards <= 2
