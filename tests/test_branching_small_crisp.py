"""Small examples (64-192 px) synthesize as crisp as the example, on a clean ground (issue 23)."""
import warnings

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import synthesize_image
from branchnb.branching.fragment_placement import _sample
from branchnb.branching.regions import matte_mask
from branchnb.core.render import draw_polylines
from branchnb.core.structure import Branch, Structure


def _walk(rng, p, heading, length, step, n):
    pts = [np.asarray(p, float)]
    for _ in range(int(length / step)):
        heading += rng.normal(0, 0.12)
        q = pts[-1] + step * np.array([np.cos(heading), np.sin(heading)])
        if not (3 <= q[0] <= n - 4 and 3 <= q[1] <= n - 4):
            break
        pts.append(q)
    return np.array(pts)


def _neuron(n, seed):
    """A fluorescent neuron: a soma and 6 forking dendrites, green with a glow on a noisy black ground."""
    rng = np.random.default_rng(seed)
    s, c = n / 128.0, np.full(2, n / 2.0)
    soma, step = max(3.0, 0.07 * n), max(1.0, 2.0 * s)
    branches = []
    for i in range(6):
        a = 2 * np.pi * i / 6 + rng.normal(0, 0.3)
        pts = _walk(rng, c + 0.8 * soma * np.array([np.cos(a), np.sin(a)]), a, 0.42 * n, step, n)
        branches.append(Branch(pts, np.linspace(max(1.2, 2.2 * s), max(0.7, 0.9 * s), len(pts))))
        b = len(branches) - 1
        v = len(pts) // 2
        if 2 <= v <= len(pts) - 3:
            t = pts[v + 1] - pts[v - 1]
            kid = _walk(rng, pts[v], np.arctan2(t[1], t[0]) + rng.choice([-1, 1]) * 0.6, 0.22 * n, step, n)
            if len(kid) >= 3:
                branches.append(Branch(kid, np.linspace(max(0.9, 1.4 * s), max(0.6, 0.7 * s), len(kid)), b, v))
    st = Structure(branches, (n, n))
    mask = draw_polylines(np.zeros((n, n, 3), np.float32), [b.points for b in branches],
                          widths=[2 * b.thickness for b in branches], colors=(1, 1, 1))[..., 0].copy()
    cv2.circle(mask, (int(c[0] * 16), int(c[1] * 16)), int(soma * 16), 1.0, -1, cv2.LINE_AA, 4)
    glow = ndi.gaussian_filter(mask, 2.0 * s)
    speckle = ndi.gaussian_filter(rng.normal(0, 1, (n, n)), 0.7)
    inten = np.clip(0.9 * mask + 0.8 * glow, 0, 1) * (0.75 + 0.15 * speckle / speckle.std())
    img = np.clip(0.03 + 0.03 * rng.normal(0, 1, (n, n, 1)), 0, 1) + inten[..., None] * (0.15, 1.0, 0.25)
    return np.clip(img, 0, 1).astype(np.float32), st


def _masks(st, n):
    lines = [b.points for b in st.branches]
    z = np.zeros((n, n, 3), np.float32)
    body = draw_polylines(z, lines, widths=[2 * b.thickness + 2 for b in st.branches], colors=(1, 1, 1))[..., 0] > 0.3
    near = draw_polylines(z, lines, widths=[6 * np.maximum(b.thickness, 1) + 2 for b in st.branches],
                          colors=(1, 1, 1))[..., 0] > 0.01
    return body, ~near


def _lap_var(img, where):
    lap = cv2.Laplacian(img[..., :3].mean(-1).astype(np.float32), cv2.CV_32F, ksize=1)
    return float((lap[where] ** 2).mean())


