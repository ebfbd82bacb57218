"""Input extraction: the source structure, from user clicks or automatically.

The paper's user clicks a polyline per branch; the clicks are refined by
uniform resampling (step ``h``) and the thickness ``r`` at every vertex is
found by a *maximum-gradient search perpendicular to the branch*: the
grey-level gradient magnitude is sampled along the normal on both sides
and the offset of its maximum on each side is an edge of the branch, so
``r`` is half the distance between the two edges. The thickness stays an
ordinary array the user may edit afterwards.

:func:`extract_structure` goes beyond the paper (its stated future work):
a ridge / vesselness filter (scikit-image ``sato``, ``frangi`` or
``meijering``), hysteresis thresholding, skeletonisation, conversion of
the skeleton graph into a tree of branches (shortest-path tree from a root
end point, main branch = the longest path, side branches hang off it) and
thickness from the Euclidean distance transform of the ridge mask.

The steps live in their own modules, all re-exported here: :mod:`.clicks`
(the paper's input), :mod:`.ridges` (filter, mask, line colour, radius),
:mod:`.backgrounds` (frame lines, binary masks, flat regions, the
example's domain) and :mod:`.skeleton_tree` (skeleton graph -> tree).
"""


from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_gray, as_rgb
from ..core.params import check_params
from ..core.polyline import arc_length
from ..core.structure import Branch, Structure
from ..core.validate import checked
from .backgrounds import (  # noqa: F401  (re-exported: split from this module)
    _flat_region_labels,
    _ground_regions,
    binary_channels,
    border_flat_regions,
    example_domain,
    flat_background,
    frame_lines,
    is_binary,
    large_flat_regions,
    outline_pixels,
    region_border_pixels,
)
from .clicks import (  # noqa: F401  (re-exported: split from this module)
    _RADIUS,
    branch_from_clicks,
    estimate_thickness,
    gray_for_extraction,
    structure_from_polylines,
)
from .fragment_links import relink_fragments
from .hubs import blob_contrast, find_hubs, hub_skeleton
from .params import ExtractionParams
from .ridges import (  # noqa: F401  (re-exported: split from this module)
    _drawn_branching_width,
    _is_drawn,
    _line_colour_and_width,
    _local_background,
    _outside_field_of_view,
    _polarity,
    fill_outlined_strokes,
    half_contrast_radius,
    line_colour_map,
    line_colour_of,
    multi_colour_ink,
    ridge_mask,
    ridge_response,
    thin_line_colour,
)
from .skeleton_tree import (  # noqa: F401  (re-exported: split from this module)
    _NO_BLUR,
    _OFFSETS,
    _delta_source_key,
    _end_radius,
    _median_then_gauss,
    _mouth_node,
    _skeleton_graph,
    skeleton_to_structure,
)
from .small_frames import SMALL_SIDE, _reach_frame
from .stroke_joins import find_stroke_joins
from .wide_lines import frame_reaching_skeleton, region_arms, wide_line_mask

__all__ = [
    "branch_from_clicks",
    "estimate_thickness",
    "example_domain",
    "extract_structure",
    "binary_channels",
    "flat_background",
    "frame_lines",
    "gray_for_extraction",
    "is_binary",
    "large_flat_regions",
    "line_colour_map",
    "line_colour_of",
    "thin_line_colour",
    "ridge_mask",
    "ridge_response",
    "skeleton_to_structure",
    "structure_from_polylines",
]


