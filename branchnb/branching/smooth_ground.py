"""Automatic extraction, beyond the paper: a silhouette of one solid colour on a smooth, shaded ground.

A winter tree against the sky, a bolt drawn on a gradient, vessels printed on a vignetted page: the lines
are one solid colour, the ground carries a gradient. Neither route of :func:`~.extraction.extract_structure`
fitted: the image is no binary mask (the gradient spans many levels, :func:`~.backgrounds.is_binary`), and
the ridge filter, tuned to lines up to ``sigma_max``, broke a tree's 16 px trunk from its 1 px twigs at
every place the width changes (an unseen 384 px winter tree came out as five pieces, the crown rooted
inside; its plain mask gives one piece rooted at the trunk). :func:`flattened_silhouette` takes the
ground's shading away (a robust low-order surface fit) and, where what is left is two-level, hands the
extraction a binary image to trace by its medial axis.
"""

from __future__ import annotations

import numpy as np

from ..core.image import as_float_image

__all__ = ["flattened_silhouette", "silhouette_colours"]

#: Robust spread (grey levels) of the ground about its fitted surface up to which the ground is smooth:
#: paper and sky, not a photograph's texture or grain.
SMOOTH_SD = 0.01
#: Least range of the fitted surface over the image: a flat ground is a binary image already.
MIN_SHADING = 0.04
#: Least share of the pixels on the ground, and least contrast of the ink against it.
MIN_GROUND = 0.5
MIN_CONTRAST = 0.25
#: Least share of the off-ground pixels within ``CORE_TOL`` x the contrast of the ink's own level (solid ink;
#: thin lines are mostly anti-aliased rims, so a small share), all of them on the ink's side of the ground.
MIN_CORE = 0.1
CORE_TOL = 0.15
MIN_ONE_SIDE = 0.97
#: Largest colour distance of an off-ground pixel from the mix of the ink and the ground under it (in its
#: own alpha) for :data:`MIN_MIXED` of them: one ink over the ground, not a second colour.
MIX_TOL = 0.04
MIN_MIXED = 0.9


def _surface(gray: np.ndarray, order: int = 2, iters: int = 4, step: int = 4, max_sd: float = np.inf):
    """Robust polynomial fit of ``gray`` over (x, y): ``(surface, residual, ground mask, robust sd)``; None
    when the fit fails or the ground's robust sd exceeds ``max_sd`` (checked on the subsampled fit, before the
    full-size surface is evaluated: a textured photo is turned away in a few milliseconds)."""
    h, w = gray.shape

    def design(yy, xx):
        x, y = xx / w - 0.5, yy / h - 0.5
        return np.stack([x ** (d - i) * y ** i for d in range(order + 1) for i in range(d + 1)], -1)

    ys, xs = np.mgrid[0:h:step, 0:w:step]
    a = design(ys.ravel().astype(np.float64), xs.ravel().astype(np.float64))
    v = gray[::step, ::step].ravel()
    keep = np.ones(len(v), bool)
    sd = 0.0
    for _ in range(iters):
        if keep.sum() < a.shape[1] * 4:
            return None
        coef = np.linalg.lstsq(a[keep], v[keep], rcond=None)[0]
        res = v - a @ coef
        sd = 1.4826 * float(np.median(np.abs(res[keep]))) + 1e-4
        keep = np.abs(res) <= max(3.0 * sd, 0.01)
    if sd > max_sd:
        return None
    yy, xx = np.mgrid[0:h, 0:w]
    surf = (design(yy.astype(np.float64), xx.astype(np.float64)) @ coef).reshape(h, w)
    res = gray - surf
    return surf, res, np.abs(res) <= max(3.0 * sd, 0.01), sd


