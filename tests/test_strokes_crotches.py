"""Crotches of new branches rounded like the source's own (issue 25).

A branch grown where the source has none meets its parent at a corner
nobody drew: the patches gave a sharp one (tree_rpg_12 + a new branch:
both crotches turned by 82-88 degrees within ~3 px) where the source's own
obtuse crotches turn over ~20-px arcs. Sharp sources (the procedural
objects) stay sharp, and nothing changes away from the new junction.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.strokes import edit_structure
from branchnb.strokes._examples import TREE_LEFT, TREE_MIDDLE, tree_add_branch
from branchnb.strokes.crotches import crotch_shape
from branchnb.strokes.procedural import bare_tree


def _tee(fillet: int):
    yy, xx = np.mgrid[0:120, 0:120]
    m = (np.abs(xx - 60) <= 12) | ((np.abs(yy - 60) <= 8) & (xx >= 60))
    if fillet:
        disk = np.hypot(*np.mgrid[-fillet:fillet + 1, -fillet:fillet + 1]) <= fillet
        m = ndi.binary_closing(np.pad(m, fillet + 1), disk)[fillet + 1:-fillet - 1, fillet + 1:-fillet - 1]
    return ndi.gaussian_filter(m.astype(float), 0.7)


@pytest.mark.parametrize("fillet", [0, 8, 14])
def test_crotch_shape_measures_the_fillet(fillet):
    got = crotch_shape(_tee(fillet), (60, 60), [(60, 60), (119, 60)], 8.0, reach=40.0)
    assert sorted(got) == [-1, 1]
    for turn, radius in got.values():
        if fillet:
            # the arc reads as one (its run may stop short of the full 90 degrees)
            assert radius >= 0.6 * fillet and radius <= 1.2 * fillet, got
        else:
            assert 80 <= turn <= 100 and radius < 3.0, got


def _no_rounding(monkeypatch):
    mod = sys.modules["branchnb.strokes.synthesis"]
    monkeypatch.setattr(mod, "new_crotches", lambda *a, **k: ([], None))


def test_a_new_branch_is_rounded_like_the_source_and_nothing_else_changes(monkeypatch):
    img, src, tgt, kw = tree_add_branch()
    alpha = img[..., 3]
    # the source's obtuse crotches turn over ~20-px arcs
    assert crotch_shape(alpha, TREE_MIDDLE[0], TREE_MIDDLE, 9.0)[-1][1] > 15
    assert crotch_shape(alpha, TREE_LEFT[0], TREE_LEFT, 12.0)[1][1] < 3  # its acute V stays sharp
    res = edit_structure(img, src, tgt, **kw)
    _no_rounding(monkeypatch)
    sharp = edit_structure(img, src, tgt, **kw)
    before = crotch_shape(sharp.image[..., 3], tgt[3][0], tgt[3], 9.0)
    after = crotch_shape(res.image[..., 3], tgt[3][0], tgt[3], 9.0)
    # before: both crotches turned by 82-88 degrees at a point
    assert min(t for t, _ in before.values()) > 75, before
    # after: what turns at a point is at most a 50-degree kink (the rest turns over the arc)
    assert max(t for t, _ in after.values()) < 50, after
    # the fillets filled the corners (and nothing else): all changes within 60 px of the junction (its reach + the arc)
    changed = np.any(res.image != sharp.image, axis=2)
    yy, xx = np.nonzero(changed)
    assert changed.sum() > 40
    assert np.hypot(xx - tgt[3][0][0], yy - tgt[3][0][1]).max() <= 60
    assert ((res.image[..., 3] > 0.5) >= (sharp.image[..., 3] > 0.5)).all()  # filled, never cut


def test_sharp_sources_stay_sharp(monkeypatch):
    """A procedural tree (sharp crotches) given a new limb: the same output as without rounding."""
    obj = bare_tree(300, rng=0)
    trunk, limb = obj.strokes[0], obj.strokes[1]
    new = limb - limb[0] + trunk[2]
    src, tgt = [trunk, limb, limb], [trunk, limb, new * [[-1, 1]] + [2 * trunk[2][0], 0]]
    res = edit_structure(obj.image, src, tgt)
    _no_rounding(monkeypatch)
    same = edit_structure(obj.image, src, tgt)
    assert np.array_equal(res.image, same.image)
