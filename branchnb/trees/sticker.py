"""Sticker-style drawn trees in a variation: a die-cut border outside the outline (beyond the paper).

A sticker tree is drawn with a dark outline round crown and trunk and then
cut out with a light (white, cream or coloured) border of even width
*outside* that outline, so the alpha covers the border and the silhouette's
rim is light. The outline handling of :mod:`~branchnb.trees.flat_art`
looks for the outline at the alpha rim and found none there; the mix's
cage warp moved both rings off the mixed silhouette, so crowns lost their
outline on whole sides and the border ran in and out (issue 24, trees41).

Here the rings are found nested, from the rim inwards: the border (a ring of
one colour from the rim to a steady depth, different from what lies inside
it), and inside it the exemplar stripped of its border, whose own rim
carries the outline (:func:`~branchnb.trees.outline.silhouette_outline`).
A mix of such exemplars is rebuilt ring by ring: the mix's silhouette is
shrunk by the mixed border width, the warped border left inside that is
taken as part of the stroke, the outline is re-inked along the shrunk
silhouette as for any outlined mix (:func:`~branchnb.trees.flat_art._ink_outline`),
and the border ring is painted back outside it in the border colour. What is left of the warped
outline inside the new ring (dotted pieces along the sides, bits at the notches where trunk meets
crown, a band running deeper at 400 px) is repainted with the fill next to it (trees55).

A sticker whose border is its only outline (a thick white ring straight round the fill) is
rebuilt the same way without the outline step: the ring at the sources' mean width (area over
rim length), the warped ring left inside it repainted with the fill, and a part thinner than two
rings (a trunk) kept in its own colours (beyond the paper, trees52).

Examples
--------
>>> import numpy as np
>>> img = np.zeros((80, 80, 4), np.float32)
>>> img[4:76, 4:76] = (1, 1, 1, 1); img[7:73, 7:73, :3] = 0.05; img[9:71, 9:71, :3] = (0.2, 0.6, 0.2)
>>> b = _sticker_border(img)
>>> b.width, [round(float(c), 2) for c in b.colour]
(3.0, [1.0, 1.0, 1.0])
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_rgba

__all__: list[str] = []

_LUM = np.array([0.299, 0.587, 0.114], np.float32)

#: A border's pixels lie within this RGB distance of its colour (anti-aliasing aside).
BORDER_TOL = 0.15
#: Share of the rim pixels in the border colour for the rim to be a border.
BORDER_SHARE = 0.8
#: Thickest border considered, as a share of the image's larger side (a wider "border" is a fill),
#: but never below BORDER_MIN_PX: a 3-8 px ring on a 96-256 px sticker is 3-8 % of its side, and
#: its square pen's corners reach 1.3x deeper (trees52).
BORDER_MAX = 0.04
BORDER_MIN_PX = 12


@dataclass(frozen=True)
class _StickerBorder:
    """A die-cut border: its colour, its width (Euclidean pixels) and the image without it.

    ``inner`` is the image with alpha 0 on the border ring, so its rim is what lies
    inside the border (the outline, when the sticker has one). ``mean_width``: the ring's area
    over the rim's length (``width`` is the deepest ring still half in the border colour).
    """

    colour: np.ndarray
    width: float
    inner: np.ndarray = field(repr=False)
    mean_width: float | None = field(default=None, repr=False)


def _edt(alpha: np.ndarray) -> np.ndarray:
    # The image frame is not transparent (a trunk cut by the frame has no rim there).
    if alpha.all():
        return np.full(alpha.shape, float(alpha.size))
    return ndi.distance_transform_edt(alpha)


def _sticker_border(image) -> _StickerBorder | None:
    """The die-cut border of a sticker-style tree, or None when its rim is no border.

    The rim (opaque pixels next to a transparent one) is a border when at least
    :data:`BORDER_SHARE` of it is one colour, that colour reaches in to a steady depth
    (the deepest 1 px ring still half as much in it, at most :data:`BORDER_MAX` of the
    image side or :data:`BORDER_MIN_PX`), the pixels 2-3 px deeper are mostly something else
    (a flat tree whose
    fill reaches the rim has no border: its colour runs on deep inside) and the border is
    lighter than they are (a plain outlined tree's dark rim is its outline).
    """
    img = as_rgba(image, name="image")
    alpha = img[..., 3] >= 0.5
    if alpha.sum() < 64:
        return None
    rgb = img[..., :3]
    depth = _edt(alpha)
    rim = alpha & (depth < 1.5)
    if rim.sum() < 16:
        return None
    colour = np.median(rgb[rim], axis=0)
    near = np.linalg.norm(rgb - colour, axis=2) <= BORDER_TOL
    share = float(near[rim].mean())
    if share < BORDER_SHARE:
        return None
    dmax = max(BORDER_MIN_PX, int(BORDER_MAX * max(alpha.shape)))
    width = 1
    for d in range(2, dmax + 2):
        ring = alpha & (depth >= d - 0.5) & (depth < d + 0.5)
        if not ring.any() or near[ring].mean() < 0.5 * share:
            break
        width = d
    if width > dmax:
        return None
    below = alpha & (depth >= width + 1.5) & (depth < width + 3.5)
    if not below.any() or near[below].mean() > 0.25:
        return None
    # A die-cut border is lighter than what it wraps: a plain outlined tree's dark rim is the
    # outline itself, not a border (its mix is re-inked by flat_art as before).
    if float(colour @ _LUM) < float(np.median(rgb[below] @ _LUM)) + 0.05:
        return None
    # The exemplar without its border: the border-coloured pixels joined to the rim (a border
    # drawn with a square pen is wider at corners than its mean Euclidean width).
    lab, _ = ndi.label(alpha & near & (depth <= 2 * width + 2), structure=np.ones((3, 3), bool))
    ids = np.unique(lab[rim & near])
    ring = np.isin(lab, ids[ids > 0])
    # The ring's mean width (area / rim length): the deepest ring half in the border colour lies
    # in a square pen's corners and the blur, 1.3x a 3-8 px outline's width on straight runs
    # (trees52). Used for a border with no outline inside it (the ring is the outline).
    mean_width = float(np.clip(ring.sum() / max(int(rim.sum()), 1), 1.0, width))
    # ... and the anti-aliased pixels between the border and what it wraps (more than a third
    # border colour), so the stripped rim is the outline's own, not a grey blend of the two.
    beyond = alpha & ~ring & (depth <= 2 * width + 4)
    if beyond.any():
        dist = np.linalg.norm(rgb - colour, axis=2)
        far = float(np.quantile(dist[beyond], 0.9))
        for _ in range(3):
            grow = ndi.binary_dilation(ring, structure=np.ones((3, 3), bool)) & alpha & ~ring
            ring |= grow & (dist < 0.7 * far)
    inner = np.array(img, np.float32, copy=True)
    inner[..., 3] = np.where(ring | ~alpha, 0.0, 1.0)
    return _StickerBorder(np.asarray(colour, np.float32), float(width), inner, mean_width)


def _exemplar_border(exemplar) -> _StickerBorder | None:
    """:func:`_sticker_border` of an exemplar (cached on it)."""
    if "sticker" not in exemplar._cages:
        exemplar._cages["sticker"] = _sticker_border(exemplar.image)
    return exemplar._cages["sticker"]


def _stripped(exemplar, border: _StickerBorder):
    """A stand-in exemplar without its border (its own cache), for the outline measures."""
    key = "sticker_inner"
    if key not in exemplar._cages:
        exemplar._cages[key] = SimpleNamespace(image=border.inner, _cages={})
    return exemplar._cages[key]


#: A thin outline's pixels are at least this much darker (luminance) than the border and the fill
#: beside them, next to at least THIN_SHARE of the first ring inside the border (:func:`_thin_ink`).
THIN_DARKER = 0.08
THIN_SHARE = 0.75
#: ... or (a sub-pixel pen blended with the border too) this far (RGB) off the line from the fill to
#: the border colour and darker than the point on it.
THIN_OFF = 0.05


def _pen_cover(image: np.ndarray, border: _StickerBorder, ink: np.ndarray, limit: float) -> float:
    """The outline's width (pixels, fractional) inside a sticker's border: the ink share of each
    pixel from the border to ``limit`` px inside it, summed and divided by the pixel count of the
    first ring inside the border. A pixel's ink share is read on the line from the ink to the
    border colour or to the fill nearest it, whichever passes nearer its colour. An outline
    thinner than a pixel after the exemplar was scaled down (a 4 px pen on a 1000 px sticker
    worked on at 256 px) is a 1 px ring of ink blended with the fill: it counts as part of a
    pixel, so the mix's ring is drawn as thin."""
    alpha = image[..., 3] >= 0.5
    depth = _edt(alpha)
    rgb = image[..., :3]
    w = border.width
    to_ink = np.linalg.norm(rgb - ink, axis=2)
    fill = alpha & (depth > w + limit + 1.0) & (to_ink > 0.35)
    first = alpha & (depth > w + 0.5) & (depth <= w + 1.5)
    if not fill.any() or not first.any():
        return 0.0
    _, (iy, ix) = ndi.distance_transform_edt(~fill, return_indices=True)
    best_q = np.zeros(depth.shape)
    best_r = np.full(depth.shape, np.inf)
    for other in (rgb[iy, ix], np.broadcast_to(border.colour, rgb.shape)):
        d = other - ink
        dd = np.maximum((d * d).sum(axis=2), 1e-6)
        t = np.clip(((rgb - ink) * d).sum(axis=2) / dd, 0.0, 1.0)
        r = np.linalg.norm(rgb - (ink + t[..., None] * d), axis=2)
        take = r < best_r
        best_q[take], best_r[take] = 1.0 - t[take], r[take]
    band = alpha & (depth <= w + limit)
    return float(best_q[band & ~(np.linalg.norm(rgb - border.colour, axis=2) <= BORDER_TOL)].sum()) / float(first.sum())


def _thin_ink(image: np.ndarray, border: _StickerBorder, blended: bool = True) -> np.ndarray | None:
    """The ink of an outline too thin for the outline measure (blended with the border and the
    fill once scaled down), or None: pixels from the border's inner edge to 2 px inside it darker
    (luminance) by :data:`THIN_DARKER` than both the border and the fill nearest them, within
    1 px of at least :data:`THIN_SHARE` of the first ring inside the border; with ``blended``, failing
    that, pixels off the line from the fill to the border colour (:data:`THIN_OFF`)."""
    img = np.asarray(image, np.float32)
    alpha = img[..., 3] >= 0.5
    depth = _edt(alpha)
    w = border.width
    lum = img[..., :3] @ _LUM
    fill = alpha & (depth > w + 3.5)
    first = alpha & (depth > w + 0.5) & (depth <= w + 1.5)
    if first.sum() < 16 or not fill.any():
        return None
    to_fill, (iy, ix) = ndi.distance_transform_edt(~fill, return_indices=True)
    band = alpha & (depth > w - 1.0) & (depth <= w + 2.5)
    dark = band & (lum <= np.minimum(lum[iy, ix], float(border.colour @ _LUM)) - THIN_DARKER)
    near = ndi.binary_dilation(dark, structure=np.ones((3, 3), bool))
    if (not dark.any() or float(near[first].mean()) < THIN_SHARE) and not blended:
        return None
    if not dark.any() or float(near[first].mean()) < THIN_SHARE:
        # A sub-pixel pen is blended with the light border as much as with the fill (a 3 px red
        # pen on a 1000 px sticker worked on at 192 px is 0.6 px: a blend of white, red and the
        # crown, often no darker than the crown): found off the line from the fill to the border
        # colour (where the plain anti-aliased step between the two lies) and darker than it
        # (beyond trees41/52, trees53).
        rgb = img[..., :3]
        f = rgb[iy, ix]
        d = border.colour - f
        # The line runs on past the fill: a fill whose rim was pushed away from the border colour
        # (a darker, more saturated first pixel, as the library's clean-up of a light fringe
        # leaves it) is no ink (96 px white-ring stickers were taken as outlined).
        t = np.minimum(((rgb - f) * d).sum(axis=2) / np.maximum((d * d).sum(axis=2), 1e-6), 1.0)
        on = f + t[..., None] * d
        # ... next to the fill (a part too thin for fill of its own, a small sticker's trunk, is no
        # blend of the crown colour it is measured against).
        dark = band & (to_fill <= 5.0) & (np.linalg.norm(rgb - on, axis=2) > THIN_OFF) & (lum <= on @ _LUM)
        if not dark.any():
            return None
        near = ndi.binary_dilation(dark, structure=np.ones((3, 3), bool))
        if float(near[first].mean()) < THIN_SHARE:
            return None
    return np.median(img[..., :3][dark & (lum <= np.quantile(lum[dark], 0.25))], axis=0).astype(np.float32)


def _drop_warped_border(mid: np.ndarray, inner: np.ndarray, colour: np.ndarray, width: float) -> np.ndarray:
    """Repaint with the fill nearest them the border-coloured pixels inside the rebuilt ring that
    are joined to it (within ``3 width + 2`` px of the rim).

    Notes
    -----
    Beyond trees41 (issue 24, trees52): a sticker whose border is its only outline (a thick white
    ring round the fill) kept the warped border wherever the cage had stretched it, so the mixed
    ring ran 2-3 times the sources' width on one side. Only pieces touching the ring go: a light
    detail of the fill away from the rim stays.
    """
    di = _edt(inner)
    rgb = mid[..., :3]
    layer = inner & (np.linalg.norm(rgb - colour, axis=2) <= 0.35)
    # ... and its anti-aliased edge: blends of the border colour with the fill next to it, left
    # as light seams along the rebuilt ring.
    core = inner & ~ndi.binary_dilation(layer, structure=np.ones((3, 3), bool), iterations=2)
    if core.any():
        _, (iy, ix) = ndi.distance_transform_edt(~core, return_indices=True)
        near = rgb[iy, ix]
        d = colour - near
        t = np.clip(((rgb - near) * d).sum(axis=2) / np.maximum((d * d).sum(axis=2), 1e-6), 0.0, 1.0)
        off = np.linalg.norm(rgb - (near + t[..., None] * d), axis=2)
        layer |= inner & (t >= 0.2) & (off <= 0.08) & ndi.binary_dilation(layer, structure=np.ones((3, 3), bool))
    lab, n = ndi.label(layer & (di <= 3.0 * width + 2.0), structure=np.ones((3, 3), bool))
    fill = inner & ~ndi.binary_dilation(layer, structure=np.ones((3, 3), bool), iterations=2)
    if not n or not fill.any():
        return mid
    touch = np.unique(lab[(lab > 0) & (di < 1.5)])
    leak = np.isin(lab, touch[touch > 0])
    _, (iy, ix) = ndi.distance_transform_edt(~fill, return_indices=True)
    out = mid.copy()
    out[leak, :3] = rgb[iy[leak], ix[leak]]
    return out


def _fill_to_ink(image: np.ndarray, border: _StickerBorder, ink: np.ndarray, pen: float) -> float | None:
    """How near (RGB, 2nd percentile) a sticker's fill comes to its outline's ``ink``: pixels
    deeper than the border, the pen and 2.5 px, not in the border colour (None when there are none)."""
    alpha = image[..., 3] >= 0.5
    rgb = image[..., :3]
    fill = alpha & (_edt(alpha) > border.width + pen + 2.5) & (np.linalg.norm(rgb - border.colour, axis=2) > 0.35)
    if not fill.any():
        return None
    return float(np.quantile(np.linalg.norm(rgb[fill] - ink, axis=1), 0.02))


#: Largest remnant of a warped outline (:func:`_drop_band_specks`), in squares of the band's depth.
SPECK_AREA = 1.0
#: ... whose pixels lie at least this share of the way from the fill next to them to the ink.
SPECK_INK = 0.3
#: ... or, 1-2 px across, this share of the way from their 5 x 5 closing to the ink (faint remnants:
#: 0.25-0.3 of the way at 400 px, where 400 px stickers' mixes kept ~30 of them each; trees57).
SPECK_FAINT = 0.15
#: ... within this RGB distance of that line (a pen's blend with a blue fill lies 0.10-0.11 off the
#: line to a grey ink: 0.1 kept ~5 of them per 400 px mix of 200 px stickers; trees57).
SPECK_OFF = 0.13


def _drop_band_specks(mid: np.ndarray, inner: np.ndarray, di: np.ndarray, ink: np.ndarray,
                      pen_w: float, lim: float) -> np.ndarray:
    """Repaint with the fill next to them the ink-coloured pieces cut off from a rebuilt outline
    ring and lying wholly in the band the warped rings were taken from (``di <= lim``).

    Notes
    -----
    Beyond trees41/53 (issue 24, trees55). The warped outline, stretched along the crown's notches
    and sides, breaks into dotted pieces 1-3 px inside the new ring, apart from the rim and from
    each other: neither the leak repaint (pieces touching the rim or running along it) nor
    :func:`~branchnb.trees.flat_art._drop_rim_flecks` (which spares the first 3 px past the pen as
    a hand-drawn outline's ragged edge) took them, so 192 px mixes kept 2-18 dark dots each. The
    ring here is painted at an exact depth, so any ink deeper than ``pen_w + 1`` is no part of it.
    A piece is ink when its pixels lie on the line from the fill next to them to the ink, at
    least :data:`SPECK_INK` of the way (anti-aliased blends of a sub-pixel pen included). One
    larger than ``SPECK_AREA lim**2`` or reaching deeper than the band is a detail of the drawing
    and stays, except a piece of at most two pens squared (``2 (pen_w + 1)**2``) within twice the
    band: at the sources' notches (trunk into crown) the warp maps their outline deeper under the
    mix's smoother rim. Faint remnants (a warped pen resampled into a dotted line 0.25-0.3 of the
    way from the fill to the ink, 5-10 px inside the ring) are found against the fill's 5 x 5 grey
    closing instead (:data:`SPECK_FAINT`; trees57: 400 px mixes of 400 px stickers, 8 px border,
    3 px pen, kept 32 of them each, then 0.1).
    """
    rgb = mid[..., :3]
    body = inner & (di > pen_w + 1.0)
    to_ink = np.linalg.norm(rgb - ink, axis=2)
    # Faint remnants: lines and dots 1-2 px across only part-way to the ink (a warped 3 px pen
    # resampled at 400 px: 0.25-0.3 of the way from the fill), too light to tell from the fill by
    # colour alone; found darker than the fill's closing round them (a step between two fills,
    # a stripe's edge, is no darker than its closing) and on its line to the ink (trees57).
    ref = np.stack([ndi.grey_closing(rgb[..., c], size=(5, 5)) for c in range(3)], axis=2)
    dr = ink - ref
    tf = ((rgb - ref) * dr).sum(axis=2) / np.maximum((dr * dr).sum(axis=2), 1e-6)
    offf = np.linalg.norm(rgb - (ref + np.clip(tf, 0.0, 1.0)[..., None] * dr), axis=2)
    faint = body & (di <= lim) & (tf >= SPECK_FAINT) & (offf <= 0.06)
    # the fill: off the ink and off the blends round it
    fillish = body & ~ndi.binary_dilation((to_ink <= 0.35) | faint, structure=np.ones((3, 3), bool))
    if not fillish.any():
        return mid
    _, (iy, ix) = ndi.distance_transform_edt(~fillish, return_indices=True)
    near = rgb[iy, ix]
    # ... a third of the way or more from the fill to the ink, on that line
    d = ink - near
    t = ((rgb - near) * d).sum(axis=2) / np.maximum((d * d).sum(axis=2), 1e-6)
    # (the line runs on past the ink: the measured ink is a median with its blends, the pen's
    # core is darker still; 400 px mixes kept black teeth of the warped band)
    off = np.linalg.norm(rgb - (near + np.maximum(t, 0.0)[..., None] * d), axis=2)
    # ... or as dark as the pen's core or darker, whatever its hue (a black core off the line from
    # a red fill through a grey ink by 0.1-0.13: 400 px mixes of 200 px stickers kept ~10 each)
    dark = body & (((t >= SPECK_INK) & (off <= SPECK_OFF)) | faint | (rgb @ _LUM <= float(ink @ _LUM) + 0.02))
    lab, n = ndi.label(dark, structure=np.ones((3, 3), bool))
    if not n:
        return mid
    idx = np.arange(1, n + 1)
    far = np.asarray(ndi.maximum(di, lab, idx))
    area = np.asarray(ndi.sum(dark, lab, idx))
    # A notch of the sources (where trunk meets crown) maps their outline deeper under the mix's
    # smoother rim: pieces a pen across reach twice the band.
    speck = ((far <= lim) & (area <= SPECK_AREA * lim * lim)) | \
        ((far <= 2.0 * lim) & (area <= 2.0 * (pen_w + 1.0) ** 2))
    if not speck.any():
        return mid
    drop = np.isin(lab, idx[speck])
    out = mid.copy()
    out[drop, :3] = near[drop]
    return out


def _ink_ring(mid: np.ndarray, inner: np.ndarray, di: np.ndarray, ink: np.ndarray, pen_w: float) -> np.ndarray:
    """``mid`` with a ring ``pen_w`` px wide (fractional: a soft inner edge) inked inside the rim of
    ``inner`` (``di``: its depth, 1 on the rim; a pixel of depth d holds the band from d - 1 to d)."""
    q = np.clip(pen_w - (di - 1.0), 0.0, 1.0)[..., None]
    ring_px = inner & (q[..., 0] > 0)
    out = mid.copy()
    out[ring_px, :3] = (q * ink + (1.0 - q) * mid[..., :3])[ring_px]
    return out


def _sticker_mix(image: np.ndarray, exemplars: Sequence, cw: np.ndarray, weights: np.ndarray,
                 sources: np.ndarray | None = None) -> np.ndarray | None:
    """Rebuild a mix of sticker trees ring by ring (None when they are not stickers).

    Bordered exemplars must hold at least half the colour weight (``sources``: the
    ``"choose"`` mode's source per pixel, counted instead). The border is ``weights``'
    (shape weights') mean of the bordered exemplars' widths, in the colour of the one
    with most colour weight.
    """
    borders = [_exemplar_border(e) for e in exemplars]
    on = np.array([b is not None for b in borders])
    if not on.any():
        return None
    img = np.asarray(image, np.float32)
    opaque = img[..., 3] >= 0.5
    if opaque.sum() < 64:
        return None
    share = cw.astype(np.float64)
    if sources is not None:
        share = np.bincount(sources[(sources >= 0) & opaque], minlength=len(exemplars)).astype(np.float64)
    if share[on].sum() < 0.5 * share.sum() - 1e-9:
        return None
    w = np.where(on, np.maximum(weights, 0.0) + 1e-9, 0.0)
    width = float(np.average([b.width if b is not None else 0.0 for b in borders], weights=w))
    best = borders[int(np.argmax(np.where(on, share, -1.0)))]
    colour = best.colour
    depth = _edt(opaque)
    inner = opaque & (depth > width + 0.5)
    if inner.sum() < 16:
        return None
    out = np.array(img, np.float32, copy=True)
    stripped = [_stripped(e, b) if b is not None else e for e, b in zip(exemplars, borders, strict=True)]
    from .flat_art import _drop_rim_flecks, exemplar_outline

    outl = [exemplar_outline(s) for s in stripped]
    # Outlines blended with the fill (thin pens scaled down) escape the outline measure: found
    # from the rim being darker than the fill inside it (beyond trees41).
    thin = [None if o.outlined or b is None else _thin_ink(e.image, b)
            for o, e, b in zip(outl, exemplars, borders, strict=True)]
    # A pen blended below a pixel found on some sources only (a 0.4 px pen: its "ink" a blend
    # with the crown, the mix ringed in the colour of one source's fill) is no pen (trees53).
    if not all(t is not None for t, o, b in zip(thin, outl, borders, strict=True) if b is not None and not o.outlined):
        thin = [None if o.outlined or b is None else _thin_ink(e.image, b, blended=False)
                for o, e, b in zip(outl, exemplars, borders, strict=True)]
    outl = [SimpleNamespace(outlined=True, ink=t, width=1, blended=True) if t is not None else o
            for o, t in zip(outl, thin, strict=True)]
    ons = [o.outlined for o in outl]
    if not any(ons):
        # The border is the sticker's only outline: drawn at the sources' mean width, not at the
        # depth their pens' corners reach (trees52).
        width = float(np.average([b.mean_width or b.width if b is not None else 0.0 for b in borders],
                                 weights=w))
        inner = opaque & (depth > width + 0.5)
        if inner.sum() < 16:
            return None
    mid = out.copy()
    mid[..., 3] = np.where(inner, 1.0, 0.0)
    if any(ons):
        ink = outl[int(np.argmax(np.where(ons, share, -1.0)))]
        ink_w = float(np.average([o.width for o in outl if o.outlined],
                                 weights=[x + 1e-9 for x, o in zip(share, outl, strict=True) if o.outlined]))
        # The pen's width in fractions of a pixel (the ring is drawn with a soft inner edge of that
        # width): whole rings of ``width + 1`` px came out 1.35-2.3x as thick as the sources'.
        covers = [(_pen_cover(e.image, b, o.ink, o.width + 2.0), x)
                  for e, b, o, x in zip(exemplars, borders, outl, share, strict=True) if o.outlined and b is not None]
        pen_w = float(np.average([c for c, _ in covers], weights=[x + 1e-9 for _, x in covers]))
        di = _edt(inner)
        # Rebuild the outline ring: the warped border and outline joined to the shrunk rim
        # (within two borders and pens of it) are repainted with the fill beyond them, then an
        # even ring is inked. Taken as stroke they stayed a band up to 10 px thick where the warp
        # had stretched them (_drop_excess keeps 2 pens + 2 at most).
        rgb = out[..., :3]
        lim = width + 2 * ink_w + 2
        # Ink-like: nearer the ink than half the way to the fills' colour nearest it (a brown trunk
        # lies 0.38 from a grey ink and 0.4 from a navy one; taken as ink it took the crown's colour).
        to_ink = np.linalg.norm(rgb - ink.ink, axis=2)
        to_border = np.linalg.norm(rgb - colour, axis=2)
        # The fills' nearest approach to the ink is read on the sources (inside their outlines):
        # read on the mix, where a warped outline band 10-25 px wide (400 px stickers) is 2 % of
        # the crown or more, it made every ink pixel "fill" and the band stayed (trees55).
        near_fill = [_fill_to_ink(e.image, b, o.ink, o.width) for e, b, o in zip(exemplars, borders, outl, strict=True)
                     if b is not None and o.outlined]
        near_fill = [q for q in near_fill if q is not None]
        tol = min(0.3, 0.5 * min(near_fill)) if near_fill else 0.3
        # ... or an anti-aliased blend of the two rings (on the line from ink to border colour).
        d = colour - ink.ink
        t = np.clip(((rgb - ink.ink) @ d) / max(float(d @ d), 1e-6), 0.0, 1.0)
        blend = np.linalg.norm(rgb - (ink.ink + t[..., None] * d), axis=2) <= 0.1
        layer = inner & ((to_border <= 0.35) | (to_ink <= tol) | blend)
        lab, n = ndi.label(layer & (di <= lim), structure=np.ones((3, 3), bool))
        fill = inner & ~ndi.binary_dilation(layer, structure=np.ones((3, 3), bool), iterations=2)
        if n and fill.any():
            touch = np.unique(lab[(lab > 0) & (di < 1.5)])
            # ... and the warped outline lying a little inside, cut off from the rim by fill: a
            # piece running along the rim (longer than 4 depths of the band), not a detail.
            boxes = ndi.find_objects(lab)
            along = [i + 1 for i, b in enumerate(boxes)
                     if b is not None and max(b[0].stop - b[0].start, b[1].stop - b[1].start) > 4 * lim]
            leak = np.isin(lab, np.union1d(touch[touch > 0], along))
            # A warped outline band running deeper than the band (400 px mixes: 10-25 px) is followed
            # to its end, and a piece of it wholly inside twice the band and running along the rim
            # goes too; a line of the drawing reaching deeper stays (trees55).
            lab2, n2 = ndi.label(layer & (di <= 3.0 * lim), structure=np.ones((3, 3), bool))
            if n2:
                idx2 = np.arange(1, n2 + 1)
                far2 = np.asarray(ndi.maximum(di, lab2, idx2))
                hit = np.asarray(ndi.maximum(leak, lab2, idx2)) > 0
                span2 = np.array([max(b[0].stop - b[0].start, b[1].stop - b[1].start) if b is not None else 0
                                  for b in ndi.find_objects(lab2)])
                more = (far2 <= 2.0 * lim) & (hit | (span2 > 4 * lim))
                leak |= np.isin(lab2, idx2[more])
            _, (iy, ix) = ndi.distance_transform_edt(~fill, return_indices=True)
            mid[leak, :3] = rgb[iy[leak], ix[leak]]
        # The outline ring itself, in the sources' ink and pen width, with a half-ink inner edge.
        # A pixel of depth d (1 on the rim) holds the band from d - 1 to d.
        bare = mid.copy()

        def inked(pw: float) -> np.ndarray:
            m = _ink_ring(bare, inner, di, ink.ink, pw)
            # Pieces of the warped outline deeper than that (at the crown's notches) are specks.
            m = _drop_rim_flecks(m, ink.ink, ink_w)
            return _drop_band_specks(m, inner, di, ink.ink, pw, lim)

        mid = inked(pen_w)
        # The same measure read on the inked mix: the band's fill and a sub-pixel pen's blends add
        # to a source's cover (a 0.64 px pen on a 128 px sticker read 1.35-1.6 px against an ink
        # measured on blends) and so to the ring drawn from it, re-inked 1.5x as heavy as the
        # sources'. The ring is redrawn at the width whose measure on the mix is the sources'
        # (one step, at most 0.6-1.5x; beyond the paper, trees56).
        probe = out.copy()
        probe[inner, :3] = mid[inner, :3]
        probe[(img[..., 3] > 0) & ~inner, :3] = colour
        # (the sources read against the mix's ink too: a source's own ink, lighter or darker than
        # the one drawn, reads a different cover and made the step thin 192 px rings that matched)
        aim = [(_pen_cover(e.image, b, ink.ink, o.width + 2.0), x)
               for e, b, o, x in zip(exemplars, borders, outl, share, strict=True) if o.outlined and b is not None]
        aim_w = float(np.average([c for c, _ in aim], weights=[x + 1e-9 for _, x in aim]))
        got = _pen_cover(probe, _StickerBorder(colour, width, probe), ink.ink, ink_w + 2.0)
        # Only for a pen read on blends for most of the colour share (a sub-pixel pen, found by
        # _thin_ink): on 192 px rings whose ink was measured on the pen's core the step thinned
        # a quarter of the mixes to 0.6-0.7 of the sources' width.
        blended = sum(x for o, x in zip(outl, share, strict=True) if getattr(o, "blended", False))
        if 2.0 * blended > sum(x for o, x in zip(outl, share, strict=True) if o.outlined) \
                and got > 1e-3 and aim_w > 1e-3:
            pen_w *= float(np.clip(aim_w / got, 0.6, 1.5))
            mid = inked(pen_w)
    else:
        mid = _drop_warped_border(mid, inner, colour, width)
    res = out
    res[inner, :3] = mid[inner, :3]
    # The border ring, soft rim pixels included, in the border colour.
    ring = (img[..., 3] > 0) & ~inner
    if not any(ons):
        # A part the warp made thinner than two rings (a trunk) would be all border: its own
        # colours stay where it is no deeper than ``width + 1`` px anywhere nearby (trees52).
        k = 2 * int(np.ceil(width)) + 1
        thin_part = ndi.grey_dilation(depth, size=(k, k)) < width + 1.0
        own = thin_part & opaque & (depth >= 0.5 * width) & (np.linalg.norm(img[..., :3] - colour, axis=2) > 0.35)
        # ... a whole run of it: a few pixels left of a trunk the warp painted over are specks
        lab, n = ndi.label(own, structure=np.ones((3, 3), bool))
        if n:
            sizes = ndi.sum(own, lab, index=np.arange(1, n + 1))
            own = np.isin(lab, 1 + np.flatnonzero(sizes >= 2.0 * width * width))
        ring &= ~own
    res[ring, :3] = colour
    return res
