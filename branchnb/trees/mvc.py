"""Colour transfer with mean value coordinates (paper, Sec. "Colour transfer").

The new tree's pixels get their colour from the exemplars through a cage
deformation. For a target pixel ``p`` inside the new contour, the mean value
coordinates ``lambda_i(p)`` with respect to the target's simplified contour
``C_s`` (``M`` vertices) give the corresponding point of every source tree,

.. math:: q = \\sum_i \\lambda_i(p)\\, C_{s,i}^{\\mathrm{src}},

where RGBA is sampled bilinearly. With several exemplars, the output alpha
is opaque where a sampled exemplar is opaque (a clean cut-out) and the
colour a random convex combination of the contributions that are opaque.

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

from ..core.image import as_mask, as_points, as_rgba, extend_nearest
from ..core.random import as_rng
from ..core.validate import Array, Choice, Real, checked
from .morph import check_weights
from .mvc_pick import (  # noqa: F401
    CHOOSE_CUT_SIDE,
    COVERS,
    ONE_PIECE,
    SEAM_EPS,
    TRUNK_IOU,
    _check_groups,
    _choose,
    _choose_parts,
    smooth_gumbel,
)

__all__ = [
    "mean_value_coordinates",
    "mvc_map",
    "sample_rgba",
    "transfer_colour",
    "smooth_gumbel",
    "COLOUR_MODES",
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
        Sample positions (x, y) in pixels, pixel centres at integers; may
        be empty. Points outside the image read transparent black.

    Returns
    -------
    (P, 4) float32 ndarray
        Premultiplied RGBA at each point.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((2, 2, 4), np.float32); img[:, 1] = 1.0
    >>> sample_rgba(img, [(0.5, 0.0), (5.0, 5.0)]).tolist()
    [[0.5, 0.5, 0.5, 0.5], [0.0, 0.0, 0.0, 0.0]]
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


#: How :func:`transfer_colour` combines the exemplars' colours.
COLOUR_MODES = ("blend", "choose", "parts")



@checked(sources=_SEQ, source_cages=_SEQ, target_cage=Array(ndim=2), target_mask=Array(ndim=2),
         mode=Choice(*COLOUR_MODES), region_scale=Real(0.0, 1.0, low_open=True), seam=Real(0, 1e6))
def transfer_colour(sources, source_cages, target_cage, target_mask, *,
                    colour_weights=None, rng=None, mode: str = "blend",
                    region_scale: float = 0.15, seam: float = 20.0, return_sources: bool = False,
                    layers=None, groups=None, contours=None):
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
        Convex weights ``c_i`` of the exemplars' colours; None draws them
        from a flat Dirichlet distribution (the paper's random convex
        combination). Exemplars with weight 0 are not sampled.
    rng : int or numpy.random.Generator, optional
        For the random colour weights and the regions of ``"choose"``.
    mode : {"blend", "choose", "parts"}
        ``"blend"`` (the paper): every pixel's colour is the convex
        combination ``sum_i c_i [a_i] rgb_i / sum_i c_i [a_i]`` of the
        exemplars opaque there, right for photographs, whose colours vary
        from pixel to pixel anyway. ``"choose"`` (beyond the paper, for
        drawn trees): every pixel takes the colour of *one* exemplar, so
        flat colours, outlines and fruits stay whole instead of showing
        through each other as half-transparent overlays. The regions are
        drawn with the Gumbel-max rule on smooth random fields
        (:func:`smooth_gumbel`: exemplar ``i`` owns a share ``c_i`` of the
        pixels on average, in regions about ``region_scale`` times the tree
        size across), then a multi-label graph cut
        (:func:`~branchnb.core.graphcut.multilabel_seams`) moves the seams
        between regions to where the exemplars agree or where they have
        edges, i.e. along their outlines. Trees larger than
        ``CHOOSE_CUT_SIDE`` pixels run the cut on a coarser grid
        (about ten times faster at 512 px; the seams move by up to half a
        block, and the rare seam across a flat fill is a few pixels
        longer).
        ``"parts"`` (beyond the paper, flat art that must read as one
        drawing): the whole crown from one source and the whole trunk from
        one source (``layers`` are the trunk masks), each drawn with
        probabilities ``c_i``: no seam crosses a fill, a stroke or a fruit,
        and the crown shows one style (see ``_choose_parts``). Alpha is the
        chosen parts' own (inside ``target_mask``), not the weight vote.
        In ``"choose"`` and ``"parts"`` (beyond the paper) a source's thin
        dark strokes are sampled as ink coverage over each target pixel's
        warped footprint, not bilinearly (see ``_sample_strokes``): 1 px
        tier lines and clump arcs stay unbroken at small sizes, and fills
        keep their flat colour next to them. Where the warp stretches a
        source by more than 1.1 (:data:`STRETCH_START`), each pixel is its
        ink over its pure fill colour, anti-aliased at the target's
        resolution, not a stretched blend of both (no smear); a warp that
        does not stretch keeps every fill pixel as drawn.
    region_scale : float
        ``"choose"``: size of the regions, as a share of the image side.
    seam : float
        ``"choose"``: weight of the seam cost against the regions' data
        term (0: the regions as drawn).
    return_sources : bool
        Also return which source each pixel's colour comes from.
    layers : sequence of (H, W) array_like, optional
        One map per source (e.g. its trunk mask), carried along: each
        opaque result pixel takes the nearest value of the map of the
        source its colour comes from (see ``sources`` below), so a result's
        parts need no new segmentation (beyond the paper).

    groups : sequence of int, optional
        ``"parts"``: one label per source (e.g. 1 outlined, 0 not); the
        trunk comes only from a source of the crown source's group, so an
        outline is either on the whole tree or on none of it. None: one
        group.
    contours : (target, sources) pair, optional
        The target's contour ``C_r`` (N, 2) and one contour per source
        (each (N, 2), corresponding point by point, as
        :func:`~branchnb.trees.morph.combine_shapes` combines them). Beyond
        the paper: the cages correspond only by arc length along the dilated
        borders, so the warp maps the target's contour up to ~50 px away
        from the sources' contours (lobed crowns), and the rim took the
        sources' transparent background or stretched edge streaks: sawtooth
        spikes and bites along smooth crowns. With ``contours`` the warp is
        corrected by the residual ``C_i(j) - f_i(C(j))`` interpolated with
        mean value coordinates over the contour (exact on it, smooth inside),
        so the rim maps onto the sources' rims; faded out for a source whose
        largest residual exceeds 0.06-0.08 of the image side (shapes so
        unlike, a palm and a broadleaf, that the correction would fold the
        warp). None: the cage warp alone.

    Returns
    -------
    (H, W, 4) float32 ndarray
        Straight (not premultiplied) RGBA with binary alpha: 1 inside
        ``target_mask`` where the exemplars opaque at the mapped point hold
        at least half the colour weight, ``sum_i c_i [a_i >= 0.5] >= 1/2``,
        so an exemplar whose weight tends to 0 adds no pixel (the paper
        takes the union, which lets a barely weighted exemplar paint its
        rim); black where alpha is 0.
    sources : (H, W) int ndarray
        With ``return_sources``: index into ``sources`` of the exemplar
        whose colour a pixel takes in ``"choose"`` mode (the one with the
        most colour weight among those opaque there in ``"blend"`` mode), -1
        where alpha is 0.
    layer : (H, W) float32 ndarray
        With ``layers`` (last): the carried map, 0 where alpha is 0.

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
        raise ValueError(f"source_cages: need one cage per source: {len(srcs)} sources, {len(cages)} cages")
    for i, c in enumerate(cages):
        if c.shape != tcage.shape:
            raise ValueError(f"source_cages[{i}] has {len(c)} vertices, target_cage {len(tcage)}: "
                             "simplified contours must correspond vertex by vertex")
    if contours is not None:
        if not isinstance(contours, (tuple, list)) or len(contours) != 2 or \
                not isinstance(contours[1], (tuple, list)):
            raise TypeError("contours must be a (target contour, [source contours]) pair, got "
                            f"{type(contours).__name__}")
        if len(contours[1]) != len(srcs):
            raise ValueError(f"contours: need one source contour per source: {len(srcs)} sources, "
                             f"{len(contours[1])} contours")
        target_c = as_points(contours[0], name="contours[0]", min_points=3)
        contours = (target_c, [as_points(c, name=f"contours[1][{i}]", min_points=3)
                               for i, c in enumerate(contours[1])])
        if any(c.shape != target_c.shape for c in contours[1]):
            raise ValueError("contours: the target and source contours must have the same number of points")
    mask = as_mask(target_mask, name="target_mask")
    gen = as_rng(rng)
    if colour_weights is None:
        cw = gen.dirichlet(np.ones(len(srcs))) if len(srcs) > 1 else np.ones(1)
    else:
        cw = check_weights(colour_weights, len(srcs), name="colour_weights")
    used = np.flatnonzero(cw > 0)
    ys, xs = np.nonzero(mask)
    pts = np.stack([xs, ys], axis=1).astype(np.float64)
    mapped = mvc_map(pts, tcage, np.stack([cages[i] for i in used]))
    if contours is not None:
        mapped = mapped + _rim_correction(pts, tcage, [cages[i] for i in used], contours, used,
                                         max(mask.shape))
    # A source takes part at a pixel only where it is opaque there (sampled
    # alpha >= 0.5): where it is transparent its colour is not blended in as
    # a half-transparent layer, and the result is a clean cut-out.
    on = np.zeros((len(used), len(pts)), bool)
    cols = np.zeros((len(used), len(pts), 3), np.float32)
    flat = mode in ("choose", "parts")
    for k, i in enumerate(used):
        smp = sample_rgba(srcs[i], mapped[k])
        on[k] = smp[:, 3] >= 0.5
        if flat:
            cols[k] = _sample_strokes(srcs[i], mapped[k], smp, ys, xs, mask.shape)
        else:
            cols[k] = smp[:, :3] / np.maximum(smp[:, 3], 1e-6)[:, None]
    c = cw[used]
    vote = (c[:, None] * on).sum(axis=0)
    opaque = vote >= 0.5 - 1e-9
    lv = None
    if layers is not None:
        lv = _layer_values(layers, srcs, used, mapped)
    if groups is not None:
        _check_groups(groups, len(srcs))
    if mode == "parts" and len(used) > 1:
        if lv is None:
            raise ValueError("mode='parts' needs layers (one trunk mask per source)")
        grp = _check_groups(groups, len(srcs))[used]
        rgb, li, opaque = _choose_parts(cols, on, lv >= 0.5, c, ys, xs, grp, gen)
    elif mode == "blend" or len(used) == 1:
        den = (c[:, None] * on).sum(axis=0)
        num = ((c[:, None] * on)[..., None] * cols).sum(axis=0)
        rgb = np.where(den[:, None] > 1e-12, num / np.maximum(den, 1e-12)[:, None], 0.0)
        li = np.argmax(np.where(on, c[:, None], -1.0), axis=0)
    else:
        rgb, li = _choose(cols, on, opaque, c, ys, xs, mask.shape, region_scale, seam, gen)
    out = np.zeros(mask.shape + (4,), np.float32)
    out[ys, xs, :3] = np.clip(rgb, 0.0, 1.0) * opaque[:, None]
    out[ys, xs, 3] = opaque
    extra = ()
    if lv is not None:
        lay = np.zeros(mask.shape, np.float32)
        val = lv[li, np.arange(len(li))]
        lay[ys[opaque], xs[opaque]] = val[opaque]
        extra = (lay,)
    if not return_sources:
        return (out,) + extra if extra else out
    src = np.full(mask.shape, -1, np.int64)
    src[ys[opaque], xs[opaque]] = used[li[opaque]]
    return (out, src) + extra


#: Vertices of the dense contour cage that interpolates the rim correction (cost ~ pixels x this).
RIM_VERTICES = 256


#: Rim correction in full up to this largest residual (share of the image side), none from RIM_NONE.
RIM_FULL = 0.06
RIM_NONE = 0.08


def _rim_correction(pts: np.ndarray, tcage: np.ndarray, cages: list, contours, used: np.ndarray,
                    side: int) -> np.ndarray:
    """Per used source, the displacement that makes the cage warp map the target contour onto the
    source's contour point by point, interpolated inside by mean value coordinates on the contour."""
    target, srcs = contours
    tc = as_points(target, name="contours[0]", min_points=3)
    sc = [as_points(srcs[i], name=f"contours[1][{i}]", min_points=3) for i in used]
    if any(c.shape != tc.shape for c in sc):
        raise ValueError("contours: the target and source contours must have the same number of points")
    step = max(1, int(np.ceil(len(tc) / RIM_VERTICES)))
    v = tc[::step]
    keep = np.ones(len(v), bool)
    keep[1:] = np.hypot(*np.diff(v, axis=0).T) > 1e-6       # no repeated vertex (pins)
    v, idx = v[keep], np.arange(0, len(tc), step)[keep]
    on_rim = mvc_map(v, tcage, np.stack(cages))
    resid = np.stack([c[idx] for c in sc]) - on_rim
    d = _mvc_map(np.ascontiguousarray(pts), np.ascontiguousarray(v), np.ascontiguousarray(resid))
    # Mean value coordinates of a dense, very concave (or self-crossing) contour can overshoot far
    # from it: no correction longer than the largest one on the contour.
    top = np.hypot(resid[..., 0], resid[..., 1]).max(axis=1)
    n = np.hypot(d[..., 0], d[..., 1])
    d = d * np.minimum(1.0, top[:, None] / np.maximum(n, 1e-9))[..., None]
    # Shapes far apart (a palm's fronds against a broadleaf crown: residuals of 0.09-0.13 of the
    # side) would fold the warp (holes, torn fills); smooth crowns need <= 0.05 of the side.
    fade = np.clip((RIM_NONE - top / side) / (RIM_NONE - RIM_FULL), 0.0, 1.0)
    return d * fade[:, None, None]


