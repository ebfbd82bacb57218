"""Issue-23 figures on lines wider than the ridge filter's scales (branching81).

``python -m branchnb.branching._wide_line_check [SEEDS] [PNG_DIR]`` paints procedural trees
(:func:`wide_line_tree`: a trunk entering from the top edge whose widest part is 8-30 px, children
about half as wide, grandchildren 1.5-4 px; anti-aliased, over a flat, noisy or textured ground,
dark-on-light and light-on-dark, 256-1024 px; the centre lines and widths are known), runs
``extract_structure`` with the defaults and prints per case ``cov`` the share of the visible true
centre-line length within ``max(3, 0.3 width)`` px of the extracted structure (a line's stretch
under a wider line drawn before it is not visible), ``rootd`` the distance (px) from the trunk's
entry at the frame to the nearest extracted root, ``rad`` the median extracted over true radius
along the trunk's upper half, ``nb`` / ``roots`` branches and pieces, ``t`` seconds.
"""
# ruff: noqa: E501
from __future__ import annotations

import sys
import time

import cv2
import numpy as np
from scipy import ndimage as ndi

#: colours (line, ground) per kind
KINDS = {
    "roots": ((0.24, 0.15, 0.09), (0.55, 0.42, 0.30)),      # dark brown roots on soil
    "river": ((0.70, 0.76, 0.82), (0.20, 0.26, 0.16)),      # a light river on dark land
    "vessel": ((0.45, 0.08, 0.05), (0.85, 0.45, 0.25)),     # dark red vessels on orange
    "darkgrey": ((0.15, 0.15, 0.15), (0.80, 0.80, 0.78)),
}
#: (kind, size, widest width, ground)
CASES = (
    ("roots", 256, 8, "noisy"), ("river", 256, 14, "flat"), ("vessel", 256, 14, "textured"),
    ("roots", 320, 8, "textured"), ("darkgrey", 384, 14, "noisy"),
    ("roots", 512, 14, "textured"), ("river", 512, 20, "noisy"), ("vessel", 512, 20, "flat"),
    ("roots", 640, 20, "noisy"), ("darkgrey", 640, 20, "textured"), ("river", 768, 30, "textured"),
    ("roots", 1024, 20, "textured"), ("vessel", 1024, 30, "noisy"), ("river", 1024, 14, "flat"),
    ("roots", 1024, 30, "flat"),
)


def _path(p0, ang, length, rng, step=4.0, wig=0.15):
    pts = [np.asarray(p0, float)]
    a = ang
    for _ in range(int(length / step)):
        a += rng.normal(0, wig) * 0.5
        pts.append(pts[-1] + step * np.array([np.cos(a), np.sin(a)]))
    return np.array(pts)


def _tree(n: int, width: float, rng) -> list[tuple[np.ndarray, np.ndarray]]:
    """(points (x, y), widths) per line, the trunk first (entering at the top edge)."""
    trunk = _path((rng.uniform(0.35, 0.65) * n, -2.0), np.pi / 2 + rng.normal(0, 0.1), 0.65 * n, rng, wig=0.08)
    tw = np.linspace(width, 0.6 * width, len(trunk))
    lines = [(trunk, tw)]
    for k in range(rng.integers(2, 4)):
        i = int(len(trunk) * rng.uniform(0.3, 0.85))
        a = np.pi / 2 + (1 if k % 2 == 0 else -1) * rng.uniform(0.5, 1.0)
        w0 = max(2.0, 0.45 * tw[i])
        c = _path(trunk[i], a, rng.uniform(0.25, 0.4) * n, rng)
        cw = np.linspace(w0, max(1.5, 0.5 * w0), len(c))
        lines.append((c, cw))
        for _ in range(rng.integers(1, 3)):
            ii = int(len(c) * rng.uniform(0.3, 0.8))
            g = _path(c[ii], a + rng.choice([-1, 1]) * rng.uniform(0.5, 0.9), rng.uniform(0.12, 0.22) * n, rng)
            lines.append((g, np.linspace(max(1.5, 0.5 * cw[ii]), 1.5, len(g))))
    out = []
    for p, w in lines:
        ok = (p[:, 0] >= -3) & (p[:, 0] <= n + 2) & (p[:, 1] >= -3) & (p[:, 1] <= n + 2)
        bad = np.flatnonzero(~ok)
        m = bad[0] if len(bad) and bad[0] > 0 else len(p)
        if m >= 3:
            out.append((p[:m], w[:m]))
    return out


