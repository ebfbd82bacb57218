"""Issue 23: a line drawing's roots enter where the example's do.

An unseen root drawing (two systems of 6-px trunks with 1-4 px roots entering from the top edge) came
out with trees starting from the left edge and the inside: the trunks, 3 x the median radius, were
taken for a sea (``binary_channels``' flat regions), and the piece was rooted at its thickest end, a
tie between the trunks' frame ends and inner ends beside a crossing. Thick lines are channels now
(``backgrounds._no_thick_lines``) and the ends where thick lines meet the frame root the trees
(``skeleton_tree._frame_entries``).
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._root_sides_check import figures, root_drawing
from branchnb.branching.backgrounds import binary_channels


def _side_distance(p, side, shape) -> float:
    h, w = shape
    return {"top": p[1], "bottom": h - 1 - p[1], "left": p[0], "right": w - 1 - p[0]}[side]


@pytest.mark.parametrize("kind", ["bottom", "left"])
def test_root_drawing_is_rooted_where_its_trunks_enter(kind):
    # main: one root 130-160 px inside the frame (bottom), the output's roots 0 of 2 at the side
    img, ent = root_drawing(kind, 420, 0)
    ex = extract_structure(img)
    roots = [b for b in ex.branches if b.parent is None]
    # the thickest roots are the trunks, at the side they enter from (a thin root cut by another side
    # of the frame may root a piece of its own)
    thick = sorted(roots, key=lambda b: -float(np.mean(b.thickness[:3])))[:2]
    assert all(_side_distance(b.points[0], kind, img.shape[:2]) <= 4 for b in thick)
    diag = float(np.hypot(*img.shape[:2]))
    for x, y, _a, _s in ent:      # every trunk's entry roots a tree
        assert min(np.hypot(b.points[0][0] - x, b.points[0][1] - y) for b in roots) < 0.03 * diag
    model = fit_model(ex, domain=example_domain(img, ex))
    for rng in (0, 1):
        out = synthesize_structure(model, rng=rng).structure
        f = figures(img, ent, ex, out)
        assert f["side"] >= 0.6
        # along the side, roots are drawn about the example's (RootModel.sample, sigma 0.3 x the
        # diagonal / sqrt(roots on that side)): main 0.40-0.61 x the diagonal from the nearest entry
        assert f["pos"] < 0.3
        assert 0.8 < f["len"] < 1.2


def test_thick_trunks_among_thin_lines_are_no_sea():
    m = np.zeros((240, 320), np.uint8)
    cv2.line(m, (100, 0), (115, 150), 1, 7)                 # a trunk, 3.5 x the lines' radius
    for k in range(12):
        cv2.line(m, (110, 20 + 15 * k), (310, 10 + 18 * k), 1, 1)
    ch, region, _sk, rad = binary_channels(m.astype(np.float32))
    assert not region.any()
    assert ch[100, 110] and rad[100, 110] >= 3.0            # its full radius, not capped
    m[180:, :] = 1                                          # a sea is one still
    _ch, region, _sk, _r = binary_channels(m.astype(np.float32))
    assert region[220, 160] and not region[100, 110]
