"""Automatic extraction, step 3a (beyond the paper): join drawn strokes across small gaps.

Line art breaks its strokes where a tree is still one piece: a side shoot
drawn up to a stem but stopping 1-3 px short of it (a T-junction), two
strokes that meet tip to tip with a sliver of paper between them, and the
over-and-under crossings of an interlace (a Celtic knot, a vine ornament),
where the strand passing under is cut by a white gap on both sides of the
one passing over. The skeleton then has one piece per stroke, and
:func:`~branchnb.branching.skeleton_tree.skeleton_to_structure` makes each
piece a tree of its own: the Celtic vine ornament of the shared samples
came out as 15 trees, and synthesis grew about 6 short separate trees
without leaves; with the joins it is 2 trees (its two entwined stems, 4.3k
and 0.8k px, the leaves their side branches) and synthesis grows 2 long
stems. On procedural line art (``_line_art_trees``: drawings whose side
branches stop 1-3 px short, interlace vines; 200-1000 px) the exact tree
count went from 5/12 to 12/12 cases. Strokes drawn as *outlines* (two
thin lines around a white inside) are not joined into one centre line:
their ink is the outline, traced as it is.

:func:`find_stroke_joins` decides by direction continuity and by what the
straight join passes over, looking along each skeleton end's outward
heading (the mean direction of its last ``4 r`` pixels of centre line):

* **through a crossing**: another end faces it (both headings within
  ``acos(min_cos)`` of the join) and the join passes paper, one stroke of
  at most about the lines' width (the strand passing over), and paper
  again, each paper gap at most ``max_gap``; the two ends become one
  stroke passing *under* the other (the join is not connected to it);
* **tip to tip**: another end faces it across one paper gap of at most
  ``max_gap``; the two ends become one stroke;
* **T-junction**: the heading runs into another stroke after one paper gap
  of at most ``max_gap``; the end joins that stroke's centre line there and
  becomes its side branch.

Crossings and tip-to-tip joins are looked for first (an end facing a
strand that passes over it would otherwise join that strand as a side
branch). Every end is joined at most once. Ends that merely lie near
another stroke without facing it (rivers that end near each other, a
crack stopping short of another at an angle) stay apart, and so do
gaps wider than ``max_gap``.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csgraph

from ..core.validate import Real, checked
from .skeleton_tree import _skeleton_graph

__all__ = ["find_stroke_joins"]

#: Sampling step (skeleton pixels) along a candidate join.
_STEP = 0.5


def _trace(g, start: int, ys: np.ndarray, xs: np.ndarray, n_max: int) -> tuple[list[int], bool]:
    """Skeleton pixels from an end inward, at most ``n_max``, and whether a junction stopped it."""
    path = [start]
    seen = {start}
    cur = start
    for _ in range(n_max):
        nb = [int(v) for v in g.indices[g.indptr[cur]:g.indptr[cur + 1]] if int(v) not in seen]
        if not nb:
            return path, False
        if len(nb) > 1:
            # a staircase corner has two touching neighbours; a junction has neighbours apart
            yy, xx = ys[nb], xs[nb]
            if len(nb) > 2 or (np.ptp(yy) > 1) or (np.ptp(xx) > 1):
                return path, True
            nb = [nb[int(np.argmax((yy - ys[start]) ** 2 + (xx - xs[start]) ** 2))]]
        cur = nb[0]
        seen.add(cur)
        path.append(cur)
    return path, False


def _without_end_forks(sk: np.ndarray, rad: np.ndarray, r_med: float) -> np.ndarray:
    """The skeleton without its short end spurs (at most ``max(3, 1.5 r)`` pixels to a junction).

    The medial axis of a stroke cut square (the strand under a crossing) forks into the cut's two
    corners: neither fork is an end with a heading, the fork point is the stroke's end."""
    g, ys, xs = _skeleton_graph(sk)
    deg = np.diff(g.indptr)
    out = sk.copy()
    for e in np.flatnonzero(deg == 1):
        n_max = int(np.ceil(max(3.0, 1.5 * max(r_med, float(rad[ys[e], xs[e]])))))
        path, at_junction = _trace(g, int(e), ys, xs, n_max)
        if at_junction:
            out[ys[path], xs[path]] = False
    return out


def _runs(ink: np.ndarray) -> list[tuple[bool, int]]:
    """Run-length encoding of a boolean profile: ``[(value, length), ...]``."""
    if len(ink) == 0:
        return []
    cut = np.flatnonzero(np.diff(ink.astype(np.int8))) + 1
    bounds = np.r_[0, cut, len(ink)]
    return [(bool(ink[a]), int(b - a)) for a, b in zip(bounds[:-1], bounds[1:])]


