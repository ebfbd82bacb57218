"""Step 4 of image synthesis: gap completion (the paper did it by hand).

The pixels no fragment covers are quilted from branch-free example pixels
(:func:`branchnb.core.completion.complete_gaps`, with a quicker window search:
:mod:`.gap_quilting`) with graph-cut seams, relit
like the fragments around them (:func:`_relight_setup`), so no
pseudo-branch and no square patch of another brightness appears.
"""

from __future__ import annotations

import time

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.completion import complete_gaps
from .gap_quilting import quilt_gaps
from .regions import ExampleRegions, _normalized_blur

__all__: list[str] = []


#: Detail scale of the relighting, as a fraction of the patch side: the example's texture keeps
#: what varies faster than this (Gaussian sigma); slower light comes from the layout.
DETAIL_SCALE = 0.25
#: Scale of the example's light layout, as a fraction of its long side (Gaussian sigma).
LAYOUT_SCALE = 1.0 / 16.0


def _filled_blur(img: np.ndarray, weight: np.ndarray, sigma: float, levels: int = 5) -> np.ndarray:
    """:func:`~branchnb.branching.regions._normalized_blur` of ``img`` over ``weight``, defined
    everywhere: where few weighted pixels lie within ``sigma`` (a wide forbidden area), the average
    at twice, four times ... the scale takes over smoothly."""
    w = weight.astype(np.float64)
    out = _normalized_blur(img, w, sigma)
    den = _normalized_blur(w[..., None], np.ones_like(w), sigma)[..., 0]
    s = sigma
    for _ in range(levels):
        a = np.clip(den / 0.3, 0.0, 1.0)[..., None]
        if a.min() >= 1.0:
            break
        s *= 2.0
        coarse = _normalized_blur(img, w, s)
        out = a * out + (1.0 - a) * coarse
        den = np.maximum(den, _normalized_blur(w[..., None], np.ones_like(w), s)[..., 0])
    return out


def _relight_setup(ex: np.ndarray, canvas: np.ndarray, covered: np.ndarray, regions: ExampleRegions,
                   body: np.ndarray, patch_size: int, dist: np.ndarray, dist_t: np.ndarray,
                   prior: float = 1.0):
    """Shading-free example and canvas for gap completion (going beyond the paper).

    The paper fills the gaps by hand. Copied automatically, square patches
    of an unevenly lit photo (a vignetted fundus image, a night sky with
    bright clouds) carry the light of the place they come from: bright and
    dark squares side by side that no seam hides. Here the example's
    background loses its light slower than the detail scale (Gaussian,
    ``sigma = DETAIL_SCALE * patch_size``: a patch's texture is kept, its
    brightness level is not), and the canvas the light of the fragments
    already in place (their background, averaged at the same scale). The
    patches are chosen and blended on these level images; adding the
    output's light back lights every patch like the fragments around it,
    while pixels no patch touched come back exactly. (Additive, not a gain:
    a gain would amplify the noise of dark corners.)

    Away from the fragments the output's light tends (with weight ``prior``
    against the fragments' local share of the background) to the example's **light
    layout** at the same relative position: its background averaged at
    ``LAYOUT_SCALE`` of its long side (the dark top of a night sky, the
    bright clouds low in the middle, a fundus photo's vignetting), so the
    large-scale light of the example is kept rather than quilted from
    patches of bright and dark. Returns ``(example, canvas, offset)`` or
    None when there is no background to measure the light on.

    (Measured on a night sky with bright clouds, ``lightning_noaa`` at
    512 px: the mean difference of the 1/16-scale backgrounds, output
    against example, 0.24 -> 0.09; the gradient along the patch grid
    against elsewhere 1.16 -> 1.01. The earlier rule, a shading at
    ``2 * patch_size`` and the example's glow by distance to its branches,
    left bright and dark patches side by side.)
    """
    n = min(ex.shape[2], 3)   # colour channels only (alpha is copied as is)
    bg_ex = ~(regions.forbidden | ndi.binary_dilation(regions.body | regions.branch_like, iterations=3))
    bg_t = covered & ~ndi.binary_dilation(body, iterations=3)
    if np.count_nonzero(bg_ex) < 64 or np.count_nonzero(bg_t) < 64:
        return None
    sigma = DETAIL_SCALE * float(patch_size)
    exc = ex[..., :n].astype(np.float64)
    shade_ex = _filled_blur(exc, bg_ex, sigma)
    mean = exc[bg_ex].mean(axis=0)
    # the example's light layout, at the output's size (same relative position)
    H, W = bg_t.shape
    layout = _filled_blur(exc, bg_ex, LAYOUT_SCALE * max(ex.shape[:2]))
    g = cv2.resize(layout.astype(np.float32), (W, H), interpolation=cv2.INTER_LINEAR).reshape(H, W, n)
    # the fragments' light where they are (their background averaged at sigma), weighted by how
    # much of it lies around
    blur_t = _normalized_blur(canvas[..., :n].astype(np.float64), bg_t.astype(np.float64), sigma)
    den = _normalized_blur(bg_t.astype(np.float64)[..., None], np.ones((H, W)), sigma)
    shade_t = (blur_t * den + prior * g) / (den + prior)
    ex_flat = ex.copy()
    ex_flat[..., :n] = ex[..., :n] + (mean - shade_ex)
    offset = np.zeros(canvas.shape, np.float32)
    offset[..., :n] = (shade_t - mean).astype(np.float32)
    return ex_flat.astype(np.float32), (canvas - offset).astype(np.float32), offset