#: Flat-art sampling: a target pixel shows a source's ink (its thin dark strokes) when the ink
#: covers at least this share of a bilinear sample at one of four points of the pixel's footprint.
STROKE_COVER = 0.6


def _footprint(mapped: np.ndarray, ys: np.ndarray, xs: np.ndarray, shape) -> tuple[np.ndarray, np.ndarray]:
    """Where a target pixel's right and lower neighbours map, relative to it (the warp's Jacobian
    columns, by differences of neighbouring mapped pixels; backward differences on the mask's edge)."""
    g = np.full(shape + (2,), np.nan)
    g[ys, xs] = mapped
    out = []
    for axis in (1, 0):
        fwd = np.full_like(g, np.nan)
        bwd = np.full_like(g, np.nan)
        if axis == 1:
            fwd[:, :-1] = g[:, 1:] - g[:, :-1]
            bwd[:, 1:] = g[:, 1:] - g[:, :-1]
        else:
            fwd[:-1] = g[1:] - g[:-1]
            bwd[1:] = g[1:] - g[:-1]
        d = np.where(np.isnan(fwd), bwd, fwd)[ys, xs]
        unit = np.array([1.0, 0.0] if axis == 1 else [0.0, 1.0])
        d[np.isnan(d).any(axis=1)] = unit
        out.append(d)
    return out[0], out[1]


