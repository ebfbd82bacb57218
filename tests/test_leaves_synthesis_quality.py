"""Synthesis quality (issue 22): solid pasted veins, smooth bleed at notches, variety, one vein system.

Measured with ``python -m branchnb.leaves._measure_synthesis`` (procedural families with true
registrations, the seven sample maples, two drawn oaks, five grass photos); here on small inputs
with known answers.
"""

import cv2
import numpy as np
import pytest
from leaves_truth import normalised_true_registrations
from scipy import ndimage as ndi

from branchnb.core.image import extend_nearest
from branchnb.leaves import leaf_family
from branchnb.leaves._measure_synthesis import median_pair_iou, synthesis_row
from branchnb.leaves.analysis import analyze
from branchnb.leaves.prepared import _bleed, _completed, _smooth_fill
from branchnb.leaves.synthesis import SynthesisParams, _masked_blur, generate


def _wide_vein(h=60, w=90, width=7):
    """A blade with a gradient and one wide dark vein across it; the vein's mask and its two rims."""
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    img = np.dstack([0.9 - 0.2 * xx / w, 0.5 + 0.3 * yy / h, 0.05 + 0 * xx]).astype(np.float32)
    vein = np.abs(yy - h / 2) < width / 2
    img[vein] = img[vein] * np.array([0.85, 0.3, 0.5], np.float32)
    rims = vein & ~ndi.binary_erosion(vein, iterations=2)
    return img, np.ones((h, w), bool), vein, rims


def test_a_mask_on_the_rims_of_a_wide_vein_is_completed():
    """An induced layer that traced the two rims of a drawn oak's wide vein was pasted hollow
    (dark rims around a core of blade colour). Completed: the whole vein, and the leaf under it
    is the blade's colour (before, the residual kept the core: contrast ratio 1 there)."""
    img, blade, vein, rims = _wide_vein()
    inner = vein & ~rims
    grown, under = _completed(img, blade, rims)
    assert inner.sum() > 50 and (grown & inner).sum() >= 0.95 * inner.sum()
    assert (grown & ~ndi.binary_dilation(vein)).sum() == 0  # nothing beside the vein joins
    truth = np.dstack([0.9 - 0.2 * np.mgrid[:60, :90][1] / 90.0, 0.5 + 0.3 * np.mgrid[:60, :90][0] / 60.0,
                       0.05 + 0 * np.mgrid[:60, :90][0]])
    err = np.abs(under - truth)[vein].max()
    assert err < 0.03
    ratio = (img / np.maximum(under, 0.02))[..., 1]
    assert ratio[inner].max() < 0.5  # the core pastes as dark as the rims


def test_smooth_fill_keeps_known_pixels_and_fills_within_their_range():
    rng = np.random.default_rng(0)
    img = rng.random((40, 50, 3)).astype(np.float32)
    known = rng.random((40, 50)) < 0.2
    out = _smooth_fill(img, known)
    assert np.array_equal(out[known], img[known])
    assert out.min() >= img[known].min() - 1e-6 and out.max() <= img[known].max() + 1e-6
    assert _smooth_fill(img[..., 0], known).shape == (40, 50)


def test_bleed_outside_a_notched_blade_has_no_rays():
    """The nearest blade colour extended past a notch fanned into hatched rays (drawn oaks at
    1 MP). Measured: mean |Laplacian| 3-20 px outside the blade 0.0153 (nearest) -> 0.0007."""
    h = w = 120
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    blade = np.hypot(xx - 60, yy - 60) < 40
    for a in np.linspace(0, 2 * np.pi, 7, endpoint=False):  # six notches
        blade &= np.hypot(xx - 60 - 38 * np.cos(a), yy - 60 - 38 * np.sin(a)) > 9
    rng = np.random.default_rng(1)
    img = np.dstack([0.9 - 0.5 * np.hypot(xx - 60, yy - 60) / 40, 0.4 + 0.2 * np.sin(xx / 5),
                     0.1 + 0.05 * rng.random((h, w))]).astype(np.float32)
    out = _bleed(img, blade)
    near = extend_nearest(img, blade)
    d = ndi.distance_transform_edt(~blade)
    ring = (d > 3) & (d < 20)

    def rough(x):
        return float(np.abs(cv2.Laplacian(np.ascontiguousarray(x), cv2.CV_32F))[ring].mean())
    assert np.array_equal(out[blade], img[blade])
    assert np.array_equal(out[(d > 0) & (d <= 2)], near[(d > 0) & (d <= 2)])  # the margin's own colour first
    assert rough(out) < 0.25 * rough(near)


def test_reduced_wide_blur_matches_the_full_size_one():
    rng = np.random.default_rng(2)
    img = cv2.GaussianBlur(rng.random((200, 240, 3)).astype(np.float32), (0, 0), 6)
    mask = np.zeros((200, 240), bool)
    mask[30:170, 40:200] = True
    sigma = 12.0
    got = _masked_blur(img, mask, sigma)
    wsum = cv2.GaussianBlur(mask.astype(np.float32), (0, 0), sigma)
    full = cv2.GaussianBlur(img * mask[..., None], (0, 0), sigma) / np.maximum(wsum, 1e-6)[..., None]
    assert np.abs(got - full)[mask].max() < 0.01
    assert np.array_equal(got[~mask], img[~mask])


@pytest.fixture(scope="module")
def family():
    fam = leaf_family(5, size=160, kind="trilobed", rng=2)
    regs = normalised_true_registrations(fam)
    return analyze(fam, 0, {"veins": fam[0].layers["veins"]}, registrations=regs)


def test_spread_and_smoothed_bootstrap_make_new_leaves_as_varied_as_the_exemplars(family):
    """Median pairwise blade IoU of 12 new leaves, mean over 4 batches (one batch swings by +-0.05).
    Measured here (rng 0-3; size and pose the leading exemplar's, issue 22): the convex blend with
    poses and sizes copied 0.62, with both changes 0.56, exemplars 0.56 (maples 0.75 -> 0.67 against
    0.63)."""
    a = family
    ex = median_pair_iou(list(a.blades))
    old = SynthesisParams(restore_spread=False, smooth_bootstrap=False)
    before = np.mean([median_pair_iou([x.blade for x in generate(a, 12, rng=r, params=old)]) for r in range(4)])
    after = np.mean([median_pair_iou([x.blade for x in generate(a, 12, rng=r)]) for r in range(4)])
    assert after <= ex + 0.05
    assert after < before - 0.03


def test_new_leaves_keep_sharp_solid_veins_inside_the_canvas(family):
    """Vein continuity along the donor's carried veins (share of its skeleton at half its own contrast)
    >= 0.9; no new leaf cut by the canvas; Laplacian variance inside the blades >= 0.8 of the
    exemplars' (issue 22's 0.8; measured here 0.99, vein continuity 1.00)."""
    r = synthesis_row(family, 4, seed=1)
    assert r["vein_cont"] >= 0.9 and r["vein_cont_min"] >= 0.85
    assert r["cut"] == 0.0
    assert r["sharp"] >= 0.8
