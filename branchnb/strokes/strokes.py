"""Strokes, stroke pairs and control-point pairs.

A *stroke* is an ordered polyline the user draws along the skeleton of an
object; every point of it carries a local orientation (the direction of
the stroke there). A *stroke pair* couples a source stroke, drawn on the
example image, with a target stroke, drawn in the output domain: the
object's texture around the source stroke is re-synthesized along the
target stroke.

*Control-point pairs* fix which point of the source stroke corresponds to
which point of the target stroke. The two end points always form a pair
(``c_0`` and ``c_K``); the user may add more in between. Between two
consecutive control points ``c_i`` and ``c_i+1`` the correspondence is by
arc-length fraction (see :meth:`StrokePair.source_arc_length`).

Positions along a stroke are arc lengths ``s`` in pixels from its first
point. Control points are stored as ``(s_source, s_target)`` rows.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.image import as_points
from ..core.polyline import arc_length
from ..core.validate import Array, Real, Seq, Shape, checked, real_array

__all__ = ["Stroke", "StrokePair", "make_pairs"]

#: Shortest accepted stroke (pixels): shorter strokes count as zero-length.
MIN_LENGTH = 1.0

#: Arc lengths along a stroke (one or many, finite).
_ARC = Array(ndim=(0, 1))


@dataclass(frozen=True, eq=False)
class Stroke:
    """An ordered polyline with a local orientation at every point.

    Parameters
    ----------
    points : (N, 2) array_like
        Vertices ``(x, y)`` in pixels, N >= 2, total length >= 1 pixel.
        Repeated consecutive vertices are allowed (they are dropped).
    name : str
        Used in error messages (e.g. ``"source_strokes[1]"``).

    Examples
    --------
    >>> st = Stroke([(0, 0), (10, 0), (10, 10)])
    >>> st.length
    20.0
    >>> st.point_at([5.0, 15.0]).tolist()
    [[5.0, 0.0], [10.0, 5.0]]
    >>> round(float(np.degrees(st.angle_at(15.0, window=2.0))))
    90
    """

    points: np.ndarray
    name: str = "stroke"
    s: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        p = as_points(self.points, name="points" if self.name == "stroke" else self.name, min_points=2)
        keep = np.concatenate([[True], np.hypot(*np.diff(p, axis=0).T) > 1e-9])
        p = p[keep]
        s = arc_length(p) if len(p) > 1 else np.zeros(1)
        if s[-1] < MIN_LENGTH:
            raise ValueError(
                f"{'points' if self.name == 'stroke' else self.name} has zero length ({s[-1]:.3g} px): "
                "draw a stroke of at least "
                f"{MIN_LENGTH:g} pixel"
            )
        p.setflags(write=False)
        s.setflags(write=False)
        object.__setattr__(self, "points", p)
        object.__setattr__(self, "s", s)

    @property
    def length(self) -> float:
        """Arc length ``L`` (pixels)."""
        return float(self.s[-1])

    @checked(s=_ARC)
    def point_at(self, s) -> np.ndarray:
        """Points ``(x, y)`` at arc lengths ``s`` (clamped to ``[0, L]``).

        Parameters
        ----------
        s : float or (M,) array_like
            Arc lengths in pixels from the first point; clamped to ``[0, L]``.

        Returns
        -------
        (2,) or (M, 2) float64 ndarray
            Linearly interpolated ``(x, y)``.
        """
        return self._point_at(s)

    def _point_at(self, s) -> np.ndarray:
        """:meth:`point_at` without the argument check (arc lengths computed here)."""
        s = np.clip(np.asarray(s, float), 0.0, self.length)
        return np.stack([np.interp(s, self.s, self.points[:, 0]),
                         np.interp(s, self.s, self.points[:, 1])], axis=-1)

    @checked(s=_ARC, window=Real(0, 1e5))
    def angle_at(self, s, *, window: float = 0.0) -> np.ndarray:
        """Local orientation (radians from +x towards +y) at arc lengths ``s``.

        The direction of the chord from ``s - window`` to ``s + window``
        (clamped to the stroke), which smooths the jitter of hand-drawn
        strokes; ``window = 0`` gives the direction of the edge under
        ``s``.

        Parameters
        ----------
        s : float or (M,) array_like
            Arc lengths in pixels; clamped to ``[0, L]``.
        window : float
            Half-length (pixels, >= 0) of the chord; 0 by default.

        Returns
        -------
        float64 ndarray
            Angles in radians, of the shape of ``s`` (y points down, so positive
            angles turn clockwise on screen).
        """
        return self._angle_at(s, window)

    def _angle_at(self, s, window: float = 0.0) -> np.ndarray:
        """:meth:`angle_at` without the argument checks."""
        s = np.clip(np.asarray(s, float), 0.0, self.length)
        w = max(float(window), 1e-3)
        lo = np.clip(s - w, 0.0, self.length - 2e-3)
        hi = np.maximum(np.clip(s + w, 0.0, self.length), lo + 1e-3)
        d = self._point_at(hi) - self._point_at(lo)
        return np.arctan2(d[..., 1], d[..., 0])

    @checked(s=_ARC, window=Real(0, 1e5))
    def normal_at(self, s, *, window: float = 0.0) -> np.ndarray:
        """Unit normals (right of the direction of travel on screen) at ``s``.

        Parameters
        ----------
        s : float or (M,) array_like
            Arc lengths in pixels; clamped to ``[0, L]``.
        window : float
            Half-length of the chord the direction is taken from (see
            :meth:`angle_at`).

        Returns
        -------
        (2,) or (M, 2) float64 ndarray
            Unit ``(x, y)`` vectors, the direction turned by +90 degrees.

        Examples
        --------
        >>> Stroke([(0, 0), (10, 0)]).normal_at(5.0).round(6).tolist()
        [-0.0, 1.0]
        """
        return self._normal_at(s, window)

    def _normal_at(self, s, window: float = 0.0) -> np.ndarray:
        """:meth:`normal_at` without the argument checks."""
        a = self._angle_at(s, window)
        return np.stack([-np.sin(a), np.cos(a)], axis=-1)

    @checked(points=Array(ndim=2))
    def project(self, points) -> tuple[np.ndarray, np.ndarray]:
        """Arc length of the nearest stroke point to each of ``points`` and the distance.

        Parameters
        ----------
        points : (M, 2) array_like
            ``(x, y)`` points in pixels.

        Returns
        -------
        s : (M,) ndarray
        dist : (M,) ndarray

        Examples
        --------
        >>> s, d = Stroke([(0, 0), (10, 0)]).project([(4, 3)])
        >>> s.tolist(), d.tolist()
        ([4.0], [3.0])
        """
        q = as_points(points, name="points")
        a, b = self.points[:-1], self.points[1:]
        ab = b - a
        seg_len2 = (ab**2).sum(axis=1)
        t = ((q[:, None, :] - a[None]) * ab[None]).sum(axis=2) / seg_len2[None]
        t = np.clip(t, 0.0, 1.0)
        foot = a[None] + t[:, :, None] * ab[None]
        d2 = ((q[:, None, :] - foot) ** 2).sum(axis=2)
        k = np.argmin(d2, axis=1)
        rows = np.arange(len(q))
        s = self.s[k] + t[rows, k] * np.sqrt(seg_len2[k])
        return s, np.sqrt(d2[rows, k])

    def reversed(self) -> Stroke:
        """The same stroke traversed the other way."""
        return Stroke(self.points[::-1].copy(), name=self.name)

    @checked(shape=Shape())
    def inside(self, shape) -> bool:
        """Whether every point lies inside an image of ``shape`` (half a pixel of tolerance).

        Parameters
        ----------
        shape : tuple of int
            Image shape ``(H, W, ...)``.

        Returns
        -------
        bool

        Examples
        --------
        >>> Stroke([(0, 0), (10, 0)]).inside((5, 10)), Stroke([(0, 0), (10, 0)]).inside((5, 11))
        (False, True)
        """
        h, w = shape[:2]
        x, y = self.points[:, 0], self.points[:, 1]
        return bool(np.all((x >= -0.5) & (x <= w - 0.5) & (y >= -0.5) & (y <= h - 0.5)))


@dataclass(frozen=True, eq=False)
class StrokePair:
    """A source stroke, its target stroke and their control-point pairs.

    Parameters
    ----------
    source, target : Stroke
        The stroke on the example image and the stroke in the output
        domain its texture is re-synthesized along.
    control : (K, 2) array_like, optional
        Control-point pairs as arc lengths ``(s_source, s_target)``. The
        end-point pairs ``(0, 0)`` and ``(L_source, L_target)`` are added
        if missing. Both columns must increase strictly: control points
        out of order raise ``ValueError``.
    name : str
        Used in error messages (``make_pairs`` passes ``"pair i"``).

    Examples
    --------
    >>> pair = StrokePair(Stroke([(0, 0), (10, 0)]), Stroke([(0, 0), (0, 20)]))
    >>> pair.source_arc_length([0.0, 10.0, 20.0]).tolist()
    [0.0, 5.0, 10.0]
    >>> pair = pair.with_control([(8, 0)], [(0, 10)])
    >>> pair.source_arc_length([5.0, 10.0, 15.0]).tolist()
    [4.0, 8.0, 9.0]
    """

    source: Stroke
    target: Stroke
    control: np.ndarray = None
    name: str = "pair"

    def __post_init__(self):
        if not isinstance(self.source, Stroke) or not isinstance(self.target, Stroke):
            raise TypeError(f"{self.name}: source and target must be Stroke instances")
        ls, lt = self.source.length, self.target.length
        c = np.zeros((0, 2)) if self.control is None else real_array(
            self.control, f"{self.name}: control", allow_empty=True, finite=False)
        if c.ndim != 2 or c.shape[1] != 2:
            raise ValueError(f"{self.name}: control must have shape (K, 2), got {c.shape}")
        if not np.all(np.isfinite(c)):
            raise ValueError(f"{self.name}: control contains NaN or infinite values")
        tol = 1e-6
        if len(c) and ((c[:, 0] < -tol).any() or (c[:, 0] > ls + tol).any()
                       or (c[:, 1] < -tol).any() or (c[:, 1] > lt + tol).any()):
            raise ValueError(f"{self.name}: control arc lengths must lie on the strokes")
        # Drop end pairs given explicitly, then add the canonical ones.
        inner = c[(c[:, 0] > tol) & (c[:, 0] < ls - tol) & (c[:, 1] > tol) & (c[:, 1] < lt - tol)]
        if len(inner) != len(c) - _n_end_pairs(c, ls, lt, tol):
            raise ValueError(
                f"{self.name}: an interior control point lies on a stroke end; control points "
                "must pair interior points with interior points"
            )
        full = np.vstack([[0.0, 0.0], inner, [ls, lt]])
        for col, which in ((0, "source"), (1, "target")):
            if np.any(np.diff(full[:, col]) <= 0):
                raise ValueError(
                    f"{self.name}: control points out of order along the {which} stroke "
                    f"(arc lengths {np.round(full[:, col], 1).tolist()}); they must follow both "
                    "strokes in the same order"
                )
        full.setflags(write=False)
        object.__setattr__(self, "control", full)

    @checked(s_target=_ARC)
    def source_arc_length(self, s_target) -> np.ndarray:
        """Map target arc lengths to source arc lengths (piecewise linear).

        A point ``p`` between target control points ``c_i`` and ``c_i+1``
        at fraction ``f`` of that stretch maps to the point at fraction
        ``f`` between the corresponding source control points.

        Parameters
        ----------
        s_target : float or (M,) array_like
            Arc lengths (pixels) along the target stroke.

        Returns
        -------
        float64 ndarray
            Corresponding arc lengths along the source stroke, of the shape of
            ``s_target`` (clamped to the ends).
        """
        return np.interp(np.asarray(s_target, float), self.control[:, 1], self.control[:, 0])

    @checked(source_points=Array(ndim=(1, 2)), target_points=Array(ndim=(1, 2)))
    def with_control(self, source_points, target_points) -> StrokePair:
        """A copy with more control-point pairs, given as points near the strokes.

        Each point is projected on its stroke (nearest point). The new
        pairs must keep the order along both strokes.

        Parameters
        ----------
        source_points : (K, 2) array_like
            ``(x, y)`` points near the source stroke, one per new pair.
        target_points : (K, 2) array_like
            ``(x, y)`` points near the target stroke, in the same order.

        Returns
        -------
        StrokePair
            ``self`` when no points are given.

        Raises
        ------
        ValueError
            If the two lists differ in length or the new pairs cross the existing
            ones (out of order along a stroke).
        """
        sp = as_points(source_points, name="source_points")
        tp = as_points(target_points, name="target_points")
        if len(sp) != len(tp):
            raise ValueError(
                f"{self.name}: got {len(sp)} source and {len(tp)} target control points; "
                "they come in pairs"
            )
        if not len(sp):
            return self
        ss, _ = self.source.project(sp)
        ts, _ = self.target.project(tp)
        new = np.vstack([self.control[1:-1], np.column_stack([ss, ts])])
        new = new[np.argsort(new[:, 1], kind="stable")]
        try:
            return StrokePair(self.source, self.target, new, name=self.name)
        except ValueError as exc:
            raise ValueError(f"source_points/target_points: {exc}") from None

    @property
    def n_control(self) -> int:
        """Number of control-point pairs (>= 2)."""
        return len(self.control)


def _n_end_pairs(c: np.ndarray, ls: float, lt: float, tol: float) -> int:
    start = (np.abs(c[:, 0]) <= tol) & (np.abs(c[:, 1]) <= tol)
    end = (np.abs(c[:, 0] - ls) <= tol) & (np.abs(c[:, 1] - lt) <= tol)
    return int(start.sum() + end.sum())


def _as_stroke(obj, name: str) -> Stroke:
    if isinstance(obj, Stroke):
        return obj
    return Stroke(obj, name=name)


@checked(source_strokes=Seq(), target_strokes=Seq(), control_points=Seq(), source_shape=Shape(), target_shape=Shape())
def make_pairs(source_strokes, target_strokes, control_points=None, *,
               source_shape=None, target_shape=None) -> list[StrokePair]:
    """Pair source and target strokes in drawing order and validate them.

    Parameters
    ----------
    source_strokes, target_strokes : sequence of (N, 2) array_like or Stroke
        The i-th source stroke pairs with the i-th target stroke; both
        lists must have the same length (>= 1). A stroke needs at least
        two points and a length of at least one pixel.
    control_points : sequence, optional
        One entry per pair: None or a pair ``(source_points, target_points)``
        of equally long ``(K, 2)`` point lists, the extra control points
        clicked near the source and the target stroke. They are projected
        on the strokes and must keep the order along both strokes.
    source_shape : tuple, optional
        Shape of the source image: every source point must lie inside it
        (the texture must exist there).
    target_shape : tuple, optional
        Shape of the output domain: a target stroke may leave it (its
        texture is clipped) but must not lie entirely outside.

    Returns
    -------
    list of StrokePair

    Examples
    --------
    >>> pairs = make_pairs([[(0, 0), (9, 0)]], [[(0, 5), (0, 14)]])
    >>> pairs[0].control.tolist()
    [[0.0, 0.0], [9.0, 9.0]]
    """
    src = _as_list(source_strokes, "source_strokes")
    tgt = _as_list(target_strokes, "target_strokes")
    if len(src) != len(tgt):
        raise ValueError(
            f"source_strokes and target_strokes must pair up one to one: got {len(src)} source "
            f"and {len(tgt)} target strokes"
        )
    if not src:
        raise ValueError("source_strokes is empty: draw at least one source and one target stroke")
    if control_points is None:
        control_points = [None] * len(src)
    control_points = list(control_points)
    if len(control_points) != len(src):
        raise ValueError(
            f"control_points must have one entry per stroke pair ({len(src)}), got {len(control_points)}"
        )
    pairs = []
    for i, (a, b, cp) in enumerate(zip(src, tgt, control_points)):
        s = _as_stroke(a, f"source_strokes[{i}]")
        t = _as_stroke(b, f"target_strokes[{i}]")
        if source_shape is not None and not s.inside(source_shape):
            bad = _first_outside(s.points, source_shape)
            raise ValueError(
                f"source_strokes[{i}] leaves the {source_shape[1]} x {source_shape[0]} source "
                f"image at ({bad[0]:.1f}, {bad[1]:.1f}): source strokes must lie on the image"
            )
        if target_shape is not None and _first_outside(t.points, target_shape, all_out=True) is not None:
            raise ValueError(
                f"target_strokes[{i}] lies entirely outside the {target_shape[1]} x "
                f"{target_shape[0]} target domain"
            )
        pair = StrokePair(s, t, name=f"pair {i}")
        if cp is not None:
            if not isinstance(cp, (tuple, list)) or len(cp) != 2:
                raise ValueError(
                    f"control_points[{i}] must be a pair (source_points, target_points)"
                )
            pair = pair.with_control(cp[0], cp[1])
        pairs.append(pair)
    return pairs


def _as_list(strokes, name: str) -> list:
    if isinstance(strokes, np.ndarray) and strokes.ndim == 2:
        raise TypeError(f"{name} must be a list of strokes, not a single (N, 2) array; wrap it in [...]")
    try:
        return list(strokes)
    except TypeError as exc:
        raise TypeError(f"{name} must be a list of (N, 2) point arrays") from exc


def _first_outside(points: np.ndarray, shape, all_out: bool = False):
    h, w = shape[:2]
    x, y = points[:, 0], points[:, 1]
    out = (x < -0.5) | (x > w - 0.5) | (y < -0.5) | (y > h - 0.5)
    if all_out:
        return points[0] if out.all() else None
    return points[int(np.flatnonzero(out)[0])] if out.any() else None
