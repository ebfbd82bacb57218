"""colour_similarity's compiled EMD pass gives exactly the NumPy loop's S_e (the code before the speed pass)."""

import cv2
import numpy as np
import pytest

from branchnb.leaves.induction_colour import colour_similarity, layer_cdfs


def _reference(q, blade, cdfs, size, w):
    """The former NumPy loop (blade spanning its box; size > 1)."""
    k, _, bins = cdfs.shape
    wch = (w / (bins - 1)).astype(np.float32)
    ksize = (size, size)
    count = cv2.boxFilter(blade.astype(np.float32), -1, ksize, normalize=False, borderType=cv2.BORDER_CONSTANT)
    inv = np.where(count > 0.5, 1.0 / np.maximum(count, 1e-6), 0.0).astype(np.float32)
    total = np.zeros((k,) + q.shape[:2], np.float32)
    tmp = np.empty(q.shape[:2], np.float32)
    for ch in range(3):
        qc = q[..., ch]
        for b in range(bins - 1):
            local = cv2.boxFilter(((qc <= b) & blade).view(np.uint8), cv2.CV_32F, ksize, normalize=False,
                                  borderType=cv2.BORDER_CONSTANT) * inv
            for j in range(k):
                np.subtract(local, np.float32(cdfs[j, ch, b]), out=tmp)
                np.abs(tmp, out=tmp)
                tmp *= wch[ch]
                total[j] += tmp
    total[:, ~blade | (count < 0.5)] = 1.0
    return np.clip(total, 0.0, 1.0)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("size", [3, 7, 15])
def test_equal_to_numpy_loop(seed, size):
    rng = np.random.default_rng(seed)
    h, w = (int(v) for v in rng.integers(30, 80, 2))
    bins = [4, 8, 32, 16][seed]
    ramp = (np.arange(w)[None, :, None] * bins // w)
    q = np.clip(rng.integers(-1, 2, (h, w, 3)) + ramp, 0, bins - 1).astype(np.uint8)
    blade = rng.random((h, w)) < 0.85
    blade[0, 0] = blade[-1, -1] = True  # the blade spans its box: no crop
    k = seed % 3 + 1
    cdfs = np.stack([layer_cdfs(q, rng.random((h, w)) < 0.3, bins) for _ in range(k)])
    wts = np.array([0.5, 0.3, 0.2]) if seed % 2 else np.full(3, 1 / 3)
    got = colour_similarity(q, blade, cdfs, size, weights=wts)
    np.testing.assert_array_equal(got, _reference(q, blade, cdfs, size, wts / wts.sum()))
    assert 0.0 < float(got[:, blade].mean()) < 1.0
