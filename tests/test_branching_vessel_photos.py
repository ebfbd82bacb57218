"""Vessel photos on the plain defaults (issue 23, branching59).

Found on the retina fundus: copied as is, fragments from the dark rim and the bright centre met
with steps in light; the gradient-domain correction spread them into pale and dark halo streaks
beside the vessels, vessel ends (which lie in the dark rim) came out as dark dots, and vessels
fell apart. Shaded photos with dark lines are now flattened by default (``flatten_shading``,
gated by ``regions._is_shaded``), and a soft photo's smoothly shaded ground is no flat-colour
region (it was drawn as a flat map once half the picture was locally flat).
"""

import numpy as np
import pytest

from branchnb.branching import ImageSynthesisParams, synthesize_image
from branchnb.branching._vessel_check import _target, measure, vessel_photo
from branchnb.branching.flat_regions import flat_colour_regions


@pytest.mark.parametrize("seed", [0, 1])
def test_shaded_vessel_photo_has_no_halos_or_tip_dots(seed):
    ex, s_ex, _ = vessel_photo("shaded", 256, seed)
    target = _target(256, seed, np.ones((256, 256), bool))
    out = np.asarray(synthesize_image(ex, s_ex, target, rng=seed).image)[..., :3]
    r = measure(ex, s_ex, out, target)
    # main: halo 0.14 / 0.10 of the vessel contrast, tip dots 0.16 / 0.05
    assert r["halo"] < 0.05, r
    assert r["tip"] < 0.08, r
    assert r["pcs"] == 1 and r["gap"] == 0, r


def test_evenly_lit_and_light_line_examples_are_copied_as_is():
    from branchnb.branching.regions import _is_shaded

    rng = np.random.default_rng(0)
    ramp = np.dstack([np.tile(np.linspace(0.3, 0.9, 64), (64, 1))] * 3)
    bg = np.ones((64, 64), bool)
    dark, light = np.full(3, 0.1), np.full(3, 0.6)
    assert _is_shaded(ramp, bg, dark, light)
    assert not _is_shaded(ramp, bg, light, dark)          # a bolt among clouds: its clouds are no shading
    even = 0.6 + 0.02 * rng.normal(size=(64, 64, 3))
    assert not _is_shaded(even, bg, dark, light)
    # flat vessel photo: the default output equals the paper's (no flattening)
    ex, s_ex, _ = vessel_photo("flat", 160, 0)
    target = _target(160, 0, np.ones((160, 160), bool))
    a = synthesize_image(ex, s_ex, target, rng=0).image
    b = synthesize_image(ex, s_ex, target, ImageSynthesisParams(flatten_shading=0.0), rng=0).image
    assert np.array_equal(a, b)


def test_soft_vignetted_photo_ground_is_no_flat_region():
    from branchnb.branching.skeleton_map import SkeletonMap

    img, s, _ = vessel_photo("vignette", 384, 2)
    pm = SkeletonMap(s, 1.0).pixel_map(img.shape[:2])
    lab, share = flat_colour_regions(img, pm.core(1.5, 2.0))
    # main: 51 % of the photo flat in 3 regions, so it was drawn as a flat-colour map
    assert share < 0.5 or lab.max() == 0, share
