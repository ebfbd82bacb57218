"""Variations of one tree and "more like this" (paper, step 3), and morph sequences.

Weights near a centre (:func:`nearby_weights`, :func:`variation_weights`),
contour distances, :func:`similar_variations`, :func:`tree_variations` and
:func:`morph_sequence`. Split out of :mod:`branchnb.trees.variations`, which
re-exports every name.

Examples
--------
>>> variation_weights(3, 0, keep=0.5, rng=0)[0] >= 0.5
np.True_
"""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np

from ..core.params import check_params
from ..core.random import as_rng
from ..core.validate import Choice, Int, Real, Seq, check_int, checked
from .morph import check_weights
from .variations import (
    MAX_VARIATIONS,
    Variation,
    VariationParams,
    _as_exemplars,
    _check_overrides,
    _random_weights,
    _select,
    make_variation,
)

__all__ = [
    "nearby_weights",
    "variation_weights",
    "contour_distance",
    "mean_pairwise_distance",
    "small_library_keep",
    "similar_variations",
    "tree_variations",
    "morph_sequence",
    "SPREAD_CANDIDATES",
]


def nearby_weights(centre, keep: float = 0.6, *, concentration=1.0, n_mix: int = 0,
                   rng=None) -> np.ndarray:
    """Random convex weights near ``centre``: ``keep centre + (1 - keep) d``.

    ``d`` is a Dirichlet draw over ``n_mix`` exemplars picked at random (0:
    all). Every exemplar keeps at least ``keep`` times its weight in
    ``centre``, so the result stays recognisably like the centre mix.

    Parameters
    ----------
    centre : (k,) array_like
        Convex weights of the centre mix (>= 0, summing to 1).
    keep : float
        Share of ``centre`` kept, in [0, 1] (1: the centre itself).
    concentration : float or (m,) array_like
        Dirichlet parameter ``alpha`` of ``d`` (1: uniform on the simplex).
    n_mix : int
        Exemplars ``d`` spreads over, picked at random (0: all ``k``).
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the picks and the draw.

    Returns
    -------
    (k,) float64 ndarray
        Convex weights.

    Raises
    ------
    ValueError
        If ``centre`` is not convex or ``keep`` is outside [0, 1].

    Examples
    --------
    >>> w = nearby_weights([0.5, 0.5, 0.0], 0.8, rng=0)
    >>> bool(w[0] >= 0.4 and w[1] >= 0.4 and abs(w.sum() - 1) < 1e-12)
    True
    """
    c = check_weights(centre, name="centre")
    if not 0.0 <= float(keep) <= 1.0:
        raise ValueError(f"keep must lie in [0, 1], got {keep}")
    w = keep * c + (1.0 - keep) * _random_weights(len(c), n_mix, concentration, rng)
    return w / w.sum()


def variation_weights(k: int, index: int, keep: float = 0.5, *, concentration=1.0,
                      n_mix: int = 0, rng=None) -> np.ndarray:
    """Random convex weights in which exemplar ``index`` keeps at least ``keep``.

    ``w = keep e_index + (1 - keep) d`` with ``d`` a Dirichlet draw over
    ``n_mix`` exemplars picked at random (0: all ``k``): ``T = index`` keeps
    ``keep`` plus its share of the rest, so it stays recognisable while the
    others vary (:func:`nearby_weights` around a corner of the simplex).

    Parameters
    ----------
    k : int
        Number of exemplars (>= 1).
    index : int
        ``T``, the exemplar kept (negative counts from the end).
    keep : float
        ``T``'s guaranteed share, in [0, 1].
    concentration : float or (m,) array_like
        Dirichlet parameter of ``d``.
    n_mix : int
        Exemplars ``d`` spreads over, picked at random (0: all ``k``, ``T``
        included).
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the picks and the draw.

    Returns
    -------
    (k,) float64 ndarray
        Convex weights with ``w[index] >= keep``.

    Raises
    ------
    ValueError
        If ``k`` is not a positive int or ``index`` is out of range.

    Examples
    --------
    >>> w = variation_weights(4, 2, 0.6, rng=0)
    >>> bool(w[2] >= 0.6 and abs(w.sum() - 1) < 1e-12)
    True
    """
    if not isinstance(k, (int, np.integer)) or k < 1:
        raise ValueError(f"k must be a positive int, got {k!r}")
    if not -k <= index < k:
        raise ValueError(f"index {index} out of range for {k} exemplars")
    return nearby_weights(np.eye(k)[index], keep, concentration=concentration, n_mix=n_mix,
                          rng=rng)


