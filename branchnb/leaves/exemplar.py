"""Leaf exemplars at the door: an RGB(A) image becomes colour, alpha and a blade mask.

The method needs, for every exemplar, the leaf's colours and its blade
(the silhouette, petiole included). Two kinds of input are accepted:

* **RGBA** with a meaningful alpha (a cut-out leaf): the blade is
  ``alpha > 0.5``, the alpha is kept as the leaf's matte.
* **Opaque** images of a leaf on a plain background (a scan or a photo
  on paper): a background model is fitted to the image border, which
  must be plain: one colour, or (paper under uneven light) a lightness
  that is a quadratic in (x, y) with one chroma, whichever fits better.
  Each pixel's distance from the paper's colour there (CIELAB
  Delta E, plus the chroma difference, so a pale-green leaf on white
  stands out) is thresholded by Otsu's method; the blade is the largest
  connected component (with parts of at least ``min_part`` of its size
  that are inside the frame and of its colours), without a grey drop or
  cast shadow on one side of it (:func:`_cast_shadow`, beyond the
  paper), the paper inside a
  broken (dashed) drawn outline added, its small holes filled (specular highlights,
  pale veins) and its thin ones too (a network of pale drawn veins, :data:`THIN_HOLE`),
  large round holes kept (real holes in the leaf). The alpha is
  then the blade mask, feathered by one pixel, and the blade's one-pixel
  rim (part paper) takes the colours of the pixels just inside.

Images whose border is not plain, or whose distance map has no clear
two-class split, or whose "leaf" touches most of the border, are
rejected with a ``ValueError``: the method cannot know where such a leaf
ends, and guessing would silently ruin every later step.

Exemplar sets (:func:`prepare_exemplars`) need at least two leaves.
They may differ in size: registration maps every exemplar into the
training leaf's frame whatever its size, so ``size_policy="keep"`` leaves
them as they are; ``"pad"`` pads every image (transparent) to the largest
height and width, centred on its blade; ``"resize"`` additionally scales
each leaf so its blade area equals the training leaf's, then pads.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage as ndi
from skimage.color import rgb2lab
from skimage.filters import threshold_otsu

from ..core.image import as_float_image, extend_nearest
from ..core.io import encode_png
from ..core.morphology import fill_holes
from ..core.validate import Int, Real, Seq, checked

__all__ = ["Exemplar", "leaf_exemplar", "blade_mask", "prepare_exemplars"]

#: The border is "plain" when the median colour distance of border pixels
#: from the border's median colour stays below this (CIELAB Delta E) ...
PLAIN_BORDER_DELTA_E = 12.0
#: ... or, for paper under uneven light, from the fitted lightness gradient
#: (:func:`_paper_lightness`) below this. Measured: plain paper 0.0-3.3 (seven
#: grass strips, zelkova, drawn maples), a mosaic of leaf close-ups 8.7
#: (a smooth fit also absorbs part of a busy border, hence the lower bound).
PLAIN_LIT_DELTA_E = 6.0
#: A hole in the blade no deeper than this share of the leaf's size (``sqrt`` of its area; 3 px at
#: least) from its edge is a line, not a hole, and is filled: pale (near-white) veins drawn on a
#: clip-art leaf are paper-coloured and joined they reach far over ``max_hole`` (a drawn maple's
#: 3 px white veins: 7 % of the blade, cut out of it, and a user's scribble on them was refused as
#: "outside the leaf"). Beyond the paper. A real hole (an insect's, a tear) is deeper.
THIN_HOLE = 0.012
#: ... with at most this share of its pixels deeper (line junctions): a round hole 4x as deep has
#: 56 % of its pixels deeper.
THIN_HOLE_DEEP = 0.05
#: Otsu's split must explain at least this fraction of the variance of
#: the distance map (between-class / total variance).
MIN_SEPARABILITY = 0.6


@dataclass
class Exemplar:
    """A normalised leaf exemplar.

    Parameters
    ----------
    rgb : (H, W, 3) float32 ndarray
        The leaf's colours in [0, 1].
    alpha : (H, W) float32 ndarray
        The matte: the input's alpha, or the feathered blade mask.
    blade : (H, W) bool ndarray
        The leaf's silhouette (lamina and petiole).
    mask_source : str
        ``"alpha"`` or ``"background"`` (the background model).
    name : str
        What messages call it (e.g. ``"images[2]"`` or a file name).
    """

    rgb: np.ndarray
    alpha: np.ndarray
    blade: np.ndarray
    mask_source: str = "alpha"
    name: str = ""

    @property
    def shape(self) -> tuple[int, int]:
        return self.blade.shape

    @property
    def rgba(self) -> np.ndarray:
        """(H, W, 4) float32: colour and matte."""
        return np.dstack([self.rgb, self.alpha]).astype(np.float32)

    def on_white(self) -> np.ndarray:
        a = self.alpha[:, :, None]
        return (self.rgb * a + (1.0 - a)).astype(np.float32)

    def _repr_png_(self) -> bytes:
        return encode_png(self.on_white())


def _border_mask(shape, width: int) -> np.ndarray:
    b = np.zeros(shape, bool)
    b[:width, :] = b[-width:, :] = b[:, :width] = b[:, -width:] = True
    return b


def _border_pixels(img: np.ndarray, width: int) -> np.ndarray:
    return img[_border_mask(img.shape[:2], width)]


def _leaf_parts(labels: np.ndarray, lab: np.ndarray, min_part: float) -> np.ndarray:
    """Labels of the components that make the leaf: the largest, and parts like it.

    Besides the largest component, the parts of a compound leaf (pinnae
    cut apart by a pale rachis) are kept, but not dust or shadows (too
    small), nor other objects on the paper: a part cut by the image frame
    (a reference card, an envelope at the edge of a crop) or one whose
    median colour lies outside the main part's own colour spread (a red
    scale square).
    """
    h, w = labels.shape
    sizes = np.bincount(labels.ravel())[1:]
    main = int(np.argmax(sizes)) + 1
    big = np.flatnonzero((sizes >= min_part * sizes.max()) & (sizes >= 5e-4 * h * w)) + 1
    frame = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
    main_lab = lab[labels == main]
    centre = np.median(main_lab, axis=0)
    spread = max(float(np.percentile(np.linalg.norm(main_lab - centre, axis=1), 90)), PLAIN_BORDER_DELTA_E)
    keep = [main]
    for part in big:
        if part == main or part in frame:
            continue
        if float(np.linalg.norm(np.median(lab[labels == part], axis=0) - centre)) <= spread:
            keep.append(int(part))
    return np.asarray(keep)


#: A drawn blade's outline may be broken (dashed): gaps up to twice this
#: fraction of the leaf's size (square root of its bounding box area) are bridged ...
OUTLINE_GAP = 0.03
#: ... when the blade is porous: inside the bridged silhouette (farther
#: than the bridging radius from its edge) at least this fraction is paper
#: (between strokes, enclosed by them or not). Measured: photographed
#: blades 0-2.5 % (grass strips, zelkova, the seven maples on white), the
#: two drawn maples 24 %.
MIN_POROSITY = 0.15


def _drawn_interior(blade: np.ndarray) -> np.ndarray:
    """The paper inside a leaf drawn as strokes in a broken outline, or an empty mask.

    Such a leaf's "blade" is its strokes: the paper between them reaches
    the background through the outline's gaps, the silhouette comes out
    as a lace, and registration then matches strokes, not outlines. The
    strokes closed by a disk of radius ``OUTLINE_GAP`` times the leaf size,
    holes filled, give the silhouette; it is used when the blade is
    porous (``MIN_POROSITY``), so a solid leaf's outline is never touched.
    """
    ys, xs = np.nonzero(blade)
    if len(ys) == 0:
        return np.zeros_like(blade)
    size = float(np.sqrt((np.ptp(ys) + 1) * (np.ptp(xs) + 1)))
    r = max(2, int(round(OUTLINE_GAP * size)))
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    pad = r + 1
    closed = cv2.morphologyEx(np.pad(blade, pad).astype(np.uint8), cv2.MORPH_CLOSE, disk)[pad:-pad, pad:-pad] > 0
    silhouette = fill_holes(closed)
    inner = cv2.distanceTransform(np.pad(silhouette, 1).astype(np.uint8), cv2.DIST_L2, 5)[1:-1, 1:-1] > r
    if inner.sum() < 16 or (inner & ~blade).sum() < MIN_POROSITY * inner.sum():
        return np.zeros_like(blade)
    return silhouette & ~blade


def _paper_lightness(lab: np.ndarray, border: np.ndarray, iterations: int = 4):
    """The paper's lightness as a quadratic in (x, y), fitted to the ``border`` pixels; its median misfit.

    Plain paper photographed under uneven light darkens smoothly towards
    one side or the corners (a 35 % falloff across a phone photo is
    common); a single border colour called such paper "busy" and the
    dark side "leaf". Light changes the lightness, not the hue, so only
    CIELAB L varies and the chroma is the border's median (a half-white,
    half-green image stays busy). The fit is robust (iteratively
    reweighted least squares with weights ``1 / max(residual, 1)``: an L1
    fit), so a petiole or a card reaching the border does not bend it.

    Returns
    -------
    lightness : callable
        ``lightness()`` evaluates the fit on the whole (H, W) grid.
    chroma : (2,) ndarray
    spread : float
        Median Delta E of the border pixels from the model.
    """
    h, w = lab.shape[:2]
    ys, xs = np.nonzero(border)
    step = max(1, len(xs) // 20000)
    ys, xs = ys[::step], xs[::step]

    def terms(x, y):
        u, v = 2.0 * x / max(w - 1, 1) - 1.0, 2.0 * y / max(h - 1, 1) - 1.0
        return [np.ones_like(u * v), u, v, u * u, u * v, v * v]

    a = np.stack(terms(xs.astype(np.float64), ys.astype(np.float64)), axis=-1)
    z = lab[ys, xs].astype(np.float64)
    chroma = np.median(z[:, 1:], axis=0)
    wts = np.ones(len(z))
    for _ in range(iterations):
        coef, *_ = np.linalg.lstsq(a * wts[:, None], z[:, 0] * wts, rcond=None)
        wts = 1.0 / np.sqrt(np.maximum(np.abs(z[:, 0] - a @ coef), 1.0))  # squared in the normal equations
    fit = np.column_stack([a @ coef, np.broadcast_to(chroma, (len(z), 2))])
    spread = float(np.median(np.linalg.norm(z - fit, axis=1)))

    def lightness() -> np.ndarray:
        # Row and column terms broadcast: no (H, W, 6) array at a megapixel.
        t = terms(np.arange(w, dtype=np.float64)[None, :], np.arange(h, dtype=np.float64)[:, None])
        return sum(c * term for c, term in zip(coef, t)).astype(np.float32)

    return lightness, chroma, spread


#: Shadow pixels are darker than the paper there by at least this (CIELAB L) ...
SHADOW_DARKENING = 3.0
#: ... but not darker than this fraction of the paper's L (ink, not a shadow) ...
SHADOW_MIN_LIGHTNESS = 0.3
#: ... and keep the paper's chroma: their (a, b) lie within this of the
#: paper's (a, b) scaled by their relative lightness (a shadow darkens the
#: paper's own colour). A green, red, yellow or brown leaf is 15-80 away.
SHADOW_CHROMA = 4.0
#: A shadow lies on one side of the leaf: the mean unit vector from the
#: nearest leaf pixel to each shadow pixel is at least this long. A grey
#: outline drawn all around a leaf (about 0) is kept.
SHADOW_ONE_SIDED = 0.3


def _cast_shadow(fg: np.ndarray, lab: np.ndarray, bg: np.ndarray) -> np.ndarray:
    """The drop or cast shadow that Otsu's split took as leaf, or an empty mask.

    Beyond the paper (which starts from segmented leaves). A grey drop
    shadow in clip art, or a leaf's soft shadow on the paper of a photo, is
    far from the paper in lightness, so the split keeps it with the blade
    (7 % of a drawn maple's blade, shown as grey rims on every new leaf).
    Shadow pixels are the paper's colour darkened (``SHADOW_DARKENING``,
    ``SHADOW_MIN_LIGHTNESS``, ``SHADOW_CHROMA``, after a 3 x 3 median), outside the leaf's coloured part
    and its holes, reaching 2 pixels or more away from it (the grey rim of
    anti-aliased ink is 1 pixel wide), and on one side of it
    (``SHADOW_ONE_SIDED``). When such grey pixels make half the
    foreground or more, the leaf itself is grey (a dry grey-brown leaf, a
    pencil drawing) and nothing is removed: a shadow under a grey leaf is
    then kept with it.
    """
    empty = np.zeros_like(fg)
    # Sensor noise scatters a grey's chroma; a median keeps the leaf's colour out of a thin shadow band.
    smooth = cv2.medianBlur(np.ascontiguousarray(lab, np.float32), 3)
    light = smooth[..., 0]
    paper = bg[..., 0]
    rel = np.clip(light / np.maximum(paper, 1.0), 0.0, 1.0)
    dab = np.hypot(smooth[..., 1] - bg[..., 1] * rel, smooth[..., 2] - bg[..., 2] * rel)
    grey = fg & (light < paper - SHADOW_DARKENING) & (light > SHADOW_MIN_LIGHTNESS * paper) & (dab < SHADOW_CHROMA)
    core = fg & ~grey
    n_fg = int(fg.sum())
    if not grey.any() or core.sum() < 0.5 * n_fg:
        return empty
    inside = fill_holes(core)
    cand = grey & ~inside
    if not cand.any():
        return empty
    # Nearest core pixel of every candidate, within the candidates' bounding box (plus margin).
    ys, xs = np.nonzero(cand)
    m = 2 + int(max(np.ptp(ys), np.ptp(xs)))
    y0, x0 = max(0, ys.min() - m), max(0, xs.min() - m)
    y1, x1 = min(fg.shape[0], ys.max() + m + 1), min(fg.shape[1], xs.max() + m + 1)
    sub = core[y0:y1, x0:x1]
    if not sub.any():
        return empty
    dist, (iy, ix) = ndi.distance_transform_edt(~sub, return_indices=True)
    # The grey rim of anti-aliased ink (1 pixel) is no shadow: seeds lie 2 pixels out or more, and
    # 3 or more unless they sit in a grey band at least 3 pixels wide (a drawing's anti-aliased
    # outline, grey where it is thinner than two pixels, is a thin grey line along the blade; the
    # price: a soft shadow narrower than 3 pixels on a small leaf is kept with it).
    band = ndi.binary_opening(cand, structure=np.ones((3, 3), bool))
    d_seed = dist[ys - y0, xs - x0]
    far = (d_seed >= 3.0) | ((d_seed >= 2.0) & band[ys, xs])
    if far.sum() < 0.002 * n_fg:
        return empty
    ys, xs = ys[far], xs[far]
    vy = (ys - y0) - iy[ys - y0, xs - x0]
    vx = (xs - x0) - ix[ys - y0, xs - x0]
    norm = np.hypot(vx, vy)
    if float(np.hypot((vx / norm).mean(), (vy / norm).mean())) < SHADOW_ONE_SIDED:
        return empty
    seeds = np.zeros_like(fg)
    seeds[ys, xs] = True
    parts, _ = ndi.label(grey, structure=np.ones((3, 3), bool))
    hit = np.unique(parts[seeds])
    return np.isin(parts, hit[hit > 0]) & ~inside


@checked(max_hole=Real(0.0, 1.0), min_part=Real(0.0, 1.0))
def blade_mask(image, *, max_hole: float = 0.01, min_part: float = 0.02, name: str = "image") -> np.ndarray:
    """The blade of a leaf on a plain background (opaque image).

    Parameters
    ----------
    image : (H, W, 3) or (H, W) array_like
        Opaque image of one leaf on a plain background.
    max_hole : float
        Holes in the blade smaller than this fraction of its area are filled (and,
        whatever their area, holes no deeper than :data:`THIN_HOLE` of the leaf size: lines).
    min_part : float
        Besides the largest component, components of at least this fraction
        of its area are kept (the pinnae of a compound leaf) when they are
        inside the frame and of the main part's colours (a red scale square
        or a card cut by the image edge is not leaf).
    name : str
        Argument name in error messages.

    Returns
    -------
    (H, W) bool ndarray

    Raises
    ------
    ValueError
        A busy (non-plain) border, no clear leaf/background split, or a
        blade touching most of the border.

    Notes
    -----
    Beyond the paper, a grey drop shadow (clip art) or a soft cast shadow
    (a photo) on one side of the leaf is not blade (:func:`_cast_shadow`).
    Measured on 324 procedural leaves (3 kinds, 128-400 px, green, dark
    green, red, yellow, brown and grey-brown, white and cream paper, drop
    shadows offset 4-10 px, soft shadows): blade IoU of brown leaves with a
    drop shadow 0.970 -> 0.993 (worst 0.885 -> 0.984), dark green 0.983
    -> 0.993. A leaf as grey as its shadow (a dry grey-brown leaf on cream
    paper) keeps its shadow: nothing tells them apart by colour.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((40, 40, 3)); img[10:30, 12:28] = (0.2, 0.5, 0.1)
    >>> abs(int(blade_mask(img).sum()) - 320) <= 8
    True
    """
    img = as_float_image(image, name=name)
    if img.shape[2] == 4:
        img = img[:, :, :3]
    if img.shape[2] == 1:
        img = np.repeat(img, 3, axis=2)
    h, w = img.shape[:2]
    if min(h, w) < 16:
        raise ValueError(f"{name} is too small for a background model ({w} x {h}; need 16 x 16)")
    lab = rgb2lab(img).astype(np.float32)
    on_border = _border_mask((h, w), max(2, min(h, w) // 50))
    border = lab[on_border]
    flat = np.median(border, axis=0)
    spread = float(np.median(np.linalg.norm(border - flat, axis=1)))
    lightness, chroma, lit_spread = _paper_lightness(lab, on_border)
    if spread > PLAIN_BORDER_DELTA_E and lit_spread > PLAIN_LIT_DELTA_E:
        raise ValueError(
            f"{name} has no alpha and a busy background (border colours vary by Delta E {spread:.1f} "
            f"> {PLAIN_BORDER_DELTA_E}, and by {lit_spread:.1f} > {PLAIN_LIT_DELTA_E} around a smooth "
            "lighting gradient): give a cut-out (RGBA) leaf or a leaf on a plain background")
    if lit_spread < spread:
        bg = np.empty_like(lab)
        bg[..., 0], bg[..., 1:] = lightness(), chroma
    else:
        bg = np.broadcast_to(flat, lab.shape)
    de = np.linalg.norm(lab - bg, axis=2)
    chroma = np.hypot(lab[..., 1], lab[..., 2])
    dist = de + np.abs(chroma - np.hypot(bg[..., 1], bg[..., 2]))
    dist = cv2.medianBlur(dist.astype(np.float32), 3)  # noise down, edges kept in place
    if float(dist.max() - dist.min()) < 1e-3:
        raise ValueError(f"{name} is uniform: there is no leaf to find")
    t = float(threshold_otsu(dist))
    fg = dist > t
    var = float(dist.var())
    m0 = float(dist[~fg].mean()) if (~fg).any() else 0.0
    m1 = float(dist[fg].mean()) if fg.any() else 0.0
    p1 = float(fg.mean())
    separability = p1 * (1 - p1) * (m1 - m0) ** 2 / max(var, 1e-12)
    if separability < MIN_SEPARABILITY:
        raise ValueError(
            f"{name} has no clear leaf/background split (Otsu separability {separability:.2f} < "
            f"{MIN_SEPARABILITY}): give a cut-out (RGBA) leaf or a leaf on a plain background")
    fg &= ~_cast_shadow(fg, lab, bg)
    lab_cc, n = ndi.label(fg)
    if n == 0:
        raise ValueError(f"{name}: no leaf found")
    blade = np.isin(lab_cc, _leaf_parts(lab_cc, lab, min_part))
    blade |= _drawn_interior(blade)
    holes = fill_holes(blade) & ~blade
    if holes.any():
        hl, nh = ndi.label(holes)
        hs = np.bincount(hl.ravel())[1:]
        # How deep each hole is: a pale vein network is large but one line wide (its junctions
        # a little deeper, hence a share of its pixels, not its deepest one).
        thin = max(3.0, THIN_HOLE * float(np.sqrt(blade.sum())))
        deep = np.bincount(hl[ndi.distance_transform_edt(holes) > thin], minlength=nh + 1)[1:]
        small = np.flatnonzero((hs < max_hole * blade.sum()) | (deep <= THIN_HOLE_DEEP * hs)) + 1
        blade |= np.isin(hl, small)
    touching = _border_pixels(blade[:, :, None], 1).mean()
    if touching > 0.5 or blade.mean() > 0.95:
        raise ValueError(f"{name}: the leaf/background split covers most of the image border; "
                         "is the background really plain?")
    if blade.sum() < 0.002 * h * w:
        raise ValueError(f"{name}: the leaf found is tiny ({int(blade.sum())} pixels)")
    return blade


@checked(max_hole=Real(0.0, 1.0))
def leaf_exemplar(image, *, name: str = "image", max_hole: float = 0.01) -> Exemplar:
    """Normalise one leaf image into an :class:`Exemplar`.

    Parameters
    ----------
    image : array_like
        ``(H, W, 4)`` RGBA (alpha used when it is not all opaque), or an
        opaque ``(H, W, 3)`` / ``(H, W)`` image of a leaf on a plain
        background (see :func:`blade_mask`). uint8, uint16 or float in [0, 1].
    name : str
        Used in error messages and kept on the result.
    max_hole : float
        See :func:`blade_mask`.

    Returns
    -------
    Exemplar

    Examples
    --------
    >>> import numpy as np
    >>> rgba = np.zeros((32, 32, 4)); rgba[8:24, 8:24] = (0.2, 0.6, 0.1, 1.0)
    >>> ex = leaf_exemplar(rgba)
    >>> ex.mask_source, int(ex.blade.sum())
    ('alpha', 256)
    """
    img = as_float_image(image, name=name)
    if img.shape[2] == 1:
        img = np.repeat(img, 3, axis=2)
    if img.shape[2] == 4 and float(img[:, :, 3].min()) < 0.5:
        rgb, alpha = img[:, :, :3], img[:, :, 3].copy()
        blade = alpha > 0.5
        if blade.sum() < 16:
            raise ValueError(f"{name}: the alpha channel holds almost no leaf ({int(blade.sum())} opaque pixels)")
        if blade.all():
            raise ValueError(f"{name}: the alpha channel marks the whole image as leaf")
        return Exemplar(np.ascontiguousarray(rgb), alpha, blade, "alpha", name)
    rgb = np.ascontiguousarray(img[:, :, :3])
    blade = blade_mask(rgb, max_hole=max_hole, name=name)
    # The blade's outermost pixels are part paper (the lens and the
    # resampling mix them): 6-12 CIELAB L units paler than the pixels
    # inside on the grass photos, as pale as a vein, so induction took every
    # exemplar's outline for a vein. They take the colour of the nearest
    # pixel inside; the feathered alpha keeps the edge soft.
    # A drawn outline is ink, not a fringe: rim pixels far darker than the
    # pixel inside (brightest channel below 0.6 of it) are kept (recoloured,
    # a 1 px outline vanished and a 2 px one came out 1 px wide).
    inner = ndi.binary_erosion(blade, structure=np.ones((3, 3), bool))
    if inner.sum() >= 0.5 * blade.sum():
        fill = extend_nearest(rgb, inner)
        rim = blade & ~inner & (rgb.max(2) >= 0.6 * fill.max(2))
        rgb = np.where(rim[..., None], fill, rgb).astype(np.float32)
    alpha = cv2.GaussianBlur(blade.astype(np.float32), (0, 0), 0.7)
    alpha = np.where(blade, np.maximum(alpha, 0.5), np.minimum(alpha, 0.49)).astype(np.float32)
    return Exemplar(rgb, alpha, blade, "background", name)


def _place(ex: Exemplar, shape: tuple[int, int], scale: float = 1.0) -> Exemplar:
    """``ex`` scaled about its blade centroid and centred on a transparent canvas of ``shape``."""
    H, W = shape
    ys, xs = np.nonzero(ex.blade)
    cx, cy = float(xs.mean()), float(ys.mean())
    tx, ty = W / 2.0 - scale * cx, H / 2.0 - scale * cy
    if scale == 1.0:  # whole-pixel shifts: padding never resamples
        tx, ty = round(tx), round(ty)
    m = np.array([[scale, 0.0, tx], [0.0, scale, ty]])
    rgba = cv2.warpAffine(ex.rgba, m, (W, H), flags=cv2.INTER_LINEAR if scale >= 1 else cv2.INTER_AREA,
                          borderMode=cv2.BORDER_CONSTANT, borderValue=(0, 0, 0, 0))
    blade = cv2.warpAffine(ex.blade.astype(np.float32), m, (W, H), flags=cv2.INTER_LINEAR) > 0.5
    return Exemplar(np.clip(rgba[:, :, :3], 0, 1), np.clip(rgba[:, :, 3], 0, 1), blade, ex.mask_source, ex.name)


@checked(min_count=Int(1, 10_000), max_hole=Real(0.0, 1.0), names=Seq())
def prepare_exemplars(images, *, size_policy: str = "keep", names=None, min_count: int = 2,
                      max_hole: float = 0.01) -> list[Exemplar]:
    """Normalise a set of exemplars of one kind; the first is the training leaf.

    Parameters
    ----------
    images : sequence of array_like or Exemplar
        At least ``min_count`` leaf images (see :func:`leaf_exemplar`).
    size_policy : {"keep", "pad", "resize"}
        ``"keep"``: sizes may differ (registration maps every exemplar into
        the training frame). ``"pad"``: pad all to the largest height and
        width, each centred on its blade. ``"resize"``: scale each so its
        blade area equals the training leaf's, then pad to a common size.
    names : sequence of str, optional
        One name per image, for the exemplars and the error messages;
        default ``"images[i]"``.
    min_count : int
        The method mixes several exemplars; two is the least that makes sense.
    max_hole : float
        See :func:`blade_mask`.

    Returns
    -------
    list of Exemplar

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((30, 20, 4)); a[5:25, 5:15] = (0.2, 0.6, 0.1, 1)
    >>> b = np.zeros((40, 40, 4)); b[5:35, 10:30] = (0.2, 0.6, 0.1, 1)
    >>> [e.shape for e in prepare_exemplars([a, b], size_policy="pad")]
    [(41, 41), (41, 41)]
    """
    if isinstance(images, np.ndarray) and images.ndim in (2, 3) and images.dtype != object:
        raise ValueError("images must be a sequence of leaf images, got a single image array; "
                         f"the method needs at least {min_count} exemplars")
    try:
        items = list(images)
    except TypeError as exc:
        raise TypeError(f"images must be a sequence of leaf images, got {type(images).__name__}") from exc
    if len(items) < min_count:
        raise ValueError(f"images holds {len(items)} exemplar(s); the method needs at least {min_count} "
                         "leaves of one kind (the first is the training leaf)")
    if size_policy not in ("keep", "pad", "resize"):
        raise ValueError(f"size_policy must be 'keep', 'pad' or 'resize', got {size_policy!r}")
    if names is not None and len(names) != len(items):
        raise ValueError(f"names has {len(names)} entries for {len(items)} images")
    out = []
    for i, item in enumerate(items):
        nm = names[i] if names is not None else f"images[{i}]"
        if isinstance(item, Exemplar):
            out.append(item)
        else:
            out.append(leaf_exemplar(item, name=nm, max_hole=max_hole))
    if size_policy == "keep":
        return out
    scales = [1.0] * len(out)
    if size_policy == "resize":
        ref = float(out[0].blade.sum())
        scales = [float(np.sqrt(ref / e.blade.sum())) for e in out]
    # Common canvas: every scaled blade's bounding box around its centroid fits.
    half_h, half_w = 0.0, 0.0
    for e, s in zip(out, scales):
        ys, xs = np.nonzero(e.blade)
        cy, cx = ys.mean(), xs.mean()
        if size_policy == "pad":
            half_h = max(half_h, cy, e.shape[0] - cy)
            half_w = max(half_w, cx, e.shape[1] - cx)
        else:
            half_h = max(half_h, s * (cy - ys.min() + 2), s * (ys.max() - cy + 2), s * e.shape[0] / 2)
            half_w = max(half_w, s * (cx - xs.min() + 2), s * (xs.max() - cx + 2), s * e.shape[1] / 2)
    shape = (int(np.ceil(2 * half_h)), int(np.ceil(2 * half_w)))
    return [_place(e, shape, s) for e, s in zip(out, scales)]
