"""Continuity of the induced veins on the real grass photos (issue 22: staircases instead of parallel lines).

Run ``python -m branchnb.leaves._measure_grass [--size 400] [--training 0,1] [--no-parallel] [--save DIR]``.
Strips 01-05 of ``/work/shared/data/leaves_photo_grass`` at ``size`` px (long side); the training
strip's own pale veins (a bright-ridge filter, its top 12 % inside the blade, pieces at least 0.15 of
the strip long) are the user's layer. Per exemplar: the induced skeleton cut at junctions and where it
turns more than 20 degrees from the strip's axis (the blade's local direction); ``run`` is the
length-weighted mean run over the strip's length, ``cross`` the share of the skeleton off the strip's
direction (rungs, zig-zags). ``--no-parallel``: without :mod:`branchnb.leaves.snapping_parallel`.
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy import ndimage as ndi

FOLDER = "/work/shared/data/leaves_photo_grass"


def _load(k: int, size: int) -> np.ndarray:
    from PIL import Image
    im = Image.open(f"{FOLDER}/leaf_strip_0{k}.jpg").convert("RGB")
    s = size / max(im.size)
    return np.asarray(im.resize((round(im.width * s), round(im.height * s)), Image.LANCZOS), np.float32) / 255


def _strip_length(blade) -> float:
    ys, xs = np.nonzero(blade)
    return float(4 * np.sqrt(np.linalg.eigvalsh(np.cov(np.vstack([xs, ys])))[-1]))


def own_veins(img) -> np.ndarray:
    """A grass strip's own pale veins: bright ridges (top 12 % inside the blade), pieces >= 0.15 strip length."""
    from skimage.filters import sato
    from skimage.morphology import skeletonize

    from .exemplar import leaf_exemplar
    b = leaf_exemplar(img).blade
    r = sato(img[..., :3].mean(-1), sigmas=[1.0], black_ridges=False)
    inner = ndi.binary_erosion(b, iterations=4)
    m = (r > np.percentile(r[inner], 88)) & inner
    lab, n = ndi.label(m, structure=np.ones((3, 3)))
    lens = np.bincount(lab[skeletonize(m)], minlength=n + 1)
    keep = lens >= 0.15 * _strip_length(b)
    keep[0] = False
    return keep[lab]


def _blade_axis(blade) -> np.ndarray:
    import cv2
    d = ndi.distance_transform_edt(blade).astype(np.float32)
    gy, gx = np.gradient(cv2.GaussianBlur(d, (0, 0), 1.5))
    s = max(3.0, 0.5 * float(d.max()))
    jxx, jyy, jxy = (cv2.GaussianBlur(v, (0, 0), s) for v in (gx * gx, gy * gy, gx * gy))
    th = 0.5 * np.arctan2(2 * jxy, jxx - jyy)
    return np.stack([-np.sin(th), np.cos(th)], -1)


def continuity(mask, blade) -> dict:
    """``run`` and ``cross`` of the module docstring for one induced mask."""
    from skimage.morphology import skeletonize

    from .snapping_parallel import _path_tangents
    length = _strip_length(blade)
    sk = skeletonize(mask & blade)
    tot = int(sk.sum())
    if tot == 0:
        return dict(run=0.0, cross=0.0)
    cos = np.abs((_path_tangents(sk) * _blade_axis(blade)).sum(-1))
    nb = ndi.convolve(sk.astype(int), np.ones((3, 3), int), mode="constant") - 1
    along = sk & (cos >= np.cos(np.radians(20))) & (nb <= 2)
    lab, n = ndi.label(along, structure=np.ones((3, 3)))
    runs = np.bincount(lab[along], minlength=n + 1)[1:].astype(float)
    return dict(run=float((runs ** 2).sum() / max(runs.sum(), 1) / length),
                cross=float(1 - (sk & (cos >= np.cos(np.radians(20)))).sum() / tot))


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m branchnb.leaves._measure_grass", description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=400)
    ap.add_argument("--training", default="0,1", help="training strips (0 = strip 01)")
    ap.add_argument("--no-parallel", action="store_true")
    ap.add_argument("--save", default=None, help="folder for a PNG of the induced layers per training strip")
    args = ap.parse_args(argv)
    from . import snapping
    from .analysis import analyze
    if args.no_parallel:
        snapping.is_parallel_layer = lambda *a, **k: False
    leaves = [_load(k, args.size) for k in range(1, 6)]
    for t in (int(x) for x in args.training.split(",")):
        a = analyze(leaves, t, {"veins": own_veins(leaves[t])})
        layer = a.layer("veins")
        rows = [continuity(layer.masks[e], a.blades[e]) for e in range(len(leaves)) if e != t]
        print(f"training strip {t + 1:02d}: run " + " ".join(f"{r['run']:.2f}" for r in rows)
              + f"  mean {np.mean([r['run'] for r in rows]):.2f} least {min(r['run'] for r in rows):.2f}"
              + f"  cross mean {np.mean([r['cross'] for r in rows]):.2f}")
        if args.save:
            from ..core.io import encode_png
            tiles = []
            for e in range(len(leaves)):
                im = np.asarray(a.exemplars[e], np.float32)[..., :3]
                ys, xs = np.nonzero(a.blades[e])
                sl = (slice(ys.min(), ys.max() + 1), slice(xs.min(), xs.max() + 1))
                ov = im.copy()
                ov[layer.masks[e]] = (1, 0, 1)
                tile = np.hstack([im[sl], ov[sl]])
                tiles.append(np.rot90(tile) if tile.shape[0] > tile.shape[1] else tile)
            w = max(x.shape[1] for x in tiles)
            img = np.vstack([np.pad(x, ((0, 6), (0, w - x.shape[1]), (0, 0)), constant_values=1) for x in tiles])
            with open(f"{args.save}/grass_training_{t + 1:02d}.png", "wb") as f:
                f.write(encode_png(np.clip(img, 0, 1)))


if __name__ == "__main__":
    main()