def contour_distance(a, b) -> float:
    """Mean distance (pixels) between corresponding points of two resampled contours ``C_r``.

    Parameters
    ----------
    a, b : (N, 2) array_like
        Two contours with the same pin layout (point ``i`` of one
        corresponds to point ``i`` of the other), in working pixels.

    Returns
    -------
    float
        Mean Euclidean distance of corresponding points, in pixels.

    Raises
    ------
    ValueError
        If the shapes differ or are not (N, 2).

    Examples
    --------
    >>> import numpy as np
    >>> round(contour_distance(np.zeros((4, 2)), np.full((4, 2), 3.0)), 3)
    4.243
    """
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape or a.ndim != 2 or a.shape[1] != 2:
        raise ValueError(f"contours must be (N, 2) arrays of the same shape, got {a.shape} and {b.shape}")
    return float(np.linalg.norm(a - b, axis=1).mean())


def mean_pairwise_distance(contours) -> float:
    """Mean :func:`contour_distance` over all pairs of a list of ``C_r`` (0 for fewer than two).

    Parameters
    ----------
    contours : sequence of (N, 2) array_like
        Resampled contours with the same pin layout.

    Returns
    -------
    float
        Mean over the ``n (n - 1) / 2`` pairs, in pixels; the measure of
        how varied a set of variations (or a library) is.

    Examples
    --------
    >>> import numpy as np
    >>> round(mean_pairwise_distance([np.zeros((3, 2)), np.full((3, 2), 3.0), np.zeros((3, 2))]), 3)
    2.828
    """
    c = [np.asarray(x, float) for x in contours]
    d = [contour_distance(c[i], c[j]) for i in range(len(c)) for j in range(i + 1, len(c))]
    return float(np.mean(d)) if d else 0.0


def _spread(candidates: np.ndarray, shapes: np.ndarray, n: int, centre: np.ndarray,
            first: int | None = None) -> np.ndarray:
    """Indices of ``n`` candidate weight vectors whose contours lie far apart (farthest-point
    sampling on the combined contours ``candidates @ shapes``, starting with candidate
    ``first`` or, if None, the one farthest from the centre's contour)."""
    vec = candidates @ shapes                      # (c, 2N)
    n_pts = shapes.shape[1] // 2
    if first is None:
        d = np.linalg.norm((vec - centre @ shapes).reshape(len(vec), n_pts, 2), axis=2).mean(axis=1)
        first = int(np.argmax(d))
    chosen = [first]
    d = np.linalg.norm((vec - vec[first]).reshape(len(vec), n_pts, 2), axis=2).mean(axis=1)
    while len(chosen) < min(n, len(candidates)):
        nxt = int(np.argmax(d))
        chosen.append(nxt)
        d = np.minimum(d, np.linalg.norm((vec - vec[nxt]).reshape(len(vec), n_pts, 2),
                                         axis=2).mean(axis=1))
    return np.asarray(chosen)


#: "More like this" draws this many candidate mixes per result and keeps the most different.
SPREAD_CANDIDATES = 16


def small_library_keep(k: int, keep: float = 0.3) -> float:
    """Default ``keep`` of :func:`similar_variations` for ``k`` exemplars: ``keep min(1, (k - 1) / 4)``.

    With few exemplars the results can only spread over ``1 - keep`` of
    the exemplars' simplex, so the centre's share shrinks: 0.15 for three
    trees, 0.225 for four, ``keep`` from five on.

    Parameters
    ----------
    k : int
        Number of exemplars in the library.
    keep : float, optional
        The centre's share for five exemplars or more (default 0.3).

    Returns
    -------
    float

    Examples
    --------
    >>> small_library_keep(3), small_library_keep(8)
    (0.15, 0.3)
    """
    return float(keep) * min(1.0, (int(k) - 1) / 4.0)


