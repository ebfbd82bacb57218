"""Pin points at the concave corner where the crown leaves the trunk (beyond the paper).

The walk from ``B`` along the contour (:func:`~branchnb.trees.contour.pin_points`)
runs while contour points are trunk in a small window. A crown that narrows
onto its trunk (a poplar's ellipse, a crown tapering to a point, a fan of
palm fronds) has its lowest rows only a little wider than the trunk; the
geometric stem estimate counts rows narrower than twice the stem as trunk
and a segmenter's neck does likewise, so the walk runs several pixels up the
crown's sides and ``R``, ``L`` sit on the crown. Every variation with weight
on that exemplar then maps its crown's bottom onto the trunk: a neck
tapering into the trunk in crown colour, a shape no source has.

The true junction is where the contour leaves the trunk's side line: a
concave corner. :func:`corner_sides` moves each side's end back to the
sharpest concave turn in the upper half of the walked stretch when that
turn is sharp (over :data:`CORNER_TURN`) and lies clearly below the walk's
end; a walk that already ends at its corner is left as it was.
"""
from __future__ import annotations

import numpy as np
from scipy.ndimage import gaussian_filter1d

__all__ = ["concave_turns", "corner_sides"]

#: Smallest concave turn (degrees) taken as the crown/trunk junction. Measured on 216 outlined and
#: plain procedural trees (9 crown kinds, 96-384 px; trees61): true junctions
#: turn 30-90 deg (a crown tapering onto the trunk ~35 deg); a bent or flaring trunk's side turns
#: under 12 deg over the window, pixel stairs under ~15 deg.
CORNER_TURN = 25.0
#: Arc window of the turn, as a share of the tree height (at least :data:`_MIN_WINDOW` px): long
#: enough that pixel stairs do not read as corners, short enough to tell the corner from the crown's
#: own bend above it.
WINDOW = 0.02
_MIN_WINDOW = 3.0


def concave_turns(c: np.ndarray, window: float) -> np.ndarray:
    """Concave turning angle (degrees, > 0 where the contour bends inwards) at each point.

    Parameters
    ----------
    c : (K, 2) ndarray
        Closed contour (either orientation).
    window : float
        Arc length (px) to each side over which the turn is read.

    Returns
    -------
    (K,) ndarray
        Turn in degrees: positive at concave points, negative at convex ones.

    Examples
    --------
    >>> sq = np.array([[0, 0], [4, 0], [4, 4], [2, 4], [2, 2], [0, 2]], float)   # an L shape
    >>> t = concave_turns(np.repeat(sq, 1, axis=0), 1.0)
    >>> int(np.argmax(t)), round(float(t.max()))
    (4, 90)
    """
    c = np.asarray(c, np.float64)
    k = len(c)
    # pixel stairs turn 30-50 deg over a few px; smoothing over half the window leaves a corner's turn
    mean_step = float(np.hypot(*np.diff(np.vstack([c, c[:1]]), axis=0).T).mean())
    if k > 8 and mean_step > 0:
        c = gaussian_filter1d(c, 0.5 * window / mean_step, axis=0, mode="wrap")
    seg = np.hypot(*np.diff(np.vstack([c, c[:1]]), axis=0).T)
    total = float(seg.sum())
    s = np.concatenate([[0.0], np.cumsum(seg)[:-1]])
    s3 = np.concatenate([s - total, s, s + total])
    i3 = np.tile(np.arange(k), 3)
    before = i3[np.clip(np.searchsorted(s3, s + total - window, side="right") - 1, 0, 3 * k - 1)]
    after = i3[np.clip(np.searchsorted(s3, s + total + window, side="left"), 0, 3 * k - 1)]
    v1 = c - c[before]
    v2 = c[after] - c
    cross = v1[:, 0] * v2[:, 1] - v1[:, 1] * v2[:, 0]
    turn = np.degrees(np.arctan2(cross, np.einsum("ij,ij->i", v1, v2)))
    # convex turns share the sign of the contour's total turning
    x, y = c[:, 0], c[:, 1]
    area2 = float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    return -turn if area2 > 0 else turn


def corner_sides(c: np.ndarray, ib: int, sides: tuple[int, int], height: float) -> tuple[int, int]:
    """Move each trunk side's end back to the concave corner where the crown meets the trunk.

    Parameters
    ----------
    c : (K, 2) ndarray
        The tree contour (closed).
    ib : int
        Index of ``B``.
    sides : tuple of int
        Steps from ``B`` to ``R`` (forwards) and to ``L`` (backwards).
    height : float
        Tree height (px).

    Returns
    -------
    tuple of int
        The steps, each shortened to the corner where one was found.

    Examples
    --------
    >>> # a trunk 4 wide under a crown 12 wide whose bottom row is 6 wide (a neck)
    >>> m = np.zeros((40, 20), bool); m[25:39, 8:12] = True; m[2:25, 4:16] = True; m[22:25, 4:16] = False
    >>> m[22:25, 7:13] = True
    >>> from branchnb.trees.exemplar import extract_contours, signed_area
    >>> c = extract_contours(m).tree; c = c[::-1] if signed_area(c) > 0 else c
    >>> ib = int(np.argmax(c[:, 1] - 0.01 * np.abs(c[:, 0] - 9.5)))
    >>> jr, jl = corner_sides(c, ib, (30, 30), 38.0)
    >>> (jr, jl) != (30, 30)
    True
    """
    k = len(c)
    window = max(_MIN_WINDOW, WINDOW * height)
    turns = concave_turns(c, window)
    seg = np.hypot(*np.diff(np.vstack([c, c[:1]]), axis=0).T)
    out = []
    for j, step in zip(sides, (1, -1)):
        idx = (ib + step * np.arange(j + 1)) % k
        rise = c[ib, 1] - c[idx, 1]
        upper = np.flatnonzero(rise >= 0.5 * rise[-1])
        if j < 2 or upper.size == 0 or rise[-1] <= 0:
            out.append(j)
            continue
        best = int(upper[np.argmax(turns[idx[upper]])])
        # arc length from the corner up to the walk's end
        beyond = float(seg[idx[best:-1] if step == 1 else (idx[best:-1] - 1) % k].sum())
        if turns[idx[best]] >= CORNER_TURN and beyond > window:
            out.append(best)
        else:
            out.append(j)
    return out[0], out[1]
