"""A synthesized lightning bolt keeps the example's cross-profile (issue 23): no faded flat tube."""

from __future__ import annotations

import numpy as np

from branchnb.branching import extract_structure, synthesize_image, synthesize_structure
from branchnb.branching._bolt_profile_check import bolt_profile
from branchnb.branching._storm_examples import storm_example
from branchnb.branching.line_contrast import centre_ring_colours, centre_ring_contrast, match_line_contrast
from branchnb.branching.skeleton_map import SkeletonMap
from branchnb.core.structure import Branch, Structure


def _glow_line(ground):
    """A bright core (0.9) with a soft glow on a flat ground."""
    y = np.arange(40, dtype=np.float32)[:, None, None]
    prof = 0.9 * np.exp(-((y - 19.5) ** 2) / 2.0) + 0.15 * np.exp(-((y - 19.5) ** 2) / 30.0)
    img = np.clip(ground + prof * (1 - ground) + np.zeros((40, 40, 3), np.float32), 0, 1).astype(np.float32)
    pm = SkeletonMap(Structure([Branch([(2, 19.5), (37, 19.5)], 1.0)]), 1.0).pixel_map((40, 40))
    return img, pm


def test_a_relit_light_line_keeps_its_core():
    ex, pm = _glow_line(0.55)            # a bolt in a bright cloud
    out, _ = _glow_line(0.08)            # the same bolt in a dark sky: stands out more
    ref = centre_ring_contrast(ex, pm)
    assert centre_ring_contrast(out, pm) > 1.5 * ref
    faded, k0 = match_line_contrast(out, pm, ref)
    kept, k1 = match_line_contrast(out, pm, ref, colours=centre_ring_colours(ex, pm))
    core_ex = float(ex[19, 20].mean())
    assert k0 < 0.8 and float(faded[19, 20].mean()) < core_ex - 0.15      # before: a dimmed tube
    assert k1 > 0.95 and abs(float(kept[19, 20].mean()) - core_ex) < 0.05


def test_a_dark_line_is_still_matched_by_contrast():
    img = np.random.default_rng(0).normal(0.8, 0.02, (40, 40, 3)).astype(np.float32)
    img[19:21, 2:38] = 0.3
    pm = SkeletonMap(Structure([Branch([(2, 19.5), (37, 19.5)], 1.0)]), 1.0).pixel_map((40, 40))
    ex = img.copy()
    ex[19:21, 2:38] = 0.5
    ref = centre_ring_contrast(ex, pm)
    out, k = match_line_contrast(img, pm, ref, colours=centre_ring_colours(ex, pm))
    assert k < 1 and abs(centre_ring_contrast(out, pm) / ref - 1) < 0.03


def test_storm_bolt_profile_kept():
    # One seed's structure decides where fragments come from, so the core brightness is taken over four
    # seeds: medians 0.58-0.62 against the example's 0.78 (per seed 0.49-0.71, with and without the
    # radius pull of growth._pull_radii); before the light-line rule seed 0 was 0.63 with correlation 0.961.
    img, _ = storm_example(seed=0, n_bolts=2)
    ex = extract_structure(img)
    pe = bolt_profile(img, SkeletonMap(ex, 1.0).pixel_map(img.shape[:2]))
    peaks = []
    for seed in range(4):
        res = synthesize_structure(ex, rng=seed)
        out = synthesize_image(img, ex, res, rng=seed).image
        po = bolt_profile(out, SkeletonMap(res.structure, 1.0).pixel_map(out.shape[:2]))
        assert np.corrcoef(pe["profile"], po["profile"])[0, 1] > 0.97
        assert po["sat"] < 0.05
        peaks.append(po["peak"])
    assert np.median(peaks) > pe["peak"] - 0.25
