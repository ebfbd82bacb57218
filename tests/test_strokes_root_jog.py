"""A lengthened finger's outline runs straight into its crotches (issue 25: finger root jog)."""

import numpy as np
import pytest

from branchnb.strokes import edit_structure
from branchnb.strokes.procedural_more import hand


def _scaled(st, f):
    st = np.asarray(st, float)
    return st[0] + f * (st - st[0])


def _sides(alpha, rows, centre, reach):
    """Per row: the distance from ``centre`` to the silhouette's left and right edges (sub-px)."""
    left, right = [], []
    for y, c in zip(rows, centre):
        on = alpha[y] > 0.5
        x0 = int(round(c))
        lo = hi = x0
        while lo > 0 and on[lo - 1] and x0 - lo < reach:
            lo -= 1
        while hi < len(on) - 1 and on[hi + 1] and hi - x0 < reach:
            hi += 1
        left.append(c - lo + alpha[y, lo - 1])
        right.append(hi - c + alpha[y, hi + 1])
    return np.array(left), np.array(right)


@pytest.mark.parametrize("size", [600, 1000])
def test_a_lengthened_finger_has_no_jog_above_its_crotches(size):
    """Palm kept, finger 2 lengthened 1.4x: over the 2.5 finger widths above its crotches the
    finger is as wide as the source finger just above them (before: the wide closing meant
    for turned children webbed both crotches, a jog of 2.7 / 3.2 px outward on the right and
    1.4 px on the left at 600 / 1000 px)."""
    obj = hand(size, rng=0)
    palm, f2 = obj.strokes[1], np.asarray(obj.strokes[3], float)
    new = _scaled(f2, 1.4)
    res = edit_structure(obj.image, [palm, f2], [palm, new])
    half = 0.0235 * size  # the finger's half width
    rows = np.arange(int(f2[0, 1] - 12 * half), int(f2[0, 1]))
    on_src = np.interp(rows, f2[::-1, 1], f2[::-1, 0])
    l0, r0 = _sides(obj.image[..., 3], rows, on_src, 3 * half)
    free = rows[(l0 + r0) < 2.3 * half]
    crotch = free.max()  # the lowest row where the source finger stands free of the palm
    band = (rows > crotch - 5 * half) & (rows < crotch - 2)
    ref = (rows > crotch - 5 * half) & (rows <= crotch)
    want_l, want_r = np.median(l0[ref]), np.median(r0[ref])
    l1, r1 = _sides(res.image[..., 3], rows[band], np.interp(rows[band], new[::-1, 1], new[::-1, 0]), 3 * half)
    # (the finger widens a little toward its root and is stretched with it: up to ~1.2 px;
    # the jog was 3.5 / 3.9 px on this measure)
    assert (r1 - want_r).max() <= 1.6 and (l1 - want_l).max() <= 1.6, ((r1 - want_r).max(), (l1 - want_l).max())
    assert (r1 - want_r).min() >= -1.0 and (l1 - want_l).min() >= -1.0, ((r1 - want_r).min(), (l1 - want_l).min())
