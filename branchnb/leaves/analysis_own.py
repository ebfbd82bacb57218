"""Reading an exemplar's own colours (steps of :func:`branchnb.leaves.analysis_induce.induce`,
beyond the paper): the blade statistics matched onto the training leaf's (:func:`_matched_lab`),
whether an exemplar's layer has another colour (:func:`_other_colour`, :func:`_has_layer_colour`) and
then its own colour model and ``delta`` (:func:`_own_cdf`, :func:`_own_delta`), thin layers the
training colour model under-induces (:func:`_under_induced`), and marks of one fixed colour on blades
of differing shade (:func:`_own_colours`)."""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from .analysis_combine import _combine
from .analysis_outline import _contrast
from .induction import _lab, _quantise_lab, choose_threshold, colour_similarity, layer_cdfs

__all__: list[str] = []


def _matched_lab(image, stats, e, t, params, lab=None):
    """CIELAB of exemplar ``e``'s ``image`` (``lab`` when converted already), moved onto the training leaf's
    blade statistics (colour matching on)."""
    lab = _lab(image) if lab is None else lab
    if params.match_colours and e != t:
        lab = (lab - stats[e][0]) / stats[e][1] * stats[t][1] + stats[t][0]
    return lab


#: An exemplar's layer has another colour than the training leaf's when its
#: contrast with the blade around it turns from the training layer's by more
#: than this (cosine below; 3 procedural kinds, pale / red / dark veins at
#: 192 px: same colours 0.93-1.00, other colours -0.6-0.9).
SAME_CONTRAST = 0.95


def _unmatched(stats, e, t, params):
    """Per-channel factor taking a colour difference on exemplar ``e`` back from the training leaf's
    statistics to its own (None without colour matching)."""
    if not params.match_colours or e == t:
        return None
    return np.asarray(stats[e][1], np.float64) / np.maximum(np.asarray(stats[t][1], np.float64), 1e-6)


def _other_colour(labs, t, user, blade_t, e, pixels, blade_e=None, *, scale=None):
    """Whether exemplar ``e``'s layer ``pixels`` stand out from their blade in another colour than ``user``.

    ``scale`` (:func:`_unmatched`) compares the two contrasts in each
    leaf's own CIELAB: matched onto the training leaf's statistics, a red
    training leaf's wide spread of ``a*`` shrank a dark-green vein's
    contrast onto the red one's (cosine 0.87-0.98 matched, 0.47-0.49 in
    their own colours; same-coloured procedural leaves 0.99-1.00 either
    way), and the dark veins were induced with the red veins' colour model
    (procedural lobed dark -> red: IoU 0.49 -> 0.71).
    """
    if pixels is None or pixels.sum() < 10:
        return False
    c_t = _contrast(labs[t], user, blade_t)
    c_e = _contrast(labs[e], pixels, np.ones(pixels.shape, bool) if blade_e is None else blade_e)
    if c_t is None or c_e is None:
        return False
    if scale is not None:
        c_e = c_e * np.asarray(scale, c_e.dtype)
    cos = float(c_t @ c_e) / max(float(np.linalg.norm(c_t) * np.linalg.norm(c_e)), 1e-9)
    return cos < SAME_CONTRAST


#: An exemplar whose blade holds at least this share of the training layer's
#: area share in the training layer's own colour keeps the training colour model.
LAYER_COLOUR_PRESENT = 0.5


def _has_layer_colour(labs, t, user, blade_t, e, pixels, blade_e) -> bool:
    """Whether exemplar ``e``'s own layer ``pixels`` turn lightness while its blade carries the layer's colour.

    The exemplar's own contrast direction (:func:`_other_colour`,
    :func:`branchnb.leaves.own_contrast.exemplar_direction`) is for veins of
    another colour. Where it stands out the other way in lightness than
    the training layer (lighter against darker) although the training
    layer's colour is there over a comparable share of the blade (within a
    third of the layer's contrast with its blade), the training colour is
    the layer and the own direction found something else: on a drawn maple
    sketch whose ink is the layer, the white paper between brush strokes
    was induced instead of the black ink (IoU with the ink 0.94 -> 0.00).
    Pale -> dark veins (the pale colour absent) and red -> dark (no turn
    in lightness) keep their own direction.
    """
    if e == t or pixels is None or pixels.sum() < 10:
        return False
    c_t = _contrast(labs[t], user, blade_t)
    c_e = _contrast(labs[e], pixels, blade_e)
    if c_t is None or c_e is None or float(c_t[0]) * float(c_e[0]) >= 0:
        return False
    colour = np.median(labs[t][user], axis=0)
    tol = max(float(np.linalg.norm(c_t)) / 3.0, 1e-6)
    close = (np.linalg.norm(labs[e] - colour, axis=-1) < tol) & blade_e
    share_t = float(user.sum()) / max(float(blade_t.sum()), 1.0)
    share_e = float(close.sum()) / max(float(blade_e.sum()), 1.0)
    return share_e >= LAYER_COLOUR_PRESENT * share_t


def _own_delta(combined, delta, pixels, blade):
    """``delta`` for one exemplar: the training leaf's, or larger where its own layer pixels need it.

    The paper's ``delta`` is chosen on the training leaf; where the
    exemplar's layer matches its colour model less closely (another vein
    colour, a re-estimated model), ``{D < delta}`` kept only its midrib
    (procedural pale -> dark veins: combined ``D`` 0.17 on its veins, 0.28
    off them, ``delta`` 0.16). Chosen the same way (eq. 4) against the
    exemplar's own layer pixels (:func:`branchnb.leaves.own_contrast.exemplar_direction`),
    never below the training leaf's.
    """
    if pixels is None or pixels.sum() < 10:
        return delta
    return max(float(delta), choose_threshold(combined, pixels, blade)[0])


