"""Space colonization: a density map that steers branches into free space.

The density of the branches ``B`` grown so far is

    D(p) = exp(-d(p, B)^2 / rho^2),

kept on a grid and updated *locally* (within ``3 rho`` of the new
segments) after every extension; since ``D`` decreases with the distance,
the update is an element-wise maximum and exact. For each candidate the
growth direction is the principal axis (PCA) of the vertices it would add,
and the density is sampled along that direction from the branch tip up to
three times the extension length. The profile first *decreases* (the
branch's own density fades); its maximum after that first decrease is the
candidate's density ``D_c`` and

    Q** = Q* / (D_c + eps),   1 / eps = 1000.

A profile that *decreases, increases, then decreases* again passes
through another branch: the candidate would cross it and gets ``Q = 0``.
On top of the paper's profile test, :func:`crosses_existing` checks the
candidate's actual segments exactly against every existing segment, so a
structure grown with colonization on never crosses itself.
"""

from __future__ import annotations

import numba
import numpy as np

from ..core.validate import Point, Points, Real, Shape, checked
from . import _kernels

__all__ = [
    "DensityMap",
    "SegmentStore",
    "coverage_fraction",
    "crosses_existing",
    "frame_density",
    "growth_directions",
    "profile_density",
]


@numba.njit(cache=True, inline="always")
def _segment_box(ax, ay, bx, by, cell, reach, gh, gw):
    """Grid rows ``r0:r1`` and columns ``c0:c1`` within ``reach`` of segment ``a``-``b``."""
    c0 = max(int(np.floor((min(ax, bx) - reach) / cell)), 0)
    c1 = min(int(np.ceil((max(ax, bx) + reach) / cell)) + 1, gw)
    r0 = max(int(np.floor((min(ay, by) - reach) / cell)), 0)
    r1 = min(int(np.ceil((max(ay, by) + reach) / cell)) + 1, gh)
    return r0, r1, c0, c1


@numba.njit(cache=True, inline="always")
def _segment_d2(x, y, ax, ay, bx, by):
    """Squared distance of ``(x, y)`` to segment ``a``-``b``."""
    dx, dy = bx - ax, by - ay
    L2 = dx * dx + dy * dy
    t = 0.0
    if L2 > 0:
        t = ((x - ax) * dx + (y - ay) * dy) / L2
        t = min(max(t, 0.0), 1.0)
    ex, ey = x - ax - t * dx, y - ay - t * dy
    return ex * ex + ey * ey


@numba.njit(cache=True)
def _splat_segments(grid, domain, p0, p1, cell, rho, level):
    """``grid = max(grid, exp(-d^2 / rho^2))`` within ``3 rho`` of each segment; returns the change in
    domain cells above ``level``. A loop per segment over its own box: the union box of a long
    stretch would be mostly far from every segment."""
    gh, gw = grid.shape
    reach = 3.0 * rho
    inv = 1.0 / (rho * rho)
    delta = 0
    for s in range(p0.shape[0]):
        ax, ay, bx, by = p0[s, 0], p0[s, 1], p1[s, 0], p1[s, 1]
        r0, r1, c0, c1 = _segment_box(ax, ay, bx, by, cell, reach, gh, gw)
        for r in range(r0, r1):
            y = (r + 0.5) * cell - 0.5
            for c in range(c0, c1):
                e2 = _segment_d2((c + 0.5) * cell - 0.5, y, ax, ay, bx, by)
                D = np.float32(np.exp(-e2 * inv))
                old = grid[r, c]
                if D > old:
                    grid[r, c] = D
                    if domain[r, c] and old <= level < D:
                        delta += 1
    return delta


@numba.njit(cache=True)
def _splat_union(grid, domain, p0, p1, cell, rho, level):
    """:func:`_splat_segments` of all segments into a zeroed ``grid`` at once: the same grid to the
    bit (a max of ``exp(-d^2 / rho^2)`` is that of the least ``d^2``, so each cell takes one ``exp``
    of its nearest segment's ``d^2`` instead of one per segment in reach) and the same count (domain
    cells above ``level``). A rebuild of the density after unborn children are removed (issue 23,
    branching46) splatted every branch again: 9 % of a 1000 px cracked mud's time."""
    gh, gw = grid.shape
    reach = 3.0 * rho
    inv = 1.0 / (rho * rho)
    d2 = np.full((gh, gw), np.inf)
    for s in range(p0.shape[0]):
        ax, ay, bx, by = p0[s, 0], p0[s, 1], p1[s, 0], p1[s, 1]
        r0, r1, c0, c1 = _segment_box(ax, ay, bx, by, cell, reach, gh, gw)
        for r in range(r0, r1):
            y = (r + 0.5) * cell - 0.5
            for c in range(c0, c1):
                e2 = _segment_d2((c + 0.5) * cell - 0.5, y, ax, ay, bx, by)
                if e2 < d2[r, c]:
                    d2[r, c] = e2
    n = 0
    for r in range(gh):
        for c in range(gw):
            if d2[r, c] < np.inf:
                D = np.float32(np.exp(-d2[r, c] * inv))
                if D > grid[r, c]:
                    grid[r, c] = D
                if domain[r, c] and grid[r, c] > level:
                    n += 1
    return n


