"""A traced vein ends where it meets a crease of the blade and fades beyond it (issue 22, beyond the paper).

Sample maple 07's midrib fades past a crease of 1-2 px holes half way up; the polar trace ran on along the
blade's faint texture to the training vein's carried length (training maples 01 / 02 -> 07: vein IoU
0.647 / 0.629 -> 0.726 / 0.692 with :func:`~branchnb.leaves.snapping_trace._crease_end`). A vein that runs
on as strongly past a crack beside it, and a vein past an isolated pinhole, are followed as before.
"""

import numpy as np
import pytest

from branchnb.leaves.snapping_trace import _crease_end, trace_branches


def _ray(deg, n, origin=(40.0, 75.0)):
    r = np.arange(n)[:, None]
    return np.asarray(origin) + r * [np.cos(np.radians(deg)), np.sin(np.radians(deg))]


def _leaf(beyond, holes):
    """A vertical vein from (40, 75) up: score 1 for 40 px, then ``beyond``; the blade with ``holes``."""
    maps = np.zeros((16, 80, 80), np.float32)
    maps[:, 35:76, 40] = 1.0
    maps[:, 5:35, 40] = beyond
    blade = np.zeros((80, 80), bool)
    blade[2:78, 2:78] = True
    for y, x in holes:
        blade[y, x] = False
    return maps, blade


def _traced_top(maps, blade):
    # The midrib carried 70 px up, and two short laterals making the junction its pivot.
    out = trace_branches([_ray(-90, 70), _ray(180, 20), _ray(0, 20)], maps, blade)
    return float(out[0][:, 1].min())


CREASE = [(33, x) for x in range(42, 47)] + [(32, 47), (31, 48)]


def test_a_vein_fading_past_a_crease_ends_at_the_crease():
    maps, blade = _leaf(0.3, CREASE)
    top = _traced_top(maps, blade)
    # Before: the trace ran on to y 5 (faint texture scores above a quarter of the vein's mean).
    assert 30.0 <= top <= 40.0


def test_without_the_crease_the_faint_continuation_is_followed():
    maps, blade = _leaf(0.3, [])
    assert _traced_top(maps, blade) < 15.0


def test_a_vein_strong_past_a_crack_runs_on():
    maps, blade = _leaf(0.9, CREASE)
    assert _traced_top(maps, blade) < 15.0


def test_a_pinhole_is_no_crease():
    maps, blade = _leaf(0.3, [(33, 42)])
    assert _traced_top(maps, blade) < 15.0


@pytest.mark.parametrize("beyond, cut", [(0.1, True), (0.5, False)])
def test_crease_end_compares_the_score_beyond_the_damage_with_before(beyond, cut):
    score = np.r_[np.full(30, 0.6), np.full(4, 0.9), np.full(20, beyond)]
    dist = np.full(54, 9.0)
    dist[30:34] = 1.0           # the trace touches the damage at 30-33; its rim scores 0.9 there
    assert _crease_end(score, dist, 10, 54) == (30 if cut else 54)
