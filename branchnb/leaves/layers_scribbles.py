"""Scribbles read for lazy snapping (:func:`branchnb.leaves.layers.grow_layers`, step 0).

Each stroke rasterised (:func:`scribble_mask`) and checked against the
image and the leaf (:func:`_check_scribbles`); the pixels of each stroke
that mark its layer rather than the blade under a wide brush
(:func:`_on_layer`); and a stand-in user for measuring
(:func:`simulate_scribbles`).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_mask
from ..core.morphology import _binary_dilation, fill_holes
from ..core.validate import brief, check_int, check_real, check_shape
from .scribbles import LayerSet, Scribble, _as_scribble

__all__ = ["scribble_mask", "simulate_scribbles"]

#: A ring around a scribble splits in two (blade, other veins) when its halves' medians are this many
#: times the blade half's spread apart (its 90th percentile, its median; :func:`_on_layer`).
_RING_SPLIT = (2.5, 6.0)
#: Scribbles one call of :func:`simulate_scribbles` may make (a user draws 10-15 per layer).
MAX_SCRIBBLES = 10_000


def scribble_mask(scribbles, shape) -> np.ndarray:
    """Rasterise scribbles (capsules of their brush radius) into an (H, W) bool mask.

    Parameters
    ----------
    scribbles : iterable of Scribble or (N, 2) array_like
        The strokes (an array is a Scribble of radius 2).
    shape : (int, int)
        ``(H, W)`` of the mask.

    Returns
    -------
    (H, W) bool ndarray
        True under some stroke; parts outside the image are clipped.

    Examples
    --------
    >>> m = scribble_mask([Scribble([(2, 2), (8, 2)], 1.0)], (5, 12))
    >>> bool(m[2, 2:9].all()), bool(m[4].any())
    (True, False)
    """
    h, w = check_shape(shape, "shape")
    if scribbles is None or isinstance(scribbles, (str, bytes)) or not hasattr(scribbles, "__iter__"):
        raise TypeError(f"scribbles must be an iterable of Scribble or (N, 2) point arrays, got {brief(scribbles)}")
    out = np.zeros((h, w), np.uint8)
    for s in scribbles:
        s = _as_scribble(s, "scribbles")
        pts = np.round(s.points * 16).astype(np.int32)
        # OpenCV refuses strokes over 32767 px thick (a radius changed after the Scribble checked it)
        thick = min(max(1, int(round(2 * s.radius))), 32767)
        if len(pts) == 1:
            cv2.circle(out, tuple(int(v) for v in pts[0]), int(round(min(s.radius, 1e6) * 16)), 1, -1,
                       lineType=cv2.LINE_8, shift=4)
        else:
            cv2.polylines(out, [pts.reshape(-1, 1, 2)], False, 1, thickness=thick,
                          lineType=cv2.LINE_8, shift=4)
    return out.astype(bool)


def _check_scribbles(layer_set: LayerSet, blade: np.ndarray) -> tuple[dict, dict]:
    """Rasterise and validate every scribble: name -> union mask, and name -> one mask per scribble."""
    shape = blade.shape
    out, each = {}, {}
    groups = [(x.name, f"layer_set.layers[{x.name!r}]", x.scribbles) for x in layer_set.layers]
    groups.append(("blade", "layer_set.background", layer_set.background))
    seen: dict = {}
    silhouette = None
    for name, label, scribbles in groups:
        m = np.zeros(shape, bool)
        each[name] = []
        for i, s in enumerate(scribbles):
            p = s.points
            key = (np.round(p, 3).tobytes(), round(float(s.radius), 3))
            if key in seen and seen[key][0] != name:
                raise ValueError(f"{label}.scribbles[{i}] is the same stroke as {seen[key][1]}: one stroke cannot "
                                 "mark two layers (or a layer and the background)")
            seen.setdefault(key, (name, f"{label}.scribbles[{i}]"))
            if (p[:, 0] < -0.5).any() or (p[:, 0] > shape[1] - 0.5).any() or \
                    (p[:, 1] < -0.5).any() or (p[:, 1] > shape[0] - 0.5).any():
                raise ValueError(f"{label}.scribbles[{i}] leaves the image ({shape[1]} x {shape[0]} px)")
            si = scribble_mask([s], shape)
            # Inside the leaf's outline counts as on the leaf: a stroke along a vein the blade
            # mask left out (a hole) is no mistake. A stroke mostly off the leaf is one (another
            # image's coordinates, a forgotten offset): refused with its name, not clipped to a
            # few pixels the user did not mean. The off-blade part of the others is dropped.
            if silhouette is None:
                silhouette = fill_holes(blade)
            on = (si & silhouette).sum()
            if on < 0.5 * si.sum():
                raise ValueError(f"{label}.scribbles[{i}] lies outside the leaf "
                                 f"({int(on)} of {int(si.sum())} pixels on the leaf)")
            m |= si & blade
            each[name].append(si & blade)
        out[name] = m
    return out, each


def _on_layer(each: list, feat: np.ndarray, blade: np.ndarray) -> np.ndarray:
    """The pixels of each scribble that mark its layer.

    A scribble drawn with a brush wider than its layer (a 3-px stroke on a
    1-px vein) covers plain blade as well: its pixels unlike a ring of
    blade 2-5 px around it (farther from the ring's median than 90 % of
    the ring's own pixels) are what it marks. (Half of its pixels, the
    rule before, put a third of plain blade into a thin vein's colour
    model.) Scribbles too short for a ring keep every pixel; a scribble
    inside a layer wider than the ring (a big spot) stands out from
    nothing and keeps the half most unlike the ring.
    """
    out = np.zeros(blade.shape, bool)
    h, w = blade.shape
    whole = np.median(feat[blade], axis=0)
    for m in each:
        ys, xs = np.nonzero(m)
        if len(ys) < 4:
            out |= m
            continue
        # The ring on the scribble's window (6 px beyond it: the 5-step
        # dilation reaches 5), the same pixels as on the whole image.
        y0, y1 = max(ys.min() - 6, 0), min(ys.max() + 7, h)
        x0, x1 = max(xs.min() - 6, 0), min(xs.max() + 7, w)
        mc, fc = m[y0:y1, x0:x1], feat[y0:y1, x0:x1]
        ring = _binary_dilation(mc, iterations=5) & ~_binary_dilation(mc, iterations=2) & blade[y0:y1, x0:x1]
        if ring.sum() < 4:
            out |= m
            continue
        rc = fc[ring]
        ref = np.median(rc, axis=0)
        spread = float(np.percentile(np.sqrt(((rc - ref) ** 2).sum(1)), 90))
        # Parallel veins 3-5 px apart (a 96-px strip) fill half of a ring:
        # its median colour lay between vein and blade, its spread reached
        # the veins, and half of a stroke, plain blade, joined the layer's
        # colours (the layer grew over the blade between the veins). Where
        # the ring splits in two clearly apart (its half nearer the whole
        # blade's median colour, and the rest), that half is the blade
        # around. A streaked, shaded blade's ring varies smoothly: no split.
        to_blade = ((rc - whole) ** 2).sum(1)
        near = to_blade <= np.median(to_blade)
        if near.sum() >= 4 and (~near).sum() >= 4:
            ref_near = np.median(rc[near], axis=0)
            d_near = np.sqrt(((rc[near] - ref_near) ** 2).sum(1))
            gap = float(np.sqrt(((np.median(rc[~near], axis=0) - ref_near) ** 2).sum()))
            # Measured gap / spread (90th percentile, median): a 96-px
            # strip's rings 2.8-4.3 and 6.9-11.7; streaked, shaded grass
            # blades (tests/test_leaves_layers.py) 1.1-2.5 and 2.3-5.5.
            if gap > _RING_SPLIT[0] * max(float(np.percentile(d_near, 90)), 1e-3) and \
                    gap > _RING_SPLIT[1] * max(float(np.median(d_near)), 1e-3):
                ref, spread = ref_near, float(np.percentile(d_near, 90))
        px = fc[mc]  # row-major, as np.nonzero(m)
        d = np.sqrt(((px - ref) ** 2).sum(1))
        keep = d > spread
        if keep.sum() < max(2, 0.1 * len(d)):
            keep = d >= np.median(d)
        out[ys[keep], xs[keep]] = True
    return out


def simulate_scribbles(mask, n: int = 12, *, length: float = 20.0, radius: float | None = None,
                       rng=None) -> list[Scribble]:
    """Short scribbles along a known layer mask: a stand-in user for measuring.

    Each scribble follows the mask's skeleton (junctions removed) for about
    ``length`` pixels from a random skeleton pixel, with a brush radius of
    at most half the local width (so it stays on the layer), as a user
    tracing a vein or dabbing a spot would.

    Parameters
    ----------
    mask : (H, W) bool array_like
        The layer (e.g. a procedural leaf's ground-truth veins).
    n : int
        Number of scribbles (the paper: 10-15 per layer).
    length : float
        Scribble length in pixels.
    radius : float, optional
        Brush radius; by default half the local width, clipped to [0.5, 3].
    rng : int or Generator
        Picks each scribble's start pixel on the skeleton.

    Returns
    -------
    list of Scribble
        ``n`` scribbles on ``mask``.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((30, 60), bool); m[14:17, 5:55] = True
    >>> ss = simulate_scribbles(m, 3, length=10, rng=0)
    >>> len(ss), bool(scribble_mask(ss, m.shape)[~m].sum() == 0)
    (3, True)
    """
    from skimage.morphology import skeletonize

    from ..core.random import as_rng
    mask = as_mask(mask, name="mask")
    if not mask.any():
        raise ValueError("mask is empty: nothing to scribble on")
    n = check_int(n, "n", 1, MAX_SCRIBBLES)
    length = check_real(length, "length", 0.0, 1e6, low_open=True)
    radius = check_real(radius, "radius", 0.0, 1e6, low_open=True, allow_none=True)
    rng = as_rng(rng)
    skel = skeletonize(mask)
    if not skel.any():
        skel = mask.copy()
    nb = ndi.convolve(skel.astype(np.int32), np.ones((3, 3), np.int32), mode="constant") - 1
    path = skel & (nb <= 2)
    if not path.any():
        path = skel
    dist = ndi.distance_transform_edt(mask)
    lab, _ = ndi.label(path, structure=np.ones((3, 3)))
    ys, xs = np.nonzero(path)
    out = []
    for _ in range(int(n)):
        i = int(rng.integers(len(xs)))
        x0, y0 = xs[i], ys[i]
        near = (lab[ys, xs] == lab[y0, x0]) & ((xs - x0) ** 2 + (ys - y0) ** 2 <= (length / 2) ** 2)
        px, py = xs[near].astype(float), ys[near].astype(float)
        r = radius
        if r is None:
            r = float(np.clip(0.5 * dist[py.astype(int), px.astype(int)].min(), 0.5, 3.0))
        if len(px) < 2:
            out.append(Scribble([(x0, y0)], r))
            continue
        pts = np.stack([px, py], 1)
        c = pts - pts.mean(0)
        axis = np.linalg.svd(c, full_matrices=False)[2][0]
        pts = pts[np.argsort(c @ axis)]
        out.append(Scribble(pts[:: max(1, len(pts) // 8)] if len(pts) > 8 else pts, r))
    return out
