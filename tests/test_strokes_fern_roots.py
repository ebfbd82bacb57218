"""An edit leaves the pinnae it does not touch as they were (issue 25, strokes49).

A fern's pinnae hang from the rachis; the edit turns pinna 3 and copies pinna 6
and keeps the rachis. A pinna hanging from the rachis took, as pixels it lies
over the rachis with (``hidden._parts_over``), a strip of the rachis's own rim
between two knobs: the rachis's look filled in from farther along landed its
rim a pixel off. The rim was then laid again from elsewhere: stair-stepped, with
dark specks at untouched pinna roots. Around those roots the edit must keep the
source.
"""
import os
import sys

import numpy as np

from branchnb.core.image import composite_over
from branchnb.strokes import edit_structure

sys.path.insert(0, os.path.dirname(__file__))
import strokes_unseen_objects as U  # noqa: E402


def test_untouched_pinna_roots_keep_their_pixels():
    n = 600
    obj, src, tgt, _, _ = U.edit_fern(n)
    res = edit_structure(obj.image, src, tgt)
    c0 = composite_over(obj.image)[..., :3]
    c = composite_over(res.image)[..., :3]
    dark = (c.mean(axis=2) < 0.25) & (c0.mean(axis=2) > 0.35)
    changed = np.abs(c - c0).max(axis=2) > 0.2
    h = int(0.04 * n) + 5
    out = {}
    for k in (1, 2, 5, 7, 8):  # pinna 4's window reaches the turned pinna 3
        p = obj.strokes[k][0]
        win = (slice(int(p[1]) - h, int(p[1]) + h), slice(int(p[0]) - h, int(p[0]) + h))
        out[k] = (int(dark[win].sum()), int(changed[win].sum()))
    # before: pinna 5's root 12 dark / 29 changed px (the rachis's rim taken by it), now 0 / 0;
    # pinnae 1, 2, 7, 8: 0 / 1, 0 / 11, 3 / 12, 0 / 2 before as now (7: 4 / 12)
    assert out[5] == (0, 0), out
    assert sum(d for d, _ in out.values()) <= 6, out
    assert sum(ch for _, ch in out.values()) <= 35, out
