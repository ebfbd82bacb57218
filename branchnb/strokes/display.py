"""Pictures of strokes: each pair in its own colour, direction marked.

The i-th source stroke and the i-th target stroke are drawn in the same
colour (:data:`PAIR_COLORS`, cycling), with a dot at the start and an
arrowhead at the end, since the direction of travel decides which end of
the source goes where. Control points are drawn as rings.
"""

from __future__ import annotations

import numpy as np

from ..core.image import as_points, as_rgb, as_rgba
from ..core.render import draw_polylines
from ..core.validate import MAX_COUNT, Colour, Int, Real, Seq, checked

__all__ = ["PAIR_COLORS", "pair_color", "pair_color_hex", "draw_strokes", "stroke_markers"]

#: Colours of the stroke pairs (RGB in [0, 1]), in drawing order (no red: seams are red).
PAIR_COLORS = (
    (0.16, 0.40, 0.90), (0.98, 0.55, 0.10), (0.20, 0.70, 0.30), (0.85, 0.20, 0.85),
    (0.10, 0.75, 0.80), (0.55, 0.25, 0.80), (0.60, 0.80, 0.10), (0.45, 0.30, 0.15),
)


@checked(i=Int())
def pair_color(i: int) -> tuple[float, float, float]:
    """Colour of stroke pair ``i`` (RGB in [0, 1]).

    Parameters
    ----------
    i : int
        Pair index; colours cycle through :data:`PAIR_COLORS`.

    Returns
    -------
    (float, float, float)

    Examples
    --------
    >>> pair_color(0) == pair_color(len(PAIR_COLORS))
    True
    """
    return PAIR_COLORS[int(i) % len(PAIR_COLORS)]


@checked(i=Int())
def pair_color_hex(i: int) -> str:
    """Colour of stroke pair ``i`` as a CSS hex string.

    Parameters
    ----------
    i : int
        Pair index; colours cycle through :data:`PAIR_COLORS`.

    Returns
    -------
    str
        ``"#rrggbb"``.

    Examples
    --------
    >>> pair_color_hex(0)
    '#2966e6'
    """
    return "#" + "".join(f"{round(c * 255):02x}" for c in pair_color(i))


def _marks(strokes, width: float, control, first: int, lines: bool):
    """Polylines, colours and widths of the strokes, their start dots, arrowheads and rings."""
    out_l, out_c, out_w = [], [], []

    def add(p, col, w):
        out_l.append(p)
        out_c.append(col)
        out_w.append(w)

    for i, st in enumerate(strokes):
        p = as_points(st, name=f"strokes[{i}]", min_points=1)
        col = pair_color(first + i)
        if len(p) > 1:
            if lines:
                add(p, col, width)
            d = p[-1] - p[-2]
            n = np.hypot(*d)
            if n > 1e-9:  # arrowhead at the end
                d = d / n
                size = 3.0 * width + 3.0
                side = 0.6 * size * np.array([-d[1], d[0]])
                add(np.array([p[-1] - size * d + side, p[-1], p[-1] - size * d - side]), col, width)
        add(p[:1], col, 2.5 * width + 1.0)  # dot at the start
        if control is not None and i < len(control) and control[i] is not None:
            for c in as_points(control[i], name=f"control[{i}]"):
                t = np.linspace(0, 2 * np.pi, 17)
                ring = c + (2.0 * width + 3.0) * np.c_[np.cos(t), np.sin(t)]
                add(ring, (1.0, 1.0, 1.0), width + 1.0)
                add(ring, col, width * 0.6)
    return out_l, out_c, out_w


@checked(strokes=Seq(), width=Real(0, 1e4), control=Seq(), first=Int(0, MAX_COUNT), background=Colour())
def draw_strokes(image, strokes, *, width: float = 2.0, control=None, first: int = 0,
                 background=(1.0, 1.0, 1.0)) -> np.ndarray:
    """Draw ``strokes`` on an RGB copy of ``image`` in their pair colours.

    Parameters
    ----------
    image : (H, W, C) array_like
        RGBA is composited over ``background``.
    strokes : sequence of (N, 2) array_like
        Stroke ``i`` gets colour :func:`pair_color` ``(first + i)``.
    width : float
        Line width (px).
    control : sequence, optional
        Per stroke, None or a ``(K, 2)`` array of control points to ring.
    first : int
        Colour index of the first stroke.
    background : RGB triple
        Colour an RGBA ``image`` is composited over; white by default.

    Returns
    -------
    (H, W, 3) float32 ndarray

    Examples
    --------
    >>> img = draw_strokes(np.ones((20, 40, 3)), [[(5, 10), (35, 10)]])
    >>> bool(img[10, 20, 2] > 0.8 and img[10, 20, 0] < 0.3)
    True
    """
    out = as_rgb(image, background=background)
    lines, colours, widths = _marks(strokes, width, control, first, lines=True)
    if not lines:
        return out
    return draw_polylines(out, lines, widths=widths, colors=colours)


@checked(strokes=Seq(), width=Real(0, 1e4), control=Seq(), first=Int(0, MAX_COUNT))
def stroke_markers(canvas, strokes, *, width: float = 2.0, control=None,
                   first: int = 0) -> np.ndarray:
    """Start dots, end arrowheads and control rings of ``strokes`` over an RGBA ``canvas``.

    ``canvas`` is an RGBA image (e.g. a transparent ``np.zeros((H, W, 4))``
    or an edit result); the stroke lines themselves are not drawn (an
    annotation canvas draws them).

    Parameters
    ----------
    canvas : (H, W, C) array_like
        Image to draw on, converted to RGBA; not modified.
    strokes : sequence of (N, 2) array_like
        Stroke ``i`` gets colour :func:`pair_color` ``(first + i)``.
    width : float
        Line width (px) the markers are sized from; 2.
    control : sequence, optional
        Per stroke, None or a ``(K, 2)`` array of control points to ring.
    first : int
        Colour index of the first stroke.

    Returns
    -------
    (H, W, 4) float32 ndarray

    Examples
    --------
    >>> m = stroke_markers(np.zeros((20, 40, 4)), [[(5, 10), (35, 10)]])
    >>> bool(m[10, 5, 3] > 0.9), bool(m[10, 20, 3] == 0)
    (True, True)
    """
    out = as_rgba(canvas, name="canvas")
    lines, colours, widths = _marks(strokes, width, control, first, lines=False)
    if not lines:
        return out
    return draw_polylines(out, lines, widths=widths, colors=colours)
