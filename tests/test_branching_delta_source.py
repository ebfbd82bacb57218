"""Issue 23 (branching83): binary deltas are rooted where their trunk enters, not at a mouth.

On main 4 of the 8 balanced deltas of ``_delta_tree_check.CASES`` were rooted at a mouth with the defaults
(their ends too alike in width for ``skeleton_tree._delta_source_key``), and 5 of 16 uneven river deltas
(``delta_river_mask``, every side, with and without a sea) with the defaults, 13 of 16 with
``root="nearest_region"``. The root is now the end the piece's forks fan out from
(``delta_source.fan_source``).
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from branchnb.branching import extract_structure
from branchnb.branching._delta_examples import delta_river_mask, delta_tree_mask
from branchnb.branching._delta_fan_check import turned
from branchnb.branching._delta_tree_check import CASES
from branchnb.branching.skeleton_tree import skeleton_to_structure


def _main_root(s):
    """The first point of the root whose tree holds the most points."""
    tot = {}
    for i, b in enumerate(s.branches):
        t = i
        while s.branches[t].parent is not None:
            t = int(s.branches[t].parent)
        tot[t] = tot.get(t, 0) + len(b.points)
    return np.asarray(s.branches[max(tot, key=tot.get)].points[0], float)


@pytest.mark.parametrize("ci", [0, 5])
def test_balanced_delta_is_rooted_at_its_entry(ci):
    # main: case 0 rooted 106 radii from the entry (a mouth) with the defaults; case 5 110 radii with
    # both the defaults and nearest_region
    fan, orders, rad, size, side = CASES[ci]
    m0, entry, _mouths, _head = delta_tree_mask((size, size), 10 + ci, fan, orders, rad)
    x, y = float(np.clip(entry[0], 0, size - 1)), float(np.clip(entry[1], 0, size - 1))
    e = {"bottom": (x, y), "top": (x, size - 1 - y), "left": (size - 1 - y, x), "right": (y, x)}[side]
    img = np.dstack([turned(m0, side)] * 3)
    for root in ("auto", "nearest_region"):
        d = np.hypot(*(_main_root(extract_structure(img, root=root)) - e))
        assert d <= 2.0 * rad, (root, d / rad)


@pytest.mark.parametrize("side,sea,seed,rad,splits", [("top", True, 24, 2.0, 1), ("bottom", True, 25, 3.0, 2),
                                                      ("left", True, 26, 2.0, 3), ("right", True, 27, 3.0, 1),
                                                      ("left", False, 22, 2.0, 3), ("bottom", False, 21, 3.0, 2)])
def test_river_delta_is_rooted_at_its_entry(side, sea, seed, rad, splits):
    # main (defaults): the four with a sea rooted 72-119 radii away, at mouths; nearest_region: the last two
    # 87-133 radii away (the frame is the sea)
    m, e, _mouths = delta_river_mask((256, 256), seed, side, rad, sea, splits)
    img = np.dstack([m] * 3)
    for root in ("auto", "nearest_region"):
        d = np.hypot(*(_main_root(extract_structure(img, root=root)) - e))
        assert d <= 2.0 * rad, (root, d / rad)


def _y_skeleton(converge: bool):
    """A one-width stem forking twice into three channels; ``converge``: drawn upside down (the channels'
    sources at the top frame, joining into the stem that reaches the sea)."""
    sk = np.zeros((200, 200), np.uint8)
    cv2.line(sk, (100, 0), (100, 80), 1, 1)
    cv2.line(sk, (100, 80), (40, 169), 1, 1)
    cv2.line(sk, (100, 80), (130, 120), 1, 1)
    cv2.line(sk, (130, 120), (105, 169), 1, 1)
    cv2.line(sk, (130, 120), (170, 169), 1, 1)
    sea = np.zeros((200, 200), bool)
    sea[172:] = True
    if converge:
        sk, sea = sk[::-1].copy(), sea[::-1].copy()
        sea[:] = False
        sea[197:] = True      # the stem's mouth at the bottom, the channels' sources at the top frame
        sk[:30] = 0
    return sk.astype(bool), sea


def test_even_y_fans_from_its_stem_but_a_river_drains_at_its_mouth():
    sk, sea = _y_skeleton(False)
    for root in ("auto", "nearest_region"):
        s = skeleton_to_structure(sk, np.full(sk.shape, 1.0), root=root, region=sea, min_component_length=20)
        assert np.hypot(*(_main_root(s) - (100, 0))) < 4.0, root
    sk, sea = _y_skeleton(True)
    for root in ("auto", "nearest_region"):
        s = skeleton_to_structure(sk, np.full(sk.shape, 1.0), root=root, region=sea, min_component_length=20)
        assert np.hypot(*(_main_root(s) - (100, 199))) < 4.0, root


@pytest.mark.parametrize("ci, fan, orders, rad, size, side, n_trib",
                         [(1, 120, 2, 3.0, 384, "left", 3), (6, 60, 2, 2.5, 256, "right", 2),
                          (0, 90, 2, 4.0, 256, "bottom", 2)])
def test_delta_with_tributaries_is_rooted_at_its_trunks_entry(ci, fan, orders, rad, size, side, n_trib):
    # branching85: a trunk with tributaries joining upstream of the fan; on main the first two were rooted
    # at a tributary's source 70 and 49 radii from the trunk's entry (each confluence voted against the
    # trunk's source), 3 of 8 such deltas in all (the third at 768 px)
    m0, entry, _mouths, _head = delta_tree_mask((size, size), 40 + ci, fan, orders, rad, tributaries=n_trib)
    x, y = float(np.clip(entry[0], 0, size - 1)), float(np.clip(entry[1], 0, size - 1))
    e = {"bottom": (x, y), "top": (x, size - 1 - y), "left": (size - 1 - y, x), "right": (y, x)}[side]
    d = np.hypot(*(_main_root(extract_structure(np.dstack([turned(m0, side)] * 3))) - e))
    assert d <= 2.0 * rad, d / rad
