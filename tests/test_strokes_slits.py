"""Background enclosed by the object after adding a part (issue 25): no slit left closed off.

A tine added beside its neighbour on a small outlined antler: their rims touch
farther out and close the slit between them into a pocket of background whose
anti-aliased rim still reaches the background around the object.
"""
import cv2
import numpy as np
from scipy import ndimage as ndi

from branchnb.strokes import edit_structure
from branchnb.strokes.outline import fill_pinholes

BROWN = np.array([0.55, 0.36, 0.2])
INK = np.array([0.16, 0.1, 0.06])


def _curve(p0, p1, p2, n=40):
    t = np.linspace(0, 1, n)[:, None]
    return (1 - t) ** 2 * p0 + 2 * (1 - t) * t * p1 + t ** 2 * p2


def _tube(mask, pts, w0, w1):
    for j in range(len(pts) - 1):
        w = w0 + (w1 - w0) * j / (len(pts) - 1)
        cv2.line(mask, tuple(np.int32(np.rint(pts[j]))), tuple(np.int32(np.rint(pts[j + 1]))), 1,
                 max(1, int(round(w))))
    return mask


def _antler_add(n, seed):
    """Outlined antler (beam, 3 tines); targets: the same plus a copy of tine 0 just above it.
    Returns image, sources, targets, the ideal mask."""
    rng = np.random.default_rng(seed)
    k = n / 500
    beam = _curve(np.array([250, 470]) * k, np.array([150 + 20 * rng.normal(), 300]) * k, np.array([260, 60]) * k)
    fr = np.array([0.3, 0.55, 0.8]) + rng.uniform(-0.03, 0.03, 3)
    last = len(beam) - 1

    def tine_at(f, side, length):
        i = int(f * last)
        p = beam[i]
        tang = beam[min(i + 1, last)] - beam[max(i - 1, 0)]
        tang /= np.linalg.norm(tang)
        d = 0.85 * np.array([-tang[1], tang[0]]) * side + 0.5 * tang
        return _curve(p, p + d * length * k * 0.6, p + (d + 0.4 * tang) * length * k)

    tines = [tine_at(f, sd, rng.uniform(90, 115)) for f, sd in zip(fr, (1, -1, 1))]
    bw, tw = (34 * k, 16 * k), (20 * k, 6 * k)
    mask = _tube(np.zeros((n, n), np.uint8), beam, *bw)
    for t in tines:
        _tube(mask, t, *tw)
    m = mask > 0
    dist = cv2.distanceTransform(mask, cv2.DIST_L2, 3)
    rgb = BROWN * np.clip(0.85 + dist[..., None] / (30 * k), 0.85, 1.05)
    ow = max(1, int(round(2.5 * k)))
    rgb[m & ~(cv2.erode(mask, np.ones((3, 3), np.uint8), iterations=ow) > 0)] = INK
    img = np.zeros((n, n, 4), np.float32)
    img[..., :3] = np.clip(rgb, 0, 1) * m[..., None]
    img[..., 3] = np.maximum(cv2.GaussianBlur(m.astype(np.float32), (0, 0), 0.6), 0.5 * m)
    new = tine_at(fr[0] + 0.1, 1, 80)
    ideal = _tube(mask.copy(), new, *tw) > 0
    return img, [beam, *tines, tines[0].copy()], [beam.copy(), *[t.copy() for t in tines], new], ideal


def _holes(alpha):
    """Areas of the background pieces (alpha <= 0.5) enclosed by the object."""
    lab, n = ndi.label(alpha <= 0.5)
    border = set(np.unique(np.r_[lab[0], lab[-1], lab[:, 0], lab[:, -1]]).tolist())
    sizes = np.bincount(lab.ravel())
    return [int(sizes[i]) for i in range(1, n + 1) if i not in border]


def test_added_tine_encloses_no_background():
    for n, seed in ((150, 0), (150, 1), (200, 1)):
        img, src, tgt, ideal = _antler_add(n, seed)
        res = edit_structure(img, src, tgt)
        assert max(_holes(res.layer[..., 3]), default=0) <= 3, (n, seed, _holes(res.layer[..., 3]))
        # the new tine is there (most of its ideal pixels covered), not merged away
        new_only = ideal & ~(img[..., 3] > 0.5)
        assert (res.layer[..., 3] > 0.5)[new_only].mean() > 0.8


