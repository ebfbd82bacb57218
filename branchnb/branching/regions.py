"""Which example pixels belong to a branch, and which may be copied at all.

Image synthesis copies example pixels in two ways: fragments copy the
neighbourhood of one source branch, gap completion copies the space
*between* branches. Both must know where the branches are:

* the **body** of the annotated structure: pixels within
  ``exclusion * r + margin`` of the skeleton (``r`` the local thickness);
* **branch-like** pixels the annotation missed (faint lightning
  branches, hairline cracks, small vessels): pixels whose colour lies at
  least ``threshold`` of the way from the *local* background colour towards
  the colour of the annotated branches. Copied into a gap they would be
  pseudo-branches;
* **salient spots**: blobs much darker or brighter than their
  surroundings that are no branch (the optic disc and the fovea of a
  retina, a stone in mud). The example has each of them once; copied
  into several gaps they would be conspicuous repetitions;
* the **matte**: a flat black or white region connected to the image
  border (the mask around a fundus photograph, letterboxing), which is no
  texture of the example and is never copied; plus whatever the caller
  excludes with an explicit ``example_mask``.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage as ndi
from skimage.filters import apply_hysteresis_threshold

from .skeleton_map import PixelMap

__all__ = ["ExampleRegions", "example_regions", "branch_likeness", "matte_mask", "salient_mask",
           "flatten_shading"]


@dataclass
class ExampleRegions:
    """Masks over the example image, all ``(H, W)`` bool.

    Parameters
    ----------
    body : (H, W) bool ndarray
        Annotated branches (skeleton within ``exclusion * r + margin``).
    branch_like : (H, W) bool ndarray
        Unannotated pixels that look like a branch (dilated by the margin).
    unusable : (H, W) bool ndarray
        Matte and pixels outside ``example_mask``: never copied.
    likeness : (H, W) float ndarray
        The branch-likeness score (0 = local background colour, 1 = branch colour).
    salient : (H, W) bool ndarray, optional
        Salient spots (not copied into gaps, nor by another branch's fragments);
        None when not detected.
    """

    body: np.ndarray
    branch_like: np.ndarray
    unusable: np.ndarray
    likeness: np.ndarray
    salient: np.ndarray | None = None

    @property
    def forbidden(self) -> np.ndarray:
        """Pixels gap completion must never copy: ``body | branch_like | salient | unusable``."""
        out = self.body | self.branch_like | self.unusable
        return out | self.salient if self.salient is not None else out


def _gaussian_kernel(sigma: float, truncate: float = 4.0) -> np.ndarray:
    """scipy.ndimage's 1-D Gaussian kernel (radius ``int(truncate * sigma + 0.5)``), float64."""
    r = int(truncate * float(sigma) + 0.5)
    x = np.arange(-r, r + 1, dtype=np.float64)
    k = np.exp(-0.5 / (float(sigma) ** 2) * x * x)
    return k / k.sum()


def _gaussian(img: np.ndarray, sigma: float) -> np.ndarray:
    """``ndi.gaussian_filter(img, (sigma, sigma[, 0]), mode="nearest")`` in float64, with OpenCV.

    The same kernel and border (replicated edge) as scipy, each channel of a
    ``(H, W, C)`` image alone; equal to scipy's within float64 rounding
    (~1e-15) at about half its CPU time.
    """
    a = np.asarray(img, np.float64)
    if sigma <= 0:
        return a.copy()
    k = _gaussian_kernel(sigma)
    if a.ndim == 3 and a.shape[2] > 4:
        return np.stack([_gaussian(a[..., c], sigma) for c in range(a.shape[2])], axis=-1)
    out = cv2.sepFilter2D(np.ascontiguousarray(a), cv2.CV_64F, k, k, borderType=cv2.BORDER_REPLICATE)
    return out.reshape(a.shape)


def _normalized_blur(img: np.ndarray, weight: np.ndarray, sigma: float) -> np.ndarray:
    """Gaussian average of ``img`` over the pixels where ``weight`` is 1.

    Wide blurs (``sigma >= 12``) are computed on a grid ``sigma / 6`` times
    coarser and interpolated back (the result is smooth at that scale).
    """
    f = int(sigma // 6) if sigma >= 12 else 1
    if f > 1:
        h, w_ = weight.shape
        hs, ws = max(h // f, 1), max(w_ // f, 1)
        wt = weight.astype(np.float32)
        sw = cv2.resize(wt, (ws, hs), interpolation=cv2.INTER_AREA)
        si = cv2.resize((img * wt[..., None]).astype(np.float32), (ws, hs),
                        interpolation=cv2.INTER_AREA).reshape(hs, ws, -1)
        si = si / np.maximum(sw, 1e-9)[..., None]
        coarse = _normalized_blur(si.astype(np.float64), sw.astype(np.float64) / max(sw.max(), 1e-9),
                                  sigma / f)
        out = cv2.resize(coarse.astype(np.float32), (w_, h), interpolation=cv2.INTER_LINEAR)
        return out.reshape(img.shape).astype(np.float64)
    w = _gaussian(weight, sigma)
    out = np.empty(img.shape, np.float64)
    for c in range(img.shape[2]):
        out[..., c] = _gaussian(img[..., c] * weight, sigma)
    good = w > 1e-3
    out[good] /= w[good, None]
    if not good.all():
        # Far from every background pixel: the global background mean.
        mean = (img * weight[..., None]).sum((0, 1)) / max(weight.sum(), 1.0)
        out[~good] = mean
    return out


def flatten_shading(image: np.ndarray, background: np.ndarray, sigma: float) -> np.ndarray:
    """The example with its large-scale shading (vignetting, uneven light) divided out.

    The shading is the Gaussian average (``sigma`` pixels) of the
    ``background`` pixels only, so branches and their glow are not taken
    for light; every pixel is multiplied by ``mean shading / shading(x)``.
    Fragments and gap patches copied from a bright and a dark part of the
    example then meet without a step in brightness that no seam can hide.

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example, float in [0, 1].
    background : (H, W) bool ndarray
        Pixels that show the background texture.
    sigma : float
        Scale of the shading (pixels); well above the texture's own scale.

    Returns
    -------
    (H, W, C) float32 ndarray
        The flattened image, clipped to [0, 1] (the image unchanged when
        ``background`` is empty).
    """
    if not background.any():
        return image.astype(np.float32)
    img = image.astype(np.float64)
    shade = _normalized_blur(img, background.astype(np.float64), sigma)
    mean = img[background].mean(axis=0)
    gain = mean / np.maximum(shade, 1e-3)
    return np.clip(img * gain, 0.0, 1.0).astype(np.float32)


#: Ground light range (95th over 5th percentile of the example's background averaged at
#: ``SHADING_SCALE`` of its size) from which an example counts as shaded; evenly lit examples (the
#: procedural rivers and mud, 1.07-1.08; the mud photo 1.04) stay below, the retina fundus (1.29)
#: and photos with a light gradient or vignetting (1.9-4.8) above.
SHADED = 1.2
SHADING_SCALE = 0.1


def _is_shaded(image: np.ndarray, background: np.ndarray, line: np.ndarray | None,
               ground: np.ndarray | None) -> bool:
    """Whether the example's ground is unevenly lit and its lines are darker than their ground.

    Absorbing lines (vessels, cracks, rivers) darken with the light that falls on them, so
    dividing the light out leaves them intact; light lines (a bolt among clouds) are no such
    thing, their "shading" is the clouds themselves. ``line``, ``ground``: the median colours of
    the centre lines and of the ground beside them (None = unknown: not shaded).

    Examples
    --------
    >>> import numpy as np
    >>> ramp = np.dstack([np.tile(np.linspace(0.3, 0.9, 64), (64, 1))] * 3)
    >>> bg = np.ones((64, 64), bool)
    >>> dark, light = np.full(3, 0.1), np.full(3, 0.6)
    >>> _is_shaded(ramp, bg, dark, light), _is_shaded(ramp, bg, light, dark)
    (True, False)
    >>> _is_shaded(np.full((64, 64, 3), 0.6), bg, dark, light)
    False
    """
    if line is None or ground is None or float(np.mean(line[:3])) >= float(np.mean(ground[:3])):
        return False
    if np.count_nonzero(background) < 64:
        return False
    img = np.asarray(image, np.float64)[..., :3]
    shade = _normalized_blur(img, background.astype(np.float64), SHADING_SCALE * max(img.shape[:2]))
    v = shade.mean(axis=2)[background]
    lo, hi = np.percentile(v, [5, 95])
    return bool(hi > SHADED * max(lo, 1e-3))


def _salient_halo(salient: np.ndarray | None) -> np.ndarray | None:
    """``salient`` grown by each spot's own equivalent radius: the spot with its glow (a retina's
    optic disc lights the ground around it well beyond its bright core), which is no light of the
    example to put back where the output's pieces go.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((40, 40), bool); m[18:22, 18:22] = True     # equivalent radius 2.3
    >>> h = _salient_halo(m)
    >>> bool(h[20, 16] and not h[20, 13]), _salient_halo(None) is None
    (True, True)
    """
    if salient is None or not salient.any():
        return salient
    lab, n = ndi.label(salient)
    radius = np.sqrt(np.bincount(lab.ravel(), minlength=n + 1) / np.pi)
    radius[0] = 0.0
    dist, (iy, ix) = ndi.distance_transform_edt(~salient, return_indices=True)
    return dist <= radius[lab[iy, ix]]


def _flattened_if_shaded(ex: np.ndarray, regions: ExampleRegions, pm: PixelMap,
                         scale: float) -> tuple[np.ndarray, np.ndarray | None]:
    """``ex`` with its shading divided out (as :func:`flatten_shading`, at ``scale`` of its size)
    when :func:`_is_shaded`, and the light to put back on the output ((h, w, C) float32: the light
    ``shading / mean`` it was divided by, except near salient spots, where it is the smooth light of
    :func:`_smooth_light`); else ``(ex, None)``."""
    from .line_contrast import centre_ring_colours

    bg = ~(regions.forbidden | ndi.binary_dilation(regions.body | regions.branch_like, iterations=3))
    colours = centre_ring_colours(ex, pm)
    halo = _salient_halo(regions.salient)
    if halo is not None and np.count_nonzero(bg & ~halo) >= 64:
        # the light put back on the output is the example's vignetting, not its optic disc's glow
        bg = bg & ~halo
    if not _is_shaded(ex, bg, *(colours if colours is not None else (None, None))):
        return ex, None
    img = ex.astype(np.float64)
    shade = _normalized_blur(img, bg.astype(np.float64), scale * max(ex.shape[:2]))
    light = np.maximum(shade, 1e-3) / img[bg].mean(axis=0)
    back = light
    if halo is not None and halo.any():
        # within the blur's reach of a salient spot the light is the spot's glow: there the smooth
        # light is put back (elsewhere the example's own, blotches and all, at the same place)
        sigma = scale * max(ex.shape[:2])
        w = np.clip(1.0 - ndi.distance_transform_edt(~halo) / (3.0 * sigma), 0.0, 1.0)[..., None]
        back = np.exp(w * np.log(_smooth_light(light, bg)) + (1.0 - w) * np.log(light))
    return np.clip(img / light, 0.0, 1.0).astype(np.float32), back.astype(np.float32)


#: Degree of the polynomial the light put back on the output is (in log light over the image plane).
LIGHT_DEGREE = 4


def _smooth_light(light: np.ndarray, bg: np.ndarray, degree: int = LIGHT_DEGREE) -> np.ndarray:
    """``light`` ((h, w, C) > 0) as a polynomial of ``degree`` in x and y (least squares of its log
    over ``bg``): the example's vignetting and light gradients, without what is local (a retina's
    optic disc lights a wide patch of ground around it; put back where the output's pieces go, it
    made a pale copy of the disc without its vessels).

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:48, :64] / 64.0
    >>> ramp = np.dstack([0.5 + xx] * 3)
    >>> glow = ramp * (1 + 0.5 * np.exp(-((xx - 0.3) ** 2 + (yy - 0.4) ** 2) / 0.002))[..., None]
    >>> out = _smooth_light(glow, np.ones((48, 64), bool))
    >>> bool(abs(out[26, 19, 0] / ramp[26, 19, 0] - 1) < 0.25 < glow[26, 19, 0] / ramp[26, 19, 0] - 1)
    True
    """
    h, w = bg.shape
    step = max(1, int(max(h, w) // 128))
    ys, xs = np.nonzero(bg[::step, ::step])
    if len(ys) < 64:
        return light

    def terms(x, y):
        return np.stack([x ** i * y ** j for i in range(degree + 1) for j in range(degree + 1 - i)], -1)

    scale = float(max(h, w))
    a = terms(xs * step / scale, ys * step / scale)
    b = np.log(np.maximum(light[ys * step, xs * step], 1e-3))
    coef, *_ = np.linalg.lstsq(a, b, rcond=None)
    yy, xx = np.mgrid[:h, :w] / scale
    # (no farther than the light seen: a photo's corners beyond its disk are extrapolated)
    fit = np.clip(terms(xx.ravel(), yy.ravel()) @ coef, b.min(axis=0), b.max(axis=0))
    return np.exp(fit).reshape(h, w, light.shape[2])


def branch_likeness(image: np.ndarray, pm: PixelMap, usable: np.ndarray | None = None
                    ) -> np.ndarray:
    """Score ``(H, W)``: how far each pixel lies from its local background towards the branch colour.

    The local background ``bg(x)`` a Gaussian average (sigma ``max(6, 4 r)``)
    of the pixels farther than ``3 r + 4`` from every branch. The score is
    ``(I(x) - bg(x)) . u / |u|^2`` with ``u`` the median of ``I - bg`` over
    the centre lines: 0 on the background, about 1 on an annotated branch. All zero when branches and
    background have about the same colour (nothing to detect).

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example, float in [0, 1].
    pm : PixelMap
        Nearest-skeleton map of the annotated structure on the image grid.
    usable : (H, W) bool ndarray, optional
        Pixels that may serve as centre-line or background samples (e.g. not
        the matte); None = all.

    Returns
    -------
    (H, W) float64 ndarray
        The score (not clipped: beyond 1 for pixels more contrasted than the
        median centre line, negative on the other side of the background).
    """
    img = image.astype(np.float64)
    h, w = img.shape[:2]
    if usable is None:
        usable = np.ones((h, w), bool)
    centre = (pm.dist <= 0.5 * pm.radius + 0.5) & usable
    far = (pm.dist > 3.0 * pm.radius + 4.0) & usable
    if centre.sum() < 4 or far.sum() < 16:
        return np.zeros((h, w))
    r_med = float(np.median(pm.radius[centre]))
    bg = _normalized_blur(img, far.astype(np.float64), max(6.0, 4.0 * r_med))
    u = np.median(img[centre] - bg[centre], axis=0)
    n2 = float(u @ u)
    # Below ~4 grey levels of contrast there is nothing to tell apart.
    if n2 < 0.03**2:
        return np.zeros((h, w))
    sm = _gaussian(img, 0.7)
    return ((sm - bg) @ u) / n2


def _border_connected(flat: np.ndarray) -> np.ndarray:
    """The connected parts of ``flat`` that touch the image border."""
    lab, n = ndi.label(flat)
    if n == 0:
        return np.zeros(flat.shape, bool)
    border = np.unique(np.concatenate([lab[0], lab[-1], lab[:, 0], lab[:, -1]]))
    border = border[border > 0]
    return np.isin(lab, border) if len(border) else np.zeros(flat.shape, bool)


def matte_mask(image: np.ndarray, *, tol: float = 0.04, min_fraction: float = 0.01,
               max_fraction: float = 0.5, dilate: int = 3) -> np.ndarray:
    """Flat black or white regions connected to the border (e.g. the mask around a fundus photo).

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example, float in [0, 1].
    tol : float, default 0.04
        Pixels darker than ``tol`` or brighter than ``1 - tol`` in every channel.
    min_fraction, max_fraction : float, default 0.01, 0.5
        Ignore a matte smaller than ``min_fraction`` of the image, or larger
        than ``max_fraction``: then the flat colour is the example's
        background itself (a drawing on white, a diagram), not a matte. A
        region whose border-connected extent at ``2 * tol`` passes
        ``max_fraction`` is a noisy ground cut by ``tol``, not a matte either
        (beyond the paper, issue 23).
    dilate : int, default 3
        Grow the matte by this many pixels (its edge is blurred in photos).

    Returns
    -------
    (H, W) bool ndarray
        The matte (all False when there is none).
    """
    rgb = image[..., :3] if image.shape[2] >= 3 else image[..., :1]
    mask = np.zeros(image.shape[:2], bool)
    for flat, loose in ((np.all(rgb <= tol, axis=2), np.all(rgb <= 2.0 * tol, axis=2)),
                        (np.all(rgb >= 1.0 - tol, axis=2), np.all(rgb >= 1.0 - 2.0 * tol, axis=2))):
        m = _border_connected(flat)
        if not (min_fraction <= m.mean() <= max_fraction):
            continue
        # A noisy dark ground (a fluorescence micrograph's) straddles ``tol``: cut there, its darker
        # half looks like a matte, which left gap completion only the glow beside the branches to
        # copy (a blotchy green haze on the black). A matte's edge is a step, so at twice ``tol`` it
        # barely grows (fundus photos 0.227 -> 0.230 of the image); a ground's grows past
        # ``max_fraction`` (neuron on noisy black 0.30-0.37 -> 0.70).
        if _border_connected(loose).mean() > max_fraction:
            continue
        mask |= m
    if mask.any() and dilate > 0:
        mask = ndi.binary_dilation(mask, iterations=dilate)
    return mask


def salient_mask(image: np.ndarray, background: np.ndarray, *, z: float = 6.0,
                 sigma: float = 3.0, scale: float = 0.08, max_fraction: float = 0.05,
                 min_area: int = 30, grow: int = 4) -> np.ndarray:
    """Spots much darker or brighter than the surrounding background texture.

    The image smoothed at ``sigma`` pixels is compared with the background
    average at ``scale * max(H, W)`` pixels (over ``background`` pixels
    only); the residual's robust z-score (median and MAD over the
    background pixels, largest over the channels) above ``z`` marks a
    spot, which extends over its connected pixels above ``z / 2``. At most
    ``max_fraction`` of the background passes ``z`` (the threshold rises if
    needed: a texture full of spots has no outliers),
    connected spots smaller than ``min_area`` pixels are dropped and the
    rest grown by ``grow`` pixels.

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example, float in [0, 1].
    background : (H, W) bool ndarray
        Pixels that show the background texture (statistics come from them).
    z : float, default 6.0
        Robust z-score above which a pixel starts a spot.
    sigma : float, default 3.0
        Smoothing of the image before the comparison (pixels).
    scale : float, default 0.08
        Scale of the background average, as a fraction of ``max(H, W)``.
    max_fraction : float, default 0.05
        Largest fraction of the background allowed above ``z``.
    min_area : int, default 30
        Smallest spot kept (pixels).
    grow : int, default 4
        Dilation of the kept spots (pixels).

    Returns
    -------
    (H, W) bool ndarray
        The salient spots.
    """
    h, w = image.shape[:2]
    if background.sum() < 64:
        return np.zeros((h, w), bool)
    img = image.astype(np.float64)
    sm = _gaussian(img, sigma)
    spot = np.zeros((h, w), bool)
    for _ in range(2):
        # The second round estimates the surroundings without the spots found.
        bg = _normalized_blur(img, (background & ~spot).astype(np.float64),
                              max(scale * max(h, w), 16.0))
        res = sm - bg
        zz = np.zeros((h, w))
        for c in range(img.shape[2]):
            rc = res[..., c]
            med = float(np.median(rc[background]))
            mad = 1.4826 * float(np.median(np.abs(rc[background] - med)))
            zz = np.maximum(zz, np.abs(rc - med) / max(mad, 5e-3))
        thr = max(z, float(np.quantile(zz[background], 1.0 - max_fraction)))
        # Hysteresis: a spot extends over its connected pixels above thr / 2.
        spot = apply_hysteresis_threshold(zz, 0.5 * thr, thr) & background
    if not spot.any():
        return spot
    lab, n = ndi.label(spot)
    sizes = np.bincount(lab.ravel())
    keep = sizes >= min_area
    keep[0] = False
    spot = keep[lab]
    if grow > 0 and spot.any():
        spot = ndi.binary_dilation(spot, iterations=grow)
    return spot


def example_regions(image: np.ndarray, pm: PixelMap, *, exclusion: float = 1.5,
                    margin: float = 2.0, threshold: float | None = 0.1,
                    matte: bool = True, example_mask: np.ndarray | None = None,
                    salient: float | None = None) -> ExampleRegions:
    """The body, branch-like and unusable masks of an example.

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example, float in [0, 1].
    pm : PixelMap
        Nearest-skeleton map of the example structure on the image grid.
    exclusion, margin : float, default 1.5, 2.0
        Body = pixels within ``exclusion * r + margin`` of the skeleton
        (margin in pixels).
    threshold : float or None, default 0.1
        Branch-likeness above which an unannotated pixel counts as a
        branch (None: only the annotated body counts). It is raised to
        the median + 3 MADs of the likeness over the background if that is
        higher, and connected groups of fewer than 12 pixels, or wider
        than 1.5 times the thickest annotated branch, are ignored.
    matte : bool, default True
        Exclude a flat black/white matte connected to the border.
    example_mask : (H, W) bool ndarray, optional
        Pixels that may be copied at all (True = usable).
    salient : float or None
        z-score above which a spot counts as salient (see :func:`salient_mask`);
        None: no salient spots.

    Returns
    -------
    ExampleRegions
        The masks and the likeness score.

    Raises
    ------
    ValueError
        If ``example_mask`` and the matte leave no usable pixel.
    """
    h, w = image.shape[:2]
    unusable = np.zeros((h, w), bool)
    if matte:
        unusable |= matte_mask(image)
    if example_mask is not None:
        unusable |= ~example_mask
    body = pm.core(exclusion, margin)
    likeness = branch_likeness(image, pm, ~unusable)
    like = np.zeros((h, w), bool)
    if threshold is not None:
        far = (pm.dist > 3.0 * pm.radius + 4.0) & ~unusable
        thr = threshold
        if far.sum() > 16:
            # Ordinary texture variation (blotches in the ground, specks in
            # mud) is not a branch: stay above the background's own spread.
            lf = likeness[far]
            med = float(np.median(lf))
            thr = max(threshold, med + 3.0 * 1.4826 * float(np.median(np.abs(lf - med))))
        like = (likeness > thr) & ~body & ~unusable
        if like.any():
            # Keep connected groups that are big enough and as thin as a
            # branch (wide blobs are texture, specks are noise).
            lab, n = ndi.label(like)
            sizes = np.bincount(lab.ravel())
            half = ndi.maximum(ndi.distance_transform_edt(like), lab, np.arange(n + 1))
            r_ref = float(np.percentile(pm.radius[pm.dist <= 0.5], 95)) if (pm.dist <= 0.5).any() else 2.0
            keep = (sizes >= 12) & (np.asarray(half) <= max(1.5 * r_ref, 2.0) + 1.0)
            keep[0] = False
            like = keep[lab]
            it = int(np.ceil(margin))
            if it > 0 and like.any():
                like = ndi.binary_dilation(like, iterations=it) & ~body
    if unusable.all():
        raise ValueError("example_mask leaves no usable example pixel (outside the mask and the matte)")
    spots = None
    if salient is not None:
        near = ndi.binary_dilation(body | like, iterations=3)
        spots = salient_mask(image, ~near & ~unusable, z=salient) & ~body & ~unusable
    return ExampleRegions(body, like, unusable, likeness, spots)


# Moved by paper step; still importable from here (documented where they are defined).
from .flat_regions import colour_labels, flat_colour_regions, region_layout  # noqa: E402,F401
from .layout_model import (  # noqa: E402,F401
    RegionLayoutModel,
    fit_region_layout,
    layout_regions,
    target_layout,
)
