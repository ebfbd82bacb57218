"""Gradient-domain (Poisson) compositing on a pixel mask.

Solves, for the pixels ``f`` inside ``mask``, the screened Poisson problem
(Perez et al. 2003)::

    min  sum_{(p,q) neighbours, p in mask} ((f_p - f_q) - (s_p - s_q))^2
         + anchor_weight * sum_{p in anchor} (f_p - s_p)^2

with ``f_q = target_q`` for neighbours outside the mask (Dirichlet
boundary) and no constraint across the image border (Neumann). The anchor
term is the "extra boundary constraints" that keep colours from drifting
when many pieces are corrected one after another.
"""

from __future__ import annotations

import numba
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from .image import as_float_image, as_mask
from .validate import Real, checked

__all__ = ["banded_spd_solve", "grid_laplacian", "poisson_blend"]

_OFFSETS = ((0, 1), (0, -1), (1, 0), (-1, 0))
#: Largest n * (band + 1)^2 solved by banded Cholesky (else sparse LU): the
#: banded solve wins on the small windows of fragments and patches.
_BANDED_MAX_WORK = 3e6


@numba.njit(cache=True, fastmath=True)
def _banded_cholesky_solve(abt, bt):
    """Solve ``A x = b`` in place for SPD ``A`` stored by rows of its lower band, ``abt[j, u + i - j] = A[i, j]``
    (``i <= j``, the transpose of LAPACK's upper band storage), ``bt`` of shape ``(C, n)``.

    Plain band Cholesky ``A = L L^T`` (no BLAS threads: on a shared machine those cost more than
    the solve); every inner loop runs over contiguous memory. Returns False if ``A`` is not
    positive definite.
    """
    n, u1 = abt.shape
    u = u1 - 1
    for j in range(n):
        i0 = max(0, j - u)
        for i in range(i0, j + 1):
            k0 = max(i0, i - u)
            s = 0.0
            oi = u - i
            oj = u - j
            for k in range(k0, i):
                s += abt[i, oi + k] * abt[j, oj + k]
            v = abt[j, u + i - j] - s
            if i == j:
                if v <= 0.0:
                    return False
                abt[j, u] = np.sqrt(v)
            else:
                abt[j, u + i - j] = v / abt[i, u]
    for c in range(bt.shape[0]):
        x = bt[c]
        for j in range(n):  # forward: L y = b
            s = 0.0
            o = u - j
            for k in range(max(0, j - u), j):
                s += abt[j, o + k] * x[k]
            x[j] = (x[j] - s) / abt[j, u]
        for i in range(n - 1, -1, -1):  # backward: L^T x = y, column by column
            x[i] = x[i] / abt[i, u]
            xi = x[i]
            o = u - i
            for k in range(max(0, i - u), i):
                x[k] -= abt[i, o + k] * xi
    return True


