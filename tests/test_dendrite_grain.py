"""Pareidolia without lattice grain (``bottleneck="density"``).

With the paper's blend metric ``a M + S`` (``a = 1000``), ``M`` the largest edge cost,
a diagonal step costs sqrt(2) times an axis step over the same weights, so on a flat
region with mild noise the paths never step diagonally: a flat dark region was drawn
as horizontal rails with vertical spikes. Measuring ``M`` per unit of step length
makes the metric isotropic."""
import math

import numpy as np
import pytest
from scipy import ndimage
from skimage.color import rgb2gray

from branchnb.dendrite.lattice import Lattice, direction_factors, node_weights
from branchnb.dendrite.pareidolia import PareidoliaParams, pareidolia_tree
from branchnb.dendrite.planner import plan

STEPS = [(0, 1), (0, -1), (1, 0), (-1, 0), (1, 1), (1, -1), (-1, 1), (-1, -1)]


def _reference_blend(weights, seed, a, factors, mfactors):
    """Textbook Dijkstra (heapq, lazy deletion) of the key a * M + S, M over
    ``mfactors``-weighted edges, S over ``factors``-weighted ones."""
    import heapq

    h, w = weights.shape
    mmax = np.full(h * w, np.inf)
    total = np.full(h * w, np.inf)
    done = np.zeros(h * w, bool)
    mmax[seed] = total[seed] = 0.0
    heap = [(0.0, seed)]
    while heap:
        k, u = heapq.heappop(heap)
        if done[u] or k != a * mmax[u] + total[u]:
            continue
        done[u] = True
        r, c = divmod(u, w)
        for j, (dr, dc) in enumerate(STEPS):
            rr, cc = r + dr, c + dc
            if 0 <= rr < h and 0 <= cc < w and not done[rr * w + cc]:
                v = rr * w + cc
                e = 0.5 * (weights[r, c] + weights[rr, cc])
                m, s = max(mmax[u], e * mfactors[j]), total[u] + e * factors[j]
                if a * m + s < a * mmax[v] + total[v] or not np.isfinite(total[v]):
                    mmax[v], total[v] = m, s
                    heapq.heappush(heap, (a * m + s, v))
    return mmax, total


@pytest.mark.parametrize("factors", [None, direction_factors(up=0.96, down=1.04)])
def test_density_blend_equals_reference(factors):
    w = node_weights(np.zeros((13, 11)), epsilon=0.3, noise=0.25, rng=3)
    lat = Lattice(w, factors, bottleneck="density")
    f = lat.factors
    mf = [f[k] / math.hypot(*STEPS[k]) for k in range(8)]
    res = plan(lat, (5, 6), metric="blend", blend_weight=1000.0)
    m, s = _reference_blend(w, 6 * 11 + 5, 1000.0, f, mf)
    assert np.allclose(res.max_cost, m) and np.allclose(res.total_cost, s)


def test_cumulative_does_not_depend_on_the_bottleneck():
    w = node_weights(np.zeros((40, 40)), noise=0.5, rng=1)
    a = plan(Lattice(w), (3, 3), metric="cumulative")
    b = plan(Lattice(w, bottleneck="density"), (3, 3), metric="cumulative")
    assert np.array_equal(a.parent, b.parent) and np.allclose(a.total_cost, b.total_cost)


def test_flat_blend_paths_step_diagonally_with_density():
    """On a flat noisy lattice the edge bottleneck never steps diagonally (the paper's
    M); the density bottleneck does about as often as a geodesic does."""
    w = node_weights(np.zeros((96, 96)), epsilon=0.3, noise=0.25, rng=0)
    share = {}
    for b in ("edge", "density"):
        res = plan(Lattice(w, bottleneck=b), (48, 48), metric="blend", blend_weight=1000.0)
        has = res.parent >= 0
        r, c = np.divmod(np.flatnonzero(has), 96)
        pr, pc = np.divmod(res.parent[has], 96)
        share[b] = float(((r != pr) & (c != pc)).mean())
    # measured: 0.00 (edge), 0.36 (density)
    assert share["edge"] < 0.02
    assert share["density"] > 0.25


def test_bad_bottleneck():
    with pytest.raises(ValueError, match="bottleneck"):
        Lattice(np.ones((3, 3)), bottleneck="max")
    with pytest.raises(ValueError, match="bottleneck"):
        plan(Lattice(np.ones((3, 3)), bottleneck="density"), (1, 1), metric="nonscalar")
    with pytest.raises(ValueError, match="bottleneck"):
        pareidolia_tree(np.ones((32, 32)), PareidoliaParams(bottleneck="max"))


