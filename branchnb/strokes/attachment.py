"""Stroke pairs adjusted before fetching: branch exits, centred sources, unstroked parts carried.

Step 2 (branching) of :func:`~branchnb.strokes.edit.edit_structure`, the
parts beyond the paper: a branch drawn from its parent's centre line starts
where it leaves the new parent's silhouette (:func:`_align_exits`), moved
source strokes are slid onto the middle of their part (:func:`_centred_pairs`,
:mod:`~branchnb.strokes.centring`), and the parts nobody stroked are carried
rigidly by the stroke they hang from (:func:`_carried_parts`; fanned apart where
they would collide, :mod:`~branchnb.strokes.fanning`).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from .centring import centre_stroke
from .hips import restore_hip
from .junctions import exit_length
from .parts import _closed_by_disk, _opened_by_disk, add_bases, carry_frame, rigid_frame
from .strokes import StrokePair, make_pairs

__all__: list[str] = []


def _align_exits(index, pairs, attached, junctions) -> None:
    """Make branches drawn from their parent's centre line leave the new parent's silhouette.

    Such a branch copies nothing of its source parent (see
    :func:`~branchnb.strokes.source.source_index`): its texture starts where
    its source stroke leaves the source parent's tube. A control pair maps
    that point to where its target stroke leaves the target parent's
    silhouette (the parent as re-synthesized: its source silhouette's width
    at the corresponding place), so the branch starts at the parent's
    edge, wherever it is moved to and however thick the parent is there.
    """
    for jn in junctions:
        i = jn.child
        src_parent = index.joined[i][jn.end] if index.joined else -1
        if src_parent < 0:
            continue
        ppair = attached[jn.parent]
        a = exit_length(pairs[i].source, index.strokes[src_parent],
                        lambda s, k=src_parent: index.half_width(k, s), jn.end)
        b = exit_length(attached[i].target, ppair.target,
                        lambda s, k=jn.parent, pp=ppair: index.edge_width(k, pp.source_arc_length(s)),
                        jn.end)
        if a is None or b is None:
            continue
        # A branch leaving its parent at the angle it left it in the source keeps the
        # parent's tube at the joint as it was (the parent copies the same pixels there):
        # it starts where it left the tube, as in the source (an identity edit is an
        # identity; with the silhouette's width a corner-cutting branch was shifted along
        # itself by the tube's excess and its unstroked parts no longer followed it).
        # The more it turns, the more the silhouette's width counts. Beyond the paper.
        same = exit_length(attached[i].target, ppair.target,
                           lambda s, k=jn.parent, pp=ppair: index.half_width(k, pp.source_arc_length(s)),
                           jn.end)
        if same is not None:
            turn = abs(_joint_angle(pairs[i].source, index.strokes[src_parent], jn.end)
                       - _joint_angle(attached[i].target, ppair.target, jn.end))
            turn = min(turn, 2.0 * np.pi - turn)
            t = float(np.clip(turn / _EXIT_TURN, 0.0, 1.0))
            b = (1.0 - t) * same + t * b
        pair = attached[i]
        ls, lt = pair.source.length, pair.target.length
        if lt - b < _MOST_SQUEEZE * (ls - a):
            # a child laid along its parent (a leaf turned onto its twig) leaves the
            # parent's silhouette only near its tip: aligning its exit would squeeze
            # the whole part into that tip. It keeps the mapping as drawn. Beyond the paper.
            continue
        row = (a, b) if jn.end == 0 else (ls - a, lt - b)
        attached[i] = _with_pins(pair, [row])


def _under_parent(index, i: int, jn) -> bool:
    """Whether source stroke ``i`` already starts (at ``jn.end``) inside its target parent's
    source silhouette: a branch drawn from inside the fork (not quite on the parent's centre
    line), not a free tip glued to the parent. Such an end is not pushed under the parent
    (an identity edit stays an identity: the extension stretched the whole branch)."""
    if not index.has_alpha:
        return False
    child, parent = index.strokes[i], index.strokes[jn.parent]
    if child.points.tobytes() == parent.points.tobytes():
        return False
    end = child.points[:1] if jn.end == 0 else child.points[-1:]
    s_par, d = parent.project(end)
    return bool(d[0] <= float(index.half_width(jn.parent, float(s_par[0]))) + 1.0)


#: Least share of its outside length a child keeps when its exit is aligned (see _align_exits).
_MOST_SQUEEZE = 0.5

#: Turn of a branch against its parent (radians) from which its exit is placed at the
#: silhouette's width only (see _align_exits).
_EXIT_TURN = np.radians(30.0)


def _joint_angle(child, parent, end: int) -> float:
    """Angle (radians, in [0, 2 pi)) of ``child`` leaving ``parent`` at its ``end``, against the
    parent's direction at the nearest point."""
    s_c = 0.0 if end == 0 else child.length
    d_c = float(child.angle_at(s_c, window=max(4.0, 0.1 * child.length)))
    if end == 1:
        d_c += np.pi
    s_p = float(parent.project(child.point_at(np.array([s_c])))[0][0])
    d_p = float(parent.angle_at(s_p, window=max(4.0, 0.05 * parent.length)))
    return float((d_c - d_p) % (2.0 * np.pi))


