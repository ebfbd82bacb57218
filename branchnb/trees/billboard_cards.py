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


#: Least share of a crown's fill pixels (off the line art, 2 px in from it and the silhouette) that
#: are flat (3 x 3 colour span at most 0.04) for :func:`flat_fill_cards`. The outlined RPG samples
#: measure 0.96-1.00 at 96, 200 and 512 px (0.70-0.97 without the 2 px margin, whose anti-aliased
#: pixels weigh most at 96 px); shaded sprites and cartoon clumps 0.62-0.97, but none is outlined.
FLAT_FILL_SHARE = 0.9


def flat_fill_cards(rgba: np.ndarray, crown: np.ndarray, lines: np.ndarray) -> bool:
    """Whether a crown without inner strokes is a flat fill in an outline band, built from cards.

    Beyond the paper (issue 24). :func:`has_inner_outlines` asks for
    strokes inside the crown; an RPG sprite has none: a flat green fill in
    a thick brown band, whose tiers and lobes are drawn by the band alone,
    folding in along the silhouette. Split into superpixels, the band's
    pieces swing across the crown from the side and its tiers melt into
    one round blob (inner-outline recall 0.11-0.78 at 45 and 90 degrees on
    mixes of the RPG samples). Such a crown is built from whole cards
    (one per fill region) when its silhouette is outlined
    (:func:`~branchnb.trees.outline.silhouette_outline`) and at least
    :data:`FLAT_FILL_SHARE` of its pixels off the line art (2 px in from
    it, past the anti-aliasing) are flat (3 x 3 colour span at most 0.04);
    shaded sprites and photographs are not. :func:`cards_hold` still compares the cards with the superpixel
    cloud.

    Parameters
    ----------
    rgba : (H, W, 4) array
        The working image, straight RGBA in [0, 1].
    crown, lines : (H, W) bool arrays
        Crown pixels and line art (:func:`~branchnb.trees.billboard_lines.line_art`).

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 40, 4), np.float32); img[4:36, 4:36] = (0.35, 0.2, 0.0, 1.0)
    >>> img[8:32, 8:32, :3] = (0.0, 0.65, 0.0)              # a green fill in a 4 px brown band
    >>> lines = np.zeros((40, 40), bool); lines[4:36, 4:8] = lines[4:36, 32:36] = True
    >>> lines[4:8, 4:36] = lines[32:36, 4:36] = True
    >>> flat_fill_cards(img, img[..., 3] > 0.5, lines)
    True
    """
    from .billboard_lines import _colour_span3
    from .outline import silhouette_outline

    crown = np.asarray(crown, bool)
    free = crown & ~np.asarray(lines, bool)
    if free.sum() < 16 or not silhouette_outline(rgba).outlined:
        return False
    core = ndi.binary_erosion(free, iterations=2)
    if core.sum() >= 16:
        free = core
    flat = _colour_span3(np.asarray(rgba, np.float32)[:, :, :3]) <= 0.04
    return bool(flat[free].mean() >= FLAT_FILL_SHARE)


#: Least share of a crown's opaque pixels within 0.06 of its 16 most frequent colours
#: (:func:`~branchnb.trees.quality.palette_coverage`) for :func:`shaded_cards`. Drawings shaded in
#: a few tones or with smooth gradients measure 0.81-1.00 on their crowns at 96 and 512 px
#: (cartoon_tree, evergreen, tree_rpg_13/14, christmas_tree_root_flare, palm_island), the
#: photographed tree_cutout_broadleaf 0.46-0.57.
SHADED_COVERAGE = 0.75


