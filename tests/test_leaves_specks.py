"""Pinholes and specks in layer induction (issue 22: maple_leaf_04's 334 matte pinholes).

A photographed blade carries dots: pinholes in its matte, specks of mottling.
A user's vein stroke across pinholes was cut into pieces (maple_leaf_04's hand
trace: 3 pieces), and the broken template was carried onto every exemplar;
specks of the vein's colour beside a carried vein were induced as dots of vein.
"""

import numpy as np
from scipy import ndimage as ndi

from branchnb.core.metrics import iou
from branchnb.leaves import analyze, leaf_family
from branchnb.leaves._measure_specks import speckle
from branchnb.leaves.analysis import normalise_exemplars
from branchnb.leaves.analysis_induce import _pinholes, _without_dots


def _pieces(m):
    return ndi.label(m, structure=np.ones((3, 3), bool))[1]


def test_pinholes_are_the_holes_narrower_than_the_layer():
    blade = np.ones((40, 60), bool)
    blade[0], blade[-1], blade[:, 0], blade[:, -1] = False, False, False, False
    blade[10:12, 10:12] = False            # a 2 px pinhole
    blade[20, 30] = False                  # a 1 px pinhole
    blade[15:25, 45:55] = False            # a real hole, 10 px across
    layer = np.zeros_like(blade)
    layer[20, 5:55] = True                 # a 1 px stroke
    holes = _pinholes(blade, layer)
    assert holes[10:12, 10:12].all() and holes[20, 30]
    assert not holes[15:25, 45:55].any()
    assert not holes[blade].any()


def test_without_dots_keeps_veins_and_drops_specks():
    m = np.zeros((40, 60), bool)
    m[20, 5:55] = True                     # a vein
    m[8:10, 8:10] = True                   # 2 px speck
    m[30:34, 40:44] = True                 # 4 px speck
    m[5:15, 30] = True                     # a 10 px side stub: elongated, kept
    out = _without_dots(m, 1.0)
    assert out[20, 5:55].all() and out[5:15, 30].all()
    assert not out[8:10, 8:10].any() and not out[30:34, 40:44].any()


def _holed_family():
    """A procedural family whose training leaf has matte pinholes punched along its veins,
    and whose exemplars carry pinholes and specks 1-4 px across."""
    fam = leaf_family(3, size=160, kind="lobed", rng=1)
    veins = fam[0].layers["veins"]
    img0 = fam[0].image.copy()
    rng = np.random.default_rng(0)
    on = np.argwhere(veins)
    for y, x in on[rng.choice(len(on), 25, replace=False)]:
        img0[y - 1:y + 1, x - 1:x + 1, 3] = 0.2
    return fam, [img0] + [speckle(leaf, i)[0] for i, leaf in enumerate(fam[1:], start=1)]


def test_a_stroke_across_pinholes_stays_whole_and_specks_are_not_induced():
    fam, images = _holed_family()
    veins = fam[0].layers["veins"]
    _, blades, offs = normalise_exemplars(images)
    a = analyze(images, 0, {"veins": veins})
    masks = a.layer("veins").masks
    # main: the training layer in 20 pieces (4 without the pinholes)
    assert _pieces(masks[0]) <= _pieces(veins)

    def on_canvas(m, o):
        c = np.zeros(blades[0].shape, bool)
        c[o[1]:o[1] + m.shape[0], o[0]:o[0] + m.shape[1]] = m
        return c
    for e in (1, 2):
        truth = on_canvas(fam[e].layers["veins"], offs[e])
        assert iou(masks[e], truth) >= 0.74
        # no induced dot shorter than a speck (main: 32 and 41 pieces)
        lab, n = ndi.label(masks[e], structure=np.ones((3, 3), bool))
        ext = [max(s[0].stop - s[0].start, s[1].stop - s[1].start) for s in ndi.find_objects(lab)]
        assert min(ext) >= 5