def _centred_pairs(src_img, pairs, control_points, target_shape) -> list[StrokePair]:
    """``pairs`` with every moved source stroke slid onto the middle of its part (:mod:`.centring`).

    Pairs whose target is the source itself (parts kept in place) and pairs
    with the user's own control points stay as drawn.
    """
    alpha = src_img[..., 3]
    if not bool((alpha < 0.999).any()):
        return pairs  # an opaque image: no silhouette to centre on
    mask = alpha > 0.5
    sources, changed = [], False
    kept = [p.source.points.shape == p.target.points.shape and np.allclose(p.source.points, p.target.points)
            for p in pairs]
    # a source stroke also given for a part kept in place (a branch copied to grow a new
    # one) stays as drawn for every pair: two copies of one stroke, one centred, would
    # split the branch's pixels between them (each the nearer one's) and neither fetch it whole
    shared = {p.source.points.tobytes() for p, k in zip(pairs, kept) if k}
    for i, p in enumerate(pairs):
        keep = (control_points is not None and control_points[i] is not None) or kept[i] or (
            p.source.points.tobytes() in shared)
        others = [q.source.points for j, q in enumerate(pairs) if j != i]
        pts = p.source.points if keep else centre_stroke(mask, p.source.points, others=others)
        changed |= pts is not p.source.points
        sources.append(pts)
    if not changed:
        return pairs
    return make_pairs(sources, [p.target for p in pairs], control_points,
                      source_shape=src_img.shape, target_shape=target_shape)


