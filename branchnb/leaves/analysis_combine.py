"""Combining the terms of a layer's induction (the paper's eqs. 2-4, steps of
:func:`branchnb.leaves.analysis_induce.induce`): the registered layers (:func:`warp_mask`), the
liberal layers and ``lambda``, ``D`` and its threshold ``delta`` (:func:`_combine`), and the induced
mask ``{D < delta}`` with a thin layer's snapped ridges (:func:`_induced`)."""

from __future__ import annotations

import numpy as np

from ..core.image import as_mask
from ..core.morphology import _binary_dilation
from ..core.validate import check_bool, check_real
from .induction import choose_threshold, layer_weight, liberal_layer, spatial_term
from .induction_scatter import TIE_LEVEL, positional_tie, scattered_layer

__all__ = ["colour_alone", "colour_delta", "registration_tolerance", "unmatched_liberal", "warp_mask"]


def warp_mask(registration, mask, *, to_training: bool, level: float = 0.5) -> np.ndarray:
    """A bool mask carried through a registration (bilinear, then ``> level``).

    A thin layer (a one-pixel vein) warped bilinearly may fall below 0.5
    between pixel centres and break up; ``level`` below 0.5 keeps it whole.

    Parameters
    ----------
    registration : Registration or IdentityRegistration
        Exemplar -> training leaf (anything with ``to_training`` and
        ``from_training``).
    mask : (H, W) bool array_like
        The mask, on the exemplar (``to_training=True``) or on the training
        leaf (``to_training=False``).
    to_training : bool
        Direction: exemplar -> training leaf, or training leaf -> exemplar.
    level : float
        Threshold of the warped coverage, in [0, 1] (default 0.5).

    Returns
    -------
    (H, W) bool ndarray
    """
    if not (callable(getattr(registration, "to_training", None))
            and callable(getattr(registration, "from_training", None))):
        raise TypeError("registration must be a leaf registration (with to_training and from_training), "
                        f"got {type(registration).__name__}")
    m = as_mask(mask, name="mask").astype(np.float32)
    to_training = check_bool(to_training, "to_training")
    level = check_real(level, "level", min=0.0, max=1.0)
    out = registration.to_training(m) if to_training else registration.from_training(m)
    out = np.asarray(out)
    if out.ndim == 3:
        out = out[..., 0]
    return out > level



def registration_tolerance(registrations, training_index: int) -> float:
    """The registration error the liberal layers must tolerate (px): the median of the exemplars' own.

    The paper's liberal radius (``||x, c||^2 < 2 eps``: 8.9 px at 2 MP) is
    about the accuracy of its registrations. Scaled to a small leaf it
    shrinks below a pixel or two, while a registration's error does not
    shrink with the image (keypoints are found to a pixel, outlines are
    pixelated): a structural layer registered with 5 px of error would
    then have no liberal overlap at all and get ``lambda = 0``. So the
    radius is at least the registrations' measured error
    (:attr:`~branchnb.leaves.registration.Registration.error_px`, the
    median distance of matched keypoints after the warp), the same for
    every exemplar (the training leaf's liberal layer included, so the
    overlap compares like with like). Registrations without an error
    estimate count as exact. Going beyond the paper.

    Parameters
    ----------
    registrations : list
        Exemplar ``i`` -> training leaf; their ``error_px`` is read.
    training_index : int
        The training leaf, left out.

    Returns
    -------
    float
        Median ``error_px`` in pixels; 0 when none is known.
    """
    errs = []
    for i, r in enumerate(registrations):
        if i == training_index:
            continue
        err = getattr(r, "error_px", None)
        if err is not None and np.isfinite(err):
            errs.append(float(err))
    return float(np.median(errs)) if errs else 0.0


#: Below this training overlap the colour term does not tell a thin layer
#: from the blade (faint 1-2 px maple veins: 0.3-0.45; procedural and drawn
#: veins: 0.75-0.9), and a snapped layer is induced from its ridges alone.
COLOUR_RELIABLE = 0.5


