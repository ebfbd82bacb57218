"""Colour transfer with mean value coordinates (paper, Sec. "Colour transfer").

The new tree's pixels get their colour from the exemplars through a cage
deformation. For a target pixel ``p`` inside the new contour, the mean value
coordinates ``lambda_i(p)`` with respect to the target's simplified contour
``C_s`` (``M`` vertices) give the corresponding point of every source tree,

.. math:: q = \\sum_i \\lambda_i(p)\\, C_{s,i}^{\\mathrm{src}},

where RGBA is sampled bilinearly. With several exemplars, the output alpha
is the maximum of the sampled alphas and the colour a random convex
combination of the contributions that are not transparent.

Mean value coordinates (Floater 2003) are computed with the formulation of
Hormann & Floater (2006) for *arbitrary* planar polygons: signed angles, so
non-convex cages and points outside the cage are handled, with the exact
limits on vertices and edges.

References
----------
M. S. Floater. Mean value coordinates. CAGD 20(1), 2003.
K. Hormann, M. S. Floater. Mean value coordinates for arbitrary planar
polygons. ACM TOG 25(4), 2006.
"""

from __future__ import annotations

import cv2
import numba
import numpy as np

from ..core.image import as_mask, as_points, as_rgba
from ..core.random import as_rng
from ..core.validate import Array, checked
from .morph import check_weights

__all__ = [
    "mean_value_coordinates",
    "mvc_map",
    "sample_rgba",
    "transfer_colour",
]

@numba.njit(cache=True)
def _mvc_point(x: float, y: float, v: np.ndarray, s: np.ndarray, r: np.ndarray,
               t: np.ndarray, lam: np.ndarray) -> None:
    """Mean value coordinates of one point (x, y) w.r.t. polygon ``v`` into ``lam``.

    ``s``, ``r``, ``t`` are scratch arrays of sizes (M, 2), M, M.
    """
    m = v.shape[0]
    for i in range(m):
        s[i, 0] = v[i, 0] - x                                 # s_i = v_i - p
        s[i, 1] = v[i, 1] - y
        r[i] = np.sqrt(s[i, 0] * s[i, 0] + s[i, 1] * s[i, 1])  # r_i = |s_i|
        if r[i] <= 1e-12:                                     # on a vertex
            lam[:] = 0.0
            lam[i] = 1.0
            return
    for i in range(m):
        j = i + 1 if i + 1 < m else 0
        a = s[i, 0] * s[j, 1] - s[i, 1] * s[j, 0]            # 2 A_i = det(s_i, s_i+1)
        d = s[i, 0] * s[j, 0] + s[i, 1] * s[j, 1]            # D_i = <s_i, s_i+1>
        rr = r[i] * r[j]
        den = rr + d                                          # r_i r_i+1 (1 + cos alpha_i)
        if den <= 1e-12 * rr and abs(a) <= 1e-9 * rr:         # on edge i: linear limit
            lam[:] = 0.0
            lam[i] = r[j] / (r[i] + r[j])
            lam[j] = r[i] / (r[i] + r[j])
            return
        t[i] = a / den                                        # tan(alpha_i / 2), signed
    total = 0.0
    wabs = 0.0
    for i in range(m):
        h = i - 1 if i > 0 else m - 1
        w = (t[h] + t[i]) / r[i]                              # w_i
        lam[i] = w
        total += w
        wabs += abs(w)
    if abs(total) > 1e-12 * wabs:
        for i in range(m):
            lam[i] /= total
        return
    # W(p) = 0 (possible outside a self-intersecting cage): nearest edge point.
    best = np.inf
    bi = 0
    bu = 0.0
    for i in range(m):
        j = i + 1 if i + 1 < m else 0
        ex = v[j, 0] - v[i, 0]
        ey = v[j, 1] - v[i, 1]
        ee = ex * ex + ey * ey
        u = 0.0 if ee <= 0.0 else min(max(-(s[i, 0] * ex + s[i, 1] * ey) / ee, 0.0), 1.0)
        dx = v[i, 0] + u * ex - x
        dy = v[i, 1] + u * ey - y
        dist = dx * dx + dy * dy
        if dist < best:
            best = dist
            bi = i
            bu = u
    lam[:] = 0.0
    lam[bi] += 1.0 - bu
    lam[bi + 1 if bi + 1 < m else 0] += bu


@numba.njit(cache=True)
def _mvc_all(x: np.ndarray, v: np.ndarray) -> np.ndarray:
    m = v.shape[0]
    out = np.empty((x.shape[0], m))
    s = np.empty((m, 2))
    r = np.empty(m)
    t = np.empty(m)
    for k in range(x.shape[0]):
        _mvc_point(x[k, 0], x[k, 1], v, s, r, t, out[k])
    return out


