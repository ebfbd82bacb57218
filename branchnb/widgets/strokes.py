"""StrokeEditApp: re-synthesize an object along new strokes, in a notebook.

A thin app over :mod:`branchnb.strokes`:

* two :class:`AnnotationCanvas` side by side: the **source image**, where
  you draw strokes along the object's skeleton, and the **target domain**
  (empty, or a background), where you draw where the parts should go.
  Draw freehand (``stroke``) or click vertices (``polyline``). The i-th
  source stroke pairs with the i-th target stroke: both are drawn in the
  same colour, with a dot at the start and an arrowhead at the end (the
  direction matters); "reverse" flips the last target stroke;
* **control points** (``point`` tool): a click near a source stroke and a
  click near its target stroke pair those two positions (in clicking
  order per stroke); unmatched clicks are listed in the status line;
* a :class:`ParamPanel` of :class:`~branchnb.strokes.StrokeEditParams`
  (patch size, sample spacing, search window, seam exponent, DP/greedy,
  graph cut/overlay, ...); the result updates on every change when
  "update on change" is ticked. The app keeps the fetched candidate
  patches (:class:`~branchnb.strokes.EditPatches` from
  :func:`~branchnb.strokes.fetch_patches`), so a change of a parameter
  the patches do not depend on (``seam_power``, seams following edges,
  shift prior, DP/greedy, graph cut/overlay) re-runs only sampling and
  composition (:func:`~branchnb.strokes.compose_patches`); when the edit
  still promises to be slow (over :data:`PREVIEW_AFTER` s) the same edit
  at reduced size is shown first;
* the result over the target canvas (under your strokes, seams optionally
  drawn in red); beside it an :class:`ImageView` with what the canvas does
  not show: the source with the pixels the result copies, and the patches
  of the result in a colour each with their seams; side-by-side
  histograms of the red, green and blue values of the source object region
  and of the result (:func:`~branchnb.strokes.compare_colours`).

Every action is a method (``add_stroke``, ``add_control_pair``,
``reverse_target``, ``edit``, ``clear``) so scripts and tests drive the
app exactly as the mouse does. Errors (a zero-length stroke, control
points out of order, ...) are shown in the error area; the app keeps
working.
"""

from __future__ import annotations

import dataclasses
import time

import cv2
import ipywidgets as widgets
import numpy as np

from ..core.image import as_float_image, as_rgba
from ..strokes import (
    EditPatches,
    StrokeEditParams,
    compare_colours,
    compose_patches,
    fetch_patches,
    pair_color_hex,
    stroke_markers,
)
from ..strokes.evaluation import CHANNELS
from .canvas import AnnotationCanvas
from .files import canvases_json, load_canvases
from .histograms import HistogramCompare
from .imageview import ImageView
from .params import ParamPanel
from .shell import AppShell

__all__ = ["StrokeEditApp", "strokes_from_shapes", "nearest_stroke"]

#: The canvases' tools (no vertex editing: freehand strokes have too many vertices to move one by one,
#: and four tools keep the toolbar on two rows beside the other canvas).
MODES = ("stroke", "polyline", "point", "pan")
_UNPAIRED = "#9e9e9e"

#: Parameter groups (the paper's steps) and readable labels.
SECTIONS = [
    ("patches and sampling", ["patch_size", "spacing", "sampling", "search_window", "search_across",
                              "search_step", "shift_penalty"]),
    ("composition (seams)", ["composition", "seam_power", "gradient_weighted"]),
    ("junctions", ["junction_tolerance", "extend_branches"]),
    ("parts nobody stroked (beyond the paper)", ["unstroked", "close_cuts", "centre_strokes",
                                                 "separate_ground"]),
]
LABELS = {
    "patch_size": ("patch size (0: auto)", "2r"), "spacing": ("spacing (0: auto)", "h"),
    "sampling": ("correspondences", ""), "search_window": ("search window", "W"),
    "search_across": ("search across", ""), "search_step": ("search step", ""),
    "shift_penalty": ("shift prior", "\u03bb"), "composition": ("stitching", ""),
    "seam_power": ("seam exponent", "p"), "gradient_weighted": ("seams follow edges", "/G"),
    "junction_tolerance": ("joint reach (0: auto)", ""), "extend_branches": ("extend branches", ""),
    "unstroked": ("unstroked parts", ""), "close_cuts": ("outline cut faces", ""),
    "centre_strokes": ("centre strokes on their part", ""),
    "separate_ground": ("cut out of a smooth ground", ""),
}

