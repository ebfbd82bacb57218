"""Small game-sprite trees (32-256 px, hard alpha, 2-3 flat colours, 1 px outline or none): do their
variations come out at their own size, quickly, in their own style? (issue 24, beyond the paper.)

``python -m branchnb.trees._sprite_check [SIZES] [SEEDS] [OUT_DIR]`` builds libraries of round, fir,
poplar and palm (tall trunk) sprites per size, outlined or not, makes variations with the defaults of
:class:`~branchnb.trees.library.TreeLibrary` and prints per size/outline/seed: output size, seconds per
variation, share of opaque output pixels within 0.03 of the sources' palette (``pal``), alpha values
other than 0/1 (``soft``), outline width in sprite pixels (``olw``: ink pixels near the rim per rim
pixel; 1.0 = a 1 px outline) and ink pixels inside the tree (``inner``: stubs of a source's outline,
e.g. where a trunk meets a crown) and ``bump``: pixels of 1-2 px bumps on a straight edge (outline
stubs). Measured on the output brought to the sprites' own pixel grid
(nearest) when it is larger.
"""

from __future__ import annotations

import sys
import time

import cv2
import numpy as np
from scipy import ndimage as ndi

from branchnb.trees.pixel_art import _drop_bumps

KINDS = ("round", "fir", "poplar", "palm")
INK = (0.08, 0.1, 0.05)
BARK = (0.45, 0.3, 0.15)


