"""BranchingApp: annotate an example's branches, synthesize new structures, render the image.

The app wires the widget kit to :mod:`branchnb.branching`:

- the example image in an :class:`AnnotationCanvas`: one polyline per
  branch (a polyline started on a vertex of another becomes its child),
  per-vertex radius in ``edit`` mode, freehand ``stroke`` = guidance path;
- "extract" fills the canvas with :func:`~branchnb.branching.extract_structure`,
  "refine clicks" resamples the clicked polylines and measures their
  thickness perpendicular to the branch (the paper's input step);
- a :class:`ParamPanel` of :class:`~branchnb.branching.SynthesisParams`
  (m, k, c, wG, rho, d, generations, ...) and a seed; changing them
  re-synthesizes at once;
- the synthesized structure, with "extend branch" / "delete branch" on
  the branch picked by the slider, side-by-side angle and thickness
  histograms (input vs synthesized, the paper's evaluation), and "render
  image" (fragment-based image synthesis, with a progress bar).

Every action is a method (``extract``, ``refine``, ``synthesize``,
``extend``, ``delete_output_branch``, ``delete_selected_subbranch``,
``render_image``) so scripts and tests drive the app exactly as the
buttons do.
"""

from __future__ import annotations

import json

import ipywidgets as widgets
import numpy as np

from ..branching import (
    ClickParams,
    Guidance,
    ImageSynthesisParams,
    Structure,
    SynthesisParams,
    extend_branch,
    extract_structure,
    fit_model,
    synthesize_image,
    synthesize_structure,
)
from ..branching.extraction import estimate_thickness, gray_for_extraction
from ..core.image import as_float_image, as_rgb
from ..core.polyline import resample_uniform
from ..core.structure import Branch
from . import AnnotationCanvas, ErrorArea, HistogramCompare, ImageView, ParamPanel, ProgressBar

__all__ = ["BranchingApp", "annotations_to_structure", "structure_to_annotations"]


# --------------------------------------------------------------------------
# annotations <-> structure (pure functions)
# --------------------------------------------------------------------------
def structure_to_annotations(structure: Structure, keep=()) -> str:
    """Annotation JSON with one polyline per branch (radii = thickness, parent in ``meta``).

    ``keep`` are other shapes (e.g. the guidance strokes) appended after them.
    """
    shapes = []
    for b in structure.branches:
        meta = {} if b.parent is None else {"parent": [int(b.parent), int(b.parent_vertex)]}
        shapes.append({"kind": "polyline", "points": b.points.tolist(), "radii": b.thickness.tolist(),
                       "label": None, "closed": True, "meta": meta})
    for s in keep:
        shapes.append(s.to_dict() if hasattr(s, "to_dict") else dict(s))
    return json.dumps({"version": 1, "shapes": shapes})


def annotations_to_structure(shapes, image_shape=None) -> tuple[Structure, list[int]]:
    """The structure drawn as polylines, and the shape index of each branch.

    A polyline's parent is taken from ``meta["parent"] = [shape, vertex]``
    when that vertex is where the polyline starts; otherwise (e.g. after
    shapes were deleted) any other polyline having a vertex exactly at
    its start is the parent. Polylines with fewer than 2 vertices are
    skipped; missing radii default to 1 pixel.
    """
    poly = [i for i, s in enumerate(shapes) if s.kind == "polyline" and len(s.points) >= 2]
    index = {si: bi for bi, si in enumerate(poly)}
    branches = []
    for si in poly:
        s = shapes[si]
        r = s.radii if s.radii is not None else np.ones(len(s.points))
        parent = pv = None
        meta = s.meta.get("parent") if isinstance(s.meta, dict) else None
        if meta is not None:
            ps, pvx = int(meta[0]), int(meta[1])
            if ps in index and ps != si and 0 <= pvx < len(shapes[ps].points) and \
                    np.allclose(shapes[ps].points[pvx], s.points[0]):
                parent, pv = index[ps], pvx
        if parent is None:
            for pj in poly:
                if pj == si:
                    continue
                d = np.hypot(*(shapes[pj].points - s.points[0]).T)
                hit = np.flatnonzero(d < 1e-6)
                if len(hit):
                    parent, pv = index[pj], int(hit[0])
                    break
        branches.append(Branch(s.points, r, parent, pv))
    try:
        st = Structure(branches, image_shape=image_shape)
    except ValueError:  # a parent cycle from inconsistent edits: drop the links that close it
        for b in branches:
            b.parent = b.parent_vertex = None
        st = Structure(branches, image_shape=image_shape)
    return st, poly


