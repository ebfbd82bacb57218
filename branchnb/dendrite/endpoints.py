"""Endpoint placement (paper, section 5).

Endpoints decide where the dendrite reaches. They should be dense where
the importance is high and evenly spaced everywhere (blue noise), so that
the strokes render tone and detail rather than clumps.

**Choice of method.** The paper places them with a stippling method; we
use weighted Voronoi stippling (Secord 2002; ``branchnb.core.sampling.stipple``,
Lloyd relaxation with density-weighted centroids) on the importance map,
rather than the graph-distance stippling of Mould (2007) that the paper
cites. Both give blue-noise points whose density follows importance;
the graph method additionally lines stipples up along edges, an effect
our importance map already produces by weighting the gradient 3x. Voronoi
stippling is vectorised, reproducible from ``rng`` and shared with other
techniques of the package.

Density = ``importance ** gamma + floor``: the small ``floor`` keeps a few
endpoints in empty (white) regions, and makes a constant image give
uniformly spread endpoints instead of an error.
"""

from __future__ import annotations

import numpy as np

from ..core.image import as_mask
from ..core.random import as_rng
from ..core.sampling import stipple
from ..core.validate import MAX_COUNT, Array, Int, Real, checked

__all__ = ["endpoint_density", "place_endpoints", "random_endpoints"]


def _check_importance(importance) -> np.ndarray:
    imp = np.asarray(importance, dtype=np.float64)
    if imp.ndim != 2 or imp.size == 0:
        raise ValueError(f"importance must be a non-empty (H, W) array, got shape {imp.shape}")
    if not np.all(np.isfinite(imp)) or (imp < 0).any():
        raise ValueError("importance must be finite and >= 0")
    return imp


def endpoint_density(importance, *, gamma: float = 1.0, floor: float = 0.02,
                     mask=None) -> np.ndarray:
    """The stippling density ``importance ** gamma + floor`` (0 outside ``mask``)."""
    imp = _check_importance(importance)
    if not np.isfinite(gamma) or gamma <= 0:
        raise ValueError(f"gamma must be > 0, got {gamma}")
    if not np.isfinite(floor) or floor < 0:
        raise ValueError(f"floor must be >= 0, got {floor}")
    d = imp ** gamma + floor
    if mask is not None:
        d = np.where(as_mask(mask, shape=imp.shape), d, 0.0)
    return d


@checked(importance=Array(ndim=2), n_endpoints=Int(1, MAX_COUNT), gamma=Real(0, 100, low_open=True),
         floor=Real(0, 1), iterations=Int(0, 10_000))
def place_endpoints(importance, n_endpoints: int, *, gamma: float = 1.0, floor: float = 0.02,
                    iterations: int = 10, mask=None, rng=None) -> np.ndarray:
    """Blue-noise endpoints whose density follows the importance map.

    Parameters
    ----------
    importance : (H, W) array_like
        Non-negative importance (e.g. :func:`~branchnb.dendrite.importance.importance_map`).
    n_endpoints : int
        Number of endpoints (>= 1); the paper's stylizations use 2,000 - 3,800.
    gamma : float
        Contrast of the density (``importance ** gamma``).
    floor : float
        Density added everywhere (see the module docstring).
    iterations : int
        Lloyd iterations of the stippling.
    mask : (H, W) bool array_like, optional
        Endpoints only where True (e.g. reachable, non-wall pixels).
    rng : {numpy.random.Generator, int}, optional

    Returns
    -------
    (n_endpoints, 2) float64 array of (x, y) pixel positions

    Raises
    ------
    ValueError
        ``n_endpoints < 1``, or a density that is zero everywhere.

    Examples
    --------
    >>> imp = np.zeros((40, 40)); imp[:, :20] = 1.0
    >>> pts = place_endpoints(imp, 50, rng=0)
    >>> pts.shape, bool((pts[:, 0] < 20).mean() > 0.8)
    ((50, 2), True)
    """
    if isinstance(n_endpoints, bool) or not isinstance(n_endpoints, (int, np.integer)):
        raise TypeError(f"n_endpoints must be an int, got {n_endpoints!r}")
    if n_endpoints < 1:
        raise ValueError(f"n_endpoints must be >= 1, got {n_endpoints}")
    d = endpoint_density(importance, gamma=gamma, floor=floor, mask=mask)
    if not (d > 0).any():
        raise ValueError("the endpoint density is zero everywhere (empty mask and no floor)")
    pts = stipple(d, int(n_endpoints), iterations=iterations, rng=rng)
    h, w = d.shape
    pts[:, 0] = np.clip(pts[:, 0], 0, w - 1)
    pts[:, 1] = np.clip(pts[:, 1], 0, h - 1)
    if mask is not None:  # a centroid may fall outside a non-convex mask: snap it back
        m = as_mask(mask, shape=d.shape) & (d > 0)
        ys, xs = np.nonzero(m)
        col = np.rint(pts[:, 0]).astype(int)
        row = np.rint(pts[:, 1]).astype(int)
        bad = ~m[row, col]
        if bad.any():
            from scipy.spatial import cKDTree

            _, j = cKDTree(np.column_stack([xs, ys])).query(pts[bad])
            pts[bad] = np.column_stack([xs[j], ys[j]])
    return pts


@checked(n_endpoints=Int(1, MAX_COUNT))
def random_endpoints(mask, n_endpoints: int, *, rng=None) -> np.ndarray:
    """``n_endpoints`` uniformly random pixels of ``mask`` as (x, y) points (white noise)."""
    m = as_mask(mask)
    if isinstance(n_endpoints, bool) or not isinstance(n_endpoints, (int, np.integer)):
        raise TypeError(f"n_endpoints must be an int, got {n_endpoints!r}")
    if n_endpoints < 1:
        raise ValueError(f"n_endpoints must be >= 1, got {n_endpoints}")
    ys, xs = np.nonzero(m)
    if xs.size == 0:
        raise ValueError("mask is empty: no place for endpoints")
    pick = as_rng(rng).choice(xs.size, size=int(n_endpoints), replace=xs.size < n_endpoints)
    return np.column_stack([xs[pick], ys[pick]]).astype(np.float64)
