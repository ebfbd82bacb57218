"""Issue 23: the quicker gap completion and composition of image synthesis (gap_quilting, gap_blend)."""

import numpy as np
import pytest

from branchnb.branching.gap_blend import compose_patch, screened_correction
from branchnb.branching.gap_quilting import _corr, quilt_gaps
from branchnb.core.blending import compose_piece
from branchnb.core.poisson import _poisson_solve


def _system(seed, h=30, w=34):
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:h, :w]
    src = (0.4 + 0.1 * np.sin(xx / 5.0 + seed)[..., None] + 0.05 * rng.random((h, w, 3))).astype(np.float32)
    kept = (yy < 8) | (xx < 6 + seed)
    tgt = np.where(kept[..., None], src + 0.2, src).astype(np.float32)
    return tgt, src, ~kept


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_screened_correction_matches_the_direct_solve(seed):
    tgt, src, mask = _system(seed)
    exact = _poisson_solve(tgt, src, mask, mask, 0.05)
    cg = screened_correction(tgt, src, mask, 0.05)
    assert np.abs(cg - exact)[mask].max() < 2e-3          # under one grey level
    assert np.array_equal(cg[~mask], tgt[~mask])


def test_screened_correction_bad_screen():
    tgt, src, mask = _system(0)
    with pytest.raises(ValueError, match="screen"):
        screened_correction(tgt, src, mask, 0.0)


@pytest.mark.parametrize("kw", [dict(screen=0.05), dict(anchor_weight=10.0)])
def test_compose_patch_as_compose_piece(kw):
    rng = np.random.default_rng(3)
    canvas = np.full((40, 40, 3), 0.3, np.float32)
    covered = np.zeros((40, 40), bool)
    covered[:, :20] = True
    piece = (0.6 + 0.05 * rng.random((24, 24, 3))).astype(np.float32)
    valid = np.ones((24, 24), bool)
    c1, v1 = canvas.copy(), covered.copy()
    a = compose_piece(c1, v1, piece, valid, (10, 8), **kw)
    c2, v2 = canvas.copy(), covered.copy()
    b = compose_patch(c2, v2, piece, valid, (10, 8), **kw)
    assert np.array_equal(a.take, b.take) and np.array_equal(v1, v2)
    assert np.abs(c1 - c2).max() < 3e-3


def test_direct_correlation_is_match_template():
    import cv2
    rng = np.random.default_rng(0)
    img, tpl = rng.random((50, 60)).astype(np.float32), rng.random((8, 8)).astype(np.float32)
    assert np.allclose(_corr(img, tpl), cv2.matchTemplate(img, tpl, cv2.TM_CCORR), atol=1e-4)


def test_quilt_gaps_fills_every_gap_pixel():
    rng = np.random.default_rng(1)
    ex = (0.5 + 0.1 * rng.random((64, 64, 3))).astype(np.float32)
    forbidden = np.zeros((64, 64), bool)
    forbidden[30:34, :] = True                            # a "branch" in the example
    canvas = np.zeros((48, 56, 3), np.float32)
    covered = np.zeros((48, 56), bool)
    covered[:, :16] = True
    canvas[covered] = 0.5
    r = quilt_gaps(canvas, covered, ex, forbidden, patch_size=12, overlap=0.25, protect=None, tolerance=0.1,
                   forbid_weight=5.0, method="graphcut", poisson=True, anchored=True, anchor_weight=10.0,
                   screen=0.05, min_free=0.0, rng=0)
    assert covered.all() and r.filled[:, 16:].all() and r.n_inpainted == 0
    # only branch-free example pixels copied
    src = r.source[r.filled & ~np.isnan(r.source[..., 0])].astype(int)
    assert not forbidden[src[:, 1], src[:, 0]].any()
