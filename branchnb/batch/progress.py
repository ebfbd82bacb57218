"""Progress reporting of a batch: tqdm on the command line, a widget in a notebook, or a callback.

Every reporter has ``note(text)`` (what the run is doing, before and
around the items: starting the cluster, preparing the inputs, unreadable
manifest lines), ``start()`` (computing begins), ``skip(n)`` (``n`` items
were already complete), ``advance(n, failed)`` (``n`` more items finished,
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
    def note(self, text: str) -> None:
        pass

    def start(self) -> None:
        pass

    def skip(self, n: int) -> None:
        pass

    def advance(self, n: int, failed: int = 0) -> None:
        pass

    def close(self, summary=None) -> None:
        pass


class _Tqdm(_Silent):
    """Status lines on stderr from the first moment, then one tqdm bar (made once, when it has something to show)."""

    def __init__(self, total: int, initial: int, description: str):
        self.total, self.initial, self.description = total, initial, description
        self.failed = 0
        self.bar = None

    def _bar(self):
        if self.bar is None:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=self.total, initial=self.initial, desc=self.description, unit="item",
                            dynamic_ncols=True, file=sys.stderr)
        return self.bar

    def note(self, text: str) -> None:
        if self.bar is None:
            print(f"branchnb batch: {text}", file=sys.stderr, flush=True)
        else:
            self.bar.write(f"branchnb batch: {text}", file=sys.stderr)

    def start(self) -> None:
        self._bar()

    def skip(self, n: int) -> None:
        self.initial += n
        if self.bar is not None:
            self.bar.update(n)

    def advance(self, n: int, failed: int = 0) -> None:
        bar = self._bar()
        self.failed += failed
        if self.failed:
            bar.set_postfix(failed=self.failed, refresh=False)
        bar.update(n)

    def close(self, summary=None) -> None:
        if self.bar is not None:
            self.bar.close()


class _Callback(_Silent):
    """``fn(done, total)`` after every computed item (done counts resumed items too)."""

    def __init__(self, fn, total: int, initial: int):
        self.fn, self.total, self.done = fn, total, initial

    def skip(self, n: int) -> None:
        self.done += n

    def advance(self, n: int, failed: int = 0) -> None:
        self.done += n
        self.fn(self.done, self.total)


class _Widget(_Silent):
    """The notebook bar (:class:`branchnb.widgets.batch_progress.BatchProgress`), shown once computing starts."""

    def __init__(self, total: int, initial: int, description: str):
        self.args = [total, initial, description]
        self.bar = None

    def _bar(self):
        if self.bar is None:
            from ..widgets.batch_progress import BatchProgress

            self.bar = BatchProgress(*self.args)
        return self.bar

    def note(self, text: str) -> None:
        print(text, flush=True)

    def start(self) -> None:
        self._bar()

    def skip(self, n: int) -> None:
        if self.bar is None:
            self.args[1] += n
        else:
            self.bar.advance(n)

    def advance(self, n: int, failed: int = 0) -> None:
        self._bar().advance(n, failed)

    def close(self, summary=None) -> None:
        self._bar().close(summary)


def make_progress(kind, total: int, initial: int = 0, description: str = ""):
    """A progress reporter.

    Parameters
    ----------
    kind : {"auto", "tqdm", "widget", None} or callable
        ``"auto"``: an ipywidgets bar inside a notebook, tqdm elsewhere;
        a callable is called as ``kind(done, total)``; None is silent.
    total, initial : int
        Items in the batch, and those already complete (resumed).
    description : str
        Label in front of the bar (tqdm's ``desc``, the widget's title);
        ``""`` (default): none. A callable ``kind`` does not get it.

    Returns
    -------
    object
        A reporter with ``note(text)``, ``start()``, ``skip(n)``,
        ``advance(n, failed=0)`` and ``close(summary=None)``.
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
        return _Widget(total, initial, description)
    raise ValueError(f"progress must be 'auto', 'tqdm', 'widget', None or a callable, got {kind!r}")
