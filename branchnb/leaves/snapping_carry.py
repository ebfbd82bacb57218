"""Carrying the training layer's points into an exemplar before the snap, and the blade box the snap works in.

Split from :mod:`~branchnb.leaves.snapping`; every name is importable from there as before.
"""

from __future__ import annotations

import numpy as np

from ..core.morphology import disk


def _affine_carry(registration, blade_t, chains, step: int = 4):
    """Chains carried by the affine map nearest the registration over the training blade."""
    ys, xs = np.nonzero(blade_t[::step, ::step])
    p = np.column_stack([xs, ys]).astype(np.float64) * step
    q = carry_points(registration, p)
    a = np.column_stack([p, np.ones(len(p))])
    m = np.linalg.lstsq(a, q, rcond=None)[0]
    return [np.column_stack([np.asarray(c, np.float64), np.ones(len(c))]) @ m for c in chains]


def _moment_carry(blade_t, blade_e, chains):
    """Chains carried by the similarity that maps the training blade's centroid and size onto the exemplar's."""
    yt, xt = np.nonzero(blade_t)
    ye, xe = np.nonzero(blade_e)
    ct, ce = np.array([xt.mean(), yt.mean()]), np.array([xe.mean(), ye.mean()])
    sc = np.sqrt(len(ye) / max(len(yt), 1))
    return [(np.asarray(c, np.float64) - ct) * sc + ce for c in chains]


def _nearest(ys, xs, p):
    i = int(np.argmin((ys - p[0]) ** 2 + (xs - p[1]) ** 2))
    return int(ys[i]), int(xs[i])


def _disk(r: int) -> np.ndarray:
    """A boolean disk of radius ``r`` px (the shared :func:`~branchnb.core.morphology.disk`)."""
    return disk(r).astype(bool)


def carry_points(registration, points) -> np.ndarray:
    """Training-leaf points (x, y) carried into an exemplar by its registration.

    Uses the dense ``map_to_training`` (bilinear) when the registration has
    one, else its ``inverse`` point map.

    Parameters
    ----------
    registration : Registration or IdentityRegistration
        Exemplar -> training leaf.
    points : (N, 2) array_like
        ``(x, y)`` on the training leaf.

    Returns
    -------
    (N, 2) float64 ndarray
        ``(x, y)`` on the exemplar.
    """
    pts = np.asarray(points, np.float64).reshape(-1, 2)
    mp = getattr(registration, "map_to_training", None)
    if mp is None:
        return np.asarray(registration.inverse(pts), np.float64)
    from ..core.warp import _remap_points
    out = _remap_points(np.asarray(mp, np.float32), pts[:, 0], pts[:, 1])
    return out.astype(np.float64)


def blade_box(blade, pad: int) -> tuple[int, int, int, int]:
    """The blade's bounding box grown by ``pad`` px, clipped to the image.

    Parameters
    ----------
    blade : (H, W) array_like of bool
        The blade mask.
    pad : int
        Pixels added on every side (negative values count as 0).

    Returns
    -------
    (int, int, int, int)
        ``(y0, y1, x0, x1)``, the whole image for an empty blade.

    Examples
    --------
    >>> import numpy as np
    >>> b = np.zeros((50, 60), bool); b[10:20, 30:45] = True
    >>> blade_box(b, 4)
    (6, 24, 26, 49)
    """
    b = np.asarray(blade, bool)
    rows, cols = np.flatnonzero(b.any(1)), np.flatnonzero(b.any(0))
    if not len(rows):
        return 0, b.shape[0], 0, b.shape[1]
    h, w = b.shape
    p = max(0, int(pad))
    return (max(int(rows[0]) - p, 0), min(int(rows[-1]) + 1 + p, h),
            max(int(cols[0]) - p, 0), min(int(cols[-1]) + 1 + p, w))


def _unbox(m, shape, y0: int, x0: int) -> np.ndarray:
    out = np.zeros(shape, bool)
    out[y0:y0 + m.shape[0], x0:x0 + m.shape[1]] = m
    return out
