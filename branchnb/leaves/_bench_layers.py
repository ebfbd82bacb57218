"""Benchmarks of the leaves' analysis (layers, registration, induction) and layered synthesis.

``rows()`` is meant to be included by :mod:`branchnb.leaves._bench`.

Targets (issue 22): analysis of 8 exemplars of ~250 px under 10 s, of 4
exemplars at ~1 MP under 20 s; one new 1 MP leaf under 1 s with a peak
of under 1 GB of array memory (``tracemalloc`` sees NumPy's and OpenCV's
output arrays, not OpenCV's scratch buffers).
"""

from __future__ import annotations

import time
import tracemalloc

import cv2
import numpy as np

from ..bench import BenchRow, timeit


def _family(n: int, size: int):
    from .procedural import leaf_family
    return leaf_family(n, size=size, rng=1)


def _layers(leaf, size: int):
    from .layers import Layer, LayerSet, simulate_scribbles
    return LayerSet([Layer("veins", "#d62728", 0, simulate_scribbles(leaf.layers["veins"], 12,
                                                                      length=0.06 * size, rng=0)),
                     Layer("spots", "#1f77b4", 1, simulate_scribbles(leaf.layers["spots"], 12,
                                                                     length=0.025 * size, rng=0))])


def _shiftmap(analysis, e: int = 1):
    """Anchor: OpenCV's shift-map inpainting of the vein layer of one exemplar.

    (The example-based fill we did not use for the residuals.)
    """
    img8 = np.ascontiguousarray((analysis.exemplars[e][..., :3] * 255).astype(np.uint8))
    keep = np.where(analysis.layer("veins").masks[e], 0, 255).astype(np.uint8)

    def run():
        out = np.zeros_like(img8)
        cv2.xphoto.inpaint(img8, keep, out, cv2.xphoto.INPAINT_SHIFTMAP)

    return timeit(run, repeat=1, warmup=False)


def _analysis(n: int, size: int):
    """The analysis, its wall time and the process's CPU time (the unloaded 2-core wall is about
    ``CPU - saved``, ``saved`` the threads' overlap: see the rows' notes)."""
    from .analysis import analyze
    fam = _family(n, size)
    t0, c0 = time.perf_counter(), time.process_time()
    a = analyze(fam, 0, _layers(fam[0], size))
    return a, time.perf_counter() - t0, time.process_time() - c0