def auto_rho(structure, h: float = 4.0) -> float:
    """A density radius from the example: its median half-gap between branches.

    The background's distance transform to the (rasterised) skeleton has
    its local maxima half-way between neighbouring branches; their median
    is the typical half-gap. Clipped to ``[h, 50 h]``.

    Parameters
    ----------
    structure : Structure
        The example (vertices in pixels).
    h : float, default 4.0
        Resampling step h (pixels): the result is clipped to ``[h, 50 h]``
        and is ``4 h`` when no gap between branches is found.

    Returns
    -------
    float
        The density radius rho (pixels).

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> s = Structure([Branch([(5, y), (95, y)], 1.0) for y in (10, 50, 90)])
    >>> round(auto_rho(s))
    20
    """
    from scipy import ndimage as ndi

    from ..core.render import coverage_polylines

    x0, y0, x1, y1 = structure.bounds()
    pad = 2
    ox, oy = np.floor(x0) - pad, np.floor(y0) - pad
    shape = (int(np.ceil(y1 - oy)) + pad + 1, int(np.ceil(x1 - ox)) + pad + 1)
    pls = [b.points - (ox, oy) for b in structure.branches]
    cov, _ = coverage_polylines(shape, pls, 1.0)
    dt = ndi.distance_transform_edt(cov < 0.5)
    peaks = (dt == ndi.maximum_filter(dt, 5)) & (dt > 2)
    # ignore the margin band, where the distance grows without a neighbour
    peaks[:pad + 1] = peaks[-pad - 1:] = False
    peaks[:, :pad + 1] = peaks[:, -pad - 1:] = False
    if not peaks.any():
        return float(4 * h)
    return float(np.clip(np.median(dt[peaks]), h, 50 * h))


