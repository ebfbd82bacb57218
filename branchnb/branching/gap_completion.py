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


def _relight_setup(ex: np.ndarray, canvas: np.ndarray, covered: np.ndarray, regions: ExampleRegions,
                   body: np.ndarray, patch_size: int, dist: np.ndarray, dist_t: np.ndarray,
                   prior: float = 0.25):
    """Shading-free example and canvas for gap completion (going beyond the paper).

    The paper fills the gaps by hand. Copied automatically, square patches
    of a vignetted or unevenly lit photo (a fundus image) carry the light of
    the place they come from: bright and dark squares side by side that no
    seam hides. Here the example's background is shifted by its own
    large-scale shading (Gaussian, ``sigma = 2 * patch_size``: larger than a
    patch, so the texture inside a patch is kept) to its mean level, and the
    canvas by the shading of the fragments already in place (their
    background, averaged at the same scale; far from every fragment, their
    mean). The patches are chosen and blended on these level images; adding
    the canvas shading back lights every patch like the fragments around it,
    while pixels no patch touched come back exactly. (Additive, not a gain:
    a gain would amplify the noise of dark corners.)

    Away from the fragments the output's light tends (with weight ``prior``
    against the fragments' local coverage) to the example's light at the
    same distance from its branches: flat under vignetting, a glow that
    fades away from the bolts on a lit sky (``lightning_noaa``), so the light
    that is the subject is kept. Returns ``(example, canvas, offset)`` or
    None when there is no background to measure the light on.
    """
    n = min(ex.shape[2], 3)   # colour channels only (alpha is copied as is)
    bg_ex = ~(regions.forbidden | ndi.binary_dilation(regions.body | regions.branch_like, iterations=3))
    bg_t = covered & ~ndi.binary_dilation(body, iterations=3)
    if np.count_nonzero(bg_ex) < 64 or np.count_nonzero(bg_t) < 64:
        return None
    sigma = 2.0 * float(patch_size)
    shade_ex = _normalized_blur(ex[..., :n].astype(np.float64), bg_ex.astype(np.float64), sigma)
    logd = np.log1p(dist[bg_ex])
    mean = ex[..., :n][bg_ex].mean(axis=0)
    # the example's light as a function of the distance to its branches (a glow around lightning;
    # flat under vignetting): what the output's light tends to away from its fragments
    edges = np.linspace(0.0, float(logd.max()) + 1e-6, 17)
    k = np.clip(np.digitize(logd, edges) - 1, 0, 15)
    cnt = np.bincount(k, minlength=16)
    prof = np.stack([np.bincount(k, weights=shade_ex[..., c][bg_ex], minlength=16) for c in range(n)], 1)
    ok = cnt > 0
    prof = prof[ok] / cnt[ok, None]
    mid = 0.5 * (edges[:-1] + edges[1:])[ok]
    lt = np.log1p(dist_t)
    g = np.stack([np.interp(lt, mid, prof[:, c]) for c in range(n)], -1)
    # the fragments' light where they are (their background averaged at sigma), weighted by how
    # much of it lies around (coarse grid: smooth at that scale anyway)
    blur_t = _normalized_blur(canvas[..., :n].astype(np.float64), bg_t.astype(np.float64), sigma)
    H, W = bg_t.shape
    f = max(int(sigma // 6), 1)
    small = cv2.resize(bg_t.astype(np.float32), (max(W // f, 1), max(H // f, 1)), interpolation=cv2.INTER_AREA)
    den = cv2.resize(ndi.gaussian_filter(small, sigma / f, mode="nearest"), (W, H),
                     interpolation=cv2.INTER_LINEAR).astype(np.float64)[..., None]
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