def _slit_layer():
    """An outlined square with a 2 px slit lined with ink closed off by a half-opaque bridge."""
    lay = np.zeros((40, 40, 4), np.float32)
    lay[5:35, 5:35] = (0.1, 0.05, 0.02, 1.0)
    lay[6:34, 6:34, :3] = (0.6, 0.4, 0.25)
    lay[5:29, 18:22, :3] = (0.1, 0.05, 0.02)
    lay[12:28, 19:21, 3] = 0.0          # the slit
    lay[5:12, 19:21, 3] = 0.7           # touching rims: above 0.5, below 0.98
    return lay


def test_fill_pinholes_closes_slit_but_not_wide_pocket_or_source_slit():
    lay = _slit_layer()
    out = fill_pinholes(lay, 1.0, slits=True)
    assert out[12:28, 19:21, 3].min() == 1.0
    # a pocket 8 px wide (a bent finger's loop) stays open
    wide = lay.copy()
    wide[12:28, 16:24, 3] = 0.0
    assert fill_pinholes(wide, 1.0, slits=True)[20, 20, 3] == 0.0
    # without slits the slit stays open; a slit lined with flesh (no outline) too
    assert fill_pinholes(lay, 1.0)[20, 20, 3] == 0.0
    plain = lay.copy()
    plain[..., :3] = (0.5, 0.3, 0.2)
    assert fill_pinholes(plain, 1.0, slits=True)[20, 20, 3] == 0.0
    # a slit the source has itself stays open
    assert fill_pinholes(lay, 1.0, slits=True, source_alpha=lay[..., 3].copy())[20, 20, 3] == 0.0


def test_fill_pinholes_closes_a_tear_lined_with_deep_flesh():
    """A flesh-lined crack (no ink) is a tear where its lining came from deep inside the
    source (a white tick in a palm under a bent finger), the gap between two parts where it
    came from their rims (an object with no outline: the slit keeps them apart)."""
    lay = np.zeros((40, 40, 4), np.float32)
    lay[5:35, 5:35] = (0.6, 0.4, 0.25, 1.0)
    lay[20:22, 10:28, 3] = 0.0          # the tick
    lay[20:22, 5:10, 3] = 0.7           # reaching the outside at the alpha 0.98 level only
    deep = np.full((40, 40), 9.0, np.float32)
    rim = np.full((40, 40), 1.0, np.float32)
    assert fill_pinholes(lay, 1.0, slits=True, depth=deep)[20:22, 10:28, 3].min() == 1.0
    assert fill_pinholes(lay, 1.0, slits=True, depth=rim)[21, 20, 3] == 0.0


def _heavy_slit_layer(ow, gap):
    """A square with an ``ow`` px ink outline split by a slit ``gap`` px wide lined with ``ow`` px of
    ink on each side, closed off at the top by half-opaque touching rims."""
    lay = np.zeros((48, 48, 4), np.float32)
    lay[4:44, 4:44] = (*INK, 1.0)
    lay[4 + ow:44 - ow, 4 + ow:44 - ow, :3] = BROWN
    c0 = 24 - gap // 2
    lay[4:20, c0 - ow:c0 + gap + ow, :3] = INK
    lay[4 + ow:20, c0:c0 + gap, 3] = 0.0
    lay[4:4 + ow, c0:c0 + gap, 3] = 0.7
    return lay, (slice(4 + ow, 20), slice(c0, c0 + gap))


def test_slit_lined_with_a_heavy_outline_is_filled_with_flesh():
    """A heavy outline's ink lining is a line of its own: the slit between two linings takes the
    flesh (not a band of ink three outline widths wide), all but its mouth; a slit lined with a
    1 px outline still takes the ink (one line keeping the parts apart)."""
    for ow, gap in ((2, 2), (3, 2), (3, 3)):
        lay, (rs, cs) = _heavy_slit_layer(ow, gap)
        out = fill_pinholes(lay, 1.0, slits=True)
        assert out[rs, cs, 3].min() == 1.0
        inner = out[rs.start + ow:rs.stop, cs, :3].reshape(-1, 3)
        d_fill = np.abs(inner - BROWN).max(axis=1)
        d_ink = np.abs(inner - INK).max(axis=1)
        assert (d_fill < d_ink).mean() >= 0.95, (ow, gap, (d_fill < d_ink).mean())
    lay, (rs, cs) = _heavy_slit_layer(1, 2)
    out = fill_pinholes(lay, 1.0, slits=True)
    thin = out[rs, cs, :3].reshape(-1, 3)
    assert (np.abs(thin - INK).max(axis=1) < np.abs(thin - BROWN).max(axis=1)).mean() >= 0.8
