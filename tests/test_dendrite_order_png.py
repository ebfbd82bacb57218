"""The app's visiting-order panel is stored light (issue 25, dendrite42): flat bands
(:func:`visiting_order_image` ``flat=True``) sent as a palette PNG (``encode_png(palette=True)``),
the same pixels as a plain PNG in a fraction of the bytes."""

import cv2
import numpy as np
import pytest

from branchnb.core.io import encode_png
from branchnb.dendrite import make_lattice, plan
from branchnb.dendrite.render import visiting_order_image


def _decode(data: bytes) -> np.ndarray:
    return cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)


def _plan(size: int, seed: int):
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:size, :size] / size
    cost = 0.5 + 0.4 * np.sin(6 * xx + 3 * seed) * np.cos(5 * yy) + 0.1 * rng.random((size, size))
    return plan(make_lattice(cost, rng=seed), (size // 3, size // 2), metric="nonscalar")


def test_palette_png_is_lossless_and_smaller():
    rng = np.random.default_rng(0)
    bands = (rng.integers(0, 8, (40, 50))[..., None] * np.array([0.1, 0.05, 0.12])).repeat(4, 0).repeat(4, 1)
    plain, packed = encode_png(bands), encode_png(bands, palette=True)
    assert np.array_equal(_decode(plain), _decode(packed))
    assert len(packed) < 0.7 * len(plain)
    photo = rng.random((30, 30, 3))  # too many colours: written as usual
    assert encode_png(photo, palette=True) == encode_png(photo)
    rgba = np.zeros((8, 8, 4))
    rgba[..., 3] = 1
    assert np.array_equal(_decode(encode_png(rgba, palette=True)), _decode(encode_png(rgba)))


@pytest.mark.parametrize("size,seed", [(96, 0), (256, 1), (400, 2)])
def test_flat_order_keeps_the_fronts_in_few_colours(size, seed):
    res = _plan(size, seed)
    full = visiting_order_image(res, seeds=False)
    flat = visiting_order_image(res, seeds=False, flat=True)
    colours = np.unique(flat.reshape(-1, 3).round(4), axis=0)
    assert len(colours) <= 16 + 1
    # the same band almost everywhere: the fronts stay where they were
    rank = res.rank.reshape(res.shape) / len(res.order)
    band = np.floor(rank * 16).clip(0, 15)
    import matplotlib

    b = np.arange(16)
    palette = matplotlib.colormaps["magma"]((b + 0.5) / 16 * 0.85 + 0.1)[:, :3]
    palette *= np.where(b % 2 == 0, 1.0, 0.78)[:, None]
    guess = np.linalg.norm(flat[..., None, :] - palette, axis=-1).argmin(-1)
    # (the speckle it drops is nodes a band or two off on these noisy plans: 0.74-0.97 exact,
    # 0.95-0.99 within two)
    assert (guess == band).mean() >= 0.7
    assert (np.abs(guess - band) <= 2).mean() >= 0.93
    assert len(encode_png(flat, palette=True)) < 0.5 * len(encode_png(full))
