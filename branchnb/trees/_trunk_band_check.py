"""Dark-trunk clip art: the outline band along a mix's trunk (issue 24, trees33), not run by the tests.

``python -m branchnb.trees._trunk_band_check [sizes] [seeds] [pens] [png dir or -] [dark,light]``
(defaults ``200,400,1000``, 2, ``1,2,4``, no PNGs, both trunks): libraries of three procedural clip-art trees
(:func:`~branchnb.trees._clipart_check.clipart_tree`: round, cloud and cone crowns, flat fills,
fruit, ``pen`` px outlines at 256 px) with a *dark* trunk (value 0.12-0.25, darker than the ink
threshold of the whole tree) and with a light one, drawn at ``size`` px; three random mixes
each. Prints per library the sources' and the mixes' outline width along the trunk and along
the crown (:func:`part_widths`: at each rim pixel, the distance inward over which the colour
stays nearer the ink than the part's own fill), median and 90th percentile, and the mixes'
*band* (:func:`trunk_band`: share of trunk pixels deeper than the sources' 90th-percentile width
+ 1 that are stroke: a dark trunk's widened outline).
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage as ndi

from ._clipart_check import KINDS, _hsv, clipart_tree


def _stroke_map(image: np.ndarray, parts: np.ndarray, ink: np.ndarray, width: float):
    """Stroke pixels (nearer the ink than their part's fill, on the line between them), depth."""
    from .outline_pen import _depth_edt

    alpha = image[..., 3] >= 0.5
    depth = _depth_edt(alpha)
    stroke = np.zeros(alpha.shape, bool)
    for part in (1, 2):
        m = alpha & (parts == part)
        # the part's own fill: deep and not ink-coloured (a widened stroke or an ink blob is no fill)
        deep = m & (depth > width + 2) & (np.linalg.norm(image[..., :3] - ink, axis=2) > 0.08)
        if deep.sum() < 5:
            continue
        fill = np.median(image[deep, :3], axis=0)
        d = fill - ink
        n2 = float(d @ d)
        if n2 < 0.03 ** 2:
            continue
        c = ((fill - image[m, :3]) @ d) / n2
        stroke[m] = c >= 0.5
    return stroke, depth, alpha


def part_widths(image, parts, ink, width: float) -> dict:
    """Outline width at the rim pixels of the crown (1) and the trunk (2): the Euclidean distance
    from the rim pixel to the nearest opaque pixel that is no stroke."""
    stroke, depth, alpha = _stroke_map(image, parts, ink, width)
    d = ndi.distance_transform_edt(~(alpha & ~stroke))
    rim = alpha & (depth < 1.5) & stroke
    out = {}
    for part in (1, 2):
        w = d[rim & (parts == part)]
        out[part] = w[w <= 6 * width + 4]
    return out


def trunk_band(image, parts, ink, width: float, limit: float) -> float:
    """Share of trunk pixels deeper than ``limit`` that are stroke."""
    stroke, depth, alpha = _stroke_map(image, parts, ink, width)
    m = alpha & (parts == 2) & (depth > limit)
    return float(stroke[m].mean()) if m.any() else float("nan")


def _parts_of(e) -> np.ndarray:
    return np.where(e.alpha, np.where(e.trunk & e.alpha, 2, 1), 0)


def library(size: int, pen: float, seed: int, dark: bool):
    from .variations import TreeLibrary

    rng = np.random.default_rng(1000 * seed + int(10 * pen) + 7 * dark)
    lib = TreeLibrary(size=256)
    for k, kind in enumerate(KINDS):
        bark = _hsv(rng.uniform(15, 35), rng.uniform(0.4, 0.8), rng.uniform(0.12, 0.25)) if dark else None
        lib.add(clipart_tree(kind, line=pen * size / 256, rng=50 * seed + k, size=size, bark=bark), kind)
    return lib


def _q(w):
    return f"{np.median(w):4.2f}/{np.quantile(w, 0.9):4.2f}" if len(w) >= 10 else " nan/ nan"


def measure(sizes=(200, 400, 1000), seeds: int = 2, pens=(1, 2, 4), mixes: int = 3, show: str | None = None,
            trunks=("dark", "light")):
    from .outline import silhouette_outline

    out = {}
    for dark in [t == "dark" for t in trunks]:
        for size in sizes:
            for pen in pens:
                for seed in range(seeds):
                    lib = library(size, pen, seed, dark)
                    w = float(pen)          # pens are given at 256 px, the working size
                    src = {1: [], 2: []}
                    for e in lib.exemplars:
                        o = silhouette_outline(e.image)
                        for k, v in part_widths(e.image, _parts_of(e), o.ink, w).items():
                            src[k].append(v)
                    src = {k: np.concatenate(v) for k, v in src.items()}
                    lim = float(np.quantile(src[2], 0.9)) + 1 if len(src[2]) else w + 1
                    mix = {1: [], 2: []}
                    bands = []
                    vs = [lib.variation(rng=s) for s in range(mixes)]
                    for v in vs:
                        o = silhouette_outline(v.image)
                        for k, val in part_widths(v.image, v.parts, o.ink, w).items():
                            mix[k].append(val)
                        bands.append(trunk_band(v.image, v.parts, o.ink, w, lim))
                    mix = {k: np.concatenate(v) for k, v in mix.items()}
                    sb = np.nanmean([trunk_band(e.image, _parts_of(e), silhouette_outline(e.image).ink, w, lim)
                                     for e in lib.exemplars])
                    name = f"{'dark' if dark else 'light'} {size:4d}px pen{pen} s{seed}"
                    print(f"{name:24s} trunk src {_q(src[2])} mix {_q(mix[2])} | crown src {_q(src[1])} "
                          f"mix {_q(mix[1])} | band src {sb:.3f} mix {np.nanmean(bands):.3f} "
                          f"(worst {np.nanmax(bands):.3f})", flush=True)
                    out[name] = (src, mix, sb, bands)
                    if show:
                        import cv2

                        from .variations import tile_images

                        t = tile_images([e.image for e in lib.exemplars] + [v.image for v in vs], cols=3)
                        cv2.imwrite(f"{show}/{name.replace(' ', '_')}.png", (t[..., ::-1] * 255).astype(np.uint8))
    return out


if __name__ == "__main__":
    a = sys.argv[1:]
    measure(tuple(int(x) for x in a[0].split(",")) if len(a) > 0 else (200, 400, 1000),
            int(a[1]) if len(a) > 1 else 2,
            tuple(float(x) for x in a[2].split(",")) if len(a) > 2 else (1, 2, 4),
            show=a[3] if len(a) > 3 and a[3] != "-" else None,
            trunks=tuple(a[4].split(",")) if len(a) > 4 else ("dark", "light"))
