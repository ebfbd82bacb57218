"""Outline width round flat-art mixes (issue 24), not run by the tests.

``python -m branchnb.trees._measure_outline [size] [seeds]`` (defaults 256, 6): for four
libraries of three outlined trees (two of procedural drawn trees, three clip-art and three RPG
samples), ``seeds`` random mixes each; prints the q10/q50/q90 of the silhouette outline's
thickness (:func:`~branchnb.trees.quality.outline_width_spread`) of the sources and the mixes,
and the mixes' cross-fade share.
"""

from __future__ import annotations

import sys

import numpy as np

SETS = {
    "clip": ("cartoon_tree", "tree_with_fruits", "evergreen"),
    "rpg": ("tree_rpg_05", "tree_rpg_06", "tree_rpg_13"),
    "drawnA": (("broadleaf", 10), ("fruit", 13), ("conifer", 12)),
    "drawnB": (("palm", 21), ("broadleaf", 22), ("fruit", 23)),
}


def measure(size: int = 256, seeds: int = 6) -> dict:
    from .. import data
    from .drawn import drawn_tree
    from .quality import crossfade_fraction, outline_width_spread
    from .variations import TreeLibrary, make_variation

    out = {}
    for name, spec in SETS.items():
        lib = TreeLibrary(size=size)
        for s in spec:
            if isinstance(s, str):
                lib.add(data.load(s), s)
            else:
                lib.add(drawn_tree(s[0], rng=s[1], size=2 * size), f"{s[0]}{s[1]}")
        src = [outline_width_spread(e.image) for e in lib.exemplars]
        mixes = []
        for seed in range(seeds):
            v = make_variation(lib, rng=seed)
            q = outline_width_spread(v.image)
            cf = crossfade_fraction(v.image, [e.image for e in lib.exemplars])
            mixes.append((q, cf))
        r = [q[2] / q[0] for q, _ in mixes]
        print(f"{name:7s} sources q90/q10 " + " ".join(f"{q[2] / q[0]:.2f}" for q in src)
              + f" | mixes mean {np.mean(r):.2f} max {max(r):.2f} | cross-fade max "
              f"{max(cf for _, cf in mixes):.4f}", flush=True)
        out[name] = (src, mixes)
    return out


if __name__ == "__main__":
    measure(int(sys.argv[1]) if len(sys.argv) > 1 else 256, int(sys.argv[2]) if len(sys.argv) > 2 else 6)
