"""Source strokes moved onto the middle of the part they were drawn along.

The paper assumes the user's source strokes run along the object's
skeleton: the texture is fetched in bands around them. Hand-drawn strokes
rarely do; a stroke drawn along the edge of a lizard's shin fetches half
background, and the edited leg comes out as a stump. Here (beyond the
paper) each moved source stroke is first slid across itself onto the
middle of the object's span: at samples every 2 px, the object's run
along the stroke's normal that holds (or lies nearest to) the sample gives
its midpoint. A sample already in the middle 60 % of its run stays; one
whose run is wider than 2.5 times the stroke's median run (the stroke
crosses a body, a junction), crosses another source stroke (it belongs
to that stroke's part) or reaches past the search distance moves with
its neighbours on the stroke's own part. A sample lying in a slit at most 3 px wide
with the object on both sides (a notch cut along a petal's axis, where the stroke runs)
takes the run across the slit: before, it took one prong of the notched tip for the
part, the stroke bent towards it and the turned petal's notch was filled (beyond the
paper). The offsets are smoothed along
the stroke, so the centred stroke
keeps the user's course and only loses the sideways error. Strokes
already within 1 px of the middle are left exactly as drawn.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

__all__ = ["centre_stroke"]

#: Sample spacing along the stroke (px).
_STEP = 2.0
#: Strokes whose sideways error stays below this (px) along 90 % of their length stay as drawn.
_KEEP = 1.0
#: A gap in the object at most this wide (px) that a sample lies in, with the object on both
#: sides, is a slit of the part (a notch along a petal's axis), not its edge.
_SLIT = 3.0


def centre_stroke(mask: np.ndarray, points, *, others=(), reach: float | None = None) -> np.ndarray:
    """A source stroke slid across itself onto the middle of the object's span.

    Parameters
    ----------
    mask : (H, W) bool ndarray
        The object's pixels (opaque alpha).
    points : (N, 2) array_like
        The stroke, ``(x, y)`` pixels, N >= 2.
    others : sequence of (K, 2) array_like, optional
        The other source strokes: a run crossing one of them belongs to that
        stroke's part (a branch starting inside the trunk), and stays.
    reach : float, optional
        How far across the stroke (px) the object's span is looked for;
        None = ``max(8, 0.08 max(H, W))``.

    Returns
    -------
    (M, 2) float64 ndarray
        The centred stroke (resampled every 2 px), or ``points`` unchanged
        when the stroke already runs within 1 px of the middle or crosses
        no object.

    Examples
    --------
    >>> m = np.zeros((40, 80), bool); m[10:30, 5:75] = True     # a bar, middle at y = 19.5
    >>> out = centre_stroke(m, [(10, 12), (70, 12)], reach=20)    # drawn along its top edge
    >>> bool(abs(np.median(out[:, 1]) - 19.5) < 1.0)
    True
    """
    pts = np.asarray(points, float)
    mask = np.asarray(mask, bool)
    h, w = mask.shape
    if reach is None:
        reach = max(8.0, 0.08 * max(h, w))
    seg = np.hypot(*np.diff(pts, axis=0).T)
    arc = np.r_[0.0, np.cumsum(seg)]
    if arc[-1] < 2 * _STEP:
        return pts
    s = np.linspace(0.0, arc[-1], max(int(np.ceil(arc[-1] / _STEP)) + 1, 3))
    p = np.c_[np.interp(s, arc, pts[:, 0]), np.interp(s, arc, pts[:, 1])]
    tangent = np.gradient(ndi.gaussian_filter1d(p, 2.0, axis=0, mode="nearest"), axis=0)
    tangent /= np.maximum(np.hypot(*tangent.T), 1e-9)[:, None]
    normal = np.c_[-tangent[:, 1], tangent[:, 0]]
    t = np.arange(-reach, reach + 0.25, 0.5)
    xy = p[:, None, :] + t[None, :, None] * normal[:, None, :]
    inside = ndi.map_coordinates(mask.astype(np.float32), [xy[..., 1].ravel(), xy[..., 0].ravel()],
                                 order=1, mode="constant", cval=0.0).reshape(xy.shape[:2]) > 0.5
    if len(others):
        drawn = np.zeros((h, w), np.uint8)
        cv2.polylines(drawn, [np.round(np.asarray(o, float)).astype(np.int32) for o in others], False, 1, 3)
        crossed = ndi.map_coordinates(drawn, [xy[..., 1].ravel(), xy[..., 0].ravel()], order=0,
                                      mode="constant", cval=0).reshape(xy.shape[:2]) > 0
    else:
        crossed = np.zeros(inside.shape, bool)
    offset = np.full(len(p), np.nan)
    width = np.full(len(p), np.nan)
    centre = len(t) // 2
    for i, row in enumerate(inside):
        hits = np.flatnonzero(row)
        if hits.size == 0:
            continue
        c = centre if row[centre] else int(hits[np.argmin(np.abs(hits - centre))])
        if not row[centre]:
            lo, hi = hits[hits < centre], hits[hits > centre]
            if lo.size and hi.size and 0.5 * (hi[0] - lo[-1] - 1) <= _SLIT:
                # the stroke runs along a slit of its own part (a petal's notch cut along
                # its axis): the slit is no edge, the part's two sides make the run
                row = row.copy()
                row[lo[-1]:hi[0]] = True
                c = centre
        gaps = np.flatnonzero(~row)
        left = gaps[gaps < c]
        right = gaps[gaps > c]
        if left.size == 0 or right.size == 0:
            continue  # the run reaches past the search distance: a body, not a limb
        a, b = int(left[-1]) + 1, int(right[0]) - 1
        if crossed[i, a:b + 1].any():
            continue  # another stroke's part
        offset[i] = 0.5 * (t[a] + t[b])
        width[i] = t[b] - t[a] + 0.5
    valid = np.isfinite(width)
    if not valid.any():
        return pts
    typical = float(np.median(width[valid]))
    # A run much wider than the stroke's own part is a body it crosses; a sample already in
    # the middle 60 % of its run is where the user meant it (limbs are rarely symmetric).
    own = valid & (width <= 2.5 * typical)
    offset[own & (np.abs(offset) < 0.3 * width)] = 0.0
    if not own.any():
        return pts
    # samples on another part (a junction, a body crossed) move with their neighbours on the
    # stroke's own part, so the stroke shifts as a whole there instead of kinking
    idx = np.arange(len(p))
    offset = np.interp(idx, idx[own], offset[own])
    offset = np.clip(offset, -typical, typical)
    offset = ndi.gaussian_filter1d(offset, max(typical / (4.0 * _STEP), 1.0), mode="nearest")
    if float(np.percentile(np.abs(offset), 90)) < _KEEP:
        return pts
    out = p + offset[:, None] * normal
    out[:, 0] = np.clip(out[:, 0], 0.0, w - 1.0)
    out[:, 1] = np.clip(out[:, 1], 0.0, h - 1.0)
    return out
