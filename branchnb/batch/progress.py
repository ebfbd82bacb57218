"""Progress reporting of a batch: tqdm on the command line, a widget in a notebook, or a callback.

Every reporter has ``advance(n, failed)`` (``n`` more items finished,
``failed`` of them failed) and ``close(summary)``.
"""

from __future__ import annotations

import sys

__all__ = ["make_progress", "in_notebook"]


def in_notebook() -> bool:
    """Whether we run inside a Jupyter kernel (so a widget can be displayed)."""
    ipython = sys.modules.get("IPython")
    if ipython is None:
        return False
    shell = ipython.get_ipython()
    return shell is not None and type(shell).__name__ == "ZMQInteractiveShell"


class _Silent:
    def advance(self, n: int, failed: int = 0) -> None:
        pass

    def close(self, summary=None) -> None:
        pass


class _Tqdm:
    def __init__(self, total: int, initial: int, description: str):
        from tqdm.auto import tqdm

        self.failed = 0
        self.bar = tqdm(total=total, initial=initial, desc=description, unit="item", dynamic_ncols=True,
                        file=sys.stderr)

    def advance(self, n: int, failed: int = 0) -> None:
        self.failed += failed
        if self.failed:
            self.bar.set_postfix(failed=self.failed, refresh=False)
        self.bar.update(n)

    def close(self, summary=None) -> None:
        self.bar.close()


class _Callback:
    """``fn(done, total)`` after every finished item (done counts resumed items too)."""

    def __init__(self, fn, total: int, initial: int):
        self.fn, self.total, self.done = fn, total, initial

    def advance(self, n: int, failed: int = 0) -> None:
        self.done += n
        self.fn(self.done, self.total)

    def close(self, summary=None) -> None:
        pass


def make_progress(kind, total: int, initial: int = 0, description: str = ""):
    """A progress reporter.

    Parameters
    ----------
    kind : {"auto", "tqdm", "widget", None} or callable
        ``"auto"``: an ipywidgets bar inside a notebook, tqdm elsewhere;
        a callable is called as ``kind(done, total)``; None is silent.
    total, initial : int
        Items in the batch, and those already complete (resumed).
    """
    if kind is None or kind is False:
        return _Silent()
    if callable(kind):
        return _Callback(kind, total, initial)
    if kind == "auto":
        kind = "widget" if in_notebook() else "tqdm"
    if kind == "tqdm":
        return _Tqdm(total, initial, description)
    if kind == "widget":
        from ..widgets.batch_progress import BatchProgress

        return BatchProgress(total, initial, description)
    raise ValueError(f"progress must be 'auto', 'tqdm', 'widget', None or a callable, got {kind!r}")
