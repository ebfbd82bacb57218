"""A thin layer's induced mask trimmed (beyond the paper): the leaf's outline and ink outline, hole rims,
specks (:func:`_trimmed`), and the matte's pinholes the user's layer keeps (:func:`_pinholes`)."""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.morphology import _binary_dilation
from .analysis_outline import INKED_OUTLINE, _outline_band, _outline_stretches

#: Leave the exemplar's hole rims (:func:`~branchnb.leaves.snapping_stray._hole_rim`, one-sided rims
#: included) out of a thin layer's induced mask.
RIM_TRIM = True


def _pinholes(blade, layer) -> np.ndarray:
    """The blade's holes narrower than the layer (inscribed disc no wider than its width, 3 px at least).

    Matte pinholes and specular dots of a photographed leaf, not its real
    holes (wider). The user's layer keeps its pixels in them: maple_leaf_04's
    hand-traced veins, cut into 3 pieces by its 334 pinholes, as the training
    leaf: induced-vein IoU on maples 01/02/03/05/06 0.68/0.71/0.69/0.70/0.64
    -> 0.77/0.82/0.73/0.76/0.71, but on 07 0.49 -> 0.36 (the whole template's
    junction lands on 07's dark hole rim above its own).
    """
    from .induction import layer_width
    holes = ndi.binary_fill_holes(blade) & ~blade
    if not holes.any() or not layer.any():
        return np.zeros_like(blade)
    lab, n = ndi.label(holes)
    depth = ndi.maximum(ndi.distance_transform_edt(holes), lab, np.arange(1, n + 1))
    half = max(1.5, 0.5 * layer_width(layer & blade))
    return np.isin(lab, np.flatnonzero(np.asarray(depth) <= half) + 1)


#: A thin layer is elongated: an induced part (8-connected) spanning fewer than
#: this many layer widths in both directions is a speck, no vein (:func:`_without_dots`) ...
SPECK_LENGTH = 3.0
#: ... and never fewer than this (px): dots of 1-4 px go at any width.
SPECK_MIN = 5


def _without_dots(m, width: float) -> np.ndarray:
    """A thin layer's induced mask without its isolated dots (beyond the paper).

    The colour term takes any pixel of the layer's colour near the carried
    layer: a speck of mottling or a pinhole's rim beside a vein is induced as
    a dot of vein. A vein is elongated: a part of the mask whose bounding box
    is shorter than ``max(SPECK_MIN, SPECK_LENGTH x width)`` px on both sides
    is no vein and is left out.
    """
    lab, n = ndi.label(m, structure=np.ones((3, 3), bool))
    if n == 0:
        return m
    need = max(SPECK_MIN, int(np.ceil(SPECK_LENGTH * float(width))))
    boxes = ndi.find_objects(lab)
    short = [i + 1 for i, b in enumerate(boxes)
             if b is not None and max(b[0].stop - b[0].start, b[1].stop - b[1].start) < need]
    return m & ~np.isin(lab, short) if short else m


#: Pixels from a hole (besides it) where a rim piece must touch to hug the hole (:func:`_rim_hugging`).
RIM_TOUCH = 2

#: ... of a hole at least this wide (inscribed radius, in leaf sizes): a torn or eaten patch. Small holes'
#: pieces stay (every hole: sample maples 05 / 07 vein IoU 0.80 -> 0.79 / 0.65 -> 0.63, training leaf 01).
RIM_HOLE = 0.03


def _rim_hugging(m, blade, rim) -> np.ndarray:
    """The pieces of ``m`` on the one-sided hole rims ``rim`` that touch the hole: a path hugging it (beyond the paper).

    The snapped paths follow the ridge evidence, and a hole's rim in the
    veins' colour is a ridge with the hole on one side: the paths ran along
    it (``_measure_holes``: of the rim pixels still taken as vein at 320 px,
    up to half lay on snapped paths). A vein running beside a hole has blade
    between itself and the hole (maple 07's lateral, 3 px off its hole's rim); a rim runs on from
    the hole's edge. So a connected piece of ``m & rim`` is a rim when it
    reaches within :data:`RIM_TOUCH` px of a hole. The path is not
    re-routed round the hole: the pieces either side stay as they are.

    >>> import numpy as np
    >>> blade = np.ones((20, 20), bool); blade[8:12, 8:12] = False
    >>> ring = np.zeros_like(blade); ring[6:14, 6:14] = True; ring &= blade
    >>> far = np.zeros_like(blade); far[1, 2:18] = True
    >>> int(_rim_hugging(ring | far, blade, ring | far).sum()), int(ring.sum())
    (48, 48)
    """
    from .snapping_stray import fill_holes
    piece = np.asarray(m, bool) & np.asarray(rim, bool)
    if not piece.any():
        return piece
    b = np.asarray(blade, bool)
    holes = fill_holes(b) & ~b
    hl, nh = ndi.label(holes)
    if nh == 0:
        return np.zeros_like(piece)
    depth = np.asarray(ndi.maximum(ndi.distance_transform_edt(holes), hl, np.arange(1, nh + 1)))
    holes = np.isin(hl, np.flatnonzero(depth >= RIM_HOLE * np.sqrt(float(b.sum()))) + 1)
    touch = _binary_dilation(holes, iterations=RIM_TOUCH) & b
    lab, n = ndi.label(piece, structure=np.ones((3, 3), bool))
    hit = np.unique(lab[touch & piece])
    return np.isin(lab, hit[hit > 0])


