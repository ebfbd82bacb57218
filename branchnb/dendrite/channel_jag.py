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
#: Share (of the log) of that noise kept on the cost of the outline band in thin parts
#: (:func:`_thin`; dendrite34): with
#: none the channel down a thin pole, all within the band, was a ruler-straight line (turn per
#: 10 px 1.6-8.5 deg against 35-40 on a plain canvas); at 1 it left a flat tree's trunk.
OUTLINE_JAG = 0.5

def _field(shape: tuple[int, int], rng) -> np.ndarray:
    """Noise of unit std with equal strength at every scale from 1 px to ``CHANNEL_SCALES[-1]``
    of the diagonal."""
    gen = np.random.default_rng(rng)
    diag = float(np.hypot(*shape))
    field = np.zeros(shape)
    for sigma in sorted({1.0, *(max(1.0, f * diag) for f in CHANNEL_SCALES)}):
        octave = ndimage.gaussian_filter(gen.standard_normal(shape), sigma, mode="reflect")
        field += octave / max(float(octave.std()), 1e-12)
    return field / max(float(field.std()), 1e-12)


def _rough(shape: tuple[int, int], amount: float, rng) -> np.ndarray:
    """A positive multiplier of mean ~1 whose log is noise of equal strength at every
    scale from 1 px to ``CHANNEL_SCALES[-1]`` of the diagonal (``amount`` its std)."""
    if amount <= 0:
        return np.ones(shape)
    return np.exp(amount * _field(shape, rng) - 0.5 * amount ** 2)


def _thin(sil: np.ndarray, band: float) -> np.ndarray:
    """Where a silhouette is thin: no pixel within ``band`` (share of the diagonal) of a
    pixel lies deeper than ``band`` inside the outline (a pole, a trunk; not the rim of a
    crown or a blob).

    >>> m = np.zeros((60, 60), bool); m[5:55, 5:11] = True; m[5:55, 20:55] = True
    >>> t = _thin(m, 0.05); bool(t[30, 7]), bool(t[30, 21])
    (True, False)
    """
    reach = max(band * float(np.hypot(*sil.shape)), 1.0)
    depth = ndimage.distance_transform_edt(np.pad(sil, 1))[1:-1, 1:-1]
    size = 2 * int(np.ceil(reach)) + 1
    return sil & (ndimage.maximum_filter(depth, size=size) <= reach)



#: Largest scale of the noise in thin parts (:func:`_thin_rough`), in widths of the part
#: (dendrite41: 1 -> 0.5, with :data:`THIN_GAIN`; see :func:`_thin_rough`).
THIN_SCALE = 0.5
#: Factor on the strength of that noise (on the ``amount`` given to :func:`_thin_rough`;
#: dendrite41: 1 -> 2; the median kept).
THIN_GAIN = 2.0
#: Where the noise's high side is clipped (stds): above the outside's cost the channel
#: stepped off a pole round a peak.
THIN_CLIP = 1.0


def _thin_width(thin: np.ndarray) -> float:
    """Median width (px) of the thin parts ``thin``: twice the depth along their medial axis."""
    from skimage.morphology import skeletonize

    depth = ndimage.distance_transform_edt(np.pad(thin, 1))[1:-1, 1:-1]
    axis = skeletonize(thin) & (depth > 0)
    return 2.0 * float(np.median(depth[axis])) if axis.any() else 1.0


