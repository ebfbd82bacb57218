"""Texture correction: where a warp stretches or squeezes, put back unwarped texture.

A non-rigid warp that moves a lobe keeps the texture's *content* but
distorts its *scale*: where it stretches, veins get fat and the grain
blurs; where it squeezes, they get thin and crowded. In the spirit of
Fang & Hart's texture correction, those places are re-textured with
patches of the **unwarped** exemplar that fit what is around them.

Which pixels
------------
For the warp's dense map ``m`` (every output pixel's source position, as
used by :func:`branchnb.core.warp.remap`), the Jacobian ``J = dm/dx`` says
how many source pixels one output pixel spans along its two principal
directions: its singular values ``s_1 >= s_2``. A global change of size is
not a distortion (the leaves of one kind differ in size), so the singular
values are divided by the median of ``sqrt(s_1 s_2)`` over the region
first. A pixel is **distorted** when a relative singular value leaves
``band = (0.5, 2.0)``: the warp magnifies the texture more than two
times (``s < 0.5``) or shrinks it more than two times (``s > 2``) along some
direction. The band is this package's choice (the paper gives none): a
factor of two is where the change of vein width and grain becomes
obvious next to undistorted texture.

How
---
The distorted pixels (grown by a few pixels, so the seams fall in
undistorted texture) are filled by :func:`branchnb.core.completion.complete_gaps`:
patch quilting from the unwarped source image, rescaled by the median
scale so patches have the output's texture scale, with windows restricted
to the source's leaf, matched on the known pixels around each cell and
composed with graph-cut seams and a gradient-domain correction
(:func:`branchnb.core.blending.compose_piece`).

References
----------
H. Fang, J. C. Hart, "Textureshop: texture synthesis as a photograph
editing tool", SIGGRAPH 2004 (texture correction of distorted regions).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from ..core.completion import CompletionResult, complete_gaps
from ..core.image import as_float_image, as_mask
from ..core.morphology import _binary_dilation, _binary_erosion
from ..core.random import as_rng
from ..core.validate import COORD_LIMIT, Int, check_finite, checked, real_array

__all__ = ["jacobian_singular_values", "distorted_pixels", "correct_texture", "TextureCorrection"]


def _check_map(warp_map, name="warp_map") -> np.ndarray:
    # float32 maps (what the synthesis makes) stay float32: converting and
    # checking a megapixel map twice in float64 was a tenth of a new leaf's time.
    dt = np.float32 if getattr(warp_map, "dtype", None) == np.float32 else np.float64
    m = real_array(warp_map, name, finite=False, dtype=dt)
    if m.ndim != 3 or m.shape[2] != 2 or min(m.shape[:2]) < 2:
        raise ValueError(f"{name} must have shape (H, W, 2) with H, W >= 2, got {m.shape}")
    return check_finite(m, name, limit=COORD_LIMIT)


def jacobian_singular_values(warp_map) -> np.ndarray:
    """Singular values ``(s_1, s_2)``, ``s_1 >= s_2``, of the map's Jacobian at every pixel.

    Parameters
    ----------
    warp_map : (H, W, 2) array_like
        Source ``(x, y)`` of every output pixel.

    Returns
    -------
    (H, W, 2) float32 ndarray

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[0:8, 0:8].astype(float)
    >>> s = jacobian_singular_values(np.dstack([3 * xx, 0.5 * yy]))
    >>> np.allclose(s[4, 4], [3, 0.5])
    True
    """
    m = _check_map(warp_map)
    dxdc = np.gradient(m[..., 0], axis=1)
    dxdr = np.gradient(m[..., 0], axis=0)
    dydc = np.gradient(m[..., 1], axis=1)
    dydr = np.gradient(m[..., 1], axis=0)
    fro = dxdc ** 2 + dxdr ** 2 + dydc ** 2 + dydr ** 2
    det = dxdc * dydr - dxdr * dydc
    disc = np.sqrt(np.maximum(fro ** 2 - 4 * det ** 2, 0.0))
    s1 = np.sqrt(np.maximum((fro + disc) / 2, 0.0))
    s2 = np.sqrt(np.maximum((fro - disc) / 2, 0.0))
    return np.dstack([s1, s2]).astype(np.float32)


def _check_band(band):
    try:
        lo, hi = (float(v) for v in band)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"band must be (low, high), got {band!r}") from exc
    if not (0 < lo < 1 < hi and np.isfinite(hi)):
        raise ValueError(f"band must satisfy 0 < low < 1 < high, got {band!r}")
    return lo, hi


def distorted_pixels(warp_map, *, band=(0.5, 2.0), mask=None) -> tuple[np.ndarray, float]:
    """Pixels where the warp's relative singular values leave ``band``.

    Parameters
    ----------
    warp_map : (H, W, 2) array_like
        Source ``(x, y)`` of every output pixel (as for
        :func:`branchnb.core.warp.remap`).
    band : (float, float)
        Allowed range of the singular values relative to the median scale,
        ``0 < low < 1 < high`` (default ``(0.5, 2.0)``: this package's
        choice, the paper gives none).
    mask : (H, W) bool array_like, optional
        Region considered (e.g. the warped blade); the median scale is taken there.

    Returns
    -------
    distorted : (H, W) bool ndarray
    scale : float
        The median scale ``sqrt(s_1 s_2)`` (source pixels per output pixel).

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[0:16, 0:16].astype(float)
    >>> mx = np.where(xx < 8, xx, 8 + 3 * (xx - 8))   # right half squeezed 3 times
    >>> bad, s = distorted_pixels(np.dstack([mx, yy]))
    >>> bool(bad[:, 12].all()), bool(bad[:, 3].any())
    (True, False)
    """
    lo, hi = _check_band(band)
    sv = jacobian_singular_values(warp_map)
    h, w = sv.shape[:2]
    region = np.ones((h, w), bool) if mask is None else as_mask(mask, shape=(h, w), name="mask", like="warp_map")
    if not region.any():
        return np.zeros((h, w), bool), 1.0
    geo = np.sqrt(sv[..., 0] * sv[..., 1])
    scale = float(np.median(geo[region]))
    if not scale > 0:
        raise ValueError("warp_map collapses the region to a point (zero scale)")
    rel = sv / scale
    bad = ((rel[..., 0] > hi) | (rel[..., 1] < lo)) & region
    return bad, scale


@dataclass
class TextureCorrection:
    """Result of :func:`correct_texture`.

    Parameters
    ----------
    image : (H, W, C) float32 ndarray
        The corrected image (alpha, if any, unchanged).
    distorted : (H, W) bool ndarray
        Pixels found outside the band.
    replaced : (H, W) bool ndarray
        Pixels re-textured (the distorted ones grown by ``grow`` pixels).
    scale : float
        Median warp scale (source pixels per output pixel).
    completion : CompletionResult or None
        The patch quilting's record (:func:`branchnb.core.completion.complete_gaps`);
        None when no pixel was distorted.
    """

    image: np.ndarray
    distorted: np.ndarray
    replaced: np.ndarray
    scale: float
    completion: CompletionResult | None


@checked(grow=Int(0, 1000), patch_size=Int(3, 1024))
def correct_texture(warped, warp_map, source_image, *, band=(0.5, 2.0), mask=None, source_mask=None,
                    grow: int = 3, patch_size: int | None = None, rng=None, **completion_kwargs) -> TextureCorrection:
    """Re-texture the strongly stretched or squeezed parts of a warped image.

    Parameters
    ----------
    warped : (H, W, C) array_like
        The warped image (``remap(source_image, warp_map)``), RGB or RGBA.
    warp_map : (H, W, 2) array_like
        Source position of every pixel of ``warped``.
    source_image : (h, w, C) array_like
        The unwarped image the texture comes from.
    band : (float, float)
        Allowed relative singular values of the warp (see :func:`distorted_pixels`).
    mask : (H, W) bool array_like, optional
        Where ``warped`` holds the leaf (default: alpha > 0.5, or everything).
    source_mask : (h, w) bool array_like, optional
        Source pixels that may be copied (default: alpha > 0.5, or everything).
    grow : int
        Distorted regions are grown by this many pixels before filling.
    patch_size : int, optional
        Patch side; default ``max(8, min(H, W) // 24)``.
    rng : {numpy.random.Generator, int}, optional
        Seeds the patch quilting's choice among well-matching patches.
    **completion_kwargs
        Passed to :func:`branchnb.core.completion.complete_gaps`.

    Returns
    -------
    TextureCorrection

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> src = rng.random((64, 64, 3)).astype(np.float32)
    >>> yy, xx = np.mgrid[0:64, 0:64].astype(np.float32)
    >>> mx = np.where(xx < 40, xx, 40 + 0.3 * (xx - 40))   # right part stretched
    >>> from branchnb.core.warp import remap
    >>> warped, _ = remap(src, mx, yy)
    >>> res = correct_texture(warped, np.dstack([mx, yy]), src, rng=0)
    >>> bool(res.replaced[:, 50].all()), bool(res.replaced[:, 10].any())
    (True, False)
    """
    img = as_float_image(warped, name="warped")
    m = _check_map(warp_map)
    h, w = img.shape[:2]
    if m.shape[:2] != (h, w):
        raise ValueError(f"warp_map must have the shape of warped {(h, w)}, got {m.shape[:2]}")
    src = as_float_image(source_image, name="source_image")
    if src.shape[2] != img.shape[2] and not (min(src.shape[2], img.shape[2]) >= 3):
        raise ValueError(f"source_image has {src.shape[2]} channels, warped has {img.shape[2]}")
    if isinstance(grow, bool) or not isinstance(grow, (int, np.integer)) or grow < 0:
        raise ValueError(f"grow must be an int >= 0, got {grow!r}")
    if mask is None:
        region = img[..., 3] > 0.5 if img.shape[2] == 4 else np.ones((h, w), bool)
    else:
        region = as_mask(mask, shape=(h, w), name="mask")
    if source_mask is None:
        allowed = src[..., 3] > 0.5 if src.shape[2] == 4 else np.ones(src.shape[:2], bool)
    else:
        allowed = as_mask(source_mask, shape=src.shape[:2], name="source_mask")
    distorted, scale = distorted_pixels(m, band=band, mask=region)
    out = img.copy()
    if not distorted.any():
        return TextureCorrection(out, distorted, distorted.copy(), scale, None)
    replaced = (_binary_dilation(distorted, iterations=grow) if grow else distorted) & region
    n_colour = 3 if img.shape[2] >= 3 else 1
    # The source at the output's texture scale.
    s = 1.0 / scale
    sh, sw = max(int(round(src.shape[0] * s)), 8), max(int(round(src.shape[1] * s)), 8)
    interp = cv2.INTER_AREA if s < 1 else cv2.INTER_LINEAR
    example = cv2.resize(np.ascontiguousarray(src[..., :n_colour]), (sw, sh), interpolation=interp)
    if example.ndim == 2:
        example = example[..., None]
    allowed_s = cv2.resize(allowed.astype(np.float32), (sw, sh), interpolation=cv2.INTER_AREA) > 0.99
    ps = int(patch_size) if patch_size is not None else max(8, min(h, w) // 24)
    if ps < 4:
        raise ValueError(f"patch_size must be >= 4, got {patch_size}")
    # Copy only from well inside the source leaf (no background at patch edges).
    forbidden = ~_binary_erosion(allowed_s, iterations=2)
    if forbidden.all():
        raise ValueError("source_mask leaves no pixels to copy texture from")
    canvas = np.ascontiguousarray(out[..., :n_colour])
    covered = ~replaced
    comp = complete_gaps(canvas, covered, np.ascontiguousarray(example, np.float32), forbidden,
                         patch_size=ps, rng=as_rng(rng), **completion_kwargs)
    out[..., :n_colour] = canvas
    return TextureCorrection(np.clip(out, 0, 1).astype(np.float32), distorted, replaced, scale, comp)


# Texture correction of a new leaf (see :mod:`branchnb.leaves.synthesis`, step 4).

def _masked_blur(img, mask, sigma):
    """Gaussian blur of ``img`` over ``mask`` only (normalised convolution); ``img`` outside it.

    A blur this wide (``sigma`` ~ 20 px at 1 MP) is smooth: it is taken on
    the image reduced by about ``sigma / 3`` and brought back bilinearly
    (at full size it was a fifth of a new leaf's time at 1 MP).
    """
    img = np.asarray(img, np.float32)
    m = np.asarray(mask, bool)
    f = max(1, int(sigma // 3))
    h, w = m.shape
    mf = m.astype(np.float32)
    num = np.ascontiguousarray(img * mf[..., None])
    if f > 1:
        size = (max(1, -(-w // f)), max(1, -(-h // f)))
        mf_s = cv2.resize(mf, size, interpolation=cv2.INTER_AREA)
        num_s = cv2.resize(num, size, interpolation=cv2.INTER_AREA)
        wb = cv2.GaussianBlur(mf_s, (0, 0), sigma / f)
        nb = cv2.GaussianBlur(num_s, (0, 0), sigma / f)
        if nb.ndim == 2:
            nb = nb[..., None]
        low = nb / np.maximum(wb, 1e-6)[..., None]
        low = cv2.resize(low, (w, h), interpolation=cv2.INTER_LINEAR).reshape(h, w, -1)
    else:
        wb = cv2.GaussianBlur(mf, (0, 0), sigma)
        nb = cv2.GaussianBlur(num, (0, 0), sigma).reshape(num.shape)
        low = nb / np.maximum(wb, 1e-6)[..., None]
    return np.where(m[..., None], low, img).astype(np.float32)


def _correct(rgb, blade, mapping, source, source_blade, rng, source_detail=None, patch_size=None):
    """Texture correction of the warped background, on its detail only.

    The distorted pixels get quilted *detail* (each image minus its blur
    at half a patch side) of the unwarped source over the warped image's
    own blur: the patches bring back grain and fine veins but not colours
    from elsewhere on the leaf. (Beyond the paper; quilting whole colours,
    a leaf with a smooth large-scale gradient, drawn or lit, came out with
    blocky patches of the wrong shade: a drawn maple's shape over two
    drawn oaks' fill. On a gradient with grain, stretched 3.3x over half
    its width: mean change of the blurred colour of the corrected pixels
    0.039-0.046 -> 0.004-0.005, their Laplacian variance unchanged; see
    the test.) Everything is computed on the new blade's bounding box
    (plus a patch side), with the patch side of the whole canvas;
    ``source_detail`` is the source's detail image when it is cached;
    ``patch_size`` the patch side (None: that of ``blade``'s canvas; given
    when ``rgb`` is a box of the canvas).
    """
    if not blade.any():
        return rgb
    full = blade.shape
    ps = max(8, min(full) // 24) if patch_size is None else int(patch_size)
    sigma = ps / 2.0
    ys, xs = np.nonzero(blade)
    pad = 2 * ps
    y0, y1 = max(0, ys.min() - pad), min(full[0], ys.max() + pad + 1)
    x0, x1 = max(0, xs.min() - pad), min(full[1], xs.max() + pad + 1)
    box = (slice(y0, y1), slice(x0, x1))
    if y1 - y0 < 2 or x1 - x0 < 2:
        return rgb
    sub, b = np.ascontiguousarray(rgb[box]), blade[box]
    low = _masked_blur(sub, b, sigma)
    detail = np.clip(sub - low + 0.5, 0, 1)
    if source_detail is None:
        source_detail = _detail(source, source_blade, sigma)
    try:
        res = correct_texture(detail, np.ascontiguousarray(mapping[box]), source_detail, mask=b,
                              source_mask=source_blade, rng=rng, patch_size=ps)
    except ValueError:
        return rgb  # nothing to copy from: keep the warped texture
    out = rgb.copy()
    rep = res.replaced
    o = out[box]
    o[rep] = np.clip(low[rep] + res.image[rep] - 0.5, 0, 1)
    return out


def _detail(src, blade, sigma):
    """``src`` minus its blur over ``blade`` (sigma px), plus 0.5: the detail texture correction quilts."""
    src = np.asarray(src, np.float32)[..., :3]
    return np.clip(src - _masked_blur(src, np.asarray(blade, bool), sigma) + 0.5, 0, 1)
