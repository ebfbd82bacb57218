"""Issue-23 figures (branching86): a painted root system on a textured soil, with known centre lines.

``python -m branchnb.branching._soil_roots_check [SIZES] [GROUNDS] [PNG_DIR] [SEEDS]`` (e.g. ``320,640,1024
smooth,grainy,pebbly OUT 0``; grounds: see :data:`GROUNDS` and :func:`make`) extracts each painting with the
defaults and prints ``prec`` (share of the extracted skeleton length within max(3 px, radius) of a true centre
line), ``rec`` (share of the true centre-line length within that of the extracted one), the branch and root
counts (the painting has 80 roots) and the time.
"""
# ruff: noqa: E501
from __future__ import annotations

import os
import sys
import time

import cv2
import numpy as np
from scipy.spatial import cKDTree

GROUNDS = ("smooth", "noisy", "grainy", "patchy", "pebbly", "textured")




def make(N: int, ground: str, seed: int = 0):
    """A painted root system ``N`` x ``N`` (two trees from the top edge, 30 -> ~6 px wide at 1024 px, scaled
    with ``N``) on a ``smooth``, ``noisy`` (strong per-pixel colour noise), ``grainy`` (strong fine grain,
    streaks and shading), ``patchy`` (large patches of lighter and darker soil, soft-edged, with a little grain)
    or ``pebbly`` (flat pebbles of lighter and darker tones with shadows) soil; ``textured``: the roots carry
    the soil's own grain (a grain texture multiplied into the whole painting after the roots are painted, so
    no pixel keeps the paint's exact colour); ``(image, [(centreline, radii), ...])``."""
    if ground not in GROUNDS:
        raise ValueError(f"ground must be one of {GROUNDS}, got {ground!r}")
    rng = np.random.default_rng(seed)
    base = np.array([0.62, 0.48, 0.33], np.float32)
    img = np.ones((N, N, 3), np.float32) * base
    if ground == "smooth":
        img += cv2.GaussianBlur(rng.normal(0, 0.03, (N, N)).astype(np.float32), (0, 0), 1.0)[..., None]
    elif ground == "noisy":
        img += rng.normal(0, 0.06, (N, N, 3)).astype(np.float32)
    elif ground == "patchy":
        # soft-edged patches a tenth of the image across, +-0.12 in tone, and a little grain
        blobs = cv2.GaussianBlur(rng.normal(0, 1, (N, N)).astype(np.float32), (0, 0), N / 25)
        blobs = np.tanh(3.0 * blobs / (blobs.std() + 1e-9)) * 0.12
        img += (blobs + cv2.GaussianBlur(rng.normal(0, 0.04, (N, N)).astype(np.float32), (0, 0), 0.8))[..., None]
    elif ground == "grainy":
        # strong grain: fine noise, streaks, and shading
        n1 = rng.normal(0, 0.07, (N, N)).astype(np.float32)
        n2 = cv2.GaussianBlur(rng.normal(0, 1, (N, N)).astype(np.float32), (0, 0), sigmaX=N / 60, sigmaY=N / 300)
        n2 *= 0.08 / (n2.std() + 1e-9)
        yy, xx = np.mgrid[:N, :N] / N
        shade = 0.08 * np.sin(2.5 * xx + 1.3 * yy) - 0.04
        img += (n1 + n2 + shade)[..., None] * np.array([1.0, 0.9, 0.8], np.float32)
    elif ground == "pebbly":
        img += cv2.GaussianBlur(rng.normal(0, 0.05, (N, N)).astype(np.float32), (0, 0), 0.8)[..., None]
        yy, xx = np.mgrid[:N, :N] / N
        img += (0.07 * np.cos(3 * xx - 2 * yy))[..., None].astype(np.float32)
        for _ in range(int(0.00025 * N * N)):
            c = (int(rng.uniform(0, N)), int(rng.uniform(0, N)))
            ax = (int(rng.uniform(0.004, 0.014) * N) + 1, int(rng.uniform(0.003, 0.011) * N) + 1)
            tone = float(rng.uniform(-0.22, 0.2))
            col = tuple(float(v) for v in np.clip(base + tone + rng.normal(0, 0.03, 3), 0, 1))
            cv2.ellipse(img, c, ax, float(rng.uniform(0, 180)), 0, 360, col, -1, cv2.LINE_AA)
            # a pebble's shadow on its lower side
            cv2.ellipse(img, (c[0], c[1] + ax[1]), (ax[0], max(1, ax[1] // 3)), 0, 0, 180,
                        tuple(float(v) for v in base - 0.12), -1, cv2.LINE_AA)
        img = cv2.GaussianBlur(img, (0, 0), 0.7)
    lines = []
    s = N / 1024.0

    def grow(p, ang, w, depth):
        L = N * (0.35 if depth == 0 else 0.22) * rng.uniform(0.7, 1.1)
        pts = [p]
        for _i in range(20):
            ang += rng.normal(0, 0.12)
            pts.append(pts[-1] + L / 20 * np.array([np.cos(ang), np.sin(ang)]))
        pts = np.array(pts)
        rads = []
        for i in range(len(pts) - 1):
            ww = w * (1 - 0.5 * i / len(pts))
            rads.append(ww)
            cv2.line(img, tuple((pts[i] * 4).astype(int)), tuple((pts[i + 1] * 4).astype(int)), (0.25, 0.16, 0.08),
                     max(1, int(round(2 * ww))), cv2.LINE_AA, shift=2)
        rads.append(rads[-1])
        lines.append((pts, np.array(rads)))
        if depth < 3 and w > 4.0 * s:
            for t in (0.4, 0.75):
                k = int(t * len(pts))
                side = rng.choice([-1, 1])
                grow(pts[k], ang + side * rng.uniform(0.5, 0.9), w * 0.6, depth + 1)
            grow(pts[-1], ang + rng.normal(0, 0.3), w * 0.7, depth + 1)
    for x in (0.3, 0.7):
        grow(np.array([x * N, 0.0]), np.pi / 2 + rng.normal(0, 0.2), 15.0 * s, 0)
    if ground == "textured":
        # one grain over soil and roots alike: fine speckle, grains a few px across, streaks
        g1 = cv2.GaussianBlur(rng.normal(0, 1, (N, N)).astype(np.float32), (0, 0), 0.7)
        g2 = cv2.GaussianBlur(rng.normal(0, 1, (N, N)).astype(np.float32), (0, 0), max(1.0, N / 400))
        g3 = cv2.GaussianBlur(rng.normal(0, 1, (N, N)).astype(np.float32), (0, 0), sigmaX=N / 80, sigmaY=N / 400)
        tex = 1.0 + sum(0.12 * g / (g.std() + 1e-9) for g in (g1, g2, g3))
        img *= tex[..., None]
    return img.clip(0, 1), lines


def dense(pts, step=0.5):
    """Points every ``step`` px along the polyline ``pts`` and their arc lengths."""
    p = np.asarray(pts, float)
    t = np.r_[0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
    ss = np.arange(0, t[-1] + 1e-9, step)
    return np.c_[np.interp(ss, t, p[:, 0]), np.interp(ss, t, p[:, 1])], ss


def scores(lines, s, N):
    """``(precision, recall)``: the share of extracted centre-line length within max(3 px, radius) of a true
    centre line, and of true centre-line length (inside the frame) within that of an extracted one."""
    tp, tr = [], []
    for pts, r in lines:
        d, ss = dense(pts)
        t = np.r_[0, np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]
        inside = (d[:, 0] >= 0) & (d[:, 0] <= N - 1) & (d[:, 1] >= 0) & (d[:, 1] <= N - 1)
        tp.append(d[inside])
        tr.append(np.interp(ss, t, r)[inside])
    tp, tr = np.vstack(tp), np.concatenate(tr)
    ep = [dense(b.points)[0] for b in s.branches if len(b.points) > 1]
    ep = np.vstack(ep) if ep else np.zeros((0, 2))
    tt = cKDTree(tp)
    dist, idx = tt.query(ep) if len(ep) else (np.zeros(0), np.zeros(0, int))
    prec = float(np.mean(dist <= np.maximum(3.0, tr[idx]))) if len(ep) else 0.0
    if len(ep):
        de, _ = cKDTree(ep).query(tp)
        rec = float(np.mean(de <= np.maximum(3.0, tr)))
    else:
        rec = 0.0
    return prec, rec


def main() -> None:
    import branchnb
    from branchnb.branching import extract_structure
    sizes = [int(v) for v in sys.argv[1].split(",")] if len(sys.argv) > 1 else [320, 640, 1024]
    grounds = sys.argv[2].split(",") if len(sys.argv) > 2 else ["smooth", "grainy", "pebbly"]
    out = sys.argv[3] if len(sys.argv) > 3 else None
    seeds = [int(v) for v in sys.argv[4].split(",")] if len(sys.argv) > 4 else [0]
    print(branchnb.__file__, flush=True)
    for N in sizes:
        for g in grounds:
            for seed in seeds:
                img, lines = make(N, g, seed)
                t = time.perf_counter()
                s = extract_structure(img)
                t = time.perf_counter() - t
                p, r = scores(lines, s, N)
                print(f"{g:7s} {N:5d} s{seed} prec={p:.3f} rec={r:.3f} nb={len(s.branches):4d} "
                      f"roots={sum(b.parent is None for b in s.branches)} t={t:.1f}s", flush=True)
                if out:
                    os.makedirs(out, exist_ok=True)
                    vis = s.render(background=img * 0.5, by_generation=True, min_width=1.5)[..., :3]
                    cv2.imwrite(f"{out}/{g}_{N}_{seed}.png", (np.hstack([img, vis]).clip(0, 1) * 255).astype(np.uint8)[..., ::-1])


if __name__ == "__main__":
    main()
