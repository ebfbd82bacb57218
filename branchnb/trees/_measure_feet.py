"""Flecks beside the trunk foot after the ground cut (issue 24), not run by the tests.

``python -m branchnb.trees._measure_feet [seeds]``: procedural drawn trees standing on a leaf
pile (:func:`~branchnb.trees.drawn.drawn_tree` ``pile=True``, four kinds, 256 and 512 px);
prints per kind the mean and max :func:`foot_flecks` of the ground-cut trees.
"""

from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage as ndi


def foot_flecks(image, foot_rows: float = 0.04) -> int:
    """Dark opaque pixels in the lowest ``foot_rows`` of a tree that an opening with a disc a
    little wider than the outline removes: thin ink spurs sticking out of the silhouette."""
    a = np.asarray(image, np.float32)
    op = a[..., 3] >= 0.5
    if not op.any():
        return 0
    ys = np.flatnonzero(op.any(axis=1))
    h = ys[-1] - ys[0] + 1
    lum = a[..., :3] @ np.array([0.299, 0.587, 0.114], np.float32)
    r = max(2, int(round(0.012 * h)))
    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    opened = cv2.morphologyEx(op.astype(np.uint8), cv2.MORPH_OPEN, disc).astype(bool)
    spur = op & ~opened & (lum < 0.2)
    spur[:ys[-1] - int(foot_rows * h)] = False
    lab, n = ndi.label(spur, np.ones((3, 3), bool))
    sizes = np.bincount(lab.ravel())[1:]
    return int(sizes[sizes >= 3].sum())


def measure(seeds=(0, 1, 2)) -> dict:
    from .drawn import drawn_tree
    from .ground import split_ground

    out = {}
    for kind in ("fruit", "palm", "broadleaf", "conifer"):
        vals = []
        for size in (256, 512):
            for seed in seeds:
                img = np.asarray(drawn_tree(kind, pile=True, rng=20 + seed, size=size), np.float32)
                vals.append(foot_flecks(split_ground(img).cut(img)))
        out[kind] = vals
        print(f"{kind:10s} foot flecks mean {np.mean(vals):6.1f} px  max {max(vals)}  ({len(vals)} trees)", flush=True)
    return out


if __name__ == "__main__":
    measure(tuple(range(int(sys.argv[1]))) if len(sys.argv) > 1 else (0, 1, 2))
