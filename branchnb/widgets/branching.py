"""BranchingApp: annotate an example's branches, synthesize new structures, render the image.

The app wires the widget kit to :mod:`branchnb.branching`:

- the example image in an :class:`AnnotationCanvas`: one polyline per
  branch (a polyline started on a vertex of another becomes its child),
  per-vertex radius in ``edit`` mode, freehand ``stroke`` = guidance path;
- "extract" fills the canvas with :func:`~branchnb.branching.extract_structure`,
  "refine clicks" resamples the clicked polylines and measures their
  thickness perpendicular to the branch (the paper's input step);
- the model is fitted inside the example's domain
  (:func:`~branchnb.branching.example_domain`: the image minus large
  branch-free flat regions such as a map's sea), so roots start on the same
  kind of boundary and the coverage target is measured where branches live;
- a :class:`ParamPanel` of :class:`~branchnb.branching.SynthesisParams`
  (m, k, c, wG, rho, d, generations, ...) grouped by the paper's steps,
  and a seed; changing them re-synthesizes (in the background inside a
  kernel, a newer change supersedes a running one): the view shows the
  skeleton growing with the new values (the partial structure from
  ``synthesize_structure(progress=...)``, first after
  :data:`PREVIEW_FIRST` s, then every :data:`PREVIEW_EVERY` s), then the
  finished structure replaces it; the "synthesize" button grows the same
  way in the background, with the progress in the status line and
  "cancel";
- the synthesized structure, with "extend branch" / "delete branch" on
  the branch picked by the slider, side-by-side angle and thickness
  histograms (input vs synthesized, the paper's evaluation), and "render
  image" (fragment-based image synthesis, with a progress bar; it runs in
  the background and "cancel" stops it between fragments).

The layout, busy state and status line are the kit's
:class:`~branchnb.widgets.shell.AppShell`.

Every action is a method (``extract``, ``refine``, ``synthesize``,
``extend``, ``delete_output_branch``, ``delete_selected_subbranch``,
``render_image``) so scripts and tests drive the app exactly as the
buttons do.
"""

from __future__ import annotations

import dataclasses
import json
import time

import ipywidgets as widgets
import numpy as np

from ..branching import (
    ClickParams,
    Guidance,
    ImageSynthesisParams,
    Structure,
    SynthesisParams,
    example_domain,
    extend_branch,
    extract_structure,
    fit_model,
    synthesize_image,
    synthesize_structure,
)
from ..branching.extraction import estimate_thickness, gray_for_extraction
from ..core.annotations import annotations_to_structure, structure_to_annotations
from ..core.image import as_float_image, as_rgb
from ..core.polyline import resample_uniform
from ..core.render import _sketch_polylines, draw_polylines
from ..core.structure_io import GENERATION_COLORS
from .canvas import AnnotationCanvas
from .feedback import Cancelled, ProgressBar
from .files import canvases_json, load_canvases
from .histograms import HistogramCompare
from .imageview import ImageView
from .params import ParamPanel
from .shell import AppShell

# The annotation <-> structure conversion lives in core (batch workers use it without ipywidgets);
# the two names stay importable from here.
__all__ = ["BranchingApp", "annotations_to_structure", "structure_to_annotations"]


