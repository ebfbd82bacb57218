"""A thin layer snapped onto each exemplar's own ridges for the induction (:func:`_snapped`), and which
layers are thin (:func:`thin_width`). The snapping itself: :mod:`branchnb.leaves.snapping`."""

from __future__ import annotations

import numpy as np

from ..core.threads import thread_map
from .analysis_outline import _ink_zone
from .margin_band import outline_region


def _snapped(residual, blades, t, user, registrations, stats, tolerance, params, *, labs=None, rgb=None):
    """The thin layer ``user`` snapped onto each exemplar's own ridges, and each exemplar's own contrast.

    Returns ``(masks, own, pixels, centred, zones, rims)``: ``masks`` None (not thin / off) or one mask
    per exemplar (None on the training leaf), ``centred`` the same paths grown to each
    exemplar's own vein (:func:`~branchnb.leaves.snapping_width._grow_to_width`); ``own[e]`` the contrast
    direction of exemplar ``e``'s own layer where it differs from the
    training leaf's (:func:`branchnb.leaves.own_contrast.exemplar_direction`), else None;
    ``zones[e]`` a drawn exemplar's ink outline zone and its depth (:func:`_ink_zone`, from
    its colours ``rgb[e]``; given None: the user's layer holds the outline), else None; ``rims[e]``
    the exemplar's hole rims (:func:`~branchnb.leaves.snapping_stray._hole_rim`), no vein
    (:data:`~branchnb.leaves.analysis_trim.RIM_TRIM`).
    """
    from .analysis_combine import warp_mask
    from .analysis_own import _matched_lab
    from .induction import layer_width
    from .own_contrast import exemplar_direction
    from .snapping import contrast_direction, is_thin_layer, snap_to_exemplars
    own = [None] * len(blades)
    pixels = [None] * len(blades)
    zones = [None] * len(blades)
    if not params.snap or not is_thin_layer(user, max_width=thin_width(blades[t], user)) or \
            outline_region(blades[t], user):
        # A band along the outline (a variegated margin, 5-7 px on a 160-px leaf) is a region, no vein:
        # snapped as thin, it was laid onto the edge of the blade's centre beside it (induced IoU 0.01-0.17).
        return None, own, pixels, None, zones, [None] * len(blades)
    if labs is None:
        labs = [_matched_lab(r, stats, e, t, params) for e, r in enumerate(residual)]
    d_t = contrast_direction(labs[t], user, blades[t])
    width = max(1.0, layer_width(user))
    if rgb is not None:
        for e in range(len(blades)):
            if e != t:
                zone, depth = _ink_zone(rgb[e], blades[e], width)
                zones[e] = (zone, depth) if zone.any() else None
    radius = max(3.0, 1.5 * float(tolerance), float(params.snap_radius) * width)

    def direction_of(e):
        prior = warp_mask(registrations[e], user, to_training=False, level=0.25) & blades[e]
        return exemplar_direction(labs[e], blades[e], prior, width, d_t, radius=radius, return_pixels=True)

    others = [e for e in range(len(blades)) if e != t]
    for e, (d, took, pix) in zip(others, thread_map(direction_of, others)):
        own[e] = d if took else None
        pixels[e] = pix
    rims = [None] * len(blades)
    masks, _, centred = snap_to_exemplars(labs, blades, t, user, registrations, tolerance=tolerance,
                                          radius_widths=params.snap_radius, directions=own, return_centred=True,
                                          outlines=[None if z is None else z[0] for z in zones], rims=rims)
    return masks, own, pixels, centred, zones, rims


#: A layer of curves at most this share of the leaf size (``sqrt`` of the blade's area) wide is thin
#: (snapped), 6 px at least (:func:`branchnb.leaves.snapping.is_thin_layer`'s pixel width does not scale).
THIN_SHARE = 0.04


def thin_width(blade, user=None) -> float:
    """The widest median curve width (px) of a thin layer on a leaf with this blade: :data:`THIN_SHARE`.

    A sketched maple's ink veins at 360 px are 6.2 px wide (0.03 of the leaf
    size); at 6 px they were not thin, nothing was snapped and the second
    maple sketch got 1227 of its ~6000 vein pixels (its midrib stayed in
    its residual); taken as thin, 5989. Only for a network: a ``user``
    layer whose skeleton is at least :data:`THIN_NETWORK` leaf sizes long
    in all (a few elongated spots are not; procedural spots at 512-1000 px
    were taken as thin without this); 6 px otherwise.

    Parameters
    ----------
    blade : (H, W) bool ndarray
        The training leaf's blade.
    user : (H, W) bool ndarray, optional
        The layer; None: taken as a network.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> thin_width(np.ones((100, 100), bool)), thin_width(np.ones((400, 400), bool))
    (6.0, 16.0)
    """
    size = float(np.sqrt(np.count_nonzero(blade)))
    if user is not None:
        from skimage.morphology import skeletonize
        if np.count_nonzero(skeletonize(np.asarray(user, bool))) < THIN_NETWORK * size:
            return 6.0
    return max(6.0, THIN_SHARE * size)


#: Least total skeleton length of a layer, in leaf sizes, for :func:`thin_width` to scale.
THIN_NETWORK = 2.0
