"""Rendering a dendrite: the plain metaphor, plus views of the planner state.

Every metaphor returns a :class:`Rendering` holding both the raster image
and an SVG document of the same strokes (``branchnb.core.svg``), so a result
can go to a plotter, a laser cutter or a vector editor. The raster is
anti-aliased with per-vertex width (``branchnb.core.render``).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from scipy import ndimage

from ..core.image import as_float_image, as_points, as_rgb
from ..core.io import encode_png
from ..core.render import draw_polylines
from ..core.svg import polylines_to_svg
from ..core.validate import Choice, Colormap, Colour, Instance, Int, Real, check_output_path, checked, real_array
from .planner import PlanResult

__all__ = [
    "Rendering",
    "cost_image",
    "draw_points",
    "render_plain",
    "svg_document",
    "visiting_order_image",
]


class Rendering:
    """A rendered dendrite: raster ``image`` (H, W, 3) float32 and its ``svg`` text.

    The SVG may be given as a string or as a function returning it; it is
    then built on first access (writing one element per stroke segment is
    slower than rasterising, and interactive use rarely needs it).

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The raster rendering, float in [0, 1] (stored as float32).
    svg : str or callable
        The SVG document, or a function of no arguments returning it (built
        and cached on first access of :attr:`svg`).

    Raises
    ------
    TypeError
        If ``svg`` is neither a string nor callable.

    Examples
    --------
    >>> r = Rendering(np.ones((4, 6, 3)), lambda: "<svg/>")
    >>> r
    Rendering(image 6 x 4, svg lazy)
    >>> r.svg
    '<svg/>'
    """

    def __init__(self, image: np.ndarray, svg):
        self.image = real_array(image, "image", ndim=(2, 3), dtype=np.float32)
        if not (isinstance(svg, str) or callable(svg)):
            raise TypeError(f"svg must be a string or a function returning one, got {type(svg).__name__}")
        self._svg = svg

    @property
    def svg(self) -> str:
        """The SVG document (built on first access)."""
        if callable(self._svg):
            self._svg = self._svg()
        return self._svg

    def save_svg(self, path) -> Path:
        """Write the SVG document to ``path``.

        Parameters
        ----------
        path : str or os.PathLike
            Output file (UTF-8 text); its folder must exist.

        Returns
        -------
        pathlib.Path
            The path written.
        """
        path = check_output_path(path)
        path.write_text(self.svg, encoding="utf-8")
        return path

    def __repr__(self) -> str:
        h, w = self.image.shape[:2]
        return f"Rendering(image {w} x {h}, svg {'built' if isinstance(self._svg, str) else 'lazy'})"

    def _repr_png_(self) -> bytes:
        return encode_png(self.image)


def _canvas(dendrite, background, fill=(1.0, 1.0, 1.0)) -> np.ndarray:
    if background is None:
        if dendrite.shape is None:
            raise ValueError("the dendrite has no image shape: pass a background")
        h, w = dendrite.shape
        return np.broadcast_to(np.asarray(fill, np.float32), (h, w, 3)).copy()
    img = as_rgb(background, name="background")
    if dendrite.shape is not None and img.shape[:2] != tuple(dendrite.shape):
        raise ValueError(f"background has shape {img.shape[:2]}, expected {tuple(dendrite.shape)}")
    return img


def svg_document(size, layers, *, background=None, defs: str = "") -> str:
    """Combine SVG layers into one document.

    Parameters
    ----------
    size : (width, height)
        Document size in pixels (also the ``viewBox``).
    layers : sequence of (svg_text, attributes)
        Each ``svg_text`` is a document from :func:`branchnb.core.svg.polylines_to_svg`
        whose content is wrapped in ``<g attributes>``.
    background : colour, optional
        Fill colour of a background rectangle.
    defs : str
        Extra ``<defs>`` content (e.g. a blur filter).

    Returns
    -------
    str
        The SVG document.

    Examples
    --------
    >>> doc = svg_document((4, 3), [('<svg><line x1="0" y1="0" x2="4" y2="3"/></svg>', 'opacity="0.5"')],
    ...                    background=(1, 1, 1))
    >>> doc.splitlines()[1:3]
    ['<rect width="4" height="3" fill="#ffffff"/>', '<g opacity="0.5"><line x1="0" y1="0" x2="4" y2="3"/></g>']
    """
    w, h = size
    out = [(f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
           f'viewBox="0 0 {w} {h}">')]
    if defs:
        out.append(f"<defs>{defs}</defs>")
    if background is not None:
        c = np.clip(np.asarray(background, float)[:3], 0, 1)
        out.append('<rect width="{}" height="{}" fill="#{:02x}{:02x}{:02x}"/>'.format(
            w, h, *np.round(c * 255).astype(int)))
    for text, attrs in layers:
        body = re.sub(r"^<svg[^>]*>", "", text.strip())
        body = re.sub(r"</svg>$", "", body.strip())
        body = re.sub(r"^<rect [^>]*/>", "", body.strip())
        out.append(f"<g {attrs}>{body}</g>" if attrs else body)
    out.append("</svg>")
    return "\n".join(out)


@checked(dendrite=Instance("Dendrite"), color=Colour(), smooth=Int(0, 10_000), width_scale=Real(0, 1e3))
def render_plain(dendrite, *, background=None, color=(0.0, 0.0, 0.0), smooth: int = 2,
                 width_scale: float = 1.0) -> Rendering:
    """The plain metaphor: every branch as an anti-aliased line of varying width.

    Parameters
    ----------
    dendrite : Dendrite
        The dendrite; each node is drawn with width ``2 * radius``.
    background : (H, W, C) array_like, optional
        Image to draw on (white by default). The SVG has only the strokes, on
        the background's colour when it is one flat colour (light ink on a dark
        ground stays visible) and on white otherwise.
    color : RGB triple
        Stroke colour in [0, 1]; black by default.
    smooth : int
        Passes of [1, 2, 1] / 4 averaging along the branches
        (:meth:`Dendrite.smoothed_points`) to soften the lattice staircase.
    width_scale : float
        Multiplies every width.

    Examples
    --------
    >>> from branchnb.dendrite import plan, make_lattice, build_dendrite
    >>> res = plan(make_lattice(np.zeros((40, 40)), rng=0), (20, 39))
    >>> r = render_plain(build_dendrite(res, [(3, 3), (36, 5)]))
    >>> r.image.shape, r.svg.startswith("<svg")
    ((40, 40, 3), True)
    """
    if not np.isfinite(width_scale) or width_scale < 0:
        raise ValueError(f"width_scale must be finite and >= 0, got {width_scale}")
    canvas = _canvas(dendrite, background)
    lines = dendrite.polylines(smooth)
    widths = [w * width_scale for w in dendrite.widths()]
    flat = canvas.reshape(-1, canvas.shape[-1])[:, :3]
    paper = tuple(float(c) for c in flat[0]) if np.ptp(flat, axis=0).max() < 1e-3 else (1, 1, 1)
    image = draw_polylines(canvas, lines, widths=widths, colors=color)
    h, w = canvas.shape[:2]
    return Rendering(image, lambda: polylines_to_svg(lines, widths=widths, colors=color,
                                                     size=(w, h), background=paper))


#: Window of the median that :func:`visiting_order_image` smooths its bands with when
#: ``flat`` (share of the lattice's diagonal; 5 px on the 512-px lattice).
FLAT_WINDOW = 0.007


@checked(bands=Int(1, 4096), cmap=Colormap())
def visiting_order_image(plan_result: PlanResult, *, bands: int = 16, cmap: str = "magma",
                         seeds: bool = True, flat: bool = False) -> np.ndarray:
    """The order in which Dijkstra settled the nodes, as banded contours.

    The visiting rank is split into ``bands`` equal-count bands drawn in
    alternating light/dark shades of a colormap, so the band edges are the
    isocontours of the growing front (the paper's contour figure). The
    cumulative metric gives round, onion-like fronts; the non-scalar one
    floods cheap regions first and gives ragged, fractal fronts.
    Unreached nodes are grey.

    Parameters
    ----------
    plan_result : PlanResult
        A lattice plan (``shape`` set).
    bands : int
        Number of equal-count contour bands (>= 1); 16 by default.
    cmap : str
        Matplotlib colormap name the visiting rank is coloured with.
    seeds : bool
        Mark the seeds with green dots (when there are at most 64 of them).
    flat : bool
        One colour per band (its middle rank's), the band of every node the median of its
        neighbours' within ``FLAT_WINDOW`` of the diagonal (at least 3 px): the fronts'
        shapes at a glance without the single-node speckle, in at most ``2 + bands``
        colours, so the image stores as a small palette PNG
        (:func:`~branchnb.core.io.encode_png`).

    Returns
    -------
    (H, W, 3) float32

    Raises
    ------
    ValueError
        If the plan is on a general graph or ``bands < 1``.

    Examples
    --------
    >>> from branchnb.dendrite.lattice import make_lattice
    >>> from branchnb.dendrite.planner import plan
    >>> visiting_order_image(plan(make_lattice(np.zeros((12, 12)), rng=0), (6, 6))).shape
    (12, 12, 3)
    """
    if plan_result.shape is None:
        raise ValueError("visiting_order_image needs a lattice plan")
    if not isinstance(bands, (int, np.integer)) or bands < 1:
        raise ValueError(f"bands must be a positive int, got {bands!r}")
    import matplotlib

    rank = plan_result.rank.astype(np.float64)
    n = max(len(plan_result.order), 1)
    t = np.where(rank >= 0, rank / n, np.nan)
    band = np.floor(np.nan_to_num(t) * bands)
    if flat:
        band = np.minimum(band, bands - 1).reshape(plan_result.shape)
        size = max(3, 2 * int(round(0.5 * FLAT_WINDOW * float(np.hypot(*plan_result.shape)))) + 1)
        band = ndimage.median_filter(band, size=size, mode="nearest").ravel()
        t = np.where(np.isnan(t), np.nan, (band + 0.5) / bands)
    shade = np.where(band % 2 == 0, 1.0, 0.78)
    rgb = matplotlib.colormaps[cmap](np.nan_to_num(t) * 0.85 + 0.1)[..., :3] * shade[:, None]
    rgb[np.isnan(t)] = 0.5
    img = rgb.reshape(*plan_result.shape, 3).astype(np.float32)
    if seeds:
        w = plan_result.shape[1]
        pts = np.column_stack([plan_result.seeds % w, plan_result.seeds // w]).astype(float)
        if len(pts) <= 64:
            img = draw_points(img, pts, color=(0.1, 0.8, 0.3), radius=3.0)
    return img


@checked(which=Choice("total", "max"))
def cost_image(plan_result: PlanResult, which: str = "total") -> np.ndarray:
    """The planner's ``total`` (S) or ``max`` (M) cost as an (H, W) array scaled to [0, 1]
    (unreached nodes are 1).

    Parameters
    ----------
    plan_result : PlanResult
        A lattice plan (``shape`` set).
    which : {"total", "max"}
        ``"total"`` for the cumulative cost ``S``, ``"max"`` for the largest
        edge ``M``.

    Returns
    -------
    (H, W) float32 ndarray
        Min-max scaled to [0, 1] over the reached nodes (0 where constant).

    Raises
    ------
    ValueError
        If the plan is on a general graph or ``which`` is unknown.

    Examples
    --------
    >>> from branchnb.dendrite.lattice import make_lattice
    >>> from branchnb.dendrite.planner import plan
    >>> c = cost_image(plan(make_lattice(np.zeros((9, 9)), noise=0.0), (0, 0)))
    >>> float(c[0, 0]), float(c[8, 8])
    (0.0, 1.0)
    """
    if plan_result.shape is None:
        raise ValueError("cost_image needs a lattice plan")
    if which not in ("total", "max"):
        raise ValueError(f"which must be 'total' or 'max', got {which!r}")
    v = plan_result.total_cost if which == "total" else plan_result.max_cost
    fin = np.isfinite(v)
    out = np.ones(v.shape)
    if fin.any():
        lo, hi = v[fin].min(), v[fin].max()
        out[fin] = (v[fin] - lo) / (hi - lo) if hi > lo else 0.0
    return out.reshape(plan_result.shape).astype(np.float32)


@checked(color=Colour(), radius=Real(0, 1e4))
def draw_points(image, points, *, color=(0.85, 0.1, 0.1), radius: float = 1.5) -> np.ndarray:
    """Dots of the given radius at ``(x, y)`` points (e.g. endpoints) on a copy of ``image``.

    Parameters
    ----------
    image : array_like
        Grey or colour image in [0, 1]; not modified.
    points : (N, 2) array_like
        ``(x, y)`` dot centres in pixels; may be empty.
    color : RGB triple
        Dot colour in [0, 1]; red by default.
    radius : float
        Dot radius in pixels (>= 0).

    Returns
    -------
    ndarray
        A float32 copy of ``image`` with the dots.

    Examples
    --------
    >>> img = draw_points(np.ones((9, 9, 3)), [(4, 4)], color=(0, 0, 0), radius=2)
    >>> float(img[4, 4, 0]), float(img[0, 0, 0])
    (0.0, 1.0)
    """
    img = as_float_image(image)
    pts = as_points(points, name="points", min_points=0)
    if not len(pts):
        return img.copy()
    return draw_polylines(img, [p[None] for p in pts], widths=2.0 * radius, colors=color)
