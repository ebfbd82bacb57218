"""Outlined silhouettes of drawn trees: measure an exemplar's outline, ink a variation's rim.

Beyond the paper. A drawn tree is stroked with a dark outline along its
silhouette. A variation's contour is a convex combination of the
exemplars' contours, and the colour comes through cages of only ``M = 20``
vertices, so the new silhouette does not run along any exemplar's outline:
where it lies inside the mapped exemplar the outline is cut away, and the
crown or trunk ends in a bare flat fill (the paper's photographs have no
outline to lose). :func:`silhouette_outline` measures whether exemplars
are outlined (the share of their rim pixels in dark ink, the ink colour
and the stroke width) and :func:`ink_silhouette` draws that outline
along a variation's rim where it is missing, as an illustrator would.

Examples
--------
>>> import numpy as np
>>> img = np.zeros((20, 20, 4), np.float32); img[3:17, 3:17] = (0.2, 0.7, 0.2, 1)
>>> img[3:17, 3:5, :3] = img[3:17, 15:17, :3] = img[3:5, 3:17, :3] = img[15:17, 3:17, :3] = 0.05
>>> o = silhouette_outline(img)
>>> round(o.share, 2), o.width
(1.0, 2)
>>> bare = img.copy(); bare[3:17, 3:17, :3] = (0.2, 0.7, 0.2)
>>> inked = ink_silhouette(bare, o.ink, o.width)
>>> bool(np.allclose(inked, img))
True
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_rgba
from ..core.validate import check_int

__all__ = ["SilhouetteOutline", "silhouette_outline", "ink_silhouette", "even_outline", "ink_seams", "rim_ink_share",
           "floating_ink", "OUTLINED_SHARE"]

_LUM = np.array([0.299, 0.587, 0.114], np.float32)

#: An exemplar counts as outlined when at least this share of its rim
#: pixels are dark ink. Drawn trees (:mod:`branchnb.trees.drawn`) and the
#: outlined clip-art samples measure 0.9-1.0; photographed cut-outs and
#: unoutlined silhouettes well below 0.5.
OUTLINED_SHARE = 0.8


@dataclass(frozen=True)
class SilhouetteOutline:
    """An exemplar's silhouette outline.

    Parameters
    ----------
    share : float
        Share of the rim pixels (opaque, 8-adjacent to a transparent pixel)
        drawn in ink.
    ink : (3,) ndarray
        Median RGB of the inked rim pixels.
    width : int
        Stroke width in pixels: the deepest distance from the rim at which
        the ink share is still at least 3/4 of ``share``.
    inner_ink : float
        Share of ink among the pixels deeper than ``2 * width + 1`` (1 when
        there are none): a silhouette drawn all in ink has no outline.

    Examples
    --------
    >>> import numpy as np
    >>> o = SilhouetteOutline(0.9, np.zeros(3), 2, 0.0)
    >>> o.outlined
    True
    """

    share: float
    ink: np.ndarray
    width: int
    inner_ink: float = 0.0

    @property
    def outlined(self) -> bool:
        """Outlined silhouette: ``share >= OUTLINED_SHARE`` round a fill that is not ink itself."""
        return self.share >= OUTLINED_SHARE and self.inner_ink < 0.5


def _depth(alpha: np.ndarray) -> np.ndarray:
    """Chessboard distance of every opaque pixel from the nearest transparent one (rim: 1).

    The image border does not count as transparent (a trunk cut by the frame has no rim there).
    """
    if alpha.all():
        return np.full(alpha.shape, alpha.size, np.int64)
    return ndi.distance_transform_cdt(alpha, metric="chessboard")


def _is_ink(rgb: np.ndarray, ink_lum: float) -> np.ndarray:
    return rgb @ _LUM <= ink_lum


def _ink_threshold(rgb: np.ndarray, alpha: np.ndarray) -> float:
    """Luminance below which a pixel is ink: half-way from the darkest 2 % to the median fill."""
    lum = rgb[alpha] @ _LUM
    lo, mid = np.quantile(lum, 0.02), np.median(lum)
    return float(min(lo + 0.5 * (mid - lo), lo + 0.2))


def silhouette_outline(image, *, max_width: int = 12) -> SilhouetteOutline:
    """Measure the outline along a tree's silhouette.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA; opaque where alpha >= 0.5.
    max_width : int
        Deepest stroke considered (pixels).

    Returns
    -------
    SilhouetteOutline
        ``share`` 0 for an image without opaque pixels.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((12, 12, 4), np.float32); img[2:10, 2:10] = (0, 0, 0, 1)
    >>> img[3:9, 3:9] = (0.0, 0.6, 0.0, 1)        # a green fill with a 1 px black outline
    >>> o = silhouette_outline(img)
    >>> o.share, o.width, o.outlined
    (1.0, 1, True)
    """
    img = as_rgba(image, name="image")
    max_width = check_int(max_width, "max_width", min=1)
    alpha = img[..., 3] >= 0.5
    if alpha.sum() < 9:
        return SilhouetteOutline(0.0, np.zeros(3, np.float32), 1, 1.0)
    rgb = img[..., :3]
    depth = _depth(alpha)
    thr = _ink_threshold(rgb, alpha)
    ink = _is_ink(rgb, thr) & alpha
    rim = depth == 1
    share = float(ink[rim].mean())
    col = np.median(rgb[rim & ink], axis=0) if (rim & ink).any() else np.zeros(3)
    width = 1
    for d in range(2, max_width + 1):
        at = depth == d
        if not at.any() or ink[at].mean() < 0.75 * share:
            break
        width = d
    inner = depth > 2 * width + 1
    inner_ink = float(ink[inner].mean()) if inner.any() else 1.0
    return SilhouetteOutline(share, np.asarray(col, np.float32), width, inner_ink)


def rim_ink_share(image, ink) -> float:
    """Share of a tree's rim pixels within 0.15 (RGB distance) of the ``ink`` colour (0 without rim).

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA tree; alpha >= 0.5 is opaque. Rim pixels are opaque
        pixels 8-adjacent to a transparent one (the image border does not
        count as transparent).
    ink : (3,) array_like
        Outline colour, RGB in [0, 1] (e.g. ``SilhouetteOutline.ink``).

    Returns
    -------
    float
        Share in [0, 1] of rim pixels within 0.15 (Euclidean RGB) of ``ink``.

    Raises
    ------
    ValueError
        If ``ink`` is not 3 finite values.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((9, 9, 4)); img[2:7, 2:7] = (0, 0.6, 0, 1); img[2:7, 2, :3] = 0
    >>> rim_ink_share(img, (0, 0, 0))  # 5 of the 16 rim pixels are black
    0.3125
    """
    img = as_rgba(image, name="image")
    alpha = img[..., 3] >= 0.5
    rim = _depth(alpha) == 1
    if not rim.any():
        return 0.0
    ink = np.asarray(ink, np.float64)
    if ink.shape != (3,) or not np.all(np.isfinite(ink)):
        raise ValueError(f"ink must be 3 finite RGB values, got shape {ink.shape}")
    d = np.linalg.norm(img[rim][:, :3] - ink[None], axis=1)
    return float(np.mean(d <= 0.15))


def floating_ink(image, ink, *, tol: float = 0.25, return_mask: bool = False):
    """Loose stroke fragments: opaque pieces, apart from the tree, drawn mostly in ink.

    A side view of a billboard cloud (or an engine's view of an exported
    level) can show bits of outline that float beside or above the crown:
    card or billboard texels whose neighbours moved elsewhere. They are
    counted here as the 8-connected opaque components other than the
    largest one of which at least half the pixels lie within ``tol``
    (Euclidean RGB) of ``ink``. A drawing's own detached pieces (fruit on the
    ground, a sun) count too: compare with the front view.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA; opaque where alpha >= 0.5.
    ink : (3,) array_like
        Outline colour, RGB in [0, 1] (e.g. ``SilhouetteOutline.ink``).
    tol : float
        RGB distance within which a pixel is ink.
    return_mask : bool
        Also return the fragments' pixels, (H, W) bool.

    Returns
    -------
    int
        Number of floating ink fragments (and the mask with ``return_mask``).

    Raises
    ------
    ValueError
        If ``ink`` is not 3 finite values or ``tol`` is not positive.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((12, 12, 4)); img[2:9, 2:9] = (0, 0.6, 0, 1); img[2:9, 2, :3] = 0
    >>> floating_ink(img, (0, 0, 0))
    0
    >>> img[10, 5:8] = (0, 0, 0, 1)                  # a loose stroke under the crown
    >>> floating_ink(img, (0, 0, 0))
    1
    """
    img = as_rgba(image, name="image")
    ink = np.asarray(ink, np.float64)
    if ink.shape != (3,) or not np.all(np.isfinite(ink)):
        raise ValueError(f"ink must be 3 finite RGB values, got shape {ink.shape}")
    if not (np.isfinite(tol) and tol > 0):
        raise ValueError(f"tol must be > 0, got {tol}")
    op = img[..., 3] >= 0.5
    mask = np.zeros(op.shape, bool)
    lab, n = ndi.label(op, structure=np.ones((3, 3), bool))
    if n <= 1:
        return (0, mask) if return_mask else 0
    idx = np.arange(1, n + 1)
    size = ndi.sum(op, lab, idx)
    dark = np.linalg.norm(img[..., :3] - ink, axis=2) <= tol
    share = ndi.sum(dark, lab, idx) / np.maximum(size, 1)
    loose = (share >= 0.5) & (idx != idx[np.argmax(size)])
    if return_mask:
        mask = loose[np.maximum(lab - 1, 0)] & op
        return int(loose.sum()), mask
    return int(loose.sum())


def ink_silhouette(image, ink, width: int, *, holes: bool = True) -> np.ndarray:
    """Draw an outline ``width`` pixels wide along the silhouette where it is missing.

    Where a rim pixel (next to a transparent one) is lighter than the ink,
    the outline is missing: the light pixels within ``width`` (chessboard
    distance) of the silhouette and of that rim pixel take the ``ink``
    colour. Pixels already dark (the exemplars' own outlines and strokes)
    and stretches where the outline is intact are kept as drawn. The image's
    border does not count as transparent (a trunk cut by the frame stays
    open). Alpha is not changed, so the silhouette stays where it was.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA with binary alpha.
    ink : (3,) array_like
        Outline colour (``SilhouetteOutline.ink``).
    width : int
        Stroke width in pixels (>= 1).
    holes : bool
        Also outline interior transparent holes (False: the outer
        silhouette only).

    Returns
    -------
    (H, W, 4) float32 ndarray
        A copy.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((12, 12, 4), np.float32); img[2:10, 2:10] = (0, 0, 0, 1)
    >>> img[3:9, 3:9] = (0.0, 0.6, 0.0, 1); img[2:10, 9] = (0.0, 0.6, 0.0, 1)  # right side cut off
    >>> round(rim_ink_share(img, (0, 0, 0)), 2), rim_ink_share(ink_silhouette(img, (0, 0, 0), 1), (0, 0, 0))
    (0.71, 1.0)
    """
    img = np.array(as_rgba(image, name="image"), dtype=np.float32, copy=True)
    width = check_int(width, "width", min=1, max=64)
    ink = np.asarray(ink, np.float64)
    if ink.shape != (3,) or not np.all(np.isfinite(ink)):
        raise ValueError(f"ink must be 3 finite RGB values, got shape {ink.shape}")
    ink = ink.astype(np.float32)
    alpha = img[..., 3] >= 0.5
    if not alpha.any():
        return img
    depth = _depth(alpha if holes else ndi.binary_fill_holes(alpha))
    band = alpha & (depth <= width)
    ink_lum = float(ink @ _LUM)
    lum = img[..., :3] @ _LUM
    light = lum > ink_lum + 0.5 * (np.median(lum[alpha]) - ink_lum)
    # Only where the outline is missing: within ``width`` of a rim pixel that is not ink
    # (an intact outline, and the shading beside it, stay as drawn).
    bare = (depth == 1) & light
    if not bare.any():
        return img
    near = cv2.dilate(bare.astype(np.uint8), np.ones((2 * width + 1, 2 * width + 1), np.uint8)) > 0
    paint = band & light & near
    img[paint, :3] = ink
    return img


def even_outline(image, ink, width: int, *, holes: bool = True) -> np.ndarray:
    """Make a silhouette outline ``width`` pixels wide all round (beyond the paper).

    A mix warps each exemplar's outline through the cage, so the warped
    stroke drifts a few pixels off the mixed silhouette: where the
    silhouette cuts into the stroke, 1 px of it is left; where the
    silhouette lies outside it, :func:`ink_silhouette` inks the rim and the
    warped stroke lies beside or under that band, 3-5 px of ink (issue 24:
    1 px upper left, 3-4 px lower right). Here every light pixel within
    ``width`` of the silhouette takes the ``ink``, and every dark stretch
    deeper than ``width`` that runs on unbroken from the rim and *along*
    the silhouette (the warped stroke: its pixels' nearest rim pixels cover
    more than ``3 (width + 1)`` rim pixels, where an inner line that meets
    the silhouette covers about its own width) within ``2 width + 2`` of it
    takes the colour of the nearest
    fill pixel (within ``width + 2``), with the stroke's soft inner edge;
    dark regions thicker than ``2 width + 2`` (a dark trunk, a sprite's
    shadow) are fills and stay. Pixels of the ``width`` band lighter than
    ink + 0.35 of the way to the median colour take the colour of the
    nearest stroke pixel (the drawing's own ink colours), and
    the ring just inside the new stroke takes half the ink, as the
    drawings' anti-aliased strokes have. Inner lines, fruits and fills keep
    their colours.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA with binary alpha.
    ink : (3,) array_like
        Outline colour (``SilhouetteOutline.ink``).
    width : int
        Stroke width in pixels (>= 1).
    holes : bool
        Interior transparent holes have a silhouette too (False: the outer
        silhouette only).

    Returns
    -------
    (H, W, 4) float32 ndarray
        A copy; alpha unchanged.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((30, 30, 4), np.float32); img[3:27, 3:27] = (0.2, 0.6, 0.2, 1)
    >>> img[3:27, 3:4, :3] = 0; img[3:27, 22:27, :3] = 0      # 1 px on the left, 5 px on the right
    >>> out = even_outline(img, (0, 0, 0), 2)
    >>> [round(float(out[15, x, 1]), 1) for x in (3, 4, 5, 6, 20, 21, 22, 23, 24, 25, 26)]
    [0.0, 0.0, 0.3, 0.6, 0.6, 0.6, 0.6, 0.6, 0.3, 0.0, 0.0]
    """
    img = np.array(as_rgba(image, name="image"), dtype=np.float32, copy=True)
    width = check_int(width, "width", min=1, max=64)
    ink = np.asarray(ink, np.float64)
    if ink.shape != (3,) or not np.all(np.isfinite(ink)):
        raise ValueError(f"ink must be 3 finite RGB values, got shape {ink.shape}")
    alpha = img[..., 3] >= 0.5
    if alpha.sum() < 9 or alpha.all():
        return img
    depth = _depth(alpha if holes else ndi.binary_fill_holes(alpha))
    ink_lum = float(ink @ _LUM)
    lum = img[..., :3] @ _LUM
    inner, _ = _inner_shapes(alpha & (lum > ink_lum + 0.5 * (np.median(lum[alpha]) - ink_lum)), depth, width)
    img = _drop_excess(img, ink, width, holes)
    # Too thin: every pixel within ``width`` of the silhouette not ink takes the colour of the
    # nearest stroke pixel there (the drawing's own ink, ``ink`` where there is none), and the
    # next ring half of it (the drawings' own strokes have an anti-aliased inner edge).
    ink = ink.astype(np.float32)
    # An inner shape the silhouette cuts (a fruit the warp moved onto the rim) gets its own ring
    # there too: the drawings keep a ring and the outline, about 1.75 width, between it and the edge.
    band = alpha & ((depth <= width) | (inner & (depth <= int(1.75 * width))))
    strong = lum <= ink_lum + 0.35 * (np.median(lum[alpha]) - ink_lum)
    # Dark but not ink-coloured (an anti-aliased mix of a fruit's orange and the ink, dark red)
    # is no stroke colour: taken as one it was spread across the band, a 3-4 px smear (issue 24).
    # Nor are the pixels next to an inner shape that the band cuts (its soft edge into the ink).
    edge_of_inner = (cv2.dilate(inner.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0) & ~inner
    inky = strong & (np.linalg.norm(img[..., :3] - ink, axis=2) <= INK_COLOUR_TOL) & ~edge_of_inner
    thin = band & ~inky
    if thin.any():
        stroke = band & inky
        col = np.broadcast_to(ink, (int(thin.sum()), 3)).copy()
        if stroke.any():
            dist, idx = ndi.distance_transform_edt(~stroke, return_indices=True)
            by = dist[thin] <= 2 * width + 1
            col[by] = img[idx[0][thin][by], idx[1][thin][by], :3]
        img[thin, :3] = col
    lum = img[..., :3] @ _LUM
    soft = alpha & (depth == width + 1) & (lum > ink_lum + 0.5 * (np.median(lum[alpha]) - ink_lum))
    img[soft, :3] = 0.5 * (img[soft, :3] + ink)
    return img


def _dark_split(img: np.ndarray, alpha: np.ndarray, depth: np.ndarray, ink: np.ndarray, width: int):
    """``(light0, light)``: lighter than half-way from the ink to the median (``light0``), and
    that or a dark fill told from the ink by colour (``light``, :func:`_dark_fill`)."""
    ink_lum = float(np.asarray(ink, np.float64) @ _LUM)
    lum = img[..., :3] @ _LUM
    light0 = lum > ink_lum + 0.5 * (np.median(lum[alpha]) - ink_lum)
    return light0, light0 | _dark_fill(img, alpha & ~light0, depth, ink, width)


def _has_dark_fill(image: np.ndarray, ink, width: int) -> bool:
    """Whether a drawing has an ink-dark region thicker than ``2 width + 2`` (a black trunk, a
    sprite's shadow): what :func:`_drop_excess` keeps as a fill."""
    alpha = image[..., 3] >= 0.5
    if alpha.sum() < 9 or alpha.all():
        return False
    ink = np.asarray(ink, np.float64)
    _, light = _dark_split(image, alpha, _depth(alpha), ink, width)
    k = 2 * width + 3
    # the frame counts as transparent here: a stroke along a crown or foot cut by it is no fill
    return bool((cv2.morphologyEx((alpha & ~light).astype(np.uint8), cv2.MORPH_OPEN, np.ones((k, k), np.uint8),
                                  borderType=cv2.BORDER_CONSTANT, borderValue=0) > 0).any())


def _drop_excess(img: np.ndarray, ink: np.ndarray, width: int, holes: bool = True,
                 dark_fills: bool = True) -> np.ndarray:
    """:func:`even_outline`'s first step, in place: a warped stroke deeper than ``width`` that runs
    along the silhouette takes the colour of the nearest fill. ``dark_fills=False``: the sources
    have no dark fill (:func:`_has_dark_fill`), so a dark region thicker than ``2 width + 2`` is
    a stroke the warp stretched (the rim correction's local stretch), not a fill to keep."""
    alpha = img[..., 3] >= 0.5
    if alpha.sum() < 9 or alpha.all():
        return img
    depth = _depth(alpha if holes else ndi.binary_fill_holes(alpha))
    light0, light = _dark_split(img, alpha, depth, ink, width)
    dark = alpha & ~light
    # Too thick: dark pixels of the shell (width, 2 width + 2] connected to the band along the rim.
    # Only ink that runs on unbroken from the rim inwards (a stroke beside the rim with fill
    # between, a fruit's ring, stays).
    reach = dark & (depth == 1)
    shell = np.zeros_like(reach)
    for d in range(2, 2 * width + 3):
        reach = dark & (depth == d) & (cv2.dilate(reach.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0)
        if d > width:
            shell |= reach
    inner, ring = _inner_shapes(alpha & light, depth, width)
    lab, n = ndi.label(shell, np.ones((3, 3), bool))
    if n:
        rim = depth == 1
        near = ndi.distance_transform_edt(~rim, return_distances=False, return_indices=True)
        ys, xs = np.nonzero(lab)
        nearest = near[0][ys, xs] * depth.shape[1] + near[1][ys, xs]
        pairs = np.unique(np.stack([lab[ys, xs], nearest]), axis=1)
        foot = np.bincount(pairs[0], minlength=n + 1)
        along = foot > 3 * (width + 1)
        along[0] = False
        excess = along[lab]
        # Dark fills (a dark trunk, a sprite's shadow) are no stroke: thicker than 2 width + 2.
        k = 2 * width + 3
        thick = cv2.morphologyEx(dark.astype(np.uint8), cv2.MORPH_OPEN, np.ones((k, k), np.uint8)) > 0
        if not dark_fills:
            thick[:] = False
        excess &= ~(cv2.dilate(thick.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0)
        if dark_fills and (light != light0).any():
            # a dark fill told from the ink (_dark_fill) keeps its ink next to a light fill (the
            # crown's line across the trunk's top), as before: only its outline band is thinned
            thick0 = cv2.morphologyEx((alpha & ~light0).astype(np.uint8), cv2.MORPH_OPEN,
                                      np.ones((k, k), np.uint8)) > 0
            by_light = cv2.dilate(light0.astype(np.uint8), np.ones((2 * k - 1, 2 * k - 1), np.uint8)) > 0
            excess &= ~((cv2.dilate(thick0.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0) & by_light)
        excess &= ~ring
        if excess.any():
            # with the stroke's soft inner edge (its anti-aliased pixels, lighter than ``dark``)
            excess = cv2.dilate(excess.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
            excess &= alpha & (depth > width) & ~thick & ~ring
            fill = alpha & light & (depth > width + 1) & ~excess & ~inner
            if fill.any():
                dist, idx = ndi.distance_transform_edt(~fill, return_indices=True)
                # only next to a fill (a thin dark trunk has none beside it: it stays)
                excess &= dist <= width + 2
                excess &= ~_between_fills(excess, img[idx[0], idx[1], :3], width)
                img[excess, :3] = img[idx[0][excess], idx[1][excess], :3]
    return img


#: :func:`_between_fills`: ink whose nearest fills within one pen width differ by at least this
#: much (RGB, any channel) lies between two fills: a line of the drawing, not a stroke to thin.
BETWEEN_FILLS = 0.2


def _between_fills(excess: np.ndarray, nearest_fill: np.ndarray, width: int) -> np.ndarray:
    """Pixels of ``excess`` with fills of two different colours next to them (beyond the paper).

    A drawn crown's outline runs on across the trunk's top where the crown lies over the
    trunk; near the silhouette it is as deep as a stroke the warp thickened, and thinned like
    one it vanished: the crown's fill then met the bark with no line between (mixes of
    outlined flat-colour trees). A stroke along the rim has one fill beside it, a line across
    a part has a different fill on each side: the nearest fill's colour changes across it.
    """
    out = np.zeros_like(excess)
    rows, cols = np.nonzero(excess)
    if not len(rows):
        return out
    k = 2 * int(width) + 1
    # only round the excess (a thin band along the rim): the filters over the whole image were most of the cost
    box = (slice(max(rows.min() - k, 0), rows.max() + k + 1), slice(max(cols.min() - k, 0), cols.max() + k + 1))
    ex = excess[box]
    spread = np.zeros(ex.shape, np.float32)
    for ch in range(3):
        col = nearest_fill[box][..., ch].astype(np.float32)
        hi = ndi.maximum_filter(np.where(ex, col, -np.inf), size=k)
        lo = ndi.minimum_filter(np.where(ex, col, np.inf), size=k)
        spread = np.maximum(spread, np.where(ex, hi - lo, 0.0))
    out[box] = ex & (spread >= BETWEEN_FILLS)
    return out


#: :func:`_drop_excess`: a dark fill (a dark trunk) is told from the ink only when its colour is at
#: least this far (RGB) from it; nearer, the two are one colour and the fill stays as drawn.
DARK_FILL_TOL = 0.08


def _dark_fill(img: np.ndarray, dark: np.ndarray, depth: np.ndarray, ink: np.ndarray, width: int) -> np.ndarray:
    """Pixels of ``dark`` that belong to a dark fill rather than to the ink (trees33).

    A trunk drawn darker than the luminance threshold of the whole tree is "dark" with its
    outline: a warp that widened the trunk's stroke (ink bled into the widened trunk) left a
    band 2-3 times the pen, which :func:`_drop_excess` kept as a dark fill. Here the fill is the
    colour of the nearest flat dark pixel deeper than the pen (3 x 3 span below 0.06, no
    anti-aliased stroke edge) farther than :data:`DARK_FILL_TOL` from the ink, and a dark pixel
    within ``2 (2 width + 3)`` of it is fill when it lies nearer that colour than the ink, on the
    line between them (coverage below 1/2); fills within :data:`DARK_FILL_TOL` of the ink stay dark.
    """
    k = 2 * width + 3
    out = np.zeros_like(dark)
    core = dark & (depth > width + 1)
    if not core.any():
        return out
    # the fill: flat (3 x 3 span < 0.06, no anti-aliased stroke edge) and not ink-coloured
    rgb = img[..., :3]
    span = (ndi.maximum_filter(rgb, size=(3, 3, 1)) - ndi.minimum_filter(rgb, size=(3, 3, 1))).max(axis=2)
    core &= (span < 0.06) & (np.linalg.norm(rgb - np.asarray(ink, np.float32), axis=2) > DARK_FILL_TOL)
    if not core.any():
        return out
    dist, idx = ndi.distance_transform_edt(~core, return_indices=True)
    near = dark & (dist <= 2 * k)
    if not near.any():
        return out
    ys, xs = np.nonzero(near)
    fill = img[idx[0][ys, xs], idx[1][ys, xs], :3].astype(np.float64)
    d = fill - np.asarray(ink, np.float64)[None]
    n2 = (d * d).sum(axis=1)
    c = ((fill - img[ys, xs, :3]) * d).sum(axis=1) / np.maximum(n2, 1e-12)
    out[ys, xs] = (n2 >= DARK_FILL_TOL ** 2) & (c < 0.5)
    return out


#: :func:`even_outline`: a light piece is an inner shape (a fruit, a bauble) when it is smaller than
#: this share of the largest light piece (the crown's fill) ...
INNER_SHAPE_AREA = 0.1
#: ... and less than this share of its pixels lie within ``2 width + 2`` of the silhouette (a
#: trunk's or a thin part's fill runs along it; a fruit touching the outline touches it at a point)
#: or it is compact: its area at most this many discs of its widest inscribed circle (a fruit the
#: warp cut with the silhouette: a half disc is 2).
INNER_SHAPE_NEAR = 0.35
INNER_SHAPE_COMPACT = 2.5


#: :func:`even_outline`: a dark pixel of the outline band gives its colour to the band (a drawing's
#: own ink colours: dark green round a crown, dark brown round a trunk) only within this RGB
#: distance of the outline's ink; farther (a dark red between a fruit and the ink) it is repainted.
INK_COLOUR_TOL = 0.3


def _inner_shapes(light: np.ndarray, depth: np.ndarray, width: int) -> tuple[np.ndarray, np.ndarray]:
    """Inner shapes among the light pieces of a drawing and their own rings.

    A fruit drawn against the crown's outline has its own ring between its fill and the outline:
    the ink there is two strokes, deeper than ``width`` and running along the rim, so it looks
    like a warped stroke to thin. Repainting it with the nearest fill (the fruit's) ran the fruit's
    colour across its ring to the outline: the 3-4 px smear of issue 24. Returns the inner shapes'
    pixels and the pixels within ``width + 1`` of them that are not theirs (their rings).
    """
    lab, n = ndi.label(light, np.ones((3, 3), bool))
    if n < 2:
        z = np.zeros_like(light)
        return z, z
    area = np.bincount(lab.ravel(), minlength=n + 1)
    near = np.bincount(lab.ravel(), weights=(depth <= 2 * width + 2).ravel(), minlength=n + 1)
    area[0] = 0
    # compact (a disc, or a disc cut by the silhouette: area within 2.5 discs of its widest
    # inscribed circle) or mostly away from the rim; a trunk's fill is long and runs along it
    rad = ndi.maximum(ndi.distance_transform_edt(light), lab, np.arange(n + 1))
    compact = area <= INNER_SHAPE_COMPACT * np.pi * np.maximum(rad, 0.5) ** 2
    inner = (area < INNER_SHAPE_AREA * area.max()) & ((near < INNER_SHAPE_NEAR * area) | compact) & (area >= 4)
    inner[0] = False
    if not inner.any():
        z = np.zeros_like(light)
        return z, z
    shapes = inner[lab]
    k = 2 * width + 3
    ring = (cv2.dilate(shapes.astype(np.uint8), np.ones((k, k), np.uint8)) > 0) & ~shapes
    return shapes, ring


def _source_seams(sources: np.ndarray) -> np.ndarray:
    """Pixels on a seam: a 4-neighbour comes from another exemplar (both labels >= 0; -1 = none)."""
    src = np.asarray(sources)
    seam = np.zeros(src.shape, bool)
    for dy, dx in ((0, 1), (1, 0)):
        a, b = src[: src.shape[0] - dy, : src.shape[1] - dx], src[dy:, dx:]
        d = (a != b) & (a >= 0) & (b >= 0)
        seam[: src.shape[0] - dy, : src.shape[1] - dx] |= d
        seam[dy:, dx:] |= d
    return seam


def ink_seams(image, sources, ink, width: int, *, edge: float = 0.12) -> np.ndarray:
    """Outline the seams of a ``"choose"`` mix where they cross a fill (beyond the paper).

    Where two neighbouring pixels take their colours from different
    exemplars (``sources`` differ) and the colour jumps there (3 x 3 colour
    span above ``edge``) with no ink within ``width + 1`` pixels, two fills
    meet with a hard edge that none of the drawings has: the seam crossed a
    flat region. It is drawn as the exemplars draw their edges, a stroke
    ``width`` pixels wide in the ``ink`` colour centred on the seam.
    Seams along outlines (ink near) and across matching colours (no jump)
    are left as they are, as is every edge inside one exemplar's region.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA with binary alpha.
    sources : (H, W) int array_like
        Source index per pixel (``transfer_colour(..., return_sources=True)``), -1 outside.
    ink : (3,) array_like
        Stroke colour.
    width : int
        Stroke width in pixels.
    edge : float
        Smallest 3 x 3 colour span of a hard edge.

    Returns
    -------
    (H, W, 4) float32 ndarray
        A copy; alpha unchanged.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((20, 20, 4), np.float32); img[2:18, 2:18] = (0.2, 0.6, 0.2, 1)
    >>> img[2:18, 10:18, :3] = (0.6, 0.8, 0.3)
    >>> src = np.where(img[..., 3] > 0, 0, -1); src[2:18, 10:18] = 1
    >>> out = ink_seams(img, src, (0.05, 0.05, 0.05), 2)
    >>> [round(float(v), 2) for v in out[10, 8:12, 0]]
    [0.2, 0.05, 0.05, 0.6]
    """
    img = np.array(as_rgba(image, name="image"), dtype=np.float32, copy=True)
    src = np.asarray(sources)
    if src.shape != img.shape[:2]:
        raise ValueError(f"sources must be an (H, W) array of shape {img.shape[:2]}, got {src.shape}")
    width = check_int(width, "width", min=1, max=64)
    ink = np.asarray(ink, np.float64)
    if ink.shape != (3,) or not np.all(np.isfinite(ink)):
        raise ValueError(f"ink must be 3 finite RGB values, got shape {ink.shape}")
    op = img[..., 3] >= 0.5
    if not op.any():
        return img
    seam = _source_seams(src)
    if not seam.any():
        return img
    rgb = img[..., :3]
    lum = rgb @ _LUM
    thr = min(_ink_threshold(rgb, op), float(ink @ _LUM) + 0.15)
    inked = op & (lum <= thr)
    span = (ndi.maximum_filter(rgb, size=(3, 3, 1)) - ndi.minimum_filter(rgb, size=(3, 3, 1))).max(axis=2)
    near_ink = cv2.dilate(inked.astype(np.uint8), np.ones((2 * width + 3, 2 * width + 3), np.uint8)) > 0
    bare = seam & op & (span > edge) & ~near_ink
    if not bare.any():
        return img
    # The seam line between the pixel pairs, widened to ``width`` (the pairs are 2 px wide).
    grow = max(0, (width - 1) // 2)
    paint = cv2.dilate(bare.astype(np.uint8), np.ones((2 * grow + 1, 2 * grow + 1), np.uint8)) > 0 if grow else bare
    if width == 1:
        paint = bare & (src == ndi.maximum_filter(np.where(bare, src, -1), size=3))
    img[paint & op, :3] = ink.astype(np.float32)
    return img
