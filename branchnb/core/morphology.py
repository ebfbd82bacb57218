"""Binary morphology with OpenCV's speed and SciPy's semantics."""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

__all__ = ["disk", "fill_holes"]


def disk(radius: int) -> np.ndarray:
    """A disk-shaped structuring element of ``radius`` px: OpenCV's elliptic kernel, ``(2r+1, 2r+1)`` uint8.

    One helper for every technique that opens, closes or dilates by a disk
    with OpenCV (which wants a numeric kernel; use ``disk(r).astype(bool)``
    for SciPy or NumPy masks). A radius under 1 gives the 3 x 3 disk.

    Parameters
    ----------
    radius : int
        Radius in pixels (rounded down to an integer, at least 1).

    Returns
    -------
    (2r+1, 2r+1) uint8 ndarray
        1 inside the disk, 0 outside.

    Raises
    ------
    ValueError
        If ``radius`` is not a finite number.

    Examples
    --------
    >>> int(disk(2).sum()), disk(0).shape
    (17, (3, 3))
    """
    try:
        r = float(radius)
    except (TypeError, ValueError):
        raise ValueError(f"radius must be a finite number, got {radius!r}") from None
    if not np.isfinite(r):
        raise ValueError(f"radius must be a finite number, got {radius!r}")
    r = max(int(r), 1)
    return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))


def fill_holes(mask) -> np.ndarray:
    """``mask`` with every hole filled: ``scipy.ndimage.binary_fill_holes(mask)``, exactly.

    A hole is a component of False pixels, 4-connected (SciPy's default
    structure), that does not reach the image's border. One OpenCV flood
    fill from a one-pixel frame of background round the mask marks the
    outside; everything else is the filled mask. About 10-20 times faster
    than SciPy's iterated dilation on a 1000 x 1000 leaf. Arrays that are
    not two-dimensional, or empty, go to SciPy.

    Parameters
    ----------
    mask : (H, W) array_like of bool
        The object (True).

    Returns
    -------
    (H, W) bool ndarray
        A new array; ``mask`` is not modified.

    Examples
    --------
    >>> m = np.zeros((5, 5), bool); m[1:4, 1:4] = True; m[2, 2] = False
    >>> bool(fill_holes(m)[2, 2]), int(fill_holes(m).sum())
    (True, 9)
    """
    m = np.asarray(mask, bool)
    if m.ndim != 2 or m.size == 0:
        return ndi.binary_fill_holes(m)
    h, w = m.shape
    img = np.ones((h + 2, w + 2), np.uint8)
    img[1:-1, 1:-1] = ~m
    cv2.floodFill(img, None, (0, 0), 2, loDiff=0, upDiff=0, flags=4)
    return img[1:-1, 1:-1] != 2


_CROSS = np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], np.uint8)


def _cv_kernel(structure):
    """The structure as an OpenCV kernel, or None where OpenCV's result would not be SciPy's."""
    if structure is None:
        return _CROSS
    s = np.asarray(structure)
    # SciPy dilates by the reflected structure and centres it at size // 2: the
    # same as OpenCV's anchor only for odd, point-symmetric structures.
    if s.ndim != 2 or s.shape[0] % 2 == 0 or s.shape[1] % 2 == 0 or not np.array_equal(s, s[::-1, ::-1]):
        return None
    return (s != 0).astype(np.uint8)


def _binary_dilation(mask, structure=None, iterations: int = 1) -> np.ndarray:
    """``scipy.ndimage.binary_dilation(mask, structure, iterations)``, exactly, by OpenCV (~20x faster at 1 MP).

    The outside of the image is False (SciPy's ``border_value=0``). Other
    cases (not 2-D, ``iterations < 1``, an even or asymmetric structure) go
    to SciPy.

    >>> m = np.zeros((5, 5), bool); m[2, 2] = True
    >>> int(_binary_dilation(m).sum()), int(_binary_dilation(m, iterations=2).sum())
    (5, 13)
    """
    m = np.asarray(mask, bool)
    k = _cv_kernel(structure)
    if m.ndim != 2 or m.size == 0 or k is None or int(iterations) < 1:
        return ndi.binary_dilation(m, structure=structure, iterations=iterations)
    out = cv2.dilate(m.view(np.uint8), k, iterations=int(iterations), borderType=cv2.BORDER_CONSTANT,
                     borderValue=0)
    return out.astype(bool)


def _binary_erosion(mask, structure=None, iterations: int = 1) -> np.ndarray:
    """``scipy.ndimage.binary_erosion(mask, structure, iterations)``, exactly, by OpenCV.

    The outside of the image is False, so the image's border erodes (SciPy's
    ``border_value=0``; OpenCV's own default would not erode it).

    >>> m = np.ones((5, 5), bool)
    >>> int(_binary_erosion(m).sum())
    9
    """
    m = np.asarray(mask, bool)
    k = _cv_kernel(structure)
    if m.ndim != 2 or m.size == 0 or k is None or int(iterations) < 1:
        return ndi.binary_erosion(m, structure=structure, iterations=iterations)
    out = cv2.erode(m.view(np.uint8), k, iterations=int(iterations), borderType=cv2.BORDER_CONSTANT,
                    borderValue=0)
    return out.astype(bool)


def _binary_opening(mask, structure=None) -> np.ndarray:
    """``scipy.ndimage.binary_opening(mask, structure)``, exactly (erosion then dilation, outside False).

    >>> m = np.zeros((6, 6), bool); m[1:4, 1:4] = True; m[5, 5] = True
    >>> int(_binary_opening(m, np.ones((3, 3))).sum())
    9
    """
    return _binary_dilation(_binary_erosion(mask, structure), structure)
