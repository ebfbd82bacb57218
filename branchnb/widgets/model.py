"""The annotation model: shapes, undo/redo and JSON, with no widget code.

The canvas view (:mod:`branchnb.widgets.canvas`) edits an
:class:`AnnotationModel`; everything it does can be done (and is tested)
by calling the model directly. Points are always image pixels ``(x, y)``.
"""

from __future__ import annotations

import copy
import json
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..core.image import as_points

__all__ = ["KINDS", "Shape", "AnnotationEvent", "AnnotationModel"]

def _number(value, name: str, *, positive: bool = False, allow_inf: bool = False) -> float:
    """A real number (not bool) for argument ``name``: finite (or +inf if allowed), > 0 if ``positive``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a number, got {type(value).__name__}")
    v = float(value)
    if v != v or (np.isinf(v) and not (allow_inf and v > 0)):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    if positive and not v > 0:
        raise ValueError(f"{name} must be > 0, got {value!r}")
    if not positive and v < 0:
        raise ValueError(f"{name} must be >= 0, got {value!r}")
    return v


def _int(value, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(value).__name__}")
    if int(value).bit_length() > 64:  # nor can such an int be shown in a message
        raise ValueError(f"{name} must fit in 64 bits, got an int of {int(value).bit_length()} bits")
    return int(value)


def _bool(value, name: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def _json_meta(meta, name: str = "meta") -> dict:
    if not isinstance(meta, dict):
        raise TypeError(f"{name} must be a dict, got {type(meta).__name__}")
    try:
        json.dumps(meta, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be JSON-serialisable with finite numbers: {exc}") from None
    return meta


#: Shape kinds: click-by-click polylines with a radius per vertex, freehand
#: strokes, freehand scribbles with a label, and single points.
KINDS = ("polyline", "stroke", "scribble", "point")


@dataclass
class Shape:
    """One annotation.

    The fields are checked on construction (points become a float64
    ``(N, 2)`` array, radii float64).

    Parameters
    ----------
    kind : str
        One of :data:`KINDS`.
    points : (N, 2) float ndarray
        Vertices (x, y) in image pixels, N >= 1.
    radii : (N,) float ndarray or None
        Per-vertex radius in pixels (> 0; polylines), None otherwise.
    label : str or None
        Class label (scribbles, points) or any tag the app wants.
    closed : bool
        Whether a polyline is finished (no more vertices are appended).
    meta : dict
        JSON-serialisable extras, e.g. ``{"parent": [shape, vertex]}`` for
        a polyline that starts on another one.

    Raises
    ------
    TypeError, ValueError
        An unknown kind, malformed points, radii not one positive value per
        point, a non-str label, a non-bool ``closed`` or a ``meta`` that is
        not JSON with finite numbers.

    Examples
    --------
    >>> Shape("polyline", [(0, 0), (5, 0)], radii=[2, 1]).radii.tolist()
    [2.0, 1.0]
    """

    kind: str
    points: np.ndarray
    radii: np.ndarray | None = None
    label: str | None = None
    closed: bool = True
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        if not isinstance(self.kind, str) or self.kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {self.kind!r}")
        self.points = as_points(self.points, name="points", min_points=1)
        if self.radii is not None:
            r = np.asarray(self.radii)
            if r.dtype == object or not (np.issubdtype(r.dtype, np.integer) or np.issubdtype(r.dtype, np.floating)):
                raise TypeError(f"radii must be real numbers, got dtype {r.dtype}")
            r = r.astype(np.float64)
            if r.shape != (len(self.points),):
                raise ValueError(f"radii must have one value per point ({len(self.points)}), got {r.shape}")
            if not np.all(np.isfinite(r)) or np.any(r <= 0):
                raise ValueError("radii must be finite and > 0")
            self.radii = r
        if self.label is not None and not isinstance(self.label, str):
            raise TypeError(f"label must be a str or None, got {type(self.label).__name__}")
        self.closed = _bool(self.closed, "closed")
        self.meta = _json_meta(self.meta)

    def to_dict(self) -> dict:
        """The shape's fields as plain JSON-ready values (points and radii as lists)."""
        return {
            "kind": self.kind,
            "points": self.points.tolist(),
            "radii": None if self.radii is None else self.radii.tolist(),
            "label": self.label,
            "closed": self.closed,
            "meta": self.meta,
        }


@dataclass(frozen=True)
class AnnotationEvent:
    """What changed in an :class:`AnnotationModel` (passed to its observers).

    Parameters
    ----------
    type : str
        One of ``"add"``, ``"append"``, ``"update"``, ``"remove"``,
        ``"clear"``, ``"load"``, ``"undo"``, ``"redo"``.
    index : int or None
        The affected shape (its index before a removal); None when the
        change concerns all shapes.

    Examples
    --------
    >>> m, events = AnnotationModel(), []
    >>> m.observe(events.append)
    >>> m.add_shape("point", [(1, 2)]); m.undo()
    0
    True
    >>> events
    [AnnotationEvent(type='add', index=0), AnnotationEvent(type='undo', index=None)]
    """

    type: str
    index: int | None = None


