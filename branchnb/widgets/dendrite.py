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
only, an endpoint change re-stipples. A slider move in ``stylize`` mode
first shows a preview computed at half resolution (its own cached
stylizer, sizes and endpoint count scaled), then the full update follows
(in the background inside a kernel; a newer move supersedes it). The
layout, busy state and status line are the kit's
:class:`~branchnb.widgets.shell.AppShell`.
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
from ..dendrite.stylize_params import effective_params
from ..dendrite.trees import TreeParams, grow_layers, grow_tree, iteration_metric, render_layers
from .canvas import AnnotationCanvas
from .files import canvases_json, load_canvases
from .histograms import HistogramCompare
from .imageview import ImageView
from .params import ParamPanel
from .shell import AppShell

__all__ = ["DendriteApp"]

MODES = ("stylize", "tree", "pareidolia")

#: Parameter groups and readable labels (paper symbols in the second place).
STYLIZE_SECTIONS = [
    ("importance map", ["lattice_size", "intensity_weight", "gradient_weight", "sigma"]),
    ("endpoints (stippling)", ["n_endpoints", "endpoint_gamma", "endpoint_threshold", "endpoint_floor",
                               "stipple_iterations"]),
    ("node weights and path metric", ["cost_weight", "epsilon", "noise", "metric", "blend_weight",
                                      "break_ties"]),
    ("thickness", ["thickness", "window", "contrast", "hierarchy", "tone", "tone_sigma", "edges",
                   "min_width", "max_width", "output_width"]),
]
STYLIZE_LABELS = {
    "intensity_weight": ("darkness weight", "w_I"), "gradient_weight": ("gradient weight", "w_G"),
    "sigma": ("gradient smoothing", "\u03c3"), "n_endpoints": ("endpoints", "N"),
    "endpoint_gamma": ("density exponent", "\u03b3"), "endpoint_floor": ("density floor", ""),
    "stipple_iterations": ("Lloyd iterations", ""), "lattice_size": ("lattice (0 = image)", ""),
    "endpoint_threshold": ("empty-paper level", ""), "break_ties": ("re-plan large ties", ""),
    "hierarchy": ("trunk hierarchy", ""), "tone": ("match tone", ""), "tone_sigma": ("tone scale", ""),
    "cost_weight": ("importance cost", "c"),
    "epsilon": ("weight offset", "\u03b5"), "noise": ("random weight", ""),
    "metric": ("path metric", ""), "blend_weight": ("max-edge weight", "a"),
    "thickness": ("thickness from", ""), "window": ("rolling window", ""),
    "contrast": ("contrast exponent", ""), "min_width": ("min width (lattice)", ""),
    "max_width": ("max width (lattice)", ""), "edges": ("edge emphasis", ""),
    "output_width": ("min width (image px)", ""),
}
TREE_SECTIONS = [
    ("growth", ["iterations", "trunk_endpoints", "endpoint_growth", "radius", "radius_decay",
                "min_distance"]),
    ("metric per iteration", ["blend_weight", "mix_power", "noise", "epsilon"]),
    ("widths", ["tip_width", "increment", "pipe", "scale_lengths"]),
    ("crown shape", ["fork_jitter", "trunk_share", "crown_top", "crown_bottom", "crown_width"]),
]
TREE_LABELS = {
    "iterations": ("iterations", "n"), "trunk_endpoints": ("trunk endpoints", ""),
    "endpoint_growth": ("endpoint growth", "\u00d7"), "radius": ("rejection radius", "R\u2082"),
    "radius_decay": ("radius decay", ""), "min_distance": ("min distance / R", ""),
    "blend_weight": ("blend weight", "a"), "mix_power": ("metric mix power", ""),
    "noise": ("random weight", ""), "epsilon": ("weight offset", "\u03b5"),
    "tip_width": ("twig width (px)", ""), "increment": ("width increment", ""),
    "pipe": ("pipe model", ""), "fork_jitter": ("fork jitter", ""), "trunk_share": ("trunk share", ""),
    "crown_top": ("crown top", ""), "crown_bottom": ("crown bottom", ""),
    "crown_width": ("crown width", ""), "scale_lengths": ("px of 512 x 512", ""),
}
PAREIDOLIA_SECTIONS = [
    ("crown and endpoints", ["side", "crown", "crown_blur", "n_endpoints", "random_ratio",
                             "endpoint_gamma"]),
    ("lattice and node weights", ["lattice_size", "max_upscale", "max_lattice", "noise_image", "noise_random",
                                  "cost_weight", "epsilon", "intensity_weight", "gradient_weight"]),
    ("growth", ["iterations", "trunk_endpoints", "blend_weight", "bottleneck", "trunk_height", "rise",
                "min_twig"]),
    ("widths", ["thickness", "window", "emphasis", "tone", "tip_width", "increment", "pipe", "max_width",
                "limb_length", "limb_width", "taper", "slim", "tone_sigma", "contrast", "refine", "cover",
                "features"]),
]
PAREIDOLIA_LABELS = {
    "side": ("image side", ""), "n_endpoints": ("image endpoints", "N"),
    "random_ratio": ("random endpoints / N", ""), "endpoint_gamma": ("density exponent", "\u03b3"),
    "noise_image": ("noise, image side", ""), "noise_random": ("noise, far side", ""),
    "cost_weight": ("importance cost", "c"), "epsilon": ("weight offset", "\u03b5"),
    "intensity_weight": ("darkness weight", "w_I"), "gradient_weight": ("gradient weight", "w_G"),
    "iterations": ("iterations", "n"), "trunk_endpoints": ("main limbs", ""),
    "blend_weight": ("blend weight", "a"), "trunk_height": ("trunk strip", ""),
    "thickness": ("thickness from", ""), "window": ("rolling window", ""),
    "emphasis": ("emphasis (px)", ""), "tip_width": ("twig width (px)", ""),
    "increment": ("width increment", ""), "pipe": ("pipe model", ""),
    "crown": ("crown shape", ""), "crown_blur": ("crown smoothing", ""),
    "lattice_size": ("lattice (0 = image)", ""), "tone": ("match tone", ""),
    "max_width": ("max crown width (px)", ""), "limb_length": ("limb thinning length", ""),
    "limb_width": ("limb end width (px)", ""),
    "taper": ("twig taper length", ""), "slim": ("slim twig ends", ""), "tone_sigma": ("tone scale", ""),
    "max_upscale": ("max image px / lattice px", ""), "max_lattice": ("largest lattice", ""),
    "contrast": ("crown contrast stretch", ""), "refine": ("tone passes at output size", ""),
    "rise": ("twigs grow up", ""), "cover": ("dark-region ink cover", ""),
    "bottleneck": ("blend bottleneck", "M"), "min_twig": ("shortest twig (px)", ""),
    "features": ("solid small dark features", ""),
}