@checked()
def extract_structure(image, params: ExtractionParams | None = None, *, mask=None,
                      return_maps: bool = False, line_colour="auto", **overrides):
    """Find a source structure in an image automatically.

    Ridge / vesselness filter -> hysteresis threshold -> skeleton ->
    tree of branches (:func:`skeleton_to_structure`) with the radius from
    the distance transform of the ridge mask. The result is meant to be
    corrected by the user (delete sub-branches, edit thickness).

    Parameters
    ----------
    image : array_like
        Grey, RGB or RGBA (composited over white).
    params : ExtractionParams, optional
        Filter, polarity, scales, thresholds, pruning, ``h``, working
        ``scale``, root rule. Keyword ``overrides`` replace single fields;
        ``root=(x, y)`` roots every piece at its end nearest to that point.
        Binary (or near-binary) input such as a water mask is detected
        (``binary="auto"``) and traced by its medial axis, the radius from
        the distance transform; foreground regions far wider than the
        channels (a sea) are no branches, and braided channels (cycles) are
        cut into a tree where the two fronts of the shortest-path tree meet.
        Outlines of large flat regions touching the border (a country
        border, a coast line) are no branches either; nor, on an engraved
        map, the coast along its hatched sea
        (:func:`~branchnb.branching.hatched_seas.erase_hatched_sea`, beyond the
        paper: the land's paper is the sea's, the outline is told by the sea's
        mask), whose rivers keep their mouth (a piece cut there is kept from
        half ``min_component_length``) and are rooted at the sea. Strokes of several
        colours on one plain paper (an ornament's black stroke with a
        coloured inner line) are traced as one ink mask
        (:func:`~branchnb.branching.ridges.multi_colour_ink`). Drawn strokes broken
        at junctions and at the over-and-under crossings of an interlace are
        joined where their directions continue (``join_gaps``, see
        :func:`~branchnb.branching.stroke_joins.find_stroke_joins`). In
        photographs (``false_ridges``), beyond the paper, the step between a
        darker and a lighter patch of ground (fields, tiles, a shading step) is
        no line: a traced stretch as dark as the ground on one of its sides is
        dropped (:func:`~branchnb.branching.line_profiles.false_ridge_pixels`).
        A blob of the lines' colour much wider than the lines leaving it (a
        neuron's soma, a coral's centre, a crater) is a hub, beyond the paper: it
        is no tangle of spurs but spokes from its centre to its lines, and the
        default root rule roots the piece there (:mod:`~branchnb.branching.hubs`).
        Lines much wider than the filter's scales (a painted root system's 20 px
        trunk, a wide river, a vessel at high resolution), whose flat interior
        the filter does not see, are found against the image itself, beyond
        the paper: uniformly dark (bright) across, elongated, of one piece with
        the fine lines (:func:`~branchnb.branching.wide_lines.wide_line_mask`);
        they join the ridge mask, their axis runs on to the frame where they
        enter, their radius is their own half width.
        Lines painted in one solid colour on a ground that is not (roots on
        soil, smooth or grained) are traced by that colour's shape, and lines
        painted with the ground's own grain (no solid colour) by their tone
        smoothed at the grain's scale
        (:func:`~branchnb.branching.textured_paint.textured_line_shape`), not by
        the filter, which would trace every grain (beyond the paper, issue 23).
        Lines of about their ground's luminance that differ in hue (a
        blue-grey river over green and tan fields seen from the air, whose
        luminance steps the filter would trace instead) are traced on the
        opponent-colour channel that sets them apart, beyond the paper
        (:func:`~branchnb.branching.colour_contrast.colour_contrast_gray`).
    mask : (H, W) bool array_like, optional
        Only look inside this region.
    return_maps : bool, default False
        Also return ``(response, ridge mask, skeleton)`` at the working scale.
    line_colour : "auto", None or (r, g, b), default "auto"
        Trace lines of this colour (in [0, 1]) instead of brightness
        ridges: the ridge filter runs on :func:`line_colour_map`, how much
        each pixel has that colour rather than its surroundings'. "auto"
        looks for a coloured thin-line colour (:func:`thin_line_colour`,
        e.g. the blue rivers of a map over a grey relief, which
        brightness alone confuses with the relief's edges), and when there
        is none, for lines set apart by hue (see above); None does neither. The colour of an annotation can be read with
        :func:`line_colour_of`.
    **overrides
        Fields of :class:`ExtractionParams` replacing those of ``params``
        (e.g. ``min_component_length=20``, ``root=(x, y)``).

    Returns
    -------
    Structure
        With ``image_shape`` set to the image's ``(H, W)``; with
        ``return_maps`` the pair ``(structure, (response, ridge mask,
        skeleton))``.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((80, 120)); img[38:43, 5:115] = 0; img[5:40, 58:62] = 0
    >>> s = extract_structure(img, min_component_length=20)
    >>> len(s.branches), s.branches[1].parent
    (2, 0)
    """
    import dataclasses

    from skimage.morphology import remove_small_objects, skeletonize
    from skimage.transform import rescale, resize

    p = params if params is not None else ExtractionParams()
    root_point = None
    if "root" in overrides and not isinstance(overrides["root"], str):
        # root=(x, y): each piece's root is its end point nearest to that point
        root_point = tuple(float(v) for v in np.asarray(overrides.pop("root"), np.float64).reshape(2))
        if not all(np.isfinite(root_point)):
            raise ValueError(f"root point must be finite (x, y), got {root_point}")
    if overrides:
        unknown = set(overrides) - {f.name for f in dataclasses.fields(p)}
        if unknown:
            raise TypeError(f"unknown extraction parameter(s): {sorted(unknown)}")
        p = dataclasses.replace(p, **overrides)
    check_params(p)
    gray = gray_for_extraction(image)
    hatched_sea = None
    if line_colour is None or isinstance(line_colour, str):
        # an engraved map's sea is parallel hatching, not rivers: erased to the paper (.hatched_seas)
        from .hatched_seas import erase_hatched_sea

        erased_image, erased_gray, hatched_sea = erase_hatched_sea(image, gray)
        if hatched_sea is not None:
            # its coast is then the outline of the sea (taken out by the ridge route's outline test against
            # the sea's mask: the land's paper is the sea's, no colour tells them apart); the binary route
            # would trace it as a line
            image, gray = erased_image, erased_gray
            if p.binary == "auto":
                p = dataclasses.replace(p, binary="off")
    colour_image = image          # the region colours, before any ink map replaces the image below
    if p.binary == "auto" and (line_colour is None or isinstance(line_colour, str)):
        # strokes of several colours on one plain paper (a black stroke with a coloured inner line):
        # traced by the medial axis of all the ink, not along one of its dark edges (beyond the paper)
        ink = multi_colour_ink(image)
        if ink is not None:
            gray = image = ink
    if p.binary != "off" and is_binary(gray):
        # strokes drawn as two outline lines with the paper between them: traced once, along the centre
        rgb = as_rgb(image) if np.ndim(image) == 3 else None
        filled, n_filled = fill_outlined_strokes(gray, colour=rgb if rgb is not None and rgb.shape[:2] ==
                                                 np.shape(gray) else None)
        if n_filled:
            gray = image = filled
    auto_colour = isinstance(line_colour, str) and line_colour == "auto"
    hue = None
    shape_width = None
    if auto_colour and p.binary != "on":
        line_colour, shape_width = _line_colour_and_width(image, sigma_max=p.sigma_max)
        if shape_width is not None and shape_width >= 3.0:
            # a drawn tree wider than the ridge filter's scales (beyond the paper): trace the colour's own
            # shape by its medial axis; its crown and ground are other colours, not a binary mask's background
            shape = np.abs(as_rgb(image)[..., :3] - line_colour).max(-1) <= 0.12
            # a thin line drawn across it (a ground line over the trunk) does not cut it in two; a closing
            # of the whole shape also merged roots running 1-4 px apart into blobs (recall 0.75 on a
            # painted root system at 640 px) and joined grain specks to them: only cuts between large
            # pieces are bridged
            shape = _bridge_cuts(shape, 5, min_area=4.0 * shape_width ** 2)
            # painted on a textured ground (a root system on soil) its lines run on past the frame: their
            # medial axis reaches it (a crown cut by the top edge enters there, see _frame_entries)
            return _extract_binary(np.where(shape, 0.0, 1.0), dataclasses.replace(p, polarity="dark"), mask,
                                   return_maps, root_point, flat_regions=False,
                                   frame_reach=not _is_drawn(as_gray(as_rgb(image)[..., :3])),
                                   close_cycles=p.close_cycles)
        if line_colour is None and shape_width is None and p.binary != "on":
            # a line of about its ground's luminance that differs in hue (a river over fields seen from the
            # air): traced on the opponent-colour channel that separates it best (beyond the paper, issue 23);
            # checked first, as a patchwork of fields would pass for lines painted with the ground's grain
            from .colour_contrast import colour_contrast_gray

            hue = colour_contrast_gray(image)
        if hue is None and line_colour is None and shape_width is None and \
                not _is_drawn(as_gray(as_rgb(image)[..., :3])):
            # lines painted with the ground's own grain (roots given the soil's texture): no solid colour, and
            # the ridge filter would trace every grain; their tone, smoothed at the grain's scale, still is
            # a branching shape of its own (beyond the paper, issue 23). Its cycles stay cut: closing them
            # took recall 0.90 -> 0.92 but the branch count from 1.6 to 2.5 times the painted roots'
            from .textured_paint import textured_line_shape

            shape = textured_line_shape(image, p.sigma_max)
            if shape is not None:
                return _extract_binary(np.where(shape, 0.0, 1.0), dataclasses.replace(p, polarity="dark"), mask,
                                       return_maps, root_point, flat_regions=False, frame_reach=True)
    if p.binary == "on" or (p.binary == "auto" and shape_width is None and is_binary(gray)):
        return _extract_binary(gray, p, mask, return_maps, root_point, colour=colour_image)
    if p.binary == "auto" and shape_width is None and hue is None and hatched_sea is None:
        # one solid ink on a smooth shaded ground (a winter tree against the sky): binary once the shading is
        # gone, and traced by its medial axis (the ridge filter broke a trunk from its twigs, .smooth_ground)
        from .smooth_ground import flattened_silhouette

        flat = flattened_silhouette(as_rgb(image)[..., :3] if np.ndim(image) == 3 else gray)
        if flat is not None:
            # (no drawn regions: a shaded sky's many colours would read as region borders cutting the lines;
            # no flat regions: one solid ink is lines, and a small tree's short trunk, 3 x its twigs' width and
            # over 1 % of a 128 px image, was taken for a sea and cut off, rooting the crown inland, issue 23)
            return _extract_binary(flat, dataclasses.replace(p, polarity="dark"), mask, return_maps, root_point,
                                   flat_regions=False)
    if hue is not None:
        gray = hue
    lines = gray
    if line_colour is not None:
        if isinstance(line_colour, str):
            if line_colour != "auto":
                raise ValueError(f"line_colour must be 'auto', None or an (r, g, b) colour, got {line_colour!r}")
            line_colour = thin_line_colour(image, sigma_max=p.sigma_max)
        else:
            try:
                c = np.asarray(line_colour, np.float64).ravel()
            except (TypeError, ValueError):
                raise TypeError(f"line_colour must be 'auto', None or an (r, g, b) colour, got {line_colour!r}") \
                    from None
            if c.shape != (3,) or not np.all(np.isfinite(c)) or c.min() < 0 or c.max() > 1:
                raise ValueError(f"line_colour must be an (r, g, b) colour in [0, 1], got {line_colour!r}")
            line_colour = c
        if line_colour is not None:
            # bright where the pixel has the line colour: the ridge filter sees only those lines
            lines = line_colour_map(image, line_colour, sigma_max=p.sigma_max)
            # no texture in that map: weak ridges (a 1 px river blended into a grey) still count
            p = dataclasses.replace(p, polarity="bright", hysteresis=min(p.hysteresis, 0.25))
    resp, _pol = ridge_response(lines, p)
    if mask is not None:
        from ..core.image import as_mask

        m = as_mask(mask, shape=gray.shape)
        if resp.shape != m.shape:
            m = resize(m.astype(np.float32), resp.shape, order=0) > 0.5
        resp = np.where(m, resp, 0).astype(np.float32)
    bw = ridge_mask(resp, p.threshold, p.hysteresis)
    min_area = max(4, int((p.min_component_length * p.scale) * 2))
    bw = bw & ~frame_lines(bw, band=int(np.ceil(3 * p.sigma_max)) + 3)
    bw = remove_small_objects(bw, max_size=min_area) if _rso_has_max_size() else \
        remove_small_objects(bw, min_size=min_area)
    work = rescale(gray, p.scale, anti_aliasing=True) if p.scale < 1 else gray
    # lines wider than the filter's scales (a 20 px trunk): the filter misses their flat interior; found
    # against the image itself (uniformly dark across), added to the mask (beyond the paper, issue 23)
    wide = wide_line_mask(work, bw, _pol, p.sigma_max) if lines is gray else np.zeros_like(bw)
    if wide.any() and np.ndim(colour_image) == 3:
        # a sea strait between two drawn coasts is an arm of the sea, no wide river (.wide_lines.region_arms)
        rgb_w = as_rgb(colour_image)
        rgb_w = rgb_w if rgb_w.shape[:2] == wide.shape else resize(rgb_w, wide.shape + (rgb_w.shape[2],))
        wide &= ~region_arms(wide, rgb_w)
    near_wide = wide
    if wide.any():
        near_wide = ndi.binary_dilation(wide, iterations=int(np.ceil(2 * p.sigma_max)))
        bw = bw | wide
        # the filter's two edge rails along a wide line leave slivers between them and its core (thin
        # holes only: the cells a crack network closes round a wide stretch are ground, not line)
        holes = ndi.binary_fill_holes(bw) & ~bw & near_wide
        if holes.any():
            lab, n = ndi.label(holes)
            depth = ndi.maximum(ndi.distance_transform_edt(holes), lab, np.arange(1, n + 1))
            bw |= np.isin(lab, 1 + np.flatnonzero(np.asarray(depth) <= p.sigma_max))
    skel = skeletonize(bw)
    if wide.any():
        # a wide line cut by the frame: its axis runs on to the frame (the root starts where it enters)
        skel = frame_reaching_skeleton(bw, skel, near_wide)
    # a wide line's axis is checked against the image already: the outline and false-ridge tests below
    # measure across a few sigma_max and take its flat interior for a flat region or an edge
    wide_axis = skel & near_wide if wide.any() else None
    outside = border_flat_regions(work, 4 * p.sigma_max, branches=bw)
    skel &= ~outline_pixels(skel, outside, 2 * p.sigma_max + 2, gray=ndi.median_filter(work, 3))
    if hatched_sea is not None:
        sea_w = hatched_sea if hatched_sea.shape == skel.shape else \
            resize(hatched_sea.astype(np.float32), skel.shape, order=0) > 0.5
        skel &= ~outline_pixels(skel, sea_w, 2 * p.sigma_max + 2)
        # the coast's outline was taken out up to that reach: a river cut there ran on to the coast
        shore = ndi.distance_transform_edt(~sea_w) <= 2 * p.sigma_max + 2
    else:
        sea_w = shore = None
    rgb = as_rgb(colour_image)
    if rgb.shape[:2] != skel.shape:
        rgb = rescale(rgb, p.scale, anti_aliasing=True, channel_axis=-1)
    # a drawn border between two inside regions of different colours (two countries) is no branch either
    if rgb.shape[:2] == skel.shape:
        skel &= ~region_border_pixels(skel, rgb, 4 * p.sigma_max, reach=2 * p.sigma_max + 4)
    if p.false_ridges and skel.any():
        from .line_profiles import false_ridge_pixels

        before_false = skel.copy()

        if lines is not gray:
            # a line colour traced on a photo: the edge between a darker and a lighter field has a little
            # of the line colour on its darker side only, and the hysteresis joins those edges to the
            # lines (a grid of field edges hanging off a river). A line has its colour against both sides
            lines_w = rescale(lines, p.scale, anti_aliasing=True) if p.scale < 1 else lines
            skel &= ~false_ridge_pixels(lines_w, skel, "bright", sigma_min=p.sigma_min, sigma_max=p.sigma_max,
                                        dotted=np.inf, beads=0.0)
        elif np.median((work - ndi.gaussian_filter(work, 3 * p.sigma_max))[skel]) > 0:
            # photographs: edges of lit regions and rows of separate lights are no lines (beyond the paper);
            # only where the traced lines are brighter than their ground (the filter's polarity may say
            # otherwise)
            # (a small example's bright lines on a dark ground, a bolt: its skeleton cuts across its zigzags,
            # read across by 1 px; a 128 px fundus photo's extraction moved with it, so only there)
            bolt = max(np.shape(gray)[:2]) <= SMALL_SIDE and \
                float(np.median(work[skel]) - np.median(work)) > 0.25
            skel &= ~false_ridge_pixels(work, skel, "bright", sigma_min=p.sigma_min, sigma_max=p.sigma_max,
                                        dot_reach=1.0 if bolt else 0.0)
        else:
            # dark lines: the step between a darker and a lighter field (a photo's fields, tiles, shading) is
            # no line either, it is as dark as its darker side; only that test (a crack's darkness is
            # intermittent, a dotted test would cut it)
            skel &= ~false_ridge_pixels(work, skel, "dark", sigma_min=p.sigma_min, sigma_max=p.sigma_max,
                                        dotted=np.inf, beads=0.0, local=2.0 * p.sigma_max)
        # a thin side branch cut off its frame-entering line where it leaves it (the stretch beside the
        # trunk reads one-sided) is linked back: rooted inside, it grew trees away from the entry
        skel = relink_fragments(skel, before_false & ~skel, p.min_component_length * p.scale)
    if wide_axis is not None:
        skel |= wide_axis
    # small examples: a line leaving the frame is traced up to it (its axis stops a width short of it)
    if max(np.shape(gray)[:2]) <= SMALL_SIDE:
        skel = _reach_frame(skel, bw)
    if p.radius == "fwhm":
        lines_w = rescale(lines, p.scale, anti_aliasing=True) if p.scale < 1 and lines is not gray else \
            (work if lines is gray else lines)
        radius = half_contrast_radius(lines_w, skel, _pol, p.sigma_max)
    else:
        radius = ndi.distance_transform_edt(bw) - 0.5
    if wide.any():
        # the half-contrast top-hat is no wider than the filter's lines: a wide line's own width counts
        radius = np.where(near_wide, np.maximum(radius, ndi.distance_transform_edt(bw) - 0.5), radius)
    # a blob of the lines' colour much wider than they are (a soma, a crater) is a hub: a region, not spurs
    blob_src = work if lines is gray else (rescale(lines, p.scale, anti_aliasing=True) if p.scale < 1 else lines)
    con = blob_contrast(blob_src, skel, _pol if lines is gray else "bright")
    hubs = find_hubs(con >= 0.5, skel, radius, con)
    if hubs:
        skel, radius = hub_skeleton(skel, radius, hubs)
    region = None
    root = p.root
    if root in ("nearest_region", "auto"):
        # an engraved map's land has the sea's paper: its hatched sea is the region its rivers drain to
        region = flat_background(work, bw, 4 * p.sigma_max) if sea_w is None else sea_w
    joins = find_stroke_joins(skel, radius, bw, max_gap=p.join_gaps, scale=p.scale)
    s = skeleton_to_structure(skel, radius, h=p.h, min_branch_length=p.min_branch_length,
                              min_component_length=p.min_component_length,
                              root=root if root_point is None else root_point,
                              scale=p.scale, smooth=p.smooth_path, smooth_radius=p.smooth_radius,
                              image_shape=gray.shape[:2], region=region, joins=joins,
                              close_cycles=p.close_cycles, hubs=[h.centre for h in hubs], shore=shore)
    if p.centre_reach > 0 and s.branches:
        from .centring import centre_on_lines

        s = centre_on_lines(lines, s, _pol, p.centre_reach)
    _carry_hubs(s, hubs, p.scale)
    if max(np.shape(gray)[:2]) <= SMALL_SIDE:
        # a line traced up to the frame (_reach_frame) may be centred or smoothed a fraction past it
        hh, ww = np.shape(gray)[:2]
        for b in s.branches:
            b.points = np.clip(b.points, 0.0, [ww - 1.0, hh - 1.0])
    if return_maps:
        return s, (resp, bw, skel)
    return s



