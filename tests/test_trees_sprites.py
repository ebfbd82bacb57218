"""Small game sprites (32-256 px) vary at their own size, in their own style (issue 24, beyond the paper)."""

import cv2
import numpy as np
import pytest

from branchnb.trees import TreeLibrary
from branchnb.trees._sprite_check import INK, KINDS, library_sprites, measure, sprite
from branchnb.trees.library import _auto_size, _extent
from branchnb.trees.pixel_art import _clean_blocks, _detect, _pixelate, _rim_ink


@pytest.fixture(scope="module")
def lib64():
    lib = TreeLibrary()
    for i, t in enumerate(library_sprites(64, True, 0)):
        lib.add(t, f"{KINDS[i]}{i}")
    return lib


def _palette(trees):
    return np.unique(np.concatenate([t[..., :3][t[..., 3] >= 0.5] for t in trees]).round(4), axis=0)


def test_auto_size_rule():
    assert _auto_size([1500, 80]) == 1024          # the paper's size for large trees
    assert _auto_size([200, 120]) == 200           # sprites: never above the largest tree
    assert _auto_size([300, 120]) == 1024          # larger drawings: the paper's size
    assert _auto_size([20]) == 40                  # small ones enlarged by whole pixels
    assert _extent(sprite("fir", 64)) <= 64
    assert TreeLibrary(size=128).size == 128       # an explicit size is kept (and its older rules)
    fixed = TreeLibrary(size=96)
    assert fixed.add(sprite("fir", 64)).normalized.pixel_art is None


def test_sprites_vary_at_their_own_size(lib64):
    trees = library_sprites(64, True, 0)
    ext = max(_extent(t) for t in trees)
    assert lib64.size == ext                       # main: 1024 (16x enlarged blocks)
    assert all(e.normalized.pixel_art is not None for e in lib64.exemplars)
    pal = _palette(trees)
    for r in range(3):
        img = np.asarray(lib64.variation(rng=r).image)
        assert img.shape == (ext, ext, 4)
        assert set(np.unique(img[..., 3]).tolist()) <= {0.0, 1.0}      # hard alpha
        m = measure(img, pal, True, ext)
        assert m["pal"] == 1.0                    # the sprites' palette only
        assert 0.9 <= m["olw"] <= 1.15            # a 1 px outline
        assert m["bump"] == 0
        assert m["inner"] == 0                    # no rim stubs inside (main: 5 ink pixels)


def test_larger_tree_reprocesses_the_library():
    lib = TreeLibrary()
    lib.add(sprite("round", 48, True, rng=1), "a")
    s0 = lib.size
    lib.add(sprite("fir", 96, True, rng=2), "b")
    assert s0 <= 48 < lib.size <= 96
    assert {e.size for e in lib.exemplars} == {lib.size}
    assert lib.names == ["a", "b"]
    assert lib.variation([0.5, 0.5], rng=0).image.shape[0] == lib.size


def test_rim_ink_finds_outlines_the_stroke_measure_misses():
    """A palm sprite enlarged by a non-integer factor (rows doubled here and there)."""
    t = sprite("palm", 48, True, rng=3)
    big = cv2.resize(t, (61, 61), interpolation=cv2.INTER_NEAREST)
    lib = TreeLibrary()
    e = lib.add(big)
    ink = _rim_ink(e.image, e.normalized.pixel_art.palette)
    assert ink is not None and np.allclose(ink, INK, atol=0.01)
    assert _rim_ink(sprite("palm", 48, False, rng=3), _palette([sprite("palm", 48, False, rng=3)])) is None


def test_outline_whole_when_a_source_is_unmeasured():
    """Mixes of sprites whose outline the stroke measure misses keep a whole 1 px outline."""
    trees = [cv2.resize(sprite(k, 48, True, rng=10 + i), (61, 61), interpolation=cv2.INTER_NEAREST)
             for i, k in enumerate(("palm", "round", "palm"))]
    lib = TreeLibrary()
    for t in trees:
        lib.add(t)
    pal = _palette(trees)
    for r in range(3):
        img = np.asarray(lib.variation(rng=r).image)
        op = img[..., 3] >= 0.5
        rim = op & ~cv2.erode(np.pad(op, 1).astype(np.uint8), np.ones((3, 3), np.uint8))[1:-1, 1:-1].astype(bool)
        inked = np.abs(img[..., :3] - np.float32(INK)).max(-1) <= 0.05
        assert (inked & rim).sum() >= 0.95 * rim.sum()
        assert measure(img, pal, True, img.shape[0])["pal"] == 1.0


def test_two_pixel_bumps_come_off_flat_edges():
    b = np.zeros((8, 10), bool)
    b[1:5, 1:9] = True
    b[5, 4:6] = True                    # a 2-wide stub under the bottom edge (main kept it)
    b[1:5, 9] = False
    out = _clean_blocks(b)
    assert not out[5].any()
    assert out[1:5, 1:9].all()
    step = np.zeros((8, 10), bool)
    step[1:5, 1:9] = True
    step[5, 1:4] = True                 # a step at the corner is a shape, not a stub
    assert (_clean_blocks(step) == step).all()


def test_ink_inside_goes_when_the_sources_ink_only_their_rims():
    img = np.zeros((12, 12, 4), np.float32)
    img[1:11, 1:11] = (0.2, 0.6, 0.2, 1.0)
    img[1:11, 1, :3] = img[1:11, 10, :3] = img[1, 1:11, :3] = img[10, 1:11, :3] = INK
    art = _detect(img)
    stub = img.copy()
    stub[5:7, 4:6, :3] = INK                # a stub of a warped rim, 2 x 2 (kept as a line before)
    out, _ = _pixelate(stub, [art], [1.0], ink=INK, inner_ink=False)
    inner = out[2:10, 2:10, :3]
    assert np.abs(inner - np.float32((0.2, 0.6, 0.2))).max() < 1e-6
    kept, _ = _pixelate(stub, [art], [1.0], ink=INK, inner_ink=True)
    assert np.abs(kept[5:7, 4:6, :3] - np.float32(INK)).max() < 1e-6    # drawn inner lines stay
