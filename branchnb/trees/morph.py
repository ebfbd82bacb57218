"""Contour synthesis: convex combinations of shape vectors and the alpha mask they enclose.

Every exemplar's resampled contour ``C_r`` has the same number of points with
the pin points (tree bottom ``B``, trunk tops ``R`` and ``L``) at the same
indices, so contours of different trees correspond point by point. A new
contour is a convex combination of the exemplars' contours,

.. math:: C = \\sum_i w_i C_{r,i}, \\qquad w_i \\ge 0, \\; \\sum_i w_i = 1,

which is the same as combining the mean-subtracted shape vectors ``v_i`` and
placing the result at the combined centroid. Weights come from the user or
from a Dirichlet draw (:func:`dirichlet_weights`).

A combined contour may cross itself where the exemplars' crowns bulge in
different places. :func:`fill_contour` rasterises it with the *non-zero
winding* rule, so a twisted loop still counts as inside (an even-odd fill, or
OpenCV's scan-line fill, would punch holes there).
"""

from __future__ import annotations

import numpy as np

from ..core.image import as_points
from ..core.random import as_rng
from ..core.validate import MAX_COUNT, Array, Choice, Int, Real, Shape, checked, real_array

__all__ = [
    "check_weights",
    "dirichlet_weights",
    "combine_shapes",
    "winding_number",
    "fill_contour",
]


def check_weights(weights, n: int | None = None, *, name: str = "weights",
                  atol: float = 1e-6) -> np.ndarray:
    """Validate convex-combination weights (``w_i >= 0``, ``sum w_i = 1``).

    Parameters
    ----------
    weights : (k,) array_like
        Candidate weights ``w_i``, one per exemplar.
    n : int, optional
        Required number of weights (one per exemplar).
    name : str
        Argument name used in error messages.
    atol : float
        Tolerance on the sum and on negative values (rounding noise).

    Returns
    -------
    (k,) float64 ndarray
        The weights, tiny negatives clipped to 0 and renormalised exactly.

    Raises
    ------
    ValueError
        Not 1-D, wrong length, NaN, a negative weight or a sum other than 1.

    Examples
    --------
    >>> check_weights([0.25, 0.75]).tolist()
    [0.25, 0.75]
    """
    w = real_array(weights, name, allow_empty=True, finite=False)
    if w.ndim != 1 or w.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array, got shape {w.shape}")
    if n is not None and w.size != n:
        raise ValueError(f"{name} needs one weight per exemplar (shapes/exemplars: {n}), got {w.size}")
    if not np.all(np.isfinite(w)):
        raise ValueError(f"{name} contains NaN or infinite values")
    if np.any(w < -atol):
        i = int(np.argmin(w))
        raise ValueError(f"{name} must be >= 0 (convex combination), got {name}[{i}] = {w[i]:.4g}")
    total = float(w.sum())
    if abs(total - 1.0) > atol:
        raise ValueError(f"{name} must sum to 1 (convex combination), got sum {total:.6g}")
    w = np.clip(w, 0.0, None)
    return w / w.sum()


@checked(n=Int(1, MAX_COUNT), concentration=Real(0, 1e6, low_open=True, arrays=True))
def dirichlet_weights(n: int, concentration=1.0, *, rng=None) -> np.ndarray:
    """Random convex weights: a draw from a Dirichlet distribution.

    Parameters
    ----------
    n : int
        Number of weights (>= 1).
    concentration : float or (n,) array_like
        Dirichlet parameters ``alpha`` (> 0). 1 is uniform on the simplex;
        larger values concentrate near the centre (even mixes), smaller
        near the corners (one exemplar dominates); a larger entry favours
        that exemplar.
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the draw; None draws a fresh seed.

    Returns
    -------
    (n,) float64 ndarray
        Weights ``w_i >= 0`` summing to 1 (``[1.0]`` for ``n = 1``).

    Raises
    ------
    ValueError
        If ``n`` is not a positive int or a concentration is not > 0.

    Examples
    --------
    >>> w = dirichlet_weights(3, rng=0)
    >>> bool(abs(w.sum() - 1) < 1e-12 and (w >= 0).all())
    True
    """
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 1:
        raise ValueError(f"n must be a positive int, got {n!r}")
    a = np.broadcast_to(np.asarray(concentration, dtype=np.float64), (n,))
    if not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise ValueError(f"concentration must be > 0, got {concentration!r}")
    if n == 1:
        return np.ones(1)
    return as_rng(rng).dirichlet(a)


