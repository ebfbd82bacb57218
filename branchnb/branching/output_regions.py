"""The output's regions for flat-colour examples (drawn maps, masks) and their drawing in style.

Going beyond the paper (which copies fragments of photographs): a map or a
mask is segmented into its flat regions (land, sea); the output's regions
come from the domain its structure grew in, or the example's own layout,
and :func:`_draw_flat` draws the target the way the example is drawn
(:mod:`.drawing`).
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
from scipy import ndimage as ndi

from .skeleton_map import PixelMap

if TYPE_CHECKING:
    from .image_params import ImageSynthesisParams
    from .image_result import ImageSynthesisResult

__all__: list[str] = []


def _grew_in_example_layout(layout: np.ndarray, pm_s: PixelMap, pm_t: PixelMap,
                            share: float = 0.98) -> bool:
    """True when the output has the example's size and the target's centre lines lie (``share`` of
    them) in the example's branch region, which is not (almost) all of it: it grew in the
    example's domain (``fit_model(..., domain=example_domain(...))``), like a delta's
    distributaries that stop at the example's sea."""
    lay = np.asarray(layout)
    if lay.shape != pm_t.dist.shape:
        return False
    on_s = lay[pm_s.dist <= 0.5]
    on_t = pm_t.dist <= 0.5
    if on_s.size == 0 or not on_t.any():
        return False
    inner = int(np.bincount(on_s - lay.min()).argmax() + lay.min())
    if np.mean(lay == inner) > 0.9:   # (almost) no other region: nothing to keep
        return False
    return bool(np.mean(lay[on_t] == inner) >= share)


def _example_layout_for(layout: np.ndarray, pm_s: PixelMap, pm_t: PixelMap) -> np.ndarray:
    """The example's own layout for a target that grew in its domain; the target's bodies lie in the
    branch region (going beyond the paper: a classifier of the skeleton's surroundings cannot tell
    a delta's sea from its land when the trunk comes from inland, and slants the coast)."""
    lay = np.asarray(layout).astype(np.int32).copy()
    on_s = lay[pm_s.dist <= 0.5]
    inner = int(np.bincount(on_s - lay.min()).argmax() + lay.min())
    lay[pm_t.core(1.0, 1.5)] = inner
    return lay


def _domain_labels(layout: np.ndarray, pm_s: PixelMap, domain: np.ndarray,
                   colours: np.ndarray | None = None) -> np.ndarray:
    """Output regions from the domain the target grew in: the example's branch region inside it,
    the region most of the example's other pixels have outside it (going beyond the paper: small
    pieces outside the domain that lie on the example's branch region, e.g. a land corner between
    rivers at the frame that the domain left out, stay in the branch region: no lake or inlet the
    example does not have). ``colours``: the example's colour labels; when its branches have the
    outer region's colour (a delta's water channels), a domain taken from the example
    (:func:`~branchnb.branching.extraction.example_domain`) has a notch of sea at every example
    mouth: the coast is drawn straight across it."""
    lay = np.asarray(layout)
    k = int(lay.max()) + 1
    inner = int(np.bincount(lay[pm_s.dist <= 0.5], minlength=k).argmax())
    rest = lay[lay != inner]
    outer = int(np.bincount(rest, minlength=k).argmax()) if rest.size else inner
    dom = np.asarray(domain, bool)
    if dom.shape == lay.shape and dom.any() and not dom.all():
        if colours is not None:
            c = np.asarray(colours)[pm_s.dist <= 0.5]
            c = c[c >= 0]
            if c.size and int(np.bincount(c).argmax()) == outer:
                dom = _across_example_mouths(dom, pm_s)
        # small pieces outside the domain lying (almost) wholly on the example's branch region are
        # no sea of the example (a flat land corner between rivers at the frame): they stay land
        pieces, n = ndi.label(~dom)
        if n:
            area = np.bincount(pieces.ravel(), minlength=n + 1)
            on_inner = np.bincount(pieces.ravel(), weights=(lay == inner).ravel(), minlength=n + 1)
            fill = (area < 0.05 * dom.size) & (on_inner >= 0.9 * area)
            fill[0] = False
            dom = dom | fill[pieces]
    return np.where(dom, inner, outer).astype(np.int32)


