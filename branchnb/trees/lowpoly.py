"""Low-poly trees keep straight facets in mixes (beyond the paper; issue 24, trees49).

A low-poly crown is drawn as flat-shaded polygons (mostly triangles) that
tile it, and its silhouette is a polygon through their outer corners. The
paper's mean-value warp is smooth but not affine: every straight facet edge
of the chosen crown comes out bent (1-5 px of sag at 256 px), and the
mixed contour, a convex combination of polygons whose corners do not
correspond (an 8-gon and a 6-gon give a lumpy 14-gon), rounds the
silhouette into a blob. Neither is in any drawing of the kind.

:func:`facet_palette` tells a faceted crown apart: its crown is covered by
flat-colour regions (colours equal at 1/64), at least :data:`MIN_FACETS` of
them, nearly all of its area and of its rim in regions that are convex
polygons of at most :data:`MAX_CORNERS` corners. A mix whose crown comes
from such sources is then **redrawn facet by facet** (:func:`straighten_facets`):
every crown pixel joins the facet region of its colour (the anti-aliased
steps between facets join the nearest region), each region is traced and
reduced to its corners (Douglas-Peucker, tolerance :data:`CORNER_TOL` of its
perimeter), corners of neighbouring regions closer than :data:`SNAP` of the
tree's size are moved onto their common mean (so two facets share one
straight edge, without a gap or overlap), and the polygons are drawn again,
anti-aliased like the sources' own facet edges. The crown's silhouette is
the union of the polygons: straight edges between the chosen crown's own
outer corners. The trunk is left as it is.

Figures (procedural low-poly trees of 6-9-corner and cone crowns, 128-1000 px, ``TreeLibrary``
defaults): borders between facets straying more than 1.5 px from a straight line 11-16 % -> 0
(``tests/test_trees_lowpoly.py``); facet-border pixels within 1 px of their fitted line, mixes
of three polygonal crowns at 256 px, 0.945 -> 0.988 (sources 0.987); an unwarped tree redrawn
moves under 1.5 % of its silhouette; no cross-fade. None of 69 drawn, synthetic, sticker,
sprite and sample trees is taken as low-poly.

Same-coloured facets (trees50): low-poly art often shades neighbouring triangles alike, and the
merged regions are non-convex, of many corners, some round others. A region that is no small convex
polygon still counts as a facet when every outline of it is straight-edged (:func:`_straight_edged`:
close to its Douglas-Peucker polygon, corners that do not multiply at a finer tolerance, measured in
the drawing's own pixels). Aliased low-poly crowns also pass for pixel art; a mix of them is redrawn
facet by facet rather than re-gridded (``variations``). Figures (``/work/prompts`` unseen generator:
triangles of 4 greens, hard edges, 4 sources, 4 mixes at 160/320/640 px): facet-border pixels within
1 px of a straight segment 0.83/0.60/0.41 -> 0.97/0.97/0.96 (sources 0.97-0.98), all 12 sources
taken as low-poly (none before); held-out seeds 10-13 at 96/256 px 2/4 and 3/4, at 1000 px 0/4
(enlarged 1.2-1.3 times, their outlines measure 0.45-0.7 px off: left as made). None of the 69
other trees is taken.

Large crowns (trees51): a big hard-edged crown's merged facets meet at shallow corners a few px off
their chord, which a tolerance of a few of the drawing's pixels takes for a curve's corners. The
straightness tolerances are in the larger of the drawing's pixel and 1/:data:`STRAIGHT_REF` of the
crown's size (a curve drawn larger is judged as the same curve drawn at that size), and each
outline has one corner of slack. Skipping short outlines (a small facet's hole) found 2 more small
crowns but took a borderless sticker for low-poly: not done.
Figures (held-out seeds 10-13 of the ``/work/prompts`` generator): 1000 px 0/4 -> 4/4 (seeds 0-3 and
20-23 too), 400-800 px 12/12 each; ``tests/test_trees_lowpoly_large.py`` hard-edged trees at
640-1000 px 1-2/6 -> 4-6/6, large curved fills (cel, clumps, dots) none. Small crowns (96-128 px,
facets 15-25 px) still fail often: their merged facets' outlines stand 0.5-0.7 px off their
Douglas-Peucker polygon, as curved fills' do.

Small crowns (trees54): a 96-200 px crown's merged facets (15-25 px) meet at corners 1-3 px off
their chords, which the 3 px tolerance drops, so one outline alone stands 0.5-0.8 px off its
polygon, as a curved fill's does. The crown's outlines on average (each outline counted once, so
many small round holes in a straight-edged ground keep their weight) stand at most
:data:`POOLED_RESIDUAL` off on low-poly crowns; then each region whose every outline stands at
most :data:`LOOSE_RESIDUAL` off and keeps its corners on its own is a facet too. Figures
(``tests/test_trees_lowpoly_small.py``, the ``/work/prompts`` generator at 96/128 px, seeds 0-3,
10-13, 20-23): hard-edged low-poly found 1-3/8 -> 3-8/8 at 64-400 px; generator 96 px 5/12 ->
6/12, 128 px 3/12 -> 6/12; curved fills (cel, clumps, dots, 64-400 px) none before or after, none
of the 69 drawn, synthetic, sticker, sprite and sample trees at 128 and 256 px. Still missed: crowns
whose regions lie 0.55-0.75 px off on average (half of the 96-128 px ones).

Thin facets and shaded photos (trees58): a small crown's facets along its sides are 2-5 px wide,
and at the 3 px tolerance their outline's polygon collapses onto its midline and stands half their
width off; an outer outline whose polygon keeps under :data:`SLIVER_KEEP` of its area has its
distance taken at half the tolerance (its corner counts are not, so a thin crescent still
multiplies its corners as a curve). A smoothly shaded crown (a photo, an airbrushed fir) cut by
the 1/64 quantisation into bands one step apart is no faceted crown (:data:`GRADIENT_SHARE`).
Figures (a session script, trees58: 180 procedural low-poly trees per size, 3 facet counts,
5 palettes, anti-aliased or hard, round/cone/tall, through a ``TreeLibrary`` of that size; 71
controls: sample photos and RPG trees, synthetic, drawn, sticker, sprite, clip-art, cel and
painterly trees, curved fills): found at 64/96/128/200/256 px 55/67/77/80/81 -> 78/96/97/90/87;
controls taken 4/8/8/6/2 -> 4/5/5/4/1, none new (the shaded plain tree, poplar and evergreen
no longer; still taken: flat-dab painterly crowns at 64-128 px, an unoutlined pixel-art palm at
200-256 px and an unoutlined anti-aliased cel tree at 200 px, and outlined trees, which the
mixes leave out before asking).

Enlarged sources and painterly crowns (trees60): a ``TreeLibrary`` enlarges a source smaller than
its working size bicubically, which blurs every facet edge over 1.5-2 of the source's pixels and
rings at it, so the flat cores lose a ragged 1-2 px. An enlarged (not pixel-art) source is judged
with ``pixel`` :data:`SMOOTH_BLUR` times its source pixel (at most :data:`SMOOTH_BLUR_MOST` more;
``flat_art``). A painterly crown of small flat dabs (each dab too small for a region) was cut into its
few regions' Voronoi cells and passed as facets: a crown with more than :data:`FLAT_FAR` of its pixels
farther than :data:`FLAT_REACH` of the drawing's pixels from any flat region, or with more than
:data:`MAX_SHADES` shades, is not faceted. Figures (the trees58 sets: 180
procedural low-poly trees per size through a ``TreeLibrary``, 71 controls): found at 64/96/128/200/256
px 78/96/97/90/87 -> 84/104/121/128/134; controls taken 4/5/5/4/1 -> 1/1/3/7/3, painterly none
(before 3/3/3/0/0); all new ones outlined (which the mixes leave out), still taken an unoutlined
pixel-art palm at 200-256 px and cel tree at 200 px. A second set (a generator of straight cuts lit per
cell, sources drawn at 0.6-1.6 times the size; controls: round and stroke dabs, watercolour, photo-like,
sprites, stickers): found at 64/96/128 px 41/47/50 -> 42/48/54 of 65, controls 1/5/2 -> 0/0/0 of 19.
A larger tolerance also loses a few crowns whose thin facets it collapses (2 of 12 at 200 px, while
it finds 2 others). Mixes: at 96 px the redraw of now-found libraries
merges thin facets (2-4 px wide) into blobs (left as is: the redraw did so on main too).

Crowns with curved fills (cel shading, clumps, cartoon leaves), outlined
or bordered crowns (an ink or sticker ring is no polygon) and pixel art are
not faceted and keep the mix as made.

Examples
--------
>>> import numpy as np
>>> img = np.zeros((40, 40, 4), np.float32)
>>> facet_palette(img) is None
True
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi
from scipy.spatial import cKDTree

from ..core.image import as_rgba

__all__ = ["facet_palette", "straighten_facets", "MIN_FACETS", "MAX_CORNERS"]

#: Least number of flat facet regions of a faceted crown (a crown of one or two flat fills
#: is a cartoon crown, not low-poly).
MIN_FACETS = 4
#: Least number of distinct shades (farther apart than :data:`SHADE_TOL`) of a faceted crown.
MIN_SHADES = 3
#: Most distinct shades of a faceted crown (trees60): low-poly crowns of 4 palettes and continuous
#: shading through a ``TreeLibrary`` at 96-256 px 3-11, painterly dab crowns 35-50 (one colour a
#: dab); one hue shaded over its whole range gives at most 1/SHADE_TOL = 25.
MAX_SHADES = 16
#: Colours of the facet regions closer than this (largest channel difference) are one shade.
SHADE_TOL = 0.04
#: Most corners (after :data:`CORNER_TOL` simplification) of a facet polygon.
MAX_CORNERS = 6
#: Least solidity (area over convex-hull area) of a facet.
FACET_SOLIDITY = 0.9
#: Least share of the crown's area, and of its rim, in polygonal facet regions.
FACET_COVER = 0.75
#: Douglas-Peucker tolerance of a facet's outline, share of its perimeter: a warped
#: facet edge sags by 1-5 px at 256 px (2-4 % of the edge), a real corner by far more.
CORNER_TOL = 0.03
#: Douglas-Peucker tolerance of a facet's run along the silhouette between two corners where
#: it meets other facets, share of the run's length: a hull corner inside the run turning 30
#: degrees stands 13 % of it off its chord, the lumps of a mixed contour 3-8 %.
RIM_TOL = 0.1
#: ... and at most this share of the tree's size (a long run keeps a real corner of a few px).
RIM_MOST = 0.012
#: Corners of neighbouring facets within this share of the tree's size are one corner.
SNAP = 0.012
#: Colours of one facet are equal at this precision (the sources' flat fills; the
#: anti-aliased steps between facets are blends and join a neighbour).
_QUANT = 64.0
#: Farthest a redrawn silhouette moves from the mix's, share of the tree's size (the lumps of a
#: mixed contour of polygons stand 1-1.2 % of it off the chords between its corners).
REACH = 0.015
#: A facet region of any corner count, holes allowed (same-coloured neighbouring facets merged),
#: is straight-edged when its outlines stand on average at most this many source pixels off their
#: Douglas-Peucker polygon at :data:`STRAIGHT_TOL` source pixels: merged low-poly facets measure
#: 0.25-0.55, curved fills (cel shading, clumps, cartoon crowns) 0.52-1.1 (each outline on its own,
#: a region's anti-aliased steps included).
STRAIGHT_RESIDUAL = 0.5
#: ... or at most :data:`LOOSE_RESIDUAL` when the outlines of all the crown's regions that are
#: no small convex polygon stand on average (each outline once) at most :data:`POOLED_RESIDUAL`
#: off (trees54): low-poly crowns of 96-200 px average 0.33-0.75 (median 0.38-0.53), cel shading
#: and clumps 0.64-1.03; dotted grounds (0.38-1.4) fail the corners kept by each outline.
POOLED_RESIDUAL = 0.55
LOOSE_RESIDUAL = 0.8
#: Douglas-Peucker tolerance (source pixels) of a straight-edged region's outlines.
STRAIGHT_TOL = 3.0
#: ... and its corners must not multiply when the tolerance is halved: a curve approximated by
#: chords gains sqrt(3) = 1.7 times the corners from 4.5 to 1.5 px, a polygon keeps them
#: (merged facets 1.0-1.6).
STRAIGHT_GAIN = 1.65
#: Crown size (px) up to which the straightness tolerances are in the drawing's pixels; a larger
#: crown's are that share of its size.
STRAIGHT_REF = 200.0
#: An outer outline whose Douglas-Peucker polygon at :data:`STRAIGHT_TOL` keeps less than this share
#: of its area (a thin facet, 2-5 px wide at 96 px, collapsed onto its midline) has its distance
#: taken from the polygon at half the tolerance (trees58; 0.5/0.8/0.9 found 105/116/113 of 180
#: procedural low-poly crowns at 96 px, main 101, no control taken).
SLIVER_KEEP = 0.8
#: Share of the borders between a crown's flat regions at most :data:`GRADIENT_STEP` apart (largest
#: channel difference of the regions' mean colours) above which the regions are bands of a smooth
#: gradient cut by the colour quantisation, no facets (trees58): low-poly crowns of 64-400 px
#: 0-0.47 (continuously shaded facets), shaded photo crowns (plain tree, poplar, evergreen) 0.71-1.
GRADIENT_SHARE = 0.6
GRADIENT_STEP = 2.0 / 64
#: Share of a crown's pixels farther than :data:`FLAT_REACH` of the drawing's pixels from every flat
#: region above which it is no faceted crown (trees60): the anti-aliased steps between facets lie
#: within 1-2 px of a facet, a painterly crown's dabs are mostly too small for a region.
FLAT_FAR = 0.25
FLAT_REACH = 2.5
#: A source enlarged smoothly (bicubic) to the working size has its facet edges blurred over about
#: this many of its own pixels: ``pixel`` of :func:`facet_palette` for it (trees60; ``TreeLibrary``
#: crowns at 64/96/128/200/256 px found 78/96/97/90/87 -> 84/104/121/128/134 of 180 at 1.5,
#: 87/106/115/132/155 at 1.8 with more controls taken at 200 px) ...
SMOOTH_BLUR = 1.5
#: ... but at most this many working pixels more (a source enlarged 3 times: its small facets
#: vanish under a 13 px tolerance).
SMOOTH_BLUR_MOST = 0.7
#: Supersampling of the redrawn polygons (their edges anti-aliased as the sources').
_SUPER = 4


def _keys(rgb: np.ndarray) -> np.ndarray:
    q = np.clip(np.round(rgb * _QUANT), 0, _QUANT).astype(np.int64)
    return (q[..., 0] * 256 + q[..., 1]) * 256 + q[..., 2]


def _regions(rgb: np.ndarray, crown: np.ndarray, min_area: int) -> tuple[np.ndarray, int]:
    """Connected regions (4-connected) of one quantised colour of at least ``min_area`` px in
    ``crown``: a label image (0 elsewhere) and the number of regions."""
    key = np.where(crown, _keys(rgb), -1)
    vals, counts = np.unique(key[crown], return_counts=True)
    lab = np.zeros(crown.shape, np.int32)
    n = 0
    for v in vals[counts >= min_area]:
        sub, m = ndi.label(key == v)
        if m == 0:
            continue
        sizes = np.bincount(sub.ravel())
        sizes[0] = 0
        big = np.flatnonzero(sizes >= min_area)
        if len(big) == 0:
            continue
        remap = np.zeros(m + 1, np.int32)
        remap[big] = n + 1 + np.arange(len(big))
        lab = np.where(sub > 0, np.maximum(lab, remap[sub]), lab)
        n += len(big)
    return lab, n


def _corners(mask: np.ndarray) -> np.ndarray | None:
    """The corners of a region's outer outline (Douglas-Peucker), (k, 2) x, y."""
    cnts, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    if not cnts:
        return None
    c = max(cnts, key=len)
    per = cv2.arcLength(c, True)
    return cv2.approxPolyDP(c, max(1.0, CORNER_TOL * per), True)[:, 0, :].astype(np.float64)


