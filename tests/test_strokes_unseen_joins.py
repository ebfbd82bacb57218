"""Multi-part edits on objects the stroke tests had not seen (issue 25): no flesh beyond the parts.

A lengthened L-shaped cactus arm got a staircase of stale uprights on its inner
side (patches on its horizontal leg copied the source's upright, each a little
farther out); a delta channel turned away from its neighbour left a sawtooth of
the neighbour's old root in the V between them (root tubes as wide as the merged
fan). Both lie beyond every part's tube: counted here as object pixels farther
than the part's half width + 3 px from every target stroke.
"""
import os
import sys

import numpy as np
import pytest

from branchnb.strokes import edit_structure

sys.path.insert(0, os.path.dirname(__file__))
from strokes_junction_table import measure  # noqa: E402
from strokes_unseen_objects import EDITS  # noqa: E402


def _stray(obj, res, strokes, widths, margin=3.0):
    """Object pixels (alpha > 0.5) farther than ``width + margin`` from each of ``strokes``."""
    import cv2

    a = res.image[..., 3] > 0.5
    ok = np.zeros_like(a)
    for st, w in zip(strokes, widths):
        canvas = np.full(a.shape, 255, np.uint8)
        cv2.polylines(canvas, [np.rint(np.asarray(st) * 16).astype(np.int32).reshape(-1, 1, 2)], False, 0, 1,
                      cv2.LINE_8, 4)
        ok |= cv2.distanceTransform(canvas, cv2.DIST_L2, 5) <= w + margin + obj.outline
    return int((a & ~ok).sum())


def _run(name, n):
    obj, src, tgt, exp, kids = EDITS[name](n)
    res = edit_structure(obj.image, src, tgt)
    return obj, src, tgt, exp, kids, res


def test_lengthened_cactus_arm_has_no_staircase():
    obj, src, tgt, exp, kids, res = _run("cactus", 600)
    # trunk, arms, flower 1 (stroked), flower 2 (carried in place by arm 2)
    strokes = list(tgt) + [obj.strokes[5]]
    widths = [obj.widths[0], obj.widths[1], obj.widths[4], obj.widths[2], obj.widths[3], obj.widths[3],
              obj.widths[5]]
    # on main: 1100+ px of stale uprights beside the lengthened arm
    assert _stray(obj, res, strokes, widths) <= 60
    r = measure(obj, res, exp, kids)
    assert r["gap"] == 0 and r["pieces"] == 1 and r["fleck_px"] == 0


def test_turned_delta_channel_leaves_no_sawtooth():
    obj, src, tgt, exp, kids, res = _run("delta", 600)
    R, t = exp[0][1:]
    side = obj.strokes[5] @ R.T + t  # the side channel, carried by the turned channel
    strokes = list(tgt) + [side]
    widths = [obj.widths[k] for k in range(6)]
    # on main: ~1000 px of the neighbour's old root filling the V
    assert _stray(obj, res, strokes, widths) <= 60
    r = measure(obj, res, exp, kids)
    assert r["gap"] == 0 and r["pieces"] == 1 and r["fleck_px"] == 0


@pytest.mark.parametrize("name", ["stickman"])
def test_new_kinds_stay_joined(name):
    obj, src, tgt, exp, kids, res = _run(name, 300)
    r = measure(obj, res, exp, kids)
    assert r["gap"] == 0 and r["pieces"] == 1 and r["fleck_px"] == 0 and r["missing"] <= 5
