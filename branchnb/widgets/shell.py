"""AppShell: the layout and behaviour every technique app shares.

::

    +--------------------------------------------------------------+
    | title   one-line help                                        |
    | [main action] [action] ... [open image] [save] [load annot.] |
    | status: "synthesize: 0.84 s | 120 branches"  [cancel]        |
    +----------------------+----------------------+----------------+
    | canvas(es)           | result views,        | parameters,    |
    |                      | histograms (below    | by paper       |
    |                      | the canvases when    | section        |
    |                      | there is no room)    |                |
    +----------------------+----------------------+----------------+

The status line appears with the first thing it has to say; "cancel"
shows beside it only while cancellable work runs. Canvases keep their
size (backing store = CSS size x the browser's pixel ratio, so they stay
sharp); the results wrap below them on a narrow page.

An app builds its widgets, hands them to the shell and registers its
actions; the shell gives every action the same busy state (spinner,
"computing ...", run buttons disabled, then the time it took), one place
for errors (they stay until the next successful action; "details" shows
the traceback), and "cancel" for long work that reports progress.

Long work (``background=True``) runs in a thread when the shell lives in
a kernel, so the kernel keeps receiving clicks (the cancel button) and
slider moves meanwhile; outside a kernel (scripts, tests) it runs at
once. Cancellation is cooperative: the work must call
:meth:`AppShell.progress` between its steps (pass it as the core
function's ``progress`` callback), which raises :class:`Cancelled` once
"cancel" was pressed.

Example: a minimal app::

    class BlurApp(widgets.VBox):
        def __init__(self, image):
            self.shell = AppShell("Blur", help="drag sigma; 'full render' for the full size")
            self.canvas = AnnotationCanvas(image, errors=self.shell.status)
            self.view = ImageView()
            self.panel = ParamPanel(BlurParams, errors=self.shell.status,
                                    sections=[("smoothing (Sec. 3)", ["sigma"])],
                                    labels={"sigma": ("blur radius", "σ")})
            self.panel.on_change(self.shell.guard(lambda p: self.preview()))
            self.shell.add_action("full render", self.render, primary=True,
                                  background=True)
            self.shell.set_body(main=[self.canvas], result=[self.view],
                                sidebar=[self.panel])
            super().__init__([self.shell])

        def preview(self):      # fast: a reduced-resolution image, under 200 ms
            with self.shell.busy("preview"):
                self.view.update([blur(small(self.canvas.image), self.panel.values)])

        def render(self):       # slow: full size; stops between rows on "cancel"
            out = blur(self.image, self.panel.values, progress=self.shell.progress)
            self.view.update([out])
            return f"{out.shape[1]} x {out.shape[0]} px"   # shown in the status line

Examples
--------
>>> shell = AppShell("demo", help="press run")
>>> b = shell.add_action("run", lambda: "42 things", primary=True)
>>> shell.click("run")
>>> shell.status.text.split(" | ")[1]
'42 things'
>>> shell.add_action("fail", lambda: 1 / 0) and None
>>> shell.click("fail"); shell.status.last_error
'ZeroDivisionError: division by zero'
>>> shell.click("run"); shell.status.last_error is None   # the next success clears it
True
"""

from __future__ import annotations

import asyncio
import html
import threading
import time
from collections.abc import Callable, Sequence

import ipywidgets as widgets

from ._assets import KitStyle
from .feedback import Cancelled, StatusLine
from .files import FileBar

__all__ = ["AppShell", "Cancelled"]

#: Width (px) of the parameter sidebar; rows of :class:`ParamPanel` fit in it.
SIDEBAR_WIDTH = 336


class _Job:
    def __init__(self, name: str):
        self.name = name
        self.cancelled = threading.Event()
        self.thread: threading.Thread | None = None


