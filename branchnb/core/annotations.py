"""Annotation shapes <-> :class:`~branchnb.core.structure.Structure`, with no widget code.

The branching app's canvas stores one polyline per branch (radii = the
thickness per vertex, ``meta["parent"] = [shape, vertex]`` for a child).
Its JSON export (``{"version": 1, "shapes": [...]}``) is read here, so that
scripts and batch workers turn annotations into a structure without
importing ipywidgets.
"""

from __future__ import annotations

import json
from collections.abc import Mapping

import numpy as np

from .image import as_points
from .structure import Branch, Structure

__all__ = ["annotations_to_structure", "structure_from_annotation_json", "structure_to_annotations"]


def structure_to_annotations(structure: Structure, keep=()) -> str:
    """Annotation JSON with one polyline per branch (radii = thickness, parent in ``meta``).

    Parameters
    ----------
    structure : Structure
        The structure to export; branch ``k`` becomes shape ``k``.
    keep : iterable, optional
        Other shapes (objects with ``to_dict()`` or dicts, e.g. the guidance
        strokes) appended after the branches, unchanged. Default: none.

    Returns
    -------
    str
        The document ``{"version": 1, "shapes": [...]}`` as JSON text, read
        back by :func:`structure_from_annotation_json`.

    Raises
    ------
    TypeError
        If ``structure`` is not a :class:`Structure`.

    Examples
    --------
    >>> s = Structure([Branch([[0, 0], [10, 0]], 2.0)], image_shape=(20, 20))
    >>> annotations_to_structure(json.loads(structure_to_annotations(s))["shapes"])[1]
    [0]
    """
    if not isinstance(structure, Structure):
        raise TypeError(f"structure must be a Structure, got {type(structure).__name__}")
    shapes = []
    for b in structure.branches:
        meta = {} if b.parent is None else {"parent": [int(b.parent), int(b.parent_vertex)]}
        shapes.append({"kind": "polyline", "points": b.points.tolist(), "radii": b.thickness.tolist(),
                       "label": None, "closed": True, "meta": meta})
    for s in keep:
        shapes.append(s.to_dict() if hasattr(s, "to_dict") else dict(s))
    return json.dumps({"version": 1, "shapes": shapes})


def _field(shape, name, default=None):
    if isinstance(shape, Mapping):
        return shape.get(name, default)
    return getattr(shape, name, default)


def _polyline(shape, k: int):
    """(points, radii or None, meta) of shape ``k`` if it is a polyline, else None (validated)."""
    kind = _field(shape, "kind")
    if not isinstance(kind, str):
        raise TypeError(f"shapes[{k}]: kind must be a str, got {type(kind).__name__}")
    if kind != "polyline":
        return None
    pts = as_points(_field(shape, "points"), name=f"shapes[{k}].points", min_points=1)
    radii = _field(shape, "radii")
    if radii is not None:
        r = np.asarray(radii)
        if r.dtype == object or not (np.issubdtype(r.dtype, np.integer) or np.issubdtype(r.dtype, np.floating)):
            raise TypeError(f"shapes[{k}].radii must be real numbers, got dtype {r.dtype}")
        r = r.astype(np.float64)
        if r.shape != (len(pts),):
            raise ValueError(f"shapes[{k}].radii must have one value per point ({len(pts)}), got {r.shape}")
        if not np.all(np.isfinite(r)) or np.any(r <= 0):
            raise ValueError(f"shapes[{k}].radii must be finite and > 0")
        radii = r
    meta = _field(shape, "meta") or {}
    if not isinstance(meta, Mapping):
        raise TypeError(f"shapes[{k}].meta must be a dict, got {type(meta).__name__}")
    return pts, radii, meta


def _parent_ref(meta):
    ref = meta.get("parent")
    if ref is None:
        return None
    try:
        ps, pv = ref
    except (TypeError, ValueError):
        return None
    if isinstance(ps, bool) or isinstance(pv, bool) or not all(
            isinstance(v, (int, np.integer)) for v in (ps, pv)):
        return None
    return int(ps), int(pv)


