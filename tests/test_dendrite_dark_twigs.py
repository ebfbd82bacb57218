"""Issue 25, dendrites: pareidolia twigs in a picture's dark regions that grow as twigs
(not squiggles widened into bean-shaped blobs), and lightning on an image that reads as
a main bolt with a few forks (not a glowing outline over an interior scribble)."""

import numpy as np
import pytest
from scipy import ndimage
from skimage.transform import resize

from branchnb import data
from branchnb.core import as_gray, as_rgb
from branchnb.dendrite import build_dendrite, make_lattice, plan, random_endpoints, stylize
from branchnb.dendrite.pareidolia import PareidoliaParams, pareidolia_tree
from branchnb.dendrite.thickness import branch_thickness


def _beans(n, rng=0):
    """Dark beans (flat, darkness ~0.85) on light paper."""
    r = np.random.default_rng(rng)
    img = np.full((n, n), 0.92)
    yy, xx = np.mgrid[0:n, 0:n]
    for cx, cy in ((0.3, 0.3), (0.68, 0.35), (0.35, 0.7), (0.7, 0.72)):
        a, b, t = 0.17 * n, 0.11 * n, r.uniform(0, np.pi)
        u = ((xx - cx * n) * np.cos(t) + (yy - cy * n) * np.sin(t)) / a
        v = (-(xx - cx * n) * np.sin(t) + (yy - cy * n) * np.cos(t)) / b
        img[u ** 2 + v ** 2 <= 1] = 0.15
    return img


def _twigs(d):
    bp = d.branch_parent
    n_child = np.bincount(bp[bp >= 0], minlength=len(bp))
    return [d.branches[b][1:] for b in np.flatnonzero((n_child == 0) & (bp >= 0))
            if len(d.branches[b]) > 2]


def _blob_share(t):
    """Share of the terminal twigs' ink (in the crown's dark parts) in twigs whose ink sits
    in a compact spot: the chord from the twig's base to its tip < 3x its widest width."""
    d, img = t.dendrite, as_gray(t.image)
    w = 2 * d.radius
    has = d.parent >= 0
    seg = np.zeros(d.n_nodes)
    seg[has] = np.hypot(*(d.points[has] - d.points[d.parent[has]]).T)
    ink = blob = 0.0
    for tw in _twigs(d):
        x, y = np.rint(d.points[tw[-1]]).astype(int)
        if img[min(y, img.shape[0] - 1), min(x, img.shape[1] - 1)] > 0.5:
            continue
        a = float(np.dot(w[tw], seg[tw]))
        ink += a
        if np.hypot(*(d.points[tw[-1]] - d.points[d.parent[tw[0]]])) < 3 * w[tw].max():
            blob += a
    return blob / ink


def _tone_r(t, sigma=4.0):
    m = t.crown_on_canvas()
    x = ndimage.gaussian_filter(1.0 - as_gray(t.image).astype(np.float64), sigma)[m]
    y = ndimage.gaussian_filter(1.0 - as_gray(t.render().image).astype(np.float64), sigma)[m]
    return float(np.corrcoef(x, y)[0, 1])


@pytest.fixture(scope="module")
def bean_trees():
    img = _beans(300)  # on a 320-px lattice (512 by default) for the test's time
    return {rise: pareidolia_tree(img, PareidoliaParams(rise=rise, lattice_size=320), rng=0)
            for rise in (0.0, 0.04)}


def test_dark_twigs_grow_as_twigs_not_blobs(bean_trees):
    # measured: blob share 0.67 -> 0.42, tone r 0.953 -> 0.957, twigs' mean rise 0 -> 2.3 px
    flat, up = bean_trees[0.0], bean_trees[0.04]
    assert _blob_share(up) < 0.8 * _blob_share(flat)
    assert _tone_r(up) >= 0.7 and _tone_r(up) >= _tone_r(flat) - 0.02
    # the twigs grow upward: their tips lie above their bases on average
    d = up.dendrite
    rise = [d.points[d.parent[tw[0]], 1] - d.points[tw[-1], 1] for tw in _twigs(d)]
    assert np.mean(rise) > 1.0


def test_rise_out_of_range_is_refused():
    with pytest.raises(ValueError, match="rise"):
        pareidolia_tree(_beans(40), PareidoliaParams(rise=-0.1), rng=0)


# ------------------------------------------------------------------ lightning
def test_share_thickness_only_the_main_channel_is_widest():
    res = plan(make_lattice(np.zeros((60, 60)), rng=0), (30, 2))
    d = build_dendrite(res, random_endpoints(np.ones((60, 60), bool), 40, rng=1))
    t = branch_thickness(d, mode="share", min_width=0.5, max_width=6.0)
    w = 2 * t.radius
    n = d.leaf_count()
    assert w.max() == pytest.approx(6.0)
    assert np.all(w[n < n.max()] < 6.0)  # the pipe model clipped at 6 px made many such
    assert w[d.tips].max() == pytest.approx(0.5)
    assert np.all(np.diff(w[np.argsort(n)]) >= -1e-9)  # wider with more tips
    with pytest.raises(ValueError, match="max_width"):
        branch_thickness(d, mode="share", max_width=None)


@pytest.fixture(scope="module")
def camera_bolt():
    img = resize(as_rgb(data.load("camera")), (256, 256), anti_aliasing=True).astype(np.float32)
    return img, stylize(img, rng=0, metaphor="lightning")


def _main_path(d):
    has = d.parent >= 0
    seg = np.zeros(d.n_nodes)
    seg[has] = np.hypot(*(d.points[has] - d.points[d.parent[has]]).T)
    n = d.leaf_count()
    kids = {}
    for i in np.flatnonzero(has):
        kids.setdefault(int(d.parent[i]), []).append(int(i))
    node = int(np.flatnonzero(~has)[0])
    path = [node]
    while node in kids:
        node = max(kids[node], key=lambda c: n[c])
        path.append(node)
    return np.array(path), seg


def test_lightning_on_an_image_is_a_main_bolt_with_few_forks(camera_bolt):
    # before: ~210 tips, 21 % of the ink on the main path, the bolt starting mid-picture
    img, s = camera_bolt
    d = s.dendrite
    assert 20 <= len(d.tips) <= 90
    path, seg = _main_path(d)
    if d.main is not None:  # the channel planned on its own (a photo): that is the bolt
        path = d.main
    ink = 2 * d.radius * seg
    # (dendrite22: with the side branches kept off the tripod's straight legs the walk down
    # the child with most tips left the planned channel, 0.49 -> 0.25; the channel 0.45)
    assert ink[path].sum() / ink.sum() > 0.3
    # the bolt strikes from the top of the picture's content
    assert d.points[d.parent < 0][0, 1] < 0.15 * img.shape[0]
    # it burns brightest along the main path, the forks dimmer
    lum = as_gray(s.rendering.image)
    at = np.rint(d.points).astype(int)
    b = lum[at[:, 1], at[:, 0]]
    off = np.setdiff1d(np.arange(d.n_nodes), path)
    assert b[path].mean() > b[off].mean() + 0.1
    # and the sky stays dark
    assert (lum > 0.6).mean() < 0.06 and np.median(lum) < 0.2
