"""Dark regions are fills only when a source has one (issue 24, trees33).

The rim correction (``transfer_colour(contours=)``) on outlined mixes stretched the sources'
strokes where it mapped them onto the mixed rim into bands thicker than ``2 width + 2``, which
the pen repaint kept as "dark fills" (pen q90/q10 1.58 in ``test_trees_outline_pen``). A dark
region is now kept as a fill only when a source has one (:func:`_has_dark_fill`); the frame does
not count (a stroke along a crown cut by it is no fill). The correction itself stays off on
outlined mixes (flecks inside the rim, see ``make_variation``).
"""

import numpy as np

from branchnb.trees.outline import _has_dark_fill
from branchnb.trees.outline_pen import _pen_outline


def _drawing(trunk, frame: bool = False):
    img = np.zeros((80, 80, 4), np.float32)
    img[10:50, 10:70] = (0.3, 0.7, 0.2, 1)
    img[45:80 if frame else 75, 32:48] = (*trunk, 1)
    a = img[..., 3] >= 0.5
    from scipy import ndimage as ndi
    rim = a & ~ndi.binary_erosion(a, iterations=2, border_value=0)
    img[rim, :3] = 0.03
    return img


def test_dark_fill_of_a_source():
    ink = (0.03, 0.03, 0.03)
    assert _has_dark_fill(_drawing((0.04, 0.04, 0.04)), ink, 2)          # a trunk in the ink colour
    assert not _has_dark_fill(_drawing((0.2, 0.13, 0.08)), ink, 2)      # a dark trunk told from the ink
    assert not _has_dark_fill(_drawing((0.45, 0.3, 0.15)), ink, 2)
    # the outline along a part cut by the frame is no fill
    img = _drawing((0.45, 0.3, 0.15), frame=True)
    img[76:80, 32:48, :3] = 0.03
    assert not _has_dark_fill(img, ink, 2)


def test_pen_outline_thins_a_stretched_stroke_without_source_fills():
    # a 3 px pen stretched to 9 px along a side (a 9 x 9 dark block: a "dark fill" to the old
    # rule) is thinned when the sources have no dark fill; kept otherwise (as on main)
    ink = np.array([0.03, 0.03, 0.03], np.float32)
    img = _drawing((0.45, 0.3, 0.15))
    img[12:40, 10:19, :3] = ink
    profile = np.array([1, 1, 1, 1, 1, 0.5, 0, 0, 0], float)            # a 3 px pen
    kept = _pen_outline(img, ink, 3, profile)
    thin = _pen_outline(img, ink, 3, profile, dark_fills=False)
    assert (kept[26, 10:22, 0] < 0.1).sum() >= 9
    assert (thin[26, 10:22, 0] < 0.1).sum() <= 5
