"""Billboard cloud from a single tree image.

A frontal RGBA tree image becomes a cloud of small textured quads
("billboards") spread in a 3-D volume, which gives parallax when the
camera turns around the tree. The steps follow the paper:

1. **Superpixels** (:func:`crown_superpixels`): SLIC on the crown pixels,
   ``n_segments = 256`` and compactness 0.35 (paper). The paper's
   compactness is measured with colours scaled to [0, 1]; scikit-image
   measures colour distances in CIELAB, whose ``L`` runs over 0..100, so
   the value passed to :func:`skimage.segmentation.slic` is
   ``100 * compactness`` (= 35). Each superpixel is one billboard.
2. **Natural outlines** (:func:`replace_straight_edges`): in flat-coloured
   areas SLIC cuts the crown with nearly straight edges, which would show
   as polygonal billboard outlines from the side. Every near-straight edge
   between two superpixels is replaced by a piece of the tree silhouette
   whose end points are at a similar distance (the piece is mapped onto
   the edge's end points by a similarity) and which stays on one side of
   its chord (it does not cross the straight edge). The pixels between the
   straight edge and the new curve change owner, so the superpixels still
   tile the crown exactly.
3. **Volume** (:func:`inflate_silhouette`): the crown silhouette is
   inflated into a height field ``h`` solving the biharmonic equation
   ``Δ²h = 1`` with ``h = 0`` (and ``Δh = 0``) on the silhouette: the
   boundary stays on the image plane. ``h`` is scaled so that its maximum
   is ``depth_scale`` times half the crown's width: trees are roughly
   symmetric about their vertical axis, so the crown is about as deep as
   it is wide (a round crown becomes a sphere). The volume spans ``-h <= z <= h``.
4. **Layers**: front billboards at ``z = h̄ (1 - δ (1 - ℓ))`` where ``h̄``
   is the mean height over the superpixel and ``ℓ`` in [0, 1] its
   brightness rank (darker billboards are pushed deeper, ``δ`` =
   ``darkness_depth``); a rear layer with the positions mirrored
   horizontally about the crown's axis at ``z < 0`` (the texture itself is
   not mirrored); ``n_interior`` extra billboards at blue-noise positions
   inside the volume (weighted Voronoi stippling with density ``h``, the
   volume's half thickness, so the points spread evenly in 3-D; depth
   uniform between the front and back layers), each with the outline of
   the superpixel under it, darkened with its depth (in proportion to the
   crown's own shading: flat-coloured clip art is not darkened, so its
   flat regions stay flat from the side); rear and interior billboards show
   the input colours under their own front-view footprint; the trunk (with
   any ground clutter at its foot, which is no crown to inflate, as a
   second one) on the image plane ``z = 0``, a leaning trunk cut into
   horizontal strips so that it stays under the crown in side views.
   Not in the paper: a *core* billboard, the whole crown flat on the
   image plane behind the front layer (hidden in the front view), so that
   the gaps that open between billboards in side views show crown colour
   rather than sky and the crown stays joined to the trunk top.
5. **Line art** (not in the paper, for drawn trees): the thin dark strokes
   that outline flat colour in clip art (:func:`line_art`) mark the
   drawing's silhouettes as seen from the front. Turned with their
   billboards, they would pile up on the axis of a side view and cover its
   flat regions with broken black dashes. Every billboard keeps its
   texture, but its stroke pixels are drawn in a first pass, behind every
   fill pixel of the cloud (the billboard version of the "inverted hull"
   outline of toon rendering): in the front view nothing covers a stroke,
   so it is unchanged; from the side, strokes show only where no fill is,
   along the side view's own silhouette. Rear, interior and core
   billboards, hidden in the front view, show the image with its strokes
   filled in by the nearest fill colour. Photographs have no such strokes
   (a stroke must border a flat-coloured region) and are drawn as before.
6. **Drawn shapes** (not in the paper, :func:`drawn_regions`): on drawn trees every
   fill region bounded by the line art is one billboard carrying its whole outline;
   only the crown's background is split for depth, and a palm's fan crown is one
   billboard. Details and measurements: :mod:`branchnb.trees.billboard_shapes`. A crown
   of flat fill in a thick outline band without inner strokes (an RPG sprite) is built from
   whole cards too, its trunk inlaid where it runs inside the crown, turning about the trunk
   where it leaves the crown (:func:`~branchnb.trees.billboard_cards.flat_fill_cards`).

Billboards are *axial* billboards (each quad turns about its vertical
axis to face the camera, the usual way trees are drawn with billboards),
so the front view (yaw 0) puts every billboard back where it came from:
front billboards tile the crown, the trunk billboard covers the trunk
and the rear/interior billboards, which are trimmed to the crown
silhouette, lie behind them. The front view reproduces the input image.

Coordinates: pixels of the working image, ``x`` right, ``y`` down, ``z``
towards the viewer. :mod:`branchnb.trees.export` writes glTF / OBJ
(y up, metres) and :mod:`branchnb.trees.preview` renders any yaw.

Examples
--------
>>> from branchnb import data
>>> cloud = billboard_cloud(data.load("tree_rpg_01"), params=BillboardParams(drawn_cards=False), rng=0)
>>> cloud.n_billboards > 256          # the paper's superpixel cloud
True
>>> billboard_cloud(data.load("tree_rpg_01"), rng=0).n_billboards < 64   # a flat-fill sprite: cards
True
"""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.image import extend_nearest
from ..core.params import check_params
from ..core.random import as_rng
from ..core.sampling import stipple
from ..core.validate import checked
from .billboard_cards import (
    _card_window,
    _centred_on,
    _good,
    _merge_cards,
    _nest_cards,
    _side_figures,
    _underpaint,
    cards_hold,
    crown_inlay,
    flat_fill_cards,
    has_inner_outlines,
    shaded_cards,
    tone_edges,
)
from .billboard_layers import _cut, _recolour, _same_colour_overlap, _shading, _trim, _trunk_strips
from .billboard_lines import (
    _LUM3,
    _colour_span3,
    _fill_lines,
    _line_masks,
    _outer_lines,
    flat_slivers,
    line_art,
    trunk_outline,
)
from .billboard_shapes import (
    _decorations,
    _drawn_regions,
    _fan_crown,
    _fit_cards,
    _join_cards,
    _lift_decorations,
    _shape_lines,
    _star_crown,
    _stray_trunk_strokes,
    drawn_regions,
)
from .billboard_superpixels import crown_superpixels, replace_straight_edges
from .billboard_types import (  # noqa: F401  (importable from here)
    CORE,
    FRONT,
    INTERIOR,
    LAYER_NAMES,
    REAR,
    TRUNK_LAYER,
    BillboardCloud,
    BillboardParams,
    _front_overlay,
)
from .billboard_volume import _extend, _majority_parts, _volume_mask, _working_image, inflate_silhouette
from .exemplar import tree_rgba
from .outline import silhouette_outline
from .segmentation import Segmentation, segment_tree