def _junctions(lab: np.ndarray, snap: float) -> tuple[np.ndarray, list]:
    """Corners where three or more labels meet, on the pixel-corner lattice (as x, y pixel
    coordinates, pixel centres at integers), those within ``snap`` of each other merged; and
    for each merged corner the set of labels meeting there."""
    p = np.pad(lab, 1, constant_values=0)
    quad = np.stack([p[:-1, :-1], p[:-1, 1:], p[1:, :-1], p[1:, 1:]])
    s = np.sort(quad, axis=0)
    distinct = 1 + (s[1:] != s[:-1]).sum(axis=0)
    jy, jx = np.nonzero(distinct >= 3)
    if len(jy) == 0:
        return np.zeros((0, 2)), []
    pts = np.stack([jx - 0.5, jy - 0.5], axis=1).astype(np.float64)
    parent = np.arange(len(pts))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b in cKDTree(pts).query_pairs(snap):
        ra, rb = root(a), root(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    roots = np.array([root(i) for i in range(len(pts))])
    out, labels = [], []
    for r in np.unique(roots):
        m = roots == r
        out.append(pts[m].mean(axis=0))
        labels.append(set(np.unique(quad[:, jy[m], jx[m]]).tolist()))
    return np.asarray(out), labels


def _facet_polygons(lab: np.ndarray, trunk: np.ndarray, n: int, snap: float):
    """Each facet region's polygon: the corners where it meets two or more other regions (the
    background, the trunk) in order round it, joined by straight edges; along the silhouette
    the run between two such corners keeps its own corners (Douglas-Peucker at
    :data:`RIM_TOL` of its length)."""
    full = np.where(trunk, n + 1, lab)
    size = max(lab.shape)
    jpts, jlabs = _junctions(full, snap)
    polys, owner = [], []
    bg = ndi.binary_dilation(full == 0)
    for j, sl in enumerate(ndi.find_objects(lab), 1):
        if sl is None:
            continue
        # traced on the region doubled, so the outline runs 1/4 px inside the pixels' edges
        # (through the rim pixels' centres a redrawn silhouette would cover them only half)
        big = cv2.resize(np.pad(lab[sl] == j, 1).astype(np.uint8), None, fx=2, fy=2,
                         interpolation=cv2.INTER_NEAREST)
        cnts, _ = cv2.findContours(big, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
        if not cnts:
            continue
        c = (max(cnts, key=len)[:, 0, :].astype(np.float64) + 0.5) / 2 - 0.5 \
            + [sl[1].start - 1, sl[0].start - 1]
        # only the corners on the region's outer outline (a junction of facets in one of its
        # holes is no corner of it)
        mine = [i for i, ls in enumerate(jlabs) if j in ls]
        if mine:
            dist = cKDTree(c).query(jpts[mine], k=1)[0]
            mine = [i for i, dd in zip(mine, dist, strict=True) if dd <= snap + 2.0]
        if len(mine) < 2:
            per = cv2.arcLength(c.astype(np.float32).reshape(-1, 1, 2), True)
            q = cv2.approxPolyDP(c.astype(np.float32).reshape(-1, 1, 2), max(1.0, CORNER_TOL * per), True)
            if len(q) >= 3:
                polys.append(q[:, 0, :].astype(np.float64))
                owner.append(j)
            continue
        # each corner at its nearest contour point, in contour order
        at = cKDTree(c).query(jpts[mine], k=1)[1]
        order = np.argsort(at, kind="stable")
        at, corners = at[order], jpts[np.asarray(mine)[order]]
        ci = np.clip(np.round(c).astype(int), 0, [lab.shape[1] - 1, lab.shape[0] - 1])
        on_rim = bg[ci[:, 1], ci[:, 0]]
        verts = []
        for k in range(len(at)):
            a, b = at[k], at[(k + 1) % len(at)]
            verts.append(corners[k])
            run = np.r_[np.arange(a, b)] if b > a else np.r_[np.arange(a, len(c)), np.arange(0, b)]
            if len(run) > 2 and on_rim[run].mean() > 0.5:
                chain = np.vstack([corners[k], c[run[1:]], corners[(k + 1) % len(at)]]).astype(np.float32)
                length = cv2.arcLength(chain.reshape(-1, 1, 2), False)
                tol = max(1.0, min(RIM_TOL * length, RIM_MOST * size))
                q = cv2.approxPolyDP(chain.reshape(-1, 1, 2), tol, False)[:, 0, :]
                verts.extend(q[1:-1].astype(np.float64))
        if len(verts) >= 3:
            polys.append(np.asarray(verts))
            owner.append(j)
    return polys, owner


def _polygonal(mask: np.ndarray) -> bool:
    """A convex-ish polygon of at most :data:`MAX_CORNERS` corners without holes (a flat fill
    round dots or stripes is a ground, no facet)."""
    if ndi.binary_fill_holes(mask).sum() > 1.05 * mask.sum() + 4:
        return False
    pts = _corners(mask)
    if pts is None or len(pts) > MAX_CORNERS:
        return False
    if len(pts) < 3:        # a sliver facet: a thin strip along one straight edge
        return True
    hull = cv2.convexHull(pts.astype(np.float32))
    return cv2.contourArea(pts.astype(np.float32)) >= FACET_SOLIDITY * max(cv2.contourArea(hull), 1e-9)


def _outline_stats(mask: np.ndarray, pixel: float = 1.0) -> list:
    """For every outline (outer and holes, 8 points or more) of a region: its length, its mean
    distance from its Douglas-Peucker polygon at :data:`STRAIGHT_TOL` ``pixel`` and its corner
    counts at half and 1.5 times that tolerance."""
    cnts, hier = cv2.findContours(mask.astype(np.uint8), cv2.RETR_CCOMP, cv2.CHAIN_APPROX_NONE)
    out = []
    for c, h in zip(cnts, hier[0] if hier is not None else [], strict=True):
        if len(c) < 8:
            continue
        tol = STRAIGHT_TOL * pixel
        q = cv2.approxPolyDP(c, tol, True)
        # a thin facet (a sliver along a small crown's side) collapses onto its midline, and its
        # outline then stands half its width off: its distance is taken at half the tolerance
        # (its corner counts are not: a thin crescent's multiply there as a curve's); not a
        # hole's (a small round dot's polygon at 3 px loses as much)
        if h[3] < 0 and abs(cv2.contourArea(q)) < SLIVER_KEEP * cv2.contourArea(c):
            q = cv2.approxPolyDP(c, 0.5 * tol, True)
        d = [abs(cv2.pointPolygonTest(q, (float(x), float(y)), True)) for x, y in c[:, 0]]
        out.append((len(c), float(np.mean(d)), len(cv2.approxPolyDP(c, 0.5 * tol, True)),
                    len(cv2.approxPolyDP(c, 1.5 * tol, True))))
    return out


def _straight_edged(mask: np.ndarray, pixel: float = 1.0, residual: float = STRAIGHT_RESIDUAL,
                    stats: list | None = None) -> bool:
    """Whether every outline of a region (outer and holes) is a union of straight segments
    (beyond the paper; :data:`STRAIGHT_RESIDUAL`, :data:`STRAIGHT_GAIN`). ``pixel`` is a source
    pixel's size in image pixels (an enlarged source's stair-steps are that large); ``residual``
    the most mean distance (in ``pixel``) of an outline from its polygon; ``stats`` the region's
    :func:`_outline_stats` when known."""
    if stats is None:
        stats = _outline_stats(mask, pixel)
    # every outline on its own: round dots in a flat ground are holes, but no straight ones
    if not stats or any(m > residual * pixel for _, m, _, _ in stats):
        return False
    fine = sum(f for _, _, f, _ in stats)
    coarse = sum(c for _, _, _, c in stats)
    # one corner of slack per outline: a small region's few corners (4 -> 7) are no curve's gain
    return fine <= STRAIGHT_GAIN * coarse + len(stats)


def facet_palette(image, trunk=None, *, pixel: float = 1.0) -> np.ndarray | None:
    """The facet colours of a low-poly (flat-shaded polygon) crown, or None if it is not one.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA tree; opaque where alpha >= 0.5.
    trunk : (H, W) array_like, optional
        The trunk mask (left out of the crown); None takes every opaque pixel as crown.
    pixel : float
        Size of one of the drawing's own pixels in ``image`` pixels (>= 1; an exemplar enlarged
        to the working size has stair-steps that large).

    Returns
    -------
    (k, 3) float32 ndarray or None
        The mean colour of every polygonal (or straight-edged) facet region, when the crown has at least
        :data:`MIN_FACETS` such regions covering :data:`FACET_COVER` of its area and rim.

    Raises
    ------
    ValueError
        ``trunk`` not of the image's (H, W) shape, ``pixel`` below 1.

    Notes
    -----
    Beyond trees49 (issue 24, trees50): low-poly art often shades neighbouring triangles alike,
    so same-coloured facets merge into non-convex regions of many corners, some round others
    (holes). Such a region counts as a facet when its outlines are straight-edged
    (:func:`_straight_edged`): close to their Douglas-Peucker polygon and with corners that do
    not multiply at a finer tolerance, as a curve's do.

    Beyond trees50 (trees51): the straightness tolerances are in the larger of ``pixel`` and
    1/:data:`STRAIGHT_REF` of the crown's size, so a large crown's shallow facet corners are not
    taken for a curve's.

    Beyond trees51 (trees54): a small crown's merged facets are judged together (their outlines'
    mean distance from their polygons at most :data:`POOLED_RESIDUAL`), then each at
    :data:`LOOSE_RESIDUAL`.

    Beyond trees54 (trees58): a thin facet's outline is measured at half the tolerance
    (:data:`SLIVER_KEEP`), and a crown whose neighbouring regions are mostly one quantisation step
    apart (a smooth gradient's bands, :data:`GRADIENT_SHARE`) is not faceted.

    Beyond trees58 (trees60): a crown mostly out of reach of its flat regions (:data:`FLAT_FAR`) or
    of more than :data:`MAX_SHADES` shades (painterly dabs) is not faceted.

    Examples
    --------
    >>> import numpy as np, cv2
    >>> img = np.zeros((64, 64, 4), np.float32)
    >>> for i, p in enumerate([[[8, 8], [56, 8], [8, 56]], [[56, 8], [56, 56], [8, 56]]]):
    ...     _ = cv2.fillPoly(img, [np.int32(p)], (0.2 + 0.3 * i, 0.6, 0.2, 1.0))
    >>> facet_palette(img) is None      # two facets: a cartoon, not low-poly
    True
    """
    img = as_rgba(image, name="image")
    if not np.isfinite(pixel) or pixel < 1:
        raise ValueError(f"pixel must be a number >= 1, got {pixel}")
    crown = img[..., 3] >= 0.5
    if trunk is not None:
        t = np.asarray(trunk)
        if t.shape != crown.shape:
            raise ValueError(f"trunk must have the image's shape {crown.shape}, got {t.shape}")
        crown &= ~(t >= 0.5)
    area = int(crown.sum())
    if area < 200:
        return None
    lab, n = _regions(img[..., :3], crown, max(12, int(0.002 * area)))
    if n < MIN_FACETS:
        return None
    # every crown pixel to its nearest region: the anti-aliased steps belong to their facets
    gap, (iy, ix) = ndi.distance_transform_edt(lab == 0, return_indices=True)
    near = lab[iy, ix]
    # ... but only steps: a crown mostly out of reach of any flat region (small painterly dabs,
    # each too small for a region) would be cut into the flat regions' Voronoi cells, polygons
    ys, xs = np.nonzero(crown)
    unit = max(float(pixel), max(np.ptp(ys), np.ptp(xs)) / STRAIGHT_REF)
    if (gap[crown] > FLAT_REACH * unit).mean() > FLAT_FAR:
        return None
    whole = np.where(crown, near, 0)
    ids = np.arange(n + 1)
    cols = np.stack([ndi.mean(img[..., c], lab, ids) for c in range(3)], axis=1)
    if not _not_gradient(whole, cols):
        return None
    good = np.zeros(n + 1, bool)
    for j, sl in enumerate(ndi.find_objects(lab), 1):
        if sl is not None:
            good[j] = _polygonal(np.pad(lab[sl] == j, 1))
    # a region of merged facets is judged with its anti-aliased steps: its outline is then the
    # middle of the steps, not their ragged inner edge
    # tolerances in the drawing's own units: its pixel, or for a large drawing a share of the
    # crown's size (a big low-poly crown has facets as big, meeting at shallow corners a few px
    # off the chord that a fixed pixel tolerance would take for a curve's)
    stats = {}
    for j, sl in enumerate(ndi.find_objects(whole), 1):
        if sl is not None and not good[j]:
            stats[j] = _outline_stats(np.pad(whole[sl] == j, 1), unit)
            good[j] = _straight_edged(None, unit, stats=stats[j])
    # a small crown's merged facets (15-25 px) meet at corners 1-3 px off their chords, which a
    # tolerance of 3 px drops: one region's outline alone then stands as far off its polygon as
    # a curve's; the crown's outlines together do not (see POOLED_RESIDUAL)
    rows = [r for st in stats.values() for r in st]
    if rows and np.mean([m for _, m, _, _ in rows]) <= POOLED_RESIDUAL * unit:
        for j, st in stats.items():
            # each outline's corners on their own: a ground's many small round holes (dots) keep
            # their few corners and would cover a curved outer outline's gain
            good[j] = good[j] or (_straight_edged(None, unit, LOOSE_RESIDUAL, stats=st)
                                  and all(f <= STRAIGHT_GAIN * c + 1 for _, _, f, c in st))
    if good.sum() < MIN_FACETS:
        return None
    rim = crown & ~ndi.binary_erosion(crown, structure=np.ones((3, 3), bool))
    if good[near[crown]].mean() < FACET_COVER or good[near[rim]].mean() < FACET_COVER:
        return None
    pal = np.unique(np.round(cols[good] * _QUANT) / _QUANT, axis=0).astype(np.float32)
    # at least MIN_SHADES shades apart: a two-tone drawing (a fir lit from one side) resampled
    # splits each fill at the quantisation's steps into near twins, no low-poly palette
    shades = len(_shades(pal))
    # ... and at most MAX_SHADES: a painterly crown's dabs each take their own colour
    if shades < MIN_SHADES or shades > MAX_SHADES:
        return None
    return pal


def _not_gradient(whole: np.ndarray, cols: np.ndarray) -> bool:
    """Whether a crown's flat regions are facets rather than the bands of a smooth gradient
    (trees58): neighbouring regions mostly more than :data:`GRADIENT_STEP` apart
    (:data:`GRADIENT_SHARE`; a quantised gradient's bands are one step apart)."""
    inner = close = 0
    for dy, dx in ((0, 1), (1, 0)):
        a, b = whole[:whole.shape[0] - dy, :whole.shape[1] - dx], whole[dy:, dx:]
        m = (a != b) & (a > 0) & (b > 0)
        inner += int(m.sum())
        close += int((np.abs(cols[a[m]] - cols[b[m]]).max(axis=1) <= GRADIENT_STEP).sum())
    return not inner or close <= GRADIENT_SHARE * inner


def _shades(pal: np.ndarray) -> list:
    """The palette's colours, those within :data:`SHADE_TOL` of an earlier one left out."""
    kept: list = []
    for c in pal:
        if all(np.abs(c - k).max() > SHADE_TOL for k in kept):
            kept.append(c)
    return kept


def straighten_facets(image, palette, trunk=None, *, sources=None):
    """Redraw a mix's faceted crown as straight polygons (see the module notes).

    Parameters
    ----------
    image : (H, W, 4) array_like
        The mix (straight RGBA, binary alpha).
    palette : (k, 3) array_like
        The facet colours of its sources (:func:`facet_palette`).
    trunk : (H, W) array_like, optional
        The mix's trunk layer (>= 0.5 on the trunk), kept as it is.
    sources : (H, W) int array_like, optional
        Each pixel's source index (-1 transparent), carried to the redrawn pixels.

    Returns
    -------
    image : (H, W, 4) float32 ndarray
    sources : (H, W) int ndarray or None
        ``sources`` with the pixels the polygons add given their nearest source.

    Raises
    ------
    ValueError
        ``palette`` not (k, 3), ``trunk`` or ``sources`` of another shape.

    Examples
    --------
    >>> import numpy as np, cv2
    >>> img = np.zeros((64, 64, 4), np.float32)
    >>> _ = cv2.fillPoly(img, [np.int32([[8, 8], [56, 8], [8, 56]])], (0.2, 0.6, 0.2, 1.0))
    >>> out, _ = straighten_facets(img, [(0.2, 0.6, 0.2)])
    >>> int(np.abs(out[..., 3] - img[..., 3]).sum()) <= 40       # a straight facet stays
    True
    """
    img = as_rgba(image, name="image").copy()
    pal = np.asarray(palette, np.float32)
    if pal.ndim != 2 or pal.shape[1] != 3 or len(pal) == 0:
        raise ValueError(f"palette must be (k, 3) colours, got shape {pal.shape}")
    h, w = img.shape[:2]
    opaque = img[..., 3] >= 0.5
    tr = np.zeros((h, w), bool)
    if trunk is not None:
        t = np.asarray(trunk)
        if t.shape != (h, w):
            raise ValueError(f"trunk must have the image's shape {(h, w)}, got {t.shape}")
        tr = (t >= 0.5) & opaque
    src = None
    if sources is not None:
        src = np.asarray(sources).astype(np.int64, copy=True)
        if src.shape != (h, w):
            raise ValueError(f"sources must have the image's shape {(h, w)}, got {src.shape}")
    crown = opaque & ~tr
    area = int(crown.sum())
    if area < 200:
        return img, src
    # flat pixels of a palette colour; runs of one colour make the facet regions
    rgb = img[..., :3]
    d, idx = cKDTree(pal).query(rgb[crown], k=1)
    flat = np.zeros((h, w), bool)
    flat[crown] = d <= 1.0 / _QUANT
    snapped = rgb.copy()
    snapped[crown] = np.where((d <= 1.0 / _QUANT)[:, None], pal[idx], rgb[crown])
    lab, n = _regions(snapped, crown & flat, max(8, int(0.001 * area)))
    if n < 2:
        return img, src
    _, (iy, ix) = ndi.distance_transform_edt(lab == 0, return_indices=True)
    lab = np.where(crown, lab[iy, ix], 0)
    cols = np.zeros((n + 1, 3), np.float32)
    for c in range(3):
        cols[1:, c] = ndi.median(snapped[..., c], np.where(flat, lab, 0), np.arange(1, n + 1))
    polys, owner = _facet_polygons(lab, tr, n, max(1.5, SNAP * max(h, w)))
    if not polys:
        return img, src
    # large regions first: a region round a hole is traced without it, and the facets in the
    # hole (smaller) are drawn over it
    order = np.argsort([-abs(cv2.contourArea(q.astype(np.float32))) for q in polys], kind="stable")
    polys, owner = [polys[i] for i in order], [owner[i] for i in order]
    # draw the polygons anti-aliased on a supersampled canvas, in the crown's bounding box
    ys, xs = np.nonzero(crown)
    m = int(np.ceil(SNAP * max(h, w))) + 2
    y0, y1 = max(0, ys.min() - m), min(h, ys.max() + m + 1)
    x0, x1 = max(0, xs.min() - m), min(w, xs.max() + m + 1)
    S = _SUPER
    prem = np.zeros(((y1 - y0) * S, (x1 - x0) * S, 3), np.float32)
    cov = np.zeros(((y1 - y0) * S, (x1 - x0) * S), np.float32)
    for q, j in zip(polys, owner, strict=True):
        # pixel centres at (x + 0.5) / S on the canvas: x supersampled = (x - x0 + 0.5) S
        p = np.round((q - [x0, y0] + 0.5) * S - 0.5).astype(np.int32)
        cv2.fillPoly(prem, [p], tuple(float(v) for v in cols[j]))
        cv2.fillPoly(cov, [p], 1.0)
    prem = cv2.resize(prem * cov[..., None], (x1 - x0, y1 - y0), interpolation=cv2.INTER_AREA)
    cov = cv2.resize(cov, (x1 - x0, y1 - y0), interpolation=cv2.INTER_AREA)
    box = np.zeros((h, w), np.float32)
    box[y0:y1, x0:x1] = cov
    col = np.zeros((h, w, 3), np.float32)
    col[y0:y1, x0:x1] = prem / np.maximum(cov, 1e-6)[..., None]
    # a pixel the mix had keeps when the polygons cover a fifth of it: their corners lie on the
    # pixels' edges, at a stair-step's inner corner half a pixel inside a slanted edge's middle
    inside = (box >= 0.5) | (crown & (box >= 0.2))
    # thin slits between polygons (a corner Douglas-Peucker left out) and the seam with the
    # trunk stay opaque, in the nearest polygon's colour
    near_trunk = ndi.binary_dilation(tr, iterations=2) if tr.any() else tr
    keep = crown & ~inside & (ndi.binary_fill_holes(inside | tr) | near_trunk)
    # the silhouette moves by at most REACH of the size: a region traced wrong (a facet the warp
    # tore, a corner snapped across a narrow part) cannot add a sliver or cut a notch beyond it
    reach = max(2.0, REACH * max(h, w))
    depth = ndi.distance_transform_edt(crown)
    near = ndi.distance_transform_edt(~crown) <= reach
    keep |= crown & (depth > reach)
    new = (inside & ~tr & near) | keep
    _, (jy, jx) = ndi.distance_transform_edt(~inside, return_indices=True)
    out = img.copy()
    out[new, :3] = np.where(inside[new][:, None], col[new], col[jy[new], jx[new]])
    gone = crown & ~new
    out[gone] = 0.0
    out[new, 3] = 1.0
    if src is not None:
        had = src >= 0
        _, (ky, kx) = ndi.distance_transform_edt(~had, return_indices=True)
        src = np.where(new & ~had, src[ky, kx], src)
        src[gone] = -1
    return out, src
