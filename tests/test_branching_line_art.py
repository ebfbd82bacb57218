"""Extraction on drawn trees: the coloured branching shape, not the crown's outline or the grass."""
import numpy as np
import pytest

from branchnb.branching import extract_structure
from branchnb.branching._line_art_examples import TRUNK, drawn_tree_example
from branchnb.branching._map_examples import line_scores
from branchnb.branching.extraction import thin_line_colour


@pytest.mark.parametrize("size", [128, 200, 320, 640])
def test_drawn_tree_extraction_follows_the_trunk_colour(size):
    img, tree = drawn_tree_example(size, rng=1)
    assert np.allclose(thin_line_colour(img), TRUNK, atol=0.03)
    p, r, _ = line_scores(extract_structure(img), tree)
    p0, r0, _ = line_scores(extract_structure(img, line_colour=None), tree)
    # brightness ridges follow the crown's dark rim and the grass blades (precision 0.13-0.3)
    assert p >= 0.9 and r >= 0.65, (p, r)
    assert p >= p0 + 0.5, (p, p0)


def test_wide_drawn_trunk_is_one_tree_through_the_ground_line():
    img, tree = drawn_tree_example(640, rng=2)
    s = extract_structure(img)
    assert sum(b.parent is None for b in s.branches) == 1
    pts = np.concatenate([b.points for b in s.branches])
    ys = pts[:, 1]
    # the trunk crosses the grass line: crown branches and roots in one structure
    assert ys.min() < 0.3 * 640 and ys.max() > 0.75 * 640


def test_branches_running_through_a_second_region_get_no_halo_of_the_first():
    from branchnb.branching.regions import target_layout
    from branchnb.core.structure import Branch, Structure

    lay = np.zeros((120, 160), np.int32)
    lay[:, 90:] = 1                              # ground left, a crown right: branches run through both
    ex = Structure([Branch([(5, y), (155, y + 6)], 1.5) for y in (20, 50, 80, 100)])
    tgt = Structure([Branch([(5, y), (155, y - 8)], 1.5) for y in (30, 60, 95)])
    out = target_layout(lay, ex, tgt, (120, 160))
    body = np.zeros((120, 160), bool)
    for b in tgt.branches:
        import cv2
        cv2.polylines(body.view(np.uint8), [np.round(b.points).astype(np.int32).reshape(-1, 1, 2)], False, 1, 3)
    right = body.copy()
    right[:, :110] = False                        # well inside the second region
    assert np.mean(out[right] == 1) >= 0.9, np.mean(out[right] == 1)


def _inked_share(image, structure, line=(0.1, 0.1, 0.1), background=(1.0, 1.0, 1.0)):
    """Share of the structure's centre-line points with ink within one pixel."""
    from scipy import ndimage as ndi

    from branchnb.core.polyline import resample_uniform

    span = np.linalg.norm(np.subtract(line, background))
    inked = ndi.minimum_filter(np.linalg.norm(image[..., :3] - np.asarray(line), axis=-1), 3) <= 0.5 * span
    h, w = inked.shape
    hits = []
    for b in structure.branches:
        if len(b.points) < 2 or b.length < 2:
            continue
        q = resample_uniform(b.points, 1.0)
        ix = np.clip(np.rint(q[:, 0]).astype(int), 0, w - 1)
        iy = np.clip(np.rint(q[:, 1]).astype(int), 0, h - 1)
        hits.append(inked[iy, ix])
    return float(np.mean(np.concatenate(hits)))


def test_synthesized_crack_drawing_keeps_its_lines_whole():
    from branchnb.branching import example_domain, fit_model, synthesize_image, synthesize_structure
    from branchnb.branching._line_art_examples import crack_drawing_example

    img = crack_drawing_example(256, rng=3, cells=60)
    s = extract_structure(img)
    model = fit_model(s, domain=example_domain(img, s))
    target = synthesize_structure(model, rng=0).structure
    out = synthesize_image(img, s, target, rng=0).image
    # fragments alone left the lines dashed (0.62 of the centre line with ink)
    assert _inked_share(out, target) >= 0.97, _inked_share(out, target)
