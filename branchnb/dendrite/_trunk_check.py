"""Measure: a lightning bolt and vines on a tree run down its trunk (issue 25), with the defaults.

``python -m branchnb.dendrite._trunk_check [sizes] [seeds] [grounds]`` draws a procedural tree (a
lobed crown on a trunk that leans and tapers, shapes vary with the seed) on a ground (``sky``: a
gradient with a grass strip; ``dark``; ``white``), stylizes it with ``metaphor="lightning"`` and
``"vines"`` and prints, per case, the share of the trunk's rows (crown bottom to foot) where the
drawing has a lit (lightning, brightness > 0.6) or inked (vines, darkness > 0.3) pixel on the
trunk (dilated by 2 % of the width). ``legs`` as a ground name draws a body on four legs on the
sky instead (a control: no stem, the bolt should stop at the body; printed as the share of the
legs' rows lit). Not a test.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage

SIZES = (250, 500, 1000)
GROUNDS = ("sky", "dark", "white", "legs")


def tree(n: int, seed: int, ground: str = "sky") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A tree (or the legged control) at width ``n``: RGB image, object mask, trunk mask."""
    rng = np.random.default_rng(seed)
    h, w = int(0.8 * n), n
    y, x = np.mgrid[0:h, 0:w] / n
    foot = 0.72
    cx, cy = 0.5 + rng.uniform(-0.06, 0.06), 0.3 + rng.uniform(-0.03, 0.03)
    th = np.arctan2(y - cy, x - cx)
    ph = rng.uniform(0, 2 * np.pi, 2)
    rx, ry = rng.uniform(0.25, 0.33), rng.uniform(0.17, 0.22)
    crown = np.hypot((x - cx) / rx, (y - cy) / ry) < 1 + 0.1 * np.sin(5 * th + ph[0]) + 0.05 * np.sin(9 * th + ph[1])
    if ground == "legs":
        trunk = np.zeros_like(crown)
        for lx in np.linspace(cx - 0.6 * rx, cx + 0.6 * rx, 4):
            trunk |= (np.abs(x - lx) < 0.018) & (y > cy) & (y < foot)
    else:
        lean = rng.uniform(-0.08, 0.08)
        t = np.clip((y - cy) / (foot - cy), 0, 1)
        half = 0.02 + 0.012 * t + rng.uniform(0, 0.01)
        trunk = (np.abs(x - (cx + lean * (1 - t))) < half) & (y > cy) & (y < foot)
    obj = crown | trunk
    trunk = trunk & ~crown
    if ground in ("sky", "legs"):
        tt = (y / y.max())[..., None]
        img = (1 - tt) * np.array([0.45, 0.65, 0.95]) + tt * np.array([0.85, 0.9, 0.98])
        img[y >= foot] = (0.3, 0.55, 0.2)
    elif ground == "dark":
        img = np.broadcast_to(np.array([0.08, 0.08, 0.1]), (h, w, 3)).copy()
    else:
        img = np.ones((h, w, 3))
    tex = ndimage.gaussian_filter(rng.standard_normal((h, w)), n / 300)
    leaf = np.array([0.25, 0.5, 0.15]) + 0.25 * tex[..., None] / max(tex.std(), 1e-9)
    img[crown] = leaf[crown]
    img[trunk] = (0.3, 0.2, 0.12)
    return np.clip(img, 0, 1).astype(np.float32), obj, trunk


def trunk_cover(out: np.ndarray, trunk: np.ndarray, lit: bool) -> float:
    """Share of the trunk's rows with a lit (or inked) pixel on it."""
    lum = np.asarray(out, np.float32)[..., :3].mean(axis=2)
    on = lum > 0.6 if lit else lum < 0.7
    near = ndimage.binary_dilation(trunk, iterations=max(1, int(0.02 * trunk.shape[1])))
    rows = np.flatnonzero(trunk.any(axis=1))
    return float((on & near)[rows].any(axis=1).mean()) if rows.size else float("nan")


def main(sizes=SIZES, seeds=(0, 1), grounds=GROUNDS) -> None:
    from . import stylize

    for ground in grounds:
        for n in sizes:
            cells = []
            for seed in seeds:
                img, obj, trunk = tree(n, seed, ground)
                bolt = stylize(img, rng=seed, metaphor="lightning").rendering.image
                vine = stylize(img, rng=seed, metaphor="vines").rendering.image
                cells.append(f"s{seed} bolt {trunk_cover(bolt, trunk, True):.2f} "
                             f"vine {trunk_cover(vine, trunk, False):.2f}")
            print(f"{ground:5s} {n:5d} | " + " | ".join(cells), flush=True)


if __name__ == "__main__":
    a = sys.argv[1:]
    main(tuple(int(v) for v in a[0].split(",")) if a else SIZES,
         tuple(int(v) for v in a[1].split(",")) if len(a) > 1 else (0, 1),
         tuple(a[2].split(",")) if len(a) > 2 else GROUNDS)
