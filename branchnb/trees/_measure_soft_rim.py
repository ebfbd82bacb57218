"""Anti-aliased rims of tree mixes (issue 24, :mod:`~branchnb.trees.rim_alpha`), not run by the tests.

``python -m branchnb.trees._measure_soft_rim [sizes] [seeds]`` (defaults ``96,128,256,512`` and 3):
libraries of smooth blob trees (:mod:`~branchnb.trees._measure_rim`, flat and watercolour fills),
drawn trees (:func:`~branchnb.trees.drawn.drawn_tree`), synthetic trees
(:func:`~branchnb.trees.synthetic.synthetic_tree`) and sample clip art / pixel art; ``seeds``
random mixes each, with and without the soft rim. Per library it prints

* ``soft``: share of the rim pixels (either side of the opaque set's edge) with 0.02 < alpha < 0.98,
  sources' (their soft alpha) | mixes without | with the soft rim;
* ``stair``: mean |alpha - coverage| on the rim, coverage of the mixed contour polygon grown by
  half a pixel (it runs through border pixel centres) at 8 x 8 samples per pixel, on the rim pixels
  whose side of 0.5 the polygon agrees with (elsewhere the silhouette left the contour: trunks,
  tips), without | with;
* ``fringe``: worst mean luminance step of the rim's composite over white and over black against
  ``alpha x colour 1 px inside + (1 - alpha) x backdrop`` (negative: darker);
* ``same``: whether the opaque set and ``crossfade_fraction`` are identical with and without.
"""

from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage as ndi

LUMA = np.array([0.299, 0.587, 0.114], np.float32)


def _band(op):
    k = np.ones((3, 3), np.uint8)
    u = op.astype(np.uint8)
    return (cv2.dilate(u, k) > 0) & ~(cv2.erode(u, k, borderType=cv2.BORDER_CONSTANT, borderValue=0) > 0)


def contour_coverage(contour, shape, grow: float = 0.5, ss: int = 8) -> np.ndarray:
    """Coverage (0-1) of each pixel by the polygon ``contour`` (x, y; pixel centres at integers)
    grown by ``grow`` px, from ``ss`` x ``ss`` samples per pixel."""
    h, w = shape
    big = np.zeros((h * ss, w * ss), np.uint8)
    pts = np.round((np.asarray(contour, np.float64) + 0.5) * ss * 16 - 0.5 * 16).astype(np.int32)
    cv2.fillPoly(big, [pts.reshape(-1, 1, 2)], 1, lineType=cv2.LINE_8, shift=4)
    r = int(round(grow * ss))
    if r > 0:
        big = cv2.dilate(big, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1)))
    return cv2.resize(big.astype(np.float32), (w, h), interpolation=cv2.INTER_AREA)


def soft_share(alpha, op) -> float:
    b = _band(op)
    a = np.asarray(alpha)[b]
    return float(((a > 0.02) & (a < 0.98)).mean()) if b.any() else 0.0


def staircase(alpha, op, cov) -> float:
    b = _band(op) & ((cov >= 0.5) == op)
    return float(np.abs(alpha[b] - cov[b]).mean()) if b.any() else 0.0


def fringe(image) -> float:
    a = image[..., 3]
    op = a >= 0.5
    soft = (a > 0.02) & (a < 0.98)
    if not soft.any():
        return 0.0
    inner = ndi.binary_erosion(op, iterations=1)
    if not inner.any():
        inner = op
    iy, ix = ndi.distance_transform_edt(~inner, return_distances=False, return_indices=True)
    ref = image[..., :3][iy, ix]
    worst = 0.0
    for bg in (1.0, 0.0):
        got = (image[..., :3] * a[..., None] + bg * (1 - a[..., None]))[soft] @ LUMA
        want = (ref * a[..., None] + bg * (1 - a[..., None]))[soft] @ LUMA
        d = float((got - want).mean())
        worst = d if abs(d) > abs(worst) else worst
    return worst


