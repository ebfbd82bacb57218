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

from ..core.structure import Structure
from .skeleton_map import PixelMap, SkeletonMap

__all__ = ["ExampleRegions", "example_regions", "branch_likeness", "matte_mask", "salient_mask",
           "flatten_shading", "flat_colour_regions", "region_layout",
           "colour_labels", "RegionLayoutModel", "fit_region_layout", "layout_regions", "target_layout"]


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
    sm = ndi.gaussian_filter(img, (0.7, 0.7, 0), mode="nearest")
    return ((sm - bg) @ u) / n2


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
        background itself (a drawing on white, a diagram), not a matte.
    dilate : int, default 3
        Grow the matte by this many pixels (its edge is blurred in photos).

    Returns
    -------
    (H, W) bool ndarray
        The matte (all False when there is none).
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


def flat_colour_regions(image: np.ndarray, exclude: np.ndarray | None = None, *, tol: float = 0.03,
                        min_fraction: float = 0.02) -> tuple[np.ndarray, float]:
    """Segment an example into its large flat-colour regions (land and sea of a map, a mask's two values).

    Pixels whose 5 x 5 neighbourhood varies by less than ``tol`` in every
    channel are flat; their connected pieces are grouped by mean colour
    (within ``2 tol``), and every group covering at least ``min_fraction``
    of the image is a region. Every other pixel (texture, branches, the
    ``exclude`` mask, e.g. the annotated branch bodies) takes the label of
    the nearest region pixel, so a branch lies in the region around it.

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example, float in [0, 1] (the first 3 channels are used).
    exclude : (H, W) bool ndarray, optional
        Pixels never taken as flat (e.g. the annotated branch bodies); None =
        none.
    tol : float, default 0.03
        Largest range of a flat 5 x 5 neighbourhood, per channel.
    min_fraction : float, default 0.02
        Smallest share of the image a region covers.

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

    Parameters
    ----------
    colours : (H, W) int ndarray
        Colour labels per pixel, -1 = no region's colour.
    branches : (H, W) bool ndarray
        The example's branch neighbourhood.
    body : (H, W) bool ndarray, optional
        Where the branch colour is read; None = ``branches``.

    Returns
    -------
    (H, W) int ndarray
        The layout: every pixel a region label >= 0 (unless no pixel had
        one).

    Raises
    ------
    ValueError
        If ``branches`` does not have the shape of ``colours``.

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

    Parameters
    ----------
    image : (H, W, C) or (H, W) float ndarray
        The example, float in [0, 1] (the first 3 channels are used).
    labels : (H, W) int ndarray
        Region labels, e.g. from :func:`flat_colour_regions`.
    sample : (H, W) bool ndarray, optional
        Pixels whose colours define the region colours (their median); None =
        all.
    tol : float, default 0.1
        Largest per-channel difference to a region colour.

    Returns
    -------
    (H, W) int32 ndarray
        The label of the nearest region colour, -1 where none is within
        ``tol``.

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


# ---------------------------------------------------------------------------
# Laying the example's regions out around other branches
#
# A region layout (land and sea of a map, floodplain along the rivers, the sea
# a delta drains into) is a function of where the branches are: the rivers lie
# in the land, their mouths on the coast, the sea beyond the mouths and away
# from every branch. The features below describe a pixel by its relation to a
# skeleton only, so the relation learnt on the example applies to any target.


def _tree_of(structure: Structure) -> np.ndarray:
    """Index of every branch's root branch."""
    out = np.arange(len(structure.branches))
    for i in range(len(out)):
        j = i
        while structure.branches[j].parent is not None:
            j = structure.branches[j].parent
        out[i] = j
    return out


