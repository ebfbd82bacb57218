"""Bolt extraction on procedural night storms, without and with the false-ridge test (issue 23).

``python -m branchnb.branching._storm_check [n_seeds]`` prints, per storm kind and seed, the
precision and recall of the traced structure against the known bolts (4 px), with
``false_ridges=False`` (before) and the default (after), then the means.
"""

from __future__ import annotations

import sys

import numpy as np

KINDS = {"full": {}, "nodots": {"dots": False}, "nocloud": {"cloud": False},
         "big": {"shape": (384, 512)}, "two": {"n_bolts": 2}}


def main(n_seeds: int = 3) -> None:
    from ._storm_examples import bolt_scores, storm_example
    from .extraction import extract_structure

    tot = {False: [], True: []}
    for kind, kw in KINDS.items():
        for seed in range(n_seeds):
            img, bolts = storm_example(seed=seed, **kw)
            row = []
            for ff in (False, True):
                p, r = bolt_scores(extract_structure(img, false_ridges=ff), bolts, img.shape[:2])
                tot[ff].append((p, r))
                row.append(f"P {p:.2f} R {r:.2f}")
            print(f"{kind:8s} seed {seed}: before {row[0]}  after {row[1]}", flush=True)
    for ff in (False, True):
        a = np.array(tot[ff])
        print(f"{'after ' if ff else 'before'} mean precision {a[:, 0].mean():.3f} (min {a[:, 0].min():.2f}) "
              f"recall {a[:, 1].mean():.3f} (min {a[:, 1].min():.2f})")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
