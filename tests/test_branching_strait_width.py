"""A sea strait traced as a wide river: drawn maps keep their line width and do not crash (issue 23).

On a drawn map of two islands 40 px apart (768 px, 2 px navy rivers and coast on white land in a grey
sea), the wide-line search reads the grey strait between the two coasts as a 40 px river: the example
structure gets stretches of radius 20-34 px in the sea. Two things then went wrong in the image:

* the drawing style's width scale (painted ink over the structure's ``2 r``) was halved by those
  stretches, and the output's rivers came out as faint 1 px dashes (80-121 line pieces per tree,
  208-338 specks);
* carrying the coast across the example's mouths closed the sea with a disk 3 x that radius
  (343 px): ``ndi.binary_closing`` ran out of memory on every seed.

Here on small procedural maps (several sizes, line widths, colours and seeds): the width scale with a
thick stretch through the sea equals the one without it, and the closing used is the same as
``binary_closing`` with a disk and does not depend on the radius.
"""
import os
import sys

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching.drawing import drawing_style
from branchnb.branching.output_regions import _disk_closing
from branchnb.branching.skeleton_map import SkeletonMap
from branchnb.core.structure import Branch, Structure

sys.path.insert(0, os.path.dirname(__file__))
from branching_island_maps import ink_map  # noqa: E402


def _two_islands(size, seed, lw, land_c, sea_c, ink_c):
    """Two round islands a strait apart, each with a few straight rivers of width ``lw``; the rivers'
    structure (radius ``lw / 2``) and a thick branch along the strait (radius = half its width)."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:size, 0:size]
    r = 0.2 * size
    c1 = np.array([0.3, 0.32]) * size + rng.normal(0, 0.01 * size, 2)
    c2 = np.array([0.7, 0.68]) * size + rng.normal(0, 0.01 * size, 2)
    land = (np.hypot(xx - c1[0], yy - c1[1]) < r) | (np.hypot(xx - c2[0], yy - c2[1]) < r)
    rivers = []
    for c in (c1, c2):
        for a in rng.uniform(0, 2 * np.pi, 4):
            u = np.array([np.cos(a), np.sin(a)])
            rivers.append(np.linspace(c + 0.9 * r * u, c + 0.15 * r * u, 60))
    img = ink_map(land, rivers, (land_c, sea_c, ink_c), lw)
    branches = [Branch(p, np.full(len(p), lw / 2)) for p in rivers]
    # the strait runs between the two coasts, across the line joining the centres
    mid, gap = (c1 + c2) / 2, np.hypot(*(c2 - c1)) - 2 * r
    n = (c2 - c1)[::-1] * np.array([1, -1]) / np.hypot(*(c2 - c1))
    strait = np.linspace(mid - 0.25 * size * n, mid + 0.25 * size * n, 80)
    thick = np.clip(0.5 * gap + 0.5 * np.abs(np.linspace(-1, 1, 80)) * 0.2 * size, 2, None)
    return img, land, branches, Branch(strait, thick)


CASES = [(256, 0, 2.0, (0.98, 0.98, 0.96), (0.70, 0.72, 0.75), (0.05, 0.08, 0.35)),
         (320, 1, 3.0, (0.62, 0.80, 0.50), (0.16, 0.30, 0.55), (0.35, 0.18, 0.05)),
         (384, 2, 2.0, (0.90, 0.78, 0.52), (0.55, 0.75, 0.85), (0.45, 0.05, 0.05))]


@pytest.mark.parametrize("size,seed,lw,land_c,sea_c,ink_c", CASES)
def test_thick_stretch_in_the_sea_keeps_the_line_width(size, seed, lw, land_c, sea_c, ink_c):
    img, land, rivers, strait = _two_islands(size, seed, lw, land_c, sea_c, ink_c)
    lay = land.astype(np.int32)
    widths = []
    for branches in (rivers, rivers + [strait]):
        s = Structure(branches, image_shape=(size, size))
        style = drawing_style(img, s, lay, SkeletonMap(s, 1.0).pixel_map((size, size)))
        assert style.branch_region == 1
        widths.append(style.width_scale * lw)       # the drawn width of a river of radius lw / 2
    # the rivers are drawn about as wide as they are (anti-aliased ink over length) with or without
    # the strait (main: the strait's 20-50 px radius cut the width to 0.25-0.5 x)
    assert 0.75 * lw <= widths[0] <= 1.5 * lw
    assert abs(widths[1] / widths[0] - 1.0) <= 0.1


def test_disk_closing_is_binary_closing_and_cheap():
    rng = np.random.default_rng(3)
    for radius in (2, 5, 9):
        m = ndi.gaussian_filter(rng.random((90, 110)), 2.5) > 0.5
        pad = radius + 1
        yy, xx = np.mgrid[-radius:radius + 1, -radius:radius + 1]
        want = ndi.binary_closing(np.pad(m, pad, mode="edge"), xx ** 2 + yy ** 2 <= radius ** 2)
        got = _disk_closing(np.pad(m, pad, mode="edge"), radius)
        assert np.array_equal(want[pad:-pad, pad:-pad], got[pad:-pad, pad:-pad])
    # a 171 px radius on a 1100 px canvas (the strait's 343 px disk): main ran out of memory
    big = np.zeros((1100, 1100), bool)
    big[:500] = True
    big[500:560, 300:340] = True
    out = _disk_closing(big, 171)
    # the notch (40 px wide, under the disk's width) is closed over the whole band next to the block
    assert out[:500].all() and out[500:540, 300:340].all() and out[700:].sum() == 0


@pytest.mark.parametrize("size,seed,side,radius", [(256, 0, "right", 3.0), (320, 1, "bottom", 4.0),
                                                   (288, 2, "top", 3.5)])
def test_binary_delta_with_a_sea_is_drawn_binary_and_unbroken(size, seed, side, radius):
    """A binary delta mask (white channels and sea on black land, two regions) is drawn with the
    mask's two colours, its thin channels as unbroken one-pixel rasters (main: anti-aliased, 0.6-1.4 %
    of the pixels grey and a 384 px delta's thin channels broken into 9 pieces with 8 specks)."""
    from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_image, synthesize_structure
    from branchnb.branching._delta_examples import delta_river_mask
    from branchnb.branching.measures import _ink, _line_gaps, line_pieces

    m, _entry, _mouths = delta_river_mask((size, size), seed, side, radius, True, 3)
    img = np.dstack([m] * 3)
    ex = extract_structure(img)
    res = synthesize_structure(fit_model(ex, domain=example_domain(img, ex)), rng=seed)
    out = synthesize_image(img, ex, res, rng=seed).image[..., :3]
    grey = (out > 1.5 / 255) & (out < 1 - 1.5 / 255)
    assert grey.mean() == 0.0
    assert out[res.domain].mean() < 0.2 and out[~res.domain].mean() > 0.95       # black land, white sea
    white, black = (1.0, 1.0, 1.0), (0.0, 0.0, 0.0)
    lp = line_pieces(out, res.structure, white, black)
    assert lp["max_pieces"] == 1 and lp["specks"] == 0
    assert _line_gaps(res.structure.branches, _ink(out, white, black)) == 0
