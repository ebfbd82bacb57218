"""What another part hides of a stroke's tube, filled in from the stroke's own pixels.

In the source a part may lie over a stroke's tube (a berry hanging over a
leaf, a stalk drawn into the leaf it passes under). Those pixels belong to
the part: the stroke's patches may not copy them, so a copied leaf showed a
notch where the berry had been (the berry's outline round it, the berry's
faint anti-aliased rim as grey arcs in the background). Here each such
stroke gets its own view of the source: the hidden pixels of its tube (and
the ring of the part's rim round them) hold the stroke's own flesh, outline
and background, copied from farther along its centre line at the same
distance from its silhouette's edge. Beyond the paper, which assumes every
stroke's tube is visible in the source.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.distance import edt as _edt
from ..core.graphcut import gradient_magnitude
from .attachment import _own_area
from .outline import outline_style
from .tubes import _tube_margin

#: The other part's pixels grown by this much (px): its anti-aliased rim and outline go with it.
_RIM = 2
#: ... and the stroke's own pixels used as a reference keep this far from them (px).
_CLEAR = 3
#: Steps along the centre line (a share of the local half width, >= 1 px) tried for a clean copy.
_STEP = 0.25
#: Another part hides the stroke where it reaches within this share of the stroke's half width.
_DEEP = 0.6
#: A joined end (a leaf's root on its twig) is left alone within this many of its parent's widths.
_END_REACH = 2.5


def _own_views(index, tubes: dict, keys: list, cuts: list, joined: list, window: float = 3.0,
               by: dict | None = None) -> dict:
    """Per stroke with a hidden stretch: ``(premult, depth, grad, hidden)`` with it filled in.

    ``tubes``: per ``(key, cuts)`` the ``(d, s_map, tube, interior, endw, core)``
    of :func:`~branchnb.strokes.source.source_index`'s first pass. Only for
    objects with an alpha channel. ``hidden`` is the full-size mask of the
    pixels filled (the stroke may copy them). ``by``, if given, gets per
    stroke with a view the strokes whose tubes hide it (None: a part does).
    """
    h, w = index.shape
    n = len(index.strokes)
    views: dict = {}
    done: dict = {}
    done_by: dict = {}
    for k in range(n):
        key = (keys[k], cuts[k])
        if key in done:
            if done[key] is not None:
                views[k] = done[key]
                if by is not None:
                    by[k] = done_by[key]
            continue
        done[key] = None
        # strokes joined to this one (its parent, its children) share its pixels at the joint
        related = {k} | {j for j in joined[k] if j >= 0} | {j for j in range(n) if k in joined[j]}
        related |= {j for j in range(n) if keys[j] == keys[k]}
        rel_keys = {keys[j] for j in related}
        d, s_map, tube, interior, endw, _ = tubes[key]
        rows, cols = np.nonzero(d < 1e5)
        if not len(rows):
            continue
        box = (slice(rows.min(), rows.max() + 1), slice(cols.min(), cols.max() + 1))
        db, sb, tb = d[box], s_map[box], tube[box]
        st = index.strokes[k]
        zone = (db <= tb + _tube_margin(tb)) & interior[box] & (endw[box] > 0.5)
        for end, par in enumerate(joined[k]):
            if par >= 0:
                reach = _END_REACH * float(np.max(index.width[par])) + 4.0
                zone &= (sb > reach) if end == 0 else (sb < st.length - reach)
        if not zone.any():
            continue
        reach_k = _END_REACH * float(np.median(index.width[k])) + 4.0
        foreign = np.zeros(zone.shape, bool)
        causes = []  # (strokes, their tube's pixels here); None: a part's
        for okey, tb_o in tubes.items():
            if okey[0] not in rel_keys:
                # another stroke's tube crossing this one's, away from both strokes' ends
                # (siblings leaving a palm side by side overlap at their roots: no hiding there)
                o = next(j for j in range(n) if keys[j] == okey[0])
                reach_o = _END_REACH * float(np.median(index.width[o])) + 4.0
                ends_k, ends_o = st.points[[0, -1]], index.strokes[o].points[[0, -1]]
                near_ends = 2.0 * max(float(np.median(index.width[k])), float(np.median(index.width[o]))) + 4.0
                if np.hypot(*(ends_k[:, None] - ends_o[None]).transpose(2, 0, 1)).min() < near_ends:
                    continue  # (a delta's distributaries leaving one fan head overlap there)
                so = tb_o[1][box]
                cross = tb_o[5][box] & (so > reach_o) & (so < index.strokes[o].length - reach_o)
                foreign |= cross
                causes.append(({j for j in range(n) if keys[j] == okey[0]}, cross))
        foreign &= (sb > reach_k) & (sb < st.length - reach_k)
        near = np.zeros(zone.shape, bool)  # the related strokes' own tubes (not a clean reference)
        for okey, tb_o in tubes.items():
            if okey[0] in rel_keys and okey[0] != keys[k]:
                near |= tb_o[5][box]
        # strokes joined at one of this one's ends (a flower's head on its stem's tip)
        at_end = {keys[j] for j in joined[k] if j >= 0}
        for j in range(n):
            for e, par in enumerate(joined[j]):
                if par == k:
                    sj = st.project(index.strokes[j].points[[0 if e == 0 else -1]])[0][0]
                    if sj <= reach_k or sj >= st.length - reach_k:
                        at_end.add(keys[j])
        for part in index.parts:
            if part.over is not None and keys[part.stroke] == keys[k]:
                # (a part hanging from this stroke hides it only where it lies over it)
                sub = np.zeros((h, w), bool)
                sub[part.box] = part.over
                foreign |= sub[box]
                causes.append((None, sub[box]))
                continue
            # (a part hanging from a stroke joined at this one's end -- a flower's petals
            # round the head on its stem's tip -- lies where the joint is: no hiding there)
            if keys[part.stroke] == keys[k] or keys[part.stroke] in at_end:
                continue
            sub = np.zeros((h, w), bool)
            sub[part.box] = part.mask
            foreign |= sub[box]
            causes.append((None, sub[box]))
        foreign &= zone
        if not foreign.any():
            continue
        # only what covers the stroke's own flesh (well inside its width), not what merely
        # touches its margin (a neighbouring finger's side at a crotch)
        lab, nlab = ndi.label(foreign, structure=np.ones((3, 3)))
        deep = np.unique(lab[foreign & (db <= _DEEP * np.interp(sb, index.width_s[k], index.edge[k]))])
        foreign = np.isin(lab, deep[deep > 0])
        if not foreign.any():
            continue
        # who hides it: strokes whose tubes cross it, or None if a part does
        cause: set | None = set()
        for who, m in causes:
            if (m & foreign).any():
                if who is None:
                    cause = None
                    break
                cause |= who
        hidden = zone & ndi.binary_dilation(foreign, iterations=_RIM)
        # (the reference is the stroke's own tube: no part, not even one hanging from it)
        # and only pixels it may copy (not a tip-held part's, taken back from its tube)
        mine = index.allowed[k][box] & (index.weight[k][box] > 0.5)
        clean = zone & ~ndi.binary_dilation(foreign | near | index.part_mask[box] | ~mine, iterations=_CLEAR)
        # the silhouette's width along the hidden stretch is the other part's: bridged
        # linearly from the stroke's own widths on either side
        ws, we = index.width_s[k], np.asarray(index.edge[k], float)
        sf = sb[hidden]
        lost = (ws >= sf.min() - _CLEAR) & (ws <= sf.max() + _CLEAR)
        if lost.any() and not lost.all():
            we = we.copy()
            we[lost] = np.interp(ws[lost], ws[~lost], we[~lost])
        for part in index.parts:
            # a part the stroke's tip ends in (a cherry on its stalk): its tube there is the
            # part's flesh, no reference
            if part.tip is None or keys[part.stroke] != keys[k]:
                continue
            sub = np.zeros((h, w), bool)
            sub[part.box] = part.mask
            sp = sb[sub[box] & (db < 1e5)]
            if len(sp):
                tip_end = st.project(np.array([part.tip[:2]], float))[0][0] > 0.5 * st.length
                clean &= (sb < sp.min() - _CLEAR) if tip_end else (sb > sp.max() + _CLEAR)
        # (nor flesh deeper inside the object than the stroke's own half width: a wider
        # part its tube runs into -- a cherry round a stalk's tip)
        clean &= index.depth[box] <= np.interp(sb, ws, we) + 2.0
        got = _refill(index, k, box, hidden, clean, window, ws, we)
        if got is None:
            continue
        filled, vals, dep = got
        premult = index.premult.copy()
        depth = index.depth.copy()
        full = np.zeros((h, w), bool)
        full[box] = filled
        premult[full] = vals
        depth[full] = dep
        rs, cs = np.nonzero(full)
        g0, g1 = max(rs.min() - 2, 0), min(rs.max() + 3, h)
        c0, c1 = max(cs.min() - 2, 0), min(cs.max() + 3, w)
        grad = index.grad.copy()
        # (the edge strength on the filled pixels' box: the same Sobel as the source's)
        grad[g0:g1, c0:c1] = gradient_magnitude(premult[max(g0 - 2, 0):g1 + 2, max(c0 - 2, 0):c1 + 2])[
            g0 - max(g0 - 2, 0):g1 - max(g0 - 2, 0), c0 - max(c0 - 2, 0):c1 - max(c0 - 2, 0)]
        done[key] = views[k] = (premult, depth, grad, full)
        done_by[key] = cause
        if by is not None:
            by[k] = cause
    return views


def _refill(index, k: int, box, hidden: np.ndarray, clean: np.ndarray, window: float, ws: np.ndarray,
            we: np.ndarray):
    """Values for ``hidden`` (box coordinates) from ``clean`` pixels of stroke ``k`` farther along it.

    Each pixel keeps its signed distance to the silhouette's edge (so the
    outline keeps its width on a tapering part); both ways are averaged where
    both reach a clean pixel at the same step.
    """
    st = index.strokes[k]
    rs, cs = np.nonzero(hidden)
    pts = np.c_[cs + box[1].start, rs + box[0].start].astype(float)
    s0, _ = st.project(pts)
    foot = st.point_at(s0)
    e0 = ((pts - foot) * st.normal_at(s0, window=window)).sum(axis=1)
    w0 = np.interp(s0, ws, we)
    sign = np.where(e0 < 0, -1.0, 1.0)
    step = np.maximum(_STEP * float(np.median(w0)), 1.0)
    acc = np.zeros((len(pts), 4))
    accd = np.zeros(len(pts))
    found = np.zeros(len(pts), bool)
    premult = index.premult
    by, bx = box[0].start, box[1].start
    hb, wb = clean.shape
    j = 1
    while not found.all() and (j - 1) * step <= st.length:
        cnt = np.zeros(len(pts))
        for way in (1.0, -1.0):
            todo = np.nonzero(~found)[0]
            s2 = s0[todo] + way * j * step
            inside = (s2 >= 0.0) & (s2 <= st.length)
            todo, s2 = todo[inside], s2[inside]
            if not len(todo):
                continue
            e2 = e0[todo] + sign[todo] * (np.interp(s2, ws, we) - w0[todo])
            e2 = np.where(e2 * sign[todo] < 0, 0.0, e2)  # not across the centre line
            q = st.point_at(s2) + e2[:, None] * st.normal_at(s2, window=window)
            qi = np.rint(q).astype(int)
            ok = (qi[:, 0] >= bx) & (qi[:, 0] < bx + wb) & (qi[:, 1] >= by) & (qi[:, 1] < by + hb)
            ok[ok] = clean[qi[ok, 1] - by, qi[ok, 0] - bx]
            todo, q = todo[ok], q[ok]
            if not len(todo):
                continue
            for c in range(4):
                acc[todo, c] += ndi.map_coordinates(premult[..., c], [q[:, 1], q[:, 0]], order=1, mode="nearest")
            accd[todo] += ndi.map_coordinates(index.depth, [q[:, 1], q[:, 0]], order=1, mode="nearest")
            cnt[todo] += 1
        hit = cnt > 0
        acc[hit] /= cnt[hit, None]
        accd[hit] /= cnt[hit]
        found |= hit
        j += 1
    if not found.any():
        return None
    filled = np.zeros_like(hidden)
    filled[rs[found], cs[found]] = True
    return filled, acc[found].astype(np.float32), accd[found].astype(np.float32)


#: Colour distance (straight RGB in [0, 1]) from the stroke's own look (filled in from farther
#: along it) above which a pixel of its tube next to a part hanging from it is that part's.
_OVER_DIFF = 0.2
#: ... and within this of one of the part's own colours (its flesh, its outline).
_OVER_OWN = 0.2
#: Least share of those pixels that look like the part for it to lie over the stroke.
_OVER_SHARE = 0.5
#: Disk (radius 2 px) closing the gap where the part's outline meets the stroke's.
_DISK = np.hypot(*np.mgrid[-2:3, -2:3]) <= 2.0
#: Least pixels of the part deep in the stroke's flesh (within :data:`_DEEP` of its half width).
_OVER_DEEP = 4
#: A part's outline ink crossing the stroke's flesh (inside the stroke's own outline) in at
#: least this many px is drawn over the stroke (a flower's leaf over its stem at 200 px: 10-20 px).
_OVER_INK = 4
#: ... else its flesh's median colour this far (RGB) from the stroke's (a cherry's red over a brown twig).
_OVER_COLOUR = 0.2
#: Colour distance (RGB) within which a pixel is the outline's ink.
_OVER_INKED = 0.1


#: :func:`_parts_over`: a part more than this many times the area of the stroke's own piece is the
#: rest of the object (the rope_loop sample's loop beside a stroked stretch of it: 110k px against
#: the piece's 18k), not a part lying over the stroke; taken as one, the rope's stretch was refilled
#: from farther along and its strands came out 1.4 times as long (notebook 05's sampling figure).
_OVER_MOST_AREA = 2.0
#: :func:`_parts_over`: a pixel differs from the stroke's own look only if it differs from all of
#: the look within this many px (the look filled in from farther along lands its rim a pixel off).
_OVER_SHIFT = 1


def _parts_over(index, tubes: dict, keys: list, cuts: list, joined: list, window: float = 3.0) -> None:
    """Give every part lying over the stroke it hangs from the pixels of its that the
    stroke's tube claimed (``Part.over``; ``Part.mask`` and ``index.part_mask`` grow by them).

    A leaf drawn over its stem with its base across the stem: the stem's tube
    (bridged over the leaf, see :func:`~branchnb.strokes.tubes._without_side_bumps`)
    holds the leaf's base, its outline across the stem. The stem's patches copied
    it along the bent stem and the carried leaf, cut at the tube, came out
    tucked behind the stem (the stem's outline across the leaf's base). Here the
    stroke's own look at its tube's pixels round the part is filled in from
    farther along it (:func:`_refill`); the pixels that differ from it by over
    :data:`_OVER_DIFF`, joined to the part, most of them within :data:`_OVER_OWN`
    of one of the part's own colours and some deep in the stroke's flesh (at
    least :data:`_OVER_DEEP` px), with the holes they close round the part's
    flesh, are the part's: it carries them over the stroke (the stroke sees its
    own flesh there, :func:`_own_views`). A part drawn under the stroke leaves
    the stroke's look as it is: nothing is taken. A part whose outline does
    not cross the stroke's flesh and whose flesh is of the stroke's colour (a
    piece of a striped body the stroke's tube cut off) is none. Beyond the paper.
    Measured on procedural scenes (flower, cherries on a twig,
    an arm over a body; 200 / 400 / 800 px, 2 seeds, bowed both ways): the
    share of the joint's overlap showing the part, source 1.00, went from 0.72
    (worst 0.31) to 0.93 (worst 0.73) on the flower, 0.88 to 0.90 on the
    others; parts drawn under stay under (0.00-0.05, unchanged).
    Off the stroke's core a pixel differs from the look only if it differs from
    all of it within :data:`_OVER_SHIFT` px: the look, filled in from farther
    along, lands the stroke's rim a pixel off, and a fern's pinna took a strip
    of the rachis's rim between two knobs (laid again stair-stepped, dark
    specks). Measured on the strokes tests' fern edit (300 / 600 / 900 px, 3
    seeds; windows round the six untouched pinna roots): new dark pixels
    15-203 -> 2-19, pixels changed 31-313 -> 6-63 (at 900 px dark 153-203 ->
    2-3; with no part taken at all 2 at 900 px, 15 at 600); the scenes above
    within 0.01 of before, the other objects of the strokes tests and the
    bench edits pixel-identical.
    """
    h, w = index.shape
    by_key: dict = {}
    for pi, part in enumerate(index.parts):
        if part.contact and not part.at_end and not part.body and part.tip is None \
                and part.area <= _OVER_MOST_AREA * _own_area(index, part.stroke):
            by_key.setdefault((keys[part.stroke], cuts[part.stroke]), []).append(pi)
    if not by_key:
        return
    rgb = index.premult[..., :3] / np.maximum(index.premult[..., 3:], 1e-6)
    style = outline_style(index.premult, index.depth)
    if style is not None:
        colour, width = np.asarray(style.colour, np.float32), float(style.width)
    for key, pis in by_key.items():
        k = index.parts[pis[0]].stroke
        d, s_map, tube, interior, endw, core = tubes[key]
        rows, cols = np.nonzero(d < 1e5)
        if not len(rows):
            continue
        box = (slice(rows.min(), rows.max() + 1), slice(cols.min(), cols.max() + 1))
        db, sb = d[box], s_map[box]
        ws, we = index.width_s[k], np.asarray(index.edge[k], float)
        # the stroke's own pixels (no other stroke's tube, not past its ends)
        zone = core[box] & interior[box] & (endw[box] > 0.5)
        for okey, tb_o in tubes.items():
            if okey[0] != key[0]:
                zone &= ~tb_o[5][box]
        near = np.zeros(zone.shape, bool)
        masks = {}
        for pi in pis:
            part = index.parts[pi]
            # the tube's pixels within its width across of the part (on the part's box grown by that)
            reach = 2.0 * float(np.interp(part.s, ws, we)) + 3.0
            g = int(np.ceil(reach)) + 1
            r0, r1 = max(part.box[0].start - g, box[0].start), min(part.box[0].stop + g, box[0].stop)
            c0, c1 = max(part.box[1].start - g, box[1].start), min(part.box[1].stop + g, box[1].stop)
            if r0 >= r1 or c0 >= c1:
                continue
            m = np.zeros((r1 - r0, c1 - c0), bool)
            a0, a1 = max(part.box[0].start, r0), min(part.box[0].stop, r1)
            b0, b1 = max(part.box[1].start, c0), min(part.box[1].stop, c1)
            m[a0 - r0:a1 - r0, b0 - c0:b1 - c0] = part.mask[a0 - part.box[0].start:a1 - part.box[0].start,
                                                            b0 - part.box[1].start:b1 - part.box[1].start]
            if not m.any():
                continue
            loc = (slice(r0 - box[0].start, r1 - box[0].start), slice(c0 - box[1].start, c1 - box[1].start))
            masks[pi] = (loc, m)
            near[loc] |= zone[loc] & (_edt(~m) <= reach)
        for loc, m in masks.values():
            near[loc] &= ~m
        if not near.any():
            continue
        mine = index.allowed[k][box] & (index.weight[k][box] > 0.5)
        clean = zone & ~ndi.binary_dilation(near | index.part_mask[box] | ~mine, iterations=_CLEAR)
        edge_b = np.interp(sb, ws, we)
        got = _refill(index, k, box, near, clean, window, ws, we)
        if got is None:
            continue
        filled = got[0]
        look = np.zeros((*zone.shape, 4), np.float32)
        look[filled] = got[1]
        look[..., :3] /= np.maximum(look[..., 3:], 1e-6)
        src = rgb[box]
        diff = filled & (np.linalg.norm(src - look[..., :3], axis=-1) > _OVER_DIFF)
        # (off the stroke's core, a pixel the look shows a pixel away is the stroke's rim landed
        # off by the refill, not the part's: a fern's rachis rim was taken between two pinnae)
        diff &= (db <= _DEEP * edge_b) | (_shifted_diff(src, look[..., :3], filled) > _OVER_DIFF)
        if style is not None:
            ink = (np.linalg.norm(src - colour, axis=-1) <= _OVER_INKED) & (index.premult[box][..., 3] > 0.5)
            look_ink = np.linalg.norm(look[..., :3] - colour, axis=-1) <= _OVER_INKED  # (look: alpha 1 inside)
        else:
            ink, look_ink = None, np.zeros(zone.shape, bool)
        for pi, (loc, mb) in masks.items():
            part = index.parts[pi]
            df, nr, sl = diff[loc], near[loc], src[loc]
            # (joined across the ink the two outlines share where the part's leaves the stroke's)
            lab, _ = ndi.label(ndi.binary_closing(df | mb, structure=_DISK) & (nr | mb), structure=np.ones((3, 3)))
            joins = np.unique(lab[mb])
            over = df & np.isin(lab, joins[joins > 0])
            if not over.any():
                continue
            # most of them look like the part (its flesh or its outline), not like the stroke
            solid = mb & (index.premult[box][loc][..., 3] > 0.5)
            own = sl[solid]
            if len(own) > 256:
                own = own[np.linspace(0, len(own) - 1, 256).astype(int)]
            dist = np.min(np.linalg.norm(sl[over][:, None] - own[None], axis=-1), axis=1)
            if (dist <= _OVER_OWN).mean() < _OVER_SHARE:
                continue
            # and the part is drawn over the stroke: its outline crosses the stroke's flesh (ink
            # inside the stroke's own outline where the stroke shows none), or its flesh is of
            # another colour than the stroke's (a piece of a striped body the stroke's tube cut
            # off differs from the stripes filled in, yet is neither)
            if ink is not None:
                inner = over & ink[loc] & ~look_ink[loc] & (db[loc] < edge_b[loc] - width - 0.5)
                drawn = int(inner.sum()) >= _OVER_INK
            else:
                drawn = False
            if not drawn:
                flesh = solid & ~ink[loc] if ink is not None else solid
                theirs = filled[loc] & ~look_ink[loc]
                drawn = bool(flesh.any() and theirs.any()) and float(np.linalg.norm(
                    np.median(sl[flesh], axis=0) - np.median(look[loc][theirs][:, :3], axis=0))) > _OVER_COLOUR
            if not drawn:
                continue
            # the holes they close round the part's flesh (flesh of the stroke's colour under it)
            over |= ndi.binary_fill_holes(ndi.binary_closing(over | mb, structure=_DISK) | mb) & nr & ~mb
            if int((over & (db[loc] <= _DEEP * edge_b[loc])).sum()) < _OVER_DEEP:
                continue
            _give(part, over, (slice(box[0].start + loc[0].start, box[0].start + loc[0].stop),
                               slice(box[1].start + loc[1].start, box[1].start + loc[1].stop)), index)


def _shifted_diff(src: np.ndarray, look: np.ndarray, filled: np.ndarray, shift: int = _OVER_SHIFT) -> np.ndarray:
    """Colour distance of ``src`` to the nearest of ``look``'s ``filled`` pixels within ``shift`` px."""
    h, w = filled.shape
    best = np.full((h, w), np.inf, np.float32)
    for dy in range(-shift, shift + 1):
        for dx in range(-shift, shift + 1):
            ys, yd = slice(max(dy, 0), h + min(dy, 0)), slice(max(-dy, 0), h + min(-dy, 0))
            xs, xd = slice(max(dx, 0), w + min(dx, 0)), slice(max(-dx, 0), w + min(-dx, 0))
            dist = np.linalg.norm(src[yd, xd] - look[ys, xs], axis=-1)
            np.minimum(best[yd, xd], np.where(filled[ys, xs], dist, np.inf), out=best[yd, xd])
    return best


def _give(part, over: np.ndarray, box: tuple, index) -> None:
    """``part`` grown by ``over`` (pixels on ``box``): ``Part.over``, ``mask``, ``base``, ``box``."""
    h, w = index.shape
    rs, cs = np.nonzero(over)
    r0 = min(part.box[0].start, box[0].start + int(rs.min()))
    r1 = max(part.box[0].stop, box[0].start + int(rs.max()) + 1)
    c0 = min(part.box[1].start, box[1].start + int(cs.min()))
    c1 = max(part.box[1].stop, box[1].start + int(cs.max()) + 1)
    big = (slice(r0, r1), slice(c0, c1))
    full = np.zeros((h, w), bool)
    full[box] = over
    new_over = full[big]
    mask = np.zeros(new_over.shape, bool)
    base = np.zeros(new_over.shape, bool)
    at = (slice(part.box[0].start - r0, part.box[0].stop - r0), slice(part.box[1].start - c0, part.box[1].stop - c0))
    mask[at], base[at] = part.mask, part.base
    part.box, part.mask, part.base, part.over = big, mask | new_over, base & ~new_over, new_over
    index.part_mask[big] |= new_over
