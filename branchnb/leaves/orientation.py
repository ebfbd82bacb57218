"""Which exemplars are mirror images of the training leaf (beyond the paper).

Leaves of one kind are drawn and photographed facing either way: an oak
leaf with its petiole to the lower left beside one with it to the lower
right. The paper registers every exemplar to the training leaf with a
non-rigid map that keeps orientation (its thin-plate spline cannot turn a
leaf over, and the inverse warps of synthesis are blended, which a
reflection would break). A mirrored exemplar then registers badly (two
drawn oaks: 27-28 px of outline error) and its induced layers land beside
its own veins. So, before registration, an exemplar whose mirror image fits
the training blade's outline clearly better than itself is turned over
(left-right) on the common canvas; the analysis keeps which were.

The outline chamfer of rigid maps only nominates an exemplar: a leaf
whose lobes differ in size from the training leaf's (procedural lobed,
trilobed, elliptic and fan families) often fits its mirror image's
outline better by this score too (ratios down to 0.42 over 10 seeds x 4
kinds x 160 / 384 px, 7 % of the pairs below :data:`MIRROR_RATIO`), yet
the thin-plate spline bends it onto the training blade as it faces. A
nominated exemplar is registered both ways and turned over only when
the turned one's registered blade overlaps the training blade clearly
better (:func:`turned_over_fits`, :data:`MIRROR_GAIN`).
"""

from __future__ import annotations

import numpy as np

from ..core.image import as_mask
from ..core.metrics import iou

#: Flip when the mirror image's best outline chamfer is at most this share of the unmirrored one's:
#: two drawn oaks facing opposite ways score 0.62-0.65 at 128-640 px, the procedural lobed, trilobed and
#: elliptic families 0.70 and more (sizes 160/384, seeds 0-2), the sample maples 0.87 and more.
MIRROR_RATIO = 0.67
#: A nominated exemplar is turned over when its registered blade's IoU with the training blade is at
#: least this much higher turned over than as it faces: the drawn oaks gain 0.11-0.16 (0.76-0.81 ->
#: 0.92, 128-640 px), the nominated procedural leaves (lobed, trilobed, elliptic at 160-384 px, 11
#: pairs with ratios 0.42-0.66) -0.005 to +0.014.
MIRROR_GAIN = 0.05


def _small(mask: np.ndarray, side: int = 512) -> np.ndarray:
    """The mask at most ``side`` px on its long side (nearest sampling: a score, not a picture)."""
    step = max(1, int(np.ceil(max(mask.shape) / side)))
    return mask[::step, ::step]


def _best_fit(outline_e: np.ndarray, mu_e: np.ndarray, chamfer_t, outline_t: np.ndarray, chamfer_e,
              mu_t: np.ndarray, scale: float, flip: np.ndarray, step_deg: float = 5.0) -> float:
    """Lowest symmetric outline chamfer over similarity maps (centroid on centroid, area-matched, every rotation)."""
    from .registration import _rot

    # Every rotation at once (the same numbers as one map at a time, without the per-map overhead).
    lin = np.array([scale * _rot(th) @ flip for th in np.deg2rad(np.arange(0.0, 360.0, step_deg))])
    off = np.array([mu_t - m @ mu_e for m in lin])
    inv = np.linalg.inv(lin)
    lin_t, inv_t = np.swapaxes(lin, 1, 2), np.swapaxes(inv, 1, 2)
    c = chamfer_t.many(outline_e @ lin_t + off[:, None]) + chamfer_e.many((outline_t - off[:, None]) @ inv_t) * scale
    return float(c.min())


