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
           "flatten_shading", "flat_colour_regions", "region_layout",
           "colour_labels"]


@dataclass
class ExampleRegions:
    """Masks over the example image, all ``(H, W)`` bool.

    Attributes
    ----------
    body : annotated branches (skeleton within ``exclusion * r + margin``).
    branch_like : unannotated pixels that look like a branch (dilated by the margin).
    unusable : matte and pixels outside ``example_mask``: never copied.
    likeness : (H, W) float ndarray
        The branch-likeness score (0 = local background colour, 1 = branch colour).
    salient : salient spots (not copied into gaps, nor by another branch's fragments).
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
    w = ndi.gaussian_filter(weight.astype(np.float64), sigma, mode="nearest")
    out = np.empty(img.shape, np.float64)
    for c in range(img.shape[2]):
        out[..., c] = ndi.gaussian_filter(img[..., c] * weight, sigma, mode="nearest")
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
    background : (H, W) bool ndarray
        Pixels that show the background texture.
    sigma : float
        Scale of the shading (pixels); well above the texture's own scale.
    """
    if not background.any():
        return image.astype(np.float32)
    img = image.astype(np.float64)
    shade = _normalized_blur(img, background.astype(np.float64), sigma)
    mean = img[background].mean(axis=0)
    gain = mean / np.maximum(shade, 1e-3)
    return np.clip(img * gain, 0.0, 1.0).astype(np.float32)


def branch_likeness(image: np.ndarray, pm: PixelMap, usable: np.ndarray | None = None
                    ) -> np.ndarray:
    """Score ``(H, W)``: how far each pixel lies from its local background towards the branch colour.

    The local background ``bg(x)`` a Gaussian average (sigma ``max(6, 4 r)``)
    of the pixels farther than ``3 r + 4`` from every branch. The score is
    ``(I(x) - bg(x)) . u / |u|^2`` with ``u`` the median of ``I - bg`` over
    the centre lines: 0 on the background, about 1 on an annotated branch. All zero when branches and
    background have about the same colour (nothing to detect).
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
    sm = ndi.gaussian_filter(img, (0.7, 0.7, 0), mode="nearest")
    return ((sm - bg) @ u) / n2


def matte_mask(image: np.ndarray, *, tol: float = 0.04, min_fraction: float = 0.01,
               max_fraction: float = 0.5, dilate: int = 3) -> np.ndarray:
    """Flat black or white regions connected to the border (e.g. the mask around a fundus photo).

    Parameters
    ----------
    image : (H, W, C) float ndarray
    tol : float
        Pixels darker than ``tol`` or brighter than ``1 - tol`` in every channel.
    min_fraction, max_fraction : float
        Ignore a matte smaller than ``min_fraction`` of the image, or larger
        than ``max_fraction``: then the flat colour is the example's
        background itself (a drawing on white, a diagram), not a matte.
    dilate : int
        Grow the matte by this many pixels (its edge is blurred in photos).
    """
    rgb = image[..., :3] if image.shape[2] >= 3 else image[..., :1]
    mask = np.zeros(image.shape[:2], bool)
    for flat in (np.all(rgb <= tol, axis=2), np.all(rgb >= 1.0 - tol, axis=2)):
        lab, n = ndi.label(flat)
        if n == 0:
            continue
        border = np.unique(np.concatenate([lab[0], lab[-1], lab[:, 0], lab[:, -1]]))
        border = border[border > 0]
        if len(border) == 0:
            continue
        m = np.isin(lab, border)
        if min_fraction <= m.mean() <= max_fraction:
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
    """
    h, w = image.shape[:2]
    if background.sum() < 64:
        return np.zeros((h, w), bool)
    img = image.astype(np.float64)
    sm = ndi.gaussian_filter(img, (sigma, sigma, 0), mode="nearest")
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
    pm : PixelMap
        Nearest-skeleton map of the example structure on the image grid.
    exclusion, margin : float
        Body = pixels within ``exclusion * r + margin`` of the skeleton.
    threshold : float or None
        Branch-likeness above which an unannotated pixel counts as a
        branch (None: only the annotated body counts). It is raised to
        the median + 3 MADs of the likeness over the background if that is
        higher, and connected groups of fewer than 12 pixels, or wider
        than 1.5 times the thickest annotated branch, are ignored.
    matte : bool
        Exclude a flat black/white matte connected to the border.
    example_mask : (H, W) bool ndarray, optional
        Pixels that may be copied at all (True = usable).
    salient : float or None
        z-score above which a spot counts as salient (see :func:`salient_mask`);
        None: no salient spots.
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


