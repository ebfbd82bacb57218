"""Dendrites: tracing, the metric comparison, importance, endpoints, thickness,
metaphors, stylization, trees, pareidolia, and bad input."""

from __future__ import annotations

import dataclasses
import itertools
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from scipy import ndimage
from scipy.spatial import cKDTree

from branchnb.dendrite import (
    LightningParams,
    StylizeParams,
    Stylizer,
    branch_thickness,
    build_dendrite,
    importance_map,
    importance_thickness,
    lightning,
    make_lattice,
    path_statistics,
    place_endpoints,
    plan,
    random_endpoints,
    render_lightning,
    render_plain,
    render_vines,
    stylize,
    visiting_order_image,
)
from branchnb.dendrite.importance import ImportanceParams
from branchnb.dendrite.pareidolia import PareidoliaParams, pareidolia_tree
from branchnb.dendrite.trees import TreeParams, grow_layers, grow_tree, rejection_endpoints, render_tree

METRICS = ["cumulative", "nonscalar", "blend"]


def _edge_costs_along(lat, nodes):
    g = lat.to_sparse()
    return np.array([g[p, q] for p, q in itertools.pairwise(nodes)])


def _root_path(d, i):
    out = [i]
    while d.parent[out[-1]] >= 0:
        out.append(int(d.parent[out[-1]]))
    return out[::-1]