#: Title of the result view's second image (the target canvas shows the result itself).
PATCHES_TITLE = "patches (a colour each), seams red"

#: Strokes shorter than this (px, image pixels) are clicks, not strokes.
MIN_STROKE = 2.0

#: Long side (px) of the reduced-size edit shown while a slow full edit is computed.
PREVIEW_SIZE = 160
#: Sample spacing of the reduced-size preview when the edit's is automatic: above every
#: patch radius there, so h = r (the edit itself uses r / 2).
PREVIEW_SPACING = 128.0
#: An edit expected to take longer than this (s; from the last fetch and composition times)
#: gets a reduced-size preview first.
PREVIEW_AFTER = 0.15


def _check_target_shape(shape):
    if shape is None:
        return None
    if isinstance(shape, (str, bytes)) or not hasattr(shape, "__len__") or len(shape) != 2:
        raise ValueError(f"target_shape must be (height, width) in pixels, got {shape!r}")
    out = []
    for v in tuple(shape):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) and not (
                isinstance(v, (float, np.floating)) and float(v).is_integer()):
            raise ValueError(f"target_shape must be two whole numbers (height, width), got {shape!r}")
        if not 1 <= int(v) <= 8192:
            raise ValueError(f"target_shape sides must be in [1, 8192] pixels, got {shape!r}")
        out.append(int(v))
    return tuple(out)


def _check_background(background):
    if background is None:
        return None
    if isinstance(background, str):
        raise ValueError(f"background must be None, an RGB colour (3 numbers in [0, 1]) or an image, "
                         f"got the string {background!r}")
    a = np.asarray(background)
    if a.ndim == 3:
        return as_float_image(a, name="background")
    if a.ndim != 1 or len(a) not in (3, 4) or not np.issubdtype(a.dtype, np.number):
        raise ValueError(f"background must be None, an RGB colour (3 numbers in [0, 1]) or an image, "
                         f"got {background!r}")
    a = a.astype(np.float64)
    if not np.all(np.isfinite(a)) or a.min() < 0 or a.max() > 1:
        raise ValueError(f"background colour values must be in [0, 1], got {background!r}")
    return tuple(float(v) for v in a)


def strokes_from_shapes(shapes, *, snap: float = 20.0):
    """Strokes and control points drawn on one canvas.

    Parameters
    ----------
    shapes : sequence of Shape
        The canvas model's shapes.
    snap : float
        A point further than this (px) from every stroke belongs to none.

    Returns
    -------
    strokes : list of (N, 2) ndarray
        Freehand strokes and finished polylines with >= 2 points, in
        drawing order (open polylines are still being drawn and skipped).
    shape_index : list of int
        The shape index of each stroke.
    points : list of list of (2,) ndarray
        Per stroke, the control points clicked near it, in clicking order.
    stray : int
        Points near no stroke.

    Examples
    --------
    >>> from branchnb.widgets.model import Shape
    >>> shapes = [Shape("stroke", [(0, 0), (10, 0)]), Shape("point", [(5, 2)]), Shape("point", [(50, 50)])]
    >>> strokes, index, points, stray = strokes_from_shapes(shapes)
    >>> index, [p.tolist() for p in points[0]], stray
    ([0], [[5.0, 2.0]], 1)
    """
    strokes, index = [], []
    for i, s in enumerate(shapes):
        if s.kind in ("stroke", "polyline") and len(s.points) >= 2 and s.closed:
            strokes.append(np.asarray(s.points, float))
            index.append(i)
    points: list[list[np.ndarray]] = [[] for _ in strokes]
    stray = 0
    for s in shapes:
        if s.kind != "point":
            continue
        p = s.points[-1]
        best = nearest_stroke(strokes, p, snap=snap)
        if best is None:
            stray += 1
        else:
            points[best].append(np.asarray(p, float))
    return strokes, index, points, stray