def _carried_parts(index, pairs, attached, window: float, drawn=None) -> list[tuple[int, int, float]]:
    """``(pair, part, s_target)``: every pair carries the parts hanging from its source stroke.

    A part touching its own stroke at several places goes only where they
    all move alike; contact with other strokes does not hold it back (it
    follows the stroke it touches most). ``drawn``: the pairs as the user
    drew them (before centring), whose start moves a body follows.
    """
    keys = [p.source.points.tobytes() for p in pairs]
    out = []
    for part in index.parts:
        _steadiest_anchor(index, part, pairs, attached, keys, window)
    _mark_bodies(index, [sum(k == keys[part.stroke] for k in keys) for part in index.parts])
    for pi, part in enumerate(index.parts):
        (rs, cs) = part.box
        corners = np.array([[cs.start, rs.start, 1.0], [cs.stop, rs.stop, 1.0],
                            [cs.start, rs.stop, 1.0], [cs.stop, rs.start, 1.0]])
        mine = [i for i in range(len(pairs)) if keys[i] == keys[part.stroke]]
        if part.body:
            _trim_body(index, part)
            if drawn is not None:
                d = drawn[mine[0]]
                part.shift = np.asarray(d.target._point_at(0.0), np.float64) - np.asarray(
                    d.source._point_at(0.0), np.float64)
        if len(mine) > 1 and any(keys[j] != keys[part.stroke] for j, _ in part.anchors) \
                and part.area > _own_area(index, part.stroke):
            # A source stroke drawn twice (a copy: an arm added) carries a copy of the
            # parts hanging from it alone (a limb's twig, the sliver at a branch's base);
            # a part larger than the stroke's own piece that also touches another stroke
            # (a starfish's disk and other arms, where every arm starts) is a body, not
            # an appendage: it stays one part, with the pair that moves it least.
            shift = [float(np.abs(corners @ rigid_frame(attached[i].source, attached[i].target, part.s,
                                                        _mapped(attached[i], part.s), window=window).T
                                  - corners[:, :2]).max()) for i in mine]
            mine = [mine[int(np.argmin(shift))]]
        for i in mine:
            s_t = _mapped(attached[i], part.s)
            moved = corners @ carry_frame(part, attached[i].source, attached[i].target, part.s, s_t,
                                          window=window).T
            alike = True
            # A part held at both ends by two strokes (a twig in a crotch, its root on a
            # limb, its tip against the trunk) follows only if both move it alike: carried
            # by one, it was torn from the other, whose tube kept its end (fragments).
            for j, s_a in part.ends:
                pj = keys.index(keys[j])  # the first pair with that source stroke
                other = corners @ rigid_frame(attached[pj].source, attached[pj].target, s_a,
                                              _mapped(attached[pj], s_a), window=window).T
                alike &= float(np.abs(other - moved).max()) <= 2.0
            # Only places on the part's own stroke (a loop between two cut ends) must move
            # alike; a part also touching another stroke (a leg at the hip where the tail
            # turns) follows the stroke it touches most, as a limb would, instead of vanishing.
            own = [s_a for j, s_a in part.anchors if keys[j] == keys[i]]
            for s_a in own if len(own) > 1 else ():
                other = corners @ carry_frame(part, attached[i].source, attached[i].target, s_a,
                                              _mapped(attached[i], s_a), window=window).T
                alike &= float(np.abs(other - moved).max()) <= 2.0
            if alike:
                out.append((i, pi, s_t))
    return out


def _mark_bodies(index, n_pairs: list[int]) -> None:
    """Set ``part.body`` of every part (:func:`_is_body`), then of the pieces of a body its stroke cut off.

    A stroke drawn from inside the body it grows out of (a leaf's stalk from
    the twig's centre line) cuts that body into pieces with its tube. A
    piece smaller than the stroke's own piece but lying off the stroke near
    its start (:func:`_off_the_stroke`) is part of that body too when
    another piece there is a body by :func:`_is_body` (the twig on the
    other side of the stalk). Turned with the stroke, it swung off with a
    stroked leaf. Pieces near the start of a stroke with no body there (a
    figure's legs below its trunk's stroke, the petals round a flower head's
    stroke) hang from the stroke and follow it, as before. Beyond the paper.
    """
    cand = []
    for part, n in zip(index.parts, n_pairs):
        part.body = _is_body(index, part, n)
        if not part.body and _body_piece(index, part, n):
            cand.append(part)
    has_body = {part.stroke for part in index.parts if part.body}
    for part in cand:
        part.body = part.stroke in has_body


def _body_piece(index, part, n_pairs: int) -> bool:
    """Whether ``part`` could be a piece of the body its stroke grows out of, whatever its area: it
    touches the stroke only near its start and hardly lies along the stroke (see :func:`_mark_bodies`)."""
    if n_pairs != 1 or part.tip is not None:
        return False
    reach = 2.0 * float(index.half_width(part.stroke, 0.0)) + 2.0
    if part.s > reach or any(j == part.stroke and s > reach for j, s in part.anchors):
        return False
    return _off_the_stroke(index, part, reach)


