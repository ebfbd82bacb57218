"""Benchmarks of the shared core."""

from __future__ import annotations

import cv2
import numpy as np

from ..bench import BenchRow, timeit
from .render import draw_polylines


def rows(quick: bool = False) -> list[BenchRow]:
    rng = np.random.default_rng(0)
    n_lines = 50 if quick else 200
    lines = [np.cumsum(rng.normal(0, 3, (100, 2)), axis=0) + 256 for _ in range(n_lines)]
    canvas = np.ones((512, 512, 3), np.float32)
    ours = timeit(lambda: draw_polylines(canvas, lines, widths=3.0, colors=(0, 0, 0)))

    def anchor():
        img = np.full((512, 512, 3), 255, np.uint8)
        pts = [np.round(p * 16).astype(np.int32) for p in lines]
        cv2.polylines(img, pts, False, (0, 0, 0), 3, cv2.LINE_AA, shift=4)

    return [
        BenchRow(
            f"draw_polylines 512x512, {n_lines} x 100 vertices, AA width 3",
            ours,
            "cv2.polylines LINE_AA (constant width, uint8)",
            timeit(anchor),
            "ours also does per-vertex width and float output",
        )
    ]
