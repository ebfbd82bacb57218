"""Flat-art colour transfer keeps its per-source maps (issue 24, trees37): same result, made once."""

import numpy as np
import pytest

from branchnb.trees import TreeLibrary
from branchnb.trees import mvc_strokes as ms
from branchnb.trees.mvc import transfer_colour


@pytest.fixture(scope="module")
def lib():
    return TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06", "tree_with_fruits"], size=128)


def _same(a, b):
    return (np.array_equal(a.image, b.image) and np.array_equal(a.sources, b.sources)
            and np.array_equal(a.parts, b.parts))


def _fresh(lib):
    for e in lib.exemplars:
        e._cages.pop("stroke_maps", None)


def test_kept_maps_give_the_same_variation_bit_for_bit(lib):
    for seed in (0, 1, 2):
        _fresh(lib)
        first = lib.variation(rng=seed)
        kept = {e.name: e._cages.get("stroke_maps") for e in lib.exemplars}
        again = lib.variation(rng=seed)
        assert _same(first, again)
        # the second call reused the maps it found (no source's maps were made again)
        for e in lib.exemplars:
            if kept[e.name] is not None:
                assert e._cages["stroke_maps"] is kept[e.name]
    assert any("stroke_maps" in e._cages for e in lib.exemplars)


def test_transfer_colour_with_a_store_equals_without(lib):
    ex = [lib["tree_rpg_05"], lib["tree_rpg_06"]]
    target = ex[1]
    store = [{}, {}]
    args = ([e.image for e in ex], [e.cage(20) for e in ex], target.cage(20), target.alpha)
    kw = dict(colour_weights=[0.5, 0.5], mode="choose", rng=3)
    plain = transfer_colour(*args, **kw)
    kept = transfer_colour(*args, **kw, _maps=store)
    again = transfer_colour(*args, **kw, _maps=store)
    assert np.array_equal(plain, kept) and np.array_equal(plain, again)
    assert all(isinstance(d.get("stroke_maps"), ms._StrokeMaps) for d in store)
    # maps kept for another source object are not used for this one
    other = [e.image.copy() for e in ex]
    m0 = store[0]["stroke_maps"]
    transfer_colour(other, *args[1:], **kw, _maps=store)
    assert store[0]["stroke_maps"] is not m0 and store[0]["stroke_maps"].key is other[0]


def test_cropped_maps_sample_like_the_whole_map():
    rng = np.random.default_rng(0)
    img = np.zeros((60, 70, 4), np.float32)
    img[20:35, 25:50] = rng.uniform(0, 1, (15, 25, 4))
    crop = ms._Crop(img, img[..., 3] > 0)
    assert crop.img.shape[:2] == (15 + 2 * ms._MARGIN, 25 + 2 * ms._MARGIN)
    pts = np.concatenate([rng.uniform(-5, 75, (4000, 2)), rng.uniform(18, 52, (4000, 2)),
                          np.array([[1e-7, 1e-7], [-0.3, 40.0], [1e5, -1e5]])])
    assert np.array_equal(crop.sample(pts), ms._remap(img, pts))


def _footprint_grid(mapped, ys, xs, shape):
    """The former nan-grid differences over the whole image (reference)."""
    g = np.full(shape + (2,), np.nan)
    g[ys, xs] = mapped
    out = []
    for axis in (1, 0):
        fwd = np.full_like(g, np.nan)
        bwd = np.full_like(g, np.nan)
        if axis == 1:
            fwd[:, :-1] = g[:, 1:] - g[:, :-1]
            bwd[:, 1:] = g[:, 1:] - g[:, :-1]
        else:
            fwd[:-1] = g[1:] - g[:-1]
            bwd[1:] = g[1:] - g[:-1]
        d = np.where(np.isnan(fwd), bwd, fwd)[ys, xs]
        d[np.isnan(d).any(axis=1)] = [1.0, 0.0] if axis == 1 else [0.0, 1.0]
        out.append(d)
    return out


def test_footprint_on_the_box_equals_the_whole_grid():
    rng = np.random.default_rng(1)
    mask = rng.uniform(size=(40, 50)) < 0.6
    mask[0, :] = True
    mask[:, -1] = True
    ys, xs = np.nonzero(mask)
    mapped = np.stack([xs * 1.3 + rng.normal(0, 0.2, len(xs)), ys * 0.7 + 0.1 * xs], axis=1)
    for a, b in zip(ms._footprint(mapped, ys, xs, mask.shape), _footprint_grid(mapped, ys, xs, mask.shape)):
        assert np.array_equal(a, b)
    one = ms._footprint(np.array([[3.0, 4.0]]), np.array([5]), np.array([6]), (10, 10))
    assert one[0].tolist() == [[1.0, 0.0]] and one[1].tolist() == [[0.0, 1.0]]
