"""The compiled per-piece steps of composition give the values of the former numpy code (issue 23 speed).

References below are the former implementations, kept here verbatim in substance:
overlap pins by dilations, float32 pair costs by array expressions, the graph cut on the
whole region's bounding box.
"""

import maxflow
import numpy as np
import pytest

from branchnb.core import graphcut as gc
from branchnb.core.blending import _NO_MASK, _dilate, _overlap_pins, compose_piece


def _pins_ref(cov, valid, pc, pp):
    overlap, only_a, only_b = cov & valid, cov & ~valid, valid & ~cov
    grown_a = _dilate(only_a)
    grown_a[0, :] = grown_a[-1, :] = grown_a[:, 0] = grown_a[:, -1] = True
    near_a = grown_a & overlap
    near_b = _dilate(only_b) & overlap & ~near_a
    pin_a = near_a | (pc & overlap) if pc is not None else near_a
    pin_b = near_b | (pp & overlap) if pp is not None else near_b
    return overlap, only_b, pin_a, pin_b & ~pin_a


def _pair_ref(a, b, eps=1e-3):
    d = np.sqrt(((a - b) ** 2).sum(axis=2))
    g = gc.gradient_magnitude(a) + gc.gradient_magnitude(b)
    right = (d[:, :-1] + d[:, 1:]) / (g[:, :-1] + g[:, 1:] + eps)
    down = (d[:-1, :] + d[1:, :]) / (g[:-1, :] + g[1:, :] + eps)
    return right.astype(np.float64), down.astype(np.float64)


def _cut_ref(right, down, region, pin_a, pin_b):
    take_b = np.zeros(region.shape, bool)
    if not region.any():
        return take_b
    g = maxflow.Graph[float]()
    ids = g.add_grid_nodes(region.shape)
    w_r = np.zeros(region.shape)
    w_r[:, :-1] = np.where(region[:, :-1] & region[:, 1:], right, 0.0)
    w_d = np.zeros(region.shape)
    w_d[:-1, :] = np.where(region[:-1, :] & region[1:, :], down, 0.0)
    g.add_grid_edges(ids, weights=w_r, structure=np.array([[0, 0, 0], [0, 0, 1], [0, 0, 0]]), symmetric=True)
    g.add_grid_edges(ids, weights=w_d, structure=np.array([[0, 0, 0], [0, 0, 0], [0, 1, 0]]), symmetric=True)
    g.add_grid_tedges(ids, np.where(pin_a, 1e9, 0.0), np.where(pin_b, 1e9, 0.0))
    g.maxflow()
    return g.get_grid_segments(ids) & region


@pytest.mark.parametrize("seed", range(4))
def test_overlap_pins_equal_dilation_code(seed):
    rng = np.random.default_rng(seed)
    n_bad = 0
    for k in range(300):
        h, w = (int(v) for v in rng.integers(1, 24, 2))
        big = rng.random((h + 3, w + 3)) < rng.random()
        cov = big[1:1 + h, 2:2 + w]                    # a strided view, like a canvas window
        valid = rng.random((h, w)) < rng.random()
        pc = rng.random((h, w)) < 0.2 if k % 2 else None
        pp = rng.random((h, w)) < 0.2 if k % 3 else None
        got = _overlap_pins(cov, valid, _NO_MASK if pc is None else pc, _NO_MASK if pp is None else pp,
                            pc is not None, pp is not None)
        n_bad += not all(np.array_equal(x, y) for x, y in zip(got, _pins_ref(cov, valid, pc, pp)))
    assert n_bad == 0


@pytest.mark.parametrize("channels", [1, 3, 4])
def test_pair_costs_compiled_equal_array_code(channels):
    rng = np.random.default_rng(channels)
    for _ in range(40):
        h, w = (int(v) for v in rng.integers(2, 30, 2))
        a = rng.random((h, w, channels), dtype=np.float32)
        b = rng.random((h, w, channels), dtype=np.float32)
        b[: h // 2] = a[: h // 2]                       # zero-cost pairs too
        for got, ref in zip(gc._pair_costs(a, b), _pair_ref(a, b)):
            assert got.dtype == np.float64 and np.array_equal(got, ref)


def test_seam_cut_on_free_pixels_equals_whole_region_cut():
    rng = np.random.default_rng(5)
    n_free_only = 0
    for k in range(200):
        h, w = (int(v) for v in rng.integers(3, 28, 2))
        a = rng.random((h, w, 3), dtype=np.float32)
        b = np.clip(a + rng.normal(0, 0.2, a.shape).astype(np.float32), 0, 1)
        if k % 4 == 0:
            b[:, : w // 2] = a[:, : w // 2]              # ties: identical halves
        right, down = gc._pair_costs(a, b)
        region = rng.random((h, w)) < 0.9
        pin_a = region & (rng.random((h, w)) < rng.uniform(0.2, 0.9))
        pin_a[:, 0] = region[:, 0]
        pin_b = region & ~pin_a & (rng.random((h, w)) < rng.uniform(0.2, 0.9))
        pin_b[:, -1] = region[:, -1] & ~pin_a[:, -1]
        got = gc._seam_cut(right, down, region, pin_a, pin_b)
        n_free_only += not (region & ~pin_a & ~pin_b).any()
        assert np.array_equal(got, _cut_ref(right, down, region, pin_a, pin_b))
    assert n_free_only < 200


def test_compose_piece_matches_reference_take():
    # a left-half canvas and a piece over its middle: the taken pixels are those of the
    # reference pins and cut (the whole former path)
    rng = np.random.default_rng(0)
    canvas = rng.random((40, 40, 3), dtype=np.float32)
    covered = np.zeros((40, 40), bool)
    covered[:, :22] = True
    piece = np.clip(canvas[4:34, 8:38] + 0.05, 0, 1).astype(np.float32)
    valid = np.ones((30, 30), bool)
    c0, cov0 = canvas.copy(), covered.copy()
    comp = compose_piece(canvas, covered, piece, valid, (8, 4), poisson=False)
    overlap, only_b, pin_a, pin_b = _pins_ref(cov0[4:34, 8:38], valid, None, None)
    right, down = _pair_ref(c0[4:34, 8:38], piece)
    take = only_b | _cut_ref(right, down, overlap, pin_a, pin_b)
    assert np.array_equal(comp.take, take)
    assert 0 < (take & overlap).sum() < overlap.sum()
    assert np.array_equal(canvas[4:34, 8:38][take], piece[take])


def test_structure_resampled_equals_per_branch_resample_uniform():
    from branchnb.branching._image_examples import random_tree
    from branchnb.core.polyline import resample_uniform
    from branchnb.core.structure import Branch, Structure

    trees = [random_tree((200, 200), k, n_children=3) for k in range(3)]
    trees.append(Structure([Branch([(0, 0), (0, 0)], 1.0), Branch([(1, 1)], 1.0), Branch([(0, 0), (9, 0)], [1, 3])]))
    for st in trees:
        for h in (0.7, 2.5):
            ref = st.with_polylines([
                (b.points.copy(), b.thickness.copy()) if len(b.points) < 2 or b.length <= 0
                else resample_uniform(b.points, h, values=b.thickness, include_end=True) for b in st.branches])
            for x, y in zip(ref.branches, st.resampled(h).branches):
                assert np.array_equal(x.points, y.points) and np.array_equal(x.thickness, y.thickness)
                assert (x.parent, x.parent_vertex) == (y.parent, y.parent_vertex)
    with pytest.raises(ValueError, match="h must be"):
        trees[0].resampled(0.0)
