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
from branchnb.core.structure import Structure

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


def _frame_share(structure, shape, sea_side, skip=12.0, margin=8.0):
    """Share of the branches' length within ``margin`` px of a frame side that is not the sea's
    (a root's first ``skip`` px, where it enters through the frame, not counted)."""
    h, w = shape
    near = total = 0.0
    for b in structure.branches:
        p = b.points
        seg = np.hypot(*np.diff(p, axis=0).T)
        mid = 0.5 * (p[1:] + p[:-1])
        d = {"top": mid[:, 1], "bottom": h - 1 - mid[:, 1], "left": mid[:, 0], "right": w - 1 - mid[:, 0]}
        fd = np.min([v for k, v in d.items() if k != sea_side], axis=0)
        arc = np.cumsum(seg)
        keep = arc > skip if b.parent is None else np.ones(len(seg), bool)
        near += seg[keep & (fd < margin)].sum()
        total += seg.sum()
    return near / total


@pytest.mark.parametrize("sea_side, seed", [("bottom", 1), ("right", 1), ("bottom", 4)])
def test_delta_trunk_enters_inland_and_keeps_off_the_frame(sea_side, seed):
    # a wide channel cut by the frame: its medial axis bends into a corner of the cut, and the
    # synthesized trunk copied that bend and ran along the frame (before: 27-88 % of the trunk
    # within 8 px of a side that is not the sea, on these three; 15 % of 48 runs over 20 %)
    mask, _ch, sea = delta_mask_example((512, 512), seed)
    if sea_side == "right":
        mask, sea = np.ascontiguousarray(mask.T), np.ascontiguousarray(sea.T)
    ex = extract_structure(mask, root="nearest_region")
    model = fit_model(ex, domain=example_domain(mask))
    assert abs(float(model.roots.offsets[0])) < 0.5          # the trunk enters along its channel
    s = synthesize_structure(model, rng=1).structure
    trunk = Structure([b for b in s.branches if b.parent is None][:1], image_shape=s.image_shape)
    assert _frame_share(trunk, mask.shape, sea_side) <= 0.02
    assert _frame_share(s, mask.shape, sea_side) <= 0.05


def _recall_on(structure, ref, off=(0, 0), tol=4.0):
    """Share of ``ref`` skeleton pixels within ``tol`` px of the structure (shifted by ``-off``)."""
    from scipy import ndimage as ndi

    from branchnb.core.polyline import resample_uniform

    traced = np.zeros(ref.shape, bool)
    if structure.branches:
        p = np.vstack([resample_uniform(b.points, 1.0, include_end=True) for b in structure.branches]) - off
        ok = (p.min(1) > -0.5) & (p[:, 0] < ref.shape[1] - 0.5) & (p[:, 1] < ref.shape[0] - 0.5)
        traced[np.rint(p[ok, 1]).astype(int), np.rint(p[ok, 0]).astype(int)] = True
    return float(np.mean(ndi.distance_transform_edt(~traced)[ref] <= tol))


@pytest.mark.parametrize("layout, y0, x0", [("coast", 256, 256), ("island", 128, 128)])
def test_crop_whose_land_runs_off_the_frame_keeps_its_rivers_and_land(layout, y0, x0):
    # rivers running off a crop cut its land into pieces that each touch the frame: those pieces were
    # taken for outside regions, their rivers' junctions for their outline (cut, and the broken
    # pieces dropped as short), and example_domain left them out (before: recall 0.67 / 0.68 on the
    # crop against 0.85 / 1.0 on the full map, 52 % / 55 % of the crop's land outside the domain)
    from skimage.morphology import skeletonize

    img, truth, land = country_map_example((512, 512), 1, layout=layout)
    cov, _ = coverage_polylines((512, 512), [b.points for b in truth.branches],
                                [2 * b.thickness for b in truth.branches])
    win = (slice(y0, y0 + 256), slice(x0, x0 + 256))
    ref = skeletonize(cov[win] > 0.3)
    ref[:6] = ref[-6:] = False
    ref[:, :6] = ref[:, -6:] = False
    crop = np.ascontiguousarray(img[win])
    sc = extract_structure(crop)
    full = _recall_on(extract_structure(img), ref, (x0, y0))
    assert full >= 0.9
    assert _recall_on(sc, ref) >= full - 0.05
    dom = example_domain(crop, sc)
    assert np.mean(dom[land[win]]) >= 0.99
    if np.mean(~land[win]) >= 0.2:
        assert np.mean(dom[~land[win]]) <= 0.2      # a wide sea stays outside


@pytest.mark.parametrize("seed", [0, 4])
def test_delta_with_the_sea_on_the_left_enters_mid_side_and_flows_through_the_middle(seed):
    # the example's trunk enters at the middle of the inland (right) side; a new one came in 60 px
    # from it, near the bottom corner, and its branches ran along the bottom edge to the sea
    mask, _ch, _sea = delta_mask_example((256, 256), seed)
    mask = np.ascontiguousarray(mask.T[:, ::-1])                   # sea on the left
    ex = extract_structure(mask, root="nearest_region")
    model = fit_model(ex, domain=example_domain(mask))
    s = synthesize_structure(model, rng=1).structure
    root = next(b for b in s.branches if b.parent is None)
    ex_root = next(b for b in ex.branches if b.parent is None)
    assert root.points[0, 0] >= 250 and abs(root.points[0, 1] - ex_root.points[0, 1]) <= 0.15 * 256
    # along the frame: over six seeds (one seed's share moves with any change upstream: masks 0, 1, 4 x
    # seeds 0-5 had a mean of 0.021 with 4 of 18 over 0.03, and 0.022 with 5 of 18 after branching39's
    # delta trunk radius; before the frame rules the branches ran along the bottom edge)
    shares = [_frame_share(synthesize_structure(model, rng=k).structure, mask.shape, "left") for k in range(6)]
    assert np.mean(shares) <= 0.03 and max(shares) <= 0.08
