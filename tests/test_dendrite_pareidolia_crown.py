"""Issue 25, pareidolia that reads as the picture and as a tree.

* The night photo of a rocket (a picture dark all over) gave tone r 0.61 inside the crown at
  4 px blur at 600 px: the limbs kept their width where they crossed the crown (the 4-px
  band round them held 34 % of the tone error) and the twigs carrying a dark picture's ink
  were so wide that their gaps made a coarse texture. The limbs' ink is now budgeted against
  the tone (``pareidolia_widths._LIMB_BUDGET``) and a dark picture gets more twigs
  (``pareidolia._DARK_TWIGS``).
* An object on a blank ground (clip art) took its own silhouette as the crown: an
  apple-shaped tree. It now gets a tree crown round it (``pareidolia_crown._AROUND``) whose
  blank ground holds light twigs (``pareidolia._GROUND_TONE``, ``_GROUND_TWIGS``), and the
  trunk keeps its width across that ground.
"""

import numpy as np
import pytest

from branchnb.core import as_gray
from branchnb.dendrite._pareidolia_sweep import apple, crown_shape, logo, picture, silhouette
from branchnb.dendrite._twig_ends import tone_r
from branchnb.dendrite.pareidolia import pareidolia_tree


def test_rocket_tone_reads_inside_the_crown():
    # tone r at 4 px blur: 0.610 -> 0.760 (2 px 0.42 -> 0.54, 8 px 0.72 -> 0.84)
    t = pareidolia_tree(picture("rocket", 600), rng=0)
    assert tone_r(t, 4.0) >= 0.7
    assert tone_r(t, 8.0) >= 0.78


@pytest.fixture(scope="module", params=["apple", "logo"])
def white_ground(request):
    img = {"apple": apple, "logo": logo}[request.param](300, 1)
    return img, pareidolia_tree(img, rng=1)


def test_white_ground_object_gets_a_tree_crown_round_it(white_ground):
    img, t = white_ground
    crown = t.crown_on_canvas()
    sil = silhouette(t.image)
    out, solid = crown_shape(t)
    # share of the crown outside the object: apple 0.09-0.10, logo 0.14-0.15 -> 0.45-0.51;
    # solidity (area over convex hull) logo 0.84 -> 0.96
    assert out > 0.3
    assert solid > 0.9
    assert (crown & sil).sum() > 0.97 * sil.sum()  # all of the picture is in the crown
    # the blank ground inside the crown has twigs, light but there (not empty, not a mass)
    ink = 1.0 - as_gray(t.render().image).astype(np.float64)
    ground = crown & ~ndimage_dilate(sil, 6)
    assert 0.02 < ink[ground].mean() < 0.25
    assert (ink[ground] > 0.5).mean() > 0.01


def test_trunk_keeps_its_width_across_the_blank_ground(white_ground):
    # the trunk narrowed from 21 to 4 px within 20 px of entering the crown's blank ground
    # (or from 11 to 3 px as it met the object), the widest twice its narrowest
    img, t = white_ground
    d = t.dendrite
    crown = t.crown_on_canvas()
    n = d.tips[0] + 1  # the trunk is traced first, to its fork
    p = np.rint(d.points[:n]).astype(int)
    inside = crown[np.clip(p[:, 1], 0, crown.shape[0] - 1), np.clip(p[:, 0], 0, crown.shape[1] - 1)]
    sil = ndimage_dilate(silhouette(t.image), 3)
    on_ground = inside & ~sil[np.clip(p[:, 1], 0, sil.shape[0] - 1), np.clip(p[:, 0], 0, sil.shape[1] - 1)]
    below = 2 * d.radius[:n][~inside]
    if img.shape[0] == img.shape[1]:  # the apple's crown reaches well below it; the logo's
        assert on_ground.sum() >= 5   # bar sits at the frame's foot, where its crown ends
    if on_ground.any():
        assert 2 * d.radius[:n][on_ground].min() > 0.7 * below[-5:].mean()
    # ... and it narrows gradually into the object (no step of 2x in 3 px; it was 3.1x)
    w = 2 * d.radius[:n]
    seg = np.hypot(*np.diff(d.points[:n], axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    j = np.searchsorted(s, s - 3.0)
    assert (w[j] / np.maximum(w, 1e-6))[inside & (s > 3.0) & (s < s[-1] - 5.0)].max() < 2.0


def ndimage_dilate(mask, r):
    from scipy import ndimage

    return ndimage.binary_dilation(mask, iterations=r)
