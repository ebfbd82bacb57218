"""A drawn map's dotted or dashed coast: recognised as a coast and drawn with its dashes.

Beyond the paper (issue 23). :func:`~branchnb.branching.drawing.drawing_style`
took a coast for drawn when ink lay beside at least half of the branch
region's edge: a dotted coast (dots a few pixels apart) or a dashed one
with long gaps fell under that share, and was no coast; one that passed
was drawn as a solid line (or, through its median colour profile, not at
all: the median across a dotted line is the ground).

- :func:`coast_dashes` walks the example's coast (the outline of the branch
  region, away from the branches and the frame), marks where ink lies on it
  and reads the runs of ink and of gaps along the arc length: a regular
  rhythm of dashes and gaps that together span nearly the whole coast is a
  dashed coast of that period and dash length.
- :func:`paint_dashes` draws the same rhythm along the output's own coast:
  one anti-aliased stroke per dash (a dash no longer than the line is wide
  is a round dot).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

__all__: list[str] = []

#: A coast is dashed when its ink covers less than this share of its outline ...
MAX_ON_SHARE = 0.85
#: ... and its runs of ink and gap, together, read at least this share of it (walls of ink and
#: long gaps, a coast drawn along part of the land only, are no rhythm) ...
MIN_RHYTHM = 0.9
#: ... and no more than this share of its gaps is longer than three periods.
MAX_LONG_GAPS = 0.1


def _outlines(inside: np.ndarray) -> list[np.ndarray]:
    """The outlines of ``inside`` as closed (N, 2) integer (x, y) pixel chains."""
    cnts, _ = cv2.findContours(np.asarray(inside, np.uint8), cv2.RETR_LIST, cv2.CHAIN_APPROX_NONE)
    return [c[:, 0] for c in cnts if len(c) >= 8]


def _arc(chain: np.ndarray) -> np.ndarray:
    """Arc length at every point of a chain (from its first point)."""
    step = np.hypot(*np.diff(chain.astype(float), axis=0).T)
    return np.r_[0.0, np.cumsum(step)]


def _runs(flags: np.ndarray) -> list[tuple[bool, int, int]]:
    """Runs ``(value, start, stop)`` of a boolean sequence."""
    cut = np.flatnonzero(np.diff(flags.astype(np.int8))) + 1
    starts = np.r_[0, cut]
    stops = np.r_[cut, len(flags)]
    return [(bool(flags[a]), int(a), int(b)) for a, b in zip(starts, stops)]


def _marked_outline(inside: np.ndarray, ink: np.ndarray, reach: float) -> tuple[list, np.ndarray]:
    """The outline chains of ``inside`` and the (H, W) mask of its pixels nearest to an ``ink`` pixel
    within ``reach``: a dash marks its own length of the outline (a dilation by the line's reach
    lengthened every dash and closed a dotted line's gaps)."""
    chains = _outlines(inside)
    near = np.zeros(inside.shape, bool)
    if not chains:
        return chains, near
    outline = np.zeros(inside.shape, bool)
    for chain in chains:
        outline[chain[:, 1], chain[:, 0]] = True
    dist, (iy, ix) = ndi.distance_transform_edt(~outline, return_indices=True)
    hit = np.asarray(ink, bool) & (dist <= reach)
    near[iy[hit], ix[hit]] = True
    return chains, near


def coast_dashes(inside: np.ndarray, ink: np.ndarray, usable: np.ndarray, width: float = 2.0,
                 min_length: float = 60.0) -> tuple[float, float] | None:
    """The rhythm ``(period, dash)`` of a dashed or dotted line along the edge of ``inside``, in pixels
    of arc length, or None when the line (if any) is not dashed.

    Parameters
    ----------
    inside : (H, W) bool array
        The branch region (the land).
    ink : (H, W) bool array
        Pixels drawn in the coast's colour (those within ``width / 2 + 1.5`` px of the outline
        mark the outline pixel nearest to them).
    usable : (H, W) bool array
        Where the outline is read (away from the branches and the frame).
    width : float, default 2.0
        The line's width.
    min_length : float, default 60.0
        Smallest length of usable outline read.

    Returns
    -------
    (period, dash) or None

    Notes
    -----
    Each run of outline pixels inside ``usable`` is split into runs of ink
    and gap. Runs at either end of a usable stretch are cut short and not
    read. The coast is dashed when ink covers less than
    :data:`MAX_ON_SHARE` of the outline, its inner runs cover at least
    :data:`MIN_RHYTHM` of it with gaps no longer than three periods (all but
    :data:`MAX_LONG_GAPS` of them); the period is the median length of a dash
    plus the gap after it.
    """
    m = np.asarray(inside, bool)
    if not m.any() or m.all():
        return None
    chains, near = _marked_outline(m, ink, width / 2.0 + 1.5)
    if not chains:
        return None
    use = np.asarray(usable, bool)
    dashes, gaps, total, read = [], [], 0.0, 0.0
    for chain in chains:
        s = _arc(chain)
        ok = use[chain[:, 1], chain[:, 0]]
        on = near[chain[:, 1], chain[:, 0]]
        for good, a, b in _runs(ok):
            if not good or s[b - 1] - s[a] < 4 * width + 8:
                continue
            total += s[b - 1] - s[a]
            runs = _runs(on[a:b])
            for v, ra, rb in runs[1:-1]:
                # (from its first pixel to the next run's: a diagonal step between runs is 1.4 px)
                length = s[a + rb] - s[a + ra]
                (dashes if v else gaps).append(length)
                read += length
    if total < min_length or len(dashes) < 4 or len(gaps) < 4:
        return None
    dashes, gaps = np.asarray(dashes), np.asarray(gaps)
    on_share = dashes.sum() / max(dashes.sum() + gaps.sum(), 1e-9)
    period = float(np.median(dashes) + np.median(gaps))
    if on_share >= MAX_ON_SHARE or read < MIN_RHYTHM * total or np.mean(gaps > 3 * period) > MAX_LONG_GAPS:
        return None
    return period, float(np.median(dashes))


def dashed_coast(img: np.ndarray, inside: np.ndarray, pm, margin: float, off_region: np.ndarray,
                 cols: np.ndarray, tol: float):
    """The dashed or dotted line drawn along the edge of ``inside``: ``(colour, width, (period, dash))``,
    or None when the edge bears none.

    Parameters
    ----------
    img : (H, W, C) float array
        The example.
    inside : (H, W) bool array
        Its branch region.
    pm : PixelMap
        Its structure's pixel map (the edge within ``margin`` of a branch is not read).
    margin : float
        Distance from the branches (pixels).
    off_region : (H, W) float array
        Each pixel's colour distance from its region's colour.
    cols : (k, C) array
        The region colours (a line of one of them is no coast).
    tol : float
        A pixel is ink when it lies farther than ``tol`` from its region's colour.

    Returns
    -------
    (colour, width, (period, dash)) or None

    Notes
    -----
    Ink must gather along the edge: its density within 4 px of it at least
    four times that 6-14 px off it (a sea hatched with dashes everywhere is
    marked, not drawn along its coast).
    """
    m = np.asarray(inside, bool)
    h, w = m.shape
    edge = m & ndi.binary_dilation(~m) | ~m & ndi.binary_dilation(m)
    edge[:3] = edge[-3:] = False
    edge[:, :3] = edge[:, -3:] = False
    edge &= pm.dist > margin
    if np.count_nonzero(edge) < 40:
        return None
    d_edge = ndi.distance_transform_edt(~edge)
    away = pm.dist > pm.radius + 1.5
    band = (d_edge <= 4) & away
    ring = (d_edge >= 6) & (d_edge <= 14) & (pm.dist > margin)
    unlike = off_region > tol
    ink = band & unlike
    if np.count_nonzero(ink) < 10 or not ring.any():
        return None
    if ink.sum() / band.sum() < 4 * float(unlike[ring].mean()) + 0.02:
        return None
    strong = ink & (off_region >= np.percentile(off_region[ink], 67))
    colour = np.median(img[strong], axis=0)
    if np.min(np.linalg.norm(np.asarray(cols, np.float32) - colour, axis=-1)) < tol:
        return None
    drawn = band & (np.linalg.norm(img - colour, axis=-1) < tol)
    if np.count_nonzero(drawn) < 10:
        return None
    # the width: the ink (anti-aliased pixels in part) over the length of outline it marks
    span = np.linalg.norm(np.asarray(cols, np.float32)[None, None] - colour, axis=-1).min(-1)
    cover = np.clip(off_region / np.maximum(span, 1e-6), 0.0, 1.0) * (band & unlike | drawn)
    _chains, marked = _marked_outline(m, drawn, 4.0)
    width = float(np.clip(cover.sum() / max(np.count_nonzero(marked), 1), 1.0, 16.0))
    usable = np.ones((h, w), bool)
    usable[:3] = usable[-3:] = False
    usable[:, :3] = usable[:, -3:] = False
    usable &= pm.dist > margin
    rhythm = coast_dashes(m, drawn, usable, width)
    if rhythm is None:
        return None
    return colour.astype(np.float32), width, rhythm


def paint_dashes(img: np.ndarray, inside: np.ndarray, colour, width: float, period: float,
                 dash: float) -> np.ndarray:
    """``img`` with a dashed line of ``colour`` along the edge of ``inside`` (not the frame).

    Parameters
    ----------
    img : (H, W, C) float array
        The drawn output so far.
    inside : (H, W) bool array
        The land (its outline is the coast).
    colour : (C,) array_like
        The coast's ink.
    width : float
        Line width (pixels).
    period, dash : float
        From :func:`coast_dashes`: a dash of ``dash`` pixels every ``period`` pixels of arc length.

    Returns
    -------
    (H, W, C) float32 ndarray
        A copy of ``img``.
    """
    if period <= 0 or dash <= 0:
        raise ValueError(f"period and dash must be > 0, got {period} and {dash}")
    out = np.array(img, np.float32, copy=True)
    m = np.asarray(inside, bool)
    h, w = m.shape
    cover = np.zeros((h, w), np.float32)
    thick = max(int(round(width)), 1)
    # a dot's stroke is its own width long: the stroke is drawn from centre to centre
    inner = max(dash - width, 0.0)
    for chain in _outlines(m):
        s = _arc(chain)
        frame = (chain[:, 0] <= 0) | (chain[:, 1] <= 0) | (chain[:, 0] >= w - 1) | (chain[:, 1] >= h - 1)
        for start in np.arange(0.5 * period, s[-1], period):
            k0, k1 = np.searchsorted(s, [start, start + inner])
            k1 = min(max(k1, k0), len(chain) - 1)
            if k0 >= len(chain) or frame[k0:k1 + 1].any():
                continue
            seg = chain[k0:k1 + 1] if k1 > k0 else chain[[k0, k0]]
            cv2.polylines(cover, [np.int32(seg * 4)], False, 1.0, thick, cv2.LINE_AA, shift=2)
    cover = np.clip(cover, 0.0, 1.0)[..., None]
    out[...] = out * (1 - cover) + cover * np.asarray(colour, np.float32)
    return out
