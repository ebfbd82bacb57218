"""The dendrite: paths traced back from the endpoints (paper, section 3).

After the planner has labelled every node, each endpoint is followed back
along its parent pointers until the path meets the structure built so far
(or reaches a seed). The union of these paths is a tree: every node has
one parent, so there are no loops, and branches only merge toward the
seed. Endpoints are traced farthest first (in hop count), so the first
branch is the longest path and later ones attach to it as side branches.

The result is a :class:`Dendrite`: the nodes in the order they were added
(a parent always comes before its children), per-node radius, and the
branch decomposition used for thickness and polylines.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numba
import numpy as np

from ..core.io import encode_png
from ..core.validate import MAX_ITERATIONS, Array, Colour, Int, Real, Shape, check_shape, checked, real_array
from .planner import PlanResult

__all__ = ["Dendrite", "PathStats", "build_dendrite", "path_statistics"]


@numba.njit(cache=True)
def _hop_depth(parent, order):
    depth = np.full(parent.shape[0], -1, np.int64)
    for i in range(order.shape[0]):
        u = order[i]
        p = parent[u]
        depth[u] = 0 if p < 0 else depth[p] + 1
    return depth


@numba.njit(cache=True)
def _trace(parent, ends, tree_index, start_count):
    """Trace each endpoint back until it meets the tree; see build_dendrite."""
    n_max = parent.shape[0]
    out_nodes = np.empty(n_max, np.int64)
    out_parent = np.empty(n_max, np.int64)
    b_start = np.empty(ends.shape[0] + 1, np.int64)
    b_junction = np.empty(ends.shape[0], np.int64)
    b_tip = np.empty(ends.shape[0], np.int64)
    m = 0
    nb = 0
    for e in ends:
        if tree_index[e] >= 0:
            continue  # the endpoint already lies on the structure
        length = 0
        v = e
        while v >= 0 and tree_index[v] < 0:
            length += 1
            v = parent[v]
        junction = tree_index[v] if v >= 0 else -1
        # write root-first
        v = e
        for k in range(length - 1, -1, -1):
            out_nodes[m + k] = v
            v = parent[v]
        for k in range(length):
            idx = start_count + m + k
            tree_index[out_nodes[m + k]] = idx
            out_parent[m + k] = junction if k == 0 else idx - 1
        b_start[nb] = m
        b_junction[nb] = junction
        b_tip[nb] = start_count + m + length - 1
        nb += 1
        m += length
    b_start[nb] = m
    return out_nodes[:m], out_parent[:m], b_start[: nb + 1], b_junction[:nb], b_tip[:nb]


@numba.njit(cache=True)
def _accumulate_up(parent, values):
    out = values.copy()
    for i in range(parent.shape[0] - 1, -1, -1):
        p = parent[i]
        if p >= 0:
            out[p] += out[i]
    return out


@numba.njit(cache=True)
def _root_of(parent):
    root = np.arange(parent.shape[0])
    for i in range(parent.shape[0]):
        if parent[i] >= 0:
            root[i] = root[parent[i]]
    return root


@numba.njit(cache=True)
def _depth_down(parent, steps):
    out = np.zeros(parent.shape[0])
    for i in range(parent.shape[0]):
        p = parent[i]
        if p >= 0:
            out[i] = out[p] + steps[i]
    return out


@dataclass
class Dendrite:
    """A tree of lattice (or graph) nodes with per-node radius.

    Parameters
    ----------
    nodes : (M,) int64
        Graph node of each tree node.
    parent : (M,) int64
        Index (into this tree) of each node's parent, -1 for a root;
        always ``parent[i] < i``.
    points : (M, 2) float64
        ``(x, y)`` of each node (pixel centres on a lattice).
    radius : (M,) float64
        Half the drawn width at each node (pixels).
    branches : list of (n_b,) int64 arrays
        Tree indices of each branch, root side first. A side branch starts
        with its junction node on its parent branch, so its polyline is
        attached to the parent's.
    branch_parent : (B,) int64
        Parent branch of each branch (-1 for a root branch).
    tips : (E,) int64
        Tree index of each traced endpoint.
    shape : (H, W) or None
        Lattice / image shape.
    iteration : (M,) int64
        Growth iteration that added each node (trees; 0 otherwise).
    main : (K,) int64 or None
        Tree indices of a main channel planned on its own, root first (a
        lightning bolt on a photo,
        :func:`~branchnb.dendrite.photo_strike.photo_channel`); None (the
        default): :func:`~branchnb.dendrite.main_channel.main_path` walks
        down the child with most tips.

    Examples
    --------
    >>> from branchnb.dendrite.lattice import make_lattice
    >>> from branchnb.dendrite.planner import plan
    >>> d = build_dendrite(plan(make_lattice(np.zeros((20, 20)), rng=0), (10, 19)), [(2, 2), (17, 3)])
    >>> d.is_tree(), d.n_branches, d.shape
    (True, 2, (20, 20))
    """

    nodes: np.ndarray
    parent: np.ndarray
    points: np.ndarray
    radius: np.ndarray
    branches: list
    branch_parent: np.ndarray
    tips: np.ndarray
    shape: tuple[int, int] | None = None
    iteration: np.ndarray = field(default=None)
    main: np.ndarray | None = None

    def __post_init__(self):
        self.nodes = real_array(self.nodes, "nodes", ndim=1, dtype=np.int64, allow_empty=True, min=0)
        n = len(self.nodes)
        self.parent = real_array(self.parent, "parent", ndim=1, dtype=np.int64, allow_empty=True, min=-1)
        self.points = real_array(self.points, "points", ndim=2, allow_empty=True)
        self.radius = real_array(self.radius, "radius", ndim=1, allow_empty=True, min=0)
        for name in ("parent", "points", "radius"):
            if len(getattr(self, name)) != n:
                raise ValueError(f"{name} must have one row per node (len(nodes) = {n}), "
                                 f"got {len(getattr(self, name))}")
        if self.shape is not None:
            self.shape = check_shape(self.shape, "shape")
        if self.iteration is None:
            self.iteration = np.zeros(n, np.int64)
        self.iteration = real_array(self.iteration, "iteration", ndim=1, dtype=np.int64, allow_empty=True, min=0)
        if self.main is not None:
            self.main = real_array(self.main, "main", ndim=1, dtype=np.int64, allow_empty=True, min=0)
            if (self.main >= n).any() or (self.main.size > 1
                                          and np.any(self.parent[self.main[1:]] != self.main[:-1])):
                raise ValueError("main must be tree indices of a path, each node's parent before it")

    # -- structure ------------------------------------------------------
    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def n_branches(self) -> int:
        return len(self.branches)

    def is_tree(self) -> bool:
        """True if every node has one earlier parent and no node repeats (no cycles)."""
        idx = np.arange(self.n_nodes)
        roots = self.parent < 0
        return bool(np.all(self.parent[~roots] < idx[~roots])
                    and np.unique(self.nodes).size == self.n_nodes)

    def leaf_count(self) -> np.ndarray:
        """Number of tips in the subtree of each node."""
        leaf = np.zeros(self.n_nodes)
        leaf[self.tips] = 1.0
        return _accumulate_up(self.parent, leaf)

    def hop_depth(self) -> np.ndarray:
        """Number of edges from each node to its root."""
        return _depth_down(self.parent, np.ones(self.n_nodes)).astype(np.int64)

    def arc_depth(self) -> np.ndarray:
        """Path length (pixels) from each node's root to the node."""
        steps = np.zeros(self.n_nodes)
        has = self.parent >= 0
        d = self.points[has] - self.points[self.parent[has]]
        steps[has] = np.hypot(d[:, 0], d[:, 1])
        return _depth_down(self.parent, steps)

    def tip_distance(self) -> np.ndarray:
        """Path length (pixels) from each node to the end of the branch it belongs to
        (:meth:`owner`): 0 at a tip, growing toward the root; used to taper twigs."""
        out = np.zeros(self.n_nodes)
        first = self.branch_parent >= 0  # a side branch's first node is its parent's junction
        for i, b in enumerate(self.branches):
            if len(b) < 2:
                continue
            seg = np.hypot(*np.diff(self.points[b], axis=0).T)
            rest = np.concatenate([np.cumsum(seg[::-1])[::-1], [0.0]])
            k = 1 if first[i] else 0
            out[b[k:]] = rest[k:]
        return out

    def next_in_branch(self) -> np.ndarray:
        """The next node along each node's own branch (-1 at a tip)."""
        nxt = np.full(self.n_nodes, -1, np.int64)
        for i, b in enumerate(self.branches):
            # a side branch's first node is its junction on the parent branch: that
            # node continues along the parent branch, not into the side branch
            k = 1 if self.branch_parent[i] >= 0 else 0
            nxt[b[k:-1]] = b[k + 1:]
        return nxt

    def owner(self) -> tuple[np.ndarray, np.ndarray]:
        """``(branch, position)`` of each node in the branch it belongs to
        (a junction node belongs to the branch it continues, not the side branch)."""
        br = np.full(self.n_nodes, -1, np.int64)
        pos = np.full(self.n_nodes, -1, np.int64)
        for i, b in enumerate(self.branches):
            first = 0 if self.branch_parent[i] < 0 else 1
            br[b[first:]] = i
            pos[b[first:]] = np.arange(first, len(b))
        return br, pos

    @checked(radius=Array(ndim=1, min=0))
    def with_radius(self, radius) -> Dendrite:
        """A copy with a new per-node radius.

        Parameters
        ----------
        radius : (M,) array_like
            New radius (half the drawn width, pixels, finite and >= 0) of every
            node, in node order.

        Returns
        -------
        Dendrite
            A new dendrite sharing the structure arrays; ``self`` is unchanged.

        Raises
        ------
        ValueError
            If ``radius`` does not have one finite value >= 0 per node.
        """
        r = np.asarray(radius, np.float64)
        if r.shape != (self.n_nodes,) or not np.all(np.isfinite(r)) or (r < 0).any():
            raise ValueError(f"radius must be {self.n_nodes} finite values >= 0")
        return Dendrite(self.nodes, self.parent, self.points, r, self.branches,
                        self.branch_parent, self.tips, self.shape, self.iteration, self.main)

    @checked(shape=Shape())
    def rescaled(self, shape) -> Dendrite:
        """The same dendrite drawn on an image of ``shape`` (H, W): points map pixel
        centre to pixel centre, radii scale by the geometric mean of the two factors.
        ``nodes`` keep indexing the original lattice.

        Parameters
        ----------
        shape : (int, int)
            ``(H, W)`` of the target image. The dendrite must have a ``shape``.

        Returns
        -------
        Dendrite
            The rescaled copy (``shape`` set to the new one).

        Raises
        ------
        ValueError
            If the dendrite has no ``shape`` to scale from.

        Examples
        --------
        >>> from branchnb.dendrite.lattice import make_lattice
        >>> from branchnb.dendrite.planner import plan
        >>> d = build_dendrite(plan(make_lattice(np.zeros((10, 10)), rng=0), (5, 9)), [(5, 0)])
        >>> big = d.rescaled((20, 20))
        >>> big.shape, float(big.points[:, 1].max()), float(big.radius[0] / d.radius[0])
        ((20, 20), 18.5, 2.0)
        """
        if self.shape is None:
            raise ValueError("rescaled needs a dendrite with an image shape")
        h, w = shape
        sx, sy = w / self.shape[1], h / self.shape[0]
        pts = (self.points + 0.5) * np.array([sx, sy]) - 0.5
        return Dendrite(self.nodes, self.parent, pts, self.radius * float(np.sqrt(sx * sy)),
                        self.branches, self.branch_parent, self.tips, (h, w), self.iteration,
                        self.main)

    # -- geometry -------------------------------------------------------
    @checked(iterations=Int(0, 10_000))
    def smoothed_points(self, iterations: int = 0) -> np.ndarray:
        """Node positions after ``iterations`` passes of [1, 2, 1] / 4 averaging
        along the branches (about a Gaussian of sigma sqrt(iterations / 2)
        nodes). Roots and tips stay fixed; junctions move with their own branch,
        so side branches stay attached.

        Parameters
        ----------
        iterations : int
            Number of averaging passes (>= 0); 0 returns a copy of ``points``.

        Returns
        -------
        (M, 2) float64 ndarray
            Smoothed ``(x, y)`` of every node.

        Examples
        --------
        >>> from branchnb.dendrite.lattice import make_lattice
        >>> from branchnb.dendrite.planner import plan
        >>> d = build_dendrite(plan(make_lattice(np.zeros((20, 20)), rng=0), (10, 19)), [(2, 2)])
        >>> p = d.smoothed_points(4)
        >>> p.shape == d.points.shape, bool((p[0] == d.points[0]).all())
        (True, True)
        """
        if iterations < 0:
            raise ValueError(f"iterations must be >= 0, got {iterations}")
        p = self.points.copy()
        if iterations == 0 or self.n_nodes < 3:
            return p
        nxt = self.next_in_branch()
        free = (self.parent >= 0) & (nxt >= 0)
        i, prv, nx = np.flatnonzero(free), self.parent[free], nxt[free]
        for _ in range(int(iterations)):
            p[i] = 0.25 * p[prv] + 0.5 * p[i] + 0.25 * p[nx]
        return p

    @checked(smooth=Int(0, 10_000))
    def polylines(self, smooth: int = 0) -> list[np.ndarray]:
        """One ``(n_b, 2)`` polyline per branch (smoothed with :meth:`smoothed_points`).

        Parameters
        ----------
        smooth : int
            Passes of [1, 2, 1] / 4 averaging applied first (0: the raw lattice
            positions, a staircase of pixel centres).

        Returns
        -------
        list of (n_b, 2) float64 ndarray
            One polyline per branch, in :attr:`branches` order, root side first.
        """
        p = self.smoothed_points(smooth)
        return [p[b] for b in self.branches]

    def widths(self) -> list[np.ndarray]:
        """Full width (2 r) at each vertex of each branch polyline."""
        return [2.0 * self.radius[b] for b in self.branches]

    def to_structure(self):
        """The dendrite as a :class:`branchnb.core.structure.Structure`
        (thickness = radius, floored at 0.05 px)."""
        from ..core.structure import Branch, Structure

        _, pos = self.owner()
        out = []
        r = np.maximum(self.radius, 0.05)
        for i, b in enumerate(self.branches):
            pb = int(self.branch_parent[i])
            out.append(Branch(self.points[b], r[b], None if pb < 0 else pb,
                              None if pb < 0 else int(pos[b[0]])))
        return Structure(out, self.shape)

    # -- output ---------------------------------------------------------
    @checked(color=Colour(), smooth=Int(0, 10_000))
    def render(self, background=None, *, color=(0.0, 0.0, 0.0), smooth: int = 2) -> np.ndarray:
        """Draw the branches with their widths (plain metaphor) on ``background``
        (white canvas of ``shape`` by default).

        Parameters
        ----------
        background : (H, W, C) array_like, optional
            Image to draw on; a white ``shape`` canvas by default (then the
            dendrite must have a ``shape``).
        color : RGB triple
            Stroke colour in [0, 1]; black by default.
        smooth : int
            Averaging passes along the branches before drawing (see
            :meth:`smoothed_points`); 2 softens the lattice staircase.

        Returns
        -------
        (H, W, 3) float32 ndarray
            The drawing, each node drawn with width ``2 * radius``.

        Examples
        --------
        >>> from branchnb.dendrite.lattice import make_lattice
        >>> from branchnb.dendrite.planner import plan
        >>> d = build_dendrite(plan(make_lattice(np.zeros((20, 20)), rng=0), (10, 19)), [(2, 2)])
        >>> img = d.render()
        >>> img.shape, bool(img.min() < 0.5)
        ((20, 20, 3), True)
        """
        from .render import render_plain

        return render_plain(self, background=background, color=color, smooth=smooth).image

    @checked(color=Colour(), smooth=Int(0, 10_000))
    def to_svg(self, *, color=(0.0, 0.0, 0.0), smooth: int = 2) -> str:
        """SVG document of the plain rendering.

        Parameters
        ----------
        color : RGB triple
            Stroke colour in [0, 1]; black by default.
        smooth : int
            Averaging passes along the branches before writing (see
            :meth:`smoothed_points`).

        Returns
        -------
        str
            An SVG document of ``shape`` size, one stroke per segment on white.
        """
        from .render import render_plain

        return render_plain(self, color=color, smooth=smooth).svg

    def _repr_png_(self) -> bytes | None:
        if self.shape is None or self.n_nodes == 0:
            return None
        return encode_png(self.render())


