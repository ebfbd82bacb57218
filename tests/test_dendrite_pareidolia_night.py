"""Issue 25, pareidolia: on a picture dark all over (a night sky, darkness 0.58-0.88) the
main limbs kept nearly their full pipe width everywhere, dark bands across the crown: on
the night photo of the rocket at 600 px the 3 px round the limbs were 7 % of the crown
and held 25-30 % of the tone error (tone r at 4 px blur 0.60). Limbs now narrow in the
lighter parts of the crown's own range of tone too (``_LIMB_RELATIVE``)."""

import numpy as np
import pytest
from scipy import ndimage

from branchnb.dendrite._twig_ends import tone_r
from branchnb.dendrite.pareidolia import pareidolia_tree


def _night(n=300, seed=0):
    """A dark sky lighter toward the horizon and a lit tower."""
    rng = np.random.default_rng(seed)
    h, w = int(0.75 * n), n
    yy, xx = np.mgrid[0:h, 0:w] / n
    lum = 0.12 + 0.3 * yy / 0.75
    lum = lum + 0.6 * ((np.abs(xx - 0.5) < 0.02) & (yy > 0.25))
    lum = ndimage.gaussian_filter(lum, 1.0) + 0.02 * rng.random((h, w))
    return np.repeat(np.clip(lum, 0, 1)[..., None], 3, axis=2).astype(np.float32)


@pytest.fixture(scope="module")
def trees():
    return [(_night(300, s), pareidolia_tree(_night(300, s), rng=s)) for s in (0, 1)]


def test_limbs_narrow_in_the_lighter_part_of_a_night_sky(trees):
    # measured (before -> after), seeds 0/1: mean limb width in the crown's lighter half
    # 3.03 / 2.92 -> 2.77 / 2.71 px (darker half 2.19 / 2.26 -> 2.16 / 2.23)
    for img, t in trees:
        d = t.dendrite
        m = t.crown_on_canvas()
        h, w = m.shape
        p = np.rint(d.points).astype(int)
        y, x = np.clip(p[:, 1], 0, h - 1), np.clip(p[:, 0], 0, w - 1)
        limb = (d.iteration == 1) & m[y, x]
        dark = 1.0 - img[np.minimum(y, img.shape[0] - 1), x, 0]
        light = limb & (dark < np.median(dark[limb]))
        assert 2 * d.radius[light].mean() < 2.85


def test_night_sky_tone(trees):
    # tone r inside the crown at 4 px blur, seeds 0/1: 0.735 / 0.726 -> 0.752 / 0.742
    r = [tone_r(t, 4.0) for _, t in trees]
    assert np.mean(r) > 0.74
