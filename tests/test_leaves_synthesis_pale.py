"""Pale layers keep their relative contrast on a lighter leaf; what every new leaf shares is held compactly (issue 22).

A grass photo's pale veins, brought from a dark strip onto a light one as a "screen", kept about half
their relative contrast (vein continuity 0.85). Here on a procedural family whose exemplars are light
and dark (RGB times 1.0 and 0.5), with true registrations and the true vein masks.
"""

import dataclasses

import cv2
import numpy as np
import pytest
from leaves_truth import normalised_true_registrations
from scipy import ndimage as ndi

from branchnb.leaves import leaf_family, synthesis
from branchnb.leaves._measure_synthesis import _contrast, _skeleton
from branchnb.leaves.analysis import analyze, normalise_exemplars
from branchnb.leaves.comparison import colour_range_fraction
from branchnb.leaves.synthesis import _prepared

_GAINS = (1.0, 0.5, 1.0, 0.5)  # light and dark exemplars
_LIGHT, _DARK = (0, 2), (1, 3)


@pytest.fixture(scope="module")
def family():
    fam = leaf_family(len(_GAINS), size=128, kind="lobed", rng=0)
    fam = [dataclasses.replace(x, image=np.dstack([x.image[..., :3] * g, x.image[..., 3:]]).astype(np.float32))
           for x, g in zip(fam, _GAINS)]
    a = analyze(fam, 0, {"veins": fam[0].layers["veins"]}, registrations=normalised_true_registrations(fam, 0))
    _, _, offs = normalise_exemplars(fam)
    truth = []
    for x, o in zip(fam, offs):
        t = np.zeros(a.blades[0].shape, bool)
        m = x.layers["veins"]
        t[o[1]:o[1] + m.shape[0], o[0]:o[0] + m.shape[1]] = m
        truth.append(t)
    return a, truth


def _vein_contrast(img, blade, veins):
    """Median relative contrast (grey over its blur in the blade, minus 1; best of 3 x 3) on the veins' skeleton."""
    sk = _skeleton(veins) & ndi.binary_erosion(blade, iterations=3)
    return float(np.median(ndi.maximum_filter(_contrast(img, blade), size=3)[sk]))


def test_pale_veins_of_a_dark_leaf_keep_their_contrast_on_a_light_one(family):
    """New leaves whose background is a light exemplar and whose veins come from a dark one: the
    veins' relative contrast over the donor's own. Measured (lobed 128 px, 19 such leaves of seeds
    0-39): as a screen 0.45-0.48 (median 0.46); as a ratio capped at the exemplars' lightest blade
    colour 0.97-1.01 (median 0.98; see ``synthesis.generate_leaf``), blade colours in the exemplars'
    range 0.994-1.000 of the pixels (exemplars 0.976)."""
    a, truth = family
    p = _prepared(a)
    calls, orig = [], p.source_coords

    def spy(e, m, d):
        c = orig(e, m, d)
        calls.append((e, synthesis._canvas_coords(p, c)))  # the leaf's maps cover its work box
        return c
    p.source_coords = spy
    ratios = []
    try:
        for s in range(40):
            calls.clear()
            x = synthesis.generate_leaf(a, s)
            d = x.layers["veins"]
            if x.background not in _LIGHT or d not in _DARK:
                continue
            c = next(c for e, c in calls[1:] if e == d)
            carried = cv2.remap(truth[d].astype(np.float32), c[..., 0], c[..., 1], cv2.INTER_LINEAR) > 0.5
            own = _vein_contrast(a.exemplars[d], a.blades[d], truth[d])
            ratios.append(_vein_contrast(x.image, x.blade, carried) / own)
            # the colours stay the exemplars' (as much of the blade as of the exemplars' own)
            assert colour_range_fraction(x.image, a.exemplars) >= 0.97
    finally:
        p.source_coords = orig
    assert len(ratios) >= 8
    assert np.median(ratios) >= 0.85 and min(ratios) >= 0.75


def test_shared_images_are_float16_colours(family):
    """The stage images, the leaf under each layer and the layer masks and weights are held as float16
    colour channels (no alpha): 319 -> 196 MB for 3 exemplars of 1.1 MP (procedural lobed, two layers)."""
    a, _ = family
    p = _prepared(a)
    h, w = a.blades[0].shape
    for group in (p.stage, p.layer_under):
        for row in group:
            for img in row:
                assert img.dtype == np.float16 and img.shape == (h, w, 3)
    for group in (p.layer_masks, p.layer_weights):
        for row in group:
            for img in row:
                assert img.dtype == np.float16 and img.shape == (h, w)
    # the masks are still the induced layers (grown by their anti-aliased rim)
    for e in range(p.n):
        assert np.all(p.layer_masks[0][e][a.layers[0].masks[e] & a.blades[e]] == 1)


def test_a_layer_of_the_other_sign_gives_no_new_leaf_its_veins(family):
    """An exemplar whose "vein" layer is its dark spots (the induction took another structure; a grass
    photo's dark dots induced as its pale veins) is passed over as a donor while the others have one.
    Measured on the grass photos: vein continuity min over rng 0-3 0.88-0.94 -> 0.93-0.94."""
    import copy

    from branchnb.leaves.synthesis import SynthesisParams, generate
    a, _ = family
    fam = leaf_family(len(_GAINS), size=128, kind="lobed", rng=0)
    _, _, offs = normalise_exemplars(fam)
    spots = np.zeros(a.blades[1].shape, bool)
    m, o = fam[1].layers["spots"], offs[1]
    spots[o[1]:o[1] + m.shape[0], o[0]:o[0] + m.shape[1]] = m
    b = copy.copy(a)
    L = copy.copy(a.layers[0])
    L.masks = [spots & a.blades[1] if e == 1 else mk for e, mk in enumerate(a.layers[0].masks)]
    b.layers = [L]
    p = _prepared(b)
    assert p.layer_agrees[0] == [True, False, True, True]
    donors = [x.layers["veins"] for x in generate(b, 8, rng=1, params=SynthesisParams(correct=False))]
    assert 1 not in donors and len(set(donors)) >= 2
    # the family as induced: every exemplar's veins are pale
    assert all(_prepared(a).layer_agrees[0])
