"""Path planning: Dijkstra's algorithm with three path metrics (paper, section 3).

A path ``P`` from the seed set to a node is labelled with the pair

    L(P) = (M(P), S(P)),   M = max edge cost along P,   S = sum of edge costs,

and the planner settles nodes in increasing order of a key built from it:

``"cumulative"``
    key = ``S``: ordinary shortest paths. Branches are smooth, nearly
    straight geodesics.
``"nonscalar"``
    key = ``(M, S)`` compared lexicographically: first the maximum edge
    cost, ties broken by the cumulative cost. This is the paper's
    *partial non-scalar* metric. ``M`` alone is the bottleneck (minimax)
    distance, so the structure floods the cheapest regions first and its
    branches wander along them: the jagged, lightning-like dendrites.
    The lexicographic order is not preserved when two paths are extended
    by the same edge (``(1, 9) < (2, 1)`` but adding an edge of cost 3 gives
    ``(3, 12) > (3, 4)``), so Dijkstra does not return globally
    lexicographic-optimal paths, only the tree obtained by settling nodes
    in this order ("partial"). Its first component *is* exact: every
    node's ``M`` equals its bottleneck distance, hence for every node the
    non-scalar path's maximum edge is <= the cumulative path's.
``"blend"``
    key = ``a * M + S`` (a scalar; ``a`` = ``blend_weight``, the paper
    found ``a = 1000`` good for trees). ``a = 0`` is the cumulative metric;
    large ``a`` approaches the non-scalar one. On a
    :class:`~branchnb.dendrite.lattice.Lattice` with ``bottleneck="density"``
    ``M`` is the largest edge cost per unit of step length (a diagonal step
    is then not sqrt(2) times dearer in ``M``); ``S`` is unchanged.

Relaxation replaces a node's label only when the new key is strictly
smaller. The non-scalar key is the whole label and the cumulative metric is
isotone, so their results do not depend on how exact key ties are broken;
the blend key ``a * M + S`` does not determine ``(M, S)`` and is not
isotone, so with exact key ties (e.g. small integer weights) its tree
depends on which tied path is settled first. With real-valued random
weights such ties practically never occur. The hot loops
(:mod:`._dijkstra`) are numba-compiled indexed 4-ary heaps (decrease-key,
one entry per frontier node) over flat arrays; the lattice version computes
edge costs on the fly (:mod:`.lattice`) and prefetches the neighbourhood of
the next node to settle, the sparse version walks a CSR matrix. On a
512 x 512 lattice the three searches take about 0.3x (cumulative) and 0.5x
(non-scalar, blend) the CPU time of ``skimage.graph.MCP_Geometric``'s
cumulative search (:mod:`._bench`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..core.io import encode_png
from ..core.validate import Array, Int, Real, checked
from ._dijkstra import _csr_pair, _csr_scalar, _lattice_pair, _lattice_scalar
from .lattice import OFFSETS, Lattice

__all__ = ["METRICS", "PlanResult", "metric_code", "plan"]

METRICS = ("cumulative", "nonscalar", "blend")
_CUMULATIVE, _NONSCALAR, _BLEND = 0, 1, 2
_DROW = np.ascontiguousarray(OFFSETS[:, 0])
_DCOL = np.ascontiguousarray(OFFSETS[:, 1])


def metric_code(metric: str) -> int:
    """Validate a metric name; return its integer code.

    Parameters
    ----------
    metric : str
        One of :data:`METRICS`: ``"cumulative"``, ``"nonscalar"``, ``"blend"``.

    Returns
    -------
    int
        0, 1 or 2 (the index in :data:`METRICS`).

    Raises
    ------
    ValueError
        If ``metric`` is not a known name.

    Examples
    --------
    >>> metric_code("nonscalar")
    1
    """
    if metric not in METRICS:
        raise ValueError(f"metric must be one of {list(METRICS)}, got {metric!r}")
    return METRICS.index(metric)


# -------------------------------------------------------------------- result
@dataclass
class PlanResult:
    """What the planner returns; every array has one entry per graph node.

    Parameters
    ----------
    metric : str
        ``"cumulative"``, ``"nonscalar"`` or ``"blend"``.
    blend_weight : float
        ``a`` of the blend metric.
    max_cost : (N,) float64
        ``M``: the largest edge cost on the node's path (``inf`` if unreached).
    total_cost : (N,) float64
        ``S``: the cumulative cost of the node's path (``inf`` if unreached).
    parent : (N,) int64
        Predecessor on the path; -1 for seeds and unreached nodes.
    order : (K,) int64
        The settled nodes in visiting order (``K`` <= N).
    seeds : (S,) int64
        The seed nodes.
    shape : (H, W) or None
        The lattice shape (None for a general graph).

    Examples
    --------
    >>> from branchnb.dendrite.lattice import make_lattice
    >>> res = plan(make_lattice(np.zeros((5, 5)), rng=0), (0, 0))
    >>> res.metric, len(res.order), int(res.parent[0])
    ('nonscalar', 25, -1)
    """

    metric: str
    blend_weight: float
    max_cost: np.ndarray
    total_cost: np.ndarray
    parent: np.ndarray
    order: np.ndarray
    seeds: np.ndarray
    shape: tuple[int, int] | None = None

    @property
    def n_nodes(self) -> int:
        return int(self.parent.shape[0])

    @property
    def reached(self) -> np.ndarray:
        """Boolean mask of the nodes the planner settled."""
        m = np.zeros(self.n_nodes, bool)
        m[self.order] = True
        return m

    @property
    def rank(self) -> np.ndarray:
        """Visiting rank of each node (0 for the first settled, -1 if never)."""
        r = np.full(self.n_nodes, -1, np.int64)
        r[self.order] = np.arange(len(self.order))
        return r

    @property
    def label(self) -> np.ndarray:
        """The comparison key of each node: (N,) for scalar metrics, (N, 2) for non-scalar."""
        if self.metric == "cumulative":
            return self.total_cost.copy()
        if self.metric == "nonscalar":
            return np.column_stack([self.max_cost, self.total_cost])
        return self.blend_weight * self.max_cost + self.total_cost

    @checked(node=Int(0))
    def path(self, node: int) -> np.ndarray:
        """Nodes from the seed set to ``node`` (inclusive), following ``parent``.

        Parameters
        ----------
        node : int
            A reached node index in ``[0, n_nodes)``.

        Returns
        -------
        (L,) int64 ndarray
            Node indices, a seed first and ``node`` last.

        Raises
        ------
        ValueError
            If ``node`` is outside the graph or was not reached.
        """
        node = int(node)
        if not 0 <= node < self.n_nodes:
            raise ValueError(f"node {node} is outside the graph of {self.n_nodes} nodes")
        if not np.isfinite(self.total_cost[node]):
            raise ValueError(f"node {node} was not reached from the seeds")
        out = [node]
        while self.parent[out[-1]] >= 0:
            out.append(int(self.parent[out[-1]]))
        return np.array(out[::-1], np.int64)

    @checked(values=Array(ndim=(1, 2), allow_inf=True))
    def as_image(self, values) -> np.ndarray:
        """Reshape a per-node array to the lattice ``(H, W)``.

        Parameters
        ----------
        values : (N,) or (H, W) array_like
            One value per node (e.g. :attr:`total_cost`).

        Returns
        -------
        (H, W) ndarray

        Raises
        ------
        ValueError
            If the plan is on a general graph or ``values`` has the wrong size.
        """
        if self.shape is None:
            raise ValueError("this plan is on a general graph, not a lattice")
        if values.size != self.n_nodes:
            raise ValueError(f"values must have one entry per node ({self.n_nodes}), got {values.size}")
        return values.reshape(self.shape)

    def _repr_png_(self) -> bytes | None:
        if self.shape is None:
            return None
        from .render import visiting_order_image

        return encode_png(visiting_order_image(self))


# ---------------------------------------------------------------------- API
def _seed_nodes(graph, seeds, n_nodes: int) -> np.ndarray:
    if isinstance(graph, Lattice):
        s = np.asarray(seeds)
        if s.dtype == bool:
            if s.shape != graph.shape:
                raise ValueError(f"a seed mask must have the lattice shape {graph.shape}, got {s.shape}")
            nodes = np.flatnonzero(s)
            if nodes.size == 0:
                raise ValueError("the seed mask is empty")
        else:
            pts = s.reshape(1, 2) if s.shape == (2,) else s
            nodes = graph.node_index(pts, name="seeds")
        walls = ~np.isfinite(graph.weights.ravel()[nodes])
        if walls.any():
            i = int(nodes[np.flatnonzero(walls)[0]])
            r, c = divmod(i, graph.shape[1])
            raise ValueError(f"seed at (x, y) = ({c}, {r}) lies on an infinite-cost node (a wall)")
        return np.unique(nodes)
    try:
        nodes = np.atleast_1d(np.asarray(seeds))
    except (TypeError, ValueError) as exc:
        raise TypeError("seeds must be node indices") from exc
    if nodes.size == 0:
        raise ValueError("seeds is empty: give at least one seed node")
    if nodes.dtype == bool:
        if nodes.shape != (n_nodes,):
            raise ValueError(f"a seed mask must have {n_nodes} entries")
        nodes = np.flatnonzero(nodes)
        if nodes.size == 0:
            raise ValueError("the seed mask is empty")
    if not np.issubdtype(nodes.dtype, np.integer):
        raise TypeError(f"seeds must be integer node indices for a sparse graph, got {nodes.dtype}")
    nodes = nodes.ravel().astype(np.int64)
    bad = (nodes < 0) | (nodes >= n_nodes)
    if bad.any():
        raise ValueError(f"seed node {int(nodes[bad][0])} is outside the graph of {n_nodes} nodes")
    return np.unique(nodes)


def _check_sparse(graph) -> sp.csr_matrix:
    g = sp.csr_matrix(graph, dtype=np.float64)
    if g.shape[0] != g.shape[1]:
        raise ValueError(f"graph must be a square adjacency matrix, got shape {g.shape}")
    g.sort_indices()
    d = g.data
    if np.isnan(d).any():
        raise ValueError("graph edge costs contain NaN")
    if (d < 0).any():
        raise ValueError("graph edge costs must be >= 0 (Dijkstra needs non-negative costs)")
    return g


@checked(blend_weight=Real(0, allow_inf=True))
def plan(graph, seeds, *, metric: str = "nonscalar", blend_weight: float = 1000.0,
         stop_at=None) -> PlanResult:
    """Dijkstra from a seed set with the chosen path metric.

    Parameters
    ----------
    graph : Lattice or scipy.sparse matrix
        A :class:`~branchnb.dendrite.lattice.Lattice` (8-connected pixel
        grid) or a square sparse adjacency matrix whose entry ``[p, q]`` is
        the cost of the directed edge ``p -> q`` (stored entries are edges,
        ``inf`` entries are ignored; symmetrise it for an undirected graph).
    seeds : array_like
        For a lattice: one ``(x, y)`` point, an ``(S, 2)`` array of points,
        or an ``(H, W)`` boolean mask (e.g. an existing structure). For a
        sparse graph: node indices or an ``(N,)`` boolean mask.
    metric : {"nonscalar", "cumulative", "blend"}
        The path metric (see the module docstring).
    blend_weight : float
        ``a`` in ``a * max_edge + total`` for ``metric="blend"``.
    stop_at : array_like of int, optional
        Node indices; the search stops once all of them are settled (the
        labels of the settled nodes are final; later nodes stay unreached).

    Returns
    -------
    PlanResult

    Raises
    ------
    ValueError
        Unknown metric, a seed outside the graph or on a wall, an empty seed
        set, NaN or negative costs.

    Examples
    --------
    >>> from branchnb.dendrite.lattice import make_lattice
    >>> lat = make_lattice(np.zeros((32, 32)), rng=0)
    >>> res = plan(lat, (16, 16), metric="nonscalar")
    >>> int(res.order[0]) == 16 * 32 + 16, bool(res.reached.all())
    (True, True)
    """
    code = metric_code(metric)
    if not np.isfinite(blend_weight) or blend_weight < 0:
        raise ValueError(f"blend_weight must be finite and >= 0, got {blend_weight}")
    if isinstance(graph, Lattice):
        n_nodes = graph.n_nodes
        # a Lattice is checked when built, but its arrays can be changed afterwards
        if np.isnan(graph.weights).any() or (graph.weights < 0).any():
            raise ValueError("graph weights contain NaN or negative values (changed after the Lattice was built?)")
        f = np.asarray(graph.factors, np.float64)
        if f.shape != (8,) or not np.isfinite(f).all() or (f <= 0).any():
            raise ValueError("graph factors must be 8 positive finite numbers")
        if code == _NONSCALAR and graph.bottleneck != "edge":
            raise ValueError("the nonscalar metric needs a lattice with bottleneck='edge', "
                             f"got {graph.bottleneck!r}")
    elif sp.issparse(graph):
        graph = _check_sparse(graph)
        n_nodes = graph.shape[0]
    else:
        raise TypeError(f"graph must be a Lattice or a scipy.sparse matrix, got {type(graph).__name__}")
    nodes = _seed_nodes(graph, seeds, n_nodes)
    stop = np.zeros(n_nodes, np.bool_)
    if stop_at is not None:
        t = np.atleast_1d(np.asarray(stop_at))
        if t.size:
            if not np.issubdtype(t.dtype, np.integer) or t.min() < 0 or t.max() >= n_nodes:
                raise ValueError("stop_at must be node indices inside the graph")
            stop[t.ravel()] = True
    # Unreached nodes must compare as +inf under every metric: M starts at 0
    # (not inf) for the scalar metrics so that a * M + S is inf, not NaN, at a = 0.
    mmax = np.full(n_nodes, np.inf if code == _NONSCALAR else 0.0)
    total = np.full(n_nodes, np.inf)
    parent = np.full(n_nodes, -1, np.int64)
    order = np.empty(n_nodes, np.int64)
    a = 0.0 if code == _CUMULATIVE else float(blend_weight)  # scalar key a * M + S
    if isinstance(graph, Lattice):
        h, w = graph.shape
        args = (graph.weights.ravel(), h, w, _DROW, _DCOL, f)
        if code == _NONSCALAR:
            count = _lattice_pair(*args, nodes, mmax, total, parent, order, stop)
        else:
            mf = np.ascontiguousarray(graph.bottleneck_factors(), np.float64)
            count = _lattice_scalar(*args, mf, nodes, a, mmax, total, parent, order, stop)
        shape = (h, w)
    else:
        args = (graph.indptr.astype(np.int64), graph.indices.astype(np.int64), graph.data, nodes)
        if code == _NONSCALAR:
            count = _csr_pair(*args, mmax, total, parent, order, stop)
        else:
            count = _csr_scalar(*args, a, mmax, total, parent, order, stop)
        shape = None
    order = order[:count].copy()
    if count < n_nodes:  # nodes left in the heap keep tentative labels: report them unreached
        settled = np.zeros(n_nodes, bool)
        settled[order] = True
        mmax[~settled] = np.inf
        total[~settled] = np.inf
        parent[~settled] = -1
    return PlanResult(metric, float(blend_weight), mmax, total, parent, order, nodes, shape)
