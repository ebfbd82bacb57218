"""Exemplars that are mirror images of the training leaf are turned over before registration."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb import data
from branchnb.leaves import analyze, leaf_family, normalise_exemplars, warp_mask
from branchnb.leaves.orientation import mirrored_exemplars


def _oaks(size: int = 160):
    import cv2

    out = []
    for i in (1, 2):
        im = data.load(f"drawn_oak_leaf_{i}")
        s = size / max(im.shape[:2])
        out.append(cv2.resize(im, None, fx=s, fy=s, interpolation=cv2.INTER_AREA))
    return out


def test_two_drawn_oaks_facing_opposite_ways_register_after_turning_one_over():
    oaks = _oaks()
    grid = np.zeros(oaks[0].shape[:2], bool)
    ys, xs = np.nonzero(oaks[0][..., 3] > 0.9)
    grid[ys[::7], xs[::7]] = True                       # any layer: the test is on the registration
    ious = {}
    for mirror in (True, False):
        a = analyze(oaks, 0, {"dots": grid}, rng=0, mirror=mirror)
        back = warp_mask(a.registrations[1], a.blades[1], to_training=True)
        ious[mirror] = (back & a.blades[0]).sum() / (back | a.blades[0]).sum()
        assert a.mirrored == [False, mirror]
    # 0.84 when the second oak is registered as it faces; 0.92 turned over
    assert ious[True] >= 0.9 and ious[True] > ious[False] + 0.04


@pytest.mark.parametrize("kind", ["lobed", "trilobed", "elliptic"])
def test_leaves_facing_one_way_are_left_alone(kind):
    _, blades, _ = normalise_exemplars(leaf_family(4, size=160, kind=kind, rng=0))
    assert mirrored_exemplars(blades, 0) == [False] * 4
    maples = [data.load(f"maple_leaf_0{i}") for i in (1, 4, 7)]
    _, blades, _ = normalise_exemplars(maples)
    assert mirrored_exemplars(blades, 1) == [False] * 3


def test_mirror_inputs_are_checked():
    leaves = leaf_family(2, size=96, rng=0)
    with pytest.raises(TypeError, match="mirror"):
        analyze(leaves, 0, {"veins": leaves[0].layers["veins"]}, mirror="yes")
    with pytest.raises(ValueError, match="training_index"):
        mirrored_exemplars([np.ones((20, 20), bool)] * 2, 2)
    with pytest.raises(ValueError, match="ratio"):
        mirrored_exemplars([np.ones((20, 20), bool)] * 2, 0, ratio=0)
