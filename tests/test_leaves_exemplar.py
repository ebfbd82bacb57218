"""Leaf exemplars at the door, keypoints on edges, texture correction."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from branchnb import data
from branchnb.core.metrics import iou
from branchnb.core.warp import remap
from branchnb.leaves import (
    blade_mask,
    correct_texture,
    distorted_pixels,
    edge_keypoints,
    jacobian_singular_values,
    leaf_exemplar,
    leaf_family,
    prepare_exemplars,
    procedural_leaf,
)
from branchnb.leaves.keypoints import INTERIOR, OUTLINE


@pytest.mark.parametrize("kind", ["lobed", "elliptic"])
@pytest.mark.parametrize("background", [(1.0, 1.0, 1.0), (0.85, 0.8, 0.7)])
def test_leaf_on_plain_background_is_found(kind, background):
    leaf = procedural_leaf(kind, size=128, rng=7)
    a = leaf.image[..., 3:4]
    opaque = leaf.image[..., :3] * a + np.asarray(background, np.float32) * (1 - a)
    ex = leaf_exemplar(opaque)
    assert ex.mask_source == "background"
    assert iou(ex.blade, leaf.blade) > 0.93
    # The same image as uint8 works too.
    assert iou(leaf_exemplar((opaque * 255).round().astype(np.uint8)).blade, leaf.blade) > 0.93


def test_rgba_leaf_uses_alpha():
    leaf = procedural_leaf(size=96, rng=1)
    ex = leaf_exemplar(leaf.image)
    assert ex.mask_source == "alpha" and np.array_equal(ex.blade, leaf.blade)
    assert ex.rgba.shape == (96, 96, 4)


def test_photographed_maple_leaves_on_white():
    # The photos are cut-outs; over white they must be found again by the background model.
    for name in ("maple_leaf_01", "maple_leaf_05"):
        img = data.load(name)
        a = img[..., 3:4]
        white = img[..., :3] * a + (1 - a)
        assert iou(blade_mask(white), img[..., 3] > 0.5) > 0.9


def test_busy_background_is_rejected():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="busy background"):
        leaf_exemplar(rng.random((80, 80, 3)))
    # A plain but leafless image.
    with pytest.raises(ValueError, match="uniform|no leaf"):
        leaf_exemplar(np.full((40, 40, 3), 0.5))
    # A half-and-half image: the "leaf" would cover most of the border.
    img = np.ones((60, 60, 3))
    img[:, 30:] = (0.2, 0.5, 0.1)
    with pytest.raises(ValueError):
        leaf_exemplar(img)


@settings(max_examples=25, deadline=None)
@given(st.sampled_from([(0,), (5, 5, 2), (3, 3, 3, 3), (8, 8, 5)]))
def test_bad_shapes_raise_value_error(shape):
    with pytest.raises(ValueError):
        leaf_exemplar(np.zeros(shape))


def test_bad_dtypes():
    with pytest.raises(TypeError):
        leaf_exemplar(np.zeros((20, 20, 3), np.int32))
    with pytest.raises(TypeError):
        leaf_exemplar(np.array([["a"]]))
    with pytest.raises(ValueError, match="values in"):
        leaf_exemplar(np.full((20, 20, 3), 2.0))


def test_exemplar_sets():
    fam = leaf_family(2, size=64, rng=0)
    big = procedural_leaf(size=100, rng=3)
    with pytest.raises(ValueError, match="at least 2"):
        prepare_exemplars([fam[0].image])
    with pytest.raises(ValueError, match="single image"):
        prepare_exemplars(fam[0].image)
    with pytest.raises(ValueError, match="size_policy"):
        prepare_exemplars([f.image for f in fam], size_policy="crop")
    kept = prepare_exemplars([fam[0].image, big.image])
    assert [e.shape for e in kept] == [(64, 64), (100, 100)]
    padded = prepare_exemplars([fam[0].image, big.image], size_policy="pad")
    assert padded[0].shape == padded[1].shape
    # Padding never resamples: the blade keeps its pixel count.
    assert padded[0].blade.sum() == fam[0].blade.sum()
    resized = prepare_exemplars([fam[0].image, big.image], size_policy="resize")
    assert resized[0].shape == resized[1].shape
    ratio = resized[1].blade.sum() / resized[0].blade.sum()
    assert 0.9 < ratio < 1.1


def test_keypoints_spread_over_the_leaf():
    leaf = procedural_leaf("lobed", size=256, rng=2)
    kp = edge_keypoints(leaf.on_white(), leaf.blade, 100)
    assert 80 <= len(kp) <= 100
    assert set(np.unique(kp.labels)) == {OUTLINE, INTERIOR}
    x, y = np.round(kp.points).astype(int).T
    # Interior points lie on the leaf, the strongest on structure edges (veins, spots).
    inner = kp.labels == INTERIOR
    assert leaf.blade[y[inner], x[inner]].all()
    structure = leaf.layers["veins"] | leaf.layers["spots"]
    from scipy import ndimage as ndi

    near = ndi.binary_dilation(structure, iterations=3) | ndi.binary_dilation(~leaf.blade, iterations=3)
    # (points come strongest first; the weaker ones also take texture edges)
    hits = near[y[inner], x[inner]]
    assert hits[: len(hits) // 2].mean() > 0.8, hits
    # Spread: every quadrant of the blade's bounding box holds some points.
    ys, xs = np.nonzero(leaf.blade)
    cx, cy = xs.mean(), ys.mean()
    quads = [(x < cx) & (y < cy), (x >= cx) & (y < cy), (x < cx) & (y >= cy), (x >= cx) & (y >= cy)]
    assert min(q.sum() for q in quads) >= 10
    # Minimum spacing of the interior points.
    p = kp.points[inner]
    d = np.hypot(*(p[:, None] - p[None]).transpose(2, 0, 1))
    d[np.arange(len(p)), np.arange(len(p))] = np.inf
    assert d.min() > 5


def test_keypoints_bad_input():
    with pytest.raises(ValueError, match="blade"):
        edge_keypoints(np.ones((20, 20, 3)), np.zeros((20, 20), bool))
    with pytest.raises(ValueError, match="n_points"):
        edge_keypoints(np.ones((20, 20, 3)), np.ones((20, 20), bool), 2)
    with pytest.raises(ValueError, match="blade"):
        edge_keypoints(np.ones((20, 20, 3)), np.ones((10, 20), bool))


def test_singular_values_and_distortion_band():
    yy, xx = np.mgrid[0:32, 0:32].astype(float)
    a = np.deg2rad(30)
    # A rotation scaled by 2 (no distortion) vs an anisotropic squeeze.
    mx = 2 * (np.cos(a) * xx - np.sin(a) * yy)
    my = 2 * (np.sin(a) * xx + np.cos(a) * yy)
    s = jacobian_singular_values(np.dstack([mx, my]))
    assert np.allclose(s[5:-5, 5:-5], 2.0, atol=1e-6)
    bad, scale = distorted_pixels(np.dstack([mx, my]))
    assert not bad.any() and abs(scale - 2.0) < 1e-6
    with pytest.raises(ValueError, match="band"):
        distorted_pixels(np.dstack([mx, my]), band=(2.0, 3.0))
    with pytest.raises(ValueError, match="warp_map"):
        jacobian_singular_values(np.zeros((4, 4, 3)))


def test_texture_correction_restores_the_grain():
    # A striped texture warped with a strong local stretch: the stretched
    # stripes are wide; correction replaces them by stripes of the
    # original width from the unwarped source.
    h = w = 96
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    src = np.dstack([0.5 + 0.4 * np.sin(xx * 2 * np.pi / 6)] * 3).astype(np.float32)
    mx = np.where(xx < 48, xx, 48 + 0.3 * (xx - 48)).astype(np.float32)
    warped, _ = remap(src, mx, yy)
    res = correct_texture(warped, np.dstack([mx, yy]), src, rng=0)
    assert res.replaced[:, 60:].mean() > 0.95 and not res.replaced[:, :40].any()
    assert np.array_equal(res.image[:, :40], warped[:, :40])

    def stripe_period(img):
        row = img[48, 60:90, 0] - img[48, 60:90, 0].mean()
        spec = np.abs(np.fft.rfft(row, 300))
        return 300 / (np.argmax(spec[1:]) + 1)

    assert stripe_period(warped) > 12  # stretched: period 20
    assert abs(stripe_period(res.image) - 6) < 1.5
    with pytest.raises(ValueError, match="warp_map"):
        correct_texture(warped, np.zeros((10, 10, 2)), src)


def _on_paper_with_shadow(kind, hue, shadow, *, size=128, paper=(1.0, 1.0, 1.0), rng=0):
    """A procedural leaf recoloured to ``hue`` on ``paper`` with a grey drop or soft cast shadow."""
    import cv2
    leaf = procedural_leaf(kind, size=size, rng=rng)
    a = leaf.image[..., 3]
    y = leaf.image[..., :3] @ np.array([0.3, 0.59, 0.11], np.float32)
    col = np.clip((y / y[leaf.blade].mean())[..., None] * np.asarray(hue, np.float32), 0, 1)
    d = 8 * size / 256 if shadow == "drop" else 10 * size / 256  # 4-10 px on a 128-256 px leaf
    sh = cv2.warpAffine(a, np.float32([[1, 0, d], [0, 1, 0.6 * d]]), (size, size))
    sh = cv2.GaussianBlur(sh, (0, 0), 0.7 if shadow == "drop" else 4 * size / 256)
    canvas = np.asarray(paper, np.float32) * (1 - 0.45 * sh)[..., None]
    img = col * a[..., None] + canvas * (1 - a[..., None])
    noise = np.random.default_rng(rng).normal(0, 0.01, img.shape)  # a photo's sensor noise
    return np.clip(img + noise, 0, 1).astype(np.float32), leaf.blade


@pytest.mark.parametrize("kind,hue,shadow,paper", [
    ("lobed", (0.2, 0.5, 0.15), "drop", (1.0, 1.0, 1.0)),        # green clip art
    ("trilobed", (0.72, 0.14, 0.1), "cast", (0.93, 0.9, 0.82)),  # red, photo on cream paper
    ("elliptic", (0.45, 0.29, 0.16), "drop", (1.0, 1.0, 1.0)),   # brown
    ("elliptic", (0.45, 0.29, 0.16), "cast", (0.93, 0.9, 0.82)),  # brown (3.7 % shadow kept before)
    ("lobed", (0.48, 0.44, 0.39), "drop", (1.0, 1.0, 1.0)),      # dry grey-brown (10.7 % before)
])
def test_blade_excludes_drop_and_cast_shadows(kind, hue, shadow, paper):
    # A soft cast shadow is a grey band under 3 px wide on a 128 px leaf, as thin as a drawing's
    # anti-aliased outline (which must stay leaf): it is measured on a 192 px leaf.
    img, truth = _on_paper_with_shadow(kind, hue, shadow, paper=paper, rng=3, size=192 if shadow == "cast" else 128)
    blade = blade_mask(img)
    assert iou(blade, truth) > 0.96
    assert (blade & ~truth).sum() < 0.025 * truth.sum()  # shadow taken as leaf
    assert (truth & ~blade).sum() < 0.015 * truth.sum()  # no leaf lost with the shadow


def test_grey_leaf_and_ink_outline_are_no_shadow():
    # A grey-brown leaf on cream paper is as grey as a shadow: kept whole.
    img, truth = _on_paper_with_shadow("elliptic", (0.5, 0.47, 0.42), "drop", paper=(0.93, 0.9, 0.82), rng=1)
    assert (truth & ~blade_mask(img)).sum() < 0.01 * truth.sum()
    # A leaf drawn with a grey outline all around (no shadow): the outline stays leaf.
    leaf = procedural_leaf("lobed", size=128, rng=2)
    import cv2
    ring = cv2.dilate(leaf.blade.astype(np.uint8), np.ones((7, 7), np.uint8)).astype(bool) & ~leaf.blade
    img = np.ones((128, 128, 3), np.float32)
    img[leaf.blade] = (0.2, 0.5, 0.15)
    img[ring] = 0.55
    assert iou(blade_mask(img), leaf.blade | ring) > 0.97
    # The drawn sample maples (black ink, anti-aliased) lose nothing.
    for name, n in (("maple_sketch_leaf_1", 119866), ("maple_sketch_leaf_2", 97335)):
        assert abs(int(blade_mask(data.load(name)[..., :3]).sum()) - n) < 0.005 * n
