"""The app shell, honest parameter panels and the canvas' robustness (issues 13 and 15)."""

import math
import threading
from dataclasses import dataclass

import numpy as np
import pytest
import traitlets

from branchnb.core.params import param
from branchnb.widgets import AnnotationCanvas, AppShell, Cancelled, ParamPanel, StatusLine


def send(canvas, event, x, y):
    top = canvas.canvas._canvases[-1]
    top._handle_frontend_event(top, {"event": event, "x": x, "y": y}, [])


# -- status line and shell ----------------------------------------------------------
def test_status_line_busy_state_disables_run_buttons_and_reports_time():
    import ipywidgets as widgets

    b = widgets.Button()
    status = StatusLine()
    status.add_run_buttons(b)
    seen = []
    with status.busy("fit", message="3 branches"):
        seen.append((b.disabled, status.busy_now, "computing fit" in status.value))
    assert seen == [(True, True, True)]
    assert not b.disabled and not status.busy_now
    assert status.text.startswith("fit: ") and status.text.endswith("| 3 branches")


def test_error_stays_until_the_next_successful_action():
    c = AnnotationCanvas(np.zeros((40, 60, 3)), mode="point", pixel_ratio=1)

    def reject(_event):
        raise ValueError("annotation rejected")

    c.model.observe(c.errors.guard(reject))
    send(c, "mouse_down", *c.image_to_view(5, 5))
    assert c.errors.last_error == "ValueError: annotation rejected"
    for k in range(5):  # mouse moves, leaving the canvas, wheel: passive, the error stays
        send(c, "mouse_move", *c.image_to_view(6 + k, 6))
    send(c, "mouse_out", 0, 0)
    assert c.errors.last_error == "ValueError: annotation rejected"
    c.model.unobserve(c.model._observers[-1])
    send(c, "mouse_down", *c.image_to_view(9, 9))  # a successful action clears it
    assert c.errors.last_error is None


def test_a_failure_inside_an_action_is_not_cleared_by_the_outer_guard():
    shell = AppShell("t")

    def action():
        with shell.busy("inner"):
            raise ValueError("inner failed")

    shell.guard(action)()
    assert shell.status.last_error == "ValueError: inner failed"
    assert "inner failed after" in shell.status.value


def test_shell_actions_busy_error_details_and_cancel():
    shell = AppShell("demo", background=True)
    started, release = threading.Event(), threading.Event()
    steps = []

    def long_work():
        started.set()
        for i in range(200):
            release.wait(0.01)
            shell.progress(i / 200, "step")
            steps.append(i)
        return "finished"

    shell.add_action("render", long_work, background=True, cancellable=True, primary=True)
    other = shell.add_action("other", lambda: None)
    # nothing said yet: no empty status strip; no cancel button taking room
    assert shell.status.layout.display == "none" and shell.cancel_button.layout.display == "none"
    assert shell.cancel_button not in shell.toolbar.children        # beside the status, not a toolbar row
    shell.click("render")
    assert started.wait(5)
    assert shell.running and other.disabled and not shell.cancel_button.disabled
    assert shell.cancel_button.layout.display is None and shell.status.layout.display is None
    shell.click("other")  # refused while the render runs, with a message
    assert "still running" in shell.status.last_error
    shell.cancel()
    assert shell.wait(10)
    assert "cancelled" in shell.status.text and len(steps) < 200
    assert not other.disabled and shell.cancel_button.disabled
    assert shell.cancel_button.layout.display == "none"

    shell.add_action("boom", lambda: math.sqrt(-1))
    shell.click("boom")
    assert shell.status.last_error == "ValueError: math domain error"
    assert "<details" in shell.status.value and "Traceback" in shell.status.last_traceback
    shell.click("other")
    assert shell.status.last_error is None and shell.status.text.startswith("other: ")


def test_progress_outside_a_job_only_reports():
    shell = AppShell()
    shell.progress(0.5, "half")
    assert "half 50 %" in shell.status.value
    with pytest.raises(ValueError, match="sidebar_width"):
        AppShell(sidebar_width=10)
    with pytest.raises(ValueError, match="exists"):
        shell.add_action("a", lambda: None)
        shell.add_action("a", lambda: None)
    assert issubclass(Cancelled, Exception)


# -- honest parameters --------------------------------------------------------------
@dataclass
class Paper:
    h: float = param(20.0, min=0.5, max=40.0, help="step h")
    n: int = param(3000, min=1, max=20000, step=50, help="endpoints")
    s: int = param(1800, min=10, max=20000, step=50)
    a: float = param(0.1, min=0.0, max=1.0, step=0.03)
    r: float = param(64.0, min=1.0, max=1000.0, log=True)
    big: float = param(20000.0, min=0.0, max=1e6, step=100.0)