def _is_body(index, part, n_pairs: int) -> bool:
    """Whether ``part`` is the body its stroke grows out of (moved, never turned: see
    :func:`~branchnb.strokes.parts.carry_frame`).

    Attached at the stroke's start (within two half widths of it; strokes are drawn from where a part grows out:
    a trunk from the ground, a tail from the hip, as in the paper's figures) and larger
    than the stroke's own piece; a stroke drawn once (a copy's body is handled by the
    copies' rule in :func:`_carried_parts`).
    """
    if n_pairs != 1 or part.tip is not None:
        return False
    reach = 2.0 * float(index.half_width(part.stroke, 0.0)) + 2.0
    # a piece the stroke also touches past the middle of its length is no body it grows out of but
    # a loop between its two cut ends (the rest of a rope: at 64 px its contact at the start came out
    # largest, and carried unturned it hung beside the new rope whole; at 128 px and more it is a loop)
    far = [s for j, s in part.anchors if j == part.stroke and s > max(reach, 0.5 * index.strokes[part.stroke].length)]
    return bool(part.s <= reach and part.area > _own_area(index, part.stroke) and not far)


#: Most share of a part's pixels lying along its stroke past the stroke's start (within 1.5 half widths
#: of it, farther than _is_body's reach from the start) for a part smaller than the stroke's own piece to
#: still be the body the stroke grows out of: a piece of a twig only its leaf's stroke cuts off (twig
#: 300-1000 px, leaf 1 turned: 0 %; turned with the leaf it swung off, 2,580-24,470 px changed away
#: from the leaf).
_ALONG = 0.2


def _off_the_stroke(index, part, reach: float) -> bool:
    """Whether ``part`` hardly lies along its stroke past the stroke's start (:data:`_ALONG`): a piece
    of the body the stroke grows out of that its tube cut off (a twig on both sides of a leaf's
    stalk), not a sliver of the stroke's own part.
    Beyond the paper."""
    k = part.stroke
    (rs, cs) = part.box
    s_loc = index.s_map[k][rs, cs][part.mask]
    if not s_loc.size:
        return False
    yy, xx = np.nonzero(part.mask)
    foot = index.strokes[k].point_at(s_loc)
    off = np.hypot(xx + cs.start - foot[:, 0], yy + rs.start - foot[:, 1])
    half = np.asarray(index.half_width(k, s_loc), np.float64)
    along = (s_loc > reach) & (off <= 1.5 * half + 2.0)
    return bool(float(along.mean()) <= _ALONG)


