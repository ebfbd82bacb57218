"""Pin points of a tree contour (paper, Sec. "Contour resampling").

``B`` is the tree bottom (the lowest contour point, the median one if several
share the lowest row). ``R`` and ``L`` are the top right and top left of the
trunk: walking along ``C`` from ``B`` to the right and to the left, the first
points that belong to the crown. With no visible trunk, ``L = R = B``. The
trunk/crown split comes from a trunk mask (the crown/trunk segmentation, or the
geometric fallback :func:`stem_trunk_mask`). Split out of
:mod:`branchnb.trees.contour`, which re-exports these names.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy.ndimage import median_filter

from ..core.image import as_mask, as_points
from ..core.validate import Array, Real, checked
from .exemplar import signed_area
from .pin_corners import corner_sides

__all__ = ["PinPoints", "stem_trunk_mask", "pin_points"]

@dataclass
class PinPoints:
    """The three pin points of a tree contour.

    Parameters
    ----------
    b, r, l : (2,) float ndarray
        Tree bottom ``B``, trunk top right ``R``, trunk top left ``L`` (x, y).
    ib, ir, il : int
        Their indices in the contour they were found on.
    has_trunk : bool
        False when no trunk is visible (then ``L = R = B``).
    """

    b: np.ndarray
    r: np.ndarray
    l: np.ndarray  # noqa: E741  (paper's symbol)
    ib: int
    ir: int
    il: int
    has_trunk: bool


@checked(alpha=Array(ndim=2), jump=Real(0, 1e3), crown_width=Real(0, 1e3), max_trunk_width=Real(0, 1e3),
         min_trunk_height=Real(0, 1e3), min_aspect=Real(0, 1e3), max_ground_height=Real(0, 1e3))
def stem_trunk_mask(alpha, *, jump: float = 2.0, crown_width: float = 0.5,
                    max_trunk_width: float = 0.45, min_trunk_height: float = 0.03,
                    min_aspect: float = 0.5, max_ground_height: float = 0.2) -> np.ndarray:
    """Geometric trunk estimate: the narrow stem at the bottom of the silhouette.

    A fallback for the crown/trunk segmentation that uses the opacity mask
    alone. Row widths ``w(y)`` (opaque pixels per row, median-filtered over
    5 rows) are read from the bottom up:

    1. Rows at least ``crown_width`` times the widest row are *wide*. Wide
       rows near the bottom (within ``max_ground_height`` of the tree) are
       a ground patch or spread roots.
    2. The *stem* is the longest run of narrow rows that starts within
       that bottom band and ends below a wide row; its width ``w_s`` is the
       median of its widths (robust to a pointed tip or flared roots).
    3. The crown baseline: walking down from that lowest wide row while
       ``w(y) > jump * w_s``; every row below it is trunk.

    No trunk is reported when the stem is shorter than
    ``min_trunk_height`` of the tree height or than ``min_aspect`` times its
    width (the rounded bottom of a round crown is no stem), wider than
    ``max_trunk_width`` of the widest row, or when the bottom rows are wide.

    Parameters
    ----------
    alpha : (H, W) array_like
        Opacity mask (nonzero = opaque).
    jump : float
        Width ratio (to the stem width) marking the crown baseline.
    crown_width : float
        Rows at least this fraction of the widest row are certainly crown.
    max_trunk_width : float
        A stem wider than this fraction of the widest row is no trunk.
    min_trunk_height : float
        A stem shorter than this fraction of the tree height is no trunk.
    min_aspect : float
        A trunk lower than this multiple of its width is no trunk.
    max_ground_height : float
        Wide bottom rows up to this fraction of the height are ground.

    Returns
    -------
    (H, W) bool ndarray
        The trunk (empty if no trunk is visible).

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((40, 30), bool); m[2:25, 3:27] = True; m[25:38, 13:17] = True
    >>> t = stem_trunk_mask(m); int(t.sum()), bool(t[30, 15]), bool(t[10, 15])
    (52, True, False)
    """
    for name, v in (("jump", jump), ("crown_width", crown_width),
                    ("max_trunk_width", max_trunk_width),
                    ("min_trunk_height", min_trunk_height), ("min_aspect", min_aspect),
                    ("max_ground_height", max_ground_height)):
        if not np.isfinite(v) or v < 0:
            raise ValueError(f"{name} must be a finite number >= 0, got {v!r}")
    m = as_mask(alpha, name="alpha")
    out = np.zeros_like(m)
    rows = np.flatnonzero(m.any(axis=1))
    if rows.size == 0:
        return out
    top, bottom = int(rows[0]), int(rows[-1])
    height = bottom - top + 1
    seg = median_filter(m[top:bottom + 1].sum(axis=1).astype(np.float64), size=5,
                        mode="nearest")
    w_max = float(seg.max())
    wide = seg >= crown_width * w_max
    n = len(seg)
    min_rows = max(min_trunk_height * height, 2.0)
    # 1. + 2. runs of narrow rows that start within the ground band at the
    # bottom and end below a wide row; the longest is the stem (wide rows
    # and short narrow runs below it are a ground patch or roots).
    best = None  # (length, stem_bottom, crown_low)
    k = n - 1
    while True:
        while k >= 0 and wide[k]:
            k -= 1
        if k < 0 or (n - 1 - k) > max_ground_height * height:
            break
        run_bottom = k
        while k >= 0 and not wide[k]:
            k -= 1
        if k < 0:
            break  # no wide row above: a bare pole, not a crown
        if best is None or run_bottom - k > best[0]:
            best = (run_bottom - k, run_bottom, k)
    if best is None or best[0] < min_rows:
        return out
    _, stem_bottom, crown_low = best
    stem = seg[crown_low + 1:stem_bottom + 1]
    w_s = float(np.median(stem))
    if w_s > max_trunk_width * w_max:
        return out
    # 3. walk down from the crown while the rows are much wider than the stem
    k = crown_low
    while k + 1 <= stem_bottom and seg[k + 1] > jump * w_s:
        k += 1
    baseline = top + k  # lowest crown row
    if (bottom - baseline) < max(min_trunk_height * height, min_aspect * w_s, 1):
        return out
    out[baseline + 1:] = m[baseline + 1:]
    return out


def _trunkness(trunk: np.ndarray, opaque: np.ndarray, points: np.ndarray, radius: int) -> np.ndarray:
    """Fraction of opaque pixels that are trunk in a window around each point."""
    h, w = opaque.shape
    if radius <= 0:
        xi = np.clip(np.round(points[:, 0]).astype(int), 0, w - 1)
        yi = np.clip(np.round(points[:, 1]).astype(int), 0, h - 1)
        return trunk[yi, xi].astype(np.float64)
    k = 2 * radius + 1
    t = cv2.boxFilter((trunk & opaque).astype(np.float32), -1, (k, k), normalize=False,
                      borderType=cv2.BORDER_CONSTANT)
    o = cv2.boxFilter(opaque.astype(np.float32), -1, (k, k), normalize=False,
                      borderType=cv2.BORDER_CONSTANT)
    xi = np.clip(np.round(points[:, 0]).astype(int), 0, w - 1)
    yi = np.clip(np.round(points[:, 1]).astype(int), 0, h - 1)
    return t[yi, xi] / np.maximum(o[yi, xi], 1.0)


def _with_trunk_rim(trunk: np.ndarray, opaque: np.ndarray, radius: int) -> np.ndarray:
    """``trunk`` plus the opaque non-trunk pixels between it and the outside (a drawn outline).

    A drawn trunk's outline is neither bark nor crown colour, so the
    segmenter leaves it out of the trunk; a 2 px outline then fills half of
    the opaque part of a window on the contour (``radius`` 4 px at 256 px),
    the trunk share along the trunk's sides falls below one half and the
    walk from ``B`` stops at once (``R`` next to ``B``). Pixels within
    ``radius`` of both the trunk and the outside count as trunk; where
    the crown meets the trunk that adds only a corner of that size.
    """
    t = trunk & opaque
    if radius <= 1 or not t.any():
        return t
    k = 2 * radius + 1
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))
    near_trunk = cv2.dilate(t.astype(np.uint8), kernel) > 0
    near_outside = cv2.dilate((~opaque).astype(np.uint8), kernel, borderValue=0) > 0
    return t | (opaque & near_trunk & near_outside)


def _close_gaps(flags: np.ndarray, max_gap: int) -> np.ndarray:
    """Fill runs of False up to ``max_gap`` long between True runs of a closed sequence.

    Clutter drawn over the trunk foot (grass blades, leaves) makes the walk
    along the trunk side meet short crown-coloured excursions; the crown
    itself is a long run.
    """
    if max_gap <= 0 or flags.all() or not flags.any():
        return flags
    start = int(np.flatnonzero(flags)[0])
    f = np.roll(flags, -start)              # starts on True
    out = f.copy()
    edges = np.flatnonzero(np.diff(f.astype(np.int8)))
    falls = edges[f[edges]]
    rises = edges[~f[edges]]
    for a in falls:
        nxt = rises[rises > a]
        end = int(nxt[0]) if nxt.size else len(f) - 1   # the last gap wraps onto f[0]
        if end - a <= max_gap:
            out[a + 1:end + 1] = True
    return np.roll(out, start)


def _bottom_middle(c: np.ndarray, opaque: np.ndarray, trunk: np.ndarray) -> int:
    """Index of ``B``: the contour point nearest the middle of the trunk's base.

    The base is the bottom 5 % of the tree height. Its span is that of the
    trunk pixels there (of the opaque pixels without a trunk); ``B`` is the
    point of the contour within the band nearest the bottom middle of the
    span. A base cut at a slant, or standing on two feet with an arch
    between them, has its lowest point at a corner, not in the middle.
    """
    ymax = c[:, 1].max()
    height = ymax - c[:, 1].min()
    y_lo = ymax - max(0.5, 0.05 * height)
    band = np.flatnonzero(c[:, 1] >= y_lo)
    rows = slice(max(0, int(np.ceil(y_lo))), int(ymax) + 1)
    base = (trunk & opaque)[rows]
    if not base.any():
        base = opaque[rows]
    cols = np.flatnonzero(base.any(axis=0))
    if cols.size == 0:
        x_mid = 0.5 * (c[band, 0].min() + c[band, 0].max())
    else:
        x_mid = 0.5 * (cols[0] + cols[-1])
    return int(band[np.argmin(np.hypot(c[band, 0] - x_mid, c[band, 1] - ymax))])


def pin_points(contour, alpha, trunk_mask=None, *, radius: float = 0.015, corners: bool = True) -> PinPoints:
    """Find the pin points ``B``, ``R``, ``L`` on a tree contour.

    Parameters
    ----------
    contour : (K, 2) array_like
        The tree contour ``C`` (closed, counter-clockwise on screen as
        returned by :func:`~branchnb.trees.exemplar.extract_contours`;
        the orientation is fixed here if not).
    alpha : (H, W) array_like
        Opacity mask of the tree.
    trunk_mask : (H, W) array_like, optional
        Trunk pixels (from the crown/trunk segmentation). None uses
        :func:`stem_trunk_mask`.
    radius : float
        Window radius (fraction of the image size) for labelling contour
        points as trunk or crown.
    corners : bool
        Move ``R`` and ``L`` back to the concave corner where a crown
        narrowing onto its trunk meets it
        (:func:`~branchnb.trees.pin_corners.corner_sides`, beyond the paper).
        Off for pixel art, whose stair steps are corners of their own.

    Returns
    -------
    PinPoints
        Indices refer to ``contour`` (after orientation).

    Notes
    -----
    ``B`` is the bottom of the tree: of the contour points within 5 % of
    the height of the lowest row, the one nearest the bottom middle of the
    trunk's span there (the paper: the lowest point; a trunk base cut at a
    slant, or standing on two feet, would put that at a corner); when that point is not trunk (clutter drawn over the
    trunk foot) but a trunk point lies within 5 % of the height above it,
    the lowest trunk point is ``B``. If ``B`` is not on the trunk, or the walk from ``B`` never
    reaches the crown (a bare tree that is all trunk), no trunk is visible
    and ``L = R = B``. Beyond the paper: when a side's walk fails (it ends
    at the foot, or is under a quarter of the other side), the trunk's
    drawn outline, which a segmentation leaves out of the trunk, is counted
    as trunk and the walk is redone.

    Examples
    --------
    >>> from branchnb.trees.exemplar import extract_contours
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> t = synthetic_tree("clean", rng=0, size=64)   # true pins in t.pins
    >>> alpha = t.image[..., 3] >= 0.5
    >>> pins = pin_points(extract_contours(alpha).tree, alpha, t.labels == 2)
    >>> pins.has_trunk, pins.b.tolist(), t.pins["B"]
    (True, [33.0, 62.0], (33.0, 62.0))
    """
    c = as_points(contour, name="contour", min_points=3)
    opaque = as_mask(alpha, name="alpha")
    if signed_area(c) > 0:
        c = c[::-1]
    trunk = (stem_trunk_mask(opaque) if trunk_mask is None
             else as_mask(trunk_mask, shape=opaque.shape, name="trunk_mask"))
    k = len(c)
    ymax = c[:, 1].max()
    ib = _bottom_middle(c, opaque, trunk)
    b = c[ib]
    none = PinPoints(b.copy(), b.copy(), b.copy(), ib, ib, ib, False)
    if not (trunk & opaque).any():
        return none
    r_px = int(round(radius * max(opaque.shape)))
    is_trunk = _trunkness(trunk, opaque, c, r_px) >= 0.5
    if not is_trunk[ib]:
        # Clutter drawn over the trunk foot (grass blades, leaves): B is the
        # lowest trunk point of the contour if it is near the bottom.
        height = ymax - c[:, 1].min()
        cand = np.flatnonzero(is_trunk & (c[:, 1] >= ymax - 0.05 * height))
        if cand.size == 0:
            return none
        y_low = c[cand, 1].max()
        low = cand[c[cand, 1] >= y_low - 0.5]
        ib = int(low[np.argsort(c[low, 0], kind="stable")[(len(low) - 1) // 2]])
        b = c[ib]
        none = PinPoints(b.copy(), b.copy(), b.copy(), ib, ib, ib, False)
    height = ymax - c[:, 1].min()
    max_gap = int(0.3 * height)
    sides = _trunk_sides(_close_gaps(is_trunk, max_gap), ib)
    if sides is not None and _failed_sides(c, ib, sides, height):
        # A side stops at once or at the foot: a drawn outline may be taking the trunk's
        # share (see _with_trunk_rim). Counting it as trunk is kept only where it helps.
        rim = _trunkness(_with_trunk_rim(trunk, opaque, r_px), opaque, c, r_px) >= 0.5
        retry = _trunk_sides(_close_gaps(rim | is_trunk, max_gap), ib)
        if retry is not None and (_failed_sides(c, ib, retry, height)
                                  < _failed_sides(c, ib, sides, height)):
            sides = retry
    if sides is None:
        return none
    jr, jl = corner_sides(c, ib, sides, height) if corners else sides
    ir, il = (ib + jr) % k, (ib - jl) % k
    return PinPoints(b.copy(), c[ir].copy(), c[il].copy(), ib, ir, il, True)


#: A trunk side walked from ``B`` shorter than this share of the other is taken as a failed walk.
_LOPSIDED = 0.25
#: ... as is a side whose end rises less than this share of the tree's height above ``B``.
_LOW_SIDE = 0.05


def _failed_sides(c: np.ndarray, ib: int, sides: tuple[int, int], height: float) -> int:
    """How many of the walked trunk sides look like a failed walk (0, 1 or 2)."""
    jr, jl = sides
    k = len(c)
    low = [c[ib, 1] - c[(ib + jr) % k, 1] < _LOW_SIDE * height,
           c[ib, 1] - c[(ib - jl) % k, 1] < _LOW_SIDE * height]
    if min(jr, jl) < _LOPSIDED * max(jr, jl):
        low[int(jl < jr)] = True
    return int(sum(low))


def _trunk_sides(is_trunk: np.ndarray, ib: int) -> tuple[int, int] | None:
    """Steps from ``B`` to the first crown point on the right and on the left (None: no crown)."""
    k = len(is_trunk)
    fwd = np.roll(is_trunk, -ib)            # fwd[j] = point ib + j (to the right)
    stop_r = np.flatnonzero(~fwd)
    if stop_r.size == 0:
        return None
    jr = int(stop_r[0])
    bwd = fwd[::-1]                          # bwd[j] = point ib - 1 - j
    jl = int(np.flatnonzero(~bwd)[0]) + 1    # steps backwards
    if jr + jl >= k - 2:
        return None
    return jr, jl
