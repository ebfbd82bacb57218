"""Pixel-art trees in mixes (issue 24), not run by the tests.

``python -m branchnb.trees._measure_pixel [seeds] [mixes]``: libraries of four procedural
pixel-art sprites (:func:`sprite`: round or pine crowns in 3 tones with a 1-px outline, or
without, art 40-96 px enlarged x2-x4 nearest: 104-480 px) mixed with the defaults
(``TreeLibrary(size=256)``); per kind prints, over the mixes' opaque pixels, the share within
0.06 of a source palette colour (``palette``), the share of alpha values other than 0/1
(``soft_alpha``), and the share of opaque pixels whose 3 x 3 neighbourhood holds more than two
colours (``aa``: anti-aliased edges; a sprite's own stays below 0.05).
"""

from __future__ import annotations

import sys

import cv2
import numpy as np

#: kind -> (crown, art width, art height, enlargement, outlined)
KINDS = {
    "round-56-x2": ("round", 56, 72, 2, True),
    "round-40-x3": ("round", 40, 52, 3, True),
    "pine-64-x2": ("pine", 64, 80, 2, True),
    "round-96-x4": ("round", 96, 120, 4, True),
    "pine-48-x3-bare": ("pine", 48, 64, 3, False),
}


def sprite(seed: int, crown: str = "round", w: int = 56, h: int = 72, k: int = 2, outlined: bool = True):
    """A pixel-art tree: ``w`` x ``h`` art pixels, 3-tone crown, 2-tone trunk, enlarged ``k`` x nearest."""
    r = np.random.default_rng(seed)
    img = np.zeros((h, w, 4), np.float32)
    yy, xx = np.mgrid[:h, :w]
    body = np.zeros((h, w), bool)
    if crown == "round":
        for _ in range(int(r.integers(3, 6))):
            cx, cy = r.uniform(0.28, 0.72) * w, r.uniform(0.2, 0.47) * h
            rx, ry = r.uniform(0.16, 0.27) * w, r.uniform(0.11, 0.18) * h
            body |= ((xx - cx) / rx) ** 2 + ((yy - cy) / ry) ** 2 <= 1
        t0 = int(0.42 * h)
    else:
        n = int(r.integers(2, 4))
        for i in range(n):
            top, bot = 0.05 * h + i * 0.2 * h, 0.35 * h + i * 0.2 * h
            half = (0.2 + 0.1 * i) * w * r.uniform(0.85, 1.1)
            body |= (yy >= top) & (yy <= bot) & (np.abs(xx - w / 2) <= half * (yy - top) / (bot - top))
        t0 = int((0.3 + 0.2 * n) * h)
    tw = max(3, int(w * r.uniform(0.1, 0.18)))
    tx = w // 2 - tw // 2
    trunk = (xx >= tx) & (xx < tx + tw) & (yy >= t0) & (yy < h - 2) & ~body
    greens = np.array([[0.13, 0.42, 0.16], [0.22, 0.58, 0.2], [0.4, 0.72, 0.26]]) * r.uniform(0.85, 1.1)
    shade = np.clip((yy - 0.14 * h) / (0.42 * h) + (xx - w / 2) / w, 0, 1)
    lvl = np.where(shade < 0.35, 2, np.where(shade < 0.7, 1, 0))
    img[trunk] = [0.45, 0.27, 0.12, 1]
    img[trunk & (xx < tx + max(1, tw // 4))] = [0.33, 0.19, 0.08, 1]
    img[body, :3] = greens[lvl[body]]
    img[body, 3] = 1
    tree = body | trunk
    if outlined:
        rim = tree & ~cv2.erode(tree.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
        img[rim] = [0.06, 0.1, 0.05, 1]
    return cv2.resize(img, (w * k, h * k), interpolation=cv2.INTER_NEAREST)


def palette_share(image, palette, tol: float = 0.06) -> float:
    """Share of opaque pixels within ``tol`` (RGB) of a palette colour."""
    a = np.asarray(image, np.float32)
    op = a[..., 3] >= 0.5
    d = np.linalg.norm(a[op, None, :3] - np.asarray(palette, np.float32)[None], axis=2).min(axis=1)
    return float((d <= tol).mean())


def aa_share(image) -> float:
    """Share of opaque pixels whose 3 x 3 neighbourhood (opaque pixels only) has more than two colours."""
    a = np.asarray(image, np.float32)
    op = a[..., 3] >= 0.5
    q = np.round(a[..., :3] * 255).astype(np.int64)
    key = np.where(op, (q[..., 0] << 16) | (q[..., 1] << 8) | q[..., 2], -1)
    h, w = key.shape
    pad = np.pad(key, 1, constant_values=-1)
    nb = np.stack([pad[dy:dy + h, dx:dx + w] for dy in range(3) for dx in range(3)])
    nb = np.sort(nb, axis=0)
    distinct = 1 + ((nb[1:] != nb[:-1]) & (nb[1:] >= 0)).sum(axis=0) - (nb[0] < 0)
    return float((distinct[op] > 2).mean())


def measure(seeds=(0, 1), mixes: int = 3, kinds=None) -> dict:
    from .library import TreeLibrary
    from .pixel_art import _detect

    out = {}
    for kind in kinds or KINDS:
        crown, w, h, k, outl = KINDS[kind]
        rows = []
        for seed in seeds:
            srcs = [sprite(100 * seed + i, crown, w, h, k, outl) for i in range(4)]
            pal = np.unique(np.concatenate([_detect(s).palette for s in srcs]), axis=0)
            lib = TreeLibrary(size=256)
            for i, s in enumerate(srcs):
                lib.add(s, f"s{i}")
            for m in range(mixes):
                v = np.asarray(lib.variation(rng=1000 * seed + m).image, np.float32)
                soft = float(((v[..., 3] > 0) & (v[..., 3] < 1)).mean())
                rows.append((palette_share(v, pal), soft, aa_share(v)))
        r = np.array(rows)
        out[kind] = r.mean(axis=0)
        print(f"{kind:18s} palette {r[:, 0].mean():.3f} (min {r[:, 0].min():.3f})  soft_alpha {r[:, 1].mean():.4f}"
              f"  aa {r[:, 2].mean():.3f} (max {r[:, 2].max():.3f})", flush=True)
    return out


if __name__ == "__main__":
    measure(tuple(range(int(sys.argv[1]))) if len(sys.argv) > 1 else (0, 1),
            int(sys.argv[2]) if len(sys.argv) > 2 else 3)
