"""The along-skeleton averaging of the one-sided test (``false_ridge_pixels(local=...)``) as one sparse
operator over the skeleton pixels (issue 23: it was 8 full-image 3 x 3 convolutions per ratio)."""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi
from skimage.morphology import skeletonize

from branchnb.branching.line_profiles import _skeleton_adjacency, false_ridge_pixels


def _skeleton(seed: int, shape=(90, 130)) -> np.ndarray:
    rng = np.random.default_rng(seed)
    field = ndi.gaussian_filter(rng.random(shape), 2.0 + seed)
    sk = skeletonize(field > np.median(field))
    sk[0, :] |= rng.random(shape[1]) < 0.5      # pixels on the frame: the convolution's zero padding
    sk[:, -1] |= rng.random(shape[0]) < 0.5
    return sk


def test_adjacency_diffusion_is_the_convolution_diffusion_to_the_last_bit():
    for seed in range(3):
        sk = _skeleton(seed)
        sy, sx = np.nonzero(sk)
        rng = np.random.default_rng(10 + seed)
        vals = np.clip(rng.normal(0, 0.7, (6, len(sy))), -1, 1)
        # the earlier rule: a diffusion over the skeleton by full-image 3 x 3 convolutions
        den = ndi.convolve(sk.astype(float), np.ones((3, 3)), mode="constant")[sy, sx]
        ref = []
        for v in vals:
            rmap = np.zeros(sk.shape)
            rmap[sy, sx] = v
            for _ in range(8):
                rmap[sy, sx] = ndi.convolve(rmap, np.ones((3, 3)), mode="constant")[sy, sx] / den
            ref.append(rmap[sy, sx])
        adj = _skeleton_adjacency(sy, sx, sk.shape)
        assert adj.shape == (len(sy), len(sy))
        np.testing.assert_array_equal(np.diff(adj.indptr), den)
        x = np.ascontiguousarray(vals.T)
        for _ in range(8):
            x = (adj @ x) / np.diff(adj.indptr)[:, None]
        assert np.array_equal(x.T, np.array(ref))


def test_adjacency_does_not_join_parallel_lines_two_pixels_apart():
    sk = np.zeros((12, 20), bool)
    sk[4, 2:18] = True
    sk[6, 2:18] = True                            # a parallel line, one ground pixel between
    sy, sx = np.nonzero(sk)
    adj = _skeleton_adjacency(sy, sx, sk.shape).tocoo()
    assert np.all(sy[adj.row] == sy[adj.col])
    assert adj.nnz == 2 * (16 + 2 * 15)           # itself and its left/right neighbours


def test_local_one_sided_test_still_drops_a_step_cut_by_spurs_and_keeps_the_line():
    # a dark line on a flat ground, and the step between a darker and a lighter field whose skeleton a
    # spur every 8 px cuts into stretches too short for the per-stretch test
    img = np.full((80, 120), 0.7)
    img[:, 60:] = 0.45
    img[20, 5:55] = 0.1
    sk = np.zeros(img.shape, bool)
    sk[20, 5:55] = True
    sk[30:78, 59] = True
    for y in range(34, 78, 8):
        sk[y, 57:59] = True
    g = ndi.gaussian_filter(img, 0.7)
    per_stretch = false_ridge_pixels(g, sk, "dark", dotted=np.inf, beads=0.0)
    bad = false_ridge_pixels(g, sk, "dark", dotted=np.inf, beads=0.0, local=8.0)
    assert per_stretch[30:78, 59].sum() == 0
    assert bad[20].sum() == 0
    assert bad[30:78, 59].sum() == 48
