"""LeafApp driven from Python: scribbles on the canvas, the layer list, analysis, sliders, generation, errors."""

from __future__ import annotations

import numpy as np
import pytest
from leaves_truth import TrueRegistration

from branchnb.leaves import leaf_family, simulate_scribbles
from branchnb.leaves.analysis import LeafAnalysis, normalise_exemplars
from branchnb.widgets.leaves import LeafApp


def send(canvas, event: str, x: float, y: float):
    top = canvas.canvas._canvases[-1]
    top._handle_frontend_event(top, {"event": event, "x": x, "y": y}, [])


def scribble(canvas, label, points):
    """Pick the label, press, drag through ``points`` (image pixels), release."""
    canvas.mode = "scribble"
    canvas.label = label
    pts = [canvas.image_to_view(*p) for p in points]
    send(canvas, "mouse_down", *pts[0])
    for p in pts[1:]:
        send(canvas, "mouse_move", *p)
    send(canvas, "mouse_up", *pts[-1])


@pytest.fixture(scope="module")
def family():
    fam = leaf_family(3, size=256, rng=4)
    _, blades, offs = normalise_exemplars(fam)
    kps = [leaf.keypoints + np.array(o) for leaf, o in zip(fam, offs)]
    regs = [TrueRegistration(k, kps[0], blades[0].shape) for k in kps]
    return fam, regs, offs


@pytest.fixture
def app(family):
    fam, regs, _ = family
    a = LeafApp(fam, registrations=regs, max_display=256)
    a.induction_panel.debounce = 0
    return a


def _scribble_truth(app, family):
    fam, _, offs = family
    dx, dy = offs[0]
    for name, n, length in (("veins", 10, 20), ("spots", 8, 8)):
        for s in simulate_scribbles(fam[0].layers[name], n, length=length, rng=2):
            scribble(app.canvas, name, s.points + [dx, dy])


def test_layer_list_editing(app):
    assert app.layer_names() == ["veins", "spots"]
    app.name_box.value = "holes"
    app.layer_buttons["add"].click()
    assert app.layer_names() == ["veins", "spots", "holes"] and app.canvas.label == "holes"
    assert list(app.canvas._label_picker.options) == app.layer_names() + ["blade"]
    app.layer_list.value = "holes"
    app.layer_buttons["up"].click()
    assert app.layer_names() == ["veins", "holes", "spots"]
    scribble(app.canvas, "holes", [(120, 120), (126, 124)])
    app.layer_buttons["remove"].click()
    assert app.layer_names() == ["veins", "spots"]
    assert not any(s.label == "holes" for s in app.canvas.model.shapes)
    app.name_box.value = ""
    app.layer_buttons["add"].click()  # no name: an error in the status line, the app keeps working
    assert "name" in app.status.last_error
    app.name_box.value = "veins"
    app.layer_buttons["add"].click()
    assert "exists" in app.status.last_error


def test_errors_show_in_the_status_line_and_the_app_keeps_working(app, family):
    app.shell.click("analyze")  # no scribbles yet
    assert "no scribbles" in app.status.last_error
    app.shell.click("generate")
    assert "analyze" in app.status.last_error
    scribble(app.canvas, "veins", [(1, 1), (6, 1)])  # in the transparent corner
    app.shell.click("analyze")
    assert "outside the leaf" in app.status.last_error
    app.shell.click("clear scribbles")
    _scribble_truth(app, family)
    app.shell.click("analyze")
    assert app.status.last_error is None and app.analysis is not None


