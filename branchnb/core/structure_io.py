"""Serialisation and rendering of :class:`~branchnb.core.structure.Structure` (its JSON and image faces).

The methods live on :class:`~branchnb.core.structure.Structure` (through the mixin
``_StructureOutput``); they were moved here from ``structure.py`` unchanged, to keep that
module about the tree itself.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .image import as_float_image, as_points
from .io import encode_png
from .jsonio import dumps_strict, loads_strict
from .render import draw_polylines
from .svg import polylines_to_svg
from .validate import check_int, check_real, check_shape, real_array

if TYPE_CHECKING:
    from .structure import Structure

__all__ = ["GENERATION_COLORS", "STRUCTURE_JSON_VERSION"]

#: Version written to (and required from) structure JSON.
STRUCTURE_JSON_VERSION = 1

#: Colours of generations 0, 1, 2, ... (the last repeats for deeper ones).
GENERATION_COLORS = ((0.10, 0.62, 0.20), (0.15, 0.35, 0.95), (0.95, 0.60, 0.05),
                     (0.90, 0.15, 0.55), (0.05, 0.70, 0.75))


class _StructureOutput:
    """JSON and image output of a structure (mixed into :class:`~branchnb.core.structure.Structure`)."""

    # -- I/O ------------------------------------------------------------
    def to_dict(self) -> dict:
        """Plain JSON-ready dict: ``version``, ``image_shape`` and per branch its fields as lists.

        Returns
        -------
        dict
            Read back by :meth:`from_dict`.
        """
        return {
            "version": STRUCTURE_JSON_VERSION,
            "image_shape": list(self.image_shape) if self.image_shape else None,
            "branches": [
                {
                    "points": b.points.tolist(),
                    "thickness": b.thickness.tolist(),
                    "parent": b.parent,
                    "parent_vertex": b.parent_vertex,
                }
                for b in self.branches
            ],
        }

    def to_json(self) -> str:
        """Serialise to a JSON string (round-trips through :meth:`from_json`).

        Returns
        -------
        str

        Raises
        ------
        ValueError
            If a value is NaN or infinite (edited after construction).
        """
        return dumps_strict(self.to_dict(), name="structure")

    @classmethod
    def from_dict(cls, d: dict, *, name: str = "structure") -> Structure:
        """Build a structure from :meth:`to_dict` output, checking every field.

        Parameters
        ----------
        d : dict
            ``{"version": 1, "image_shape": [H, W] or None, "branches":
            [{"points", "thickness", "parent", "parent_vertex"}, ...]}``
            (``version`` and ``image_shape`` may be absent).
        name : str, optional
            How messages name the document.

        Returns
        -------
        Structure

        Raises
        ------
        ValueError, TypeError
            A missing or mistyped field, an unknown ``version``, or points
            and thickness that are not finite numbers; the message names
            the field (``structure['branches'][3]['thickness']``).
        """
        if not isinstance(d, dict):
            raise TypeError(f"d ({name}) must be a JSON object (dict), got {type(d).__name__}")
        version = d.get("version", STRUCTURE_JSON_VERSION)
        if version != STRUCTURE_JSON_VERSION or isinstance(version, bool):
            raise ValueError(f"{name}['version'] = {version!r} is not supported (expected {STRUCTURE_JSON_VERSION})")
        branches = d.get("branches")
        if not isinstance(branches, list):
            raise ValueError(f"{name} needs a 'branches' list")
        shape = d.get("image_shape")
        if shape is not None:
            if not isinstance(shape, (list, tuple)) or len(shape) != 2:
                raise ValueError(f"{name}['image_shape'] must be [height, width] or null, got {shape!r:.60}")
            shape = check_shape(shape, f"{name}['image_shape']")
        from .structure import Branch  # (the module that mixes these methods in)

        out = []
        for i, b in enumerate(branches):
            where = f"{name}['branches'][{i}]"
            if not isinstance(b, dict):
                raise TypeError(f"{where} must be an object, got {type(b).__name__}")
            missing = [k for k in ("points", "thickness") if k not in b]
            if missing:
                raise ValueError(f"{where} lacks {', '.join(map(repr, missing))}")
            unknown = set(b) - {"points", "thickness", "parent", "parent_vertex"}
            if unknown:
                raise ValueError(f"{where} has unknown field(s) {sorted(unknown)}")
            parent = check_int(b.get("parent"), f"{where}['parent']", 0, allow_none=True)
            vertex = check_int(b.get("parent_vertex"), f"{where}['parent_vertex']", 0, allow_none=True)
            points = as_points(b["points"], name=f"{where}['points']")
            thickness = real_array(b["thickness"], f"{where}['thickness']", ndim=(0, 1))
            try:
                out.append(Branch(points, thickness, parent, vertex))
            except ValueError as exc:
                raise ValueError(f"{where}: {exc}") from None
        return cls(out, shape)

    @classmethod
    def from_json(cls, text: str) -> Structure:
        """Parse a structure written by :meth:`to_json` (strict JSON, every field checked).

        Parameters
        ----------
        text : str or bytes
            JSON text in the layout of :meth:`to_dict`.

        Returns
        -------
        Structure

        Raises
        ------
        TypeError, ValueError
            Invalid JSON (NaN, duplicate keys, ...) or a malformed field (see
            :meth:`from_dict`).

        Examples
        --------
        >>> from branchnb.core.structure import Branch, Structure
        >>> s = Structure([Branch([(0, 0), (10, 0)], 2.0)])
        >>> Structure.from_json(s.to_json()).n_vertices
        2
        """
        return cls.from_dict(loads_strict(text, name="text"))

    # -- rendering ------------------------------------------------------
    def _canvas_shape(self, shape) -> tuple[int, int]:
        if shape is not None:
            return check_shape(shape, "shape")
        if self.image_shape is not None:
            return self.image_shape
        _x0, _y0, x1, y1 = self.bounds()
        return check_shape((max(np.ceil(y1), 0) + 2, max(np.ceil(x1), 0) + 2), "the structure's bounds")

    def render(self, shape=None, *, background=None, color=(0.0, 0.0, 0.0), by_generation: bool = False,
               alpha: float = 1.0, min_width: float = 0.0) -> np.ndarray:
        """Rasterise the skeleton with its thickness (width = 2 r).

        Parameters
        ----------
        shape : (H, W), optional
            Canvas size; ``image_shape`` or the bounds by default.
        background : (H, W, C) array_like, optional
            Image to draw on (white if None).
        color : RGB triple, or one per branch
            Stroke colour(s) in [0, 1]; ignored with ``by_generation``.
        by_generation : bool
            Colour each branch by its generation (:data:`GENERATION_COLORS`).
        alpha : float
            Opacity of the strokes.
        min_width : float
            Draw every stroke at least this wide (pixels), e.g. to see a
            thin skeleton over a photo.

        Returns
        -------
        (H, W, C) float32 ndarray
            A new image (C of the background; RGB on the default white).

        Examples
        --------
        >>> from branchnb.core.structure import Branch, Structure
        >>> img = Structure([Branch([(2, 5), (17, 5)], 2.0)]).render((10, 20))
        >>> img.shape, float(img[5, 10].max()), float(img[0, 0].min())
        ((10, 20, 3), 0.0, 1.0)
        """
        min_width = check_real(min_width, "min_width", 0, 1e4)
        self.validate()
        if background is None:
            h, w = self._canvas_shape(shape)
            background = np.ones((h, w, 3), np.float32)
        else:
            background = as_float_image(background, name="background")
        if not self.branches:
            return background.copy()
        if by_generation:
            pal = np.asarray(GENERATION_COLORS, np.float32)
            color = pal[np.minimum([self.generation(i) for i in range(len(self.branches))], len(pal) - 1)]
        return draw_polylines(background, [b.points for b in self.branches],
                              widths=[np.maximum(2 * b.thickness, min_width) for b in self.branches],
                              colors=color, alpha=alpha)

    def to_svg(self, shape=None, *, color=(0.0, 0.0, 0.0)) -> str:
        """SVG document of the skeleton with thickness.

        Parameters
        ----------
        shape : (H, W), optional
            Canvas size in pixels; ``image_shape`` or the bounds by default.
        color : RGB triple, or one per branch
            Stroke colour(s) in [0, 1].

        Returns
        -------
        str
            A standalone SVG document on a white background, one path per
            branch with width ``2 r``.

        Examples
        --------
        >>> from branchnb.core.structure import Branch, Structure
        >>> svg = Structure([Branch([(0, 0), (10, 0)], 2.0)], image_shape=(8, 12)).to_svg()
        >>> svg.startswith("<svg") or svg.startswith("<?xml")
        True
        """
        h, w = self._canvas_shape(shape)
        return polylines_to_svg([b.points for b in self.branches],
                                widths=[2 * b.thickness for b in self.branches],
                                colors=color, size=(w, h), background=(1, 1, 1))

    def _repr_png_(self) -> bytes | None:
        if not self.branches:
            return None
        try:
            return encode_png(self.render())
        except ValueError:  # too large to show: the text repr stands in
            return None
