"""A photograph's matte is no drawn boundary line.

Found on the retina fundus with the map workflow (``fit_model(..., domain=example_domain(...))``):
the vignetted rim of the disk darkens into the black matte, its darkest pixels took the matte's
colour, and ``synthesize_image`` drew a black "coastline" arc along the output's domain.
"""

import numpy as np

from branchnb.branching import extract_structure
from branchnb.branching.drawn_domains import drawn_boundary
from branchnb.branching.skeleton_map import SkeletonMap


def _fundus(n=240, seed=0):
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:n, :n].astype(np.float32)
    c = n / 2.0
    r = np.hypot(xx - c, yy - c) / (0.45 * n)
    disk = r <= 1.0
    shade = np.clip(1.0 - 0.85 * r ** 6, 0.0, 1.0)          # vignetting down to almost black at the rim
    img = np.zeros((n, n, 3), np.float32)
    img[disk] = np.array([0.8, 0.31, 0.22], np.float32) * shade[disk, None]
    # a few dark vessels from a disc on the left
    for a in np.linspace(-1.0, 1.0, 5):
        t = np.linspace(0, 1, 200)
        x = 0.25 * n + t * 0.6 * n
        y = c + a * t * 0.35 * n + 4 * np.sin(6 * t + a)
        for xi, yi in zip(x, y):
            yi_, xi_ = int(yi), int(xi)
            if 0 <= yi_ < n and 0 <= xi_ < n and disk[yi_, xi_]:
                img[max(yi_ - 1, 0):yi_ + 2, max(xi_ - 1, 0):xi_ + 2] *= 0.55
    img += rng.normal(0, 0.01, img.shape).astype(np.float32) * disk[..., None]
    return np.clip(img, 0, 1)


def test_vignetted_matte_rim_is_no_line():
    img = _fundus()
    ex = extract_structure(img)
    pm = SkeletonMap(ex, 1.0).pixel_map(img.shape[:2])
    assert drawn_boundary(img, ex, pm) is None
