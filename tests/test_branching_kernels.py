"""Issue 23 (branching23): the compiled inner loops of structure synthesis (branchnb.branching._kernels)
compute what the numpy reference computes: density profiles, PCA directions, a step's scores and a
branch start's heads; and a sanity check of the weak straight-run rule where runs are short."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import _kernels, fit_model, synthesize_structure
from branchnb.branching._map_examples import crack_pattern_example
from branchnb.branching.colonization import DensityMap, growth_directions, profile_density
from branchnb.branching.params import SynthesisParams
from branchnb.branching.scoring import _DIRECTION_BINS, _base_scores, binned_profile, score_candidates
from branchnb.core.structure import Branch, Structure


def _density(rho, rng, shape=(120, 160)):
    dm = DensityMap(shape, rho)
    for _ in range(25):
        a = rng.uniform(0, shape[1], 2)
        dm.add_segments([a], [a + rng.normal(0, 25, 2)])
    return dm


@pytest.mark.parametrize("rho", [2.5, 12.0])   # a fine (nearest) and a coarse (bilinear) grid
def test_binned_profiles_equal_the_numpy_profiles(rho):
    rng = np.random.default_rng(1)
    dm = _density(rho, rng)
    dirs = rng.normal(size=(300, 2))
    dirs /= np.hypot(*dirs.T)[:, None]
    q = np.rint(np.arctan2(dirs[:, 1], dirs[:, 0]) * (_DIRECTION_BINS / (2 * np.pi))).astype(int) % _DIRECTION_BINS
    ang = q * 2 * np.pi / _DIRECTION_BINS
    ref_dc, ref_cross, _ = profile_density(dm, (80.0, 60.0), np.c_[np.cos(ang), np.sin(ang)], 48.0)
    dc, cross = binned_profile(dm, (80.0, 60.0), dirs, 48.0)
    np.testing.assert_allclose(dc, ref_dc, atol=1e-6)
    assert np.array_equal(cross, ref_cross)
    assert 0 < ref_cross.sum() < len(dirs)   # both answers were exercised


def test_pca_directions_equal_growth_directions():
    rng = np.random.default_rng(2)
    pts = rng.uniform(0, 100, (40, 5, 2))
    nv = rng.integers(1, 6, 40)
    np.testing.assert_allclose(_kernels.pca_directions(50.0, 50.0, pts, nv),
                               growth_directions((50.0, 50.0), pts, nv), atol=1e-12)


@pytest.fixture(scope="module")
def crack_model():
    from branchnb.branching import example_domain, extract_structure

    img = crack_pattern_example((192, 192), 2)
    ex = extract_structure(img)
    return fit_model(ex, domain=example_domain(img, ex))


def test_compiled_step_scores_equal_the_numpy_scores(crack_model):
    p = SynthesisParams()
    rng = np.random.default_rng(3)
    matcher = crack_model.matcher(p.wG)
    b0 = crack_model.example.branches[0]
    matcher.add(b0.angles()[:10], b0.thickness[:10])
    dm = DensityMap((192, 192), crack_model.rho)
    for b in crack_model.example.branches[:15]:
        dm.add_segments(b.points[:-1] + 4, b.points[1:] + 4)
    for _ in range(4):
        L = int(rng.integers(1, 14))
        ha, hr = rng.normal(0, 0.2, L), rng.uniform(1, 3, L)
        tip, theta = rng.uniform(40, 150, 2), float(rng.uniform(-3, 3))
        got = score_candidates(crack_model, ha, hr, tip, theta, params=p, matcher=matcher, density=dm)
        ref = _base_scores(crack_model, ha, hr, tip, theta, p, matcher, None)
        live = ref.n_new > 0
        dc, cross = binned_profile(dm, tip, ref.dirs[live], 3.0 * p.m * p.h)
        D = np.zeros(len(ref.t))
        X = np.zeros(len(ref.t), bool)
        D[live], X[live] = dc, cross
        ok = live & ~X
        D[~live] = D[ok].min() if ok.any() else 1.0
        score = np.where(X, 0.0, ref.base / (D + p.eps))
        np.testing.assert_allclose(got.Q, ref.Q, rtol=1e-12)
        np.testing.assert_allclose(got.points, ref.points, atol=1e-9)
        np.testing.assert_allclose(got.hist_factor, ref.hist_factor, rtol=1e-9)
        assert np.array_equal(got.crossing, X)
        np.testing.assert_allclose(got.score, score, rtol=1e-9)


def test_compiled_start_matches_the_numpy_heads(crack_model):
    # the first vertices of every candidate head and its histogram factor, against the numpy formulas
    p = SynthesisParams()
    m = crack_model
    hm = m.matcher(p.wG)
    hm.add([0.1, -0.2, 0.0], [2.0, 2.0, 1.5])
    heads = np.flatnonzero(m.first_len > 0)
    H = len(heads)
    rng = np.random.default_rng(4)
    th0 = rng.uniform(-3, 3, H)
    sign = np.where(rng.random(H) < 0.5, -1.0, 1.0)
    n = m.first_len[heads]
    rows_a, rows_r = _kernels.head_rows(m.first_a, m.first_len, hm.edges_a, _kernels.element_bins(m.cum_r),
                                        m.head_start)
    new, th, score, _dirs, _dc = _kernels.start_scores(
        heads, th0, sign, m.first_a, n, 30.0, 40.0, p.h, np.ones(H), True, rows_a, hm.p_a, hm.counts_a,
        rows_r, hm.p_r, hm.counts_r, hm.wG * hm.n_nodes / hm.m, False,
        np.zeros((1, 1), np.float32), 1.0, 48.0, 8, 0.02, _DIRECTION_BINS, p.eps)
    turns = np.concatenate([np.zeros((H, 1)), m.first_a[heads] * sign[:, None]], axis=1)
    valid = np.arange(p.m + 1)[None, :] <= n[:, None]
    ref_th = th0[:, None] + np.cumsum(turns * valid, axis=1)
    steps = p.h * valid
    ref_new = np.stack([30.0 + np.cumsum(np.cos(ref_th) * steps, axis=1),
                        40.0 + np.cumsum(np.sin(ref_th) * steps, axis=1)], axis=-1)
    np.testing.assert_allclose(th, ref_th, atol=1e-12)
    np.testing.assert_allclose(new, ref_new, atol=1e-9)
    ok = np.arange(p.m)[None, :] < n[:, None]
    bins = hm.bin_angles(m.first_a[heads] * sign[:, None])
    ca = np.bincount((bins + p.bins * np.arange(H)[:, None])[ok], minlength=H * p.bins).reshape(H, p.bins)
    cr = m.cum_r[m.head_start[heads] + n] - m.cum_r[m.head_start[heads]]
    np.testing.assert_allclose(score, hm.factors(ca.astype(float), cr), rtol=1e-9)


def test_short_run_examples_keep_their_straight_runs():
    # a zigzag-free example whose branches turn every few steps (short runs, below RUN_MIN_MEAN):
    # the weak straight-run factor keeps the output's mean run within 0.8-1.25 x the example's
    from branchnb.branching.measures import straight_runs
    from branchnb.branching.straightness import RUN_MIN_MEAN, StraightRuns

    rng = np.random.default_rng(5)
    branches = []
    for k in range(6):
        th, p, pts = rng.uniform(0, 2 * np.pi), np.array([20.0 + 25 * k, 20.0]), []
        for i in range(40):
            pts.append(p.copy())
            if i % 4 == 3:
                th += rng.choice([-1, 1]) * np.radians(rng.uniform(15, 30))
            p = p + 4.0 * np.array([np.cos(th), np.sin(th)])
        pts = np.clip(pts, 2, 197)
        branches.append(Branch(np.asarray(pts), np.full(len(pts), 1.5)))
    ex = Structure(branches, image_shape=(200, 200))
    model = fit_model(ex)
    runs = StraightRuns(model.bending.angles, model.bending.branch)
    assert runs.mean_run < RUN_MIN_MEAN
    _a, r_ex = straight_runs(model.example)
    ratios = [straight_runs(synthesize_structure(model, rng=s).structure)[1] / r_ex for s in range(3)]
    assert 0.8 <= np.mean(ratios) <= 1.25
