"""Clip-art mixes keep a fruit's ring where it touches the outline (issue 24, trees26).

Procedural clip-art trees (``branchnb.trees._clipart_check``: flat crowns, 4 px outlines, fruit
discs tangent to the outline). On main the outline step repainted the two merged strokes between a
fruit and the edge with the nearest fill, the fruit's: its colour ran across its ring to the
outline (spill 0.03-0.07 per rim pixel at 256 px, sources 0.00-0.01).
"""

import numpy as np
import pytest

from branchnb.trees._clipart_check import libraries, specks, spill
from branchnb.trees.outline import even_outline
from branchnb.trees.variations import TreeLibrary, make_variation


@pytest.fixture(scope="module")
def lib():
    lib = TreeLibrary(size=256)
    for i, t in enumerate(libraries(256)["lines 4/4/4"]):
        lib.add(t, f"clip{i}")
    return lib


def test_fruit_colour_does_not_run_into_the_outline(lib):
    for seed in (0, 1):
        v = make_variation(lib, rng=seed)
        assert spill(v.image, 4.0) <= 0.015
        assert specks(v.image) <= 2


def test_even_outline_keeps_a_fruit_ring_against_a_thick_outline():
    img = np.zeros((60, 60, 4), np.float32)
    img[5:55, 5:55] = (0.05, 0.05, 0.05, 1)
    img[8:52, 8:52, :3] = (0.3, 0.7, 0.2)             # 3 px outline ...
    img[8:12, 8:52, :3] = 0.05                         # ... 7 px along the top (a warped stroke)
    yy, xx = np.mgrid[:60, :60]
    disc = (yy - 21) ** 2 + (xx - 30) ** 2
    img[disc <= 81, :3] = 0.05                         # a fruit with a 2 px ring touching it
    img[disc <= 49, :3] = (1.0, 0.4, 0.0)
    out = even_outline(img, (0.05, 0.05, 0.05), 3)
    fruit = np.all(np.abs(out[..., :3] - (1.0, 0.4, 0.0)) < 0.1, axis=2)
    assert fruit[: 5 + 3 + 2].sum() == 0                # no fruit colour in the outline or its ring
    assert 0.8 * (disc <= 49).sum() <= fruit.sum() <= (disc <= 49).sum()
    green = np.all(np.abs(out[..., :3] - (0.3, 0.7, 0.2)) < 0.1, axis=2)
    assert green[9:11, 10:18].all()                    # the warped stroke away from the fruit thinned
