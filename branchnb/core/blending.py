"""Composing a new piece of texture into the partly synthesised image.

Every fragment (and every gap-completion patch) goes through the same
two steps:

1. **Graph-cut seam** (Kwatra et al. 2003, :func:`branchnb.core.graphcut.seam_cut`):
   in the overlap with what is already there, a minimum cut decides which
   pixels take the new piece. Overlap pixels next to the part only the old
   image covers stay old, those next to the part only the new piece covers
   become new, and *protected* pixels are pinned: the body of branches
   already synthesised stays, the body of the branch the new fragment
   carries is taken from it.
2. **Photometric correction** in the gradient domain
   (:func:`branchnb.core.poisson.poisson_blend`): the new pixels keep the
   piece's gradients and meet the kept pixels without a colour step. With
   *anchors* (the paper's extra boundary constraints), the pixels of the
   window that nothing covers yet are tied to the piece's own colours, so
   a correction fades out across the piece instead of being handed on to
   the next piece: colours do not drift along a chain of fragments.
   Protected canvas pixels (bodies of other branches) are *neutral* in the
   correction: the piece meets them with its own colours, so a branch's
   colour does not bleed into the background next to it as a halo.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np

from .graphcut import _pair_costs, _seam_cost, _seam_cut
from .poisson import _poisson_solve
from .poisson_cg import _cg_solve

__all__ = ["Composition", "compose_piece"]


@dataclass
class Composition:
    """What :func:`compose_piece` did inside its window.

    Parameters
    ----------
    window : (slice, slice)
        Rows and columns of the canvas the piece touched.
    sub : (slice, slice)
        The same region in the piece's own coordinates.
    take : (h, w) bool ndarray
        Window pixels now taken from the piece.
    seam : (h, w) bool ndarray
        Kept pixels adjacent to taken ones inside the overlap.
    cost : float
        Seam cost (:func:`branchnb.core.graphcut.seam_cost`) of the labelling.

    Examples
    --------
    >>> import numpy as np
    >>> canvas, covered = np.zeros((8, 8, 3), np.float32), np.zeros((8, 8), bool)
    >>> c = compose_piece(canvas, covered, np.ones((4, 4, 3), np.float32), np.ones((4, 4), bool), (2, 2))
    >>> c.window, int(c.take.sum()), c.cost         # an empty canvas: the whole piece, no seam
    ((slice(2, 6, None), slice(2, 6, None)), 16, 0.0)
    """

    window: tuple
    sub: tuple
    take: np.ndarray
    seam: np.ndarray
    cost: float


_CROSS = cv2.getStructuringElement(cv2.MORPH_CROSS, (3, 3))


def _dilate(mask: np.ndarray) -> np.ndarray:
    """``scipy.ndimage.binary_dilation(mask)`` (4-neighbours, nothing from outside the window), with OpenCV."""
    return cv2.dilate(mask.view(np.uint8), _CROSS).view(bool)


_NO_MASK = np.zeros((1, 1), bool)


@numba.njit(cache=True, nogil=True)
def _overlap_pins(cov, valid, prot_a, prot_b, has_a, has_b):
    """``overlap``, ``only_b``, ``pin_a`` and ``pin_b`` of a window in one pass.

    ``overlap = cov & valid``; ``only_b = valid & ~cov``; an overlap pixel is pinned to the canvas
    (``pin_a``) on the window's border, next to (4-neighbours) or on a pixel only the canvas covers, or
    where ``prot_a`` (if ``has_a``) protects it; else to the piece (``pin_b``) next to a pixel only
    the piece covers or where ``prot_b`` (if ``has_b``) protects it. The values of the former
    dilation-based numpy code.
    """
    h, w = cov.shape
    overlap = np.zeros((h, w), np.bool_)
    only_b = np.zeros((h, w), np.bool_)
    pin_a = np.zeros((h, w), np.bool_)
    pin_b = np.zeros((h, w), np.bool_)
    for i in range(h):
        for j in range(w):
            overlap[i, j] = cov[i, j] and valid[i, j]
            only_b[i, j] = valid[i, j] and not cov[i, j]
    for i in range(h):
        for j in range(w):
            if not overlap[i, j]:
                continue
            # next to a pixel only the canvas covers (a covered, not valid neighbour), or on the border
            near_a = i == 0 or j == 0 or i == h - 1 or j == w - 1
            if not near_a:
                near_a = ((cov[i - 1, j] and not valid[i - 1, j]) or (cov[i + 1, j] and not valid[i + 1, j])
                          or (cov[i, j - 1] and not valid[i, j - 1]) or (cov[i, j + 1] and not valid[i, j + 1]))
            pa = near_a or (has_a and prot_a[i, j])
            pin_a[i, j] = pa
            if pa:
                continue
            near_b = ((i > 0 and only_b[i - 1, j]) or (i < h - 1 and only_b[i + 1, j])
                      or (j > 0 and only_b[i, j - 1]) or (j < w - 1 and only_b[i, j + 1]))
            pin_b[i, j] = near_b or (has_b and prot_b[i, j])
    return overlap, only_b, pin_a, pin_b


def _clip_window(origin, size, shape):
    x0, y0 = int(origin[0]), int(origin[1])
    h, w = size
    r0, r1 = max(y0, 0), min(y0 + h, shape[0])
    c0, c1 = max(x0, 0), min(x0 + w, shape[1])
    if r0 >= r1 or c0 >= c1:
        return None
    return (slice(r0, r1), slice(c0, c1)), (slice(r0 - y0, r1 - y0), slice(c0 - x0, c1 - x0))


def compose_piece(canvas: np.ndarray, covered: np.ndarray, piece: np.ndarray, valid: np.ndarray,
                  origin, *, protect_canvas=None, protect_piece=None, method: str = "graphcut",
                  poisson: bool = True, anchored: bool = True,
                  anchor_weight: float = 10.0, screen: float = 0.0,
                  solver: str = "direct", neutral_canvas=None) -> Composition | None:
    """Compose ``piece`` (covering ``valid``) into ``canvas`` **in place**.

    Parameters
    ----------
    canvas : (H, W, C) float32 ndarray
        The image being synthesised (modified).
    covered : (H, W) bool ndarray
        Pixels of ``canvas`` already synthesised (modified).
    piece : (h, w, C) ndarray
        The new texture, placed with its top-left pixel at ``origin``.
        It must hold meaningful colours on the whole window (the parts
        outside ``valid`` serve as the anchor colours).
    valid : (h, w) bool ndarray
        Pixels the piece may cover.
    origin : (x0, y0)
        Canvas pixel (column, row) of the piece's top-left pixel; the window
        is clipped to the canvas.
    protect_canvas, protect_piece : (h, w) bool ndarray, optional
        Overlap pixels pinned to the old image / to the piece. Protected
        canvas pixels do not constrain the photometric correction.
    method : {"graphcut", "overlay"}
        Seam by minimum cut, or the new piece simply on top (baseline).
    poisson : bool
        Gradient-domain photometric correction of the taken pixels.
    anchored : bool
        Tie still uncovered window pixels to the piece's colours (extra
        boundary constraints against colour drift).
    anchor_weight : float
        Weight of those constraints.
    screen : float
        If > 0, every solved pixel is tied to the piece's colour with this
        weight instead (screened Poisson): a correction then fades within
        about ``1 / sqrt(screen)`` pixels of the seam, so the colour of a
        bright or dark neighbour cannot spread across the piece as a halo.
    solver : {"direct", "iterative"}
        How the correction is solved: a banded Cholesky factorisation
        (exact; default) or, where the system is well posed (``screen > 0``
        or anchored with ``anchor_weight > 0``), conjugate gradients to a
        relative residual of 1e-3 (:mod:`~branchnb.core.poisson_cg`: within
        a grey level, several times faster on small pieces).
    neutral_canvas : (h, w) bool ndarray, optional
        Canvas pixels that do not constrain the photometric correction
        either, without being pinned (the piece may still cut into them):
        e.g. the old lines' soft edges, whose colour spread into a thin new
        line faded it.

    Returns
    -------
    Composition or None
        None if the window lies outside the canvas.

    Examples
    --------
    >>> import numpy as np
    >>> canvas = np.zeros((16, 16, 3), np.float32)
    >>> covered = np.zeros((16, 16), bool); covered[:, :8] = True      # left half done
    >>> piece, valid = np.ones((16, 12, 3), np.float32), np.ones((16, 12), bool)
    >>> c = compose_piece(canvas, covered, piece, valid, (4, 0), poisson=False)
    >>> c.window[1], bool(covered.all()), float(canvas[0, 0, 0]), float(canvas[0, 15, 0])
    (slice(4, 16, None), True, 0.0, 1.0)
    """
    if method not in ("graphcut", "overlay"):
        raise ValueError(f"method must be 'graphcut' or 'overlay', got {method!r}")
    if solver not in ("direct", "iterative"):
        raise ValueError(f"solver must be 'direct' or 'iterative', got {solver!r}")
    for name, w in (("anchor_weight", anchor_weight), ("screen", screen)):
        if not (np.isfinite(w) and 0 <= w <= 1e12):
            raise ValueError(f"{name} must be finite and in [0, 1e12], got {w}")
    if neutral_canvas is not None and np.shape(neutral_canvas) != np.shape(valid):
        raise ValueError(f"neutral_canvas must have valid's shape {np.shape(valid)}, got {np.shape(neutral_canvas)}")
    clip = _clip_window(origin, valid.shape, covered.shape)
    if clip is None:
        return None
    win, sub = clip
    A = canvas[win]
    covA = covered[win]
    P = piece[sub].astype(np.float32)
    V = valid[sub]
    overlap, only_b, pin_a, pin_b = _overlap_pins(
        covA, V, protect_canvas[sub] if protect_canvas is not None else _NO_MASK,
        protect_piece[sub] if protect_piece is not None else _NO_MASK,
        protect_canvas is not None, protect_piece is not None)
    if not overlap.any():
        take = only_b.copy()
        cost = 0.0
    else:
        # Seam costs only where the cut can run: the overlap's bounding box plus one pixel of
        # context for the gradients (the same costs there as on the whole window).
        bx, by, bw, bh = cv2.boundingRect(overlap.view(np.uint8))   # the overlap's bounding box
        box = (slice(max(by - 1, 0), by + bh + 1), slice(max(bx - 1, 0), bx + bw + 1))
        # (the checked public graphcut functions would validate every argument of every piece again)
        right, down = _pair_costs(np.asarray(A[box], np.float32), P[box])
        if method == "overlay":
            take = only_b | (overlap & ~pin_a)
        else:
            take = only_b.copy()
            take[box] |= _seam_cut(right, down, overlap[box], pin_a[box], pin_b[box])
        cost = _seam_cost(right, down, take[box], overlap[box])
    seam = ~take & overlap & _dilate(take)
    if not take.any():
        return Composition(win, sub, take, seam, cost)
    new = P
    kept = covA & ~take
    neutral = kept & protect_canvas[sub] if protect_canvas is not None else None
    if neutral_canvas is not None:
        extra = kept & neutral_canvas[sub]
        neutral = extra if neutral is None else neutral | extra
    if poisson and kept.any() and (neutral is None or not np.array_equal(neutral, kept)):
        # Kept pixels are the Dirichlet boundary; neutral ones take the
        # piece's own value there (no correction injected from them).
        bnd = kept if neutral is None else kept & ~neutral
        target = np.where(bnd[:, :, None], A, P)
        if solver == "iterative" and screen > 0:
            new = _cg_solve(target, P, ~kept, np.where(kept, 0.0, float(screen)))
        elif solver == "iterative" and anchored and anchor_weight > 0:
            new = _cg_solve(target, P, ~kept, np.where(~covA & ~take, float(anchor_weight), 0.0))
        elif screen > 0:
            new = _poisson_solve(target, P, ~kept, ~kept, float(screen))
        else:
            anchor = (~covA & ~take) if anchored else np.zeros_like(kept)
            new = _poisson_solve(target, P, ~kept, anchor, float(anchor_weight) if anchored else 0.0)
    A[take] = new[take]
    covA[take] = True
    return Composition(win, sub, take, seam, cost)
