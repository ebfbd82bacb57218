"""A part moved over another part is drawn over it, with its own outline (beyond the paper).

The graph cut of :func:`~branchnb.strokes.composition.compose` stitches the
patches of every stroke into one silhouette. Where an edit lays one part over
another part it was apart from in the source (a finger bent so that its tip lies
over the next finger's tip), the cut runs wherever the two textures agree best:
the two parts merge into one silhouette with a faint seam and no outline between
them. An artist draws the moved part over the other one, its outline across the
other's flesh. Here each stroke's patches are laid alone (every pixel from the
patch whose centre lies nearest), and where two strokes' own silhouettes overlap
on flesh that was not shared in the source, the stroke that moved more there is
drawn over the result.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.distance import edt as _edt

__all__: list[str] = []

#: Alpha from which a stroke's own (laid alone) pixel is flesh.
_FLESH = 0.5
#: Source points of two strokes' pixels nearer than this (px, + the outline's width) are the
#: same flesh (a joint, a crossing that stays): not an overlap the edit made.
_SHARED = 3.0
#: A stroke moved less than this (px) at an overlap did not move there.
_STILL = 2.0
#: Overlaps smaller than this (px) are left to the graph cut (touching, not lying over).
_MIN_OVERLAP = 12


def _solo(placed: list, shape) -> dict:
    """``stroke -> (box, premult, src)``: each stroke's patches laid alone on the box of its
    patches, every pixel from the covering patch whose centre lies nearest (``src``: the
    source ``(x, y)`` of every pixel, NaN where none)."""
    h, w = shape
    by: dict = {}
    for pp in placed:
        if pp.stroke is None or pp.stroke < 0 or pp.source_map is None:
            continue
        by.setdefault(pp.stroke, []).append(pp)
    out = {}
    for k, pps in by.items():
        x0 = max(min(p.origin[0] for p in pps), 0)
        y0 = max(min(p.origin[1] for p in pps), 0)
        x1 = min(max(p.origin[0] + p.valid.shape[1] for p in pps), w)
        y1 = min(max(p.origin[1] + p.valid.shape[0] for p in pps), h)
        if x0 >= x1 or y0 >= y1:
            continue
        pm = np.zeros((y1 - y0, x1 - x0, 4), np.float32)
        src = np.full((y1 - y0, x1 - x0, 2), np.nan, np.float32)
        best = np.full((y1 - y0, x1 - x0), np.inf, np.float32)
        for p in pps:
            s = p.valid.shape[0]
            ox, oy = p.origin
            a0, a1 = max(oy, y0), min(oy + s, y1)
            b0, b1 = max(ox, x0), min(ox + s, x1)
            if a0 >= a1 or b0 >= b1:
                continue
            pv = (slice(a0 - oy, a1 - oy), slice(b0 - ox, b1 - ox))
            cv = (slice(a0 - y0, a1 - y0), slice(b0 - x0, b1 - x0))
            yy, xx = np.mgrid[a0:a1, b0:b1]
            d = np.hypot(xx - (ox + 0.5 * s), yy - (oy + 0.5 * s)).astype(np.float32)
            take = p.valid[pv] & (p.pixels[pv][..., 3] > 0.02) & (d < best[cv])
            if not take.any():
                continue
            best[cv][take] = d[take]
            pm[cv][take] = p.pixels[pv][take]
            m = p.source_map
            src[cv][take] = np.c_[m[0, 0] * xx[take] + m[0, 1] * yy[take] + m[0, 2],
                                  m[1, 0] * xx[take] + m[1, 1] * yy[take] + m[1, 2]]
        out[k] = ((slice(y0, y1), slice(x0, x1)), pm, src)
    return out


def _cut(item, r0: int, r1: int, c0: int, c1: int):
    """A stroke's laid-alone pixels and source places on the canvas box ``[r0:r1, c0:c1]``."""
    (rs, cs), pm, src = item
    pm_out = np.zeros((r1 - r0, c1 - c0, 4), np.float32)
    src_out = np.full((r1 - r0, c1 - c0, 2), np.nan, np.float32)
    a0, a1 = max(r0, rs.start), min(r1, rs.stop)
    b0, b1 = max(c0, cs.start), min(c1, cs.stop)
    if a0 < a1 and b0 < b1:
        pm_out[a0 - r0:a1 - r0, b0 - c0:b1 - c0] = pm[a0 - rs.start:a1 - rs.start, b0 - cs.start:b1 - cs.start]
        src_out[a0 - r0:a1 - r0, b0 - c0:b1 - c0] = src[a0 - rs.start:a1 - rs.start, b0 - cs.start:b1 - cs.start]
    return pm_out, src_out


