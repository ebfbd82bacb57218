"""Independent jobs (one per exemplar, per tile, ...) run in threads of one process.

NumPy's large array loops, OpenCV and the project's ``numba`` kernels
(compiled with ``nogil=True``) release the GIL, so jobs made of such calls
overlap on several cores without the copies and start-up of processes.
Results come back in the order of the inputs and do not depend on the
number of threads (a job must not share mutable state or a random
generator with another).
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable, Iterable
from concurrent.futures import ThreadPoolExecutor

import numpy as np

__all__ = ["thread_count", "thread_map"]

#: Environment variable capping the threads (``1``: run every job in the caller's thread).
THREADS_ENV = "BRANCHNB_THREADS"


def thread_count(jobs: int) -> int:
    """How many threads ``jobs`` independent jobs get: the usable cores, at most ``jobs``.

    Parameters
    ----------
    jobs : int
        Number of jobs.

    Returns
    -------
    int
        At least 1; capped by the environment variable ``BRANCHNB_THREADS`` when set.

    Examples
    --------
    >>> thread_count(1)
    1
    """
    if isinstance(jobs, bool) or not isinstance(jobs, (int, np.integer)):
        raise TypeError(f"jobs must be an int, got {type(jobs).__name__}")
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        cores = os.cpu_count() or 1
    cap = os.environ.get(THREADS_ENV, "").strip()
    if cap:
        try:
            cores = min(cores, max(1, int(cap)))
        except ValueError:
            raise ValueError(f"{THREADS_ENV} must be a positive int, got {cap!r}") from None
    return int(max(1, min(cores, int(jobs))))


def thread_map(fn: Callable, items: Iterable, *, threads: int | None = None) -> list:
    """``[fn(x) for x in items]``, the calls spread over threads.

    Parameters
    ----------
    fn : callable
        Called once per item; must not share mutable state with the other calls.
    items : iterable
        The jobs' inputs.
    threads : int, optional
        Most threads (default :func:`thread_count` of the number of items);
        1 runs in the caller's thread.

    Returns
    -------
    list
        The results in the order of ``items``. The first job's exception
        (in input order) is raised after every started job finished.

    Examples
    --------
    >>> thread_map(lambda x: x * x, range(5))
    [0, 1, 4, 9, 16]
    """
    if not callable(fn):
        raise TypeError(f"fn must be callable, got {type(fn).__name__}")
    items = list(items)
    if threads is None:
        threads = thread_count(len(items))
    elif isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1:
        raise ValueError(f"threads must be a positive int, got {threads!r}")
    if threads == 1 or len(items) <= 1:
        return [fn(x) for x in items]
    with _blas_in_turn(), ThreadPoolExecutor(max_workers=int(threads)) as pool:
        futures = [pool.submit(fn, x) for x in items]
    return [f.result() for f in futures]


def _blas_in_turn():
    """OpenBLAS on one thread while the jobs run (threadpoolctl, which scikit-learn brings).

    Our threads already fill the cores; OpenBLAS's own workers, called from
    two of them at once, spin-wait for each other: 8 leaves of 256 px took
    8.3 s of CPU in two threads against 6.2-6.5 s in one, and 6.0 s with
    OpenBLAS on one thread (same load, ~25). The limit is process-wide
    while it lasts (the library's setting, restored after).
    """
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - scikit-learn depends on it
        return contextlib.nullcontext()
    return threadpool_limits(1, user_api="blas")

