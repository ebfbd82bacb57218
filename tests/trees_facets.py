"""Shared measurement helper of the low-poly tree tests: the crown's flat facet regions."""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi


def facet_regions(img: np.ndarray, crown: np.ndarray, min_px: int) -> tuple[np.ndarray, int]:
    """Label the flat-colour facet regions of a crown.

    Parameters
    ----------
    img : np.ndarray
        HxWx3 or HxWx4 float image in [0, 1].
    crown : np.ndarray
        HxW bool mask of the crown.
    min_px : int
        Smallest connected region of one colour (quantised to 1/64) kept as a facet.

    Returns
    -------
    lab : np.ndarray
        HxW int32 labels 1..n inside ``crown`` (0 outside); pixels of regions smaller than
        ``min_px`` (anti-aliased seams, specks) take the label of the nearest kept region, so the
        borders between labels fall where the facets meet.
    n : int
        Number of facet regions.
    """
    q = np.round(img[..., :3] * 64).astype(np.int64)
    key = np.where(crown, (q[..., 0] * 256 + q[..., 1]) * 256 + q[..., 2], -1)
    lab, n = np.zeros(crown.shape, np.int32), 0
    vals, cnt = np.unique(key[crown], return_counts=True)
    for v in vals[cnt >= min_px]:
        sub, _ = ndi.label(key == v)
        sizes = np.bincount(sub.ravel())
        sizes[0] = 0
        for j in np.flatnonzero(sizes >= min_px):
            n += 1
            lab[sub == j] = n
    if n == 0:
        return lab, 0
    _, (iy, ix) = ndi.distance_transform_edt(lab == 0, return_indices=True)
    return np.where(crown, lab[iy, ix], 0).astype(np.int32), n


def reduce_drawing(rgb: np.ndarray, alpha: np.ndarray, trunk: np.ndarray, size: int, ss: int):
    """A drawing made ``ss`` times too large, reduced to ``size`` (premultiplied area average).

    Parameters
    ----------
    rgb, alpha, trunk : np.ndarray
        The large drawing: HxWx3 colour, HxW coverage, HxW trunk coverage.
    size : int
        Side of the reduced image.
    ss : int
        Supersampling factor the drawing was made at (1: returned as drawn).

    Returns
    -------
    image : np.ndarray
        ``size`` x ``size`` x 4 float32 straight RGBA.
    trunk : np.ndarray
        Its trunk pixels (trunk and alpha both at least 0.5).
    """
    import cv2

    if ss > 1:
        prem = cv2.resize(np.dstack([rgb * alpha[..., None], alpha]), (size, size), interpolation=cv2.INTER_AREA)
        alpha = prem[..., 3]
        rgb = np.clip(prem[..., :3] / np.maximum(alpha, 1e-6)[..., None], 0, 1)
        trunk = cv2.resize(trunk, (size, size), interpolation=cv2.INTER_AREA)
    return np.dstack([rgb, alpha]).astype(np.float32), (trunk >= 0.5) & (alpha >= 0.5)