def test_analysis_reinduction_and_generation(app, family, monkeypatch):
    _scribble_truth(app, family)
    app.shell.click("analyze")
    assert app.status.last_error is None
    a = app.analysis
    assert [x.name for x in a.layers] == ["veins", "spots"]
    assert "λ" in app.report.value and "veins" in app.report.value
    assert len(app.exemplar_view.images) == 3
    # A thumbnail is drawn at its own size (megapixel exemplars: every step-th pixel), layers and grid on it.
    h, w = a.blades[1].shape
    small, full = app.registration_overlay(1, step=2), app.registration_overlay(1)
    assert small.shape == (-(-h // 2), -(-w // 2), 3) and full.shape == (h, w, 3)
    import cv2
    assert np.abs(small - cv2.resize(full, small.shape[1::-1], interpolation=cv2.INTER_AREA)).mean() < 0.02
    assert app.histograms.comparison is not None and app.histograms.comparison.metric == "emd"
    assert app.histograms.comparison.labels[0] == "user layer"
    regs = a.registrations
    overlay_before = app.exemplar_view.images[1].value
    previews = []
    retune = LeafAnalysis.retune
    monkeypatch.setattr(LeafAnalysis, "retune", lambda self, **kw: previews.append(kw) or retune(self, **kw))
    import branchnb.widgets.leaves as mod
    conversions, lab = [], mod.rgb2lab
    monkeypatch.setattr(mod, "rgb2lab", lambda img: conversions.append(1) or lab(img))
    app.induction_panel.controls["eps"].value = 5.0  # a slider move re-induces only
    app.shell.wait_live()
    # First a preview on the cached colour terms, then the full re-induction.
    assert previews == [{"eps": 5.0}]
    assert conversions == []  # the exemplars on white and their L* are kept between slider moves
    assert overlay_before != app.exemplar_view.images[1].value
    app.induction_panel.controls["neighbourhood"].value = 4  # new colour terms: no preview
    app.shell.wait_live()
    assert len(previews) == 1 and app.analysis.params.neighbourhood == 4
    app.induction_panel.controls["eps"].value = 20.0
    app.shell.wait_live()
    assert app.analysis is not a and app.analysis.registrations is regs
    assert app.analysis.params.eps == 20.0
    # Saved with the results: the scribbles as the API reads them back (LayerSet.from_json).
    assert app._outputs()["layer_scribbles.json"] == app.layer_set().to_json()
    app.hist_layer.value = "spots"
    assert app.histograms.comparison.labels[0] == "user layer"
    app.n_outputs.value = 2
    app.seed.value = 5
    app.shell.click("generate")
    assert app.status.last_error is None and len(app.leaves) == 2
    first = [leaf.image.copy() for leaf in app.leaves]
    app.shell.click("generate")
    assert all(np.array_equal(x, leaf.image) for x, leaf in zip(first, app.leaves))  # same seed, same leaves
    assert len(app.gallery.images) == 2
    # The first leaf is open at its full size below the gallery.
    assert app.open_leaf.value == 0 and len(app.full_view.images) == 1
    assert "leaf #0" in app.full_view.title_texts[0]
    app.open_leaf.value = 1
    assert "leaf #1" in app.full_view.title_texts[0]


def test_layer_json_round_trips_through_the_app():
    """Blade scribbles and each scribble's radius come back exactly (the stored maple layers)."""
    from branchnb import data
    from branchnb.leaves import LayerSet
    text = (data.DATA_DIR / "leaves" / "maple_leaf_01_layers.json").read_text()
    ls = LayerSet.from_json(text)
    assert ls.background and {s.radius for x in ls.layers for s in x.scribbles} != {2.0}
    app = LeafApp([data.load("maple_leaf_01"), data.load("maple_leaf_02")], layers=ls, max_display=256)
    assert app.layer_set().to_json() == ls.to_json()
    assert "blade" in app.canvas.labels
    # The analysis gets the same radii (canvas pixels: shifted by the leaf's offset only).
    canvas_ls = app.scribbled_layers()
    assert [s.radius for s in canvas_ls.background] == [s.radius for s in ls.background]


def test_warnings_name_a_thin_layer_that_came_out_non_structural(app, family):
    from types import SimpleNamespace

    from branchnb.widgets.leaves import layer_warnings
    fake = SimpleNamespace(layers=[SimpleNamespace(name="veins", lam=0.0, delta=1.0, snapped=[None, None, None],
                                                   masks=[1, 1, 1], empty=[2])])
    w = layer_warnings(fake)
    assert len(w) == 2 and "non-structural" in w[0] and "#2" in w[1]
    assert "e+" not in app.report.value


def test_stored_layer_file_loads_through_the_load_button_and_saves_back():
    """The app's "load" takes a stored layer JSON; the saved outputs give the same file back."""
    import json

    from branchnb import data
    text = (data.DATA_DIR / "leaves" / "maple_leaf_01_layers.json").read_text()
    app = LeafApp([data.load("maple_leaf_01"), data.load("maple_leaf_02")], max_display=256)
    app._load_annotations(text)
    assert app.layer_set().to_json() == text
    radii = sorted({s.meta["radius"] for s in app.canvas.model.shapes})
    assert 1.0 in radii and any(s.label == "blade" for s in app.canvas.model.shapes)
    # The app's own annotation file round-trips too.
    other = LeafApp([data.load("maple_leaf_01"), data.load("maple_leaf_02")], max_display=256)
    other._load_annotations(app._annotations())
    assert json.loads(other.layer_set().to_json()) == json.loads(text)
    with pytest.raises(TypeError, match="layers"):
        app.load_layers(3)


def test_analyze_can_be_cancelled(app, family, monkeypatch):
    import threading

    import branchnb.widgets.leaves as mod

    _scribble_truth(app, family)
    started, calls = threading.Event(), []
    real = mod.analyze

    def watched(*args, progress=None, **kwargs):
        def report(f, text=""):
            calls.append(f)
            started.set()
            threading.Event().wait(0.05)
            progress(f, text)
        return real(*args, progress=report, **kwargs)

    monkeypatch.setattr(mod, "analyze", watched)
    app.shell.background = True
    app.shell.click("analyze")
    assert started.wait(30)
    assert app.shell.cancel_button.layout.visibility == "visible"
    n = len(calls)
    app.shell.cancel()
    assert app.shell.wait(30)
    assert "cancelled" in app.status.text and app.status.last_error is None
    assert app.analysis is None and len(calls) <= n + 2  # stopped at its next step


def test_table_and_warning_say_when_a_scribbled_structure_came_out_non_structural():
    from types import SimpleNamespace as NS

    from branchnb.widgets.leaves import _kind_text, is_structural, layer_warnings, spatial_reach
    # The delta criterion: a perfect colour match joins within eps sqrt(ln(delta / lambda)).
    assert spatial_reach(0.5, 0.5 * np.e) == pytest.approx(1.0)
    assert spatial_reach(0.0, 1.0) == np.inf and spatial_reach(1e-3, 5.93e6) > 3
    thin = NS(name="veins", lam=0.3, delta=5.93e6, snapped=[None], masks=[1], empty=[])
    assert not is_structural(thin) and "non-structural" in _kind_text(thin)
    assert "non-structural" in layer_warnings(NS(layers=[thin]))[0]
    placed = NS(name="veins", lam=0.3, delta=0.9, snapped=[None], masks=[1], empty=[])
    assert is_structural(placed) and _kind_text(placed).startswith("structural")
    assert layer_warnings(NS(layers=[placed])) == []
    spots = NS(name="spots", lam=0.0, delta=0.9, snapped=None, masks=[1], empty=[])
    assert _kind_text(spots) == "colour" and layer_warnings(NS(layers=[spots])) == []
