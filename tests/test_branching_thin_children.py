"""Issue 23, masks with thick trunks and many thin children that cover part of their frame.

An unseen random-walk crack mask (260 x 380, a few 3-4 px trunks with many 1-px side cracks in the
lower part of the frame) grew over the upper half the example leaves empty: for a mask with one
region (lines on a plain ground) :func:`~branchnb.branching.example_domain` returned the whole frame.
The part a large line-free disk fits in is now outside the domain
(:func:`~branchnb.branching.empty_ground._empty_part`), but it is no hole to fill and no coast
(``StructureModel.ground``): with it counted as a region outside, a wavy vine grew to 1.3 x its length.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._thin_children_check import comb_mask, figures
from branchnb.branching._thin_mask_check import thin_mask_example


def _rgb(m, dark=True):
    img = (1.0 - m if dark else m)[..., None] * np.ones(3, np.float32)
    return img.astype(np.float32)


@pytest.mark.parametrize("seed", [1, 2])
def test_partial_crack_mask_domain_leaves_the_empty_part_out(seed):
    m = comb_mask(380, seed, partial=True)
    img = _rgb(m)
    dom = example_domain(img)
    lines = m > 0.5
    far = ndi.distance_transform_edt(~lines) > 0.1 * min(m.shape)
    # the upper part the example leaves empty is out, every line and its surroundings in
    top = far[: int(0.3 * m.shape[0])]
    assert (~dom[: int(0.3 * m.shape[0])])[top].mean() > 0.95
    assert dom[lines].all()
    assert dom[ndi.binary_dilation(lines, iterations=5)].mean() > 0.99


@pytest.mark.parametrize("kind", ["crack", "vessel"])
def test_anti_aliased_masks_get_the_binary_masks_domain(kind):
    # drawn at 4 x and averaged down, either polarity: the empty part of the binary mask's domain
    dom = example_domain(thin_mask_example(kind, 300, 0))
    assert 0.2 < 1.0 - dom.mean() < 0.8
    for dark in (True, False):
        img = thin_mask_example(kind, 300, 0, aa=True, dark=dark)
        d2 = example_domain(img, extract_structure(img))
        assert np.mean(d2 == dom) > 0.97


def test_network_that_fills_its_frame_keeps_the_whole_frame():
    # a mesh of lines (mud-like cells, 60 px) over the whole frame: no empty part
    m = np.zeros((200, 300), np.float32)
    rng = np.random.default_rng(0)
    for x in range(0, 300, 60):
        cv2.line(m, (x + int(rng.integers(0, 20)), 0), (x + int(rng.integers(0, 20)), 199), 1.0, 2)
    for y in range(0, 200, 60):
        cv2.line(m, (0, y + int(rng.integers(0, 20))), (299, y + int(rng.integers(0, 20))), 1.0, 1)
    assert example_domain(_rgb(m)).all()


def test_partial_crack_mask_output_stays_where_the_example_is():
    # main: 48-75 % of the synthesized length lay > 8 % of the short side from every example line
    img = _rgb(comb_mask(300, 0, partial=True))
    ex = extract_structure(img)
    model = fit_model(ex, domain=example_domain(img, ex))
    # the empty part is ground, not a coast: coverage, holes and the length cap read the whole frame
    assert model.ground is not None and model.region is None
    res = synthesize_structure(model, rng=0)
    f = figures(img, ex, res.structure)
    assert f["out"] < 0.2 and f["out15"] < 0.05
    assert 0.85 < f["len"] < 1.15
    assert 0.7 < f["nb"] < 1.5
    # the output's regions are the example's one region: no sea where the ground is
    assert res.domain.all()
