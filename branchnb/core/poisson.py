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

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import factorized

from .image import as_float_image, as_mask
from .validate import Real, checked

__all__ = ["grid_laplacian", "poisson_blend"]

_OFFSETS = ((0, 1), (0, -1), (1, 0), (-1, 0))


def grid_laplacian(mask) -> tuple[sp.csr_matrix, np.ndarray]:
    """Graph Laplacian of the 4-connected pixels of ``mask``.

    Parameters
    ----------
    mask : (H, W) bool array_like

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
    out = target.copy()
    if not mask.any():
        return out
    h, w = mask.shape
    L, index = grid_laplacian(mask)
    n = L.shape[0]
    idx = np.flatnonzero(mask)
    pr, pc = np.unravel_index(idx, mask.shape)
    # Degree counts all in-image neighbours: those outside the mask become
    # Dirichlet boundary terms on the right-hand side.
    deg = np.zeros(n)
    rhs = np.zeros((n, target.shape[2]))
    for dr, dc in _OFFSETS:
        qr, qc = pr + dr, pc + dc
        inside = (qr >= 0) & (qr < h) & (qc >= 0) & (qc < w)
        deg += inside
        qr_i, qc_i = qr[inside], qc[inside]
        sel = np.flatnonzero(inside)
        gs = source[pr[sel], pc[sel]] - source[qr_i, qc_i]
        if mixed:
            gt = target[pr[sel], pc[sel]] - target[qr_i, qc_i]
            gs = np.where(np.abs(gt) > np.abs(gs), gt, gs)
        rhs[sel] += gs
        boundary = ~mask[qr_i, qc_i]
        rhs[sel[boundary]] += target[qr_i[boundary], qc_i[boundary]]
    a_w = anchor_weight * anchor[pr, pc]
    off = L - sp.diags(L.diagonal())
    A = (off + sp.diags(deg + a_w)).tocsc()
    rhs += a_w[:, None] * source[pr, pc]
    if np.all(deg == L.diagonal()) and not a_w.any():
        # No Dirichlet boundary and no anchor: fix one pixel to make the
        # Neumann problem well posed.
        A = A.tolil()
        A[0, :] = 0
        A[0, 0] = 1
        A = A.tocsc()
        rhs[0] = target[pr[0], pc[0]]
    solve = factorized(A)
    for ch in range(target.shape[2]):
        out[pr, pc, ch] = solve(rhs[:, ch])
    return np.clip(out, 0, 1).astype(np.float32)
