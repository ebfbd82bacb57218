"""Issue 23, connected output on the flat drawing path: each synthesized tree of a binary mask or a
drawn map is one 8-connected line, its children joined to their parents, no specks.

A guard (branching73): on main a2dc929 these already hold (29 masks and maps, 256-1024 px, measured
with :mod:`branchnb.branching._flat_joins_check`); the "floating pieces" of a downscaled neuron-mask
sheet were one-pixel children lost in the shrinking. These tests keep the joins when the flat path
changes (hub pastes, outlet extension and tail trimming, one-pixel rasters of thin lines).
"""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching._flat_joins_check import case, flat_joins
from branchnb.branching.drawing import DrawingStyle, draw_in_style
from branchnb.core.structure import Branch, Structure


def _random_tree(rng, size=160):
    """A parent with 2-4 children at random vertices, some thinner than a pixel, some grandchildren."""
    t = np.linspace(0, 1, 25)
    a0 = rng.uniform(0, 2 * np.pi)
    p = np.c_[size / 2 + 60 * t * np.cos(a0) + rng.normal(0, 1, 25).cumsum() * 0.3,
              size / 2 + 60 * t * np.sin(a0) + rng.normal(0, 1, 25).cumsum() * 0.3]
    s = Structure([Branch(p, np.linspace(rng.uniform(0.4, 3.0), 0.3, 25))])
    for _ in range(int(rng.integers(2, 5))):
        par = int(rng.integers(0, len(s.branches)))
        q = s.branches[par].points
        v = int(rng.integers(1, len(q) - 1))
        a = rng.uniform(0, 2 * np.pi)
        n = int(rng.integers(4, 12))
        c = q[v] + np.c_[np.arange(n) * 3.0 * np.cos(a), np.arange(n) * 3.0 * np.sin(a)]
        if np.all((c > 1) & (c < size - 2)):
            s.add_branch(c, np.full(n, rng.uniform(0.2, 1.2)), parent=par, parent_vertex=v)
    return s


@pytest.mark.parametrize("seed", range(6))
def test_two_tone_drawing_joins_thin_children(seed):
    rng = np.random.default_rng(seed)
    s = _random_tree(rng)
    style = DrawingStyle(np.array([[0.0, 0.0, 0.0]]), 0, np.array([1.0, 1.0, 1.0]), 1.0, None, 0.0, two_tone=True)
    img = draw_in_style(style, s, np.zeros((160, 160), int))
    d = flat_joins(img[..., 0] > 0.5, s)
    assert d["pieces"] == 1.0 and d["detached"] == 0 and d["off"] == 0
    assert d["gaps"] == 0 and d["specks"] == 0


def test_flat_joins_counts_a_detached_child():
    s = Structure([Branch([(2, 10), (16, 10), (30, 10)], 1.0), Branch([(16, 10), (16, 30)], 1.0, 0, 1)])
    ink = np.zeros((40, 40), bool)
    ink[9:12, 2:31] = True
    ink[16:31, 15:18] = True
    d = flat_joins(ink, s)
    assert (d["pieces"], d["detached"], d["off"], d["gaps"]) == (2.0, 1, 0, 1)


@pytest.mark.parametrize("kind,size,seed", [("neuron", 384, 1), ("Rcrack_bright-bow", 256, 0), ("delta", 256, 0),
                                            ("vessel_bow", 300, 1), ("rmap", 400, 1)])
def test_flat_outputs_are_one_line_per_tree(kind, size, seed):
    d = case(kind, size, seed)
    assert d["kids"] > 0
    assert d["max_pieces"] == 1, d
    assert d["detached"] == 0 and d["off"] == 0, d
    assert d["gaps"] == 0 and d["specks"] == 0, d
