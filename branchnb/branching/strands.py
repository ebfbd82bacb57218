"""Strands broken where another passes over them, joined again before learning (beyond the paper).

Line art often draws a crossing as over-and-under: the strand passing
under is interrupted by a white gap on both sides of the one passing over
(a Celtic knot, a vine ornament, a woven pattern). Extraction then sees
every piece between two crossings as a tree of its own: the Celtic vine
ornament of the shared samples (one long stem with leaves) came out as 15
trees of 140-1060 px, and synthesis grew 14-15 short trees instead of one
long stem (root count, branch lengths and the longest branch all come
from the example's trees).

:func:`join_strands` joins two trees' root branches end to end when their
ends face each other across a gap that another branch passes through:

* the ends are at most ``max_gap`` apart (default 9 x the median
  thickness of the example, at least 6 px);
* both ends head toward each other: the gap's direction is within
  ``acos(min_cos)`` of each end's outward heading;
* the straight bridge between them passes over another branch (comes
  within its thickness + 1.5 px; the strand itself counts away from
  its end, a loop passes over itself): that is what cut the strand. Two rivers
  that merely end near each other, or a crack that stops short of
  another, are left alone.

The joined root branch reads in the direction of the longer piece, the
gap is bridged by a straight piece, and the children keep their vertices.

Examples
--------
>>> import numpy as np
>>> from branchnb.core.structure import Branch, Structure
>>> t = np.arange(0, 60.0)
>>> left = Branch(np.c_[t, np.full(60, 50.0)], 2.0)
>>> right = Branch(np.c_[t + 75, np.full(60, 50.0)], 2.0)
>>> over = Branch(np.c_[np.full(80, 67.0), np.arange(10, 90.0)], 2.0)
>>> joined = join_strands(Structure([left, right, over], image_shape=(100, 140)))
>>> len(joined.branches), round(joined.branches[0].length)
(2, 134)
"""

from __future__ import annotations

import numpy as np

from ..core.structure import Branch, Structure

__all__ = ["join_strands"]

#: Default largest gap, in median thicknesses of the example.
GAP_RADII = 9.0


def _end(points: np.ndarray, at_start: bool, reach: float) -> tuple[np.ndarray, np.ndarray]:
    """(end point, outward unit heading measured over ``reach`` px of arc) of a polyline."""
    p = points if not at_start else points[::-1]
    seg = np.hypot(*np.diff(p, axis=0).T)
    arc = np.r_[0.0, np.cumsum(seg[::-1])][::-1]      # arc length to the end
    j = int(np.argmax(arc <= reach)) if np.any(arc <= reach) else len(p) - 2
    j = min(j, len(p) - 2)
    d = p[-1] - p[j]
    n = float(np.hypot(*d))
    return p[-1], (d / n if n > 1e-9 else np.zeros(2))


def _near_other(a, b, strands, step: float = 1.0) -> bool:
    """Whether the middle of the segment a-b (30-70 %) passes within a strand's thickness + 1.5 px."""
    n = max(int(np.hypot(*(b - a)) / step), 2)
    q = a + (b - a) * np.linspace(0.3, 0.7, n)[:, None]
    for pts, rad in strands:
        if len(pts):
            d = np.hypot(q[:, None, 0] - pts[None, :, 0], q[:, None, 1] - pts[None, :, 1])
            if np.any(d <= rad[None, :] + 1.5):
                return True
    return False


