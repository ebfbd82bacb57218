"""DendriteApp: dendritic stylization, trees and pareidolia trees with live sliders.

A thin app over :mod:`branchnb.dendrite`:

* the image in an :class:`AnnotationCanvas`; **click to place the seed**
  (in the tree modes: the trunk base). The last clicked point is used.
* a mode switch: ``stylize`` (the image as a dendrite), ``tree`` (iterative
  growth, optional occlusion layers) and ``pareidolia`` (the image hidden in
  a tree's crown), each with its :class:`ParamPanel` (paper defaults, reset
  button), plus the rendering metaphor and the random seed;
* in ``stylize`` mode: the cumulative and the chosen metric side by side on
  the same endpoints, Dijkstra's visiting order (the paper's contour
  figure), and histograms of per-path tortuosity and per-path maximum edge
  cost; the chosen metric's dendrite is overlaid on the canvas;
* in the tree modes: the tree and the per-iteration metric schedule.

The stylization stages are cached (:class:`~branchnb.dendrite.Stylizer`):
a thickness or metaphor change re-renders only, a metric change re-plans
only, an endpoint change re-stipples. Every callback is guarded: errors are
shown in the app's error area and the app keeps working.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import cv2
import ipywidgets as widgets
import numpy as np

from ..core.image import as_float_image, as_rgb
from ..core.render import draw_polylines
from ..dendrite import (
    StylizeParams,
    Stylizer,
    compare_metrics,
    render_lightning,
    render_plain,
    render_vines,
    visiting_order_image,
)
from ..dendrite.metaphors import METAPHORS
from ..dendrite.pareidolia import PareidoliaParams, pareidolia_tree
from ..dendrite.trees import TreeParams, grow_layers, grow_tree, iteration_metric, render_layers
from .canvas import AnnotationCanvas
from .feedback import ErrorArea
from .histograms import HistogramCompare
from .imageview import ImageView
from .params import ParamPanel

__all__ = ["DendriteApp"]

MODES = ("stylize", "tree", "pareidolia")


def _fit(image, max_size: int) -> np.ndarray:
    img = as_rgb(as_float_image(image, name="image"), name="image")
    h, w = img.shape[:2]
    s = max_size / max(h, w)
    if s < 1:
        img = cv2.resize(img, (max(1, round(w * s)), max(1, round(h * s))),
                         interpolation=cv2.INTER_AREA)
    return np.clip(img, 0, 1).astype(np.float32)


class DendriteApp(widgets.VBox):
    """Interactive dendritic stylization, trees and pareidolia trees.

    Parameters
    ----------
    image : array_like
        Grey or colour image (RGBA is composited over white).
    max_size : int
        The image is downscaled so its long side is at most this (speed).
    params : StylizeParams, optional
        Initial stylization parameters (paper defaults).
    mode : {"stylize", "tree", "pareidolia"}
    display : int
        Display width of each result image (screen pixels).

    Attributes
    ----------
    comparison : MetricComparison or None
        The last stylize-mode result (both metrics).
    tree : GrownTree, list of GrownTree, PareidoliaTree or None
        The last tree-mode result.
    rendering : Rendering or None
        The main picture of the last update (its ``.svg`` is what
        "save SVG" writes).

    Examples
    --------
    >>> img = np.ones((48, 48)); img[12:36, 12:36] = 0.0
    >>> app = DendriteApp(img, params=StylizeParams(n_endpoints=40, stipple_iterations=3))
    >>> app.set_seed((10, 10))
    >>> app.comparison.second.seed.tolist()
    [10.0, 10.0]
    """

    def __init__(self, image, *, max_size: int = 400, params: StylizeParams | None = None,
                 mode: str = "stylize", display: int = 300):
        if mode not in MODES:
            raise ValueError(f"mode must be one of {list(MODES)}, got {mode!r}")
        self.image = _fit(image, int(max_size))
        self.stylizer = Stylizer(self.image)
        self.errors = ErrorArea()
        self.comparison = None
        self.tree = None
        self.rendering = None
        self.seed: np.ndarray | None = None
        g = self.errors.guard

        self.canvas = AnnotationCanvas(self.image, mode="point", modes=("point", "pan"),
                                       max_display=min(480, max(200, int(max_size))))
        self.canvas.model.observe(g(self._on_model))
        self.mode_picker = widgets.ToggleButtons(options=list(MODES), value=mode,
                                                 description="mode")
        self.metaphor = widgets.Dropdown(options=list(METAPHORS), value="plain",
                                         description="metaphor")
        self.rng = widgets.BoundedIntText(value=0, min=0, max=2**31 - 1, description="rng seed",
                                          layout=widgets.Layout(width="180px"))
        self.layers = widgets.IntSlider(value=1, min=1, max=4, description="layers",
                                        tooltip="occlusion: trees sharing one trunk (tree mode)",
                                        continuous_update=False)
        self.svg_path = widgets.Text(value="dendrite.svg", description="SVG file",
                                     layout=widgets.Layout(width="260px"))
        self.svg_button = widgets.Button(description="save SVG", icon="download",
                                         layout=widgets.Layout(width="auto"))
        self.svg_button.on_click(g(lambda _: self.save_svg(self.svg_path.value)))
        self.status = widgets.HTML()

        self.panels = {
            "stylize": ParamPanel(params if params is not None else StylizeParams(),
                                  title="stylization (paper defaults)"),
            "tree": ParamPanel(TreeParams, title="tree growth"),
            "pareidolia": ParamPanel(PareidoliaParams, title="pareidolia tree"),
        }
        for panel in self.panels.values():
            panel.on_change(g(lambda _values: self.update()))
        self.mode_picker.observe(g(self._on_mode), names="value")
        for w in (self.metaphor, self.rng, self.layers):
            w.observe(g(lambda _change: self.update()), names="value")

        self.views = ImageView(width=int(display))
        self.hist_tortuosity = HistogramCompare(bins=16, metric="l1",
                                                title="per-path tortuosity (length / straight)",
                                                width=520, height=150)
        self.hist_max_edge = HistogramCompare(bins=16, metric="l1",
                                              title="per-path maximum edge cost",
                                              width=520, height=150)
        self.schedule = widgets.HTML()
        self._panel_box = widgets.VBox()
        controls = widgets.VBox([
            self.mode_picker,
            widgets.HBox([self.metaphor, self.rng, self.layers]),
            self._panel_box,
            widgets.HBox([self.svg_path, self.svg_button]),
        ], layout=widgets.Layout(width="440px", max_height="640px", overflow="auto"))
        self._stats_box = widgets.VBox([self.hist_tortuosity, self.hist_max_edge])
        super().__init__([
            widgets.HBox([self.canvas, controls]),
            self.status, self.errors, self.views, self.schedule, self._stats_box,
        ])
        g(self._on_mode)(None)

    # -- public API (everything the widgets do, callable from Python) ----------
    @property
    def mode(self) -> str:
        return self.mode_picker.value

    @mode.setter
    def mode(self, value: str) -> None:
        self.mode_picker.value = value

    def params(self):
        """The current parameter dataclass of the active mode."""
        return self.panels[self.mode].values

    def set_seed(self, xy) -> None:
        """Place the seed (trunk base in the tree modes) at image pixel ``(x, y)``."""
        self.canvas.model.add_shape("point", [tuple(map(float, xy))])

    def save_svg(self, path) -> Path:
        """Write the current picture's SVG."""
        if self.rendering is None:
            raise ValueError("nothing rendered yet")
        path = Path(path)
        path.write_text(self.rendering.svg, encoding="utf-8")
        self.status.value = f"wrote {path} ({path.stat().st_size // 1024} kB)"
        return path

    def update(self) -> None:
        """Recompute (cached stages are reused) and redraw."""
        with self.errors.catch():
            if self.mode == "stylize":
                self._update_stylize()
            elif self.mode == "tree":
                self._update_tree()
            else:
                self._update_pareidolia()

    # -- callbacks -------------------------------------------------------------
    def _on_model(self, _event) -> None:
        pts = self.canvas.model.of_kind("point")
        new = None if not pts else pts[-1].points[-1].copy()
        if (new is None) != (self.seed is None) or (new is not None and not np.array_equal(new, self.seed)):
            self.seed = new
            self.update()

    def _on_mode(self, _change) -> None:
        self._panel_box.children = [self.panels[self.mode]]
        tree_mode = self.mode != "stylize"
        self._stats_box.layout.display = "none" if tree_mode else None
        self.schedule.layout.display = None if tree_mode else "none"
        self.layers.layout.display = None if self.mode == "tree" else "none"
        self.update()

    # -- modes ----------------------------------------------------------------------
    def _update_stylize(self) -> None:
        p = self.panels["stylize"].values
        c = compare_metrics(self.stylizer, p, seed=self.seed, rng=int(self.rng.value),
                            metaphor=self.metaphor.value)
        self.comparison = c
        self.rendering = c.second.rendering
        order = visiting_order_image(c.second.plan)
        self.views.update(
            [c.first.rendering.image, c.second.rendering.image, order],
            [f"{c.first.params.metric}", f"{c.second.params.metric}"
             + (f" (a = {p.blend_weight:g})" if c.second.params.metric == "blend" else ""),
             f"visiting order ({c.second.params.metric})"])
        labels = [c.first.params.metric, c.second.params.metric]
        t1, t2 = c.stats_first.tortuosity, c.stats_second.tortuosity
        self.hist_tortuosity.update(t1[np.isfinite(t1)], t2[np.isfinite(t2)], labels=labels)
        self.hist_max_edge.update(c.stats_first.max_edge, c.stats_second.max_edge, labels=labels)
        d = c.second.dendrite
        overlay = draw_polylines(np.zeros((*self.image.shape[:2], 4), np.float32), d.polylines(2),
                                 widths=d.widths(), colors=(0.9, 0.1, 0.1))
        self.canvas.set_overlay(overlay)
        s = c.second.seed
        self.status.value = (
            f"seed ({s[0]:.0f}, {s[1]:.0f}) &nbsp;|&nbsp; {len(c.second.endpoints)} endpoints "
            f"&nbsp;|&nbsp; {d.n_nodes} nodes, {d.n_branches} branches &nbsp;|&nbsp; "
            f"mean tortuosity {np.nanmean(t1):.2f} vs {np.nanmean(t2):.2f}")

    def _tree_render(self, dendrite):
        m = self.metaphor.value
        if m == "vines":
            return render_vines(dendrite, rng=int(self.rng.value))
        if m == "lightning":
            return render_lightning(dendrite)
        return render_plain(dendrite, color=(0.24, 0.16, 0.09), smooth=3)

    def _schedule_html(self, p, radii=None) -> str:
        rows = []
        for i in range(1, p.iterations + 1):
            metric, a = iteration_metric(i, p)
            r = "" if radii is None or i - 1 >= len(radii) or not np.isfinite(radii[i - 1]) \
                else f", R = {radii[i - 1]:.1f} px"
            rows.append(f"{i}: {metric}" + (f" a = {a:.0f}" if metric == "blend" else "") + r)
        return "<b>metric per iteration</b>: " + " &nbsp;|&nbsp; ".join(rows)

    def _update_tree(self) -> None:
        p = self.panels["tree"].values
        h, w = self.image.shape[:2]
        base = self.seed
        rng = int(self.rng.value)
        if self.layers.value > 1:
            trees = grow_layers((h, w), p, layers=int(self.layers.value), rng=rng, base=base)
            self.tree = trees
            self.rendering = render_layers(trees)
            main = trees[-1]
        else:
            main = grow_tree((h, w), p, base=base, rng=rng)
            self.tree = main
            self.rendering = self._tree_render(main.dendrite)
        self.views.update([self.rendering.image], [f"tree, {p.iterations} iterations"])
        self.schedule.value = self._schedule_html(p, main.radii)
        self.canvas.set_overlay(None)
        d = main.dendrite
        self.status.value = (f"{d.n_nodes} nodes, {d.n_branches} branches, endpoints per iteration "
                             f"{[len(e) for e in main.endpoints]}")

    def _update_pareidolia(self) -> None:
        p = self.panels["pareidolia"].values
        t = pareidolia_tree(self.image, p, rng=int(self.rng.value))
        self.tree = t
        m = self.metaphor.value
        self.rendering = t.render() if m == "plain" else self._tree_render(t.dendrite)
        self.views.update([t.image, self.rendering.image], ["image (+ trunk strip)", "pareidolia tree"])
        self.schedule.value = self._schedule_html(
            dataclasses.replace(TreeParams(), iterations=p.iterations, blend_weight=p.blend_weight))
        self.canvas.set_overlay(None)
        self.status.value = (f"{len(t.endpoints_image)} stippled + {len(t.endpoints_random)} random "
                             f"endpoints, {t.dendrite.n_nodes} nodes (the trunk starts below the "
                             "image; the seed click is not used in this mode)")
