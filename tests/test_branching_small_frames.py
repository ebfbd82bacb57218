"""Issue 23, small examples (<= 256 px): a line cut by the frame is traced up to the frame
(``small_frames._reach_frame``) and the piece is rooted where its thick line enters
(``skeleton_tree._small_frame_lead`` / ``_small_frame_key``); on main a 96-256 px river's skeleton
stopped 4-5 px short of the frame and was rooted at a spur or a tip 4-65 px inside."""

from __future__ import annotations

import warnings

import cv2
import numpy as np
import pytest

from branchnb.branching import extract_structure
from branchnb.branching.small_frames import SMALL_SIDE, _reach_frame

_EDGES = {"bottom": ((0.5, 1.0), -np.pi / 2), "top": ((0.45, 0.0), np.pi / 2),
          "left": ((0.0, 0.55), 0.0), "right": ((1.0, 0.45), np.pi)}
_COLOURS = {"river": ((0.55, 0.75, 0.45), (0.25, 0.45, 0.85), 30),
            "vessel": ((0.9, 0.6, 0.55), (0.5, 0.1, 0.1), 35)}


def _walk(rng, img, p, ang, length, w, col, depth, n):
    pts = [np.array(p, float)]
    step = max(1.5, n / 80)
    for i in range(int(length / step)):
        ang += rng.normal(0, 0.2)
        pts.append(pts[-1] + step * np.array([np.cos(ang), np.sin(ang)]))
        if depth < 1 and i > 3 and rng.random() < 0.07:
            _walk(rng, img, pts[-1], ang + rng.choice([-1, 1]) * rng.uniform(0.5, 1.0), length * 0.4, w * 0.6,
                  col, depth + 1, n)
    for k, (a, b) in enumerate(zip(pts[:-1], pts[1:])):
        ww = max(1, int(round(w * (1 - 0.5 * k / len(pts)))))
        cv2.line(img, tuple(np.int32(a)), tuple(np.int32(b)), col, ww, cv2.LINE_AA)


def _example(kind, edge, n, seed):
    """A tapering line with side branches entering from ``edge``, on a plain ground."""
    rng = np.random.default_rng(seed)
    (fx, fy), ang = _EDGES[edge]
    ground, col, div = _COLOURS[kind]
    img = np.zeros((n, n, 3), np.float32) + np.float32(ground)
    _walk(rng, img, (min(fx * n, n - 1), min(fy * n, n - 1)), ang, n * 0.9, max(3, n / div), col, 0, n)
    return np.clip(img, 0, 1)


def _entry_distance(s, edge, n):
    x, y = np.asarray([b.points[0] for b in s.branches if b.parent is None]).T
    return float(np.min({"bottom": n - 1 - y, "top": y, "left": x, "right": n - 1 - x}[edge]))


# main: 4.0, 4.0, 25.2, 65.1, 4.0 px
@pytest.mark.parametrize("edge, n, seed", [("bottom", 96, 0), ("top", 96, 0), ("right", 96, 0),
                                           ("bottom", 256, 1), ("left", 160, 0)])
def test_small_river_is_rooted_where_it_enters_the_frame(edge, n, seed):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = extract_structure(_example("river", edge, n, seed))
    assert _entry_distance(s, edge, n) <= 1.5
    pts = np.concatenate([b.points for b in s.branches])
    assert pts.min() >= 0.0 and pts.max() <= n - 1.0


@pytest.mark.parametrize("edge, n", [("bottom", 256), ("top", 256), ("left", 160)])
def test_small_vessel_keeps_its_trunk_entry_among_side_branches_leaving_the_frame(edge, n):
    # traced up to the frame, side branches leaving it became frame ends too; the trunk stays the root
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = extract_structure(_example("vessel", edge, n, 0))
    assert _entry_distance(s, edge, n) <= 1.5


def test_reach_frame_runs_a_cut_line_on_to_the_frame_and_keeps_tips_inside():
    sk = np.zeros((128, 128), bool)
    sk[20:122, 60] = True                        # cut by the bottom edge: its mask goes on to row 126
    sk[30, 10:100] = True
    bw = np.zeros_like(sk)
    bw[18:127, 58:63] = True
    bw[28:33, 8:102] = True
    out = _reach_frame(sk, bw)
    assert out[122:, 60].all()                   # on to the frame
    assert not out[30, :10].any() and not out[30, 100:].any()   # tips whose mask ends inside stay
    assert not out[:20, 60].any()                # the top end is 20 px from the frame


def test_reach_frame_leaves_larger_examples_alone():
    n = SMALL_SIDE + 64
    sk = np.zeros((n, n), bool)
    sk[20:n - 5, 60] = True
    bw = np.zeros_like(sk)
    bw[18:n - 1, 58:63] = True
    assert np.array_equal(_reach_frame(sk, bw), sk)
