"""Smooth displacement field: removing the shape error left by the rigid alignment.

After the rigid alignment ``x -> R x + t`` of a source fragment, its
skeleton lands at ``R p_j + t`` instead of on the target skeleton ``q_j``.
A displacement field ``u`` over the fragment with ``u(q_j) = q_j - (R p_j +
t)`` and minimal discrete bi-Laplacian energy ``||L u||^2`` bends the
fragment so that its skeleton (and, with thickness constraints, its
edges) lies exactly on the target's. The field is the solution of one
sparse linear system per fragment; solving it on a coarser grid (step
``g`` pixels) and interpolating is accurate because the field is smooth.
"""

from __future__ import annotations

from functools import lru_cache

import numba
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from ..core.poisson import banded_spd_solve, grid_laplacian

__all__ = ["displacement_field", "backward_map"]


#: Largest n * band^2 solved by banded Cholesky (else sparse LU, faster on the widest windows).
_BANDED_MAX_WORK = 1e7


@lru_cache(maxsize=64)
def _bilaplacian(gh: int, gw: int) -> sp.csr_matrix:
    L, _ = grid_laplacian(np.ones((gh, gw), bool))
    return (L.T @ L).tocsr()


@lru_cache(maxsize=64)
def _bilaplacian_band(gh: int, gw: int) -> np.ndarray:
    """``L^T L`` of a ``gh x gw`` node grid in upper band storage (band ``2 gw``, row-major nodes)."""
    K = _bilaplacian(gh, gw).tocoo()
    n = gh * gw
    u = min(2 * gw, n - 1)
    up = K.row <= K.col
    ab = np.zeros((u + 1, n))
    ab[u + K.row[up] - K.col[up], K.col[up]] = K.data[up]
    ab.flags.writeable = False
    return ab


@lru_cache(maxsize=128)
def _interpolation(n_px: int, n_nodes: int, step: int) -> np.ndarray:
    """``(n_px, n_nodes)`` linear interpolation from nodes ``0, step, 2 step, ...`` to pixels."""
    t = np.arange(n_px) / step
    j0 = np.minimum(np.floor(t).astype(np.int64), n_nodes - 2)
    f = t - j0
    M = np.zeros((n_px, n_nodes))
    M[np.arange(n_px), j0] = 1.0 - f
    M[np.arange(n_px), j0 + 1] += f
    M.flags.writeable = False
    return M


@numba.njit(cache=True)
def _add_constraints(ab, rhs, cols, vals, d, weight):
    """``weight B^T d`` into ``rhs`` and ``weight B^T B`` into the band ``ab``, in place.

    The sums of ``np.add.at`` over the constraints' four nodes and their pairs ``a <= b``,
    added in the same order (identical values), without its per-call overhead.
    """
    u = ab.shape[0] - 1
    M = cols.shape[0]
    for m in range(M):
        for k in range(4):
            wv = weight * vals[m, k]
            for c in range(2):
                rhs[cols[m, k], c] += wv * d[m, c]
    for m in range(M):
        for a in range(4):
            wa = weight * vals[m, a]
            for b in range(a, 4):
                ab[u + cols[m, a] - cols[m, b], cols[m, b]] += wa * vals[m, b]


