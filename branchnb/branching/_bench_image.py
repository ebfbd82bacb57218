"""Benchmark rows of fragment-based image synthesis (issue 3, items 9-10).

``bench_rows(quick)`` is meant to be called from :mod:`branchnb.branching._bench`.
The anchor is the paper's own figure: 8.6 to 72.8 s per synthesized image
on the authors' machine (so the ratio compares different machines).
"""

from __future__ import annotations

import importlib.util
import time

import numpy as np

from ..bench import BenchRow
from ._image_examples import random_tree, river_example
from .image_synthesis import ImageSynthesisParams, synthesize_image

__all__ = ["bench_rows"]

PAPER_FASTEST = 8.6  # seconds per image, paper (range 8.6 to 72.8 s)
NOTE = "paper figure (8.6 to 72.8 s per image), other machine"
REPEAT = 3


def _median_time(fn, repeat: int = REPEAT) -> float:
    """Median wall time of ``repeat`` calls (one slow call on a shared machine does not decide)."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def _river_row(size: int, repeat: int = REPEAT) -> BenchRow:
    img, src = river_example((size, size), 0, n_children=4)
    tgt = random_tree((size, size), 7, n_children=5, grandchildren=1)
    last = {}

    def run():
        last["r"] = synthesize_image(img, src, tgt, rng=0)

    sec = _median_time(run, repeat)
    r = last["r"]
    return BenchRow(
        f"image synthesis {size} x {size}, procedural river ({len(r.fragments)} fragments "
        f"+ gap completion, {100 * r.fill_mask.mean():.0f}% filled)",
        sec, "paper, fastest reported image", PAPER_FASTEST, _note(repeat))


def _note(repeat: int) -> str:
    return (f"median of {repeat} runs (the first included); " if repeat > 1 else "one run; ") + NOTE


def _retina_row() -> list[BenchRow]:
    """512 x 512 retina with an extracted example and a synthesized target structure.

    Needs the structure part of the technique (extraction, synthesis).
    """
    if (importlib.util.find_spec("branchnb.branching.extraction") is None
            or importlib.util.find_spec("branchnb.branching.synthesis") is None):
        return []
    from skimage.transform import resize

    from .. import data
    from .extraction import extract_structure
    from .synthesis import synthesize_structure

    img = data.load("retina_fundus")
    img = resize(img, (512, 512), anti_aliasing=True).astype(np.float32).clip(0, 1)
    example = extract_structure(img)
    target = synthesize_structure(example, rng=6).structure
    params = ImageSynthesisParams(flatten_shading=0.05)
    last = {}

    def run():
        last["r"] = synthesize_image(img, example, target, params, rng=0)

    sec = _median_time(run)
    return [BenchRow(
        f"image synthesis 512 x 512, retina (extracted example, synthesized target, "
        f"{len(last['r'].fragments)} fragments + gap completion)",
        sec, "paper, fastest reported image", PAPER_FASTEST, _note(REPEAT))]


def bench_rows(quick: bool = False) -> list[BenchRow]:
    """Image synthesis time for a 512 x 512 output (256 x 256 with ``quick``, timed once)."""
    if quick:
        return [_river_row(256, repeat=1)]
    return [_river_row(512)] + _retina_row()
