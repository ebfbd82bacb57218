"""Colour transfer of flat (drawn) sources: strokes kept whole, stretched fills kept flat (beyond the paper).

Part of :func:`~branchnb.trees.mvc.transfer_colour` in its ``"choose"`` and
``"parts"`` modes (moved here from :mod:`~branchnb.trees.mvc`, issue 24). What
depends on a source alone (its ink, its pure fills, the fill under each
anti-aliased pixel, the ink coverage and the maps sampled from it) is
computed once per source by :class:`_StrokeMaps` and can be kept with the
source (``TreeLibrary`` keeps it on each exemplar): a variation then only
samples those maps through its warp. The results are the same bit for bit
whether the maps are kept or made afresh.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..core.image import extend_nearest

#: Flat-art sampling: a target pixel shows a source's ink (its thin dark strokes) when the ink
#: covers at least this share of a bilinear sample at one of four points of the pixel's footprint.
STROKE_COVER = 0.6

#: Flat-art sampling: from this local stretch of the warp (target pixels per source pixel along
#: the most stretched direction) fills are sampled more and more from pure fill pixels only, fully
#: from :data:`STRETCH_FULL` (between them a linear mix of both samples). An anti-aliased pixel
#: stretched by 1.1 stays about one target pixel wide: no smear to remove, and the identity warp
#: (stretch 1) keeps every source pixel exactly.
STRETCH_START = 1.1
STRETCH_FULL = 1.3

#: Kept maps are cropped to the box of their non-zero pixels grown by this many pixels (a
#: bilinear sample reads a 2 x 2 neighbourhood, so anything farther out reads zeros either way).
_MARGIN = 3


class _Crop:
    """A premultiplied RGBA map cropped to the box of its non-zero pixels (zeros outside it),
    sampled bilinearly exactly as the whole map would be (:func:`_remap`)."""

    __slots__ = ("img", "x0", "y0")

    def __init__(self, img: np.ndarray, nonzero: np.ndarray):
        ys, xs = np.nonzero(nonzero)
        if len(ys) == 0:
            self.img, self.x0, self.y0 = img[:1, :1] * 0, 0, 0
            return
        h, w = nonzero.shape
        y0, x0 = max(int(ys.min()) - _MARGIN, 0), max(int(xs.min()) - _MARGIN, 0)
        y1, x1 = min(int(ys.max()) + _MARGIN + 1, h), min(int(xs.max()) + _MARGIN + 1, w)
        self.img = np.ascontiguousarray(img[y0:y1, x0:x1], dtype=np.float32)
        self.x0, self.y0 = x0, y0

    @property
    def nbytes(self) -> int:
        return int(self.img.nbytes)

    def sample(self, points: np.ndarray) -> np.ndarray:
        return _remap(self.img, points, self.x0, self.y0)


def _remap(img: np.ndarray, p: np.ndarray, x0: int = 0, y0: int = 0) -> np.ndarray:
    """Bilinear samples of a float32 (H, W, 4) map at points (x, y), zero outside; the map's
    pixel (0, 0) lies at (x0, y0). The body of :func:`~branchnb.trees.mvc.sample_rgba` without
    the input checks (the maps here are made by this module)."""
    n = len(p)
    if n == 0:
        return np.zeros((0, 4), np.float32)
    # OpenCV maps must be smaller than SHRT_MAX in both directions: lay the points out as rows of
    # 1024. The offset is taken off in float32 after the rounding to float32 (exact: a point
    # whose shifted coordinate would round differently lies more than a pixel outside the map,
    # where both read zeros), so a cropped map samples exactly like the whole one.
    width = 1024
    rows = -(-n // width)
    mx = np.full(rows * width, -2.0, np.float32)
    my = np.full(rows * width, -2.0, np.float32)
    mx[:n], my[:n] = p[:, 0], p[:, 1]
    if x0:
        mx[:n] -= np.float32(x0)
    if y0:
        my[:n] -= np.float32(y0)
    mx, my = mx.reshape(rows, width), my.reshape(rows, width)
    out = np.empty((rows * width, 4), np.float32)
    step = 16384
    for k in range(0, rows, step):
        out[k * width:(k + step) * width] = cv2.remap(
            img, mx[k:k + step], my[k:k + step], cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_CONSTANT, borderValue=(0, 0, 0, 0)).reshape(-1, 4)
    return out[:n]


def _rgb_at(src: np.ndarray, flat: np.ndarray) -> np.ndarray:
    """Straight RGB of a premultiplied source at flat pixel indices (as ``src / a`` computes it)."""
    s = src.reshape(-1, 4)[flat]
    return s[:, :3] / np.maximum(s[:, 3], 1e-6)[:, None]


class _StrokeMaps:
    """What the flat-art sampling of one source derives from the source alone (not the warp).

    Made once per source and reused by every variation that samples it
    (:func:`_sample_strokes`); the stretched-fill maps (:meth:`hard`) only
    when a warp first stretches the source. Colours are kept as flat
    indices of source pixels (the ink colour and fill colour of every
    pixel are copies of some pixel's), so the kept maps take about 60-70
    MB for a 1024 x 1024 source. ``key`` is the object the maps were made
    from (a caller checks it is still the same source).
    """

    def __init__(self, src: np.ndarray, key=None):
        from .outline import _ink_threshold, _is_ink

        self.key = key
        self.shape = src.shape[:2]
        a = src[..., 3]
        op = a >= 0.5
        self.few = bool(op.sum() < 9)
        self.has_ink = False
        self._hard = False            # not made yet (None: made, no pure fill)
        if self.few:
            return
        rgb = src[..., :3] / np.maximum(a, 1e-6)[..., None]
        ink = _is_ink(rgb, _ink_threshold(rgb, op)) & op
        self.has_ink = bool(ink.any())
        if not self.has_ink:
            return
        self.op, self.ink = op, ink
        inkf = ink.astype(np.float32)
        self.inkimg = _Crop(np.concatenate([rgb * inkf[..., None], inkf[..., None]], axis=2), ink)
        fill = a * (1.0 - inkf)
        self.fillimg = _Crop(np.concatenate([rgb * fill[..., None], fill[..., None]], axis=2), fill != 0)

    @property
    def nbytes(self) -> int:
        """Memory the kept maps take."""
        if not self.has_ink:
            return 0
        n = self.op.nbytes + self.ink.nbytes + self.inkimg.nbytes + self.fillimg.nbytes
        if self._hard:
            n += sum(v.nbytes for v in self._hard.values())
        return int(n)

    def hard(self, src: np.ndarray):
        """The maps of :func:`_stretched_sample` (made on first use), None where the source has no
        pure fill pixel: ``packed`` (coverage gradient, coverage, peak), ``pimg`` (fill weighted
        by how much of each pixel it covers), ``inkidx`` (each pixel's ink colour) and ``nearidx``
        (the fill of the nearest pixel that has one), the last two as flat source indices."""
        if self._hard is False:
            self._hard = _hard_maps(src, self.op, self.ink)
        return self._hard


def _footprint(mapped: np.ndarray, ys: np.ndarray, xs: np.ndarray, shape) -> tuple[np.ndarray, np.ndarray]:
    """Where a target pixel's right and lower neighbours map, relative to it (the warp's Jacobian
    columns, by differences of neighbouring mapped pixels; backward differences on the mask's edge,
    a unit step for a pixel without neighbours). Gathered through an index grid over the mask's
    bounding box (``shape`` is the whole target's)."""
    if len(ys) == 0:
        return np.zeros((0, 2)), np.zeros((0, 2))
    r0, c0 = int(ys.min()), int(xs.min())
    h, w = int(ys.max()) - r0 + 1, int(xs.max()) - c0 + 1
    yy, xx = ys - r0, xs - c0
    grid = np.full((h + 2, w + 2), -1, np.int64)        # a frame of "no pixel" round the box
    grid[yy + 1, xx + 1] = np.arange(len(ys))
    out = []
    for dy, dx in ((0, 1), (1, 0)):
        nxt = grid[yy + 1 + dy, xx + 1 + dx]
        prv = grid[yy + 1 - dy, xx + 1 - dx]
        d = np.where((nxt >= 0)[:, None], mapped[nxt] - mapped, mapped - mapped[prv])
        d[(nxt < 0) & (prv < 0)] = (dx, dy)
        out.append(d)
    return out[0], out[1]


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
    """Every pixel given the darkest ink pixel in the 3 x 3 neighbourhood of its nearest ink
    pixel (as a flat pixel index): a stroke's own colour, not that of the lighter ink at its
    anti-aliased rim."""
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
    return extend_nearest(oy * w + ox, ink)


def _unmixed_fill(rgb: np.ndarray, pure: np.ndarray, soft: np.ndarray, inkcol: np.ndarray,
                  radius: int = 5, tol: float = 0.12) -> np.ndarray:
    """Fill colours under the ``soft`` (anti-aliased) pixels, as a flat index of the pixel that
    gives each pixel its fill: of the pure fill pixels within ``radius`` (Chebyshev), the one
    whose mix with the ink (``inkcol``, per pixel) passes nearest the soft pixel's colour, if
    within ``tol`` (RGB); else the pixel itself (a fill of its own). The nearest pure pixel is
    often the wrong fill: between a crown's outline and a fruit's ring it is the fruit's, and a
    stretch then paints the gap orange."""
    h, w = pure.shape
    out = np.arange(h * w).reshape(h, w)
    ys, xs = np.nonzero(soft)
    if len(ys) == 0:
        return out
    c = rgb[ys, xs]
    k = inkcol[ys, xs]
    best = np.full(len(ys), tol)
    at = ys * w + xs
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
            at[better] = (qy * w + qx)[better]
    out[ys, xs] = at
    return out


def _hard_maps(src: np.ndarray, op: np.ndarray, ink: np.ndarray):
    """The per-source maps :func:`_stretched_sample` samples (see :meth:`_StrokeMaps.hard`)."""
    rgb = src[..., :3] / np.maximum(src[..., 3], 1e-6)[..., None]
    pure = _pure_fill(rgb, op, ink)
    if not pure.any():
        return None
    h, w = op.shape
    flat_rgb = rgb.reshape(-1, 3)
    inkidx = _darkest_ink(rgb, ink)
    inkcol = flat_rgb[inkidx].reshape(rgb.shape)
    # the fill under each pixel, and how much of the pixel the ink covers: where its colour lies on
    # the way from that fill to the ink
    # (a faint ink pixel, a thin line's anti-aliased half or a dark red between a fruit and its
    # ring, covers only part of its pixel: taken as all ink it thickened the line when stretched)
    fidx = _unmixed_fill(rgb, pure, op & ~pure, inkcol)
    fcol = flat_rgb[fidx].reshape(rgb.shape)
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
    packed = np.clip(np.stack([0.5 + gx, 0.5 + gy, cov, peak], axis=2).astype(np.float32), 0.0, 1.0)
    # the fill weighted by how much of each pixel it covers (none on ink)
    wgt = (op * (1.0 - cov)).astype(np.float32)
    pimg = _Crop(np.concatenate([fcol * wgt[..., None], wgt[..., None]], axis=2), wgt != 0)
    # deep in a stroke, the fill of the nearest pixel that has one
    nearidx = extend_nearest(fidx, wgt > 1e-3)
    return {"packed": packed, "pimg": pimg, "inkidx": inkidx.astype(np.int32),
            "nearidx": nearidx.astype(np.int32)}


def _stretched_sample(src: np.ndarray, maps: _StrokeMaps, pts: np.ndarray, jx: np.ndarray, jy: np.ndarray):
    """Colours of a flat source at ``pts`` where the warp (Jacobian columns ``jx``, ``jy``)
    stretches it: ink over a pure fill colour (:func:`_pure_fill`) with an ink coverage
    anti-aliased at the target's resolution, never a stretched blend of the two.

    The ink coverage is 1 on ink, 0 on pure fill, and on the anti-aliased pixels between them how
    far their colour lies from their fill's (:func:`_unmixed_fill`) towards the ink's. Sampled
    bilinearly, it ramps across the stretched edge over several target pixels; it is steepened
    about 1/2 (where the drawing's own coverage crosses 1/2, so a stroke keeps its width) to a
    ramp of one target pixel. The ink colour is the stroke's darkest nearby pixel, the fill
    colour a bilinear sample of pure pixels only. None where the source has no pure fill pixel.
    The maps come from ``maps`` (made once per source); only the sampling runs here."""
    hm = maps.hard(src)
    if hm is None:
        return None
    g = _remap(hm["packed"], pts)
    gs = g[:, :2] - 0.5
    c = g[:, 2]
    top = np.maximum(g[:, 3], 1e-3)
    # the coverage's slope per target pixel (chain rule through the warp), steepened to 1
    slope = np.hypot((gs * jx).sum(axis=1), (gs * jy).sum(axis=1)) / top
    k = np.clip(1.0 / np.maximum(slope, 1e-3), 1.0, 8.0)
    cs = (top * np.clip(0.5 + (c / top - 0.5) * k, 0.0, 1.0))[:, None]
    p = hm["pimg"].sample(pts)
    h, w = maps.shape
    px = np.clip(np.rint(pts[:, 0]), 0, w - 1).astype(np.int64)
    py = np.clip(np.rint(pts[:, 1]), 0, h - 1).astype(np.int64)
    at = py * w + px
    fill = np.where(p[:, 3:] > 1e-3, p[:, :3] / np.maximum(p[:, 3:], 1e-6),
                    _rgb_at(src, hm["nearidx"].ravel()[at]))
    return cs * _rgb_at(src, hm["inkidx"].ravel()[at]) + (1.0 - cs) * fill


def _sample_strokes(src: np.ndarray, mapped: np.ndarray, smp: np.ndarray, ys, xs, shape,
                    maps: _StrokeMaps | None = None) -> np.ndarray:
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

    ``maps`` are the source's :class:`_StrokeMaps` when the caller keeps them (None: made here).
    """
    m = maps if maps is not None else _StrokeMaps(src)
    base = smp[:, :3] / np.maximum(smp[:, 3], 1e-6)[:, None]
    if m.few or not m.has_ink:
        return base
    jx, jy = _footprint(mapped, ys, xs, shape)
    best = np.zeros((len(mapped), 4), np.float32)
    at = mapped.copy()
    for sx in (-0.25, 0.25):
        for sy in (-0.25, 0.25):
            q = mapped + sx * jx + sy * jy
            s = m.inkimg.sample(q)
            better = s[:, 3] > best[:, 3]
            best[better] = s[better]
            at[better] = q[better]
    f = m.fillimg.sample(mapped)
    out = np.where(f[:, 3:] > 1e-3, f[:, :3] / np.maximum(f[:, 3:], 1e-6), base)
    stroke = best[:, 3] >= STROKE_COVER
    out[stroke] = best[stroke, :3] / best[stroke, 3:]
    # The ink colour of the nearest ink pixel, not a mean of two inks (an outline and a dark fill).
    h, w = m.shape
    px = np.clip(np.rint(at[:, 0]), 0, w - 1).astype(np.int64)
    py = np.clip(np.rint(at[:, 1]), 0, h - 1).astype(np.int64)
    own = stroke & m.ink[py, px]
    out[own] = _rgb_at(src, py[own] * w + px[own])
    t = np.clip((_stretch(jx, jy) - STRETCH_START) / (STRETCH_FULL - STRETCH_START), 0.0, 1.0)
    if (t > 0).any():
        k = np.flatnonzero(t > 0)
        hard = _stretched_sample(src, m, mapped[k], jx[k], jy[k])
        if hard is not None:
            out[k] = (1.0 - t[k, None]) * out[k] + t[k, None] * hard
    return out.astype(np.float32)
