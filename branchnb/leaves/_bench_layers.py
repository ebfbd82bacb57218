"""Benchmarks of the leaves' analysis (layers, registration, induction) and layered synthesis.

``rows()`` is meant to be included by :mod:`branchnb.leaves._bench`.
"""

from __future__ import annotations

import time

import cv2
import numpy as np

from ..bench import BenchRow, timeit


def _family(size: int):
    from .procedural import leaf_family
    return leaf_family(4, size=size, rng=1)


def rows(quick: bool = False) -> list[BenchRow]:
    from .analysis import analyze, normalise_exemplars
    from .layers import Layer, LayerSet, simulate_scribbles
    from .synthesis import generate

    size = 384 if quick else 1000
    fam = _family(size)
    leaf = fam[0]
    ls = LayerSet([Layer("veins", "#d62728", 0, simulate_scribbles(leaf.layers["veins"], 12,
                                                                    length=0.06 * size, rng=0)),
                   Layer("spots", "#1f77b4", 1, simulate_scribbles(leaf.layers["spots"], 12,
                                                                   length=0.025 * size, rng=0))])
    t0 = time.perf_counter()
    a = analyze(fam, 0, ls)
    t_analysis = time.perf_counter() - t0
    images, blades, _ = normalise_exemplars(fam)
    mp = images[0].shape[0] * images[0].shape[1] / 1e6

    # Anchor: OpenCV's shift-map inpainting of the vein layer of one exemplar
    # (the example-based fill we did not use for the residuals).
    img8 = np.ascontiguousarray((images[1][..., :3] * 255).astype(np.uint8))
    keep = np.where(a.layer("veins").masks[1], 0, 255).astype(np.uint8)

    def shiftmap():
        out = np.zeros_like(img8)
        cv2.xphoto.inpaint(img8, keep, out, cv2.xphoto.INPAINT_SHIFTMAP)

    t_shift = timeit(shiftmap, repeat=1, warmup=False)
    generate(a, 1, rng=0)  # the per-analysis preparation, paid once
    t_gen = timeit(lambda: generate(a, 1, rng=1), repeat=2, warmup=False)
    rgba = a.exemplars[0]
    h, w = rgba.shape[:2]
    mx, my = np.meshgrid(np.arange(w, dtype=np.float32) + 0.3, np.arange(h, dtype=np.float32) + 0.3)
    t_remap = timeit(lambda: cv2.remap(rgba, mx, my, cv2.INTER_LINEAR))
    return [
        BenchRow(f"leaves analysis: 4 exemplars {mp:.2f} MP, 2 layers (lazy snapping, TPS-RPM, induction, residuals)",
                 t_analysis, "one cv2.xphoto shift-map inpainting of one vein layer", t_shift,
                 "target < 30 s at ~1 MP; the paper: several minutes"),
        BenchRow(f"leaves synthesis: one new leaf {mp:.2f} MP", t_gen,
                 "one cv2.remap of the RGBA leaf", t_remap, "target < 2 s per leaf at ~1 MP"),
    ]