def _complete(out, ex: np.ndarray, regions: ExampleRegions, p, flat: bool, use_poisson: bool, pm_s, pm_t,
              labels_t, src_labels, rng: np.random.Generator, report, frag_share: float, timings: dict):
    """Gap completion of the fragments' canvas ``out`` (a ``_Canvas``, updated in place).

    Returns ``(fill, n_inpainted)``.
    """
    canvas, covered, body = out.canvas, out.covered, out.body
    fill = np.zeros(covered.shape, bool)
    n_inpainted = 0
    if p.completion and not covered.all():
        t1 = time.perf_counter()

        def sub_progress(frac, text):
            report(frag_share + (1.0 - frag_share) * frac, text)

        # Patches may only cut into a thin rim of the fragments (to hide the
        # disks' edges), never into the branches.
        rim = int(p.completion_rim)
        inner = ndi.binary_erosion(covered, iterations=rim, border_value=1) if rim > 0 else covered
        relit = None
        if p.relight_completion and not flat:
            relit = _relight_setup(ex, canvas, covered, regions, body, p.patch_size, pm_s.dist, pm_t.dist)
            if relit is not None:
                ex_fill, canvas, offset_t = relit
        ex_c = ex if relit is None else ex_fill
        kw = dict(patch_size=p.patch_size, overlap=p.patch_overlap, protect=(body & covered) | inner,
                  tolerance=p.completion_tolerance, forbid_weight=p.forbid_weight, min_free=p.min_free,
                  method=p.seams, poisson=use_poisson, anchored=p.anchors, anchor_weight=p.anchor_weight,
                  screen=p.completion_screen if p.anchors else 0.0, rng=rng, progress=sub_progress)
        if labels_t is None:    # the quicker window search of gap_quilting (issue 23)
            comp = quilt_gaps(canvas, covered, ex_c, regions.forbidden, **kw)
        else:                   # region by region (maps): the core's loop
            comp = complete_gaps(canvas, covered, ex_c, regions.forbidden, regions=labels_t,
                                 example_regions=src_labels, fast=True, **kw)
        if relit is not None:
            canvas += offset_t      # back to the output's own light (fragments: exactly as before)
            out.canvas = canvas
        fill = comp.filled
        out.source[fill] = comp.source[fill]
        out.frag_index[fill] = -1
        out.seams |= comp.seams
        out.total_seam += comp.seam_cost
        n_inpainted = comp.n_inpainted
        timings["completion"] = time.perf_counter() - t1
    return fill, n_inpainted
