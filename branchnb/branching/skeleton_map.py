"""Arc-length queries on a structure and its nearest-branch pixel map.

Image synthesis needs, for the source and the target structure alike,
(1) the skeleton position, thickness and direction at any arc length of
any branch, for many queries at once (shape vectors of hundreds of
candidate fragments), and (2) for every pixel the nearest skeleton
sample: which branch it belongs to, where along it, and how far from its
centre line. :class:`SkeletonMap` answers both.
"""

from __future__ import annotations

from bisect import bisect_right
from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..core.polyline import _arc_length
from ..core.structure import Structure

__all__ = ["SkeletonMap", "PixelMap"]


@dataclass
class PixelMap:
    """Nearest skeleton sample of every pixel of an ``(H, W)`` grid.

    Parameters
    ----------
    branch : (H, W) int ndarray
        Branch of the nearest sample.
    arc : (H, W) float ndarray
        Arc length of the nearest sample along its branch.
    dist : (H, W) float ndarray
        Distance (pixels) from the pixel centre to the nearest sample.
    radius : (H, W) float ndarray
        Thickness ``r`` of the structure at the nearest sample.
    """

    branch: np.ndarray
    arc: np.ndarray
    dist: np.ndarray
    radius: np.ndarray

    def core(self, scale: float = 1.0, margin: float = 0.0) -> np.ndarray:
        """Pixels within ``scale * r + margin`` of the skeleton (the branch's body).

        Parameters
        ----------
        scale : float, default 1.0
            Multiple of the thickness r (1 = the branch's body as drawn).
        margin : float, default 0.0
            Extra distance in pixels (negative shrinks the body).

        Returns
        -------
        (H, W) bool ndarray
            True within ``scale * r + margin`` of the nearest skeleton sample.
        """
        return self.dist <= scale * self.radius + margin


def _interp1(x: float, xp: list, fp: list) -> float:
    """``np.interp(x, xp, fp)`` of one float on strictly increasing ``xp`` (Python lists): numpy's
    arithmetic step for step (identical values) without its array set-up, for scalar loops."""
    j = bisect_right(xp, x) - 1
    if j < 0:
        return fp[0]
    if j >= len(xp) - 1 or xp[j] == x:
        return fp[j]
    slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
    return slope * (x - xp[j]) + fp[j]


