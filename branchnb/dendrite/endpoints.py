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

Density = ``importance ** gamma`` where the importance reaches
``threshold``, plus ``floor`` everywhere. Below the threshold a pixel
counts as empty paper and gets no endpoints, so flat backgrounds stay
clean (the dendrite only crosses them to join separate parts); a positive
``floor`` puts a few endpoints there anyway. A weighted centroid can fall
into an empty gap (inside a ring, between two arms): such endpoints are
moved to the nearest pixel of positive density.
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
                     threshold: float = 0.0, mask=None) -> np.ndarray:
    """The stippling density ``importance ** gamma`` (0 below ``threshold``) ``+ floor``,
    0 outside ``mask``.

    Parameters
    ----------
    importance : (H, W) array_like
        Finite, non-negative importance (usually in [0, 1],
        :func:`~branchnb.dendrite.importance.importance_map`).
    gamma : float
        Contrast exponent (> 0): above 1 concentrates endpoints on the most
        important pixels, below 1 spreads them out. 1 by default.
    floor : float
        Density (>= 0) added to every pixel inside ``mask``, including those
        below ``threshold``; 0.02 by default.
    threshold : float
        Importance (>= 0) below which a pixel's ``importance ** gamma`` term
        is 0; 0 (every pixel counts) by default.
    mask : (H, W) bool array_like, optional
        The density is 0 where False; everywhere allowed by default.

    Returns
    -------
    (H, W) float64 ndarray
        The unnormalised density (>= 0).

    Raises
    ------
    ValueError
        If ``importance`` is not a finite non-negative 2-D array, or ``gamma``,
        ``floor`` or ``threshold`` are out of range.

    Examples
    --------
    >>> imp = np.array([[0.0, 0.5], [1.0, 0.1]])
    >>> endpoint_density(imp, threshold=0.2, floor=0.0).tolist()
    [[0.0, 0.5], [1.0, 0.0]]
    """
    imp = _check_importance(importance)
    if not np.isfinite(gamma) or gamma <= 0:
        raise ValueError(f"gamma must be > 0, got {gamma}")
    if not np.isfinite(floor) or floor < 0:
        raise ValueError(f"floor must be >= 0, got {floor}")
    if not np.isfinite(threshold) or threshold < 0:
        raise ValueError(f"threshold must be >= 0, got {threshold}")
    d = np.where(imp >= threshold, imp ** gamma, 0.0) + floor
    if mask is not None:
        d = np.where(as_mask(mask, shape=imp.shape), d, 0.0)
    return d


@checked(importance=Array(ndim=2), n_endpoints=Int(1, MAX_COUNT), gamma=Real(0, 100, low_open=True),
         floor=Real(0, 1), iterations=Int(0, 10_000))
def place_endpoints(importance, n_endpoints: int, *, gamma: float = 1.0, floor: float = 0.02,
                    threshold: float = 0.0, iterations: int = 10, mask=None,
                    rng=None) -> np.ndarray:
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
    threshold : float
        Importance below which a pixel gets no endpoints (unless ``floor > 0``).
    iterations : int
        Lloyd iterations of the stippling.
    mask : (H, W) bool array_like, optional
        Endpoints only where True (e.g. reachable, non-wall pixels).
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed of the initial points; the same seed gives
        the same endpoints.

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
    d = endpoint_density(importance, gamma=gamma, floor=floor, threshold=threshold, mask=mask)
    if not (d > 0).any():
        raise ValueError("the endpoint density is zero everywhere (empty mask, nothing above "
                         "the threshold and no floor)")
    pts = stipple(d, int(n_endpoints), iterations=iterations, rng=rng)
    h, w = d.shape
    pts[:, 0] = np.clip(pts[:, 0], 0, w - 1)
    pts[:, 1] = np.clip(pts[:, 1], 0, h - 1)
    # a centroid may fall into an empty gap of a non-convex region: snap it back
    return _snap_into(pts, d > 0)


def _snap_into(pts: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Move the points ``(x, y)`` (inside the frame) whose rounded pixel misses ``mask`` to its
    nearest pixel, in place; ``mask`` must not be empty. Returns ``pts``."""
    col = np.rint(pts[:, 0]).astype(int)
    row = np.rint(pts[:, 1]).astype(int)
    bad = ~mask[row, col]
    if bad.any():
        from scipy.spatial import cKDTree

        ys, xs = np.nonzero(mask)
        _, j = cKDTree(np.column_stack([xs, ys])).query(pts[bad])
        pts[bad] = np.column_stack([xs[j], ys[j]])
    return pts


@checked(n_endpoints=Int(1, MAX_COUNT))
def random_endpoints(mask, n_endpoints: int, *, rng=None) -> np.ndarray:
    """``n_endpoints`` uniformly random pixels of ``mask`` as (x, y) points (white noise).

    Parameters
    ----------
    mask : (H, W) bool array_like
        Pixels that may hold an endpoint; must have at least one True pixel.
    n_endpoints : int
        Number of endpoints (>= 1). Pixels repeat only when ``mask`` has fewer
        pixels than that.
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed; None draws a fresh seed.

    Returns
    -------
    (n_endpoints, 2) float64 ndarray
        Integer-valued ``(x, y)`` pixel positions.

    Raises
    ------
    ValueError
        If ``mask`` is empty or ``n_endpoints < 1``.

    Examples
    --------
    >>> m = np.zeros((10, 10), bool); m[2:4, 5:8] = True
    >>> pts = random_endpoints(m, 4, rng=0)
    >>> pts.shape, bool(m[pts[:, 1].astype(int), pts[:, 0].astype(int)].all())
    ((4, 2), True)
    """
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
