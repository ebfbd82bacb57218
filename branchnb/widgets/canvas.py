"""AnnotationCanvas: draw polylines, strokes, scribbles and points on an image.

The view is an ipycanvas ``MultiCanvas`` with four layers: the image, an
optional result overlay, the finished annotations, and the shape being
drawn. It edits an :class:`~branchnb.widgets.model.AnnotationModel`; all
coordinates it stores or reports are image pixels ``(x, y)``, whatever the
zoom, pan or on-screen size of the canvas (ipycanvas reports mouse
positions in canvas pixels, and the view maps them through its own
zoom/pan transform).

Interaction
-----------
- ``polyline``: click vertices; click the last vertex again, press Enter or
  the "finish" button to end. A polyline started on a vertex of another
  one snaps to it and records ``meta["parent"] = [shape, vertex]``.
  New vertices get the radius slider's value.
- ``stroke`` / ``scribble``: press, drag, release. Scribbles carry the
  current ``label`` and its colour.
- ``point``: click.
- ``edit``: click a vertex to select it, drag to move it; the radius
  slider (or ``[`` / ``]``) changes the selected vertex's radius; Delete
  removes the selected shape.
- ``pan``: drag to pan. The mouse wheel zooms about the pointer; "fit"
  resets the view. Ctrl+Z / Ctrl+Y undo and redo.

Drawing cost does not grow with the number of shapes: each mouse move
adds one segment to the top layer, a new vertex or shape draws only
itself; only undo, deletion, zoom and pan redraw the annotation layer.

Sharpness: the canvas buffer has ``pixel_ratio`` device pixels per CSS
pixel. A one-pixel probe in the widget reads ``window.devicePixelRatio``
from the browser and sets it (2 until it reports, so that HiDPI screens
are sharp from the start). Marker sizes and the snap distance are in CSS
pixels, the wheel zooms by a fixed factor per notch whatever the ratio.
"""

from __future__ import annotations

import ipywidgets as widgets
import numpy as np
import traitlets
from ipycanvas import MultiCanvas

from ..core.image import as_float_image, as_rgba
from ..core.io import encode_png
from ._assets import COMPACT_CSS, PixelRatioProbe, backing_ratio
from ._draw import batched
from .canvas_mouse import KIND_COLOURS, WHEEL_STEP, CanvasBindings
from .feedback import ErrorArea
from .model import AnnotationEvent, AnnotationModel

__all__ = ["AnnotationCanvas", "DEFAULT_LABELS"]

MODES = ("polyline", "stroke", "scribble", "point", "edit", "pan")

#: Default scribble labels and colours.
DEFAULT_LABELS = {"foreground": "#e53935", "background": "#1e88e5"}


#: What the tool buttons say (the values stay the short mode names).
_MODE_LABELS = {"polyline": "polyline", "stroke": "freehand", "scribble": "scribble",
                "point": "point", "edit": "select/move", "pan": "pan"}

#: Font Awesome icon of each tool: a narrow canvas (``max_display`` < :data:`COMPACT_BELOW`) shows the
#: icons alone (the name is the tooltip) so that its toolbar holds one row.
_MODE_ICONS = {"polyline": "share-alt", "stroke": "pencil", "scribble": "paint-brush", "point": "map-marker",
               "edit": "mouse-pointer", "pan": "arrows"}

#: Canvases narrower than this (``max_display``, CSS px) get the compact toolbar: icon-only tools and
#: 21 px buttons (12 controls in 274 px; the named tools and 34 px buttons took two rows below ~480 px).
COMPACT_BELOW = 480

_MODE_HELP = {
    "polyline": "click vertices; click the last one again (or Enter) to finish",
    "stroke": "drag to draw freehand",
    "scribble": "drag to draw with the current label",
    "point": "click to place a point",
    "edit": "click a vertex to select, drag to move; radius slider / [ ] resize; Delete removes",
    "pan": "drag to pan; the mouse wheel zooms (also in the other tools)",
}


_PixelRatioProbe = PixelRatioProbe  # the old private name


