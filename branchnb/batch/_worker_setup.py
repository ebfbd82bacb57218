"""Dask preload of the local cluster's workers: one thread each, and Ctrl-C is the client's to handle.

A batch is parallel across items, one worker process per core; OpenCV's
own thread pool (one thread per core in every worker, which Dask's
``OMP_NUM_THREADS=1`` does not reach) would make the workers fight over
the cores, and a 1-worker run look better than it is.

A terminal sends SIGINT to every process of its foreground group, workers
included; they would die mid-item with a KeyboardInterrupt traceback each,
while the client already stops the batch cleanly and closes the cluster.
"""

from __future__ import annotations

import signal


def dask_setup(worker=None) -> None:
    import cv2

    cv2.setNumThreads(1)
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the main thread of the worker process: leave it
        pass
