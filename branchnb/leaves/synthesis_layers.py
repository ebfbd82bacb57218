"""Steps 1, 2, 4 and 5 of :mod:`branchnb.leaves.synthesis` on the new leaf's work box.

:func:`_background` samples one exemplar's residual (texture-corrected
where the shape warp stretches), :func:`_paste_layers` brings each layer
from a donor (:func:`_pick_donor`, :func:`_contrast_colours`) and
composites them, :func:`_attach_petiole` puts the petiole under the
lamina and :func:`_finish` draws a drawn leaf's outline anew. Every array
here covers the work box only (see :func:`_work_box`): outside it a new
leaf is transparent, and nothing is computed there.
"""

from __future__ import annotations

import cv2
import numpy as np

from .correction import _correct
from .inking import _ink_outline, _to_palette
from .shaping import GRAIN_SIGMA, _sample, _sample_grain_at, _sample_line_at, _sample_sharp_at, random_warp

#: A layer's donor is the background's own exemplar only when every other is stretched more than this
#: (log of the scale; see :func:`branchnb.leaves.synthesis.generate_leaf`).
_REUSE_STRETCH = float(np.log(1.5))


#: Median width (px) up to which a layer's curves are hairlines, pasted without carrying their grain
#: whole (:func:`_hairline`).
_HAIRLINE = 2.0

#: Whether a drawing's hairline layers are drawn anew rather than resampled (:func:`_sample_line_at`).
_REDRAW_LINES = True


def _hairline(p, k: int) -> bool:
    """Whether layer ``k`` is made of hairlines (veins 1-2 px wide on the training leaf).

    Beyond the paper. :func:`branchnb.leaves.shaping._sample_grain_at`
    carries a layer's detail from the nearest source pixel to keep a
    texture's grain; a 1-px vein is nothing but detail, and carried that
    way under a rotation it came out beaded: procedural 128-px leaves with
    dark 1-2 px veins, dark pieces per 100 px of their skeleton 0.3
    (elliptic) and 1.1 (strip) in the exemplars, 4.3 and 3.1 in new leaves;
    with Lanczos alone 0.5 and 1.8, vein contrast 1.00 -> 0.99 and
    0.97 -> 0.93 of the exemplars'. Wider layers (spots, a 400-px leaf's
    veins) keep their grain.
    """
    cache = p.__dict__.setdefault("_hairline", {})
    if k not in cache:
        from .snapping import is_thin_layer
        a = p.analysis
        cache[k] = bool(is_thin_layer(a.layers[k].masks[a.training_index], max_width=_HAIRLINE))
    return cache[k]


