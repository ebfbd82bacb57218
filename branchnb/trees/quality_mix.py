"""Measures of flat-art mixes that should read as one drawing (issue 24, beyond the paper).

A ``"choose"`` mix of drawn trees can avoid cross-fades (:func:`~branchnb.trees.quality.crossfade_fraction`)
and still look like a collage. These numbers say where (all are re-exported by
:mod:`branchnb.trees.quality`):

* :func:`outline_continuity`: share of the new silhouette's rim drawn in ink
  (target >= 0.95 when an outlined exemplar is used);
* :func:`stray_ink`: open ink strokes inside the crown (pieces of a cut
  outline: target 0);
* :func:`seam_through_flat`: share of the seam length between sources that
  cuts through a flat fill of one of them instead of running along its
  colour edges;
* :func:`foreign_patches`: patches from an exemplar that holds less than 5 %
  of the tree (a lone fruit or clump of another style pasted in: target 0);
* :func:`outline_width_spread`: how evenly wide the silhouette's outline is
  (q90 / q10 of its thickness round the rim: close to the exemplars').

Examples
--------
>>> import numpy as np
>>> img = np.zeros((20, 20, 4), np.float32); img[2:18, 2:18] = (0.0, 0.0, 0.0, 1.0)
>>> img[3:17, 3:17, :3] = (0.2, 0.7, 0.2)
>>> outline_continuity(img, (0, 0, 0)), stray_ink(img)
(1.0, 0)
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_rgba
from ..core.validate import check_int, check_real

__all__ = ["outline_continuity", "stray_ink", "seam_through_flat", "foreign_patches", "crown_sources",
           "outline_width_spread"]

_EIGHT = np.ones((3, 3), bool)


def _ink_colour(ink) -> np.ndarray:
    ink = np.asarray(ink, np.float64)
    if ink.shape != (3,) or not np.all(np.isfinite(ink)):
        raise ValueError(f"ink must be 3 finite RGB values, got shape {ink.shape}")
    return ink


def outline_continuity(image, ink, *, tol: float = 0.2) -> float:
    """Share of a tree's silhouette rim drawn in the outline ink.

    Rim pixels are opaque pixels 8-adjacent to a transparent one (outer
    silhouette and the rims of holes; the image border does not count). A
    rim pixel is inked when its RGB lies within ``tol`` of ``ink`` or it is
    no lighter than the ink's luminance + ``tol`` (anti-aliased strokes).

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA; opaque where alpha >= 0.5.
    ink : (3,) array_like
        Outline colour (e.g. ``SilhouetteOutline.ink`` of the outlined exemplar used).
    tol : float
        RGB distance / luminance margin of an inked pixel.

    Returns
    -------
    float
        In [0, 1]; 0 when the image has no rim.

    Raises
    ------
    ValueError
        ``ink`` not 3 finite values, ``tol`` negative.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((9, 9, 4)); img[2:7, 2:7] = (0, 0.6, 0, 1); img[2:7, 2, :3] = 0
    >>> outline_continuity(img, (0, 0, 0))  # 5 of the 16 rim pixels are black
    0.3125
    """
    from .outline import _LUM, _depth

    img = as_rgba(image, name="image")
    ink = _ink_colour(ink)
    tol = check_real(tol, "tol", min=0.0)
    alpha = img[..., 3] >= 0.5
    rim = _depth(alpha) == 1
    if not rim.any():
        return 0.0
    rgb = img[rim][:, :3].astype(np.float64)
    near = np.linalg.norm(rgb - ink[None], axis=1) <= tol
    dark = rgb @ _LUM <= float(ink @ _LUM) + tol
    return float(np.mean(near | dark))


def _ink_and_width(img: np.ndarray, op: np.ndarray, width):
    from .outline import _ink_threshold, _is_ink, silhouette_outline

    rgb = img[..., :3]
    ink = op & _is_ink(rgb, min(_ink_threshold(rgb, op), 0.3))
    w = silhouette_outline(img).width if width is None else check_int(width, "width", min=1)
    return ink, int(w)


_FADING = True


def _weak_ink(img: np.ndarray, op: np.ndarray, ink: np.ndarray) -> np.ndarray:
    """Opaque pixels connected to ink through pixels less than 0.6 of the way from the ink to the
    fill beside them.

    A pixel half covered by a 1 px stroke (resampled) sits half-way between the ink and
    the fill it lies on (the lightest pixel within 2 px).
    """
    from .outline import _LUM

    if not ink.any() or ink.all():
        return np.zeros(op.shape, bool)
    lum = img[..., :3] @ _LUM
    dark = float(np.median(lum[ink]))
    fill = ndi.maximum_filter(np.where(op & ~ink, lum, dark), size=5)
    cand = op & ~ink & (lum <= dark + 0.6 * (fill - dark))
    if not _FADING:
        return cand & ndi.binary_dilation(ink, _EIGHT)
    # A stroke that fades out (an arc drawn lighter towards its end, resampled at a small size)
    # goes on through such pixels: every one connected to ink through them joins it (issue 24:
    # arbre_modern's fading arc at 96 px read as an open stroke).
    lab, n = ndi.label(cand | ink, structure=_EIGHT)
    hit = np.zeros(n + 1, bool)
    hit[np.unique(lab[ink])] = True
    hit[0] = False
    return cand & hit[lab]


def stray_ink(image, *, width: int | None = None, min_length: int | None = None,
              return_mask: bool = False):
    """Open ink strokes inside a tree: pieces of an outline that a mix cut out of its drawing.

    Ink pixels (as dark as the tree's outline, see
    :func:`~branchnb.trees.outline.silhouette_outline`) form 8-connected
    strokes. A stroke counts as stray when it lies wholly inside the tree
    (no pixel within ``2 * width + 2`` of the silhouette: an arc occluded by
    another shape ends on the outline, also where a mix moved the
    silhouette by a stroke's width), is thin (no pixel deeper than ``width + 1`` inside the
    stroke: solid dark shapes are fills, not strokes), is *open* (encloses
    no region even with one-pixel gaps closed: a whole fruit's or clump's
    outline is a ring, perhaps broken by resampling) and is
    at least ``min_length`` pixels. Drawings score 0.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA; opaque where alpha >= 0.5.
    width : int, optional
        Outline width in pixels (default: measured).
    min_length : int, optional
        Smallest stroke counted, in pixels (default ``max(8, 4 * width)``:
        shorter crumbs are left by resampling a warped stroke, where a
        fruit's ring meets a clump's outline; the fragments a mix cuts out
        of a drawing are 10-30 px long).
    return_mask : bool
        Also return the stray strokes' pixels, (H, W) bool.

    Returns
    -------
    int
        Number of stray strokes.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((30, 30, 4), np.float32); img[2:28, 2:28] = (0, 0, 0, 1)
    >>> img[3:27, 3:27, :3] = (0.2, 0.7, 0.2)
    >>> stray_ink(img)
    0
    >>> img[14, 8:20, :3] = 0.0                      # a loose line inside the crown
    >>> stray_ink(img)
    1
    """
    from .outline import _depth

    img = as_rgba(image, name="image")
    op = img[..., 3] >= 0.5
    found = np.zeros(op.shape, bool)
    if op.sum() < 9:
        return (0, found) if return_mask else 0
    ink, w = _ink_and_width(img, op, width)
    min_length = max(8, 4 * w) if min_length is None else check_int(min_length, "min_length", min=1)
    deep = _depth(ndi.binary_fill_holes(op)) > 2 * w + 2
    # Hysteresis: a thin stroke resampled at a small size (or where two strokes meet) has
    # pixels lighter than the ink threshold but still darker than 0.6 of the way to the fill; those
    # next to ink join its stroke, so a fruit's ring or an arc meeting another stays whole.
    weak = _weak_ink(img, op, ink)
    lab, n = ndi.label(ink | weak, structure=_EIGHT)
    if n == 0:
        return (0, found) if return_mask else 0
    touches = np.zeros(n + 1, bool)
    touches[np.unique(lab[(ink | weak) & ~deep])] = True
    size = np.bincount(lab[ink], minlength=n + 1)
    thick = ndi.distance_transform_cdt(ink, metric="chessboard")
    thickest = ndi.maximum(thick, lab, index=np.arange(n + 1))
    count = 0
    for i in np.flatnonzero(~touches & (size >= min_length) & (np.asarray(thickest) <= w + 1)):
        if i == 0:
            continue
        sl = ndi.find_objects((lab == i).astype(np.int32))[0]
        # A ring broken by a pixel or two (resampling) is still a whole shape's outline.
        comp = ndi.binary_closing(np.pad(lab[sl] == i, 3), structure=_EIGHT)
        if ndi.binary_fill_holes(comp).sum() == comp.sum():
            count += 1
            found |= (lab == i) & ink
    return (count, found) if return_mask else count


def seam_through_flat(image, sources, *, span: float = 0.06) -> float:
    """Share of the seam length between sources that cuts through a flat fill of one of them.

    A seam pixel is an opaque pixel 4-adjacent to an opaque pixel of
    another source (``sources``), away from the silhouette's rim. It runs
    along its own source's drawing when its 3 x 3 window, restricted to
    pixels of the same source, has a colour edge (span above ``span``) or
    the pixel is ink; otherwise the seam cuts that source's flat fill, as
    scissors through a drawing do.

    Parameters
    ----------
    image : (H, W, 4) array_like
        The mix (straight RGBA).
    sources : (H, W) int array_like
        Each pixel's exemplar index, -1 where transparent
        (:attr:`~branchnb.trees.variations.Variation.sources`).
    span : float
        Largest 3 x 3 colour range (per channel) of a flat fill.

    Returns
    -------
    float
        Seam pixels cutting a flat fill over all seam pixels (0 without seams).

    Raises
    ------
    ValueError
        ``sources`` not of the image's (H, W) shape.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((20, 20, 4), np.float32); img[2:18, 2:18] = (0.2, 0.6, 0.2, 1)
    >>> src = np.where(img[..., 3] > 0, 0, -1); src[2:18, 10:18] = 1   # same fill, cut in two
    >>> seam_through_flat(img, src)
    1.0
    """
    from .outline import _depth, _source_seams

    img = as_rgba(image, name="image")
    src = np.asarray(sources)
    if src.shape != img.shape[:2]:
        raise ValueError(f"sources must be an (H, W) array of shape {img.shape[:2]}, got {src.shape}")
    span = check_real(span, "span", min=0.0)
    op = img[..., 3] >= 0.5
    if op.sum() < 9:
        return 0.0
    src = np.where(op, src, -1)
    seam = _source_seams(src) & (_depth(op) > 1)
    if not seam.any():
        return 0.0
    ink, _ = _ink_and_width(img, op, 1)
    rgb = img[..., :3]
    flat = np.zeros(op.shape, bool)
    for k in np.unique(src[seam]):
        mine = src == k
        hi = ndi.maximum_filter(np.where(mine[..., None], rgb, -1.0), size=(3, 3, 1))
        lo = ndi.minimum_filter(np.where(mine[..., None], rgb, 2.0), size=(3, 3, 1))
        flat |= seam & mine & ((hi - lo).max(axis=2) <= span)
    flat &= ~ink
    return float(flat.sum() / seam.sum())


def crown_sources(sources, parts=None, *, share: float = 0.05) -> int:
    """Number of exemplars that paint at least ``share`` of a mix's crown (its crown styles).

    Parameters
    ----------
    sources : (H, W) int array_like
        Each pixel's exemplar index, -1 where transparent.
    parts : (H, W) array_like, optional
        1 crown, 2 trunk (:attr:`~branchnb.trees.variations.Variation.parts`);
        None counts every opaque pixel as crown.
    share : float
        Smallest share of the crown's pixels.

    Returns
    -------
    int

    Examples
    --------
    >>> import numpy as np
    >>> src = np.zeros((10, 10), int); src[:, 9] = 1
    >>> crown_sources(src), crown_sources(src, share=0.2)
    (2, 1)
    """
    src = np.asarray(sources)
    share = check_real(share, "share", min=0.0, max=1.0)
    crown = (src >= 0) if parts is None else (src >= 0) & (np.asarray(parts) == 1)
    n = int(crown.sum())
    if n == 0:
        return 0
    counts = np.bincount(src[crown])
    return int(np.count_nonzero(counts >= share * n))


def foreign_patches(sources, parts=None, *, share: float = 0.05, min_area: int = 4) -> int:
    """Patches of a mix's crown that come from an exemplar used almost nowhere else.

    An exemplar whose pixels (crown and trunk) are fewer than ``share`` of
    the crown's contributes no part of the tree, only pasted pieces: each
    8-connected piece of it in the crown of at least ``min_area`` pixels
    counts (a lone fruit on another tree, one clump of another style).

    Parameters
    ----------
    sources : (H, W) int array_like
        Each pixel's exemplar index, -1 where transparent.
    parts : (H, W) array_like, optional
        1 crown, 2 trunk; None counts every opaque pixel as crown.
    share : float
        Share of the crown below which an exemplar is foreign.
    min_area : int
        Smallest patch counted, in pixels.

    Returns
    -------
    int
        Number of foreign patches (target 0).

    Examples
    --------
    >>> import numpy as np
    >>> src = np.zeros((40, 40), int); src[10:14, 10:14] = 1   # a 16 px patch of another tree
    >>> foreign_patches(src), foreign_patches(src, share=0.005)
    (1, 0)
    """
    src = np.asarray(sources)
    share = check_real(share, "share", min=0.0, max=1.0)
    min_area = check_int(min_area, "min_area", min=1)
    crown = (src >= 0) if parts is None else (src >= 0) & (np.asarray(parts) == 1)
    n = int(crown.sum())
    if n == 0:
        return 0
    total = np.bincount(src[src >= 0])
    count = 0
    for k in np.flatnonzero((total > 0) & (total < share * n)):
        lab, m = ndi.label(crown & (src == k), structure=_EIGHT)
        if m:
            count += int(np.count_nonzero(np.bincount(lab.ravel())[1:] >= min_area))
    return count


def outline_width_spread(image, ink=None) -> tuple[float, float, float]:
    """Thickness of the silhouette's outline round the rim: its 10th, 50th and 90th percentiles.

    At every inked rim pixel (opaque, 8-adjacent to a transparent one, and
    closer to the ink than to the fill: luminance below ink + 0.35 of the
    way to the median) the outline is as thick as the Euclidean distance to
    the nearest opaque pixel that is not ink; thicknesses above
    ``4 width + 2`` (a dark trunk, an inner line running inward) are left
    out. A drawing stroked with one pen has q90 / q10 about 1.4-1.6 (the
    distance across a diagonal stroke is longer); a mix whose warped
    outline drifted off its silhouette measured 1.6-3.6 (issue 24).

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA; opaque where alpha >= 0.5.
    ink : (3,) array_like, optional
        Outline colour (default: :func:`~branchnb.trees.outline.silhouette_outline`'s).

    Returns
    -------
    (float, float, float)
        q10, q50, q90 in pixels (nan with fewer than 10 inked rim pixels).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 40, 4), np.float32); img[4:36, 4:36] = (0, 0, 0, 1)
    >>> img[6:34, 6:34, :3] = (0.2, 0.7, 0.2)                 # a 2 px outline all round
    >>> [round(v, 1) for v in outline_width_spread(img)]
    [2.0, 2.0, 2.0]
    >>> img[6:34, 6:9, :3] = 0.0                              # 5 px on the left
    >>> [round(v, 1) for v in outline_width_spread(img)]
    [2.0, 2.0, 5.0]
    """
    from .outline import _LUM, _depth, silhouette_outline

    img = as_rgba(image, name="image")
    a = img[..., 3] >= 0.5
    o = silhouette_outline(img)
    ink = o.ink if ink is None else _ink_colour(ink)
    if a.sum() < 9 or a.all():
        return (float("nan"),) * 3
    lum = img[..., :3] @ _LUM
    il = float(np.asarray(ink, np.float32) @ _LUM)
    inked = a & (lum <= il + 0.35 * (np.median(lum[a]) - il))
    fill = a & ~inked
    if not fill.any():
        return (float("nan"),) * 3
    d = ndi.distance_transform_edt(~fill)
    w = d[(_depth(a) == 1) & inked]
    w = w[w <= 4 * max(o.width, 1) + 2]
    if len(w) < 10:
        return (float("nan"),) * 3
    q10, q50, q90 = np.quantile(w, [0.1, 0.5, 0.9])
    return float(q10), float(q50), float(q90)
