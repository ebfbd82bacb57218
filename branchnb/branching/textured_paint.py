"""Lines painted with the ground's own texture: found by their tone, not by ridges (beyond the paper).

A root system painted on soil and then given the soil's grain (the texture multiplied into the whole
painting) has no pixel of one exact colour, so :func:`~branchnb.branching.ridges._line_colour_and_width`
finds no solid paint, and the ridge filter takes every ridge of the grain for a line (a 1024 px painting
with 80 roots gave 3400 branches). Smoothed at the grain's scale, such a painting has two tones: the
ground's and the lines'. :func:`textured_line_shape` splits them at the valley of the smoothed tone's
histogram and keeps the side that is a branching shape (few pieces, long and narrow, see
:func:`~branchnb.branching.ridges._drawn_branching_width`); the caller traces that shape by its medial axis.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_gray, as_rgb

__all__ = ["textured_line_shape"]

#: The grain is smoothed away by a Gaussian of this sigma (pixels) per 1024 px of the image's shorter side,
#: at least :data:`GRAIN_SIGMA_MIN` (thin lines of a small image keep their tone).
GRAIN_SIGMA = 2.0
GRAIN_SIGMA_MIN = 1.25
#: The lines' tone starts where the pixels in excess of the ground's mirrored peak are this many times the
#: ground's own.
DOMINANCE = 2.0
#: The shape's mean width is at least this many times the ridge filter's largest scale: thinner lines on a
#: textured ground (a tree drawn on noise, cracks in mud) the filter traces well, and their smoothed tone
#: loses their thin ends (recall 0.91 -> 0.52 on a 512 px tree on noise).
MIN_WIDTH_SIGMAS = 1.5
#: ... unless the ground's fine grain (its high-pass standard deviation) is at least this share of the lines'
#: tone contrast: the ridge filter then traces the grain (0.13-0.24 on roots given the soil's grain; 0.05-0.09
#: on trees drawn on noise, cracks in mud), ...
GRAIN_MIN = 0.11
#: ... and at most this share: a ground grained as strongly as the lines' contrast (stripes) has no second tone.
GRAIN_MAX = 0.35
#: Lines whose grain (high-pass spread inside them) is more than this many times the ground's have a
#: texture of their own: not lines painted with the ground's grain.
OWN_GRAIN = 2.0
#: The lines' tone covers at least / at most this share of the image.
MIN_SHARE, MAX_SHARE = 0.01, 0.4


def _two_tone_split(tone: np.ndarray, bins: int = 96) -> tuple[float, float, float] | None:
    """``(ground peak, split, lines' tone)`` of ``tone`` when one side of the ground's peak holds a second
    tone covering :data:`MIN_SHARE` - :data:`MAX_SHARE` of the pixels; else None.

    The ground's tones are taken as symmetric about their peak: its far side, mirrored, is the ground's
    share on the near side, the rest there is the lines'. The split is the tone nearest the peak at which
    the lines' share is at least :data:`DOMINANCE` times the ground's (thin lines of a small image, their
    tone blurred into a shoulder of the ground's peak, leave no valley to split at).
    """
    lo, hi = np.percentile(tone, [0.05, 99.95])
    if hi - lo < 0.05:
        return None
    h, e = np.histogram(tone, bins=bins, range=(lo, hi))
    hs = ndi.gaussian_filter1d(h.astype(np.float64), 1.0)
    c = 0.5 * (e[:-1] + e[1:])
    g = int(np.argmax(hs))
    best = None
    for side in (-1, 1):
        near = np.arange(g - 1, -1, -1) if side < 0 else np.arange(g + 1, bins)
        far = g - side * np.arange(1, len(near) + 1)
        ground = np.where((far >= 0) & (far < bins), hs[np.clip(far, 0, bins - 1)], 0.0)
        excess = np.maximum(hs[near] - ground, 0.0)
        dom = np.flatnonzero(excess >= DOMINANCE * np.maximum(ground, 1e-9))
        if len(dom) == 0:
            continue
        k = int(dom[0])
        share = float(excess[k:].sum() / h.sum())
        if not MIN_SHARE <= share <= MAX_SHARE:
            continue
        lines = float(np.sum(excess[k:] * c[near[k:]]) / max(excess[k:].sum(), 1e-9))
        if best is None or share > best[0]:
            best = (share, (float(c[g]), float(0.5 * (c[near[k]] + c[near[max(k - 1, 0)]])), lines))
    return None if best is None else best[1]


def textured_line_shape(image, sigma_max: float = 4.0) -> np.ndarray | None:
    """The pixels of lines painted with the ground's texture in a tone of their own, or None.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        A textured picture (not a flat drawing).
    sigma_max : float, default 4.0
        The ridge filter's largest scale: the shape must be a branching one at least 3 px and
        :data:`MIN_WIDTH_SIGMAS` times as wide on average
        (:func:`~branchnb.branching.ridges._drawn_branching_width`), or its ground grained enough for the
        filter to trace the grain (:data:`GRAIN_MIN`); other lines are the filter's.

    Returns
    -------
    (H, W) bool ndarray or None
        The lines' pixels (pieces of the lines' tone holding no pixel of its core tone, grain specks, left
        out), or None when the smoothed tones are not two, or the rarer tone is no branching shape.

    Notes
    -----
    Beyond the paper (issue 23): the split is at the valley of the histogram of the luminance smoothed at
    the grain's scale (:data:`GRAIN_SIGMA`), not Otsu's threshold, which with lines covering a fifth of the
    picture lies inside the ground's dark tail and takes its darker grains for lines. A piece of the
    lines' tone counts only if some pixel of it lies past the midpoint between the valley and the lines'
    peak (a hysteresis: the grain's darkest specks reach the valley, not the lines' core).
    """
    from .ridges import PAINTED_PIECES, _drawn_branching_width

    rgb = as_rgb(image)[..., :3].astype(np.float32)
    gray = as_gray(rgb).astype(np.float32)
    h, w = gray.shape
    sigma = max(GRAIN_SIGMA_MIN, GRAIN_SIGMA * min(h, w) / 1024.0)
    tone = ndi.gaussian_filter(gray, sigma)
    split = _two_tone_split(tone)
    if split is None:
        return None
    ground, t, peak = split
    sgn = 1.0 if peak < t else -1.0
    weak = sgn * tone < sgn * t
    strong = sgn * tone < sgn * 0.5 * (t + peak)
    lab, n = ndi.label(weak, np.ones((3, 3), bool))
    keep = np.zeros(n + 1, bool)
    keep[np.unique(lab[strong])] = True
    keep[0] = False
    shape = keep[lab]
    width = _drawn_branching_width(shape, sigma_max, pieces=PAINTED_PIECES)
    if width is None or width < 3.0:
        return None
    hp = gray - ndi.gaussian_filter(gray, 1.0)
    outer = ndi.distance_transform_edt(~shape) >= 3.0
    grain = float(np.std(hp[outer])) / max(abs(ground - peak), 1e-6) if outer.any() else np.inf
    if grain > GRAIN_MAX or (width < MIN_WIDTH_SIGMAS * sigma_max and grain < GRAIN_MIN):
        return None
    # the lines carry the ground's grain; lines with a texture of their own, much stronger than the
    # ground's (a speckled neuron or a bright crack network on a dark ground, with a soma or hub: 2.3-5.9x
    # against 0.6-1.1x for roots painted with the soil's grain), are the other routes' (hubs, glow)
    inner = ndi.distance_transform_edt(shape) >= 2.0
    if inner.any() and float(np.std(hp[inner])) / max(abs(ground - peak), 1e-6) > OWN_GRAIN * grain:
        return None
    return shape
