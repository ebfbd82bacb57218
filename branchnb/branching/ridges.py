"""Automatic extraction, step 1 (beyond the paper): ridge response, ridge mask, line colour, radius.

A ridge / vesselness filter (scikit-image ``sato``, ``frangi`` or
``meijering``) on the luminance, or on how much each pixel has a thin-line
colour (the blue rivers of a map), then hysteresis thresholding; the
branch radius from the half-contrast (FWHM) width.

Split from :mod:`.extraction` (which re-exports every name).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.distance import edt
from ..core.image import as_gray, as_rgb
from ..core.params import check_params
from ..core.polyline import resample_uniform
from ..core.structure import Branch, Structure  # noqa: F401  (Branch: used by the examples)
from .backgrounds import border_flat_regions, outline_pixels
from .clicks import gray_for_extraction
from .params import ExtractionParams

__all__ = [
    "ridge_response",
    "ridge_mask",
    "half_contrast_radius",
    "thin_line_colour",
    "line_colour_of",
    "line_colour_map",
]


# --------------------------------------------------------------------------
# Automatic extraction (beyond the paper)
# --------------------------------------------------------------------------
def _polarity(gray: np.ndarray, polarity: str, sigma: float) -> str:
    if polarity != "auto":
        return polarity
    res = gray - ndi.gaussian_filter(gray, max(4.0, 4 * sigma))
    res = res - res.mean()
    sd = res.std()
    if sd == 0:
        return "dark"
    skew = float(np.mean(res ** 3) / sd ** 3)
    # Thin bright structures on a dark background give a long bright tail.
    return "bright" if skew > 0 else "dark"


def _outside_field_of_view(gray: np.ndarray, margin: float, sigma_max: float) -> np.ndarray:
    """Large near-black regions (outside a circular fundus view) plus a margin.

    Only regions of at least 1 % of the image that are much thicker than
    any ridge the filter looks for (inner radius > 4 sigma_max) count, so
    thin black branches on a light background are kept.
    """
    dark = gray < 0.04
    if dark.mean() < 0.01:
        return np.zeros_like(dark)
    lab, _ = ndi.label(dark)
    sizes = np.bincount(lab.ravel())
    sizes[0] = 0
    thick = np.zeros(len(sizes))
    dt = edt(dark)
    np.maximum.at(thick, lab.ravel(), dt.ravel())
    big = (sizes >= 0.01 * gray.size) & (thick > 4 * sigma_max)
    big[0] = False
    out = big[lab]
    if out.any() and margin > 0:
        out = edt(~out) <= margin
    return out


def ridge_response(image, params: ExtractionParams | None = None) -> tuple[np.ndarray, str]:
    """Normalised ridge / vesselness response in [0, 1] and the polarity used.

    Parameters
    ----------
    image : array_like
        Grey, RGB or RGBA (composited over white).
    params : ExtractionParams, optional
        ``filter``, ``polarity``, ``sigma_min`` .. ``sigma_max``, ``scale``.

    Returns
    -------
    response : (H', W') float32
        At the working scale ``params.scale``.
    polarity : {"dark", "bright"}
    """
    from skimage import filters
    from skimage.transform import rescale

    p = check_params(params if params is not None else ExtractionParams())
    if p.sigma_max < p.sigma_min:
        raise ValueError(f"params.sigma_max ({p.sigma_max}) must be >= sigma_min ({p.sigma_min})")
    # float32: scikit-image's Hessians follow the input's precision; float64 took 1.5-1.8x as long on
    # 1-2 MP photos for responses within 3e-7 of each other (same structures on the samples)
    gray = gray_for_extraction(image).astype(np.float32)
    if p.scale < 1:
        gray = rescale(gray, p.scale, anti_aliasing=True)
    pol = _polarity(gray, p.polarity, p.sigma_max)
    n_s = max(2, int(np.ceil(p.sigma_max - p.sigma_min)) + 1)
    sigmas = np.linspace(p.sigma_min, p.sigma_max, n_s)
    fn = {"sato": filters.sato, "frangi": filters.frangi, "meijering": filters.meijering}[p.filter]
    resp = fn(gray, sigmas=sigmas, black_ridges=(pol == "dark"))
    if pol == "dark":
        resp[_outside_field_of_view(gray, 2.5 * p.sigma_max + 2, p.sigma_max)] = 0
    resp[: 1] = resp[-1:] = 0
    resp[:, :1] = resp[:, -1:] = 0
    top = np.percentile(resp, 99.9)
    if top <= 0:
        return np.zeros(gray.shape, np.float32), pol
    return np.clip(resp / top, 0, 1).astype(np.float32), pol


def ridge_mask(response: np.ndarray, threshold: float = 0.0, hysteresis: float = 0.5) -> np.ndarray:
    """Hysteresis threshold of a ridge response (``threshold = 0``: Otsu).

    Parameters
    ----------
    response : (H, W) array_like
        Ridge / vesselness filter response.
    threshold : float, default 0.0
        High threshold on the response; 0 = Otsu's threshold.
    hysteresis : float, default 0.5
        Low threshold = ``hysteresis * threshold``: weaker pixels connected
        to strong ones are kept.

    Returns
    -------
    (H, W) bool ndarray
        The ridge mask (empty for a constant response).

    Raises
    ------
    ValueError
        If ``response`` is not 2-D.

    Examples
    --------
    >>> import numpy as np
    >>> r = np.zeros((5, 7)); r[2, 1:6] = [0.5, 0.6, 1.0, 0.6, 0.2]
    >>> ridge_mask(r, threshold=0.8)[2].astype(int).tolist()
    [0, 1, 1, 1, 1, 0, 0]
    """
    from skimage.filters import apply_hysteresis_threshold, threshold_otsu

    r = np.asarray(response, np.float64)
    if r.ndim != 2:
        raise ValueError(f"response must be 2-D, got shape {r.shape}")
    if threshold <= 0:
        if r.max() <= r.min():
            return np.zeros(r.shape, bool)
        threshold = float(threshold_otsu(r))
    return apply_hysteresis_threshold(r, hysteresis * threshold, threshold)


def half_contrast_radius(gray, skeleton, polarity: str, sigma_max: float) -> np.ndarray:
    """Branch radius map: distance transform of the half-contrast (FWHM) mask.

    The local contrast is the morphological top-hat (black top-hat for
    dark branches, white for bright ones) with a disk wider than any
    branch the filter looks for. A pixel belongs to a branch if its
    contrast is at least half the contrast on the nearest skeleton pixel
    (the full width at half maximum, the usual vessel calibre), and the
    radius is the distance transform of that mask minus half a pixel.
    Unlike the thresholded ridge response, whose width follows the filter
    scale, this measures the branch itself.

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1] (:func:`gray_for_extraction`).
    skeleton : (H, W) bool array_like
        Centre lines of the branches.
    polarity : {"dark", "bright"}
        Branches darker or brighter than the background.
    sigma_max : float
        Largest filter scale (pixels); sets the top-hat disk (radius
        2 sigma_max + 1).

    Returns
    -------
    (H, W) float ndarray
        Radius (pixels) of the half-contrast mask at every pixel.
    """
    import cv2

    g = np.asarray(gray, np.float32)
    sk = np.asarray(skeleton, bool)
    rad = int(np.ceil(2 * sigma_max)) + 1
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * rad + 1, 2 * rad + 1))
    if polarity == "dark":
        th = cv2.morphologyEx(g, cv2.MORPH_CLOSE, disk, borderType=cv2.BORDER_REFLECT) - g
    else:
        th = g - cv2.morphologyEx(g, cv2.MORPH_OPEN, disk, borderType=cv2.BORDER_REFLECT)
    if not sk.any():
        return np.zeros(g.shape)
    peak = ndi.maximum_filter(th, 3)
    dist, (iy, ix) = ndi.distance_transform_edt(~sk, return_indices=True)
    ref = peak[iy, ix]
    mask = ((th >= 0.5 * ref) & (ref > 0) & (dist <= rad)) | sk
    return ndi.distance_transform_edt(mask) - 0.5


def _local_background(rgb: np.ndarray, sigma_max: float) -> np.ndarray:
    """Per-channel median over a window wider than any line: the colour around a line, edges kept."""
    import cv2

    k = 2 * int(np.ceil(2 * sigma_max)) + 1
    u8 = np.clip(np.rint(rgb * 255.0), 0, 255).astype(np.uint8)
    return cv2.medianBlur(np.ascontiguousarray(u8), min(k, 255)).astype(np.float32) / 255.0


def _off_outline(has: np.ndarray, outline: np.ndarray) -> np.ndarray:
    """``has`` without its outline pixels and without the rest of any piece that is mostly outline.

    Beyond the paper. A country border drawn in a line colour is found as
    outline only where the outside region comes within reach of it; where
    the border bulges away from the frame (or the image was scaled down, so
    the outside's margin is relatively wider) stretches of it are left over
    and outnumber thin rivers of another colour. A piece (8-connected) of
    the colour at least half of which is outline is the border as a whole.
    """
    rest = has & ~outline
    if not outline.any():
        return rest
    lab, n = ndi.label(has, np.ones((3, 3), bool))
    tot = np.bincount(lab.ravel(), minlength=n + 1)
    on = np.bincount(lab[outline], minlength=n + 1)
    border = (on >= 0.5 * np.maximum(tot, 1)) & (np.arange(n + 1) > 0)
    return rest & ~border[lab]


#: A colour is painted solid on a textured ground when at least this share of its pixels has that exact
#: colour in all of its 3 x 3 neighbours while at most :data:`SOLID_GROUND` of the other pixels do.
SOLID_LINES = 0.3
SOLID_GROUND = 0.02
#: ... or at most a tenth of the lines' share, up to this (flat pebbles on a grainy soil).
SOLID_GROUND_MAX = 0.05
#: On a ground smooth enough to pass for a drawing, at least this share of a solid paint's pixels are
#: line-like (contrast to their local median): roots on a smooth soil 0.18-0.67, a photo's black surround 0.
DRAWN_LINE_LIKE = 0.1
#: Lines painted solid on a textured ground may be this many separate pieces (root systems side by side).
PAINTED_PIECES = 3


def _is_drawn(gray: np.ndarray) -> bool:
    """Whether at least half of a picture is flat (a drawing, not a photograph or a textured ground)."""
    flat = (ndi.maximum_filter(gray, 5) - ndi.minimum_filter(gray, 5)) < 0.03
    return bool(flat.mean() >= 0.5)


def _solid_on_texture(solid: np.ndarray, has: np.ndarray) -> bool:
    """Whether the pixels ``has`` are a solid paint (:data:`SOLID_LINES`) on a ground that is not.

    The ground may hold a little solid paint of its own: pebbles painted flat on a grainy soil cover
    3 % of a 1024 px root painting (2 % at most before, which sent it to the ridge filter: its grain
    traced as short branches, precision 0.86). Up to a tenth of the lines' own solid share (at most
    :data:`SOLID_GROUND_MAX`) the ground still counts as textured (beyond the paper).
    """
    if not has.any() or has.all():
        return False
    lines = float(np.mean(solid[has]))
    ground = float(np.mean(solid[~has]))
    return bool(lines >= SOLID_LINES and ground <= max(SOLID_GROUND, min(SOLID_GROUND_MAX, 0.1 * lines)))


def _drawn_branching_width(has: np.ndarray, sigma_max: float, pieces: int = 1) -> float | None:
    """Mean width of a colour's pixels when they form one connected, long, narrow shape (a drawn tree), else None.

    Narrow is relative to the image (a trunk drawn 20 px wide in a 1000 px
    picture is still a tree's), long means a centre line of at least half
    the image's width plus height. With ``pieces`` > 1 up to that many
    connected pieces may hold the colour (several root systems painted side
    by side on a soil, each entering at the frame; beyond the paper).
    """
    from skimage.morphology import skeletonize

    # a thin line drawn across the shape (a ground line over the trunk) does not cut it in two
    lab, n = ndi.label(ndi.binary_closing(has, np.ones((5, 5), bool)) | has, np.ones((3, 3), bool))
    if n == 0:
        return None
    sizes = np.bincount(lab[has], minlength=n + 1)[1:]
    order = np.argsort(-sizes)
    k = int(np.searchsorted(np.cumsum(sizes[order]), 0.8 * sizes.sum())) + 1
    if k > pieces:
        return None
    main = has & np.isin(lab, order[:k] + 1)
    length = int(skeletonize(main).sum())
    h, w = has.shape
    width = float(main.sum()) / max(length, 1)
    if length < 0.5 * (h + w) or width > max(3.0, 0.03 * min(h, w)):
        return None
    return width


def thin_line_colour(image, *, sigma_max: float = 4.0, min_contrast: float = 0.12, tol: float = 0.12,
                     min_share: float = 0.0005, max_colours: int = 6):
    """The colour of the thin lines of a drawn image (the blue rivers of a map), or None.

    A pixel is *line-like* when its colour differs by at least
    ``min_contrast`` (largest channel) from the median colour of a window
    wider than any line (``4 sigma_max + 1`` pixels; the median keeps the
    edges between flat areas, so an edge is not a line). The most common
    colours of the line-like pixels (up to ``max_colours``, quantised to
    eighths) are candidates; a candidate colour is a *line colour* when

    * at least ``min_share`` of the image has it (within ``tol``),
    * most of its pixels are line-like (a colour that fills areas, such
      as a grey relief level, is no line colour) and not the anti-aliased
      rim of a line of another colour;

    pixels along the outline of a large flat region touching the image
    border (a country border, a coast line) are not counted.

    The most frequent line colour wins. It is returned only when its
    contrast to the surroundings is largely one of hue (chroma at least
    half the brightness difference in a drawn image, at least 1 x in a
    photograph, medians over the line): a coloured line over a relief
    of greys is what brightness-based ridge filters miss (they follow the
    terrain's edges instead). Grey, black or white lines, and the dark
    branches of photographs, keep the brightness path.

    Beyond the paper, a drawing's *coloured tree shape* is a line colour
    too, however wide its trunk: a colour filled solid (exactly flat) whose
    pixels form one connected shape (thin lines drawn across it do not cut
    it) with a centre line at least half the image's width plus height and
    a mean width of at most ``max(3, 0.03 min(H, W))`` pixels (the brown
    trunk, branches and roots of a clip-art tree, not its green crown or its
    grass). It wins over a grey or dark line colour (the crown's rim), and
    :func:`extract_structure` traces it by its medial axis when it is at
    least 3 pixels wide.

    Beyond the paper (issue 23), the coast's ink does not win by its count
    alone: when at least a quarter of the most frequent colour's pixels lay
    on the outline, what the outline test leaves of it is most likely coast
    too (a double coast's offshore line, a coast beside a narrow strip of
    sea, an isthmus's two shores) or the strokes of map glyphs. A coloured
    line colour off the outline (under a tenth of it there), at least a
    quarter as frequent as that rest, with at least half of its pixels in
    pieces longer than ``4 sigma_max`` (rivers, not tree glyphs) and passing
    the hue test above wins instead, before the tree-shape rule.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example, float in [0, 1] (RGBA composited over white).
    sigma_max : float, default 4.0
        Largest line scale (pixels), as ``ExtractionParams.sigma_max``.
    min_contrast : float, default 0.12
        Smallest colour difference of a line-like pixel to its
        surroundings (largest channel).
    tol : float, default 0.12
        Colour tolerance (largest channel) of a line colour's pixels.
    min_share : float, default 0.0005
        Smallest fraction of the image in a line colour.
    max_colours : int, default 6
        Candidate colours examined.

    Returns
    -------
    (3,) float32 ndarray or None
        The RGB line colour in [0, 1]; None when there is no coloured line
        (then extraction follows brightness ridges).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((80, 80, 3), 0.7, np.float32); img[:, 40:] = 0.55     # two relief greys
    >>> img[20:22, 5:75] = (0.0, 0.55, 0.83); img[22:60, 30:32] = (0.0, 0.55, 0.83)   # blue rivers
    >>> [round(float(v), 2) for v in thin_line_colour(img)]
    [0.0, 0.55, 0.83]
    """
    return _line_colour_and_width(image, sigma_max=sigma_max, min_contrast=min_contrast, tol=tol,
                                  min_share=min_share, max_colours=max_colours)[0]


# share of a colour's pixels on the outline of the outside regions from which it is the coast's ink
COAST_INK_SHARE = 0.25
# least count of a coloured line colour, relative to what the outline test leaves of the coast's ink
COAST_RIVAL_SHARE = 0.25


def _chroma_ratio(rgb: np.ndarray, bg: np.ndarray, colour: np.ndarray, line_like: np.ndarray, tol: float) -> float:
    """Median hue-to-brightness ratio of the contrast of ``colour``'s line pixels to their surroundings."""
    has = (np.abs(rgb - colour).max(-1) <= tol) & line_like
    if not has.any():
        return 0.0
    diff = colour[None] - bg[has]
    lum = np.abs(diff.mean(-1)) * np.sqrt(3.0)
    chroma = np.linalg.norm(diff - diff.mean(-1, keepdims=True), axis=-1)
    return float(np.median(chroma / np.maximum(lum, 1e-6)))


def _elongated_share(has: np.ndarray, min_extent: float) -> float:
    """Share of ``has``'s pixels in pieces whose bounding box diagonal reaches ``min_extent`` (lines, not glyphs)."""
    lab, n = ndi.label(has, structure=np.ones((3, 3)))
    if n == 0:
        return 0.0
    sizes = np.bincount(lab.ravel(), minlength=n + 1)
    long_ = np.zeros(n + 1, bool)
    for i, sl in enumerate(ndi.find_objects(lab), start=1):
        if sl is not None and np.hypot(sl[0].stop - sl[0].start, sl[1].stop - sl[1].start) >= min_extent:
            long_[i] = True
    return float(sizes[long_].sum() / max(sizes[1:].sum(), 1))


def _line_colour_and_width(image, *, sigma_max: float = 4.0, min_contrast: float = 0.12, tol: float = 0.12,
                           min_share: float = 0.0005, max_colours: int = 6):
    """:func:`thin_line_colour` and, for a drawn branching shape wider than a line, its mean width (else None)."""
    rgb = as_rgb(image)[..., :3].astype(np.float32)
    h, w = rgb.shape[:2]
    bg = _local_background(rgb, sigma_max)
    line_like = np.abs(rgb - bg).max(-1) >= min_contrast
    if line_like.sum() < max(min_share * h * w, 20):
        return None, None
    q = np.clip((rgb[line_like] * 8).astype(np.int64), 0, 7)
    key = (q[:, 0] * 8 + q[:, 1]) * 8 + q[:, 2]
    counts = np.bincount(key, minlength=512)
    # a drawn tree's trunk is wider than a line: the image's main colours are candidates too
    qa = np.clip((rgb.reshape(-1, 3) * 8).astype(np.int64), 0, 7)
    all_counts = np.bincount((qa[:, 0] * 8 + qa[:, 1]) * 8 + qa[:, 2], minlength=512)
    gray = as_gray(rgb)
    drawn = _is_drawn(gray)
    # a drawing's shapes are filled with one exact colour; a smooth photograph (a fundus) is not
    solid = np.max([ndi.maximum_filter(rgb[..., i], 3) - ndi.minimum_filter(rgb[..., i], 3)
                    for i in range(3)], axis=0) < 0.005
    outside = border_flat_regions(gray, 4 * sigma_max)
    contrast = np.linalg.norm(rgb - bg, axis=-1)
    # the anti-aliased rim of a line: a neighbour has much more contrast
    rim = ndi.maximum_filter(contrast, 3) > contrast + 0.1
    found = []
    candidates = list(np.argsort(-counts)[:max_colours])
    # thin coloured lines in a small image are few line-like pixels beside the greys of a relief's edges
    # (beyond the paper): the four commonest clearly coloured bins are candidates as well
    bins = np.stack(np.unravel_index(np.arange(512), (8, 8, 8)), -1)
    chromatic = (bins.max(-1) - bins.min(-1) >= 2) & (counts >= 20)
    candidates += [k for k in np.argsort(-np.where(chromatic, counts, -1))[:4]
                   if chromatic[k] and k not in candidates]
    if drawn:
        candidates += [k for k in np.argsort(-all_counts)[:max_colours] if k not in candidates]
    for k in candidates:
        if counts[k] == 0 and all_counts[k] == 0:
            continue
        c = np.median(rgb[line_like][key == k], axis=0) if counts[k] >= 20 else \
            np.median(rgb.reshape(-1, 3)[((qa[:, 0] * 8 + qa[:, 1]) * 8 + qa[:, 2]) == k], axis=0)
        has = np.abs(rgb - c).max(-1) <= tol
        if has.sum() < min_share * h * w:
            continue  # too rare already (the outline test below only takes pixels away)
        # a border line drawn in the same colour (a coast) is not counted
        outline = outline_pixels(has, outside, 2 * sigma_max + 2)
        # (a grey or black border as a whole; a coloured shape touching the outside, a trunk, stays)
        n_all = int(has.sum())
        has = _off_outline(has, outline) if c.max() - c.min() < 0.2 else has & ~outline
        n = int(has.sum())
        if n < min_share * h * w or np.mean(rim[has]) > 0.5:
            continue
        # wider than a line, yet in a drawing a coloured tree shape is still the structure
        width = _drawn_branching_width(has, sigma_max) if drawn and c.max() - c.min() >= 0.2 \
            and np.mean(solid[has]) >= 0.12 else None
        if width is None and _solid_on_texture(solid, has) and \
                (not drawn or np.mean(line_like[has]) >= DRAWN_LINE_LIKE):
            # lines painted in one exact colour on a textured ground (a root system on soil): where they
            # are wider than the ridge filter's scales (a crown at the frame) the filter sees two edges
            # and the crown is lost, so its shape is traced by its medial axis (beyond the paper). A smooth
            # soil (faint grain) passes for a drawing, yet its ground has no solid paint either: the same
            # (a dull brown root paint missed the drawn-tree test above; recall 0.84-0.89 by the filter),
            # as long as some of the colour stands out from its surroundings as a line does (a fundus
            # photo's black surround, a region, has none)
            w_line = _drawn_branching_width(has, sigma_max, pieces=PAINTED_PIECES)
            width = w_line if w_line is not None and w_line >= 3.0 else None
        if width is None and np.mean(line_like[has]) < 0.5:
            continue
        found.append((n, c, width, 1.0 - n / max(n_all, 1)))
    if not found:
        return None, None
    found.sort(key=lambda f: -f[0])
    trees = [f for f in found if f[2] is not None]
    n, best, width, border_share = found[0]
    min_ratio = 0.5 if drawn else 1.0
    if border_share >= COAST_INK_SHARE:
        # the commonest colour is the coast's ink (much of it on the outline of the outside): what the
        # outline test leaves of it is still coast (the thin second line of a double coast, a coast
        # beside a narrow strip of sea, an isthmus's two shores) or glyphs' strokes, and tracing it
        # (by brightness, or as a drawn shape) took those for rivers (precision 0.75-0.81 on fantasy
        # maps, 0 where the glyphs' trunks made it a "tree"). Coloured thin lines of their own, off the
        # outline, long and not rare beside that rest, are the structure (beyond the paper)
        for n2, c2, w2, share2 in found[1:]:
            if w2 is None and share2 < 0.1 and n2 >= COAST_RIVAL_SHARE * n and \
                    _chroma_ratio(rgb, bg, c2, line_like, tol) >= min_ratio and \
                    _elongated_share(np.abs(rgb - c2).max(-1) <= tol, 4 * sigma_max) >= 0.5:
                return c2.astype(np.float32), None
    if width is not None:
        # a coloured branching shape among flat areas: brightness ridges would trace the areas' outlines
        return best.astype(np.float32), width
    if _chroma_ratio(rgb, bg, best, line_like, tol) >= min_ratio:
        return best.astype(np.float32), None
    # the commonest line colour is grey or dark (a crown's rim): a coloured tree shape still wins
    return (trees[0][1].astype(np.float32), trees[0][2]) if trees else (None, None)


def line_colour_of(image, structure: Structure) -> np.ndarray:
    """The median colour on the centre lines of an annotation (pass it as ``line_colour``).

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example: grey, RGB or RGBA (composited over white), float in [0, 1] or integer.
    structure : Structure
        Its annotated branches (pixels of ``image``).

    Returns
    -------
    (3,) ndarray
        RGB median in [0, 1] of the pixels under the centre lines (sampled
        every half pixel of arc length).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((20, 40, 3), 0.7, np.float32); img[9:11] = (0.0, 0.55, 0.83)
    >>> s = Structure([Branch([(2, 9.5), (37, 9.5)], 1.0)])
    >>> [round(float(v), 2) for v in line_colour_of(img, s)]
    [0.0, 0.55, 0.83]
    """
    rgb = as_rgb(image)[..., :3]
    h, w = rgb.shape[:2]
    if not isinstance(structure, Structure) or not structure.branches:
        raise ValueError("structure must be a non-empty Structure")
    pts = np.vstack([resample_uniform(b.points, 0.5, include_end=True) if len(b.points) > 1 else b.points
                     for b in structure.branches])
    ix = np.clip(np.floor(pts[:, 0] + 0.5).astype(int), 0, w - 1)
    iy = np.clip(np.floor(pts[:, 1] + 0.5).astype(int), 0, h - 1)
    return np.median(rgb[iy, ix], axis=0).astype(np.float32)


def line_colour_map(image, colour, *, sigma_max: float = 4.0, spread: float = 0.15) -> np.ndarray:
    """How much each pixel has the line ``colour`` rather than its surroundings' colour, in [0, 1].

    With ``b`` the median colour around the pixel (see
    :func:`thin_line_colour`) and ``c`` the line colour, a pixel ``I`` on
    the segment from ``b`` to ``c`` (a blend: an anti-aliased line edge)
    scores its position ``t`` along it, 1 on the line colour and 0 on the
    surroundings; the score falls to 0 as ``I`` leaves the segment by
    ``spread`` (RGB distance): another colour, such as a darker relief
    grey next to a white lowland, is no line however it compares in
    brightness. Pixels within ``spread`` of ``c`` score ``1 - |I - c| /
    (2 spread)`` at least (inside a wide river the surroundings are the
    line colour too). Bright lines on black, ready for the ridge filter.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The image: grey, RGB or RGBA (composited over white), float in [0, 1] or integer.
    colour : (3,) array_like
        The line colour (RGB in [0, 1]).
    sigma_max : float, default 4.0
        Largest line scale (pixels): sets the median window of the
        surroundings.
    spread : float, default 0.15
        RGB distance from the blend segment at which the score reaches 0.

    Returns
    -------
    (H, W) float32 ndarray
        The score in [0, 1].

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((30, 30, 3), 0.7, np.float32); img[14:16] = (0.0, 0.55, 0.83); img[:5] = 0.5
    >>> m = line_colour_map(img, (0.0, 0.55, 0.83))
    >>> float(m[15, 10]), float(m[20, 10]), float(m[4, 10]) < 0.01
    (1.0, 0.0, True)
    """
    rgb = as_rgb(image)[..., :3].astype(np.float32)
    c = np.asarray(colour, np.float32).reshape(3)
    bg = _local_background(rgb, sigma_max)
    u = c[None, None] - bg
    v = rgb - bg
    n2 = np.maximum((u * u).sum(-1), 1e-6)
    t = np.clip((v * u).sum(-1) / n2, 0.0, 1.0)
    perp = np.linalg.norm(v - t[..., None] * u, axis=-1)
    blend = t * np.clip(1.0 - perp / spread, 0.0, 1.0)
    blend[n2 < spread ** 2] = 0.0
    close = 1.0 - np.linalg.norm(rgb - c, axis=-1) / (2.0 * spread)
    return np.clip(np.maximum(blend, close), 0.0, 1.0).astype(np.float32)


#: An enclosed inside is a stroke's (its two outline lines parallel) when the width along its medial axis
#: varies by at most :data:`STROKE_WIDTH_CV` (coefficient of variation) and at least
#: :data:`STROKE_FULL_WIDTH` of the axis is wider than 0.6 x the inside's widest (:func:`_parallel_sides`).
STROKE_WIDTH_CV = 0.2
STROKE_FULL_WIDTH = 0.9


def _parallel_sides(reg: np.ndarray, dt: np.ndarray, width: float) -> bool:
    """Whether the inside ``reg`` (``dt``: distance to the ink, ``width`` its widest) is as wide along
    its whole medial axis, as a stroke's inside between its two outline lines is.

    Beyond the paper (issue 23): the cells between crossing lines of a line network (a river map's
    tributaries crossing, forks closed by a line across them) are enclosed, narrow and wrapped in
    thin ink too; filled, they turned the network into blobs (a 420 px crossing network rooted
    inside). They are lenses and wedges: the width along their axis runs from nothing at the
    corners to its widest between (coefficient of variation 0.21-0.64 on procedural crossing
    networks, 256-900 px), where an outlined stroke's stays within 0.2 (0.00-0.19 on outlined
    drawings and interlace vines, 200-600 px). A stroke drawn as a tapering outline is therefore
    traced as its two outline lines.
    """
    from skimage.morphology import skeletonize

    wd = 2.0 * dt[skeletonize(reg)]
    if len(wd) < 2:
        return True
    return bool(np.std(wd) <= STROKE_WIDTH_CV * np.mean(wd) and np.mean(wd >= 0.6 * width) >= STROKE_FULL_WIDTH)


def fill_outlined_strokes(gray, *, max_width: float = 24.0, colour=None,
                          colour_tol: float = 0.06) -> tuple[np.ndarray, int]:
    """Fill the insides of strokes drawn as outlines, so each is traced once along its centre line.

    Going beyond the paper (its examples are solid lines). A stroke drawn as
    two parallel outline lines with the paper between them would otherwise
    be traced as two lines. An inside is a region of the background colour
    that is enclosed by dark ink (touches no frame edge), narrow (at most
    ``max_width`` px and at most 6 x the ink line's width across),
    elongated (its length at least 3 x its width), wrapped in *thin* ink
    (beyond the ink line lies background again, unlike the islands between
    the wide channels of a braided river) and of one width along its length
    (parallel outline lines; the lens- and wedge-shaped cells between the
    crossing lines of a river network stay, see ``_parallel_sides``). Cells
    of a crack drawing are wide and stay.

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1] of dark ink on a light background.
    max_width : float, default 24.0
        Widest inside (pixels) that is filled.
    colour : (H, W, 3) array_like, optional
        The colour image ``gray`` was made from. When given, an inside is
        only filled when the background just beyond its ink has the
        inside's colour (within ``colour_tol`` in every channel) on more
        than 80 % of it: on a map whose two land colours have nearly one
        grey, the sliver of one country between a river and the drawn
        border has the other country's colour beyond the border, and is no
        stroke's inside (beyond the paper; filling it would merge the river
        and the border into one wide blob that is then dropped).
    colour_tol : float, default 0.06
        Largest colour difference (over the channels) still the same colour.

    Returns
    -------
    gray : (H, W) float32 ndarray
        The image with the insides set to the ink's grey (a copy).
    n : int
        Number of insides filled.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.ones((40, 80), np.float32)
    >>> g[15:25, 10:70] = 0.0; g[17:23, 12:68] = 1.0        # a stroke drawn as its outline
    >>> out, n = fill_outlined_strokes(g)
    >>> n, float(out[20, 40])
    (1, 0.0)
    """
    from skimage.morphology import skeletonize

    g = np.asarray(gray, np.float32)
    out = g.copy()
    rgb = None
    if colour is not None:
        rgb = np.asarray(colour, np.float32)
        if rgb.ndim != 3 or rgb.shape[:2] != g.shape or rgb.shape[2] < 3:
            raise ValueError(f"colour must be an (H, W, 3) image of gray's shape {g.shape}, got {rgb.shape}")
        rgb = rgb[..., :3]
    lo, hi = np.percentile(g, [1, 99])
    if hi - lo < 0.25:
        return out, 0
    ink = g < 0.5 * (lo + hi)
    if ink.mean() > 0.5 or not ink.any():
        return out, 0
    sk = skeletonize(ink)
    d_ink = ndi.distance_transform_edt(ink)
    lw = 2.0 * float(np.median(d_ink[sk])) if sk.any() else 1.0
    bg = ~ink
    lab, n = ndi.label(bg)                       # 4-connected: an 8-connected ink line encloses
    if n < 2:
        return out, 0
    edge = np.unique(np.concatenate([lab[0], lab[-1], lab[:, 0], lab[:, -1]]))
    objs = ndi.find_objects(lab)
    dt = ndi.distance_transform_edt(bg)
    filled = 0
    pad = int(np.ceil(lw)) + 4
    h, w = g.shape
    for i, sl in enumerate(objs, start=1):
        if sl is None or i in edge:
            continue
        y0, y1 = max(sl[0].start - pad, 0), min(sl[0].stop + pad, h)
        x0, x1 = max(sl[1].start - pad, 0), min(sl[1].stop + pad, w)
        reg = lab[y0:y1, x0:x1] == i
        width = 2.0 * float(dt[y0:y1, x0:x1][reg].max())
        area = float(reg.sum())
        if width > min(max_width, 6.0 * lw) or area < 3.0 * width * width:
            continue
        # thin ink around it: the shell just beyond one ink width is mostly background again
        d_out = ndi.distance_transform_edt(~reg)
        shell = (d_out > lw + 1.5) & (d_out <= lw + 3.5)
        if not shell.any() or bg[y0:y1, x0:x1][shell].mean() < 0.6:
            continue
        if not _parallel_sides(reg, dt[y0:y1, x0:x1], width):
            continue
        if rgb is not None:
            # a stroke's inside has the paper's colour beyond its outline too; a sliver of one country
            # between a river and the border has the other country's colour beyond the border
            win = rgb[y0:y1, x0:x1]
            inside = np.median(win[reg], axis=0)
            out_bg = shell & bg[y0:y1, x0:x1]
            if np.mean(np.abs(win[out_bg] - inside).max(-1) > colour_tol) >= 0.2:
                continue
        out[y0:y1, x0:x1][reg] = float(np.median(g[ink]))
        filled += 1
    return out, filled


def multi_colour_ink(image, *, paper_share: float = 0.5, tol: float = 0.1,
                     share: float = 0.97) -> np.ndarray | None:
    """Ink of several colours on one plain paper, as one dark-on-white grey image (or None).

    Going beyond the paper. A drawn stroke of two colours (a black outline
    stroke with a red or green inner line, an ornament) is no brightness
    ridge: the ridge filter finds its two dark edges and traces one of
    them, so fragments come out with the inner line off to one side. When
    at least ``paper_share`` of the pixels have one colour (the paper, the
    most frequent colour) and at least ``share`` of all pixels lie within
    ``tol`` of it or clearly away from it (3 ``tol``: the ink, only its
    anti-aliased rim in between), while the ink is thin everywhere (at
    most 35 % of the image, and no part of it wider than 3 x the strokes'
    median width, as a sea or a land is) and
    of more than one colour (one ink colour is a mask already), the ink's
    distance from the paper colour is returned as a grey image (0 = ink, 1 = paper), for
    tracing by its medial axis like a binary mask.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The image (RGBA composited over white).
    paper_share : float, default 0.5
        Smallest share of the paper colour.
    tol : float, default 0.1
        Largest channel difference of a paper pixel from the paper colour.
    share : float, default 0.97
        Share of the pixels that are clearly paper or clearly ink.

    Returns
    -------
    (H, W) float32 ndarray or None
        The ink as a grey image, or None when the image is no such drawing.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((60, 80, 3)); img[26:35, 5:75] = 0.0; img[29:32, 5:75] = (0.9, 0.1, 0.1)
    >>> ink = multi_colour_ink(img)
    >>> float(ink[30, 40]), float(ink[10, 40])
    (0.0, 1.0)
    """
    from .backgrounds import large_flat_regions

    rgb = np.asarray(as_rgb(image), np.float64)[..., :3]
    q = np.clip((rgb * 15.999).astype(np.int64), 0, 15)
    code = (q[..., 0] * 16 + q[..., 1]) * 16 + q[..., 2]
    counts = np.bincount(code.ravel(), minlength=4096)
    top = int(np.argmax(counts))
    paper = rgb[code == top].mean(axis=0)
    d = np.abs(rgb - paper).max(-1)
    near, far = d <= tol, d >= 3 * tol
    if near.mean() < paper_share or (near | far).mean() < share or not far.any():
        return None
    solid = ndi.binary_erosion(far, np.ones((3, 3), bool))   # no anti-aliased rim
    if not solid.any():
        return None
    spread = np.percentile(rgb[solid], 95, axis=0) - np.percentile(rgb[solid], 5, axis=0)
    if spread.max() < 0.25:
        return None         # one ink colour: its grey image is a mask already
    ink = d >= 1.5 * tol
    dt = ndi.distance_transform_edt(ink)
    from skimage.morphology import skeletonize

    sk = skeletonize(ink)
    if not sk.any():
        return None
    r_med = float(np.median(dt[sk]))
    if (ink.mean() > 0.35 or float(np.percentile(dt[sk], 99)) > 3.0 * r_med + 1.0
            or large_flat_regions(ink, max(3.0 * r_med, 3.0)).any()):
        return None         # a sea, a land or a filled shape: no drawing of strokes
    depth = float(np.percentile(d[far], 25))   # every ink colour fully dark
    return (1.0 - np.clip(d / max(depth, 1e-6), 0.0, 1.0)).astype(np.float32)
