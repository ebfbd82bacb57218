"""Parallel venation: snapped veins followed along the exemplar's own ridges (step 8 of
:mod:`branchnb.leaves.snapping`, beyond the paper).

A grass-type blade's veins run side by side a few pixels apart. The
template fit and the path search of :mod:`branchnb.leaves.snapping` carry
each training vein into a narrower or bent strip across its neighbours, and
the least-cost path climbs from vein to vein in a staircase (real grass
photos, 400 px: the induced layers were networks of rungs, 4-8 parts, 77-93 %
of their length along the strip). For a layer of *parallel* veins
(:func:`is_parallel_layer`) the snapped paths are cut where they cross the
exemplar's own vein direction (:func:`vein_direction`), and every piece
left is followed along its ridge's centre line in both directions
(:func:`along_ridges`) as far as the ridge shows: one continuous line per vein.

Measured (``python -m branchnb.leaves._measure snapping --kinds strips``:
procedural strips, every strip of 4 as training leaf, true registrations
perturbed by 2 vein widths, seeds 0-1): vein IoU min / mean 0.67 / 0.92 ->
0.68 / 0.94 at 192 px, 0.35 / 0.88 -> 0.36 / 0.90 at 384 px. Real grass
photos 01-05 at 400 px (``python -m branchnb.leaves._measure_grass``: the
training strip's own pale veins as its layer; along-strip runs of the
induced skeleton, cut at junctions and turns over 20 degrees, over the
strip's length): training 01, mean / least run 0.13 / 0.10 -> 0.31 / 0.18,
off-direction share 0.15 -> 0.07; training 02, 0.23 / 0.18 -> 0.37 / 0.15
(strip 05 0.18 -> 0.15), 0.12 -> 0.11.
Followed on the ridge's crest (:func:`follow_lines`, sub-pixel, in place of
the pixel-wise centre line, which broke wherever a faint vein's centre fell
between two pixels: strip 05's veins lie 3-4 px apart): mean / least run,
training 01, 0.31 / 0.18 -> 0.46 / 0.35 (strip 04 0.21 -> 0.35, strip 05
0.18 -> 0.37), off-direction share 0.07 -> 0.08; training 02, 0.37 / 0.15 ->
0.45 / 0.28 (strip 04 0.27 -> 0.42, strip 05 0.15 -> 0.28; strip 01 0.51 ->
0.42: two of its six lines join near one end), 0.11 -> 0.13. Procedural
strips (``--kinds strips``, seed 0): min / mean 0.68 / 0.89 and
0.94 / 0.98 -> 0.68 / 0.89 and 0.93 / 0.98 at 192 / 384 px. (These
before -> after figures include the third template start,
:data:`~branchnb.leaves.snapping.REGISTRATION_START`; the crest alone, on the
same snapped paths of training 01: strip 04 / 05 runs 0.21 / 0.18 -> 0.35 / 0.37.)
Not solved: a line may still bend onto the blade's margin where the vein
direction field follows it (strip 04 from training 02: one hook).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from scipy import ndimage as ndi

__all__ = ["is_parallel_layer", "vein_direction", "along_ridges", "follow_lines"]

#: Least share of a layer's main-branch points whose nearest other branch runs the same way
#: (within :data:`PARALLEL_ANGLE` degrees) for the layer to be parallel venation.
PARALLEL_SHARE = 0.8
#: Largest angle (degrees) between neighbouring parallel veins, and between a kept path and the
#: exemplar's vein direction (:func:`along_ridges`).
PARALLEL_ANGLE = 20.0
#: Largest share of a parallel layer's main branches meeting another at an end (:func:`is_parallel_layer`).
MEETING_SHARE = 0.3
#: Ridge evidence of the centre line a parallel vein is followed along (:func:`along_ridges`).
ALONG_LEVEL = 0.15
#: Steps (px) a followed vein may cross below :data:`ALONG_LEVEL` (a faint stretch, a speck on it)
#: before it ends (:func:`follow_lines`).
ALONG_GAP = 4
#: Largest turn (degrees) of a followed vein from the direction it started in (:func:`follow_lines`).
ALONG_TURN = 30.0


def _tangents(chain: np.ndarray, span: int = 3) -> np.ndarray:
    c = np.asarray(chain, np.float64)
    n = len(c)
    i0 = np.clip(np.arange(n) - span, 0, n - 1)
    i1 = np.clip(np.arange(n) + span, 0, n - 1)
    d = c[i1] - c[i0]
    return d / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-9)[:, None]


def is_parallel_layer(chains, blade_size: float, *, share: float = PARALLEL_SHARE,
                      angle: float = PARALLEL_ANGLE) -> bool:
    """Whether a layer's main branches are parallel venation (a grass blade's), not a branching network.

    Parallel: at least three branches, at most :data:`MEETING_SHARE` of
    them meeting another (an end within 2 px of another branch: every branch
    of a network meets others at its junctions; a few parallel veins grown
    from scribbles touch where lazy snapping bridged them), and at least ``share`` of the branch
    points whose nearest other branch lies within a quarter of the leaf
    size run within ``angle`` degrees of it.

    Parameters
    ----------
    chains : list of (N, 2) array_like
        The layer's main branches (:func:`~branchnb.leaves.snapping.main_branches`), ``(x, y)``.
    blade_size : float
        The leaf's size in pixels (``sqrt`` of the blade's area).
    share : float
        Least share of agreeing points (default :data:`PARALLEL_SHARE`).
    angle : float
        Largest angle in degrees between neighbouring veins (default :data:`PARALLEL_ANGLE`).

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> lines = [np.column_stack([np.arange(10, 150), np.full(140, y)]) for y in (20, 30, 40, 50)]
    >>> star = [np.column_stack([np.arange(0, 60), np.arange(0, 60) * k]) for k in (0, 1, 3)]
    >>> is_parallel_layer(lines, 100.0), is_parallel_layer(star, 100.0)
    (True, False)
    """
    from scipy.spatial import cKDTree
    cs = [np.asarray(c, np.float64) for c in chains if len(c) >= 4]
    if len(cs) < 3:
        return False
    tans = [_tangents(c) for c in cs]
    trees = [cKDTree(c) for c in cs]
    agree = total = meeting = 0
    for i, (c, tg) in enumerate(zip(cs, tans)):
        best_d = np.full(len(c), np.inf)
        best_t = np.zeros_like(tg)
        for j, tr in enumerate(trees):
            if j == i:
                continue
            d, k = tr.query(c)
            closer = d < best_d
            best_d[closer] = d[closer]
            best_t[closer] = tans[j][k[closer]]
        # A branch meeting another at its end: a network's junction.
        meeting += int(min(best_d[0], best_d[-1]) <= 2.0)
        near = best_d <= 0.25 * float(blade_size)
        total += int(near.sum())
        cos = np.abs((tg * best_t).sum(1))
        agree += int((near & (cos >= np.cos(np.radians(angle)))).sum())
    if meeting > MEETING_SHARE * len(cs):
        return False
    return total > 0 and agree >= share * total


def vein_direction(evidence, blade, scale: float) -> np.ndarray:
    """Unit tangent ``(tx, ty)`` of the exemplar's veins at every pixel: the ridge evidence's structure tensor.

    The gradient of the evidence, averaged over a Gaussian window of
    ``scale`` px as a doubled-angle tensor, points across the veins around
    a pixel; the veins run perpendicular to it.

    Parameters
    ----------
    evidence : (H, W) float ndarray
        :func:`~branchnb.leaves.snapping_evidence.ridge_evidence`.
    blade : (H, W) bool ndarray
        The blade (the evidence is 0 outside it).
    scale : float
        Window of the tensor (px).

    Returns
    -------
    (H, W, 2) float32 ndarray
    """
    import cv2
    ev = np.where(blade, np.asarray(evidence, np.float32), 0.0).astype(np.float32)
    gy, gx = np.gradient(cv2.GaussianBlur(ev, (0, 0), 1.0))
    s = max(1.0, float(scale))
    jxx = cv2.GaussianBlur((gx * gx).astype(np.float32), (0, 0), s)
    jyy = cv2.GaussianBlur((gy * gy).astype(np.float32), (0, 0), s)
    jxy = cv2.GaussianBlur((gx * gy).astype(np.float32), (0, 0), s)
    th = 0.5 * np.arctan2(2.0 * jxy, jxx - jyy)  # across the veins
    return np.stack([-np.sin(th), np.cos(th)], -1).astype(np.float32)


def _path_tangents(skel) -> np.ndarray:
    """Unit tangent of a one-pixel path at every pixel (structure tensor of the path, 2 px window)."""
    import cv2
    f = cv2.GaussianBlur(skel.astype(np.float32), (0, 0), 1.0)
    gy, gx = np.gradient(f)
    jxx = cv2.GaussianBlur((gx * gx).astype(np.float32), (0, 0), 2.0)
    jyy = cv2.GaussianBlur((gy * gy).astype(np.float32), (0, 0), 2.0)
    jxy = cv2.GaussianBlur((gx * gy).astype(np.float32), (0, 0), 2.0)
    th = 0.5 * np.arctan2(2.0 * jxy, jxx - jyy)
    return np.stack([-np.sin(th), np.cos(th)], -1).astype(np.float32)


def along_ridges(mask, evidence, blade, width: float, *, level: float = ALONG_LEVEL,
                 angle: float = PARALLEL_ANGLE, min_run: float = 0.0, scale: float | None = None,
                 centre=None) -> np.ndarray:
    """Snapped parallel veins cut where they cross the vein direction and followed along their ridges.

    1. The mask's skeleton keeps its pixels running within ``angle``
       degrees of the exemplar's vein direction (:func:`vein_direction`):
       the rungs of a staircase across neighbouring veins go.
    2. Each kept pixel, strongest first, seeds a line followed along the
       vein direction on the ridge's crest in both directions
       (:func:`follow_lines`: sub-pixel, at most half a pixel across per
       step, ending where it meets a line already followed, turns, or the
       evidence stays below ``level``); lines shorter than ``min_run`` px
       go, and the rest are drawn ``width`` px wide
       (:func:`~branchnb.leaves.snapping_width._grow_to_width`).

    Parameters
    ----------
    mask : (H, W) bool ndarray
        The snapped layer on the exemplar.
    evidence : (H, W) float ndarray
        Its :func:`~branchnb.leaves.snapping_evidence.ridge_evidence`.
    blade : (H, W) bool ndarray
        The exemplar's blade.
    width : float
        The veins' width on this exemplar (px).
    level : float
        Least evidence of the centre line (default :data:`ALONG_LEVEL`).
    angle : float
        Largest angle (degrees) between a kept path and the vein direction.
    min_run : float
        Shortest line kept (px of centre line).
    scale : float, optional
        Window of :func:`vein_direction`; default ``max(4, 3 width)``.
    centre : (H, W) float ndarray, optional
        Per-pixel vein likelihood: the lines grown by it
        (:func:`~branchnb.leaves.snapping_width._grow_to_width`) instead of evenly.

    Returns
    -------
    (H, W) bool ndarray

    Examples
    --------
    >>> import numpy as np
    >>> ev = np.zeros((60, 200), np.float32); ev[20, 5:195] = 1; ev[30, 5:195] = 1   # two veins
    >>> m = np.zeros((60, 200), bool); m[20, 20:80] = True; m[20:31, 80] = True; m[30, 80:120] = True
    >>> out = along_ridges(m, ev, np.ones((60, 200), bool), 1.0)
    >>> bool(out[20, 10:190].all() and out[30, 10:190].all()), int(out[22:29, 80].sum())
    (True, 0)
    """
    from skimage.morphology import skeletonize

    from .snapping_width import _grow_to_width
    m = np.asarray(mask, bool)
    ev = np.asarray(evidence, np.float32)
    b = np.asarray(blade, bool)
    if not m.any():
        return m.copy()
    sc = float(scale) if scale is not None else max(4.0, 3.0 * float(width))
    tan = vein_direction(ev, b, sc)
    skel = skeletonize(m)
    pt = _path_tangents(skel)
    cos = np.abs((pt * tan).sum(-1))
    keep = skel & (cos >= np.cos(np.radians(angle)))
    # Each kept piece followed along its ridge's crest, in both directions.
    lines = follow_lines(keep, ev, tan, b, level=level, max_turn=angle, min_length=min_run)
    if not lines.any():
        return np.zeros_like(m)
    return _grow_to_width(skeletonize(lines), float(width), centre) & b


@numba.njit(cache=True, nogil=True)
def _bilinear(img, x, y):  # pragma: no cover - numba
    h, w = img.shape
    x = min(max(x, 0.0), w - 1.001)
    y = min(max(y, 0.0), h - 1.001)
    x0 = int(x)
    y0 = int(y)
    fx = x - x0
    fy = y - y0
    return ((img[y0, x0] * (1 - fx) + img[y0, x0 + 1] * fx) * (1 - fy)
            + (img[y0 + 1, x0] * (1 - fx) + img[y0 + 1, x0 + 1] * fx) * fy)


@numba.njit(cache=True, nogil=True)
def _follow_kernel(sy, sx, ev, tx, ty, inner, level, sep, gap, cos_turn, cos_total,
                   min_length):  # pragma: no cover - numba
    h, w = ev.shape
    occ = np.zeros((h, w), np.bool_)
    out = np.zeros((h, w), np.bool_)
    r = int(math.ceil(sep))
    n_off = 9
    px_buf = np.empty(4 * (h + w) + 8, np.float64)
    py_buf = np.empty(4 * (h + w) + 8, np.float64)
    line_x = np.empty(2 * px_buf.size + 1, np.float64)
    line_y = np.empty(2 * px_buf.size + 1, np.float64)
    for i in range(sy.size):
        x0 = float(sx[i])
        y0 = float(sy[i])
        if occ[sy[i], sx[i]]:
            continue
        n_line = 0
        for half in range(2):
            sgn = 1.0 if half == 0 else -1.0
            t_x = tx[sy[i], sx[i]] * sgn
            t_y = ty[sy[i], sx[i]] * sgn
            s_x, s_y = t_x, t_y
            x, y = x0, y0
            n = 0
            low = 0
            while n < px_buf.size:
                ux = _bilinear(tx, x, y)
                uy = _bilinear(ty, x, y)
                nrm = math.hypot(ux, uy)
                if nrm < 1e-6:
                    break
                ux /= nrm
                uy /= nrm
                if ux * t_x + uy * t_y < 0:
                    ux, uy = -ux, -uy
                if ux * t_x + uy * t_y < cos_turn or ux * s_x + uy * s_y < cos_total:
                    break
                t_x, t_y = ux, uy
                qx = x + t_x
                qy = y + t_y
                nx, ny = -t_y, t_x
                # The crest across the vein within one pixel either side, to a quarter pixel and a parabola.
                best = -1.0
                kb = 0
                vals = np.empty(n_off)
                for k in range(n_off):
                    o = -1.0 + 2.0 * k / (n_off - 1)
                    vals[k] = _bilinear(ev, qx + o * nx, qy + o * ny)
                    if vals[k] > best:
                        best = vals[k]
                        kb = k
                o = -1.0 + 2.0 * kb / (n_off - 1)
                if 0 < kb < n_off - 1:
                    den = vals[kb - 1] - 2 * vals[kb] + vals[kb + 1]
                    if den < 0:
                        o += 0.5 * (vals[kb - 1] - vals[kb + 1]) / den * (2.0 / (n_off - 1))
                o = min(max(o, -0.5), 0.5)
                qx += o * nx
                qy += o * ny
                ix = int(round(qx))
                iy = int(round(qy))
                if ix < 0 or iy < 0 or ix >= w or iy >= h or not inner[iy, ix] or occ[iy, ix]:
                    break
                if _bilinear(ev, qx, qy) < level:
                    low += 1
                    if low > gap:
                        break
                else:
                    low = 0
                px_buf[n] = qx
                py_buf[n] = qy
                n += 1
                x, y = qx, qy
            n -= low
            if n < 0:
                n = 0
            if half == 0:
                # The forward half reversed, then the seed, then the backward half.
                for k in range(n):
                    line_x[n - 1 - k] = px_buf[k]
                    line_y[n - 1 - k] = py_buf[k]
                line_x[n] = x0
                line_y[n] = y0
                n_line = n + 1
            else:
                for k in range(n):
                    line_x[n_line + k] = px_buf[k]
                    line_y[n_line + k] = py_buf[k]
                n_line += n
        length = 0.0
        for k in range(1, n_line):
            length += math.hypot(line_x[k] - line_x[k - 1], line_y[k] - line_y[k - 1])
        for k in range(n_line):
            ix = int(round(line_x[k]))
            iy = int(round(line_y[k]))
            for dy in range(-r, r + 1):
                for dx in range(-r, r + 1):
                    if dx * dx + dy * dy <= sep * sep and 0 <= iy + dy < h and 0 <= ix + dx < w:
                        occ[iy + dy, ix + dx] = True
            if length >= min_length:
                out[iy, ix] = True
                if k > 0:  # the midpoint too: an 8-connected line
                    out[int(round(0.5 * (line_y[k] + line_y[k - 1]))),
                        int(round(0.5 * (line_x[k] + line_x[k - 1])))] = True
    return out


def follow_lines(seeds, evidence, tangents, blade, *, level: float = ALONG_LEVEL, max_turn: float = PARALLEL_ANGLE,
                 total_turn: float = ALONG_TURN, gap: int = ALONG_GAP, separation: float = 1.5, rim: float = 2.0,
                 min_length: float = 0.0) -> np.ndarray:
    """Veins followed from seed pixels along the vein direction, held on their ridge's crest.

    From each seed, strongest first, a line steps one pixel along the
    exemplar's vein direction (``tangents``, :func:`vein_direction`) in both
    directions and moves onto the evidence's crest across it (sampled to a
    quarter pixel within one pixel either side, at most half a pixel per
    step: a neighbouring vein 3-4 px away is never reached in one step). It
    ends at the blade's rim (``rim`` px), where it meets a line already
    followed (within ``separation`` px), where its direction turns more than
    ``max_turn`` degrees in one step or ``total_turn`` from where it
    started, or after more than ``gap`` steps below ``level``. Beyond the
    paper (parallel venation, :func:`along_ridges`): a pixel-wise centre line
    (the evidence's maximum across the vein at whole pixels) broke wherever
    a faint vein's centre fell between two pixels (real grass strip 05 at
    400 px: veins 3-4 px apart, mean run 0.15-0.18 of the strip's length).

    Parameters
    ----------
    seeds : (H, W) bool ndarray
        Pixels to start from (the snapped paths running along the veins).
    evidence : (H, W) float ndarray
        Ridge evidence in ``[0, 1]``.
    tangents : (H, W, 2) float ndarray
        Unit vein direction ``(tx, ty)`` per pixel (sign free).
    blade : (H, W) bool ndarray
        The blade.
    level : float
        Least evidence along a line (default :data:`ALONG_LEVEL`).
    max_turn, total_turn : float
        Largest turn in degrees per step and from the start (defaults
        :data:`PARALLEL_ANGLE`, :data:`ALONG_TURN`).
    gap : int
        Steps below ``level`` bridged (default :data:`ALONG_GAP`).
    separation : float
        Least distance (px) between two lines.
    rim : float
        Lines keep this far (px) inside the blade.
    min_length : float
        Shorter lines (px) are left out.

    Returns
    -------
    (H, W) bool ndarray
        The lines, one pixel wide and 8-connected.

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[0:40, 0:120]
    >>> ev = np.exp(-0.5 * ((yy - 20.4 - 0.03 * xx) / 0.8) ** 2).astype(np.float32)  # one slanted vein
    >>> tan = np.dstack([np.full(ev.shape, 1.0), np.full(ev.shape, 0.03)]).astype(np.float32)
    >>> seeds = np.zeros(ev.shape, bool); seeds[22, 60] = True
    >>> out = follow_lines(seeds, ev, tan, np.ones(ev.shape, bool))
    >>> int(out.any(0).sum()) >= 110, int(np.abs(np.argmax(out, 0)[5:115] - (20.4 + 0.03 * np.arange(5, 115))).max())
    (True, 0)
    """
    s = np.asarray(seeds, bool)
    ev = np.ascontiguousarray(evidence, np.float32)
    tg = np.asarray(tangents, np.float32)
    b = np.asarray(blade, bool)
    if s.shape != ev.shape or b.shape != ev.shape or tg.shape != ev.shape + (2,):
        raise ValueError(f"seeds, evidence, blade (H, W) and tangents (H, W, 2) must agree, got "
                         f"{s.shape}, {ev.shape}, {b.shape}, {tg.shape}")
    ys, xs = np.nonzero(s)
    order = np.argsort(-ev[ys, xs], kind="stable")
    inner = ndi.distance_transform_edt(b) > float(rim)
    return _follow_kernel(ys[order].astype(np.int64), xs[order].astype(np.int64), ev,
                          np.ascontiguousarray(tg[..., 0]), np.ascontiguousarray(tg[..., 1]), inner,
                          float(level), float(separation), int(gap), float(np.cos(np.radians(max_turn))),
                          float(np.cos(np.radians(total_turn))), float(min_length))
