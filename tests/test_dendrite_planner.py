"""The planner against a plain heapq Dijkstra written here with the same comparison rule."""

from __future__ import annotations

import heapq
import itertools
import math

import numpy as np
import pytest
import scipy.sparse as sp
from skimage.graph import MCP_Geometric

from branchnb.dendrite.lattice import Lattice, direction_factors, make_lattice, node_weights
from branchnb.dendrite.planner import plan

# Lattice edges: (w[p] + w[q]) / 2 * f_k, f_k = 1 for axis steps and sqrt(2) for diagonals.
STEPS = [(0, 1), (0, -1), (1, 0), (-1, 0), (1, 1), (1, -1), (-1, 1), (-1, -1)]


def _key(metric, a, m, s):
    if metric == "cumulative":
        return (s, 0.0)
    if metric == "nonscalar":
        return (m, s)  # lexicographic: max edge first, ties by cumulative cost
    return (a * m + s, 0.0)


def reference_dijkstra(weights, seeds, metric, a=1000.0, factors=None):
    """Textbook Dijkstra with heapq and lazy deletion; labels (M, S) per node."""
    h, w = weights.shape
    if factors is None:
        factors = [math.sqrt(2.0) if dr and dc else 1.0 for dr, dc in STEPS]
    inf = float("inf")
    mmax = np.full(h * w, inf)
    total = np.full(h * w, inf)
    done = np.zeros(h * w, bool)
    heap = []
    for s in seeds:
        mmax[s] = total[s] = 0.0
        heapq.heappush(heap, (0.0, 0.0, s))
    while heap:
        k1, k2, u = heapq.heappop(heap)
        if done[u] or (k1, k2) != _key(metric, a, mmax[u], total[u]):
            continue
        done[u] = True
        r, c = divmod(u, w)
        for k, (dr, dc) in enumerate(STEPS):
            rr, cc = r + dr, c + dc
            if not (0 <= rr < h and 0 <= cc < w):
                continue
            v = rr * w + cc
            if done[v] or not np.isfinite(weights[rr, cc]):
                continue
            e = 0.5 * (weights[r, c] + weights[rr, cc]) * factors[k]
            m, s = max(mmax[u], e), total[u] + e
            new = _key(metric, a, m, s)
            old = _key(metric, a, mmax[v], total[v]) if np.isfinite(total[v]) else (inf, inf)
            if new < old:
                mmax[v], total[v] = m, s
                heapq.heappush(heap, (*new, v))
    return mmax, total


METRICS = ["cumulative", "nonscalar", "blend"]


