"""Issue 23: line maps rooted at their outlets: crossing networks and rivers meeting a drawn coast.

On main (9be8f67): the narrow cells between a network's crossing lines were filled as outlined strokes
(8 on the 420 px crossing network), which cut it into 5 trees rooted inside; on a paper map with a drawn
coast over a flat sea, the sea was not found (the closing of its wavy edge covered 2.2 % of the line
pixels, read as rivers in it) and the network was rooted at the frame, 500 px from its mouth.
"""

from __future__ import annotations

import numpy as np

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._river_outlet_check import river_drawing
from branchnb.branching._root_sides_check import figures, root_drawing
from branchnb.branching.clicks import gray_for_extraction
from branchnb.branching.ridges import fill_outlined_strokes


def _main_tree_root(s):
    lengths: dict[int, float] = {}
    for i, b in enumerate(s.branches):
        t = i
        while s.branches[t].parent is not None:
            t = int(s.branches[t].parent)
        lengths[t] = lengths.get(t, 0.0) + float(np.hypot(*np.diff(b.points, axis=0).T).sum())
    return s.branches[max(lengths, key=lengths.get)].points[0]


def test_crossing_cells_are_no_outlined_strokes():
    img, _ent = root_drawing("river", 420, 1)
    # main: 8 cells filled (lenses up to 20 px wide); left: a 3-px slit between two lines side by side
    assert fill_outlined_strokes(gray_for_extraction(img), colour=img)[1] <= 1


def test_crossing_network_rooted_at_its_entry():
    img, ent = root_drawing("river", 420, 1)
    ex = extract_structure(img)
    # main: 5 trees, the main one rooted 36 px inside at a filled cell
    assert sum(b.parent is None for b in ex.branches) == 1
    p = _main_tree_root(ex)
    assert np.hypot(p[0] - ent[0][0], p[1] - ent[0][1]) <= 4.0          # 2 strand widths
    out = synthesize_structure(fit_model(ex, domain=example_domain(img, ex)), rng=1).structure
    assert figures(img, ent, ex, out)["side"] == 1.0                    # main: 0.0


def test_paper_map_rooted_at_the_coast():
    img, (ox, oy), coast = river_drawing("even", "coast", 512, 0)
    ex = extract_structure(img)
    p = _main_tree_root(ex)
    # main: rooted at the right edge of the frame, ~300 px from the mouth
    assert np.hypot(p[0] - ox, p[1] - oy) <= 4.0
    from scipy import ndimage as ndi

    out = synthesize_structure(fit_model(ex, domain=example_domain(img, ex)), rng=0).structure
    dc = ndi.distance_transform_edt(~coast)
    roots = [b.points[0] for b in out.branches if b.parent is None]
    assert all(dc[int(round(q[1])), int(round(q[0]))] <= 0.04 * 512 for q in roots)


def test_tapered_network_rooted_at_its_trunk_mouth():
    # several ends of the joined network meet the coast; a one-pixel tributary's comes nearest the sea
    img, (ox, oy), _coast = river_drawing("taper", "coast", 512, 0)
    p = _main_tree_root(extract_structure(img))
    assert np.hypot(p[0] - ox, p[1] - oy) <= 10.0                       # 2 widths of the 5-px trunk
