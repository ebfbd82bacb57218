"""Straight trunk edges in hard-edged mixes (beyond the paper; issue 24, trees54).

A flat, aliased (hard-edged) tree often stands on a trunk whose sides are straight lines, vertical
or slanted. The paper's mean-value warp is smooth but not affine: it bends those sides by a
fraction of a pixel to a pixel, and a hard-edged mix (put back on its 1-px grid by ``pixel_art``,
or aliased as its sources) turns every such bend into a stray step, so a straight trunk side becomes a staircase of 1-px
notches and bumps. No drawing of the kind has them.

:func:`trunk_edges` measures the trunk's sides on its rows free of the crown (one opaque run, mostly
trunk): a line fitted to each side (Theil-Sen: the medians follow the majority of the rows)
and the share of rows within a pixel of it. When every source's trunk is straight in that sense
(:data:`STRAIGHT_SHARE` of its rows), :func:`straighten_trunk` redraws the mix's free trunk rows
between its two fitted lines, rounded to the pixel grid: pixels the line adds take the colour of
the row's nearest trunk pixel, pixels beyond it are cleared. A mixed trunk further than
:data:`BEND_MOST` off its lines (a crooked or forking trunk) is kept as made.

Figures (procedural hard-edged trees: aliased three-tone elliptic crowns on slanted straight
trunks, 4 sources and 4 mixes at 128/256 px; ``/tmp`` scripts in the commit message): largest
trunk-edge deviation from its fitted line, sources 0.51-0.57 px, mixes at 128 px 0.81/0.80/0.88/0.48
-> 0.54/0.49/0.52/0.0, at 256 px 0.48/0.48/0.99/0.50 -> 0.52/0.52/0.52/0.54; hard-edged firs (not
pixel art) lose the 1-px step the warp left on a vertical trunk side.

Examples
--------
>>> import numpy as np
>>> img = np.zeros((40, 40, 4), np.float32)
>>> img[10:38, 18:23] = (0.4, 0.25, 0.1, 1.0)
>>> tr = img[..., 3] > 0
>>> e = trunk_edges(img, tr)
>>> round(e.share, 2), round(e.deviation, 2)
(1.0, 0.0)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi
from scipy.stats import theilslopes

from ..core.image import as_rgba

__all__ = ["TrunkEdges", "trunk_edges", "straighten_trunk", "STRAIGHT_SHARE", "BEND_MOST"]

#: Least share of a straight trunk's free rows whose two sides lie within a pixel of their lines.
STRAIGHT_SHARE = 0.9
#: Farthest (px, or this share of the free rows' count when larger) a mixed trunk's side may stray
#: from its fitted line and still be redrawn straight: the warp's bends measure 0.5-1.5 px, a
#: crooked trunk's far more.
BEND_MOST = 3.0
BEND_SHARE = 0.05
#: Least number of free rows measured (a shorter visible trunk has no sides to speak of).
MIN_ROWS = 8


@dataclass(frozen=True)
class TrunkEdges:
    """The sides of a trunk on its free rows.

    Parameters
    ----------
    rows : ndarray
        The free rows (y), top to bottom.
    left : ndarray
        Leftmost trunk pixel (x) of each row.
    right : ndarray
        Rightmost trunk pixel (x) of each row.
    fit_left : ndarray
        The left side's fitted line at those rows.
    fit_right : ndarray
        The right side's fitted line at those rows.
    share : float
        Share of rows whose both sides lie within 1 px of their lines.
    deviation : float
        Largest distance (px) of a side from its line.
    """

    rows: np.ndarray
    left: np.ndarray
    right: np.ndarray
    fit_left: np.ndarray
    fit_right: np.ndarray
    share: float
    deviation: float


def _fit(y: np.ndarray, x: np.ndarray) -> np.ndarray:
    # Theil-Sen (median of the pairwise slopes, median intercept): a least-squares line through
    # a side the warp shifted by a pixel over a third of its rows leans, and rounded back to the
    # grid it puts the step back elsewhere; the medians follow the majority of the rows
    slope, icpt = theilslopes(x, y)[:2]
    return icpt + slope * y


def trunk_edges(image, trunk) -> TrunkEdges | None:
    """The sides of a tree's trunk on its rows free of the crown, or None when fewer than
    :data:`MIN_ROWS` such rows.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA tree; opaque where alpha >= 0.5.
    trunk : (H, W) array_like
        The trunk mask (>= 0.5 on the trunk).

    Returns
    -------
    TrunkEdges or None
        A free row's opaque pixels are one run, more than half of it trunk; the longest
        stretch of consecutive free rows is measured.

    Raises
    ------
    ValueError
        ``trunk`` not of the image's (H, W) shape.
    """
    img = as_rgba(image, name="image")
    op = img[..., 3] >= 0.5
    t = np.asarray(trunk)
    if t.shape != op.shape:
        raise ValueError(f"trunk must have the image's shape {op.shape}, got {t.shape}")
    tr = (t >= 0.5) & op
    # the row's opaque pixels, one run, mostly trunk: a few pixels of it the warp gave the crown's
    # label (at the foot, along a side) are the trunk's still
    one_run = (np.diff(np.pad(op, ((0, 0), (1, 1))).astype(np.int8), axis=1) == 1).sum(axis=1) == 1
    free = one_run & (2 * tr.sum(axis=1) > op.sum(axis=1))
    lab, n = ndi.label(free)
    if n == 0:
        return None
    sizes = np.bincount(lab)[1:]
    rows = np.flatnonzero(lab == 1 + int(np.argmax(sizes)))
    if len(rows) < MIN_ROWS:
        return None
    sub = op[rows]
    left = np.argmax(sub, axis=1).astype(np.float64)
    right = (sub.shape[1] - 1 - np.argmax(sub[:, ::-1], axis=1)).astype(np.float64)
    y = rows.astype(np.float64)
    fl, fr = _fit(y, left), _fit(y, right)
    dl, dr = np.abs(left - fl), np.abs(right - fr)
    return TrunkEdges(rows, left, right, fl, fr, float(((dl <= 1.0) & (dr <= 1.0)).mean()),
                      float(max(dl.max(), dr.max())))


def straighten_trunk(image, trunk, *, sources=None):
    """Redraw a hard-edged mix's trunk sides straight on its free rows (see the module notes).

    Parameters
    ----------
    image : (H, W, 4) array_like
        The mix (straight RGBA, binary alpha).
    trunk : (H, W) array_like
        Its trunk layer (>= 0.5 on the trunk).
    sources : (H, W) int array_like, optional
        Each pixel's source index (-1 transparent), carried to the pixels added.

    Returns
    -------
    image : (H, W, 4) float32 ndarray
    trunk : (H, W) float32 ndarray
    sources : (H, W) int ndarray or None

    Raises
    ------
    ValueError
        ``trunk`` or ``sources`` not of the image's (H, W) shape.

    Notes
    -----
    Only rows where the trunk is alone are touched, so the crown and the trunk's hidden top keep
    as made; a trunk straying more than :data:`BEND_MOST` px (or :data:`BEND_SHARE` of its free
    rows) from its lines is crooked by design and kept.
    """
    img = as_rgba(image, name="image").copy()
    h, w = img.shape[:2]
    t = np.asarray(trunk, np.float32)
    if t.shape != (h, w):
        raise ValueError(f"trunk must have the image's shape {(h, w)}, got {t.shape}")
    src = None
    if sources is not None:
        src = np.asarray(sources).astype(np.int64, copy=True)
        if src.shape != (h, w):
            raise ValueError(f"sources must have the image's shape {(h, w)}, got {src.shape}")
    t = t.copy()
    e = trunk_edges(img, t)
    if e is None or e.deviation > max(BEND_MOST, BEND_SHARE * len(e.rows)):
        return img, t, src
    xs = np.arange(w)
    for y, l0, r0, fl, fr in zip(e.rows, e.left.astype(int), e.right.astype(int), e.fit_left, e.fit_right,
                                 strict=True):
        lo, hi = int(np.clip(np.round(fl), 0, w - 1)), int(np.clip(np.round(fr), 0, w - 1))
        if hi < lo:
            continue
        want = (xs >= lo) & (xs <= hi)
        # a pixel the line adds takes the colour (and source) of the row's nearest trunk pixel
        near = np.clip(xs, l0, r0)
        row = img[y].copy()
        add = want & (img[y, :, 3] < 0.5)
        row[add, :3] = img[y, near[add], :3]
        row[add, 3] = 1.0
        row[~want] = 0.0
        img[y] = row
        t[y] = np.where(want, 1.0, 0.0)
        if src is not None:
            s = src[y].copy()
            s[add] = src[y, near[add]]
            s[~want] = -1
            src[y] = s
    return img, t, src