def _extreme_candidates(centre: np.ndarray, keep: float, n_mix: int) -> np.ndarray:
    """``keep c + (1 - keep) v`` for ``v`` the corners of the simplex and (up to 16
    exemplars) its edge midpoints: the farthest a nearby mix can go."""
    k = len(centre)
    eye = np.eye(k)
    verts = list(eye)
    if k <= 16 and (n_mix <= 0 or n_mix >= 2):
        verts += [(eye[i] + eye[j]) / 2 for i, j in itertools.combinations(range(k), 2)]
    return np.stack([keep * centre + (1.0 - keep) * v for v in verts])


@checked(n=Int(1, MAX_VARIATIONS), keep=Real(0, 1))
def similar_variations(library, variation: Variation, n: int = 6,
                       params: VariationParams | None = None, *, keep: float | None = None,
                       rng=None, **overrides) -> list[Variation]:
    """"More like this": random variations around an existing variation's weights.

    Parameters
    ----------
    library : TreeLibrary or sequence of Exemplar
        Must contain the exemplars of ``variation``.
    variation : Variation
        The centre; its exemplars, shape and colour weights and reference
        are reused.
    n : int
        Number of variations.
    params : VariationParams, optional
        ``n_mix`` and the concentrations of the random part; None uses the
        defaults.
    keep : float, optional
        Share of the centre's weights every new variation keeps
        (:func:`nearby_weights`); the rest is a random Dirichlet mix of
        ``params.n_mix`` exemplars of the same set. None (default): 0.3,
        less for fewer than five exemplars (:func:`small_library_keep`).
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the candidate weights and the colour transfer.
    **overrides
        Fields of ``params`` (e.g. ``n_mix=2``).

    Returns
    -------
    list of Variation
        ``n`` variations, far apart from each other (see Notes).

    Raises
    ------
    ValueError
        If ``library`` lacks one of the variation's exemplars, or the
        variation's reference was an array.
    TypeError
        If ``variation`` is not a Variation or an override is unknown.

    Notes
    -----
    Beyond the paper: independent draws around one centre often land
    close together, so six results look alike. ``SPREAD_CANDIDATES``
    times ``n`` candidate shape weights are drawn and ``n`` of them kept by
    farthest-point sampling on their combined contours (cheap: a contour is
    the weights times the exemplars' ``C_r``), so the results differ as
    much as ``keep`` allows. The candidates also include the farthest
    mixes ``keep`` allows (``keep c + (1 - keep) v`` for every corner and
    edge midpoint ``v`` of the simplex), which random Dirichlet draws
    rarely reach. Still, six results can spread over only ``1 - keep`` of
    the exemplars' simplex: with three trees and ``keep`` = 0.3 at most
    about 0.47 of the exemplars' mean distance (without duplicates), so
    small libraries get a smaller ``keep`` by default
    (:func:`small_library_keep`). Mean pairwise contour distance of six
    results over the mean distance between the library's exemplars, six
    centres each (``python -m branchnb.trees._measure variety 128``):
    four libraries of three trees (three drawn, three RPG sprites) 0.54-0.59,
    worst centre 0.54 (formerly 0.39-0.41, worst 0.36); 8 drawn trees 0.72;
    14 RPG sprites 0.86. The app passes its ``keep`` slider (0.3) as it is,
    so it gets the corner candidates but not the smaller ``keep``.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> v = make_variation(lib, [0.5, 0.5], rng=0)
    >>> len(similar_variations(lib, v, 2, rng=0))
    2
    """
    p = params if params is not None else VariationParams()
    if overrides:
        _check_overrides(overrides)
        p = replace(p, **overrides)
    check_params(p)
    if not isinstance(variation, Variation):
        raise TypeError(f"variation must be a Variation, got {type(variation).__name__}")
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n must be a positive int, got {n!r}")
    chosen = _select(_as_exemplars(library), list(variation.names))
    rng = as_rng(rng)
    ref = variation.reference
    if ref == "image":
        raise ValueError("the variation's reference was an array; give similar variations "
                         "a named reference")
    if keep is None:
        keep = small_library_keep(len(chosen))
    centre = np.asarray(variation.weights, float)
    cands = np.stack([nearby_weights(variation.weights, keep, concentration=p.concentration,
                                     n_mix=p.n_mix, rng=rng)
                      for _ in range(SPREAD_CANDIDATES * int(n))])
    cands = np.vstack([cands, _extreme_candidates(centre / centre.sum(), keep, p.n_mix)])
    shapes = np.stack([e.resampled.ravel() for e in chosen])
    out = []
    for i in _spread(cands, shapes, int(n), np.asarray(variation.weights, float)):
        cw = nearby_weights(variation.colour_weights, keep, concentration=p.colour_concentration,
                            n_mix=p.n_mix, rng=rng)
        out.append(make_variation(chosen, cands[i], p, colour_weights=cw, reference=ref, rng=rng))
    return out


