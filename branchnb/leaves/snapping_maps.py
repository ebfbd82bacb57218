"""An exemplar's ridge evidence for the snapping, with its hole rims and ink outline masked out (beyond the paper).

Step 2 of :mod:`branchnb.leaves.snapping` per exemplar: the ridge evidence ``E_e`` at the layer's width
(:func:`~branchnb.leaves.snapping_evidence.ridge_evidence`), its oriented Hessian
(:func:`~branchnb.leaves.snapping_fit.ridge_hessian`) and the one-pixel evidence the paths follow, each
zero where a ridge is the blade's edge and not a vein: a hole's rim (a torn or eaten patch,
:func:`~branchnb.leaves.snapping_stray._hole_rim`) and a drawn leaf's ink outline
(:func:`~branchnb.leaves.analysis_outline._ink_zone`).
"""

from __future__ import annotations

import numpy as np

from .snapping_carry import _unbox
from .snapping_evidence import ridge_evidence
from .snapping_fit import _oriented_maps, ridge_hessian
from .snapping_stray import _hole_rim
from .snapping_width import vein_centre

#: Pixels around a hole in the blade with no ridge evidence (0: off).
HOLE_RIM = 2

#: Largest share of the blade the holes' rims may cover for them to take no evidence; past it the
#: holes are texture, not damage (:func:`~branchnb.leaves.snapping_stray._hole_rim`).
HOLE_SHARE = 0.1

#: Reach (in layer widths, 3 px at least) of a hole's one-sided rim: ridge pixels with the hole on one
#: side (:func:`~branchnb.leaves.snapping_stray._one_sided_rim`), no vein of the layer is induced on
#: them outside the snapped paths (``rims``; 0: the rim of HOLE_RIM px only).
HOLE_REACH = 2.0

#: ... and at least this share of the leaf size (``sqrt`` of the blade's area): a torn patch's browned
#: rim widens with the leaf (procedural rims of 0.025 leaf sizes: 4-5 px at 320 px, 9 px at 640 px
#: reached past 2 layer widths and their outer half was induced as vein, ``_measure_holes``).
HOLE_REACH_SHARE = 0.04


def _exemplar_maps(lab, b, direction, width: float, line_frac: float, *, oriented: bool, fit: bool,
                   centred: bool, outline=None, box=None, rims=None, e: int = 0):
    """The snapping's maps of one exemplar on its blade's box: ``(ev, hess, pev, centre, omaps)``.

    ``ev`` the ridge evidence at the layer's ``width`` (straight segments ``line_frac`` of the leaf
    size), ``hess`` its oriented Hessian (None unless ``oriented``), ``pev`` the one-pixel evidence the
    paths follow, ``centre`` the vein centres (:func:`~branchnb.leaves.snapping_width.vein_centre`,
    only with ``centred``), ``omaps`` the blurred oriented maps the fits and traces share (only with
    ``fit`` and ``oriented``). All are 0 on the hole rims and on ``outline`` (this box's part of a
    drawn leaf's ink outline, or None). With ``rims`` (a list), ``rims[e]`` is set to the hole rims
    with their one-sided reach (:data:`HOLE_REACH`), on the full canvas ``box = (shape, y0, x0)``.
    """
    ev = ridge_evidence(lab, b, direction, width, line_frac * np.sqrt(float(b.sum())))
    hess = ridge_hessian(lab, b, direction, width) if oriented else None
    # A hole's rim (a torn or eaten patch) is an edge, not a vein.
    rim = _hole_rim(b, HOLE_RIM, HOLE_SHARE)
    if rims is not None:
        # The rims no vein is induced on (the one-sided rim too, up to HOLE_REACH layer widths).
        shape, y0, x0 = box
        rims[e] = _unbox(_hole_rim(b, HOLE_RIM, HOLE_SHARE, hessian=hess,
                                   reach=max(3.0, HOLE_REACH * width, HOLE_REACH_SHARE * np.sqrt(float(b.sum())))
                                   if HOLE_REACH > 0 else 0.0),
                         shape, y0, x0)
    if outline is not None:
        # A drawn leaf's ink outline is the blade's edge drawn, not a vein.
        rim = rim | outline
    if rim.any():
        ev = np.where(rim, 0.0, ev).astype(np.float32)
        if hess is not None:
            hess = np.where(rim[None], 0.0, hess).astype(np.float32)
    # The path itself on the finest ridge response (one-pixel scale, no
    # line averaging): the centre of a 3 px vein, not of its blurred halo.
    pev = ridge_evidence(lab, b, direction, 1.0)
    centre = vein_centre(lab, b, direction, width) if centred else None
    if rim.any():
        pev = np.where(rim, 0.0, pev).astype(np.float32)
    omaps = None
    if fit and hess is not None:
        # The fits, the traces and the basal search score poses on the same oriented maps: made once.
        import cv2
        evb = cv2.GaussianBlur(np.where(b, ev, 0.0).astype(np.float32), (0, 0), 0.7)
        omaps = _oriented_maps(evb, hess)
    return ev, hess, pev, centre, omaps