@checked(shapes=Array(ndim=(2, 3)), weights=Array(ndim=1))
def combine_shapes(shapes, weights) -> np.ndarray:
    """Convex combination ``sum_i w_i s_i`` of corresponding contours or shape vectors.

    Parameters
    ----------
    shapes : sequence of (N, 2) or (2N,) array_like
        Resampled contours ``C_r`` (or shape vectors ``v``) with the same
        layout.
    weights : (k,) array_like
        Convex weights (validated by :func:`check_weights`).

    Returns
    -------
    ndarray with the layout of one input.

    Examples
    --------
    >>> import numpy as np
    >>> a, b = np.zeros((4, 2)), np.ones((4, 2))
    >>> combine_shapes([a, b], [0.25, 0.75])[0].tolist()
    [0.75, 0.75]
    """
    arrs = [np.asarray(s, dtype=np.float64) for s in shapes]
    if not arrs:
        raise ValueError("shapes is empty: need at least one exemplar")
    if any(a.shape != arrs[0].shape for a in arrs):
        raise ValueError(f"shapes must all have the same shape, got {[a.shape for a in arrs]}")
    w = check_weights(weights, len(arrs))
    return np.tensordot(w, np.stack(arrs), axes=1)


def winding_number(polygon, shape: tuple[int, int]) -> np.ndarray:
    """Winding number of a closed polygon around every pixel centre.

    Parameters
    ----------
    polygon : (K, 2) array_like
        Vertices (x, y); the closing edge back to the first vertex is implied.
    shape : (H, W)
        Size of the pixel grid; pixel ``(row, col)`` has its centre at
        ``(x, y) = (col, row)``.

    Returns
    -------
    (H, W) int32 ndarray
        Signed number of turns of the polygon around each pixel centre:
        +1 inside a loop that runs counter-clockwise on screen (y down,
        like the tree contours), -1 inside a clockwise one.

    Notes
    -----
    Scan-line accumulation, vectorised over edge/row crossings: every edge
    crossing row ``y`` (half-open in y, so vertices are counted once) adds
    its direction (+1 downwards, -1 upwards) to every pixel right of the
    crossing; a cumulative sum along the rows turns these into winding
    numbers. Cost: O(perimeter in rows + H W).

    Examples
    --------
    >>> w = winding_number([(1, 1), (1, 4), (4, 4), (4, 1)], (6, 6))  # down, right, up
    >>> int(w[2, 2]), int(w[0, 0])
    (1, 0)
    """
    p = as_points(polygon, name="polygon", min_points=3)
    h, w = int(shape[0]), int(shape[1])
    q = np.roll(p, -1, axis=0)
    y0, y1 = p[:, 1], q[:, 1]
    x0, x1 = p[:, 0], q[:, 0]
    moving = y0 != y1
    y0, y1, x0, x1 = y0[moving], y1[moving], x0[moving], x1[moving]
    direction = np.where(y1 > y0, 1, -1).astype(np.int32)
    ylo, yhi = np.minimum(y0, y1), np.maximum(y0, y1)
    r_first = np.maximum(np.ceil(ylo), 0).astype(np.int64)
    r_end = np.minimum(np.ceil(yhi), h).astype(np.int64)  # exclusive
    counts = np.maximum(r_end - r_first, 0)
    diff = np.zeros((h, w + 1), np.int32)
    total = int(counts.sum())
    if total:
        edge = np.repeat(np.arange(len(counts)), counts)
        start = np.repeat(np.cumsum(counts) - counts, counts)
        rows = r_first[edge] + (np.arange(total) - start)
        t = (rows - y0[edge]) / (y1[edge] - y0[edge])
        xc = x0[edge] + t * (x1[edge] - x0[edge])
        cols = np.clip(np.floor(xc).astype(np.int64) + 1, 0, w)
        np.add.at(diff, (rows, cols), direction[edge])
    return np.cumsum(diff[:, :w], axis=1, dtype=np.int32)


@checked(polygon=Array(ndim=2), shape=Shape(), rule=Choice("nonzero", "evenodd"))
def fill_contour(polygon, shape: tuple[int, int], *, rule: str = "nonzero") -> np.ndarray:
    """Rasterise the region enclosed by a (possibly self-intersecting) contour.

    Parameters
    ----------
    polygon : (K, 2) array_like
        Closed contour, (x, y) pixels.
    shape : (H, W)
        Output size.
    rule : {"nonzero", "evenodd"}
        Fill rule. ``"nonzero"`` (default) fills every pixel the contour
        winds around, so the loops a self-intersecting combined contour
        makes stay filled; ``"evenodd"`` alternates.

    Returns
    -------
    (H, W) bool ndarray
        True where the pixel centre is inside.

    Examples
    --------
    >>> import numpy as np
    >>> twice = [(1, 1), (8, 1), (8, 8), (1, 8)] * 2   # a loop run around twice
    >>> int(fill_contour(twice, (10, 10)).sum()), int(fill_contour(twice, (10, 10), rule="evenodd").sum())
    (49, 0)
    """
    if rule not in ("nonzero", "evenodd"):
        raise ValueError(f"rule must be 'nonzero' or 'evenodd', got {rule!r}")
    wn = winding_number(polygon, shape)
    return wn != 0 if rule == "nonzero" else (wn % 2) != 0
