"""Flat sources under a stretching warp: ink over pure fills, no smear; the identity stays exact
(issue 24, trees27).

Procedural clip-art trees (``branchnb.trees._clipart_check``) warped by a known stretch with
``transfer_colour`` and compared with the same tree drawn stretched. On main the fills were
sampled bilinearly across the anti-aliased pixels between strokes and fills, so a 2x stretch
spread them into a 2-4 px dark smear (smear 0.012-0.077, PSNR 26.1-26.5 dB on the 1 px cases
below) and blurred the 4 px outlines' edges (wrong pixels per edge pixel 0.08-0.25).
"""

import numpy as np
import pytest

from branchnb.trees._clipart_check import clipart_tree, edge_error, smear_share, spill, stretched
from branchnb.trees.mvc import _stretch, transfer_colour
from branchnb.trees.outline import _ink_threshold, _is_ink


def test_local_stretch_of_simple_warps():
    one = np.array([[1.0, 0.0]]), np.array([[0.0, 1.0]])
    assert _stretch(*one)[0] == pytest.approx(1.0)
    assert _stretch(np.array([[0.5, 0.0]]), np.array([[0.0, 1.0]]))[0] == pytest.approx(2.0)
    c, s = np.cos(0.7), np.sin(0.7)
    assert _stretch(np.array([[c, s]]), np.array([[-s, c]]))[0] == pytest.approx(1.0)
    assert _stretch(np.array([[2 * c, 2 * s]]), np.array([[-s, c]]))[0] == pytest.approx(1.0)


def test_identity_warp_copies_a_flat_drawing_exactly():
    src = clipart_tree("cloud", line=1.0, rng=1, size=96)
    h, w = src.shape[:2]
    cage = np.array([(-0.5, -0.5), (w - 0.5, -0.5), (w - 0.5, h - 0.5), (-0.5, h - 0.5)])
    out = transfer_colour([src], [cage], cage, np.ones((h, w), bool), colour_weights=[1.0], mode="choose")
    op = src[..., 3] >= 0.5
    assert np.array_equal(out[..., 3] >= 0.5, op)
    ink = _is_ink(src[..., :3], _ink_threshold(src[..., :3], op)) & op
    d = np.abs(out[..., :3] - src[..., :3]).max(axis=2)
    assert d[op & ~ink].max() == 0.0                      # every fill and anti-aliased pixel as drawn
    # ink pixels take the colour of the darkest ink in their footprint, as on main (<= 0.05 here)
    assert d[ink].max() <= 0.05


@pytest.mark.parametrize("kind, seed, smear_max, psnr_min", [("round", 0, 0.02, 27.5), ("cloud", 1, 0.005, 27.0)])
def test_thin_outlines_stretched_twice_do_not_smear(kind, seed, smear_max, psnr_min):
    src, out, ref = stretched(kind, 0.5, seed, 128, (2.0, 2.0))
    assert smear_share(out, [src]) <= smear_max          # main: 0.077 / 0.012
    assert edge_error(out, ref)[0] >= psnr_min           # main: 26.5 / 26.1 dB


@pytest.mark.parametrize("kind, seed, f, wrong_max", [("cloud", 1, (2.0, 1.0), 0.04), ("round", 0, (2.0, 2.0), 0.15)])
def test_thick_outlines_stretched_keep_hard_edges(kind, seed, f, wrong_max):
    src, out, ref = stretched(kind, 2.0, seed, 128, f)
    assert edge_error(out, ref)[1] <= wrong_max          # main: 0.081 / 0.247
    # the fruit's colour reaches the silhouette no more than in the stretched drawing
    assert spill(out, 2.0 * min(f)) <= spill(ref, 2.0 * min(f)) + 0.005


def test_gap_between_outline_and_fruit_ring_keeps_the_crown_colour():
    # a fruit 1 px below the crown's 1 px outline: the row between them is a dark green mix; its
    # nearest pure pixel is the fruit's, and filling it with that painted an orange bar
    src, out, ref = stretched("round", 1.0, 0, 256, (2.0, 1.0))
    assert spill(out, 1.0) <= spill(ref, 1.0) + 0.002
