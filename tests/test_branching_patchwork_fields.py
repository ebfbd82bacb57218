"""Patchwork grounds laid field by field, without halos beside the rivers or a grid of seams (issue 23)."""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi
from test_branching_patchwork import PALETTE, _fields, _river

from branchnb.branching import synthesize_image
from branchnb.branching.patchwork import paste_fields
from branchnb.core.structure import Branch, Structure


def _labels(img):
    sm = cv2.medianBlur(np.ascontiguousarray(img.astype(np.float32)), 5)
    return np.argmin(np.linalg.norm(sm[..., None, :] - PALETTE[None, None], axis=-1), -1)


def _axis_aligned(img, ground, run=12):
    """Share of the ground's colour edges on straight vertical or horizontal runs of ``run`` pixels."""
    lab = _labels(img)
    eh = (lab[:, 1:] != lab[:, :-1]) & ground[:, 1:] & ground[:, :-1]
    ev = (lab[1:] != lab[:-1]) & ground[1:] & ground[:-1]
    straight = (ndi.binary_opening(eh, np.ones((run, 1), bool)).sum()
                + ndi.binary_opening(ev, np.ones((1, run), bool)).sum())
    return straight / max(eh.sum() + ev.sum(), 1)


def _halo(img, d, r):
    """Share of a band beside the river (r+2..r+8 px) whose field differs from the ground 14-22 px off."""
    lab = _labels(img)
    band = (d >= r + 2) & (d <= r + 8)
    ring = (d >= r + 14) & (d <= r + 22)
    _, (iy, ix) = ndi.distance_transform_edt(~ring, return_indices=True)
    return float(np.mean(lab[band] != lab[iy[band], ix[band]]))


def _dist(pts, n):
    m = np.ones((n, n), np.uint8)
    cv2.polylines(m, [np.int32(np.round(pts * 4))], False, 0, 1, cv2.LINE_8, shift=2)
    return ndi.distance_transform_edt(m)


@pytest.mark.parametrize("n, seed", [(128, 0), (300, 1)])
def test_paste_fields_lays_whole_fields(n, seed):
    ex = _fields(256, seed, cells=21)     # an example larger or smaller than the output
    canvas = np.zeros((n, n, 3), np.float32)
    covered = np.zeros((n, n), bool)
    covered[: n // 4] = True               # a strip already drawn stays as it is
    canvas[covered] = 0.5
    filled, source = paste_fields(canvas, covered, ex, np.zeros((256, 256), bool), rng=seed)
    assert covered.all() and filled.sum() == n * n - n * (n // 4)
    assert np.all(canvas[: n // 4] == 0.5)
    sx, sy = source[filled][:, 0].astype(int), source[filled][:, 1].astype(int)
    assert np.array_equal(canvas[filled], ex[sy, sx])     # every pixel is the example's own
    ground = np.zeros((n, n), bool)
    ground[n // 4 + 2:] = True
    # the example's Voronoi fields: 3-13 % of their edges axis-aligned; square quilting patches 31-40 %
    assert _axis_aligned(canvas, ground) < 0.1


def test_paste_fields_rejects_mismatched_shapes():
    with pytest.raises(ValueError, match="forbidden"):
        paste_fields(np.zeros((10, 10, 3), np.float32), np.zeros((10, 10), bool), np.zeros((12, 12, 3)),
                     np.zeros((10, 10), bool))


def test_river_over_fields_without_halo_or_grid():
    n, width = 256, 9
    t = np.linspace(0, 1, 60)
    src = np.stack([n * (0.45 + 0.1 * np.sin(3 * t + 1)), -2 + (n + 4) * t], 1)
    tgt = np.stack([-2 + (n + 4) * t, n * (0.5 + 0.12 * np.sin(2.5 * t + 1))], 1)
    img = _river(_fields(n, 1, cells=21), src, width, 1)
    inside = lambda p: p[(p[:, 0] >= 0) & (p[:, 0] <= n - 1) & (p[:, 1] >= 0) & (p[:, 1] <= n - 1)]  # noqa: E731
    S = Structure([Branch(inside(src), width / 2)], image_shape=(n, n))
    T = Structure([Branch(inside(tgt), width / 2)], image_shape=(n, n))
    out = synthesize_image(img, S, T, rng=0).image[..., :3]
    d_s, d_t = _dist(src, n), _dist(tgt, n)
    # fragments carried their own field beside the river: 43 % of the band unlike the ground beyond
    # it, against 18 % in the example
    assert _halo(out, d_t, width / 2) <= _halo(img, d_s, width / 2) + 0.12
    # square quilting patches met along a grid: 33 % of the colour edges axis-aligned (example 3 %)
    assert _axis_aligned(out, d_t > width / 2 + 3) < 0.15
    # the river keeps its colour on the target's centre line
    centre = out[np.round(tgt[2:-2, 1]).astype(int).clip(0, n - 1), np.round(tgt[2:-2, 0]).astype(int).clip(0, n - 1)]
    assert np.linalg.norm(np.median(centre, axis=0) - [0.32, 0.42, 0.5]) < 0.06
