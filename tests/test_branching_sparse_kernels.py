"""Issue 23 (branching28): the faster glue of structure synthesis computes what it replaced, to the bit.

The histogram factors read each candidate's few counted bins (``_kernels.count_bins``,
``_kernels.element_bins``) instead of its ``B``-wide row of counts; ``_Grower._inside`` is compiled;
furcation picks reuse the branch's windows; the hole map rasterises every branch at once.
"""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import _kernels, example_domain, extract_structure, fit_model
from branchnb.branching._map_examples import crack_pattern_example
from branchnb.branching.filling import _hole_map
from branchnb.branching.furcation import _gaps, furcation_features, vertex_angles, window_features


@pytest.fixture(scope="module")
def crack_model():
    img = crack_pattern_example((256, 256), 0)
    ex = extract_structure(img)
    return fit_model(ex, domain=example_domain(img, ex))


def test_count_bins_rebuild_the_counts():
    rng = np.random.default_rng(0)
    cc = rng.integers(0, 3, (200, 16)).astype(np.float64)
    cc[5] = 0.0
    bins = _kernels.count_bins(cc)
    back = np.zeros_like(cc)
    for i, row in enumerate(bins):
        for b in row[row < 16]:
            back[i, b] += 1
    assert np.array_equal(back, cc)
    assert (np.diff(bins.astype(np.int64), axis=1) >= 0).all()   # ascending, padding last
    with pytest.raises(ValueError, match="whole counts"):
        _kernels.count_bins(cc + 0.5)


@pytest.mark.parametrize("which", ["a", "r"])
def test_sparse_improvements_equal_the_dense_ones_to_the_bit(crack_model, which):
    m = crack_model
    hm = m.matcher(50.0)
    rng = np.random.default_rng(1)
    p = hm.p_a if which == "a" else hm.p_r
    cc = m.cand_counts_a if which == "a" else m.cand_counts_r
    counts = rng.integers(0, 40, len(p)).astype(np.float64)
    t = np.sort(rng.choice(len(cc), min(500, len(cc)), replace=False))
    dense = _kernels._improvements(p, counts, cc, np.zeros(0), t)
    sparse = _kernels._improvements_bins(p, counts, _kernels.count_bins(cc), t)
    assert np.array_equal(dense, sparse)
    assert np.abs(dense).max() > 0


def test_element_bins_rebuild_the_running_counts(crack_model):
    cum = crack_model.cum_r
    b = _kernels.element_bins(cum)
    one = np.zeros_like(cum)
    one[1 + np.arange(len(b)), b] = 1.0
    assert np.array_equal(np.cumsum(one, axis=0), cum)


@pytest.mark.parametrize("with_domain", [False, True])
def test_inside_kernel_equals_the_numpy_rule(with_domain):
    rng = np.random.default_rng(2)
    h, w = 37, 51
    dom = rng.random((h, w)) < 0.6
    pts = np.r_[rng.uniform(-2, 53, (400, 2)),
                [[-0.5, 0], [w - 0.5, h - 0.5], [-0.51, 3], [2.5, 3.5], [3.5, 2.5], [w - 0.49, 0]]]
    ok = (pts[:, 0] >= -0.5) & (pts[:, 0] <= w - 0.5) & (pts[:, 1] >= -0.5) & (pts[:, 1] <= h - 0.5)
    if with_domain:
        ix = np.clip(np.rint(pts[:, 0]).astype(np.int64), 0, w - 1)
        iy = np.clip(np.rint(pts[:, 1]).astype(np.int64), 0, h - 1)
        ok &= dom[iy, ix]
    got = _kernels.inside(pts, h, w, dom if with_domain else np.zeros((1, 1), bool), with_domain)
    assert np.array_equal(got, ok)
    assert got.any() and not got.all()


def _choose_reference(fm, points, radii, d, min_spacing=0, existing=(), weights=None):
    """FurcationModel.choose as it was: features rebuilt (np.pad) at every pick."""
    N = len(points)
    chosen, furc = [], list(existing)
    for _ in range(int(d)):
        av = vertex_angles(points)
        pa, pr = np.pad(av, fm.k), np.pad(np.asarray(radii, np.float64), fm.k, mode="edge")
        idx = np.arange(N)[:, None] + np.arange(2 * fm.k + 1)[None, :]
        nm, npl = _gaps(N, furc)
        p = fm._proba(np.hstack([pa[idx], pr[idx], nm[:, None], npl[:, None]]))
        ok = np.ones(N, bool) if weights is None else weights > 0
        if weights is not None:
            p = p * weights
        ok[0] = ok[-1] = False
        for f in furc:
            ok[max(f - max(min_spacing, 1) + 1, 0):min(f + max(min_spacing, 1), N)] = False
        if not ok.any():
            break
        v = int(np.flatnonzero(ok)[np.argmax(p[ok])])
        chosen.append(v)
        furc.append(v)
    return sorted(chosen)


def test_furcation_choose_equals_the_rebuilt_features(crack_model):
    fm = crack_model.furcation
    assert fm.can_branch
    rng = np.random.default_rng(3)
    for trial in range(12):
        N = int(rng.integers(4, 60))
        pts = np.cumsum(rng.normal(0, 1, (N, 2)) + [4.0, 0.0], axis=0)
        rad = rng.uniform(0.8, 3.0, N)
        wts = rng.random(N) * (rng.random(N) < 0.7) if trial % 2 else None
        ex = tuple(rng.choice(N, 2, replace=False).tolist()) if trial % 3 == 0 else ()
        d, sp = int(rng.integers(1, 4)), int(rng.integers(0, 4))
        got = fm.choose(pts, rad, d, min_spacing=sp, existing=ex, weights=wts)
        assert got == _choose_reference(fm, pts, rad, d, sp, ex, wts)
    # the windows without np.pad are np.pad's
    av, rv = rng.normal(0, 0.3, 9), rng.uniform(1, 2, 9)
    wa, wr = window_features(av, rv, 3)
    idx = np.arange(9)[:, None] + np.arange(7)[None, :]
    assert np.array_equal(wa, np.pad(av, 3)[idx]) and np.array_equal(wr, np.pad(rv, 3, mode="edge")[idx])
    assert furcation_features(av, rv, [4], 3).shape == (9, 16)


def test_hole_map_of_all_branches_at_once_equals_branch_by_branch():
    rng = np.random.default_rng(4)
    dom = np.zeros((120, 150), bool)
    dom[10:110, 5:140] = True
    lines = [np.cumsum(rng.normal(0, 2, (int(rng.integers(1, 40)), 2)), axis=0) + [75, 60] for _ in range(6)]
    lines.append(np.zeros((0, 2)))
    share, dist, gap = _hole_map(lines, dom, 2.0)
    occ = np.zeros(dom[::2, ::2].shape, bool)
    for q in lines:
        if len(q):
            c = np.clip(np.floor((q[:, 0] + 0.5) / 2).astype(int), 0, occ.shape[1] - 1)
            r = np.clip(np.floor((q[:, 1] + 0.5) / 2).astype(int), 0, occ.shape[0] - 1)
            occ[r, c] = True
    assert np.array_equal(dist == 0, occ)
    assert 0.0 < share < 1.0 and gap > 0

