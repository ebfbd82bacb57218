"""What keeps a batch run safe: Ctrl-C handling and one run per output folder."""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

__all__ = ["Interrupt", "OutdirLock", "OutdirBusyError", "LOCK_NAME"]

LOCK_NAME = ".branchnb-batch.lock"


class Interrupt:
    """SIGINT handling of a run.

    Ctrl-C raises KeyboardInterrupt at once during the start-up (starting
    the cluster, preparing the inputs), but not while an item is being
    recorded (``critical``) nor while the run waits for results
    (``deferred``: the loop polls :meth:`check`, so no KeyboardInterrupt
    lands inside Dask's own code), and never once shutdown began
    (``closing``: later Ctrl-Cs are only noted), so a second Ctrl-C cannot
    tear the cluster's shutdown into a traceback.
    """

    def __init__(self):
        self.requested = False
        self.critical = False
        self.deferred = False
        self.closing = False
        self._old = None

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            self._old = signal.signal(signal.SIGINT, self._handler)
        return self

    def __exit__(self, *exc):
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)
        return False

    def _handler(self, signum, frame):
        first = not self.requested
        self.requested = True
        if first and not (self.critical or self.deferred or self.closing):
            raise KeyboardInterrupt

    def check(self):
        if self.requested and not self.closing:
            raise KeyboardInterrupt


class OutdirBusyError(ValueError):
    """Another run is writing to the same output folder."""


class OutdirLock:
    """An exclusive lock on an output folder (``OUTDIR/.branchnb-batch.lock``, ``fcntl.flock``).

    The lock belongs to the open file, so the operating system releases it
    when the process ends, even by SIGKILL: a stale lock file never blocks
    a later run. Where ``fcntl`` is missing (Windows) no lock is taken.
    """

    def __init__(self, outdir, *, wait: float = 0.0):
        self.path = Path(outdir) / LOCK_NAME
        self.wait = float(wait)
        self._f = None

    def __enter__(self):
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX
            return self
        f = open(self.path, "a+", encoding="utf-8")  # noqa: SIM115 - held for the whole run
        deadline = time.monotonic() + self.wait
        while True:
            try:
                fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except OSError:
                if time.monotonic() >= deadline:
                    f.seek(0)
                    holder = f.read(200).strip() or "another process"
                    f.close()
                    raise OutdirBusyError(
                        f"{self.path.parent} is in use by another branchnb batch ({holder}); wait for it to "
                        "finish (it records every item it makes, so running again afterwards only adds what "
                        "is missing) or choose another output folder") from None
                time.sleep(0.2)
        f.seek(0)
        f.truncate()
        f.write(f"process {os.getpid()} since {time.strftime('%Y-%m-%d %H:%M:%S')}")
        f.flush()
        self._f = f
        return self

    def __exit__(self, *exc):
        if self._f is not None:
            self._f.close()  # closing the file releases the lock
            self._f = None
        return False