def flat_colour_regions(image: np.ndarray, exclude: np.ndarray | None = None, *, tol: float = 0.03,
                        min_fraction: float = 0.02) -> tuple[np.ndarray, float]:
    """Segment an example into its large flat-colour regions (land and sea of a map, a mask's two values).

    Pixels whose 5 x 5 neighbourhood varies by less than ``tol`` in every
    channel are flat; their connected pieces are grouped by mean colour
    (within ``2 tol``), and every group covering at least ``min_fraction``
    of the image is a region. Every other pixel (texture, branches, the
    ``exclude`` mask, e.g. the annotated branch bodies) takes the label of
    the nearest region pixel, so a branch lies in the region around it.

    Returns
    -------
    labels : (H, W) int32 ndarray
        Region index per pixel (all 0 when there are fewer than two regions).
    share : float
        Fraction of the image that is flat and in a region.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 40, 3), np.float32); img[:, 20:] = 0.8
    >>> lab, share = flat_colour_regions(img)
    >>> int(lab[5, 5]), int(lab[5, 35]), share > 0.8
    (0, 1, True)
    """
    img = np.asarray(image, np.float32)
    h, w = img.shape[:2]
    rng_ = np.zeros((h, w), np.float32)
    k = np.ones((5, 5), np.uint8)
    for c in range(min(img.shape[2], 3)):
        ch = np.ascontiguousarray(img[..., c])
        rng_ = np.maximum(rng_, cv2.dilate(ch, k) - cv2.erode(ch, k))
    flat = rng_ < tol
    if exclude is not None:
        flat &= ~np.asarray(exclude, bool)
    lab, n = ndi.label(flat)
    zeros = np.zeros((h, w), np.int32)
    if n == 0:
        return zeros, 0.0
    area = np.bincount(lab.ravel(), minlength=n + 1)
    means = np.stack([ndi.mean(img[..., c], lab, np.arange(1, n + 1)) for c in range(min(img.shape[2], 3))], 1)
    order = np.argsort(-area[1:]) + 1
    groups: list[list[int]] = []
    colours: list[np.ndarray] = []
    for i in order:
        if area[i] < 0.0005 * h * w:
            break
        col = means[i - 1]
        for g, c in enumerate(colours):
            if np.max(np.abs(c - col)) <= 2 * tol:
                groups[g].append(int(i))
                break
        else:
            groups.append([int(i)])
            colours.append(col)
    region_of = np.full(n + 1, -1, np.int32)
    k_reg = 0
    for g in groups:
        if area[g].sum() >= min_fraction * h * w:
            region_of[g] = k_reg
            k_reg += 1
    if k_reg < 2:
        share = float(area[[i for g in groups for i in g if region_of[i] >= 0]].sum() / (h * w)) if k_reg else 0.0
        return zeros, share
    labels = region_of[lab]
    share = float(np.mean(labels >= 0))
    _, (iy, ix) = ndi.distance_transform_edt(labels < 0, return_indices=True)
    return labels[iy, ix].astype(np.int32), share


def region_layout(colours: np.ndarray, branches: np.ndarray, body: np.ndarray | None = None) -> np.ndarray:
    """The example's region layout without its branches: what surrounds the branches, not the branches.

    ``colours`` are per-pixel colour labels (:func:`colour_labels`, -1 =
    no region's colour). Pixels of no region's colour (a blue river on a
    map, anti-aliased edges) take the label of the nearest labelled pixel.
    When the branches themselves have a region's colour (the white
    channels of a water mask, white like the sea), the pixels of that
    colour in ``branches`` (the example's branch neighbourhood) are
    relabelled the same way, so the layout holds land and sea only and a
    target laid out on it carries no ghosts of the example's channels.
    ``body`` (default ``branches``) is where the branch colour is read.

    Examples
    --------
    >>> lab = np.zeros((20, 20), np.int32); lab[15:] = 1; lab[:, 9:11] = 1   # a channel into the sea
    >>> zone = np.zeros((20, 20), bool); zone[:15, 8:12] = True
    >>> body = np.zeros((20, 20), bool); body[:15, 9:11] = True
    >>> out = region_layout(lab, zone, body)
    >>> int(out[5, 10]), int(out[18, 10])
    (0, 1)
    """
    colours = np.asarray(colours)
    zone = np.asarray(branches, bool)
    if zone.shape != colours.shape:
        raise ValueError(f"branches must have the labels' shape {colours.shape}, got {zone.shape}")
    body = zone if body is None else np.asarray(body, bool)
    redo = colours < 0
    known = colours[body & ~redo]
    if known.size and np.count_nonzero(body & ~redo) >= 0.5 * np.count_nonzero(body):
        redo |= zone & (colours == np.bincount(known).argmax())
    if not redo.any() or redo.all():
        return colours.copy()
    _, (iy, ix) = ndi.distance_transform_edt(redo, return_indices=True)
    return colours[iy, ix]


def colour_labels(image: np.ndarray, labels: np.ndarray, sample: np.ndarray | None = None, *,
                  tol: float = 0.1) -> np.ndarray:
    """Label every pixel by the region whose mean colour matches its own colour.

    ``flat_colour_regions`` gives a branch and its anti-aliased rim the
    label of the region around it (a white channel lies in black land).
    To copy "land from land" pixel by pixel, the colour decides instead:
    a white rim pixel is water wherever it lies. Region colours are the
    means over ``sample`` (default: every pixel) of each label; a pixel
    farther than ``tol`` (in its most different channel) from every
    region colour gets -1 (a river's own colour, a blend at an edge).

    Examples
    --------
    >>> img = np.zeros((10, 10, 3), np.float32); img[:, 5:] = 1.0; img[2, 2] = 0.95; img[3, 3] = 0.5
    >>> lab = np.zeros((10, 10), np.int32); lab[:, 5:] = 1
    >>> c = colour_labels(img, lab)
    >>> int(c[2, 2]), int(c[2, 3]), int(c[3, 3])
    (1, 0, -1)
    """
    img = np.asarray(image, np.float32)
    img = img[..., :3] if img.ndim == 3 else img[..., None]
    labels = np.asarray(labels)
    use = np.ones(labels.shape, bool) if sample is None else np.asarray(sample, bool)
    ks = np.unique(labels)
    cols = []
    for k in ks:
        m = (labels == k) & use
        cols.append(np.median(img[m], 0) if m.any() else np.median(img[labels == k], 0))
    cols = np.asarray(cols, np.float32)
    d = np.abs(img[:, :, None, :] - cols[None, None]).max(-1)
    out = ks[np.argmin(d, axis=-1)].astype(np.int32)
    out[d.min(-1) > tol] = -1
    return out
