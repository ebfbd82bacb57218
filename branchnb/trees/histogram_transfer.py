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

__all__ = ["opaque_pixels", "channel_mapping", "histogram_transfer"]


def opaque_pixels(image, *, threshold: float = 0.5, name: str = "image") -> np.ndarray:
    """RGB values ``(P, 3)`` of the pixels whose alpha is at least ``threshold``.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((2, 2, 4), np.float32); img[0, 0] = (1, 0, 0, 1)
    >>> opaque_pixels(img).tolist()
    [[1.0, 0.0, 0.0]]
    """
    img = as_rgba(image, name=name)
    return img[img[:, :, 3] >= threshold][:, :3]


def channel_mapping(source, reference) -> tuple[np.ndarray, np.ndarray]:
    """Monotone map of one channel's values so their histogram matches ``reference``'s.

    Parameters
    ----------
    source, reference : (P,) and (Q,) array_like
        Samples of one channel.

    Returns
    -------
    values, mapped : (U,) ndarrays
        The distinct source values and their images: a source value at
        quantile ``F_s(v)`` goes to the reference value at the same
        quantile, ``F_r^{-1}(F_s(v))`` (linear interpolation in between).
        Apply it with ``np.interp(x, values, mapped)``.

    Examples
    --------
    >>> v, m = channel_mapping([0.0, 0.0, 1.0, 1.0], [0.2, 0.2, 0.6, 0.6])
    >>> v.tolist(), m.tolist()
    ([0.0, 1.0], [0.2, 0.6])
    """
    src = np.asarray(source, dtype=np.float64).ravel()
    ref = np.asarray(reference, dtype=np.float64).ravel()
    if src.size == 0 or ref.size == 0:
        raise ValueError("source and reference need at least one sample each")
    sv, sc = np.unique(src, return_counts=True)
    rv, rc = np.unique(ref, return_counts=True)
    sq = np.cumsum(sc) / src.size
    rq = np.cumsum(rc) / ref.size
    return sv, np.interp(sq, rq, rv)


def histogram_transfer(image, reference, *, threshold: float = 0.5,
                       strength: float = 1.0) -> np.ndarray:
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
        values, mapped = channel_mapping(src_px[:, c], ref_px[:, c])
        matched[:, c] = np.interp(vis_px[:, c], values, mapped)
    out = img.copy()
    s = float(strength)
    out[visible, :3] = np.clip((1.0 - s) * vis_px + s * matched, 0.0, 1.0)
    return out
