"""Layer donors (issue 22): veins from the exemplar carried with the least stretch, never an under-induced one.

A grass leaf led by a wide exemplar took its veins from narrow strips stretched across it (vein
continuity 0.45, no midrib). Here on procedural families with true registrations, some leaves
stretched 3.5x across (a family of narrow and wide leaves of one kind).
"""

import dataclasses

import cv2
import numpy as np
import pytest
from leaves_truth import normalised_true_registrations

from branchnb.leaves import leaf_family
from branchnb.leaves.analysis import analyze
from branchnb.leaves.synthesis import SynthesisParams, _prepared, generate

#: Without texture correction (half of a leaf's time here): it draws from a stream of its own, so the
#: donors, shapes and sizes are those of the defaults (with it, on 150 px leaves, the file took 26-61 s).
_PLAIN = SynthesisParams(correct=False)


def _stretched(leaf, fx):
    h, w = leaf.image.shape[:2]
    size = (int(round(w * fx)), h)

    def rs(m):
        return cv2.resize(m.astype(np.float32), size, interpolation=cv2.INTER_LINEAR) > 0.5
    img = cv2.resize(leaf.image, size, interpolation=cv2.INTER_AREA)
    layers = {k: rs(v) for k, v in leaf.layers.items()}
    return dataclasses.replace(leaf, image=img, blade=rs(leaf.blade), layers=layers,
                               keypoints=leaf.keypoints * np.array([fx, 1.0]))


def _analysis(kind, seed, wide=(0,)):
    fam = leaf_family(4, size=110, kind=kind, rng=seed)
    fam = [_stretched(x, 3.5) if i in wide else x for i, x in enumerate(fam)]
    regs = normalised_true_registrations(fam, 0)
    return analyze(fam, 0, {"veins": fam[0].layers["veins"]}, registrations=regs)


@pytest.fixture(scope="module")
def wide_training():
    return _analysis("elliptic", 2)


def test_anisotropy_of_scaled_maps(wide_training):
    a = wide_training  # exemplar 0 is the training leaf: its map is the identity
    p = _prepared(a)
    ident = np.stack([p.xx, p.yy], -1)
    blade = a.blades[0]
    c = np.array(blade.shape[::-1], np.float32) / 2
    assert p.carried_anisotropy(0, ident, blade) == pytest.approx(0.0, abs=1e-6)
    half = ((ident - c) * 0.5 + c).astype(np.float32)  # a similarity: no anisotropy
    assert p.carried_anisotropy(0, half, blade) == pytest.approx(0.0, abs=1e-6)
    wide = ((ident - c) * np.array([0.5, 1.0], np.float32) + c).astype(np.float32)  # spread 2x across
    assert p.carried_anisotropy(0, wide, blade) == pytest.approx(np.log(2.0) / 2, abs=0.01)


def _donor_stretch(a, params=_PLAIN):
    """Per new leaf: the stretch (log size ratio and anisotropy) of its vein donor and the least among the exemplars."""
    from branchnb.leaves import synthesis
    p = _prepared(a)
    maps, out = [], []
    orig = p.source_coords

    def spy(e, m, d):
        maps.append(synthesis._canvas_coords(p, m))  # the leaf's maps cover its work box
        return orig(e, m, d)
    p.source_coords = spy
    try:
        for s in range(8):
            maps.clear()
            x = synthesis.generate_leaf(a, s, params)
            m = maps[0]
            b = x.image[..., 3] > 0.5
            # as generate_leaf weighs it: anisotropy beyond a 1.5x stretch one way
            an = [np.hypot(np.log(p.lamina_size[e] / np.sqrt(b.sum())),
                           max(p.carried_anisotropy(e, m, b) - 0.5 * np.log(1.5), 0.0)) for e in range(p.n)]
            out.append((an[x.layers["veins"]], min(an)))
    finally:
        p.source_coords = orig
    return np.array(out)


def test_veins_come_from_the_least_stretched_donor(wide_training):
    """One exemplar 3.5x wider than the others: its shape spreads a narrow leaf's veins across it.
    Measured (elliptic 110 px, 8 leaves): mean stretch of the vein donor, any donor (the paper,
    ``donor_size_sigma=0``) 0.29 -> 0.22 (least possible 0.19, the background's own exemplar
    included, which is taken only when every other is stretched more than 1.5x)."""
    now = _donor_stretch(wide_training)
    anyd = _donor_stretch(wide_training, SynthesisParams(donor_size_sigma=0.0, correct=False))
    assert np.all(now[:, 0] <= now[:, 1] + np.log(1.5) + 1e-9)
    assert now[:, 0].mean() < anyd[:, 0].mean() - 0.05


def test_an_under_induced_donor_is_passed_over(wide_training):
    """An exemplar whose vein layer is a few dashes (a fifth of the others' skeleton) gives no new
    leaf its veins while others have a layer."""
    import copy
    a = copy.copy(wide_training)
    L = copy.copy(a.layers[0])
    masks = list(L.masks)
    ys, xs = np.nonzero(masks[2])
    keep = np.zeros_like(masks[2])
    keep[ys[: len(ys) // 5], xs[: len(xs) // 5]] = True
    masks[2] = keep
    L.masks = masks
    a.layers = [L]
    p = _prepared(a)
    assert p.layer_complete[0][2] < 0.75 <= min(p.layer_complete[0][e] for e in (0, 1, 3))
    donors = [x.layers["veins"] for x in generate(a, 8, rng=1, params=_PLAIN)]
    assert 2 not in donors and len(set(donors)) >= 2


def _aspect(blade):
    ys, xs = np.nonzero(blade)
    ev = np.linalg.eigvalsh(np.cov(np.stack([xs, ys]).astype(float)))
    return float(np.sqrt(ev[1] / ev[0]))


def test_a_shape_blends_only_compatible_exemplars(wide_training):
    """The wide exemplar's map lies 0.72-1.04 leaf sizes from the narrow ones' (those 0.22-0.32
    apart): a leaf it leads is its own shape, not a blend bent between a wide and a narrow leaf.
    Measured (elliptic 110 px, 8 leaves): aspect ratio (principal axes) of the leaves it leads,
    every exemplar blended -> compatible ones only: 2.2 and 13.6 (a sliver) -> 1.47 and 1.51 (its own 1.51);
    with the lead's own size (issue 22), 16 leaves: 1.08-4.34 -> 1.48-1.51."""
    from branchnb.leaves.synthesis import _exemplar_draws
    a = wide_training
    p = _prepared(a)
    iou = {}
    for lim in (0.3, 10.0):
        new = generate(a, 16, rng=3, params=SynthesisParams(shape_compatible=lim, correct=False))
        lead0 = [x for x in new if _exemplar_draws(x.seed, p.n)[2] == 0]
        assert lead0
        if lim == 0.3:
            for x in new:
                lead = _exemplar_draws(x.seed, p.n)[2]
                far = ~p.compatible(lead, 0.3)
                assert np.all(np.asarray(x.shape_weights)[far] == 0)
        iou[lim] = [_aspect(x.blade) for x in lead0]
    own = _aspect(a.blades[0])
    assert max(abs(v - own) for v in iou[0.3]) < 0.1
    assert max(abs(v - own) for v in iou[10.0]) > 0.5