def mirrored_exemplars(blades, training_index: int, *, ratio: float = MIRROR_RATIO) -> list[bool]:
    """For each exemplar, whether its mirror image fits the training blade clearly better.

    Each exemplar's lamina (the blade without petiole and other thin
    parts) is laid on the training leaf's by similarity maps (centroid on
    centroid, area matched, every 5 degrees), as itself and mirrored; it is
    taken as mirrored when the mirror image's best symmetric chamfer
    distance of the outlines is at most ``ratio`` times its own. A nearly
    symmetric blade (an elliptic leaf, a maple) fits both ways about
    equally and is left as it is; so is one whose mirror image equals a
    rotation of itself.

    Parameters
    ----------
    blades : list of (H, W) bool array_like
        The exemplars' blades on one canvas (:func:`normalise_exemplars`).
    training_index : int
        The training leaf (never mirrored).
    ratio : float
        Largest share of the unmirrored score the mirrored one may have, in (0, 1].

    Returns
    -------
    list of bool

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:80, :80]
    >>> blade = (((xx - 40) / 30.0) ** 2 + ((yy - 40) / 14.0) ** 2 < 1) & ~((xx > 40) & (yy < 36))
    >>> blade |= (np.abs(yy - 47 - (xx - 10) // 3) < 2) & (xx > 10) & (xx < 30)   # a thin part: ignored
    >>> mirrored_exemplars([blade, blade[:, ::-1], blade], 0)
    [False, True, False]
    """
    from .registration import _Chamfer, _contour_points, _lamina, _moments

    if isinstance(training_index, bool) or not isinstance(training_index, (int, np.integer)) \
            or not 0 <= training_index < len(blades):
        raise ValueError(f"training_index must be an int in [0, {len(blades) - 1}], got {training_index!r}")
    if not 0 < float(ratio) <= 1:
        raise ValueError(f"ratio must be in (0, 1], got {ratio!r}")
    laminae = [_lamina(_small(as_mask(b, name=f"blades[{i}]"))) for i, b in enumerate(blades)]
    lt = laminae[training_index]
    out = [False] * len(laminae)
    if lt.sum() < 16:
        return out
    mu_t, _, a_t = _moments(lt)
    outline_t, chamfer_t = _contour_points(lt), _Chamfer(lt)
    for i, le in enumerate(laminae):
        if i == training_index or le.sum() < 16:
            continue
        mu_e, _, a_e = _moments(le)
        outline_e, chamfer_e = _contour_points(le), _Chamfer(le)
        scale = float(np.sqrt(a_t / a_e))
        args = (outline_e, mu_e, chamfer_t, outline_t, chamfer_e, mu_t, scale)
        own = _best_fit(*args, np.eye(2))
        flipped = _best_fit(*args, np.diag([-1.0, 1.0]))
        out[i] = bool(flipped <= ratio * own)
    return out


def registered_blade_iou(registration, blade: np.ndarray, training_blade: np.ndarray) -> float:
    """IoU of ``blade`` warped into the training frame by ``registration`` with ``training_blade``.

    Parameters
    ----------
    registration : Registration
        Exemplar -> training leaf.
    blade : (H, W) bool array_like
        The registered exemplar's blade.
    training_blade : (H_t, W_t) bool array_like
        The training leaf's blade.

    Returns
    -------
    float

    Examples
    --------
    >>> from branchnb.leaves import leaf_family, normalise_exemplars, register
    >>> c, b, _ = normalise_exemplars(leaf_family(2, size=96, rng=0))
    >>> registered_blade_iou(register(c[1], c[0], b[1], b[0]), b[1], b[0]) > 0.9
    True
    """
    return iou(registration.to_training(np.asarray(blade, bool)), training_blade)


def turned_over_fits(own, turned, blade, training_blade, *, gain: float = MIRROR_GAIN) -> bool:
    """Whether the exemplar turned over registers clearly better than as it faces.

    A leaf whose lobes differ in size from the training leaf's may fit its
    mirror image's outline better under rigid maps (what
    :func:`mirrored_exemplars` scores), but the thin-plate spline bends it
    onto the training blade as it faces just as well; a leaf that truly
    faces the other way does not bend onto it (the orientation-keeping
    spline cannot turn it over). Beyond the paper; measured figures at
    :data:`MIRROR_GAIN`.

    Parameters
    ----------
    own, turned : Registration
        The exemplar registered as it faces, and turned over (left-right).
    blade : (H, W) bool array_like
        The exemplar's blade as it faces (turned over here for ``turned``).
    training_blade : (H_t, W_t) bool array_like
        The training leaf's blade.
    gain : float
        Least rise of the registered blade IoU that turns the exemplar over.

    Returns
    -------
    bool

    Examples
    --------
    >>> from branchnb.leaves import leaf_family, normalise_exemplars, register
    >>> c, b, _ = normalise_exemplars(leaf_family(2, size=96, kind="trilobed", rng=3))
    >>> own = register(c[1], c[0], b[1], b[0])
    >>> turned = register(c[1][:, ::-1], c[0], b[1][:, ::-1], b[0])
    >>> turned_over_fits(own, turned, b[1], b[0])
    False
    """
    m = as_mask(blade, name="blade")
    t = as_mask(training_blade, name="training_blade")
    if not np.isfinite(gain) or gain < 0:
        raise ValueError(f"gain must be a finite number >= 0, got {gain!r}")
    return registered_blade_iou(turned, m[:, ::-1], t) >= registered_blade_iou(own, m, t) + gain
