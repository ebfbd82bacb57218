"""Issue 23 (branching40): the compiled glue of the grow loop gives the answers of the numpy code it
replaces, to the bit: ``_Grower._register`` (segment store, density, length, running histograms)
against its numpy path, a plain Markov step (``_loop_kernels.plain_step``) against the general path of
``_Grower.step`` over whole syntheses, and the fill rounds' distance transform (``filling._edt``)
against scipy's."""

from __future__ import annotations

import types

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import _loop_kernels, fit_model, synthesize_structure
from branchnb.branching._map_examples import crack_pattern_example
from branchnb.branching.colonization import DensityMap, SegmentStore
from branchnb.branching.filling import _edt
from branchnb.branching.growth import _Grower
from branchnb.branching.histogram_matching import HistogramMatcher
from branchnb.branching.straightness import BendHistogram


@pytest.fixture(scope="module")
def crack_model():
    from branchnb.branching import extract_structure

    # no domain: roots then start on a free frame, which only the general step handles, so both paths run
    img = crack_pattern_example((288, 288), 2)   # above small_frames.SMALL_SIDE: the paper's frame rules
    # (its former roots: root="auto" now also roots a tree where a thick crack enters the frame)
    return fit_model(extract_structure(img, root="thickest"))


def _bookkeeping(rng, density: bool):
    g = types.SimpleNamespace()
    g.store = SegmentStore(capacity=4, shape=(90, 120))   # small: the buffers grow
    g.store._next = g.store._next[:3]
    g.store._seg = g.store._seg[:3]
    dom = rng.random((90, 120)) < 0.8
    g.density = DensityMap((90, 120), 6.0, domain=dom, level=float(np.exp(-1.0))) if density else None
    g.matcher = HistogramMatcher(rng.normal(0, 0.3, 200), rng.uniform(0.5, 4, 200), bins=16, wG=50.0, m=4)
    g.bends = BendHistogram(rng.normal(0, 0.3, 200), wG=50.0, m=4)
    g.total_length = 0.0
    g._e_grid, g._e_dom = np.zeros((1, 1), np.float32), np.zeros((1, 1), bool)
    return g


@pytest.mark.parametrize("density", [True, False])
def test_register_equals_the_numpy_path(monkeypatch, density):
    rng = np.random.default_rng(3)
    polys = []
    for _ in range(60):
        n = int(rng.choice([1, 2, 5, 7, 9, 30]))
        p = rng.uniform(-10, 130, 2) + np.cumsum(rng.normal(0, 4, (n, 2)), axis=0)   # some off the frame
        a = rng.normal(0, 0.5, max(n - 2, 0)) * (rng.random() < 0.9)
        polys.append((p, a, rng.uniform(0.3, 5, n)))
    fast, ref = _bookkeeping(np.random.default_rng(1), density), _bookkeeping(np.random.default_rng(1), density)
    for p, a, r in polys:
        _Grower._register(fast, p, a, r)
    monkeypatch.setattr(_loop_kernels, "MAX_REGISTER", 0)   # the numpy path
    for p, a, r in polys:
        _Grower._register(ref, p, list(a), list(r))
    assert fast.total_length == ref.total_length > 0
    s, t = fast.store, ref.store
    assert s.n == t.n and np.array_equal(s.p0[:s.n], t.p0[:t.n]) and np.array_equal(s.p1[:s.n], t.p1[:t.n])
    assert s._n_entries == t._n_entries and np.array_equal(s._head, t._head)
    assert np.array_equal(s._next[:s._n_entries], t._next[:t._n_entries])
    assert np.array_equal(s._seg[:s._n_entries], t._seg[:t._n_entries])
    for k in ("counts_a", "counts_r", "n_nodes"):
        assert np.array_equal(getattr(fast.matcher, k), getattr(ref.matcher, k)), k
    assert np.array_equal(fast.bends.counts, ref.bends.counts) and fast.bends.counts.sum() > 50
    if density:
        assert np.array_equal(fast.density.grid, ref.density.grid)
        assert fast.density.coverage() == ref.density.coverage() > 0


def _key(s):
    return [(b.points.tobytes(), np.asarray(b.thickness).tobytes(), b.parent, b.parent_vertex) for b in s.branches]


@pytest.mark.parametrize("cap", [None, 12])   # every candidate scored, and a random share with retries
def test_plain_steps_equal_the_general_path(crack_model, monkeypatch, cap):
    import branchnb.branching.growth as growth

    if cap is not None:
        monkeypatch.setattr(growth, "MAX_CANDIDATES", cap)
    calls = []
    plain = _Grower._plain

    def counted(self, st):
        out = plain(self, st)
        calls.append(out)
        return out

    monkeypatch.setattr(_Grower, "_plain", counted)
    new = [synthesize_structure(crack_model, rng=s).structure for s in (0, 1, 2)]
    assert 20 < sum(calls) < len(calls)   # both paths were taken (roots on a free frame: the general one)
    monkeypatch.setattr(_Grower, "_plain", lambda self, st: False)
    old = [synthesize_structure(crack_model, rng=s).structure for s in (0, 1, 2)]
    for a, b in zip(new, old):
        assert len(a.branches) >= 5
        assert _key(a) == _key(b)


def test_edt_equals_scipy():
    rng = np.random.default_rng(4)
    for trial in range(60):
        h, w = (int(v) for v in rng.integers(1, 160, 2))
        m = rng.random((h, w)) > float(rng.choice([0.0, 0.002, 0.05, 0.5, 0.98, 1.0]))
        ref = ndi.distance_transform_edt(m)
        got, got32 = _edt(m), _edt(m, float32=True)
        assert got.dtype == np.float64 and got32.dtype == np.float32
        assert np.array_equal(got, ref), trial
        assert np.array_equal(got32, ref.astype(np.float32)), trial