def _induced(combined, delta, training_overlap, snapped, e, blade, taken, *, centred=None, over: bool = False):
    """The induced layer on exemplar ``e``: ``{D < delta}``, with a thin layer's snapped ridges.

    Where the colour term reproduces the user's layer on the training leaf
    (training overlap at least :data:`COLOUR_RELIABLE`), the paper's layer,
    its ``||x, c||`` measured to the carried-over layer and the snapped main
    structure (adding the snapped paths themselves lowered the IoU with the
    truth on procedural leaves, 0.77 -> 0.70: their widths are the training
    leaf's); where it does not, the snapped structure alone (``{D < delta}``
    is then mostly blade of the layer's colour: measured on the sample
    maples with their hand-traced veins, mean IoU 0.30 with it, 0.34 without).
    With the colour term, the ``centred`` snapped pixels next to ``{D < delta}``
    (one pixel) join it: the snapped paths, grown to their vein's side and
    width (:func:`~branchnb.leaves.snapping_width._grow_to_width`), fill the pixels the
    colour term left beside its thin veins (procedural elliptic 192 px,
    training leaf 2 -> exemplar 3, seed 2: IoU 0.64 -> 0.70); all of them
    (a union) added the off-vein paths too (lobed 192 px 0.81 -> 0.80).
    ``over`` (:func:`_over_induced`): the colour term takes most of this exemplar's blade, the
    snapped structure alone is induced there too (beyond the paper).
    """
    m = (combined < delta) & blade & ~taken
    if snapped is None or snapped[e] is None:
        return m
    if training_overlap < COLOUR_RELIABLE or over:
        return snapped[e] & ~taken
    # The snapped paths (grown to the side their vein lies) where they run
    # beside {D < delta}: the colour term, averaged over a neighbourhood,
    # puts a thin vein's pixels one pixel off along whole side veins.
    if centred is None or centred[e] is None:
        return m
    return m | (centred[e] & blade & ~taken & _binary_dilation(m))


#: A thin layer's ``{D < delta}`` covering more than this many times the area the layer should take
#: on an exemplar (the training layer's share of its blade) is no layer: the colour term does not
#: tell it from the blade there (:func:`_over_induced`).
OVER_INDUCED = 4.0


def _over_induced(combined, delta, blade, user, blade_t) -> bool:
    """Whether ``{D < delta}`` takes over :data:`OVER_INDUCED` times the layer's expected area on this blade.

    A drawn leaf's one-pixel veins of another hue (yellow on an orange
    fill, 640 px) are antialiased into the fill: the colour histograms of
    the vein pixels and of the fill overlap and ``{D < delta}`` covered
    77-93 % of every exemplar's blade; what was left after the contrast trim
    was a few dots (10-566 px of ~2000). The snapped paths found the veins
    there; they alone are induced then, as when the colour term fails on
    the training leaf itself (:data:`COLOUR_RELIABLE`). Beyond the paper.
    """
    expected = float(np.count_nonzero(user)) / max(float(np.count_nonzero(blade_t)), 1.0) * float(
        np.count_nonzero(blade))
    return float(np.count_nonzero((combined < delta) & blade)) > OVER_INDUCED * max(expected, 1.0)


#: A thin layer's ``{D < delta}`` on an exemplar covering more than this many times the layer's
#: expected area there, with ``lambda > 0``, is read by its colour term alone (:func:`colour_alone`).
THIN_OVER = 2.0


def colour_delta(colour_t, user, blade_t, lam: float, training_overlap: float, thin: bool):
    """The training leaf's threshold of ``S`` alone (eq. 4 at ``lambda = 0``) for :func:`colour_alone`.

    None where :func:`colour_alone` never applies: a layer that is not thin, ``lambda`` 0 (``D`` is
    ``S`` already) or a training overlap under :data:`COLOUR_RELIABLE` (the snapped paths are induced).

    Parameters
    ----------
    colour_t : (H, W) ndarray
        ``S`` on the training leaf.
    user : (H, W) bool ndarray
        The training layer.
    blade_t : (H, W) bool ndarray
        The training blade.
    lam : float
        The layer's ``lambda``.
    training_overlap : float
        The layer's overlap on the training leaf.
    thin : bool
        Whether the layer is a thin (line) layer.

    Returns
    -------
    float or None
    """
    if not thin or lam <= 0 or training_overlap < COLOUR_RELIABLE:
        return None
    return choose_threshold(np.asarray(colour_t), user, blade_t)[0]


