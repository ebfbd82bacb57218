"""Dendrites on objects (issue 25): a lightning bolt runs down a tree's trunk, vines are sized
to the object and follow its outline, and a drawn outline keeps its weight on a small input.

Procedural objects with known answers: trees (a lobed crown on a leaning trunk) on a sky, a
dark and a white ground, a body on four legs (no stem), a blob and an "E" at two fills of the
frame, and a light fill in a dark outline at 250 and 750 px.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from branchnb.dendrite import stylize
from branchnb.dendrite._small_check import master, stats
from branchnb.dendrite._trunk_check import tree, trunk_cover
from branchnb.dendrite._vine_size_check import shape
from branchnb.dendrite.main_channel import _channel_end, silhouette


@pytest.mark.parametrize("ground, n, seed", [("sky", 250, 1), ("dark", 500, 1), ("white", 500, 1)])
def test_lightning_runs_down_the_trunk(ground, n, seed):
    img, obj, trunk = tree(n, seed, ground)
    out = stylize(img, rng=seed, metaphor="lightning").rendering.image
    # main: 0.22 / 0.01 / 0.00 of the trunk's rows lit (the bolt stopped in the crown)
    assert trunk_cover(out, trunk, lit=True) > 0.9


def test_a_body_on_legs_has_no_stem():
    _, obj, _ = tree(400, 0, "legs")
    assert not _channel_end(silhouette(obj))[1]
    _, obj, _ = tree(400, 0, "sky")
    assert _channel_end(silhouette(obj))[1]


def _tips_per_outline(kind, fill, n):
    m = shape(kind, n, fill)
    img = np.repeat(np.where(m, 0.3, 1.0).astype(np.float32)[..., None], 3, axis=2)
    tips = len(stylize(img, rng=0, metaphor="vines").dendrite.tips)
    return tips / float((m & ~ndimage.binary_erosion(m)).sum())


def test_vines_on_a_small_object_are_as_dense_as_on_a_large_one():
    # tips per outline pixel: leaves and stems sized to the object, not to the frame
    big, small = _tips_per_outline("blob", "big", 1000), _tips_per_outline("blob", "small", 1000)
    assert small > 0.6 * big  # main: 0.079 against 0.195 (0.40)


def test_vines_on_a_letter_follow_its_outline():
    # an "E" of thin bars: ~one tip per leaf length of its outline (dendrite31: 0.58 per 6.5-px
    # leaf). Since dendrite35 the leaf drawn is 0.055 of the object's size (9.6 px here) and
    # the tips stop at twice the area's count (VINE_OUTLINE_CAP): 0.69 per leaf drawn
    from branchnb.dendrite import Stylizer

    m = shape("letter", 500, "big")
    st = Stylizer(np.repeat(np.where(m, 0.3, 1.0).astype(np.float32)[..., None], 3, axis=2))
    tips = len(st.run(rng=0, metaphor="vines").dendrite.tips)
    assert tips / float((m & ~ndimage.binary_erosion(m)).sum()) * st._vine_leaf > 0.65


def test_a_drawn_outline_keeps_its_weight_on_a_small_input():
    masters = {("light", 1): master("light", 1)}
    small, ref = stats("light", 250, 1, masters), stats("light", 750, 1, masters)
    ratio = (small["band"] / small["inner"]) / (ref["band"] / ref["inner"])
    assert ratio > 0.82  # main: 0.72 (outline band over interior ink, 250 against 750 px)
    assert abs(small["ink"] / ref["ink"] - 1) < 0.15

