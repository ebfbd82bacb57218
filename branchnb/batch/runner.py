"""Run a batch spec on Dask: scatter the shared inputs once, run chunks of items, record each item.

The client does the bookkeeping (which items are complete, the manifest,
writing files); workers only compute. Outputs travel back as bytes, so a
remote cluster (``scheduler="tcp://..."``) needs no shared file system,
only the installed package on its workers.

Items are generated lazily (a spec of ten million items starts at once, in
little memory); the shared inputs are sent again when the worker holding
them is lost; a chunk whose worker died is computed again, and a chunk that
kills workers is split to find the one item that does.
"""

from __future__ import annotations

import asyncio
import dataclasses
import hashlib
import json
import logging
import os
import re
import time
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._guards import Interrupt, OutdirLock
from .jobs import ItemOutput, Job
from .manifest import Manifest, file_record, write_atomic
from .progress import make_progress
from .spec import BatchSpec, _build_params, _plain, load_spec

__all__ = ["run_batch", "run_items", "BatchSummary", "ClusterLostError", "item_stem", "spec_key"]

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_NON_FINITE = re.compile(r"(?i)(?<![a-z#])(nan|inf)(?![a-z])")


@dataclass
class BatchSummary:
    """What a run did.

    Parameters
    ----------
    job : str
        The job's name.
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
        The output folder (holds ``manifest.jsonl`` and the files).
    workers : int
        Dask worker threads used (0 if nothing had to be computed).
    startup_seconds : float
        From the call to the first submitted item: reading the manifest,
        starting the cluster, preparing and sending the shared inputs.
    compute_seconds : float
        From the first submitted item to the last recorded one.
    notes : list of str
        What the run reported on the way (unreadable manifest lines, ...).
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
    startup_seconds: float = 0.0
    compute_seconds: float = 0.0
    notes: list = dataclasses.field(default_factory=list)

    @property
    def computed(self) -> int:
        """Items computed in this run (done or failed)."""
        return self.done + self.failed

    @property
    def items_per_second(self) -> float:
        """Items computed per second once computing started (start-up excluded)."""
        return self.computed / self.compute_seconds if self.compute_seconds > 0 else 0.0

    @property
    def seconds_per_item(self) -> float:
        """Seconds per computed item once computing started (start-up excluded); 0 if none was computed."""
        return self.compute_seconds / self.computed if self.computed else 0.0

    def __str__(self) -> str:
        state = "interrupted" if self.interrupted else "finished"
        left = self.total - self.done - self.skipped - self.failed
        parts = [f"{self.done} done", f"{self.skipped} already complete", f"{self.failed} failed"]
        if left:
            parts.append(f"{left} not run")
        if self.computed:
            rate = (f"start-up {self.startup_seconds:.1f} s, then {self.seconds_per_item:.3g} s per item = "
                    f"{self.items_per_second:.2f} items/s on {self.workers} worker{'s' * (self.workers != 1)}")
        else:
            rate = "nothing computed"
        return f"batch {self.job} {state}: " + ", ".join(parts) + f" of {self.total} in {self.seconds:.1f} s ({rate})"


def item_stem(job: Job, index: int, count: int) -> str:
    """File-name stem of item ``index``: ``<job stem>_<index, zero-padded to >= 5 digits>``.

    Parameters
    ----------
    job : Job
        Gives the stem's prefix (``job.stem``).
    index : int
        The item's index in the spec (0-based).
    count : int
        Items in the spec: the padding is wide enough for ``count - 1``, so
        the names of one batch sort in item order.

    Returns
    -------
    str

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> item_stem(SimpleNamespace(stem="tree"), 17, 200)
    'tree_00017'
    >>> item_stem(SimpleNamespace(stem="tree"), 17, 1_000_000)
    'tree_000017'
    """
    return f"{job.stem}_{index:0{max(5, len(str(count - 1)))}d}"


def spec_key(spec: BatchSpec) -> str:
    """Fingerprint of what all items share (the job and its shared inputs).

    Parameters
    ----------
    spec : BatchSpec
        The spec; its job, shared inputs and ``base_dir`` are hashed (not
        ``count``, ``seed`` or the parameters, which are checked per item).

    Returns
    -------
    str
        16 hex digits; a manifest record with another key is recomputed.
    """
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

    Parameters
    ----------
    job : Job
        Its ``make`` computes each item.
    shared : object
        What ``job.prepare`` returned (scattered once to every worker).
    items : list of tuple
        ``(index, seed, params, inputs, stem)`` per item: ``seed`` (int)
        seeds the item's ``numpy.random.Generator``, ``params`` maps
        sections to parameter dataclasses.

    Returns
    -------
    list of dict
        One result per item, in the order of ``items``.
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



def _default_workers() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def _connect(client, scheduler, n_workers, dashboard: bool):
    """``(client, cluster_we_own_or_None)``.

    A local cluster listens on 127.0.0.1 only (scheduler, workers, nannies
    and the HTTP server); its dashboard is off unless asked for.
    """
    if client is not None:
        return client, None
    from dask.distributed import Client, LocalCluster

    if scheduler is not None:
        return Client(scheduler, timeout="30s"), None
    n = _default_workers() if n_workers is None else int(n_workers)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # e.g. "port 8787 in use": noise between the status lines
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address="127.0.0.1:0", scheduler_kwargs={"dashboard": bool(dashboard)},
                               preload=["branchnb.batch._worker_setup"], silence_logs=logging.ERROR)
    try:
        return Client(cluster), cluster
    except BaseException:
        cluster.close(timeout=10)
        raise


def _check_run_args(chunk, n_workers, client, scheduler, dashboard) -> None:
    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1):
        raise ValueError(f"chunk must be an int >= 1, got {chunk!r}")
    if n_workers is not None and (isinstance(n_workers, bool) or not isinstance(n_workers, int) or n_workers < 1):
        raise ValueError(f"n_workers must be an int >= 1, got {n_workers!r}")
    if scheduler is not None and (not isinstance(scheduler, str) or not scheduler):
        raise TypeError(f"scheduler must be an address like 'tcp://host:8786', got {scheduler!r}")
    if client is not None and scheduler is not None:
        raise ValueError("give either client or scheduler, not both")
    if not isinstance(dashboard, bool):
        raise TypeError(f"dashboard must be a bool, got {dashboard!r}")


class _Items:
    """The spec's items, generated one at a time: ``next_todo()`` records invalid ones and skips complete ones."""

    def __init__(self, spec: BatchSpec, manifest: Manifest, key: str, summary, bar, record):
        self.spec, self.job, self.manifest, self.key = spec, spec.job_info, manifest, key
        self.summary, self.bar, self.record = summary, bar, record
        self.next_index = 0
        self._peeked = None

    def _meta(self, i: int, params_plain, inputs) -> dict:
        return {"seed": self.spec.item_seeds([i])[0], "params": params_plain, "inputs": inputs, "key": self.key}

    def next_todo(self):
        """The next item to compute as ``(index, params, inputs, stem, meta)``, or None at the end."""
        if self._peeked is not None:
            item, self._peeked = self._peeked, None
            return item
        spec, job = self.spec, self.job
        while self.next_index < spec.count:
            i = self.next_index
            self.next_index += 1
            raw, inputs = spec.item_raw(i)
            try:
                params = _build_params(job, raw, f"item {i} params")
            except (TypeError, ValueError) as exc:
                self.record(i, self._meta(i, raw, inputs), {}, {}, 0.0, f"{type(exc).__name__}: {exc}")
                continue
            full = {s: dataclasses.asdict(p) for s, p in params.items()}
            meta = self._meta(i, _plain(full, "params"), inputs)
            if self.manifest.is_complete(i, meta):
                self.summary.skipped += 1
                self.bar.skip(1)
                continue
            return i, params, inputs, item_stem(job, i, spec.count), meta
        return None

    def peek(self):
        if self._peeked is None:
            self._peeked = self.next_todo()
        return self._peeked

    def take(self, k: int) -> list:
        out = []
        while len(out) < k:
            item = self.next_todo()
            if item is None:
                break
            out.append(item)
        return out


