"""Colour borders (issue 25, dendrite41): the plain stylization draws isoluminant colour borders
(a red part next to a blue one of the same luminance) and lightning over objects touching along
a wide stretch traces each object of its own colour.

Procedural inputs with known borders and masks: a disc split by a wavy line into two colours of
one luminance, overlapping fruits of different colours, a shaded and a textured single blob.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage
from skimage.color import rgb2lab

from branchnb.dendrite import stylize
from branchnb.dendrite.importance import gradient_strength
from branchnb.dendrite.strike_outline import outline_parts, split_by_colour

W709 = np.array([0.2126, 0.7152, 0.0722])


def _iso(colour, lum):
    """``colour``'s hue at luminance ``lum`` exactly (its chroma shrunk to fit in [0, 1])."""
    c = np.asarray(colour, float)
    ch = c - c @ W709
    s = min([1.5] + [(1 - lum) / v for v in ch if v > 0] + [lum / -v for v in ch if v < 0])
    return lum + s * ch


def _split_disc(n, pair, lum, seed=0):
    rng = np.random.default_rng(seed)
    h, w = int(0.6 * n), n
    y, x = np.mgrid[0:h, 0:w]
    cx, cy, r = w / 2, h / 2, 0.38 * h
    disc = np.hypot(x - cx, y - cy) < r
    wave = cx + 0.15 * r * np.sin(y / (0.3 * r) + rng.uniform(0, 6))
    lab = np.where(disc, np.where(x < wave, 1, 2), 0)
    img = np.ones((h, w, 3))
    img[lab == 1] = _iso(pair[0], lum)
    img[lab == 2] = _iso(pair[1], lum)
    border = (lab == 1) & ndimage.binary_dilation(lab == 2)
    return img.astype(np.float32), lab, border


def _fruits(n, colours, seed=0, shade=True):
    rng = np.random.default_rng(seed)
    h, w = int(0.7 * n), n
    img = np.ones((h, w, 3))
    yy, xx = np.mgrid[0:h, 0:w]
    lab = np.zeros((h, w), int)
    k = len(colours)
    r = 0.22 * n if k == 2 else 0.17 * n
    tex = ndimage.gaussian_filter(rng.standard_normal((h, w)), max(1, n / 150))
    for i, col in enumerate(colours):
        cx, cy = 0.5 * w - (k - 1) * 0.8 * r + i * 1.6 * r, 0.5 * h
        m = np.hypot(xx - cx, yy - cy) < r * (1 + 0.06 * np.sin(3 * np.arctan2(yy - cy, xx - cx) + i))
        lab[m] = i + 1
        light = 0.85 + 0.15 * np.clip(1 - np.hypot(xx - cx + 0.3 * r, yy - cy + 0.3 * r) / (1.5 * r), 0, 1)
        c = np.asarray(col) * (light[..., None] if shade else 1.0) + 0.02 * (tex / tex.std())[..., None]
        img[m] = c[m]
    return np.clip(img, 0, 1).astype(np.float32), lab


def test_gradient_strength_sees_an_isoluminant_border_and_keeps_grey_pictures():
    img = np.ones((32, 32, 3)) * _iso((0.9, 0.1, 0.1), 0.4)
    img[:, 16:] = _iso((0.2, 0.25, 1.0), 0.4)
    g = gradient_strength(img)
    assert g[10, 15] >= 0.9 and g[10, 3] == 0.0  # luminance alone: 0 everywhere
    grey = np.random.default_rng(0).random((40, 40))
    np.testing.assert_allclose(gradient_strength(np.dstack([grey] * 3)), gradient_strength(grey), atol=1e-6)


@pytest.mark.parametrize("pair, lum", [(((0.9, 0.12, 0.1), (0.2, 0.25, 1.0)), 0.6),
                                       (((0.15, 0.6, 0.1), (0.85, 0.1, 0.85)), 0.35)])
def test_plain_stylization_draws_an_isoluminant_colour_border(pair, lum):
    img, lab, border = _split_disc(200, pair, lum)
    pic = np.asarray(stylize(img, rng=0).rendering.image)[..., :3]
    dark = 1.0 - pic.mean(-1)
    ink = dark > 0.5
    near_ink = ndimage.distance_transform_edt(~ink) <= 2
    assert near_ink[border].mean() >= 0.7
    # the border reads as a line: its band is inked more than the regions' insides
    band = ndimage.distance_transform_edt(~border) <= 1.5
    rim = (lab > 0) & ~ndimage.binary_erosion(lab > 0)
    deep = (lab > 0) & (ndimage.distance_transform_edt(~(border | rim)) > 5)
    assert dark[band].mean() >= RATIO * dark[deep].mean()


RATIO = 1.3


def test_outline_parts_split_touching_objects_of_different_colour():
    img, lab = _fruits(300, [(0.85, 0.2, 0.1), (0.35, 0.65, 0.15), (0.95, 0.75, 0.1)])
    parts = outline_parts(lab > 0, image=img)
    assert parts.max() == 3
    for k in range(1, 4):  # each part is one fruit
        best = max(((parts == j) & (lab == k)).sum() / ((parts == j) | (lab == k)).sum() for j in range(1, 4))
        assert best >= 0.95
    # by shape alone the fruits (centres 1.6 radii apart) split at their necks too
    # (dendrite42, split_by_shape; before: one blob)
    assert outline_parts(lab > 0).max() == 3


def test_a_shaded_or_textured_object_stays_one_part():
    img, lab = _fruits(300, [(0.85, 0.2, 0.1)])
    assert outline_parts(lab > 0, image=img).max() == 1
    ramp = np.ones((100, 160, 3))
    m = np.zeros((100, 160), bool)
    m[10:90, 10:150] = True
    ramp[10:90, 10:150] = np.linspace(0.1, 0.9, 140)[None, :, None] * np.array([0.3, 0.6, 1.0])
    assert split_by_colour(m, rgb2lab(ramp), 0.02 * m.size) is None
    with pytest.raises(ValueError, match="image"):
        outline_parts(m, image=np.ones((5, 5, 3)))


def test_lightning_traces_each_of_two_touching_fruits():
    img, lab = _fruits(300, [(0.85, 0.2, 0.1), (0.35, 0.65, 0.15)])
    pic = np.asarray(stylize(img, metaphor="lightning", rng=0).rendering.image)[..., :3]
    near = ndimage.distance_transform_edt(~(pic.mean(-1) > 0.5)) <= 4
    covers = [near[(lab == k) & ~ndimage.binary_erosion(lab == k)].mean() for k in (1, 2)]
    assert min(covers) >= 0.6  # main: 0.07 / 0.05 (one bolt through both)
