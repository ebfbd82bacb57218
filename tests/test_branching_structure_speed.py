"""Issue 23 (branching21): structure synthesis on large examples scores a random share of the
candidates (speed), the crossing test reads a bucket grid, deltas part at their head, and the
straight runs of drawn lines follow the example's."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

import branchnb.branching.growth as growth
from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._map_examples import crack_pattern_example, delta_mask_example
from branchnb.branching.colonization import SegmentStore, crosses_existing
from branchnb.branching.domains import head_share
from branchnb.branching.measures import straight_runs
from branchnb.core.polyline import segments_intersect


@pytest.fixture(scope="module")
def crack_model():
    img = crack_pattern_example((256, 256), 0)
    ex = extract_structure(img)
    return fit_model(ex, domain=example_domain(img, ex))


def _segments_brute(store, poly, eps=1e-9):
    """The crossing test over every stored segment (reference)."""
    ref = SegmentStore(cell=1e9)   # one bucket: every segment is read
    ref.add(store.p0[:store.n], store.p1[:store.n])
    return crosses_existing(ref, poly, eps)


def test_bucketed_crossing_test_equals_the_full_scan():
    rng = np.random.default_rng(0)
    store = SegmentStore(capacity=4, cell=16.0)
    for _ in range(60):   # random walks of 4 px steps, like grown branches
        p = np.cumsum(np.r_[rng.uniform(0, 200, (1, 2)), rng.normal(0, 3, (8, 2))], axis=0)
        store.add_polyline(p)
    hits = 0
    for _ in range(400):
        q = np.cumsum(np.r_[rng.uniform(0, 200, (1, 2)), rng.normal(0, 6, (4, 2))], axis=0)
        got = crosses_existing(store, q)
        assert got == _segments_brute(store, q)
        hits += got
    assert 20 < hits < 380   # both answers were exercised


def test_small_examples_score_every_candidate(crack_model, monkeypatch):
    # below MAX_CANDIDATES nothing is subsampled: the same seed gives the same structure
    n = crack_model.bending.n_elements
    assert n < growth.MAX_CANDIDATES
    a = synthesize_structure(crack_model, rng=3).structure
    monkeypatch.setattr(growth, "MAX_CANDIDATES", 10 ** 9)
    b = synthesize_structure(crack_model, rng=3).structure
    assert len(a.branches) == len(b.branches)
    assert all(np.array_equal(x.points, y.points) for x, y in zip(a.branches, b.branches))


def test_a_share_of_the_candidates_keeps_the_figures(crack_model, monkeypatch):
    # scoring a random 64 of the example's ~500 windows (and heads) per step: the length, the
    # straight runs and the turning angles stay those of the full scoring (within 15 %)
    full = [synthesize_structure(crack_model, rng=s).structure for s in range(3)]
    monkeypatch.setattr(growth, "MAX_CANDIDATES", 64)
    share = [synthesize_structure(crack_model, rng=s).structure for s in range(3)]
    for key in (lambda s: s.total_length, lambda s: straight_runs(s)[1], lambda s: straight_runs(s)[0]):
        f = np.mean([key(s) for s in full])
        g = np.mean([key(s) for s in share])
        assert g == pytest.approx(f, rel=0.15)
    for s in share:   # still no crossings
        p0, p1, _ = s.segments()
        assert int(np.triu(segments_intersect(p0, p1, p0, p1), 1).sum()) == 0


@pytest.mark.parametrize("size, seed", [(256, 0), (320, 4)])
def test_delta_channels_part_at_the_head(size, seed):
    # before: the trunk's children started anywhere along it (often right at the top of the
    # image) and the channels fanned from where the trunk entered; now they part where the
    # example's do (its first furcation's depth share) and nowhere upstream of it
    m, _ch, _sea = delta_mask_example((size, size), seed)
    img = np.dstack([m] * 3)
    ex = extract_structure(img)
    dom = example_domain(img, ex)
    model = fit_model(ex, domain=dom)
    share = head_share(model.example, model.domain)
    assert 0.2 < share < 0.95
    depth = ndi.distance_transform_edt(dom)
    for rng in range(2):
        s = synthesize_structure(model, rng=rng).structure
        roots = [i for i, b in enumerate(s.branches) if b.parent is None]
        assert len(roots) == 1
        trunk = s.branches[roots[0]].points
        d0 = depth[int(round(trunk[0][1])), int(round(trunk[0][0]))]
        kids = [b for b in s.branches if b.parent == roots[0]]
        assert kids
        for b in kids:
            x, y = np.rint(b.points[0]).astype(int)
            assert depth[y, x] <= share * d0 + 2.0, "a channel parts upstream of the delta's head"
