"""Joint bodies: the parent's flesh at a junction stays with the parent.

Beyond the paper (whose children keep their source angle at junctions):
when a child stroke is turned about its root, its patches near the root
were fetched along the child's *source* tube, which also covers part of
the parent's body there (a starfish's disk, a lizard's hip). Turned, the
child takes that piece of the body away and leaves a notch, a wedge as
wide as the turn, in the parent.

The body at a junction is the largest disk of the source silhouette
centred on the junction (its radius the source depth there, the distance
to the background): every pixel of it belongs to the parent, whatever
the child does. :func:`hold_joint_bodies` lays that disk, carried
rigidly by the parent's frame at the junction, *under* the composed
layer, so it fills only what the edit left (partly) transparent.
:func:`close_hairlines` then closes the thin partly transparent lines
left where two anti-aliased edges meet inside the object near a joint.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from .parts import rigid_frame

__all__ = ["joint_disks", "joint_roots", "hold_joint_bodies", "close_hairlines"]

#: A child's root tube is at most this many times the child's median half width (see :func:`joint_roots`).
_ROOT_WIDTH = 1.25


def _straight(premult: np.ndarray) -> np.ndarray:
    out = premult.copy()
    a = out[..., 3:4]
    out[..., :3] = np.where(a > 1e-6, np.clip(out[..., :3] / np.maximum(a, 1e-6), 0, 1), 0)
    return out


def joint_disks(index, attached, junctions, window: float) -> list[tuple[np.ndarray, np.ndarray, float]]:
    """The body disk of every junction: ``(target centre, 2 x 3 target->source map, radius)``.

    Parameters
    ----------
    index : SourceIndex
        The source index (its ``depth``: the source silhouette's distance map).
    attached : list of StrokePair
        The stroke pairs (targets attached to their parents).
    junctions : list of Junction
        Junctions among the targets.
    window : float
        Half length (px) of the chords the parent's direction is taken from.

    Returns
    -------
    list of tuple
        One entry per junction with a disk of radius >= 2 px.

    Examples
    --------
    >>> joint_disks(None, [], [], 5.0)
    []
    """
    out = []
    h, w = index.shape if index is not None else (0, 0)
    for jn in junctions:
        par = attached[jn.parent]
        s_src = float(par.source_arc_length(jn.parent_s))
        ps = par.source.point_at(s_src)
        x, y = np.rint(ps).astype(int)
        if not (0 <= x < w and 0 <= y < h):
            continue
        r = float(index.depth[y, x]) - 0.5
        if r < 2.0:
            continue
        fwd = rigid_frame(par.source, par.target, s_src, float(jn.parent_s), window=window)
        rot = fwd[:, :2]
        inv = np.hstack([rot.T, (-rot.T @ fwd[:, 2])[:, None]])
        # clipped to the parent's own width there (not past its silhouette's sides)
        hw = float(index.edge_width(jn.parent, np.array([s_src]))[0])
        out.append((fwd @ np.append(ps, 1.0), inv, r, par.target, hw))
    return out


def joint_roots(index, attached, junctions, window: float) -> list[tuple]:
    """The root of every child at a junction, as bodies to hold: the child's own tube
    from the junction to where it leaves its parent (and half its width on).

    A child turned about its root (a limb raised) has its cut face turned with it;
    between the face and the parent's side a wedge of the child's tube was nobody's
    (the parent's patches stop at the parent's silhouette, the child's near its
    root keep the parent's interior): an enclosed notch, outlined like a hole. The
    root tube, carried rigidly by the child's frame where it leaves the parent, is
    laid under the layer like the joint bodies (:func:`hold_joint_bodies`), so it
    fills only what the edit left open. Beyond the paper.

    Parameters
    ----------
    index : SourceIndex
        The source index.
    attached : list of StrokePair
        The stroke pairs (targets attached to their parents).
    junctions : list of Junction
        Junctions among the targets.
    window : float
        Half length (px) of the chords the child's direction is taken from.

    Returns
    -------
    list of tuple
        ``(centre, 2 x 3 target->source map, radius, clip stroke, clip half width,
        source map, the parent's target->source map)`` for
        :func:`hold_joint_bodies`: the disk round the junction that reaches the
        exit, clipped to the child's target tube (its half width at the exit less
        1 px: the edges stay as synthesized).

    Examples
    --------
    >>> joint_roots(None, [], [], 5.0)
    []
    """
    from .strokes import Stroke

    out = []
    for jn in junctions:
        pair, par = attached[jn.child], attached[jn.parent]
        child = pair.source
        if child.length < 2.0:
            continue
        t = np.arange(0.0, child.length, 1.0)
        s_c = t if jn.end == 0 else child.length - t
        s_par, d = par.source.project(child.point_at(s_c))
        away = np.flatnonzero(d > index.edge_width(jn.parent, s_par) + 1.0)
        if not len(away):
            continue
        s_exit = float(s_c[away[0]])
        sign = 1.0 if jn.end == 0 else -1.0
        probe = np.clip(s_exit + sign * np.array([1.0, 2.0, 3.0]), 0.0, child.length)
        hw = float(index.edge_width(jn.child, probe).min())
        # at most a little over the child's typical width: where siblings leave one point (a
        # delta's channels) the silhouette across a child's root spans its neighbours, and a
        # root tube that wide filled the V between a turned channel and the next with the
        # neighbour's old root (a sawtooth of stale flesh)
        typical = float(np.median(index.edge_width(jn.child, np.linspace(0.0, child.length, 33))))
        hw = min(hw, _ROOT_WIDTH * typical) - 1.0
        if hw < 1.5:
            continue
        s_exit_t = float(np.interp(s_exit, pair.control[:, 0], pair.control[:, 1]))
        end_t = 0.0 if jn.end == 0 else pair.target.length
        reach_t = abs(s_exit_t - end_t) + hw
        fwd = rigid_frame(child, pair.target, s_exit, s_exit_t, window=window)
        rot = fwd[:, :2]
        inv = np.hstack([rot.T, (-rot.T @ fwd[:, 2])[:, None]])
        a, b = sorted((end_t, float(np.clip(end_t + sign * reach_t, 0.0, pair.target.length))))
        if b - a < 1.0:
            continue
        tgt = pair.target
        mid = (tgt.s > a) & (tgt.s < b)  # the target's own vertices between a and b
        clip = Stroke(np.vstack([tgt.point_at(a)[None], tgt.points[mid], tgt.point_at(b)[None]]))
        centre = pair.target.point_at(end_t)

        u = child.point_at(s_exit + sign) - child.point_at(s_exit)
        u = u / max(float(np.hypot(*u)), 1e-9)  # the child's source direction, away from the parent

        def own(sx, sy, parent=par.source, k=jn.parent, u=u):
            # only the child's own flesh (outside the parent's silhouette in the source):
            # a limb raised far must not pull flaps of its parent's body out along it;
            # a pixel whose source lies in the parent takes the child's texture a little
            # farther along the child instead
            sx, sy = sx.copy(), sy.copy()
            ok = np.zeros(len(sx), bool)
            for _ in range(4):
                s_p, d_p = parent.project(np.c_[sx, sy])
                short = index.edge_width(k, s_p) + 1.0 - d_p
                ok = short <= 0.5
                if ok.all():
                    break
                sx[~ok] += u[0] * short[~ok]
                sy[~ok] += u[1] * short[~ok]
            # and solid flesh there (not the child's anti-aliased edge or the background)
            h, w = index.shape
            x, y = np.rint(sx).astype(int), np.rint(sy).astype(int)
            inb = (x >= 0) & (x < w) & (y >= 0) & (y < h)
            ok &= inb
            ok[inb] &= index.premult[y[inb], x[inb], 3] >= 0.98
            return sx, sy, ok

        # behind the junction only over the parent's flesh: across it lies its far side
        pf = rigid_frame(par.source, par.target, float(par.source_arc_length(jn.parent_s)), float(jn.parent_s),
                         window=3.0)
        behind = np.hstack([pf[:, :2].T, (-pf[:, :2].T @ pf[:, 2])[:, None]])
        out.append((centre, inv, reach_t + hw, clip, hw, own, behind))
    return out


def hold_joint_bodies(layer: np.ndarray, source_premult: np.ndarray, source_depth: np.ndarray,
                      disks, depth: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Lay every joint's body disk (the parent's source pixels) under ``layer``.

    Parameters
    ----------
    layer : (H, W, 4) float32 ndarray
        The composed object, straight alpha.
    source_premult : (Hs, Ws, 4) ndarray
        The source image, premultiplied alpha.
    source_depth : (Hs, Ws) ndarray
        The source silhouette's depth (distance to the background).
    disks : list of tuple
        From :func:`joint_disks` or :func:`joint_roots`: ``(centre, map, radius)``,
        optionally a clip stroke and half width (target side: the pixels within
        the half width of the stroke), a map of the source coordinates
        ``(sx, sy) -> (sx, sy, usable)`` (source side) and the parent's 2 x 3
        target -> source map: behind the clip stroke's start only the pixels
        it maps into the source's flesh (``source_depth > 0``) are filled.
    depth : (H, W) ndarray, optional
        Source depth of every target pixel; updated in place where a
        disk fills a pixel that had alpha < 0.5.

    Returns
    -------
    layer : (H, W, 4) float32 ndarray
        ``layer`` over the disks (a new array; ``layer`` itself if no disk).
    held : (H, W) bool ndarray
        Pixels that were transparent (alpha < 0.5) and are opaque now.

    Examples
    --------
    >>> src = np.ones((9, 9, 4), np.float32)
    >>> out, held = hold_joint_bodies(np.zeros((9, 9, 4), np.float32), src, np.full((9, 9), 4.0),
    ...                               [(np.array([4.0, 4.0]), np.array([[1.0, 0, 0], [0, 1.0, 0]]), 3.0)])
    >>> int(held.sum()), float(out[4, 4, 3])
    (29, 1.0)
    """
    h, w = layer.shape[:2]
    held = np.zeros((h, w), bool)
    if not disks:
        return layer, held
    # premultiplied on the disks' boxes only (the rest is not looked at), in a copy of
    # the box round all the disks (pm, done and changed are that box's; yy, xx the image's)
    boxes = []
    for centre, _inv, r, *_clip in disks:
        cx, cy = centre
        boxes.append((max(int(np.floor(cy - r)), 0), min(int(np.ceil(cy + r)) + 1, h),
                      max(int(np.floor(cx - r)), 0), min(int(np.ceil(cx + r)) + 1, w)))
    R0, R1 = min(b[0] for b in boxes), max(b[1] for b in boxes)
    C0, C1 = min(b[2] for b in boxes), max(b[3] for b in boxes)
    if R0 >= R1 or C0 >= C1:
        return np.array(layer, np.float32, copy=True), held
    pm = np.array(layer[R0:R1, C0:C1], np.float32, copy=True)
    done = np.zeros(pm.shape[:2], bool)
    changed = np.zeros(pm.shape[:2], bool)
    for (centre, inv, r, *clip), (r0, r1, c0, c1) in zip(disks, boxes):
        cx, cy = centre
        if r0 >= r1 or c0 >= c1:
            continue
        lb = (slice(r0 - R0, r1 - R0), slice(c0 - C0, c1 - C0))
        todo = ~done[lb]
        if todo.any():
            win = pm[lb]
            win[todo, :3] *= win[todo, 3:4]
            done[lb] = True
        yy, xx = np.mgrid[r0:r1, c0:c1]
        # only pixels the edit left (partly) open are filled: the others are not looked at
        inside = (np.hypot(xx - cx, yy - cy) <= r) & (pm[lb][..., 3] < 0.5)
        if not inside.any():
            continue
        if clip:
            # within the half width of the clip stroke, and behind its start only over the
            # parent's flesh (a thin child whose smoothed width is its blade's, a petiole,
            # left a stub on its twig's far edge; a new branch a knob on its trunk's)
            q = np.c_[xx[inside], yy[inside]].astype(float)
            s, d = clip[0].project(q)
            keep = d <= clip[1]
            back = keep & (s <= 0) & (d > 0.5)
            if len(clip) > 3 and back.any():
                # behind the start: only where the parent's frame finds its source's flesh
                px, py = np.rint(q[back] @ clip[3][:, :2].T + clip[3][:, 2]).astype(int).T
                hs, ws = source_depth.shape
                ok = (px >= 0) & (px < ws) & (py >= 0) & (py < hs)
                ok[ok] = source_depth[py[ok], px[ok]] > 0
                keep[np.flatnonzero(back)[~ok]] = False
            inside[inside] = keep
        yy, xx = yy[inside], xx[inside]
        sx = inv[0, 0] * xx + inv[0, 1] * yy + inv[0, 2]
        sy = inv[1, 0] * xx + inv[1, 1] * yy + inv[1, 2]
        if len(clip) > 2 and len(xx):
            sx, sy, ok = clip[2](sx, sy)  # the source side: the child's own flesh only
            yy, xx, sx, sy = yy[ok], xx[ok], sx[ok], sy[ok]
        under = np.stack([ndi.map_coordinates(source_premult[..., c], [sy, sx], order=1, mode="nearest")
                          for c in range(4)], axis=1)
        ly, lx = yy - R0, xx - C0
        top = pm[ly, lx]
        # only where the edit left the body (partly) open: the parent's own edges,
        # as synthesized, stay as they are
        was = top[:, 3] < 0.5
        pm[ly[was], lx[was]] = top[was] + under[was] * (1.0 - top[was, 3:4])
        changed[ly[was], lx[was]] = True
        now = pm[ly, lx, 3] >= 0.5
        held[yy[was & now], xx[was & now]] = True
        if depth is not None and (was & now).any():
            depth[yy[was & now], xx[was & now]] = ndi.map_coordinates(
                source_depth, [sy[was & now], sx[was & now]], order=1, mode="nearest")
    # back to straight alpha where the disks filled (elsewhere the layer as it was)
    out = np.array(layer, np.float32, copy=True)
    out[R0:R1, C0:C1][changed] = _straight(pm[changed])
    return out, held


def close_hairlines(layer: np.ndarray, zones, *, reach: int = 2,
                    keep_open: np.ndarray | None = None) -> np.ndarray:
    """Close thin, partly transparent lines inside the object near the joints.

    Two anti-aliased edges meeting inside the object (a turned arm's edge
    along a kept arm's) leave a line of pixels with alpha < 1 between
    opaque pixels. A pixel with alpha < 0.9 that has opaque pixels within
    ``reach`` px on both sides along one of four directions is made
    opaque with its nearest opaque pixel's colour. Only pixels within the
    ``zones`` (``(centre, radius)`` discs) are touched.

    Parameters
    ----------
    layer : (H, W, 4) float32 ndarray
        Straight alpha RGBA.
    zones : list of ((2,) ndarray, float)
        Centres ``(x, y)`` and radii of the discs to work in.
    reach : int
        How far (px) to look for the opaque sides.
    keep_open : (H, W) bool ndarray, optional
        Pixels left as they are: the source's own slits carried onto the result (a turned
        petal's notch, see :func:`~branchnb.strokes.slits._carried_slits`).

    Returns
    -------
    (H, W, 4) float32 ndarray
        A new layer (``layer`` itself if nothing changed).

    Examples
    --------
    >>> lay = np.ones((5, 7, 4), np.float32)
    >>> lay[:, 3, 3] = 0.4
    >>> float(close_hairlines(lay, [(np.array([3.0, 2.0]), 5.0)])[2, 3, 3])
    1.0
    """
    h, w = layer.shape[:2]
    out = layer
    for (cx, cy), r in zones:
        # each zone on its own box (grown by ``reach``, for the sides)
        g = int(np.ceil(r)) + reach + 1
        r0, r1 = max(int(cy) - g, 0), min(int(cy) + g + 1, h)
        c0, c1 = max(int(cx) - g, 0), min(int(cx) + g + 1, w)
        if r0 >= r1 or c0 >= c1:
            continue
        win = out[r0:r1, c0:c1]
        hit = _hairline(win[..., 3], reach)
        yy, xx = np.mgrid[r0:r1, c0:c1]
        hit &= (xx - cx) ** 2 + (yy - cy) ** 2 <= r * r
        if keep_open is not None:
            hit &= ~keep_open[r0:r1, c0:c1]
        if not hit.any():
            continue
        _, (iy, ix) = ndi.distance_transform_edt(win[..., 3] < 0.98, return_indices=True)
        if out is layer:
            out = layer.copy()
        win = out[r0:r1, c0:c1]
        win[hit, :3] = win[iy[hit], ix[hit], :3]
        win[hit, 3] = 1.0
    return out


def _hairline(a: np.ndarray, reach: int) -> np.ndarray:
    """Pixels with alpha < 0.9 that have opaque pixels within ``reach`` px on both sides
    along one of four directions (a pixel of a smooth edge has its neighbours along
    the edge about as open as itself)."""
    h, w = a.shape
    opaque = a >= 0.98
    pad = np.pad(opaque, reach)
    hit = np.zeros((h, w), bool)
    for dy, dx in ((0, 1), (1, 0), (1, 1), (1, -1)):
        lo = np.zeros((h, w), bool)
        hi = np.zeros((h, w), bool)
        for k in range(1, reach + 1):
            lo |= pad[reach - k * dy:reach - k * dy + h, reach - k * dx:reach - k * dx + w]
            hi |= pad[reach + k * dy:reach + k * dy + h, reach + k * dx:reach + k * dx + w]
        hit |= lo & hi
    return hit & (a < 0.9)


def _vacated_roots(index, pairs, window: float) -> list[tuple[int, int, float]]:
    """``(child, parent, s)``: source strokes whose root on a parent's source stroke
    (at arc length ``s`` of it) is left by their target, where the parent's target
    stays put (a pinna used only as a copy source elsewhere)."""
    out = []
    for c, pc in enumerate(pairs):
        for end in (0, -1):
            q = pc.source.points[end]
            # a root only (the end cut where the child meets its parent), not a free tip
            if not index.cut_ends[c][end] or np.hypot(*(pc.target.points[end] - q)) <= window:
                continue
            hw_c = float(index.half_width(c, 0.0 if end == 0 else pc.source.length))
            for p, pp in enumerate(pairs):
                if p == c:
                    continue
                s, d = pp.source.project(q[None])
                s, d = float(s[0]), float(d[0])
                if not 0.0 < s < pp.source.length or d > float(index.half_width(p, s)) + 2.0:
                    continue
                # the parent's target keeps its place there, and no other target stroke
                # comes to the root (the root's place is left empty, not re-used)
                if np.hypot(*(pp.target.point_at(s) - pp.source.point_at(s))) > 1.0:
                    continue
                near = [o for o, po in enumerate(pairs) if o != p
                        and float(po.target.project(q[None])[1][0]) < hw_c + 2.0]
                if not near:
                    out.append((c, p, s, end))
    return out


def _refill_vacated_roots(layer: np.ndarray, index, pairs, window: float, outline: float) -> np.ndarray:
    """Make the parent's tube whole where a child's root was and its target left.

    The parent's tube in the source gives the child's root pixels to the child,
    so when the child is only copied elsewhere nothing lays the parent's side
    there and the cut face's outline bites into the parent. Those pixels are
    copied from the parent's own source a little farther along its centre line
    (flesh and outline; both ways averaged where both are clear of other
    children, so a tapering parent keeps its width): along the child's root on
    its side, and over the child's round root cap on the far side. Beyond the
    paper, which only ever draws the strokes' tubes.
    """
    out = layer
    h, w = layer.shape[:2]
    for c, p, s, end in _vacated_roots(index, pairs, window):
        pp, pc = pairs[p], pairs[c]
        q = pc.source.points[end]
        hw_c = float(index.half_width(c, 0.0 if end == 0 else pc.source.length))
        hw_p = float(index.half_width(p, s))
        rad = hw_c + 3.0 * outline + 3.0
        nrm = pp.source.normal_at(s, window=window)
        side = np.sign(float(np.dot(pc.source.point_at(min(hw_c + hw_p, pc.source.length) if end == 0
                                                        else max(pc.source.length - hw_c - hw_p, 0.0))
                                    - pp.source.point_at(s), nrm))) or 1.0
        x0, x1 = int(max(q[0] - rad - hw_p, 0)), int(min(q[0] + rad + hw_p + 1, w))
        y0, y1 = int(max(q[1] - rad - hw_p, 0)), int(min(q[1] + rad + hw_p + 1, h))
        yy, xx = np.mgrid[y0:y1, x0:x1].astype(float)
        ps = pp.source.point_at(s)
        along = np.abs((xx - ps[0]) * nrm[1] - (yy - ps[1]) * nrm[0])
        off = ((xx - ps[0]) * nrm[0] + (yy - ps[1]) * nrm[1]) * side
        # the child's side along its root, and on the far side what its round root cap
        # pushed out past the parent's other edge
        zone = (np.abs(off) <= hw_p + 2.0 * outline + 2.0) & (
            ((along <= rad) & (off > 0)) | (np.hypot(xx - q[0], yy - q[1]) <= hw_c + 2.0 * outline + 2.0))
        # each pixel as (arc length, signed distance) on the parent's source stroke
        pix = np.c_[xx.ravel(), yy.ravel()]
        sx_s, _ = pp.source.project(pix)
        foot = pp.source.point_at(sx_s)
        sx_d = ((pix - foot) * pp.source.normal_at(sx_s, window=window)).sum(axis=1)
        got = []
        for step in (rad + hw_c + outline, -(rad + hw_c + outline)):
            s2 = s + step
            if not 0.0 <= s2 <= pp.source.length:
                continue
            # along the parent's own centre line (a polyline's corner inside the zone
            # bends a rigid copy off by a pixel or two at the zone's ends)
            s3 = np.clip(sx_s + step, 0.0, pp.source.length)
            base = pp.source.point_at(s3)
            n3 = pp.source.normal_at(s3, window=window)
            sx = (base[:, 0] + sx_d * n3[:, 0]).reshape(xx.shape).astype(np.float32)
            sy = (base[:, 1] + sx_d * n3[:, 1]).reshape(xx.shape).astype(np.float32)
            # bilinear: a half-pixel jog at the zone's ends shows
            src = cv2.remap(np.ascontiguousarray(index.premult, np.float32), sx, sy, cv2.INTER_LINEAR,
                            borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            # another child there (opaque beyond the parent's edge): not a clean copy
            stray = int(((along <= rad) & (np.abs(off) > hw_p + outline + 2.0) & (src[..., 3] > 0.5)).sum())
            got.append((stray, src))
        if not got:
            continue
        least = min(g[0] for g in got)
        # both ways when both are clean: a tapering parent's widths before and after average
        # to its width here
        src = np.mean([g[1] for g in got if g[0] == least], axis=0)
        a = src[..., 3]
        # the whole zone, transparent too: what is left there of the child's root goes
        put = zone
        if not (put & (a > 0.5)).any():
            continue
        if out is layer:
            out = layer.copy()
        sub = out[y0:y1, x0:x1]
        col = np.clip(src[..., :3] / np.maximum(a, 1e-6)[..., None], 0.0, 1.0)
        sub[put, :3] = col[put]
        sub[put, 3] = a[put]
    return out
