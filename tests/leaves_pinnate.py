"""Procedural pinnate leaves with known veins, for measuring vein induction (issue 22, leaves62).

A blade with a midrib and ``n_lat`` laterals; within a family the laterals'
junctions along the midrib and their angles differ from leaf to leaf (and
the blade's width, tilt and bend), so a registered template lands beside
each leaf's own veins unless induction finds them.
"""

from __future__ import annotations

import cv2
import numpy as np


def pinnate_leaf(size: int, base_pos, base_ang, rng):
    """``(rgba, blade, veins)`` of one leaf on a ``size`` square canvas (veins lighter than the blade)."""
    rng = np.random.default_rng(rng)
    s = int(size)
    length = 0.78 * s * rng.uniform(0.92, 1.0)
    w = rng.uniform(0.26, 0.34)
    tilt = np.radians(rng.uniform(-8, 8))
    bend = rng.uniform(-0.06, 0.06)
    cx, cy = s / 2 + rng.uniform(-0.03, 0.03) * s, s * 0.9

    def to_img(u, v):  # u across, v along the leaf (0 base, 1 tip)
        u = u + bend * 4 * v * (1 - v)
        x, y = u * length, -v * length
        c, si = np.cos(tilt), np.sin(tilt)
        return np.stack([cx + c * x - si * y, cy + si * x + c * y], -1)

    def half(v):
        return w * np.sqrt(np.clip(v * (1 - v), 0, None)) * 2 * (1.0 - 0.25 * v)

    vs = np.linspace(0, 1, 400)
    poly = np.concatenate([to_img(half(vs), vs), to_img(-half(vs), vs)[::-1]])
    blade = np.zeros((s, s), np.uint8)
    cv2.fillPoly(blade, [np.round(poly * 16).astype(np.int32)], 1, lineType=cv2.LINE_AA, shift=4)
    blade = blade.astype(bool)
    wid = max(1.5, s / 110.0)
    veins = np.zeros((s, s), np.uint8)

    def draw(line, t):
        cv2.polylines(veins, [np.round(line * 16).astype(np.int32)], False, 1,
                      thickness=max(1, int(round(t))), lineType=cv2.LINE_8, shift=4)

    draw(to_img(np.zeros(50), np.linspace(0.0, 0.97, 50)), wid)
    n_lat = len(base_pos)
    pos = np.asarray(base_pos) + rng.normal(0, 0.04, n_lat)
    ang = np.asarray(base_ang) + rng.normal(0, 8, n_lat)
    for k in range(n_lat):
        side = 1 if k % 2 == 0 else -1
        v0 = float(np.clip(pos[k], 0.08, 0.85))
        a = np.radians(ang[k])
        t = np.linspace(0, 1, 40)
        r = 0.95 * t
        vv = np.minimum(v0 + r * np.cos(a) * 0.81 * half(v0) / max(np.sin(a), 0.3) + 0.04 * t * t, 0.99)
        uu = side * r * half(np.clip(vv, 0.01, 0.99))
        draw(to_img(uu, vv), 0.75 * wid)
    veins = veins.astype(bool) & blade
    base = np.array([0.25, 0.48, 0.14]) * rng.uniform(0.9, 1.1)
    tex = cv2.GaussianBlur(rng.standard_normal((s, s)).astype(np.float32), (0, 0), 2.0) * 0.04
    img = np.zeros((s, s, 4), np.float32)
    img[..., :3] = base + tex[..., None] + 0.01 * rng.standard_normal((s, s, 3))
    vm = cv2.GaussianBlur(veins.astype(np.float32), (0, 0), 0.6)
    img[..., :3] += vm[..., None] * (np.array([0.55, 0.72, 0.35]) - base)
    img[..., 3] = blade
    img = np.clip(img, 0, 1).astype(np.float32)
    img[~blade, :3] = 0
    return img, blade, veins


def pinnate_family(size: int, n_lat: int, seed: int, n: int = 4):
    """``n`` leaves of one family: ``n_lat`` laterals whose junctions and angles vary per leaf."""
    rng = np.random.default_rng(seed)
    base_pos = np.sort(rng.uniform(0.12, 0.75, n_lat))
    base_ang = rng.uniform(35, 60, n_lat)
    return [pinnate_leaf(size, base_pos, base_ang, seed * 100 + i) for i in range(n)]


def induced_vein_ious(size: int, n_lat: int, seed: int, n: int = 4):
    """Vein IoU of every other leaf's induced layer (defaults, TPS-RPM), leaf 0's true veins the user's."""
    from branchnb.core.metrics import iou
    from branchnb.leaves import analyze
    from branchnb.leaves.analysis import normalise_exemplars

    fam = pinnate_family(size, n_lat, seed, n)
    ims = [f[0] for f in fam]
    _, blades, offs = normalise_exemplars(ims)
    a = analyze(ims, 0, {"veins": fam[0][2]})
    out = []
    for e in range(1, n):
        g = np.zeros(blades[0].shape, bool)
        v, (dx, dy) = fam[e][2], offs[e]
        g[dy:dy + v.shape[0], dx:dx + v.shape[1]] = v
        if a.mirrored[e]:  # the analysis turned this exemplar over: its layers are in the turned frame
            g = g[:, ::-1]
        out.append(iou(a.layer("veins").masks[e], g))
    return out
