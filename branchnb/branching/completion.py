"""Automatic gap completion: filling the space between branches.

The paper completed the area between the synthesised branches by hand, in
about ten minutes of interactive image completion per result. Here it is
automatic: square patches are quilted into the remaining gaps (Efros &
Freeman 2001 / Kwatra et al. 2003 style) from **branch-free** windows of
the example only:

* a source window is admissible only if none of its pixels lies in the
  example's branch region (the skeleton's body grown by a margin), so no
  branch texture can be copied and no pseudo-branch appears;
* the gap cell with the most already-known pixels is filled first (the
  filling grows inwards from the fragments); its window is matched by
  masked SSD on the known pixels (OpenCV ``matchTemplate`` on a reduced
  image, refined at full resolution) and one of the near-best windows is
  drawn at random;
* the patch is composed with a graph-cut seam and a gradient-domain
  correction (:func:`branchnb.branching.blending.compose_piece`); synthesised
  branch bodies are protected and never overwritten.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import cv2
import numpy as np

from ..core.random import as_rng
from .blending import compose_piece

__all__ = ["CompletionResult", "admissible_windows", "complete_gaps"]


@dataclass
class CompletionResult:
    """Result of :func:`complete_gaps`.

    Attributes
    ----------
    filled : (H, W) bool ndarray
        Pixels filled by completion patches.
    source : (H, W, 2) float ndarray
        Example pixel (x, y) each filled pixel was copied from (NaN elsewhere).
    seams : (H, W) bool ndarray
    n_patches : int
    seam_cost : float
        Sum of the seam costs of all patches.
    patch_size : int
        Patch size actually used (reduced if the example has no branch-free
        window of the requested size).
    """

    filled: np.ndarray
    source: np.ndarray
    seams: np.ndarray
    n_patches: int
    seam_cost: float
    patch_size: int


def admissible_windows(forbidden: np.ndarray, size: int, margin: int = 0) -> np.ndarray:
    """Top-left corners of ``size x size`` windows containing no forbidden pixel.

    Parameters
    ----------
    forbidden : (H, W) bool ndarray
        The example's branch region.
    size : int
        Window side.
    margin : int
        Keep a band of ``margin`` pixels of image around the window (the
        band may touch branches: it only serves as colour anchors).

    Returns
    -------
    ok : (H - size + 1, W - size + 1) bool ndarray
    """
    h, w = forbidden.shape
    if size > h or size > w:
        return np.zeros((max(h - size + 1, 0), max(w - size + 1, 0)), bool)
    ii = np.zeros((h + 1, w + 1), np.int64)
    ii[1:, 1:] = np.cumsum(np.cumsum(forbidden.astype(np.int64), 0), 1)
    cnt = ii[size:, size:] - ii[:-size, size:] - ii[size:, :-size] + ii[:-size, :-size]
    ok = cnt == 0
    if margin > 0:
        ok[:margin, :] = False
        ok[:, :margin] = False
        ok[ok.shape[0] - margin:, :] = False
        ok[:, ok.shape[1] - margin:] = False
    return ok


def _cv(img: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(img[:, :, 0] if img.shape[2] == 1 else img, np.float32)


def _cells(h: int, w: int, size: int, step: int) -> list[tuple[int, int]]:
    ys = list(range(0, max(h - size, 0) + 1, step))
    xs = list(range(0, max(w - size, 0) + 1, step))
    if ys[-1] != max(h - size, 0):
        ys.append(max(h - size, 0))
    if xs[-1] != max(w - size, 0):
        xs.append(max(w - size, 0))
    return [(y, x) for y in ys for x in xs]


def complete_gaps(canvas: np.ndarray, covered: np.ndarray, example: np.ndarray,
                  forbidden: np.ndarray, *, patch_size: int = 32, overlap: float = 0.25,
                  protect: np.ndarray | None = None, tolerance: float = 0.1,
                  search_size: int = 256, method: str = "graphcut", poisson: bool = True,
                  anchored: bool = True, anchor_weight: float = 10.0, rng=None,
                  progress: Callable[[float, str], None] | None = None) -> CompletionResult:
    """Fill every uncovered pixel of ``canvas`` **in place** with branch-free texture.

    Parameters
    ----------
    canvas : (H, W, C) float32 ndarray
        Partly synthesised image (modified).
    covered : (H, W) bool ndarray
        Pixels already synthesised (modified; all True on return).
    example : (h, w, C) float32 ndarray
        The example image.
    forbidden : (h, w) bool ndarray
        Example pixels that must never be copied (its branches with a margin).
    patch_size : int
        Side of the square patches (reduced automatically if the example
        has no branch-free window that large; the minimum is 6).
    overlap : float
        Overlap of neighbouring cells, as a fraction of ``patch_size``.
    protect : (H, W) bool ndarray, optional
        Canvas pixels a patch must never replace (the synthesised branches).
    tolerance : float
        Windows with a matching cost within ``(1 + tolerance)`` of the best
        are equally likely (quilting's randomness).
    search_size : int
        The example is searched at a scale where its long side is at most
        this many pixels; the choice is refined at full resolution.
    method, poisson, anchored, anchor_weight
        Composition of each patch, see :func:`branchnb.branching.blending.compose_piece`.
    rng : int or numpy.random.Generator, optional
    progress : callable(fraction, text), optional

    Returns
    -------
    CompletionResult
    """
    rng = as_rng(rng)
    H, W = covered.shape
    eh, ew = example.shape[:2]
    margin = 2 if (poisson and anchored) else 0
    size = int(min(patch_size, H, W, eh - 2 * margin, ew - 2 * margin))
    ok = None
    while size >= 6:
        ok = admissible_windows(forbidden, size, margin)
        if ok.any():
            break
        size = int(size * 0.75)
    if ok is None or not ok.any():
        raise ValueError(
            "example_image has no branch-free window of at least 6 x 6 pixels to complete the "
            "gaps from; reduce the exclusion margin or disable completion"
        )
    full = size + 2 * margin
    step = max(1, int(round(size * (1.0 - overlap))))
    filled = np.zeros((H, W), bool)
    source = np.full((H, W, 2), np.nan)
    seams = np.zeros((H, W), bool)
    total_cost = 0.0
    n_patches = 0

    # Reduced example for the search.
    scale = max(1, int(np.ceil(max(eh, ew) / float(search_size))))
    ex_cv = _cv(example)
    small = cv2.resize(ex_cv, (max(ew // scale, 1), max(eh // scale, 1)),
                       interpolation=cv2.INTER_AREA) if scale > 1 else ex_cv
    tsz = max(size // scale, 2)
    ok_small = ok[::scale, ::scale]

    cells = _cells(H, W, size, step)
    ii_known = None
    pending = [c for c in cells if not covered[c[0]:c[0] + size, c[1]:c[1] + size].all()]
    n_start = max(len(pending), 1)
    while pending:
        ii_known = np.zeros((H + 1, W + 1), np.int64)
        ii_known[1:, 1:] = np.cumsum(np.cumsum(covered, 0), 1)
        frac = []
        for (y, x) in pending:
            k = (ii_known[y + size, x + size] - ii_known[y, x + size]
                 - ii_known[y + size, x] + ii_known[y, x])
            frac.append(k)
        frac = np.array(frac)
        done = frac >= size * size
        if done.any():
            pending = [c for c, d in zip(pending, done) if not d]
            frac = frac[~done]
            if not pending:
                break
        y, x = pending.pop(int(np.argmax(frac)))
        known = covered[y:y + size, x:x + size]
        tpl = canvas[y:y + size, x:x + size]
        sy, sx = _choose_window(ex_cv, small, ok, ok_small, tpl, known, size, tsz, scale,
                                tolerance, rng)
        # Piece = inner window plus the anchor band.
        py0, px0 = sy - margin, sx - margin
        piece = example[py0:py0 + full, px0:px0 + full]
        valid = np.zeros((full, full), bool)
        valid[margin:margin + size, margin:margin + size] = True
        prot = None
        if protect is not None:
            prot = np.zeros((full, full), bool)
            r0, c0 = y - margin, x - margin
            rr0, cc0 = max(r0, 0), max(c0, 0)
            rr1, cc1 = min(r0 + full, H), min(c0 + full, W)
            prot[rr0 - r0:rr1 - r0, cc0 - c0:cc1 - c0] = protect[rr0:rr1, cc0:cc1]
        comp = compose_piece(canvas, covered, piece, valid, (x - margin, y - margin),
                             protect_canvas=prot, method=method, poisson=poisson,
                             anchored=anchored, anchor_weight=anchor_weight)
        n_patches += 1
        if comp is not None:
            total_cost += comp.cost
            wr, wc = comp.window
            tk = comp.take
            filled[wr, wc] |= tk
            seams[wr, wc] |= comp.seam
            rows, cols = np.nonzero(tk)
            src = source[wr, wc]
            # Window pixel (i, j) of the piece came from example (px0 + j', py0 + i').
            src[rows, cols, 0] = px0 + cols + comp.sub[1].start
            src[rows, cols, 1] = py0 + rows + comp.sub[0].start
        if progress is not None:
            progress(1.0 - len(pending) / n_start, f"gap completion: {n_patches} patches")
    return CompletionResult(filled, source, seams, n_patches, total_cost, size)


def _choose_window(ex_cv, small, ok, ok_small, tpl, known, size, tsz, scale, tolerance, rng):
    """Top-left example corner of the window used for one cell."""
    cand = np.argwhere(ok)
    if not known.any():
        return tuple(cand[rng.integers(len(cand))])
    t_cv = _cv(tpl)
    m = known.astype(np.float32)
    if scale > 1:
        t_s = cv2.resize(t_cv, (tsz, tsz), interpolation=cv2.INTER_AREA)
        m_s = (cv2.resize(m, (tsz, tsz), interpolation=cv2.INTER_AREA) > 0.99).astype(np.float32)
        if not m_s.any():
            m_s = (cv2.resize(m, (tsz, tsz), interpolation=cv2.INTER_AREA) > 0.5).astype(np.float32)
    else:
        t_s, m_s = t_cv, m
    if m_s.any():
        res = cv2.matchTemplate(small, t_s, cv2.TM_SQDIFF, mask=m_s)
        hh = min(res.shape[0], ok_small.shape[0])
        ww = min(res.shape[1], ok_small.shape[1])
        cost = np.full(res.shape, np.inf)
        cost[:hh, :ww] = np.where(ok_small[:hh, :ww], res[:hh, :ww], np.inf)
        best = float(cost.min())
    else:
        best = np.inf
    if not np.isfinite(best):
        coarse = [tuple(cand[rng.integers(len(cand))])]
    else:
        good = np.argwhere(cost <= best * (1.0 + tolerance) + 1e-6)
        pick = good[rng.integers(len(good))]
        coarse = [(int(pick[0]) * scale, int(pick[1]) * scale)]
    # Refine at full resolution around the coarse choice.
    cy, cx = coarse[0]
    r = scale if scale > 1 else 0
    y0, y1 = max(cy - r, 0), min(cy + r, ok.shape[0] - 1)
    x0, x1 = max(cx - r, 0), min(cx + r, ok.shape[1] - 1)
    region = ex_cv[y0:y1 + size, x0:x1 + size]
    res = cv2.matchTemplate(region, t_cv, cv2.TM_SQDIFF, mask=m)
    res = np.where(ok[y0:y0 + res.shape[0], x0:x0 + res.shape[1]], res, np.inf)
    if not np.isfinite(res).any():
        return cy, cx
    iy, ix = np.unravel_index(int(np.argmin(res)), res.shape)
    return y0 + int(iy), x0 + int(ix)
