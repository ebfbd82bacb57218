"""Quality measures of tree variations: ghosting, soft alpha, islands and holes.

What a reader of the paper checks by eye, as numbers:

* :func:`soft_alpha_fraction`: share of opaque-ish pixels with alpha between
  0.1 and 0.9 away from the silhouette rim (a clean cut-out has none);
* :func:`crossfade_fraction`: share of a variation's flat pixels whose
  colour is far from every dominant colour of the exemplars (cross-fade
  ghosting of drawn trees);
* :func:`pieces` and :func:`large_holes`: opaque components and interior
  transparent holes larger than a given area;
* :func:`flat_region_speckle`: of a billboard cloud, the share of the
  front view's large flat-coloured regions that turn busy in a side view.

Examples
--------
>>> import numpy as np
>>> a = np.zeros((9, 9, 4), np.float32); a[2:7, 2:7] = (0.2, 0.6, 0.1, 1.0)
>>> soft_alpha_fraction(a), pieces(a[..., 3]), large_holes(a[..., 3], 0)
(0.0, 1, 0)
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi
from scipy.spatial import cKDTree

from ..core.image import as_rgba
from ..core.validate import check_real

__all__ = ["soft_alpha_fraction", "flat_pixels", "palette_coverage", "palette_pixels", "FLAT_COVERAGE",
           "dominant_palette", "crossfade_fraction",
           "foreign_colour_fraction", "dark_rim_fraction", "pieces", "large_holes", "hole_sizes",
           "flat_region_speckle", "colour_span", "largest_piece_share", "side_view_figures",
           "bare_seam_share", "outline_continuity", "outline_width_spread", "stray_ink", "seam_through_flat",
           "foreign_patches", "crown_sources"]


def soft_alpha_fraction(image, *, rim: int = 1) -> float:
    """Share of pixels with 0.1 < alpha < 0.9 more than ``rim`` pixels inside the silhouette.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA with alpha in [0, 1]; the silhouette is alpha >= 0.5.
    rim : int
        Erosion (3 x 3 cross, in pixels) of the silhouette before counting,
        so the anti-aliased edge is left out; 0 counts every pixel.

    Returns
    -------
    float
        Soft pixels in the eroded silhouette over all silhouette pixels
        (0 for a clean binary cut-out).

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((9, 9, 4), np.float32); a[1:8, 1:8, 3] = 1.0; a[4, 4, 3] = 0.5
    >>> round(soft_alpha_fraction(a), 3)  # 1 soft pixel of 49
    0.02
    """
    a = np.asarray(image, dtype=np.float32)[..., 3]
    inside = a >= 0.5
    core = ndi.binary_erosion(inside, iterations=rim) if rim > 0 else inside
    soft = (a > 0.1) & (a < 0.9)
    n = max(int(inside.sum()), 1)
    return float(np.count_nonzero(soft & core) / n)


def flat_pixels(image, *, span: float = 0.06, alpha: float = 0.99) -> np.ndarray:
    """Pixels inside flat colour areas: opaque 3 x 3 neighbourhoods varying by less than ``span``.

    Anti-aliased edges, outlines' rims and photographic texture are left
    out, so what remains is where a drawn tree has one flat fill colour.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA (RGB or grey: opaque).
    span : float
        Largest per-channel range in the 3 x 3 window.
    alpha : float
        Every pixel of the window must be at least this opaque.

    Returns
    -------
    (H, W) bool ndarray
        True at the centre of every flat, fully opaque 3 x 3 window.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((6, 6, 4), np.float32); img[:, 3:, :3] = 0.0
    >>> flat_pixels(img)[2].tolist()  # the columns next to the colour edge are not flat
    [False, True, False, False, True, False]
    """
    img = as_rgba(image, name="image")
    span = check_real(span, "span", min=0.0)
    alpha = check_real(alpha, "alpha", min=0.0, max=1.0)
    opaque = ndi.minimum_filter(img[..., 3], size=3, mode="constant") >= alpha
    return opaque & (colour_span(img[..., :3], size=3) < span)


def palette_coverage(image, *, n_colours: int = 16, tol: float = 0.06, threshold: float = 0.5) -> float:
    """Share of the opaque pixels within ``tol`` (RGB) of the image's ``n_colours`` most frequent colours.

    Colours are counted after quantisation to 1/32. Drawn trees
    (:func:`~branchnb.trees.drawn.drawn_tree`, 8 of each kind at 96 and
    128 px) measure at least 0.92 (broadleaf, conifer, fruit) and 0.86
    (outlined palms, whose thin fills leave almost no flat 3 x 3 window);
    the photographed ``tree_cutout_broadleaf`` 0.45; clip art shaded with
    gradients 0.81 (``christmas_tree_root_flare``, flat art anyway by its
    flat pixels: 0.62), so :data:`FLAT_COVERAGE` calls smooth gradients
    "not flat" while thin outlined fills still count.

    Parameters
    ----------
    image : (H, W, 4) array_like
        An RGBA tree billboard.
    n_colours : int, optional
        How many of the most frequent (quantised) colours make the palette (default 16).
    tol : float, optional
        RGB distance within which a pixel matches a palette colour (default 0.06).
    threshold : float, optional
        Alpha at or above which a pixel counts as opaque (default 0.5).

    Returns
    -------
    float
        The share in [0, 1]; 0 for an image with no opaque pixel.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((8, 8, 4), np.float32); a[:, :, 3] = 1; a[:, 4:, 1] = 0.5
    >>> palette_coverage(a)
    1.0
    """
    img = as_rgba(image, name="image")
    opaque = img[..., 3] >= threshold
    if not opaque.any():
        return 0.0
    return float(palette_pixels(img, n_colours=n_colours, tol=tol, threshold=threshold)[opaque].mean())


def palette_pixels(image, *, n_colours: int = 16, tol: float = 0.06, threshold: float = 0.5) -> np.ndarray:
    """Opaque pixels within ``tol`` (RGB) of one of the image's ``n_colours`` most frequent colours.

    The pixels :func:`palette_coverage` counts; on flat art with fills too
    thin for a flat 3 x 3 window (outlined palms at 128 px) they are the
    fills.

    Parameters
    ----------
    image : (H, W, 4) array_like
        An RGBA tree billboard.
    n_colours : int, optional
        How many of the most frequent (quantised) colours make the palette (default 16).
    tol : float, optional
        RGB distance within which a pixel matches a palette colour (default 0.06).
    threshold : float, optional
        Alpha at or above which a pixel counts as opaque (default 0.5).

    Returns
    -------
    (H, W) bool ndarray

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((4, 4, 4), np.float32); a[:, :, 3] = 1; a[0, 0, :3] = 0.5
    >>> int(palette_pixels(a, n_colours=1).sum())
    15
    """
    img = as_rgba(image, name="image")
    opaque = img[..., 3] >= threshold
    out = np.zeros(opaque.shape, bool)
    px = img[opaque][:, :3].astype(np.float64)
    if len(px) == 0:
        return out
    u, c = np.unique(np.round(px * 32).astype(np.int32), axis=0, return_counts=True)
    top = u[np.argsort(c, kind="stable")[::-1][:n_colours]] / 32.0
    d = np.min(((px[:, None, :] - top[None]) ** 2).sum(-1), axis=1)
    out[opaque] = d <= tol * tol
    return out


#: :func:`palette_coverage` from which a tree counts as flat art.
FLAT_COVERAGE = 0.84


def dominant_palette(sources, *, tol: float = 0.12, span: float = 0.06, quant: float = 1 / 64,
                     max_colours: int = 512) -> np.ndarray:
    """The dominant flat colours of some drawn images, enough to cover all their flat pixels.

    The flat pixels (:func:`flat_pixels`) of every source are quantised to
    ``quant`` and covered greedily: the most frequent colour not yet within
    ``tol`` of the palette joins it, until every flat colour is covered (or
    ``max_colours`` is reached). So each source scores 0 against itself in
    :func:`crossfade_fraction`, while a palette entry is never a blend of
    two others unless the sources themselves contain that colour.

    Parameters
    ----------
    sources : (H, W, C) array_like or sequence of them
        The drawn images (straight RGBA; RGB counts as opaque).
    tol : float
        RGB distance within which a flat colour is covered by a palette
        entry (the same ``tol`` as in :func:`crossfade_fraction`).
    span : float
        Flatness of a pixel's 3 x 3 window (:func:`flat_pixels`).
    quant : float
        Quantisation step of the colours before counting (default 1/64).
    max_colours : int
        Largest palette size.

    Returns
    -------
    (P, 3) float32 ndarray
        Quantised RGB, the most frequent colour first; empty when no
        source has a flat pixel.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((8, 12, 4), np.float32); img[:, 8:, :3] = (0.0, 0.5, 0.0)
    >>> dominant_palette(img).tolist()  # white covers more flat pixels
    [[1.0, 1.0, 1.0], [0.0, 0.5, 0.0]]
    """
    cols = []
    if isinstance(sources, np.ndarray) and sources.ndim == 3:
        sources = [sources]
    for i, s in enumerate(sources):
        s = as_rgba(s, name=f"sources[{i}]")
        cols.append(s[flat_pixels(s, span=span)][:, :3])
    c = np.vstack(cols) if cols else np.zeros((0, 3), np.float32)
    if len(c) == 0:
        return np.zeros((0, 3), np.float32)
    q, counts = np.unique(np.round(c / quant).astype(np.int32), axis=0, return_counts=True)
    q = q.astype(np.float32) * quant
    order = np.argsort(counts, kind="stable")[::-1]
    q = q[order]
    covered = np.zeros(len(q), bool)
    palette = []
    tree = cKDTree(q)
    for i in range(len(q)):
        if covered[i]:
            continue
        palette.append(q[i])
        covered[tree.query_ball_point(q[i], tol - 0.5 * np.sqrt(3) * quant)] = True
        if len(palette) >= max_colours:
            break
    return np.asarray(palette, np.float32)


def crossfade_fraction(image, sources, *, tol: float = 0.12, span: float = 0.06,
                       palette=None) -> float:
    """Share of a variation's flat pixels whose colour is a cross-fade of the sources' palettes.

    A flat pixel (opaque 3 x 3 neighbourhood varying by less than ``span``,
    :func:`flat_pixels`) counts as a cross-fade when its RGB is farther than
    ``tol`` from every dominant colour of the sources
    (:func:`dominant_palette`). Each source scores 0 against itself; half
    green and half brown (an olive veil) or a half-transparent fruit
    scores 1. This replaces the old foreign-colour share, which compared
    with *every* source pixel colour and so matched blended colours
    against the soft edge pixels of the sources.

    Parameters
    ----------
    image : (H, W, 4) array_like
        The variation (straight RGBA).
    sources : sequence of (H, W, 4) array_like
        The exemplars mixed.
    tol : float
        Euclidean RGB distance.
    span : float
        Flatness of a pixel's 3 x 3 window (:func:`flat_pixels`).
    palette : (P, 3) array_like, optional
        A precomputed :func:`dominant_palette` of ``sources``.

    Returns
    -------
    float
        0 when the image has no flat pixel.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((8, 8, 4), np.float32); a[...] = (0.1, 0.6, 0.1, 1)
    >>> b = a.copy(); b[..., :3] = (0.5, 0.3, 0.1)
    >>> mix = a.copy(); mix[..., :3] = 0.5 * a[..., :3] + 0.5 * b[..., :3]
    >>> crossfade_fraction(a, [a, b]), crossfade_fraction(mix, [a, b])
    (0.0, 1.0)
    """
    img = as_rgba(image, name="image")
    tol = check_real(tol, "tol", min=0.0)
    span = check_real(span, "span", min=0.0)
    flat = flat_pixels(img, span=span)
    if not flat.any():
        return 0.0
    pal = dominant_palette(sources, tol=tol, span=span) if palette is None \
        else np.asarray(palette, np.float32).reshape(-1, 3)
    if len(pal) == 0:
        return 1.0
    d, _ = cKDTree(pal).query(img[flat][:, :3], k=1)
    return float(np.mean(d > tol))


def foreign_colour_fraction(image, sources, *, tol: float = 0.12, **kwargs) -> float:
    """Deprecated name of :func:`crossfade_fraction` (the dominant-palette measure).

    Parameters
    ----------
    image : (H, W, 4) array_like
        The variation (straight RGBA).
    sources : sequence of (H, W, 4) array_like
        The exemplars mixed.
    tol : float
        Euclidean RGB distance.
    **kwargs
        Further arguments of :func:`crossfade_fraction` (``span``,
        ``palette``).

    Returns
    -------
    float
        :func:`crossfade_fraction` of the same arguments.
    """
    return crossfade_fraction(image, sources, tol=tol, **kwargs)


def dark_rim_fraction(image, mask, *, darkest=None) -> float:
    """Share of opaque pixels outside the (dilated by one pixel) ``mask`` darker than ``darkest``.

    Clean rims: no pixel darker than the outline may stick out of the mixed
    contour. ``darkest`` defaults to 0.9 times the luminance of the darkest
    tenth of a percent of the image inside ``mask``.

    Parameters
    ----------
    image : (H, W, 4) array_like
        The variation (straight RGBA; alpha >= 0.5 is opaque).
    mask : (H, W) array_like
        The mixed contour's interior (non-zero is inside), e.g.
        ``Variation.mask``.
    darkest : float, optional
        Luminance (Rec. 601 weights) below which an outside pixel counts;
        None derives it from the image as above.

    Returns
    -------
    float
        Dark opaque pixels outside the dilated mask over all opaque pixels
        (0 when nothing opaque lies outside).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((10, 10, 4), np.float32); img[2:8, 2:8] = (0.2, 0.6, 0.2, 1)
    >>> img[2:8, 2] = (0.1, 0.1, 0.1, 1)  # outline, inside the mask: darkest = 0.09
    >>> mask = np.zeros((10, 10), bool); mask[2:8, 2:8] = True
    >>> img[9, 9] = (0.0, 0.0, 0.0, 1)    # a dark pixel sticking out
    >>> round(dark_rim_fraction(img, mask), 3)  # 1 of 37 opaque pixels
    0.027
    """
    img = np.asarray(image, dtype=np.float32)
    m = np.asarray(mask, bool)
    lum = img[..., :3] @ np.array([0.299, 0.587, 0.114], np.float32)
    op = img[..., 3] >= 0.5
    outside = op & ~ndi.binary_dilation(m, iterations=1)
    if not outside.any():
        return 0.0
    if darkest is None:
        inside = lum[op & m]
        darkest = 0.9 * float(np.quantile(inside, 0.001)) if inside.size else 0.0
    return float(np.count_nonzero(outside & (lum < darkest)) / max(int(op.sum()), 1))


def pieces(alpha, *, min_area: int = 1) -> int:
    """Opaque 8-connected components of at least ``min_area`` pixels.

    Parameters
    ----------
    alpha : (H, W) array_like
        Opacity; pixels >= 0.5 are opaque.
    min_area : int
        Smallest component counted, in pixels (default 1: every one).

    Returns
    -------
    int
        Number of components (0 for a transparent image).

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((8, 8)); a[1:3, 1:3] = 1; a[5:8, 5:8] = 1
    >>> pieces(a), pieces(a, min_area=5)
    (2, 1)
    """
    m = np.asarray(alpha) >= 0.5
    lab, n = ndi.label(m, structure=np.ones((3, 3), bool))
    if n == 0:
        return 0
    areas = np.bincount(lab.ravel())[1:]
    return int(np.count_nonzero(areas >= min_area))


def largest_piece_share(alpha) -> float:
    """Share of the opaque pixels in the largest 8-connected opaque piece (1 for one piece).

    Parameters
    ----------
    alpha : (H, W) array_like
        Opacity; pixels >= 0.5 are opaque.

    Returns
    -------
    float
        In [0, 1]; 0 for a transparent image.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((8, 8)); a[0:1, 0:4] = 1; a[4:8, 4:7] = 1
    >>> largest_piece_share(a)
    0.75
    """
    m = np.asarray(alpha) >= 0.5
    lab, n = ndi.label(m, structure=np.ones((3, 3), bool))
    if n == 0:
        return 0.0
    areas = np.bincount(lab.ravel())[1:]
    return float(areas.max() / areas.sum())


def hole_sizes(alpha) -> np.ndarray:
    """Areas of the interior transparent holes (not connected to the border), 4-connected.

    Parameters
    ----------
    alpha : (H, W) array_like
        Opacity; pixels below 0.5 are transparent.

    Returns
    -------
    (n,) int ndarray
        Area in pixels of each hole, in label order (empty without holes).

    Examples
    --------
    >>> import numpy as np
    >>> a = np.ones((9, 9)); a[0] = 0; a[2:4, 2:4] = 0; a[6, 6] = 0
    >>> hole_sizes(a).tolist()
    [4, 1]
    """
    m = np.asarray(alpha) >= 0.5
    lab, n = ndi.label(~m)
    if n == 0:
        return np.zeros(0, int)
    border = np.unique(np.concatenate([lab[0], lab[-1], lab[:, 0], lab[:, -1]]))
    sizes = np.bincount(lab.ravel(), minlength=n + 1)
    sizes[0] = 0
    sizes[border] = 0
    return sizes[sizes > 0]


def large_holes(alpha, limit: int) -> int:
    """Interior holes larger than ``limit`` pixels.

    Parameters
    ----------
    alpha : (H, W) array_like
        Opacity; pixels below 0.5 are transparent.
    limit : int
        Area in pixels a hole must exceed to count (see :func:`hole_sizes`).

    Returns
    -------
    int
        Number of interior holes with area > ``limit``.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.ones((9, 9)); a[2:4, 2:4] = 0; a[6, 6] = 0
    >>> large_holes(a, 0), large_holes(a, 2)
    (2, 1)
    """
    return int(np.count_nonzero(hole_sizes(alpha) > limit))


def colour_span(rgb, size: int = 5) -> np.ndarray:
    """Largest per-channel colour range in each ``size`` x ``size`` window, (H, W).

    Parameters
    ----------
    rgb : (H, W, C) array_like
        Colours; only the first three channels are used.
    size : int
        Side of the square window in pixels (default 5); borders are
        reflected.

    Returns
    -------
    (H, W) float32 ndarray
        ``max - min`` of each channel in the window, the largest over the
        channels.

    Examples
    --------
    >>> import numpy as np
    >>> rgb = np.zeros((5, 8, 3), np.float32); rgb[:, 4:, 1] = 0.5
    >>> colour_span(rgb, size=3)[2].tolist()
    [0.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.0]
    """
    rgb = np.asarray(rgb, dtype=np.float32)[..., :3]
    win = (size, size, 1)
    return (ndi.maximum_filter(rgb, size=win) - ndi.minimum_filter(rgb, size=win)).max(axis=2)


def bare_seam_share(image, sources=None, *, edge: float = 0.12, reach: int | None = None) -> float:
    """Share of a ``"choose"`` mix's seams that cross a fill without an outline.

    The ``"choose"`` colour mode cuts the sources along graph-cut seams
    (``sources``: each pixel's exemplar, :attr:`Variation.sources`). A seam
    pixel (4-adjacent to a pixel of another source, opaque, not on the
    silhouette's rim) crosses a fill bare when the colour jumps there (its
    3 x 3 colour span above ``edge``: a seam between matching colours is
    invisible) and no ink pixel (luminance at most the image's ink
    threshold, as in :func:`~branchnb.trees.outline.silhouette_outline`,
    and at most 0.25) lies within ``reach`` pixels (default: the outline
    width + 1): two fills meet with a hard edge that no drawing has. Without
    ``sources`` every inner colour edge counts as a seam (0 for a drawing
    whose fills are all outlined).

    Parameters
    ----------
    image : (H, W, 4) array_like
        The mix (straight RGBA).
    sources : (H, W) int array_like, optional
        Each pixel's exemplar index (-1 where transparent), as in
        :attr:`Variation.sources`; None treats every inner colour edge as a
        seam.
    edge : float
        Smallest 3 x 3 colour span (per channel) of a visible seam.
    reach : int, optional
        Distance in pixels within which an ink pixel covers a seam; None
        uses the outline width + 1.

    Returns
    -------
    float
        Bare seam pixels over all seam pixels (0 without seams).

    Raises
    ------
    ValueError
        If ``sources`` does not have the image's (H, W) shape.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((30, 30, 4), np.float32); img[5:25, 5:25] = (0.2, 0.6, 0.2, 1)
    >>> img[5:25, 15:25, :3] = (0.6, 0.8, 0.3)            # a second fill, no outline
    >>> src = np.where(img[..., 3] > 0, 0, -1); src[5:25, 15:25] = 1
    >>> round(bare_seam_share(img, src), 2)
    1.0
    >>> img[5:25, 14:16, :3] = 0.05                       # outlined
    >>> bare_seam_share(img, src)
    0.0
    """
    from .outline import _depth, _ink_threshold, _is_ink, _source_seams, silhouette_outline

    img = as_rgba(image, name="image")
    op = img[..., 3] >= 0.5
    if op.sum() < 9:
        return 0.0
    rgb = img[..., :3]
    ink = op & _is_ink(rgb, min(_ink_threshold(rgb, op), 0.25))
    if reach is None:
        reach = silhouette_outline(img).width + 1
    near_ink = ndi.binary_dilation(ink, iterations=int(reach)) if ink.any() else np.zeros_like(ink)
    inner = (_depth(op) > 2) & (ndi.minimum_filter(op, size=3) > 0)
    span = colour_span(np.where(op[..., None], rgb, 0.0), size=3)
    if sources is None:
        seam = inner & ~ink & (span > edge)
        bare = seam
    else:
        src = np.asarray(sources)
        if src.shape != op.shape:
            raise ValueError(f"sources must be an (H, W) array of shape {op.shape}, got {src.shape}")
        seam = _source_seams(src) & inner
        bare = seam & (span > edge)
    if not seam.any():
        return 0.0
    return float((bare & ~near_ink).sum() / seam.sum())


# Measures of flat-art mixes that read as one drawing (issue 24), kept in their own module.
from .quality_mix import (  # noqa: E402
    crown_sources,
    foreign_patches,
    outline_continuity,
    outline_width_spread,
    seam_through_flat,
    stray_ink,
)
from .quality_views import flat_region_speckle, side_view_figures  # noqa: E402
