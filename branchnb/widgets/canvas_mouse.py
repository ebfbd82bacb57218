"""Mouse and keyboard bindings of the annotation canvas.

Kept apart from the view (:class:`~branchnb.widgets.canvas.AnnotationCanvas`:
layers, zoom, pan, drawing) and from the data model
(:class:`~branchnb.widgets.model.AnnotationModel`), as napari keeps its
layer data apart from its mouse bindings: the handlers here turn pointer
events in canvas pixels into edits of the model and nothing else, so each
can be called from Python (and from tests) with plain numbers.
"""

from __future__ import annotations

import numpy as np

from ._draw import batched

__all__ = ["CanvasBindings"]

#: Colours of the shape kinds while they are drawn.
KIND_COLOURS = {"polyline": "#ffb300", "stroke": "#00e676", "point": "#ff1744"}
SNAP_PX = 8.0  # CSS pixels
WHEEL_STEP = 1.2  # zoom factor per wheel notch


class CanvasBindings:
    """What the current tool does on mouse and key events.

    A base class of :class:`~branchnb.widgets.canvas.AnnotationCanvas`.

    Needs from the view: ``model``, ``mode``, ``label``, ``labels``,
    ``radius``, ``zoom``, ``canvas`` (its top layer 3 shows the shape being
    drawn), ``view_to_image``, ``image_to_view``, ``zoom_by``, ``pan_by`` and
    the drawing helpers ``_px``, ``_inside``, ``_ring``, ``_draw_shapes``.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.widgets.canvas import AnnotationCanvas
    >>> c = AnnotationCanvas(np.zeros((100, 200, 3)), mode="stroke")
    >>> c.handle_mouse_down(*c.image_to_view(10, 10))
    >>> c.handle_mouse_move(*c.image_to_view(30, 12))
    >>> c.handle_mouse_up(*c.image_to_view(30, 12))
    >>> c.model.shapes[0].kind
    'stroke'
    """

    # -- polylines ------------------------------------------------------------
    def finish(self) -> None:
        """End the polyline being drawn (no-op if none)."""
        i = self.model.open_polyline()
        if i is not None:
            self.model.set_closed(i, True)

    def _snap(self, xy, exclude=None):
        hit = self.model.nearest_vertex(xy, max_distance=self._px(SNAP_PX) / self.zoom, exclude=exclude)
        return hit

    # -- mouse & keyboard -------------------------------------------------------
    def handle_mouse_down(self, x: float, y: float) -> None:
        """Mouse pressed at canvas pixel (x, y): the current tool acts there.

        ``point`` adds a point, ``stroke``/``scribble`` start a freehand
        line, ``polyline`` adds a vertex (or starts a polyline, snapping to
        a nearby vertex as its parent), ``edit`` selects the nearest vertex,
        ``pan`` starts dragging the view. Clicks outside the image are ignored.

        Parameters
        ----------
        x, y : float
            Canvas (device) pixels; non-finite values are ignored.
        """
        if not (np.isfinite(x) and np.isfinite(y)):
            return
        ix, iy = self.view_to_image(x, y)
        self.pointer = (ix, iy)
        if self.mode == "pan":
            self._panning = (x, y)
            return
        if not self._inside(ix, iy):
            return
        if self.mode == "point":
            self.model.add_shape("point", [(ix, iy)], label=self.label or None)
        elif self.mode in ("stroke", "scribble"):
            self._active = [(ix, iy)]
            c = self.canvas[3]
            with batched():
                c.clear()
                colour = self.labels.get(self.label, "#fff") if self.mode == "scribble" else KIND_COLOURS["stroke"]
                c.stroke_style = colour
                c.fill_style = colour
                c.line_width = self._px(3 if self.mode == "scribble" else 1.5)
                c.line_cap = "round"
                c.fill_circle(float(x), float(y), self._px(2))
        elif self.mode == "polyline":
            self._polyline_click(ix, iy)
        elif self.mode == "edit":
            self.selected = self.model.nearest_vertex((ix, iy), max_distance=self._px(SNAP_PX) / self.zoom)
            self._dragging = self.selected is not None
            if self.selected is not None:
                s = self.model.shapes[self.selected[0]]
                if s.radii is not None:
                    self.radius = float(s.radii[self.selected[1]])
            self._draw_shapes()

    def _polyline_click(self, ix: float, iy: float) -> None:
        i = self.model.open_polyline()
        if i is None:
            hit = self._snap((ix, iy))
            meta = {}
            if hit is not None:
                ix, iy = self.model.shapes[hit[0]].points[hit[1]]
                meta["parent"] = [int(hit[0]), int(hit[1])]
            self.model.add_shape("polyline", [(ix, iy)], radii=[self.radius], closed=False, meta=meta)
            return
        last = self.model.shapes[i].points[-1]
        if np.hypot(ix - last[0], iy - last[1]) * self.zoom <= self._px(SNAP_PX):
            self.model.set_closed(i, True)  # clicking the last vertex again ends the polyline
            return
        self.model.append_point(i, (ix, iy), radius=self.radius)

    def handle_mouse_move(self, x: float, y: float) -> None:
        """Mouse moved to canvas pixel (x, y): pan, extend a freehand line, or show a dragged vertex.

        Cheap by design (browsers do not throttle move events): the
        annotations are not redrawn, only the top layer.

        Parameters
        ----------
        x, y : float
            Canvas (device) pixels; non-finite values are ignored.
        """
        if not (np.isfinite(x) and np.isfinite(y)):
            return
        ix, iy = self.view_to_image(x, y)
        self.pointer = (ix, iy)
        self._last_view = (x, y)
        if self._panning is not None:
            px, py = self._panning
            self._panning = (x, y)
            self.pan_by(x - px, y - py)
            return
        if self._active is not None:
            if not self._inside(ix, iy):
                return
            lx, ly = self.image_to_view(*self._active[-1])
            self._active.append((ix, iy))
            with batched():
                self.canvas[3].stroke_line(float(lx), float(ly), float(x), float(y))
            return
        if self._dragging and self.selected is not None and self._inside(ix, iy):
            # Move on release only (one undo step); show a marker meanwhile.
            c = self.canvas[3]
            with batched():
                c.clear()
                self._ring(c, x, y)

    def handle_mouse_up(self, x: float, y: float) -> None:
        """Mouse released at canvas pixel (x, y): drop a dragged vertex there, or finish a freehand line.

        Parameters
        ----------
        x, y : float
            Canvas (device) pixels; a vertex moves only if released inside
            the image more than one pixel away.
        """
        self._panning = None
        if not (np.isfinite(x) and np.isfinite(y)):
            self._dragging = False
            self._end_active()
            return
        ix, iy = self.view_to_image(x, y)
        if self._dragging and self.selected is not None:
            self._dragging = False
            i, j = self.selected
            old = self.model.shapes[i].points[j]
            if self._inside(ix, iy) and np.hypot(ix - old[0], iy - old[1]) * self.zoom > self._px(1.0):
                self.model.move_vertex(i, j, (ix, iy))
            self.canvas[3].clear()
            return
        self._end_active()

    def handle_mouse_out(self, x: float, y: float) -> None:
        """Pointer left the canvas: stop panning and dragging, finish a freehand line.

        Parameters
        ----------
        x, y : float
            Canvas pixels of the event (not used).
        """
        self._panning = None
        self._dragging = False
        self._end_active()

    def _end_active(self) -> None:
        if self._active is None:
            return
        pts, self._active = self._active, None
        kind = "scribble" if self.mode == "scribble" else "stroke"
        label = self.label if kind == "scribble" else None
        self.canvas[3].clear()
        self.model.add_shape(kind, pts, label=label)

    def handle_wheel(self, dx: float, dy: float) -> None:
        """Zoom about the last pointer position: one fixed step per notch (wheel up = in).

        The step does not depend on ``deltaY``'s size, which differs between
        browsers, devices and pixel ratios.

        Parameters
        ----------
        dx, dy : float
            The wheel event's deltas; only the sign of ``dy`` counts
            (negative zooms in, 0 or non-finite does nothing).
        """
        if not np.isfinite(dy) or dy == 0:
            return
        self.zoom_by(WHEEL_STEP if dy < 0 else 1 / WHEEL_STEP, about=self._last_view)

    def handle_key(self, key: str, shift: bool, ctrl: bool, meta: bool) -> None:
        """A key pressed over the canvas.

        Ctrl/Cmd+Z undoes, Ctrl/Cmd+Y redoes, Enter finishes the polyline,
        Escape drops the line being drawn and finishes, ``[``/``]`` shrink or
        grow the selected vertex's radius by 20/25 %, Delete/Backspace
        removes the selected shape.

        Parameters
        ----------
        key : str
            The browser's ``KeyboardEvent.key`` (``"z"``, ``"Enter"``, ...).
        shift : bool
            Shift held (not used).
        ctrl : bool
            Ctrl held.
        meta : bool
            Cmd/Windows key held (same as Ctrl).
        """
        mod = ctrl or meta
        if mod and key.lower() == "z":
            self.model.undo()
        elif mod and key.lower() == "y":
            self.model.redo()
        elif key == "Enter":
            self.finish()
        elif key == "Escape":
            self._active = None
            self.canvas[3].clear()
            self.finish()
        elif key in ("[", "]") and self.selected is not None:
            self.radius = max(0.5, self.radius * (1.25 if key == "]" else 0.8))
        elif key in ("Delete", "Backspace") and self.selected is not None:
            i = self.selected[0]
            self.selected = None
            self.model.remove_shape(i)
