"""Soft-alpha trees: background matted into notches is no opaque paper speck (issue 24, slits)."""

import numpy as np
import pytest

from branchnb.trees import TreeLibrary
from branchnb.trees.exemplar import normalize_exemplar


def _lobed(seed: int, side: int, paper) -> np.ndarray:
    """A crown with deep narrow notches, soft (blurred) alpha, paper colour in transparent pixels."""
    import cv2

    r = np.random.default_rng(seed)
    h, w = side, int(side * 0.75)
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    cx, cy, rad = w / 2, 0.35 * h, 0.3 * w
    th, rr = np.arctan2(yy - cy, xx - cx), np.hypot(xx - cx, yy - cy)
    n, ph, depth = r.integers(5, 9), r.uniform(0, 2 * np.pi), r.uniform(0.35, 0.55)
    crown = rr < rad * (1 - depth * np.abs(np.sin(n * th / 2 + ph)) ** 0.35)
    trunk = (np.abs(xx - cx) < 0.05 * w) & (yy > cy) & (yy < 0.97 * h)
    m = crown | trunk
    alpha = cv2.GaussianBlur(m.astype(np.float32), (0, 0), max(1.0, side / 350))
    rgb = np.where(crown[..., None], np.array([0.3, 0.6, 0.25]), np.array([0.45, 0.3, 0.18]))
    rgb = np.where(m[..., None], rgb, np.array(paper))
    return np.dstack([rgb, alpha]).astype(np.float32)


def _paper_px(img: np.ndarray, paper) -> int:
    op = img[..., 3] >= 0.5
    return int((op & (np.abs(img[..., :3] - np.asarray(paper, np.float32)).max(-1) < 0.12)).sum())


@pytest.mark.parametrize("paper", [(1.0, 1.0, 1.0), (0.95, 0.9, 0.78)])
@pytest.mark.parametrize("seed,side", [(0, 200), (1, 420), (2, 700)])
def test_notches_keep_no_paper_specks(paper, seed, side):
    src = _lobed(seed, side, paper)
    # main: 4-30 opaque paper-coloured pixels per normalised crown
    assert _paper_px(normalize_exemplar(src, size=512).image, paper) == 0


def test_mix_of_soft_crowns_has_no_paper_slits():
    paper = (1.0, 1.0, 1.0)
    lib = TreeLibrary(size=512)
    for k in range(3):
        lib.add(_lobed(k, 200, paper), f"t{k}")
    bad = [_paper_px(np.asarray(lib.variation(rng=v).image, np.float32), paper) for v in range(2)]
    assert sum(bad) == 0        # main: 14 + 64 px


def test_dark_outline_over_cleared_pixels_is_kept():
    # a black anti-aliased outline over black (cleared) transparent pixels is the drawing's own
    img = np.zeros((64, 48, 4), np.float32)
    img[8:56, 8:40] = (0.2, 0.7, 0.1, 1.0)
    ring = np.zeros((64, 48), bool)
    ring[8:56, 8:40] = True
    ring[10:54, 10:38] = False
    img[ring] = (0.0, 0.0, 0.0, 0.7)
    out = normalize_exemplar(img, size=64).image
    op = out[..., 3] >= 0.5
    assert (op & (out[..., :3].max(-1) < 0.1)).sum() > 100