def _bridge_cuts(shape: np.ndarray, size: int, min_area: float) -> np.ndarray:
    """``shape`` with the gaps a ``size`` x ``size`` closing fills added only where they join two or more
    8-connected pieces of ``shape`` of at least ``min_area`` pixels each (beyond the paper).

    A thin line drawn across a wide stroke (a ground line over a trunk) cuts it into two large pieces the
    closing joins again; the gaps between two lines of one network running close together (a painted
    root system's tangle), or between a line and a speck of ground of its colour, join nothing: they stay.
    """
    closed = ndi.binary_closing(shape, np.ones((size, size), bool))
    new = closed & ~shape
    if not new.any():
        return shape
    eight = np.ones((3, 3), bool)
    lab, n = ndi.label(shape, eight)
    big = np.bincount(lab.ravel(), minlength=n + 1) >= min_area
    big[0] = False
    gap, n_gap = ndi.label(new, eight)
    ys, xs = np.nonzero(new)
    padded = np.pad(lab, 1)
    pairs = []
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            nb = padded[ys + 1 + dy, xs + 1 + dx]
            k = big[nb]
            pairs.append(np.c_[gap[ys[k], xs[k]], nb[k]])
    pairs = np.unique(np.vstack(pairs), axis=0)
    joins = np.bincount(pairs[:, 0], minlength=n_gap + 1) >= 2
    joins[0] = False
    return shape | joins[gap]


