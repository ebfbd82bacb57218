"""Automatic gap completion: filling the space between branches.

The paper completed the area between the synthesised branches by hand, in
about ten minutes of interactive image completion per result. Here it is
automatic, by patch quilting (Efros & Freeman 2001) with graph-cut seams
(Kwatra et al. 2003) from the example's **branch-free** pixels only:

* ``forbidden`` marks the example pixels that must never be copied: the
  annotated branches with a margin, unannotated branch-like pixels and
  the matte (:mod:`branchnb.branching.regions`). A patch may come from a
  window that contains forbidden pixels, but those pixels are *not part
  of the patch*: they are never copied, so no branch texture and no
  pseudo-branch can appear. Windows whose forbidden pixels would fall on
  still-empty output pixels are penalised, so wholly branch-free windows
  win when they match about as well;
* the output is covered by square cells (side ``patch_size``, overlapping
  by ``overlap``); the cell with the most already-known pixels is filled
  first, so the filling grows inwards from the fragments; holes left by
  forbidden pixels become cells of their own in a second pass;
* a cell's window is matched by SSD on its known pixels (OpenCV
  ``matchTemplate`` on a reduced copy of the example, refined at full
  resolution) and one of the windows within ``(1 + tolerance)`` of the
  best is drawn at random;
* the patch is composed with a graph-cut seam and an anchored
  gradient-domain correction (:func:`branchnb.core.blending.compose_piece`);
  the synthesised branch bodies are protected: never overwritten, and
  neutral in the colour correction (no halo).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import cv2
import numba
import numpy as np
from scipy import ndimage as ndi

from .blending import compose_piece
from .random import as_rng
from .validate import check_callback

__all__ = ["CompletionResult", "admissible_windows", "complete_gaps"]


@dataclass
class CompletionResult:
    """Result of :func:`complete_gaps`.

    Parameters
    ----------
    filled : (H, W) bool ndarray
        Pixels filled by completion patches.
    source : (H, W, 2) float ndarray
        Example pixel (x, y) each filled pixel was copied from (NaN elsewhere).
    seams : (H, W) bool ndarray
        Pixels along the graph-cut seams between patches and their surroundings.
    n_patches : int
        Number of patches pasted.
    seam_cost : float
        Sum of the seam costs of all patches.
    patch_size : int
        Patch side actually used.
    n_inpainted : int
        Pixels no patch could fill (all its candidate pixels were forbidden),
        filled with the colour of the nearest known pixels as a last resort.

    Examples
    --------
    >>> import numpy as np
    >>> example = np.full((32, 32, 3), 0.5, np.float32)
    >>> canvas, covered = np.zeros((16, 16, 3), np.float32), np.zeros((16, 16), bool)
    >>> r = complete_gaps(canvas, covered, example, np.zeros((32, 32), bool), patch_size=8, rng=0)
    >>> int(r.filled.sum()), r.n_inpainted, float(canvas.min())
    (256, 0, 0.5)
    """

    filled: np.ndarray
    source: np.ndarray
    seams: np.ndarray
    n_patches: int
    seam_cost: float
    patch_size: int
    n_inpainted: int = 0


def admissible_windows(forbidden: np.ndarray, size: int, margin: int = 0) -> np.ndarray:
    """Top-left corners of ``size x size`` windows containing no forbidden pixel.

    Parameters
    ----------
    forbidden : (H, W) bool ndarray
        The example's branch region.
    size : int
        Window side.
    margin : int
        The windows must stay ``margin`` pixels inside the image.

    Returns
    -------
    ok : (H - size + 1, W - size + 1) bool ndarray

    Examples
    --------
    >>> import numpy as np
    >>> f = np.zeros((6, 6), bool); f[:, 3] = True
    >>> admissible_windows(f, 3).astype(int)
    array([[1, 0, 0, 0],
           [1, 0, 0, 0],
           [1, 0, 0, 0],
           [1, 0, 0, 0]])
    """
    h, w = forbidden.shape
    if size > h or size > w:
        return np.zeros((max(h - size + 1, 0), max(w - size + 1, 0)), bool)
    cnt = _box_count(forbidden, size)
    ok = cnt == 0
    if margin > 0:
        ok[:margin, :] = False
        ok[:, :margin] = False
        ok[ok.shape[0] - margin:, :] = False
        ok[:, ok.shape[1] - margin:] = False
    return ok


def _box_count(mask: np.ndarray, size: int) -> np.ndarray:
    """Number of True pixels in every ``size x size`` window (top-left indexed)."""
    ii = np.zeros((mask.shape[0] + 1, mask.shape[1] + 1), np.int64)
    ii[1:, 1:] = np.cumsum(np.cumsum(mask.astype(np.int64), 0), 1)
    return ii[size:, size:] - ii[:-size, size:] - ii[size:, :-size] + ii[:-size, :-size]


def _cv(img: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(img[:, :, 0] if img.shape[2] == 1 else img, np.float32)


def _ccorr(img: np.ndarray, tpl: np.ndarray) -> np.ndarray:
    return cv2.matchTemplate(img, tpl, cv2.TM_CCORR)


def _with_squares(img: np.ndarray):
    """``img`` (as :func:`_cv` gives it) prepared for :func:`_masked_ssd`: its channels plus the
    sum of their squares as one more channel (a pair of images past OpenCV's 4 channels)."""
    chans = img if img.ndim == 3 else img[:, :, None]
    sq = (chans.astype(np.float64) ** 2).sum(axis=2).astype(np.float32)
    if chans.shape[2] + 1 <= 4:
        return np.ascontiguousarray(np.dstack([chans, sq]), np.float32)
    return img, sq


def _channel_planes(img: np.ndarray) -> list[np.ndarray]:
    """``img`` (as :func:`_cv` gives it) as single-channel planes plus the sum of their squares
    (the last plane), for :func:`_masked_ssd_planes`."""
    chans = img if img.ndim == 3 else img[:, :, None]
    sq = (chans.astype(np.float64) ** 2).sum(axis=2).astype(np.float32)
    return [np.ascontiguousarray(chans[:, :, c], np.float32) for c in range(chans.shape[2])] + [sq]


def _masked_ssd_planes(planes, tpl: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """:func:`_masked_ssd` with one single-channel correlation per plane (``planes`` from
    :func:`_channel_planes`, possibly cropped): OpenCV correlates a multi-channel image several
    times slower than its channels one by one. Same values up to float32 rounding."""
    t = tpl if tpl.ndim == 3 else tpl[:, :, None]
    m = np.ascontiguousarray(mask, np.float32)
    mt = m[:, :, None] * t
    const = float((mt.astype(np.float64) * t).sum())
    res = cv2.matchTemplate(planes[-1], m, cv2.TM_CCORR)
    for c in range(t.shape[2]):
        res -= 2.0 * cv2.matchTemplate(planes[c], np.ascontiguousarray(mt[:, :, c]), cv2.TM_CCORR)
    return np.maximum(res + np.float32(const), 0.0)


def _masked_ssd(pre, tpl: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """``cv2.matchTemplate(img, tpl, TM_SQDIFF, mask=mask)`` for a 0/1 mask, by plain correlations.

    ``sum m (I - T)^2 = corr(sum_c I_c^2, m) - 2 sum_c corr(I_c, m T_c) + sum m T^2``: with the
    squares stored as an extra channel of the image (``pre``, from :func:`_with_squares`) this is
    one unmasked correlation, several times faster than OpenCV's masked matching (same values up
    to float32 rounding; clipped at 0).
    """
    t = tpl if tpl.ndim == 3 else tpl[:, :, None]
    m = mask.astype(np.float32)
    mt = m[:, :, None] * t
    const = float((mt.astype(np.float64) * t).sum())
    if isinstance(pre, tuple):
        img, sq = pre
        img_t = mt if img.ndim == 3 else mt[:, :, 0]
        res = (cv2.matchTemplate(sq, m, cv2.TM_CCORR)
               - 2.0 * cv2.matchTemplate(img, np.ascontiguousarray(img_t), cv2.TM_CCORR))
    else:
        res = cv2.matchTemplate(pre, np.ascontiguousarray(np.dstack([-2.0 * mt, m]), np.float32), cv2.TM_CCORR)
    return np.maximum(res + np.float32(const), 0.0)


def _grid_cells(h: int, w: int, size: int, step: int) -> list[tuple[int, int]]:
    ys = list(range(0, max(h - size, 0) + 1, step))
    xs = list(range(0, max(w - size, 0) + 1, step))
    if ys[-1] != max(h - size, 0):
        ys.append(max(h - size, 0))
    if xs[-1] != max(w - size, 0):
        xs.append(max(w - size, 0))
    return [(y, x) for y in ys for x in xs]


def _hole_cells(uncovered: np.ndarray, size: int) -> list[tuple[int, int]]:
    """Cells (top-left y, x) centred on the holes that remain after a pass."""
    h, w = uncovered.shape
    lab, n = ndi.label(uncovered)
    cells = []
    for sl in ndi.find_objects(lab):
        if sl is None:
            continue
        r0, r1, c0, c1 = sl[0].start, sl[0].stop, sl[1].start, sl[1].stop
        step = max(size // 2, 1)
        for yc in range(r0, r1, step):
            for xc in range(c0, c1, step):
                y1, x1 = min(yc + step, r1), min(xc + step, c1)
                cy, cx = (yc + y1) // 2, (xc + x1) // 2
                y = int(np.clip(cy - size // 2, 0, max(h - size, 0)))
                x = int(np.clip(cx - size // 2, 0, max(w - size, 0)))
                cells.append((y, x))
    return list(dict.fromkeys(cells))


@numba.njit(cache=True, nogil=True)
def _window_choice(ssd, has_ssd, f, used, usable, forbid_weight, reuse_weight, tolerance):
    """Coarse window costs of :meth:`_Matcher.choose` (``fast``): the typical (median) match,
    and the flat indices (row-major) of the usable windows within the tolerance of the best."""
    H, W = f.shape
    typical = 1e-3
    if has_ssd:
        buf = np.empty(H * W, np.float32)
        n = 0
        for i in range(H):
            for j in range(W):
                v = ssd[i, j]
                if usable[i, j] and np.isfinite(v):
                    buf[n] = v
                    n += 1
        if n > 0:
            typical = float(np.median(buf[:n]))
        typical = max(typical, 1e-5)
    c = np.empty(H * W)
    best = np.inf
    for i in range(H):
        for j in range(W):
            v = np.inf
            if usable[i, j]:
                sv = np.float64(ssd[i, j])
                if np.isfinite(sv):
                    v = sv + typical * (forbid_weight * np.float64(f[i, j]) + reuse_weight * np.float64(used[i, j]))
            c[i * W + j] = v
            if v < best:
                best = v
    if not np.isfinite(best):
        return typical, np.empty(0, np.int64)
    thr = best + tolerance * abs(best) + 1e-12
    return typical, np.flatnonzero(c <= thr)


class _Matcher:
    """Masked-SSD window search in the example, coarse then fine."""

    def __init__(self, example: np.ndarray, forbidden: np.ndarray, size: int, margin: int,
                 search_size: int, forbid_weight: float, reuse_weight: float = 1.0, fast: bool = False):
        eh, ew = example.shape[:2]
        self.size, self.margin = size, margin
        self.ex = _cv(example)
        self.forbid = forbidden.astype(np.float32)
        self.scale = max(1, int(np.ceil(max(eh, ew) / float(search_size))))
        s = self.scale
        if s > 1:
            self.small = cv2.resize(self.ex, (max(ew // s, 1), max(eh // s, 1)), interpolation=cv2.INTER_AREA)
            self.forbid_small = cv2.resize(self.forbid, self.small.shape[1::-1], interpolation=cv2.INTER_AREA)
        else:
            self.small, self.forbid_small = self.ex, self.forbid
        self.tsz = max(size // s, 2)
        self.fast = fast
        prep = _channel_planes if fast else _with_squares
        self.small_sq = prep(self.small)
        self.ex_sq = prep(self.ex) if s > 1 else self.small_sq
        self._ssd = _masked_ssd_planes if fast else _masked_ssd
        # The coarse search's correlations (a subclass may compute them another way).
        self._coarse_ssd = self._ssd
        self._coarse_corr = _ccorr
        # Windows that stay inside the example with their anchor band and
        # are not entirely forbidden.
        cnt = _box_count(forbidden, size)
        self.usable = cnt < size * size
        if margin > 0:
            self.usable[:margin, :] = False
            self.usable[:, :margin] = False
            self.usable[self.usable.shape[0] - margin:, :] = False
            self.usable[:, self.usable.shape[1] - margin:] = False
        if not self.usable.any():
            raise ValueError("example_image has no usable (branch-free) pixels to complete the gaps from")
        self.usable_small = self.usable[::s, ::s]
        self.forbid_weight = forbid_weight
        self.reuse_weight = reuse_weight
        # How often each (reduced) example pixel was copied already.
        self.used = np.zeros(self.small.shape[:2], np.float32)
        self.channels = example.shape[2]
        self._usable_cache: dict = {}

    def choose(self, tpl: np.ndarray, known: np.ndarray, tolerance: float,
               rng: np.random.Generator) -> tuple[int, int]:
        """Top-left (y, x) in the example of the window used for one cell."""
        s = self.scale
        unknown = (~known).astype(np.float32)
        n_unknown = max(float(unknown.sum()), 1.0)
        n_known = float(known.sum())
        t_cv = _cv(tpl)
        m = known.astype(np.float32)
        if s > 1:
            t_s = cv2.resize(t_cv, (self.tsz, self.tsz), interpolation=cv2.INTER_AREA)
            m_s = cv2.resize(m, (self.tsz, self.tsz), interpolation=cv2.INTER_AREA)
            u_s = cv2.resize(unknown, (self.tsz, self.tsz), interpolation=cv2.INTER_AREA)
            m_s = (m_s > 0.99).astype(np.float32)
        else:
            t_s, m_s, u_s = t_cv, m, unknown
        # Mean squared colour difference on the known pixels, and the
        # fraction of the cell's empty pixels the window would leave empty
        # (its forbidden pixels are not copied).
        hh, ww = self.usable_small.shape
        f = self._coarse_corr(self.forbid_small, u_s) / max(float(u_s.sum()), 1.0)
        hh, ww = min(hh, f.shape[0]), min(ww, f.shape[1])
        usable = self._usable_cache.get(f.shape)
        if usable is None:
            usable = np.zeros(f.shape, bool)
            usable[:hh, :ww] = self.usable_small[:hh, :ww]
            self._usable_cache[f.shape] = usable
        if not usable.any():
            cand = np.argwhere(self.usable)
            return tuple(int(v) for v in cand[rng.integers(len(cand))])
        if self.fast:
            # the same costs and draw, in one compiled pass (no full-size temporaries)
            box = cv2.boxFilter(self.used, -1, (self.tsz, self.tsz), anchor=(0, 0),
                                normalize=True, borderType=cv2.BORDER_CONSTANT)
            used = np.zeros(f.shape, np.float32)
            used[:hh, :ww] = box[:hh, :ww]
            has = bool(m_s.sum() >= 1)
            ssd = (self._coarse_ssd(self.small_sq, t_s, m_s) / np.float32(float(m_s.sum()) * self.channels) if has
                   else np.zeros(f.shape, np.float32))
            typical, good = _window_choice(ssd, has, f, used, usable, float(self.forbid_weight),
                                           float(self.reuse_weight), float(tolerance))
            if len(good) == 0:
                cand = np.argwhere(self.usable)
                return tuple(int(v) for v in cand[rng.integers(len(cand))])
            gy, gx = divmod(int(good[rng.integers(len(good))]), f.shape[1])
        else:
            typical, gy, gx = self._coarse_choice(f, usable, hh, ww, t_s, m_s, tolerance, rng)
            if gy < 0:
                cand = np.argwhere(self.usable)
                return tuple(int(v) for v in cand[rng.integers(len(cand))])
        self.used[gy:gy + self.tsz, gx:gx + self.tsz] += 1.0
        cy, cx = gy * s, gx * s
        if s == 1:
            return cy, cx
        return self._refine(cy, cx, typical, t_cv, m, unknown, n_known, n_unknown)

    def _coarse_choice(self, f, usable, hh, ww, t_s, m_s, tolerance, rng):
        """The coarse window of :meth:`choose` (the exact path): ``(typical, gy, gx)``, gy < 0 if none."""
        if m_s.sum() >= 1:
            ssd = self._ssd(self.small_sq, t_s, m_s) / (float(m_s.sum()) * self.channels)
            ssd = np.where(np.isfinite(ssd), ssd, np.inf)
            typical = max(float(np.median(ssd[usable & np.isfinite(ssd)])) if np.isfinite(ssd[usable]).any()
                          else 1e-3, 1e-5)
        else:
            ssd, typical = np.zeros(f.shape), 1e-3
        # Penalties in units of a typical match: holes left by forbidden
        # pixels, and reuse of the example around earlier windows (so the
        # same few windows are not tiled everywhere).
        # Mean earlier use of the pixels under each window (a window that
        # half overlaps a used one pays half): a distinctive spot of the
        # example is not repeated by shifted windows either.
        box = cv2.boxFilter(self.used, -1, (self.tsz, self.tsz), anchor=(0, 0),
                            normalize=True, borderType=cv2.BORDER_CONSTANT)
        used = np.zeros(f.shape)
        used[:hh, :ww] = box[:hh, :ww]
        c = ssd + typical * (self.forbid_weight * f + self.reuse_weight * used)
        c = np.where(usable, c, np.inf)
        best = float(c.min())
        if not np.isfinite(best):
            return typical, -1, -1
        good = np.argwhere(c <= best + tolerance * abs(best) + 1e-12)
        gy, gx = (int(v) for v in good[rng.integers(len(good))])
        return typical, gy, gx

    def _refine(self, cy, cx, typical, t_cv, m, unknown, n_known, n_unknown):
        """Refine the coarse choice ``(cy, cx)`` at full resolution around it."""
        size, s = self.size, self.scale
        y0, y1 = max(cy - s, 0), min(cy + s, self.usable.shape[0] - 1)
        x0, x1 = max(cx - s, 0), min(cx + s, self.usable.shape[1] - 1)
        if isinstance(self.ex_sq, (tuple, list)):
            region = type(self.ex_sq)(a[y0:y1 + size, x0:x1 + size] for a in self.ex_sq)
        else:
            region = self.ex_sq[y0:y1 + size, x0:x1 + size]
        fr = self.forbid[y0:y1 + size, x0:x1 + size]
        res = cv2.matchTemplate(fr, unknown, cv2.TM_CCORR) * (typical * self.forbid_weight / n_unknown)
        if n_known >= 1:
            res = res + self._ssd(region, t_cv, m) / (n_known * self.channels)
        ok = self.usable[y0:y0 + res.shape[0], x0:x0 + res.shape[1]]
        res = np.where(ok, res, np.inf)
        if not np.isfinite(res).any():
            return cy, cx
        iy, ix = np.unravel_index(int(np.argmin(res)), res.shape)
        return y0 + int(iy), x0 + int(ix)


def complete_gaps(canvas: np.ndarray, covered: np.ndarray, example: np.ndarray,
                  forbidden: np.ndarray, *, patch_size: int = 32, overlap: float = 0.25,
                  protect: np.ndarray | None = None, tolerance: float = 0.1,
                  forbid_weight: float = 5.0, search_size: int = 192, method: str = "graphcut",
                  poisson: bool = True, anchored: bool = True, anchor_weight: float = 10.0,
                  screen: float = 0.05, min_free: float = 0.0, reuse_weight: float = 1.0,
                  max_passes: int = 4, rng=None,
                  progress: Callable[[float, str], None] | None = None,
                  regions: np.ndarray | None = None, example_regions: np.ndarray | None = None,
                  outside: np.ndarray | None = None, fast: bool = False) -> CompletionResult:
    """Fill every uncovered pixel of ``canvas`` **in place** with branch-free texture.

    Parameters
    ----------
    canvas : (H, W, C) float32 ndarray
        Partly synthesised image (modified).
    covered : (H, W) bool ndarray
        Pixels already synthesised (modified; all True on return).
    example : (h, w, C) float32 ndarray
        The example image the texture is copied from (channels as ``canvas``).
    forbidden : (h, w) bool ndarray
        Example pixels that must never be copied (branches with a margin, matte).
    patch_size : int
        Side of the square cells and patches: reduced (down to 8) until at
        least ``min_free`` of the example's windows are wholly branch-free.
    overlap : float
        Overlap of neighbouring cells, as a fraction of ``patch_size``.
    protect : (H, W) bool ndarray, optional
        Canvas pixels a patch must never replace (the synthesised branches).
    tolerance : float
        Windows with a matching cost within ``(1 + tolerance)`` of the best
        are equally likely (quilting's randomness).
    forbid_weight : float
        Cost of a window per unit fraction of the cell's empty pixels that
        its forbidden pixels would leave empty, in units of the median
        matching cost (mean squared colour difference on the known pixels).
    search_size : int
        The example is searched at a scale where its long side is at most
        this many pixels; the choice is refined at full resolution.
    method : {"graphcut", "overlay"}
        Seam of each patch, as for :func:`branchnb.core.blending.compose_piece`.
    poisson, anchored : bool
        Photometric correction of each patch, as for ``compose_piece``.
    anchor_weight, screen : float
        Correction strengths, as for ``compose_piece``
        (with ``screen > 0`` the anchors are replaced by a screened correction
        that stays near the seams).
    min_free : float
        See ``patch_size``.
    reuse_weight : float
        Penalty for reusing example pixels: the mean number of earlier
        copies of the pixels under a window, times this weight, in the
        same units.
    max_passes : int
        Passes over the remaining holes before the last-resort inpainting.
    rng : int or numpy.random.Generator, optional
        Seed or generator: each patch window is drawn among those whose
        matching cost is within the tolerance of the best.
    progress : callable(fraction, text), optional
        Called with the filled fraction of the holes in [0, 1] and a short
        message as patches are placed.
    regions, example_regions : (H, W) and (h, w) int ndarray, optional
        Region labels of the canvas and of the example (e.g. land and sea
        of a map, from a flat-colour segmentation). Given both, each
        region is completed on its own, only from example pixels of the
        same region: land from land, sea from sea. A patch never covers
        pixels of another region, so seams follow the region boundaries,
        and other regions are neutral in its colour correction.
    outside : (H, W) bool ndarray, optional
        Canvas pixels this call neither fills nor matches against (used for
        the per-region passes; also available to callers that complete one
        part of an image).
    fast : bool
        Match each channel with its own correlation (OpenCV correlates
        multi-channel images several times slower): the same matching costs
        up to float32 rounding, so a near tie between windows may be drawn
        differently; off (default), the results of earlier releases exactly.

    Returns
    -------
    CompletionResult

    Examples
    --------
    >>> import numpy as np
    >>> example = np.random.default_rng(0).random((40, 40, 3)).astype(np.float32)
    >>> canvas = np.zeros((24, 24, 3), np.float32); canvas[:, :12] = example[:24, :12]
    >>> covered = np.zeros((24, 24), bool); covered[:, :12] = True     # the right half is a gap
    >>> r = complete_gaps(canvas, covered, example, np.zeros((40, 40), bool), patch_size=8, rng=0)
    >>> bool(covered.all()), r.patch_size, int(r.filled.sum()) > 0
    (True, 8, True)
    """
    rng = as_rng(rng)
    H, W = covered.shape
    eh, ew = example.shape[:2]
    if forbidden.shape != (eh, ew):
        raise ValueError(f"forbidden must have the example's shape {(eh, ew)}, got {forbidden.shape}")
    check_callback(progress, "progress")
    if not isinstance(fast, (bool, np.bool_)):
        raise TypeError(f"fast must be a bool, got {type(fast).__name__}")
    if regions is not None and example_regions is not None:
        regions = np.asarray(regions)
        example_regions = np.asarray(example_regions)
        if regions.shape != (H, W) or example_regions.shape != (eh, ew):
            raise ValueError(f"regions must have the canvas shape {(H, W)} and example_regions the "
                             f"example's {(eh, ew)}, got {regions.shape} and {example_regions.shape}")
        labels = np.unique(regions[~covered])
        if len(np.unique(regions)) > 1 or len(labels) > 1:
            return _complete_by_region(canvas, covered, example, forbidden, regions, example_regions,
                                       labels, outside, rng, progress,
                                       dict(patch_size=patch_size, overlap=overlap, protect=protect,
                                            tolerance=tolerance, forbid_weight=forbid_weight,
                                            search_size=search_size, method=method, poisson=poisson,
                                            anchored=anchored, anchor_weight=anchor_weight, screen=screen,
                                            min_free=min_free, reuse_weight=reuse_weight,
                                            max_passes=max_passes, fast=fast))
    covered_in = None
    if outside is not None:
        outside = np.asarray(outside, bool)
        covered_in = covered.copy()
        covered |= outside
        protect = outside if protect is None else (np.asarray(protect, bool) | outside)
    return _quilt(canvas, covered, example, forbidden, patch_size=patch_size, overlap=overlap, protect=protect,
                  tolerance=tolerance, method=method, poisson=poisson, anchored=anchored,
                  anchor_weight=anchor_weight, screen=screen, min_free=min_free, rng=rng, progress=progress,
                  max_passes=max_passes, outside=outside, covered_in=covered_in,
                  matcher=lambda size, margin: _Matcher(example, forbidden, size, margin, search_size,
                                                        forbid_weight, reuse_weight, fast),
                  compose=compose_piece)


def _quilt(canvas, covered, example, forbidden, *, patch_size, overlap, protect, tolerance, method, poisson,
           anchored, anchor_weight, screen, min_free, rng, progress, max_passes, outside, covered_in,
           matcher: Callable, compose: Callable) -> CompletionResult:
    """The patch loop of :func:`complete_gaps` on one region.

    ``matcher(size, margin)`` builds the window search (an object with
    ``choose(window, known, tolerance, rng)``) and ``compose`` stitches a
    piece in (as :func:`~branchnb.core.blending.compose_piece`), so a
    technique can quilt with a quicker search or solver and the same loop.
    ``outside`` and ``covered_in`` are prepared by :func:`complete_gaps`.
    """
    H, W = covered.shape
    eh, ew = example.shape[:2]
    margin = 2 if (poisson and anchored) else 0
    size = int(min(patch_size, H, W, eh - 2 * margin, ew - 2 * margin))
    if size < 4:
        raise ValueError(f"example_image ({ew} x {eh}) is too small for gap completion")
    # Smaller patches where branch-free windows of the requested size are
    # too rare to choose from (every cell would reuse the same few).
    while size > 8 and (_box_count(forbidden, size) == 0).mean() < min_free:
        size = max(8, int(round(size * 0.75)))
    full = size + 2 * margin
    step = max(1, int(round(size * (1.0 - overlap))))
    matcher = matcher(size, margin)
    filled = np.zeros((H, W), bool)
    source = np.full((H, W, 2), np.nan)
    seams = np.zeros((H, W), bool)
    total_cost = 0.0
    n_patches = 0
    n_total = max(int((~covered).sum()), 1)
    prot_full = protect if protect is not None else None

    for pass_i in range(max_passes):
        if covered.all():
            break
        cells = _grid_cells(H, W, size, step) if pass_i == 0 else _hole_cells(~covered, size)
        cells = np.array(cells, np.int64).reshape(-1, 2)
        known_n = np.array([covered[y:y + size, x:x + size].sum() for y, x in cells], np.int64)
        todo = known_n < size * size
        while todo.any():
            # The cell with the most known pixels next (filling grows inwards).
            i = int(np.argmax(np.where(todo, known_n, -1)))
            todo[i] = False
            y, x = (int(v) for v in cells[i])
            known = covered[y:y + size, x:x + size]
            if outside is not None:
                known = known & ~outside[y:y + size, x:x + size]
            sy, sx = matcher.choose(canvas[y:y + size, x:x + size], known, tolerance, rng)
            # Piece = the window plus its anchor band; forbidden pixels are no part of it.
            py0, px0 = sy - margin, sx - margin
            piece = example[py0:py0 + full, px0:px0 + full]
            valid = np.zeros((full, full), bool)
            valid[margin:margin + size, margin:margin + size] = True
            if outside is not None:
                valid[margin:margin + size, margin:margin + size] = ~outside[y:y + size, x:x + size]
            valid &= ~forbidden[py0:py0 + full, px0:px0 + full]
            prot = None
            if prot_full is not None:
                prot = np.zeros((full, full), bool)
                r0, c0 = y - margin, x - margin
                rr0, cc0 = max(r0, 0), max(c0, 0)
                rr1, cc1 = min(r0 + full, H), min(c0 + full, W)
                prot[rr0 - r0:rr1 - r0, cc0 - c0:cc1 - c0] = prot_full[rr0:rr1, cc0:cc1]
            comp = compose(canvas, covered, piece, valid, (x - margin, y - margin),
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
            # Update the known counts of the cells the patch touched.
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
        if outside is None:
            _inpaint(canvas, covered)
        else:
            # from this region's known pixels only: the others may still be empty (black)
            known = (covered_in | filled) & ~outside
            _inpaint(canvas, known if known.any() else covered_in | filled, only=~covered)
        filled |= ~covered
        covered[:] = True
    if outside is not None:
        covered[:] = covered_in | filled
    return CompletionResult(filled, source, seams, n_patches, total_cost, size, n_inpainted)


def _complete_by_region(canvas, covered, example, forbidden, regions, example_regions, labels, outside,
                        rng, progress, kw) -> CompletionResult:
    """:func:`complete_gaps` once per region, each from the example's pixels of that region."""
    H, W = covered.shape
    filled = np.zeros((H, W), bool)
    source = np.full((H, W, 2), np.nan)
    seams = np.zeros((H, W), bool)
    n_patches, cost, n_inp, size = 0, 0.0, 0, kw["patch_size"]
    labels = sorted(labels, key=lambda k: -int(np.count_nonzero(regions == k)))
    for i, k in enumerate(labels):
        mine = regions == k
        forb = forbidden | (example_regions != k)
        if forb.all():  # the example has no usable pixel of this region: any region will do
            forb = forbidden
        out_k = ~mine if outside is None else (~mine | outside)

        def sub(frac, text, i=i):
            if progress is not None:
                progress((i + frac) / len(labels), text)

        r = complete_gaps(canvas, covered, example, forb, rng=rng, progress=sub, outside=out_k, **kw)
        filled |= r.filled
        src = r.filled
        source[src] = r.source[src]
        seams |= r.seams
        n_patches += r.n_patches
        cost += r.seam_cost
        n_inp += r.n_inpainted
        size = r.patch_size
    return CompletionResult(filled, source, seams, n_patches, cost, size, n_inp)


def _inpaint(canvas: np.ndarray, covered: np.ndarray, only: np.ndarray | None = None) -> None:
    """Fill the last holes with the colour of the nearest known pixels, in place.

    Each hole pixel takes the mean of the known pixels at the nearest
    distance found by a normalised box average that grows until it reaches
    them. (OpenCV's Telea inpainting is not used: on float32 images it
    returns values far outside [0, 1].) The result stays within the range
    of the known colours. ``only`` limits the pixels written (default: every hole).
    """
    hole = ~covered if only is None else (~covered & only)
    if not hole.any():
        return
    if not covered.any():
        canvas[hole] = 0.0
        return
    known = covered.astype(np.float32)
    vals = np.where(covered[:, :, None], canvas, 0.0).astype(np.float32)
    todo = hole.copy()
    k = 3
    while todo.any():
        w = cv2.boxFilter(known, -1, (k, k), normalize=False, borderType=cv2.BORDER_CONSTANT)
        ok = todo & (w > 0)
        if ok.any():
            for c in range(canvas.shape[2]):
                s = cv2.boxFilter(np.ascontiguousarray(vals[:, :, c]), -1, (k, k), normalize=False,
                                  borderType=cv2.BORDER_CONSTANT)
                canvas[:, :, c][ok] = s[ok] / w[ok]
            todo &= ~ok
        k = 2 * k + 1
