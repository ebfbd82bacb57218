"""Children queued but never grown are no comb of stubs (issue 23, branching42).

When the coverage target or the total length stops the growth, children already started (their
first segment copied) but not yet grown used to stay as short heads along their parent. They are
dropped, and the length they held is grown elsewhere (``_Filling._drop_unborn``).
"""

import numpy as np
import pytest

from branchnb.branching import extract_structure, synthesize_structure
from branchnb.branching._thin_mask_check import thin_mask_example


def _stubs(s):
    """Short thick leaf children: shorter than 8 r + 6 px, at least half the parent's radius r >= 1.2."""
    parents = {b.parent for b in s.branches if b.parent is not None}
    n = 0
    for i, b in enumerate(s.branches):
        if b.parent is None or i in parents:
            continue
        rp = float(s.branches[b.parent].thickness[b.parent_vertex])
        n += b.length < 8 * rp + 6 and float(np.mean(b.thickness)) >= 0.5 * rp and rp >= 1.2
    return n


def _crack(seed):
    # a random-walk crack mask, 300 x 450, lines 4 -> 1 px (_thin_mask_check's family). Seed 1 was used
    # until branching57: its two narrow cells between crack lines were filled as outlined strokes then
    # (no longer: ``ridges._parallel_sides``), and its new, fuller extraction sits on the bounds' edge
    # (seed 0: 1 stub, 5 short children; seeds 0-5 together as many as before). Seeds 7 and 5 are
    # extracted alike by both rules; without ``_drop_unborn`` they give 6 stubs and 9 short children.
    return extract_structure(thin_mask_example("crack", 450, seed))


@pytest.fixture(scope="module")
def crack():
    # rooted where the rule of branching57-77 rooted it (its end at (31, 186)): since branching78 the
    # default roots this crack at its bottom frame entry (70, 299), a different example for the same
    # mechanism, where seeds 0-2 give 2 / 1 / 0 stubs (the bound below was set on this one)
    return extract_structure(thin_mask_example("crack", 450, 7), root=(31.0, 186.0))


@pytest.fixture(scope="module")
def crack_leaves():
    return _crack(5)


def test_no_head_stubs_and_length_kept(crack):
    ex_len = sum(b.length for b in crack.branches)
    stubs, ratios = [], []
    for seed in range(3):
        res = synthesize_structure(crack, rng=seed)
        s = res.structure
        stubs.append(_stubs(s))
        ratios.append(sum(b.length for b in s.branches) / ex_len)
    # before: 12 stubs in seed 0 (a comb of copied heads along the last parents grown), now 0
    assert sum(stubs) <= 1, stubs
    # the heads' length grown elsewhere: 0.95-0.99 (dropping them alone gave 0.79-0.93; before 0.97-1.01)
    assert min(ratios) >= 0.9, ratios
    assert max(ratios) <= 1.1, ratios


def test_every_leaf_child_grew(crack_leaves):
    res = synthesize_structure(crack_leaves, rng=0)
    s = res.structure
    m = 4  # SynthesisParams.m: a head is at most m + 1 vertices after the furcation point
    parents = {b.parent for b in s.branches if b.parent is not None}
    # a leaf child longer than a bare head, unless it left the domain / frame on its way
    short = [i for i, b in enumerate(s.branches)
             if b.parent is not None and i not in parents and len(b.points) <= m + 2]
    h, w = s.image_shape
    at_frame = [i for i in short if not (3 < s.branches[i].points[-1][0] < w - 4
                                         and 3 < s.branches[i].points[-1][1] < h - 4)]
    assert len(short) - len(at_frame) <= 1, (short, at_frame)
