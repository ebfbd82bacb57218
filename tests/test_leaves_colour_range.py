"""The exemplars' colour range as new leaves are measured against it (issue 22)."""

import numpy as np

from branchnb.leaves.comparison import colour_range_fraction


def _leaf(rgb):
    return np.dstack([rgb, np.ones(rgb.shape[:2], np.float32)]).astype(np.float32)


def test_a_pixel_capped_at_the_bound_is_inside():
    """A pixel one float32 step past the range (the round-off of a colour capped at the exemplars'
    99.5th percentile and blended) is inside; one 1e-3 past it is not. Before, the first counted as
    outside: 49 such pixels put a new procedural leaf 0.0001 under the synthesis test's floor."""
    rng = np.random.default_rng(0)
    ex = _leaf(rng.uniform(0.2, 0.8, (40, 50, 3)).astype(np.float32))
    hi = np.percentile(ex[..., :3].reshape(-1, 3), 99.5, axis=0).astype(np.float32)
    lo = np.percentile(ex[..., :3].reshape(-1, 3), 0.5, axis=0).astype(np.float32)
    mid = 0.5 * (lo + hi)
    new = np.tile(mid, (10, 10, 1)).astype(np.float32)
    new[0, :5] = np.nextafter(hi, np.float32(1))          # one float32 step above the bound
    new[1, :5] = np.nextafter(lo, np.float32(0))          # one below the lower bound
    assert colour_range_fraction(_leaf(new), [ex]) == 1.0
    new[2, :5] = hi + 1e-3
    new[3, :5] = lo - 1e-3
    assert colour_range_fraction(_leaf(new), [ex]) == 0.9
