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
Not yet handled: shapes in a notch of the silhouette or between several
pieces of a split base fill leave sky when they move away (see
``BillboardParams.drawn_cards``).

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
