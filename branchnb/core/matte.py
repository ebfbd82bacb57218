"""Soft alpha mattes of objects photographed or drawn on a plain or smooth ground.

An opaque picture of one object on white, on a flat colour, on a
vertical or diagonal gradient (a sky) or on light paper texture is split
into the object (an RGBA layer with a soft edge) and a smooth model of the
ground behind it, which also fills the area the object hides. Shared by the
techniques that take opaque photos of objects (stroke editing, tree
exemplars).

How it works (:func:`matte_from_background`):

1. A smooth model of the ground is fitted to the image border: a
   polynomial of degree 2 in ``(x, y)`` per channel, by trimmed least
   squares (the object may leave the image at an edge, a branch cut by the
   frame).
2. Pixels within the ground's own noise of the model (``tol``, measured
   from the border) and connected to the border are background; the model
   is refitted on all of them (degree 3) and the local, non-polynomial
   smooth part of the ground (a sky's soft brightening, paper shading) is
   added by normalised convolution of the residual.
3. The object is everything else, with small enclosed pockets of
   ground colour kept as object (a drawing's white eye) and specks of
   texture dropped. Alpha is 1 inside; within two pixels of the ground it
   is the projection of ``I - B`` on ``F - B``, ``F`` the colour of the
   nearest interior object pixel, and the layer's colours there are the
   un-mixed foreground ``F``-side colours (no halo of the old ground over a
   new one).

A ground whose border is not smooth (a busy photo) gives ``None``: there is
no plain ground to separate from.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from .image import as_float_image
from .validate import Real, checked

__all__ = ["Matte", "matte_from_background"]


@dataclass
class Matte:
    """An object separated from a smooth ground (:func:`matte_from_background`).

    Parameters
    ----------
    image : (H, W, 4) float32 ndarray
        The object: un-mixed foreground colours, straight alpha (0 on the ground).
    alpha : (H, W) float32 ndarray
        The soft matte (``image[..., 3]``).
    background : (H, W, 3) float32 ndarray
        The ground behind the object: the input where alpha is 0, the
        smooth model where the object hid it (and in its soft rim).
    model : (H, W, 3) float32 ndarray
        The smooth ground model everywhere.
    noise : float
        The ground's noise level (RMS colour distance to the model on the border).
    """

    image: np.ndarray
    alpha: np.ndarray
    background: np.ndarray
    model: np.ndarray
    noise: float


#: Weight of the chroma part of a colour difference against its luma part.
CHROMA_WEIGHT = 0.5
_LUMA = np.array([0.299, 0.587, 0.114])


def _colour_distance(diff: np.ndarray) -> np.ndarray:
    """Length of colour differences (last axis RGB) with the chroma part down-weighted.

    JPEG stores colour at half resolution: a dark branch on a blue sky
    smears its chroma 4-8 px into the sky while the luma stays sharp;
    measured in plain RGB those smears became blobs of object round every
    edge.
    """
    y = diff @ _LUMA
    c = diff - y[..., None]
    return np.sqrt(3.0 * y * y + CHROMA_WEIGHT ** 2 * np.sum(c * c, axis=-1))


def _poly_features(xn: np.ndarray, yn: np.ndarray, degree: int) -> np.ndarray:
    cols = [xn ** i * yn ** j for i in range(degree + 1) for j in range(degree + 1 - i)]
    return np.stack(cols, axis=1)


def _fit_poly(rgb, ys, xs, degree, h, w, keep=None, rounds=3):
    """Trimmed least-squares polynomial fit of ``rgb[ys, xs]``; returns (coef, residual distances, kept)."""
    xn = xs / max(w - 1, 1) * 2.0 - 1.0
    yn = ys / max(h - 1, 1) * 2.0 - 1.0
    a = _poly_features(xn, yn, degree)
    vals = rgb[ys, xs].astype(np.float64)
    keep = np.ones(len(ys), bool) if keep is None else keep.copy()
    coef = None
    for _ in range(rounds):
        if keep.sum() < a.shape[1] * 3:
            break
        coef, *_ = np.linalg.lstsq(a[keep], vals[keep], rcond=None)
        d = _colour_distance(vals - a @ coef)
        # outliers are the object crossing the border: far beyond the ground's own spread
        med = float(np.median(d[keep]))
        keep = d <= max(4.0 * med, 0.04)
    if coef is None:
        return None, None, keep
    d = _colour_distance(vals - a @ coef)
    return coef, d, keep


def _eval_poly(coef, degree, h, w) -> np.ndarray:
    # separable: sum_ij c_ij x^i y^j = Y C^T X^T per channel (no H*W x terms matrix)
    xn = np.arange(w) / max(w - 1, 1) * 2.0 - 1.0
    yn = np.arange(h) / max(h - 1, 1) * 2.0 - 1.0
    xp = np.stack([xn ** i for i in range(degree + 1)], axis=1)
    yp = np.stack([yn ** j for j in range(degree + 1)], axis=1)
    terms = [(i, j) for i in range(degree + 1) for j in range(degree + 1 - i)]
    out = np.empty((h, w, coef.shape[1]), np.float32)
    for c in range(coef.shape[1]):
        cm = np.zeros((degree + 1, degree + 1))
        for k, (i, j) in enumerate(terms):
            cm[i, j] = coef[k, c]
        out[..., c] = yp @ cm.T @ xp.T
    return out


def _smooth_residual(res: np.ndarray, mask: np.ndarray, sigma: float) -> np.ndarray:
    """Normalised convolution of ``res`` over ``mask``, fading to 0 far from any ground pixel."""
    m = mask.astype(np.float32)
    den = cv2.GaussianBlur(m, (0, 0), sigma)
    out = np.empty_like(res)
    for c in range(res.shape[2]):
        num = cv2.GaussianBlur(res[..., c] * m, (0, 0), sigma)
        out[..., c] = num / np.maximum(den, 1e-6)
    fade = np.clip(den / 0.05, 0.0, 1.0)[..., None]
    return out * fade


@checked(tol=Real(0, 1, low_open=True), max_noise=Real(0, 1), min_ground=Real(0, 1))
def matte_from_background(image, *, tol: float | None = None, max_noise: float = 0.08,
                          min_ground: float = 0.4) -> Matte | None:
    """Separate the object of an opaque image from a plain or smooth ground.

    Parameters
    ----------
    image : (H, W, C) array_like
        The picture (C = 1, 3 or 4; an alpha channel is ignored). At least 8 x 8.
    tol : float, optional
        Colour distance (Euclidean RGB, in [0, 1]) to the ground model
        below which a pixel is ground; default: from the ground's own noise
        on the border (``max(0.05, 1.5 x its 99th percentile)``).
    max_noise : float
        A ground noisier than this (RMS distance to the smooth model on the
        border) is busy: None is returned; 0.08.
    min_ground : float
        Share of the border that must be ground (the rest is the object
        leaving the frame); None below it; 0.4.

    Returns
    -------
    Matte or None
        None when the ground is not smooth (a busy photo), when no object
        stands out, or when the object covers nearly the whole picture.

    Raises
    ------
    ValueError
        An image smaller than 8 x 8, ``tol`` outside (0, 1], ``max_noise`` or
        ``min_ground`` outside [0, 1].

    Notes
    -----
    Beyond the papers that use it (which take RGBA objects or key one
    colour): the ground may be a gradient or lightly textured. Ground
    colour enclosed by the object is kept as object when the pocket is
    smaller than 5 % of the object (a drawing's white eye, a highlight) and
    is ground otherwise (the sky through a loop of a branch). The model
    inside a large object is a smooth extrapolation: texture of the ground
    is not re-created there.

    Examples
    --------
    >>> import numpy as np
    >>> yy = np.linspace(0.5, 0.9, 64, dtype=np.float32)[:, None, None]
    >>> img = np.broadcast_to(yy * np.float32([0.6, 0.8, 1.0]), (64, 64, 3)).copy()  # a sky gradient
    >>> img[20:44, 28:36] = (0.35, 0.22, 0.1)                                      # a brown stick
    >>> m = matte_from_background(img)
    >>> round(float(m.alpha[30, 31]), 2), round(float(m.alpha[5, 5]), 2)
    (1.0, 0.0)
    >>> bool(np.abs(m.background[30, 31] - img[30, 20]).max() < 0.02)   # the ground behind the stick
    True
    """
    img = as_float_image(image, name="image")
    if img.shape[2] == 1:
        img = np.repeat(img, 3, axis=2)
    rgb = np.ascontiguousarray(img[..., :3], dtype=np.float32)
    h, w = rgb.shape[:2]
    if h < 8 or w < 8:
        raise ValueError(f"image must be at least 8 x 8 pixels, got {w} x {h}")
    if tol is not None and not (0.0 < float(tol) <= 1.0):
        raise ValueError(f"tol must lie in (0, 1], got {tol}")
    if not (0.0 <= float(max_noise) <= 1.0):
        raise ValueError(f"max_noise must lie in [0, 1], got {max_noise}")
    if not (0.0 <= float(min_ground) <= 1.0):
        raise ValueError(f"min_ground must lie in [0, 1], got {min_ground}")

    # 1. the ground on the border
    band = max(2, int(round(0.02 * min(h, w))))
    border = np.zeros((h, w), bool)
    border[:band], border[-band:], border[:, :band], border[:, -band:] = True, True, True, True
    ys, xs = np.nonzero(border)
    step = max(1, len(ys) // 20000)
    ys, xs = ys[::step], xs[::step]
    coef, d_border, keep = _fit_poly(rgb, ys, xs, 2, h, w)
    if coef is None or keep.mean() < min_ground:
        return None
    noise = float(np.sqrt(np.mean(d_border[keep] ** 2)))
    if noise > max_noise:
        return None
    t_lo = float(tol) if tol is not None else max(0.05, 1.5 * float(np.quantile(d_border[keep], 0.99)))
    model = _eval_poly(coef, 2, h, w)

    # 2. the ground connected to the border; refit on all of it
    dist = _colour_distance(rgb - model)
    ground = _border_connected(dist <= t_lo)
    gy, gx = np.nonzero(ground)
    if len(gy) < 64:
        return None
    step = max(1, len(gy) // 40000)
    c2, _, _ = _fit_poly(rgb, gy[::step], gx[::step], 3, h, w, rounds=2)
    if c2 is not None:
        model = _eval_poly(c2, 3, h, w)
    res = np.where(ground[..., None], rgb - model, 0.0).astype(np.float32)
    model = np.clip(model + _smooth_residual(res, ground, max(3.0, 0.03 * min(h, w))), 0.0, 1.0)
    dist = _colour_distance(rgb - model)
    ground = _border_connected(dist <= t_lo)

    # 3. the object: specks dropped; enclosed ground colour is ground when large (the sky
    # through a loop of a branch), object when small (a drawing's white eye)
    obj = ~ground
    n, lab, stats, _ = cv2.connectedComponentsWithStats(obj.astype(np.uint8), connectivity=8)
    min_speck = max(12, int(2e-4 * h * w))
    small = np.zeros(n, bool)
    small[1:] = stats[1:, cv2.CC_STAT_AREA] < min_speck
    obj &= ~small[lab]
    k3 = np.ones((3, 3), np.uint8)
    enclosed = (cv2.erode(((dist <= t_lo) & obj).astype(np.uint8), k3) > 0)
    ne, le, se, _ = cv2.connectedComponentsWithStats(enclosed.astype(np.uint8), connectivity=4)
    area = int(obj.sum()) - int(enclosed.sum())
    big = np.zeros(ne, bool)
    big[1:] = se[1:, cv2.CC_STAT_AREA] >= max(0.05 * area, min_speck)
    if big.any():
        obj &= ~((cv2.dilate(big[le].astype(np.uint8), k3) > 0) & (dist <= t_lo))
    area = int(obj.sum())
    if area < min_speck or area > 0.9 * h * w:
        return None
    ground = ~obj

    # soft rim: the object pixels next to the ground, alpha from the projection on the strongest colour
    cross = cv2.getStructuringElement(cv2.MORPH_CROSS, (3, 3))
    o8 = obj.astype(np.uint8)
    rim = obj & (cv2.erode(o8, cross, borderType=cv2.BORDER_REPLICATE) == 0)
    # pixels of ground just outside the rim with some object colour mixed in
    outer = ~obj & (cv2.dilate(o8, cross) > 0) & (dist > 0.5 * t_lo)
    fg = _strongest_neighbour(rgb, model, obj, rim | outer | (~obj & (cv2.dilate(o8, cross) > 0)), 2)
    diff_f = fg - model
    num = np.sum((rgb - model) * diff_f, axis=2)
    den = np.sum(diff_f * diff_f, axis=2)
    proj = np.where(den > t_lo ** 2, num / np.maximum(den, 1e-12), 1.0)
    alpha = o8.astype(np.float32)
    alpha[rim] = np.clip(proj[rim], 0.0, 1.0)
    alpha[outer] = np.clip(proj[outer], 0.0, 0.5)
    alpha = _drop_specks(alpha, min_speck)
    a3 = alpha[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        unmixed = np.where(a3 > 0.05, (rgb - (1.0 - a3) * model) / np.maximum(a3, 1e-6), fg)
    colour = np.where((alpha >= 0.999)[..., None], rgb, np.clip(unmixed, 0.0, 1.0))
    layer = np.dstack([colour, alpha]).astype(np.float32)
    # faint anti-aliased rim pixels outside the matte go too (no ghost outline where the object was)
    near = cv2.dilate((alpha > 0.0).astype(np.uint8), np.ones((5, 5), np.uint8)) > 0
    fill = np.clip(model + _ground_grain(rgb - model, near, ground & ~cv2.dilate(
        near.astype(np.uint8), np.ones((7, 7), np.uint8)).astype(bool)), 0.0, 1.0)
    behind = np.where(near[..., None], fill, rgb).astype(np.float32)
    return Matte(image=layer, alpha=alpha, background=behind, model=model.astype(np.float32), noise=noise)


def _border_connected(mask: np.ndarray) -> np.ndarray:
    """The pixels of ``mask`` reached from the image border through ``mask`` opened by a 3 x 3 square.

    The opening keeps the ground from leaking through one- or two-pixel
    gaps of a thin anti-aliased outline into a part of nearly the ground's
    colour (a skin-coloured arm drawn on beige paper).
    """
    k = np.ones((3, 3), np.uint8)
    core = cv2.erode(mask.astype(np.uint8), k, borderType=cv2.BORDER_REPLICATE)
    n, lab = cv2.connectedComponents(core, connectivity=4)
    edge = np.unique(np.concatenate([lab[0], lab[-1], lab[:, 0], lab[:, -1]]))
    keep = np.zeros(n, bool)
    keep[edge] = True
    keep[0] = False
    return (cv2.dilate(keep[lab].astype(np.uint8), k) > 0) & mask



def _strongest_neighbour(rgb: np.ndarray, model: np.ndarray, obj: np.ndarray, where: np.ndarray,
                         reach: int) -> np.ndarray:
    """Per pixel of ``where``, the colour of the object pixel within ``reach`` px (Chebyshev) farthest
    from the ground (``rgb`` itself elsewhere).

    The foreground an anti-aliased rim pixel mixes with the ground is the
    strongest colour next to it (a drawing's dark outline, not the pale fill
    inside it): alpha is the rim pixel's share of that colour.
    """
    h, w = obj.shape
    out = rgb.copy()
    ys, xs = np.nonzero(where)
    if len(ys) == 0:
        return out
    d = np.where(obj, _colour_distance(rgb - model), -1.0)
    best = np.full(len(ys), -1.0)
    col = rgb[ys, xs].copy()
    for dy in range(-reach, reach + 1):
        for dx in range(-reach, reach + 1):
            ty, tx = np.clip(ys + dy, 0, h - 1), np.clip(xs + dx, 0, w - 1)
            cand = d[ty, tx]
            better = cand > best
            best[better] = cand[better]
            col[better] = rgb[ty[better], tx[better]]
    out[ys, xs] = col
    return out


def _ground_grain(res: np.ndarray, hole: np.ndarray, usable: np.ndarray) -> np.ndarray:
    """The ground's fine grain (``res``: image minus smooth model) copied into ``hole``.

    Each hole pixel takes the residual of the pixel a fixed shift away, the
    shortest of a set of shifts (8 directions, growing lengths) that lands on
    ``usable`` ground: paper grain and noise continue over the area the
    object vacated instead of a smooth, too-clean patch. Zero where no
    shift lands on ground.
    """
    h, w = hole.shape
    out = np.zeros_like(res)
    ys, xs = np.nonzero(hole)
    if len(ys) == 0 or not usable.any():
        return out
    todo = np.ones(len(ys), bool)
    step = max(8, min(h, w) // 16)
    dirs = [(1, 0), (0, 1), (-1, 0), (0, -1), (1, 1), (-1, 1), (1, -1), (-1, -1)]
    for k in range(1, max(h, w) // step + 2):
        for dy, dx in dirs:
            if not todo.any():
                return out
            ty, tx = ys[todo] + dy * k * step, xs[todo] + dx * k * step
            inside = (ty >= 0) & (ty < h) & (tx >= 0) & (tx < w)
            ok = np.zeros(len(ty), bool)
            ok[inside] = usable[ty[inside], tx[inside]]
            idx = np.nonzero(todo)[0][ok]
            out[ys[idx], xs[idx]] = res[ty[ok], tx[ok]]
            todo[idx] = False
    return out


def _drop_specks(alpha: np.ndarray, min_area: int) -> np.ndarray:
    """``alpha`` without opaque islands under ``min_area`` px and the soft pixels round them.

    JPEG ringing next to a dark branch leaves islands of a few pixels just
    off the object: as parts of their own they change how an edit splits
    the object (a crumb read as the body the stroke grows out of).
    """
    n, lab, st, _ = cv2.connectedComponentsWithStats((alpha > 0.5).astype(np.uint8), connectivity=8)
    small = np.zeros(n, bool)
    small[1:] = st[1:, cv2.CC_STAT_AREA] < min_area
    out = alpha.copy()
    if small.any():
        k3 = np.ones((3, 3), np.uint8)
        gone = cv2.dilate(small[lab].astype(np.uint8), k3) > 0
        kept = cv2.dilate((~small[lab] & (lab > 0)).astype(np.uint8), k3) > 0
        out[gone & ~kept] = 0.0
    # soft pixels touching no opaque pixel are ghosts of the rim, not object
    n2, lab2 = cv2.connectedComponents((out > 0).astype(np.uint8), connectivity=8)
    has = np.zeros(n2, bool)
    has[np.unique(lab2[out > 0.5])] = True
    has[0] = False
    out[~has[lab2]] = 0.0
    return out
