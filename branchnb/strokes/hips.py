"""The body's own contour across the hip a stroked tail grows out of (beyond the paper).

A body a stroke grows out of (:func:`~branchnb.strokes.attachment._is_body`:
a lizard's trunk when only its tail is stroked) stays where it was while
the tail moves. The tail's tube takes every object pixel within its half
width of the stroke, so where the tail left the body it also took the
body's own flesh up to the body's contour: the convex cap of the body's
silhouette between the two points where the tail's sides meet it. Closing
the body (as :func:`~branchnb.strokes.attachment._trim_body` does for the
slot a stroke drawn from inside the body cuts) fills concave notches only;
the cap is convex, and with the tail swung away a bite of up to a half
width deep stayed in the hip (15 px on a 320 px animal).

:func:`restore_hip` continues the body's contour across the tail's root:
its silhouette on each side of the root, near it, is fitted by a parabola
over the chord between the two corners, the two joined by the cubic with
their heights and slopes at the corners, and the object pixels of the root
under that curve are the body's again.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

__all__: list[str] = []

_EIGHT = np.ones((3, 3), bool)

#: The body's silhouette within this many times the tail's half width (at least 8 px) of each corner is fitted.
_REACH = 1.0
#: The fitted curve may lie at most this many px off the silhouette points it is fitted to (median);
#: a worse fit (the contour no graph over the chord) restores nothing.
_FIT_TOL = 1.5
#: The sides' slopes (over the chord) are clamped to this (about 56 deg): steeper, the cubic overshoots
#: the body into a stump of the old tail (a 160 px animal: 4.5 px out with 3).
_SLOPE = 1.5


def restore_hip(body: np.ndarray, obj: np.ndarray, root: np.ndarray, half: float) -> np.ndarray:
    """``body`` with the cap of its contour the tail's root took given back (a new mask).

    Parameters
    ----------
    body : (h, w) bool ndarray
        The body's pixels (in the box of its part).
    obj : (h, w) bool ndarray
        The source object's pixels (alpha > 0.5) in the same box.
    root : (h, w) bool ndarray
        Where the tail's tube may have taken the body's flesh: object pixels near the
        stroke's start, within its tube.
    half : float
        The tail's half width at its start (px).

    Returns
    -------
    (h, w) bool ndarray
        ``body`` or ``body`` plus the object pixels of ``root`` between the chord
        joining the two corners where the tail's sides meet the body's silhouette and
        the cubic continuing that silhouette from both sides of them. ``body`` itself
        when there are not exactly two corners or the silhouette near them is no
        graph over the chord.

    Examples
    --------
    >>> yy, xx = np.mgrid[:60, :60]
    >>> disk = (xx - 30) ** 2 + (yy - 25) ** 2 <= 20 ** 2
    >>> tail = (abs(xx - 30) <= 5) & (yy >= 25)
    >>> obj = disk | tail
    >>> body = disk & ~(tail & (yy >= 35))     # the tail's tube took the disk's cap
    >>> out = restore_hip(body, obj, tail & (yy >= 35), 5.0)
    >>> int((disk & ~body).sum()) > 20, int((disk & ~out).sum()) <= 2
    (True, True)
    """
    gap = obj & root & ~body
    if not gap.any() or not body.any():
        return body
    # the body's silhouette (on the ground, not on the tail's root)
    sil = body & ~ndi.binary_erosion(body) & ndi.binary_dilation(~obj, structure=_EIGHT)
    near_gap = ndi.distance_transform_edt(~gap)
    corners = sil & (near_gap <= 1.5)
    lab, n = ndi.label(ndi.binary_dilation(corners, structure=_EIGHT, iterations=2), structure=_EIGHT)
    if n != 2:
        return body
    ends = []
    for i in (1, 2):
        ys, xs = np.nonzero(corners & (lab == i))
        if not len(ys):
            return body
        ends.append(np.array([xs.mean(), ys.mean()]))
    a, b = ends
    chord = b - a
    length = float(np.hypot(*chord))
    if length < 2.0:
        return body
    u = chord / length
    v = np.array([-u[1], u[0]])
    mid = 0.5 * (a + b)
    ys, xs = np.nonzero(body)
    if float(((np.stack([xs, ys], 1) - mid) @ v).mean()) > 0:
        v = -v  # v points away from the body
    reach = max(_REACH * float(half), 8.0)
    ys, xs = np.nonzero(sil)
    p = np.stack([xs, ys], 1) - mid
    x, y = p @ u, p @ v
    slopes, heights = [], [0.0, 0.0]
    for end, sign in ((a, -1.0), (b, 1.0)):
        # (each side's silhouette beyond its corner, within reach of it, fitted by a parabola:
        # its slope at the corner)
        dist = np.hypot(xs - end[0], ys - end[1])
        side = (dist <= reach) & (sign * x >= 0.5 * length - 1.0)
        if side.sum() < 4 or np.ptp(x[side]) < 2.0:
            return body
        coef = np.polyfit(x[side], y[side], 2 if np.ptp(x[side]) >= 4.0 else 1)
        if float(np.median(np.abs(np.polyval(coef, x[side]) - y[side]))) > _FIT_TOL:
            return body
        slopes.append(float(np.clip(np.polyval(np.polyder(coef), sign * 0.5 * length), -_SLOPE, _SLOPE)))
        heights[0 if sign < 0 else 1] = float(np.polyval(coef, sign * 0.5 * length))

    def curve(t):
        # the cubic Hermite from corner to corner with the sides' slopes
        h = 0.5 * length
        z = (t + h) / length
        h00, h10 = 2 * z ** 3 - 3 * z ** 2 + 1, z ** 3 - 2 * z ** 2 + z
        h01, h11 = -2 * z ** 3 + 3 * z ** 2, z ** 3 - z ** 2
        return h00 * heights[0] + h10 * length * slopes[0] + h01 * heights[1] + h11 * length * slopes[1]

    gy, gx = np.nonzero(gap)
    q = np.stack([gx, gy], 1) - mid
    qx, qy = q @ u, q @ v
    inside = (np.abs(qx) <= 0.5 * length) & (qy <= curve(qx) + 0.5)
    if not inside.any():
        return body
    add = np.zeros_like(body)
    add[gy[inside], gx[inside]] = True
    out = body | add
    # (only what joins the body: a piece of the root cut off under the curve is the tail's)
    lab, _ = ndi.label(out)
    keep = np.unique(lab[body])
    return out & np.isin(lab, keep[keep > 0])