def _region_colours(image, share: float = 0.01) -> int:
    """How many colours (quantised to 1/20) each cover more than ``share`` of ``image``."""
    q = np.round(as_rgb(image)[::2, ::2] * 20).astype(np.int16).reshape(-1, 3)
    _, counts = np.unique(q, axis=0, return_counts=True)
    return int((counts > share * len(q)).sum())


def _extract_binary(gray, p: ExtractionParams, mask, return_maps: bool, root_point=None, flat_regions: bool = True,
                    colour=None, frame_reach: bool = False, close_cycles: float = 0.0):
    """``extract_structure`` for a binary mask: medial axis + distance-transform radius (``colour``: the
    colour image, whose drawn region borders are taken out, see ``region_border_pixels``; ``close_cycles``:
    see :class:`ExtractionParams`, off for a mask's braids, on for lines painted on a ground, whose cycles are
    roots crossing: the cut edge of each was dropped whole, recall 0.89 on a 256 px root painting).

    Braided channels form cycles; the shortest-path tree from each root
    cuts every cycle once, where the two fronts meet (see
    :func:`skeleton_to_structure`).
    """
    from skimage.morphology import skeletonize
    from skimage.transform import rescale

    work = rescale(gray, p.scale, order=0, anti_aliasing=False) if p.scale < 1 else gray
    pol = p.polarity
    channels, region, skel, radius = binary_channels(work, pol, flat_regions=flat_regions)
    if frame_reach and channels.any():
        # lines cut by the frame continue beyond it (edge rows repeated), so the medial axis runs on to it
        # (the skeleton of a wide crown cut by the frame otherwise stops a radius or more short of it)
        pad = int(np.ceil(2.0 * float(radius[skel].max()))) + 2 if skel.any() else 2
        full = skeletonize(np.pad(channels, pad, mode="edge"))
        skel = full[pad:-pad, pad:-pad] & channels
        # the frame row holds only where the axis goes on outside (a crown's V whose apex touches the frame
        # is an end there, not a bend): the ring just outside the frame, moved onto it
        o = full[pad - 1:full.shape[0] - pad + 1, pad - 1:full.shape[1] - pad + 1]
        skel[0], skel[-1] = o[0, 1:-1] & channels[0], o[-1, 1:-1] & channels[-1]
        skel[:, 0], skel[:, -1] = o[1:-1, 0] & channels[:, 0], o[1:-1, -1] & channels[:, -1]
    if region.any():
        channels, region, skel = _hub_regions(channels, region, skel, radius)
    if colour is not None and np.ndim(colour) == 3 and _region_colours(colour) >= 3:
        # black lines on a map of two near-equal greys (a crop with no sea) read as binary: a drawn border
        # between two regions of different colours is still no branch. A true two-colour mask (a delta's
        # water and land) has no such regions: its channels beside the sea would be taken for borders.
        rgb = as_rgb(colour)
        if rgb.shape[:2] != skel.shape:
            rgb = rescale(rgb, p.scale, anti_aliasing=True, channel_axis=-1)
        if rgb.shape[:2] == skel.shape:
            skel &= ~region_border_pixels(skel, rgb, 4 * p.sigma_max, reach=2 * p.sigma_max + 4)
    if mask is not None:
        from skimage.transform import resize

        from ..core.image import as_mask

        m = as_mask(mask, shape=gray.shape)
        if m.shape != skel.shape:
            m = resize(m.astype(np.float32), skel.shape, order=0) > 0.5
        skel &= m
    hubs = find_hubs(channels, skel, radius)
    if hubs:
        skel, radius = hub_skeleton(skel, radius, hubs)
    root = p.root if root_point is None else root_point
    joins = find_stroke_joins(skel, radius, channels, max_gap=p.join_gaps, scale=p.scale)
    s = skeleton_to_structure(skel, radius, h=p.h, min_branch_length=p.min_branch_length,
                              min_component_length=p.min_component_length, root=root,
                              scale=p.scale, smooth=p.smooth_path, smooth_radius=p.smooth_radius,
                              image_shape=gray.shape[:2], region=region, joins=joins,
                              close_cycles=close_cycles,   # (a mask's braids stay cut: ExtractionParams.close_cycles)
                              hubs=[h.centre for h in hubs])
    s = _unpinch_frame_ends(s, gray.shape[:2])
    _carry_hubs(s, hubs, p.scale)
    if return_maps:
        return s, (channels.astype(np.float32), channels, skel)
    return s



