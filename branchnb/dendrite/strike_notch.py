"""Touching objects of one colour cut apart between the notches of their outline (issue 25,
dendrite43; beyond the papers). Used by :func:`~branchnb.dendrite.strike_outline.outline_parts`
after :func:`~branchnb.dendrite.strike_outline.split_by_shape`.

The distance map's watershed of :func:`~branchnb.dendrite.strike_outline.split_by_shape` needs a
neck; a 2 x 2 cluster of discs has none (its middle fills in and is its deepest point) and
neither do bold letters touching side by side (their join is as wide as two strokes). Both
still show where they meet on their outline: a sharp notch, where the outline turns back on
itself. :func:`split_at_notches` cuts a piece along a straight segment from such a notch,
inside the piece, when

* both ends are sharp notches and both sides are round (convex) parts: discs, fruits,
  pebbles in a cluster (:data:`NOTCH_ROUND_SOLID`), or
* the piece is a row of strokes (a word: at least :data:`NOTCH_ROW_ASPECT` times as long as it
  is high and :data:`NOTCH_ROW_STROKES` stroke widths high) and the cut, from a notch sharper
  than :data:`NOTCH_ROW_ANGLE`, crosses at most :data:`NOTCH_ROW_CUT` stroke widths, each side
  at least :data:`NOTCH_ROW_SIDE` of the row's height long: a letter's join to its neighbour.
  A single letter ("M", "W") is no row and stays whole; so do worms and bananas (their
  bends are no sharp notches). Every notch under an edge of the convex hull counts here,
  not only its deepest, and a cut whose far end meets another notch sharper than
  :data:`NOTCH_ROW_MEET_ANGLE` (two letters' outlines crossing above and below their join)
  is taken before shorter ones (strokes41: along a word's straight top only an "M"'s or an
  "N"'s inner corner was found, and the shortest cut from it ran inside the letter).

A ring of round parts round a hole (:func:`split_round_hole`) is cut from every notch of its
outline to the corner of the hole it faces (strokes41).

Measured (session scripts of strokes41, not kept; parts == letters with both shares > 0.9): 17 words
(HAM MOON FERN GO MAPLE WAVE TREES NEW MAX WIND ZOOM KNOW M W N K A) in Hershey duplex at
256 / 512 / 768 px and simplex and triplex at 256 / 768 px, 119 cases, 84 -> 92 exact and
none worse: "MOON" (6 parts, 0.53-0.55 -> 4 parts, 0.99) and "ZOOM" at 512 / 768 px. Rings of
4-8 bumpy discs, centres 1.15-1.9 radii apart, 256 / 768 px: 6 discs 1.25 apart at 256 px 5
-> 6 parts (agreement 0.50 -> 0.69), 1.15 apart at 768 px 1 -> 6 (0.24 -> 0.59), none worse.
Letters whose join shows no notch (a "Z" and an "O" at 256 px) stay one part.

dendrite46 (rings of 6 / 8 / 10 bumpy beads 1.2 / 1.5 / 1.8
radii apart spanning 0.9 / 0.6 / 0.4 of the picture, 2 x 2 and 3 x 3 clusters 1.15-1.8 radii
apart, at 256 / 512 / 768 px; exact == as many parts as beads and agreement > 0.6). Beads
under ``OUTLINE_MIN_PART`` of the picture are cut at a floor of
:data:`~branchnb.dendrite.strike_outline.OUTLINE_PART_SHARE` of their piece (when it
comes apart into ``OUTLINE_PART_COUNT`` or more): rings 35 -> 61
of 81 exact (10 beads 1.8 radii apart at 512 px 2 parts, 0.15 -> 10, 0.95). A cluster whose
middle fills in (its inscribed radius ~1.4 discs') has its notches read again at
:data:`NOTCH_CLUSTER_SCALE` of it, and a sharp notch whose partner stays blunt is cut along
its halving line when that crosses a cut already made: 2 x 2 clusters 13 -> 22 of 24 exact,
all 24 in 4 parts (1.15 radii apart at 512 px 1 part, 0.36 -> 4, 0.63; the ground truth gives
each overlap to one disc, the cut halves it). The 119 word cases above unchanged. Limits:
beads overlapping to 1.2 radii apart in a ring (4 -> 7 of 27 exact; 10 such beads at 256 /
768 px, 3 of 6, stay one part; 6 at 768 px spanning 0.4, 3 -> 6 parts, 0.45 -> 0.39) and
3 x 3 clusters 1.3 radii apart or closer (the middle disc never reaches the outline: 1-3
parts at 0.16-0.24 -> 2-10 parts at 0.20-0.36, some cuts inside discs) stay wrong;
3 x 3 clusters 1.5 radii apart or more come apart as before.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

__all__: list[str] = []

#: Sharpest outline angle (degrees, between the outline 0.35 inscribed radii to either side) at
#: a notch that :func:`split_at_notches` cuts from between round parts: two discs meeting at
#: 1.4 radii make ~105-140, a bumpy blob's dents and a capsule's sides ~165-180.
NOTCH_ROUND_ANGLE = 145.0
#: Share of the piece's inscribed radius at which :func:`split_at_notches` reads round parts'
#: notches again when none qualified (dendrite46): a 2 x 2 cluster 1.15 radii apart is ~1.4
#: discs' radii deep in its middle, its notches read ~140-155 degrees there.
NOTCH_CLUSTER_SCALE = 0.7
#: Least depth of a notch (below the convex hull) over the piece's inscribed radius.
NOTCH_DEPTH = 0.1
#: Largest angle (degrees) between a cut between round parts and either notch's halving line.
NOTCH_ROUND_AIM = 30.0
#: Least solidity (area over convex hull area) of both sides of a cut between round parts
#: (two overlapping discs ~0.96-0.99; halves of a bold letter 0.75-0.91).
NOTCH_ROUND_SOLID = 0.93
#: A row of strokes is at least this many times as long as it is high (two bold capitals
#: touching 1.75-2, one 1.0-1.2, a lowercase "m" 1.56)...
NOTCH_ROW_ASPECT = 1.7
#: ... and at least this many stroke widths high (a bold word ~5; a worm ~3, a capsule 1).
NOTCH_ROW_STROKES = 3.0
#: Sharpest angle at a notch from which a row is cut (letter joins 20-70, worms' bends 135+).
NOTCH_ROW_ANGLE = 100.0
#: Longest cut across a row, in stroke widths (a join of two letters 0.7-1.7).
NOTCH_ROW_CUT = 2.0
#: Largest angle (degrees) between a cut across a row and the row's normal.
NOTCH_ROW_ACROSS = 30.0
#: Largest angle (degrees) between a cut across a row and its notch's halving line
#: (strokes41: a letter's join ~0-20, a cut beside an "M"'s or "N"'s inner "V" 60+).
NOTCH_ROW_AIM = 45.0
#: Distance (stroke widths) from a cut's far end to another sharp notch within which the cut
#: runs notch to notch and is preferred to shorter ones (strokes41).
NOTCH_ROW_MEET = 0.35
#: Sharpest angle (degrees) at both notches of such a cut (two letters' outlines crossing
#: 19-53; the "V"s above and below an "X"'s crossing 66-74).
NOTCH_ROW_MEET_ANGLE = 60.0
#: Most holes of at least :data:`NOTCH_RING_HOLE` squared inscribed radii in a piece that
#: :func:`split_round_hole` cuts (a ring round one hole, its beads' own holes; not a texture).
NOTCH_RING_HOLES = 12
#: Least area of a hole whose corners :func:`split_round_hole` reads, in squared inscribed
#: radii of the piece (6 discs 1.15 radii apart round a hole of ~0.07).
NOTCH_RING_HOLE = 0.02
#: Least length of each side of a cut row along it, over the row's height (a narrow letter
#: such as "I" ~0.3).
NOTCH_ROW_SIDE = 0.25


def _outline(piece: np.ndarray) -> np.ndarray:
    import cv2

    cs, _ = cv2.findContours(piece.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    return max(cs, key=len)[:, 0, :].astype(np.int64) if cs else np.zeros((0, 2), np.int64)


def _notches(c: np.ndarray, least_depth: float, reach: int,
             every: bool = False) -> list[tuple[int, float, np.ndarray]]:
    """Indices along the outline ``c`` of its notches at least ``least_depth`` below the
    convex hull, with their angle (degrees) between the outline ``reach`` points away and the
    unit vector halving it into the piece.

    OpenCV's convexity defects give one notch per edge of the hull, its deepest: along a
    word's straight top every join of two letters lies under one edge, and only the deepest
    notch (an "N"'s inner corner) was found. With ``every`` each point under an edge that is
    the deepest within ``reach`` points either side (the first of a flat bottom) is a notch
    too (strokes41).
    """
    import cv2

    if len(c) < 8:
        return []
    hull = cv2.convexHull(c.astype(np.int32), returnPoints=False, clockwise=False)
    try:
        d = cv2.convexityDefects(c.astype(np.int32), hull)
    except cv2.error:  # a self-touching outline: its hull indices are not monotone
        return []
    if d is None:
        return []
    n = len(c)
    picks = []
    for s0, e0, f, s in d.reshape(-1, 4):
        if s / 256.0 < least_depth:
            continue
        picks.append(int(f))
        if not every:
            continue
        k = (int(s0) + np.arange((int(e0) - int(s0)) % n + 1)) % n
        p, q = c[int(s0)].astype(float), c[int(e0)].astype(float)
        t = (q - p) / max(float(np.hypot(*(q - p))), 1e-9)
        depth = np.abs((c[k, 0] - p[0]) * t[1] - (c[k, 1] - p[1]) * t[0])
        top = ndimage.maximum_filter1d(depth, 2 * reach + 1, mode="constant")
        cand = np.flatnonzero((depth >= top) & (depth >= least_depth))
        for r in cand[np.r_[True, np.diff(cand) > reach]] if cand.size else []:
            gap = abs(int(k[r]) - int(f)) % n
            if min(gap, n - gap) > reach:
                picks.append(int(k[r]))
    out = []
    for f in picks:
        a = c[(f - reach) % n] - c[f]
        b = c[(f + reach) % n] - c[f]
        la, lb = max(float(np.linalg.norm(a)), 1e-9), max(float(np.linalg.norm(b)), 1e-9)
        cos = float(a @ b) / (la * lb)
        # the outline either side of a notch bends outwards: its halving line points in
        into = -(a / la + b / lb)
        into = into / max(float(np.linalg.norm(into)), 1e-9)
        out.append((int(f), float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))), into))
    return out


def _area_solidity(pts: np.ndarray) -> tuple[float, float]:
    import cv2

    p = pts.astype(np.float32)
    a = abs(float(cv2.contourArea(p)))
    h = float(cv2.contourArea(cv2.convexHull(p)))
    return a, a / max(h, 1e-9)


def _inside(piece: np.ndarray, p: np.ndarray, q: np.ndarray) -> bool:
    t = np.linspace(0.0, 1.0, max(2, int(np.hypot(*(q - p))) + 1))
    xy = np.rint(p[None] + t[:, None] * (q - p)[None]).astype(int)
    return bool(piece[xy[:, 1], xy[:, 0]].all())


def _cut(piece: np.ndarray, segments: list, least: float) -> np.ndarray | None:
    """Labels 1..n of ``piece`` cut along the segments ``(p, q)`` (None when they do not part
    it into two or more pieces of at least ``least`` pixels); the segments' pixels and the
    crumbs go to the nearest piece."""
    import cv2

    line = np.zeros(piece.shape, np.uint8)
    for p, q in segments:
        cv2.line(line, (int(p[0]), int(p[1])), (int(q[0]), int(q[1])), 1, 3)
    lab, n = ndimage.label(piece & (line == 0), np.ones((3, 3), bool))
    if n < 2:
        return None
    sizes = np.bincount(lab.ravel())[1:]
    big = np.flatnonzero(sizes >= least)
    if big.size < 2:
        return None
    seeds = np.zeros(piece.shape, np.int64)
    for k, b in enumerate(big, 1):
        seeds[lab == b + 1] = k
    _, (iy, ix) = ndimage.distance_transform_edt(seeds == 0, return_indices=True)
    return np.where(piece, seeds[iy, ix], 0)


def split_at_notches(piece: np.ndarray, least: float) -> np.ndarray | None:
    """Labels (1..n; 0 off ``piece``) of ``piece`` cut along straight segments from a
    sharp notch of its outline (a 2 x 2 cluster of discs, letters of a bold word touching side
    by side), or None when no cut qualifies (see the module's rules).

    Parameters
    ----------
    piece : (H, W) bool ndarray
        One connected part of a silhouette.
    least : float
        Least pixels of each side.

    Returns
    -------
    (H, W) int ndarray or None

    Notes
    -----
    Beyond the papers (dendrite43). Of the cuts between two sharp notches whose sides are
    both round the one with the roundest sides is taken; else, on a row of strokes, the
    shortest cut from a sharp notch. Applied again on the sides (by
    :func:`~branchnb.dendrite.strike_outline.outline_parts`), a cluster comes apart disc by
    disc and a word letter by letter (or in pairs of letters that are no row any more).

    Examples
    --------
    >>> y, x = np.mgrid[0:120, 0:120]
    >>> four = np.zeros((120, 120), bool)
    >>> for cx in (42, 78):
    ...     for cy in (42, 78):
    ...         four |= np.hypot(x - cx, y - cy) < 28
    >>> out = split_at_notches(four, 300)
    >>> int(out.max()), len({int(out[30, 30]), int(out[30, 90]), int(out[90, 30]), int(out[90, 90])})
    (4, 4)
    >>> split_at_notches(np.hypot(x - 60, y - 60) < 40, 300) is None  # a disc
    True
    """
    import cv2

    piece = np.asarray(piece, bool)
    if piece.ndim != 2:
        raise ValueError(f"piece must be 2-D, got shape {piece.shape}")
    if piece.sum() < 2 * least:
        return None
    depth = ndimage.distance_transform_edt(np.pad(piece, 1))[1:-1, 1:-1]
    rin = float(depth.max())
    if rin < 2.0:
        return None
    from skimage.morphology import skeletonize

    axis = skeletonize(piece) & (depth > 0)
    stroke = 2.0 * float(np.median(depth[axis])) if axis.any() else 2.0 * rin
    c = _outline(piece)
    n = len(c)
    # the notch's angle is read a third of the inscribed radius away (a quarter stroke width
    # on a bold letter; the skeleton of a symmetric cluster can shrink to a point)
    notches = _notches(c, NOTCH_DEPTH * rin, max(3, int(round(0.35 * rin))))
    if not notches:
        return None
    step = max(1, n // 400)  # a 1000-px outline's every pixel is not needed as a cut's end
    idx = np.arange(0, n, step)

    def sides(i: int, j: int) -> tuple[float, float, float, float]:
        a, b = (i, j) if i < j else (j, i)
        return (*_area_solidity(c[a:b + 1]), *_area_solidity(np.vstack([c[b:], c[:a + 1]])))

    # round parts: cuts between two sharp notches, both sides convex, that run into the
    # piece along both notches' halving lines (a cut from one disc's notch to the next
    # disc's slices a disc off a 2 x 2 cluster's diagonal and leaves the other two joined);
    # all made at once (the cluster's two cuts cross in its middle)
    aim = np.cos(np.radians(NOTCH_ROUND_AIM))
    cand = notches
    for again in (False, True):
        if again:
            # a cluster whose middle fills in is deeper there than its parts are: its
            # notches read again at a part's scale, every one under a hull edge (dendrite46)
            r2 = NOTCH_CLUSTER_SCALE * rin
            cand = _notches(c, NOTCH_DEPTH * r2, max(3, int(round(0.35 * r2))), every=True)
        segments = []
        sharp = [nt for nt in cand if nt[1] <= NOTCH_ROUND_ANGLE]
        for u in range(len(sharp)):
            for v in range(u + 1, len(sharp)):
                (i, _, di), (j, _, dj) = sharp[u], sharp[v]
                e = (c[j] - c[i]) / max(float(np.hypot(*(c[j] - c[i]))), 1e-9)
                if min(float(di @ e), float(-(dj @ e))) < aim:
                    continue
                a1, s1, a2, s2 = sides(i, j)
                if min(a1, a2) < least or min(s1, s2) < NOTCH_ROUND_SOLID or not _inside(piece, c[i], c[j]):
                    continue
                segments.append((c[i], c[j]))
        # a sharp notch whose partner across a filled middle is too blunt to count (a 2 x 2
        # cluster's fourth notch on a bumpy disc): cut straight in along its halving line to
        # the far outline where that crosses a cut already made and leaves two round sides
        # (dendrite46; an apple's dent crosses no cut)
        used = {tuple(int(v) for v in p) for seg in segments for p in seg}
        for i, _, di in (sharp if segments else []):
            if tuple(int(v) for v in c[i]) in used:
                continue
            q = _ray_end(piece, c[i], di)
            if q is None or not any(_crosses(c[i], q, p0, p1) for p0, p1 in segments):
                continue
            j = int(np.argmin(np.hypot(*(c - q).T)))
            a1, s1, a2, s2 = sides(i, j)
            if min(a1, a2) >= least and min(s1, s2) >= NOTCH_ROUND_SOLID:
                segments.append((c[i], c[j]))
        if segments:
            out = _cut(piece, segments, least)
            if out is not None:
                return out
    # a row of strokes: the shortest cut from a sharp notch that leaves two long sides
    (_, _), (rw, rh), _ = cv2.minAreaRect(c.astype(np.float32))
    long, high = max(rw, rh), min(rw, rh)
    if long < NOTCH_ROW_ASPECT * high or high < NOTCH_ROW_STROKES * stroke:
        return None
    (cx, cy), (ex, ey) = _axis(c)
    along = (c[:, 0] - cx) * ex + (c[:, 1] - cy) * ey
    cands = []
    across = np.sin(np.radians(NOTCH_ROW_ACROSS))
    aim = np.cos(np.radians(NOTCH_ROW_AIM))
    every = [nt for nt in _notches(c, NOTCH_DEPTH * rin, max(3, int(round(0.35 * rin))), every=True)
             if nt[1] <= NOTCH_ROW_ANGLE]
    near = max(2.0, NOTCH_ROW_MEET * stroke)
    deepest = {nt[0] for nt in notches}
    for i, ang, into in every:
        dist = np.hypot(*(c[idx] - c[i]).T)
        arc = np.abs(idx - i)
        arc = np.minimum(arc, n - arc)
        # a join between letters side by side runs across the row, a cut through a
        # letter's diagonal (an "M"'s, an "N"'s) or along its bar does not
        slant = np.abs((c[idx, 0] - c[i, 0]) * ex + (c[idx, 1] - c[i, 1]) * ey)
        # (and into the piece along the notch's halving line: from the apex of an "M"'s
        # middle "V" the shortest cut ran up beside the V's side, cutting a stem off)
        into_d = (c[idx] - c[i]) @ into
        ok = ((dist <= NOTCH_ROW_CUT * stroke) & (arc >= 1.25 * dist + 2)
              & (slant <= across * np.maximum(dist, 1e-9)) & (into_d >= aim * dist))
        # (a far end on another sharp notch: the outlines of two letters crossing on both
        # sides of the row, preferred to a shorter cut from a notch inside a letter, where an
        # "M"'s or an "N"'s diagonal leaves its stem, to the letter's straight side)
        others = np.array([c[k] for k, a, _ in every
                           if k != i and a <= NOTCH_ROW_MEET_ANGLE]).reshape(-1, 2)
        meets = (np.hypot(*(c[idx][:, None] - others[None]).transpose(2, 0, 1)).min(axis=1) <= near
                 if len(others) else np.zeros(idx.size, bool))
        # (a notch that is not its hull edge's deepest starts notch-to-notch cuts only: on a
        # jagged outline, a textured blob's, every dent would start one)
        found = [i not in deepest, False]
        for j in idx[ok][np.argsort(dist[ok])]:
            m = bool(meets[np.searchsorted(idx, j)]) and ang <= NOTCH_ROW_MEET_ANGLE
            if found[m] or found[True]:
                continue
            a, b = (i, j) if i < j else (j, i)
            s1, s2 = along[a:b + 1], np.concatenate([along[b:], along[:a + 1]])
            if min(np.ptp(s1), np.ptp(s2)) < NOTCH_ROW_SIDE * high:
                continue
            a1, _, a2, _ = sides(i, int(j))
            if min(a1, a2) < least or not _inside(piece, c[i], c[j]):
                continue
            cands.append((not m, float(np.hypot(*(c[j] - c[i]))), i, int(j)))
            found[m] = True
    for _, _, i, j in sorted(cands):
        out = _cut(piece, [(c[i], c[j])], least)
        if out is not None:
            return out
    return None


def _ray_end(piece: np.ndarray, p: np.ndarray, d: np.ndarray) -> np.ndarray | None:
    """Last pixel of ``piece`` on the ray from ``p`` along ``d`` before it leaves the piece
    (None when it leaves at once)."""
    h, w = piece.shape
    t = np.arange(1.0, float(np.hypot(h, w)))
    xy = np.rint(p[None] + t[:, None] * d[None]).astype(int)
    ok = (xy[:, 0] >= 0) & (xy[:, 0] < w) & (xy[:, 1] >= 0) & (xy[:, 1] < h)
    ok[ok] = piece[xy[ok, 1], xy[ok, 0]]
    # (the first pixels next to the notch may lie off the piece: start at the first inside)
    first = np.flatnonzero(ok)
    if first.size == 0:
        return None
    out = np.flatnonzero(~ok[first[0]:])
    last = first[0] + (out[0] - 1 if out.size else ok.size - 1 - first[0])
    return xy[last].astype(float) if last > first[0] + 2 else None


def _crosses(p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray) -> bool:
    """Whether the segments ``pq`` and ``ab`` cross."""
    def side(u, v, w):
        return float((v[0] - u[0]) * (w[1] - u[1]) - (v[1] - u[1]) * (w[0] - u[0]))

    p, q, a, b = (np.asarray(x, float) for x in (p, q, a, b))
    return side(p, q, a) * side(p, q, b) < 0 and side(a, b, p) * side(a, b, q) < 0


def _axis(c: np.ndarray) -> tuple[tuple[float, float], tuple[float, float]]:
    """Centre and unit direction of the outline's longest extent (its minimum-area rectangle's
    long side)."""
    import cv2

    (cx, cy), (rw, rh), ang = cv2.minAreaRect(c.astype(np.float32))
    t = np.radians(ang if rw >= rh else ang + 90.0)
    return (float(cx), float(cy)), (float(np.cos(t)), float(np.sin(t)))


def split_round_hole(piece: np.ndarray, least: float) -> np.ndarray | None:
    """Labels (1..n; 0 off ``piece``) of a ring of round parts round a hole (discs, beads or
    fruits touching in a circle) cut from every sharp notch of its outline to the sharp
    corner of the hole it faces, or None when the piece has no hole or a side is not round.

    Parameters
    ----------
    piece : (H, W) bool ndarray
        One connected part of a silhouette.
    least : float
        Least pixels of each side.

    Returns
    -------
    (H, W) int ndarray or None

    Notes
    -----
    Beyond the papers (strokes41). The outer outline of a ring has a notch between every two
    round parts, but a cut between two of them crosses the hole: only with the hole's own
    outline read (its corners where two parts meet) does the ring come apart. Tried before
    :func:`~branchnb.dendrite.strike_outline.split_by_shape`, whose watershed merged two
    parts of a ring of wide necks and left a pair with a blunt notch on the hole's side.

    Examples
    --------
    >>> y, x = np.mgrid[0:200, 0:200]
    >>> ring = np.zeros((200, 200), bool)
    >>> for a in np.arange(6) * np.pi / 3:
    ...     ring |= np.hypot(x - 100 - 56 * np.cos(a), y - 100 - 56 * np.sin(a)) < 30
    >>> int(split_round_hole(ring, 500).max())
    6
    >>> split_round_hole(np.hypot(x - 100, y - 100) < 60, 500) is None  # a disc: no hole
    True
    """
    piece = np.asarray(piece, bool)
    if piece.ndim != 2:
        raise ValueError(f"piece must be 2-D, got shape {piece.shape}")
    if piece.sum() < 2 * least:
        return None
    holes, count = ndimage.label(ndimage.binary_fill_holes(piece) & ~piece)
    if count == 0:
        return None
    depth = ndimage.distance_transform_edt(np.pad(piece, 1))[1:-1, 1:-1]
    rin = float(depth.max())
    if rin < 2.0:
        return None
    # a ring's hole, not a texture's pinholes (a speckled 1000-px blob had 2573: their corners
    # took minutes); a piece with many holes is no ring of round parts
    area = np.bincount(holes.ravel())[1:]
    if count > NOTCH_RING_HOLES and (area >= NOTCH_RING_HOLE * rin ** 2).sum() > NOTCH_RING_HOLES:
        return None
    c = _outline(piece)
    reach = max(3, int(round(0.35 * rin)))
    sharp = [nt for nt in _notches(c, NOTCH_DEPTH * rin, reach) if nt[1] <= NOTCH_ROUND_ANGLE]
    if len(sharp) < 2:
        return None
    return _ring_cut(piece, c, sharp, least, reach, NOTCH_RING_HOLE * rin ** 2)


def _hole_corners(piece: np.ndarray, reach: int,
                  hole: float = 0.0) -> list[tuple[np.ndarray, float, np.ndarray]]:
    """Sharp corners of the piece's holes of at least ``hole`` pixels that point into the
    piece (where two discs of a ring meet round its hole): ``(point, angle in degrees, unit
    vector into the piece)``."""
    import cv2

    cs, hier = cv2.findContours(piece.astype(np.uint8), cv2.RETR_CCOMP, cv2.CHAIN_APPROX_NONE)
    out: list = []
    if hier is None:
        return out
    h, w = piece.shape
    for c, (_, _, _, parent) in zip(cs, hier[0]):
        if parent < 0 or len(c) < 8 or abs(cv2.contourArea(c)) < hole:
            continue
        c = c[:, 0, :].astype(np.float64)
        # (a small hole's corners lie closer together than the outline's reach)
        r = max(2, min(reach, len(c) // 12))
        a = np.roll(c, r, axis=0) - c
        b = np.roll(c, -r, axis=0) - c
        la = np.maximum(np.hypot(*a.T), 1e-9)
        lb = np.maximum(np.hypot(*b.T), 1e-9)
        ang = np.degrees(np.arccos(np.clip((a * b).sum(1) / (la * lb), -1.0, 1.0)))
        # local minima of the angle (one per corner)
        lo = ndimage.minimum_filter1d(ang, 2 * r + 1, mode="wrap")
        for f in np.flatnonzero((ang <= lo) & (ang <= NOTCH_ROUND_ANGLE)):
            into = -(a[f] / la[f] + b[f] / lb[f])
            into /= max(float(np.hypot(*into)), 1e-9)
            q = np.rint(c[f] + 2.0 * into).astype(int)
            if 0 <= q[0] < w and 0 <= q[1] < h and piece[q[1], q[0]]:
                if not out or min(float(np.hypot(*(c[f] - o[0]))) for o in out) > r:
                    out.append((c[f], float(ang[f]), into))
    return out


def _ring_cut(piece: np.ndarray, c: np.ndarray, sharp: list, least: float,
              reach: int, hole: float = 0.0) -> np.ndarray | None:
    """Labels of ``piece`` cut from each sharp notch of its outline to the nearest sharp corner
    of a hole it faces (round parts in a ring round a hole: the outline's notches alone part
    nothing), kept when every side is round (solidity at least :data:`NOTCH_ROUND_SOLID`);
    None otherwise (strokes41, beyond the papers)."""
    if not sharp:
        return None
    corners = _hole_corners(piece, reach, hole)
    if not corners:
        return None
    aim = np.cos(np.radians(NOTCH_ROUND_AIM))
    segments = []
    for i, _, di in sharp:
        best = None
        for q, _, dq in corners:
            d = q - c[i]
            length = float(np.hypot(*d))
            e = d / max(length, 1e-9)
            if min(float(di @ e), float(-(dq @ e))) < aim:
                continue
            if not _inside(piece, c[i].astype(float), q) or (best is not None and length >= best[0]):
                continue
            best = (length, q)
        if best is not None:
            segments.append((c[i], np.rint(best[1]).astype(int)))
    # every notch cut to the hole (an unmatched one left two parts in one round-looking piece)
    if len(segments) < 2 or len(segments) < len(sharp):
        return None
    out = _cut(piece, segments, least)
    # a ring cut n times falls into n pieces (fewer: two cuts met a corner of one part)
    if out is None or int(out.max()) != len(segments):
        return None
    import cv2

    for k in range(1, int(out.max()) + 1):
        cs, _ = cv2.findContours((out == k).astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
        if _area_solidity(max(cs, key=len)[:, 0, :])[1] < NOTCH_ROUND_SOLID:
            return None
    return out
