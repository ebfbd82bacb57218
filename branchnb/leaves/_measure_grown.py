"""Measure the training leaf's own grown vein layer (issue 22): procedural families, simulated scribbles.

``leaf_family`` leaves of four kinds at 128-400 px, seeds 0-5, training
leaf 0 and 2; twelve :func:`branchnb.leaves.layers.simulate_scribbles`
strokes of 6 % of the leaf on the true veins and twelve of 2.5 % on the
spots, grown by :func:`branchnb.leaves.layers.grow_layers` with the
defaults. Prints each case's vein IoU, precision and recall against the
truth and the spots' IoU, then mean and minimum::

    python -m branchnb.leaves._measure_grown [--kinds lobed,trilobed,elliptic,fan]
        [--sizes 128,192,256,400] [--seeds 0,1,2,3,4,5] [--training 0,2]
"""

from __future__ import annotations

import argparse

import numpy as np


def grown_row(kind: str, size: int, seed: int, training: int = 0) -> dict:
    """One case: the grown vein layer's IoU, precision and recall, the spots' IoU.

    Parameters
    ----------
    kind : str
        A :data:`branchnb.leaves.procedural.KINDS` family.
    size : int
        Canvas side (px).
    seed : int
        The family's seed.
    training : int
        Which leaf of the family is scribbled.

    Returns
    -------
    dict

    Examples
    --------
    >>> r = grown_row("lobed", 96, 0)
    >>> sorted(r)[:3]
    ['iou', 'kind', 'precision']
    """
    from ..core.metrics import iou
    from .layers import Layer, LayerSet, grow_layers, simulate_scribbles
    from .procedural import leaf_family

    leaf = leaf_family(training + 1, size=size, kind=kind, rng=seed)[training]
    ls = LayerSet([Layer("veins", "#d62728", 0, simulate_scribbles(leaf.layers["veins"], 12,
                                                                    length=0.06 * size, rng=0)),
                   Layer("spots", "#1f77b4", 1, simulate_scribbles(leaf.layers["spots"], 12,
                                                                   length=0.025 * size, rng=0))])
    r = grow_layers(leaf.image, leaf.blade, ls)
    v, truth = r.masks["veins"], leaf.layers["veins"] & leaf.blade
    both = float((v & truth).sum())
    return dict(kind=kind, size=size, seed=seed, training=training, iou=iou(v, truth),
                precision=both / max(1, v.sum()), recall=both / max(1, truth.sum()),
                spots=iou(r.masks["spots"], leaf.layers["spots"]))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(prog="python -m branchnb.leaves._measure_grown", description=__doc__.split("\n")[0])
    ap.add_argument("--kinds", default="lobed,trilobed,elliptic,fan")
    ap.add_argument("--sizes", default="128,192,256,400")
    ap.add_argument("--seeds", default="0,1,2,3,4,5")
    ap.add_argument("--training", default="0,2")
    args = ap.parse_args(argv)
    rows = []
    for t in (int(v) for v in args.training.split(",")):
        for kind in args.kinds.split(","):
            for size in (int(v) for v in args.sizes.split(",")):
                for seed in (int(v) for v in args.seeds.split(",")):
                    r = grown_row(kind, size, seed, t)
                    rows.append(r)
                    print(f"{kind:<9} {size:4d} seed {seed} leaf {t}  IoU {r['iou']:.3f}  prec {r['precision']:.3f}  "
                          f"rec {r['recall']:.3f}  spots {r['spots']:.3f}", flush=True)
    a = np.array([[r["iou"], r["precision"], r["recall"], r["spots"]] for r in rows])
    print("mean IoU {:.3f} prec {:.3f} rec {:.3f} spots {:.3f}".format(*a.mean(0)))
    print("min  IoU {:.3f} prec {:.3f} rec {:.3f} spots {:.3f}".format(*a.min(0)))


if __name__ == "__main__":
    main()