def _carry_hubs(s, hubs, scale: float) -> None:
    """Put the hubs on the structure as ``s.hubs = [(x, y, radius), ...]`` (full-size pixels) for
    radial synthesis (:mod:`.radial`); a structure without hubs gets no attribute."""
    if hubs:
        s.hubs = [(float(h.centre[1]) / scale, float(h.centre[0]) / scale, float(h.radius) / scale)
                  for h in hubs]


def _hub_regions(channels: np.ndarray, region: np.ndarray, skel: np.ndarray, radius: np.ndarray):
    """``(channels, region, skel)`` with the flat regions that are hubs (round, off the frame, three or
    more channels leaving them: a big soma, a coral's centre; :func:`~branchnb.branching.hubs.find_hubs`)
    given back to the channels: a sea roots its rivers at its edge, a hub roots one tree at its centre."""
    from skimage.morphology import skeletonize

    whole = channels | region
    lab, _n = ndi.label(region)
    back = np.zeros_like(region)
    for hub in find_hubs(whole, skeletonize(whole), radius):
        k = lab[hub.centre]
        if k:
            back |= lab == k
    if not back.any():
        return channels, region, skel
    channels, region = channels | back, region & ~back
    skel = skeletonize(channels)
    if region.any():
        skel &= ndi.distance_transform_edt(~region) > 1.5
    return channels, region, skel