def _across_example_mouths(domain: np.ndarray, pm_s: PixelMap) -> np.ndarray:
    """``domain`` with the outer region's edge carried straight across the example's channels.

    The outer region is taken without the example's channel bodies (a tube
    of ``1.5 r + 4`` pixels) and closed with a disk wider than the tube, so it
    grows back into the tubes only as far as its edge on both sides reaches;
    the rest of the tubes (the notch each mouth cut into the coast) is
    inside the domain."""
    zone = pm_s.dist <= 1.5 * pm_s.radius + 4.0
    out = ~domain
    if not (out & zone).any():
        return domain
    R = 3 * int(np.ceil(1.5 * float(np.max(pm_s.radius[zone & out])) + 6.0))   # (a wide disk dips little)
    pad = R + 1
    closed = _disk_closing(np.pad(out & ~zone, pad, mode="edge"), R)[pad:-pad, pad:-pad]
    return domain | (out & zone & ~closed)


def _disk_closing(mask: np.ndarray, radius: float) -> np.ndarray:
    """Binary closing of ``mask`` by the disk ``x**2 + y**2 <= radius**2``, from two distance transforms.

    The same pixels as ``ndi.binary_closing`` with that disk away from the array's border (within
    ``radius`` of it the border counts as inside, not outside), in time independent of ``radius``:
    ``binary_closing`` with a disk costs its area per pixel, and a channel of radius 34 px across a
    sea strait (issue 23, two islands at 768 px) made a 343 px disk that ran out of memory."""
    grown = ndi.distance_transform_edt(~mask) <= radius
    return ndi.distance_transform_edt(grown) > radius


def _draw_flat(ex, example_structure, target_structure, layout, labels_t, target_domain, pm_s, labels_ex,
               p: ImageSynthesisParams, t_start: float, report, shape, cache: dict | None = None
               ) -> ImageSynthesisResult:
    """``synthesize_image`` for flat-colour examples: draw the target in the example's style.
    ``cache``: the example side kept between calls (:mod:`.example_cache`); its style is measured once."""
    from .drawing import draw_in_style, drawing_style
    from .image_result import ImageSynthesisResult

    report(0.1, "measuring the example's drawing style")
    style = None if cache is None else cache.get("flat_style")
    glow = None if cache is None else cache.get("flat_glow", False)
    if style is None:
        style = drawing_style(ex, example_structure, layout, pm_s)
        if glow is False:
            # beyond the paper (issue 23): glowing lines (lightning, neon) light their ground; the
            # ground's colours and textures are measured without that light (no ghost of the example's
            # lines) and the light is added around the output's lines (.glow)
            from .glow import glow_model

            glow = glow_model(ex, pm_s, layout)
        if glow is not None:
            clean = drawing_style(glow.ground, example_structure, layout, pm_s)
            style = replace(style, region_colours=clean.region_colours, region_textures=glow.region_textures(layout),
                            boundary_colour=clean.boundary_colour, boundary_width=clean.boundary_width)
        if cache is not None:
            cache["flat_style"] = style
            cache["flat_glow"] = glow
    H, W = shape
    if labels_t is None:
        labels_t = _domain_labels(layout, pm_s, target_domain) if target_domain is not None else \
            np.full((H, W), style.branch_region, np.int32)
    labels_t = _without_specks(labels_t, style.branch_region, target_structure)
    report(0.5, "drawing")
    if glow is not None:
        from .skeleton_map import SkeletonMap

        img = glow.paint(draw_in_style(style, target_structure, labels_t, lines=False),
                         SkeletonMap(target_structure, 1.0).pixel_map((H, W)))
    else:
        img = draw_in_style(style, target_structure, labels_t)
    report(1.0, "done")
    z = np.zeros((H, W), bool)
    return ImageSynthesisResult(img, z, z.copy(), np.full((H, W, 2), np.nan), np.full((H, W), -1, np.int64),
                                z.copy(), [], 0.0, target_structure, None, 0,
                                {"total": time.perf_counter() - t_start}, p,
                                example_labels=labels_ex, labels=labels_t)


