"""Crotches: the rounded concave corners where a child leaves its parent (beyond the paper).

Clip-art and drawn trees round the corner between a branch and its parent
(the fork's "collar"): along the silhouette the outline turns through the
crotch over an arc, not at a point. A branch added where the source has
none, or turned away from its source angle, meets its parent at a corner
nobody drew: the patches give a sharp one (the paper composes patches
only). :func:`crotch_shape` measures a crotch on a silhouette (the turn
and the radius of the arc it turns over); :func:`source_fillet` takes the
source's own crotches' radius; the composition closes a new crotch with
a disk of that radius (:func:`~branchnb.strokes.outline.fill_joints`), so
new junctions are rounded like the source's and sharp sources stay sharp.

>>> import numpy as np
>>> yy, xx = np.mgrid[0:80, 0:80]
>>> alpha = ((np.abs(xx - 40) <= 8) | ((yy >= 32) & (yy <= 48) & (xx >= 40))).astype(float)
>>> shape = crotch_shape(alpha, (40, 40), np.array([(40.0, 40.0), (79.0, 40.0)]), 8.0)
>>> sorted(shape), [abs(shape[s][0] - 90) < 4 for s in sorted(shape)]   # two right angles
([-1, 1], [True, True])
>>> max(shape[s][1] for s in shape) < 3.0                            # sharp: radius < 3 px
True
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from .strokes import Stroke

__all__ = ["crotch_shape", "crotch_angles", "source_fillet", "new_crotches", "round_crotches"]

#: Smoothing of the contour's turning (px of arc length, at the measuring scale) before the arc is measured.
_SIGMA = 1.5
#: The child's half width (px) every crotch is measured at: the silhouette around the junction is
#: resampled by ``_MEASURE_HW / half_width`` first (beyond the paper). Measured at its own pixels, a
#: crotch's concave run merged or split with the image's scale (tree_rpg_12's source radius measured
#: 6.4 / 23.2 / 16.3 px per unit of scale at 0.5x / 1x / 2x, so nothing was rounded at 0.5x).
_MEASURE_HW = 12.0


def _scale(half_width: float) -> float:
    """The resampling factor of the measure for a child of ``half_width`` (px)."""
    return _MEASURE_HW / float(half_width)


def _sharp_radius(half_width: float, turn: float) -> float:
    """The radius (px) a sharp corner turning by ``turn`` degrees measures on a child of ``half_width``
    (smoothed over :data:`_SIGMA` at the measuring scale, and over at least the 1 px of a source's
    anti-aliasing: a thin child's corner resampled up is soft over one source pixel)."""
    return _SHARP * max(_SIGMA / _scale(half_width), 1.0) / np.radians(turn)


#: The radius a sharp corner measures times its turn (radians), per px of :data:`_SIGMA` (at the measuring scale).
_SHARP = 3.5
#: The run of a crotch: where the concave curvature exceeds this share of its peak.
_RUN_SHARE = 0.05


#: The longest dip (px at the measuring scale) a concave run is followed across.
_GAP = 3.0


def _run_end(concave: np.ndarray, i: int, step: int, level: float) -> int:
    """The last index of the run through ``i`` (in direction ``step``) where ``concave > level``,
    dips of at most :data:`_GAP` px included."""
    end, gap, j = i, 0, i + step
    while 0 <= j < len(concave):
        if concave[j] > level:
            end, gap = j, 0
        else:
            gap += 1
            if gap * 0.5 > _GAP:
                break
        j += step
    return end


def _contours(alpha: np.ndarray) -> list[np.ndarray]:
    from skimage.measure import find_contours

    return [c[:, ::-1] for c in find_contours(np.pad(alpha, 1), 0.5)]  # (x, y), shifted by the pad


def crotch_shape(alpha: np.ndarray, point, child, half_width: float, *, reach: float | None = None) -> dict:
    """The crotches on both sides of a child leaving its parent at ``point``.

    Parameters
    ----------
    alpha : (H, W) ndarray
        The silhouette's alpha (the contour at 0.5 is measured).
    point : (2,) array_like
        Where the child's stroke leaves its parent's ``(x, y)``.
    child : (N, 2) array_like or Stroke
        The child's stroke, starting at ``point``.
    half_width : float
        The child's half width (px): the crotches are looked for within
        ``reach`` of ``point`` (default ``4 half_width``).
    reach : float, optional
        See ``half_width``.

    Returns
    -------
    dict
        ``{side: (turn, radius)}`` for each side of the child (``+1``: to
        the left of its direction of travel in image coordinates, ``-1``)
        where the silhouette turns concavely: the turn in degrees and the
        radius (px) it turns over: along the concave run through the sharpest
        point, the turn ``T`` over the integral of the squared curvature (a fillet of radius ``R`` gives
        ``R``; a sharp corner, smoothed over ``s`` px, ``3.5 s / T`` in
        radians; an arc with a kink, between the two, weighted by their turns).

    Notes
    -----
    Beyond the paper. The silhouette around ``point`` is first resampled so
    that ``half_width`` becomes :data:`_MEASURE_HW` px, and the contour's
    turning is smoothed over :data:`_SIGMA` px there (``s`` above:
    ``half_width / 8``, at least one source pixel): the same crotch drawn at
    any size measures the same radius relative to its child (measured at its
    own pixels, a concave run merged or split with the image's scale). A run
    is followed across dips of at most :data:`_GAP` px (pixel steps break a
    faint arc into pieces), and a run whose peak lies outside the side's zone
    belongs to another corner (it is not this crotch).

    Examples
    --------
    >>> yy, xx = np.mgrid[0:60, 0:60]
    >>> alpha = ((np.abs(xx - 30) <= 6) | ((np.hypot(xx - 30, yy - 30) <= 20) & (yy >= 30))).astype(float)
    >>> sorted(crotch_shape(alpha, (30, 30), [(30, 30), (30, 59)], 6.0))
    [-1, 1]
    """
    alpha = np.asarray(alpha, float)
    if alpha.ndim != 2:
        raise ValueError(f"alpha must be (H, W), got shape {alpha.shape}")
    if not np.isfinite(half_width) or half_width <= 0:
        raise ValueError(f"half_width must be > 0, got {half_width}")
    st = child if isinstance(child, Stroke) else Stroke(np.asarray(child, float))
    p = np.asarray(point, float)
    reach = 4.0 * half_width if reach is None else float(reach)
    ahead = st.point_at(min(st.length, 2.0 * half_width + 2.0)) - p
    u = ahead / max(np.hypot(*ahead), 1e-9)
    m = int(np.ceil(reach)) + 4
    h, w = alpha.shape
    x, y = int(round(p[0])), int(round(p[1]))
    r0, c0 = max(y - m, 0), max(x - m, 0)
    sub = alpha[r0:min(y + m + 1, h), c0:min(x + m + 1, w)]
    if sub.size == 0:
        return {}
    # measured at one scale relative to the child: the child's half width becomes _MEASURE_HW px
    g = _scale(half_width)
    shape = (max(int(round(sub.shape[1] * g)), 2), max(int(round(sub.shape[0] * g)), 2))
    gx, gy = shape[0] / sub.shape[1], shape[1] / sub.shape[0]
    if shape != sub.shape[::-1]:
        import cv2

        sub = cv2.resize(np.ascontiguousarray(sub, np.float32), shape,
                         interpolation=cv2.INTER_AREA if g < 1 else cv2.INTER_LINEAR)
    p = (p - (c0, r0) + 0.5) * (gx, gy) - 0.5          # the junction in the measuring frame
    reach, half_width = reach * g, half_width * g
    out: dict = {}
    for c in _contours(sub):
        if len(c) < 8:
            continue
        c = c - 1.0
        # uniform 0.5-px resampling, turning angle smoothed along the arc
        seg = np.hypot(*np.diff(c, axis=0).T)
        s = np.r_[0.0, np.cumsum(seg)]
        if s[-1] < 4:
            continue
        t = np.arange(0.0, s[-1], 0.5)
        q = np.c_[np.interp(t, s, c[:, 0]), np.interp(t, s, c[:, 1])]
        d = np.gradient(q, axis=0)
        th = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
        th = ndi.gaussian_filter1d(th, _SIGMA / 0.5, mode="nearest")
        kappa = np.gradient(th) / 0.5
        # the object's side of the contour (left or right of travel), from the alpha itself
        nrm = np.c_[-np.sin(th), np.cos(th)]
        probe = np.rint(q + 1.5 * nrm).astype(int)
        ok = (probe[:, 0] >= 0) & (probe[:, 0] < sub.shape[1]) & (probe[:, 1] >= 0) & (probe[:, 1] < sub.shape[0])
        left = np.mean(sub[probe[ok, 1], probe[ok, 0]] > 0.5) if ok.any() else 0.5
        concave = kappa * (-1.0 if left >= 0.5 else 1.0)
        rel = q - p
        near = np.hypot(*rel.T) <= reach
        across = -rel[:, 0] * u[1] + rel[:, 1] * u[0]
        along = rel @ u
        for side in (1, -1):
            zone = near & (side * across > 0) & (along > -half_width)
            if not zone.any():
                continue
            z = np.flatnonzero(zone)
            i = z[np.argmax(concave[z])]
            # uphill to the run's own peak: a peak beyond reach belongs to another corner (the
            # zone only cut its flank, e.g. a notch further along the parent)
            while True:
                j = i - 1 if i > 0 and concave[i - 1] > concave[i] else i + 1
                if j >= len(q) or concave[j] <= concave[i]:
                    break
                i = j
            if not zone[i]:
                continue
            peak = concave[i]
            if peak <= 0.02:
                continue
            # the concave run through the peak (to where the curvature is back to ~0)
            # (across dips of at most _GAP px: pixel steps of a small or resampled source break
            # a long arc's faint curvature into pieces)
            lo = _run_end(concave, i, -1, _RUN_SHARE * peak)
            hi = _run_end(concave, i, 1, _RUN_SHARE * peak)
            k = np.maximum(concave[lo:hi + 1], 0.0)
            turn = float(k.sum()) * 0.5
            if turn < np.radians(5.0):
                continue
            radius = turn / (float((k * k).sum()) * 0.5) / g
            if side not in out or turn > np.radians(out[side][0]):
                out[side] = (float(np.degrees(turn)), radius)
    return out


def crotch_angles(point, child, parent: Stroke, parent_s: float, half_width: float) -> dict:
    """The angle (degrees) between a child and its parent on each side of the child.

    ``{side: angle}`` (sides as in :func:`crotch_shape`): the angle between
    the child's direction and the parent's tangent at ``parent_s`` pointing
    to that side (both over ``2 half_width + 2`` px); below 90 an acute
    crotch (a V), above an obtuse one.

    Parameters
    ----------
    point : (2,) array_like
        The junction.
    child : (N, 2) array_like or Stroke
        The child's stroke, starting at ``point``.
    parent : Stroke
        The parent's stroke.
    parent_s : float
        Arc length of the junction on ``parent``.
    half_width : float
        The child's half width (px).

    Returns
    -------
    dict

    Examples
    --------
    >>> ang = crotch_angles((0, 50), [(0, 50), (40, 10)], Stroke([(0, 0), (0, 100)]), 50.0, 4.0)
    >>> {k: round(v) for k, v in sorted(ang.items())}
    {-1: 45, 1: 135}
    """
    st = child if isinstance(child, Stroke) else Stroke(np.asarray(child, float))
    p = np.asarray(point, float)
    ahead = st.point_at(min(st.length, 2.0 * half_width + 2.0)) - p
    u = ahead / max(np.hypot(*ahead), 1e-9)
    a = float(parent.angle_at(np.array([float(parent_s)]), window=2.0 * half_width + 2.0)[0])
    t = np.array([np.cos(a), np.sin(a)])
    out = {}
    for d in (t, -t):
        side = 1 if u[0] * d[1] - u[1] * d[0] > 0 else -1
        out[side] = float(np.degrees(np.arccos(np.clip(u @ d, -1.0, 1.0))))
    return out


def source_fillet(alpha: np.ndarray, junctions, strokes, half_widths, *, min_angle: float = 60.0) -> float | None:
    """The radius of the source's obtuse crotches (median over its junctions), or None.

    Parameters
    ----------
    alpha : (H, W) ndarray
        The source's alpha.
    junctions : list of Junction
        Among the source strokes (:func:`~branchnb.strokes.junctions.find_junctions`).
    strokes : list of Stroke
        The source strokes.
    half_widths : sequence of float
        Per junction, the child's half width where it leaves (px).
    min_angle : float
        The crotches counted: those where the child leaves the parent at
        ``min_angle`` degrees or more (:func:`crotch_angles`; the acute ones,
        V-shaped, are not closed).

    Returns
    -------
    float or None
        None if the source has no such crotch, or if they are sharp (most
        measure less than twice a sharp corner's radius, ``3.5 s`` over
        the turn in radians, ``s`` the smoothing of :func:`crotch_shape`):
        sharp sources stay sharp.

    Examples
    --------
    >>> from branchnb.strokes.junctions import find_junctions
    >>> yy, xx = np.mgrid[0:80, 0:80]
    >>> alpha = ((np.abs(xx - 40) <= 8) | ((yy >= 32) & (yy <= 48) & (xx >= 40))).astype(float)
    >>> st = [Stroke([(40, 0), (40, 79)]), Stroke([(40, 40), (79, 40)])]
    >>> print(source_fillet(alpha, find_junctions(st, 2.0), st, [8.0]))     # sharp corners
    None
    """
    radii = []
    for jn, hw in zip(junctions, half_widths):
        child = strokes[jn.child] if jn.end == 0 else strokes[jn.child].reversed()
        ang = crotch_angles(jn.point, child, strokes[jn.parent], jn.parent_s, float(hw))
        for side, (turn, radius) in crotch_shape(alpha, jn.point, child, float(hw)).items():
            if ang.get(side, 0.0) >= min_angle and turn >= 15.0:
                # a sharp corner measures _SHARP / turn: within twice that it counts as sharp
                radii.append(radius if radius > 2.0 * _sharp_radius(float(hw), turn) else 0.0)
    if not radii or np.median(radii) <= 0.0:
        return None
    return float(np.median(radii))


def _child_width(index, k: int) -> float:
    st = index.strokes[k]
    return float(np.median(index.half_width(k, np.linspace(0.0, st.length, 21))))


def _relative_angle(child: Stroke, end: int, parent: Stroke, s_par: float, hw: float) -> float:
    """Direction of ``child`` leaving at ``end``, relative to ``parent``'s tangent at ``s_par`` (rad)."""
    a = child.point_at(0.0 if end == 0 else child.length)
    b = child.point_at(min(2.0 * hw + 2.0, child.length) if end == 0 else max(child.length - 2.0 * hw - 2.0, 0.0))
    t = float(parent.angle_at(np.array([s_par]), window=hw)[0])
    return float(np.arctan2(b[1] - a[1], b[0] - a[0]) - t)


def new_crotches(index, attached, junctions, tolerance: float) -> tuple[list, float | None]:
    """The junctions whose crotches nobody drew, and the source's crotch radius.

    A junction's crotches are new when its child leaves its parent where
    or at an angle (by more than 10 degrees) the source child did not: a
    branch added from a copy, a limb turned about its root.

    Parameters
    ----------
    index : SourceIndex
        The source strokes and widths (:func:`~branchnb.strokes.source.source_index`).
    attached : list of StrokePair
        The pairs, target strokes extended at junctions.
    junctions : list of Junction
        Among the target strokes.
    tolerance : float
        The junction tolerance (px).

    Returns
    -------
    list of Junction, float or None
        The new junctions and :func:`source_fillet` of the source's own
        (None: the source has no obtuse crotch; nothing is rounded).

    Examples
    --------
    >>> from branchnb.strokes import fetch_patches
    >>> img = np.zeros((60, 60, 4), np.float32); img[:, 22:38] = (0.5, 0.3, 0.1, 1.0)
    >>> p = fetch_patches(img, [[(30, 59), (30, 0)]], [[(30, 59), (30, 0)]])
    >>> new_crotches(p._index, p.attached, p.junctions, 3.0)
    ([], None)
    """
    from .junctions import find_junctions

    if not junctions:
        return [], None
    strokes = index.strokes
    # the source's junctions among its distinct strokes (a stroke given twice, to grow
    # two branches from one, is one stroke of the source)
    # (within 1 px: centring may move two copies of one stroke by a hair apart)
    keys = list(range(len(strokes)))
    for k, st in enumerate(strokes):
        for j in range(k):
            o = strokes[j].points
            if keys[j] == j and o.shape == st.points.shape and np.abs(o - st.points).max() <= 1.0:
                keys[k] = j
                break
    first = [k for k in range(len(strokes)) if keys[k] == k]
    src_j = [(first[sj.child], sj.end, first[sj.parent], sj.parent_s)
             for sj in find_junctions([strokes[k] for k in first], tolerance)]
    new = []
    for jn in junctions:
        hw = _child_width(index, jn.child)
        parent = attached[jn.parent]
        s_src = float(parent.source_arc_length(jn.parent_s))
        same = [sj for sj in src_j if keys[sj[0]] == keys[jn.child] and sj[1] == jn.end
                and keys[sj[2]] == keys[jn.parent] and abs(sj[3] - s_src) <= hw]
        if same:
            a_t = _relative_angle(attached[jn.child].target, jn.end, parent.target, float(jn.parent_s), hw)
            a_s = _relative_angle(strokes[jn.child], jn.end, strokes[jn.parent], same[0][3], hw)
            if abs((a_t - a_s + np.pi) % (2 * np.pi) - np.pi) <= np.radians(10.0):
                continue
        new.append(jn)
    if not new:
        return [], None
    # the source's radius is the same for every edit of this source (an app re-composing)
    cache = index.__dict__.setdefault("_crotch_fillets", {})
    if tolerance in cache:
        return new, cache[tolerance]
    from .junctions import Junction

    mine = [Junction(c, e, p, s, strokes[p].point_at(s), 0.0) for c, e, p, s in src_j]
    alpha = index.premult[:, :, 3]
    cache[tolerance] = source_fillet(alpha, mine, strokes, [_child_width(index, sj.child) for sj in mine])
    return new, cache[tolerance]


def round_crotches(layer: np.ndarray, junctions, attached, joints, fillet: float, *, inner: int = 0,
                   half_widths=None, min_angle: float = 60.0) -> np.ndarray:
    """``layer`` with the obtuse crotches at ``junctions`` closed by a disk of radius ``fillet``.

    Only the sides of a child whose crotch is obtuse (``min_angle`` degrees
    or more, :func:`crotch_angles`) and sharper than ``fillet`` (:func:`crotch_shape`
    on ``layer``'s alpha) change, and only pixels along the child
    (within ``3 fillet`` of its target stroke). The arc's radius is at
    most 1.5 times the child's half width.

    Parameters
    ----------
    layer : (H, W, 4) ndarray
        Straight RGBA.
    junctions : list of Junction
        The junctions to round (:func:`new_crotches`).
    attached : list of StrokePair
        The pairs (their target strokes).
    joints : list of tuple
        Per junction, ``(point, reach, pocket, junction)`` as the composition
        closes them (the same order as ``junctions``).
    fillet : float
        The source's crotch radius (:func:`source_fillet`).
    inner : int, optional
        New pixels take the colours from this deep inside (an outlined object).
    half_widths : sequence of float, optional
        Per junction, the child's half width (default: ``fillet``).
    min_angle : float
        See :func:`source_fillet`.

    Returns
    -------
    ndarray
        A new array, or ``layer`` if nothing changed.

    Examples
    --------
    >>> from branchnb.strokes.junctions import find_junctions
    >>> from branchnb.strokes.strokes import StrokePair
    >>> layer = np.zeros((80, 80, 4), np.float32); layer[:, 32:49] = (0.5, 0.3, 0.1, 1.0)
    >>> layer[32:49, 40:] = (0.5, 0.3, 0.1, 1.0)
    >>> st = [Stroke([(40, 0), (40, 79)]), Stroke([(40, 40), (79, 40)])]
    >>> pairs = [StrokePair(s, s) for s in st]
    >>> jn = find_junctions(st, 2.0)
    >>> out = round_crotches(layer, jn, pairs, [(j.point, 20.0, None, j) for j in jn], 8.0)
    >>> int((out[..., 3] > 0.5).sum() - (layer[..., 3] > 0.5).sum()) > 20    # two corners filled
    True
    """
    from .outline import fill_joints

    hws = [fillet] * len(junctions) if half_widths is None else list(half_widths)
    alpha = layer[:, :, 3]
    allowed = []
    for jn, hw in zip(junctions, hws):
        child = attached[jn.child].target
        child = child if jn.end == 0 else child.reversed()
        ang = crotch_angles(jn.point, child, attached[jn.parent].target, jn.parent_s, float(hw))
        sides = [side for side, (turn, radius) in crotch_shape(alpha, jn.point, child, float(hw)).items()
                 if ang.get(side, 0.0) >= min_angle and radius < fillet]
        allowed.append((child, sides))
    todo = [(j, a) for j, a in zip(joints, allowed) if a[1]]
    if not todo:
        return layer
    # the fillet's arc reaches ``fillet tan(turn / 2)`` past the corner: the joints' reach grown by it
    todo = [((j[0], j[1] + fillet, j[2], j[3]), a) for j, a in todo]
    # no arc wider than 1.5 child half widths (a thin twig on a trunk with wide collars
    # would get a web)
    radii = [min(fillet, 1.5 * hw) for hw, (_, sides) in zip(hws, allowed) if sides]
    out = fill_joints(layer, [j[0] for j, _ in todo], [j[1] for j, _ in todo],
                      pockets=radii, inner=inner)
    if out is layer:
        return layer
    changed = np.any(out != layer, axis=2)
    keep = np.zeros_like(changed)
    yy, xx = np.nonzero(changed)
    q = np.c_[xx, yy].astype(float)
    for (point, reach, _, _), (child, sides) in todo:
        s, d = child.project(q)
        ahead = child.point_at(min(child.length, 2.0 * fillet + 2.0)) - np.asarray(point, float)
        u = ahead / max(np.hypot(*ahead), 1e-9)
        rel = q - np.asarray(point, float)
        across = np.sign(-rel[:, 0] * u[1] + rel[:, 1] * u[0])
        ok = (np.hypot(*rel.T) <= reach) & (d <= 3.0 * fillet) & (rel @ u > 0) & np.isin(across, sides)
        keep[yy[ok], xx[ok]] = True
    if keep.all() or not (changed & ~keep).any():
        return out
    out[changed & ~keep] = layer[changed & ~keep]
    return out
