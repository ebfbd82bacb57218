"""Pale (paper-white) veins drawn on a clip-art leaf are leaf, and a scribble on them is taken (issue 22).

On main the blade mask cut a drawn maple's 3 px white veins out as one large hole (7 % of the blade,
over ``max_hole``), so ``python -m branchnb.leaves._measure_drawn --styles pale`` crashed on maple
400 px seed 2 and 800 px seed 1: the user's scribbles along the midrib were refused as "outside the
leaf" (14 of 54 pixels on the blade).
"""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.leaves import Layer, LayerSet, Scribble
from branchnb.leaves._clipart_kinds import clip_leaf
from branchnb.leaves._measure_unseen import user_scribbles
from branchnb.leaves.exemplar import blade_mask, leaf_exemplar
from branchnb.leaves.layers import _check_scribbles


@pytest.mark.parametrize("size, seed, vein_px", [(400, 2, 3.0), (800, 1, 3.0)])
def test_pale_drawn_veins_stay_in_the_blade(size, seed, vein_px):
    leaf = clip_leaf("maple", size, 10 * seed, vein_px, "pale", outline_px=1, shadow=True)
    ex = leaf_exemplar(leaf.image)
    inside = ndi.binary_erosion(leaf.blade, iterations=2)
    assert (ex.blade & leaf.veins & inside).sum() >= 0.98 * (leaf.veins & inside).sum()   # main: ~0.4
    marks, _ = _check_scribbles(user_scribbles(leaf, rng=seed), ex.blade)                 # main: ValueError
    assert marks["veins"].sum() > 0


def test_thin_lines_filled_round_hole_kept():
    img = np.ones((200, 200, 3), np.float32)
    yy, xx = np.mgrid[:200, :200]
    leaf = np.hypot(yy - 100, xx - 100) < 80
    img[leaf] = (0.2, 0.5, 0.1)
    lines = leaf & ((np.abs(yy - 100) <= 1) | (np.abs(xx - 100) <= 1) | (np.abs(yy - xx) <= 1)) \
        & (np.hypot(yy - 100, xx - 100) < 76)
    img[lines] = 1.0                                     # a network of white lines: 3 % of the leaf
    hole = np.hypot(yy - 130, xx - 60) < 12              # a real hole, away from the lines
    img[hole] = 1.0
    b = blade_mask(img)
    assert b[lines & ~hole].mean() == 1.0
    assert not b[ndi.binary_erosion(hole, iterations=2)].any()


def test_scribble_off_the_leaf_is_refused_by_name_on_a_hole_taken():
    img = np.zeros((120, 120, 4), np.float32)
    img[..., :3] = (0.2, 0.5, 0.1)
    yy, xx = np.mgrid[:120, :120]
    img[..., 3] = (np.hypot(yy - 60, xx - 60) < 50) & ~(np.hypot(yy - 60, xx - 60) < 12)
    blade = img[..., 3] > 0.5
    on_hole = LayerSet([Layer("veins", "#d62728", 0, [Scribble([(52, 60), (68, 60)], 1.0)])],
                       [Scribble([(60, 90)], 3.0)])
    marks, _ = _check_scribbles(on_hole, blade)          # inside the leaf's outline: no error
    assert not marks["veins"].any()                      # main: ValueError "lies outside the leaf"
    off = LayerSet([Layer("veins", "#d62728", 0, [Scribble([(112, 5), (118, 5)], 1.0)])],
                   [Scribble([(60, 90)], 3.0)])
    with pytest.raises(ValueError, match=r"layer_set.layers\['veins'\].scribbles\[0\] lies outside the leaf"):
        _check_scribbles(off, blade)
