"""The training layer's branches placed on one exemplar (steps 3-5 of :mod:`branchnb.leaves.snapping`).

The branches are carried into the exemplar, posed by the template fit from the best of its starts
(:func:`_template_start`), traced from their junction and snapped to the exemplar's ridges by the
path search (:func:`_place_branches`). Beyond the paper.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from .snapping_aim import _reaim_laterals
from .snapping_basal import ANCHOR_MOVE, ANCHOR_REACH, ANCHOR_SHARE, _junction_of
from .snapping_carry import _affine_carry, _moment_carry, carry_points
from .snapping_fit import _fit_each, _fit_template
from .snapping_star import reseat_star
from .snapping_trace import refine_carried, trace_branches


def _template_start(registration, blade_t, b_full, chains, carried, off, ev, b, hess, omaps, *, fit_reach: float,
                    registration_start: float, only_start, anchor, star):
    """The branches posed by the template fit from the best of its starts (None: no start fitted).

    Starts: the affine map nearest the registration, the blades' centroids and sizes alone (a
    registration of outlines can turn the inside of a leaf by tens of degrees: maple 02 -> 03), and the
    registration's own non-rigid carry ``carried`` (unless ``registration_start`` is 0). The better
    fit wins; the registration's own only by the margin ``registration_start``
    (:data:`~branchnb.leaves.snapping.REGISTRATION_START`); ``only_start`` forces one
    (:data:`~branchnb.leaves.snapping._ONLY_START`). With an ``anchor`` (the training junction and the
    exemplar's petiole base) the fit held at the petiole may replace it
    (:data:`~branchnb.leaves.snapping_basal.ANCHOR_SHARE`).
    """
    best = None
    starts = [[c - off for c in _affine_carry(registration, blade_t, chains)],
              [c - off for c in _moment_carry(blade_t, b_full, chains)]]
    if registration_start > 0:
        starts.append(carried)
    # The starts compete on their template scores; only the winner's branches are then posed one by one
    # (the per-branch stage was a third of the fits' time; the same poses as fitting every start fully).
    for k, start in enumerate(starts):
        if only_start is not None and k != only_start:
            continue
        fit = _fit_template(start, ev, b, reach=fit_reach * np.sqrt(float(b.sum())), hessian=hess, maps=omaps)
        score = fit.score / registration_start if k == 2 else fit.score
        if best is None or score > best[1]:
            best = (fit, score)
    if best is None:
        return None
    best = (_fit_each(best[0]), best[1])
    if anchor is not None and ANCHOR_SHARE > 0 and only_start is None:
        # The template's junction held at the exemplar's own petiole base.
        jc = _affine_carry(registration, blade_t, [anchor[0][None]])[0][0] - off
        held = [c + (anchor[1] - jc) for c in starts[0]]
        fit = _fit_template(held, ev, b, reach=ANCHOR_REACH * np.sqrt(float(b.sum())), hessian=hess, maps=omaps)
        score = fit.score
        if score >= ANCHOR_SHARE * best[1]:
            got = _fit_each(fit)
            # Only where the fit moved the junction away from the petiole (else it is kept).
            moved = np.hypot(*(_junction_of(best[0], star) - _junction_of(got, star)))
            if moved > ANCHOR_MOVE * np.sqrt(float(b.sum())):
                best = (got, score)
    return best[0]


def _place_branches(chains, widths, n_user, registration, blade_t, b_full, off, b, ev, hess, pev, centre, omaps,
                    anchor, star, *, radius: float, width: float, scale: float, scale_e: float, fit: bool,
                    fit_reach: float, trace: bool, trace_kw, refine: bool, min_evidence: float,
                    registration_start: float, only_start):
    """``(mask, kept, centred)`` of the branches carried into one exemplar, fitted, traced and snapped.

    The branches past ``n_user`` are candidates (mirrored branches): each is kept only where it found a
    vein of its own, not one a branch of the user's already took. All on the blade's box (``b``, offset
    ``off``); ``b_full`` is the exemplar's blade on the canvas.
    """
    from .snapping import snap_layer
    carried = [carry_points(registration, c) - off for c in chains]
    reach = max(radius, 0.12 * np.sqrt(float(b.sum())))
    tube = radius
    if fit and chains:
        best = _template_start(registration, blade_t, b_full, chains, carried, off, ev, b, hess, omaps,
                               fit_reach=fit_reach, registration_start=registration_start,
                               only_start=only_start, anchor=anchor, star=star)
        carried = best if best is not None else carried
        tube = max(2.0, 1.5 * width)
        if trace and hess is not None:
            # Two traces may not share a vein: "near a placed branch" spans
            # the vein's own width (3 px on a 3 px vein; a drawn oak's 6 px
            # veins at 480 px took two traces side by side, 4 px apart).
            kw = {"overlap_px": max(3.0, float(np.ceil(width * scale_e)))}
            kw.update(trace_kw or {})
            carried = trace_branches(carried, omaps, b, **kw)
            if star is not None:
                # A star posed one vein slot over (its midrib on a faint ridge beside the exemplar's).
                carried = reseat_star(carried, star, omaps, b, overlap_px=kw["overlap_px"])
                # A lateral carried off its vein (a squeezed side of the leaf) re-aimed by its evidence.
                carried = _reaim_laterals(carried, star, omaps, b, overlap_px=kw["overlap_px"])
    elif refine:
        carried = refine_carried(carried, ev, b, reach=reach)
    sw = [wd * scale for wd in widths]
    got = snap_layer(pev, b, carried[:n_user], sw[:n_user], tube, min_evidence=min_evidence, centre=centre)
    m, k = got[0], got[1]
    mcen = got[2] if centre is not None else m
    if len(carried) > n_user:
        # A candidate (a mirrored branch) is kept only where it found a
        # vein of its own: not one a branch of the user's already took.
        taken = ndi.binary_dilation(m, iterations=max(2, int(np.ceil(max(sw[:n_user], default=1.0)))))
        for c, wd in zip(carried[n_user:], sw[n_user:]):
            gc = snap_layer(pev, b, [c], [wd], tube, min_evidence=min_evidence, centre=centre)
            mc = gc[0]
            if mc.any() and (mc & taken).sum() < 0.5 * mc.sum():
                m = m | mc
                mcen = mcen | (gc[2] if centre is not None else mc)
    return m, k, mcen
