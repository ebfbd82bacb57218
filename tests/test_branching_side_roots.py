"""Roots sampled on an image side stay near where the example's roots on that side are (issue 23)."""

import numpy as np

from branchnb.branching.roots import fit_roots
from branchnb.core.structure import Branch, Structure

_NORMAL = {"bottom": -np.pi / 2, "left": 0.0}


def _example(entries, seed, size=400):
    rng = np.random.default_rng(seed)
    branches = []
    for side, f in entries:
        x, y = (f * size, size - 1.5) if side == "bottom" else (0.5, f * size)
        a = _NORMAL[side] + rng.normal(0, 0.3)
        length = rng.uniform(100, 200)
        branches.append(Branch([(x, y), (x + length * np.cos(a), y + length * np.sin(a))], 2.0))
    return fit_roots(Structure(branches, image_shape=(size, size)))


def _offsets(rm, size, seed):
    """Per output root on a side the example uses: distance along it to the nearest example root there."""
    out = []
    for x, y, _a in rm.sample(np.ones((size, size), bool), seed):
        k = int(np.argmin([y, size - 1 - y, x, size - 1 - x]))
        along = rm.positions[rm.sides == k, 0 if k < 2 else 1]
        assert len(along), f"root at ({x}, {y}) on a side the example does not use"
        out.append(float(np.min(np.abs(along - (x if k < 2 else y) / size))))
    return np.array(out)


def test_clustered_side_roots_start_near_the_examples():
    # frost from the bottom middle and two branches leaving the left side a few pixels apart: the
    # second left root used to be pushed to the far end of the side (mean 0.19, max 0.70 of its length)
    offs = []
    for mseed in range(3):
        c = 0.35 + 0.1 * mseed
        rm = _example([("bottom", c - 0.15), ("bottom", c + 0.15), ("left", 0.72), ("left", 0.77)], mseed)
        for size in (256, 512, 768):
            for seed in range(6):
                offs.append(_offsets(rm, size, seed))
    offs = np.concatenate(offs)
    assert offs.mean() < 0.12, offs.mean()
    assert offs.max() < 0.3, offs.max()


def test_spread_side_roots_keep_their_spread():
    # roots spread over the whole bottom side are still drawn over all of it (no collapse onto one place)
    rm = _example([("bottom", 0.1), ("bottom", 0.5), ("bottom", 0.9)], 0)
    xs = np.array([x for seed in range(6) for x, _y, _a in rm.sample(np.ones((300, 300), bool), seed)])
    assert xs.min() < 0.25 * 300 and xs.max() > 0.75 * 300, (xs.min(), xs.max())
    assert len(np.unique(np.round(xs / 30))) >= 4
