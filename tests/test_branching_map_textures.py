"""Drawn maps synthesized with their own region marks and their coast as drawn (issue 23).

A fantasy map (parchment land with tree glyphs, a teal sea hatched with wave dashes, a brown
double coast) was drawn in style with flat regions and one coast line: the marks were lost and the
double coast became single. Here the example's style is drawn on another island (the example's
mirrored, so the output's sea lies on the example's land in places and the reverse).
"""
import numpy as np
import pytest
from scipy import ndimage as ndi
from test_branching_marked_seas import SEA, _fantasy_map

from branchnb.branching import extract_structure
from branchnb.branching.drawing import draw_in_style, drawing_style
from branchnb.branching.skeleton_map import SkeletonMap
from branchnb.core.structure import Branch, Structure

COAST = np.array([0.30, 0.20, 0.10], np.float32)
TREE = np.array([0.25, 0.40, 0.20], np.float32)


def _drawn(size, seed):
    img, truth, land = _fantasy_map(size, seed)
    s = extract_structure(img)
    pm = SkeletonMap(s, 1.0).pixel_map(img.shape[:2])
    style = drawing_style(img, s, land.astype(np.int32), pm)
    w = img.shape[1]
    flipped = Structure([Branch(np.c_[w - 1 - b.points[:, 0], b.points[:, 1]], b.thickness, b.parent, b.parent_vertex)
                         for b in s.branches], image_shape=img.shape[:2])
    out_land = land[:, ::-1]
    return img, land, draw_in_style(style, flipped, out_land.astype(np.int32)), out_land


def _share(img, mask, colour, tol):
    return float(np.mean(np.linalg.norm(img[mask] - colour, axis=-1) < tol))


@pytest.mark.parametrize("size, seed", [(256, 3), (400, 2)])
def test_marks_and_double_coast_kept(size, seed):
    img, land, out, out_land = _drawn(size, seed)
    sea_e = ndi.binary_erosion(~land, iterations=10, border_value=1)
    sea_o = ndi.binary_erosion(~out_land, iterations=10, border_value=1)
    # wave dashes: pixels off the sea colour, at 0.5-2x the example's density
    dash_e = 1 - _share(img, sea_e, SEA, 0.06)
    dash_o = 1 - _share(out, sea_o, SEA, 0.06)
    assert 0.5 * dash_e <= dash_o <= 2 * dash_e, (dash_e, dash_o)
    land_e = ndi.binary_erosion(land, iterations=10)
    land_o = ndi.binary_erosion(out_land, iterations=10)
    tree_e, tree_o = _share(img, land_e, TREE, 0.1), _share(out, land_o, TREE, 0.1)
    assert 0.5 * tree_e <= tree_o <= 2 * tree_e, (tree_e, tree_o)
    # the double coast: a thin line 5-6 px off the thick one along >= 80 % of the output's coast
    dist = ndi.distance_transform_edt(~out_land)
    brown = np.linalg.norm(out - COAST, axis=-1) < 0.2
    shore = (dist > 0) & (dist <= 1.5)
    shore[:8] = shore[-8:] = False
    shore[:, :8] = shore[:, -8:] = False
    ring = brown & (dist >= 4.5) & (dist <= 7.5)
    near = ndi.distance_transform_edt(~ring)[shore] <= 6.5
    gap = np.linalg.norm(out - SEA, axis=-1)[(dist >= 2.6) & (dist <= 3.6)]
    assert near.mean() >= 0.8, near.mean()
    # ... with sea between the two lines
    assert np.median(gap) < 0.1
    # no specks of the coast colour away from the coast
    lab, n = ndi.label(brown & (ndi.distance_transform_edt(ndi.distance_transform_edt(out_land) != 1) > 10)
                       & (dist > 10))
    assert n == 0, n


def test_flat_region_crossed_by_unextracted_lines_is_not_marked():
    # a flat country crossed by river lines the structure does not hold was taken as marked (its lines'
    # pixels counted as marks) and quilted with ghost lines; a region with real dots stays marked
    import cv2

    from branchnb.branching.drawing import _region_textures

    h, w = 200, 240
    cream, green, dots = (np.array(c, np.float32) for c in ([0.94, 0.9, 0.77], [0.8, 0.9, 0.72], [0.75, 0.45, 0.3]))
    lay = np.zeros((h, w), np.int32)
    lay[:, w // 2:] = 1
    img = np.where(lay[..., None] == 0, cream, green).astype(np.float32)
    for y in range(30, 190, 40):
        cv2.polylines(img, [np.array([[135, y], [180, y + 15], [230, y - 5]], np.int32)], False,
                      (0.0, 0.0, 0.0), 2, cv2.LINE_AA)
    s = Structure([Branch(np.c_[np.full(40, 60.0), np.linspace(20, 180, 40)], np.full(40, 1.5))],
                  image_shape=(h, w))
    pm = SkeletonMap(s, 1.0).pixel_map((h, w))
    cols = np.stack([cream, green])
    assert 1 not in _region_textures(img, lay, cols, pm, np.zeros(3, np.float32), 1.0, 0)
    rng = np.random.default_rng(0)
    ys, xs = rng.integers(20, 180, 150), rng.integers(w // 2 + 20, w - 20, 150)
    img[ys, xs] = dots
    tex = _region_textures(img, lay, cols, pm, np.zeros(3, np.float32), 1.0, 0)
    assert 1 in tex
    far = ndi.binary_erosion(lay == 1, iterations=12)
    # no line ink copied into the region's texture away from the lines' own places
    assert np.mean(np.linalg.norm(tex[1][far], axis=-1) < 0.35) < 0.05
