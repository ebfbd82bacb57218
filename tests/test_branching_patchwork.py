"""Patchwork grounds (flat fields with sharp borders) in image synthesis (issue 23, branching93)."""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import synthesize_image
from branchnb.branching.patchwork import ground_palette, is_patchwork
from branchnb.core.structure import Branch, Structure

PALETTE = np.array([[0.45, 0.55, 0.25], [0.6, 0.6, 0.35], [0.3, 0.42, 0.2], [0.7, 0.62, 0.42], [0.22, 0.35, 0.18]])


def _fields(n, seed, cells=24):
    rng = np.random.default_rng(seed)
    pts = rng.uniform(0, n, (cells, 2))
    yy, xx = np.mgrid[:n, :n]
    lab = np.argmin((xx[..., None] - pts[:, 0]) ** 2 + (yy[..., None] - pts[:, 1]) ** 2, -1)
    img = PALETTE[rng.integers(0, 5, cells)][lab].astype(np.float32)
    return img + cv2.GaussianBlur(rng.normal(0, 0.06, (n, n, 3)).astype(np.float32), (0, 0), 1.0)


def _river(img, points, width, seed):
    n = img.shape[0]
    water = np.zeros((n, n), np.float32)
    cv2.polylines(water, [np.int32(np.round(points * 4))], False, 1.0, int(width), cv2.LINE_AA, shift=2)
    colour = np.array([0.32, 0.42, 0.5], np.float32)
    noise = cv2.GaussianBlur(np.random.default_rng(seed).normal(0, 0.03, (n, n)).astype(np.float32), (0, 0), 2)
    out = img * (1 - water[..., None]) + (colour + noise[..., None]) * water[..., None]
    return np.clip(out, 0, 1).astype(np.float32)


@pytest.mark.parametrize("n", [96, 400])
def test_patchwork_told_from_ramps_and_textures(n):
    rng = np.random.default_rng(1)
    bg = np.ones((n, n), bool)
    assert is_patchwork(_fields(n, 0), bg)
    ramp = np.dstack([np.tile(np.linspace(0.2, 0.8, n), (n, 1))] * 3).astype(np.float32)
    texture = 0.4 + 0.1 * cv2.GaussianBlur(rng.normal(0, 1, (n, n, 3)).astype(np.float32), (0, 0), 2.0) * 3
    yy, xx = np.mgrid[:n, :n]
    dunes = (0.6 + 0.12 * np.sin(2 * np.pi * (xx + 0.6 * yy) / (n / 6)))[..., None] * np.ones(3)
    for img in (ramp, texture, dunes.astype(np.float32), np.full((n, n, 3), 0.5, np.float32)):
        assert not is_patchwork(img, bg)
    colours, shares = ground_palette(_fields(n, 0), bg)
    # every palette colour used is found within the grain's reach
    assert np.min(np.linalg.norm(colours[:, None] - PALETTE[None], axis=2), axis=1)[shares > 0.05].max() < 0.03


def test_ground_palette_rejects_mismatched_shapes():
    with pytest.raises(ValueError, match="background"):
        ground_palette(np.zeros((10, 10, 3)), np.ones((8, 8), bool))


def test_patchwork_ground_synthesized_sharp():
    """A river over fields: the output's ground is the example's field colours, not a blurred mix."""
    n = 160
    t = np.linspace(0, 1, 40)
    src_pts = np.stack([n * (0.45 + 0.1 * np.sin(3 * t)), -2 + (n + 4) * t], 1)
    tgt_pts = np.stack([-2 + (n + 4) * t, n * (0.5 + 0.12 * np.sin(4 * t))], 1)
    img = _river(_fields(n, 3), src_pts, 7, 3)
    inside = lambda p: p[(p[:, 0] >= 0) & (p[:, 0] <= n - 1) & (p[:, 1] >= 0) & (p[:, 1] <= n - 1)]  # noqa: E731
    src = Structure([Branch(inside(src_pts), 3.5)], image_shape=(n, n))
    tgt = Structure([Branch(inside(tgt_pts), 3.5)], image_shape=(n, n))
    out = synthesize_image(img, src, tgt, rng=0).image[..., :3]
    yy, xx = np.mgrid[:n, :n]
    d = np.min(np.hypot(xx[..., None] - tgt_pts[:, 0], yy[..., None] - tgt_pts[:, 1]), -1)
    ground = d > 10
    near = np.min(np.linalg.norm(out[ground][:, None] - PALETTE[None], axis=2), axis=1)
    # blur band: ground pixels far from every field colour (the example has none; blurred/relit
    # grounds had 7-12 %)
    assert np.mean(near > 0.1) < 0.02
    # the field borders stay sharp: few pixels of the smoothed output lie between two field colours
    sm = cv2.medianBlur(np.ascontiguousarray(out), 5)[ndi.binary_erosion(ground, iterations=3)]
    assert np.mean(np.min(np.linalg.norm(sm[:, None] - PALETTE[None], axis=2), axis=1) > 0.05) < 0.1
    # the river keeps its colour on the target's centre line
    centre = out[np.round(tgt_pts[2:-2, 1]).astype(int), np.round(tgt_pts[2:-2, 0]).astype(int)]
    assert np.linalg.norm(np.median(centre, axis=0) - [0.32, 0.42, 0.5]) < 0.06
