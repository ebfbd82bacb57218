import numpy as np
import pytest

from branchnb.core.image import (
    as_float_image,
    as_gray,
    as_mask,
    as_points,
    as_rgb,
    as_rgba,
    composite_over,
    split_alpha,
    to_uint8,
)


@pytest.mark.parametrize("dtype,value,expected", [(np.uint8, 255, 1.0), (np.uint16, 65535, 1.0),
                                                  (bool, True, 1.0), (np.float64, 0.25, 0.25)])
def test_as_float_image_scales_dtypes(dtype, value, expected):
    img = as_float_image(np.full((3, 4), value, dtype=dtype))
    assert img.shape == (3, 4, 1) and img.dtype == np.float32
    assert np.allclose(img, expected)


def test_as_float_image_does_not_modify_input():
    a = np.full((2, 2, 3), 0.5)
    out = as_float_image(a)
    out[:] = 0
    assert np.all(a == 0.5)


@pytest.mark.parametrize("bad,exc,match", [
    (np.zeros((0, 3)), ValueError, "empty"),
    (np.zeros((2, 2, 2)), ValueError, "channels"),
    (np.zeros((2, 2, 3, 1)), ValueError, "2-D"),
    (np.full((2, 2), np.nan), ValueError, "NaN"),
    (np.full((2, 2), 2.0), ValueError, r"\[0, 1\]"),
    (np.zeros((2, 2), np.int32), TypeError, "integer dtype"),
    (np.array([["a"]]), TypeError, "numeric"),
])
def test_as_float_image_rejects_bad_input(bad, exc, match):
    with pytest.raises(exc, match=match):
        as_float_image(bad, name="image")


def test_error_names_the_argument():
    with pytest.raises(ValueError, match="^background"):
        as_float_image(np.zeros((0,)), name="background")


def test_rgb_rgba_gray_conversions():
    gray = np.linspace(0, 1, 12).reshape(3, 4)
    assert as_rgb(gray).shape == (3, 4, 3)
    rgba = as_rgba(gray)
    assert rgba.shape == (3, 4, 4) and np.all(rgba[..., 3] == 1)
    assert np.allclose(as_gray(as_rgb(gray)), gray, atol=1e-6)
    half = np.dstack([np.zeros((2, 2, 3)), np.full((2, 2), 0.5)])
    assert np.allclose(as_rgb(half), 0.5)  # black at 50 % over white
    assert np.allclose(composite_over(half, (0, 0, 1))[..., 2], 0.5)
    rgb, a = split_alpha(half)
    assert rgb.shape == (2, 2, 3) and np.allclose(a, 0.5)


def test_to_uint8_round_trip():
    img = np.random.default_rng(0).integers(0, 256, (5, 6, 3)).astype(np.uint8)
    assert np.array_equal(to_uint8(as_float_image(img)), img)


def test_as_points_validation():
    assert as_points([(1, 2)]).dtype == np.float64
    with pytest.raises(ValueError, match=r"shape \(N, 2\)"):
        as_points([1, 2, 3])
    with pytest.raises(ValueError, match="NaN"):
        as_points([(np.nan, 1)])
    with pytest.raises(ValueError, match="at least 2"):
        as_points([(0, 0)], min_points=2)
    with pytest.raises(ValueError, match=r"seeds\[1\].*outside"):
        as_points([(0, 0), (10, 0)], name="seeds", image_shape=(5, 5))


def test_as_mask():
    assert as_mask(np.eye(3)).dtype == bool
    with pytest.raises(ValueError, match="mask has shape"):
        as_mask(np.eye(3), shape=(2, 2))
