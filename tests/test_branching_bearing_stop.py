"""Issue 23 (branching87, branching94): a root entering from the frame keeps its bearing.

``frame_band.bearing_keep`` / ``entry_turn_limit`` end a root whose chord turns past the example's own
largest turn + ``BEARING_MARGIN`` off its entry side's inward normal; a tree whose root the stop cut short
drops its children whose first Markov step was refused (``_Filling._drop_heads``; covered on the crack of
tests/test_branching_unborn.py::test_every_leaf_child_grew, which left 3 bare heads without it).
"""

from __future__ import annotations

import numpy as np

from branchnb.branching._frame_hug_check import case
from branchnb.branching.frame_band import BEARING_MARGIN, bearing_keep, entry_side, entry_turn_limit
from branchnb.core.structure import Branch, Structure


def _root_turning(turn_deg: float, shape=(400, 400)) -> np.ndarray:
    """A root entering from the top at x = 200, 150 px straight down, then 150 px turned by ``turn_deg``."""
    a = np.radians(90.0 - turn_deg)
    t = np.arange(0.0, 151.0, 3.0)
    down = np.stack([np.full_like(t, 200.0), t], 1)
    bent = down[-1] + np.stack([np.cos(a) * t[1:], np.sin(a) * t[1:]], 1)
    return np.vstack([down, bent])


def test_the_turn_limit_is_the_examples_largest_turn_plus_the_margin():
    for turn in (10.0, 35.0):
        ex = Structure([Branch(_root_turning(turn), 2.0)], image_shape=(400, 400))
        assert abs(entry_turn_limit(ex) - (turn + BEARING_MARGIN)) < 1.0
    inside = Structure([Branch(_root_turning(30.0) + [0.0, 50.0], 2.0)], image_shape=(400, 400))
    assert entry_turn_limit(inside) == np.inf          # no root enters from the frame: no stop
    assert entry_side((200.0, 2.0), 2.0, (400, 400)) == 1
    assert entry_side((200.0, 50.0), 2.0, (400, 400)) == -1


def test_a_root_is_cut_where_its_chord_turns_past_the_limit():
    p = _root_turning(90.0)                            # runs along, 150 px under the top after its turn
    head, new = p[:40], p[40:]
    ok = bearing_keep(head, new, 1, 55.0, (400, 400))
    cut = int(np.argmin(ok))
    assert not ok.all() and ok[:cut].all() and not ok[cut:].any()
    # the chord over the window (25 px) passes 55 deg 15 px after the turn at (200, 150) (18 on the 3 px
    # vertices): the root keeps its first steps along the turn, not the run along the frame
    x, y = new[cut]
    assert 150.0 <= y <= 151.0 and 210.0 < x < 225.0
    straight = _root_turning(15.0)
    assert bearing_keep(straight[:40], straight[40:], 1, 55.0, (400, 400)).all()


def test_a_river_trunk_from_the_bottom_keeps_its_bearing():
    # river 512 px seed 2 of _frame_hug_check: the trunk ran up to 45 px under the top, turned 90 deg and
    # ran 200 px along it (net bearing 29.2 deg off the example's roots' before the stop, 0.5 after)
    r = case("river", 512, 2)
    assert r["dev"] < 10.0, r
    assert r["fq"] <= r["lim"], r
