"""A dark trunk's outline stays a pen wide in a mix (issue 24, trees33).

A trunk drawn darker than the tree's ink threshold was taken, with its outline, for one dark
fill: the warped stroke widened by the mix (ink bled into the widened trunk) stayed as a band
2-3 pens wide. Main keeps the 8-px band; the stroke is now thinned as on a light trunk.
"""

import numpy as np
import pytest

from branchnb.trees.outline import _drop_excess, even_outline
from branchnb.trees.outline_pen import _pen_outline

INK = np.array([0.03, 0.03, 0.03], np.float32)


def _picture(trunk, pen=3, widened=8):
    """A trunk and a larger light crown side by side, both outlined with a ``pen`` px stroke; the
    trunk's left stroke widened to ``widened`` px over rows 20-40 (as a warp leaves it)."""
    img = np.zeros((60, 180, 4), np.float32)
    img[5:55, 10:50] = (*trunk, 1)
    img[5:55, 70:175] = (0.3, 0.7, 0.2, 1)
    for x0, x1 in ((10, 50), (70, 175)):
        img[5:55, x0:x0 + pen, :3] = INK
        img[5:55, x1 - pen:x1, :3] = INK
        img[5:5 + pen, x0:x1, :3] = INK
        img[55 - pen:55, x0:x1, :3] = INK
    img[20:40, 10:10 + widened, :3] = INK
    return img


def _band(img, x0=10):
    """Width of the dark run from the trunk's left edge, rows 22-37."""
    return max(int(np.argmin(img[y, x0:x0 + 20, 0] < 0.1)) for y in range(22, 38))


@pytest.mark.parametrize("trunk", [(0.2, 0.13, 0.08), (0.16, 0.1, 0.14), (0.45, 0.3, 0.15)])
def test_widened_stroke_on_a_trunk_is_thinned_dark_or_light(trunk):
    img = _picture(trunk)
    assert _band(img) == 8
    out = _drop_excess(img.copy(), INK, 3)
    assert _band(out) <= 4                     # main: 8 on the dark trunks
    np.testing.assert_allclose(out[30, 20, :3], trunk, atol=1e-6)


def test_even_outline_and_pen_thin_a_dark_trunk_band():
    img = _picture((0.2, 0.13, 0.08))
    assert _band(even_outline(img, INK, 3)) <= 4                       # main: 8
    profile = np.array([1, 1, 1, 1, 1, 0.5, 0, 0, 0, 0, 0], float)    # a 3 px pen, soft inner edge
    assert _band(_pen_outline(img, INK, 3, profile)) <= 4              # main: 8


def test_ink_coloured_fill_and_crown_line_stay():
    # a trunk drawn in the ink colour is one dark fill (no outline to tell from it): unchanged
    img = _picture(tuple(INK + 0.02))
    out = _drop_excess(img.copy(), INK, 3)
    np.testing.assert_allclose(out[..., :3], img[..., :3], atol=1e-6)
    # the crown's line across a dark trunk's top (ink between a light fill and the trunk) stays
    img = _picture((0.2, 0.13, 0.08))
    img[5:20, 10:50, :3] = (0.3, 0.7, 0.2)
    img[5:8, 10:50, :3] = INK
    img[18:21, 10:50, :3] = INK
    out = _drop_excess(img.copy(), INK, 3)
    assert (out[18:21, 14:46, 0] < 0.1).mean() > 0.95
