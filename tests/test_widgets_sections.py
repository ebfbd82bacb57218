"""Every parameter an app shows sits in one of its named sections, with a readable label.

ParamPanel never drops a field: one left out of ``sections`` lands in a last
group titled "other". These tests make that a failure for the apps that
group their parameters, so a field added to a technique's dataclass must be
placed (and labelled) in the app deliberately.
"""

from __future__ import annotations

import dataclasses

import ipywidgets as widgets
import numpy as np
import pytest

from branchnb.branching import Branch, ImageSynthesisParams, Structure, SynthesisParams
from branchnb.dendrite import StylizeParams
from branchnb.dendrite.pareidolia import PareidoliaParams
from branchnb.dendrite.trees import TreeParams
from branchnb.widgets import ParamPanel
from branchnb.widgets import branching as branching_app
from branchnb.widgets import dendrite as dendrite_app


def _panels(widget) -> list[ParamPanel]:
    """Every ParamPanel under ``widget`` (also ones not displayed, e.g. another mode's)."""
    out, todo = [], [widget]
    while todo:
        w = todo.pop()
        if isinstance(w, ParamPanel):
            out.append(w)
            continue
        todo.extend(c for c in getattr(w, "children", ()) if isinstance(c, widgets.Widget))
    return out


def _section_titles(panel: ParamPanel) -> list[str]:
    return [acc.get_title(0) for acc in panel.sections]


def test_param_panel_puts_unsectioned_fields_in_other():
    """The behaviour the app tests rely on: nothing vanishes, the rest goes to "other"."""
    panel = ParamPanel(SynthesisParams, sections=[("markov", ["h", "m", "k"])])
    assert _section_titles(panel) == ["markov", "other"]
    other = [w for w in panel.sections[-1].children[0].children if "bnb-help-box" not in w._dom_classes]
    assert len(other) == len(panel.rows) - 3
    assert {r.box for n, r in panel.rows.items() if n not in ("h", "m", "k")} == set(other)


@pytest.mark.parametrize("sections, labels, cls", [
    (branching_app.SYNTHESIS_SECTIONS, branching_app.SYNTHESIS_LABELS, SynthesisParams),
    (branching_app.IMAGE_SECTIONS, branching_app.IMAGE_LABELS, ImageSynthesisParams),
    (dendrite_app.STYLIZE_SECTIONS, dendrite_app.STYLIZE_LABELS, StylizeParams),
    (dendrite_app.TREE_SECTIONS, dendrite_app.TREE_LABELS, TreeParams),
    (dendrite_app.PAREIDOLIA_SECTIONS, dendrite_app.PAREIDOLIA_LABELS, PareidoliaParams),
])
def test_every_field_is_sectioned_once_and_labelled(sections, labels, cls):
    fields = [f.name for f in dataclasses.fields(cls)]
    placed = [n for _title, names in sections for n in names]
    assert sorted(placed) == sorted(set(placed)), "a field is in two sections"
    assert set(fields) - set(placed) == set(), f"{cls.__name__} fields in no section"
    assert set(placed) - set(fields) == set()
    assert set(fields) - set(labels) == set(), f"{cls.__name__} fields without a readable label"


def _wiggle(shape=(120, 160)) -> Structure:
    t = np.linspace(0, 1, 50)
    trunk = np.c_[10 + 140 * t, 60 + 15 * np.sin(7 * t)]
    return Structure([Branch(trunk, 2.0)], image_shape=shape)


def test_branching_app_panels_have_no_other_section():
    app = branching_app.BranchingApp(np.ones((120, 160, 3), np.float32), structure=_wiggle())
    panels = _panels(app)
    assert {type(p.values) for p in panels} == {SynthesisParams, ImageSynthesisParams}
    for p in panels:
        assert "other" not in _section_titles(p), type(p.values).__name__
    assert app.panel.rows["max_coverage"].exact == 0.0
    assert "0 = example" in app.panel.rows["max_coverage"].label.value


def test_dendrite_app_panels_have_no_other_section():
    img = np.ones((48, 48))
    img[12:36, 12:36] = 0.0
    app = dendrite_app.DendriteApp(img, params=StylizeParams(n_endpoints=40, stipple_iterations=2))
    panels = list(app.panels.values())
    assert {type(p.values) for p in panels} == {StylizeParams, TreeParams, PareidoliaParams}
    for p in panels:
        assert "other" not in _section_titles(p), type(p.values).__name__
