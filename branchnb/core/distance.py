"""Euclidean distance transform of a mask: OpenCV's exact transform with SciPy's semantics."""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

__all__ = ["edt", "edt_boxed"]


def edt(mask) -> np.ndarray:
    """Distance (float32) of every True pixel of ``mask`` to the nearest False one (0 on False).

    The values of ``scipy.ndimage.distance_transform_edt(mask)`` cast to
    float32, exactly (OpenCV's ``DIST_MASK_PRECISE`` is the exact Euclidean
    transform, Felzenszwalb and Huttenlocher's, rounded here to the root of
    an integer squared distance), about four times faster on a 1000 x 1000
    mask. A mask without a False pixel goes to SciPy
    (OpenCV has no background to measure from). For the nearest pixel's
    indices use SciPy's ``return_indices``.

    Parameters
    ----------
    mask : (H, W) array_like of bool
        The object (True) whose pixels get their distance to the background (False).

    Returns
    -------
    (H, W) float32 ndarray

    Raises
    ------
    ValueError
        If ``mask`` is not two-dimensional.

    Examples
    --------
    >>> m = np.ones((3, 5), bool); m[1, 0] = False
    >>> edt(m)[1].tolist()
    [0.0, 1.0, 2.0, 3.0, 4.0]
    """
    m = np.asarray(mask, bool)
    if m.ndim != 2:
        raise ValueError(f"mask must be a 2-D array, got {m.ndim} dimensions")
    if m.all() or min(m.shape) == 0:
        return ndi.distance_transform_edt(m).astype(np.float32)
    d = cv2.distanceTransform(np.ascontiguousarray(m).view(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    if float(d.max()) > _EXACT_UP_TO:
        return ndi.distance_transform_edt(m).astype(np.float32)
    # OpenCV's float32 sums differ from the exact distance by an ulp, and by
    # where the mask is cropped; a squared distance is an integer: rounded,
    # its root is SciPy's value (float32), on any crop.
    d64 = d.astype(np.float64)
    return np.sqrt(np.rint(d64 * d64)).astype(np.float32)


#: Up to this distance (px) a float32 distance squared lies within 0.5 of its integer.
_EXACT_UP_TO = 1500.0


def edt_boxed(mask) -> np.ndarray:
    """:func:`edt` computed on the True pixels' box grown by 1 px only (the same values).

    Every True pixel's nearest False one lies within that box: its ring
    is all False (or the image's edge, which is no background in either).
    Much faster than :func:`edt` for a small object on a large canvas.

    Parameters
    ----------
    mask : (H, W) array_like of bool
        The object (True) whose pixels get their distance to the background (False).

    Returns
    -------
    (H, W) float32 ndarray

    Raises
    ------
    ValueError
        If ``mask`` is not two-dimensional.

    Examples
    --------
    >>> m = np.zeros((8, 9), bool); m[2:5, 3:8] = True
    >>> bool(np.array_equal(edt_boxed(m), edt(m)))
    True
    """
    m = np.asarray(mask, bool)
    if m.ndim != 2:
        raise ValueError(f"mask must be a 2-D array, got {m.ndim} dimensions")
    rows, cols = np.flatnonzero(m.any(axis=1)), np.flatnonzero(m.any(axis=0))
    out = np.zeros(m.shape, np.float32)
    if not len(rows):
        return out
    box = (slice(max(rows[0] - 1, 0), rows[-1] + 2), slice(max(cols[0] - 1, 0), cols[-1] + 2))
    out[box] = edt(m[box])
    return out
