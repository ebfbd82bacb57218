"""Drive the widgets from Python: simulated mouse messages, slider changes."""

from dataclasses import dataclass

import numpy as np
import pytest
import traitlets

from branchnb.core.params import param
from branchnb.widgets import AnnotationCanvas, ErrorArea, HistogramCompare, ImageView, ParamPanel, ProgressBar


def send(canvas: AnnotationCanvas, event: str, x: float, y: float):
    """Deliver a frontend mouse message exactly as ipycanvas does."""
    top = canvas.canvas._canvases[-1]
    top._handle_frontend_event(top, {"event": event, "x": x, "y": y}, [])


@pytest.fixture
def canvas():
    img = np.random.default_rng(0).random((100, 200, 3))
    return AnnotationCanvas(img, max_display=400, pixel_ratio=1)


def test_canvas_size_and_fit(canvas):
    assert (canvas.canvas.width, canvas.canvas.height) == (400, 200)
    assert canvas.zoom == pytest.approx(2.0)
    assert canvas.view_to_image(*canvas.image_to_view(37.0, 81.0)) == pytest.approx((37.0, 81.0))


def test_freehand_stroke_in_image_pixels_at_any_zoom(canvas):
    canvas.mode = "stroke"
    canvas.zoom_by(3.0, about=(100, 50))
    canvas.pan_by(-40, 25)
    path = [(20.0 + 5 * k, 30.0 + 2 * k) for k in range(8)]
    send(canvas, "mouse_down", *canvas.image_to_view(*path[0]))
    for p in path[1:]:
        send(canvas, "mouse_move", *canvas.image_to_view(*p))
    send(canvas, "mouse_up", *canvas.image_to_view(*path[-1]))
    (shape,) = canvas.model.shapes
    assert shape.kind == "stroke"
    assert np.allclose(shape.points, path, atol=1e-9)


def test_polyline_clicks_radii_and_finish(canvas):
    canvas.mode = "polyline"
    canvas.radius = 4.0
    for p in [(10, 10), (50, 40)]:
        send(canvas, "mouse_down", *canvas.image_to_view(*p))
    canvas.radius = 7.0
    send(canvas, "mouse_down", *canvas.image_to_view(90, 45))
    send(canvas, "mouse_down", *canvas.image_to_view(90.5, 45))  # click the last vertex again: finish
    (s,) = canvas.model.shapes
    assert s.closed and s.radii.tolist() == [4.0, 4.0, 7.0]
    # A new polyline started on a vertex of the first one snaps to it and records its parent.
    send(canvas, "mouse_down", *canvas.image_to_view(50.8, 40.6))
    send(canvas, "mouse_down", *canvas.image_to_view(60, 80))
    canvas.finish()
    child = canvas.model.shapes[1]
    assert child.meta["parent"] == [0, 1] and child.points[0].tolist() == [50.0, 40.0]


def test_edit_mode_moves_vertex_and_sets_radius(canvas):
    canvas.model.add_shape("polyline", [(10, 10), (50, 40)], radii=[3.0, 3.0])
    canvas.mode = "edit"
    send(canvas, "mouse_down", *canvas.image_to_view(50, 40))
    assert canvas.selected == (0, 1)
    send(canvas, "mouse_up", *canvas.image_to_view(60, 45))
    assert canvas.model.shapes[0].points[1].tolist() == [60.0, 45.0]
    canvas.radius = 9.0
    assert canvas.model.shapes[0].radii[1] == 9.0
    canvas.handle_key("Delete", False, False, False)
    assert len(canvas.model) == 0


def test_scribble_label_point_and_outside_clicks(canvas):
    canvas.mode = "scribble"
    canvas.label = "background"
    send(canvas, "mouse_down", *canvas.image_to_view(5, 5))
    send(canvas, "mouse_move", *canvas.image_to_view(15, 5))
    send(canvas, "mouse_out", *canvas.image_to_view(15, 5))
    assert canvas.model.shapes[0].label == "background"
    canvas.mode = "point"
    send(canvas, "mouse_down", *canvas.image_to_view(-20, 5))  # outside the image: ignored
    send(canvas, "mouse_down", *canvas.image_to_view(199, 99))
    assert len(canvas.model) == 2 and canvas.model.shapes[1].points.tolist() == [[199.0, 99.0]]


