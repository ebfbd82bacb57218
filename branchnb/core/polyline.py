"""Polylines: resampling, turning angles, tangents/normals and rigid alignment.

A polyline is an ``(N, 2)`` float array of ``(x, y)`` vertices in image
pixels (origin top-left, y down). Per-vertex attributes such as thickness
travel alongside as ``(N,)`` or ``(N, K)`` arrays.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .image import as_points
from .validate import MAX_COUNT, Int, Real, checked, real_array

__all__ = [
    "arc_length",
    "polyline_length",
    "resample_uniform",
    "resample_chord",
    "turning_angles",
    "tangents",
    "normals",
    "RigidTransform",
    "rigid_align",
    "segments_intersect",
]


def _values(values, n: int, name: str = "values") -> np.ndarray | None:
    if values is None:
        return None
    v = real_array(values, name, allow_empty=True, finite=False)
    if v.shape[:1] != (n,):
        raise ValueError(f"{name} must have one row per vertex ({n}), got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return v


@checked()
def arc_length(points, *, closed: bool = False) -> np.ndarray:
    """Cumulative arc length at each vertex (starts at 0).

    With ``closed=True`` one more entry is appended: the total length
    including the closing edge back to the first vertex.

    Parameters
    ----------
    points : (N, 2) array_like
        Vertices (x, y) in pixels, N >= 1.
    closed : bool
        Count the edge from the last vertex back to the first.

    Returns
    -------
    (N,) or (N + 1,) float ndarray
        Distance along the polyline from ``points[0]`` (pixels).

    Examples
    --------
    >>> arc_length([(0, 0), (3, 4), (3, 5)]).tolist()
    [0.0, 5.0, 6.0]
    """
    p = as_points(points, min_points=1)
    if closed:
        p = np.vstack([p, p[:1]])
    seg = np.hypot(*np.diff(p, axis=0).T)
    return np.concatenate([[0.0], np.cumsum(seg)])


@checked()
def polyline_length(points, *, closed: bool = False) -> float:
    """Total length of a polyline.

    Parameters
    ----------
    points : (N, 2) array_like
        Vertices (x, y) in pixels, N >= 1 (a single vertex has length 0).
    closed : bool
        Add the edge from the last vertex back to the first.

    Returns
    -------
    float
        Length in pixels.

    Examples
    --------
    >>> polyline_length([(0, 0), (3, 4)]), polyline_length([(0, 0), (3, 4)], closed=True)
    (5.0, 10.0)
    """
    return float(arc_length(points, closed=closed)[-1])


def _interp_at(s_new: np.ndarray, s: np.ndarray, data: np.ndarray) -> np.ndarray:
    # Drop zero-length edges so interpolation is well defined.
    keep = np.concatenate([[True], np.diff(s) > 1e-12])
    s, data = s[keep], data[keep]
    if data.ndim == 1:
        return np.interp(s_new, s, data)
    return np.stack([np.interp(s_new, s, data[:, j]) for j in range(data.shape[1])], axis=1)


@checked(h=Real(0, low_open=True))
def resample_uniform(points, h: float, *, values=None, include_end: bool = False):
    """Resample a polyline at uniform arc-length step ``h``.

    Vertices are placed at arc lengths ``0, h, 2h, ...`` along the input,
    so every edge of the output has chord length close to ``h`` (exactly
    ``h`` along straight parts), which makes turning angles of different
    polylines comparable.

    Parameters
    ----------
    points : (N, 2) array_like
        Input vertices, N >= 2, not all identical.
    h : float
        Step (pixels), > 0.
    values : (N,) or (N, K) array_like, optional
        Per-vertex attributes (e.g. thickness), linearly interpolated.
    include_end : bool
        Also append the last input vertex if the remainder is > h / 2.

    Returns
    -------
    out : (M, 2) ndarray
        Resampled vertices; ``(out, values_out)`` if ``values`` was given.

    Examples
    --------
    >>> resample_uniform([(0, 0), (10, 0)], 2.5).tolist()
    [[0.0, 0.0], [2.5, 0.0], [5.0, 0.0], [7.5, 0.0], [10.0, 0.0]]
    """
    p = as_points(points, min_points=2)
    if not np.isfinite(h) or h <= 0:
        raise ValueError(f"h must be a positive step, got {h}")
    v = _values(values, len(p))
    s = arc_length(p)
    if s[-1] <= 0:
        raise ValueError("points has zero length: all vertices coincide")
    return _resample_uniform(p, h, v, include_end, s)


def _arc_length(p: np.ndarray) -> np.ndarray:
    """:func:`arc_length` of checked (N, 2) float points (open polyline)."""
    seg = np.hypot(*np.diff(p, axis=0).T)
    return np.concatenate([[0.0], np.cumsum(seg)])


def _resample_uniform(p: np.ndarray, h: float, v, include_end: bool, s: np.ndarray):
    """:func:`resample_uniform` of checked points ``p``, values ``v`` (or None) and their arc length
    ``s`` (> 0 at the end): the per-branch inner call of structure resampling."""
    total = s[-1]
    if total / h > MAX_COUNT:
        raise ValueError(f"h = {h:g} would make {total / h:.3g} points along a polyline of length {total:.4g} "
                         f"(limit {MAX_COUNT})")
    s_new = np.arange(0.0, total + 1e-9 * max(1.0, total), h)
    if include_end and total - s_new[-1] > h / 2:
        s_new = np.append(s_new, total)
    out = _interp_at(s_new, s, p)
    if v is None:
        return out
    return out, _interp_at(s_new, s, v)


@checked(n=Int(2, MAX_COUNT))
def resample_chord(points, n: int, *, closed: bool = False, values=None):
    """Resample to exactly ``n`` points equally spaced by chord (arc) length.

    Parameters
    ----------
    points : (N, 2) array_like
        Vertices (x, y) in pixels.
    n : int
        Number of output points, >= 2 (>= 3 if closed).
    closed : bool
        Treat the polyline as a closed contour: the ``n`` points are spread
        over the whole loop and the last one does not repeat the first.
    values : (N,) or (N, K) array_like, optional
        Per-vertex attributes to interpolate.

    Returns
    -------
    points : (n, 2) float ndarray
        The resampled points.
    values : ndarray
        The attributes interpolated linearly at them; only returned when
        ``values`` is given.

    Raises
    ------
    TypeError, ValueError
        If ``n`` is not an int large enough, or all vertices coincide.

    Examples
    --------
    >>> resample_chord([(0, 0), (4, 0)], 3).tolist()
    [[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]]
    """
    p = as_points(points, min_points=2)
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool):
        raise TypeError(f"n must be an int, got {type(n).__name__}")
    if n < (3 if closed else 2):
        raise ValueError(f"n must be >= {3 if closed else 2}, got {n}")
    v = _values(values, len(p))
    if closed:
        p = np.vstack([p, p[:1]])
        if v is not None:
            v = np.concatenate([v, v[:1]])
    s = arc_length(p)
    if s[-1] <= 0:
        raise ValueError("points has zero length: all vertices coincide")
    if closed:
        s_new = np.linspace(0.0, s[-1], n + 1)[:-1]
    else:
        s_new = np.linspace(0.0, s[-1], n)
    out = _interp_at(s_new, s, p)
    if v is None:
        return out
    return out, _interp_at(s_new, s, v)


def turning_angles(points) -> np.ndarray:
    """Signed turning angle (radians, in (-pi, pi]) at each interior vertex.

    Positive angles turn clockwise on screen (counter-clockwise in the
    usual y-up frame is negative) because y points down in image
    coordinates. Returns ``N - 2`` values.

    Parameters
    ----------
    points : (N, 2) array_like
        Vertices (x, y), N >= 2 (two vertices give an empty array).
        A repeated vertex gives angle 0 there.

    Returns
    -------
    (N - 2,) float ndarray
        The angle between edge ``i`` and edge ``i + 1`` at vertex ``i + 1``.

    Examples
    --------
    >>> import numpy as np
    >>> np.degrees(turning_angles([(0, 0), (1, 0), (1, 1)])).round(6).tolist()
    [90.0]
    """
    p = as_points(points, min_points=2)
    d = np.diff(p, axis=0)
    u, v = d[:-1], d[1:]
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    dot = np.einsum("ij,ij->i", u, v)
    return np.arctan2(cross, dot)


@checked()
def tangents(points, *, closed: bool = False) -> np.ndarray:
    """Unit tangents at each vertex (central differences, one-sided at ends).

    Parameters
    ----------
    points : (N, 2) array_like
        Vertices (x, y), N >= 2.
    closed : bool
        Treat the polyline as a loop: the ends use central differences
        across the closing edge too.

    Returns
    -------
    (N, 2) float ndarray
        Unit vectors (x, y); zero where two neighbours coincide.

    Examples
    --------
    >>> tangents([(0, 0), (2, 0)]).tolist()
    [[1.0, 0.0], [1.0, 0.0]]
    """
    p = as_points(points, min_points=2)
    if closed:
        t = np.roll(p, -1, axis=0) - np.roll(p, 1, axis=0)
    else:
        t = np.empty_like(p)
        t[1:-1] = p[2:] - p[:-2]
        t[0] = p[1] - p[0]
        t[-1] = p[-1] - p[-2]
    norm = np.hypot(t[:, 0], t[:, 1])
    norm[norm == 0] = 1.0
    return t / norm[:, None]


@checked()
def normals(points, *, closed: bool = False) -> np.ndarray:
    """Unit normals: tangents rotated by +90 degrees, ``(-ty, tx)``.

    On screen (y down) the normal points to the right of the direction of
    travel.

    Parameters
    ----------
    points : (N, 2) array_like
        Vertices (x, y), N >= 2.
    closed : bool
        Treat the polyline as a loop (see :func:`tangents`).

    Returns
    -------
    (N, 2) float ndarray
        Unit normals (x, y).

    Examples
    --------
    >>> normals([(0, 0), (2, 0)]).tolist()
    [[-0.0, 1.0], [-0.0, 1.0]]
    """
    t = tangents(points, closed=closed)
    return np.stack([-t[:, 1], t[:, 0]], axis=1)


@dataclass(frozen=True)
class RigidTransform:
    """A 2-D rigid transform ``x -> R @ x + t``.

    Calling it maps ``(N, 2)`` points (x, y) and returns the moved points.

    Parameters
    ----------
    rotation : (2, 2) ndarray
        The rotation matrix ``R`` (orthonormal, determinant +1), acting on
        column vectors (x, y).
    translation : (2,) ndarray
        The shift ``t`` (pixels), applied after the rotation.

    Examples
    --------
    >>> import numpy as np
    >>> T = RigidTransform(np.array([[0.0, -1.0], [1.0, 0.0]]), np.array([10.0, 0.0]))
    >>> T([(1, 0)]).tolist(), round(np.degrees(T.angle))
    ([[10.0, 1.0]], 90)
    """

    rotation: np.ndarray
    translation: np.ndarray

    @property
    def angle(self) -> float:
        """Rotation angle in radians."""
        return float(np.arctan2(self.rotation[1, 0], self.rotation[0, 0]))

    @property
    def matrix(self) -> np.ndarray:
        """The 2 x 3 affine matrix ``[R | t]`` (OpenCV's layout)."""
        return np.hstack([self.rotation, self.translation[:, None]])

    def __call__(self, points) -> np.ndarray:
        p = as_points(points)
        return p @ self.rotation.T + self.translation


def rigid_align(source, target, *, weights=None) -> RigidTransform:
    """Closed-form least-squares rigid alignment of two point sets (Kabsch).

    Finds the rotation ``R`` (no reflection) and translation ``t`` that
    minimise ``sum_i w_i ||R p_i + t - q_i||^2``: one step of 2-D ICP with
    known correspondences.

    Parameters
    ----------
    source, target : (N, 2) array_like
        Corresponding points ``p_i`` and ``q_i``.
    weights : (N,) array_like, optional
        Non-negative weights (equal by default), with a positive sum.

    Returns
    -------
    RigidTransform
        Maps ``source`` onto ``target``.

    Raises
    ------
    ValueError
        If the point sets differ in shape or the weights are invalid.

    Examples
    --------
    >>> import numpy as np
    >>> p = np.array([(0, 0), (1, 0), (0, 2)], float)
    >>> T = rigid_align(p, p @ [[0, 1], [-1, 0]] + 5)
    >>> np.allclose(T(p), p @ [[0, 1], [-1, 0]] + 5)
    True
    """
    p = as_points(source, name="source")
    q = as_points(target, name="target")
    if p.shape != q.shape:
        raise ValueError(f"source and target must have the same shape, got {p.shape} and {q.shape}")
    w = np.ones(len(p)) if weights is None else _values(weights, len(p), "weights")
    if np.any(w < 0) or w.sum() <= 0:
        raise ValueError("weights must be non-negative with a positive sum")
    w = w / w.sum()
    mp, mq = w @ p, w @ q
    h = (p - mp).T @ ((q - mq) * w[:, None])
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(vt.T @ u.T)) or 1.0
    r = vt.T @ np.diag([1.0, d]) @ u.T
    return RigidTransform(rotation=r, translation=mq - r @ mp)


