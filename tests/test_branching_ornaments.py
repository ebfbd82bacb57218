"""Issue 23, unseen ornaments: a drawn stroke of two colours (a black stroke with a coloured inner
line on white paper) is traced along its centre, as one stroke of its full width, so fragments
keep the inner line in the middle (procedural examples with a known centre line and width)."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import extract_structure
from branchnb.branching._image_examples import random_tree
from branchnb.branching._map_examples import country_map_example
from branchnb.branching.ridges import multi_colour_ink
from branchnb.core.render import coverage_polylines
from branchnb.core.structure import Branch, Structure


def _double_line(n: int, seed: int, inner, outer_w: float, inner_w: float):
    tree = random_tree((n, n), seed, n_children=4, grandchildren=1)
    tree = Structure([Branch(b.points, np.full(len(b.points), outer_w / 2), b.parent, b.parent_vertex)
                      for b in tree.branches], (n, n))
    pts = [b.points for b in tree.branches]
    cov, _ = coverage_polylines((n, n), pts, [outer_w] * len(pts))
    cin, _ = coverage_polylines((n, n), pts, [inner_w] * len(pts))
    img = np.ones((n, n, 3)) * (1 - cov[..., None])
    img = img * (1 - cin[..., None]) + cin[..., None] * np.asarray(inner, float)
    return img.astype(np.float32), tree


@pytest.mark.parametrize("n,seed,inner,outer_w,inner_w", [(256, 1, (0.85, 0.1, 0.1), 6.0, 2.0),
                                                           (384, 2, (0.85, 0.1, 0.1), 9.0, 3.0),
                                                           (320, 4, (0.1, 0.7, 0.2), 8.0, 2.5)])
def test_two_colour_strokes_are_traced_along_their_centre(n, seed, inner, outer_w, inner_w):
    img, truth = _double_line(n, seed, inner, outer_w, inner_w)
    assert multi_colour_ink(img) is not None
    found = extract_structure(img)
    pts = np.vstack([b.points for b in found.branches])
    r = np.concatenate([np.broadcast_to(b.thickness, len(b.points)) for b in found.branches])
    # on the inner line (its colour), not along one of the black edges (measured before: radius 0.5,
    # the centre line on a black edge)
    iy = np.clip(np.rint(pts[:, 1]).astype(int), 0, n - 1)
    ix = np.clip(np.rint(pts[:, 0]).astype(int), 0, n - 1)
    on_inner = np.abs(img[iy, ix] - np.asarray(inner, np.float32)).max(-1) < 0.3
    assert on_inner.mean() >= 0.8, on_inner.mean()
    # one stroke of the full width
    assert 0.75 <= np.median(r) / (outer_w / 2) <= 1.3, np.median(r)
    # about the true length (once, not as two edge lines)
    ratio = sum(b.length for b in found.branches) / sum(b.length for b in truth.branches)
    assert 0.8 <= ratio <= 1.2, ratio


def test_plain_drawings_and_maps_are_no_two_colour_strokes():
    img, _t = _double_line(200, 3, (0.0, 0.0, 0.0), 6.0, 2.0)          # one ink colour
    assert multi_colour_ink(img) is None
    for size, seed in ((96, 3), (128, 4), (256, 5)):                     # land, sea, rivers, coast
        assert multi_colour_ink(country_map_example((size, size), seed, layout="island")[0]) is None
    rng = np.random.default_rng(0)
    assert multi_colour_ink(rng.random((64, 64, 3))) is None             # a photograph
