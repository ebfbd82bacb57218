"""One vein system per new leaf: what the induction left of a layer in the background (issue 22).

Going beyond the paper, whose background is the residual of every layer
removed. Where the induction missed part of an exemplar's veins (a
photographed maple's lateral vein, 1-3 px of a faint one), the residual
keeps them, and a new leaf built on it shows them a few pixels beside the
donor's pasted veins: two vein systems. And the removed veins' strips are
filled by diffusion (Telea), smoother than the blade around them (ridge
response at the true veins 0.4-0.8 of plain blade's): pale bands beside
the pasted veins.

:func:`flatten_leftover` takes the background of a new leaf (the last
residual) and

1. finds the lines left in it that stand out as the layer does (same
   polarity, Hessian ridge strength at the layer's scales at least
   ``level`` times that of the exemplar's own induced layer, in elongated
   pieces at least ``min_length`` of the leaf size long), fills them from
   the blade around them, and
2. gives those pixels (and, with ``regrain``, the strips the residual
   filled: where it differs from the leaf it came from) the blade's grain
   again: the detail (image minus a Gaussian of 1 px) of plain blade
   pixels a few widths away.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

__all__ = ["ridge_strength", "flatten_leftover"]


def ridge_strength(grey: np.ndarray, sigmas, sign: float) -> np.ndarray:
    """Largest scale-normalised Hessian line strength of ``grey`` over ``sigmas``, for lines of ``sign``.

    ``sign`` > 0: lines lighter than their surroundings, < 0: darker. A
    line has one large curvature across it and none along it; a blob has
    two, so the second is subtracted (spots score low).

    Parameters
    ----------
    grey : (H, W) float ndarray
        Grey image searched for lines.
    sigmas : sequence of float
        Gaussian scales (px).
    sign : float
        Polarity of the lines.

    Returns
    -------
    (H, W) float32 ndarray
        0 where nothing line-like of that polarity is.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.full((40, 40), 0.5, np.float32); g[:, 19:22] = 0.3
    >>> r = ridge_strength(g, [1.5], -1.0)
    >>> bool(r[20, 20] > 10 * r[20, 5])
    True
    """
    g = np.asarray(grey, np.float32) * np.float32(-1.0 if sign > 0 else 1.0)  # dark lines: a valley
    out = np.zeros(g.shape, np.float32)
    for s in sigmas:
        b = cv2.GaussianBlur(g, (0, 0), float(s))
        dxx = cv2.Sobel(b, cv2.CV_32F, 2, 0, ksize=3)
        dyy = cv2.Sobel(b, cv2.CV_32F, 0, 2, ksize=3)
        dxy = cv2.Sobel(b, cv2.CV_32F, 1, 1, ksize=3)
        root = np.sqrt((dxx - dyy) ** 2 + 4.0 * dxy ** 2)
        big, small = 0.5 * (dxx + dyy + root), 0.5 * (dxx + dyy - root)
        r = (np.maximum(big, 0.0) - np.maximum(small, 0.0)) * np.float32(s * s)
        np.maximum(out, r, out=out)
    return out


def _grain(img: np.ndarray, blade: np.ndarray, hole: np.ndarray, reach: int) -> np.ndarray:
    """Detail (img minus its 1 px Gaussian) for the ``hole`` pixels, from blade pixels ``reach`` px away."""
    detail = img - cv2.GaussianBlur(img, (0, 0), 1.0)
    src_ok = blade & ~hole
    out = np.zeros_like(img)
    todo = hole.copy()
    h, w = hole.shape
    for dy, dx in ((reach, reach), (-reach, -reach), (reach, -reach), (-reach, reach),
                   (2 * reach, 0), (0, 2 * reach), (-2 * reach, 0), (0, -2 * reach)):
        if not todo.any():
            break
        ys, xs = np.nonzero(todo)
        sy, sx = ys + dy, xs + dx
        ok = (sy >= 0) & (sy < h) & (sx >= 0) & (sx < w)
        ok[ok] = src_ok[sy[ok], sx[ok]]
        out[ys[ok], xs[ok]] = detail[sy[ok], sx[ok]]
        todo[ys[ok], xs[ok]] = False
    return out


def flatten_leftover(residual, blade, source, layer_image, layer_mask, sign: float, width: float, *,
                     corridor=None, level: float = 0.5, min_length: float = 0.04, regrain: bool = False):
    """The background ``residual`` with the lines left of a layer flattened and its filled strips regrained.

    Parameters
    ----------
    residual : (H, W, 3) float ndarray
        The exemplar with every layer removed (the new leaf's background).
    blade : (H, W) bool ndarray
        The leaf's blade; nothing outside it is changed.
    source : (H, W, 3) float ndarray
        The exemplar itself (where ``residual`` differs from it, the
        layers were filled).
    layer_image, layer_mask : ndarray
        The image in which the layer was induced and its induced mask
        (the strength its own lines have there is the reference).
    sign : float
        The layer's polarity (> 0 lighter than the leaf, < 0 darker).
    width : float
        The layer's typical width (px); sets the scales and the reach.
    corridor : (H, W) bool ndarray, optional
        Where the layer's lines may be left (e.g. the training layer
        carried onto the exemplar, grown by the registration tolerance);
        None: the whole blade. Outside it nothing is flattened: a maple's
        network of tertiary veins is as strong as the induced ones on some
        leaves, and flattening it everywhere blurred the blade.
    level : float
        A line is flattened where its strength reaches this share of the
        layer's median strength on its own mask (default 0.5), and the
        90th percentile of the blade's.
    min_length : float
        Shortest piece flattened, as a share of the leaf size (square
        root of the blade's area; default 0.04): shorter ones are grain,
        spots or dents.
    regrain : bool
        Also give the strips the residual filled the blade's grain
        (default False). Measured on procedural elliptic leaves (320 px, 8
        new leaves): ridge response at the background's true veins over
        plain blade 0.44-0.60 -> 0.82-0.92 in the residual, 0.86-1.30 ->
        0.99-1.45 in the new leaves (the donor's layer is pasted over them
        as a ratio): the smooth strips are less visible, but the measure
        of issue 22 rises past plain blade's, so it is off by default.

    Returns
    -------
    (H, W, 3) float32 ndarray

    Examples
    --------
    Two dark veins; the induction found one (``mask``), the residual keeps the other:

    >>> import numpy as np
    >>> leaf = np.full((60, 60, 3), 0.5, np.float32)
    >>> leaf[10:50, 29:32] = 0.3; leaf[20:40, 10:13] = 0.3
    >>> blade = np.ones((60, 60), bool); mask = np.zeros_like(blade); mask[10:50, 29:32] = True
    >>> res = leaf.copy(); res[10:50, 29:32] = 0.5  # the found vein removed
    >>> out = flatten_leftover(res, blade, leaf, leaf, mask, -1.0, 3.0)
    >>> float(res[30, 11, 0]), bool(abs(out[30, 11, 0] - 0.5) < 0.02)
    (0.30000001192092896, True)
    """
    res = np.asarray(residual, np.float32)[..., :3]
    blade = np.asarray(blade, bool)
    mask = np.asarray(layer_mask, bool) & blade
    if not blade.any() or not mask.any() or sign == 0:
        return res
    # On the blade's box (and a margin for the filters): a fifth of a 1 MP canvas's work.
    ys, xs = np.nonzero(blade)
    pad = 8 + int(np.ceil(2 * max(float(width), 1.0)))
    y0, y1 = max(int(ys.min()) - pad, 0), min(int(ys.max()) + pad + 1, blade.shape[0])
    x0, x1 = max(int(xs.min()) - pad, 0), min(int(xs.max()) + pad + 1, blade.shape[1])
    box = (slice(y0, y1), slice(x0, x1))
    if (y1 - y0) * (x1 - x0) < 0.8 * blade.size:
        out = res.copy()
        out[box] = flatten_leftover(res[box], blade[box], np.asarray(source)[box], np.asarray(layer_image)[box],
                                    mask[box], sign, width, corridor=None if corridor is None else
                                    np.asarray(corridor, bool)[box], level=level, min_length=min_length,
                                    regrain=regrain)
        return out
    src = np.asarray(source, np.float32)[..., :3]
    w = max(float(width), 1.0)
    sigmas = sorted({1.0, max(1.0, 0.3 * w), max(1.0, 0.6 * w)})
    ref = ridge_strength(np.asarray(layer_image, np.float32)[..., :3].mean(-1), sigmas, sign)
    ref_level = float(np.median(ref[mask]))
    out = res.copy()
    hole = np.zeros(blade.shape, bool)
    if ref_level > 0:
        inner = ndi.binary_erosion(blade, iterations=2)
        r = ridge_strength(res.mean(-1), sigmas, sign)
        lines = (r >= max(level * ref_level, float(np.percentile(r[blade], 90)))) & inner
        if corridor is not None:
            lines &= np.asarray(corridor, bool)
        lab, n = ndi.label(lines, structure=np.ones((3, 3)))
        if n:
            size = float(np.sqrt(blade.sum()))
            objs = ndi.find_objects(lab)
            area = np.bincount(lab.ravel(), minlength=n + 1)[1:]
            ext = np.array([np.hypot(sl[0].stop - sl[0].start, sl[1].stop - sl[1].start) for sl in objs])
            keep = (ext >= min_length * size) & (area / np.maximum(ext, 1.0) <= max(3.0, 1.5 * w))
            if keep.any():
                hole = ndi.binary_dilation(np.isin(lab, 1 + np.flatnonzero(keep)), iterations=1) & blade
        if hole.any():
            from .prepared import _smooth_fill
            out = np.where(hole[..., None], _smooth_fill(res, blade & ~hole), res).astype(np.float32)
    # The grain of the blade where the residual was filled (and where lines were just flattened).
    filled = (hole | ((np.abs(res - src).max(-1) > 2e-3) if regrain else False)) & blade
    if filled.any():
        reach = int(np.ceil(2 * w)) + 2
        g = _grain(src, blade & ~filled, filled, reach)
        out = np.where(filled[..., None], out - (out - cv2.GaussianBlur(out, (0, 0), 1.0)) + g, out)
    return np.clip(out, 0.0, 1.0).astype(np.float32)
