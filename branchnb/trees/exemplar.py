"""Exemplar processing: normalisation and contour extraction (paper, Sec. "Exemplar processing").

Every tree image of the library goes through the same steps before it can be
combined with others:

1. **Normalisation** (:func:`normalize_exemplar`): the alpha channel is
   thresholded at 0.5, transparent pixels become black, the image is cropped
   to the bounding box of the opaque pixels, padded to a square without
   distortion (the tree centred horizontally and standing on the bottom edge)
   and resized to a working size (1024 x 1024 by default).
2. **Contours** (:func:`extract_contours`): the borders of the opaque region
   are traced with Suzuki & Abe's border-following algorithm
   (``cv2.findContours`` with ``RETR_CCOMP``), which classifies each border
   as *exterior* (an outer boundary) or *interior* (the boundary of a hole);
   the longest exterior border is the tree contour ``C``.

Bad input is handled at the door: an image without alpha raises a
``ValueError`` that points to :func:`alpha_from_background`; fully transparent
and fully opaque images raise; several disconnected opaque regions are
resolved by ``components`` (keep the largest by default, see
:func:`normalize_exemplar`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_float_image, as_mask, as_rgba, composite_over
from ..core.io import encode_png
from ..core.matte import matte_from_background
from ..core.params import check_params, param
from ..core.render import draw_polylines
from ..core.validate import MAX_PIXELS, Array, Int, Real, checked
from ..core.validate_arrays import as_colour
from .pixel_art import _detect as _detect_pixel_art

__all__ = [
    "ExemplarParams",
    "Normalized",
    "alpha_from_background",
    "normalize_exemplar",
    "tree_rgba",
    "ContourSet",
    "extract_contours",
    "signed_area",
]


@dataclass
class ExemplarParams:
    """Parameters of exemplar normalisation (defaults: the paper's).

    Parameters
    ----------
    size : int
        Working size ``S``: the normalised image is ``S x S`` (paper: 1024).
    alpha_threshold : float
        Pixels with alpha >= this are opaque (paper: 0.5).
    components : str
        What to do with several disconnected opaque regions: ``"largest"``
        keeps the largest one (8-connectivity) and drops the rest (small
        specks and other trees alike), ``"all"`` keeps everything (only the
        longest exterior border becomes ``C``), ``"error"`` raises a
        ``ValueError`` when a second region has at least
        ``second_tree_fraction`` of the largest one's area (specks are
        dropped).
    second_tree_fraction : float
        Area ratio above which a second region counts as a second tree.
    sprite_pixels : bool
        Pixel art worked on at about its own size (``size`` at most
        ``SPRITE_SIZE``, not reduced) keeps its hard pixels, palette and
        1 px outline, however small its pixels (beyond the paper; set by
        :class:`~branchnb.trees.library.TreeLibrary`'s automatic size).
        False by default: the paper's resampling.

    Examples
    --------
    >>> ExemplarParams(size=256).components
    'largest'
    """

    size: int = param(1024, min=32, max=4096, step=32, help="working size S (paper: 1024)")
    alpha_threshold: float = param(0.5, min=0.01, max=0.99, step=0.01,
                                   help="alpha threshold (paper: 0.5)")
    components: str = param("largest", options=("largest", "all", "error"),
                            help="several disconnected regions: keep largest / all / raise")
    second_tree_fraction: float = param(0.1, min=0.0, max=1.0, step=0.01,
                                        help="area ratio making a second region a second tree",
                                        ui=False)
    sprite_pixels: bool = param(False, help="keep a sprite's hard pixels at about its own size", ui=False)


@checked(tol=Real(0, 2))
def alpha_from_background(image, tol: float = 0.1, *, background=None,
                          connected: bool = False) -> np.ndarray:
    """Give an RGB image an alpha channel by keying out its background colour.

    Parameters
    ----------
    image : (H, W, 3) or (H, W, 4) array_like
        The picture (an existing alpha channel is ignored).
    tol : float
        A pixel is background when every channel differs from the
        background colour by at most ``tol`` (Chebyshev distance, in [0, 1]).
    background : 3-tuple or "smooth", optional
        Background colour; by default the median colour of the image border.
        ``"smooth"``: the ground is a smooth model fitted at the border (a
        sky gradient over grass, light paper) and alpha is a soft matte
        (:func:`~branchnb.core.matte.matte_from_background`; ``tol`` is then
        its colour tolerance, and ``connected`` is implied).
    connected : bool
        If True only background-coloured pixels connected to the image
        border become transparent (keeps background-coloured details inside
        the tree, e.g. white highlights); if False every background-coloured
        pixel does (also the sky seen through the crown).

    Returns
    -------
    (H, W, 4) float32 ndarray
        RGBA image with alpha 0 on the background and 1 elsewhere.

    Raises
    ------
    ValueError
        ``tol`` outside [0, 1], a background colour that is not an RGB triple,
        or ``background="smooth"`` on a picture whose ground is not smooth.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((8, 8, 3), np.float32); img[2:6, 3:5] = (0.2, 0.5, 0.1)
    >>> float(alpha_from_background(img)[..., 3].sum())
    8.0

    A tree on a sky gradient (one colour cannot key it out):

    >>> sky = np.linspace(0.4, 0.95, 64, dtype=np.float32)[:, None, None] * np.ones((64, 64, 3), np.float32)
    >>> sky[16:48, 28:36] = (0.3, 0.2, 0.1)
    >>> float(alpha_from_background(sky, background="smooth")[..., 3].sum())
    256.0
    """
    img = as_float_image(image)
    if img.shape[2] == 1:
        img = np.repeat(img, 3, axis=2)
    rgb = img[:, :, :3]
    if not (0.0 <= float(tol) <= 1.0):
        raise ValueError(f"tol must lie in [0, 1], got {tol}")
    if isinstance(background, str):
        if background != "smooth":
            raise ValueError(f'background must be an RGB triple or "smooth", got {background!r}')
        matte = matte_from_background(rgb, tol=float(tol) if tol > 0 else None)
        if matte is None:
            raise ValueError("background='smooth': the image's ground is not smooth (a busy photo); "
                             "give an RGBA image or key one colour with background=(r, g, b)")
        return matte.image
    if background is not None:
        background = as_colour(background, "background", channels=(3,))
    if background is None:
        border = np.concatenate([rgb[0], rgb[-1], rgb[:, 0], rgb[:, -1]], axis=0)
        bg = np.median(border, axis=0)
    else:
        bg = np.asarray(background, dtype=np.float32)
        if bg.shape != (3,) or not np.all(np.isfinite(bg)):
            raise ValueError(f"background must be an RGB triple, got {background!r}")
    is_bg = np.max(np.abs(rgb - bg), axis=2) <= tol
    if connected:
        n, labels = cv2.connectedComponents(is_bg.astype(np.uint8), connectivity=4)
        edge = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
        edge = edge[edge > 0]
        is_bg = np.isin(labels, edge)
    alpha = (~is_bg).astype(np.float32)
    return np.dstack([rgb, alpha]).astype(np.float32)


@dataclass
class Normalized:
    """A normalised exemplar and the transform that produced it.

    Parameters
    ----------
    image : (S, S, 4) float32 ndarray
        RGBA with binary alpha and black transparent pixels.
    box : (int, int, int, int)
        ``(x0, y0, x1, y1)`` crop of the source image (x1, y1 exclusive).
    scale : float
        Working pixels per source pixel.
    offset : (float, float)
        ``(x, y)`` of the crop's top-left corner in the working image.
    source_shape : (int, int)
        ``(H, W)`` of the source image.
    dropped_components : int
        Opaque regions removed (``components="largest"``/``"error"``).
    pixel_art : PixelArt or None
        Set when the source is pixel art (:mod:`~branchnb.trees.pixel_art`:
        hard-edged, few colours); the image was then resized nearest.
    soft_alpha : (S, S) float32 ndarray or None
        The source's own (anti-aliased) alpha resampled like ``image``
        (None for pixel art); the thin-structure mix of bare trees keeps its
        soft edges (:mod:`~branchnb.trees.bare`). For a translucent source
        (:mod:`~branchnb.trees.translucent`) it is the source's own alpha,
        which the variations carry through the mix.
    alpha_level : float
        The source alpha the silhouette was taken at: 0.5 (the paper's
        threshold) unless the source is translucent (beyond the paper,
        :func:`~branchnb.trees.translucent.translucent_level`).
    rim_softness : float or None
        Share of the source's own rim pixels (either side of its thresholded
        edge, before resampling) with partial alpha (0.05-0.95): about 0
        for hard-edged drawings, which a smooth resize softens at the
        working size (the mixes' rims stay hard for them,
        :mod:`~branchnb.trees.rim_alpha`); None when not measured.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 20, 4), np.float32); img[5:35, 5:15] = (0.2, 0.6, 0.2, 1)
    >>> n = normalize_exemplar(img, size=64)
    >>> n.image.shape, n.box, n.scale
    ((64, 64, 4), (5, 5, 15, 35), 2.1)
    """

    image: np.ndarray
    box: tuple[int, int, int, int]
    scale: float
    offset: tuple[float, float]
    source_shape: tuple[int, int]
    dropped_components: int = 0
    pixel_art: object = None
    soft_alpha: np.ndarray | None = None
    alpha_level: float = 0.5
    rim_softness: float | None = None

    @property
    def alpha(self) -> np.ndarray:
        """Binary opacity mask ``(S, S)`` bool."""
        return self.image[:, :, 3] >= 0.5

    def to_working(self, points) -> np.ndarray:
        """Map source-image points ``(x, y)`` to the working image.

        Parameters
        ----------
        points : (..., 2) array_like
            Points (x, y) in source-image pixels (pixel centres at integers).

        Returns
        -------
        (..., 2) float64 ndarray
            The same points in working-image pixels (crop, scale, offset).

        Examples
        --------
        >>> import numpy as np
        >>> n = Normalized(np.zeros((8, 8, 4)), (2, 2, 6, 6), 2.0, (0.0, 0.0), (10, 10))
        >>> n.to_working([(2, 2), (5, 5)]).tolist()
        [[0.5, 0.5], [6.5, 6.5]]
        """
        p = np.asarray(points, dtype=np.float64)
        x0, y0 = self.box[:2]
        # pixel centres: source centre c maps to (c - x0 + 0.5) * s - 0.5 + offset
        return (p - (x0, y0) + 0.5) * self.scale - 0.5 + np.asarray(self.offset)

    def warp_mask(self, mask) -> np.ndarray:
        """Bring a mask aligned with the source image (e.g. a hand-labelled
        trunk mask) into the working image (nearest neighbour).

        Parameters
        ----------
        mask : (H, W) array_like
            Mask of the source image's shape (``source_shape``); non-zero
            is True.

        Returns
        -------
        (S, S) bool ndarray
            The mask cropped, scaled and placed like the exemplar.

        Raises
        ------
        ValueError
            If ``mask`` does not have the source image's shape.
        """
        m = as_mask(mask, shape=self.source_shape, name="mask")
        x0, y0, x1, y1 = self.box
        s = self.image.shape[0]
        a = np.array([[self.scale, 0, self.offset[0] + 0.5 * self.scale - 0.5],
                      [0, self.scale, self.offset[1] + 0.5 * self.scale - 0.5]], np.float64)
        crop = m[y0:y1, x0:x1].astype(np.uint8)
        out = cv2.warpAffine(crop, a, (s, s), flags=cv2.INTER_NEAREST,
                             borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        return out.astype(bool)

    def _repr_png_(self) -> bytes:
        return encode_png(composite_over(self.image, (1.0, 1.0, 1.0)))


#: Pixel art (:mod:`~branchnb.trees.pixel_art`) is kept hard when its art pixels are at
#: least this many working pixels across; smaller ones (a hard-edged drawing at about its
#: own size) are resampled as before.
ART_PIXEL_MIN = 2.0
#: ... unless the working size is at most this and the art is not reduced (beyond the paper: a
#: sprite worked on at about its own size, :class:`~branchnb.trees.library.TreeLibrary`'s
#: automatic size, keeps its hard pixels, palette and 1 px outline).
SPRITE_SIZE = 256


#: A soft (semi-transparent) region of a source is a shape of its own, not the anti-aliased edge of
#: the tree, when less than this share of its pixels touch (8-adjacent) the opaque tree.
SOFT_EDGE_SHARE = 0.5


def _drop_cast_shadows(alpha: np.ndarray, opaque: np.ndarray, threshold: float) -> np.ndarray:
    """``alpha`` with the soft regions that are shapes of their own (not the tree's anti-aliased
    edge) made transparent, for the pixel-art test.

    Beyond the paper (issue 24): game sprites draw a soft cast-shadow ellipse (alpha <= 0.35) at
    the trunk foot. It lies under the alpha threshold, so it is no part of the exemplar, but its
    soft pixels told :func:`~branchnb.trees.pixel_art._detect` the sprite was anti-aliased: the
    same hard-edged, outlined sprite went to the pixel-art path without a shadow and was resampled
    smoothly with one (its 1 px outline blurred, trunk edges left without a dark line). An
    anti-aliased edge hugs the opaque silhouette; a cast shadow mostly lies away from it.
    """
    soft = (alpha > 1.0 / 255) & (alpha < threshold)
    if not soft.any():
        return alpha
    lab, n = ndi.label(soft, structure=np.ones((3, 3), bool))
    hug = ndi.binary_dilation(opaque, structure=np.ones((3, 3), bool))
    idx = np.arange(1, n + 1)
    share = ndi.mean(hug.astype(np.float64), lab, idx)
    own = np.isin(lab, idx[np.asarray(share) < SOFT_EDGE_SHARE])
    if not own.any():
        return alpha
    return np.where(own, 0.0, alpha)


def _select_components(opaque: np.ndarray, mode: str, second_fraction: float):
    n, labels, stats, _ = cv2.connectedComponentsWithStats(opaque.astype(np.uint8), connectivity=8)
    if n <= 2:  # background + one region
        return opaque, 0
    areas = stats[1:, cv2.CC_STAT_AREA]
    order = np.argsort(areas)[::-1]
    largest = int(order[0]) + 1
    if mode == "all":
        return opaque, 0
    if mode == "error":
        big = areas[order[1:]] >= second_fraction * areas[order[0]]
        if big.any():
            raise ValueError(
                f"image contains {1 + int(big.sum())} disconnected trees (opaque regions of "
                f"{', '.join(str(int(a)) for a in areas[order[: 1 + int(big.sum())]])} pixels); "
                "crop it to one tree or use components='largest' or 'all'"
            )
    return labels == largest, n - 2


@checked(alpha_threshold=Real(0, 1, low_open=True), min_pixels=Int(0, MAX_PIXELS))
def tree_rgba(image, *, alpha_threshold: float = 0.5, min_pixels: int = 1,
              name: str = "image") -> tuple[np.ndarray, np.ndarray]:
    """Validate an RGBA tree image; return ``(rgba float32, opaque mask)``.

    The door every tree function walks its input through (normalisation,
    segmentation, billboard clouds).

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA tree image, floats in [0, 1] or uint8/uint16 (scaled
        to [0, 1]).
    alpha_threshold : float
        Pixels with alpha >= this are opaque (paper: 0.5), in [0, 1].
    min_pixels : int
        Fewest opaque pixels accepted (at least 1).
    name : str
        Argument name used in error messages.

    Returns
    -------
    rgba : (H, W, 4) float32 ndarray
        The image as float32 in [0, 1].
    opaque : (H, W) bool ndarray
        ``alpha >= alpha_threshold``.

    Raises
    ------
    ValueError
        No alpha channel (make one from the background colour with
        :func:`alpha_from_background`), no opaque pixel, or no transparent
        pixel (no silhouette).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((8, 8, 4)); img[2:6, 3:5] = 1.0
    >>> int(tree_rgba(img)[1].sum())
    8
    """
    img = as_float_image(image, name=name)
    if img.shape[2] != 4:
        raise ValueError(
            f"{name} must be RGBA (H, W, 4) with the tree opaque on a transparent background, "
            f"got {img.shape[2]} channel(s); make an alpha channel with alpha_from_background(image, tol) "
            f"(background='smooth' for a gradient or paper ground)"
        )
    if not 0.0 <= alpha_threshold <= 1.0:
        raise ValueError(f"alpha_threshold must be in [0, 1], got {alpha_threshold}")
    mask = img[:, :, 3] >= alpha_threshold
    if mask.sum() < max(min_pixels, 1):
        raise ValueError(f"{name} is (almost) fully transparent: fewer than min_pixels = {max(min_pixels, 1)} "
                         f"pixel(s) with alpha >= {alpha_threshold}")
    if mask.all():
        raise ValueError(
            f"{name} is fully opaque (alpha >= alpha_threshold = {alpha_threshold:g} everywhere): there is "
            "no background to separate the tree from; "
            "make one with alpha_from_background(image, tol)"
        )
    return img, mask


@checked()
def normalize_exemplar(image, params: ExemplarParams | None = None, *, defringe: bool = True,
                       **overrides) -> Normalized:
    """Normalise a tree image (paper: threshold, black background, crop, square, resize).

    Parameters
    ----------
    image : (H, W, 4) array_like
        RGBA tree image with a transparent background. Images without an
        alpha channel are refused; key the background out first with
        :func:`alpha_from_background`.
    params : ExemplarParams, optional
        ``size`` (S = 1024), ``alpha_threshold`` (0.5), ``components``.
    defringe : bool
        Give soft edge pixels that show the background's colour the tree's
        nearby colour (:func:`_defringe`); False for translucent sources,
        whose soft alpha is the paint's own coverage, not a matte
        (:mod:`~branchnb.trees.translucent`).
    **overrides
        Fields of ``params`` to override, e.g. ``size=256``.

    Returns
    -------
    Normalized
        ``.image`` is ``(S, S, 4)`` float32 with binary alpha, transparent
        pixels black, the opaque bounding box scaled to fit the square
        (its longer side spans the whole square), centred horizontally and
        touching the bottom edge.

    Raises
    ------
    ValueError
        No alpha channel, fully transparent or fully opaque image, several
        trees with ``components="error"``.

    Notes
    -----
    Resizing works on premultiplied colour (which the black background
    already is), then divides by the resampled alpha and thresholds it
    again at 0.5, so the edges neither darken nor blur.

    Pixel art (beyond the paper) is resized nearest. Soft regions lying
    apart from the opaque tree (a sprite's cast-shadow ellipse, below the
    threshold and dropped with the background) do not make a hard-edged
    source count as anti-aliased (:func:`_drop_cast_shadows`).

    Examples
    --------
    >>> from branchnb import data
    >>> normalize_exemplar(data.load("tree_rpg_01"), size=256).image.shape
    (256, 256, 4)
    """
    p = check_params(params if params is not None else ExemplarParams())
    if overrides:
        from dataclasses import replace
        p = check_params(replace(p, **overrides))
    img, opaque = tree_rgba(image, alpha_threshold=p.alpha_threshold)
    if defringe:
        img = _defringe(img, opaque)
    h, w = img.shape[:2]
    opaque, dropped = _select_components(opaque, p.components, p.second_tree_fraction)
    ys, xs = np.nonzero(opaque)
    x0, x1, y0, y1 = int(xs.min()), int(xs.max()) + 1, int(ys.min()), int(ys.max()) + 1
    bw, bh = x1 - x0, y1 - y0
    s = p.size
    scale = s / max(bw, bh)
    pre = img[y0:y1, x0:x1, :3] * opaque[y0:y1, x0:x1, None]
    rgba = np.dstack([pre, opaque[y0:y1, x0:x1].astype(np.float32)])
    nw, nh = max(1, int(round(bw * scale))), max(1, int(round(bh * scale)))
    # Beyond the paper: pixel art keeps its hard pixels (a smooth resize draws its stair-steps
    # as anti-aliased curves and mixes colours no palette has).
    # (the raw alpha of the kept tree: soft edges say it is no pixel art; dropped regions are gone)
    a_raw = img[y0:y1, x0:x1, 3]
    kept = np.where(opaque[y0:y1, x0:x1] | (a_raw < p.alpha_threshold), a_raw, 0.0)
    kept = _drop_cast_shadows(kept, opaque[y0:y1, x0:x1], p.alpha_threshold)
    art = _detect_pixel_art(np.dstack([img[y0:y1, x0:x1, :3], kept]))
    if art is not None and art.block * scale < ART_PIXEL_MIN and not (
            p.sprite_pixels and s <= SPRITE_SIZE and scale >= 1.0):
        art = None          # art pixels this small show no stair-steps: resampled like any drawing
    interp = cv2.INTER_NEAREST if art is not None else cv2.INTER_AREA if scale < 1 else cv2.INTER_CUBIC
    small = cv2.resize(rgba, (nw, nh), interpolation=interp)
    small = np.clip(small, 0.0, 1.0)
    a = small[:, :, 3]
    keep = a >= 0.5
    rgb = np.where(keep[:, :, None], small[:, :, :3] / np.maximum(a, 1e-6)[:, :, None], 0.0)
    out = np.zeros((s, s, 4), np.float32)
    ox, oy = (s - nw) // 2, s - nh
    out[oy:oy + nh, ox:ox + nw, :3] = np.clip(rgb, 0.0, 1.0)
    out[oy:oy + nh, ox:ox + nw, 3] = keep
    if not keep.any():
        raise ValueError("the opaque region vanishes at this working size; use a larger size")
    soft = None
    if art is None:     # the anti-aliased edge, for bare trees' mixes (bare.py)
        soft = np.zeros((s, s), np.float32)
        soft[oy:oy + nh, ox:ox + nw] = np.clip(cv2.resize(kept.astype(np.float32), (nw, nh), interpolation=interp),
                                               0.0, 1.0)
    op = opaque[y0:y1, x0:x1]
    rim = ndi.binary_dilation(op) & ~ndi.binary_erosion(op, border_value=0)
    rim_soft = float(((kept[rim] > 0.05) & (kept[rim] < 0.95)).mean()) if rim.any() else 0.0
    return Normalized(out, (x0, y0, x1, y1), float(nw / bw), (float(ox), float(oy)), (h, w),
                      dropped, art, soft, rim_softness=rim_soft)


#: Defringing: a soft-edged opaque pixel (alpha below FRINGE_ALPHA) is background matted in when its
#: colour lies within FRINGE_BG of the transparent pixels around it and farther than FRINGE_FAR from
#: the nearest solid pixel.
FRINGE_ALPHA = 0.9
FRINGE_BG = 0.12
FRINGE_FAR = 0.2
#: Transparent pixels darker than this (every channel) are cleared, not a background colour.
FRINGE_DARK = 0.15
#: Composited edges: a soft opaque pixel is ``a * tree + (1 - a) * matte`` (premultiplied, or cut
#: from a dark matte / sky) when that model explains its colour within FRINGE_MIX and at most half
#: as far as the tree's own nearby colour does, which lies farther than FRINGE_NEAR.
FRINGE_MIX = 0.1
FRINGE_NEAR = 0.06
#: ... and the tree's share ``t`` of that mix is at least this (an ink line over cleared black
#: pixels has t ~ 0: the drawing's own dark, kept).
FRINGE_T = 0.08
#: Unmixing divides by t when t is at least this; below, the pixel (almost all matte) takes the
#: inner colour.
FRINGE_T_DIV = 0.3
#: A drawn outline is no matte: a soft pixel is left as it is when its colour does not move towards
#: the tree's as alpha rises (from it to the colour at full alpha beside it, t grows by less than
#: FRINGE_RISE x the alpha step: a composite's colour follows its coverage, t ~ alpha; a
#: straight-colour anti-aliased line keeps its colour). When the colour at full alpha beside it is
#: itself this dark on the matte -> tree line (t below FRINGE_INK: a dark band at full alpha, ink),
#: a darker soft pixel (premultiplied ink) is unmixed only up to that band's colour, not the fill's.
FRINGE_INK = 0.35
FRINGE_RISE = 0.15
#: ... and by at least this (a painted rim a shade darker than the colour beside it is no matte).
FRINGE_RISE_MIN = 0.1
#: Farthest a matted-in rim pixel lies from a clear one (px).
FRINGE_REACH = 8
#: Smallest tree (long side of its opaque box, px) whose composited edges are unmixed: below it a
#: drawn 1 px anti-aliased outline never reaches full alpha and reads like a matte (96-128 px drawn
#: trees lost 12-98 outline pixels each), so small trees keep their edges as drawn.
FRINGE_MIN_SIZE = 192


def _full_alpha_share(rgb, a, solid, soft, ys, xs, inner, bg, near, far):
    """The tree's share ``t`` (on the matte -> inner colour line) of the colour at full alpha beside
    each soft pixel ``(ys, xs)``, and that pixel's alpha: the least over the solid pixels of its
    5 x 5 neighbourhood (a drawn line's own colour when one is there, not the fill past it), else
    its nearest solid pixel ``near``; NaN where that is ``far`` (a soft pixel inside a translucent
    patch: no rim, nothing matted in)."""
    d = inner - bg
    t = np.clip(((rgb - bg) * d).sum(axis=2) / np.maximum((d * d).sum(axis=2), 1e-6), 0.0, 1.0)
    box = np.ones((5, 5), bool)
    ring = ndi.binary_dilation(soft, box) & solid     # only where a soft pixel looks
    t_min = ndi.minimum_filter(np.where(ring, t, 2.0), footprint=box)[ys, xs]
    a_min = ndi.minimum_filter(np.where(ring, a, 2.0), footprint=box)[ys, xs]
    none = t_min > 1.5
    iy, ix = near
    t_min[none], a_min[none] = t[iy, ix][none], a[iy, ix][none]
    t_min[none & far] = np.nan
    return t_min, a_min


def _defringe(img: np.ndarray, opaque: np.ndarray) -> np.ndarray:
    """Opaque soft-edge pixels that show the background's colour take the tree's nearby colour.

    Beyond the paper: a soft alpha (watercolour, blurred cut-outs) reaches 0.5 in the narrow notches
    between lobes, where the straight colour is the paper's; thresholded, these pixels become opaque
    paper-white specks on the rim, which a warp that stretches the lobe 2-4x draws as white slits.
    Only pixels whose colour matches the transparent surroundings (within ``FRINGE_BG``) and is far
    from the tree's own nearest colour are replaced, so a binary alpha (all samples, pixel art,
    keyed photos) and soft edges of the tree's own colour are unchanged; transparent pixels cleared
    to black carry no background colour, so a dark outline over them is kept by this rule.

    Also beyond the paper: edges composited over a matte (premultiplied RGBA, cut-outs from a black,
    dark-blue or dark-green background, trees photographed against a dark sky) hold
    ``t * c + (1 - t) * m`` for the tree's colour ``c`` and the matte ``m`` (the nearest transparent
    pixels' colour, black when cleared). Where that model explains a soft opaque pixel's colour
    (within ``FRINGE_MIX``, and at most half as far as the plain colour ``c`` of the nearby inner
    pixels does) the matte is taken out, ``(rgb - (1 - t) m) / t``. The tree's share ``t`` is
    fitted, not read from the alpha (a keyed photo's alpha runs wider than its colour edge). A dark
    outline drawn over cleared pixels keeps its colour: it is no mix of the fill beside it with black
    (t ~ 0). Trees smaller than ``FRINGE_MIN_SIZE`` keep their composited edges (a drawn 1 px outline
    there never reaches full alpha and cannot be told from a matte).
    """
    a = img[:, :, 3]
    soft = opaque & (a < FRINGE_ALPHA)
    if not soft.any():
        return img
    solid = a >= FRINGE_ALPHA
    clear = a < 0.1
    if not solid.any() or not clear.any():
        return img
    rgb = img[:, :, :3]
    # the background's colour is that of the nearest clear pixel (however wide the soft band)
    _, (by, bx) = ndi.distance_transform_edt(~clear, return_indices=True)
    cf = clear.astype(np.float32)
    smooth = cv2.blur(rgb * cf[:, :, None], (7, 7)) / np.maximum(cv2.blur(cf, (7, 7)), 1e-6)[:, :, None]
    bg = smooth[by, bx]         # averaged over its clear neighbours: no paper grain
    _, (iy, ix) = ndi.distance_transform_edt(~solid, return_indices=True)
    own = rgb[iy, ix]
    out = img.copy()
    oy, ox = np.nonzero(opaque)
    if max(oy.max() - oy.min(), ox.max() - ox.min()) + 1 < FRINGE_MIN_SIZE:
        return _light_fringe(out, soft, bg, own)
    # Composited edges first (any matte, cleared black included): rgb = t * c + (1 - t) * m with c
    # the tree's colour inside (averaged: photographed leaves vary pixel to pixel; a keyed photo's
    # alpha runs wider than its colour edge, so t is fitted, not taken from alpha).
    # inner = past the soft band twice over (a keyed photo's colour edge runs on inside its alpha)
    dist_clear = ndi.distance_transform_edt(~clear)
    depth = int(np.clip(np.ceil(2 * np.percentile(dist_clear[soft], 90)), 2, 8))
    core = solid & (dist_clear > depth)
    core = core if core.any() else solid
    cf_ = core.astype(np.float32)
    _, (jy, jx) = ndi.distance_transform_edt(~core, return_indices=True)
    own_s = (cv2.blur(rgb * cf_[:, :, None], (5, 5)) / np.maximum(cv2.blur(cf_, (5, 5)), 1e-6)[:, :, None])
    ys, xs = np.nonzero(soft)
    o_s = own_s[jy[ys, xs], jx[ys, xs]]
    c_s, m_s = rgb[ys, xs], bg[ys, xs]
    d = o_s - m_s
    t = np.clip(((c_s - m_s) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-6), 0.0, 1.0)[:, None]
    mix_err = np.abs(c_s - (t * o_s + (1 - t) * m_s)).max(axis=1)
    plain_err = np.abs(c_s - o_s).max(axis=1)
    d_solid = ndi.distance_transform_edt(~solid)[ys, xs]
    t_f, a_f = _full_alpha_share(rgb, a, solid, soft, ys, xs, own_s[jy, jx], bg,
                                 (iy[ys, xs], ix[ys, xs]), d_solid > FRINGE_REACH)
    # A straight-colour line keeps its colour as alpha rises: the drawing's own, left as it is.
    # A matte shows on the rim only: within FRINGE_REACH of a clear pixel, beside a solid one.
    with np.errstate(invalid="ignore"):
        drawn = ~(t_f - t[:, 0] >= np.maximum(FRINGE_RISE * (a_f - a[ys, xs]), FRINGE_RISE_MIN)) | \
            (dist_clear[ys, xs] > FRINGE_REACH)
    comp = (t[:, 0] >= FRINGE_T) & (mix_err <= FRINGE_MIX) & (plain_err > FRINGE_NEAR) & \
        (mix_err <= 0.5 * plain_err) & (np.abs(d).max(axis=1) > FRINGE_FAR) & ~drawn
    if comp.any():
        # The matte taken out of the pixel's own colour (photographed texture kept), up to the
        # tree's colour, or only up to the dark band's beside it (a premultiplied ink line stays ink).
        goal = np.where(t_f < FRINGE_INK, t_f, 1.0)[:, None]
        unmixed = np.where(t >= FRINGE_T_DIV, m_s + (c_s - m_s) * goal / np.maximum(t, FRINGE_T_DIV),
                           m_s + goal * d)
        out[ys[comp], xs[comp], :3] = np.clip(unmixed, 0.0, 1.0)[comp]
    return _light_fringe(out, soft, bg, own)


def _light_fringe(out: np.ndarray, soft: np.ndarray, bg: np.ndarray, own: np.ndarray) -> np.ndarray:
    """Soft pixels of ``out`` showing a light matte's colour take their nearest solid pixel's."""
    # A matte background is one colour (paper, up to its grain); transparent pixels holding
    # leftover colours of the art (sprites) are no background to match against.
    ring = bg[soft]
    if np.percentile(np.abs(ring - np.median(ring, axis=0)).max(axis=1), 90) > FRINGE_BG / 2:
        return out
    # Cleared (black) transparent pixels say nothing about a background: a dark anti-aliased
    # outline over them is the drawing's own.
    rgb2 = out[:, :, :3]
    fringe = soft & (bg.max(axis=2) > FRINGE_DARK) & (np.abs(rgb2 - bg).max(axis=2) <= FRINGE_BG) & \
        (np.abs(rgb2 - own).max(axis=2) > FRINGE_FAR)
    out[fringe, :3] = own[fringe]
    return out


def signed_area(polygon) -> float:
    """Shoelace area of a closed polygon in image coordinates (y down).

    Negative for a contour that runs counter-clockwise *on screen*
    (bottom -> right -> top -> left).

    Parameters
    ----------
    polygon : (K, 2) array_like
        Vertices (x, y) in order; the closing edge back to the first vertex
        is implied.

    Returns
    -------
    float
        Signed area in square pixels (0 for fewer than 3 distinct vertices).

    Examples
    --------
    >>> signed_area([(0, 0), (0, 2), (2, 2), (2, 0)])  # down, right, up: counter-clockwise on screen
    -4.0
    """
    p = np.asarray(polygon, dtype=np.float64)
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


@dataclass
class ContourSet:
    """Borders of an opaque region, classified by the border-following algorithm.

    Parameters
    ----------
    exterior : list of (K, 2) float ndarray
        Outer boundaries (one per connected region), pixel centres (x, y).
    interior : list of (K, 2) float ndarray
        Hole boundaries.
    tree : (K, 2) float ndarray
        The tree contour ``C``: the longest exterior border, oriented
        counter-clockwise on screen (bottom -> right -> top -> left);
        None when there is no opaque region.
    shape : (H, W), optional
        Size of the mask the borders were traced in (sets the size of
        :meth:`render`'s picture).

    Examples
    --------
    >>> import numpy as np
    >>> alpha = np.zeros((20, 20), bool); alpha[4:16, 4:16] = True; alpha[8:12, 8:12] = False
    >>> cs = extract_contours(alpha)
    >>> len(cs.exterior), len(cs.interior), cs.shape
    (1, 1, (20, 20))
    """

    exterior: list = field(default_factory=list)
    interior: list = field(default_factory=list)
    tree: np.ndarray | None = None
    shape: tuple[int, int] | None = None

    @checked()
    def render(self, background=None) -> np.ndarray:
        """RGB picture: exterior borders green, interior (hole) borders blue, ``C`` red.

        Parameters
        ----------
        background : (H, W, 3|4) array_like, optional
            Drawn faded underneath (e.g. the normalised exemplar).
        """
        if background is None:
            if self.shape is None:
                raise ValueError("give a background: this ContourSet does not know its image size")
            img = np.ones(self.shape + (3,), np.float32)
        else:
            img = composite_over(as_float_image(background), (1.0, 1.0, 1.0)) * 0.35 + 0.65
        lw = max(1.0, img.shape[0] / 400)
        loops = [np.vstack([c, c[:1]]) for c in self.exterior]
        holes = [np.vstack([c, c[:1]]) for c in self.interior]
        if holes:
            img = draw_polylines(img, holes, widths=lw, colors=(0.1, 0.3, 0.95))
        if loops:
            img = draw_polylines(img, loops, widths=lw, colors=(0.1, 0.65, 0.1))
        if self.tree is not None:
            img = draw_polylines(img, [np.vstack([self.tree, self.tree[:1]])], widths=2 * lw,
                                 colors=(0.85, 0.05, 0.05))
        return img


@checked(alpha=Array(ndim=2), threshold=Real(0, 1, low_open=True))
def extract_contours(alpha, *, threshold: float = 0.5) -> ContourSet:
    """Trace and classify the borders of an opacity mask; pick the tree contour ``C``.

    Parameters
    ----------
    alpha : (H, W) array_like or (H, W, 4) RGBA image
        Opacity (thresholded at ``threshold``) or an RGBA image.
    threshold : float
        Opacity threshold (paper: 0.5).

    Returns
    -------
    ContourSet
        Exterior and interior borders (Suzuki-Abe border following via
        ``cv2.findContours(..., RETR_CCOMP, CHAIN_APPROX_NONE)``: a border
        whose hierarchy parent is -1 is exterior) and ``tree``, the longest
        exterior one by arc length.

    Raises
    ------
    ValueError
        No opaque pixel.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((9, 9)); m[2:7, 2:7] = 1; m[4, 4] = 0
    >>> cs = extract_contours(m)
    >>> len(cs.exterior), len(cs.interior), len(cs.tree)
    (1, 1, 16)
    """
    a = np.asarray(alpha)
    if a.ndim == 3:
        a = as_rgba(a, name="alpha")[:, :, 3]
    mask = as_mask(np.asarray(a, dtype=np.float64) >= threshold, name="alpha")
    if not mask.any():
        raise ValueError("alpha has no opaque pixel: no contour to extract")
    contours, hierarchy = cv2.findContours(mask.astype(np.uint8), cv2.RETR_CCOMP,
                                           cv2.CHAIN_APPROX_NONE)
    ext, inner = [], []
    for c, h in zip(contours, hierarchy[0]):
        pts = c[:, 0, :].astype(np.float64)
        (ext if h[3] < 0 else inner).append(pts)
    lengths = [cv2.arcLength(c.astype(np.float32)[:, None], True) for c in ext]
    tree = ext[int(np.argmax(lengths))]
    if len(tree) >= 3 and signed_area(tree) > 0:
        tree = tree[::-1].copy()
    return ContourSet(ext, inner, tree, mask.shape)