def rows(quick: bool = False) -> list[BenchRow]:
    from .synthesis import generate

    out = []
    # Many small exemplars: a user's phone photos cut to ~250 px.
    small_n, small_size = (4, 160) if quick else (8, 256)
    a, t, cpu = _analysis(small_n, small_size)
    mp = a.exemplars[0].shape[0] * a.exemplars[0].shape[1] / 1e6
    out.append(BenchRow(f"leaves analysis: {small_n} exemplars {mp:.2f} MP each, 2 layers", t,
                        "one cv2.xphoto shift-map inpainting of one vein layer", _shiftmap(a),
                        f"CPU {cpu:.1f} s this run; "
                        "target < 10 s for 8 exemplars of ~250 px (CPU, loaded 2 cores: 12.6 s before the "
                        "compiled snapping, 8-9 s after; issue 22 speed pass, A/B: one run at load ~25 "
                        "15.5 -> 10.2 s, three interleaved at load ~4 9.7-10.4 -> 9.2-10.0 s; the same layers; "
                        "issue 22 margin pass (vectorised start and mirror searches, Cholesky TPS-RPM), CPU A/B "
                        "at load ~25: 10.8 -> 8.1, 7.1 -> 4.9, 5.4 -> 4.9 s, the same layers and leaves; "
                        "issue 22 kernel pass (subnormal "
                        "softassign weights flushed, one compiled call per pose search, OpenCV's exact EDT, CIELAB "
                        "once, ridge evidence on the blade's box), CPU A/B at load ~12-16: 9.8 -> 8.7, 9.9 -> 8.3 s, "
                        "the same layers; TPS-RPM vectorised exp and OpenCV binary morphology (SciPy's masks), "
                        "interleaved CPU A/B at load ~20: 10.47 -> 8.96, 10.73 -> 9.12 s, identical layers and "
                        "residuals, maps within 4e-6 px; issue 22 TPS-RPM values pass (each round solved for "
                        "the spline's values at its centres, no (K, K) product), same-load CPU A/B at load ~25: "
                        "7.69 -> 6.69 s, registration 3.23 -> 2.20 s, identical layers, maps within 4e-6 px; "
                        "issue 22 threads pass (the exemplars registered, snapped, their CIELAB, S_e, distance maps "
                        "and masks in threads, core.threads; numba kernels nogil; the closed blade's distance map "
                        "once per exemplar): identical layers on the maples, 8 x 256 px, 4 x 512 px elliptic and "
                        "trilobed, 4 x 1 MP lobed; same-load CPU at load ~22: main 5.78 s, threads 5.86 s, one thread "
                        "5.88 s (OpenBLAS kept on one thread inside the pool: without, two threads spin-waited, "
                        "8.26 s); the threaded jobs are 4.8 of 6.1 s CPU, their overlap on 2 idle cores saves an "
                        "estimated 1.2-2.4 s (each job's thread CPU: sum minus max(longest, sum / 2), halved when "
                        "half of it holds the GIL): unloaded wall ~3.5-4.5 s; measured wall 9.7 s at load ~14)"))
    size = 384 if quick else 1000
    a, t_analysis, cpu = _analysis(4, size)
    mp = a.exemplars[0].shape[0] * a.exemplars[0].shape[1] / 1e6
    out.append(BenchRow(f"leaves analysis: 4 exemplars {mp:.2f} MP, 2 layers (lazy snapping, TPS-RPM, "
                        "induction, residuals)", t_analysis,
                        "one cv2.xphoto shift-map inpainting of one vein layer", _shiftmap(a),
                        f"CPU {cpu:.1f} s this run; "
                        "target < 20 s at ~1 MP (CPU, loaded 2 cores: 38-39 s before the compiled snapping, "
                        "25-27 s after; issue 22 speed pass (registration 2.5 -> 1.3-1.5 s per exemplar with "
                        "its dense maps, lazy snapping 3.4 -> 2.3 s), A/B runs: 30.4 -> 20.2 s at load ~25, "
                        "33.6 -> 20.4 s at load ~4; margin pass, CPU A/B at load ~25: 12.5 -> 11.6, 11.6 -> 11.2 s; "
                        "memory pass (S_e on the blades' boxes, D and ||x, c|| recomputed when read, residuals[0] "
                        "the exemplars themselves; colour term on the blade's box): held by the analysis 447 -> "
                        "304 MB, traced peak 656 -> 612 MB, CPU 24.4 -> 23.0 s at load ~12, the same layers); "
                        "kernel pass (as the row above), CPU A/B at load ~12-16: 22.5 -> 19.6, 21.7 -> 19.4 s, the "
                        "same layers; fill-holes and colour-EMD pass (OpenCV flood fill for scipy's "
                        "binary_fill_holes; S_e's per-bin terms in one compiled float32 pass), same-run CPU A/B at "
                        "load ~3-4: lobed 19.1 -> 17.9 s, fan 19.3 -> 17.8 s, identical layers and registrations; "
                        "integer-addressed pose-search kernel (whole-pixel shifts), two interleaved CPU A/B pairs "
                        "at load ~15-20: 20.5 -> 18.8, 19.4 -> 18.6 s, identical layers and registrations; "
                        "extend_nearest indices only with np.take (1 MP: 51 -> 35 ms per RGB call, x24), "
                        "interleaved CPU A/B at load ~10-15: 18.6 -> 17.6, 16.5 -> 17.3 s (within the noise), "
                        "identical layers and registrations; "
                        "TPS-RPM vectorised exp (1 ulp of np.exp) and OpenCV binary morphology (SciPy's masks), "
                        "interleaved CPU A/B at load ~20: 22.29 -> 20.13, 22.37 -> 19.00 s, identical layers and "
                        "residuals (maps within 6e-5 px); "
                        "TPS-RPM values pass (as the row above), same-load CPU A/B at load ~25: 19.42 -> 19.21 s, "
                        "registration 2.92 -> 2.63 s (the induction, 12.4 s, is most of it), veins IoU >= 0.9996, "
                        "maps within 6e-5 px; "
                        "issue 22 threads pass (as the row above), identical layers, same-load CPU at load ~22: "
                        "main 20.20 s, threads 18.65 s, one thread 18.56 s; threaded jobs 10.1 of 18.2 s CPU, "
                        "estimated overlap on 2 idle cores 2.5-5.0 s: unloaded wall ~13-16 s; measured wall "
                        "25.8 s at load ~10; "
                        "layers split pass (lazy snapping without np.union1d's and np.unique's sorts, the pixel "
                        "cut's colour distances reused): grow_layers on the 1 MP training leaf 1.88 -> 1.61 s CPU, "
                        "whole analysis same-load CPU A/B at load ~40: 19.11 -> 19.15 s (within the noise), "
                        "identical layers; "
                        "the paper: several minutes"))
    # The per-analysis preparation (stage images bled, layers completed, petioles), paid by the first leaf.
    t_prep = timeit(lambda: generate(a, 1, rng=0), repeat=1, warmup=False)
    out.append(BenchRow(f"leaves synthesis: preparation of 4 exemplars {mp:.2f} MP (first leaf)", t_prep,
                        "the analysis of the same 4 exemplars", t_analysis,
                        "paid once per analysis; issue 22 preparation pass (push-pull's finest level as a select, "
                        "OpenCV binary morphology, flat-art test stops at the first photo, nearest colours on the "
                        "ring's box), interleaved CPU A/B of the preparation alone at load ~20: 1.12 MP 8.98 -> 5.81, "
                        "8.48 -> 5.56 s; 0.30 MP 2.30 -> 1.47, 2.25 -> 1.45 s; new leaves bit-identical"))
    t_gen = timeit(lambda: generate(a, 1, rng=1), repeat=2, warmup=False)
    tracemalloc.start()
    try:
        generate(a, 1, rng=2)
        peak = tracemalloc.get_traced_memory()[1] / 1e9
    finally:
        tracemalloc.stop()
    rgba = a.exemplars[0]
    h, w = rgba.shape[:2]
    mx, my = np.meshgrid(np.arange(w, dtype=np.float32) + 0.3, np.arange(h, dtype=np.float32) + 0.3)
    t_remap = timeit(lambda: cv2.remap(rgba, mx, my, cv2.INTER_LINEAR))
    out.append(BenchRow(f"leaves synthesis: one new leaf {mp:.2f} MP", t_gen,
                        "one cv2.remap of the RGBA leaf", t_remap,
                        f"peak array memory {peak:.2f} GB (tracemalloc); target < 1 s and < 1 GB per leaf at ~1 MP "
                        "(CPU at load ~25: 0.4-0.7 s, 0.27 GB; preparation pass, interleaved CPU A/B at load ~20: "
                        "1.12 MP 0.94 -> 0.91, 0.88 -> 0.85 s per leaf, 0.30 MP 0.30 -> 0.29, 0.27 -> 0.26 s, "
                        "traced peak 0.26 GB unchanged, the same leaves; sampling pass (grain split and Lanczos "
                        "on the source box, petiole on its output box, affine grids by row and column, the map "
                        "continued past the canvas only there), interleaved CPU A/B at load ~20-40, 4 leaves "
                        "after the caches: 1.12 MP 0.73 -> 0.57, 0.68 -> 0.63, 0.60 -> 0.56 s; 0.25 MP 0.16 -> "
                        "0.14, 0.17 -> 0.14, 0.15 -> 0.14 s; 1.90 MP 1.12 -> 1.01 s; traced peak 0.229 -> 0.222 "
                        "GB at 1.12 MP; 48 leaves at 0.25/1.12/1.90 MP bit-identical; work-box pass (background, "
                        "layers, compositing, petiole and outline on the lamina's box plus two patch sides, and the"
                        " petiole's), interleaved CPU A/B at load ~25-30, 4 leaves after the caches: 0.25 MP 0.198 "
                        "-> 0.177, 0.173 -> 0.216 s (noise); 1.12 MP 0.641 -> 0.640, 0.613 -> 0.563 s; 1.90 MP "
                        "1.063 -> 0.996, 1.095 -> 1.002 s; traced peak 0.050 -> 0.048, 0.222 -> 0.219, 0.374 -> "
                        "0.369 GB; 24 leaves bit-identical; still on the whole canvas: the shape map (blend, pose, "
                        "fit; about 30 % of a leaf) and the random warps)"))
    return out
