"""Convex weight sliders: moving one weight rescales the others so they still sum to 1."""

from __future__ import annotations

import numpy as np

__all__ = ["convex_update"]


def convex_update(weights, index: int, value: float) -> np.ndarray:
    """Set ``weights[index] = value`` and rescale the others so the sum stays 1.

    The others keep their proportions; if they are all zero they share
    ``1 - value`` equally.

    Parameters
    ----------
    weights : (K,) array_like
        Convex weights (>= 0, summing to 1), one per mixed tree.
    index : int
        The weight that is set (the slider moved).
    value : float
        Its new value, clipped to [0, 1]. With one tree the result is ``[1]``.

    Returns
    -------
    (K,) float ndarray
        A new array summing to 1.

    Examples
    --------
    >>> convex_update([0.5, 0.3, 0.2], 0, 0.8).round(3).tolist()
    [0.8, 0.12, 0.08]
    >>> convex_update([1.0, 0.0, 0.0], 0, 0.4).round(3).tolist()
    [0.4, 0.3, 0.3]
    """
    w = np.asarray(weights, dtype=np.float64).copy()
    k = len(w)
    v = float(np.clip(value, 0.0, 1.0))
    if k == 1:
        return np.ones(1)
    w[index] = 0.0
    rest = w.sum()
    w = w * ((1.0 - v) / rest) if rest > 1e-12 else np.full(k, (1.0 - v) / (k - 1))
    w[index] = v
    return w
