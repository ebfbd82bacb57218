"""Issue 23 (branching64): the ground between the synthesized lines keeps the example's texture.

Known line trees over known grounds (:mod:`branchnb.branching._ground_texture_check`): on an evenly lit
ground of field patches the gap completion relit every patch to the fragments' smoothed light, so the
fields came out as one even green (energy of the patch-sized bands 0.10-0.22 of the example's)."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import synthesize_image
from branchnb.branching._ground_texture_check import _target, disc_copy, example, ground_distance


@pytest.mark.parametrize("kind, seed", [("fields", 0), ("fields", 3), ("noise", 2)])
def test_ground_keeps_its_patches(kind, seed):
    img, s, _ = example(kind, 256, seed)
    tgt = _target(256, seed)
    out = synthesize_image(img, s, tgt, rng=seed)
    d = ground_distance(img, s, np.asarray(out.image)[..., :3], tgt)
    # main: fields 0 big 0.10, hist 0.28, spec 1.45 (the patches relit away)
    assert d["big"] > 0.45, d
    assert d["hist"] < 0.2, d
    assert d["spec"] < 0.8, d
    assert 0.9 < d["lstd"] < 1.1, d


def test_no_copy_of_a_bright_disc():
    # a bright disc on the root branch (a retina's optic disc): no fragment carries it off the
    # branch's body (main: a blob of 0.027 of the disc's area at a junction, brighter than any ground pixel)
    img, s, disc = example("disc", 384, 1)
    tgt = _target(384, 1)
    out = synthesize_image(img, s, tgt, rng=1)
    assert disc_copy(img, s, disc, np.asarray(out.image)) < 0.01
