"""Venation of the procedural leaves (Runions et al. 2005: open venation, uniform growth).

Step 3 of :mod:`branchnb.leaves.procedural`: vein nodes grown while the blade
grows about its base, subdivided as growth stretches them, and turned into
polylines whose widths follow the pipe model.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy.spatial import cKDTree

if TYPE_CHECKING:
    from .procedural import _Shape


def _grow_venation(shape: _Shape, rng: np.random.Generator, *, step: float = 0.009,
                   birth: float = 0.03, kill: float = 0.012, stages: int = 26,
                   iterations: int = 4, start: float = 0.2, max_nodes: int = 20000):
    """Vein nodes (leaf frame) and parents, grown while the blade grows about its base."""
    root = np.array([[0.0, -0.01]])
    nodes = root.copy()
    parent = np.array([-1], np.int64)
    # Primary veins along the lobe axes (the midrib for unlobed kinds),
    # present from the start and stretched by growth like everything else.
    for line in shape.primaries(rng, spacing=2.0 * step):
        first = len(nodes)
        nodes = np.vstack([nodes, line * start])
        par = np.arange(first - 1, first + len(line) - 1)
        par[0] = 0
        parent = np.concatenate([parent, par])
    # Secondaries (pinnate kinds) branch off the nearest midrib node.
    for line in shape.secondaries(rng, spacing=2.0 * step):
        first = len(nodes)
        attach = int(cKDTree(nodes).query(line[0] * start)[1])
        nodes = np.vstack([nodes, line * start])
        par = np.arange(first - 1, first + len(line) - 1)
        par[0] = attach
        parent = np.concatenate([parent, par])
    sources = np.zeros((0, 2))
    outline = shape.outline(360)
    lo, hi = outline.min(0), outline.max(0)
    prev = start
    for s in np.geomspace(start, 1.0, stages):
        # Uniform growth: everything stretches about the base.
        ratio = s / prev
        nodes = nodes * ratio
        sources = sources * ratio
        prev = s
        nodes, parent = _subdivide(nodes, parent, 2.5 * step)
        # New sources by dart throwing inside the blade at this size (none
        # on a kind without fine veins: its veins only stretch).
        if not shape.kind.get("fine", True):
            continue
        cand = rng.uniform(lo * s, hi * s, (400, 2))
        cand = cand[shape.inside_depth(cand / s) > 0.02]
        if len(cand):
            dv, _ = cKDTree(nodes).query(cand)
            cand = cand[dv > birth]
            kept = []
            tree_s = cKDTree(sources) if len(sources) else None
            for c in cand:
                if tree_s is not None and tree_s.query(c)[0] <= birth:
                    continue
                if kept and np.min(np.hypot(*(np.asarray(kept) - c).T)) <= birth:
                    continue
                kept.append(c)
            if kept:
                sources = np.vstack([sources, kept])
        for _ in range(iterations):
            if not len(sources) or len(nodes) >= max_nodes:
                break
            tree = cKDTree(nodes)
            d, idx = tree.query(sources)
            keep = d > kill
            sources, d, idx = sources[keep], d[keep], idx[keep]
            if not len(sources):
                break
            unit = (sources - nodes[idx]) / d[:, None]
            acc = np.zeros_like(nodes)
            np.add.at(acc, idx, unit)
            growing = np.unique(idx)
            g = acc[growing]
            norm = np.hypot(g[:, 0], g[:, 1])
            # Opposite sources cancel: nudge such nodes towards one of them.
            tiny = norm < 1e-6
            if tiny.any():
                g[tiny] = rng.normal(size=(int(tiny.sum()), 2))
                norm[tiny] = np.hypot(g[tiny, 0], g[tiny, 1])
            new = nodes[growing] + step * g / norm[:, None]
            nodes = np.vstack([nodes, new])
            parent = np.concatenate([parent, growing])
        if len(sources):
            d, _ = cKDTree(nodes).query(sources)
            sources = sources[d > kill]
    return nodes, parent


def _subdivide(nodes, parent, max_len):
    """Split vein segments longer than ``max_len`` (growth stretches them)."""
    while True:
        child = np.flatnonzero(parent >= 0)
        seg = nodes[child] - nodes[parent[child]]
        long = child[np.hypot(seg[:, 0], seg[:, 1]) > max_len]
        if not len(long):
            return nodes, parent
        mid = 0.5 * (nodes[long] + nodes[parent[long]])
        new_idx = np.arange(len(nodes), len(nodes) + len(long))
        nodes = np.vstack([nodes, mid])
        parent = np.concatenate([parent, parent[long]])
        parent[long] = new_idx


def _vein_polylines(nodes, parent, exponent: float = 2.5):
    """Chains between branch points with pipe-model widths (relative, tip = 1)."""
    n = len(nodes)
    children = [[] for _ in range(n)]
    for i in range(1, n):
        children[parent[i]].append(i)
    # Pipe model: w^e = sum over children; tips have w = 1. Children come
    # after their parent in ``nodes`` except after subdivision, so order by depth.
    depth = np.zeros(n, np.int64)
    order = [0]
    for i in order:
        for c in children[i]:
            depth[c] = depth[i] + 1
            order.append(c)
    flow = np.ones(n)
    for i in reversed(order):
        if children[i]:
            flow[i] = sum(flow[c] for c in children[i])
    # Flow^(1/e) so w^e adds up at branch points.
    width = flow ** (1.0 / exponent)
    lines, widths = [], []
    starts = [0]
    while starts:
        s = starts.pop()
        for c in children[s]:
            chain = [s, c]
            while len(children[chain[-1]]) == 1:
                chain.append(children[chain[-1]][0])
            if children[chain[-1]]:
                starts.append(chain[-1])
            lines.append(nodes[chain])
            widths.append(width[chain])
    return lines, widths


def _smooth_line(p):
    """One Chaikin pass (keeps the end points)."""
    if len(p) < 3:
        return p
    q = 0.75 * p[:-1] + 0.25 * p[1:]
    r = 0.25 * p[:-1] + 0.75 * p[1:]
    mid = np.empty((2 * (len(p) - 1), p.shape[1]))
    mid[0::2], mid[1::2] = q, r
    return np.vstack([p[:1], mid[1:-1], p[-1:]])