def _patch_side(shape) -> int:
    """Texture correction's patch side on a canvas of ``shape`` (see :func:`branchnb.leaves.correction._correct`)."""
    return max(8, min(shape) // 24)


def _background(p, a, params, seed: int, rng, m, box, alpha, bg: int, base_amp: float, corr: float):
    """The background's colours on the work box and its source coordinates: ``(rgb, c_bg)``.

    ``m`` and ``alpha`` are the shape map and the lamina's alpha on the box ``box`` of the canvas.
    """
    d0 = random_warp(p.shape, base_amp, corr, rng)
    c_bg = p.source_coords(bg, m, d0)
    # Colours where the new leaf is, and a rim of a patch side around it: the
    # texture correction matches patches against the canvas there.
    ps = _patch_side(p.shape)
    rim = 2 * (ps + 2) + 1
    shown = cv2.dilate((alpha > 0).astype(np.uint8), cv2.getStructuringElement(cv2.MORPH_RECT, (rim, rim))) > 0
    rgb = _sample_grain_at(p.stage[-1][bg][..., :3], c_bg, shown)
    if params.correct:
        # Texture correction where the composed warp stretches or squeezes,
        # from the background exemplar's unwarped residual (before the layers
        # go on, so no vein or spot is replaced by plain texture).
        # From a stream of its own: how many draws the quilting takes depends
        # on the pixels, and the layers' donors drawn after it changed with
        # any change of the correction (two of four test leaves took the same ones).
        rgb = _correct(rgb, alpha > 0.5, c_bg, p.stage[-1][bg], a.blades[bg],
                       np.random.default_rng((int(seed), 4)), p.source_detail(bg), patch_size=ps)
    return rgb, c_bg


def _pick_donor(p, params, k: int, rng, used: set, chosen: dict, new_size: float, m_full, inside_full):
    """The exemplar layer ``k`` comes from (None: no exemplar has it)."""
    a = p.analysis
    n = p.n
    L = a.layers[k]
    cands = [e for e in range(n) if L.masks[e].any()]
    if not cands:
        return None
    # Under-induced donors (a layer far sparser than most exemplars':
    # a few dashes of veins) are passed over while others have one.
    full = [e for e in cands if p.layer_complete[k][e] >= params.donor_complete]
    cands = full if full else cands
    # Nor one whose layer stands out the other way than the training
    # leaf's (see prepared._Prepared._agreement): a grass strip's dark dots
    # induced as its pale veins gave new leaves dotted, not lined, veins
    # (vein continuity 0.88 where that strip gave the veins).
    same = [e for e in cands if p.layer_agrees[k][e]]
    cands = same if same else cands
    # Never the donor of another layer (two layers of one exemplar
    # pasted with different warps lay beside each other: vein continuity
    # 0.58 on maples whose spots and veins came from one leaf).
    free = [e for e in cands if e not in chosen.values()] or cands
    fresh = [e for e in free if e not in used]
    if params.donor_size_sigma > 0 and len(free) > 1 and new_size > 0:
        # Donors whose layer is carried with the least stretch (see
        # SynthesisParams.donor_size_sigma); the background's own
        # exemplar only when every other one is stretched more.
        sig = params.donor_size_sigma
        size = np.log(np.maximum([p.lamina_size[j] for j in free], 1e-6) / new_size)
        aniso = np.array([p.carried_anisotropy(j, m_full, inside_full) for j in free])
        stretch = np.hypot(size, np.maximum(aniso - 0.5 * _REUSE_STRETCH, 0.0))
        ok = [i for i, j in enumerate(free) if j in fresh]
        if not ok or stretch[ok].min() > max(float(stretch.min()) + 2.0 * sig, _REUSE_STRETCH):
            ok = list(range(len(free)))
        idx = ok
        pool = [free[i] for i in idx]
        # exp(-z^2 / 2) normalised, taken relative to its largest (no underflow when all are stretched)
        logw = -0.5 * (stretch[idx] / sig) ** 2
        w = np.exp(logw - logw.max())
        w = w / w.sum() if w.sum() > 0 else np.full(len(pool), 1.0 / len(pool))
        return int(pool[int(rng.choice(len(pool), p=w))]) if len(pool) > 1 else int(pool[0])
    pool = fresh if fresh else free
    return int(rng.choice(pool))


def _contrast_colours(p, k: int, e: int, c, on, col, rgb, rgb_low):
    """Layer ``k`` of donor ``e`` as its contrast to its own leaf, on the background ``rgb`` (in ``col``)."""
    # The layer relative to the same leaf without it (the next
    # residual): a vein of a yellow leaf darkens an orange
    # background as it darkened its own leaf, instead of painting a
    # yellow stripe on it.
    # As a ratio (a pigment multiplies the light the leaf under it
    # reflects), so black ink stays black whatever it lies on.
    # Clipped to the layer's colours in the exemplars, widened to
    # the background's own colour: a pixel the layer leaves as it
    # was (ratio ~1, the mask's anti-aliased rim) keeps the
    # background's colour. (Clipped to the layer's range alone, the
    # rim of a light vein was lifted to the vein's colour: veins
    # widened and blurred, new leaves had about half their
    # exemplars' Laplacian variance on procedural families.)
    # (On the layer's footprint only: a weight of 0 elsewhere.)
    under = _sample_sharp_at(p.layer_under[k][e][..., :3], c, on)[on]
    lo, hi = p.layer_range[k]
    fg = col[on]
    own = np.clip(rgb[on], *p.blade_range)
    # The background under the layer without its grain (``rgb_low``): the
    # layer's ratio brings the donor's grain (the leaf under it is smooth),
    # and on top of the background's own it doubled the texture under the
    # pasted footprint.
    bg_on = rgb_low[on]
    # A layer lighter than the leaf under it (pale veins) is brought
    # as a ratio of the light it lets through, 1 - (1 - rgb) (1 - col)
    # / (1 - under) (a "screen"), a darker one as a ratio of the light
    # (multiply): the ratio of a pale vein alone, on a background
    # lighter than its own leaf, pushed it past every exemplar's vein
    # (2-4 % of new blades' pixels above the exemplars' 99.5th
    # percentile against 0.3-0.5 % in the exemplars, procedural
    # families), which the blade's percentile clip had hidden by
    # cutting every pale vein's crest.
    mul = bg_on * fg / np.maximum(under, 0.02)
    scr = 1.0 - (1.0 - bg_on) * (1.0 - fg) / np.maximum(1.0 - under, 0.02)
    # Pale layers as a plain ratio too (it keeps the layer's relative
    # contrast), only never past the exemplars' lightest blade colour
    # (99.5th percentile) unless the screen goes past it: as a screen
    # alone, a pale vein of a dark leaf pasted onto a light one kept
    # about half its relative contrast (grass photos: 13-15 % of a
    # dark strip's veins fell below half their own contrast on a light
    # background; vein continuity 0.85).
    light = np.maximum(scr, np.minimum(mul, p.blade_range[1]))
    col[on] = np.clip(np.where(fg > under, light, mul), np.minimum(lo, own), np.maximum(hi, own))


def _is_band(layer) -> bool:
    """Whether ``layer`` was induced as a band along the outline (a variegated margin), hiding the others.

    Beyond the paper, which composites the layers by depth. A variegated
    band's donor brings its own veins across it (the induction gives the
    veins' parts across the band to the band: see ``crossed`` of
    :func:`~branchnb.leaves.margin_band.band_rim`), so the vein layer's
    donor has none there; where its green centre reached farther than the
    new leaf's band lets it, its vein tips, a fork with the green between
    them and the green rims of its veins were mixed into the pasted band by
    weight. The band hides the other layers under its pasted cover,
    whatever their depth. Procedural variegated leaves
    (``tests/test_leaves_variegated.py``; 12 new leaves, rng 0-1), pieces of
    3 px or more of the centre's colours inside the band (4 px off the
    outline) per new leaf, and their px: 240 px, 4 exemplars 2.6 / 27 ->
    0.17 / 0.6; 600 px, 6 exemplars 5.8 / 89 -> 2.0 / 33; 400 px, a band
    of 8 % of the image 4.5 / 160 -> 3.5 / 132 (the rest: the band's
    spots); the exemplars 0. Cream flecks in the green centre 3.1 -> 2.1
    at 600 px.
    """
    return bool(layer.steps is not None and getattr(layer.steps, "band", False))


def _paste_layers(p, params, rng, m, m_full, inside_full, alpha, rgb, c_bg, bg: int, base_amp: float,
                  corr: float, eps_px: float, warps: dict):
    """The layers, bottom first, each from a donor with its own warp, composited on ``rgb``.

    Returns ``(rgb, chosen)``: the composited colours and the donor of each layer.
    """
    a = p.analysis
    shape = alpha.shape
    new_size = float(np.sqrt((alpha > 0.5).sum()))
    used = {bg}
    chosen = {}
    cover = np.zeros(shape, np.float32)
    rgb_low = None
    mix = np.zeros(shape + (3,), np.float32)
    wsum = np.zeros(shape, np.float32)
    band_cover = None
    for k in reversed(range(len(a.layers))):
        L = a.layers[k]
        e = _pick_donor(p, params, k, rng, used, chosen, new_size, m_full, inside_full)
        if e is None:
            continue
        used.add(e)
        chosen[L.name] = e
        amp = base_amp + params.layer_warp * eps_px * (1.0 - p.structural[k])
        warps[L.name] = amp
        c = p.source_coords(e, m, random_warp(p.shape, amp, corr, rng))
        a_k = np.clip(_sample(p.layer_masks[k][e], c)[..., 0], 0, 1)
        if p.leftover is not None and k == p.leftover[0] and params.one_system > 0:
            # One vein system: the background's own lines of this layer that
            # run beside the donor's pasted one (the same vein of the other
            # leaf, moved by both registrations' errors and the warps) are
            # taken out, filled from the blade's own texture.
            gone = p.beside_lines(bg, c_bg, a_k > 0.5, alpha > 0.5,
                                  params.one_system * (eps_px + p.registration_error) + p.leftover[2])
            if gone is not None:
                rgb[gone] = _sample_grain_at(p.own_lines(bg)[1], c_bg, gone)[gone]
                rgb_low = None
        on = a_k > 0  # the layer's colours are needed under its footprint only
        if _hairline(p, k):
            # Veins 1-2 px wide are all detail band: their grain carried from
            # the nearest source pixel put a rotated 1-px vein on every other
            # pixel (beads, dashes near the rim of 128-px leaves); resampled
            # smoothly they stay lines (see _HAIRLINE).
            if p.flat is not None and _REDRAW_LINES:
                # A drawing's ink lines are drawn anew at their new place (see _sample_line_at).
                col = _sample_line_at(p.stage[k][e][..., :3], p.layer_under[k][e][..., :3], c, on)
            else:
                col = _sample_sharp_at(p.stage[k][e][..., :3], c, on)
        else:
            col = _sample_grain_at(p.stage[k][e][..., :3], c, on)
        if params.layer_colour == "contrast":
            if rgb_low is None:
                rgb_low = cv2.GaussianBlur(rgb, (0, 0), GRAIN_SIGMA)
            # Hairlines keep the background's grain under their footprint: their
            # colours are resampled smoothly (above), so the ratio brings back
            # little of the donor's grain, and on the background without its
            # own the footprint of every thin vein came out as a smooth band
            # (7 sample maples as in notebook 04, 6 new leaves, rng 0-2: mean
            # gradient magnitude inside the blade 0.831-0.835 -> 0.844-0.850 of
            # the exemplars', Laplacian variance 0.98-1.12 -> 1.07-1.20).
            _contrast_colours(p, k, e, c, on, col, rgb, rgb if _hairline(p, k) else rgb_low)
        ext = getattr(p, "layer_ext", None)
        if ext is not None and ext[k][e] is not None:
            # A vein's faint ends (its ridge extension, prepared._removed_extension) are blade colours in
            # the exemplars; their ratio onto another leaf put 1 % of a new maple's blade below the
            # exemplars' 0.5th percentile of blue (tests/test_leaves_photos.py).
            x = on & (_sample(ext[k][e], c)[..., 0] > 0.5)
            col[x] = np.clip(col[x], *p.blade_range)
        shown = a_k
        if _is_band(a.layers[k]):
            # A band along the outline hides the other layers' pixels: see _is_band.
            mix *= (1.0 - a_k)[..., None]
            wsum *= 1.0 - a_k
            band_cover = a_k if band_cover is None else np.maximum(band_cover, a_k)
        elif band_cover is not None:
            shown = a_k * (1.0 - band_cover)
        wgt = (np.clip(_sample(p.layer_weights[k][e], c)[..., 0], 0, None) + 1e-6) * shown
        cover = np.maximum(cover, shown)
        mix += wgt[..., None] * col
        wsum += wgt
    layer_rgb = mix / np.maximum(wsum, 1e-12)[..., None]
    rgb = rgb * (1 - cover[..., None]) + layer_rgb * cover[..., None]
    return rgb, chosen


def _attach_petiole(rgb, alpha, pet):
    """The petiole ``pet`` (RGBA) under the lamina: ``(rgb, alpha, pet_own)``, ``pet_own`` where it shows."""
    ap = np.clip(pet[..., 3], 0, 1)
    pet_own = ap * (1 - alpha) > 0.5
    out_a = alpha + ap * (1 - alpha)
    rgb = (rgb * alpha[..., None] + pet[..., :3] * (ap * (1 - alpha))[..., None]) / np.maximum(
        out_a, 1e-6)[..., None]
    return rgb, out_a, pet_own


def _finish(p, rgb, alpha, pet, pet_own):
    """A drawn leaf's palette and new outline (step 6), then the RGBA image (colours 0 where transparent)."""
    if p.flat is not None:
        own = None
        if pet_own is not None and pet_own.any():
            # A petiole drawn without ink (a fill-coloured stalk) stays as its
            # exemplar drew it; the new outline is the lamina's. Outlined along
            # its boundary too, a clip-art leaf's 2 px fill-coloured petiole
            # came out solid ink on every new leaf. An inked petiole (most of
            # its pixels nearer the ink than halfway to the blade's median
            # colour) is outlined anew with the blade, as before.
            own = pet[..., :3][pet_own]
            ink = p.flat.outline_colour
            half = 0.5 * float(np.linalg.norm(np.median(rgb[alpha > 0.5], axis=0) - ink))
            if (np.linalg.norm(own - ink, axis=1) < half).mean() >= 0.5:
                own = None
        rgb, alpha = _ink_outline(rgb, alpha, p.flat)
        if own is not None:
            rgb[pet_own] = _to_palette(own, p.flat.palette, p.flat.hard) if len(p.flat.palette) else own
    img = np.empty(alpha.shape + (4,), np.float32)  # written in place: no temporaries of the box
    np.clip(rgb, 0, 1, out=img[..., :3])
    img[..., :3] *= (alpha > 0)[..., None]
    img[..., 3] = alpha
    return img
