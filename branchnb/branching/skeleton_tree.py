"""Automatic extraction, step 3 (beyond the paper): the skeleton graph as a tree of branches.

The skeleton's pixels are a graph; each connected piece becomes a tree by
the shortest-path tree from a root end point (main branch = the longest
path, side branches hang off it), thickness from a radius map.

Split from :mod:`.extraction` (which re-exports every name); where each piece is rooted (frame
entries, delta outlets, end radii) is in :mod:`.skeleton_roots` (issue 23, branching103), whose
names are re-exported here.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi
from scipy import sparse
from scipy.sparse import csgraph

from ..core.polyline import arc_length, polyline_length, resample_uniform
from ..core.structure import Branch, Structure
from .delta_source import _delta_source_key, _fan_root
from .frame_trunks import frame_trunks
from .path_smoothing import NOISE_PX, keep_corners_smooth
from .skeleton_roots import (  # noqa: F401  (re-exported: split from this module)
    ENTRY_FRAME,
    ENTRY_RADII,
    ENTRY_RATIO,
    ENTRY_SHARE,
    INSIDE_FADE,
    INSIDE_FROM,
    INSIDE_SPAN,
    OUTLET_COAST,
    OUTLET_EVEN,
    OUTLET_FRAME,
    OUTLET_INNER,
    OUTLET_INNER_MARGIN,
    OUTLET_MARGIN,
    SMALL_FRAME,
    SMALL_LEAD,
    SMALL_TIE,
    SMALL_VOTES,
    TRUNK_EXTRA,
    TRUNK_HELD_RATIO,
    _end_radius,
    _even_ends,
    _frame_entries,
    _frame_outlet,
    _frame_trunk_end,
    _held_radius,
    _inside_radius,
    _junction_trunk_arms,
    _mouth_node,
    _one_per_line,
    _region_outlet,
    _small_frame_entry,
    _small_frame_key,
    _small_frame_lead,
    _walk_arm,
)
from .small_frames import SMALL_SIDE

__all__ = [
    "skeleton_to_structure",
]


_OFFSETS = ((0, 1), (1, -1), (1, 0), (1, 1))


def _skeleton_graph(skel: np.ndarray):
    ys, xs = np.nonzero(skel)
    n = len(ys)
    index = -np.ones(skel.shape, np.int64)
    index[ys, xs] = np.arange(n)
    rows, cols, w = [], [], []
    h, wd = skel.shape
    for dy, dx in _OFFSETS:
        y2, x2 = ys + dy, xs + dx
        ok = (y2 >= 0) & (y2 < h) & (x2 >= 0) & (x2 < wd)
        j = np.full(n, -1)
        j[ok] = index[y2[ok], x2[ok]]
        ok = j >= 0
        rows.append(np.flatnonzero(ok))
        cols.append(j[ok])
        w.append(np.full(ok.sum(), np.hypot(dy, dx)))
    r, c, ww = np.concatenate(rows), np.concatenate(cols), np.concatenate(w)
    g = sparse.coo_matrix((ww, (r, c)), shape=(n, n)).tocsr()
    return (g + g.T).tocsr(), ys, xs


def _add_joins(g, ys, xs, node_r, shape, joins):
    """The skeleton graph with a chain of extra nodes (about one pixel apart) for every join.

    The chain's nodes sit on the straight line between the two pixels but are connected only to each
    other, so a join through a crossing does not touch the stroke passing over it. Their radius is
    the strokes' own: the median over about 30 skeleton pixels from each end (the radius right at an
    end is pinched by the line's cut), the smaller of the two (a T-join's target is the thicker
    stem)."""
    from scipy import sparse as sp

    def stroke_r(i: int, n_max: int = 30) -> float:
        seen, todo = {i}, [i]
        while todo and len(seen) < n_max:
            v = todo.pop(0)
            for u in g.indices[g.indptr[v]:g.indptr[v + 1]]:
                if int(u) not in seen:
                    seen.add(int(u))
                    todo.append(int(u))
        return float(np.median(node_r[list(seen)]))

    index = -np.ones(shape, np.int64)
    index[ys, xs] = np.arange(len(ys))
    n = len(ys)
    new_y, new_x, new_r, rows, cols, w = [], [], [], [], [], []
    for (y0, x0), (y1, x1), _through in joins:
        i0, i1 = int(index[y0, x0]), int(index[y1, x1])
        if i0 < 0 or i1 < 0 or i0 == i1:
            continue
        d = float(np.hypot(y1 - y0, x1 - x0))
        m = max(int(np.ceil(d)) - 1, 0)
        t = np.linspace(0.0, 1.0, m + 2)[1:-1]
        chain = [i0] + list(range(n, n + m)) + [i1]
        new_y += list(np.rint(y0 + t * (y1 - y0)).astype(np.int64))
        new_x += list(np.rint(x0 + t * (x1 - x0)).astype(np.int64))
        new_r += [min(stroke_r(i0), stroke_r(i1))] * m
        n += m
        rows += chain[:-1]
        cols += chain[1:]
        w += [d / (m + 1)] * (m + 1)
    if not rows:
        return g, ys, xs, node_r
    big = sp.csr_matrix((g.data, g.indices, g.indptr), shape=(len(g.indptr) - 1, len(g.indptr) - 1))
    big.resize((n, n))
    extra = sp.coo_matrix((w, (rows, cols)), shape=(n, n)).tocsr()
    return ((big + extra + extra.T).tocsr(), np.r_[ys, np.asarray(new_y, np.int64)],
            np.r_[xs, np.asarray(new_x, np.int64)], np.r_[node_r, np.asarray(new_r, np.float64)])


def skeleton_to_structure(skeleton, radius, *, h: float = 4.0, min_branch_length: float = 12.0,
                          min_component_length: float = 60.0, root="thickest",
                          scale: float = 1.0, smooth: float = 4.0,
                          smooth_radius: float = 8.0, image_shape=None, region=None,
                          spur_factor: float = 2.0, joins=None, close_cycles: float = 0.0,
                          hubs=None, shore=None) -> Structure:
    """Convert a one-pixel skeleton into a tree of branches.

    Each connected piece becomes one tree: a root end point is chosen
    (``root``), the shortest-path tree from it is computed (cycles, e.g.
    in crack networks, are cut where the two fronts meet), the main branch
    follows the longest path and every other subtree hanging off a branch
    becomes a child branch (recursively). Subtrees shorter than
    ``min_branch_length`` are pruned (skeleton spurs).

    Parameters
    ----------
    skeleton : (H, W) bool array_like
        One-pixel-wide centre lines (8-connected), at the working scale.
    radius : (H, W) array_like
        Branch radius at each pixel (e.g. the distance transform).
    h : float, default 4.0
        Resampling step h of the result (full-size pixels).
    min_branch_length, min_component_length : float, default 12.0, 60.0
        Pruning thresholds in pixels of the *output* (full-size) image. A
        piece that reaches the image frame (within 4 px) is kept from half
        ``min_component_length``: the frame cut it (a crop's rivers that
        enter from its frame), beyond the paper.
    root : {"auto", "thickest", "top", "bottom", "left", "right", "border", "nearest_region"} or (x, y)
        Root end point per piece: ``"auto"`` takes the end nearest to
        ``region`` when there is one and the piece's lines all have about one
        width (its 75th radius percentile under 1.5 x the 25th, or at most
        a pixel above it: a drawn map's rivers drain where they meet the sea;
        a node of the piece more than 4 px nearer than every end, a mouth the
        coast's removed outline left as a loop, beats the ends; among several
        ends at the sea, the one its forks point to, ``_region_outlet``; when they point to an
        end inland instead, a delta's source, that end, ``delta_source.fan_source``), else the centre of
        every hub in the piece (``hubs``: a neuron grows out of its soma), else the thickest end (a
        vessel tree's trunk, a delta's inland channel; the radius near an end,
        not at it, which the frame or a rounded tip pinches), every end where a thick line
        enters the frame (``_frame_entries``), or, on a piece of one width that meets the
        frame, the frame end its forks point to (``_frame_outlet``: a line map's river cut by
        the frame drains there, beyond the paper); or the thickest, the top-most ..., the one
        nearest to the image border, the one nearest to ``region`` (e.g.
        the sea a river flows into; the border if there is none; a piece
        that meets the region, or the border, at several mouths and fans out
        from an end away from them, a delta, roots at that end, see
        ``_delta_source_key``),
        or the one nearest to a given point (full-size pixels). Default
        ``"thickest"``.
    scale : float, default 1.0
        The skeleton is a ``scale`` x downscaled copy; coordinates and
        radii are divided by it.
    smooth : float, default 4.0
        Gaussian smoothing (full-size pixels of arc length) of each pixel
        path before resampling; removes the staircase of the pixel grid,
        whose noise would otherwise dominate the turning angles.
    smooth_radius : float, default 8.0
        Gaussian smoothing of the radius along each branch (full-size
        pixels of arc length): the distance transform bumps at every
        junction and blob, which the synthesis would otherwise copy.
    image_shape : (H, W), optional
        Stored on the result (full-size).
    region : (H, W) bool array_like, optional
        At the skeleton's scale: the region ``root="nearest_region"`` looks for.
    spur_factor : float, default 2.0
        A side subtree is also pruned when it is shorter than this times the
        radius where it leaves its parent (the skeleton's spurs at the bends of
        wide channels are about one radius long).
    joins : sequence of ((y0, x0), (y1, x1), through), optional
        Skeleton pixels to connect by a straight piece of centre line, as
        found by :func:`~branchnb.branching.stroke_joins.find_stroke_joins`
        (drawn strokes broken at junctions and crossings). The piece touches
        no other pixel: a join through a crossing passes under the stroke
        it crosses.
    close_cycles : float, default 0.0
        Beyond the paper: close again every cycle of the skeleton at least
        this long (full-size pixels of loop) that the shortest-path tree cut,
        by a *join* branch: a child of the branch on one side of the cut that
        follows the skeleton across it and ends on a vertex of the branch on
        the other side (``branchnb.branching.skeleton_cycles``), so a
        crack network's cells stay closed. 0 = off (every cycle stays cut).
    hubs : sequence of (y, x), optional
        Skeleton pixels at the centres of hubs, blobs much wider than the lines
        that leave them (a soma, a crater; :func:`~branchnb.branching.hubs.find_hubs`).
        With ``root="auto"`` a piece holding hubs is rooted at them (each hub a
        tree; the piece split where their shortest paths meet), unless it is a
        line map's piece that drains into ``region`` (beyond the paper).
    shore : (H, W) bool array_like, optional
        A coast whose drawn line was taken out of the skeleton (an engraved
        map's hatched sea): a piece reaching within 4 px of it is kept from
        half ``min_component_length``, as one cut by the frame (the river ran
        on into the removed coast line), beyond the paper. None: no such coast.

    Returns
    -------
    Structure
        One tree per kept piece, with ``image_shape`` set.

    Examples
    --------
    >>> import numpy as np
    >>> sk = np.zeros((40, 80), bool); sk[20, 5:75] = True; sk[21:36, 40] = True
    >>> s = skeleton_to_structure(sk, np.full(sk.shape, 2.0), min_component_length=20)
    >>> len(s.branches), s.branches[1].parent
    (2, 0)
    >>> sk[21:24, 40] = False      # the side branch stops 3 px short of the main one
    >>> joined = skeleton_to_structure(sk, np.full(sk.shape, 2.0), min_component_length=20,
    ...                                joins=[((24, 40), (20, 40), False)])
    >>> len(joined.branches), joined.branches[1].parent
    (2, 0)
    >>> ring = np.zeros((60, 60), bool); ring[10, 10:50] = ring[49, 10:50] = True
    >>> ring[10:50, 10] = ring[10:50, 49] = True                       # one closed square cell
    >>> s = skeleton_to_structure(ring, np.full(ring.shape, 1.5), close_cycles=40.0)
    >>> img = s.render((60, 60))[..., 0] < 0.5
    >>> from scipy import ndimage as ndi
    >>> int(ndi.label(~img)[1])                                        # inside and outside
    2
    """
    sk = np.asarray(skeleton).astype(bool)
    rad = np.asarray(radius, np.float64)
    if sk.ndim != 2 or rad.shape != sk.shape:
        raise ValueError("skeleton must be 2-D and radius must have the same shape")
    if not h > 0:
        raise ValueError(f"h must be > 0, got {h}")
    out = Structure([], image_shape=tuple(image_shape) if image_shape is not None else None)
    if not sk.any():
        return out
    g, ys, xs = _skeleton_graph(sk)
    node_r = rad[ys, xs]
    if joins:
        g, ys, xs, node_r = _add_joins(g, ys, xs, node_r, sk.shape, joins)
    n_comp, comp = csgraph.connected_components(g, directed=False)
    deg = np.diff(g.indptr)
    pts_full = np.column_stack([xs, ys]).astype(np.float64) / scale
    r_full = np.maximum(node_r / scale, 0.5)
    # Component lengths (sum of spanning edges ~ number of pixels).
    comp_len = np.bincount(comp, minlength=n_comp) / scale
    hh, ww = sk.shape
    yy_, xx_ = np.mgrid[0:hh, 0:ww]
    border_dist = np.minimum(np.minimum(yy_, hh - 1 - yy_), np.minimum(xx_, ww - 1 - xx_)).astype(np.float64)
    region_dist = border_dist
    has_region = False
    if isinstance(root, str) and root in ("nearest_region", "auto") and region is not None:
        reg = np.asarray(region, bool)
        if reg.shape != sk.shape:
            raise ValueError(f"region must have the skeleton's shape {sk.shape}, got {reg.shape}")
        if reg.any():
            region_dist = ndi.distance_transform_edt(~reg)
            has_region = True
    # a piece cut by the frame (it reaches within 4 px of it) is kept from half the length: the rest
    # of the line is outside the image (a crop's rivers entering from its frame)
    comp_frame = np.full(n_comp, np.inf)
    np.minimum.at(comp_frame, comp, border_dist[ys, xs])
    if shore is not None:
        sh = np.asarray(shore, bool)
        if sh.shape != sk.shape:
            raise ValueError(f"shore must have the skeleton's shape {sk.shape}, got {sh.shape}")
        if sh.any():
            # a river that met the removed coast line: its mouth is where the piece was cut (beyond the paper)
            np.minimum.at(comp_frame, comp, ndi.distance_transform_edt(~sh)[ys, xs])
    min_len = np.where(comp_frame <= 4.0 * scale, 0.5 * min_component_length, min_component_length)
    # small examples (issue 23): see _small_frame_key
    small = max(hh, ww) / scale <= SMALL_SIDE
    roots = []
    hub_nodes = np.zeros(0, np.int64)
    if hubs:
        hub_yx = np.asarray(hubs, np.float64).reshape(-1, 2)
        if not (np.all(np.isfinite(hub_yx)) and np.all(hub_yx >= 0) and np.all(hub_yx < sk.shape)):
            raise ValueError(f"hubs must be (y, x) pixels of the skeleton's shape {sk.shape}")
        where = -np.ones(sk.shape, np.int64)
        where[ys, xs] = np.arange(len(ys))
        hub_nodes = np.asarray([where[int(y), int(x)] for y, x in hub_yx], np.int64)
        hub_nodes = hub_nodes[hub_nodes >= 0]
    # the frame side each node is nearest to (0 left, 1 top, 2 right, 3 bottom; see _one_per_line)
    node_side = np.argmin(np.stack([xs, ys, ww - 1 - xs, hh - 1 - ys], 1), 1)
    for c in np.flatnonzero(comp_len >= min_len):
        members = np.flatnonzero(comp == c)
        ends = members[deg[members] == 1]
        cand = ends if len(ends) else members
        own_hubs = hub_nodes[comp[hub_nodes] == c]
        if isinstance(root, str):
            if root == "auto":
                lo, hi = np.percentile(r_full[members], [25, 75])
                # one width: within 1.5 x, or within a pixel (the radius of a 1-2 px drawn line comes
                # in half-pixel steps, 0.5 vs 0.9, which says nothing about where it drains); 0.5 vs 1.5
                # too when the piece reaches the region (a paper map's 2-px rivers meeting its coast; a
                # fundus's vessels, ending inside its matte, keep their thickest end)
                one_width = hi < 1.5 * lo or hi - lo < 1.0 or (
                    has_region and hi - lo <= 1.0 and float(region_dist[ys[cand], xs[cand]].min()) / scale
                    <= OUTLET_FRAME + 2.0 * float(np.median(r_full[members])) + OUTLET_COAST)
                if one_width and has_region and _frame_trunk_end(
                        pts_full, r_full, ends, members, border_dist[ys[ends], xs[ends]] / scale, hi):
                    one_width = False
                if has_region and one_width:
                    key = region_dist[ys[cand], xs[cand]]
                    cand, key = _mouth_node(cand, key, members, region_dist[ys[members], xs[members]], scale)
                    if len(cand) > 1 and (mouth := _region_outlet(g, deg, cand, members, pts_full, r_full,
                                                                   key / scale)) is not None:
                        roots.append(mouth)
                        continue
                    # forks pointing inland at several mouths: a delta, rooted where it fans out from
                    # (its ends' widths too alike to tell, issue 23, branching83)
                    if (src := _fan_root(g, deg, cand, members, pts_full, r_full, key / scale)) is not None:
                        roots.append(src)
                        continue
                if len(own_hubs):
                    # lines radiating from a blob much wider than they are grow out of it (a neuron's
                    # soma, a crater): rooted at a line's tip, the learnt model grew from the wrong place
                    roots.extend(int(v) for v in own_hubs)
                    continue
                if not (has_region and one_width):
                    key = -_end_radius(pts_full, r_full, cand, members)
                    # (on lines of about one width, a thick end must stay thick: see _frame_entries)
                    even = hi <= 1.5 * lo or hi - lo <= 1.0
                    entries = _frame_entries(cand, -key, border_dist[ys[cand], xs[cand]] / scale,
                                             pts_full, float(np.median(r_full[members])),
                                             r_full if even else None, members if even else None,
                                             0.0 if small else ENTRY_RADII)
                    entries = _one_per_line(entries, g, r_full, -key[np.isin(cand, entries)].min()
                                            if entries else 0.0, node_side)
                    # trunks entering less than twice as thick as the piece's median line (a river
                    # network from the bottom edge: 1.5-1.8 x), each rooting its own tree (.frame_trunks);
                    # beside a full-thickness entry, those entering by its side of the frame
                    # (not on lines of about one width: there a thick end at the frame is where two lines
                    # meet it in a V, and a crossing network from the bottom was rooted at the top frame)
                    trunks = [] if even else frame_trunks(g, deg, cand, members, pts_full, r_full,
                                                          border_dist[ys[cand], xs[cand]] / scale, -key,
                                                          node_side)
                    if entries:
                        trunks = [t for t in trunks if node_side[t] in {int(node_side[e]) for e in entries}
                                  and all(np.hypot(*(pts_full[t] - pts_full[e])) > 4.0 * r_full[e]
                                          for e in entries)]
                    if entries or trunks:
                        roots.extend(entries + trunks)
                        continue
                    # lines of one width (within a pixel: 1 and 2 px lines), no end much thicker than the
                    # others (a drawn root system's trunks among its thin roots; an end is as thick as the
                    # line stays near it, not as the V where two lines meet at the frame), that meet the
                    # frame drain there
                    if small and (lead := _small_frame_entry(g, deg, cand, members, pts_full, r_full,
                                                             border_dist[ys[cand], xs[cand]] / scale)) is not None:
                        roots.append(lead)
                        continue
                    if small and (lead := _small_frame_lead(-key, border_dist[ys[cand], xs[cand]] / scale, pts_full,
                                                            r_full, cand, members)) is not None:
                        roots.append(lead)
                        continue
                    if (hi <= 1.5 * lo or hi - lo <= 1.0) and len(ends) and \
                            _even_ends(-key, pts_full, r_full, cand, members) and (outlet := _frame_outlet(
                            g, deg, cand, members, pts_full, r_full, border_dist[ys[cand], xs[cand]] / scale)) \
                            is not None:
                        roots.append(outlet)
                        continue
                    # larger examples too: a line of one width entering at the frame whose few forks
                    # do not agree (a 512 px map of 2-px black rivers: 2 of 4 forks for the outlet) was
                    # rooted at a blob of overlapping lines inside (_small_frame_entry)
                    if not small and (lead := _small_frame_entry(g, deg, cand, members, pts_full, r_full,
                                                                 border_dist[ys[cand], xs[cand]] / scale)) \
                            is not None:
                        roots.append(lead)
                        continue
                    if small:
                        key = _small_frame_key(key, border_dist[ys[cand], xs[cand]] / scale)
            elif root == "thickest":
                key = -_end_radius(pts_full, r_full, cand, members)
            elif root == "top":
                key = pts_full[cand, 1]
            elif root == "bottom":
                key = -pts_full[cand, 1]
            elif root == "left":
                key = pts_full[cand, 0]
            elif root == "right":
                key = -pts_full[cand, 0]
            elif root in ("border", "nearest_region"):
                key = region_dist[ys[cand], xs[cand]] if root == "nearest_region" else \
                    border_dist[ys[cand], xs[cand]]
                if root == "nearest_region":
                    key = _delta_source_key(key, pts_full, r_full, cand, members, scale, g, deg, has_region)
            else:
                raise ValueError("root must be auto/thickest/top/bottom/left/right/border/nearest_region "
                                 f"or (x, y), got {root!r}")
        else:
            q = np.asarray(root, np.float64).reshape(2)
            key = np.hypot(*(pts_full[cand] - q).T)
        roots.append(int(cand[np.argmin(key)]))
    if not roots:
        return out
    dist, pred, _ = csgraph.dijkstra(g, directed=False, indices=roots, return_predecessors=True,
                                     min_only=True)
    reach = np.isfinite(dist)
    order = np.argsort(dist)
    order = order[reach[order]]
    children: dict[int, list[int]] = {}
    height = np.zeros(len(ys))
    for v in order[::-1]:
        pv = pred[v]
        if pv >= 0:
            children.setdefault(int(pv), []).append(int(v))
            hv = height[v] + np.hypot(ys[v] - ys[pv], xs[v] - xs[pv])
            height[pv] = max(height[pv], hv)
    min_len_px = min_branch_length * scale
    # Decompose: (start node, parent branch, index of start node on the parent path)
    stack = [(r, None, None) for r in roots]
    paths: list[tuple[list[int], int | None, int | None]] = []
    while stack:
        start, par, pvx = stack.pop()
        path = [start]
        v = start
        while v in children:
            kids = children[v]
            best = max(kids, key=lambda u: height[u])
            path.append(best)
            v = best
        bi = len(paths)
        paths.append((path, par, pvx))
        for i, node in enumerate(path):
            for u in children.get(node, ()):
                if i + 1 < len(path) and u == path[i + 1]:
                    continue
                sub = height[u] + np.hypot(ys[u] - ys[node], xs[u] - xs[node])
                if sub >= max(min_len_px, spur_factor * node_r[node]):
                    stack.append((u, bi, i))
    # Build branches in creation order; children prepend their furcation node.
    new_index: dict[int, int] = {}
    built: list[Branch] = []
    attach: dict[int, list[int]] = {}
    for _path, par, pvx in paths:
        if par is not None:
            attach.setdefault(par, []).append(pvx)
    for bi, (path, par, pvx) in enumerate(paths):
        nodes = path if par is None else [paths[par][0][pvx]] + path
        pts = pts_full[nodes]
        r = r_full[nodes]
        if par is not None and par not in new_index:
            continue
        first = 0
        if par is not None and len(nodes) > 2:
            # The distance transform near the junction measures the parent:
            # use the child's own radius from one parent radius onwards.
            arc = arc_length(pts)
            inside = arc < r[0] + 1.0
            if inside.all():
                inside[-1] = False
            first = int(np.argmin(inside))
            r = r.copy()
            r[:first] = r[first]
        if len(pts) >= 3 and smooth * scale > _NO_BLUR:
            # within a junction's disk the skeleton bends from one line's centre to another's: no corner
            calm = np.zeros(len(pts), bool)
            calm[:first] = True
            if attach.get(bi):
                arc = arc_length(pts)
                for k in attach[bi]:
                    k += par is not None   # a child's points start with its furcation node
                    calm |= np.abs(arc - arc[k]) < r[k] + 1.0
            pts = _smooth_pixels(pts, smooth * scale, NOISE_PX / scale, calm=calm)
        if len(r) >= 3 and smooth_radius * scale > _NO_BLUR:
            r = _median_then_gauss(r, smooth_radius * scale)
        length = polyline_length(pts)
        if length < max(h, 1e-9) or (par is None and length < min_branch_length):
            continue
        rp, rr = resample_uniform(pts, h, values=r, include_end=True)
        if len(rp) < 2:
            continue
        if par is None:
            built.append(Branch(rp, np.maximum(rr, 0.5)))
        else:
            parent_b = built[new_index[par]]
            anchor = pts[0]
            v = int(np.argmin(np.hypot(*(parent_b.points - anchor).T)))
            rp[0] = parent_b.points[v]
            built.append(Branch(rp, np.maximum(rr, 0.5), new_index[par], v))
        new_index[bi] = len(built) - 1
    if close_cycles > 0 and built:
        built += _cycle_joins(g, pred, dist, paths, new_index, built, pts_full, r_full,
                              close_cycles * scale, h, scale * smooth, scale * smooth_radius,
                              NOISE_PX / scale)
    return Structure(built, image_shape=out.image_shape)


def _cycle_joins(g, pred, dist, paths, new_index, built, pts_full, r_full, min_loop, h, smooth,
                 smooth_radius, noise) -> list[Branch]:
    """Join branches closing the cycles the tree cut (see ``close_cycles`` and :mod:`.skeleton_cycles`)."""
    from .skeleton_cycles import cycle_chains

    on_built = np.full(len(pts_full), -1, np.int64)
    for bi, (path, _par, _pvx) in enumerate(paths):
        if bi in new_index:
            on_built[path] = new_index[bi]
    out = []
    for nodes, b0, b1 in cycle_chains(g, pred, dist, on_built, min_loop):
        pts, r = pts_full[nodes], r_full[nodes]
        if len(pts) >= 3 and smooth > _NO_BLUR:
            pts = _smooth_pixels(pts, smooth, noise)
        # the radius of the lines it joins (the distance transform swells where they meet)
        rr = float(np.median(r))
        rp = resample_uniform(pts, h, include_end=True) if polyline_length(pts) >= h else pts[[0, -1]]
        rp = np.array(rp, np.float64)
        first, last = built[b0].points, built[b1].points
        v = int(np.argmin(np.hypot(*(first - rp[0]).T)))
        rp[0] = first[v]
        rp[-1] = last[int(np.argmin(np.hypot(*(last - rp[-1]).T)))]
        if len(rp) < 2 or np.allclose(rp[0], rp[-1]):
            continue
        out.append(Branch(rp, np.full(len(rp), max(rr, 0.5)), b0, v))
    return out


#: Gaussian sigmas (pixels) below this are no smoothing (scipy divides by a vanishing sigma).
_NO_BLUR = 1e-3


def _smooth_pixels(pts: np.ndarray, sigma: float, noise: float, calm=None) -> np.ndarray:
    """A pixel path smoothed over ``sigma`` samples, its ends kept (corners too when
    :data:`.path_smoothing.KEEP_CORNERS`, except at its ``calm`` samples)."""
    from . import path_smoothing

    if path_smoothing.KEEP_CORNERS:
        return keep_corners_smooth(pts, sigma, noise=noise, calm=calm)
    sm = ndi.gaussian_filter1d(pts, sigma, axis=0, mode="nearest")
    sm[0], sm[-1] = pts[0], pts[-1]
    return sm


def _median_then_gauss(r: np.ndarray, sigma: float) -> np.ndarray:
    k = max(3, round(sigma) | 1)
    return ndi.gaussian_filter1d(ndi.median_filter(r, size=k, mode="nearest"), sigma, mode="nearest")
