"""Binary masks drawn in style: children that taper, no blunt ends, no stubs, one piece per tree (issue 23,
branching80).

A mask's output drew every branch at the radii the synthesized structure carries: copied piece by piece,
a child kept one radius to its end and stopped there at full width with a round cap (a delta fan's
distributary ending 3.6 px wide where the example's end 1.6 px; a crack mask's 3-px children ending
1.4 px wide, the example's 0.6 px), and a dense 128 px crack comb (under half its pixels in flat cells)
was copied fragment by fragment into 3-6 pieces. Figures: :mod:`branchnb.branching._mask_taper_check`.
"""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching._mask_taper_check import case, figures, taper_mask
from branchnb.branching.drawn_taper import burrs, example_taper, tapered_radii
from branchnb.core.structure import Branch, Structure


def _tree() -> Structure:
    """A 2-px trunk along y = 50; a blunt 3-px child up to a free end, a 4-px stub, a child to the frame."""
    s = Structure([Branch(np.c_[np.linspace(10, 110, 51), np.full(51, 50.0)], 2.0)], image_shape=(100, 120))
    s.add_branch(np.c_[np.full(21, 40.0), np.linspace(50, 10, 21)], np.full(21, 3.0), parent=0, parent_vertex=15)
    s.add_branch([(70.0, 50.0), (70.0, 54.0)], [2.0, 2.0], parent=0, parent_vertex=30)
    s.add_branch(np.c_[np.full(26, 90.0), np.linspace(50, 99, 26)], np.full(26, 1.0), parent=0, parent_vertex=40)
    return s


def test_drawn_radii_taper_to_the_tip_and_thin_stubs():
    s = _tree()
    r = tapered_radii(s, (100, 120), 0.5, 0.6)
    blunt = r[1]
    # the blunt child: under the example's ramp (3 -> 1.5 px), down to the tip radius at its free end
    assert blunt[0] == pytest.approx(3.0) and blunt[10] <= 2.26 and blunt[-1] <= 0.6 + 1e-9
    assert np.all(np.diff(blunt) <= 1e-9)
    # the 4-px stub: no thicker than a third of what shows beyond its parent's drawn body (4 - 1.4 px)
    assert r[0][30] == pytest.approx(1.4) and np.max(r[2]) <= (4.0 - 1.4) / 3.0 + 1e-9
    # the child running out of the frame keeps the ramp only (no tip there)
    assert r[3][-1] == pytest.approx(0.5, abs=0.01) and r[3][-1] > 0.6 * 0.5
    # never above the structure's own radii, and the trunk's end (free) ends at the tip radius
    assert all(np.all(a <= b.thickness + 1e-9) for a, b in zip(r, s.branches))
    assert r[0][-1] <= 0.6 + 1e-9
    # the stub shows 2.1 px beyond its parent's drawn edge: a burr, left out; the others are drawn
    assert burrs(s, r).tolist() == [False, False, True, False]


def test_example_taper_reads_the_mask():
    from branchnb.branching import extract_structure

    img = taper_mask("vessel", 256)
    ex = extract_structure(img)
    taper, tip = example_taper(ex, img.shape[:2])
    # drawn: every branch ends at 0.7 x its start radius, round tips of 0.9-1.3 px
    assert 0.45 <= taper <= 0.85 and 0.6 <= tip <= 1.6, (taper, tip)
    f = figures(img, ex)
    assert f["pieces"] == 1 and f["stubs"] == 0 and f["thick_end"] == 0.0


@pytest.mark.parametrize("kind, size, seed", [("dfan", 256, 1), ("tcrack", 256, 1), ("comb", 128, 1),
                                              ("vessel", 512, 0)])
def test_mask_outputs_taper_like_the_example(kind, size, seed):
    fx, fo = case(kind, size, seed)
    # before: tips 3.58 px (example 1.56), 1.43 (0.57); the comb in 6 pieces; the vessel with a stub
    assert fo["tip"] <= fx["tip"] + 1.0, (fx, fo)
    assert fo["thick_end"] <= fx["thick_end"] + 0.05, (fx, fo)
    assert fo["pieces"] == 1, fo
    assert fo["stubs"] == 0, fo
