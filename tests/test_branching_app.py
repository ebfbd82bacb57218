"""BranchingApp driven from Python: clicks, buttons and sliders call the same methods."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import Branch, Structure
from branchnb.widgets.branching import (
    PREVIEW_FIRST,
    BranchingApp,
    annotations_to_structure,
    structure_to_annotations,
)


def send(canvas, event: str, x: float, y: float):
    top = canvas.canvas._canvases[-1]
    top._handle_frontend_event(top, {"event": event, "x": x, "y": y}, [])


def click(canvas, x, y):
    send(canvas, "mouse_down", *canvas.image_to_view(x, y))
    send(canvas, "mouse_up", *canvas.image_to_view(x, y))


def wiggle_structure(shape=(200, 300)) -> Structure:
    t = np.linspace(0, 1, 70)
    trunk = np.c_[15 + 270 * t, 100 + 25 * np.sin(7 * t)]
    s = Structure([Branch(trunk, np.linspace(4, 2, len(t)))], image_shape=shape)
    for v, side in ((20, -1), (40, 1)):
        u = np.linspace(0, 1, 25)[:, None]
        d = np.array([0.6, side * 0.8])
        s.add_branch(trunk[v] + u * 70 * d + np.c_[np.zeros(25), 3 * np.sin(9 * u[:, 0])], 1.5,
                     parent=0, parent_vertex=v)
    return s


@pytest.fixture
def app():
    img = np.ones((200, 300, 3), np.float32)
    a = BranchingApp(img, structure=wiggle_structure(), max_display=300)
    a.panel.debounce = 0
    return a


def test_structure_annotation_roundtrip(app):
    s = wiggle_structure()
    t, index = annotations_to_structure(app.canvas.model.shapes, s.image_shape)
    assert index == [0, 1, 2]
    assert [(b.parent, b.parent_vertex) for b in t.branches] == [(None, None), (0, 20), (0, 40)]
    assert np.allclose(t.branches[1].thickness, 1.5)
    assert '"parent": [0, 20]' in structure_to_annotations(s)


def test_clicked_polylines_become_parent_and_child():
    img = np.ones((120, 200, 3), np.float32)
    img[58:63, :] = 0.1
    img[:60, 99:102] = 0.1
    app = BranchingApp(img, max_display=400)
    for p in [(5, 60), (100, 60.2), (195, 60)]:
        click(app.canvas, *p)
    app.canvas.finish()
    click(app.canvas, 100.3, 60.4)  # snaps to vertex 1 of the first polyline
    click(app.canvas, 100, 5)
    app.canvas.finish()
    s = app.example_structure()
    assert len(s.branches) == 2 and (s.branches[1].parent, s.branches[1].parent_vertex) == (0, 1)
    # the paper's input step: resampling at h and thickness by maximum-gradient search
    r = app.refine()
    steps = np.hypot(*np.diff(r.branches[0].points, axis=0).T)
    assert np.allclose(steps[:-1], app.params.h, atol=0.05)
    assert abs(np.median(r.branches[0].thickness) - 2.5) < 0.8
    assert abs(np.median(r.branches[1].thickness[3:]) - 1.5) < 0.8
    assert np.allclose(r.branches[1].points[0], r.branches[0].points[r.branches[1].parent_vertex])
    assert app.canvas.model.can_undo


def test_synthesize_updates_view_histograms_and_branch_picker(app):
    res = app.synthesize()
    assert res.structure.n_vertices > 20
    assert app.branch_pick.max == len(res.structure.branches) - 1
    assert len(app.view.children) >= 1
    d_angle = app.hist_angle.comparison.distances[1]
    assert d_angle == pytest.approx(res.histogram_distances()["angle"], rel=1e-6)
    assert "vertices" in app.info.value


def test_sliders_resynthesize_with_the_new_parameters(app):
    app.synthesize()
    first = app.result.structure.to_json()
    app.panel.controls["max_generations"].value = 0
    assert app.result.structure.to_json() != first
    assert all(b.parent is None for b in app.result.structure.branches)
    app.seed.value = 5
    assert app.result.diagnostics["n_branches"] == len(app.result.structure.branches)


def test_same_seed_same_structure(app):
    a = app.synthesize().structure.to_json()
    b = app.synthesize().structure.to_json()
    assert a == b


def test_extend_and_delete_output_branch(app):
    app.synthesize()
    s = app.result.structure
    i = int(np.argmax([len(b.points) for b in s.branches]))
    before = len(s.branches[i].points)
    res = app.extend(i, 4)
    assert len(app.result.structure.branches[i].points) == before + res.diagnostics["added_vertices"]
    n = len(app.result.structure.branches)
    app.delete_output_branch(0)
    assert len(app.result.structure.branches) < n


def test_delete_selected_subbranch_in_the_example(app):
    app.canvas.mode = "edit"
    click(app.canvas, *app.canvas.model.shapes[1].points[5])
    assert app.canvas.selected == (1, 5)
    out = app.delete_selected_subbranch()
    assert len(out.branches) == 2 and app.example_structure().branches[1].parent_vertex == 40
    app.canvas.selected = (0, 3)
    assert app.delete_selected_subbranch().branches == []


def test_guidance_stroke_is_used(app):
    assert app.guidance() is None
    app.canvas.model.add_shape("stroke", [(10, 180), (150, 150), (290, 180)])
    g = app.guidance()
    assert g is not None and g.map[180, 10] < 0.05
    s = app.example_structure()
    assert len(s.branches) == 3  # strokes are not branches
    app.clear_guidance()
    assert app.guidance() is None and len(app.example_structure().branches) == 3


def test_buttons_show_errors_and_stay_alive():
    app = BranchingApp(np.ones((100, 150, 3), np.float32))
    app.buttons["extend"].click()
    assert "synthesize a structure first" in app.errors.value
    app.buttons["synthesize"].click()
    assert "empty" in app.errors.value
    app.buttons["delete"].click()
    assert "select a vertex" in app.errors.value
    with pytest.raises(ValueError, match="outside"):
        app.set_structure(wiggle_structure())  # drawn for a 300 x 200 image


def test_extract_button_on_a_drawn_tree():
    img = np.ones((120, 200), np.float32)
    img[58:65, 10:190] = 0
    img[10:60, 99:102] = 0
    app = BranchingApp(img)
    app.buttons["extract"].click()
    assert app.errors.last_error is None
    s = app.example_structure()
    assert len(s.branches) == 2 and s.branches[1].parent == 0


def test_render_image_button(app):
    app.synthesize()
    app.image_panel.controls["flatten_shading"].value = 0.05
    app.buttons["render"].click()
    assert app.errors.last_error is None
    assert app.image_result is not None and app.image_result.image.shape[:2] == (200, 300)
    assert app.progress.bar.value == 1.0
    assert app.image_result.timings["total"] > 0
    assert f"{app.image_result.timings['total']:.1f} s" in app.progress.text.value


def test_render_image_failure_shows_as_a_failure(app, monkeypatch):
    import branchnb.widgets.branching as mod

    app.synthesize()

    def broken(*args, progress=None, **kwargs):
        progress(0.3, "fragments")
        raise ValueError("image is float with values in [-1.191, 1.765]")

    monkeypatch.setattr(mod, "synthesize_image", broken)
    app.shell.click("render image")
    assert "render image failed" in app.errors.value and "-1.191" in app.errors.last_error
    assert app.progress.text.value.startswith("failed") and app.progress.bar.bar_style == "danger"
    assert app.progress.text.value != "starting"
    assert not app.buttons["synthesize"].disabled  # the busy state ended


def test_info_line_counts_what_is_shown_after_delete(app):
    app.synthesize()
    app.delete_output_branch(len(app.result.structure.branches) - 1)
    s = app.result.structure
    assert f"{len(s.branches)} branches, {s.n_vertices} vertices" in app.info.value


def test_parameters_panel_is_honest_and_labelled(app):
    from branchnb.branching import ImageSynthesisParams, SynthesisParams

    assert app.panel.values == SynthesisParams() and app.image_panel.values == ImageSynthesisParams()
    assert "history length" in app.panel.rows["k"].label.value
    assert app.panel.rows["k"].label.tooltip.startswith("history")
    assert type(app.panel.controls["max_total_length"]).__name__ == "FloatLogSlider"


def test_render_image_runs_in_the_background_and_cancel_stops_it(app, monkeypatch):
    import threading

    import branchnb.widgets.branching as mod

    app.synthesize()
    started = threading.Event()

    def slow(*args, progress=None, **kwargs):
        started.set()
        for i in range(500):
            progress(i / 500, "fragments")
            threading.Event().wait(0.01)
        raise AssertionError("not cancelled")

    monkeypatch.setattr(mod, "synthesize_image", slow)
    app.shell.background = True
    app.shell.click("render image")
    assert started.wait(10) and app.buttons["synthesize"].disabled
    assert app.shell.cancel_button.layout.visibility == "visible"
    app.shell.cancel()
    assert app.shell.wait(10)
    assert "cancelled" in app.errors.text and app.errors.last_error is None
    assert app.progress.text.value == "cancelled" and not app.buttons["synthesize"].disabled


def _map_example():
    """A textured land with a flat sea on the right; a river drains into the sea."""
    rng = np.random.default_rng(0)
    h, w = 120, 200
    img = np.empty((h, w, 3), np.float32)
    img[:] = 0.55 + 0.1 * rng.random((h, w, 1))
    img[:, 130:] = (0.2, 0.4, 0.8)
    t = np.linspace(0, 1, 60)
    trunk = np.c_[128 - 110 * t, 60 + 20 * np.sin(5 * t)]
    s = Structure([Branch(trunk, 2.0)], image_shape=(h, w))
    u = np.linspace(0, 1, 20)[:, None]
    s.add_branch(trunk[20] + u * np.array([-40, -30]), 1.5, parent=0, parent_vertex=20)
    return img, s


def test_synthesis_grows_in_the_example_domain_not_the_sea():
    img, s = _map_example()
    app = BranchingApp(img, structure=s)
    dom = app.domain()
    assert dom[:, :125].all() and not dom[:, 135:].any()
    for seed in (0, 1, 2):
        app.seed.value = seed
        res = app.synthesize()
        assert app._model.domain is not None and np.array_equal(app._model.domain, dom)
        pts = np.round(np.concatenate([b.points for b in res.structure.branches])).astype(int)
        pts = np.clip(pts, 0, [img.shape[1] - 1, img.shape[0] - 1])
        assert dom[pts[:, 1], pts[:, 0]].mean() > 0.98
    assert "coverage" in app.info.value


def test_annotation_conversion_lives_in_core_and_batch_needs_no_widgets(tmp_path):
    import json
    import subprocess
    import sys

    from branchnb.core import annotations

    assert annotations_to_structure is annotations.annotations_to_structure
    assert structure_to_annotations is annotations.structure_to_annotations
    s = wiggle_structure()
    doc = json.loads(structure_to_annotations(s))
    t = annotations.structure_from_annotation_json(doc, s.image_shape)
    assert [(b.parent, b.parent_vertex) for b in t.branches] == [(None, None), (0, 20), (0, 40)]
    assert all(np.array_equal(a.points, b.points) for a, b in zip(s.branches, t.branches))
    bad = {"shapes": [{"kind": "polyline", "points": [[0, 0], [float("nan"), 1]]}]}
    with pytest.raises(ValueError, match=r"shapes\[0\]\.points"):
        annotations.structure_from_annotation_json(bad)
    with pytest.raises(ValueError, match="radii"):
        annotations.annotations_to_structure([{"kind": "polyline", "points": [[0, 0], [1, 1]],
                                               "radii": [1.0]}])
    with pytest.raises(ValueError, match="shapes"):
        annotations.structure_from_annotation_json('{"branches": []}')
    path = tmp_path / "example.json"
    path.write_text(json.dumps(doc), encoding="utf-8")
    code = ("import sys\nfrom pathlib import Path\nfrom branchnb.batch._builtin import _read_example\n"
            f"s = _read_example(Path({str(path)!r}), (200, 300))\n"
            "assert len(s.branches) == 3, s\nassert 'ipywidgets' not in sys.modules\n")
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)


def test_slider_shows_the_new_skeleton_growing_then_the_result(app):
    from branchnb.branching import synthesize_structure

    app.synthesize()
    old = app.result.structure
    app.preview_first = app.preview_every = 0.0  # a partial skeleton after every step
    shown = []
    show = app._show_partial

    def spy(growth):
        show(growth)
        shown.append((growth.attempt, app.partial, app.view.title_texts[0]))

    app._show_partial = spy
    app.panel.controls["c"].value = 4
    p = app.params
    assert p.c == 4
    script = synthesize_structure(app._fitted(p), p, rng=int(app.seed.value), shape=app.image_shape)
    assert app.result.structure.to_json() == script.structure.to_json()  # the final result is a script's
    assert app.partial is None and "growing" not in app.view.title_texts[0]
    assert shown and all("growing with the new parameters" in t for _, _, t in shown)
    final_attempt = script.diagnostics["attempts"]
    mine = [s for a, s, _ in shown if a == final_attempt]
    assert mine
    for s in mine:  # each preview is the new synthesis, partly grown
        assert s.n_vertices <= script.structure.n_vertices
        for a, b in zip(s.branches, script.structure.branches):
            assert np.array_equal(a.points, b.points[: len(a.points)])

    def prefix_of_old(s):
        return all(len(a.points) <= len(b.points) and np.array_equal(a.points, b.points[: len(a.points)])
                   for a, b in zip(s.branches, old.branches)) and len(s.branches) <= len(old.branches)

    assert not prefix_of_old(mine[-1])  # not the old result: c changed the growth


def test_a_newer_slider_move_supersedes_a_growing_synthesis(app):
    from branchnb.branching import synthesize_structure

    app.synthesize()
    app.shell.background = True  # as in a kernel: re-synthesis in the background, latest wins
    app.panel.controls["c"].value = 3
    app.panel.controls["c"].value = 4
    assert app.shell.wait_live(60)
    p = app.params
    script = synthesize_structure(app._fitted(p), p, rng=int(app.seed.value), shape=app.image_shape)
    assert p.c == 4 and app.result.structure.to_json() == script.structure.to_json()
    assert app.errors.last_error is None and app.partial is None
    assert "growing" not in app.view.title_texts[0]


def _slowed(mod, monkeypatch, pause: float):
    """synthesize_structure with a pause at every Markov step (a big example, on a slow machine)."""
    import threading

    real = mod.synthesize_structure

    def slow(*args, progress=None, **kwargs):
        def watch(growth):
            threading.Event().wait(pause)
            if progress is not None:
                progress(growth)
        return real(*args, progress=watch, **kwargs)

    monkeypatch.setattr(mod, "synthesize_structure", slow)


def test_synthesize_button_grows_in_the_background_with_previews(app, monkeypatch):
    import branchnb.widgets.branching as mod

    _slowed(mod, monkeypatch, 0.01)
    shown = []
    orig = app._show_partial
    monkeypatch.setattr(app, "_show_partial", lambda g: (shown.append(g.n_branches), orig(g)))
    app.preview_first, app.preview_every = 0.05, 0.05
    app.shell.background = True
    app.shell.click("synthesize")
    assert app.buttons["synthesize"].disabled  # busy while it grows
    assert app.shell.wait(60)
    assert app.errors.last_error is None and app.result is not None
    assert len(shown) >= 2 and app.partial is None  # previews while growing, then the result
    assert "synthesize" in app.errors.text and not app.buttons["synthesize"].disabled


def test_synthesize_button_cancel_stops_the_growth(app, monkeypatch):
    import threading

    import branchnb.widgets.branching as mod

    _slowed(mod, monkeypatch, 0.05)
    grew = threading.Event()
    orig = app._show_partial
    monkeypatch.setattr(app, "_show_partial", lambda g: (grew.set(), orig(g)))
    app.preview_first = 0.0
    app.shell.background = True
    app.shell.click("synthesize")
    assert grew.wait(30)
    assert app.shell.cancel_button.layout.visibility == "visible"
    app.shell.cancel()
    assert app.shell.wait(30)
    assert "cancelled" in app.errors.text and app.errors.last_error is None
    assert app.result is None and not app.buttons["synthesize"].disabled


def test_cancel_takes_the_growing_skeleton_off_and_shows_the_last_result(app, monkeypatch):
    # Found in the browser (widgets23): after "cancel" the view kept the cancelled skeleton,
    # titled "growing: 68 branches so far (the finished structure follows)" - nothing followed.
    import threading

    import branchnb.widgets.branching as mod

    app.synthesize()
    before = app.result.structure.to_json()
    shown_before = app.view.title_texts[0]
    _slowed(mod, monkeypatch, 0.05)
    grew = threading.Event()
    orig = app._show_partial
    monkeypatch.setattr(app, "_show_partial", lambda g: (orig(g), grew.set()))
    app.preview_first = 0.0
    app.shell.background = True
    app.shell.click("synthesize")
    assert grew.wait(30) and "growing" in app.view.title_texts[0]
    app.shell.cancel()
    assert app.shell.wait(30)
    assert "cancelled" in app.errors.text and app.partial is None
    assert app.view.title_texts[0].startswith("synthesized structure") and "growing" not in app.info.value
    assert app.view.title_texts[0] == shown_before and app.result.structure.to_json() == before


def test_first_synthesis_says_it_fits_the_model(app, monkeypatch):
    # Found in the browser (widgets23): the first "synthesize" of a 360 px retina spent 4.4 s fitting
    # (domain and model) under a bare "computing synthesize ..." before its first preview.
    texts = []
    real = app.shell.progress
    monkeypatch.setattr(app.shell, "progress", lambda f, t="": (texts.append(t), real(f, t)))
    app._resynthesize(fresh=True)
    fit = [t for t in texts if t.startswith("fitting")]
    # every fitting step is named before the growth starts (widgets25: the domain, then fit_model's steps)
    assert texts[: len(fit)] == fit and len(fit) >= 4
    assert any("furcation" in t for t in fit) and any("branches live" in t for t in fit)
    texts.clear()
    app._resynthesize(fresh=True)  # the model is kept: straight to growing
    assert texts and "fitting" not in " ".join(texts)
    app.auto.value = False
    app.panel.controls["k"].value = app.params.k + 2  # the model depends on k: fitted again
    texts.clear()
    app._resynthesize(fresh=True)
    assert texts[0].startswith("fitting the model to the example")
    assert not any("branches live" in t for t in texts)  # the domain is kept


def test_fit_shows_the_example_at_once_and_cancels_between_steps(app, monkeypatch):
    # widgets25: the first "synthesize" showed nothing but a spinner for the 3-4 s of the fit;
    # now the example's structure over its domain, and "cancel" stops before the furcation SVM.
    from branchnb.widgets.feedback import Cancelled

    seen = []

    def progress(fraction, text=""):
        seen.append((text, app.view.title_texts[:1], [im.value for im in app.view.images]))
        if "furcation" in text:
            raise Cancelled("cancelled by the test")

    monkeypatch.setattr(app.shell, "progress", progress)
    with pytest.raises(Cancelled):
        app._resynthesize(fresh=True)
    shown = [(t, title) for t, title, imgs in seen if imgs and title and title[0].startswith("the example")]
    assert shown, [s[:2] for s in seen]
    assert seen[0][1][0].startswith("the example")  # already before the domain is looked for
    assert any("grey = outside its domain" in title[0] for _, title in shown)
    assert app._model is None and app.result is None  # stopped inside the fit
    assert app.view.images == [] or app.view.title_texts == []  # the example preview was taken off
    # the picture is the example: dark generation-coloured lines on white, 3 branches in the title
    assert "3 branches" in shown[0][1][0]


def test_partial_skeletons_are_quick_sketches_at_the_view_width(monkeypatch):
    # widgets25: a partial skeleton was rasterised at the image's full size with per-vertex tapers
    # (25-60 ms under load of a first preview's 200 ms budget); now a sketch at the view's width.
    import branchnb.widgets.branching as mod

    img = np.ones((400, 600, 3), np.float32)
    t = np.linspace(0, 1, 120)
    s = Structure([Branch(np.c_[40 + 520 * t, 200 + 40 * np.sin(9 * t)], 3.0)], image_shape=(400, 600))
    a = BranchingApp(img, structure=s, display=200)
    a.synthesize()
    full = []
    real = mod.draw_polylines
    monkeypatch.setattr(mod, "draw_polylines", lambda *x, **k: (full.append(1), real(*x, **k))[1])
    shapes = []
    show = a._show_partial

    def spy(growth):
        show(growth)
        shapes.append(a.view.images[0].value)

    a._show_partial = spy
    a.preview_first = a.preview_every = 0.0
    a._grow_with_previews(False)
    assert shapes
    import cv2
    for png in shapes:
        got = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_UNCHANGED)
        assert max(got.shape[:2]) <= 200 and got.shape[1] == 200  # reduced to the view's width
    assert PREVIEW_FIRST <= 0.05


def test_resynthesis_reuses_the_domain_frame(app, monkeypatch):
    # widgets25: every re-synthesis computed the domain's boundary frame (an EDT) and the example's
    # angles again before its first step: 115-122 ms to the first partial skeleton, now ~40 ms.
    import branchnb.branching.roots as roots

    app.synthesize()
    calls = []
    real = roots._boundary_frame
    monkeypatch.setattr(roots, "_boundary_frame", lambda d: (calls.append(1), real(d))[1])
    model = app._fitted(app.params)
    angles = []
    real_angles = type(model.example).angles
    monkeypatch.setattr(type(model.example), "angles",
                        lambda self: (angles.append(self is model.example), real_angles(self))[1])
    from branchnb.branching import synthesize_structure

    for seed in (1, 2):
        synthesize_structure(model, app.params, rng=seed, shape=app.image_shape)
    assert calls == [] and not any(angles)


def test_slider_updates_convert_the_example_once_per_change(app, monkeypatch):
    # widgets23: every slider move converted the canvas' polylines to a structure and JSON again
    # (60-160 ms of a loaded machine's first-preview budget); now once per annotation change.
    import branchnb.widgets.branching as mod

    calls = []
    real = mod.annotations_to_structure
    monkeypatch.setattr(mod, "annotations_to_structure", lambda *a, **k: (calls.append(1), real(*a, **k))[1])
    app.synthesize()
    n = len(calls)
    app.synthesize()
    first = app.result
    app.panel.controls["c"].value = app.params.c + 1  # re-synthesizes
    assert len(calls) == n and app.result is not first
    # an edit of the example is seen at once: the model is fitted to the new example
    v0 = app.result.example.n_vertices
    app.canvas.model.remove_shape(len(app.canvas.model) - 1)
    app.synthesize()
    assert len(calls) == n + 1 and app.result.example.n_vertices < v0
    assert app._example_and_json()[1] == app.example_structure().to_json()
