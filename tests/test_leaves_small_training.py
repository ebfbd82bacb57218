"""Small leaves (96-128 px): training layers grown from a user's few strokes cover the thin veins.

Procedural leaves of three kinds (lobed with five primaries and 1-px
laterals, elliptic with a midrib and pinnate 1-px secondaries, a strap-like
strip with five parallel veins), flat colour, darker anti-aliased veins 1-2
px wide (truth: coverage >= 0.5). The user draws radius-1 strokes over the
middle of the midrib(s) and three laterals, and one blade blob.

Before (main at ea60042, seeds 0 / 1): strip 96 px IoU 0.49 / 0.50, strip
128 px 0.64 / 0.91, lobed 96 px 0.67 / 0.68. After: strip 0.63 / 0.65 and
0.81 / 0.81, lobed 0.85 / 0.86 (``_lines._plain_level``'s far-blade level
on a flat blade, the blade scribbles' level in ``_line_channel``,
``layers._on_layer``'s split ring).
"""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.leaves import Layer, LayerSet, grow_layers


def _rot(p, c, a):
    ca, sa = np.cos(a), np.sin(a)
    q = p - c
    return np.stack([c[0] + q[:, 0] * ca - q[:, 1] * sa, c[1] + q[:, 0] * sa + q[:, 1] * ca], 1)


def _leaf(kind, S, seed, contrast=0.6):
    """``(image, blade, veins, lines)``; ``lines`` (polyline, width px, is_main), the mains first."""
    rng = np.random.default_rng(seed)
    c = np.array([S * 0.5, S * 0.55]) + rng.normal(0, S * 0.01, 2)
    rot = rng.uniform(-0.5, 0.5)
    lines = []
    if kind == "lobed":
        R = S * rng.uniform(0.36, 0.42)
        lobes = [(0.0, 1.0), (0.95, 0.85), (-0.95, 0.85), (1.9, 0.55), (-1.9, 0.55)]
        a = np.linspace(-np.pi, np.pi, 720, endpoint=False)
        r = np.full_like(a, 0.3)
        for ai, li in lobes:
            d = np.angle(np.exp(1j * (a - ai)))
            r = np.maximum(r, li * rng.uniform(0.9, 1.1) * np.clip(1 - np.abs(d) / 0.85, 0, None) ** 0.6)
        r = R * r * (1 + 0.03 * np.sign(np.sin(a * 40)))
        out = np.stack([c[0] + r * np.cos(a - np.pi / 2), c[1] + r * np.sin(a - np.pi / 2)], 1)
        for ai, _ in lobes:
            k = int(np.argmin(np.abs(np.angle(np.exp(1j * (a - ai))))))
            tip = c + 0.88 * r[k] * np.array([np.cos(ai - np.pi / 2), np.sin(ai - np.pi / 2)])
            lines.append((c + np.linspace(0, 1, 30)[:, None] * (tip - c), 2, True))
            L = np.linalg.norm(tip - c)
            for f in (0.35, 0.65):
                for sgn in (-1, 1):
                    b = ai - np.pi / 2 + sgn * 0.75
                    q = c + f * (tip - c) + np.linspace(0, 1, 15)[:, None] * L * 0.38 * (1.1 - f) * \
                        np.array([np.cos(b), np.sin(b)])
                    lines.append((q, 1, False))
    elif kind == "elliptic":
        hl, hw = S * rng.uniform(0.40, 0.44), S * rng.uniform(0.16, 0.20)
        t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
        out = np.stack([c[0] + hw * np.sin(t) * (1 - 0.25 * np.cos(t)), c[1] - hl * np.cos(t)], 1)
        lines.append((np.stack([np.full(30, c[0]), np.linspace(c[1] + hl * 0.98, c[1] - hl * 0.92, 30)], 1),
                      2, True))
        for y in np.linspace(-0.6, 0.6, 6):
            for sgn in (-1, 1):
                wy = hw * (1 + 0.25 * y) * np.sqrt(max(0.0, 1 - y * y))
                xs = np.linspace(0, 0.9, 15)
                q = np.stack([c[0] + sgn * xs * wy,
                              c[1] + y * hl + sgn * 0.04 * hl - xs * 0.5 * hw - 0.2 * hw * xs**2], 1)
                lines.append((q, 1, False))
    else:
        L, hw = S * rng.uniform(0.42, 0.46), S * rng.uniform(0.09, 0.11)
        u = np.linspace(-1, 1, 60)
        bend = rng.uniform(-0.05, 0.05) * S

        def at(v):
            return np.stack([c[0] + v * hw + bend * (1 - u**2), c[1] + u * L], 1)

        out = np.concatenate([at(1.0), at(-1.0)[::-1]])
        for v in (0.0, -0.5, 0.5, -0.82, 0.82):
            lines.append((at(v)[2:-2], 2 if v == 0 else 1, v == 0))
    out = _rot(out, c, rot)
    lines = [(_rot(p, c, rot), w, m) for p, w, m in lines]
    blade = np.zeros((S, S), np.uint8)
    cv2.fillPoly(blade, [np.round(out).astype(np.int32)], 1)
    blade = blade > 0
    ss = 4
    cov = np.zeros((S * ss, S * ss), np.uint8)
    for p, w, _ in lines:
        cv2.polylines(cov, [np.round((p + 0.5) * ss - 0.5).astype(np.int32)], False, 255, thickness=w * ss)
    cov = cv2.resize(cov.astype(np.float32) / 255, (S, S), interpolation=cv2.INTER_AREA)
    cov = cov * ndi.binary_erosion(blade, iterations=1)
    col = np.array([0.36, 0.58, 0.2]) * rng.uniform(0.9, 1.1)
    img = np.ones((S, S, 3), np.float32)
    img[blade] = col + 0.01 * rng.standard_normal((blade.sum(), 3))
    img = np.where(blade[..., None], img * (1 - cov[..., None]) + contrast * col * cov[..., None], img)
    return np.clip(img, 0, 1).astype(np.float32), blade, cov >= 0.5, lines


