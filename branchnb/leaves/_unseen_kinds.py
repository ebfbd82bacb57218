"""Four leaf kinds the package's procedural families do not have, with their true veins (issue 22).

For measuring the whole workflow on leaves nobody tuned for
(:mod:`branchnb.leaves._measure_unseen`): ``willow`` (narrow lanceolate,
curved midrib, many parallel pinnate secondaries curving to the tip),
``cordate`` (heart-shaped, five basal veins from the sinus, a few
secondaries), ``oak`` (deeply lobed with a wavy margin, one vein per lobe,
rust spots), all photo-like (blade texture, side lighting, grain, a soft
shadow on grey paper); and ``clipart`` (an ovate serrate leaf in flat
colours: ink outline, pale vein lines, a grey drop shadow).

Each leaf is built in a unit frame (base at the origin, tip at ``(0, -1)``),
varied per seed, turned by up to 12 degrees and drawn with
:func:`branchnb.core.render.coverage_polylines`; the vein mask is the
drawn veins' coverage >= 0.5 inside the blade.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.render import coverage_polylines

KINDS44 = ("willow", "cordate", "oak", "clipart")


@dataclass
class UnseenLeaf:
    """One leaf: the RGB picture on paper, its true blade (with petiole), veins and spots, and the plain rendering."""

    image: np.ndarray
    blade: np.ndarray
    veins: np.ndarray
    spots: np.ndarray
    plain: np.ndarray
    kind: str
    seed: int
    #: main vein polylines (pixels): midrib first; for scribbling
    main: list


def _curve(p0, p1, bend, n=24):
    """A quadratic curve from p0 to p1 bowed by ``bend`` (share of its length) to its left."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    d = p1 - p0
    c = (p0 + p1) / 2 + bend * np.array([-d[1], d[0]])
    t = np.linspace(0, 1, n)[:, None]
    return (1 - t) ** 2 * p0 + 2 * t * (1 - t) * c + t ** 2 * p1


def _profile_outline(wl, wr, bend, n=200):
    """Outline from half-widths along a midrib x = bend * t^2 (t in [0, 1], y = -t)."""
    t = np.linspace(0, 1, n)
    x0 = bend * t ** 2
    left = np.stack([x0 - wl(t), -t], 1)
    right = np.stack([x0 + wr(t), -t], 1)
    return np.concatenate([right, left[::-1]])


def _willow(r):
    bend = r.uniform(-0.08, 0.08)
    hw = 0.085 * r.uniform(0.85, 1.15)
    peak = r.uniform(0.3, 0.42)

    def w(t):
        t = np.clip(t, 0, 1)
        s = np.where(t < peak, np.clip(np.sin(0.5 * np.pi * t / peak), 0, 1) ** 0.7,
                     np.clip(np.cos(0.5 * np.pi * (t - peak) / (1 - peak)), 0, 1) ** 0.9)
        return hw * s
    outline = _profile_outline(w, w, bend)
    t = np.linspace(0, 1, 60)
    mid = np.stack([bend * t ** 2, -t], 1)
    veins, widths = [mid], [np.linspace(0.011, 0.003, 60)]
    pairs = int(r.integers(11, 16))
    for tb in np.linspace(0.07, 0.86, pairs):
        for side in (-1, 1):
            tb2 = float(np.clip(tb + (0.02 if side > 0 else 0.0) + r.normal(0, 0.008), 0.03, 0.9))
            x0 = bend * tb2 ** 2
            reach = 0.85 * w(tb2 + 0.06)
            te = tb2 + reach / np.tan(np.radians(r.uniform(50, 58)))
            p = _curve((x0, -tb2), (bend * te ** 2 + side * reach, -te), -side * 0.18, 14)
            veins.append(p)
            widths.append(np.linspace(0.0045, 0.0025, len(p)))
    return outline, veins, widths, 0.10, []


def _heart_outline(r, n=240):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    x = 16 * np.sin(t) ** 3
    y = 13 * np.cos(t) - 5 * np.cos(2 * t) - 2 * np.cos(3 * t) - np.cos(4 * t)
    # the classic heart has its point down and its sinus up at (0, 5): turn it so the point is the tip
    x, y = x / 32.0, (y - 5.0) / 22.0             # sinus at the origin, point at y = -1
    y = np.where(y <= 0, -np.abs(y) ** r.uniform(0.9, 1.1), y)
    return np.stack([x * r.uniform(0.9, 1.1), y], 1)


