"""Rasterise polylines with per-vertex width, anti-aliased.

Each edge is drawn as a tapered capsule (radius interpolated linearly
between its two vertices); overlapping capsules combine by maximum
coverage, so joints and branch points show no double-blended seams.
"""

from __future__ import annotations

import numba
import numpy as np

from .image import as_float_image
from .validate import COORD_LIMIT, as_colours, as_polylines, check_real, check_shape, real_array

__all__ = ["draw_polylines", "coverage_polylines", "pack_polylines"]

#: Widest stroke (pixels) a polyline may have: as far as coordinates may reach.
MAX_WIDTH = COORD_LIMIT


def _is_number(value) -> bool:
    return isinstance(value, (int, float, np.number)) and not isinstance(value, (bool, np.bool_))


@numba.njit(cache=True)
def _rasterise(segs, seg_color, height, width, coverage, colour_idx):
    # segs: (S, 6) x0, y0, r0, x1, y1, r1
    for s in range(segs.shape[0]):
        x0, y0, r0, x1, y1, r1 = segs[s, 0], segs[s, 1], segs[s, 2], segs[s, 3], segs[s, 4], segs[s, 5]
        rmax = max(r0, r1) + 1.0
        # Clamp in floating point before converting: a far-away coordinate
        # would overflow int64 and index outside the arrays.
        c0 = int(np.floor(min(max(min(x0, x1) - rmax, 0.0), width)))
        c1 = int(np.ceil(max(min(max(x0, x1) + rmax, width - 1.0), -1.0)))
        q0 = int(np.floor(min(max(min(y0, y1) - rmax, 0.0), height)))
        q1 = int(np.ceil(max(min(max(y0, y1) + rmax, height - 1.0), -1.0)))
        dx, dy = x1 - x0, y1 - y0
        len2 = dx * dx + dy * dy
        for r in range(q0, q1 + 1):
            for c in range(c0, c1 + 1):
                px, py = c - x0, r - y0
                t = 0.0
                if len2 > 0:
                    t = (px * dx + py * dy) / len2
                    t = min(max(t, 0.0), 1.0)
                ex, ey = px - t * dx, py - t * dy
                d = np.sqrt(ex * ex + ey * ey)
                rad = r0 + t * (r1 - r0)
                # Sub-pixel radii: fade the line instead of letting it vanish.
                if rad < 0.5:
                    cov = min(max(0.5 - d + 0.5, 0.0), 1.0) * 2.0 * rad
                else:
                    cov = min(max(rad - d + 0.5, 0.0), 1.0)
                if cov > coverage[r, c]:
                    coverage[r, c] = cov
                    colour_idx[r, c] = seg_color[s]