def _endpoint_nodes(plan_result: PlanResult, endpoints) -> np.ndarray:
    n = plan_result.n_nodes
    if plan_result.shape is not None:
        from ..core.image import as_points

        h, w = plan_result.shape
        pts = as_points(endpoints, name="endpoints", min_points=1, image_shape=(h, w))
        col = np.clip(np.rint(pts[:, 0]).astype(np.int64), 0, w - 1)
        row = np.clip(np.rint(pts[:, 1]).astype(np.int64), 0, h - 1)
        return row * w + col
    e = np.atleast_1d(np.asarray(endpoints))
    if e.size == 0:
        raise ValueError("endpoints is empty: give at least one endpoint")
    if not np.issubdtype(e.dtype, np.integer):
        raise TypeError("endpoints must be integer node indices on a general graph")
    e = e.ravel().astype(np.int64)
    if e.min() < 0 or e.max() >= n:
        raise ValueError(f"endpoint nodes must lie in [0, {n})")
    return e


@checked(radius=Real(0, 1e4), iteration=Int(0, MAX_ITERATIONS))
def build_dendrite(plan_result: PlanResult, endpoints, *, base: Dendrite | None = None,
                   positions=None, radius: float = 1.0, iteration: int = 0) -> Dendrite:
    """Trace the endpoints back to the seeds and return the dendrite.

    Parameters
    ----------
    plan_result : PlanResult
        Output of :func:`~branchnb.dendrite.planner.plan`.
    endpoints : array_like
        ``(E, 2)`` points ``(x, y)`` on a lattice (rounded to the nearest
        pixel), or node indices on a general graph.
    base : Dendrite, optional
        An existing structure that was the seed set of ``plan_result``;
        the new branches are added to it (iterative tree growth).
    positions : (N, 2) array_like, optional
        Node coordinates for a general graph (pixel centres on a lattice).
    radius : float
        Initial radius of the new nodes.
    iteration : int
        Stored in :attr:`Dendrite.iteration` for the new nodes.

    Returns
    -------
    Dendrite
        Every endpoint is a node of it. An endpoint that an earlier (longer)
        path already passes through adds no branch and is not listed in
        ``tips``; duplicate endpoints (same pixel) count once.

    Raises
    ------
    ValueError
        No endpoints, an endpoint outside the graph, or one the planner
        did not reach (a wall, another component, or cut off by ``stop_at``).

    Examples
    --------
    >>> from branchnb.dendrite.lattice import make_lattice
    >>> from branchnb.dendrite.planner import plan
    >>> res = plan(make_lattice(np.zeros((40, 40)), rng=0), (20, 39))
    >>> d = build_dendrite(res, [(2, 2), (37, 3), (20, 5)])
    >>> d.is_tree(), len(d.tips)
    (True, 3)
    """
    if not isinstance(plan_result, PlanResult):
        raise TypeError(f"plan_result must be a PlanResult, got {type(plan_result).__name__}")
    ends = _endpoint_nodes(plan_result, endpoints)
    unreached = ~np.isfinite(plan_result.total_cost[ends])
    if unreached.any():
        bad = int(ends[np.flatnonzero(unreached)[0]])
        where = (f"(x, y) = ({bad % plan_result.shape[1]}, {bad // plan_result.shape[1]})"
                 if plan_result.shape is not None else f"node {bad}")
        raise ValueError(f"{int(unreached.sum())} endpoint(s) were not reached by the planner, "
                         f"e.g. {where}: a wall or a part of the graph cut off from the seeds")
    ends = np.unique(ends)
    depth = _hop_depth(plan_result.parent, plan_result.order)
    ends = ends[np.argsort(-depth[ends], kind="stable")]

    n = plan_result.n_nodes
    tree_index = np.full(n, -1, np.int64)
    if base is not None:
        if not isinstance(base, Dendrite):
            raise TypeError("base must be a Dendrite")
        if base.nodes.size and base.nodes.max() >= n:
            raise ValueError("base does not live on this graph")
        tree_index[base.nodes] = np.arange(base.n_nodes)
        start = base.n_nodes
    else:
        start = 0
    new_nodes, new_parent, b_start, b_junction, b_tip = _trace(
        plan_result.parent, ends, tree_index, start)

    if plan_result.shape is not None:
        w = plan_result.shape[1]
        new_points = np.column_stack([new_nodes % w, new_nodes // w]).astype(np.float64)
    elif positions is not None:
        pos = np.asarray(positions, np.float64)
        if pos.shape != (n, 2) or not np.all(np.isfinite(pos)):
            raise ValueError(f"positions must be a finite ({n}, 2) array")
        new_points = pos[new_nodes]
    else:
        new_points = np.zeros((len(new_nodes), 2))

    # owner branch of each tree node, to find each new branch's parent branch
    if base is not None:
        owner_base, _ = base.owner()
        branches = list(base.branches)
        branch_parent = list(base.branch_parent)
        nodes = np.concatenate([base.nodes, new_nodes])
        parent = np.concatenate([base.parent, new_parent])
        points = np.concatenate([base.points, new_points])
        radius_all = np.concatenate([base.radius, np.full(len(new_nodes), float(radius))])
        iters = np.concatenate([base.iteration, np.full(len(new_nodes), int(iteration))])
        tips = list(base.tips)
    else:
        owner_base = np.zeros(0, np.int64)
        branches, branch_parent, tips = [], [], []
        nodes, parent, points = new_nodes, new_parent, new_points
        radius_all = np.full(len(new_nodes), float(radius))
        iters = np.full(len(new_nodes), int(iteration), np.int64)
    owner = np.concatenate([owner_base, np.full(len(new_nodes), -1, np.int64)])
    for k in range(len(b_junction)):
        s, e = start + b_start[k], start + b_start[k + 1]
        j = int(b_junction[k])
        idx = np.arange(s, e)
        bi = len(branches)
        if j >= 0:
            branches.append(np.concatenate([[j], idx]))
            branch_parent.append(int(owner[j]))
        else:
            branches.append(idx)
            branch_parent.append(-1)
        owner[idx] = bi
        tips.append(int(b_tip[k]))
    return Dendrite(nodes, parent, points, radius_all, branches,
                    np.asarray(branch_parent, np.int64), np.asarray(tips, np.int64),
                    plan_result.shape, iters)


@dataclass
class PathStats:
    """Per-endpoint statistics of the full path from the seed set.

    Parameters
    ----------
    length : (E,) float64 ndarray
        Path length in pixels, along the dendrite from the root to the tip.
    straight : (E,) float64 ndarray
        Straight-line distance (pixels) from the path's seed to the tip.
    tortuosity : (E,) float64 ndarray
        ``length / straight`` (>= 1; 1 for a tip on a seed, a path of length 0).
    max_edge : (E,) float64 ndarray
        Largest edge cost on the path (the non-scalar ``M``).
    total : (E,) float64 ndarray
        Cumulative cost of the path (``S``).

    Examples
    --------
    >>> st = PathStats(np.array([12.0]), np.array([10.0]), np.array([1.2]), np.array([0.5]), np.array([6.0]))
    >>> float(st.tortuosity[0])
    1.2
    """

    length: np.ndarray
    straight: np.ndarray
    tortuosity: np.ndarray
    max_edge: np.ndarray
    total: np.ndarray


@checked()
def path_statistics(dendrite: Dendrite, plan_result: PlanResult) -> PathStats:
    """Tortuosity and costs of the seed-to-tip path of every tip of ``dendrite``.

    Parameters
    ----------
    dendrite : Dendrite
        A dendrite traced in ``plan_result`` (:func:`build_dendrite`); its
        roots must be seeds of the plan.
    plan_result : PlanResult
        The plan the dendrite was traced in; gives each tip's path costs
        ``M`` and ``S``.

    Returns
    -------
    PathStats
        One entry per tip of ``dendrite`` (in :attr:`Dendrite.tips` order).

    Raises
    ------
    TypeError
        If the arguments are not a Dendrite and a PlanResult.
    ValueError
        If the dendrite was not traced in ``plan_result`` (node indices or
        roots do not match).

    Examples
    --------
    >>> from branchnb.dendrite.lattice import make_lattice
    >>> from branchnb.dendrite.planner import plan
    >>> res = plan(make_lattice(np.zeros((30, 30)), rng=0), (15, 29))
    >>> st = path_statistics(build_dendrite(res, [(3, 3), (26, 4)]), res)
    >>> bool((st.tortuosity >= 1).all())
    True
    """
    if not isinstance(dendrite, Dendrite):
        raise TypeError(f"dendrite must be a Dendrite, got {type(dendrite).__name__}")
    if not isinstance(plan_result, PlanResult):
        raise TypeError(f"plan_result must be a PlanResult, got {type(plan_result).__name__}")
    n_nodes = len(plan_result.max_cost)
    # (the shapes may differ: a stylization's dendrite lives in image pixels, its plan on a coarser lattice)
    if len(dendrite.nodes) and int(np.max(dendrite.nodes)) >= n_nodes:
        raise ValueError(f"plan_result is not the plan this dendrite was traced in: it has {n_nodes} nodes, the "
                         f"dendrite uses node {int(np.max(dendrite.nodes))}")
    roots = dendrite.nodes[np.asarray(dendrite.parent) < 0]
    if len(roots) and not np.isin(roots, plan_result.seeds).all():
        raise ValueError("plan_result is not the plan this dendrite was traced in: the dendrite's roots are not "
                         "among its seeds")
    arc = dendrite.arc_depth()
    root = _root_of(dendrite.parent)
    t = dendrite.tips
    length = arc[t]
    d = dendrite.points[t] - dendrite.points[root[t]]
    straight = np.hypot(d[:, 0], d[:, 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        tort = np.where(straight > 0, length / np.where(straight > 0, straight, 1), 1.0)
    g = dendrite.nodes[t]
    return PathStats(length, straight, tort, plan_result.max_cost[g], plan_result.total_cost[g])

