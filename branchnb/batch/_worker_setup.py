"""Dask preload of the local cluster's workers: Ctrl-C in a terminal is the client's to handle.

A terminal sends SIGINT to every process of its foreground group, workers
included; they would die mid-item with a KeyboardInterrupt traceback each,
while the client already stops the batch cleanly and closes the cluster.
"""

from __future__ import annotations

import signal


def dask_setup(worker=None) -> None:
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the main thread of the worker process: leave it
        pass