def _overlaid_parts(layer: np.ndarray, placed: list, junctions: list, index, attached,
                   width: float = 0.0) -> np.ndarray:
    """``layer`` (straight RGBA) with every stroke moved over another stroke's flesh drawn
    over it as it is alone (its rim, the outline of an outlined source, across the
    other's flesh).

    Pairs joined by a junction are judged only beyond both parts' half widths +
    ``width`` + 2 px of the junction (the joint is closed as before); flesh both
    strokes copy from the same source place (within :data:`_SHARED` + ``width`` px:
    a joint, a crossing that stays), or whose source place lies that near the other
    stroke's own flesh in the source (two tentacles' roots), is no overlap. The stroke that moved more over
    the overlap (its pixels' mean distance to their source) lies on top, and only
    within three of its half widths of its tip (a part that ends over another; a
    curled tentacle crossing others on its way is left as the cut laid it); a stroke
    hidden by the other in the source stays under it. ``width``: the outline's
    width (0: none).
    """
    shape = layer.shape[:2]
    solo = _solo(placed, shape)
    keys = sorted(solo)
    if len(keys) < 2:
        return layer
    apart: dict = {}

    def away(k, src):
        # px from each pixel's source place to stroke k's own flesh in the source
        if k not in apart:
            # (OpenCV's exact transform: SciPy's values, ~4x faster on a large canvas)
            apart[k] = _edt(~(index.allowed[k] & index.object))
        d = apart[k]
        hs, ws = d.shape
        x = np.clip(np.rint(np.nan_to_num(src[..., 0], nan=-1)), -1, ws).astype(np.intp)
        y = np.clip(np.rint(np.nan_to_num(src[..., 1], nan=-1)), -1, hs).astype(np.intp)
        ok = (x >= 0) & (x < ws) & (y >= 0) & (y < hs)
        out = np.zeros(src.shape[:2], np.float32)
        out[ok] = d[y[ok], x[ok]]
        return out
    h, w = shape
    m = int(np.ceil(width)) + 3
    out = None
    for a_i, i in enumerate(keys):
        for j in keys[a_i + 1:]:
            (ri, ci), (rj, cj) = solo[i][0], solo[j][0]
            r0, r1 = max(ri.start, rj.start), min(ri.stop, rj.stop)
            c0, c1 = max(ci.start, cj.start), min(ci.stop, cj.stop)
            if r1 - r0 < 2 or c1 - c0 < 2:
                continue
            # (the boxes' overlap, grown by the top part's rim round it)
            r0, r1, c0, c1 = max(r0 - m, 0), min(r1 + m, h), max(c0 - m, 0), min(c1 + m, w)
            fi, si = _cut(solo[i], r0, r1, c0, c1)
            fj, sj = _cut(solo[j], r0, r1, c0, c1)
            yy, xx = np.mgrid[r0:r1, c0:c1]
            box = (slice(r0, r1), slice(c0, c1))
            both = (fi[..., 3] > _FLESH) & (fj[..., 3] > _FLESH)
            if int(both.sum()) < _MIN_OVERLAP:
                continue
            shared = np.hypot(si[..., 0] - sj[..., 0], si[..., 1] - sj[..., 1]) <= _SHARED + width
            both &= ~shared
            if not both.any():
                continue
            # (flesh that touched the other part's in the source: the roots of two tentacles)
            both &= (away(j, si) > _SHARED + width) & (away(i, sj) > _SHARED + width)
            for jn in junctions:
                if {jn.child, jn.parent} != {i, j}:
                    continue
                hw = float(index.half_width(jn.parent, attached[jn.parent].source_arc_length(jn.parent_s)))
                hc = float(np.max(index.half_width(jn.child, np.array([0.0, attached[jn.child].source.length]))))
                r = hw + hc + width + 2.0
                both &= np.hypot(xx - jn.point[0], yy - jn.point[1]) > r
            if int(both.sum()) < _MIN_OVERLAP:
                continue
            mi = float(np.mean(np.hypot(xx[both] - si[both][:, 0], yy[both] - si[both][:, 1])))
            mj = float(np.mean(np.hypot(xx[both] - sj[both][:, 0], yy[both] - sj[both][:, 1])))
            if max(mi, mj) < _STILL:
                continue
            top, ft = (i, fi) if mi >= mj else (j, fj)
            bottom = j if top == i else i
            if bottom in index.views and top in (index.hidden_by.get(bottom) or ()):
                pass
            elif top in index.views and bottom in (index.hidden_by.get(top) or ()):
                top, ft = bottom, (fj if bottom == j else fi)
            # only where the top part ends over the other (a finger bent over its neighbour's
            # tip), not where it crosses it on its way (a curled tentacle over the others)
            tip = attached[top].target.points[-1]
            reach = 3.0 * float(np.max(index.width[top]))
            both &= np.hypot(xx - tip[0], yy - tip[1]) <= reach + width + 2.0
            if int(both.sum()) < _MIN_OVERLAP:
                continue
            # the top part's pixels over (and round, its rim) the overlap
            near = ndi.binary_dilation(both, iterations=int(np.ceil(width)) + 2)
            paint = near & (ft[..., 3] > 0.02)
            if not paint.any():
                continue
            if out is None:
                out = layer.copy()
            sub = out[box]
            a = ft[paint][:, 3:4]
            la = sub[paint][:, 3:4]
            pm = ft[paint][:, :3] + sub[paint][:, :3] * la * (1.0 - a)
            na = a + la * (1.0 - a)
            sub[paint, :3] = np.where(na > 1e-6, pm / np.maximum(na, 1e-6), 0.0)
            sub[paint, 3] = na[:, 0]
    return layer if out is None else out


