"""How apps report problems and long work: a status line, an error area, a progress bar.

:class:`StatusLine` is the one line under an app's toolbar (see
:class:`~branchnb.widgets.shell.AppShell`): what the last action did and
how long it took, a spinner and "computing ..." while a callback runs,
and the last error with a "details" disclosure holding the traceback.
An error stays visible until the user's next *successful* action, so
that a mouse move or a redraw cannot wipe it before it was read.

:class:`ErrorArea` is the same error display without the busy state, for
widgets used on their own.
"""

from __future__ import annotations

import functools
import html
import threading
import time
import traceback
from contextlib import contextmanager

import ipywidgets as widgets

__all__ = ["Cancelled", "ErrorArea", "ProgressBar", "StatusLine"]


class Cancelled(Exception):
    """Raised inside long work (by its progress callback) when the user pressed "cancel".

    Parameters
    ----------
    message : str
        What the status line shows.

    Raises
    ------
    TypeError
        If ``message`` is not a str.

    Examples
    --------
    >>> str(Cancelled("synthesis cancelled"))
    'synthesis cancelled'
    """

    def __init__(self, message: str = "cancelled"):
        if not isinstance(message, str):
            raise TypeError(f"message must be a str, got {type(message).__name__}")
        super().__init__(message)


_SPINNER = (
    "<style>@keyframes bnb-spin{to{transform:rotate(360deg)}}"
    ".bnb-spin{display:inline-block;width:11px;height:11px;border:2px solid #90caf9;"
    "border-top-color:#1565c0;border-radius:50%;animation:bnb-spin .8s linear infinite;"
    "vertical-align:-2px;margin-right:6px}</style><span class='bnb-spin'></span>"
)


def _message(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}"


def _traceback(exc: BaseException) -> str:
    return "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))


class ErrorArea(widgets.HTML):
    """Shows the last exception of a guarded callback; hidden while there is none.

    Wrap every callback a widget registers with :meth:`guard`: an exception
    (bad input, a failed computation) is shown here with its message and a
    collapsible traceback, and the widget keeps working. The error stays
    until a guarded *action* succeeds; passive callbacks (mouse moves,
    redraws: ``guard(fn, action=False)``) never clear it.

    Parameters
    ----------
    **kwargs
        Passed to :class:`ipywidgets.HTML` (e.g. ``layout``).

    Examples
    --------
    >>> errors = ErrorArea()
    >>> @errors.guard
    ... def on_click(_):
    ...     raise ValueError("k must be >= 1")
    >>> on_click(None)
    >>> errors.last_error
    'ValueError: k must be >= 1'
    >>> errors.guard(lambda: None, action=False)(); errors.last_error is None
    False
    >>> errors.guard(lambda: None)(); errors.last_error is None
    True
    """

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.last_error: str | None = None
        self.last_traceback: str | None = None
        self._depth = 0
        self._n_shown = 0  # errors shown so far: an action clears only if it showed none
        self._lock = threading.RLock()
        self.layout.display = "none"

    def show(self, exc: BaseException) -> None:
        """Display an exception.

        Parameters
        ----------
        exc : BaseException
            Shown as ``"Type: message"`` (in ``last_error``) with its
            traceback under a "details" disclosure.
        """
        self._n_shown += 1
        self.last_error = _message(exc)
        self.last_traceback = _traceback(exc)
        self.value = (
            "<div style='border-left:4px solid #c62828;background:#fdecea;padding:4px 8px;"
            "font-family:monospace;white-space:pre-wrap'>"
            f"<b>{html.escape(self.last_error)}</b>"
            f"<details><summary>details</summary>{html.escape(self.last_traceback)}</details></div>"
        )
        self.layout.display = None

    def clear(self) -> None:
        """Hide the error."""
        self.last_error = self.last_traceback = None
        self.value = ""
        self.layout.display = "none"

    def guard(self, fn=None, *, action: bool = True):
        """Wrap ``fn`` so that exceptions are shown here instead of propagating.

        ``action=True`` (a button, a slider, a click that edits): when the
        outermost guarded call succeeds, the previous error is cleared.
        ``action=False`` (mouse moves, hover, redraws) leaves it alone.
        Usable as ``@guard`` or ``guard(fn, action=False)``.

        Parameters
        ----------
        fn : callable, optional
            The callback; None returns a decorator taking it.
        action : bool
            Whether a success of ``fn`` clears the shown error.

        Returns
        -------
        callable
            A wrapper with ``fn``'s signature that returns ``fn``'s result, or
            None after showing an exception.
        """
        if fn is None:
            return functools.partial(self.guard, action=action)

        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            with self.catch(action=action):
                return fn(*args, **kwargs)
            return None

        return wrapper

    @contextmanager
    def catch(self, *, action: bool = True):
        """Context manager form of :meth:`guard`.

        Parameters
        ----------
        action : bool
            Whether a block that succeeds (nothing inside showed an error)
            clears the shown error.

        Yields
        ------
        None
            The block runs inside; an exception it raises is shown, not
            propagated.
        """
        with self._lock:
            self._depth += 1
            outermost = self._depth == 1
            shown_before = self._n_shown
        try:
            yield
        except Exception as exc:  # noqa: BLE001 - shown to the user
            self.show(exc)
        finally:
            with self._lock:
                self._depth -= 1
            # Cleared only by a whole action that succeeded (nothing inside it failed either).
            if outermost and action and self._n_shown == shown_before and self.last_error is not None:
                self._succeeded()

    def _succeeded(self) -> None:
        self.clear()


