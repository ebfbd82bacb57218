"""Issue 23, lightning photographs: the edge of a lit cloud and a row of city lights are no bolts."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import extract_structure
from branchnb.branching._storm_examples import bolt_scores, storm_example
from branchnb.branching.line_profiles import false_ridge_pixels


@pytest.mark.parametrize("seed,kw", [(0, {}), (1, {"shape": (384, 512)}), (0, {"cloud": False})])
def test_storm_extraction_keeps_bolts_and_drops_lights_and_cloud_edges(seed, kw):
    img, bolts = storm_example(seed=seed, **kw)
    before = extract_structure(img, false_ridges=False)
    s = extract_structure(img)
    p0, _ = bolt_scores(before, bolts, img.shape[:2])
    p, r = bolt_scores(s, bolts, img.shape[:2])
    low = max(b[:, 1].max() for b in bolts) + 6            # the city lights lie below every bolt
    below = [sum(int((b.points[:, 1] > low).sum()) for b in t.branches) for t in (before, s)]
    # sparse rows go entirely; a dense row (dots overlapping into a line) may keep a short stretch
    assert below[0] >= 50 and below[1] <= 0.25 * below[0], below
    assert p >= 0.8 and p >= p0 + 0.05, (p0, p)
    assert r >= 0.9, r


def test_false_ridge_pixels_edge_dots_and_line():
    img = np.full((60, 90), 0.1)
    img[15, 5:85] = 1.0                                    # a line
    img[40:, :] = 0.8                                      # the edge of a lit region
    yy, xx = np.mgrid[0:60, 0:90]
    for x0 in range(6, 85, 8):                             # a row of dots
        img += 0.9 * np.exp(-((xx - x0) ** 2 + (yy - 28) ** 2) / 3.0)
    sk = np.zeros(img.shape, bool)
    sk[15, 5:85] = sk[39, 5:85] = sk[28, 6:84] = True
    bad = false_ridge_pixels(np.clip(img, 0, 1), sk, "bright")
    assert bad[15].sum() == 0
    assert bad[39].mean() > 0.8 * sk[39].mean() and bad[28].sum() >= 0.8 * sk[28].sum()
    with pytest.raises(ValueError, match="polarity"):
        false_ridge_pixels(img, sk, "up")
