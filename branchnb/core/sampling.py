"""Point placement driven by a density: weighted Voronoi stippling.

Secord's weighted Voronoi stippling (Lloyd relaxation where each cell's
centroid is weighted by the density) puts more points where the density
is high while keeping them evenly spaced (blue noise). A uniform density
gives plain blue-noise samples of a region.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .random import as_rng
from .validate import MAX_COUNT, MAX_ITERATIONS, Int, checked, real_array

__all__ = ["stipple"]


@checked(n_points=Int(1, MAX_COUNT), iterations=Int(0, MAX_ITERATIONS))
def stipple(density, n_points: int, *, iterations: int = 20, rng=None) -> np.ndarray:
    """Place ``n_points`` by weighted Voronoi stippling of ``density``.

    Parameters
    ----------
    density : (H, W) array_like
        Non-negative weights; points only land where it is > 0.
    n_points : int
        Number of points, >= 1.
    iterations : int
        Lloyd iterations (0 returns the initial density-proportional draw).
    rng : {numpy.random.Generator, int}, optional
        Seed or generator for the initial draw (None: not reproducible).

    Returns
    -------
    points : (n_points, 2) float ndarray of (x, y)

    References
    ----------
    A. Secord, "Weighted Voronoi Stippling", NPAR 2002.

    Examples
    --------
    >>> import numpy as np
    >>> pts = stipple(np.ones((32, 32)), 16, rng=0)
    >>> pts.shape
    (16, 2)
    """
    d = real_array(density, "density", allow_empty=True, finite=False)
    if d.ndim != 2 or d.size == 0:
        raise ValueError(f"density must be a non-empty 2-D array, got shape {d.shape}")
    if not np.all(np.isfinite(d)) or (d < 0).any():
        raise ValueError("density must be finite and non-negative")
    if not isinstance(n_points, (int, np.integer)) or isinstance(n_points, bool) or n_points < 1:
        raise ValueError(f"n_points must be a positive int, got {n_points!r}")
    if iterations < 0:
        raise ValueError(f"iterations must be >= 0, got {iterations}")
    rng = as_rng(rng)
    flat = np.flatnonzero(d > 0)
    if flat.size == 0:
        raise ValueError("density is zero everywhere: no place for points")
    w = d.ravel()[flat]
    ys, xs = np.unravel_index(flat, d.shape)
    pix = np.column_stack([xs, ys]).astype(np.float64)
    pick = rng.choice(flat.size, size=n_points, replace=flat.size < n_points, p=w / w.sum())
    pts = pix[pick] + rng.uniform(-0.5, 0.5, (n_points, 2))
    for _ in range(iterations):
        # One thread: query threads (workers=-1) could outlive a KeyboardInterrupt and crash the kernel.
        _, owner = cKDTree(pts).query(pix)
        mass = np.bincount(owner, weights=w, minlength=n_points)
        cx = np.bincount(owner, weights=w * pix[:, 0], minlength=n_points)
        cy = np.bincount(owner, weights=w * pix[:, 1], minlength=n_points)
        has = mass > 0
        pts[has, 0] = cx[has] / mass[has]
        pts[has, 1] = cy[has] / mass[has]
    return pts
