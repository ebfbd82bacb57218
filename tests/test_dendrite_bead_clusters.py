"""Beads of a ring under ``OUTLINE_MIN_PART`` of the picture each and a 2 x 2 cluster of bumpy
discs whose middle fills in come apart disc by disc (issue 25, dendrite46); separate specks
under ``OUTLINE_MIN_PART`` still fall out and a blob with one dent stays whole."""

from __future__ import annotations

import numpy as np
import pytest
from test_dendrite_notch_rings import _agreement, _ring

from branchnb.dendrite.strike_notch import split_at_notches
from branchnb.dendrite.strike_outline import outline_parts


def _bumpy_cluster(n: int, gap: float, fill: float, seed: int) -> np.ndarray:
    """Label image of 4 discs in a 2 x 2 grid spanning ``fill`` of ``n``, centres ``gap`` radii
    apart, each with random bumps (one notch of the four comes out blunt)."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:n, 0:n]
    r = fill * n / (gap + 2)
    lab = np.zeros((n, n), int)
    for i, (a, b) in enumerate(((0, 0), (0, 1), (1, 0), (1, 1)), 1):
        cx = n / 2 + (a - 0.5) * gap * r + rng.normal(0, 0.02 * r)
        cy = n / 2 + (b - 0.5) * gap * r + rng.normal(0, 0.02 * r)
        ang = np.arctan2(yy - cy, xx - cx)
        ph = rng.uniform(0, 2 * np.pi, 6)
        bump = 1 + sum(0.03 * np.sin(j * ang + ph[j]) for j in range(2, 6))
        lab[(np.hypot(xx - cx, yy - cy) < r * bump) & (lab == 0)] = i
    return lab


@pytest.mark.parametrize(("n", "k", "gap", "rr"), [(256, 8, 1.5, 0.06), (768, 10, 1.4, 0.05),
                                                    (512, 9, 1.6, 0.055)])
def test_small_beads_of_a_ring_come_apart(n, k, gap, rr):
    lab = _ring(n, k, gap, rr)
    assert (lab == 1).mean() < 0.02  # each bead under OUTLINE_MIN_PART of the picture
    m, agree = _agreement(outline_parts(lab > 0), lab)
    # before: 2 parts, agreement 0.17-0.26 (beads merged until a part held 2 % of the picture)
    assert m == k and agree >= 0.7


@pytest.mark.parametrize(("n", "gap", "seed"), [(256, 1.15, 258), (512, 1.15, 514), (768, 1.3, 770)])
def test_a_filled_cluster_with_a_blunt_notch_comes_apart(n, gap, seed):
    lab = _bumpy_cluster(n, gap, 0.9, seed)
    m, agree = _agreement(outline_parts(lab > 0), lab)
    # before: 1 / 2 / 3 parts, agreement 0.36 / 0.48 / 0.49
    assert m == 4 and agree >= 0.55


def test_specks_fall_out_and_a_dented_blob_stays_whole():
    yy, xx = np.mgrid[0:256, 0:256]
    specks = np.zeros((256, 256), bool)
    for x in range(30, 230, 40):
        specks |= np.hypot(xx - x, yy - 128) < 12  # each ~0.7 % of the picture
    assert outline_parts(specks).max() == 0
    big = specks | (np.hypot(xx - 128, yy - 200) < 50)
    assert outline_parts(big).max() == 1
    # an apple: one sharp dent at its top, no cut for its ray to cross
    apple = (np.hypot(xx - 105, yy - 140) < 70) | (np.hypot(xx - 151, yy - 140) < 70)
    apple &= ~(np.hypot(xx - 128, yy - 40) < 35)
    assert split_at_notches(apple, 0.02 * apple.size) is None
    assert outline_parts(apple).max() == 1
