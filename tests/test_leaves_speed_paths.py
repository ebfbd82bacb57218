"""Issue 22 speed pass: each faster path computes what the code it replaced computed.

(No timing assertions: the figures are in ``branchnb bench`` and in the commit messages.)
"""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.core.distance import edt
from branchnb.core.morphology import _binary_dilation, _binary_erosion, _binary_opening
from branchnb.leaves._snapkernels import sample_scores, sample_scores_many
from branchnb.leaves.snapping import ridge_evidence
from branchnb.leaves.tpsrpm import _exp_row, _softassign, _softassign_nb


@pytest.mark.parametrize("shape, seed", [((31, 47), 0), ((120, 90), 1), ((64, 64), 2)])
def test_edt_is_scipys(shape, seed):
    rng = np.random.default_rng(seed)
    m = ~ndi.binary_dilation(rng.random(shape) < 0.01, iterations=2)
    got = edt(m)
    assert got.dtype == np.float32
    assert np.array_equal(got, ndi.distance_transform_edt(m).astype(np.float32))
    # The same values on a crop (OpenCV's own float sums are not crop-invariant).
    assert np.array_equal(edt(m[3:-2, 5:]), ndi.distance_transform_edt(m[3:-2, 5:]).astype(np.float32))
    # Integer thresholds select the same pixels (sqrt of an integer vs an integer has no tie in float32).
    for r in (1, 2, 3, 5):
        assert np.array_equal(got <= r, ndi.distance_transform_edt(m) <= r)


def test_edt_edge_cases():
    full = np.ones((4, 5), bool)
    assert np.array_equal(edt(full), ndi.distance_transform_edt(full).astype(np.float32))
    assert not edt(np.zeros((3, 3), bool)).any()
    with pytest.raises(ValueError, match="mask"):
        edt(np.ones((2, 2, 2), bool))


def test_sample_scores_many_rows_are_sample_scores():
    rng = np.random.default_rng(3)
    maps = rng.random((8, 50, 60)).astype(np.float32)
    q = rng.random((5, 40, 2)) * [70, 60] - 5          # some points fall outside
    k = rng.integers(0, 8, (5, 40)).astype(np.int32)
    g = np.arange(-4, 5, 1.0)
    shifts = np.array([(x, y) for y in g for x in g]) + 0.25
    got = sample_scores_many(maps, k, q, shifts)
    assert got.shape == (5, len(shifts))
    for a in range(5):
        # The same float64 sums in the same order: equal, not just close.
        assert np.array_equal(got[a], sample_scores(maps, k[a], np.ascontiguousarray(q[a]), shifts))


@pytest.mark.parametrize("t", [1.0, 1e-2, 1e-4])
def test_softassign_with_flushed_weights_is_the_numpy_one(t):
    rng = np.random.default_rng(4)
    x = rng.random((60, 2))
    fv = x[::-1][:50] + rng.normal(0, 0.02, (50, 2))
    cx, cv = x.mean(0), fv.mean(0)
    want = _softassign(x, fv, None, None, t, 1.0, cx, cv, 10)
    got = _softassign_nb(x, fv, np.zeros(60, np.int64), np.zeros(50, np.int64), False, np.zeros((1, 1)), False,
                         t, 1.0, cx, cv, 10, 0.0)
    # Weights below 1e-307 of the largest are 0 in the compiled kernel; the rest agree.
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-300)
    assert np.all(np.isfinite(got)) and np.all(got >= 0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_opencv_morphology_is_scipys(seed):
    rng = np.random.default_rng(seed)
    r = 1 + seed
    yy, xx = np.mgrid[-r:r + 1, -r:r + 1]
    disk = xx**2 + yy**2 <= r * r
    for shape in [(1, 9), (7, 5), (40, 63), (120, 90)]:
        m = rng.random(shape) < 0.2
        m[:, 0] = True  # the image border: outside is False in both
        for it in (1, 2, 4):
            for st in (None, disk, np.ones((3, 3), bool)):
                assert np.array_equal(_binary_dilation(m, st, iterations=it),
                                      ndi.binary_dilation(m, st, iterations=it))
                assert np.array_equal(_binary_erosion(m, st, iterations=it),
                                      ndi.binary_erosion(m, st, iterations=it))
        assert np.array_equal(_binary_opening(m, structure=disk), ndi.binary_opening(m, structure=disk))
    # Cases OpenCV would not match go to SciPy: an even structure, iterations 0 (until nothing changes).
    m = rng.random((30, 30)) < 0.1
    even = np.ones((2, 2), bool)
    assert np.array_equal(_binary_dilation(m, even), ndi.binary_dilation(m, even))
    assert np.array_equal(_binary_dilation(m, iterations=0), ndi.binary_dilation(m, iterations=0))


def test_exp_row_is_numpys_exp_within_an_ulp():
    rng = np.random.default_rng(5)
    z = np.concatenate([-rng.uniform(0, 720, 20000), -rng.uniform(0, 1e-3, 100),
                        [0.0, -0.0, -1e-300, -707.99, -708.0, -708.01, -1e5, -np.inf]])
    got = np.empty_like(z)
    _exp_row(z, got)
    want = np.where(z > -708.0, np.exp(z), 0.0)
    assert np.array_equal(got == 0, want == 0)
    live = want > 0
    rel = np.abs(got[live] - want[live]) / want[live]
    assert rel.max() <= 2.3e-16  # 1 ulp
    assert np.mean(got == want) > 0.9


@pytest.mark.parametrize("t", [0.5, 1e-2, 1e-4])
def test_softassign_with_labels_and_pair_cost_is_the_numpy_one(t):
    rng = np.random.default_rng(6)
    x = rng.random((70, 2))
    fv = x[:55] + rng.normal(0, 0.02, (55, 2))
    lx, lv = (np.arange(70) % 3).astype(np.int64), (np.arange(55) % 3).astype(np.int64)
    cost = rng.uniform(0, 0.05, (70, 55))
    cx, cv = x.mean(0), fv.mean(0)
    want = _softassign(x, fv, lx, lv, t, 2.0, cx, cv, 10, cost)
    got = _softassign_nb(x, fv, lx, lv, True, cost, True, t, 2.0, cx, cv, 10, 0.0)
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-300)
    assert not got[lx[:, None] != lv[None, :]].any()