#: Flat-art sampling: from this local stretch of the warp (target pixels per source pixel along
#: the most stretched direction) fills are sampled more and more from pure fill pixels only, fully
#: from :data:`STRETCH_FULL` (between them a linear mix of both samples). An anti-aliased pixel
#: stretched by 1.1 stays about one target pixel wide: no smear to remove, and the identity warp
#: (stretch 1) keeps every source pixel exactly.
STRETCH_START = 1.1
STRETCH_FULL = 1.3


def _stretch(jx: np.ndarray, jy: np.ndarray) -> np.ndarray:
    """Local stretch of a warp from its target-to-source Jacobian columns ``jx``, ``jy`` (N, 2):
    the inverse of the smaller singular value (1 for the identity, 2 where the target is twice
    the source along some direction)."""
    a, c = jx[:, 0], jx[:, 1]
    b, d = jy[:, 0], jy[:, 1]
    s2 = a * a + b * b + c * c + d * d
    det = np.abs(a * d - b * c)
    disc = np.sqrt(np.maximum(s2 * s2 - 4.0 * det * det, 0.0))
    smin = np.sqrt(np.maximum(0.5 * (s2 - disc), 0.0))
    return 1.0 / np.maximum(smin, 1e-6)


def _pure_fill(rgb: np.ndarray, op: np.ndarray, ink: np.ndarray) -> np.ndarray:
    """Opaque pixels that are fill colour as drawn: not ink, and either flat (their 3 x 3
    neighbourhood varies by < 0.06 in every channel) or more than 2 px from ink. The pixels
    between a stroke and a fill (its anti-aliased edge, 1-2 px) are neither."""
    k3 = np.ones((3, 3), np.uint8)
    c = np.ascontiguousarray(rgb, dtype=np.float32)
    flat = (cv2.dilate(c, k3) - cv2.erode(c, k3)).max(axis=2) < 0.06
    near = cv2.dilate(ink.astype(np.uint8), np.ones((5, 5), np.uint8)) > 0
    return op & ~ink & (flat | ~near)