def colour_alone(combined_e, delta, colour_e, delta_s, blade, user, blade_t):
    """``(D, delta)`` of a thin layer on one exemplar: the paper's, or its colour term alone where that
    takes the blade round the layer.

    Beyond the paper (issue 22, leaves80). ``delta`` is chosen on the
    training leaf, where ``lambda F`` lifts the blade beside a vein well
    above the veins: with pale veins on a flat blade (``S`` 0.002 on the
    veins, 0.73 on the blade) ``lambda`` 0.24 put ``delta`` at 0.95. Colour
    matching scales each channel by the ratio of the blades' spreads, a
    guess for a nearly flat blade's tiny ``b*`` spread (0.1-0.8): it put
    two exemplars' plain blade at ``S`` 0.49-0.55, and their
    ``{D < delta}`` took a 2-3 px sleeve of blade round every registered
    vein (4-5.4 times the layer's area; the other exemplars 1.0). With
    ``lambda`` 0 (before :func:`unmatched_liberal` gave these leaves a
    positional tie) ``delta`` fell between the two and the veins were
    induced with IoU 0.98-0.99; with ``lambda`` it was 0.88-0.89. Such an
    exemplar (``{D < delta}`` over :data:`THIN_OVER` times the training
    layer's share of its blade) is read by ``S_e`` and the training leaf's
    threshold of ``S`` alone (``delta_s``, :func:`colour_delta`);
    ``lambda`` is kept for the others.

    Parameters
    ----------
    combined_e : (H, W) ndarray
        ``D`` on the exemplar.
    delta : float
        The layer's threshold of ``D``.
    colour_e : (H, W) ndarray or None
        ``S_e`` on the exemplar.
    delta_s : float or None
        :func:`colour_delta` (None: ``(combined_e, delta)`` as they are).
    blade, user, blade_t : (H, W) bool ndarray
        The exemplar's blade, the training layer and the training blade.

    Returns
    -------
    combined : (H, W) ndarray
    delta : float
    """
    if delta_s is None or colour_e is None:
        return combined_e, delta
    expected = float(np.count_nonzero(user)) / max(float(np.count_nonzero(blade_t)), 1.0) * float(
        np.count_nonzero(blade))
    if float(np.count_nonzero((np.asarray(combined_e) < delta) & blade)) <= THIN_OVER * max(expected, 1.0):
        return combined_e, delta
    return np.asarray(colour_e), float(delta_s)


#: Share of the training leaf's colour matches (``S_t`` under the liberal threshold) that must be the
#: user's layer for a scattered layer's positional tie to be dropped (:func:`_combine`).
SINGLES_OUT = 0.5


def _combine(colour, dist, lengths, tolerance, params, blades, registrations, t, user, liberal=None):
    """Eqs. 2-4 from the colour terms and distance maps: ``lambda``, ``D`` per exemplar, ``delta``.

    ``liberal`` (optional, per exemplar a map or None): the colour term the
    liberal layer of that exemplar is read on instead of ``colour[e]``
    (:func:`unmatched_liberal`, an exemplar's own colours where the matched
    ones find none of the layer); ``D`` always takes ``colour``.

    Beyond the paper (issue 22): ``lambda`` is 0 for marks at random places
    (:mod:`~branchnb.leaves.induction_scatter`): the user's layer is
    scattered small marks (:func:`~branchnb.leaves.induction_scatter.scattered_layer`;
    a vein network never is, so veins keep the paper's ``lambda``) and the
    exemplars' pixels of its colour sit no nearer the registered layer than
    chance (:func:`~branchnb.leaves.induction_scatter.positional_tie` under
    :data:`~branchnb.leaves.induction_scatter.TIE_LEVEL`): a chance overlap
    of a few marks is no positional tie. Only while the layer's colour
    singles it out on the training leaf (at least :data:`SINGLES_OUT` of
    the pixels with ``S_t`` under the liberal threshold are the user's
    layer); else its place is all it has.
    """
    liberal_t, spat = [], []
    for e in range(len(colour)):
        eps_px, _, lib_r = lengths[e]
        s_lib = colour[e] if liberal is None or liberal[e] is None else liberal[e]
        lib = liberal_layer(s_lib, dist[e], params.liberal_threshold, max(lib_r, tolerance), blades[e])
        lib_t = lib if e == t else _liberal_to_training(registrations[e], lib)
        liberal_t.append(lib_t & blades[t])
        spat.append(spatial_term(dist[e], colour[e], eps_px))
    lam, overlap = layer_weight(liberal_t, params.kappa)
    match_t = (np.asarray(colour[t]) < params.liberal_threshold) & blades[t]
    if lam > 0 and (match_t & user).sum() >= SINGLES_OUT * match_t.sum() and scattered_layer(user, blades[t]):
        # Only where the layer's colour singles it out on the training leaf: marks of nearly the blade's
        # colour (the sample maple_leaf_01's 36-px spots: lambda 0.8, tie 0.003) have only their place to go
        # by. The tie is measured within the liberal radius widened to the registration error, as the
        # liberal layers are.
        radii = [max(ln[2], tolerance) for ln in lengths]
        tie = positional_tie([np.asarray(colour[e]) < params.liberal_threshold for e in range(len(colour))],
                             [np.asarray(dist[e]) for e in range(len(dist))], blades, t, radii)
        if tie < TIE_LEVEL:
            lam = 0.0
    combined = [(np.float32(lam) * f + s).astype(np.float32) for f, s in zip(spat, colour)]
    delta, tr_iou = choose_threshold(combined[t], user, blades[t])
    return lam, overlap, combined, delta, tr_iou


