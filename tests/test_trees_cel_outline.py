"""Outlined cel-shaded game trees: mixes keep the outline round crown and trunk at the sources'
width, and a soft cast shadow is dropped consistently (issue 24, beyond the paper)."""

import numpy as np
import pytest

from branchnb.trees import TreeLibrary
from branchnb.trees._cel_check import cel_tree, outline_figures
from branchnb.trees.exemplar import _drop_cast_shadows


def _library(size, outline, shadow, seed, aa=False):
    lib = TreeLibrary()
    for i in range(3):
        lib.add(cel_tree(size, outline, shadow, rng=seed + i, aa=aa), f"t{i}")
    return lib


def _mixes(lib):
    return [lib.variation(rng=k).image for k in range(2)] + [lib.variations_of(0, n=1, rng=7)[0].image]


@pytest.mark.parametrize("size, outline, shadow, aa, seed", [(96, 1, True, False, 0), (128, 2, False, False, 10),
                                                             (160, 1, True, True, 60)])
def test_mixes_keep_outline_round_crown_and_trunk(size, outline, shadow, aa, seed):
    lib = _library(size, outline, shadow, seed, aa)
    tol = 0.25 if aa else 0.12          # an anti-aliased 1 px stroke is a blend of ink and fill
    src = [outline_figures(e.image, outline, tol) for e in lib.exemplars]
    width = np.mean([s["width"] for s in src])
    for img in _mixes(lib):
        f = outline_figures(img, outline, tol)
        # main: trunk 0.87-0.92 (edges and foot bare), 2 px outlines re-inked 1 px wide (0.51)
        assert f["crown"] >= 0.9 and f["trunk"] >= 0.9, f
        assert 0.8 <= f["width"] / width <= 1.25, (f["width"], width)


def test_cast_shadow_is_dropped_consistently():
    for size, outline in ((96, 1), (200, 2)):
        with_shadow, without = TreeLibrary(), TreeLibrary()
        a = with_shadow.add(cel_tree(size, outline, True, rng=5), "a")
        b = without.add(cel_tree(size, outline, False, rng=5), "b")
        # main: the shadow's soft pixels sent the sprite to the smooth resample (blurred outline)
        assert a.normalized.pixel_art is not None
        np.testing.assert_array_equal(np.asarray(a.image), np.asarray(b.image))
    lib = _library(96, 1, True, 11)
    for img in _mixes(lib):
        assert outline_figures(img, 1)["soft"] == 0       # no half shadow in a mix either


def test_soft_edge_is_no_cast_shadow():
    alpha = np.zeros((20, 20), np.float32)
    alpha[5:15, 5:15] = 1.0
    alpha[4, 5:15] = 0.4                    # an anti-aliased edge hugging the opaque tree
    alpha[18, 2:18] = 0.3                   # a shadow lying apart
    out = _drop_cast_shadows(alpha, alpha >= 0.5, 0.5)
    assert np.all(out[4, 5:15] == 0.4) and np.all(out[18] == 0.0)
    np.testing.assert_array_equal(out[5:15, 5:15], 1.0)
