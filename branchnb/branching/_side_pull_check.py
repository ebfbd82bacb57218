"""Issue-23 figures on how far sampled roots start from the example's roots on the same side (branching124).

``python -m branchnb.branching._side_pull_check [SEEDS]`` fits :class:`.roots.RootModel` to procedural
examples (400 px, straight 100-200 px root branches) whose roots enter from known places and samples
starts in 256, 512 and 768 px frames (seeds 0-5 by default, three examples per kind). Per kind it prints
the distance of each output root from the nearest example root on the same image side, as a share of
that side's length (1 for a root on a side the example does not use): mean, 90th percentile, max and
the share above 0.25. Kinds: ``frost`` (two roots 0.3 apart on the bottom, two 0.05 apart near the
bottom of the left side), ``crack`` (three on the upper left side), ``coast`` (three on the right part
of the bottom), ``winter`` (two on the bottom, one on top), ``spread`` (three over the whole top).
Needs no extraction or synthesis: the figures are the sampler's alone.
"""
# ruff: noqa: E501, E702
from __future__ import annotations

import sys

import numpy as np

from branchnb.branching.roots import fit_roots
from branchnb.core.structure import Branch, Structure

KINDS = ("frost", "crack", "coast", "winter", "spread")
_NORMAL = {"top": np.pi / 2, "bottom": -np.pi / 2, "left": 0.0, "right": np.pi}


def _entries(kind: str, rng) -> list[tuple[str, float]]:
    c = rng.uniform(0.3, 0.7)
    if kind == "frost":
        return [("bottom", c - 0.15), ("bottom", c + 0.15), ("left", 0.72), ("left", 0.77)]
    if kind == "crack":
        return [("left", c - 0.1), ("left", c - 0.02), ("left", c + 0.07)]
    if kind == "coast":
        return [("bottom", c + 0.05), ("bottom", c + 0.15), ("bottom", c + 0.25)]
    if kind == "winter":
        return [("bottom", rng.uniform(0.15, 0.3)), ("bottom", rng.uniform(0.4, 0.5)), ("top", 0.8)]
    return [("top", 0.1), ("top", 0.5), ("top", 0.9)]


def example_roots(kind: str, seed: int, size: int = 400):
    """The :class:`.roots.RootModel` of a procedural example of ``kind``."""
    rng = np.random.default_rng(seed); br = []
    for side, f in _entries(kind, rng):
        x, y = {"top": (f * size, 0.5), "bottom": (f * size, size - 1.5), "left": (0.5, f * size), "right": (size - 1.5, f * size)}[side]
        a = _NORMAL[side] + rng.normal(0, 0.3); L = rng.uniform(100, 200)
        br.append(Branch([(x, y), (x + L * np.cos(a) / 2, y + L * np.sin(a) / 2), (x + L * np.cos(a), y + L * np.sin(a))], 2.0))
    return fit_roots(Structure(br, image_shape=(size, size)))


def side_offsets(rm, size: int, seed: int) -> list[float]:
    """Per sampled root in a ``size`` square: distance along its side to the nearest example root there."""
    out = []
    for x, y, _a in rm.sample(np.ones((size, size), bool), seed):
        k = int(np.argmin([y, size - 1 - y, x, size - 1 - x]))
        along = rm.positions[rm.sides == k, 0 if k < 2 else 1]
        out.append(float(np.min(np.abs(along - (x if k < 2 else y) / size))) if len(along) else 1.0)
    return out


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    seeds = [int(s) for s in argv[0].split(",")] if argv else list(range(6))
    for kind in KINDS:
        ds = np.array([d for m in range(3) for size in (256, 512, 768) for s in seeds
                       for d in side_offsets(example_roots(kind, m), size, s)])
        print(f"{kind:7s} mean {ds.mean():.3f} p90 {np.percentile(ds, 90):.3f} max {ds.max():.3f} share>0.25 {np.mean(ds > 0.25):.3f}")


if __name__ == "__main__":
    main()
