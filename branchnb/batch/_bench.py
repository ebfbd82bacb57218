"""Benchmark rows of batch generation: items per second on 1 and 2 Dask workers.

Two jobs: tree variations (light items, where the client's bookkeeping and
Dask's overhead show) and billboard clouds of the sample trees (heavy items,
where per-item work dominates). For each, a 1-worker and a 2-worker
``LocalCluster`` run the same batch in the same process, each warmed up
first (imports, numba compilation); the time is the run's
``compute_seconds``, the best of a few runs (first submitted item to last
recorded one: the steady throughput a long batch has, without the cluster
start and the one-off preparation, which
:class:`~branchnb.batch.runner.BatchSummary` reports apart; the best, as
another process's burst only ever slows a run). The ratio is 2-worker time / 1-worker time (0.5 = linear scaling).
The machine's load average is in the note: other processes competing for
the cores distort any scaling figure.
"""

from __future__ import annotations

import logging
import os
import tempfile

from ..bench import BenchRow


def _throughput(n_workers: int, spec, warm, reps: int = 1) -> tuple[float, float]:
    """(compute seconds of the batch, best of ``reps`` runs; mean worker RSS in MB) on a fresh LocalCluster."""
    import psutil
    from dask.distributed import Client, LocalCluster

    from .runner import run_batch

    with LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0", preload=["branchnb.batch._worker_setup"],
                      silence_logs=logging.ERROR) as cluster, \
            Client(cluster) as client:
        with tempfile.TemporaryDirectory() as tmp:
            run_batch(warm, tmp, client=client, chunk=1, progress=None)
        best = float("inf")
        for _ in range(reps):
            with tempfile.TemporaryDirectory() as tmp:
                summary = run_batch(spec, tmp, client=client, progress=None)
            if summary.failed:
                raise RuntimeError(f"benchmark batch had {summary.failed} failed items")
            best = min(best, summary.compute_seconds)
        rss = client.run(lambda: psutil.Process().memory_info().rss)
    return best, sum(rss.values()) / len(rss) / 2**20


def _row(label: str, n: int, spec, warm, reps: int = 1) -> BenchRow:
    load0 = os.getloadavg()[0]
    t1, mem1 = _throughput(1, spec, warm, reps)
    t2, mem2 = _throughput(2, spec, warm, reps)
    load1 = os.getloadavg()[0]
    return BenchRow(
        f"batch: {label} on Dask, 2 workers ({n / t2:.2f} items/s)",
        t2, f"same batch, 1 worker ({n / t1:.2f} items/s)", t1,
        f"0.5 = linear scaling ({t1 / t2:.2f}x); compute time, start-up excluded, best of {reps}; memory per worker "
        f"{mem2:.0f} MB (1 worker: {mem1:.0f} MB); load average {load0:.1f} -> {load1:.1f} on "
        f"{os.cpu_count()} cores",
    )


def rows(quick: bool = False) -> list[BenchRow]:
    from .spec import BatchSpec

    n, size = (12, 192) if quick else (40, 256)
    inputs = {"library": ["tree_rpg_01", "tree_rpg_03", "tree_rpg_06"], "size": size, "trunk": "stem"}
    spec = BatchSpec("tree_variations", count=n, seed=1, inputs=inputs)
    warm = BatchSpec("tree_variations", count=2, seed=2, inputs=inputs)
    out = [_row(f"{n} tree variations {size}x{size}", n, spec, warm, 1 if quick else 3)]
    m = 4 if quick else 12
    clouds = {"library": ["tree_rpg_01", "tree_rpg_03", "tree_rpg_06"], "from_variations": False}
    spec = BatchSpec("billboard_cloud", count=m, seed=1, inputs=clouds)
    warm = BatchSpec("billboard_cloud", count=2, seed=2, inputs=clouds)
    out.append(_row(f"{m} billboard clouds of the sample trees (glTF + atlas)", m, spec, warm, 1 if quick else 2))
    return out