class AnnotationCanvas(CanvasBindings, widgets.VBox):
    """An image with annotation tools, zoom and pan.

    Parameters
    ----------
    image : (H, W, C) array_like
        Any layout accepted by :func:`branchnb.core.image.as_float_image`.
    mode : str
        Initial tool: one of ``modes``.
    labels : dict, optional
        Scribble label -> CSS colour.
    max_display : int
        Long side of the canvas in CSS pixels at zoom "fit".
    model : AnnotationModel, optional
        Share a model between views; a new one by default.
    modes : sequence of str, optional
        Tools offered in the toolbar (all by default): a non-empty subset
        of ``polyline``, ``stroke``, ``scribble``, ``point``, ``edit``,
        ``pan``.
    errors : ErrorArea or StatusLine, optional
        Where errors of the canvas' callbacks are shown (an app's status
        line); the canvas gets its own area by default.
    pixel_ratio : float, optional
        Device pixels per CSS pixel of the canvas buffer; by default the
        browser's ``devicePixelRatio`` (2 until it is known).

    Examples
    --------
    >>> import numpy as np
    >>> c = AnnotationCanvas(np.zeros((100, 200, 3)), mode="point")
    >>> c.handle_mouse_down(*c.image_to_view(50, 20))
    >>> c.model.shapes[0].points.round(6).tolist()
    [[50.0, 20.0]]
    """

    #: Current tool.
    mode = traitlets.Unicode("polyline")
    #: Current scribble label.
    label = traitlets.Unicode("")
    #: Radius (image pixels) of new polyline vertices / the selected vertex.
    radius = traitlets.Float(3.0)
    #: Zoom: canvas (device) pixels per image pixel.
    zoom = traitlets.Float(1.0)
    #: Device pixels per CSS pixel of the canvas buffer.
    pixel_ratio = traitlets.Float(2.0)
    #: Last pointer position in image pixels (x, y), or None.
    pointer = traitlets.Any(None)
    #: Whether the annotations are drawn (the "eye" button); hiding them shows the image alone.
    show_annotations = traitlets.Bool(True)
    #: Opacity of the drawn annotations in (0, 1].
    annotation_opacity = traitlets.Float(0.9)

    def __init__(self, image, *, mode: str = "polyline", labels: dict | None = None,
                 max_display: int = 640, model: AnnotationModel | None = None,
                 modes=MODES, errors: ErrorArea | None = None, pixel_ratio: float | None = None):
        if isinstance(modes, str) or not hasattr(modes, "__iter__"):
            raise TypeError(f"modes must be a sequence of tool names, got {modes!r}")
        modes = tuple(modes)
        if not modes:
            raise ValueError(f"modes must name at least one tool of {MODES}")
        for m in modes:
            if m not in MODES:
                raise ValueError(f"modes must be a subset of {MODES}, got {m!r}")
        if mode not in modes:
            raise ValueError(f"mode must be one of the offered modes {modes}, got {mode!r}")
        self.errors = errors if errors is not None else ErrorArea()
        self.model = model if model is not None else AnnotationModel()
        if model is not None and not isinstance(model, AnnotationModel):
            raise TypeError(f"model must be an AnnotationModel, got {type(model).__name__}")
        self.labels = dict(DEFAULT_LABELS if labels is None else labels)
        if not self.labels:
            raise ValueError("labels must name at least one scribble label")
        if isinstance(max_display, bool) or not isinstance(max_display, (int, np.integer)) \
                or max_display < 64:
            raise ValueError(f"max_display must be an int >= 64, got {max_display!r}")
        self.max_display = int(max_display)
        self._auto_ratio = pixel_ratio is None
        if pixel_ratio is not None:
            self.pixel_ratio = self._valid_ratio_value(pixel_ratio)
        self._image = as_rgba(image, name="image")
        self._image_widget = widgets.Image(format="png")
        self._overlay_widget = widgets.Image(format="png")
        self._has_overlay = False
        self._offset = np.zeros(2)
        self._active: list[tuple[float, float]] | None = None
        self._panning: tuple[float, float] | None = None
        self._dragging = False
        self._last_view: tuple[float, float] | None = None
        self.selected: tuple[int, int] | None = None

        self.canvas = MultiCanvas(4)
        compact = self.max_display < COMPACT_BELOW
        self._tools = widgets.ToggleButtons(options=[(_MODE_LABELS[m], m) for m in modes], value=mode,
                                            tooltips=[(f"{_MODE_LABELS[m]}: " if compact else "") + _MODE_HELP[m]
                                                      for m in modes],
                                            icons=[_MODE_ICONS[m] for m in modes] if compact else [],
                                            style={"button_width": "21px" if compact else "auto"})
        self._tools.layout.display = None if len(modes) > 1 else "none"
        self._label_picker = widgets.Dropdown(options=list(self.labels), description="label",
                                              style={"description_width": "36px"},
                                              layout=widgets.Layout(width="190px"))
        self._radius_slider = widgets.FloatSlider(value=self.radius, min=0.5, max=40.0, step=0.5,
                                                  description="radius", continuous_update=False,
                                                  style={"description_width": "44px"},
                                                  layout=widgets.Layout(width="230px"))
        g = self.errors.guard
        buttons = []
        self.buttons: dict[str, widgets.Button] = {}
        for name, icon, tip, handler in (
            ("undo", "undo", "undo (Ctrl+Z)", lambda _: self.model.undo()),
            ("redo", "repeat", "redo (Ctrl+Y)", lambda _: self.model.redo()),
            ("clear", "trash", "remove all annotations on this canvas (undoable)",
             lambda _: self.model.clear()),
            ("finish", "check", "finish the polyline (Enter, or click its last vertex again)",
             lambda _: self.finish()),
            ("+", "search-plus", "zoom in (mouse wheel)", lambda _: self.zoom_by(WHEEL_STEP)),
            ("-", "search-minus", "zoom out (mouse wheel)", lambda _: self.zoom_by(1 / WHEEL_STEP)),
            ("fit", "expand", "fit the image into the canvas", lambda _: self.fit()),
            ("show", "eye", "hide / show the annotations (to see the image under them)",
             lambda _: setattr(self, "show_annotations", not self.show_annotations)),
        ):
            b = widgets.Button(description="", icon=icon, tooltip=tip,
                               layout=widgets.Layout(width="21px" if compact else "34px", padding="0"))
            b.on_click(g(handler))
            buttons.append(b)
            self.buttons[name] = b
        self.buttons["finish"].layout.display = None if "polyline" in modes else "none"
        self.status = widgets.HTML(layout=widgets.Layout(width="100%", overflow="hidden"))
        # The options row keeps its height whatever the tool (no jump of the canvas).
        self._options = widgets.HBox([self._label_picker, self._radius_slider],
                                     layout=widgets.Layout(flex_flow="row wrap", min_height="30px",
                                                           align_items="center"))
        row = widgets.HBox([self._tools] + buttons, layout=widgets.Layout(flex_flow="row wrap",
                                                                         align_items="center"))
        if compact:
            row.add_class("bnb-compact")  # (the kit's stylesheet hides the tool names, narrows the margins)
        style = [widgets.HTML(f"<style>{COMPACT_CSS}</style>", layout=widgets.Layout(height="0px", margin="0",
                                                                                       overflow="hidden"))]
        toolbar = widgets.VBox([row, self._options] + (style if compact else []))
        self._probe = _PixelRatioProbe()
        children = [toolbar, self.canvas, self.status, self._probe]
        if errors is None:
            children.append(self.errors)
        super().__init__(children)
        self.add_class("bnb-canvas")

        traitlets.link((self._tools, "value"), (self, "mode"))
        traitlets.link((self._label_picker, "value"), (self, "label"))
        traitlets.link((self._radius_slider, "value"), (self, "radius"))
        self.label = self._label_picker.value
        self.mode = self._tools.value
        self._show_tool_options()

        passive = self.errors.guard(action=False)
        self.canvas.on_mouse_down(g(self.handle_mouse_down))
        self.canvas.on_mouse_move(passive(self.handle_mouse_move))
        self.canvas.on_mouse_up(passive(self.handle_mouse_up))
        self.canvas.on_mouse_out(passive(self.handle_mouse_out))
        self.canvas.on_mouse_wheel(passive(self.handle_wheel))
        self.canvas.on_key_down(g(self.handle_key))
        self.canvas.on_client_ready(passive(lambda: self.redraw()))
        self.model.observe(passive(self._on_model))
        self._probe.observe(passive(self._on_probe), names="ratio")
        self.set_image(self._image)

    # -- validation of traits ---------------------------------------------
    @traitlets.validate("mode")
    def _valid_mode(self, proposal):
        if proposal["value"] not in MODES:
            raise traitlets.TraitError(f"mode must be one of {MODES}, got {proposal['value']!r}")
        return proposal["value"]

    @traitlets.validate("radius")
    def _valid_radius(self, proposal):
        r = float(proposal["value"])
        if not np.isfinite(r) or r <= 0:
            raise traitlets.TraitError(f"radius must be > 0, got {r}")
        return r

    @traitlets.validate("zoom")
    def _valid_zoom(self, proposal):
        z = float(proposal["value"])
        if not np.isfinite(z) or z <= 0:
            raise traitlets.TraitError(f"zoom must be a finite number > 0, got {z}")
        return z

    @staticmethod
    def _valid_ratio_value(r) -> float:
        if isinstance(r, bool) or not isinstance(r, (int, float, np.integer, np.floating)):
            raise ValueError(f"pixel_ratio must be a number in [0.5, 4], got {r!r}")
        r = float(r)
        if not np.isfinite(r) or not 0.5 <= r <= 4:
            raise ValueError(f"pixel_ratio must be in [0.5, 4], got {r}")
        return r

    @traitlets.validate("pixel_ratio")
    def _valid_ratio(self, proposal):
        try:
            return self._valid_ratio_value(proposal["value"])
        except ValueError as exc:
            raise traitlets.TraitError(str(exc)) from None

    @traitlets.observe("pixel_ratio")
    def _ratio_changed(self, change):
        if hasattr(self, "_image_widget") and change["old"] != change["new"]:
            self._resize()

    def _on_probe(self, change) -> None:
        if self._auto_ratio:
            self.pixel_ratio = backing_ratio(change["new"])

    @traitlets.validate("annotation_opacity")
    def _valid_opacity(self, proposal):
        a = float(proposal["value"])
        if not np.isfinite(a) or not 0 < a <= 1:
            raise traitlets.TraitError(f"annotation_opacity must be in (0, 1], got {a}")
        return a

    @traitlets.observe("show_annotations", "annotation_opacity")
    def _style_changed(self, change):
        if "show" in getattr(self, "buttons", {}):
            self.buttons["show"].icon = "eye" if self.show_annotations else "eye-slash"
        if hasattr(self, "canvas"):
            self._draw_shapes()

    @traitlets.observe("mode")
    def _mode_changed(self, change):
        self._end_active()
        self.selected = None
        self._show_tool_options()
        if "edit" in (change["old"], change["new"]) and hasattr(self, "canvas"):
            self._draw_shapes()  # the vertex handles show in edit mode only
        self._update_status()

    def _show_tool_options(self) -> None:
        # visibility, not display: the row keeps its size and the canvas does not jump
        offered = {v for _, v in self._tools.options}
        self._label_picker.layout.visibility = "visible" if self.mode == "scribble" else "hidden"
        self._label_picker.layout.display = None if "scribble" in offered else "none"
        self._radius_slider.layout.visibility = "visible" if self.mode in ("polyline", "edit") else "hidden"
        self._radius_slider.layout.display = None if {"polyline", "edit"} & offered else "none"
        self._options.layout.display = None if {"scribble", "polyline", "edit"} & offered else "none"

    @traitlets.observe("radius")
    def _radius_changed(self, change):
        if self.selected is not None:
            i, j = self.selected
            s = self.model.shapes[i]
            if s.radii is not None and not np.isclose(s.radii[j], change["new"]):
                self.model.set_radius(i, j, change["new"])

    # -- image, overlay, view transform --------------------------------------
    @property
    def image_shape(self) -> tuple[int, int]:
        return self._image.shape[:2]

    @property
    def image(self) -> np.ndarray:
        """The background image (RGBA float32)."""
        return self._image

    def set_image(self, image) -> None:
        """Replace the background image (annotations are kept) and fit the view.

        Parameters
        ----------
        image : (H, W, C) array_like
            Any layout :func:`branchnb.core.image.as_float_image` accepts;
            stored as RGBA. The canvas is resized to its aspect ratio.
        """
        self._image = as_rgba(image, name="image")
        self._image_widget.value = encode_png(self._image)
        self._resize()

    def _resize(self) -> None:
        h, w = self.image_shape
        s = self.max_display / max(h, w)
        css_w, css_h = max(1, int(round(w * s))), max(1, int(round(h * s)))
        r = self.pixel_ratio
        self.canvas.width = int(round(css_w * r))
        self.canvas.height = int(round(css_h * r))
        self.canvas.layout.width = f"{css_w}px"
        self.canvas.layout.max_width = "100%"
        # The whole widget is as wide as its canvas (toolbar rows wrap), so
        # that apps can put two canvases side by side.
        self.layout.width = f"{max(css_w, 300) + 8}px"
        self.layout.max_width = "100%"
        self.fit()

    def _px(self, css: float) -> float:
        """CSS pixels -> canvas buffer pixels."""
        return float(css) * self.pixel_ratio

    def set_overlay(self, overlay) -> None:
        """Show an RGBA image (same size as the image) over it, under the annotations; None hides it.

        Parameters
        ----------
        overlay : (H, W, C) array_like or None
            Same height and width as the image; its alpha lets the image show
            through (gray or RGB overlays are opaque).

        Raises
        ------
        ValueError
            If the overlay's size differs from the image's.
        """
        if overlay is None:
            self._has_overlay = False
        else:
            ov = as_float_image(overlay, name="overlay")
            if ov.shape[:2] != self.image_shape:
                raise ValueError(f"overlay must be {self.image_shape} like the image, got {ov.shape[:2]}")
            self._overlay_widget.value = encode_png(as_rgba(ov))
            self._has_overlay = True
        self._draw_background()

    def fit(self) -> None:
        """Zoom so that the whole image fills the canvas."""
        h, w = self.image_shape
        self.zoom = min(self.canvas.width / w, self.canvas.height / h)
        self._offset = np.zeros(2)
        self.redraw()

    def zoom_by(self, factor: float, about=None) -> None:
        """Multiply the zoom by ``factor`` keeping view point ``about`` fixed (canvas centre by default).

        The zoom stays between a quarter of "fit" and 64 CSS pixels per image pixel.

        Parameters
        ----------
        factor : float
            Zoom multiplier (> 0; 2 zooms in twice).
        about : (x, y), optional
            Canvas (device) pixel that stays in place; the canvas centre if
            None or not finite.

        Raises
        ------
        ValueError
            If ``factor`` is not a finite number > 0.
        """
        if not np.isfinite(factor) or factor <= 0:
            raise ValueError(f"factor must be > 0, got {factor}")
        if about is None or not np.all(np.isfinite(np.asarray(about, float))):
            about = (self.canvas.width / 2, self.canvas.height / 2)
        fit = min(self.canvas.width / self.image_shape[1], self.canvas.height / self.image_shape[0])
        new = float(np.clip(self.zoom * factor, fit / 4, 64.0 * self.pixel_ratio))
        about = np.asarray(about, float)
        self._offset = about - (about - self._offset) * (new / self.zoom)
        self.zoom = new
        self.redraw()

    def pan_by(self, dx: float, dy: float) -> None:
        """Shift the view by (dx, dy) canvas pixels (non-finite shifts are ignored).

        Parameters
        ----------
        dx, dy : float
            Shift in canvas (device) pixels; positive moves the image right
            and down.
        """
        if not (np.isfinite(dx) and np.isfinite(dy)):
            return
        self._offset = self._offset + [dx, dy]
        self.redraw()

    def view_to_image(self, x: float, y: float) -> tuple[float, float]:
        """Canvas pixel -> image pixel (pixel centres at integers).

        Parameters
        ----------
        x, y : float
            Position in canvas (device) pixels, as mouse events give it.

        Returns
        -------
        (float, float)
            Image ``(x, y)`` in pixels, with the current zoom and pan.
        """
        return ((x - self._offset[0]) / self.zoom - 0.5, (y - self._offset[1]) / self.zoom - 0.5)

    def image_to_view(self, x, y):
        """Image pixel -> canvas pixel (arrays allowed); the inverse of :meth:`view_to_image`.

        Parameters
        ----------
        x, y : float or array_like
            Image coordinates in pixels (pixel centres at integers).

        Returns
        -------
        (x, y)
            Canvas (device) pixels, floats or arrays like the input.
        """
        return ((np.asarray(x) + 0.5) * self.zoom + self._offset[0],
                (np.asarray(y) + 0.5) * self.zoom + self._offset[1])

    def _inside(self, x: float, y: float) -> bool:
        h, w = self.image_shape
        return -0.5 <= x <= w - 0.5 and -0.5 <= y <= h - 0.5

    # -- drawing ------------------------------------------------------------
    def _draw_background(self) -> None:
        h, w = self.image_shape
        x0, y0 = self._offset
        with batched():
            for layer, show, img in ((0, True, self._image_widget),
                                     (1, self._has_overlay, self._overlay_widget)):
                c = self.canvas[layer]
                c.clear()
                c.image_smoothing_enabled = self.zoom < 2.0 * self.pixel_ratio
                if show:
                    c.draw_image(img, float(x0), float(y0), float(w * self.zoom), float(h * self.zoom))

    def _colour(self, shape) -> str:
        if shape.kind == "scribble":
            return self.labels.get(shape.label, "#ffffff")
        return shape.meta.get("color", KIND_COLOURS.get(shape.kind, "#ffffff"))

    def _line_width(self, shape) -> float:
        return self._px(3 if shape.kind == "scribble" else 1.5)

    def _outline(self, c, pts, width) -> None:
        """A dark halo under a line: visible on light and dark images alike."""
        c.stroke_style = "rgba(0,0,0,0.6)"
        c.line_width = width + self._px(2)
        c.line_join = "round"
        c.stroke_lines(pts)

    def _dots(self, c, x, y, colour, radius: float) -> None:
        """Vertex dots with a dark rim (radius in CSS pixels)."""
        c.fill_style = "rgba(0,0,0,0.6)"
        c.fill_circles(x, y, self._px(radius + 1))
        c.fill_style = colour
        c.fill_circles(x, y, self._px(radius))

    def _vertex_marks(self, shape, x, y):
        """Which vertices get a dot: every one while it can be edited, else the two ends.

        A finished polyline (an extracted one has a vertex every few pixels)
        with a dot at each vertex would cover the very structure it
        annotates; in ``edit`` mode, or while it is being drawn, every
        vertex is a handle and is shown.
        """
        if len(x) <= 2 or self.mode == "edit" or self._open_index(shape):
            return x, y
        return x[[0, -1]], y[[0, -1]]

    def _open_index(self, shape) -> bool:
        return shape.kind == "polyline" and not shape.closed

    def _draw_shape(self, c, shape) -> None:
        if not self.show_annotations:
            return
        x, y = self.image_to_view(shape.points[:, 0], shape.points[:, 1])
        pts = np.column_stack([x, y])
        colour = self._colour(shape)
        c.global_alpha = self.annotation_opacity
        try:
            if shape.kind == "point":
                self._dots(c, x, y, colour, 4.5)
                return
            width = self._line_width(shape)
            if len(pts) > 1:
                self._outline(c, pts, width)
                c.stroke_style = colour
                c.line_width = width
                c.stroke_lines(pts)
            if shape.kind == "polyline":
                if shape.radii is not None and self._open_index(shape):
                    self._radii(c, x, y, shape.radii, colour)
                mx, my = self._vertex_marks(shape, x, y)
                self._dots(c, mx, my, colour, 2.0 if shape.closed else 3.0)
            elif len(pts) == 1:
                self._dots(c, x, y, colour, 2.0)
        finally:
            c.global_alpha = 1.0

    def _radii(self, c, x, y, radii, colour) -> None:
        c.global_alpha = 0.5 * self.annotation_opacity
        c.stroke_style = colour
        c.line_width = self._px(1)
        c.stroke_circles(x, y, np.maximum(np.asarray(radii) * self.zoom, self._px(1)))
        c.global_alpha = self.annotation_opacity

    def _draw_appended(self, c, shape) -> None:
        """Only the newest segment and vertex of a shape (the rest is on the layer already)."""
        if not self.show_annotations:
            return
        p = shape.points[-2:]
        x, y = self.image_to_view(p[:, 0], p[:, 1])
        pts = np.column_stack([x, y])
        width = self._line_width(shape)
        colour = self._colour(shape)
        c.global_alpha = self.annotation_opacity
        self._outline(c, pts, width)
        c.stroke_style = colour
        c.line_width = width
        c.stroke_lines(pts)
        if shape.radii is not None:
            self._radii(c, x[-1:], y[-1:], shape.radii[-1:], colour)
        self._dots(c, x, y, colour, 3.0)
        c.global_alpha = 1.0

    def _draw_shapes(self) -> None:
        c = self.canvas[2]
        with batched():
            c.clear()
            for s in self.model.shapes:
                self._draw_shape(c, s)
            self._draw_selection(c)

    def _ring(self, c, x: float, y: float) -> None:
        """Black, white and yellow rings: visible on any colour."""
        for colour, width, radius in (("#000000", 5, 8), ("#ffffff", 3, 8), ("#ffd600", 1.5, 8)):
            c.stroke_style = colour
            c.line_width = self._px(width)
            c.stroke_circle(float(x), float(y), self._px(radius))

    def _draw_selection(self, c) -> None:
        if self.selected is None:
            return
        i, j = self.selected
        if i >= len(self.model) or j >= len(self.model.shapes[i].points):
            self.selected = None
            return
        s = self.model.shapes[i]
        if len(s.points) > 1:
            x, y = self.image_to_view(s.points[:, 0], s.points[:, 1])
            c.stroke_style = "#ffffff"
            c.global_alpha = 0.8
            c.line_width = self._line_width(s) + self._px(5)
            c.stroke_lines(np.column_stack([x, y]))
            c.global_alpha = 1.0
            self._draw_shape(c, s)
            if s.radii is not None and self.show_annotations:
                self._radii(c, x, y, s.radii, self._colour(s))
                c.global_alpha = 1.0
        self._ring(c, *self.image_to_view(*s.points[j]))

    def redraw(self) -> None:
        """Redraw every layer (after zoom, pan, undo, ...)."""
        with batched():
            self._draw_background()
            self._draw_shapes()
            self.canvas[3].clear()
        self._update_status()

    def _on_model(self, event: AnnotationEvent) -> None:
        if event.type == "add" and self.selected is None:
            with batched():
                self._draw_shape(self.canvas[2], self.model.shapes[event.index])
        elif event.type == "append" and self.selected is None:
            with batched():
                self._draw_appended(self.canvas[2], self.model.shapes[event.index])
        else:
            self._draw_shapes()
        self._update_status()

    def _update_status(self) -> None:
        p = self.pointer
        where = f"x {p[0]:.0f}, y {p[1]:.0f}" if p is not None else "x, y -"
        h, w = self.image_shape
        self.status.value = (
            "<div style='font-family:monospace;font-size:11px;white-space:nowrap;overflow:hidden;"
            f"text-overflow:ellipsis;color:#444'>{where} · {w}×{h} px · "
            f"{self.zoom / self.pixel_ratio * 100:.0f} % · {len(self.model)} shapes</div>"
        )
