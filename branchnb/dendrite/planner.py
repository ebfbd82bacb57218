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
    large ``a`` approaches the non-scalar one.

Relaxation replaces a node's label only when the new key is strictly
smaller. The non-scalar key is the whole label and the cumulative metric is
isotone, so their results do not depend on how exact key ties are broken;
the blend key ``a * M + S`` does not determine ``(M, S)`` and is not
isotone, so with exact key ties (e.g. small integer weights) its tree
depends on which tied path is settled first. With real-valued random
weights such ties practically never occur. The hot loop is a numba-compiled indexed binary heap (decrease-key)
over flat arrays with precomputed neighbour offsets; the lattice version
computes edge costs on the fly (:mod:`.lattice`), the sparse version walks
a CSR matrix.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np
import scipy.sparse as sp

from ..core.io import encode_png
from ..core.validate import Array, Int, Real, checked
from .lattice import OFFSETS, Lattice

__all__ = ["METRICS", "PlanResult", "metric_code", "plan"]

METRICS = ("cumulative", "nonscalar", "blend")
_CUMULATIVE, _NONSCALAR, _BLEND = 0, 1, 2


def metric_code(metric: str) -> int:
    """Validate a metric name; return its integer code."""
    if metric not in METRICS:
        raise ValueError(f"metric must be one of {list(METRICS)}, got {metric!r}")
    return METRICS.index(metric)


# ------------------------------------------------------------------ queue
# The priority queue is exact but two-level (a bucket queue in front of a
# heap). Keys are pairs (key1, key2) compared lexicographically, and Dijkstra
# pops them in non-decreasing order, so a node whose key1 falls in a later
# key1 interval ("bucket") just sits, unsorted, in that bucket's linked
# list (O(1) insert, appended to a pool in creation order); only the current
# bucket lives in a small 4-ary heap. The bucket index int((key1 - lo) *
# inv) is a non-decreasing function of key1, so every heap entry is smaller
# than every bucket entry and the pop order is exactly that of a plain heap
# Dijkstra. Keys beyond the bucket range go to an overflow list that is
# re-bucketed over its own key range when reached. Superseded entries are
# skipped lazily (no decrease-key); when the heap or the entry pool fills
# up it is compacted in place, so no array is reallocated inside the loop.
# This matters for the non-scalar metric, whose frontier holds most of the
# graph at once: a single heap over it would be ~18 levels deep. For that
# metric, entries whose key1 equals the current level (the key1 of the node
# just settled: the flood inside one basin) go to a second, single-key heap
# ordered by key2 alone; a pop takes the smaller top of the two heaps.
#
# State: hk/hn heap keys (interleaved k1, k2) and nodes, n its size;
# ek/en/enext the pool of bucket entries (keys, node or -1 once consumed,
# next entry of the same bucket), ne its size; head[b] the first entry of
# bucket b (head[nb] = overflow); cur the current bucket.
_ARITY = 4


@numba.njit(cache=True, inline="always")
def _keys(metric, a, m, s):
    """The comparison key (key1, key2) of the label (m, s) = (max edge, total)."""
    if metric == 0:
        return s, 0.0
    if metric == 1:
        return m, s
    return a * m + s, 0.0


@numba.njit(cache=True, inline="always")
def _live(k1, k2, v, metric, a, mmax, total, done):
    """Is a queue entry (k1, k2, v) still current (v unsettled, key unchanged)?"""
    if done[v]:
        return False
    c1, c2 = _keys(metric, a, mmax[v], total[v])
    return k1 == c1 and k2 == c2


@numba.njit(cache=True)
def _hpush(hk, hn, n, k1, k2, v):
    i = n
    while i > 0:
        p = (i - 1) // _ARITY
        p1 = hk[2 * p]
        if k1 < p1 or (k1 == p1 and k2 < hk[2 * p + 1]):
            hk[2 * i] = p1
            hk[2 * i + 1] = hk[2 * p + 1]
            hn[i] = hn[p]
            i = p
        else:
            break
    hk[2 * i] = k1
    hk[2 * i + 1] = k2
    hn[i] = v
    return n + 1


