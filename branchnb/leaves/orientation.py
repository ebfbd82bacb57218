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
"""

from __future__ import annotations

import numpy as np

from ..core.image import as_mask

#: Flip when the mirror image's best outline chamfer is at most this share of the unmirrored one's:
#: two drawn oaks facing opposite ways score 0.62-0.65 at 128-640 px, the procedural lobed, trilobed and
#: elliptic families 0.70 and more (sizes 160/384, seeds 0-2), the sample maples 0.87 and more.
MIRROR_RATIO = 0.67


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
