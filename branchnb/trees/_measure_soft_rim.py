"""Anti-aliased rims of tree mixes (issue 24, :mod:`~branchnb.trees.rim_alpha`), not run by the tests.

``python -m branchnb.trees._measure_soft_rim [sizes] [seeds]`` (defaults ``96,128,256,512`` and 3):
libraries of smooth blob trees (:mod:`~branchnb.trees._measure_rim`, flat and watercolour fills),
drawn trees (:func:`~branchnb.trees.drawn.drawn_tree`), synthetic trees
(:func:`~branchnb.trees.synthetic.synthetic_tree`) and sample clip art / pixel art; ``seeds``
random mixes each, with and without the soft rim. Per library it prints

* ``soft``: share of the rim pixels (either side of the opaque set's edge) with 0.02 < alpha < 0.98,
  sources' (their soft alpha) | mixes without | with the soft rim;
* ``stair``: the staircase against a known answer: each source's binary working silhouette given
  the soft rim (:func:`~branchnb.trees.rim_alpha.soft_rim` with its own ramp) against its own
  soft alpha, mean |difference| on the rim, binary -> soft rim (the mixed contour polygon is no
  such answer: it runs through the border pixel centres of binary silhouettes, and the sources'
  own soft alpha scored worse on it than their binary cut);
* ``fringe``: worst mean luminance step of the rim's composite over white and over black against
  ``alpha x colour of the nearest opaque pixel + (1 - alpha) x backdrop`` (negative: darker), and
  the same had the soft pixels outside kept their colour (black, a dark fringe);
* ``opaque same``: mixes whose opaque set is identical with and without; ``crossfade``:
  :func:`~branchnb.trees.quality.crossfade_fraction` of each mix without > with.
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


def soft_share(alpha, op) -> float:
    b = _band(op)
    a = np.asarray(alpha)[b]
    return float(((a > 0.02) & (a < 0.98)).mean()) if b.any() else 0.0


def staircase(exemplar) -> tuple[float, float]:
    """Mean |alpha - soft alpha| on an exemplar's rim: binary cut, soft rim (hard sources: both
    the binary cut)."""
    from .rim_alpha import exemplar_rim_width, soft_rim

    op = exemplar.image[..., 3] >= 0.5
    sa = exemplar.normalized.soft_alpha
    if sa is None:
        return 0.0, 0.0
    b = _band(op)
    soft = soft_rim(exemplar.image, [exemplar_rim_width(exemplar)])[..., 3]
    return float(np.abs(op[b] - sa[b]).mean()), float(np.abs(soft[b] - sa[b]).mean())


def fringe(image, keep=None) -> float:
    """Worst mean luminance step over white / black of the soft rim against its nearest opaque
    colour; ``keep``: RGB the soft pixels outside had before (their colour left as it was)."""
    a = image[..., 3]
    op = a >= 0.5
    soft = (a > 0.02) & (a < 0.98)
    if not soft.any():
        return 0.0
    iy, ix = ndi.distance_transform_edt(~op, return_distances=False, return_indices=True)
    ref = image[..., :3][iy, ix]
    rgb = image[..., :3] if keep is None else np.where(op[..., None], image[..., :3], keep)
    worst = 0.0
    for bg in (1.0, 0.0):
        got = (rgb * a[..., None] + bg * (1 - a[..., None]))[soft] @ LUMA
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
                same = bool((op == (a1 >= 0.5)).all())
                rows.append((soft_share(a0, op), soft_share(a1, op), fringe(v1.image),
                             fringe(v1.image, v0.image[..., :3]), same,
                             crossfade_fraction(v0.image, srcs), crossfade_fraction(v1.image, srcs)))
            r = np.array(rows, float)
            st = np.array([staircase(e) for e in lib.exemplars]).mean(axis=0)
            print(f"{size:4d} {name:10s} W {' '.join(f'{w:.2f}' for w in widths)} | soft {src_soft:.2f} | "
                  f"{r[:, 0].mean():.2f} -> {r[:, 1].mean():.2f} | stair {st[0]:.3f} -> {st[1]:.3f}"
                  f" | fringe {r[np.argmax(np.abs(r[:, 2])), 2]:+.4f} (kept {r[np.argmax(np.abs(r[:, 3])), 3]:+.3f})"
                  f" | opaque same {int(r[:, 4].sum())}/{len(r)}"
                  f" | crossfade {' '.join(f'{a:.4f}>{b:.4f}' for a, b in r[:, 5:7])}", flush=True)
            out[(size, name)] = r
    return out


if __name__ == "__main__":
    measure(tuple(int(s) for s in sys.argv[1].split(",")) if len(sys.argv) > 1 else (96, 128, 256, 512),
            int(sys.argv[2]) if len(sys.argv) > 2 else 3)
