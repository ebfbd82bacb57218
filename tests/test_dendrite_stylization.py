"""What the dendritic stylization reaches with its defaults on varied inputs (issue 12):
clean backgrounds, tone, scale-independence, metaphor lengths, pareidolia.

The inputs are small (<= 256 px) photos, drawings and procedural scenes; the
stylization plans on its own 512-lattice whatever the input size, so each
run costs the same few seconds.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage
from skimage import draw
from skimage.transform import resize

from branchnb import data
from branchnb.core.image import as_gray, as_rgb
from branchnb.dendrite import StylizeParams, Stylizer, render_lightning, stylize
from branchnb.dendrite.metaphors import vine_curves, vine_length
from branchnb.dendrite.pareidolia import PareidoliaParams, pareidolia_tree

PAPER = 0.9  # rendered luminance that still counts as paper


def _fit(img, long_side):
    img = as_rgb(img)
    h, w = img.shape[:2]
    s = long_side / max(h, w)
    return resize(img, (round(h * s), round(w * s)), anti_aliasing=True).astype(np.float32)


def _shapes(n=192):
    """Known answer: a dark disc, a grey square and a thin black ring on flat white."""
    img = np.ones((n, n), np.float32)
    rr, cc = draw.disk((0.35 * n, 0.35 * n), 0.18 * n)
    img[rr, cc] = 0.1
    img[int(0.55 * n):int(0.85 * n), int(0.55 * n):int(0.85 * n)] = 0.5
    rr, cc = draw.circle_perimeter(int(0.72 * n), int(0.27 * n), int(0.12 * n))
    img[rr, cc] = 0.0
    return np.dstack([img] * 3)


def _twig(n=224, seed=1):
    """A forking brown twig on off-white paper with a little noise (a procedural 'photo')."""
    r = np.random.default_rng(seed)
    img = np.ones((n, n, 3), np.float32) * np.array([0.97, 0.96, 0.94], np.float32)

    def branch(x, y, ang, length, width, depth):
        for _ in range(24):
            ang += r.normal(0, 0.05)
            x, y = x + np.cos(ang) * length / 24, y + np.sin(ang) * length / 24
            rr, cc = draw.disk((y, x), max(width, 0.7), shape=(n, n))
            img[rr, cc] = np.array([0.35, 0.24, 0.15]) * r.uniform(0.7, 1.0)
            width *= 0.98
        if depth:
            for side in (-1, 1):
                branch(x, y, ang + side * r.uniform(0.35, 0.7), length * 0.62, width * 0.6,
                       depth - 1)

    branch(0.5 * n, 0.97 * n, -np.pi / 2, 0.35 * n, 0.02 * n, 4)
    img += r.normal(0, 0.01, (n, n, 1)).astype(np.float32)
    return np.clip(ndimage.gaussian_filter(img, (0.7, 0.7, 0)), 0, 1)


def _night(n=224, seed=0):
    """A dark night sky with stars, a lit moon and a house with two lit windows."""
    r = np.random.default_rng(seed)
    yy = np.mgrid[0:n, 0:n][0] / n
    sky = 0.04 + 0.1 * yy
    img = np.dstack([sky * 0.7, sky * 0.8, sky * 1.3]) + r.normal(0, 0.01, (n, n, 1))
    img[r.integers(0, n // 2, 30), r.integers(0, n, 30)] = 0.9
    rr, cc = draw.disk((0.22 * n, 0.75 * n), 0.08 * n, shape=(n, n))
    img[rr, cc] = (0.95, 0.93, 0.8)
    img[int(0.8 * n):] = (0.05, 0.06, 0.05)
    rr, cc = draw.polygon([0.8 * n, 0.45 * n, 0.33 * n, 0.45 * n, 0.8 * n],
                          [0.2 * n, 0.2 * n, 0.4 * n, 0.6 * n, 0.6 * n], shape=(n, n))
    img[rr, cc] = (0.12, 0.09, 0.07)
    img[int(0.52 * n):int(0.64 * n), int(0.27 * n):int(0.37 * n)] = (1.0, 0.85, 0.45)
    img[int(0.62 * n):int(0.8 * n), int(0.45 * n):int(0.53 * n)] = (0.95, 0.75, 0.35)
    return np.clip(img, 0, 1).astype(np.float32)


def _blurred_darkness(img, sigma):
    return ndimage.gaussian_filter(1.0 - as_gray(img).astype(np.float64), sigma)


def _tone_r(img, rendering, mask=None):
    """Pearson r of the blurred darkness of input and rendering (blur: 1.5 % of the diagonal)."""
    sigma = 0.015 * np.hypot(*img.shape[:2])
    a, b = _blurred_darkness(img, sigma), _blurred_darkness(rendering, sigma)
    if mask is not None:
        a, b = a[mask], b[mask]
    return float(np.corrcoef(a.ravel(), b.ravel())[0, 1])


def _flat_background(img):
    """Light pixels whose 9 x 9 neighbourhood is flat, away from the content."""
    g = as_gray(img).astype(np.float64)
    mean = ndimage.uniform_filter(g, 9)
    sd = np.sqrt(np.maximum(ndimage.uniform_filter(g * g, 9) - mean ** 2, 0))
    return ndimage.binary_erosion((mean > 0.9) & (sd < 0.01), iterations=3)


_RUNS: dict = {}


def _run(name, img):
    if name not in _RUNS:
        _RUNS[name] = stylize(img, rng=0)
    return _RUNS[name]


_INPUTS = {
    "shapes": _shapes,
    "twig": _twig,
    "maple_leaf": lambda: _fit(data.load("maple_leaf_03"), 200),
    "zelkova_leaf": lambda: _fit(data.load("zelkova_leaf"), 224),
    "night": _night,
    "lightning_night_photo": lambda: _fit(data.load("lightning_noaa"), 256),
    "retina": lambda: _fit(data.load("retina_fundus"), 192),
    "tree_photo": lambda: _fit(data.load("tree_cutout_broadleaf"), 200),
    "astronaut": lambda: _fit(data.load("astronaut"), 224),
    "camera": lambda: _fit(data.load("camera"), 224),
    "chelsea": lambda: _fit(data.load("chelsea"), 224),
    "coffee": lambda: _fit(data.load("coffee"), 224),
}


@pytest.mark.parametrize("name", ["shapes", "twig", "maple_leaf", "tree_photo"])
def test_flat_backgrounds_stay_clean(name):
    img = _INPUTS[name]()
    out = _run(name, img)
    # endpoints only where there is something to draw
    hl, wl = out.importance.shape
    e = np.rint(np.clip((out.endpoints + 0.5) / out.scale - 0.5, 0, [wl - 1, hl - 1])).astype(int)
    assert (out.importance[e[:, 1], e[:, 0]] < 0.05).mean() < 0.05
    # and the rendered background is paper (the dendrite only crosses it to join parts)
    bg = _flat_background(img)
    assert bg.mean() > 0.15
    paper = as_gray(out.rendering.image)[bg] > PAPER
    assert paper.mean() > 0.97


@pytest.mark.parametrize("name", list(_INPUTS))
def test_tone_follows_the_input(name):
    img = _INPUTS[name]()
    out = _run(name, img)
    assert _tone_r(img, out.rendering.image) >= 0.6
    # dark input, dark rendering: the ink grows with the input's mean darkness
    if name == "night":
        assert 1.0 - as_gray(out.rendering.image).mean() > 0.3


def test_tone_parameter_balances_tone_against_edges():
    img = _INPUTS["camera"]()
    st = Stylizer(img)
    edges = st.run(StylizeParams(tone=0.0), rng=0)
    tone = st.run(StylizeParams(tone=1.0), rng=0)
    assert tone.plan is edges.plan  # thickness only: the cached plan is reused
    assert _tone_r(img, tone.rendering.image) > _tone_r(img, edges.rendering.image) + 0.05
    # dark flat regions (the coat) get more ink with tone, the paper's importance
    # emphasis alone keeps them light
    g = as_gray(img)
    coat = ndimage.binary_erosion(g < 0.15, iterations=3)
    assert coat.mean() > 0.05

    def ink(out):
        return 1.0 - as_gray(out.rendering.image)[coat].mean()

    assert ink(tone) > ink(edges) + 0.1


def test_same_picture_at_every_size():
    big = _fit(data.load("astronaut"), 512)
    small = _fit(big, 256)
    a = stylize(small, rng=0).rendering.image
    b = stylize(big, rng=0).rendering.image
    b_small = resize(b, a.shape, anti_aliasing=True)
    ink_a, ink_b = 1 - as_gray(a).mean(), 1 - as_gray(b_small).mean()
    assert abs(ink_a - ink_b) < 0.1 * ink_a
    assert _tone_r(a, b_small) > 0.9


def test_every_length_scales_with_the_diagonal():
    img = _INPUTS["shapes"]()
    st = Stylizer(img)
    out = st.run(StylizeParams(n_endpoints=400), rng=0, metaphor=None)
    d1 = out.dendrite
    d2 = d1.rescaled((2 * img.shape[0], 2 * img.shape[1]))
    # widths: the same lattice widths drawn on a twice bigger image are twice as wide
    np.testing.assert_allclose(d2.radius, 2 * d1.radius)
    # the narrowest stroke is min_width lattice px (a fixed share of the image diagonal),
    # but never thinner than output_width image px
    k = np.sqrt(np.prod(st.scale(StylizeParams())))
    p = StylizeParams()
    assert 2 * d1.radius.min() == pytest.approx(max(p.min_width * k, p.output_width), rel=1e-6)
    # vines: leaf size and curl length follow the image diagonal
    for d in (d1, d2):
        d.radius[:] = np.minimum(d.radius, 0.5)
    _, _, leaves1, lw1 = vine_curves(d1, rng=0)
    _, _, leaves2, lw2 = vine_curves(d2, rng=0)

    def leaf_length(leaves):
        return np.median([np.hypot(*(lf[-1] - lf[0])) for lf in leaves])

    # (never below VINE_MIN_PIXELS: small images get readable leaves, not green specks)
    for d, leaves, lw in ((d1, leaves1, lw1), (d2, leaves2, lw2)):
        assert leaf_length(leaves) == pytest.approx(vine_length("leaf_length", d.shape), rel=0.15)
        assert np.median([w.max() for w in lw]) == pytest.approx(vine_length("leaf_width", d.shape),
                                                                 rel=0.15)
    big = d1.rescaled((6 * img.shape[0], 6 * img.shape[1]))
    big.radius[:] = np.minimum(big.radius, 0.5)
    assert leaf_length(vine_curves(big, rng=0)[2]) == pytest.approx(
        7.0 * np.hypot(*big.shape) / np.hypot(512, 512), rel=0.15)
    # lightning glow: the big rendering, shrunk, looks like the small one
    g1 = render_lightning(d1).image
    g2 = resize(render_lightning(d2).image, g1.shape, anti_aliasing=True)
    assert np.abs(g1 - g2).mean() < 0.03


def img_rows(t):
    """Rows of the pareidolia lattice canvas that hold the picture (above the trunk strip)."""
    return round(t.crown.shape[0] / (1 + t.params.trunk_height))


@pytest.mark.parametrize("name", ["astronaut", "zelkova_leaf"])
def test_pareidolia_hides_a_recognisable_picture(name):
    img = _fit(data.load(name), 256)
    t = pareidolia_tree(img, rng=0)
    d = t.dendrite
    assert d.is_tree()
    crown = t.crown_on_canvas()
    rendering = t.render().image
    # the picture inside the crown
    assert _tone_r(t.image, rendering, crown) >= 0.5
    # the crown follows the content: it holds the picture's importance ...
    h, w = t.crown.shape
    if name == "astronaut":
        # ... cut to a tree crown's lobed outline where the picture fills its frame, so the
        # crown reads as a crown, not as the image's rectangle
        n = img_rows(t)
        assert t.crown[:n].mean() < 0.85
        yy, xx = np.mgrid[0:n, 0:w]
        inner = np.hypot((xx - (w - 1) / 2) / (w / 2), (yy - (n - 1) / 2) / (n / 2)) < 0.75
        assert t.crown[:n][inner].all()  # every lobed outline holds the inner ellipse
        rows = np.flatnonzero(t.crown.any(axis=1))
        widths = t.crown[rows].sum(axis=1)
        # wide in the middle, narrowing toward the top and the bottom (not a box)
        assert widths[len(widths) // 2] > 1.4 * widths[2] and widths[len(widths) // 2] > 1.4 * widths[-3]
    else:
        assert t.importance[t.crown].sum() > 0.85 * t.importance.sum()
    if name == "zelkova_leaf":
        # ... and on a blank ground a tree crown round the leaf (issue 25: the leaf's own
        # silhouette as the crown drew a leaf-shaped tree), holding all of it
        from skimage.morphology import convex_hull_image

        leaf = ndimage.binary_fill_holes(as_gray(img) < 0.8)
        leaf_canvas = np.zeros(crown.shape, bool)
        leaf_canvas[:img.shape[0]] = leaf
        assert (crown & leaf_canvas).sum() > 0.97 * leaf_canvas.sum()
        assert (crown & ~leaf_canvas).sum() > 0.2 * crown.sum()
        assert crown.sum() > 0.9 * convex_hull_image(crown).sum()
    # the trunk: a pipe-model trunk, tapering from the foot to the fork, thicker than all else
    trunk = np.flatnonzero(d.iteration == 1)
    trunk = trunk[~crown[np.rint(d.points[trunk, 1]).astype(int),
                         np.rint(d.points[trunk, 0]).astype(int)]]
    r = d.radius[trunk]
    y = d.points[trunk, 1]
    order = np.argsort(-y)  # from the foot up
    assert np.all(np.diff(r[order]) <= 0.02 * r.max()) and r[order[0]] > 1.2 * r[order[-1]]
    assert r.max() > 4 * np.median(d.radius)
    # Leonardo's rule: the trunk carries every tip, width = tip + pipe * sqrt(tips - 1)
    p = PareidoliaParams()
    k = np.sqrt(d.shape[0] / h * d.shape[1] / w)  # canvas px per lattice px
    middle = trunk[order[len(order) // 2]]
    carried = d.leaf_count()[middle]
    assert carried >= 0.95 * len(d.tips)
    assert 2 * d.radius[middle] / k == pytest.approx(p.tip_width + p.pipe * np.sqrt(carried - 1),
                                                     rel=0.1)


# ---------------------------------------------------------------- ties
def test_large_ties_are_replanned_non_scalar():
    from branchnb.dendrite import build_dendrite, make_lattice, path_statistics, plan
    from branchnb.dendrite.ties import refine_ties, tie_share

    lat = make_lattice(np.zeros((96, 96)), epsilon=0.5, noise=1.0, rng=2)
    res = plan(lat, (48, 48), metric="nonscalar")
    assert tie_share(res) > 0.9  # one edge opened almost the whole lattice at once
    ref = refine_ties(lat, res)
    np.testing.assert_array_equal(ref.max_cost, res.max_cost)  # M stays the bottleneck
    # still a tree in settle order: every parent is settled before its child
    rank = np.empty(lat.n_nodes, np.int64)
    rank[ref.order] = np.arange(len(ref.order))
    has = ref.parent >= 0
    assert np.all(rank[ref.parent[has]] < rank[has])
    assert sorted(ref.order.tolist()) == list(range(lat.n_nodes))
    # the new paths never use an edge above the node's M
    g = lat.to_sparse()
    nodes = np.flatnonzero(has)[::97]
    edges = np.array([g[ref.parent[v], v] for v in nodes])
    assert np.all(edges <= ref.max_cost[nodes] + 1e-12)
    # inside the tie the branches wander like non-scalar ones instead of running straight
    ends = np.column_stack([np.arange(4, 92, 8).repeat(11), np.tile(np.arange(4, 92, 8), 11)])
    before = np.nanmean(path_statistics(build_dendrite(res, ends), res).tortuosity)
    after = np.nanmean(path_statistics(build_dendrite(ref, ends), ref).tortuosity)
    assert after > before + 0.15