def _trim_body(index, part) -> None:
    """Leave the stroke's own rim to the stroke: a body (:func:`_is_body`) loses its slivers along it.

    A stroke's tube is a little narrower than its part in places, and the
    strip left along its side joins the body it grows from. Turned with the
    stroke that strip lay along the new part; a body is no longer turned, so
    it stuck out in the old direction as prongs beside a bent tail.
    """
    k = part.stroke
    st = index.strokes[k]
    _grow_box(part, int(np.ceil(2.0 * float(index.half_width(k, 0.0)))) + 2, index.object.shape)
    (rs, cs) = part.box
    s_loc = index.s_map[k][rs, cs]
    foot = st.point_at(s_loc.ravel()).reshape(*s_loc.shape, 2)
    yy, xx = np.mgrid[rs, cs]
    off = np.hypot(xx - foot[..., 0], yy - foot[..., 1])
    half = np.asarray(index.half_width(k, s_loc.ravel()), np.float64).reshape(s_loc.shape)
    start = 2.0 * float(index.half_width(k, 0.0)) + 2.0
    # a strip beside the stroke past its start, thinner than the part (the body's own flesh there
    # is thick: it stays)
    r = max(1, int(round(0.5 * float(np.median(half)))))
    thin = part.mask & ~_opened_by_disk(part.mask, r)
    rim = thin & (s_loc > start) & (off <= 1.5 * half + 2.0)
    # and keeps what the stroke's start claimed inside it (a hole where the tail's tube began in the hip)
    # (the pixels behind the stroke's start, which its tube's cap claimed, are the body's)
    behind = (s_loc <= 1.0) & (off <= 1.5 * half + 2.0)
    body = (part.mask & ~rim) | behind
    # the slot the stroke's tube cut through the body from a start drawn inside it (up to where the
    # body holds the stroke) is the body's own flesh, up to the body's outline closed across it
    beside = part.mask & ~thin & (off <= 1.5 * half + 2.0)
    exit_s = max(part.s, float(s_loc[beside].max())) if beside.any() else part.s
    slot = (s_loc <= exit_s) & (off <= 1.5 * half + 2.0)
    wide = max(1, int(round(float(index.half_width(k, 0.0)))) + 2)
    pad = wide + 1
    closed = _closed_by_disk(np.pad(body, pad), wide)[pad:-pad, pad:-pad]
    body |= closed & slot
    # and the convex cap of its contour where the tail left it (closing fills notches only: a bite
    # out of the hip once the tail swung away)
    h0 = float(index.half_width(k, 0.0))
    root = (s_loc <= max(exit_s, start) + 2.0 * h0) & (off <= 1.5 * half + 2.0)
    body = restore_hip(ndi.binary_fill_holes(body) & index.object[rs, cs], index.object[rs, cs], root, h0)
    part.mask = ndi.binary_fill_holes(body) & index.object[rs, cs]
    part.area = int(part.mask.sum())
    # its base (the overlap it is stitched in by) was the stroke's pixels along that strip too: only
    # the stroke's start stays its base
    base_s = index.s_map[k][rs, cs]
    part.base = part.base & (base_s <= start)


def _grow_box(part, pad: int, shape) -> None:
    """Grow ``part``'s box by ``pad`` px on every side within ``shape`` (its mask and base padded
    with False; in place): the cap of a body's contour its stroke's tube took lies outside the
    box of what is left (see :func:`~branchnb.strokes.hips.restore_hip`)."""
    (rs, cs) = part.box
    r0, r1 = max(rs.start - pad, 0), min(rs.stop + pad, shape[0])
    c0, c1 = max(cs.start - pad, 0), min(cs.stop + pad, shape[1])
    grown = ((rs.start - r0, r1 - rs.stop), (cs.start - c0, c1 - cs.stop))
    part.box = (slice(r0, r1), slice(c0, c1))
    part.mask = np.pad(part.mask, grown)
    part.base = np.pad(part.base, grown)


def _own_area(index, k: int) -> float:
    """Area (px) of stroke ``k``'s own piece: its length times twice its typical half width."""
    st = index.strokes[k]
    s = np.linspace(0.0, st.length, 16)
    return float(st.length * 2.0 * np.median(index.edge_width(k, s)))


#: A part leaves the stroke it touches most for a steadier one moving it at most this share as far.
_STEADIER = 0.5


