"""Issue 23 (branching81): lines wider than the ridge filter's scales are traced.

A painted root system at 640 px (20-px trunk entering from the top, on noisy soil) came out with
its trunk missing, each root rooted where the children leave it (~200 px inside): the ridge filter
(sigma <= 4) sees only the trunk's edges. Wide lines are now found against the image itself
(:func:`~branchnb.branching.wide_lines.wide_line_mask`) and added to the ridge mask.
"""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import extract_structure
from branchnb.branching._wide_line_check import case, figures
from branchnb.branching.wide_lines import wide_line_mask


@pytest.mark.parametrize("i", [8, 6])
def test_wide_trunk_is_traced_from_where_it_enters(i):
    # main, case 8 (640 px roots, 20 px trunk, noisy soil): root 286 px from the entry, radius 0.43 x;
    # case 6 (512 px light river, 20 px, noisy): coverage 0.88, root 34 px off, radius 0.17 x
    img, lines, (_k, _n, width, _g) = case(i)
    f = figures(img, lines, extract_structure(img))
    assert f["cov"] >= 0.9
    assert f["rootd"] <= max(6.0, 0.5 * width)
    assert abs(f["rad"] - 1.0) <= 0.25
    assert f["roots"] == 1


def test_thin_cluster_is_no_wide_line():
    # many thin dark lines close together: dark only on the lines, never across the cluster
    g = np.full((300, 300), 0.8, np.float32)
    ridge = np.zeros_like(g, bool)
    for x in range(100, 200, 7):
        g[20:280, x:x + 3] = 0.2
        ridge[20:280, x:x + 3] = True
    assert not wide_line_mask(g, ridge, "dark", 4.0).any()


def test_wide_line_mask_finds_a_band_and_not_a_blob():
    g = np.full((300, 300), 0.3, np.float32)
    g[:, 140:160] = 0.9                      # a bright 20 px river
    g[40:80, 30:70] = 0.9                    # a bright round patch
    ridge = np.zeros_like(g, bool)
    ridge[:, 139:141] = ridge[:, 159:161] = True     # the filter's two edge rails
    ridge[40:80, 29:31] = True
    m = wide_line_mask(g, ridge, "bright", 4.0)
    band = np.zeros_like(m)
    band[:, 140:160] = True
    assert (m & band).sum() / band.sum() >= 0.9
    assert not m[40:80, 30:70].any()


def test_wide_line_mask_rejects_bad_input():
    with pytest.raises(ValueError, match="ridge"):
        wide_line_mask(np.zeros((50, 50)), np.zeros((40, 50), bool), "dark", 4.0)
    with pytest.raises(ValueError, match="polarity"):
        wide_line_mask(np.zeros((50, 50)), np.zeros((50, 50), bool), "up", 4.0)