class DensityMap:
    """``D(p) = exp(-d(p, B)^2 / rho^2)`` on a grid covering the domain.

    Parameters
    ----------
    shape : (H, W) tuple of int
        Domain in pixels.
    rho : float
        Density radius rho (pixels), > 0.
    cell : float, optional
        Grid spacing in pixels. None (default): ``rho / 6`` but at least
        1 pixel, at most ``rho / 3`` and never below 0.5, coarser for
        domains above ~4 M pixels.
    domain : (H, W) bool array_like, optional
        Pixels that belong to the domain (they count in :meth:`coverage`);
        None = the whole frame.
    level : float, default 0.5
        Density above which a domain cell counts as covered by
        :meth:`coverage` (kept up to date incrementally).

    Examples
    --------
    >>> dm = DensityMap((50, 50), rho=5)
    >>> dm.add_segments([(10, 25)], [(40, 25)])
    >>> float(dm.sample([(25, 25)])[0]) > 0.99, float(dm.sample([(25, 40)])[0]) < 0.01
    (True, True)
    """

    def __init__(self, shape, rho: float, cell: float | None = None, *, domain=None,
                 level: float = 0.5):
        h, w = int(shape[0]), int(shape[1])
        if h <= 0 or w <= 0:
            raise ValueError(f"shape must be positive, got {shape}")
        if not rho > 0:
            raise ValueError(f"rho must be > 0, got {rho}")
        self.shape = (h, w)
        self.rho = float(rho)
        if cell is None:
            # D is a Gaussian of width rho: rho / 6 resolves it (sampled bilinearly), and the
            # local update costs (6 * 6 / rho)^2 less than a pixel grid on wide gaps
            cell = max(0.5, min(max(1.0, rho / 6.0), rho / 3.0))
            cell = max(cell, np.sqrt(h * w / 4e6))  # keep the grid <= ~4 M cells
        self.cell = float(cell)
        self.grid = np.zeros((int(np.ceil(h / self.cell)), int(np.ceil(w / self.cell))), np.float32)
        self.n_updates = 0
        #: coverage() counts domain cells with D > level (kept up to date incrementally)
        self.level = float(level)
        gh, gw = self.grid.shape
        if domain is None:
            self.domain = np.ones((gh, gw), bool)
        else:
            import cv2

            d = np.asarray(domain, bool)
            if d.shape != (h, w):
                raise ValueError(f"domain must have the shape {(h, w)}, got {d.shape}")
            self.domain = cv2.resize(d.astype(np.uint8), (gw, gh), interpolation=cv2.INTER_NEAREST) > 0
        self._n_domain = max(int(self.domain.sum()), 1)
        self._n_above = 0

    def add_segments(self, p0, p1) -> None:
        """Raise the density around new segments (local update within ``3 rho``).

        Parameters
        ----------
        p0, p1 : (n, 2) array_like
            Start and end points (x, y) of the new segments (pixels).
        """
        p0 = np.asarray(p0, np.float64).reshape(-1, 2)
        p1 = np.asarray(p1, np.float64).reshape(-1, 2)
        if len(p0) == 0:
            return
        self._n_above += int(_splat_segments(self.grid, self.domain, p0, p1, self.cell, self.rho, self.level))
        self.n_updates += 1

    def _rebuild(self, polylines) -> None:
        """The density of ``polylines`` alone (the grid cleared first): :meth:`add_segments` of each
        one, in one compiled pass (:func:`_splat_union`, the same grid to the bit)."""
        self.grid[:] = 0.0
        self._n_above = 0
        qs = [np.asarray(q, np.float64) for q in polylines if len(q) > 1]
        if not qs:
            return
        p0 = np.concatenate([q[:-1] for q in qs]).reshape(-1, 2)
        p1 = np.concatenate([q[1:] for q in qs]).reshape(-1, 2)
        self._n_above = int(_splat_union(self.grid, self.domain, p0, p1, self.cell, self.rho, self.level))
        self.n_updates += len(qs)

    def sample(self, points) -> np.ndarray:
        """Density at points ``(..., 2)`` (x, y); 0 outside the domain.

        Parameters
        ----------
        points : (..., 2) array_like
            Positions (x, y) in pixels.

        Returns
        -------
        (...) float32 ndarray
            D at each point, in [0, 1] (nearest cell on fine grids, bilinear on
            grids coarser than 1 pixel).
        """
        p = np.asarray(points, np.float64)
        gh, gw = self.grid.shape
        if self.cell <= 1.0:
            c = np.floor((p[..., 0] + 0.5) / self.cell).astype(np.int64)
            r = np.floor((p[..., 1] + 0.5) / self.cell).astype(np.int64)
            ok = (c >= 0) & (c < gw) & (r >= 0) & (r < gh)
            out = np.zeros(p.shape[:-1], np.float32)
            out[ok] = self.grid[r[ok], c[ok]]
            return out
        # coarse grid: bilinear between cell centres, so profiles along a ray stay smooth
        fx = (p[..., 0] + 0.5) / self.cell - 0.5
        fy = (p[..., 1] + 0.5) / self.cell - 0.5
        ok = (fx >= -0.5) & (fx < gw - 0.5) & (fy >= -0.5) & (fy < gh - 0.5)
        fx, fy = np.minimum(np.maximum(fx, 0), gw - 1), np.minimum(np.maximum(fy, 0), gh - 1)   # np.clip
        c0 = np.minimum(fx.astype(np.int64), gw - 2) if gw > 1 else np.zeros(fx.shape, np.int64)
        r0 = np.minimum(fy.astype(np.int64), gh - 2) if gh > 1 else np.zeros(fy.shape, np.int64)
        c1, r1 = np.minimum(c0 + 1, gw - 1), np.minimum(r0 + 1, gh - 1)
        tx, ty = fx - c0, fy - r0
        g = self.grid
        v = (g[r0, c0] * (1 - tx) + g[r0, c1] * tx) * (1 - ty) + (g[r1, c0] * (1 - tx) + g[r1, c1] * tx) * ty
        return np.where(ok, v, 0.0).astype(np.float32)

    def coverage(self, level: float | None = None) -> float:
        """Fraction of the domain with density above ``level`` (default: the map's ``level``).

        With ``level = exp(-1)`` this is the fraction of the domain within
        ``rho`` of a branch (``D = exp(-d^2 / rho^2)``).

        Parameters
        ----------
        level : float, optional
            Density threshold in [0, 1]; None = the map's ``level`` (counted
            incrementally, no pass over the grid).

        Returns
        -------
        float
            Covered fraction of the domain's cells, in [0, 1].
        """
        if level is None or level == self.level:
            return self._n_above / self._n_domain
        return float(np.count_nonzero((self.grid > level) & self.domain) / self._n_domain)

    def image(self) -> np.ndarray:
        """The density grid resized to the domain, ``(H, W)`` float32."""
        import cv2

        return cv2.resize(self.grid, (self.shape[1], self.shape[0]), interpolation=cv2.INTER_LINEAR)


