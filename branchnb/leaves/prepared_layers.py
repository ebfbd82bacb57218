"""The layers' parts of the prepared stages (:mod:`branchnb.leaves.prepared`).

What the analysis removed of a layer beyond its mask (:func:`_removed_extension`,
:func:`_without_specks`), the background's layer rims refilled
(:func:`_refilled_rims`), the most structural layer (:func:`_leftover_layer`)
and how complete each exemplar's layer is (:func:`_completeness`).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.morphology import _binary_dilation, _binary_erosion
from .prepared_fill import _completed, _smooth_fill

__all__: list[str] = []


def _removed_extension(a, k: int, e: int, mask: np.ndarray):
    """What the analysis removed of layer ``k`` on exemplar ``e`` beyond its (completed) ``mask``, or None.

    Going beyond the paper (issue 22). The residual of a thin layer removes
    its induced mask grown along the layer's ridges
    (:func:`branchnb.leaves.analysis_induce._ridge_extension`): the faint
    ends of fine veins the colour term misses. The layer was pasted by its
    induced mask alone, so those ends left the background and never came
    back: new maples lost the fine detail at their veins' ends (mean
    gradient magnitude inside the blade 0.845-0.850 of the exemplars' on 7
    sample maples, 6 new leaves, rng 0-2; pasted back 0.887-0.917). The
    removed pixels are those the residual changed (it leaves every other
    pixel as it was); the ones more than 1 px beyond ``mask`` are returned.
    :class:`_Prepared` leaves out those within 2 px of another layer's mask
    (a vein's extension reaching into a spot's rim pasted faint rims where
    the new leaf had no spot) and pieces shorter than 8 px
    (:func:`_without_specks`), and the pasted colours there are clipped to
    the exemplars' blade colours (``synthesis_layers._paste_layers``).
    """
    if k + 1 >= len(a.residuals):
        return None
    blade = np.asarray(a.blades[e], bool)
    before = np.asarray(a.residuals[k][e], np.float32)[..., :3]
    after = np.asarray(a.residuals[k + 1][e], np.float32)[..., :3]
    removed = blade & (np.abs(before - after).max(-1) > 1e-4)
    ext = removed & ~_binary_dilation(mask, iterations=1)
    return ext if ext.any() else None


#: Pieces of a pasted ridge extension shorter than this (px, longer side of the box) are left out.
_SPECK_SIDE = 8


def _without_specks(ext: np.ndarray):
    """``ext`` without its pieces (8-connected) shorter than :data:`_SPECK_SIDE` px, or None when nothing is left.

    A ridge extension also reaches vein-coloured specks right beside a
    vein; pasted with the vein they bead it on a new leaf whose blade has
    none (``tests/test_leaves_vein_beads.py``: share of the pasted change
    more than 1 px from the true vein 0.27 with them, at most 0.25 wanted).
    The faint end of a vein is a longer piece.
    """
    lab, n = ndi.label(ext, structure=np.ones((3, 3), bool))
    if n == 0:
        return None
    keep = np.zeros(n + 1, bool)
    for i, sl in enumerate(ndi.find_objects(lab), start=1):
        keep[i] = max(sl[0].stop - sl[0].start, sl[1].stop - sl[1].start) >= _SPECK_SIDE
    out = keep[lab]
    return out if out.any() else None


def _refilled_rims(img: np.ndarray, a, e: int, top) -> np.ndarray:
    """The background ``img`` of exemplar ``e`` with what its layers (but ``top``) left around their masks filled.

    Going beyond the paper. The analysis' residual fills each induced
    mask, but a spot's rim the mask missed and its halo stayed: faint
    ghosts of the background's own spots beside the donor's pasted ones.
    Measured (procedural families of 256 px, true registrations, 3
    exemplars each): contrast left in the background at the true spots,
    as a share of the exemplar's, lobed 0.01-0.18 -> 0.01-0.06, elliptic
    0.13-0.33 -> 0.01-0.13, fan 0.07-0.21 -> 0.04-0.09 (grown by 2 px:
    0.05-0.08, 0.03-0.07, 0.05-0.07, but new leaves' colours strayed out
    of the exemplars' range on 0.04 % more of their blade). Each layer's mask is
    completed by the pixels beside it that stand out as the layer does
    (:func:`_completed`, in the image where the layer was induced), grown
    by 1 px, filled smoothly from the blade around it and given the
    blade's grain back (:func:`branchnb.leaves.leftover._grain`).
    """
    from .leftover import _grain
    blade = a.blades[e]
    hole = np.zeros(blade.shape, bool)
    for j, L in enumerate(a.layers):
        mk = np.asarray(L.masks[e], bool) & blade
        if j == top or not mk.any():
            continue
        grown, _ = _completed(a.residuals[j][e], blade, mk)
        hole |= _binary_dilation(grown, iterations=1)
    hole &= _binary_erosion(blade, iterations=1)
    if not hole.any():
        return img
    img = np.asarray(img, np.float32)
    rgb = img[..., :3]
    out = np.where(hole[..., None], _smooth_fill(rgb, blade & ~hole), rgb).astype(np.float32)
    g = _grain(rgb, blade & ~hole, hole, 4)
    out = np.where(hole[..., None], out - (out - cv2.GaussianBlur(out, (0, 0), 1.0)) + g, out)
    # Within the blade's own colours (0.5-99.5th percentiles of the pixels kept): grain added to a
    # fill can step past them, and those pixels stood out of every exemplar's colours.
    kept = rgb[blade & ~hole]
    if len(kept) > 100:
        lo, hi = np.percentile(kept, 0.5, axis=0), np.percentile(kept, 99.5, axis=0)
        out = np.where(hole[..., None], np.clip(out, lo, hi), out)
    if img.shape[-1] == 4:
        out = np.dstack([out, img[..., 3:]])
    return np.clip(out, 0.0, 1.0).astype(np.float32)


def _leftover_layer(a):
    """``(k, sign, width)`` of the most structural layer (largest lambda): its polarity on the
    training leaf and its median width (px) there; None without layers or a training mask."""
    if not a.layers or len(a.residuals) < 2:
        return None
    k = int(np.argmax([L.lam for L in a.layers]))
    t = a.training_index
    mk = np.asarray(a.layers[k].masks[t], bool) & a.blades[t]
    if mk.sum() < 10:
        return None
    g_on = np.asarray(a.residuals[k][t], np.float32)[..., :3][mk].mean(-1)
    g_off = np.asarray(a.residuals[k + 1][t], np.float32)[..., :3][mk].mean(-1)
    sign = float(np.sign(np.median(g_on - g_off)))
    from skimage.morphology import skeletonize
    sk = skeletonize(mk)
    width = float(np.median(2.0 * ndi.distance_transform_edt(mk)[sk] - 1.0)) if sk.any() else 1.0
    return (k, sign, width) if sign != 0 else None


def _completeness(layer) -> list[float]:
    """Per exemplar: skeleton length of the induced mask over the registered training mask's (at most 1),
    over the median of these ratios among the exemplars with a layer (1: as complete as most; 0: empty).
    """
    from skimage.morphology import skeletonize
    reg = getattr(layer, "registered", None)
    q = []
    for e, mk in enumerate(layer.masks):
        own = float(skeletonize(np.asarray(mk, bool)).sum()) if mk.any() else 0.0
        pred = float(skeletonize(np.asarray(reg[e], bool)).sum()) if reg is not None and reg[e].any() else own
        q.append(min(1.0, own / pred) if pred > 0 else 0.0)
    q = np.array(q)
    med = float(np.median(q[q > 0])) if (q > 0).any() else 1.0
    return [float(x / med) for x in q]