class StatusLine(ErrorArea):
    """One line: the last action's result and time, a spinner while busy, or the last error.

    Besides the :class:`ErrorArea` protocol (``guard``, ``catch``,
    ``show``, ``last_error``) it has a busy state: inside
    ``with status.busy("synthesis"):`` it shows a spinner and "computing
    synthesis ...", disables the registered run buttons, and afterwards
    prints "synthesis: 1.23 s" (or the error). Register buttons with
    :meth:`add_run_buttons`; give the cancel button with ``cancel``.

    Parameters
    ----------
    cancel : ipywidgets.Button, optional
        The app's cancel button: shown and enabled only while cancellable
        work runs (see :meth:`set_busy`).
    **kwargs
        Passed to :class:`ipywidgets.HTML`.

    Examples
    --------
    >>> status = StatusLine()
    >>> with status.busy("fit"):
    ...     pass
    >>> status.text.startswith("fit: ")
    True
    >>> with status.busy("fit"):
    ...     raise ValueError("draw a branch first")
    >>> status.last_error, status.busy_now
    ('ValueError: draw a branch first', False)
    """

    def __init__(self, *, cancel: widgets.Button | None = None, **kwargs):
        super().__init__(**kwargs)
        self.layout.min_height = "24px"
        self.layout.width = "100%"
        self.text = ""
        self.busy_now = False
        self.last_seconds: float | None = None
        self._run_buttons: list[widgets.Button] = []
        self.cancel_button = cancel
        self._render("ready", "")

    # -- display --------------------------------------------------------------
    def _render(self, kind: str, text: str, details: str = "") -> None:
        colours = {"ready": ("#546e7a", "#eceff1"), "ok": ("#2e7d32", "#e8f5e9"),
                   "busy": ("#1565c0", "#e3f2fd"), "error": ("#c62828", "#fdecea")}
        fg, bg = colours[kind]
        body = _SPINNER if kind == "busy" else ""
        body += f"<b>{html.escape(text)}</b>" if kind == "error" else html.escape(text)
        if details:
            body += (f"<details style='display:inline'><summary style='display:inline;cursor:pointer;"
                     f"margin-left:10px;color:{fg}'>details</summary><pre style='white-space:pre-wrap;"
                     f"max-height:260px;overflow:auto;font-size:11px'>{html.escape(details)}</pre></details>")
        self.value = (f"<div class='bnb-status bnb-status-{kind}' style='border-left:4px solid {fg};"
                      f"background:{bg};color:#212121;padding:3px 8px;font-size:13px;"
                      f"line-height:18px'>{body}</div>")
        # Nothing to say yet (a fresh app): no empty strip.
        self.layout.display = "none" if kind == "ready" and not text else None

    def info(self, text: str) -> None:
        """Show a message (keeps a visible error: it is replaced by the next success only).

        Parameters
        ----------
        text : str
            The message (converted with ``str``); kept in ``text``.
        """
        self.text = str(text)
        if self.last_error is None and not self.busy_now:
            self._render("ok", self.text)

    def show(self, exc: BaseException) -> None:
        """Show an exception on the line, its traceback under "details".

        Parameters
        ----------
        exc : BaseException
            The error; kept as ``last_error`` until the next success.
        """
        self._n_shown += 1
        self.last_error = _message(exc)
        self.last_traceback = _traceback(exc)
        self._render("error", self.last_error, self.last_traceback)
        self.layout.display = None

    def clear(self) -> None:
        """Forget the error and show the last message again (or nothing)."""
        self.last_error = self.last_traceback = None
        self._render("ok" if self.text else "ready", self.text)

    # -- busy state -----------------------------------------------------------
    def add_run_buttons(self, *buttons: widgets.Button) -> None:
        """Buttons disabled while a callback runs.

        Parameters
        ----------
        *buttons : ipywidgets.Button
            Added to those already registered; re-enabled by :meth:`set_idle`.
        """
        self._run_buttons.extend(buttons)

    def set_busy(self, name: str, *, cancellable: bool = False) -> None:
        """Spinner, "computing <name> ...", run buttons disabled, cancel offered if ``cancellable``.

        Parameters
        ----------
        name : str
            What is computing (e.g. ``"synthesis"``).
        cancellable : bool
            Show and enable the cancel button given to the constructor.
        """
        self.busy_now = True
        self._render("busy", f"computing {name} ...")
        for b in self._run_buttons:
            b.disabled = True
        if self.cancel_button is not None and cancellable:
            self.cancel_button.disabled = False
            self.cancel_button.layout.visibility = "visible"
            self.cancel_button.layout.display = None

    def progress(self, fraction: float, text: str = "") -> None:
        """Show progress of the running work (``progress(fraction, text)`` of the core).

        Parameters
        ----------
        fraction : float
            Done part of the work, clipped to [0, 1]; shown as a percentage.
        text : str
            What is being done; "computing ..." if empty.
        """
        pct = f"{100 * min(max(float(fraction), 0.0), 1.0):.0f} %"
        self._render("busy", f"{text} {pct}".strip() if text else f"computing ... {pct}")

    def set_idle(self) -> None:
        """Leave the busy state: run buttons enabled, the cancel button hidden."""
        self.busy_now = False
        for b in self._run_buttons:
            b.disabled = False
        if self.cancel_button is not None:
            self.cancel_button.disabled = True
            self.cancel_button.layout.visibility = "hidden"
            self.cancel_button.layout.display = "none"  # no empty space where it was

    @contextmanager
    def busy(self, name: str, *, message=None):
        """Run the block in the busy state; afterwards show its time or its error.

        Parameters
        ----------
        name : str
            What runs; the line says ``"<name>: 1.23 s"`` afterwards, or
            ``"<name> failed after ..."`` with the error.
        message : str or callable, optional
            What the line adds on success besides the time; a callable is
            called after the block (so it can report the result).

        Yields
        ------
        None
            The block runs inside; an exception it raises is shown, not
            propagated.
        """
        self.set_busy(name)
        t0 = time.perf_counter()
        shown_before = self._n_shown
        with self.catch():
            try:
                yield
            finally:
                self.last_seconds = time.perf_counter() - t0
                self.set_idle()
            msg = message() if callable(message) else message
            self.text = f"{name}: {self.last_seconds:.2f} s" + (f" | {msg}" if msg else "")
        if self._n_shown == shown_before:
            # A finished computation is a successful action, even inside a mouse callback.
            self.last_error = self.last_traceback = None
            self._render("ok", self.text)
        else:
            self._render("error", f"{name} failed after {self.last_seconds:.2f} s: {self.last_error}",
                         self.last_traceback or "")