@numba.njit(cache=True)
def _mvc_map(x: np.ndarray, v: np.ndarray, dst: np.ndarray) -> np.ndarray:
    m = v.shape[0]
    nk = dst.shape[0]
    out = np.zeros((nk, x.shape[0], 2))
    s = np.empty((m, 2))
    r = np.empty(m)
    t = np.empty(m)
    lam = np.empty(m)
    for k in range(x.shape[0]):
        _mvc_point(x[k, 0], x[k, 1], v, s, r, t, lam)
        for c in range(nk):
            qx = 0.0
            qy = 0.0
            for i in range(m):
                qx += lam[i] * dst[c, i, 0]
                qy += lam[i] * dst[c, i, 1]
            out[c, k, 0] = qx
            out[c, k, 1] = qy
    return out


@checked(points=Array(ndim=2), polygon=Array(ndim=2))
def mean_value_coordinates(points, polygon) -> np.ndarray:
    """Mean value coordinates of points with respect to a closed polygon.

    Parameters
    ----------
    points : (P, 2) array_like
        Query points (x, y), anywhere in the plane.
    polygon : (M, 2) array_like
        Polygon vertices ``v_i`` (any orientation; non-convex is fine).

    Returns
    -------
    (P, M) float64 ndarray
        ``lambda_i(p)``: each row sums to 1 and reproduces the point,
        ``sum_i lambda_i v_i = p`` (linear precision), inside and outside.

    Notes
    -----
    Hormann & Floater (2006), Eq. (4) with ``tan(alpha_i / 2) =
    det(s_i, s_{i+1}) / (r_i r_{i+1} + <s_i, s_{i+1}>)``, ``s_i = v_i - p``,
    ``r_i = |s_i|``: the signed angle makes the coordinates valid for
    arbitrary polygons, and the expression is finite everywhere except on
    an edge, where the limit (linear interpolation between the edge's end
    points) is used, as it is on a vertex. Where the weights sum to zero
    (possible outside a self-intersecting polygon) the point is snapped to
    the nearest edge point. One compiled (numba) loop over the points; the
    memory footprint is the output only.

    Examples
    --------
    >>> import numpy as np
    >>> sq = np.array([(0, 0), (2, 0), (2, 2), (0, 2)], float)
    >>> mean_value_coordinates([(1, 1)], sq).round(3).tolist()
    [[0.25, 0.25, 0.25, 0.25]]
    """
    x = as_points(points, name="points", min_points=0)
    v = as_points(polygon, name="polygon", min_points=3)
    return _mvc_all(np.ascontiguousarray(x), np.ascontiguousarray(v))


def mvc_map(points, cage_from, cage_to) -> np.ndarray:
    """Map points through a cage deformation: ``q = sum_i lambda_i(p; cage_from) cage_to_i``.

    Parameters
    ----------
    points : (P, 2) array_like
        Points ``p`` in the space of ``cage_from``.
    cage_from, cage_to : (M, 2) or (k, M, 2) array_like
        Corresponding cages; a stack of ``k`` target cages maps the points
        into ``k`` spaces at once (coordinates are computed once).

    Returns
    -------
    (P, 2) or (k, P, 2) float64 ndarray

    Examples
    --------
    >>> import numpy as np
    >>> sq = np.array([(0, 0), (2, 0), (2, 2), (0, 2)], float)
    >>> mvc_map([(1, 1), (0.5, 1.5)], sq, 3 * sq + 1).round(9).tolist()
    [[4.0, 4.0], [2.5, 5.5]]
    """
    x = as_points(points, name="points", min_points=0)
    src = as_points(cage_from, name="cage_from", min_points=3)
    dst = np.asarray(cage_to, dtype=np.float64)
    single = dst.ndim == 2
    dst3 = dst[None] if single else dst
    if dst3.ndim != 3 or dst3.shape[1:] != src.shape:
        raise ValueError(f"cage_to must have shape {src.shape} or (k, {len(src)}, 2), "
                         f"got {dst.shape}")
    if not np.all(np.isfinite(dst3)):
        raise ValueError("cage_to contains NaN or infinite values")
    out = _mvc_map(np.ascontiguousarray(x), np.ascontiguousarray(src),
                   np.ascontiguousarray(dst3))
    return out[0] if single else out


