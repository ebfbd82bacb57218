"""analyze says when a layer scribbled as a structure comes out non-structural, and when a blade holds a shadow.

Procedural leaves with known veins: their true vein layer (scribbled or
given as a mask) stands out from the blade on every exemplar and gives no
warning; the same layer given on the same leaves with their veins painted
out (a vein layer on plain blade) gives a :class:`NonStructuralLayerWarning`
naming the layer and its lambda.
"""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import branchnb.leaves as leaves
from branchnb.leaves import (
    Layer,
    LayerSet,
    LeafAnalysisWarning,
    NonStructuralLayerWarning,
    ShadowAsLeafWarning,
    analyze,
    is_structural,
    leaf_exemplar,
    leaf_family,
    shadow_share,
    simulate_scribbles,
)
from branchnb.leaves._measure_structural import plain_blade

ROOT = Path(__file__).resolve().parents[1]


def _analyse(exemplars, layers):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        a = analyze(exemplars, 0, layers)
    return a, [w for w in caught if issubclass(w.category, LeafAnalysisWarning)]


@pytest.mark.parametrize("kind,palette", [("lobed", "green"), ("trilobed", "autumn"), ("elliptic", "green"),
                                          ("fan", "autumn")])
def test_true_veins_are_structural(kind, palette):
    family = leaf_family(3, size=192, kind=kind, palette=palette, rng=3)
    a, caught = _analyse(family, {"veins": family[0].layers["veins"]})
    veins = a.layer("veins")
    assert caught == []
    assert veins.lam < 0.05  # the paper's rule alone would call these thin veins non-structural
    assert veins.standout is not None and min(veins.standout) >= 1.0
    assert is_structural(veins)


@pytest.mark.parametrize("kind,given", [("lobed", "mask"), ("elliptic", "scribbles"), ("trilobed", "mask")])
def test_vein_layer_on_plain_blade_warns(kind, given):
    family = leaf_family(3, size=160 if kind == "trilobed" else 192, kind=kind, rng=3)
    plain = [plain_blade(leaf) for leaf in family]
    veins = family[0].layers["veins"]
    layers = {"veins": veins} if given == "mask" else \
        LayerSet([Layer("veins", "#d62728", 0, simulate_scribbles(veins, 10, length=12, rng=0))])
    with pytest.warns(NonStructuralLayerWarning, match=r"'veins' was scribbled as thin lines .*λ = \d\.\d{3}"):
        a = analyze(plain, 0, layers)
    x = a.layer("veins")
    assert not is_structural(x)
    assert float(np.median(x.standout)) < 0.3
    assert any("non-structural" in w for w in leaves.layer_warnings(a))


def test_spots_are_not_judged_as_lines():
    from types import SimpleNamespace as NS

    from branchnb.leaves import Scribble
    from branchnb.leaves.analysis import scribbled_as_lines
    dabs = [Scribble([(40, 40)], 4.0), Scribble([(60, 30), (63, 31)], 3.0)]
    strokes = [Scribble([(10, 10), (40, 12), (70, 30)], 1.0), Scribble([(20, 50), (22, 52)], 1.0)]
    a = NS(layer_set=LayerSet([Layer("spots", "#1f77b4", 0, dabs), Layer("veins", "#d62728", 1, strokes)]),
           layers=[NS(name="spots", snapped=None), NS(name="veins", snapped=None)])
    assert not scribbled_as_lines(a, "spots") and scribbled_as_lines(a, "veins")


def _with_drop_shadow(leaf, offset=5, grey=0.62):
    """The leaf's RGBA with a grey drop shadow (alpha 1) ``offset`` px down and right of it."""
    img = leaf.image.copy()
    shifted = np.roll(np.roll(leaf.blade, offset, 0), offset, 1) & ~leaf.blade
    img[shifted] = (grey, grey, grey, 1.0)
    return img, leaf.blade | shifted


def test_shadow_share_sees_a_drop_shadow():
    leaf = leaf_family(1, size=192, kind="lobed", rng=4)[0]
    assert shadow_share(leaf.image, leaf.blade) == 0.0
    img, blade = _with_drop_shadow(leaf)
    share = shadow_share(img, blade)
    truth = float((blade & ~leaf.blade).sum()) / float(blade.sum())
    assert share >= 0.8 * truth and share <= 1.05 * truth
    a = img[..., 3:]
    cut = leaf_exemplar(img[..., :3] * a + (1 - a))  # the door cuts the shadow: nothing left to warn about
    assert shadow_share(np.dstack([cut.rgb, cut.alpha]), cut.blade) < 0.01


def test_analyze_warns_about_a_shadowed_blade():
    family = leaf_family(3, size=160, kind="trilobed", rng=5)
    img, _ = _with_drop_shadow(family[1])
    with pytest.warns(ShadowAsLeafWarning, match="exemplar #1"):
        analyze([family[0].image, img, family[2].image], 0, {"veins": family[0].layers["veins"]})


def test_warnings_are_one_family_and_the_app_uses_the_same_judgement():
    from branchnb.widgets import leaves as app
    assert issubclass(NonStructuralLayerWarning, LeafAnalysisWarning)
    assert issubclass(ShadowAsLeafWarning, LeafAnalysisWarning) and issubclass(LeafAnalysisWarning, UserWarning)
    assert app.is_structural is leaves.is_structural and app.layer_warnings is leaves.layer_warnings
    assert app.spatial_reach is leaves.spatial_reach
    assert app.MIN_STRUCTURAL_LAMBDA == leaves.MIN_STRUCTURAL_LAMBDA
    assert app.MAX_STRUCTURAL_REACH == leaves.MAX_STRUCTURAL_REACH


def _notebook_code(name: str) -> str:
    nb = json.loads((ROOT / "notebooks" / name).read_text())
    return "\n".join("".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "code")


def test_notebook_04_uses_public_leaves_names():
    code = _notebook_code("04_leaves.ipynb")
    assert not re.search(r"from branchnb\.leaves\.\w+ import", code), "import from branchnb.leaves itself"
    for block in re.findall(r"from branchnb\.leaves import \(?([^)]*?)\)?\n(?!\s)", code + "\n"):
        for name in re.findall(r"\w+", block):
            assert name in leaves.__all__, name
    assert not re.search(r"\bleaves\.\_|\b_lamina\b", code)


@pytest.mark.parametrize("func", [leaves.analyze, leaves.generate])
def test_pipeline_docstrings_use_public_names(func):
    doc = func.__doc__
    assert ">>> " in doc
    assert not re.search(r"from branchnb\.leaves\.\w+ import", doc)
    for block in re.findall(r"from branchnb\.leaves import ([\w, ]+)", doc):
        for name in re.findall(r"\w+", block):
            assert name in leaves.__all__ and not name.startswith("_"), name


def test_leaf_app_reports_the_warning_instead_of_raising_it():
    from branchnb.leaves import Scribble
    from branchnb.widgets.leaves import LeafApp
    family = leaf_family(3, size=160, kind="lobed", rng=3)
    strokes = [Scribble(v, 1.0) for v in family[0].veins[1:7]]  # traced along the (painted-out) main veins
    app = LeafApp([plain_blade(leaf) for leaf in family], layers=LayerSet([Layer("veins", "#d62728", 0, strokes)]))
    with warnings.catch_warnings():
        warnings.simplefilter("error", LeafAnalysisWarning)  # the app shows them in its report, not on stderr
        app.run_analysis()
    assert not is_structural(app.analysis.layer("veins"))
    assert "non-structural" in app.report.value and "λ = " in app.report.value
