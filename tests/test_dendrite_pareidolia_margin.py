"""Issue 25, a pareidolia crown that keeps a margin from the frame.

The crown filling a frame was its inscribed ellipse with scallops: the side scallops touched
the frame's left and right edges, and twigs ran along strong edges outside the crown (a
tower by the frame) into them. The outline now keeps ``pareidolia_crown._MARGIN`` (4 % of
the frame's shorter side) from the sides and top, so does a crown round an object on a
blank ground, and the picture outside the crown is dear to the paths
(``pareidolia._OFF_CROWN``). ``python -m branchnb.dendrite._margin_check`` measures photos.
"""

import numpy as np
import pytest

from branchnb.core import as_gray
from branchnb.dendrite._margin_check import edge_towers
from branchnb.dendrite._twig_ends import tone_r
from branchnb.dendrite.pareidolia import content_crown, pareidolia_tree, tree_crown


@pytest.mark.parametrize("shape", [(300, 450), (400, 400), (450, 300), (200, 400)])
def test_crown_keeps_a_margin_from_the_sides_and_top(shape):
    h, w = shape
    for seed in range(3):
        c = tree_crown(shape, rng=seed)
        cols = np.flatnonzero(c.any(axis=0))
        rows = np.flatnonzero(c.any(axis=1))
        # the side scallops reached column 0 and w - 1 before; 4 % of the shorter side now
        assert min(cols[0], w - 1 - cols[-1]) >= 0.035 * min(h, w)
        assert rows[0] >= 0.035 * min(h, w)
        # ... and the crown still spans the frame but for that margin (and the lobes' phase)
        assert cols[-1] - cols[0] + 1 > w - 2 * 0.07 * min(h, w)


def test_crown_round_a_large_object_keeps_the_margin():
    imp = np.zeros((200, 300))
    imp[30:180, 40:260] = 1.0  # 1.3 x its box is wider than the frame
    c = content_crown(imp, blur=3)
    cols = np.flatnonzero(c.any(axis=0))
    assert cols[0] >= 7 and cols[-1] <= 300 - 1 - 7  # columns 0 and 299 before
    assert c[30:180, 40:260].all()  # the object itself is all in it


@pytest.mark.parametrize("n,aspect,seed", [(240, 1.5, 0), (240, 1.5, 1), (200, 2 / 3, 1)])
def test_twigs_keep_off_the_frame_sides(n, aspect, seed):
    img = edge_towers(n, aspect, seed)
    t = pareidolia_tree(img, rng=seed)
    hh, ww = img.shape[:2]
    ink = 1.0 - as_gray(t.render().image).astype(np.float64)[:hh] > 0.3
    b = max(2, round(0.01 * min(hh, ww)))
    # share of the side edges' rows whose 1 % band holds ink: 0.006-0.21 on one side or both
    # before (the ink's side margin 0-0.5 % of the width); none now, a margin of 2-4 %
    assert not ink[:, :b].any() and not ink[:, -b:].any() and not ink[:b].any()
    cols = np.flatnonzero(ink.any(axis=0))
    assert min(cols[0], ww - 1 - cols[-1]) >= 0.015 * ww
    # tone r at 4 px blur 0.953 / 0.957 / 0.935 before, 0.946 / 0.943 / 0.945 now: the towers
    # by the frame's sides lie outside the crown now
    assert tone_r(t, 4.0) > 0.93
