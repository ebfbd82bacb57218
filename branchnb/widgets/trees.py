"""TreeVariationsApp: mix library trees with sliders, morph, "more like this", recolour.

A thin app over :mod:`branchnb.trees`:

* **library**: a thumbnail per exemplar with a checkbox; the checked trees
  are mixed;
* **mix**: one weight slider per checked tree, kept convex (moving one
  rescales the others so they still sum to 1), "random weights" (a
  Dirichlet draw from the rng seed), ``M`` (cage vertices, paper: 20), the
  colour mode (random convex combination as in the paper, or the shape
  weights), and a reference tree for histogram transfer. The result, the
  variation before recolouring and the reference are shown side by side,
  with the R, G and B histograms of reference, source and result and their
  distances to the reference;
* **morph**: two trees and a slider ``t`` (weights ``1 - t``, ``t``);
* **more like this**: a grid of random variations around the current mix
  (each keeps ``keep`` of its weights, the rest a random mix of trees drawn
  from the whole library, or of the checked trees only); "use" adopts one
  as the new mix;
* **segmentation**: the crown/trunk segmentation of a library tree on an
  annotation canvas; crown/trunk scribbles re-run the segmenter and the
  corrected trunk moves the tree's pin points (and so every mix using it);
* **billboard cloud** (when :mod:`branchnb.trees.billboard` is available):
  the cloud of the current variation or of a library tree, seen from any
  yaw angle.

Every callback is guarded: errors are shown in the app's status line (the
kit's :class:`~branchnb.widgets.shell.AppShell`) and the app keeps working.
Everything the widgets do is a method callable from
Python (``select``, ``set_weight``, ``random_weights``, ``set_morph``,
``more_like_this``, ``adopt``, ``segment``, ``build_cloud``, ``set_yaw``).
"""

from __future__ import annotations

import dataclasses

import cv2
import ipywidgets as widgets
import numpy as np

from ..core.image import composite_over
from ..core.io import encode_png
from ..trees.histogram_transfer import histogram_transfer, opaque_pixels
from ..trees.morph import dirichlet_weights
from ..trees.variations import (
    TreeLibrary,
    Variation,
    VariationParams,
    make_variation,
    small_library_keep,
)
from .canvas import AnnotationCanvas
from .files import canvases_json, load_canvases
from .histograms import HistogramCompare, channel_range
from .imageview import ImageView
from .params import ParamPanel
from .shell import AppShell
from .trees_tabs import HAS_BILLBOARD, _SegmentCloudTabs
from .weights import convex_update

__all__ = ["TreeVariationsApp", "convex_update", "channel_range"]

#: Scribble labels of the segmentation canvas and their colours.
SEG_LABELS = {"trunk": "#c62828", "crown": "#2e7d32"}

#: Extra histogram-transfer references offered besides the library trees.
REFERENCES = ("maple_leaf_03", "maple_leaf_01", "tree_cutout_broadleaf", "evergreen")


#: A row of controls that wraps instead of squeezing them (layout of the tabs' control rows).
_WRAP_ROW = {"flex_flow": "row wrap", "align_items": "center"}


def _thumb(image, size: int) -> np.ndarray:
    return cv2.resize(composite_over(image, (1.0, 1.0, 1.0)), (size, size),
                      interpolation=cv2.INTER_AREA)


