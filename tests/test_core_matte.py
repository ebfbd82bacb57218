"""core.matte: objects cut out of plain and smooth grounds (white, flat, gradients, paper, JPEG)."""

import cv2
import numpy as np
import pytest

from branchnb.core.matte import matte_from_background


def _ground(kind, h, w):
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    if kind == "white":
        return np.ones((h, w, 3), np.float32)
    if kind == "sky":
        t = (yy / h)[..., None]
        return (1 - t) * np.float32([0.35, 0.55, 0.9]) + t * np.float32([0.85, 0.92, 1.0])
    if kind == "diag":
        t = ((xx + yy) / (h + w))[..., None]
        return (1 - t) * np.float32([0.95, 0.7, 0.5]) + t * np.float32([0.5, 0.6, 0.85])
    n = cv2.GaussianBlur(np.random.default_rng(1).normal(0, 1, (h, w)).astype(np.float32), (0, 0), 1.2)
    return np.clip(np.float32([0.96, 0.94, 0.88]) + (n / n.std() * 0.02)[..., None], 0, 1)


def _stick(size, kind, jpeg=False):
    """A bark-textured branch leaving the frame on the left, a twig on it; soft edges."""
    h, w = int(0.75 * size), size
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    d = np.full((h, w), np.inf, np.float32)
    for (a, b, hw) in (((-5, 0.62 * h), (0.95 * w, 0.5 * h), 0.03 * size),
                       ((0.45 * w, 0.57 * h), (0.62 * w, 0.2 * h), 0.012 * size)):
        a, b = np.float32(a), np.float32(b)
        ab = b - a
        t = np.clip(((xx - a[0]) * ab[0] + (yy - a[1]) * ab[1]) / (ab @ ab), 0, 1)
        d = np.minimum(d, np.hypot(xx - a[0] - t * ab[0], yy - a[1] - t * ab[1]) - hw)
    alpha = np.clip(0.5 - d, 0, 1)[..., None]
    bark = 0.5 + 0.5 * np.sin(xx / (0.012 * size))
    col = np.stack([0.32 + 0.15 * bark, 0.22 + 0.1 * bark, 0.12 + 0.05 * bark], -1)
    g = _ground(kind, h, w)
    img = (alpha * col + (1 - alpha) * g).astype(np.float32)
    if jpeg:
        _, buf = cv2.imencode(".jpg", (img[..., ::-1] * 255).astype(np.uint8), [cv2.IMWRITE_JPEG_QUALITY, 85])
        img = cv2.imdecode(buf, 1)[..., ::-1].astype(np.float32) / 255
    return img, alpha[..., 0], g


def _iou(a, b):
    return (a & b).sum() / max((a | b).sum(), 1)


@pytest.mark.parametrize("size,kind,jpeg", [(160, "white", False), (400, "sky", False), (400, "diag", True),
                                            (240, "sky", True), (1000, "paper", False)])
def test_matte_separates_the_stick_from_its_ground(size, kind, jpeg):
    img, alpha, g = _stick(size, kind, jpeg)
    m = matte_from_background(img)
    assert m is not None
    assert _iou(m.alpha > 0.5, alpha > 0.5) >= 0.95
    assert np.abs(m.alpha - alpha).mean() <= 0.01
    # one object, no islands of JPEG ringing round it
    n, _ = cv2.connectedComponents((m.alpha > 0.5).astype(np.uint8), connectivity=8)
    assert n == 2
    # the ground behind the object is the ground (a smooth model; paper grain copied, so looser there)
    under = alpha > 0.5
    rms = float(np.sqrt(np.mean((m.background[under] - g[under]) ** 2)))
    assert rms <= (0.035 if kind == "paper" else 0.015)
    # and outside it the input itself
    off = cv2.dilate((alpha > 0).astype(np.uint8), np.ones((7, 7), np.uint8)) == 0
    assert np.sqrt(np.mean((m.background[off] - img[off]) ** 2)) <= 0.004


def test_matte_keeps_a_part_of_nearly_the_grounds_colour_inside_a_thin_outline():
    h, w = 160, 200
    g = np.broadcast_to(np.float32([0.85, 0.78, 0.55]), (h, w, 3)).copy()
    img = g.copy()
    truth = np.zeros((h, w), np.uint8)
    cv2.ellipse(truth, (100, 80), (60, 14), 20, 0, 360, 1, -1)
    img[truth > 0] = (0.96, 0.72, 0.6)  # skin on beige: 0.11 from the ground
    ring = np.zeros((h, w), np.uint8)
    cv2.ellipse(ring, (100, 80), (60, 14), 20, 0, 360, 1, 1, cv2.LINE_AA)
    img = np.where(ring[..., None] > 0, np.float32([0.15, 0.1, 0.08]), img)
    m = matte_from_background(img)
    assert m is not None
    assert _iou(m.alpha > 0.5, (truth | ring) > 0) >= 0.95


def test_small_pocket_of_ground_colour_is_object_a_large_loop_is_ground():
    img = np.ones((200, 200, 3), np.float32)
    cv2.circle(img, (60, 100), 30, (0.2, 0.3, 0.6), -1)
    cv2.circle(img, (60, 100), 5, (1, 1, 1), -1)                 # a white eye: object
    cv2.circle(img, (150, 100), 40, (0.3, 0.2, 0.1), 4)           # a loop of twig round sky: ground inside
    m = matte_from_background(img)
    assert m.alpha[100, 60] == 1.0
    assert m.alpha[100, 150] == 0.0


def test_busy_ground_gives_none():
    rng = np.random.default_rng(0)
    img = cv2.GaussianBlur(rng.uniform(0, 1, (180, 240, 3)).astype(np.float32), (0, 0), 2.0)
    img = np.clip((img - 0.5) * 6 + 0.5, 0, 1)
    img[60:120, 80:160] = (0.3, 0.2, 0.1)
    assert matte_from_background(img) is None


def test_bad_arguments():
    with pytest.raises(ValueError, match="image"):
        matte_from_background(np.ones((4, 20, 3), np.float32))
    with pytest.raises(ValueError, match="tol"):
        matte_from_background(np.ones((20, 20, 3), np.float32), tol=0.0)
    with pytest.raises(ValueError, match="max_noise"):
        matte_from_background(np.ones((20, 20, 3), np.float32), max_noise=2.0)


def test_trees_alpha_from_background_smooth_uses_the_matte():
    from branchnb.trees.exemplar import alpha_from_background

    img, alpha, _ = _stick(300, "sky")
    keyed = alpha_from_background(img)                       # default: one colour, unchanged
    smooth = alpha_from_background(img, background="smooth")
    assert _iou(smooth[..., 3] > 0.5, alpha > 0.5) >= 0.95
    assert _iou(keyed[..., 3] > 0.5, alpha > 0.5) <= 0.5    # a sky gradient is not one colour
    with pytest.raises(ValueError, match="background"):
        alpha_from_background(img, background="sky")
    busy = np.random.default_rng(0).uniform(0, 1, (64, 64, 3)).astype(np.float32)
    with pytest.raises(ValueError, match="not smooth"):
        alpha_from_background(busy, background="smooth")
