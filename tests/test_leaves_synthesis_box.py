"""A new leaf is computed on its work box (the lamina, a margin, the petiole), and is the same leaf.

Measured (``branchnb bench`` set-up, 4 procedural lobed exemplars, interleaved CPU A/B): see the
synthesis row of :mod:`branchnb.leaves._bench_layers`; 24 leaves at 0.25/1.12/1.9 MP bit-identical.
"""

import numpy as np
import pytest

from branchnb.leaves import analyze, leaf_family, synthesis


@pytest.fixture(scope="module")
def small_leaf_analysis():
    fam = leaf_family(2, size=96, kind="lobed", rng=2)
    # Each exemplar on a canvas three times its size: a new leaf covers a small part of it.
    ex = []
    for leaf in fam:
        img = np.zeros((3 * leaf.image.shape[0], 3 * leaf.image.shape[1], 4), np.float32)
        h, w = leaf.image.shape[:2]
        img[h:2 * h, w:2 * w] = leaf.image
        ex.append(img)
    veins = np.zeros(ex[0].shape[:2], bool)
    veins[h:2 * h, w:2 * w] = fam[0].layers["veins"]
    return analyze(ex, 0, {"veins": veins})


def test_the_maps_of_a_leaf_cover_its_box_not_the_canvas(small_leaf_analysis):
    a = small_leaf_analysis
    p = synthesis._prepared(a)
    shapes, orig = [], p.source_coords

    def spy(e, m, d):
        shapes.append(m.shape[:2])
        return orig(e, m, d)
    p.source_coords = spy
    try:
        leaf = synthesis.generate_leaf(a, 3)
    finally:
        p.source_coords = orig
    canvas = leaf.image.shape[0] * leaf.image.shape[1]
    ys, xs = np.nonzero(leaf.image[..., 3] > 0)
    drawn = (np.ptp(ys) + 1) * (np.ptp(xs) + 1)
    assert shapes and all(h * w <= 0.6 * canvas for h, w in shapes)
    assert all(h * w >= drawn for h, w in shapes)
    # The spying measurements see the coordinates on the whole canvas.
    full = synthesis._canvas_coords(p, np.zeros(shapes[0] + (2,), np.float32))
    assert full.shape[:2] == leaf.image.shape[:2]


@pytest.mark.parametrize("seed", [0, 5])
def test_the_leaf_on_its_box_is_the_leaf_on_the_canvas(small_leaf_analysis, monkeypatch, seed):
    a = small_leaf_analysis
    boxed = synthesis.generate_leaf(a, seed)
    monkeypatch.setattr(synthesis, "_BOX", False)
    whole = synthesis.generate_leaf(a, seed)
    assert np.array_equal(boxed.image, whole.image)
    assert boxed.record() == whole.record()
