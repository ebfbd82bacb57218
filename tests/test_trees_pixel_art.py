"""Pixel-art trees mix into pixel art (issue 24, beyond the paper).

Before, sprites (hard edges, a few palette colours, alpha 0/1) were resized smoothly and sampled
bilinearly through the warp: their mixes had anti-aliased edges (about a third of the opaque
pixels in 3 x 3 windows of three or more colours) and 15-20 % of the pixels in colours no sprite
has. Now the exemplars are resized nearest and a mix is put back on the sprites' art-pixel grid
in their palette, with a one-art-pixel outline.
"""

import numpy as np
import pytest

from branchnb import data
from branchnb.trees._measure_pixel import aa_share, palette_share, sprite
from branchnb.trees.exemplar import normalize_exemplar
from branchnb.trees.pixel_art import _detect
from branchnb.trees.variations import TreeLibrary


@pytest.fixture(scope="module")
def lib():
    lib = TreeLibrary(size=128)
    for i in range(3):
        lib.add(sprite(10 + i, "round", 40, 52, 2), f"s{i}")
    return lib


def test_sprites_are_detected_with_their_block():
    art = _detect(sprite(0, "round", 40, 52, 3))
    assert art is not None and art.block == 3
    assert 4 <= len(art.palette) <= 8


@pytest.mark.parametrize("name", ["tree_rpg_05", "tree_cutout_broadleaf", "palm_silhouette"])
def test_drawn_and_photographed_samples_are_no_pixel_art(name):
    assert _detect(np.asarray(data.load(name), np.float32)) is None
    assert normalize_exemplar(data.load(name), size=64).pixel_art is None


def test_exemplar_keeps_hard_pixels(lib):
    e = lib["s0"]
    assert e.normalized.pixel_art is not None
    pal = e.normalized.pixel_art.palette
    assert palette_share(e.image, pal, tol=1e-3) == 1.0


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_mix_is_pixel_art(lib, seed):
    v = np.asarray(lib.variation(rng=seed).image, np.float32)
    pal = np.unique(np.concatenate([lib[n].normalized.pixel_art.palette for n in lib.names]), axis=0)
    assert set(np.unique(v[..., 3]).tolist()) <= {0.0, 1.0}
    assert palette_share(v, pal, tol=1e-3) == 1.0          # main: 0.80-0.86
    assert aa_share(v) < 0.02                                # main: about 0.3
    # the rim is the outline colour (a one-art-pixel outline, as the sprites have)
    op = v[..., 3] >= 0.5
    rim = op & ~np.pad(op, 1)[:-2, 1:-1] | op & ~np.pad(op, 1)[2:, 1:-1]
    ink = v[rim, :3].sum(axis=1) < 0.3
    assert ink.mean() > 0.9, ink.mean()