def _strokes(lines, blade, veins, seed):
    """Radius-1 strokes over the middle half of the midrib(s) and three laterals; one blade blob."""
    rng = np.random.default_rng(seed + 100)
    mains = [i for i, x in enumerate(lines) if x[2]]
    lats = [i for i, x in enumerate(lines) if not x[2]]
    ls = LayerSet([Layer("veins")])
    h, w = blade.shape
    for i in mains[:2] + list(rng.choice(lats, 3, replace=False)):
        p = lines[i][0]
        q = np.round(p[int(len(p) * 0.2):int(len(p) * 0.7)])
        q = q[veins[q[:, 1].astype(int).clip(0, h - 1), q[:, 0].astype(int).clip(0, w - 1)]]
        if len(q) >= 2:
            ls.add_scribble("veins", q, radius=1)
    d = ndi.distance_transform_edt(blade & ~veins)
    y, x = np.unravel_index(np.argmax(d), d.shape)
    r = max(1.5, min(4.0, d[y, x] - 1))
    ls.add_scribble("blade", [(x - r, y), (x + r, y)], radius=r)
    return ls


@pytest.mark.parametrize("kind", ["lobed", "elliptic", "strip"])
@pytest.mark.parametrize("size,least", [(96, 0.6), (128, 0.7)])
def test_small_training_layers_cover_the_thin_veins(kind, size, least):
    for seed in (0, 1):
        img, blade, veins, lines = _leaf(kind, size, seed)
        m = grow_layers(img, blade, _strokes(lines, blade, veins, seed), rng=0).masks["veins"]
        iou = (m & veins).sum() / max(1, (m | veins).sum())
        # main: strip 96 px 0.49 / 0.50, strip 128 px seed 0 0.64; lobed 96 px 0.67 / 0.68.
        assert iou >= least, (seed, iou)
        assert 0.6 * veins.sum() <= m.sum() <= 1.4 * veins.sum(), (seed, m.sum() / veins.sum())