def banded_spd_solve(ab: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """Solve ``A x = b`` for a symmetric positive definite band matrix ``A``.

    Parameters
    ----------
    ab : (u + 1, n) float64 ndarray
        Upper band storage, ``ab[u + i - j, j] = A[i, j]`` for ``i <= j``
        (the layout of :func:`scipy.linalg.solveh_banded`); overwritten.
    b : (n,) or (n, k) array_like
        Right-hand side(s).

    Returns
    -------
    x : ndarray or None
        The solution (shape of ``b``), or None if ``A`` is not positive
        definite (the caller falls back to a general solver).

    Notes
    -----
    A plain band Cholesky compiled with numba: on the many small systems of
    fragment synthesis it is several times faster than a sparse LU and
    uses no BLAS threads.

    Examples
    --------
    >>> import numpy as np
    >>> ab = np.array([[0.0, -1.0, -1.0], [2.0, 2.0, 2.0]])   # tridiagonal [-1, 2, -1]
    >>> banded_spd_solve(ab, np.array([1.0, 0.0, 1.0])).round(6).tolist()
    [1.0, 1.0, 1.0]
    """
    ab = np.asarray(ab, np.float64)
    if ab.ndim != 2:
        raise ValueError(f"ab must be a (u + 1, n) band array, got shape {ab.shape}")
    b = np.asarray(b, np.float64)
    one = b.ndim == 1
    bt = np.array(b.reshape(len(b), -1).T, np.float64, order="C")
    if bt.shape[1] != ab.shape[1]:
        raise ValueError(f"b has {bt.shape[1]} rows, the matrix {ab.shape[1]}")
    if not _banded_cholesky_solve(np.ascontiguousarray(ab.T), bt):
        return None
    return bt[0] if one else bt.T


def grid_laplacian(mask) -> tuple[sp.csr_matrix, np.ndarray]:
    """Graph Laplacian of the 4-connected pixels of ``mask``.

    Parameters
    ----------
    mask : (H, W) bool array_like
        The pixels that are unknowns (N = number of True pixels).

    Returns
    -------
    L : (N, N) scipy.sparse.csr_matrix
        ``L[i, i]`` = number of in-mask neighbours, ``L[i, j] = -1`` for
        neighbours (positive semi-definite; Neumann boundary).
    index : (H, W) int64 ndarray
        Row of each mask pixel in ``L`` (-1 outside the mask); rows follow
        ``np.flatnonzero(mask)`` order.

    Examples
    --------
    >>> import numpy as np
    >>> L, idx = grid_laplacian(np.ones((2, 2), bool))
    >>> L.toarray().diagonal().tolist()
    [2.0, 2.0, 2.0, 2.0]
    """
    mask = as_mask(mask)
    index = np.full(mask.shape, -1, np.int64)
    n = int(mask.sum())
    index[mask] = np.arange(n)
    rows, cols = [], []
    for dr, dc in ((0, 1), (1, 0)):
        a = index[: mask.shape[0] - dr, : mask.shape[1] - dc]
        b = index[dr:, dc:]
        ok = (a >= 0) & (b >= 0)
        rows.append(a[ok])
        cols.append(b[ok])
    r = np.concatenate(rows)
    c = np.concatenate(cols)
    adj = sp.coo_matrix((np.ones(len(r)), (r, c)), shape=(n, n))
    adj = (adj + adj.T).tocsr()
    deg = np.asarray(adj.sum(axis=1)).ravel()
    return (sp.diags(deg) - adj).tocsr(), index


@checked(anchor_weight=Real(0, 1e12))
def poisson_blend(target, source, mask, *, anchor=None, anchor_weight: float = 0.0,
                  mixed: bool = False) -> np.ndarray:
    """Paste ``source`` into ``target`` inside ``mask`` in the gradient domain.

    Parameters
    ----------
    target : (H, W, C) array_like
        Supplies the boundary values (pixels outside ``mask``).
    source : (H, W, C) array_like
        Supplies the gradients inside ``mask``.
    mask : (H, W) bool array_like
        Pixels to solve for.
    anchor : (H, W) bool array_like, optional
        Pixels softly pulled towards their ``source`` value.
    anchor_weight : float
        Weight of the anchor term (0 disables it).
    mixed : bool
        Use, per neighbour pair, whichever of the source and target
        gradients is stronger (mixed seamless cloning).

    Returns
    -------
    out : (H, W, C) float32 ndarray
        ``target`` with the solved pixels, clipped to [0, 1].

    Examples
    --------
    >>> import numpy as np
    >>> t = np.full((5, 5, 1), 0.5); s = np.zeros((5, 5, 1))
    >>> m = np.zeros((5, 5), bool); m[1:4, 1:4] = True
    >>> float(poisson_blend(t, s, m)[2, 2, 0])  # flat source: takes the boundary value
    0.5
    """
    target = as_float_image(target, name="target")
    source = as_float_image(source, name="source")
    if target.shape != source.shape:
        raise ValueError(f"target and source must have the same shape, got {target.shape} and {source.shape}")
    mask = as_mask(mask, shape=target.shape[:2])
    if anchor_weight < 0 or not np.isfinite(anchor_weight):
        raise ValueError(f"anchor_weight must be finite and >= 0, got {anchor_weight}")
    anchor = np.zeros_like(mask) if anchor is None else as_mask(anchor, shape=mask.shape, name="anchor")
    return _poisson_solve(target, source, mask, anchor, float(anchor_weight), mixed)


@numba.njit(cache=True)
def _mask_band(mask):
    """Row-major index of the mask pixels and the band of their 4-neighbour system."""
    h, w = mask.shape
    index = np.full((h, w), -1, np.int64)
    n = 0
    band = 0
    for i in range(h):
        for j in range(w):
            if mask[i, j]:
                index[i, j] = n
                n += 1
                if j > 0 and mask[i, j - 1]:
                    band = max(band, 1)
                if i > 0 and index[i - 1, j] >= 0:
                    band = max(band, n - 1 - index[i - 1, j])
    return index, n, band


@numba.njit(cache=True)
def _assemble_band(index, n, band, src, tgt, anchor, anchor_weight):
    """The system of :func:`_poisson_solve` in the lower-band storage of :func:`_banded_cholesky_solve`.

    Same terms, added in the same order, as the vectorised assembly (identical values).
    """
    h, w = index.shape
    C = src.shape[2]
    abt = np.zeros((n, band + 1))
    rhs = np.zeros((C, n))
    has_boundary = False
    for i in range(h):
        for j in range(w):
            p = index[i, j]
            if p < 0:
                continue
            deg = 0.0
            for d in range(4):
                qi, qj = i, j
                if d == 0:
                    qj = j + 1
                elif d == 1:
                    qj = j - 1
                elif d == 2:
                    qi = i + 1
                else:
                    qi = i - 1
                if qi < 0 or qi >= h or qj < 0 or qj >= w:
                    continue
                deg += 1.0
                q = index[qi, qj]
                for c in range(C):
                    rhs[c, p] += src[i, j, c] - src[qi, qj, c]
                if q >= 0:
                    if q > p:
                        abt[q, band + p - q] = -1.0
                else:
                    has_boundary = True
                    for c in range(C):
                        rhs[c, p] += tgt[qi, qj, c]
            a_w = anchor_weight if anchor[i, j] else 0.0
            for c in range(C):
                rhs[c, p] += a_w * src[i, j, c]
            abt[p, band] = deg + a_w
    return abt, rhs, has_boundary


def _poisson_solve(target: np.ndarray, source: np.ndarray, mask: np.ndarray, anchor: np.ndarray,
                   anchor_weight: float, mixed: bool = False) -> np.ndarray:
    """:func:`poisson_blend` on validated arrays (float (H, W, C) images, (H, W) bool masks)."""
    out = target.copy()
    if not mask.any():
        return out
    if not mixed:
        # the common case, assembled and solved in compiled loops (identical values)
        mask_c = np.ascontiguousarray(mask, bool)
        index, n, band = _mask_band(mask_c)
        if n * (band + 1) ** 2 <= _BANDED_MAX_WORK:
            abt, rhs, has_boundary = _assemble_band(index, n, band, np.ascontiguousarray(source, np.float64),
                                                    np.ascontiguousarray(target, np.float64),
                                                    np.ascontiguousarray(anchor, bool), float(anchor_weight))
            anchored = anchor_weight > 0 and bool(anchor[mask_c].any())
            if (has_boundary or anchored) and _banded_cholesky_solve(abt, rhs):
                out[mask_c] = rhs.T
                return np.clip(out, 0, 1).astype(np.float32)
    return _poisson_solve_sparse(out, target, source, mask, anchor, anchor_weight, mixed)


def _poisson_solve_sparse(out, target, source, mask, anchor, anchor_weight, mixed):
    """The general path of :func:`_poisson_solve` (mixed gradients, wide masks, singular systems)."""
    h, w = mask.shape
    C = target.shape[2]
    idx = np.flatnonzero(mask)
    n = len(idx)
    index = np.full(h * w, -1, np.int64)
    index[idx] = np.arange(n)
    pr, pc = np.divmod(idx, w)
    src = source.reshape(-1, C).astype(np.float64)
    tgt = target.reshape(-1, C).astype(np.float64)
    # One pass per neighbour direction: degree (in-image neighbours),
    # off-diagonal -1 for in-mask neighbours, source gradients and the
    # Dirichlet values of out-of-mask neighbours on the right-hand side.
    deg = np.zeros(n)
    rhs = np.zeros((n, C))
    rows, cols = [], []
    has_boundary = False
    for dr, dc in _OFFSETS:
        qr, qc = pr + dr, pc + dc
        sel = np.flatnonzero((qr >= 0) & (qr < h) & (qc >= 0) & (qc < w))
        deg[sel] += 1
        q = qr[sel] * w + qc[sel]
        gs = src[idx[sel]] - src[q]
        if mixed:
            gt = tgt[idx[sel]] - tgt[q]
            gs = np.where(np.abs(gt) > np.abs(gs), gt, gs)
        rhs[sel] += gs
        qi = index[q]
        inm = qi >= 0
        rows.append(sel[inm])
        cols.append(qi[inm])
        bnd = sel[~inm]
        if len(bnd):
            has_boundary = True
            rhs[bnd] += tgt[q[~inm]]
    a_w = anchor_weight * anchor.ravel()[idx]
    rhs += a_w[:, None] * src[idx]
    r = np.concatenate(rows + [np.arange(n)])
    c = np.concatenate(cols + [np.arange(n)])
    v = np.concatenate([-np.ones(len(r) - n), deg + a_w])
    if not has_boundary and not a_w.any():
        # No Dirichlet boundary and no anchor: fix one pixel to make the
        # Neumann problem well posed.
        keep = r != 0
        r, c, v = np.concatenate([r[keep], [0]]), np.concatenate([c[keep], [0]]), np.concatenate([v[keep], [1.0]])
        rhs[0] = tgt[idx[0]]
    sol = None
    if has_boundary or a_w.any():
        # Symmetric positive definite with a narrow band in row-major pixel
        # order (vertical neighbours are at most one mask row apart): a
        # banded Cholesky solve is several times faster than a sparse LU on
        # the windows used here.
        band = int(np.max(np.abs(r - c))) if len(r) else 0
        if n * (band + 1) ** 2 <= _BANDED_MAX_WORK:
            up = r <= c
            abt = np.zeros((n, band + 1))
            abt[c[up], band + r[up] - c[up]] = v[up]
            sol = np.ascontiguousarray(rhs.T)
            if _banded_cholesky_solve(abt, sol):
                sol = sol.T
            else:  # a piece of the mask without boundary: singular
                sol = None
    if sol is None:
        A = sp.csc_matrix((v, (r, c)), shape=(n, n))
        sol = splu(A, permc_spec="MMD_AT_PLUS_A").solve(rhs)
    out.reshape(-1, C)[idx] = sol
    return np.clip(out, 0, 1).astype(np.float32)