class AnnotationModel:
    """A list of shapes with undo/redo and JSON round trip.

    Every edit is one undo step (a polyline vertex, a whole freehand
    stroke, a radius change, a clear). Observers are called after each
    change with an :class:`AnnotationEvent`.

    Parameters
    ----------
    shapes : sequence of Shape or dict
        Initial shapes (dicts hold a :class:`Shape`'s fields); none by
        default. Not an undo step.
    max_undo : int
        Most undo steps kept (0 .. 100000); the oldest are dropped.

    Examples
    --------
    >>> m = AnnotationModel()
    >>> i = m.add_shape("polyline", [(10, 10)], radii=[3.0], closed=False)
    >>> m.append_point(i, (20, 15))
    >>> m.shapes[0].points.tolist()
    [[10.0, 10.0], [20.0, 15.0]]
    >>> m.undo(); len(m.shapes[0].points)
    True
    1
    >>> AnnotationModel.from_json(m.to_json()).shapes[0].kind
    'polyline'
    """

    def __init__(self, shapes=(), *, max_undo: int = 200):
        if isinstance(shapes, (str, bytes, dict)) or not hasattr(shapes, "__iter__"):
            raise TypeError(f"shapes must be a sequence of Shape or dicts, got {type(shapes).__name__}")
        self._shapes: list[Shape] = []
        for k, s in enumerate(shapes):
            if isinstance(s, Shape):
                self._shapes.append(s)
            elif isinstance(s, dict):
                try:
                    self._shapes.append(Shape(**s))
                except TypeError as exc:
                    raise TypeError(f"shapes[{k}]: {exc}") from None
            else:
                raise TypeError(f"shapes[{k}] must be a Shape or a dict, got {type(s).__name__}")
        self._undo: list[list[Shape]] = []
        self._redo: list[list[Shape]] = []
        self._observers: list[Callable[[AnnotationEvent], None]] = []
        self.max_undo = _int(max_undo, "max_undo")
        if not 0 <= self.max_undo <= 100_000:
            raise ValueError(f"max_undo must be in [0, 100000], got {max_undo!r}")

    # -- observation ----------------------------------------------------
    def observe(self, callback: Callable[[AnnotationEvent], None]) -> None:
        """Call ``callback(event)`` after every change.

        Parameters
        ----------
        callback : callable
            Called with one :class:`AnnotationEvent`, in registration order.
        """
        if not callable(callback):
            raise TypeError("callback must be callable")
        self._observers.append(callback)

    def unobserve(self, callback) -> None:
        """Stop calling ``callback``.

        Parameters
        ----------
        callback : callable
            A callback registered with :meth:`observe`.

        Raises
        ------
        ValueError
            If it is not observing this model.
        """
        if callback not in self._observers:
            raise ValueError("callback is not observing this model")
        self._observers.remove(callback)

    def _notify(self, event: AnnotationEvent) -> None:
        for cb in list(self._observers):
            cb(event)

    def _checkpoint(self) -> None:
        self._undo.append(copy.deepcopy(self._shapes))
        if len(self._undo) > self.max_undo:
            self._undo.pop(0)
        self._redo.clear()

    def _index(self, index: int) -> int:
        index = _int(index, "index")
        if not -len(self._shapes) <= index < len(self._shapes):
            raise ValueError(f"shape index {index!r} out of range for {len(self._shapes)} shapes")
        return int(index) % len(self._shapes)

    # -- queries ----------------------------------------------------------
    @property
    def shapes(self) -> tuple[Shape, ...]:
        """The shapes (read-only view; edit through the methods)."""
        return tuple(self._shapes)

    def __len__(self) -> int:
        return len(self._shapes)

    def of_kind(self, kind: str) -> list[Shape]:
        """Shapes of one kind, in drawing order.

        Parameters
        ----------
        kind : str
            One of :data:`KINDS`.

        Returns
        -------
        list of Shape
            The shapes themselves (not copies).
        """
        if not isinstance(kind, str) or kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
        return [s for s in self._shapes if s.kind == kind]

    def open_polyline(self) -> int | None:
        """Index of the polyline still being drawn, if any."""
        for i in range(len(self._shapes) - 1, -1, -1):
            s = self._shapes[i]
            if s.kind == "polyline" and not s.closed:
                return i
        return None

    def nearest_vertex(self, xy, *, kinds=("polyline",), max_distance: float = np.inf,
                       exclude: int | None = None) -> tuple[int, int] | None:
        """``(shape, vertex)`` of the vertex nearest to ``xy`` within ``max_distance``.

        Parameters
        ----------
        xy : (x, y)
            Query point in image pixels.
        kinds : str or sequence of str
            Kinds of shapes searched (polylines by default).
        max_distance : float
            Largest distance in pixels (>= 0; unlimited by default).
        exclude : int, optional
            A shape index to skip (e.g. the polyline being drawn).

        Returns
        -------
        (int, int) or None
            Shape index and vertex index, or None if no vertex is close enough.

        Examples
        --------
        >>> m = AnnotationModel([Shape("polyline", [(0, 0), (10, 0)], radii=[1, 1])])
        >>> m.nearest_vertex((9, 1)), m.nearest_vertex((9, 1), max_distance=1)
        ((0, 1), None)
        """
        p = as_points([xy], name="xy")[0]
        max_distance = _number(max_distance, "max_distance", allow_inf=True)
        if isinstance(kinds, str):
            kinds = (kinds,)
        if not hasattr(kinds, "__iter__") or any(not isinstance(k, str) or k not in KINDS for k in kinds):
            raise ValueError(f"kinds must be a sequence of {KINDS}, got {kinds!r}")
        if exclude is not None:
            exclude = _int(exclude, "exclude")
        best, best_d = None, max_distance
        for i, s in enumerate(self._shapes):
            if s.kind not in kinds or i == exclude:
                continue
            d = np.hypot(*(s.points - p).T)
            j = int(np.argmin(d))
            if d[j] <= best_d:
                best, best_d = (i, j), float(d[j])
        return best

    # -- edits ------------------------------------------------------------
    def add_shape(self, kind: str, points, *, radii=None, label: str | None = None,
                  closed: bool = True, meta: dict | None = None) -> int:
        """Add a shape; returns its index.

        Parameters
        ----------
        kind : str
            One of :data:`KINDS`.
        points : (N, 2) array_like
            Vertices (x, y) in image pixels, N >= 1.
        radii : (N,) array_like, optional
            Radius per vertex (pixels, > 0), for polylines.
        label : str, optional
            Class label (scribbles, points) or a tag.
        closed : bool
            False for a polyline still being drawn (see :meth:`append_point`).
        meta : dict, optional
            JSON-serialisable extras (copied).

        Returns
        -------
        int
            The new shape's index (the last).
        """
        if meta is not None and not isinstance(meta, dict):
            raise TypeError(f"meta must be a dict or None, got {type(meta).__name__}")
        shape = Shape(kind, points, radii, label, closed, dict(meta or {}))
        self._checkpoint()
        self._shapes.append(shape)
        self._notify(AnnotationEvent("add", len(self._shapes) - 1))
        return len(self._shapes) - 1

    def append_point(self, index: int, xy, radius: float | None = None) -> None:
        """Append a vertex to an open polyline (or any shape).

        Parameters
        ----------
        index : int
            Shape index (negative counts from the end).
        xy : (x, y)
            The new vertex in image pixels.
        radius : float, optional
            Its radius (> 0) if the shape has radii; the last vertex's radius
            by default.
        """
        i = self._index(index)
        s = self._shapes[i]
        p = as_points([xy], name="xy")
        if radius is not None:
            radius = _number(radius, "radius", positive=True)
        if s.radii is not None:
            r = s.radii[-1] if radius is None else radius
        self._checkpoint()
        s.points = np.vstack([s.points, p])
        if s.radii is not None:
            s.radii = np.append(s.radii, r)
        self._notify(AnnotationEvent("append", i))

    def set_closed(self, index: int, closed: bool = True) -> None:
        """Finish (or reopen) a polyline.

        Parameters
        ----------
        index : int
            Shape index (negative counts from the end).
        closed : bool
            True finishes the polyline, False reopens it for more vertices.
        """
        i = self._index(index)
        closed = _bool(closed, "closed")
        self._checkpoint()
        self._shapes[i].closed = closed
        self._notify(AnnotationEvent("update", i))

    def set_radius(self, index: int, vertex: int, radius: float) -> None:
        """Set the radius of one vertex of a polyline.

        Parameters
        ----------
        index : int
            Shape index (negative counts from the end); the shape must have radii.
        vertex : int
            Vertex index (negative counts from the end).
        radius : float
            New radius in pixels (> 0).
        """
        i = self._index(index)
        s = self._shapes[i]
        if s.radii is None:
            raise ValueError(f"shape {i} ({s.kind}) has no radii")
        vertex = _int(vertex, "vertex")
        if not -len(s.radii) <= vertex < len(s.radii):
            raise ValueError(f"vertex {vertex} out of range for {len(s.radii)} vertices")
        radius = _number(radius, "radius", positive=True)
        self._checkpoint()
        s.radii = s.radii.copy()
        s.radii[vertex] = float(radius)
        self._notify(AnnotationEvent("update", i))

    def move_vertex(self, index: int, vertex: int, xy) -> None:
        """Move one vertex.

        Parameters
        ----------
        index : int
            Shape index (negative counts from the end).
        vertex : int
            Vertex index (negative counts from the end).
        xy : (x, y)
            New position in image pixels.
        """
        i = self._index(index)
        s = self._shapes[i]
        vertex = _int(vertex, "vertex")
        if not -len(s.points) <= vertex < len(s.points):
            raise ValueError(f"vertex {vertex} out of range for {len(s.points)} vertices")
        p = as_points([xy], name="xy")[0]
        self._checkpoint()
        s.points = s.points.copy()
        s.points[vertex] = p
        self._notify(AnnotationEvent("update", i))

    def remove_shape(self, index: int) -> None:
        """Delete one shape (undoable); later shapes move down by one index.

        Parameters
        ----------
        index : int
            Shape index (negative counts from the end).
        """
        i = self._index(index)
        self._checkpoint()
        del self._shapes[i]
        self._notify(AnnotationEvent("remove", i))

    def clear(self) -> None:
        """Remove every shape (undoable)."""
        if not self._shapes:
            return
        self._checkpoint()
        self._shapes.clear()
        self._notify(AnnotationEvent("clear"))

    # -- history ----------------------------------------------------------
    @property
    def can_undo(self) -> bool:
        return bool(self._undo)

    @property
    def can_redo(self) -> bool:
        return bool(self._redo)

    def undo(self) -> bool:
        """Revert the last edit; False if there is nothing to undo."""
        if not self._undo:
            return False
        self._redo.append(self._shapes)
        self._shapes = self._undo.pop()
        self._notify(AnnotationEvent("undo"))
        return True

    def redo(self) -> bool:
        """Re-apply the last undone edit; False if there is nothing to redo."""
        if not self._redo:
            return False
        self._undo.append(self._shapes)
        self._shapes = self._redo.pop()
        self._notify(AnnotationEvent("redo"))
        return True

    # -- serialisation ----------------------------------------------------
    def to_dict(self) -> dict:
        """``{"version": 1, "shapes": [...]}``, each shape as :meth:`Shape.to_dict` gives it."""
        return {"version": 1, "shapes": [s.to_dict() for s in self._shapes]}

    def to_json(self) -> str:
        """All shapes as JSON (image-pixel coordinates)."""
        return json.dumps(self.to_dict())

    @staticmethod
    def _parse(text) -> list[Shape]:
        if not isinstance(text, (str, bytes, bytearray, dict)):
            raise TypeError(f"text must be annotation JSON (str) or its dict, got {type(text).__name__}")
        try:
            d = json.loads(text) if isinstance(text, (str, bytes, bytearray)) else text
        except (json.JSONDecodeError, UnicodeDecodeError, RecursionError) as exc:
            raise ValueError(f"text is not valid annotation JSON: {exc}") from None
        if not isinstance(d, dict) or not isinstance(d.get("shapes"), list):
            raise ValueError("text: annotation JSON needs a 'shapes' list")
        version = d.get("version", 1)
        if version != 1 or isinstance(version, bool):
            raise ValueError(f"text: unsupported annotation JSON version {version!r} (this reads version 1)")
        out = []
        for k, s in enumerate(d["shapes"]):
            if not isinstance(s, dict):
                raise ValueError(f"text: shapes[{k}] must be an object")
            try:
                out.append(Shape(**s))
            except (TypeError, ValueError) as exc:
                raise ValueError(f"text: shapes[{k}]: {exc}") from None
        return out

    def load_json(self, text) -> None:
        """Replace all shapes by those in ``text`` (undoable).

        Parameters
        ----------
        text : str, bytes or dict
            Annotation JSON written by :meth:`to_json` (version 1), or its
            parsed dict.

        Raises
        ------
        TypeError, ValueError
            If ``text`` is not annotation JSON or a shape is malformed; the
            model is then unchanged.
        """
        shapes = self._parse(text)
        self._checkpoint()
        self._shapes = shapes
        self._notify(AnnotationEvent("load"))

    @classmethod
    def from_json(cls, text) -> AnnotationModel:
        """A new model holding the shapes in ``text``.

        Parameters
        ----------
        text : str, bytes or dict
            Annotation JSON written by :meth:`to_json`, or its parsed dict.

        Returns
        -------
        AnnotationModel
            With an empty undo history.
        """
        return cls(cls._parse(text))
