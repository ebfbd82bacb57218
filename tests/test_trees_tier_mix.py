"""Fir mixes with different tier counts keep whole tiers; bare-tree mixes take limbs from both trees
(issue 24, trees46)."""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi
from skimage.morphology import skeletonize
from test_trees_bare import bare_tree

from branchnb.trees import TreeLibrary
from branchnb.trees.corners import _contour_corners
from branchnb.trees.variations import make_variation


def _fir(n, h, seed):
    """A flat two-tone fir of ``n`` stacked triangular tiers, ``h`` px tall, drawn 4x and reduced."""
    r = np.random.default_rng(seed)
    w, ss = int(round(h * 0.75)), 4
    big = np.zeros((h * ss, w * ss, 4), np.float32)
    cx, top, bottom = 0.5 * w, 0.05 * h, 0.8 * h
    crown = np.zeros(big.shape[:2], np.uint8)
    for k in range(n):
        t0, t1 = top + (bottom - top) * k / n * 0.9, top + (bottom - top) * (k + 1) / n
        half = w * (0.12 + 0.32 * (k + 1) / n) * r.uniform(0.95, 1.05)
        cv2.fillPoly(crown, [np.int32(np.array([[cx, t0], [cx - half, t1], [cx + half, t1]]) * ss)], 1)
    trunk = np.zeros_like(crown)
    tw = 0.05 * w
    cv2.fillPoly(trunk, [np.int32(np.array([[cx - tw, 0.6 * h], [cx + tw, 0.6 * h], [cx + tw, 0.97 * h],
                                            [cx - tw, 0.97 * h]]) * ss)], 1)
    big[(trunk > 0) & (crown == 0)] = (0.42, 0.27, 0.15, 1.0)
    big[crown > 0] = (0.1, 0.38, 0.22, 1.0)
    big[(crown > 0) & (np.arange(w * ss)[None, :] > cx * ss)] = (0.15, 0.55, 0.32, 1.0)
    small = cv2.resize(big, (w, h), interpolation=cv2.INTER_AREA)
    a = small[..., 3:]
    return np.dstack([np.where(a > 1e-4, small[..., :3] / np.maximum(a, 1e-4), 1.0), a]).astype(np.float32)


