"""Input extraction: the source structure, from user clicks or automatically.

The paper's user clicks a polyline per branch; the clicks are refined by
uniform resampling (step ``h``) and the thickness ``r`` at every vertex is
found by a *maximum-gradient search perpendicular to the branch*: the
grey-level gradient magnitude is sampled along the normal on both sides
and the offset of its maximum on each side is an edge of the branch, so
``r`` is half the distance between the two edges. The thickness stays an
ordinary array the user may edit afterwards.

:func:`extract_structure` goes beyond the paper (its stated future work):
a ridge / vesselness filter (scikit-image ``sato``, ``frangi`` or
``meijering``), hysteresis thresholding, skeletonisation, conversion of
the skeleton graph into a tree of branches (shortest-path tree from a root
end point, main branch = the longest path, side branches hang off it) and
thickness from the Euclidean distance transform of the ridge mask.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi
from scipy import sparse
from scipy.sparse import csgraph

from ..core.image import as_gray, as_points, as_rgb
from ..core.params import check_params
from ..core.polyline import arc_length, normals, polyline_length, resample_uniform
from ..core.structure import Branch, Structure
from ..core.validate import Array, Image, Int, Point, Real, checked
from .params import ClickParams, ExtractionParams

__all__ = [
    "branch_from_clicks",
    "estimate_thickness",
    "example_domain",
    "extract_structure",
    "binary_channels",
    "flat_background",
    "frame_lines",
    "gray_for_extraction",
    "is_binary",
    "large_flat_regions",
    "line_colour_map",
    "line_colour_of",
    "thin_line_colour",
    "ridge_mask",
    "ridge_response",
    "skeleton_to_structure",
    "structure_from_polylines",
]


def gray_for_extraction(image, *, name: str = "image") -> np.ndarray:
    """Luminance used by the extraction functions.

    Grayscale images are used as they are, RGB through Rec. 709 luminance,
    and RGBA images are first composited over white (transparent pixels
    count as background, like paper behind a drawing).

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The image: grey, RGB or RGBA (composited over white), float in [0, 1] or integer.
    name : str, default "image"
        Argument name used in error messages.

    Returns
    -------
    (H, W) ndarray
        Luminance in [0, 1].

    Raises
    ------
    ValueError
        If the input is not an image (named ``name`` in the message).

    Examples
    --------
    >>> import numpy as np
    >>> rgba = np.zeros((2, 2, 4)); rgba[0, 0] = (0, 0, 0, 1)   # one opaque black pixel, the rest clear
    >>> gray_for_extraction(rgba).round(3).tolist()
    [[0.0, 1.0], [1.0, 1.0]]
    """
    return as_gray(as_rgb(image, name=name), name=name)


# --------------------------------------------------------------------------
# From clicks (the paper's input)
# --------------------------------------------------------------------------
#: A radius search bound (pixels).
_RADIUS = Real(0, 1e3, low_open=True)


@checked(points=Array(ndim=2), max_radius=_RADIUS, min_radius=_RADIUS, sigma=Real(0, 100), smooth=Int(0, 1000),
         step=Real(0.01, 100))
def estimate_thickness(image, points, *, max_radius: float = 15.0, min_radius: float = 0.75,
                       sigma: float = 1.0, smooth: int = 2, step: float = 0.25,
                       return_offsets: bool = False):
    """Thickness ``r`` at each vertex by maximum-gradient search perpendicular to the branch.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example image (grey, RGB, or RGBA composited over white).
    points : (N, 2) array_like
        Branch vertices (x, y), N >= 2, inside the image.
    max_radius : float
        Search range on each side of the branch (pixels).
    min_radius : float
        Lower bound of the result (keeps ``r > 0``).
    sigma : float
        Gaussian scale of the gradient magnitude (0 = plain Sobel).
    smooth : int
        Median filter half-width over the vertices (0 = off); removes the
        occasional jump to a neighbouring edge.
    step : float
        Sampling step along the normal (pixels).
    return_offsets : bool
        Also return the two edge offsets ``(left, right)`` per vertex.

    Returns
    -------
    r : (N,) ndarray
        Radius (half width) per vertex; ``(r, left, right)`` if requested.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((40, 60)); img[16:25, :] = 0.0          # a 9 px wide dark bar
    >>> r = estimate_thickness(img, [(5, 20), (55, 20)], max_radius=10)
    >>> bool(abs(r.mean() - 4.5) < 0.6)
    True
    """
    gray = gray_for_extraction(image)
    pts = as_points(points, min_points=2, image_shape=gray.shape)
    if not max_radius > 0 or not min_radius > 0:
        raise ValueError("max_radius and min_radius must be > 0")
    if min_radius > max_radius:
        raise ValueError(f"min_radius ({min_radius}) must not exceed max_radius ({max_radius})")
    if np.all(np.ptp(pts, axis=0) == 0):
        raise ValueError("points has zero length: all vertices coincide")
    g = gray.astype(np.float64)
    if sigma > 0:
        grad = ndi.gaussian_gradient_magnitude(g, sigma)
    else:
        grad = np.hypot(ndi.sobel(g, 0), ndi.sobel(g, 1)) / 8.0
    nrm = normals(pts)
    offs = np.arange(step, max_radius + 1e-9, step)
    # (N, S) sample positions on each side, bilinear interpolation.
    out = []
    for sign in (-1.0, 1.0):
        xy = pts[:, None, :] + sign * offs[None, :, None] * nrm[:, None, :]
        vals = ndi.map_coordinates(grad, [xy[..., 1].ravel(), xy[..., 0].ravel()], order=1,
                                   mode="nearest").reshape(xy.shape[:2])
        out.append(offs[np.argmax(vals, axis=1)])
    left, right = out
    r = np.clip(0.5 * (left + right), min_radius, max_radius)
    if smooth > 0 and len(r) > 2:
        r = ndi.median_filter(r, size=2 * int(smooth) + 1, mode="nearest")
    if return_offsets:
        return r, left, right
    return r


@checked(parent=Int(0), parent_vertex=Int(0), start=Point())
def branch_from_clicks(image, points, params: ClickParams | None = None, *,
                       parent: int | None = None, parent_vertex: int | None = None,
                       start=None) -> Branch:
    """One branch from clicked points: uniform resampling + thickness search.

    Parameters
    ----------
    image : array_like
        The example image.
    points : (N, 2) array_like
        Clicked vertices (x, y), N >= 2, inside the image.
    params : ClickParams, optional
        ``h`` (resampling step), ``max_radius`` ...
    parent, parent_vertex : int, optional
        Link to the parent branch (``start`` should then be that vertex).
    start : (x, y), optional
        Prepended as the first vertex (the furcation point on the parent).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((40, 80)); img[18:23, :] = 0
    >>> b = branch_from_clicks(img, [(5, 20), (70, 20)])
    >>> len(b.points), bool(abs(b.thickness.mean() - 2.5) < 0.8)
    (17, True)
    """
    p = check_params(params if params is not None else ClickParams())
    gray = gray_for_extraction(image)
    pts = as_points(points, min_points=2 if start is None else 1, image_shape=gray.shape)
    if start is not None:
        s = as_points(np.reshape(start, (1, 2)), name="start", image_shape=gray.shape)
        pts = np.vstack([s, pts])
    if polyline_length(pts) < p.h:
        raise ValueError(f"points span {polyline_length(pts):.1f} px, less than one step h = {p.h}")
    res = resample_uniform(pts, p.h, include_end=True)
    if len(res) < 2:
        res = np.vstack([pts[0], pts[-1]])
    r = estimate_thickness(gray, res, max_radius=p.max_radius, min_radius=p.min_radius,
                           sigma=p.sigma, smooth=p.smooth)
    return Branch(res, r, parent, parent_vertex)


@checked()
def structure_from_polylines(image, polylines, params: ClickParams | None = None,
                             radii=None) -> Structure:
    """A structure from several clicked polylines (one per branch).

    The first polyline is a root. Each later polyline whose first point
    lies within ``params.snap`` pixels of a vertex of an earlier branch
    becomes a child starting at that vertex; otherwise it is a new root.
    Thickness comes from :func:`estimate_thickness` unless ``radii`` gives
    user-edited values (one array per polyline, used after resampling by
    linear interpolation; ``None`` entries are estimated).

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example: grey, RGB or RGBA (composited over white), float in [0, 1] or integer.
    polylines : sequence of (N_i, 2) array_like
        Clicked vertices (x, y) in pixels, one polyline per branch.
    params : ClickParams, optional
        Resampling step ``h``, thickness search and ``snap`` distance; None =
        the defaults.
    radii : sequence of (array_like or None), optional
        User-edited radii (pixels) per polyline, or None to estimate them.

    Returns
    -------
    Structure
        Resampled at ``params.h``, with ``image_shape`` set.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((60, 80)); img[28:33, :] = 0; img[:30, 39:42] = 0
    >>> s = structure_from_polylines(img, [[(2, 30), (77, 30)], [(40, 30), (40, 3)]])
    >>> s.branches[1].parent, s.branches[1].parent_vertex
    (0, 9)
    """
    p = check_params(params if params is not None else ClickParams())
    gray = gray_for_extraction(image)
    if isinstance(polylines, (str, bytes, dict)) or not hasattr(polylines, "__len__"):
        raise TypeError(f"polylines must be a list of (N, 2) point lists, got {type(polylines).__name__}")
    if polylines is None or len(polylines) == 0:
        raise ValueError("polylines is empty: click at least one branch")
    if radii is not None and (isinstance(radii, (str, bytes)) or not hasattr(radii, "__len__")):
        raise TypeError(f"radii must be one entry per polyline, got {type(radii).__name__}")
    if radii is not None and len(radii) != len(polylines):
        raise ValueError(f"radii must have one entry per polyline ({len(polylines)})")
    s = Structure([], image_shape=gray.shape[:2])
    for i, pl in enumerate(polylines):
        pts = as_points(pl, name=f"polylines[{i}]", min_points=2, image_shape=gray.shape)
        parent = pv = None
        if s.branches and p.snap > 0:
            best = (np.inf, None, None)
            for j, b in enumerate(s.branches):
                d = np.hypot(*(b.points - pts[0]).T)
                v = int(np.argmin(d))
                if d[v] < best[0]:
                    best = (d[v], j, v)
            if best[0] <= p.snap:
                parent, pv = best[1], best[2]
        if parent is not None:
            anchor = s.branches[parent].points[pv]
            pts = np.vstack([anchor, pts[1:]]) if np.hypot(*(pts[0] - anchor)) < p.h / 2 else \
                np.vstack([anchor, pts])
        res = resample_uniform(pts, p.h, include_end=True)
        if len(res) < 2:
            raise ValueError(f"polylines[{i}] is shorter than one step h = {p.h}")
        user_r = None if radii is None else radii[i]
        if user_r is None:
            r = estimate_thickness(gray, res, max_radius=p.max_radius, min_radius=p.min_radius,
                                   sigma=p.sigma, smooth=p.smooth)
        else:
            ur = np.asarray(user_r, np.float64)
            if ur.shape != (len(pl),):
                raise ValueError(f"radii[{i}] must have one value per clicked vertex ({len(pl)})")
            from ..core.polyline import arc_length

            s_in = arc_length(as_points(pl))
            s_out = arc_length(res)
            r = np.interp(s_out * (s_in[-1] / max(s_out[-1], 1e-12)), s_in, ur)
        s.add_branch(res, r, parent, pv)
    return s


# --------------------------------------------------------------------------
# Automatic extraction (beyond the paper)
# --------------------------------------------------------------------------
def _polarity(gray: np.ndarray, polarity: str, sigma: float) -> str:
    if polarity != "auto":
        return polarity
    res = gray - ndi.gaussian_filter(gray, max(4.0, 4 * sigma))
    res = res - res.mean()
    sd = res.std()
    if sd == 0:
        return "dark"
    skew = float(np.mean(res ** 3) / sd ** 3)
    # Thin bright structures on a dark background give a long bright tail.
    return "bright" if skew > 0 else "dark"


def _outside_field_of_view(gray: np.ndarray, margin: float, sigma_max: float) -> np.ndarray:
    """Large near-black regions (outside a circular fundus view) plus a margin.

    Only regions of at least 1 % of the image that are much thicker than
    any ridge the filter looks for (inner radius > 4 sigma_max) count, so
    thin black branches on a light background are kept.
    """
    dark = gray < 0.04
    if dark.mean() < 0.01:
        return np.zeros_like(dark)
    lab, _ = ndi.label(dark)
    sizes = np.bincount(lab.ravel())
    sizes[0] = 0
    thick = np.zeros(len(sizes))
    dt = ndi.distance_transform_edt(dark)
    np.maximum.at(thick, lab.ravel(), dt.ravel())
    big = (sizes >= 0.01 * gray.size) & (thick > 4 * sigma_max)
    big[0] = False
    out = big[lab]
    if out.any() and margin > 0:
        out = ndi.distance_transform_edt(~out) <= margin
    return out


def ridge_response(image, params: ExtractionParams | None = None) -> tuple[np.ndarray, str]:
    """Normalised ridge / vesselness response in [0, 1] and the polarity used.

    Parameters
    ----------
    image : array_like
        Grey, RGB or RGBA (composited over white).
    params : ExtractionParams, optional
        ``filter``, ``polarity``, ``sigma_min`` .. ``sigma_max``, ``scale``.

    Returns
    -------
    response : (H', W') float32
        At the working scale ``params.scale``.
    polarity : {"dark", "bright"}
    """
    from skimage import filters
    from skimage.transform import rescale

    p = check_params(params if params is not None else ExtractionParams())
    if p.sigma_max < p.sigma_min:
        raise ValueError(f"params.sigma_max ({p.sigma_max}) must be >= sigma_min ({p.sigma_min})")
    gray = gray_for_extraction(image).astype(np.float64)
    if p.scale < 1:
        gray = rescale(gray, p.scale, anti_aliasing=True)
    pol = _polarity(gray, p.polarity, p.sigma_max)
    n_s = max(2, int(np.ceil(p.sigma_max - p.sigma_min)) + 1)
    sigmas = np.linspace(p.sigma_min, p.sigma_max, n_s)
    fn = {"sato": filters.sato, "frangi": filters.frangi, "meijering": filters.meijering}[p.filter]
    resp = fn(gray, sigmas=sigmas, black_ridges=(pol == "dark"))
    if pol == "dark":
        resp[_outside_field_of_view(gray, 2.5 * p.sigma_max + 2, p.sigma_max)] = 0
    resp[: 1] = resp[-1:] = 0
    resp[:, :1] = resp[:, -1:] = 0
    top = np.percentile(resp, 99.9)
    if top <= 0:
        return np.zeros(gray.shape, np.float32), pol
    return np.clip(resp / top, 0, 1).astype(np.float32), pol


def ridge_mask(response: np.ndarray, threshold: float = 0.0, hysteresis: float = 0.5) -> np.ndarray:
    """Hysteresis threshold of a ridge response (``threshold = 0``: Otsu).

    Parameters
    ----------
    response : (H, W) array_like
        Ridge / vesselness filter response.
    threshold : float, default 0.0
        High threshold on the response; 0 = Otsu's threshold.
    hysteresis : float, default 0.5
        Low threshold = ``hysteresis * threshold``: weaker pixels connected
        to strong ones are kept.

    Returns
    -------
    (H, W) bool ndarray
        The ridge mask (empty for a constant response).

    Raises
    ------
    ValueError
        If ``response`` is not 2-D.

    Examples
    --------
    >>> import numpy as np
    >>> r = np.zeros((5, 7)); r[2, 1:6] = [0.5, 0.6, 1.0, 0.6, 0.2]
    >>> ridge_mask(r, threshold=0.8)[2].astype(int).tolist()
    [0, 1, 1, 1, 1, 0, 0]
    """
    from skimage.filters import apply_hysteresis_threshold, threshold_otsu

    r = np.asarray(response, np.float64)
    if r.ndim != 2:
        raise ValueError(f"response must be 2-D, got shape {r.shape}")
    if threshold <= 0:
        if r.max() <= r.min():
            return np.zeros(r.shape, bool)
        threshold = float(threshold_otsu(r))
    return apply_hysteresis_threshold(r, hysteresis * threshold, threshold)


_OFFSETS = ((0, 1), (1, -1), (1, 0), (1, 1))


def _skeleton_graph(skel: np.ndarray):
    ys, xs = np.nonzero(skel)
    n = len(ys)
    index = -np.ones(skel.shape, np.int64)
    index[ys, xs] = np.arange(n)
    rows, cols, w = [], [], []
    h, wd = skel.shape
    for dy, dx in _OFFSETS:
        y2, x2 = ys + dy, xs + dx
        ok = (y2 >= 0) & (y2 < h) & (x2 >= 0) & (x2 < wd)
        j = np.full(n, -1)
        j[ok] = index[y2[ok], x2[ok]]
        ok = j >= 0
        rows.append(np.flatnonzero(ok))
        cols.append(j[ok])
        w.append(np.full(ok.sum(), np.hypot(dy, dx)))
    r, c, ww = np.concatenate(rows), np.concatenate(cols), np.concatenate(w)
    g = sparse.coo_matrix((ww, (r, c)), shape=(n, n)).tocsr()
    return (g + g.T).tocsr(), ys, xs


def _end_radius(pts: np.ndarray, r: np.ndarray, ends: np.ndarray, members: np.ndarray) -> np.ndarray:
    """How thick the line is at each end: the largest radius within ``3 r_med + 4`` pixels of it.

    The radius right at a skeleton end is small (the medial axis ends where
    the channel's rounded tip or the frame closes in), so a wide channel
    leaving the frame would lose against a spur of a narrower one.
    """
    reach = 3.0 * float(np.median(r[members])) + 4.0
    out = np.empty(len(ends))
    for i in range(0, len(ends), 64):
        e = ends[i:i + 64]
        d2 = ((pts[e, None, :] - pts[None, members, :]) ** 2).sum(-1)
        out[i:i + 64] = np.where(d2 <= reach * reach, r[members][None, :], 0.0).max(1)
    return np.maximum(out, r[ends])


def _mouth_node(cand: np.ndarray, key: np.ndarray, members: np.ndarray, member_key: np.ndarray,
                scale: float) -> tuple[np.ndarray, np.ndarray]:
    """Root candidates of a piece that drains into a region: its ends, or the node nearest the region
    when that is more than 4 px nearer than every end.

    Going beyond the paper: where a drawn river meets the coast line, removing the coast's outline
    from the skeleton can leave a little loop or junction at the mouth, so the mouth is no end of
    the skeleton and the nearest *end* is the river's source (a tree rooted inland, upstream).
    """
    k = int(np.argmin(member_key))
    if len(key) and member_key[k] + 4.0 * scale < float(np.min(key)):
        return members[k:k + 1], member_key[k:k + 1]
    return cand, key


def _delta_source_key(key: np.ndarray, pts: np.ndarray, r: np.ndarray, ends: np.ndarray,
                      members: np.ndarray, scale: float) -> np.ndarray:
    """Root key of a piece that reaches the region at several mouths: a delta roots at its source.

    A river drains to the sea at one mouth; a delta reaches it at several
    (its distributaries) and comes from one wide channel inland. When two
    or more ends of the piece lie at the region (within ``3 + 2 r`` pixels
    of it) and the thickest end away from it is at least 1.5 x thicker than
    every mouth, that end becomes the root (key -1); else ``key`` is kept.
    Going beyond the paper, whose roots are clicked: rooted at a mouth, a
    delta's tree runs upstream and the synthesis grows its trunk from the sea.
    """
    if len(ends) < 3:
        return key
    er = _end_radius(pts, r, ends, members)
    near = key * 1.0 / scale <= 3.0 + 2.0 * er
    if near.sum() < 2 or near.all():
        return key
    far = np.flatnonzero(~near)
    best = far[np.argmax(er[far])]
    if er[best] < 1.5 * er[near].max():
        return key
    out = np.asarray(key, np.float64).copy()
    out[best] = -1.0
    return out


def skeleton_to_structure(skeleton, radius, *, h: float = 4.0, min_branch_length: float = 12.0,
                          min_component_length: float = 60.0, root="thickest",
                          scale: float = 1.0, smooth: float = 4.0,
                          smooth_radius: float = 8.0, image_shape=None, region=None,
                          spur_factor: float = 2.0) -> Structure:
    """Convert a one-pixel skeleton into a tree of branches.

    Each connected piece becomes one tree: a root end point is chosen
    (``root``), the shortest-path tree from it is computed (cycles, e.g.
    in crack networks, are cut where the two fronts meet), the main branch
    follows the longest path and every other subtree hanging off a branch
    becomes a child branch (recursively). Subtrees shorter than
    ``min_branch_length`` are pruned (skeleton spurs).

    Parameters
    ----------
    skeleton : (H, W) bool array_like
        One-pixel-wide centre lines (8-connected), at the working scale.
    radius : (H, W) array_like
        Branch radius at each pixel (e.g. the distance transform).
    h : float, default 4.0
        Resampling step h of the result (full-size pixels).
    min_branch_length, min_component_length : float, default 12.0, 60.0
        Pruning thresholds in pixels of the *output* (full-size) image. A
        piece that reaches the image frame (within 4 px) is kept from half
        ``min_component_length``: the frame cut it (a crop's rivers that
        enter from its frame), beyond the paper.
    root : {"auto", "thickest", "top", "bottom", "left", "right", "border", "nearest_region"} or (x, y)
        Root end point per piece: ``"auto"`` takes the end nearest to
        ``region`` when there is one and the piece's lines all have about one
        width (its 75th radius percentile under 1.5 x the 25th, or less than
        a pixel above it: a drawn map's rivers drain where they meet the sea;
        a node of the piece more than 4 px nearer than every end, a mouth the
        coast's removed outline left as a loop, beats the ends), else the thickest end (a
        vessel tree's trunk, a delta's inland channel; the radius near an end,
        not at it, which the frame or a rounded tip pinches); or the thickest, the top-most ..., the one
        nearest to the image border, the one nearest to ``region`` (e.g.
        the sea a river flows into; the border if there is none; a piece
        that meets the region at several mouths and has a much thicker end
        away from it, a delta, roots at that end, see ``_delta_source_key``),
        or the one nearest to a given point (full-size pixels). Default
        ``"thickest"``.
    scale : float, default 1.0
        The skeleton is a ``scale`` x downscaled copy; coordinates and
        radii are divided by it.
    smooth : float, default 4.0
        Gaussian smoothing (full-size pixels of arc length) of each pixel
        path before resampling; removes the staircase of the pixel grid,
        whose noise would otherwise dominate the turning angles.
    smooth_radius : float, default 8.0
        Gaussian smoothing of the radius along each branch (full-size
        pixels of arc length): the distance transform bumps at every
        junction and blob, which the synthesis would otherwise copy.
    image_shape : (H, W), optional
        Stored on the result (full-size).
    region : (H, W) bool array_like, optional
        At the skeleton's scale: the region ``root="nearest_region"`` looks for.
    spur_factor : float, default 2.0
        A side subtree is also pruned when it is shorter than this times the
        radius where it leaves its parent (the skeleton's spurs at the bends of
        wide channels are about one radius long).
    """
    sk = np.asarray(skeleton).astype(bool)
    rad = np.asarray(radius, np.float64)
    if sk.ndim != 2 or rad.shape != sk.shape:
        raise ValueError("skeleton must be 2-D and radius must have the same shape")
    if not h > 0:
        raise ValueError(f"h must be > 0, got {h}")
    out = Structure([], image_shape=tuple(image_shape) if image_shape is not None else None)
    if not sk.any():
        return out
    g, ys, xs = _skeleton_graph(sk)
    n_comp, comp = csgraph.connected_components(g, directed=False)
    deg = np.diff(g.indptr)
    pts_full = np.column_stack([xs, ys]).astype(np.float64) / scale
    r_full = np.maximum(rad[ys, xs] / scale, 0.5)
    # Component lengths (sum of spanning edges ~ number of pixels).
    comp_len = np.bincount(comp, minlength=n_comp) / scale
    hh, ww = sk.shape
    yy_, xx_ = np.mgrid[0:hh, 0:ww]
    border_dist = np.minimum(np.minimum(yy_, hh - 1 - yy_), np.minimum(xx_, ww - 1 - xx_)).astype(np.float64)
    region_dist = border_dist
    has_region = False
    if isinstance(root, str) and root in ("nearest_region", "auto") and region is not None:
        reg = np.asarray(region, bool)
        if reg.shape != sk.shape:
            raise ValueError(f"region must have the skeleton's shape {sk.shape}, got {reg.shape}")
        if reg.any():
            region_dist = ndi.distance_transform_edt(~reg)
            has_region = True
    # a piece cut by the frame (it reaches within 4 px of it) is kept from half the length: the rest
    # of the line is outside the image (a crop's rivers entering from its frame)
    comp_frame = np.full(n_comp, np.inf)
    np.minimum.at(comp_frame, comp, border_dist[ys, xs])
    min_len = np.where(comp_frame <= 4.0 * scale, 0.5 * min_component_length, min_component_length)
    roots = []
    for c in np.flatnonzero(comp_len >= min_len):
        members = np.flatnonzero(comp == c)
        ends = members[deg[members] == 1]
        cand = ends if len(ends) else members
        if isinstance(root, str):
            if root == "auto":
                lo, hi = np.percentile(r_full[members], [25, 75])
                # one width: within 1.5 x, or within a pixel (the radius of a 1-2 px drawn line comes
                # in half-pixel steps, 0.5 vs 0.9, which says nothing about where it drains)
                one_width = hi < 1.5 * lo or hi - lo < 1.0
                if has_region and one_width:
                    key = region_dist[ys[cand], xs[cand]]
                    cand, key = _mouth_node(cand, key, members, region_dist[ys[members], xs[members]], scale)
                else:
                    key = -_end_radius(pts_full, r_full, cand, members)
            elif root == "thickest":
                key = -_end_radius(pts_full, r_full, cand, members)
            elif root == "top":
                key = pts_full[cand, 1]
            elif root == "bottom":
                key = -pts_full[cand, 1]
            elif root == "left":
                key = pts_full[cand, 0]
            elif root == "right":
                key = -pts_full[cand, 0]
            elif root in ("border", "nearest_region"):
                key = region_dist[ys[cand], xs[cand]] if root == "nearest_region" else \
                    border_dist[ys[cand], xs[cand]]
                if root == "nearest_region" and has_region:
                    key = _delta_source_key(key, pts_full, r_full, cand, members, scale)
            else:
                raise ValueError("root must be auto/thickest/top/bottom/left/right/border/nearest_region "
                                 f"or (x, y), got {root!r}")
        else:
            q = np.asarray(root, np.float64).reshape(2)
            key = np.hypot(*(pts_full[cand] - q).T)
        roots.append(int(cand[np.argmin(key)]))
    if not roots:
        return out
    dist, pred, _ = csgraph.dijkstra(g, directed=False, indices=roots, return_predecessors=True,
                                     min_only=True)
    reach = np.isfinite(dist)
    order = np.argsort(dist)
    order = order[reach[order]]
    children: dict[int, list[int]] = {}
    height = np.zeros(len(ys))
    for v in order[::-1]:
        pv = pred[v]
        if pv >= 0:
            children.setdefault(int(pv), []).append(int(v))
            hv = height[v] + np.hypot(ys[v] - ys[pv], xs[v] - xs[pv])
            height[pv] = max(height[pv], hv)
    min_len_px = min_branch_length * scale
    # Decompose: (start node, parent branch, index of start node on the parent path)
    stack = [(r, None, None) for r in roots]
    paths: list[tuple[list[int], int | None, int | None]] = []
    while stack:
        start, par, pvx = stack.pop()
        path = [start]
        v = start
        while v in children:
            kids = children[v]
            best = max(kids, key=lambda u: height[u])
            path.append(best)
            v = best
        bi = len(paths)
        paths.append((path, par, pvx))
        for i, node in enumerate(path):
            for u in children.get(node, ()):
                if i + 1 < len(path) and u == path[i + 1]:
                    continue
                sub = height[u] + np.hypot(ys[u] - ys[node], xs[u] - xs[node])
                if sub >= max(min_len_px, spur_factor * rad[ys[node], xs[node]]):
                    stack.append((u, bi, i))
    # Build branches in creation order; children prepend their furcation node.
    new_index: dict[int, int] = {}
    built: list[Branch] = []
    for bi, (path, par, pvx) in enumerate(paths):
        nodes = path if par is None else [paths[par][0][pvx]] + path
        pts = pts_full[nodes]
        r = r_full[nodes]
        if par is not None and par not in new_index:
            continue
        if par is not None and len(nodes) > 2:
            # The distance transform near the junction measures the parent:
            # use the child's own radius from one parent radius onwards.
            arc = arc_length(pts)
            inside = arc < r[0] + 1.0
            if inside.all():
                inside[-1] = False
            first = int(np.argmin(inside))
            r = r.copy()
            r[:first] = r[first]
        if len(pts) >= 3 and smooth * scale > _NO_BLUR:
            sm = ndi.gaussian_filter1d(pts, smooth * scale, axis=0, mode="nearest")
            sm[0], sm[-1] = pts[0], pts[-1]
            pts = sm
        if len(r) >= 3 and smooth_radius * scale > _NO_BLUR:
            r = _median_then_gauss(r, smooth_radius * scale)
        length = polyline_length(pts)
        if length < max(h, 1e-9) or (par is None and length < min_branch_length):
            continue
        rp, rr = resample_uniform(pts, h, values=r, include_end=True)
        if len(rp) < 2:
            continue
        if par is None:
            built.append(Branch(rp, np.maximum(rr, 0.5)))
        else:
            parent_b = built[new_index[par]]
            anchor = pts[0]
            v = int(np.argmin(np.hypot(*(parent_b.points - anchor).T)))
            rp[0] = parent_b.points[v]
            built.append(Branch(rp, np.maximum(rr, 0.5), new_index[par], v))
        new_index[bi] = len(built) - 1
    return Structure(built, image_shape=out.image_shape)


def half_contrast_radius(gray, skeleton, polarity: str, sigma_max: float) -> np.ndarray:
    """Branch radius map: distance transform of the half-contrast (FWHM) mask.

    The local contrast is the morphological top-hat (black top-hat for
    dark branches, white for bright ones) with a disk wider than any
    branch the filter looks for. A pixel belongs to a branch if its
    contrast is at least half the contrast on the nearest skeleton pixel
    (the full width at half maximum, the usual vessel calibre), and the
    radius is the distance transform of that mask minus half a pixel.
    Unlike the thresholded ridge response, whose width follows the filter
    scale, this measures the branch itself.

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1] (:func:`gray_for_extraction`).
    skeleton : (H, W) bool array_like
        Centre lines of the branches.
    polarity : {"dark", "bright"}
        Branches darker or brighter than the background.
    sigma_max : float
        Largest filter scale (pixels); sets the top-hat disk (radius
        2 sigma_max + 1).

    Returns
    -------
    (H, W) float ndarray
        Radius (pixels) of the half-contrast mask at every pixel.
    """
    import cv2

    g = np.asarray(gray, np.float32)
    sk = np.asarray(skeleton, bool)
    rad = int(np.ceil(2 * sigma_max)) + 1
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * rad + 1, 2 * rad + 1))
    if polarity == "dark":
        th = cv2.morphologyEx(g, cv2.MORPH_CLOSE, disk, borderType=cv2.BORDER_REFLECT) - g
    else:
        th = g - cv2.morphologyEx(g, cv2.MORPH_OPEN, disk, borderType=cv2.BORDER_REFLECT)
    if not sk.any():
        return np.zeros(g.shape)
    peak = ndi.maximum_filter(th, 3)
    dist, (iy, ix) = ndi.distance_transform_edt(~sk, return_indices=True)
    ref = peak[iy, ix]
    mask = ((th >= 0.5 * ref) & (ref > 0) & (dist <= rad)) | sk
    return ndi.distance_transform_edt(mask) - 0.5


def frame_lines(mask, band: int = 4, share: float = 0.5) -> np.ndarray:
    """Pixels of ``mask`` that form a line along the image frame (a drawn border, a map's frame).

    Along each side, the band of ``band`` pixels is a frame line when
    ``mask`` covers at least ``share`` of that side's length there; a
    branch that merely enters the image through a side covers a few pixels.

    Parameters
    ----------
    mask : (H, W) bool array_like
        Line pixels (e.g. a thresholded ridge mask).
    band : int, default 4
        Width of the strip along each side (pixels).
    share : float, default 0.5
        Fraction of a side's length the strip must cover.

    Returns
    -------
    (H, W) bool ndarray
        The frame-line pixels (all False when none).
    """
    m = np.asarray(mask, bool)
    out = np.zeros_like(m)
    h, w = m.shape
    b = int(min(band, h // 4, w // 4))
    if b < 1:
        return out
    for sl, axis in (((slice(0, b), slice(None)), 0), ((slice(h - b, h), slice(None)), 0),
                     ((slice(None), slice(0, b)), 1), ((slice(None), slice(w - b, w)), 1)):
        strip = m[sl]
        if strip.any(axis=axis).mean() < share:
            continue
        # a line, not the edge of a wide region (a sea reaching the border): the
        # next band inwards is mostly free
        r0, r1 = sl[0].start, sl[0].stop
        c0, c1 = sl[1].start, sl[1].stop
        if axis == 0:
            inner = m[b:2 * b] if r0 == 0 else m[h - 2 * b:h - b]
        else:
            inner = m[:, b:2 * b] if c0 == 0 else m[:, w - 2 * b:w - b]
        if inner.any(axis=axis).mean() < 0.5 * share:
            out[r0:r1, c0:c1] = strip
    return out


def is_binary(gray, *, tol: float = 0.1, share: float = 0.97) -> bool:
    """True if at least ``share`` of the pixels lie within ``tol`` (of the range) of the darkest
    or the brightest level, and the two levels differ by at least 0.25 (a mask, maybe anti-aliased).

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1].
    tol : float, default 0.1
        Distance to the 1st / 99th percentile level, as a fraction of their
        difference.
    share : float, default 0.97
        Fraction of the pixels that must lie near one of the two levels.

    Returns
    -------
    bool
        Whether the image is a (near-)binary mask.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((20, 20)); m[5:9] = 1
    >>> is_binary(m), is_binary(np.linspace(0, 1, 400).reshape(20, 20))
    (True, False)
    """
    g = np.asarray(gray, np.float64)
    lo, hi = np.percentile(g, [1, 99])
    if hi - lo < 0.25:
        return False
    t = tol * (hi - lo)
    return bool(np.mean((np.abs(g - lo) <= t) | (np.abs(g - hi) <= t)) >= share)


def large_flat_regions(mask, radius: float, min_area: float = 0.01) -> np.ndarray:
    """Parts of ``mask`` far wider than any branch: a sea, a lake, a flat background.

    The opening of ``mask`` with a disk of ``radius`` keeps what a disk of
    that radius fits into; its connected pieces of at least ``min_area`` of
    the image are returned, grown by one pixel.

    Parameters
    ----------
    mask : (H, W) bool array_like
        Candidate pixels (e.g. a mask's foreground).
    radius : float
        Radius (pixels) of the opening disk: wider than any branch.
    min_area : float, default 0.01
        Smallest piece kept, as a fraction of the image.

    Returns
    -------
    (H, W) bool ndarray
        The large regions (within ``mask``).
    """
    import cv2

    m = np.asarray(mask, bool)
    r = max(int(round(radius)), 1)
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    opened = cv2.morphologyEx(m.astype(np.uint8), cv2.MORPH_OPEN, disk, borderType=cv2.BORDER_REPLICATE) > 0
    lab, n = ndi.label(opened)
    if n == 0:
        return np.zeros_like(m)
    sizes = np.bincount(lab.ravel())
    keep = sizes >= min_area * m.size
    keep[0] = False
    out = keep[lab]
    return ndi.binary_dilation(out) & m if out.any() else out


def binary_channels(gray, polarity: str = "auto", *, flat_regions: bool = True):
    """Foreground channels of a binary mask, the large flat regions removed, and the medial axis.

    The foreground is the bright class (``polarity="bright"``), the dark one
    (``"dark"``), or with ``"auto"`` the class that covers less of the image.
    Foreground regions much wider than the channels (more than 3 x their
    median radius and 1 % of the image, e.g. the sea a delta drains into)
    are no branches: they are returned as ``region``.

    Parameters
    ----------
    gray : (H, W) array_like
        The mask's luminance (two levels, maybe anti-aliased).
    polarity : {"auto", "bright", "dark"}, default "auto"
        Which class is foreground.
    flat_regions : bool, default True
        Set wide foreground regions apart as ``region``; False keeps every
        foreground pixel a channel (a drawn tree's wide trunk is no sea).

    Returns
    -------
    channels : (H, W) bool
        Foreground without the large flat regions (and without a line
        along the image frame).
    region : (H, W) bool
        The large flat foreground regions.
    skeleton : (H, W) bool
        Medial axis of ``channels``.
    radius : (H, W) float
        Distance transform of the whole foreground (the channel's half width
        on its centre line), capped at the flat regions' scale.
    """
    from skimage.morphology import skeletonize

    g = np.asarray(gray, np.float64)
    lo, hi = np.percentile(g, [1, 99])
    bright = g > 0.5 * (lo + hi)
    if polarity == "bright":
        fg = bright
    elif polarity == "dark":
        fg = ~bright
    else:
        fg = bright if bright.mean() <= 0.5 else ~bright
    fg = fg & ~frame_lines(fg, band=8)
    dt = ndi.distance_transform_edt(np.pad(fg, 1, mode="edge"))[1:-1, 1:-1]
    sk0 = skeletonize(fg)
    r_med = float(np.median(dt[sk0])) if sk0.any() else 1.0
    big_r = max(3.0 * r_med, 3.0)
    region = large_flat_regions(fg, big_r) if flat_regions else np.zeros_like(fg)
    if not flat_regions:
        big_r = float(dt.max()) + 1.0
    channels = fg & ~region
    skel = skeletonize(channels)
    # Skeleton stubs along the region's edge are outline, not branches.
    if region.any():
        skel &= ndi.distance_transform_edt(~region) > 1.5
    # The distance to the nearest background pixel centre is r + 0.5 on an
    # odd-width channel's centre pixel and r on an even one (the centre line
    # falls between two pixels): -0.25 is unbiased on average.
    radius = np.minimum(dt, big_r) - 0.25
    return channels, region, skel, np.maximum(radius, 0.5)


def _local_background(rgb: np.ndarray, sigma_max: float) -> np.ndarray:
    """Per-channel median over a window wider than any line: the colour around a line, edges kept."""
    import cv2

    k = 2 * int(np.ceil(2 * sigma_max)) + 1
    u8 = np.clip(np.rint(rgb * 255.0), 0, 255).astype(np.uint8)
    return cv2.medianBlur(np.ascontiguousarray(u8), min(k, 255)).astype(np.float32) / 255.0


def _drawn_branching_width(has: np.ndarray, sigma_max: float) -> float | None:
    """Mean width of a colour's pixels when they form one connected, long, narrow shape (a drawn tree), else None.

    Narrow is relative to the image (a trunk drawn 20 px wide in a 1000 px
    picture is still a tree's), long means a centre line of at least half
    the image's width plus height.
    """
    from skimage.morphology import skeletonize

    # a thin line drawn across the shape (a ground line over the trunk) does not cut it in two
    lab, n = ndi.label(ndi.binary_closing(has, np.ones((5, 5), bool)) | has, np.ones((3, 3), bool))
    if n == 0:
        return None
    sizes = np.bincount(lab[has], minlength=n + 1)[1:]
    if sizes.max() < 0.8 * sizes.sum():
        return None
    main = has & (lab == (int(np.argmax(sizes)) + 1))
    length = int(skeletonize(main).sum())
    h, w = has.shape
    width = float(main.sum()) / max(length, 1)
    if length < 0.5 * (h + w) or width > max(3.0, 0.03 * min(h, w)):
        return None
    return width


def thin_line_colour(image, *, sigma_max: float = 4.0, min_contrast: float = 0.12, tol: float = 0.12,
                     min_share: float = 0.0005, max_colours: int = 6):
    """The colour of the thin lines of a drawn image (the blue rivers of a map), or None.

    A pixel is *line-like* when its colour differs by at least
    ``min_contrast`` (largest channel) from the median colour of a window
    wider than any line (``4 sigma_max + 1`` pixels; the median keeps the
    edges between flat areas, so an edge is not a line). The most common
    colours of the line-like pixels (up to ``max_colours``, quantised to
    eighths) are candidates; a candidate colour is a *line colour* when

    * at least ``min_share`` of the image has it (within ``tol``),
    * most of its pixels are line-like (a colour that fills areas, such
      as a grey relief level, is no line colour) and not the anti-aliased
      rim of a line of another colour;

    pixels along the outline of a large flat region touching the image
    border (a country border, a coast line) are not counted.

    The most frequent line colour wins. It is returned only when its
    contrast to the surroundings is largely one of hue (chroma at least
    half the brightness difference in a drawn image, at least 1 x in a
    photograph, medians over the line): a coloured line over a relief
    of greys is what brightness-based ridge filters miss (they follow the
    terrain's edges instead). Grey, black or white lines, and the dark
    branches of photographs, keep the brightness path.

    Beyond the paper, a drawing's *coloured tree shape* is a line colour
    too, however wide its trunk: a colour filled solid (exactly flat) whose
    pixels form one connected shape (thin lines drawn across it do not cut
    it) with a centre line at least half the image's width plus height and
    a mean width of at most ``max(3, 0.03 min(H, W))`` pixels (the brown
    trunk, branches and roots of a clip-art tree, not its green crown or its
    grass). It wins over a grey or dark line colour (the crown's rim), and
    :func:`extract_structure` traces it by its medial axis when it is at
    least 3 pixels wide.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example, float in [0, 1] (RGBA composited over white).
    sigma_max : float, default 4.0
        Largest line scale (pixels), as ``ExtractionParams.sigma_max``.
    min_contrast : float, default 0.12
        Smallest colour difference of a line-like pixel to its
        surroundings (largest channel).
    tol : float, default 0.12
        Colour tolerance (largest channel) of a line colour's pixels.
    min_share : float, default 0.0005
        Smallest fraction of the image in a line colour.
    max_colours : int, default 6
        Candidate colours examined.

    Returns
    -------
    (3,) float32 ndarray or None
        The RGB line colour in [0, 1]; None when there is no coloured line
        (then extraction follows brightness ridges).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((80, 80, 3), 0.7, np.float32); img[:, 40:] = 0.55     # two relief greys
    >>> img[20:22, 5:75] = (0.0, 0.55, 0.83); img[22:60, 30:32] = (0.0, 0.55, 0.83)   # blue rivers
    >>> [round(float(v), 2) for v in thin_line_colour(img)]
    [0.0, 0.55, 0.83]
    """
    return _line_colour_and_width(image, sigma_max=sigma_max, min_contrast=min_contrast, tol=tol,
                                  min_share=min_share, max_colours=max_colours)[0]


def _line_colour_and_width(image, *, sigma_max: float = 4.0, min_contrast: float = 0.12, tol: float = 0.12,
                           min_share: float = 0.0005, max_colours: int = 6):
    """:func:`thin_line_colour` and, for a drawn branching shape wider than a line, its mean width (else None)."""
    rgb = as_rgb(image)[..., :3].astype(np.float32)
    h, w = rgb.shape[:2]
    bg = _local_background(rgb, sigma_max)
    line_like = np.abs(rgb - bg).max(-1) >= min_contrast
    if line_like.sum() < max(min_share * h * w, 20):
        return None, None
    q = np.clip((rgb[line_like] * 8).astype(np.int64), 0, 7)
    key = (q[:, 0] * 8 + q[:, 1]) * 8 + q[:, 2]
    counts = np.bincount(key, minlength=512)
    # a drawn tree's trunk is wider than a line: the image's main colours are candidates too
    qa = np.clip((rgb.reshape(-1, 3) * 8).astype(np.int64), 0, 7)
    all_counts = np.bincount((qa[:, 0] * 8 + qa[:, 1]) * 8 + qa[:, 2], minlength=512)
    gray = as_gray(rgb)
    flat = (ndi.maximum_filter(gray, 5) - ndi.minimum_filter(gray, 5)) < 0.03
    drawn = flat.mean() >= 0.5
    # a drawing's shapes are filled with one exact colour; a smooth photograph (a fundus) is not
    solid = np.max([ndi.maximum_filter(rgb[..., i], 3) - ndi.minimum_filter(rgb[..., i], 3)
                    for i in range(3)], axis=0) < 0.005
    outside = border_flat_regions(gray, 4 * sigma_max)
    contrast = np.linalg.norm(rgb - bg, axis=-1)
    # the anti-aliased rim of a line: a neighbour has much more contrast
    rim = ndi.maximum_filter(contrast, 3) > contrast + 0.1
    found = []
    candidates = list(np.argsort(-counts)[:max_colours])
    if drawn:
        candidates += [k for k in np.argsort(-all_counts)[:max_colours] if k not in candidates]
    for k in candidates:
        if counts[k] == 0 and all_counts[k] == 0:
            continue
        c = np.median(rgb[line_like][key == k], axis=0) if counts[k] >= 20 else \
            np.median(rgb.reshape(-1, 3)[((qa[:, 0] * 8 + qa[:, 1]) * 8 + qa[:, 2]) == k], axis=0)
        has = np.abs(rgb - c).max(-1) <= tol
        # a border line drawn in the same colour (a coast) is not counted
        has &= ~outline_pixels(has, outside, 2 * sigma_max + 2)
        n = int(has.sum())
        if n < min_share * h * w or np.mean(rim[has]) > 0.5:
            continue
        # wider than a line, yet in a drawing a coloured tree shape is still the structure
        width = _drawn_branching_width(has, sigma_max) if drawn and c.max() - c.min() >= 0.2 \
            and np.mean(solid[has]) >= 0.12 else None
        if width is None and np.mean(line_like[has]) < 0.5:
            continue
        found.append((n, c, width))
    if not found:
        return None, None
    found.sort(key=lambda f: -f[0])
    trees = [f for f in found if f[2] is not None]
    n, best, width = found[0]
    if width is not None:
        # a coloured branching shape among flat areas: brightness ridges would trace the areas' outlines
        return best.astype(np.float32), width
    # hue against brightness in the line's contrast to its surroundings
    has = (np.abs(rgb - best).max(-1) <= tol) & line_like
    diff = best[None] - bg[has]
    lum = np.abs(diff.mean(-1)) * np.sqrt(3.0)
    chroma = np.linalg.norm(diff - diff.mean(-1, keepdims=True), axis=-1)
    ratio = float(np.median(chroma / np.maximum(lum, 1e-6)))
    if ratio >= (0.5 if drawn else 1.0):
        return best.astype(np.float32), None
    # the commonest line colour is grey or dark (a crown's rim): a coloured tree shape still wins
    return (trees[0][1].astype(np.float32), trees[0][2]) if trees else (None, None)


def line_colour_of(image, structure: Structure) -> np.ndarray:
    """The median colour on the centre lines of an annotation (pass it as ``line_colour``).

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example: grey, RGB or RGBA (composited over white), float in [0, 1] or integer.
    structure : Structure
        Its annotated branches (pixels of ``image``).

    Returns
    -------
    (3,) ndarray
        RGB median in [0, 1] of the pixels under the centre lines (sampled
        every half pixel of arc length).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((20, 40, 3), 0.7, np.float32); img[9:11] = (0.0, 0.55, 0.83)
    >>> s = Structure([Branch([(2, 9.5), (37, 9.5)], 1.0)])
    >>> [round(float(v), 2) for v in line_colour_of(img, s)]
    [0.0, 0.55, 0.83]
    """
    rgb = as_rgb(image)[..., :3]
    h, w = rgb.shape[:2]
    if not isinstance(structure, Structure) or not structure.branches:
        raise ValueError("structure must be a non-empty Structure")
    pts = np.vstack([resample_uniform(b.points, 0.5, include_end=True) if len(b.points) > 1 else b.points
                     for b in structure.branches])
    ix = np.clip(np.floor(pts[:, 0] + 0.5).astype(int), 0, w - 1)
    iy = np.clip(np.floor(pts[:, 1] + 0.5).astype(int), 0, h - 1)
    return np.median(rgb[iy, ix], axis=0).astype(np.float32)


def line_colour_map(image, colour, *, sigma_max: float = 4.0, spread: float = 0.15) -> np.ndarray:
    """How much each pixel has the line ``colour`` rather than its surroundings' colour, in [0, 1].

    With ``b`` the median colour around the pixel (see
    :func:`thin_line_colour`) and ``c`` the line colour, a pixel ``I`` on
    the segment from ``b`` to ``c`` (a blend: an anti-aliased line edge)
    scores its position ``t`` along it, 1 on the line colour and 0 on the
    surroundings; the score falls to 0 as ``I`` leaves the segment by
    ``spread`` (RGB distance): another colour, such as a darker relief
    grey next to a white lowland, is no line however it compares in
    brightness. Pixels within ``spread`` of ``c`` score ``1 - |I - c| /
    (2 spread)`` at least (inside a wide river the surroundings are the
    line colour too). Bright lines on black, ready for the ridge filter.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The image: grey, RGB or RGBA (composited over white), float in [0, 1] or integer.
    colour : (3,) array_like
        The line colour (RGB in [0, 1]).
    sigma_max : float, default 4.0
        Largest line scale (pixels): sets the median window of the
        surroundings.
    spread : float, default 0.15
        RGB distance from the blend segment at which the score reaches 0.

    Returns
    -------
    (H, W) float32 ndarray
        The score in [0, 1].

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((30, 30, 3), 0.7, np.float32); img[14:16] = (0.0, 0.55, 0.83); img[:5] = 0.5
    >>> m = line_colour_map(img, (0.0, 0.55, 0.83))
    >>> float(m[15, 10]), float(m[20, 10]), float(m[4, 10]) < 0.01
    (1.0, 0.0, True)
    """
    rgb = as_rgb(image)[..., :3].astype(np.float32)
    c = np.asarray(colour, np.float32).reshape(3)
    bg = _local_background(rgb, sigma_max)
    u = c[None, None] - bg
    v = rgb - bg
    n2 = np.maximum((u * u).sum(-1), 1e-6)
    t = np.clip((v * u).sum(-1) / n2, 0.0, 1.0)
    perp = np.linalg.norm(v - t[..., None] * u, axis=-1)
    blend = t * np.clip(1.0 - perp / spread, 0.0, 1.0)
    blend[n2 < spread ** 2] = 0.0
    close = 1.0 - np.linalg.norm(rgb - c, axis=-1) / (2.0 * spread)
    return np.clip(np.maximum(blend, close), 0.0, 1.0).astype(np.float32)


#: Gaussian sigmas (pixels) below this are no smoothing (scipy divides by a vanishing sigma).
_NO_BLUR = 1e-3


def _median_then_gauss(r: np.ndarray, sigma: float) -> np.ndarray:
    k = max(3, round(sigma) | 1)
    return ndi.gaussian_filter1d(ndi.median_filter(r, size=k, mode="nearest"), sigma, mode="nearest")


@checked()
def extract_structure(image, params: ExtractionParams | None = None, *, mask=None,
                      return_maps: bool = False, line_colour="auto", **overrides):
    """Find a source structure in an image automatically.

    Ridge / vesselness filter -> hysteresis threshold -> skeleton ->
    tree of branches (:func:`skeleton_to_structure`) with the radius from
    the distance transform of the ridge mask. The result is meant to be
    corrected by the user (delete sub-branches, edit thickness).

    Parameters
    ----------
    image : array_like
        Grey, RGB or RGBA (composited over white).
    params : ExtractionParams, optional
        Filter, polarity, scales, thresholds, pruning, ``h``, working
        ``scale``, root rule. Keyword ``overrides`` replace single fields;
        ``root=(x, y)`` roots every piece at its end nearest to that point.
        Binary (or near-binary) input such as a water mask is detected
        (``binary="auto"``) and traced by its medial axis, the radius from
        the distance transform; foreground regions far wider than the
        channels (a sea) are no branches, and braided channels (cycles) are
        cut into a tree where the two fronts of the shortest-path tree meet.
        Outlines of large flat regions touching the border (a country
        border, a coast line) are no branches either.
    mask : (H, W) bool array_like, optional
        Only look inside this region.
    return_maps : bool, default False
        Also return ``(response, ridge mask, skeleton)`` at the working scale.
    line_colour : "auto", None or (r, g, b), default "auto"
        Trace lines of this colour (in [0, 1]) instead of brightness
        ridges: the ridge filter runs on :func:`line_colour_map`, how much
        each pixel has that colour rather than its surroundings'. "auto"
        looks for a coloured thin-line colour (:func:`thin_line_colour`,
        e.g. the blue rivers of a map over a grey relief, which
        brightness alone confuses with the relief's edges); None never
        does. The colour of an annotation can be read with
        :func:`line_colour_of`.
    **overrides
        Fields of :class:`ExtractionParams` replacing those of ``params``
        (e.g. ``min_component_length=20``, ``root=(x, y)``).

    Returns
    -------
    Structure
        With ``image_shape`` set to the image's ``(H, W)``; with
        ``return_maps`` the pair ``(structure, (response, ridge mask,
        skeleton))``.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((80, 120)); img[38:43, 5:115] = 0; img[5:40, 58:62] = 0
    >>> s = extract_structure(img, min_component_length=20)
    >>> len(s.branches), s.branches[1].parent
    (2, 0)
    """
    import dataclasses

    from skimage.morphology import remove_small_objects, skeletonize
    from skimage.transform import rescale, resize

    p = params if params is not None else ExtractionParams()
    root_point = None
    if "root" in overrides and not isinstance(overrides["root"], str):
        # root=(x, y): each piece's root is its end point nearest to that point
        root_point = tuple(float(v) for v in np.asarray(overrides.pop("root"), np.float64).reshape(2))
        if not all(np.isfinite(root_point)):
            raise ValueError(f"root point must be finite (x, y), got {root_point}")
    if overrides:
        unknown = set(overrides) - {f.name for f in dataclasses.fields(p)}
        if unknown:
            raise TypeError(f"unknown extraction parameter(s): {sorted(unknown)}")
        p = dataclasses.replace(p, **overrides)
    check_params(p)
    gray = gray_for_extraction(image)
    auto_colour = isinstance(line_colour, str) and line_colour == "auto"
    shape_width = None
    if auto_colour and p.binary != "on":
        line_colour, shape_width = _line_colour_and_width(image, sigma_max=p.sigma_max)
        if shape_width is not None and shape_width >= 3.0:
            # a drawn tree wider than the ridge filter's scales (beyond the paper): trace the colour's own
            # shape by its medial axis; its crown and ground are other colours, not a binary mask's background
            shape = np.abs(as_rgb(image)[..., :3] - line_colour).max(-1) <= 0.12
            # a thin line drawn across it (a ground line over the trunk) does not cut it in two
            shape |= ndi.binary_closing(shape, np.ones((5, 5), bool))
            return _extract_binary(np.where(shape, 0.0, 1.0), dataclasses.replace(p, polarity="dark"), mask,
                                   return_maps, root_point, flat_regions=False)
    if p.binary == "on" or (p.binary == "auto" and shape_width is None and is_binary(gray)):
        return _extract_binary(gray, p, mask, return_maps, root_point)
    lines = gray
    if line_colour is not None:
        if isinstance(line_colour, str):
            if line_colour != "auto":
                raise ValueError(f"line_colour must be 'auto', None or an (r, g, b) colour, got {line_colour!r}")
            line_colour = thin_line_colour(image, sigma_max=p.sigma_max)
        else:
            try:
                c = np.asarray(line_colour, np.float64).ravel()
            except (TypeError, ValueError):
                raise TypeError(f"line_colour must be 'auto', None or an (r, g, b) colour, got {line_colour!r}") \
                    from None
            if c.shape != (3,) or not np.all(np.isfinite(c)) or c.min() < 0 or c.max() > 1:
                raise ValueError(f"line_colour must be an (r, g, b) colour in [0, 1], got {line_colour!r}")
            line_colour = c
        if line_colour is not None:
            # bright where the pixel has the line colour: the ridge filter sees only those lines
            lines = line_colour_map(image, line_colour, sigma_max=p.sigma_max)
            # no texture in that map: weak ridges (a 1 px river blended into a grey) still count
            p = dataclasses.replace(p, polarity="bright", hysteresis=min(p.hysteresis, 0.25))
    resp, _pol = ridge_response(lines, p)
    if mask is not None:
        from ..core.image import as_mask

        m = as_mask(mask, shape=gray.shape)
        if resp.shape != m.shape:
            m = resize(m.astype(np.float32), resp.shape, order=0) > 0.5
        resp = np.where(m, resp, 0).astype(np.float32)
    bw = ridge_mask(resp, p.threshold, p.hysteresis)
    min_area = max(4, int((p.min_component_length * p.scale) * 2))
    bw = bw & ~frame_lines(bw, band=int(np.ceil(3 * p.sigma_max)) + 3)
    bw = remove_small_objects(bw, max_size=min_area) if _rso_has_max_size() else \
        remove_small_objects(bw, min_size=min_area)
    skel = skeletonize(bw)
    work = rescale(gray, p.scale, anti_aliasing=True) if p.scale < 1 else gray
    outside = border_flat_regions(work, 4 * p.sigma_max, branches=bw)
    skel &= ~outline_pixels(skel, outside, 2 * p.sigma_max + 2, gray=ndi.median_filter(work, 3))
    if p.radius == "fwhm":
        lines_w = rescale(lines, p.scale, anti_aliasing=True) if p.scale < 1 and lines is not gray else \
            (work if lines is gray else lines)
        radius = half_contrast_radius(lines_w, skel, _pol, p.sigma_max)
    else:
        radius = ndi.distance_transform_edt(bw) - 0.5
    region = None
    root = p.root
    if root in ("nearest_region", "auto"):
        region = flat_background(work, bw, 4 * p.sigma_max)
    s = skeleton_to_structure(skel, radius, h=p.h, min_branch_length=p.min_branch_length,
                              min_component_length=p.min_component_length,
                              root=root if root_point is None else root_point,
                              scale=p.scale, smooth=p.smooth_path, smooth_radius=p.smooth_radius,
                              image_shape=gray.shape[:2], region=region)
    if return_maps:
        return s, (resp, bw, skel)
    return s


def _flat_region_labels(gray, radius: float, tol: float):
    """Labels of the large flat-colour regions (wider than ``radius``) and which of them touch the border."""
    g = np.asarray(gray, np.float64)
    flat = (ndi.maximum_filter(g, 5) - ndi.minimum_filter(g, 5)) < tol
    lab, n = ndi.label(large_flat_regions(flat, radius, min_area=0.02))
    touch = np.zeros(n + 1, bool)
    for edge in (lab[0], lab[-1], lab[:, 0], lab[:, -1]):
        touch[edge] = True
    touch[0] = False
    return lab, n, touch


def _ground_regions(gray, branches, lab, n: int, tol: float) -> np.ndarray:
    """Per label of ``lab`` (0..n): True when the region has the colour the ``branches`` lie in: the
    median grey of the pixels 3-8 px beside them, when at least half of those pixels are within
    ``2 tol`` of it (a flat ground, not a relief of greys), and the region's median is too."""
    import cv2

    br = np.asarray(branches, bool)
    out = np.zeros(n + 1, bool)
    if not br.any() or n == 0:
        return out
    b8 = br.astype(np.uint8)
    near = cv2.dilate(b8, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (17, 17))) > 0
    ring = near & ~(cv2.dilate(b8, np.ones((7, 7), np.uint8)) > 0)
    if not ring.any():
        return out
    g = np.asarray(gray, np.float64)
    ground = float(np.median(g[ring]))
    if np.mean(np.abs(g[ring] - ground) <= 2 * tol) < 0.5:
        return out
    med = ndi.median(g, lab, np.arange(1, n + 1))
    out[1:] = np.abs(np.asarray(med, np.float64) - ground) <= 2 * tol
    return out


def border_flat_regions(gray, radius: float, tol: float = 0.02, branches=None) -> np.ndarray:
    """Large flat-colour regions (wider than ``radius``) that touch the image border.

    With ``branches`` ((H, W) bool), regions of the colour the branches lie in are left out: on a
    crop whose land runs off the frame, the land is no outside region (its rivers' junctions would
    otherwise count as the outline of the land pieces between them and be cut).

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1].
    radius : float
        Regions must be wider than a disk of this radius (pixels).
    tol : float, default 0.02
        Largest range of a flat 5 x 5 neighbourhood.
    branches : (H, W) bool array_like, optional
        Branch pixels; None = no such exclusion.

    Returns
    -------
    (H, W) bool ndarray
        The regions' pixels.
    """
    lab, n, touch = _flat_region_labels(gray, radius, tol)
    if branches is not None:
        touch = touch & ~_ground_regions(gray, branches, lab, n, tol)
    return touch[lab]


def outline_pixels(skeleton, outside, reach: float, gray=None, tol: float = 0.04) -> np.ndarray:
    """Skeleton pixels that trace the outline of the ``outside`` regions (a map's country border, a coast line).

    A skeleton pixel within ``reach`` of ``outside`` is outline when, looking
    away from the nearest outside pixel, the other side is no outside: the
    line separates the outside from the rest, and the line runs along the
    outside rather than into it (its direction, from the structure tensor
    of the skeleton, is within 45 degrees of the outside's edge). A branch
    lying *in* a flat region (a lightning bolt in a flat sky) has that
    region on both sides and stays; so does a river mouth meeting the
    coast.

    With ``gray`` (the image the regions were found in), the other side
    counts by its colour: the line is outline when the two sides differ by
    more than ``tol`` (land on one side, sea on the other), whether or not
    the other side is a large flat region itself; rivers close together
    have land on both sides, though the strip between them is too narrow
    to be a region, and stay branches.

    Parameters
    ----------
    skeleton : (H, W) bool array_like
        Centre-line pixels.
    outside : (H, W) bool array_like
        The outside regions (e.g. :func:`border_flat_regions`).
    reach : float
        Largest distance (pixels) of an outline pixel to ``outside``.
    gray : (H, W) array_like, optional
        Luminance the regions were found in; None = judge the other side by
        ``outside`` alone.
    tol : float, default 0.04
        Smallest luminance difference between the two sides of an outline.

    Returns
    -------
    (H, W) bool ndarray
        The outline pixels of ``skeleton``.
    """
    sk = np.asarray(skeleton, bool)
    out = np.asarray(outside, bool)
    if not out.any() or not sk.any():
        return np.zeros_like(sk)
    dist, (iy, ix) = ndi.distance_transform_edt(~out, return_indices=True)
    ys, xs = np.nonzero(sk & (dist <= reach))
    if len(ys) == 0:
        return np.zeros_like(sk)
    d = dist[ys, xs]
    vy, vx = iy[ys, xs] - ys, ix[ys, xs] - xs
    n = np.maximum(np.hypot(vy, vx), 1e-9)
    step = d + 3.0
    oy = np.clip(np.rint(ys - vy / n * step).astype(int), 0, sk.shape[0] - 1)
    ox = np.clip(np.rint(xs - vx / n * step).astype(int), 0, sk.shape[1] - 1)
    # The line's direction (structure tensor of the blurred skeleton): a line heading into
    # the outside (a river mouth at the coast) is no outline, one running along it is.
    b = ndi.gaussian_filter(sk.astype(np.float64), 1.0)
    gy, gx = np.gradient(b)
    jxx = ndi.gaussian_filter(gx * gx, 2.0)[ys, xs]
    jyy = ndi.gaussian_filter(gy * gy, 2.0)[ys, xs]
    jxy = ndi.gaussian_filter(gx * gy, 2.0)[ys, xs]
    # the tensor's main axis is the line's normal; the tangent is perpendicular to it
    theta = 0.5 * np.arctan2(2 * jxy, jxx - jyy)
    tx, ty = -np.sin(theta), np.cos(theta)
    heads_out = np.abs(tx * vx + ty * vy) / n > 0.7
    res = np.zeros_like(sk)
    if gray is not None:
        g = np.asarray(gray, np.float64)
        other = np.abs(g[oy, ox] - g[iy[ys, xs], ix[ys, xs]]) > tol
    else:
        other = ~out[oy, ox]
    res[ys, xs] = other & ~heads_out
    return res


def flat_background(gray, branches, radius: float, tol: float = 0.02) -> np.ndarray:
    """Large flat-colour regions without branches (the sea around a river map's land).

    Pixels whose 5 x 5 neighbourhood varies by less than ``tol`` form flat
    regions; those wider than ``radius`` (see :func:`large_flat_regions`)
    that hold (almost) no ``branches`` pixel and touch the image border are
    returned.

    A branch lies *in* a region when the region's closing (a disk of
    ``radius``) covers it: a drawn river is a thin non-flat line with the
    land on both sides, so the land's closing bridges it, while a coast
    line has land on one side only and belongs to neither. A region holds
    no branches when less than 2 % of the branch pixels lie in it (the
    river mouths touching the coast).

    Beyond that rule, a region of the colour the branches lie in (the
    median of the flat pixels 3-8 px beside them) is never background:
    on a crop whose land runs off the frame, rivers running from frame to
    frame cut the land into pieces that each touch the frame and hold no
    river (each river lies between two pieces), yet they are land.

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1].
    branches : (H, W) bool array_like
        Branch pixels (e.g. the rendered annotation).
    radius : float
        Regions must be wider than a disk of this radius (pixels).
    tol : float, default 0.02
        Largest range of a flat 5 x 5 neighbourhood.

    Returns
    -------
    (H, W) bool ndarray
        The background regions' pixels.
    """
    import cv2

    lab, n, touch = _flat_region_labels(gray, radius, tol)
    br = np.asarray(branches, bool)
    keep = np.zeros(n + 1, bool)
    n_br = int(br.sum())
    r = max(int(round(radius)), 1)
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    ground = _ground_regions(gray, br, lab, n, tol)
    for k in np.flatnonzero(touch):
        region = lab == k
        if ground[k]:
            continue  # the branches' own ground
        closed = cv2.morphologyEx(region.astype(np.uint8), cv2.MORPH_CLOSE, disk,
                                  borderType=cv2.BORDER_REPLICATE) > 0
        keep[k] = np.count_nonzero(closed & br) <= 0.02 * n_br
    keep[0] = False
    return keep[lab]


@checked(image=Image(), radius=_RADIUS)
def example_domain(image, structure: Structure | None = None, *, radius: float = 12.0) -> np.ndarray:
    """Where an example's branches live: the image minus its large branch-free flat regions.

    For a binary mask, the foreground regions far wider than the channels
    (the sea of a delta, see :func:`binary_channels`) are outside; for any
    other image, the large flat-colour regions that touch the border and
    hold no branch (the sea around a river map's land, see
    :func:`flat_background`; the branches are ``structure`` if given).
    Pass the result to :func:`~branchnb.branching.fit_model` as ``domain``.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example: grey, RGB or RGBA (composited over white), float in [0, 1] or integer.
    structure : Structure, optional
        Its branches; None = judge regions by the image alone.
    radius : float, default 12.0
        Flat regions must be wider than a disk of this radius (pixels).

    Returns
    -------
    (H, W) bool ndarray
        True where the branches may grow.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((100, 100)); m[70:] = 1; m[:70, 48:52] = 1   # a channel into a sea
    >>> d = example_domain(m)
    >>> bool(d[10, 50]), bool(d[90, 50])
    (True, False)
    """
    gray = gray_for_extraction(image)
    if is_binary(gray):
        _ch, region, _sk, _r = binary_channels(gray)
        return ~region
    branches = np.zeros(gray.shape, bool)
    if structure is not None and structure.branches:
        from ..core.render import coverage_polylines

        cov, _ = coverage_polylines(gray.shape, [b.points for b in structure.branches],
                                    [2 * b.thickness + 2 for b in structure.branches])
        branches = cov > 0.5
    return ~flat_background(gray, branches, radius)


def _extract_binary(gray, p: ExtractionParams, mask, return_maps: bool, root_point=None, flat_regions: bool = True):
    """``extract_structure`` for a binary mask: medial axis + distance-transform radius.

    Braided channels form cycles; the shortest-path tree from each root
    cuts every cycle once, where the two fronts meet (see
    :func:`skeleton_to_structure`).
    """
    from skimage.transform import rescale

    work = rescale(gray, p.scale, order=0, anti_aliasing=False) if p.scale < 1 else gray
    pol = p.polarity
    channels, region, skel, radius = binary_channels(work, pol, flat_regions=flat_regions)
    if mask is not None:
        from skimage.transform import resize

        from ..core.image import as_mask

        m = as_mask(mask, shape=gray.shape)
        if m.shape != skel.shape:
            m = resize(m.astype(np.float32), skel.shape, order=0) > 0.5
        skel &= m
    root = p.root if root_point is None else root_point
    s = skeleton_to_structure(skel, radius, h=p.h, min_branch_length=p.min_branch_length,
                              min_component_length=p.min_component_length, root=root,
                              scale=p.scale, smooth=p.smooth_path, smooth_radius=p.smooth_radius,
                              image_shape=gray.shape[:2], region=region)
    s = _unpinch_frame_ends(s, gray.shape[:2])
    if return_maps:
        return s, (channels.astype(np.float32), channels, skel)
    return s


def _straight_frame_end(pts: np.ndarray, k: int, shape) -> np.ndarray:
    """``pts[:k]`` (the end at the frame) replaced by the straight continuation of the branch behind
    ``pts[k]`` back to the frame, with as many points (the branch's vertex indices stay valid)."""
    h, w = shape
    arc = arc_length(pts)
    k2 = int(np.clip(np.searchsorted(arc, arc[k] + max(arc[k], 6.0)), k + 1, len(pts) - 1))
    d = pts[k] - pts[k2]
    n = float(np.hypot(*d))
    if n < 1e-9:
        return pts
    d = d / n
    # distance from pts[k] along d to the frame (the nearest side crossed), at most twice the old end
    ts = [((0.0 if d[i] < 0 else (w - 1.0, h - 1.0)[i]) - pts[k, i]) / d[i] for i in (0, 1) if abs(d[i]) > 1e-9]
    t = min(min(v for v in ts if v >= 0.0) if any(v >= 0.0 for v in ts) else 0.0, 2.0 * arc[k])
    f = np.linspace(1.0, 0.0, k + 1)[:-1, None]
    out = pts.copy()
    out[:k] = pts[k] + f * t * d
    out[:k, 0] = np.clip(out[:k, 0], 0.0, w - 1.0)
    out[:k, 1] = np.clip(out[:k, 1], 0.0, h - 1.0)
    return out


def _unpinch_frame_ends(s: Structure, shape) -> Structure:
    """A channel cut by the frame: its medial axis bends into a corner of the cut, where the distance
    transform is small, so the branch would start several times thinner than it is. Its radius
    there is the one two radii inward (a delta's trunk entering from inland keeps its width).

    The bent end also sets the branch's heading: a root would leave the frame at up to 60 degrees
    off the channel (the synthesized trunk then runs along the frame). A root's end at the frame is
    therefore the straight continuation of the channel from two radii inward; likewise a tip that
    ends at the frame when no child starts on that stretch."""
    h, w = shape
    out = []
    kids: dict[int, list[int]] = {}
    for b in s.branches:
        if b.parent is not None:
            kids.setdefault(int(b.parent), []).append(int(b.parent_vertex))

    def end_k(pts, r):
        arc = arc_length(pts)
        return int(np.clip(np.searchsorted(arc, 2.0 * r.max() if len(r) < 4 else 2.0 * np.median(r[:8])),
                           1, len(r) - 1))

    def at_frame(p):
        return min(p[0], p[1], w - 1 - p[0], h - 1 - p[1]) <= 6.0

    for i, b in enumerate(s.branches):
        if len(b.points) < 3:
            out.append(b)
            continue
        pts, r = b.points.copy(), b.thickness.copy()
        if at_frame(pts[0]):
            k = end_k(pts, r)
            r[:k] = np.maximum(r[:k], r[k])
            if b.parent is None and k < len(pts) - 1 and all(v > k for v in kids.get(i, [])):
                pts = _straight_frame_end(pts, k, shape)
        if at_frame(pts[-1]) and len(pts) >= 4:
            k = end_k(pts[::-1], r[::-1])
            n = len(pts)
            if k < n - 1 and all(v < n - 1 - k for v in kids.get(i, [])):
                pts = _straight_frame_end(pts[::-1], k, shape)[::-1].copy()
        out.append(Branch(pts, r, b.parent, b.parent_vertex))
    return Structure(out, image_shape=s.image_shape)


def _rso_has_max_size() -> bool:
    import inspect

    from skimage.morphology import remove_small_objects

    return "max_size" in inspect.signature(remove_small_objects).parameters