def coverage_fraction(structure, shape, rho: float, domain=None) -> float:
    """Fraction of the domain (default: the whole ``(H, W)`` frame) within ``rho`` pixels of a branch.

    The measure the automatic stopping rule aims at (pixel-exact here).

    Parameters
    ----------
    structure : Structure
        The branches B (vertices in pixels; their thickness is ignored).
    shape : (H, W) tuple of int
        Size of the frame in pixels.
    rho : float
        Distance to the nearest centre line (pixels) within which a pixel
        counts as covered.
    domain : (H, W) bool array_like, optional
        The pixels that count; None = the whole frame.

    Returns
    -------
    float
        Covered fraction of the domain in [0, 1]; 0 for an empty structure or
        domain.

    Raises
    ------
    ValueError
        If ``domain`` does not have the shape ``shape``.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> s = Structure([Branch([(0, 50), (99, 50)], 1.0)])
    >>> round(coverage_fraction(s, (100, 100), 10.0), 2)
    0.21
    """
    from scipy import ndimage as ndi

    from ..core.render import coverage_polylines

    h, w = int(shape[0]), int(shape[1])
    dom = np.ones((h, w), bool) if domain is None else np.asarray(domain, bool)
    if dom.shape != (h, w):
        raise ValueError(f"domain must have the shape {(h, w)}, got {dom.shape}")
    if not structure.branches or not dom.any():
        return 0.0
    cov, _ = coverage_polylines((h, w), [b.points for b in structure.branches], 1.0)
    if not (cov >= 0.5).any():
        return 0.0
    d = ndi.distance_transform_edt(cov < 0.5)
    return float(np.count_nonzero((d <= rho) & dom) / np.count_nonzero(dom))


def growth_directions(tip, new_points: np.ndarray, n_valid: np.ndarray) -> np.ndarray:
    """Unit growth direction of each candidate: PCA of ``[tip] + its new vertices``.

    Parameters
    ----------
    tip : (2,) array_like
        Position (x, y) of the branch tip the candidates grow from (pixels).
    new_points : (J, m, 2) ndarray
        The vertices each of the J candidates would append.
    n_valid : (J,) int ndarray
        Number of real vertices per candidate (the rest repeat the last one).

    Returns
    -------
    (J, 2) ndarray
        Principal axis oriented from the tip towards the candidate's last vertex.
    """
    J, m, _ = new_points.shape
    tip = np.asarray(tip, np.float64)
    rel = new_points - tip  # the tip is the origin: its own term is zero
    w = (np.arange(m)[None, :] < n_valid[:, None])
    relx = np.where(w, rel[..., 0], 0.0)
    rely = np.where(w, rel[..., 1], 0.0)
    n = n_valid + 1.0
    mx, my = relx.sum(1) / n, rely.sum(1) / n
    sxx = (relx * relx).sum(1) - n * mx * mx
    syy = (rely * rely).sum(1) - n * my * my
    sxy = (relx * rely).sum(1) - n * mx * my
    ang = 0.5 * np.arctan2(2 * sxy, sxx - syy)
    v = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    last = rel[np.arange(J), np.maximum(n_valid - 1, 0)]
    flip = v[:, 0] * last[:, 0] + v[:, 1] * last[:, 1] < 0
    v[flip] *= -1
    return v