def shaded_cards(rgba: np.ndarray, crown: np.ndarray) -> bool:
    """Whether a drawn crown without outlines (shaded tones, gradients) is built from cards.

    Beyond the paper (issue 24). :func:`has_inner_outlines` and
    :func:`flat_fill_cards` ask for strokes inside the crown or a flat fill
    in an outline band; a crown drawn in clumps of a few tones of green
    without outlines (``cartoon_tree``), or a gradient fill whose band is
    not taken for an outline (the RPG palms), has neither. Cut into
    superpixels, its clumps and the band folding in over it swing apart
    from the side and the drawing melts into blobs (inner-outline recall
    0.17-0.62 at 45 and 90 degrees). The crown is segmented by its own
    regions (the fill regions of the line art, else its opaque pixels) and
    built from cards when it is a drawing: at least :data:`SHADED_COVERAGE`
    of its pixels are near one of its 16 main colours (a photograph's
    foliage is not). :func:`cards_hold` still compares the cards with the
    superpixel cloud.

    Parameters
    ----------
    rgba : (H, W, 4) array
        The working image, straight RGBA in [0, 1].
    crown : (H, W) bool array
        Crown pixels.

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 40, 4), np.float32); img[4:36, 4:36] = (0.1, 0.5, 0.1, 1.0)
    >>> img[10:20, 10:20, :3] = (0.3, 0.8, 0.2)               # a lighter clump, no outline
    >>> shaded_cards(img, img[..., 3] > 0.5)
    True
    >>> rng = np.random.default_rng(0)
    >>> img[4:36, 4:36, :3] = rng.random((32, 32, 3))          # photographic noise
    >>> shaded_cards(img, img[..., 3] > 0.5)
    False
    """
    from .quality import palette_coverage

    crown = np.asarray(crown, bool)
    if crown.sum() < 16:
        return False
    img = np.array(rgba, np.float32, copy=True)
    img[..., 3] = np.where(crown, img[..., 3], 0.0)
    return bool(palette_coverage(img) >= SHADED_COVERAGE)


#: Least 3 x 3 colour span (per channel) of a sharp tone edge inside a shaded crown
#: (:func:`tone_edges`): clumps drawn in different tones of green differ by 0.2-0.5, a smooth
#: gradient changes by at most 0.03 over 3 pixels at 96-512 px.
TONE_EDGE = 0.12


def tone_edges(rgba: np.ndarray, crown: np.ndarray) -> np.ndarray:
    """Sharp colour edges inside a crown: where two tones of a drawing without outlines meet.

    Beyond the paper (issue 24). A crown drawn as overlapping clumps in a
    few tones (``cartoon_tree``) or tiers set off by highlight lines
    (``evergreen``) has no strokes between its shapes, so the fill regions
    of its line art are the whole crown, one card. Its crown pixels (off
    the silhouette's outermost pixel) whose 3 x 3 colour span exceeds
    :data:`TONE_EDGE` split it instead, as strokes would: each clump or
    tier of one tone is a card of its own, and a smooth gradient (no such
    edge) stays one card.

    Parameters
    ----------
    rgba : (H, W, 4) array
        The working image, straight RGBA in [0, 1].
    crown : (H, W) bool array
        Crown pixels.

    Returns
    -------
    (H, W) bool ndarray
        The edge pixels (a subset of ``crown``).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((20, 20, 4), np.float32); img[2:18, 2:18] = (0.1, 0.5, 0.1, 1.0)
    >>> img[2:18, 10:18, :3] = (0.3, 0.8, 0.2)               # a second tone, no outline
    >>> e = tone_edges(img, img[..., 3] > 0.5)
    >>> sorted(set(np.nonzero(e)[1].tolist()))
    [9, 10]
    """
    from .billboard_lines import _colour_span3

    crown = np.asarray(crown, bool)
    inner = ndi.binary_erosion(crown, border_value=1)
    return inner & (_colour_span3(np.asarray(rgba, np.float32)[:, :, :3]) > TONE_EDGE)