#: An exemplar whose liberal layer (matched colours) holds under this share of the training leaf's, per
#: blade area, found none of the layer in its matched colours (:func:`unmatched_liberal`).
LIBERAL_EMPTY = 0.1


def unmatched_liberal(colour, dist, lengths, tolerance, params, blades, t, own_colour):
    """The colour terms the liberal layers are read on: an exemplar's own colours where the matched find none.

    Beyond the paper (issue 22). Colour matching moves each blade's CIELAB
    onto the training blade's mean and spread, assuming a layer's colour
    moves with its blade's. A blade whose statistics move for another
    reason breaks that for the liberal layers, which use the strict
    ``liberal_threshold``: a variegated leaf's cream band (its share of the
    blade varies, mean L* 64.7 on the training leaf, 70.4 on another) moved
    the pale veins 5.6 L* units off, and a flat green blade's tiny b*
    spread (0.1-0.8) moved them 4.6 b* units. No pixel of two of four
    exemplars came under the threshold (S_e at least 0.11-0.14 everywhere),
    the intersection of the liberal layers was empty and ``lambda`` 0
    though the veins sat at the same place on every leaf and were induced
    with IoU 0.94-0.99. Such an exemplar (its liberal layer under
    :data:`LIBERAL_EMPTY` of the training leaf's, per blade area) has its
    liberal layer read in its own, unmatched colours (the lower of the two
    terms); ``D`` keeps the matched term. Exemplars whose matched colours
    find the layer keep the paper's liberal layer.

    Parameters
    ----------
    colour : list of (H, W) ndarray
        ``S_e`` per exemplar (matched colours).
    dist : list of (H, W) ndarray
        ``||x, c||`` per exemplar.
    lengths : list of tuple
        :func:`~branchnb.leaves.induction.scaled_lengths` per exemplar.
    tolerance : float
        :func:`registration_tolerance`.
    params : InductionParams
        ``liberal_threshold`` is read.
    blades : list of (H, W) bool ndarray
        The exemplars' blades.
    t : int
        The training leaf.
    own_colour : callable(e) -> (H, W) ndarray
        ``S_e`` of exemplar ``e`` in its own colours (called only for the exemplars that need it).

    Returns
    -------
    list or None
        Per exemplar the map for :func:`_combine`'s ``liberal`` (None: its
        ``colour``), or None when every exemplar keeps its matched term.
    """
    def liberal(e, s):
        return liberal_layer(s, dist[e], params.liberal_threshold, max(lengths[e][2], tolerance), blades[e])

    per_area_t = float(np.count_nonzero(liberal(t, colour[t]))) / max(float(np.count_nonzero(blades[t])), 1.0)
    if per_area_t <= 0:
        return None
    out = [None] * len(colour)
    for e in range(len(colour)):
        if e == t:
            continue
        expected = per_area_t * float(np.count_nonzero(blades[e]))
        if np.count_nonzero(liberal(e, colour[e])) < LIBERAL_EMPTY * expected:
            out[e] = np.minimum(np.asarray(colour[e]), np.asarray(own_colour(e))).astype(np.float32)
    return out if any(x is not None for x in out) else None


#: Liberal layers carried into the training frame, by registration and mask
#: digest: a slider move (kappa always, eps while the registration error
#: bounds the liberal radius) leaves most of them as they were, and their
#: warp was half of a 1 MP preview.
_LIBERAL_CACHE: dict = {}


def _liberal_to_training(registration, lib):
    """``warp_mask(registration, lib, to_training=True)``, reusing the last results for the same mask."""
    import hashlib
    import weakref
    lib = np.ascontiguousarray(lib, bool)
    key = (id(registration), lib.shape, hashlib.blake2b(np.packbits(lib).tobytes(), digest_size=16).digest())
    hit = _LIBERAL_CACHE.get(key)
    if hit is not None and hit[0]() is registration:
        return hit[1].copy()
    out = warp_mask(registration, lib, to_training=True)
    try:
        ref = weakref.ref(registration)  # the cache does not keep a registration alive
    except TypeError:
        return out
    if len(_LIBERAL_CACHE) >= 32:
        _LIBERAL_CACHE.pop(next(iter(_LIBERAL_CACHE)))
    _LIBERAL_CACHE[key] = (ref, out.copy())
    return out