def profile_density(dmap: DensityMap, tip, directions: np.ndarray, length: float,
                    *, n_samples: int | None = None, tol: float = 0.02):
    """Density profiles along growth directions: ``(D_c, crossing, profiles)``.

    Parameters
    ----------
    dmap : DensityMap
        Density D of the branches grown so far.
    tip : (2,) array_like
        Start of every ray (the branch tip or furcation vertex).
    directions : (J, 2) ndarray
        Unit directions.
    length : float
        Ray length: 3 x the extension length in the paper.
    n_samples : int, optional
        Samples per ray (default: one per ``rho / 2``, 8 to 48).
    tol : float
        Rises and falls smaller than this are noise.

    Returns
    -------
    D_c : (J,) ndarray
        Maximum density after the profile's first decrease.
    crossing : (J,) bool ndarray
        The profile decreases, increases and decreases again.
    profiles : (J, n) ndarray
        The sampled densities, from the tip outwards.
    """
    if n_samples is None:
        n_samples = int(np.clip(np.ceil(length / (dmap.rho / 2.0)), 8, 48))
    t = np.linspace(length / n_samples, length, n_samples)
    tip = np.asarray(tip, np.float64)
    pts = tip[None, None, :] + t[None, :, None] * directions[:, None, :]
    prof = dmap.sample(pts)
    _J, n = prof.shape
    # First index where the profile rises: the end of the branch's own fading density.
    rising = (prof[:, 1:] - prof[:, :-1]) > tol * 0.5
    first = np.where(rising.any(axis=1), rising.argmax(axis=1), n - 1)
    D_c = np.where(np.arange(n)[None, :] >= first[:, None], prof, 0.0).max(axis=1)
    # Crossing: a peak that is higher than something before it and something after it.
    pre_min = np.minimum.accumulate(prof, axis=1)
    post_min = np.minimum.accumulate(prof[:, ::-1], axis=1)[:, ::-1]
    crossing = ((prof - pre_min > tol) & (prof - post_min > tol)).any(axis=1)
    return D_c.astype(np.float64), crossing, prof


@checked(shape=Shape(), tip=Point(), directions=Points(), length=Real(0, 1e6), rho=Real(0, 1e4, low_open=True))
def frame_density(shape, tip, directions: np.ndarray, length: float, rho: float) -> np.ndarray:
    """Density of the image frame ahead of a tip: ``exp(-d^2 / rho^2)`` at the end of each ray.

    Beyond the paper. Its density ``D`` sees only the branches grown so
    far: the space beyond the image frame reads as free as the middle of
    the domain, so a tip near a side drifts out as often as in (a tree
    rooted near a corner leaves through the nearest sides and never spans
    the image). Here the frame counts as one more branch: ``d`` is the
    distance from the point ``length`` pixels ahead along each direction
    to the nearest side, 0 (density 1) past it. Synthesis applies it to
    roots only (their trunk spans the example); on every branch it made
    children run along the frame.

    Parameters
    ----------
    shape : (H, W) tuple of int
        The frame in pixels.
    tip : (2,) array_like
        Start (x, y) of every ray.
    directions : (J, 2) ndarray
        Unit directions.
    length : float
        How far ahead the density is read (pixels): the paper's ray of
        ``3 m h``.
    rho : float
        Density radius rho (pixels), > 0.

    Returns
    -------
    (J,) ndarray
        Frame density in [0, 1] for each direction.

    Examples
    --------
    >>> import numpy as np
    >>> d = frame_density((100, 100), (90, 50), np.array([[1.0, 0.0], [-1.0, 0.0]]), 20.0, 8.0)
    >>> float(d[0]), round(float(d[1]), 3)
    (1.0, 0.0)
    """
    h, w = float(shape[0]), float(shape[1])
    end = np.asarray(tip, np.float64)[None, :] + float(length) * np.asarray(directions, np.float64).reshape(-1, 2)
    d = np.minimum.reduce([end[:, 0] + 0.5, w - 0.5 - end[:, 0], end[:, 1] + 0.5, h - 0.5 - end[:, 1]])
    return np.exp(-np.maximum(d, 0.0) ** 2 / float(rho) ** 2)


