"""A delta's own axis and fan, learned from the example (beyond the paper; issue 23, branching58).

The paper's Markov chain has no notion of downstream; :class:`.domains._Drain` pulls a delta's
branches toward the sea. Its trunk followed the steepest descent of the land to the sea, so it always
reached the sea straight across the coast, and its channels took bearings off that descent. An
example's trunk may run far off the descent (a river entering through a side of the frame and
fanning toward a coast below): this module reads the delta's *axis* off the example, from where its
trunk enters the land to the mean of its mouths (where its channels meet the sea), and the example's
distribution of channel headings at the sea about that axis; the trunk heads for the example's mouths
and each new channel takes a heading the synthesized channels have used least
(:meth:`.domains._Drain.bearing`).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.structure import Structure

#: A branch reaches the sea when its last vertex is within this share of the land's deepest depth of
#: it (as :func:`.domains._drains` and :func:`.domains.fan_spread`).
SEA_SHARE = 0.1
#: A channel's heading at the sea is taken where it last lies this share of the frame's diagonal from
#: the sea, over the preceding :data:`HEADING_BACK` share (as ``_structure_check.sea_bearings_inland``,
#: the fan's measure): the fan of the channels, not the turns of their mouths along the coast.
HEADING_INLAND = 0.05
HEADING_BACK = 0.03


def _mouths(example: Structure, depth: np.ndarray) -> tuple[list[int], np.ndarray]:
    """Indices and last vertices of the example's branches that reach the sea."""
    h, w = depth.shape
    deep = float(depth.max())
    idx, ends = [], []
    for i, b in enumerate(example.branches):
        if len(b.points) < 2:
            continue
        x, y = np.clip(np.rint(b.points[-1]).astype(int), 0, [w - 1, h - 1])
        if depth[y, x] < SEA_SHARE * deep:
            idx.append(i)
            ends.append(np.asarray(b.points[-1], np.float64))
    return idx, np.asarray(ends, np.float64).reshape(-1, 2)


def delta_axis(example: Structure, domain: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The delta's axis: (start, target), both (x, y).

    ``start`` is the first vertex of the example's longest root (where its trunk enters the land) and
    ``target`` the mean of the last vertices of its branches that reach the sea (within
    :data:`SEA_SHARE` x the deepest depth of it): the direction from the inland root to the sea-side
    spread of the channels, not the descent of the land. A trunk entering through a side of the frame
    runs far off the descent (55 degrees on the ``fan55`` kind of :mod:`._delta_fan_check`).

    Parameters
    ----------
    example : Structure
        The example's structure.
    domain : (H, W) array_like of bool
        Where it may grow (the land); the sea lies outside it.

    Returns
    -------
    tuple of two (2,) ndarray or None
        None when no root starts inland of the target (at least a tenth of the deepest depth deeper)
        or no branch reaches the sea.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> dom = np.zeros((100, 100), bool); dom[:80] = True
    >>> s = Structure([Branch([(0, 20), (40, 50)], 2.0), Branch([(40, 50), (20, 79)], 1.0, 0, 1),
    ...                Branch([(40, 50), (80, 79)], 1.0, 0, 1)])
    >>> start, target = delta_axis(s, dom)
    >>> start.tolist(), target.tolist()
    ([0.0, 20.0], [50.0, 79.0])
    """
    dom = np.asarray(domain, bool)
    if dom.all() or not dom.any():
        return None
    depth = ndi.distance_transform_edt(dom)
    roots = [b for b in example.branches if b.parent is None and len(b.points) >= 2]
    if not roots:
        return None
    root = max(roots, key=lambda b: float(np.hypot(*np.diff(np.asarray(b.points, np.float64), axis=0).T).sum()))
    _idx, ends = _mouths(example, depth)
    if not len(ends):
        return None
    start = np.asarray(root.points[0], np.float64)
    target = ends.mean(0)
    h, w = dom.shape

    def at(p):
        x, y = np.clip(np.rint(p).astype(int), 0, [w - 1, h - 1])
        return float(depth[y, x])

    if at(start) < at(target) + 0.1 * float(depth.max()) or np.hypot(*(target - start)) < 1.0:
        return None
    return start, target


def fan_offsets(example: Structure, domain: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Signed angles (radians, image frame: positive clockwise on screen) of the headings of the example's
    channels at the sea off the delta's ``axis`` (unit x, y, :func:`delta_axis`), one per branch that
    reaches the sea, the trunk's included.

    The heading is a channel's direction over the :data:`HEADING_BACK` x the diagonal before the point
    where it last lies :data:`HEADING_INLAND` x the diagonal from the sea (its chord when shorter).

    Parameters
    ----------
    example : Structure
        The example's structure.
    domain : (H, W) array_like of bool
        Where it may grow (the land).
    axis : (2,) array_like
        The delta's axis direction (x, y).

    Returns
    -------
    (K,) ndarray
        Sorted; empty when no branch reaches the sea.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> dom = np.zeros((100, 100), bool); dom[:80] = True
    >>> s = Structure([Branch([(50, 0), (50, 40)], 2.0), Branch([(50, 40), (10, 80)], 1.0, 0, 1),
    ...                Branch([(50, 40), (90, 80)], 1.0, 0, 1)])
    >>> np.round(np.degrees(fan_offsets(s, dom, (0.0, 1.0)))).tolist()
    [-45.0, 45.0]
    """
    dom = np.asarray(domain, bool)
    depth = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    diag = float(np.hypot(h, w))
    ax = np.asarray(axis, np.float64)
    a0 = float(np.arctan2(ax[1], ax[0]))
    idx, _ends = _mouths(example, depth)
    out = []
    for i in idx:
        p = np.asarray(example.branches[i].points, np.float64)
        ix = np.clip(np.rint(p).astype(int), 0, [w - 1, h - 1])
        dv = depth[ix[:, 1], ix[:, 0]]
        far = np.flatnonzero(dv >= HEADING_INLAND * diag)
        k = int(far[-1]) if len(far) else len(p) - 1
        seg = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p[: k + 1], axis=0).T))]
        j = int(np.searchsorted(seg, seg[-1] - HEADING_BACK * diag))
        v = p[k] - p[j] if j < k else p[-1] - p[0]
        if np.hypot(*v) < 1e-9:
            continue
        out.append(float(np.angle(np.exp(1j * (np.arctan2(v[1], v[0]) - a0)))))
    return np.sort(np.asarray(out, np.float64))
