"""Issue 23 (branching78): small river maps (96-256 px) rooted where their trunk enters the frame.

Procedural maps: a river (blue and tapering, or black and of one width) entering at one frame edge at
an angle, tributaries joining it at acute angles, drawn on green land. On main the skeleton of a 6-px
river stopped 9 px from the frame (past ``small_frames.REACH``), a traced frame end made 3-pixel
cycles (no end point of the skeleton's graph), and the radius *at* a frame end (where the filters
fade against the border) ranked it below tributary tips: trees were rooted 8-67 px inside the frame.
"""

from __future__ import annotations

import warnings

import cv2
import numpy as np
import pytest

from branchnb.branching import extract_structure
from branchnb.branching.small_frames import _reach_frame

_KINDS = {"blue": ((0.55, 0.75, 0.45), (0.25, 0.45, 0.85), 1 / 30, 3.0, True),
          "black": ((0.55, 0.75, 0.45), (0.05, 0.05, 0.08), 0.0, 2.0, False)}


def _frame_d(p, n):
    return min(p[0], p[1], n - 1 - p[0], n - 1 - p[1])


def _river_map(kind, n, edge, seed):
    """Image and the entry point (x, y) on the frame of a river tree entering at ``edge``."""
    rng = np.random.default_rng(seed)
    ground, col, wfrac, wmin, taper = _KINDS[kind]
    img = np.zeros((n, n, 3), np.float32) + np.float32(ground)
    t = rng.uniform(0.3, 0.7) * n
    (x0, y0), ang0 = {"bottom": ((t, n + 3.0), -np.pi / 2), "top": ((t, -4.0), np.pi / 2),
                      "left": ((-4.0, t), 0.0), "right": ((n + 3.0, t), np.pi)}[edge]
    w0 = max(wmin, wfrac * n)
    ang0 += rng.uniform(-0.6, 0.6)
    lines, step = [], max(1.5, n / 90)

    def walk(p, ang, length, w, depth, home):
        pts, a, inside = [np.array(p, float)], ang, False
        for _ in range(int(length / step)):
            a += rng.normal(0, 0.18)
            a += 0.15 * np.angle(np.exp(1j * (home - a)))
            q = pts[-1] + step * np.array([np.cos(a), np.sin(a)])
            if inside and _frame_d(q, n) < w + 5:
                break
            inside |= _frame_d(q, n) >= w + 6
            pts.append(q)
        pts = np.array(pts)
        m = len(pts)
        ws = np.linspace(w, max(wmin * 0.6, 1.0), m) if taper else np.full(m, w)
        lines.append((pts, ws))
        if depth >= (2 if n >= 160 else 1) or m < 10:
            return
        lo = max(4, m // 6)
        for j, v in enumerate(np.sort(rng.choice(np.arange(lo, m - 4), min(rng.integers(2, 4), m - 4 - lo),
                                                 replace=False))):
            tt = pts[min(v + 1, m - 1)] - pts[max(v - 1, 0)]
            da = (1 if (j + depth) % 2 == 0 else -1) * rng.uniform(0.5, 1.0)
            hd = np.arctan2(tt[1], tt[0])
            walk(pts[v], hd + da, length * rng.uniform(0.35, 0.55), max(wmin if not taper else 1.0, ws[v] * 0.6),
                 depth + 1, hd + da * 0.7)

    walk((x0, y0), ang0, 0.85 * n, w0, 0, ang0)
    for pts, ws in lines:
        for k in range(len(pts) - 1):
            cv2.line(img, tuple(np.int32(np.round(pts[k]))), tuple(np.int32(np.round(pts[k + 1]))), col,
                     max(1, int(round(ws[k]))), cv2.LINE_AA)
    trunk = lines[0][0]
    e = trunk[np.flatnonzero([(0 <= p[0] <= n - 1) and (0 <= p[1] <= n - 1) for p in trunk])[0]].copy()
    e = np.clip(e, 0, n - 1)
    e[{"bottom": 1, "top": 1, "left": 0, "right": 0}[edge]] = {"bottom": n - 1, "top": 0, "left": 0,
                                                                "right": n - 1}[edge]
    return np.clip(img, 0, 1), e, w0 / 2.0


# main: the first five rooted 23, 17, 8, 67 and 36 px from the frame; the last three (rooted at their entry on
# main too) guard the rules against moving a good root
@pytest.mark.parametrize("kind, n, edge, seed", [
    ("blue", 96, "bottom", 3), ("blue", 128, "right", 1), ("blue", 160, "bottom", 1), ("blue", 192, "bottom", 0),
    ("blue", 192, "top", 1), ("blue", 256, "left", 0), ("black", 96, "left", 0), ("black", 256, "right", 0)])
def test_small_river_map_is_rooted_at_its_entry(kind, n, edge, seed):
    img, entry, r_in = _river_map(kind, n, edge, seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = extract_structure(img)
    roots = [b for b in s.branches if b.parent is None]
    assert len(roots) == 1
    p = roots[0].points[0]
    assert _frame_d(p, n) <= 2.0, p
    assert float(np.hypot(*(p - entry))) <= 2.0 * r_in + 8.0, (p, entry)


def test_reach_frame_reach_grows_with_the_line_and_leaves_a_clean_end():
    sk = np.zeros((160, 160), bool)
    sk[30:150, 80] = True                       # a 13-px line's axis, 10 px short of the bottom frame
    bw = np.zeros_like(sk)
    bw[24:160, 74:87] = True
    out = _reach_frame(sk, bw)
    assert out[159].any()                       # on to the frame (8 px reach + 2 radii)
    # the frame end is an end point of the skeleton (one neighbour): no 3-pixel cycle there
    y, x = 159, int(np.flatnonzero(out[159])[0])
    assert int(out[y - 1:y + 1, x - 1:x + 2].sum()) - 1 == 1
    thin = np.zeros_like(sk)
    thin[30:150, 80] = True                     # a 3-px line 10 px short: its reach is 8 + 2 x 2 px ...
    bw_thin = np.zeros_like(sk)
    bw_thin[28:152, 79:82] = True               # ... and its mask ends inside: it stays
    assert not _reach_frame(thin, bw_thin)[152:].any()
