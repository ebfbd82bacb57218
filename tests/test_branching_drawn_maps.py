"""Issue 23 on procedural examples with known answers: drawn country maps (flat land and sea, black
rivers of one width, a black coast) and a binary delta mask, through the default workflow."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import (
    example_domain,
    extract_structure,
    fit_model,
    synthesize_image,
    synthesize_structure,
)
from branchnb.branching._map_examples import country_map_example, delta_mask_example, line_scores
from branchnb.branching.measures import (
    boundary_drawn_share,
    far_share,
    line_pieces,
    root_boundary_distance,
    thick_end_share,
)
from branchnb.core.render import coverage_polylines

LAYOUTS = [("island", 384), ("coast", 320), ("bay", 352)]


def _workflow(layout, size, seed=1):
    img, truth, land = country_map_example((size, size), seed, layout=layout)
    ex = extract_structure(img)
    dom = example_domain(img, ex)
    return img, truth, land, ex, dom, fit_model(ex, domain=dom)


@pytest.fixture(scope="module", params=LAYOUTS, ids=[lay for lay, _ in LAYOUTS])
def drawn(request):
    return _workflow(*request.param)


def test_domain_of_a_drawn_map_is_its_land(drawn):
    _img, _truth, land, _ex, dom, _model = drawn
    assert (dom & land).sum() / (dom | land).sum() >= 0.93


def test_map_examples_keep_the_frame_as_drawn():
    # an island's sea reaches the frame (no ring of land, no coast drawn along the frame);
    # a coast map's land runs off the frame up to its corners
    img, _s, land = country_map_example((200, 200), 3, layout="island")
    frame = np.r_[land[0], land[-1], land[:, 0], land[:, -1]]
    assert not frame.any()
    assert np.abs(img[:3] - img[0, 100]).max() < 1e-6          # the top rows are plain sea
    _img, _s, land = country_map_example((200, 200), 3, layout="coast")
    assert land[0, 0] and land[0, -1] and land[:10].all()


@pytest.mark.parametrize("layout, size", [("island", 384), ("coast", 700), ("bay", 700)])
def test_rivers_are_found_not_the_coast(layout, size):
    # (on maps of 320-512 px, 1.5 px lines, recall is still only 0.59-0.77: see the report)
    img, truth, _land = country_map_example((size, size), 1, layout=layout)
    ex = extract_structure(img)
    cov, _ = coverage_polylines(img.shape[:2], [b.points for b in truth.branches],
                                [np.full(len(b.points), 2.0) for b in truth.branches])
    precision, recall, _ = line_scores(ex, cov > 0.3)
    assert precision >= 0.95 and recall >= 0.85, (precision, recall)


def test_default_roots_are_outlets_at_the_coast(drawn):
    # one line width everywhere: "thickest" would be arbitrary; the rivers drain where they meet the sea
    _img, _truth, _land, ex, dom, model = drawn
    lim = max(12.0, 0.015 * np.hypot(*dom.shape))
    assert np.median(root_boundary_distance(ex, dom)) <= lim
    for seed in (0, 1):
        s = synthesize_structure(model, rng=seed).structure
        assert np.median(root_boundary_distance(s, dom)) <= lim + 4


def test_coverage_like_the_example_in_every_seed(drawn):
    _img, _truth, _land, ex, dom, model = drawn
    target = far_share(model.example, dom)
    for seed in (0, 1, 2):
        s = synthesize_structure(model, rng=seed).structure
        assert far_share(s, dom) <= 1.5 * target + 0.01, (seed, far_share(s, dom), target)


def test_no_empty_coast_lobes_on_a_densely_drawn_island():
    # the coverage target (share within rho) was met with branches crowded in the middle and empty
    # lobes along the coast: 2-4x the example's far share before the hole filling (issue 23)
    img, _truth, _land = country_map_example((600, 600), 1, layout="island", n_trees=30)
    ex = extract_structure(img)
    dom = example_domain(img, ex)
    model = fit_model(ex, domain=dom)
    target = far_share(model.example, dom)
    s = synthesize_structure(model, rng=1).structure
    assert far_share(s, dom) <= 1.5 * target, (far_share(s, dom), target)


def test_branches_start_no_thinner_than_they_run_on_wide_lines():
    # lines of 4 px: extracted heads read thin at junctions and at the coast; copied into the
    # output they made 18-40 % of the branches end more than 2 x thicker than they start (issue 23)
    img, _truth, _land = country_map_example((448, 448), 2, layout="coast", line_width=4.0)
    ex = extract_structure(img)
    model = fit_model(ex, domain=example_domain(img, ex))
    for seed in (0, 1):
        assert thick_end_share(synthesize_structure(model, rng=seed).structure) <= thick_end_share(ex) + 0.05


def test_lifted_heads_keep_thick_heads_and_shapes():
    from branchnb.branching.synthesis import _lift_child_heads
    from branchnb.core.structure import Branch, Structure

    root = Branch(np.c_[np.arange(0, 60, 4.0), np.zeros(15)], np.r_[0.6, 0.9, np.full(13, 2.0)])
    kid = Branch(np.c_[np.full(10, 20.0), np.arange(0, 40, 4.0)], np.r_[0.5, 0.8, 1.2, np.full(7, 1.5)], 0, 5)
    fat = Branch(np.c_[np.full(10, 40.0), np.arange(0, 40, 4.0)], np.r_[3.0, np.full(9, 1.0)], 0, 10)
    out = _lift_child_heads(Structure([root, kid, fat]))
    assert np.allclose(out.branches[0].thickness[:2], 2.0)          # the root's body
    assert np.allclose(out.branches[1].thickness[:3], 1.5)          # min(its body, its parent)
    np.testing.assert_array_equal(out.branches[2].thickness, fat.thickness)   # thick heads stay
    np.testing.assert_array_equal(out.branches[1].points, kid.points)


def test_drawn_map_image_connected_rivers_coast_and_land(drawn):
    img, _truth, land_ex, ex, dom, model = drawn
    res = synthesize_structure(model, rng=0)
    out = synthesize_image(img, ex, res, rng=0)
    ink, ground = np.zeros(3), np.median(img[dom], axis=0)
    pieces = line_pieces(out.image, res.structure, ink, ground)
    assert pieces["max_pieces"] == 1 and pieces["specks"] == 0, pieces   # one stroke per tree
    land = out.labels == np.bincount(out.labels[dom]).argmax()
    assert (land & res.domain).sum() / (land | res.domain).sum() >= 0.95
    assert boundary_drawn_share(out.image, land, ink, ground) >= 0.9      # along its own coast
    assert boundary_drawn_share(img, land_ex, ink, ground) >= 0.9   # (as in the example)


@pytest.fixture(scope="module")
def delta():
    mask, channels, sea = delta_mask_example((320, 320), 2)
    ex = extract_structure(mask)
    dom = example_domain(mask)
    return mask, sea, ex, dom, fit_model(ex, domain=dom)


def test_delta_grows_from_its_inland_trunk_to_the_sea(delta):
    mask, sea, ex, dom, model = delta
    from scipy import ndimage as ndi

    depth = ndi.distance_transform_edt(dom)
    root = next(b for b in ex.branches if b.parent is None)
    assert root.points[0, 1] <= 6 and root.thickness[0] >= 0.8 * root.thickness.max()  # the trunk, at the frame
    assert model.drains
    for seed in (0, 1):
        s = synthesize_structure(model, rng=seed).structure
        roots = [b for b in s.branches if b.parent is None]
        assert len(roots) == 1 and depth[int(roots[0].points[0, 1]), int(roots[0].points[0, 0])] > 0.8 * depth.max()
        def at(p):
            return depth[int(np.clip(p[1], 0, 319)), int(np.clip(p[0], 0, 319))]

        # downstream: the trunk heads for the sea, the network gets at least half way there
        assert at(roots[0].points[-1]) < at(roots[0].points[0]) - 0.3 * depth.max()
        assert min(at(b.points[-1]) for b in s.branches) < 0.5 * depth.max()
        assert thick_end_share(s) <= thick_end_share(ex) + 0.05


def test_delta_image_keeps_the_sea_and_no_frame_edges(delta):
    mask, sea, ex, dom, model = delta
    res = synthesize_structure(model, rng=0)
    out = synthesize_image(np.dstack([mask] * 3), ex, res, rng=0).image[..., 0]
    assert np.mean(out[sea] > 0.5) >= 0.99                       # the sea where the structure's domain ends
    body, _ = coverage_polylines(mask.shape, [b.points for b in res.structure.branches],
                                 [2 * b.thickness + 4 for b in res.structure.branches])
    stray = (out > 0.5) & (body < 0.01) & ~sea
    assert stray.sum() <= 0.01 * (body > 0.5).sum()               # water only along the channels
    lp = line_pieces(np.dstack([out] * 3), res.structure, np.ones(3), np.zeros(3))
    assert lp["max_pieces"] == 1