def _silhouette(image):
    """``(alpha, ink colour, ground)`` of one solid ink on a smooth shaded ground (``ground``: the fitted
    (H, W, 3) shading), or None (see :func:`flattened_silhouette`)."""
    img = as_float_image(image, name="image").astype(np.float64)
    if img.shape[2] >= 3:
        # (an RGBA image's alpha is left out: a silhouette's ground is painted, not transparent)
        rgb = img[..., :3]
        g = rgb @ np.array([0.2125, 0.7154, 0.0721])
    else:
        rgb, g = None, img[..., 0]
    if min(g.shape) < 16:
        return None
    fit = _surface(g, max_sd=SMOOTH_SD)
    if fit is None:
        return None
    surf, res, ground, sd = fit
    if sd > SMOOTH_SD or float(np.ptp(surf[ground])) < MIN_SHADING or ground.mean() < MIN_GROUND:
        return None
    off = ~ground
    if off.sum() < 20:
        return None
    side = np.sign(np.median(res[off]))
    if np.mean(res[off] * side > 0) < MIN_ONE_SIDE:
        return None
    ink = float(np.percentile(g[off], 2 if side < 0 else 98))
    # how far the ink stands off the ground where it lies (the shading moves the ground, not the ink)
    lift = ink - surf
    if np.min(lift * side) < MIN_CONTRAST:
        return None
    if np.mean(np.abs(g[off] - ink) <= CORE_TOL * np.abs(lift[off])) < MIN_CORE:
        return None
    alpha = np.clip(res / lift, 0.0, 1.0)
    if rgb is not None:
        fits = [_surface(rgb[..., c]) for c in range(3)]
        ground_rgb = np.stack([f[0] if f is not None else surf for f in fits], -1)
        core = off & (alpha >= 0.9)
        ink_rgb = np.median(rgb[core], axis=0)
        mix = alpha[..., None] * ink_rgb + (1.0 - alpha[..., None]) * ground_rgb
        if np.mean(np.abs(rgb[off] - mix[off]).max(-1) <= MIX_TOL) < MIN_MIXED:
            return None
    else:
        ink_rgb = np.full(3, ink)
        ground_rgb = np.repeat(surf[..., None], 3, -1)
    return alpha, ink_rgb, ground_rgb


def flattened_silhouette(image) -> np.ndarray | None:
    """A binary-like image of the solid-colour lines on a smooth, shaded ground (``None``: not such an image).

    Parameters
    ----------
    image : (H, W) or (H, W, 3) array_like
        Luminance or RGB in [0, 1].

    Returns
    -------
    (H, W) float32 ndarray or None
        0 on the lines, 1 on the ground, anti-aliased rims between; ``None`` when the ground is flat
        (already binary), textured (more than :data:`SMOOTH_SD` about its fitted shading), covers less than
        :data:`MIN_GROUND` of the image, or the rest is not one solid ink at least :data:`MIN_CONTRAST` off it.

    Notes
    -----
    Beyond the paper (issue 23). The ground's shading is a quadratic surface fitted to the pixels that stay
    within three robust deviations of it (ink drops out after the first fit). The ink's level is the far
    end of the off-ground levels (thin lines are mostly anti-aliased rims); in colour, every off-ground
    pixel must be a mix of that ink and the ground under it. Each pixel is scaled between the ground under
    it and the ink; dark and light lines alike come out dark.

    Examples
    --------
    >>> import numpy as np
    >>> sky = np.linspace(0.5, 0.9, 64)[:, None] * np.ones((64, 64))
    >>> sky[:, 30:34] = 0.1                      # a dark trunk on a shaded sky
    >>> flat = flattened_silhouette(sky)
    >>> float(flat[:, 31].max()), float(flat[:, 5].min())
    (0.0, 1.0)
    >>> flattened_silhouette(np.full((64, 64), 0.8)) is None     # nothing drawn
    True
    """
    found = _silhouette(image)
    return None if found is None else (1.0 - found[0]).astype(np.float32)


def silhouette_colours(image) -> tuple[np.ndarray, np.ndarray] | None:
    """The ink colour and the shaded ground of a silhouette on a smooth ground (``None``: not such an image).

    Parameters
    ----------
    image : (H, W) or (H, W, 3) array_like
        Luminance or RGB in [0, 1].

    Returns
    -------
    (ink, ground) : (3,) and (H, W, 3) float32 ndarrays, or None
        The solid ink's colour and the ground's fitted shading under the whole image (the ink taken out);
        see :func:`flattened_silhouette`.

    Examples
    --------
    >>> import numpy as np
    >>> sky = np.linspace(0.5, 0.9, 64)[:, None] * np.ones((64, 64))
    >>> sky[:, 30:34] = 0.1
    >>> ink, ground = silhouette_colours(sky)
    >>> round(float(ground[32, 31, 0]), 2), round(float(sky[32, 5]), 2)
    (0.7, 0.7)
    """
    found = _silhouette(image)
    if found is None:
        return None
    return np.asarray(found[1], np.float32), np.clip(found[2], 0.0, 1.0).astype(np.float32)