class ProgressBar(widgets.HBox):
    """A progress bar with a message, for long work such as image synthesis.

    Pass :meth:`update` as the ``progress`` callback of a core function
    (``progress(fraction, text)``), or iterate with :meth:`track`. Call
    :meth:`fail` when the work raised: the bar turns red and says so.

    Parameters
    ----------
    description : str
        Label left of the bar.
    **kwargs
        Passed to :class:`ipywidgets.HBox`.

    Examples
    --------
    >>> bar = ProgressBar("synthesis")
    >>> bar.update(0.25, "fragment 3"); bar.bar.value, bar.text.value
    (0.25, 'fragment 3')
    """

    def __init__(self, description: str = "", **kwargs):
        self.bar = widgets.FloatProgress(value=0.0, min=0.0, max=1.0, description=description)
        self.text = widgets.Label("")
        super().__init__([self.bar, self.text], **kwargs)
        self.layout.display = "none"

    def update(self, fraction: float, text: str = "") -> None:
        """Set progress to ``fraction`` in [0, 1] with an optional message.

        Parameters
        ----------
        fraction : float
            Done part of the work (clipped to [0, 1]).
        text : str
            Message right of the bar (replaces the previous one).
        """
        self.layout.display = None
        self.bar.bar_style = ""
        self.bar.value = min(max(float(fraction), 0.0), 1.0)
        self.text.value = str(text)

    def done(self, text: str = "done") -> None:
        """Fill the bar and turn it green.

        Parameters
        ----------
        text : str
            Message right of the bar.
        """
        self.update(1.0, text)
        self.bar.bar_style = "success"

    def fail(self, text: str = "failed") -> None:
        """Show that the work did not finish.

        Parameters
        ----------
        text : str
            Message right of the bar (e.g. the error); the bar turns red and
            keeps its value.
        """
        self.layout.display = None
        self.bar.bar_style = "danger"
        self.text.value = str(text)

    def reset(self) -> None:
        """Empty the bar, clear its message and hide it."""
        self.bar.value = 0.0
        self.bar.bar_style = ""
        self.text.value = ""
        self.layout.display = "none"

    def track(self, iterable, total: int | None = None, text: str = ""):
        """Yield from ``iterable`` while advancing the bar.

        Parameters
        ----------
        iterable : iterable
            The items to go through.
        total : int, optional
            Number of items, for the fraction; ``len(iterable)`` by default.
        text : str
            Prefix of the ``"i/total"`` message.

        Yields
        ------
        object
            The items of ``iterable``; the bar is filled (:meth:`done`) after
            the last.
        """
        if total is None:
            total = len(iterable)
        for i, item in enumerate(iterable):
            self.update(i / max(total, 1), f"{text} {i}/{total}".strip())
            yield item
        self.done()