def _browser_snap(w):
    """What ipywidgets' slider view does to a value: round it onto the slider's grid."""
    if type(w).__name__ == "FloatLogSlider":
        e = math.log10(w.value)
        return w.base ** (w.min + round((e - w.min) / w.step) * w.step)
    return w.min + round((w.value - w.min) / w.step) * w.step


def test_param_panel_keeps_exact_defaults_through_browser_snapping():
    panel = ParamPanel(Paper, log=("big",))
    # The thumbs sit on the defaults (each slider's grid passes through its default) ...
    for name in ("h", "n", "s", "a", "r"):
        assert _browser_snap(panel.controls[name]) == pytest.approx(getattr(Paper(), name), rel=1e-12)
    # ... and what the browser sends back after snapping is not taken for a change.
    for name, shown in (("h", 19.9), ("n", 3001), ("s", 1810), ("a", 0.09), ("r", 63.99999999999999)):
        panel.controls[name].value = shown
    assert panel.values == Paper()
    assert type(panel.controls["big"]).__name__ == "FloatLogSlider"
    # A real move is taken, and reset gives the exact defaults again.
    panel.controls["h"].value = 25.0
    panel.controls["r"].value = 200.0
    assert panel.values.h == 25.0 and panel.values.r == 200.0
    panel.reset()
    assert panel.values == Paper()
    assert [panel.rows[n].readout.value for n in ("h", "n", "a", "r")] == ["20", "3000", "0.1", "64"]


def test_param_panel_typed_values_are_exact_or_refused_with_a_message():
    got = []
    panel = ParamPanel(Paper, on_change=got.append)
    assert panel.type_value("h", "12.345")
    assert panel.values.h == 12.345 and got[-1].h == 12.345
    assert not panel.type_value("h", "99")
    row = panel.rows["h"]
    assert "must be in [0.5, 40]" in row.message.value and panel.values.h == 12.345
    assert row.readout.value == "12.345"
    assert not panel.type_value("n", "2.5") and "whole numbers" in panel.rows["n"].message.value
    assert not panel.type_value("n", "abc") and "not a number" in panel.rows["n"].message.value
    assert panel.type_value("n", "1234") and panel.values.n == 1234
    assert panel.rows["n"].message.layout.display == "none"


def test_param_panel_sections_labels_and_tooltips():
    panel = ParamPanel(Paper, sections=[("Markov model (Sec. 4)", ["h", "n"])],
                       labels={"h": ("resampling step", "h")}, closed=("other",))
    assert len(panel.sections) == 2
    assert panel.sections[0].titles == ("Markov model (Sec. 4)",)
    assert panel.sections[1].titles == ("other",) and panel.sections[1].selected_index is None
    assert "resampling step" in panel.rows["h"].label.value and "<i" in panel.rows["h"].label.value
    assert panel.rows["h"].label.tooltip == "step h" and panel.controls["h"].tooltip == "step h"
    widths = {r.label.layout.width for r in panel.rows.values()}
    assert len(widths) == 1  # the same geometry for every row
    with pytest.raises(ValueError, match="no field"):
        ParamPanel(Paper, labels={"nope": "x"})


# -- canvas robustness (issue 13, class 5) ----------------------------------------------
def test_canvas_rejects_bad_modes_zoom_and_ignores_non_finite_events():
    img = np.zeros((40, 60, 3))
    with pytest.raises(ValueError, match="mode must be one of"):
        AnnotationCanvas(img, mode="bogus")
    with pytest.raises(ValueError, match="at least one tool"):
        AnnotationCanvas(img, modes=())
    with pytest.raises(ValueError, match="offered"):
        AnnotationCanvas(img, mode="pan", modes=("point",))
    c = AnnotationCanvas(img, mode="pan", modes=("point", "pan"), pixel_ratio=1)
    for bad in (float("nan"), 0.0, -1.0, float("inf")):
        with pytest.raises(traitlets.TraitError, match="zoom"):
            c.zoom = bad
    send(c, "mouse_down", 10, 10)
    send(c, "mouse_move", float("inf"), 10)  # a broken pan event
    send(c, "mouse_up", 12, 10)
    c.handle_wheel(0, float("nan"))
    assert np.all(np.isfinite(c._offset)) and np.isfinite(c.zoom)
    c.mode = "point"
    send(c, "mouse_down", *c.image_to_view(20, 30))
    assert c.model.shapes[-1].points.tolist() == [[20.0, 30.0]]


