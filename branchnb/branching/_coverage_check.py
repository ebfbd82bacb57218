"""Coverage of default synthesis against the example's, per example kind and seed (issue 10).

``python -m branchnb.branching._coverage_check [kinds] [n_seeds]`` prints, for every kind, the
ratio (fraction of the domain within ``rho`` of a synthesized branch) / (the example's) for seeds
0 .. n_seeds - 1, with the default parameters. Kinds: retina and lightning (extracted from the
sample images), river (procedural river map, land domain), delta (binary delta mask, extracted),
crack (procedural crack pattern, extracted), sparse and dense (procedural trees, known structure).
"""

from __future__ import annotations

import sys
import time

import numpy as np

__all__ = ["KINDS", "coverage_ratios"]


def _kinds():
    from .. import data
    from ._image_examples import random_tree
    from ._map_examples import crack_pattern_example, delta_mask_example, river_map_example
    from .extraction import extract_structure

    def river():
        _img, s, land = river_map_example((320, 320), 1)
        return s, land

    def delta():
        m, _ch, sea = delta_mask_example((256, 256), 1)
        return extract_structure(m), ~sea

    return {
        "retina": lambda: (extract_structure(data.load("retina_fundus"), scale=0.5), None),
        "lightning": lambda: (extract_structure(data.load("lightning_trace"), scale=0.5, root="top"), None),
        "river": river,
        "delta": delta,
        "crack": lambda: (extract_structure(crack_pattern_example((256, 256), 2)), None),
        "sparse": lambda: (random_tree((256, 256), 3, n_children=2), None),
        "dense": lambda: (random_tree((256, 256), 4, n_children=5, grandchildren=3, r_root=3, r_child=2), None),
    }


KINDS = ("retina", "lightning", "river", "delta", "crack", "sparse", "dense")


def coverage_ratios(kind: str, seeds=range(10)) -> tuple[np.ndarray, list[dict]]:
    """Synthesized / example coverage for each seed, and each run's diagnostics."""
    from .colonization import coverage_fraction
    from .synthesis import fit_model, synthesize_structure

    s, dom = _kinds()[kind]()
    model = fit_model(s, domain=dom)
    target = coverage_fraction(model.example, s.image_shape, model.rho, model.domain)
    ratios, diags = [], []
    for seed in seeds:
        r = synthesize_structure(model, rng=seed)
        ratios.append(coverage_fraction(r.structure, s.image_shape, model.rho, model.domain) / target)
        diags.append(r.diagnostics)
    return np.array(ratios), diags


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    kinds = argv[0].split(",") if argv else KINDS
    n = int(argv[1]) if len(argv) > 1 else 10
    for kind in kinds:
        t0 = time.perf_counter()
        ratios, diags = coverage_ratios(kind, range(n))
        print(f"{kind:9s} seeds 0-{n - 1}: " + " ".join(f"{v:.2f}" for v in ratios)
              + f"   min {ratios.min():.2f} max {ratios.max():.2f}   "
              f"({(time.perf_counter() - t0) / n:.2f} s per synthesis)", flush=True)


if __name__ == "__main__":
    main()