#: Alpha below which a result pixel is background for :func:`_solid_cracks`.
_CLEAR = 0.02
#: Alpha from which a pixel is opaque.
_OPAQUE = 0.98


def _solid_cracks(layer: np.ndarray, source_alpha: np.ndarray) -> np.ndarray:
    """``layer`` with the see-through pixels inside the object made opaque.

    A patch's pixels are weighted by its tube's one-pixel ramp where the tube cuts the
    object; where two fingers' tubes meet below the crotch between them and the palm
    does not cover the ramps, a crack of half-transparent pixels runs on from the
    crotch's bottom into the palm: white and grey ticks in the outline over a white
    background. For a source with a hard alpha (none half-transparent), pixels with
    0.02 < alpha < 0.98 at least 1.5 px inside the silhouette (from alpha <= 0.02)
    are set opaque, colour unchanged.
    """
    a = layer[..., 3]
    part = (a > _CLEAR) & (a < _OPAQUE)
    if not part.any():
        return layer
    if ((source_alpha > _CLEAR) & (source_alpha < _OPAQUE)).any():
        # (an anti-aliased source: half-transparent ink there made opaque turned into dark
        # blobs at an octopus's turned tentacles; left as laid)
        return layer
    cand = part & (ndi.distance_transform_edt(a > _CLEAR) >= 1.5)
    if not cand.any():
        return layer
    out = layer.copy()
    out[cand, 3] = 1.0
    return out