def test_wheel_zoom_keeps_pointer_fixed(canvas):
    send(canvas, "mouse_move", 120, 80)
    before = canvas.view_to_image(120, 80)
    send(canvas, "mouse_wheel", 0, -200)
    assert canvas.zoom > 2.0
    assert canvas.view_to_image(120, 80) == pytest.approx(before)


def test_pan_mode(canvas):
    canvas.mode = "pan"
    grabbed = canvas.view_to_image(100, 100)
    send(canvas, "mouse_down", 100, 100)
    send(canvas, "mouse_move", 130, 90)
    send(canvas, "mouse_up", 130, 90)
    assert canvas.view_to_image(130, 90) == pytest.approx(grabbed)  # the grabbed point follows the mouse
    assert len(canvas.model) == 0


def test_undo_redo_keys(canvas):
    canvas.model.add_shape("point", [(1, 1)])
    canvas.handle_key("z", False, True, False)
    assert len(canvas.model) == 0
    canvas.handle_key("y", False, True, False)
    assert len(canvas.model) == 1


def test_errors_in_callbacks_are_shown_and_widget_survives(canvas):
    def boom(_event):
        raise ValueError("annotation rejected")

    canvas.model.observe(canvas.errors.guard(boom))
    canvas.mode = "point"
    send(canvas, "mouse_down", *canvas.image_to_view(3, 3))
    assert canvas.errors.last_error == "ValueError: annotation rejected"
    assert len(canvas.model) == 1


def test_invalid_traits_and_arguments(canvas):
    with pytest.raises(traitlets.TraitError):
        canvas.mode = "lasso"
    with pytest.raises(traitlets.TraitError):
        canvas.radius = -1
    with pytest.raises(ValueError, match="overlay"):
        canvas.set_overlay(np.zeros((5, 5, 4)))
    with pytest.raises(ValueError, match="image"):
        AnnotationCanvas(np.zeros((0, 3)))
    canvas.set_overlay(np.zeros((100, 200, 4)))
    canvas.set_overlay(None)


@dataclass
class Params:
    k: int = param(3, min=1, max=10, help="history length k")
    w: float = param(50.0, min=0.0, max=100.0, help="w_G")
    scale: float = param(1.0, min=0.01, max=100.0, log=True)
    crossing: bool = param(True)
    metric: str = param("nonscalar", options=("cumulative", "nonscalar", "blend"))
    hidden: int = param(7, ui=False)


def test_param_panel_builds_controls_and_calls_back():
    got = []
    panel = ParamPanel(Params, on_change=got.append, debounce=0)
    kinds = {name: type(w).__name__ for name, w in panel.controls.items()}
    assert kinds == {"k": "IntSlider", "w": "FloatSlider", "scale": "FloatLogSlider",
                     "crossing": "Checkbox", "metric": "Dropdown"}
    assert panel.controls["k"].tooltip == "history length k"
    panel.controls["k"].value = 5
    panel.controls["metric"].value = "blend"
    assert got[-1] == Params(k=5, metric="blend")
    panel.reset()
    assert got[-1] == Params() and panel.values.hidden == 7


def test_param_panel_debounces_inside_a_running_loop():
    import asyncio

    got = []

    async def drive():
        panel = ParamPanel(Params, on_change=got.append, debounce=0.05)
        for v in range(2, 8):
            panel.controls["k"].value = v
        await asyncio.sleep(0.2)

    asyncio.run(drive())
    assert [p.k for p in got] == [7]


def test_param_panel_shows_validation_errors():
    panel = ParamPanel(Params(), debounce=0)
    panel.on_change(lambda values: (_ for _ in ()).throw(ValueError("too many")))
    panel.controls["k"].value = 4
    assert panel.errors.last_error == "ValueError: too many"
    with pytest.raises(TypeError, match="dataclass"):
        ParamPanel(int)


def test_histogram_compare_updates_in_place():
    h = HistogramCompare(bins=8, metric="chi2", title="angles")
    canvas = h.canvas
    h.update([0, 1, 2, 3], [0, 1, 2, 3], [3, 3, 3, 3], labels=["in", "same", "other"])
    assert h.canvas is canvas
    assert h.comparison.distances[1] == 0 and h.comparison.distances[2] > 0.5
    assert "chi2" in h.caption.value and "other" in h.caption.value
    h.update([np.nan])
    assert "NaN" in h.errors.last_error