def test_fragments_are_sampled_without_bilinear_blur():
    rng = np.random.default_rng(0)
    ex = rng.random((64, 64, 3)).astype(np.float32)
    yy, xx = np.mgrid[0:40, 0:40].astype(np.float32) - 20
    inner = np.s_[8:-8, 8:-8]
    for angle in (0.3, 0.7, 1.1):
        c, s = np.cos(angle), np.sin(angle)
        mx = (c * xx - s * yy + 32.3).astype(np.float32)
        my = (s * xx + c * yy + 31.6).astype(np.float32)
        out, valid = _sample(ex, mx, my)
        assert valid.all()
        assert out.min() >= ex.min() and out.max() <= ex.max()      # no ringing past the example's range
        # bilinear kept 0.28-0.30 of a white-noise texture's Laplacian energy; bicubic 0.49-0.55
        lin = cv2.remap(ex, mx, my, cv2.INTER_LINEAR)
        full = np.ones((24, 24), bool)
        ref = _lap_var(ex[inner], np.ones((48, 48), bool))
        assert _lap_var(out[inner], full) / ref >= 0.45
        assert _lap_var(lin[inner], full) / ref < 0.35


def test_a_noisy_black_ground_is_no_matte_but_a_flat_surround_is():
    img, _ = _neuron(96, 0)
    assert not matte_mask(img).any()
    # a photo disc in a flat black surround (a fundus) keeps its matte
    n = 96
    yy, xx = np.mgrid[0:n, 0:n]
    disc = np.hypot(xx - n / 2, yy - n / 2) < 0.45 * n
    rng = np.random.default_rng(1)
    photo = np.where(disc[..., None], (0.8, 0.4, 0.15) + 0.05 * rng.normal(0, 1, (n, n, 3)), 0.0)
    m = matte_mask(np.clip(photo, 0, 1).astype(np.float32), dilate=0)
    assert abs(m.mean() - (~disc).mean()) < 0.01


@pytest.mark.parametrize("n, seed", [(64, 0), (128, 1)])
def test_a_small_neuron_is_crisp_on_a_clean_black_ground(n, seed):
    img, src = _neuron(n, seed)
    _, tgt = _neuron(n, seed + 10)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = synthesize_image(img, src, tgt, rng=seed).image
    body_s, ground_s = _masks(src, n)
    body_t, ground_t = _masks(tgt, n)
    g = np.median(img[ground_s], axis=0)
    spread = float(np.linalg.norm(img[ground_s] - g, axis=1).mean())
    haze = float(np.linalg.norm(out[ground_t][:, :3] - g, axis=1).mean())
    # before: the noisy black was taken for a matte, gap completion copied the glow (haze 2.3-2.6 x)
    assert haze <= 1.5 * spread, (haze, spread)
    # before (bilinear fragments): 0.6-0.8 of the example's Laplacian energy on the branches
    assert _lap_var(out, body_t) >= 0.8 * _lap_var(img, body_s)


def test_line_contrast_keeps_a_wide_lines_texture_and_fills_its_gap():
    from branchnb.branching.line_contrast import line_profile, restore_line_contrast
    from branchnb.branching.skeleton_map import SkeletonMap

    rng = np.random.default_rng(3)
    img = np.full((64, 96, 3), 0.05, np.float32)
    speckle = np.clip(0.7 + 0.2 * rng.normal(0, 1, (9, 92)), 0.2, 1.0)
    img[28:37, 2:94, 1] = speckle                         # a bright speckled line, r = 4.5
    s = Structure([Branch([(2, 32.0), (93, 32.0)], 4.5)])
    pm = SkeletonMap(s, 1.0).pixel_map(img.shape[:2])
    prof = line_profile(img, pm)
    out, _ = restore_line_contrast(img, pm, prof)
    line = np.s_[30:35, 10:86, 1]
    # pixel by pixel, the speckle under 0.85 of the median was raised: std 0.19 -> 0.13
    assert out[line].std() >= 0.9 * img[line].std()
    faded = img.copy()
    faded[28:37, 40:60, 1] = 0.15                          # a gap no fragment covered
    out, _ = restore_line_contrast(faded, pm, prof)
    assert np.median(out[30:35, 44:56, 1]) >= 0.8 * np.median(img[line])
