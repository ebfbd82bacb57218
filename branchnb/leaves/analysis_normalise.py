"""Exemplars on one canvas: the check for one leaf per image, and :func:`normalise_exemplars`."""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_mask
from .layers import LayerSet

__all__ = ["normalise_exemplars"]


COMPOUND_GAP = 0.03


def _check_one_leaf(blade: np.ndarray, name: str) -> None:
    """Refuse an exemplar whose blade falls into two or more big pieces: several leaves, not one.

    A piece of at least a fifth of the largest (and 64 px) counts as a
    leaf; crumbs (a torn tip, a speck of background) do not. Pieces less
    than :data:`COMPOUND_GAP` of the leaf's size apart are one compound
    leaf (a fern frond drawn as 33 pinnae with 4-8 px gaps at 1021 px,
    1.6 % of its size, was refused as "33 separate leaves").
    """
    labels, n = ndi.label(blade)
    if n < 2:
        return
    gap = COMPOUND_GAP * np.sqrt(float(blade.sum()))
    labels, n = ndi.label(ndi.distance_transform_edt(~blade) <= gap / 2)
    labels = labels * blade
    if n < 2:
        return
    sizes = np.sort(np.bincount(labels.ravel())[1:])[::-1]
    big = sizes[sizes >= max(64, 0.2 * sizes[0])]
    if len(big) > 1:
        raise ValueError(f"{name} holds {len(big)} separate leaves (blade pieces of {', '.join(map(str, big[:4]))} "
                         "px): give one leaf per image")


def normalise_exemplars(exemplars) -> tuple[list, list, list]:
    """Exemplars on one common canvas, each centred on its blade by a whole-pixel shift.

    Each leaf is normalised by :func:`branchnb.leaves.exemplar.prepare_exemplars`
    (alpha, or a plain-background model); then all are padded to one
    canvas (the blend of inverse warps in synthesis needs one), centred on
    their blade centroids by integer shifts, so nothing is resampled and
    the user's scribbles on the training leaf move by the same shift.

    Parameters
    ----------
    exemplars : list of images or Exemplar
        At least two leaves of one kind: RGBA (the leaf in the alpha), RGB
        on a plain background, :class:`~branchnb.leaves.exemplar.Exemplar`
        or objects with an ``image`` (e.g. procedural leaves).

    Returns
    -------
    images : list of (H, W, 4) float32
    blades : list of (H, W) bool
    offsets : list of (dx, dy) int
        Where each input's pixel (0, 0) lands on the canvas.
    """
    from .exemplar import Exemplar, prepare_exemplars
    if isinstance(exemplars, np.ndarray) and exemplars.dtype != object and exemplars.ndim in (2, 3):
        raise ValueError("exemplars must be a list of leaf images, got a single image; "
                         "the method needs at least two leaves of one kind")
    try:
        items = list(exemplars)
    except TypeError as exc:
        raise TypeError(f"exemplars must be a list of leaf images, got {type(exemplars).__name__}") from exc
    if len(items) < 2:
        raise ValueError(f"exemplars holds {len(items)} leaf image(s); the method needs at least 2 leaves "
                         "of one kind (the first is the training leaf)")
    items = [e if isinstance(e, Exemplar) else getattr(e, "image", e) for e in items]
    prepared = prepare_exemplars(items, size_policy="keep", names=[f"exemplars[{i}]" for i in range(len(items))])
    for i, e in enumerate(prepared):
        _check_one_leaf(e.blade, f"exemplars[{i}]")
    cents = []
    half_h = half_w = 0
    for e in prepared:
        ys, xs = np.nonzero(e.blade)
        cy, cx = int(round(ys.mean())), int(round(xs.mean()))
        cents.append((cx, cy))
        h, w = e.shape
        half_h = max(half_h, cy, h - cy)
        half_w = max(half_w, cx, w - cx)
    turned_h, turned_w = _turned_extents([e.blade for e in prepared], cents)
    half_h, half_w = max(half_h, turned_h), max(half_w, turned_w)
    H, W = 2 * half_h, 2 * half_w
    images, blades, offsets = [], [], []
    for e, (cx, cy) in zip(prepared, cents):
        dx, dy = half_w - cx, half_h - cy
        h, w = e.shape
        img = np.zeros((H, W, 4), np.float32)
        img[dy:dy + h, dx:dx + w] = e.rgba
        b = np.zeros((H, W), bool)
        b[dy:dy + h, dx:dx + w] = e.blade
        images.append(img)
        blades.append(b)
        offsets.append((int(dx), int(dy)))
    return images, blades, offsets


def _axis_angle(xs: np.ndarray, ys: np.ndarray) -> tuple[float, float]:
    """Principal axis angle of a point set (radians) and its elongation (axis ratio >= 1)."""
    x, y = xs - xs.mean(), ys - ys.mean()
    mxx, myy, mxy = float((x * x).mean()), float((y * y).mean()), float((x * y).mean())
    ev = np.linalg.eigvalsh(np.array([[mxx, mxy], [mxy, myy]]))
    return 0.5 * float(np.arctan2(2 * mxy, mxx - myy)), float(np.sqrt(ev[1] / max(ev[0], 1e-12)))


def _turned_extents(blades, cents) -> tuple[int, int]:
    """Half height and width a canvas needs when the blades lie at different angles.

    New leaves lie in the exemplars' mean pose (:mod:`.synthesis`), and
    the pose of a leaf is only known after registration (an oak leaf
    registers to another at 150 degrees while their principal axes differ
    by 30): when the elongated blades' principal axes differ by more than
    5 degrees (a round blade's axis says nothing), the canvas holds every
    blade turned to any angle about its centroid, plus a margin for the
    random warps. Leaves photographed at one angle (most maple sets) keep
    a tight canvas.
    """
    axes, reach = [], 0.0
    for b, (cx, cy) in zip(blades, cents):
        ys, xs = np.nonzero(b)
        axes.append(_axis_angle(xs.astype(np.float64), ys.astype(np.float64)))
        reach = max(reach, float(np.sqrt(((xs - cx) ** 2 + (ys - cy) ** 2).max())))
    angles = [a for a, ratio in axes if ratio >= 1.2]
    diff = [abs((a - b + np.pi / 2) % np.pi - np.pi / 2) for a in angles for b in angles]
    if max(diff, default=0.0) < np.radians(5):
        return 0, 0
    half = int(np.ceil(1.03 * reach)) + 2
    return half, half


def _shift_mask(mask, offset, shape, name):
    m = as_mask(mask, name=name)
    out = np.zeros(shape, bool)
    dx, dy = offset
    h, w = m.shape
    if dy + h > shape[0] or dx + w > shape[1]:
        raise ValueError(f"{name} has shape {m.shape}, larger than the training leaf")
    out[dy:dy + h, dx:dx + w] = m
    return out


def _shift_layers(layer_set: LayerSet, offset) -> LayerSet:
    import copy
    ls = copy.deepcopy(layer_set)
    d = np.asarray(offset, float)
    for layer in ls.layers:
        for s in layer.scribbles:
            s.points = s.points + d
    for s in ls.background:
        s.points = s.points + d
    return ls


def _on_canvas(mask, offset, shape) -> np.ndarray:
    """A leaf's own ``mask`` placed on the common canvas ``shape`` at its whole-pixel ``offset``
    ``(dx, dy)`` from :func:`normalise_exemplars` (measures compare induced masks with a leaf's truth)."""
    out = np.zeros(shape, bool)
    dx, dy = offset
    out[dy:dy + mask.shape[0], dx:dx + mask.shape[1]] = mask
    return out
