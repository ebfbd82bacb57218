"""LeafApp: scribble layers on a training leaf, analyse the exemplars, generate new leaves.

A thin app on :class:`~branchnb.widgets.shell.AppShell`; everything it
computes is a call into :mod:`branchnb.leaves` (``analyze``, ``reinduce``,
``generate``) that a script can make directly.

* left: the training leaf on a scribble canvas (one scribble label per
  layer) and the layer list (name, colour, order; add, remove, up, down);
* middle: the exemplars with their registration (keypoints and the
  training frame's grid carried onto them) and induced layers, the colour
  histograms of each user layer against the induced layer of each exemplar
  with their EMD, and the generated leaves next to the exemplars;
* right: the induction parameters (eps, kappa, neighbourhood, ...), the
  synthesis parameters (warp magnitudes, shape blend), number of outputs
  and seed.

Changing an induction parameter re-runs the induction only
(:meth:`branchnb.leaves.analysis.LeafAnalysis.reinduce`): the registrations
are computed once per exemplar set and kept.
"""

from __future__ import annotations

import dataclasses
import html
import warnings

import cv2
import ipywidgets as widgets
import numpy as np
from skimage.color import rgb2lab

from ..core.render import coverage_polylines
from ..leaves.analysis import LeafAnalysis, analyze, normalise_exemplars
from ..leaves.induction import InductionParams
from ..leaves.layers import Layer, LayerSet
from ..leaves.structural import (  # noqa: F401  (importable from here as before)
    MAX_STRUCTURAL_REACH,
    MIN_STANDOUT,
    MIN_STRUCTURAL_LAMBDA,
    LeafAnalysisWarning,
    ShadowAsLeafWarning,
    _delta_text,
    _reach_text,
    _scribbled_as_structure,
    is_structural,
    layer_warnings,
    spatial_reach,
)
from ..leaves.synthesis import SynthesisParams, generate
from .canvas import AnnotationCanvas
from .files import canvases_json, load_canvases
from .histograms import HistogramCompare
from .imageview import ImageView
from .params import ParamPanel
from .shell import AppShell

__all__ = ["LeafApp", "layer_set_from_shapes", "layer_warnings", "spatial_reach", "is_structural", "BLADE"]

#: Induction parameters :meth:`LeafAnalysis.retune` previews without new colour terms.
_RETUNABLE = {"eps", "kappa", "liberal_threshold"}

_PALETTE = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"]


def _white(rgba: np.ndarray) -> np.ndarray:
    a = rgba[..., 3:]
    return (rgba[..., :3] * a + (1 - a)).astype(np.float32)


#: Label (and colour) of scribbles on the plain blade, the background layer.
BLADE = "blade"
_BLADE_COLOUR = "#7f7f7f"


def layer_set_from_shapes(shapes, layers: LayerSet, *, radius: float = 2.0, offset=(0.0, 0.0)) -> LayerSet:
    """The app's layer list with the canvas' scribbles (label = layer name) as their scribbles.

    A scribble keeps the brush radius it was loaded or drawn with
    (``meta["radius"]``), else ``radius``; ``"blade"`` scribbles go to the
    background. ``offset`` is subtracted from the points (canvas -> leaf
    pixels). Scribbles whose label names no layer raise a ``ValueError``
    naming the label.

    Parameters
    ----------
    shapes : sequence of Shape
        The canvas' shapes; only scribbles count (their ``label`` is a layer
        name or ``"blade"``).
    layers : LayerSet
        The app's layers (names, colours, order); copied without their
        scribbles.
    radius : float
        Brush radius in pixels for scribbles without ``meta["radius"]``.
    offset : (dx, dy)
        Shift subtracted from every point (canvas -> leaf pixels).

    Returns
    -------
    LayerSet
        A new layer set holding the scribbles.

    Raises
    ------
    ValueError
        If a scribble's label names no layer.

    Examples
    --------
    >>> from branchnb.widgets.model import Shape
    >>> layers = LayerSet(); _ = layers.add("veins", "#aa0000")
    >>> out = layer_set_from_shapes([Shape("scribble", [(5, 5), (9, 9)], label="veins")], layers, offset=(1, 1))
    >>> out.layers[0].scribbles[0].points.tolist(), out.layers[0].scribbles[0].radius
    ([[4.0, 4.0], [8.0, 8.0]], 2.0)
    """
    out = LayerSet([Layer(x.name, x.colour, x.order) for x in layers.layers])
    names = {x.name for x in out.layers}
    d = np.asarray(offset, float)
    for i, s in enumerate(shapes):
        if s.kind != "scribble":
            continue
        if s.label not in names and s.label != BLADE:
            raise ValueError(f"scribble {i} has label {s.label!r}, which is no layer "
                             f"(layers: {sorted(names)})")
        r = s.meta.get("radius", radius)
        out.add_scribble(s.label, s.points - d, radius=float(r))
    return out