def _darkest_ink(rgb: np.ndarray, ink: np.ndarray) -> np.ndarray:
    """Every pixel given the colour of the darkest ink pixel in the 3 x 3 neighbourhood of its
    nearest ink pixel: a stroke's own colour, not that of the lighter ink at its anti-aliased rim."""
    from .outline import _LUM

    h, w = ink.shape
    lum = np.where(ink, rgb @ _LUM, np.inf)
    pad = np.pad(lum, 1, constant_values=np.inf)
    best = np.full((h, w), np.inf)
    by, bx = np.mgrid[:h, :w]
    oy, ox = by.copy(), bx.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            v = pad[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
            better = v < best
            best[better] = v[better]
            oy[better], ox[better] = (by + dy)[better], (bx + dx)[better]
    col = rgb[oy, ox]
    return extend_nearest(col, ink)


def _unmixed_fill(rgb: np.ndarray, pure: np.ndarray, soft: np.ndarray, inkcol: np.ndarray,
                  radius: int = 5, tol: float = 0.12) -> np.ndarray:
    """Fill colours under the ``soft`` (anti-aliased) pixels: of the pure fill pixels within
    ``radius`` (Chebyshev), the one whose mix with the ink (``inkcol``, per pixel) passes nearest
    the soft pixel's colour, if within ``tol`` (RGB); else the pixel's own colour (a fill of its
    own). The nearest pure pixel is often the wrong fill: between a crown's outline and a fruit's
    ring it is the fruit's, and a stretch then paints the gap orange."""
    h, w = pure.shape
    out = rgb.copy()
    ys, xs = np.nonzero(soft)
    if len(ys) == 0:
        return out
    c = rgb[ys, xs]
    k = inkcol[ys, xs]
    best = np.full(len(ys), tol)
    fill = c.copy()
    for dy in range(-radius, radius + 1):
        for dx in range(-radius, radius + 1):
            qy, qx = ys + dy, xs + dx
            ok = (qy >= 0) & (qy < h) & (qx >= 0) & (qx < w)
            qy, qx = np.clip(qy, 0, h - 1), np.clip(qx, 0, w - 1)
            ok &= pure[qy, qx]
            f = rgb[qy, qx]
            d = f - k
            tt = np.clip(((c - k) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-9), 0.0, 1.0)
            # distance to the mix, then (a tie) the nearer pixel
            dist = np.linalg.norm(k + tt[:, None] * d - c, axis=1) + 1e-3 * np.hypot(dy, dx)
            better = ok & (dist < best)
            best[better] = dist[better]
            fill[better] = f[better]
    out[ys, xs] = fill
    return out


def _stretched_sample(rgb: np.ndarray, op: np.ndarray, ink: np.ndarray, pts: np.ndarray,
                      jx: np.ndarray, jy: np.ndarray):
    """Colours of a flat source at ``pts`` where the warp (Jacobian columns ``jx``, ``jy``)
    stretches it: ink over a pure fill colour (:func:`_pure_fill`) with an ink coverage
    anti-aliased at the target's resolution, never a stretched blend of the two.

    The ink coverage is 1 on ink, 0 on pure fill, and on the anti-aliased pixels between them how
    far their colour lies from their fill's (:func:`_unmixed_fill`) towards the ink's. Sampled
    bilinearly, it ramps across the stretched edge over several target pixels; it is steepened
    about 1/2 (where the drawing's own coverage crosses 1/2, so a stroke keeps its width) to a
    ramp of one target pixel. The ink colour is the stroke's darkest nearby pixel, the fill
    colour a bilinear sample of pure pixels only. None where the source has no pure fill pixel."""
    pure = _pure_fill(rgb, op, ink)
    if not pure.any():
        return None
    inkcol = _darkest_ink(rgb, ink)
    # the fill under each pixel, and how much of the pixel the ink covers: where its colour lies on
    # the way from that fill to the ink
    # (a faint ink pixel, a thin line's anti-aliased half or a dark red between a fruit and its
    # ring, covers only part of its pixel: taken as all ink it thickened the line when stretched)
    fcol = _unmixed_fill(rgb, pure, op & ~pure, inkcol)
    d = fcol - inkcol
    dd = (d * d).sum(axis=2)
    found = (fcol != rgb).any(axis=2) & (dd > 0.05 ** 2)
    cov = np.clip(((fcol - rgb) * d).sum(axis=2) / np.maximum(dd, 1e-9), 0.0, 1.0)
    cov = np.where(pure, 0.0, np.where(found, cov, ink.astype(np.float64)))
    # transparent pixels take the coverage of the nearest opaque one: a stroke along the silhouette
    # stays ink out to the edge of the opaque samples (no fill fringe outside the outline)
    cov = extend_nearest(cov, op)
    gy, gx = np.gradient(cov)
    # the peak coverage nearby: a thin or faint line (peak < 1) is cut at half its peak and drawn
    # with its peak's strength, so it keeps its ink (as wide as its pixels, stretched, as faint)
    peak = cv2.dilate(cov.astype(np.float32), np.ones((3, 3), np.uint8))
    packed = np.stack([0.5 + gx, 0.5 + gy, cov, peak], axis=2).astype(np.float32)
    g = sample_rgba(np.clip(packed, 0.0, 1.0), pts)
    gs = g[:, :2] - 0.5
    c = g[:, 2]
    top = np.maximum(g[:, 3], 1e-3)
    # the coverage's slope per target pixel (chain rule through the warp), steepened to 1
    slope = np.hypot((gs * jx).sum(axis=1), (gs * jy).sum(axis=1)) / top
    k = np.clip(1.0 / np.maximum(slope, 1e-3), 1.0, 8.0)
    cs = (top * np.clip(0.5 + (c / top - 0.5) * k, 0.0, 1.0))[:, None]
    # the fill weighted by how much of each pixel it covers (none on ink)
    wgt = (op * (1.0 - cov)).astype(np.float32)
    p = sample_rgba(np.concatenate([fcol * wgt[..., None], wgt[..., None]], axis=2).astype(np.float32), pts)
    # deep in a stroke, the fill of the nearest pixel that has one
    near = extend_nearest(fcol, wgt > 1e-3)
    h, w = op.shape
    px = np.clip(np.rint(pts[:, 0]), 0, w - 1).astype(np.int64)
    py = np.clip(np.rint(pts[:, 1]), 0, h - 1).astype(np.int64)
    fill = np.where(p[:, 3:] > 1e-3, p[:, :3] / np.maximum(p[:, 3:], 1e-6), near[py, px])
    out = cs * inkcol[py, px] + (1.0 - cs) * fill
    return out


def _sample_strokes(src: np.ndarray, mapped: np.ndarray, smp: np.ndarray, ys, xs, shape) -> np.ndarray:
    """Straight RGB of a flat (drawn) source at mapped points, its thin strokes kept whole.

    Beyond the paper: bilinear samples of a 1 px stroke between two pixel centres are half
    ink, half fill, lighter than the ink; where the warp shrinks the drawing, samples step over
    the stroke. Both break a drawing's inner lines (tier lines, clump arcs) into dashes at
    small sizes. Here the ink (pixels as dark as the drawing's outline,
    :func:`~branchnb.trees.outline.silhouette_outline`'s threshold) is sampled as a coverage at
    four points of each target pixel's footprint (a quarter pixel off its centre along the
    warp's Jacobian): a pixel whose best coverage is at least :data:`STROKE_COVER` takes the ink
    colour, any other the colour of the fill without ink. Strokes stay 1-2 px wide and
    unbroken under a warp that shrinks by up to 2, and fills stay flat (no dark fringe).

    Where the warp stretches the drawing (its local stretch, the inverse of the smaller singular
    value of the target-to-source Jacobian, above :data:`STRETCH_START`), the anti-aliased pixels
    between a stroke and a fill are no fill colour to sample: stretched, they became a 2-4 px
    smear (a fruit's orange run into the outline, dark red; issue 24). There a pixel is either ink
    or a pure fill colour (:func:`_stretched_sample`), fully from :data:`STRETCH_FULL` on, so the
    edge is hard at the target's resolution. A warp that does not stretch (the identity: a
    one-exemplar variation is an exact copy) samples every pixel as before (beyond the paper).
    """
    from .outline import _ink_threshold, _is_ink

    a = src[..., 3]
    op = a >= 0.5
    rgb = src[..., :3] / np.maximum(a, 1e-6)[..., None]
    if op.sum() < 9:
        return smp[:, :3] / np.maximum(smp[:, 3], 1e-6)[:, None]
    ink = (_is_ink(rgb, _ink_threshold(rgb, op)) & op).astype(np.float32)
    base = smp[:, :3] / np.maximum(smp[:, 3], 1e-6)[:, None]
    if not ink.any():
        return base
    inkimg = np.concatenate([rgb * ink[..., None], ink[..., None]], axis=2).astype(np.float32)
    fill = a * (1.0 - ink)
    fillimg = np.concatenate([rgb * fill[..., None], fill[..., None]], axis=2).astype(np.float32)
    jx, jy = _footprint(mapped, ys, xs, shape)
    best = np.zeros((len(mapped), 4), np.float32)
    at = mapped.copy()
    for sx in (-0.25, 0.25):
        for sy in (-0.25, 0.25):
            q = mapped + sx * jx + sy * jy
            s = sample_rgba(inkimg, q)
            better = s[:, 3] > best[:, 3]
            best[better] = s[better]
            at[better] = q[better]
    f = sample_rgba(fillimg, mapped)
    out = np.where(f[:, 3:] > 1e-3, f[:, :3] / np.maximum(f[:, 3:], 1e-6), base)
    stroke = best[:, 3] >= STROKE_COVER
    out[stroke] = best[stroke, :3] / best[stroke, 3:]
    # The ink colour of the nearest ink pixel, not a mean of two inks (an outline and a dark fill).
    h, w = ink.shape
    px = np.clip(np.rint(at[:, 0]), 0, w - 1).astype(np.int64)
    py = np.clip(np.rint(at[:, 1]), 0, h - 1).astype(np.int64)
    own = stroke & (ink[py, px] > 0)
    out[own] = rgb[py[own], px[own]]
    t = np.clip((_stretch(jx, jy) - STRETCH_START) / (STRETCH_FULL - STRETCH_START), 0.0, 1.0)
    if (t > 0).any():
        k = np.flatnonzero(t > 0)
        hard = _stretched_sample(rgb, op, ink > 0, mapped[k], jx[k], jy[k])
        if hard is not None:
            out[k] = (1.0 - t[k, None]) * out[k] + t[k, None] * hard
    return out.astype(np.float32)


def _layer_values(layers, srcs, used, mapped) -> np.ndarray:
    """Each used source's map (``layers``) at the mapped points, (k, P) float32 (nearest pixel)."""
    if isinstance(layers, (str, bytes)) or not hasattr(layers, "__len__"):
        raise TypeError(f"layers must be a sequence of (H, W) arrays, got {type(layers).__name__}")
    if len(layers) != len(srcs):
        raise ValueError(f"layers: need one map per source: {len(srcs)} sources, {len(layers)} maps")
    out = np.zeros((len(used), mapped.shape[1]), np.float32)
    for k, i in enumerate(used):
        try:
            m = np.asarray(layers[i], np.float32)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"layers[{i}] must be a numeric (H, W) array") from exc
        if m.shape != srcs[i].shape[:2]:
            raise ValueError(f"layers[{i}] has shape {m.shape}, its source {srcs[i].shape[:2]}")
        px = np.clip(np.rint(mapped[k][:, 0]), 0, m.shape[1] - 1).astype(np.int64)
        py = np.clip(np.rint(mapped[k][:, 1]), 0, m.shape[0] - 1).astype(np.int64)
        out[k] = m[py, px]
    return out
