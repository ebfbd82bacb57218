"""Glowing lines on a flat-ground example (a bolt with a violet glow on a smooth night sky over a black
skyline) are synthesized with their glow and leave no ghost of the example's lines (issue 23)."""

import cv2
import numpy as np
import pytest

from branchnb.branching import extract_structure, fit_model, synthesize_image, synthesize_structure
from branchnb.branching.glow import glow_model, glowing_share
from branchnb.branching.skeleton_map import SkeletonMap
from branchnb.core.structure import Branch, Structure


def _storm(w=384, seed=5):
    """A horizontal jagged bolt (white core, violet glow, sigma w/150) on a gradient sky over a skyline."""
    h = w // 3
    rng = np.random.default_rng(seed)
    yy = np.mgrid[:h, :w][0]
    img = np.dstack([0.05 + 0.1 * yy / h, 0.04 + 0.05 * yy / h, 0.15 + 0.1 * yy / h]).astype(np.float32)
    core = np.zeros((h, w), np.float32)
    pts = [np.array([-2.0, h * 0.35])]
    while pts[-1][0] < w * 0.9:
        a = 0.05 + rng.normal(0, 0.5)
        pts.append(pts[-1] + 4 * np.array([np.cos(a), np.sin(a)]))
    pts = np.array(pts)
    cv2.polylines(core, [(pts * 4).astype(np.int32)], False, 1.0, 2, cv2.LINE_AA, shift=2)
    sigma = w / 150
    glow = cv2.GaussianBlur(core, (0, 0), sigma)
    img = img + glow[..., None] * np.array([0.5, 0.3, 0.9]) * 1.2 + core[..., None] * np.array([0.9, 0.9, 1.0])
    img[int(h * 0.85):] = (0.03, 0.03, 0.05)
    return np.clip(img, 0, 1).astype(np.float32), sigma


def _profile(img, pm, n):
    lum = img[..., :3].mean(axis=2)
    d = np.round(pm.dist).astype(int)
    p = np.array([np.median(lum[d == k]) for k in range(n + 4)])
    return (p[:n] - p[-3:].mean()) / (p[0] - p[-3:].mean())


@pytest.fixture(scope="module")
def storm():
    img, sigma = _storm()
    ex = extract_structure(img)
    res = synthesize_structure(fit_model(ex), rng=0)
    out = synthesize_image(img, ex, res, rng=0).image
    return img, sigma, ex, res.structure, out


def test_glow_carried_and_no_ghost(storm):
    img, sigma, ex, tgt, out = storm
    shape = img.shape[:2]
    pm_s = SkeletonMap(ex, 1.0).pixel_map(shape)
    pm_t = SkeletonMap(tgt, 1.0).pixel_map(shape)
    n = int(np.ceil(3 * sigma)) + 1
    # the luminance profile across the output's lines is the example's out to 3x the glow width
    pe, po = _profile(img, pm_s, n), _profile(out, pm_t, n)
    assert np.max(np.abs(pe[2:] - po[2:])) <= 0.2
    assert po[3] >= 0.1                      # a glow, not a bare core (it fell to ~0 before)
    # no ghost: the output's sky along the example's bolt, far from the output's lines, is like its sky
    lum = out[..., :3].mean(axis=2)
    far = pm_t.dist > 3 * sigma + 6
    sky = np.zeros(shape, bool)
    sky[: int(shape[0] * 0.8)] = True
    along = (pm_s.dist <= sigma) & far & sky
    ctrl = (pm_s.dist > 3 * sigma + 6) & (np.abs(pm_s.dist - 3 * sigma - 12) < 6) & far & sky
    assert along.sum() > 50
    assert abs(np.median(lum[along]) - np.median(lum[ctrl])) < 0.02   # was 0.14
    # the sky stays smooth: gradient of the output's ground at most 1.5x the example's
    def grad(im):
        gy, gx = np.gradient(cv2.GaussianBlur(im[..., :3].mean(axis=2), (0, 0), 1.0))
        return np.hypot(gx, gy)
    ge = grad(img)[(pm_s.dist > 3 * sigma + 6) & sky].mean()
    go = grad(out)[far & sky].mean()
    assert go <= 1.5 * ge + 1e-4
    # the skyline stays where the example has it
    assert np.abs(out[-3:, :, :3] - img[-3:, :, :3]).max() < 0.05


def test_drawn_lines_do_not_glow():
    img = np.full((80, 120, 3), 0.9, np.float32)
    img[60:] = 0.3
    cv2.polylines(img, [np.array([[5, 30], [60, 20], [115, 35]], np.int32)], False, (0.1, 0.2, 0.8), 2,
                  cv2.LINE_AA)
    s = Structure([Branch([(5, 30), (60, 20), (115, 35)], 1.0)])
    pm = SkeletonMap(s, 1.0).pixel_map((80, 120))
    assert glowing_share(img, pm) < 0.5
    assert glow_model(img, pm) is None
    blurred = img.copy()
    glow = cv2.GaussianBlur((img[..., 2] - img[..., 0] > 0.3).astype(np.float32), (0, 0), 3.0)
    blurred[:60] += 0.5 * glow[:60, :, None]
    m = glow_model(np.clip(blurred, 0, 1), pm)
    assert m is not None and m.reach >= 5


def test_glow_on_one_plain_ground():
    """A glowing cell on plain black (one flat region, the textured path before) keeps its glow."""
    rng = np.random.default_rng(3)
    s = 160
    core = np.zeros((s, s), np.float32)
    for a in (0.3, 2.2, 4.2):
        p = [np.array([s / 2, s / 2])]
        for _ in range(18):
            b = a + rng.normal(0, 0.4)
            p.append(p[-1] + 3.5 * np.array([np.cos(b), np.sin(b)]))
        cv2.polylines(core, [(np.array(p) * 4).astype(np.int32)], False, 1.0, 2, cv2.LINE_AA, shift=2)
    img = 0.02 + cv2.GaussianBlur(core, (0, 0), 4.0)[..., None] * np.array([0.2, 1.0, 0.3]) * 1.5 \
        + core[..., None] * np.array([0.5, 1.0, 0.5])
    img = np.clip(img, 0, 1).astype(np.float32)
    ex = extract_structure(img)
    res = synthesize_structure(fit_model(ex), rng=1)
    out = synthesize_image(img, ex, res, rng=1).image
    pm_s = SkeletonMap(ex, 1.0).pixel_map(img.shape[:2])
    pm_t = SkeletonMap(res.structure, 1.0).pixel_map(img.shape[:2])
    pe, po = _profile(img, pm_s, 9), _profile(out, pm_t, 9)
    assert po[4] >= 0.5 * pe[4] and po[4] > 0.05          # the glow reaches as far (it ended at ~3 px)
    assert np.max(np.abs(pe[3:] - po[3:])) <= 0.2
