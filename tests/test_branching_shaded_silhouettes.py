"""Silhouettes of one solid ink on a smooth shaded ground (issue 23; beyond the paper, .smooth_ground).

A winter tree against a sky gradient: its plain mask traces as one tree rooted at the trunk; the ridge
route broke the trunk from its twigs (five pieces, the crown rooted inside) and the maps' rule took the sky
for a sea. Procedural trees of known masks, several sizes and skies, dark on light and light on dark.
"""

import numpy as np
import pytest
from scipy import ndimage as ndi
from skimage.draw import line_aa

from branchnb import data
from branchnb.branching import extract_structure
from branchnb.branching.smooth_ground import flattened_silhouette


def _tree(size, seed, ink=(0.12, 0.10, 0.09), sky=((0.45, 0.62, 0.85), (0.92, 0.85, 0.75))):
    """A tapered binary tree growing up from the bottom edge (pipe-model widths) over a vertical gradient."""
    import cv2

    rng = np.random.default_rng(seed)
    h = w = size
    y = np.linspace(0, 1, h)[:, None, None]
    ground = (np.asarray(sky[0]) * (1 - y) + np.asarray(sky[1]) * y) * np.ones((h, w, 3))
    mask = np.zeros((h, w), np.uint8)
    s = size / 512

    def grow(x, yy, ang, r, depth):
        length = 60 * s * (0.82 ** max(0, 4 - depth)) * rng.uniform(0.8, 1.2)
        for i in range(8):
            ang += rng.normal(0, 0.12)
            nx, ny = x + np.cos(ang) * length / 8, yy - np.sin(ang) * length / 8
            cv2.line(mask, (int(x * 4), int(yy * 4)), (int(nx * 4), int(ny * 4)), 255,
                     max(1, int(round(2 * r * (1 - 0.25 * i / 8)))), cv2.LINE_AA, shift=2)
            x, yy = nx, ny
        if depth and r >= 0.6:
            for j in range(2):
                grow(x, yy, ang + rng.uniform(0.3, 0.7) * (1 if j else -1), r * 0.56, depth - 1)

    grow(w / 2, h - 1, np.pi / 2, 9 * s, 6)
    alpha = mask.astype(np.float64)[..., None] / 255
    return (ground * (1 - alpha) + np.asarray(ink) * alpha).astype(np.float32), mask > 127


@pytest.mark.parametrize("size,seed", [(128, 0), (256, 1), (384, 0), (512, 1), (1000, 2)])
def test_flattened_silhouette_is_the_mask(size, seed):
    img, m = _tree(size, seed)
    flat = flattened_silhouette(img)
    assert flat is not None
    ink = flat < 0.5
    assert (ink & m).sum() / (ink | m).sum() >= 0.97


@pytest.mark.parametrize("size,seed", [(256, 1), (384, 0), (512, 1)])
def test_shaded_tree_is_one_tree_rooted_at_its_trunk(size, seed):
    img, m = _tree(size, seed)
    s = extract_structure(img)
    roots = [b for b in s.branches if b.parent is None]
    assert len(roots) == 1
    x, y = roots[0].points[0]
    assert y >= size - 0.05 * size and abs(x - size / 2) <= 0.05 * size
    # the traced lines lie on the tree (a ridge route's twig gaps and a sky's spurs both fail this)
    pts = np.concatenate([b.points for b in s.branches]).round().astype(int)
    m = ndi.binary_dilation(m)      # (1-px twigs: a smoothed path rounds to a pixel beside them)
    assert m[np.clip(pts[:, 1], 0, size - 1), np.clip(pts[:, 0], 0, size - 1)].mean() >= 0.97


def test_light_lines_on_a_dark_shaded_ground():
    img, m = _tree(384, 3, ink=(0.95, 0.95, 0.9), sky=((0.05, 0.05, 0.2), (0.25, 0.2, 0.35)))
    flat = flattened_silhouette(img)
    assert flat is not None and ((flat < 0.5) & m).sum() / ((flat < 0.5) | m).sum() >= 0.97
    s = extract_structure(img)
    assert sum(b.parent is None for b in s.branches) == 1


def test_not_taken_for_a_silhouette():
    rng = np.random.default_rng(0)
    # flat grounds are binary images already; textured grounds, two inks and photographs are no silhouettes
    img, _ = _tree(256, 0, sky=((0.9, 0.9, 0.9), (0.9, 0.9, 0.9)))
    assert flattened_silhouette(img) is None
    noisy, _ = _tree(256, 0)
    assert flattened_silhouette(np.clip(noisy + rng.normal(0, 0.04, noisy.shape), 0, 1)) is None
    two = _tree(256, 0)[0].copy()
    rr, cc, val = line_aa(10, 10, 10, 240)
    two[rr, cc] = [0.9, 0.1, 0.1]
    two[60:70, 20:200] = [0.1, 0.6, 0.1]
    assert flattened_silhouette(two) is None
    for name in ("retina_fundus", "lightning_trace", "cracked_mud"):
        assert flattened_silhouette(data.load(name)) is None


def test_synthesized_tree_keeps_the_sky_clean_and_the_ink_solid():
    from branchnb.branching import fit_model, synthesize_image, synthesize_structure
    from branchnb.core.render import coverage_polylines

    img, _ = _tree(256, 1)
    s = extract_structure(img)
    target = synthesize_structure(fit_model(s), rng=0).structure
    out = synthesize_image(img, s, target, rng=0).image[..., :3]
    cover = coverage_polylines(out.shape[:2], [b.points for b in target.branches],
                               [2.0 * np.asarray(b.thickness) for b in target.branches])[0]
    far = ~ndi.binary_dilation(cover > 0.05, iterations=3)
    # the ground away from the lines is the example's sky where it lies (quilted sky patches from other
    # heights made pale blotches, the fragments' stray ink dark smudges: up to 0.3 off)
    y = np.linspace(0, 1, 256)[:, None, None]
    sky = np.asarray((0.45, 0.62, 0.85)) * (1 - y) + np.asarray((0.92, 0.85, 0.75)) * y
    dev = np.abs(out - sky).max(-1)[far]
    assert np.percentile(dev, 99.5) <= 0.03
    # the lines are drawn in the ink: their cores are the ink colour
    core = cover >= 0.95
    assert core.sum() > 50
    assert np.median(np.abs(out[core] - np.asarray((0.12, 0.10, 0.09))).max(-1)) <= 0.05
