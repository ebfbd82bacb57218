"""Steps 1-2 of the ridge snapping, split into :mod:`branchnb.leaves.snapping_evidence`."""

import numpy as np
import pytest

from branchnb.leaves import snapping, snapping_evidence
from branchnb.leaves.snapping_evidence import contrast_direction, ridge_evidence


def _leaf_with_vein(size=96, dark=20.0):
    lab = np.zeros((size, size, 3), np.float64)
    lab[..., 0], lab[..., 1], lab[..., 2] = 60.0, -20.0, 30.0
    vein = np.zeros((size, size), bool)
    vein[size // 2 - 1:size // 2 + 1, 12:size - 12] = True  # a 2 px dark vein
    lab[vein, 0] -= dark
    blade = np.zeros((size, size), bool)
    blade[6:-6, 6:-6] = True
    return lab, vein, blade


def test_still_importable_from_snapping():
    assert snapping.contrast_direction is snapping_evidence.contrast_direction
    assert snapping.ridge_evidence is snapping_evidence.ridge_evidence


def test_direction_and_evidence_on_a_dark_vein():
    lab, vein, blade = _leaf_with_vein()
    d = contrast_direction(lab, vein, blade)
    np.testing.assert_allclose(d, [-1.0, 0.0, 0.0], atol=1e-6)
    ev = ridge_evidence(lab, blade, d, 2.0)
    assert ev.dtype == np.float32 and ev.min() >= 0.0 and ev.max() <= 1.0
    on = ev[vein[:, 20:-20].any(1)][:, 20:-20].mean()
    far = ev[20:30, 20:-20].mean()
    assert on > 0.8 and far < 0.05
    assert not ev[~blade].any()


def test_contrast_direction_bad_mask():
    lab, vein, blade = _leaf_with_vein()
    with pytest.raises((ValueError, TypeError), match="layer"):
        contrast_direction(lab, vein[:10], blade)
