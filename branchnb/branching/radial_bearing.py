"""Radial tropism (beyond the paper, issue 23): a hub's lines run outward as the example's do.

The bending model is relative: it learns turning angles, never where a branch heads. Round a hub (a
neuron's soma, a coral's centre, see :mod:`.hubs` and :mod:`.radial`) the example's lines run away
from it on the whole, because that is how they grew; grown from relative turns alone, with only the
first few hub radii pulled out along the spoke (:func:`.radial._spoke_goal`), the synthesized
primaries wandered sideways and curled round their hub. A drawn neuron of long curving dendrites
(384 px, primaries ~280 px long) grew primaries that turned 120-190 degrees and circled the soma.

This is :mod:`.tropism` in the hub's frame: :func:`_fit_radial_bearing` learns the example's
length-weighted histogram of each segment's bearing *relative to the outward direction from its
nearest hub* (mirror-symmetrised: a hub has no handedness), and :func:`_radial_factor` weighs a
candidate continuation by how common its relative bearing is in the example. Structures without hubs
take no part in it.
"""

from __future__ import annotations

import numpy as np

from .tropism import TROPISM_BINS, _angle_bin, _bearing_weights, _candidate_ends

#: Switch (for measuring against the paper's relative-only growth).
RADIAL_BEARING = True
#: Segments closer to their hub than this many hub radii are left out of the fit (under the pasted
#: disc, where "outward" is the spoke itself).
RADIAL_NEAR = 1.5


def _relative_bin(d: np.ndarray, out: np.ndarray) -> np.ndarray:
    """Bin (of :data:`~.tropism.TROPISM_BINS` over ``[-pi, pi)``) of the angle from ``out`` to ``d``."""
    return _angle_bin(np.arctan2(d[..., 1], d[..., 0]) - np.arctan2(out[..., 1], out[..., 0]))


def _nearest_hub(points: np.ndarray, hubs: np.ndarray) -> np.ndarray:
    """Index into ``hubs`` ``(K, 3)`` of the hub nearest (in hub radii) each of ``points`` ``(N, 2)``."""
    d = np.hypot(points[:, None, 0] - hubs[None, :, 0], points[:, None, 1] - hubs[None, :, 1])
    return np.argmin(d / np.maximum(hubs[None, :, 2], 1e-9), axis=1)


def _fit_radial_bearing(structure) -> np.ndarray | None:
    """``(TROPISM_BINS,)`` weights (mean 1 before the floor) of the example's bearings relative to the outward direction
    from each segment's nearest hub, or None without hubs or lines beyond :data:`RADIAL_NEAR` radii."""
    hubs = getattr(structure, "hubs", None)
    if not hubs:
        return None
    hubs = np.asarray([tuple(map(float, h[:3])) for h in hubs], np.float64)
    segs, mids = [], []
    for b in structure.branches:
        p = np.asarray(b.points, np.float64)
        if len(p) >= 2:
            segs.append(np.diff(p, axis=0))
            mids.append(0.5 * (p[1:] + p[:-1]))
    if not segs:
        return None
    d, m = np.concatenate(segs), np.concatenate(mids)
    j = _nearest_hub(m, hubs)
    out = m - hubs[j, :2]
    far = np.hypot(out[:, 0], out[:, 1]) > RADIAL_NEAR * hubs[j, 2]
    ln = np.hypot(d[:, 0], d[:, 1]) * far
    if ln.sum() <= 0:
        return None
    hist = np.bincount(_relative_bin(d, out), weights=ln, minlength=TROPISM_BINS)
    return _bearing_weights(0.5 * (hist + hist[::-1]))   # bin k holds [-pi + k w, ...): its mirror is K-1-k


def _radial_factor(weights: np.ndarray, hubs: np.ndarray, tip, pts: np.ndarray, n_new: np.ndarray) -> np.ndarray:
    """Score factor of candidates (``pts`` (N, K, 2) after ``tip``, ``n_new`` live points each): the
    example's weight of the bearing from the tip to a candidate's last point, relative to the outward
    direction from the tip's nearest of ``hubs`` ``(K, 3)`` (1 for a dead candidate)."""
    n = len(n_new)
    if not n:
        return np.ones(0)
    tip = np.asarray(tip, np.float64)
    c = hubs[_nearest_hub(tip[None], hubs)[0], :2]
    out = tip - c
    if np.hypot(out[0], out[1]) <= 1e-9:
        return np.ones(n)
    end = _candidate_ends(tip, pts, n_new)
    return np.where(n_new > 0, weights[_relative_bin(end, np.broadcast_to(out, end.shape))], 1.0)


def _radial_weights(model) -> np.ndarray | None:
    """:func:`_fit_radial_bearing` of a :class:`~branchnb.branching.model.StructureModel`'s source, kept
    on it."""
    got = model.__dict__.get("_radial_weights")
    if got is None or got[0] is not model.source:
        got = model.__dict__["_radial_weights"] = (model.source, _fit_radial_bearing(model.source))
    return got[1]