def crown_inlay(crown: np.ndarray, trunk: np.ndarray) -> np.ndarray:
    """Trunk pixels inside the crown's rows (between a row's leftmost and rightmost crown pixel).

    Beyond the paper (issue 24): on a flat-fill crown built from cards
    (:func:`flat_fill_cards`) they go on the cards, so that branches drawn
    over the crown turn with it from the side instead of opening sky in
    its notches.

    Parameters
    ----------
    crown, trunk : (H, W) bool array_like
        Crown and trunk pixels of the working image (same shape).

    Returns
    -------
    (H, W) bool ndarray
        The trunk pixels that lie within their row's span of crown.

    Raises
    ------
    ValueError
        If ``crown`` and ``trunk`` are not 2-D arrays of one shape.

    Examples
    --------
    >>> import numpy as np
    >>> crown = np.zeros((5, 7), bool); crown[1:3, 1:6] = True; crown[1:3, 3] = False
    >>> trunk = np.zeros_like(crown); trunk[1:5, 3] = True
    >>> crown_inlay(crown, trunk)[:, 3].astype(int).tolist()
    [0, 1, 1, 0, 0]
    """
    crown = np.asarray(crown, bool)
    trunk = np.asarray(trunk, bool)
    if crown.ndim != 2 or trunk.shape != crown.shape:
        raise ValueError(f"crown and trunk must be 2-D masks of one shape, got {crown.shape} and {trunk.shape}")
    cols = np.arange(crown.shape[1])
    has = crown.any(axis=1)
    left = np.where(has, np.argmax(crown, axis=1), crown.shape[1])
    right = np.where(has, crown.shape[1] - 1 - np.argmax(crown[:, ::-1], axis=1), -1)
    return trunk & (cols[None, :] >= left[:, None]) & (cols[None, :] <= right[:, None])


def _nest_cards(z: np.ndarray, labels: np.ndarray, card: np.ndarray, opaque: np.ndarray,
                step: float = 1.0, *, notches: bool = True, trunk: np.ndarray | None = None):
    """Depths with every shape inside a card's hole (or notch) in front of that card.

    A shape drawn over a card is in its hole (:func:`_holes`) or, at the
    silhouette, in a notch of it (:func:`_notch_shapes`, a fruit drawn on
    the crown's rim). Returns ``(z, holes, owner)``: ``holes`` maps a
    card's label to the (H, W) bool mask of the pixels its texture is to be
    underpainted over (:func:`_underpaint`), ``owner`` maps every shape so
    nested to the innermost card it lies on (the billboard builder centres
    its quad on that card's, so that no side view turns it behind the card).
    ``trunk`` (an (H, W) bool mask, optional) is the trunk's pixels: round a
    shape in a notch they count as allowed, like sky (a bauble where a crown
    tier meets the trunk; beyond the earlier rule, issue 24).
    """
    z = z.copy()
    holes: dict = {}
    owner: dict = {}
    objs = ndi.find_objects(labels)
    n = len(z)
    H, W = labels.shape
    area = np.bincount(labels.ravel(), minlength=n)
    cards = [int(k) for k in np.flatnonzero(card[: min(len(card), n)]) if k > 0 and k <= len(objs)
             and objs[k - 1] is not None]
    for k in np.argsort(-area[: len(card)], kind="stable"):
        if k == 0 or k >= len(objs) + 1 or not card[k] or objs[k - 1] is None:
            continue
        sl = objs[k - 1]
        m = labels[sl] == k
        hole = np.zeros((H, W), bool)
        hole[sl] = _holes(m, opaque[sl])
        if notches:
            inner = set(int(v) for v in np.unique(labels[hole]))
            while True:
                more = _notch_shapes(labels, k, [c for c in cards if c != k and c not in owner and c not in inner],
                                     opaque, objs, inner, trunk=trunk)
                if not more:
                    break
                for s in more:
                    hole |= labels == s
                    inner.add(s)
        if not hole.any():
            continue
        holes[int(k)] = hole
        inside = np.unique(labels[hole])
        inside = inside[(inside > 0) & (inside != k) & (inside < n)]
        z[inside] = z[k] + step + NEST_DEPTH * np.maximum(z[inside] - z[k] - step, 0.0)
        for s in inside:
            owner[int(s)] = int(k)
    return z, holes, owner


#: Share of its own depth in front of its card a nested shape keeps (:func:`_nest_cards`): at its
#: full depth (1.0) a clump stack 58 px in front of a 200 px fruit tree's crown slid over the
#: outlines beside it at 45 degrees (recall 0.86); at 0.3 the generated broadleaf and fruit trees
#: (seed 0, with and without a leaf pile) keep 0.98-0.99 at 45 and 0.96 at 90 degrees, with parallax.
NEST_DEPTH = 0.3
#: A shape may also sit in a notch together with other candidate shapes (clumps touching each other
#: at the rim, at least 30 % of their ring on the card): fruit_pile_0 at 200 px, recall at 45 degrees
#: 0.87 -> 0.97 (its cards still fall back: a bite opens at 90 degrees).
_PEERS = True