def _corners(alpha):
    """Turning angles of the corners (at least 25 deg) on the upper 3/4 of the silhouette."""
    cs, _ = cv2.findContours((alpha >= 0.5).astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    c = max(cs, key=cv2.contourArea)[:, 0].astype(np.float64)
    c = np.roll(c, -int(np.argmax(c[:, 1])), axis=0)
    cc = np.vstack([c, c[:1]])
    s = np.concatenate([[0], np.cumsum(np.hypot(*np.diff(cc, axis=0).T))])
    u = np.linspace(0, s[-1], 1600, endpoint=False)
    pts = np.stack([np.interp(u, s, cc[:, 0]), np.interp(u, s, cc[:, 1])], 1)
    i, t = _contour_corners(pts, (0, 0, len(pts) - 1), angle=25.0)
    return t[pts[i, 1] < pts[:, 1].min() + 0.75 * np.ptp(pts[:, 1])]


def _tier_tips(alpha):
    """Heights (share of the tree's height) of the tier tips on each side, top down."""
    m = alpha >= 0.5
    ys = np.flatnonzero(m.any(axis=1))
    height = ys[-1] - ys[0]
    out = []
    for side in (0, 1):
        x = np.array([np.flatnonzero(m[y]).min() if side == 0 else m.shape[1] - 1 - np.flatnonzero(m[y]).max()
                      for y in ys], float)
        look = max(2, int(0.03 * height))
        tips = []
        for i in range(len(ys) - look):
            if (x[i + 1:i + 1 + look].max() - x[i] >= max(2, 0.025 * height)
                    and x[i] <= x[max(0, i - look):i + 1].min() and ys[i] < ys[0] + 0.9 * height
                    and (not tips or ys[i] - tips[-1] > 0.03 * height)):
                tips.append(ys[i])
        out.append((np.array(tips) - ys[0]) / height)
    return out


@pytest.mark.parametrize("size", [128, 256])
def test_fir_mixes_keep_whole_tiers(size):
    lib = TreeLibrary(size=size)
    lib.add(_fir(3, 300, 3), "fir3")
    lib.add(_fir(5, 420, 15), "fir5")
    src = [_tier_tips(e.alpha) for e in lib.exemplars]
    assert [len(s[0]) for s in src] == [3, 5]
    smallest = min(np.diff(np.r_[0.0, s[0]]).min() for s in src)
    for w3 in (0.3, 0.7):
        v = make_variation(lib, [w3, 0.7 if w3 == 0.3 else 0.3], colour_weights="shape", rng=0)
        t = _corners(v.image[..., 3])
        # a tier only one source holds came out scaled by its weight: shallow bumps and dents on
        # the flanks (main: 8-9 corners of 25-60 deg at 0.7/0.3, none in a source)
        assert (np.abs(t) < 60).sum() <= 2, np.round(t)
        left, right = _tier_tips(v.image[..., 3])
        assert len(left) == len(right) and 3 <= len(left) <= 5
        assert np.diff(np.r_[0.0, left]).min() >= 0.6 * smallest


def test_bare_mixes_take_limbs_of_both_trees():
    lib = TreeLibrary(size=192)
    lib.add(bare_tree(170, "round", 31), "round")
    lib.add(bare_tree(190, "asym", 32, two_tone=True), "asym")
    for seed in (0, 1):
        v = make_variation(lib, [0.5, 0.5], colour_weights="shape", rng=seed)
        op = v.image[..., 3] >= 0.5
        sk = skeletonize(op)
        share = [(v.sources[sk] == i).mean() for i in (0, 1)]
        assert min(share) >= 0.3, share
        lab, _ = ndi.label(op, structure=np.ones((3, 3)))
        areas = np.bincount(lab.ravel())[1:]
        assert areas.max() >= 0.97 * areas.sum()
    one = make_variation(lib, [0.9, 0.1], colour_weights="shape", rng=0)
    assert (one.sources[one.image[..., 3] >= 0.5] == 0).mean() >= 0.9     # a light tree gives no limb


@pytest.mark.parametrize(("n1", "n2", "seeds", "size"), [(3, 5, (3, 15), 192), (2, 5, (7, 8), 256)])
def test_even_fir_mix_has_a_tier_count_between_the_sources(n1, n2, seeds, size):
    """trees48: an even mix of a 3- and a 5-tier fir had 3 tiers (the heavier-indexed source's
    wide tiers hid the other's extra tier ends); now the count follows the weight."""
    lib = TreeLibrary(size=size)
    lib.add(_fir(n1, 300, seeds[0]), "a")
    lib.add(_fir(n2, 420, seeds[1]), "b")
    src = [_tier_tips(e.alpha) for e in lib.exemplars]
    assert [len(s[0]) for s in src] == [n1, n2]
    smallest = min(np.diff(np.r_[0.0, s[0]]).min() for s in src)
    counts = []
    for w in (0.2, 0.5, 0.8):
        v = make_variation(lib, [1 - w, w], colour_weights="shape", rng=0)
        left, right = _tier_tips(v.image[..., 3])
        assert len(left) == len(right)
        assert np.diff(np.r_[0.0, left]).min() >= 0.6 * smallest
        counts.append(len(left))
        if w == 0.5:    # no see-through hole inside the crown where a tier was dropped
            op = v.image[..., 3] >= 0.5
            filled = ndi.binary_fill_holes(op)
            assert (filled & ~op).sum() <= 2
    assert n1 < counts[1] < n2, counts
    assert counts == sorted(counts), counts
    assert abs(counts[0] - n1) <= 1 and abs(counts[2] - n2) <= 1, counts