class LeafApp(widgets.VBox):
    """Leaf variations by structural layering, in a notebook.

    Parameters
    ----------
    exemplars : list of images (RGBA cut-outs or leaves on a plain background)
        Leaves of one kind; at least two.
    training_index : int
        The leaf to scribble on.
    layers : LayerSet, optional
        Initial layers (scribbles in the training image's pixels); by default
        empty "veins" and "spots" layers.
    registrations : list, optional
        Precomputed registrations (exemplar -> training), e.g. through known
        correspondences; computed by the first analysis otherwise.
    max_display : int
        Long side of the canvas in CSS pixels.

    Examples
    --------
    >>> from branchnb.leaves import leaf_family
    >>> app = LeafApp(leaf_family(2, size=96, rng=0))
    >>> app.layer_names()
    ['veins', 'spots']
    """

    def __init__(self, exemplars, *, training_index: int = 0, layers: LayerSet | None = None,
                 registrations=None, max_display: int = 480):
        self.shell = AppShell("Leaf variations (Assa & Cohen-Or 2012)",
                              help="scribble each layer on the training leaf (pick the layer, drag); "
                                   "'analyze', then 'generate'")
        self.status = self.errors = self.shell.status
        self.images, self.blades, self.offsets = normalise_exemplars(exemplars)
        n = len(self.images)
        if isinstance(training_index, bool) or not isinstance(training_index, (int, np.integer)) \
                or not 0 <= training_index < n:
            raise ValueError(f"training_index must be an int in [0, {n - 1}], got {training_index!r}")
        self.training_index = int(training_index)
        if registrations is not None and len(registrations) != n:
            raise ValueError(f"registrations must have one entry per exemplar ({n}), got {len(registrations)}")
        self._registrations = list(registrations) if registrations is not None else None
        self._marks: dict = {}  # exemplar -> (registration key, (grid, keypoint) coverage)
        self._white: dict = {}  # exemplar -> (its image, on white, L*): kept between slider moves
        self.analysis: LeafAnalysis | None = None
        self._shadows: list[str] = []  # ShadowAsLeafWarning messages of the last analysis, shown in the report
        self.leaves: list = []
        if layers is None:
            layers = LayerSet([Layer("veins", _PALETTE[0], 0), Layer("spots", _PALETTE[1], 1)])
        if not isinstance(layers, LayerSet):
            raise TypeError(f"layers must be a LayerSet, got {type(layers).__name__}")
        self.layers = LayerSet([Layer(x.name, x.colour, x.order) for x in layers.layers])
        t = self.training_index
        labels = {x.name: x.colour for x in self.layers.ordered()} or {"veins": _PALETTE[0]}
        labels[BLADE] = _BLADE_COLOUR
        self.canvas = AnnotationCanvas(_white(self.images[t]), mode="scribble", labels=labels,
                                       modes=("scribble", "edit", "pan"), max_display=max_display,
                                       errors=self.status)
        self.canvas.radius = 2.0
        for shape in self._layer_shapes(layers):
            self.canvas.model.add_shape("scribble", shape.points, label=shape.label, meta=shape.meta)
        # Layer list.
        self.layer_list = widgets.Select(options=self.layer_names(), rows=4,
                                         layout=widgets.Layout(width="150px"))
        self.layer_list.observe(self.status.guard(self._pick_layer, action=False), names="value")
        self.name_box = widgets.Text(placeholder="new layer", layout=widgets.Layout(width="110px"))
        self.colour_box = widgets.ColorPicker(value=_PALETTE[len(self.layers.layers) % len(_PALETTE)],
                                              concise=True, layout=widgets.Layout(width="36px"))
        self.colour_box.observe(self.status.guard(self._recolour, action=False), names="value")
        buttons = {}
        for name, fn, tip in (("add", self.add_layer, "add a layer with this name and colour"),
                              ("remove", lambda: self.remove_layer(self.layer_list.value),
                               "remove the selected layer and its scribbles"),
                              ("up", lambda: self.move_layer(self.layer_list.value, -1), "move up (drawn later)"),
                              ("down", lambda: self.move_layer(self.layer_list.value, +1), "move down")):
            b = widgets.Button(description=name, tooltip=tip, layout=widgets.Layout(width="auto"))
            b.on_click(self.status.guard(lambda _b, fn=fn: fn(), action=False))
            buttons[name] = b
        self.layer_buttons = buttons
        layer_box = widgets.VBox([
            widgets.HTML("<b>layers</b> (top first)"),
            widgets.HBox([self.layer_list, widgets.VBox([buttons["up"], buttons["down"], buttons["remove"]])]),
            widgets.HBox([self.name_box, self.colour_box, buttons["add"]]),
        ])
        if self.layer_names():
            self.layer_list.value = self.layer_names()[0]
        # Views.
        self.exemplar_view = ImageView(width=150, max_size=400)
        self.histograms = HistogramCompare(bins=24, metric="emd", title="L* of the user layer vs induced",
                                           width=460, height=150)
        self.hist_layer = widgets.Dropdown(options=self.layer_names(), description="histogram",
                                           layout=widgets.Layout(width="240px"))
        self.hist_layer.observe(self.status.guard(lambda _c: self._show_histograms(), action=False),
                                names="value")
        self.report = widgets.HTML()
        self.gallery = ImageView(width=120, max_size=300)
        # One generated leaf at its full size (the gallery's thumbnails hide veins and spots).
        self.open_leaf = widgets.Dropdown(options=[], description="full size", layout=widgets.Layout(width="200px"))
        self.full_view = ImageView(width=480)
        self.open_leaf.observe(self.status.guard(lambda _c: self.show_leaf(self.open_leaf.value), action=False),
                               names="value")
        self._show_exemplars()
        # Parameters.
        self.induction_panel = ParamPanel(InductionParams, errors=self.status,
                                          title="layer induction (Sec. 4)",
                                          labels={"eps": ("eps", "ε"), "kappa": ("kappa", "κ"),
                                                  "neighbourhood": ("neighbourhood", "n")})
        self.induction_panel.on_change(self.status.guard(self._induction_changed, action=False))
        self.synthesis_panel = ParamPanel(SynthesisParams, errors=self.status, title="synthesis (Sec. 5)")
        self.n_outputs = widgets.BoundedIntText(8, min=1, max=64, description="outputs",
                                                layout=widgets.Layout(width="150px"))
        self.seed = widgets.BoundedIntText(0, min=0, max=2**31 - 1, description="seed",
                                           layout=widgets.Layout(width="150px"))
        self.shell.add_action("analyze", self.run_analysis, primary=True, background=True, cancellable=True,
                              tooltip="grow the layers, register the exemplars (once) and induce the layers")
        self.shell.add_action("generate", self.run_generate, background=True, cancellable=True,
                              tooltip="new leaves from the analysis")
        self.shell.add_action("clear scribbles", self.clear_scribbles, run=False)
        self.shell.add_tool(self.n_outputs, self.seed)
        self.shell.add_files(name="leaves", open=self._open_images, open_label="open leaves", multiple=True,
                             outputs=self._outputs, annotations=self._annotations, load=self._load_annotations)
        self.shell.set_body(main=[self.canvas, layer_box],
                            result=[widgets.HTML("<b>exemplars</b>: registration and induced layers"),
                                    self.exemplar_view, self.report, self.hist_layer, self.histograms,
                                    widgets.HTML("<b>generated leaves</b>"), self.gallery,
                                    self.open_leaf, self.full_view],
                            sidebar=[self.induction_panel, self.synthesis_panel])
        super().__init__([self.shell])

    # -- files (the shell's open / save / load annotations) -------------------------------
    def set_exemplars(self, exemplars, training_index: int = 0) -> None:
        """Work on other leaves (two or more of one kind): the layers stay, their scribbles go.

        Parameters
        ----------
        exemplars : list of images
            RGBA cut-outs or leaves on a plain background, two or more; they
            are centred on one common canvas (see
            :func:`branchnb.leaves.analysis.normalise_exemplars`).
        training_index : int
            The leaf shown on the canvas, whose scribbles define the layers.

        Raises
        ------
        ValueError
            If fewer than two leaves are given or ``training_index`` is out
            of range.
        """
        images, blades, offsets = normalise_exemplars(exemplars)
        if not 0 <= training_index < len(images):
            raise ValueError(f"training_index must be in [0, {len(images) - 1}], got {training_index!r}")
        self.images, self.blades, self.offsets = images, blades, offsets
        self.training_index = int(training_index)
        self._registrations, self._marks, self._white = None, {}, {}
        self.analysis, self.leaves = None, []
        self.canvas.set_image(_white(self.images[self.training_index]))
        self.canvas.model.clear()
        self.report.value = ""
        self.histograms.clear()
        self.gallery.update([], [])
        self._show_exemplars()

    def _open_images(self, images) -> str:
        if len(images) < 2:
            raise ValueError("open leaves: choose two or more leaves of one kind at once (the first is "
                             "the training leaf)")
        self.set_exemplars([img for _, img in images])
        return f"{len(images)} leaves; scribble the layers on the first, then 'analyze'"

    def _layer_shapes(self, layers: LayerSet) -> list:
        """Canvas scribbles of ``layers`` (training-leaf pixels), each with its own brush radius.

        The paper's users draw one-pixel vein strokes and wide blade dabs
        in one session: ``meta["radius"]`` carries each one's radius.
        """
        from .model import Shape

        d = np.asarray(self.offsets[self.training_index], float)
        out = [Shape("scribble", s.points + d, label=x.name, meta={"radius": float(s.radius)})
               for x in layers.layers for s in x.scribbles]
        return out + [Shape("scribble", s.points + d, label=BLADE, meta={"radius": float(s.radius)})
                      for s in layers.background]

    def load_layers(self, layers) -> None:
        """Replace the layers and their scribbles (undoable on the canvas).

        Parameters
        ----------
        layers : LayerSet or str
            Scribbles in the training leaf's own pixels, or their JSON
            (:meth:`LayerSet.to_json`, e.g. ``data/leaves/maple_leaf_01_layers.json``).
            Blade scribbles and each scribble's radius are kept:
            :meth:`layer_set` gives the same JSON back.

        Raises
        ------
        TypeError
            If ``layers`` is neither a LayerSet nor text.
        ValueError
            If the JSON is not a layer set.
        """
        if isinstance(layers, (bytes, bytearray)):
            layers = bytes(layers).decode("utf-8")
        if isinstance(layers, str):
            layers = LayerSet.from_json(layers)
        if not isinstance(layers, LayerSet):
            raise TypeError(f"layers must be a LayerSet or its JSON text, got {type(layers).__name__}")
        shapes = self._layer_shapes(layers)
        self.layers = LayerSet([Layer(x.name, x.colour, x.order) for x in layers.layers])
        self.canvas.model.load_json(_shapes_json(shapes))
        self._sync_layers()
        if self.layer_names():
            self.layer_list.value = self.layer_names()[0]

    def _outputs(self) -> dict:
        out = {f"leaf_{i:02d}.png": leaf.image for i, leaf in enumerate(self.leaves)}
        if self.analysis is not None:
            # The scribbles as the API takes them (LayerSet.from_json), radii and blade included.
            out["layer_scribbles.json"] = self.layer_set().to_json()
            out["layers.json"] = {"layers": [
                {"name": x.name, "lambda": float(x.lam), "delta": float(x.delta),
                 "training_iou": float(x.training_overlap)} for x in self.analysis.layers]}
        return out

    def _annotations(self) -> str:
        return canvases_json({"training": self.canvas}, app="leaves", extra={"layers": [
            {"name": x.name, "colour": x.colour, "order": x.order} for x in self.layers.ordered()]})

    def _load_annotations(self, text) -> None:
        import json

        if isinstance(text, (bytes, bytearray)):
            text = bytes(text).decode("utf-8")
        d = json.loads(text)
        if isinstance(d, dict) and "canvases" not in d and "shapes" not in d and any(
                isinstance(x, dict) and "scribbles" in x for x in d.get("layers") or []):
            self.load_layers(text)  # a stored layer set (LayerSet.to_json), not the app's own file
            return
        layers = ((d.get("extra") or {}).get("layers") if isinstance(d, dict) else None) or []
        if not all(isinstance(x, dict) and isinstance(x.get("name"), str) for x in layers):
            raise ValueError("annotations: 'layers' must list objects with a 'name'")
        new = LayerSet([Layer(x["name"], str(x.get("colour", _PALETTE[i % len(_PALETTE)])), i)
                        for i, x in enumerate(layers)]) if layers else self.layers
        old = self.layers
        self.layers = new
        try:
            self._sync_layers()
            load_canvases(text, {"training": self.canvas}, app="leaves")
        except Exception:
            self.layers = old
            self._sync_layers()
            raise
        if self.layer_names():
            self.layer_list.value = self.layer_names()[0]

    # -- layer list -----------------------------------------------------------------
    def layer_names(self) -> list[str]:
        """The layers' names, in stacking order (top first)."""
        return self.layers.names()

    def _sync_layers(self) -> None:
        names = self.layer_names()
        self.layer_list.options = names
        self.hist_layer.options = names
        self.canvas.labels = {**{x.name: x.colour for x in self.layers.ordered()}, BLADE: _BLADE_COLOUR}
        picker = self.canvas._label_picker  # the canvas' own label dropdown follows the layer list
        if names:
            keep = self.canvas.label if self.canvas.label in names + [BLADE] else names[0]
            picker.options = names + [BLADE]
            picker.value = keep
        self.canvas.redraw()

    def _pick_layer(self, change) -> None:
        if change["new"]:
            self.canvas.label = change["new"]
            self.colour_box.value = self.layers.get(change["new"]).colour

    def _recolour(self, change) -> None:
        name = self.layer_list.value
        if name:
            colour = change["new"]
            if not colour.startswith("#") or len(colour) != 7:
                return  # a CSS colour name from the picker: keep the last hex
            self.layers.get(name).colour = colour
            self._sync_layers()

    def add_layer(self, name: str | None = None, colour: str | None = None) -> None:
        """Add a layer (at the bottom) and select it for scribbling.

        Parameters
        ----------
        name : str, optional
            Layer name; the name box's text if None.
        colour : str, optional
            CSS colour ``"#rrggbb"`` of its scribbles; the colour box's value
            if None, the next palette colour if that is not of this form.

        Raises
        ------
        ValueError
            If the name is empty or taken.
        """
        name = (name if name is not None else self.name_box.value).strip()
        if not name:
            raise ValueError("type a name for the new layer first")
        colour = colour or self.colour_box.value
        if not colour.startswith("#") or len(colour) != 7:
            colour = _PALETTE[len(self.layers.layers) % len(_PALETTE)]
        self.layers.add(name, colour)
        self.name_box.value = ""
        self._sync_layers()
        self.layer_list.value = name

    def remove_layer(self, name: str) -> None:
        """Remove a layer and its scribbles.

        Parameters
        ----------
        name : str
            The layer's name (the selected layer in the app).

        Raises
        ------
        ValueError
            If ``name`` is None or names no layer.
        """
        if name is None:
            raise ValueError("select a layer to remove")
        self.layers.remove(name)
        keep = [s for s in self.canvas.model.shapes if s.label != name]
        self.canvas.model.load_json(_shapes_json(keep))
        self._sync_layers()

    def move_layer(self, name: str, step: int) -> None:
        """Move a layer up (``-1``, towards the top) or down (``+1``).

        Parameters
        ----------
        name : str
            The layer's name.
        step : int
            Positions to move; negative moves towards the top of the
            stacking order.

        Raises
        ------
        ValueError
            If ``name`` is None or names no layer.
        """
        if name is None:
            raise ValueError("select a layer to move")
        names = self.layer_names()
        self.layers.move(name, names.index(name) + int(step))
        self._sync_layers()
        self.layer_list.value = name

    def clear_scribbles(self) -> None:
        """Remove every scribble from the canvas (undoable); the layers stay."""
        self.canvas.model.clear()

    def scribbled_layers(self) -> LayerSet:
        """The layers with the canvas' scribbles (canvas pixels: the app's exemplars are already on one canvas)."""
        return layer_set_from_shapes(self.canvas.model.shapes, self.layers, radius=self.canvas.radius)

    def layer_set(self) -> LayerSet:
        """The layers with their scribbles in the training leaf's own pixels (as given to the app).

        ``LayerSet.to_json`` of it gives back the JSON the app was started
        from, blade scribbles and each scribble's radius included.
        """
        return layer_set_from_shapes(self.canvas.model.shapes, self.layers, radius=self.canvas.radius,
                                     offset=self.offsets[self.training_index])

    # -- actions ------------------------------------------------------------------------
    def run_analysis(self) -> str:
        """Grow the scribbled layers, register (once), induce; show the result."""
        ls = self.scribbled_layers()
        prm = self.induction_panel.values
        # The report shows analyze's warnings (layer_warnings and the shadowed blades): not on stderr too.
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", LeafAnalysisWarning)
            a = analyze(self.images, self.training_index, ls, prm, progress=self.shell.progress,
                        registrations=self._registrations)
        self._shadows = [str(w.message) for w in caught if issubclass(w.category, ShadowAsLeafWarning)]
        self._registrations = a.registrations
        self.analysis = a
        self._show_analysis()
        return ", ".join(f"{x.name}: lambda {x.lam:.2f}, delta {x.delta:.2f}" for x in a.layers)

    def _induction_changed(self, params) -> None:
        if self.analysis is None:
            return
        shown = self.analysis.params
        changed = {f.name: getattr(params, f.name) for f in dataclasses.fields(params)
                   if getattr(params, f.name) != getattr(shown, f.name)}
        preview = None
        if changed and set(changed) <= _RETUNABLE:
            # eps, kappa and the liberal threshold leave the colour terms as they are: a
            # few milliseconds on the cached terms now, the full re-induction behind it.
            preview = lambda: self._show_analysis(self.analysis.retune(**changed))  # noqa: E731
        self.shell.live("re-induce", lambda: self._reinduce(params), preview=preview)

    def _reinduce(self, params) -> str:
        changes = {f.name: getattr(params, f.name) for f in dataclasses.fields(params)}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", LeafAnalysisWarning)  # shown in the report
            a = self.analysis.reinduce(progress=self.shell.progress, **changes)
        self.analysis = a
        self._show_analysis()
        return ", ".join(f"{x.name}: lambda {x.lam:.2f}" for x in a.layers)

    def run_generate(self) -> str:
        """Generate new leaves from the last analysis (the "generate" button); returns a summary.

        Raises
        ------
        ValueError
            If nothing was analysed yet.
        """
        if self.analysis is None:
            raise ValueError("run 'analyze' first: there is nothing to generate from yet")
        n = int(self.n_outputs.value)
        self.leaves = generate(self.analysis, n, rng=int(self.seed.value), params=self.synthesis_panel.values,
                               progress=self.shell.progress)
        self.gallery.update([leaf.on_white() for leaf in self.leaves],
                            # a shortened seed would not reproduce the leaf: the full-size view shows it whole
                            [f"#{i}" for i in range(len(self.leaves))])
        self.open_leaf.options = [(f"leaf #{i}", i) for i in range(len(self.leaves))]
        self.open_leaf.value = 0
        self.show_leaf(0)
        return f"{n} leaves"

    def show_leaf(self, i) -> None:
        """Show generated leaf ``i`` at its full size (cropped to the leaf) below the gallery.

        Parameters
        ----------
        i : int or None
            Index into the generated leaves; None (nothing picked) does nothing.
        """
        if i is None or not self.leaves:
            return
        leaf = self.leaves[int(i)]
        ys, xs = np.nonzero(leaf.image[..., 3] > 0.02)
        img = leaf.on_white()
        if len(ys):
            img = img[max(ys.min() - 4, 0):ys.max() + 5, max(xs.min() - 4, 0):xs.max() + 5]
        self.full_view.width = max(16, min(960, img.shape[1]))
        self.full_view.update([img], [f"leaf #{int(i)} ({img.shape[1]} x {img.shape[0]} px), seed {leaf.seed}"])

    # -- views ---------------------------------------------------------------------------
    def registration_overlay(self, e: int, analysis: LeafAnalysis | None = None, *, step: int = 1) -> np.ndarray:
        """Exemplar ``e`` with its induced layers, keypoints and the training grid carried onto it.

        Parameters
        ----------
        e : int
            Exemplar index.
        analysis : LeafAnalysis, optional
            The analysis to show; the app's last one by default. Without
            one, the plain exemplar on white is returned.
        step : int
            Every ``step``-th pixel (the thumbnails of megapixel exemplars:
            a slider preview draws no more than is shown).

        Returns
        -------
        (ceil(H / step), ceil(W / step), 3) float32 ndarray
            The training leaf shows only its layers (no grid).
        """
        a = analysis if analysis is not None else self.analysis
        if a is None:
            return _white(self.images[e])[::step, ::step]
        img = a.overlay(e, base=self._on_white(a, e, step), step=step)
        if e == a.training_index:
            return img
        grid, dots = self._registration_marks(e, a.registrations[e], img.shape[:2], step)
        for cov, colour in ((grid, (0.2, 0.2, 0.2)), (dots, (0.95, 0.9, 0.1))):
            on = cov > 0  # the marks cover a few percent of the image: blend there only
            c = cov[on][:, None]
            img[on] = img[on] * (1 - c) + np.asarray(colour, np.float32) * c
        return img.astype(np.float32)

    def _on_white(self, a: LeafAnalysis, e: int, step: int = 1) -> np.ndarray:
        """Exemplar ``e`` of ``a`` on white (every ``step``-th pixel, area-averaged), kept between slider moves.

        Its CIELAB L* (full size, for the histograms) is kept with it.
        """
        img = a.exemplars[e]
        hit = self._white.get(e)
        if hit is None or hit[0] is not img:
            rgb = _white(img) if img.shape[-1] == 4 else np.asarray(img[..., :3], np.float32)
            hit = self._white[e] = (img, rgb, rgb2lab(img[..., :3])[..., 0], {})
        if step == 1:
            return hit[1]
        small = hit[3].get(step)
        if small is None:
            h, w = hit[1].shape[:2]
            small = hit[3][step] = cv2.resize(hit[1], (-(-w // step), -(-h // step)), interpolation=cv2.INTER_AREA)
        return small

    def _view_step(self, shape) -> int:
        """Pixel step that brings an exemplar down to the exemplar view's size (1 for small leaves)."""
        limit = self.exemplar_view.max_size
        return 1 if limit is None else max(1, -(-max(shape[:2]) // limit))

    def _registration_marks(self, e: int, reg, shape, step: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """Coverage of the carried grid and of the keypoint marks (drawn once per registration).

        ``shape`` is the drawing's, every ``step``-th pixel of the exemplar's.
        """
        key = (id(reg), shape, step)
        hit = self._marks.get(e)
        if hit is not None and hit[0] == key:
            return hit[1]
        m = np.asarray(reg.map_to_training)
        h, w = m.shape[:2]
        gap = max(8, min(h, w) // 12)
        lines = ([m[y, ::4] / step for y in range(gap // 2, h, gap)]
                 + [m[::4, x] / step for x in range(gap // 2, w, gap)])
        grid = np.clip(coverage_polylines(shape, lines, [0.6 / step] * len(lines))[0], 0, 1)  # as full size, shrunk
        pts = getattr(getattr(reg, "exemplar_keypoints", None), "points", None)
        dots = np.zeros(shape, np.float32)
        if pts is not None and len(pts):
            r = 1.5
            circles = [np.array([[x - r, y], [x, y - r], [x + r, y], [x, y + r], [x - r, y]]) / step for x, y in pts]
            dots = np.clip(coverage_polylines(shape, circles, [1.0] * len(circles))[0], 0, 1)
        self._marks[e] = (key, (grid, dots))
        return grid, dots

    def _show_exemplars(self, analysis: LeafAnalysis | None = None) -> None:
        t = self.training_index
        n = len(self.images)
        # Drawn at the view's size: a megapixel exemplar is shown (and previewed) as a 400 px thumbnail.
        tiles = [self.registration_overlay(e, analysis, step=self._view_step(self.images[e].shape)) for e in range(n)]
        self.exemplar_view.update(tiles, [("training " if e == t else "") + f"#{e}" for e in range(n)])

    def _show_analysis(self, analysis: LeafAnalysis | None = None) -> None:
        """Overlays, the lambda/delta table and the histograms of ``analysis`` (default: the app's)."""
        a = analysis if analysis is not None else self.analysis
        self._show_exemplars(a)
        rows = "".join(f"<tr><td>{html.escape(x.name)}</td><td>{x.lam:.3f}</td><td>{_delta_text(x.delta)}</td>"
                       f"<td>{x.training_overlap:.2f}</td><td>{x.neighbourhood}</td><td>{_reach_text(x)}</td>"
                       f"<td>{_kind_text(x)}</td>"
                       f"<td>{len(x.masks) - len(x.empty)}/{len(x.masks)}</td></tr>" for x in a.layers)
        warn = "".join(f"<div style='color:#b35900'>⚠ {html.escape(w)}</div>"
                       for w in layer_warnings(a) + self._shadows)
        self.report.value = ("<table style='font-size:12px'><tr><th>layer</th><th>λ</th><th>δ</th>"
                             "<th title='IoU of the induced layer with yours on the training leaf'>IoU</th>"
                             "<th title='neighbourhood side of S_e (px)'>n</th>"
                             "<th title='how far from the registered layer it can be induced, in ε: "
                             "sqrt(ln(δ / λ)) (the δ criterion)'>reach</th>"
                             f"<th title='structural: λ &gt; {MIN_STRUCTURAL_LAMBDA} and reach ≤ "
                             f"{MAX_STRUCTURAL_REACH} ε (thin lines: stands out from its blade by ≥ "
                             f"{MIN_STANDOUT} colour spreads); colour: leans on colour alone; non-structural ⚠: "
                             "scribbled as a structure but induced by colour'>kind</th>"
                             "<th title='exemplars on which the layer was found'>found</th></tr>"
                             + rows + "</table>" + warn)
        self._show_histograms(a)

    def _show_histograms(self, analysis: LeafAnalysis | None = None) -> None:
        a = analysis if analysis is not None else self.analysis
        name = self.hist_layer.value
        if a is None or not name:
            return
        layer = a.layer(name)
        samples, labels = [], []
        t = a.training_index
        for e in [t] + [i for i in range(len(a.exemplars)) if i != t]:
            m = layer.masks[e]
            if not m.any():
                continue
            self._on_white(a, e)
            samples.append(self._white[e][2][m])
            labels.append("user layer" if e == t else f"#{e}")
        if len(samples) >= 1:
            self.histograms.update(*samples, labels=labels, range=(0.0, 100.0))


def _kind_text(layer) -> str:
    if is_structural(layer):
        kind = "structural"
    elif _scribbled_as_structure(layer):
        kind = "<b style='color:#b35900'>non-structural ⚠</b>"  # scribbled as a structure
    else:
        kind = "colour"
    return kind + (", snapped" if layer.snapped is not None else "")


def _shapes_json(shapes) -> str:
    import json
    return json.dumps({"version": 1, "shapes": [s.to_dict() for s in shapes]}, allow_nan=False)
