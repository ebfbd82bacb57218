"""Flat-fill drawn trees (RPG sprites: a green fill in a thick brown band, no inner strokes) get cards (issue 24)."""

import numpy as np
import pytest

from branchnb import data
from branchnb.trees import TreeLibrary, billboard
from branchnb.trees._measure_sides import _resized
from branchnb.trees.billboard import BillboardParams, billboard_cloud
from branchnb.trees.billboard_cards import crown_inlay, flat_fill_cards
from branchnb.trees.lod import bake_side_outline
from branchnb.trees.side_lines import side_line_figures


def _sprite(shaded: bool = False) -> np.ndarray:
    """A 96 px sprite: an elliptic crown of flat green (or leafy shading) in a 4 px brown band."""
    h = w = 96
    yy, xx = np.mgrid[0:h, 0:w]
    crown = ((xx - 48) / 36.0) ** 2 + ((yy - 40) / 32.0) ** 2 <= 1.0
    trunk = (np.abs(xx - 48) <= 6) & (yy >= 50) & (yy < 92)
    img = np.zeros((h, w, 4), np.float32)
    brown, green = (0.35, 0.18, 0.0), (0.0, 0.67, 0.0)
    img[crown | trunk] = (*brown, 1.0)
    from scipy import ndimage as ndi

    inner = ndi.binary_erosion(crown, iterations=4) & ~ndi.binary_dilation(trunk, iterations=4)
    img[inner, :3] = green
    if shaded:
        img[inner, 1] = np.random.default_rng(0).uniform(0.45, 0.85, int(inner.sum()))
    return img


def test_flat_fill_crown_is_recognised_and_shaded_is_not():
    img = _sprite()
    opaque = img[..., 3] > 0.5
    lines = billboard.line_art(img)
    assert flat_fill_cards(img, opaque, lines)
    shaded = _sprite(shaded=True)
    assert not flat_fill_cards(shaded, opaque, billboard.line_art(shaded))


def test_crown_inlay_takes_the_trunk_inside_the_crown_rows_only():
    img = _sprite()
    crown = img[..., 1] > 0.5
    trunk = (img[..., 3] > 0.5) & ~crown
    inlay = crown_inlay(crown, trunk)
    rows = np.flatnonzero(crown.any(axis=1))
    assert inlay.any() and not inlay[rows.max() + 1:].any() and not inlay[: rows.min()].any()
    with pytest.raises(ValueError):
        billboard_cloud(np.zeros((8, 8, 4), np.float32))


def _recalls(cloud):
    baked = bake_side_outline(cloud)
    return [side_line_figures(baked, y)["recall"] for y in (45.0, 90.0)]


def test_rpg_mix_with_branches_in_the_crown_keeps_its_outlines_from_the_side(monkeypatch):
    # A random mix of the RPG samples (seed 1: branches drawn up into the crown). Superpixels lost
    # its inner outlines from the side (recall 0.38 at 45, 0.11 at 90 degrees); cards keep them.
    lib = TreeLibrary.from_data([f"tree_rpg_{i:02d}" for i in range(1, 11)], size=256)
    v = lib.variation(rng=1)
    cloud = billboard_cloud(v.image, params=BillboardParams(max_size=256), rng=0)
    assert cloud.n_billboards < 60
    r45, r90 = _recalls(cloud)
    assert r45 >= 0.95 and r90 >= 0.95
    monkeypatch.setattr(billboard, "_FLAT_CARDS", False)
    monkeypatch.setattr(billboard, "_SHADED_CARDS", False)
    old = billboard_cloud(v.image, params=BillboardParams(max_size=256), rng=0)
    assert old.n_billboards > 300 and max(_recalls(old)) < 0.6


def test_tiered_rpg_conifer_gets_cards_at_200px():
    # tree_rpg_05: tiers drawn by the band alone; its cards trade up to 0.07 of reduced-level rim ink
    # (anti-aliased fringe) for recall 0.95 / 1.0 against the superpixel cloud's 0.74 / 0.46.
    img = _resized(data.load("tree_rpg_05"), 200)
    cloud = billboard_cloud(img, params=BillboardParams(max_size=200), rng=0)
    assert cloud.n_billboards < 60
    assert min(_recalls(cloud)) >= 0.9
