"""Candidate scoring of structure synthesis (one Markov step, vectorised over all candidates).

``score = Q * exp(wG (dA + dR) n_t / m) / (D_c + eps) / (G_c + eps)``: the
bending model's quality ``Q``, the global histogram factor, space
colonization's density ``D_c`` ahead and the guidance ``G_c`` ahead (see
:func:`score_candidates`). Split from :mod:`branchnb.branching.synthesis`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from . import _kernels
from .colonization import DensityMap
from .guidance import Guidance
from .histogram_matching import HistogramMatcher
from .params import SynthesisParams

if TYPE_CHECKING:
    import branchnb.branching  # the full name: leaves has a SynthesisParams too (the API docs link it)

    from .model import StructureModel

__all__ = ["CandidateScores", "score_candidates"]

#: Directions a density profile is computed for per step (candidates share the nearest).
_DIRECTION_BINS = 512


def binned_profile(density: DensityMap, tip, dirs: np.ndarray, length: float) -> tuple[np.ndarray, np.ndarray]:
    """Density profiles along binned directions: each distinct direction is profiled once.

    Parameters
    ----------
    density : DensityMap
        The space-colonization density.
    tip : (2,) array_like
        Where the profiles start (x, y).
    dirs : (K, 2) ndarray
        Directions; each is replaced by the nearest of ``_DIRECTION_BINS`` directions.
    length : float
        Profile length in pixels.

    Returns
    -------
    (K,) ndarray, (K,) ndarray
        ``D_c`` and ``crossing`` of :func:`~branchnb.branching.colonization.profile_density`
        for each of ``dirs``.
    """
    d = np.ascontiguousarray(dirs, np.float64).reshape(-1, 2)
    tip = np.asarray(tip, np.float64)
    n_samples = int(min(max(np.ceil(length / (density.rho / 2.0)), 8), 48))
    # compiled (the numpy reference is profile_density over the unique bins)
    return _kernels.profile_bins(density.grid, density.cell, float(tip[0]), float(tip[1]), d, float(length),
                                 n_samples, 0.02, _DIRECTION_BINS)


@dataclass
class CandidateScores:
    """Scores of all candidates of one step.

    Parameters
    ----------
    t : (J,) int ndarray
        Candidate windows (index of their last input element).
    Q : (J,) ndarray
        Markov quality ``Q``.
    score : (J,) ndarray
        Final score ``Q***`` used for the choice (0 = forbidden).
    points : (J, m, 2) ndarray
        Vertices each candidate would append.
    n_new : (J,) int ndarray
        Real number of appended vertices.
    hist_factor, D_c, G_c : (J,) ndarray
        Global histogram factor ``exp(wG (dA + dR) n_t / m)``, density
        ``D_c`` ahead (0 without colonization) and guidance ``G_c`` ahead
        (1 without guidance).
    crossing : (J,) bool ndarray
        The density profile shows a crossing of another branch.
    """

    t: np.ndarray
    Q: np.ndarray
    score: np.ndarray
    points: np.ndarray
    n_new: np.ndarray
    hist_factor: np.ndarray
    D_c: np.ndarray
    G_c: np.ndarray
    crossing: np.ndarray


def _continue_radii(rad: np.ndarray, r_tip: float, r_src: float, r_min: float, r_max: float,
                    like: float = 0.0, resolved: float = 0.0) -> np.ndarray:
    """Copied radii scaled to continue from the tip (thickness continuity).

    ``r_src`` is the input radius that precedes the copied elements: the
    copy keeps the input's relative change (its taper) from the tip's own
    radius, ``rad * r_tip / r_src``, within the input's range
    ``[r_min, r_max]``. (Copying absolute radii, or fading a shift back to
    them, makes the radius jump at every step whenever the matched input
    piece is thicker or thinner than the tip: beads along the branch.)

    ``like`` > 0 (beyond the paper, issue 23; ``growth.TAPER_LIKENESS``): the
    relative change is raised to ``(min(r_src, r_tip) / max(r_src, r_tip)) ** like``,
    so a piece as thick as the tip passes on its whole taper and a much
    thinner or thicker one little of it. A 1-px crack's blurred end, where
    the extraction measures it 30-50 % thicker at the junction, thins the
    tip that copies it by as much: on masks with 3-4 px trunks and many 1-px
    side cracks (most of the pieces) the trunks thinned step after step from
    2.6 to 0.9 px within 160 px; with ``like`` = 2 they keep 2.1-2.4 px.
    Radii below ``resolved`` count as ``resolved`` in the likeness
    (``growth.TAPER_RESOLVED``): sub-pixel widths are alike.

    Examples
    --------
    >>> _continue_radii(np.array([0.5]), 2.0, 1.0, 0.1, 9.0).tolist()
    [1.0]
    >>> round(float(_continue_radii(np.array([0.5]), 2.0, 1.0, 0.1, 9.0, like=2.0)[0]), 3)
    1.682
    >>> _continue_radii(np.array([0.5]), 0.8, 0.6, 0.1, 9.0, like=2.0, resolved=1.0).round(3).tolist()
    [0.667]
    """
    if like > 0:
        r_src = max(r_src, 1e-9)
        lo, hi = max(min(r_src, r_tip), resolved), max(r_src, r_tip, resolved, 1e-9)
        w = (lo / hi) ** like
        return np.minimum(np.maximum(r_tip * (np.maximum(rad, 1e-9) / r_src) ** w, r_min), r_max)
    return np.minimum(np.maximum(rad * (r_tip / max(r_src, 1e-9)), r_min), r_max)   # np.clip, less overhead


def _rank_key(score: np.ndarray) -> np.ndarray:
    """Scores rounded to float32 for ranking: equal scores computed in a
    different order (last-bit differences) tie and fall back to the
    candidate index, so every scorer ranks identically."""
    return np.asarray(score, np.float64).astype(np.float32)


def _rotate(v: np.ndarray, theta: float) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    out = np.empty_like(v)
    out[..., 0] = c * v[..., 0] - s * v[..., 1]
    out[..., 1] = s * v[..., 0] + c * v[..., 1]
    return out


@dataclass
class _Base:
    """Everything about the candidates of one step except the density."""

    t: np.ndarray
    Q: np.ndarray
    n_new: np.ndarray
    points: np.ndarray
    dirs: np.ndarray
    hist_factor: np.ndarray
    G_c: np.ndarray
    base: np.ndarray


def _base_scores(model: StructureModel, hist_a, hist_r, tip, theta: float, params: SynthesisParams,
                 matcher: HistogramMatcher | None, guidance: Guidance | None, subset=None) -> _Base:
    bm = model.bending
    t, Q = bm.quality(hist_a, hist_r, subset)
    n_new = bm.cont_len[t]
    pts = bm.continuation_points(t, tip, theta)
    dirs = _rotate(model.local_dirs[t], theta)
    J = len(t)
    base = Q.copy()
    if matcher is not None and matcher.wG > 0 and matcher.n_nodes > 0:
        hf = matcher.factors(model.cand_counts_a[t], model.cand_counts_r[t],
                             model.cand_sq_a[t], model.cand_sq_r[t])
        base *= hf
    else:
        hf = np.ones(J)
    G_c = np.ones(J)
    if guidance is not None:
        g = guidance.along(tip, dirs, 3.0 * params.m * params.h)
        G_c = np.where(n_new == 0, float(guidance.sample(np.asarray(tip, float)[None])[0]), g)
        base = base / (G_c + params.eps)
    return _Base(t=t, Q=Q, n_new=n_new, points=pts, dirs=dirs, hist_factor=hf, G_c=G_c, base=base)


def score_candidates(model: StructureModel, hist_a, hist_r, tip, theta: float, *,
                     params: branchnb.branching.SynthesisParams, matcher: HistogramMatcher | None = None,
                     density: DensityMap | None = None,
                     guidance: Guidance | None = None, subset=None) -> CandidateScores:
    """Score every candidate continuation of a branch tip (vectorised).

    ``score = Q * exp(wG (dA + dR) n_t / m) / (D_c + eps) / (G_c + eps)``
    with the colonization and guidance factors only when ``density`` /
    ``guidance`` are given; candidates whose density profile shows a
    crossing get 0. Candidates that end the branch (no followers in the
    input) get the best continuing candidate's density and the tip's
    guidance, so colonization neither favours nor prevents stopping.

    Per step the work is a handful of ``(J, L)``, ``(J, m)``, ``(J, B)`` and
    ``(J, n_samples)`` array operations over all ``J`` candidates; the
    candidates' vertices, PCA directions and histogram counts are
    precomputed in the tip's frame by :func:`fit_model`.

    Parameters
    ----------
    model : StructureModel
        The fitted example.
    hist_a, hist_r : (L0,) array_like
        The growing branch's elements so far: turning angles (radians) and
        thicknesses (pixels).
    tip : (2,) array_like
        Position (x, y) of the branch tip (pixels).
    theta : float
        Heading of the tip (radians).
    params : SynthesisParams
        ``m``, ``h``, ``eps`` and the other synthesis parameters.
    matcher : HistogramMatcher, optional
        Running histograms of the synthesis; None = no histogram factor.
    density : DensityMap, optional
        Density of the branches so far; None = no colonization factor.
    guidance : Guidance, optional
        Guidance map; None = no guidance factor.
    subset : int array_like, optional
        Score only these candidates (positions in the list of all windows of
        the history's length, :meth:`~branchnb.branching.bending.BendingModel.windows`); None = all.
        The grower passes a random share on large examples (beyond the paper,
        for speed: see :data:`~branchnb.branching.growth.MAX_CANDIDATES`).

    Returns
    -------
    CandidateScores
        Every candidate's factors and final score.
    """
    if guidance is None:
        return _compiled_scores(model, hist_a, hist_r, tip, theta, params, matcher, density, subset)
    b = _base_scores(model, hist_a, hist_r, tip, theta, params, matcher, guidance, subset)
    J = len(b.t)
    term = b.n_new == 0
    D_c = np.zeros(J)
    crossing = np.zeros(J, bool)
    score = b.base.copy()
    if density is not None:
        live = ~term
        if live.any():
            # Many candidates head the same way: profile each direction (to 0.7 degrees, well
            # under a pixel over the ray) once.
            dc, cross = binned_profile(density, tip, b.dirs[live], 3.0 * params.m * params.h)
            D_c[live] = dc
            crossing[live] = cross
            ok = live.copy()
            ok[live] = ~cross
            D_c[term] = D_c[ok].min() if ok.any() else 1.0
        score = np.where(crossing, 0.0, score / (D_c + params.eps))
    return CandidateScores(t=b.t, Q=b.Q, score=score, points=b.points, n_new=b.n_new,
                           hist_factor=b.hist_factor, D_c=D_c, G_c=b.G_c, crossing=crossing)


def _cand_bins(model: StructureModel, which: str) -> np.ndarray:
    """``model.cand_counts_a`` (``which = "a"``) or ``cand_counts_r`` as :func:`._kernels.count_bins`
    rows, computed once per model."""
    cc = model.cand_counts_a if which == "a" else model.cand_counts_r
    cache = model.__dict__.setdefault("_cand_bins", {})
    got = cache.get(which)
    if got is None or got[0] is not cc:
        got = cache[which] = (cc, _kernels.count_bins(cc))
    return got[1]


def _compiled_scores(model: StructureModel, hist_a, hist_r, tip, theta: float, params: SynthesisParams,
                     matcher: HistogramMatcher | None, density: DensityMap | None, subset) -> CandidateScores:
    """:func:`score_candidates` without guidance as one compiled pass (:func:`._kernels.score_step`)."""
    bm = model.bending
    L = min(len(hist_a), bm.max_history())
    if L < 1:
        raise ValueError("the history is empty: a branch needs at least one element")
    # the windows are read in place (not copied per step): the last L elements of the history
    ha, hr = np.asarray(hist_a[-L:], np.float64), np.asarray(hist_r[-L:], np.float64)
    t = bm.windows(L)[0]
    if subset is not None:
        t = t[subset]
    use_hist = matcher is not None and matcher.wG > 0 and matcher.n_nodes > 0
    hm = matcher if use_hist else None
    e1, e2 = np.zeros(1), np.zeros((1, 1), np.int16)
    length = 3.0 * params.m * params.h
    if density is not None:
        grid, cell = density.grid, density.cell
        n_samples = int(min(max(np.ceil(length / (density.rho / 2.0)), 8), 48))
    else:
        grid, cell, n_samples = np.zeros((1, 1), np.float32), 1.0, 8
    tip = np.asarray(tip, np.float64)
    Q, score, pts, hf, D_c, cross = _kernels.score_step(
        t, bm.angles, bm.radii, ha, hr,
        model.bending.local_points, model.local_dirs, bm.cont_len, float(tip[0]), float(tip[1]), float(theta),
        use_hist, hm.p_a if hm else e1, hm.counts_a if hm else e1, _cand_bins(model, "a") if hm else e2,
        hm.p_r if hm else e1, hm.counts_r if hm else e1, _cand_bins(model, "r") if hm else e2,
        hm.wG * hm.n_nodes / hm.m if hm else 0.0,
        density is not None, grid, cell, length, n_samples, 0.02, _DIRECTION_BINS, float(params.eps))
    return CandidateScores(t=t, Q=Q, score=score, points=pts, n_new=bm.cont_len[t], hist_factor=hf,
                           D_c=D_c, G_c=np.ones(len(t)), crossing=cross)
