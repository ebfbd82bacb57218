"""Benchmarks of the apps' callbacks, timed from Python (what a slider move or a button costs).

Each app row times the callback the widget runs (panel change -> preview
and/or full update, button -> action) against the core call it wraps
(or against the 200 ms preview budget),
timed in the same run: the ratio is the app's overhead (display, PNG
encoding, histograms) on top of the computation. Preview rows compare the
reduced-resolution preview with the 200 ms budget of issue 15. Inputs are
the sample images (retina at 360 px, cameraman at 240 px, a 300 x 120
striped bar, three library trees at 160 px).
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from ..bench import BenchRow

__all__ = ["rows"]

#: The preview budget of issue 15 (seconds from a slider move to a preview).
PREVIEW_BUDGET = 0.2


def _best(fn, repeat: int) -> float:
    best = float("inf")
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def _branching(quick: bool, repeat: int) -> list[BenchRow]:
    import cv2

    from .. import data
    from ..branching import extract_structure, synthesize_structure
    from .branching import PREVIEW_FIRST, BranchingApp

    size = 240 if quick else 360
    img = cv2.resize(data.load("retina_fundus"), (size, size), interpolation=cv2.INTER_AREA)
    app = BranchingApp(img, structure=extract_structure(img))
    app.synthesize()
    values = iter(range(3, 100))

    def slider():  # what moving "c" does (outside a kernel the full update runs at once)
        app.panel.type_value("c", str(2 + next(values) % 4))

    ours = _best(slider, repeat)
    p = app.params
    model = app._fitted(p)
    again = iter(range(3, 100))
    core = _best(lambda: synthesize_structure(model, dataclasses.replace(p, c=2 + next(again) % 4), rng=0,
                                              shape=app.image_shape), repeat)

    # slider move -> the first partial skeleton of the new synthesis on screen (the growing preview)
    shown: list[float] = []
    show = app._show_partial

    def spy(growth):
        show(growth)
        shown.append(time.perf_counter())

    app._show_partial = spy
    firsts = []
    for _ in range(max(1, repeat)):
        shown.clear()
        t0 = time.perf_counter()
        slider()
        if shown:
            firsts.append(shown[0] - t0)
    app._show_partial = show
    first = min(firsts) if firsts else float("nan")
    return [BenchRow(f"BranchingApp slider c -> re-synthesis, retina {size} px", ours,
                     "synthesize_structure alone (same model)", core,
                     "growing previews (partial skeletons) are drawn meanwhile"),
            BenchRow(f"BranchingApp slider c -> first partial skeleton shown, retina {size} px", first,
                     "preview budget (issue 15)", PREVIEW_BUDGET,
                     f"synthesize_structure(progress=...); first after PREVIEW_FIRST = {PREVIEW_FIRST} s")]


def _dendrite(quick: bool, repeat: int) -> list[BenchRow]:
    from .. import data
    from ..dendrite import compare_metrics
    from .dendrite import DendriteApp

    size = 160 if quick else 240
    app = DendriteApp(data.load("camera"), max_size=size)
    widths = iter(np.linspace(3.0, 6.0, 50))
    ours = _best(lambda: app.panels["stylize"].controls["max_width"].__setattr__("value",
                                                                                float(next(widths))),
                 repeat)
    prev = _best(app._preview, repeat)
    p = app.panels["stylize"].values
    core = _best(lambda: compare_metrics(app.stylizer, dataclasses.replace(p, max_width=p.max_width + 0.01),
                                         seed=app.seed, rng=0), repeat)
    return [
        BenchRow(f"DendriteApp slider max_width -> preview + full update, cameraman {size} px", ours,
                 "compare_metrics alone (cached stages)", core, "both metrics, histograms, overlay"),
        BenchRow(f"DendriteApp half-resolution preview, cameraman {size} px", prev,
                 "preview budget (issue 15)", PREVIEW_BUDGET, "render-only change, cached stylizer"),
    ]


def _strokes(quick: bool, repeat: int) -> list[BenchRow]:
    from ..strokes import compose_patches, edit_structure
    from .strokes import PREVIEW_AFTER, StrokeEditApp

    x = np.arange(300)
    bar = np.zeros((120, 300, 4), np.float32)
    bar[45:75, 15:285, 0] = 0.5 + 0.4 * np.sin(x[15:285] / 6.0)
    bar[45:75, 15:285, 1] = np.linspace(0.2, 0.8, 270)
    bar[45:75, 15:285, 2] = 0.3
    bar[45:75, 15:285, 3] = 1.0
    app = StrokeEditApp(bar, target_shape=(200, 300), max_display=280)
    src, tgt = [(25, 60), (150, 60), (275, 60)], [(30, 40), (150, 100), (270, 160)]
    app.add_stroke("source", src)
    app.add_stroke("target", tgt)
    powers = iter([1.25, 1.5, 1.75, 2.0, 2.25, 2.5] * 9)
    ours = _best(lambda: app.panel.type_value("seam_power", str(next(powers))), repeat)
    # slider move -> the first picture sent (the reduced preview when the edit is expected to be slow)
    update, stamps = app.view.update, []
    app.view.update = lambda images, titles=None: (stamps.append(time.perf_counter()), update(images, titles))
    firsts = []
    for _ in range(max(1, repeat)):
        stamps.clear()
        t0 = time.perf_counter()
        app.panel.type_value("seam_power", str(next(powers)))
        firsts.append(stamps[0] - t0)
    del app.view.update
    first = min(firsts)
    compose = _best(lambda: compose_patches(app.patches, dataclasses.replace(app.params,
                                                                              seam_power=next(powers))),
                    repeat)
    prev = _best(app._preview, repeat)
    core = _best(lambda: edit_structure(bar, [np.array(src, float)], [np.array(tgt, float)], app.params,
                                        target_shape=(200, 300)), repeat)
    return [
        BenchRow("StrokeEditApp slider seam_power -> result, 300 x 200 target", ours,
                 "edit_structure alone (fetch + compose)", core,
                 "the app keeps the fetched patches: sampling + composition only"),
        BenchRow("StrokeEditApp slider seam_power -> first picture, 300 x 200 target", first,
                 "preview budget (issue 15)", PREVIEW_BUDGET,
                 f"the result, or the reduced preview when an edit takes > PREVIEW_AFTER = {PREVIEW_AFTER} s"),
        BenchRow("compose_patches alone (seam_power changed), 300 x 200 target", compose,
                 "edit_structure alone (fetch + compose)", core, "stage 2 of edit_structure"),
        BenchRow("StrokeEditApp reduced-size preview (long side 160 px, patches kept)", prev,
                 "preview budget (issue 15)", PREVIEW_BUDGET,
                 "its patches fetched after a slow edit"),
    ]


def _trees(quick: bool, repeat: int) -> list[BenchRow]:
    from ..trees.variations import TreeLibrary, make_variation
    from .trees import TreeVariationsApp

    size = 128 if quick else 160
    lib = TreeLibrary.from_data(["tree_rpg_01", "tree_rpg_03", "tree_rpg_06"], size=size)
    app = TreeVariationsApp(lib, display=200)
    ws = iter(np.linspace(0.2, 0.8, 60))
    ours = _best(lambda: app._on_slider("tree_rpg_01", float(next(ws))), repeat)
    core = _best(lambda: make_variation(lib, app.weights, app.params(), use=app.selected, rng=0), repeat)
    return [BenchRow(f"TreeVariationsApp weight slider -> mix, 2 trees at {size} px", ours,
                     "make_variation alone", core, "+ histograms of 2 samples, 2 PNGs")]


def rows(quick: bool = False) -> list[BenchRow]:
    repeat = 1 if quick else 3
    out: list[BenchRow] = []
    for suite in (_branching, _dendrite, _strokes, _trees):
        out.extend(suite(quick, repeat))
    return out
