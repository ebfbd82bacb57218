import numpy as np
import pytest

from branchnb.core.histogram import (
    chi_square_distance,
    compare_samples,
    emd_1d,
    histogram_distance,
    histograms,
    l1_distance,
    l2_squared_distance,
    shared_bins,
)


def test_shared_bins_cover_all_samples():
    e = shared_bins([0, 1], [5], bins=5)
    assert e[0] == 0 and e[-1] == 5 and len(e) == 6


def test_histograms_normalised_and_clipped():
    h, e = histograms([0, 0, 1, 10], bins=4, range=(0, 2))
    assert np.isclose(h.sum(), 1) and h[0, -1] == 0.25  # 10 clipped into the last bin


def test_distances_known_values():
    p, q = np.array([1.0, 0, 0]), np.array([0, 0, 1.0])
    assert l1_distance(p, q) == 2.0
    assert chi_square_distance(p, q) == 1.0
    assert l2_squared_distance(p, q) == pytest.approx(2 / 3)
    assert emd_1d(p, q) == 2.0  # all mass moves two bins
    assert emd_1d(p, q, edges=[0, 0.5, 1.0, 1.5]) == 1.0
    assert histogram_distance(p, p, "chi2") == 0.0


def test_emd_matches_scipy_wasserstein():
    from scipy.stats import wasserstein_distance

    rng = np.random.default_rng(0)
    a, b = rng.normal(0, 1, 500), rng.normal(0.7, 1.3, 500)
    h, e = histograms(a, b, bins=64)
    c = 0.5 * (e[1:] + e[:-1])
    assert emd_1d(h[0], h[1], e) == pytest.approx(wasserstein_distance(c, c, h[0], h[1]), rel=1e-6)


def test_compare_samples_orders_distances():
    rng = np.random.default_rng(0)
    ref = rng.normal(0, 1, 2000)
    c = compare_samples(ref, rng.normal(0, 1, 2000), rng.normal(2, 1, 2000), labels=["ref", "same", "shifted"])
    assert c.distances[0] == 0 and c.distances[1] < c.distances[2]


def test_bad_input():
    with pytest.raises(ValueError, match="samples\\[1\\] is empty"):
        histograms([1.0], [])
    with pytest.raises(ValueError, match="NaN"):
        histograms([np.nan])
    with pytest.raises(ValueError, match="metric"):
        histogram_distance([1], [1], "cosine")
    with pytest.raises(ValueError, match="labels"):
        compare_samples([1], [2], labels=["one"])