#: A shape is in a notch of a card (:func:`_notch_shapes`) when at least this share of the pixels
#: round it are the card's, and the rest sky (or trunk).
NOTCH_SHARE = 0.55
#: Trunk pixels round a shape count as allowed in :func:`_notch_shapes` (beyond the earlier rule,
#: issue 24): christmas_tree_root_flare at 512 px has a bauble where the lowest tier meets the
#: trunk (ring 79 % tier, 21 % trunk, no sky); left out of the tier's window, nothing filled
#: behind it and sky opened there at 45 degrees.
_TRUNK_NOTCH = True


def _notch_shapes(labels: np.ndarray, k: int, others: list, opaque: np.ndarray, objs,
                  inner=(), trunk: np.ndarray | None = None) -> list:
    """The shapes among ``others`` that sit in a notch of card ``k`` at the silhouette.

    Round the shape (a 2-pixel ring), at least :data:`NOTCH_SHARE` of the
    pixels are card ``k``'s and all the others are sky (beyond the
    silhouette, at most 45 %), shapes already nested in ``k`` (``inner``)
    or, beyond the earlier rule, the trunk's (``trunk``, an (H, W) bool
    mask; :data:`_TRUNK_NOTCH`, only where no sky is round the shape): a fruit or clump drawn over the crown's
    rim, or a bauble where a tier meets the trunk. A conifer's tier (mostly
    sky round it) or a shape touching other cards is not in a notch.
    """
    use_trunk = _TRUNK_NOTCH and trunk is not None
    inner = np.asarray(sorted(inner), int)
    H, W = labels.shape
    out = []
    for s in others:
        sl = objs[s - 1]
        win = (slice(max(sl[0].start - 3, 0), min(sl[0].stop + 3, H)),
               slice(max(sl[1].start - 3, 0), min(sl[1].stop + 3, W)))
        m = labels[win] == s
        ring = ndi.binary_dilation(m, iterations=2) & ~m
        n = int(ring.sum())
        if n == 0:
            continue
        on_k = int((ring & (labels[win] == k)).sum()) / n
        sky = int((ring & ~opaque[win]).sum()) / n
        nested = int((ring & np.isin(labels[win], inner)).sum()) / n if inner.size else 0.0
        peers = int((ring & np.isin(labels[win], others)).sum()) / n
        if use_trunk and sky == 0.0:
            # Enclosed by the card and the trunk (no sky round it): arbre_modern at 256 px has a
            # clump at the rim touching the trunk and sky, which nested lost rim ink (0.970 -> 0.963).
            sky = int((ring & opaque[win] & trunk[win] & (labels[win] != k)).sum()) / n
        if (on_k >= NOTCH_SHARE * (1.0 - nested) and sky <= 0.45 and on_k + sky + nested >= 0.97) or \
                (_PEERS and on_k >= 0.3 and sky <= 0.45 and on_k + sky + nested + peers >= 0.97):
            out.append(s)
    return out


def _holes(m: np.ndarray, opaque: np.ndarray) -> np.ndarray:
    """Opaque pixels enclosed by a card's shape ``m`` (shapes drawn inside the card)."""
    return ndi.binary_fill_holes(m) & ~m & opaque


