"""Flat-colour examples (drawn maps, binary masks): draw the output the way the example is drawn.

The paper paints a new image with disk fragments of a photographed
example (vessels, lightning, cracks). A drawn map or a water mask is not a
photograph: it is flat regions (land, sea), maybe a boundary line between
them (a coast), and lines of one colour whose width follows the branch's
thickness. Copying fragments of such an image breaks one-pixel-accurate
lines into pieces, leaves specks, drags pieces of the frame along and
cannot draw a coast that is not in any fragment. Going beyond the paper,
for these examples the style is measured from the example
(:func:`drawing_style`: each region's colour, the line colour, how wide
the lines are drawn for a given radius, whether and how the region
boundary is drawn) and the target is drawn in that style
(:func:`draw_in_style`): regions in their colours, the boundary line along
the output's own region boundary, every branch as one connected
anti-aliased stroke joined to its parent.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..core.render import coverage_polylines
from ..core.structure import Branch, Structure
from .drawn_domains import draw_boundary
from .roots import outlet_starts
from .skeleton_map import PixelMap

__all__ = ["DrawingStyle", "draw_in_style", "drawing_style"]


@dataclass
class DrawingStyle:
    """How a flat-colour example is drawn (see :func:`drawing_style`).

    Parameters
    ----------
    region_colours : (K, C) ndarray
        Colour of every region label.
    branch_region : int
        The region the branches lie in (the land of a map).
    line_colour : (C,) ndarray
        Colour of the branch lines.
    width_scale : float
        Drawn line width over ``2 r`` (the structure's radius).
    boundary_colour : (C,) ndarray or None
        Colour of the line drawn along the branch region's boundary (a
        coast), None when the example draws none.
    boundary_width : float
        Its width in pixels.
    outlet_reach : float
        How far (pixels) the example's roots start from the region boundary
        at most: roots that close reach it in the drawing (a river's mouth
        meets the coast line). 0 when the roots do not start at the boundary.
    tip_reach : float
        The same for the branch ends: how far (pixels) the example's free
        branch ends lie from the region boundary at most when they end at
        it (a delta's distributaries run into the sea); 0 when they end
        inland (a river's sources).
    region_textures : dict or None
        ``{label: (H', W', C) image}`` for regions that are not one flat
        colour in the example (a map's relief in several greys): the
        example's own pixels of that region with its lines and boundary
        ink taken out (each such pixel takes the colour of the nearest
        kept pixel of the region). :func:`draw_in_style` fills the region
        from it at the same place (mirrored beyond its size). None or a
        missing label: the flat colour.
    two_tone : bool
        The example is a binary line mask (every pixel a region's colour or
        the line colour, no anti-aliasing, no boundary line: one ground, or
        a delta's land and sea): the drawing is snapped to those colours,
        each branch keeping an unbroken 8-connected centre line (beyond the
        paper: a mask synthesized from a mask stays a mask, and its one-pixel
        lines stay whole and full strength; with a sea, issue 23, three
        384-1024 px deltas: grey pixels 0.6-1.4 % -> 0, one seed's 9 line
        pieces and 8 specks -> 1 and 0).
    taper : float or None
        For masks (one ground, or lines in the colour of a region: a delta's
        channels in the sea's): the example's median end-to-start radius
        ratio along its branches, and ``tip_radius`` the median radius of its
        free ends; :func:`draw_in_style` then draws every branch within them
        (:mod:`~branchnb.branching.drawn_taper`: children that taper, no
        blunt ends or stubs). None: the structure's radii as they are.
    tip_radius : float
        See ``taper``.
    coast_profile : (distances, colours) or None
        The example's colour across its drawn coast by signed distance to
        the branch region's edge (:func:`~branchnb.branching.drawn_profiles.coast_profile`);
        when set, :func:`draw_in_style` paints it along the output's edge
        instead of one line of ``boundary_colour`` (a double coast stays
        double). None: the single line.
    coast_dashes : (period, dash) or None
        A dotted or dashed coast's rhythm along its arc length, in pixels
        (:func:`~branchnb.branching.drawn_dashes.coast_dashes`); when set,
        :func:`draw_in_style` draws the coast with it in ``boundary_colour``
        and ``boundary_width``. None: a continuous coast.
    """

    region_colours: np.ndarray
    branch_region: int
    line_colour: np.ndarray
    width_scale: float
    boundary_colour: np.ndarray | None
    boundary_width: float
    outlet_reach: float = 0.0
    tip_reach: float = 0.0
    region_textures: dict | None = None
    two_tone: bool = False
    taper: float | None = None
    tip_radius: float = 0.0
    coast_profile: tuple | None = None
    coast_dashes: tuple | None = None


def _median_colour(img: np.ndarray, mask: np.ndarray, fallback) -> np.ndarray:
    return np.median(img[mask], axis=0) if np.count_nonzero(mask) else np.asarray(fallback, np.float32)


def drawing_style(image: np.ndarray, structure: Structure, layout: np.ndarray, pm: PixelMap,
                  *, tol: float = 0.2) -> DrawingStyle:
    """Measure how a flat-colour example is drawn.

    Parameters
    ----------
    image : (H, W, C) float32
        The example.
    structure : Structure
        Its branches.
    layout : (H, W) int ndarray
        Its regions without the branches (:func:`~branchnb.branching.flat_regions.region_layout`).
    pm : PixelMap
        The structure's pixel map on the example.
    tol : float
        A pixel is drawn in a colour when it lies within ``tol`` of it
        (Euclidean, in [0, 1] units), and not within ``tol`` of its region.

    Notes
    -----
    - Region colours: the median of each region's pixels away from the
      branches.
    - Line colour: the median of the pixels under the centre lines; the
      drawn width is the area drawn in that colour near the branches over
      their length, against the structure's mean ``2 r``.
    - Boundary line: the pixels where the branch region meets another,
      away from the branches; when most of them are drawn in a colour
      unlike both regions', that colour, with the width measured like the
      lines'.
    """
    img = np.asarray(image, np.float32)
    lay = np.asarray(layout)
    k = int(lay.max()) + 1
    far = pm.dist > pm.radius + 3
    cols = np.stack([_median_colour(img, (lay == i) & far, img.reshape(-1, img.shape[2]).mean(0))
                     for i in range(k)])
    centre = pm.dist <= 0.5
    branch_region = int(np.bincount(lay[centre], minlength=k).argmax()) if centre.any() else 0
    region_col = cols[lay]
    off_region = np.linalg.norm(img - region_col, axis=-1)
    # the line's own colour: its centre pixels that stand out most (thin anti-aliased lines blend
    # most of their centre pixels with the ground: their median drew pale rivers), the drawn width
    # below then comes out narrower, so the ink per length stays the example's
    # (a line mask on one ground, k == 1: its lines of every width are one ink at full cover, so the
    # line colour is its strongest centre pixels'; a mask mostly of thin anti-aliased lines otherwise
    # drew its wide trunk grey)
    pct = 90 if k == 1 else 67
    strong = centre & (off_region >= np.percentile(off_region[centre], pct)) if centre.any() else centre
    line = _median_colour(img, strong, cols[branch_region])
    unlike_region = off_region > tol

    def cover(colour):
        # how much of each pixel the line covers: anti-aliased edges count in part
        span = np.linalg.norm(np.asarray(colour, np.float32) - region_col, axis=-1)
        return np.clip(off_region / np.maximum(span, 1e-6), 0.0, 1.0) * (span > tol)

    # the width is measured along the branches' stretches that lie in the branch region: a stretch in
    # another region is no line drawn on it (a sea strait between two islands that the wide-line search
    # took for a 40 px river, issue 23): its 20-34 px radius against the coast lines' ink halved the
    # scale, and the output's 2 px rivers came out as faint 1 px dashes (768 px two-island map: 80-121
    # line pieces per tree, 208-338 specks)
    inside = lay == branch_region
    total, mean_r = _length_and_radius(structure, inside)
    zone = pm.dist <= 3 * max(mean_r, 1.0) + 3
    drawn = float(cover(line)[zone].sum())
    width = drawn / total
    scale = float(np.clip(width / max(2 * mean_r, 1e-6), 0.25, 4.0)) if drawn else 1.0
    b_col, b_width = _boundary_line(img, inside, lay, k, pm, mean_r, off_region, unlike_region, line, cover,
                                    cols, tol)
    direct = b_col is not None
    if b_col is None:
        # Beyond the paper: the branch region by colour may be one relief level of the land (a small
        # terrain map whose white lowlands have the colour of the white outside, and whose rivers lie
        # mostly in a grey level): the coast is then read along the example's domain, the land a
        # drawn line walls off (:func:`~branchnb.branching.backgrounds.example_domain`).
        from .backgrounds import example_domain

        dom = example_domain(img[..., :3], structure)
        if 0.02 < dom.mean() < 0.98:
            b_col, b_width = _boundary_line(img, dom, lay, k, pm, mean_r, off_region, unlike_region, line,
                                            cover, cols, tol)
    # roots that start near the region boundary are outlets: the drawing joins them to it
    reach, tip_reach = 0.0, 0.0
    outside = ~inside
    if outside.any() and not outside.all():
        d_out = ndi.distance_transform_edt(inside)
        h, w = lay.shape
        lim = max(12.0, 0.015 * float(np.hypot(h, w)))
        # a tree the tracer rooted at a source drains where its one branch end at the boundary is
        # (see roots.outlet_starts): that end is its mouth, no free end running into the sea
        mouths = outlet_starts(structure, inside)
        reach = _boundary_reach([d_out[_pixel(q, w, h)] for q in mouths], lim)
        mouth_px = {_pixel(q, w, h) for q in mouths}
        # free branch ends (not running into another branch, not at the frame) that end at the
        # boundary: a delta's distributaries
        ends = []
        for i, b in enumerate(structure.branches):
            x, y = b.points[-1]
            if min(x, y, w - 1 - x, h - 1 - y) < 2 or _pixel(b.points[-1], w, h) in mouth_px:
                continue
            others = pm.branch != i
            rad = 2.0 * float(b.thickness[-1]) + 2.0
            iy, ix = _pixel(b.points[-1], w, h)
            y0, x0 = max(iy - int(rad) - 1, 0), max(ix - int(rad) - 1, 0)
            win = (pm.dist[y0:iy + int(rad) + 2, x0:ix + int(rad) + 2] <= pm.radius[y0:iy + int(rad) + 2,
                                                                                 x0:ix + int(rad) + 2])
            if (win & others[y0:iy + int(rad) + 2, x0:ix + int(rad) + 2]).any():
                continue
            # at the boundary, not merely near it all along (a river in a narrow floodplain band)
            body = np.median([d_out[_pixel(q, w, h)] for q in b.points])
            ends.append(d_out[iy, ix] if d_out[iy, ix] <= 0.5 * body else np.inf)
        tip_reach = _boundary_reach(ends, lim, share=0.5)
    profile = None
    dashes = None
    rest = lay[~inside]
    outer = int(np.bincount(rest, minlength=k).argmax()) if rest.size else branch_region
    shore = ~inside & ndi.binary_dilation(inside)
    if (direct or b_col is None) and shore.any() and np.mean(lay[shore] == outer) >= 0.9:
        # a dotted or dashed coast (beyond the paper, issue 23): under half the edge bears ink, or
        # the median profile across it is the ground's; drawn with the example's rhythm instead
        from .drawn_dashes import dashed_coast

        found = dashed_coast(img, inside, pm, 3 * max(mean_r, 1.0) + 6, off_region, cols, tol)
        if found is not None:
            b_col, b_width, dashes = found
            direct = False
    if direct and shore.any() and np.mean(lay[shore] == outer) >= 0.9:
        # (only where the branch region meets one other region, the sea, along its coast: against
        # relief levels with no line between them, or a coast read along the drawn domain, the
        # profile across the region's edge is no coast's)
        from .drawn_profiles import coast_profile

        profile = coast_profile(img, inside, pm, 3 * max(mean_r, 1.0) + 6, cols[branch_region], cols[outer])
    # (a texture is read away from every line the coast profile draws)
    band = b_width if b_col is not None else 0.0
    if profile is not None:
        band = max(band, float(np.max(np.abs(profile[0]))))
    textures = _region_textures(img, lay, cols, pm, line, band, branch_region, b_col)
    # a binary line mask: every pixel is the ground colour or the line colour
    # (and a binary mask with a sea, k == 2: a delta's white channels and sea on black land, where
    # each pixel is a region's colour or the line's; drawn anti-aliased, 0.6-1.4 % of the output's
    # pixels were grey and thin channels faded into dashes: 384 px delta, 9 pieces, 8 specks)
    two_tone = bool(b_col is None and not textures and profile is None
                    and np.all(np.min([np.abs(img - c).max(-1) for c in list(cols) + [line]], axis=0) <= 1.5 / 255))
    # a mask (lines on one ground, or drawn in a region's own colour: a delta's channels in the sea's
    # colour) is drawn with the example's taper; a map's rivers in their own ink keep their radii
    taper, tip_r = None, 0.0
    if k == 1 or np.min(np.linalg.norm(np.delete(cols, branch_region, axis=0) - line, axis=-1)) <= tol:
        from .drawn_taper import example_taper

        taper, tip_r = example_taper(structure, lay.shape)
    return DrawingStyle(cols.astype(np.float32), branch_region, line.astype(np.float32), scale,
                        None if b_col is None else b_col.astype(np.float32), b_width, reach, tip_reach,
                        textures or None, two_tone, taper, tip_r, profile, dashes)


def _length_and_radius(structure: Structure, inside: np.ndarray) -> tuple[float, float]:
    """(length, length-weighted mean radius) of the branches' segments that lie in ``inside``: both
    ends on it and at most 1 px less deep in it than their radius (a line drawn on a region stays in
    it); of all segments when under half of the length does (the region does not hold the lines)."""
    h, w = inside.shape
    depth = ndi.distance_transform_edt(inside)
    seg, rad, ins = [], [], []
    for b in structure.branches:
        p = np.asarray(b.points, np.float64)
        if len(p) < 2:
            continue
        t = np.asarray(b.thickness, np.float64)
        q = np.rint(p).astype(int)
        on = depth[np.clip(q[:, 1], 0, h - 1), np.clip(q[:, 0], 0, w - 1)] + 1.0 >= np.maximum(t, 0.5)
        seg.append(np.hypot(*np.diff(p, axis=0).T))
        rad.append(0.5 * (t[1:] + t[:-1]))
        ins.append(on[1:] & on[:-1])
    if not seg:
        return 1.0, 0.0
    seg, rad, ins = np.concatenate(seg), np.concatenate(rad), np.concatenate(ins)
    if seg[ins].sum() < 0.5 * seg.sum():
        ins[:] = True
    total = max(float(seg[ins].sum()), 1.0)
    return total, float(np.sum(seg[ins] * rad[ins])) / total


def _boundary_line(img, inside, lay, k, pm, mean_r, off_region, unlike_region, line, cover, cols, tol):
    """The colour and width of the line drawn along the boundary of ``inside`` (the branch region)
    away from the branches and the frame, or ``(None, 0.0)`` when most of it is not drawn or its
    colour is a region's own (within ``tol`` of one of ``cols``: a photograph's matte with a
    vignetted rim, e.g. a fundus, whose darkest rim pixels are the matte's colour, is no line)."""
    edge = inside & ndi.binary_dilation(~inside) | ~inside & ndi.binary_dilation(inside)
    edge[:2] = edge[-2:] = False
    edge[:, :2] = edge[:, -2:] = False
    # Away from the branches (their ink is no boundary line). On a small, densely drawn map the
    # rivers reach the coast every few pixels and no boundary lies that far from them: then the
    # boundary just off the branch bodies is read (beyond the paper, which draws no boundaries).
    b_col, b_width = None, 0.0
    for margin in (3 * max(mean_r, 1.0) + 6, 2 * max(mean_r, 1.0) + 3):
        kept = edge & (pm.dist > margin)
        if np.count_nonzero(kept) >= 20:
            break
    edge = kept
    if np.count_nonzero(edge) >= 20:
        band = ndi.binary_dilation(edge, iterations=4) & (pm.dist > pm.radius + 1.5)
        ink = band & unlike_region
        hit = ndi.binary_dilation(ink, iterations=1)[edge]
        against = False
        if hit.mean() < 0.5 and k > 2:
            edge, band, ink, hit = _drawn_against(edge, inside, lay, k, band, ink, unlike_region, pm)
            against = True
        if hit.mean() >= 0.5 and ink.any():
            # the line's own colour: its most saturated pixels, not the anti-aliased rim
            strong = ink & (off_region >= np.percentile(off_region[ink], 67))
            b_col = _median_colour(img, strong, line)
            if np.min(np.linalg.norm(np.asarray(cols, np.float32) - b_col, axis=-1)) < tol:
                return None, 0.0
            if against:
                # the band also crosses other regions' edges: the line's width is its own area over its length
                from skimage.morphology import skeletonize

                solid = band & (cover(b_col) >= 0.5)
                b_width = float(np.clip(solid.sum() / max(int(skeletonize(solid).sum()), 1), 1.0, 16.0))
            else:
                length = max(np.count_nonzero(edge) / 2.0, 1.0)  # both sides of the boundary are marked
                b_width = float(np.clip(cover(b_col)[band & (pm.dist > margin - 4)].sum() / length, 1.0, 16.0))
    return b_col, b_width


#: A region is textured when more than ``_TEXTURED_SHARE`` of its pixels away from the lines differ
#: from its median colour by more than ``_TEXTURED_DEV`` (flat fills and their anti-aliasing stay flat),
#: or more than ``_MARKED_SHARE`` of those away from its edge too (marks printed on it: wave dashes,
#: tree glyphs, stipple; an edge's anti-aliasing is no mark; a sea sparsely hatched with 1 px dashes has 1 %).
_TEXTURED_DEV = 0.06
_TEXTURED_SHARE = 0.15
_MARKED_SHARE = 0.004


def _region_textures(img: np.ndarray, lay: np.ndarray, cols: np.ndarray, pm: PixelMap, line: np.ndarray,
                     boundary_width: float, branch_region: int, boundary_colour=None) -> dict:
    """The example's pixels of every region that is not one flat colour, without its lines or boundary.

    Beyond the paper (which paints photographs with fragments): a drawn map whose land shows
    relief in several greys kept only the land's median colour when drawn in style. The regions
    the branches run through about as densely as through the branch region (>= 0.2x: relief
    levels of the land, not the sea the rivers end at) form one group with it and share its
    texture, so the output's land shows the example's relief.

    Pixels of the coast's colour (``boundary_colour``, within 0.1) at the frame
    are no texture (a coast drawn along the frame, where the land
    meets it, was copied as brown bars and specks into the output's land).
    """
    out = {}
    k = len(cols)
    far = pm.dist > pm.radius + 3
    centre = pm.dist <= 0.5
    area = np.bincount(lay.ravel(), minlength=k).astype(float)
    density = np.bincount(lay[centre], minlength=k) / np.maximum(area, 1.0)
    group = set(np.flatnonzero(density >= 0.2 * density[branch_region]).tolist()) | {branch_region}
    # ink of lines the structure does not hold (reservoirs, unextracted rivers): colours on the way from
    # the ground to the line colour (within a cone around that segment; relief greys lie off it
    # unless the lines are grey too)
    c0 = np.asarray(cols[branch_region], np.float32)
    d = np.asarray(line, np.float32) - c0
    dd = float(d @ d)
    ink = np.zeros(lay.shape, bool)
    ground_ink = np.zeros(k, bool)
    if dd > 0.01:
        # a region whose own colour lies in that cone (a teal sea between a parchment land and blue
        # rivers) would be all ink: there the cone tells nothing and the region's marks stay
        tc = np.clip(((cols - c0) @ d) / dd, 0.0, 1.0)
        ground_ink = (tc > 0.25) & (np.linalg.norm(cols - c0 - tc[:, None] * d, axis=-1) < 0.35 * tc * np.sqrt(dd))
        t = np.clip(((img - c0) @ d) / dd, 0.0, 1.0)
        perp = np.linalg.norm(img - c0 - t[..., None] * d, axis=-1)
        ink = (t > 0.25) & (perp < 0.35 * t * np.sqrt(dd))
    groups = [sorted(group)] + [[i] for i in range(k) if i not in group]
    for g in groups:
        reg = np.isin(lay, g)
        m = reg & far
        if np.count_nonzero(m) < 50:
            continue
        ground = cols[g[0] if len(g) == 1 else branch_region]
        dev = np.linalg.norm(img[m] - ground, axis=-1)
        # away from the region's edge (a drawn boundary and its anti-aliasing) and from any ink
        inner = ndi.binary_erosion(reg, iterations=int(np.ceil(boundary_width)) + 2, border_value=1)
        ink_g = ink if len(g) > 1 or not ground_ink[g[0]] else np.zeros_like(ink)
        sparse = np.mean(dev > _TEXTURED_DEV) <= _TEXTURED_SHARE
        if sparse:
            # (ink of lines the structure does not hold, and its anti-aliasing, is no mark: a flat
            # country crossed by unextracted river ends was taken as marked and quilted with ghost lines)
            mi = m & inner & ndi.binary_erosion(reg, iterations=3, border_value=0) \
                & ~ndi.binary_dilation(ink_g, iterations=2)
            if np.count_nonzero(mi) < 200 or \
                    np.mean(np.linalg.norm(img[mi] - ground, axis=-1) > _TEXTURED_DEV) <= _MARKED_SHARE:
                continue
        if boundary_colour is not None:
            coast_ink = np.linalg.norm(img - np.asarray(boundary_colour, np.float32), axis=-1) < 0.1
            rim = np.zeros(lay.shape, bool)
            e = int(np.ceil(boundary_width)) + 3
            rim[:e] = rim[-e:] = True
            rim[:, :e] = rim[:, -e:] = True
            ink_g = ink_g | (coast_ink & rim & (np.linalg.norm(img - ground, axis=-1) > 0.1))
        keep = (pm.dist > pm.radius + 2) & inner & ~ndi.binary_dilation(ink_g, iterations=1)
        if np.count_nonzero(keep) < 50:
            continue
        from .drawn_profiles import quilt_fill

        # beyond the example's region: blocks copied whole from it (a nearest-pixel fill smeared marks).
        # Only for one region's texture: a group's (relief levels, two countries the rivers cross) keeps
        # the example's pixels where they are, since blocks moved the levels and the countries' border
        # about (the Czech relief drawn white with streaks, a green country's specks in the other).
        # Marks steer the blocks only where they are sparse: on relief (greys over most of the region)
        # every block's rim crosses one, and the few unmarked blocks drew the land white.
        tex = None
        if len(g) == 1:
            tex = quilt_fill(img.astype(np.float32), keep,
                             marks=(np.linalg.norm(img - ground, axis=-1) > _TEXTURED_DEV) if sparse else None)
        if tex is None:
            _d, (iy, ix) = ndi.distance_transform_edt(~keep, return_indices=True)
            tex = img[iy, ix].astype(np.float32)
        tex = _keep_border_ink(img, tex, reg, ink, pm)
        for i in g:
            out[i] = tex
    return out


def _keep_border_ink(img: np.ndarray, tex: np.ndarray, reg: np.ndarray, ink: np.ndarray, pm: PixelMap,
                     tol: float = 0.06) -> np.ndarray:
    """``tex`` with the example's ink put back where it is a drawn line between two colours of the region.

    Beyond the paper. A region's texture is filled over all ink (rivers the
    structure does not hold would otherwise be copied), but on a political
    map the land holds two countries of different colours with a drawn
    border between them: filled over, the countries met in a soft seam with
    no line (issue 23). Ink pixels along the seams of the filled texture
    (where its colour changes by more than ``tol``), in pieces of at least
    ``12 w`` pixels off the structure's bodies running along a seam (a river
    crossing it alone leaves a dash of about its width; a traced river along
    a relief level's edge is no border), keep the example's pixels (within 2 px of the
    seam: a river crossing the border leaves no more than a tick).
    """
    if not ink.any():
        return tex
    step = np.zeros(reg.shape, bool)
    for ax in (0, 1):
        d = np.abs(np.diff(tex, axis=ax)).max(-1) > tol
        if ax == 0:
            step[:-1] |= d
            step[1:] |= d
        else:
            step[:, :-1] |= d
            step[:, 1:] |= d
    step &= reg & ndi.binary_erosion(reg, iterations=2, border_value=1)
    if not step.any():
        return tex
    line = ink & reg & ndi.binary_dilation(step, iterations=2)
    lab, n = ndi.label(line, structure=np.ones((3, 3)))
    if n == 0:
        return tex
    w = max(float(np.median(ndi.distance_transform_edt(ink)[ink])) * 2.0, 1.0)
    # counted off the structure's bodies: a traced river lying along a relief level's edge is no border,
    # a border passing beside a river keeps its whole length
    sizes = np.bincount(lab.ravel(), weights=(pm.dist > pm.radius + 1.5).ravel(), minlength=n + 1)
    ok = sizes >= 12 * w * w + 20
    ok[0] = False
    put = ok[lab]
    # with the anti-aliased rim of the kept line
    put = ndi.binary_dilation(put, iterations=1) & reg & ndi.binary_dilation(step, iterations=3)
    out = tex.copy()
    out[put] = img[put]
    return out


def _drawn_against(edge, inside, lay, k, band, ink, unlike_region, pm):
    """The boundary of the branch region against those neighbour regions it is drawn along.

    Beyond the paper. A drawn map's land may meet several regions: the
    transparent outside along a drawn border, and relief levels inside with
    no line between them. The boundary line is judged on the edge against
    each neighbour region (at least 20 pixels of it) alone; when some are
    drawn (a line along at least half of that edge), the edge, band, ink
    and hits are those against them; else they are returned as given.
    """
    near_ink = ndi.binary_dilation(ink, iterations=1)
    outer = edge & ~inside
    good = np.zeros(k, bool)
    for j in np.unique(lay[outer]):
        e_j = outer & (lay == j)
        if np.count_nonzero(e_j) >= 20 and near_ink[e_j].mean() >= 0.5:
            good[j] = True
    if not good.any():
        return edge, band, ink, near_ink[edge]
    edge = edge & ndi.binary_dilation(good[lay] & ~inside)
    band = ndi.binary_dilation(edge, iterations=4) & (pm.dist > pm.radius + 1.5)
    ink = band & unlike_region
    return edge, band, ink, ndi.binary_dilation(ink, iterations=1)[edge]


def _pixel(p, w: int, h: int) -> tuple[int, int]:
    """(row, column) of point ``p`` = (x, y), clipped to the image."""
    x, y = np.clip(np.rint(np.asarray(p, np.float64)).astype(int), 0, [w - 1, h - 1])
    return int(y), int(x)


def _boundary_reach(depths, lim: float, share: float = 0.5) -> float:
    """How far ends lying at the region boundary may start from it: 0 unless at least ``share`` of
    the ``depths`` (distance of each end to the boundary) are within ``lim``; else 1.5 x the largest
    such depth + 2, at least ``lim`` (a synthesized end stops up to one growth step short of its
    domain's edge, whatever the example's), at most ``3 lim``."""
    d = np.asarray(depths, np.float64)
    if d.size == 0 or np.mean(d <= lim) < share:
        return 0.0
    return float(min(max(np.max(d[d <= lim]) * 1.5 + 2, lim), 3 * lim))


def _extend_to(points: np.ndarray, inside: np.ndarray, d_out: np.ndarray, reach: float, nearest=None):
    """Point where the ray back from ``points[0]`` (away from ``points[1:]``) leaves ``inside``,
    when ``points[0]`` lies inside within ``reach`` of its boundary; else None.

    ``nearest``: (2, H, W) row and column of the nearest pixel outside ``inside`` (the indices of
    its distance transform). Going beyond a straight continuation: when the ray runs along the
    boundary instead (a river whose first steps follow the coast), the end is joined to that
    nearest outside pixel, no farther than ``reach`` (a mouth that never met its coast line
    would float inland)."""
    h, w = inside.shape
    iy, ix = _pixel(points[0], w, h)
    if d_out[iy, ix] > reach or not inside[iy, ix] or len(points) < 2:
        return None
    k = min(3, len(points) - 1)
    back = points[0] - points[k]
    n = float(np.hypot(*back))
    if n < 1e-9:
        return None
    back = back / n
    steps = np.arange(1, int(np.ceil(reach * 2)) + 1)[:, None] * 0.5
    ray = points[0] + steps * back
    ix = np.clip(np.rint(ray[:, 0]).astype(int), 0, w - 1)
    iy = np.clip(np.rint(ray[:, 1]).astype(int), 0, h - 1)
    leave = np.flatnonzero(~inside[iy, ix])
    if len(leave):
        return ray[leave[0]]
    if nearest is None:
        return None
    y0, x0 = _pixel(points[0], w, h)
    return np.array([nearest[1][y0, x0], nearest[0][y0, x0]], np.float64)


def _trim_tail(points: np.ndarray, r: np.ndarray, d_out: np.ndarray, clear: float, keep: int):
    """Drop the last points of a branch while they lie within ``clear`` of the region boundary
    (never index ``keep`` or before, never more than half the branch)."""
    h, w = d_out.shape
    ix = np.clip(np.rint(points[:, 0]).astype(int), 0, w - 1)
    iy = np.clip(np.rint(points[:, 1]).astype(int), 0, h - 1)
    near = d_out[iy, ix] < clear
    n = len(points)
    end = n
    while end - 1 > max(keep, n // 2, 1) and near[end - 1]:
        end -= 1
    return (points[:end], r[:end]) if end < n else (points, r)


def _to_outlets(structure: Structure, inside: np.ndarray, reach: float, tip_reach: float = 0.0,
                clear: float = 0.0) -> Structure:
    """Lengthen every root that starts within ``reach`` of the region boundary back to it, and every
    branch that ends within ``tip_reach`` of it on to it (straight on along its last heading).
    Without ``tip_reach``, branch ends that stop within ``clear`` of the boundary are cut back to
    ``clear`` (a river's source a pixel from the coast line would read as a broken mouth)."""
    if reach <= 0 and tip_reach <= 0 and clear <= 0:
        return structure
    d_out, nearest = ndi.distance_transform_edt(inside, return_indices=True)
    last_child = {}
    for b in structure.branches:
        if b.parent is not None:
            last_child[b.parent] = max(last_child.get(b.parent, 0), int(b.parent_vertex or 0))
    out = []
    for i, b in enumerate(structure.branches):
        pts, r, pv = b.points, b.thickness, b.parent_vertex
        if tip_reach <= 0 < clear and len(pts) > 2:
            pts, r = _trim_tail(pts, r, d_out, clear, last_child.get(i, 0))
        if reach > 0 and b.parent is None:
            tip = _extend_to(pts, inside, d_out, reach, nearest)
            if tip is not None:
                pts, r = np.vstack([tip, pts]), np.r_[r[0], r]
        if tip_reach > 0:
            tip = _extend_to(pts[::-1], inside, d_out, tip_reach)
            if tip is not None:
                pts, r = np.vstack([pts, tip]), np.r_[r, r[-1]]
        out.append(b if pts is b.points else Branch(pts, r, b.parent, pv))
    # children's parent vertices move by one where their parent got a new first vertex
    moved = {i for i, (a, b) in enumerate(zip(out, structure.branches))
             if len(a.points) and len(b.points) and not np.array_equal(a.points[0], b.points[0])}
    fixed = []
    for b in out:
        if b.parent is not None and b.parent in moved:
            b = Branch(b.points, b.thickness, b.parent, b.parent_vertex + 1)
        fixed.append(b)
    return Structure(fixed, image_shape=structure.image_shape)


def _mirror(i: np.ndarray, n: int) -> np.ndarray:
    """Indices ``i`` reflected into ``[0, n)`` (a texture repeated mirrored beyond its size)."""
    i = np.mod(i, 2 * n)
    return np.where(i < n, i, 2 * n - 1 - i)


def draw_in_style(style: DrawingStyle, structure: Structure, labels: np.ndarray, *,
                  lines: bool = True) -> np.ndarray:
    """Draw ``structure`` over the region map ``labels`` in ``style``; (H, W, C) float32.

    Regions are filled with their colours (or the example's own pixels of
    a textured region, see :class:`DrawingStyle`), the boundary of the branch
    region (not the frame) is drawn with the style's boundary line, then
    every branch with the line colour at ``width_scale * 2 r`` (at least one
    pixel, so no branch breaks into dots).

    With ``style.coast_profile`` the coast is the example's colour profile
    across its coast painted along the output's region edge (a double coast
    stays double); a textured or marked region's pixels beyond the example's
    region are blocks of it copied whole (beyond the paper, issue 23;
    :mod:`~branchnb.branching.drawn_profiles`).

    For a mask (``style.taper`` or ``style.tip_radius`` set) the radii are
    first bounded by what the example shows (beyond the paper, issue 23;
    :func:`~branchnb.branching.drawn_taper.tapered_radii`): each branch stays
    under the example's end-to-start ramp and never ends more than twice as
    thick as it starts, free ends narrow to the example's tip radius, short
    children are drawn as thin twigs and leaf twigs showing less than three
    radii beyond their parent are left out
    (:func:`~branchnb.branching.drawn_taper.burrs`).

    Parameters
    ----------
    style : DrawingStyle
        How the example is drawn (:func:`drawing_style`).
    structure : Structure
        The branches to draw (vertices and radii r in pixels of ``labels``).
    labels : (H, W) int ndarray
        Region label of every pixel, indexing ``style.region_colours``
        (out-of-range labels are clipped).
    lines : bool, default True
        Draw the branches; False = the regions and the boundary line only
        (the ground a glowing example's light is added to, :mod:`.glow`).

    Returns
    -------
    (H, W, C) float32 ndarray
        The drawing, in [0, 1].

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> style = DrawingStyle(np.array([[1.0, 1, 1]]), 0, np.array([0.0, 0, 1]), 1.0, None, 0.0)
    >>> img = draw_in_style(style, Structure([Branch([(2, 10), (18, 10)], 1.5)]), np.zeros((20, 20), int))
    >>> img[10, 10].tolist(), img[2, 2].tolist()
    ([0.0, 0.0, 1.0], [1.0, 1.0, 1.0])
    """
    lab = np.asarray(labels)
    h, w = lab.shape
    cols = style.region_colours
    img = cols[np.clip(lab, 0, len(cols) - 1)].astype(np.float32)
    for i, tex in (style.region_textures or {}).items():
        sel = lab == i
        if sel.any() and tex.shape[2] == img.shape[2]:
            ys, xs = np.nonzero(sel)
            img[ys, xs] = tex[_mirror(ys, tex.shape[0]), _mirror(xs, tex.shape[1])]
    inside = lab == style.branch_region

    def paint(cov, colour):
        np.multiply(img, 1 - cov[..., None], out=img)
        img[...] += cov[..., None] * np.asarray(colour, np.float32)

    if style.boundary_colour is not None and style.coast_dashes is not None:
        from .drawn_dashes import paint_dashes

        img[...] = paint_dashes(img, inside, style.boundary_colour, style.boundary_width, *style.coast_dashes)
    elif style.boundary_colour is not None and style.coast_profile is not None:
        from .drawn_profiles import paint_coast

        out_lab = lab[~inside]
        outer = int(np.bincount(np.clip(out_lab, 0, len(cols) - 1)).argmax()) if out_lab.size else style.branch_region
        img[...] = paint_coast(img, inside, style.coast_profile, cols[style.branch_region], cols[outer])
    elif style.boundary_colour is not None:
        img[...] = draw_boundary(img, inside, style.boundary_colour, style.boundary_width)
    if not lines:
        return np.clip(img, 0.0, 1.0)
    clear = 2.0 * style.boundary_width + 2.0 if style.boundary_colour is not None else 0.0
    s = _to_outlets(structure, inside, style.outlet_reach, style.tip_reach, clear)
    radii = [b.thickness for b in s.branches]
    if style.taper is not None or style.tip_radius > 0:
        from .drawn_taper import burrs, tapered_radii

        radii = tapered_radii(s, (h, w), style.taper, style.tip_radius)
        skip = burrs(s, radii, style.width_scale)
    else:
        skip = np.zeros(len(s.branches), bool)
    drawn = [i for i, b in enumerate(s.branches) if len(b.points) >= 2 and not skip[i]]
    pls = [s.branches[i].points for i in drawn]
    raw = [style.width_scale * 2 * np.asarray(radii[i], np.float64) for i in drawn]
    wid = [np.maximum(x, 1.0) for x in raw]
    if pls and style.two_tone:
        # a binary mask: lines under 1.5 px are one-pixel rasters (as the example draws them), wider
        # ones every pixel they cover at least half of; no anti-aliasing
        wide = [i for i, x in enumerate(raw) if np.median(x) >= 1.5]
        cov = coverage_polylines((h, w), [pls[i] for i in wide], [wid[i] for i in wide])[0] if wide \
            else np.zeros((h, w), np.float32)
        return _two_tone(cov >= 0.5, pls, img, style.line_colour)
    if pls:
        cov, owner = coverage_polylines((h, w), pls, wid)
        # a line thinner than a pixel is drawn one pixel wide at that share of the ink (as the
        # example's anti-aliasing shows it), not one full pixel of its strongest colour
        alpha = np.array([np.clip(np.median(x), 0.3, 1.0) for x in raw] + [1.0], np.float32)
        paint(cov * alpha[owner], style.line_colour)
    return np.clip(img, 0.0, 1.0)


def _two_tone(ink: np.ndarray, lines: list, ground: np.ndarray, line: np.ndarray) -> np.ndarray:
    """A two-colour drawing: ``ink`` pixels and every line's 8-connected centre-line raster in the
    ``line`` colour, the rest ``ground`` (a colour, or an (H, W, C) image of the regions' colours)."""
    import cv2

    g, c = np.asarray(ground, np.float32), np.asarray(line, np.float32)
    ink = np.array(ink, bool)
    centre = np.zeros(ink.shape, np.uint8)
    for pts in lines:
        cv2.polylines(centre, [np.round(np.asarray(pts, np.float64) * 8).astype(np.int32)], False, 1, 1,
                      cv2.LINE_8, 3)
    ink |= centre > 0
    g = g if g.ndim == 3 else np.broadcast_to(g, ink.shape + g.shape)
    return np.where(ink[..., None], c, g).astype(np.float32)
