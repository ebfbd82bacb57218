"""Small patchwork examples: fields not laid over and over, no halo beside the river (issue 23, branching103).

A 160-256 px example of 21 Voronoi fields has 8-11 fields cut by its frame and 2-3 whole ones: the framed
fields were left out, and 97-100 % of the pasted ground lay in a field laid 3 or more times (a visible
repeat). Framed fields are now laid against the same side of the output's frame (``patchwork.FRAME_FIELDS``)
and a field laid again is drawn less often (``patchwork.REPEAT_PENALTY``).
"""

from __future__ import annotations

import numpy as np
import pytest
from test_branching_patchwork import _fields, _river
from test_branching_patchwork_fields import _axis_aligned, _dist, _halo

from branchnb.branching import synthesize_image
from branchnb.branching.patchwork import paste_fields
from branchnb.core.structure import Branch, Structure


def _repeated(filled, source, shape) -> float:
    """Share of the pasted pixels whose example pixel was pasted more than twice."""
    sx, sy = source[filled][:, 0].astype(int), source[filled][:, 1].astype(int)
    count = np.zeros(shape, int)
    np.add.at(count, (sy, sx), 1)
    return float(np.mean(count[sy, sx] > 2))


@pytest.mark.parametrize("n, seed", [(160, 0), (160, 3), (256, 1), (256, 2)])
def test_small_patchwork_fields_do_not_repeat(n, seed):
    ex = _fields(n, seed, cells=21)
    canvas = np.zeros((n, n, 3), np.float32)
    covered = np.zeros((n, n), bool)
    filled, source = paste_fields(canvas, covered, ex, np.zeros((n, n), bool), rng=seed)
    assert covered.all()
    sx, sy = source[filled][:, 0].astype(int), source[filled][:, 1].astype(int)
    assert np.array_equal(canvas[filled], ex[sy, sx])
    # before: 0.14 / 0.37 / 1.00 / 1.00 of the ground in a field laid 3+ times; after 0.16 / 0.30 / 0.22 / 0.21
    assert _repeated(filled, source, (n, n)) <= 0.35
    # the framed fields' cut edges lie on the frame, not inside the ground: axis-aligned share of the colour
    # edges 0.13 / 0.11 / 0.05 / 0.03 before (examples 0.04 / 0.06 / 0.05 / 0.01), 0.03 / 0.10 / 0.07 / 0.02 after
    inner = np.zeros((n, n), bool)
    inner[3:-3, 3:-3] = True
    assert _axis_aligned(canvas, inner) <= _axis_aligned(ex, inner) + 0.06


def test_small_river_over_fields_without_halo():
    n, width, seed = 256, 9, 1
    t = np.linspace(0, 1, 60)
    src = np.stack([n * (0.45 + 0.1 * np.sin(3 * t + 2)), -2 + (n + 4) * t], 1)
    tgt = np.stack([-2 + (n + 4) * t, n * (0.5 + 0.12 * np.sin(2.5 * t + 2))], 1)
    img = _river(_fields(n, seed, cells=21), src, width, seed)
    inside = lambda p: p[(p[:, 0] >= 0) & (p[:, 0] <= n - 1) & (p[:, 1] >= 0) & (p[:, 1] <= n - 1)]  # noqa: E731
    S = Structure([Branch(inside(src), width / 2)], image_shape=(n, n))
    T = Structure([Branch(inside(tgt), width / 2)], image_shape=(n, n))
    out = synthesize_image(img, S, T, rng=seed).image[..., :3]
    # halo share above the example's: 0.27 before (the ground repeated 2-3 fields), 0.09 after
    assert _halo(out, _dist(tgt, n), width / 2) <= _halo(img, _dist(src, n), width / 2) + 0.12