class SkeletonMap:
    """Arc-length parametrisation of every branch of a structure.

    Parameters
    ----------
    structure : Structure
        Branches are resampled at step ``h``; branches of zero length keep
        their single point.
    h : float
        Resampling step (pixels).

    Examples
    --------
    >>> from branchnb.core.structure import Structure, Branch
    >>> sm = SkeletonMap(Structure([Branch([(0, 0), (10, 0)], 2.0)]))
    >>> sm.position([0], [4.0]).tolist()
    [[4.0, 0.0]]
    """

    def __init__(self, structure: Structure, h: float = 1.0):
        if not isinstance(structure, Structure):
            raise TypeError(f"structure must be a Structure, got {type(structure).__name__}")
        if not structure.branches:
            raise ValueError("structure is empty")
        self.structure = structure.resampled(h)
        self.h = float(h)
        pts, arcs, rads = [], [], []
        for b in self.structure.branches:
            pts.append(b.points)
            # (the resampled structure's points are checked: arc_length's values without its checks)
            arcs.append(_arc_length(np.asarray(b.points, np.float64)) if len(b.points) > 1 else np.zeros(1))
            rads.append(b.thickness)
        self.points = pts
        self.arcs = arcs
        self.radii = rads
        self.lengths = np.array([a[-1] for a in arcs], float)
        # One increasing global coordinate: branch b occupies
        # [offset[b], offset[b] + length[b]], separated by gaps of 1.
        self.offsets = np.concatenate([[0.0], np.cumsum(self.lengths + 1.0)[:-1]])
        g, x, y, r = [], [], [], []
        for i in range(len(pts)):
            a = arcs[i]
            keep = np.concatenate([[True], np.diff(a) > 1e-9])
            g.append(a[keep] + self.offsets[i])
            x.append(pts[i][keep, 0])
            y.append(pts[i][keep, 1])
            r.append(rads[i][keep])
        self._g = np.concatenate(g)
        self._x = np.concatenate(x)
        self._y = np.concatenate(y)
        self._r = np.concatenate(r)

    @property
    def n_branches(self) -> int:
        return len(self.points)

    def parent(self, i: int) -> int | None:
        """Index of the parent of branch ``i`` (None for a root).

        Parameters
        ----------
        i : int
            Branch index.

        Returns
        -------
        int or None
            The parent branch's index.
        """
        return self.structure.branches[i].parent

    def parent_arc(self, i: int) -> float:
        """Arc length on the parent where branch ``i`` starts.

        Parameters
        ----------
        i : int
            Index of a child branch (one with a parent).

        Returns
        -------
        float
            Arc length (pixels) of its parent vertex along the parent.
        """
        b = self.structure.branches[i]
        return float(self.arcs[b.parent][b.parent_vertex])

    def _global(self, branch, arc):
        b = np.asarray(branch, np.int64)
        s = np.asarray(arc, float)
        if b.shape != s.shape and b.ndim:
            # (one branch for many arcs, the common call, broadcasts as a scalar without copies)
            b, s = np.broadcast_arrays(b, s)
        # np.clip's values, without its dispatch overhead (called per fragment, many times)
        s_cl = np.minimum(np.maximum(s, 0.0), self.lengths[b])
        return self.offsets[b] + s_cl, s_cl != s

    def position(self, branch, arc) -> np.ndarray:
        """Skeleton points ``(..., 2)`` at arc lengths ``arc`` (clamped to each branch).

        Parameters
        ----------
        branch : int or array_like of int
            Branch index (one for all arcs, or one per arc; broadcast with
            ``arc``).
        arc : float or array_like
            Arc length along the branch from its first vertex (pixels). Clamped to ``[0, length]``.

        Returns
        -------
        (..., 2) ndarray
            Skeleton points (x, y), linearly interpolated between vertices.
        """
        g, _ = self._global(branch, arc)
        out = np.empty(g.shape + (2,))
        out[..., 0] = np.interp(g, self._g, self._x)
        out[..., 1] = np.interp(g, self._g, self._y)
        return out

    def thickness(self, branch, arc) -> np.ndarray:
        """Thickness ``r`` at arc lengths ``arc`` (clamped).

        Parameters
        ----------
        branch : int or array_like of int
            Branch index (one for all arcs, or one per arc; broadcast with
            ``arc``).
        arc : float or array_like
            Arc length along the branch from its first vertex (pixels). Clamped to ``[0, length]``.

        Returns
        -------
        ndarray
            Thickness r (pixels), linearly interpolated, shaped like the
            broadcast of ``branch`` and ``arc``.
        """
        g, _ = self._global(branch, arc)
        return np.interp(g, self._g, self._r)

    def thickness_at(self, branch: int, arc: float) -> float:
        """:meth:`thickness` of one ``(branch, arc)`` as a float (the same value, without the
        array set-up: for loops that step along a branch one query at a time).

        Parameters
        ----------
        branch : int
            Branch index.
        arc : float
            Arc length along it (pixels), clamped to ``[0, length]``.

        Returns
        -------
        float
            Thickness r (pixels).
        """
        x = float(self.offsets[branch]) + min(max(float(arc), 0.0), float(self.lengths[branch]))
        return _interp1(x, *self._lists())

    def _lists(self):
        """``_g`` and ``_r`` as Python lists (for :func:`_interp1`), made once."""
        lists = self.__dict__.get("_g_r_lists")
        if lists is None:
            lists = self._g_r_lists = (self._g.tolist(), self._r.tolist())
        return lists

    def clamped(self, branch, arc) -> np.ndarray:
        """True where ``arc`` lies outside ``[0, length]`` of its branch.

        Parameters
        ----------
        branch : int or array_like of int
            Branch index (one for all arcs, or one per arc; broadcast with
            ``arc``).
        arc : float or array_like
            Arc length along the branch from its first vertex (pixels).

        Returns
        -------
        bool ndarray
            True where the arc length was clamped.
        """
        return self._global(branch, arc)[1]

    def tangent(self, branch, arc, sign=1.0, step: float = 1.5) -> np.ndarray:
        """Unit tangent ``(..., 2)`` in the direction of travel ``sign`` (+1 = root to tip).

        Parameters
        ----------
        branch : int or array_like of int
            Branch index (one for all arcs, or one per arc; broadcast with
            ``arc``).
        arc : float or array_like
            Arc length along the branch from its first vertex (pixels).
        sign : float or array_like, default 1.0
            Direction of travel: +1 from root to tip, -1 back.
        step : float, default 1.5
            Half-width (pixels) of the central difference.

        Returns
        -------
        (..., 2) ndarray
            Unit tangents (one-sided at a clamped end).
        """
        sign = np.asarray(sign, float)
        s = np.asarray(arc, float)
        d = self.position(branch, s + sign * step) - self.position(branch, s - sign * step)
        n = np.hypot(d[..., 0], d[..., 1])
        bad = n < 1e-9
        if np.any(bad):
            # At a clamped end both samples coincide: look one-sided.
            d2 = self.position(branch, s) - self.position(branch, s - sign * 2 * step)
            d = np.where(bad[..., None], d2, d)
            n = np.hypot(d[..., 0], d[..., 1])
        n = np.where(n < 1e-9, 1.0, n)
        return d / n[..., None]

    def _frame(self, branch, arc, sign, step: float = 1.5):
        """``(position, thickness, tangent(sign, step))`` of 1-D queries in one batch of interpolations
        (the values of the three methods, elementwise; for the per-fragment inner loop)."""
        b = np.asarray(branch, np.int64)
        s = np.asarray(arc, float)
        sg = np.broadcast_to(np.asarray(sign, float), s.shape)
        n = len(s)
        g, _ = self._global(np.concatenate([b, b, b]), np.concatenate([s, s + sg * step, s - sg * step]))
        x = np.interp(g, self._g, self._x)
        y = np.interp(g, self._g, self._y)
        pos = np.stack([x[:n], y[:n]], 1)
        r = np.interp(g[:n], self._g, self._r)
        d = np.stack([x[n:2 * n] - x[2 * n:], y[n:2 * n] - y[2 * n:]], 1)
        nrm = np.hypot(d[:, 0], d[:, 1])
        bad = nrm < 1e-9
        if np.any(bad):
            d2 = pos - self.position(b, s - sg * 2 * step)
            d = np.where(bad[:, None], d2, d)
            nrm = np.hypot(d[:, 0], d[:, 1])
        nrm = np.where(nrm < 1e-9, 1.0, nrm)
        return pos, r, d / nrm[:, None]

    def pixel_map(self, shape) -> PixelMap:
        """Nearest skeleton sample of every pixel of ``shape`` (H, W).

        A child's first vertex lies on its parent and is attributed to the
        parent. Samples outside the grid are ignored.

        Parameters
        ----------
        shape : (H, W)
            Size of the pixel grid.

        Returns
        -------
        PixelMap
            Per pixel: nearest branch, arc length, distance and thickness (all
            ``-1`` / ``inf`` distance when no sample lies on the grid).

        Examples
        --------
        >>> from branchnb.core.structure import Structure, Branch
        >>> pm = SkeletonMap(Structure([Branch([(2, 5), (12, 5)], 2.0)])).pixel_map((10, 15))
        >>> int(pm.branch[8, 6]), float(pm.arc[8, 6]), float(pm.dist[8, 6]), int(pm.core()[8, 6])
        (0, 4.0, 3.0, 0)
        """
        h, w = int(shape[0]), int(shape[1])
        ids = np.full((h, w), -1, np.int64)
        sx, sy, sb, sa, sr = [], [], [], [], []
        for i, p in enumerate(self.points):
            start = 1 if (self.structure.branches[i].parent is not None and len(p) > 1) else 0
            sx.append(p[start:, 0])
            sy.append(p[start:, 1])
            sb.append(np.full(len(p) - start, i))
            sa.append(self.arcs[i][start:])
            sr.append(self.radii[i][start:])
        sx, sy = np.concatenate(sx), np.concatenate(sy)
        sb, sa, sr = np.concatenate(sb), np.concatenate(sa), np.concatenate(sr)
        cx, cy = np.round(sx).astype(np.int64), np.round(sy).astype(np.int64)
        inside = (cx >= 0) & (cx < w) & (cy >= 0) & (cy < h)
        if not inside.any():
            inf = np.full((h, w), np.inf)
            return PixelMap(np.full((h, w), -1), np.zeros((h, w)), inf, np.zeros((h, w)))
        # Thicker samples last so they win shared pixels.
        order = np.flatnonzero(inside)
        order = order[np.argsort(sr[order], kind="stable")]
        ids[cy[order], cx[order]] = order
        _, (iy, ix) = ndi.distance_transform_edt(ids < 0, return_indices=True)
        near = ids[iy, ix]
        yy, xx = np.mgrid[0:h, 0:w]
        dist = np.hypot(xx - sx[near], yy - sy[near])
        return PixelMap(sb[near], sa[near], dist, sr[near])
