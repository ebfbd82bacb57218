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
from .regions import ExampleRegions

__all__: list[str] = []


#: Detail scale of the relighting, as a fraction of the patch side: the example's texture keeps
#: what varies faster than this (Gaussian sigma); slower light comes from the layout.
DETAIL_SCALE = 0.25
#: Scale of the example's light layout, as a fraction of its long side (Gaussian sigma; at least the
#: patch side, so that a small example's lines leave no dark trace in it).
LAYOUT_SCALE = 1.0 / 16.0
#: An example whose light layout varies by less than this factor (95th over 5th percentile) is evenly
#: lit: only its light layout is taken out of the gaps' texture (relit at the detail scale, a
#: field's patches came out as one even green).
SHADED = 1.2
#: Share of the ground's detail-scale variation the light layout may leave unexplained for the gaps
#: to be relit at the detail scale (vignetted grounds 0.05-0.13; fields, blotches, stripes 0.23-0.95).
TEXTURE_SHARE = 0.2
#: Side of the quilting patches on a patchwork ground, as a fraction of its patches' typical diameter.
PATCHWORK_PATCH = 0.5
#: ``line_margin`` of hub examples (:func:`_complete`, branching116): the fragments' pixels within
#: r + this many px of a target line are neutral in the gaps' correction. With r + 1 px the lines' soft
#: edges were its boundary and glowed 4-5 px into the ground, most round free ends, where a thin
#: twig's disk (``min_radius``) stops about at the tip. Stray line colour per tip (median,
#: :mod:`._hub_image_check`, ten hub examples 256-768 px): 0.20-1.13 -> 0.09-0.25 (example 0.13-0.90;
#: :func:`.radial._off_hubs` alone left about 0.5 on coral and neuron_dark 384 s1)
HUB_LINE_MARGIN = 3.0
#: ``line_margin`` of every other example (:func:`_complete`; beyond the paper, issue 23): the same glow
#: round free ends and junctions where the lines stand out strongly from their ground (light frost-like
#: dendrites on a dark graded sky of my own, 256-512 px: fine ground blotchiness, std of a 2-px over a
#: 16-px blur 2+ px off the lines, 0.0069-0.0115 -> 0.0037-0.0087, example 0.0013-0.0018; 3 px gave
#: 0.0027-0.0058 but kept neighbouring cracks' bits round a cracked mud's lines as specks, 10 -> 21);
#: within noise on dark lines over light grounds (``_ground_texture_check``, ``_vessel_check``)
LINE_MARGIN = 2.0
#: hub examples: within ``HUB_LINE_MARGIN`` of a line, a canvas pixel differing from a new fragment by
#: more than this share of the example's line contrast (in a channel) is no boundary of the fragment's
#: gradient-domain correction (a line's edge against the other's ground; branching119, measured with
#: ``_hub_image_check`` on coral / neuron / neuron_dark 256-512 px)
HUB_SEAM_MISMATCH = 0.3


