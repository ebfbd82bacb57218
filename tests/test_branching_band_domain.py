"""Issue 23, ornaments and border bands (branching53): a line mask whose strands occupy a band of the frame
(a vine along two borders, a ring) grows its output in that band, as strands that stay in it.

Known answers: procedural ornaments (:mod:`branchnb.branching._band_examples`) with their strand spacing.
"""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._band_check import figures
from branchnb.branching._band_examples import band_example
from branchnb.branching.domains import _ground
from branchnb.branching.empty_ground import _line_domain
from branchnb.core.structure import Branch, Structure


def test_line_domain_is_the_band_of_two_strands_and_all_of_a_grid():
    m = np.zeros((200, 240), bool)
    m[30, :] = m[50, :] = True
    d = _line_domain(m)
    assert d[40].all() and d[60].all()                  # between and just beyond the strands
    assert not d[100:].any()                            # the empty part below
    grid = np.zeros((200, 240), bool)
    grid[::25, :] = grid[:, ::25] = True                # cells smaller than the spacing: the whole frame
    assert _line_domain(grid).all()


def test_the_ground_round_a_band_is_no_coast():
    ex = Structure([Branch(np.c_[np.linspace(2, 197, 60), np.full(60, 40.0)], 1.0),
                    Branch(np.c_[np.linspace(2, 197, 60), np.full(60, 60.0)], 1.0)], image_shape=(200, 200))
    band = np.zeros((200, 200), bool)
    band[28:73] = True                                  # 12 px round the strands: ground
    assert _ground(ex, band) is not None and _ground(ex, band)[150].all()
    rivers = Structure([Branch(np.c_[np.linspace(2, 148, 50), np.full(50, y)], 1.0) for y in (40.0, 120.0)],
                       image_shape=(200, 200))
    coast = np.zeros((200, 200), bool)
    coast[:, :150] = True                               # the rivers run out to it: a coast
    assert _ground(rivers, coast) is None


@pytest.mark.parametrize("kind,size,seed", [("L", 256, 0), ("ring", 256, 1)])
def test_border_vine_grows_in_its_band_as_strands(kind, size, seed):
    img, spacing = band_example(kind, size, seed, leaves=kind == "ring")
    ex = extract_structure(img)
    model = fit_model(ex, domain=example_domain(img, ex))
    for s in (0, 1):
        out = synthesize_structure(model, rng=s).structure
        f = figures(img, spacing, ex, out)
        # main: 0.32 (L) and 0.49 (ring) of the length beyond the strand spacing from every example line
        assert f["out"] <= 0.05, f
        assert 0.7 <= f["len"] <= 1.3, f
