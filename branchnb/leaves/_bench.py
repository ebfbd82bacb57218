"""Benchmark rows of leaf variations: registration here, analysis and synthesis in ``_bench_layers``."""

from __future__ import annotations

import numpy as np

from ..bench import BenchRow, timeit


def rows(quick: bool = False) -> list[BenchRow]:
    from scipy.interpolate import RBFInterpolator

    from . import _bench_layers
    from .procedural import leaf_family
    from .registration import register

    size = 384 if quick else 1000
    tr, ex = leaf_family(2, size=size, rng=1)
    t_reg = timeit(lambda: register(ex, tr).map_to_training, repeat=1, warmup=False)
    # Anchor: a dense thin-plate-spline warp through the TRUE correspondences
    # with SciPy, evaluated at every pixel (what one dense map costs naively).
    h, w = tr.blade.shape
    yy, xx = np.mgrid[0:h, 0:w]
    grid = np.column_stack([xx.ravel(), yy.ravel()]).astype(float)

    def naive():
        RBFInterpolator(tr.keypoints, ex.keypoints, kernel="thin_plate_spline")(grid)

    t_naive = timeit(naive, repeat=1, warmup=False)
    mp = h * w / 1e6
    out = [BenchRow(f"leaves registration: one exemplar {mp:.2f} MP (starts, TPS-RPM, dense inverse)",
                    t_reg, "scipy RBFInterpolator TPS through 64 points, evaluated per pixel", t_naive,
                    "the paper's whole analysis: several minutes")]
    return out + _bench_layers.rows(quick)