def _profile(mask: np.ndarray, p0: np.ndarray, p1: np.ndarray) -> np.ndarray:
    """Ink (mask) samples every ``_STEP`` pixels on the straight line ``p0 -> p1`` ((x, y) points)."""
    d = float(np.hypot(*(p1 - p0)))
    n = max(2, int(np.ceil(d / _STEP)) + 1)
    t = np.linspace(0.0, 1.0, n)[:, None]
    q = np.rint(p0 + t * (p1 - p0)).astype(np.int64)
    h, w = mask.shape
    q[:, 0] = np.clip(q[:, 0], 0, w - 1)
    q[:, 1] = np.clip(q[:, 1], 0, h - 1)
    return mask[q[:, 1], q[:, 0]]


def _gaps(prof: np.ndarray) -> list[tuple[bool, int]] | None:
    """The runs between the leading and the trailing ink (the strokes the join starts and ends in)."""
    runs = _runs(prof)
    if len(runs) < 3 or not runs[0][0] or not runs[-1][0]:
        return None
    return runs[1:-1]


@checked(max_gap=Real(0, 100), min_cos=Real(-1, 1), scale=Real(0, 1, low_open=True))
def find_stroke_joins(skeleton, radius, mask, *, max_gap: float = 3.0, min_cos: float = 0.8,
                      scale: float = 1.0) -> list[tuple[tuple[int, int], tuple[int, int], bool]]:
    """Where drawn strokes broken at junctions and crossings continue (beyond the paper).

    Parameters
    ----------
    skeleton : (H, W) bool array_like
        One-pixel-wide centre lines (8-connected), at the working scale.
    radius : (H, W) array_like
        Half the line width at each pixel (e.g. the distance transform of
        ``mask``), at the working scale.
    mask : (H, W) bool array_like
        The ink (the lines' pixels), at the working scale.
    max_gap : float, default 3.0
        Widest paper gap joined, in full-size pixels, beyond half the
        line's width (a thick stroke's gaps are wider); 0 joins nothing.
    min_cos : float, default 0.8
        Direction continuity: an end's heading must be within
        ``acos(min_cos)`` (37 degrees) of the join.
    scale : float, default 1.0
        The maps are a ``scale`` x downscaled copy.

    Returns
    -------
    list of ((y0, x0), (y1, x1), through)
        Skeleton pixels to connect, from an end to another end or to a
        centre-line pixel of the stroke it runs into. ``through`` is True
        for a join through a crossing: it passes under the stroke between
        its ends and must not be connected to it.

    Examples
    --------
    >>> import numpy as np
    >>> ink = np.zeros((40, 80), bool); ink[18:23, 5:75] = True; ink[23:38, 38:43] = True
    >>> ink[23:26, 38:43] = False          # the shoot stops 3 px short of the stem
    >>> sk = np.zeros_like(ink); sk[20, 5:75] = True; sk[27:36, 40] = True
    >>> rad = np.where(ink, 2.5, 0.0)
    >>> [(a, b, through) for a, b, through in find_stroke_joins(sk, rad, ink)]
    [((27, 40), (20, 40), False)]
    """
    sk = np.asarray(skeleton).astype(bool)
    rad = np.asarray(radius, np.float64)
    ink = np.asarray(mask).astype(bool)
    if sk.ndim != 2 or rad.shape != sk.shape or ink.shape != sk.shape:
        raise ValueError("skeleton must be 2-D and radius and mask must have its shape")
    gap_px = max_gap * scale
    if gap_px <= 0 or not sk.any():
        return []
    r_med = float(np.median(np.maximum(rad[sk], 0.5)))
    g, ys, xs = _skeleton_graph(_without_end_forks(sk, rad, r_med))
    deg = np.diff(g.indptr)
    ends = np.flatnonzero(deg == 1)
    if len(ends) == 0:
        return []
    heads, width, own, anchor = {}, {}, {}, {}
    pts = np.column_stack([xs, ys]).astype(np.float64)
    for e in ends:
        r_e = max(r_med, float(rad[ys[e], xs[e]]))
        path, _ = _trace(g, int(e), ys, xs, int(np.ceil(3.0 * r_e + 8)))
        # the last pixels bend into a corner of a cut or into a tapering tip: the stroke's own
        # heading is read from one radius inward on
        k1 = min(int(np.ceil(r_e)), len(path) - 1)
        k2 = min(k1 + int(np.ceil(2.0 * r_e)) + 4, len(path) - 1)
        if k2 - k1 < 3:
            continue
        d = pts[path[k1]] - pts[path[k2]]
        n = float(np.hypot(*d))
        if n < 1e-9:
            continue
        e = int(e)
        heads[e] = d / n
        width[e] = float(np.max(rad[ys[path], xs[path]]))
        own[e] = set(path)
        anchor[e] = int(path[k1])
    keys = np.array(sorted(heads), np.int64)
    if len(keys) == 0:
        return []
    at = np.array([anchor[int(k)] for k in keys], np.int64)
    used: set[int] = set()
    joins: list[tuple[tuple[int, int], tuple[int, int], bool]] = []
    # pieces of the skeleton, merged as joins connect them: a join never closes a loop (the tree
    # would then be cut somewhere else, e.g. a braided channel pinched shut on a mask)
    _n, piece = csgraph.connected_components(g, directed=False)
    up = list(range(_n))

    def find(i: int) -> int:
        while up[i] != i:
            up[i] = up[up[i]]
            i = up[i]
        return i

    def link(i: int, j: int) -> bool:
        a, b = find(int(piece[i])), find(int(piece[j]))
        if a == b:
            return False
        up[a] = b
        return True

    def node(i: int) -> tuple[int, int]:
        return int(ys[i]), int(xs[i])

    # 1. end to end: tip to tip across one gap, or through a crossing (gap, a stroke, gap)
    cands = []
    for a_i, a in enumerate(keys):
        a = int(a)
        pa = pts[anchor[a]]
        reach = 6.0 * width[a] + 2.0 * (2.0 * max(width[a], r_med) + gap_px) + 6.0
        d = pts[at] - pa
        dist = np.hypot(d[:, 0], d[:, 1])
        for b_i in np.flatnonzero((dist <= reach) & (dist > 0)):
            if b_i <= a_i:
                continue
            b = int(keys[b_i])
            u = d[b_i] / dist[b_i]
            ca, cb = float(heads[a] @ u), float(-heads[b] @ u)
            if ca < min_cos or cb < min_cos:
                continue
            wa = max(width[a], width[b])
            runs = _gaps(_profile(ink, pa, pts[anchor[b]]))
            if runs is None:
                continue
            run_px = [(v, k * _STEP) for v, k in runs]
            if len(run_px) == 1 and not run_px[0][0] and run_px[0][1] <= gap_px + 1.0 + wa:
                through = False
            elif (len(run_px) == 3 and not run_px[0][0] and not run_px[2][0]
                  and max(run_px[0][1], run_px[2][1]) <= gap_px + 1.0 + 2.0 * wa
                  and run_px[1][1] <= 3.0 * max(wa, r_med) + 2.0):
                through = True
            else:
                continue
            cands.append((float(dist[b_i]) * (2.0 - ca - cb), a, b, through))
    for _score, a, b, through in sorted(cands):
        if a in used or b in used or not link(anchor[a], anchor[b]):
            continue
        used.update((a, b))
        # from end to end (a join from one radius inward would leave the tip as a stub, a root
        # candidate of its own)
        joins.append((node(a), node(b), through))
    # 2. T-junctions: the heading runs into another stroke after one small gap
    from scipy.spatial import cKDTree

    tree = cKDTree(pts)
    for a in keys:
        a = int(a)
        if a in used:
            continue
        pa = pts[anchor[a]]
        reach = 3.0 * width[a] + 2.0 * max(width[a], r_med) + gap_px + 3.0
        near = np.asarray(tree.query_ball_point(pa, reach), np.int64)
        if len(near) == 0:
            continue
        d = pts[near] - pa
        dn = np.hypot(d[:, 0], d[:, 1])
        near, d, dn = near[dn > 0], d[dn > 0], dn[dn > 0]
        cos = (d @ heads[a]) / dn
        ok = cos >= min_cos
        near, cos, dn = near[ok], cos[ok], dn[ok]
        best = None
        # nearest to the heading's ray first (its distance from the ray, a little of the distance)
        for q in near[np.argsort(dn * (np.sqrt(np.clip(1.0 - cos * cos, 0.0, 1.0)) + 0.05))]:
            if int(q) in own[a] or find(int(piece[q])) == find(int(piece[anchor[a]])):
                continue
            runs = _gaps(_profile(ink, pa, pts[q]))
            if runs is not None and len(runs) == 1 and not runs[0][0] and \
                    runs[0][1] * _STEP <= gap_px + 1.0 + width[a]:
                best = int(q)
                break
        if best is not None:
            link(anchor[a], best)
            used.add(a)
            joins.append((node(a), node(best), False))
    return joins