def _own_cdf(q, pixels, cdf, bins):
    """An exemplar's colour model of the layer: the training leaf's, or re-estimated from its own layer ``pixels``."""
    if pixels is None or pixels.sum() < 10:
        return cdf
    return layer_cdfs(q, pixels, bins)



#: An exemplar's own (unmatched) colours may add to what the matched ones find while the layer
#: then covers at most this many times the training layer's share of the blade (:func:`_own_colours`).
OWN_COLOURS_MAX = 3.0


def _own_colours(colour, combined, delta, residual, blades, t, user, cdf, own_px, space, n_px, params, *,
                 counted=None):
    """``colour`` with each exemplar's colour term the better of its matched and its own colours.

    Beyond the paper (issue 22): matching each blade's colour statistics
    onto the training leaf's (``params.match_colours``) lets leaves whose
    overall hue differs compare by pattern, but it assumes a layer's colour
    moves with its blade's. Spots or marks of one fixed colour on blades of
    differing shade break that: on a darker birch-like leaf with more spots
    the match moved the spots' colour 30 Lab units away and not one spot
    was found (IoU 0.92 in its own colours -> 0.00); on a lighter one a third
    (0.31). Each exemplar's term is therefore the lower (more similar) of
    the two, unless the own colours would make the layer cover more than
    :data:`OWN_COLOURS_MAX` times the training layer's share of the blade
    (a blade whose own colour is the layer's would otherwise be taken
    whole: the case matching is for). Not for thin layers (veins): they
    follow each exemplar's own ridges and colour model
    (:func:`_under_induced`).
    """
    share_t = float(user.sum()) / max(float(blades[t].sum()), 1.0)
    w = space.weights if params.lab_units else None
    out = colour
    for e in range(len(colour)):
        if e == t:
            continue
        q_own = _quantise_lab(_lab(residual[e]), space)
        own = colour_similarity(q_own, blades[e] if counted is None else counted[e],
                                _own_cdf(q_own, own_px[e], cdf, space.bins), n_px, weights=w)
        better = np.minimum(colour[e], own)
        # D = lambda F + S: lowering S lowers D by as much (F grows as S falls, but lambda ~ 0 here)
        got = float(((combined[e] < delta) & blades[e]).sum())
        found = float(((combined[e] - colour[e] + better < delta) & blades[e]).sum())
        if got < found <= OWN_COLOURS_MAX * share_t * float(blades[e].sum()):
            out = list(out) if out is colour else out
            out[e] = better.astype(np.float32)
    return out


#: An exemplar whose ``{D < delta}`` under the training leaf's colour model
#: covers less than this share of the area the layer should cover there
#: (the training layer's area scaled by the blades' areas) takes its own
#: colour model (:func:`_under_induced`).
UNDER_INDUCED = 0.5


def _under_induced(q, blades, t, user, cdf, own_px, ridge_px, dist, lengths, tolerance, params,
                   registrations, space, n_px):
    """``own_px`` with the exemplars the training colour model under-induces on given their own pixels.

    A vein plays the same role on every leaf but its colour is the leaf's
    own. Where the contrast test (:func:`_other_colour`) takes two colours
    for one (red and dark-green veins both stand out darker, and after the
    blade statistics are matched the dark veins' contrast turns within
    0.95 of the red ones'), the training leaf's colour model finds a third
    of the exemplar's veins (procedural red -> dark: IoU 0.05-0.20). Such
    an exemplar's ``{D < delta}`` (training model and ``delta``) covers
    under :data:`UNDER_INDUCED` of the area the layer should take on it;
    it then takes the colour model of its own layer pixels (beyond the
    paper). Deciding by the colour term at the exemplar's ridge pixels
    instead fired on same-coloured lobed and trilobed leaves
    (``_measure_colours`` notes): their induced area is never that short.
    """
    n = len(blades)
    if not _long_network(user, blades[t]):
        return own_px
    todo = [e for e in range(n) if e != t and own_px[e] is None and ridge_px[e] is not None
            and ridge_px[e].sum() >= 10]
    if not todo:
        return own_px
    w = space.weights if params.lab_units else None
    colour = [colour_similarity(q[e], blades[e], cdf, n_px, weights=w) for e in range(n)]
    _, _, combined, delta, _ = _combine(colour, dist, lengths, tolerance, params, blades, registrations, t, user)
    out = list(own_px)
    area_t = float(user.sum()) / max(float(blades[t].sum()), 1.0)
    for e in todo:
        expected = area_t * float(blades[e].sum())
        got = float(((combined[e] < delta) & blades[e]).sum())
        if got < UNDER_INDUCED * expected:
            out[e] = ridge_px[e]
    return out


def _long_network(user, blade, *, share: float = 1.0) -> bool:
    """Whether ``user`` holds one connected piece whose skeleton is at least ``share`` of the leaf size long.

    A vein system does; small spots (thin enough for :func:`~branchnb.leaves.snapping.is_thin_layer`)
    do not, and their area varies from leaf to leaf, so no exemplar's spots
    count as under-induced (procedural trilobed, spots 0.68 -> 0.01 IoU without this; a
    cluster of spots had a skeleton 0.3 of the leaf size long, a vein system's is several).
    """
    from skimage.morphology import skeletonize
    lab, n = ndi.label(user, structure=np.ones((3, 3)))
    if n == 0:
        return False
    length = np.bincount(lab[skeletonize(user)], minlength=n + 1)[1:]
    return float(length.max()) >= share * np.sqrt(float(blade.sum()))
