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

from ..core.morphology import _binary_dilation, _binary_erosion

__all__ = ["ridge_strength", "flatten_leftover", "layer_strength", "own_lines", "parallel_lines"]


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


def _rimless(img: np.ndarray, blade: np.ndarray) -> np.ndarray:
    """``img`` (H, W, 3) with the blade's colours extended beyond ``blade`` (:func:`branchnb.leaves.prepared._bleed`).

    Going beyond the paper: a residual's backdrop (white, or black when
    premultiplied) meets the blade in a step, which a ridge filter reads as
    a line all along the outline and a Gaussian blur pulls into the rim.
    Flattened and regrained as a leftover vein, the rim came out in dark
    stubs where the fan's veins reach the margin (the frayed rim of new
    ginkgo leaves).
    """
    from .prepared import _bleed
    return np.asarray(_bleed(np.asarray(img, np.float32)[..., :3], blade), np.float32)


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


def _line_pieces(img, blade, sigmas, sign, floor, w, min_length, corridor=None) -> np.ndarray:
    """Labels (1, 2, ...) of the elongated pieces of ``img``'s lines of polarity ``sign`` (0 elsewhere).

    A line pixel's ridge strength (:func:`ridge_strength` over ``sigmas``)
    reaches ``floor`` and the blade's 90th percentile, 2 px inside the
    blade (and inside ``corridor`` if given); a piece is kept when it spans
    ``min_length`` of the leaf size and is no wider than ``max(3, 1.5 w)``
    px on average (area over extent).
    """
    inner = _binary_erosion(blade, iterations=2)
    r = ridge_strength(np.asarray(img, np.float32)[..., :3].mean(-1), sigmas, sign)
    lines = (r >= max(floor, float(np.percentile(r[blade], 90)))) & inner
    if corridor is not None:
        lines &= np.asarray(corridor, bool)
    lab, n = ndi.label(lines, structure=np.ones((3, 3)))
    out = np.zeros(blade.shape, np.int32)
    if not n:
        return out
    size = float(np.sqrt(blade.sum()))
    objs = ndi.find_objects(lab)
    area = np.bincount(lab.ravel(), minlength=n + 1)[1:]
    ext = np.array([np.hypot(sl[0].stop - sl[0].start, sl[1].stop - sl[1].start) for sl in objs])
    keep = (ext >= min_length * size) & (area / np.maximum(ext, 1.0) <= max(3.0, 1.5 * w))
    if keep.any():
        new_id = np.zeros(n + 1, np.int32)
        new_id[1 + np.flatnonzero(keep)] = np.arange(1, int(keep.sum()) + 1, dtype=np.int32)
        out = new_id[lab]
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

    Notes
    -----
    Going beyond the paper (as is the whole step): lines are looked for,
    filled and regrained on the residual with the blade's colours extended
    past its outline (:func:`_rimless`), not on the backdrop. The step from
    the blade to the backdrop read as a line along the rim beside every
    vein that reaches the margin, and filling it pulled in colours from
    across the leaf: dark stubs at the vein ends (the frayed margin of new
    ginkgo leaves). Share of the 3 px rim band of a fan leaf's background
    standing out by more than 6 % from the blade around it: 0.05-0.11 ->
    0.006-0.009 (exemplars 0.016-0.025 with their veins); on new leaves
    (veins scribbled on one of 4 ginkgo fans, 200 and 400 px, 2 seeds)
    0.085-0.120 -> 0.044-0.097 (the rest: the veins' own ends at the rim).

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
    # Beyond the blade the colours are the blade's own, extended (_rimless):
    # the backdrop's step at the outline read as a line along the rim, and
    # the fills and grain blurs pulled it in (dark stubs at a fan's vein ends).
    res = _rimless(res, blade)
    src = _rimless(np.asarray(source, np.float32)[..., :3], blade)
    w = max(float(width), 1.0)
    sigmas = sorted({1.0, max(1.0, 0.3 * w), max(1.0, 0.6 * w)})
    ref = ridge_strength(np.asarray(layer_image, np.float32)[..., :3].mean(-1), sigmas, sign)
    ref_level = float(np.median(ref[mask]))
    out = res.copy()
    hole = np.zeros(blade.shape, bool)
    if ref_level > 0:
        lab = _line_pieces(res, blade, sigmas, sign, level * ref_level, w, min_length, corridor)
        if lab.any():
            hole = _binary_dilation(lab > 0, iterations=1) & blade
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


def own_lines(background, blade, layer_image, layer_mask, sign: float, width: float, *, level: float = 0.5,
              min_length: float = 0.04, ref_level: float | None = None):
    """The lines of a layer left anywhere in a background, and the background with them filled.

    The first half of the per-leaf step that gives a new leaf one vein
    system (:func:`parallel_lines` is the second): unlike
    :func:`flatten_leftover`, which flattens only inside the training
    layer's corridor (for every new leaf alike), this finds the
    background's own lines of the layer's polarity over the whole blade,
    and leaves to each new leaf the choice of which to remove: those that
    run beside a vein pasted from a donor (the same vein of the other
    leaf, moved by the registration errors and warps of both), not the
    tertiary network elsewhere.

    Parameters
    ----------
    background : (H, W, 3) float ndarray
        The exemplar's background (its last residual).
    blade : (H, W) bool ndarray
        The exemplar's blade.
    layer_image, layer_mask : ndarray
        The image in which the layer was induced and its induced mask: the
        median ridge strength of the layer on its mask there is the
        reference strength (unless ``ref_level`` is given).
    sign : float
        The layer's polarity (> 0 lighter than the leaf, < 0 darker).
    width : float
        The layer's typical width (px).
    level : float
        A line reaches this share of the reference strength (default 0.5,
        as in :func:`flatten_leftover`) and the blade's 90th percentile.
    min_length : float
        Shortest piece, as a share of the leaf size (default 0.04).
    ref_level : float, optional
        Reference strength to use instead of the exemplar's own (an
        exemplar whose layer was not induced has none).

    Returns
    -------
    labels : (H, W) int32 ndarray
        0 off the lines, ``1..n`` one label per piece.
    filled : (H, W, 3) float32 ndarray
        ``background`` with every piece (grown by 1 px) filled smoothly from
        the blade around it, with the blade's grain (detail above a 1 px
        Gaussian of blade pixels a few widths away).
    ref_level : float
        The reference strength used.

    Examples
    --------
    >>> import numpy as np
    >>> bg = np.full((60, 60, 3), 0.5, np.float32); bg[10:50, 20:22] = 0.35
    >>> layer = bg.copy(); layer[10:50, 40:43] = 0.3
    >>> mask = np.zeros((60, 60), bool); mask[10:50, 40:43] = True
    >>> lab, filled, ref = own_lines(bg, np.ones((60, 60), bool), layer, mask, -1.0, 3.0)
    >>> int(lab.max()), bool(lab[30, 20] > 0), bool(abs(filled[30, 20, 0] - 0.5) < 0.02)
    (1, True, True)
    """
    res = np.asarray(background, np.float32)[..., :3]
    blade = np.asarray(blade, bool)
    w = max(float(width), 1.0)
    sigmas = sorted({1.0, max(1.0, 0.3 * w), max(1.0, 0.6 * w)})
    if ref_level is None:
        ref_level = layer_strength(layer_image, np.asarray(layer_mask, bool) & blade, sign, width)
    lab = np.zeros(blade.shape, np.int32)
    if not blade.any() or sign == 0 or not ref_level > 0:
        return lab, res.copy(), float(ref_level)
    ys, xs = np.nonzero(blade)
    pad = 8 + int(np.ceil(2 * w))
    y0, y1 = max(int(ys.min()) - pad, 0), min(int(ys.max()) + pad + 1, blade.shape[0])
    x0, x1 = max(int(xs.min()) - pad, 0), min(int(xs.max()) + pad + 1, blade.shape[1])
    box = (slice(y0, y1), slice(x0, x1))
    sub = _rimless(res[box], blade[box])  # see flatten_leftover
    lab[box] = _line_pieces(sub, blade[box], sigmas, sign, level * ref_level, w, min_length)
    filled = res.copy()
    if lab.any():
        from .prepared import _smooth_fill
        hole = _binary_dilation(lab[box] > 0, iterations=1) & blade[box]
        out = np.where(hole[..., None], _smooth_fill(sub, blade[box] & ~hole), sub).astype(np.float32)
        g = _grain(sub, blade[box] & ~hole, hole, int(np.ceil(2 * w)) + 2)
        out = np.where(hole[..., None], out - (out - cv2.GaussianBlur(out, (0, 0), 1.0)) + g, out)
        filled[box] = np.clip(out, 0.0, 1.0)
        lab[box] = np.where(hole, ndi.grey_dilation(lab[box], size=3), lab[box])
    return lab, filled, float(ref_level)


def layer_strength(layer_image, layer_mask, sign: float, width: float) -> float:
    """Median ridge strength (:func:`ridge_strength` at a layer's scales) of a layer on its own mask.

    Parameters
    ----------
    layer_image : (H, W, 3) float ndarray
        The image in which the layer was induced.
    layer_mask : (H, W) bool ndarray
        Its induced mask (0.0 is returned when empty).
    sign, width : float
        The layer's polarity and typical width (px).

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((40, 40, 3), 0.5, np.float32); img[5:35, 19:22] = 0.3
    >>> m = np.zeros((40, 40), bool); m[5:35, 19:22] = True
    >>> bool(layer_strength(img, m, -1.0, 3.0) > 0), layer_strength(img, m, 1.0, 3.0)
    (True, 0.0)
    """
    mask = np.asarray(layer_mask, bool)
    if not mask.any():
        return 0.0
    w = max(float(width), 1.0)
    sigmas = sorted({1.0, max(1.0, 0.3 * w), max(1.0, 0.6 * w)})
    ref = ridge_strength(np.asarray(layer_image, np.float32)[..., :3].mean(-1), sigmas, sign)
    return float(np.median(ref[mask]))


def _doubled_angle(mask: np.ndarray, sigma: float) -> np.ndarray:
    """Unit doubled-angle vectors (cos 2t, sin 2t) of the structure tensor of ``mask`` (t across its lines)."""
    m = cv2.GaussianBlur(np.asarray(mask, np.float32), (0, 0), max(0.7, 0.5 * sigma))
    gx = cv2.Sobel(m, cv2.CV_32F, 1, 0, ksize=3)
    gy = cv2.Sobel(m, cv2.CV_32F, 0, 1, ksize=3)
    jxx = cv2.GaussianBlur(gx * gx, (0, 0), sigma)
    jyy = cv2.GaussianBlur(gy * gy, (0, 0), sigma)
    jxy = cv2.GaussianBlur(gx * gy, (0, 0), sigma)
    c, s = jxx - jyy, 2.0 * jxy
    n = np.maximum(np.hypot(c, s), 1e-12)
    return np.stack([c / n, s / n], -1)


def parallel_lines(labels, footprint, reach: float, *, max_angle: float = 30.0, share: float = 0.5,
                   width: float = 2.0) -> np.ndarray:
    """Pixels of the line pieces ``labels`` that run beside ``footprint`` (within ``reach``, about parallel).

    The second half of the one-vein-system step (see :func:`own_lines`):
    ``labels`` are a background's own line pieces carried into a new leaf,
    ``footprint`` where a donor's layer of the same kind is pasted on it.
    A pixel is beside the footprint when it lies within ``reach`` px of it
    and the piece's direction there is within ``max_angle`` degrees of the
    footprint's direction at its nearest pixel. A piece with at least
    ``share`` of its pixels beside the footprint is taken whole (it is the
    same vein, moved); of the others only the pixels beside it, grown by
    ``width`` px along the piece.

    Parameters
    ----------
    labels : (H, W) int ndarray
        0 off the lines, one positive label per piece.
    footprint : (H, W) bool ndarray
        The pasted layer.
    reach : float
        Largest distance (px) between a line and the footprint.
    max_angle : float
        Largest angle (degrees) between their directions (default 30).
    share : float
        Share of a piece beside the footprint for it to go whole (default 0.5).
    width : float
        Growth (px) of the pixels taken from a piece that stays (default 2).

    Returns
    -------
    (H, W) bool ndarray

    Examples
    --------
    A line 6 px beside a pasted vein goes, one across it stays:

    >>> import numpy as np
    >>> lab = np.zeros((80, 80), np.int32); lab[10:70, 30:32] = 1; lab[50:52, 40:75] = 2
    >>> foot = np.zeros((80, 80), bool); foot[10:70, 37:40] = True
    >>> out = parallel_lines(lab, foot, 8.0)
    >>> bool(out[40, 30]), bool(out[50, 60])
    (True, False)
    """
    labels = np.asarray(labels)
    foot = np.asarray(footprint, bool)
    out = np.zeros(labels.shape, bool)
    if not foot.any() or not (labels > 0).any():
        return out
    lines = labels > 0
    ys, xs = np.nonzero(lines | foot)
    pad = int(np.ceil(reach)) + 8
    y0, y1 = max(int(ys.min()) - pad, 0), min(int(ys.max()) + pad + 1, labels.shape[0])
    x0, x1 = max(int(xs.min()) - pad, 0), min(int(xs.max()) + pad + 1, labels.shape[1])
    box = (slice(y0, y1), slice(x0, x1))
    lab, f, ln = labels[box], foot[box], lines[box]
    dist, (iy, ix) = ndi.distance_transform_edt(~f, return_indices=True)
    sig = max(1.5, 0.5 * float(width) + 1.0)
    o_line = _doubled_angle(ln, sig)
    o_foot = _doubled_angle(f, sig)[iy, ix]
    cos = (o_line * o_foot).sum(-1)
    beside = ln & (dist <= reach) & (cos >= np.cos(np.radians(2.0 * max_angle)))
    n = int(lab.max())
    tot = np.bincount(lab.ravel(), minlength=n + 1)
    hit = np.bincount(lab[beside].ravel(), minlength=n + 1)
    whole = (hit >= share * np.maximum(tot, 1)) & (tot > 0)
    whole[0] = False
    grown = _binary_dilation(beside, iterations=max(1, int(round(width)))) & ln
    out[box] = whole[lab] | grown
    return out
