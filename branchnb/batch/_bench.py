"""Benchmark row of batch generation: tree variations per second on 1 and 2 Dask workers.

Both clusters run in the same process, each warmed up first (numba
compilation, imports) so the row compares steady throughput; the ratio is
2-worker time / 1-worker time (0.5 = perfect scaling). The note gives the
resident memory of each worker after its batch.
"""

from __future__ import annotations

import logging
import tempfile

from ..bench import BenchRow


def _throughput(n_workers: int, spec, warm) -> tuple[float, float]:
    """(seconds for the batch, mean worker RSS in MB) on a fresh LocalCluster."""
    import psutil
    from dask.distributed import Client, LocalCluster

    from .runner import run_batch

    with LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        with tempfile.TemporaryDirectory() as tmp:
            run_batch(warm, tmp, client=client, chunk=1, progress=None)
        with tempfile.TemporaryDirectory() as tmp:
            summary = run_batch(spec, tmp, client=client, progress=None)
        if summary.failed:
            raise RuntimeError(f"benchmark batch had {summary.failed} failed items")
        rss = client.run(lambda: psutil.Process().memory_info().rss)
    return summary.seconds, sum(rss.values()) / len(rss) / 2**20


def rows(quick: bool = False) -> list[BenchRow]:
    from .spec import BatchSpec

    n, size = (12, 192) if quick else (40, 256)
    inputs = {"library": ["tree_rpg_01", "tree_rpg_03", "tree_rpg_06"], "size": size, "trunk": "stem"}
    spec = BatchSpec("tree_variations", count=n, seed=1, inputs=inputs)
    warm = BatchSpec("tree_variations", count=2, seed=2, inputs=inputs)
    t1, mem1 = _throughput(1, spec, warm)
    t2, mem2 = _throughput(2, spec, warm)
    return [BenchRow(
        f"batch: {n} tree variations {size}x{size} on Dask, 2 workers ({n / t2:.2f} items/s)",
        t2, f"same batch, 1 worker ({n / t1:.2f} items/s)", t1,
        f"0.5 = linear scaling; memory per worker {mem2:.0f} MB (1-worker run: {mem1:.0f} MB); "
        "includes library preparation and scatter",
    )]