def test_large_leaf_keeps_its_training_layer():
    """The same lobed leaf at 400 px (veins still 1-2 px wide): IoU 0.85 before and after."""
    img, blade, veins, lines = _leaf("lobed", 400, 0)
    m = grow_layers(img, blade, _strokes(lines, blade, veins, 0), rng=0).masks["veins"]
    assert (m & veins).sum() / (m | veins).sum() >= 0.8


def test_small_leaves_induce_unbroken_veins():
    """Induced on the other leaves of a 128-px lobed family: main IoU 0.81-0.83, 71-76 % of the true veins
    in one piece along 90 % of their length; now 0.91-0.93 and every vein."""
    from branchnb.leaves import analyze

    fam = [_leaf("lobed", 128, s) for s in range(3)]
    a = analyze([np.dstack([f[0], f[1].astype(np.float32)]) for f in fam], 0,
                _strokes(fam[0][3], fam[0][1], fam[0][2], 0))
    for i in (1, 2):
        img, blade, veins, lines = fam[i]
        m = np.asarray(a.layers[0].masks[i], bool)
        dx, dy = (int(v) for v in a.offsets[i])
        truth = np.zeros(m.shape, bool)
        truth[dy:dy + 128, dx:dx + 128] = veins
        assert (m & truth).sum() / (m | truth).sum() >= 0.85
        lab = ndi.maximum_filter(ndi.label(m, structure=np.ones((3, 3)))[0], size=3)
        whole = []
        for p, _, _ in lines:
            one = np.zeros(m.shape, np.uint8)
            cv2.polylines(one, [np.round(p + [dx, dy]).astype(np.int32)], False, 1, 1)
            on = (one > 0) & truth
            if on.sum() >= 5:
                ids = lab[on][lab[on] > 0]
                whole.append(len(ids) > 0 and np.bincount(ids).max() >= 0.9 * on.sum())
        assert np.mean(whole) >= 0.95, (i, np.mean(whole))


def _dark_pieces(rgb, blade, share):
    """``(contrast, pieces)``: median blade lightness minus the mean of its darkest ``share`` (the veins'
    share of the exemplars), and that darkest part's 8-connected pieces per 100 px of its skeleton."""
    from skimage.morphology import skeletonize

    lum = np.asarray(rgb, np.float32)[..., :3].mean(-1)
    inner = ndi.binary_erosion(blade, iterations=1)
    v = lum[inner]
    t = np.partition(v, int(share * len(v)))[int(share * len(v))]
    dark = inner & (lum <= t)
    pieces = 100.0 * ndi.label(dark, structure=np.ones((3, 3)))[1] / max(1, skeletonize(dark).sum())
    return float(np.median(v) - v[v <= t].mean()), pieces


def test_small_new_leaves_keep_their_hairline_veins_whole():
    """New 128-px elliptic leaves with 1-2 px dark veins: main's veins came out beaded (4.3 dark pieces per
    100 px of skeleton against the exemplars' 0.3, ``synthesis_layers._hairline``); now 0.5, contrast 0.99
    of the exemplars'."""
    from branchnb.leaves import analyze, generate

    fam = [_leaf("elliptic", 128, s) for s in range(3)]
    a = analyze([np.dstack([f[0], f[1].astype(np.float32)]) for f in fam], 0,
                _strokes(fam[0][3], fam[0][1], fam[0][2], 0))
    share = float(np.mean([f[2].sum() / f[1].sum() for f in fam]))
    ex = np.mean([_dark_pieces(f[0], f[1], share) for f in fam], 0)
    new = np.mean([_dark_pieces(x.on_white(), x.blade, share) for x in generate(a, 3, rng=0)], 0)
    assert new[0] >= 0.7 * ex[0], (new, ex)
    assert new[1] <= ex[1] + 1.0, (new, ex)
