"""Measure: how far a lightning bolt's side branches wander from where they fork.

``python -m branchnb.dendrite._side_spread [sizes] [names]`` stylizes photos without
lightning (and the NOAA photo) with ``metaphor="lightning"`` and the defaults, and prints
per picture the share of the side branches' length outside the cone of ``CONE`` degrees
about straight down from each side branch's fork on the main channel (above the fork or
sideways past the cone: a bolt's branches fork downwards, as in the papers' lightning
figures and in the procedural storms of :mod:`~branchnb.branching._storm_examples`,
whose side branches leave at 29-52 degrees off the vertical), the side branches'
mean lateral reach (px from the fork, share of the diagonal), and the median and largest
length of a side branch (fork to farthest tip) as a share of the main channel's length
(the storms' 0.19-0.37). Not a test.
"""

from __future__ import annotations

import sys

import numpy as np

CONE = 60.0


def fork_of(parent: np.ndarray, main: np.ndarray) -> np.ndarray:
    """Per node, its nearest ancestor on the main channel (itself when on it; -1 if none)."""
    fork = np.where(main, np.arange(len(parent)), -1)
    for _ in range(len(parent)):
        todo = (fork < 0) & (parent >= 0)
        if not todo.any():
            break
        new = np.where(todo, fork[np.maximum(parent, 0)], fork)
        if np.array_equal(new, fork):
            break
        fork = new
    return fork


def side_spread(d, cone: float = CONE) -> tuple[float, float]:
    """(share of side-branch length outside the cone, mean lateral reach / diagonal)."""
    from .main_channel import main_path

    main = np.zeros(d.n_nodes, bool)
    main[main_path(d)] = True
    fork = fork_of(d.parent, main)
    side = ~main & (d.parent >= 0) & (fork >= 0)
    i = np.flatnonzero(side)
    p, q = d.points[i], d.points[d.parent[i]]
    seg = np.hypot(*(p - q).T)
    rel = 0.5 * (p + q) - d.points[fork[i]]
    ang = np.degrees(np.arctan2(np.abs(rel[:, 0]), rel[:, 1]))  # 0 = straight down
    out = (ang > cone) & (np.hypot(*rel.T) > 2.0)
    diag = float(np.hypot(*d.shape))
    if seg.sum() == 0:
        return 0.0, 0.0
    return float(seg[out].sum() / seg.sum()), float(np.average(np.abs(rel[:, 0]), weights=seg) / diag)


def side_lengths(d) -> np.ndarray:
    """Per fork on the main channel, its side branches' longest path (px) over the channel's length."""
    from .main_channel import main_path

    path = main_path(d)
    main = np.zeros(d.n_nodes, bool)
    main[path] = True
    fork = fork_of(d.parent, main)
    side = ~main & (d.parent >= 0) & (fork >= 0)
    seg = np.zeros(d.n_nodes)
    i = np.flatnonzero(d.parent >= 0)
    seg[i] = np.hypot(*(d.points[i] - d.points[d.parent[i]]).T)
    dist = np.zeros(d.n_nodes)
    for _ in range(d.n_nodes):
        new = np.where(side, dist[np.maximum(d.parent, 0)] + seg, 0.0)
        if np.array_equal(new, dist):
            break
        dist = new
    if not side.any():
        return np.zeros(0)
    longest = np.zeros(d.n_nodes)
    np.maximum.at(longest, fork[side], dist[side])
    return longest[np.unique(fork[side])] / max(float(seg[path[1:]].sum()), 1.0)


def main(argv=None) -> None:
    from . import stylize
    from ._strike_sweep import fit, load

    argv = list(argv or [])
    sizes = [int(v) for v in argv[0].split(",")] if argv else [320, 640]
    names = argv[1].split(",") if len(argv) > 1 else ["rocket", "text", "clock", "coffee", "chelsea",
                                                       "astronaut", "camera", "cracked_mud",
                                                       "lightning_noaa"]
    for name in names:
        big = load(name)
        row = []
        for n in sizes:
            d = stylize(fit(big, n), rng=0, metaphor="lightning").dendrite
            out, reach = side_spread(d)
            v = side_lengths(d)
            row.append(f"{n}: out {out:.2f} reach {reach:.3f} length {np.median(v) if len(v) else 0:.2f}"
                       f"/{v.max(initial=0):.2f}")
        print(f"{name:14s} " + " | ".join(row), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
