"""Layer induction on every exemplar (the paper's Sec. 4 as steps of :func:`branchnb.leaves.analysis.analyze`):
the colour and spatial terms, the snapped layers, the induced masks and their result, :class:`LayerInduction`."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage as ndi

from ..core.distance import edt as _edt
from ..core.image import as_mask, as_rgb
from ..core.morphology import _binary_dilation
from ..core.random import as_rng
from ..core.threads import thread_map
from ..core.validate import check_bool, check_callback, check_int, check_real
from .analysis_masks import _contrast_map, _exemplar_mask, _MaskSteps
from .analysis_outline import (  # noqa: F401  (importable from here as before)
    INKED_OUTLINE,
    OUTLINE_GAP,
    OUTLINE_IN_LAYER,
    OUTLINE_STRETCH,
    _closed_blade,
    _contrast,
    _ink_zone,
    _inked_outline,
    _outline_band,
    _outline_in_layer,
    _outline_stretches,
)
from .analysis_snapped import THIN_NETWORK, THIN_SHARE, _snapped, thin_width  # noqa: F401
from .analysis_trim import RIM_TRIM, SPECK_LENGTH, SPECK_MIN, _pinholes, _trimmed, _without_dots  # noqa: F401
from .induction import (
    ColourSpace,
    InductionParams,
    _lab,
    _quantise_lab,
    blade_lab_stats,
    choose_threshold,
    colour_similarity,
    colour_space,
    layer_cdfs,
    layer_weight,
    layer_width,
    liberal_layer,
    neighbourhood_candidates,
    remove_layer,
    scaled_lengths,
    spatial_term,
)
from .induction_scatter import TIE_LEVEL, positional_tie, scattered_layer
from .snapping import contrast_direction
from .stored_maps import BoxedMaps, CombinedMaps, DistanceMaps

__all__ = ["LayerInduction", "induce", "registration_tolerance", "warp_mask"]

Progress = Callable[[float, str], None]


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


@dataclass
class LayerInduction:
    """One user layer induced on every exemplar.

    Parameters
    ----------
    name : str
        The user layer's name.
    lam : float
        ``lambda_c = kappa |cap L~e| / |cup L~e|``.
    liberal_overlap : float
        ``|cap L~e| / |cup L~e|`` (``lambda / kappa``).
    delta : float
        The threshold of ``D`` (eq. 4).
    training_overlap : float
        IoU of ``{D < delta}`` with the user's layer on the training leaf.
    masks : list of (H, W) bool ndarray
        The induced layer in each exemplar (the user's layer on the training leaf).
    colour : sequence of (H, W) float32 ndarray
        ``S_e(x, c)`` per exemplar (from :func:`induce`: a
        :class:`~branchnb.leaves.stored_maps.BoxedMaps`, kept on the blades' boxes).
    combined : sequence of (H, W) float32 ndarray
        ``D(x, c)`` per exemplar (from :func:`induce`: a
        :class:`~branchnb.leaves.stored_maps.CombinedMaps`, recomputed when read).
    registered : list of (H, W) bool ndarray
        The user layer registered onto each exemplar.
    distance : sequence of (H, W) float32 ndarray
        ``||x, c||`` per exemplar (from :func:`induce`: a
        :class:`~branchnb.leaves.stored_maps.DistanceMaps` of ``registered``).
    eps_px : list of float
        The scaled ``eps`` of each exemplar.
    neighbourhood : int
        The side ``n`` of the neighbourhood of ``S_e`` used for this layer.
    snapped : list of (H, W) bool ndarray or None, optional
        A thin layer's main structure snapped onto each exemplar's own
        ridges (None on the training leaf), or None when the layer is not
        thin or snapping is off (beyond the paper; see
        :mod:`branchnb.leaves.snapping`).
    contrast : list of ((H, W) float32 ndarray or None) or None, optional
        Per exemplar, each pixel's high-pass colour along the thin layer's
        contrast direction there, which its induced mask was trimmed by
        (:func:`~branchnb.leaves.own_contrast.trim_by_contrast`); None where not trimmed.
    centred : list of (H, W) bool ndarray or None, optional
        The snapped paths grown to the side and width of each exemplar's own
        vein (:func:`~branchnb.leaves.snapping_width._grow_to_width`); joined to
        ``{D < delta}`` beside it (:func:`_induced`).
    standout : list of (float or None) or None, optional
        For a layer scribbled as thin lines: how much its mask stands out
        from the blade around it on each exemplar (the training leaf's
        included), :func:`~branchnb.leaves.structural.layer_standout` (0 where it
        covers under :data:`~branchnb.leaves.structural.MIN_FOUND` of the
        training leaf's share of the blade); None
        for other layers (set by :func:`~branchnb.leaves.analysis.analyze`,
        read by :func:`~branchnb.leaves.structural.is_structural`).
    steps : _MaskSteps or None, optional
        What :func:`induce` found besides ``D`` (snapped paths, outline zones, hole rims, ...), so
        :meth:`~branchnb.leaves.analysis.LeafAnalysis.retune` makes the masks by the same code
        (:func:`~branchnb.leaves.analysis_masks._exemplar_mask`).
    """

    name: str
    lam: float
    liberal_overlap: float
    delta: float
    training_overlap: float
    masks: list
    colour: list = field(repr=False)
    combined: list = field(repr=False)
    registered: list = field(repr=False)
    distance: list = field(repr=False)
    eps_px: list = field(repr=False)
    neighbourhood: int = 1
    snapped: list | None = field(default=None, repr=False)
    contrast: list | None = field(default=None, repr=False)
    centred: list | None = field(default=None, repr=False)
    standout: list | None = field(default=None, repr=False)
    steps: _MaskSteps | None = field(default=None, repr=False)

    def spatial(self, e: int) -> np.ndarray:
        """``F(x, c)`` on exemplar ``e`` (recomputed from the stored terms).

        Parameters
        ----------
        e : int
            Exemplar index.

        Returns
        -------
        (H, W) float32 ndarray
        """
        e = check_int(e, "e", 0, len(self.distance) - 1)
        return spatial_term(self.distance[e], self.colour[e], self.eps_px[e])

    @property
    def empty(self) -> list[int]:
        """Exemplars on which the layer induced to nothing."""
        return [i for i, m in enumerate(self.masks) if not m.any()]


def _progress(progress: Progress | None, lo: float, hi: float) -> Progress:
    check_callback(progress, "progress")

    def report(f: float, text: str) -> None:
        if progress is not None:
            progress(lo + (hi - lo) * float(np.clip(f, 0, 1)), text)
    return report


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


def induce(images, blades, training_index: int, user_masks: dict, registrations,
           params: InductionParams, *, space: ColourSpace | None = None,
           progress: Progress | None = None, rng=0):
    """Induce the user layers (top first) on every exemplar, removing each before the next.

    Parameters
    ----------
    images : list of (H, W, 3) float arrays
        The exemplars' RGB on the common canvas, in [0, 1].
    blades : list of (H, W) bool arrays
        Their blades.
    training_index : int
        The exemplar the user's layers are on.
    user_masks : dict name -> (H, W) bool
        The user's layers on the training leaf, in order top first.
    registrations : list
        Exemplar ``i`` -> training leaf (``to_training`` / ``from_training``).
    params : InductionParams
        ``eps``, ``kappa``, bins, ... (the paper's defaults in ``InductionParams()``).
    space : ColourSpace, optional
        Quantisation (computed from the blades if None).
    progress : callable(fraction, text), optional
        Called between steps; an exception it raises stops the induction.
    rng : {numpy.random.Generator, int}
        Seeds the removal of each layer (patch quilting of wide parts); default 0.

    Returns
    -------
    layers : list of LayerInduction
    residuals : list of list of (H, W, 3) ndarray
    space : ColourSpace

    Notes
    -----
    Beyond the paper (issue 22): a layer of marks at chance places is never snapped, is read on the
    residual the layer above left outside its mask, and its windows leave out what the layers above
    took (:mod:`~branchnb.leaves.induction_scatter`).
    """
    report = _progress(progress, 0.0, 1.0)
    rng = as_rng(rng)
    n = len(images)
    rgb = [as_rgb(im, name=f"images[{i}]") for i, im in enumerate(images)]
    # Each exemplar's CIELAB, converted once for the colour space, the blade statistics and the first layer.
    lab0 = [_lab(im) for im in rgb]
    if space is None:
        space = colour_space(rgb, blades, params.bins, labs=lab0)
    t = training_index
    lengths = [scaled_lengths(params, b) for b in blades]
    tolerance = registration_tolerance(registrations, training_index)
    stats = [blade_lab_stats(im, b, lab=lab) for im, b, lab in zip(rgb, blades, lab0)]
    residual = list(rgb)
    # The exemplars themselves where they are the same float32 colours (no second copy).
    residuals = [[im if isinstance(im, np.ndarray) and im.dtype == np.float32 and im.shape == r.shape
                  and np.array_equal(im, r) else r for im, r in zip(images, rgb)]]
    taken = [np.zeros_like(b) for b in blades]
    kept = None
    out = []
    names = list(user_masks)
    steps = max(len(names) * (2 * n + 1), 1)
    step = 0
    for name in names:
        user = as_mask(user_masks[name], shape=blades[t].shape, name=f"user_masks[{name!r}]")
        # A layer stroke across a pinhole of the matte is one stroke: cut there, a
        # traced vein fell into pieces (maple_leaf_04's hand trace: 3 pieces, and a
        # template of broken branches carried onto every exemplar).
        user = user & (blades[t] | _pinholes(blades[t], user))
        if not user.any():
            raise ValueError(f"user_masks[{name!r}] is empty on the training leaf's blade")
        # Each residual's CIELAB (moved onto the training leaf's statistics),
        # converted once for the colour term, the snapping and the ridge extension.
        scattered = scattered_layer(user, blades[t])
        # Scattered marks are read on the residual the layer above left outside its mask (see Notes).
        seen = kept if scattered and kept is not None else residual
        labs = thread_map(lambda e, seen=seen, lab0=lab0: _matched_lab(
            seen[e], stats, e, t, params, lab=lab0[e] if seen[e] is rgb[e] else None), range(n))
        lab0 = [None] * n  # later layers' residuals differ: not held any longer
        q = thread_map(lambda lab: _quantise_lab(lab, space), labs)
        cdf = layer_cdfs(q[t], user, space.bins)
        report(step / steps, f"layer {name}: snapping to each exemplar's ridges")  # "cancel" stops here too
        # An ink layer the user drew with the leaf's outline (a sketch's ink) keeps it on every exemplar.
        outline_in_layer = _outline_in_layer(blades[t], user)
        if scattered:
            # Marks at chance places (blotches cut by veins, hole rims, lichen dots) have no main
            # structure to carry: snapped as thin, each exemplar got ridges at the training
            # marks' registered places (see Notes of :func:`induce`).
            snapped, own, ridge_px, centred, zones, rims = None, [None] * n, [None] * n, None, [None] * n, [None] * n
        else:
            snapped, own, ridge_px, centred, zones, rims = _snapped(
                residual, blades, t, user, registrations, stats, tolerance, params, labs=labs,
                rgb=None if outline_in_layer else rgb)
        # The training leaf's colour model where the exemplar's layer has its
        # colour (it is exact there; re-estimated from the found pixels it lost
        # 0.03-0.13 IoU on same-coloured veins), else the exemplar's own.
        own_px = [p if p is not None and (own[e] is not None or
                                          _other_colour(labs, t, user, blades[t], e, p, blades[e],
                                                        scale=_unmatched(stats, e, t, params)))
                  and not _has_layer_colour(labs, t, user, blades[t], e, p, blades[e]) else None
                  for e, p in enumerate(ridge_px)]
        # The registered user layer and its distance map do not depend on n.

        def registered(e, user=user, snapped=snapped):
            ru = user if e == t else warp_mask(registrations[e], user, to_training=False, level=0.25) & blades[e]
            if snapped is not None and e != t:
                # The exemplar's own main structure joins the carried-over prior.
                ru = ru | snapped[e]
            return ru, (_edt(~ru) if ru.any() else np.full(ru.shape, 1e6, np.float32))

        reg_user, dist = (list(x) for x in zip(*thread_map(registered, range(n))))
        best = None
        candidates = neighbourhood_candidates(params, blades[t], user)
        inked_outline = not outline_in_layer and _inked_outline(labs[t], blades[t], user)
        if snapped is not None:
            own_px = _under_induced(q, blades, t, user, cdf, own_px, ridge_px, dist, lengths, tolerance, params,
                                    registrations, space, candidates[0])
        # A scattered layer's windows leave out what the layers above took: their removal filled it
        # from around, and beside a vein that was the marks' own colour (hole rims on a midrib).
        counted = [b if e == t or not scattered else b & ~taken[e] for e, b in enumerate(blades)]
        tried = {}
        for n_px in candidates:
            report(step / steps, f"layer {name}: colour and space terms ({n_px} px window)")
            colour = thread_map(lambda e, n_px=n_px, q=q, own_px=own_px, cdf=cdf, counted=counted: colour_similarity(
                q[e], counted[e], _own_cdf(q[e], own_px[e], cdf, space.bins), n_px,
                weights=space.weights if params.lab_units else None), range(n))
            lam, overlap, combined, delta, tr_iou = _combine(colour, dist, lengths, tolerance, params, blades,
                                                             registrations, t, user)
            tried[n_px] = colour
            if best is None or tr_iou > best[0] + 1e-9:
                best = (tr_iou, n_px, colour, lam, overlap, combined, delta)
        step += n
        tr_iou, n_px, colour, lam, overlap, combined, delta = best
        if params.match_colours and snapped is None:
            redo = _own_colours(colour, combined, delta, seen, blades, t, user, cdf, own_px, space, n_px, params,
                                counted=counted)
            if redo is not colour:
                colour = redo
                lam, overlap, combined, delta, tr_iou = _combine(colour, dist, lengths, tolerance, params, blades,
                                                                 registrations, t, user)
                tried[n_px] = colour
        masks = []
        new_residual = []
        kept = []
        steps_kept = _MaskSteps(user, blades, t, snapped, centred, own, own_px, ridge_px, zones, rims,
                                outline_in_layer, inked_outline)
        contrast = [None] * n

        def contrast_of(e, labs=labs, steps_kept=steps_kept):
            return _contrast_map(labs[t], labs[e], steps_kept, e)

        report(step / steps, f"layer {name}: masks")

        def induced(e, user=user, snapped=snapped, residual=residual, labs=labs, own=own, steps_kept=steps_kept,
                    combined=combined, delta=delta, tr_iou=tr_iou):
            m, c = _exemplar_mask(steps_kept, e, combined[e], delta, tr_iou, taken[e], contrast_of)
            gone = m if snapped is None or e == t else _ridge_extension(residual, blades, t, e, user, m, stats, params,
                                                                        labs=labs, direction=own[e])
            return m, c, gone

        for e, (m, contrast[e], gone) in enumerate(thread_map(induced, range(n))):
            report(step / steps, f"layer {name}: residual of exemplar {e + 1}/{n}")
            step += 1
            masks.append(m)
            taken[e] = taken[e] | m
            # In turn: the patch quilting of wide parts draws from one generator, exemplar after exemplar.
            new_residual.append(remove_layer(residual[e], blades[e], gone, rng=rng))
            # Outside the mask as it was: the removal also grew the mask (by its ridge extension and its
            # anti-aliasing rim), eating the marks that touch a vein.
            kept.append(new_residual[-1] if e == t else
                        np.where(m[..., None], new_residual[-1], residual[e]).astype(new_residual[-1].dtype))
        residual = new_residual
        residuals.append(list(residual))
        # Kept small (:mod:`branchnb.leaves.stored_maps`): S_e on the blades' boxes, ||x, c|| and D
        # recomputed from the registered layers when read (the same values).
        eps_list = [ln[0] for ln in lengths]
        colour_kept = BoxedMaps(colour, blades, 1.0)
        # Every window's S_e, so a retune picks the window as the induction would (:func:`_retuned`).
        steps_kept.colours = {k: colour_kept if k == n_px else BoxedMaps(c, blades, 1.0) for k, c in tried.items()}
        dist_kept = DistanceMaps(reg_user)
        out.append(LayerInduction(name, lam, overlap, delta, tr_iou, masks, colour_kept,
                                  CombinedMaps(lam, colour_kept, dist_kept, eps_list),
                                  reg_user, dist_kept, eps_list, n_px, snapped=snapped,
                                  contrast=contrast if any(c is not None for c in contrast) else None,
                                  centred=centred, steps=steps_kept))
        step += 1
    report(1.0, "induction done")
    return out, residuals, space


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


def _matched_lab(image, stats, e, t, params, lab=None):
    """CIELAB of exemplar ``e``'s ``image`` (``lab`` when converted already), moved onto the training leaf's
    blade statistics (colour matching on)."""
    lab = _lab(image) if lab is None else lab
    if params.match_colours and e != t:
        lab = (lab - stats[e][0]) / stats[e][1] * stats[t][1] + stats[t][0]
    return lab


def _ridge_extension(residual, blades, t, e, user, m, stats, params, *, level: float = 0.2,
                     reach: float = 0.15, labs=None, direction=None):
    """A thin layer's induced mask on exemplar ``e``, grown along the layer's ridges, for its removal.

    The colour term misses the faint ends of fine veins; left in the
    residual they show as short dashes of a second vein system on every new
    leaf that takes this exemplar as background. Grown (beyond the paper)
    into pixels connected to the mask whose ridge evidence along the
    layer's contrast direction is at least ``level``, within ``reach`` of
    the leaf size. Measured on procedural families (3 kinds, 192 and 320 px,
    true registrations, 3 leaves each): ridge response of the residual at
    the true vein pixels over that on plain blade, mean 0.94 -> 0.71, at
    most 1 on 17 of 18 exemplars (before 10), worst 1.41 -> 1.32 (an
    elliptic leaf whose own veins stand out only 1.75x). With ``level``
    0.25 and ``reach`` 0.04 the stubs of an elliptic leaf's secondaries
    stayed as short light dashes beside the donor's veins; with 0.2 and
    0.15 (``_measure veinsystems``, new leaves, 2 seeds x 4, at 192 / 320
    px) the ratio at the background's own veins went from 1.00 / 1.11 to
    1.00 / 1.01 elliptic, 0.87 / 0.91 to 0.81 / 0.80 trilobed and 0.91 /
    0.81 to 0.93 / 0.79 lobed (level 0.15: the same, but on a drawn leaf
    the grown mask reached the outline and its fill left ink in the
    residual; 0.10 and 0.12: 1.00 / 1.02; a 2 px rim instead of 1: no gain).
    """
    from .snapping import ridge_evidence

    def lab_of(k):
        return labs[k] if labs is not None else _matched_lab(residual[k], stats, k, t, params)
    if direction is None:
        direction = contrast_direction(lab_of(t), user, blades[t])
    ev = ridge_evidence(lab_of(e), blades[e], direction, max(1.0, layer_width(user)))
    steps = max(1, int(round(reach * np.sqrt(float(blades[e].sum())))))
    return ndi.binary_dilation(m, iterations=steps, mask=(ev >= level) & blades[e]) | m


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


#: Share of the training leaf's colour matches (``S_t`` under the liberal threshold) that must be the
#: user's layer for a scattered layer's positional tie to be dropped (:func:`_combine`).
SINGLES_OUT = 0.5


def _combine(colour, dist, lengths, tolerance, params, blades, registrations, t, user):
    """Eqs. 2-4 from the colour terms and distance maps: ``lambda``, ``D`` per exemplar, ``delta``.

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
        lib = liberal_layer(colour[e], dist[e], params.liberal_threshold, max(lib_r, tolerance), blades[e])
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


