"""Small leaves (96-128 px): induced vein ends, petioles and tiny spots, and new leaves of dense veins (issue 22).

Procedural families (``leaf_family(4, size, kind, rng=seed)``, TPS-RPM registrations, the defaults), the
training leaf's true veins and spots as the user's layers, IoU of every other exemplar's induced layer with
its true layer. On main (0c99f840):

* elliptic 128 px seed 4, veins [0.708, 0.665, 0.773], the petiole of exemplars 1 and 2 not induced at all:
  the induced veins' ends at the margin and the petiole covered 0.24-0.28 of the 2-px outline band, which
  ``INKED_OUTLINE`` (0.2) took for an inked outline, and the whole band went (:func:`_trimmed`);
* elliptic 96 px seed 1, spots [0.172, 0.354, 0.435]: colour alone reproduced the training spots with IoU
  0.23 only (the removal of the veins beside them filled most of their pixels), so their edges were never
  decided by colour (``MARKS_SINGLED``);
* elliptic 96 px seed 1 with the vein ends kept (leaves90): the veins cover half the blade, 2-4 px apart,
  and the leaf under them was read from the blade 2 px clear of them (10 px of 1546 on exemplar 1): new
  leaf 0 of ``generate(a, 3, rng=0)`` came out pale, blade mean (0.56, 0.74, 0.30) against the exemplars'
  (0.47-0.49, 0.61-0.64, 0.24-0.26) (:func:`~branchnb.leaves.prepared_fill._clear_of`).
"""

from functools import lru_cache

import numpy as np
import pytest

from branchnb.core.metrics import iou
from branchnb.core.morphology import _binary_dilation
from branchnb.leaves._measure import _family_on_canvas
from branchnb.leaves.analysis import analyze
from branchnb.leaves.analysis_induce import MARKS_CLEAR_MIN, _clear_of_above
from branchnb.leaves.analysis_trim import _trimmed, band_crossing
from branchnb.leaves.prepared import _prepared
from branchnb.leaves.prepared_fill import _UNDER_SUPPORT, _clear_of, _completed, _smooth_fill
from branchnb.leaves.starts import split_petiole
from branchnb.leaves.synthesis import generate


@lru_cache(maxsize=3)
def _analysed(kind, size, seed):
    fam, gt, _, _ = _family_on_canvas(kind, size, 4, seed)
    a = analyze(fam, 0, {"veins": fam[0].layers["veins"], "spots": fam[0].layers["spots"]})
    return a, gt


def test_small_elliptic_leaves_keep_vein_ends_and_petiole():
    a, gt = _analysed("elliptic", 128, 4)
    veins = [np.asarray(a.layer("veins").masks[e], bool) for e in (1, 2, 3)]
    ious = [iou(m, gt[e]["veins"]) for e, m in zip((1, 2, 3), veins)]
    assert min(ious) >= 0.72, ious                       # main 0.665 (now 0.738)
    for e, m in zip((1, 2, 3), veins):
        _, pet, _ = split_petiole(a.blades[e])
        truth = gt[e]["veins"] & pet
        assert truth.sum() >= 10
        assert (m & truth).sum() >= 0.3 * truth.sum(), e   # main: none on exemplars 1 and 2 (now 0.44+)


@pytest.mark.parametrize("kind,size,seed,least,mean", [("elliptic", 96, 1, 0.5, 0.6), ("fan", 128, 4, 0.65, 0.72)])
def test_tiny_spots_take_their_edges_by_colour(kind, size, seed, least, mean):
    """main: elliptic 96 px [0.172, 0.354, 0.435] (now [0.583, 0.667, 0.736]), fan 128 px [0.443, 0.548,
    0.521] (now [0.726, 0.821, 0.775])."""
    a, gt = _analysed(kind, size, seed)
    ious = [iou(np.asarray(a.layer("spots").masks[e], bool), gt[e]["spots"]) for e in (1, 2, 3)]
    assert min(ious) >= least and np.mean(ious) >= mean, ious


def _small_blade():
    """An elliptic blade (about 100 x 50 px) with a 2-px petiole; 12 veins 2 px wide run into its margin."""
    yy, xx = np.mgrid[:140, :80]
    blade = ((xx - 40) / 24.0) ** 2 + ((yy - 60) / 50.0) ** 2 <= 1
    blade[109:135, 39:41] = True
    veins = np.zeros_like(blade)
    veins[12:135, 39:41] = True
    for y in range(25, 100, 7):
        veins[y:y + 2, 14:66] = True
    return blade, veins & blade


