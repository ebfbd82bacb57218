"""Measure: pareidolia twig ends that read as dark flecks.

``python -m branchnb.dendrite._twig_ends [size] [names]`` grows a pareidolia tree with the
defaults on each picture (long side ``size`` px, 600 by default) with the fork cap of
:func:`~branchnb.dendrite.pareidolia_widths._slim_twigs` off and on (``_FORK_CAP`` 0 / 1,
interleaved), and prints: the share of terminal twigs more than 0.5 px wider than the
branch at their fork (a dark fleck on a pale twig), the same in the crown's light parts
(picture darkness < 0.4 at the twig), and tone r inside the crown at 4 px blur. Not a
test.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage

NAMES = ("astronaut", "chelsea", "coffee", "camera", "rocket", "maple_leaf_01")


def fleck_shares(t) -> tuple[float, float]:
    """(share of terminal twigs > 0.5 px wider than their fork, the same in light parts)."""
    from ..core import as_gray

    d = t.dendrite
    dark = 1.0 - as_gray(t.image).astype(np.float64)
    bp = d.branch_parent
    n_child = np.bincount(bp[bp >= 0], minlength=len(bp))
    w = 2 * d.radius
    h, wd = dark.shape
    wide, light, n_light, n = 0, 0, 0, 0
    for b in np.flatnonzero((n_child == 0) & (bp >= 0)):
        br = d.branches[b]
        if len(br) < 3:
            continue
        n += 1
        is_wide = w[br[1:]].max() > w[br[0]] + 0.5
        wide += is_wide
        x, y = np.rint(d.points[br[len(br) // 2]]).astype(int)
        if dark[min(max(y, 0), h - 1), min(max(x, 0), wd - 1)] < 0.4:
            n_light += 1
            light += is_wide
    return wide / max(n, 1), light / max(n_light, 1)


def tone_r(t, sigma: float = 4.0) -> float:
    from ..core import as_gray

    m = t.crown_on_canvas()
    x = ndimage.gaussian_filter(1.0 - as_gray(t.image).astype(np.float64), sigma)[m]
    y = ndimage.gaussian_filter(1.0 - as_gray(t.render().image).astype(np.float64), sigma)[m]
    return float(np.corrcoef(x, y)[0, 1])


def main(argv=None) -> None:
    from . import pareidolia_widths as pw
    from ._strike_sweep import fit, load
    from .pareidolia import pareidolia_tree

    argv = list(argv or [])
    n = int(argv[0]) if argv else 600
    names = argv[1].split(",") if len(argv) > 1 else NAMES
    keep = pw._FORK_CAP
    try:
        for name in names:
            img = fit(load(name), n)
            row = []
            for cap in (0.0, keep):
                pw._FORK_CAP = cap
                t = pareidolia_tree(img, rng=0)
                a, b = fleck_shares(t)
                row.append(f"flecks {a:.3f} light {b:.3f} r {tone_r(t):.3f}")
            print(f"{name:14s} off: {row[0]}  ->  on: {row[1]}", flush=True)
    finally:
        pw._FORK_CAP = keep


if __name__ == "__main__":
    main(sys.argv[1:])
