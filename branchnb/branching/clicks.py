"""Input extraction from user clicks (the paper's input).

The paper's user clicks a polyline per branch; the clicks are refined by
uniform resampling (step ``h``) and the thickness ``r`` at every vertex is
found by a *maximum-gradient search perpendicular to the branch*: the
grey-level gradient magnitude is sampled along the normal on both sides
and the offset of its maximum on each side is an edge of the branch, so
``r`` is half the distance between the two edges. The thickness stays an
ordinary array the user may edit afterwards.

Split from :mod:`.extraction` (which re-exports every name).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_gray, as_points, as_rgb
from ..core.params import check_params
from ..core.polyline import normals, polyline_length, resample_uniform
from ..core.structure import Branch, Structure
from ..core.validate import Array, Int, Point, Real, checked
from .params import ClickParams

__all__ = [
    "gray_for_extraction",
    "estimate_thickness",
    "branch_from_clicks",
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