def sprite(kind: str, size: int = 64, outline: bool = True, rng=0) -> np.ndarray:
    """A hard-edged ``size`` x ``size`` RGBA tree sprite drawn on its pixel grid (no anti-aliasing)."""
    r = np.random.default_rng(rng)
    H = W = int(size)
    rgb = np.zeros((H, W, 3), np.float32)
    a = np.zeros((H, W), np.uint8)
    g1 = (0.15, float(0.5 + 0.1 * r.random()), 0.2)
    g2 = (0.35, 0.75, 0.3)
    cx = W / 2 + r.uniform(-0.04, 0.04) * W

    def poly(pts, col):
        pts = np.round(np.asarray(pts, np.float64)).astype(np.int32)
        cv2.fillPoly(rgb, [pts], col)
        cv2.fillPoly(a, [pts], 1)

    tw = max(1.5, W * r.uniform(0.04, 0.07))
    top = {"round": 0.55, "fir": 0.7, "poplar": 0.75, "palm": 0.25}[kind] * H
    lean = r.uniform(-0.08, 0.08) * W if kind == "palm" else 0.0
    poly([[cx - tw + lean, top], [cx + tw + lean, top], [cx + tw * 1.2, H - 1], [cx - tw * 1.2, H - 1]], BARK)
    cx2 = cx + lean
    if kind == "round":
        for _ in range(int(r.integers(3, 6))):
            c = (int(cx2 + r.uniform(-0.18, 0.18) * W), int(H * r.uniform(0.25, 0.45)))
            rad = int(W * r.uniform(0.15, 0.24))
            cv2.circle(rgb, c, rad, g1, -1)
            cv2.circle(a, c, rad, 1, -1)
            cv2.circle(rgb, (c[0] - rad // 3, c[1] - rad // 3), max(1, rad // 2), g2, -1)
    elif kind == "fir":
        n = int(r.integers(3, 5))
        for k in range(n):
            t0 = H * (0.03 + 0.7 * k / n)
            t1 = t0 + H * 0.3
            half = W * (0.16 + 0.3 * (k + 1) / n)
            poly([[cx, t0], [cx - half, t1], [cx + half, t1]], g1)
            poly([[cx, t0], [cx - half, t1], [cx - half * 0.3, t1]], g2)
    elif kind == "poplar":
        ax, ay = int(W * r.uniform(0.14, 0.2)), int(H * 0.4)
        c = (int(cx), int(H * 0.42))
        cv2.ellipse(rgb, c, (ax, ay), 0, 0, 360, g1, -1)
        cv2.ellipse(a, c, (ax, ay), 0, 0, 360, 1, -1)
        cv2.ellipse(rgb, (c[0] - ax // 3, c[1]), (max(1, ax // 3), int(ay * 0.8)), 0, 0, 360, g2, -1)
    else:
        p = np.array([cx2, top + 1])
        for ang in np.linspace(-2.8, -0.35, int(r.integers(4, 7))):
            q = p + W * r.uniform(0.33, 0.45) * np.array([np.cos(ang), np.sin(ang) + 0.75])
            m = (p + q) / 2 + np.array([0, -H * 0.07])
            wdt = H * 0.045
            poly([p, m + [0, -wdt], q, m + [0, wdt]], g1 if ang < -1.5 else g2)
    if outline:
        edge = a - cv2.erode(a, np.ones((3, 3), np.uint8))
        rgb[edge > 0] = INK
    return np.dstack([rgb * a[..., None], a.astype(np.float32)]).astype(np.float32)


def _on_grid(img: np.ndarray, n: int) -> np.ndarray:
    """``img`` brought to ``n`` x ``n`` (nearest, at the art pixels' centres) when it is larger."""
    if img.shape[0] <= n:
        return img
    return cv2.resize(img, (n, n), interpolation=cv2.INTER_NEAREST)


def measure(out: np.ndarray, palette: np.ndarray, outlined: bool, grid: int) -> dict:
    """Style figures of one output (see the module docstring)."""
    out = np.asarray(out, np.float32)
    al = out[..., 3]
    soft = float(np.mean((al > 1e-6) & (al < 1 - 1e-6)))
    g = _on_grid(out, grid)
    op = g[..., 3] >= 0.5
    col = g[..., :3][op]
    d = np.sqrt(((col[:, None] - palette[None]) ** 2).sum(-1)).min(1) if len(col) else np.zeros(0)
    pal = float(np.mean(d <= 0.03)) if len(d) else 1.0
    ink = op & (np.abs(g[..., :3] - np.float32(INK)).max(-1) <= 0.1)
    inside = ndi.distance_transform_edt(np.pad(op, 1))[1:-1, 1:-1]
    rim = op & (inside <= 1.5)        # 8-connected rim: a pixel with an 8-neighbour outside
    olw = float((ink & (inside <= 3.5)).sum() / max(rim.sum(), 1)) if outlined else float("nan")
    inner = int((ink & (inside > 3.5)).sum()) if outlined else 0
    bump = int(sum((np.rot90(op, k) & ~_drop_bumps(np.rot90(op, k))).sum() for k in range(4)))
    return dict(pal=pal, soft=soft, olw=olw, inner=inner, bump=bump)


def library_sprites(size: int, outline: bool, seed: int) -> list[np.ndarray]:
    """One sprite of each kind (seeded)."""
    return [sprite(k, size, outline, rng=100 * seed + i) for i, k in enumerate(KINDS)]


def run(sizes=(32, 64, 96, 128, 256), seeds=(0, 1), n_var: int = 3, show: str | None = None) -> dict:
    from branchnb.trees import TreeLibrary

    res = {}
    for size in sizes:
        for outline in (True, False):
            for seed in seeds:
                trees = library_sprites(size, outline, seed)
                t0 = time.perf_counter()
                lib = TreeLibrary()
                for i, t in enumerate(trees):
                    lib.add(t, f"{KINDS[i]}{i}")
                t1 = time.perf_counter()
                outs = [np.asarray(lib.variation(rng=seed * 10 + v).image, np.float32) for v in range(n_var)]
                t2 = time.perf_counter()
                op = [t[..., 3] >= 0.5 for t in trees]
                palette = np.unique(np.concatenate([t[..., :3][o] for t, o in zip(trees, op)]).round(4), axis=0)
                ms = [measure(o, palette, outline, size) for o in outs]
                agg = {k: float(np.nanmean([m[k] for m in ms])) if k not in ("inner", "bump") else max(m[k] for m in ms)
                       for k in ms[0]}
                agg.update(out=outs[0].shape[0], s_add=(t1 - t0) / len(trees), s_var=(t2 - t1) / n_var)
                res[(size, outline, seed)] = agg
                print(f"{size:4d} ol{int(outline)} seed{seed} out {agg['out']:4d} add {agg['s_add']:6.2f}s "
                      f"var {agg['s_var']:6.2f}s pal {agg['pal']:.3f} soft {agg['soft']:.4f} "
                      f"olw {agg['olw']:.2f} inner {agg['inner']} bump {agg['bump']}", flush=True)
                if show:
                    def on(x, h=4 * size):
                        x = cv2.resize(x, (h, h), interpolation=cv2.INTER_NEAREST)
                        return x[..., :3] * x[..., 3:] + 0.85 * (1 - x[..., 3:])
                    row = np.concatenate([np.concatenate([on(t) for t in trees], 1),
                                          np.concatenate([on(o) for o in outs]
                                                         + [np.ones((4 * size, 4 * size, 3), np.float32)]
                                                         * (len(trees) - n_var), 1)], 0)
                    cv2.imwrite(f"{show}/sprites_{size}_{int(outline)}_{seed}.png",
                                (np.clip(row, 0, 1)[..., ::-1] * 255).astype(np.uint8))
    return res


if __name__ == "__main__":
    sz = tuple(int(x) for x in sys.argv[1].split(",")) if len(sys.argv) > 1 else (32, 64, 96, 128, 256)
    sd = tuple(int(x) for x in sys.argv[2].split(",")) if len(sys.argv) > 2 else (0, 1)
    run(sz, sd, show=sys.argv[3] if len(sys.argv) > 3 else None)
