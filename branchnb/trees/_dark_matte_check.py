"""Dark-matte fringe check (issue 24): trees composited over black / dark blue / dark green.

``python -m branchnb.trees._dark_matte_check [sizes] [seeds]`` prints, per procedural exemplar and
per mix, the fringe pixels: opaque rim pixels whose colour lies closer to the matte than to every
solid colour of the tree(s).
"""

from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage as ndi
from scipy.spatial import cKDTree

MATTES = {"black": (0.0, 0.0, 0.0), "blue": (0.04, 0.06, 0.2), "green": (0.03, 0.12, 0.05)}
KINDS = ("flat", "watercolour", "photo")


def matted_tree(kind: str, matte, side: int, soft: float, seed: int, keyed: bool = False) -> np.ndarray:
    """A lobed crown on a trunk, composited over ``matte`` with a soft edge of ``soft`` px.

    ``keyed``: the alpha runs wider than the colour edge (a photo keyed off a dark sky), so opaque
    rim pixels hold up to half the matte's colour; else alpha is the composite's share (premultiplied).
    """
    r = np.random.default_rng(seed)
    h, w = side, int(side * 0.8)
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    cx, cy, rad = w / 2, 0.38 * h, 0.34 * w
    th, rr = np.arctan2(yy - cy, xx - cx), np.hypot(xx - cx, yy - cy)
    n, ph = r.integers(5, 10), r.uniform(0, 2 * np.pi)
    crown = rr < rad * (1 - 0.25 * np.abs(np.sin(n * th / 2 + ph)) ** 0.6)
    trunk = (np.abs(xx - cx) < 0.05 * w) & (yy > cy) & (yy < 0.97 * h)
    m = crown | trunk
    g = np.array(r.choice([(0.35, 0.62, 0.22), (0.55, 0.75, 0.3), (0.25, 0.5, 0.3)]))
    rgb = np.where(crown[..., None], g, np.array([0.5, 0.33, 0.2])).astype(np.float32)
    if kind == "watercolour":
        noise = cv2.GaussianBlur(r.normal(0, 1, (h, w, 3)).astype(np.float32), (0, 0), side / 25)
        rgb = rgb + 0.12 * noise / max(noise.std(), 1e-6)
    elif kind == "photo":
        leaf = cv2.GaussianBlur(r.normal(0, 1, (h, w)).astype(np.float32), (0, 0), 1.2)
        shade = np.clip(1.15 - 0.5 * (yy - cy + rad) / (2 * rad), 0.6, 1.2)
        rgb = rgb * (shade * (1 + 0.25 * leaf / max(leaf.std(), 1e-6)))[..., None]
    rgb = np.clip(rgb, 0, 1)
    f = cv2.GaussianBlur(m.astype(np.float32), (0, 0), soft)
    out = f[..., None] * rgb + (1 - f[..., None]) * np.asarray(matte, np.float32)
    alpha = np.clip((f - 0.05) / 0.5, 0, 1) if keyed else f
    return np.dstack([out, alpha]).astype(np.float32)


def fringe_pixels(img: np.ndarray, matte, solid_sources) -> int:
    """Opaque rim pixels (2 px) closer to ``matte`` than to every solid colour of the sources."""
    op = img[..., 3] >= 0.5
    rim = op & ~ndi.binary_erosion(op, iterations=2)
    cols = []
    for s in solid_sources:
        so = ndi.binary_erosion(s[..., 3] >= 0.5, iterations=5)
        c = s[so, :3]
        cols.append(c[np.random.default_rng(0).permutation(len(c))[:4000]])
    d_solid, _ = cKDTree(np.vstack(cols)).query(img[rim, :3])
    d_matte = np.linalg.norm(img[rim, :3] - np.asarray(matte, np.float32), axis=1)
    return int((d_matte < d_solid).sum())


def main(argv: list[str]) -> None:
    from .exemplar import normalize_exemplar
    from .library import TreeLibrary

    sizes = [int(v) for v in (argv[0] if argv else "200,500,1000").split(",")]
    seeds = [int(v) for v in (argv[1] if len(argv) > 1 else "0,1").split(",")]
    tot = 0
    for mname, matte in MATTES.items():
        for kind in KINDS:
            row = []
            for side in sizes:
                for seed in seeds:
                    soft = 1.0 + 3.0 * ((seed + side) % 4) / 3
                    src = matted_tree(kind, matte, side, soft, seed, keyed=seed % 2 == 1)
                    norm = normalize_exemplar(src, size=512).image
                    row.append(fringe_pixels(norm, matte, [norm]))
            tot += sum(row)
            print(f"{mname:6s} {kind:12s} exemplars {row}")
        for kind in KINDS:
            lib = TreeLibrary(size=256)
            for k in range(3):
                lib.add(matted_tree(kind, matte, 400, 1.0 + k, 10 + k, keyed=k > 0), f"t{k}")
            srcs = [e.image for e in lib]
            mix = [fringe_pixels(np.asarray(lib.variation(rng=v).image, np.float32), matte, srcs)
                   for v in range(2)]
            tot += sum(mix)
            print(f"{mname:6s} {kind:12s} mixes     {mix}")
    print("total", tot)


if __name__ == "__main__":
    main(sys.argv[1:])