def _fit(image, max_size: int) -> np.ndarray:
    img = as_rgb(as_float_image(image, name="image"), name="image")
    h, w = img.shape[:2]
    s = max_size / max(h, w)
    if s < 1:
        img = cv2.resize(img, (max(1, round(w * s)), max(1, round(h * s))),
                         interpolation=cv2.INTER_AREA)
    return np.clip(img, 0, 1).astype(np.float32)


def _ring(center, radius: float) -> np.ndarray:
    t = np.linspace(0, 2 * np.pi, 33)
    return np.c_[center[0] + radius * np.cos(t), center[1] + radius * np.sin(t)]


def _scaled(p: StylizeParams, s: float) -> StylizeParams:
    """The same stylization for an image scaled by ``s``, planned on a lattice ``s`` times as large.

    Lengths are in lattice pixels, so they scale with the lattice (its
    size times ``s``, or the image's own pixels for ``lattice_size = 0``);
    the endpoint count scales with the area, ``s**2``.
    """
    lattice = p.lattice_size if p.lattice_size == 0 else max(16, int(round(p.lattice_size * s)))
    return dataclasses.replace(
        p, lattice_size=lattice, sigma=p.sigma * s, tone_sigma=max(1.0, p.tone_sigma * s),
        n_endpoints=max(1, int(round(p.n_endpoints * s * s))),
        min_width=p.min_width * s, max_width=p.max_width * s)


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
        Initial mode: the image as a dendrite, a grown tree, or the image
        hidden in a tree's crown (switchable in the app).
    display : int
        Display width of each result image (CSS pixels).

    Attributes
    ----------
    comparison : MetricComparison or None
        The last stylize-mode result (both metrics).
    tree : GrownTree, list of GrownTree, PareidoliaTree or None
        The last tree-mode result.
    rendering : Rendering or None
        The main picture of the last update (its ``.svg`` is what
        "save SVG" writes).
    preview : Stylization or None
        The last half-resolution preview (stylize mode).

    Examples
    --------
    >>> img = np.ones((48, 48)); img[12:36, 12:36] = 0.0
    >>> app = DendriteApp(img, params=StylizeParams(n_endpoints=40, stipple_iterations=3))
    >>> app.set_seed((10, 10))
    >>> app.comparison.second.seed.tolist()
    [10.0, 10.0]
    """

    def __init__(self, image, *, max_size: int = 400, params: StylizeParams | None = None,
                 mode: str = "stylize", display: int = 270):
        if mode not in MODES:
            raise ValueError(f"mode must be one of {list(MODES)}, got {mode!r}")
        if isinstance(max_size, bool) or not isinstance(max_size, (int, np.integer)) or max_size < 16:
            raise ValueError(f"max_size must be an int >= 16 (pixels), got {max_size!r}")
        if isinstance(display, bool) or not isinstance(display, int) or display < 64:
            raise ValueError(f"display must be an int >= 64 (pixels), got {display!r}")
        self.max_size = int(max_size)
        self._use_image(image)
        self.comparison = None
        self.tree = None
        self.rendering = None
        self.preview = None
        self.seed: np.ndarray | None = None
        self.shell = AppShell("Dendritic structures by path planning",
                              help="click to place the seed (trunk base in the tree modes); sliders "
                                   "update at once (preview), then in full")
        status = self.errors = self.shell.status
        g = self.shell.guard
        self._keeping_one_seed = False

        self.canvas = AnnotationCanvas(self.image, mode="point", modes=("point", "pan"),
                                       max_display=min(380, max(200, int(max_size))), errors=status)
        self.canvas.model.observe(self.shell.guard(self._on_model, action=False))
        self.mode_picker = widgets.ToggleButtons(options=list(MODES), value=mode,
                                                 tooltips=["the image as a dendrite",
                                                           "a tree grown iteratively",
                                                           "the image hidden in a tree's crown"],
                                                 style={"button_width": "auto"})
        self.metaphor = widgets.Dropdown(options=list(METAPHORS), value="plain", description="metaphor",
                                         style={"description_width": "initial"},
                                         layout=widgets.Layout(width="170px"))
        self.rng = widgets.BoundedIntText(value=0, min=0, max=2**31 - 1, description="seed",
                                          tooltip="random seed", style={"description_width": "32px"},
                                          layout=widgets.Layout(width="120px"))
        self.layers = widgets.IntSlider(value=1, min=1, max=4, description="layers",
                                        tooltip="occlusion: trees sharing one trunk (tree mode)",
                                        continuous_update=False, style={"description_width": "40px"},
                                        layout=widgets.Layout(width="190px"))
        self.status = widgets.HTML(layout=widgets.Layout(width="100%"))

        self.panels = {
            "stylize": ParamPanel(params if params is not None else StylizeParams(), errors=status,
                                  sections=STYLIZE_SECTIONS, labels=STYLIZE_LABELS,
                                  title="stylization (paper defaults)"),
            "tree": ParamPanel(TreeParams, errors=status, sections=TREE_SECTIONS, labels=TREE_LABELS,
                               closed=("crown shape",), title="tree growth"),
            "pareidolia": ParamPanel(PareidoliaParams, errors=status, sections=PAREIDOLIA_SECTIONS,
                                     labels=PAREIDOLIA_LABELS, title="pareidolia tree"),
        }
        for panel in self.panels.values():
            panel.on_change(g(lambda _values: self._live()))
        self.mode_picker.observe(g(self._on_mode), names="value")
        for w_ in (self.metaphor, self.rng, self.layers):
            w_.observe(g(lambda _change: self._live()), names="value")

        self.shell.add_action("update", self.update, icon="refresh", primary=True,
                              tooltip="recompute in full (cached stages are reused)")
        self.shell.add_tool(self.mode_picker, self.metaphor, self.rng, self.layers)
        self.shell.add_files(name="dendrite", open=self._open_images, outputs=self._outputs,
                             annotations=lambda: canvases_json({"image": self.canvas}, app="dendrite",
                                                               extra={"mode": self.mode}),
                             load=self._load_annotations)

        self.views = ImageView(width=int(display), max_size=2 * int(display))
        self.hist_tortuosity = HistogramCompare(bins=16, metric="l1",
                                                title="per-path tortuosity (length / straight)",
                                                width=2 * int(display) + 8, height=120)
        self.hist_max_edge = HistogramCompare(bins=16, metric="l1", title="per-path maximum edge cost",
                                              width=2 * int(display) + 8, height=120)
        self.schedule = widgets.HTML()
        self._panel_box = widgets.VBox()
        self._stats_box = widgets.VBox([self.hist_tortuosity, self.hist_max_edge])
        self.shell.set_body(main=[self.canvas],
                            result=[self.views, self.status, self.schedule, self._stats_box],
                            sidebar=[self._panel_box])
        super().__init__([self.shell])
        g(self._on_mode)(None)

    def _use_image(self, image) -> None:
        self.image = _fit(image, self.max_size)
        self.stylizer = Stylizer(self.image)
        h, w = self.image.shape[:2]
        self._preview_scale = 0.5 if max(h, w) >= 96 else 1.0
        small = _fit(self.image, max(8, int(round(max(h, w) * self._preview_scale))))
        self._preview_scale = small.shape[1] / w
        self.preview_stylizer = Stylizer(small)

    # -- public API (everything the widgets do, callable from Python) ----------
    def set_image(self, image) -> None:
        """Stylize another image (downscaled to ``max_size``); the seed click is dropped.

        Parameters
        ----------
        image : (H, W, C) array_like
            Any layout :func:`branchnb.core.image.as_float_image` accepts.
        """
        self._use_image(image)
        self.comparison = self.tree = self.rendering = self.preview = None
        self.seed = None
        self.canvas.set_overlay(None)
        self.canvas.set_image(self.image)
        self._keeping_one_seed = True
        try:
            self.canvas.model.clear()
        finally:
            self._keeping_one_seed = False
        self._live()

    def _open_images(self, images) -> None:
        self.set_image(images[0][1])

    def _outputs(self) -> dict:
        if self.rendering is None:
            return {}
        return {f"{self.mode}.png": self.rendering.image, f"{self.mode}.svg": self.rendering.svg}

    def _load_annotations(self, text) -> None:
        extra = load_canvases(text, {"image": self.canvas}, app="dendrite")
        if extra.get("mode") in MODES:
            self.mode = extra["mode"]

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
        """Place the seed (trunk base in the tree modes) at image pixel ``(x, y)``.

        Parameters
        ----------
        xy : (x, y)
            Image pixels of the (downscaled) image shown; the click replaces
            the previous seed.
        """
        self.canvas.model.add_shape("point", [tuple(map(float, xy))])

    def save_svg(self, path) -> Path:
        """Write the current picture's SVG.

        Parameters
        ----------
        path : str or os.PathLike
            File to write (UTF-8; overwritten if it exists).

        Returns
        -------
        pathlib.Path

        Raises
        ------
        ValueError
            If nothing was rendered yet or ``path`` is a folder.
        """
        if self.rendering is None:
            raise ValueError("nothing rendered yet")
        path = Path(path)
        if path.is_dir():
            raise ValueError(f"path {str(path)!r} is a folder: give a file name such as dendrite.svg")
        path.write_text(self.rendering.svg, encoding="utf-8")
        return path

    def update(self) -> str:
        """Recompute (cached stages are reused) and redraw; returns a summary."""
        if self.mode == "stylize":
            return self._update_stylize()
        if self.mode == "tree":
            return self._update_tree()
        return self._update_pareidolia()

    # -- callbacks -------------------------------------------------------------
    def _live(self) -> None:
        preview = self._preview if self.mode == "stylize" else None
        self.shell.live("update", self.update, preview=preview, stale=self._mark_stale)

    def _mark_stale(self) -> None:
        for i, t in enumerate(self.views.title_texts):
            self.views.set_title(i, f"{t} (updating ...)")

    def _preview(self) -> None:
        s = self._preview_scale
        full = self.panels["stylize"].values
        p = _scaled(full, s)
        if p.output_width > 0:
            # the size-adapted parameters with ``output_width = 0``: the same widths, without
            # the rounds that drop twigs to match the ink of a larger picture (3/4 of the
            # preview's time on a 240-px camera man: 0.43 s -> 0.12 s under load)
            k = self.preview_stylizer.size_scale(p)
            p = dataclasses.replace(effective_params(p, k), output_width=0.0)
        # the full update's seed (clicked, or the stylizer's important region), in preview pixels
        seed = (self.stylizer.start_seed(full, metaphor=self.metaphor.value) if self.seed is None
                else self.seed)
        seed = (np.asarray(seed, float) + 0.5) * s - 0.5
        try:
            self.preview = self.preview_stylizer.run(p, seed=seed, rng=int(self.rng.value),
                                                     metaphor=self.metaphor.value)
        except ValueError:
            return  # the full update that follows reports it with the user's own values
        if len(self.views.images) >= 2:
            self.views.update_one(1, self.preview.rendering.image,
                                  f"{p.metric}: preview at {s:.0%} size (full one follows)")
        else:
            self.views.update([self.preview.rendering.image], ["preview"])

    def _on_model(self, _event) -> None:
        if self._keeping_one_seed:
            return
        pts = self.canvas.model.of_kind("point")
        if len(pts) > 1:  # only the last click is the seed: drop the older dots
            self._keeping_one_seed = True
            try:
                last = pts[-1].to_dict()
                self.canvas.model.load_json({"version": 1, "shapes": [
                    s.to_dict() for s in self.canvas.model.shapes if s.kind != "point"] + [last]})
            finally:
                self._keeping_one_seed = False
            pts = self.canvas.model.of_kind("point")
        new = None if not pts else pts[-1].points[-1].copy()
        if (new is None) != (self.seed is None) or (new is not None and not np.array_equal(new, self.seed)):
            self.seed = new
            self._live()

    def _on_mode(self, _change) -> None:
        self._panel_box.children = [self.panels[self.mode]]
        tree_mode = self.mode != "stylize"
        self._stats_box.layout.display = "none" if tree_mode else None
        self.schedule.layout.display = None if tree_mode else "none"
        self.layers.layout.display = None if self.mode == "tree" else "none"
        self._live()

    # -- modes ----------------------------------------------------------------------
    def _update_stylize(self) -> str:
        p = self.panels["stylize"].values
        c = compare_metrics(self.stylizer, p, seed=self.seed, rng=int(self.rng.value),
                            metaphor=self.metaphor.value)
        self.comparison = c
        self.rendering = c.second.rendering
        # the plan lives on the planning lattice: shown at the image's size like the renderings
        # (no larger than the view sends, so that it is not blended back into thousands of
        # colours), its bands flat: a palette PNG of 10-40 kB in the notebook, not 80-430
        h, w = self.image.shape[:2]
        f = min(1.0, self.views.max_size / max(h, w)) if self.views.max_size else 1.0
        order = cv2.resize(visiting_order_image(c.second.plan, flat=True),
                           (max(1, round(w * f)), max(1, round(h * f))), interpolation=cv2.INTER_NEAREST)
        self.views.update(
            [c.first.rendering.image, c.second.rendering.image, order],
            [f"{c.first.params.metric}", f"{c.second.params.metric}"
             + (f" (a = {p.blend_weight:g})" if c.second.params.metric == "blend" else ""),
             f"visiting order ({c.second.params.metric})"])
        labels = [c.first.params.metric, c.second.params.metric]
        t1, t2 = c.stats_first.tortuosity, c.stats_second.tortuosity
        self.hist_tortuosity.update(t1[np.isfinite(t1)], t2[np.isfinite(t2)], labels=labels)
        self.hist_max_edge.update(c.stats_first.max_edge, c.stats_second.max_edge, labels=labels)
        d = c.second.dendrite  # image pixels (Stylization.scale maps them to the lattice)
        # Half-transparent orange, at most 2 px wide: the image stays readable under it.
        overlay = draw_polylines(np.zeros((*self.image.shape[:2], 4), np.float32), d.polylines(2),
                                 widths=[np.minimum(w, 2.0) for w in d.widths()], colors=(1.0, 0.45, 0.0),
                                 alpha=0.6)
        s = c.second.seed
        if self.seed is None:  # mark the default seed (the important region) where no click is drawn
            ring = [_ring(s, max(4.0, 0.02 * max(self.image.shape[:2])))]
            overlay = draw_polylines(overlay, ring, widths=[4.0], colors=(1.0, 1.0, 1.0))
            overlay = draw_polylines(overlay, ring, widths=[2.0], colors=(0.1, 0.35, 0.95))
        self.canvas.set_overlay(overlay)
        self.status.value = (
            f"<span style='font-size:12px'>seed ({s[0]:.0f}, {s[1]:.0f})"
            f"{'' if self.seed is not None else ' (default: the important region, blue ring)'} · "
            f"{len(c.second.endpoints)} "
            f"endpoints · {d.n_nodes} nodes, {d.n_branches} branches · mean tortuosity "
            f"{np.nanmean(t1):.2f} ({labels[0]}) vs {np.nanmean(t2):.2f} ({labels[1]})</span>")
        return f"{d.n_branches} branches"

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

    def _update_tree(self) -> str:
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
        self.status.value = (f"<span style='font-size:12px'>{d.n_nodes} nodes, {d.n_branches} branches, "
                             f"endpoints per iteration {[len(e) for e in main.endpoints]}</span>")
        return f"{d.n_branches} branches"

    def _update_pareidolia(self) -> str:
        p = self.panels["pareidolia"].values
        t = pareidolia_tree(self.image, p, rng=int(self.rng.value))
        self.tree = t
        m = self.metaphor.value
        self.rendering = t.render() if m == "plain" else self._tree_render(t.dendrite)
        self.views.update([t.image, self.rendering.image], ["image (+ trunk strip)", "pareidolia tree"])
        self.schedule.value = self._schedule_html(
            dataclasses.replace(TreeParams(), iterations=p.iterations, blend_weight=p.blend_weight))
        self.canvas.set_overlay(None)
        self.status.value = (f"<span style='font-size:12px'>{len(t.endpoints_image)} stippled + "
                             f"{len(t.endpoints_random)} random endpoints, {t.dendrite.n_nodes} nodes "
                             "(the trunk starts below the image; the seed click is not used in this "
                             "mode)</span>")
        return f"{t.dendrite.n_nodes} nodes"
