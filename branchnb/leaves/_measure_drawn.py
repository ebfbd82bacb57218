"""Drawn leaves' ink outline is no vein: induced vein precision / recall on clip art with known veins (issue 22).

``python -m branchnb.leaves._measure_drawn [--shapes maple,oak,elm,palmate] [--styles none,black,colour]
[--outlines 1,2,4] [--shadows 1,0] [--sizes 200,512,1000] [--seeds 0] [--layer auto|mask|scribbles]
[--cycle] [--save DIR]`` draws four leaves per case with
:func:`branchnb.leaves._clipart_kinds.clip_leaf` (flat fill, an ink outline
``outline_px`` wide, drawn veins of style ``black``/``colour``/``pale`` or
none at all (``none``: plain fill), with or without the grey drop shadow),
gives the training leaf (the first) a vein layer, runs ``leaf_exemplar``
-> ``analyze`` and prints, over the three other exemplars:

* ``prec``: share of the induced vein pixels within 1 px of the true veins
  (mean); on plain fill the true veins are where the drawing has none, so
  only ``outline`` is read there;
* ``rec``: share of the true vein pixels within 1 px of the induced ones (mean);
* ``outline``: share of the outline zone (the lamina within ``outline_px``
  + 2 px of its edge, off the true veins) taken as vein (max): the ink
  outline induced as vein.

The layer (``--layer auto``): the true veins of the training leaf as a
mask on plain fill (notebook 04's last figure), else a user's scribbles
grown by lazy snapping (:func:`branchnb.leaves._measure_unseen.user_scribbles`).
``--cycle``: each case at one of the sizes in turn (fewer rows, every size).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy import ndimage as ndi


def _zone(blade, outline_px, size):
    """The lamina (petiole opened away) within ``outline_px + 2`` px of its edge."""
    import cv2
    r = max(3, int(round(0.012 * size)))
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    lam = cv2.morphologyEx(blade.astype(np.uint8), cv2.MORPH_OPEN, disk).astype(bool)
    return lam & (ndi.distance_transform_edt(lam) <= outline_px + 2)


def run(shape: str, style: str, outline_px: int, shadow: bool, size: int, seed: int, layer: str = "auto",
        save: str | None = None, n: int = 4) -> dict:
    """One row: mean precision and recall of the induced veins, max outline share (see the module docstring)."""
    import warnings

    from ._clipart_kinds import clip_leaf
    from ._measure_unseen import _on_canvas, user_scribbles
    from .analysis import analyze
    from .exemplar import leaf_exemplar

    vein_px = 1.0 + (seed % 3) if size < 700 else 2.0 + (seed % 2)
    leaves = [clip_leaf(shape, size, 10 * seed + k, vein_px, style, outline_px=outline_px, shadow=shadow)
              for k in range(n)]
    ex = [leaf_exemplar(x.image) for x in leaves]
    if layer == "auto":
        layer = "mask" if style == "none" else "scribbles"
    user = {"veins": leaves[0].veins} if layer == "mask" else user_scribbles(leaves[0], rng=seed)
    t0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = analyze(ex, 0, user)
    t_an = time.process_time() - t0
    shape_c = a.blades[0].shape
    L = a.layer("veins")
    prec, rec, outl = [], [], []
    tiles = []
    for e in range(1, n):
        truth = _on_canvas(leaves[e].veins, a.offsets[e], shape_c, a.mirrored[e])
        blade = _on_canvas(leaves[e].blade, a.offsets[e], shape_c, a.mirrored[e])
        m = L.masks[e]
        near_t = ndi.binary_dilation(truth, iterations=1)
        zone = _zone(blade, outline_px, size) & ~near_t
        prec.append(float((m & near_t).sum() / max(m.sum(), 1)))
        rec.append(float((truth & ndi.binary_dilation(m, iterations=1)).sum() / max(truth.sum(), 1)))
        outl.append(float((m & zone).sum() / max(zone.sum(), 1)))
        if save:
            img = a.exemplars[e]
            rgb = (img[..., :3] * img[..., 3:] + (1 - img[..., 3:])).copy()
            rgb[m] = 0.35 * rgb[m] + 0.65 * np.array((0.95, 0.1, 0.1))
            tiles.append(np.pad(rgb, ((0, 0), (0, 4), (0, 0)), constant_values=1))
    name = f"{shape}-{style}-o{outline_px}{'-sh' if shadow else ''}_{size}_{seed}"
    if save:
        from ..core.io import encode_png
        with open(f"{save}/{name}.png", "wb") as f:
            f.write(encode_png(np.hstack(tiles)))
    return dict(name=name, layer=layer, prec=float(np.mean(prec)), rec=float(np.mean(rec)),
                outline=float(np.max(outl)), t_an=t_an)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m branchnb.leaves._measure_drawn", description=__doc__.split("\n")[0])
    ap.add_argument("--shapes", default="maple,oak,elm,palmate")
    ap.add_argument("--styles", default="none,black,colour")
    ap.add_argument("--outlines", default="1,2,4")
    ap.add_argument("--shadows", default="1,0")
    ap.add_argument("--sizes", default="200,512,1000")
    ap.add_argument("--seeds", default="0")
    ap.add_argument("--layer", default="auto", choices=("auto", "mask", "scribbles"))
    ap.add_argument("--save", default=None)
    ap.add_argument("--cycle", action="store_true", help="one size per case, in turn")
    args = ap.parse_args(argv)
    rows = []
    sizes = [int(v) for v in args.sizes.split(",")]
    case = 0
    for shape in args.shapes.split(","):
        for style in args.styles.split(","):
            for o in (int(v) for v in args.outlines.split(",")):
                for sh in (bool(int(v)) for v in args.shadows.split(",")):
                    case += 1
                    for size in ([sizes[case % len(sizes)]] if args.cycle else sizes):
                        for seed in (int(v) for v in args.seeds.split(",")):
                            r = run(shape, style, o, sh, size, seed, args.layer, args.save)
                            rows.append(r)
                            print(f"{r['name']:<32} {r['layer']:<9} prec {r['prec']:.3f}  rec {r['rec']:.3f}  "
                                  f"outline {r['outline']:.3f}  analysis {r['t_an']:.1f} s", flush=True)
    for style in args.styles.split(","):
        sub = [r for r in rows if f"-{style}-" in r["name"]]
        if sub:
            print(f"{style:<8} mean prec {np.mean([r['prec'] for r in sub]):.3f}  min "
                  f"{np.min([r['prec'] for r in sub]):.3f}  mean rec {np.mean([r['rec'] for r in sub]):.3f}  min "
                  f"{np.min([r['rec'] for r in sub]):.3f}  outline mean {np.mean([r['outline'] for r in sub]):.3f} "
                  f"max {np.max([r['outline'] for r in sub]):.3f}", flush=True)


if __name__ == "__main__":
    main()
