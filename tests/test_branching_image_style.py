"""Synthesized images in the example's style: line contrast, connected lines, small drawn maps."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import (
    example_domain,
    extract_structure,
    fit_model,
    synthesize_image,
    synthesize_structure,
)
from branchnb.branching._image_examples import cracked_mud_example
from branchnb.branching._map_examples import country_map_example
from branchnb.branching.image_synthesis import ImageSynthesisParams
from branchnb.branching.line_contrast import line_profile, restore_line_contrast
from branchnb.branching.measures import boundary_drawn_share, line_contrast, line_pieces
from branchnb.branching.skeleton_map import SkeletonMap
from branchnb.core.render import coverage_polylines
from branchnb.core.structure import Branch, Structure


def _line():
    img = np.full((48, 48, 3), 0.8, np.float32)
    img[23:25, 2:46] = (0.3, 0.2, 0.1)
    s = Structure([Branch([(2, 23.5), (45, 23.5)], 1.0)])
    return img, s, SkeletonMap(s, 1.0).pixel_map((48, 48))


def test_restore_draws_a_pale_gap_and_leaves_the_rest():
    img, s, pm = _line()
    prof = line_profile(img, pm)
    faded = img.copy()
    faded[23:25, 15:30] = 0.75                          # a pale gap in the line
    faded[5:8, 5:8] = 0.2                               # a dark spot far from the line
    out, n = restore_line_contrast(faded, pm, prof, 1.0)
    assert n > 0
    np.testing.assert_allclose(out[23:25, 18:27], img[23:25, 18:27], atol=0.06)   # the line is back
    np.testing.assert_array_equal(out[:15], faded[:15])                            # nothing else moved
    # pixels already darker than the example's line are never lightened
    dark = img.copy()
    dark[23:25] = 0.05
    out2, _ = restore_line_contrast(dark, pm, prof, 1.0)
    assert np.all(out2 <= dark + 1e-6)


def test_bright_lines_are_restored_brighter():
    img, s, pm = _line()
    img = 1.0 - img                                      # a bright line on a dark ground
    prof = line_profile(img, pm)
    faded = img.copy()
    faded[23:25, 15:30] = 0.25
    out, _ = restore_line_contrast(faded, pm, prof)
    assert out[23, 20].mean() > 0.6


def test_no_profile_when_the_lines_do_not_show():
    img, s, pm = _line()
    assert line_profile(np.full_like(img, 0.5), pm) is None
    with pytest.raises(ValueError, match="share"):
        restore_line_contrast(img, pm, line_profile(img, pm), -1.0)


@pytest.fixture(scope="module", params=[(160, 3)], ids=["mud160"])
def mud(request):
    size, seed = request.param
    img, _cracks = cracked_mud_example((size, size), seed)
    ex = extract_structure(img)
    dom = example_domain(img, ex)
    res = synthesize_structure(fit_model(ex, domain=dom), rng=seed)
    return img, ex, res


def test_cracks_keep_the_examples_contrast_and_connect(mud):
    img, ex, res = mud
    c_ex = line_contrast(img, ex)
    out = synthesize_image(img, ex, res, rng=0)
    off = synthesize_image(img, ex, res, ImageSynthesisParams(line_contrast=0.0), rng=0)
    ratio = line_contrast(out.image, res.structure) / c_ex
    assert 0.8 <= ratio <= 1.25, ratio
    assert ratio >= line_contrast(off.image, res.structure) / c_ex - 0.01
    pm = SkeletonMap(ex, 1.0).pixel_map(img.shape[:2])
    ink = np.median(img[pm.dist <= 0.5], axis=0)
    ground = np.median(img[pm.dist > 6], axis=0)
    v = ink - ground
    half = ((out.image[..., :3] - ground) @ v) / float(v @ v) >= 0.4      # at least 40 % of the way to the ink
    # every tree's centre line lies on one 8-connected line: no gap, children joined
    lab, _n = ndi.label(half, structure=np.ones((3, 3)))
    trees: dict = {}
    for i, b in enumerate(res.structure.branches):
        r = i
        while res.structure.branches[r].parent is not None:
            r = res.structure.branches[r].parent
        trees.setdefault(r, []).append(b)
    for bs in trees.values():
        cov, _ = coverage_polylines(img.shape[:2], [b.points for b in bs], [np.full(len(b.points), 1.0) for b in bs])
        touch = ndi.maximum_filter(lab, 3)[cov > 0.9]
        assert np.mean(touch == np.bincount(touch[touch > 0]).argmax()) >= 0.98
    # no more specks than the texture of the example itself shows
    assert line_pieces(out.image, res.structure, ink, ground)["specks"] <= \
        line_pieces(img, ex, ink, ground)["specks"] + 2


@pytest.mark.parametrize("size,seed", [(96, 3), (128, 129), (128, 4)])
def test_small_drawn_maps_keep_their_coast(size, seed):
    img, _truth, land = country_map_example((size, size), seed, layout="island")
    ex = extract_structure(img)
    coast = land & ~np.pad(land, 1, mode="edge")[:-2, 1:-1] | land & ~np.pad(land, 1, mode="edge")[2:, 1:-1]
    pts = np.vstack([b.points for b in ex.branches])
    iy = np.clip(np.rint(pts[:, 1]).astype(int), 0, size - 1)
    ix = np.clip(np.rint(pts[:, 0]).astype(int), 0, size - 1)
    near_coast = ndi.binary_dilation(coast, iterations=2)
    assert np.mean(near_coast[iy, ix]) <= 0.25            # rivers found, the coast is no river
    dom = example_domain(img, ex)
    res = synthesize_structure(fit_model(ex, domain=dom), rng=0)
    out = synthesize_image(img, ex, res, rng=0)
    ink, ground = np.zeros(3), np.median(img[land], axis=0)
    assert boundary_drawn_share(img, land, ink, ground) >= 0.9
    out_land = out.labels == np.bincount(out.labels[res.domain]).argmax()
    assert boundary_drawn_share(out.image, out_land, ink, ground) >= 0.9
    pieces = line_pieces(out.image, res.structure, ink, ground)
    assert pieces["max_pieces"] == 1 and pieces["specks"] == 0, pieces


@pytest.mark.parametrize("kind,size,width", [("drawing", 200, 8.0), ("vine", 500, None)])
def test_outlined_strokes_are_traced_once(kind, size, width):
    from branchnb.branching._line_art_trees import branching_drawing, interlace_vine, measure_line_art

    make = branching_drawing if kind == "drawing" else interlace_vine
    img, truth, junctions = make(size, 0, outlined=True, width=width)
    found = extract_structure(img)
    m = measure_line_art(truth, junctions, found)
    assert m["trees"] == 1 and m["recall"] >= 0.9, m
    # once, not as its two outline lines: about the true length
    ratio = sum(b.length for b in found.branches) / sum(b.length for b in truth.branches)
    assert ratio <= 1.25, ratio


def test_only_outlined_insides_are_filled():
    from branchnb.branching._line_art_examples import crack_drawing_example
    from branchnb.branching._map_examples import delta_mask_example
    from branchnb.branching.ridges import fill_outlined_strokes

    cells = crack_drawing_example(256, 0).mean(-1)           # wide cells of a crack drawing stay
    assert fill_outlined_strokes(cells)[1] == 0
    mask, _ch, _sea = delta_mask_example((256, 256), 3)      # islands between wide channels stay
    assert fill_outlined_strokes(1.0 - mask.astype(np.float32))[1] == 0
    assert fill_outlined_strokes(mask.astype(np.float32))[1] == 0
