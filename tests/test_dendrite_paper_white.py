"""A low-key picture's lightest tone is paper (issue 25: dendrites on inputs nobody tried).

Before, a dark object on a dark ground (a 0.12 cat on a 0.25 textured ground) was
inked as densely as its ground (mean ink 0.50 inside, 0.46 outside): the object vanished.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage
from skimage import draw

from branchnb.core.image import as_gray
from branchnb.dendrite import stylize
from branchnb.dendrite.importance import _to_paper_white


def _dark_cat(n):
    rng = np.random.default_rng(1)
    tex = ndimage.gaussian_filter(rng.normal(0, 1, (n, n)), n / 80)
    tex /= tex.std()
    ground = 0.25 + 0.03 * tex + 0.05 * np.linspace(0, 1, n)[None]
    m = np.zeros((n, n), bool)
    rr, cc = draw.ellipse(0.6 * n, 0.5 * n, 0.22 * n, 0.18 * n, shape=(n, n))
    m[rr, cc] = True
    rr, cc = draw.ellipse(0.33 * n, 0.5 * n, 0.11 * n, 0.12 * n, shape=(n, n))
    m[rr, cc] = True
    img = ndimage.gaussian_filter(np.where(m, 0.12 + 0.02 * tex, ground), n / 700)
    return np.dstack([img] * 3).astype(np.float32), m


def test_dark_object_on_dark_ground_stands_out():
    img, m = _dark_cat(300)
    ink = 1.0 - as_gray(stylize(img, rng=0).rendering.image)
    inner = ndimage.binary_erosion(m, iterations=3)
    far = ~ndimage.binary_dilation(m, iterations=6)
    # main: 0.50 inside vs 0.46 on the ground
    assert ink[inner].mean() - ink[far].mean() > 0.15
    assert ink[far].mean() < 0.3


def test_pictures_on_white_are_unchanged():
    img = np.ones((40, 50, 3), np.float32)
    img[10:30, 10:40] = 0.2
    assert _to_paper_white(img) is img or np.array_equal(_to_paper_white(img), img)
    dark = np.full((20, 20), 0.05, np.float32)
    dark[5:9, 5:9] = 0.02
    # the gain is capped: a night picture stays dark
    assert _to_paper_white(dark).max() <= 0.05 * 4.0 + 1e-6
