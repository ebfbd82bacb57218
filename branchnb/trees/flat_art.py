"""Drawn (flat-art) trees in a variation, beyond the paper: outlines, flatness, pieces, parts.

What a mix of drawn trees needs that the paper's photographs do not: the
exemplars' outlines (:func:`exemplar_outline`, re-inked along a mix's
silhouette), their flatness (:func:`flat_share`, which decides
``colour_mode="auto"``), a result in one piece like its exemplars
(:func:`one_piece`) and the crown/trunk parts (:func:`exemplar_parts`); low-poly crowns
are redrawn facet by facet (``_facet_mix``, :mod:`~branchnb.trees.lowpoly`).
Split out of :mod:`branchnb.trees.variations`, which re-exports every name.

Examples
--------
>>> resolve_colour_mode("auto", [])
'blend'
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy import ndimage as ndi

from ..core.image import extend_nearest
from .processing import Exemplar, ExemplarParams, process_exemplar  # noqa: F401 (doctests)

__all__ = [
    "exemplar_outline",
    "flat_share",
    "resolve_colour_mode",
    "exemplar_largest_hole",
    "one_piece",
    "exemplar_parts",
    "FLAT_ART_SHARE",
]


#: ``colour_mode="auto"`` chooses instead of blending when the mixed exemplars
#: have on average at least this share of their opaque pixels in flat colour
#: areas (:func:`~branchnb.trees.quality.flat_pixels`). Drawn trees measure
#: 0.45-0.83 at 128-256 px (a thin outlined palm at 128 px: 0.047, its
#: outlines take most pixels); the photographed ``tree_cutout_broadleaf``
#: 0.006-0.014: photographs have texture in every 3 x 3 window.
FLAT_ART_SHARE = 0.04


def exemplar_outline(exemplar: Exemplar):
    """:func:`~branchnb.trees.outline.silhouette_outline` of an exemplar (cached on it).

    Parameters
    ----------
    exemplar : Exemplar
        A processed exemplar; the measure is stored on it and reused.

    Returns
    -------
    SilhouetteOutline
        Ink share, colour and stroke width along the silhouette.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> exemplar_outline(lib["tree_rpg_05"]).outlined  # a drawn sprite
    True
    """
    if "outline" not in exemplar._cages:
        from .outline import silhouette_outline

        exemplar._cages["outline"] = silhouette_outline(exemplar.image)
    return exemplar._cages["outline"]


#: Largest RGB distance between the median crown and trunk colours of a tree drawn in one
#: colour (a silhouette), as the palette tolerance of :func:`~branchnb.trees.quality.crossfade_fraction`.
MONOCHROME_TOL = 0.12


def _drawing_group(exemplar: Exemplar) -> int:
    """Style group of an exemplar for ``"parts"``: 1 if outlined, + 2 if drawn in one colour.

    Beyond the paper: a trunk comes only from a source of the crown source's group. A
    silhouette (crown and trunk of one colour, median colours within
    :data:`MONOCHROME_TOL`) given a brown trunk of a coloured tree, or a coloured crown
    given a silhouette's black trunk, no longer reads as one drawing; both keep their own.
    """
    if "group" not in exemplar._cages:
        op = exemplar.alpha
        trunk, crown = op & exemplar.trunk, op & ~exemplar.trunk
        mono = False
        if trunk.sum() >= 4 and crown.sum() >= 4:
            rgb = exemplar.image[..., :3]
            d = np.median(rgb[trunk], axis=0) - np.median(rgb[crown], axis=0)
            mono = bool(np.linalg.norm(d) <= MONOCHROME_TOL)
        exemplar._cages["group"] = int(exemplar_outline(exemplar).outlined) + 2 * mono
    return exemplar._cages["group"]


def _ink_outline(image: np.ndarray, exemplars: Sequence[Exemplar], cw: np.ndarray,
                 sources: np.ndarray | None = None) -> np.ndarray:
    """Ink the silhouette when outlined exemplars hold at least half the colour weight, and
    (``sources``: the ``"choose"`` mode's source per pixel) the seams that cross a fill."""
    from .outline import ink_seams

    outl = [exemplar_outline(e) for e in exemplars]
    on = np.array([o.outlined for o in outl])
    if sources is not None:
        # "choose": what the pixels show decides (a crown from an outlined tree is outlined
        # whatever its colour weight), not the weights.
        cw = np.bincount(sources[sources >= 0], minlength=len(exemplars)).astype(np.float64)
    if cw[on].sum() < 0.5 * cw.sum() - 1e-9 or not on.any():
        return image
    best = outl[int(np.argmax(np.where(on, cw, -1.0)))]
    if sources is not None:
        image = ink_seams(image, sources, best.ink, best.width)
    closed = [_closed_foot(e, o) for e, o in zip(exemplars, outl, strict=True)]
    if sum(w for w, c, o in zip(cw, closed, on, strict=True) if c and o) > 0.5 * cw[on].sum():
        # The outlined sources draw their foot's bottom edge too: the frame's bottom row is then
        # no cut through the trunk, and the mix's foot is inked like the rest of its rim.
        pad = np.zeros((1,) + image.shape[1:], np.float32)
        return _ink_outline_rim(np.concatenate([image, pad], 0), exemplars, cw, on, outl, best)[:-1]
    return _ink_outline_rim(image, exemplars, cw, on, outl, best)


#: A source's foot is closed (its outline runs along the bottom of the trunk) when at least this
#: share of its bottom row is ink.
CLOSED_FOOT_SHARE = 0.6


def _closed_foot(exemplar: Exemplar, outline) -> bool:
    """Whether an outlined exemplar's trunk foot (its bottom row, where it stands) is inked."""
    from .outline import _LUM

    if not outline.outlined:
        return False
    if "closed_foot" not in exemplar._cages:
        img = np.asarray(exemplar.image, np.float32)
        row = img[-1]
        op = row[:, 3] >= 0.5
        ok = False
        if op.sum() >= 2:
            lum = img[..., :3] @ _LUM
            alpha = img[..., 3] >= 0.5
            ink_lum = float(np.asarray(outline.ink, np.float32) @ _LUM)
            # as dark as the outline (a soft, anti-aliased stroke included), not the trunk's fill
            dark = lum[-1] <= ink_lum + 0.5 * (float(np.median(lum[alpha])) - ink_lum)
            ok = bool(dark[op].mean() >= CLOSED_FOOT_SHARE)
        exemplar._cages["closed_foot"] = ok
    return exemplar._cages["closed_foot"]


def _ink_outline_rim(image: np.ndarray, exemplars: Sequence[Exemplar], cw: np.ndarray, on: np.ndarray,
                     outl: list, best) -> np.ndarray:
    """The silhouette outline of :func:`_ink_outline` (seams inked already)."""
    from .outline import even_outline, ink_silhouette
    from .outline_pen import _pen_outline, _pen_width

    i = int(np.argmax(np.where(on, cw, -1.0)))
    profile = _exemplar_pen(exemplars[i])
    if profile is None:
        return _drop_rim_flecks(even_outline(ink_silhouette(image, best.ink, best.width), best.ink, best.width),
                                best.ink, best.width)
    # The sources' own pen (width and soft inner edge, in Euclidean depth) rather than a band of
    # ``best.width`` whole pixels, which was thinner and ragged next to the sources' stroke. Each
    # source is scaled to the working size by its own box, so their pens differ: the mix's is the
    # weighted mean width, in the soft edge of the source with most weight.
    pens = [(_pen_width(p), w) for e, w, o in zip(exemplars, cw, on, strict=True)
            if o and w > 0 and (p := _exemplar_pen(e)) is not None]
    pen = float(np.average([p for p, _ in pens], weights=[w for _, w in pens])) if pens else None
    # Dark regions thicker than the stroke are kept as fills only when a source has one: the rim
    # correction maps the sources' strokes onto the mixed rim and stretches them there.
    fills = any(_exemplar_dark_fill(e) for e, w in zip(exemplars, cw, strict=True) if w > 0)
    image = _pen_outline(ink_silhouette(image, best.ink, best.width), best.ink, best.width, profile, pen,
                         dark_fills=fills)
    return _drop_rim_flecks(image, best.ink, best.width if pen is None else max(best.width, pen))


#: Rim flecks: ink specks at most this many pen widths from the silhouette's edge and at most
#: FLECK_AREA pen widths squared (and 3 pen widths across) are repainted with the fill round them.
FLECK_BAND = 3.0
FLECK_AREA = 2.0


def _drop_rim_flecks(image: np.ndarray, ink, width: float) -> np.ndarray:
    """Repaint ink-coloured specks just inside the mixed silhouette's outline with the fill next to
    them (beyond the paper).

    The sources' outlines at notches and bumps of their crowns are mapped a few pixels inside the
    mix's (smoother) silhouette, where they are left as small dark triangles and dots cut off from
    the outline, often hanging on a 1 px thread. A speck is a connected ink-coloured piece deeper
    than the outline (one pen width and a pixel; reaching 2 px more), within ``FLECK_BAND`` pen widths of the
    silhouette's edge, at most ``FLECK_AREA`` pen widths squared and 3 pen widths across; inner
    lines of the drawing reach deeper or are longer and stay.
    """
    img = np.asarray(image, np.float32)
    opaque = img[..., 3] >= 0.5
    if not opaque.any():
        return image
    w = max(float(width), 1.0)
    ink = np.asarray(ink, np.float32)[:3]
    dark = opaque & (np.abs(img[..., :3] - ink).max(axis=2) < 0.25)
    if not dark.any():
        return image
    filled = ndi.binary_fill_holes(opaque)
    depth = ndi.distance_transform_edt(np.pad(filled, 1))[1:-1, 1:-1]
    # Cut at the outline's own depth: a speck hanging off the outline by a 1 px thread is a fleck.
    lab, n = ndi.label(dark & (depth > w + 1.0), structure=np.ones((3, 3), bool))
    if n == 0:
        return image
    idx = np.arange(1, n + 1)
    far = ndi.maximum(depth, lab, idx)
    area = ndi.sum(np.ones_like(depth), lab, idx)
    boxes = ndi.find_objects(lab)
    span = np.array([max(b[0].stop - b[0].start, b[1].stop - b[1].start) for b in boxes])
    # ... but not the outline's own ragged inner edge, which barely passes the cut.
    fleck = (far > w + 3.0) & (far <= FLECK_BAND * w + 1.0) & (area <= max(FLECK_AREA * w * w, 4.0)) & \
        (span <= 3.0 * w + 1.0)
    if not fleck.any():
        return image
    drop = np.isin(lab, idx[fleck])
    fill = opaque & ~dark
    if not fill.any():
        return image
    _, (iy, ix) = ndi.distance_transform_edt(~fill, return_indices=True)
    out = img.copy()
    out[drop, :3] = img[iy[drop], ix[drop], :3]
    return out


def _pixel_arts(exemplars: Sequence[Exemplar]):
    """The exemplars' :class:`~branchnb.trees.pixel_art.PixelArt` when every one is pixel art, else None."""
    arts = [getattr(e.normalized, "pixel_art", None) for e in exemplars]
    return arts if arts and all(a is not None for a in arts) else None


def _pixel_mix(image: np.ndarray, exemplars: Sequence[Exemplar], cw: np.ndarray, sources: np.ndarray,
               trunk: np.ndarray, outline: bool = True):
    """A mix of pixel-art exemplars on their art-pixel grid (beyond the paper, see
    :mod:`~branchnb.trees.pixel_art`): ``(image, sources, trunk)``, all resampled alike."""
    from .pixel_art import _inner_ink, _pixelate, _rim_ink

    arts = _pixel_arts(exemplars)
    blocks = [a.block * e.normalized.scale for a, e in zip(arts, exemplars, strict=True)]
    outl = [exemplar_outline(e) for e in exemplars]
    # inks: the measured outline, else a rim drawn in the darkest palette colour (sprites enlarged by a
    # non-integer factor, thin palm fronds: the stroke measure misses those)
    inks = [o.ink if o.outlined else _rim_ink(e.image, a.palette) for o, e, a in zip(outl, exemplars, arts)]
    on = np.array([k is not None for k in inks])
    ink = None
    if outline and on.any() and cw[on].sum() >= 0.5 * cw.sum() - 1e-9:
        ink = inks[int(np.argmax(np.where(on, cw, -1.0)))]
    # the outline's width in art pixels, as the outlined sources draw it (a 2-3 px game-sprite
    # outline was re-inked 1 px wide and the ring inside it repainted as a stray outline)
    wide = [o.width / max(b, 1.0) for o, b in zip(outl, blocks, strict=True) if o.outlined]
    ink_blocks = max(1, int(round(float(np.median(wide))))) if wide else 1
    inner = ink is None or any(_inner_ink(e.image, ink, b) for e, b in zip(exemplars, blocks, strict=True))
    out, (src, tr) = _pixelate(image, arts, blocks, ink=ink, layers=(sources, trunk), inner_ink=inner,
                               ink_blocks=ink_blocks)
    return out, src, tr


def _source_pixel(exemplar: Exemplar) -> float:
    """Size of a source pixel in working pixels (1 when the source was shrunk)."""
    norm = getattr(exemplar, "normalized", None)
    return max(1.0, float(getattr(norm, "scale", 1.0)))


def _exemplar_straight_trunk(exemplar: Exemplar) -> bool:
    """Whether an exemplar's trunk has straight sides (:func:`~branchnb.trees.trunk_lines.trunk_edges`,
    :data:`~branchnb.trees.trunk_lines.STRAIGHT_SHARE` of its free rows within a pixel of its
    lines; cached on it)."""
    if "straight_trunk" not in exemplar._cages:
        from .trunk_lines import STRAIGHT_SHARE, trunk_edges

        e = trunk_edges(exemplar.image, exemplar.trunk)
        exemplar._cages["straight_trunk"] = e is not None and e.share >= STRAIGHT_SHARE
    return exemplar._cages["straight_trunk"]


def _hard_edged(exemplar: Exemplar) -> bool:
    """Whether an exemplar is drawn without anti-aliasing: under 5 % of its silhouette's rim
    pixels of partial alpha (cached on it)."""
    if "hard_edged" not in exemplar._cages:
        a = exemplar.image[..., 3]
        op = a >= 0.5
        rim = ndi.binary_dilation(op) & ~ndi.binary_erosion(op)
        part = (a > 0.05) & (a < 0.95)
        exemplar._cages["hard_edged"] = bool(rim.any()) and float(part[rim].mean()) < 0.05
    return exemplar._cages["hard_edged"]


def _straight_trunk_mix(image: np.ndarray, exemplars: Sequence[Exemplar], sources: np.ndarray,
                        trunk: np.ndarray, grains: Sequence[float] | None = None):
    """A hard-edged mix whose sources all stand on straight trunks, its trunk's sides redrawn
    straight (beyond the paper, :mod:`~branchnb.trees.trunk_lines`): ``(image, sources, trunk)``.
    ``grains`` are the pixel-art sources' art pixels (a grid of blocks keeps its steps); without
    them every source must be hard-edged (an anti-aliased mix keeps its soft sides)."""
    from .trunk_lines import straighten_trunk

    if grains is not None and max(grains) > 1.5:
        return image, sources, trunk
    if grains is None and not all(_hard_edged(e) for e in exemplars):
        return image, sources, trunk
    if not all(_exemplar_straight_trunk(e) for e in exemplars):
        return image, sources, trunk
    out, tr, src = straighten_trunk(image, trunk, sources=sources)
    return out, src, tr


def _exemplar_facets(exemplar: Exemplar):
    """:func:`~branchnb.trees.lowpoly.facet_palette` of an exemplar's crown (cached on it)."""
    if "facets" not in exemplar._cages:
        from .lowpoly import SMOOTH_BLUR, SMOOTH_BLUR_MOST, facet_palette

        # an outlined crown (tiers of a drawn fir) keeps its ink; its thin ring is too small for a
        # facet region and would join the fills beside it
        # (and a sticker's die-cut border, rebuilt by sticker.py)
        from .sticker import _exemplar_border

        # an enlarged source resampled smoothly (not pixel art, kept nearest) has its facet edges
        # blurred over more than one of its pixels
        pixel = _source_pixel(exemplar)
        if pixel > 1.0 and getattr(getattr(exemplar, "normalized", None), "pixel_art", None) is None:
            pixel = min(pixel * SMOOTH_BLUR, pixel + SMOOTH_BLUR_MOST)
        exemplar._cages["facets"] = (None if exemplar_outline(exemplar).outlined or _exemplar_border(exemplar)
                                     is not None else facet_palette(exemplar.image, exemplar.trunk,
                                                                     pixel=pixel))
    return exemplar._cages["facets"]


#: A mix's crown is redrawn as facets when sources painting at least this share of it are
#: low-poly (:func:`_facet_mix`); the rest of it may be anti-aliased steps only.
FACET_CROWN = 0.95


def _facet_mix(image: np.ndarray, exemplars: Sequence[Exemplar], sources: np.ndarray, trunk: np.ndarray):
    """A ``"choose"`` mix whose crown comes from low-poly exemplars, its facets redrawn straight
    (beyond the paper, :mod:`~branchnb.trees.lowpoly`): ``(image, sources)``; unchanged otherwise."""
    from .lowpoly import straighten_facets

    crown = (image[..., 3] >= 0.5) & (trunk < 0.5) & (sources >= 0)
    if not crown.any():
        return image, sources
    share = np.bincount(sources[crown], minlength=len(exemplars)) / crown.sum()
    pals = [_exemplar_facets(e) for e in exemplars]
    faceted = np.array([p is not None for p in pals])
    if share[faceted].sum() < FACET_CROWN:
        return image, sources
    pal = np.unique(np.concatenate([p for p in pals if p is not None]), axis=0)
    src = np.where(image[..., 3] >= 0.5, sources, -1)
    out, src = straighten_facets(image, pal, trunk, sources=src)
    return out, np.where(src >= 0, src, sources)


def _exemplar_dark_fill(exemplar: Exemplar) -> bool:
    """Whether an exemplar has an ink-dark fill region (:func:`~branchnb.trees.outline._has_dark_fill`,
    cached on it; True when it has no outline: nothing to tell)."""
    if "dark_fill" not in exemplar._cages:
        from .outline import _has_dark_fill

        o = exemplar_outline(exemplar)
        exemplar._cages["dark_fill"] = _has_dark_fill(exemplar.image, o.ink, o.width) if o.outlined else True
    return exemplar._cages["dark_fill"]


def _exemplar_pen(exemplar: Exemplar):
    """The pen profile of an outlined exemplar (:func:`~branchnb.trees.outline_pen._pen_profile`,
    cached on it; None when not outlined or unmeasurable)."""
    if "pen" not in exemplar._cages:
        from .outline_pen import _pen_profile

        o = exemplar_outline(exemplar)
        exemplar._cages["pen"] = _pen_profile(exemplar.image, o.ink, o.width) if o.outlined else None
    return exemplar._cages["pen"]


def flat_share(exemplar: Exemplar) -> float:
    """Share of an exemplar's opaque pixels in flat colour areas (cached on the exemplar).

    Parameters
    ----------
    exemplar : Exemplar
        A processed exemplar.

    Returns
    -------
    float
        :func:`~branchnb.trees.quality.flat_pixels` over the opaque pixels,
        in [0, 1]: drawn trees measure 0.05-0.9, photographs about 0.01.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> flat_share(lib["tree_rpg_05"]) > FLAT_ART_SHARE
    True
    """
    if "flat_share" not in exemplar._cages:
        from .quality import flat_pixels

        n = max(int(exemplar.alpha.sum()), 1)
        exemplar._cages["flat_share"] = float(flat_pixels(exemplar.image).sum() / n)
    return exemplar._cages["flat_share"]


def resolve_colour_mode(mode: str, exemplars: Sequence[Exemplar]) -> str:
    """``"blend"`` or ``"choose"`` for ``mode`` (``"auto"``: by the exemplars' :func:`flat_share`).

    Parameters
    ----------
    mode : {"auto", "blend", "choose"}
        ``VariationParams.colour_mode``; ``"blend"`` and ``"choose"`` are
        returned as they are.
    exemplars : sequence of Exemplar
        The exemplars mixed; ``"auto"`` chooses when their mean flat share
        is at least :data:`FLAT_ART_SHARE` (an empty list blends).

    Returns
    -------
    str
        ``"blend"`` or ``"choose"``.

    Raises
    ------
    ValueError
        Unknown ``mode``.

    Examples
    --------
    >>> resolve_colour_mode("blend", []), resolve_colour_mode("auto", [])
    ('blend', 'blend')
    """
    if mode not in ("auto", "blend", "choose"):
        raise ValueError(f"colour_mode must be 'auto', 'blend' or 'choose', got {mode!r}")
    if mode != "auto":
        return mode
    share = float(np.mean([flat_share(e) for e in exemplars])) if exemplars else 0.0
    return "choose" if share >= FLAT_ART_SHARE else "blend"


def _holes(alpha: np.ndarray) -> tuple[np.ndarray, int]:
    """Transparent regions not connected to the image border, and their count."""
    lab, n = ndi.label(~alpha)
    border = np.unique(np.concatenate([lab[0], lab[-1], lab[:, 0], lab[:, -1]]))
    holes = (lab > 0) & ~np.isin(lab, border)
    return holes, int(n - np.count_nonzero(border > 0))


def exemplar_largest_hole(exemplar: Exemplar) -> int:
    """Area (pixels) of the largest interior transparent hole of an exemplar.

    Parameters
    ----------
    exemplar : Exemplar
        A processed exemplar (its binary alpha at the working size).

    Returns
    -------
    int
        Pixels of the largest transparent 4-connected region that does not
        touch the image border (0 without holes); :func:`one_piece` fills
        larger holes in a variation.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> exemplar_largest_hole(lib["tree_rpg_05"]) >= 0
    True
    """
    holes, _ = _holes(exemplar.alpha)
    if not holes.any():
        return 0
    lab, _ = ndi.label(holes)
    return int(np.bincount(lab.ravel())[1:].max())


def one_piece(image, exemplars: Sequence[Exemplar]) -> np.ndarray:
    """Keep a variation in one piece, like its exemplars.

    The largest opaque component (8-connected) is kept; other components
    are kept only if some exemplar has several pieces and they are at least
    as large as that exemplar's smallest piece, and never more pieces than
    the most broken-up exemplar has (the largest ones). Interior transparent holes
    larger than the largest hole of the exemplars are filled, with the
    colour of the nearest opaque pixel.

    Parameters
    ----------
    image : (S, S, 4) array_like
        Straight RGBA with binary alpha.
    exemplars : sequence of Exemplar
        The exemplars that were mixed.

    Returns
    -------
    (S, S, 4) float32 ndarray

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> ex = process_exemplar(synthetic_tree("clean", rng=0, size=64).image, size=64, trunk="stem")
    >>> img = ex.image.copy(); img[0, 0] = (0.0, 0.6, 0.0, 1.0)     # a stray speck
    >>> float(one_piece(img, [ex])[0, 0, 3])
    0.0
    """
    return _one_piece(image, exemplars)


def _own_holes(alpha: np.ndarray, exemplars: Sequence[Exemplar], cage: np.ndarray, m_points: int) -> np.ndarray:
    """Hole pixels of a mix that the cage maps into a hole of one of its exemplars (their drawing's own)."""
    from .mvc import mvc_map

    holes, _ = _holes(alpha)
    out = np.zeros(alpha.shape, bool)
    if not holes.any():
        return out
    ys, xs = np.nonzero(holes)
    pts = np.stack([xs, ys], axis=1).astype(np.float64)
    for e in exemplars:
        own = ndi.binary_dilation(_holes(e.alpha)[0], iterations=2)
        if not own.any():
            continue
        q = mvc_map(pts, cage, e.cage(m_points))
        px = np.clip(np.rint(q[:, 0]), 0, own.shape[1] - 1).astype(np.int64)
        py = np.clip(np.rint(q[:, 1]), 0, own.shape[0] - 1).astype(np.int64)
        out[ys, xs] |= own[py, px]
    return out


def _one_piece(image, exemplars: Sequence[Exemplar], own_holes=None) -> np.ndarray:
    img = np.array(image, dtype=np.float32, copy=True)
    alpha = img[:, :, 3] >= 0.5
    if not alpha.any():
        return img
    lab, n = ndi.label(alpha, structure=np.ones((3, 3), bool))
    if n > 1:
        areas = np.bincount(lab.ravel())
        areas[0] = 0
        keep = areas >= areas.max()
        pieces = [np.bincount(ndi.label(e.alpha, structure=np.ones((3, 3), bool))[0].ravel())[1:]
                  for e in exemplars]
        multi = [p.min() for p in pieces if len(p) > 1]
        if multi:
            keep |= areas >= min(multi)
            # Never more pieces than the most broken-up exemplar: a warp can
            # split its thin parts into crumbs, which are no pieces of its own.
            most = max(len(p) for p in pieces)
            order = np.argsort(areas)[::-1]
            keep[order[most:]] = False
        keep[0] = False
        alpha = keep[lab]
    holes, _ = _holes(alpha)
    if holes.any():
        limit = max((exemplar_largest_hole(e) for e in exemplars), default=0)
        hl, _ = ndi.label(holes)
        sizes = np.bincount(hl.ravel())
        sizes[0] = 0
        big = sizes > limit
        if own_holes is not None:       # holes the exemplars' own holes map to stay open
            big[np.unique(hl[own_holes & holes])] = False
        fill = big[hl] & holes
        if fill.any():
            img[fill, :3] = extend_nearest(img[:, :, :3], alpha)[fill]
            alpha = alpha | fill
    img[~alpha] = 0.0
    img[:, :, 3] = alpha
    return img


def exemplar_parts(exemplar: Exemplar) -> np.ndarray:
    """An exemplar's parts as :func:`~branchnb.trees.histogram_transfer.tree_parts` labels its image.

    Parameters
    ----------
    exemplar : Exemplar
        A processed exemplar; its stored trunk mask splits the opaque pixels.

    Returns
    -------
    (S, S) uint8 ndarray
        0 background, 1 crown, 2 trunk.

    Examples
    --------
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> img = synthetic_tree("clean", rng=0, size=64).image
    >>> ex = process_exemplar(img, "t", exemplar_params=ExemplarParams(size=64))
    >>> sorted(np.unique(exemplar_parts(ex)).tolist())
    [0, 1, 2]
    """
    if not isinstance(exemplar, Exemplar):
        raise TypeError(f"exemplar must be an Exemplar, got {type(exemplar).__name__}")
    opaque = exemplar.image[..., 3] >= 0.5
    return np.where(opaque, np.where(exemplar.trunk & opaque, 2, 1), 0).astype(np.uint8)
