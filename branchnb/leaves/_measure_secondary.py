"""Secondary veins on every exemplar, each leaf of a family as the training leaf (issue 22, leaves89).

``python -m branchnb.leaves._measure_secondary [--kinds lobed,trilobed,elliptic,fan] [--sizes 192,256,400]
[--seeds 0,1,2] [--mode 0|1|2]`` builds ``leaf_family(3, size, kind, rng=seed)``, scribbles each leaf in turn
as a user would (:func:`~branchnb.leaves.layers_scribbles.simulate_scribbles`: 10 vein strokes of 0.06
and 10 spot strokes of 0.025 of the canvas), runs :func:`~branchnb.leaves.analysis.analyze` and prints
one JSON row per (kind, size, seed, training leaf): the vein and spot IoU of every exemplar's induced
layer with its truth (the training leaf's entry: its grown layer), then a summary per kind and size.
``--mode 0``: without an exemplar's own ``delta`` at its ridge pixels, ``1``: with it and the whole mask
trimmed by contrast (:data:`branchnb.leaves.analysis_masks._RIDGE_DELTA`; default 2).
"""

from __future__ import annotations

import argparse
import json
import warnings

import numpy as np


def secondary_row(kind: str, size: int, seed: int, t: int, n: int = 3) -> dict:
    """Vein and spot IoU of every exemplar (the training leaf ``t``'s grown layer among them)."""
    from ..core.metrics import iou
    from ._measure_unseen import _on_canvas
    from .analysis import analyze
    from .layers import Layer, LayerSet, simulate_scribbles
    from .procedural import leaf_family

    fam = leaf_family(n, size=size, kind=kind, rng=seed)
    ls = LayerSet([Layer("veins", "#d62728", 0, simulate_scribbles(fam[t].layers["veins"], 10,
                                                                   length=0.06 * size, rng=0)),
                   Layer("spots", "#1f77b4", 1, simulate_scribbles(fam[t].layers["spots"], 10,
                                                                   length=0.025 * size, rng=0))])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = analyze(fam, t, ls)
    shape = a.blades[0].shape
    out = dict(kind=kind, size=size, seed=seed, t=t, veins=[], spots=[])
    for e in range(n):
        for name in ("veins", "spots"):
            truth = _on_canvas(fam[e].layers[name], a.offsets[e], shape, a.mirrored[e])
            out[name].append(iou(a.layer(name).masks[e], truth))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m branchnb.leaves._measure_secondary",
                                 description=__doc__.split("\n")[0])
    ap.add_argument("--kinds", default="lobed,trilobed,elliptic,fan")
    ap.add_argument("--sizes", default="192,256,400")
    ap.add_argument("--seeds", default="0,1,2")
    ap.add_argument("--mode", type=int, default=2, choices=(0, 1, 2),
                    help="0: without the exemplars' own delta at their ridges (before); 1: whole mask trimmed")
    args = ap.parse_args(argv)
    from . import analysis_masks
    analysis_masks._RIDGE_DELTA = args.mode
    rows = []
    for seed in (int(s) for s in args.seeds.split(",")):
        for size in (int(s) for s in args.sizes.split(",")):
            for kind in args.kinds.split(","):
                for t in range(3):
                    rows.append(secondary_row(kind, size, seed, t))
                    print(json.dumps(rows[-1]), flush=True)
    for key in sorted({(r["kind"], r["size"]) for r in rows}):
        rs = [r for r in rows if (r["kind"], r["size"]) == key]
        ex = np.array([v for r in rs for e, v in enumerate(r["veins"]) if e != r["t"]])
        grown = np.array([r["veins"][r["t"]] for r in rs])
        spots = np.array([v for r in rs for v in r["spots"]])
        print(f"{key[0]:<9} {key[1]:>4}  exemplar veins mean {ex.mean():.3f} min {ex.min():.3f} under 0.7 "
              f"{int((ex < 0.7).sum())}/{ex.size}  grown mean {grown.mean():.3f} min {grown.min():.3f}  "
              f"spots mean {spots.mean():.3f} min {spots.min():.3f}")


if __name__ == "__main__":
    main()