__all__ = [
    "BillboardParams",
    "BillboardCloud",
    "billboard_cloud",
    "crown_superpixels",
    "replace_straight_edges",
    "inflate_silhouette",
    "FRONT",
    "REAR",
    "INTERIOR",
    "TRUNK_LAYER",
    "CORE",
    "LAYER_NAMES",
    "line_art",
    "drawn_regions",
]


#: Whether a card crown is checked against the superpixel cloud (billboard_cards.cards_hold).
_CHECK_CARDS = True
#: A flat-fill crown in a thick outline band without inner strokes (an RPG sprite) is built from
#: cards too (billboard_cards.flat_fill_cards), its trunk inlaid where it runs inside the crown.
_FLAT_CARDS = True
#: A drawn crown without outlines (clumps in tones, gradients) is cards too (billboard_cards.shaded_cards).
_SHADED_CARDS = True



#: Lobes of one star (:func:`_merged_lobes`) share one depth, and thin arms of the trunk mask
#: that run into the crown go to the crown (:func:`_stray_trunk_strokes`); ``_measure palms``
#: turns them off to compare.
#: Shapes in a notch of a card at the silhouette are nested in it like shapes in its holes
#: (billboard_cards._nest_cards), and nested shapes' quads are centred on their card's (_centred_on).
_NOTCHES = True
#: Cards joined by _join_cards become one card (_merge_cards).
_MERGE_JOINED = True
_CENTRE_NESTED = True
_JOIN_STARS = True
_HUB_STROKES = True
#: A fan crown (:func:`_fan_crown`) of an outlined drawing is one billboard turning about the
#: trunk's top (``_measure palms`` compares it with the cards and lobes rule).
_STAR_ONE = True
#: A drawn trunk's side strokes go to the trunk (:func:`~branchnb.trees.billboard_lines.trunk_outline`).
_TRUNK_OUTLINE = True
#: Tone cards that fail from the side are tried once more with the slivers of dark fills as
#: fill, not strokes (billboard_lines.flat_slivers), before the fill regions become the cards.
_FILL_SLIVERS = True


