"""A meandering example's swings kept by the growth (beyond the paper; issue 23, branching105).

The Markov step copies windows of ``m h`` (16 px by default) of the example's turns, so the output wiggles
at that scale but loses swings of a longer wavelength: a meandering river (sinuosity 1.2-1.4 over half
wavelengths of 45-130 px) came out 0.71-1.20 x as sinuous per branch (``_meander_check``). Where the
example meanders (:func:`example_meander`), every branch is held to a sine-generated heading of the
example's wavelength and amplitude (:func:`meander_factor`), as a delta's trunk is held to its sine
(:mod:`.drain_meander`). Examples that do not meander (straight, jagged, vessels) are not touched.

Notes
-----
Beyond the paper. The wavelength is read off the example's inflections; the swing is the larger of the
swing read off its headings and the swing whose sine-generated curve has the example's path-over-chord
sinuosity (the headings' one fell short: output 0.70-0.81 x the example per branch). Each branch starts
at a crossing of its sine, about the heading it starts with (its side drawn from ``rng``).
``_meander_check 160,256,512 0,1,2 1,2,3`` (before -> after): per branch within 15 % on 12 -> 17 of 27
cases, over quarter-size windows 19 -> 27 of 27 (0.90-1.12); ``_meander_check 1000 0,1 1,2``: per branch
0.67/0.65 -> 0.88/0.87 (mask 1), 0.98/1.00 -> 0.93/0.91 (mask 2), but windowed 0.80/0.79 -> 1.21/1.18 (mask
1: the swing from its inflated path over chord, 84 degrees, overshoots). The mean of the two swings was
tried: windowed 0.90-1.03 everywhere, per branch 15 of 27 only. Retina, lightning, Czech map, cracked mud,
river, line-art (256-1000 px), random-walk cracks and rivers, vessel photos and deltas (a drain has its
own trunk meander) are not read as meanders: byte-identical output.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi
from scipy.special import j0

#: A branch meanders when the sinuosity of its swings (``1 / J0(omega)`` of a sine-generated curve of
#: its heading's swing ``omega``) is at least this ...
MEANDER_MIN_SIN = 1.15
#: ... its curvature changes sign at least this many times (a bend is no meander; at 3 a 450 px random-walk
#: crack's longest line, 4 swings of 42 degrees over 87 px, was held as one: tests/test_branching_unborn.py) ...
MEANDER_MIN_CROSSINGS = 5
#: ... its swings' wavelength is at least this many Markov windows ``m h`` (shorter ones the copied windows
#: keep) ...
MEANDER_MIN_WINDOWS = 3.0
#: Smoothing (px, Gaussian sigma) of an example branch's heading and curvature before its swings are read.
MEANDER_SMOOTH_PX = 3.0
#: A swing is a run of one curvature sign past a quarter of this quantile of the branch's curvature.
MEANDER_CURV_QUANTILE = 0.9
#: The example meanders when such branches make at least this share of the length of its branches
#: longer than :data:`MEANDER_MIN_LENGTH` x its frame's larger side.
MEANDER_SHARE = 0.5
MEANDER_MIN_LENGTH = 0.15
#: Spread (radians) of a candidate's heading about the sine it is held to: its factor is
#: ``exp(-mean(d**2) / (2 MEANDER_SIGMA**2))`` over its steps.
MEANDER_SIGMA = 0.12
#: The largest swing (radians) a branch is held to: past 100 degrees a sine-generated curve loops back.
MEANDER_MAX_OMEGA = np.radians(100.0)


def _headings(p: np.ndarray) -> np.ndarray:
    d = np.diff(p, axis=0)
    return np.unwrap(np.arctan2(d[:, 1], d[:, 0]))


def _branch_meander(points: np.ndarray, min_wavelength: float) -> tuple[float, float, float] | None:
    """``(omega, wavelength, length)`` of one branch if it meanders (None otherwise): read off its
    inflections (where its smoothed heading peaks), not its chord, which a river that drifts or leaves the
    frame mid-swing makes meaningless (a 160 px meander's trunk: sinuosity 2.4 over its chord, 2 crossings)."""
    from ..core.polyline import resample_uniform

    p = np.asarray(points, np.float64)
    if len(p) < 4:
        return None
    q = resample_uniform(p, 1.0)
    if len(q) < 16:
        return None
    length = float(np.hypot(*np.diff(q, axis=0).T).sum())
    # smoothed past the pixel steps of a drawn or extracted line
    head = ndi.gaussian_filter1d(_headings(q), MEANDER_SMOOTH_PX, mode="nearest")
    curv = ndi.gaussian_filter1d(np.diff(head), MEANDER_SMOOTH_PX, mode="nearest")
    # past a quarter of a high quantile, not of the largest: one kink (a junction) would hide the swings
    # (a 1000 px meander's trunk: a kink of 0.13 rad/px, swings of 0.02)
    big = np.flatnonzero(np.abs(curv) > 0.25 * float(np.quantile(np.abs(curv), MEANDER_CURV_QUANTILE)))
    if big.size < 2:
        return None
    flips = np.flatnonzero(np.sign(curv[big[1:]]) != np.sign(curv[big[:-1]]))
    runs = np.split(big, flips + 1)
    if len(runs) < MEANDER_MIN_CROSSINGS + 1:
        return None
    peaks = np.array([r[0] + int(np.argmax(np.abs(curv[r]))) for r in runs])
    # heading between consecutive curvature peaks' midpoints (its extremes): swings of 2 omega
    mids = ((peaks[1:] + peaks[:-1]) // 2).astype(np.int64)
    if len(mids) < 2:
        return None
    swings = np.abs(np.diff(head[mids]))
    om = 0.5 * float(np.median(swings))
    lam = 2.0 * float(np.median(np.diff(mids)))
    if lam < min_wavelength or 1.0 / j0(min(om, 2.3)) < MEANDER_MIN_SIN:
        return None
    return om, lam, length


def example_meander(example, window: float) -> tuple[float, float] | None:
    """``(omega, wavelength)`` of the example's meanders (radians, pixels), or None where it does not
    meander (see :data:`MEANDER_SHARE`).

    Parameters
    ----------
    example : Structure
        The model's example structure.
    window : float
        The Markov window ``m h`` (pixels): swings shorter than :data:`MEANDER_MIN_WINDOWS` of them are
        not read as meanders.

    Returns
    -------
    tuple of float or None
        The length-weighted median swing ``omega`` of the meandering branches' headings (the amplitude of
        a sine-generated curve) and their length-weighted median wavelength.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> s = Structure([Branch(np.c_[np.arange(200.0), np.zeros(200)], 2.0)], image_shape=(200, 200))
    >>> example_meander(s, 16.0) is None
    True
    """
    if example.image_shape is not None:
        side = float(max(example.image_shape[:2]))
    else:   # no frame given: the extent of its points
        pts = [np.asarray(b.points, np.float64) for b in example.branches if len(b.points)]
        if not pts:
            return None
        allp = np.vstack(pts)
        side = float((allp.max(0) - allp.min(0)).max())
    min_len = MEANDER_MIN_LENGTH * side
    total = chords = 0.0
    rows = []
    for b in example.branches:
        p = np.asarray(b.points, np.float64)
        if len(p) < 2:
            continue
        length = float(np.hypot(*np.diff(p, axis=0).T).sum())
        if length < min_len:
            continue
        total += length
        chords += float(np.hypot(*(p[-1] - p[0])))
        m = _branch_meander(p, MEANDER_MIN_WINDOWS * window)
        if m is not None:
            rows.append(m)
    if not rows or sum(r[2] for r in rows) < MEANDER_SHARE * total:
        return None
    oms, lams, wts = (np.array(c, np.float64) for c in zip(*rows))

    def wmedian(v):
        o = np.argsort(v)
        c = np.cumsum(wts[o])
        return float(v[o][np.searchsorted(c, 0.5 * c[-1])])

    # the swing read off the headings falls short of the example's path over its branches' chords (0.70-0.81
    # x per branch on 160-512 px meanders, MEANDER_SIGMA 0.12): a sine-generated curve's sinuosity is
    # 1 / J0(omega), solved for the example's, where that is the larger swing
    return max(wmedian(oms), _omega(total / max(chords, 1e-9))), wmedian(lams)


def _omega(sin: float) -> float:
    """The swing ``omega`` (radians) of a sine-generated curve of sinuosity ``sin`` (``1 / J0(omega)``,
    at most :data:`MEANDER_MAX_OMEGA`)."""
    if sin <= 1.0:
        return 0.0
    lo, hi = 0.0, MEANDER_MAX_OMEGA
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if 1.0 / j0(mid) < sin else (lo, mid)
    return 0.5 * (lo + hi)


def meander_factor(hold: tuple[float, float, float, float], theta: float, s0: float, h: float,
                   cont_angles: np.ndarray, n_new: np.ndarray) -> np.ndarray:
    """Factor (N,) of candidates whose heading follows the sine ``hold`` = ``(base, omega, wavelength,
    phase)``: the target heading at arc length ``s`` is ``base + omega sin(2 pi s / wavelength + phase)``.

    Parameters
    ----------
    hold : tuple of float
        The branch's sine.
    theta : float
        The branch's heading now (radians, unwrapped as ``base``).
    s0 : float
        Its arc length now (pixels).
    h : float
        Markov step length.
    cont_angles : ndarray (N, m)
        Each candidate's turns.
    n_new : ndarray (N,)
        Each candidate's number of steps (the turns past it are not taken).
    """
    base, om, lam, ph = hold
    n = cont_angles.shape[1]
    heads = theta + np.cumsum(cont_angles, axis=1)
    s = s0 + h * np.arange(1, n + 1)
    target = base + om * np.sin(2.0 * np.pi * s / lam + ph)
    live = np.arange(n)[None, :] < np.asarray(n_new)[:, None]
    d2 = np.where(live, (heads - target[None, :]) ** 2, 0.0).sum(1) / np.maximum(live.sum(1), 1)
    return np.exp(-d2 / (2.0 * MEANDER_SIGMA ** 2))
