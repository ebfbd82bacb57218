"""The per-analysis preparation of synthesis does no full-canvas work it does not use (issue 22 speed).

Checks what is computed, not how long it takes: the bled stage images search
nearest colours on the ring's box only, and a photograph is told from flat art
on its first exemplar, without the outline measurements.
"""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.leaves import flatart, prepared, prepared_fill


def _leaf(h=120, w=160, seed=0):
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:h, :w]
    blade = ((yy - 60) / 35.0) ** 2 + ((xx - 70) / 45.0) ** 2 < 1
    img = np.clip(0.3 + 0.2 * rng.random((h, w, 3)), 0, 1).astype(np.float32)
    img[~blade] = 1.0
    return img, blade


def _reference_bleed(img, mask):
    """The former whole-canvas formula: nearest colours everywhere, then the push-pull fill."""
    near = prepared.extend_nearest(img, mask)
    ring = ndi.binary_dilation(mask, iterations=2)
    v, w = near, ring.astype(np.float32)
    return np.where(ring[..., None], near, prepared._smooth_fill(v * w[..., None], ring))


def test_bleed_searches_nearest_colours_on_the_rings_box_only(monkeypatch):
    img, blade = _leaf()
    seen = []
    real = prepared_fill.extend_nearest  # the module _bleed lives in (re-exported by prepared)

    def spy(values, known):
        seen.append(np.asarray(known).shape)
        return real(values, known)

    monkeypatch.setattr(prepared_fill, "extend_nearest", spy)
    out = prepared._bleed(img, blade)
    ring = ndi.binary_dilation(blade, iterations=2)
    rows, cols = np.flatnonzero(ring.any(1)), np.flatnonzero(ring.any(0))
    assert seen == [(rows[-1] - rows[0] + 1, cols[-1] - cols[0] + 1)]
    assert seen[0][0] * seen[0][1] < 0.6 * blade.size
    monkeypatch.setattr(prepared_fill, "extend_nearest", real)
    np.testing.assert_array_equal(out, _reference_bleed(img, blade))


@pytest.mark.parametrize("two", [False, True])
def test_smooth_fill_keeps_known_pixels_and_matches_the_pyramid_blend(two):
    rng = np.random.default_rng(3)
    img = rng.random((37, 53) if two else (37, 53, 3)).astype(np.float32)
    known = ndi.gaussian_filter(rng.random((37, 53)), 3) > 0.5
    out = prepared._smooth_fill(img, known)
    assert out.dtype == np.float32 and out.shape == img.shape
    np.testing.assert_array_equal(out[known], img[known])
    # Unknown pixels lie within the known values' range (a convex blend of them).
    assert out[~known].min() >= img[known].min() - 1e-6 and out[~known].max() <= img[known].max() + 1e-6


def test_photo_is_not_flat_art_without_measuring_its_outline(monkeypatch):
    imgs, blades = zip(*[_leaf(seed=s) for s in range(3)])

    def forbidden(*args, **kwargs):
        raise AssertionError("outline measured on a photograph")

    monkeypatch.setattr(flatart.ndi, "distance_transform_edt", forbidden)
    assert flatart.flat_art(list(imgs), list(blades)) is None
