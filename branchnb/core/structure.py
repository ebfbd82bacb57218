"""The branching structure: a tree of branches, each a polyline with per-vertex thickness.

A :class:`Structure` is what the user annotates on an example image, what
the learned models are trained on, and what synthesis produces. Branch 0
(and any branch with ``parent is None``) is a root; every other branch
starts at vertex ``parent_vertex`` of branch ``parent``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np

from .image import as_points
from .polyline import _arc_length, _resample_uniform, turning_angles
from .structure_io import GENERATION_COLORS, STRUCTURE_JSON_VERSION, _StructureOutput
from .validate import COORD_LIMIT, check_finite, check_int, check_real, check_shape, real_array

__all__ = ["Branch", "Structure", "GENERATION_COLORS", "STRUCTURE_JSON_VERSION"]


@dataclass
class Branch:
    """One branch.

    The fields are checked and converted on construction (points to float64
    ``(N, 2)``, a scalar thickness repeated per vertex).

    Parameters
    ----------
    points : (N, 2) float ndarray
        Vertices (x, y) in pixels. For a child branch, ``points[0]`` is the
        furcation point on the parent.
    thickness : (N,) float ndarray or float
        Radius ``r`` at each vertex (pixels, > 0): half the visible width.
        A single number applies to every vertex.
    parent : int or None
        Index of the parent branch, None for a root.
    parent_vertex : int or None
        Vertex of the parent the branch starts at (set exactly when
        ``parent`` is).

    Raises
    ------
    ValueError
        If the points are not ``(N, 2)`` finite, the thickness does not
        match them or is not > 0, or only one of ``parent`` and
        ``parent_vertex`` is set.

    Examples
    --------
    >>> b = Branch([(0, 0), (3, 4)], 1.5)
    >>> b.thickness.tolist(), b.length
    ([1.5, 1.5], 5.0)
    """

    points: np.ndarray
    thickness: np.ndarray
    parent: int | None = None
    parent_vertex: int | None = None

    def __post_init__(self):
        self.points = as_points(self.points, name="points", min_points=1)
        t = real_array(self.thickness, "thickness", finite=False)
        if t.ndim == 0:
            t = np.full(len(self.points), float(t))
        if t.shape != (len(self.points),):
            raise ValueError(
                f"thickness must have one value per vertex of points ({len(self.points)}), got shape {t.shape}"
            )
        if not np.all(np.isfinite(t)) or np.any(t <= 0):
            raise ValueError("thickness must be finite and > 0 at every vertex")
        self.thickness = t
        self.parent = check_int(self.parent, "parent", 0, allow_none=True)
        self.parent_vertex = check_int(self.parent_vertex, "parent_vertex", 0, allow_none=True)
        if (self.parent is None) != (self.parent_vertex is None):
            raise ValueError("parent and parent_vertex must both be set or both be None")

    @property
    def length(self) -> float:
        """Arc length (pixels)."""
        # the points are checked at construction: polyline_length's value without its checks
        return float(_arc_length(np.asarray(self.points, np.float64))[-1]) if len(self.points) > 1 else 0.0

    def angles(self) -> np.ndarray:
        """Turning angles alpha at the interior vertices (N - 2 values, radians).

        Returns
        -------
        (N - 2,) float ndarray
            See :func:`branchnb.core.polyline.turning_angles`; empty for
            fewer than 3 vertices.
        """
        return turning_angles(self.points) if len(self.points) > 2 else np.zeros(0)


def _as_branch(b, i: int) -> Branch:
    """A Branch from a Branch or a dict of its fields (``Structure.from_dict`` layout)."""
    if isinstance(b, Branch):
        return b
    if not isinstance(b, dict):
        raise TypeError(f"branches[{i}] must be a Branch or a dict of its fields, got {type(b).__name__}")
    names = {f.name for f in fields(Branch)}
    unknown, missing = sorted(set(b) - names), sorted(n for n in ("points", "thickness") if n not in b)
    if unknown or missing:
        raise ValueError(f"branches[{i}]: a branch dict needs 'points' and 'thickness' (optional 'parent', "
                         f"'parent_vertex'); missing {missing}, unknown {unknown}")
    return Branch(**b)


@dataclass
class Structure(_StructureOutput):
    """A branching structure: a list of :class:`Branch` forming a forest.

    Parameters
    ----------
    branches : list of Branch or dict
        The branches; a dict holds a branch's fields (``points``,
        ``thickness``, optional ``parent``, ``parent_vertex``). A child's
        ``parent`` is an index into this list. Empty by default.
    image_shape : (int, int), optional
        ``(H, W)`` of the image the structure lives on (None: unknown; the
        renderers then use the bounds).

    Raises
    ------
    TypeError, ValueError
        If a branch is malformed or the parent links are not a forest (see
        :meth:`validate`).

    Examples
    --------
    >>> s = Structure([Branch([(0, 0), (10, 0), (20, 5)], 2.0)])
    >>> s.add_branch([(10, 0), (12, 10)], 1.0, parent=0, parent_vertex=1)
    1
    >>> s.n_vertices, s.children(0)
    (5, [1])
    """

    branches: list[Branch] = field(default_factory=list)
    #: Optional (height, width) of the image the structure lives on.
    image_shape: tuple[int, int] | None = None

    def __post_init__(self):
        if not isinstance(self.branches, (list, tuple)):
            raise TypeError(f"branches must be a list of Branch, got {type(self.branches).__name__}")
        self.branches = [_as_branch(b, i) for i, b in enumerate(self.branches)]
        if self.image_shape is not None:
            self.image_shape = check_shape(self.image_shape, "image_shape")
        self.validate()

    # -- building -------------------------------------------------------
    def add_branch(self, points, thickness, parent: int | None = None,
                   parent_vertex: int | None = None) -> int:
        """Append a branch and return its index.

        Parameters
        ----------
        points : (N, 2) array_like
            Vertices (x, y) in pixels; for a child, ``points[0]`` should be
            the parent's vertex ``parent_vertex``.
        thickness : float or (N,) array_like
            Radius per vertex (pixels, > 0).
        parent : int, optional
            Index of an existing branch; None adds a root.
        parent_vertex : int, optional
            Vertex of ``parent`` the branch starts at.

        Returns
        -------
        int
            The new branch's index.

        Raises
        ------
        ValueError
            If the branch or its link is invalid; the structure is left
            unchanged.
        """
        b = Branch(points, thickness, parent, parent_vertex)
        self.branches.append(b)
        try:
            self.validate()
        except ValueError:
            self.branches.pop()
            raise
        return len(self.branches) - 1

    def validate(self) -> Structure:
        """Check parent links (existing branch, valid vertex, no cycles).

        Vertices outside ``image_shape`` are allowed here (a synthesized
        structure may be cropped by its output); :meth:`check_inside`
        rejects them where an image is involved.

        Returns
        -------
        Structure
            ``self``, for chaining.

        Raises
        ------
        TypeError, ValueError
            Naming the first bad branch: not a Branch, non-finite points or
            thickness, a parent or vertex out of range, or a parent cycle.
        """
        n = len(self.branches)
        for i, b in enumerate(self.branches):
            # Branches are mutable: re-check what the rasterisers and models index with.
            if not isinstance(b, Branch):
                raise TypeError(f"branches[{i}] must be a Branch, got {type(b).__name__}")
            check_finite(b.points, f"branches[{i}].points", limit=COORD_LIMIT)
            if np.shape(b.thickness) != (len(b.points),) or not np.all(np.asarray(b.thickness) > 0):
                raise ValueError(f"branches[{i}].thickness must be one positive value per vertex")
            check_finite(b.thickness, f"branches[{i}].thickness", limit=COORD_LIMIT)
            if b.parent is None:
                continue
            if not (0 <= b.parent < n) or b.parent == i:
                raise ValueError(f"branches[{i}].parent = {b.parent} is not another branch index")
            nv = len(self.branches[b.parent].points)
            if not (0 <= b.parent_vertex < nv):
                raise ValueError(
                    f"branches[{i}].parent_vertex = {b.parent_vertex} outside parent's {nv} vertices"
                )
        for i in range(n):
            seen, j = set(), i
            while self.branches[j].parent is not None:
                if j in seen:
                    raise ValueError(f"branch {i} is part of a parent cycle")
                seen.add(j)
                j = self.branches[j].parent
        return self

    def _index(self, index, name: str = "index") -> int:
        index = check_int(index, name)
        if not 0 <= index < len(self.branches):
            raise ValueError(f"{name} {index} out of range for {len(self.branches)} branches")
        return index

    def remove_subtree(self, index: int) -> Structure:
        """A new structure without branch ``index`` and all its descendants.

        Parameters
        ----------
        index : int
            Branch to remove, ``0 <= index < len(branches)``.

        Returns
        -------
        Structure
            A copy; the remaining branches keep their order and their parent
            indices are renumbered.

        Examples
        --------
        >>> s = Structure([Branch([(0, 0), (10, 0)], 2.0), Branch([(10, 0), (10, 9)], 1.0, 0, 1)])
        >>> len(s.remove_subtree(1).branches), len(s.remove_subtree(0).branches)
        (1, 0)
        """
        index = self._index(index)
        self.validate()
        drop = {index}
        changed = True
        while changed:
            changed = False
            for i, b in enumerate(self.branches):
                if i not in drop and b.parent in drop:
                    drop.add(i)
                    changed = True
        keep = [i for i in range(len(self.branches)) if i not in drop]
        remap = {old: new for new, old in enumerate(keep)}
        out = []
        for i in keep:
            b = self.branches[i]
            out.append(Branch(b.points.copy(), b.thickness.copy(),
                              remap.get(b.parent) if b.parent is not None else None,
                              b.parent_vertex))
        return Structure(out, self.image_shape)

    def check_inside(self, shape=None, *, name: str = "structure") -> Structure:
        """Raise ValueError if a vertex lies outside ``shape`` (default ``image_shape``).

        Half a pixel of tolerance, as for pixel centres.

        Parameters
        ----------
        shape : (int, int), optional
            ``(H, W)`` to check against; ``image_shape`` by default (no check
            when both are None).
        name : str, optional
            How the message names the structure.

        Returns
        -------
        Structure
            ``self``, for chaining.

        Raises
        ------
        ValueError
            Naming the first vertex outside.

        Examples
        --------
        >>> Structure([Branch([(0, 0), (60, 10)], 1.0)], image_shape=(40, 50)).check_inside()
        Traceback (most recent call last):
        ...
        ValueError: structure.branches[0].points[1] = (60.0, 10.0) lies outside the 50 x 40 image
        """
        shp = check_shape(shape, "shape") if shape is not None else self.image_shape
        if shp is None:
            return self
        h, w = int(shp[0]), int(shp[1])
        for i, b in enumerate(self.branches):
            x, y = b.points[:, 0], b.points[:, 1]
            bad = (x < -0.5) | (x > w - 0.5) | (y < -0.5) | (y > h - 0.5)
            if bad.any():
                j = int(np.flatnonzero(bad)[0])
                raise ValueError(f"{name}.branches[{i}].points[{j}] = ({x[j]:.1f}, {y[j]:.1f}) lies outside "
                                 f"the {w} x {h} image{' given as shape' if shape is not None else ''}")
        return self

    def copy(self) -> Structure:
        """A deep copy.

        Returns
        -------
        Structure
            New arrays; editing the copy never changes ``self``.
        """
        return Structure([Branch(b.points.copy(), b.thickness.copy(), b.parent, b.parent_vertex)
                          for b in self.branches], self.image_shape)

    def scaled(self, factor: float) -> Structure:
        """The structure at another image resolution: points, thickness and image shape times ``factor``.

        Pixel centres map to pixel centres (``x' = (x + 0.5) f - 0.5``).

        Parameters
        ----------
        factor : float
            Scale ``f`` (> 0), e.g. 0.5 for an image half as large; the image
            shape is rounded to whole pixels (at least 1).

        Returns
        -------
        Structure
            A new structure.

        Raises
        ------
        ValueError
            If ``factor`` is not > 0 or would move points beyond the
            coordinate limit.

        Examples
        --------
        >>> s = Structure([Branch([(0.5, 0.5), (10.5, 0.5)], 2.0)], image_shape=(20, 30))
        >>> t = s.scaled(2.0)
        >>> t.branches[0].points.tolist(), t.image_shape, float(t.branches[0].thickness[0])
        ([[1.5, 1.5], [21.5, 1.5]], (40, 60), 4.0)
        """
        f = check_real(factor, "factor", 0, low_open=True)
        _x0, _y0, x1, y1 = self.bounds() if self.branches else (0, 0, 0, 0)
        if max(abs(x1), abs(y1), *(self.image_shape or ())) * f > COORD_LIMIT:
            raise ValueError(f"factor {f:g} would move points beyond +-{COORD_LIMIT:g} pixels")
        shape = None
        if self.image_shape is not None:
            shape = (max(1, int(round(self.image_shape[0] * f))), max(1, int(round(self.image_shape[1] * f))))
        return Structure([Branch((b.points + 0.5) * f - 0.5, b.thickness * f, b.parent, b.parent_vertex)
                          for b in self.branches], shape)

    def with_thickness(self, index: int, vertex: int | slice, r) -> Structure:
        """A copy with the thickness of ``branches[index]`` at ``vertex`` set to ``r`` (> 0).

        The paper's thickness stays user-editable: this is the edit.

        Parameters
        ----------
        index : int
            Branch to edit.
        vertex : int or slice
            Vertex (negative counts from the end) or a slice of vertices.
        r : float or array_like
            New radius in pixels (> 0), or one per vertex of the slice.

        Returns
        -------
        Structure
            A copy; ``self`` is unchanged.

        Raises
        ------
        ValueError
            If ``index`` or ``vertex`` is out of range or ``r`` is not > 0.

        Examples
        --------
        >>> s = Structure([Branch([(0, 0), (10, 0)], 2.0)])
        >>> s.with_thickness(0, 1, 5.0).branches[0].thickness.tolist()
        [2.0, 5.0]
        """
        index = self._index(index)
        if not isinstance(vertex, slice):
            vertex = check_int(vertex, "vertex")
        out = self.copy()
        t = out.branches[index].thickness.copy()
        try:
            t[vertex] = r
        except (IndexError, OverflowError) as exc:
            raise ValueError(f"vertex {vertex} out of range for branch {index} "
                             f"({len(t)} vertices)") from exc
        out.branches[index] = Branch(out.branches[index].points, t, out.branches[index].parent,
                                     out.branches[index].parent_vertex)
        return out

    # -- queries --------------------------------------------------------
    @property
    def n_vertices(self) -> int:
        return int(sum(len(b.points) for b in self.branches))

    @property
    def total_length(self) -> float:
        return float(sum(b.length for b in self.branches))

    def children(self, index: int) -> list[int]:
        """Indices of the branches that start on branch ``index``.

        Parameters
        ----------
        index : int
            A branch index.

        Returns
        -------
        list of int
            Its direct children, in branch order.
        """
        index = self._index(index)
        return [i for i, b in enumerate(self.branches) if b.parent == index]

    def generation(self, index: int) -> int:
        """0 for roots, 1 for their children, ...

        Parameters
        ----------
        index : int
            A branch index.

        Returns
        -------
        int
            Number of parent links from the branch up to its root.

        Raises
        ------
        ValueError
            If ``index`` is out of range or the parents were edited into a cycle.

        Examples
        --------
        >>> s = Structure([Branch([(0, 0), (10, 0)], 2.0), Branch([(10, 0), (10, 9)], 1.0, 0, 1)])
        >>> s.generation(0), s.generation(1)
        (0, 1)
        """
        j = self._index(index)
        g = 0
        while self.branches[j].parent is not None:
            j = self.branches[j].parent
            g += 1
            if g > len(self.branches):  # parents changed after construction into a cycle
                raise ValueError(f"branch {index} is part of a parent cycle")
        return g

    def angles(self) -> np.ndarray:
        """All turning angles of all branches, concatenated.

        Returns
        -------
        float ndarray
            Radians, branch after branch (see :meth:`Branch.angles`).
        """
        parts = [b.angles() for b in self.branches]
        return np.concatenate(parts) if parts else np.zeros(0)

    def thicknesses(self) -> np.ndarray:
        """All vertex thicknesses, concatenated.

        Returns
        -------
        float ndarray
            Radii ``r`` in pixels, branch after branch.
        """
        parts = [b.thickness for b in self.branches]
        return np.concatenate(parts) if parts else np.zeros(0)

    def segments(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """All edges as ``(p0 (E, 2), p1 (E, 2), branch index (E,))``.

        Returns
        -------
        p0, p1 : (E, 2) float ndarray
            Start and end (x, y) of each edge.
        owner : (E,) int ndarray
            The branch each edge belongs to.
        """
        p0, p1, owner = [], [], []
        for i, b in enumerate(self.branches):
            if len(b.points) > 1:
                p0.append(b.points[:-1])
                p1.append(b.points[1:])
                owner.append(np.full(len(b.points) - 1, i))
        if not p0:
            return np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0, int)
        return np.vstack(p0), np.vstack(p1), np.concatenate(owner)

    def bounds(self) -> tuple[float, float, float, float]:
        """``(xmin, ymin, xmax, ymax)`` including thickness.

        Returns
        -------
        (float, float, float, float)
            Pixels; each vertex counts as a disk of its radius.

        Raises
        ------
        ValueError
            If the structure is empty.
        """
        if not self.branches:
            raise ValueError("structure is empty")
        pts = np.vstack([b.points for b in self.branches])
        r = np.concatenate([b.thickness for b in self.branches])
        return (float((pts[:, 0] - r).min()), float((pts[:, 1] - r).min()),
                float((pts[:, 0] + r).max()), float((pts[:, 1] + r).max()))

    # -- transforms -----------------------------------------------------
    def resampled(self, h: float) -> Structure:
        """Every branch resampled at uniform arc-length step ``h``.

        Child branches keep their furcation point: ``parent_vertex`` is
        moved to the nearest resampled vertex of the parent and the child's
        first vertex snaps to it.

        Parameters
        ----------
        h : float
            Step along each branch in pixels (> 0); each branch keeps its end
            vertex, and thickness is interpolated linearly. Branches of a
            single vertex or zero length are kept as they are.

        Returns
        -------
        Structure
            A new structure.

        Raises
        ------
        ValueError
            If the structure is empty or ``h`` is not > 0.

        Examples
        --------
        >>> s = Structure([Branch([(0, 0), (10, 0)], 2.0)])
        >>> s.resampled(2.5).branches[0].points[:, 0].tolist()
        [0.0, 2.5, 5.0, 7.5, 10.0]
        """
        if not self.branches:
            raise ValueError("structure is empty")
        h = check_real(h, "h", 0, low_open=True)
        new = []
        for b in self.branches:
            # the branch's points and thickness are checked already: resample_uniform's steps without
            # its argument checks (same values)
            pts = np.asarray(b.points, np.float64)
            s = _arc_length(pts) if len(pts) >= 2 else None
            if s is None or s[-1] <= 0:
                new.append((b.points.copy(), b.thickness.copy()))
                continue
            p, t = _resample_uniform(pts, float(h), np.asarray(b.thickness, np.float64), True, s)
            new.append((p, t))
        return self.with_polylines(new)

    def with_polylines(self, polylines) -> Structure:
        """The same tree with new vertices for every branch, children re-attached.

        Parameters
        ----------
        polylines : sequence of (points (N_i, 2), thickness (N_i,))
            One new polyline per branch, in branch order (e.g. resampled or
            refined versions of the current ones).

        Returns
        -------
        Structure
            A new structure with the same parents and ``image_shape``.

        Raises
        ------
        TypeError
            If ``polylines`` is not a sequence.
        ValueError
            If it does not hold one entry per branch.

        Notes
        -----
        Each child's ``parent_vertex`` moves to the vertex of the parent's new
        polyline nearest to its old furcation point, and the child's first
        vertex snaps to it, so furcations survive any re-sampling.
        """
        if isinstance(polylines, (str, bytes)) or not hasattr(polylines, "__len__"):
            raise TypeError(f"polylines must be a sequence of (points, thickness), got {type(polylines).__name__}")
        if len(polylines) != len(self.branches):
            raise ValueError(f"polylines must have one entry per branch ({len(self.branches)}), "
                             f"got {len(polylines)}")
        out = []
        for b, (p, t) in zip(self.branches, polylines):
            pv = None
            if b.parent is not None:
                anchor = self.branches[b.parent].points[b.parent_vertex]
                pp = np.asarray(polylines[b.parent][0], np.float64)
                pv = int(np.argmin(np.hypot(*(pp - anchor).T)))
                p = np.array(p, np.float64)
                p[0] = pp[pv]
            out.append(Branch(p, t, b.parent, pv))
        return Structure(out, self.image_shape)
