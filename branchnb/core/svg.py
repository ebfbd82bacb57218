"""SVG export of polylines with per-vertex width.

SVG strokes have one width per path, so a polyline whose width varies is
written as one round-capped ``<line>`` per edge with the edge's mean width;
constant-width polylines become a single ``<polyline>``. The result opens
in vector editors and plotter/laser-cutter software.
"""

from __future__ import annotations

import numpy as np

from .render import pack_polylines
from .validate import COORD_LIMIT, as_colour, as_colours, as_polylines, check_real

__all__ = ["polylines_to_svg"]


def _hex(color) -> str:
    c = np.clip(np.asarray(color, float)[:3], 0, 1)
    return "#{:02x}{:02x}{:02x}".format(*np.round(c * 255).astype(int))


def polylines_to_svg(polylines, widths=None, colors=(0.0, 0.0, 0.0), *, size,
                     background=None) -> str:
    """Write polylines as an SVG document string.

    Parameters
    ----------
    polylines : sequence of (N_i, 2) array_like
        Vertices in (x, y) pixels; the SVG user unit is one pixel.
    widths : float or sequence, optional
        As in :func:`branchnb.core.render.draw_polylines`.
    colors : colour or sequence of colours
        One RGB(A) colour in [0, 1] for all polylines, or one per polyline.
    size : (width, height)
        Canvas size in pixels.
    background : colour, optional
        Fill colour of a background rectangle; transparent if None.

    Returns
    -------
    str
        A standalone SVG document (``<svg ...>...</svg>``) in pixel units.

    Examples
    --------
    >>> svg = polylines_to_svg([[(0, 0), (10, 5)]], widths=2, size=(20, 10))
    >>> svg.startswith("<svg")
    True
    """
    if isinstance(size, (str, bytes)) or not hasattr(size, "__len__") or len(size) != 2:
        raise TypeError(f"size must be a (width, height) pair, got {size!r:.60}")
    w = check_real(size[0], "size[0]", 0, COORD_LIMIT, low_open=True)
    h = check_real(size[1], "size[1]", 0, COORD_LIMIT, low_open=True)
    w, h = f"{w:g}", f"{h:g}"
    if isinstance(polylines, np.ndarray) and polylines.ndim == 2:
        polylines = [polylines]
    n = len(as_polylines(polylines, "polylines"))
    col = as_colours(colors, n, "colors", channels=(3, 4))
    if background is not None:
        background = as_colour(background, "background")
    segs, owner = pack_polylines(polylines, widths)
    # Everything below formats validated, finite numbers: the document is valid SVG.
    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
        f'viewBox="0 0 {w} {h}">'
    ]
    if background is not None:
        parts.append(f'<rect width="{w}" height="{h}" fill="{_hex(background)}"/>')
    for i in range(n):
        s = segs[owner == i]
        if not len(s):
            continue
        colour = _hex(col[i])
        widths_i = np.concatenate([s[:, 2], s[-1:, 5]]) * 2
        if np.allclose(widths_i, widths_i[0]):
            pts = np.vstack([s[:, :2], s[-1:, 3:5]])
            coords = " ".join(f"{x:.2f},{y:.2f}" for x, y in pts)
            parts.append(
                f'<polyline points="{coords}" fill="none" stroke="{colour}" '
                f'stroke-width="{widths_i[0]:.2f}" stroke-linecap="round" stroke-linejoin="round"/>'
            )
        else:
            parts.append(f'<g stroke="{colour}" stroke-linecap="round">')
            for x0, y0, r0, x1, y1, r1 in s:
                parts.append(
                    f'<line x1="{x0:.2f}" y1="{y0:.2f}" x2="{x1:.2f}" y2="{y1:.2f}" '
                    f'stroke-width="{(r0 + r1):.2f}"/>'
                )
            parts.append("</g>")
    parts.append("</svg>")
    return "\n".join(parts)
