"""StrokeEditApp driven from Python: mouse strokes, control clicks, sliders, errors."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.strokes import pair_color_hex
from branchnb.widgets.strokes import StrokeEditApp, strokes_from_shapes


def send(canvas, event: str, x: float, y: float):
    top = canvas.canvas._canvases[-1]
    top._handle_frontend_event(top, {"event": event, "x": x, "y": y}, [])


def drag(canvas, points):
    """Press, drag through ``points`` (image pixels) and release: a freehand stroke."""
    canvas.mode = "stroke"
    pts = [canvas.image_to_view(*p) for p in points]
    send(canvas, "mouse_down", *pts[0])
    for p in pts[1:]:
        send(canvas, "mouse_move", *p)
    send(canvas, "mouse_up", *pts[-1])


def click(canvas, x, y, mode="point"):
    canvas.mode = mode
    send(canvas, "mouse_down", *canvas.image_to_view(x, y))
    send(canvas, "mouse_up", *canvas.image_to_view(x, y))


def striped_bar(shape=(60, 160)):
    """An RGBA bar with stripes along x (so every part of it looks different)."""
    h, w = shape
    img = np.zeros((h, w, 4), np.float32)
    x = np.arange(10, w - 10)
    img[22:38, 10:w - 10, 0] = 0.5 + 0.4 * np.sin(x / 4.0)
    img[22:38, 10:w - 10, 1] = np.linspace(0.2, 0.8, len(x))
    img[22:38, 10:w - 10, 2] = 0.3
    img[22:38, 10:w - 10, 3] = 1.0
    return img


SRC = [(14, 30), (60, 30), (100, 30), (146, 30)]
TGT = [(20, 10), (60, 30), (80, 50), (130, 50)]


@pytest.fixture
def app():
    a = StrokeEditApp(striped_bar(), max_display=320)
    a.panel.debounce = 0
    return a


def test_drawing_a_pair_of_strokes_runs_the_edit(app):
    drag(app.source_canvas, SRC)
    assert app.result is None and "draw 1 more target" in app.status.value
    drag(app.target_canvas, TGT)
    assert app.errors.last_error is None
    res = app.result
    assert res is not None and res.mask.sum() > 500
    # the result follows the target stroke: the bar is now low on the right
    assert res.mask[45:55, 110:130].mean() > 0.8 and not res.mask[25:35, 110:130].any()
    # pairing is visible: both strokes carry pair 0's colour
    for c in (app.source_canvas, app.target_canvas):
        assert c.model.shapes[0].meta["color"] == pair_color_hex(0)
    # the result lies over the target canvas, the histograms compare colours
    assert app.target_canvas._has_overlay and app.view.images
    assert [h.comparison.labels for h in app.hists] == [["source object", "result"]] * 3
    assert max(h.comparison.distances[1] for h in app.hists) < 0.5
    assert "1 source / 1 target" in app.status.value


def test_second_pair_gets_its_own_colour(app):
    app.add_stroke("source", SRC)
    app.add_stroke("target", TGT)
    app.add_stroke("source", [(20, 30), (80, 30)])
    assert "draw 1 more target" in app.status.value
    app.add_stroke("target", [(100, 5), (140, 10)])
    assert app.errors.last_error is None
    colours = [s.meta["color"] for s in app.target_canvas.model.shapes]
    assert colours == [pair_color_hex(0), pair_color_hex(1)]
    assert app.result.mask[:15, 100:140].any()


def test_control_points_by_clicking(app):
    app.add_stroke("source", SRC)
    app.add_stroke("target", TGT)
    click(app.source_canvas, 40, 31)
    assert "0 target control points" in app.status.value
    click(app.target_canvas, 95, 49)
    assert app.errors.last_error is None
    pair = app.result.pairs[0]
    assert pair.n_control == 3
    # the source point at s = 26 now maps to the target point clicked
    s_src, s_tgt = pair.control[1]
    assert s_src == pytest.approx(26.0, abs=1.0)
    assert np.allclose(pair.target.point_at(s_tgt), (95, 50), atol=1.5)
    assert app.source_canvas.model.shapes[-1].meta["color"] == pair_color_hex(0)
    # a second pair out of order -> a clear error, the app keeps working
    click(app.source_canvas, 120, 30)
    click(app.target_canvas, 40, 20)
    assert "out of order" in app.errors.last_error
    app.target_canvas.model.undo()
    app.source_canvas.model.undo()
    assert app.errors.last_error is None and app.result.pairs[0].n_control == 3


def test_sliders_and_seams(app):
    app.add_stroke("source", SRC)
    app.add_stroke("target", TGT)
    app.panel.controls["composition"].value = "overlay"
    assert app.result.params.composition == "overlay"
    app.panel.controls["patch_size"].value = 24
    assert app.result.radius == 12.0
    app.show_seams.value = True
    ov = app.result.seams
    assert ov.any()
    # the view shows what the target canvas does not: where the result came from, and its seams
    assert app.view.title_texts == ["copied from the source (the rest dimmed)", "patches (a colour each), seams red"]
    copied = app._copied(app.result)
    inside, obj = app.result.source_region, app.image[..., 3] > 0.5
    assert copied.shape[:2] == app.image.shape[:2] and inside.any() and (obj & ~inside).any()
    # the copied pixels as they are, the others faded towards white
    assert np.allclose(copied[inside & obj], app.image[inside & obj][:, :3], atol=1e-6)
    assert copied[obj & ~inside].mean() > app.image[obj & ~inside][:, :3].mean() + 0.2


def test_errors_are_shown_and_the_app_survives(app):
    app.add_stroke("target", [(50, 30), (50.2, 30)])  # a stroke of 0.2 px: a click
    assert "a click is not a stroke" in app.errors.last_error and len(app.target_canvas.model) == 0
    app.add_stroke("source", SRC)
    app.add_stroke("target", TGT)
    assert app.errors.last_error is None and app.result is not None
    with pytest.raises(ValueError, match="side"):
        app.add_stroke("middle", SRC)


def test_reverse_and_clear(app):
    app.add_stroke("source", SRC)
    app.add_stroke("target", TGT)
    before = app.result.layer.copy()
    app.reverse_target()
    tgt, _, _, _ = strokes_from_shapes(app.target_canvas.model.shapes)
    assert np.allclose(tgt[0][0], TGT[-1])
    assert not np.allclose(app.result.layer, before)
    app.clear()
    assert len(app.source_canvas.model) == 0 and "0 source / 0 target" in app.status.value
    with pytest.raises(ValueError, match="no target stroke"):
        app.reverse_target()


def test_background_and_target_shape():
    app = StrokeEditApp(striped_bar(), background=(0.2, 0.3, 0.4), target_shape=(80, 120),
                        max_display=200)
    app.add_stroke("source", SRC)
    app.add_stroke("target", [(10, 40), (110, 40)])
    assert app.result.image.shape == (80, 120, 4)
    assert np.allclose(app.result.image[2, 2], (0.2, 0.3, 0.4, 1.0))


def test_clear_all_removes_the_result(app):
    app.add_stroke("source", SRC)
    app.add_stroke("target", TGT)
    assert app.result is not None and app.view.images
    app.shell.click("clear all")
    assert app.result is None and not app.view.images
    assert all(h.comparison is None for h in app.hists) and not app.target_canvas._has_overlay


@pytest.mark.parametrize("kwargs, match", [
    ({"target_shape": (-5, 10)}, "target_shape sides"),
    ({"target_shape": ("a", 10)}, "two whole numbers"),
    ({"target_shape": 7}, "height, width"),
    ({"background": "red"}, "string 'red'"),
    ({"background": (0.2, 2.0, 0.1)}, r"in \[0, 1\]"),
    ({"background": ("a", "b", "c")}, "RGB colour"),
])
def test_bad_arguments_get_clear_messages(kwargs, match):
    with pytest.raises(ValueError, match=match):
        StrokeEditApp(striped_bar(), max_display=200, **kwargs)


def test_slow_edits_get_a_reduced_size_preview_first():
    import cv2

    big = cv2.resize(striped_bar(), (320, 120), interpolation=cv2.INTER_NEAREST)
    app = StrokeEditApp(big, max_display=200)
    app.preview_after = 0.0  # as if every edit were slow
    app.add_stroke("source", [(p[0] * 2, p[1] * 2) for p in SRC])
    app.add_stroke("target", [(p[0] * 2, p[1] * 2) for p in TGT])
    app.panel.controls["seam_power"].value = 2.0
    assert app.result.params.seam_power == 2.0
    assert app.preview is not None and app.preview.params.seam_power == 2.0
    assert app.preview.image.shape[1] < app.result.image.shape[1]  # reduced size, shown first
    assert app.errors.last_error is None


def test_seam_only_change_reuses_the_fetched_patches_and_equals_a_script(app, monkeypatch):
    import branchnb.widgets.strokes as mod
    from branchnb.strokes import edit_structure

    app.add_stroke("source", SRC)
    app.add_stroke("target", TGT)
    before, patches = app.result, app.patches
    assert patches is not None
    fetches = []
    real = mod.fetch_patches
    monkeypatch.setattr(mod, "fetch_patches", lambda *a, **k: fetches.append(1) or real(*a, **k))
    assert app.expected_seconds() == app.stage_seconds["compose"]
    app.panel.controls["seam_power"].value = 3.0
    assert not fetches and app.patches is patches  # only sampling and composition ran again
    src, tgt, control, _ = app.strokes()
    script = edit_structure(app.image, src, tgt, app.params, control_points=control,
                            target_shape=app.target_shape)
    assert np.array_equal(app.result.image, script.image) and app.result.energies == script.energies
    assert not np.array_equal(app.result.labels, before.labels)  # the new seams, not the old image
    app.panel.controls["search_window"].value = 4  # a fetch parameter: fetched again
    assert fetches == [1] and app.patches is not patches
    app.add_stroke("source", SRC)
    app.add_stroke("target", [(20, 50), (140, 50)])  # new strokes: fetched again
    assert len(fetches) == 2 and len(app.result.pairs) == 2


def test_reduced_preview_is_the_new_value_at_reduced_size():
    import cv2

    from branchnb.strokes import edit_structure

    big = cv2.resize(striped_bar(), (320, 120), interpolation=cv2.INTER_NEAREST)
    app = StrokeEditApp(big, max_display=200)
    app.panel.debounce = 0
    app.preview_after = 0.0  # as if every edit were slow: the reduced patches are fetched after each edit
    app.add_stroke("source", [(p[0] * 2, p[1] * 2) for p in SRC])
    app.add_stroke("target", [(p[0] * 2, p[1] * 2) for p in TGT])
    assert app._preview_ready()
    shown = []
    update = app.view.update
    app.view.update = lambda images, titles=None: (shown.append((images, titles)), update(images, titles))
    app.panel.controls["seam_power"].value = 2.5
    (first, t_first), (last, t_last) = shown[0], shown[-1]
    assert "preview" in t_first[0] and t_last[0].startswith("copied")
    pv = app.preview
    s = 0.5  # PREVIEW_SIZE 160 over the long side 320
    src, tgt, _, _ = app.strokes()
    ref = edit_structure(cv2.resize(big, (160, 60), interpolation=cv2.INTER_AREA), [a * s for a in src],
                         [b * s for b in tgt], pv.params, target_shape=pv.image.shape[:2])
    assert pv.params.seam_power == 2.5 and np.array_equal(pv.image, ref.image)
    assert np.array_equal(first[0], pv.show())
    assert np.array_equal(last[1], app._patches(app.result)) and app.result.params.seam_power == 2.5
    app.preview_after = 10.0  # fast edits: a seam-only change shows the result without a preview
    shown.clear()
    app.panel.controls["seam_power"].value = 3.0
    assert len(shown) == 1 and shown[0][1][0].startswith("copied")


def test_a_single_click_is_not_a_stroke(app):
    drag(app.source_canvas, SRC)
    click(app.target_canvas, 50, 30, mode="stroke")  # press and release on the spot
    assert len(app.target_canvas.model) == 0  # not kept as an invisible stroke
    assert "a click is not a stroke" in app.shell.status.last_error
    assert "0.00 s" not in app.shell.status.value and app.result is None
    # pressing re-synthesize says what is missing, next to the action
    app.shell.click("re-synthesize")
    assert "draw 1 more target stroke" in app.shell.status.last_error
    drag(app.target_canvas, TGT)
    assert app.shell.status.last_error is None and app.result is not None


def test_automatic_parameters_say_so(app):
    app.add_stroke("source", SRC)
    app.add_stroke("target", TGT)
    for name in ("patch_size", "spacing", "junction_tolerance"):
        assert getattr(app.params, name) == 0 and "0: auto" in app.panel.rows[name].label.value
    assert set(app.result.auto) == {"patch_size", "spacing", "junction_tolerance"}
    assert f"2r = {app.result.auto['patch_size']:g} px" in app.status.value
    app.panel.controls["patch_size"].value = 24
    assert "patch_size" not in app.result.auto and "2r =" not in app.status.value


def test_result_view_does_not_repeat_the_target_canvas(app):
    # Found (issue 25, app): the view's second image was the result with its seams, which the
    # target canvas already shows ("show seams"). It now shows which patch each pixel comes from.
    app.add_stroke("source", SRC)
    app.add_stroke("target", TGT)
    import cv2

    r = app.result
    copied, patches = (cv2.cvtColor(cv2.imdecode(np.frombuffer(im.value, np.uint8), cv2.IMREAD_COLOR),
                                    cv2.COLOR_BGR2RGB).astype(np.float32) / 255.0 for im in app.view.images)
    shown = r.show(seams=True)
    obj = r.image[..., 3] > 0.5
    assert patches.shape == shown.shape and obj.sum() > 200
    # off the seams (red in both), the patch picture differs from the canvas' result ...
    same = np.abs(patches - shown).max(axis=-1) < 0.05
    assert same[obj & ~r.seams].mean() < 0.1
    assert (patches[(r.image[..., 3] == 0) & ~r.seams] > 0.97).all()  # (white around the object, like the result)
    # ... it has one colour per patch (up to the object's shading): touching patches differ
    inner = obj & ~r.seams & (r.labels >= 0)
    labels = np.unique(r.labels[inner])
    assert labels.size >= 3
    hue = patches / np.maximum(patches.sum(axis=-1, keepdims=True), 1e-6)  # chromaticity
    means = np.array([hue[inner & (r.labels == k)].mean(axis=0) for k in labels])
    steps = np.abs(np.diff(means, axis=0)).sum(axis=1)
    assert steps.min() > 0.05, steps
    assert np.allclose(patches[r.seams], (1.0, 0.0, 0.0))
    # and the source picture is the source's size, not the target's
    assert copied.shape[:2] == app.image.shape[:2]


def test_narrow_canvases_get_a_one_row_toolbar():
    # widgets25: at max_display 280 each canvas' 4 named tools and 8 buttons of 34 px took two rows;
    # narrow canvases show the tools as icons (name in the tooltip) and 21 px buttons: 12 x 21 px + margins.
    from branchnb.widgets.canvas import COMPACT_BELOW, AnnotationCanvas

    img = np.ones((120, 300, 3), np.float32)
    app = StrokeEditApp(img, target_shape=(200, 300), max_display=280)
    for c in (app.source_canvas, app.target_canvas):
        row = c.children[0].children[0]
        assert "bnb-compact" in row._dom_classes
        assert len(c._tools.icons) == len(c._tools.options) == 4
        assert c._tools.style.button_width == "21px"
        widths = [b.layout.width for b in c.buttons.values() if b.layout.display != "none"]
        assert widths == ["21px"] * 8
        assert all(t.split(":")[0] in ("freehand", "polyline", "point", "pan") for t in c._tools.tooltips)
        assert [label for label, _ in c._tools.options] == ["freehand", "polyline", "point", "pan"]
    wide = AnnotationCanvas(img, max_display=COMPACT_BELOW)
    assert "bnb-compact" not in wide.children[0].children[0]._dom_classes and not wide._tools.icons
