"""Random warps, the shape blend and resampling (steps 1-3 of :mod:`branchnb.leaves.synthesis`).

:func:`random_warp` moves the background and each layer by a smooth random
field; :func:`shape_weights` gives the per-pixel convex weights ``a_i(x)``
of the blend of inverse registration warps. The private helpers compose
and resample the coordinate maps (every image of a new leaf is resampled
once) and fit the new leaf's size on the canvas.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..core.random import as_rng

__all__ = ["random_warp", "shape_weights"]


def random_warp(shape, amplitude: float, correlation: float, rng) -> np.ndarray:
    """A smooth random displacement field (H, W, 2) whose largest displacement is ``amplitude`` px.

    Random vectors on a grid of spacing ``correlation`` px, interpolated
    bicubically.

    Parameters
    ----------
    shape : (int, int)
        ``(H, W)`` of the field.
    amplitude : float
        Largest displacement length in pixels, ``>= 0`` (0: no warp).
    correlation : float
        Grid spacing of the random vectors in pixels, ``> 0``: the length
        over which displacements are alike.
    rng : {numpy.random.Generator, int}
        Draws the random vectors.

    Returns
    -------
    (H, W, 2) float32 ndarray
        Displacement ``(dx, dy)`` per pixel.

    Examples
    --------
    >>> d = random_warp((40, 50), 2.0, 20.0, 0)
    >>> d.shape, round(float(np.hypot(d[..., 0], d[..., 1]).max()), 3)
    ((40, 50, 2), 2.0)
    """
    rng = as_rng(rng)
    h, w = int(shape[0]), int(shape[1])
    if not (np.isfinite(amplitude) and amplitude >= 0):
        raise ValueError(f"amplitude must be finite and >= 0, got {amplitude}")
    if not (np.isfinite(correlation) and correlation > 0):
        raise ValueError(f"correlation must be > 0, got {correlation}")
    gh = max(2, int(np.ceil(h / correlation)) + 1)
    gw = max(2, int(np.ceil(w / correlation)) + 1)
    coarse = rng.standard_normal((gh, gw, 2)).astype(np.float32)
    d = cv2.resize(coarse, (w, h), interpolation=cv2.INTER_CUBIC)
    m = float(np.hypot(d[..., 0], d[..., 1]).max())
    if amplitude == 0 or m == 0:
        return np.zeros((h, w, 2), np.float32)
    d *= np.float32(amplitude / m)  # in place: the same float32 products, no whole-canvas copy
    return d

def shape_weights(shape, n: int, grid: int, sigma_px: float, rng, concentration: float = 0.3,
                  spread: float = 0.75) -> np.ndarray:
    """Per-pixel convex weights ``a_i(x)`` (n, H, W): random coefficients, blurred, normalised.

    One draw per leaf decides which exemplars its shape comes from: global
    weights ``g ~ Dirichlet(concentration)`` (small concentration: one or
    two exemplars dominate). Each of the ``grid`` x ``grid`` cells then
    multiplies them by its own Gamma noise of mean 1 and coefficient of
    variation ``spread`` (so the weights vary smoothly over the leaf), and
    the coefficients are blurred by a Gaussian of ``sigma_px`` and
    normalised per pixel.

    Going beyond the paper: a Dirichlet drawn independently per cell (as a
    literal reading of "random convex weights per pixel" suggests), once
    blurred, averages nearly evenly over all exemplars at every pixel, so
    every new leaf came out close to the mean shape (median pairwise
    blade IoU 0.86 among new maples against the exemplars' 0.63).

    Parameters
    ----------
    shape : (int, int)
        ``(H, W)`` of the fields.
    n : int
        Number of exemplars.
    grid : int
        Random coefficients per side.
    sigma_px : float
        Blur of the coefficients (px).
    rng : {numpy.random.Generator, int}
        Draws the per-leaf weights and the per-cell factors.
    concentration : float
        Symmetric Dirichlet concentration of the per-leaf weights.
    spread : float
        Coefficient of variation of the per-cell factors (0: the same
        weights everywhere).

    Returns
    -------
    (n, H, W) float32 ndarray
        Non-negative, summing to 1 at every pixel.

    Examples
    --------
    >>> a = shape_weights((30, 30), 3, 2, 5.0, 0)
    >>> a.shape, bool(np.allclose(a.sum(0), 1)), bool(a.min() >= 0)
    ((3, 30, 30), True, True)
    """
    rng = as_rng(rng)
    h, w = int(shape[0]), int(shape[1])
    if not (np.isfinite(concentration) and concentration > 0):
        raise ValueError(f"concentration must be > 0, got {concentration}")
    if not (np.isfinite(spread) and spread >= 0):
        raise ValueError(f"spread must be >= 0, got {spread}")
    g = rng.dirichlet(np.full(n, float(concentration)))
    g = np.maximum(np.nan_to_num(g, nan=0.0), 0.0)
    if g.sum() <= 0:  # a degenerate draw (all alphas tiny): one exemplar
        g = np.eye(n)[int(rng.integers(n))]
    g = g / g.sum()
    if spread > 1e-6:  # below, the gamma noise is 1 to float precision (and spread ** 2 underflows)
        k = 1.0 / float(spread) ** 2
        noise = rng.gamma(k, 1.0 / k, size=(grid, grid, n))
    else:
        noise = np.ones((grid, grid, n))
    coeff = (g * noise).astype(np.float32)  # (g, g, n)
    coeff /= np.maximum(coeff.sum(-1, keepdims=True), 1e-12)
    # The fields are smooth: blur on a reduced grid, then interpolate up.
    f = max(1, int(sigma_px // 4))
    hs, ws = max(2, int(np.ceil(h / f))), max(2, int(np.ceil(w / f)))
    out = np.empty((n, h, w), np.float32)
    for i in range(n):
        c = cv2.resize(coeff[..., i], (ws, hs), interpolation=cv2.INTER_LINEAR)
        c = cv2.GaussianBlur(c, (0, 0), max(float(sigma_px) / f, 0.5), borderType=cv2.BORDER_REFLECT)
        out[i] = cv2.resize(c, (w, h), interpolation=cv2.INTER_LINEAR)
    out = np.maximum(out, 0)
    out /= np.maximum(out.sum(0, keepdims=True), 1e-12)
    return out

def _grid(shape):
    h, w = shape
    xx, yy = np.meshgrid(np.arange(w, dtype=np.float32), np.arange(h, dtype=np.float32))
    return xx, yy

def _affine_grid(shape, lin, centre) -> np.ndarray:
    """``(y - centre) @ lin.T + centre`` for every pixel ``y`` (x, y) of ``shape``, as float32 (H, W, 2).

    Row and column terms apart (float64, then one add per pixel): the whole-canvas float64 stack
    and matrix product were a tenth of a new leaf's time at 1 MP.
    """
    h, w = int(shape[0]), int(shape[1])
    lin = np.asarray(lin, np.float64)
    centre = np.asarray(centre, np.float64)
    cols = (np.arange(w, dtype=np.float64) - centre[0])[:, None] * lin[:, 0]  # (W, 2): x's part
    rows = (np.arange(h, dtype=np.float64) - centre[1])[:, None] * lin[:, 1] + centre  # (H, 2)
    return (cols[None] + rows[:, None]).astype(np.float32)


def _map_jacobian(field: np.ndarray, point) -> np.ndarray:
    """2 x 2 Jacobian of a dense coordinate map ``field`` (H, W, 2) at ``point`` (x, y), by central differences."""
    h, w = field.shape[:2]
    x, y = float(point[0]), float(point[1])
    step = 3.0
    pts = np.array([[x + step, y], [x - step, y], [x, y + step], [x, y - step]], np.float32)
    pts[:, 0] = np.clip(pts[:, 0], 0, w - 1)
    pts[:, 1] = np.clip(pts[:, 1], 0, h - 1)
    v = _remap_values(field, pts[None])[0]
    dx = (v[0] - v[1]) / max(float(pts[0, 0] - pts[1, 0]), 1e-6)
    dy = (v[2] - v[3]) / max(float(pts[2, 1] - pts[3, 1]), 1e-6)
    return np.column_stack([dx, dy]).astype(np.float64)


def _linear_part(field: np.ndarray) -> np.ndarray:
    """The 2 x 2 linear part of the least-squares affine fit of a coordinate map (H, W, 2)."""
    h, w = field.shape[:2]
    step = max(1, int(np.sqrt(h * w / 4096)))
    ys, xs = np.mgrid[0:h:step, 0:w:step]
    src = np.column_stack([xs.ravel(), ys.ravel(), np.ones(xs.size)]).astype(np.float64)
    dst = field[::step, ::step].reshape(-1, 2).astype(np.float64)
    coef, *_ = np.linalg.lstsq(src, dst, rcond=None)
    return coef[:2].T


def _remap_map(field, c):
    """A coordinate map resampled at ``c``, continued past the canvas by its affine fit.

    Off the canvas the map is its edge value plus the fit's linear part
    times the step beyond the edge, so far points keep going away (the
    replicated edge value drew straight streaks from a leaf to the canvas
    edge). A sentinel "off" value instead was blended into other maps with
    a small weight, and bilinearly into its neighbours, giving finite
    coordinates that landed on the lamina: stray fragments of leaf far
    from the new one.
    """
    h, w = field.shape[:2]
    c = np.asarray(c, np.float32)
    inside = np.empty_like(c)
    inside[..., 0] = np.clip(c[..., 0], 0, w - 1)
    inside[..., 1] = np.clip(c[..., 1], 0, h - 1)
    out = _remap_values(field, inside)
    beyond = c - inside
    off = (beyond != 0).any(-1)
    if off.any():
        # Only the pixels past the edge (0 elsewhere: out + 0 is out), not a whole-canvas product.
        out[off] += beyond[off] @ _linear_part(field).T.astype(np.float32)
    return out.astype(np.float32, copy=False)


def _remap_values(field, c):
    """Bilinear samples of any float field (coordinates, displacements) at ``c``; edges replicated."""
    # One (H, W, 2) map: OpenCV reads it as the two split maps, with the same result, and
    # no copies of the x and y planes are made.
    out = cv2.remap(np.ascontiguousarray(field, np.float32), np.ascontiguousarray(c, np.float32), None,
                    cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    return out


def _sample(img, c):
    """Bilinear samples (H, W, C) of an internal float image at ``c``, edges replicated.

    :func:`branchnb.core.warp.remap` without its input checks (the maps and
    images here are the package's own float32 arrays): the checks were a
    tenth of a new leaf's time at 1 MP.
    """
    img = np.ascontiguousarray(img, np.float32)
    out = cv2.remap(img, np.ascontiguousarray(c, np.float32), None, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    return out[..., None] if out.ndim == 2 else out


def _sample_sharp(img, c):
    """Colours sampled bicubically (clipped to [0, 1]).

    Bilinear resampling at fractional offsets averages neighbours: a new
    leaf came out with half its exemplars' high-frequency energy
    (Laplacian variance inside the blade 0.49 of theirs on a 384 px
    procedural family). Bicubic keeps veins and texture crisp.
    """
    img = np.ascontiguousarray(img, np.float32)
    out = cv2.remap(img, np.ascontiguousarray(c, np.float32), None, cv2.INTER_LANCZOS4,
                    borderMode=cv2.BORDER_REPLICATE)
    if out.ndim == 2:
        out = out[..., None]
    return np.clip(out, 0.0, 1.0)


def _picks(c, where):
    """The flat indices of ``where`` and the coordinates ``c`` there, as two float32 vectors."""
    idx = np.flatnonzero(where)
    c = np.asarray(c, np.float32)
    return idx, c[..., 0].reshape(-1)[idx], c[..., 1].reshape(-1)[idx]


def _picked(img, px, py, interpolation):
    """``img`` remapped at the coordinates ``(px, py)`` (vectors) only, as (n, C) values (no clipping)."""
    ch = img.shape[2] if img.ndim == 3 else 1
    n = px.size
    # The picked coordinates as a (rows, 1024) map (OpenCV maps are < 32767 on a side), padded.
    rows = -(-n // 1024)
    maps = []
    for v0 in (px, py):
        v = np.zeros(rows * 1024, np.float32)
        v[:n] = v0
        maps.append(v.reshape(rows, 1024))
    vals = cv2.remap(img, maps[0], maps[1], interpolation, borderMode=cv2.BORDER_REPLICATE)
    return vals.reshape(-1, ch)[:n]


def _source_box(img, px, py, margin: int):
    """``img`` cut to the box of the coordinates ``(px, py)`` plus ``margin`` px, and the box's (x0, y0).

    The box's corner is a whole pixel, so ``px - x0`` is exact in float32 and a remap of the box at
    the shifted coordinates reads the same pixels with the same weights; a box side that reaches
    the image's edge keeps it (the replicated border is the same). ``(img, None)`` when the box is
    the whole image.
    """
    h, w = img.shape[:2]
    if not (np.isfinite(px).all() and np.isfinite(py).all()):
        return img, None
    x0 = max(0, int(np.floor(max(float(px.min()), -1.0))) - margin)
    y0 = max(0, int(np.floor(max(float(py.min()), -1.0))) - margin)
    x1 = min(w, int(np.ceil(min(float(px.max()), float(w)))) + margin + 1)
    y1 = min(h, int(np.ceil(min(float(py.max()), float(h)))) + margin + 1)
    if x0 >= x1 or y0 >= y1 or (x0 == 0 and y0 == 0 and x1 == w and y1 == h):
        return img, None
    return img[y0:y1, x0:x1], (np.float32(x0), np.float32(y0))


def _sample_sharp_at(img, c, where):
    """:func:`_sample_sharp` at the pixels of ``where`` only (0 elsewhere).

    The same values where computed (remapping is per pixel), at the cost
    of the pixels that are used: the blade, a layer's footprint. Lanczos
    resampling of every channel over the whole canvas was half the time of
    a new leaf at a megapixel.
    """
    ch = img.shape[2] if img.ndim == 3 else 1
    out = np.zeros(where.shape + (ch,), np.float32)
    if not where.any():
        return out
    idx, px, py = _picks(c, where)
    img, off = _source_box(img, px, py, _LANCZOS_REACH)  # the same samples (see _sample_grain_at)
    if off is not None:
        px, py = px - off[0], py - off[1]
    img = np.ascontiguousarray(img, np.float32)
    out.reshape(-1, ch)[idx] = np.clip(_picked(img, px, py, cv2.INTER_LANCZOS4), 0.0, 1.0)
    return out


#: Pixels a Lanczos-4 sample reads on either side of its coordinate (and a margin).
_LANCZOS_REACH = 5


#: Sub-samples per side of an output pixel when a hairline is drawn anew (:func:`_sample_line_at`).
_LINE_SUPERSAMPLE = 4

#: Contrast (RGB distance to the leaf under the line) below which a pixel is not ink (:func:`_sample_line_at`).
_LINE_MIN_CONTRAST = 0.05

#: Percentile of the lines' peak contrasts taken as the ink's full contrast (:func:`_sample_line_at`).
_LINE_FULL_PERCENTILE = 90.0


def _sample_line_at(img, under, c, where, ss: int = _LINE_SUPERSAMPLE):
    """Colours of a layer of 1-2 px ink lines at ``c`` on ``where``: each line drawn anew, not resampled.

    ``img`` is the layer's stage image, ``under`` the same leaf without
    the lines (the two differ by the ink alone). The line's profile
    ``q = |img - under|`` is interpolated bicubically at ``ss`` x ``ss``
    points of each output pixel (their source coordinates from the map's
    local Jacobian); a point lies on the line where ``q`` is above half
    its local peak (the 3 x 3 maximum: the line's full width at half
    maximum, whatever its phase on the pixel grid), and the pixel's
    coverage is the share of its points on the line. The pixel is
    ``under`` (resampled smoothly) plus that coverage times the ink's
    contrast at the line's peak pixel. The warp moves a line; it need not
    resample its pixels.

    Going beyond the paper (which leaves the resampling open): every
    interpolation at a fractional offset filters an anti-aliased 1-px line
    a second time. Drawn maples and elms with 1-2 px black veins
    (``python -m branchnb.leaves._measure_unseen --kinds
    maple-black-1,maple-black-2,elm-black-2 --sizes 256,400 --seeds 0,1``)
    had 0.72-0.93 of their exemplars' Laplacian variance inside the blade
    with Lanczos (maple-black-1: 0.72-0.79), 0.88-1.00 drawn anew (maple-
    black-1); nearest neighbour kept it but beaded the lines. Straight
    1-2 px box-filtered lines turned by 0-23 degrees and shifted by a
    fraction of a pixel (``tests/test_leaves_line_redraw.py``): Laplacian
    variance 0.90 -> 1.01 of the same lines drawn at their new place,
    mean absolute error to them 0.016 -> 0.0066.
    """
    ch = img.shape[2] if img.ndim == 3 else 1
    out = np.zeros(where.shape + (ch,), np.float32)
    if not where.any():
        return out
    c = np.asarray(c, np.float32)
    idx, px, py = _picks(c, where)
    # The map's local Jacobian (per output pixel step in x and in y) places the sub-samples.
    gx = np.gradient(c, axis=1).reshape(-1, 2)[idx]
    gy = np.gradient(c, axis=0).reshape(-1, 2)[idx]
    reach = _LANCZOS_REACH + int(np.ceil(float(np.abs(gx).max() + np.abs(gy).max())))
    img3 = np.asarray(img, np.float32).reshape(img.shape[:2] + (ch,))
    both = np.concatenate([img3, np.asarray(under, np.float32).reshape(img.shape[:2] + (-1,))[..., :ch]], -1)
    both, off = _source_box(both, px, py, reach)
    if off is not None:
        px, py = px - off[0], py - off[1]
    both = np.ascontiguousarray(both, np.float32)
    im, un = both[..., :ch], both[..., ch:]
    diff = im - un
    q = np.sqrt((diff * diff).sum(-1)).astype(np.float32)
    # The ink's contrast at the strongest pixel of each 3 x 3 neighbourhood (the line's peak), and that peak.
    qp = np.pad(q, 1, mode="edge")
    dp = np.pad(diff, ((1, 1), (1, 1), (0, 0)), mode="edge")
    h, w = q.shape
    peak = q.copy()
    ink = diff.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dx or dy:
                qs = qp[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
                more = qs > peak
                peak = np.where(more, qs, peak)
                ink = np.where(more[..., None], dp[1 + dy:1 + dy + h, 1 + dx:1 + dx + w], ink)
    # The ink's full contrast: a high percentile of the lines' peaks (most lines cross some pixel
    # whole). A line whose peak reaches half of it is drawn at full ink, as wide as its profile
    # is above half the full contrast (a box-filtered line of any width and phase crosses it
    # there); a fainter one keeps its own peak and its width at half maximum.
    lines = peak[peak > _LINE_MIN_CONTRAST]
    full = np.float32(np.percentile(lines, _LINE_FULL_PERCENTILE)) if lines.size else np.float32(1.0)
    strong = peak >= 0.5 * full
    thr = np.where(strong, 0.5 * full, 0.5 * peak).astype(np.float32)
    ink *= np.where(strong, full / np.maximum(peak, 1e-6), 1.0).astype(np.float32)[..., None]
    thr = np.ascontiguousarray(thr)
    cover = np.zeros(px.size, np.float32)
    for i in range(ss):
        for j in range(ss):
            ox, oy = np.float32((j + 0.5) / ss - 0.5), np.float32((i + 0.5) / ss - 0.5)
            sx = px + ox * gx[:, 0] + oy * gy[:, 0]
            sy = py + ox * gx[:, 1] + oy * gy[:, 1]
            qv = _picked(q, sx, sy, cv2.INTER_CUBIC)[:, 0]
            tv = _picked(thr, sx, sy, cv2.INTER_LINEAR)[:, 0]
            cover += ((qv > tv) & (tv > 0.5 * _LINE_MIN_CONTRAST)).astype(np.float32)
    cover /= np.float32(ss * ss)
    base = _picked(np.ascontiguousarray(un), px, py, cv2.INTER_LINEAR).reshape(-1, ch)
    ink_v = _picked(np.ascontiguousarray(ink), px, py, cv2.INTER_LINEAR).reshape(-1, ch)
    out.reshape(-1, ch)[idx] = np.clip(base + cover[:, None] * ink_v, 0.0, 1.0)
    return out


#: Gaussian sigma (px) splitting an image into the band resampled smoothly and its grain
#: (:func:`_sample_grain_at`).
GRAIN_SIGMA = 1.0


def _sample_grain_at(img, c, where, sigma: float = GRAIN_SIGMA):
    """Colours at ``c`` on the pixels of ``where``: the smooth band resampled, the grain carried whole.

    ``img`` is split into a low band (Gaussian of ``sigma`` px), sampled
    with Lanczos as :func:`_sample_sharp_at` does, and its detail (``img``
    minus the low band), taken from the nearest source pixel and added
    back. Going beyond the paper (which warps the layers and leaves the
    resampling open): every interpolation at a fractional offset averages
    neighbouring pixels, and a photograph's grain (or a procedural
    leaf's per-pixel texture) is half its pixels' contrast: new 1 MP
    leaves had 0.72-0.99 of their exemplars' Laplacian variance inside
    the blade with Lanczos alone. Carried from whole pixels the grain
    keeps its variance, while the edges of veins and spots, in the low
    band, still move smoothly (sub-pixel, no stair steps).
    """
    ch = img.shape[2] if img.ndim == 3 else 1
    out = np.zeros(where.shape + (ch,), np.float32)
    if not where.any():
        return out
    idx, px, py = _picks(c, where)
    # Only the source box the picked pixels read (Lanczos taps, the blur's kernel) is split into its
    # bands: the same values as on the whole image (a float16 stage image turned to float32 and
    # blurred over the canvas was a fifth of a new leaf's time at 1 MP).
    img, off = _source_box(img, px, py, _LANCZOS_REACH + int(np.ceil(4 * float(sigma))) + 1)
    if off is not None:
        px, py = px - off[0], py - off[1]
    img = np.ascontiguousarray(img, np.float32)
    low = cv2.GaussianBlur(img, (0, 0), float(sigma))
    # Rounded half up here (OpenCV's nearest rounds x.5 either way from pixel to pixel: a shift of
    # half a pixel doubled every other grain pixel and kept 0.28 of its Laplacian variance).
    half = np.float32(0.5)
    vals = _picked(low, px, py, cv2.INTER_LANCZOS4) + _picked(np.ascontiguousarray(img - low), np.floor(px + half),
                                                              np.floor(py + half), cv2.INTER_NEAREST)
    out.reshape(-1, ch)[idx] = np.clip(vals, 0.0, 1.0)
    return out


def _border_alpha(alpha: np.ndarray) -> float:
    """Opacity on the canvas border (0: nothing is cut by the canvas edge)."""
    return float(alpha[0].sum() + alpha[-1].sum() + alpha[:, 0].sum() + alpha[:, -1].sum())


def _fit_size(p, m, size_from: int, shrink: float = 1.0, scale: float = 1.0) -> np.ndarray:
    """The shape map ``m`` scaled (to one exemplar's size) and moved so the lamina stays on the canvas.

    Going beyond the paper: a convex blend of warps averages the
    exemplars' sizes, so new leaves came out nearly one size (size is most
    of the variation among photographed maples: pairwise blade IoU 0.78
    among new leaves against the exemplars' 0.63). With ``size_from >= 0``
    the blend gives the shape and the size (square root of the lamina's
    area) is that of exemplar ``size_from`` (-1: the blend's size). A
    leaf that would then cross the canvas edge (a large exemplar's size on
    the training leaf's place) is moved inwards, and shrunk only if it
    cannot fit; ``shrink`` scales it further (room for a
    petiole). ``scale`` multiplies the wanted size before the leaf is
    fitted to the canvas (the size's smoothed bootstrap).
    """
    # The lamina on a coarse grid reaching half a canvas past each edge
    # (the map continues past the canvas), so a leaf the canvas already
    # cuts is measured whole.
    h, w = p.shape
    st = max(1.0, p.size / 100.0)
    gx = np.arange(-0.5 * w, 1.5 * w, st, dtype=np.float32)
    gy = np.arange(-0.5 * h, 1.5 * h, st, dtype=np.float32)
    gxx, gyy = np.meshgrid(gx, gy)
    mc = _remap_map(m, np.stack([gxx, gyy], -1))
    lam = _remap_values(p.alpha_t, mc)
    lam = np.where((mc[..., 0] >= 0) & (mc[..., 0] <= w - 1) & (mc[..., 1] >= 0) & (mc[..., 1] <= h - 1), lam, 0.0)
    inside = lam > 0.5
    if not inside.any():
        return m
    area = float(lam.sum()) * st * st
    k = 1.0
    if size_from >= 0 and p.lamina_size[size_from] > 0:
        k = p.lamina_size[size_from] * float(scale) / np.sqrt(area)
    ctr = np.array([(lam * gxx).sum(), (lam * gyy).sum()]) / float(lam.sum())
    lo = np.array([gxx[inside].min(), gyy[inside].min()], float)
    hi = np.array([gxx[inside].max(), gyy[inside].max()], float)
    margin = 2.0 + 0.02 * p.size
    room = np.array([w - 1.0, h - 1.0]) - 2 * margin
    ext = np.maximum(hi - lo, 1.0)
    k = float(min(k, *(room / ext))) if np.all(room > 0) else k
    k *= float(shrink)
    lo_k, hi_k = ctr + (lo - ctr) * k, ctr + (hi - ctr) * k
    shift = np.maximum(margin - lo_k, 0.0) - np.maximum(hi_k - (np.array([w - 1.0, h - 1.0]) - margin), 0.0)
    if abs(k - 1.0) < 1e-6 and not np.any(shift):
        return m
    # Each coordinate depends on its own axis only: the same float32 steps on a row and a column.
    s32, c32, k32 = (ctr + shift).astype(np.float32), ctr.astype(np.float32), np.float32(k)
    q = np.empty((h, w, 2), np.float32)
    q[..., 0] = (np.arange(w, dtype=np.float32) - s32[0]) / k32 + c32[0]
    q[..., 1] = ((np.arange(h, dtype=np.float32) - s32[1]) / k32 + c32[1])[:, None]
    return _remap_map(m, q)