def run_batch(spec, outdir, *, client=None, scheduler: str | None = None, n_workers: int | None = None,
              chunk: int | None = None, progress="auto", dashboard: bool = False) -> BatchSummary:
    """Run every incomplete item of ``spec`` on Dask and record it in ``OUTDIR/manifest.jsonl``.

    Parameters
    ----------
    spec : BatchSpec, or path of a .json/.toml spec
        What to run: the job, the item count, the base seed, the inputs and
        parameters (a path is read with :func:`~branchnb.batch.spec.load_spec`).
    outdir : str or Path
        Output folder (created if needed). Items already complete there
        (see :mod:`branchnb.batch.manifest`) are skipped: running the same
        spec again resumes. One run at a time may use a folder (a lock).
    client : dask.distributed.Client, optional
        Use this client (and its cluster).
    scheduler : str, optional
        Address of a running scheduler (``"tcp://host:8786"``); its workers
        need only the installed package. The scheduler and workers run
        whatever the client sends (pickled functions and data): connect
        only to a cluster you trust, over TLS when it is not on your machine
        (see the README's "At scale").
    n_workers : int, optional
        Worker processes of the default ``LocalCluster`` (one per core).
    chunk : int, optional
        Items per Dask task. Default: adapted as the batch goes, one item
        per task at first, then about 0.2 s of work per task (at most 16
        items), shrinking to one item near the end so that no worker idles
        while another finishes a long chunk.
    progress : {"auto", "tqdm", "widget", None} or callable(done, total)
        ``"auto"``: an ipywidgets bar in a notebook, tqdm elsewhere (which
        also prints what the run is doing before the first item: starting
        the cluster, preparing the inputs).
    dashboard : bool
        Start the Dask dashboard of the local cluster (on 127.0.0.1 only,
        its address is printed); off by default.

    Returns
    -------
    BatchSummary

    Raises
    ------
    ValueError, TypeError
        An invalid spec or shared input (e.g. a library folder without
        trees, or a library image above the pixel limit), an unusable
        manifest (``manifest.jsonl`` is a folder), or the folder is in use
        by another run. A single item's invalid parameters or failure is
        recorded in the manifest instead, and the batch goes on.

        Shared inputs are prepared before the cluster starts, so a run no
        item can succeed in stops within seconds, in little memory, with
        the message naming the file (and, for an image, its declared size);
        as every item would fail with that message, the manifest records it
        once, as a run record (see :mod:`branchnb.batch.manifest`), rather
        than once per item.

    Notes
    -----
    Item ``i`` gets ``numpy.random.default_rng(seed_i)`` with ``seed_i`` from
    ``SeedSequence(spec.seed).spawn(count)[i]``, so its files are identical
    whatever the number of workers and the order of completion. Items are
    generated as the workers need them, so the first item starts within
    seconds whatever the count. Ctrl-C (or interrupting the kernel) at any
    moment stops the run after recording the items that have finished; the
    summary says ``interrupted``; further Ctrl-Cs during the shutdown are
    ignored. The loss of a worker costs only the items it was computing:
    they run again, and the shared inputs are sent again if no worker holds
    them any more.

    Examples
    --------
    >>> from branchnb.batch import BatchSpec, run_batch
    >>> spec = BatchSpec("dendrite_tree", count=2, inputs={"shape": [64, 56], "svg": False},
    ...                  params={"tree": {"iterations": 2, "radius": 12}})
    >>> import tempfile; out = tempfile.mkdtemp()
    >>> run_batch(spec, out, n_workers=1, progress=None).done       # doctest: +SKIP
    2
    """
    t_start = time.perf_counter()
    spec = spec if isinstance(spec, BatchSpec) else load_spec(spec)
    _check_run_args(chunk, n_workers, client, scheduler, dashboard)
    outdir = Path(outdir)
    if outdir.exists() and not outdir.is_dir():
        raise ValueError(f"outdir {str(outdir)!r} is a file, not a folder")
    outdir.mkdir(parents=True, exist_ok=True)
    summary = BatchSummary(spec.job, spec.count, 0, 0, 0, 0.0, False, outdir)
    bar = make_progress(progress, spec.count, 0, description=spec.job)
    interrupt = Interrupt()
    with interrupt:
        try:
            with OutdirLock(outdir):
                _run(spec, outdir, summary, bar, interrupt, client, scheduler, n_workers, chunk, dashboard,
                     t_start)
        except KeyboardInterrupt:
            summary.interrupted = True
        summary.interrupted = summary.interrupted or interrupt.requested
        summary.seconds = time.perf_counter() - t_start
        interrupt.closing = True
        bar.close(summary)
    return summary


