"""The fast paths of the leaf induction compute what the plain NumPy / scikit-image code computed."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.leaves import snapping
from branchnb.leaves._snapkernels import (
    oriented_maps,
    polar_dp,
    sample_scores,
    sample_scores_int,
    sample_scores_many,
    sato_bright,
)
from branchnb.leaves.induction import choose_threshold, colour_similarity, layer_cdfs


def _image(shape, seed=0):
    rng = np.random.default_rng(seed)
    return ndi.gaussian_filter(rng.random(shape) * 80, 1.5).astype(np.float32)


@pytest.mark.parametrize("sigmas", [[0.7, 1.0], [1.0, 2.5], [1.5, 3.0]])
def test_sato_bright_is_skimage_sato(sigmas):
    from skimage.filters import sato
    im = _image((40, 52))
    want = sato(im, sigmas=sigmas, black_ridges=False, mode="reflect")
    got = sato_bright(im, sigmas)
    # OpenCV sums the Gaussian taps in float32, SciPy in float64: ~1e-7 of the response.
    assert np.abs(got - want).max() <= 1e-5 * np.abs(want).max()


def test_sample_scores_is_the_numpy_mean():
    rng = np.random.default_rng(1)
    maps = rng.random((4, 30, 40)).astype(np.float32)
    q = rng.random((25, 2)) * [45, 35] - 2          # some points fall outside
    shifts = np.array([[0.0, 0.0], [2.0, -1.0], [-3.0, 4.0]])
    k = rng.integers(0, 4, 25).astype(np.int32)
    ix = np.round(q[None, :, 0] + shifts[:, None, 0]).astype(int)
    iy = np.round(q[None, :, 1] + shifts[:, None, 1]).astype(int)
    inside = (ix >= 0) & (ix < 40) & (iy >= 0) & (iy < 30)
    v = maps[k[None], np.clip(iy, 0, 29), np.clip(ix, 0, 39)]
    want = np.where(inside, v, 0.0).mean(1)
    np.testing.assert_allclose(sample_scores(maps, k, q, shifts), want, rtol=1e-6)


@pytest.mark.parametrize("halves", [False, True])
def test_whole_pixel_shifts_give_the_same_scores_bit_for_bit(halves):
    """The integer-addressed kernel of the pose searches equals the float one exactly: points near and
    past the border, exact half pixels (round half to even), a NaN point, shift grids of step 1-3."""
    rng = np.random.default_rng(3)
    maps = rng.random((6, 50, 61)).astype(np.float32)
    for trial in range(12):
        q = rng.uniform(-8, 66, (int(rng.integers(1, 9)), int(rng.integers(1, 40)), 2))
        if halves:
            q = np.round(q * 2) / 2
        q[0, 0] = np.nan if trial == 5 else q[0, 0]
        k = rng.integers(0, 6, q.shape[:2]).astype(np.int32)
        r, step = int(rng.integers(1, 9)), int(rng.integers(1, 4))
        g = np.arange(-r, r + 1, step)
        shifts = np.array([(x, y) for y in g for x in g], np.float64) + rng.integers(-4, 5, 2)
        want = sample_scores_many(maps, k, q, shifts)
        got = sample_scores_int(maps, k, q, shifts.astype(np.int64))
        assert np.array_equal(got, want, equal_nan=True)


@pytest.mark.parametrize("r0, slope", [(3.0, 0.5), (3.0, 0.3), (150.0, 0.3), (300.0, 0.01)])
def test_polar_dp_is_the_numpy_recursion(r0, slope):
    rng = np.random.default_rng(2)
    s = rng.random((40, 15)).astype(np.float32)
    rs = np.arange(r0, r0 + 40.0)
    da = np.radians(1.0)
    v, back, single = polar_dp(s, rs, da, slope)
    if single:
        v = v.astype(np.float32)
    # The loop it replaces (trace_branches before): a sideways budget of slope px per px.
    n_a = s.shape[1]
    vw = s[0].copy()
    bw = np.zeros(s.shape, np.int32)
    idx = np.arange(n_a)
    budget = 0.0
    for j in range(1, len(rs)):
        budget += slope
        m = int(min(np.floor(budget / (rs[j] * da)), 6))
        if m == 0:
            vw = vw + s[j]
            bw[j] = idx
            continue
        budget = 0.0
        best, arg = np.full(n_a, -np.inf), idx.copy()
        for d in range(-m, m + 1):
            src = idx + d
            cand = np.where((src >= 0) & (src < n_a), vw[np.clip(src, 0, n_a - 1)], -np.inf)
            better = cand > best
            best, arg = np.where(better, cand, best), np.where(better, src, arg)
        vw, bw[j] = best + s[j], arg
    assert v.dtype == vw.dtype and np.array_equal(v, vw) and np.array_equal(back, bw)


def test_oriented_maps_are_the_oriented_response():
    rng = np.random.default_rng(3)
    hess = (rng.standard_normal((3, 20, 24)) * 0.7).astype(np.float32)
    ev = rng.random((20, 24)).astype(np.float32)
    got = snapping._oriented_maps(ev, hess, 8)
    iy, ix = np.mgrid[:20, :24]
    for k in range(8):
        t = np.array([np.cos(np.pi * k / 8), np.sin(np.pi * k / 8)])
        want = (snapping.ORIENTED_WEIGHT * snapping.oriented_response(hess, ix, iy, t)
                + (1.0 - snapping.ORIENTED_WEIGHT) * ev).astype(np.float32)
        assert np.array_equal(got[k], want)
    tx, ty = np.cos(np.pi * np.arange(8) / 8), np.sin(np.pi * np.arange(8) / 8)
    assert oriented_maps(hess, ev, tx, ty, 0.5).shape == (8, 20, 24)


def _threshold_by_sort(d, target, blade):
    v, y = np.asarray(d, np.float64)[blade], target[blade]
    order = np.argsort(v, kind="stable")
    v, y = v[order], y[order]
    inter = np.cumsum(y)
    iou = inter / (np.arange(1, len(v) + 1) + y.sum() - inter)
    iou = np.where(np.r_[v[1:] != v[:-1], True], iou, -1.0)
    i = int(np.argmax(iou))
    return float(0.5 * (v[i] + v[i + 1]) if i + 1 < len(v) else v[i] + 1e-6), float(iou[i])


@pytest.mark.parametrize("seed", range(6))
def test_choose_threshold_is_the_full_sort(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 400))
    d = np.round(rng.random((1, n)) * rng.integers(1, 20), int(rng.integers(0, 3)))  # ties
    t = rng.random((1, n)) < 0.3
    t[0, 0] = True
    b = (rng.random((1, n)) < 0.9) | t
    assert choose_threshold(d, t, b) == _threshold_by_sort(d, t, b)


def test_colour_similarity_matches_float_box_filters():
    import cv2
    rng = np.random.default_rng(4)
    q = rng.integers(0, 8, (30, 34, 3)).astype(np.uint8)
    blade = rng.random((30, 34)) < 0.9
    cdfs = np.stack([layer_cdfs(q, rng.random((30, 34)) < 0.2, 8) for _ in range(2)])
    got = colour_similarity(q, blade, cdfs, 3)
    box = lambda a: cv2.boxFilter(a, -1, (3, 3), normalize=False, borderType=cv2.BORDER_CONSTANT)  # noqa: E731
    count = box(blade.astype(np.float32))
    inv = np.where(count > 0.5, 1.0 / np.maximum(count, 1e-6), 0.0).astype(np.float32)
    want = np.zeros_like(got)
    for ch in range(3):
        for b in range(7):
            local = box(((q[..., ch] <= b) & blade).astype(np.float32)) * inv
            for j in range(2):
                want[j] += np.float32(1 / 3 / 7) * np.abs(local - np.float32(cdfs[j, ch, b]))
    want[:, ~blade | (count < 0.5)] = 1.0
    assert np.array_equal(got, np.clip(want, 0, 1))
