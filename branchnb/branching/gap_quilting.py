"""Step 4 of image synthesis, the patch loop: quilting the gaps faster (issue 23).

:func:`branchnb.core.completion.complete_gaps` (shared with the leaves)
with a cheaper window search, for image synthesis only:

* the coarse search runs on a copy of the example whose long side is at
  most :data:`SEARCH_SIZE` = 128 px (core: 192), then is refined at full
  resolution around the chosen window as before;
* the coarse correlations (an 8 x 8 template at that scale) are direct
  (``cv2.filter2D``) instead of OpenCV's ``matchTemplate``, which pays a DFT
  for every call: about 2.5 times less work per window search.

The chosen windows differ (a coarser first look, float32 rounding), the
quilting does not: same cells, order, seams and colour correction (the
screened correction solved iteratively, :mod:`.gap_blend`). Region
labels (maps) are passed on to ``complete_gaps`` unchanged.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..core.completion import CompletionResult, _box_count, _grid_cells, _hole_cells, _inpaint, _Matcher, _window_choice
from ..core.random import as_rng
from .gap_blend import compose_patch

__all__: list[str] = []

#: Long side (pixels) of the reduced example the windows are first searched on.
SEARCH_SIZE = 128


def _corr(img: np.ndarray, tpl: np.ndarray) -> np.ndarray:
    """``cv2.matchTemplate(img, tpl, TM_CCORR)`` by a direct correlation (small templates)."""
    h, w = img.shape[0] - tpl.shape[0] + 1, img.shape[1] - tpl.shape[1] + 1
    return cv2.filter2D(img, -1, tpl, anchor=(0, 0), borderType=cv2.BORDER_CONSTANT)[:h, :w]


def _ssd_direct(planes, tpl: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Masked SSD of :func:`branchnb.core.completion._masked_ssd_planes` by direct correlations."""
    t = tpl if tpl.ndim == 3 else tpl[:, :, None]
    m = np.ascontiguousarray(mask, np.float32)
    mt = m[:, :, None] * t
    const = float((mt.astype(np.float64) * t).sum())
    res = _corr(planes[-1], m)
    for c in range(t.shape[2]):
        res -= 2.0 * _corr(planes[c], np.ascontiguousarray(mt[:, :, c]))
    return np.maximum(res + np.float32(const), 0.0)


class _QuickMatcher(_Matcher):
    """:class:`branchnb.core.completion._Matcher` (``fast``) with direct coarse correlations."""

    def choose(self, tpl: np.ndarray, known: np.ndarray, tolerance: float,
               rng: np.random.Generator) -> tuple[int, int]:
        s = self.scale
        unknown = (~known).astype(np.float32)
        n_unknown = max(float(unknown.sum()), 1.0)
        n_known = float(known.sum())
        t_cv = np.ascontiguousarray(tpl[:, :, 0] if tpl.shape[2] == 1 else tpl, np.float32)
        m = known.astype(np.float32)
        if s > 1:
            sz = (self.tsz, self.tsz)
            t_s = cv2.resize(t_cv, sz, interpolation=cv2.INTER_AREA)
            m_s = (cv2.resize(m, sz, interpolation=cv2.INTER_AREA) > 0.99).astype(np.float32)
            u_s = cv2.resize(unknown, sz, interpolation=cv2.INTER_AREA)
        else:
            t_s, m_s, u_s = t_cv, m, unknown
        hh, ww = self.usable_small.shape
        f = _corr(self.forbid_small, u_s) / max(float(u_s.sum()), 1.0)
        hh, ww = min(hh, f.shape[0]), min(ww, f.shape[1])
        usable = self._usable_cache.get(f.shape)
        if usable is None:
            usable = np.zeros(f.shape, bool)
            usable[:hh, :ww] = self.usable_small[:hh, :ww]
            self._usable_cache[f.shape] = usable
        if not usable.any():
            cand = np.argwhere(self.usable)
            return tuple(int(v) for v in cand[rng.integers(len(cand))])
        box = cv2.boxFilter(self.used, -1, (self.tsz, self.tsz), anchor=(0, 0),
                            normalize=True, borderType=cv2.BORDER_CONSTANT)
        used = np.zeros(f.shape, np.float32)
        used[:hh, :ww] = box[:hh, :ww]
        has = bool(m_s.sum() >= 1)
        ssd = (_ssd_direct(self.small_sq, t_s, m_s) / np.float32(float(m_s.sum()) * self.channels) if has
               else np.zeros(f.shape, np.float32))
        typical, good = _window_choice(ssd, has, f, used, usable, float(self.forbid_weight),
                                       float(self.reuse_weight), float(tolerance))
        if len(good) == 0:
            cand = np.argwhere(self.usable)
            return tuple(int(v) for v in cand[rng.integers(len(cand))])
        gy, gx = divmod(int(good[rng.integers(len(good))]), f.shape[1])
        self.used[gy:gy + self.tsz, gx:gx + self.tsz] += 1.0
        cy, cx = gy * s, gx * s
        if s == 1:
            return cy, cx
        return self._refine(cy, cx, typical, t_cv, m, unknown, n_known, n_unknown)


