"""Issue 23: holes left after growth are filled by branches grown into them (``_Filling._fill_far``).

Known answer: a comb example (a trunk along the left side, evenly spaced teeth across the frame)
leaves no part of the frame far from a branch; a forest grown only along the top edge leaves the
lower part empty, and the fill pass must bring the far share down to the example's with children
joined to the branches already there.
"""

from __future__ import annotations

import numpy as np

from branchnb.branching.filling import _hole_map
from branchnb.branching.growth import FILL_LENGTH_FACTOR, _Grower, length_cap
from branchnb.branching.measures import far_share
from branchnb.branching.params import SynthesisParams
from branchnb.branching.synthesis import fit_model
from branchnb.core.structure import Branch, Structure


def _comb(n: int = 160) -> Structure:
    rng = np.random.default_rng(3)
    trunk = np.c_[np.full(40, 8.0) + rng.normal(0, 0.3, 40), np.linspace(4, n - 5, 40)]
    br = [Branch(trunk, np.linspace(3, 2, 40))]
    for v in range(3, 38, 5):
        y = trunk[v, 1]
        xs = np.linspace(8, n - 6, 36)
        ys = y + 3 * np.sin(xs / 17.0 + v)
        br.append(Branch(np.c_[xs, ys], np.linspace(2, 1, 36), 0, v))
    return Structure(br, (n, n))


def _grown_along_the_top(model, seed):
    g = _Grower(model, SynthesisParams(), np.random.default_rng(seed), (160, 160), None)
    r = g.start_root(6.0, 10.0, 0.0)
    g.branches[r].target = np.inf
    g.grow(r, 30)
    g.stop_reason = "density (coverage)"
    # as synthesize_structure does before its fill passes: holes may be filled past the auto cap
    g.max_total = length_cap(model, SynthesisParams(), (160, 160), None, factor=FILL_LENGTH_FACTOR)
    return g


def test_fill_far_grows_children_into_the_empty_part():
    ex = _comb()
    model = fit_model(ex)
    dom = np.ones((160, 160), bool)
    target = far_share(model.example, dom)
    for seed in (0, 1, 2):
        g = _grown_along_the_top(model, seed)
        before = far_share(g.structure(), dom)
        n0 = len(g.branches)
        g._fill_far()
        s = g.structure()
        after = far_share(s, dom)
        assert before > 0.4 and after <= 1.5 * target + 0.02, (seed, before, after, target)
        # every new branch is a child joined to a branch grown before it
        assert all(b.parent is not None and b.parent < i for i, b in enumerate(s.branches[n0:], n0))
        # the stop reason of the run is kept, unless the fill itself reached the length cap
        # (FILL_LENGTH_FACTOR = 1.3 since branching19; at 2 it never did here)
        assert g.stop_reason in ("density (coverage)", "total length")


def test_a_fill_child_stopping_short_leaves_the_rest_of_the_hole_open(monkeypatch):
    # branching54: with like-radius tapers (growth.TAPER_LIKENESS 2, off by default) the first child
    # toward the lower-left corner of seed 0 left the domain after 64 px of the 150 it had to go; the
    # whole hole within 150 px of the corner was then ruled out and the fill stopped at a far share of
    # 0.556 (example 0.108). Now only the goal's neighbourhood is left: 0.114
    import branchnb.branching.growth as growth

    monkeypatch.setattr(growth, "TAPER_LIKENESS", 2.0)
    ex = _comb()
    model = fit_model(ex)
    dom = np.ones((160, 160), bool)
    target = far_share(model.example, dom)
    g = _grown_along_the_top(model, 0)
    g._fill_far()
    assert far_share(g.structure(), dom) <= 1.5 * target + 0.02


def test_fill_far_leaves_a_covered_frame_alone_and_respects_the_user():
    ex = _comb()
    model = fit_model(ex)
    g = _grown_along_the_top(model, 0)
    g.p = SynthesisParams(fill_rounds=0)
    n0 = len(g.branches)
    g._fill_far()
    assert len(g.branches) == n0
    # a structure as spread as the example has nothing to fill
    g = _Grower(model, SynthesisParams(), np.random.default_rng(0), (160, 160), None)
    g.add_existing(ex)
    assert _hole_map([b.points for b in ex.branches], np.ones((160, 160), bool), 2.0)[0] < 0.15
    g._fill_far()
    assert not g.branches


def test_tapering_example_gives_branches_that_never_thicken():
    # the copied taper ratios multiply step after step; before issue 23 some branches ended > 2 x
    # thicker than they started (lightning seed 4: 16 % against the example's 5 %)
    from branchnb.branching._image_examples import random_tree
    from branchnb.branching.growth import _radius_growth
    from branchnb.branching.measures import thick_end_share
    from branchnb.branching.synthesis import synthesize_structure

    ex = random_tree((192, 192), 4, n_children=5, grandchildren=2, r_root=3, r_child=2)
    assert _radius_growth(ex) == 1.0
    model = fit_model(ex)
    for seed in (0, 1):
        s = synthesize_structure(model, rng=seed).structure
        for b in s.branches:
            if len(b.thickness) > 2:
                assert b.thickness.max() <= b.thickness[:2].max() + 1e-9
        assert thick_end_share(s) == 0.0
