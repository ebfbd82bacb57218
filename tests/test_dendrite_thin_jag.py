"""Lightning down a thin part (a pole, a twig, a stick figure's limb) zigzags like inside a wide
object (issue 25, dendrite41): its noise reaches half the part's width at twice the spread.
"""

from __future__ import annotations

import numpy as np

from branchnb.dendrite._bolt_shape_check import turning
from branchnb.dendrite.channel_jag import THIN_CLIP, _thin_rough
from branchnb.dendrite.main_channel import strike_channel


def _pole_turns():
    turns = []
    for seed in range(6):
        for width in (8, 12):
            m = np.zeros((200, 250), bool)
            m[20:190, 120:120 + width] = True
            path = strike_channel(np.ones(m.shape), m, (120 + width // 2, 22), rng=seed)
            assert m[path[:, 1], path[:, 0]].all()  # it stays in the pole
            turns.append(turning(path.astype(float), 10.0))
    return np.array(turns)


def test_channel_down_a_pole_turns_like_a_bolt():
    t = _pole_turns()
    # main: mean 21.6 deg per 10 px (a bolt on a plain canvas or in a wide blob: 34-46)
    assert t.mean() >= 28.0
    assert np.median(t) >= 28.0


def test_thin_noise_keeps_its_median_and_leaves_the_rest():
    m = np.zeros((64, 64), bool)
    m[:, 28:36] = True
    r = _thin_rough(m, 1.8, 0)
    assert np.all(r[~m] == 1.0)
    # the median stays exp(-amount^2 / 2): a thin part costs what it did against the wide parts
    assert abs(np.log(np.median(r[m])) + 0.5 * 1.8 ** 2) < 1.5  # at mean 1 it was -6.5
    assert np.log(r[m]).std() > 2.5  # wider than the 1.8 spread (2.85, its high side clipped)
    assert np.log(r[m]).max() <= 2 * 1.8 * THIN_CLIP - 0.5 * 1.8 ** 2 + 1e-9
