"""Residuals (the paper's Fig. 7): an induced layer's pixels filled from the rest of the
same leaf before the next layer is induced (see :mod:`branchnb.leaves.induction`).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.completion import complete_gaps
from ..core.image import as_mask, as_rgb, extend_nearest
from ..core.morphology import _binary_dilation, _binary_erosion, _binary_opening

__all__ = ["remove_layer", "telea"]

#: Margin (px) around the blade's box :func:`remove_layer` works in.
BOX_PAD = 8


def telea(image: np.ndarray, hole: np.ndarray, radius: float = 3.0) -> np.ndarray:
    """OpenCV Telea inpainting of a float image, channel by channel at 16 bits.

    (OpenCV 5's float32 path returns values far outside the input range, so
    the channels go through uint16.)

    Parameters
    ----------
    image : (H, W, C) float ndarray
        Values in [0, 1] (clipped).
    hole : (H, W) bool or uint8 ndarray
        Pixels to fill (non-zero).
    radius : float
        Telea's neighbourhood radius in pixels (default 3).

    Returns
    -------
    (H, W, C) float32 ndarray
    """
    h8 = np.asarray(hole, np.uint8)
    out = np.empty(image.shape, np.float32)
    for c in range(image.shape[2]):
        ch = np.round(np.clip(image[..., c], 0, 1) * 65535).astype(np.uint16)
        out[..., c] = cv2.inpaint(ch, h8, radius, cv2.INPAINT_TELEA).astype(np.float32) / 65535.0
    return out


def remove_layer(image, blade, mask, *, grow: int = 1, thin_width: float = 6.0,
                 patch_size: int | None = None, rng=None) -> np.ndarray:
    """Fill the pixels of an induced layer from the rest of the same leaf (the residual).

    Thin parts of the layer (veins: at most ``thin_width`` pixels across,
    and elongated parts of any width) are filled by OpenCV's Telea inpainting, which continues the blade's
    colour across a few pixels without visible blur; wide parts (spots)
    by example-based patch quilting with graph-cut seams
    (:func:`branchnb.core.completion.complete_gaps`) from the leaf's
    layer-free blade, which keeps the blade's texture where diffusion
    would leave a smooth blot. OpenCV's shift-map inpainting
    (``cv2.xphoto.inpaint``) fills as well as quilting but takes about 7 s
    per megapixel and layer, too slow for the 30 s analysis budget.

    Parameters
    ----------
    image : (H, W, 3|4) array_like
        The exemplar (or its residual so far), RGB(A) in [0, 1].
    blade : (H, W) bool
        Its blade; fills come from the blade outside ``mask``.
    mask : (H, W) bool
        The layer's pixels.
    grow : int
        The mask is grown by this many pixels first: a layer's anti-aliased
        rim has mixed colours that would otherwise stay as a ghost outline.
    thin_width : float
        Parts up to this width (px) count as thin.
    patch_size : int, optional
        Quilting patch side; by default 5 % of the leaf's size
        (``sqrt(blade area)``), between 8 and 48 px.
    rng : int or Generator
        Seeds the patch quilting of wide parts.

    Returns
    -------
    (H, W, 3) float32 ndarray
        The residual (unchanged outside ``mask``).
    """
    rgb = as_rgb(image, name="image")
    blade = as_mask(blade, shape=rgb.shape[:2], name="blade")
    mask = as_mask(mask, shape=rgb.shape[:2], name="mask") & blade
    out = rgb.copy()
    if not mask.any():
        return out
    rows, cols = np.flatnonzero(blade.any(1)), np.flatnonzero(blade.any(0))
    pad = BOX_PAD + int(grow)
    y0, y1 = max(int(rows[0]) - pad, 0), min(int(rows[-1]) + 1 + pad, rgb.shape[0])
    x0, x1 = max(int(cols[0]) - pad, 0), min(int(cols[-1]) + 1 + pad, rgb.shape[1])
    if (y1 - y0) * (x1 - x0) < 0.9 * blade.size:
        # Only the blade's box changes: work there (a padded canvas is 2-5x
        # larger; the nearest-colour extension and the fills only read the blade).
        out[y0:y1, x0:x1] = remove_layer(rgb[y0:y1, x0:x1], blade[y0:y1, x0:x1], mask[y0:y1, x0:x1], grow=grow,
                                         thin_width=thin_width, patch_size=patch_size, rng=rng)
        return out
    if grow > 0:
        mask = _binary_dilation(mask, iterations=int(grow)) & blade
    if patch_size is None:
        patch_size = int(np.clip(round(0.05 * np.sqrt(blade.sum())), 8, 48))
    # Colour outside the blade must not bleed in: extend the blade's own
    # colours outwards first (nearest blade pixel).
    keep = blade & ~mask
    if not keep.any():
        return out
    ext = extend_nearest(rgb, keep)
    # Wide parts: what survives an opening by a disk of diameter thin_width
    # (spots, a broad petiole), grown back by a pixel; the rest is thin.
    r = max(1, int(np.ceil(thin_width / 2)))
    yy, xx = np.mgrid[-r:r + 1, -r:r + 1]
    disk = xx**2 + yy**2 <= r * r
    wide = _binary_dilation(_binary_opening(mask, structure=disk), iterations=1) & mask
    # Only blob-like wide parts (spots); elongated ones (a broad petiole or
    # midrib) are filled along their length by diffusion as well.
    wl, nw = ndi.label(wide, structure=np.ones((3, 3)))
    for i, sl in enumerate(ndi.find_objects(wl), start=1):
        side = max(sl[0].stop - sl[0].start, sl[1].stop - sl[1].start)
        part = wl[sl] == i
        if part.sum() < 0.15 * side * side:
            wide[sl] &= ~part
    thin = mask & ~wide
    filled = telea(ext, mask)
    out[thin] = filled[thin]
    if wide.any():
        canvas = filled.copy()
        covered = ~wide
        forbidden = _binary_dilation(mask, iterations=2) | ~_binary_erosion(blade, iterations=2)
        if (~forbidden).sum() > 4 * patch_size**2:
            # One canvas per wide part: its bounding box plus a ring of known
            # pixels, filled by one example patch of that size (more where
            # the patch's own layer pixels leave holes), then blended.
            wl, _ = ndi.label(wide, structure=np.ones((3, 3)))
            ring = max(3, patch_size // 4)
            H, W = rgb.shape[:2]
            for sl in ndi.find_objects(wl):
                r0, r1 = max(sl[0].start - ring, 0), min(sl[0].stop + ring, H)
                c0, c1 = max(sl[1].start - ring, 0), min(sl[1].stop + ring, W)
                size = max(r1 - r0, c1 - c0, patch_size)
                # The example: the leaf around the part (three part sizes
                # each way), nearby texture matches best and is fast to search.
                reach = 3 * size
                er0, er1 = max(r0 - reach, 0), min(r1 + reach, H)
                ec0, ec1 = max(c0 - reach, 0), min(c1 + reach, W)
                sub = canvas[r0:r1, c0:c1].copy()
                cov = covered[r0:r1, c0:c1].copy()
                try:
                    complete_gaps(sub, cov, ext[er0:er1, ec0:ec1], forbidden[er0:er1, ec0:ec1],
                                  patch_size=size, poisson=True, rng=rng)
                except ValueError:
                    continue  # too little layer-free texture: keep the diffusion fill
                canvas[r0:r1, c0:c1] = sub
        out[wide] = canvas[wide]
    out[~blade] = rgb[~blade]
    return np.clip(out, 0.0, 1.0).astype(np.float32)
