"""Issue 22: the analysis keeps its per-exemplar maps small with the same values; thin sketched veins;
a painted blade's outline band."""

import pickle

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.core.distance import edt
from branchnb.core.metrics import iou
from branchnb.leaves.analysis_induce import _closed_blade, _outline_band, thin_width
from branchnb.leaves.induction import spatial_term
from branchnb.leaves.induction_colour import colour_similarity, layer_cdfs
from branchnb.leaves.snapping import is_thin_layer
from branchnb.leaves.stored_maps import BoxedMaps, CombinedMaps, DistanceMaps


def _blade_in_pieces(h=100, w=110):
    b = np.zeros((h, w), bool)
    b[8:30, 10:40] = True
    b[40:55, 45:66] = True  # a second piece: the box holds rows and columns with no blade
    b[15:20, 20:25] = False  # a hole
    return b


@pytest.mark.parametrize("size", [1, 3, 6])
def test_colour_term_on_the_blades_box_is_the_whole_canvas_term(size):
    rng = np.random.default_rng(size)
    b = _blade_in_pieces()
    q = rng.integers(0, 12, b.shape + (3,)).astype(np.uint8)
    cdf = np.stack([layer_cdfs(q, b & (q[..., 0] < 4), 12), layer_cdfs(q, b & (q[..., 2] > 7), 12)])
    got = colour_similarity(q, b, cdf, size)
    # The same leaf on a canvas it fills to the edges (no box to cut) gives the same values.
    ys, xs = np.flatnonzero(b.any(1)), np.flatnonzero(b.any(0))
    sl = np.s_[ys[0]:ys[-1] + 1, xs[0]:xs[-1] + 1]
    ref = colour_similarity(np.ascontiguousarray(q[sl]), b[sl], cdf, size)
    assert np.array_equal(got[(slice(None),) + sl], ref)
    assert np.all(got[:, ~b] == 1.0)


def test_stored_maps_read_as_the_full_maps_and_pickle():
    rng = np.random.default_rng(0)
    blades = [_blade_in_pieces(), np.roll(_blade_in_pieces(), 5, axis=1)]
    colour = [np.where(b, rng.uniform(0, 1, b.shape), 1.0).astype(np.float32) for b in blades]
    layers = [b & (rng.uniform(size=b.shape) < 0.02) for b in blades]
    layers.append(np.zeros_like(blades[0]))  # an empty layer: 1e6 everywhere
    colour.append(np.ones(blades[0].shape, np.float32))
    eps = [7.0, 9.5, 3.0]
    c = BoxedMaps(colour, blades + [blades[0]], 1.0)
    d = DistanceMaps(layers)
    comb = CombinedMaps(0.37, c, d, eps)
    assert len(c) == len(d) == len(comb) == 3
    assert c.stored_bytes < 0.6 * sum(x.nbytes for x in colour)
    for e in range(3):
        dist = (edt(~layers[e]) if layers[e].any()  # the induction's distance map (core.distance.edt)
                else np.full(layers[e].shape, 1e6, np.float32))
        assert np.array_equal(c[e], colour[e])
        assert np.array_equal(d[e], dist)
        want = (np.float32(0.37) * spatial_term(dist, colour[e], eps[e]) + colour[e]).astype(np.float32)
        assert np.array_equal(comb[e], want)
    assert np.array_equal(c[-1], colour[2]) and [x.shape for x in c] == [x.shape for x in colour]
    back = pickle.loads(pickle.dumps(comb))
    assert np.array_equal(back[1], comb[1])
    with pytest.raises(IndexError):
        c[3]
    # A map that is not ``fill`` off its mask is kept whole (still the same values).
    odd = BoxedMaps([np.zeros((5, 5), np.float32)], [np.eye(5, dtype=bool)], 1.0)
    assert np.array_equal(odd[0], np.zeros((5, 5)))


def _curves(shape, width, n, rng, length):
    m = np.zeros(shape, bool)
    h, w = shape
    for _ in range(n):
        y, x = rng.uniform(0.2, 0.8) * h, rng.uniform(0.2, 0.8) * w
        a = rng.uniform(0, np.pi)
        t = np.linspace(-length / 2, length / 2, 4 * length)
        ys = np.clip(np.round(y + t * np.sin(a)).astype(int), 0, h - 1)
        xs = np.clip(np.round(x + t * np.cos(a)).astype(int), 0, w - 1)
        m[ys, xs] = True
    return ndi.binary_dilation(m, iterations=width // 2)


def test_wide_sketched_veins_are_thin_but_spots_are_not():
    """Ink veins 9 px wide (median 7.2) on a 400 px leaf (0.02 of its size) are snapped like a photo's
    2 px veins; a few short streaks of the same width stay spots."""
    rng = np.random.default_rng(3)
    blade = np.zeros((440, 440), bool)
    blade[20:420, 20:420] = True
    veins = _curves(blade.shape, 9, 8, rng, 200)
    streaks = _curves(blade.shape, 9, 3, rng, 60)
    assert not is_thin_layer(veins)  # the fixed 6 px limit
    assert thin_width(blade, veins) == pytest.approx(16.0)
    assert is_thin_layer(veins, max_width=thin_width(blade, veins))
    assert thin_width(blade, streaks) == 6.0
    assert thin_width(np.ones((100, 100), bool)) == 6.0


def test_outline_band_of_a_painted_blade_follows_its_outline_only():
    """Brush strokes with white gaps between them: the gaps' edges are not the leaf's outline."""
    yy, xx = np.mgrid[:200, :200]
    disk = (yy - 100) ** 2 + (xx - 100) ** 2 < 85 ** 2
    painted = disk.copy()
    for y0 in range(30, 170, 16):
        painted[y0:y0 + 4, 20:150] = False  # gaps open to the outside on the left
    user = np.zeros_like(disk)
    user[99:102, 60:140] = True
    assert _closed_blade(painted).sum() >= 0.99 * disk.sum()
    band = _outline_band(painted, user)
    far = ndi.distance_transform_edt(disk) > 10
    assert (band & far).sum() == 0
    assert (band & ~far).sum() > 0.8 * (painted & (ndi.distance_transform_edt(disk) <= 3)).sum()
    # A solid leaf's band is its own edge, as before (the closing adds a few pixels of a digital disk).
    solid = _outline_band(disk, user)
    assert iou(solid, disk & (ndi.distance_transform_edt(disk) <= 3)) > 0.95