def _underpaint(tex: np.ndarray, keep: np.ndarray, opaque: np.ndarray, sl, lines: np.ndarray,
                reach: float, hole: np.ndarray | None = None, alpha: np.ndarray | None = None,
                trunk: np.ndarray | None = None) -> np.ndarray:
    """``tex`` (a card's texture, alpha already cut to ``keep``) with its holes (:func:`_holes`,
    or the window of ``hole``, an (H, W) mask from :func:`_nest_cards`), and the strokes and
    anti-aliased pixels within ``reach`` of them (the outlines of the shapes drawn there), painted
    with the card's nearest flat fill colour (off its strokes); strokes along the silhouette (a
    notch's rim) keep their ink. ``alpha`` (the window's alpha in the drawing; default 1) is the
    alpha the hole gets. ``trunk`` (an (H, W) mask of the trunk's pixels, optional; beyond the
    earlier rule, issue 24): the hole's pixels take the colour of the nearer of the card's flat fill
    and the trunk's (a bauble where a tier meets the trunk is filled behind from both)."""
    hole = _holes(keep, opaque) if hole is None else (hole[sl] & opaque & ~keep)
    if not hole.any():
        return tex
    rgb = tex[:, :, :3]
    span = (ndi.maximum_filter(rgb, size=(3, 3, 1)) - ndi.minimum_filter(rgb, size=(3, 3, 1))).max(axis=2)
    near = ndi.distance_transform_edt(~hole) <= reach
    rim = lines[sl] & (ndi.distance_transform_edt(opaque) <= reach + 1)
    paint = (hole | (keep & near & (lines[sl] | (span > 0.06)))) & ~rim
    src = keep & ~lines[sl] & (tex[:, :, 3] >= 0.99) & (span <= 0.06) & ~paint
    if not src.any():
        return tex
    out = tex.copy()
    out[paint, :3] = extend_nearest(rgb, src)[paint]
    if trunk is not None:
        t_src = trunk[sl] & opaque & ~keep & ~lines[sl] & (span <= 0.06) & ~paint
        # Only the hole's pieces that touch the trunk (a bauble on it), not those the card encloses.
        lab, _ = ndi.label(hole)
        near_t = np.unique(lab[ndi.binary_dilation(t_src, iterations=2) & hole])
        on_t = np.isin(lab, near_t[near_t > 0])
        if on_t.any():
            out[on_t, :3] = extend_nearest(rgb, src | t_src)[on_t]
    out[hole, 3] = 1.0 if alpha is None else alpha[hole]
    return out


#: Side views the card cloud is checked from (:func:`cards_hold`), degrees.
CHECK_YAWS = (45.0, 90.0)


#: Fewest inner-outline pixels whose recall :func:`cards_hold` compares: tree_rpg_05 at 96 px has 6
#: (a stroke's tip), of which the cards kept 4 and the superpixels 5 at 45 degrees, so its cards
#: (recall 0.83 against 0.0 at 90 degrees once it has 845 at 512 px) fell back.
MIN_INNER_LINES = 20


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
        f = side_line_figures(baked, yaw)
        # A few inner-outline pixels (a stroke's tip folding in) say nothing of the drawing's lines.
        out[f"recall{yaw:g}"] = f["recall"] if f["lines"] >= MIN_INNER_LINES else 1.0
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


#: Figures of a card cloud good enough to keep it without building the superpixel cloud
#: (:func:`cards_hold`): inner-outline recall at every check yaw, and rim ink of both levels. With
#: them, 13 of the 24 drawn trees (96-512 px) skip the second build.
GOOD_RECALL = 0.95
#: Rim ink share (45 degrees, full and reduced levels) a card cloud may keep even where the superpixel
#: cloud's is higher (:func:`cards_hold`): fruit_0_s11 at 96 px, 0.994 against 0.997, fell back to
#: a cloud whose inner-outline recall at 90 degrees is 0.72 (cards 0.97).
GOOD_RIM = 0.95


