"""Line contrast of synthesized images within 0.8-1.25x the example's (issue 23), at every size."""

from __future__ import annotations

import numpy as np
import pytest
from skimage.transform import resize

from branchnb import data
from branchnb.branching import extract_structure, synthesize_image, synthesize_structure
from branchnb.branching.image_synthesis import ImageSynthesisParams
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
    if size == 128:   # the case this is about: without the line contrast step, 1.3-1.6x
        off = synthesize_image(img, ex, tgt, ImageSynthesisParams(line_contrast=0.0), rng=0)
        assert line_contrast(off.image, tgt) / line_contrast(img, ex) > 1.25
