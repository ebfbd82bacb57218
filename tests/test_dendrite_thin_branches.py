"""A lightning bolt on a thin object (a mast with arms, a pole) zigzags and branches like on a
wide one (issue 25, dendrite38): noise at the thin part's width's scales on the channel's and
the branches' costs (``channel_jag._thin_rough``), tips counted along the object's medial
axis (``stylization._strike_share``)."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.dendrite._thin_branch_check import measure
from branchnb.dendrite.channel_jag import _thin_rough
from branchnb.dendrite.stylization import _strike_share


def test_thin_noise_changes_across_a_pole_and_nowhere_else():
    m = np.zeros((200, 200), bool)
    m[:, 95:105] = True  # a 10-px pole
    r = np.log(_thin_rough(m, 1.8, 0))
    assert np.all(r[~m] == 0.0)
    # across the pole (10 px) the noise changes about as much as along it
    across = np.abs(np.diff(r[:, 95:105], axis=1)).mean()
    along = np.abs(np.diff(r[:, 95:105], axis=0)).mean()
    assert across > 0.5 * along


def test_tips_follow_a_thin_objects_length_not_its_area():
    pole = np.zeros((400, 500), bool)
    pole[80:380, 240:255] = True
    blob = np.zeros((400, 500), bool)
    yy, xx = np.mgrid[:400, :500]
    blob[np.hypot(yy - 200, xx - 250) < 150] = True
    assert _strike_share(pole) > 3 * pole.mean()
    assert _strike_share(blob) == pytest.approx(blob.mean())


@pytest.mark.parametrize("kind,seed", [("mast", 0), ("lamp", 1)])
def test_bolt_down_a_thin_object_turns_and_branches(kind, seed):
    # main: mast 500 s0 main channel 17.3 deg per 10 px, lamp s1 19.8 (plain canvas 35-40);
    # 8-9 tips
    m = measure(kind, 500, seed)
    assert m["main"] >= 23.0
    assert m["tips"] >= 12