# --------------------------------------------------------------------------
# the app
# --------------------------------------------------------------------------
#: Parameter groups (the paper's steps) and readable labels with the paper's symbols.
SYNTHESIS_SECTIONS = [
    ("input and Markov model", ["h", "m", "k", "bins", "c", "thickness_blend"]),
    ("global statistics", ["wG"]),
    ("furcations", ["d", "min_spacing", "mirror_children", "svm_C"]),
    ("space colonization", ["colonization", "rho", "inv_eps", "stop_density"]),
    ("roots", ["roots", "n_roots"]),
    ("guidance and stopping", ["guidance_width", "max_generations", "max_total_length",
                               "max_coverage", "fill_rounds", "branch_end", "max_branch_factor"]),
]
SYNTHESIS_LABELS = {
    "h": ("resampling step", "h"), "m": ("elements per step", "m"), "k": ("history length", "k"),
    "bins": ("histogram bins", "B"), "c": ("best candidates", "c"),
    "thickness_blend": ("blend radii at tips", ""), "wG": ("global histogram weight", "wG"),
    "d": ("furcations per branch", "d"), "min_spacing": ("furcation spacing", ""),
    "mirror_children": ("mirrored furcations", ""), "svm_C": ("SVM regularisation", "C"),
    "colonization": ("space colonization", ""), "rho": ("density radius", "\u03c1"),
    "inv_eps": ("density offset", "1/\u03b5"), "stop_density": ("stop at density", ""),
    "guidance_width": ("guidance width", ""), "max_generations": ("max generation", ""),
    "max_total_length": ("max total length", ""),
    "max_coverage": ("max coverage (0 = example's)", ""), "fill_rounds": ("fill-in rounds", ""),
    "roots": ("root starts", ""), "n_roots": ("roots (-1 = example's)", ""),
    "branch_end": ("branch end", ""), "max_branch_factor": ("max branch length", "\u00d7"),
}
IMAGE_SECTIONS = [
    ("fragments", ["lam", "radius_scale", "min_radius", "max_radius", "k", "w_s", "w_c", "c",
                   "shortlist", "source_density", "reverse"]),
    ("deformation and composition", ["displacement", "match_thickness", "displacement_step", "seams",
                                     "poisson", "anchors", "anchor_weight", "furcation_clear", "line_contrast",
                                     "relight_fragments"]),
    ("what is never copied", ["exclusion", "exclusion_margin", "avoid_unannotated", "avoid_salient",
                              "salient_z", "branch_like", "flatten_shading", "exclude_matte"]),
    ("flat-colour examples (maps, masks)", ["flat_drawing", "keep_regions", "flat_poisson"]),
    ("gap completion", ["completion", "patch_size", "patch_overlap", "completion_tolerance",
                        "completion_screen", "completion_rim", "min_free", "forbid_weight",
                        "relight_completion"]),
]
IMAGE_LABELS = {
    "lam": ("fragment spacing", "\u03bb"), "radius_scale": ("fragment radius / r", "s"),
    "min_radius": ("min fragment radius", ""), "max_radius": ("max fragment radius", ""),
    "k": ("samples per shape vector", "k"), "w_s": ("thickness weight", "wS"),
    "w_c": ("colour weight", "wC"), "c": ("best fragments", "c"), "shortlist": ("shortlist", ""),
    "source_density": ("source density", ""), "reverse": ("reversed fragments", ""),
    "displacement": ("bend onto skeleton", ""), "match_thickness": ("match width", ""),
    "displacement_step": ("displacement grid", ""), "seams": ("seams", ""),
    "poisson": ("Poisson correction", ""), "anchors": ("Poisson anchors", ""),
    "anchor_weight": ("anchor weight", ""), "furcation_clear": ("furcation clearing", ""),
    "line_contrast": ("line contrast (0 = off)", ""),
    "exclusion": ("exclusion / r", ""), "exclusion_margin": ("exclusion margin", ""),
    "avoid_unannotated": ("avoid unannotated", ""), "avoid_salient": ("avoid salient spots", ""),
    "salient_z": ("salient spot z", "z"), "branch_like": ("branch-like level", ""),
    "flatten_shading": ("flatten shading", ""), "exclude_matte": ("exclude matte", ""),
    "flat_drawing": ("draw like the example", ""),
    "keep_regions": ("keep map regions", ""), "flat_poisson": ("flat-colour Poisson", ""),
    "completion": ("complete gaps", ""), "relight_completion": ("relight gap patches", ""),
    "relight_fragments": ("relight fragments", ""),
    "patch_size": ("patch size", ""),
    "patch_overlap": ("patch overlap", ""), "completion_tolerance": ("completion tolerance", ""),
    "completion_screen": ("completion screen", ""), "completion_rim": ("completion rim", ""),
    "min_free": ("min free fraction", ""), "forbid_weight": ("forbid weight", ""),
}

#: After "synthesize" or a parameter change, the partial skeleton is first shown this many seconds into the
#: synthesis,
PREVIEW_FIRST = 0.03
#: then again every this many seconds until the finished structure replaces it.
PREVIEW_EVERY = 0.25

_PICK_HALO = (0.0, 0.0, 0.0)
_PICK_CORE = (1.0, 1.0, 1.0)


