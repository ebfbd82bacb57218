"""Benchmark row of the billboard cloud.

``branchnb.trees._bench`` (the technique's bench module) calls
:func:`bench_rows` and appends its rows.
"""

from __future__ import annotations

from ..bench import BenchRow, timeit


def bench_rows(quick: bool = False) -> list[BenchRow]:
    from .. import data
    from .billboard import BillboardParams, billboard_cloud
    from .segmentation import segment_tree

    img = data.load("tree_with_fruits")          # 858 x 1023 RGBA
    seg = segment_tree(img, rng=0)
    size = 512 if quick else 1024
    params = BillboardParams(max_size=size)
    cloud = billboard_cloud(img, seg, params, rng=0)
    # The call above was the warm-up.
    secs = timeit(lambda: billboard_cloud(img, seg, params, rng=0), repeat=1 if quick else 2, warmup=False)
    h, w = cloud.image.shape[:2]
    return [
        BenchRow(
            f"billboard cloud, tree_with_fruits at {w}x{h}: {cloud.n_billboards} billboards "
            f"(SLIC 256, edge replacement, inflation, rear + {params.n_interior} interior)",
            secs,
            "paper: 20-50 s per billboard cloud (lower bound used)",
            20.0,
            "paper figure, other machine",
        ),
    ]
