"""Small low-poly crowns with thin facets, and shaded photo crowns (issue 24, trees58).

A 96-128 px low-poly crown often has facets 2-5 px wide along its sides; at the 3 px
straightness tolerance their outline's Douglas-Peucker polygon collapses onto the midline and
stands half their width off, as a curve's does (``lowpoly.SLIVER_KEEP``). A smoothly shaded crown
cut by the colour quantisation into bands one step apart is no faceted crown
(``lowpoly.GRADIENT_SHARE``).
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scipy.spatial import Delaunay
from trees_facets import reduce_drawing

from branchnb.trees import TreeLibrary
from branchnb.trees.flat_art import _source_pixel
from branchnb.trees.lowpoly import _outline_stats, _straight_edged, facet_palette

PALETTES = (
    np.array([[0.62, 0.8, 0.35], [0.45, 0.68, 0.27], [0.3, 0.54, 0.2], [0.2, 0.4, 0.16]]),
    np.array([[0.98, 0.78, 0.3], [0.93, 0.55, 0.18], [0.8, 0.33, 0.12], [0.6, 0.2, 0.1], [0.45, 0.14, 0.08]]),
    np.array([[1.0, 0.8, 0.88], [0.95, 0.62, 0.75], [0.82, 0.45, 0.62], [0.65, 0.3, 0.5]]),
)


def faceted(size, seed, aa=True):
    """A low-poly tree: a 6-11-gon (or cone) crown with 8-14 inner points, Delaunay triangles
    shaded from the upper left in one of three palettes (neighbours often merge), a two-tone
    trunk; supersampled (``aa``) or hard-edged. Image and trunk mask."""
    r = np.random.default_rng(seed)
    ss = 4 if aa else 1
    S = size * ss
    rgb, a, tr = np.zeros((S, S, 3), np.float32), np.zeros((S, S), np.float32), np.zeros((S, S), np.float32)
    cx = S * r.uniform(0.46, 0.54)
    if seed % 2:
        top, base, half = 0.06 * S, r.uniform(0.68, 0.74) * S, r.uniform(0.22, 0.32) * S
        hull = np.array([[cx, top], [cx - half, base], [cx + half, base]])
        cy, rx, ry, t0 = (top + base) / 2, half, (base - top) / 2, base - 0.02 * S
    else:
        n = int(r.integers(6, 12))
        ang = np.sort(np.linspace(0, 2 * np.pi, n, endpoint=False) + r.uniform(-0.25, 0.25, n))
        rx, ry, cy = r.uniform(0.26, 0.36) * S, r.uniform(0.22, 0.3) * S, r.uniform(0.34, 0.4) * S
        hull = np.c_[cx + rx * r.uniform(0.82, 1.08, n) * np.cos(ang), cy + ry * r.uniform(0.82, 1.08, n) * np.sin(ang)]
        t0 = cy + 0.5 * ry
    H = hull.astype(np.float32)
    inner = []
    while len(inner) < int(r.integers(8, 15)):
        p = (cx + r.uniform(-1, 1) * rx, cy + r.uniform(-1, 1) * ry)
        if cv2.pointPolygonTest(H, (float(p[0]), float(p[1])), True) > 0.06 * min(rx, ry):
            inner.append(p)
    pts = np.r_[hull, np.array(inner)]
    tw = S * r.uniform(0.03, 0.05)
    trunk = np.int32([[cx - tw, S * 0.95], [cx + tw, S * 0.95], [cx + 0.6 * tw, t0], [cx - 0.6 * tw, t0]])
    cv2.fillPoly(rgb, [trunk[[0, 3, 2]]], (0.45, 0.3, 0.17))
    cv2.fillPoly(rgb, [trunk[[0, 1, 2]]], (0.32, 0.2, 0.11))
    cv2.fillPoly(a, [trunk], 1.0)
    cv2.fillPoly(tr, [trunk], 1.0)
    pal = PALETTES[seed % 3]
    for simp in Delaunay(pts).simplices:
        c = pts[simp].mean(0)
        if cv2.pointPolygonTest(H, (float(c[0]), float(c[1])), False) < 0:
            continue
        lit = ((c[0] - cx) / rx + (c[1] - cy) / ry) * 0.55 + r.normal(0, 0.25)
        col = pal[int(np.clip(round((lit + 1) / 2 * (len(pal) - 1)), 0, len(pal) - 1))]
        p = np.round(pts[simp]).astype(np.int32)
        cv2.fillPoly(rgb, [p], tuple(map(float, col)))
        cv2.fillPoly(a, [p], 1.0)
        cv2.fillPoly(tr, [p], 0.0)
    return reduce_drawing(rgb, a, tr, size, ss)


def test_thin_facet_outline_is_straight():
    """A bent facet 3-5 px wide: its outline stood 0.83 px off its polygon at 3 px (collapsed onto
    the midline; main refused it), now 0.3 px. A thin crescent of the same size stays curved."""
    m = np.zeros((20, 30), np.uint8)
    cv2.fillPoly(m, [np.int32([[2, 2], [14, 4], [24, 12], [4, 6]])], 1)
    (_, resid, fine, coarse), = _outline_stats(m)
    assert resid < 0.5, resid
    assert _straight_edged(m)
    yy, xx = np.mgrid[:40, :40]
    crescent = ((xx - 20) ** 2 + (yy - 20) ** 2 <= 100) & ~((xx - 23) ** 2 + (yy - 17) ** 2 <= 100)
    assert not _straight_edged(crescent.astype(np.uint8))
    assert not _straight_edged(crescent.astype(np.uint8), residual=0.8)


@pytest.mark.parametrize("size", [96, 128])
def test_small_faceted_crowns_found_in_a_library(size):
    """Through a library (enlarged 1.1-1.3 times): main found 4/24 at 96 px, 8/24 at 128 px (now 10, 10)."""
    lib = TreeLibrary(size=size)
    found = 0
    for seed in range(12):
        for aa in (True, False):
            img, tr = faceted(size, seed, aa)
            e = lib.add(img, f"t{seed}{aa}", trunk_mask=tr)
            found += facet_palette(e.image, e.trunk, pixel=_source_pixel(e)) is not None
    assert found >= {96: 8, 128: 9}[size], found


def test_shaded_photo_crowns_not_low_poly():
    """Smoothly shaded crowns cut into quantisation bands (each band a thin polygon) were taken
    for low-poly at 96-256 px; neighbouring bands one step apart tell them apart."""
    yy, xx = np.mgrid[:128, :128]
    img = np.zeros((128, 128, 4), np.float32)
    crown = ((xx - 64) / 36.0) ** 2 + ((yy - 50) / 44.0) ** 2 <= 1
    img[crown] = np.stack([0.05 + 0.25 * xx[crown] / 128, 0.3 + 0.45 * xx[crown] / 128, 0.1 + 0.1 * yy[crown] / 128,
                           np.ones(crown.sum())], 1)
    assert facet_palette(img) is None
    for size in (96, 128):
        lib = TreeLibrary.from_data(["plain_tree", "poplar_tree_with_branches"], size=size)
        taken = [e.name for e in lib.exemplars if facet_palette(e.image, e.trunk, pixel=_source_pixel(e)) is not None]
        assert not taken, (size, taken)
