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
Not solved: on a faint strip whose veins lie 4 px apart (photo 05 at 300
px) the lines stay broken (mean run 0.09 before and after; the strict
centre line breaks where a vein's centre falls between two pixels, and a
tolerant one joined neighbouring veins).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

__all__ = ["is_parallel_layer", "vein_direction", "along_ridges"]

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
        :func:`~branchnb.leaves.snapping.ridge_evidence`.
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
    2. The ridge's centre line: pixels of evidence at least ``level`` that
       are the evidence's maximum across the vein direction (one pixel
       either side).
    3. Each kept piece, moved onto the centre line within one pixel,
       grows along it (8-connected) in both directions; grown lines
       shorter than ``min_run`` px go, and the rest are drawn ``width``
       px wide (:func:`~branchnb.leaves.snapping_width._grow_to_width`).

    Parameters
    ----------
    mask : (H, W) bool ndarray
        The snapped layer on the exemplar.
    evidence : (H, W) float ndarray
        Its :func:`~branchnb.leaves.snapping.ridge_evidence`.
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
    # The centre line: evidence at least ``level``, a maximum across the veins.
    import cv2
    h, w = ev.shape
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    nx, ny = -tan[..., 1], tan[..., 0]
    side1 = cv2.remap(ev, xx + nx, yy + ny, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)
    side2 = cv2.remap(ev, xx - nx, yy - ny, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)
    # (Strictly: within 5-15 % the centre lines of real grass veins 4-5 px apart joined into rungs.)
    line = (ev >= level) & (ev >= side1) & (ev >= side2) & b
    seeds = ndi.binary_dilation(keep, structure=np.ones((3, 3), bool)) & line
    grown = ndi.binary_propagation(seeds, structure=np.ones((3, 3), bool), mask=line)
    # Only along the veins: a centre-line pixel stepping across them (a crossing texture ridge) is no vein.
    gt = _path_tangents(skeletonize(grown)) if grown.any() else tan
    grown &= np.abs((gt * tan).sum(-1)) >= np.cos(np.radians(angle))
    grown = ndi.binary_propagation(seeds & grown, structure=np.ones((3, 3), bool), mask=grown)
    if min_run > 0 and grown.any():
        lab, n = ndi.label(grown, structure=np.ones((3, 3), bool))
        size = np.bincount(lab.ravel(), minlength=n + 1)
        ok = size >= float(min_run)
        ok[0] = False
        grown = ok[lab]
    if not grown.any():
        return np.zeros_like(m)
    path = skeletonize(grown)
    return _grow_to_width(path, float(width), centre) & b
