"""The sources' pen along a mix's silhouette (beyond the paper; issue 24).

:func:`~branchnb.trees.outline.even_outline` inks a band of whole pixels,
``width`` deep in chessboard distance, with one ring of half ink inside it.
The width is an integer read off one exemplar, so a 3-px anti-aliased pen
came out as a 2-px one (measured 2 on one source, 3 on the next); a
chessboard band is thinner across diagonal stretches (by up to 1/sqrt 2)
and follows every stair-step of the mixed silhouette, so the outline looked
thinner and ragged next to the sources' stroke.

Here the pen is measured rather than assumed: its *profile* is the median
ink coverage of the sources' pixels at each Euclidean depth from the
silhouette (the coverage of a pixel is its position on the line from the
fill behind the stroke to the ink). The mix's band is repainted with that
profile at its own Euclidean depth, over the colour of the nearest fill
pixel beyond the band: the outline has the sources' width and soft inner
edge, evenly along crown and trunk.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

_LUM = np.array([0.299, 0.587, 0.114], np.float32)

#: Depth bins of the pen profile (pixels).
_STEP = 0.5


def _depth_edt(alpha: np.ndarray) -> np.ndarray:
    """Euclidean distance of every opaque pixel from the nearest transparent one (rim: 1).

    The image border does not count as transparent (a trunk cut by the frame has no rim there).
    """
    pad = np.pad(alpha, 1, constant_values=True)
    if pad.all():
        return np.full(alpha.shape, float(alpha.size))
    return ndi.distance_transform_edt(pad)[1:-1, 1:-1]


def _chessboard(alpha: np.ndarray) -> np.ndarray:
    from .outline import _depth

    return _depth(alpha)


def _coverage(rgb: np.ndarray, fill: np.ndarray, ink: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Ink coverage of pixels between their fill and the ink, and where that is measurable."""
    d = fill - ink[None]
    n2 = (d * d).sum(axis=1)
    ok = n2 > 0.15 ** 2
    c = ((fill - rgb) * d).sum(axis=1) / np.maximum(n2, 1e-9)
    return np.clip(c, 0.0, 1.0), ok


def _pen_profile(image: np.ndarray, ink: np.ndarray, width: int) -> np.ndarray | None:
    """Median ink coverage per Euclidean depth bin of an outlined tree (None when unmeasurable).

    Entry ``k`` is the coverage at depth ``1 + k * _STEP`` (the rim is at depth 1); zero beyond
    the stroke.
    """
    alpha = image[..., 3] >= 0.5
    if alpha.sum() < 50:
        return None
    depth = _depth_edt(alpha)
    cut = 2 * width + 3
    deep = alpha & (depth > cut)
    band = alpha & (depth <= cut)
    if deep.sum() < 10 or not band.any():
        return None
    idx = ndi.distance_transform_edt(~deep, return_distances=False, return_indices=True)
    ys, xs = np.nonzero(band)
    fill = image[idx[0][ys, xs], idx[1][ys, xs], :3].astype(np.float64)
    c, ok = _coverage(image[ys, xs, :3].astype(np.float64), fill, np.asarray(ink, np.float64))
    k = np.round((depth[ys, xs] - 1) / _STEP).astype(int)
    n = int(round((cut - 1) / _STEP)) + 1
    prof = np.zeros(n)
    for b in range(n):
        sel = ok & (k == b)
        if sel.sum() >= 5:
            prof[b] = np.median(c[sel])
        elif b > 0:
            prof[b] = prof[b - 1]
    prof = np.minimum.accumulate(prof)
    prof[prof < 0.05] = 0.0
    if prof[0] < 0.5:          # the rim (depth 1) is no ink: not an outlined drawing
        return None
    return prof


def _profile_at(profile: np.ndarray, depth: np.ndarray) -> np.ndarray:
    grid = 1 + _STEP * np.arange(len(profile))
    return np.interp(depth, grid, profile, left=profile[0], right=0.0)


def _pen_width(profile: np.ndarray) -> float:
    """Width of a pen: the depth its coverage falls through 1/2 (the rim pixel counting 1)."""
    grid = 1 + _STEP * np.arange(len(profile))
    below = np.flatnonzero(profile < 0.5)
    if not len(below):
        return float(grid[-1] + 0.5)
    k = below[0]
    if k == 0:
        return 0.5
    # linear between the last bin at or above 1/2 and the first below it
    t = (profile[k - 1] - 0.5) / max(profile[k - 1] - profile[k], 1e-9)
    return float(grid[k - 1] + t * _STEP + 0.5)


def _pen_outline(image: np.ndarray, ink, width: int, profile: np.ndarray, pen: float | None = None,
                 dark_fills: bool = True) -> np.ndarray:
    """A mix's outline in the sources' pen: the warped stroke deeper than ``width`` goes
    (:func:`~branchnb.trees.outline._drop_excess`), then :func:`_draw_pen` with ``profile``
    shifted to the pen width ``pen`` (default: the profile's own). ``dark_fills``: whether the
    sources have dark fills to keep (:func:`~branchnb.trees.outline._has_dark_fill`)."""
    from .outline import _depth, _drop_excess, _inner_shapes

    img = np.array(image, dtype=np.float32, copy=True)
    alpha = img[..., 3] >= 0.5
    if alpha.sum() < 9 or alpha.all():
        return img
    # inner shapes (fruits) before the stroke is thinned, as even_outline finds them
    ink_lum = float(np.asarray(ink, np.float32) @ _LUM)
    lum = img[..., :3] @ _LUM
    inner, _ = _inner_shapes(alpha & (lum > ink_lum + 0.5 * (np.median(lum[alpha]) - ink_lum)), _depth(alpha), width)
    img = _drop_excess(img, np.asarray(ink, np.float64), width, dark_fills=dark_fills)
    shift = 0.0 if pen is None else pen - _pen_width(profile)
    return _draw_pen(img, ink, profile, shift=shift, inner=inner, inner_depth=int(1.75 * width))


