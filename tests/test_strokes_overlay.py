"""A part bent over another part keeps its own outline there; no see-through ticks in crotches (issue 25).

Figures (main -> this branch), ``tests/strokes_overlay_table.py`` (hands, tridents, starfish,
candelabra; 300/600 px; seeds 0, 1; outlined and plain): share of the moved part's outline
ring over the neighbour's flesh that is outline-coloured 0.00 -> 0.90-1.00 (16 outlined
cases); light px inside the silhouette (ticks) 0-26 -> 0 (32 cases); PSNR away from the
moved part unchanged or better.
"""
import os
import sys

import numpy as np

from branchnb.strokes import edit_structure
from branchnb.strokes.junctions import find_junctions
from branchnb.strokes.overlays import _solid_cracks
from branchnb.strokes.strokes import Stroke

sys.path.insert(0, os.path.dirname(__file__))
import strokes_overlay_table as T  # noqa: E402


def _run(kind, S, seed, outlined=True):
    img, src, tgt, truth = T.case(kind, S, seed, outlined)
    return T.measure(img, edit_structure(img, src, tgt, rng=0), truth)


def test_a_finger_bent_over_its_neighbour_keeps_its_outline():
    cover, ticks, _ = _run("hand", 300, 0)
    assert cover >= 0.8, f"outline over the neighbour finger {cover:.2f} (main: 0.00)"
    assert ticks == 0, f"{ticks} light px inside the hand (main: 16)"


def test_a_starfish_arm_bent_over_the_next_keeps_its_outline():
    cover, _, _ = _run("starfish", 300, 1)
    assert cover >= 0.8, f"outline over the next arm {cover:.2f} (main: 0.00)"


def test_no_light_ticks_at_the_crotches_of_a_plain_hand():
    _, ticks, _ = _run("hand", 300, 1, outlined=False)
    assert ticks == 0, f"{ticks} light px inside the hand (main: 12)"


def test_a_free_tip_moved_onto_another_stroke_is_no_junction():
    a = Stroke([(0, 0), (0, 100)])
    b = Stroke([(30, 100), (30, 20)])
    moved = Stroke([(30, 100), (15, 50), (1, 25)])
    assert find_junctions([a, b], 3, [a, b]) == []
    assert find_junctions([a, moved], 3, [a, b]) == []
    # a branch drawn from its tip to a parent it already lay on still joins
    c = Stroke([(40, 20), (1, 50)])
    assert [(j.child, j.end, j.parent) for j in find_junctions([a, c], 3, [a, c])] == [(1, 1, 0)]


def test_see_through_pixels_inside_the_object_are_made_opaque():
    layer = np.zeros((20, 20, 4), np.float32)
    layer[2:18, 2:18] = (0.8, 0.6, 0.5, 1.0)
    layer[8:12, 9] = (0.8, 0.6, 0.5, 0.3)  # a crack inside
    layer[2, 5:8, 3] = 0.5  # the anti-aliased rim
    src = np.zeros((20, 20), np.float32)
    src[2:18, 2:18] = 1.0
    out = _solid_cracks(layer, src)
    assert (out[8:12, 9, 3] == 1.0).all()
    assert (out[2, 5:8, 3] == 0.5).all()
    # an anti-aliased source: left as laid
    soft = src.copy()
    soft[2, 2:18] = 0.5
    assert np.allclose(_solid_cracks(layer, soft)[8:12, 9, 3], 0.3)
