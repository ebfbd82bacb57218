"""Line contrast of synthesized images within 0.8-1.25x the example's (issue 23), at every size."""

from __future__ import annotations

import numpy as np
import pytest
from skimage.transform import resize

from branchnb import data
from branchnb.branching import extract_structure, synthesize_image, synthesize_structure
from branchnb.branching.line_contrast import centre_ring_contrast, match_line_contrast
from branchnb.branching.measures import line_contrast
from branchnb.branching.skeleton_map import SkeletonMap
from branchnb.core.structure import Branch, Structure


def _line(value=0.3):
    img = np.random.default_rng(0).normal(0.8, 0.02, (40, 40, 3)).astype(np.float32)
    img[19:21, 2:38] = value
    s = Structure([Branch([(2, 19.5), (37, 19.5)], 1.0)])
    return img, SkeletonMap(s, 1.0).pixel_map((40, 40))


@pytest.mark.parametrize("ref", [0.3, 0.5, 0.7])
def test_match_scales_a_too_strong_line_down_to_the_reference(ref):
    img, pm = _line()
    out, k = match_line_contrast(img, pm, ref)
    assert k < 1
    assert abs(centre_ring_contrast(out, pm) / ref - 1) < 0.03
    far = pm.dist > 4
    assert np.array_equal(out[far], img[far])          # the ground stays


def test_match_raises_a_pale_line_and_leaves_one_in_the_band():
    img, pm = _line(0.7)
    c = centre_ring_contrast(img, pm)
    out, k = match_line_contrast(img, pm, 2 * c)
    assert k > 1 and abs(centre_ring_contrast(out, pm) / (2 * c) - 1) < 0.03
    same, k1 = match_line_contrast(img, pm, 1.1 * c)
    assert k1 == 1.0 and np.array_equal(same, img)


def test_match_rejects_bad_arguments():
    img, pm = _line()
    with pytest.raises(ValueError, match="reference"):
        match_line_contrast(img, pm, -1.0)
    with pytest.raises(ValueError, match="low"):
        match_line_contrast(img, pm, 0.2, low=1.2)


@pytest.mark.parametrize("size,seed", [(128, 2), (256, 2)])
def test_small_retina_lines_as_contrasted_as_the_example(size, seed):
    # before: 1.57x (128 px) and 1.43x (256 px) with these seeds; the fragments' lines sit exactly
    # on the target's centre lines, the extracted example's a fraction of a pixel off its vessels
    img = resize(data.load("retina_fundus"), (size, size), anti_aliasing=True).astype(np.float32).clip(0, 1)
    ex = extract_structure(img)
    tgt = synthesize_structure(ex, rng=seed).structure
    out = synthesize_image(img, ex, tgt, rng=0)
    ratio = line_contrast(out.image, tgt) / line_contrast(img, ex)
    assert 0.8 <= ratio <= 1.25, ratio
    if size == 128:
        # the extracted centre lines lie on the vessels' crest (sub-pixel centring): along the skeleton
        # on pixel centres the example's own lines read 2.5x paler (0.012 against 0.030)
        flat = extract_structure(img, centre_reach=0.0)
        assert line_contrast(img, ex) >= 1.5 * line_contrast(img, flat)


def test_centring_moves_a_traced_line_onto_its_crest_and_keeps_junctions():
    from branchnb.branching.centring import centre_on_lines

    img = np.ones((40, 60), np.float32)
    img[20, :] = 0.0                      # a 1 px line on row 20
    img[:20, 30] = 0.0                    # a side line on column 30
    s = Structure([Branch([(x, 19.4) for x in range(2, 58, 4)], 0.5),
                   Branch([(30.0, 19.4), (30.6, 14), (30.6, 8), (30.6, 2)], 0.5, 0, 7)])
    c = centre_on_lines(img, s)
    assert np.allclose(c.branches[0].points[1:-1, 1], 20.0, atol=0.15)
    assert np.allclose(c.branches[1].points[1:, 0], 30.0, atol=0.15)
    assert np.array_equal(c.branches[1].points[0], c.branches[0].points[7])
    with pytest.raises(ValueError, match="polarity"):
        centre_on_lines(img, s, "grey")


def test_czech_map_keeps_its_relief_greys_and_dark_rivers():
    import cv2
    from scipy import ndimage as ndi

    from branchnb.branching import example_domain, fit_model

    full = np.asarray(data.load("czech_rivers_map"), np.float32)
    img = cv2.resize(full, (510, 298), interpolation=cv2.INTER_AREA)
    ex = extract_structure(img)
    res = synthesize_structure(fit_model(ex, domain=example_domain(img, ex)), rng=0)
    out = synthesize_image(img, ex, res, rng=0).image

    def opaque(a):
        return a[..., :3] * a[..., 3:] + (1 - a[..., 3:])

    e3, o3 = opaque(img), opaque(out)
    pm_e = SkeletonMap(ex, 1.0).pixel_map(img.shape[:2])
    pm_o = SkeletonMap(res.structure, 1.0).pixel_map(out.shape[:2])
    land_e, land_o = img[..., 3] >= 0.5, res.domain
    far_e, far_o = land_e & (pm_e.dist > 4), land_o & (pm_o.dist > 4)
    he = np.histogram(e3[far_e].mean(-1), 16, (0, 1))[0] / far_e.sum()
    ho = np.histogram(o3[far_o].mean(-1), 16, (0, 1))[0] / far_o.sum()
    assert 0.5 * np.abs(he - ho).sum() <= 0.15          # before: 0.48 (the land drawn plain white)
    # the rivers: darkest pixel across each centre-line pixel, median, like the example's
    dark_e = np.median(ndi.minimum_filter(e3.mean(-1), 3)[pm_e.dist <= 0.5])
    dark_o = np.median(ndi.minimum_filter(o3.mean(-1), 3)[(pm_o.dist <= 0.5) & land_o])
    assert dark_o <= dark_e + 0.05                       # before: 0.84 against 0.68