def _straight_frame_end(pts: np.ndarray, k: int, shape) -> np.ndarray:
    """``pts[:k]`` (the end at the frame) replaced by the straight continuation of the branch behind
    ``pts[k]`` back to the frame, with as many points (the branch's vertex indices stay valid)."""
    h, w = shape
    arc = arc_length(pts)
    k2 = int(np.clip(np.searchsorted(arc, arc[k] + max(arc[k], 6.0)), k + 1, len(pts) - 1))
    d = pts[k] - pts[k2]
    n = float(np.hypot(*d))
    if n < 1e-9:
        return pts
    d = d / n
    # distance from pts[k] along d to the frame (the nearest side crossed), at most twice the old end
    ts = [((0.0 if d[i] < 0 else (w - 1.0, h - 1.0)[i]) - pts[k, i]) / d[i] for i in (0, 1) if abs(d[i]) > 1e-9]
    t = min(min(v for v in ts if v >= 0.0) if any(v >= 0.0 for v in ts) else 0.0, 2.0 * arc[k])
    f = np.linspace(1.0, 0.0, k + 1)[:-1, None]
    out = pts.copy()
    out[:k] = pts[k] + f * t * d
    out[:k, 0] = np.clip(out[:k, 0], 0.0, w - 1.0)
    out[:k, 1] = np.clip(out[:k, 1], 0.0, h - 1.0)
    return out



