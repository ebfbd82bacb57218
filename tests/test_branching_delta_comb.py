"""Issue 23 (branching74): a delta's channels fan out to the sea instead of running side by side in a comb.

On main the ``fan0`` delta (512 px, :func:`branchnb.branching._delta_examples.delta_fan_mask`) grew, in seeds 2, 3
and 6, two to four channels that left nearly one place on one bearing and ran parallel to the sea: a side's later
channel or a channel's grandchild took an earlier channel's bearing, or left its parent on the side away from its
bearing and could not cross it (``branch_starts.FAN_BUNDLE``, ``FAN_TRAPPED``).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._delta_examples import FAN_KINDS, delta_fan_mask
from branchnb.branching.branch_starts import _Starts


def combs(s, dom: np.ndarray, ang: float = 10.0, near: float = 0.05) -> int:
    """Pairs of channels reaching the sea (non-root branches, chord >= 10 % of the diagonal) whose chords run
    less than ``ang`` degrees apart with one's start less than ``near`` x the diagonal off the other's line."""
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    diag = float(np.hypot(h, w))
    ch = []
    for b in s.branches:
        p = np.asarray(b.points, float)
        if b.parent is None or len(p) < 2:
            continue
        x, y = np.clip(np.rint(p[-1]).astype(int), 0, [w - 1, h - 1])
        c = p[-1] - p[0]
        n = float(np.hypot(*c))
        if d[y, x] > 6 or n < 0.1 * diag:
            continue
        ch.append((p[0], c / n))
    out = 0
    for i in range(len(ch)):
        for j in range(i + 1, len(ch)):
            (a, u), (b, v) = ch[i], ch[j]
            r = b - a
            if u @ v > np.cos(np.radians(ang)) and abs(r[0] * u[1] - r[1] * u[0]) < near * diag:
                out += 1
    return out


def to_sea(s, dom: np.ndarray) -> int:
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    ends = [np.clip(np.rint(b.points[-1]).astype(int), 0, [w - 1, h - 1]) for b in s.branches if len(b.points) > 1]
    return int(sum(d[y, x] <= 6 for x, y in ends))


@pytest.fixture(scope="module")
def fan0():
    t, c, f, n = FAN_KINDS["fan0"]
    mask = delta_fan_mask((512, 512), 515, t, c, f, n)[0]
    img = np.dstack([mask] * 3)
    ex = extract_structure(img)
    dom = example_domain(img, ex)
    model = fit_model(ex, domain=dom)
    assert model.drains
    return model, dom


@pytest.mark.parametrize("seed", [2, 3, 6])
def test_delta_channels_do_not_run_side_by_side(fan0, seed):
    model, dom = fan0
    s = synthesize_structure(model, rng=seed).structure
    assert combs(s, dom) == 0            # main: 1, 1, 3
    assert to_sea(s, dom) >= to_sea(model.example, dom)   # still as many channels at the sea as the example


def test_trapped_child_is_one_whose_bearing_lies_across_its_parent():
    down_right = np.array([np.cos(np.radians(45.0)), np.sin(np.radians(45.0))])
    steeper = np.array([np.cos(np.radians(80.0)), np.sin(np.radians(80.0))])
    assert _Starts._trapped(np.array([1.0, 0.0]), down_right, steeper)          # leaves outward, bearing inward
    assert not _Starts._trapped(np.array([0.0, 1.0]), down_right, steeper)      # leaves on its bearing's side
    assert not _Starts._trapped(np.array([1.0, 0.0]), None, steeper)            # a trunk's channel
