"""branchnb.core.morphology.fill_holes: exactly scipy's binary_fill_holes, on masks of several kinds."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.core.morphology import fill_holes


@pytest.mark.parametrize("seed", range(6))
def test_equal_to_scipy_on_random_masks(seed):
    rng = np.random.default_rng(seed)
    for _ in range(40):
        h, w = (int(v) for v in rng.integers(1, 50, 2))
        m = rng.random((h, w)) < rng.uniform(0.2, 0.8)
        if rng.random() < 0.5:
            m = ndi.binary_opening(m) | ndi.binary_erosion(rng.random((h, w)) < 0.7)
        np.testing.assert_array_equal(fill_holes(m), ndi.binary_fill_holes(m))


def test_leaf_with_holes_diagonal_gap_and_border_notch():
    yy, xx = np.mgrid[:120, :140]
    m = (yy - 60) ** 2 + (xx - 70) ** 2 < 50 ** 2
    m[55:65, 40:50] = False          # a hole: filled
    m[0:40, 68:72] = False           # a notch from the border: kept
    m[30, 90] = m[31, 91] = False    # two pixels touching by a corner only: 4-connected holes, filled
    out = fill_holes(m)
    np.testing.assert_array_equal(out, ndi.binary_fill_holes(m))
    assert out[60, 45] and out[30, 90] and not out[5, 70]
    assert int((out & ~m).sum()) == 100 + 2


def test_input_untouched_and_other_shapes_go_to_scipy():
    m = np.zeros((5, 5), bool)
    m[1:4, 1:4] = True
    m[2, 2] = False
    before = m.copy()
    assert fill_holes(m)[2, 2] and np.array_equal(m, before)
    assert fill_holes(np.zeros((0, 3), bool)).shape == (0, 3)
    cube = np.ones((3, 3, 3), bool)
    cube[1, 1, 1] = False
    assert fill_holes(cube).all()