def pack_polylines(polylines, widths=None, default_width: float = 1.0):
    """Validate polylines and widths; return ``(segments (S, 6), polyline index (S,))``.

    Parameters
    ----------
    polylines : sequence of (N_i, 2) array_like
        Vertices (x, y) in pixels; a single ``(N, 2)`` array is one
        polyline. Empty polylines are skipped; a one-vertex polyline is a dot.
    widths : None, float, or sequence of float / (N_i,) array_like
        Full line width (diameter, pixels, 0..``MAX_WIDTH``) for all, per
        polyline or per vertex.
    default_width : float
        Width used when ``widths`` is None.

    Returns
    -------
    segments : (S, 6) float ndarray
        One row ``(x0, y0, r0, x1, y1, r1)`` per segment, radii = half widths.
    index : (S,) int ndarray
        The polyline each segment belongs to.

    Raises
    ------
    TypeError, ValueError
        If a polyline is not ``(N, 2)`` real coordinates, or ``widths`` has
        the wrong length or a width is negative or non-finite.

    Examples
    --------
    >>> segs, index = pack_polylines([[(0, 0), (4, 0), (4, 3)]], widths=2.0)
    >>> segs.tolist(), index.tolist()
    ([[0.0, 0.0, 1.0, 4.0, 0.0, 1.0], [4.0, 0.0, 1.0, 4.0, 3.0, 1.0]], [0, 0])
    """
    if isinstance(polylines, np.ndarray) and polylines.ndim == 2:
        if widths is not None and not _is_number(widths):
            widths = [widths]
    polylines = as_polylines(polylines, "polylines")
    if widths is not None and not _is_number(widths):
        if isinstance(widths, (str, bytes)) or not hasattr(widths, "__len__"):
            raise TypeError(f"widths must be a number or one entry per polyline, got {type(widths).__name__}")
        if len(widths) != len(polylines):
            raise ValueError(f"widths must have one entry per polyline ({len(polylines)}), got {len(widths)}")
    segs, owner = [], []
    for i, p in enumerate(polylines):
        if len(p) == 0:
            continue
        if widths is None:
            w = np.full(len(p), default_width)
        elif _is_number(widths):
            w = np.full(len(p), check_real(widths, "widths", 0, MAX_WIDTH))
        else:
            wi = widths[i]
            if _is_number(wi):
                w = np.full(len(p), check_real(wi, f"widths[{i}]", 0, MAX_WIDTH))
            else:
                w = real_array(wi, f"widths[{i}]", finite=False)
            if w.shape != (len(p),):
                raise ValueError(f"widths[{i}] must be a number or have {len(p)} entries")
        if not np.all(np.isfinite(w)) or np.any(w < 0) or np.any(w > MAX_WIDTH):
            raise ValueError(f"widths for polylines[{i}] must be finite and in [0, {MAX_WIDTH:g}]")
        r = w / 2.0
        if len(p) == 1:  # a dot
            p = np.vstack([p, p])
            r = np.concatenate([r, r])
        segs.append(np.column_stack([p[:-1], r[:-1], p[1:], r[1:]]))
        owner.append(np.full(len(p) - 1, i))
    if not segs:
        return np.zeros((0, 6)), np.zeros(0, np.int64)
    return np.vstack(segs), np.concatenate(owner).astype(np.int64)


def coverage_polylines(shape, polylines, widths=None) -> tuple[np.ndarray, np.ndarray]:
    """Anti-aliased coverage of polylines on an ``(H, W)`` grid.

    Parameters
    ----------
    shape : (int, int)
        ``(H, W)`` of the grid (extra entries, e.g. channels, are ignored).
    polylines : sequence of (N_i, 2) array_like
        Vertices (x, y) in pixels.
    widths : None, float, or sequence of float / (N_i,) array_like
        Full line width (pixels) for all, per polyline or per vertex;
        1 pixel by default (see :func:`pack_polylines`).

    Returns
    -------
    coverage : (H, W) float32 in [0, 1]
        Fraction of each pixel covered by the thick lines.
    owner : (H, W) int64
        Index of the polyline that covers each pixel most (-1 if none).

    Examples
    --------
    >>> cov, owner = coverage_polylines((5, 9), [[(1, 2), (7, 2)]], widths=3)
    >>> float(cov[2, 4]), int(owner[2, 4]), int(owner[0, 0])
    (1.0, 0, -1)
    """
    h, w = check_shape(shape, "shape")
    segs, owner = pack_polylines(polylines, widths)
    coverage = np.zeros((h, w), np.float32)
    idx = np.full((h, w), -1, np.int64)
    if len(segs):
        _rasterise(segs, owner, h, w, coverage, idx)
    return coverage, idx