def _thin_rough(thin: np.ndarray, amount: float, rng) -> np.ndarray:
    """A positive multiplier for the cost of the thin parts ``thin`` (a mask; 1 elsewhere):
    noise like :func:`_rough`'s (``amount`` the std of its log) but at scales from 1 px to
    ``THIN_SCALE`` times the parts' width (:func:`_thin_width`) instead of the diagonal's.

    Beyond the papers (dendrite38): the channel's noise runs up to 4 % of the diagonal, wider
    than a pole, so across a pole it did not change and the bolt went straight down it (turn
    per 10 px 17-24 deg against 35-40 inside a wide blob and on a plain canvas); the side
    branches' costs there were the lattice's per-pixel noise plus the outline band's
    constant, which drowned it (straight stubs).

    Dendrite41: at scales up to the part's width and the channel's strength the bolt still
    ran straighter down a thin part than inside a wide one (its branches' turn per 10 px
    inside a pole, a stem, a T 0.54x a wide blob's at 250 px); octaves up to
    ``THIN_SCALE = 0.5`` width with ``THIN_GAIN = 2`` times the spread (the median kept, so a
    thin part costs what it did against the wide parts) and its high side clipped at
    ``THIN_CLIP`` std (a peak dearer than the outside sent the channel off the pole round it)
    make it zigzag across the part (the main channel down a pole 8-12 px wide, 6 seeds: 21.6
    -> 31.4 deg per 10 px, all inside; 250-px poles, stems, T, lamps, stick figures, twigs:
    all-branch turn 20.4 -> 22.5 deg per 10 px, 0.52 -> 0.57 of a wide blob's; more gain or
    smaller scales add little: the part's width bounds the turn, and on a small picture,
    planned on the 512-px lattice, 10 image px span a whole part's width).

    >>> m = np.zeros((64, 64), bool); m[:, 28:36] = True
    >>> r = _thin_rough(m, 1.8, 0)
    >>> bool(r[~m].min() == r[~m].max() == 1.0 and r[m].std() > 1.0)
    True
    """
    thin = np.asarray(thin, bool)
    out = np.ones(thin.shape)
    if amount <= 0 or not thin.any():
        return out
    gen = np.random.default_rng(rng)
    width = _thin_width(thin)
    field = np.zeros(thin.shape)
    for sigma in sorted({1.0, *(max(1.0, f * THIN_SCALE * width) for f in (0.25, 0.5, 1.0))}):
        octave = ndimage.gaussian_filter(gen.standard_normal(thin.shape), sigma, mode="reflect")
        field += octave / max(float(octave.std()), 1e-12)
    field /= max(float(field[thin].std()), 1e-12)
    # the gain widens the spread but keeps the median (the part's cost against the wide
    # parts': scaled to mean 1 instead, a thin part at 3x became a highway 1e-6 as cheap)
    out[thin] = np.exp(THIN_GAIN * amount * np.minimum(field[thin], THIN_CLIP) - 0.5 * amount ** 2)
    return out

#: Where :func:`_ground` clips the noise's low side (in stds): below it the ground is flat.
GROUND_FLOOR = 2.0
#: Distance off the objects (share of the diagonal) over which :func:`_ground`'s cost grows
#: e-fold, so a bolt jumps between objects where they are close.
GROUND_REACH = 0.02


def _ground(objects: np.ndarray, amount: float, rng) -> np.ndarray:
    """A multiplier >= 1 for the cost of the ground between ``objects`` (a mask): the same
    multi-scale noise as :func:`_rough` (``amount`` the std of its log), clipped at
    ``GROUND_FLOOR`` stds below its mean and scaled so that the floor is 1 (the ground never
    gets cheaper than it was and the bolt keeps to the objects), times ``e`` per
    ``GROUND_REACH`` of the diagonal off the nearest object.

    Beyond the papers (dendrite34): the ground's cost was uniform up to the lattice's
    per-pixel noise, which averages out along a long path, so a bolt jumping from one
    object to another crossed the empty sky in a ruler-straight line; and with noise alone
    (the planner's non-scalar metric minimises a path's largest step first, whatever its
    length) it took the lowest pass of the noise wherever that was, up from an object's foot.
    Growing off the objects, the cost's lowest pass lies where they are close.

    >>> m = np.zeros((64, 64), bool); m[:, :20] = m[:, 44:] = True
    >>> g = _ground(m, 1.8, 0)
    >>> bool(g[m].min() == 1.0 and g[:, 32].min() > 10 * g[:, 21].min())
    True
    """
    obj = np.asarray(objects, bool)
    log = np.zeros(obj.shape)
    if amount > 0:
        log += amount * (np.maximum(_field(obj.shape, rng), -GROUND_FLOOR) + GROUND_FLOOR)
    if obj.any() and not obj.all():
        log += ndimage.distance_transform_edt(~obj) / (GROUND_REACH * float(np.hypot(*obj.shape)))
    return np.exp(log)


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
