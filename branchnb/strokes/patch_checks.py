"""Step 4 of the edit, the patches laid: which of a patch's pixels it may lay.

A patch copies a rigid square of the source. Where the target stroke is not the
source moved rigidly, or where a child leaves its parent, some of its pixels
would land where they do not belong: :class:`_AcrossCheck` drops those reached
across a bend of the source (or target) stroke, :func:`_inside_parent` finds
those over a parent's interior. Used by
:func:`~branchnb.strokes.synthesis.compose_patches`.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy.spatial import cKDTree

from .parts import rigid_frame
from .tubes import _distance_map

__all__: list[str] = []


#: A patch pixel lands at most this share of the patch radius (and 2 px) farther from or nearer
#: to its target stroke than its source pixel lies from the source stroke (see :class:`_AcrossCheck`).
_ACROSS_TOL = 0.06
#: ... judged only where its source stroke's nearest point lies more than this share of the
#: patch radius farther along (or back) than the pixel's own offset along the patch.
_BEND_TOL = 0.25
#: Turn (rad) within one patch radius past which a target stroke is a curl (see _AcrossCheck).
_CURL_TURN = 0.75


class _AcrossCheck:
    """``(origin, size, map) -> (size, size) bool``: the patch pixels that land about as far
    from the target stroke as their source pixels lie from the source stroke.

    A patch copies a rigid square of the source. Where the target stroke is not the
    source moved rigidly (lengthened, bent), pixels far along the patch that belong to
    another leg of the source stroke (the upright of an L-shaped arm seen from a patch on
    its horizontal leg) land beside the target's leg instead of on it: a lengthened
    cactus arm got a staircase of stale uprights on its inner side, each patch's a little
    farther out. Such a pixel lands much farther from (or nearer to) the target stroke than
    its source lies from the source stroke; the along-stroke error of a stretch moves
    pixels along the tube and is kept. Pixels off the source stroke's own tube (beyond
    twice the patch radius) are not judged. Beyond the paper (its patches are rigid
    copies, its strokes short).

    The same holds across a bend of the target stroke (``t0``, the sample's target arc
    length, given): on a target that curls tighter than about the patch radius
    (:data:`_CURL_TURN`), a patch pixel whose nearest target point lies much farther
    along than its offset along the patch and that lands nearer to the target stroke
    than its source pixel lies from the source stroke is folded over another turn (an
    octopus's tentacle re-stroked into a spiral: the tips knotted, outline scraps inside
    the curl) and is dropped; the patches centred nearer along the stroke cover it.
    """

    def __init__(self, index, stroke: int, pair, radii, shape):
        self.tol = max(2.0, _ACROSS_TOL * float(np.median(radii)))
        self.bend = _BEND_TOL * float(np.median(radii))
        self.s_map = index.s_map[stroke]
        self.length = float(index.strokes[stroke].length)
        reach = 2.0 * float(np.max(radii)) + 2.0

        def dist(stroke, shp):
            # distance to the stroke's polyline on a box round it (+ reach), as a full-size map
            h, w = shp
            lo = np.floor(stroke.points.min(axis=0) - reach).astype(int)
            hi = np.ceil(stroke.points.max(axis=0) + reach).astype(int) + 1
            x0, y0 = max(lo[0], 0), max(lo[1], 0)
            x1, y1 = min(hi[0], w), min(hi[1], h)
            out = np.full((h, w), np.inf, np.float32)
            if x0 >= x1 or y0 >= y1:
                return out
            canvas = np.full((y1 - y0, x1 - x0), 255, np.uint8)
            # (8 sub-pixel bits: the polyline is drawn to 1/256 px)
            line = np.rint((stroke.points - (x0, y0)) * 256.0).astype(np.int32)
            cv2.polylines(canvas, [line.reshape(-1, 1, 2)], False, 0, 1, cv2.LINE_8, 8)
            d = cv2.distanceTransform(canvas, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
            d[d > reach] = np.inf
            out[y0:y1, x0:x1] = d
            return out

        self.src = dist(pair.source, index.shape)
        self.tgt = dist(pair.target, shape)
        self.target = pair.target
        # the target-side check only where the target turns by over 0.75 rad within one
        # patch radius (a curl tighter than about 1.3 r): elsewhere no patch reaches
        # across a turn, and the result (and the cost) is the check's without it
        r = float(np.median(radii))
        grid = np.arange(0.0, pair.target.length + 0.5, 1.0)
        turn = np.unwrap(pair.target.angle_at(grid, window=2.0))
        span = max(1, int(round(r)))
        self.t_map = None
        if len(grid) > span and np.abs(turn[span:] - turn[:-span]).max() > _CURL_TURN:
            self.t_map = _distance_map(pair.target, shape, reach)[1]

    def __call__(self, origin, size: int, m: np.ndarray, centre, angle: float, s0: float,
                 t0: float | None = None) -> np.ndarray:
        x0, y0 = int(origin[0]), int(origin[1])
        yy, xx = np.mgrid[y0:y0 + size, x0:x0 + size]
        fx = m[0, 0] * xx + m[0, 1] * yy + m[0, 2]
        fy = m[1, 0] * xx + m[1, 1] * yy + m[1, 2]
        hs, ws = self.src.shape
        sx = np.clip(np.rint(fx).astype(np.intp), 0, ws - 1)
        sy = np.clip(np.rint(fy).astype(np.intp), 0, hs - 1)
        # only pixels reached across a bend of the source stroke: their nearest stroke point
        # lies much farther along (or back) than their offset along the patch's own axis
        along = (fx - centre[0]) * np.cos(angle) + (fy - centre[1]) * np.sin(angle)
        # (not beyond the stroke's ends, where the nearest point is the end itself: a tip)
        sig = self.s_map[sy, sx]
        bent = (np.abs(sig - s0 - along) > self.bend) & (sig > 0.5) & (sig < self.length - 0.5)
        ds = self.src[sy, sx]
        ht, wt = self.tgt.shape
        dt = self.tgt[np.clip(yy, 0, ht - 1), np.clip(xx, 0, wt - 1)]
        judged = bent & np.isfinite(ds) & np.isfinite(dt)
        keep = ~judged | (np.abs(dt - ds) <= self.tol)
        if t0 is None or self.t_map is None:
            return keep
        # the same across a bend of the target stroke (a tentacle re-stroked into a curl
        # tighter than its half width): a pixel whose nearest target point lies much
        # farther along (or back) than its offset along the patch, and that lands nearer
        # to the target stroke than its source pixel lies from the source stroke, is the
        # patch folded over another turn of the curl (the texture knotted at the tips);
        # the patches centred nearer along the stroke cover it. Pixels landing farther
        # out (the outside of a sharp corner) are kept: no other patch reaches them.
        # Beyond the paper.
        q = self.target.point_at(float(t0))
        a = float(self.target.angle_at(float(t0), window=3.0))
        along_t = (xx - q[0]) * np.cos(a) + (yy - q[1]) * np.sin(a)
        sig_t = self.t_map[np.clip(yy, 0, ht - 1), np.clip(xx, 0, wt - 1)]
        length_t = float(self.target.length)
        bent_t = (np.abs(sig_t - t0 - along_t) > self.bend) & (sig_t > 0.5) & (sig_t < length_t - 0.5)
        folded = bent_t & np.isfinite(ds) & np.isfinite(dt) & (dt < ds - self.tol)
        return keep & ~folded


def _patch_map(f, k: int) -> np.ndarray:
    """Target ``(x, y)`` -> source ``(x, y)`` of candidate ``k`` of ``f`` (a rotation about the sample;
    for mirror-image patches a reflection)."""
    if getattr(f, "mirror", False):
        ph = float(f.source_angles[k]) + float(f.dst_angle)
        c, s = np.cos(ph), np.sin(ph)
        (cx, cy), (dx, dy) = f.source_points[k], f.dst_point
        return np.array([[c, s, cx - c * dx - s * dy], [s, -c, cy - s * dx + c * dy]])
    th = float(f.source_angles[k]) - float(f.dst_angle)
    c, s = np.cos(th), np.sin(th)
    (cx, cy), (dx, dy) = f.source_points[k], f.dst_point
    return np.array([[c, -s, cx - c * dx + s * dy], [s, c, cy - s * dx - c * dy]])


#: Parents with at most this many segments are measured exactly in :func:`_inside_points`.
_FEW_SEGMENTS = 16


def _inside_parent(index, attached, jn, origin, size: int, cache: dict | None = None) -> np.ndarray:
    """Pixels of a ``size`` x ``size`` patch at ``origin`` inside the parent's silhouette
    (1.5 px in from its edge, the silhouette's half width at the junction): they keep
    the parent's texture, a child turned far does not lay its cut face over its parent.

    Only where the parent has flesh: the source silhouette carried by the parent's
    frame at the junction (a child added between two limbs that start at one centre,
    a starfish's sixth arm, is not held back over the empty background within the
    parent's width; that left it floating off the body). ``cache`` (a dict, one per
    edit) keeps the parent's geometry per junction: every patch near a junction
    asks the same question.
    """
    key = id(jn)
    got = None if cache is None else cache.get(key)
    if got is None:
        parent = attached[jn.parent]
        s_src = float(parent.source_arc_length(jn.parent_s))
        hw = float(index.edge_width(jn.parent, np.array([s_src]))[0])
        # where the child leaves along the parent's normal, the width across is the child's
        hw = min(hw, index.side_width.get((jn.child, jn.end, jn.parent), np.inf) + 1.0)
        # the parent's target stroke, densely sampled (0.25 px: distances exact to 0.01 px)
        st = parent.target
        pts = st.points if st.length < 1e-9 else \
            np.stack([np.interp(np.linspace(0.0, st.length, int(np.ceil(st.length / 0.25)) + 1), st.s,
                                st.points[:, c]) for c in (0, 1)], axis=1)
        fwd = rigid_frame(parent.source, parent.target, s_src, float(jn.parent_s), window=3.0)
        # a parent of a few segments (a starfish's disk, a figure's body): exact distances to
        # its segments, cheaper than the tree's nearest sample
        near = st.points if len(st.points) <= _FEW_SEGMENTS + 1 and st.length >= 1e-9 else cKDTree(pts)
        got = (near, hw, fwd, pts.min(axis=0), pts.max(axis=0))
        if cache is not None:
            cache[key] = got
    tree, hw, fwd, lo, hi = got[:5]
    reach = hw - 1.5
    if reach < 0 or (np.asarray(origin) + size < lo - reach).any() or (np.asarray(origin) > hi + reach).any():
        return np.zeros((size, size), bool)  # the patch's square is nowhere near the parent
    if cache is None:
        yy, xx = np.mgrid[0:size, 0:size]
        q = np.c_[xx.ravel() + origin[0], yy.ravel() + origin[1]].astype(float)
        return _inside_points(index, tree, reach, fwd, q).reshape(size, size)
    if len(got) == 5:
        # a map of the pixels that can be within reach of the parent, filled as patches ask
        # (they overlap: each pixel is computed once per junction, not once per patch)
        x0, y0 = (np.floor(lo - reach) - 1).astype(int)
        x1, y1 = (np.ceil(hi + reach) + 2).astype(int)
        got = cache[key] = (*got, (x0, y0), np.zeros((y1 - y0, x1 - x0), bool),
                            np.zeros((y1 - y0, x1 - x0), bool))
    (x0, y0), box, done = got[5], got[6], got[7]
    out = np.zeros((size, size), bool)
    ox, oy = int(origin[0]), int(origin[1])
    a0, a1 = max(oy, y0), min(oy + size, y0 + box.shape[0])
    b0, b1 = max(ox, x0), min(ox + size, x0 + box.shape[1])
    if a0 < a1 and b0 < b1:
        sub = (slice(a0 - y0, a1 - y0), slice(b0 - x0, b1 - x0))
        todo = ~done[sub]
        if todo.any():
            ty, tx = np.nonzero(todo)
            q = np.c_[tx + b0, ty + a0].astype(float)
            box[sub][ty, tx] = _inside_points(index, tree, reach, fwd, q)
            done[sub] = True
        out[a0 - oy:a1 - oy, b0 - ox:b1 - ox] = box[sub]
    return out


def _inside_points(index, tree, reach: float, fwd: np.ndarray, q: np.ndarray) -> np.ndarray:
    """:func:`_inside_parent` at the pixels ``q`` ((N, 2) ``(x, y)``); ``tree`` is a KD-tree
    of the parent's densely sampled stroke or its (few) vertices."""
    if isinstance(tree, np.ndarray):
        d = np.full(len(q), np.inf)
        for a, b in zip(tree[:-1], tree[1:]):
            ab = b - a
            n2 = float(ab @ ab)
            t = np.clip(((q - a) @ ab) / n2, 0.0, 1.0) if n2 > 0 else np.zeros(len(q))
            np.minimum(d, np.hypot(q[:, 0] - a[0] - t * ab[0], q[:, 1] - a[1] - t * ab[1]), out=d)
    else:
        d, _ = tree.query(q, distance_upper_bound=reach + 1e-9)
    inside = d <= reach
    if inside.any():
        src = (q[inside] - fwd[:, 2]) @ fwd[:, :2]  # the inverse rigid map, row-wise
        x, y = np.rint(src).astype(int).T
        hs, ws = index.shape
        ok = (x >= 0) & (x < ws) & (y >= 0) & (y < hs)
        flesh = np.zeros(len(x), bool)
        flesh[ok] = index.object[y[ok], x[ok]]
        inside[np.flatnonzero(inside)[~flesh]] = False
    return inside