def test_vein_ends_of_a_small_leaf_are_no_inked_outline():
    blade, veins = _small_blade()
    crossing = band_crossing(blade, veins)
    assert 0.1 < crossing < 0.4
    kept = _trimmed(veins.copy(), blade, veins, veins, None, None, outline_in_layer=False, inked_outline=False,
                    crossing=crossing)
    assert kept.sum() == veins.sum()
    # Without the training leaf's own share the ends (0.21 of the band) were an inked outline and went;
    # the 2-px petiole is no outline either way (main: its 48 px went with the band).
    _, pet, _ = split_petiole(blade)
    cut = _trimmed(veins.copy(), blade, veins, veins, None, None, outline_in_layer=False, inked_outline=False)
    assert (veins & ~cut).sum() >= 60 and (cut & pet).sum() == (veins & pet).sum() >= 40
    # An inked outline covering the band is still left out (the petiole stays: no outline).
    from scipy import ndimage as ndi
    ink = blade & ~ndi.binary_erosion(blade, iterations=2) & ~pet
    m = _trimmed(veins | ink, blade, veins, veins, None, None, outline_in_layer=False, inked_outline=False,
                 crossing=crossing)
    assert (m & ink & ~veins).sum() <= 0.02 * ink.sum()
    assert (m & veins & pet).sum() == (veins & pet).sum()


def test_marks_read_clear_of_the_layers_above_unless_too_few():
    blade = np.ones((30, 30), bool)
    taken = np.zeros_like(blade)
    taken[:, 10] = True
    user = np.zeros_like(blade)
    user[5:8, 11:14] = True                     # 3 x 3 spot beside the vein: 6 pixels clear of it
    clear = _clear_of_above(user, blade, taken)
    assert not clear[:, 9:12].any() and clear[:, 12:].all()
    assert (user & clear).sum() == 6 >= MARKS_CLEAR_MIN
    user[:] = False
    user[5:8, 11] = True                        # a spot only along the vein: the whole blade
    assert _clear_of_above(user, blade, taken).all()


def test_new_leaves_of_dense_small_veins_keep_the_exemplars_blade_colour():
    a, gt = _analysed("elliptic", 96, 1)
    p = _prepared(a)
    k = [L.name for L in a.layers].index("veins")
    for e in range(4):
        b = a.blades[e]
        # The leaf without its veins: its colours 1 px clear of the true veins and spots, filled.
        truth = _smooth_fill(np.asarray(a.exemplars[e], np.float32)[..., :3],
                             b & ~_binary_dilation(gt[e]["veins"] | gt[e]["spots"], iterations=1))
        under = np.asarray(p.layer_under[k][e], np.float32)
        assert np.abs(under[b] - truth[b]).mean() < 0.03, e        # 2 px clear: 0.106-0.116 on exemplars 0, 1
    ex = np.array([np.asarray(a.exemplars[e])[..., :3][a.blades[e]].mean(0) for e in range(4)])
    for g in generate(a, 3, rng=0):
        m = g.image[..., :3][g.image[..., 3] > 0.5].mean(0)
        assert np.all(m >= ex.min(0) - 0.02) and np.all(m <= ex.max(0) + 0.02), m   # was (0.56, 0.74, 0.30)


def test_the_leaf_under_a_dense_layer_is_read_nearer_than_its_rim():
    yy, xx = np.mgrid[:60, :60]
    r2 = ((xx - 30) ** 2 + (yy - 30) ** 2) / 26.0 ** 2
    blade, inner = r2 <= 1, r2 <= (24.5 / 26) ** 2
    img = np.zeros((60, 60, 3), np.float32)
    img[...] = (0.35, 0.55, 0.17)
    img[blade & ~inner] = (0.5, 0.65, 0.25)             # a pale margin the veins end 1-2 px short of
    veins = inner & (yy % 5 < 2)                         # 2 px wide, 3 px apart
    img[veins] = (0.6, 0.8, 0.35)
    two = blade & ~_binary_dilation(veins, iterations=2)
    one = blade & ~_binary_dilation(veins, iterations=1)
    # 2 px clear of the veins is the margin's outer ring only: 1 px clear is taken.
    assert two.sum() < _UNDER_SUPPORT * (blade & ~veins).sum() and (one & inner).sum() > 100
    assert (_clear_of(blade, veins) == one).all()
    _, under = _completed(img, blade, veins)
    err = np.abs(under[veins] - (0.35, 0.55, 0.17)).max(axis=1).mean()
    assert err < 0.03, err
    assert np.abs(_smooth_fill(img, two)[veins] - (0.35, 0.55, 0.17)).max(axis=1).mean() > 0.1
    # A sparse layer keeps its 2 px rim out.
    sparse = blade & (yy == 30)
    assert (_clear_of(blade, sparse) == (blade & ~_binary_dilation(sparse, iterations=2))).all()
