"""Steps 1-2 of the ridge snapping (:mod:`branchnb.leaves.snapping`): the layer's contrast direction and ``E_e``.

Split from :mod:`branchnb.leaves.snapping` (unchanged; both names are still importable from there).
"""

from __future__ import annotations

import numpy as np

from ..core.image import as_mask, extend_nearest
from ..core.morphology import _binary_dilation, _binary_erosion

__all__ = ["contrast_direction", "ridge_evidence"]


def contrast_direction(lab, layer, blade) -> np.ndarray:
    """Unit CIELAB direction in which a layer stands out from the blade around it.

    The layer's mean colour minus the mean of the blade pixels within a
    few layer widths of it (not the whole blade: shading and mottling far
    away say nothing about the contrast a vein makes with its own blade).

    Parameters
    ----------
    lab : (H, W, 3) float ndarray
        The training leaf's CIELAB colours.
    layer : (H, W) bool array_like
        The user's layer on it.
    blade : (H, W) bool array_like
        Its blade.

    Returns
    -------
    (3,) float ndarray
        Unit vector; ``(-1, 0, 0)`` (darker) when the layer or the blade
        around it is empty or they do not differ.

    Raises
    ------
    ValueError
        ``lab`` is not ``(H, W, 3)`` or a mask is not ``(H, W)``.
    """
    lab = np.asarray(lab)
    if lab.ndim != 3 or lab.shape[2] != 3:
        raise ValueError(f"lab must be an (H, W, 3) array, got shape {lab.shape}")
    layer = as_mask(layer, shape=lab.shape[:2], name="layer")
    blade = as_mask(blade, shape=lab.shape[:2], name="blade")
    ring = _binary_dilation(layer, iterations=4) & blade & ~layer
    if not ring.any():
        ring = blade & ~layer
    if not ring.any() or not layer.any():
        return np.array([-1.0, 0.0, 0.0])
    d = lab[layer].mean(0) - lab[ring].mean(0)
    n = float(np.linalg.norm(d))
    return d / n if n > 1e-6 else np.array([-1.0, 0.0, 0.0])


def ridge_evidence(lab, blade, direction, width: float, line_length: float = 0.0) -> np.ndarray:
    """``E_e``: ridge response (0..1) of the colours projected on ``direction``.

    Parameters
    ----------
    lab : (H, W, 3) float ndarray
        CIELAB colours (already moved onto the training leaf's statistics).
    blade : (H, W) bool ndarray
        The exemplar's blade.
    direction : (3,) ndarray
        :func:`contrast_direction`.
    width : float
        The layer's typical width in pixels.
    line_length : float
        When at least 3: geometric mean with the best straight-segment mean
        over this many pixels, so long veins keep their response and short
        texture ridges weaken; 0 (default): off.

    Returns
    -------
    (H, W) float32 ndarray
        0 outside the blade and on its outline pixel.
    """
    from ._snapkernels import sato_bright  # skimage.filters.sato without its imports, fewer zero taps
    blade = as_mask(blade, shape=lab.shape[:2], name="blade")
    s = max(0.7, 0.5 * float(width))
    sigmas = [s, max(s, float(width))]
    # Only the blade's pixels are kept: filter its box grown by the two
    # Gaussian passes' reach (the same values there; a padded canvas is 2-5x larger).
    big = max(sigmas)
    reach = 2 * int((8 if big > 1 else 12) * big / np.sqrt(2) + 0.5) + 2
    rows, cols = np.flatnonzero(blade.any(1)), np.flatnonzero(blade.any(0))
    if len(rows):
        y0, y1 = max(0, int(rows[0]) - reach), min(blade.shape[0], int(rows[-1]) + reach + 1)
        x0, x1 = max(0, int(cols[0]) - reach), min(blade.shape[1], int(cols[-1]) + reach + 1)
    else:
        y0, y1, x0, x1 = 0, blade.shape[0], 0, blade.shape[1]
    lab_box = np.asarray(lab)[y0:y1, x0:x1]
    p = (np.asarray(lab_box, np.float32) @ np.asarray(direction, np.float32)).astype(np.float32)
    # Outside the blade the projection continues the nearest blade pixel:
    # the outline is no ridge.
    p = extend_nearest(p, blade[y0:y1, x0:x1])
    r = np.zeros(blade.shape, np.float32)
    r[y0:y1, x0:x1] = sato_bright(p, sigmas)
    inner = _binary_erosion(blade)
    r = np.where(inner, r, 0.0).astype(np.float32)
    if line_length and line_length >= 3:
        # Veins run on: the geometric mean with the best straight-segment
        # mean keeps a vein and weakens the texture's short ridges.
        from .keypoints import _line_average
        r = np.sqrt(r * _line_average(r, int(round(line_length)))[0])
    scale = float(np.percentile(r[inner], 99)) if inner.any() else 0.0
    if scale <= 0:
        return np.zeros(blade.shape, np.float32)
    return np.clip(r / scale, 0.0, 1.0).astype(np.float32)
