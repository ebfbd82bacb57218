"""Flecks beside the trunk foot after the ground cut (issue 24), not run by the tests.

``python -m branchnb.trees._measure_feet [seeds] [kinds]``: procedural drawn trees standing on a leaf
pile (:func:`~branchnb.trees.drawn.drawn_tree` ``pile=True``, four kinds, 256 and 512 px);
prints per kind the mean and max :func:`foot_flecks` of the ground-cut trees, the same of the trees
without a pile (the no-pile reference), and :func:`foot_remnants`: pixels of the cut tree that are
not the tree drawn without its pile (trees35), with the trunk rows lost to the cut.
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


def without_pile(kind: str, rng, size: int) -> np.ndarray:
    """``drawn_tree(kind, pile=True, rng=, size=)`` drawn without its leaves: the true tree."""
    from unittest import mock

    from . import drawn

    with mock.patch.object(drawn, "_leaf_pile", lambda *a, **k: None):
        return np.asarray(drawn.drawn_tree(kind, pile=True, rng=rng, size=size), np.float32)


def foot_remnants(cut, truth) -> tuple[int, int]:
    """(remnant px, trunk rows lost) of a ground-cut tree against the tree without its pile.

    Remnants: opaque pixels of ``cut`` where the true tree is transparent (beyond 1 px of it) or
    farther than 0.2 (largest channel difference) from every true colour within 1 px: leaves,
    their outlines and spurs kept at the foot. Rows lost: the true tree's lowest row minus the
    cut's (the trunk hidden by the pile cannot come back; a cut above the pile's top costs more).
    """
    c = np.asarray(cut, np.float32)
    t = np.asarray(truth, np.float32)
    oc, ot = c[..., 3] >= 0.5, t[..., 3] >= 0.5
    near = cv2.dilate(ot.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    d = np.full(oc.shape, np.inf, np.float32)
    pad = np.pad(np.where(ot[..., None], t[..., :3], np.inf), ((1, 1), (1, 1), (0, 0)),
                 constant_values=np.inf)
    h, w = oc.shape
    for dy in range(3):
        for dx in range(3):
            d = np.minimum(d, np.abs(c[..., :3] - pad[dy:dy + h, dx:dx + w]).max(axis=2))
    bad = oc & (~near | (d > 0.2))
    rows_c, rows_t = np.flatnonzero(oc.any(axis=1)), np.flatnonzero(ot.any(axis=1))
    return int(bad.sum()), int(rows_t[-1] - rows_c[-1]) if rows_c.size else 0


def measure(seeds=(0, 1, 2), kinds=("fruit", "palm", "broadleaf", "conifer")) -> dict:
    from .drawn import drawn_tree
    from .ground import split_ground

    out = {}
    for kind in kinds:
        vals, ref, rem, lost = [], [], [], []
        for size in (256, 512):
            for seed in seeds:
                img = np.asarray(drawn_tree(kind, pile=True, rng=20 + seed, size=size), np.float32)
                cut = split_ground(img).cut(img)
                vals.append(foot_flecks(cut))
                r, k = foot_remnants(cut, without_pile(kind, 20 + seed, size))
                rem.append(r)
                lost.append(k)
                clean = np.asarray(drawn_tree(kind, pile=False, rng=20 + seed, size=size), np.float32)
                ref.append(foot_flecks(split_ground(clean).cut(clean)))
        out[kind] = vals, ref, rem, lost
        print(f"{kind:10s} foot flecks mean {np.mean(vals):6.1f} px  max {max(vals)}  (no pile {np.mean(ref):5.1f}"
              f"  max {max(ref)})  remnants mean {np.mean(rem):6.1f} max {max(rem)}  rows lost mean "
              f"{np.mean(lost):5.1f} max {max(lost)}  ({len(vals)} trees)", flush=True)
    return out


if __name__ == "__main__":
    measure(tuple(range(int(sys.argv[1]))) if len(sys.argv) > 1 else (0, 1, 2),
            *([tuple(sys.argv[2].split(","))] if len(sys.argv) > 2 else []))
