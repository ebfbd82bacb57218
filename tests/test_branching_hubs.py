"""Radial examples (issue 23, branching62): a blob much wider than the lines leaving it (a soma, a
coral's centre, a crater) is traced as a hub, a region without spurs, and the structure is rooted there."""
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import extract_structure
from branchnb.branching._hub_check import _case, measure
from branchnb.branching._radial_examples import radial_example
from branchnb.branching.extraction import skeleton_to_structure


@pytest.mark.parametrize("kind, size, seed", [("neuron", 384, 1), ("crack_bright", 384, 1), ("coral_dark", 256, 2)])
def test_radial_examples_rooted_at_their_hubs(kind, size, seed):
    # main: neuron 384/1 (two somas) hub 0.00, roots 1.00, 2 spurs; crack_bright 384/1 hub 0.00; coral_dark
    # 256/2 hub 0.00, roots 2, 1 spur
    r = _case(kind, size, seed, None)
    assert r["hub"] == 1.0, r                            # every hub roots a tree
    assert r["roots"] == 1.0, r                          # ... and only the hubs
    assert r["spurs"] == 0, r                            # no branch ends inside a hub
    assert r["rec"] >= 0.9, r


def test_binary_neuron_mask_rooted_at_its_soma():
    _rgb, centre, lines, hubs = radial_example("neuron", 384, 0)
    s = extract_structure(np.where(lines, 0.0, 1.0))     # black ink on white: a binary mask
    r = measure(s, centre, lines, hubs)
    assert r["hub"] == 1.0 and r["roots"] == 1.0 and r["spurs"] == 0, r
    root = next(b for b in s.branches if b.parent is None)
    x, y, rad = hubs[0]
    assert np.hypot(*(root.points[0] - (x, y))) <= 0.3 * rad
    assert root.thickness[0] <= 0.3 * rad                # the soma is no fat root start (the synthesis smeared it)


def _soma(n_lines: int, elongation: float = 1.0, size: int = 160):
    yy, xx = np.mgrid[:size, :size]
    c = size // 2
    m = np.hypot((yy - c) / elongation, xx - c) <= 12
    sk = np.zeros((size, size), bool)
    for k in range(n_lines):
        a = 2 * np.pi * k / n_lines + 0.3
        t = np.arange(0, 0.45 * size)
        sk[np.rint(c + t * np.sin(a)).astype(int), np.rint(c + t * np.cos(a)).astype(int)] = True
    return m | ndi.binary_dilation(sk), sk


def test_find_hubs_wants_a_round_blob_with_three_lines_leaving():
    from branchnb.branching.hubs import find_hubs

    m, sk = _soma(5)
    hubs = find_hubs(m, sk, np.where(sk, 1.0, 0.0))
    assert len(hubs) == 1 and hubs[0].centre == (80, 80) and len(hubs[0].arms) == 5
    m, sk = _soma(2)                                     # a lake on a river: two lines, no hub
    assert find_hubs(m, sk, np.where(sk, 1.0, 0.0)) == []
    m, sk = _soma(5, elongation=2.5)                     # a long thick stretch, no hub
    assert find_hubs(m, sk, np.where(sk, 1.0, 0.0)) == []


def test_soft_dark_spot_among_lines_is_no_hub():
    # a fundus's fovea: a dark spot fading from its middle, vessels around it
    from branchnb.branching.hubs import blob_contrast, find_hubs

    size = 200
    yy, xx = np.mgrid[:size, :size]
    g = 0.8 - 0.5 * np.exp(-(np.hypot(yy - 100, xx - 100) / 18.0) ** 2)
    sk = np.zeros((size, size), bool)
    for k in range(5):
        a = 2 * np.pi * k / 5
        t = np.arange(30, 95)
        sk[np.rint(100 + t * np.sin(a)).astype(int), np.rint(100 + t * np.cos(a)).astype(int)] = True
    g = np.where(ndi.binary_dilation(sk), 0.4, g)
    con = blob_contrast(g, sk, "dark")
    assert find_hubs(con >= 0.5, sk, np.where(sk, 1.0, 0.0), con) == []


def test_auto_root_splits_a_piece_between_two_hubs():
    sk = np.zeros((60, 200), bool)
    sk[30, 10:190] = True
    s = skeleton_to_structure(sk, np.full(sk.shape, 1.0), root="auto", hubs=[(30, 40), (30, 160)],
                              min_branch_length=5)
    starts = sorted(tuple(np.round(b.points[0]).astype(int)) for b in s.branches if b.parent is None)
    assert starts == [(40, 30), (160, 30)]