def test_image_view_is_lossless_by_default():
    import cv2

    img = np.random.default_rng(0).random((16, 16, 3)).astype(np.float32)
    v = ImageView([img], ["noise"])
    assert v.images[0].format == "png"
    dec = cv2.imdecode(np.frombuffer(v.images[0].value, np.uint8), cv2.IMREAD_UNCHANGED)[..., ::-1]
    assert np.array_equal(dec, np.round(img * 255).astype(np.uint8))
    fast = ImageView([img], fast=True)
    assert fast.images[0].format == "jpeg"
    first = v.images[0]
    v.update([img * 0.5])
    assert v.images[0] is first  # reused, no re-layout


def test_error_area_and_progress():
    errors = ErrorArea()
    assert errors.layout.display == "none"
    with errors.catch():
        raise TypeError("bad image")
    assert errors.last_error == "TypeError: bad image" and errors.layout.display is None
    bar = ProgressBar()
    seen = list(bar.track(range(4)))
    assert seen == [0, 1, 2, 3] and bar.bar.value == 1.0
    bar.update(0.5, "half")
    assert bar.text.value == "half"


def test_tool_options_follow_the_mode():
    c = AnnotationCanvas(np.zeros((10, 10, 3)), mode="polyline")
    # hidden by visibility, so that the options row keeps its height (the canvas does not jump)
    assert c._label_picker.layout.visibility == "hidden" and c._radius_slider.layout.visibility == "visible"
    c.mode = "scribble"
    assert c._label_picker.layout.visibility == "visible" and c._radius_slider.layout.visibility == "hidden"


def test_histogram_backing_store_follows_the_pixel_ratio_and_the_column_width():
    h = HistogramCompare(bins=8, width=300, height=100)
    assert h.canvas.layout.height == "24px"                       # no data yet: one line, no empty box
    h.update([0, 1, 1, 2], [0, 2, 2, 2])
    h._probe._box.value = "1 0"                                   # the browser: DPR 1, no fitting column
    assert (h.canvas.width, h.canvas.height, h.canvas.layout.width) == (300, 100, "300px")
    h._probe._box.value = "2 0"
    assert (h.canvas.width, h.canvas.height) == (600, 200) and h.canvas.layout.width == "300px"
    h._probe._box.value = "2 240"                                 # shown in a 240 px column: drawn at 240
    assert (h.canvas.width, h.canvas.layout.width) == (480, "240px")
    h._probe._box.value = "2 900"                                 # never wider than asked for
    assert h.canvas.layout.width == "300px"
    h._probe._box.value = "garbage"                               # ignored
    assert h.pixel_ratio == 2.0
    h.clear()
    assert h.canvas.layout.height == "24px"


def test_image_view_never_enlarges_and_marks_stale():
    v = ImageView(width=200)
    v.update([np.zeros((10, 50, 3)), np.zeros((400, 800, 3))], ["small", "big"])
    assert v.images[0].layout.max_width == "50px" and v.images[1].layout.max_width == "200px"
    v.mark_stale()
    assert v.stale and v.title_texts == ["out of date: small", "out of date: big"]
    assert "bnb-stale" in v._dom_classes
    v.update([np.zeros((10, 50, 3))] * 2, ["a", "b"])
    assert not v.stale and "bnb-stale" not in v._dom_classes


def test_param_sections_have_a_visible_help_line():
    from branchnb.branching import SynthesisParams

    panel = ParamPanel(SynthesisParams, sections=[("markov", ["h", "m", "k"])], labels={"k": ("history", "k")})
    help_box = panel.sections[0].children[0].children[0]
    assert "what these do" in help_box.value and "<b>history</b> <i>k</i>" in help_box.value
    assert "white-space:nowrap" in panel.rows["k"].label.value                # one line per row


def test_eye_button_hides_and_shows_the_annotations():
    c = AnnotationCanvas(np.zeros((20, 30, 3)), mode="point")
    c.handle_mouse_down(*c.image_to_view(5, 5))
    c.buttons["show"].click()
    assert not c.show_annotations and c.buttons["show"].icon == "eye-slash"
    c.buttons["show"].click()
    assert c.show_annotations and c.buttons["show"].icon == "eye"
    with pytest.raises(traitlets.TraitError):
        c.annotation_opacity = 0.0
