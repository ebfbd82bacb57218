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
import numpy as np

from ..core.image import as_mask, as_points, as_rgba
from ..core.random import as_rng
from .morph import check_weights

__all__ = [
    "mean_value_coordinates",
    "mvc_map",
    "sample_rgba",
    "transfer_colour",
]

_CHUNK = 1 << 15


def _mvc_block(x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Mean value coordinates of points ``x`` (P, 2) w.r.t. polygon ``v`` (M, 2)."""
    s = v[None, :, :] - x[:, None, :]                       # s_i = v_i - x
    r = np.sqrt(s[..., 0] ** 2 + s[..., 1] ** 2)            # r_i = |s_i|
    sn = np.roll(s, -1, axis=1)
    rn = np.roll(r, -1, axis=1)
    a = s[..., 0] * sn[..., 1] - s[..., 1] * sn[..., 0]     # 2 A_i = det(s_i, s_i+1)
    d = s[..., 0] * sn[..., 0] + s[..., 1] * sn[..., 1]     # D_i = <s_i, s_i+1>
    rr = r * rn
    den = rr + d                                            # r_i r_i+1 (1 + cos alpha_i)
    scale = np.maximum(rr, 1e-300)
    on_edge = (den <= 1e-12 * scale) & (np.abs(a) <= 1e-9 * scale)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(on_edge, 0.0, a / np.where(on_edge, 1.0, den))  # tan(alpha_i / 2), signed
        w = (np.roll(t, 1, axis=1) + t) / r
    lam = np.empty_like(w)
    at_vertex = r <= 1e-12
    total = w.sum(axis=1)
    wabs = np.abs(w).sum(axis=1)
    ok = np.isfinite(total) & (np.abs(total) > 1e-12 * np.where(np.isfinite(wabs), wabs, 1.0))
    ok &= ~at_vertex.any(axis=1) & ~on_edge.any(axis=1)
    lam[ok] = w[ok] / total[ok, None]
    bad = np.flatnonzero(~ok)
    if bad.size:
        lam[bad] = 0.0
        m = v.shape[0]
        for k in bad:                                       # rare: on the cage or W = 0
            vert = np.flatnonzero(at_vertex[k])
            if vert.size:
                lam[k, vert[0]] = 1.0
                continue
            edge = np.flatnonzero(on_edge[k])
            if edge.size:
                i = edge[0]
                j = (i + 1) % m
                lam[k, i] = rn[k, i] / (r[k, i] + rn[k, i])
                lam[k, j] = r[k, i] / (r[k, i] + rn[k, i])
                continue
            # W(x) = 0 (possible outside a self-intersecting cage): project on the nearest edge.
            e = np.roll(v, -1, axis=0) - v
            u = np.clip(np.einsum("ij,ij->i", x[k] - v, e) / np.maximum((e * e).sum(1), 1e-300),
                        0.0, 1.0)
            dist = np.hypot(*(v + u[:, None] * e - x[k]).T)
            i = int(np.argmin(dist))
            lam[k, i] += 1.0 - u[i]
            lam[k, (i + 1) % m] += u[i]
    return lam


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
    points) is used, as it is on a vertex. Vectorised over points in blocks
    of 32768 points.

    Examples
    --------
    >>> import numpy as np
    >>> sq = np.array([(0, 0), (2, 0), (2, 2), (0, 2)], float)
    >>> mean_value_coordinates([(1, 1)], sq).round(3).tolist()
    [[0.25, 0.25, 0.25, 0.25]]
    """
    x = as_points(points, name="points", min_points=0)
    v = as_points(polygon, name="polygon", min_points=3)
    out = np.empty((len(x), len(v)))
    for k in range(0, len(x), _CHUNK):
        out[k:k + _CHUNK] = _mvc_block(x[k:k + _CHUNK], v)
    return out


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
    >>> mvc_map([(1, 1), (0.5, 1.5)], sq, 3 * sq + 1).tolist()
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
    out = np.empty((len(dst3), len(x), 2))
    for k in range(0, len(x), _CHUNK):
        lam = _mvc_block(x[k:k + _CHUNK], src)
        out[:, k:k + _CHUNK] = np.einsum("pm,kmc->kpc", lam, dst3)
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
    mx = p[:, 0].astype(np.float32).reshape(-1, 1)
    my = p[:, 1].astype(np.float32).reshape(-1, 1)
    out = np.empty((len(p), 4), np.float32)
    step = 1 << 15  # OpenCV maps are limited to SHRT_MAX rows
    for k in range(0, len(p), step):
        out[k:k + step] = cv2.remap(img, mx[k:k + step], my[k:k + step], cv2.INTER_LINEAR,
                                    borderMode=cv2.BORDER_CONSTANT,
                                    borderValue=(0, 0, 0, 0))[:, 0, :]
    return out


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
