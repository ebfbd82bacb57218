"""Bare (leafless) trees mix by envelope warp: limbs joined, twigs thin, edges soft (issue 24)."""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi
from skimage.morphology import skeletonize

from branchnb import data
from branchnb.trees import TreeLibrary
from branchnb.trees.bare import bare_mix, is_bare_alpha, soft_image


def _line(img, p, q, w):
    m = w + 3
    x0, y0 = int(max(min(p[0], q[0]) - m, 0)), int(max(min(p[1], q[1]) - m, 0))
    x1, y1 = int(min(max(p[0], q[0]) + m, img.shape[1])), int(min(max(p[1], q[1]) + m, img.shape[0]))
    if x1 <= x0 or y1 <= y0:
        return
    t = np.zeros((y1 - y0, x1 - x0), np.uint8)
    cv2.line(t, (round((p[0] - x0) * 16), round((p[1] - y0) * 16)),
             (round((q[0] - x0) * 16), round((q[1] - y0) * 16)), 255, w, cv2.LINE_AA, 4)
    np.maximum(img[y0:y1, x0:x1], t, out=img[y0:y1, x0:x1])     # strokes never erase each other


def bare_tree(h, shape, seed, two_tone=False):
    """A forking, tapering bare tree drawn anti-aliased (6 levels, 1 px twigs)."""
    rng = np.random.default_rng(seed)
    a = np.zeros((h, h), np.uint8)
    lit = np.zeros((h, h), np.uint8)
    spread = {"round": (0.35, 0.65), "weeping": (0.5, 0.8), "asym": (0.2, 0.6)}[shape]

    def grow(x, y, ang, length, width, depth):
        if shape == "weeping" and depth <= 3:
            ang -= 0.35
        x2, y2 = x + np.cos(ang) * length, y - np.sin(ang) * length
        wi = max(1, int(round(width)))
        _line(a, (x, y), (x2, y2), wi)
        if wi >= 3:
            _line(lit, (x + wi / 4, y), (x2 + wi / 4, y2), max(1, wi // 2))
        if depth == 0 or width < 1:
            return
        for s in (-1, 1):
            bias = 0.25 if shape == "asym" and s > 0 else 0.0
            grow(x2, y2, ang + s * rng.uniform(*spread) + bias, length * rng.uniform(0.65, 0.8),
                 width * 0.65, depth - 1)

    grow(h / 2, h * 0.97, np.pi / 2, h * 0.27, h / 22, 6)
    al, li = a / 255.0, (lit / 255.0 * (a / 255.0))[..., None]
    img = np.zeros((h, h, 4), np.float32)
    base = np.array([0.32, 0.27, 0.23])
    img[..., :3] = base * (1 - li) + np.array([0.62, 0.55, 0.45]) * li if two_tone else base
    img[..., 3] = al
    return img


def _twig_width(img):
    a = img[..., 3]
    sk = skeletonize(a > 0.5)
    k = np.ones((7, 7), np.float32)
    wid = np.sort((cv2.filter2D(a, -1, k, borderType=cv2.BORDER_CONSTANT)
                   / np.maximum(cv2.filter2D(sk.astype(np.float32), -1, k, borderType=cv2.BORDER_CONSTANT), 1))[sk])
    return float(np.median(wid[:max(1, len(wid) // 5)]))


def _soft_share(img):
    a = img[..., 3]
    rim = (a > 0.02) & cv2.dilate((a <= 0.02).astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    return float(((a < 0.95) & rim).sum() / max(rim.sum(), 1))


@pytest.fixture(scope="module")
def bare_lib():
    lib = TreeLibrary()
    for i, sh in enumerate(("round", "weeping", "asym")):
        lib.add(bare_tree(160, sh, 10 + i, two_tone=i == 1), sh)
    return lib


def test_bare_detection():
    assert is_bare_alpha(bare_tree(128, "round", 0)[..., 3])
    lib = TreeLibrary(size=128)
    for n in ("tree_rpg_05", "palm_silhouette", "tree_cutout_broadleaf"):
        assert not is_bare_alpha(lib.add(data.load(n), n).image[..., 3]), n
    with pytest.raises(ValueError, match="alpha"):
        is_bare_alpha(np.zeros((4, 4, 3)))


def test_bare_mixes_connected_thin_soft(bare_lib):
    srcs = [soft_image(e.image, e.normalized.soft_alpha) for e in bare_lib.exemplars]
    twig0 = np.median([_twig_width(s) for s in srcs])
    soft0 = np.median([_soft_share(s) for s in srcs])
    mixes = [bare_lib.variation(rng=s).image for s in range(3)]
    mixes += [v.image for v in bare_lib.variations_of("round", n=2, rng=0)]
    for m in mixes:
        op = m[..., 3] > 0.5
        lab, n = ndi.label(op, structure=np.ones((3, 3)))
        areas = np.bincount(lab.ravel())[1:]
        assert areas.max() >= 0.95 * areas.sum()
        # every limb wider than 2 px lies on the trunk's piece
        foot = lab[np.nonzero(op)[0].max()][op[np.nonzero(op)[0].max()]][0]
        sk = skeletonize(op) & (2 * ndi.distance_transform_edt(op) > 2.5)
        assert (lab[sk] == foot).mean() >= 0.99
        assert 0.8 <= _twig_width(m) / twig0 <= 1.5
        assert 0.7 <= _soft_share(m) / soft0 <= 1.3


def test_bare_mix_identity_and_errors():
    img = bare_tree(96, "round", 3)
    out, src, _ = bare_mix([img, img], [0.5, 0.5], [0.5, 0.5])
    assert np.abs(out[..., 3] - img[..., 3]).mean() < 1e-3     # equal envelopes: no warp
    assert set(np.unique(src)) <= {-1, 0}
    with pytest.raises(ValueError, match="weights"):
        bare_mix([img, img], [1.0], [0.5, 0.5])


def test_hard_edged_bare_mixes_stay_hard_and_joined():
    lib = TreeLibrary()
    srcs = []
    for i, sh in enumerate(("round", "weeping", "asym")):
        t = bare_tree(160, sh, 20 + i)
        t[..., 3] = t[..., 3] >= 0.5             # a hard-edged, one-colour drawing (pixel art)
        srcs.append(lib.add(t, sh).image)
    twig0 = np.median([_twig_width(s) for s in srcs])
    for s in range(3):
        m = lib.variation(rng=s).image
        assert set(np.unique(m[..., 3])) <= {0.0, 1.0}
        lab, _ = ndi.label(m[..., 3] > 0.5, structure=np.ones((3, 3)))
        areas = np.bincount(lab.ravel())[1:]
        assert areas.max() >= 0.95 * areas.sum()
        assert 0.8 <= _twig_width(m) / twig0 <= 1.5
