"""Mixes of anti-aliased trees get an anti-aliased rim, their opaque set unchanged (issue 24).

Before, a mix's alpha was 0 / 1 (the exemplars thresholded at 0.5, as in the paper): none of its
rim pixels was partial while 45-70 % of the sources' were. Pixel art and hard-edged sources stay
hard (test_trees_pixel_art checks that the sprites' mixes keep alpha 0 / 1).
"""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.trees import variations
from branchnb.trees._measure_rim import blob_tree
from branchnb.trees._measure_soft_rim import _band, soft_share
from branchnb.trees.drawn import drawn_tree
from branchnb.trees.quality import crossfade_fraction, soft_alpha_fraction
from branchnb.trees.rim_alpha import exemplar_rim_width, rim_width, soft_rim
from branchnb.trees.variations import TreeLibrary, make_variation

SIZE = 128


@pytest.fixture(scope="module")
def lib():
    # drawn trees: supersampled, anti-aliased
    lib = TreeLibrary(size=SIZE)
    for i, k in enumerate(("broadleaf", "conifer", "fruit")):
        lib.add(drawn_tree(k, rng=i, size=2 * SIZE), k)
    return lib


@pytest.fixture(scope="module")
def pairs(lib):
    out = []
    for seed in (0, 1):
        hard = variations.soft_rim
        variations.soft_rim = lambda img, *a, **k: img
        try:
            before = make_variation(lib, rng=seed)
        finally:
            variations.soft_rim = hard
        out.append((before, make_variation(lib, rng=seed)))
    return out


def test_opaque_set_and_colours_unchanged(pairs, lib):
    srcs = [e.image for e in lib.exemplars]
    for before, after in pairs:
        op = before.image[..., 3] >= 0.5
        assert np.array_equal(op, after.image[..., 3] >= 0.5)
        assert np.array_equal(before.sources, after.sources) and np.array_equal(before.parts, after.parts)
        # opaque pixels keep their colour
        assert np.array_equal(before.image[op, :3], after.image[op, :3])
        assert abs(crossfade_fraction(before.image, srcs) - crossfade_fraction(after.image, srcs)) < 0.005


def test_rim_is_anti_aliased(pairs):
    for before, after in pairs:
        op = before.image[..., 3] >= 0.5
        assert soft_share(before.image[..., 3], op) == 0.0
        assert soft_share(after.image[..., 3], op) > 0.4           # sources 0.45 (measured)
        # only the pixel either side of the edge changes: a clean cut-out inside
        assert np.array_equal(before.image[..., 3][~_band(op)], after.image[..., 3][~_band(op)])
        assert soft_alpha_fraction(after.image) == 0.0


def test_no_fringe(pairs):
    # soft pixels outside carry the nearest opaque colour: over white and black backdrops the
    # rim is that colour at its alpha (a transparent pixel's black would darken it over white)
    for _, after in pairs:
        img = after.image
        a = img[..., 3]
        op = a >= 0.5
        out = (a > 0) & ~op
        assert out.any()
        iy, ix = ndi.distance_transform_edt(~op, return_distances=False, return_indices=True)
        near = img[..., :3][iy[out], ix[out]]
        assert np.abs(img[out, :3] - near).max() < 1e-6
        for bg in (0.0, 1.0):
            comp = img[out, :3] * a[out, None] + bg * (1 - a[out, None])
            want = near * a[out, None] + bg * (1 - a[out, None])
            assert np.abs(comp - want).max() < 1e-6


def test_rim_closer_to_sources_own_alpha(lib):
    # the exemplars' binary silhouettes given the soft rim are closer to their sources' own soft
    # alpha (mean |difference| on the rim)
    err = []
    for e in lib.exemplars:
        op = e.image[..., 3] >= 0.5
        b, sa = _band(op), e.normalized.soft_alpha
        w = exemplar_rim_width(e)
        assert 1.0 <= w <= 2.0, w
        soft = soft_rim(e.image, [w])[..., 3]
        err.append((np.abs(op[b] - sa[b]).mean(), np.abs(soft[b] - sa[b]).mean()))
    err = np.array(err).mean(axis=0)
    assert err[1] < 0.75 * err[0], err          # measured 0.126 -> 0.077


def test_hard_edged_sources_stay_hard():
    # binary-alpha drawings (smoothly resized to the working size, so their working alpha is soft)
    lib = TreeLibrary(size=SIZE)
    for i, (k, h) in enumerate([("round", 300), ("lobed", 420), ("tall", 260)]):
        lib.add(blob_tree(k, "flat", i, h), k)
    assert all(e.normalized.rim_softness == 0.0 and exemplar_rim_width(e) == 0.0 for e in lib.exemplars)
    a = make_variation(lib, rng=0).image[..., 3]
    assert set(np.unique(a).tolist()) <= {0.0, 1.0}


def test_soft_rim_of_a_disc():
    yy, xx = np.mgrid[:64, :64]
    op = np.hypot(xx - 32, yy - 30) < 20.3
    img = np.zeros((64, 64, 4), np.float32)
    img[op] = (0.2, 0.6, 0.2, 1.0)
    assert rim_width(op, op.astype(np.float32)) == 0.0 and rim_width(op, None) == 0.0
    assert soft_rim(img, [1.2, 0.0]) is img or np.array_equal(soft_rim(img, [1.2, 0.0]), img)
    soft = soft_rim(img, [1.2])
    assert np.array_equal(soft[..., 3] >= 0.5, op) and soft_share(soft[..., 3], op) > 0.3
    # a 1-px line keeps its alpha (it would blur under 0.5)
    img[5, 5:60] = (0, 0, 0, 1)
    assert (soft_rim(img, [1.2])[5, 8:57, 3] == 1.0).all()
    with pytest.raises(ValueError, match="image"):
        soft_rim(img[..., :3], [1.0])
    with pytest.raises(ValueError, match="weights"):
        soft_rim(img, [1.0, 1.0], [1.0])