def _cordate(r):
    outline = _heart_outline(r)
    ang = np.arctan2(outline[:, 0], -outline[:, 1])
    rad = np.hypot(outline[:, 0], outline[:, 1])

    def reach(a):
        # distance to the margin in direction a (angle from the tip direction)
        k = np.argmin(np.abs(np.angle(np.exp(1j * (ang - a)))) + 10.0 * (rad < 0.1))
        return rad[k]
    veins, widths = [], []
    t = np.linspace(0, 1, 50)
    mid = np.stack([0.02 * r.normal() * t, -t * reach(0.0) * 0.96], 1)
    veins.append(mid)
    widths.append(np.linspace(0.012, 0.003, 50))
    for side in (-1, 1):
        for a, wv in ((r.uniform(38, 48), 0.008), (r.uniform(80, 95), 0.006)):
            a = np.radians(a) * side
            d = 0.82 * reach(a)
            end = (d * np.sin(a), -d * np.cos(a))
            p = _curve((0.0, 0.0), end, -side * 0.12, 30)
            veins.append(p)
            widths.append(np.linspace(wv, 0.0025, len(p)))
            # two outward branches of each basal vein
            for f in (0.4, 0.65):
                q = p[int(f * (len(p) - 1))]
                b = a + side * np.radians(40)
                dd = 0.35 * reach(b) * (1 - f * 0.5)
                br = _curve(q, (q[0] + dd * np.sin(b), q[1] - dd * np.cos(b)), -side * 0.1, 10)
                veins.append(br)
                widths.append(np.linspace(0.0035, 0.002, len(br)))
        for f in (0.45, 0.62, 0.78):
            q = mid[int(f * 49)]
            b = side * np.radians(r.uniform(45, 55))
            dd = 0.6 * reach(b) * (1 - f) + 0.05
            br = _curve(q, (q[0] + dd * np.sin(b), q[1] - dd * np.cos(b)), -side * 0.12, 12)
            veins.append(br)
            widths.append(np.linspace(0.0045, 0.0022, len(br)))
    return outline, veins, widths, 0.16, []


def _oak(r):
    n_lobes = int(r.integers(4, 6))
    depth = r.uniform(0.6, 0.72)
    hw = 0.27 * r.uniform(0.9, 1.1)
    phase = r.uniform(0.15, 0.3)

    def env(t):
        t = np.clip(t, 0, 1)
        return hw * np.clip(np.sin(np.pi * t ** 0.85), 0, 1) ** 0.6 + 0.02 * (t < 0.98)

    def lobe(t, shift):
        u = (t * n_lobes + shift) % 1.0
        return (1 - depth) + depth * np.sin(np.pi * u) ** 0.45

    def wave(t, s):
        return 1 + 0.035 * np.sin(2 * np.pi * (t * 3 * n_lobes + s))
    wl = lambda t: env(t) * lobe(t, 0.0) * wave(t, 0.3)  # noqa: E731
    wr = lambda t: env(t) * lobe(t, phase) * wave(t, 0.8)  # noqa: E731
    bend = r.uniform(-0.05, 0.05)
    outline = _profile_outline(wl, wr, bend, 400)
    t = np.linspace(0, 1, 60)
    veins, widths = [np.stack([bend * t ** 2, -t], 1)], [np.linspace(0.012, 0.003, 60)]
    for side, shift, wf in ((-1, 0.0, wl), (1, phase, wr)):
        for k in range(n_lobes):
            tp = (k + 0.5 - shift) / n_lobes
            if not 0.06 < tp < 0.9:
                continue
            tb = max(tp - 0.07, 0.02)
            end = (bend * tp ** 2 + side * 0.85 * wf(tp), -tp)
            p = _curve((bend * tb ** 2, -tb), end, -side * 0.08, 16)
            veins.append(p)
            widths.append(np.linspace(0.006, 0.0025, len(p)))
    spots = []
    for _ in range(int(r.integers(4, 9))):
        tt = r.uniform(0.15, 0.85)
        spots.append((bend * tt ** 2 + r.uniform(-0.6, 0.6) * env(tt) * (1 - depth), -tt, r.uniform(0.012, 0.03)))
    return outline, veins, widths, 0.14, spots


def _clipart(r):
    hw = 0.3 * r.uniform(0.88, 1.12)
    n_teeth = int(r.integers(18, 26))

    def w(t):
        t = np.clip(t, 0, 1)
        base = hw * np.clip(np.sin(np.pi * t ** 0.75), 0, 1) ** 0.8
        return base * (1 + 0.05 * (np.abs(np.sin(np.pi * n_teeth * t)) - 0.5))
    outline = _profile_outline(w, w, 0.0, 300)
    t = np.linspace(0, 1, 40)
    veins, widths = [np.stack([0 * t, -t], 1)], [np.full(40, 0.008)]
    for tb in np.linspace(0.1, 0.78, int(r.integers(6, 9))):
        for side in (-1, 1):
            te = tb + 0.14
            p = np.array([[0.0, -tb], [side * 0.8 * w(te), -te]])
            veins.append(p)
            widths.append(np.full(2, 0.006))
    return outline, veins, widths, 0.12, []


_BUILD = {"willow": _willow, "cordate": _cordate, "oak": _oak, "clipart": _clipart}
_COLOURS = {  # blade, vein, spot
    "willow": ((0.36, 0.52, 0.22), (0.68, 0.76, 0.42), None),
    "cordate": ((0.22, 0.42, 0.14), (0.52, 0.66, 0.30), None),
    "oak": ((0.66, 0.46, 0.14), (0.86, 0.74, 0.40), (0.36, 0.20, 0.08)),
    "clipart": ((0.42, 0.70, 0.28), (0.78, 0.90, 0.58), None),
}