@numba.njit(cache=True)
def _sift_down(hk, hn, i, n):
    lk1 = hk[2 * i]
    lk2 = hk[2 * i + 1]
    ln = hn[i]
    while True:
        c0 = _ARITY * i + 1
        if c0 >= n:
            break
        c = c0
        b1 = hk[2 * c]
        b2 = hk[2 * c + 1]
        cend = min(c0 + _ARITY, n)
        for j in range(c0 + 1, cend):
            x1 = hk[2 * j]
            if x1 < b1 or (x1 == b1 and hk[2 * j + 1] < b2):
                c = j
                b1 = x1
                b2 = hk[2 * j + 1]
        if b1 < lk1 or (b1 == lk1 and b2 < lk2):
            hk[2 * i] = b1
            hk[2 * i + 1] = b2
            hn[i] = hn[c]
            i = c
        else:
            break
    hk[2 * i] = lk1
    hk[2 * i + 1] = lk2
    hn[i] = ln


@numba.njit(cache=True)
def _hpop(hk, hn, n):
    n -= 1
    if n > 0:
        hk[0] = hk[2 * n]
        hk[1] = hk[2 * n + 1]
        hn[0] = hn[n]
        _sift_down(hk, hn, 0, n)
    return n


@numba.njit(cache=True)
def _hpush_room(hk, hn, n, k1, k2, v, metric, a, mmax, total, done):
    """Push, compacting the heap first if it is full (drops superseded entries;
    at most one live entry per unsettled node remains, so it always fits)."""
    if n >= hn.shape[0]:
        m = 0
        for i in range(n):
            u = hn[i]
            if _live(hk[2 * i], hk[2 * i + 1], u, metric, a, mmax, total, done):
                hk[2 * m] = hk[2 * i]
                hk[2 * m + 1] = hk[2 * i + 1]
                hn[m] = u
                m += 1
        n = m
        for i in range((n - 2) // _ARITY, -1, -1):
            _sift_down(hk, hn, i, n)
    return _hpush(hk, hn, n, k1, k2, v)


@numba.njit(cache=True)
def _hpush1(hk, hn, n, k, v):
    i = n
    while i > 0:
        p = (i - 1) // _ARITY
        if k < hk[p]:
            hk[i] = hk[p]
            hn[i] = hn[p]
            i = p
        else:
            break
    hk[i] = k
    hn[i] = v
    return n + 1


@numba.njit(cache=True)
def _hpop1(hk, hn, n):
    n -= 1
    if n > 0:
        lk = hk[n]
        ln = hn[n]
        i = 0
        while True:
            c0 = _ARITY * i + 1
            if c0 >= n:
                break
            c = c0
            b = hk[c]
            for j in range(c0 + 1, min(c0 + _ARITY, n)):
                if hk[j] < b:
                    c = j
                    b = hk[j]
            if b < lk:
                hk[i] = b
                hn[i] = hn[c]
                i = c
            else:
                break
        hk[i] = lk
        hn[i] = ln
    return n


@numba.njit(cache=True)
def _hpush1_room(hk, hn, n, k, v, level, metric, a, mmax, total, done):
    """Push onto the level heap (entries (level, k)); compact it first if full."""
    if n >= hn.shape[0]:
        m = 0
        for i in range(n):
            u = hn[i]
            if _live(level, hk[i], u, metric, a, mmax, total, done):
                hk[m] = hk[i]
                hn[m] = u
                m += 1
        n = 0
        for i in range(m):  # rebuild (entries are few after compaction)
            n = _hpush1(hk, hn, n, hk[i], hn[i])
    return _hpush1(hk, hn, n, k, v)


@numba.njit(cache=True)
def _compact_pool(ek, en, enext, head, ne, lo, inv, metric, a, mmax, total, done):
    """Drop consumed and superseded bucket entries and relink the buckets.

    At most one live entry per unsettled node remains, so the pool (of
    capacity >= number of nodes) always has room afterwards."""
    nb = head.shape[0] - 1
    head[:] = -1
    m = 0
    for k in range(ne):
        v = en[k]
        if v >= 0 and _live(ek[2 * k], ek[2 * k + 1], v, metric, a, mmax, total, done):
            ek[2 * m] = ek[2 * k]
            ek[2 * m + 1] = ek[2 * k + 1]
            en[m] = v
            x = (ek[2 * m] - lo) * inv
            b = int(x) if x < nb else nb
            enext[m] = head[b]
            head[b] = m
            m += 1
    return m


@numba.njit(cache=True)
def _advance(hk, hn, ek, en, enext, head, cur, lo, inv, metric, a, mmax, total, done):
    """Refill the empty heap from the next non-empty bucket.

    Returns ``(n, cur, lo, inv)``; ``n == 0`` means the queue is empty.
    """
    nb = head.shape[0] - 1
    n = 0
    while n == 0:
        cur += 1
        while cur < nb and head[cur] < 0:
            cur += 1
        if cur >= nb:
            j = head[nb]
            if j < 0:
                return 0, nb, lo, inv
            # re-bucket the overflow list over its own key range
            head[nb] = -1
            lo = np.inf
            hi = -np.inf
            k = j
            while k >= 0:
                v = en[k]
                if _live(ek[2 * k], ek[2 * k + 1], v, metric, a, mmax, total, done):
                    lo = min(lo, ek[2 * k])
                    hi = max(hi, ek[2 * k])
                k = enext[k]
            inv = nb / (hi - lo) if hi > lo else 0.0
            k = j
            while k >= 0:
                nxt = enext[k]
                v = en[k]
                if _live(ek[2 * k], ek[2 * k + 1], v, metric, a, mmax, total, done):
                    b = int((ek[2 * k] - lo) * inv)
                    if b >= nb:
                        b = nb - 1
                    enext[k] = head[b]
                    head[b] = k
                else:
                    en[k] = -1
                k = nxt
            cur = -1
            continue
        k = head[cur]
        head[cur] = -1
        while k >= 0:
            v = en[k]
            if _live(ek[2 * k], ek[2 * k + 1], v, metric, a, mmax, total, done):
                n = _hpush_room(hk, hn, n, ek[2 * k], ek[2 * k + 1], v, metric, a, mmax, total, done)
            en[k] = -1
            k = enext[k]
    return n, cur, lo, inv




@numba.njit(cache=True)
def _start(n_nodes, seeds, mmax, total, parent, n_buckets):
    # int32 node indices in the queue halve its memory traffic
    cap = n_nodes + 16
    hk = np.empty(2 * cap)
    hn = np.empty(cap, np.int32)
    lk = np.empty(cap)  # the level heap (non-scalar metric): entries (level, total)
    ln = np.empty(cap, np.int32)
    cap = 2 * n_nodes + 16  # room for superseded entries before a compaction
    ek = np.empty(2 * cap)
    en = np.empty(cap, np.int32)
    enext = np.empty(cap, np.int32)
    head = np.full(n_buckets + 1, -1, np.int32)
    done = np.zeros(n_nodes, np.bool_)
    n = 0
    for s in seeds:
        if total[s] != 0.0:
            mmax[s] = 0.0
            total[s] = 0.0
            parent[s] = -1
            n = _hpush(hk, hn, n, 0.0, 0.0, s)
    return hk, hn, lk, ln, ek, en, enext, head, done, n


@numba.njit(cache=True)
def _count_stops(stop_at):
    c = 0
    for i in range(stop_at.shape[0]):
        if stop_at[i]:
            c += 1
    return c


# ------------------------------------------------------------------- kernels
# The lattice and CSR kernels repeat the same queue loop on purpose: moving
# the pop and the relaxation into shared numba helpers (inlined or not) made
# the planner three to four times slower on a 512 x 512 lattice.
@numba.njit(cache=True)
def _dijkstra_lattice(w, height, width, drow, dcol, factor, seeds, metric, a,
                      mmax, total, parent, order, stop_at, key_hint, n_buckets):
    hk, hn, lk, ln, ek, en, enext, head, done, n = _start(
        height * width, seeds, mmax, total, parent, n_buckets)
    ne = 0
    nl = 0
    level = 0.0
    cur = 0
    lo = 0.0
    inv = n_buckets / key_hint
    remaining = _count_stops(stop_at)
    count = 0
    while True:
        if n == 0 and nl == 0:
            n, cur, lo, inv = _advance(hk, hn, ek, en, enext, head, cur, lo, inv,
                                       metric, a, mmax, total, done)
            if n == 0:
                break
        if nl > 0 and (n == 0 or level < hk[0] or (level == hk[0] and lk[0] < hk[1])):
            u = ln[0]
            nl = _hpop1(lk, ln, nl)
            if done[u]:
                continue
        else:
            u = hn[0]
            k1u = hk[0]
            n = _hpop(hk, hn, n)
            if done[u]:
                continue
            level = k1u
        done[u] = True
        order[count] = u
        count += 1
        if stop_at[u]:
            remaining -= 1
            if remaining == 0:
                break
        r = u // width
        c = u - r * width
        wu = w[u]
        mu = mmax[u]
        su = total[u]
        for k in range(8):
            rr = r + drow[k]
            cc = c + dcol[k]
            if rr < 0 or rr >= height or cc < 0 or cc >= width:
                continue
            v = rr * width + cc
            if done[v]:
                continue
            wv = w[v]
            if not wv < np.inf:
                continue
            e = 0.5 * (wu + wv) * factor[k]
            m = max(mu, e)
            s = su + e
            nk1, nk2 = _keys(metric, a, m, s)
            o1, o2 = _keys(metric, a, mmax[v], total[v])
            if nk1 < o1 or (nk1 == o1 and nk2 < o2):
                mmax[v] = m
                total[v] = s
                parent[v] = u
                x = (nk1 - lo) * inv
                if metric == 1 and nk1 == level:
                    nl = _hpush1_room(lk, ln, nl, nk2, v, level, metric, a, mmax, total, done)
                elif x < cur + 1:
                    n = _hpush_room(hk, hn, n, nk1, nk2, v, metric, a, mmax, total, done)
                else:
                    if ne >= en.shape[0]:
                        ne = _compact_pool(ek, en, enext, head, ne, lo, inv, metric, a, mmax,
                                          total, done)
                    b = int(x) if x < n_buckets else n_buckets
                    ek[2 * ne] = nk1
                    ek[2 * ne + 1] = nk2
                    en[ne] = v
                    enext[ne] = head[b]
                    head[b] = ne
                    ne += 1
    return count


@numba.njit(cache=True)
def _dijkstra_csr(indptr, indices, data, seeds, metric, a,
                  mmax, total, parent, order, stop_at, key_hint, n_buckets):
    hk, hn, lk, ln, ek, en, enext, head, done, n = _start(
        indptr.shape[0] - 1, seeds, mmax, total, parent, n_buckets)
    ne = 0
    nl = 0
    level = 0.0
    cur = 0
    lo = 0.0
    inv = n_buckets / key_hint
    remaining = _count_stops(stop_at)
    count = 0
    while True:
        if n == 0 and nl == 0:
            n, cur, lo, inv = _advance(hk, hn, ek, en, enext, head, cur, lo, inv,
                                       metric, a, mmax, total, done)
            if n == 0:
                break
        if nl > 0 and (n == 0 or level < hk[0] or (level == hk[0] and lk[0] < hk[1])):
            u = ln[0]
            nl = _hpop1(lk, ln, nl)
            if done[u]:
                continue
        else:
            u = hn[0]
            k1u = hk[0]
            n = _hpop(hk, hn, n)
            if done[u]:
                continue
            level = k1u
        done[u] = True
        order[count] = u
        count += 1
        if stop_at[u]:
            remaining -= 1
            if remaining == 0:
                break
        mu = mmax[u]
        su = total[u]
        for jj in range(indptr[u], indptr[u + 1]):
            v = indices[jj]
            if done[v]:
                continue
            e = data[jj]
            if not e < np.inf:
                continue
            m = max(mu, e)
            s = su + e
            nk1, nk2 = _keys(metric, a, m, s)
            o1, o2 = _keys(metric, a, mmax[v], total[v])
            if nk1 < o1 or (nk1 == o1 and nk2 < o2):
                mmax[v] = m
                total[v] = s
                parent[v] = u
                x = (nk1 - lo) * inv
                if metric == 1 and nk1 == level:
                    nl = _hpush1_room(lk, ln, nl, nk2, v, level, metric, a, mmax, total, done)
                elif x < cur + 1:
                    n = _hpush_room(hk, hn, n, nk1, nk2, v, metric, a, mmax, total, done)
                else:
                    if ne >= en.shape[0]:
                        ne = _compact_pool(ek, en, enext, head, ne, lo, inv, metric, a, mmax,
                                          total, done)
                    b = int(x) if x < n_buckets else n_buckets
                    ek[2 * ne] = nk1
                    ek[2 * ne + 1] = nk2
                    en[ne] = v
                    enext[ne] = head[b]
                    head[b] = ne
                    ne += 1
    return count


# -------------------------------------------------------------------- result
@dataclass
class PlanResult:
    """What the planner returns; every array has one entry per graph node.

    Attributes
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
        """Nodes from the seed set to ``node`` (inclusive), following ``parent``."""
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
        """Reshape a per-node array to the lattice ``(H, W)``."""
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


def _bucket_range(graph, code: int, a: float, n_nodes: int) -> tuple[int, float]:
    """Number of buckets and the expected key1 range of the queue (a hint only:
    keys beyond it go to the overflow list, so any value gives exact results)."""
    if isinstance(graph, Lattice):
        w = graph.weights
        fin = w[np.isfinite(w)]
        e_max = float(fin.max()) * float(graph.factors.max()) if fin.size else 1.0
        e_mean = float(fin.mean()) * float(graph.factors.mean()) if fin.size else 1.0
        span = float(sum(graph.shape))
    else:
        d = graph.data[np.isfinite(graph.data)]
        e_max = float(d.max()) if d.size else 1.0
        e_mean = float(d.mean()) if d.size else 1.0
        span = 2.0 * np.sqrt(max(n_nodes, 1))
    s_hint = e_mean * span
    hint = {0: s_hint, 1: e_max, 2: a * e_max + s_hint}[code]
    if not np.isfinite(hint) or hint <= 0:
        hint = 1.0
    return int(np.clip(n_nodes // 4, 16, 1 << 16)), float(hint)


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
    n_buckets, key_hint = _bucket_range(graph, code, float(blend_weight), n_nodes)
    # Unreached nodes must compare as +inf under every metric: M starts at 0
    # (not inf) for the scalar metrics so that a * M + S is inf, not NaN, at a = 0.
    mmax = np.full(n_nodes, np.inf if code == _NONSCALAR else 0.0)
    total = np.full(n_nodes, np.inf)
    parent = np.full(n_nodes, -1, np.int64)
    order = np.empty(n_nodes, np.int64)
    if isinstance(graph, Lattice):
        h, w = graph.shape
        count = _dijkstra_lattice(graph.weights.ravel(), h, w, OFFSETS[:, 0].copy(),
                                  OFFSETS[:, 1].copy(), graph.factors, nodes, code,
                                  float(blend_weight), mmax, total, parent, order, stop,
                                  key_hint, n_buckets)
        shape = (h, w)
    else:
        count = _dijkstra_csr(graph.indptr.astype(np.int64), graph.indices.astype(np.int64),
                              graph.data, nodes, code, float(blend_weight),
                              mmax, total, parent, order, stop, key_hint, n_buckets)
        shape = None
    order = order[:count].copy()
    if count < n_nodes:  # nodes left in the heap keep tentative labels: report them unreached
        settled = np.zeros(n_nodes, bool)
        settled[order] = True
        mmax[~settled] = np.inf
        total[~settled] = np.inf
        parent[~settled] = -1
    return PlanResult(metric, float(blend_weight), mmax, total, parent, order, nodes, shape)
