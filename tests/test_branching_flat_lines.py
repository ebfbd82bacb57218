"""Lines of one flat colour on a textured ground (issue 23, :mod:`branchnb.branching.flat_lines`).

Pale roots of one paint on a grained, pebbled soil: synthesized, they must keep that colour with no pale
halo beside them (the seams' colour correction spread it), and the soil around them its grain.
"""
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import extract_structure, synthesize_image
from branchnb.branching.flat_lines import flat_line_colour
from branchnb.branching.skeleton_map import SkeletonMap
from branchnb.core.render import coverage_polylines
from branchnb.core.structure import Branch, Structure

ROOT = np.array([0.86, 0.78, 0.62], np.float32)


def _soil_roots(size=160, seed=0, flat=True):
    """Pale roots (one colour; ``flat=False``: carrying the soil's grain at 3x) on a textured soil."""
    rng = np.random.default_rng(seed)
    n = rng.normal(0, 1, (size, size))
    tex = ndi.gaussian_filter(n, 1.0) * 0.5 + ndi.gaussian_filter(n, 2.0) * 2.0
    tex = (tex - tex.mean()) / tex.std()
    soil = np.stack([0.36 + 0.04 * tex, 0.24 + 0.03 * tex, 0.14 + 0.02 * tex], -1)
    lines, widths = [], []
    for k, x0 in enumerate((0.25, 0.5, 0.75)):
        y = np.linspace(0, size - 1, 40)
        x = size * x0 + 0.06 * size * np.sin(y / size * 5 + k)
        lines.append(np.c_[x, y])
        widths.append(np.linspace(7.0, 3.0, 40))
        yb = np.linspace(0.35 * size, 0.7 * size, 12)
        xb = x[14] + (yb - yb[0]) * (0.7 if k % 2 else -0.7)
        lines.append(np.c_[xb, yb])
        widths.append(np.linspace(4.0, 2.5, 12))
    cov, _ = coverage_polylines((size, size), lines, widths)
    paint = ROOT if flat else ROOT * (1 + 3 * 0.1 * tex[..., None])
    img = soil * (1 - cov[..., None]) + paint * cov[..., None]
    return np.clip(img, 0, 1).astype(np.float32), cov >= 0.5


def _paint_share(img, ground):
    d = ROOT - ground
    return ((img[..., :3] - ground) @ d) / float(d @ d)


def test_flat_line_colour_only_for_one_paint():
    img, _ = _soil_roots()
    s = extract_structure(img)
    pm = SkeletonMap(s, 1.0).pixel_map(img.shape[:2])
    found = flat_line_colour(img, pm)
    assert found is not None
    assert np.linalg.norm(found[0] - ROOT) < 0.05
    assert np.linalg.norm(found[1] - np.array([0.36, 0.24, 0.14])) < 0.05
    grained, _ = _soil_roots(flat=False)
    pm2 = SkeletonMap(extract_structure(grained), 1.0).pixel_map(img.shape[:2])
    assert flat_line_colour(grained, pm2) is None


def _target(size):
    """Three trunks with three children each, forking where the example's roots do not."""
    bs = []
    for k, x0 in enumerate((0.2, 0.5, 0.8)):
        y = np.linspace(2, size - 3, 30)
        x = size * x0 + 0.05 * size * np.cos(y / size * 4 + 2 * k)
        bs.append(Branch(np.c_[x, y], np.linspace(3.5, 1.5, 30)))
        trunk = len(bs) - 1
        for j, v in enumerate((8, 15, 22)):
            side = 1 if (j + k) % 2 else -1
            t = np.linspace(0, 1, 8)[:, None]
            pts = bs[trunk].points[v] + t * np.array([side * 0.8, 0.6]) * 0.22 * size
            bs.append(Branch(pts, np.linspace(2.0, 1.2, 8), parent=trunk, parent_vertex=v))
    return Structure(bs, image_shape=(size, size))


@pytest.mark.parametrize("seed", [0, 1])
def test_no_pale_halo_and_flat_lines_on_textured_soil(seed):
    img, truth = _soil_roots(seed=seed)
    s = extract_structure(img)
    tgt = _target(img.shape[0])
    out = synthesize_image(img, s, tgt, rng=0).image[..., :3]
    cov, _ = coverage_polylines(img.shape[:2], [b.points for b in tgt.branches],
                                [2 * b.thickness for b in tgt.branches])
    lines = cov >= 0.5
    dist = ndi.distance_transform_edt(~lines)
    ground = np.array([0.36, 0.24, 0.14], np.float32)
    t = _paint_share(out, ground)
    ring = (dist >= 2) & (dist <= 8)
    # no pale halo beside the lines (main before the fix: 0.010-0.011 of the ring a third of the way to the paint)
    assert np.mean(t[ring] >= 0.3) <= 0.003
    # the lines are the example's one paint, with no dark seam across them (main: 90th percentile 0.09-0.11)
    core = ndi.binary_erosion(lines, iterations=1)
    assert np.percentile(np.linalg.norm(out[core] - ROOT, axis=1), 90) < 0.04
    far = dist > 8
    # the soil keeps its grain (not smoothed over) and its colour
    assert np.std(out[far].mean(-1)) > 0.5 * np.std(img[ndi.distance_transform_edt(~truth) > 8].mean(-1))
    assert np.linalg.norm(np.median(out[far], axis=0) - ground) < 0.05
