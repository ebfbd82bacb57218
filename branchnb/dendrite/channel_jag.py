"""A lightning bolt's main channel through an object made jagged (issue 25, dendrite33;
beyond the papers): noise at every scale on its cost, and its corners cut so that, made a
highway, it stays the bolt's main path. Used by :func:`~branchnb.dendrite.main_channel.strike_channel`.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

__all__: list[str] = []

#: Strength (std of the log) of the multi-scale noise on a lightning bolt's main channel's
#: cost (:func:`strike_channel`), and its largest scales (shares of the diagonal).
CHANNEL_JAG = 1.8
CHANNEL_SCALES = (0.005, 0.01, 0.02, 0.04)

def _rough(shape: tuple[int, int], amount: float, rng) -> np.ndarray:
    """A positive multiplier of mean ~1 whose log is noise of equal strength at every
    scale from 1 px to ``CHANNEL_SCALES[-1]`` of the diagonal (``amount`` its std)."""
    if amount <= 0:
        return np.ones(shape)
    gen = np.random.default_rng(rng)
    diag = float(np.hypot(*shape))
    field = np.zeros(shape)
    for sigma in sorted({1.0, *(max(1.0, f * diag) for f in CHANNEL_SCALES)}):
        octave = ndimage.gaussian_filter(gen.standard_normal(shape), sigma, mode="reflect")
        field += octave / max(float(octave.std()), 1e-12)
    field /= max(float(field.std()), 1e-12)
    return np.exp(amount * field - 0.5 * amount ** 2)


def _taut(path: np.ndarray) -> np.ndarray:
    """``path`` without the corner pixels whose neighbours along it touch: made a highway
    (weight 0, :func:`strike_weights`), the step past such a corner costs 0 too, and the
    bolt's plan cut it (its main channel then was no longer the whole path).

    >>> _taut(np.array([[0, 0], [1, 0], [1, 1], [1, 2]])).tolist()
    [[0, 0], [1, 1], [1, 2]]
    """
    keep = [0]
    for i in range(1, len(path)):
        if len(keep) >= 2 and np.abs(path[i] - path[keep[-2]]).max() <= 1:
            keep[-1] = i  # the corner keep[-1] is skipped: keep[-2] touches path[i]
        else:
            keep.append(i)
    return path[keep]
