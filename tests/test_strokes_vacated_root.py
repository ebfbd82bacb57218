"""A child copied away from its parent leaves the parent whole (issue 25).

A fern pinna whose only target stroke lies elsewhere (copied to the rachis's
base) gave its root pixels up from the rachis's tube and nothing laid them
again: the cut face's outline bit ~4 px into the rachis, with two flecks of the
pinna's root beside it. The answer is known: the same fern drawn without that
pinna. Around the old root the edit must match it.
"""
import os
import sys

import pytest

from branchnb.core.image import composite_over
from branchnb.strokes import edit_structure

sys.path.insert(0, os.path.dirname(__file__))
import strokes_unseen_objects as U  # noqa: E402


def _without(name, n):
    """``U.fern(n)`` drawn without the part called ``name``."""
    orig = U._square_canvas

    def canvas(*a, **k):
        c, nn, kk = orig(*a, **k)
        part = c.part
        c.part = lambda pts, nm, *r: None if nm == name else part(pts, nm, *r)
        return c, nn, kk

    U._square_canvas = canvas
    try:
        return U.fern(n).image
    finally:
        U._square_canvas = orig


@pytest.mark.parametrize("n", [300, 600])
def test_copied_pinna_leaves_rachis_whole(n):
    obj, src, tgt, _, _ = U.edit_fern(n)
    res = edit_structure(obj.image, src, tgt)
    ref = _without("pinna 6", n)
    p = obj.strokes[6][0]
    h = int(0.03 * n) + 4
    win = (slice(int(p[1]) - h, int(p[1]) + h), slice(int(p[0]) - h, int(p[0]) + h))
    a, ar = res.image[..., 3][win] > 0.5, ref[..., 3][win] > 0.5
    g = composite_over(res.image)[win][..., :3].mean(axis=2)
    gr = composite_over(ref)[win][..., :3].mean(axis=2)
    # main: 32 / 119 px of the pinna's root left beside the rachis, its outline 0 / 2 px inside
    assert int((a & ~ar).sum()) <= 0.01 * n
    # (the rachis's rim: anti-aliased pixels either side of 0.5)
    assert int((ar & ~a).sum()) <= 0.03 * n
    assert int(((g < 0.2) & (gr > 0.3) & ar).sum()) == 0
