"""Issue 23 (branching102): a marked sea's coast stays smooth in the domain, a sea piece no river reaches is
sea (not ground), an engraved map's hatched sea is found by its texture."""

import cv2
import numpy as np
from scipy import ndimage as ndi

from branchnb.branching import example_domain, extract_structure
from branchnb.branching.domains import _ground
from branchnb.branching.hatched_seas import hatched_background, without_hatched_sea
from branchnb.core.structure import Branch, Structure


def _island(H, rng):
    yy, xx = np.mgrid[0:H, 0:H] / H
    noise = cv2.GaussianBlur(rng.normal(0, 1, (H, H)).astype(np.float32), (0, 0), H / 12)
    land = (0.45 - np.hypot(xx - 0.5, yy - 0.5) + 0.12 * noise / noise.std()) > 0.08
    lab, n = ndi.label(land)
    land = lab == 1 + np.argmax(ndi.sum(land, lab, range(1, n + 1)))
    return ndi.binary_fill_holes(land)


def _rivers(land, n, rng):
    """n rivers from the coast inland (2 px), as a raster."""
    H = land.shape[0]
    dt = ndi.distance_transform_edt(land)
    gy, gx = np.gradient(dt)
    truth = np.zeros(land.shape, np.uint8)
    cnt = max(cv2.findContours(land.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)[0], key=len)[:, 0]
    for k in range(n):
        p = cnt[int(k * len(cnt) / n)].astype(float)
        pts = [p]
        for _ in range(H // 8):
            d = np.array([gx[int(p[1]), int(p[0])], gy[int(p[1]), int(p[0])]])
            d = d / (np.linalg.norm(d) + 1e-9) + rng.normal(0, 0.3, 2)
            p = p + 3 * d / np.linalg.norm(d)
            if not land[int(p[1]), int(p[0])] or dt[int(p[1]), int(p[0])] > H / 5:
                break
            pts.append(p)
        cv2.polylines(truth, [np.round(pts).astype(np.int32)], False, 1, 2)
    return truth > 0


def _marked_sea_map(H=240, seed=0):
    """A fantasy map: parchment land, teal sea with wave dashes, brown double coast, blue rivers."""
    rng = np.random.default_rng(seed)
    land = _island(H, rng)
    img = np.empty((H, H, 3), np.float32)
    img[:] = (0.93, 0.85, 0.66)
    img[~land] = (0.45, 0.66, 0.68)
    for _ in range(H * H // 900):
        x, y = int(rng.integers(0, H)), int(rng.integers(0, H))
        if not land[y, x]:
            cv2.ellipse(img, (x, y), (4, 2), 0, 180, 360, (0.35, 0.55, 0.58), 1, cv2.LINE_AA)
    cnts, _ = cv2.findContours(land.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    cv2.drawContours(img, cnts, -1, (0.30, 0.20, 0.10), 2, cv2.LINE_AA)
    d_out = ndi.distance_transform_edt(~land)
    img[(d_out > 5) & (d_out < 6.2)] = (0.30, 0.20, 0.10)
    rivers = _rivers(land, 4, rng)
    img[rivers] = (0.20, 0.38, 0.62)
    return img, land, rivers


def _engraved_map(H=256, seed=0):
    """An old-atlas map: paper, the sea as horizontal hatching, stippled land, black coast and rivers."""
    rng = np.random.default_rng(seed)
    land = _island(H, rng)
    d_out = ndi.distance_transform_edt(~land)
    yy = np.mgrid[0:H, 0:H][0]
    sp = max(4, H // 80)
    ink = np.where(~land & (d_out > 3), (np.abs(((yy + 0.5) % sp) - sp / 2) < 0.6), 0).astype(np.float32)
    n = int(land.sum() / 30)
    ys, xs = rng.integers(0, H, n), rng.integers(0, H, n)
    ok = land[ys, xs]
    ink[ys[ok], xs[ok]] = 0.7
    coast = np.zeros((H, H), np.uint8)
    cv2.drawContours(coast, cv2.findContours(land.astype(np.uint8), cv2.RETR_EXTERNAL,
                                             cv2.CHAIN_APPROX_NONE)[0], -1, 1, 2)
    rivers = _rivers(land, 4, rng)
    ink = np.maximum(np.maximum(ink, coast), rivers.astype(np.float32))
    paper, black = np.array([0.94, 0.91, 0.83], np.float32), np.array([0.12, 0.10, 0.09], np.float32)
    return (paper * (1 - ink[..., None]) + black * ink[..., None]).astype(np.float32), land


def _sign_changes_per_100px(mask):
    c = max(cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)[0],
            key=len)[:, 0].astype(float)
    H, W = mask.shape
    cs = ndi.gaussian_filter1d(c, 2.0, axis=0, mode="wrap")
    d1 = np.gradient(cs, axis=0)
    d2 = np.gradient(d1, axis=0)
    k = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    off = (c[:, 0] > 1) & (c[:, 0] < W - 2) & (c[:, 1] > 1) & (c[:, 1] < H - 2)
    s = np.sign(k[off & (np.abs(k) > 0.05)])
    length = np.linalg.norm(np.diff(cs[off], axis=0), axis=1).sum()
    return (np.diff(s) != 0).sum() / (length / 100.0)


def test_marked_sea_domain_has_no_dash_spurs():
    # before: every wave dash near the coast left a spur (a pocket of sea up to the flat test's radius):
    # 14-15 pieces of domain beyond the double coast's band and 4.5-4.9 curvature sign changes per 100 px
    # of coast against the island's 1.2-2.5 (after: 6-10 pieces, most of them sea corners at the frame
    # too narrow for the flat test; 3.1)
    for seed in (1, 2):
        img, land, _rivers_ = _marked_sea_map(240, seed)
        ex = extract_structure(img)
        dom = example_domain(img, ex)
        _lab, pieces = ndi.label(dom & (ndi.distance_transform_edt(~land) > 7.5))
        assert pieces <= 11, pieces
        assert _sign_changes_per_100px(dom) <= _sign_changes_per_100px(land) + 2.1
        assert (dom & land).sum() / (dom | land).sum() >= 0.8
        assert not hatched_background(img.mean(-1)).any()    # a flat sea is no hatching


def test_a_sea_piece_no_river_reaches_is_no_ground():
    dom = np.ones((200, 200), bool)
    dom[150:] = False                                    # the coast the rivers start at
    dom[:40, :40] = False                                # a bay cut off by land, far from every river
    ex = Structure([Branch(np.c_[np.full(30, 120.0), np.linspace(147, 60, 30)], 2.0),
                    Branch(np.c_[np.full(30, 170.0), np.linspace(147, 80, 30)], 2.0)], image_shape=(200, 200))
    assert _ground(ex, dom) is None
    # rooted far from every outside part (a line mask's empty ground): ground, as before
    ex2 = Structure([Branch(np.c_[np.full(30, 120.0), np.linspace(60, 120, 30)], 2.0)], image_shape=(200, 200))
    g = _ground(ex2, dom)
    assert g is not None and g[10, 10] and g[190, 100]


def test_engraved_map_sea_found_by_its_hatching():
    for H, seed in ((200, 0), (320, 1)):
        img, land = _engraved_map(H, seed)
        sea = hatched_background(img.mean(-1))
        iou = (sea & ~land).sum() / (sea | ~land).sum()
        assert iou >= 0.8, iou
        assert (sea & land).sum() <= 0.03 * land.sum()
        image, gray = without_hatched_sea(img, img.mean(-1))
        assert np.ptp(gray[sea]) < 0.05                   # the hatching is erased to the paper
        ex = extract_structure(img)
        # before: the hatching lines were traced as rivers (95 % of the branch length lay in the sea)
        pts = np.concatenate([b.points for b in ex.branches])
        xi, yi = np.clip(np.round(pts).astype(int), 0, H - 1).T
        in_sea = ~land[yi, xi] & (ndi.distance_transform_edt(~land)[yi, xi] > 4)
        assert in_sea.mean() <= 0.15, in_sea.mean()
        dom = example_domain(img, ex)
        assert (dom & land).sum() / (dom | land).sum() >= 0.8


def _engraved_river_map(H, seed, kind="wavy", tint=False):
    """An engraved map with known rivers: the sea hatched at a random angle and spacing (lines joined to the
    coast at 1000 px), the coast wavy or scalloped, the land stippled or tinted; ``(image, land, rivers)``."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:H, 0:H] / H
    noise = cv2.GaussianBlur(rng.normal(0, 1, (H, H)).astype(np.float32), (0, 0), H / 12)
    f = 0.45 - np.hypot(xx - 0.5, yy - 0.5) + 0.12 * noise / noise.std()
    if kind == "scalloped":
        f = f + 0.025 * np.abs(np.sin(9 * np.arctan2(yy - 0.5, xx - 0.5) + rng.uniform(0, 6)))
    elif kind == "wavy":
        n2 = cv2.GaussianBlur(rng.normal(0, 1, (H, H)).astype(np.float32), (0, 0), H / 40)
        f = f + 0.03 * n2 / n2.std()
    lab, n = ndi.label(f > 0.08)
    land = ndi.binary_fill_holes(lab == 1 + np.argmax(ndi.sum(f > 0.08, lab, range(1, n + 1))))
    d_out = ndi.distance_transform_edt(~land)
    dt = ndi.distance_transform_edt(land)
    gy, gx = np.gradient(ndi.gaussian_filter(dt, 2))
    # rivers from the coast inland, each with a tributary, until the land's crest
    rivers = np.zeros((H, H), np.uint8)
    width = 2 if H < 600 else 3
    cnt = max(cv2.findContours(land.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)[0], key=len)[:, 0]
    n_riv, off, step = int(rng.integers(3, 6)), rng.uniform(0, 1), max(3, H / 90)

    def walk(p, m, side):
        pts = [p]
        for _ in range(m):
            x, y = int(p[0]), int(p[1])
            d = np.array([gx[y, x], gy[y, x]])
            d = d / (np.linalg.norm(d) + 1e-9)
            d = d + side * 0.9 * np.array([-d[1], d[0]]) + rng.normal(0, 0.3 if side == 0 else 0.2, 2)
            p = p + step * d / np.linalg.norm(d)
            x, y = int(p[0]), int(p[1])
            if not (0 <= x < H and 0 <= y < H) or not land[y, x] or dt[y, x] > H / 5 or (side and dt[y, x] < 4):
                break
            if len(pts) > 6 and dt[y, x] < dt[int(pts[-6][1]), int(pts[-6][0])] - 1:
                break
            pts.append(p)
        return pts

    for k in range(n_riv):
        pts = walk(cnt[int(((k + off) / n_riv % 1) * len(cnt))].astype(float), H // 6, 0)
        if len(pts) > 3:
            cv2.polylines(rivers, [np.round(pts).astype(np.int32)], False, 1, width)
            if len(pts) > 10:
                t2 = walk(pts[len(pts) // 2], len(pts) // 2, rng.choice([-1, 1]))
                if len(t2) > 3:
                    cv2.polylines(rivers, [np.round(t2).astype(np.int32)], False, 1, max(1, width - 1))
    ang = np.radians(rng.uniform(0, 180))
    sp = max(4, H // int(rng.uniform(60, 90)))
    u = (-np.sin(ang) * xx + np.cos(ang) * yy) * H
    lw = 0.6 if H < 600 else 0.9
    ink = np.where(~land & (d_out > 3), np.clip(lw + 0.5 - np.abs(((u + 0.5) % sp) - sp / 2), 0, 1), 0)
    ink = ink.astype(np.float32)
    if not tint:
        n_dots = int(land.sum() / 30)
        ys, xs = rng.integers(0, H, n_dots), rng.integers(0, H, n_dots)
        ok = land[ys, xs]
        ink[ys[ok], xs[ok]] = 0.7
    # the coast line along the land's edge, none along the frame where the land runs off it
    dpad = ndi.distance_transform_edt(np.pad(land, 4, mode="edge"))[4:-4, 4:-4]
    cw = 2 if H < 600 else 3
    coast = (land & (dpad <= cw / 2 + 0.5)) | (~land & (d_out <= cw / 2 - 0.5))
    rv = (rivers > 0) & (land | coast)
    ink = np.maximum(np.maximum(ink, coast.astype(np.float32)), rv.astype(np.float32))
    paper, black = np.array([0.94, 0.91, 0.83], np.float32), np.array([0.12, 0.10, 0.09], np.float32)
    bg = np.broadcast_to(paper, (H, H, 3)).copy()
    if tint:
        bg[land] = (0.90, 0.86, 0.66)
    return (bg * (1 - ink[..., None]) + black * ink[..., None]).astype(np.float32), land, rv


def _river_scores(ex, rivers, tol):
    from skimage.morphology import skeletonize

    H, W = rivers.shape
    traced = np.zeros((H, W), np.uint8)
    for b in ex.branches:
        cv2.polylines(traced, [np.round(b.points).astype(np.int32)], False, 1, 1)
    traced = traced > 0
    precision = (ndi.distance_transform_edt(~rivers)[traced] <= tol).mean() if traced.any() else 0.0
    recall = (ndi.distance_transform_edt(~traced)[skeletonize(rivers)] <= tol).mean()
    return precision, recall, traced


def test_engraved_coast_is_no_river():
    # before: the coast along the hatched sea was traced as a river (precision 0.19-0.29; a sea corner cut
    # off at the frame was traced line by line, 256 px seed 1 gave no branch at all)
    for H, seed, kind, tint in ((256, 0, "wavy", False), (256, 1, "scalloped", True), (512, 4, "scalloped", False)):
        img, land, rivers = _engraved_river_map(H, seed, kind, tint)
        ex = extract_structure(img)
        tol = max(3.0, H / 100)
        precision, recall, traced = _river_scores(ex, rivers, tol)
        assert precision >= 0.9, (H, seed, precision)
        # (the rivers missed are 20-28 px stubs at 256 px, under half min_component_length: 0.76-0.87)
        assert recall >= 0.75, (H, seed, recall)
        # rivers that reach the coast keep their mouth: a traced line within 2 tol of every mouth
        sea_near = ndi.distance_transform_edt(land) <= 3
        mouths, n_m = ndi.label(rivers & sea_near)
        centres = np.array(ndi.center_of_mass(rivers, mouths, range(1, n_m + 1)))
        d_tr = ndi.distance_transform_edt(~traced)
        kept = [d_tr[int(round(y)), int(round(x))] <= 2 * tol for y, x in centres]
        assert np.mean(kept) >= 0.75, (H, seed, kept)
        dom = example_domain(img, ex)
        assert (dom & land).sum() / (dom | land).sum() >= 0.95


def test_hatched_sea_corners_and_hatching_joined_to_the_coast():
    # before: a corner of the sea cut off by land at the frame was no sea (its eroded core under half of it:
    # sea IoU 0.62 at 512 px), nor the hatching lines joined to the coast line at 1000 px (0.41 of the
    # sea left as lines, traced as rivers)
    for H, seed, kind, tint in ((512, 4, "scalloped", False), (1000, 5, "wavy", False)):
        img, land, _rivers = _engraved_river_map(H, seed, kind, tint)
        sea = hatched_background(img.mean(-1))
        assert (sea & ~land).sum() / (sea | ~land).sum() >= 0.95
        assert (sea & land).sum() <= 0.01 * land.sum()


def test_a_river_cut_at_the_shore_is_kept_from_half_length():
    from branchnb.branching.skeleton_tree import skeleton_to_structure

    sk = np.zeros((120, 120), bool)
    sk[30:70, 60] = True                        # a 40 px river: under min_component_length 60
    shore = np.zeros((120, 120), bool)
    shore[72:, :] = True                        # the coast's removed line just below its mouth
    assert len(skeleton_to_structure(sk, np.full(sk.shape, 1.5)).branches) == 0
    s = skeleton_to_structure(sk, np.full(sk.shape, 1.5), shore=shore)
    assert len(s.branches) == 1 and s.branches[0].length > 35
    far = np.zeros_like(shore)
    far[110:, :] = True                         # a shore 40 px off the piece keeps nothing
    assert len(skeleton_to_structure(sk, np.full(sk.shape, 1.5), shore=far).branches) == 0
    import pytest

    with pytest.raises(ValueError, match="shore"):
        skeleton_to_structure(sk, np.full(sk.shape, 1.5), shore=np.zeros((10, 10), bool))


def _streaks(H, seed):
    """Wood-like streaks: noise stretched along one direction, parallel but at no regular spacing."""
    t = ndi.gaussian_filter(np.random.default_rng(seed).normal(0, 1, (H, H)), (0.8, 12))
    return np.clip(0.6 + 0.15 * (t - t.mean()) / t.std(), 0, 1).astype(np.float32)


def _grained_soil_roots(H, seed):
    """Pale roots on a grained dark soil: the soil's texture reads as parallel along the roots."""
    rng = np.random.default_rng(seed)
    n = rng.normal(0, 1, (H, H))
    tex = ndi.gaussian_filter(n, 1.0) * 0.5 + ndi.gaussian_filter(n, 2.0) * 2.0
    g = 0.26 + 0.03 * (tex - tex.mean()) / tex.std()
    yy = np.arange(H, dtype=float)
    for k, x0 in enumerate((0.25, 0.5, 0.75)):
        x = H * x0 + 0.06 * H * np.sin(yy / H * 5 + k)
        d = np.abs(np.arange(H)[None, :] - x[:, None])
        g = np.where(d <= np.linspace(3.5, 1.5, H)[:, None], 0.78, g)
    return g.astype(np.float32)


def _jittered_hatching(H, jitter, seed):
    """Hatching whose line spacing is jittered (std ``jitter`` of it) round a plain island with a coast line."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:H, 0:H].astype(float)
    a = np.radians(33 + 40 * seed)
    sp = max(4, H // 70)
    u = -np.sin(a) * xx + np.cos(a) * yy
    k = np.floor(u / sp)
    offs = rng.normal(0, jitter * sp, int(k.max() - k.min()) + 3)
    ink = np.clip(1.1 - np.abs(u - k * sp - offs[(k - k.min()).astype(int)] - sp / 2), 0, 1)
    d = np.hypot(xx - H / 2, yy - H / 2)
    ink[d < 0.3 * H + 3] = 0
    ink[np.abs(d - 0.3 * H) < 1.2] = 1
    return (0.92 - 0.82 * ink).astype(np.float32), d < 0.3 * H


def test_parallel_texture_at_no_regular_spacing_is_no_hatched_sea():
    # before (branching108, reverted): the grained soil along pale roots was 11-21 % hatched sea, whose outline
    # step then broke tests/test_branching_flat_lines.py; wood streaks 94-96 %. Hatching is lines at a
    # regular spacing: the pieces' periodic share 0.0-0.27 here, 0.99-1.0 on the engraved maps
    for H, seed in ((128, 4), (240, 3)):
        assert not hatched_background(_grained_soil_roots(H, seed)).any(), (H, seed)
    for H, seed in ((128, 0), (300, 1)):
        assert not hatched_background(_streaks(H, seed)).any(), (H, seed)
    # hatching drawn by hand, its spacing jittered by a fifth, still is a sea (periodic share 0.59-0.92)
    for H, seed in ((200, 1), (400, 3)):
        g, land = _jittered_hatching(H, 0.2, seed)
        sea = hatched_background(g)
        assert (sea & ~land).sum() / (sea | ~land).sum() >= 0.95, (H, seed)