def _ridge_evidence_full_canvas(lab, blade, direction, width):
    """ridge_evidence before the speed pass: the whole canvas filtered."""
    from branchnb.core.image import extend_nearest
    from branchnb.leaves._snapkernels import sato_bright
    p = (np.asarray(lab, np.float32) @ np.asarray(direction, np.float32)).astype(np.float32)
    p = extend_nearest(p, blade)
    s = max(0.7, 0.5 * float(width))
    r = sato_bright(p, [s, max(s, float(width))]).astype(np.float32)
    inner = ndi.binary_erosion(blade)
    r = np.where(inner, r, 0.0).astype(np.float32)
    scale = float(np.percentile(r[inner], 99))
    return np.clip(r / scale, 0.0, 1.0).astype(np.float32)


@pytest.mark.parametrize("width, pad", [(1.0, 40), (2.5, 60), (6.0, 15)])
def test_ridge_evidence_on_the_blade_box_is_the_full_canvas_one(width, pad):
    """The blade's box grown by the filters' reach gives the same evidence as the padded canvas."""
    from branchnb.leaves import leaf_family
    leaf = leaf_family(1, size=128, rng=5)[0]
    from skimage.color import rgb2lab
    lab = np.pad(rgb2lab(leaf.image[..., :3]).astype(np.float32), ((pad, pad // 2), (pad // 3, pad), (0, 0)),
                 mode="edge")
    blade = np.pad(leaf.blade, ((pad, pad // 2), (pad // 3, pad)))
    direction = np.array([-1.0, 0.2, 0.1]) / np.sqrt(1.05)
    got = ridge_evidence(lab, blade, direction, width)
    want = _ridge_evidence_full_canvas(lab, blade, direction, width)
    assert np.array_equal(got, want)


@pytest.mark.parametrize("shape, channels, dtype, share", [
    ((1, 4), None, np.float64, 0.5), ((37, 53), 3, np.float32, 0.02), ((64, 81), 4, np.float32, 0.6),
    ((50, 40), None, np.int64, 0.1), ((45, 33), 1, np.uint8, 0.9), ((30, 70), 3, bool, 0.3)])
def test_extend_nearest_is_scipys_nearest_value(shape, channels, dtype, share):
    """extend_nearest (indices only, gathered with np.take) equals SciPy's nearest-index lookup exactly."""
    from branchnb.core.image import extend_nearest
    rng = np.random.default_rng(len(shape) + shape[0])
    v = (rng.random(shape + (() if channels is None else (channels,))) * 9).astype(dtype)
    known = rng.random(shape) < share
    known.flat[0] = True
    known.flat[-1] = False
    ref = v[tuple(ndi.distance_transform_edt(~known, return_indices=True)[1])]
    got = extend_nearest(v, known)
    assert got.dtype == ref.dtype and np.array_equal(got, ref)
    view = np.repeat(v, 2, axis=1)[:, ::2]  # a strided view
    assert np.array_equal(extend_nearest(view, known), ref)
