"""The weighted pixel lattice the dendrites are planned on (paper, section 3).

One node per pixel, 8-connected. Every node carries a weight

    w(p) = cost(p) + epsilon + noise * U(p),        U(p) ~ uniform [0, 1)

(the cost map, a small constant ``epsilon`` that keeps every weight
positive, and a random contribution that makes the paths wander), and the
edge between neighbours ``p`` and ``q`` in direction ``k`` costs

    c(p, q) = (w(p) + w(q)) / 2 * f_k .

``f_k`` is the length factor of the direction: **1 for the four axis
edges and sqrt(2) for the four diagonal edges** by default (the Euclidean
step length, as in :class:`skimage.graph.MCP_Geometric`), so the cumulative
metric measures weighted Euclidean length and has no preference for
diagonal staircases. ``diagonal="unit"`` treats diagonals as length 1
instead. The lightning metaphor multiplies ``f_k`` by a direction penalty
so that edges pointing up or sideways cost more than edges pointing down
(:func:`direction_factors`); with such penalties the lattice is a directed
graph (``c(p, q) != c(q, p)``).

A weight of ``+inf`` marks an impassable node (a wall): no edge enters or
leaves it. NaN, ``-inf`` and negative weights are rejected.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..core.image import as_points
from ..core.random import as_rng
from ..core.validate import Array, Choice, Real, checked, real_array

__all__ = [
    "OFFSETS",
    "Lattice",
    "direction_factors",
    "make_lattice",
    "node_weights",
]

#: The 8 neighbour offsets ``(drow, dcol)``: E, W, S, N, SE, SW, NE, NW.
OFFSETS = np.array(
    [(0, 1), (0, -1), (1, 0), (-1, 0), (1, 1), (1, -1), (-1, 1), (-1, -1)], dtype=np.int64
)
_DIAGONAL = np.array([False] * 4 + [True] * 4)


#: Direction length factors: positive and finite.
_FACTOR = Real(0, 1e6, low_open=True)
#: A cost map: real, NaN-free, +inf allowed (walls).
_COST = Array(ndim=2, allow_inf=True)


@checked(diagonal=Choice("euclidean", "unit"), down=_FACTOR, side=_FACTOR, up=_FACTOR)
def direction_factors(*, diagonal: str = "euclidean", down: float = 1.0, side: float = 1.0,
                      up: float = 1.0) -> np.ndarray:
    """Length factors ``f_k`` of the 8 lattice directions (in :data:`OFFSETS` order).

    Parameters
    ----------
    diagonal : {"euclidean", "unit"}
        Diagonal edges have length sqrt(2) ("euclidean", default) or 1.
    down, side, up : float
        Multipliers for edges whose step goes down (+row), sideways
        (row unchanged) or up (-row); a diagonal step counts as up or down.
        The lightning metaphor uses ``up > side > down`` so branches grow
        downward.

    Examples
    --------
    >>> direction_factors().round(3).tolist()
    [1.0, 1.0, 1.0, 1.0, 1.414, 1.414, 1.414, 1.414]
    """
    if diagonal not in ("euclidean", "unit"):
        raise ValueError(f"diagonal must be 'euclidean' or 'unit', got {diagonal!r}")
    for name, v in (("down", down), ("side", side), ("up", up)):
        if not np.isfinite(v) or v <= 0:
            raise ValueError(f"{name} must be a positive finite factor, got {v}")
    f = np.where(_DIAGONAL, np.sqrt(2.0) if diagonal == "euclidean" else 1.0, 1.0)
    dr = OFFSETS[:, 0]
    f = f * np.where(dr > 0, down, np.where(dr < 0, up, side))
    return f.astype(np.float64)


def _check_weights(weights, name: str) -> np.ndarray:
    w = real_array(weights, name, allow_empty=True, finite=False)
    if w.ndim != 2 or w.shape[0] < 1 or w.shape[1] < 1:
        raise ValueError(f"{name} must be a non-empty 2-D (H, W) array, got shape {w.shape}")
    if np.isnan(w).any():
        raise ValueError(f"{name} contains NaN")
    if (w < 0).any():
        raise ValueError(f"{name} must be >= 0 (found {w.min():.4g}); use +inf for walls")
    return w


@checked(cost=_COST, epsilon=Real(0, 1e6), noise=Real(0, 1e6, arrays=True))
def node_weights(cost, *, epsilon: float = 0.01, noise: float = 0.5, rng=None) -> np.ndarray:
    """Node weights ``w = cost + epsilon + noise * U`` with ``U ~ uniform[0, 1)``.

    Parameters
    ----------
    cost : (H, W) array_like
        Non-negative cost map; ``+inf`` marks walls (kept as ``+inf``).
    epsilon : float
        Small constant so that every weight is > 0 (``epsilon`` in the docs).
    noise : float
        Amplitude of the random contribution. A scalar, or an ``(H, W)``
        array for a spatially varying amount (pareidolia trees raise it
        toward one side).
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed for ``U``; None draws a fresh seed.

    Returns
    -------
    w : (H, W) float64 ndarray

    Examples
    --------
    >>> w = node_weights(np.zeros((4, 4)), epsilon=0.1, noise=0.0)
    >>> float(w.min()), float(w.max())
    (0.1, 0.1)
    """
    c = _check_weights(cost, "cost")
    if c.size and not np.isfinite(c).any():
        raise ValueError("cost is +inf everywhere: every pixel is a wall, so no path exists")
    if not np.isfinite(epsilon) or epsilon < 0:
        raise ValueError(f"epsilon must be finite and >= 0, got {epsilon}")
    amp = np.asarray(noise, dtype=np.float64)
    if amp.ndim not in (0, 2) or (amp.ndim == 2 and amp.shape != c.shape):
        raise ValueError(f"noise must be a number or an array of shape {c.shape}")
    if not np.all(np.isfinite(amp)) or (amp < 0).any():
        raise ValueError("noise must be finite and >= 0")
    u = as_rng(rng).random(c.shape)
    with np.errstate(invalid="ignore"):
        w = c + epsilon + amp * u
    return w


@dataclass
class Lattice:
    """An 8-connected pixel lattice with node weights.

    Node ``i`` is pixel ``(row, col) = divmod(i, W)``, i.e. point
    ``(x, y) = (col, row)``.

    Parameters
    ----------
    weights : (H, W) array_like
        Node weights ``w`` (>= 0, no NaN; ``+inf`` = wall), usually from
        :func:`node_weights`.
    factors : (8,) array_like, optional
        Per-direction edge length factors ``f_k`` (positive, finite) in
        :data:`OFFSETS` order; Euclidean diagonals
        (:func:`direction_factors`) by default.
    bottleneck : {"edge", "density"}
        What the bottleneck term ``M`` of the blend metric
        (:func:`~branchnb.dendrite.planner.plan`) takes the maximum of: the
        edge costs ``c(p, q)`` ("edge", the paper's, default) or the edge
        costs per unit of Euclidean step length, ``c(p, q) / |q - p|``
        ("density", beyond the paper). With "edge" a diagonal step's cost is
        sqrt(2) times an axis step's over the same weights, so with a large
        blend weight (``a = 1000``) and weights that vary by less than that
        factor (a flat region with mild noise) the paths never step
        diagonally: 4-connected staircases, which on a flat dark region draw
        a grain of horizontal rails and vertical spikes. "density" makes ``M``
        isotropic; the cumulative term ``S`` is the same either way. The
        non-scalar metric supports "edge" only.

    Raises
    ------
    ValueError
        If ``weights`` is not a non-empty 2-D array of values >= 0 (or
        +inf), ``factors`` is not 8 positive finite numbers, or
        ``bottleneck`` is not "edge" or "density".

    Examples
    --------
    >>> lat = Lattice(np.ones((3, 4)))
    >>> lat.n_nodes, lat.node_index([(3, 2)]).tolist()
    (12, [11])
    """

    weights: np.ndarray
    factors: np.ndarray | None = None
    bottleneck: str = "edge"

    def __post_init__(self):
        if self.bottleneck not in ("edge", "density"):
            raise ValueError(f"bottleneck must be 'edge' or 'density', got {self.bottleneck!r}")
        self.weights = np.ascontiguousarray(_check_weights(self.weights, "weights"))
        if self.factors is None:
            self.factors = direction_factors()
        f = real_array(self.factors, "factors", finite=False)
        if f.shape != (8,) or not np.all(np.isfinite(f)) or (f <= 0).any():
            raise ValueError("factors must be 8 positive finite numbers (one per direction)")
        self.factors = f

    def bottleneck_factors(self) -> np.ndarray:
        """The 8 direction factors of the bottleneck term ``M``: :attr:`factors`
        ("edge"), or :attr:`factors` over the Euclidean step lengths ("density").

        Examples
        --------
        >>> Lattice(np.ones((2, 2)), bottleneck="density").bottleneck_factors().round(3).tolist()
        [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]
        """
        if self.bottleneck == "edge":
            return self.factors
        return self.factors / np.hypot(OFFSETS[:, 0], OFFSETS[:, 1])

    @property
    def shape(self) -> tuple[int, int]:
        return self.weights.shape

    @property
    def n_nodes(self) -> int:
        return int(self.weights.size)

    def node_index(self, points, *, name: str = "points") -> np.ndarray:
        """Flat node index of each ``(x, y)`` point (rounded to the nearest pixel).

        Raises ValueError if a point lies outside the lattice.

        Parameters
        ----------
        points : (N, 2) array_like
            ``(x, y)`` positions inside the lattice (pixel units).
        name : str
            Argument name used in error messages.

        Returns
        -------
        (N,) int64 ndarray
            ``row * W + col`` of the nearest pixel of each point.
        """
        h, w = self.shape
        pts = as_points(points, name=name, min_points=1, image_shape=(h, w))
        col = np.clip(np.rint(pts[:, 0]).astype(np.int64), 0, w - 1)
        row = np.clip(np.rint(pts[:, 1]).astype(np.int64), 0, h - 1)
        return row * w + col

    @checked(nodes=Array(ndim=(0, 1), dtype=np.int64, allow_empty=True, min=0))
    def node_points(self, nodes) -> np.ndarray:
        """``(x, y)`` of flat node indices, as an (N, 2) float array.

        Parameters
        ----------
        nodes : int or (N,) array_like of int
            Flat node indices in ``[0, n_nodes)``.

        Returns
        -------
        (N, 2) float64 ndarray
            ``(x, y) = (col, row)`` of each node.

        Examples
        --------
        >>> Lattice(np.ones((3, 4))).node_points([0, 11]).tolist()
        [[0.0, 0.0], [3.0, 2.0]]
        """
        if nodes.size and nodes.max() >= self.n_nodes:
            raise ValueError(f"nodes must be < {self.n_nodes} (the lattice's node count), got {int(nodes.max())}")
        row, col = np.divmod(nodes, self.shape[1])
        return np.column_stack([col, row]).astype(np.float64)

    def to_sparse(self) -> sp.csr_matrix:
        """The same graph as a scipy CSR matrix (entry ``[p, q]`` = ``c(p, q)``).

        Walls have no edges. Useful to check the lattice planner against the
        general graph planner, or to hand the lattice to scipy.sparse.csgraph.
        """
        h, w = self.shape
        wt = self.weights
        rows, cols, vals = [], [], []
        idx = np.arange(h * w).reshape(h, w)
        for k, (dr, dc) in enumerate(OFFSETS):
            r0, r1 = max(0, -dr), h - max(0, dr)
            c0, c1 = max(0, -dc), w - max(0, dc)
            src = idx[r0:r1, c0:c1]
            dst = idx[r0 + dr:r1 + dr, c0 + dc:c1 + dc]
            cost = 0.5 * (wt[r0:r1, c0:c1] + wt[r0 + dr:r1 + dr, c0 + dc:c1 + dc]) * self.factors[k]
            ok = np.isfinite(cost)
            rows.append(src[ok])
            cols.append(dst[ok])
            vals.append(cost[ok])
        return sp.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(h * w, h * w)
        )


@checked(cost=_COST, epsilon=Real(0, 1e6), noise=Real(0, 1e6, arrays=True), factors=Array(ndim=1))
def make_lattice(cost, *, epsilon: float = 0.01, noise: float = 0.5, rng=None,
                 factors=None) -> Lattice:
    """Build a :class:`Lattice` from a cost map: ``w = cost + epsilon + noise * U``.

    See :func:`node_weights` for the parameters; ``factors`` are the
    direction factors (:func:`direction_factors`, Euclidean diagonals by
    default).

    Parameters
    ----------
    cost : (H, W) array_like
        Non-negative cost of each pixel (e.g. ``1 - importance``); ``+inf``
        marks walls.
    epsilon : float
        Constant added to every weight so that no edge is free; 0.01 by
        default.
    noise : float or (H, W) array_like
        Amplitude of the uniform random term that makes paths wander; 0.5 by
        default. An array varies it per pixel.
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed for the noise.
    factors : (8,) array_like, optional
        Per-direction edge length factors ``f_k``; Euclidean diagonals
        (:func:`direction_factors`) by default.

    Returns
    -------
    Lattice

    Examples
    --------
    >>> lat = make_lattice(np.zeros((8, 8)), rng=0)
    >>> lat.shape
    (8, 8)
    """
    return Lattice(node_weights(cost, epsilon=epsilon, noise=noise, rng=rng), factors)
