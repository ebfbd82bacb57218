"""Layer induction on every exemplar (the paper's Sec. 4 as steps of :func:`branchnb.leaves.analysis.analyze`):
one layer after another, its colour and spatial terms, snapped layers, induced masks and removal
(:func:`induce`), and their result, :class:`LayerInduction`. The steps live in
:mod:`~branchnb.leaves.analysis_combine` (eqs. 2-4 and the induced mask),
:mod:`~branchnb.leaves.analysis_own` (each exemplar's own colours), :mod:`~branchnb.leaves.analysis_snapped`,
:mod:`~branchnb.leaves.analysis_outline` and :mod:`~branchnb.leaves.analysis_trim`."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial

import numpy as np
from scipy import ndimage as ndi

from ..core.distance import edt as _edt
from ..core.image import as_mask, as_rgb
from ..core.morphology import _binary_dilation
from ..core.random import as_rng
from ..core.threads import thread_map
from ..core.validate import check_callback, check_int
from .analysis_combine import (  # noqa: F401  (importable from here as before)
    _LIBERAL_CACHE,
    COLOUR_RELIABLE,
    OVER_INDUCED,
    SINGLES_OUT,
    _combine,
    _induced,
    _liberal_to_training,
    _over_induced,
    colour_delta,
    registration_tolerance,
    unmatched_liberal,
    warp_mask,
)
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
from .analysis_own import (  # noqa: F401  (importable from here as before)
    LAYER_COLOUR_PRESENT,
    OWN_COLOURS_MAX,
    SAME_CONTRAST,
    UNDER_INDUCED,
    _has_layer_colour,
    _long_network,
    _matched_lab,
    _other_colour,
    _own_cdf,
    _own_colours,
    _own_delta,
    _under_induced,
    _unmatched,
)
from .analysis_snapped import THIN_NETWORK, THIN_SHARE, _snapped, thin_width  # noqa: F401
from .analysis_trim import RIM_TRIM, SPECK_LENGTH, SPECK_MIN, _pinholes, _trimmed, _without_dots  # noqa: F401
from .induction import (
    ColourSpace,
    InductionParams,
    _lab,
    _quantise_lab,
    blade_lab_stats,
    colour_similarity,
    colour_space,
    layer_cdfs,
    layer_width,
    neighbourhood_candidates,
    remove_layer,
    scaled_lengths,
    spatial_term,
)
from .induction_scatter import layer_coloured, scattered_layer
from .margin_band import BAND_MIX, band_coloured, band_rim, band_share, band_threshold, outline_region
from .snapping import contrast_direction
from .stored_maps import BoxedMaps, CombinedMaps, DistanceMaps

__all__ = ["LayerInduction", "induce", "registration_tolerance", "warp_mask"]

Progress = Callable[[float, str], None]


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



def _band_claimed(share, blade, removed, taken):
    """The pixels a band takes back on an exemplar (``claimed``, ``crossed`` of :func:`band_rim`).

    ``share`` its pixels' own :func:`~branchnb.leaves.margin_band.band_share`; ``removed`` what the
    removals above took outside their masks, ``taken`` their masks. A vein crossing the band is pale
    there as the band is, and in the green centre pale too: the layers' pixels count as the band's
    where they lie :data:`BAND_MIX` of the way from their own median colour to the band's, never under
    :data:`BAND_MIX` itself (:func:`~branchnb.leaves.margin_band.band_rim` then keeps those across the
    band only).

    Notes
    -----
    At half the way (leaves82) the veins' parts across the band stayed veins wherever the band
    painted them a darker cream than its own: the procedural variegated leaves' veins lie 0.26 of the
    way in the green centre and 0.59 across the band (0.78-0.80 only on their anti-aliased edges),
    so only those edges went to the band, the vein tips kept star-shaped blobs of the band's edge
    (600 px, exemplar 3: 469 of the mask's 593 false pixels in the band, vein IoU 0.84) and new leaves
    carried them as cream flecks at their veins' ends. Beyond the paper.
    """
    coloured = blade & (share > np.float32(BAND_MIX))
    cut = BAND_MIX
    if taken.any():
        own = float(np.median(share[taken]))
        cut = max(BAND_MIX, own + BAND_MIX * (1.0 - own))
    return removed & ~taken & coloured, taken & blade & (share > np.float32(cut))


#: The fainter lines a thin layer grew along are left out of the structure snapped onto the exemplars
#: (:func:`_carried`; False: snapped with the rest, as leaves94): the sample maples' induced veins (training
#: maple_leaf_01, six exemplars) IoU with the hand tracings mean 0.399 -> 0.492; procedural families
#: (``_measure_secondary`` seed 0, 72 exemplars) vein IoU mean 0.804 -> 0.802, min 0.736 -> 0.735.
_CARRY_CORE = True


def _carried(training) -> dict | None:
    """Per thin line layer grown along fainter lines, its mask without them: the structure snapped.

    Parameters
    ----------
    training : TrainingLayers
        The grown training layers (:func:`~branchnb.leaves.layers.grow_layers`).

    Returns
    -------
    dict or None
        Name -> mask, for the layers that grew along fainter lines; None when none did.

    Notes
    -----
    Beyond the paper (issue 22, leaves97): the fainter lines a scribbled vein layer grew along
    (:func:`~branchnb.leaves.layers_lines._along_lines`) stay in its colour model and its mask, but
    not in the structure carried to the exemplars. Joined to the main veins, each split a main vein's
    skeleton chain at a new junction (maple_leaf_01's midrib: one chain of 45 samples -> 15 + 14 + a
    31-sample side branch), and the chains were placed apart: on maple_leaf_05 the right main
    lateral's first third was traced as a 56-px zig-zag beside the midrib, the lateral itself started
    a third of its length up. Left out (:data:`_CARRY_CORE`): the six other sample maples' induced veins
    (training maple_leaf_01, its stored scribbles) IoU with their hand tracings 0.407 / 0.427 / 0.359 /
    0.413 / 0.470 / 0.317 -> 0.534 / 0.551 / 0.430 / 0.568 / 0.564 / 0.305, mean 0.399 -> 0.492;
    ``python -m branchnb.leaves._measure_secondary --seeds 0`` (4 kinds, 192 / 256 / 400 px, each leaf
    as the training leaf; 72 exemplars, where the fainter lines are true secondaries): vein IoU mean
    0.804 -> 0.802, min 0.736 -> 0.735, largest drop 0.028, none under 0.7; spots 0.929 either way;
    the grown training layers (``_measure_grown``) are the same masks.

    Examples
    --------
    >>> import numpy as np
    >>> from types import SimpleNamespace as NS
    >>> m = np.ones((2, 2), bool); a = np.array([[True, False], [False, False]])
    >>> int(_carried(NS(masks={"veins": m}, along={"veins": a}))["veins"].sum())
    3
    """
    along = getattr(training, "along", None)
    if not along or not _CARRY_CORE:
        return None
    out = {name: training.masks[name] & ~extra for name, extra in along.items()
           if name in training.masks and extra is not None and extra.any()}
    return out or None


def induce(images, blades, training_index: int, user_masks: dict, registrations,
           params: InductionParams, *, space: ColourSpace | None = None,
           progress: Progress | None = None, rng=0, carried: dict | None = None):
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
    carried : dict name -> (H, W) bool, optional
        Per layer, the part of its user mask whose structure is snapped onto
        the exemplars (:func:`_carried`); default (or a missing name) the whole mask.

    Returns
    -------
    layers : list of LayerInduction
    residuals : list of list of (H, W, 3) ndarray
    space : ColourSpace

    Notes
    -----
    Beyond the paper (issue 22): a layer of marks at chance places is never snapped, is read on the
    residual the layer above left outside its mask, and its windows leave out what the layers above
    took (:mod:`~branchnb.leaves.induction_scatter`). Where its own colour singles it out
    (:data:`MARKS_SINGLED`), its edges follow its pixels' colour and the marks the layers above took
    come back to it by their shape, leaving those layers' masks (leaves75).
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
    # What the layers' removals took beyond their masks (ridge extensions), per exemplar.
    removed = [np.zeros_like(b) for b in blades]
    kept = None
    out = []
    names = list(user_masks)
    # Each layer's colour on the training leaf (in its matched CIELAB), for the marks' edges below.
    above_colours = []
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
            core = user
            if carried is not None and carried.get(name) is not None:
                core = user & np.asarray(carried[name], bool)
                core = core if core.any() else user
            snapped, own, ridge_px, centred, zones, rims = _snapped(
                residual, blades, t, core, registrations, stats, tolerance, params, labs=labs,
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
        tried, liberal_tried = {}, {}
        q_own = {}

        def own_colour(e, n_px, seen=seen, cdf=cdf, counted=counted, q_own=q_own):
            # The exemplar's unmatched colours against the training layer's model (the liberal layer only).
            if e not in q_own:
                q_own[e] = _quantise_lab(_lab(seen[e]), space)
            return colour_similarity(q_own[e], counted[e], cdf, n_px,
                                     weights=space.weights if params.lab_units else None)

        for n_px in candidates:
            report(step / steps, f"layer {name}: colour and space terms ({n_px} px window)")
            colour = thread_map(lambda e, n_px=n_px, q=q, own_px=own_px, cdf=cdf, counted=counted: colour_similarity(
                q[e], counted[e], _own_cdf(q[e], own_px[e], cdf, space.bins), n_px,
                weights=space.weights if params.lab_units else None), range(n))
            lib_colour = unmatched_liberal(colour, dist, lengths, tolerance, params, blades, t,
                                           partial(own_colour, n_px=n_px)) if params.match_colours else None
            lam, overlap, combined, delta, tr_iou = _combine(colour, dist, lengths, tolerance, params, blades,
                                                             registrations, t, user, liberal=lib_colour)
            tried[n_px] = colour
            liberal_tried[n_px] = lib_colour
            if best is None or tr_iou > best[0] + 1e-9:
                best = (tr_iou, n_px, colour, lam, overlap, combined, delta)
        step += n
        tr_iou, n_px, colour, lam, overlap, combined, delta = best
        own_read = []
        if params.match_colours and snapped is None:
            redo = _own_colours(colour, combined, delta, seen, blades, t, user, cdf, own_px, space, n_px, params,
                                counted=counted)
            if redo is not colour:
                own_read = [e for e in range(n) if redo[e] is not colour[e]]
                colour = redo
                liberal_tried[n_px] = unmatched_liberal(colour, dist, lengths, tolerance, params, blades, t,
                                                        partial(own_colour, n_px=n_px))
                lam, overlap, combined, delta, tr_iou = _combine(colour, dist, lengths, tolerance, params, blades,
                                                                 registrations, t, user, liberal=liberal_tried[n_px])
                tried[n_px] = colour
        masks = []
        new_residual = []
        kept = []
        steps_kept = _MaskSteps(user, blades, t, snapped, centred, own, own_px, ridge_px, zones, rims,
                                outline_in_layer, inked_outline,
                                band=snapped is None and not scattered and outline_region(blades[t], user))
        clear = _clear_of_above(user, blades[t], taken[t]) if scattered else None
        colour_t = np.median(labs[t][user & clear], axis=0) if scattered else None
        # Only marks whose pixels' own colour tells them from the blade on the training leaf (not the
        # sample maples' spots of nearly the blade's colour: there the edges grew over the blade).
        singled = scattered and _iou(layer_coloured(labs[t], blades[t], colour_t, taken[t]) & clear,
                                     user & clear) >= MARKS_SINGLED
        if singled:
            # Each mark's edge by its pixels' own colour, in the colours its term was read in.
            own_t = np.median(_lab(seen[t])[user], axis=0) if own_read else None
            # Nearer the marks' colour than the layers above's too: a pale vein's soft edge over a
            # dark spot (see Notes of :func:`~branchnb.leaves.induction_scatter.layer_coloured`).
            steps_kept.coloured = [None if e == t else layer_coloured(
                _lab(seen[e]) if e in own_read else labs[e], blades[e], own_t if e in own_read else colour_t,
                taken[e], above=None if e in own_read else tuple(above_colours), local=True) for e in range(n)]
        if singled and len(residuals) >= 2:
            # D of the marks on the residual the layer above was read on: what that layer took of
            # their colour (see Notes).
            steps_kept.claims = thread_map(partial(_claims, residuals[-2], t=t, taken=taken, stats=stats,
                                                   params=params, space=space, own_px=own_px, cdf=cdf, n_px=n_px,
                                                   blades=blades, combined=combined, colour=colour), range(n))
        band_reach = band_threshold(colour[t], user, blades[t]) if steps_kept.band else None
        if steps_kept.band:
            # Each pixel's own colour takes the rim the windowed colour term leaves at the band's edge
            # (:func:`~branchnb.leaves.margin_band.band_rim`).
            layer_c = np.median(labs[t][user], axis=0)
            rest_t = blades[t] & ~user & ~taken[t]
            if rest_t.any():
                blade_c = np.median(labs[t][rest_t], axis=0)
                steps_kept.band_coloured = [band_coloured(labs[e], blades[e], layer_c, blade_c) for e in range(n)]
                steps_kept.band_reach = int(n_px)
                if any((rm | tk).any() for rm, tk in zip(removed, taken)):
                    # The band's colour in the exemplars' own pixels where a layer above or its removal
                    # took them: the band's pale edge read as a vein's ridge, the veins' tips crossing
                    # into the band (see band_rim's ``claimed`` and ``crossed``).
                    own_c = [None if e == t or not (removed[e] | taken[e]).any() else band_share(
                        _matched_lab(rgb[e], stats, e, t, params), layer_c, blade_c) for e in range(n)]
                    steps_kept.band_claimed = [None if c is None else _band_claimed(c, blades[e], removed[e], taken[e])
                                               for e, c in enumerate(own_c)]
        contrast = [None] * n

        def contrast_of(e, labs=labs, steps_kept=steps_kept):
            return _contrast_map(labs[t], labs[e], steps_kept, e)

        report(step / steps, f"layer {name}: masks")
        delta_s = colour_delta(colour[t], user, blades[t], lam, tr_iou, snapped is not None)

        def induced(e, user=user, snapped=snapped, residual=residual, labs=labs, own=own, steps_kept=steps_kept,
                    combined=combined, delta=delta, tr_iou=tr_iou, colour=colour, reach=band_reach,
                    delta_s=delta_s):
            m, c = _exemplar_mask(steps_kept, e, combined[e], delta, tr_iou, taken[e], contrast_of,
                                  colour_e=colour[e], band_delta=reach, delta_s=delta_s)
            gone = m if snapped is None or e == t else _ridge_extension(residual, blades, t, e, user, m, stats, params,
                                                                        labs=labs, direction=own[e])
            if e == t and steps_kept.band_coloured is not None:
                # The training leaf keeps the user's band; its removal takes the rim of the band's colour the
                # user's strokes left (it stayed in the residual, a background of new leaves).
                gone = band_rim(m, steps_kept.band_coloured[t], blades[t] & ~taken[t], steps_kept.band_reach)
            return m, c, gone

        for e, (m, contrast[e], gone) in enumerate(thread_map(induced, range(n))):
            report(step / steps, f"layer {name}: residual of exemplar {e + 1}/{n}")
            step += 1
            masks.append(m)
            moved = m & taken[e]
            if moved.any():
                # Marks given back by their shape (:func:`_claims`) leave the layers above.
                for above in out:
                    above.masks[e] = above.masks[e] & ~moved
            taken[e] = taken[e] | m
            removed[e] = removed[e] | (np.asarray(gone, bool) & ~m)
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
        steps_kept.liberal = {k: v for k, v in liberal_tried.items() if v is not None} or None
        dist_kept = DistanceMaps(reg_user)
        above_colours.append(np.median(labs[t][user], axis=0))
        out.append(LayerInduction(name, lam, overlap, delta, tr_iou, masks, colour_kept,
                                  CombinedMaps(lam, colour_kept, dist_kept, eps_list),
                                  reg_user, dist_kept, eps_list, n_px, snapped=snapped,
                                  contrast=contrast if any(c is not None for c in contrast) else None,
                                  centred=centred, steps=steps_kept))
        step += 1
    report(1.0, "induction done")
    return out, residuals, space


#: A scattered layer's edges and the marks the layers above took (:func:`induce`) are decided by the
#: pixels' own colour only where that colour alone reproduces the user's layer on the training leaf at
#: least this well (IoU of :func:`~branchnb.leaves.induction_scatter.layer_coloured` with it).
MARKS_SINGLED = 0.5

#: ... read on the training leaf's pixels farther than this (px, 4-connected: the removal's growth) from
#: what the layers above took, when at least :data:`MARKS_CLEAR_MIN` of the user's mark pixels lie there
#: (:func:`_clear_of_above`; 96 px spots: 4-8 of 9-25 pixels, IoU of colour alone there 0.57-0.89).
MARKS_CLEAR = 1
#: See :data:`MARKS_CLEAR`.
MARKS_CLEAR_MIN = 4


def _clear_of_above(user, blade, taken) -> np.ndarray:
    """The training leaf's blade away from what the layers above took, where its marks' colour is read.

    The training leaf's scattered layer is read on the residual whose removal of
    the layers above grew their mask by a pixel (its ``delta``, see
    :func:`induce`): the marks' pixels beside a vein are filled with blade
    colour there. On small leaves, whose 1.5-2 px veins lie every few px,
    that is most of a spot (procedural families at 96 px: 11-20 of 9-25 spot
    pixels within a pixel of a vein), so the marks' median colour moved
    towards the blade's and colour alone reproduced the user's marks with
    IoU 0.21-0.43 (:data:`MARKS_SINGLED` 0.5): their edges were never
    decided by colour. Away from the layers above: 0.57-1.0 at 96 px (9-25
    spot pixels), 0.85-0.92 at 128 px, lobed 160 px 0.78 -> 0.96.
    The whole blade when fewer than :data:`MARKS_CLEAR_MIN` mark pixels lie
    there. Beyond the paper.
    """
    away = blade & ~_binary_dilation(taken, iterations=MARKS_CLEAR)
    return away if np.count_nonzero(user & away) >= MARKS_CLEAR_MIN else np.asarray(blade, bool)


def _iou(a, b) -> float:
    return float(np.count_nonzero(a & b)) / max(float(np.count_nonzero(a | b)), 1.0)


def _claims(before, e, *, t, taken, stats, params, space, own_px, cdf, n_px, blades, combined, colour):
    """A scattered layer's ``D`` on exemplar ``e`` read on ``before[e]``, the residual the layers above
    were read on, where they took it (a one-map :class:`~branchnb.leaves.stored_maps.BoxedMaps`, ``inf``
    elsewhere; None on the training leaf and where they took nothing), for
    :func:`~branchnb.leaves.induction_scatter.reclaim_marks`."""
    if e == t or not taken[e].any():
        return None
    q = _quantise_lab(_matched_lab(before[e], stats, e, t, params), space)
    s = colour_similarity(q, blades[e], _own_cdf(q, own_px[e], cdf, space.bins), n_px,
                          weights=space.weights if params.lab_units else None)
    # D = lambda F + S: the same spatial part, the colour term read before the removal. Only what was
    # taken is read (:func:`~branchnb.leaves.induction_scatter.reclaim_marks`): kept on its box.
    where = taken[e] & blades[e]
    d = np.where(where, np.asarray(combined[e]) - np.asarray(colour[e]) + s, np.inf).astype(np.float32)
    return BoxedMaps([d], [where], np.inf)


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
