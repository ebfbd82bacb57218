"""Sampling an image at many points: OpenCV's remap asserts each output side < 32767."""
import cv2
import numpy as np

from branchnb.core.warp import _remap_points
from branchnb.leaves.snapping_carry import carry_points


def test_remap_points_equals_one_row_remap_and_takes_any_count():
    rng = np.random.default_rng(0)
    img = rng.random((60, 70, 2)).astype(np.float32)
    x, y = rng.random(5000) * 69, rng.random(5000) * 59
    one_row = cv2.remap(img, x.astype(np.float32)[None], y.astype(np.float32)[None], cv2.INTER_LINEAR,
                        borderMode=cv2.BORDER_REPLICATE)[0]
    np.testing.assert_array_equal(_remap_points(img, x, y), one_row)
    assert _remap_points(img, [], []).shape == (0, 2)
    many = _remap_points(img, np.full(40000, 3.0), np.full(40000, 4.0))
    assert many.shape == (40000, 2) and np.array_equal(many, np.broadcast_to(img[4, 3], (40000, 2)))


class _Dense:
    """A registration with a dense map: every exemplar pixel maps to itself shifted by (2, 1)."""

    def __init__(self, h, w):
        yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
        self.map_to_training = np.dstack([xx + 2, yy + 1])


def test_carry_points_takes_a_contour_longer_than_opencv_row_limit():
    pts = np.column_stack([np.linspace(0, 99, 40000), np.linspace(0, 79, 40000)])
    out = carry_points(_Dense(80, 100), pts)
    assert out.shape == (40000, 2)
    np.testing.assert_allclose(out, pts + [2, 1], atol=0.05)  # remap weighs in 1/32 px steps
