"""Stopping rules of the growth loop: the total-length cap of a synthesis and the winding limit of a branch.

The coverage stop (space colonization) and the density stop of a step live with the grower
(:meth:`.growth._Grower.global_stop`, :meth:`.growth._Grower.step`); this module holds the limits
they are measured against that come from the example: :func:`length_cap` (the length per area of
the example, beyond the paper's fixed total length) and :func:`winding_limit` (no spirals). Split
from :mod:`branchnb.branching.growth` (issue 23, branching46); ``growth`` re-exports every name.
"""

from __future__ import annotations

import numpy as np

from ..core.structure import Structure
from .domains import _frame
from .model import StructureModel
from .params import SynthesisParams

__all__ = ["FILL_LENGTH_FACTOR", "LENGTH_BOUND", "LENGTH_FACTOR", "LENGTH_FLOOR", "WIND_BOUNDS_DEG", "WIND_FACTOR",
           "example_length", "length_cap", "winding", "winding_limit"]

#: Auto length cap (``max_total_length = 0``): this x the example's total length per domain area,
#: while the forest grows (the coverage stop usually ends growth first, at 0.95-1.2 x) ...
LENGTH_FACTOR = 1.15
#: ... and at most this x once holes the example does not have are filled (``_Filling._fill_far``),
#: so the output's length per area stays within 1.3 x the example's. It was 1.3 and 2.0: a 1000 px
#: retina ended at 1.41-1.43 x, a 1000 px lightning at 1.21-1.50 x; at 1.15 and 1.3 the lightning
#: ends at 1.21-1.30 x with its far share 1.11-1.40 x the example's (3 seeds; issue 23, branching19).
FILL_LENGTH_FACTOR = 1.3
#: Safety bound of the auto length cap against runaway growth: branch length (px) per domain pixel
#: (0.25: branches 4 px apart all over the domain), and never below the former fixed 20000 px.
LENGTH_BOUND = 0.25
LENGTH_FLOOR = 20000.0


def example_length(model: StructureModel) -> float:
    """The example's total length (pixels), computed once per model.

    A 1000 px crack example has 7.7 k branches: 0.3 s per sum, once per
    synthesized branch, so the sum is cached on the model.

    Parameters
    ----------
    model : StructureModel
        The fitted model whose example is measured.

    Returns
    -------
    float
        Sum of the example's branch lengths in pixels.
    """
    key = (id(model.example), len(model.example.branches))
    cached = model.__dict__.get("_example_length")
    if cached is None or cached[0] != key:
        cached = (key, float(model.example.total_length))
        model.__dict__["_example_length"] = cached
    return cached[1]


def length_cap(model: StructureModel, params: SynthesisParams, shape, domain: np.ndarray | None,
               factor: float | None = None) -> float:
    """The total-length stop of a synthesis (pixels).

    ``params.max_total_length`` when set (> 0); else (auto, beyond the
    paper) the example's total length per area of its domain times the
    output domain's area, times :data:`LENGTH_FACTOR`: a 1000 px retina or
    cracked mud needs 1-2.5 x the former fixed 20000 px to reach its
    example's density, a 250 px one a tenth of it. The output's length per
    area thus stays within :data:`FILL_LENGTH_FACTOR` = 1.3 x the example's, like its other statistics
    (the coverage stop ends most syntheses before, at 0.95-1.2 x). Bounded by
    ``max(LENGTH_FLOOR, LENGTH_BOUND x domain pixels)`` against runaway
    growth.

    Parameters
    ----------
    model : StructureModel
        The fitted example (its resampled ``example`` and ``domain``).
    params : ~branchnb.branching.params.SynthesisParams
        Synthesis parameters (``max_total_length``).
    shape : (H, W)
        Output frame.
    domain : (H, W) bool ndarray or None
        Output domain (None: the whole frame).
    factor : float, optional
        Multiple of the example's length per area; default
        :data:`LENGTH_FACTOR` (:data:`FILL_LENGTH_FACTOR` while holes are
        filled).

    Returns
    -------
    float
        The cap (pixels), > 0.

    Examples
    --------
    >>> from branchnb.branching import fit_model
    >>> from branchnb.core.structure import Branch
    >>> ex = Structure([Branch(np.c_[np.linspace(2, 97, 96), np.full(96, 50.0)], 2.0)], image_shape=(100, 100))
    >>> m = fit_model(ex)
    >>> round(length_cap(m, SynthesisParams(), (200, 200), None) / m.example.total_length, 1)   # 4 x the area
    4.6
    """
    if params.max_total_length > 0:
        return float(params.max_total_length)
    h, w = int(shape[0]), int(shape[1])
    area = float(np.count_nonzero(domain)) if domain is not None else float(h * w)
    if model.region is not None:
        ex_area = float(np.count_nonzero(model.region))
    else:
        fh, fw = _frame(model.source)
        ex_area = float(fh * fw)
    f = LENGTH_FACTOR if factor is None else float(factor)
    cap = f * example_length(model) * area / max(ex_area, 1.0)
    return float(min(max(cap, 1.0), max(LENGTH_FLOOR, LENGTH_BOUND * area)))


#: Largest net turn (radians) of any piece of a synthesized branch, as a multiple of the example's
#: largest (:func:`winding_limit`): a branch may wind like the example's most winding one, a little more,
#: never round in a spiral.
WIND_FACTOR = 1.25
#: Bounds of the winding limit (degrees): the floor lets a fairly straight example's branches still
#: turn (a drawn map's rivers wind 120-200 degrees), the ceiling keeps every branch off a full turn
#: (a 1000 px river map grew a spiral with nested children, a 1000 px lightning a 650 degree curl;
#: issue 23).
WIND_BOUNDS_DEG = (150.0, 300.0)


def winding(angles) -> float:
    """Largest net turn (radians) of any piece of a branch: ``ptp(cumsum(alpha))``.

    Parameters
    ----------
    angles : array_like
        The branch's turning angles alpha (radians), in order.

    Returns
    -------
    float
        ``max - min`` of the running heading (0 for fewer than 1 angle); a
        spiral's is above ``2 pi``.

    Examples
    --------
    >>> round(float(np.degrees(winding(np.radians([30.0, 30.0, -90.0, 10.0])))))
    90
    """
    c = np.cumsum(np.r_[0.0, np.asarray(angles, np.float64).ravel()])
    return float(np.ptp(c))


def winding_limit(example: Structure) -> float:
    """The winding limit of synthesized branches (radians): :data:`WIND_FACTOR` x the example's most
    winding branch, within :data:`WIND_BOUNDS_DEG`.

    Parameters
    ----------
    example : Structure
        The extracted example; its branches' windings (see :func:`winding`) set the limit.

    Returns
    -------
    float
        The largest range of headings (radians) a synthesized branch may sweep.
    """
    w = max((winding(b.angles()) for b in example.branches if len(b.points) > 2), default=0.0)
    lo, hi = np.radians(WIND_BOUNDS_DEG)
    return float(np.clip(WIND_FACTOR * w, lo, hi))
