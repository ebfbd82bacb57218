"""Image comparison figures used to check results: PSNR on a mask, IoU of masks."""

from __future__ import annotations

import numpy as np

from .image import as_mask
from .validate import check_real, real_array

__all__ = ["psnr", "iou"]


def psnr(a, b, mask=None, *, data_range: float = 1.0) -> float:
    """Peak signal-to-noise ratio of ``a`` against ``b`` (dB), optionally on ``mask`` only.

    Parameters
    ----------
    a, b : array_like, same shape (H, W) or (H, W, C)
        The image tested and the reference, in the units of ``data_range``.
    mask : (H, W) bool array_like, optional
        Pixels to compare (all by default).
    data_range : float
        Peak value (1 for the project's float images).

    Returns
    -------
    float
        ``inf`` for identical inputs.

    Examples
    --------
    >>> import numpy as np
    >>> round(psnr(np.zeros((4, 4)), np.full((4, 4), 0.1)), 6)
    20.0
    """
    a = real_array(a, "a", ndim=(2, 3))
    b = real_array(b, "b", ndim=(2, 3))
    data_range = check_real(data_range, "data_range", 0, low_open=True)
    if a.shape != b.shape:
        raise ValueError(f"a and b must have the same shape, got {a.shape} and {b.shape}")
    if mask is not None:
        mask = as_mask(mask, shape=a.shape[:2])
        if not mask.any():
            raise ValueError("mask selects no pixel")
        a, b = a[mask], b[mask]
    # Scaled so that huge values or ranges neither overflow nor underflow.
    scale = max(float(np.abs(a).max()), float(np.abs(b).max()), 1e-300)
    mse_scaled = float(np.mean(((a / scale) - (b / scale)) ** 2))
    if mse_scaled == 0:
        return float("inf")
    return float(20 * np.log10(data_range) - 20 * np.log10(scale) - 10 * np.log10(mse_scaled))


def iou(a, b) -> float:
    """Intersection over union of two boolean masks (1 for two empty masks).

    Parameters
    ----------
    a, b : (H, W) array_like
        Masks of the same shape (nonzero is True).

    Returns
    -------
    float
        ``|a & b| / |a | b|`` in [0, 1].

    Raises
    ------
    ValueError
        If the masks are not 2-D or differ in shape.

    Examples
    --------
    >>> import numpy as np
    >>> iou(np.eye(2, dtype=bool), np.ones((2, 2), bool))
    0.5
    """
    a = as_mask(a, name="a")
    b = as_mask(b, shape=a.shape, name="b")
    union = int((a | b).sum())
    return 1.0 if union == 0 else float((a & b).sum() / union)
