"""Issue 23 (branching85): a delta whose trunk meanders keeps its meanders.

The trunk held to its way to the sea (``drain.TRUNK_HOLD``, ``drain.STRAIGHT_HOLD``) came out ruler-straight
on meandering deltas (``_delta_fan_check``'s ``mean0``: sinuosity 1.002 against the example's 1.16). Where
the example's trunk meanders (``drain._meander_of``) it is now held to a sine about that way, of the
example's number of lobes and sinuosity (``drain.MEANDER_SIN``).
"""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._delta_fan_check import bearing_error, mask_of, trunk_bearing, trunk_sinuosity, turned
from branchnb.branching.drain import _meander_of
from branchnb.core.structure import Branch, Structure


def _root(xs, ys) -> Structure:
    return Structure([Branch(np.c_[xs, ys], 3.0)], image_shape=(200, 200))


def test_meander_is_told_from_a_bend_and_a_straight_trunk():
    dom = np.ones((200, 200), bool)
    dom[180:] = False                                   # the sea along the bottom
    y = np.linspace(0.0, 100.0, 101)
    wave = _meander_of(_root(100 + 12 * np.sin(2 * np.pi * 1.5 * y / 100), y), dom)
    assert wave is not None
    slope, lobes, sign = wave
    assert lobes == 3 and sign == -1.0      # first toward +x, the chord's normal (-dy, dx) being -x
    # the largest slope of the sine: 2 pi 12 / (100 / 1.5) = 1.13; read from the sinuosity (1 + s^2 / 4)
    assert 0.8 <= slope <= 1.4, slope
    assert _meander_of(_root(100 + 30 * np.sin(np.pi * y / 100), y), dom) is None      # one bend
    assert _meander_of(_root(np.full_like(y, 100.0), y), dom) is None                 # straight


@pytest.mark.parametrize("seed", [0, 1])
def test_meandering_trunk_keeps_its_sinuosity_and_bearing(seed):
    # main: sinuosity 1.003 / 1.007 (example 1.134), bearing error 6.8 / 4.7 deg; branching85: 1.09 / 1.07,
    # 6.2 / 3.1 deg
    img = np.dstack([turned(mask_of("mean0", 320, 2), "left")] * 3)
    ex = extract_structure(img)
    dom = example_domain(img, ex)
    m = fit_model(ex, domain=dom)
    s = synthesize_structure(m, rng=seed).structure
    assert trunk_sinuosity(s, dom) >= 1.05
    assert bearing_error(trunk_bearing(s, dom), trunk_bearing(m.example, dom)) <= 10.0