def _without_specks(labels: np.ndarray, inner: int, structure, max_area: int = 400) -> np.ndarray:
    """``labels`` with pieces of the ``inner`` region under ``max_area`` pixels that hold no branch
    vertex given to the region around them (beyond the paper, issue 23: a domain's stray speck at the
    frame or off the coast, drawn with the example's coast around it, made a brown-outlined speck)."""
    lab = np.asarray(labels)
    pieces, n = ndi.label(lab == inner)
    if n < 2:
        return lab
    area = np.bincount(pieces.ravel(), minlength=n + 1)
    held = np.zeros(n + 1, bool)
    h, w = lab.shape
    for b in structure.branches:
        ix = np.clip(np.rint(b.points[:, 0]).astype(int), 0, w - 1)
        iy = np.clip(np.rint(b.points[:, 1]).astype(int), 0, h - 1)
        held[pieces[iy, ix]] = True
    drop = (area < max_area) & ~held
    drop[0] = False
    if not drop.any():
        return lab
    out = lab.copy()
    # each dropped piece takes the label most of its rim has
    for i in np.flatnonzero(drop):
        piece = pieces == i
        rim = ndi.binary_dilation(piece, iterations=1) & ~piece
        out[piece] = np.bincount(lab[rim]).argmax() if rim.any() else out[piece]
    return out


def _matte_colour(image: np.ndarray) -> np.ndarray | None:
    """The colour of the example's flat black/white matte (a fundus photo's surround), or None."""
    from .regions import matte_mask

    matte = matte_mask(image, dilate=0)
    if not matte.any():
        return None
    return np.median(image[matte], axis=0).astype(np.float32)


def _keep_matte(canvas: np.ndarray, domain: np.ndarray, colour: np.ndarray,
                feather: float = 1.0) -> np.ndarray:
    """``canvas`` with everything outside ``domain`` in the example's matte colour.

    Going beyond the paper (which fills the whole frame with the example's
    texture): a photo's matte is a region of its own, not texture to copy, so
    the output keeps it outside the domain its structure grew in; its edge is
    a soft step like a photo's (a Gaussian of ``feather`` pixels), no drawn
    line.
    """
    inside = ndi.gaussian_filter(np.asarray(domain, np.float32), feather) if feather > 0 else \
        np.asarray(domain, np.float32)
    inside = np.where(domain, np.maximum(inside, 0.5), inside)[..., None]
    return (canvas * inside + colour[None, None, :] * (1.0 - inside)).astype(canvas.dtype)


def _walls_off_matte(domain: np.ndarray, colour: np.ndarray, image: np.ndarray, share: float = 0.8,
                     tol: float = 0.08) -> bool:
    """True when a "drawn" boundary is the soft edge of the example's flat matte, not a drawn coast.

    What the line walls off is (``share`` of it, without the line's band) the
    matte, and the line's ``colour`` is a blend of the matte's and the
    domain's (within ``tol`` of the segment between them): a blurred step.
    A terrain map's dark coast on a white outside is no such blend.
    """
    from .regions import matte_mask

    dom = np.asarray(domain, bool)
    out = ~ndi.binary_dilation(dom, iterations=4)
    inner = ndi.binary_erosion(dom, iterations=4)
    if not out.any() or not inner.any():
        return False
    matte = matte_mask(image, dilate=2)
    if np.mean(matte[out]) < share:
        return False
    c = image.shape[2]
    m = np.median(image[out & matte], axis=0)
    g = np.median(image[inner], axis=0)
    col = np.asarray(colour, np.float64).ravel()[:c]
    d = g - m
    t = float(np.clip((col - m) @ d / max(float(d @ d), 1e-9), 0.0, 1.0))
    return bool(np.max(np.abs(col - (m + t * d))) <= tol)