class BranchingApp(widgets.VBox):
    """Example-based synthesis of branching structures in a notebook.

    Parameters
    ----------
    image : (H, W, C) array_like
        The example image (grey, RGB or RGBA).
    structure : Structure, optional
        A starting annotation (e.g. from ``extract_structure``).
    params : SynthesisParams, optional
        Initial values of the parameter panel (the paper's defaults if None).
    max_display : int
        Long side of the example canvas in CSS pixels.
    display : int
        Width of the result views in CSS pixels.

    Attributes
    ----------
    result : SynthesisResult or None
        The last finished synthesis (what the view shows when idle).
    partial : Structure or None
        The last partial skeleton shown while a re-synthesis grew (None
        once the finished result replaced it).
    preview_first, preview_every : float
        When partial skeletons are shown (seconds; default
        :data:`PREVIEW_FIRST`, :data:`PREVIEW_EVERY`).

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
                 max_display: int = 380, display: int = 300):
        self.image = as_float_image(image, name="image")
        self.image_shape = self.image.shape[:2]
        if isinstance(display, bool) or not isinstance(display, int) or display < 64:
            raise ValueError(f"display must be an int >= 64 (pixels), got {display!r}")
        self.shell = AppShell(
            "Branching structures from an example",
            help="draw one polyline per branch (start a child on its parent's vertex), then "
                 "<b>synthesize</b>; sliders re-synthesize")
        status = self.errors = self.shell.status
        self.canvas = AnnotationCanvas(as_rgb(self.image), mode="polyline", max_display=max_display,
                                       modes=("polyline", "edit", "stroke", "pan"), errors=status)
        self.panel = ParamPanel(params if params is not None else SynthesisParams(), errors=status,
                                sections=SYNTHESIS_SECTIONS, labels=SYNTHESIS_LABELS,
                                closed=("furcations", "space colonization", "roots", "guidance and stopping"),
                                log=("max_total_length",), title="structure synthesis")
        # Image synthesis only runs on "render image", so its panel needs no callback.
        self.image_panel = ParamPanel(ImageSynthesisParams(), errors=status, sections=IMAGE_SECTIONS,
                                      labels=IMAGE_LABELS, closed=[t for t, _ in IMAGE_SECTIONS],
                                      title="image synthesis (render image)")
        self.seed = widgets.BoundedIntText(value=0, min=0, max=2**31 - 1, description="seed",
                                           tooltip="random seed of the synthesis",
                                           style={"description_width": "32px"},
                                           layout=widgets.Layout(width="130px"))
        self.auto = widgets.Checkbox(value=True, description="re-synthesize on change", indent=False,
                                     layout=widgets.Layout(width="auto"))
        self.use_guidance = widgets.Checkbox(value=True, description="use guidance path", indent=False,
                                             tooltip="the last freehand stroke on the example guides "
                                             "the growth", layout=widgets.Layout(width="auto"))
        sh = self.shell
        sh.add_action("synthesize", lambda: self._resynthesize(fresh=True), icon="play", primary=True,
                      background=True, cancellable=True,
                      tooltip="grow a new structure from the example (the growing skeleton shows "
                      "while it grows; cancel stops it)")
        sh.add_action("render image", lambda: self.render_image(progress=self.shell.progress), icon="image",
                      background=True, cancellable=True,
                      tooltip="synthesize the final image from fragments of the example "
                      "(slow; cancel stops it between fragments)")
        sh.add_action("extract", self.extract, icon="magic",
                      tooltip="find the example's structure automatically (ridge filter + skeleton)")
        sh.add_action("refine clicks", self.refine, tooltip="resample the polylines at step h and measure "
                      "the thickness perpendicular to each branch")
        sh.add_action("delete sub-branch", self.delete_selected_subbranch, icon="trash",
                      tooltip="example: delete the branch selected with select/move and its children")
        sh.add_action("clear guidance", self.clear_guidance, tooltip="remove the guidance strokes")
        sh.add_tool(self.seed, self.auto, self.use_guidance)
        self.buttons = {
            "synthesize": sh.buttons["synthesize"], "render": sh.buttons["render image"],
            "extract": sh.buttons["extract"], "refine": sh.buttons["refine clicks"],
            "delete": sh.buttons["delete sub-branch"], "clear_guidance": sh.buttons["clear guidance"],
        }
        self.branch_pick = widgets.IntSlider(value=0, min=0, max=0, description="branch",
                                             continuous_update=False, tooltip="output branch to extend "
                                             "or delete (outlined in the view)",
                                             style={"description_width": "initial"},
                                             layout=widgets.Layout(width="210px"))
        self.steps = widgets.BoundedIntText(value=5, min=1, max=500, description="steps",
                                            tooltip="Markov steps added by 'extend'",
                                            style={"description_width": "initial"},
                                            layout=widgets.Layout(width="110px"))
        extend = widgets.Button(description="extend", icon="plus", tooltip="grow the picked output "
                                "branch further", layout=widgets.Layout(width="auto"))
        extend.on_click(lambda _: sh.run("extend", self.extend))
        delete_out = widgets.Button(description="delete", icon="trash", tooltip="delete the picked "
                                    "output branch and its children", layout=widgets.Layout(width="auto"))
        delete_out.on_click(lambda _: sh.run("delete branch", self.delete_output_branch))
        self.buttons["extend"], self.buttons["delete_out"] = extend, delete_out
        status.add_run_buttons(extend, delete_out)
        self.display = int(display)
        self.view = ImageView(width=self.display, max_size=2 * self.display)
        self.hist_angle = HistogramCompare(bins=16, metric="l2sq", title="turning angle",
                                           width=self.display, height=120)
        self.hist_thick = HistogramCompare(bins=16, metric="l2sq", title="thickness",
                                           width=self.display, height=120)
        self.progress = ProgressBar("image")
        self.info = widgets.HTML()

        self.result = None  # SynthesisResult
        self.partial = None
        self._fit_shown = False  # the view shows the example while its model is fitted
        self.preview_first, self.preview_every = PREVIEW_FIRST, PREVIEW_EVERY
        self._growing = "growing with the new parameters"  # what a partial skeleton's title says
        self.image_result = None
        self._model = None
        self._model_key = None
        self._domain = None
        self._domain_key = None
        # The canvas' example as a structure and its JSON, per revision of the annotations (a
        # slider move re-synthesizes from the same example: converting it again cost 60-160 ms
        # of the first preview's 200 ms).
        self._example_rev = 0
        self._example_cache = None

        g = sh.guard
        self.panel.on_change(g(self._params_changed))
        self.seed.observe(g(lambda _: self._params_changed(None)), names="value")
        self.branch_pick.observe(g(lambda _: self._show()), names="value")
        self.canvas.model.observe(sh.guard(lambda _: self._invalidate(), action=False))
        if structure is not None:
            self.set_structure(structure)

        # The result's controls show once there is a result to extend or delete from.
        self.result_controls = widgets.HBox([self.branch_pick, self.steps, extend, delete_out],
                                            layout=widgets.Layout(flex_flow="row wrap", align_items="center",
                                                                  display="none"))
        sh.add_files(name="branching", open=self._open_images, outputs=self._outputs,
                     annotations=lambda: canvases_json({"example": self.canvas}, app="branching",
                                                       extra={"seed": int(self.seed.value)}),
                     load=self._load_annotations)
        sh.set_body(
            main=[self.canvas],
            result=[self.view, self.result_controls,
                    self.info, self.progress, self.hist_angle, self.hist_thick],
            sidebar=[self.panel, self.image_panel])
        super().__init__([sh])

    # -- the example --------------------------------------------------------
    @property
    def params(self) -> SynthesisParams:
        return self.panel.values

    def example_structure(self) -> Structure:
        """The structure drawn on the canvas (one branch per polyline)."""
        s, _ = annotations_to_structure(self.canvas.model.shapes, self.image_shape)
        return s

    def set_structure(self, structure: Structure) -> None:
        """Show ``structure`` on the canvas (replaces the polylines, keeps the guidance strokes; undoable).

        Parameters
        ----------
        structure : Structure
            The example structure, in pixels of the current image.

        Raises
        ------
        TypeError
            If ``structure`` is not a :class:`~branchnb.core.Structure`.
        ValueError
            If a vertex lies outside the image.
        """
        if not isinstance(structure, Structure):
            raise TypeError(f"structure must be a Structure, got {type(structure).__name__}")
        structure.check_inside(self.image_shape)
        strokes = [s for s in self.canvas.model.shapes if s.kind == "stroke"]
        self.canvas.model.load_json(structure_to_annotations(structure, keep=strokes))

    def extract(self, **overrides) -> str:
        """Run :func:`~branchnb.branching.extract_structure` and put the result on the canvas.

        Parameters
        ----------
        **overrides
            Keyword arguments of :func:`~branchnb.branching.extract_structure`
            (``line_colour``, ``mask``, fields of its parameters); by default
            the panel's ``h`` and, for images over 600 pixels, ``scale=0.5``.

        Returns
        -------
        str
            A summary for the status line (branches and vertices found).

        Raises
        ------
        ValueError
            If no branch was found.
        """
        kw = {"h": self.params.h, "scale": 0.5 if max(self.image_shape) > 600 else 1.0}
        kw.update(overrides)
        s = extract_structure(self.image, **kw)
        if not s.branches:
            raise ValueError("extract found no branch: try another polarity or a lower threshold")
        self.set_structure(s)
        return f"extracted {len(s.branches)} branches, {s.n_vertices} vertices"

    def refine(self, params: ClickParams | None = None) -> Structure:
        """The paper's input step: resample each polyline at ``h`` and measure its thickness.

        The clicked polylines are turned into a structure, each resampled at
        step ``h`` and given the thickness measured perpendicular to it in
        the image; the result replaces them on the canvas.

        Parameters
        ----------
        params : ClickParams, optional
            Resampling step and thickness search; the defaults with the
            panel's ``h`` if None.

        Returns
        -------
        Structure

        Raises
        ------
        ValueError
            If no polyline of two or more clicks is drawn.
        """
        p = params if params is not None else ClickParams(h=self.params.h)
        shapes = self.canvas.model.shapes
        s, index = annotations_to_structure(shapes, self.image_shape)
        if not s.branches:
            raise ValueError("refine: draw at least one polyline (two clicks or more) first")
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
        """Delete the branch selected in ``select/move`` mode and all its descendants."""
        sel = self.canvas.selected
        if sel is None:
            raise ValueError("delete sub-branch: first select a vertex of the branch "
                             "(tool 'select/move', click the branch)")
        s, index = annotations_to_structure(self.canvas.model.shapes, self.image_shape)
        if sel[0] not in index:
            raise ValueError("delete sub-branch: the selection is not a branch polyline")
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

    # -- files (the shell's open / save / load annotations) -------------------------------
    def set_image(self, image) -> None:
        """Use another example image: the annotations are cleared (undoable), the result goes.

        Parameters
        ----------
        image : (H, W, C) array_like
            Any layout :func:`branchnb.core.image.as_float_image` accepts.
        """
        img = as_float_image(image, name="image")
        self.image = img
        self.image_shape = img.shape[:2]
        had_result = self.result is not None
        self.result = self.partial = self.image_result = None
        self.canvas.set_image(as_rgb(img))
        self.canvas.model.clear()
        self._model = self._domain = self._domain_key = None
        self._example_rev += 1
        self.result_controls.layout.display = "none"
        if had_result:
            self.view.mark_stale("from the previous example")
        self.info.value = ""

    def _open_images(self, images) -> str:
        name, img = images[0]
        self.set_image(img)
        return "draw the branches (or press extract), then synthesize"

    def _outputs(self) -> dict:
        if self.result is None:
            return {}
        s = self.result.structure
        out = {"structure.json": s.to_json(), "structure.svg": s.to_svg(self.image_shape),
               "structure.png": s.render(self.image_shape, by_generation=True, min_width=1.0)}
        if self.image_result is not None:
            out["image.png"] = as_rgb(self.image_result.image)
        return out

    def _load_annotations(self, text) -> None:
        extra = load_canvases(text, {"example": self.canvas}, app="branching")
        if isinstance(extra.get("seed"), int) and extra["seed"] >= 0:
            self.seed.value = extra["seed"]

    def clear_guidance(self) -> None:
        """Remove the guidance strokes from the canvas (one undo step); the polylines stay."""
        keep = [s.to_dict() for s in self.canvas.model.shapes if s.kind != "stroke"]
        self.canvas.model.load_json(json.dumps({"version": 1, "shapes": keep}))

    # -- synthesis ------------------------------------------------------------
    def _invalidate(self) -> None:
        self._example_rev += 1
        self._model = None
        if self.result is not None and not self.view.stale:
            # the shown structure was grown from the example as it was (e.g. before "clear")
            self.view.mark_stale("out of date (the example changed; synthesize again)")

    def _example_and_json(self) -> tuple[Structure, str]:
        """The canvas' example and its JSON, converted once per revision of the annotations."""
        rev, cached = self._example_rev, self._example_cache
        if cached is None or cached[0] != rev:
            ex = self.example_structure()
            cached = (rev, ex, ex.to_json())
            self._example_cache = cached  # (a change meanwhile bumped the revision: redone next time)
        return cached[1], cached[2]

    def _fitted(self, params: SynthesisParams, progress=None):
        """The model of the canvas' example (cached); ``progress(fraction, text)`` while fitting."""
        ex, text = self._example_and_json()
        if not ex.branches:
            raise ValueError("the example is empty: draw a branch (polyline tool) or press 'extract'")
        key = (text, params.h, params.m, params.k, params.bins, params.svm_C)
        if self._model is None or self._model_key != key:
            report = progress if progress is not None else (lambda fraction, text: None)
            if self._domain_key != text:
                if progress is not None:  # at once: the example (its domain follows in a second or so)
                    self._show_example(ex, None)
                    self._fit_shown = True
                report(0.0, "fitting: finding where the example's branches live")
            dom = self.domain(ex, _text=text)
            report(0.3, "fitting the model to the example")
            if progress is not None:
                self._show_example(ex, dom)
                self._fit_shown = True
            self._model = fit_model(ex, params, domain=dom, progress=lambda f, t: report(
                0.3 + 0.7 * f, f"fitting the model to the example: {t}"))
            self._model_key = key
            self._fit_shown = False
        return self._model

    def domain(self, structure: Structure | None = None, *, _text: str | None = None) -> np.ndarray:
        """Where the example's branches live ((H, W) bool): :func:`~branchnb.branching.example_domain`.

        The image minus its large branch-free flat regions (the sea around a
        river map's land, the wide water of a delta mask); the whole frame
        for a photo. The model learns where roots start relative to its
        boundary, and synthesis grows inside it. Cached per structure.

        Parameters
        ----------
        structure : Structure, optional
            The example structure; the canvas's by default.

        Returns
        -------
        (H, W) bool ndarray
        """
        ex = self.example_structure() if structure is None else structure
        text = ex.to_json() if _text is None else _text
        if self._domain_key != text:
            self._domain = example_domain(self.image, ex)
            self._domain_key = text
        return self._domain

    def _params_changed(self, _values) -> None:
        if self.auto.value and self.result is not None:
            self.shell.live("synthesize", self._resynthesize, stale=self._mark_stale)

    def _mark_stale(self) -> None:
        self.view.set_title(0, "out of date: re-synthesizing with the new parameters ...")

    def _resynthesize(self, fresh: bool = False):
        """Synthesis with partial skeletons while it grows, then the result (the "synthesize"
        button, ``fresh``, and every parameter change).

        The shell's progress is reported between Markov steps, so "cancel"
        or a newer change stops this one (before its result is shown). The
        first synthesis of an example fits its model first (seconds on a
        large example): the view shows the example's structure over its
        domain at once, the status line the fitting step, and "cancel"
        stops between the steps (the furcation SVM, half the fit, is one
        step). Partial skeletons are quick sketches at the view's width
        (a few ms; the first one after :data:`PREVIEW_FIRST`). A cancelled
        or failed synthesis takes its partial skeleton (or the example shown
        during the fit) off the view and shows the last finished structure
        again.
        """
        try:
            return self._grow_with_previews(fresh)
        except Cancelled:
            if fresh:  # (a superseded slider update: the newer one shows its own skeleton)
                self._drop_partial()
            raise
        except Exception:
            self._drop_partial()
            raise

    def _drop_partial(self) -> None:
        """Take a growing skeleton nobody will finish off the view (the last result shows again)."""
        if self.partial is None and not self._fit_shown:
            return
        self.partial, self._fit_shown = None, False
        if self.result is not None:
            self._after_change()
        else:
            self.view.update([], [])
            self.info.value = ""

    def _grow_with_previews(self, fresh: bool):
        t0 = time.perf_counter()
        due = {"preview": t0 + self.preview_first, "status": t0}
        self._growing = "growing" if fresh else "growing with the new parameters"

        def watch(growth):
            now = time.perf_counter()
            if growth.done or now >= due["status"]:
                self.shell.progress(growth.fraction, "growing")  # raises Cancelled when superseded
                due["status"] = now + 0.1
            if not growth.done and now >= due["preview"]:
                self._show_partial(growth)
                due["preview"] = time.perf_counter() + self.preview_every

        return self.synthesize(progress=watch, fit_progress=self._fit_progress)

    def _fit_progress(self, fraction: float, text: str) -> None:
        self.shell.progress(fraction, text)  # raises Cancelled on "cancel"

    def _sketch(self, structure: Structure, background=None) -> np.ndarray:
        """A growing skeleton at the view's width (a few ms: what a preview can afford)."""
        st = structure
        pal = np.asarray(GENERATION_COLORS, np.float32)
        colors = pal[np.minimum([st.generation(i) for i in range(len(st.branches))], len(pal) - 1)] \
            if st.branches else pal[:1]
        return _sketch_polylines(self.image_shape, [b.points for b in st.branches],
                                 [np.maximum(2 * b.thickness, 1.0) for b in st.branches], colors,
                                 max_size=self.display, background=background)

    def _show_example(self, example: Structure, domain: np.ndarray | None) -> None:
        """While the model is fitted: the example's structure over its domain (grey outside) once known."""
        n = len(example.branches)
        what = f"the example: {n} branch{'es' * (n != 1)}"
        if domain is None:
            self.view.update([self._sketch(example)], [f"{what} (finding its domain, then fitting the model; "
                                                       "the synthesized structure grows here next)"])
            return
        bg = np.where(domain, np.float32(1.0), np.float32(0.82))[..., None]
        self.view.update([self._sketch(example, np.repeat(bg, 3, axis=2))],
                         [f"{what}, grey = outside its domain "
                          "(fitting the model; the synthesized structure grows here next)"])

    def _show_partial(self, growth) -> None:
        what = self._growing
        s = growth.structure()
        self.partial, self._fit_shown = s, False
        n = len(s.branches)
        self.view.update([self._sketch(s)], [f"{what}: {n} branch{'es' * (n != 1)} so far "
                                             "(the finished structure follows)"])
        self.info.value = (f"<span style='font-size:12px'>growing: {n} branch{'es' * (n != 1)}, "
                           f"{s.n_vertices} vertices so far (attempt {growth.attempt})</span>")

    def synthesize(self, progress=None, fit_progress=None):
        """Grow a new structure from the example with the panel's parameters and seed.

        Parameters
        ----------
        progress : callable, optional
            ``progress(growth)``, passed on to
            :func:`~branchnb.branching.synthesize_structure` (partial
            skeletons while it grows; raising there stops it).
        fit_progress : callable, optional
            ``fit_progress(fraction, text)`` while the model of a new example
            is fitted (the first synthesis; seconds on a large example); the
            view shows the example's structure and domain meanwhile.

        Returns
        -------
        SynthesisResult
            Also kept as ``result`` and drawn.
        """
        p = self.params
        model = self._fitted(p, fit_progress)
        self.result = synthesize_structure(model, p, rng=int(self.seed.value), guidance=self.guidance(),
                                           shape=self.image_shape, progress=progress)
        self.partial = None
        self.image_result = None
        self._after_change()
        return self.result

    def extend(self, branch: int | None = None, steps: int | None = None):
        """Grow one branch of the synthesized structure further (``steps`` Markov steps).

        Parameters
        ----------
        branch : int, optional
            Branch of the result to extend; the branch picker's value by default.
        steps : int, optional
            Number of Markov steps (of length ``h``); the steps box's value by
            default.

        Returns
        -------
        SynthesisResult
            The new result (kept as ``result``).

        Raises
        ------
        ValueError
            If nothing was synthesized yet.
        """
        if self.result is None:
            raise ValueError("extend: synthesize a structure first")
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
        """Delete a branch of the synthesized structure with its children.

        Parameters
        ----------
        branch : int, optional
            Branch of the result; the branch picker's value by default.

        Returns
        -------
        SynthesisResult
            The new result (kept as ``result``).

        Raises
        ------
        ValueError
            If nothing was synthesized yet, or the index is out of range.
        """
        if self.result is None:
            raise ValueError("delete branch: synthesize a structure first")
        b = int(self.branch_pick.value if branch is None else branch)
        s = self.result.structure.remove_subtree(b)
        self.result = dataclasses.replace(self.result, structure=s)
        self.image_result = None
        self._after_change()
        return self.result

    def render_image(self, progress=None):
        """Synthesize the final image along the structure (fragment-based image synthesis).

        ``progress(fraction, text)`` is called between fragments (the
        button passes the shell's, which stops the work on "cancel"). The
        progress bar says "failed" or "cancelled" when the work does not
        finish.

        Parameters
        ----------
        progress : callable, optional
            ``progress(fraction, text)``, fraction in [0, 1].

        Returns
        -------
        ImageSynthesisResult
            The synthesized image with its fragments and timings (kept as
            ``image_result`` and shown).

        Raises
        ------
        ValueError
            If nothing was synthesized yet.
        """
        if self.result is None:
            raise ValueError("render image: synthesize a structure first")

        def report(fraction, text=""):
            if progress is not None:
                progress(fraction, text)
            self.progress.update(fraction, text)

        self.progress.update(0.0, "starting")
        try:
            out = synthesize_image(self.image, self.example_structure(), self.result,
                                   params=self.image_panel.values, rng=int(self.seed.value),
                                   progress=report, shape=self.image_shape)
        except Exception as exc:
            self.progress.fail("cancelled" if type(exc).__name__ == "Cancelled" else
                               f"failed: {type(exc).__name__}")
            raise
        self.progress.done(f"done in {out.timings.get('total', 0.0):.1f} s")
        self.image_result = out
        self._show()
        return out

    # -- display ------------------------------------------------------------------
    def _after_change(self, keep_pick: int | None = None) -> None:
        self.result_controls.layout.display = None
        s = self.result.structure
        n = len(s.branches)
        self.branch_pick.max = max(n - 1, 0)
        if keep_pick is not None:
            self.branch_pick.value = min(keep_pick, max(n - 1, 0))
        self._show()
        ex = self.result.example
        if s.branches and s.angles().size:
            ra = (float(ex.angles().min()), float(ex.angles().max()))
            rr = (float(ex.thicknesses().min()), float(ex.thicknesses().max()))
            self.hist_angle.update(ex.angles(), s.angles(), labels=["input", "synthesized"], range=ra)
            self.hist_thick.update(ex.thicknesses(), s.thicknesses(), labels=["input", "synthesized"], range=rr)
        d = self.result.diagnostics
        # Counts from the structure shown (diagnostics describe the last synthesis step only).
        cov, target = d.get("coverage"), d.get("coverage_target")
        coverage = "" if cov is None or target is None else \
            f" &nbsp;|&nbsp; coverage {cov:.0%} of target {target:.0%}"
        self.info.value = (
            f"<span style='font-size:12px'>{n} branches, {s.n_vertices} vertices &nbsp;|&nbsp; "
            f"last step {d.get('time_s', 0.0) * 1000:.0f} ms, stop: {d.get('stop_reason', '-')}"
            f"{coverage}</span>")

    def _show(self) -> None:
        if self.result is None:
            return
        s = self.result.structure
        img = s.render(self.image_shape, by_generation=True, min_width=1.0)
        title = "synthesized structure (colour = generation)"
        if s.branches:
            k = min(self.branch_pick.value, len(s.branches) - 1)
            b = s.branches[k]
            w = np.maximum(2 * b.thickness, 2.0)
            # A black halo and a white core: visible whatever the generation colours.
            img = draw_polylines(img, [b.points], widths=[w + 6.0], colors=_PICK_HALO, alpha=1.0)
            img = draw_polylines(img, [b.points], widths=[w + 2.0], colors=_PICK_CORE, alpha=1.0)
            title += f"; branch {k} outlined"
        images, titles = [img], [title]
        if self.image_result is not None:
            images.append(as_rgb(self.image_result.image))
            titles.append("synthesized image")
        self.view.update(images, titles)
