"""The user's input to lazy snapping: scribbles, layers and the layer set (with its JSON form).

A :class:`Scribble` is a brush stroke on the training leaf; a :class:`Layer`
(veins, spots, ...) has a name, a colour, an order and its scribbles; a
:class:`LayerSet` holds the layers. :func:`branchnb.leaves.layers.grow_layers`
grows them into masks. Everything here is importable from
:mod:`branchnb.leaves.layers` too.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from ..core.image import as_points
from ..core.jsonio import dumps_strict, loads_strict
from ..core.validate import MAX_COUNT, check_int, check_real

__all__ = ["Scribble", "Layer", "LayerSet"]

_HEX = re.compile(r"^#[0-9a-fA-F]{6}$")


@dataclass
class Scribble:
    """One freehand stroke: a polyline in image pixels ``(x, y)`` and a brush radius.

    Parameters
    ----------
    points : (N, 2) array_like
        The stroke's polyline ``(x, y)`` in image pixels; one point is a dab.
    radius : float
        Brush radius in pixels, in ``(0, 1e4]`` (default 2): the stroke
        covers every pixel within ``radius`` of the polyline.

    Examples
    --------
    >>> Scribble([(0, 0), (4, 3)], 1.5).points.shape
    (2, 2)
    """

    points: np.ndarray
    radius: float = 2.0

    def __post_init__(self):
        self.points = as_points(self.points, name="points", min_points=1)
        # OpenCV draws strokes at most 32767 px thick: 10,000 px covers any image this package reads
        self.radius = check_real(self.radius, "radius", 0.0, 1e4, low_open=True)

    def to_dict(self) -> dict:
        return {"points": self.points.tolist(), "radius": self.radius}

    @classmethod
    def from_dict(cls, d: dict) -> Scribble:
        """A scribble from :meth:`to_dict`'s plain data.

        Parameters
        ----------
        d : dict
            ``{"points": [[x, y], ...], "radius": r}``; ``radius`` defaults to 2.

        Returns
        -------
        Scribble
        """
        _check_dict(d, "d", "points")
        return cls(d["points"], d.get("radius", 2.0))


def _check_dict(d, name: str, *keys) -> dict:
    if not isinstance(d, dict):
        raise TypeError(f"{name} must be a dict, got {type(d).__name__}")
    missing = [k for k in keys if k not in d]
    if missing:
        raise ValueError(f"{name} lacks the key(s) {missing}")
    return d


def _check_list(value, name: str) -> list:
    if isinstance(value, (str, bytes, dict)) or not isinstance(value, (list, tuple)):
        raise TypeError(f"{name} must be a list, got {type(value).__name__}")
    return list(value)


def _as_scribble(s, name: str) -> Scribble:
    if isinstance(s, Scribble):
        return s
    try:
        return Scribble(np.asarray(s, float))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a Scribble or an (N, 2) array of (x, y) points: {exc}") from exc


@dataclass
class Layer:
    """A user layer of the training leaf.

    Parameters
    ----------
    name : str
        Unique name ("veins", "spots", ...).
    colour : str
        Display colour ``#rrggbb``.
    order : int
        Stacking order, 0 = top: induced (and removed) first, drawn last.
    scribbles : list of Scribble
        The user's strokes on this layer (an ``(N, 2)`` array of points is
        taken as a Scribble of radius 2); empty by default.
    """

    name: str
    colour: str = "#d62728"
    order: int = 0
    scribbles: list = field(default_factory=list)

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name.strip():
            raise ValueError(f"name must be a non-empty str, got {self.name!r}")
        if self.name == "blade":
            raise ValueError("name 'blade' is reserved for the background layer")
        if not isinstance(self.colour, str) or not _HEX.match(self.colour):
            raise ValueError(f"colour must be '#rrggbb', got {self.colour!r}")
        if isinstance(self.order, bool) or not isinstance(self.order, (int, np.integer)):
            raise TypeError(f"order must be an int, got {self.order!r}")
        self.order = int(self.order)
        self.scribbles = [_as_scribble(s, f"scribbles[{i}]")
                          for i, s in enumerate(_check_list(self.scribbles, "scribbles"))]

    def to_dict(self) -> dict:
        return {"name": self.name, "colour": self.colour, "order": self.order,
                "scribbles": [s.to_dict() for s in self.scribbles]}

    @classmethod
    def from_dict(cls, d: dict) -> Layer:
        """A layer from :meth:`to_dict`'s plain data.

        Parameters
        ----------
        d : dict
            ``{"name", "colour", "order", "scribbles"}``; only ``name`` is
            required (colour ``#d62728``, order 0, no scribbles by default).

        Returns
        -------
        Layer
        """
        _check_dict(d, "d", "name")
        return cls(d["name"], d.get("colour", "#d62728"), check_int(d.get("order", 0), "order"),
                   [Scribble.from_dict(s) for s in _check_list(d.get("scribbles", []), "scribbles")])


@dataclass
class LayerSet:
    """The user's layers of one training leaf, plus optional blade scribbles.

    Parameters
    ----------
    layers : list of Layer
        The user layers, unique names (empty by default).
    background : list of Scribble
        Optional scribbles on the plain blade (the background layer
        ``"blade"``); they sharpen the background colour model but are not
        required.

    Examples
    --------
    >>> ls = LayerSet([Layer("veins", order=0), Layer("spots", "#1f77b4", 1)])
    >>> ls.add_scribble("veins", [(1, 1), (5, 5)])
    >>> [layer.name for layer in LayerSet.from_json(ls.to_json()).ordered()]
    ['veins', 'spots']
    """

    layers: list = field(default_factory=list)
    #: Optional scribbles on the plain blade (the background); they sharpen
    #: the background colour model but are not required.
    background: list = field(default_factory=list)

    def __post_init__(self):
        self.layers = _check_list(self.layers, "layers")
        self.background = _check_list(self.background, "background")
        for i, layer in enumerate(self.layers):
            if not isinstance(layer, Layer):
                raise TypeError(f"layers[{i}] must be a Layer, got {type(layer).__name__}")
        names = [layer.name for layer in self.layers]
        if len(set(names)) != len(names):
            raise ValueError(f"layer names must be unique, got {names}")
        self.background = [_as_scribble(s, f"background[{i}]") for i, s in enumerate(self.background)]

    # -- editing ---------------------------------------------------------
    def names(self) -> list[str]:
        return [layer.name for layer in self.ordered()]

    def ordered(self) -> list[Layer]:
        """Layers from top (order 0) to bottom; ties keep insertion order."""
        return sorted(self.layers, key=lambda layer: layer.order)

    def get(self, name: str) -> Layer:
        """The layer called ``name`` (KeyError if there is none).

        Parameters
        ----------
        name : str
            A layer's name.

        Returns
        -------
        Layer
        """
        for layer in self.layers:
            if layer.name == name:
                return layer
        raise KeyError(f"no layer named {name!r}; layers are {[x.name for x in self.layers]}")

    def add(self, name: str, colour: str = "#d62728", order: int | None = None) -> Layer:
        """Add an empty layer (no scribbles yet).

        Parameters
        ----------
        name : str
            Its name, new in the set and not ``"blade"``.
        colour : str
            Display colour ``#rrggbb``.
        order : int, optional
            Stacking order (0 = top); None: below every layer so far.

        Returns
        -------
        Layer
            The new layer (scribble on it with :meth:`add_scribble`).
        """
        if any(x.name == name for x in self.layers):
            raise ValueError(f"a layer named {name!r} exists already")
        order = len(self.layers) if order is None else order
        layer = Layer(name, colour, order)
        self.layers.append(layer)
        return layer

    def remove(self, name: str) -> None:
        """Remove layer ``name`` and renumber the others' order 0, 1, ...

        Parameters
        ----------
        name : str
            A layer's name (KeyError if there is none).
        """
        self.layers.remove(self.get(name))
        self._renumber()

    def move(self, name: str, new_index: int) -> None:
        """Put layer ``name`` at position ``new_index`` of the top-to-bottom order.

        Parameters
        ----------
        name : str
            A layer's name (KeyError if there is none).
        new_index : int
            Its new position, 0 = top; clipped to the number of layers.
        """
        order = self.ordered()
        layer = self.get(name)
        order.remove(layer)
        new_index = check_int(new_index, "new_index", -MAX_COUNT, MAX_COUNT)
        order.insert(int(np.clip(new_index, 0, len(order))), layer)
        for i, x in enumerate(order):
            x.order = i

    def _renumber(self) -> None:
        for i, x in enumerate(self.ordered()):
            x.order = i

    def add_scribble(self, name: str, points, radius: float = 2.0) -> None:
        """Add a scribble to layer ``name`` (``"blade"`` for the background).

        Parameters
        ----------
        name : str
            A layer's name, or ``"blade"`` for a background scribble.
        points : (N, 2) array_like
            The stroke ``(x, y)`` in image pixels.
        radius : float
            Brush radius in pixels (default 2).
        """
        s = Scribble(points, radius)
        if name == "blade":
            self.background.append(s)
            return
        if not any(x.name == name for x in self.layers):
            raise ValueError(f"name {name!r} is not a layer (layers: {[x.name for x in self.layers]}); "
                             "add the layer first")
        self.get(name).scribbles.append(s)

    # -- JSON ------------------------------------------------------------
    def to_dict(self) -> dict:
        return {"version": 1, "layers": [x.to_dict() for x in self.ordered()],
                "background": [s.to_dict() for s in self.background]}

    def to_json(self) -> str:
        """Strict JSON (no NaN)."""
        return dumps_strict(self.to_dict(), name="layer set")

    @classmethod
    def from_dict(cls, d: dict) -> LayerSet:
        """A layer set from :meth:`to_dict`'s plain data.

        Parameters
        ----------
        d : dict
            ``{"layers": [...], "background": [...]}`` (``background`` optional).

        Returns
        -------
        LayerSet
        """
        if not isinstance(d, dict) or "layers" not in d:
            raise ValueError("d (a layer set) must be a dict with a 'layers' list")
        return cls([Layer.from_dict(x) for x in _check_list(d["layers"], "layers")],
                   [Scribble.from_dict(s) for s in _check_list(d.get("background", []), "background")])

    @classmethod
    def from_json(cls, text: str) -> LayerSet:
        """A layer set from :meth:`to_json`'s text.

        Parameters
        ----------
        text : str
            Strict JSON (duplicate keys and NaN refused).

        Returns
        -------
        LayerSet
        """
        return cls.from_dict(loads_strict(text, name="text"))
