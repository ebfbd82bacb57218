"""Outlined trees get the rim correction too (issue 24, trees33).

The rim correction (``transfer_colour(contours=)``) was passed only to mixes without an ink
outline: on outlined ones it stretched the sources' strokes where it mapped them onto the mixed
rim into bands thicker than ``2 width + 2``, which the pen repaint kept as "dark fills" (pen
q90/q10 1.58 in ``test_trees_outline_pen``). Dark regions are now kept as fills only when a
source has one, and the silhouette of an outlined mix follows the mixed contour.
"""

import numpy as np

from branchnb.trees._clipart_check import KINDS, clipart_tree
from branchnb.trees.outline import _has_dark_fill
from branchnb.trees.variations import TreeLibrary


def _miss(v) -> float:
    """Pixels between a mix's silhouette and its mixed contour's fill, per pixel of rim."""
    a = v.image[..., 3] >= 0.5
    per = (a ^ np.roll(a, 1, 0)).sum() + (a ^ np.roll(a, 1, 1)).sum()
    return float((a ^ v.mask).sum() / per)


def test_outlined_mix_follows_the_mixed_contour():
    lib = TreeLibrary(size=256)
    for k, kind in enumerate(KINDS):
        lib.add(clipart_tree(kind, line=1.0, rng=k, size=256), kind)
    miss = [_miss(lib.variation(rng=s)) for s in range(3)]
    # main (no correction on outlined trees): 1.00 / 1.44 / 1.86; now 0.50-0.56
    assert max(miss) <= 0.7, miss


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
