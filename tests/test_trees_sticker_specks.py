"""Sticker mixes (dark outline inside a die-cut border): no dark specks left of the warped outline
inside the rebuilt ring, and no warped outline band left inside a 400 px crown (issue 24, trees55)."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.trees import TreeLibrary
from branchnb.trees._measure_sticker import _BORDERS, _INKS, _inner, _specks, sticker_tree


def _library(size, spec_seed, border, outline, bc, ink, fills, work):
    lib = TreeLibrary(size=work)
    for s in range(3):
        lib.add(sticker_tree(size, spec_seed + s, border=border, outline=outline, border_colour=_BORDERS[bc],
                             ink=_INKS[ink], fill=fills[s % len(fills)]), f"t{s}")
    return lib


@pytest.mark.parametrize("seed", [0, 6])
def test_no_specks_inside_the_rebuilt_ring_at_192(seed):
    # 400 px stickers (8 px border, 3 px pen) at 192 px: the warped outline broke into dotted pieces
    # 1-3 px inside the new ring (main: 26 and 29 specks on these seeds).
    lib = _library(400, 0, 8, 3, 0, 0, ["dots", "stripes", "flat"], 192)
    img = np.asarray(lib.variation(rng=seed).image, np.float32)
    assert _specks(img, _INKS[0], _BORDERS[0]) <= 8
    # ... and the rebuilt ring is there: ink 1-2 px inside the border on most of the rim
    inner, di = _inner(img, _BORDERS[0])
    band = inner & (di < 1.5)
    ink = np.linalg.norm(img[..., :3] - np.asarray(_INKS[0]), axis=2) <= 0.35
    near = ndi.binary_dilation(ink & inner, structure=np.ones((3, 3), bool))
    assert float(near[band].mean()) >= 0.8


def test_warped_outline_band_goes_at_400():
    # 300 px stickers (2 px border, 2 px pen, navy ink) at 400 px: the warped outline was left as a
    # saw-toothed band 10-25 px wide inside the crown (read as fill: it was 2 % of the mix's crown).
    lib = _library(300, 40, 2, 2, 1, 1, ["dots", "stripes", "flat"], 400)
    img = np.asarray(lib.variation(rng=3).image, np.float32)
    inner, di = _inner(img, _BORDERS[1])
    ink = inner & (np.linalg.norm(img[..., :3] - np.asarray(_INKS[1]), axis=2) <= 0.3)
    deep = inner & (di > 6.0) & (di <= 30.0)
    assert float(ink[deep].mean()) <= 0.02
    assert _specks(img, _INKS[1], _BORDERS[1]) <= 20


def test_faint_and_black_specks_go_at_400():
    # 400 px stickers (8 px border, 3 px pen) at 400 px: a dotted line of faint remnants 5-10 px
    # inside the ring, a quarter of the way to the ink (main: 39 specks on this mix); 200 px stickers
    # (3 px border, 1 px pen) on a red crown: black cores off the fill-to-grey-ink line (main: 23)
    lib = _library(400, 0, 8, 3, 0, 0, ["dots", "stripes", "flat"], 400)
    assert _specks(np.asarray(lib.variation(rng=0).image, np.float32), _INKS[0], _BORDERS[0]) <= 5
    lib = _library(200, 10, 3, 1, 1, 0, ["stripes", "flat", "gradient"], 400)
    assert _specks(np.asarray(lib.variation(rng=2).image, np.float32), _INKS[0], _BORDERS[1]) <= 8