# ------------------------------------------------------------------ tracing
@pytest.mark.parametrize("metric", METRICS)
@pytest.mark.parametrize("rng", [0, 1])
def test_every_endpoint_connected_and_no_cycles(metric, rng):
    lat = make_lattice(np.random.default_rng(rng).random((40, 50)), rng=rng)
    seeds = np.array([[25.0, 20.0], [3.0, 3.0]])
    res = plan(lat, seeds, metric=metric)
    ends = random_endpoints(np.ones((40, 50), bool), 60, rng=rng)
    d = build_dendrite(res, ends)
    # no cycles: parents come first, nodes unique, edges = nodes - roots
    assert d.is_tree()
    roots = np.flatnonzero(d.parent < 0)
    assert (d.parent >= 0).sum() == d.n_nodes - len(roots)
    assert set(d.nodes[roots]) <= set(lat.node_index(seeds))
    # every endpoint is a tree node whose parent chain reaches a seed
    end_nodes = set(lat.node_index(ends))
    assert end_nodes <= set(d.nodes)
    where = {int(n): i for i, n in enumerate(d.nodes)}
    for e in end_nodes:
        chain = _root_path(d, where[e])
        assert d.nodes[chain[0]] in set(lat.node_index(seeds))
        # consecutive tree nodes are lattice neighbours and follow the planner's parents
        nodes = d.nodes[chain]
        assert np.abs(np.diff(nodes % 50)).max() <= 1 and np.abs(np.diff(nodes // 50)).max() <= 1
        np.testing.assert_array_equal(res.parent[nodes[1:]], nodes[:-1])
    # branches: each branch's first node is on its parent branch
    for b, pb in zip(d.branches, d.branch_parent):
        if pb >= 0:
            assert b[0] in set(d.branches[pb].tolist())


def test_nonscalar_max_edge_never_exceeds_cumulative():
    for rng in range(3):
        lat = make_lattice(np.random.default_rng(rng).random((48, 48)) ** 3, noise=0.5, rng=rng)
        ends = random_endpoints(np.ones((48, 48), bool), 80, rng=rng + 10)
        res_c = plan(lat, (24, 24), metric="cumulative")
        res_n = plan(lat, (24, 24), metric="nonscalar")
        st_c = path_statistics(build_dendrite(res_c, ends), res_c)
        st_n = path_statistics(build_dendrite(res_n, ends), res_n)
        # same tips in both (sorted by node), compare per endpoint
        nodes = np.sort(lat.node_index(ends))
        dc = build_dendrite(res_c, ends)
        dn = build_dendrite(res_n, ends)
        mc = dict(zip(dc.nodes[dc.tips], st_c.max_edge))
        mn = dict(zip(dn.nodes[dn.tips], st_n.max_edge))
        for n in np.unique(nodes):
            if n in mc and n in mn:
                assert mn[n] <= mc[n]
        # and recomputed from the actual lattice edges of the traced paths
        where = {int(n): i for i, n in enumerate(dn.nodes)}
        for e in np.unique(nodes)[:10]:
            path = dn.nodes[_root_path(dn, where[int(e)])]
            if len(path) > 1:
                assert _edge_costs_along(lat, path).max() == res_n.max_cost[e] <= res_c.max_cost[e]
        # the metrics really differ: non-scalar paths are more tortuous on average
        assert np.nanmean(st_n.tortuosity) > np.nanmean(st_c.tortuosity)


def test_base_dendrite_grows_without_duplicating_nodes():
    lat = make_lattice(np.zeros((40, 40)), rng=0)
    res = plan(lat, (20, 39))
    d1 = build_dendrite(res, [(20, 2)], iteration=1)
    mask = np.zeros(1600, bool)
    mask[d1.nodes] = True
    res2 = plan(lat, mask.reshape(40, 40))
    d2 = build_dendrite(res2, [(2, 10), (37, 12)], base=d1, iteration=2)
    assert d2.is_tree() and d2.n_nodes > d1.n_nodes
    np.testing.assert_array_equal(d2.nodes[: d1.n_nodes], d1.nodes)
    assert set(d2.iteration.tolist()) == {1, 2}
    assert np.all(d2.parent[d1.n_nodes:] >= 0)  # new branches attach to the base


def test_sparse_graph_dendrite_with_positions():
    lat = make_lattice(np.zeros((10, 10)), rng=0)
    res = plan(lat.to_sparse(), [0])
    pos = lat.node_points(np.arange(100))
    d = build_dendrite(res, [99, 9, 90], positions=pos)
    assert d.is_tree() and len(d.tips) == 3
    np.testing.assert_array_equal(d.points[d.tips[0]], pos[d.nodes[d.tips[0]]])


def test_to_structure_round_trip():
    res = plan(make_lattice(np.zeros((30, 30)), rng=0), (15, 29))
    d = branch_thickness(build_dendrite(res, [(2, 2), (28, 3), (15, 1)]))
    s = d.to_structure()
    assert len(s.branches) == d.n_branches
    assert s.n_vertices == d.n_nodes + d.n_branches - 1  # junctions repeat once per side branch


# ---------------------------------------------------------------- importance
def test_importance_weights_gradient_three_times_darkness():
    img = np.ones((40, 40))
    img[:, 20:] = 0.0
    imp = importance_map(img)
    assert imp[20, 2] == 0.0  # white, flat
    assert imp[20, 37] == pytest.approx(0.25)  # black, flat: w_I / (w_I + w_G)
    assert imp[20, 19:21].max() > 0.9  # the edge
    only_dark = importance_map(img, ImportanceParams(intensity_weight=1, gradient_weight=0))
    assert only_dark[20, 37] == pytest.approx(1.0)


@pytest.mark.parametrize("value", [0.0, 0.4, 1.0])
def test_constant_image_gives_constant_importance(value):
    imp = importance_map(np.full((30, 30), value))
    assert np.ptp(imp) == 0.0
    assert imp[0, 0] == pytest.approx((1 - value) / 4)


# ----------------------------------------------------------------- endpoints
def test_endpoints_follow_importance_and_are_well_spaced():
    imp = np.zeros((80, 80))
    imp[:, :40] = 1.0
    pts = place_endpoints(imp, 200, rng=0)
    assert pts.shape == (200, 2)
    left = (pts[:, 0] < 40).mean()
    assert left > 0.9
    d, _ = cKDTree(pts[pts[:, 0] < 40]).query(pts[pts[:, 0] < 40], k=2)
    # blue noise: no two endpoints on top of each other, spacing fairly even
    assert d[:, 1].min() > 0.3 * d[:, 1].mean()


def test_constant_importance_gives_uniform_endpoints():
    pts = place_endpoints(np.zeros((60, 60)), 36, rng=1)
    hist, _, _ = np.histogram2d(pts[:, 0], pts[:, 1], bins=3, range=[[0, 60], [0, 60]])
    assert hist.min() >= 2 and hist.max() <= 6


def test_endpoints_respect_mask():
    mask = np.zeros((50, 50), bool)
    mask[10:20, 5:45] = True
    pts = place_endpoints(np.random.default_rng(0).random((50, 50)), 40, mask=mask, rng=0)
    assert mask[np.rint(pts[:, 1]).astype(int), np.rint(pts[:, 0]).astype(int)].all()


# ----------------------------------------------------------------- thickness
def _line_dendrite():
    res = plan(make_lattice(np.zeros((5, 60)), noise=0.0, rng=0), (0, 2), metric="cumulative")
    return build_dendrite(res, [(59, 2)])


def test_importance_thickness_rolls_and_thins_tips():
    d = _line_dendrite()
    imp = np.zeros((5, 60))
    imp[:, 20:40] = 1.0
    t = importance_thickness(d, imp, window=9, min_width=0.0, max_width=4.0)
    x = t.points[:, 0].astype(int)
    r = np.zeros(60)
    r[x] = t.radius
    assert r[30] == pytest.approx(2.0)  # inside the important stretch: full width
    assert r[5] == 0.0 and r[55] == 0.0
    assert 0 < r[18] < r[22] < 2.0  # the rolling average ramps up
    ones = importance_thickness(d, np.ones((5, 60)), window=9, min_width=0, max_width=4)
    rr = np.zeros(60)
    rr[ones.points[:, 0].astype(int)] = ones.radius
    # overshoot: the last window/2 nodes taper toward the tip, the root side does not
    assert rr[59] == pytest.approx(2.0 * 5 / 9)
    assert rr[0] == pytest.approx(2.0) and rr[30] == pytest.approx(2.0)
    np.testing.assert_allclose(rr[55:], 2.0 * np.arange(9, 4, -1) / 9)


def test_subtree_thickness_pipe_model():
    res = plan(make_lattice(np.zeros((40, 40)), rng=0), (20, 39))
    d = branch_thickness(build_dendrite(res, random_endpoints(np.ones((40, 40), bool), 20, rng=0)),
                         min_width=1.0, max_width=None, exponent=2.0)
    has = d.parent >= 0
    assert np.all(d.radius[d.parent[has]] >= d.radius[has] - 1e-12)  # never thicker than parent
    root = np.flatnonzero(d.parent < 0)[0]
    assert d.radius[root] == pytest.approx(0.5 * np.sqrt(len(d.tips)))


# ----------------------------------------------------------- metaphors / svg
def _check_svg(text):
    root = ET.fromstring(text)
    assert root.tag.endswith("svg")
    return root


def test_metaphors_render_and_export_svg():
    res = plan(make_lattice(np.zeros((60, 60)), rng=0), (30, 59))
    d = branch_thickness(build_dendrite(res, random_endpoints(np.ones((60, 60), bool), 15, rng=0)))
    plain = render_plain(d)
    vines = render_vines(d, rng=0)
    light = render_lightning(d)
    for r in (plain, vines, light):
        assert r.image.shape == (60, 60, 3) and r.image.dtype == np.float32
        _check_svg(r.svg)
    assert plain.image.min() < 0.1  # dark strokes on white
    assert vines.image[..., 1].mean() < 1.0 and (vines.image[..., 1] > vines.image[..., 0]).any()
    assert light.image.mean() < 0.5 and light.image.max() > 0.95  # bright core on a night sky
    assert "feGaussianBlur" in light.svg


def test_lightning_grows_downward():
    bolt = lightning((120, 80), LightningParams(n_branches=25), rng=0)
    assert bolt.is_tree()
    has = bolt.parent >= 0
    dy = bolt.points[has, 1] - bolt.points[bolt.parent[has], 1]
    assert (dy < 0).mean() < 0.05  # hardly any step goes up
    assert (dy > 0).mean() > 0.5
    # the channel to the ground is the thickest branch
    bottom = np.argmax(bolt.points[:, 1])
    assert bolt.radius[bottom] >= np.median(bolt.radius[bolt.tips])


def test_visiting_order_contours_differ_by_metric():
    lat = make_lattice(np.zeros((64, 64)), noise=1.0, epsilon=1.0, rng=0)
    a = plan(lat, (32, 32), metric="cumulative")
    b = plan(lat, (32, 32), metric="nonscalar")
    ia, ib = visiting_order_image(a, seeds=False), visiting_order_image(b, seeds=False)
    assert ia.shape == ib.shape == (64, 64, 3) and np.abs(ia - ib).mean() > 0.05

    def roughness(res):  # visiting-order jumps between neighbours: fronts' raggedness
        r = res.as_image(res.rank).astype(float)
        return np.abs(np.diff(r, axis=0)).mean() + np.abs(np.diff(r, axis=1)).mean()

    assert roughness(b) > 2 * roughness(a)


# ---------------------------------------------------------------- stylization
def _test_image():
    img = np.ones((64, 64))
    img[16:48, 16:48] = 0.0
    return img


def test_stylize_small_image_and_cache():
    st = Stylizer(_test_image())
    # the paper's importance emphasis alone, in pixels, endpoints everywhere
    p = StylizeParams(n_endpoints=80, stipple_iterations=5, tone=0.0, hierarchy=0.0,
                      lattice_size=0, endpoint_threshold=0.0, endpoint_floor=0.01)
    out = st.run(p, rng=0)
    assert out.dendrite.is_tree()
    ends = out.lattice.node_index(out.endpoints)
    assert np.isin(ends, out.dendrite.nodes).all()  # every endpoint is on the dendrite
    _check_svg(out.rendering.svg)
    # importance emphasis: strokes along the square's edges (gradient, 3x weight)
    # are thicker than inside it (darkness only), which beat the white background
    r = out.dendrite.radius
    x, y = out.dendrite.points.T
    cheb = np.maximum(np.abs(x - 31.5), np.abs(y - 31.5))  # 16 on the square's edge
    edge, inside, white = np.abs(cheb - 16) < 2, cheb < 12, cheb > 20
    assert r[edge].mean() > 1.5 * r[inside].mean() > 1.5 * r[white].mean()
    # a thickness-only change reuses plan and endpoints
    out2 = st.run(dataclasses.replace(p, max_width=6.0), rng=0)
    assert out2.plan is out.plan and out2.endpoints is out.endpoints
    assert out2.dendrite.radius.max() > out.dendrite.radius.max()
    # a metric change re-plans but keeps the endpoints
    out3 = st.run(dataclasses.replace(p, metric="cumulative"), rng=0)
    assert out3.plan is not out.plan and out3.endpoints is out.endpoints


def test_stylize_is_reproducible():
    a = stylize(_test_image(), StylizeParams(n_endpoints=40, stipple_iterations=3), rng=3)
    b = stylize(_test_image(), StylizeParams(n_endpoints=40, stipple_iterations=3), rng=3)
    np.testing.assert_array_equal(a.rendering.image, b.rendering.image)


@pytest.mark.parametrize("value", [0.0, 1.0])
def test_constant_image_is_handled(value):
    out = stylize(np.full((40, 40), value), StylizeParams(n_endpoints=100, stipple_iterations=5),
                  rng=0)
    d = out.dendrite
    assert d.is_tree() and len(d.tips) == len(np.unique(d.nodes[d.tips]))
    # constant importance: constant width away from the tapered tips
    nxt = d.next_in_branch()
    deep = np.array([nxt[nxt[nxt[nxt[nxt[nxt[nxt[nxt[i]]]]]]]] >= 0 if nxt[i] >= 0 else False
                     for i in range(d.n_nodes)])
    inner = d.radius[deep & (d.parent >= 0)]
    assert np.ptp(inner) < 1e-9


# ---------------------------------------------------------------------- trees
def test_tree_trunk_is_thickest_and_iterations_shrink():
    p = TreeParams(iterations=3, radius=30.0, scale_lengths=False)
    t = grow_tree((160, 140), p, rng=0)
    d = t.dendrite
    assert d.is_tree()
    root = np.flatnonzero(d.parent < 0)
    assert len(root) == 1 and d.radius[root[0]] == d.radius.max()
    assert set(d.iteration.tolist()) == {1, 2, 3}
    assert t.metrics[0][0] == "cumulative" and t.metrics[-1] == ("blend", p.blend_weight)
    assert t.radii[1] == 30.0 and t.radii[2] == pytest.approx(30.0 * p.radius_decay)
    # thicker for older iterations
    means = [d.radius[d.iteration == i].mean() for i in (1, 2, 3)]
    assert means[0] > means[1] > means[2]
    # endpoints of iteration i were within R_i of the structure before it
    for i in (2, 3):
        mask = np.zeros(d.shape, bool).ravel()
        mask[d.nodes[d.iteration < i]] = True
        dist = ndimage.distance_transform_edt(~mask.reshape(d.shape))
        e = t.endpoints[i - 1].astype(int)
        assert dist[e[:, 1], e[:, 0]].max() <= t.radii[i - 1] + 1e-9
    # grows upward from the bottom centre
    assert d.points[root[0], 1] == 159 and d.points[:, 1].mean() < 100


def test_tree_is_the_same_at_any_canvas_size():
    # the radius and widths are px of 512 x 512 and scale with the canvas: before, a
    # 2000-px tree was a thin pole with hairline limbs (mean ink 0.016 vs 0.235 at 200 px)
    p = TreeParams(iterations=3)
    ink, trunk = {}, {}
    for n in (128, 384):
        t = grow_tree((n, n), p, rng=0)
        ink[n] = 1.0 - float(render_tree(t.dendrite).image[..., :3].mean())
        trunk[n] = 2 * t.dendrite.radius.max()
        assert t.radii[1] == pytest.approx(p.radius * n / 512)
        assert t.params == p  # the parameters as given
    assert 0.8 < ink[128] / ink[384] < 1.25, ink  # 0.046 / 0.048 (1.7x before)
    assert 2.2 < trunk[384] / trunk[128] < 3.8, trunk
    # scale_lengths=False: px of the canvas itself, as in the paper
    raw = grow_tree((128, 128), TreeParams(iterations=3, scale_lengths=False), rng=0)
    assert raw.radii[1] == p.radius


def test_rejection_endpoints_band():
    m = np.zeros((60, 60), bool)
    m[30, 10:50] = True
    pts = rejection_endpoints(m, 100, 10.0, min_distance=4.0, rng=0)
    dist = ndimage.distance_transform_edt(~m)
    v = dist[pts[:, 1].astype(int), pts[:, 0].astype(int)]
    assert len(pts) == 100 and v.min() >= 4.0 and v.max() <= 10.0


def test_occlusion_layers_share_the_trunk():
    layers = grow_layers((100, 90), TreeParams(iterations=2, radius=20.0), layers=3, rng=0)
    firsts = [lay.dendrite.nodes[lay.dendrite.iteration == 1] for lay in layers]
    assert all(np.array_equal(firsts[0], f) for f in firsts[1:])
    seconds = [set(lay.dendrite.nodes[lay.dendrite.iteration == 2]) for lay in layers]
    assert seconds[0] != seconds[1]


def test_pareidolia_branches_follow_the_image_on_its_side():
    img = np.ones((96, 96))
    img[20:70, 8:40] = 0.0  # a dark block on the left (image) side
    t = pareidolia_tree(img, PareidoliaParams(n_endpoints=150, iterations=3, side="left",
                                              crown="ellipse", random_ratio=0.5,
                                              lattice_size=0), rng=0)
    d = t.dendrite
    assert d.is_tree()
    assert len(t.endpoints_random) == 75  # about half as many random endpoints
    assert (t.endpoints_image[:, 0] < 48).all() and (t.endpoints_random[:, 0] >= 48).all()
    later = d.iteration > 1
    x = d.points[:, 0]
    imp = t.importance.ravel()[d.nodes]
    # on the image side the branches concentrate on important pixels
    side_mean = t.importance[:96, :48].mean()
    assert imp[later & (x < 48)].mean() > 1.5 * side_mean


# ------------------------------------------------------------------ bad input
def test_bad_input_errors():
    lat = make_lattice(np.zeros((20, 20)), rng=0)
    res = plan(lat, (10, 10))
    with pytest.raises(ValueError, match="at least 1"):
        build_dendrite(res, np.zeros((0, 2)))
    with pytest.raises(ValueError, match="outside"):
        build_dendrite(res, [(25, 3)])
    with pytest.raises(ValueError, match="n_endpoints must be >= 1"):
        place_endpoints(np.ones((10, 10)), 0)
    with pytest.raises(ValueError, match="n_endpoints"):
        stylize(_test_image(), StylizeParams(n_endpoints=0))
    with pytest.raises(ValueError, match="seed"):
        Stylizer(_test_image()).run(StylizeParams(n_endpoints=10), seed=(100, 5))
    with pytest.raises(ValueError, match="NaN"):
        stylize(np.full((10, 10), np.nan))
    with pytest.raises(ValueError, match="both 0"):
        importance_map(_test_image(), ImportanceParams(intensity_weight=0, gradient_weight=0))
    with pytest.raises(ValueError, match="metaphor"):
        stylize(_test_image(), StylizeParams(n_endpoints=5), metaphor="oil")
    with pytest.raises(ValueError, match="density is zero"):
        place_endpoints(np.zeros((10, 10)), 5, floor=0.0)


def test_unreachable_endpoint_is_an_error():
    w = np.ones((20, 20))
    w[:, 10] = np.inf
    from branchnb.dendrite import Lattice

    res = plan(Lattice(w), (2, 2))
    with pytest.raises(ValueError, match="not reached"):
        build_dendrite(res, [(15, 5)])


def test_bench_rows_quick():
    from branchnb.dendrite._bench import rows

    out = rows(quick=True)
    assert len(out) == 5 and all(r.seconds > 0 and r.anchor_seconds > 0 for r in out)
    assert out[3].seconds < out[3].anchor_seconds  # far below the paper's 237 s


def test_metric_mix_per_iteration():
    from branchnb.dendrite.trees import iteration_metric

    p = TreeParams(iterations=4, blend_weight=900.0, mix_power=1.0)
    assert [iteration_metric(i, p) for i in range(1, 5)] == [
        ("cumulative", 0.0), ("blend", 300.0), ("blend", 600.0), ("blend", 900.0)]
    flat = TreeParams(iterations=3, mix_power=0.0)
    assert [iteration_metric(i, flat)[1] for i in (2, 3)] == [1000.0, 1000.0]