def _disc(n):
    yy, xx = np.mgrid[0:n, 0:n] / n
    g = np.where(np.hypot(xx - 0.5, yy - 0.5) < 0.38, 0.05, 0.95)
    return np.repeat(g[..., None], 3, -1).astype(np.float32)


def _orientation_hist(t, nb=12):
    """Orientation histogram (structure tensor, energy weighted) of the drawn ink in the
    disc's dark region (eroded 3 px); bin 0 is horizontal, nb // 2 vertical."""
    ink = 1.0 - rgb2gray(np.asarray(t.render().image)[..., :3])
    dk = ndimage.binary_erosion((1.0 - rgb2gray(t.image) >= 0.6) & t.crown_on_canvas(),
                                iterations=3)
    gy = ndimage.gaussian_filter(ink, 1.0, order=(1, 0))
    gx = ndimage.gaussian_filter(ink, 1.0, order=(0, 1))
    jxx, jyy, jxy = (ndimage.gaussian_filter(a, 2.0) for a in (gx * gx, gy * gy, gx * gy))
    ang = (0.5 * np.arctan2(2 * jxy, jxx - jyy) + np.pi / 2) % np.pi
    wt = np.hypot(jxx - jyy, 2 * jxy)
    b = np.floor((ang[dk] + np.pi / nb / 2) / (np.pi / nb)).astype(int) % nb
    h = np.bincount(b, weights=wt[dk], minlength=nb)
    return h / h.sum() * nb  # 1 = uniform


@pytest.fixture(scope="module")
def discs():
    img = _disc(400)
    out = {b: pareidolia_tree(img, PareidoliaParams(bottleneck=b), rng=0) for b in ("edge", "density")}
    out["stubs"] = pareidolia_tree(img, PareidoliaParams(min_twig=0.0), rng=0)
    return out


def _twigs(t):
    """Length and length / mean width of the terminal twigs in the dark region."""
    d = t.dendrite
    dk = ndimage.binary_erosion((1.0 - rgb2gray(t.image) >= 0.6) & t.crown_on_canvas(),
                                iterations=3)
    at = np.rint(d.points).astype(int)
    inside = dk[np.clip(at[:, 1], 0, dk.shape[0] - 1), np.clip(at[:, 0], 0, dk.shape[1] - 1)]
    has = d.parent >= 0
    seg = np.zeros(d.n_nodes)
    seg[has] = np.hypot(*(d.points[has] - d.points[d.parent[has]]).T)
    tips = set(d.tips.tolist())
    length, aspect = [], []
    for b in d.branches:
        b = b[1:] if len(b) > 1 else b
        if int(b[-1]) in tips and inside[b].mean() > 0.8 and seg[b].sum() > 0:
            length.append(seg[b].sum())
            aspect.append(seg[b].sum() ** 2 / np.sum(2 * d.radius[b] * seg[b]))
    return np.median(length), np.median(aspect)


def test_flat_dark_disc_has_no_horizontal_rails(discs):
    assert PareidoliaParams().bottleneck == "density"
    edge, dens = (_orientation_hist(discs[b]) for b in ("edge", "density"))
    # measured (400 px): horizontal bin 2.2 -> 0.5 of uniform, largest bin 2.2 -> 1.7,
    # axis bins 1.36 -> 1.02 (the rest of the anisotropy is up and out: ``rise``)
    assert edge[0] > 1.8 and dens[0] < 1.0
    assert dens.max() < 0.8 * edge.max()
    # the axis bins (0, 45, 90, 135 deg) together near their uniform share
    assert dens[[0, 3, 6, 9]].sum() / 4 < 1.2


def test_tone_holds_without_grain(discs):
    for t in discs.values():
        crown = t.crown_on_canvas()
        x = ndimage.gaussian_filter(1.0 - rgb2gray(t.image), 4.0)[crown]
        y = ndimage.gaussian_filter(1.0 - rgb2gray(np.asarray(t.render().image)[..., :3]), 4.0)[crown]
        assert np.corrcoef(x, y)[0, 1] >= 0.75


def test_twigs_are_long_and_slim(discs):
    """No stubs next to the branches (``min_twig``) and twigs at least 6x as long as
    wide in the dark: measured on the 400-px disc, median length 6.3 px (stubs kept:
    5.3), length / width 7.6 (5.0 with the paper's 3x everywhere)."""
    length, aspect = _twigs(discs["density"])
    length0, _ = _twigs(discs["stubs"])
    assert length > 1.1 * length0
    assert aspect >= 6.5