def _run(spec, outdir, summary, bar, interrupt, client, scheduler, n_workers, chunk, dashboard, t_start):
    job = spec.job_info
    key = spec_key(spec)
    manifest = Manifest(outdir)
    for problem in manifest.problems:
        summary.notes.append(problem)
        bar.note(problem)

    def record(index, meta, files, info, seconds, error):
        interrupt.critical = True
        try:
            for name, content in files.items():
                write_atomic(outdir / name, bytes(content))
            manifest.append({"item": index, **meta, "status": "failed" if error else "done",
                             "files": [file_record(n, bytes(c)) for n, c in files.items()],
                             "info": info, "time": round(float(seconds), 4), "error": error}, sync=False)
            if error:
                summary.failed += 1
            else:
                summary.done += 1
            bar.advance(1, 1 if error else 0)
        finally:
            interrupt.critical = False
        interrupt.check()

    items = _Items(spec, manifest, key, summary, bar, record)
    client_, cluster = None, None
    futures = {}
    failure = None
    try:
        if items.peek() is None:
            return
        # the shared inputs first, before any cluster: a library no item can run without (a missing or
        # hostile image, ...) stops the run at once, in little memory, and the manifest says why
        bar.note(f"preparing the shared inputs of {spec.job} ...")
        try:
            base = _build_params(job, spec.params, "params")
            prepared = job.prepare(spec.shared_inputs(), spec.base_dir, base)
        except (ValueError, TypeError) as exc:
            failure = f"{type(exc).__name__}: {exc}"
            if type(exc) not in (ValueError, TypeError):
                raise
            raise type(exc)(f"{exc} (no item was run: the reason is recorded in {manifest.path})") from None
        interrupt.check()
        if client is None and scheduler is None:
            n = _default_workers() if n_workers is None else n_workers
            bar.note(f"starting a local Dask cluster: {n} worker process{'es' * (n != 1)} ...")
        elif scheduler is not None:
            bar.note(f"connecting to the Dask scheduler at {scheduler} ...")
        interrupt.deferred = True  # a KeyboardInterrupt inside Dask's start-up would strand half a cluster
        try:
            client_, cluster = _connect(client, scheduler, n_workers, dashboard)
            summary.workers = int(sum(client_.nthreads().values())) or 1
            _warm_up(client_, job)
        finally:
            interrupt.deferred = False
        interrupt.check()
        if dashboard and cluster is not None:
            bar.note(f"Dask dashboard (this machine only): {cluster.dashboard_link}")
        interrupt.deferred = True
        try:
            shared = _Shared(client_, prepared, interrupt)
        finally:
            interrupt.deferred = False
        interrupt.check()
        t0 = time.perf_counter()
        summary.startup_seconds = t0 - t_start
        bar.note(f"computing on {summary.workers} worker{'s' * (summary.workers != 1)} "
                 f"(start-up took {summary.startup_seconds:.1f} s)")
        bar.start()
        interrupt.deferred = True
        try:
            sizer = _ChunkSizer(chunk, summary.workers, lambda: spec.count - items.next_index)
            reruns = _run_chunks(client_, job, shared, spec.shared_inputs(), items, sizer, 2 * summary.workers,
                                 futures, record, interrupt, manifest.sync)
            if reruns or shared.resent:
                note = (f"{reruns} task(s) ran again after a worker was lost; the shared inputs were sent again "
                        f"{shared.resent} time(s)")
                summary.notes.append(note)
                bar.note(note)
        finally:
            interrupt.deferred = False
            summary.compute_seconds = time.perf_counter() - t0
    finally:
        interrupt.closing = True  # from here on Ctrl-C is only noted: nothing may tear the shutdown
        if futures and client_ is not None:
            try:
                client_.cancel(list(futures))
            except Exception:  # noqa: BLE001 - a dead scheduler: nothing left to cancel
                pass
        manifest.compact()
        if failure is not None:
            manifest.record_run_failure(failure, key, spec.count - summary.skipped - summary.done - summary.failed)
        if client is None and client_ is not None:
            client_.close(timeout=10)
        if cluster is not None:
            cluster.close(timeout=20)


