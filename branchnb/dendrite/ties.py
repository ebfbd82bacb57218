"""Breaking the large ties of the partial non-scalar metric.

The non-scalar planner settles nodes in order of the largest edge ``M`` on
their path and breaks ties by the cumulative cost ``S``. On a random
lattice ``M`` takes the value of one particular edge for a whole region at
once: when the flood finally crosses the cheapest edge of a barrier, every
node behind it that is connected below that level gets exactly that ``M``
(in percolation terms, the seed's cluster merges with another large one
through a single edge). Inside such a tie only ``S`` decides, so the
branches there are cumulative shortest paths: a smooth radial burst from
the barrier's gap instead of the jagged dendrite. How large the ties get is
a matter of chance (it changes with the random seed and the image size;
on 512 x 512 noise anything from a few percent to most of the lattice).

:func:`refine_ties` re-plans every tie larger than ``min_share`` of the
nodes with the non-scalar metric itself, restricted to the tie's nodes and
started from the node through which the flood entered it, and repeats on
the ties that re-planning leaves. This is the non-scalar idea applied
recursively (compare the largest edge, then the largest edge of what is
left), which converges to paths in the minimum spanning tree, the limit
the paper's partial metric approximates. Nodes outside the large ties keep
their paths; every node keeps its ``M`` (the tie's value), so the first
component stays the exact bottleneck distance.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .lattice import Lattice
from .planner import PlanResult, plan

__all__ = ["refine_ties", "tie_share"]


def tie_share(plan_result: PlanResult) -> float:
    """Largest share of the settled nodes that have one and the same ``M``.

    Parameters
    ----------
    plan_result : PlanResult
        A plan (any metric); only its settled nodes count.

    Returns
    -------
    float
        In [0, 1]; 0 for a plan that settled nothing. Close to 1/K for a plan
        without ties, large when one ``M`` value covers a big region.

    Examples
    --------
    >>> from branchnb.dendrite.lattice import make_lattice
    >>> from branchnb.dendrite.planner import plan
    >>> res = plan(make_lattice(np.zeros((10, 10)), noise=0.0, rng=0), (0, 0), metric="nonscalar")
    >>> tie_share(res)  # uniform weights: every node has the same M
    0.99
    """
    m = plan_result.max_cost[plan_result.order]
    if m.size == 0:
        return 0.0
    _, counts = np.unique(m, return_counts=True)
    return float(counts.max() / m.size)


def refine_ties(lattice: Lattice, plan_result: PlanResult, *, min_share: float = 0.02,
                max_rounds: int = 12) -> PlanResult:
    """Re-plan the large ties of a non-scalar plan (see the module docstring).

    Parameters
    ----------
    lattice : Lattice
        The lattice ``plan_result`` was planned on.
    plan_result : PlanResult
        A ``metric="nonscalar"`` plan on ``lattice``.
    min_share : float
        Ties with at least this share of the settled nodes are re-planned.
    max_rounds : int
        At most this many re-plannings.

    Returns
    -------
    PlanResult
        Same ``max_cost``; new ``parent``, ``order`` and ``total_cost`` inside
        the re-planned ties (``total_cost`` continues the entry node's).

    Examples
    --------
    >>> from branchnb.dendrite.lattice import make_lattice
    >>> lat = make_lattice(np.zeros((64, 64)), epsilon=0.5, noise=1.0, rng=0)
    >>> res = refine_ties(lat, plan(lat, (32, 32), metric="nonscalar"))
    >>> bool(tie_share(res) <= tie_share(plan(lat, (32, 32), metric="nonscalar")))
    True
    """
    if not isinstance(lattice, Lattice):
        raise TypeError(f"lattice must be a Lattice, got {type(lattice).__name__}")
    if not isinstance(plan_result, PlanResult) or plan_result.metric != "nonscalar":
        raise ValueError("refine_ties needs a non-scalar PlanResult")
    if plan_result.n_nodes != lattice.n_nodes:
        raise ValueError("plan_result does not belong to this lattice")
    parent = plan_result.parent.copy()
    total = plan_result.total_cost.copy()
    order = plan_result.order.copy()
    n = max(len(order), 1)
    # each tie to do is (its nodes in settle order); ties of the first plan first
    todo = _large_ties(plan_result.max_cost, order, min_share * n)
    rounds = 0
    while todo and rounds < max_rounds:
        group = todo.pop(0)
        rounds += 1
        entry = group[0]
        weights = np.full(lattice.n_nodes, np.inf)
        weights[group] = lattice.weights.ravel()[group]
        sub = plan(Lattice(weights.reshape(lattice.shape), lattice.factors),
                   np.array([entry % lattice.shape[1], entry // lattice.shape[1]], float)[None],
                   metric="nonscalar")
        if len(sub.order) != len(group):  # not connected within itself: leave it as it was
            continue
        inner = sub.order[1:]
        parent[inner] = sub.parent[inner]
        total[inner] = total[entry] + sub.total_cost[inner]
        # the tie's nodes are settled contiguously (same M): put them in the new order
        start = int(np.flatnonzero(order == entry)[0])
        order[start:start + len(group)] = sub.order
        todo.extend(_large_ties(sub.max_cost, sub.order, min_share * n))
    return dataclasses.replace(plan_result, parent=parent, total_cost=total, order=order)


def _large_ties(max_cost, order, min_size) -> list[np.ndarray]:
    m = max_cost[order]
    if m.size == 0:
        return []
    values, first, counts = np.unique(m, return_index=True, return_counts=True)
    big = np.flatnonzero(counts >= max(min_size, 2))
    # all nodes of one M value are settled contiguously, in order
    return [order[first[k]:first[k] + counts[k]] for k in big[np.argsort(first[big])]]
