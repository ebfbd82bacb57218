"""Measuring the source object along its strokes: widths, tubes, cut and joined ends.

The geometry :func:`~branchnb.strokes.source.source_index` prepares before
any patch is fetched (see :mod:`branchnb.strokes.source` for the rules): the
distance and arc-length maps of every stroke, the object's half width
across each stroke and its smoothing, which stroke ends are joined to
another stroke or cut across a longer object, and the tubes of pixels
each stroke owns near its ends. Split out of :mod:`branchnb.strokes.fetch` (now :mod:`~branchnb.strokes.source`);
the names are importable from there too.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from .strokes import Stroke

#: Opaque pixels are copied up to this far beyond the half width (px).
_OPAQUE_MARGIN = 2.0
#: Longest distance the width measurement walks from the stroke (px).
_MAX_WIDTH = 256


def _children_beyond_caps(strokes, keys, cuts, joined, tubes) -> dict:
    """Per tube with a free end that children join: the pixels of its tip's cap
    (beyond a round cap of the end's half width) inside a child's tube.

    A free end's cap reaches a tip's length beyond the stroke (a pointed tip
    drawn short), but where children start under a rounded end (a figure's legs
    under its body's lower dome) the object beyond the round cap is the
    children's tops: copied with the parent they stay put while the children
    turn, and peek out below the parent as teeth. They are taken out of the
    parent's tube (its core and the pixels it may copy), so the children's
    patches copy them and turn them with the children. Beyond the paper.
    The cores in ``tubes`` are changed in place.
    """
    out: dict = {}
    for k, st in enumerate(strokes):
        key = (keys[k], cuts[k])
        d, s_map, tube, interior, _, core = tubes[key]
        free_ends = [end for end in (0, 1) if not cuts[k][end]]
        if not free_ends:
            continue
        kids = [j for j in range(len(strokes)) if keys[j] != keys[k] and k in joined[j]]
        if not kids:
            continue
        at_cap = ~interior & (d > tube + 0.5)
        ends = np.zeros_like(at_cap)
        for end in free_ends:
            ends |= (s_map <= 1.0) if end == 0 else (s_map >= st.length - 1.0)
        at_cap &= ends
        if not at_cap.any():
            continue
        theirs = np.zeros_like(at_cap)
        for j in kids:
            dj, _, tj, _, _, _ = tubes[(keys[j], cuts[j])]
            theirs |= dj <= tj + 0.5
        taken = at_cap & theirs
        if taken.any():
            core[taken] = False
            out[key] = out[key] | taken if key in out else taken
    return out


def _reach_box(d: np.ndarray) -> tuple[slice, slice]:
    """The box of the pixels a distance map reaches (``d < 1e6``; see :func:`_distance_map`)."""
    near = d < 1e6
    rows, cols = np.flatnonzero(near.any(axis=1)), np.flatnonzero(near.any(axis=0))
    if not len(rows):
        return slice(0, 0), slice(0, 0)
    return slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1)


def _tube_margin(half_width):
    """Background kept around the silhouette: ``0.15 w + 3`` px."""
    return 0.15 * half_width + 3.0


def _distance_map(stroke: Stroke, shape, reach: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
    """Distance to ``stroke`` and arc length of its nearest point, for every pixel.

    Computed within ``reach`` px of the stroke's bounding box only (farther
    pixels get the distance ``1e6`` and the arc length 0: nothing of the stroke reaches them).
    """
    h, w = shape
    s = np.linspace(0.0, stroke.length, max(2, int(np.ceil(stroke.length * 2)) + 1))
    p = stroke.point_at(s)
    c = np.clip(np.round(p[:, 0]).astype(int), 0, w - 1)
    r = np.clip(np.round(p[:, 1]).astype(int), 0, h - 1)
    pad = int(min(np.ceil(reach), max(h, w))) + 1
    r0, r1 = max(int(r.min()) - pad, 0), min(int(r.max()) + pad + 1, h)
    c0, c1 = max(int(c.min()) - pad, 0), min(int(c.max()) + pad + 1, w)
    seeds = np.ones((r1 - r0, c1 - c0), bool)
    seed_s = np.zeros((r1 - r0, c1 - c0), np.float32)
    seeds[r - r0, c - c0] = False
    seed_s[r - r0, c - c0] = s
    d_in, (ir, ic) = ndi.distance_transform_edt(seeds, return_indices=True)
    if (r0, r1, c0, c1) == (0, h, 0, w):
        return d_in.astype(np.float32), seed_s[ir, ic]
    d = np.full((h, w), 1e6, np.float32)
    s_map = np.zeros((h, w), np.float32)
    d[r0:r1, c0:c1] = d_in
    s_map[r0:r1, c0:c1] = seed_s[ir, ic]
    return d, s_map


def _lookup(mask: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """``mask`` at the nearest pixels of ``pts`` (False outside the image)."""
    h, w = mask.shape
    c = np.round(pts[..., 0]).astype(np.int64)
    r = np.round(pts[..., 1]).astype(np.int64)
    inside = (c >= 0) & (c < w) & (r >= 0) & (r < h)
    out = np.zeros(pts.shape[:-1], bool)
    out[inside] = mask[r[inside], c[inside]]
    return out


def _colours(rgb: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """``rgb`` at the nearest pixels of the ``(x, y)`` points ``pts`` (clipped to the image)."""
    q = np.rint(pts).astype(np.int64)
    return rgb[np.clip(q[..., 1], 0, rgb.shape[0] - 1), np.clip(q[..., 0], 0, rgb.shape[1] - 1)]


def _run_length(inside: np.ndarray) -> np.ndarray:
    """Number of leading True values along the last axis."""
    first_out = np.argmin(inside, axis=-1)
    return np.where(inside.all(axis=-1), inside.shape[-1], first_out)


def _raw_width(stroke: Stroke, obj: np.ndarray, edt: np.ndarray, children=(), cache: dict | None = None,
               ink: tuple | None = None):
    """Half width a patch centred on ``stroke`` needs, every pixel of arc length (unsmoothed).

    Along the normal at each stroke point ``p``, the run of object pixels
    containing ``p`` (or the nearest run, for a stroke drawn a little off
    the object) spans ``[t0, t1]``; a patch centred on ``p`` needs
    ``max(|t0|, |t1|)``. Where the normal runs along another part of the
    object (a crossing), the run is capped by ``2 m + 2`` with ``m`` the
    largest distance to the background within ``edt(p) + 2`` px of ``p``
    (the object's half width at its medial axis, also for a stroke up to
    half a width off-centre).

    ``children`` (``(stroke, half_width)`` of the strokes joined to this one,
    see :func:`_joined_ends`): on the side where the run reaches a child's
    flesh (pixels nearer to the child's stroke than to this one and within
    the child's typical half width + 1 px of it), the run is the child's, not this
    stroke's -- a branch leaving a trunk at 36 degrees runs along the
    trunk's normal for several trunk widths, and the trunk measured across
    it was 2.3 times as wide as it is: its tube swallowed the branch's root
    and the branch's texture started 85 px along it instead of ~45 (a coral
    at 512 px). There the width is the other side's run, or this side's up
    to the child's flesh if that is longer (a stroke drawn off-centre, the
    crotch between a limb and the trunk beyond the limb's width); with
    children on both sides it is interpolated from the samples with none.
    Beyond the paper.

    ``cache`` (a dict kept per stroke): the rays and runs, measured once for
    every set of ``children`` (they do not depend on them).

    ``ink`` (``(ink, rgb, other)``: the object's outline pixels, its colours
    and the other strokes' pixels; None: no outline): another part drawn over
    the stroke's side is left out of its widths (:func:`_without_side_bumps`).

    Returns the arc lengths, the widths and their median (at least 1).
    """
    if cache is not None and "rays" in cache:
        s, p, t, rays, start, stop, has, local, wv = cache["rays"]
    else:
        s, p, t, rays, start, stop, has, local, wv = _width_runs(stroke, obj, edt)
        if cache is not None:
            cache["rays"] = (s, p, t, rays, start, stop, has, local, wv)
    if len(children):
        wv = _away_from_children(stroke, p, t, rays, start, stop, has, wv, children, obj.shape, local)
    wv = np.minimum(wv, local)
    if ink is not None:
        wv = _without_side_bumps(wv, t, rays, start, stop, has, *ink)
    return s, wv, float(max(1, int(np.ceil(np.median(wv)))))


#: A side's extent over this many times its median (+ 1 px), the other side's within
#: :data:`_BUMP_OTHER` times its own, is another part lying over the stroke on that side.
_BUMP = 1.5
#: ... the other side's extent at most this many times its median (+ 1 px) there.
_BUMP_OTHER = 1.25
#: ... over a stretch at most this many median half widths long, away from the stroke's ends.
_BUMP_LONG = 8.0
#: ... and outline ink inside the run on that side in at least this share of its samples.
_BUMP_INKED = 0.5
#: ... or flesh there this far (RGB distance) from the stroke's own colour.
_BUMP_COLOUR = 0.2


def _without_side_bumps(wv: np.ndarray, t: np.ndarray, rays: np.ndarray, start: np.ndarray, stop: np.ndarray,
                        has: np.ndarray, ink: np.ndarray, rgb: np.ndarray, other: np.ndarray) -> np.ndarray:
    """The widths with one-sided bumps bridged from the widths on either side (beyond the paper).

    Where another part lies over the stroke on one side only (a leaf whose
    base overlaps its stem), the run across the stroke reaches over that
    part: the stroke's tube took a leaf's first 15 px, its patches copied
    them along the bent stem (a flap with an outline spike below a flower's
    leaf at 400 px, outline streaks inside the leaves at 200 px) and the
    carried leaf was cut short. A stretch at most :data:`_BUMP_LONG` median
    half widths long, inside the stroke, where one side reaches over
    :data:`_BUMP` times its median while the other keeps to its own, gets
    the widths bridged linearly from either end: the part stays whole (a
    carried part). Only a part drawn over the stroke: in at least
    :data:`_BUMP_INKED` of the stretch's samples, outline ink (``ink``)
    crosses the run on that side short of its end, or the run's flesh beyond
    the side's own extent is of another colour (``rgb``, over
    :data:`_BUMP_COLOUR` from the stroke's flesh: a leaf over a twig, which
    hides the twig's outline). A limb growing out of the stroke's flesh (a
    lizard's thigh) has neither and stays the stroke's, as a bulge of the
    stroke's own does; so does one another stroke runs through (``other``:
    a stroked child's root, left to the junctions).
    Flower at 400 px: half widths up to 22.8 px where the leaves cross, 6.5
    elsewhere; now 6.5 throughout.
    """
    ok = has & (start >= 0) & (stop < len(t))
    if ok.sum() < 8:
        return wv
    a, b = np.abs(t[start]), np.abs(t[stop])
    ma, mb = float(np.median(a[ok])), float(np.median(b[ok]))
    bump = ok & (((a > _BUMP * ma + 1.0) & (b <= _BUMP_OTHER * mb + 1.0))
                 | ((b > _BUMP * mb + 1.0) & (a <= _BUMP_OTHER * ma + 1.0)))
    if not bump.any():
        return wv
    # (out to where that side comes back to its own width: the part's flanks too)
    rising = ok & (((a > ma + 1.0) & (b <= _BUMP_OTHER * mb + 1.0)) | ((b > mb + 1.0) & (a <= _BUMP_OTHER * ma + 1.0)))
    bump = ndi.binary_propagation(bump, mask=bump | rising)
    typical = max(1.0, float(np.median(wv[ok])))
    lab, n = ndi.label(bump)
    out = wv.copy()
    idx = np.arange(len(wv))
    inked = _lookup(ink, rays)
    near_other = _lookup(other, rays)
    centre = int(np.argmin(np.abs(t)))
    # the stroke's own flesh: the colour on its centre line away from the bumps
    mid = ok & ~bump & ~inked[:, centre]
    if not mid.any():
        return wv
    flesh = np.median(_colours(rgb, rays[mid, centre]), axis=0)
    for r in ndi.find_objects(lab):
        i0, i1 = r[0].start, r[0].stop
        if i0 == 0 or i1 >= len(wv) or i1 - i0 > _BUMP_LONG * typical:
            continue
        hits = 0
        if any(near_other[i, (slice(start[i], centre) if a[i] > b[i] else slice(centre + 1, stop[i] + 1))].any()
               for i in range(i0, i1)):
            continue
        for i in range(i0, i1):
            # from the centre outwards on the bump's side
            sl = slice(start[i], centre) if a[i] > b[i] else slice(centre + 1, stop[i] + 1)
            seg, pts, own = inked[i, sl], rays[i, sl], (ma if a[i] > b[i] else mb)
            if a[i] > b[i]:
                seg, pts = seg[::-1], pts[::-1]
            # the outline at the run's end is the part's own rim: ink short of it is inner ink
            end = len(seg)
            while end > 0 and seg[end - 1]:
                end -= 1
            if seg[:end].any():
                hits += 1
                continue
            far = ~seg & (np.arange(1, len(seg) + 1) > own + 1.0)
            if far.any():
                c = _colours(rgb, pts[far])
                hits += bool(np.linalg.norm(np.median(c, axis=0) - flesh) > _BUMP_COLOUR)
        if hits < _BUMP_INKED * (i1 - i0):
            continue
        # bridged from the stroke's own widths just before and after the stretch
        out[i0:i1] = np.interp(idx[i0:i1], [i0 - 1, i1], [wv[i0 - 1], wv[i1]])
    return out


def _width_runs(stroke: Stroke, obj: np.ndarray, edt: np.ndarray):
    """The rays along the normals of :func:`_raw_width` and the object's runs on them."""
    s = np.linspace(0.0, stroke.length, max(2, int(np.ceil(stroke.length)) + 1))
    p = stroke.point_at(s)
    n = stroke.normal_at(s, window=3.0)
    t = np.arange(-_MAX_WIDTH, _MAX_WIDTH + 1, dtype=float)
    rays = p[:, None, :] + t[None, :, None] * n[:, None, :]
    inside = _lookup(obj, rays)
    near = np.argmin(np.where(inside, np.abs(t)[None], np.inf), axis=1)
    # the run of object pixels through the nearest one: from after the last gap
    # before it to before the first gap after it
    col = np.arange(len(t))[None]
    gap = ~inside
    start = np.where(gap & (col < near[:, None]), col, -1).max(axis=1) + 1
    stop = np.where(gap & (col > near[:, None]), col, len(t)).min(axis=1) - 1
    has = inside[np.arange(len(s)), near]
    local = 2.0 * _local_max(edt, p) + 2.0
    wv = np.where(has, np.maximum(np.abs(t[start]), np.abs(t[stop])) + 0.5, 0.0)
    return s, p, t, rays, start, stop, has, local, wv


def _far_half_width(wv: np.ndarray, joined, parent: int) -> float:
    """A child's typical half width: the median of its raw widths ``wv`` over the half of
    its stroke away from the end joined to ``parent`` (a limb hugging its trunk for a while
    measures the trunk too near its root: its median over the whole stroke was 2.2 times
    its width, a swayed tree at 500 px)."""
    half = len(wv) // 2
    far = wv[half:] if joined[0] == parent else wv[:max(half, 1)]
    return float(max(1.0, np.median(far)))


def _away_from_children(stroke: Stroke, p, t, rays, start, stop, has, wv, children, shape,
                        local) -> np.ndarray:
    """The widths of :func:`_raw_width` with the runs into children's flesh left out."""
    h, w = shape
    rho = float(min(np.max(local, initial=0.0), _MAX_WIDTH)) + 2.0
    # seeds: the stroke, and the children's strokes (without their points within 1.5 px of
    # it: a child starting on the centre line would tie with it across the stroke)
    own = stroke.point_at(np.linspace(0.0, stroke.length, int(np.ceil(2.0 * stroke.length)) + 1))
    kid, reach = [], []
    for ch, hw in children:
        q = ch.point_at(np.linspace(0.0, ch.length, int(np.ceil(2.0 * ch.length)) + 1))
        q = q[stroke.project(q)[1] > 1.5]
        kid.append(q)
        reach.append(np.full(len(q), float(hw) + 1.0))
    kid = np.concatenate(kid) if kid else np.zeros((0, 2))
    reach = np.concatenate(reach) if reach else np.zeros(0)
    lo = np.floor(own.min(axis=0) - rho).astype(int)
    hi = np.ceil(own.max(axis=0) + rho).astype(int) + 1
    c0, r0 = max(int(lo[0]), 0), max(int(lo[1]), 0)
    c1, r1 = min(int(hi[0]), w), min(int(hi[1]), h)
    if c0 >= c1 or r0 >= r1 or not len(kid):
        return wv
    box = (r1 - r0, c1 - c0)
    # per seed pixel: how far its flesh reaches (the child's typical half width + 1 px;
    # -1 for the stroke's own seeds, which win where they coincide)
    label = np.zeros(box, np.float32)
    for val, q in ((reach, kid), (np.full(len(own), -1.0), own)):
        c = np.round(q[:, 0]).astype(int) - c0
        r = np.round(q[:, 1]).astype(int) - r0
        ok = (c >= 0) & (c < box[1]) & (r >= 0) & (r < box[0])
        label[r[ok], c[ok]] = val[ok]
    if not (label > 0).any():
        return wv
    dist, (ir, ic) = ndi.distance_transform_edt(label == 0, return_indices=True)
    flesh = np.zeros(shape, bool)
    flesh[r0:r1, c0:c1] = dist <= label[ir, ic]
    theirs = _lookup(flesh, rays)
    mid = len(t) // 2  # t = 0
    col = np.arange(len(t))[None]
    # per side: the first child pixel between the stroke and the run's end
    plus = np.where(theirs & (col > mid) & (col <= stop[:, None]), col, len(t)).min(axis=1)
    minus = np.where(theirs & (col < mid) & (col >= start[:, None]), col, -1).max(axis=1)
    hit_p, hit_m = plus < len(t), minus >= 0
    run_p = np.maximum(t[stop], 0.0)
    run_m = np.maximum(-t[start], 0.0)
    cut_p = np.where(hit_p, np.maximum(t[np.minimum(plus, len(t) - 1)] - 1.0, 0.0), run_p)
    cut_m = np.where(hit_m, np.maximum(-t[np.maximum(minus, 0)] - 1.0, 0.0), run_m)
    out = wv.copy()
    one = has & (hit_p ^ hit_m)
    out[one] = np.where(hit_p, np.maximum(run_m, cut_p), np.maximum(run_p, cut_m))[one] + 0.5
    both = has & hit_p & hit_m
    clean = has & ~hit_p & ~hit_m
    if both.any():
        if clean.any():
            idx = np.arange(len(wv))
            out[both] = np.maximum(np.maximum(cut_p, cut_m)[both] + 0.5,
                                   np.interp(idx[both], idx[clean], wv[clean]))
        else:
            out[both] = np.maximum(cut_p, cut_m)[both] + 0.5
    # only where the child swallowed the run: the width measured across it over 1.5 times
    # the new one + 2 px, as in _parent_side (which trims a tube a little too wide on the
    # child's side to the silhouette there: a lizard's thigh at 100 px)
    return np.where(wv > 1.5 * out + 2.0, out, wv)


def _connected_to_stroke(core: np.ndarray, seed: np.ndarray) -> np.ndarray:
    """The pixels of ``core`` in a piece (8-connected) that touches ``seed`` (the stroke's middle).

    A tube or a free end's cap reaching across the background onto another
    limb (a lizard's hind-leg stroke ending next to its front foot at 100 px)
    would copy that limb with the stroke: a loose piece moved with it. Such
    pixels stay unstroked parts (they follow the stroke they touch).
    """
    n, lab = cv2.connectedComponents(core.view(np.uint8), connectivity=8)
    if n <= 2:
        return core
    hit = np.zeros(n, bool)
    hit[lab[seed & core]] = True
    hit[0] = False
    return hit[lab]


def _parent_side(cut: np.ndarray, child: Stroke, end: int, parent: Stroke, s_map: np.ndarray,
                 obj: np.ndarray, half_width: float, d_parent: np.ndarray,
                 d_child: np.ndarray, tube_width: float) -> tuple[np.ndarray, float]:
    """The pixels of ``cut`` (the parent's tube about a child's joined ``end``) that are the parent's.

    The parent's tube is as wide as the parent is anywhere across it; where a
    limb leaves along the parent's normal (a lizard's thigh at the hip), the
    run measured along that normal is the limb, so the tube swallows the
    limb's base. On the child's side, the parent keeps only the pixels within
    its own silhouette there: the run of object pixels along the normal on
    either flank of the child (``1.5 w + 4`` px away along the parent, ``w``
    the child's half width), the smaller of the two, plus a pixel, and the
    pixels nearer to the parent's stroke (``d_parent``) than to the child's
    (``d_child``) -- only where the parent's tube at the joint (``tube_width``)
    is wider than 1.5 times that run (else the tube is the parent's own
    width and stays). Beyond the paper (which assumes strokes with clean tubes).

    Returns those pixels and the parent's half width on the child's side
    (``inf`` where it cannot be measured).
    """
    s_j, _ = parent.project(child.points[:1] if end == 0 else child.points[-1:])
    s_j = float(s_j[0])
    p_j, n_j = parent.point_at(s_j), parent.normal_at(s_j, window=3.0)
    t = np.arange(0.0, child.length + 0.5, 1.0)
    pts = child.point_at(t if end == 0 else child.length - t)
    side = float(np.sign(np.mean((pts - p_j) @ n_j)))
    if side == 0.0:
        return cut, np.inf
    runs, flanks = [], 0
    for s_f in (s_j - 1.5 * half_width - 4.0, s_j + 1.5 * half_width + 4.0):
        if not 0.0 <= s_f <= parent.length:
            continue
        flanks += 1
        q, n = parent.point_at(s_f), parent.normal_at(s_f, window=3.0)
        ray = _lookup(obj, q[None] + side * np.arange(0.0, _MAX_WIDTH)[:, None] * n[None])
        if ray[0]:
            runs.append(_run_length(ray))
    if not flanks and tube_width > half_width + 2.0:
        # a parent stroke shorter than the child is wide (a short stroke across a round
        # body, a starfish's disk, its arms leaving from its centre): no flank to measure
        # the parent's silhouette on, and its tube, measured across the arms, reaches far
        # along the child; the parent keeps only the pixels nearer its stroke than the
        # child's (else the child's root stays behind at the source when the child moves)
        rs, cs = np.nonzero(cut)
        out = np.zeros_like(cut)
        keep = d_parent[rs, cs] <= d_child[rs, cs]
        out[rs[keep], cs[keep]] = True
        return out, np.inf
    if not runs or tube_width <= 1.5 * min(runs) + 2.0:
        return cut, np.inf  # a tube about as wide as the parent: the existing rule holds
    rs, cs = np.nonzero(cut)
    if not len(rs):
        return cut, float(min(runs))
    s_px = s_map[rs, cs]
    foot, normal = parent.point_at(s_px), parent.normal_at(s_px, window=3.0)
    signed = side * ((cs - foot[:, 0]) * normal[:, 0] + (rs - foot[:, 1]) * normal[:, 1])
    keep = (signed <= min(runs) + 1.0) | (d_parent[rs, cs] <= d_child[rs, cs])
    out = np.zeros_like(cut)
    out[rs[keep], cs[keep]] = True
    return out, float(min(runs))


def _clear_of(child: Stroke, end: int, parent: Stroke, ws, wv, half_width: float) -> float:
    """How far along ``child`` from its ``end`` its silhouette (``half_width``) is clear of
    the parent's (``wv`` at ``ws``): a branch leaving at a narrow angle runs along its
    parent's side for several parent widths."""
    t = np.arange(0.0, child.length + 0.5, 1.0)
    s_par, d = parent.project(child.point_at(t if end == 0 else child.length - t))
    out = np.flatnonzero(d > np.interp(s_par, ws, wv) + half_width)
    return float(t[out[0]]) if len(out) else 0.0


def _wide_ends(stroke: Stroke, cut, edt: np.ndarray, typical: float) -> tuple[bool, bool]:
    """Per end: cut, or inside a body wider than the stroke's part (its depth over 1.5
    times the typical half width: a starfish's arm stroked from the centre of its disk).

    There the widths are the body's, not the stroke's own: :func:`_smooth_width`
    replaces them as at a cut end, so that the stroke's tube does not swallow the
    body and the parts round it (which then stay unstroked parts, held whole). Else
    whether the median filter trimmed that bulge depended on the image's size
    (kept at 400 px, swallowed at 150). Beyond the paper.
    """
    h, w = edt.shape
    out = []
    for end in (0, 1):
        x, y = np.rint(stroke.points[0 if end == 0 else -1]).astype(int)
        deep = 0 <= x < w and 0 <= y < h and float(edt[y, x]) > 1.5 * typical
        out.append(bool(cut[end] or deep))
    return out[0], out[1]


def _smooth_width(wv: np.ndarray, typical: float, cut) -> np.ndarray:
    """The width profile used for the tube and the patch radius.

    At a cut end (the stroke runs into a longer object: a branch drawn
    from the trunk, a tail drawn from the body) the widths above 1.5
    times the median are the parent's and are replaced by the first width
    of the stroke's own. A median filter along the stroke then removes
    short outliers, a running maximum keeps the patches over local bulges
    and a Gaussian smooths the profile, so that the tube's edge has no
    steps where the width changes.
    """
    wv = wv.copy()
    for end in (0, 1):
        if cut[end]:
            w = wv if end == 0 else wv[::-1]
            free = np.flatnonzero(w <= 1.5 * typical)
            if len(free):
                w[:free[0]] = w[free[0]]
    n = int(typical)
    wv = ndi.median_filter(wv, size=2 * n + 1, mode="nearest")
    wv = ndi.maximum_filter1d(wv, size=2 * n + 1, mode="nearest")
    return ndi.gaussian_filter1d(wv, sigma=typical / 2.0, mode="nearest").astype(float)


def _joined_ends(strokes, raw, keys) -> list[tuple[int, int]]:
    """Per stroke and end: the (different) stroke the end lies on, within half its local width + 3 px, or -1.

    Two ends meeting (each on the other near its end) join as in
    :func:`~branchnb.strokes.junctions.find_junctions`: the later-drawn stroke
    is the child.
    """
    out = []
    for k, st in enumerate(strokes):
        flags = []
        for end in (0, 1):
            q = st.points[0 if end == 0 else -1][None]
            hit, best = -1, np.inf
            for j, other in enumerate(strokes):
                if j == k or keys[j] == keys[k]:
                    continue
                s, d = other.project(q)
                tol = 0.5 * float(np.interp(s[0], raw[j][0], raw[j][1])) + 3.0
                if d[0] <= tol and 1.0 < s[0] < other.length - 1.0 and d[0] < best:
                    if j > k and min(s[0], other.length - s[0]) <= tol:
                        # two ends meeting (a body's end where two legs start): the
                        # later-drawn stroke is the child, as in find_junctions --
                        # else each would be the other's child and the pixels round
                        # the meeting point nobody's (a hole in the body)
                        continue
                    hit, best = j, float(d[0])
            flags.append(hit)
        out.append(tuple(flags))
    return out


def _local_max(edt: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Largest ``edt`` within ``edt(p) + 2`` px of each point ``p``.

    Evaluated every few points (a quarter of the typical half width) and
    interpolated in between: the widths are smoothed over several half
    widths afterwards anyway.
    """
    h, w = edt.shape
    e_all = edt[np.clip(np.round(p[:, 1]).astype(int), 0, h - 1),
                np.clip(np.round(p[:, 0]).astype(int), 0, w - 1)]
    step = max(1, int(np.median(e_all) // 4))
    pick = np.unique(np.r_[np.arange(0, len(p), step), len(p) - 1])
    e0 = e_all[pick]
    rho = int(np.ceil(min(float(e0.max()), _MAX_WIDTH))) + 2
    out = np.zeros(len(pick))
    pts = np.round(p[pick]).astype(np.int64)
    for i, ((x, y), e) in enumerate(zip(pts, e0)):
        # the disk of radius e + 2 (at most rho) about the point, cut to the image
        rr = min(int(np.floor(e + 2.0)), rho)
        r0, r1, c0, c1 = max(y - rr, 0), min(y + rr + 1, h), max(x - rr, 0), min(x + rr + 1, w)
        if r0 >= r1 or c0 >= c1:
            continue
        oy, ox = np.ogrid[r0 - y:r1 - y, c0 - x:c1 - x]
        disk = np.hypot(ox, oy) <= e + 2.0
        out[i] = max(float(edt[r0:r1, c0:c1][disk].max(initial=0.0)), 0.0)
    return np.interp(np.arange(len(p)), pick, out)


def _end_direction(stroke: Stroke, end: int, window: float) -> tuple[np.ndarray, np.ndarray]:
    s_end = 0.0 if end == 0 else stroke.length
    a = float(stroke.angle_at(s_end, window=window))
    u = np.array([np.cos(a), np.sin(a)])
    return stroke.point_at(s_end), (-u if end == 0 else u)


def _is_cut(stroke: Stroke, obj: np.ndarray, half_width: float, end: int) -> bool:
    """Whether the object goes on for more than ``max(2 w, 8)`` px beyond the stroke end.

    ``w`` is the stroke's typical (median) half width.
    """
    p, u = _end_direction(stroke, end, window=max(3.0, half_width))
    limit = max(2.0 * half_width, 8.0)
    t = np.arange(1.0, np.ceil(limit) + 2.0)
    run = _run_length(_lookup(obj, p[None] + t[:, None] * u[None]))
    return bool(run > limit)


def _beyond_weight(stroke: Stroke, end: int, s_map: np.ndarray, xx: np.ndarray,
                   yy: np.ndarray) -> np.ndarray:
    """0 past the straight cut at a stroke end, 1 before it, a one-pixel ramp between.

    "Past" = the nearest stroke point is the end point and the pixel lies
    ahead of it along the stroke direction.
    """
    p, u = _end_direction(stroke, end, window=3.0)
    at_end = s_map <= 1.0 if end == 0 else s_map >= stroke.length - 1.0
    ahead = (xx - p[0]) * u[0] + (yy - p[1]) * u[1]
    return np.where(at_end, np.clip(0.5 - ahead, 0.0, 1.0), 1.0).astype(np.float32)


def _end_tube(stroke: Stroke, end: int, s_map: np.ndarray, xx: np.ndarray, yy: np.ndarray,
              half_width: float, inked: np.ndarray) -> np.ndarray:
    """The tube of :func:`source_index` continued over the pixels nearest to a cut end.

    Those pixels lie on the half plane behind the end point; the tube
    bounds them laterally (distance from the stroke's end line), with the
    same margins and one-pixel ramp as along the stroke.
    """
    p, u = _end_direction(stroke, end, window=3.0)
    at_end = s_map <= 1.0 if end == 0 else s_map >= stroke.length - 1.0
    lateral = np.abs((xx - p[0]) * u[1] - (yy - p[1]) * u[0])
    margin = np.where(inked, _OPAQUE_MARGIN, _tube_margin(half_width))
    ramp = np.clip(half_width + margin - lateral + 0.5, 0.0, 1.0)
    return np.where(at_end, ramp, 1.0).astype(np.float32)
