"""The step from a layer's ``D`` to its induced mask on each exemplar, one code path for
:func:`~branchnb.leaves.analysis_induce.induce` (so :meth:`~branchnb.leaves.analysis.LeafAnalysis.reinduce`)
and the slider preview :meth:`~branchnb.leaves.analysis.LeafAnalysis.retune`: ``{D < delta}`` with the
snapped paths (:func:`~branchnb.leaves.analysis_combine._induced`), the exemplar's own ``delta`` beside
its own layer pixels, the contrast trim, and a thin layer's outline / ink-zone / hole-rim / speck trimming
(:func:`~branchnb.leaves.analysis_trim._trimmed`). The preview skipped the last three and the own
``delta``: on the sample maples (training leaf 01, ``liberal_threshold=0.3``) it showed 242 and 434 vein
pixels the applied induction did not give."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..core.morphology import _binary_dilation


@dataclass
class _MaskSteps:
    """What a layer's induction found besides ``D`` and ``delta``, kept to make its masks again.

    ``user`` the training layer (pinholes closed), ``blades`` the exemplars' blades, ``t`` the training
    index; for a thin layer (else None / lists of None): ``snapped``/``centred`` the snapped paths,
    ``own`` each exemplar's own contrast direction, ``own_px``/``ridge_px`` its own layer pixels,
    ``zones``/``rims`` its ink outline zone and hole rims, ``outline_in_layer``/``inked_outline`` the
    training leaf's outline flags (:func:`~branchnb.leaves.analysis_trim._trimmed`); ``colours`` the
    colour terms ``S_e`` of every neighbourhood the induction tried (side -> maps, in its order);
    ``claims`` a scattered layer's ``D`` per exemplar read before the layers above were removed, where
    they took it (one-map :class:`~branchnb.leaves.stored_maps.BoxedMaps`; None where nothing was
    taken), for the marks they took (:func:`~branchnb.leaves.induction_scatter.reclaim_marks`);
    ``coloured`` its pixels of the layer's colour per exemplar, deciding the marks' edges
    (:func:`~branchnb.leaves.induction_scatter.refine_edges`);
    ``band`` whether the layer is a band along the outline (:func:`~branchnb.leaves.margin_band.outline_region`);
    ``liberal`` per neighbourhood the colour terms its liberal layers were read on where an exemplar's
    own colours stood in (:func:`~branchnb.leaves.analysis_combine.unmatched_liberal`; None: none did);
    ``band_coloured``/``band_reach`` a band's pixels of its colour per exemplar and how far from the
    band they join it (:func:`~branchnb.leaves.margin_band.band_rim`; the training leaf's for its removal only);
    ``band_claimed`` per exemplar the pixels of the band's colour (in its own pixels) the removal of a
    layer above took outside that layer's mask, and those the layers above took, which the band takes
    back where they join it or lie across it (``claimed``/``crossed`` of
    :func:`~branchnb.leaves.margin_band.band_rim`; None: none);
    ``crossing`` the share of the training leaf's outline band its layer covers
    (:func:`~branchnb.leaves.analysis_trim.band_crossing`; None: not read yet).
    """

    user: np.ndarray
    blades: list
    t: int
    snapped: list | None
    centred: list | None
    own: list
    own_px: list
    ridge_px: list
    zones: list
    rims: list
    outline_in_layer: bool
    inked_outline: bool
    colours: dict | None = None
    claims: list | None = None
    coloured: list | None = None
    band: bool = False
    liberal: dict | None = None
    band_coloured: list | None = None
    band_reach: int = 0
    band_claimed: list | None = None
    crossing: float | None = None


#: An exemplar without its own colour model chooses its own ``delta`` against its own ridge pixels
#: (:func:`_exemplar_mask`): 2 (default) what that adds is trimmed by contrast, 1 the whole mask is
#: (worse at 400 px), 0 (as before leaves89) the training leaf's ``delta`` alone there.
_RIDGE_DELTA = 2

#: The own ``delta`` at the ridge pixels is taken only up to this many times the training leaf's:
#: procedural leaves' veins raised it 1.03-1.28x (4 kinds, 160-400 px, 11 exemplars); ridges that
#: are no layer 2.4x (a plain-fill drawn maple's ink outline, its veins not drawn) and 6.2x (a blade
#: with its veins painted out: noise ridges).
RIDGE_RAISE_MAX = 2.0


def _contrast_map(lab_t, lab_e, steps: _MaskSteps, e: int) -> np.ndarray:
    """Exemplar ``e``'s high-pass colour along its layer's contrast direction (the contrast trim's map)."""
    from .induction import layer_width
    from .own_contrast import high_pass
    from .snapping import contrast_direction
    d = steps.own[e] if steps.own[e] is not None else contrast_direction(lab_t, steps.user, steps.blades[steps.t])
    d = np.asarray(d, np.float64)
    return (high_pass(lab_e, steps.blades[e], layer_width(steps.user) + 1.0) @ (d / np.linalg.norm(d))).astype(
        np.float32)


def _exemplar_mask(steps: _MaskSteps, e: int, combined_e, delta: float, tr_iou: float, taken_e, contrast_of,
                   colour_e=None, band_delta: float | None = None, delta_s: float | None = None):
    """The induced layer on exemplar ``e`` and the contrast map it was trimmed by (or None).

    ``combined_e`` its ``D``, ``delta`` and ``tr_iou`` the layer's threshold and training overlap,
    ``taken_e`` what the layers above took there, ``contrast_of(e)`` the contrast map when needed
    (:func:`_contrast_map`; computed only then); ``colour_e`` its colour term ``S_e`` and ``band_delta``
    the training leaf's threshold on it, for a band along the outline
    (:func:`~branchnb.leaves.margin_band.band_extent`, :func:`~branchnb.leaves.margin_band.band_threshold`);
    ``delta_s`` a thin layer's training threshold of ``S`` alone, for an exemplar whose ``D`` takes the
    blade round the layer (:func:`~branchnb.leaves.analysis_combine.colour_alone`).

    Notes
    -----
    Beyond the paper (issue 22, leaves89): the paper's ``delta`` is chosen on the training leaf, and an
    exemplar whose blade matched onto the training leaf's statistics lifts its veins' colour term above
    it keeps only its midrib and the snapped paths (procedural trilobed 192 px, seed 3, training leaf 2:
    exemplar 0's veins at median ``S`` 0.127 against 0.086 on the training leaf, ``delta`` 0.145; vein IoU
    0.43, a lobe's lateral and most secondaries lost). An exemplar read with the training colour model
    (``own_px`` None) now chooses its own ``delta`` (:func:`~branchnb.leaves.analysis_own._own_delta`,
    never below the training leaf's) against its own ridge pixels (``ridge_px``, there 0.997 on true
    veins, 0.82 of them), applied next to them only, and what that adds is trimmed by contrast as an
    exemplar with its own colour model is (there 0.43 -> 0.74). Measured with ``python -m
    branchnb.leaves._measure_secondary`` (4 kinds, 192 / 256 / 400 px, seed 0, each of 3 leaves as the
    training leaf, simulated scribbles; 68 exemplars): vein IoU mean 0.775 -> 0.805, min 0.633 -> 0.721,
    under 0.7 4 -> 0, none lower by 0.001; spots 0.927 either way. Trimming the whole raised mask instead
    (``_RIDGE_DELTA`` 1; 234 exemplars, seeds 0-3): mean 0.767 -> 0.804, under 0.7 22 -> 0, but 400 px
    veins lost width (trilobed 400 px mean 0.808 -> 0.785, one exemplar 0.884 -> 0.779).
    Where the exemplar's ridge pixels are no layer it keeps the training leaf's ``delta`` (leaves93;
    measured on the exemplar itself): where an ink outline zone was found on it (a drawn leaf: its
    ridges hold its outline, and what the raise added drew the removal's ridge extension onto the ink,
    54 ink pixels left inside a drawn lobed leaf's background), and where its own ``delta`` would be over
    :data:`RIDGE_RAISE_MAX` times the training leaf's (procedural veins 1.03-1.28x; a blade with its
    veins painted out 6.2x, its noise ridges made the layer structural; a plain-fill drawn maple's ink
    outline 2.4x). On by default since leaves93: ``_measure_secondary`` seed 0 (4 kinds, 192 / 256 /
    400 px, each leaf as the training leaf; 68 exemplars): vein IoU mean 0.773 -> 0.805, min 0.633 ->
    0.721, under 0.7 5 -> 0, none lower by 0.001, spots within 0.008; ``_measure_unseen`` willow /
    cordate / oak 400 px within 0.009; ``_measure_drawn`` clip art (10 cases): the same masks.
    """
    from .analysis_combine import COLOUR_RELIABLE, _induced, _over_induced, colour_alone
    from .analysis_own import _own_delta
    from .analysis_trim import _trimmed, band_crossing
    from .own_contrast import trim_by_contrast, without_blobs
    s, t = steps, steps.t
    if e == t:
        return s.user.copy(), None
    blade = s.blades[e]
    if s.band and colour_e is not None and band_delta is not None:
        from .margin_band import band_extent, band_rim
        m = _induced(combined_e, delta, tr_iou, s.snapped, e, blade, taken_e, centred=s.centred)
        m = band_extent(m, colour_e, band_delta, blade & ~taken_e)
        if s.band_coloured is not None and s.band_coloured[e] is not None:
            claimed, crossed = s.band_claimed[e] if s.band_claimed is not None and s.band_claimed[e] is not None \
                else (None, None)
            m = band_rim(m, s.band_coloured[e], blade & ~taken_e, s.band_reach, claimed=claimed, crossed=crossed)
        from .margin_band import band_holes
        return band_holes(m, blade & ~taken_e), None
    if s.snapped is not None:
        combined_e, delta = colour_alone(combined_e, delta, colour_e, delta_s, blade, s.user, s.blades[t])
    over = s.snapped is not None and _over_induced(combined_e, delta, blade, s.user, s.blades[t])
    m = _induced(combined_e, delta, tr_iou, s.snapped, e, blade, taken_e, centred=s.centred, over=over)
    # Only where the exemplar's layer has its own colour model (re-chosen
    # on same-coloured leaves too, whenever the training delta found
    # under half of the exemplar's ridge pixels, a lobed leaf's spots
    # went 0.70 -> 0.38 IoU after the wider vein removal).
    if over and s.zones[e] is not None and s.ridge_px[e] is not None and s.snapped is not None \
            and s.snapped[e] is not None:
        # The snapped paths carry the training layer's main structure only: the short side veins
        # it left are among the exemplar's own layer pixels (its ridges of the layer's contrast near
        # the carried layer). Those joined to the paths are taken (beyond the paper), on drawn leaves
        # (an ink outline zone found: on the grass photos the parallel veins' runs fell 0.30 -> 0.29); the ink outline
        # they reach goes with the outline trimming below (cut at the ink zone instead, the veins'
        # last few px before the margin went too: drawn maple 640 px recall 0.89 against 0.94).
        own = s.ridge_px[e] & blade & ~taken_e
        lab, _ = ndi.label(own | m, structure=np.ones((3, 3), bool))
        keep = np.unique(lab[m])
        m = m | (own & np.isin(lab, keep[keep > 0]))
    # An exemplar read with the training colour model chooses its own delta against its own ridge
    # pixels (see Notes).
    own_px = s.own_px[e] if s.own_px[e] is not None or _RIDGE_DELTA == 0 or s.zones[e] is not None \
        else s.ridge_px[e]
    d_e = _own_delta(combined_e, delta, own_px, blade)
    if s.own_px[e] is None and d_e > RIDGE_RAISE_MAX * delta:
        d_e = delta
    raised = d_e > delta and not over
    before = m
    if raised:
        # Beyond the training leaf's delta only next to the exemplar's own layer pixels: its ridges of
        # the layer's contrast and the snapped paths grown to its own veins' width. Next to the ridges
        # alone, a pale midrib in a pale centre beside a dark margin band (whose matched colours put it
        # just above the training delta, 0.236 against 0.155, under this exemplar's own 0.243) lost
        # its lower half: 256 px dark band, seeds 40-43, vein IoU exemplar 3 0.548 -> 0.892, exemplar
        # 1 0.491 -> 0.533; 192 px 0.325 / 0.629 / 0.151 -> 0.554 / 0.700 / 0.255; cream bands and
        # 400 px unchanged (leaves88).
        own_e = s.ridge_px[e]
        if own_e is not None and s.centred is not None and s.centred[e] is not None:
            own_e = own_e | s.centred[e]
        near = _binary_dilation(own_e, iterations=1)
        m = m | _induced(np.where(near, combined_e, np.inf), d_e, tr_iou, s.snapped, e, blade, taken_e,
                         centred=s.centred)
    contrast = None
    if s.snapped is not None and tr_iou >= COLOUR_RELIABLE and not over and (s.own_px[e] is not None or raised):
        # Where {D < delta} is induced (the snapped paths alone are drawn to width already:
        # trimmed, the sample maples' induced veins lost half their width, IoU 0.64 -> 0.43).
        contrast = contrast_of(e)
        trimmed = trim_by_contrast(without_blobs(m, s.user, s.blades[t], blade), contrast)
        # Read with the training colour model, only what the own delta added is trimmed: the whole
        # mask trimmed lost width on wider veins (trilobed 400 px: 0.88 -> 0.78, see Notes).
        m = trimmed if s.own_px[e] is not None or _RIDGE_DELTA != 2 else before | (trimmed & ~before)
    if s.snapped is not None:
        if s.crossing is None:
            s.crossing = band_crossing(s.blades[t], s.user)
        m = _trimmed(m, blade, s.user, s.snapped[e], s.zones[e], s.rims[e], outline_in_layer=s.outline_in_layer,
                     inked_outline=s.inked_outline, crossing=s.crossing)
    if s.coloured is not None and s.coloured[e] is not None:
        from .induction_scatter import refine_edges
        m = refine_edges(m, s.coloured[e], blade & ~taken_e)
    if s.claims is not None and s.claims[e] is not None:
        # Marks the layers above took by their colour come back where their shape is a mark's.
        from .induction_scatter import reclaim_marks
        m = m | reclaim_marks((np.asarray(s.claims[e][0]) < delta) & blade, m, taken_e, s.user)
    return m, contrast