def draw_polylines(image, polylines, widths=None, colors=(0.0, 0.0, 0.0), *,
                   alpha: float = 1.0) -> np.ndarray:
    """Draw polylines with per-vertex width onto a copy of ``image``.

    Parameters
    ----------
    image : (H, W, C) array_like
        Canvas (any layout accepted by :func:`as_float_image`); RGBA
        canvases get their alpha raised under the strokes.
    polylines : sequence of (N_i, 2) array_like
        Vertices in (x, y) pixels.
    widths : float or sequence, optional
        Full width per polyline, or per vertex (``(N_i,)`` arrays).
    colors : colour or sequence of colours
        One RGB(A) triple for all, or one per polyline.
    alpha : float
        Opacity of all strokes in [0, 1], multiplied with each colour's own
        alpha.

    Returns
    -------
    out : ndarray, same shape as the converted ``image``

    Examples
    --------
    >>> import numpy as np
    >>> img = draw_polylines(np.ones((20, 20, 3)), [[(2, 10), (17, 10)]], widths=[[2, 6]])
    >>> float(img[10, 15, 0]) < 0.1
    True
    """
    img = as_float_image(image)
    alpha = check_real(alpha, "alpha", 0, 1)
    n_lines = len(as_polylines(polylines, "polylines"))
    col = as_colours(colors, n_lines, "colors")
    if col.shape[1] == 1:
        col = np.repeat(col, 3, axis=1)
    col_alpha = col[:, 3] if col.shape[1] == 4 else np.ones(len(col), np.float32)
    coverage, idx = coverage_polylines(img.shape[:2], polylines, widths)
    a = coverage * alpha * np.where(idx >= 0, col_alpha[np.maximum(idx, 0)], 0.0)
    a = a[:, :, None].astype(np.float32)
    c = img.shape[2]
    src = col[np.maximum(idx, 0), :3]
    if c == 1:
        src = (src @ np.array([0.2126, 0.7152, 0.0722], np.float32))[:, :, None]
    out = img.copy()
    out[:, :, : min(c, 3)] = img[:, :, : min(c, 3)] * (1 - a) + src[:, :, : min(c, 3)] * a
    if c == 4:
        out[:, :, 3] = img[:, :, 3] + a[:, :, 0] * (1 - img[:, :, 3])
    return np.clip(out, 0, 1).astype(np.float32)


def _sketch_polylines(shape, polylines, widths, colors, *, max_size: int, background=None) -> np.ndarray:
    """A quick preview of polylines: uint8 RGB, at most ``max_size`` px on its long side.

    One OpenCV anti-aliased line per polyline at its mean width (no taper,
    no coverage blending): a few milliseconds where :func:`draw_polylines`
    at full size takes tens to hundreds (apps show growing skeletons with
    it; the finished structure is drawn by :func:`draw_polylines`).
    ``background`` (H, W[, C], any layout :func:`as_float_image` takes) is
    shrunk under the lines; white if None. Widths are full widths in
    pixels of ``shape``; lines are at least 1 px wide after shrinking.
    """
    import cv2

    h, w = (int(v) for v in shape[:2])
    s = min(1.0, float(max_size) / max(h, w, 1))
    size = (max(1, round(w * s)), max(1, round(h * s)))
    if background is None:
        out = np.full((size[1], size[0], 3), 255, np.uint8)
    else:
        bg = as_float_image(background)
        bg = bg[..., :3] if bg.shape[2] >= 3 else np.repeat(bg[..., :1], 3, axis=2)
        bg = cv2.resize(bg, size, interpolation=cv2.INTER_AREA) if s < 1.0 else bg
        out = np.ascontiguousarray(np.clip(bg * 255.0 + 0.5, 0, 255).astype(np.uint8))
    col = np.asarray(colors, np.float64).reshape(-1, 3) if len(polylines) else np.zeros((0, 3))
    if len(col) == 1:
        col = np.repeat(col, len(polylines), axis=0)
    for pts, wd, c in zip(polylines, widths, col):
        p = np.asarray(pts, np.float64)
        if len(p) < 2:
            continue
        t = max(1, int(round(float(np.mean(wd)) * s)))
        q = np.round(p * (s * 4.0)).astype(np.int32).reshape(-1, 1, 2)  # shift=2: quarter pixels
        cv2.polylines(out, [q], False, tuple(int(round(255 * v)) for v in c[:3]), t, cv2.LINE_AA, shift=2)
    return out
