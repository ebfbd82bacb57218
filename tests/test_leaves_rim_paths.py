"""Hole rims are no veins on the snapped paths either (issue 22).

The snapped paths follow the ridge evidence, and a hole's rim in the veins' colour is a ridge with the
hole on one side: the paths ran along it and the rim under them stayed induced (``python -m
branchnb.leaves._measure_holes``: 0.31 of the rims taken at 320 px). A path piece on the one-sided rim
that touches the hole goes; a vein beside a hole with blade between them stays.
"""

import numpy as np

from branchnb.leaves import analyze, leaf_family
from branchnb.leaves._measure_holes import hole_leaf
from branchnb.leaves.analysis import normalise_exemplars
from branchnb.leaves.analysis_normalise import _on_canvas
from branchnb.leaves.analysis_trim import _trimmed


def _holed_blade():
    blade = np.ones((60, 60), bool)
    yy, xx = np.mgrid[:60, :60]
    d = np.hypot(yy - 30, xx - 30)
    blade[d <= 8] = False
    return blade, d


def test_snapped_path_hugging_a_hole_is_trimmed_a_vein_beside_it_kept():
    blade, d = _holed_blade()
    hug = (d > 8) & (d <= 11) & (np.arange(60)[None, :] < 30)       # a path along the hole's left rim
    beside = (d >= 14) & (d <= 15) & (np.arange(60)[None, :] >= 36)   # a vein with blade between it and the hole
    rim = (d > 8) & (d <= 16)                                        # the one-sided rim (reach 8 px)
    snapped = hug | beside
    user = np.zeros_like(blade)
    user[5:55, 5] = True
    m = _trimmed(snapped.copy(), blade, user, snapped, None, rim, outline_in_layer=True, inked_outline=False)
    assert not (m & hug).any()                 # main kept all 150-odd px of the hugging path
    assert (m & beside).sum() == beside.sum()


def test_holed_lobed_leaf_320px_rims_not_taken():
    """Procedural lobed family at 320 px, seed 0, holes beside the junction and the midrib: main took
    0.31 of the rim pixels as vein (338/75/108 px on the three exemplars), now 0.065 (37/48/24)."""
    fam = leaf_family(4, size=320, kind="lobed", rng=0)
    holed = [None] + [hole_leaf(leaf, i, where=("junction", "midrib")) for i, leaf in enumerate(fam) if i > 0]
    images = [fam[0].image] + [x[0] for x in holed[1:]]
    _, blades, offs = normalise_exemplars(images)

    masks = analyze(images, 0, {"veins": fam[0].layers["veins"]}).layer("veins").masks
    rims = [_on_canvas(x[2], o, blades[0].shape) for x, o in zip(holed[1:], offs[1:])]
    taken = sum((masks[e] & rims[e - 1]).sum() for e in range(1, 4)) / sum(r.sum() for r in rims)
    assert taken < 0.1, taken
