"""Sticker trees (dark outline inside a light die-cut border) keep both rings in mixes (issue 24, trees41)."""

import numpy as np
import pytest
from scipy import ndimage as ndi

import branchnb.trees.variations as V
from branchnb.trees import TreeLibrary
from branchnb.trees._measure_sticker import sticker_tree
from branchnb.trees.sticker import _sticker_border

INK = np.array([0.1, 0.08, 0.08])


@pytest.fixture(scope="module")
def lib():
    lib = TreeLibrary(size=256)
    for s, fill in zip(range(3), ["dots", "stripes", "gradient"]):
        lib.add(sticker_tree(400, s, border=8, outline=3, fill=fill), f"s{s}")
    return lib


def _rings(img, border):
    alpha = img[..., 3] >= 0.5
    depth = ndi.distance_transform_edt(alpha)
    rgb = img[..., :3]
    outer = alpha & (depth < border - 0.5)
    white = float((np.linalg.norm(rgb[outer] - 1.0, axis=1) <= 0.2).mean())
    band = alpha & (depth > border + 1.5) & (depth <= border + 2.5)
    ink = float((np.linalg.norm(rgb[band] - INK, axis=1) <= 0.3).mean())
    return white, ink


def test_border_found_on_stickers_only(lib):
    b = _sticker_border(lib["s0"].image)
    assert b is not None and 4 <= b.width <= 8 and np.allclose(b.colour, 1.0, atol=0.05)
    assert _sticker_border(sticker_tree(300, 1, border=None, outline=3)) is None      # plain outlined
    assert _sticker_border(sticker_tree(300, 1, border=None, outline=None)) is None   # borderless


def test_mix_keeps_border_and_outline_rings(lib):
    for rng in range(3):
        v = np.asarray(lib.variation(rng=rng).image, np.float32)
        w = float(np.mean([_sticker_border(lib[n].image).width for n in lib.names]))
        white, ink = _rings(v, w)
        assert white >= 0.97, (rng, white)
        assert ink >= 0.9, (rng, ink)


def test_plain_outlined_mix_unchanged(monkeypatch):
    lib = TreeLibrary(size=192)
    for s in range(2):
        lib.add(sticker_tree(300, s, border=None, outline=3), f"o{s}")
    new = np.asarray(lib.variation(rng=0).image)
    monkeypatch.setattr(V, "_sticker_mix", lambda *a, **k: None)
    assert np.array_equal(new, np.asarray(lib.variation(rng=0).image))
