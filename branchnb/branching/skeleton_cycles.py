"""Automatic extraction, beyond the paper: the cycles of a network closed again.

:func:`~branchnb.branching.skeleton_tree.skeleton_to_structure` turns each
piece of the skeleton into a shortest-path tree, which cuts every cycle of
the skeleton graph once, where the two fronts meet; the two half-edges on
either side of the cut are then short subtrees that the spur pruning drops.
On a network (crack patterns, mud, braided channels, a road map) the
extracted structure is a tree of open ends where the example shows closed
cells. This module finds every such cut (a graph edge outside the tree whose
loop is long enough to be a real cell, not a pixel triangle at a junction)
and returns the pixel chain that joins the two built branches again: from
the nearest kept node on one side, across the cut, to the nearest kept node
on the other. :func:`skeleton_to_structure` adds each chain as a *join*
branch, a child of the first branch that ends on a vertex of the second,
so the tree stays a tree while its drawing closes the cell.
"""

from __future__ import annotations

import numpy as np
from scipy import sparse

__all__: list[str] = []


def _loop_at_least(a: int, b: int, pred: np.ndarray, dist: np.ndarray, min_loop: float) -> bool:
    """Whether the cycle the non-tree edge ``(a, b)`` closes is at least ``min_loop`` long.

    Walks up from both ends (always the farther one from the root) until they meet at their
    common ancestor or the walked length passes ``min_loop`` (bounded work for long cycles).
    """
    x, y = a, b
    while x != y:
        if x < 0 or y < 0:          # different trees (cannot happen within a piece)
            return False
        if (dist[a] - dist[x]) + (dist[b] - dist[y]) >= min_loop:
            return True
        if dist[x] >= dist[y]:
            x = int(pred[x])
        else:
            y = int(pred[y])
    return (dist[a] - dist[x]) + (dist[b] - dist[y]) >= min_loop


def _up_to_built(v: int, pred: np.ndarray, stop: np.ndarray) -> list[int]:
    """Nodes from ``v`` up the tree to (and including) the first one where ``stop`` holds."""
    chain = [v]
    while not stop[chain[-1]]:
        u = int(pred[chain[-1]])
        if u < 0:
            return []
        chain.append(u)
    return chain


def cycle_chains(g: sparse.csr_matrix, pred: np.ndarray, dist: np.ndarray, on_built: np.ndarray,
                 min_loop: float) -> list[tuple[list[int], int, int]]:
    """Pixel chains that close the cycles a shortest-path tree cut.

    Parameters
    ----------
    g : (N, N) sparse matrix
        The skeleton graph (symmetric, edge weights = pixel distances).
    pred, dist : (N,) ndarray
        Predecessors and distances of the shortest-path forest (``scipy.sparse.csgraph.dijkstra``;
        ``pred < 0`` at roots and unreached nodes, ``dist`` infinite at unreached ones).
    on_built : (N,) int ndarray
        Index of the built branch a node lies on, -1 for nodes the pruning dropped.
    min_loop : float
        Shortest cycle closed (graph pixels): shorter loops are pixel clusters at junctions.

    Returns
    -------
    list of (nodes, first_branch, last_branch)
        ``nodes`` runs from a node of branch ``first_branch`` across the cut to a node of branch
        ``last_branch``; one entry per closed cycle (a cut the pruning left with both ends on one
        branch, or already joined by an earlier chain, gives none).

    Examples
    --------
    >>> import numpy as np
    >>> from scipy import sparse
    >>> from scipy.sparse import csgraph
    >>> ring = sparse.csr_matrix((np.ones(8), (np.arange(8), (np.arange(8) + 1) % 8)), shape=(8, 8))
    >>> ring = (ring + ring.T).tocsr()
    >>> dist, pred = csgraph.dijkstra(ring, directed=False, indices=0, return_predecessors=True)
    >>> on_built = np.array([0, 0, 0, 0, -1, -1, 1, 1])     # 4 and 5 pruned, 0-3 and 6-7 built
    >>> cycle_chains(ring, pred, dist, on_built, 6.0)
    [([3, 4, 5, 6], 0, 1)]
    """
    coo = sparse.triu(g, k=1).tocoo()
    a, b = coo.row.astype(np.int64), coo.col.astype(np.int64)
    reach = np.isfinite(dist)
    cut = reach[a] & reach[b] & (pred[a] != b) & (pred[b] != a)
    out: list[tuple[list[int], int, int]] = []
    built = on_built >= 0
    stop = built.copy()          # built branches, then also the joins added so far
    used = np.zeros(len(on_built), bool)
    # nearest cuts first: several cut edges where one cell's fronts meet give one join
    for i in np.flatnonzero(cut)[np.argsort(dist[a[cut]] + dist[b[cut]], kind="stable")]:
        u, v = int(a[i]), int(b[i])
        if used[u] or used[v] or not _loop_at_least(u, v, pred, dist, min_loop):
            continue
        cu, cv = _up_to_built(u, pred, stop), _up_to_built(v, pred, stop)
        if not cu or not cv or not (built[cu[-1]] and built[cv[-1]]):
            continue             # (a chain ending on an earlier join: that join closes this cell)
        if on_built[cu[-1]] == on_built[cv[-1]] and len(cu) + len(cv) == 2:
            continue
        nodes = cu[::-1] + cv
        out.append((nodes, int(on_built[cu[-1]]), int(on_built[cv[-1]])))
        stop[nodes[1:-1]] = True
        used[[u, v]] = True
    return out