@checked()
def billboard_cloud(rgba, trunk=None, params: BillboardParams | None = None, *,
                    rng=0) -> BillboardCloud:
    """Turn one RGBA tree image into a billboard cloud.

    Parameters
    ----------
    rgba : (H, W, 4) array_like
        Frontal tree image on a transparent background, any size.
    trunk : (H, W) bool array, Segmentation, or None
        Trunk pixels (one billboard). ``None`` runs :func:`segment_tree`;
        an all-False mask means "no trunk" (every opaque pixel is crown).
    params : BillboardParams, optional
        Superpixels, edge replacement, volume, layers and the drawn-tree
        options; None uses the defaults (the paper's where it has them).
    rng : int or numpy.random.Generator
        Edge pieces, interior positions and depths.

    Returns
    -------
    BillboardCloud
        The billboards (front, rear, interior, trunk, core layers) in
        working-image pixels, with the working image and its superpixels.

    Raises
    ------
    ValueError
        No alpha channel, fully transparent image, trunk mask of the wrong
        shape.

    Examples
    --------
    >>> from branchnb import data
    >>> cloud = billboard_cloud(data.load("tree_rpg_05"), rng=1)
    >>> sorted(cloud.counts())
    ['core', 'front', 'interior', 'rear', 'trunk']
    """
    return _billboard_cloud(rgba, trunk, params, rng=rng)


