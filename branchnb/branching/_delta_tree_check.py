"""Trunk bearing and fan balance on even binary deltas for issue 23 (branching79).

``python -m branchnb.branching._delta_tree_check N [OUT] [CACHE]`` fits the default workflow on the
:func:`._delta_examples.delta_tree_mask` deltas of :data:`CASES` (a trunk splitting evenly 2-4 times, 60-150
degree fans, 256-1024 px, trunk radius 2-6 px, the sea on each of the four sides; rooted at the trunk's entry,
see below), synthesizes seeds 0 .. N - 1 and prints per case the example's trunk bearing
(:func:`._delta_fan_check.trunk_bearing`) and balance, then over the seeds: the trunk bearing error against the
example's (mean, max), the side share (:func:`._delta_fan_check.side_share`), the mouth share
(:func:`._delta_fan_check.mouth_share`) and the channels reaching the sea; a last line the mean over the cases.
Sheets of the example and seeds 0-2 go to ``OUT_case.png``; fitted examples are cached in CACHE.

The examples are extracted with ``root=`` their trunk's entry: the automatic root took a mouth of 4 of these 8
masks (its ends' radii too even for :func:`.delta_source._delta_source_key`), and such an example does not
drain. (Since branching83 the automatic root takes the entry of all 8, :func:`.delta_source.fan_source`;
the explicit root keeps these figures comparable with the earlier ones.)
"""

from __future__ import annotations

import sys

import numpy as np

from ._check_table import cached
from ._delta_examples import delta_tree_mask
from ._delta_fan_check import bearing_error, mouth_share, n_to_sea, side_share, trunk_bearing, turned

#: (fan degrees, orders, trunk radius px, size px, sea side)
CASES = [(60, 2, 2.0, 256, "bottom"), (90, 2, 4.0, 512, "left"), (120, 3, 3.0, 512, "top"),
         (150, 2, 6.0, 512, "right"), (100, 3, 5.0, 1024, "bottom"), (75, 4, 3.0, 384, "left"),
         (140, 3, 2.5, 256, "top"), (110, 2, 4.0, 768, "right")]


def fitted(ci: int, cache: str | None = None):
    """(image, domain, model) of case ``ci`` of :data:`CASES` (mask seed ``10 + ci``)."""
    from . import example_domain, extract_structure, fit_model

    fan, orders, rad, size, side = CASES[ci]

    def make():
        m0, entry, _mouths, _head = delta_tree_mask((size, size), 10 + ci, fan, orders, rad)
        x, y = float(np.clip(entry[0], 0, size - 1)), float(np.clip(entry[1], 0, size - 1))
        # the entry (x, y) of the mask with its sea at the bottom, after turned()
        root = {"bottom": (x, y), "top": (x, size - 1 - y), "left": (size - 1 - y, x), "right": (y, x)}[side]
        img = np.dstack([turned(m0, side)] * 3)
        ex = extract_structure(img, root=root)
        dom = example_domain(img, ex)
        return img, dom, fit_model(ex, domain=dom)

    return cached(cache, f"tree_{fan}_{orders}_{rad}_{size}_{side}.pkl", make)


def run(seeds, out: str | None = None, cache: str | None = None) -> list[float]:
    """Print the figures of every case; returns the mean bearing error per case."""
    from . import synthesize_structure
    from ._seed_check import _sheet

    means = []
    for ci, (fan, orders, rad, size, side) in enumerate(CASES):
        img, dom, model = fitted(ci, cache)
        eb = trunk_bearing(model.example, dom)
        rows = []
        for sd in seeds:
            s = synthesize_structure(model, rng=sd).structure
            rows.append(dict(berr=bearing_error(trunk_bearing(s, dom), eb), side=side_share(s, dom),
                             mouth=mouth_share(s, dom), sea=n_to_sea(s, dom), struct=s))
        b = [r["berr"] for r in rows]
        means.append(float(np.mean(b)))
        print(f"fan {fan} orders {orders} r {rad} {size} {side}: example bearing {eb:.0f} side "
              f"{side_share(model.example, dom):.2f} mouths {mouth_share(model.example, dom):.2f} sea "
              f"{n_to_sea(model.example, dom)} | bearing err mean {np.mean(b):.1f} max {max(b):.1f} | side "
              + " ".join(f"{r['side']:.2f}" for r in rows)
              + f" | mouths mean {np.mean([r['mouth'] for r in rows]):.2f}: "
              + " ".join(f"{r['mouth']:.2f}" for r in rows) + " | sea " + " ".join(str(r["sea"]) for r in rows),
              flush=True)
        if out:
            _sheet(img, dom, model.example, rows[:3], f"{out}_{ci}.png")
    print(f"ALL bearing err mean over cases {np.mean(means):.1f}, worst case {max(means):.1f}")
    return means


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    run(range(n), sys.argv[2] if len(sys.argv) > 2 else None, sys.argv[3] if len(sys.argv) > 3 else None)