def _stalk(blade, user) -> np.ndarray:
    """The blade's petiole when it is no wider than the outline band holds (all band, no inside), else empty.

    Such a stalk is no outline: its whole width is the layer (a procedural
    leaf's petiole is vein). Left in :func:`_outline_band` it made the band's
    share of vein pixels reach :data:`~branchnb.leaves.analysis_outline.INKED_OUTLINE`
    on small leaves and went with the band (elliptic 128 px: 9 % of the
    petiole's true pixels induced).
    """
    from .induction import layer_width
    from .starts import split_petiole
    blade = np.asarray(blade, bool)
    _, pet, base = split_petiole(blade)
    if base is None or not pet.any():
        return np.zeros_like(blade)
    reach = max(2.0, float(np.ceil(layer_width(user)))) if np.asarray(user).any() else 2.0
    if float(ndi.distance_transform_edt(blade)[pet].max()) > reach + 0.5:
        return np.zeros_like(blade)
    return pet


def band_crossing(blade, user) -> float:
    """Share of the training leaf's outline band (its narrow petiole left out) that its own layer covers.

    A thin layer's veins cross the band where they end at the margin; on a
    small leaf (veins 1.5-2 px at any size, a margin a few hundred px long)
    they cover a fair share of it on every exemplar, ink or none: the
    induced veins of procedural elliptic leaves at 128 px covered 0.18-0.28
    of the band, which :data:`~branchnb.leaves.analysis_outline.INKED_OUTLINE`
    (0.2) took for an inked outline, so the vein ends and the petiole went
    (beyond the paper). The training layer's own share is what crossing
    veins cover; :func:`_trimmed` needs ``INKED_OUTLINE`` more than that.

    Parameters
    ----------
    blade : (H, W) bool array_like
        The training leaf's blade.
    user : (H, W) bool array_like
        The user's (thin) layer on it.

    Returns
    -------
    float
        In [0, 1]; 0 for an empty layer.

    Examples
    --------
    >>> import numpy as np
    >>> blade = np.zeros((40, 40), bool); blade[5:35, 5:35] = True
    >>> user = np.zeros_like(blade); user[20, 5:35] = True
    >>> round(band_crossing(blade, user), 3)
    0.018
    """
    user = np.asarray(user, bool)
    if not user.any():
        return 0.0
    band = _outline_band(blade, user) & ~_stalk(blade, user)
    return float((user & band).sum() / max(int(band.sum()), 1))


def _trimmed(m, blade, user, snapped, zone, rim, *, outline_in_layer: bool, inked_outline: bool,
             crossing: float = 0.0) -> np.ndarray:
    """A thin layer's induced mask ``m`` on one exemplar without its outline stretches, hole rims and dots.

    ``blade`` the exemplar's blade, ``user`` the training layer, ``snapped`` the exemplar's snapped
    paths, ``zone`` a drawn exemplar's ink outline zone and its depth
    (:func:`~branchnb.leaves.analysis_outline._ink_zone`, or None), ``rim`` its hole rims (or None);
    ``outline_in_layer``: the user's layer holds the leaf's outline (kept), ``inked_outline``: the
    training leaf's outline is inked (its stretches along the band go); ``crossing``: the share of the
    training leaf's outline band its own layer covers (:func:`band_crossing`), added to
    :data:`~branchnb.leaves.analysis_outline.INKED_OUTLINE` before the whole band goes.
    """
    if not outline_in_layer:
        band = _outline_band(blade, user)
        lam_band = band & ~_stalk(blade, user)
        if (m & lam_band).sum() >= (INKED_OUTLINE + crossing) * max(int(lam_band.sum()), 1):
            m = m & ~lam_band
        elif inked_outline:
            m = m & ~_outline_stretches(m & band, user)
        if zone is not None:
            # A drawn leaf's ink outline (and the strip inside it) taken along the blade's edge.
            m = m & ~_outline_stretches(m & zone[0], user, zone[1])
    if RIM_TRIM and rim is not None:
        # A hole's rim in the layer's colour is no vein: the colour term took 58-99 % of
        # the vein-coloured rims of procedural holes (``_measure_holes``). The snapped
        # paths stay (their ridge evidence placed them; maple 07's lateral runs 3 px from a hole)
        # unless they hug the hole itself (:func:`_rim_hugging`).
        m = m & ~((rim & ~snapped) | _rim_hugging(m | snapped, blade, rim))
    from .induction import layer_width
    return _without_dots(m, layer_width(user))