def _billboard_cloud(rgba, trunk, params, *, rng, slivers: bool = False) -> BillboardCloud:
    """:func:`billboard_cloud` on checked arguments; ``slivers``: the retry that takes the slivers
    of dark fills as fill (:func:`~branchnb.trees.billboard_lines.flat_slivers`)."""
    p = check_params(params if params is not None else BillboardParams())
    img, opaque_full = tree_rgba(rgba, alpha_threshold=p.alpha_threshold, min_pixels=16, name="rgba")
    rng = as_rng(rng)
    H0, W0 = opaque_full.shape
    seg = None
    if trunk is None or isinstance(trunk, Segmentation):
        seg = segment_tree(img, rng=rng) if trunk is None else trunk
        # Ground clutter at the foot (a leaf pile, an island, a stand) joins
        # the trunk billboard: it is no crown to inflate and looks alike from
        # every side.
        trunk_full = seg.trunk if seg.ground is None else seg.trunk | seg.ground
        ground_full = seg.ground
    else:
        trunk_full = np.asarray(trunk)
        if trunk_full.shape != (H0, W0):
            raise ValueError(f"trunk must be an (H, W) mask of shape {(H0, W0)}, got {trunk_full.shape}")
        trunk_full = trunk_full.astype(bool)
    if trunk is not None and not isinstance(trunk, Segmentation):
        ground_full = None
    # The generator's state here: the superpixel cloud a card cloud is checked against
    # (cards_hold) is built from it, as a build with drawn_cards=False would be.
    rng_state = rng.bit_generator.state
    work, s = _working_image(img, p.max_size)
    H, W = work.shape[:2]
    alpha = work[:, :, 3]
    opaque = alpha >= p.alpha_threshold
    if opaque.sum() < 4:
        raise ValueError("rgba has too few opaque pixels at the working size")
    if s < 1.0:
        # Each working pixel goes to the part that covers more of it: thresholding
        # the trunk alone at 0.5 left rim pixels of a bare tree to the crown, as
        # specks that the crown layer then scattered in side views.
        trunk_w, ground_w = _majority_parts(opaque_full, trunk_full, ground_full, (W, H))
    else:
        trunk_w = trunk_full
        ground_w = ground_full if ground_full is not None else np.zeros((H, W), bool)
    trunk_w = trunk_w & opaque
    ground_w = ground_w & trunk_w
    crown = opaque & ~trunk_w
    # Parts: 1 crown, 2 trunk, extended to the soft (0 < alpha < threshold) rim.
    part = np.where(crown, 1, np.where(trunk_w, 2, 0)).astype(np.int32)
    part_ext = _extend(part, alpha > 1e-3)
    crown_ext = part_ext == 1
    trunk_ext = part_ext == 2

    # 5. Line art, and the image with it filled in for the hidden billboards.
    if p.line_art and p.line_width > 0:
        lines = line_art(work, width=p.line_width, alpha_threshold=p.alpha_threshold)
    else:
        lines = np.zeros((H, W), bool)
    if _TRUNK_OUTLINE and lines.any() and trunk_w.any() and crown.any():
        # The trunk's own strokes go with it (billboard_lines.trunk_outline).
        half0 = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
        grown = trunk_outline(trunk_w, opaque, lines, 2.0 * half0 + 1.5) & ~ground_w
        if (grown & ~trunk_w).any() and (opaque & ~(trunk_w | grown)).any():
            trunk_w = trunk_w | grown
            crown = opaque & ~trunk_w
            part = np.where(crown, 1, np.where(trunk_w, 2, 0)).astype(np.int32)
            part_ext = _extend(part, alpha > 1e-3)
            crown_ext = part_ext == 1
            trunk_ext = part_ext == 2
    filled = _fill_lines(work, lines, alpha > 1e-3) if lines.any() else work
    star_crown = bool(lines.any() and crown.any() and _star_crown(crown, lines))
    if _HUB_STROKES and star_crown:
        stray = _stray_trunk_strokes(trunk_w & ~ground_w, crown, lines)
        if stray.any():
            trunk_w = trunk_w & ~stray
            crown = opaque & ~trunk_w
            part = np.where(crown, 1, np.where(trunk_w, 2, 0)).astype(np.int32)
            part_ext = _extend(part, alpha > 1e-3)
            crown_ext = part_ext == 1
            trunk_ext = part_ext == 2

    # 1-2. Superpixels with natural outlines; on drawn trees the drawn shapes.
    regions = p.drawn_regions and lines.any()
    all_cards = bool(regions and p.drawn_cards and has_inner_outlines(lines, crown, opaque))
    # Beyond the paper: a flat fill in a thick outline band (no inner strokes) is cards too.
    flat_cards = bool(_FLAT_CARDS and regions and p.drawn_cards and not all_cards
                      and flat_fill_cards(work, crown, lines))
    # Beyond that: a drawn crown shaded in tones or gradients, without outlines, is cards too.
    shaded = bool(_SHADED_CARDS and regions and p.drawn_cards and not all_cards and not flat_cards
                  and shaded_cards(work, crown))
    flat_cards = flat_cards or shaded
    all_cards = all_cards or flat_cards
    # The fill regions are bounded by the strokes, and on a shaded crown by its sharp tone edges.
    region_lines = lines & crown
    toned = bool(shaded and p.tone_cards and _one_region(crown, lines))
    if toned and slivers:
        # Flat discs without outlines: the slivers of their darkest fills are no strokes.
        sliver = flat_slivers(work, lines, crown, width=p.line_width, alpha_threshold=p.alpha_threshold)
        if sliver.any():
            lines = lines & ~sliver
            region_lines = lines & crown
            filled = _fill_lines(work, lines, alpha > 1e-3) if lines.any() else work
    if toned:
        region_lines = region_lines | tone_edges(work, crown)
    card_holes: dict = {}
    card_owner: dict = {}
    if regions:
        stars: list = []
        sp_lab, background = _drawn_regions(work[:, :, :3], crown, region_lines, n_segments=p.n_segments,
                                            compactness=p.compactness, stars=stars)
        if background.any():
            # A background beside shapes spanning the crown (tiers, together at least half
            # its size) is one more card (a conifer's lowest tier); otherwise (a crown with
            # clumps and fruits drawn over it, or no inner outlines) it is split as before.
            shapes = np.ones(int(sp_lab.max()) + 1, bool)
            shapes[0] = False
            shapes[np.unique(sp_lab[background])] = False
            half = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
            spans = shapes & ~_decorations(sp_lab, shapes, background, crown, 2.0 * half + 1.5)
            if all_cards or int(np.isin(sp_lab, np.flatnonzero(spans)).sum()) >= 0.5 * background.sum():
                stars = []
                sp_lab, background = _drawn_regions(work[:, :, :3], crown, region_lines,
                                                    n_segments=p.n_segments, compactness=p.compactness,
                                                    background_share=2.0, stars=stars)
    else:
        background = np.zeros((H, W), bool)
        sp_lab = crown_superpixels(work[:, :, :3], crown, n_segments=p.n_segments, compactness=p.compactness)
    curves: list[np.ndarray] = []
    if p.replace_edges and sp_lab.max() > 1:
        sp_lab, curves = replace_straight_edges(sp_lab, opaque, straightness=p.straightness,
                                                min_edge_length=p.min_edge_length,
                                                chord_tolerance=p.chord_tolerance, rng=rng)
    sp_ext = _extend(sp_lab, crown_ext)

    # Drawn shapes (every fill region but the background) carry their whole outline; the
    # background's pieces none of it. The hidden billboards (rear, interior, core) show the
    # background's fill under the shapes (the underpainting): the shapes drawn over it exist
    # once each, on their own billboards, instead of being scattered in depth as flecks.
    shape_lines, under = {}, filled
    owned = np.zeros((H, W), bool)
    base = crown_ext
    card = np.zeros(int(sp_lab.max()) + 1, bool)
    if regions:
        # The background's labels (most of their pixels in it: the straight-edge replacement
        # moves a few pixels between neighbours).
        n_lab = int(sp_lab.max()) + 1
        in_bg = np.bincount(sp_lab[background], minlength=n_lab)
        shapes = in_bg <= 0.5 * np.bincount(sp_lab.ravel(), minlength=n_lab)
        shapes[0] = False
        background = crown & ~np.isin(sp_lab, np.flatnonzero(shapes)) & (sp_lab > 0)
        half = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
        shape_lines = _shape_lines(sp_lab, shapes, lines & crown_ext, 2.0 * half + 1.5)
        for win, m in shape_lines.values():
            owned[win] |= m
        deco = _decorations(sp_lab, shapes, background, crown, 2.0 * half + 1.5)
        base = crown_ext & (background | np.isin(sp_ext, np.flatnonzero(deco | ~shapes)))
        card = shapes & ~deco
        if deco.any():
            under = filled.copy()
            # Everything but the cards and the background's own fill (its median colour,
            # within 0.15; a fruit left in the background, its outline open, or the lines
            # round a fruit filled with its colour would spread it otherwise).
            fill = np.median(filled[background][:, :3], axis=0)
            src = background & (np.linalg.norm(filled[:, :, :3] - fill, axis=2) <= 0.15)
            paint = crown_ext & ~src & ~np.isin(sp_ext, np.flatnonzero(card))
            under[paint, :3] = extend_nearest(filled[:, :, :3], src if src.any() else background)[paint]

    # 3. Volume.
    if crown.any():
        vol = _volume_mask(crown, trunk_w)
        hn = inflate_silhouette(vol)
        xs_c = np.nonzero(crown)[1]
        half_width = 0.5 * float(xs_c.max() - xs_c.min() + 1)
        hmap = (hn * p.depth_scale * half_width).astype(np.float32)
    else:
        hmap = np.zeros((H, W), np.float32)
    axis = float(np.nonzero(crown)[1].mean()) if crown.any() else float(np.nonzero(opaque)[1].mean())

    from .billboard_crumbs import adopt_crumbs

    centers, sizes, tex_idx, tints, layers, sources, textures = [], [], [], [], [], [], []

    def add(x0, y0, tex, z, tint, layer, source=None, tex_id=None):
        h, w = tex.shape[:2]
        if tex_id is None:
            textures.append(tex.astype(np.float32))
            tex_id = len(textures) - 1
        centers.append((x0 + 0.5 * w, y0 + 0.5 * h, z))
        sizes.append((w, h))
        tex_idx.append(tex_id)
        tints.append(tint)
        layers.append(layer)
        sources.append(len(sources) if source is None else source)
        return len(sources) - 1

    # 4a. Front layer.
    n_sp = int(sp_ext.max())
    lum_img = work[:, :, :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    idx = sp_lab.ravel()
    cnt = np.bincount(idx, minlength=n_sp + 1).astype(np.float64)
    mean_h = np.bincount(idx, weights=hmap.ravel(), minlength=n_sp + 1) / np.maximum(cnt, 1)
    mean_l = np.bincount(idx, weights=lum_img.ravel(), minlength=n_sp + 1) / np.maximum(cnt, 1)
    valid = np.arange(n_sp + 1) > 0
    valid &= cnt > 0
    rank = np.zeros(n_sp + 1)
    if valid.sum() > 1:
        order = np.argsort(np.argsort(mean_l[valid]))
        rank[valid] = order / (valid.sum() - 1)
    elif valid.any():
        rank[valid] = 1.0
    z_front = mean_h * (1.0 - p.darkness_depth * (1.0 - rank))
    if regions:
        z_front = _fit_cards(z_front, sp_lab, card, crown, hmap, axis, 2.0 * half + 1.5)
        joined: list = []
        z_front = _join_cards(z_front, sp_lab, card, work[:, :, :3], 2.0 * half + 1.5, groups_out=joined)
        if all_cards and _MERGE_JOINED and joined:
            # One card per group of joined cards (one fill colour, meeting across strokes): pieces
            # of a base fill split by clumps, lobes of one crown turn together from the side, and
            # the shapes in the holes of their union are nested in it (beyond the paper).
            sp_lab, sp_ext, shape_lines = _merge_cards(joined, sp_lab, sp_ext, shape_lines)
            for g in joined:
                card[g[1:]] = False
                shapes[g[1:]] = False
                valid[g[1:]] = False
        if _JOIN_STARS:
            # Lobes of one star (palm fronds merged at the hub) at one depth, their least: at
            # different depths the fronds tear apart at the hub from the side, and the hub's
            # converging strokes scatter into shards (beyond the paper).
            for g in stars:
                g = g[g < len(z_front)]
                if len(g) > 1:
                    z_front[g] = z_front[g].min()
        z_front = _lift_decorations(z_front, sp_lab, deco, background, mean_h, 2.0 * half + 1.5)
        if all_cards:
            z_front, card_holes, card_owner = _nest_cards(z_front, sp_ext, card, opaque, notches=_NOTCHES,
                                                              trunk=trunk_ext & ~ground_w)
    zf_map = np.zeros((H, W), np.float32)
    front_tex = {}
    objs = ndi.find_objects(sp_ext)
    same_ok = crown_ext & (alpha >= 0.99)
    grows = valid.copy()
    if regions:
        # Shapes are whole: only the background's pieces grow, and not over the shapes.
        grows &= ~shapes
        same_ok &= ~owned & ~np.isin(sp_lab, np.flatnonzero(shapes))
    r_over = int(round(p.overlap * np.sqrt(cnt[grows].mean()))) if grows.any() else 0
    if card_holes:
        objs = list(objs)
        for k, hole in card_holes.items():
            # A card's window covers the shapes in its notches (underpainted below).
            if k - 1 < len(objs) and objs[k - 1] is not None:
                ys, xs = np.nonzero(hole)
                sl = objs[k - 1]
                objs[k - 1] = (slice(min(sl[0].start, ys.min()), max(sl[0].stop, ys.max() + 1)),
                               slice(min(sl[1].start, xs.min()), max(sl[1].stop, xs.max() + 1)))
    inlay_lab = None
    flat_pivot = None
    if flat_cards and regions:
        # The cards turn about the trunk where it leaves the crown (the pivot of the trunk strip
        # at the crown's lowest row), so the crown stays on its trunk from every side.
        stem = trunk_ext & ~ground_w
        crown_rows = np.flatnonzero(crown_ext.any(axis=1))
        if stem.any() and crown.any() and crown_rows.size:
            below = [pv for pc, pv in _trunk_strips(stem, H) if np.flatnonzero(pc.any(axis=1)).max() >= crown_rows[-1]]
            flat_pivot = below[0] if below else None
        # The trunk's pixels inside the crown's rows go on the nearest card: on their own strips,
        # turning about other centres, they would open sky in the card's notches from the side.
        inlay = crown_inlay(crown_ext, trunk_ext & ~ground_w)
        if inlay.any():
            inlay_lab = np.where(inlay, _extend(np.where(np.isin(sp_ext, np.flatnonzero(card)), sp_ext, 0),
                                                crown_ext | inlay), 0)
            objs = list(objs)
            for k, sl in enumerate(ndi.find_objects(inlay_lab), start=1):
                if sl is not None and k - 1 < len(objs) and objs[k - 1] is not None:
                    o = objs[k - 1]
                    objs[k - 1] = (slice(min(o[0].start, sl[0].start), max(o[0].stop, sl[0].stop)),
                                   slice(min(o[1].start, sl[1].start), max(o[1].stop, sl[1].stop)))
    for k, sl in enumerate(objs, start=1):
        if sl is None or not valid[k]:
            continue
        if k in shape_lines:
            win, m = shape_lines[k]
            ya, yb = min(sl[0].start, win[0].start), max(sl[0].stop, win[0].stop)
            xa, xb = min(sl[1].start, win[1].start), max(sl[1].stop, win[1].stop)
            sl = (slice(ya, yb), slice(xa, xb))
            keep = sp_ext[sl] == k
            keep[win[0].start - ya: win[0].stop - ya, win[1].start - xa: win[1].stop - xa] |= m
        elif r_over > 0 and grows[k]:
            sl, keep = _same_colour_overlap(work, sp_ext, k, sl, same_ok, r_over, p.overlap_tolerance)
        else:
            keep = sp_ext[sl] == k
        if inlay_lab is not None and card[k]:
            keep = keep | (inlay_lab[sl] == k)
        if regions and not shapes[k]:
            keep = keep & ~owned[sl]
            if not keep.any():
                continue
        y0, x0 = sl[0].start, sl[1].start
        tex = work[sl].copy()
        tex[:, :, 3] *= keep
        if all_cards and k in card_holes:
            tex = _underpaint(tex, keep, opaque[sl], sl, lines, 2.0 * half + 1.5, hole=card_holes[k],
                              alpha=work[sl][:, :, 3], trunk=trunk_ext & ~ground_w)
        if all_cards and k in card_owner and _CENTRE_NESTED:
            x0, tex = _centred_on(x0, tex, _card_window(card_owner, k, objs, shape_lines))
        elif flat_pivot is not None and card[k]:
            x0, tex = _centred_on(x0, tex, (int(np.floor(flat_pivot)), int(np.ceil(flat_pivot))))
        bid = add(x0, y0, tex, float(z_front[k]), 1.0, FRONT)
        front_tex[k] = (x0, y0, bid, tex_idx[bid])
        zf_map[sl][keep] = z_front[k]

    # 4b. Rear layer: mirrored positions about the axis, behind the image plane.
    # Behind the front layer only where it is fully opaque, so nothing shows through
    # its soft edges in the front view.
    allowed = (crown_ext & (alpha >= 0.99)).astype(np.float32)
    if p.rear_layer:
        for k, (x0, y0, bid, tid) in front_tex.items():
            tex = textures[tid]
            h, w = tex.shape[:2]
            cx = 2.0 * axis - (x0 + 0.5 * w)
            rx0 = round(cx - 0.5 * w)
            if regions and card[k]:
                continue                       # a card's mirror image would cover the cards in side views
            t = _recolour(_trim(tex, rx0, y0, allowed), rx0, y0, under)
            a = t[:, :, 3]
            if a.sum() < 1.0:
                continue
            ys, xs = np.nonzero(a > 0)
            hh = hmap[np.clip(ys + y0, 0, H - 1), np.clip(xs + rx0, 0, W - 1)]
            z = -float(hh.mean()) * (1.0 - p.darkness_depth * (1.0 - rank[k]))
            add(rx0, y0, t, min(z, -1e-3), 1.0, REAR, source=bid)

    # 4c. Interior billboards at blue-noise positions, darkened with depth.
    if p.n_interior > 0 and n_sp > 0 and hmap.max() > 0:
        shade = _shading(filled, sp_lab)
        pts = stipple(hmap * crown, int(p.n_interior), iterations=10, rng=rng)
        for px, py in pts:
            xi = int(np.clip(round(px), 0, W - 1))
            yi = int(np.clip(round(py), 0, H - 1))
            k = int(sp_ext[yi, xi])
            if k == 0 or k not in front_tex:
                continue
            if regions and card[k]:
                continue
            x0, y0, bid, tid = front_tex[k]
            tex = textures[tid]
            h, w = tex.shape[:2]
            ix0, iy0 = round(px - 0.5 * w), round(py - 0.5 * h)
            t = _recolour(_trim(tex, ix0, iy0, allowed), ix0, iy0, under)
            a = t[:, :, 3]
            if a.sum() < 1.0:
                continue
            ys, xs = np.nonzero(a > 0)
            zcap = float(zf_map[np.clip(ys + iy0, 0, H - 1), np.clip(xs + ix0, 0, W - 1)].min())
            zcap = max(zcap, 1e-3)
            z = float(rng.uniform(-0.9, 0.9)) * zcap
            depth01 = (0.9 * zcap - z) / (1.8 * zcap)
            add(ix0, iy0, t, z, 1.0 - p.interior_darkening * shade * depth01, INTERIOR, source=bid)

    # 4d. The core (not in the paper): the whole crown as one flat billboard
    # on the image plane, behind the front layer (hidden in the front view).
    # Seen from the side the front and rear billboards spread apart in depth
    # and leave gaps; through them the sky would show as speckle in flat
    # colour, and the crown would come loose from the trunk top, which also
    # stays on the image plane.
    if p.core_layer and crown.any() and not all_cards:
        # Without the crown's rim: a drawn outline runs along it, and it would
        # cross the middle of every side view.
        ys_c, xs_c = np.nonzero(crown)
        r = max(1, int(round(0.02 * max(np.ptp(ys_c), np.ptp(xs_c)))))
        core = cv2.erode(crown_ext.astype(np.uint8), cv2.getStructuringElement(
            cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))) > 0
        if regions:
            # Under the background and its decorations only: the other shapes (tiers,
            # fronds) are cards of their own, which a flat crown on the axis would cover
            # in side views.
            core &= base
        cut = _cut(under, core if core.any() else crown_ext) if core.any() or not regions else None
        if cut is not None:
            x0, y0, tex = cut
            tex = _trim(tex, x0, y0, allowed)
            if tex[:, :, 3].sum() >= 1.0:
                add(x0, y0, tex, 0.0, 1.0, CORE)

    # 4e. The trunk: one billboard on the image plane; ground clutter at its
    # foot another one (in one quad, a wide island would pull the trunk off
    # the crown's axis in side views).
    ground_ext = np.zeros_like(trunk_ext)
    if ground_w.any():
        g = ground_w
        # Labelled on the opaque pixels, then extended: the soft rim of the
        # ground goes with the ground, or trunk strips would span it and
        # turn about the ground's middle in side views.
        ground_ext = _extend(np.where(trunk_w & g, 1, np.where(trunk_w, 2, 0)).astype(np.int32),
                             trunk_ext) == 1
    # A leaning trunk is cut into horizontal strips, each its own axial
    # billboard: turned sideways, one flat quad would swing its top away from
    # the crown by half the lean; strips follow the crown's axis.
    # The ground turns about the trunk's foot, so the trunk stays standing
    # where it stood on it (about its own middle, a wide island would slide
    # under the trunk).
    trunk_only = trunk_ext & ~ground_ext
    pieces = []
    if trunk_only.any() and not crown.any():
        xs_t = np.nonzero(trunk_only)[1]
        pieces.append((trunk_only, 0.5 * (xs_t.min() + xs_t.max() + 1)))
    elif trunk_only.any():
        pieces += _trunk_strips(trunk_only, H)
        # A strip of soft rim pixels only (alpha below the threshold: a row where the trunk
        # meets the crown or the ground) joins its neighbour: on its own it is a billboard an
        # engine (alpha cut-off 0.5) draws nothing of, 1 in 4 RPG sprites at 96 px.
        i = 0
        while len(pieces) > 1 and i < len(pieces):
            if alpha[pieces[i][0]].max() < p.alpha_threshold:
                j = i - 1 if i > 0 else i + 1
                pieces[j] = (pieces[j][0] | pieces[i][0], pieces[j][1])
                del pieces[i]
            else:
                i += 1
    # pieces[-1] holds the trunk's foot.
    pieces.insert(0, (ground_ext, pieces[-1][1] if pieces else None))
    n_crown = len(centers)
    for piece, pivot in pieces:
        cut = _cut(work, piece, pivot)
        if cut is not None:
            x0, y0, tex = cut
            add(x0, y0, tex, 0.0, 1.0, TRUNK_LAYER)
    if _STAR_ONE and regions and n_crown and _fan_crown(crown, lines, opaque) and silhouette_outline(work).outlined:
        # A palm's crown (a star of fronds meeting at the hub) as one billboard turning about
        # the trunk's top: see :func:`_one_star`.
        top = next((pv for pc, pv in pieces[1:] if pc.any() and pv is not None), None)
        cut = _cut(work, crown_ext, top)
        if cut is not None:
            keep = list(range(n_crown, len(centers)))
            centers, sizes, tints, layers = ([a[i] for i in keep] for a in (centers, sizes, tints, layers))
            used = sorted({tex_idx[i] for i in keep})
            remap = {t: j for j, t in enumerate(used)}
            textures = [textures[t] for t in used]
            tex_idx = [remap[tex_idx[i]] for i in keep]
            sources = list(range(len(keep)))
            x0, y0, tex = cut
            add(x0, y0, tex, 1e-3, 1.0, FRONT)

    # With drawn regions the crown's outlines travel on their shapes' billboards; only the
    # trunk's outlines are still drawn behind the fills.
    behind = lines & (~crown_ext | _outer_lines(lines, opaque)) if regions else lines
    if regions and silhouette_outline(work).outlined:
        # With them, the anti-aliased fringe of an outlined silhouette's outline (pixels next
        # to it darker than the fill beyond them): on the rim pieces it would pile up in dark
        # fans where a side view stacks them.
        flat = _colour_span3(work[:, :, :3]) <= 0.04
        ref = extend_nearest(work[:, :, :3], flat & crown_ext & ~lines) if (flat & crown_ext).any() else work
        lum_w = work[:, :, :3] @ _LUM3
        ring = cv2.dilate(behind.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
        behind = behind | (ring & crown_ext & ~lines & (lum_w < ref[:, :, :3] @ _LUM3 - 0.03))
    line_masks = _line_masks(behind, textures, tex_idx, centers, sizes)

    # Texels cut off their billboard's piece would float from the side: each goes to the
    # billboard it touches in the front view (billboard_crumbs; the front view is unchanged).
    cloud = adopt_crumbs(BillboardCloud(
        centers=np.asarray(centers, np.float64).reshape(-1, 3),
        sizes=np.asarray(sizes, np.float64).reshape(-1, 2),
        texture=np.asarray(tex_idx, np.int64),
        tint=np.asarray(tints, np.float64),
        layer=np.asarray(layers, np.int64),
        source=np.asarray(sources, np.int64),
        textures=textures, axis=axis, image=work, superpixels=sp_lab,
        depth=hmap, replaced=curves, scale=s, lines=lines, line_masks=line_masks,
    ))
    if all_cards and _CHECK_CARDS:
        # Whole cards only where they hold up from the side (billboard_cards.cards_hold).
        again = type(rng.bit_generator)()
        again.state = rng_state
        if toned and not _good(_side_figures(cloud)):
            if _FILL_SLIVERS and not slivers:
                # First with the dark slivers as fill (cartoon_tree: one flat card -> 12-14 cards).
                again2 = type(rng.bit_generator)()
                again2.state = rng_state
                return _billboard_cloud(rgba, seg if seg is not None else trunk, p,
                                        rng=np.random.Generator(again2), slivers=True)
            # Tone cards that lose lines or open sky from the side: the fill regions are the cards.
            return billboard_cloud(rgba, seg if seg is not None else trunk, replace(p, tone_cards=False),
                                   rng=np.random.Generator(again))
        built: list = []

        def plain():
            # Built only when the cards are not good outright (billboard_cards.cards_hold).
            built.append(billboard_cloud(rgba, seg if seg is not None else trunk, replace(p, drawn_cards=False),
                                         rng=np.random.Generator(again)))
            return built[0]

        if not cards_hold(cloud, plain):
            return built[0] if built else plain()
    return cloud


def _one_region(crown: np.ndarray, lines: np.ndarray, share: float = 0.05) -> bool:
    """Whether the strokes leave the crown one fill region (no other of ``share`` of its area).

    Then a shaded crown is split by its tones (billboard_cards.tone_edges); where the strokes
    already cut it into shapes (an RPG palm's band round gradient fronds), its gradients would
    only add pieces that open sky from the side.
    """
    lab, n = ndi.label(crown & ~lines)
    if n < 2:
        return True
    areas = np.bincount(lab.ravel())[1:]
    return int((areas >= share * crown.sum()).sum()) <= 1