def _coarse_blur(img: np.ndarray, weight: np.ndarray, sigma: float, levels: int = 0) -> np.ndarray:
    """Gaussian average of ``img`` over ``weight`` (normalised), on a grid ``sigma / 3`` times coarser
    (float32, interpolated back: the result is smooth at that scale anyway).

    With ``levels``, the average is defined everywhere: where few weighted
    pixels lie within ``sigma`` (a wide forbidden area), the average at
    twice, four times ... the scale (each on its own coarser grid) takes
    over smoothly.
    """
    H, W = weight.shape
    n = img.shape[2]
    wimg = (img * weight[..., None]).astype(np.float32)
    wt32 = weight.astype(np.float32)

    def average(scale, size):
        f = max(int(scale // 3), 1)
        hs, ws = max(H // f, 1), max(W // f, 1)
        wt = cv2.resize(wt32, (ws, hs), interpolation=cv2.INTER_AREA)
        iw = cv2.resize(wimg, (ws, hs), interpolation=cv2.INTER_AREA).reshape(hs, ws, n)
        den = cv2.GaussianBlur(wt, (0, 0), scale / f, borderType=cv2.BORDER_REPLICATE)
        num = cv2.GaussianBlur(iw, (0, 0), scale / f, borderType=cv2.BORDER_REPLICATE).reshape(hs, ws, n)
        if (ws, hs) != size:
            den = cv2.resize(den, size, interpolation=cv2.INTER_LINEAR)
            num = cv2.resize(num, size, interpolation=cv2.INTER_LINEAR).reshape(size[1], size[0], n)
        return num / np.maximum(den, 1e-6)[..., None], den

    f0 = max(int(sigma // 3), 1)
    size = (max(W // f0, 1), max(H // f0, 1))
    out, den = average(sigma, size)
    scale = sigma
    for _ in range(levels):
        a = np.clip(den / 0.3, 0.0, 1.0)[..., None]
        if a.min() >= 1.0 or scale > max(H, W):
            break
        scale *= 2.0
        coarse, d2 = average(scale, size)
        out = a * out + (1.0 - a) * coarse
        den = np.maximum(den, d2)
    if den.min() <= 1e-6:
        mean = wimg.sum((0, 1)) / max(float(weight.sum()), 1.0)
        out = np.where(den[..., None] > 1e-6, out, mean.astype(np.float32))
    return cv2.resize(out, (W, H), interpolation=cv2.INTER_LINEAR).reshape(H, W, n).astype(np.float64)


def light_layout(ex: np.ndarray, regions: ExampleRegions, patch_size: int) -> np.ndarray | None:
    """The example's light layout: its background averaged at ``LAYOUT_SCALE`` of its long side
    (at least ``patch_size``), defined everywhere; (h, w, n) float32 over its colour channels, or
    None when there is no background to measure it on.

    The same layout :func:`_relight_setup` lights the gaps with; the fragments use it too (a
    fragment's ground is moved from the layout where it comes from to the layout where it goes).

    Parameters
    ----------
    ex : (h, w, C) float ndarray
        The example image.
    regions : ExampleRegions
        The example's regions; the background is what is neither forbidden nor (near) a body
        or branch-like pixel.
    patch_size : int
        Smallest blur scale (pixels).

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.branching.regions import ExampleRegions
    >>> z = np.zeros((64, 64), bool)
    >>> img = np.full((64, 64, 3), 0.5, np.float32)
    >>> lay = light_layout(img, ExampleRegions(z, z, z, z.astype(float)), 32)
    >>> lay.shape, bool(np.allclose(lay, 0.5, atol=1e-3))
    ((64, 64, 3), True)
    """
    n = min(ex.shape[2], 3)
    bg_ex = ~(regions.forbidden | ndi.binary_dilation(regions.body | regions.branch_like, iterations=3))
    if np.count_nonzero(bg_ex) < 64:
        return None
    exc = ex[..., :n].astype(np.float64)
    return _coarse_blur(exc, bg_ex, max(LAYOUT_SCALE * max(ex.shape[:2]), float(patch_size)),
                        levels=5).astype(np.float32)


def _light_mode(shade: np.ndarray, layout: np.ndarray, mean: np.ndarray, bg: np.ndarray) -> str:
    """How the gaps of an example are relit: ``"even"`` (its light layout varies by less than
    ``SHADED``), ``"lit"`` (the ground's variation at the detail scale, ``shade``, is mostly the
    light ``layout``: taken out at the detail scale) or ``"textured"`` (lit, but more than
    ``TEXTURE_SHARE`` of that variation is no light: patches, blotches). Only ``"lit"`` grounds
    lose their detail-scale variation; the others only their light layout.

    Examples
    --------
    >>> import numpy as np
    >>> ramp = np.dstack([np.tile(np.linspace(0.3, 0.9, 32), (32, 1))] * 3)
    >>> bg = np.ones((32, 32), bool)
    >>> m = ramp[bg].mean(axis=0)
    >>> _light_mode(ramp, ramp, m, bg), _light_mode(np.full_like(ramp, 0.5), np.full_like(ramp, 0.5), m, bg)
    ('lit', 'even')
    >>> patches = ramp + 0.2 * (np.indices((32, 32)).sum(0) // 8 % 2)[..., None]
    >>> _light_mode(patches, ramp, m, bg)
    'textured'
    """
    lum = layout.mean(axis=2)[bg]
    lo, hi = np.percentile(lum, [5, 95])
    if hi <= SHADED * max(lo, 1e-3):
        return "even"
    dc = float(((shade - mean)[bg] ** 2).sum())
    dr = float(((shade - layout)[bg] ** 2).sum())
    return "textured" if dr > TEXTURE_SHARE * max(dc, 1e-12) else "lit"


def _relight_setup(ex: np.ndarray, canvas: np.ndarray, covered: np.ndarray, regions: ExampleRegions,
                   body: np.ndarray, patch_size: int, dist: np.ndarray, dist_t: np.ndarray,
                   prior: float = 1.0, domains=None):
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
    ``LAYOUT_SCALE`` of its long side, at least the patch side (the dark top of a night sky, the
    bright clouds low in the middle, a fundus photo's vignetting), so the
    large-scale light of the example is kept rather than quilted from
    patches of bright and dark. Returns ``(example, canvas, offset)`` or
    None when there is no background to measure the light on.

    Only where the light explains the ground's detail-scale variation
    (:func:`_light_mode` ``"lit"``: a vignetted fundus, a night sky) is it
    taken out at the detail scale; elsewhere (evenly lit grounds, patches of
    fields, blotches, stripes) only the light layout is, at its own scale:
    taken out at the detail scale they came out as one even tone with faint
    seams (``_ground_texture_check`` fields: energy of the patch-sized bands
    0.10-0.22 of the example's).

    ``domains = (example_domain, output_domain)`` (an example whose domain a
    drawn line walls off, :mod:`~branchnb.branching.drawn_domains`): the light
    is measured and changed inside the domains only (the white outside of a
    shaded map would brighten its land's light; the outside keeps its own).

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
    if domains is not None:
        bg_ex = bg_ex & domains[0]
        bg_t = bg_t & domains[1]
    if np.count_nonzero(bg_ex) < 64 or np.count_nonzero(bg_t) < 64:
        return None
    sigma = DETAIL_SCALE * float(patch_size)
    exc = ex[..., :n].astype(np.float64)
    shade_ex = _coarse_blur(exc, bg_ex, sigma, levels=5)
    mean = exc[bg_ex].mean(axis=0)
    # the example's light layout, at the output's size (same relative position)
    H, W = bg_t.shape
    layout_sigma = max(LAYOUT_SCALE * max(ex.shape[:2]), float(patch_size))
    layout = _coarse_blur(exc, bg_ex, layout_sigma, levels=5)
    mode = _light_mode(shade_ex, layout, mean, bg_ex)
    if mode != "lit":
        # the ground's patches are texture, not light: only the light layout is taken out
        sigma, shade_ex = layout_sigma, layout
    g = cv2.resize(layout.astype(np.float32), (W, H), interpolation=cv2.INTER_LINEAR).reshape(H, W, n)
    # the fragments' light where they are (their background averaged at sigma), weighted by how
    # much of it lies around
    blur_t = _coarse_blur(canvas[..., :n], bg_t, sigma, levels=5)
    den = _coarse_blur(bg_t[..., None].astype(np.float32), np.ones((H, W), bool), sigma)
    shade_t = (blur_t * den + prior * g) / (den + prior)
    ex_flat = ex.copy()
    ex_flat[..., :n] = ex[..., :n] + (mean - shade_ex)
    offset = np.zeros(canvas.shape, np.float32)
    offset[..., :n] = (shade_t - mean).astype(np.float32)
    if domains is not None:
        ex_flat[~domains[0]] = ex[~domains[0]]
        offset[~domains[1]] = 0.0
    return ex_flat.astype(np.float32), (canvas - offset).astype(np.float32), offset


def _complete(out, ex: np.ndarray, regions: ExampleRegions, p, flat: bool, use_poisson: bool, pm_s, pm_t,
              labels_t, src_labels, rng: np.random.Generator, report, frag_share: float, timings: dict,
              domains=None, patchwork: float = 0.0, line_margin: float | None = None):
    """Gap completion of the fragments' canvas ``out`` (a ``_Canvas``, updated in place).

    ``line_margin`` (px; None: ``LINE_MARGIN``): the fragments' pixels
    within ``r + line_margin`` of a target line are kept and are no boundary of the gaps' colour
    correction (their colour is not spread into the quilted ground: a line's soft edge glowed there,
    strongest round free ends where a fragment's disk stops at the tip; beyond the paper, issue 23).

    ``patchwork`` (> 0: the ground is flat patches of this typical diameter,
    :func:`~branchnb.branching.patchwork.is_patchwork`; beyond the paper, issue 23): the patches are
    copied as they are, with graph-cut seams only, no relighting and no gradient-domain correction
    (both smeared one field's colour into the next: a blurred mush of field colours where the
    example has flat fields with sharp borders), and the quilting patches are half a field across
    (``PATCHWORK_PATCH``; from ``p.patch_size`` up to 3 x it): patches much smaller than a field are
    one flat colour each, and the borders between them were the seams' staircases along the patch
    grid rather than the example's own borders (aerial fields at 1024 px: gradient-histogram
    distance to the example's ground 0.039 -> 0.026). Without a relit ground the gaps are then laid
    with whole fields of the example (:func:`~branchnb.branching.patchwork.paste_fields`: square
    patches met along a grid of straight seams, a third of the ground's colour edges axis-aligned);
    the quilting fills only what they leave.

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
        if p.relight_completion and not flat and not patchwork:
            relit = _relight_setup(ex, canvas, covered, regions, body, p.patch_size, pm_s.dist, pm_t.dist,
                                   domains=domains)
            if relit is not None:
                ex_fill, canvas, offset_t = relit
        ex_c = ex if relit is None else ex_fill
        size = p.patch_size
        if patchwork > 0:
            size = int(2 * round(np.clip(PATCHWORK_PATCH * patchwork, p.patch_size, 3 * p.patch_size) / 2))
        lines = pm_t.core(1.0, LINE_MARGIN if line_margin is None else line_margin)
        kw = dict(patch_size=size, overlap=p.patch_overlap, protect=(lines & covered) | inner,
                  tolerance=p.completion_tolerance, forbid_weight=p.forbid_weight, min_free=p.min_free,
                  method=p.seams, poisson=use_poisson and not patchwork, anchored=p.anchors,
                  anchor_weight=p.anchor_weight,
                  screen=p.completion_screen if p.anchors else 0.0, rng=rng, progress=sub_progress)
        pasted = None
        if patchwork > 0 and labels_t is None and relit is None:
            # whole fields laid one by one: quilting's square patches left a grid of straight seams
            from .patchwork import paste_fields

            pasted = paste_fields(canvas, covered, ex_c, regions.forbidden, rng=rng)
        if pasted is not None and covered.all():
            from branchnb.core.completion import CompletionResult

            comp = CompletionResult(filled=pasted[0], source=pasted[1], seams=np.zeros(covered.shape, bool),
                                    n_patches=0, seam_cost=0.0, patch_size=size)
        elif labels_t is None:    # the quicker window search of gap_quilting (issue 23)
            comp = quilt_gaps(canvas, covered, ex_c, regions.forbidden, **kw)
        else:                   # region by region (maps): the core's loop
            comp = complete_gaps(canvas, covered, ex_c, regions.forbidden, regions=labels_t,
                                 example_regions=src_labels, fast=True, **kw)
        if pasted is not None and pasted[0].any() and comp.filled is not pasted[0]:
            comp.source[pasted[0]] = pasted[1][pasted[0]]
            comp.filled = comp.filled | pasted[0]
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
