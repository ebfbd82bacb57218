"""Branching: target strokes that start (or end) on another stroke form junctions.

When the user draws a stroke whose end point lies on another target
stroke (within a tolerance), the two meet at a *junction*: the stroke
touching with its end is the *child* (a branch), the other the *parent*.
A junction is handled in three ways:

1. **Order.** Parents are composed before their children, so a branch is
   cut into the canvas that already holds its parent
   (:func:`stroke_order`, a topological order; cycles are broken in
   drawing order).
2. **Geometry.** The child keeps the end point the user drew. If the
   child's *source* stroke has a free end there (a tip: it neither starts
   on another source stroke nor ends inside a longer object, see
   :mod:`~branchnb.strokes.fetch`), its end cap would show as a rounded
   tip glued to the parent; the child is therefore extended into the
   parent by the parent's half width, so the cap lies under the parent
   and the branch grows out of it (:func:`attach`). A source stroke that
   starts on another source stroke, or is cut straight at that end,
   carries junction texture (or a clean cut hidden in the parent) and is
   not extended.
3. **Composition.** The patches of the child near the junction may not
   paint over the far side of the parent (the canvas pixels beyond the
   parent's centre line are pinned to the canvas, :func:`far_side`), and
   their centres are not forced on top, so where the parent already looks
   right the graph cut keeps it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.validate import MAX_COUNT, Array, Int, Point, Real, checked
from .strokes import Stroke, StrokePair

__all__ = ["Junction", "find_junctions", "stroke_order", "attach", "far_side", "exit_length"]


@dataclass(frozen=True)
class Junction:
    """A stroke end lying on another stroke.

    Parameters
    ----------
    child : int
        Index of the stroke touching with an end.
    end : int
        0 if the child's first point touches, 1 if its last point does.
    parent : int
        Index of the stroke touched.
    parent_s : float
        Arc length of the junction on the parent.
    point : (2,) ndarray
        The junction point on the parent.
    distance : float
        Gap between the child's end point and the parent.

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke
    >>> j = find_junctions([Stroke([(0, 0), (0, 100)]), Stroke([(1, 50), (40, 20)])], 3)[0]
    >>> j.point.tolist(), j.distance
    ([0.0, 50.0], 1.0)
    """

    child: int
    end: int
    parent: int
    parent_s: float
    point: np.ndarray
    distance: float


def _DICT(value, name, allow_none):
    if not isinstance(value, dict):
        raise TypeError(f"{name} must be a dict, got {type(value).__name__}")
    return value


@checked(tolerance=Real(0, 1e5))
def find_junctions(strokes: list[Stroke], tolerance: float, sources: list[Stroke] | None = None) -> list[Junction]:
    """Junctions among ``strokes``: every stroke end within ``tolerance`` of another stroke.

    Each end attaches to at most one stroke (the nearest). A stroke end
    touching the *end* of another stroke also counts (the strokes then
    continue each other), except that of two ends touching each other only
    the later stroke is the child.

    With ``sources`` (the source strokes, one per stroke), an end that stays
    where it was (within ``tolerance`` of its source end) does not join a
    stroke that was moved over it: it joins stroke ``j`` only if it lay on
    source stroke ``j`` too. Without this, a part turned over a kept part's
    end (a leaf laid along its twig, an arm over a leg) would take the kept
    part as its child and drag it along. And a stroke's last point (its tip:
    strokes are drawn from their roots) that lay on no source stroke and was
    moved onto a stroke joins nothing: the part lies over the other one (a
    finger bent over its neighbour's tip keeps its own outline there, see
    :func:`~branchnb.strokes.overlays._overlaid_parts`). Beyond the paper.

    Parameters
    ----------
    strokes : list of Stroke
        The target strokes, in drawing order.
    tolerance : float
        Largest gap (pixels, >= 0) between a stroke end and another stroke
        that still counts as touching (``StrokeEditParams.junction_tolerance``).
    sources : list of Stroke, optional
        The source strokes (same length as ``strokes``), in the same frame.

    Returns
    -------
    list of Junction
        At most two per stroke (one per end), in stroke order.

    Raises
    ------
    TypeError
        If ``sources`` is not a list of :class:`~branchnb.strokes.strokes.Stroke`.
    ValueError
        If ``sources`` has not one stroke per stroke.

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke
    >>> trunk = Stroke([(0, 0), (0, 100)])
    >>> branch = Stroke([(1, 50), (40, 20)])
    >>> [(j.child, j.end, j.parent, j.parent_s) for j in find_junctions([trunk, branch], 3)]
    [(1, 0, 0, 50.0)]
    """
    if sources is not None and (not isinstance(sources, (list, tuple))
                                or not all(isinstance(s, Stroke) for s in sources)):
        raise TypeError(f"sources must be a list of Stroke or None, got {type(sources).__name__}")
    if sources is not None and len(sources) != len(strokes):
        raise ValueError(f"sources must have one stroke per stroke ({len(strokes)}), got {len(sources)}")
    out = []
    for i, st in enumerate(strokes):
        for end, q in ((0, st.points[0]), (1, st.points[-1])):
            stayed = None
            if sources is not None:
                q_src = sources[i].points[0 if end == 0 else -1]
                stayed = q_src if np.hypot(*(q - q_src)) <= tolerance else None
                if end == 1 and stayed is None and not any(
                        sources[j].project(q_src[None])[1][0] <= tolerance
                        for j in range(len(sources)) if j != i):
                    continue  # a free tip moved onto another stroke lies on it
            best = None
            for j, other in enumerate(strokes):
                if j == i:
                    continue
                if stayed is not None and sources[j].project(stayed[None])[1][0] > tolerance:
                    continue  # a stroke moved over an end that stayed put
                s, d = other.project(q[None])
                if d[0] <= tolerance and (best is None or d[0] < best[2]):
                    best = (j, float(s[0]), float(d[0]))
            if best is None:
                continue
            j, s, d = best
            at_end = min(s, strokes[j].length - s) <= tolerance
            if at_end and j > i:
                # Two ends meeting: the later-drawn stroke is the child.
                continue
            out.append(Junction(i, end, j, s, strokes[j].point_at(s), d))
    return out


@checked(n=Int(0, MAX_COUNT))
def stroke_order(n: int, junctions: list[Junction]) -> list[int]:
    """Stroke indices with every parent before its children (drawing order otherwise).

    Parameters
    ----------
    n : int
        Number of strokes (>= 0).
    junctions : list of Junction
        The junctions among them (:func:`find_junctions`).

    Returns
    -------
    list of int
        A permutation of ``range(n)``; a cycle is broken at the earliest
        drawn stroke.

    Examples
    --------
    >>> j = Junction(0, 0, 1, 5.0, np.zeros(2), 0.0)
    >>> stroke_order(3, [j])
    [1, 0, 2]
    """
    parents = {i: {j.parent for j in junctions if j.child == i} for i in range(n)}
    done: list[int] = []
    left = list(range(n))
    while left:
        ready = [i for i in left if not (parents[i] - set(done))]
        nxt = ready[0] if ready else left[0]  # a cycle: break it in drawing order
        done.append(nxt)
        left.remove(nxt)
    return done


@checked(depth=_DICT)
def attach(pair: StrokePair, junctions: list[Junction], target_strokes: list[Stroke],
           depth: dict) -> tuple[StrokePair, dict]:
    """Extend the target stroke of ``pair`` into its parents at its junction ends.

    Parameters
    ----------
    pair : StrokePair
        The pair whose target stroke is the child; not modified.
    junctions : list of Junction
        The junctions where this pair's target stroke is the child.
    target_strokes : list of Stroke
        All target strokes (for the parents' directions).
    depth : dict
        ``{end: e}``: how far to extend the stroke into the parent at each
        end (0 for no extension).

    Returns
    -------
    pair : StrokePair
        With the new target stroke; interior control points keep their
        position on the stroke.
    shift : dict
        ``{end: extra length}`` added at each end.

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke, StrokePair
    >>> trunk, branch = Stroke([(0, 0), (0, 100)]), Stroke([(0, 50), (40, 50)])
    >>> pair = StrokePair(Stroke([(0, 0), (40, 0)]), branch)
    >>> new, added = attach(pair, find_junctions([trunk, branch], 2), [trunk, branch], {0: 5.0})
    >>> new.target.points[0].tolist(), added
    ([-5.0, 50.0], {0: 5.0, 1: 0.0})
    """
    pts = pair.target.points.copy()
    added = {0: 0.0, 1: 0.0}
    for jn in junctions:
        e = float(depth.get(jn.end, 0.0))
        if e <= 0:
            continue
        if jn.end == 0:
            d = pts[0] - pts[min(1, len(pts) - 1)]
        else:
            d = pts[-1] - pts[max(len(pts) - 2, 0)]
        n = np.hypot(*d)
        if n < 1e-9:
            continue
        ext = pts[0 if jn.end == 0 else -1] + d / n * e
        pts = np.vstack([ext, pts]) if jn.end == 0 else np.vstack([pts, ext])
        added[jn.end] = e
    target = Stroke(pts, name=pair.target.name)
    inner = pair.control[1:-1].copy()
    inner[:, 1] += added[0]
    return StrokePair(pair.source, target, inner, name=pair.name), added


@checked(child_dir=Array(ndim=1), origin=Point(), size=Int(1, 4096), window=Real(0, 1e4))
def far_side(junction: Junction, parent: Stroke, child_dir: np.ndarray, origin, size: int,
             *, window: float) -> np.ndarray:
    """Pixels of a ``size`` x ``size`` patch at ``origin`` beyond the parent's centre line.

    "Beyond" is the side of the parent's tangent line at the junction
    away from the child's direction ``child_dir`` (a unit vector pointing
    from the junction into the child).

    Parameters
    ----------
    junction : Junction
        The junction, with its point and arc length on the parent.
    parent : Stroke
        The parent's target stroke.
    child_dir : (2,) array_like
        Unit vector from the junction into the child.
    origin : (int, int)
        Target ``(x, y)`` of the patch's top-left pixel.
    size : int
        Side of the square patch (pixels).
    window : float
        Half-length (pixels) of the chord the parent's tangent is taken from
        (:meth:`Stroke.angle_at`).

    Returns
    -------
    (size, size) bool ndarray
        True more than half a pixel beyond the line, on the side away from the
        child.

    Raises
    ------
    ValueError
        If ``child_dir`` is not a finite 2-vector.

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke
    >>> trunk, branch = Stroke([(10, 0), (10, 40)]), Stroke([(10, 20), (30, 20)])
    >>> j = find_junctions([trunk, branch], 2)[0]
    >>> m = far_side(j, trunk, np.array([1.0, 0.0]), (0, 15), 20, window=4.0)
    >>> bool(m[5, 2]), bool(m[5, 15])
    (True, False)
    """
    child_dir = np.asarray(child_dir, dtype=np.float64) if not isinstance(child_dir, (str, bytes)) else None
    if child_dir is None or child_dir.shape != (2,) or not np.isfinite(child_dir).all():
        raise ValueError("child_dir must be a finite 2-vector (x, y)")
    t = parent.angle_at(junction.parent_s, window=window)
    nrm = np.array([-np.sin(float(t)), np.cos(float(t))])
    side = np.sign(nrm @ child_dir) or 1.0
    x0, y0 = origin
    yy, xx = np.mgrid[0:size, 0:size]
    rel = np.stack([xx + x0 - junction.point[0], yy + y0 - junction.point[1]], axis=-1)
    return (rel @ nrm) * side < -0.5


def exit_length(child: Stroke, parent: Stroke, half_width, end: int) -> float | None:
    """How far along ``child`` from its ``end`` it leaves ``parent``'s silhouette (px), or None.

    ``half_width(s)`` is the parent's half width at its arc lengths ``s``;
    the child leaves the silhouette at the first point farther from the
    parent's centre line than that.

    Parameters
    ----------
    child : Stroke
        The branch's stroke.
    parent : Stroke
        The stroke whose silhouette the child starts in.
    half_width : callable
        ``half_width(s) -> ndarray``: the parent's half width (pixels) at its
        arc lengths ``s``.
    end : int
        0 to walk from the child's first point, 1 from its last.

    Returns
    -------
    float or None
        Arc length (pixels, in steps of 0.5) from ``end``; None if the child
        never leaves the silhouette or does not start inside it.

    Examples
    --------
    >>> trunk = Stroke([(0, 0), (0, 100)])
    >>> branch = Stroke([(0, 50), (40, 50)])
    >>> exit_length(branch, trunk, lambda s: np.full(np.shape(s), 8.0), 0)
    8.5
    """
    t = np.arange(0.0, child.length + 0.25, 0.5)
    s_child = t if end == 0 else child.length - t
    s_par, d = parent.project(child.point_at(s_child))
    out = np.flatnonzero(d > np.asarray(half_width(s_par), float))
    if not len(out) or out[0] == 0:
        return None
    return float(t[out[0]])
