"""Issue 23, speed: the example side of image synthesis is kept for the next call with the same
example; results are exactly those of a cold call."""

from __future__ import annotations

import numpy as np

from branchnb.branching import image_synthesis as isy
from branchnb.branching._image_examples import random_tree, river_example


def test_second_render_of_an_example_reuses_its_preparation_with_the_same_result():
    img, src = river_example((128, 128), 0, n_children=3)
    targets = [random_tree((128, 128), k, n_children=3) for k in (7, 8)]
    cold = []
    for t in targets:
        isy._EXAMPLE_CACHE.clear()
        cold.append(isy.synthesize_image(img, src, t, rng=0).image)
    # warm: the cache holds the example side (and shape banks) of the last call
    warm = [isy.synthesize_image(img, src, t, rng=0) for t in targets]
    assert len(isy._EXAMPLE_CACHE) == 1
    for a, b in zip(cold, warm):
        np.testing.assert_array_equal(a, b.image)
    assert warm[1].timings["prepare"] < warm[1].timings["total"]
    # another example (one pixel changed) is prepared afresh
    img2 = img.copy()
    img2[0, 0] = 1.0 - img2[0, 0]
    key = next(iter(isy._EXAMPLE_CACHE))
    isy.synthesize_image(img2, src, targets[0], rng=0)
    assert len(isy._EXAMPLE_CACHE) == 1 and next(iter(isy._EXAMPLE_CACHE)) != key


def test_a_drawn_map_measures_its_layout_and_style_once(monkeypatch):
    # flat-colour examples: the example's region layout and drawing style depend on the example only
    from branchnb.branching import drawing
    from branchnb.branching._map_examples import river_map_example

    img, src, _land = river_map_example((128, 128), 0, n_trees=6)
    targets = [random_tree((128, 128), k, n_children=3) for k in (7, 8)]
    cold = []
    for t in targets:
        isy._EXAMPLE_CACHE.clear()
        cold.append(isy.synthesize_image(img, src, t, rng=0))
    calls = {"style": 0, "labels": 0}

    def counted(fn, key):
        def f(*a, **k):
            calls[key] += 1
            return fn(*a, **k)
        return f

    monkeypatch.setattr(drawing, "drawing_style", counted(drawing.drawing_style, "style"))
    monkeypatch.setattr(isy, "colour_labels", counted(isy.colour_labels, "labels"))
    warm = [isy.synthesize_image(img, src, t, rng=0) for t in reversed(targets)][::-1]
    assert calls == {"style": 0, "labels": 0}
    for a, b in zip(cold, warm):
        np.testing.assert_array_equal(a.image, b.image)
        np.testing.assert_array_equal(a.labels, b.labels)