def _source_rooted(structure: Structure) -> set:
    """Roots of the trees that flow from their root (a delta's inland channel, thicker than 2 x
    the median of its tips): their outlets are their tips, not their root."""
    kids = {b.parent for b in structure.branches}
    tree = _tree_of(structure)
    out = set()
    for i, b in enumerate(structure.branches):
        if b.parent is not None or len(b.points) < 2:
            continue
        tips = [float(c.thickness[-min(len(c.thickness), 4):].max()) for j, c in enumerate(structure.branches)
                if j not in kids and tree[j] == i and j != i]
        if len(tips) >= 2 and float(np.max(b.thickness[:4])) >= 2.0 * float(np.median(tips)):
            out.add(i)
    return out



def _add_heading(p: np.ndarray, pts: list, dirs: list, along: float = 8.0) -> None:
    """Append ``p``'s first point and its unit heading over the first ``along`` pixels (if it has one)."""
    arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
    k = int(np.clip(np.searchsorted(arc, along), 1, len(p) - 1))
    d = p[k] - p[0]
    n = float(np.hypot(*d))
    if n > 1e-9:
        pts.append(p[0])
        dirs.append(d / n)

def _root_starts(structure: Structure):
    """Start points ``(R, 2)`` and unit directions ``(R, 2)`` into the network of the outlets.

    An outlet is a root (a river's mouth) or, for a tree that flows from its
    root (a delta rooted at its inland channel), the tip farthest from that
    root (one of its mouths; going beyond the paper)."""
    pts, dirs = [], []
    src = _source_rooted(structure)
    kids = {b.parent for b in structure.branches}
    tree = _tree_of(structure)
    # one outlet per such tree, as a river has one mouth: its tip farthest from the source
    outlet, best = {}, {}
    for i, b in enumerate(structure.branches):
        t = int(tree[i])
        if t in src and i not in kids and i != t and len(b.points) >= 2:
            r = float(np.hypot(*(np.asarray(b.points[-1]) - structure.branches[t].points[0])))
            if r > best.get(t, -1.0):
                outlet[t], best[t] = i, r
    for i, b in enumerate(structure.branches):
        if len(b.points) < 2:
            continue
        if b.parent is None and i in src and i in outlet:
            continue
        if b.parent is not None:
            if outlet.get(int(tree[i])) != i:
                continue
            # from the tip, heading into the network
            _add_heading(np.asarray(b.points, np.float64)[::-1], pts, dirs)
            continue
        _add_heading(np.asarray(b.points, np.float64), pts, dirs)
    return np.asarray(pts, np.float64).reshape(-1, 2), np.asarray(dirs, np.float64).reshape(-1, 2)