# --------------------------------------------------------------------------
# the app
# --------------------------------------------------------------------------
class BranchingApp(widgets.VBox):
    """Example-based synthesis of branching structures in a notebook.

    Parameters
    ----------
    image : (H, W, C) array_like
        The example image (grey, RGB or RGBA).
    structure : Structure, optional
        A starting annotation (e.g. from ``extract_structure``).
    params : SynthesisParams, optional
    max_display : int
        Long side of the example canvas in screen pixels.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.branching import Branch, Structure
    >>> t = np.linspace(0, 1, 60)
    >>> s = Structure([Branch(np.c_[20 + 260 * t, 100 + 20 * np.sin(9 * t)], 3.0)], image_shape=(200, 300))
    >>> app = BranchingApp(np.ones((200, 300, 3)), structure=s)
    >>> app.synthesize().structure.n_vertices > 10
    True
    """

    def __init__(self, image, structure: Structure | None = None, *, params: SynthesisParams | None = None,
                 max_display: int = 560):
        self.image = as_float_image(image, name="image")
        self.image_shape = self.image.shape[:2]
        self.errors = ErrorArea()
        g = self.errors.guard
        self.canvas = AnnotationCanvas(as_rgb(self.image), mode="polyline", max_display=max_display,
                                       modes=("polyline", "edit", "stroke", "pan"))
        # Image synthesis only runs on "render image", so its panel needs no callback.
        self.image_panel = ParamPanel(ImageSynthesisParams(), debounce=0)
        self.panel = ParamPanel(params if params is not None else SynthesisParams(), debounce=0.3,
                                continuous=False, title="synthesis parameters")
        self.seed = widgets.BoundedIntText(value=0, min=0, max=2**31 - 1, description="seed",
                                           layout=widgets.Layout(width="160px"))
        self.auto = widgets.Checkbox(value=True, description="re-synthesize on change", indent=False)
        self.use_guidance = widgets.Checkbox(value=True, description="use guidance path (strokes)",
                                             indent=False)

        def button(label, tip, fn, icon=""):
            b = widgets.Button(description=label, tooltip=tip, icon=icon, layout=widgets.Layout(width="auto"))
            b.on_click(g(lambda _: fn()))
            return b

        self.buttons = {
            "extract": button("extract", "find the structure automatically (ridge filter + skeleton)",
                              self.extract, "magic"),
            "refine": button("refine clicks", "resample the polylines at step h and measure the thickness "
                             "perpendicular to each branch", self.refine),
            "delete": button("delete sub-branch", "edit mode: delete the selected branch and its children",
                             self.delete_selected_subbranch, "trash"),
            "synthesize": button("synthesize", "grow a new structure", self.synthesize, "play"),
            "extend": button("extend branch", "grow the picked output branch further", self.extend, "plus"),
            "delete_out": button("delete branch", "delete the picked output branch and its children",
                                 self.delete_output_branch, "trash"),
            "render": button("render image", "synthesize the final image from fragments of the example",
                             self.render_image, "image"),
            "clear_guidance": button("clear guidance", "remove the guidance strokes", self.clear_guidance),
        }
        self.branch_pick = widgets.IntSlider(value=0, min=0, max=0, description="branch",
                                             continuous_update=False, layout=widgets.Layout(width="320px"))
        self.steps = widgets.BoundedIntText(value=5, min=1, max=500, description="steps",
                                            layout=widgets.Layout(width="150px"))
        self.view = ImageView(width=360)
        self.hist_angle = HistogramCompare(bins=16, metric="l2sq", title="turning angle", width=520, height=150)
        self.hist_thick = HistogramCompare(bins=16, metric="l2sq", title="thickness", width=520, height=150)
        self.progress = ProgressBar("image")
        self.info = widgets.HTML()

        self.result = None  # SynthesisResult
        self.image_result = None
        self._model = None
        self._model_key = None

        self.panel.on_change(g(self._params_changed))
        self.seed.observe(g(lambda _: self._params_changed(None)), names="value")
        self.branch_pick.observe(g(lambda _: self._show()), names="value")
        self.canvas.model.observe(g(lambda _: self._invalidate()))
        if structure is not None:
            self.set_structure(structure)

        b = self.buttons
        left = widgets.VBox([
            widgets.HTML("<b>example</b>: one polyline per branch; start a child on a vertex of its parent; "
                         "<i>edit</i> to move vertices or change radii; <i>stroke</i> paints a guidance path"),
            self.canvas,
            widgets.HBox([b["extract"], b["refine"], b["delete"], b["clear_guidance"]],
                         layout=widgets.Layout(flex_flow="row wrap")),
        ])
        right = widgets.VBox([
            widgets.HBox([b["synthesize"], self.seed, self.auto, self.use_guidance],
                         layout=widgets.Layout(flex_flow="row wrap")),
            self.view,
            widgets.HBox([self.branch_pick, self.steps, b["extend"], b["delete_out"]],
                         layout=widgets.Layout(flex_flow="row wrap")),
            widgets.HBox([b["render"], self.progress]),
            self.info,
            self.hist_angle,
            self.hist_thick,
        ])
        super().__init__([
            widgets.HBox([left, right], layout=widgets.Layout(flex_flow="row wrap")),
            widgets.Accordion(children=[self.panel, self.image_panel],
                              titles=("structure synthesis parameters", "image synthesis parameters")),
            self.errors,
        ])

    # -- the example --------------------------------------------------------
    @property
    def params(self) -> SynthesisParams:
        return self.panel.values

    def example_structure(self) -> Structure:
        """The structure drawn on the canvas (one branch per polyline)."""
        s, _ = annotations_to_structure(self.canvas.model.shapes, self.image_shape)
        return s

    def set_structure(self, structure: Structure) -> None:
        """Show ``structure`` on the canvas (replaces the polylines, keeps the guidance strokes; undoable)."""
        if not isinstance(structure, Structure):
            raise TypeError(f"structure must be a Structure, got {type(structure).__name__}")
        structure.check_inside(self.image_shape)
        strokes = [s for s in self.canvas.model.shapes if s.kind == "stroke"]
        self.canvas.model.load_json(structure_to_annotations(structure, keep=strokes))

    def extract(self, **overrides) -> Structure:
        """Run :func:`~branchnb.branching.extract_structure` and put the result on the canvas."""
        kw = {"h": self.params.h, "scale": 0.5 if max(self.image_shape) > 600 else 1.0}
        kw.update(overrides)
        s = extract_structure(self.image, **kw)
        if not s.branches:
            raise ValueError("no branch found: try another polarity or a lower threshold")
        self.set_structure(s)
        self.info.value = f"extracted {len(s.branches)} branches, {s.n_vertices} vertices"
        return s

    def refine(self, params: ClickParams | None = None) -> Structure:
        """The paper's input step: resample each polyline at ``h`` and measure its thickness."""
        p = params if params is not None else ClickParams(h=self.params.h)
        shapes = self.canvas.model.shapes
        s, index = annotations_to_structure(shapes, self.image_shape)
        if not s.branches:
            raise ValueError("draw at least one polyline (two clicks or more) first")
        gray = gray_for_extraction(self.image)
        new = []
        for b in s.branches:
            pts = b.points
            if len(pts) >= 2 and np.hypot(*(pts[-1] - pts[0])) + 1e-9 >= p.h / 2:
                pts = resample_uniform(b.points, p.h, include_end=True)
            r = estimate_thickness(gray, pts, max_radius=p.max_radius, min_radius=p.min_radius,
                                   sigma=p.sigma, smooth=p.smooth) if len(pts) >= 2 else b.thickness
            new.append((pts, r))
        st = s.with_polylines(new)
        st.image_shape = self.image_shape
        self.set_structure(st)
        return st

    def delete_selected_subbranch(self) -> Structure:
        """Delete the branch selected in ``edit`` mode and all its descendants."""
        sel = self.canvas.selected
        if sel is None:
            raise ValueError("select a vertex of the branch first (edit mode)")
        s, index = annotations_to_structure(self.canvas.model.shapes, self.image_shape)
        if sel[0] not in index:
            raise ValueError("the selection is not a branch polyline")
        out = s.remove_subtree(index.index(sel[0]))
        self.canvas.selected = None
        self.set_structure(out)
        return out

    def guidance(self) -> Guidance | None:
        """A guidance map from the last freehand stroke (None if there is none or it is switched off)."""
        strokes = [s for s in self.canvas.model.shapes if s.kind == "stroke" and len(s.points) >= 2]
        if not strokes or not self.use_guidance.value:
            return None
        return Guidance.from_path(self.image_shape, strokes[-1].points, width=self.params.guidance_width)

    def clear_guidance(self) -> None:
        keep = [s.to_dict() for s in self.canvas.model.shapes if s.kind != "stroke"]
        self.canvas.model.load_json(json.dumps({"version": 1, "shapes": keep}))

    # -- synthesis ------------------------------------------------------------
    def _invalidate(self) -> None:
        self._model = None

    def _fitted(self, params: SynthesisParams):
        ex = self.example_structure()
        key = (ex.to_json(), params.h, params.m, params.k, params.bins, params.svm_C)
        if self._model is None or self._model_key != key:
            self._model = fit_model(ex, params)
            self._model_key = key
        return self._model

    def _params_changed(self, _values) -> None:
        if self.auto.value and self.result is not None:
            self.synthesize()

    def synthesize(self):
        """Grow a new structure from the example with the panel's parameters and seed."""
        p = self.params
        model = self._fitted(p)
        self.result = synthesize_structure(model, p, rng=int(self.seed.value), guidance=self.guidance(),
                                           shape=self.image_shape)
        self.image_result = None
        self._after_change()
        return self.result

    def extend(self, branch: int | None = None, steps: int | None = None):
        """Grow one branch of the synthesized structure further (``steps`` Markov steps)."""
        if self.result is None:
            raise ValueError("synthesize a structure first")
        b = int(self.branch_pick.value if branch is None else branch)
        n = int(self.steps.value if steps is None else steps)
        p = self.params
        res = extend_branch(self.result.structure, b, self._fitted(p), p, n_steps=n,
                            rng=int(self.seed.value) + 7919 * (b + 1), guidance=self.guidance())
        self.result = res
        self.image_result = None
        self._after_change(keep_pick=b)
        return res

    def delete_output_branch(self, branch: int | None = None):
        """Delete a branch of the synthesized structure with its children."""
        if self.result is None:
            raise ValueError("synthesize a structure first")
        b = int(self.branch_pick.value if branch is None else branch)
        s = self.result.structure.remove_subtree(b)
        import dataclasses

        self.result = dataclasses.replace(self.result, structure=s)
        self.image_result = None
        self._after_change()
        return self.result

    def render_image(self):
        """Synthesize the final image along the structure (fragment-based image synthesis)."""
        if self.result is None:
            raise ValueError("synthesize a structure first")
        self.progress.update(0.0, "starting")
        out = synthesize_image(self.image, self.example_structure(), self.result.structure,
                               params=self.image_panel.values,
                               rng=int(self.seed.value), progress=self.progress.update,
                               shape=self.image_shape)
        self.progress.done(f"done in {out.timings.get('total', 0.0):.1f} s")
        self.image_result = out
        self._show()
        return out

    # -- display ------------------------------------------------------------------
    def _after_change(self, keep_pick: int | None = None) -> None:
        n = len(self.result.structure.branches)
        self.branch_pick.max = max(n - 1, 0)
        if keep_pick is not None:
            self.branch_pick.value = min(keep_pick, max(n - 1, 0))
        self._show()
        ex, s = self.result.example, self.result.structure
        if s.branches and s.angles().size:
            ra = (float(ex.angles().min()), float(ex.angles().max()))
            rr = (float(ex.thicknesses().min()), float(ex.thicknesses().max()))
            self.hist_angle.update(ex.angles(), s.angles(), labels=["input", "synthesized"], range=ra)
            self.hist_thick.update(ex.thicknesses(), s.thicknesses(), labels=["input", "synthesized"], range=rr)
        d = self.result.diagnostics
        self.info.value = (
            f"<span style='font-family:monospace'>{d['n_branches']} branches, {d['n_vertices']} vertices, "
            f"{d['time_s'] * 1000:.0f} ms &nbsp;|&nbsp; stop: {d['stop_reason']}</span>")

    def _show(self) -> None:
        if self.result is None:
            return
        s = self.result.structure
        img = s.render(self.image_shape, by_generation=True, min_width=1.0)
        if s.branches:
            b = s.branches[min(self.branch_pick.value, len(s.branches) - 1)]
            from ..core.render import draw_polylines

            img = draw_polylines(img, [b.points], widths=[np.maximum(2 * b.thickness, 3.0)],
                                 colors=(0.9, 0.05, 0.05), alpha=0.8)
        images, titles = [img], ["synthesized structure (picked branch red)"]
        if self.image_result is not None:
            images.append(as_rgb(self.image_result.image))
            titles.append("synthesized image")
        self.view.update(images, titles)