def displacement_field(shape, points, displacements, *, step: int = 2,
                       weight: float = 1e3, eps: float = 1e-6) -> np.ndarray:
    """Minimal bi-Laplacian-energy field through prescribed displacements.

    Minimises ``||L u||^2 + weight * sum_j ||u(x_j) - d_j||^2 + eps ||u||^2``
    over a grid of nodes ``step`` pixels apart covering ``shape``; ``L`` is
    the 4-neighbour grid Laplacian (:func:`branchnb.core.poisson.grid_laplacian`)
    and ``u(x_j)`` is bilinear in the nodes. A large ``weight`` makes the
    constraints practically hard; ``eps`` only fixes the field where no
    constraint reaches.

    Parameters
    ----------
    shape : (h, w)
        Size of the pixel grid (e.g. a fragment's bounding box).
    points : (M, 2) array_like
        Constraint positions (x, y) in that grid's pixel coordinates;
        those outside are ignored.
    displacements : (M, 2) array_like
        Required displacement ``d_j`` at each point.
    step : int, default 2
        Node spacing ``g`` of the solve grid in pixels (1 = every pixel).
    weight : float, default 1e3
        Weight of the constraints against the bi-Laplacian energy (large =
        practically hard constraints).
    eps : float, default 1e-6
        Small Tikhonov term that fixes the field where no constraint
        reaches (it pulls the field towards 0 there).

    Returns
    -------
    u : (h, w, 2) float ndarray
        Displacement (dx, dy) at every pixel.

    Examples
    --------
    >>> import numpy as np
    >>> u = displacement_field((21, 21), [(5, 10), (15, 10)], [(1, 0), (1, 0)])
    >>> bool(np.allclose(u[10, 5], (1, 0), atol=1e-2) and np.allclose(u[0, 0], (1, 0), atol=1e-2))
    True
    """
    h, w = int(shape[0]), int(shape[1])
    if h < 1 or w < 1:
        raise ValueError(f"shape must be positive, got {shape}")
    step = int(step)
    if step < 1:
        raise ValueError(f"step must be >= 1, got {step}")
    pts = np.asarray(points, float).reshape(-1, 2)
    d = np.asarray(displacements, float).reshape(-1, 2)
    if len(pts) != len(d):
        raise ValueError("points and displacements must have the same length")
    # Nodes 0, g, 2g, ... up to the first at or past the last pixel.
    gh, gw = max(-(-(h - 1) // step) + 1, 2), max(-(-(w - 1) // step) + 1, 2)
    ok = (pts[:, 0] >= 0) & (pts[:, 0] <= w - 1) & (pts[:, 1] >= 0) & (pts[:, 1] <= h - 1)
    ok &= np.all(np.isfinite(d), axis=1)
    pts, d = pts[ok], d[ok]
    if len(pts) == 0:
        return np.zeros((h, w, 2))
    # Bilinear weights of each constraint on its four surrounding nodes.
    gx, gy = pts[:, 0] / step, pts[:, 1] / step
    x0 = np.minimum(np.floor(gx).astype(np.int64), gw - 2)
    y0 = np.minimum(np.floor(gy).astype(np.int64), gh - 2)
    fx, fy = gx - x0, gy - y0
    rows = np.repeat(np.arange(len(pts)), 4)
    cols = np.stack([y0 * gw + x0, y0 * gw + x0 + 1, (y0 + 1) * gw + x0, (y0 + 1) * gw + x0 + 1], 1)
    vals = np.stack([(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy], 1)
    n = gh * gw
    sol = None
    if n * min(2 * gw, n - 1) ** 2 <= _BANDED_MAX_WORK:
        # Banded solve of (L^T L + weight B^T B + eps I) u = weight B^T d: the
        # constraints couple the four nodes of a cell (within the band 2 gw).
        rhs = np.zeros((n, 2))
        ab = _bilaplacian_band(gh, gw).copy()
        u = ab.shape[0] - 1
        ab[u] += eps
        # (cols increase within a row, so the pairs a <= b are in the upper band)
        _add_constraints(ab, rhs, cols, vals, d, float(weight))
        sol = banded_spd_solve(ab, rhs)
    if sol is None:  # large window (wide band) or not positive definite in floating point: sparse solve
        B = sp.csr_matrix((vals.ravel(), (rows, cols.ravel())), shape=(len(pts), n))
        A = _bilaplacian(gh, gw) + weight * (B.T @ B) + eps * sp.eye(n)
        sol = np.asarray(spsolve(A.tocsc(), weight * (B.T @ d)))
    sol = sol.reshape(gh, gw, 2)
    # bilinear from the nodes to every pixel, separably (two small products per component)
    Wy, Wx = _interpolation(h, gh, step), _interpolation(w, gw, step)
    return np.stack([Wy @ sol[..., c] @ Wx.T for c in range(2)], axis=-1)


def backward_map(origin, shape, rotation, translation, field=None) -> tuple[np.ndarray, np.ndarray]:
    """Source coordinates of the pixels of a target window.

    The fragment's rigid transform maps source points to the target,
    ``x = R p + t``; with the displacement field ``u`` the target pixel
    ``x`` takes its colour from ``p = R^T (x - u(x) - t)``.

    Parameters
    ----------
    origin : (x0, y0)
        Target pixel of the window's top-left corner.
    shape : (h, w)
        Size of the target window in pixels.
    rotation : (2, 2) array_like
        Rotation R of the fragment's rigid transform (source to target).
    translation : (2,) array_like
        Translation t (x, y) of the rigid transform (pixels).
    field : (h, w, 2) ndarray, optional
        Displacement ``u`` over the window.

    Returns
    -------
    map_x, map_y : (h, w) float32 ndarrays
        Source x and y of every window pixel (as for ``cv2.remap``).

    Examples
    --------
    >>> mx, my = backward_map((10, 20), (2, 3), [[1, 0], [0, 1]], (4, 5))
    >>> float(mx[0, 0]), float(my[0, 0])
    (6.0, 15.0)
    """
    h, w = int(shape[0]), int(shape[1])
    R = np.asarray(rotation, float)
    t = np.asarray(translation, float)
    # (a row and a column broadcast: the values of the full pixel grids, without building them)
    X = np.arange(w, dtype=float)[None, :] + origin[0] - t[0]
    Y = np.arange(h, dtype=float)[:, None] + origin[1] - t[1]
    if field is not None:
        X = X - field[..., 0]
        Y = Y - field[..., 1]
    else:
        X, Y = np.broadcast_arrays(X, Y)
    # R^T (X, Y)
    mx = R[0, 0] * X + R[1, 0] * Y
    my = R[0, 1] * X + R[1, 1] * Y
    return mx.astype(np.float32), my.astype(np.float32)
