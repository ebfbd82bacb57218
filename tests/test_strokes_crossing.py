"""Strokes that cross and stay where they were keep their crossing as in the source (issue 25).

Object: the octopus of ``strokes_touching_table.py`` (outlined tentacles
with light suckers, one outline round their union, two tentacles' tips
crossing). On main each of two crossing tentacles took the other as lying
over it and filled its crossing from farther along itself: a pink smear of
suckers' colour at the crossing of two tentacles nobody edited. Now strokes
left in place and hidden only by strokes left in place copy the source as
it is (a moved stroke still gets its own view: it drags no neighbour along).
"""
import os
import sys
from types import SimpleNamespace

import numpy as np
import pytest

from branchnb.strokes import Stroke, edit_structure
from branchnb.strokes.edit import _still_crossings
from branchnb.strokes.source import source_index

sys.path.insert(0, os.path.dirname(__file__))
from strokes_touching_table import oct_edit  # noqa: E402


def _cross(a, b):
    return float(a[0] * b[1] - a[1] * b[0])


def _dense(t):
    s = np.r_[0, np.cumsum(np.hypot(*np.diff(t, axis=0).T))]
    u = np.arange(0, s[-1], 1.0)
    return np.c_[np.interp(u, s, t[:, 0]), np.interp(u, s, t[:, 1])]


def _crossings(strokes, unchanged):
    """(x, y) where two unchanged strokes' polylines cross."""
    out = []
    for i in unchanged:
        for j in unchanged:
            if j <= i:
                continue
            a, b = strokes[i], strokes[j]
            for p, q in zip(a[:-1], a[1:]):
                for r, s in zip(b[:-1], b[1:]):
                    d = _cross(q - p, s - r)
                    if abs(d) < 1e-9:
                        continue
                    t = _cross(r - p, s - r) / d
                    u = _cross(r - p, q - p) / d
                    if 0 <= t <= 1 and 0 <= u <= 1:
                        out.append(p + t * (q - p))
    return out


@pytest.mark.parametrize("size,seed", [(300, 0), (500, 1)])
def test_crossing_of_unedited_tentacles_stays_as_in_the_source(size, seed):
    img, src, tgt, ow = oct_edit("oct_curl", size, seed)
    unchanged = [k for k in range(1, len(src)) if np.array_equal(src[k], tgt[k])]
    moved = [t for k, t in enumerate(tgt) if k not in unchanged]
    # (away from every edited stroke's new place: only what nobody edited)
    pts = [p for p in _crossings(src, unchanged)
           if min(np.hypot(*(_dense(t) - p).T).min() for t in moved) > 0.1 * size]
    assert pts, "the octopus's tentacles cross"
    out = edit_structure(img, src, tgt, rng=0).image
    yy, xx = np.mgrid[:size, :size]
    worst = 0.0
    for x, y in pts:
        disk = (np.hypot(xx - x, yy - y) <= 0.03 * size) & (img[..., 3] > 0.5)
        worst = max(worst, float(np.abs(out[disk, :3] - img[disk, :3]).mean()))
    # main: 0.146 / 0.062 (a smear of the suckers' colour); now 0.007 / 0.000
    assert worst < 0.015, worst


def test_views_dropped_only_where_nothing_that_hides_moves():
    img, src, _, _ = oct_edit("oct_curl", 300, 0)
    strokes = [Stroke(s) for s in src]
    index = source_index(img, strokes)
    crossing = sorted(k for k, by in index.hidden_by.items() if by)
    assert len(crossing) >= 2, crossing
    a = crossing[0]
    still = [SimpleNamespace(source=s, target=s) for s in strokes]
    assert not set(_still_crossings(index, still).views) & set(crossing)
    # one of them moved: the others it hid keep their own view, and so does it
    moved = list(still)
    moved[a] = SimpleNamespace(source=strokes[a], target=Stroke(src[a] + (3.0, 0.0)))
    kept = _still_crossings(index, moved).views
    assert a in kept
    assert all(k in kept for k in crossing if a in index.hidden_by[k])
