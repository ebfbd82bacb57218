"""DendriteApp driven from Python: callbacks, caching, modes and errors."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from branchnb.dendrite import StylizeParams
from branchnb.dendrite.stylize_params import SMALL_ENDPOINT_POWER
from branchnb.widgets.dendrite import DendriteApp


def _image():
    img = np.ones((60, 60))
    img[15:45, 15:45] = 0.0
    return img


@pytest.fixture
def app():
    return DendriteApp(_image(), params=StylizeParams(n_endpoints=60, stipple_iterations=3))


def test_starts_with_both_metrics_side_by_side(app):
    assert app.errors.last_error is None
    c = app.comparison
    assert c.first.params.metric == "cumulative" and c.second.params.metric == "nonscalar"
    assert c.first.endpoints is c.second.endpoints  # same endpoints
    assert len(app.views.images) == 3
    # histograms: tortuosity and max edge of both metrics on shared bins
    assert app.hist_max_edge.comparison.labels == ["cumulative", "nonscalar"]
    assert (c.stats_second.max_edge <= c.stats_first.max_edge).all()
    assert np.nanmean(c.stats_second.tortuosity) > np.nanmean(c.stats_first.tortuosity)


def test_click_places_the_seed(app):
    app.canvas.handle_mouse_down(*app.canvas.image_to_view(5, 50))
    app.canvas.handle_mouse_up(*app.canvas.image_to_view(5, 50))
    seed = app.comparison.second.seed
    assert np.allclose(seed, (5, 50), atol=0.5)
    root = app.comparison.second.dendrite.points[app.comparison.second.dendrite.parent < 0]
    assert np.allclose(root, np.rint(seed))


def test_slider_changes_reuse_the_cached_plan(app):
    plan = app.comparison.second.plan
    ends = app.comparison.second.endpoints
    before = app.comparison.second.dendrite.radius.max()
    app.panels["stylize"].controls["max_width"].value = 7.0
    assert app.comparison.second.plan is plan
    assert app.comparison.second.dendrite.radius.max() > 1.5 * before
    app.panels["stylize"].controls["metric"].value = "blend"
    assert app.comparison.second.params.metric == "blend"
    assert app.comparison.second.endpoints is ends
    app.panels["stylize"].controls["n_endpoints"].value = 100
    # an image smaller than the lattice gets n_endpoints x (image px per lattice px) ** 1.25
    # (of the lattice_size lattice: a small picture is planned on a smaller one, size_scale)
    k = app.stylizer.size_scale(app.comparison.second.params)
    assert k < 1
    assert len(app.comparison.second.endpoints) == round(100 * k ** SMALL_ENDPOINT_POWER)


@pytest.mark.parametrize("metaphor", ["plain", "vines", "lightning"])
def test_metaphors_and_svg_export(app, metaphor, tmp_path):
    app.metaphor.value = metaphor
    assert app.errors.last_error is None
    path = app.save_svg(tmp_path / "out.svg")
    assert ET.parse(path).getroot().tag.endswith("svg")


def test_tree_modes(app):
    p = app.panels["tree"]
    p.set_values(dataclass_replace(p.values, iterations=2, radius=15.0))
    app.mode = "tree"
    assert app.errors.last_error is None
    d = app.tree.dendrite
    assert d.is_tree() and d.iteration.max() == 2
    assert "blend" in app.schedule.value
    app.layers.value = 2
    assert isinstance(app.tree, list) and len(app.tree) == 2
    pp = app.panels["pareidolia"]
    pp.set_values(dataclass_replace(pp.values, n_endpoints=40, iterations=2))
    app.mode = "pareidolia"
    assert app.errors.last_error is None and app.tree.dendrite.is_tree()


def test_errors_are_shown_and_the_app_survives(app):
    panel = app.panels["stylize"]
    panel.controls["min_width"].value = 5.0
    panel.controls["max_width"].value = 1.0
    assert "max_width" in app.errors.last_error
    panel.controls["max_width"].value = 6.0
    assert app.errors.last_error is None
    with pytest.raises(ValueError, match="nothing rendered"):
        DendriteApp.save_svg(type("X", (), {"rendering": None})(), "x.svg")
    with pytest.raises(ValueError, match="mode"):
        DendriteApp(_image(), mode="oil")


def dataclass_replace(obj, **kw):
    import dataclasses

    return dataclasses.replace(obj, **kw)


def test_only_the_last_click_is_shown_as_the_seed(app):
    for xy in ((5, 50), (30, 10), (50, 40)):
        app.set_seed(xy)
    pts = app.canvas.model.of_kind("point")
    assert len(pts) == 1 and pts[0].points.tolist() == [[50.0, 40.0]]
    assert np.allclose(app.comparison.second.seed, (50, 40), atol=0.5)


def test_slider_move_shows_a_half_resolution_preview_first():
    img = np.ones((120, 120))
    img[30:90, 30:90] = 0.0
    app = DendriteApp(img, params=StylizeParams(n_endpoints=120, stipple_iterations=3))
    app.panels["stylize"].controls["max_width"].value = 6.0
    assert app.preview is not None
    assert app.preview.rendering.image.shape[0] < app.comparison.second.rendering.image.shape[0]
    assert app.errors.last_error is None and app.errors.text.startswith("update: ")


def test_preview_keeps_the_size_adapted_widths_without_the_pruning_rounds():
    from branchnb.dendrite.stylize_params import effective_params, on_lattice
    from branchnb.widgets.dendrite import _scaled

    img = np.ones((200, 200))
    img[50:150, 50:150] = 0.0
    app = DendriteApp(img, max_size=200)
    app.panels["stylize"].controls["max_width"].value = 7.0
    pv = app.preview
    full = app.panels["stylize"].values
    s = app._preview_scale
    # the size adaptation at the lattice_size lattice's scale, its lengths then put on the
    # lattice the (small) preview is planned on
    k = app.preview_stylizer.size_scale(_scaled(full, s))
    want = on_lattice(effective_params(_scaled(full, s), k),
                      app.preview_stylizer.lattice_factor(_scaled(full, s)))
    assert k < 1  # a small picture on a larger lattice: the full run prunes twigs
    # the same floor and widths, but not the twig-dropping rounds (3/4 of the preview's time)
    assert pv.params.output_width == 0.0
    assert (pv.params.min_width, pv.params.max_width) == (want.min_width, want.max_width)
    assert pv.params.n_endpoints == want.n_endpoints
    ink = 1.0 - pv.rendering.image.mean()
    assert 0.05 < ink < 0.6


def test_tree_mode_controls_are_usable(app):
    app.mode = "tree"
    assert app.layers.layout.display is None
    assert app.panels["tree"].reset_button.layout.height == "28px"
    assert app.panels["tree"] in app._panel_box.children


def test_lattice_results_are_shown_at_image_size_and_the_default_seed_is_marked():
    """Importance and plan live on the 512 lattice; what the app draws is in image pixels."""
    img = np.ones((100, 150))
    img[50:85, 100:140] = 0.0  # the important region, off centre
    app = DendriteApp(img, params=StylizeParams(n_endpoints=80, stipple_iterations=2))
    c = app.comparison
    assert c.second.plan.shape != img.shape  # planned on the lattice
    import cv2

    shown = [cv2.imdecode(np.frombuffer(im.value, np.uint8), cv2.IMREAD_UNCHANGED) for im in app.views.images]
    assert [im.shape[:2] for im in shown] == [img.shape] * 3
    seed = c.second.seed
    assert np.allclose(seed, app.stylizer.default_seed(app.params()))
    assert 95 <= seed[0] <= 145 and 45 <= seed[1] <= 90  # in the dark block, in image pixels
    assert "default" in app.status.value
    d = c.second.dendrite
    pts = np.concatenate(d.polylines())
    assert pts[:, 0].max() <= img.shape[1] and pts[:, 1].max() <= img.shape[0]
    # the preview plans the same picture on a lattice half as large, from the same seed
    app._preview()
    assert app._preview_scale == 0.5 and app.preview.params.lattice_size == 256
    assert np.allclose((seed + 0.5) * app._preview_scale - 0.5, app.preview.seed, atol=1.0)
