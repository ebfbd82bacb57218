"""Billboard clouds, step 6b: a drawn crown as whole cards (not in the paper, issue 24).

With ``BillboardParams(drawn_cards=True)`` (opt-in), a drawn tree whose
crown holds inner outlines (:func:`has_inner_outlines`) is built from its
drawn shapes only: every fill region bounded by strokes, the largest one
(the crown's base fill) included, is one billboard carrying its whole
outline, instead of the base fill being cut into superpixels with rear,
interior and core copies in fill colour. Seen from the side, those copies and pieces
covered the strokes with flat-colour blobs; whole cards keep every inner
outline. Where a card's shape has a hole holding other shapes (fruits, a
clump drawn over the base fill), the hole is underpainted with the card's
nearest fill colour (:func:`_underpaint`), and the shapes in it are put in
front of the card (:func:`_nest_cards`), so that the front view is the
drawing and a side view shows fill, not sky, where the shapes moved away.
Shapes in a notch of the silhouette or between several pieces of a split
base fill leave sky when they move away; so the card cloud is kept only
where it holds up from the side (:func:`cards_hold`): it is compared, as
an engine draws it at 45 and 90 degrees, with the superpixel cloud of the
same tree, and the superpixel cloud is used where the cards are worse.

Part of :func:`~branchnb.trees.billboard.billboard_cloud`.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.image import extend_nearest

#: Length of the inner outlines (in stroke widths) per pixel of the crown's equivalent radius from
#: which a drawn crown is built from whole cards (:func:`has_inner_outlines`).
INNER_PER_RADIUS = 1.0


def has_inner_outlines(lines: np.ndarray, crown: np.ndarray, opaque: np.ndarray) -> bool:
    """Whether a drawn crown holds enough inner outlines to be built from whole cards.

    The stroke pixels of ``lines`` inside the crown and off the silhouette
    (:func:`~branchnb.trees.billboard_lines._outer_lines`), divided by the
    stroke width (twice the 90th percentile of the strokes' half width) and
    by the crown's equivalent radius ``sqrt(area / pi)``: a length ratio, the
    same at every size. Outlined clip art (clumps, tiers, fruits, baubles)
    measures 1.1-4.3 on the samples at 96, 200 and 512 px; shaded RPG
    sprites and cartoon clumps without strokes 0.0-0.74, a photograph 0.
    At least :data:`INNER_PER_RADIUS` is a drawing of outlined shapes.

    Parameters
    ----------
    lines, crown, opaque : (H, W) bool arrays
        Line art, crown and opaque pixels of the working image.

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> crown = np.zeros((60, 60), bool); crown[5:55, 5:55] = True
    >>> lines = np.zeros_like(crown); lines[29:31, 10:50] = lines[10:50, 29:31] = True   # a cross
    >>> has_inner_outlines(lines, crown, crown)
    True
    >>> has_inner_outlines(np.zeros_like(crown), crown, crown)
    False
    """
    from .billboard_lines import _outer_lines

    area = float(crown.sum())
    if area <= 0 or not lines.any():
        return False
    inner = lines & crown & ~_outer_lines(lines, opaque)
    half = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
    return bool(inner.sum() / max(1.0, 2.0 * half) >= INNER_PER_RADIUS * np.sqrt(area / np.pi))


def _nest_cards(z: np.ndarray, labels: np.ndarray, card: np.ndarray, opaque: np.ndarray,
                step: float = 1.0):
    """Depths with every shape inside a card's hole in front of that card, and the cards with holes.

    Returns ``(z, holes)``: ``holes`` maps a card's label to True when its shape has
    opaque holes (filled by :func:`_underpaint`)."""
    z = z.copy()
    holes = {}
    objs = ndi.find_objects(labels)
    n = len(z)
    area = np.bincount(labels.ravel(), minlength=n)
    for k in np.argsort(-area[: len(card)], kind="stable"):
        if k == 0 or k >= len(objs) + 1 or not card[k] or objs[k - 1] is None:
            continue
        sl = objs[k - 1]
        m = labels[sl] == k
        hole = _holes(m, opaque[sl])
        if not hole.any():
            continue
        holes[int(k)] = True
        inside = np.unique(labels[sl][hole])
        inside = inside[(inside > 0) & (inside != k) & (inside < n)]
        z[inside] = np.maximum(z[inside], z[k] + step)
    return z, holes


def _holes(m: np.ndarray, opaque: np.ndarray) -> np.ndarray:
    """Opaque pixels enclosed by a card's shape ``m`` (shapes drawn inside the card)."""
    return ndi.binary_fill_holes(m) & ~m & opaque


def _underpaint(tex: np.ndarray, keep: np.ndarray, opaque: np.ndarray, sl, lines: np.ndarray,
                reach: float) -> np.ndarray:
    """``tex`` (a card's texture, alpha already cut to ``keep``) with its holes (:func:`_holes`),
    and the strokes and anti-aliased pixels within ``reach`` of them (the outlines of the shapes
    drawn there), painted with the card's nearest flat fill colour (off its strokes)."""
    hole = _holes(keep, opaque)
    if not hole.any():
        return tex
    rgb = tex[:, :, :3]
    span = (ndi.maximum_filter(rgb, size=(3, 3, 1)) - ndi.minimum_filter(rgb, size=(3, 3, 1))).max(axis=2)
    near = ndi.distance_transform_edt(~hole) <= reach
    paint = hole | (keep & near & (lines[sl] | (span > 0.06)))
    src = keep & ~lines[sl] & (tex[:, :, 3] >= 0.99) & (span <= 0.06) & ~paint
    if not src.any():
        return tex
    out = tex.copy()
    out[paint, :3] = extend_nearest(rgb, src)[paint]
    out[hole, 3] = 1.0
    return out


#: Side views the card cloud is checked from (:func:`cards_hold`), degrees.
CHECK_YAWS = (45.0, 90.0)


def _side_figures(cloud) -> dict:
    """Front PSNR, inner-outline recall at :data:`CHECK_YAWS` and, for an outlined tree, the
    45-degree rim ink of the full and reduced levels as exported (baked outline, side cards)."""
    from ..core.image import composite_over
    from .lod import bake_side_outline, engine_view, reduce_cloud
    from .lod_cards import side_outline_cards
    from .outline import rim_ink_share, silhouette_outline
    from .side_lines import side_line_figures

    baked = bake_side_outline(cloud)
    front = composite_over(engine_view(baked, 0.0, crop="image"), (1, 1, 1))
    ref = composite_over(cloud.image, (1, 1, 1))
    out = {"psnr": 10 * np.log10(1.0 / max(float(np.mean((front - ref) ** 2)), 1e-10))}
    for yaw in CHECK_YAWS:
        out[f"recall{yaw:g}"] = side_line_figures(baked, yaw)["recall"]
        # Sky seen through the crown: cards moved apart in depth open gaps inside the silhouette.
        solid = engine_view(baked, float(yaw))[..., 3] > 0.5
        out[f"closed{yaw:g}"] = 1.0 - float((ndi.binary_fill_holes(solid) & ~solid).sum()) / max(int(solid.sum()), 1)
    o = silhouette_outline(cloud.image)
    if o.outlined:
        red = reduce_cloud(cloud)
        rbaked = bake_side_outline(red)
        out["rim"] = rim_ink_share(engine_view(baked, 45.0, cards=side_outline_cards(cloud, baked=baked)), o.ink)
        out["rrim"] = rim_ink_share(engine_view(rbaked, 45.0, cards=side_outline_cards(red, baked=rbaked)),
                                    o.ink)
    return out


#: Sky a card cloud may show through its side views beyond the superpixel cloud's (share of its opaque
#: pixels): a drawing's own holes widen a little when their rims move in depth (arbre_modern at 200 px:
#: 0.8 %), while cards moved apart open gaps of 2-12 % (three outlined lobes, 45 and 90 degrees).
SKY_TOLERANCE = 0.015


def cards_hold(cards, plain, *, min_psnr: float = 30.0) -> bool:
    """Whether a drawn crown's card cloud is at least as good from the side as its superpixel cloud.

    Not in the paper (issue 24). Whole cards keep a drawing's inner
    outlines from the side, but shapes sitting in a notch of the
    silhouette or between pieces of a split base fill leave sky when they
    move in depth. Both clouds are drawn as an engine shows them
    (:func:`~branchnb.trees.lod.bake_side_outline`,
    :func:`~branchnb.trees.lod.engine_view`): the cards hold when their
    inner-outline recall (:func:`~branchnb.trees.side_lines.side_line_figures`)
    at 45 and 90 degrees and, on an outlined tree, the rim ink share at 45
    degrees of the full and reduced levels with their side cards
    (:func:`~branchnb.trees.outline.rim_ink_share`) are each no lower than
    the superpixel cloud's, no more sky shows through the side views at
    those yaws (holes inside the silhouette, per opaque pixel; up to
    :data:`SKY_TOLERANCE` more), and the
    front view keeps ``min_psnr``.

    Parameters
    ----------
    cards, plain : BillboardCloud
        The same tree built with and without ``drawn_cards``.
    min_psnr : float
        Least PSNR (dB) of the card cloud's front view against its drawing.

    Returns
    -------
    bool

    Examples
    --------
    >>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
    >>> from branchnb.trees.drawn import drawn_tree
    >>> img = drawn_tree("conifer", rng=0, size=96)
    >>> cloud = billboard_cloud(img, params=BillboardParams(max_size=96), rng=0)
    >>> cards_hold(cloud, cloud)
    True
    """
    a, b = _side_figures(cards), _side_figures(plain)
    if a["psnr"] < min_psnr:
        return False
    return all(a[k] >= b[k] - (SKY_TOLERANCE if k.startswith("closed") else 1e-9)
               for k in b if k != "psnr" and k in a)
