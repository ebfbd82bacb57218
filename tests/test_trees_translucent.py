"""Translucent (watercolour, airbrushed, glass) sources give whole, translucent crowns (issue 24, trees47)."""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi
from skimage.color import rgb2lab

from branchnb.trees import TreeLibrary
from branchnb.trees.synthetic import SYNTHETIC_KINDS, synthetic_tree
from branchnb.trees.translucent import from_working_alpha, to_working_alpha, translucent_level


def translucent_tree(kind, seed, h):
    """RGBA tree with a translucent crown, and its crown mask: ``watercolour`` (wash ~0.4, pooled
    rim ~0.7, paper grain), ``airbrush`` (opaque core, wide soft halo) or ``glass`` (alpha 0.3
    everywhere, trunk too)."""
    rng = np.random.default_rng(seed)
    cx = h / 2 + rng.normal(0, h * 0.03)
    crown = np.zeros((h, h), np.float32)
    for _ in range(rng.integers(4, 8)):
        c = (int(cx + rng.normal(0, h * 0.12)), int(h * 0.33 + rng.normal(0, h * 0.07)))
        cv2.ellipse(crown, c, (int(h * rng.uniform(0.1, 0.18)), int(h * rng.uniform(0.08, 0.14))),
                    rng.uniform(0, 180), 0, 360, 1.0, -1)
    trunk = np.zeros((h, h), np.float32)
    cv2.line(trunk, (int(cx), int(h * 0.95)), (int(cx + rng.normal(0, h * 0.02)), int(h * 0.42)), 1.0,
             max(2, h // 28), cv2.LINE_AA)
    col = np.array([0.45, 0.6, 0.2], np.float32)
    bark = np.array([0.35, 0.22, 0.12], np.float32)
    grain = cv2.GaussianBlur(rng.normal(0, 1, (h, h)).astype(np.float32), (0, 0), 0.7)
    if kind == "watercolour":
        cm = crown > 0.5
        dist = cv2.distanceTransform(cm.astype(np.uint8), cv2.DIST_L2, 5)
        dens = np.clip(0.45 + 0.4 * np.exp(-dist / (h / 60)) + 0.08 * grain, 0, 1) * cm
        ca, crgb = dens * 0.85, col * (1 - 0.5 * dens[..., None])
    elif kind == "airbrush":
        core = cv2.erode(crown, np.ones((max(3, h // 20),) * 2, np.uint8))
        ca = np.clip(cv2.GaussianBlur(core, (0, 0), h / 30) * 1.4, 0, 1)
        cm, crgb = ca > 0.05, np.broadcast_to(col, (h, h, 3))
    else:
        cm = crown > 0.5
        ca = (0.3 + 0.02 * grain) * cm
        crgb = np.broadcast_to(np.array([0.45, 0.75, 0.85], np.float32), (h, h, 3))
        bark = np.array([0.5, 0.6, 0.7], np.float32)
    tm = trunk > 0.5
    ta = np.clip(trunk, 0, 1) * (0.3 if kind == "glass" else 1.0)
    a = np.clip(np.where(tm, np.maximum(ta, ca), ca + ta * (1 - ca)), 0, 1)
    rgb = np.where(tm[..., None], bark, crgb)
    return np.dstack([rgb, a]).astype(np.float32), cm & ~tm


def _white(img):
    return img[..., :3] * img[..., 3:] + 1 - img[..., 3:]


@pytest.mark.parametrize("kind", ["watercolour", "airbrush", "glass"])
@pytest.mark.parametrize("h", [96, 300])
def test_translucent_sources_detected(kind, h):
    img, _ = translucent_tree(kind, 1, h)
    level = translucent_level(img[..., 3])
    assert 0.05 <= level < 0.35


@pytest.mark.parametrize("kind", SYNTHETIC_KINDS)
def test_opaque_sources_keep_threshold(kind):
    # anti-aliased edges, cast shadows, ground clutter: no translucent crown
    for size in (64, 256):
        assert translucent_level(synthetic_tree(kind, rng=0, size=size).image[..., 3]) == 0.5


def test_cast_shadow_is_not_a_wash():
    img = np.zeros((120, 120, 4), np.float32)
    cv2.circle(img, (60, 40), 30, (0.2, 0.6, 0.2, 1.0), -1)
    img[60:100, 56:64] = (0.4, 0.25, 0.1, 1.0)
    sh = np.zeros((120, 120), np.float32)
    cv2.ellipse(sh, (60, 102), (40, 9), 0, 0, 360, 0.3, -1)
    img[..., 3] = np.maximum(img[..., 3], sh)
    assert translucent_level(img[..., 3]) == 0.5


def test_working_alpha_round_trip():
    a = np.linspace(0, 1, 101, dtype=np.float32)
    w = to_working_alpha(a, 0.2)
    assert w[20] == pytest.approx(0.5) and w[0] == 0 and w[-1] == pytest.approx(1.0)
    assert np.allclose(from_working_alpha(w, 0.2), a, atol=1e-6)


@pytest.mark.parametrize("kind", ["watercolour", "glass"])
def test_translucent_mix_whole_and_translucent(kind):
    trees = [translucent_tree(kind, s, 128) for s in range(3)]
    lib = TreeLibrary()
    for i, (img, _) in enumerate(trees):
        lib.add(img, f"t{i}")
    assert all(e.normalized.alpha_level < 0.5 for e in lib.exemplars)
    src_alpha = np.mean([img[..., 3][cm].mean() for img, cm in trees])
    src_lab = np.mean([rgb2lab(_white(img)[cm][None])[0].mean(0) for img, cm in trees], axis=0)
    for seed in range(2):
        v = lib.variation(rng=seed)
        # inside the mixed contour (and any hole of the alpha: a hollow crown's inside), 3 px in
        shape = v.mask | (cv2.morphologyEx((v.image[..., 3] > 0.02).astype(np.uint8), cv2.MORPH_CLOSE,
                                           np.ones((5, 5), np.uint8)) > 0)
        inner = cv2.erode(ndi.binary_fill_holes(shape).astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
        trunk = cv2.dilate((v.parts == 2).astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
        crown = inner & ~trunk
        a = v.image[..., 3]
        assert (a[crown] < 0.05).mean() < 0.02          # no hollow crown
        assert abs(a[crown].mean() - src_alpha) < 0.1   # as translucent as the sources
        lab = rgb2lab(_white(v.image)[crown][None])[0].mean(0)
        assert np.linalg.norm(lab - src_lab) < 8        # same colour on paper


def test_opaque_mix_unchanged_by_translucent_path():
    lib = TreeLibrary()
    for s in range(3):
        lib.add(synthetic_tree("clean", rng=s, size=128).image, f"c{s}")
    assert all(e.normalized.alpha_level == 0.5 for e in lib.exemplars)
    a = lib.variation(rng=0).image[..., 3]
    assert set(np.unique(a).tolist()) <= {0.0, 1.0}


def _halo_width(img):
    """95th percentile distance (px) of the faint painted pixels from the crown's core (alpha at
    least half the median of the painted pixels)."""
    a = img[..., 3]
    core = a >= 0.5 * np.median(a[a > 0.1])
    core = cv2.morphologyEx(core.astype(np.uint8), cv2.MORPH_CLOSE, np.ones((3, 3), np.uint8)) > 0
    dist = cv2.distanceTransform((~core).astype(np.uint8), cv2.DIST_L2, 5)
    soft = ~core & (a > 0.02)
    return float(np.percentile(dist[soft], 95)) if soft.any() else 0.0


def test_airbrushed_mix_halo_as_wide_as_the_sources():
    """trees48: a warp stretching an airbrushed rim spread the mix's halo to 1.7-1.9x the sources'
    (12 px against 7 at 128, 25 against 14 at 256)."""
    lib = TreeLibrary(size=128)
    for s in range(3):
        lib.add(translucent_tree("airbrush", 4 + s, 300)[0], f"a{s}")
    src = max(_halo_width(np.dstack([e.image[..., :3], e.normalized.soft_alpha])) for e in lib.exemplars)
    for seed in range(3):
        v = lib.variation(rng=seed)
        assert _halo_width(v.image) <= 1.5 * src, (seed, _halo_width(v.image), src)
        # the core stays: the crown is not thinned to a faint disc
        assert (v.image[..., 3] >= 0.9).sum() >= 0.3 * (v.image[..., 3] > 0.02).sum()