#: Rim ink share (45 degrees) a card cloud may lose against the superpixel cloud's, below
#: :data:`GOOD_RIM`, where it keeps at least :data:`RECALL_GAIN` more of the inner outlines at some
#: check yaw (:func:`cards_hold`). On the RPG sprites (flat fill in a thick band) the reduced
#: level's rim reads 0.888-0.891 with cards at 96 px and 0.927-0.947 at 200 px, against
#: 0.958-0.995 for superpixels: the shortfall is isolated anti-aliased pixels of the band (a larger
#: share of a shorter rim at 96 px), while the superpixel cloud keeps 0.0-0.74 of the inner outlines.
RIM_TRADE = 0.07
#: Inner-outline recall gain that buys :data:`RIM_TRADE`.
RECALL_GAIN = 0.2
#: Inner-outline recall a card cloud may lose against a superpixel cloud that shows at least
#: :data:`SKY_TOLERANCE` more sky inside its side views (which also buys :data:`RIM_TRADE`):
#: christmas_tree_root_flare at 512 px fell back to superpixels with 3.5-4.2 % sky (baubles
#: moved off their holes, white discs from the side) for 0.939 / 0.940 against 0.959 / 0.948.
RECALL_SLACK = 0.03
#: Sky a card cloud may show beyond the superpixel cloud's where it keeps at least
#: :data:`RECALL_GAIN` more of the inner outlines at some check yaw (in place of
#: :data:`SKY_TOLERANCE`): the drawn fruit tree with a leaf pile (``drawn_trees(rng=0)``,
#: fruit_pile_0) at 512 px fell back, for 1.6 % sky against 0 %, to a superpixel cloud that keeps
#: 0.786 / 0.602 of its inner outlines at 45 / 90 degrees (smeared blobs; cards 0.948 / 0.950).
#: Below the 2 % of cards moved apart (:data:`SKY_TOLERANCE`).
SKY_TRADE = 0.02


def _good(a: dict) -> bool:
    return (all(a[f"recall{y:g}"] >= GOOD_RECALL and a[f"closed{y:g}"] >= 1.0 - SKY_TOLERANCE
                for y in CHECK_YAWS) and all(a[k] >= GOOD_RIM for k in ("rim", "rrim") if k in a))