@pytest.mark.parametrize("metric", METRICS)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_labels_equal_reference(metric, seed):
    rng = np.random.default_rng(seed)
    h, w = rng.integers(5, 24, size=2)
    weights = node_weights(rng.random((h, w)) ** 2, epsilon=0.01, noise=0.3, rng=seed)
    seeds = rng.choice(h * w, size=1 + seed, replace=False)
    res = plan(Lattice(weights), np.column_stack([seeds % w, seeds // w]), metric=metric,
               blend_weight=7.5 if metric == "blend" else 1000.0)
    ref_m, ref_s = reference_dijkstra(weights, seeds, metric, a=7.5)
    np.testing.assert_array_equal(res.total_cost, ref_s)
    np.testing.assert_array_equal(res.max_cost, ref_m)


@pytest.mark.parametrize("metric", METRICS)
def test_labels_equal_reference_with_walls_and_directions(metric):
    rng = np.random.default_rng(5)
    weights = rng.random((17, 13)) + 0.05
    weights[rng.random(weights.shape) < 0.15] = np.inf
    weights[8, 6] = 0.5
    f = direction_factors(down=1.0, side=2.5, up=6.0)
    res = plan(Lattice(weights, f), (6, 8), metric=metric)
    ref_m, ref_s = reference_dijkstra(weights, [8 * 13 + 6], metric, factors=list(f))
    np.testing.assert_array_equal(res.total_cost, ref_s)
    np.testing.assert_array_equal(res.max_cost, ref_m)
    assert not res.reached[~np.isfinite(weights.ravel())].any()


@pytest.mark.parametrize("metric", METRICS)
def test_sparse_graph_gives_the_lattice_result(metric):
    lat = make_lattice(np.random.default_rng(3).random((20, 30)), rng=3)
    a = plan(lat, (4, 15), metric=metric)
    b = plan(lat.to_sparse(), [15 * 30 + 4], metric=metric)
    np.testing.assert_array_equal(a.total_cost, b.total_cost)
    np.testing.assert_array_equal(a.max_cost, b.max_cost)
    np.testing.assert_array_equal(a.parent, b.parent)
    np.testing.assert_array_equal(a.order, b.order)


@pytest.mark.parametrize("metric", METRICS)
@pytest.mark.parametrize("noise", [0.05, 1.0, 20.0])
def test_labels_equal_reference_many_seeds_and_scales(metric, noise):
    # weak to strong noise: long floods at one level (non-scalar level heap),
    # frontier nodes later reached at a lower level, wide key ranges
    rng = np.random.default_rng(int(noise * 10))
    cost = rng.random((31, 27)) ** 3
    weights = node_weights(cost, epsilon=0.1, noise=noise, rng=rng)
    weights[rng.random(weights.shape) < 0.05] = np.inf
    seeds = rng.choice(np.flatnonzero(np.isfinite(weights)), size=4, replace=False)
    f = direction_factors(down=1.0, side=1.5, up=3.0)
    res = plan(Lattice(weights, f), np.column_stack([seeds % 27, seeds // 27]), metric=metric,
               blend_weight=50.0)
    ref_m, ref_s = reference_dijkstra(weights, seeds, metric, a=50.0, factors=list(f))
    np.testing.assert_array_equal(res.total_cost, ref_s)
    np.testing.assert_array_equal(res.max_cost, ref_m)
    # every parent link reproduces its child's label
    ok = res.parent >= 0
    assert np.all(res.total_cost[res.parent[ok]] < res.total_cost[ok])
    assert np.all(res.max_cost[res.parent[ok]] <= res.max_cost[ok])


def test_cumulative_equals_skimage_mcp_geometric():
    lat = make_lattice(np.random.default_rng(4).random((40, 50)), rng=4)
    res = plan(lat, (10, 20), metric="cumulative")
    costs, _ = MCP_Geometric(lat.weights, fully_connected=True).find_costs([(20, 10)])
    np.testing.assert_allclose(res.as_image(res.total_cost), costs, rtol=1e-12)


def test_parent_chain_reproduces_labels_and_order_is_sorted():
    lat = make_lattice(np.zeros((25, 25)), noise=1.0, rng=7)
    res = plan(lat, (12, 12), metric="nonscalar")
    keys = res.label[res.order]
    # nodes are settled in non-decreasing lexicographic key order
    assert all(tuple(keys[i]) <= tuple(keys[i + 1]) for i in range(len(keys) - 1))
    sp_graph = lat.to_sparse()
    for node in (0, 24, 300, 624):
        path = res.path(node)
        e = np.array([sp_graph[p, q] for p, q in itertools.pairwise(path)])
        assert e.max() == res.max_cost[node]
        assert np.isclose(e.sum(), res.total_cost[node])


def test_stop_at_settles_the_targets_with_final_labels():
    lat = make_lattice(np.zeros((30, 30)), rng=1)
    full = plan(lat, (0, 0), metric="nonscalar")
    part = plan(lat, (0, 0), metric="nonscalar", stop_at=[5 * 30 + 5])
    assert part.reached.sum() < full.reached.sum()
    ok = part.reached
    np.testing.assert_array_equal(part.total_cost[ok], full.total_cost[ok])
    assert np.isinf(part.total_cost[~ok]).all()


def test_bucket_overflow_and_huge_keys_stay_exact():
    # keys far beyond the queue's range hint exercise the overflow re-bucketing
    rng = np.random.default_rng(9)
    weights = np.exp(rng.normal(0, 3, (15, 15)))
    for metric in METRICS:
        res = plan(Lattice(weights), (7, 7), metric=metric)
        ref_m, ref_s = reference_dijkstra(weights, [7 * 15 + 7], metric)
        np.testing.assert_array_equal(res.total_cost, ref_s)
        np.testing.assert_array_equal(res.max_cost, ref_m)


def test_blend_zero_is_cumulative():
    lat = make_lattice(np.zeros((12, 12)), rng=2)
    a = plan(lat, (3, 3), metric="blend", blend_weight=0.0)
    b = plan(lat, (3, 3), metric="cumulative")
    np.testing.assert_array_equal(a.total_cost, b.total_cost)


@pytest.mark.parametrize("seeds, match", [
    ((40, 3), "outside"),
    ((-1, 0), "outside"),
    ((3, 3), "infinite-cost"),
    (np.zeros((10, 10), bool), "empty"),
    (np.zeros((0, 2)), "at least 1"),
])
def test_bad_seeds(seeds, match):
    w = np.ones((10, 10))
    w[3, 3] = np.inf
    with pytest.raises(ValueError, match=match):
        plan(Lattice(w), seeds)


@pytest.mark.parametrize("weights, match", [
    (np.full((4, 4), np.nan), "NaN"),
    (-np.ones((4, 4)), ">= 0"),
    (np.ones(4), "2-D"),
])
def test_bad_weights(weights, match):
    with pytest.raises(ValueError, match=match):
        Lattice(weights)


def test_bad_cost_map_and_metric_and_graph():
    with pytest.raises(ValueError, match="NaN"):
        make_lattice(np.array([[0.0, np.nan]]))
    with pytest.raises(ValueError, match=">= 0"):
        make_lattice(np.array([[0.0, -1.0]]))
    with pytest.raises(ValueError, match="metric"):
        plan(Lattice(np.ones((3, 3))), (1, 1), metric="euclid")
    with pytest.raises(TypeError, match="Lattice or a scipy.sparse"):
        plan(np.ones((3, 3)), (1, 1))
    g = sp.csr_matrix(np.array([[0, -1.0], [1.0, 0]]))
    with pytest.raises(ValueError, match="non-negative"):
        plan(g, [0])
    with pytest.raises(ValueError, match="outside the graph"):
        plan(sp.csr_matrix(np.ones((3, 3))), [5])


def test_infinite_cost_map_is_a_wall():
    cost = np.zeros((9, 9))
    cost[:, 4] = np.inf
    res = plan(make_lattice(cost, rng=0), (1, 4 - 3))
    img = res.as_image(res.reached)
    assert img[:, :4].all() and not img[:, 4:].any()


@pytest.mark.parametrize("metric", ["cumulative", "nonscalar"])
def test_labels_equal_reference_with_many_exact_ties(metric):
    """The blend key a * M + S is not isotone and does not determine the label (M, S):
    with exact key ties its result depends on which tied path is settled first, in
    any Dijkstra, so it is compared on tie-free (real-valued) weights only, above."""
    # small integer weights and unit diagonals: many paths tie exactly in M and in S
    rng = np.random.default_rng(11)
    weights = rng.integers(1, 4, size=(19, 23)).astype(float)
    f = direction_factors(diagonal="unit")
    res = plan(Lattice(weights, f), np.array([[3.0, 4.0], [20.0, 15.0]]), metric=metric,
               blend_weight=2.0)
    ref_m, ref_s = reference_dijkstra(weights, [4 * 23 + 3, 15 * 23 + 20], metric, a=2.0, factors=list(f))
    # with exact ties the *key* is unique; the part of the label outside the key
    # (M for cumulative, the (M, S) split of a * M + S for blend) depends on which
    # of the tied offers came first, in any Dijkstra
    ref_key = np.array([_key(metric, 2.0, m, s_) for m, s_ in zip(ref_m, ref_s)])
    key = np.array([_key(metric, 2.0, m, s_) for m, s_ in zip(res.max_cost, res.total_cost)])
    np.testing.assert_array_equal(key, ref_key)
    if metric == "nonscalar":
        np.testing.assert_array_equal(res.max_cost, ref_m)


def test_bench_rows_report_the_round_with_the_median_ratio(monkeypatch):
    """The planner bench rows pair each of our runs with an anchor run just before it
    and report the round whose ratio is the median, so one slow round cannot move them."""
    from branchnb.dendrite import _bench

    # (anchor, ours) CPU times of three rounds: ratios 0.5, 1.0, 0.25
    times = iter([2.0, 1.0, 1.0, 1.0, 4.0, 1.0])
    monkeypatch.setattr(_bench, "_cpu", lambda fn: next(times))
    calls = []
    ours, anchor = _bench._paired_median(lambda: calls.append("ours"), lambda: calls.append("anchor"), 3)
    assert (ours, anchor) == (1.0, 2.0)
    assert calls == ["ours", "anchor"]  # one warm-up call each, outside the timed rounds
