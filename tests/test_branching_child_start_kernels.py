"""Issue 23 (branching46): the compiled child start and density rebuild give the answers of the code
they replace, to the bit: ``_loop_kernels.child_start`` (a child's start without guidance, drain or
shore, up to the draw) against ``_Starts._start_branch`` over whole syntheses, every input head's
histogram rows (``_kernels.head_rows``) against the matcher's bins, and the density rebuild
(``colonization._splat_union``) against splatting segment by segment."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import _kernels, fit_model, synthesize_structure
from branchnb.branching._map_examples import crack_pattern_example
from branchnb.branching.colonization import _splat_segments, _splat_union
from branchnb.branching.growth import _Grower
from branchnb.branching.params import SynthesisParams


@pytest.fixture(scope="module")
def crack_model():
    from branchnb.branching import example_domain, extract_structure

    img = crack_pattern_example((192, 192), 2)
    ex = extract_structure(img)
    return fit_model(ex, domain=example_domain(img, ex))


def _key(s):
    return [(b.points.tobytes(), np.asarray(b.thickness).tobytes(), b.parent, b.parent_vertex) for b in s.branches]


@pytest.mark.parametrize("cap", [None, 12])   # every furcation scored, and a random share with retries
@pytest.mark.parametrize("mirror", [True, False])
def test_plain_child_starts_equal_the_general_path(crack_model, monkeypatch, cap, mirror):
    import branchnb.branching.growth as growth

    if cap is not None:
        monkeypatch.setattr(growth, "MAX_CANDIDATES", cap)
    p = SynthesisParams(mirror_children=mirror)
    calls = []
    plain = _Grower._plain_child

    def counted(self, *a):
        calls.append(1)
        return plain(self, *a)

    monkeypatch.setattr(_Grower, "_plain_child", counted)
    new = [synthesize_structure(crack_model, p, rng=s).structure for s in (0, 1)]
    assert len(calls) >= 10
    monkeypatch.setattr(_Grower, "_plain_start", lambda self: False)
    old = [synthesize_structure(crack_model, p, rng=s).structure for s in (0, 1)]
    for a, b in zip(new, old):
        assert sum(x.parent is not None for x in a.branches) >= 2
        assert _key(a) == _key(b)


def test_head_rows_are_the_heads_sorted_bins(crack_model):
    m = crack_model
    hm = m.matcher(SynthesisParams().wG)
    rows_a, rows_r = _kernels.head_rows(m.first_a, m.first_len, hm.edges_a, _kernels.element_bins(m.cum_r),
                                        m.head_start)
    assert rows_a.shape[:2] == (2, len(m.first_len)) and rows_r.shape[0] == len(m.first_len)
    nb = len(hm.edges_a) - 1
    checked = 0
    for hd in np.flatnonzero(m.first_len > 0):
        n = int(m.first_len[hd])
        k = min(n, m.first_a.shape[1])
        for s, sg in ((0, 1.0), (1, -1.0)):
            want = np.sort(np.clip(np.searchsorted(hm.edges_a, m.first_a[hd, :k] * sg, side="right") - 1, 0, nb - 1))
            assert np.array_equal(rows_a[s, hd, :k], want) and (rows_a[s, hd, k:] == 32767).all()
        cr = m.cum_r[m.head_start[hd] + n] - m.cum_r[m.head_start[hd]]   # the head's thickness counts
        want_r = np.repeat(np.arange(len(cr)), np.rint(cr).astype(int))
        assert np.array_equal(rows_r[hd, :n], want_r) and (rows_r[hd, n:] == 32767).all()
        checked += 1
    assert checked >= 8   # the 192 px crack keeps fewer heads since the small-frame rules (10)


@pytest.mark.parametrize("cell", [1.0, 2.0, 2.5])
def test_density_rebuild_equals_segment_by_segment(cell):
    rng = np.random.default_rng(int(cell * 10))
    level = float(np.exp(-1.0))
    for trial in range(12):
        gh, gw = (int(v) for v in rng.integers(10, 150, 2))
        rho = float(rng.uniform(1.5, 20.0))
        dom = rng.random((gh, gw)) < 0.8
        n = int(rng.integers(1, 250))
        p0 = rng.uniform(-15, max(gh, gw) * cell + 15, (n, 2))   # some off the grid
        p1 = p0 + rng.normal(0, 6, (n, 2))
        p1[: n // 10] = p0[: n // 10]   # zero-length segments
        ref = np.zeros((gh, gw), np.float32)
        got = np.zeros((gh, gw), np.float32)
        above = sum(int(_splat_segments(ref, dom, p0[k:k + 5], p1[k:k + 5], cell, rho, level))
                    for k in range(0, n, 5))
        assert int(_splat_union(got, dom, p0, p1, cell, rho, level)) == above
        assert np.array_equal(got.view(np.int32), ref.view(np.int32)), trial
        assert (ref > 0).any()
