"""Issue 23 (branching86): one labelled distance transform for every wide-line candidate, one disk helper.

``wide_lines._sharp_edged`` computed a full-image distance transform per candidate region (seconds on a
cracked-mud photo); :func:`~branchnb.branching.wide_lines._edge_rings` computes one labelled transform
for all of them. The decisions must not change: pinned here against the per-candidate rule on a small
case with wide lines, a fading blob and a second dark area near (but not within 8 px of) a line.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import wide_lines
from branchnb.branching.wide_lines import WIDE_EDGE, _edge_rings, _sharp_edged, wide_line_mask
from branchnb.core.morphology import disk


def _old_sharp_edged(dark_lab, reg, con, thr):
    """The per-candidate rule before branching86 (a full distance transform of the candidate's area)."""
    ids = np.unique(dark_lab[reg])
    ids = ids[ids > 0]
    if not ids.size:
        return False
    d = ndi.distance_transform_edt(~np.isin(dark_lab, ids))
    ring = (d >= 2.0) & (d <= 4.0)
    if not ring.any():
        return True
    return float(np.median(con[ring])) <= WIDE_EDGE * thr


def _scene(seed: int):
    """Painted wide bands (sharp), a shaded blob (fading), thin lines, on a noisy ground; (gray, ridge)."""
    rng = np.random.default_rng(seed)
    g = np.full((240, 240), 0.8, np.float32) + rng.normal(0, 0.02, (240, 240)).astype(np.float32)
    ridge = np.zeros(g.shape, bool)
    cv2.line(g, (60, 0), (70, 200), 0.2, 18)                          # a 18 px trunk from the top
    cv2.line(g, (150, 239), (130, 120), 0.25, 14)                     # a 14 px root from the bottom
    yy, xx = np.mgrid[:240, :240]
    g -= (0.5 * np.exp(-((xx - 205) ** 2 + (yy - 195) ** 2) / (2 * 12.0 ** 2))).astype(np.float32)  # shading
    for x0, y0, x1, y1 in ((70, 120, 130, 120), (130, 120, 220, 40), (70, 200, 30, 235), (140, 170, 185, 185)):
        cv2.line(g, (x0, y0), (x1, y1), 0.3, 3)
        cv2.line(ridge.view(np.uint8), (x0, y0), (x1, y1), 1, 5)
    cv2.circle(g, (110, 30), 9, 0.2, -1)                              # a dark spot 20 px off the trunk
    return np.clip(g, 0, 1), ridge


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_one_labelled_transform_gives_the_per_candidate_decisions(seed):
    g, ridge = _scene(seed)
    con = wide_lines._far_contrast(g, "dark", max(24.0, 0.06 * 240))
    thr = 0.15
    dark = con >= thr
    core = cv2.morphologyEx(dark.astype(np.uint8), cv2.MORPH_OPEN, disk(6)).astype(bool)
    lab, n = ndi.label(core, np.ones((3, 3), bool))
    dark_lab, _ = ndi.label(dark, np.ones((3, 3), bool))
    assert n >= 3                                                     # two bands and the shaded blob at least
    rings = _edge_rings(dark_lab)
    old = [_old_sharp_edged(dark_lab, lab == i, con, thr) for i in range(1, n + 1)]
    new = [_sharp_edged(dark_lab, lab == i, con, thr, rings) for i in range(1, n + 1)]
    assert new == old
    assert any(old) and not all(old)                                  # both answers occur: the test can fail
    # the whole mask is unchanged with the shared transform
    m = wide_line_mask(g, ridge, "dark", 4.0)
    assert m[100, 65] and m[180, 140] and not m[195, 205]


def test_edge_rings_label_each_ring_pixel_with_its_nearest_area():
    lab = np.zeros((40, 60), np.int32)
    lab[10:20, 5:15] = 1
    lab[10:20, 40:50] = 2
    rows, cols, near = _edge_rings(lab)
    assert set(np.unique(near).tolist()) == {1, 2}
    assert np.all(near[cols < 28] == 1) and np.all(near[cols > 32] == 2)
    d = ndi.distance_transform_edt(lab == 0)[rows, cols]
    assert d.min() >= 2.0 and d.max() <= 4.0


def test_shared_disk_is_opencvs_ellipse_and_used_by_both_techniques():
    from branchnb.leaves import snapping_carry

    for r in (1, 3, 7, 12):
        k = disk(r)
        assert k.shape == (2 * r + 1, 2 * r + 1) and k.dtype == np.uint8
        assert np.array_equal(k, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1)))
        assert np.array_equal(snapping_carry._disk(r), k.astype(bool))
    assert disk(0).shape == (3, 3)
    assert wide_lines._disk is disk
    with pytest.raises(ValueError, match="radius"):
        disk(float("nan"))
    with pytest.raises(ValueError, match="radius"):
        disk("big")
