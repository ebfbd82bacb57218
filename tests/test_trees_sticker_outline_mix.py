"""Stickers whose only outline is a thick light ring keep it closed and even in mixes (issue 24, trees52)."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.trees import TreeLibrary
from branchnb.trees._measure_sticker import sticker_tree
from branchnb.trees.sticker import _sticker_border

WHITE = np.ones(3)


def _lib(size, pen, seed0=0):
    lib = TreeLibrary(size=size)
    for s, fill in zip(range(3), ["dots", "stripes", "flat"]):
        lib.add(sticker_tree(size, seed0 + s, border=None, outline=pen, ink=(1.0, 1.0, 1.0), fill=fill), f"t{s}")
    return lib


def _figures(img, pen):
    """(outline-coloured share of the 2 px band inside the rim, outline-coloured pixels deeper
    than pen + 2.5 per rim pixel)."""
    a = img[..., 3] >= 0.5
    d = ndi.distance_transform_edt(a)
    near = np.linalg.norm(img[..., :3] - WHITE, axis=2) <= 0.25
    band = a & (d <= 2.0)
    deep = a & (d > pen + 2.5)
    return float(near[band].mean()), float((near & deep).sum() / (a & (d < 1.5)).sum())


@pytest.mark.parametrize("size,pen", [(96, 3), (96, 8), (256, 8)])
def test_white_ring_closed_and_even_in_mixes(size, pen):
    lib = _lib(size, pen, seed0=size + pen)
    assert all(_sticker_border(lib[n].image) is not None for n in lib.names)
    mixes = [lib.variation(rng=r).image for r in range(2)]
    mixes += [v.image for v in lib.variations_of("t0", 1, rng=5)]
    for i, m in enumerate(mixes):
        share, deep = _figures(np.asarray(m, np.float32), pen)
        assert share >= 0.95, (i, share)
        # the warped ring no longer runs 2-3 widths deep where the cage stretched it
        assert deep <= 0.2, (i, deep)


def test_ring_width_is_the_pens_not_its_corners():
    b = _sticker_border(sticker_tree(256, 1, border=None, outline=8, ink=(1.0, 1.0, 1.0)))
    assert b is not None and 7.0 <= b.mean_width <= 9.5 and b.width >= b.mean_width
