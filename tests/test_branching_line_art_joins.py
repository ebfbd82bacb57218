"""Issue 23, line art: extraction gives connected trees on drawings broken at junctions and at the
over-and-under crossings of an interlace (.stroke_joins), on procedural examples with a known tree."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import extract_structure
from branchnb.branching._line_art_trees import branching_drawing, interlace_vine, measure_line_art
from branchnb.branching.stroke_joins import find_stroke_joins


@pytest.mark.parametrize("size, seed, gap", [(200, 1, 3.0), (500, 1, 3.0), (400, 2, 2.0)])
def test_a_drawing_with_gaps_at_its_junctions_is_one_tree(size, seed, gap):
    # before: the side branches stopping 2-3 px short of their parent came out as trees of their
    # own (200 px: 2 trees, 500 px: 5, 1000 px: 6; junctions 0.0)
    img, truth, junctions = branching_drawing(size, seed, gap=gap)
    m = measure_line_art(truth, junctions, extract_structure(img))
    assert m["trees"] == 1
    assert m["junctions"] >= 0.6
    assert m["recall"] >= 0.95


@pytest.mark.parametrize("size", [300, 500])
def test_an_interlace_vine_is_one_tree_with_its_shoots(size):
    # before: 3 trees (the stem cut at each crossing it passes under)
    img, truth, junctions = interlace_vine(size, 0)
    m = measure_line_art(truth, junctions, extract_structure(img))
    assert m["trees"] == 1
    assert m["junctions"] >= 0.75
    assert m["recall"] >= 0.95


def _stem_and_shoot(gap):
    ink = np.zeros((40, 80), bool)
    ink[18:23, 5:75] = True
    ink[23 + gap:38, 38:43] = True
    sk = np.zeros_like(ink)
    sk[20, 5:75] = True
    sk[25 + gap:36, 40] = True
    return sk, np.where(ink, 2.5, 0.0), ink


def test_find_stroke_joins_t_junction_tip_to_tip_and_crossing():
    sk, rad, ink = _stem_and_shoot(3)
    (a, b, through), = find_stroke_joins(sk, rad, ink)
    assert a[1] == b[1] == 40 and b[0] == 20 and not through
    # a gap far wider than the line: left alone
    assert find_stroke_joins(*_stem_and_shoot(14)) == []
    # a strand cut on both sides of one passing over it: joined under it
    ink = np.zeros((60, 120), bool)
    ink[28:33, 5:50] = True
    ink[28:33, 66:115] = True
    ink[5:55, 55:61] = True
    sk = np.zeros_like(ink)
    sk[30, 5:50] = True
    sk[30, 66:115] = True
    sk[5:55, 58] = True
    joins = find_stroke_joins(sk, np.where(ink, 2.5, 0.0), ink)
    assert len(joins) == 1 and joins[0][2]
    assert {joins[0][0][0], joins[0][1][0]} == {30}
    # ends that do not face each other (one turned away): no join through the crossing
    sk2 = sk.copy()
    sk2[30, 66:115] = False
    ink2 = ink.copy()
    ink2[28:33, 66:115] = False
    ink2[30:55, 66:71] = True
    sk2[32:55, 68] = True
    assert not any(t for _a, _b, t in find_stroke_joins(sk2, np.where(ink2, 2.5, 0.0), ink2))


@pytest.mark.parametrize("bad, exc", [({"max_gap": -1.0}, ValueError), ({"max_gap": np.nan}, ValueError),
                                      ({"min_cos": 2.0}, ValueError), ({"scale": 0.0}, ValueError),
                                      ({"max_gap": "3"}, TypeError)])
def test_find_stroke_joins_rejects_bad_arguments(bad, exc):
    sk, rad, ink = _stem_and_shoot(3)
    with pytest.raises(exc, match=next(iter(bad))):
        find_stroke_joins(sk, rad, ink, **bad)


def test_find_stroke_joins_needs_maps_of_one_shape():
    sk, rad, ink = _stem_and_shoot(3)
    with pytest.raises(ValueError, match="mask"):
        find_stroke_joins(sk, rad, ink[:, :10])