class TreeVariationsApp(_SegmentCloudTabs, widgets.VBox):
    """Interactive image-based tree variations.

    Parameters
    ----------
    library : TreeLibrary, optional
        Processed exemplars (default: the 14 RPG sprites at 512 x 512).
    selected : sequence of str, optional
        Trees checked at start (default: the first two).
    display : int
        Display width of each result image (screen pixels).
    thumb : int
        Side of the library thumbnails in CSS pixels (>= 16).
    references : sequence of str
        Sample names offered as histogram-transfer references besides the
        library trees.

    Attributes
    ----------
    variation : Variation or None
        The current mix (after histogram transfer, if a reference is set).
    source : Variation or None
        The same mix before histogram transfer.
    morph_result : Variation or None
    similar : list of Variation

    Examples
    --------
    >>> lib = TreeLibrary.from_data(["tree_rpg_01", "tree_rpg_03"], size=128)
    >>> app = TreeVariationsApp(lib)
    >>> app.set_weight("tree_rpg_01", 0.75)
    >>> app.weights.tolist()
    [0.75, 0.25]
    """

    def __init__(self, library: TreeLibrary | None = None, *, selected=None, display: int = 256,
                 thumb: int = 72, references=REFERENCES):
        for arg, v, lo in (("display", display, 64), ("thumb", thumb, 16)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < lo:
                raise ValueError(f"{arg} must be an int >= {lo} (pixels), got {v!r}")
        self.library = library if library is not None else TreeLibrary.from_data(size=512)
        if not isinstance(self.library, TreeLibrary):
            raise TypeError(f"library must be a TreeLibrary, got {type(self.library).__name__}")
        if len(self.library) == 0:
            raise ValueError("library is empty: add trees first")
        names = self.library.names
        sel = list(selected) if selected is not None else names[:2]
        for n in sel:
            if n not in names:
                raise ValueError(f"selected: no tree named {n!r} in the library")
        self.shell = AppShell("Tree variations from a library",
                              help="check trees to mix them; weights, M and the reference update at "
                                   "once; <b>more like this</b> varies the current mix")
        self.errors = self.shell.status
        g = self.shell.guard
        self.variation: Variation | None = None
        self.source: Variation | None = None
        self.morph_result: Variation | None = None
        self.similar: list[Variation] = []
        self._syncing = False
        self._weights: dict[str, float] = {}

        # -- library thumbnails
        self.checks: dict[str, widgets.Checkbox] = {}
        self._thumb = int(thumb)
        cells = [self._library_cell(ex, ex.name in sel) for ex in self.library]
        self.thumbnails = widgets.HBox(cells, layout=widgets.Layout(flex_flow="row wrap"))

        # -- mix controls
        self.sliders_box = widgets.VBox()
        self.sliders: dict[str, widgets.FloatSlider] = {}
        self.panel = ParamPanel(VariationParams, errors=self.errors, hide=("keep",), labels={
            "m_points": ("cage vertices", "M"), "n_mix": ("trees per random mix", ""),
            "concentration": ("shape concentration", "\u03b1"),
            "colour_concentration": ("colour concentration", "\u03b1c"),
            "colour_mode": ("colour mixing", ""), "region_scale": ("colour region size", ""),
            "seam": ("seam weight", ""), "choose_by": ("choose by", "")}, title="variation parameters")
        self.m_points = self.panel.controls["m_points"]
        self.panel.on_change(g(lambda _p: self._live_update()))
        self.rng = widgets.BoundedIntText(value=0, min=0, max=2**31 - 1, description="seed",
                                          tooltip="random seed", style={"description_width": "32px"},
                                          layout=widgets.Layout(width="120px"))
        self.colour_mode = widgets.Dropdown(options=[("random (paper)", "random"),
                                                     ("= shape weights", "shape")],
                                            value="random", description="colour")
        refs = [("none", None)] + [(n, n) for n in names] + [(n, n) for n in references
                                                             if n not in names]
        self.reference = widgets.Dropdown(options=refs, index=0, description="reference",
                                          tooltip="histogram transfer of the colours to this image",
                                          style={"description_width": "64px"},
                                          layout=widgets.Layout(width="310px"))
        # "none" stays shown when the value is set to None from Python (index None = blank)
        self.reference.observe(lambda c: setattr(self.reference, "index", 0) if c["new"] is None else None,
                               names="index")
        self.colour_mode.layout.width = "310px"
        self.colour_mode.style.description_width = "64px"
        self.random_button = self.shell.add_action(
            "random weights", self.random_weights, icon="random",
            tooltip="Dirichlet weights for the checked trees from the seed")
        for w in (self.rng, self.colour_mode, self.reference):
            w.observe(g(lambda _c: self._live_update()), names="value")
        # Never wider than the trees themselves: a 128 px tree shown at 256 px is a
        # blurred, pixelated enlargement.
        disp = int(min(int(display), self.library.size))
        self._display = disp
        self.views = ImageView(width=disp, max_size=2 * disp)
        self.hists = [HistogramCompare(bins=24, metric="l1", title=f"{c} channel",
                                       width=max(3 * disp + 16, 400), height=110)
                      for c in ("red", "green", "blue")]
        self.status = widgets.HTML()
        mix = widgets.VBox([self.status, self.views, *self.hists])
        self._mix_controls = widgets.VBox([
            widgets.HTML("<b>weights</b> (kept convex)"), self.sliders_box,
            self.colour_mode, self.reference, self.panel])

        # -- morph
        self.morph_a = widgets.Dropdown(options=names, value=names[0], description="tree a")
        self.morph_b = widgets.Dropdown(options=names, value=names[min(1, len(names) - 1)],
                                        description="tree b")
        self.morph_t = widgets.FloatSlider(value=0.5, min=0.0, max=1.0, step=0.05,
                                           description="t", continuous_update=False)
        for w in (self.morph_a, self.morph_b, self.morph_t):
            w.observe(g(self._on_morph_widget), names="value")
        self.morph_view = ImageView(width=disp)
        # Fixed widths in a wrapping row: the tab is as wide as the column gives (min_width 0, so the
        # sidebar never jumps), and a flexible row squeezed the sliders' tracks to nothing.
        for w in (self.morph_a, self.morph_b):
            w.layout, w.style.description_width = widgets.Layout(width="200px"), "44px"
        self.morph_t.layout = widgets.Layout(width="260px", min_width="200px")
        morph = widgets.VBox([widgets.HBox([self.morph_a, self.morph_b, self.morph_t], layout=_WRAP_ROW),
                              self.morph_view])

        # -- more like this
        # A small library gets a smaller default keep, so its six variations can spread (as the API's keep=None).
        keep0 = round(small_library_keep(len(self.library.names)) / 0.05) * 0.05
        self.keep = widgets.FloatSlider(value=keep0, min=0.0, max=1.0, step=0.05, description="keep",
                                        continuous_update=False,
                                        tooltip="share of the current weights each variation keeps")
        self.n_similar = widgets.IntSlider(value=6, min=1, max=12, description="count",
                                           continuous_update=False)
        self.more_button = self.shell.add_action(
            "more like this", lambda: f"{len(self.more_like_this())} variations", icon="th", primary=True,
            tooltip="random variations around the current mix (tab 'more like this')")
        self.similar_library = widgets.Checkbox(
            value=True, description="draw from the whole library", indent=False,
            layout=widgets.Layout(width="auto"),
            tooltip="the random part of each variation may mix any library tree (off: only the "
                    "checked trees; two checked trees then give results on one line between them)")
        self.grid = widgets.HBox(layout=widgets.Layout(flex_flow="row wrap"))
        self.grid.add_class("bnb-view")
        self._grid_size = min(max(96, int(display) // 2), self.library.size)
        for w in (self.keep, self.n_similar):
            w.layout = widgets.Layout(width="240px", min_width="200px")
            w.style.description_width = "44px"
        similar = widgets.VBox([widgets.HBox([self.keep, self.n_similar, self.similar_library],
                                             layout=_WRAP_ROW),
                                self.grid])

        # -- segmentation (scribble correction)
        self.segmentation = None
        self._scribbles: dict[str, str] = {}
        self._loading_scribbles = False
        self.seg_tree = widgets.Dropdown(options=names, value=names[0], description="tree")
        self.seg_tree.observe(g(lambda _c: self._on_seg_tree()), names="value")
        # At most the trees' own size, like the views: a 128 px tree on a 384 px canvas was
        # drawn 6 device pixels per pixel, without smoothing (pixelated); the canvas zooms.
        self.seg_canvas = AnnotationCanvas(self.library[names[0]].image, mode="scribble",
                                           modes=("scribble", "pan"), labels=SEG_LABELS,
                                           max_display=max(64, min(int(max(256, 1.5 * display)),
                                                                   self.library.size)))
        self.seg_canvas.model.observe(g(self._on_scribble))
        self.seg_reset = widgets.Button(description="automatic", icon="undo",
                                        tooltip="drop the scribbles of this tree",
                                        layout=widgets.Layout(width="auto"))
        self.seg_reset.on_click(g(lambda _: self.seg_canvas.model.clear()))
        self.seg_status = widgets.HTML()
        self.seg_view = ImageView(width=disp)
        seg_tab = widgets.VBox([
            widgets.HBox([self.seg_tree, self.seg_reset], layout=_WRAP_ROW),
            widgets.HTML("scribble <b>trunk</b> (red) or <b>crown</b> (green) where the "
                         "segmentation is wrong; the pin points B, R, L follow"),
            widgets.HBox([self.seg_canvas, self.seg_view]), self.seg_status])

        children = [mix, morph, similar, seg_tab]
        titles = ["mix", "morph", "more like this", "segmentation"]

        # -- billboard cloud
        self.cloud = None
        if HAS_BILLBOARD:
            self.cloud_source = widgets.Dropdown(options=["current variation"] + names,
                                                 value="current variation", description="tree")
            self.cloud_button = widgets.Button(description="build cloud", icon="cubes",
                                               tooltip="build the billboard cloud (slow)",
                                               layout=widgets.Layout(width="auto"))
            self.cloud_button.on_click(lambda _: self.shell.run("build cloud", self.build_cloud,
                                                                background=True))
            self.errors.add_run_buttons(self.cloud_button)
            self.yaw = widgets.FloatSlider(value=30.0, min=-180.0, max=180.0, step=5.0,
                                           description="yaw", continuous_update=False)
            self.yaw.observe(g(lambda _c: self.set_yaw()), names="value")
            self.cloud_source.layout = widgets.Layout(width="240px")
            self.cloud_source.style.description_width = "36px"
            self.cloud_button.layout.min_width = "max-content"  # ("build ..." when squeezed)
            self.yaw.layout = widgets.Layout(width="260px", min_width="200px")
            self.cloud_view = ImageView(width=disp)
            self.cloud_status = widgets.HTML()
            children.append(widgets.VBox([
                widgets.HBox([self.cloud_source, self.cloud_button, self.yaw], layout=_WRAP_ROW),
                self.cloud_status, self.cloud_view]))
            titles.append("billboard cloud")

        # The tabs take the width the column gives them, whatever the selected tab holds
        # (min_width 0: a wide tab scrolls inside instead of widening the column), so the
        # sidebar beside them does not jump sideways when tabs switch.
        self.tabs = widgets.Tab(children=children,
                                layout=widgets.Layout(width="100%", min_width="0", overflow="auto"))
        for i, title in enumerate(titles):
            self.tabs.set_title(i, title)
        self.shell.add_tool(self.rng)
        self.shell.add_files(name="trees", open=self._open_images, open_label="add trees", multiple=True,
                             outputs=self._outputs, annotations=self._annotations, load=self._load_annotations)
        self.shell.set_body(main=[widgets.HTML("<b>library</b> (check the trees to mix)"),
                                  self.thumbnails, self.tabs],
                            sidebar=[self._mix_controls])
        self.shell.result.layout.display = "none"
        self.shell.sidebar.add_class("bnb-trees-sidebar")
        super().__init__([self.shell])
        self._rebuild_sliders()
        g(self.update)()
        g(self.set_morph)()
        g(self._show_segmentation)()

    # -- public API -------------------------------------------------------------
    @property
    def selected(self) -> list[str]:
        """Names of the checked trees, in library order."""
        return [n for n in self.library.names if self.checks[n].value]

    @property
    def weights(self) -> np.ndarray:
        """Shape weights of the checked trees (convex)."""
        return np.array([self._weights[n] for n in self.selected])

    def params(self) -> VariationParams:
        """The variation parameters of the panel (validated)."""
        return self.panel.values

    def select(self, names) -> None:
        """Check exactly these trees (weights reset to equal shares).

        Parameters
        ----------
        names : iterable of str
            Library tree names; all others are unchecked.

        Raises
        ------
        ValueError
            If a name is not in the library.
        """
        names = list(names)
        for n in names:
            if n not in self.checks:
                raise ValueError(f"no tree named {n!r} in the library")
        self._syncing = True
        try:
            for n, cb in self.checks.items():
                cb.value = n in names
        finally:
            self._syncing = False
        self._rebuild_sliders()
        self.update()

    def set_weights(self, weights) -> None:
        """Set all weights of the checked trees (dict or sequence; validated as convex).

        Parameters
        ----------
        weights : dict or sequence of float
            Tree name -> weight (missing checked trees get 0), or one weight
            per checked tree in their order; >= 0 and summing to 1.

        Raises
        ------
        ValueError
            If the weights are not convex or of the wrong length.
        """
        from ..trees.morph import check_weights

        sel = self.selected
        if isinstance(weights, dict):
            weights = [float(weights.get(n, 0.0)) for n in sel]
        w = check_weights(weights, len(sel))
        self._weights = dict(zip(sel, w))
        self._sync_sliders()
        self.update()

    def set_weight(self, name: str, value: float) -> None:
        """Move one slider; the others are rescaled to keep the weights convex.

        Parameters
        ----------
        name : str
            A checked tree.
        value : float
            Its new weight in [0, 1] (see :func:`convex_update`).

        Raises
        ------
        ValueError
            If the tree is not checked.
        """
        sel = self.selected
        if name not in sel:
            raise ValueError(f"{name!r} is not checked; check it first")
        w = convex_update(self.weights, sel.index(name), value)
        self._weights = dict(zip(sel, w))
        self._sync_sliders()
        self.update()

    def random_weights(self) -> None:
        """Draw Dirichlet weights for the checked trees from the rng seed."""
        sel = self.selected
        if not sel:
            raise ValueError("check at least one tree")
        p = VariationParams()
        w = dirichlet_weights(len(sel), p.concentration, rng=int(self.rng.value))
        self.set_weights(w)

    def update(self) -> None:
        """Recompute the mix and redraw the result, images and histograms."""
        with self.errors.catch():
            sel = self.selected
            if not sel:
                self._clear_mix()
                raise ValueError("check at least one tree of the library to mix")
            w = self.weights
            colour = "shape" if self.colour_mode.value == "shape" else None
            rng = int(self.rng.value)
            self.source = make_variation(self.library, w, self.params(), use=sel,
                                         colour_weights=colour, rng=rng)
            ref = self.reference.value
            if ref is None:
                self.variation = self.source
                dom = sel[int(np.argmax(w))]
                ref_img = self.library[dom].image
                images = [self.source.image, ref_img]
                titles = ["variation", f"largest weight: {dom}"]
                samples = (ref_img, self.source.image)
                labels = [dom, "variation"]
            else:
                ref_img = self._reference_image(ref)
                self.variation = dataclasses.replace(
                    self.source, image=histogram_transfer(self.source.image, ref_img),
                    reference=ref)
                images = [self.variation.image, self.source.image, ref_img]
                titles = ["result", "before transfer", f"reference: {ref}"]
                samples = (ref_img, self.source.image, self.variation.image)
                labels = ["reference", "source", "result"]
            self.views.update(images, titles)
            px = [opaque_pixels(s) for s in samples]
            for c, h in enumerate(self.hists):
                h.update(*[p[:, c] for p in px], labels=labels, range=channel_range(px, c))
            cw = self.variation.colour_weights
            self.status.value = (
                "shape: " + self.variation.label() + " &nbsp;|&nbsp; colour: "
                + " + ".join(f"{c:.2f} {n}" for n, c in zip(self.variation.names, cw) if c > 0)
                + f" &nbsp;|&nbsp; M = {self.params().m_points} &nbsp;|&nbsp; colours "
                + ("chosen per region" if self.variation.colour_mode == "choose" else "blended"))

    def set_morph(self, a: str | None = None, b: str | None = None, t: float | None = None) -> None:
        """Morph tree ``a`` into tree ``b`` at ``t`` (weights ``1 - t``, ``t``).

        Shape is mixed by the weights; the colours follow the shape weights.
        Errors are shown in the app's status line.

        Parameters
        ----------
        a, b : str, optional
            Library tree names; the dropdowns' current values if None.
        t : float, optional
            Morph parameter in [0, 1] (0 shows ``a``); the slider's value if None.
        """
        self._syncing = True
        try:
            if a is not None:
                self.morph_a.value = a
            if b is not None:
                self.morph_b.value = b
            if t is not None:
                self.morph_t.value = float(t)
        finally:
            self._syncing = False
        with self.errors.catch():
            a, b, t = self.morph_a.value, self.morph_b.value, float(self.morph_t.value)
            if a == b:
                self.morph_result = make_variation(self.library, [1.0], self.params(), use=[a])
            else:
                self.morph_result = make_variation(self.library, [1.0 - t, t], self.params(),
                                                   use=[a, b], colour_weights="shape")
            self.morph_view.update([self.library[a].image, self.morph_result.image,
                                    self.library[b].image],
                                   [f"a: {a}", f"t = {t:.2f}", f"b: {b}"])

    def more_like_this(self, n: int | None = None) -> list[Variation]:
        """Random variations around the current mix, shown in the grid.

        Parameters
        ----------
        n : int, optional
            Number of variations; the "how many" box's value if None.

        Returns
        -------
        list of Variation
            Also kept as ``similar``; empty (and an error shown) before the
            first mix.
        """
        with self.errors.catch():
            if self.variation is None:
                raise ValueError("no current variation to vary")
            count = int(self.n_similar.value if n is None else n)
            centre = self.variation
            if self.similar_library.value and len(centre.names) < len(self.library):
                # Every library tree in the centre (weight 0 for the unchecked ones), so the
                # random part can reach them: mixes of two checked trees otherwise all lie on
                # the line between the two (six results differ by a third of their distance).
                names = tuple(self.library.names)
                at = {n: i for i, n in enumerate(names)}
                w, cw = np.zeros(len(names)), np.zeros(len(names))
                for n, a, b in zip(centre.names, centre.weights, centre.colour_weights):
                    w[at[n]], cw[at[n]] = a, b
                centre = dataclasses.replace(centre, names=names, weights=w, colour_weights=cw)
            self.similar = self.library.similar(centre, count, self.params(),
                                                keep=float(self.keep.value),
                                                rng=int(self.rng.value) + 1)
            cells = []
            for i, v in enumerate(self.similar):
                g = self._grid_size  # sent at twice its CSS size: sharp on HiDPI screens too
                img = widgets.Image(value=encode_png(_thumb(v.image, 2 * g)), format="png",
                                    layout=widgets.Layout(width=f"{g}px", height=f"{g}px"))
                btn = widgets.Button(description=f"use {i + 1}", layout=widgets.Layout(width="auto"),
                                     tooltip=v.label())
                btn.on_click(self.errors.guard(lambda _b, i=i: self.adopt(i)))
                cells.append(widgets.VBox([img, btn], layout=widgets.Layout(align_items="center")))
            self.grid.children = cells
        return self.similar

    def adopt(self, index: int) -> None:
        """Make grid variation ``index`` the current mix (its shape weights).

        Parameters
        ----------
        index : int
            Position in the grid of :meth:`more_like_this`, from 0.

        Raises
        ------
        ValueError
            If ``index`` is out of range.
        """
        if not 0 <= index < len(self.similar):
            raise ValueError(f"index {index} out of range for {len(self.similar)} variations")
        v = self.similar[index]
        used = {n: w for n, w, c in zip(v.names, v.weights, v.colour_weights) if w > 0 or c > 0}
        self._syncing = True
        try:
            for n, cb in self.checks.items():
                cb.value = n in used
        finally:
            self._syncing = False
        total = sum(used.values())
        self._weights = {n: w / total for n, w in used.items()} if total > 0 else {
            n: 1.0 / len(used) for n in used}
        self._rebuild_sliders(keep_weights=True)
        self.update()

    # -- files (the shell's open / save / load annotations) ----------------------------
    def _library_cell(self, ex, checked: bool) -> widgets.VBox:
        """A library tree's thumbnail with its "mix" checkbox."""
        t = self._thumb
        # twice the pixels of its CSS size: sharp on HiDPI screens too
        img = widgets.Image(value=encode_png(_thumb(ex.image, 2 * t)), format="png",
                            layout=widgets.Layout(width=f"{t}px", height=f"{t}px"))
        cb = widgets.Checkbox(value=checked, description=ex.name, indent=False,
                              tooltip=f"mix {ex.name}", style={"description_width": "initial"},
                              layout=widgets.Layout(width="auto"))
        cb.observe(self.shell.guard(self._on_check), names="value")
        self.checks[ex.name] = cb
        return widgets.VBox([img, cb], layout=widgets.Layout(align_items="center", margin="0 4px"))

    def add_trees(self, images) -> list[str]:
        """Add ``(name, RGBA image)`` trees to the library and mix them (they become the checked ones).

        Parameters
        ----------
        images : iterable of (str, ndarray)
            Names and RGBA cut-outs (float in [0, 1]); a name already in the
            library gets a suffix ``_2``, ``_3``, ...

        Returns
        -------
        list of str
            The names the trees were added under. Two or more are mixed
            alone; a single one joins the checked trees.
        """
        added = []
        for name, img in images:
            base, k = str(name), 2
            while name in self.library.names:  # a second "tree.png" is kept as "tree_2"
                name, k = f"{base}_{k}", k + 1
            added.append(self.library.add(img, name).name)
        self.thumbnails.children = list(self.thumbnails.children) + [
            self._library_cell(self.library[n], False) for n in added]
        names = self.library.names
        for dd in (self.morph_a, self.morph_b, self.seg_tree):
            dd.options = names
        self.reference.options = [("none", None)] + [(n, n) for n in names] + [
            (o, o) for o, v in self.reference.options[1:] if o not in names]
        if HAS_BILLBOARD:
            self.cloud_source.options = ["current variation"] + names
        self.select(added if len(added) >= 2 else [*self.selected, *added])
        return added

    def _open_images(self, images) -> str:
        added = self.add_trees(images)
        return f"added {', '.join(added)} to the library and mixed them"

    def _outputs(self) -> dict:
        out = {}
        if self.variation is not None:
            out["variation.png"] = self.variation.image
            out["mix.json"] = {"trees": self.selected, "weights": [float(w) for w in self.weights],
                               "seed": int(self.rng.value)}
        if self.cloud is not None:
            import tempfile
            from pathlib import Path

            from ..trees.lod import export_full_gltf

            with tempfile.TemporaryDirectory() as tmp:
                # With a drawn tree's side-view outline (baked and on side cards), as the LOD chain's full level.
                path = export_full_gltf(self.cloud, Path(tmp) / "cloud.gltf", yaw=float(self.yaw.value))
                out["cloud.gltf"] = path.read_bytes()
        return out

    def _annotations(self) -> str:
        return canvases_json({"segmentation": self.seg_canvas}, app="trees", extra={
            "tree": self.seg_tree.value, "selected": self.selected,
            "weights": [float(w) for w in self.weights]})

    def _load_annotations(self, text) -> None:
        import json

        d = json.loads(text)
        tree = (d.get("extra") or {}).get("tree") if isinstance(d, dict) else None
        if tree is not None and tree not in self.library.names:
            raise ValueError(f"annotations: they are for the tree {tree!r}, which is not in the library")
        if tree is not None:
            self.seg_tree.value = tree
        extra = load_canvases(text, {"segmentation": self.seg_canvas}, app="trees")
        sel, w = extra.get("selected"), extra.get("weights")
        if isinstance(sel, list) and sel and set(sel) <= set(self.library.names):
            self.select(sel)
            if isinstance(w, list) and len(w) == len(sel):
                self.set_weights(w)

    # -- internals ----------------------------------------------------------------
    def _live_update(self) -> None:
        self.shell.live("mix", self.update)

    def _clear_mix(self) -> None:
        """No tree checked: nothing to show (no stale result, nothing to vary)."""
        self.variation = self.source = None
        self.similar = []
        self.views.update([], [])
        self.grid.children = []
        for h in self.hists:
            h.clear()
        self.status.value = "no tree checked"

    # -- internals (mix) ------------------------------------------------------------
    def _reference_image(self, ref: str) -> np.ndarray:
        if ref in self.library.names:
            return self.library[ref].image
        from .. import data

        return data.load(ref)

    def _on_morph_widget(self, _change) -> None:
        if not self._syncing:
            self.set_morph()

    def _on_check(self, _change) -> None:
        if self._syncing:
            return
        self._rebuild_sliders()
        self.update()

    def _rebuild_sliders(self, keep_weights: bool = False) -> None:
        sel = self.selected
        if not keep_weights:
            self._weights = {n: 1.0 / len(sel) for n in sel} if sel else {}
        self.sliders = {}
        for n in sel:
            s = widgets.FloatSlider(value=self._weights[n], min=0.0, max=1.0, step=0.01,
                                    description=n, continuous_update=False,
                                    style={"description_width": "96px"},
                                    layout=widgets.Layout(width="320px"))
            s.observe(self.errors.guard(lambda c, n=n: self._on_slider(n, c["new"])), names="value")
            s.add_class(f"bnb-weight-{n}")
            self.sliders[n] = s
        self.sliders_box.children = list(self.sliders.values())

    def _sync_sliders(self) -> None:
        self._syncing = True
        try:
            for n, s in self.sliders.items():
                s.value = round(float(self._weights[n]), 4)
        finally:
            self._syncing = False

    def _on_slider(self, name: str, value: float) -> None:
        if self._syncing:
            return
        with self.shell.busy("mix"):
            self.set_weight(name, value)
