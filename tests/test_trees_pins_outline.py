"""Pin points of a drawn tree whose trunk outline the trunk mask leaves out."""
import cv2
import numpy as np
import pytest

from branchnb.trees.contour import pin_points
from branchnb.trees.exemplar import extract_contours


def _outlined_tree(size: int, line: int):
    """A lollipop tree drawn with a dark ``line``-px outline; the trunk mask holds the bark only."""
    alpha = np.zeros((size, size), np.uint8)
    bark = np.zeros_like(alpha)
    cx = size // 2
    crown = (cx, int(0.35 * size)), int(0.3 * size)
    trunk = np.array([[cx - 0.05 * size, 0.6 * size], [cx + 0.05 * size, 0.6 * size],
                      [cx + 0.07 * size, size - 1], [cx - 0.07 * size, size - 1]], np.int32)
    cv2.fillPoly(alpha, [trunk], 1)
    cv2.fillPoly(bark, [trunk], 1)
    cv2.circle(alpha, *crown, 1, -1)
    cv2.circle(bark, *crown, 0, -1)
    # The outline is drawn over the silhouette's rim: the segmenter takes it for neither part.
    ink = (alpha > 0) & (cv2.erode(alpha, np.ones((2 * line + 1,) * 2, np.uint8)) == 0)
    # The trunk leaves the crown near the circle's lowest row.
    return alpha > 0, (bark > 0) & ~ink, (cx, size - 1), 0.65 * size


@pytest.mark.parametrize("size,line", [(256, 2), (256, 3), (256, 4), (512, 4), (512, 6)])
def test_an_outlined_trunk_gets_both_sides(size, line):
    alpha, trunk, foot, crown_bottom = _outlined_tree(size, line)
    pins = pin_points(extract_contours(alpha).tree, alpha, trunk)
    assert pins.has_trunk
    # Both trunk sides run from the foot up to where the crown starts (before: R next to B).
    for p in (pins.r, pins.l):
        assert abs(p[1] - crown_bottom) < 0.05 * size
    assert abs(pins.b[0] - foot[0]) < 0.05 * size


def test_a_trunk_mask_with_its_rim_needs_no_retry():
    alpha, _, _, crown_bottom = _outlined_tree(256, 2)
    bark = alpha.copy()
    bark[: int(crown_bottom) + 1] = False   # the whole trunk with its outline
    pins = pin_points(extract_contours(alpha).tree, alpha, bark)
    assert pins.has_trunk
    assert abs(pins.r[1] - crown_bottom) < 6 and abs(pins.l[1] - crown_bottom) < 6
