"""Filling and storing the prepared images (:mod:`branchnb.leaves.prepared`).

Colours bled outside a mask (:func:`_bleed`) by a smooth fill
(:func:`_smooth_fill`), a layer's mask completed by what stands out beside
it and the image under it (:func:`_completed`), the stored (float16)
copies (:func:`_stored`) and a hard alpha's outline softened (:func:`_soft_rim`).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.image import extend_nearest
from ..core.morphology import _binary_dilation, _binary_erosion

__all__: list[str] = []


def _bleed(img: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Colours of ``mask`` extended outwards, smoothly, so warps never pull in the backdrop.

    The first ring (2 px) takes the nearest blade pixel's colour (the
    margin's own colour right at the outline); farther out a smooth fill
    (:func:`_smooth_fill`). The nearest colour alone extended every
    outline pixel along a ray: where a new blade reached past the
    exemplar's (a margin notch of the donor), the new leaf showed
    fan-shaped hatched streaks of the notch's colours (drawn oaks at 1 MP).
    """
    img = np.asarray(img, np.float32)
    mask = np.asarray(mask, bool)
    if not mask.any() or mask.all():
        return img
    ring = _binary_dilation(mask, iterations=2)
    # Only the ring's nearest colours are read (_smooth_fill keeps its known pixels as they are and
    # ignores the others): the nearest-pixel search on the ring's box, not the canvas.
    rows, cols = np.flatnonzero(ring.any(1)), np.flatnonzero(ring.any(0))
    box = (slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1))
    near = np.zeros_like(img)
    near[box] = extend_nearest(img[box], mask[box])
    return _smooth_fill(near, ring)


def _stored(img: np.ndarray) -> np.ndarray:
    """An image kept for every new leaf: its colour channels (no alpha) as float16.

    The stage images, the leaf under each layer, the layer masks and
    weights of every exemplar are held as long as the analysis: as float32
    RGBA they were 319 MB for 3 exemplars of 1.1 MP (procedural lobed, two
    layers); float16 RGB halves that and more (relative precision 5e-4,
    a tenth of a grey level; they are turned back to float32 where sampled).
    """
    img = np.asarray(img)
    if img.ndim == 3 and img.shape[2] == 4:
        img = img[..., :3]
    return np.ascontiguousarray(img, np.float16)


def _completed(img: np.ndarray, blade: np.ndarray, mask: np.ndarray, reach: int = 3, line: bool = False):
    """A layer's mask completed by the pixels beside it that stand out as the layer does, and the leaf under it.

    Going beyond the paper (whose layers are pasted as induced). The leaf
    without the layer is estimated by filling the mask (grown by 2 px, less
    for a dense layer: :func:`_clear_of`) smoothly from the blade around it
    (:func:`_smooth_fill`); every pixel
    within ``reach`` px of the mask whose difference from that estimate
    is at least half the layer's median difference (projected on the
    layer's median colour contrast) joins the mask, and the estimate is
    made again without it. Returns ``(mask, under)``.

    The analysis' residual (an inpainting, never exact) kept the parts of
    a layer its mask missed, so a contrast taken against it was 1 there:
    an induced vein layer tracing the two rims of a wide drawn vein (a
    drawn oak) was pasted as a hollow outline around a core of blade
    colour, and one traced in dashes along a grass strip's veins stayed
    dashed.

    With ``line`` (the most structural layer of a photograph, its veins),
    what grows farther than 1 px from the mask is kept only where it joins
    two of the mask's pieces (a dash's gap): a side knob is a speck or a
    dark fleck of the blade beside the vein, not the vein. Kept, the knobs
    came with the vein onto a new leaf whose blade had none: the maples'
    pasted veins looked beaded. Share of a pasted vein layer's change more
    than 1 px from the traced vein (``python -m
    branchnb.leaves._measure_beads pasted``): maples 0.201 -> 0.188,
    procedural families unchanged (0.007-0.010).
    """
    img = np.asarray(img, np.float32)[..., :3]
    under = _smooth_fill(img, _clear_of(blade, mask))
    diff = img - under
    d = np.median(diff[mask], axis=0)
    dn = float((d ** 2).sum())
    if dn < 1e-6:
        return mask, under
    strength = (diff @ d) / dn  # 1: as strong as the layer's median pixel, in its direction
    near = _binary_dilation(mask, iterations=reach) & blade
    grown = mask | (near & (strength > 0.5))
    if line:
        grown = _without_knobs(grown, mask)
    if grown.sum() == mask.sum():
        return mask, under
    return grown, _smooth_fill(img, _clear_of(blade, grown))


#: Least share of the blade outside a layer's mask that the leaf under the layer is read from
#: (:func:`_clear_of`). Procedural elliptic leaves at 96 px, seed 1 (veins about 2 px wide, 2-4 px
#: apart, half the blade): 2 px clear of the veins left 1-11 % of the blade outside them, and the
#: fill from it was 0.02-0.07 (mean abs. RGB) off the leaf without its veins (the true blade colour
#: filled from 1 px clear of the true veins); 1 px clear left 19-38 % and 0.005-0.036 off.
_UNDER_SUPPORT = 0.15