def _unpinch_frame_ends(s: Structure, shape) -> Structure:
    """A channel cut by the frame: its medial axis bends into a corner of the cut, where the distance
    transform is small, so the branch would start several times thinner than it is. Its radius
    there is the one two radii inward (a delta's trunk entering from inland keeps its width).

    The bent end also sets the branch's heading: a root would leave the frame at up to 60 degrees
    off the channel (the synthesized trunk then runs along the frame). A root's end at the frame is
    therefore the straight continuation of the channel from two radii inward; likewise a tip that
    ends at the frame when no child starts on that stretch."""
    h, w = shape
    out = []
    kids: dict[int, list[int]] = {}
    for b in s.branches:
        if b.parent is not None:
            kids.setdefault(int(b.parent), []).append(int(b.parent_vertex))

    def end_k(pts, r):
        arc = arc_length(pts)
        return int(np.clip(np.searchsorted(arc, 2.0 * r.max() if len(r) < 4 else 2.0 * np.median(r[:8])),
                           1, len(r) - 1))

    def at_frame(p):
        return min(p[0], p[1], w - 1 - p[0], h - 1 - p[1]) <= 6.0

    for i, b in enumerate(s.branches):
        if len(b.points) < 3:
            out.append(b)
            continue
        pts, r = b.points.copy(), b.thickness.copy()
        if at_frame(pts[0]):
            k = end_k(pts, r)
            r[:k] = np.maximum(r[:k], r[k])
            if b.parent is None and k < len(pts) - 1 and all(v > k for v in kids.get(i, [])):
                pts = _straight_frame_end(pts, k, shape)
        if at_frame(pts[-1]) and len(pts) >= 4:
            k = end_k(pts[::-1], r[::-1])
            n = len(pts)
            if k < n - 1 and all(v < n - 1 - k for v in kids.get(i, [])):
                pts = _straight_frame_end(pts[::-1], k, shape)[::-1].copy()
        out.append(Branch(pts, r, b.parent, b.parent_vertex))
    return Structure(out, image_shape=s.image_shape)



def _rso_has_max_size() -> bool:
    import inspect

    from skimage.morphology import remove_small_objects

    return "max_size" in inspect.signature(remove_small_objects).parameters
