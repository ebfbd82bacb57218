"""Issue 23, image stage on unseen kinds (procedural examples with known answers):

- a shaded terrain map (continuous hill shading, pixel noise, a black coast) keeps its coast along
  the output's domain and its land grey (measured before: coast share 0.04-0.13, land left white);
- a glowing bolt copied from a bright cloud into a dark sky brings no glowing tube of cloud (its glow
  width against the example's, measured 1.39x before, 1.14x with the fragments relit);
- a strand crossing a drawn stroke (a knot) is not copied as a cross-shaped tick across the
  synthesized stroke (:mod:`~branchnb.branching.crossings`).
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import (
    ImageSynthesisParams,
    example_domain,
    extract_structure,
    fit_model,
    synthesize_image,
    synthesize_structure,
)
from branchnb.branching._image_examples import random_tree
from branchnb.branching._map_examples import terrain_map_example
from branchnb.branching.measures import boundary_drawn_share
from branchnb.core.render import coverage_polylines
from branchnb.core.structure import Branch, Structure


@pytest.mark.parametrize("seed", [0, 1])
def test_shaded_terrain_keeps_its_coast_and_land(seed):
    img, _s, _riv = terrain_map_example((256, 256), seed, relief="shade")
    ex = extract_structure(img)
    dom = example_domain(img, ex)
    res = synthesize_structure(fit_model(ex, domain=dom), rng=0)
    out = synthesize_image(img, ex, res, rng=0)
    ink, ground = np.array([0.13, 0.13, 0.15]), np.ones(3)
    assert boundary_drawn_share(out.image, res.domain, ink, ground) >= 0.9
    # the land is the example's land grey (measured 0.86 against 0.70 before), the outside white
    g_ex = np.median(img[..., :3].mean(-1)[dom])
    g_out = np.median(out.image[..., :3].mean(-1)[res.domain])
    assert abs(g_out - g_ex) < 0.05, (g_out, g_ex)
    far = ~ndi.binary_dilation(res.domain, iterations=4)
    assert np.median(out.image[..., :3].mean(-1)[far]) > 0.95


def _glow_width(img, st, dmax=14):
    h, w = img.shape[:2]
    lines = np.zeros((h, w), np.uint8)
    for b in st.branches:
        cv2.polylines(lines, [np.round(b.points).astype(np.int32)], False, 1, 1)
    d = ndi.distance_transform_edt(lines == 0)
    lum = img[..., :3].mean(-1)
    ring = (d >= 16) & (d <= 24)
    ground = ndi.gaussian_filter(lum * ring, 12) / np.maximum(ndi.gaussian_filter(ring.astype(float), 12), 1e-6)
    prof = np.array([np.median((lum - ground)[(d >= k - 0.5) & (d < k + 0.5)]) for k in range(dmax + 1)])
    return float(np.clip(prof, 0, None).sum() / max(prof[0], 1e-6))


def _bolt(n, seed, glow_sigma):
    tree = random_tree((n, n), seed, n_children=5, grandchildren=1)
    yy, xx = np.mgrid[:n, :n]
    y = (yy / n)[..., None]
    sky = np.array([0.04, 0.03, 0.12]) * (1 - y) + np.array([0.25, 0.15, 0.3]) * y
    cloud = np.exp(-(((xx - 0.3 * n) / (0.25 * n)) ** 2 + ((yy - 0.45 * n) / (0.15 * n)) ** 2))
    sky = sky + cloud[..., None] * np.array([0.45, 0.3, 0.45])
    sky = sky + np.random.default_rng(seed).normal(0, 0.01, sky.shape)
    pts = [b.points for b in tree.branches]
    lines = np.zeros((n, n), np.uint8)
    for p in pts:
        cv2.polylines(lines, [np.round(p).astype(np.int32)], False, 1, 1)
    glow = 0.45 * np.exp(-0.5 * (ndi.distance_transform_edt(lines == 0) / glow_sigma) ** 2)
    cov, _ = coverage_polylines((n, n), pts, [1.6] * len(pts))
    img = sky + glow[..., None] * np.array([1.0, 0.8, 1.0])
    img = img * (1 - cov[..., None]) + cov[..., None] * np.array([1.0, 0.97, 1.0])
    return np.clip(img, 0, 1).astype(np.float32)


def test_bolts_bring_no_glowing_tube_of_cloud():
    img = _bolt(256, 1, 2.0)
    ex = extract_structure(img)
    res = synthesize_structure(fit_model(ex, domain=example_domain(img, ex)), rng=0)
    w_ex = _glow_width(img, ex)
    on = synthesize_image(img, ex, res, rng=0)
    off = synthesize_image(img, ex, res, ImageSynthesisParams(relight_fragments=False), rng=0)
    w_on, w_off = _glow_width(on.image, res.structure), _glow_width(off.image, res.structure)
    assert w_on / w_ex < 1.25, (w_on, w_ex)
    # relit 1.78 against unrelit 1.90 until branching120; since thin lines take sources of a like radius
    # (fragment_choice.THIN_MATCH_RATIO) both carry less cloud, relit 1.69, unrelit 1.72 (example 2.25)
    assert w_on < 0.99 * w_off and w_on < 0.78 * w_ex, (w_on, w_off, w_ex)
    # the bolts stay as bright as the example's (their cores are not dimmed with the ground)
    core = ndi.distance_transform_edt(~_centre(res.structure, 256)) < 0.6
    assert np.median(on.image[core].mean(-1)) > 0.8


def _centre(st, n):
    m = np.zeros((n, n), np.uint8)
    for b in st.branches:
        cv2.polylines(m, [np.round(b.points).astype(np.int32)], False, 1, 1)
    return m > 0


@pytest.mark.parametrize("annotated", [True, False])
def test_a_crossing_strand_is_not_copied_across_a_stroke(annotated):
    n, w = 160, 6.0
    img = np.ones((n, n, 3), np.float32)
    h_line = np.array([(8.0, 80.0), (152.0, 80.0)])
    v_line = np.array([(80.0, 8.0), (80.0, 152.0)])
    cov, _ = coverage_polylines((n, n), [h_line, v_line], [w, w])
    img *= 1 - cov[..., None]
    # two strands crossing without a junction (a knot), or one of them not annotated
    src = Structure([Branch(h_line, w / 2)] + ([Branch(v_line, w / 2)] if annotated else []), (n, n))
    tgt = Structure([Branch(np.array([(10.0, 40.0), (150.0, 120.0)]), w / 2)], (n, n))
    out = synthesize_image(img, src, tgt, rng=0)
    body, _ = coverage_polylines((n, n), [tgt.branches[0].points], [w + 4.0])
    ticks = (out.image[..., :3].mean(-1) < 0.5) & (body < 0.05)
    assert ticks.sum() < 5, int(ticks.sum())


def test_crossing_fragments_are_left_out_of_the_library():
    from branchnb.branching.crossings import crossing_points, without_crossings
    from branchnb.branching.fragments import source_fragments
    from branchnb.branching.skeleton_map import SkeletonMap

    n = 160
    h_line = np.array([(8.0, 80.0), (152.0, 80.0)])
    knot = Structure([Branch(h_line, 3.0), Branch(np.array([(80.0, 8.0), (80.0, 152.0)]), 3.0)], (n, n))
    cross = crossing_points(knot, (n, n))
    ys, xs = np.nonzero(cross)
    assert np.hypot(xs - 80, ys - 80).max() <= 1.5            # the one crossing, where it is
    # a child starting on its parent is a junction, no crossing
    tee = Structure([Branch(np.array([(80.0, 80.0), (8.0, 80.0)]), 3.0),
                     Branch(np.array([(80.0, 80.0), (152.0, 80.0)]), 3.0, 0, 0),
                     Branch(np.array([(80.0, 80.0), (80.0, 150.0)]), 3.0, 0, 0)], (n, n))
    assert not crossing_points(tee, (n, n)).any()
    lib, _ = source_fragments(SkeletonMap(knot, 1.0))
    kept = without_crossings(lib, knot, (n, n))
    d = np.hypot(*(lib.center - 80.0).T)
    assert 0 < len(kept) < len(lib)
    assert np.all(np.hypot(*(kept.center - 80.0).T) > kept.radius)   # no kept disk holds the crossing
    assert len(kept) == int(np.sum(d > lib.radius))