def join_strands(structure: Structure, *, max_gap: float | None = None, min_cos: float = 0.6) -> Structure:
    """Join trees whose root branches are one strand cut where another passes over it.

    Parameters
    ----------
    structure : Structure
        The example (e.g. from :func:`~branchnb.branching.extract_structure`);
        not modified.
    max_gap : float, optional
        Largest gap (pixels) bridged; default :data:`GAP_RADII` x the
        median thickness, at least 6 px.
    min_cos : float, default 0.6
        Both ends must head toward each other: cosine between each end's
        outward heading and the gap's direction at least this (0.6: within
        53 degrees; a curving strand turns across the gap).

    Returns
    -------
    Structure
        The structure with the strands joined (the same object when there
        is nothing to join).

    Raises
    ------
    TypeError
        If ``structure`` is not a Structure.
    ValueError
        If ``max_gap`` is not positive or ``min_cos`` is outside [-1, 1].

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 50.0)
    >>> s = Structure([Branch(np.c_[t, t * 0 + 20], 1.5), Branch(np.c_[t + 80, t * 0 + 20], 1.5)])
    >>> len(join_strands(s).branches)           # a 30 px gap with nothing passing through it
    2
    """
    if not isinstance(structure, Structure):
        raise TypeError(f"structure must be a Structure, got {type(structure).__name__}")
    if max_gap is not None and not (np.isfinite(max_gap) and max_gap > 0):
        raise ValueError(f"max_gap must be a positive number or None, got {max_gap!r}")
    if not (-1.0 <= float(min_cos) <= 1.0):
        raise ValueError(f"min_cos must lie in [-1, 1], got {min_cos!r}")
    bs = [dict(points=np.asarray(b.points, np.float64), r=np.asarray(b.thickness, np.float64),
               parent=b.parent, pv=b.parent_vertex) for b in structure.branches]
    if sum(b["parent"] is None for b in bs) < 2:
        return structure
    r_med = float(np.median(np.concatenate([b["r"] for b in bs])))
    gap = float(max_gap) if max_gap is not None else max(GAP_RADII * r_med, 6.0)
    reach = max(3.0 * r_med, 6.0)
    changed = False
    while True:
        tree = _trees(bs)
        # strand ends: every branch's tip; a root branch's start too (a root branch may be read backwards)
        ends = [(k, False, *_end(b["points"], False, reach)) for k, b in enumerate(bs) if len(b["points"]) >= 3]
        ends += [(k, True, *_end(b["points"], True, reach)) for k, b in enumerate(bs)
                 if b["parent"] is None and len(b["points"]) >= 3]
        best = None
        for a in range(len(ends)):
            i, sa, pa, ua = ends[a]
            for b in range(a + 1, len(ends)):
                j, sb, pb, ub = ends[b]
                if tree[i] == tree[j]:
                    continue
                # one side must be a whole tree's root branch (it is appended to the other's branch)
                if bs[j]["parent"] is not None and bs[i]["parent"] is not None:
                    continue
                v = pb - pa
                d = float(np.hypot(*v))
                if d > gap or (best is not None and d >= best[0]):
                    continue
                if d > 1e-9:
                    v = v / d
                    if ua @ v < min_cos or ub @ -v < min_cos:
                        continue
                # the strand passing over may be one of the two (a loop crossing itself): all strands
                # count, but not the two ends themselves
                others = []
                for k, bk in enumerate(bs):
                    keep = np.ones(len(bk["points"]), bool)
                    for e, pe in ((i, pa), (j, pb)):
                        if k == e:
                            keep &= np.hypot(*(bk["points"] - pe).T) > 0.5 * d
                    others.append((bk["points"][keep], bk["r"][keep]))
                if d > 2.0 and not _near_other(pa, pb, others):
                    continue
                best = (d, i, sa, j, sb)
        if best is None:
            break
        _, i, sa, j, sb = best
        if bs[j]["parent"] is not None:
            i, sa, j, sb = j, sb, i, sa      # a child is the host: it keeps its direction
        _merge(bs, i, sa, j, sb)
        changed = True
    if not changed:
        return structure
    return Structure([Branch(b["points"], b["r"], b["parent"], b["pv"]) for b in _ordered(bs)],
                     image_shape=structure.image_shape)


def _trees(bs: list) -> list:
    """Root index of every branch (parents come first)."""
    t = []
    for k in range(len(bs)):
        while bs[k]["parent"] is not None:
            k = bs[k]["parent"]
        t.append(k)
    return t


def _ordered(bs: list) -> list:
    """The branches reordered so that every parent comes before its children."""
    kids: dict = {}
    for k, b in enumerate(bs):
        kids.setdefault(b["parent"], []).append(k)
    order, queue = [], list(kids.get(None, []))
    while queue:
        k = queue.pop(0)
        order.append(k)
        queue.extend(kids.get(k, []))
    new = {old: n for n, old in enumerate(order)}
    return [dict(bs[k], parent=None if bs[k]["parent"] is None else new[bs[k]["parent"]]) for k in order]


def _merge(bs: list, i: int, i_at_start: bool, j: int, j_at_start: bool) -> None:
    """Append root branch ``j`` (its tree) to branch ``i`` (in place) across the gap between the given ends.

    Branch ``i`` is read backwards only when it is a root branch joined at its start.
    """
    A, B = bs[i], bs[j]
    # piece 1 ends at the gap, piece 2 starts there
    p1, r1, rev1 = (A["points"][::-1], A["r"][::-1], True) if i_at_start else (A["points"], A["r"], False)
    p2, r2, rev2 = (B["points"][::-1], B["r"][::-1], True) if not j_at_start else (B["points"], B["r"], False)
    d = float(np.hypot(*(p2[0] - p1[-1])))
    k = max(int(np.ceil(d)), 1)
    t = np.arange(1, k) / k
    bridge = p1[-1] + (p2[0] - p1[-1]) * t[:, None]
    pts = np.vstack([p1, bridge, p2])
    rad = np.r_[r1, r1[-1] + (r2[0] - r1[-1]) * t, r2]
    n1, nb = len(p1), len(bridge)
    len1 = float(np.hypot(*np.diff(p1, axis=0).T).sum())
    len2 = float(np.hypot(*np.diff(p2, axis=0).T).sum())
    # read the joined strand the way the longer piece was read (a child keeps its direction)
    flip = (rev1 if len1 >= len2 else rev2) if A["parent"] is None else False
    N = len(pts)

    def where(v, first: bool) -> int:
        if first:
            pos = (len(A["points"]) - 1 - v) if rev1 else v
        else:
            pos = n1 + nb + ((len(B["points"]) - 1 - v) if rev2 else v)
        return N - 1 - pos if flip else pos

    for c in bs:
        if c["parent"] == i:
            c["pv"] = where(c["pv"] or 0, True)
        elif c["parent"] == j:
            c["parent"], c["pv"] = i, where(c["pv"] or 0, False)
    A["points"], A["r"] = (pts[::-1], rad[::-1]) if flip else (pts, rad)
    del bs[j]
    for c in bs:
        if c["parent"] is not None and c["parent"] > j:
            c["parent"] -= 1