def quilt_gaps(canvas: np.ndarray, covered: np.ndarray, example: np.ndarray, forbidden: np.ndarray, *,
               patch_size: int, overlap: float, protect: np.ndarray | None, tolerance: float,
               forbid_weight: float, method: str, poisson: bool, anchored: bool, anchor_weight: float,
               screen: float, min_free: float, rng: np.random.Generator, progress=None,
               reuse_weight: float = 1.0, max_passes: int = 4) -> CompletionResult:
    """:func:`branchnb.core.completion.complete_gaps` (no regions, ``fast``) with :class:`_QuickMatcher`.

    ``canvas`` and ``covered`` are modified in place (all covered on return).

    Parameters
    ----------
    canvas, covered, example, forbidden
        As for ``complete_gaps``.
    patch_size, overlap, protect, tolerance, forbid_weight, method, poisson, anchored, anchor_weight, \
screen, min_free, rng, progress, reuse_weight, max_passes
        As for ``complete_gaps`` (``rng`` a Generator).

    Returns
    -------
    CompletionResult

    Examples
    --------
    >>> import numpy as np
    >>> ex = np.random.default_rng(0).random((40, 40, 3)).astype(np.float32)
    >>> canvas = np.zeros((24, 24, 3), np.float32); canvas[:, :12] = ex[:24, :12]
    >>> covered = np.zeros((24, 24), bool); covered[:, :12] = True
    >>> r = quilt_gaps(canvas, covered, ex, np.zeros((40, 40), bool), patch_size=8, overlap=0.25,
    ...                protect=None, tolerance=0.1, forbid_weight=5.0, method="graphcut", poisson=True,
    ...                anchored=True, anchor_weight=10.0, screen=0.05, min_free=0.0,
    ...                rng=np.random.default_rng(0))
    >>> bool(covered.all()), r.patch_size
    (True, 8)
    """
    rng = as_rng(rng)
    H, W = covered.shape
    eh, ew = example.shape[:2]
    margin = 2 if (poisson and anchored) else 0
    size = int(min(patch_size, H, W, eh - 2 * margin, ew - 2 * margin))
    if size < 4:
        raise ValueError(f"example_image ({ew} x {eh}) is too small for gap completion")
    while size > 8 and (_box_count(forbidden, size) == 0).mean() < min_free:
        size = max(8, int(round(size * 0.75)))
    full = size + 2 * margin
    step = max(1, int(round(size * (1.0 - overlap))))
    matcher = _QuickMatcher(example, forbidden, size, margin, SEARCH_SIZE, forbid_weight, reuse_weight, True)
    filled = np.zeros((H, W), bool)
    source = np.full((H, W, 2), np.nan)
    seams = np.zeros((H, W), bool)
    total_cost = 0.0
    n_patches = 0
    n_total = max(int((~covered).sum()), 1)
    for pass_i in range(max_passes):
        if covered.all():
            break
        cells = _grid_cells(H, W, size, step) if pass_i == 0 else _hole_cells(~covered, size)
        cells = np.array(cells, np.int64).reshape(-1, 2)
        known_n = np.array([covered[y:y + size, x:x + size].sum() for y, x in cells], np.int64)
        todo = known_n < size * size
        while todo.any():
            i = int(np.argmax(np.where(todo, known_n, -1)))     # the most known pixels first
            todo[i] = False
            y, x = (int(v) for v in cells[i])
            known = covered[y:y + size, x:x + size]
            sy, sx = matcher.choose(canvas[y:y + size, x:x + size], known, tolerance, rng)
            py0, px0 = sy - margin, sx - margin
            piece = example[py0:py0 + full, px0:px0 + full]
            valid = np.zeros((full, full), bool)
            valid[margin:margin + size, margin:margin + size] = True
            valid &= ~forbidden[py0:py0 + full, px0:px0 + full]
            prot = None
            if protect is not None:
                prot = np.zeros((full, full), bool)
                r0, c0 = y - margin, x - margin
                rr0, cc0 = max(r0, 0), max(c0, 0)
                rr1, cc1 = min(r0 + full, H), min(c0 + full, W)
                prot[rr0 - r0:rr1 - r0, cc0 - c0:cc1 - c0] = protect[rr0:rr1, cc0:cc1]
            comp = compose_patch(canvas, covered, piece, valid, (x - margin, y - margin),
                                 protect_canvas=prot, method=method, poisson=poisson,
                                 anchored=anchored, anchor_weight=anchor_weight, screen=screen)
            n_patches += 1
            if comp is not None:
                total_cost += comp.cost
                wr, wc = comp.window
                tk = comp.take
                filled[wr, wc] |= tk
                seams[wr, wc] |= comp.seam
                rows, cols = np.nonzero(tk)
                src = source[wr, wc]
                src[rows, cols, 0] = px0 + cols + comp.sub[1].start
                src[rows, cols, 1] = py0 + rows + comp.sub[0].start
            near = np.flatnonzero(todo & (np.abs(cells[:, 0] - y) < size + margin)
                                  & (np.abs(cells[:, 1] - x) < size + margin))
            for j in near:
                cy, cx = cells[j]
                known_n[j] = covered[cy:cy + size, cx:cx + size].sum()
            todo[near[known_n[near] >= size * size]] = False
            if progress is not None and n_patches % 16 == 0:
                progress(min(1.0, 1.0 - (~covered).sum() / n_total), f"gap completion: {n_patches} patches")
    n_inpainted = int((~covered).sum())
    if n_inpainted:
        _inpaint(canvas, covered)
        filled |= ~covered
        covered[:] = True
    return CompletionResult(filled, source, seams, n_patches, total_cost, size, n_inpainted)