def nearest_stroke(strokes, point, *, snap: float = 20.0) -> int | None:
    """Index of the stroke nearest to ``point`` if within ``snap`` px, else None.

    Distances are measured to the strokes' segments, not only their vertices.

    Parameters
    ----------
    strokes : sequence of (N_i, 2) ndarray
        Polylines (x, y) in image pixels, each with at least 2 vertices.
    point : (x, y)
        The click, in the same pixels.
    snap : float
        Largest distance in pixels that still picks a stroke.

    Returns
    -------
    int or None
        The nearest stroke's index (the later one on a tie).

    Examples
    --------
    >>> import numpy as np
    >>> strokes = [np.array([[0, 0], [10, 0]]), np.array([[0, 30], [10, 30]])]
    >>> nearest_stroke(strokes, (5, 26)), nearest_stroke(strokes, (5, 15), snap=10)
    (1, None)
    """
    p = np.asarray(point, float)
    best, best_d = None, snap
    for k, st in enumerate(strokes):
        a, b = st[:-1], st[1:]
        ab = b - a
        t = np.clip(((p - a) * ab).sum(1) / np.maximum((ab**2).sum(1), 1e-12), 0, 1)
        d = float(np.min(np.hypot(*(a + t[:, None] * ab - p).T)))
        if d <= best_d:
            best, best_d = k, d
    return best


