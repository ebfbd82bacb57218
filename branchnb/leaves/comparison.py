"""How new leaves compare with their exemplars: aligned image distance, share of exemplar colours.

Used by the tests and measurements of :mod:`branchnb.leaves.synthesis`.
"""

from __future__ import annotations

import cv2
import numpy as np

__all__ = ["leaf_distance", "colour_range_fraction"]


def _align_moments(mask):
    ys, xs = np.nonzero(mask)
    c = np.array([xs.mean(), ys.mean()])
    cov = np.cov(np.stack([xs - c[0], ys - c[1]]))
    evals, evecs = np.linalg.eigh(cov)
    return c, evecs[:, ::-1], float(np.sqrt(mask.sum()))


def leaf_distance(a, b) -> float:
    """Image distance of two RGBA leaves after aligning ``b`` to ``a`` (similarity from blade moments).

    Mean absolute RGB difference (0..1) over the union of the two blades,
    on white (so shape differences count), after moving ``b``'s blade onto
    ``a``'s by centroid, principal axes and area (the better of the two
    axis signs and of mirroring).

    Parameters
    ----------
    a : (H, W, 4) array_like
        RGBA leaf, float in [0, 1]; its blade is ``alpha > 0.5``.
    b : (h, w, 4) array_like
        RGBA leaf moved onto ``a``'s frame.

    Returns
    -------
    float
        0 for identical leaves; up to 1.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.zeros((20, 20, 4), np.float32); x[5:15, 4:12] = (0.2, 0.6, 0.1, 1)
    >>> leaf_distance(x, x)
    0.0
    """
    a = np.asarray(a, np.float32)
    b = np.asarray(b, np.float32)
    for nm, v in (("a", a), ("b", b)):
        if v.ndim != 3 or v.shape[2] != 4:
            raise ValueError(f"{nm} must be an RGBA (H, W, 4) image, got shape {v.shape}")
        if not (v[..., 3] > 0.5).any():
            raise ValueError(f"{nm} has no leaf pixel (alpha > 0.5)")
    ma, mb = a[..., 3] > 0.5, b[..., 3] > 0.5
    ca, ra, sa = _align_moments(ma)
    cb, rb, sb = _align_moments(mb)
    wa = a[..., :3] * a[..., 3:] + (1 - a[..., 3:])
    wb = b[..., :3] * b[..., 3:] + (1 - b[..., 3:])
    h, w = a.shape[:2]
    best = np.inf
    for sx in (1, -1):
        for sy in (1, -1):
            rbs = rb * np.array([sx, sy])
            for mirror in (False, True):
                r = rbs.copy()
                if mirror:
                    r = r @ np.diag([1, -1])
                # x_b = cb + (sb / sa) R_b R_a^T (x_a - ca)
                lin = (sb / sa) * r @ ra.T
                off = cb - lin @ ca
                mat = np.hstack([lin, off[:, None]]).astype(np.float64)
                wbw = cv2.warpAffine(wb, mat, (w, h), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                     borderMode=cv2.BORDER_CONSTANT, borderValue=(1, 1, 1))
                mbw = cv2.warpAffine(mb.astype(np.float32), mat, (w, h),
                                     flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP) > 0.5
                u = ma | mbw
                dist = float(np.abs(wa - wbw)[u].mean()) if u.any() else 0.0
                best = min(best, dist)
    return float(best)


def colour_range_fraction(leaf_image, exemplars, blades=None, *, percentiles=(0.5, 99.5)) -> float:
    """Fraction of a leaf's blade pixels whose RGB lies inside the exemplars' range on every channel.

    The range per channel is the ``percentiles`` of all exemplar blade
    pixels, widened by two float32 steps (the images' round-off): the
    synthesis caps pale veins at the exemplars' lightest blade colour (its
    99.5th percentile), and the arithmetic after the cap (the layers'
    weighted mean, the compositing over the background) lands such a pixel
    one float32 step above it.
    Counted as outside, 50-70 px of a 19,000 px procedural blade were
    "out of range" by ``6e-8`` (``tests/test_leaves_synthesis.py``: a new
    leaf at 0.9754 against a floor of 0.9755; 0.9791 with them inside).

    Parameters
    ----------
    leaf_image : (H, W, 4) array_like
        RGBA leaf, float in [0, 1] (e.g. a :class:`GeneratedLeaf`'s image).
    exemplars : sequence of (h, w, 4) array_like
        RGBA exemplar leaves.
    blades : sequence of (h, w) bool array_like, optional
        The exemplars' blades; None: each exemplar's ``alpha > 0.5``.
    percentiles : (float, float)
        Low and high percentile of the range (default ``(0.5, 99.5)``).

    Returns
    -------
    float
        In [0, 1]; 1: every blade pixel has exemplar colours.
    """
    img = np.asarray(leaf_image, np.float32)
    inside = img[..., 3] > 0.5
    if not inside.any():
        raise ValueError("leaf_image has no leaf pixel")
    px = []
    for i, ex in enumerate(exemplars):
        ex = np.asarray(ex, np.float32)
        m = ex[..., 3] > 0.5 if blades is None else np.asarray(blades[i], bool)
        px.append(ex[..., :3][m])
    allpx = np.concatenate(px)
    lo = np.percentile(allpx, percentiles[0], axis=0).astype(np.float32)
    hi = np.percentile(allpx, percentiles[1], axis=0).astype(np.float32)
    lo, hi = lo - 2 * np.spacing(np.abs(lo)), hi + 2 * np.spacing(np.abs(hi))
    c = img[..., :3][inside]
    ok = np.all((c >= lo) & (c <= hi), axis=1)
    return float(ok.mean())
