"""No ink spurs beside the trunk foot after the ground cut (issue 24).

A leaf pile drawn against the trunk foot left the upper outlines of its leaves above the cut: a
2-4 px black line sticking out sideways from the trunk's lowest rows, which every mix of the tree
then showed as a fleck beside its foot (notebook 02's conifer). The conifer below kept 30 dark
pixels outside the trunk's column in its last rows; now 1.
"""

import numpy as np

from branchnb.trees._measure_feet import foot_flecks
from branchnb.trees.drawn import drawn_tree
from branchnb.trees.ground import split_ground


def _outside_column(tree: np.ndarray, img: np.ndarray, rows: int = 6) -> int:
    """Dark tree pixels in the last ``rows`` rows outside the trunk's span 8 rows higher (+1 px)."""
    ys = np.flatnonzero(tree.any(axis=1))
    yb = ys[-1]
    xs = np.flatnonzero(tree[yb - rows - 8])
    mid = np.median(np.flatnonzero(tree[yb]))
    runs = np.split(xs, np.flatnonzero(np.diff(xs) > 1) + 1)
    run = min(runs, key=lambda q: 0 if q[0] <= mid <= q[-1] else min(abs(q[0] - mid), abs(q[-1] - mid)))
    band = tree[yb - rows:yb + 1].copy()
    band[:, max(0, run[0] - 1):run[-1] + 2] = False
    lum = img[yb - rows:yb + 1, :, :3] @ np.array([0.299, 0.587, 0.114])
    return int((band & (lum < 0.2)).sum())


def test_conifer_foot_has_no_leaf_outline_left():
    img = np.asarray(drawn_tree("conifer", pile=True, rng=23, size=512), np.float32)
    s = split_ground(img)
    assert s.has_ground
    assert _outside_column(s.tree, img) <= 1            # main: 30


def test_foot_flecks_near_a_clean_foot():
    # palm and conifer on piles, 256 and 512 px: as few flecks as the same trees without a pile
    cut, clean = [], []
    for kind in ("palm", "conifer"):
        for size, seed in ((256, 22), (512, 21)):
            img = np.asarray(drawn_tree(kind, pile=True, rng=seed, size=size), np.float32)
            cut.append(foot_flecks(split_ground(img).cut(img)))
            clean.append(foot_flecks(np.asarray(drawn_tree(kind, pile=False, rng=seed, size=size), np.float32)))
    assert np.mean(cut) <= np.mean(clean) + 5, (cut, clean)   # main: 19.5 vs 10.5, now 14.75


def test_flared_foot_stays():
    # a trunk widening into a solid foot (fill-coloured, thick) on a pile keeps its flare
    img = np.zeros((120, 90, 4), np.float32)
    img[5:50, 10:80] = (0.1, 0.5, 0.1, 1)
    img[50:100, 38:52] = (0.45, 0.27, 0.12, 1)
    for y in range(92, 100):
        d = y - 91
        img[y, 38 - d:52 + d] = (0.45, 0.27, 0.12, 1)
    img[100:112, 5:85] = (0.8, 0.3, 0.05, 1)                # the pile
    s = split_ground(img)
    assert s.has_ground
    assert s.tree[98, 38 - 6] and s.tree[98, 52 + 5]
