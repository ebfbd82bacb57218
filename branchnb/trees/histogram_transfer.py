"""Histogram transfer (paper, Sec. "Histogram transfer"): recolour a tree like a reference tree.

Seasonal colour changes (a summer tree turned autumnal, a green crown made
dry) are obtained by matching the colour histogram of a tree to that of a
reference tree, one RGB channel at a time. Only the tree's pixels count: the
transparent background (black after normalisation) would otherwise dominate
both histograms. Each channel value is mapped through the source's cumulative
histogram and the inverse of the reference's (histogram specification, as
``skimage.exposure.match_histograms`` does, but with the histograms of the
opaque pixels only; the mapping is then applied to every pixel that is not
fully transparent, so soft edges follow).
"""

from __future__ import annotations

import numpy as np

from ..core.image import as_rgba
from ..core.validate import Int, Real, checked

__all__ = ["opaque_pixels", "channel_mapping", "histogram_transfer"]


def opaque_pixels(image, *, threshold: float = 0.5, name: str = "image") -> np.ndarray:
    """RGB values ``(P, 3)`` of the pixels whose alpha is at least ``threshold``.

    Parameters
    ----------
    image : (H, W, C) array_like
        Any image :func:`branchnb.core.image.as_rgba` accepts; without an
        alpha channel every pixel is opaque.
    threshold : float
        Smallest alpha of a pixel that counts (default 0.5).
    name : str
        Argument name used in error messages.

    Returns
    -------
    (P, 3) float32 ndarray
        Row-major RGB of the opaque pixels, in [0, 1].

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((2, 2, 4), np.float32); img[0, 0] = (1, 0, 0, 1)
    >>> opaque_pixels(img).tolist()
    [[1.0, 0.0, 0.0]]
    """
    img = as_rgba(image, name=name)
    return img[img[:, :, 3] >= threshold][:, :3]


def channel_mapping(source, reference, levels: int = 256) -> np.ndarray:
    """Lookup table that gives one channel of ``source`` the histogram of ``reference``.

    Parameters
    ----------
    source, reference : (P,) and (Q,) array_like
        Samples of one channel, in [0, 1].
    levels : int
        Source values are grouped into this many levels (8-bit by default).

    Returns
    -------
    (levels,) float ndarray
        ``lut[k]`` is the new value of source level ``k``: the mean of the
        reference's quantile function over the quantile band
        ``[F_s(k-), F_s(k)]`` the level occupies in the source. For
        continuous data (thin bands) this is the classical
        ``F_r^{-1}(F_s(v))``; for a flat-coloured drawing, where one level
        holds a large share of the pixels, it is the mean of the reference
        colours in that share instead of the single value at its upper end
        (which would send e.g. an all-zero blue channel to the reference's
        maximum blue). Levels absent from the source get
        ``F_r^{-1}(F_s(k))``, so the table stays monotone.

    Examples
    --------
    >>> lut = channel_mapping([0.0, 0.0, 1.0, 1.0], [0.2, 0.2, 0.6, 0.6])
    >>> round(float(lut[0]), 3), round(float(lut[255]), 3)
    (0.2, 0.6)
    """
    src = np.asarray(source, dtype=np.float64).ravel()
    ref = np.sort(np.asarray(reference, dtype=np.float64).ravel())
    if src.size == 0 or ref.size == 0:
        raise ValueError("source and reference need at least one sample each")
    lv = _levels(src, levels)
    counts = np.bincount(lv, minlength=levels).astype(np.float64)
    q_hi = np.cumsum(counts) / src.size
    q_lo = q_hi - counts / src.size
    n = ref.size
    q_grid = np.arange(n + 1) / n
    integral = np.concatenate([[0.0], np.cumsum(ref)]) / n   # G(q) = int_0^q F_r^{-1}
    width = q_hi - q_lo
    band_mean = (np.interp(q_hi, q_grid, integral) - np.interp(q_lo, q_grid, integral)) / \
        np.maximum(width, 1e-300)
    at_q = np.interp(q_hi, (np.arange(n) + 0.5) / n, ref)
    return np.where(width > 0, band_mean, at_q)


def _levels(values: np.ndarray, levels: int) -> np.ndarray:
    return np.clip(np.round(values * (levels - 1)), 0, levels - 1).astype(np.int64)


@checked(threshold=Real(0, 1, low_open=True), strength=Real(0, 1), levels=Int(2, 65536))
def histogram_transfer(image, reference, *, threshold: float = 0.5,
                       strength: float = 1.0, levels: int = 256) -> np.ndarray:
    """Match the per-channel colour histograms of a tree to a reference tree.

    Parameters
    ----------
    image : (H, W, 4) array_like
        RGBA tree to recolour (straight alpha).
    reference : (H', W', 4) array_like
        RGBA reference tree (any size).
    threshold : float
        Pixels with alpha below this are transparent and ignored in both
        images (paper: 0.5, the normalisation threshold).
    strength : float
        Blend between the input colours (0) and the matched ones (1).
    levels : int
        Quantisation of the channel values (see :func:`channel_mapping`).

    Returns
    -------
    (H, W, 4) float32 ndarray
        ``image`` with matched colours wherever alpha > 0 (the mapping is
        built from the opaque pixels); alpha and transparent pixels
        unchanged.

    Raises
    ------
    ValueError
        An image without alpha, or without any opaque pixel.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((4, 4, 4), np.float32); a[1:3, 1:3] = (0.2, 0.6, 0.1, 1)
    >>> b = np.zeros((4, 4, 4), np.float32); b[:2] = (0.8, 0.4, 0.1, 1)
    >>> [round(float(c), 2) for c in histogram_transfer(a, b)[1, 1]]
    [0.8, 0.4, 0.1, 1.0]
    """
    img = as_rgba(image, name="image")
    ref = as_rgba(reference, name="reference")
    if not (0.0 <= float(strength) <= 1.0):
        raise ValueError(f"strength must lie in [0, 1], got {strength}")
    if not isinstance(levels, (int, np.integer)) or levels < 2:
        raise ValueError(f"levels must be an int >= 2, got {levels!r}")
    opaque = img[:, :, 3] >= threshold
    if not opaque.any():
        raise ValueError(f"image has no opaque pixel (alpha >= {threshold})")
    ref_px = opaque_pixels(ref, threshold=threshold, name="reference")
    if len(ref_px) == 0:
        raise ValueError(f"reference has no opaque pixel (alpha >= {threshold})")
    src_px = img[opaque][:, :3]
    visible = img[:, :, 3] > 0
    vis_px = img[visible][:, :3]
    matched = np.empty_like(vis_px)
    for c in range(3):
        lut = channel_mapping(src_px[:, c], ref_px[:, c], levels)
        matched[:, c] = lut[_levels(vis_px[:, c], levels)]
    out = img.copy()
    s = float(strength)
    out[visible, :3] = np.clip((1.0 - s) * vis_px + s * matched, 0.0, 1.0)
    return out
