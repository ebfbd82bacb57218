"""Rendering metaphors (paper, section 7): plain dendrite, vines and lightning.

* **plain**: variable-width anti-aliased lines (:func:`~branchnb.dendrite.render.render_plain`).
* **vines**: the branches as smooth curves (heavily smoothed along the
  tree), with optional curls at the tips and leaves along the stems.
* **lightning**: a glow (blurred wide strokes) under a bright thin core on
  a night sky. :func:`lightning` also *grows* a lightning bolt: on a lattice
  whose up and sideways edges cost more than downward ones
  (:func:`~branchnb.dendrite.lattice.direction_factors`), planned with the
  non-scalar metric from a seed at the top, so the branches fork downward.

Every function returns a :class:`~branchnb.dendrite.render.Rendering`
(raster + SVG). Lengths left at ``None`` (leaf size and spacing, curl
length, smoothing, glow) are given for a 512 x 512 image and scale with the
dendrite's diagonal (:mod:`.scale`), so a 256-px and a 1024-px input look
alike; a number is taken as pixels.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ..core.image import as_points
from ..core.params import check_params, param
from ..core.polyline import arc_length
from ..core.random import as_rng
from ..core.render import coverage_polylines, draw_polylines
from ..core.svg import polylines_to_svg
from ..core.validate import Colour, Int, Point, Real, Shape, checked
from ..core.validate_arrays import real_array
from .dendrite import Dendrite, build_dendrite
from .lattice import direction_factors, make_lattice
from .planner import plan
from .render import Rendering, _canvas, render_plain, svg_document
from .scale import length_scale

__all__ = [
    "METAPHORS",
    "LightningParams",
    "lightning",
    "render",
    "render_lightning",
    "render_vines",
    "vine_curves",
    "vine_length",
]

METAPHORS = ("plain", "vines", "lightning")


def render(dendrite: Dendrite, metaphor: str = "plain", **options) -> Rendering:
    """Render ``dendrite`` with a metaphor by name (options go to its function).

    Parameters
    ----------
    dendrite : Dendrite
        The dendrite to draw, with its widths (``2 * radius``).
    metaphor : {"plain", "vines", "lightning"}
        Which rendering: :func:`~branchnb.dendrite.render.render_plain`,
        :func:`render_vines` or :func:`render_lightning`.
    **options
        Keyword arguments of that function (e.g. ``background``, ``smooth``).

    Returns
    -------
    Rendering
        Raster image and SVG of the same strokes.

    Raises
    ------
    ValueError
        If ``metaphor`` is not one of :data:`METAPHORS`.

    Examples
    --------
    >>> bolt = lightning((60, 40), LightningParams(n_branches=5), rng=0)
    >>> render(bolt, "lightning").image.shape
    (60, 40, 3)
    """
    if metaphor == "plain":
        return render_plain(dendrite, **options)
    if metaphor == "vines":
        return render_vines(dendrite, **options)
    if metaphor == "lightning":
        return render_lightning(dendrite, **options)
    raise ValueError(f"metaphor must be one of {list(METAPHORS)}, got {metaphor!r}")


# ----------------------------------------------------------------------- vines
def _tip_tangent(line: np.ndarray, k: int = 6) -> np.ndarray:
    d = line[-1] - line[max(0, len(line) - 1 - k)]
    n = np.hypot(*d)
    return d / n if n > 0 else np.array([1.0, 0.0])


def _curl(start, direction, length, turn, rng, step=0.75, total=None):
    """A tendril curl: a spiral whose curvature grows as it winds in (``total`` radians,
    drawn from ``rng`` when None)."""
    n = max(int(length / step), 4)
    phi = np.arctan2(direction[1], direction[0])
    pts = [np.asarray(start, float)]
    if total is None:
        total = rng.uniform(1.3, 2.2) * 2 * np.pi  # how far it winds
    for k in range(1, n):
        t = k / n
        # curvature rises like 1 / (1 - t): an inward spiral
        phi += turn * total / n * (0.4 + 1.6 * t * t)
        pts.append(pts[-1] + step * np.array([np.cos(phi), np.sin(phi)]))
    return np.array(pts)


def _leaf(base, direction, length, width, side):
    """A leaf as a polyline with a lens-shaped width profile (tapers to 0 at both ends)."""
    s = np.linspace(0.0, 1.0, 9)
    normal = np.array([-direction[1], direction[0]]) * side
    bend = 0.12 * length * np.sin(np.pi * s)  # a slight curve
    pts = base + np.outer(s * length, direction) + np.outer(bend, normal)
    widths = width * np.sin(np.pi * np.clip(s * 0.92 + 0.04, 0, 1)) ** 0.8
    return pts, widths


def _leaf_within(base, tangent, ang, length, width, side, within):
    """:func:`_leaf` at ``ang`` from the stem's ``tangent``; with a ``within`` mask, turned to
    the stem's other side, then shortened (down to half), until its points lie in it; None
    when none does."""
    def at(a, sd, ln):
        c, sn = np.cos(a), np.sin(a)
        d = np.array([c * tangent[0] - sn * tangent[1], sn * tangent[0] + c * tangent[1]])
        return _leaf(base, d, ln, width * min(1.0, ln / max(length, 1e-9)) ** 0.5, sd)

    lp, lw = at(ang, side, length)
    if within is None:
        return lp, lw
    h, w = within.shape

    def inside(pts):
        ix, iy = np.rint(pts[:, 0]).astype(int), np.rint(pts[:, 1]).astype(int)
        ok = (ix >= 0) & (ix < w) & (iy >= 0) & (iy < h)
        return bool(ok.all() and within[iy, ix].all())

    for ln in (length, 0.75 * length, 0.5 * length):
        for a, sd in ((ang, side), (-ang, -side)):
            lp, lw = at(a, sd, ln)
            if inside(lp):
                return lp, lw
    return None, None


def _hug(points: np.ndarray, hug: np.ndarray, reach: float) -> np.ndarray:
    """``points`` ``(N, 2)`` that lie off the mask ``hug`` but within ``reach`` pixels of it,
    moved onto its nearest pixel; the others as they are."""
    h, w = hug.shape
    dist, (iy, ix) = ndimage.distance_transform_edt(~hug, return_indices=True)
    cx = np.clip(np.rint(points[:, 0]).astype(int), 0, w - 1)
    cy = np.clip(np.rint(points[:, 1]).astype(int), 0, h - 1)
    move = (dist[cy, cx] > 0) & (dist[cy, cx] <= reach)
    out = np.array(points, float, copy=True)
    out[move, 0] = ix[cy[move], cx[move]]
    out[move, 1] = iy[cy[move], cx[move]]
    return out


def _fits(pts: np.ndarray, mask: np.ndarray) -> bool:
    h, w = mask.shape
    ix, iy = np.rint(pts[:, 0]).astype(int), np.rint(pts[:, 1]).astype(int)
    ok = (ix >= 0) & (ix < w) & (iy >= 0) & (iy < h)
    return bool(ok.all() and mask[iy, ix].all())


#: How far (share of the image's diagonal, at least ``VINE_HUG_PIXELS``) off the ``hug`` mask
#: a vine's stem is moved onto it (:func:`vine_curves`): the smoothing along the tree and the
#: lattice's coarser grid put stems on an outline 1-4 px past it.
VINE_HUG_REACH = 0.006
VINE_HUG_PIXELS = 3.0

#: Vine lengths (pixels at 512 x 512) used when an argument is None.
VINE_LENGTHS = {"curl_length": 14.0, "leaf_spacing": 14.0, "leaf_length": 7.0,
                "leaf_width": 4.0, "max_leaf_radius": 1.6}

#: Vine lengths never fall below these (pixels at the image's own size): on a
#: 250-px image leaves of 7 px x 0.5 would be ~3 px specks, green noise.
VINE_MIN_PIXELS = {"curl_length": 10.0, "leaf_spacing": 11.0, "leaf_length": 6.5,
                   "leaf_width": 3.6, "max_leaf_radius": 0.8}


#: Metaphor lengths never shrink below this share of their 512 x 512 values, so a
#: thumbnail (diagonal under ~180 px) still shows a glow.
MIN_SCALE = 0.25


def _unit(shape) -> float:
    return max(length_scale(shape), MIN_SCALE)


def _len(value, shape, default: float) -> float:
    return float(value) if value is not None else float(default) * _unit(shape)


def vine_length(name: str, shape) -> float:
    """The vine length ``name`` (a key of :data:`VINE_LENGTHS`) in pixels for an image of ``shape``:
    its 512 x 512 value scaled to the diagonal, never below :data:`VINE_MIN_PIXELS`.

    Parameters
    ----------
    name : str
        One of ``"curl_length"``, ``"leaf_spacing"``, ``"leaf_length"``,
        ``"leaf_width"``, ``"max_leaf_radius"``.
    shape : (int, int, ...)
        Image shape ``(H, W, ...)``.

    Returns
    -------
    float
        The length in pixels of that image.

    Raises
    ------
    ValueError
        If ``name`` is not a key of :data:`VINE_LENGTHS`.

    Examples
    --------
    >>> vine_length("leaf_length", (1024, 1024)), vine_length("leaf_length", (200, 200))
    (14.0, 6.5)
    """
    if name not in VINE_LENGTHS:
        raise ValueError(f"name must be one of {sorted(VINE_LENGTHS)}, got {name!r}")
    return max(VINE_LENGTHS[name] * length_scale(shape), VINE_MIN_PIXELS[name])


def _vine_len(value, shape, name: str) -> float:
    return float(value) if value is not None else vine_length(name, shape)


def _vine_smooth(smooth, shape) -> int:
    # [1, 2, 1] passes blur by sqrt(passes / 2) nodes: passes grow with the scale squared
    if smooth is not None:
        return int(smooth)
    return max(1, round(12 * length_scale(shape) ** 2)) if shape is not None else 12


def vine_curves(dendrite: Dendrite, *, smooth: int | None = None, curls: float = 0.6,
                curl_length: float | None = None, leaves: bool = True,
                leaf_spacing: float | None = None, leaf_length: float | None = None,
                leaf_width: float | None = None, max_leaf_radius: float | None = None,
                within=None, hug=None, rng=None):
    """Geometry of the vine metaphor.

    Lengths left at None are :data:`VINE_LENGTHS` scaled to the dendrite's
    image diagonal, never below :data:`VINE_MIN_PIXELS` (:func:`vine_length`);
    ``smooth`` (passes along the branches) scales with the diagonal's square.

    Parameters
    ----------
    dendrite : Dendrite
        The dendrite; its widths become the stem widths.
    smooth : int, optional
        Averaging passes along the branches
        (:meth:`~branchnb.dendrite.dendrite.Dendrite.smoothed_points`); vines
        want soft curves, so 12 at 512 x 512 by default.
    curls : float
        Probability in [0, 1] that a branch (of >= 3 nodes) ends in a tendril
        curl; 0.6 by default.
    curl_length : float, optional
        Mean curl length in pixels (14 px at 512 x 512 by default); each curl
        is 0.6 to 1.2 times that.
    leaves : bool
        Add leaves along the stems.
    leaf_spacing : float, optional
        Mean arc-length distance (pixels, > 0) between leaves, alternating
        sides (14 px at 512 x 512).
    leaf_length, leaf_width : float, optional
        Leaf size in pixels (7 and 4 px at 512 x 512), varied by +-25 %.
    max_leaf_radius : float, optional
        Leaves grow only where the stem radius is at most this (1.6 px at
        512 x 512): twigs carry leaves, the trunk does not.
    within : (H, W) bool array_like, optional
        Where leaves may lie (the dendrite's image shape): a leaf whose points fall outside
        is turned to the stem's other side, else shortened to no less than half its length,
        else left out (beyond the paper: vines grown on an object's outline hung half their
        leaves past it). Everywhere by default. The random draws do not depend on it.
    hug : (H, W) bool array_like, optional
        Where the stems belong (the object they grow on, the dendrite's image shape): smoothed
        stem points off it by at most ``VINE_HUG_REACH`` of the diagonal (at least
        ``VINE_HUG_PIXELS``) are moved onto its nearest pixel, and a curl that does not fit in
        it grown by 1 px is turned the other way, else shortened (down to half), else left
        out. None (the default) changes nothing; the random draws do not depend on it.
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed for curls and leaf placement.

    Returns
    -------
    stems : list of (n, 2) arrays, stem_widths : list of (n,) arrays,
    leaves : list of (9, 2) arrays, leaf_widths : list of (9,) arrays

    Raises
    ------
    ValueError
        If ``smooth < 0``, ``curls`` is outside [0, 1] or ``leaf_spacing <= 0``, or ``within``
        or ``hug`` does not have the dendrite's shape.

    Notes
    -----
    ``hug`` is beyond the paper (issue 25): on a drawn object on white the stems, paths along
    the object's outline smoothed over a dozen nodes and planned on a lattice coarser than a
    large picture, ran 1-4 px past the outline, and tip curls wider than a thin stroke hung
    off it.

    Examples
    --------
    >>> bolt = lightning((60, 40), LightningParams(n_branches=5), rng=0)
    >>> stems, widths, leaves, leaf_widths = vine_curves(bolt, rng=0)
    >>> len(stems) == bolt.n_branches, all(len(p) == 9 for p in leaves)
    (True, True)
    """
    shape = dendrite.shape if dendrite.shape is not None else (512, 512)
    smooth = _vine_smooth(smooth, dendrite.shape)
    curl_length = _vine_len(curl_length, shape, "curl_length")
    leaf_spacing = _vine_len(leaf_spacing, shape, "leaf_spacing")
    leaf_length = _vine_len(leaf_length, shape, "leaf_length")
    leaf_width = _vine_len(leaf_width, shape, "leaf_width")
    max_leaf_radius = _vine_len(max_leaf_radius, shape, "max_leaf_radius")
    unit = _unit(shape)
    if smooth < 0 or not 0 <= curls <= 1 or leaf_spacing <= 0:
        raise ValueError("smooth must be >= 0, curls in [0, 1], leaf_spacing > 0")
    if within is not None:
        within = real_array(within, "within", ndim=2) > 0
        if within.shape != tuple(shape):
            raise ValueError(f"within must have the dendrite's shape {tuple(shape)}, got {within.shape}")
    if hug is not None:
        hug = real_array(hug, "hug", ndim=2) > 0
        if hug.shape != tuple(shape):
            raise ValueError(f"hug must have the dendrite's shape {tuple(shape)}, got {hug.shape}")
        if not hug.any():
            hug = None
    rng = as_rng(rng)
    p = dendrite.smoothed_points(smooth)
    if hug is not None:
        p = _hug(p, hug, max(VINE_HUG_PIXELS, VINE_HUG_REACH * float(np.hypot(*shape[:2]))))
        room = ndimage.binary_dilation(hug)
    stems, widths, leaf_pts, leaf_w = [], [], [], []
    for bi, b in enumerate(dendrite.branches):
        line, wid = p[b], 2.0 * dendrite.radius[b]
        if len(line) >= 3 and rng.random() < curls:
            t = _tip_tangent(line)
            length = curl_length * rng.uniform(0.6, 1.2)
            turn = rng.choice([-1.0, 1.0])
            total = rng.uniform(1.3, 2.2) * 2 * np.pi
            step = 0.75 * min(unit, 1.0)
            curl = _curl(line[-1], t, length, turn, rng, step=step, total=total)
            if hug is not None and not _fits(curl, room):
                curl = None
                for f in (1.0, 0.75, 0.5):
                    for sd in (turn, -turn):
                        c = _curl(line[-1], t, f * length, sd, rng, step=step, total=total)
                        if curl is None and _fits(c, room):
                            curl = c
            if curl is not None:
                cw = np.linspace(max(wid[-1], 0.6 * unit), 0.3 * unit, len(curl))
                line = np.vstack([line, curl[1:]])
                wid = np.concatenate([wid, cw[1:]])
        stems.append(line)
        widths.append(wid)
        if not leaves or len(line) < 4:
            continue
        arc = arc_length(line)
        side = 1.0 if bi % 2 else -1.0
        s = rng.uniform(0.3, 1.0) * leaf_spacing
        while s < arc[-1] - 2.0 * unit:
            k = int(np.searchsorted(arc, s))
            k = min(max(k, 1), len(line) - 1)
            r = wid[min(k, len(wid) - 1)] / 2.0
            if r <= max_leaf_radius:
                t = line[k] - line[k - 1]
                t = t / (np.hypot(*t) or 1.0)
                ang = side * np.deg2rad(rng.uniform(35, 65))
                size = rng.uniform(0.75, 1.25)
                lp, lw = _leaf_within(line[k], t, ang, leaf_length * size, leaf_width * size,
                                      side, within)
                if lp is not None:
                    leaf_pts.append(lp)
                    leaf_w.append(lw)
            side = -side
            s += leaf_spacing * rng.uniform(0.7, 1.3)
    return stems, widths, leaf_pts, leaf_w


@checked(stem_color=Colour(), leaf_color=Colour(), smooth=Int(0, 10_000), curls=Real(0, 1), curl_length=Real(0, 1e4),
         leaf_spacing=Real(0.5, 1e4), leaf_length=Real(0, 1e4), leaf_width=Real(0, 1e4))
def render_vines(dendrite: Dendrite, *, background=None, stem_color=(0.22, 0.3, 0.12),
                 leaf_color=(0.3, 0.55, 0.18), smooth: int | None = None, curls: float = 0.6,
                 curl_length: float | None = None, leaves: bool = True,
                 leaf_spacing: float | None = None, leaf_length: float | None = None,
                 leaf_width: float | None = None, within=None, hug=None, rng=0) -> Rendering:
    """The vine metaphor: smooth stems, curled tips, alternating leaves.

    Leaf colours vary slightly around ``leaf_color``; leaves grow only where
    the stem is thin (radius <= 1.6 px at 512 x 512). See :func:`vine_curves`
    for the geometry parameters; None means "scaled to the image diagonal".

    Parameters
    ----------
    dendrite : Dendrite
        The dendrite; its widths become the stem widths.
    background : (H, W, C) array_like, optional
        Image to draw on; white by default.
    stem_color : RGB triple
        Colour of the stems and curls in [0, 1] (dark green).
    leaf_color : RGB triple
        Mean leaf colour in [0, 1]; each leaf's shade is scaled by 0.8-1.2.
    smooth : int, optional
        See :func:`vine_curves`.
    curls : float
        See :func:`vine_curves`.
    curl_length : float, optional
        See :func:`vine_curves`.
    leaves : bool
        Draw leaves.
    leaf_spacing : float, optional
        See :func:`vine_curves`.
    leaf_length : float, optional
        See :func:`vine_curves`.
    leaf_width : float, optional
        See :func:`vine_curves`.
    within : (H, W) bool array_like, optional
        Where leaves may lie; see :func:`vine_curves`.
    hug : (H, W) bool array_like, optional
        Where the stems belong; see :func:`vine_curves`.
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed of the geometry and the leaf shades; 0 by
        default, so the same dendrite always gives the same vines.

    Returns
    -------
    Rendering

    Examples
    --------
    >>> bolt = lightning((60, 40), LightningParams(n_branches=5), rng=0)
    >>> r = render_vines(bolt)
    >>> r.image.shape, bool(r.image[..., 1].min() < 0.9)
    ((60, 40, 3), True)
    """
    rng = as_rng(rng)  # one stream for the geometry and the leaf shades: rng=s equals default_rng(s)
    canvas = _canvas(dendrite, background)
    stems, widths, lp, lw = vine_curves(
        dendrite, smooth=smooth, curls=curls, curl_length=curl_length, leaves=leaves,
        leaf_spacing=leaf_spacing, leaf_length=leaf_length, leaf_width=leaf_width,
        within=within, hug=hug, rng=rng)
    img = draw_polylines(canvas, stems, widths=widths, colors=stem_color)
    h, w = canvas.shape[:2]
    cols = None
    if lp:
        shade = rng.uniform(0.8, 1.2, (len(lp), 1))
        cols = np.clip(np.asarray(leaf_color)[None, :] * shade, 0, 1)
        img = draw_polylines(img, lp, widths=lw, colors=cols)

    def svg():
        layers = [(polylines_to_svg(stems, widths=widths, colors=stem_color, size=(w, h)), "")]
        if lp:
            layers.append((polylines_to_svg(lp, widths=lw, colors=cols, size=(w, h)), ""))
        return svg_document((w, h), layers, background=(1, 1, 1))

    return Rendering(img, svg)


# ------------------------------------------------------------------- lightning
@checked(sky=Colour(), core_color=Colour(), glow_color=Colour(), glow_sigma=Real(0, 1e3), glow_strength=Real(0, 1e4),
         core_scale=Real(0, 1e3), smooth=Int(0, 10_000))
def render_lightning(dendrite: Dendrite, *, background=None, sky=(0.02, 0.02, 0.07),
                     core_color=(1.0, 1.0, 1.0), glow_color=(0.55, 0.6, 1.0),
                     glow_sigma: float | None = None, glow_strength: float = 4.0,
                     core_scale: float = 0.6, smooth: int = 0) -> Rendering:
    """The lightning metaphor: a blurred glow under a bright core.

    The SVG uses an ``feGaussianBlur`` filter for the glow.

    Parameters
    ----------
    dendrite : Dendrite
        The bolt (or any dendrite); wider branches glow more and burn whiter.
    background : (H, W, C) array_like, optional
        Image to draw on; a plain ``sky`` colour by default.
    sky : RGB triple
        Canvas colour when there is no ``background`` (night blue).
    core_color : RGB triple
        Colour of the widest channels' cores; thin branches fade toward
        ``glow_color``.
    glow_color : RGB triple
        Colour of the glow (pale blue).
    glow_sigma : float, optional
        Blur of the glow (pixels); 5 px at 512 x 512 scaled to the image
        diagonal by default.
    glow_strength : float
        Gain of the glow.
    core_scale : float
        Core width relative to the dendrite's widths.
    smooth : int
        Smoothing passes (0 keeps the jagged lattice look, fitting for lightning).

    Returns
    -------
    Rendering

    Raises
    ------
    ValueError
        If ``glow_sigma`` or ``core_scale`` is not > 0.

    Examples
    --------
    >>> bolt = lightning((60, 40), LightningParams(n_branches=5), rng=0)
    >>> img = render_lightning(bolt).image
    >>> bool(img.max() > 0.5), bool(np.median(img) < 0.2)  # a bright bolt on a dark sky
    (True, True)
    """
    canvas = _canvas(dendrite, background, fill=sky)
    glow_sigma = _len(glow_sigma, canvas.shape[:2], 5.0)
    if glow_sigma <= 0 or glow_strength < 0 or core_scale <= 0:
        raise ValueError("glow_sigma and core_scale must be > 0, glow_strength >= 0")
    lines = dendrite.polylines(smooth)
    widths = dendrite.widths()
    h, w = canvas.shape[:2]
    # the glow is the blurred coverage of widened strokes: thick channels glow
    # most, hair-thin branches hardly at all; 1 - exp(-x) saturates softly
    glow_w = [x * 2.5 for x in widths]
    cov, _ = coverage_polylines((h, w), lines, glow_w)
    glow = ndimage.gaussian_filter(cov.astype(np.float64), glow_sigma)
    glow = glow + 0.5 * ndimage.gaussian_filter(cov.astype(np.float64), glow_sigma * 3)
    # dense structures (a stylized image) would glow everywhere: scale so the
    # densest 2 % of the picture saturates, but never boost a sparse bolt
    ref = max(float(np.percentile(glow, 98.0)), 0.15)
    a = (1.0 - np.exp(-glow_strength * glow / ref * 0.15))[:, :, None]
    img = canvas * (1 - a) + np.asarray(glow_color, np.float32) * a
    core_w = [x * core_scale for x in widths]
    # a channel's brightness follows its width (the charge it carries): the main
    # channels burn white, thin side branches fade into the glow
    w_ref = max(max((float(x.max()) for x in widths if len(x)), default=1.0), 1e-6)
    glow_rgb = np.asarray(glow_color, float)
    core_rgb = np.asarray(core_color, float)
    cols = [np.clip(glow_rgb + (core_rgb - glow_rgb) * min(1.0, 0.35 + 0.65 * np.sqrt(
        float(x.mean()) / w_ref) * 1.6), 0, 1) if len(x) else core_rgb for x in widths]
    img = draw_polylines(np.clip(img, 0, 1), lines, widths=core_w, colors=cols)

    def svg():
        defs = (f'<filter id="glow" x="-20%" y="-20%" width="140%" height="140%">'
                f'<feGaussianBlur stdDeviation="{glow_sigma:.2f}"/></filter>')
        layers = [
            (polylines_to_svg(lines, widths=glow_w, colors=glow_color,
                              size=(w, h)), 'filter="url(#glow)" opacity="0.9"'),
            (polylines_to_svg(lines, widths=core_w, colors=cols, size=(w, h)), ""),
        ]
        return svg_document((w, h), layers, background=sky, defs=defs)

    return Rendering(img.astype(np.float32), svg)


@dataclass
class LightningParams:
    """A lightning bolt grown on a direction-weighted lattice.

    Parameters
    ----------
    noise : float
        Amplitude of the random node weight (the lattice's ``noise``); 1.
    epsilon : float
        Constant node weight ``epsilon``; 0.3.
    up_cost : float
        Length factor ``f_k`` of edges stepping up (>= 1); 6, so branches grow
        downward.
    side_cost : float
        Length factor of sideways edges (>= 1); 1.6.
    metric : {"cumulative", "nonscalar", "blend"}
        Path metric of the planner; the non-scalar one gives jagged forks.
    n_branches : int
        Number of side-branch endpoints (>= 0); 60.
    spread : float
        Half-width of the cone the side-branch endpoints are drawn in, at the
        bottom of the image, as a fraction of W; 0.45.
    main_weight : float
        The ground strike counts as this many tips in the pipe model, so the
        main channel is the thickest; 40.
    min_width : float
        Width of the finest branches (pixels at 512 x 512); 0.6.
    max_width : float
        Width of the widest channel (pixels at 512 x 512); 5.
    scale_lengths : bool
        Scale both widths with the image diagonal (:func:`~branchnb.dendrite.scale.length_scale`);
        False takes them as pixels.

    Examples
    --------
    >>> LightningParams().up_cost > LightningParams().side_cost > 1
    True
    """

    noise: float = param(1.0, min=0.0, max=5.0, step=0.05, help="random node weight amplitude")
    epsilon: float = param(0.3, min=0.0, max=5.0, step=0.05, help="constant node weight")
    up_cost: float = param(6.0, min=1.0, max=50.0, step=0.5,
                           help="factor on edges stepping up (branches grow downward)")
    side_cost: float = param(1.6, min=1.0, max=20.0, step=0.1,
                             help="factor on sideways edges")
    metric: str = param("nonscalar", options=("cumulative", "nonscalar", "blend"),
                        help="path metric (non-scalar gives the jagged forks)")
    n_branches: int = param(60, min=0, max=2000, help="endpoints of the side branches")
    spread: float = param(0.45, min=0.05, max=1.0, step=0.05,
                          help="half-width of the branch region at the bottom (fraction of W)")
    main_weight: float = param(40.0, min=1.0, max=1000.0, log=True,
                               help="the ground strike counts as this many tips (thick channel)")
    min_width: float = param(0.6, min=0.1, max=10.0, step=0.1,
                             help="width of the finest branches (px at 512 x 512)")
    max_width: float = param(5.0, min=0.5, max=30.0, step=0.5,
                             help="widest channel (px at 512 x 512)")
    scale_lengths: bool = param(True, help="widths are for 512 x 512 and scale with the diagonal")


@checked(shape=Shape(), start=Point(), strike=Point())
def lightning(shape, params: LightningParams | None = None, *, start=None, strike=None,
              rng=None) -> Dendrite:
    """Grow a lightning bolt: non-scalar paths that prefer to go down.

    Parameters
    ----------
    shape : (H, W)
        Image size in pixels (at least 4 x 4); the lattice has one node per pixel.
    params : LightningParams, optional
        Defaults (``LightningParams()``) if None.
    start : (x, y), optional
        Where the bolt leaves the cloud (top centre by default).
    strike : (x, y), optional
        Where it hits the ground (random near the bottom by default).
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed of the lattice noise, strike and branch
        endpoints.

    Returns
    -------
    Dendrite
        With the pipe-model thickness; the channel to ``strike`` is thickest.

    Raises
    ------
    ValueError
        If ``shape`` is smaller than 4 x 4 or ``start``/``strike`` lie
        outside it.

    Examples
    --------
    >>> bolt = lightning((80, 60), LightningParams(n_branches=10), rng=0)
    >>> bolt.is_tree(), bolt.shape
    (True, (80, 60))
    """
    p = check_params(params if params is not None else LightningParams())
    h, w = shape
    if h < 4 or w < 4:
        raise ValueError(f"shape must be at least 4 x 4, got {shape}")
    for name, point in (("start", start), ("strike", strike)):
        if point is not None:
            as_points(point[None], name=name, image_shape=(h, w))
    rng = as_rng(rng)
    f = direction_factors(down=1.0, side=p.side_cost, up=p.up_cost)
    lat = make_lattice(np.zeros((h, w)), epsilon=p.epsilon, noise=p.noise, rng=rng, factors=f)
    start = np.array([w / 2.0, 0.0]) if start is None else np.asarray(start, float)
    if strike is None:
        strike = np.array([np.clip(w / 2 + rng.normal(0, w * 0.15), 0, w - 1), h - 1.0])
    res = plan(lat, start, metric=p.metric)
    # side branches: random points in a cone widening downward from the start
    n = p.n_branches
    y = h * rng.uniform(0.1, 0.95, n) ** 0.8
    half = p.spread * w * (y / h)
    x = np.clip(start[0] + rng.uniform(-1, 1, n) * half, 0, w - 1)
    ends = np.vstack([np.asarray(strike, float)[None], np.column_stack([x, y])])
    d = build_dendrite(res, ends)
    # pipe model with the strike weighted: the main channel carries the charge
    main = int(np.flatnonzero(d.nodes == lat.node_index(np.asarray(strike)[None])[0])[0])
    tipw = np.zeros(d.n_nodes)
    tipw[d.tips] = 1.0
    tipw[main] = p.main_weight
    from .dendrite import _accumulate_up

    load = _accumulate_up(d.parent, tipw)
    k = length_scale((h, w)) if p.scale_lengths else 1.0
    width = np.minimum(p.min_width * k * np.maximum(load, 1.0) ** 0.5, p.max_width * k)
    return d.with_radius(0.5 * width)
