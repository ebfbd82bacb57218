"""Which strokes an edit touches (beyond the paper, issue 25).

An edit should change only what the user touched: strokes given unchanged
elsewhere on the object must not steer how the moved ones are re-synthesized.
"""

from __future__ import annotations

import numpy as np


def _still_pairs(pairs) -> set:
    """Indices of the pairs whose target stroke is their source stroke (left where it was)."""
    return {k for k, p in enumerate(pairs) if p.source.points.shape == p.target.points.shape
            and np.array_equal(p.source.points, p.target.points)}


def _typical_radius(index, pairs, patch_size: float) -> float:
    """The edit's typical patch radius: the median over the strokes the edit touches.

    Those are the moved strokes, the strokes they join in the source (a moved
    arm's trunk, a moved trunk's branches) and the strokes they were copied
    from; all strokes if none moved. The radius sets the chord window of the
    stroke directions, the junction tolerance, the depth a glued tip is pushed
    under its parent and the automatic values reported. Beyond the paper (the
    median over all strokes): an edit changes only what the user touched, so
    strokes given unchanged elsewhere on the object must not steer it. A
    figure's arm raised (400 px) got patches of 40.3 px with the body's and the
    other limbs' strokes given unchanged, 68.6 px with the body's alone; now
    64.4 / 68.6 (the rest: the arm measured wider with the other arm's root
    unstroked beside it). A cactus arm (300 px): 52.4 / 62.0 px with the other
    arm's stroke given or not, now 62.0 / 62.0. The five bench edits are
    unchanged (their moved strokes join all the others).
    """
    still = _still_pairs(pairs)
    moved = {k for k in range(len(pairs)) if k not in still}
    keys = [p.source.points.tobytes() for p in pairs]
    joined = [set(index.joined[k]) - {-1} if index.joined else set() for k in range(len(pairs))]
    near = set(moved)
    for k in range(len(pairs)):
        if k in moved:
            near |= joined[k]  # its parents
        elif joined[k] & moved or any(keys[k] == keys[j] for j in moved):
            near.add(k)  # its children, the stroke it was copied from
    use = sorted(near) or list(range(len(pairs)))
    return float(np.median(np.concatenate([
        index.radius(k, np.linspace(0, pairs[k].source.length, 32), patch_size) for k in use])))
