"""Issue 23 (branching84): a branch does not run along a side of the frame (frame_band.parallel_keep).

A painted root system's trunk (320 px) reached the bottom 20 px above the frame, outside the 6-px band,
turned and ran along it for 170 px.
"""
import numpy as np

from branchnb.branching.frame_band import PARALLEL_SHARE, parallel_keep


def _walk(pts, shape, skip=-1, step=5):
    """Feed ``pts`` to parallel_keep ``step`` points at a time, as growth does; the points kept."""
    run, kept = 0.0, [pts[0]]
    for i in range(1, len(pts), step):
        ok, run = parallel_keep(kept[-1], pts[i:i + step], run, shape, skip)
        kept.extend(pts[i:i + step][ok])
        if not ok.all():
            break
    return np.asarray(kept)


def test_trunk_turning_along_the_bottom_ends_there():
    H, W = 320, 320
    down = np.column_stack([np.full(70, 60.0), np.linspace(0, 295, 70)])
    along = np.column_stack([np.linspace(63, 250, 60), np.full(60, 297.0)])
    kept = _walk(np.vstack([down, along]), (H, W), skip=1)
    run_x = kept[:, 0].max() - 60.0
    assert kept[:, 1].max() >= 290            # it went down to the bottom
    assert run_x <= PARALLEL_SHARE * W + 10   # and ran along it at most a 16th of it (+ one step), not 190 px


def test_steep_and_far_branches_kept():
    H, W = 320, 320
    down = np.column_stack([np.full(80, 100.0), np.linspace(0, 318, 80)])        # straight down to the frame
    assert len(_walk(down, (H, W), skip=1)) == len(down)
    mid = np.column_stack([np.linspace(20, 300, 80), np.full(80, 160.0)])        # across the middle
    assert len(_walk(mid, (H, W))) == len(mid)
    top = np.column_stack([np.linspace(20, 300, 80), np.full(80, 10.0)])         # along the entry side
    assert len(_walk(top, (H, W), skip=1)) == len(top)
    assert len(_walk(top, (H, W))) < 20                                           # any other side: cut