def _steadiest_anchor(index, part, pairs, attached, keys, window: float) -> None:
    """Hang ``part`` from the stroke among those it touches that moves it least (in place).

    A part touching two strokes that move apart (a starfish's arm between
    the kept arm and the turned one, both stroked from the centre; a leg at
    the hip where the tail turns) stays with the one that keeps it nearest
    to where it was: an edit changes only what the user touched. Only a
    markedly steadier stroke (moving it at most :data:`_STEADIER` times as
    far) wins over the one it touches most: a part every stroke moves far
    (a petal under a flower's head, also touching the shortened stem's
    side) stays with its main contact. Beyond the paper.
    """
    strokes = {j for j, _ in part.anchors if keys[j] != keys[part.stroke]}
    if not strokes or part.tip is not None:  # a stroke whose tip ends in the part carries it
        return
    (rs, cs) = part.box
    corners = np.array([[cs.start, rs.start, 1.0], [cs.stop, rs.stop, 1.0],
                        [cs.start, rs.stop, 1.0], [cs.stop, rs.start, 1.0]])
    src = corners[:, :2]

    def moved(j, s_a):
        i = keys.index(keys[j])  # the first pair with that source stroke
        frame = rigid_frame(attached[i].source, attached[i].target, s_a, _mapped(attached[i], s_a),
                            window=window)
        return float(np.abs(corners @ frame.T - src).max())

    own = [s_a for j, s_a in part.anchors if keys[j] == keys[part.stroke]] or [part.s]
    best, best_d = None, min(moved(part.stroke, s_a) for s_a in own)
    first_d = best_d
    for j in sorted(strokes):
        d = max(moved(j, s_a) for jj, s_a in part.anchors if jj == j)
        # markedly steadier only (at most half the move): a part that every stroke it
        # touches moves far (a flower's petal under its head, touching the shortened
        # stem's side too) follows the one it touches most, not the one moving it a few
        # percent less (the petal slid into the head: a bite out of it by the stem)
        if d < best_d - 2.0 and d <= max(2.0, _STEADIER * first_d):
            best, best_d = j, d
    if best is None:
        return
    s_best = [s_a for j, s_a in part.anchors if j == best]
    part.stroke, part.s = best, float(np.median(s_best))
    part.anchors = [(j, s_a) for j, s_a in part.anchors if keys[j] == keys[best]]
    part.box = (slice(part.box[0].start, part.box[0].stop), slice(part.box[1].start, part.box[1].stop))
    add_bases([part], index, window=3.0)


def _mapped(pair: StrokePair, s_source: float) -> float:
    """Target arc length of source arc length ``s_source`` (the pair's control mapping).

    A target stroke that is a rigid copy of its source (moved or turned as a
    whole, e.g. a head carried on a shortened stem) maps every arc length to
    itself: its parts follow the one rigid map, whatever pins the mapping
    holds (an exit pin where the copy leaves its parent's new silhouette
    slid a flower's side petals 7 px along the head at 1000 px).
    """
    if _rigid_copy(pair):
        return float(s_source)
    return float(np.interp(s_source, pair.control[:, 0], pair.control[:, 1]))


def _rigid_copy(pair: StrokePair, tol: float = 0.5) -> bool:
    """The target's points are the source's moved rigidly (within ``tol`` px)."""
    a, b = pair.source.points, pair.target.points
    if a.shape != b.shape or abs(pair.source.length - pair.target.length) > tol:
        return False
    ca, cb = a - a.mean(axis=0), b - b.mean(axis=0)
    u, _, vt = np.linalg.svd(ca.T @ cb)
    if np.linalg.det(u @ vt) < 0:
        u[:, -1] = -u[:, -1]  # a proper rotation (Kabsch); a reflection only fits collinear points
    r = u @ vt
    return float(np.abs(ca @ r - cb).max()) <= tol


def _with_pins(pair: StrokePair, pins) -> StrokePair:
    """``pair`` with extra control points at ``(s_source, s_target)`` on its own mapping.

    They do not change the mapping; they put a sample exactly where a part
    is attached and pin it there (no shift by global sampling), so the
    parent's texture at the joint is the one the part was cut from.
    """
    ctl = pair.control
    rows = [tuple(r) for r in ctl[1:-1]]
    ls, lt = ctl[-1]
    for a, b in pins:
        if not (1.0 < a < ls - 1.0 and 1.0 < b < lt - 1.0):
            continue
        if any(abs(a - r[0]) < 1.0 or abs(b - r[1]) < 1.0 for r in rows):
            continue
        rows.append((a, b))
    rows.sort(key=lambda r: r[1])
    if len(rows) == len(ctl) - 2:
        return pair
    try:
        return StrokePair(pair.source, pair.target, np.array(rows, float).reshape(-1, 2), name=pair.name)
    except ValueError:
        return pair  # pins out of order (a folded mapping): sample as drawn
