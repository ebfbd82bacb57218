"""Extraction on drawn trees: the coloured branching shape, not the crown's outline or the grass."""
import numpy as np
import pytest

from branchnb.branching import extract_structure
from branchnb.branching._drawn_tree_examples import TRUNK, drawn_tree_example
from branchnb.branching._map_examples import line_scores
from branchnb.branching.extraction import thin_line_colour


@pytest.mark.parametrize("size", [200, 320, 640])
def test_drawn_tree_extraction_follows_the_trunk_colour(size):
    img, tree = drawn_tree_example(size, rng=1)
    assert np.allclose(thin_line_colour(img), TRUNK, atol=0.03)
    p, r, _ = line_scores(extract_structure(img), tree)
    p0, r0, _ = line_scores(extract_structure(img, line_colour=None), tree)
    # brightness ridges follow the crown's dark rim and the grass blades (precision 0.13-0.3)
    assert p >= 0.95 and r >= 0.7, (p, r)
    assert p >= p0 + 0.5, (p, p0)


def test_wide_drawn_trunk_is_one_tree_through_the_ground_line():
    img, tree = drawn_tree_example(640, rng=2)
    s = extract_structure(img)
    assert sum(b.parent is None for b in s.branches) == 1
    pts = np.concatenate([b.points for b in s.branches])
    ys = pts[:, 1]
    # the trunk crosses the grass line: crown branches and roots in one structure
    assert ys.min() < 0.3 * 640 and ys.max() > 0.75 * 640
