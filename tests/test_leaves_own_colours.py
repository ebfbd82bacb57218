"""Spots of one fixed colour on blades of differing shade are induced on every leaf (issue 22).

Matching each blade's colour statistics onto the training leaf's moves a layer's colour with its blade; rust
spots keep theirs. Before ``analysis_own._own_colours`` a darker leaf with more spots got none of them
(IoU 0.00 where its own colours give 0.90).
"""

import warnings

import pytest
from leaves_marks import marked_leaf

from branchnb.core.metrics import iou
from branchnb.leaves import Layer, LayerSet, analyze, simulate_scribbles
from branchnb.leaves._measure_unseen import _on_canvas

SIZE = 300


def _birch(seed, blade_colour=None):
    """An ovate, doubly toothed, tilted leaf: pinnate veins lighter than the blade, 4-8 rust spots of one
    fixed colour anywhere on the blade; the blade's green varies by +-10 % between leaves."""
    return marked_leaf(seed, SIZE, "spots", (4, 9), margin=0.0, blade_colour=blade_colour)


def _analyse(leaves):
    layers = LayerSet([Layer("veins", "#d62728", 0, simulate_scribbles(leaves[0][2], 12, length=30, rng=0)),
                       Layer("spots", "#1f77b4", 1, simulate_scribbles(leaves[0][1], 8, length=10, rng=0))])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return analyze([im for im, _, _ in leaves], 0, layers, mirror=False)


def _spot_iou(a, leaves, e):
    truth = _on_canvas(leaves[e][1], a.offsets[e], a.blades[e].shape, a.mirrored[e])
    return iou(a.layer("spots").masks[e], truth)


def test_fixed_colour_spots_found_on_a_darker_leaf():
    leaves = [_birch(seed) for seed in range(5)]
    a = _analyse(leaves)
    scores = [_spot_iou(a, leaves, e) for e in range(5)]
    assert min(scores) >= 0.7, scores


@pytest.mark.parametrize("blade_colour", [(0.48, 0.26, 0.08), (0.55, 0.33, 0.12)])
def test_own_colours_do_not_take_a_blade_of_the_spots_colour(blade_colour):
    """A leaf whose whole blade has the spots' colour must not come out as one big spot."""
    leaves = [_birch(seed, blade_colour=blade_colour if seed == 3 else None) for seed in range(5)]
    a = _analyse(leaves)
    share = float(a.layer("spots").masks[3].sum()) / float(a.blades[3].sum())
    training_share = float(a.layer("spots").masks[0].sum()) / float(a.blades[0].sum())
    assert share <= 3.0 * training_share + 0.01, (share, training_share)
