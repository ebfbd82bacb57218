"""Issue 23 (branching79): a straight delta's trunk runs from where it enters to the example's mouths, and
its fan is not lopsided. Balanced binary deltas (:func:`delta_tree_mask`: a trunk splitting evenly 2-3 times,
as many mouths on either side) and ``fan0`` (a straight trunk with a channel on each side)."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._delta_examples import FAN_KINDS, delta_fan_mask, delta_tree_mask
from branchnb.branching._delta_fan_check import bearing_error, mouth_share, trunk_bearing, turned
from branchnb.branching.delta_fan import _even_fork, _trunk_turns
from branchnb.branching.domains import _Drain
from branchnb.core.structure import Branch, Structure


def test_an_even_fork_is_no_turn_of_the_trunk():
    dom = np.zeros((100, 100), bool)
    dom[:80] = True
    # the root follows the left arm of an even Y: no turn
    even = Structure([Branch([(50, 0), (50, 40), (25, 79)], 3.0), Branch([(50, 40), (75, 79)], 3.0, 0, 1)])
    assert not _trunk_turns(even, dom)
    # a thin arm on the other side: the trunk turns into the wide one
    bent = Structure([Branch([(50, 0), (50, 40), (25, 79)], 4.0), Branch([(50, 40), (75, 79)], 1.0, 0, 1)])
    assert _trunk_turns(bent, dom)
    assert _even_fork(np.radians([30.0, -35.0]), np.array([3.0, 2.5]))
    assert not _even_fork(np.radians([30.0, 70.0]), np.array([3.0, 2.5]))        # both on one side
    assert not _even_fork(np.radians([10.0, -70.0]), np.array([3.0, 2.5]))       # bisector 30 deg off


def test_a_straight_trunk_target_moves_with_its_start():
    dom = np.zeros((200, 200), bool)
    dom[:170] = True
    ex = Structure([Branch([(100, 0), (100, 80)], 3.0), Branch([(100, 80), (60, 169)], 2.0, 0, 1),
                    Branch([(100, 80), (140, 169)], 2.0, 0, 1)])
    d = _Drain(dom)
    d.set_axis(ex, dom)
    assert d.axis is None and d.trunk_axis is not None            # along the descent: the trunk is held only
    np.testing.assert_allclose(d.trunk_target, [100.0, 169.0])
    d.set_trunk_start((112.0, 2.0))
    np.testing.assert_allclose(d.trunk_target, [112.0, 171.0])
    wd = d.way_down((112.0, 10.0))
    assert abs(wd[0]) < 1e-6 and wd[1] > 0.99                     # straight on, the example's bearing


def _fit(mask, root=None):
    img = np.dstack([mask] * 3)
    ex = extract_structure(img) if root is None else extract_structure(img, root=root)
    dom = example_domain(img, ex)
    return dom, fit_model(ex, domain=dom)


@pytest.fixture(scope="module")
def tree_delta():
    # an even binary delta, 140 degree fan, 3 orders (8 mouths), sea at the top (rooted at its entry: the
    # automatic root takes a mouth of some such masks, a separate matter)
    m, entry, _mouths, _head = delta_tree_mask((256, 256), 16, 140.0, 3, 2.5)
    x, y = float(entry[0]), max(float(entry[1]), 0.0)
    return _fit(turned(m, "top"), root=(x, 255.0 - y))


def test_even_binary_delta_keeps_its_bearing_and_both_sides(tree_delta):
    """before (main): bearing error 21.3/17.2/23.7 degrees, mouths on the smaller side 0.25/0.33/0.00;
    after 1.0/3.5/1.4, 0.40/0.25/0.40."""
    dom, model = tree_delta
    ex_bear = trunk_bearing(model.example, dom)
    assert mouth_share(model.example, dom) == 0.5
    errs, shares = [], []
    for seed in range(3):
        s = synthesize_structure(model, rng=seed).structure
        errs.append(bearing_error(trunk_bearing(s, dom), ex_bear))
        shares.append(mouth_share(s, dom))
    assert np.mean(errs) < 8.0, errs
    assert np.mean(shares) >= 0.3 and min(shares) > 0.2, shares


@pytest.fixture(scope="module")
def fan0_512():
    t, c, f, n = FAN_KINDS["fan0"]
    return _fit(turned(delta_fan_mask((512, 512), 515, t, c, f, n)[0], "left"))


def test_fan0_trunk_heads_for_the_mouths(fan0_512):
    """before (main): bearing error 8.1/6.8/20.7 degrees (the trunk drifted toward a corner), mouths on the
    smaller side 0.50/0.25/0.00; after 5.0/3.1/11.6, 0.40/0.40/0.20."""
    dom, model = fan0_512
    ex_bear = trunk_bearing(model.example, dom)
    errs, shares = [], []
    for seed in range(3):
        s = synthesize_structure(model, rng=seed).structure
        errs.append(bearing_error(trunk_bearing(s, dom), ex_bear))
        shares.append(mouth_share(s, dom))
    assert np.mean(errs) < 9.0, errs
    assert min(shares) > 0.1, shares