def _clear_of(blade: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """The blade pixels the leaf under layer ``mask`` is read from: 2 px clear of it, nearer when too few.

    Beyond the paper. 2 px leaves a layer's anti-aliased rim out; a dense
    layer (the veins of a 96-px leaf, half its blade, 2-4 px apart) leaves
    almost no blade 2 px clear of it, and the fill from the few pixels
    left (the 10 px of 1546 between two vein ends) was no colour of the
    blade: once the mask had grown by what stood out against it, nothing
    was left, the leaf under the veins came out 0.1 darker than the true
    one, and the veins pasted as their ratio to it turned new leaves pale
    (blade mean (0.56, 0.74, 0.30) against the exemplars' 0.47-0.49 red,
    0.61-0.64 green). The nearest of 2, 1 and 0 px that leaves
    :data:`_UNDER_SUPPORT` of the blade outside the mask is taken.
    """
    blade = np.asarray(blade, bool)
    mask = np.asarray(mask, bool)
    outside = blade & ~mask
    need = _UNDER_SUPPORT * int(outside.sum())
    for r in (2, 1):
        known = blade & ~_binary_dilation(mask, iterations=r)
        if known.sum() >= need and known.any():
            return known
    return outside


def _without_knobs(grown: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """``grown`` without the parts beyond 1 px of ``mask`` that touch fewer than two of its pieces."""
    eight = np.ones((3, 3), bool)
    near = _binary_dilation(mask, structure=eight)
    extra = grown & ~near
    if not extra.any():
        return grown
    lab_x, n_x = ndi.label(extra, structure=eight)
    lab_m, _ = ndi.label(mask, structure=eight)
    # The pieces of the mask each extra part reaches (within 2 px: it lies beyond the 1 px ring).
    reach = ndi.grey_dilation(lab_x, size=5)
    at = (reach > 0) & (lab_m > 0)
    if not at.any():
        return grown & near
    pairs = np.unique(np.stack([reach[at], lab_m[at]], 1), axis=0)
    touched = np.bincount(pairs[:, 0], minlength=n_x + 1)
    return (grown & near) | np.isin(lab_x, np.flatnonzero(touched >= 2))


def _smooth_fill(img: np.ndarray, known: np.ndarray) -> np.ndarray:
    """``img`` with the pixels outside ``known`` filled smoothly (push-pull over an image pyramid).

    Known pixels keep their values; each unknown one takes the known
    values' mean at the finest pyramid level that reaches it, bilinearly
    upsampled (Gortler et al. 1996's push-pull).
    """
    img = np.asarray(img, np.float32)
    known = np.asarray(known, bool)
    two = img.ndim == 2
    v = img[..., None] if two else img
    w = known.astype(np.float32)
    levels = [(np.where(known[..., None], v, np.float32(0)), w)]
    while min(levels[-1][1].shape) > 2 and (levels[-1][1] <= 1e-6).any():
        pv, pw = levels[-1]
        h, wd = pw.shape
        size = ((wd + 1) // 2, (h + 1) // 2)
        nv = cv2.resize(pv, size, interpolation=cv2.INTER_AREA)
        nw = cv2.resize(pw, size, interpolation=cv2.INTER_AREA)
        levels.append((nv.reshape(nv.shape[:2] + (v.shape[2],)), nw))
    if len(levels) == 1:
        return levels[0][0][..., 0] if two else levels[0][0]
    pv, pw = levels[-1]
    cur = pv / np.maximum(pw, 1e-12)[..., None]
    for pv, pw in reversed(levels[1:-1]):
        h, wd = pw.shape
        up = cv2.resize(cur, (wd, h), interpolation=cv2.INTER_LINEAR).reshape(h, wd, v.shape[2])
        a = np.clip(pw, 0, 1)[..., None]
        cur = pv / np.maximum(pw, 1e-12)[..., None] * a + up * (1 - a)
    # The finest level's weights are 0 or 1: its blend is the known pixels or the upsampled fill
    # (the same values, without five full-resolution temporaries).
    h, wd = w.shape
    up = cv2.resize(cur, (wd, h), interpolation=cv2.INTER_LINEAR).reshape(h, wd, v.shape[2])
    out = np.where(known[..., None], v, up)
    return out[..., 0] if two else out


#: Give a hard-edged (binary) training alpha a one-pixel ramp before the shape warp carries it (:func:`_soft_rim`).
_SOFT_RIM = True


def _soft_rim(alpha: np.ndarray) -> np.ndarray:
    """A binary ``alpha`` with its outline smoothed into a ramp about 1 px wide; a soft one as it is.

    Going beyond the paper. A new leaf's alpha is the training leaf's
    carried (bilinearly) by the shape warp. A hard 0/1 alpha (a cut-out
    with no anti-aliasing) is a staircase, and a staircase turned and
    stretched by a warp comes out as a saw-toothed, frayed rim: perimeter
    of the new blade over that of its smoothed self (Gaussian of 3 px)
    1.05-1.09 against the exemplars' 1.03-1.04 (ginkgo fans, 300 px).
    Blurred by a Gaussian of 1 px and steepened back to a 1 px ramp, the
    outline is the staircase's smooth mean line. An alpha that is already
    anti-aliased (most of its outline pixels partial: photographs,
    drawings) is left as it is.
    """
    a = np.asarray(alpha, np.float32)
    inside = a > 0.5
    edge = inside & ~_binary_erosion(inside, iterations=1)
    if not _SOFT_RIM or not edge.any():
        return a
    # Partial pixels on or beside the outline: a few (a cleanup's stray) still count as hard.
    ring = _binary_dilation(edge, iterations=1)
    if ((a > 0.02) & (a < 0.98) & ring).sum() > 0.05 * edge.sum():
        return a
    soft = (cv2.GaussianBlur(a, (0, 0), 1.0) - 0.5) * np.float32(2.5) + np.float32(0.5)
    return np.clip(soft, 0.0, 1.0).astype(np.float32)