def _checkerboard(shape, cell: int = 16) -> np.ndarray:
    h, w = shape
    yy, xx = np.mgrid[0:h, 0:w]
    board = ((yy // cell + xx // cell) % 2).astype(np.float32)
    return np.dstack([0.93 + 0.04 * board] * 3)


class StrokeEditApp(widgets.VBox):
    """Draw source and target strokes; see the object re-synthesized along the targets.

    Parameters
    ----------
    image : (H, W, C) array_like
        The source image: an RGBA object on a transparent background (the
        sample objects ``lizard``, ``rope_loop``, the bare trees) or an
        opaque image.
    target_shape : (H, W), optional
        Size of the target domain (default: the background's, or the
        source's).
    background : None, RGB colour or image, optional
        What the result is composed over (None: transparent).
    params : StrokeEditParams, optional
        Initial values of the parameter panel (the paper's defaults if None).
    max_display : int
        Long side of each canvas in screen pixels.

    Attributes
    ----------
    result : StrokeEditResult or None
        The last edit.
    patches : EditPatches or None
        The fetched candidate patches of the last edit (reused while the
        strokes and the fetch parameters stay the same).
    preview : StrokeEditResult or None
        The last reduced-size preview.
    preview_after : float
        Show a reduced-size preview first when the edit is expected to
        take longer than this (s; default :data:`PREVIEW_AFTER`).
    comparisons : list of HistogramComparison
        Red, green, blue histograms of the last edit.

    Examples
    --------
    >>> img = np.zeros((40, 80, 4), np.float32); img[15:25, 5:75] = (0.6, 0.4, 0.2, 1.0)
    >>> app = StrokeEditApp(img, max_display=200)
    >>> app.add_stroke("source", [(8, 20), (72, 20)])
    >>> app.add_stroke("target", [(40, 5), (40, 35)])
    >>> bool(app.result.mask[:, 40].sum() > 20)
    True
    """

    def __init__(self, image, *, target_shape=None, background=None,
                 params: StrokeEditParams | None = None, max_display: int = 300):
        self.image = as_float_image(image, name="image")
        target_shape = _check_target_shape(target_shape)
        background = _check_background(background)
        self.background = background
        if isinstance(background, np.ndarray) and background.ndim == 3:
            bg = background
            target_shape = bg.shape[:2] if target_shape is None else target_shape
            target_view = as_rgba(bg)
        else:
            target_shape = self.image.shape[:2] if target_shape is None else target_shape
            h, w = target_shape
            target_view = _checkerboard((h, w))
            if background is not None:
                target_view = np.broadcast_to(np.asarray(background, np.float32)[:3], (h, w, 3)).copy()
        self.target_shape = tuple(int(v) for v in target_shape)
        self.result = None
        self.preview = None
        self.patches: EditPatches | None = None
        self._patches_key = None
        self._preview_patches: EditPatches | None = None
        self._preview_key = None
        self.preview_after = PREVIEW_AFTER
        self.comparisons: list = []
        self.elapsed = 0.0
        self.stage_seconds = {"fetch": 0.0, "compose": 0.0}
        self._dropping = False
        self.shell = AppShell(
            "Stroke-based structure editing",
            help="draw strokes along the object on the <b>source</b>, then where each part goes on the "
                 "<b>target</b> (same order and direction: same colour = a pair)")
        status = self.errors = self.shell.status
        g = self.shell.guard

        self.source_canvas = AnnotationCanvas(self.image, mode="stroke", modes=MODES,
                                              max_display=max_display, errors=status)
        self.target_canvas = AnnotationCanvas(target_view, mode="stroke", modes=MODES,
                                              max_display=max_display, errors=status)
        self.canvases = {"source": self.source_canvas, "target": self.target_canvas}
        for c in self.canvases.values():
            c.model.observe(g(self._on_strokes))

        self.panel = ParamPanel(params if params is not None else StrokeEditParams(), errors=status,
                                sections=SECTIONS, labels=LABELS, title="stroke editing")
        self.panel.on_change(g(lambda _values: self._changed()))
        self.auto = widgets.Checkbox(value=True, description="update on change", indent=False,
                                     layout=widgets.Layout(width="auto"))
        self.show_seams = widgets.Checkbox(value=False, description="show seams", indent=False,
                                           layout=widgets.Layout(width="auto"))
        self.show_seams.observe(g(lambda _: self._show()), names="value")
        sh = self.shell
        sh.add_action("re-synthesize", self.edit, icon="play", primary=True,
                      tooltip="re-synthesize the object along the target strokes")
        sh.add_action("reverse last target", lambda: self.reverse_target(-1), icon="exchange",
                      tooltip="flip the direction of the last target stroke")
        sh.add_action("clear all", self.clear, icon="trash", run=False,
                      tooltip="remove all strokes and control points, and the result")
        sh.add_tool(self.auto, self.show_seams)
        sh.add_files(name="strokes", open=self._open_images, open_label="open source image",
                     outputs=self._outputs, load=lambda text: load_canvases(text, self.canvases, app="strokes"),
                     annotations=lambda: canvases_json(self.canvases, app="strokes"))
        self.buttons = {"edit": sh.buttons["re-synthesize"], "reverse": sh.buttons["reverse last target"],
                        "clear": sh.buttons["clear all"]}
        self.view = ImageView(width=int(0.6 * max_display), max_size=2 * max_display)
        self.hists = [HistogramCompare(bins=16, metric="l1", title=f"{ch} channel", width=max_display,
                                       height=110) for ch in CHANNELS]
        self.status = widgets.HTML(layout=widgets.Layout(width="100%"))
        sh.set_body(
            main=[widgets.HBox([
                widgets.VBox([widgets.HTML("<b>source image</b>"), self.source_canvas]),
                widgets.VBox([widgets.HTML("<b>target domain</b> (the result shows here)"),
                              self.target_canvas]),
            ], layout=widgets.Layout(flex_flow="row wrap")),
                self.status,
                widgets.HBox([self.view, widgets.VBox(self.hists)],
                             layout=widgets.Layout(flex_flow="row wrap"))],
            sidebar=[self.panel])
        self.shell.result.layout.display = "none"
        super().__init__([sh])
        self._on_strokes(None)

    # -- public API (what the mouse and buttons do) ---------------------------
    @property
    def params(self) -> StrokeEditParams:
        return self.panel.values

    def add_stroke(self, side: str, points) -> None:
        """Add a stroke on the ``"source"`` or ``"target"`` canvas (image pixels).

        Parameters
        ----------
        side : {"source", "target"}
            Which canvas: along the object, or where its part should go.
        points : (N, 2) array_like
            The stroke's vertices (x, y) in that canvas' image pixels, in
            drawing order (the direction matters for matching).
        """
        self._canvas(side).model.add_shape("stroke", points)

    def add_control_pair(self, source_xy, target_xy) -> None:
        """Click a control point near a source stroke and one near its target stroke.

        Parameters
        ----------
        source_xy : (x, y)
            Point on (or near) a source stroke, source image pixels.
        target_xy : (x, y)
            The corresponding point near its target stroke, target pixels.
        """
        self.source_canvas.model.add_shape("point", [tuple(map(float, source_xy))])
        self.target_canvas.model.add_shape("point", [tuple(map(float, target_xy))])

    def reverse_target(self, i: int = -1) -> None:
        """Flip the direction of target stroke ``i`` (one undo step).

        Parameters
        ----------
        i : int
            Index among the target strokes (negative counts from the end;
            the last drawn by default).

        Raises
        ------
        ValueError
            If there is no such target stroke.
        """
        _, index, _, _ = strokes_from_shapes(self.target_canvas.model.shapes)
        if not index:
            raise ValueError("there is no target stroke to reverse")
        if not -len(index) <= i < len(index):
            raise ValueError(f"target stroke {i} does not exist ({len(index)} strokes)")
        model = self.target_canvas.model
        shape = model.shapes[index[i]]
        pts = shape.points[::-1].copy()
        model.load_json({"version": 1, "shapes": [
            dict(s.to_dict(), points=pts.tolist()) if k == index[i] else s.to_dict()
            for k, s in enumerate(model.shapes)]})

    def set_image(self, image) -> None:
        """Edit another source object: its strokes, the targets and the result are cleared.

        Parameters
        ----------
        image : (H, W, C) array_like
            Any layout :func:`branchnb.core.image.as_float_image` accepts
            (RGBA keeps the object's cut-out).
        """
        self.image = as_float_image(image, name="image")
        self.source_canvas.set_image(self.image)
        self._patches_key = self._preview_key = None
        self.clear()

    def _open_images(self, images) -> str:
        self.set_image(images[0][1])
        return "draw strokes along the object, then where its parts go on the target"

    def _outputs(self) -> dict:
        return {} if self.result is None else {"result.png": self.result.image}

    def clear(self) -> None:
        """Remove every stroke and control point (undoable on each canvas) and the result."""
        self.result = self.preview = None
        self.patches = self._preview_patches = None
        self.comparisons = []
        for c in self.canvases.values():
            c.model.clear()
        self.view.update([], [])
        for h in self.hists:
            h.clear()
        self._target_overlay()

    def strokes(self):
        """``(source_strokes, target_strokes, control_points, notes)`` as drawn.

        ``control_points`` has one entry per pair (None or
        ``(source_points, target_points)``, the first ``min`` clicks near
        both strokes); ``notes`` lists what is incomplete.
        """
        src, _, src_pts, src_stray = strokes_from_shapes(self.source_canvas.model.shapes)
        tgt, _, tgt_pts, tgt_stray = strokes_from_shapes(self.target_canvas.model.shapes)
        notes = []
        if len(src) > len(tgt):
            notes.append(f"draw {len(src) - len(tgt)} more target stroke(s)")
        elif len(tgt) > len(src):
            notes.append(f"draw {len(tgt) - len(src)} more source stroke(s)")
        control = []
        for k in range(min(len(src), len(tgt))):
            n = min(len(src_pts[k]), len(tgt_pts[k]))
            if len(src_pts[k]) != len(tgt_pts[k]):
                notes.append(f"pair {k}: {len(src_pts[k])} source vs {len(tgt_pts[k])} target "
                             "control points (extra ones ignored)")
            control.append(None if n == 0 else (np.array(src_pts[k][:n]), np.array(tgt_pts[k][:n])))
        if src_stray or tgt_stray:
            notes.append(f"{src_stray + tgt_stray} control point(s) near no stroke (ignored)")
        return src, tgt, control, notes

    def edit(self):
        """Run :func:`~branchnb.strokes.edit_structure` on the strokes drawn; returns the result.

        As its two stages: :func:`~branchnb.strokes.fetch_patches` only when
        the strokes or a fetch parameter changed (else ``patches`` is
        reused), then :func:`~branchnb.strokes.compose_patches` (the same
        result as ``edit_structure``; ``stage_seconds`` has the times).

        Raises ``ValueError`` saying what is missing while the two canvases
        do not hold the same number of strokes (the re-synthesize button
        shows it next to the action).
        """
        src, tgt, control, notes = self.strokes()
        if not src or len(src) != len(tgt):
            self.status.value = self._status_text(src, tgt, notes)
            raise ValueError(notes[0] if notes else "draw a stroke on the source image and its target first")
        t0 = time.perf_counter()
        p = self.params
        key = self._inputs_key(src, tgt, control)
        if self.patches is None or self._patches_key != key or not self.patches.reusable_for(p):
            self.patches, self._patches_key = None, None
            patches = fetch_patches(self.image, src, tgt, p, control_points=control,
                                    target_shape=self.target_shape, background=self.background)
            self.patches, self._patches_key = patches, key
            self.stage_seconds["fetch"] = time.perf_counter() - t0
        t1 = time.perf_counter()
        res = compose_patches(self.patches, p)
        self.stage_seconds["compose"] = time.perf_counter() - t1
        self.elapsed = time.perf_counter() - t0
        self.result = res
        self._show()  # the picture first, then the histograms
        self.comparisons = compare_colours(self.image, res)
        for h, cmp in zip(self.hists, self.comparisons):
            h.show(cmp)
        if self.stage_seconds["compose"] > self.preview_after and not self._preview_ready():
            self._warm_preview()  # seam-only changes are slow here too: have their preview ready
        self.status.value = self._status_text(src, tgt, notes)
        return res

    # -- callbacks ---------------------------------------------------------------
    def _canvas(self, side: str) -> AnnotationCanvas:
        if side not in self.canvases:
            raise ValueError(f"side must be 'source' or 'target', got {side!r}")
        return self.canvases[side]

    def _on_strokes(self, _event) -> None:
        if self._dropping:
            return
        self._drop_clicks()
        self._recolour()
        self._markers()
        self._changed()

    def _drop_clicks(self) -> None:
        """Remove finished strokes shorter than :data:`MIN_STROKE` (a click) and say so."""
        dropped = []
        for side, c in self.canvases.items():
            for i in range(len(c.model.shapes) - 1, -1, -1):
                sh = c.model.shapes[i]
                if sh.kind not in ("stroke", "polyline") or not sh.closed:
                    continue
                pts = np.asarray(sh.points, float)
                if len(pts) >= 2 and np.hypot(*np.diff(pts, axis=0).T).sum() >= MIN_STROKE:
                    continue
                self._dropping = True
                try:
                    c.model.remove_shape(i)
                finally:
                    self._dropping = False
                dropped.append(side)
        if dropped:
            self.shell.status.show(ValueError(
                f"a click is not a stroke: press, drag and release to draw one (the click on the "
                f"{' and '.join(sorted(set(dropped)))} canvas was removed)"))

    @staticmethod
    def _inputs_key(src, tgt, control) -> tuple:
        """What the fetched patches depend on besides the parameters (the strokes as drawn)."""
        def b(a):
            return np.ascontiguousarray(a, np.float64).tobytes()

        return (tuple(b(a) for a in src), tuple(b(a) for a in tgt),
                tuple(None if c is None else (b(c[0]), b(c[1])) for c in control))

    def expected_seconds(self) -> float:
        """How long the next edit is expected to take: composition alone if the patches are reusable."""
        src, tgt, control, _ = self.strokes()
        reuse = (self.patches is not None and self.patches.reusable_for(self.params)
                 and self._patches_key == self._inputs_key(src, tgt, control))
        c = self.stage_seconds["compose"]
        return c if reuse else c + self.stage_seconds["fetch"]

    def _changed(self) -> None:
        src, tgt, _, notes = self.strokes()
        if not src or len(src) != len(tgt):
            # nothing to re-synthesize yet: say what is missing (not a green "0.00 s")
            self.status.value = self._status_text(src, tgt, notes)
            if self.shell.status.last_error is None:
                self.shell.status.info(notes[0] if notes else "draw a stroke on the source image")
            return
        if self.auto.value:
            slow = self.expected_seconds() > self.preview_after
            if slow and self._reusable() and not self._preview_ready():
                slow = False  # fetching the reduced patches would cost more than composing the full ones
            self.shell.live("re-synthesize", self.edit, preview=self._preview if slow else None,
                            stale=self._mark_stale)
        else:
            self.status.value = self._status_text(src, tgt, notes)

    def _reusable(self) -> bool:
        src, tgt, control, _ = self.strokes()
        return (self.patches is not None and self.patches.reusable_for(self.params)
                and self._patches_key == self._inputs_key(src, tgt, control))

    def _mark_stale(self) -> None:
        if self.view.images:
            self.view.set_title(0, "out of date: re-synthesizing ...")

    def _reduced(self) -> dict | None:
        """The edit's inputs at reduced size (long side PREVIEW_SIZE px), or None if not worth it."""
        src, tgt, control, _ = self.strokes()
        if not src or len(src) != len(tgt):
            return None
        s = min(1.0, PREVIEW_SIZE / max(self.target_shape + self.image.shape[:2]))
        if s >= 0.95:
            return None
        p = self.params
        # the preview samples one patch per radius (h = r, the largest spacing the method
        # allows; auto is r / 2): half the patches, about 0.1 s CPU for a 5-part edit
        spacing = p.spacing * s if p.spacing else PREVIEW_SPACING
        small = dataclasses.replace(
            p, patch_size=2 * int(round(p.patch_size * s / 2)) if p.patch_size else 0,
            spacing=spacing, search_window=int(round(p.search_window * s)),
            search_across=int(round(p.search_across * s)), search_step=max(1, int(round(p.search_step * s))),
            junction_tolerance=p.junction_tolerance * s)
        if small.patch_size and small.patch_size < 8:
            small = dataclasses.replace(small, patch_size=8)
        return {"s": s, "params": small, "src": src, "tgt": tgt, "control": control,
                "key": (s, self._inputs_key(src, tgt, control))}

    def _preview_ready(self, red: dict | None = None) -> bool:
        red = self._reduced() if red is None else red
        return (red is not None and self._preview_patches is not None and self._preview_key == red["key"]
                and self._preview_patches.reusable_for(red["params"]))

    def _reduced_patches(self, red: dict) -> EditPatches:
        """The candidate patches of the reduced-size edit (kept like the full ones)."""
        if self._preview_ready(red):
            return self._preview_patches
        s = red["s"]
        h, w = self.image.shape[:2]
        image = cv2.resize(self.image, (max(1, round(w * s)), max(1, round(h * s))),
                           interpolation=cv2.INTER_AREA)
        bg = self.background
        if isinstance(bg, np.ndarray):
            bg = cv2.resize(bg, (max(1, round(bg.shape[1] * s)), max(1, round(bg.shape[0] * s))),
                            interpolation=cv2.INTER_AREA)
        shape = (max(1, round(self.target_shape[0] * s)), max(1, round(self.target_shape[1] * s)))
        if isinstance(bg, np.ndarray):
            shape = bg.shape[:2]
        ctrl = [None if c is None else (c[0] * s, c[1] * s) for c in red["control"]]
        self._preview_patches = None
        self._preview_patches = fetch_patches(image, [a * s for a in red["src"]], [b * s for b in red["tgt"]],
                                              red["params"], control_points=ctrl, target_shape=shape,
                                              background=bg)
        self._preview_key = red["key"]
        return self._preview_patches

    def _warm_preview(self) -> None:
        """Fetch the reduced-size patches now, so that the next seam-only change can preview at once."""
        red = self._reduced()
        if red is not None:
            try:
                self._reduced_patches(red)
            except ValueError:
                pass  # no preview then; the full edit reports problems itself

    def _preview(self) -> None:
        """The same edit at reduced size (long side PREVIEW_SIZE px), shown until the full one arrives."""
        red = self._reduced()
        if red is None:
            return
        try:
            res = compose_patches(self._reduced_patches(red), red["params"])
        except ValueError:
            return  # the full edit that follows reports it with the strokes as drawn
        self.preview = res
        self.view.update([res.show(seams=self.show_seams.value)],
                         [f"preview at {red['s']:.0%} size (the full result follows)"])

    def _recolour(self) -> None:
        """Pair colours on both canvases (shape.meta["color"], which the canvas honours)."""
        for c in self.canvases.values():
            shapes = c.model.shapes
            strokes, index, _, _ = strokes_from_shapes(shapes)
            changed = False
            for k, si in enumerate(index):
                colour = pair_color_hex(k)
                if shapes[si].meta.get("color") != colour:
                    shapes[si].meta["color"] = colour
                    changed = True
            for s in shapes:
                if s.kind == "point":
                    k = nearest_stroke(strokes, s.points[-1])
                    colour = _UNPAIRED if k is None else pair_color_hex(k)
                    if s.meta.get("color") != colour:
                        s.meta["color"] = colour
                        changed = True
            if changed:
                c.redraw()

    def _markers(self) -> None:
        """Start dots and arrowheads over the source canvas (the target's come with the result)."""
        src, _, _, _ = strokes_from_shapes(self.source_canvas.model.shapes)
        h, w = self.source_canvas.image_shape
        self.source_canvas.set_overlay(stroke_markers(np.zeros((h, w, 4), np.float32), src)
                                       if src else None)
        self._target_overlay()

    def _target_overlay(self) -> None:
        _, tgt, _, _ = self.strokes()
        h, w = self.target_shape
        base = np.zeros((h, w, 4), np.float32)
        if self.result is not None:
            base = self.result.layer.copy()
            if self.show_seams.value:
                base[self.result.seams] = (1.0, 0.0, 0.0, 1.0)
        self.target_canvas.set_overlay(stroke_markers(base, tgt) if tgt or self.result is not None
                                       else None)

    def _show(self) -> None:
        """The target canvas shows the result; the view shows what it is made of."""
        if self.result is None:
            return
        r = self.result
        self.view.update([self._copied(r), self._patches(r)],
                         ["copied from the source (the rest dimmed)", PATCHES_TITLE])
        self._target_overlay()

    @staticmethod
    def _patches(res) -> np.ndarray:
        """Each patch of the result in a colour of its own (over the object's shading), seams red.

        The target canvas already shows the result itself (and its seams with
        "show seams"); this shows what it does not: which patch every pixel
        comes from.
        """
        labels = res.labels
        n = int(labels.max()) + 1 if labels.size else 0
        hues = (np.arange(max(n, 1)) * 0.618034) % 1.0  # golden-ratio hues: neighbours differ
        hsv = np.stack([hues * 180, np.full_like(hues, 170), np.full_like(hues, 235)], -1).astype(np.uint8)
        colours = cv2.cvtColor(hsv[None], cv2.COLOR_HSV2RGB)[0].astype(np.float32) / 255.0
        alpha = np.clip(res.image[..., 3:4], 0.0, 1.0)
        inside = (labels >= 0) & (alpha[..., 0] > 0)
        shade = res.image[..., :3].mean(axis=-1, keepdims=True)  # the object's light and dark, kept
        tinted = np.ones(labels.shape + (3,), np.float32)
        tinted[inside] = colours[labels[inside]] * (0.45 + 0.55 * shade[inside])
        rgb = np.where(inside[..., None], alpha * tinted + (1.0 - alpha), 1.0).astype(np.float32)
        rgb[res.seams] = (1.0, 0.0, 0.0)
        return rgb

    def _copied(self, res) -> np.ndarray:
        """The source with the pixels the result copies at full strength, the rest dimmed."""
        rgb = _checkerboard(self.image.shape[:2]) if self.image.shape[2] == 4 else np.ones_like(self.image[..., :3])
        if self.image.shape[2] == 4:
            a = self.image[..., 3:4]
            rgb = self.image[..., :3] * a + rgb * (1 - a)
        else:
            rgb = self.image[..., :3].copy()
        region = res.source_region if res.source_region is not None else np.ones(rgb.shape[:2], bool)
        return np.where(region[..., None], rgb, 0.35 * rgb + 0.65).astype(np.float32)

    def _status_text(self, src, tgt, notes) -> str:
        parts = [f"{len(src)} source / {len(tgt)} target stroke(s)"]
        if self.result is not None and src and len(src) == len(tgt):
            e = self.result.energies
            parts.append(f"{len(self.result.junctions)} junction(s), patch radius ~"
                         f"{self.result.radius:.0f} px, sampling energy {e['sampling']:.3g}, "
                         f"seam cost {e['seam']:.3g}, {self.elapsed:.2f} s")
            if self.result.auto:
                names = {"patch_size": "2r", "spacing": "h", "junction_tolerance": "junction tolerance"}
                parts.append("auto: " + ", ".join(f"{names[k]} = {v:g} px" for k, v in self.result.auto.items()))
        parts += notes
        return " &nbsp;|&nbsp; ".join(parts)
