"""Small low-poly crowns (90-160 px) are told apart (issue 24, trees54): their merged facets'
outlines stand 0.5-0.8 px off their Douglas-Peucker polygon, as a curved fill's do, but the
crown's outlines on average do not (``lowpoly.POOLED_RESIDUAL``)."""

from __future__ import annotations

import pytest
from test_trees_lowpoly_large import curved, hard_lowpoly

from branchnb.trees import TreeLibrary
from branchnb.trees._measure_sticker import sticker_tree
from branchnb.trees.flat_art import _source_pixel
from branchnb.trees.lowpoly import facet_palette


@pytest.mark.parametrize("size", [96, 128])
def test_small_hard_edged_low_poly_found(size):
    """Main found 1 (96 px) and 2 (128 px) of these 8."""
    found = sum(facet_palette(*hard_lowpoly(size, s)) is not None for s in range(8))
    assert found >= {96: 3, 128: 5}[size], found


@pytest.mark.parametrize("size", [96, 128, 200])
def test_small_curved_fills_not_low_poly(size):
    for kind in ("cel", "clumps", "dots"):
        for seed in range(4):
            img, trunk = curved(size, seed, kind)
            assert facet_palette(img, trunk) is None, (kind, seed)


def test_dotted_sticker_fir_not_low_poly():
    """A borderless sticker fir: a flat triangle with small round dots. Its straight outer outline
    must not carry the dots' round holes (a length-weighted pool of the outlines took it)."""
    lib = TreeLibrary(size=256)
    for s in range(3):
        lib.add(sticker_tree(400, s, border=None, outline=None), f"b{s}")
    assert all(facet_palette(e.image, e.trunk, pixel=_source_pixel(e)) is None for e in lib.exemplars)