class AppShell(widgets.VBox):
    """Toolbar, status line, canvases | results | parameters, and a busy state.

    Parameters
    ----------
    title : str
        Shown bold at the top.
    help : str
        One line of how-to next to the title (HTML allowed).
    background : bool or None
        Run ``background=True`` actions in a thread: None (default) when
        inside a running event loop (a kernel), True always, False never.
    sidebar_width : int
        Width of the parameter column in pixels.

    Attributes
    ----------
    status : StatusLine
        The app's one status/error line; give it as ``errors=`` to the
        kit's widgets so their errors appear there too.
    buttons : dict
        Action name -> button.

    Examples
    --------
    >>> shell = AppShell("blur", help="move the slider")
    >>> _ = shell.add_action("run", lambda: "3 px", primary=True)
    >>> shell.click("run"); shell.status.text.endswith("| 3 px")
    True
    """

    def __init__(self, title: str = "", *, help: str = "", background: bool | None = None,
                 sidebar_width: int = SIDEBAR_WIDTH):
        if not isinstance(title, str) or not isinstance(help, str):
            raise TypeError(f"title and help must be strings, got {type(title).__name__} and "
                            f"{type(help).__name__}")
        if background not in (None, True, False):
            raise ValueError(f"background must be None, True or False, got {background!r}")
        if not isinstance(sidebar_width, int) or sidebar_width < 200:
            raise ValueError(f"sidebar_width must be an int >= 200, got {sidebar_width!r}")
        self.background = background
        self.cancel_button = widgets.Button(description="cancel", icon="stop", disabled=True,
                                            button_style="warning", tooltip="stop the running work "
                                            "at its next step", layout=widgets.Layout(
                                                width="auto", visibility="hidden", display="none",
                                                flex="0 0 auto"))
        self.cancel_button.on_click(lambda _: self.cancel())
        self.status = StatusLine(cancel=self.cancel_button)
        self.buttons: dict[str, widgets.Button] = {}
        self._actions: dict[str, Callable[[], None]] = {}
        self._job: _Job | None = None
        self._lock = threading.Lock()
        self._live_pending: Callable | None = None
        self._live_job: _Job | None = None
        self._live_thread: threading.Thread | None = None
        self.header = widgets.HTML(
            f"<div style='display:flex;align-items:baseline;gap:12px;white-space:nowrap;"
            f"overflow:hidden;text-overflow:ellipsis'><b style='font-size:15px'>{html.escape(title)}"
            f"</b><span style='color:#555;font-size:12px;white-space:normal'>{help}</span></div>")
        self.toolbar = widgets.HBox(layout=widgets.Layout(flex_flow="row wrap", align_items="center"))
        self._tools = widgets.HBox(layout=widgets.Layout(flex_flow="row wrap", align_items="center"))
        self._file_tools = widgets.HBox(layout=widgets.Layout(flex_flow="row wrap", align_items="center",
                                                              display="none"))
        self.toolbar.children = [self._tools, self._file_tools]
        self.toolbar.add_class("bnb-toolbar")
        # The cancel button lives in the status row and shows only while cancellable work runs:
        # hidden, it takes no room (no empty toolbar row).
        self.status_row = widgets.HBox([self.status, self.cancel_button],
                                       layout=widgets.Layout(align_items="center", width="100%"))
        self.files: FileBar | None = None
        self._links = widgets.VBox()
        # Canvases keep their size (a squeezed canvas is blurry and its clicks land off); the results
        # sit beside them when there is room and wrap below them when not; the parameters stay on
        # the right.
        self.main = widgets.VBox(layout=widgets.Layout(flex="0 0 auto", max_width="100%"))
        self.result = widgets.VBox(layout=widgets.Layout(flex="1 1 auto", min_width="0", max_width="100%"))
        self.sidebar = widgets.VBox(layout=widgets.Layout(flex=f"0 0 {sidebar_width}px",
                                                          width=f"{sidebar_width}px"))
        self.work = widgets.HBox([self.main, self.result],
                                 layout=widgets.Layout(flex="1 1 0", min_width="0", flex_flow="row wrap",
                                                       align_items="flex-start"))
        self.body = widgets.HBox([self.work, self.sidebar],
                                 layout=widgets.Layout(align_items="flex-start", width="100%"))
        super().__init__([KitStyle(), self.header, self.toolbar, self.status_row, self._links, self.body],
                         layout=widgets.Layout(width="100%"))
        self.add_class("bnb-app")

    # -- building -----------------------------------------------------------------
    def set_body(self, *, main: Sequence[widgets.Widget] = (), result: Sequence[widgets.Widget] = (),
                 sidebar: Sequence[widgets.Widget] = ()) -> None:
        """Put the canvases (``main``), result views and parameter panels in their columns.

        Parameters
        ----------
        main : sequence of ipywidgets.Widget
            Left column: the canvases (kept at their size).
        result : sequence of ipywidgets.Widget
            Middle column: result views, histograms (wraps below the
            canvases on a narrow page).
        sidebar : sequence of ipywidgets.Widget
            Right column: parameter panels; hidden when empty.
        """
        self.main.children = list(main)
        self.result.children = list(result)
        self.sidebar.children = list(sidebar)
        self.sidebar.layout.display = None if sidebar else "none"

    def add_files(self, **hooks) -> FileBar:
        """Give the app "open image", "save" and "load annotations" (see :class:`FileBar`).

        Parameters
        ----------
        **hooks
            :class:`FileBar`'s keyword arguments (``open``, ``outputs``,
            ``annotations``, ``load``, ``name``, ``multiple``, ...) except
            ``errors``: errors and messages go to the status line.

        Returns
        -------
        FileBar
            Also kept as ``files``.

        Raises
        ------
        ValueError
            If the files were added already.
        """
        if self.files is not None:
            raise ValueError("add_files was called already")
        self.files = FileBar(errors=self.status, **hooks)
        self._file_tools.children = self.files.widgets
        self._file_tools.layout.display = None if self.files.widgets else "none"
        self._links.children = [self.files.links]
        return self.files

    def add_tool(self, *items: widgets.Widget) -> None:
        """Put non-action widgets (a seed box, a checkbox) into the toolbar.

        Parameters
        ----------
        *items : ipywidgets.Widget
            Appended after the existing buttons and tools.
        """
        self._tools.children = list(self._tools.children) + list(items)

    def add_action(self, name: str, fn: Callable[[], object], *, tooltip: str = "", icon: str = "",
                   primary: bool = False, background: bool = False, cancellable: bool = False,
                   label: str | None = None, run: bool = True) -> widgets.Button:
        """A toolbar button that runs ``fn()`` with the busy state.

        ``fn`` may return a string: the status line shows it after the
        time. ``background=True`` for long work (threaded in a kernel);
        ``cancellable=True`` when ``fn`` calls :meth:`progress` between its
        steps, so that "cancel" can stop it (the button is offered only then). ``run=False`` for quick
        buttons that are not disabled while something computes (e.g.
        "clear"). ``primary`` styles the app's main action.

        Parameters
        ----------
        name : str
            The action's name: its key in ``buttons``, the name shown in the
            status line, and the button's label unless ``label`` is given.
        fn : callable
            ``fn()``; may return a str for the status line.
        tooltip : str
            Hover text (``name`` if empty).
        icon : str
            Font Awesome icon name (none if empty).
        primary : bool
            Style as the app's main action.
        background : bool
            Run in a thread inside a kernel (long work).
        cancellable : bool
            ``fn`` calls :meth:`progress` between its steps, so "cancel" can
            stop it.
        label : str, optional
            Button text, if other than ``name``.
        run : bool
            Disable the button while any action computes.

        Returns
        -------
        ipywidgets.Button

        Raises
        ------
        TypeError
            If ``fn`` is not callable.
        ValueError
            If an action of that name exists.
        """
        if not callable(fn):
            raise TypeError(f"fn of action {name!r} must be callable")
        if name in self.buttons:
            raise ValueError(f"an action named {name!r} exists already")
        b = widgets.Button(description=label or name, tooltip=tooltip or name, icon=icon,
                           button_style="primary" if primary else "",
                           layout=widgets.Layout(width="auto"))
        def action():
            self.run(name, fn, background=background, cancellable=cancellable)

        b.on_click(lambda _b: action())
        self.buttons[name] = b
        self._actions[name] = action
        if run:
            self.status.add_run_buttons(b)
        self._tools.children = list(self._tools.children) + [b]
        return b

    def click(self, name: str) -> None:
        """Press an action's button from Python (what a user's click does).

        Parameters
        ----------
        name : str
            The action's name given to :meth:`add_action`.

        Raises
        ------
        ValueError
            If there is no such action.
        """
        if name not in self._actions:
            raise ValueError(f"no action named {name!r}; have {list(self._actions)}")
        self._actions[name]()

    # -- running ----------------------------------------------------------------------
    def guard(self, fn=None, *, action: bool = True):
        """Route a callback's errors to the status line (see :meth:`StatusLine.guard`).

        Parameters
        ----------
        fn : callable, optional
            The callback; None returns a decorator.
        action : bool
            Whether a success clears the shown error (False for mouse moves
            and redraws).

        Returns
        -------
        callable
        """
        return self.status.guard(fn, action=action)

    def busy(self, name: str, *, message=None):
        """``with shell.busy("preview"):`` - the busy state around a block (synchronous).

        Parameters
        ----------
        name : str
            What runs, shown as "computing <name> ..." and then with its time.
        message : str or callable, optional
            Added to the status line on success (see :meth:`StatusLine.busy`).

        Returns
        -------
        contextlib.AbstractContextManager
        """
        return self.status.busy(name, message=message)

    @property
    def running(self) -> bool:
        """Whether background work is running."""
        return self._job is not None

    def _use_thread(self) -> bool:
        if self.background is not None:
            return self.background
        try:
            asyncio.get_running_loop()
        except RuntimeError:
            return False
        return True

    def run(self, name: str, fn: Callable[[], object], *, background: bool = False,
            cancellable: bool = False) -> None:
        """Run ``fn`` in the busy state; its string result (if any) goes to the status line.

        While background work runs, another ``run`` shows an error instead
        of starting.

        Parameters
        ----------
        name : str
            What runs (status line text).
        fn : callable
            ``fn()``; errors are shown, not raised.
        background : bool
            Run in a thread when inside a kernel (see the ``background``
            argument of the shell); otherwise at once.
        cancellable : bool
            Offer "cancel" (``fn`` must call :meth:`progress`).
        """
        if self._job is not None:
            self.status.show(RuntimeError(f"{self._job.name} is still running: wait or press cancel"))
            return
        if not (background and self._use_thread()):
            result: list = []
            with self.status.busy(name, message=lambda: result[0] if result and
                                  isinstance(result[0], str) else None):
                result.append(fn())
            return
        job = _Job(name)
        self._job = job
        self.status.set_busy(name, cancellable=cancellable)

        def work():
            t0 = time.perf_counter()
            try:
                out = fn()
                dt = time.perf_counter() - t0
                self.status.last_seconds = dt
                self.status.text = f"{name}: {dt:.2f} s" + (f" | {out}" if isinstance(out, str) else "")
                self.status.clear()
            except Cancelled:
                self.status.text = f"{name} cancelled after {time.perf_counter() - t0:.1f} s"
                self.status.clear()
            except Exception as exc:  # noqa: BLE001 - shown to the user
                self.status.show(exc)
                self.status._render("error", f"{name} failed after {time.perf_counter() - t0:.2f} s: "
                                    f"{self.status.last_error}", self.status.last_traceback or "")
            finally:
                with self._lock:
                    self._job = None
                self.status.set_idle()

        job.thread = threading.Thread(target=work, name=f"branchnb-{name}", daemon=True)
        job.thread.start()

    def progress(self, fraction: float, text: str = "") -> None:
        """Progress callback for long work: shows it, raises :class:`Cancelled` after "cancel".

        Live updates (:meth:`live`) are cancelled the same way when a newer
        change arrives.

        Parameters
        ----------
        fraction : float
            Done part of the work in [0, 1].
        text : str
            What is being done.

        Raises
        ------
        Cancelled
            In the worker thread, after "cancel" (or a newer live request).
        """
        for job in (self._job, self._live_job):
            if job is not None and job.cancelled.is_set() and threading.current_thread() is job.thread:
                raise Cancelled(f"{job.name} cancelled")
        self.status.progress(fraction, text)

    # -- live updates (slider moves) ---------------------------------------------------
    def live(self, name: str, full: Callable[[], object], *, preview: Callable[[], object] | None = None,
             stale: Callable[[], None] | None = None) -> None:
        """A parameter changed: a fast ``preview()`` now, the ``full()`` result after it.

        ``preview`` runs at once (keep it under 200 ms: reduced resolution,
        cached stages); ``stale`` marks the shown result as out of date when
        there is no preview. ``full`` runs in the background inside a
        kernel, latest request wins: a newer change cancels the running one
        at its next :meth:`progress` and its result is dropped. Outside a
        kernel both run at once, in order.

        Parameters
        ----------
        name : str
            What is updated (status line text).
        full : callable
            ``full()`` computes the full result; may return a str for the
            status line.
        preview : callable, optional
            ``preview()``, run at once.
        stale : callable, optional
            ``stale()``, run at once when there is no preview.
        """
        if preview is not None:
            with self.status.busy(f"{name} preview"):
                preview()
        elif stale is not None:
            with self.status.catch(action=False):
                stale()
        if not self._use_thread():
            self.run(name, full)
            return
        with self._lock:
            self._live_pending = (name, full)
            if self._live_job is not None:
                self._live_job.cancelled.set()
            start = self._live_thread is None
            if start:
                self._live_thread = threading.Thread(target=self._live_worker, name="branchnb-live",
                                                     daemon=True)
        if start:
            self._live_thread.start()
        else:
            self.status.set_busy(name)

    def _live_worker(self) -> None:
        while True:
            with self._lock:
                if self._live_pending is None:
                    self._live_thread = None
                    self._live_job = None
                    break
                name, full = self._live_pending
                self._live_pending = None
                job = _Job(name)
                job.thread = threading.current_thread()
                self._live_job = job
            self.status.set_busy(name)
            t0 = time.perf_counter()
            try:
                out = full()
                if job.cancelled.is_set():
                    continue  # superseded: a newer request is pending
                dt = time.perf_counter() - t0
                self.status.last_seconds = dt
                self.status.text = f"{name}: {dt:.2f} s" + (f" | {out}" if isinstance(out, str) else "")
                self.status.clear()
            except Cancelled:
                continue
            except Exception as exc:  # noqa: BLE001 - shown to the user
                self.status.show(exc)
            finally:
                if self._live_pending is None and self._job is None:
                    self.status.set_idle()
        if self._job is None:
            self.status.set_idle()

    def wait_live(self, timeout: float = 60.0) -> bool:
        """Wait until the live updates are done; True if none is running.

        Parameters
        ----------
        timeout : float
            Most seconds to wait.

        Returns
        -------
        bool
        """
        t_end = time.perf_counter() + timeout
        while self._live_thread is not None and time.perf_counter() < t_end:
            time.sleep(0.01)
        return self._live_thread is None

    def cancel(self) -> None:
        """Ask the running work to stop at its next progress report."""
        job = self._job
        if job is not None:
            job.cancelled.set()
            self.status._render("busy", f"cancelling {job.name} (at its next step) ...")

    def wait(self, timeout: float | None = None) -> bool:
        """Wait for background work to finish; True if nothing is running any more.

        Parameters
        ----------
        timeout : float, optional
            Most seconds to wait; None waits until it ends.

        Returns
        -------
        bool
        """
        job = self._job
        if job is not None and job.thread is not None:
            job.thread.join(timeout)
        return self._job is None
