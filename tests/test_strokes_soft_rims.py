"""Crotches of carried parts on RGBA objects whose soft rim carries no colour (issue 25, strokes30).

A matted cut-out often stores black under the anti-aliased alpha of its rim:
closing a joint's pocket made those half-transparent pixels opaque with their
black colour -- dark 1-2 px specks in every crotch where a carried tine met its
bent beam (an antler: 3 of 3). Main: 1 / 4 speck px at the crotches (antler,
seeds 0 / 1, 300 px); now 0.
"""
import os
import sys

import numpy as np
import pytest

from branchnb.strokes import edit_structure
from branchnb.strokes.outline import fill_joints
from branchnb.strokes.parts import carry_stroke

sys.path.insert(0, os.path.dirname(__file__))
from strokes_speck_table import antler, junction_specks  # noqa: E402


def _pocketed_bar():
    # a bar and a branch meeting with a pocket; the rim round the pocket half transparent
    # and black (no colour of its own)
    layer = np.zeros((30, 30, 4), np.float32)
    layer[:, 10:20] = (0.8, 0.7, 0.5, 1.0)
    layer[14:20, 20:30] = (0.8, 0.7, 0.5, 1.0)
    layer[14:16, 19] = (0.0, 0.0, 0.0, 0.0)
    layer[13:17, 18] = (0.0, 0.0, 0.0, 0.6)
    layer[16:18, 19] = (0.0, 0.0, 0.0, 0.6)
    return layer


def test_fill_joints_gives_raised_rim_the_solid_colour():
    layer = _pocketed_bar()
    out = fill_joints(layer, [(19, 16)], [8.0])
    raised = (out[..., 3] > layer[..., 3] + 0.2) & (layer[..., 3] > 0.05)
    assert raised.any()
    # coverage it had (0.6, black) + the rest from the solid fill: no darker than 0.4 x fill
    assert out[raised, :3].min() >= 0.4 * 0.5 - 1e-6
    assert np.all(out[raised, 0] >= 0.4 * 0.8 - 1e-6)


def test_fill_joints_keeps_solid_colours():
    layer = _pocketed_bar()
    out = fill_joints(layer, [(19, 16)], [8.0])
    solid = layer[..., 3] >= 1.0
    assert np.array_equal(out[solid], layer[solid])


@pytest.mark.parametrize("seed", [0, 1])
def test_bent_antler_crotches_have_no_dark_specks(seed):
    img, beam, tines, bent = antler(300, seed)
    res = edit_structure(img, [beam] + tines, [bent] + [carry_stroke(t, beam, bent) for t in tines])
    assert len(res.junctions) >= 3
    assert junction_specks(res) == 0

