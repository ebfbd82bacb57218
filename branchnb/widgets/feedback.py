"""Error area and progress bar: how apps report problems and long work."""

from __future__ import annotations

import functools
import html
import traceback
from contextlib import contextmanager

import ipywidgets as widgets

__all__ = ["ErrorArea", "ProgressBar"]


class ErrorArea(widgets.HTML):
    """Shows the last exception of a guarded callback; hidden while there is none.

    Wrap every callback an app registers with :meth:`guard`: an exception
    (bad input, a failed computation) is shown here with its message and a
    collapsible traceback, and the widget keeps working.

    Examples
    --------
    >>> errors = ErrorArea()
    >>> @errors.guard
    ... def on_click(_):
    ...     raise ValueError("k must be >= 1")
    >>> on_click(None)
    >>> errors.last_error
    'ValueError: k must be >= 1'
    """

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.last_error: str | None = None
        self._depth = 0
        self.layout.display = "none"

    def show(self, exc: BaseException) -> None:
        """Display an exception."""
        self.last_error = f"{type(exc).__name__}: {exc}"
        tb = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
        self.value = (
            "<div style='border-left:4px solid #c62828;background:#fdecea;padding:4px 8px;"
            "font-family:monospace;white-space:pre-wrap'>"
            f"<b>{html.escape(self.last_error)}</b>"
            f"<details><summary>traceback</summary>{html.escape(tb)}</details></div>"
        )
        self.layout.display = None

    def clear(self) -> None:
        """Hide the error area."""
        self.last_error = None
        self.value = ""
        self.layout.display = "none"

    def guard(self, fn):
        """Wrap ``fn`` so that exceptions are shown here instead of propagating.

        The outermost guarded call clears the previous error when it starts,
        so an error stays visible until the user's next action; guarded
        callbacks nested inside it (e.g. model observers) do not clear it.
        """

        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            with self.catch():
                return fn(*args, **kwargs)
            return None

        return wrapper

    @contextmanager
    def catch(self):
        """Context manager form of :meth:`guard`."""
        if self._depth == 0 and self.last_error is not None:
            self.clear()
        self._depth += 1
        try:
            yield
        except Exception as exc:  # noqa: BLE001 - shown to the user
            self.show(exc)
        finally:
            self._depth -= 1


class ProgressBar(widgets.HBox):
    """A progress bar with a message, for long work such as image synthesis.

    Pass :meth:`update` as the ``progress`` callback of a core function
    (``progress(fraction, text)``), or iterate with :meth:`track`.
    """

    def __init__(self, description: str = "", **kwargs):
        self.bar = widgets.FloatProgress(value=0.0, min=0.0, max=1.0, description=description)
        self.text = widgets.Label("")
        super().__init__([self.bar, self.text], **kwargs)
        self.layout.display = "none"

    def update(self, fraction: float, text: str = "") -> None:
        """Set progress to ``fraction`` in [0, 1] with an optional message."""
        self.layout.display = None
        self.bar.value = min(max(float(fraction), 0.0), 1.0)
        self.text.value = str(text)

    def done(self, text: str = "done") -> None:
        self.update(1.0, text)

    def reset(self) -> None:
        self.bar.value = 0.0
        self.text.value = ""
        self.layout.display = "none"

    def track(self, iterable, total: int | None = None, text: str = ""):
        """Yield from ``iterable`` while advancing the bar."""
        if total is None:
            total = len(iterable)
        for i, item in enumerate(iterable):
            self.update(i / max(total, 1), f"{text} {i}/{total}".strip())
            yield item
        self.done()