@checked(n=Int(1, MAX_VARIATIONS), use=Seq())
def tree_variations(library, target, n: int = 6, params: VariationParams | None = None, *,
                    use=None, rng=None, reference=None, **overrides) -> list[Variation]:
    """Variations of one tree ``T`` that keep it recognisable.

    Parameters
    ----------
    library : TreeLibrary or sequence of Exemplar
        Must contain ``target`` and at least one other exemplar.
    target : str or int
        ``T``: the name or index of the user's tree in the library (add a
        new tree with :meth:`TreeLibrary.add` first).
    n : int
        Number of variations.
    params : VariationParams, optional
        ``keep`` (0.5) is ``T``'s shape weight and its minimum colour
        weight; the rest of the shape weight goes to ``n_mix`` random
        exemplars other than ``T`` with Dirichlet weights.
    use : sequence, optional
        The exemplars to mix with (default: all; ``T`` is always used).
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the partners, weights and colour transfer.
    reference : optional
        Histogram-transfer reference (see :func:`make_variation`).
    **overrides
        Fields of ``params`` (e.g. ``keep=0.7``).

    Returns
    -------
    list of Variation
        ``n`` variations in which ``T`` has shape weight ``keep``.

    Raises
    ------
    ValueError
        ``target`` not in the library, or no other exemplar to mix with.

    Notes
    -----
    Beyond the paper, against results that are near copies of ``T``: drawn
    independently, with the partners picked among all exemplars, ``T``
    often won part of the rest as well (weight up to 0.9) and results often
    landed close to ``T`` and to each other. Now ``T`` keeps exactly
    ``keep``, the partners are other exemplars, and ``SPREAD_CANDIDATES``
    times ``n`` candidate weights are drawn and, starting from the first
    (random) one, the ``n`` whose combined contours lie farthest apart are
    kept (farthest-point sampling, as :func:`similar_variations`).
    Mean contour distance of 5 results to ``T`` over the mean distance
    between the exemplars (every exemplar as ``T``, seeds 2 and 5, 128 px;
    ``python -m branchnb.trees._measure targets 128``), before -> now:
    RPG sprites min 0.21 mean 0.39 -> min 0.45 mean 0.52, clip art
    0.21/0.39 -> 0.32/0.45, two sets of 8 drawn trees 0.17-0.18/0.37-0.41
    -> 0.33-0.36/0.46-0.47 (max 0.66); between the results themselves
    mean 0.26-0.32 -> 0.40-0.52.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_01", "tree_rpg_02", "tree_rpg_03"], size=128)
    >>> vs = tree_variations(lib, "tree_rpg_02", 2, rng=0, keep=0.7)
    >>> [bool(v.weights[1] >= 0.7) for v in vs]
    [True, True]
    """
    p = params if params is not None else VariationParams()
    if overrides:
        _check_overrides(overrides)
        p = replace(p, **overrides)
    check_params(p)
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n must be a positive int, got {n!r}")
    exemplars = _as_exemplars(library)
    names = [e.name for e in exemplars]
    if isinstance(target, str):
        if target not in names:
            raise ValueError(f"target {target!r} is not in the library ({names}); add it first")
        t = names.index(target)
    else:
        t = check_int(target, "target")
        if not -len(names) <= t < len(names):
            raise ValueError(f"target index {t} out of range for {len(names)} exemplars")
        t %= len(names)
    chosen = _select(exemplars, use)
    if exemplars[t] not in chosen:
        chosen = [exemplars[t]] + chosen
    if len(chosen) < 2:
        raise ValueError("variations of a tree need at least one other exemplar to mix with")
    ti = chosen.index(exemplars[t])
    rng = as_rng(rng)
    k = len(chosen)
    others = np.delete(np.arange(k), ti)
    # Beyond the paper (see Notes): T keeps exactly ``keep``, the rest goes to
    # partners other than T, and the n most different of many candidates are kept.
    cands = np.zeros((SPREAD_CANDIDATES * int(n), k))
    cands[:, ti] = p.keep
    for c in cands:
        c[others] += (1.0 - p.keep) * _random_weights(len(others), p.n_mix, p.concentration, rng)
    shapes = np.stack([e.resampled.ravel() for e in chosen])
    centre = np.eye(k)[ti]
    out = []
    # Start from a random draw (not the extreme one), so a single variation (batch jobs
    # draw one per item) is an unbiased draw and n > 1 spread out from it.
    for i in _spread(cands, shapes, int(n), centre, first=0):
        w = cands[i]                    # T keeps exactly ``keep``; the rest sums to 1 - keep
        cw = np.zeros_like(w)
        mixed = np.flatnonzero(w > 0)
        cw[mixed] = variation_weights(len(mixed), int(np.flatnonzero(mixed == ti)[0]), p.keep,
                                      concentration=p.colour_concentration, rng=rng)
        out.append(make_variation(chosen, w, p, colour_weights=cw, reference=reference, rng=rng))
    return out


