"""Tropism: the global direction of a structure that enters from one side of the frame.

Beyond the paper (issue 23). The bending model is relative: it learns
turning angles, never where a branch heads in the image. A structure that
hangs from the frame (a plant's roots growing down from a crown at the top
edge, lightning from the top, a tree from the ground) keeps its global
direction in the example only because gravity or the ground pulled it; grown
from relative turns alone its branches wandered sideways and looped back up
(a root system's output spread from its crown in every direction).

When every root of the example enters from one side of the frame and its
lines run on the whole away from that side, :func:`_fit_tropism` learns the
example's length-weighted histogram of absolute bearings (the direction of
each segment in the image), and :func:`_tropism_factor` weighs a candidate
continuation by how common its bearing is in the example. The pull is a
drift term of its own, not the paper's: it does not depend on depth.

The same factor weighs the head a branch starts with (a child's copied input
head, :mod:`.branch_starts`), from the fork to the head's last vertex: with
the Markov steps alone a winter tree growing up from the ground (issue 23)
started its children sideways or down at the fork, and steps that only
re-weigh their few candidates went on that way. On 30 upright trees (the
tests' two generators, 128-512 px, seeds 0-4) the length share of the output
more than 100 deg from up fell from 0.11 to 0.04 on average; on the 27 that
fit a tropism from up to 0.45 to at most 0.17 (the examples' 0-0.17).
A structure that fits no tropism is unchanged.

Small trees fitted none because their trunk was lost in extraction: a
flattened silhouette (:mod:`.smooth_ground`) set its short trunk apart as a
sea (3 x its twigs' width, over 1 % of the image), rooting the crown inland
(side 5). Traced without flat regions, all 36 upright trees (96-512 px,
seeds 0-5) fit one, 11 of them (96-192 px) none before; on those 11 the
output's down share fell from 0.30 to 0.004 on average and the trunk's
largest turn from up from 47-179 deg (mean 105) to 12-57 deg (mean 39)
(the tests' two generators, synthesized with rng 0). Crack
networks entering from one side can fit one (cracked mud 160 px, a 200 x 300
crack mask: mean inward cosine 0.44-0.52): their children now head the way
the cracks run too. A head leaving the frame is never favoured (the factor
capped at 1): a crack mask's child pulled up out of the picture at its
parent's end was a stub the drawing left out, a gap in the line. A step is
only re-weighed, never refused: refusing steps
under a quarter of the mean weight (branching111) changed none of 20 of
those trees' down share and copied more of a cracked mud's ground (21 specks
against the example's 10).
"""

from __future__ import annotations

import numpy as np

from ..core.structure import Structure

#: Bearing bins of the histogram (absolute direction of a segment, 0 = +x).
TROPISM_BINS = 16
#: The example's lines must run away from their entry side on the whole: the length-weighted mean
#: cosine between a segment and the side's inward normal at least this (0 for a river network draining
#: through a side; roots hanging from the top 0.6-0.8, lightning 0.5-0.7).
TROPISM_MIN = 0.35
#: A bearing the example never takes keeps this share of the mean weight (a branch may still turn there).
TROPISM_FLOOR = 0.1
#: The weights are the smoothed histogram to this power: at 1 a root system's output (512 px) still ran
#: 73-89 % of its length down against the example's 98 %.
TROPISM_POWER = 2.0
#: Inward normal (x, y) of the frame sides, as numbered by :func:`.roots.boundary_frame`.
_INWARD = {0: (0.0, 1.0), 1: (0.0, -1.0), 2: (1.0, 0.0), 3: (-1.0, 0.0)}


def _fit_tropism(example: Structure, sides) -> np.ndarray | None:
    """The example's bearing weights ``(TROPISM_BINS,)`` (mean 1) when all its roots enter from one frame
    side (``sides``: :attr:`.roots.RootModel.sides`) and its lines run away from it
    (:data:`TROPISM_MIN`); else None. No hubs (a neuron grows all round its soma)."""
    sides = np.asarray(sides, np.int64).ravel()
    if not len(sides) or sides[0] not in _INWARD or (sides != sides[0]).any() or getattr(example, "hubs", None):
        return None
    segs = [np.diff(np.asarray(b.points, np.float64), axis=0) for b in example.branches if len(b.points) >= 2]
    if not segs:
        return None
    d = np.concatenate(segs)
    ln = np.hypot(d[:, 0], d[:, 1])
    if ln.sum() <= 0:
        return None
    inward = np.asarray(_INWARD[int(sides[0])])
    if float((d @ inward).sum() / ln.sum()) < TROPISM_MIN:
        return None
    return _bearing_weights(np.bincount(_bearing_bin(d), weights=ln, minlength=TROPISM_BINS))


def _bearing_weights(hist: np.ndarray) -> np.ndarray:
    """Weights of a length histogram over the bearing bins: smoothed [1, 2, 1] / 4 round the circle, to
    :data:`TROPISM_POWER`, mean 1, at least :data:`TROPISM_FLOOR` (also :mod:`.radial_bearing`'s)."""
    hist = (np.roll(hist, 1) + 2.0 * hist + np.roll(hist, -1)) / 4.0
    hist = (hist / hist.mean()) ** TROPISM_POWER
    return np.maximum(hist / hist.mean(), TROPISM_FLOOR)


def _angle_bin(ang: np.ndarray) -> np.ndarray:
    """Bin (of :data:`TROPISM_BINS` over ``[-pi, pi)``) of angles in radians."""
    return (np.floor((ang + np.pi) / (2.0 * np.pi) * TROPISM_BINS).astype(np.int64)) % TROPISM_BINS


def _bearing_bin(d: np.ndarray) -> np.ndarray:
    return _angle_bin(np.arctan2(d[..., 1], d[..., 0]))


def _candidate_ends(tip, pts: np.ndarray, n_new: np.ndarray) -> np.ndarray:
    """``(N, 2)``: from ``tip`` to each candidate's last live point (``pts`` (N, K, 2), ``n_new`` live each)."""
    return pts[np.arange(len(n_new)), np.maximum(n_new, 1) - 1] - np.asarray(tip, np.float64)


def _tropism_factor(weights: np.ndarray, tip, pts: np.ndarray, n_new: np.ndarray) -> np.ndarray:
    """Score factor of candidates (``pts`` (N, K, 2) after ``tip``, ``n_new`` live points each): the
    example's weight of the bearing from the tip to a candidate's last point (1 for a dead candidate)."""
    if not len(n_new):
        return np.ones(0)
    return np.where(n_new > 0, weights[_bearing_bin(_candidate_ends(tip, pts, n_new))], 1.0)