def sample_rgba(image, points) -> np.ndarray:
    """Bilinear samples of a *premultiplied* RGBA image at points (x, y); zero outside.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Premultiplied RGBA (a normalised exemplar, whose transparent
        pixels are black, already is).
    points : (P, 2) array_like

    Returns
    -------
    (P, 4) float32 ndarray
    """
    img = as_rgba(image)
    p = as_points(points, name="points", min_points=0)
    if len(p) == 0:
        return np.zeros((0, 4), np.float32)
    # OpenCV maps must be smaller than SHRT_MAX in both directions: lay the
    # points out as rows of 1024.
    width = 1024
    n = len(p)
    rows = -(-n // width)
    mx = np.full(rows * width, -2.0, np.float32)
    my = np.full(rows * width, -2.0, np.float32)
    mx[:n], my[:n] = p[:, 0], p[:, 1]
    mx, my = mx.reshape(rows, width), my.reshape(rows, width)
    out = np.empty((rows * width, 4), np.float32)
    step = 16384
    for k in range(0, rows, step):
        out[k * width:(k + step) * width] = cv2.remap(
            img, mx[k:k + step], my[k:k + step], cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_CONSTANT, borderValue=(0, 0, 0, 0)).reshape(-1, 4)
    out = out[:n]
    return out


def _SEQ(value, name, allow_none):
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__"):
        raise TypeError(f"{name} must be a list (one entry per source), got {type(value).__name__}")
    return value


@checked(sources=_SEQ, source_cages=_SEQ, target_cage=Array(ndim=2), target_mask=Array(ndim=2))
def transfer_colour(sources, source_cages, target_cage, target_mask, *,
                    colour_weights=None, rng=None) -> np.ndarray:
    """Colour a target shape from one or more exemplars through their simplified contours.

    Parameters
    ----------
    sources : (H, W, 4) array_like or sequence of them
        Exemplar images (normalised: binary alpha, black transparent
        pixels, i.e. premultiplied).
    source_cages : (M, 2) array_like or sequence of them
        Each exemplar's simplified contour ``C_s``, corresponding vertex by
        vertex with ``target_cage``.
    target_cage : (M, 2) array_like
        The target's simplified contour.
    target_mask : (H, W) array_like
        Pixels to colour (the filled target contour).
    colour_weights : (k,) array_like, optional
        Convex weights of the exemplars' colours; None draws them from a
        flat Dirichlet distribution (the paper's random convex combination).
        Exemplars with weight 0 are not sampled.
    rng : int or numpy.random.Generator, optional
        For the random colour weights.

    Returns
    -------
    (H, W, 4) float32 ndarray
        Straight (not premultiplied) RGBA: alpha is the maximum sampled
        alpha inside ``target_mask`` (0 outside); colour is
        ``sum_i c_i a_i rgb_i / sum_i c_i a_i`` over the exemplars whose
        sample is not transparent; black where alpha is 0.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((8, 8, 4), np.float32); img[2:6, 2:6] = (1, 0, 0, 1)
    >>> cage = np.array([(0, 0), (7, 0), (7, 7), (0, 7)], float)
    >>> out = transfer_colour(img, cage, cage, img[..., 3] > 0)
    >>> bool(np.allclose(out, img))
    True
    """
    if isinstance(sources, np.ndarray) and sources.ndim == 3:
        sources, source_cages = [sources], [source_cages]
    srcs = [as_rgba(s, name=f"sources[{i}]") for i, s in enumerate(sources)]
    if not srcs:
        raise ValueError("sources is empty: need at least one exemplar")
    cages = [as_points(c, name=f"source_cages[{i}]", min_points=3)
             for i, c in enumerate(source_cages)]
    tcage = as_points(target_cage, name="target_cage", min_points=3)
    if len(cages) != len(srcs):
        raise ValueError(f"need one cage per source: {len(srcs)} sources, {len(cages)} cages")
    for i, c in enumerate(cages):
        if c.shape != tcage.shape:
            raise ValueError(f"source_cages[{i}] has {len(c)} vertices, target_cage {len(tcage)}: "
                             "simplified contours must correspond vertex by vertex")
    mask = as_mask(target_mask, name="target_mask")
    if colour_weights is None:
        cw = as_rng(rng).dirichlet(np.ones(len(srcs))) if len(srcs) > 1 else np.ones(1)
    else:
        cw = check_weights(colour_weights, len(srcs), name="colour_weights")
    used = np.flatnonzero(cw > 0)
    ys, xs = np.nonzero(mask)
    pts = np.stack([xs, ys], axis=1).astype(np.float64)
    mapped = mvc_map(pts, tcage, np.stack([cages[i] for i in used]))
    amax = np.zeros(len(pts), np.float32)
    num = np.zeros((len(pts), 3), np.float64)
    den = np.zeros(len(pts), np.float64)
    for k, i in enumerate(used):
        smp = sample_rgba(srcs[i], mapped[k])
        amax = np.maximum(amax, smp[:, 3])
        num += cw[i] * smp[:, :3]
        den += cw[i] * smp[:, 3]
    rgb = np.where(den[:, None] > 1e-6, num / np.maximum(den, 1e-12)[:, None], 0.0)
    out = np.zeros(mask.shape + (4,), np.float32)
    out[ys, xs, :3] = np.clip(rgb, 0.0, 1.0) * (amax[:, None] > 0)
    out[ys, xs, 3] = amax
    return out
