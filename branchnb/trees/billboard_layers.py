"""Billboard clouds, step 4: helpers that cut, place, trim and recolour the layers' textures.

Part of :func:`~branchnb.trees.billboard.billboard_cloud`; the steps are described in
:mod:`branchnb.trees.billboard`.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi


def _cut(image: np.ndarray, keep: np.ndarray, pivot: float | None = None):
    """Bounding box texture of ``keep``: (x0, y0, rgba) or None.

    With ``pivot``, the box is widened with transparent columns so that its
    centre (the axis an axial billboard turns about) is at ``x = pivot``.
    """
    ys, xs = np.nonzero(keep)
    if len(ys) == 0:
        return None
    y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    tex = image[y0:y1, x0:x1].copy()
    tex[:, :, 3] *= keep[y0:y1, x0:x1]
    if pivot is not None:
        c2 = int(round(2.0 * pivot))            # twice the wanted centre, in pixel edges
        left = max(0, (x0 + x1) - c2)           # columns to add on the left / right
        right = max(0, c2 - (x0 + x1))
        if left or right:
            tex = np.pad(tex, ((0, 0), (left, right), (0, 0)))
            x0 -= left
    return int(x0), int(y0), tex


def _trunk_strips(trunk: np.ndarray, height: int, max_strips: int = 64):
    """Horizontal strips of a trunk mask and the ``x`` each turns about.

    The pivot line runs through the trunk's middle (the per-row centre,
    smoothed over 10 % of the trunk's height, so branches and forks do not
    jerk it about); a new strip starts where the pivot has drifted by
    ``step`` pixels (0.5 % of the image height, at least 1 px; more if
    ``max_strips`` would be exceeded). Neighbouring strips then part by at
    most ``step`` in a side view, and a branching trunk keeps its branches:
    every strip turns about the stem, not about its own bounding box, whose
    centre jumps from row to row with the branches it holds.
    """
    rows = np.flatnonzero(trunk.any(axis=1))
    yy, xx = np.nonzero(trunk)
    cnt = np.bincount(yy, minlength=rows[-1] + 1)[rows]
    centre = np.bincount(yy, weights=xx, minlength=rows[-1] + 1)[rows] / cnt
    span = rows[-1] - rows[0] + 1
    sigma = max(1.0, 0.1 * span / 2.355)
    wts = ndi.gaussian_filter1d(cnt.astype(np.float64), sigma, mode="nearest")
    pivot = ndi.gaussian_filter1d(centre * cnt, sigma, mode="nearest") / np.maximum(wts, 1e-9)
    variation = float(np.abs(np.diff(pivot)).sum())
    step = max(1.0, 0.005 * height, variation / max_strips)
    out, start = [], 0
    for i in range(1, len(rows) + 1):
        if i == len(rows) or abs(pivot[i] - pivot[start]) >= step:
            strip = np.zeros_like(trunk)
            a, b = rows[start], rows[i - 1] + 1
            strip[a:b] = trunk[a:b]
            out.append((strip, float(np.mean(pivot[start:i]))))
            start = i
    return out


def _trim(tex: np.ndarray, x0: float, y0: float, allowed: np.ndarray) -> np.ndarray:
    """Multiply ``tex`` alpha by ``allowed`` under its front-view footprint (integer placement)."""
    h, w = tex.shape[:2]
    H, W = allowed.shape
    xi, yi = int(round(x0)), int(round(y0))
    win = np.zeros((h, w), np.float32)
    ax0, ay0 = max(xi, 0), max(yi, 0)
    ax1, ay1 = min(xi + w, W), min(yi + h, H)
    if ax1 > ax0 and ay1 > ay0:
        win[ay0 - yi: ay1 - yi, ax0 - xi: ax1 - xi] = allowed[ay0:ay1, ax0:ax1]
    out = tex.copy()
    out[:, :, 3] *= win
    return out


def _recolour(tex: np.ndarray, x0: float, y0: float, image: np.ndarray) -> np.ndarray:
    """``tex`` with the colours of ``image`` under its front-view footprint.

    A rear or interior billboard keeps the outline of the superpixel it was
    copied from but shows what lies in front of it in the input: a large
    flat-coloured region then stays flat coloured from the side instead of
    being speckled with colours carried over from elsewhere.
    """
    h, w = tex.shape[:2]
    H, W = image.shape[:2]
    xi, yi = int(round(x0)), int(round(y0))
    ys = np.clip(np.arange(h) + yi, 0, H - 1)
    xs = np.clip(np.arange(w) + xi, 0, W - 1)
    out = tex.copy()
    out[:, :, :3] = image[np.ix_(ys, xs)][:, :, :3]
    return out


def _same_colour_overlap(image, labels, k, sl, allowed, radius, tol):
    """Footprint of superpixel ``k`` grown by up to ``radius`` px over pixels of its own colour.

    Seen from the side, neighbouring billboards at different depths part and
    leave gaps in a flat-coloured region; grown over the neighbours' pixels
    of the same colour (within ``tol`` of the nearest own pixel, per
    channel), they overlap there and the region stays one colour. The
    texture shows the image's own colours on the grown pixels, so the front
    view is unchanged; nothing grows across a colour edge (an outline's
    pixels stay with the outline's billboards).

    Returns the grown window (slices) and its footprint mask.
    """
    H, W = labels.shape
    ya, yb = max(sl[0].start - radius, 0), min(sl[0].stop + radius, H)
    xa, xb = max(sl[1].start - radius, 0), min(sl[1].stop + radius, W)
    win = (slice(ya, yb), slice(xa, xb))
    own = labels[win] == k
    dist, (iy, ix) = ndi.distance_transform_edt(~own, return_indices=True)
    rgb = image[win][:, :, :3]
    near = rgb[iy, ix]
    grow = (~own & (dist <= radius) & allowed[win]
            & (np.abs(rgb - near).max(axis=2) <= tol))
    keep = own | grow
    ys, xs = np.nonzero(keep)
    tight = (slice(ya + ys.min(), ya + ys.max() + 1), slice(xa + xs.min(), xa + xs.max() + 1))
    return tight, keep[ys.min(): ys.max() + 1, xs.min(): xs.max() + 1]


def _shading(image: np.ndarray, labels: np.ndarray) -> float:
    """How much a crown is shaded, in [0, 1]: the median colour spread inside its superpixels.

    0 for flat-coloured clip art (every superpixel one colour), 1 for a
    photograph; scales the darkening of interior billboards, which would
    otherwise speckle flat colour regions seen from the side.
    """
    n = int(labels.max())
    if n == 0:
        return 0.0
    lum = image[:, :, :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    idx = labels.ravel()
    cnt = np.bincount(idx, minlength=n + 1).astype(np.float64)
    m1 = np.bincount(idx, weights=lum.ravel(), minlength=n + 1) / np.maximum(cnt, 1)
    m2 = np.bincount(idx, weights=lum.ravel() ** 2, minlength=n + 1) / np.maximum(cnt, 1)
    std = np.sqrt(np.maximum(m2 - m1 ** 2, 0.0))[1:][cnt[1:] > 0]
    return float(np.clip(np.median(std) / 0.05, 0.0, 1.0)) if std.size else 0.0