def cards_hold(cards, plain, *, min_psnr: float = 30.0) -> bool:
    """Whether a drawn crown's card cloud is good from the side, or at least as good as its superpixel cloud.

    Not in the paper (issue 24). Whole cards keep a drawing's inner
    outlines from the side, but shapes sitting in a notch of the
    silhouette or between pieces of a split base fill leave sky when they
    move in depth. The card cloud is drawn as an engine shows it
    (:func:`~branchnb.trees.lod.bake_side_outline`,
    :func:`~branchnb.trees.lod.engine_view`) and must keep ``min_psnr`` in
    the front view. It holds outright when its inner-outline recall
    (:func:`~branchnb.trees.side_lines.side_line_figures`) at 45 and 90
    degrees is at least :data:`GOOD_RECALL`, no sky shows through those
    side views (holes inside the silhouette, per opaque pixel, at most
    :data:`SKY_TOLERANCE`) and, on an outlined tree, the rim ink share at
    45 degrees of the full and reduced levels with their side cards
    (:func:`~branchnb.trees.outline.rim_ink_share`) is at least
    :data:`GOOD_RIM`. Otherwise (only then is the superpixel cloud needed)
    it holds when each figure is no worse than the superpixel cloud's:
    recall no lower, up to :data:`SKY_TOLERANCE` more sky, rim ink no
    lower or at least :data:`GOOD_RIM` (less :data:`RIM_TRADE` where the cards keep
    :data:`RECALL_GAIN` more of the inner outlines at some check yaw, which also
    buys up to :data:`SKY_TRADE` more sky in place of :data:`SKY_TOLERANCE`; beyond the
    earlier rule, for flat-fill sprites, :func:`flat_fill_cards`). Where the
    superpixel cloud shows at least :data:`SKY_TOLERANCE` more sky inside its
    side views, the cards may also keep :data:`RECALL_SLACK` less recall and
    trade :data:`RIM_TRADE` of rim ink. Recall is compared only for drawings
    with at least :data:`MIN_INNER_LINES` inner-outline pixels.

    Parameters
    ----------
    cards : BillboardCloud
        The tree built with ``drawn_cards``.
    plain : BillboardCloud or callable
        The same tree built without ``drawn_cards``, or a function of no
        arguments building it (called only when the cards are not good
        outright).
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
    a = _side_figures(cards)
    if a["psnr"] < min_psnr:
        return False
    if _good(a):
        return True
    b = _side_figures(plain() if callable(plain) else plain)
    tol = {"rim": None, "rrim": None}
    gain = max(a[f"recall{y:g}"] - b[f"recall{y:g}"] for y in CHECK_YAWS)
    # Beyond the earlier rule: superpixels that open sky inside the crown (shapes moved off
    # their underpainting) are no reference to lose a little recall or rim ink against.
    sky = max(a[f"closed{y:g}"] - b[f"closed{y:g}"] for y in CHECK_YAWS) >= SKY_TOLERANCE
    trade = RIM_TRADE if gain >= RECALL_GAIN or sky else 0.0
    slack = RECALL_SLACK if sky else 1e-9
    sky_tol = SKY_TRADE if gain >= RECALL_GAIN else SKY_TOLERANCE
    for k in b:
        if k == "psnr" or k not in a:
            continue
        if k in tol:
            ok = a[k] >= min(b[k], GOOD_RIM) - trade - 1e-9
        elif k.startswith("recall"):
            ok = a[k] >= b[k] - slack
        else:
            ok = a[k] >= b[k] - (sky_tol if k.startswith("closed") else 1e-9)
        if not ok:
            return False
    return True


def _card_window(owner: dict, k: int, objs, shape_lines: dict) -> tuple[int, int]:
    """Columns ``[x0, x1)`` of the quad of the outermost card ``k`` is nested in (:func:`_nest_cards`)."""
    seen = {k}
    while k in owner and owner[k] not in seen:
        k = owner[k]
        seen.add(k)
    sl = objs[k - 1]
    x0, x1 = sl[1].start, sl[1].stop
    if k in shape_lines:
        win = shape_lines[k][0]
        x0, x1 = min(x0, win[1].start), max(x1, win[1].stop)
    return x0, x1


def _centred_on(x0: int, tex: np.ndarray, window: tuple[int, int]) -> tuple[int, np.ndarray]:
    """``(x0, tex)`` padded with transparent columns so that the quad's centre is ``window``'s.

    Not in the paper (issue 24). Axial quads are drawn in the order of
    their centres' depth: a shape drawn on a card (a fruit, a clump) whose
    centre lies ``dx`` beside the card's turns behind it from yaws past
    ``atan(dz / dx)``, and the card hides it. With one centre, the shape
    stays on the card from every side, ``dz`` in front of it.
    """
    h, w = tex.shape[:2]
    c2 = window[0] + window[1]                     # twice the card's centre
    # The quad [x0 - pad_l, x0 + w + pad_r) centred on c2 / 2: pad on the side facing away.
    if 2 * x0 + w < c2:
        pad_l, pad_r = 0, c2 - (2 * x0 + w)
    else:
        pad_l, pad_r = (2 * x0 + w) - c2, 0
    if not pad_l and not pad_r:
        return x0, tex
    out = np.zeros((h, w + pad_l + pad_r, tex.shape[2]), tex.dtype)
    out[:, pad_l: pad_l + w] = tex
    return x0 - pad_l, out


def _merge_cards(groups: list, sp_lab: np.ndarray, sp_ext: np.ndarray, shape_lines: dict):
    """Labels (working and extended) and shape outlines with every group's cards under its first label."""
    n = int(max(sp_lab.max(), sp_ext.max())) + 1
    to = np.arange(n)
    for g in groups:
        to[np.asarray(g)] = g[0]
    sp_lab, sp_ext = to[sp_lab].astype(sp_lab.dtype), to[sp_ext].astype(sp_ext.dtype)
    out = dict(shape_lines)
    for g in groups:
        parts = [(k, out.pop(k)) for k in g if k in out]
        if not parts:
            continue
        ya = min(w[0].start for _, (w, _) in parts)
        yb = max(w[0].stop for _, (w, _) in parts)
        xa = min(w[1].start for _, (w, _) in parts)
        xb = max(w[1].stop for _, (w, _) in parts)
        m = np.zeros((yb - ya, xb - xa), bool)
        for _, (w, mk) in parts:
            m[w[0].start - ya: w[0].stop - ya, w[1].start - xa: w[1].stop - xa] |= mk
        out[g[0]] = ((slice(ya, yb), slice(xa, xb)), m)
    return sp_lab, sp_ext, out
