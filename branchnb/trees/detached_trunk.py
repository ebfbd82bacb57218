"""Icon-style trees whose trunk is drawn apart from the crown.

Beyond the paper (its exemplars are one region): a thin gap between a round
crown and the rectangle of the trunk below it makes the trunk a region of its
own, which keeping the largest region would drop. :func:`_detached_trunk`
finds such a trunk and :func:`_join_detached_trunk` draws it on up into the
crown, before the ground is split off (:mod:`.ground`) and the tree is
segmented.
"""

from __future__ import annotations

import cv2
import numpy as np

from .exemplar import tree_rgba
from .ground import GroundParams

#: Largest gap (fraction of the tree height) a detached trunk may leave under the crown.
TRUNK_GAP = 0.1


def _detached_trunk(opaque: np.ndarray) -> tuple[np.ndarray, np.ndarray, int] | None:
    """A trunk drawn apart from the crown: ``(crown, trunk, gap rows)`` or None.

    Icon-style trees often leave a thin gap between a round crown and the
    rectangle of the trunk below it; the trunk is then a region of its own
    that ``components="largest"`` would drop. A region is such a trunk when
    it is narrow (its median row at most ``stem_width`` of the crown's
    widest row), upright (at least 0.75 times as tall as that width and
    8 % of the tree's height), at least 2 % of the crown's area, under
    the crown (its top row's columns below crown pixels and its centre
    within a quarter of the crown's width from the crown's centre), below
    the crown's centre of mass, and its top at most ``TRUNK_GAP`` of the
    tree height below the crown's lowest pixel in those columns. A sun, a
    ground disc or a leaf pile (wide, flat, aside or far below) is none.
    Of several candidates the one nearest the crown is taken.
    """
    n, labels, stats, cents = cv2.connectedComponentsWithStats(opaque.astype(np.uint8), connectivity=8)
    if n <= 2:
        return None
    areas = stats[1:, cv2.CC_STAT_AREA]
    c_id = int(np.argmax(areas)) + 1
    crown = labels == c_id
    cx0, cw = stats[c_id, cv2.CC_STAT_LEFT], stats[c_id, cv2.CC_STAT_WIDTH]
    ys = np.flatnonzero(opaque.any(axis=1))
    height = ys[-1] - ys[0] + 1
    crown_w = float(crown.sum(axis=1).max())
    # Lowest crown row per column (-1 where the column has no crown).
    h = opaque.shape[0]
    low = np.where(crown.any(axis=0), h - 1 - np.argmax(crown[::-1], axis=0), -1)
    best = None
    for k in range(1, n):
        # A trunk is a part of the tree, no speck, pebble or stroke fragment.
        if k == c_id or areas[k - 1] < 0.02 * areas[c_id - 1]:
            continue
        x, y, w, hh = stats[k, :4]
        if y <= cents[c_id][1]:
            continue
        part = labels[y:y + hh, x:x + w] == k
        widths = part.sum(axis=1)
        w_med = float(np.median(widths))
        if w_med > GroundParams.stem_width * crown_w or hh < max(0.75 * w_med, 0.08 * height):
            continue
        if abs((x + 0.5 * w) - cents[c_id][0]) > 0.25 * cw or x < cx0 or x + w > cx0 + cw:
            continue
        top_cols = x + np.flatnonzero(part[0])
        above = low[top_cols]
        if (above < 0).any() or (above >= y).any():
            continue
        gap = int(y - above.max() - 1)
        if gap > TRUNK_GAP * height:
            continue
        if best is None or gap < best[2]:
            best = (crown, labels == k, gap)
    return best


def _join_detached_trunk(image, alpha_threshold: float = 0.5) -> np.ndarray:
    """``image`` (RGBA) with a trunk drawn apart from the crown joined to it.

    Beyond the paper (its exemplars are one region): the trunk found by
    :func:`_detached_trunk` is drawn on upwards into the crown, column by
    column up to the crown's lowest pixel, with one of its own rows (the
    first row below its top outline: the fill between its side outlines),
    which also paints over the trunk's top outline. The image is returned
    unchanged (a copy) when there is no such trunk.
    """
    img, opaque = tree_rgba(image, alpha_threshold=alpha_threshold, name="image")
    img = img.copy()
    found = _detached_trunk(opaque)
    if found is None:
        return img
    crown, trunk, _ = found
    ys = np.flatnonzero(trunk.any(axis=1))
    t0, t1 = int(ys[0]), int(ys[-1])
    # The reference row: the first row of the trunk's upper half whose
    # colour matches the median colour of those rows (below the top outline).
    upper = np.arange(t0, t0 + max(1, (t1 - t0 + 1) // 2))
    means = np.array([img[r, trunk[r], :3].mean(axis=0) for r in upper])
    ref_c = np.median(means, axis=0)
    ok = np.flatnonzero(np.abs(means - ref_c).max(axis=1) < 0.06)
    ref = int(upper[ok[0]]) if ok.size else int(upper[-1])
    xs = np.flatnonzero(trunk[ref])
    x0, x1 = max(0, xs[0] - 1), min(img.shape[1], xs[-1] + 2)   # with the anti-aliased edges
    row = img[ref, x0:x1].copy()
    h = opaque.shape[0]
    low = np.where(crown.any(axis=0), h - 1 - np.argmax(crown[::-1], axis=0), -1)
    start_default = int(low[xs].max()) + 1
    for j, x in enumerate(range(x0, x1)):
        start = int(low[x]) + 1 if 0 <= low[x] < t0 else start_default
        seg = img[start:ref, x]
        own = trunk[start:ref, x]
        # Over the gap the trunk row goes under what is there (the crown's soft
        # rim); over the trunk's top outline it replaces it.
        take = own | (seg[:, 3] < row[j, 3])
        seg[take] = row[j]
    return img
