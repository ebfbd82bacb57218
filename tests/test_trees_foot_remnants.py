"""No pile pieces left on a drawn trunk's foot after the ground cut (issue 24, trees35).

The cut at the row where a leaf pile widens the neck kept the leaves drawn *over* the trunk's
lowest rows (inside its column): colour specks and outline arcs at the foot of every mix of
palms and broadleaf trees. Those rows are now drawn on down from the trunk's clean rows above
(``GroundSplit.repaint``), so the foot stays where it was and the pieces go.
"""

import numpy as np
import pytest

from branchnb.trees._measure_feet import foot_remnants, without_pile
from branchnb.trees.drawn import drawn_tree
from branchnb.trees.ground import split_ground


@pytest.mark.parametrize("kind", ["palm", "broadleaf", "fruit"])
def test_no_pile_pieces_on_the_foot(kind):
    rem, lost = [], []
    for seed in range(20, 24):
        img = np.asarray(drawn_tree(kind, pile=True, rng=seed, size=256), np.float32)
        r, k = foot_remnants(split_ground(img).cut(img), without_pile(kind, seed, 256))
        rem.append(r)
        lost.append(k)
    # main: largest palm 49, broadleaf 50, fruit 12 px; now <= 8
    assert max(rem) <= 10, rem
    assert max(lost) <= 16, lost          # the trunk is not shortened (main: 5-16 rows)


def test_leaf_over_the_trunk_foot_is_repainted():
    img = np.zeros((120, 90, 4), np.float32)
    img[5:35, 10:80] = (0.2, 0.55, 0.15, 1)                     # crown
    img[35:104, 36:54] = (0.05, 0.04, 0.03, 1)                  # trunk outline
    img[35:104, 39:51] = (0.5, 0.3, 0.12, 1)                    # trunk fill
    img[100:112, 5:85] = (0.05, 0.04, 0.03, 1)                  # the pile, outlined
    img[102:110, 8:82] = (0.9, 0.5, 0.1, 1)
    img[93:100, 40:49] = (0.05, 0.04, 0.03, 1)                  # a leaf drawn over the trunk
    img[95:98, 42:47] = (0.95, 0.2, 0.1, 1)
    s = split_ground(img)
    cut = s.cut(img)
    assert s.repaint is not None
    assert s.foot[1] == 99                                       # the foot stays
    foot = cut[90:100, 39:51, :3]
    assert np.abs(foot - (0.5, 0.3, 0.12)).max() < 0.05        # the trunk's fill, no leaf
    assert (cut[90:100, 36:39, 0] < 0.1).all() and (cut[90:100, 51:54, 0] < 0.1).all()
    assert not cut[100:, :, 3].any() and not cut[90:100, :36, 3].any()