def test_canvas_draws_at_device_resolution_and_wheel_steps_do_not_depend_on_it():
    img = np.zeros((100, 200, 3))
    zooms = []
    for ratio in (1.0, 2.0):
        c = AnnotationCanvas(img, max_display=400, pixel_ratio=ratio)
        assert c.canvas.width == 400 * ratio and c.canvas.layout.width == "400px"
        z0 = c.zoom
        c.handle_wheel(0, -100 * ratio)  # one notch; deltaY differs by device
        zooms.append(c.zoom / z0)
        # Snapping works in CSS pixels at any ratio: a click 5 CSS px from a vertex snaps.
        c.mode = "polyline"
        c.fit()
        send(c, "mouse_down", *c.image_to_view(50, 50))
        send(c, "mouse_down", *c.image_to_view(90, 50))
        c.finish()
        x, y = c.image_to_view(90, 50)
        send(c, "mouse_down", x + 5 * ratio, y)
        assert c.model.shapes[-1].meta.get("parent") == [0, 1]
    assert zooms[0] == pytest.approx(zooms[1])
    c.pixel_ratio = 1.5  # the browser reported its ratio: the buffer follows, the CSS size stays
    assert c.canvas.width == 600 and c.canvas.layout.width == "400px"


def _bytes_sent(fn) -> int:
    """Bytes of canvas drawing messages sent while ``fn`` runs."""
    from ipycanvas import canvas as ipc

    manager = ipc._CANVAS_MANAGER
    sent = []
    orig = manager._send_custom
    manager._send_custom = lambda command, buffers=[]: (
        sent.append(len(str(command)) + sum(len(bytes(b)) for b in buffers)), orig(command, buffers))[1]
    try:
        fn()
    finally:
        manager._send_custom = orig
    return sum(sent)


@pytest.mark.parametrize("n_shapes", [2, 200])
def test_adding_a_vertex_sends_the_same_little_whatever_the_number_of_shapes(n_shapes):
    c = AnnotationCanvas(np.zeros((100, 200, 3)), mode="polyline", pixel_ratio=1)
    for k in range(n_shapes):
        c.model.add_shape("stroke", [(k % 190, 0), (k % 190, 90), (k % 190 + 5, 95)])
    send(c, "mouse_down", *c.image_to_view(10, 10))
    cost = _bytes_sent(lambda: send(c, "mouse_down", *c.image_to_view(40, 30)))
    assert len(c.model.shapes[-1].points) == 2
    assert 0 < cost < 3000  # one segment, one vertex: not a redraw of every shape


# -- clear messages for bad app arguments (issue 13, class 5) ------------------------------
def _apps():
    from branchnb.trees.variations import TreeLibrary
    from branchnb.widgets import HistogramCompare, ImageView
    from branchnb.widgets.dendrite import DendriteApp
    from branchnb.widgets.strokes import StrokeEditApp
    from branchnb.widgets.trees import TreeVariationsApp

    img = np.random.default_rng(0).random((40, 60, 3)).astype(np.float32)
    lib = TreeLibrary.from_data(["tree_rpg_01", "tree_rpg_03"], size=64)
    return {
        "max_display": lambda v: AnnotationCanvas(img, max_display=v),
        "pixel_ratio": lambda v: AnnotationCanvas(img, pixel_ratio=v),
        "max_size": lambda v: DendriteApp(img, max_size=v),
        "display": lambda v: TreeVariationsApp(lib, display=v),
        "thumb": lambda v: TreeVariationsApp(lib, thumb=v),
        "width": lambda v: ImageView(width=v),
        "height": lambda v: HistogramCompare(height=v),
        "target_shape": lambda v: StrokeEditApp(img, target_shape=v),
        "background": lambda v: StrokeEditApp(img, background=v),
    }


def test_bad_app_arguments_name_the_argument():
    cryptic = ("negative dimensions", "could not convert", "invalid literal", "NoneType", "OpenCV")
    for arg, make in _apps().items():
        for bad in (-5, 0, "a", None, float("nan"), (1, 2, "x"), True):
            if bad is None and arg in ("background", "pixel_ratio", "target_shape"):
                continue  # None is valid: transparent / the browser's ratio / the source's size
            try:
                make(bad)
            except (ValueError, TypeError) as exc:
                msg = str(exc)
                assert arg in msg and not any(c in msg for c in cryptic), (arg, bad, msg)
            else:
                raise AssertionError(f"{arg}={bad!r} was accepted")


def test_add_files_puts_open_save_load_in_the_toolbar():
    shell = AppShell("demo")
    assert shell._file_tools.layout.display == "none"
    files = shell.add_files(name="demo", open=lambda imgs: None, outputs=lambda: {}, load=lambda t: None)
    assert shell.files is files and shell._file_tools.layout.display is None
    assert {files.upload, files.save_button, files.folder, files.annotation_upload} <= set(shell._file_tools.children)
    assert files.links in shell._links.children
    with pytest.raises(ValueError, match="already"):
        shell.add_files(name="again")
    with pytest.raises(TypeError, match="open must be callable"):
        AppShell().add_files(open=3)