def _draw_pen(image: np.ndarray, ink, profile: np.ndarray, *, shift: float = 0.0, ink_tol: float = 0.3,
              holes: bool = True, inner: np.ndarray | None = None, inner_depth: float = 0.0) -> np.ndarray:
    """Repaint a silhouette's outline band with the pen ``profile`` (a copy; alpha unchanged).

    Every opaque pixel at Euclidean depth ``d`` where the profile is above 0 becomes
    ``c(d - shift) ink + (1 - c(d - shift)) fill`` (``shift``: how much wider the pen is drawn).
    ``fill`` is the colour of the nearest pixel beyond the band, the ink the colour of the
    darkest band pixel near by within ``ink_tol`` of ``ink`` (dark green round a crown, dark
    brown round a trunk, as drawn), else ``ink``. Pixels of ``inner`` shapes (a fruit the warp
    moved onto the rim) are ink to ``inner_depth``: the drawings keep the fruit's ring and the
    outline between its fill and the edge (even_outline inks them to 1.75 ``width`` too).
    """
    img = np.array(image, dtype=np.float32, copy=True)
    alpha = img[..., 3] >= 0.5
    if alpha.sum() < 9 or alpha.all():
        return img
    a = alpha if holes else ndi.binary_fill_holes(alpha)
    depth = _depth_edt(a)
    reach = 1 + _STEP * np.flatnonzero(profile > 0).max() + shift if (profile > 0).any() else 0.0
    if reach <= 0:
        return img
    # chessboard depth, as the ring is kept round a fruit in the drawings (and in even_outline)
    deep_pen = np.zeros_like(alpha) if inner is None else inner & (_chessboard(a) <= inner_depth)
    band = alpha & ((depth <= reach + 0.5 * _STEP) | deep_pen)
    beyond = alpha & ~band
    if not beyond.any():
        return img
    ink = np.asarray(ink, np.float32)
    ys, xs = np.nonzero(band)
    idx = ndi.distance_transform_edt(~beyond, return_distances=False, return_indices=True)
    fill = img[idx[0][ys, xs], idx[1][ys, xs], :3]
    lum = img[..., :3] @ _LUM
    ink_lum = float(ink @ _LUM)
    strong = lum <= ink_lum + 0.35 * (np.median(lum[alpha]) - ink_lum)
    own = band & strong & (np.linalg.norm(img[..., :3] - ink, axis=2) <= ink_tol)
    col = np.broadcast_to(ink, fill.shape).copy()
    if own.any():
        # the darkest ink-coloured pixel near by: a warped thin stroke's anti-aliased pixels
        # are ink-coloured too, but lighter; the nearest of them greyed the new pen
        r = int(np.ceil(2 * reach + 1))
        h, w = alpha.shape
        none = np.int64(2) ** 52        # exact as a float (the filter's border value)
        key = np.where(own, np.round(np.clip(lum, 0, 1) * 4095).astype(np.int64) * (h * w)
                       + np.arange(h * w).reshape(h, w), none)
        best = ndi.minimum_filter(key, size=2 * r + 1, mode="nearest")[ys, xs]
        by = best < none
        flat = best[by] % (h * w)
        col[by] = img[flat // w, flat % w, :3]
    c = _profile_at(profile, np.maximum(depth[ys, xs] - shift, 1.0))
    c[deep_pen[ys, xs]] = 1.0
    c = c[:, None].astype(np.float32)
    img[ys, xs, :3] = c * col + (1 - c) * fill
    # light as against the pen as drawn (its rim), the colour a reader of the mix takes for ink
    rim_lum = float(np.median(img[alpha & (depth < 1.5), :3] @ _LUM))
    return _close_flecks(img, alpha, depth, min(ink_lum, rim_lum), 2 * reach + 2)


def _close_flecks(img: np.ndarray, alpha: np.ndarray, depth: np.ndarray, ink_lum: float, near: float) -> np.ndarray:
    """Flecks of fill left between the new pen and a dark stroke beyond it (within ``near`` of
    the silhouette) take the colour of the darkest pixel next to them (in place).

    :func:`~branchnb.trees.outline._drop_excess` gives the fill's colour to a warped stroke
    only next to a fill; where a thick dark stretch stays beyond it, a strip of that fill is
    cut off between the pen and the dark: light specks in a dark stroke, which no drawing has.
    """
    lum = img[..., :3] @ _LUM
    light = alpha & (lum > ink_lum + 0.5 * (np.median(lum[alpha]) - ink_lum))
    lab, n = ndi.label(light, np.ones((3, 3), bool))
    if n < 2:
        return img
    area = np.bincount(lab.ravel(), minlength=n + 1)
    small = area <= max(2.0, 4e-4 * alpha.sum())
    small[0] = False
    fleck = small[lab] & (depth <= near)
    if not fleck.any():
        return img
    h, w = alpha.shape
    none = np.int64(2) ** 52
    key = np.where(alpha & ~light, np.round(np.clip(lum, 0, 1) * 4095).astype(np.int64) * (h * w)
                   + np.arange(h * w).reshape(h, w), none)
    best = ndi.minimum_filter(key, size=5, mode="nearest")[fleck]
    ok = best < none
    fy, fx = np.nonzero(fleck)
    flat = best[ok] % (h * w)
    img[fy[ok], fx[ok], :3] = img[flat // w, flat % w, :3]
    return img

