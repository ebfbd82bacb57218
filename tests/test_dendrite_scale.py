"""Dendrites on inputs of any size (issue 25, items 1-4): the same ink and solid strokes
at 250 and 750 px, vines that stay readable from small to large inputs, lightning that
reads as lightning on an image, and pareidolia that reads as a tree and as the picture.

The objects are procedural, with a known mask: a green leaf with light veins on white,
and a drawn fish (black outline, grey body, faint scale circles) on white.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy import ndimage
from skimage import draw
from skimage.transform import resize

from branchnb import data
from branchnb.core.image import as_gray, as_rgb
from branchnb.dendrite import StylizeParams, Stylizer, stylize
from branchnb.dendrite.importance import gradient_strength
from branchnb.dendrite.metaphors import vine_curves
from branchnb.dendrite.pareidolia import PareidoliaParams, pareidolia_tree, tree_crown
from branchnb.dendrite.stylization import effective_params, metaphor_params


def _leaf(n):
    """An elliptic green leaf with a light midrib and side veins, and a stem."""
    h, w = n, int(0.75 * n)
    yy, xx = np.mgrid[0:h, 0:w] / n
    cx, top, bot = 0.375, 0.08, 0.78
    t = (yy - top) / (bot - top)
    blade = (t >= 0) & (t <= 1) & (np.abs(xx - cx) < 0.28 * np.sin(np.pi * np.clip(t, 0, 1)) ** 0.8)
    img = np.ones((h, w, 3), np.float32)
    img[blade] = np.array([0.25, 0.5, 0.18]) * (0.9 + 0.2 * (1 - t[blade, None]))
    img[(np.abs(xx - cx) < 0.006) & (yy > top) & (yy < bot)] = (0.85, 0.9, 0.6)
    stem = (np.abs(xx - cx) < 0.008) & (yy >= bot) & (yy < 0.95)
    img[stem] = (0.3, 0.35, 0.15)
    for k in range(7):
        y0 = top + (k + 1) / 8 * (bot - top) * 0.95
        for side in (-1, 1):
            d = side * (xx - cx)
            img[(d > 0) & (np.abs((yy - y0) + 0.6 * d) < 0.0035) & blade] = (0.8, 0.88, 0.55)
    img = ndimage.gaussian_filter(img, (0.6 * n / 500, 0.6 * n / 500, 0))
    return np.clip(img, 0, 1), blade | stem


def _fish(n):
    """A drawn fish on white: black outline, grey body, faint scale circles, an eye, a fin."""
    img = np.ones((n, n), np.float32)

    def ell(cy, cx, ry, rx, val):
        rr, cc = draw.ellipse(int(cy * n), int(cx * n), int(ry * n), int(rx * n), shape=(n, n))
        img[rr, cc] = val

    ell(0.5, 0.45, 0.22, 0.33, 0.0)
    ell(0.5, 0.45, 0.2, 0.31, 0.85)
    rr, cc = draw.polygon([0.5 * n, 0.3 * n, 0.7 * n], [0.74 * n, 0.95 * n, 0.95 * n], shape=(n, n))
    img[rr, cc] = 0.3
    for i in range(5):
        for j in range(3):
            rr, cc = draw.circle_perimeter(int((0.4 + 0.1 * j) * n), int((0.35 + 0.08 * i) * n),
                                           int(0.04 * n), shape=(n, n))
            img[rr, cc] = 0.2
    ell(0.45, 0.22, 0.035, 0.035, 0.0)
    img = ndimage.gaussian_filter(img, n / 700)
    return np.dstack([img] * 3).astype(np.float32), ndimage.binary_fill_holes(img < 0.95)


def _star(n, line=0.006):
    """A five-pointed star outlined by a thin black line (``line`` x n px wide) on white."""
    a = np.arange(10) * np.pi / 5 - np.pi / 2
    r = np.where(np.arange(10) % 2 == 0, 0.42, 0.18) * n
    inside = np.zeros((n, n), bool)
    rr, cc = draw.polygon(0.5 * n + r * np.sin(a), 0.5 * n + r * np.cos(a), (n, n))
    inside[rr, cc] = True
    dist = np.where(inside, ndimage.distance_transform_edt(inside),
                    ndimage.distance_transform_edt(~inside)) - 0.5
    img = 1.0 - np.clip(line * n / 2 + 0.5 - dist, 0, 1)
    return np.dstack([img] * 3).astype(np.float32), ndimage.binary_dilation(inside, iterations=2)


_OBJECTS = {"leaf": _leaf, "fish": _fish, "star": _star}


def _ink(rendering, mask):
    ink = 1.0 - as_gray(rendering)[mask]
    return float(ink.mean()), float((ink > 0.5).mean())


@pytest.mark.parametrize("name", list(_OBJECTS))
def test_same_ink_and_solid_strokes_at_250_and_750_px(name):
    out = {}
    for n in (250, 750):
        img, mask = _OBJECTS[name](n)
        s = stylize(img, rng=0)
        out[n] = _ink(s.rendering.image, mask), s
    (ink_s, solid_s), small = out[250]
    (ink_l, solid_l), _ = out[750]
    assert abs(ink_s - ink_l) <= 0.2 * ink_l
    assert solid_s >= 0.6 * solid_l
    # no stroke thinner than ~1 px at the output size (no pale grey hairlines)
    assert 2.0 * small.dendrite.radius.min() >= 0.99
    # a small image gets fewer endpoints (its strokes must fit between one another)
    assert len(small.endpoints) < StylizeParams().n_endpoints


def test_thin_outline_keeps_its_ink_on_a_small_image():
    # a 1.5-px outline at 250 px: the 1-px floor drew several parallel strokes along it
    # (1.8x the ink of the same star at 750 px); twigs_within_ink thins them to one
    (ink_s, solid_s), (ink_l, solid_l) = (_ink(stylize(_star(n)[0], rng=0).rendering.image,
                                               _star(n)[1]) for n in (250, 750))
    assert abs(ink_s - ink_l) <= 0.12 * ink_l
    assert solid_s >= 0.8 * solid_l


def test_twigs_within_ink_keeps_lone_lines():
    from branchnb.dendrite import build_dendrite, make_lattice, plan
    from branchnb.dendrite.thickness import twigs_within_ink

    # a comb: a long spine with short teeth, and one long lone stem hanging off it
    cost = np.ones((80, 80))
    cost[10, 5:76] = cost[10:, 40] = 0.0
    res = plan(make_lattice(cost, rng=0, noise=0.0), (40, 10))
    ends = [(x, 14) for x in range(10, 71, 3)] + [(40, 75)]
    d = build_dendrite(res, ends)
    d = d.with_radius(np.full(d.n_nodes, 1.0))
    keep = twigs_within_ink(d, np.full(d.n_nodes, 0.25), sigma=6.0, rng=0)
    stem = int(np.argmin(np.hypot(*(d.points[d.tips] - (40, 75)).T)))
    assert keep[stem]
    assert keep.mean() < 0.6  # the short teeth go
    assert twigs_within_ink(d, d.radius, sigma=6.0, rng=0).all()  # no excess: all kept


def test_same_ink_from_200_to_1000_px_on_a_photo():
    # a maple-leaf photo (258 px) resized: before, 1.44x the ink at 200 px as at 1000 px
    leaf = as_rgb(data.load("maple_leaf_03"))
    out = []
    for n in (200, 1000):
        f = n / max(leaf.shape[:2])
        img = resize(leaf, (round(leaf.shape[0] * f), round(leaf.shape[1] * f), 3),
                     anti_aliasing=True).astype(np.float32)
        mask = ndimage.binary_fill_holes(as_gray(img) < 0.9)
        out.append(_ink(stylize(img, rng=0).rendering.image, mask))
    (ink_s, solid_s), (ink_l, solid_l) = out
    assert abs(ink_s - ink_l) <= 0.2 * ink_l
    assert solid_s >= 0.6 * solid_l


def test_images_larger_than_the_lattice_keep_its_widths():
    # a 1000-px and a 2000-px input are drawn as the 512-px picture scaled up
    p = StylizeParams()
    assert effective_params(p, 2.0) == effective_params(p, 4.0) == effective_params(p, 1.0)
    assert effective_params(p, 4.0).min_width == p.output_width


def test_outline_weighted_after_the_tone_match():
    img, mask = _fish(400)
    st = Stylizer(img)
    # output_width=0: the same tree for both (no twigs dropped to fit the ink of a small image)
    plain = st.run(StylizeParams(edges=0.0, output_width=0.0), rng=0, metaphor=None).dendrite
    weighted = st.run(StylizeParams(output_width=0.0), rng=0, metaphor=None).dendrite
    assert weighted is not plain
    # nodes on the fish's black outline (strong edges) get wider, flat regions stay
    g = gradient_strength(img)
    at = np.rint(weighted.points).astype(int)
    edge = g[at[:, 1], at[:, 0]] > 0.6
    flat = g[at[:, 1], at[:, 0]] < 0.05
    assert edge.sum() > 50 and flat.sum() > 50
    gain = weighted.radius / plain.radius
    assert np.median(gain[edge]) > 1.3
    assert np.median(gain[flat]) < 1.05


def test_effective_params_keep_every_field_in_range():
    for scale in (0.01, 0.1, 0.5, 1.0, 3.0):
        q = effective_params(StylizeParams(), scale)
        assert q.min_width <= q.max_width <= 30.0 and q.min_width <= 10.0
        assert 1 <= q.n_endpoints <= StylizeParams().n_endpoints
    assert effective_params(StylizeParams(output_width=0.0), 0.3) == StylizeParams(output_width=0.0)


# ------------------------------------------------------------------- vines
def _green(rendering):
    r = rendering
    return (r[..., 1] > r[..., 0] + 0.1) & (r[..., 1] > r[..., 2] + 0.1)


@pytest.mark.parametrize("n", [250, 1000])
def test_vines_readable_at_any_size(n):
    img, mask = _fish(n)
    st = Stylizer(img)
    s = st.run(rng=0, metaphor="vines")
    # the endpoint count follows the object's area and the leaf size (drawn: sized to the
    # object since dendrite35), not the paper's 3,000
    leaf = st._vine_leaf
    expect = mask.mean() * n * n / (2.5 * leaf) ** 2
    assert 0.5 * expect < len(s.endpoints) < 2.0 * expect
    # no overgrown mass: most of the object stays paper
    ink = 1.0 - as_gray(s.rendering.image)
    assert (ink[mask] > 0.2).mean() < 0.35
    # no green noise: leaves at least 6 px long, and there are leaves
    _, _, leaves, _ = vine_curves(s.dendrite, rng=0)
    lengths = [np.hypot(*(lf[-1] - lf[0])) for lf in leaves]
    assert len(leaves) > 10 and np.median(lengths) >= 6.0
    assert _green(s.rendering.image).mean() > 0.01


def test_vine_endpoints_follow_area_and_size():
    p = StylizeParams()
    small = metaphor_params(p, "vines", (250, 250), 0.5, 250 / 512)
    large = metaphor_params(p, "vines", (1000, 1000), 0.5, 1000 / 512)
    half = metaphor_params(p, "vines", (1000, 1000), 0.25, 1000 / 512)
    assert small.n_endpoints < large.n_endpoints < p.n_endpoints
    assert half.n_endpoints == pytest.approx(large.n_endpoints / 2, abs=1)
    assert metaphor_params(p, "plain", (1000, 1000), 0.5, 2.0) is p


# --------------------------------------------------------------- lightning
def test_lightning_on_an_image_reads_as_bolts_along_its_edges():
    img = as_rgb(data.load("camera"))
    img = resize(img, (256, 256), anti_aliasing=True).astype(np.float32)
    s = stylize(img, rng=0, metaphor="lightning")
    d = s.dendrite
    # a few hundred branches at most, not the paper's 3,000 (a glowing scribble)
    assert len(s.endpoints) < 400
    # a hierarchy of channels: the main ones several times wider than the twigs
    w = 2 * d.radius
    assert np.percentile(w, 99) >= 2.5 * np.median(w)
    # the sky stays dark: the bright core covers a small share of the picture
    lum = as_gray(s.rendering.image)
    assert (lum > 0.8).mean() < 0.12 and np.median(lum) < 0.25
    # the bolts run along the picture's edges
    g = gradient_strength(img, sigma=1.5)
    core = lum > 0.8
    assert g[core].mean() > 1.8 * g.mean()
    # thin branches are dimmer than the main channels
    thin = np.flatnonzero(w <= w.min() * 1.01)
    wide = np.flatnonzero(w >= w.max() * 0.99)
    assert len(thin) > 100 and len(wide) > 20

    def brightness(idx):
        at = np.rint(d.points[idx]).astype(int)
        return float(lum[at[:, 1], at[:, 0]].mean())

    assert brightness(wide) > brightness(thin) + 0.05


def test_lightning_at_200_px_looks_like_the_larger_bolt_shown_small():
    # below 512 px the widths follow the diagonal too (floors 0.4 / 2 px instead of 1 / 3):
    # before, a 200-px bolt's twigs were as wide and bright as its core (mean brightness
    # 0.24 vs 0.16 for the 600-px bolt shown at 200 px, 7 % bright pixels vs 2.5 %)
    src = as_rgb(data.load("astronaut"))
    lum = {}
    for n in (200, 600):
        img = resize(src, (n, n), anti_aliasing=True).astype(np.float32)
        lum[n] = as_gray(stylize(img, rng=0, metaphor="lightning").rendering.image)
    small = resize(lum[600], (200, 200), anti_aliasing=True)
    assert lum[200].mean() == pytest.approx(small.mean(), rel=0.2)
    assert (lum[200] > 0.7).mean() == pytest.approx((small > 0.7).mean(), rel=0.35)
    # still a hierarchy: the main channels burn white
    assert (lum[200] > 0.9).mean() > 0.003


def test_lightning_widths_follow_the_diagonal_above_the_lattice():
    # before, 1-px twigs on a 2000-px image: the pipe model never reached the widest
    # channel and the whole picture was dim (bright core 0.8 % of the image vs 2.8 % at 500 px)
    p = StylizeParams()
    q = [metaphor_params(p, "lightning", (n, n), 1.0, n / 512) for n in (512, 1024, 2048)]
    assert q[0].min_width == pytest.approx(q[1].min_width) == pytest.approx(q[2].min_width)
    assert q[0].max_width == pytest.approx(q[1].max_width) == pytest.approx(q[2].max_width)


# -------------------------------------------------------------- pareidolia
def _tone_r(a, b, mask, sigma=4.0):
    x = ndimage.gaussian_filter(1.0 - as_gray(a).astype(np.float64), sigma)[mask]
    y = ndimage.gaussian_filter(1.0 - as_gray(b).astype(np.float64), sigma)[mask]
    return float(np.corrcoef(x, y)[0, 1])


@pytest.fixture(scope="module")
def portrait_tree():
    img = resize(as_rgb(data.load("astronaut")), (320, 320), anti_aliasing=True).astype(np.float32)
    return pareidolia_tree(img, rng=0)


def test_pareidolia_portrait_tone_in_the_crown(portrait_tree):
    t = portrait_tree
    assert _tone_r(t.image, t.render().image, t.crown_on_canvas()) >= 0.7


def test_pareidolia_crown_is_a_crown_not_the_frame(portrait_tree):
    t = portrait_tree
    crown = t.crown
    rows = np.flatnonzero(crown.any(axis=1))
    top = crown[rows[0]:rows[0] + 3].sum()
    middle = crown[rows[len(rows) // 2]].sum()
    assert middle > 2 * top / 3 * 1.5  # rounded at the top, not a flat edge
    # the corners of the picture are outside the crown
    n = rows[-1] + 1
    assert not crown[0, 0] and not crown[0, -1] and not crown[n - 1, 0] and not crown[n - 1, -1]
    # a lobed outline: the crown's boundary radius varies around a smooth ellipse
    c = tree_crown((200, 160), rng=3)
    assert 0.6 < c.mean() < 0.8


def test_pareidolia_limbs_grow_from_the_trunk_and_twigs_taper(portrait_tree):
    t = portrait_tree
    d = t.dendrite
    crown = t.crown_on_canvas()
    at = np.rint(d.points).astype(int)
    inside = crown[np.clip(at[:, 1], 0, crown.shape[0] - 1), np.clip(at[:, 0], 0, crown.shape[1] - 1)]
    # limbs: the first iteration's branches inside the crown are much wider than the twigs
    limbs = (d.iteration == 1) & inside
    assert limbs.sum() > 50
    assert np.percentile(d.radius[limbs], 75) > 2 * np.median(d.radius[inside & (d.iteration > 1)])
    # the limbs fan out: they reach well above the fork point, left and right of the trunk
    fork_y = d.points[d.iteration == 1][:, 1][~inside[d.iteration == 1]].min()
    ly = d.points[limbs]
    assert (ly[:, 1] < fork_y - 0.25 * crown.shape[0]).any()
    assert np.ptp(ly[:, 0]) > 0.4 * crown.shape[1]
    # twig ends taper: at a tip the width is well below the width a few px back
    dist = d.tip_distance()
    tips = d.tips[inside[d.tips]]
    back = np.array([_ancestor(d, i, dist, 6.0) for i in tips])
    ok = back >= 0
    assert ok.mean() > 0.5
    assert np.median(d.radius[tips[ok]] / d.radius[back[ok]]) < 0.6


def test_pareidolia_on_a_larger_image_gets_more_endpoints():
    # drawn back at 2x, the lattice's tree would have its branches twice as far apart:
    # 4x the endpoints (they share an area) keep them as far apart in image px
    img = np.ones((128, 128))
    img[30:90, 40:100] = 0.2
    p = PareidoliaParams(n_endpoints=100, iterations=2, lattice_size=64, max_upscale=2.0)
    small = pareidolia_tree(img[::2, ::2], p, rng=0)
    large = pareidolia_tree(img, p, rng=0)
    assert len(small.endpoints_image) == 100
    assert len(large.endpoints_image) == 400
    # ... and the trunk is as wide in image px as the picture is large (2x), not wider
    # because it carries more twigs (the pipe model's gain falls with the density: with the
    # gain as given it was 2.5x wider on a 2000-px cat photo than at 1000 px)
    ratio = large.dendrite.radius[0] / small.dendrite.radius[0]
    assert 1.6 < ratio < 2.4, ratio


def _ancestor(d, i, dist, how_far):
    """The first ancestor of tree node ``i`` at least ``how_far`` px from its tip (or -1)."""
    j = i
    while j >= 0 and dist[j] < how_far:
        j = int(d.parent[j])
    return j


def test_next_in_branch_stays_on_the_junctions_own_branch():
    from branchnb.dendrite import build_dendrite, make_lattice, plan

    res = plan(make_lattice(np.zeros((40, 40)), rng=0), (20, 39))
    d = build_dendrite(res, [(3, 3), (36, 5), (20, 2)])
    nxt = d.next_in_branch()
    own, _ = d.owner()
    for i, b in enumerate(d.branches):
        if d.branch_parent[i] < 0:
            continue
        junction = b[0]
        # the junction continues its parent branch, never into the side branch
        assert own[junction] != i and nxt[junction] != b[1]
        if nxt[junction] >= 0:
            assert own[nxt[junction]] == own[junction]
    # a rolling window along a branch is then smooth through the junctions
    from branchnb.dendrite import rolling_importance

    ramp = np.tile(np.linspace(0, 1, 40), (40, 1))
    r = rolling_importance(d, ramp, 9)
    main = max(d.branches, key=len)
    assert np.abs(np.diff(r[main][4:-4])).max() < 0.05


def test_pareidolia_twig_ends_taper_in_dark_regions_too():
    # before, the tone match widened the ends of a dark region's twigs as much as their
    # bodies (more: less ink around an end), and round caps drew them as dots
    img = np.ones((96, 96))
    img[20:76, 16:80] = 0.05
    t = pareidolia_tree(img, PareidoliaParams(n_endpoints=120, iterations=3, lattice_size=0), rng=0)
    d = t.dendrite
    dist = d.tip_distance()
    at = np.rint(d.points[d.tips]).astype(int)
    tips = d.tips[img[np.clip(at[:, 1], 0, 95), np.clip(at[:, 0], 0, 95)] < 0.5]
    back = np.array([_ancestor(d, i, dist, 6.0) for i in tips])
    ok = back >= 0
    assert ok.sum() > 20
    ratio = d.radius[tips[ok]] / d.radius[back[ok]]
    assert ratio.max() <= 0.3 + 1e-9  # every end, not only the median
    # no node within the last 6 px is wider than the branch 6 px back
    near = np.flatnonzero(dist < 6.0)
    body = np.array([_ancestor(d, i, dist, 6.0) for i in near])
    assert (d.radius[near[body >= 0]] <= d.radius[body[body >= 0]] + 1e-9).all()


def test_pareidolia_lattice_grows_on_large_pictures():
    # a 2000-px picture planned on a 512 lattice had its twigs 4 image px per lattice px
    # apart, and tone r at 4 px blur fell from 0.72 (1000 px) to 0.60 (a portrait)
    img = np.ones((256, 256))
    img[60:200, 70:190] = 0.3
    p = PareidoliaParams(n_endpoints=40, iterations=2, lattice_size=64, max_upscale=2.0)
    t = pareidolia_tree(img, p, rng=0)
    assert t.importance.shape[1] == 128  # the picture's side / max_upscale
    assert len(t.endpoints_image) == 40 * 2 ** 2 * 4  # x (image px per lattice px) ** 2 x lattice area
    assert t.dendrite.shape == t.image.shape[:2]
    q = pareidolia_tree(img, PareidoliaParams(n_endpoints=40, iterations=2, lattice_size=64,
                                              max_upscale=4.0), rng=0)
    assert q.importance.shape[1] == 64 and len(q.endpoints_image) == 640
    # the default: the lattice follows the picture up to max_lattice
    r = pareidolia_tree(img, PareidoliaParams(n_endpoints=40, iterations=2, lattice_size=64,
                                              max_lattice=192), rng=0)
    assert r.importance.shape[1] == 192 and len(r.endpoints_image) == round(40 * (256 / 192) ** 2 * 9)


def test_pareidolia_low_contrast_picture_is_stretched():
    # mid-grey fur (darkness 0.4-0.6) drowned in the branches' texture: tone r at 4 px
    # blur 0.61 on a 1000-px cat photo; stretched to the full range it reads (0.76)
    yy, xx = np.mgrid[0:96, 0:96]
    img = 0.45 + 0.15 * (xx > 48) + 0.05 * ((yy - 48) ** 2 + (xx - 30) ** 2 < 150)
    p = PareidoliaParams(n_endpoints=300, iterations=3, lattice_size=0, refine=0)
    ink = {}
    for c in (0.0, 1.0):
        t = pareidolia_tree(img, dataclasses.replace(p, contrast=c), rng=0)
        out = 1.0 - as_gray(t.render().image)[:96]
        ink[c] = out[:, 56:90].mean() / out[:, 6:40].mean()  # light half over dark half
    assert ink[1.0] < 0.75 * ink[0.0]
    from branchnb.dendrite.pareidolia import _stretch

    dark = 1.0 - img.astype(np.float32)
    s = _stretch(dark, np.ones_like(dark, bool), 1.0)
    assert s.min() == 0.0 and s.max() > 0.7  # 0.2 of range stretched to 0.75 (gain 5 at most)
    flat = _stretch(np.full((8, 8), 0.5, np.float32) + 0.01 * np.eye(8, dtype=np.float32),
                    np.ones((8, 8), bool), 1.0)
    assert np.ptp(flat) <= 5 * 0.01 + 1e-6  # a nearly flat picture: gain at most 5


def test_pareidolia_refine_matches_tone_at_the_output_size():
    # planned on a lattice 3x coarser than the picture, the lattice tone match works over
    # 15 output px; the pass on the drawing itself follows the picture at the output's scale
    yy, xx = np.mgrid[0:192, 0:192]
    img = np.ones((192, 192))
    img[((yy - 80) ** 2 + (xx - 96) ** 2) < 70 ** 2] = 0.35
    img[40:70, 50:150] = 0.05
    img[100:150, 60:90] = 0.8
    p = PareidoliaParams(n_endpoints=400, iterations=3, lattice_size=64, max_upscale=3.0)
    r = {}
    for k in (0, 2):
        t = pareidolia_tree(img, dataclasses.replace(p, refine=k), rng=0)
        assert t.importance.shape[1] == 64
        r[k] = _tone_r(t.image, t.render().image, t.crown_on_canvas(), 3.0)
        d = t.dendrite
        assert d.is_tree() and d.shape == t.image.shape[:2]
    assert r[2] > r[0] + 0.03


def _limb_reach(t):
    """Share of the crown's height (above the fork) reached by branches wider than twice
    the twig width along their whole path from the root."""
    d = t.dendrite
    crown = t.crown_on_canvas()
    at = np.rint(d.points).astype(int)
    inside = crown[np.clip(at[:, 1], 0, crown.shape[0] - 1), np.clip(at[:, 0], 0, crown.shape[1] - 1)]
    w = 2 * d.radius
    twig = inside & (d.iteration == d.iteration.max()) & (w >= 0.5)
    thick = w > 2 * max(float(np.median(w[twig])), 1.0)
    for i in range(d.n_nodes):  # parent[i] < i: thick all the way from the root
        if d.parent[i] >= 0 and not thick[d.parent[i]]:
            thick[i] = False
    rows = np.flatnonzero(crown.any(axis=1))
    # the trunk is traced first, to the fork: its end is the first tip (the end of the
    # first unbroken chain of nodes is not, when a limb continues straight up from it)
    fork_y = d.points[d.tips[0], 1]
    return (fork_y - d.points[thick & inside, 1].min()) / (rows[-1] - rows[0])


def test_pareidolia_limbs_stay_thick_into_the_crown(portrait_tree):
    # the pipe model over all twigs thinned the limbs soon after the fork (twigs hang
    # mostly from their lower parts): limbs wider than 2 twigs reached 0.17 of the crown's
    # height on this portrait (0.0-0.28 on six 500/1000-px pictures); a pipe model over the
    # limbs' ends carries them into the crown
    assert _limb_reach(portrait_tree) > 0.4
    t = portrait_tree
    assert _tone_r(t.image, t.render().image, t.crown_on_canvas()) >= 0.8  # 0.88 before


def test_limb_widths_follow_the_pipe_model_and_the_trunk_top_has_no_knob():
    from branchnb.dendrite import build_dendrite, make_lattice, plan
    from branchnb.dendrite.pareidolia_widths import _limb_widths

    lat = make_lattice(np.zeros((120, 100)), rng=0)
    trunk = build_dendrite(plan(lat, (50, 119)), [(50, 60)], iteration=1)
    k = round(0.75 * trunk.n_nodes) - 1
    seeds = np.zeros((120, 100), bool)
    ys, xs = np.divmod(trunk.nodes[k:], 100)
    seeds[ys, xs] = True
    d = build_dendrite(plan(make_lattice(np.zeros((120, 100)), rng=1), seeds),
                       [(10, 10), (30, 5), (70, 5), (90, 12), (50, 2)], base=trunk, iteration=1)
    w = _limb_widths(d, k, 12.0, 4.0, 0.5)
    assert w[k] == pytest.approx(12.0)  # every end's pipe at its departure: the trunk's width
    assert w[0] == pytest.approx(12.0)
    # Leonardo's rule at every junction: width^2 of the parent = sum over the children
    kids = {}
    for i in np.flatnonzero(d.parent >= 0):
        kids.setdefault(int(d.parent[i]), []).append(i)
    junctions = [j for j, c in kids.items() if len(c) > 1]
    assert junctions
    for j in junctions:
        assert w[j] ** 2 == pytest.approx(sum(w[c] ** 2 for c in kids[j]), rel=0.1)
    # the limbs keep at least limb_width over most of their length, and end at a twig
    arc = d.arc_depth()
    for e in d.tips[d.tips >= trunk.n_nodes]:
        path = [e]
        while d.parent[path[-1]] >= 0:
            path.append(int(d.parent[path[-1]]))
        t = (arc[path] - arc[k]) / (arc[e] - arc[k])
        assert (w[path][t <= 0.8] >= 4.0 - 1e-9).all()
        assert w[e] == pytest.approx(0.5)
    # the trunk's own top (no limb continues from it) narrows instead of ending as wide
    # as the trunk (a knob): before, it kept its pipe width up to its round cap
    top = trunk.n_nodes - 1
    if not any(d.iteration[c] == 1 for c in kids.get(top, [])):
        assert w[top] < 0.2 * w[k]


def test_pareidolia_limbs_keep_off_a_bright_object():
    # a night sky with a lit tower up the middle (a rocket on its pad): on the importance's
    # cost the limbs followed the tower's strong edges, half their ink within 4 px of it,
    # drawn as a thick dark limb over the brightest part of the picture (tone r at 4 px
    # blur 0.42 on a 500-px night photo of a rocket; 0.50 now)
    yy, xx = np.mgrid[0:160, 0:160]
    img = np.full((160, 160), 0.2) + 0.1 * yy / 160
    bar = (np.abs(xx - 80) < 5) & (yy > 20)
    img[bar] = 0.95
    img = ndimage.gaussian_filter(img, 1.0)
    t = pareidolia_tree(img, PareidoliaParams(n_endpoints=400, lattice_size=0), rng=0)
    d = t.dendrite
    at = np.rint(d.points).astype(int)
    limb = (d.iteration == 1) & (at[:, 1] < 160) & (np.arange(d.n_nodes) > d.tips[0])
    near = ndimage.binary_dilation(bar, iterations=4)[np.clip(at[:, 1], 0, 159),
                                                      np.clip(at[:, 0], 0, 159)]
    w = 2 * d.radius
    assert limb.sum() > 100
    assert (w * (near & limb)).sum() < 0.2 * (w * limb).sum()


def test_pareidolia_night_sky_is_equalised(monkeypatch):
    # a night photo: a dark sky over most of the crown, a lit tower and a dark mast. With
    # the linear stretch alone the sky got nearly even ink, its gradient lost in the
    # twigs' texture (tone r at 4 px blur 0.50 on a 500-px night photo of a rocket; with
    # half the tone map equalised over the crown's histogram 0.62)
    import functools

    from branchnb.dendrite import pareidolia as par

    yy, xx = np.mgrid[0:200, 0:200]
    img = 0.12 + 0.25 * yy / 200
    img[(np.abs(xx - 100) < 6) & (yy > 40)] = 0.9
    img[(np.abs(xx - 40) < 2) & (yy > 80)] = 0.05
    img = ndimage.gaussian_filter(img, 1.0)
    r = {}
    # the dark photos' tone map after the stretch (_TONE_MEAN, dendrite45) does much of what
    # the equalisation does here (r at 4 px: linear 0.547 -> 0.656, half equalised 0.642 ->
    # 0.641; at 2 / 8 px 0.485 / 0.675 -> 0.508 / 0.699): the equalisation is measured
    # without it
    monkeypatch.setattr(par, "_TONE_MEAN", 0.0)
    for eq in (0.0, 0.5):
        monkeypatch.setattr(par, "_stretch", functools.partial(_stretch_orig, equalize=eq))
        t = pareidolia_tree(img, PareidoliaParams(n_endpoints=600), rng=0)
        r[eq] = _tone_r(t.image, t.render().image, t.crown_on_canvas())
    assert r[0.5] > r[0.0] + 0.05, r
    # the sky's tones (darkness 0.63-0.88, most of the crown) spread wider
    dark = (1.0 - img).astype(np.float32)
    sky = (yy > 20) & (np.abs(xx - 100) > 12) & (np.abs(xx - 40) > 6)
    spread = [np.ptp(_stretch_orig(dark, np.ones_like(dark, bool), 1.0, equalize=e)[sky])
              for e in (0.0, 0.5)]
    assert spread[1] > spread[0] + 0.1, spread


def test_pareidolia_dark_regions_get_solid_ink():
    # a night photo (skimage's rocket): a dark sky over most of the crown. With twigs at
    # most 5 px wide the darkest tones read mid-grey and the texture drowned the picture
    # (tone r at 4 px blur here 0.72 -> 0.80; at 500 px 0.62 -> 0.71, 0.80 with the fork
    # on the dark side of the lit rocket)
    from skimage import data as skdata

    img = resize(skdata.rocket() / 255.0, (169, 300), anti_aliasing=True).astype(np.float32)
    r = {}
    for mw in (5.0, 8.0):
        t = pareidolia_tree(img, PareidoliaParams(max_width=mw), rng=0)
        r[mw] = _tone_r(t.image, t.render().image, t.crown_on_canvas())
    assert PareidoliaParams().max_width == 8.0
    # (issue 25, dendrite28: with more twigs on a picture dark all over and the limbs' ink
    # budgeted, r 0.80 -> 0.89 at max_width 8 and 0.87 at 5: the default still ahead)
    assert r[8.0] >= 0.7 and r[8.0] > r[5.0] + 0.01, r


def test_pareidolia_trunk_enters_the_crown_beside_a_light_object():
    # a dark picture with a lit tower up its middle: the trunk (the widest stroke) entered
    # the crown below the centre, drawn black over the tower's foot (the lit rocket at
    # 1000 px: 43 % of the tone error within 8 px of the trunk and limbs, 9 % of the crown)
    from branchnb.dendrite.pareidolia import _fork_point

    yy, xx = np.mgrid[0:200, 0:200]
    img = np.full((200, 200), 0.15)
    tower = np.abs(xx - 100) < 12
    img[tower] = 0.95
    t = pareidolia_tree(ndimage.gaussian_filter(img, 1.0), PareidoliaParams(n_endpoints=600), rng=0)
    d = t.dendrite
    trunk = d.iteration == 1
    low = trunk & (d.points[:, 1] > 200)  # the trunk in the blank strip below the picture
    assert abs(np.median(d.points[low, 0]) - 100) > 14
    # ... and straight: its foot under its fork
    assert np.ptp(d.points[low, 0]) < 12
    # a plain crown keeps the centre
    crown = np.zeros((100, 100), bool)
    crown[10:80, 20:80] = True
    assert _fork_point(crown, np.zeros((100, 100)))[0] == pytest.approx(49.5, abs=0.6)
    assert _fork_point(crown)[0] == pytest.approx(49.5, abs=0.6)


from branchnb.dendrite.pareidolia_widths import _stretch as _stretch_orig  # noqa: E402


def test_blur_at_nodes_is_scipys_gaussian_bit_for_bit():
    # twigs_within_ink and tone_thickness blur only at the nodes (issue 25): the same numbers
    from scipy import ndimage

    from branchnb.dendrite.thickness import _blur_at

    rng = np.random.default_rng(0)
    for t in range(60):
        h, w = (int(v) for v in rng.integers(3, 70, 2))
        nodes = np.unique(rng.integers(0, h * w, int(rng.integers(1, 40))))
        if t % 3 == 0:  # dense (a darkness map) or sparse (an ink map)
            img = rng.random((h, w))
        else:
            img = np.zeros((h, w))
            img.ravel()[nodes] = rng.random(nodes.size)
        sigma = float(rng.choice([0.6, 2.0, 5.3, 30.0]))
        assert np.array_equal(_blur_at(img, nodes, sigma), ndimage.gaussian_filter(img, sigma).ravel()[nodes])
    # both first passes: a few nodes in a large map (sparse) and a map with ink on a
    # tenth of its pixels in every row (dense: scipy's own pass, 1.5x faster there)
    for share in (0.0005, 0.1):
        img = np.zeros((150, 120))
        nodes = np.unique(rng.integers(0, img.size, int(share * img.size) + 3))
        img.ravel()[nodes] = rng.random(nodes.size)
        assert np.array_equal(_blur_at(img, nodes, 9.0), ndimage.gaussian_filter(img, 9.0).ravel()[nodes])
