"""A stroke crossing itself or another stroke passes over it, outline and all (beyond the paper).

The graph cut of :func:`~branchnb.strokes.composition.compose` stitches every
patch into one silhouette. Where a target stroke crosses its own path (a rope
re-stroked into a loop) or another target stroke on its way (two ropes laid
across each other, a tentacle crossing another), the cut runs wherever the two
passes' textures agree best: a patchwork with no over/under, the upper pass's
outline missing across the lower one, the stripes of both meeting along a seam.
An artist draws the upper pass over the lower one, continuous, its outline across
the lower's flesh, the lower pass resuming on both sides.

Here every such crossing is redrawn from the two passes' own patches, each pass's
stretch through the crossing composed alone (the same graph cut, only its own
patches), the lower pass first, the upper one over it. Which pass lies on top:

* a stroke crossing itself: the later pass (by arc length along the stroke);
* two strokes: the one given later, unless the source shows it lying under the
  other (:attr:`~branchnb.strokes.source.SourceIndex.hidden_by`), as
  :func:`~branchnb.strokes.overlays._overlaid_parts` decides for a tip laid over
  another part.

Crossings near a stroke's end (a tip laid over another part:
:mod:`~branchnb.strokes.overlays`; a branch: :mod:`~branchnb.strokes.junctions`),
near a junction, of strokes left where they were (the source's crossing is
copied as it is) or at under :data:`_MIN_ANGLE` (two strokes running side by
side) are left as the cut laid them. Crowded crossings (three or more passes
within a tube width: overlapping loops, a loop with no hole, several passes
through one point) are redrawn together, each pixel from its top pass
(:func:`_redraw_crowd`). Only for objects with an alpha (an RGBA
source, or an opaque one on a smooth ground): a busy ground's patches are
opaque squares.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import cv2
import numpy as np

from .composition import compose

__all__: list[str] = []

#: Crossings at a smaller angle (rad) than this are two strokes running side by side: left alone.
_MIN_ANGLE = np.deg2rad(12.0)
#: The passes' stretches redrawn reach at most this many half widths (of the two) from the crossing.
_MAX_REACH = 8.0
#: A self-crossing whose loop is at most this many times the two passes' clearance long is a
#: hairpin's own turn, not counted; up to pi times, a loop with no hole (a rope's knot-like blob),
#: redrawn as a crowded crossing. (Measured on one-loop ropes at 400 px: loops of 64-85 px at a
#: clearance of 26 px had a patchwork X at their neck, outline share 0.05-0.07 across it.)
_TIGHT = 2.0
#: Alpha under which a composed pixel is transparent.
_CLEAR = 0.02


@dataclass
class _Crossing:
    """Where an upper pass (stroke ``top`` at arc length ``s_top``) crosses a lower one."""

    point: np.ndarray
    top: int
    s_top: float
    bottom: int
    s_bottom: float
    angle: float
    #: A loop too short to clear its own crossing (its passes' bands overlap all round it): redrawn
    #: as a crowded crossing (:func:`_redraw_crowd`), never pairwise.
    tight: bool = False


def _segment_hits(p: np.ndarray, q: np.ndarray):
    """Intersections of the polylines ``p`` and ``q``: ``(i, j, t, u)`` arrays, segment ``i`` of
    ``p`` at parameter ``t`` meeting segment ``j`` of ``q`` at ``u`` (both in [0, 1))."""
    a, b = p[:-1], p[1:]
    c, d = q[:-1], q[1:]
    r = b - a
    s = d - c
    den = r[:, None, 0] * s[None, :, 1] - r[:, None, 1] * s[None, :, 0]
    ac = c[None, :, :] - a[:, None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (ac[..., 0] * s[None, :, 1] - ac[..., 1] * s[None, :, 0]) / den
        u = (ac[..., 0] * r[:, None, 1] - ac[..., 1] * r[:, None, 0]) / den
    ok = (np.abs(den) > 1e-12) & (t >= 0) & (t < 1) & (u >= 0) & (u < 1)
    i, j = np.nonzero(ok)
    return i, j, t[i, j], u[i, j]


def _arc(points: np.ndarray) -> np.ndarray:
    return np.r_[0.0, np.cumsum(np.hypot(*np.diff(points, axis=0).T))]


def _half_width(index, attached, k: int, s: float) -> float:
    return float(index.half_width(k, attached[k].source_arc_length(float(s))))


def find_crossings(attached: list, index, junctions: list, still: set, width: float) -> list[_Crossing]:
    """The crossings of the target strokes (see the module's docstring for which count).

    Parameters
    ----------
    attached : list of StrokePair
        The stroke pairs (targets extended at junctions).
    index : SourceIndex
        The source's strokes (half widths, who hides whom).
    junctions : list of Junction
        Branches among the target strokes.
    still : set of int
        Strokes left where they were.
    width : float
        Outline width (px; 0 for none).

    Returns
    -------
    list of _Crossing
    """
    polys = [np.asarray(p.target.points, float) for p in attached]
    arcs = [_arc(p) for p in polys]
    found: list[_Crossing] = []
    for a in range(len(polys)):
        for b in range(a, len(polys)):
            if a == b and a in still or a != b and a in still and b in still:
                continue
            i, j, t, u = _segment_hits(polys[a], polys[b])
            if not len(i):
                continue
            pa, pb = polys[a], polys[b]
            sa = arcs[a][i] + t * (arcs[a][i + 1] - arcs[a][i])
            sb = arcs[b][j] + u * (arcs[b][j + 1] - arcs[b][j])
            pts = pa[i] + t[:, None] * (pa[i + 1] - pa[i])
            da = (pa[i + 1] - pa[i]) / np.maximum(np.hypot(*(pa[i + 1] - pa[i]).T), 1e-12)[:, None]
            db = (pb[j + 1] - pb[j]) / np.maximum(np.hypot(*(pb[j + 1] - pb[j]).T), 1e-12)[:, None]
            ang = np.arccos(np.clip(np.abs((da * db).sum(axis=1)), 0.0, 1.0))
            for n in range(len(i)):
                s_a, s_b = float(sa[n]), float(sb[n])
                if a == b:
                    if s_a >= s_b:
                        continue  # (each self-crossing once: the earlier pass as a)
                if ang[n] < _MIN_ANGLE:
                    continue
                wa, wb = _half_width(index, attached, a, s_a), _half_width(index, attached, b, s_b)
                near = wa + wb + 2.0 * width + 4.0
                if a == b and s_b - s_a <= _TIGHT * near:
                    continue  # (a tight curl's own turn, not a loop crossing the path)
                tight = a == b and s_b - s_a <= np.pi * near
                # (a tip laid over the other stroke, or a branch: others' business)
                if min(s_a, s_b, arcs[a][-1] - s_a, arcs[b][-1] - s_b) < near:
                    continue
                if any(np.hypot(*(np.asarray(jn.point) - pts[n])) < near + max(wa, wb)
                       for jn in junctions if {jn.child, jn.parent} & {a, b}):
                    continue
                if any(np.hypot(*(c.point - pts[n])) < 1.0 and {c.top, c.bottom} == {a, b} for c in found):
                    continue  # (the same crossing met at a shared vertex)
                if a == b:
                    top, s_top, bottom, s_bottom = a, s_b, a, s_a
                else:
                    top, s_top, bottom, s_bottom = b, s_b, a, s_a
                    # (unless the source shows the later one under the other)
                    if bottom in (index.hidden_by.get(top) or ()):
                        top, s_top, bottom, s_bottom = a, s_a, b, s_b
                found.append(_Crossing(pts[n], top, s_top, bottom, s_bottom, float(ang[n]), tight))
    return found


def _reach(w_self: float, w_other: float, angle: float) -> float:
    """Arc length either side of a crossing over which a pass is redrawn: its band (``w_self``
    wide, round-capped) clears the other pass's band (``w_other``) at ``angle``."""
    sin = max(np.sin(angle), np.sin(_MIN_ANGLE))
    cos = np.cos(angle)
    d = (w_other + w_self) / sin + w_self * cos / sin + 2.0
    return float(min(d, _MAX_REACH * (w_self + w_other)))


def _band(stroke, s0: float, s1: float, half: float, box) -> np.ndarray:
    """Pixels of ``box`` (rows, cols slices) within ``half`` px of ``stroke`` between arc lengths s0 and s1."""
    rs, cs = box
    h, w = rs.stop - rs.start, cs.stop - cs.start
    s = np.linspace(s0, s1, max(2, int(np.ceil(s1 - s0)) + 1))
    pts = stroke.point_at(s) - (cs.start, rs.start)
    canvas = np.full((h, w), 255, np.uint8)
    line = np.rint(pts * 256.0).astype(np.int32)
    cv2.polylines(canvas, [line.reshape(-1, 1, 2)], False, 0, 1, cv2.LINE_8, 8)
    d = cv2.distanceTransform(canvas, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    return d <= half


def _pass_layer(placed: list, laid: list, k: int, s0: float, s1: float, box, method: str,
                power: float, gradient_weighted: bool) -> np.ndarray | None:
    """Straight RGBA on ``box``: stroke ``k``'s patches reaching arc lengths [s0, s1], composed alone."""
    rs, cs = box
    sub = []
    for pp, where in zip(placed, laid):
        if where is None or where[0] != k:
            continue
        r = 0.5 * pp.valid.shape[0]
        if where[1] + r < s0 or where[1] - r > s1:
            continue
        # (the patch as laid but for the check that drops pixels folded over another turn of
        # the stroke: at a crossing the other pass is such a turn, and the pass over it is wanted)
        valid = pp.valid if where[2] is None else where[2]
        sub.append(dataclasses.replace(pp, valid=valid,
                                       origin=(int(pp.origin[0]) - cs.start, int(pp.origin[1]) - rs.start)))
    if not sub:
        return None
    comp = compose(sub, (rs.stop - rs.start, cs.stop - cs.start), method=method, power=power,
                   gradient_weighted=gradient_weighted)
    pm = comp.image
    out = np.zeros((*pm.shape[:2], 5), np.float32)  # (straight RGBA, covered)
    a = pm[..., 3]
    nz = a > 1e-6
    out[nz, :3] = np.clip(pm[nz, :3] / a[nz, None], 0.0, 1.0)
    out[..., 3] = a
    out[..., 4] = comp.covered
    return out


def _crowded(attached, index, c: _Crossing, stretches, width: float) -> bool:
    """Whether any other stroke, or another stretch of the crossing's strokes, comes within the
    two passes' bands (a tight curl's next turn, a third stroke through the crossing): the
    crossing is then left as the cut laid it (its passes' patches also cover those)."""
    for m, pair in enumerate(attached):
        st = pair.target
        s = np.arange(0.0, st.length + 0.5, 1.0)
        keep = np.ones(len(s), bool)
        for k, s0, s1, _ in stretches:
            if k == m:
                keep &= (s < s0) | (s > s1)
        if not keep.any():
            continue
        pts = st.point_at(s[keep])
        w_m = float(np.max(index.half_width(m, pair.source_arc_length(s[keep])))) + width + 2.0
        for k, s0, s1, wk in stretches:
            q = attached[k].target.point_at(np.arange(s0, s1 + 0.5, 1.0))
            near = np.hypot(pts[:, None, 0] - q[None, :, 0], pts[:, None, 1] - q[None, :, 1]).min(axis=1)
            if k == m:
                # (the stroke's own points just past the stretch's ends are no crowd)
                gap = np.minimum(np.abs(s[keep] - s0), np.abs(s[keep] - s1))
                near = np.where(gap > 2.0 * (wk + w_m), near, np.inf)
            if (near < wk + w_m).any():
                return True
    return False


def _over_into(dst: np.ndarray, src: np.ndarray, where: np.ndarray) -> None:
    """Straight-alpha ``src`` over ``dst`` (in place) on ``where``."""
    a = np.where(where, src[..., 3], 0.0)[..., None]
    la = dst[..., 3:4]
    na = a + la * (1.0 - a)
    pm = src[..., :3] * a + dst[..., :3] * la * (1.0 - a)
    rgb = np.where(na > 1e-6, pm / np.maximum(na, 1e-6), 0.0)
    dst[..., :3] = np.where(where[..., None], rgb, dst[..., :3])
    dst[..., 3] = np.where(where, na[..., 0], dst[..., 3])


def crossed_over(layer: np.ndarray, placed: list, laid: list, labels: np.ndarray, attached: list, index,
                 junctions: list, still: set, width: float, *, method: str = "graphcut",
                 power: float = 1.0, gradient_weighted: bool = True) -> np.ndarray:
    """``layer`` (straight RGBA) with every crossing redrawn: the upper pass over the lower one.

    Parameters
    ----------
    layer : (H, W, 4) float32 ndarray
        The composed object.
    placed : list of PlacedPatch
        Every patch laid (``labels`` index it).
    laid : list
        Per patch: ``(stroke, target arc length, valid)`` of a stroke's sample (``valid``: its
        pixels without the check for folds over another turn of the stroke, None if the same
        as the patch's), None for others.
    labels : (H, W) int ndarray
        Patch each pixel came from (-1: none).
    attached : list of StrokePair
        The stroke pairs (targets extended at junctions).
    index : SourceIndex
        The source's strokes.
    junctions : list of Junction
        Branches among the target strokes.
    still : set of int
        Strokes left where they were.
    width : float
        Outline width (px; 0 for none).
    method, power, gradient_weighted
        The composition's (:func:`~branchnb.strokes.composition.compose`).

    Returns
    -------
    (H, W, 4) float32 ndarray
        ``layer`` itself when no crossing counts.
    """
    crossings = find_crossings(attached, index, junctions, still, width)
    if not crossings:
        return layer
    h, w = layer.shape[:2]
    stroke_of = np.array([pp.stroke if pp.stroke is not None else -1 for pp in placed] + [-1])
    out = layer.copy()
    crowded: list = []
    for c in crossings:
        w_top = _half_width(index, attached, c.top, c.s_top) + width + 2.0
        w_bot = _half_width(index, attached, c.bottom, c.s_bottom) + width + 2.0
        stretches = []
        for k, s, wk, wo in ((c.bottom, c.s_bottom, w_bot, w_top), (c.top, c.s_top, w_top, w_bot)):
            d = _reach(wk, wo, c.angle)
            stretches.append((k, max(s - d, 0.0), min(s + d, attached[k].target.length), wk))
        reach = max(st[2] - st[1] for st in stretches) + 2.0 * max(w_top, w_bot)
        x0, y0 = (int(np.floor(v - reach)) for v in c.point)
        x1, y1 = (int(np.ceil(v + reach)) + 1 for v in c.point)
        box = (slice(max(y0, 0), min(y1, h)), slice(max(x0, 0), min(x1, w)))
        if box[0].start >= box[0].stop or box[1].start >= box[1].stop:
            continue
        if c.tight or _crowded(attached, index, c, stretches, width):
            crowded.append((c, stretches, box))
            continue
        layers, bands = [], []
        for k, s0, s1, wk in stretches:
            lay = _pass_layer(placed, laid, k, s0, s1, box, method, power, gradient_weighted)
            if lay is None:
                break
            layers.append(lay)
            bands.append(_band(attached[k].target, s0, s1, wk, box))
        if len(layers) < 2:
            continue
        region = bands[0] | bands[1]
        sub = out[box].copy()
        # the two passes' own pixels in the region are redrawn (other parts' stay under them)
        # (only where their stretches' patches reach: no hole where they do not)
        mine = np.isin(stroke_of[labels[box]], [c.top, c.bottom]) & region \
            & ((layers[0][..., 4] > 0) | (layers[1][..., 4] > 0))
        sub[mine] = 0.0
        for lay, band in zip(layers, bands):
            _over_into(sub, lay, band & (lay[..., 3] > _CLEAR))
        out[box][region] = sub[region]
    for cluster in _clusters(crowded):
        _redraw_crowd(out, cluster, placed, laid, stroke_of, labels, attached, index, width,
                      method, power, gradient_weighted)
    return out


#: A patch may lay a pixel of a crowded crossing's pass only if its sample lies within this many
#: patch radii (along the stroke) of the pixel's top pass's nearest point (see :func:`_redraw_crowd`):
#: a patch square reaches ~1.4 radii along a straight stroke (its corners); the passes of the
#: loops measured (coils, 3-petal roses, loops with no hole, 160-1000 px) lie >= 3 radii apart.
_SAME_PASS = 1.5


def _clusters(crowded: list) -> list[list]:
    """The crowded crossings ``(crossing, stretches, box)`` grouped by overlapping boxes."""
    groups: list[list] = []
    for item in crowded:
        (rs, cs) = item[2]
        hit = [g for g in groups if any(rs.start < b[0].stop and b[0].start < rs.stop
                                        and cs.start < b[1].stop and b[1].start < cs.stop
                                        for _, _, b in g)]
        merged = [item] + [x for g in hit for x in g]
        groups = [g for g in groups if not any(g is h for h in hit)] + [merged]
    return groups


def _rank(index, strokes: list[int]) -> dict:
    """Stacking rank of ``strokes``: the later given higher, but under any stroke the source shows
    lying over it (:attr:`~branchnb.strokes.source.SourceIndex.hidden_by`)."""
    order = sorted(strokes)
    for _ in range(len(order)):
        moved = False
        for i in range(len(order) - 1):
            a, b = order[i], order[i + 1]
            if b in (index.hidden_by.get(a) or ()) and a not in (index.hidden_by.get(b) or ()):
                continue
            if a in (index.hidden_by.get(b) or ()):
                order[i], order[i + 1] = b, a
                moved = True
        if not moved:
            break
    return {k: n for n, k in enumerate(order)}


def _redraw_crowd(out: np.ndarray, cluster: list, placed: list, laid: list, stroke_of: np.ndarray,
                  labels: np.ndarray, attached: list, index, width: float, method: str, power: float,
                  gradient_weighted: bool) -> None:
    """Redraw a cluster of crowded crossings (in place): every pixel from its top pass only.

    Where three or more passes meet within a tube width (a stroke crossing itself
    several times in one place, a small loop whose next turn runs past the crossing),
    the pairwise redraw of :func:`crossed_over` does not apply (its two passes'
    patches also cover the others). Here every pixel within a pass's silhouette
    (its edge half width + 1 px) is owned by the topmost pass there: the latest by
    arc length of a stroke, the higher of two strokes by :func:`_rank`. The passes'
    patches are composed together by the same graph cut, each only on the pixels of
    its own pass (its sample within :data:`_SAME_PASS` patch radii along the stroke
    of the pixel's owner), so the top pass lies whole, with its outline, and the
    others resume around it. Beyond the paper.
    """
    h, w = out.shape[:2]
    r0 = min(b[0].start for _, _, b in cluster)
    r1 = max(b[0].stop for _, _, b in cluster)
    c0 = min(b[1].start for _, _, b in cluster)
    c1 = max(b[1].stop for _, _, b in cluster)
    box = (slice(r0, r1), slice(c0, c1))
    spans: dict = {}
    for _, stretches, _ in cluster:
        for k, s0, s1, wk in stretches:
            a, b, ww = spans.get(k, (s0, s1, wk))
            spans[k] = (min(a, s0), max(b, s1), max(ww, wk))
    band = np.zeros((r1 - r0, c1 - c0), bool)
    for k, (s0, s1, wk) in spans.items():
        band |= _band(attached[k].target, s0, s1, wk, box)
    lab = labels[box]
    if ((lab >= 0) & band & ~np.isin(stroke_of[lab], list(spans))).any():
        # (another stroke or a carried part within the passes' bands -- tentacles crowding at an
        # octopus's head --: its joints and outline are others' business, left as the cut laid them)
        return
    rank = _rank(index, list(spans))
    # owner of each pixel: (stroke, arc length) of the top pass whose silhouette covers it, by
    # painting the passes' disks from the lowest key up (the last painted wins)
    own_k = np.full((r1 - r0, c1 - c0), -1, np.intp)
    own_s = np.zeros((r1 - r0, c1 - c0))
    for k in sorted(spans, key=rank.get):
        s0, s1, wk = spans[k]
        s = np.arange(s0, s1 + 0.25, 0.5)
        pts = attached[k].target.point_at(s)
        rad = index.edge_width(k, attached[k].source_arc_length(s)) + 1.0
        for si, (x, y), rr in zip(s, pts, rad):
            y0, y1 = max(int(y - rr) - r0, 0), min(int(y + rr) + 2 - r0, r1 - r0)
            x0, x1 = max(int(x - rr) - c0, 0), min(int(x + rr) + 2 - c0, c1 - c0)
            if y0 >= y1 or x0 >= x1:
                continue
            yy, xx = np.ogrid[y0 + r0:y1 + r0, x0 + c0:x1 + c0]
            disk = np.hypot(xx - x, yy - y) <= rr
            own_k[y0:y1, x0:x1][disk] = k
            own_s[y0:y1, x0:x1][disk] = si
    sub = []
    for pp, where in zip(placed, laid):
        if where is None or where[0] not in spans:
            continue
        k, s_p = where[0], where[1]
        rad = 0.5 * pp.valid.shape[0]
        s0, s1, _ = spans[k]
        if s_p + rad < s0 or s_p - rad > s1:
            continue
        valid = (pp.valid if where[2] is None else where[2]).copy()
        # (only on its own pass's pixels, or on those no pass covers)
        ox, oy = int(pp.origin[0]) - c0, int(pp.origin[1]) - r0
        n = valid.shape[0]
        a0, a1, b0, b1 = max(oy, 0), min(oy + n, r1 - r0), max(ox, 0), min(ox + n, c1 - c0)
        if a0 < a1 and b0 < b1:
            ok_k, ok_s = own_k[a0:a1, b0:b1], own_s[a0:a1, b0:b1]
            mine = (ok_k < 0) | ((ok_k == k) & (np.abs(ok_s - s_p) <= _SAME_PASS * rad))
            valid[a0 - oy:a1 - oy, b0 - ox:b1 - ox] &= mine
        if valid.any():
            sub.append(dataclasses.replace(pp, valid=valid, origin=(ox, oy)))
    if not sub:
        return
    comp = compose(sub, (r1 - r0, c1 - c0), method=method, power=power, gradient_weighted=gradient_weighted)
    pm = comp.image
    lay = np.zeros((*pm.shape[:2], 4), np.float32)
    a = pm[..., 3]
    nz = a > 1e-6
    lay[nz, :3] = np.clip(pm[nz, :3] / a[nz, None], 0.0, 1.0)
    lay[..., 3] = a
    region = band & comp.covered
    cur = out[box].copy()
    # the passes' own pixels in the region are redrawn where the new layer lays them opaque (other
    # parts' stay under them); elsewhere the new layer goes over the old pixels: no hole is opened
    # (on a 3-petal rose the slivers between a petal's sides, off both passes' silhouettes, were
    # cleared into 1-px cracks; half-clear edges thinned the coil's tubes)
    mine = np.isin(stroke_of[labels[box]], list(spans)) & region & (lay[..., 3] > 0.5)
    cur[mine] = 0.0
    _over_into(cur, lay, region & (lay[..., 3] > _CLEAR))
    out[box][region] = cur[region]