class SegmentStore:
    """All segments grown so far, in a growing buffer, for exact crossing tests.

    Parameters
    ----------
    capacity : int, default 1024
        Initial number of segments the buffer holds (it doubles when full).
    cell : float, default 16.0
        Side (pixels) of the grid buckets a crossing test reads: only the
        segments whose bounding box meets the candidate's cells are tested.
    shape : tuple of int, optional
        (height, width) of the frame the segments lie in, which sizes the
        grid; None = 4096 x 4096.

    Examples
    --------
    >>> store = SegmentStore(capacity=2)
    >>> store.add_polyline([(0, 0), (10, 0), (10, 10)])
    >>> store.add([(0, 20)], [(5, 20)])
    >>> store.n
    3
    """

    def __init__(self, capacity: int = 1024, cell: float = 16.0, shape=None):
        self.p0 = np.zeros((capacity, 2))
        self.p1 = np.zeros((capacity, 2))
        self.n = 0
        # a grid of buckets (cell x cell px) of the segments whose bounding box meets each
        # cell, as linked lists in flat arrays (``_kernels.bucket_add``): a crossing test reads
        # only the buckets under the candidate (speed, issue 23). Cells past the grid's sides
        # share its border cells (still a superset of the segments near a box).
        self.cell = float(cell)
        h, w = (4096, 4096) if shape is None else (int(shape[0]), int(shape[1]))
        self._head = np.full((max(h // int(cell) + 1, 1), max(w // int(cell) + 1, 1)), -1, np.int64)
        self._next = np.zeros(4 * capacity, np.int64)
        self._seg = np.zeros(4 * capacity, np.int64)
        self._n_entries = 0

    def add(self, p0, p1) -> None:
        """Append segments ``p0[i] -> p1[i]``, growing the buffer as needed.

        Parameters
        ----------
        p0, p1 : (n, 2) array_like
            Start and end points (x, y) of the segments to store (pixels).
        """
        p0 = np.asarray(p0, np.float64).reshape(-1, 2)
        p1 = np.asarray(p1, np.float64).reshape(-1, 2)
        k = len(p0)
        while self.n + k > len(self.p0):
            self.p0 = np.vstack([self.p0, np.zeros_like(self.p0)])
            self.p1 = np.vstack([self.p1, np.zeros_like(self.p1)])
        self.p0[self.n:self.n + k] = p0
        self.p1[self.n:self.n + k] = p1
        while True:
            e = _kernels.bucket_add(self._head, self._next, self._seg, self._n_entries,
                                    self.p0[:self.n + k], self.p1[:self.n + k], self.n, self.cell)
            if e >= 0:
                break
            self._next = np.r_[self._next, np.zeros_like(self._next)]
            self._seg = np.r_[self._seg, np.zeros_like(self._seg)]
        self._n_entries = int(e)
        self.n += k

    def near(self, lo, hi) -> np.ndarray:
        """Indices of the stored segments whose bounding box may meet the box ``lo`` .. ``hi`` (x, y).

        Parameters
        ----------
        lo, hi : (2,) array_like
            Corners (x, y) of the box (pixels).

        Returns
        -------
        (n,) int ndarray
            Sorted unique segment indices (a superset of those meeting the box).
        """
        gh, gw = self._head.shape
        lo = np.asarray(lo, np.float64)
        hi = np.asarray(hi, np.float64)
        x0, x1 = (int(np.clip(np.floor(v / self.cell), 0, gw - 1)) for v in (lo[0], hi[0]))
        y0, y1 = (int(np.clip(np.floor(v / self.cell), 0, gh - 1)) for v in (lo[1], hi[1]))
        out: list[int] = []
        for e in self._head[y0:y1 + 1, x0:x1 + 1].ravel().tolist():
            while e >= 0:
                out.append(int(self._seg[e]))
                e = int(self._next[e])
        return np.unique(np.asarray(out, np.int64))

    def add_polyline(self, points) -> None:
        """Append the segments of a polyline.

        Parameters
        ----------
        points : (N, 2) array_like
            Vertices (x, y) of a polyline; its N - 1 segments are stored (none
            when N < 2).
        """
        p = np.asarray(points, np.float64)
        if len(p) > 1:
            self.add(p[:-1], p[1:])


def crosses_existing(store: SegmentStore, polyline: np.ndarray, eps: float = 1e-9) -> bool:
    """Does the polyline (its segments) properly cross a stored segment or itself?

    Same predicate as :func:`branchnb.core.polyline.segments_intersect`
    (touching end points do not count), inlined without input validation
    because it runs inside the synthesis loop.

    Parameters
    ----------
    store : SegmentStore
        The segments grown so far.
    polyline : (N, 2) array_like
        Vertices (x, y) of the candidate extension (pixels); zero-length
        segments are ignored.
    eps : float, default 1e-9
        Tolerance of the orientation products: a crossing must be proper by
        more than this (collinear or touching segments do not count).

    Returns
    -------
    bool
        True if a segment of ``polyline`` properly crosses a stored segment
        or another of its own segments.

    Examples
    --------
    >>> store = SegmentStore()
    >>> store.add_polyline([(0, 5), (10, 5)])
    >>> crosses_existing(store, [(5, 0), (5, 10)]), crosses_existing(store, [(5, 5), (5, 10)])
    (True, False)
    """
    p = np.ascontiguousarray(polyline, np.float64).reshape(-1, 2)
    return bool(_kernels.crosses(store._head, store._next, store._seg, store.p0, store.p1, store.n,
                                 store.cell, p, float(eps)))
