"""Mixes of polygonal crowns keep sharp tips: corners are matched before the contours are combined
(issue 24; ``branchnb/trees/corners.py``, beyond the paper)."""

import numpy as np
import pytest

from branchnb.trees import corners
from branchnb.trees._measure_corners import flat_tree, tip_stats
from branchnb.trees.variations import TreeLibrary, make_variation


def _square_with_notch(n=400):
    """A closed contour: a square's four sides sampled evenly (pins at 0, 40, 360)."""
    t = np.linspace(0, 4, n, endpoint=False)
    side = np.floor(t).astype(int)
    f = t - side
    corners_xy = np.array([[50, 100], [100, 100], [100, 50], [50, 50], [50, 100]], float)
    return corners_xy[side] * (1 - f[:, None]) + corners_xy[side + 1] * f[:, None]


def test_corners_are_found_on_a_square_and_not_on_a_circle():
    sq = _square_with_notch()
    idx, turn = corners._contour_corners(sq, (0, 40, 360))
    assert sorted(idx.tolist()) == [100, 200, 300]      # the corner at 0 is the pin B
    assert np.all(np.abs(np.abs(turn) - 90) < 15)
    a = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    circle = np.stack([75 + 40 * np.cos(a), 75 + 40 * np.sin(a)], 1)
    assert corners._contour_corners(circle, (0, 40, 360))[0].size == 0


def test_match_keeps_order_sign_and_shift():
    pairs = corners._match_corners(np.array([0.1, 0.3, 0.5]), np.array([1, -1, 1]),
                                  np.array([0.12, 0.28, 0.33, 0.9]), np.array([1, 1, -1, 1]))
    assert pairs == [(0, 0), (1, 2)]       # 0.5 has no partner within MATCH_SHIFT, 0.28 is a tip


def test_round_contours_are_left_alone():
    a = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    c1 = np.stack([75 + 40 * np.cos(a), 75 + 40 * np.sin(a)], 1)
    c2 = np.stack([75 + 30 * np.cos(a), 75 + 45 * np.sin(a)], 1)
    out = corners._corner_matched([c1, c2], [0.5, 0.5], (0, 40, 360))
    assert np.array_equal(out[0], c1) and np.array_equal(out[1], c2)


@pytest.fixture(scope="module")
def fir_library():
    lib = TreeLibrary(size=192)
    for i, (kind, h) in enumerate((("fir", 300), ("fir", 520), ("zigzag", 420))):
        lib.add(flat_tree(kind, i, h), f"{kind}{i}")
    return lib


@pytest.mark.parametrize("use", [(0, 1), (1, 2)])
def test_mixes_of_polygonal_crowns_keep_sharp_tips(fir_library, use):
    v = make_variation(fir_library, [0.5, 0.5], use=list(use), colour_weights="shape", rng=0)
    src, mix, kept = tip_stats(v.image[..., 3], [fir_library.exemplars[i].alpha for i in use])
    # arc-length correspondence (main): mixes' k sharpest tips turned 25-60 deg less than the
    # sources' and half their tips were lost; now within a few degrees, tips kept
    assert mix >= 0.9 * src
    assert kept >= 0.75


def test_a_round_mix_is_unchanged(monkeypatch):
    lib = TreeLibrary(size=128)
    for i, h in enumerate((260, 400)):
        lib.add(flat_tree("round", i, h), f"round{i}")
    v = make_variation(lib, [0.4, 0.6], colour_weights="shape", rng=1)
    monkeypatch.setattr("branchnb.trees.variations._tip_matched",
                        lambda cs, w, pins: ([np.asarray(c, float) for c in cs],) * 2 + ([],))
    old = make_variation(lib, [0.4, 0.6], colour_weights="shape", rng=1)
    assert np.array_equal(v.image, old.image)


def _outlined_disc():
    """A green disc with a 4 px black outline, a dark speck hanging 3 px under the outline at the
    top by a 1 px thread, and an inner line running from the outline deep into the crown."""
    import cv2
    img = np.zeros((120, 120, 4), np.float32)
    cv2.circle(img, (60, 60), 50, (0.2, 0.6, 0.2, 1.0), -1)
    cv2.circle(img, (60, 60), 48, (0.05, 0.05, 0.05, 1.0), 4)
    fleck = np.zeros((120, 120), np.uint8)
    cv2.fillPoly(fleck, [np.int32([[57, 17], [63, 17], [60, 20]])], 1)
    fleck[14:17, 60] = 1                                   # the thread to the outline
    img[fleck > 0, :3] = 0.05
    line = np.zeros((120, 120), np.uint8)
    cv2.line(line, (100, 60), (60, 60), 1, 3)
    img[line > 0, :3] = 0.05
    return img, fleck > 0, line > 0


def test_rim_flecks_of_outlined_mixes_are_repainted():
    from branchnb.trees.flat_art import _drop_rim_flecks
    img, fleck, line = _outlined_disc()
    out = _drop_rim_flecks(img, (0.05, 0.05, 0.05), 4.0)
    body = fleck.copy()
    body[14:17, 60] = False                                # the thread's top joins the outline
    assert np.all(out[body & (np.arange(120)[:, None] >= 18), 1] > 0.5)   # the speck is green now
    assert np.array_equal(out[line], img[line])           # the inner line stays
    ring = ~fleck & ~line & (np.abs(img[..., :3] - 0.05).max(axis=2) < 1e-6)
    assert np.array_equal(out[ring], img[ring])           # so does the outline