def _import(module: str) -> None:
    import importlib

    importlib.import_module(module)


def _warm_up(client, job: Job) -> None:
    """Import the job's module on every worker now, so start-up is not billed to the first items."""
    if job.make.__module__.startswith("branchnb."):
        try:
            client.run(_import, job.make.__module__)
        except Exception:  # noqa: BLE001 - only an optimisation: the items import it anyway
            pass


class ClusterLostError(RuntimeError):
    """The cluster has had no worker for too long (they keep dying, or the scheduler is gone)."""


class _Shared:
    """The job's prepared inputs on the cluster: scattered once, sent again if every copy was lost."""

    def __init__(self, client, value, interrupt, patience: float = 120.0):
        self.client, self.value, self.interrupt, self.patience = client, value, interrupt, patience
        self.resent = 0
        self.future = self._scatter()

    def _scatter(self):
        # right after a worker died its nanny is still starting the next one: wait for a worker, in short
        # steps so that a Ctrl-C is not kept waiting
        deadline = time.monotonic() + self.patience
        while True:
            try:
                if not self.client.nthreads():
                    raise TimeoutError("no worker is up")
                [future] = self.client.scatter([self.value], broadcast=True, hash=False, timeout=30)
                return future
            except (TimeoutError, asyncio.TimeoutError, OSError) as exc:
                self.interrupt.check()
                time.sleep(0.5)
                if time.monotonic() > deadline:
                    raise ClusterLostError(f"the Dask cluster has had no worker to send the shared inputs to for "
                                           f"{self.patience:.0f} s ({exc})") from None

    def ensure(self):
        if self.future.status != "finished":
            self.resent += 1
            self.future = self._scatter()
        return self.future


