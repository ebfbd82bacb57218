"""Drawn leaves: the ink outline is neither grown nor induced as vein when nobody scribbled it (issue 22)."""

import numpy as np

from branchnb.core.metrics import iou
from branchnb.leaves._clipart_kinds import clip_leaf
from branchnb.leaves._measure_unseen import _on_canvas, user_scribbles
from branchnb.leaves.analysis import analyze
from branchnb.leaves.analysis_outline import _outline_band
from branchnb.leaves.exemplar import leaf_exemplar
from branchnb.leaves.layers import grow_layers
from branchnb.leaves.scribbles import Layer, LayerSet, Scribble


def test_drawn_maple_veins_stay_off_the_outline():
    # A drawn maple with 2 px veins and a 2 px ink outline; short vein scribbles only.
    leaves = [clip_leaf("maple", 384, k, 2.0, "pale") for k in range(2)]
    ex = [leaf_exemplar(x.image) for x in leaves]
    a = analyze(ex, 0, user_scribbles(leaves[0], rng=0))
    L = a.layer("veins")
    shape = a.blades[0].shape
    for e in range(2):
        truth = _on_canvas(leaves[e].veins, a.offsets[e], shape, a.mirrored[e])
        band = _outline_band(a.blades[e], truth)
        # main: 0.88 of the band taken, IoU 0.42
        assert (L.masks[e] & band).sum() < 0.3 * band.sum()
        assert iou(L.masks[e], truth) > 0.6


def test_scribbled_outline_stays_in_the_layer():
    # A user who scribbles the outline itself (a sketch's ink as one layer) keeps it.
    leaf = clip_leaf("maple", 256, 0, 2.0, "black")
    ex = leaf_exemplar(leaf.image)
    from branchnb.core.distance import edt
    d = edt(ex.blade)
    ring = (d >= 2) & (d <= 2.5)
    ry, rx = np.nonzero(ring)
    pts = [Scribble([(float(rx[i]), float(ry[i]))], 1.0) for i in range(0, len(rx), max(1, len(rx) // 40))]
    ls = LayerSet([Layer("ink", "#000000", 0, pts)], background=user_scribbles(leaf).background)
    tr = grow_layers(ex.rgba, ex.blade, ls)
    band = _outline_band(ex.blade, tr.masks["ink"])
    assert (tr.masks["ink"] & band).sum() > 0.5 * band.sum()
