"""Issue 23, connected output on photographs: every synthesized tree is one line judged against its
local ground (a global colour threshold breaks the example's own retina vessels into ~50 pieces)."""

from __future__ import annotations

import numpy as np
import pytest
from skimage.transform import resize

from branchnb import data
from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_image, synthesize_structure
from branchnb.branching._image_examples import cracked_mud_example, river_example
from branchnb.branching.measures import relative_line_pieces
from branchnb.core.structure import Branch, Structure


def _retina():
    img = data.load("retina_fundus")
    return resize(img, (256, 256), anti_aliasing=True).astype(np.float32).clip(0, 1)


KINDS = {"retina256": _retina,
         "river224": lambda: river_example((224, 224), 0, n_children=4)[0],
         "mud160": lambda: cracked_mud_example((160, 160), 3)[0]}


@pytest.mark.parametrize("kind", list(KINDS))
def test_each_synthesized_tree_is_one_line(kind):
    img = KINDS[kind]()
    ex = extract_structure(img)
    res = synthesize_structure(fit_model(ex, domain=example_domain(img, ex)), rng=1)
    out = synthesize_image(img, ex, res, rng=0)
    m = relative_line_pieces(img, ex, out.image, res.structure)
    assert m["trees"] >= 1 and m["max_pieces"] == 1 and m["gaps"] == 0 and m["specks"] == 0, m


def test_relative_pieces_find_a_pale_gap_on_a_shaded_ground():
    y, x = np.mgrid[0:48, 0:64]
    img = np.dstack([0.5 + 0.4 * x / 63.0] * 3).astype(np.float32)       # ground shaded left to right
    img[23:25, 2:62] -= 0.25
    s = Structure([Branch([(2, 23.5), (61, 23.5)], 1.0)])
    assert relative_line_pieces(img, s, img, s)["max_pieces"] == 1
    gap = img.copy()
    gap[23:25, 30:34] += 0.25
    m = relative_line_pieces(img, s, gap, s)
    assert m["max_pieces"] == 2 and m["gaps"] == 1, m