def libraries(size: int) -> dict:
    from .. import data
    from ._measure_rim import blob_tree
    from .drawn import drawn_tree
    from .synthetic import synthetic_tree

    big = max(2 * size, 200)
    libs = {
        "blob_flat": [blob_tree(k, "flat", i, int(big * f)) for i, (k, f) in
                      enumerate([("round", 1.0), ("lobed", 1.3), ("tall", 0.9), ("wide", 1.6)])],
        "blob_water": [blob_tree(k, "watercolour", 5 + i, int(big * f)) for i, (k, f) in
                       enumerate([("round", 1.2), ("tall", 1.0), ("offcentre", 1.5)])],
        "drawn": [drawn_tree(k, rng=i, size=big) for i, k in enumerate(("broadleaf", "conifer", "fruit", "palm"))],
        "synthetic": [synthetic_tree(k, rng=i, size=big).image for i, k in
                      enumerate(("clean", "palm", "outlined", "leaf_pile"))],
        "clipart": [data.load(n) for n in ("cartoon_tree", "tree_with_fruits", "evergreen", "plain_tree")],
        "pixel_rpg": [data.load(n) for n in ("tree_rpg_05", "tree_rpg_06", "tree_rpg_13")],
    }
    return libs


def measure(sizes=(96, 128, 256, 512), seeds: int = 3) -> dict:
    from . import variations
    from .quality import crossfade_fraction
    from .rim_alpha import exemplar_rim_width
    from .variations import TreeLibrary, make_variation

    out = {}
    soft_rim = variations.soft_rim
    for size in sizes:
        for name, srcs in libraries(size).items():
            lib = TreeLibrary(size=size)
            for i, img in enumerate(srcs):
                lib.add(img, f"{name}{i}")
            src_soft = np.mean([soft_share(e.normalized.soft_alpha if e.normalized.soft_alpha is not None
                                           else e.image[..., 3], e.image[..., 3] >= 0.5) for e in lib.exemplars])
            widths = [exemplar_rim_width(e) for e in lib.exemplars]
            rows = []
            for seed in range(seeds):
                variations.soft_rim = lambda img, *a, **k: img
                try:
                    v0 = make_variation(lib, rng=seed)
                finally:
                    variations.soft_rim = soft_rim
                v1 = make_variation(lib, rng=seed)
                a0, a1 = v0.image[..., 3], v1.image[..., 3]
                op = a0 >= 0.5
                cov = contour_coverage(v1.resampled, op.shape)
                same = bool((op == (a1 >= 0.5)).all()) and (
                    crossfade_fraction(v0.image, srcs) == crossfade_fraction(v1.image, srcs))
                rows.append((soft_share(a0, op), soft_share(a1, op), staircase(a0, op, cov),
                             staircase(a1, op, cov), fringe(v1.image), same,
                             crossfade_fraction(v0.image, srcs), crossfade_fraction(v1.image, srcs)))
            r = np.array(rows, float)
            print(f"{size:4d} {name:11s} W {' '.join(f'{w:.2f}' for w in widths)} | soft {src_soft:.2f} | "
                  f"{r[:, 0].mean():.2f} -> {r[:, 1].mean():.2f} | stair {r[:, 2].mean():.3f} -> {r[:, 3].mean():.3f}"
                  f" | fringe {r[np.argmax(np.abs(r[:, 4])), 4]:+.4f} | same {int(r[:, 5].sum())}/{len(r)}"
                  f" | crossfade {' '.join(f'{a:.4f}>{b:.4f}' for a, b in r[:, 6:8])}", flush=True)
            out[(size, name)] = r
    return out


if __name__ == "__main__":
    measure(tuple(int(s) for s in sys.argv[1].split(",")) if len(sys.argv) > 1 else (96, 128, 256, 512),
            int(sys.argv[2]) if len(sys.argv) > 2 else 3)
