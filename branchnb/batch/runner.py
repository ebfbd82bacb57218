"""Run a batch spec on Dask: scatter the shared inputs once, run chunks of items, record each item.

The client does the bookkeeping (which items are complete, the manifest,
writing files); workers only compute. Outputs travel back as bytes, so a
remote cluster (``scheduler="tcp://..."``) needs no shared file system,
only the installed package on its workers.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import logging
import os
import re
import signal
import threading
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .jobs import ItemOutput, Job
from .manifest import Manifest, file_record, write_atomic
from .progress import make_progress
from .spec import BatchSpec, _build_params, _plain, load_spec

__all__ = ["run_batch", "run_items", "BatchSummary", "item_stem", "spec_key"]

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_NON_FINITE = re.compile(r"(?i)(?<![a-z#])(nan|inf)(?![a-z])")


@dataclass
class BatchSummary:
    """What a run did.

    Attributes
    ----------
    job : str
    total : int
        Items in the spec.
    done : int
        Items computed in this run.
    skipped : int
        Items already complete in the manifest (resumed).
    failed : int
        Items that failed in this run (recorded with their error).
    seconds : float
        Wall time of the run.
    interrupted : bool
        The run was stopped (Ctrl-C / kernel interrupt); the manifest holds every finished item.
    outdir : Path
    workers : int
        Dask worker threads used (0 if nothing had to be computed).
    """

    job: str
    total: int
    done: int
    skipped: int
    failed: int
    seconds: float
    interrupted: bool
    outdir: Path
    workers: int = 0

    @property
    def items_per_second(self) -> float:
        """Items computed (done or failed) per second of this run."""
        n = self.done + self.failed
        return n / self.seconds if self.seconds > 0 else 0.0

    def __str__(self) -> str:
        state = "interrupted" if self.interrupted else "finished"
        left = self.total - self.done - self.skipped - self.failed
        parts = [f"{self.done} done", f"{self.skipped} already complete", f"{self.failed} failed"]
        if left:
            parts.append(f"{left} not run")
        return (f"batch {self.job} {state}: " + ", ".join(parts) + f" of {self.total} in "
                f"{self.seconds:.1f} s ({self.items_per_second:.2f} items/s on {self.workers} workers)")


def item_stem(job: Job, index: int, count: int) -> str:
    """File-name stem of item ``index``: ``<job stem>_<index, zero-padded to >= 5 digits>``."""
    return f"{job.stem}_{index:0{max(5, len(str(count - 1)))}d}"


def spec_key(spec: BatchSpec) -> str:
    """Fingerprint of what all items share (the job and its shared inputs)."""
    text = json.dumps({"job": spec.job, "inputs": spec.shared_inputs(),
                       "base_dir": str(spec.base_dir) if spec.base_dir else None}, sort_keys=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def _reject_constant(name):
    raise ValueError(f"non-standard JSON constant {name}")


def _check_file(name: str, content: bytes) -> None:
    """Refuse to write an invalid file (the package never writes one)."""
    suffix = Path(name).suffix.lower()
    if suffix == ".png" and not content.startswith(_PNG_SIGNATURE):
        raise ValueError(f"{name} is not a PNG")
    if suffix in (".json", ".gltf"):
        json.loads(content.decode("utf-8"), parse_constant=_reject_constant)
    if suffix == ".svg":
        root = ET.fromstring(content)
        if not root.tag.endswith("svg"):
            raise ValueError(f"{name}: the root element is {root.tag!r}, not svg")
        for el in root.iter():
            for attr, value in el.attrib.items():
                if _NON_FINITE.search(value):
                    raise ValueError(f"{name}: <{el.tag.rsplit('}', 1)[-1]} {attr}={value[:40]!r}> is not finite")


def _check_output(out, stem: str) -> ItemOutput:
    if not isinstance(out, ItemOutput):
        raise TypeError(f"the job's make() must return an ItemOutput, got {type(out).__name__}")
    if not out.files:
        raise ValueError("the item produced no file")
    for name, content in out.files.items():
        if not isinstance(name, str) or Path(name).name != name or not name.startswith(stem):
            raise ValueError(f"output file name {name!r} must be a plain name starting with {stem!r}")
        if not isinstance(content, (bytes, bytearray)):
            raise TypeError(f"output {name!r} must be bytes, got {type(content).__name__}")
        try:
            _check_file(name, bytes(content))
        except (ValueError, ET.ParseError, UnicodeDecodeError) as exc:
            raise ValueError(f"the job wrote an invalid file {name}: {exc}") from None
    return out


def run_items(job: Job, shared, items: list) -> list[dict]:
    """Compute a chunk of items (runs on a Dask worker).

    ``items`` holds ``(index, seed, params, inputs, stem)`` (``inputs``: the
    shared and the item inputs together); each result is a
    dict with ``item``, ``files`` (name -> bytes), ``info``, ``time`` and
    ``error`` (``"Type: message"`` or None). An item's exception is recorded,
    never raised, so the rest of the chunk and of the batch go on.
    """
    results = []
    for index, seed, params, inputs, stem in items:
        t0 = time.perf_counter()
        try:
            out = _check_output(job.make(shared, params, inputs, np.random.default_rng(seed), stem), stem)
            results.append({"item": index, "files": dict(out.files), "info": _plain(out.info, "info"),
                            "time": time.perf_counter() - t0, "error": None})
        except Exception as exc:  # noqa: BLE001 - one failing item must not stop the batch
            results.append({"item": index, "files": {}, "info": {}, "time": time.perf_counter() - t0,
                            "error": f"{type(exc).__name__}: {exc}"})
    return results


class _Interrupt:
    """SIGINT handling: Ctrl-C raises KeyboardInterrupt, but never while an item is being recorded."""

    def __init__(self):
        self.requested = False
        self.critical = False
        self._old = None

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            self._old = signal.signal(signal.SIGINT, self._handler)
        return self

    def __exit__(self, *exc):
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)

    def _handler(self, signum, frame):
        self.requested = True
        if not self.critical:
            raise KeyboardInterrupt

    def check(self):
        if self.requested:
            raise KeyboardInterrupt


def _default_workers() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def _connect(client, scheduler, n_workers):
    """``(client, cluster_we_own_or_None)``."""
    if client is not None:
        return client, None
    from dask.distributed import Client, LocalCluster

    if scheduler is not None:
        return Client(scheduler, timeout="30s"), None
    n = _default_workers() if n_workers is None else int(n_workers)
    if n < 1:
        raise ValueError(f"n_workers must be >= 1, got {n_workers!r}")
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=logging.ERROR)
    return Client(cluster), cluster


def run_batch(spec, outdir, *, client=None, scheduler: str | None = None, n_workers: int | None = None,
              chunk: int | None = None, progress="auto") -> BatchSummary:
    """Run every incomplete item of ``spec`` on Dask and record it in ``OUTDIR/manifest.jsonl``.

    Parameters
    ----------
    spec : BatchSpec, or path of a .json/.toml spec
    outdir : str or Path
        Output folder (created if needed). Items already complete there
        (see :mod:`branchnb.batch.manifest`) are skipped: running the same
        spec again resumes.
    client : dask.distributed.Client, optional
        Use this client (and its cluster).
    scheduler : str, optional
        Address of a running scheduler (``"tcp://host:8786"``); its workers
        need only the installed package.
    n_workers : int, optional
        Worker processes of the default ``LocalCluster`` (one per core).
    chunk : int, optional
        Items per Dask task (default: up to 16, so that every worker gets
        several tasks); cheap items in bigger chunks cost less overhead.
    progress : {"auto", "tqdm", "widget", None} or callable(done, total)
        ``"auto"``: an ipywidgets bar in a notebook, tqdm elsewhere.

    Returns
    -------
    BatchSummary

    Raises
    ------
    ValueError, TypeError
        An invalid spec or shared input (e.g. a library folder without
        trees). A single item's invalid parameters or failure is recorded in
        the manifest instead, and the batch goes on.

    Notes
    -----
    Item ``i`` gets ``numpy.random.default_rng(seed_i)`` with ``seed_i`` from
    ``SeedSequence(spec.seed).spawn(count)[i]``, so its files are identical
    whatever the number of workers and the order of completion. Ctrl-C (or
    interrupting the kernel) stops the run after recording the items that
    have finished; the summary says ``interrupted``.

    Examples
    --------
    >>> from branchnb.batch import BatchSpec, run_batch
    >>> spec = BatchSpec("dendrite_tree", count=2, inputs={"shape": [64, 56], "svg": False},
    ...                  params={"tree": {"iterations": 2, "radius": 12}})
    >>> import tempfile; out = tempfile.mkdtemp()
    >>> run_batch(spec, out, n_workers=1, progress=None).done       # doctest: +SKIP
    2
    """
    spec = spec if isinstance(spec, BatchSpec) else load_spec(spec)
    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1):
        raise ValueError(f"chunk must be an int >= 1, got {chunk!r}")
    t_start = time.perf_counter()
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    job = spec.job_info
    key = spec_key(spec)
    manifest = Manifest(outdir)
    seeds = spec.item_seeds()
    summary = BatchSummary(spec.job, spec.count, 0, 0, 0, 0.0, False, outdir)
    todo, invalid = [], []
    for i in range(spec.count):
        raw, inputs = spec.item_raw(i)
        stem = item_stem(job, i, spec.count)
        try:
            params = _build_params(job, raw, f"item {i} params")
        except (TypeError, ValueError) as exc:
            invalid.append((i, raw, inputs, f"{type(exc).__name__}: {exc}"))
            continue
        full = {s: dataclasses.asdict(p) for s, p in params.items()}
        meta = {"seed": seeds[i], "params": _plain(full, "params"), "inputs": inputs, "key": key}
        if manifest.is_complete(i, meta):
            summary.skipped += 1
        else:
            todo.append((i, params, inputs, stem, meta))

    bar = make_progress(progress, spec.count, summary.skipped, description=spec.job)
    interrupt = _Interrupt()

    def record(index, meta, files, info, seconds, error):
        interrupt.critical = True
        try:
            for name, content in files.items():
                write_atomic(outdir / name, bytes(content))
            manifest.append({"item": index, **meta, "status": "failed" if error else "done",
                             "files": [file_record(n, bytes(c)) for n, c in files.items()],
                             "info": info, "time": round(float(seconds), 4), "error": error})
            if error:
                summary.failed += 1
            else:
                summary.done += 1
            bar.advance(1, 1 if error else 0)
        finally:
            interrupt.critical = False
        interrupt.check()

    client_, cluster = None, None
    futures = {}
    with interrupt:
        try:
            for i, raw, inputs, err in invalid:
                record(i, {"seed": seeds[i], "params": raw, "inputs": inputs, "key": key}, {}, {}, 0.0, err)
            if todo:
                client_, cluster = _connect(client, scheduler, n_workers)
                summary.workers = int(sum(client_.nthreads().values())) or 1
                base = _build_params(job, spec.params, "params")
                shared = job.prepare(spec.shared_inputs(), spec.base_dir, base)
                [shared_future] = client_.scatter([shared], broadcast=True, hash=False)
                k = chunk or max(1, min(16, len(todo) // (4 * summary.workers)))
                chunks = [todo[j:j + k] for j in range(0, len(todo), k)]
                _run_chunks(client_, job, shared_future, spec.shared_inputs(), chunks, 2 * summary.workers,
                            futures, record)
        except KeyboardInterrupt:
            summary.interrupted = True
        finally:
            if futures and client_ is not None:
                client_.cancel(list(futures))
            manifest.compact()
            if client is None and client_ is not None:
                client_.close()
            if cluster is not None:
                cluster.close()
    summary.seconds = time.perf_counter() - t_start
    bar.close(summary)
    return summary


def _run_chunks(client, job, shared_future, shared_inputs, chunks, in_flight, futures, record):
    """Submit chunks with at most ``in_flight`` tasks queued; record every result as it arrives."""
    from dask.distributed import as_completed

    pending = iter(chunks)
    done_iter = as_completed()

    def submit_next():
        c = next(pending, None)
        if c is None:
            return
        payload = [(i, meta["seed"], params, {**shared_inputs, **inputs}, stem)
                   for i, params, inputs, stem, meta in c]
        fut = client.submit(run_items, job, shared_future, payload, pure=False)
        futures[fut] = c
        done_iter.add(fut)

    for _ in range(min(in_flight, len(chunks))):
        submit_next()
    for fut in done_iter:
        chunk = futures.pop(fut)
        try:
            results = fut.result()
        except Exception as exc:  # noqa: BLE001 - a lost worker fails its chunk, not the batch
            err = f"{type(exc).__name__}: {exc}"
            results = [{"item": i, "files": {}, "info": {}, "time": 0.0, "error": err} for i, *_ in chunk]
        by_item = {c[0]: c for c in chunk}
        for r in results:
            meta = by_item[r["item"]][4]
            record(r["item"], meta, r["files"], r["info"], r["time"], r["error"])
        submit_next()
