"""Bare trees edited with hand-like strokes (issue 25): a few clicks per branch, corners cut at forks.

A user clicks a few points along each branch: the strokes cut across
background between forks, start inside a fork rather than on the parent's
centre line, and one of them is copied to grow a new branch. Re-using the
source strokes as targets must give the tree back (alpha IoU >= 0.97), and
adding a branch must keep every original branch and grow the new one.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from branchnb import data
from branchnb.strokes import edit_structure

#: ``tree_rpg_11`` (474 x 505): trunk, two left limbs, two top limbs, right branch and its fork.
TREE_11 = [
    [(225, 485), (235, 320), (240, 230)],
    [(232, 325), (150, 290), (35, 318)],
    [(150, 290), (70, 230), (20, 175)],
    [(240, 230), (185, 160), (145, 15)],
    [(250, 240), (300, 65)],
    [(265, 310), (350, 255), (460, 250)],
    [(350, 255), (450, 110)],
]
#: ``tree_rpg_12`` (507 x 473): trunk through the right fork, left limbs, middle and right branches.
TREE_12 = [
    [(205, 455), (205, 330), (300, 195), (400, 40)],
    [(190, 290), (120, 180), (20, 95)],
    [(160, 225), (20, 240)],
    [(325, 160), (255, 110), (212, 15)],
    [(340, 140), (490, 100)],
]
#: A new branch from the trunk of ``tree_rpg_12``, grown from the middle branch (stroke 3).
NEW_12 = [(205, 380), (270, 375), (330, 355), (400, 320)]


def _tree(name, size):
    img = data.load(name)
    h, w = img.shape[:2]
    f = size / max(h, w)
    return cv2.resize(img, (round(w * f), round(h * f)), interpolation=cv2.INTER_AREA).astype(np.float32), f


def _iou(a, b):
    return float((a & b).sum() / max((a | b).sum(), 1))


@pytest.mark.parametrize("name, strokes, size", [("tree_rpg_11", TREE_11, 900), ("tree_rpg_12", TREE_12, 900),
                                                 ("tree_rpg_12", TREE_12, 250)])
def test_identity_edit_with_corner_cutting_strokes_gives_the_tree_back(name, strokes, size):
    # main before issue 25: IoU 0.947 (tree 11: a limb's curled tip lost, its branch shifted
    # along itself at the fork) and 0.965 (tree 12: the right branch stretched into the fork)
    img, f = _tree(name, size)
    src = [np.array(s, float) * f for s in strokes]
    res = edit_structure(img, src, src)
    before = img[..., 3] > 0.5
    assert _iou(before, res.mask) >= 0.97
    both = before & res.mask
    assert float(np.abs(res.layer[..., :3] - img[..., :3])[both].mean()) < 0.02


def test_new_branch_from_a_copied_branch_keeps_the_tree_and_grows():
    # main before issue 25: the copied (moved, hence centred) stroke and the kept one split the
    # middle branch's pixels between them; the new branch came out empty
    img, f = _tree("tree_rpg_12", 474)
    src = [np.array(s, float) * f for s in TREE_12]
    new = np.array(NEW_12, float) * f
    res = edit_structure(img, src + [src[3]], src + [new])
    before = img[..., 3] > 0.5
    band = np.zeros(before.shape, np.uint8)
    cv2.polylines(band, [np.round(new).astype(np.int32)], False, 1, int(0.12 * 474))
    away = band == 0
    assert _iou(before & away, res.mask & away) >= 0.95
    # the new branch: opaque along its stroke (beyond the trunk) and about as wide as the donor
    s = np.linspace(0.25, 0.9, 30)
    seg = np.r_[0.0, np.cumsum(np.hypot(*np.diff(new, axis=0).T))]
    pts = np.c_[np.interp(s * seg[-1], seg, new[:, 0]), np.interp(s * seg[-1], seg, new[:, 1])]
    on = res.mask[np.round(pts[:, 1]).astype(int), np.round(pts[:, 0]).astype(int)]
    assert on.mean() >= 0.9
    grown = (res.mask & ~before & (band > 0)).sum()
    assert grown >= 0.5 * 4.0 * seg[-1]  # at least ~4 px wide on average (the donor is ~10 px)


@pytest.mark.parametrize("name, strokes, k, angle", [("tree_rpg_11", TREE_11, 5, -0.35),
                                                     ("tree_rpg_12", TREE_12, 4, -0.3)])
def test_turning_one_branch_keeps_the_others(name, strokes, k, angle):
    # main before issue 25: IoU 0.963 / 0.982 away from the turned branch (neighbouring
    # branches shifted along themselves at their forks, a limb's tip lost)
    img, f = _tree(name, 474)
    src = [np.array(s, float) * f for s in strokes]
    c, s = np.cos(angle), np.sin(angle)
    tgt = list(src)
    tgt[k] = (src[k] - src[k][0]) @ np.array([[c, -s], [s, c]]).T + src[k][0]
    res = edit_structure(img, src, tgt)
    band = np.zeros(res.mask.shape, np.uint8)
    for pts in (src[k], tgt[k]):
        cv2.polylines(band, [np.round(pts).astype(np.int32)], False, 1, 60)
    away = band == 0
    assert _iou((img[..., 3] > 0.5) & away, res.mask & away) >= 0.98