def wide_line_tree(kind: str, n: int, width: float, ground: str, seed: int = 0):
    """``(image (n, n, 3) float32, lines)``: a painted tree whose trunk is ``width`` px wide at the top."""
    rng = np.random.default_rng(seed)
    lines = _tree(n, width, rng)
    fg, bg = KINDS[kind]
    img = np.empty((n, n, 3), np.float32)
    img[:] = bg
    if ground in ("noisy", "textured"):
        img += (ndi.gaussian_filter(rng.normal(0, 0.06, (n, n)), 1.0) * 2.0).astype(np.float32)[..., None]
    if ground == "textured":
        t = ndi.gaussian_filter(rng.normal(0, 1, (n, n)), max(n / 24.0, 2.0 * width))
        img += (t / (t.std() + 1e-9) * 0.07).astype(np.float32)[..., None]
        for _ in range(n * n // 4000):       # small stones
            col = np.clip(np.array(bg) + rng.normal(0, 0.08, 3), 0, 1)
            cv2.circle(img, (int(rng.uniform(0, n)), int(rng.uniform(0, n))), int(rng.uniform(1, 4)),
                       tuple(float(v) for v in col), -1, cv2.LINE_AA)
    layer = np.zeros((n, n), np.float32)
    for p, w in lines:
        for i in range(len(p) - 1):
            a = tuple(int(round(v * 4)) for v in p[i])
            b = tuple(int(round(v * 4)) for v in p[i + 1])
            cv2.line(layer, a, b, 1.0, max(1, int(round(w[i]))), cv2.LINE_AA, shift=2)
    al = np.clip(layer, 0, 1)[..., None]
    fgn = np.array(fg, np.float32) + (rng.normal(0, 0.03, (n, n, 1)).astype(np.float32) if ground != "flat" else 0)
    img = img * (1 - al) + fgn * al
    if ground != "flat":
        img = cv2.GaussianBlur(img, (0, 0), 0.7)
    return np.clip(img, 0, 1).astype(np.float32), lines


def case(i: int, seed: int = 0):
    kind, n, w, ground = CASES[i]
    img, lines = wide_line_tree(kind, n, w, ground, 1000 * seed + i)
    return img, lines, CASES[i]


def _dense(p, step=0.5):
    from ..core.polyline import resample_uniform

    return resample_uniform(p, step, include_end=True) if len(p) > 1 else p


def _widths(p, w, d):
    return np.interp(np.linspace(0, 1, len(d)), np.linspace(0, 1, len(w)), w)


def figures(img, lines, s) -> dict:
    """``cov``, ``rootd``, ``rad``, ``nb``, ``roots`` of the structure ``s`` (see the module's docstring)."""
    from scipy.spatial import cKDTree

    n = img.shape[0]
    if not s.branches:
        return {"cov": 0.0, "rootd": np.inf, "rad": np.nan, "nb": 0, "roots": 0}
    ep = [_dense(b.points) for b in s.branches]
    et = np.concatenate([_widths(b.points, b.thickness, d) for b, d in zip(s.branches, ep)])
    tree = cKDTree(np.vstack(ep))
    tot = ok = 0
    for k, (p, w) in enumerate(lines):
        d = _dense(p)
        ww = _widths(p, w, d)
        vis = (d[:, 0] >= 0) & (d[:, 0] < n) & (d[:, 1] >= 0) & (d[:, 1] < n)
        for q, qw in lines[:k]:
            dq = _dense(q)
            dd, j = cKDTree(dq).query(d)
            vis &= ~(dd <= 0.5 * _widths(q, qw, dq)[j] + 1)
        dist, _ = tree.query(d[vis])
        tot += int(vis.sum())
        ok += int((dist <= np.maximum(3.0, 0.3 * ww[vis])).sum())
    trunk, tw = lines[0]
    entry = np.array([trunk[0, 0] + (trunk[1, 0] - trunk[0, 0]) * (0 - trunk[0, 1]) / (trunk[1, 1] - trunk[0, 1]), 0.0])
    roots = [b.points[0] for b in s.branches if b.parent is None]
    d = _dense(trunk)
    ww = _widths(trunk, tw, d)
    sel = slice(int(0.1 * len(d)), int(0.6 * len(d)))
    dist, idx = tree.query(d[sel])
    good = dist <= np.maximum(3.0, 0.3 * ww[sel])
    rad = float(np.median(et[idx[good]] / (ww[sel][good] / 2))) if good.any() else np.nan
    return {"cov": ok / max(tot, 1), "rootd": float(min(np.hypot(*(r - entry)) for r in roots)), "rad": rad,
            "nb": len(s.branches), "roots": len(roots)}


def main(argv) -> None:
    from .extraction import extract_structure

    seeds = [int(v) for v in argv[0].split(",")] if argv else [0]
    pngdir = argv[1] if len(argv) > 1 else None
    for seed in seeds:
        for i in range(len(CASES)):
            img, lines, c = case(i, seed)
            t = time.time()
            s = extract_structure(img)
            f = figures(img, lines, s)
            print(f"{seed} {i:2d} {c[0]:8s} N={c[1]:4d} w={c[2]:2d} {c[3]:8s} cov={f['cov']:.3f} rootd={f['rootd']:6.1f} "
                  f"rad={f['rad']:.2f} nb={f['nb']:3d} roots={f['roots']} t={time.time() - t:5.1f}s", flush=True)
            if pngdir:
                out = (img * 255).astype(np.uint8)[..., ::-1].copy()
                for b in s.branches:
                    cv2.polylines(out, [np.round(b.points * 4).astype(np.int32)], False,
                                  (0, 0, 255) if b.parent is None else (255, 0, 255), 2, cv2.LINE_AA, shift=2)
                cv2.imwrite(f"{pngdir}/wide_{seed}_{i:02d}.png", out)


if __name__ == "__main__":
    main(sys.argv[1:])
