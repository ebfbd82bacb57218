"""A bolt's trunk entering from the frame keeps its bearing (issue 23, branching101): the turn the example's
roots allow (``frame_band.entry_turn_limit``) is capped at ``ENTRY_TURN_CAP``: a chord turning further runs
along the entry side or back towards it."""
import numpy as np

from branchnb.branching._frame_hug_check import case
from branchnb.branching.frame_band import BEARING_MARGIN, ENTRY_CAP_ROOTS, ENTRY_TURN_CAP, entry_turn_limit
from branchnb.core.structure import Branch, Structure


def test_turn_limit_is_capped():
    # a root from the top, 150 px down, then 150 px turned 100 deg (running back up a little)
    t = np.arange(0.0, 151.0, 3.0)
    a = np.radians(90.0 - 100.0)
    down = np.stack([np.full_like(t, 200.0), t], 1)
    p = np.vstack([down, down[-1] + np.stack([np.cos(a) * t[1:], np.sin(a) * t[1:]], 1)])
    ex = Structure([Branch(p, 2.0)], image_shape=(400, 400))
    assert entry_turn_limit(ex) == ENTRY_TURN_CAP              # main: 120 (100 + the margin)
    gentle = Structure([Branch(down, 2.0)], image_shape=(400, 400))
    assert entry_turn_limit(gentle) < BEARING_MARGIN + 1.0    # straight: the margin alone


def test_roots_that_all_run_sideways_keep_their_turn():
    # several entering roots turning 100 deg each (cracks running along their side, like cracked mud's
    # three of five): the turn is the example's own, not one root's jag, and the cap would starve corners
    t = np.arange(0.0, 151.0, 3.0)
    a = np.radians(90.0 - 100.0)
    roots = []
    for x in (60.0, 200.0, 340.0)[:ENTRY_CAP_ROOTS + 1]:
        down = np.stack([np.full_like(t, x), t], 1)
        roots.append(Branch(np.vstack([down, down[-1] + np.stack([np.cos(a) * t[1:], np.sin(a) * t[1:]], 1)]), 2.0))
    many = Structure(roots, image_shape=(400, 400))
    assert entry_turn_limit(many) > ENTRY_TURN_CAP + 30.0   # ~100 + the margin
    one_jag = Structure(roots[:1] + [Branch(np.stack([np.full_like(t, 300.0), t], 1), 2.0)], image_shape=(400, 400))
    assert entry_turn_limit(one_jag) == ENTRY_TURN_CAP


def test_frame_hug_bolt_keeps_its_bearing():
    # _frame_hug_check bolt 256 px seed 1: the example's traced root turns 85.5 deg at a jag, so its
    # trunk was let run sideways along the bottom: 26.8 deg off the example's mean root bearing
    r = case("bolt", 256, 1)
    assert r["dev"] <= 15.0, r                              # branching101: 2.0
    assert r["fq"] <= r["lim"], r