@checked(eps=Real(0))
def segments_intersect(a0, a1, b0, b1, *, eps: float = 1e-12) -> np.ndarray:
    """Which pairs of segments properly cross (touching end points do not count).

    Parameters
    ----------
    a0, a1 : (N, 2) array_like
        End points of the first N segments.
    b0, b1 : (M, 2) array_like
        End points of the other M segments.
    eps : float
        Tolerance on the orientation tests: crossings within ``eps`` of
        collinear (a touching end point, overlapping collinear segments)
        do not count.

    Returns
    -------
    (N, M) bool ndarray
        ``True`` where segment i of ``a`` crosses segment j of ``b`` at a
        point interior to both.

    Examples
    --------
    >>> segments_intersect([(0, 0)], [(2, 2)], [(0, 2)], [(2, 0)]).tolist()
    [[True]]
    """
    a0, a1 = as_points(a0, name="a0"), as_points(a1, name="a1")
    b0, b1 = as_points(b0, name="b0"), as_points(b1, name="b1")
    if len(a0) != len(a1):
        raise ValueError(f"a0 and a1 must hold the same number of end points, got {len(a0)} and {len(a1)}")
    if len(b0) != len(b1):
        raise ValueError(f"b0 and b1 must hold the same number of end points, got {len(b0)} and {len(b1)}")

    def orient(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (
            r[..., 0] - p[..., 0]
        )

    A0, A1 = a0[:, None, :], a1[:, None, :]
    B0, B1 = b0[None, :, :], b1[None, :, :]
    d1 = orient(A0, A1, B0)
    d2 = orient(A0, A1, B1)
    d3 = orient(B0, B1, A0)
    d4 = orient(B0, B1, A1)
    return (d1 * d2 < -eps) & (d3 * d4 < -eps)
