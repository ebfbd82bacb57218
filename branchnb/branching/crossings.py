"""Source fragments away from crossing strands (going beyond the paper).

An extracted drawing may have strands that cross without joining (the
over-and-under of a Celtic knot, vines winding round each other, an artery
crossing a vein). Near the crossing the other strand lies within the own
branch's body zone and is owned by it in the pixel map, so a branch fragment
taken there copies a short piece of the crossing strand on either side of the
synthesized stroke: a cross-shaped stub where the target has no crossing.
Branch fragments whose disk holds such a crossing are left out of the source
library (when enough others remain).
"""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.structure import Structure
from .fragments import FragmentLibrary

__all__ = ["crossing_points", "without_crossings"]


def crossing_points(structure: Structure, shape) -> np.ndarray:
    """Pixels where two branches' centre lines meet other than at a junction; (H, W) bool.

    A child's start on its parent (within 3 px) is a junction, not a crossing.

    Parameters
    ----------
    structure : Structure
        The branches whose centre lines are drawn.
    shape : tuple of int
        (H, W) of the returned mask.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> s = Structure([Branch([(2, 10), (18, 10)], 1.0), Branch([(10, 2), (10, 18)], 1.0)], (20, 20))
    >>> c = crossing_points(s, (20, 20))
    >>> bool(c[10, 10]), int(c.sum()) <= 4
    (True, True)
    """
    h, w = int(shape[0]), int(shape[1])
    count = np.zeros((h, w), np.int16)
    for b in structure.branches:
        p = np.round(b.points).astype(np.int32)
        x0, y0 = max(int(p[:, 0].min()) - 1, 0), max(int(p[:, 1].min()) - 1, 0)
        x1, y1 = min(int(p[:, 0].max()) + 2, w), min(int(p[:, 1].max()) + 2, h)
        if x1 <= x0 or y1 <= y0:
            continue
        one = np.zeros((y1 - y0, x1 - x0), np.uint8)      # its bounding box only
        cv2.polylines(one, [p - (x0, y0)], False, 1, 1)
        count[y0:y1, x0:x1] += one
    cross = count >= 2
    if not cross.any():
        return cross
    starts = np.zeros((h, w), bool)
    for b in structure.branches:
        if b.parent is not None:
            x, y = np.round(b.points[0]).astype(int)
            if 0 <= x < w and 0 <= y < h:
                starts[y, x] = True
    if starts.any():
        cross &= ndi.distance_transform_edt(~starts) > 3.0
    return cross


def without_crossings(lib: FragmentLibrary, structure: Structure, shape, *, keep: float = 0.5
                      ) -> FragmentLibrary:
    """``lib`` without the fragments whose disk holds a crossing of two branches.

    Parameters
    ----------
    lib : FragmentLibrary
        Source branch fragments.
    structure : Structure
        The example's branches.
    shape : (H, W)
        The example's size.
    keep : float, default 0.5
        Least share of ``lib`` kept: with fewer fragments left, ``lib`` is returned as is.

    Returns
    -------
    FragmentLibrary
    """
    if len(lib) == 0:
        return lib
    cross = crossing_points(structure, shape)
    if not cross.any():
        return lib
    d = ndi.distance_transform_edt(~cross)
    h, w = cross.shape
    cx = np.clip(np.rint(lib.center[:, 0]).astype(int), 0, w - 1)
    cy = np.clip(np.rint(lib.center[:, 1]).astype(int), 0, h - 1)
    ok = d[cy, cx] > lib.radius
    if ok.all() or ok.mean() < keep:
        return lib
    return replace(lib, branch=lib.branch[ok], arc=lib.arc[ok], sign=lib.sign[ok], child=lib.child[ok],
                   center=lib.center[ok], radius=lib.radius[ok])
