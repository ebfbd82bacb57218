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

import numba
import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_mask, as_points, as_rgba
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
from .mvc_strokes import (  # noqa: F401
    STRETCH_FULL,
    STRETCH_START,
    STROKE_COVER,
    _footprint,
    _remap,
    _sample_strokes,
    _stretch,
    _StrokeMaps,
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
    return _remap(img, p)


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
                    layers=None, groups=None, contours=None, alphas=None, _maps=None):
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
    alphas : sequence of (H, W) array_like, optional
        One soft alpha per source (a translucent source's own alpha,
        :mod:`~branchnb.trees.translucent`), carried like ``layers`` but
        sampled bilinearly; returned last (beyond the paper).

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
        With ``layers``: the carried map, 0 where alpha is 0.
    alpha : (H, W) float32 ndarray
        With ``alphas`` (last): the carried soft alpha, 0 where alpha is 0.

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
    if _maps is not None and (isinstance(_maps, (str, bytes, dict)) or not hasattr(_maps, "__len__")
                              or not all(isinstance(d, dict) for d in _maps)):
        raise TypeError("_maps must be a sequence of dicts (one per source: where its maps are kept)")
    if _maps is not None and len(_maps) != len(srcs):
        raise ValueError(f"_maps: need one dict per source: {len(srcs)} sources, {len(_maps)} dicts")
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
        smp = _remap(srcs[i], mapped[k])
        on[k] = smp[:, 3] >= 0.5
        if flat:
            cols[k] = _sample_strokes(srcs[i], mapped[k], smp, ys, xs, mask.shape,
                                      maps=_kept_maps(_maps, sources, srcs, i))
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
    if alphas is not None:
        av = _alpha_values(alphas, srcs, used, mapped)
        soft = np.zeros(mask.shape, np.float32)
        soft[ys[opaque], xs[opaque]] = av[li, np.arange(len(li))][opaque]
        extra = extra + (soft,)
    if not return_sources:
        return (out,) + extra if extra else out
    src = np.full(mask.shape, -1, np.int64)
    src[ys[opaque], xs[opaque]] = used[li[opaque]]
    return (out, src) + extra


def _kept_maps(store, sources, srcs, i: int):
    """Source ``i``'s :class:`~branchnb.trees.mvc_strokes._StrokeMaps` from ``store`` (one dict per
    source that the caller keeps, e.g. each exemplar's cache), made and put there when missing or
    made from another object than ``sources[i]`` (``srcs[i]`` is its checked copy); None without a
    store (made afresh, not kept)."""
    if store is None:
        return None
    d = store[i]
    m = d.get("stroke_maps")
    if m is None or m.key is not sources[i]:
        m = _StrokeMaps(srcs[i], key=sources[i])
        d["stroke_maps"] = m
    return m


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


def _alpha_values(alphas, srcs, used, mapped) -> np.ndarray:
    """Each used source's soft alpha at the mapped points, (k, P) float32 (bilinear)."""
    if isinstance(alphas, (str, bytes)) or not hasattr(alphas, "__len__") or len(alphas) != len(srcs):
        raise ValueError(f"alphas: need one (H, W) map per source ({len(srcs)})")
    out = np.zeros((len(used), mapped.shape[1]), np.float32)
    for k, i in enumerate(used):
        m = np.asarray(alphas[i], np.float32)
        if m.shape != srcs[i].shape[:2]:
            raise ValueError(f"alphas[{i}] has shape {m.shape}, its source {srcs[i].shape[:2]}")
        out[k] = ndi.map_coordinates(m, [mapped[k][:, 1], mapped[k][:, 0]], order=1, mode="nearest")
    return out


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
