"""Billboard clouds, step 6: drawn shapes (not in the paper).

Part of :func:`~branchnb.trees.billboard.billboard_cloud` (see
:mod:`branchnb.trees.billboard` for the other steps).

SLIC cuts across the shapes of a drawing, and a side view then scatters pieces
of every inner outline and fruit at different depths (smeared outlines, loose
stroke bits, red flecks). On drawn trees every fill region bounded by the line
art is a shape and one billboard with its whole outline; only the *background*
(the largest region, when it lies under shapes drawn over it) is split for
depth. Shapes drawn over it (*decorations*: fruits, clumps) sit on the crown's
surface, in front of the background pieces round them; shapes spanning the
crown from rim to rim (a conifer's tiers) are *cards* placed to fit in the
volume (a tier as wide as the crown stays on the axis) without rear or
interior copies (with no decoration, the background is a card too). Rear,
interior and core billboards show the background's fill in place of the
decorations (the underpainting), so each fruit exists once. On 12 drawn trees
of every kind (``python -m branchnb.trees._measure sideviews``) loose stroke
bits at 45/90 degrees went from 3.6 % (max 10.6 %) of the ink to 0.5 % (max
3.2 %); the hidden layers of 5 drawn fruit trees held 4-14 times as many
fruit-coloured texels as the fruits have pixels, now none. Palm fronds whose
outlines leave gaps at the hub merge into one region in the line art; as the
largest region it was taken for the background and cut into pieces, which from
the side made one green umbrella with comb-like streaks of the midribs. A
region whose convex hull is mostly sky (less than 0.8 crown; a crown's base
fill has crown all round it) is split at its necks into lobes, one card each
(:func:`_merged_lobes`): on 10 drawn palms (8 at 256 px, 2 at 384 px, half
with a leaf pile) the loose stroke bits at 45/90 degrees over the front view's
went from 2.6 % (max 7.4 %) of the ink to 0.3 % (max 0.8 %), and the inner ink
kept from 0.20 to at least 0.54; the other kinds do not change. Cards of one
fill colour that meet across a stroke (a frond's halves either side of its
midrib) share one depth, so they do not part; so do the lobes of one star. The
segmenter calls a palm's dark midribs, radiating from the hub, trunk, and the
one-row trunk strips at the hub then showed them from the side as ink whiskers
across it: on a star crown the trunk mask's thin arms into the crown go to the
crown (:func:`_stray_trunk_strokes`). On the 10 palms loose stroke bits went
from 0.3 % to 0.2 % (max 0.8 %), inner ink kept from 0.73 to 0.76 (min 0.54);
the 256 px palm of ``sideviews`` from 1.0 % stroke bits at 90 degrees to 0,
inner ink from 0.56 to 0.77, and the other 17 trees of ``sideviews`` do not
change. Whiskers remain on about 3 of the 10 palms at 90 degrees (midribs the
arms rule does not reach). Even so, fronds on cards at (mostly) one depth
gather on the axis from the side: left and right fronds cross in an X, fronds
of one slant pile up with their outlines drawn twice a few pixels apart
(:func:`~branchnb.trees.stacked.stacked_outline_share` up to 0.095 of the
stroke length at 45/90/135 degrees, above 0.01 on all 10 palms, above 0.03 on
9). A crown with sky between its fronds, covering less than 0.66 of its convex
hull (:func:`_fan_crown`: drawn palms 0.47-0.63, the other drawn kinds
0.84-0.97, the clip-art and RPG samples 0.74-0.98 but two palm sprites, 0.45
and 0.50, whose silhouettes are not outlined), of an outlined drawing is one
billboard whose turning axis is the trunk's top (a palm's crown is near round
about the trunk, so every side view shows the drawn fan on the trunk): stacked
outlines, loose stroke bits and flecks 0 on all 10 palms, inner ink kept 1.0;
such crowns have no parallax of their own.

Issue 24: a fan whose broad fronds touch each other (a fan palm's leaf
segments, a palm of broad fronds, an agave or yucca rosette) fills 0.66-0.9 of
its hull and was split into cards or superpixels that pile up from the side.
A crown is also a fan when its inner strokes radiate from one hub
(:func:`_radial_lines`; a rule, not a hull threshold moved to fit one tree):
on ``python -m branchnb.trees._fan_check`` (6 fan kinds of
:mod:`~branchnb.trees._fan_family` x 3 seeds at 128/256 px, 1 seed at 512) every
fan is taken as one, no drawn broadleaf, conifer or fruit tree, unseen cypress
or apple, nor any clip-art, RPG or ground sample (96, 200, 512 px) changes;
the unseen fan palm's side-view inner-line recall at 45/90 degrees went from
0.853/0.770 (200 px) and 0.846/0.798 (320 px) to 1.0/1.0.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi


def drawn_regions(rgb: np.ndarray, crown: np.ndarray, lines: np.ndarray, *, n_segments: int = 256,
                  compactness: float = 0.35, min_area: int = 6, background_share: float = 0.25) -> np.ndarray:
    """Superpixels of a drawn crown that follow its drawn shapes (beyond the paper).

    SLIC cuts across the shapes of clip art, so a side view scatters pieces
    of every outline and fruit. Here each fill region bounded by the line
    art (4-connected crown pixels off the lines) is a *shape* and stays one
    superpixel, whatever its size: a fruit, a leaf clump, a frond or a tier
    moves as a whole in a side view, with its outline closed round it. Only
    the *background*, the largest region when it covers at least
    ``background_share`` of the crown (the crown's base fill under the
    clumps and fruits), is split by SLIC into pieces as large as the
    ``n_segments`` superpixels of the crown would be on average, so that it
    still gets depth variation. Regions smaller than ``min_area`` join a
    neighbour. Line pixels are left to the caller (the billboard cloud
    gives each shape its whole outline).

    Parameters
    ----------
    rgb : (H, W, 3) float array
        Colours in [0, 1].
    crown : (H, W) bool array
        The crown pixels.
    lines : (H, W) bool array
        The line art (:func:`~branchnb.trees.billboard_lines.line_art`); its pixels get label 0 and split
        the crown into regions.
    n_segments : int
        Superpixels the whole crown would get (sets the size of the
        background's pieces: crown area / ``n_segments``).
    compactness : float
        SLIC compactness for the background split, on [0, 1] colours.
    min_area : int
        Regions smaller than this (pixels) are dropped (label 0; the
        caller joins them to a neighbour).
    background_share : float
        Smallest share of the crown the largest region must cover to count
        as the background and be split.

    Returns
    -------
    labels : (H, W) int32
        1..K on the crown off the lines, 0 elsewhere.

    Examples
    --------
    >>> import numpy as np
    >>> crown = np.zeros((40, 40), bool); crown[5:35, 5:35] = True
    >>> lines = np.zeros_like(crown); lines[5:35, 19:21] = True
    >>> rgb = np.zeros((40, 40, 3), np.float32)
    >>> int(drawn_regions(rgb, crown, lines, n_segments=2).max())
    2
    """
    return _drawn_regions(rgb, crown, lines, n_segments=n_segments, compactness=compactness,
                          min_area=min_area, background_share=background_share)[0]


def _drawn_regions(rgb, crown, lines, *, n_segments=256, compactness=0.35, min_area=6,
                   background_share=0.25, stars: list | None = None):
    """:func:`drawn_regions` and the background mask (pixels of the split region; all False if none).

    ``stars``: a list that receives, per region split into lobes (:func:`_merged_lobes`), the
    array of its lobes' labels.
    """
    from skimage.segmentation import slic

    crown = np.asarray(crown, bool)
    lines = np.asarray(lines, bool)
    free = crown & ~lines
    lab, n = ndi.label(free)
    out = np.zeros(crown.shape, np.int32)
    background = np.zeros(crown.shape, bool)
    if n == 0:
        return out, background
    areas = np.bincount(lab.ravel(), minlength=n + 1)
    areas[0] = 0
    target = max(float(crown.sum()) / max(int(n_segments), 1), 1.0)
    big = int(np.argmax(areas))
    bg_ids = {big}
    if areas[big] < background_share * crown.sum():
        big = -1
        bg_ids = _split_base(rgb, lab, areas, crown, background_share) if _SPLIT_BASE else set()
    k = 0
    for i, sl in enumerate(ndi.find_objects(lab), start=1):
        if sl is None or areas[i] < min_area:
            continue
        m = lab[sl] == i
        if i == big:
            lobes = _merged_lobes(m, crown[sl])
            if lobes is not None:
                # Shapes merged through gaps in their outlines (palm fronds meeting at the
                # hub): one shape per lobe, no background.
                first = k + 1
                for j in range(1, int(lobes.max()) + 1):
                    k += 1
                    out[sl][lobes == j] = k
                if stars is not None and k > first:
                    stars.append(np.arange(first, k + 1))
                continue
        pieces = int(round(areas[i] / target)) if i in bg_ids else 1
        if i in bg_ids:
            background[sl] |= m
        if pieces >= 2:
            sub = slic(np.asarray(rgb[sl], np.float64), n_segments=pieces, compactness=100.0 * compactness,
                       mask=m, start_label=1, enforce_connectivity=True, channel_axis=-1)
            sub = np.where(m, sub, 0)
            ids = np.unique(sub[sub > 0])
            fill = np.median(rgb[sl][m], axis=0)
            # One flat fill (most of it within 0.06 of its median): a piece of another colour,
            # mostly outlined, is a shape in it whose outline is open (a fruit drawn over the
            # crown's rim).
            one_fill = np.mean(np.linalg.norm(rgb[sl][m] - fill, axis=1) <= 0.06) >= 0.8
            for j in ids:
                k += 1
                piece = sub == j
                out[sl][piece] = k
                if (i in bg_ids and one_fill and np.linalg.norm(rgb[sl][piece].mean(axis=0) - fill) > 0.15
                        and _outlined(piece, lines[sl])):
                    background[sl] &= ~piece
            rest = m & (sub == 0)
            if rest.any():
                out[sl][rest] = k
        else:
            k += 1
            out[sl][m] = k
    return out, background



#: A crown's base fill cut into several regions by the shapes drawn over it is its background
#: (:func:`_split_base`); ``False`` turns the rule off to compare.
_SPLIT_BASE = True


def _split_base(rgb, lab, areas, crown, share: float, tol: float = 0.06, other: float = 0.02) -> set:
    """Labels of ``lab`` that are one base fill cut apart by shapes drawn over it (beyond the paper).

    When no fill region reaches ``share`` of the crown, clumps drawn over a
    crown's base fill out to its rim may still cut that fill into pieces
    (a fruit tree whose clumps touch the rim and each other). The regions
    whose median colour is within ``tol`` of the largest region's are taken
    as that base when together they reach ``share`` of the crown and
    regions of another colour (more than ``0.15`` away) cover at least
    ``other`` of it; a drawn conifer's tiers, one fill with nothing of
    another colour drawn over them, stay shapes of their own (cards).
    Without it every piece of such a base was a card (no rear, interior or
    core billboards): side views tore the crown into a swirl of sky holes.
    On the drawn fruit tree with a leaf pile of ``drawn_trees(rng=0)`` at
    200 / 256 px the sky holes inside its 45 degree view went from 656 /
    1091 px to 4 / 3, the rim ink share there from 0.87 / 0.89 to 0.99 /
    1.00 (engine view with side cards 0.87 -> 0.96), at the cost of the
    split background's usual loose stroke bits (0.03 of the ink over the
    front view's) and inner ink kept at 90 degrees (0.8 -> 0.4). Of 40 drawn
    trees (seeds 0, 5, 11 at 96 and 200 px) and the 25 samples at 200 px
    only that one changes (conifers' tiers are taken back as cards by the
    tier rule of :func:`~branchnb.trees.billboard.billboard_cloud`).
    Returns an empty set when the rule does not apply.
    """
    n = len(areas) - 1
    if n < 2:
        return set()
    med = np.zeros((n + 1, 3))
    for i, sl in enumerate(ndi.find_objects(lab), start=1):
        if sl is not None and areas[i] > 0:
            med[i] = np.median(rgb[sl][lab[sl] == i], axis=0)
    big = int(np.argmax(areas))
    d = np.linalg.norm(med - med[big], axis=1)
    same = (d <= tol) & (areas > 0)
    same[0] = False
    diff = (d > 0.15) & (areas > 0)
    diff[0] = False
    total = float(crown.sum())
    if same.sum() < 2 or areas[same].sum() < share * total or areas[diff].sum() < other * total:
        return set()
    return set(np.flatnonzero(same).tolist())


#: A fill region whose convex hull (holes filled) is less than this share crown is no
#: base fill under other shapes but drawn shapes merged through gaps in their outlines
#: (:func:`_merged_lobes`). Crown bases measure 0.96-1.0 (drawn broadleaf, fruit and
#: conifer trees, the clip-art and RPG samples at least 0.85); merged palm fronds 0.48-0.77.
_SKY_HULL = 0.8

#: A crown (holes filled) covering less than this share of its convex hull is a fan
#: (:func:`_fan_crown`).
_FAN_HULL = 0.66


def _merged_lobes(m: np.ndarray, crown: np.ndarray, *, necks=(0.5, 0.4, 0.3), min_share: float = 0.03):
    """One label per lobe of a fill region made of shapes merged at narrow necks, or None.

    Beyond the paper. Drawn palm fronds meet at the hub, where their
    outlines converge and leave gaps, so the line art encloses several
    fronds as one region: a star of lobes with sky between them. Split into
    pieces for depth like a crown's base fill, it shows from the side as one
    umbrella of fill with comb-like streaks of the midribs; each lobe is a
    drawn shape (a card) instead. A region is such a star when its convex
    hull (holes filled) is less than ``_SKY_HULL`` crown; a base fill has
    crown all round it (clumps and fruits drawn over it), and is left to
    the caller (None). The lobes are the pieces of the region deeper than
    ``neck`` times its ridge depth (95th percentile of the distance to its
    border) holding at least ``min_share`` of that deep area, for the first
    of ``necks`` that gives two or more, grown back over the region (each
    pixel to the nearest lobe); one label for the whole region if none does.
    """
    from skimage.morphology import convex_hull_image

    hull = convex_hull_image(ndi.binary_fill_holes(m))
    if (hull & crown).sum() >= _SKY_HULL * hull.sum():
        return None
    d = ndi.distance_transform_edt(np.pad(m, 1))[1:-1, 1:-1]
    ridge = float(np.percentile(d[m], 95))
    for neck in necks:
        lab, n = ndi.label(d > neck * ridge)
        area = np.bincount(lab.ravel(), minlength=n + 1)
        area[0] = 0
        keep = area >= min_share * area.sum()
        if int(keep.sum()) >= 2:
            seeds = np.where(keep[lab], lab, 0)
            _, (iy, ix) = ndi.distance_transform_edt(seeds == 0, return_indices=True)
            _, ids = np.unique(seeds[iy, ix], return_inverse=True)
            return np.where(m, ids.reshape(m.shape) + 1, 0).astype(np.int32)
    return m.astype(np.int32)


def _decorations(labels, shapes, background, crown, outline: float, *, rows: float = 0.5,
                 span: float = 0.9) -> np.ndarray:
    """Shapes drawn over the background (bool per label): fruits, clumps, a clump's fruits.

    Without a background every shape is a card. With one, a shape is a
    decoration unless it spans the crown: in at least ``rows`` of its rows it
    runs (with its outline, ``outline`` px) from the crown's left rim to its
    right rim, over at least ``span`` of the crown's width there, as the tiers
    of a drawn conifer do, stacked rather than drawn over a base.
    """
    deco = np.zeros(len(shapes), bool)
    if not background.any():
        return deco
    for k, sl in enumerate(ndi.find_objects(labels), start=1):
        if sl is None or k >= len(shapes) or not shapes[k]:
            continue
        m = labels[sl[0]] == k
        on = m.any(axis=1)
        m, cr = m[on], crown[sl[0]][on]
        W = m.shape[1]
        idx = np.arange(W)
        c0, c1 = np.where(m, idx, W).min(axis=1), np.where(m, idx, -1).max(axis=1) + 1
        k0, k1 = np.where(cr, idx, W).min(axis=1), np.where(cr, idx, -1).max(axis=1) + 1
        wide = np.minimum(c1 + outline, k1) - np.maximum(c0 - outline, k0) >= span * np.maximum(k1 - k0, 1)
        deco[k] = wide.mean() < rows
    return deco


def _fit_cards(z, labels, cards, crown, hmap, axis: float, outline: float = 0.0) -> np.ndarray:
    """Depths of the cards (shapes that are no decorations) capped so that each fits in the volume.

    A flat card reaching ``e`` from the axis in a row where the crown reaches
    ``R`` from the axis on that side, in rows where the crown is ``D`` deep
    (its largest height there), fits in the volume when it lies at most
    ``D sqrt(1 - (e / R)^2)`` off the image plane (``e / R`` the 90th
    percentile over the card's rows; the card's outline, ``outline`` px
    wide, counts as part of it): a conifer's tier spanning the crown,
    or a frond drawn out to the silhouette, stays on the axis (it would
    swing off the trunk in side views and its mirror copy would show as a
    second tree).
    """
    z = z.copy()
    for k, sl in enumerate(ndi.find_objects(labels), start=1):
        if sl is None or k >= len(cards) or not cards[k] or k >= len(z):
            continue
        m = labels[sl[0]] == k
        rows = m.any(axis=1) & crown[sl[0]].any(axis=1)
        if not rows.any():
            continue
        m, cr = m[rows], crown[sl[0]][rows]
        W = m.shape[1]
        idx = np.arange(W)
        # Per row: how far the card reaches towards the crown's rim on each side of the axis.
        c0, c1 = np.where(m, idx, W).min(axis=1), np.where(m, idx, -1).max(axis=1) + 1
        k0, k1 = np.where(cr, idx, W).min(axis=1), np.where(cr, idx, -1).max(axis=1) + 1
        left = (axis - c0 + outline) / np.maximum(axis - k0, 1.0)
        right = (c1 + outline - axis) / np.maximum(k1 - axis, 1.0)
        e = float(np.percentile(np.maximum(left, right), 90))
        depth = float(hmap[sl[0]].max())
        z[k] = min(z[k], depth * np.sqrt(max(0.0, 1.0 - min(1.0, e) ** 2)))
    return z


#: Cards are joined by their flat fill's median colour (:func:`_join_cards`), not their mean colour.
_FILL_COLOUR = True


def _join_cards(z, labels, cards, rgb, reach: float, tol: float = 0.06, groups_out: list | None = None) -> np.ndarray:
    """One depth for the cards of one fill colour that meet across a stroke.

    A stroke drawn inside a shape (a frond's midrib) cuts it into two cards;
    at different depths they part in side views and open a sliver. Cards of
    the same fill colour (mean colours within ``tol``) within ``reach + 1``
    pixels of each other form a group that takes its least depth (cards of
    different colours, a conifer's alternating tiers, keep theirs). The
    groups of more than one card are appended to ``groups_out`` (a list).

    Pieces of one gradient fill (a star's tips cut off by its outline) differ
    in median colour and stay apart. Joining cards whose colours match where
    they meet was tried and dropped (issue 24, 512/200 px sweep): it joined a
    light clump to a darker crown (fruit_0_s11 at 200 px: side-view recall
    0.982 -> 0.945 at 90 degrees) and lowered the reduced level's 45 degree rim
    ink of christmas_tree_root_flare at 512 px from 0.927 to 0.900.
    """
    ks = np.flatnonzero(cards)
    ks = ks[ks < len(z)]
    if len(ks) < 2:
        return z
    z = z.copy()
    n = len(z)
    idx = labels.ravel()
    cnt = np.maximum(np.bincount(idx, minlength=n), 1).astype(np.float64)
    mean = np.stack([np.bincount(idx, weights=rgb[..., c].ravel(), minlength=n) / cnt for c in range(3)], 1)
    if _FILL_COLOUR:
        # A card's fill colour: the median over its flat pixels (3 x 3 colour span <= tol). The
        # mean took in its strokes, so a thin piece of a base fill cut off by a clump touching the
        # silhouette (mostly outline) read darker than the rest of the fill and stayed apart.
        span = (ndi.maximum_filter(rgb, size=(3, 3, 1)) - ndi.minimum_filter(rgb, size=(3, 3, 1))).max(axis=2)
        flat = span <= tol
        for k in ks:
            m = (labels == k) & flat
            if m.sum() >= 4:
                mean[k] = np.median(rgb[m], axis=0)
    parent = {int(k): int(k) for k in ks}

    def find(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    r = int(np.ceil(reach)) + 1
    H, W = labels.shape
    objs = ndi.find_objects(labels)
    for k in ks:
        sl = objs[k - 1] if k - 1 < len(objs) else None
        if sl is None:
            continue
        win = (slice(max(sl[0].start - r, 0), min(sl[0].stop + r, H)),
               slice(max(sl[1].start - r, 0), min(sl[1].stop + r, W)))
        lab = labels[win]
        dk = ndi.distance_transform_edt(lab != k)
        near = np.unique(lab[dk <= reach + 1])
        for j in near:
            j = int(j)
            if j == k or j not in parent:
                continue
            if np.abs(mean[j] - mean[k]).max() <= tol:
                parent[find(j)] = find(int(k))
    groups = {}
    for k in ks:
        groups.setdefault(find(int(k)), []).append(int(k))
    for g in groups.values():
        if len(g) > 1:
            z[g] = z[g].min()
            if groups_out is not None:
                groups_out.append(sorted(g))
    return z


def _lift_decorations(z, labels, deco, background, mean_h, reach: float, passes: int = 4) -> np.ndarray:
    """Depths of the decorations: on the crown's surface, over what they are drawn on.

    A fruit darker than the crown would sink behind the crown's pieces round
    it (darker billboards are pushed deeper) and vanish from side views. A
    decoration lies at least where the background would at its place (its
    mean height times the background pieces' median depth factor) and half a
    pixel in front of any larger decoration next to it (a fruit on a clump
    moves with the clump).
    """
    z = z.copy()
    bg = np.unique(labels[background])
    bg = bg[(bg > 0) & (bg < len(z))]
    ok = bg[mean_h[bg] > 0] if len(bg) else bg
    factor = float(np.median(z[ok] / mean_h[ok])) if len(ok) else 1.0
    ks = np.flatnonzero(deco)
    ks = ks[ks < len(z)]
    z[ks] = np.maximum(z[ks], factor * mean_h[ks])
    r = int(np.ceil(reach)) + 4
    H, W = labels.shape
    objs = ndi.find_objects(labels)
    area = np.bincount(labels.ravel(), minlength=len(z))
    for _ in range(passes):
        changed = False
        for k in ks:
            if k > len(objs) or objs[k - 1] is None:
                continue
            sl = objs[k - 1]
            win = (slice(max(sl[0].start - r, 0), min(sl[0].stop + r, H)),
                   slice(max(sl[1].start - r, 0), min(sl[1].stop + r, W)))
            lab = labels[win]
            d = ndi.distance_transform_edt(lab != k)
            near = np.unique(lab[(d > 0) & (d <= reach + 3)])
            near = near[(near > 0) & (near < len(z))]
            near = near[deco[near] & (area[near] > area[k])] if len(near) else near
            if len(near) and z[near].max() + 0.5 > z[k]:
                z[k] = z[near].max() + 0.5
                changed = True
        if not changed:
            break
    return z


def _outlined(piece: np.ndarray, lines: np.ndarray, share: float = 0.1) -> bool:
    """At least ``share`` of the pixels just outside ``piece`` (3 x 3 ring) are line pixels."""
    ring = (cv2.dilate(piece.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0) & ~piece
    return bool(ring.any() and lines[ring].mean() >= share)


def _shape_lines(labels: np.ndarray, shapes: np.ndarray, lines: np.ndarray, reach: float) -> dict:
    """Per shape label (``shapes[k]`` True), the line pixels within ``reach`` of it: its whole outline.

    A line between two shapes goes to both (their billboards overlap on it in
    the front view, with the same pixels), so each keeps a closed outline
    when a side view moves them apart.
    """
    out = {}
    r = int(np.ceil(reach)) + 1
    H, W = labels.shape
    for k, sl in enumerate(ndi.find_objects(labels), start=1):
        if sl is None or k >= len(shapes) or not shapes[k]:
            continue
        ya, yb = max(sl[0].start - r, 0), min(sl[0].stop + r, H)
        xa, xb = max(sl[1].start - r, 0), min(sl[1].stop + r, W)
        win = (slice(ya, yb), slice(xa, xb))
        d = ndi.distance_transform_edt(labels[win] != k)
        m = lines[win] & (d <= reach)
        if m.any():
            out[k] = (win, m)
    return out


def _star_crown(crown: np.ndarray, lines: np.ndarray, background_share: float = 0.25) -> bool:
    """Whether the crown's largest fill region is a star of merged shapes (:func:`_merged_lobes`)."""
    from skimage.morphology import convex_hull_image

    lab, n = ndi.label(crown & ~lines)
    if n == 0:
        return False
    areas = np.bincount(lab.ravel(), minlength=n + 1)
    areas[0] = 0
    big = int(np.argmax(areas))
    if areas[big] < background_share * crown.sum():
        return False
    sl = ndi.find_objects(lab)[big - 1]
    hull = convex_hull_image(ndi.binary_fill_holes(lab[sl] == big))
    return bool((hull & crown[sl]).sum() < _SKY_HULL * hull.sum())


def _fan_crown(crown: np.ndarray, lines: np.ndarray | None = None, opaque: np.ndarray | None = None) -> bool:
    """Whether the crown is a fan: it covers (holes filled) less than ``_FAN_HULL`` of its convex
    hull, fronds with sky between them (drawn palms 0.47-0.63; the other drawn kinds 0.84-0.97),
    or, given its ``lines`` and the ``opaque`` mask, its inner strokes radiate from one hub
    (:func:`_radial_lines`)."""
    from skimage.morphology import convex_hull_image

    if not crown.any():
        return False
    f = ndi.binary_fill_holes(crown)
    hull = convex_hull_image(f)
    if f.sum() < _FAN_HULL * hull.sum():
        return True
    return bool(_RADIAL and lines is not None and opaque is not None and _radial_lines(crown, lines, opaque))


#: A crown whose inner strokes radiate from one hub is a fan (:func:`_radial_lines`); off, only
#: the convex-hull share decides (``_fan_check`` compares them).
_RADIAL = True
#: :func:`_radial_lines`: share of the coherent inner stroke pixels pointing at the hub (fan-like
#: crowns 0.67-1.0, the other drawn kinds and samples with four rays or more at most 0.46), the
#: angle (degrees) a pixel's stroke may miss the hub by, the rays (four: the inner edges of five
#: touching fronds; three strokes may meet at one point by chance, as a conifer sprite's notch
#: strokes do at 512 px) and their spread (degrees).
_RADIAL_SHARE = 0.6
_RADIAL_TOL = 12.0
_RADIAL_RAYS = 4
_RADIAL_SPREAD = 90.0


def _radial_lines(crown: np.ndarray, lines: np.ndarray, opaque: np.ndarray, *, max_points: int = 3000) -> bool:
    """Whether the crown's inner strokes radiate from one point: the drawing of a fan.

    Beyond the paper. A fan's fronds (a palm's, a fan palm's leaf segments,
    an agave's or yucca's rosette) are long shapes that leave one hub, so
    the strokes between and along them point at it; whether the fronds
    touch each other (the crown then fills most of its convex hull, and
    :data:`_FAN_HULL` misses it) does not change that. The strokes off the
    silhouette whose direction is well defined (coherence of the structure
    tensor, integrated over twice the stroke width, at least 0.5) vote for
    every point their line passes within ``_RADIAL_TOL`` degrees of; the
    hub is the point on a grid of about 80 x 80 over the crown with most
    votes. The crown is a fan when at least ``_RADIAL_SHARE`` of those
    pixels point at the hub, along at least ``_RADIAL_RAYS`` rays (15
    degree sectors about the hub holding 2 % of them, 5 px at least, over a
    radial extent of 0.15 times the square root of the crown's area) that
    spread over at least ``_RADIAL_SPREAD`` degrees. Clumps, fruits and
    scale arcs are round (their tangents miss any one point), a conifer's
    tier edges run across; the sprites whose few inner strokes all point
    one way (a trunk's sides) have one or two rays.
    """
    from .billboard_lines import _outer_lines

    inner = lines & crown & ~_outer_lines(lines, opaque)
    if inner.sum() < 20:
        return False
    half = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
    sig = max(1.0, half)
    f = ndi.gaussian_filter(lines.astype(np.float32), sig)
    gy, gx = np.gradient(f)
    ys, xs = np.nonzero(inner)
    a = ndi.gaussian_filter(gx * gx, 2 * sig)[ys, xs]
    b = ndi.gaussian_filter(gy * gy, 2 * sig)[ys, xs]
    c = ndi.gaussian_filter(gx * gy, 2 * sig)[ys, xs]
    coherent = np.sqrt((a - b) ** 2 + 4 * c * c) >= 0.5 * np.maximum(a + b, 1e-12)
    if coherent.sum() < 20:
        return False
    theta = 0.5 * np.arctan2(2 * c, a - b)[coherent]          # the strokes' normals
    px, py = xs[coherent].astype(float), ys[coherent].astype(float)
    nx, ny = np.cos(theta), np.sin(theta)
    sel = np.arange(len(px))
    if len(sel) > max_points:
        sel = np.random.default_rng(0).choice(sel, max_points, replace=False)
    cy, cx = np.nonzero(crown)
    step = max(1, int(round(max(np.ptp(cx), np.ptp(cy)) / 80)))
    hx, hy = np.meshgrid(np.arange(cx.min(), cx.max() + 1, step, dtype=float),
                         np.arange(cy.min(), cy.max() + 1, step, dtype=float))
    hx, hy = hx.ravel(), hy.ravel()
    s = np.sin(np.deg2rad(_RADIAL_TOL))
    votes = np.zeros(len(hx))
    for i in range(0, len(sel), 500):
        j = sel[i:i + 500]
        dx, dy = hx[:, None] - px[None, j], hy[:, None] - py[None, j]
        r = np.hypot(dx, dy)
        votes += ((np.abs(dx * nx[None, j] + dy * ny[None, j]) <= s * r + 1.0) & (r > 2 * step)).sum(1)
    k = int(np.argmax(votes))
    dx, dy = hx[k] - px, hy[k] - py
    r = np.hypot(dx, dy)
    radial = np.abs(dx * nx + dy * ny) <= s * r + 1.0
    if radial.sum() < _RADIAL_SHARE * len(px):
        return False
    ang = np.arctan2(-dy[radial], -dx[radial])
    sector = np.floor((ang + np.pi) / np.deg2rad(15.0)).astype(int)
    count = np.bincount(sector, minlength=25)
    reach = 0.15 * np.sqrt(crown.sum())
    rays = [q for q in np.flatnonzero(count >= max(5, 0.02 * radial.sum())) if np.ptp(r[radial][sector == q]) >= reach]
    if len(rays) < _RADIAL_RAYS:
        return False
    a_sorted = np.sort(ang)
    spread = 2 * np.pi - np.diff(np.r_[a_sorted, a_sorted[0] + 2 * np.pi]).max()
    return bool(np.degrees(spread) >= _RADIAL_SPREAD)


def _stray_trunk_strokes(trunk: np.ndarray, crown: np.ndarray, lines: np.ndarray) -> np.ndarray:
    """Thin arms of the trunk mask that run off into the crown: they belong to the crown.

    Beyond the paper. The segmenter calls a palm's dark frond midribs, which
    radiate from the hub, trunk; cut into one-row trunk strips they turn
    about the stem and show from the side as whiskers of ink across the hub.
    The trunk's body is the mask opened by a disc of ``2 w + 1`` px (``w``
    the strokes' half width); a piece of the rest that reaches farther than
    ``2 w + 1.5`` px from the body and touches the crown goes to the crown
    (bark ticks on the stem and the trunk's outline stay). Applied where the
    crown is such a star (:func:`_star_crown`): a broadleaf's branches drawn
    as strokes into its crown stay trunk.
    """
    half = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
    r = int(np.ceil(2.0 * half + 1.0))
    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    body = cv2.morphologyEx(trunk.astype(np.uint8), cv2.MORPH_OPEN, disc) > 0
    if not body.any():
        return np.zeros_like(trunk)
    arms = trunk & ~body
    lab, n = ndi.label(arms, structure=np.ones((3, 3)))
    if n == 0:
        return arms
    far = ndi.distance_transform_edt(~body) > 2.0 * half + 1.5
    near_crown = cv2.dilate(crown.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    reach = np.bincount(lab[far & arms], minlength=n + 1) > 0
    touch = np.bincount(lab[near_crown & arms], minlength=n + 1) > 0
    keep = reach & touch
    keep[0] = False
    return keep[lab]