def _hull_features(structure: Structure, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where points ``q`` lie relative to the convex hull of the skeleton.

    Returns the signed distance to the hull (> 0 outside); how much the
    nearest hull edge faces the way the nearest root points out of the
    network; and the signed distance beyond the coast line at the nearest
    root (below). The hull's edges between river mouths follow the coast,
    the sea lies outside them in the direction the mouths point (a cosine
    of about 1); outside an edge that runs along a river (the land beside
    a delta's outer arm) the cosine is about 0.
    """
    pts = np.vstack([np.asarray(b.points, np.float64) for b in structure.branches])
    hull = cv2.convexHull(pts.astype(np.float32)).reshape(-1, 2).astype(np.float64)
    n = len(q)
    if len(hull) < 3:
        return np.zeros(n), np.zeros(n), np.zeros(n)
    a, b = hull, np.roll(hull, -1, axis=0)
    ab = b - a
    t = np.clip((((q[:, None, :] - a[None]) * ab[None]).sum(-1)) / np.maximum((ab ** 2).sum(-1), 1e-9), 0.0, 1.0)
    d = np.hypot(*(q[:, None, :] - (a[None] + t[..., None] * ab[None])).transpose(2, 0, 1))
    e = np.argmin(d, axis=1)
    dist = d[np.arange(n), e]
    # outward normals: the hull from cv2 is ordered, its centroid inside
    nrm = np.column_stack([ab[:, 1], -ab[:, 0]]) / np.maximum(np.hypot(ab[:, 0], ab[:, 1]), 1e-9)[:, None]
    if ((a + 0.5 * ab - hull.mean(0)) * nrm).sum(1).mean() < 0:
        nrm = -nrm
    inside = np.all(((q[:, None, :] - a[None]) * nrm[None]).sum(-1) <= 0.0, axis=1)
    signed = np.where(inside, -dist, dist)
    starts, heads = _root_starts(structure)
    if len(starts) == 0:
        return signed, np.zeros(n), np.zeros(n)
    from scipy.spatial import cKDTree

    _, k = cKDTree(starts).query(q)
    facing = -(nrm[e] * heads[k]).sum(1)
    # The coast line at each root: of the two hull edges at the hull vertex
    # nearest to the root, the one that faces away from the skeleton's centre
    # most (a root's own heading can run along the coast); how far a point
    # lies beyond that line, extended past the hull (the coast goes on
    # beyond the outermost mouth).
    v = np.argmin(np.hypot(*(starts[:, None, :] - hull[None]).transpose(2, 0, 1)), axis=1)
    cand = np.stack([v, (v - 1) % len(hull)], 1)
    away = starts - pts.mean(0)
    away /= np.maximum(np.hypot(away[:, 0], away[:, 1]), 1e-9)[:, None]
    face = (nrm[cand] * away[:, None, :]).sum(-1)
    coast = cand[np.arange(len(starts)), np.argmax(face, 1)]
    beyond = ((q - starts[k]) * nrm[coast[k]]).sum(1)
    return signed, facing, beyond


def _layout_features(structure: Structure, pm: PixelMap, sigma: float, stride: int) -> np.ndarray:
    """Per-pixel features ``(h', w', 9)`` on every ``stride``-th pixel, from the skeleton alone.

    Distance to the centre line and to the branch's edge, distance to the
    nearest root start, the cosine between the root's heading and the
    direction to the pixel (-1 behind a river mouth) and the offset along
    that heading, how one-sided the branches around the pixel are (the
    length of the mean offset to the skeleton pixels within ``sigma``,
    over ``sigma``: about 0 inside a branch network, about 0.8 beside it,
    e.g. in the sea off a coast), and the pixel's relation to the convex
    hull of the skeleton (see :func:`_hull_features`: the line between a
    delta's mouths is its coast).

    Nothing refers to the image frame: an example's sea may be 40 pixels
    deep along its bottom side, a target's 60; the trees would learn the
    frame distance, which separates the example perfectly and says nothing
    about a target of another size.
    """
    h, w = pm.dist.shape
    ys = np.arange(0, h, stride)
    xs = np.arange(0, w, stride)
    dist = pm.dist[np.ix_(ys, xs)]
    edge = dist - pm.radius[np.ix_(ys, xs)]
    yy, xx = np.meshgrid(ys.astype(np.float64), xs.astype(np.float64), indexing="ij")
    q = np.column_stack([xx.ravel(), yy.ravel()])
    starts, heads = _root_starts(structure)
    if len(starts):
        from scipy.spatial import cKDTree

        d_root, k = cKDTree(starts).query(q)
        off = q - starts[k]
        cos = (off * heads[k]).sum(1) / np.maximum(d_root, 1e-9)
        d_root = d_root.reshape(yy.shape)
        cos = np.where(d_root > 1e-9, cos.reshape(yy.shape), 1.0)
        along = (off * heads[k]).sum(1).reshape(yy.shape)
    else:
        d_root = np.full(yy.shape, float(np.hypot(h, w)))
        cos = np.zeros(yy.shape)
        along = np.zeros(yy.shape)
    skel = (pm.dist <= 0.75).astype(np.float64)
    gy_, gx_ = np.mgrid[0:h, 0:w].astype(np.float64)
    n = ndi.gaussian_filter(skel, sigma, mode="constant")
    mx = ndi.gaussian_filter(skel * gx_, sigma, mode="constant")
    my = ndi.gaussian_filter(skel * gy_, sigma, mode="constant")
    good = n > 1e-6
    ox = np.where(good, mx / np.maximum(n, 1e-12) - gx_, 0.0)
    oy = np.where(good, my / np.maximum(n, 1e-12) - gy_, 0.0)
    side = np.where(good, np.hypot(ox, oy) / sigma, 1.0)[np.ix_(ys, xs)]
    hull_d, facing, beyond = (a.reshape(yy.shape) for a in _hull_features(structure, q))

    def slog(v):
        return np.sign(v) * np.log1p(np.abs(v))

    return np.stack([np.log1p(dist), slog(edge), np.log1p(d_root), cos, slog(along), side,
                     slog(hull_d), facing, slog(beyond)], axis=-1)


@dataclass
class RegionLayoutModel:
    """How an example's flat regions lie around its branches (see :func:`fit_region_layout`).

    Parameters
    ----------
    labels : (K,) int ndarray
        The region labels.
    shares : (K,) ndarray
        Fraction of the example covered by each region.
    branch_region : int
        The region the branches lie in (the land of a river map).
    sigma : float
        Scale (pixels) of the one-sidedness feature.
    min_area : (K,) ndarray
        Smallest piece of each region in the example (pixels); smaller
        pieces of a target layout are absorbed by their surroundings.
    classifier : object, optional
        Predicts a pixel's region from its relation to the skeleton (None
        when the example has a single region).
    bearing : (K,) bool ndarray, optional
        Regions that hold a real share (>= 10 %) of the example's centre
        lines besides the branch region (a drawn tree's branches run on
        white ground and through a green crown); a target branch may lie in
        any of them. None: only in the branch region.
    """

    labels: np.ndarray
    shares: np.ndarray
    branch_region: int
    sigma: float
    min_area: np.ndarray
    classifier: object | None = None
    bearing: np.ndarray | None = None


def _stride(shape) -> int:
    return max(1, int(round(np.sqrt(shape[0] * shape[1]) / 160.0)))


def fit_region_layout(layout: np.ndarray, structure: Structure, pm: PixelMap | None = None
                      ) -> RegionLayoutModel:
    """Learn from an example how its regions relate to its branches.

    Parameters
    ----------
    layout : (H, W) int ndarray
        Region of every example pixel, branches relabelled to their
        surroundings (:func:`region_layout`).
    structure : Structure
        The example's branches.
    pm : PixelMap, optional
        Its nearest-skeleton map on the layout's grid (computed if omitted).

    Returns
    -------
    RegionLayoutModel
        The learnt relation (without a classifier when the layout has a
        single region).

    Raises
    ------
    ValueError
        If ``layout`` is not a 2-D integer label map.

    Notes
    -----
    The region the branches lie in is the most common layout label on the
    centre lines. An ensemble of randomised trees learns every pixel's
    region from its relation to the skeleton (see ``_layout_features``):
    distance to the branches and to their edge, to the nearest root start
    and on which side of it, how one-sided the branches around it are, and
    how far outside the skeleton's convex hull (beyond the coast line
    through the mouths) it lies; never its distance to the image frame.
    """
    from sklearn.ensemble import ExtraTreesClassifier

    lay = np.asarray(layout)
    if lay.ndim != 2 or not np.issubdtype(lay.dtype, np.integer):
        raise ValueError(f"layout must be a 2-D integer label map, got {lay.dtype} {lay.shape}")
    if pm is None:
        pm = SkeletonMap(structure, 1.0).pixel_map(lay.shape)
    labels, counts = np.unique(lay, return_counts=True)
    shares = counts / lay.size
    on = lay[pm.dist <= 0.75]
    branch_region = int(np.bincount(on - labels.min()).argmax() + labels.min()) if on.size else int(labels[0])
    inside = (pm.dist < np.inf)
    reach = pm.dist[inside & (lay == branch_region)]
    sigma = float(np.clip(2.0 * np.percentile(reach, 90) if reach.size else 20.0, 8.0, 0.25 * max(lay.shape)))
    min_area = np.zeros(len(labels))
    for i, k in enumerate(labels):
        lab, n = ndi.label(lay == k)
        sizes = np.bincount(lab.ravel())[1:]
        sizes = sizes[sizes >= 16]
        min_area[i] = float(sizes.min()) if sizes.size else 16.0
    clf = None
    if len(labels) >= 2:
        st = _stride(lay.shape)
        feats = _layout_features(structure, pm, sigma, st)
        y = lay[::st, ::st][: feats.shape[0], : feats.shape[1]]
        X = feats.reshape(-1, feats.shape[-1])
        y = y.ravel()
        step = max(1, len(y) // 30000)
        # randomised trees: fast on one core, and their average gives soft boundaries
        # (every feature at every split: with a random third of them the trees
        # lean on weak features as often as on the one that separates)
        clf = ExtraTreesClassifier(n_estimators=12, max_depth=12, min_samples_leaf=10, max_features=None,
                                   n_jobs=1, random_state=0)
        clf.fit(X[::step], y[::step])
    on_share = np.array([np.mean(on == k) for k in labels]) if on.size else np.zeros(len(labels))
    bearing = (on_share >= 0.1) | (labels == branch_region)
    return RegionLayoutModel(labels, shares, branch_region, sigma, min_area, clf, bearing)


def layout_regions(model: RegionLayoutModel, structure: Structure, shape, pm: PixelMap | None = None, *,
                   share_tolerance: float = 0.25) -> np.ndarray:
    """Lay the learnt regions out around ``structure`` on an ``(H, W)`` grid.

    The classifier's region probabilities (on a coarse grid, interpolated)
    get one bias per region, adjusted until every region covers the image
    within ``share_tolerance`` (relative) of the example's share; the branches and their bodies always lie in
    the branch region, and pieces of a region smaller than its smallest
    piece in the example are absorbed by their surroundings. The
    boundaries are smooth curves (iso-lines of distances), never block
    edges.

    Parameters
    ----------
    model : RegionLayoutModel
        From :func:`fit_region_layout`.
    structure : Structure
        The target branches (pixels of the new grid).
    shape : (H, W)
        Size of the target grid.
    pm : PixelMap, optional
        The structure's nearest-skeleton map on that grid (computed if
        omitted).
    share_tolerance : float, default 0.25
        Relative deviation from the example's share allowed to each region.

    Returns
    -------
    (H, W) int32 ndarray
        The example's region label of every pixel.
    """
    import cv2

    h, w = int(shape[0]), int(shape[1])
    if pm is None:
        pm = SkeletonMap(structure, 1.0).pixel_map((h, w))
    K = len(model.labels)
    br = int(np.flatnonzero(model.labels == model.branch_region)[0])
    if K < 2 or model.classifier is None:
        return np.full((h, w), model.labels[0], np.int32)
    st = _stride((h, w))
    feats = _layout_features(structure, pm, model.sigma, st)
    proba = np.zeros(feats.shape[:2] + (K,))
    cls = list(model.classifier.classes_)
    pr = model.classifier.predict_proba(feats.reshape(-1, feats.shape[-1]))
    for j, c in enumerate(cls):
        proba[..., int(np.flatnonzero(model.labels == c)[0])] = pr[:, j].reshape(feats.shape[:2])
    proba = proba.astype(np.float32)
    if st > 1:
        # coarse sample (i, j) sits on pixel (i st, j st)
        mx, my = np.meshgrid(np.arange(w, dtype=np.float32) / st, np.arange(h, dtype=np.float32) / st)
        proba = np.stack([cv2.remap(np.ascontiguousarray(proba[..., k]), mx, my, cv2.INTER_LINEAR,
                                    borderMode=cv2.BORDER_REPLICATE) for k in range(K)], -1)
    # the trees' thresholds leave a ragged edge: smooth it over a few pixels
    proba = np.stack([cv2.GaussianBlur(proba[..., k], (0, 0), 2.0) for k in range(K)], -1)
    logp = np.log(np.clip(proba, 1e-4, 1.0))
    body = pm.core(1.0, 1.5)
    # a branch lies in the branch region, or in another region where the example's branches also run
    # (going beyond the paper: a drawn tree's branches through its crown get no halo of ground)
    bearing = np.zeros(K, bool) if model.bearing is None else np.asarray(model.bearing, bool)
    bearing[br] = True
    several = bool(bearing.sum() >= 2)
    if several:
        on_body = logp[body]
        on_body[:, ~bearing] = -1e3
        logp[body] = on_body
    else:
        logp[body] = -1e3
        logp[body, br] = 0.0
    # One bias per region keeps the areas near the example's shares: within
    # ``share_tolerance`` of them the learnt relation decides (a target with
    # longer rivers has more floodplain), beyond it the biases pull back.
    bias = np.zeros(K, np.float32)
    lo = np.maximum(model.shares * (1.0 - share_tolerance) - 0.005, 0.0)
    hi = model.shares * (1.0 + share_tolerance) + 0.005
    for _ in range(40):
        lab = np.argmax(logp + bias, axis=-1)
        cur = np.bincount(lab.ravel(), minlength=K) / lab.size
        goal = np.clip(cur, lo, hi)
        if np.all(np.abs(cur - goal) < 0.002):
            break
        bias += 0.7 * np.log((goal + 1e-3) / (cur + 1e-3)).astype(np.float32)
    lab = np.argmax(logp + bias, axis=-1)
    lab[body] = np.where(bearing[lab[body]], lab[body], br) if several else br
    # Specks: pieces smaller than half the example's smallest piece of that
    # region, holding no branch, join their surroundings (a short river's
    # floodplain is small but stays).
    for k in range(K):
        pieces, n = ndi.label(lab == k)
        if n <= 1:
            continue
        sizes = np.bincount(pieces.ravel())
        small = (sizes < 0.5 * model.min_area[k])
        small[0] = False
        small[np.unique(pieces[body])] = False
        drop = small[pieces]
        if drop.any():
            _, (iy, ix) = ndi.distance_transform_edt(drop, return_indices=True)
            lab = np.where(drop, lab[iy, ix], lab)
    return model.labels[lab].astype(np.int32)


def target_layout(layout: np.ndarray, example_structure: Structure, target_structure: Structure, shape, *,
                  pm_example: PixelMap | None = None, pm_target: PixelMap | None = None) -> np.ndarray:
    """The example's region layout laid out around the target branches as in the example.

    ``fit_region_layout`` on the example, then ``layout_regions`` on the
    target (see both).

    Parameters
    ----------
    layout : (H, W) int ndarray
        The example's layout (:func:`region_layout`).
    example_structure : Structure
        The example's branches.
    target_structure : Structure
        The target branches.
    shape : (H2, W2)
        Size of the target grid.
    pm_example, pm_target : PixelMap, optional
        Nearest-skeleton maps of the two structures on their grids (computed
        if omitted).

    Returns
    -------
    (H2, W2) int32 ndarray
        Region label of every target pixel.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> lay = np.zeros((96, 96), np.int32); lay[:, 80:] = 1       # land left, sea right of the mouth
    >>> ex = Structure([Branch([(78, 48), (10, 40)], 1.5)])
    >>> tgt = Structure([Branch([(78, 20), (10, 70)], 1.5)])
    >>> out = target_layout(lay, ex, tgt, (96, 96))
    >>> int(out[45, 40]), int(out[20, 92])
    (0, 1)
    """
    model = fit_region_layout(layout, example_structure, pm_example)
    return layout_regions(model, target_structure, shape, pm_target)