def _noise(shape, cell, r):
    h, w = shape
    g = r.normal(size=(h // cell + 3, w // cell + 3)).astype(np.float32)
    big = cv2.resize(g, ((w // cell + 3) * cell, (h // cell + 3) * cell), interpolation=cv2.INTER_CUBIC)
    return big[:h, :w]


def unseen_leaf(kind: str, size: int = 400, seed: int = 0) -> UnseenLeaf:
    """One leaf of ``kind`` (:data:`KINDS44`) on a ``size`` x ``size`` canvas; reproducible from ``seed``."""
    r = np.random.default_rng([KINDS44.index(kind), int(seed)])
    outline, veins, widths, pet_len, spots = _BUILD[kind](r)
    length = {"willow": 0.8, "cordate": 0.62, "oak": 0.72, "clipart": 0.72}[kind] * size
    rot = np.radians(r.uniform(-12, 12))
    c, s = np.cos(rot), np.sin(rot)
    R = np.array([[c, -s], [s, c]])
    lo, hi = outline.min(0), outline.max(0)
    centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + max(hi[1], pet_len)) / 2])

    def px(p):
        return (np.asarray(p, float) - centre) @ R.T * length + size / 2
    shape = (size, size)
    blade_cov = np.zeros(shape, np.float32)
    cv2.fillPoly(blade_cov, [np.round(px(outline) * 16).astype(np.int32)], 1.0, cv2.LINE_AA, shift=4)
    blade_cov = np.clip(blade_cov, 0, 1)
    pet = np.array([[0.0, -0.03], [0.01 * r.normal(), pet_len]])
    pet_cov, _ = coverage_polylines(shape, [px(pet)], [max(0.012 * length, 2.0)])
    lam = blade_cov > 0.5
    vlines = [px(v) for v in veins]
    vw = [np.maximum(np.asarray(wv) * length, 1.0) for wv in widths]
    vcov, _ = coverage_polylines(shape, vlines, vw)
    inner = ndi.binary_erosion(lam, iterations=2)
    vcov = vcov * inner
    spot_mask = np.zeros(shape, np.float32)
    for sx, sy, sr in spots:
        q = px([[sx, sy]])[0]
        ax = max(sr * length, 2.0)
        cv2.ellipse(spot_mask, (int(q[0]), int(q[1])), (int(ax), int(ax * r.uniform(0.6, 1.0))),
                    float(r.uniform(0, 180)), 0, 360, 1.0, -1, cv2.LINE_AA)
    spot_mask = np.clip(spot_mask, 0, 1) * inner
    alpha = np.maximum(blade_cov, pet_cov)
    blade_col, vein_col, spot_col = (np.array(x, np.float32) if x is not None else None for x in _COLOURS[kind])
    yy, xx = np.mgrid[:size, :size].astype(np.float32) / size
    if kind == "clipart":
        paper = np.ones(shape + (3,), np.float32)
        off = int(round(0.025 * size))
        sh = np.roll(alpha, (off, off), (0, 1))
        sh = cv2.GaussianBlur(sh, (0, 0), 0.6)
        paper = paper * (1 - 0.35 * sh[..., None])
        leaf = np.broadcast_to(blade_col, shape + (3,)).copy()
        ink = np.array((0.10, 0.22, 0.08), np.float32)
        rim = lam & ~ndi.binary_erosion(lam, iterations=2)
        plain = leaf.copy()
        plain[rim] = ink
        leaf = leaf * (1 - vcov[..., None]) + vein_col * vcov[..., None]
        leaf[rim] = ink
    else:
        paper = (0.90 + 0.04 * (xx - 0.5) + 0.01 * _noise(shape, 8, r))[..., None] * np.array((1.0, 0.99, 0.96))
        sh = cv2.GaussianBlur(np.roll(alpha, (int(0.02 * size), int(0.015 * size)), (0, 1)), (0, 0), 0.012 * size)
        paper = paper * (1 - 0.3 * sh[..., None])
        tex = 1 + 0.07 * _noise(shape, max(size // 20, 3), r) + 0.04 * _noise(shape, max(size // 80, 2), r)
        light = 0.85 + 0.3 * (1 - (xx * np.cos(rot + 0.6) + yy * np.sin(rot + 0.6)))
        plain = blade_col * (tex * light)[..., None]
        if spot_col is not None:
            sc = spot_col * (1 + 0.1 * _noise(shape, 3, r))[..., None]
            plain = plain * (1 - spot_mask[..., None]) + sc * spot_mask[..., None]
        vc = vein_col * light[..., None]
        leaf = plain * (1 - vcov[..., None]) + vc * vcov[..., None]
        grain = 0.012 * r.normal(size=shape + (3,)).astype(np.float32)
        leaf, plain = leaf + grain, plain + grain
    a3 = alpha[..., None]
    img = np.clip(paper * (1 - a3) + leaf * a3, 0, 1).astype(np.float32)
    img_plain = np.clip(paper * (1 - a3) + plain * a3, 0, 1).astype(np.float32)
    return UnseenLeaf(img, alpha > 0.5, vcov >= 0.5, spot_mask >= 0.5, img_plain, kind, int(seed),
                      [vlines[0]] + vlines[1:])