@checked(steps=Int(2, MAX_VARIATIONS), colour=Choice("shape", "random"))
def morph_sequence(library, a, b, steps: int = 5, params: VariationParams | None = None, *,
                   colour: str = "shape", rng=None, **overrides) -> list[Variation]:
    """Morph from tree ``a`` to tree ``b``: weights ``(1 - t, t)`` for ``t`` in ``[0, 1]``.

    Parameters
    ----------
    library : TreeLibrary or sequence of Exemplar
        Holds ``a`` and ``b``.
    a, b : str or int
        The two trees.
    steps : int
        Number of frames (>= 2), ``t = 0 ... 1``.
    params : VariationParams, optional
        ``M``, colour mode and outline options of every frame; None uses
        the defaults.
    colour : {"shape", "random"}
        Colour weights follow the shape weights (a morph) or are random.
    rng : {numpy.random.Generator, int}, optional
        Used only with ``colour="random"``: the default morph is fully
        determined by ``a``, ``b`` and ``steps`` (every frame uses the same
        fixed seam noise, so chosen colour regions do not flicker).
    **overrides
        Fields of ``params``.

    Returns
    -------
    list of Variation
        ``steps`` frames; the first is ``a`` itself, the last ``b``.

    Raises
    ------
    ValueError
        ``steps < 2``, an unknown ``colour``, or ``a``/``b`` not in the
        library.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> frames = morph_sequence(lib, "tree_rpg_05", "tree_rpg_06", 3)
    >>> [f.weights.tolist() for f in frames]
    [[1.0, 0.0], [0.5, 0.5], [0.0, 1.0]]
    """
    if not isinstance(steps, (int, np.integer)) or steps < 2:
        raise ValueError(f"steps must be an int >= 2, got {steps!r}")
    if colour not in ("shape", "random"):
        raise ValueError(f"colour must be 'shape' or 'random', got {colour!r}")
    pair = _select(_as_exemplars(library), [a, b], labels=("a", "b"))
    if colour == "random":
        rng = as_rng(rng)
        return [make_variation(pair, [1.0 - t, t], params, rng=rng, **overrides)
                for t in np.linspace(0.0, 1.0, int(steps))]
    # Every frame draws the same seam noise (the "choose" colour mode), so the
    # regions a frame takes from each tree stay put from frame to frame.
    return [make_variation(pair, [1.0 - t, t], params, rng=0, colour_weights="shape", **overrides)
            for t in np.linspace(0.0, 1.0, int(steps))]
