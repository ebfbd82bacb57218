"""Thin glows (1-2 px cores, glow sigma 1-1.5 px: a bolt photo shrunk to 128 px) are told apart from
anti-aliased drawn lines (issue 23, branching101: :func:`branchnb.branching.glow.glow_tail`)."""
import cv2
import numpy as np
import pytest

from branchnb.branching import extract_structure, fit_model, synthesize_image, synthesize_structure
from branchnb.branching.glow import THIN_TAIL, glow_model, glow_tail
from branchnb.branching.skeleton_map import SkeletonMap


def _bolt_lines(n, seed):
    rng = np.random.default_rng(seed)

    def walk(p, heading, length):
        pts, a = [np.asarray(p, float)], heading
        while len(pts) * 4.5 < length:
            a = heading + 0.7 * (a - heading) + rng.normal(0, 0.5)
            pts.append(pts[-1] + rng.uniform(3, 6) * np.array([np.cos(a), np.sin(a)]))
        return np.array(pts)

    main = walk((n * rng.uniform(0.3, 0.7), -2.0), np.pi / 2, n)
    return [main, walk(main[len(main) // 3], np.pi / 2 + 0.7, 0.4 * n)]


def _glow(n, seed, core, sigma):
    c = np.zeros((n, n), np.float32)
    cv2.polylines(c, [(p * 4).astype(np.int32) for p in _bolt_lines(n, seed)], False, 1.0, core, cv2.LINE_AA, shift=2)
    img = np.array([0.05, 0.05, 0.15]) + cv2.GaussianBlur(c, (0, 0), sigma)[..., None] * np.array([0.6, 0.36, 1.08]) \
        + c[..., None] * np.array([0.9, 0.9, 1.0])
    return np.clip(img, 0, 1).astype(np.float32)


def _drawn(n, seed, w, kind):
    f = 3 if kind == "shrunk" else 1
    img = np.full((n * f, n * f, 3), 0.95, np.float32)
    lines = [(p * f * 4).astype(np.int32) for p in _bolt_lines(n, seed)]
    if kind == "cased":
        cv2.polylines(img, lines, False, (0.4, 0.4, 0.4), w + 2, cv2.LINE_AA, shift=2)
        cv2.polylines(img, lines, False, (1.0, 0.9, 0.5), w, cv2.LINE_AA, shift=2)
    else:
        cv2.polylines(img, lines, False, (0.1, 0.1, 0.1), w * f, cv2.LINE_AA, shift=2)
    if kind == "shrunk":
        img = cv2.resize(img, (n, n), interpolation=cv2.INTER_AREA)
    if kind == "jpeg":
        ok, buf = cv2.imencode(".jpg", (img * 255).astype(np.uint8), [cv2.IMWRITE_JPEG_QUALITY, 75])
        img = cv2.imdecode(buf, 1).astype(np.float32) / 255
    return img


def _pm(img):
    return SkeletonMap(extract_structure(img), 1.0).pixel_map(img.shape[:2])


@pytest.mark.parametrize("seed, core, sigma", [(0, 1, 1.5), (1, 2, 1.25), (2, 1, 1.25)])
def test_thin_glow_is_a_glow(seed, core, sigma):
    img = _glow(128, seed, core, sigma)
    pm = _pm(img)
    # main: none of these was a glow (its ring 0.45-0.74 under the 0.8 share)
    assert glow_tail(img, pm) >= 1.4 * THIN_TAIL
    assert glow_model(img, pm) is not None


@pytest.mark.parametrize("kind", ["plain", "shrunk", "jpeg", "cased"])
def test_drawn_lines_are_no_thin_glow(kind):
    for seed, w in ((0, 1), (1, 2), (2, 3)):
        img = _drawn(128, seed, w, kind)
        pm = _pm(img)
        assert glow_tail(img, pm) < 0.6 * THIN_TAIL, (seed, w)      # 0.000-0.010
        assert glow_model(img, pm) is None, (seed, w)


@pytest.mark.parametrize("seed, core, sigma", [(1, 2, 1.25), (2, 1, 1.25)])
def test_thin_glow_output_keeps_the_examples_profile(seed, core, sigma):
    img = _glow(128, seed, core, sigma)
    ex = extract_structure(img)
    res = synthesize_structure(fit_model(ex), rng=0)
    out = synthesize_image(img, ex, res, rng=0).image

    def profile(im, s):
        pm = SkeletonMap(s, 1.0).pixel_map(im.shape[:2])
        lum = im[..., :3].mean(axis=2)
        d = np.round(pm.dist).astype(int)
        p = np.array([np.median(lum[d == k]) for k in range(10)])
        return (p[:5] - p[-3:].mean()) / (p[0] - p[-3:].mean())

    pe, po = profile(img, ex), profile(out, res.structure)
    # main (drawn flat): seed 2 0.46 / 0.00 1 / 2 px out for the example's 0.16 / 0.07, seed 1 0.44 / 0.00
    # 2 / 3 px out for 0.28 / 0.10; now within 0.02
    assert np.max(np.abs(pe[1:] - po[1:])) <= 0.03, (pe, po)
    assert po[3] >= 0.01 and po[2] >= 0.05