_MAX_ATTEMPTS = 4


def _lost(exc: BaseException) -> bool:
    """Whether a task failed because its worker or its inputs were lost (not because of the item)."""
    from concurrent.futures import CancelledError

    name = type(exc).__name__
    return isinstance(exc, CancelledError) or name in ("FutureCancelledError", "CancelledError", "CommClosedError") \
        or "lost dependencies" in str(exc)


def _completed(futures: dict, interrupt):
    """The futures of ``futures`` as they complete (it may grow meanwhile); a Ctrl-C is raised here within
    0.2 s, never inside Dask's code."""
    from dask.distributed import wait

    while futures:
        interrupt.check()
        try:
            done, _ = wait(list(futures), timeout=0.2, return_when="FIRST_COMPLETED")
        except (TimeoutError, asyncio.TimeoutError):
            continue
        except Exception:  # noqa: BLE001 - wait() raises for cancelled futures (a lost worker): they are done too
            done = [f for f in list(futures) if f.done()]
            if not done:
                time.sleep(0.05)
        for fut in done:
            if fut in futures:
                yield fut


class _ChunkSizer:
    """How many items the next task gets: ``chunk`` if given, else adapted to the items' measured time.

    A task costs the client and the scheduler a few ms of CPU (on the same
    cores as the workers, on a local cluster), so cheap items go in chunks
    of up to 16, about :data:`TASK_SECONDS` of work each; but a chunk is
    also the grain of the load balance at the end of a batch (one worker
    finishing a long chunk while the other idles), so the first tasks hold
    one item each (their time is not known yet) and chunks shrink as the
    items left to submit fall below 4 chunks per worker.
    """

    TASK_SECONDS = 0.2
    MAX = 16

    def __init__(self, chunk, workers: int, left):
        self.fixed, self.workers, self.left = chunk, max(1, int(workers)), left
        self.seconds, self.n = 0.0, 0

    def observe(self, seconds: float) -> None:
        """One item took ``seconds`` on a worker."""
        self.seconds += max(0.0, float(seconds))
        self.n += 1

    def __call__(self) -> int:
        if self.fixed:
            return self.fixed
        if not self.n:
            return 1
        mean = max(self.seconds / self.n, 1e-4)
        cap = max(1, min(self.MAX, self.left() // (4 * self.workers)))
        return max(1, min(cap, round(self.TASK_SECONDS / mean)))


def _run_chunks(client, job, shared, shared_inputs, items, sizer, in_flight, futures, record, interrupt,
                sync=lambda: None):
    """Submit chunks of ``sizer()`` items, at most ``in_flight`` at a time; record every result as it arrives.

    Returns how many chunks ran again after a worker was lost.

    A chunk lost with its worker (or with the shared inputs) runs again, up
    to 4 times; a chunk that killed its workers (``KilledWorker``) is split
    into single items, so only the item that kills a worker fails.
    """
    from distributed import KilledWorker

    retry: list[tuple[list, int]] = []
    reruns = 0

    def submit(chunk, attempt):
        payload = [(i, meta["seed"], params, {**shared_inputs, **inputs}, stem)
                   for i, params, inputs, stem, meta in chunk]
        fut = client.submit(run_items, job, shared.ensure(), payload, pure=False)
        futures[fut] = (chunk, attempt)

    def submit_next():
        if retry:
            submit(*retry.pop(0))
            return
        chunk = items.take(sizer())
        if chunk:
            submit(chunk, 1)

    for _ in range(in_flight):
        submit_next()
    for fut in _completed(futures, interrupt):
        chunk, attempt = futures.pop(fut)
        try:
            results = fut.result()
        except KilledWorker as exc:
            if len(chunk) > 1:
                retry.extend(([c], attempt) for c in chunk)
                submit_next()
                continue
            err = (f"KilledWorker: the worker process died each time it computed this item (out of memory, or a "
                   f"crash in native code): {exc}")
            results = [{"item": chunk[0][0], "files": {}, "info": {}, "time": 0.0, "error": err}]
        except Exception as exc:  # noqa: BLE001 - a lost worker fails its chunk, not the batch
            if _lost(exc) and attempt < _MAX_ATTEMPTS:
                reruns += 1
                retry.append((chunk, attempt + 1))
                submit_next()
                continue
            err = f"{type(exc).__name__}: {exc}"
            results = [{"item": i, "files": {}, "info": {}, "time": 0.0, "error": err} for i, *_ in chunk]
        by_item = {c[0]: c for c in chunk}
        for r in results:
            sizer.observe(r["time"])
            meta = by_item[r["item"]][4]
            record(r["item"], meta, r["files"], r["info"], r["time"], r["error"])
        submit_next()
        sync()  # one fsync per finished task, after the next one is on its way
    return reruns