def annotations_to_structure(shapes, image_shape=None) -> tuple[Structure, list[int]]:
    """The structure drawn as polylines, and the shape index of each branch.

    ``shapes`` are annotation shapes: objects with ``kind``, ``points``,
    ``radii`` and ``meta`` attributes (the canvas's ``Shape``) or dicts with
    those keys (its JSON). Only polylines count; other kinds (guidance
    strokes, points) are skipped. A polyline's parent is taken from
    ``meta["parent"] = [shape, vertex]`` when that vertex is where the
    polyline starts; otherwise (e.g. after shapes were deleted) any other
    polyline having a vertex exactly at its start is the parent. Polylines
    with fewer than 2 vertices are skipped; missing radii default to 1 pixel.
    Links that would close a parent cycle (inconsistent edits) are dropped:
    every branch then becomes a root.

    Parameters
    ----------
    shapes : sequence of shapes or dicts
        The canvas's shapes, or the ``"shapes"`` list of its JSON export;
        points are (x, y) pixels, radii the thickness per vertex (> 0).
    image_shape : (int, int), optional
        ``(H, W)`` of the annotated image, stored on the structure (None:
        unknown).

    Returns
    -------
    structure : Structure
        One branch per polyline with at least 2 vertices.
    index : list of int
        ``index[b]`` is the position in ``shapes`` of branch ``b``.

    Raises
    ------
    TypeError
        If ``shapes`` is not a sequence, or a shape's kind, radii or meta has
        the wrong type.
    ValueError
        If a polyline's radii do not match its points or are not > 0.

    Examples
    --------
    >>> trunk = {"kind": "polyline", "points": [[0, 0], [10, 0], [20, 0]], "radii": [3, 3, 2]}
    >>> twig = {"kind": "polyline", "points": [[10, 0], [15, 8]]}
    >>> s, index = annotations_to_structure([trunk, {"kind": "stroke", "points": [[1, 1]]}, twig])
    >>> index, s.branches[1].parent, s.branches[1].parent_vertex
    ([0, 2], 0, 1)
    """
    if isinstance(shapes, (str, bytes, Mapping)) or not hasattr(shapes, "__iter__"):
        raise TypeError(f"shapes must be a sequence of shapes, got {type(shapes).__name__}")
    shapes = list(shapes)
    parsed = {k: _polyline(s, k) for k, s in enumerate(shapes)}
    poly = [k for k, v in parsed.items() if v is not None and len(v[0]) >= 2]
    index = {si: bi for bi, si in enumerate(poly)}
    branches = []
    for si in poly:
        pts, radii, meta = parsed[si]
        r = radii if radii is not None else np.ones(len(pts))
        parent = pv = None
        ref = _parent_ref(meta)
        if ref is not None:
            ps, pvx = ref
            if ps in index and ps != si and 0 <= pvx < len(parsed[ps][0]) and \
                    np.allclose(parsed[ps][0][pvx], pts[0]):
                parent, pv = index[ps], pvx
        if parent is None:
            for pj in poly:
                if pj == si:
                    continue
                d = np.hypot(*(parsed[pj][0] - pts[0]).T)
                hit = np.flatnonzero(d < 1e-6)
                if len(hit):
                    parent, pv = index[pj], int(hit[0])
                    break
        branches.append(Branch(pts, r, parent, pv))
    try:
        st = Structure(branches, image_shape=image_shape)
    except ValueError:  # a parent cycle from inconsistent edits: drop the links that close it
        for b in branches:
            b.parent = b.parent_vertex = None
        st = Structure(branches, image_shape=image_shape)
    return st, poly


def structure_from_annotation_json(doc, image_shape=None) -> Structure:
    """The structure in an annotation JSON document (text or the parsed dict with ``"shapes"``).

    Parameters
    ----------
    doc : str, bytes or dict
        JSON text, or the parsed document: a dict whose ``"shapes"`` is a
        list of shape dicts (see :func:`annotations_to_structure`).
    image_shape : (int, int), optional
        ``(H, W)`` of the annotated image (None: unknown).

    Returns
    -------
    Structure

    Raises
    ------
    ValueError
        If ``doc`` is not valid JSON or has no ``"shapes"``.
    TypeError
        If ``"shapes"`` is not a list of dicts.

    Examples
    --------
    >>> s = Structure([Branch([[0, 0], [10, 0]], 2.0)], image_shape=(20, 20))
    >>> structure_from_annotation_json(structure_to_annotations(s), (20, 20)).n_vertices
    2
    """
    if isinstance(doc, (str, bytes)):
        try:
            doc = json.loads(doc)
        except json.JSONDecodeError as exc:
            raise ValueError(f"doc is not valid JSON: {exc}") from None
    if not isinstance(doc, Mapping) or "shapes" not in doc:
        raise ValueError("doc must be an annotation document: a dict with a 'shapes' list")
    shapes = doc["shapes"]
    if not isinstance(shapes, list):
        raise TypeError(f"doc['shapes'] must be a list, got {type(shapes).__name__}")
    for k, s in enumerate(shapes):
        if not isinstance(s, Mapping):
            raise TypeError(f"shapes[{k}] must be a dict, got {type(s).__name__}")
    return annotations_to_structure(shapes, image_shape)[0]
