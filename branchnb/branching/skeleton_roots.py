"""Automatic extraction, step 3 (beyond the paper): where a skeleton piece's tree is rooted.

Which end of a skeleton piece is its root: a river's or a bolt's entry from the frame
(:func:`_frame_entries`, on small frames :func:`_small_frame_entry`), a delta's outlet at the frame
or its coast (:func:`_frame_outlet`, :func:`_region_outlet`, the trunk arms of a junction
:func:`_junction_trunk_arms`) and the mouth node a piece drains to (:func:`_mouth_node`); each
end's radius (:func:`_end_radius`, :func:`_held_radius`, :func:`_inside_radius`). Split from
:mod:`.skeleton_tree` (issue 23, branching103), which re-exports every name and calls these from
:func:`~.skeleton_tree.skeleton_to_structure`.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csgraph


def _end_radius(pts: np.ndarray, r: np.ndarray, ends: np.ndarray, members: np.ndarray) -> np.ndarray:
    """How thick the line is at each end: the largest radius within ``3 r_med + 4`` pixels of it.

    The radius right at a skeleton end is small (the medial axis ends where
    the channel's rounded tip or the frame closes in), so a wide channel
    leaving the frame would lose against a spur of a narrower one.
    """
    reach = 3.0 * float(np.median(r[members])) + 4.0
    out = np.empty(len(ends))
    for i in range(0, len(ends), 64):
        e = ends[i:i + 64]
        d2 = ((pts[e, None, :] - pts[None, members, :]) ** 2).sum(-1)
        out[i:i + 64] = np.where(d2 <= reach * reach, r[members][None, :], 0.0).max(1)
    return np.maximum(out, r[ends])


#: ``root="auto"`` on a piece not of one width: ends within this many pixels (plus :data:`ENTRY_RADII` x
#: their radius) of the frame, at least
#: :data:`ENTRY_SHARE` x as thick as the piece's thickest end and :data:`ENTRY_RATIO` x its median
#: radius, are where it enters the frame: each roots a tree (:func:`_frame_entries`).
ENTRY_FRAME = 4.0
#: ... plus this many times the end's radius: a thick line's medial axis stops about a radius short
#: of the frame that cuts it (beyond the paper, issue 23; a thin interior end stays off the frame).
ENTRY_RADII = 1.0
ENTRY_SHARE = 0.75
ENTRY_RATIO = 2.0


def _held_radius(pts: np.ndarray, r: np.ndarray, ends: np.ndarray, members: np.ndarray) -> np.ndarray:
    """How thick the line stays near each end: the median radius of the piece's nodes within
    ``3 r_med + 4`` pixels of it (where :func:`_end_radius` takes the largest)."""
    reach = 3.0 * float(np.median(r[members])) + 4.0
    out = np.empty(len(ends))
    for i in range(0, len(ends), 64):
        e = ends[i:i + 64]
        d2 = ((pts[e, None, :] - pts[None, members, :]) ** 2).sum(-1)
        near = np.where(d2 <= reach * reach, r[members][None, :], np.nan)
        out[i:i + 64] = np.nanmedian(near, axis=1)
    return out


#: A piece whose lines mostly have one width still has a *trunk* when an end at the frame stays at least
#: this many times as thick as the piece's 75th radius percentile (and :data:`TRUNK_EXTRA` px more):
#: :func:`_frame_trunk_end`.
TRUNK_HELD_RATIO = 3.0
TRUNK_EXTRA = 2.0


def _frame_trunk_end(pts: np.ndarray, r: np.ndarray, ends: np.ndarray, members: np.ndarray,
                     frame_d: np.ndarray, hi: float) -> bool:
    """Whether a thick trunk enters the frame at one of a piece's ends (``frame_d``: each end's distance
    to the frame; ``hi``: the piece's 75th radius percentile).

    Beyond the paper (issue 23, an unseen winter tree against the sky): a tree's twigs are most of its
    skeleton, so its radius quartiles (0.5 / 1.5 px) read as lines of one width, and a drawn map's rule
    (rooted where the lines meet a large flat region) took the sky for the sea and rooted the tree in its
    crown; the synthesized trees grew from the crown downward. A line that stays several times thicker than
    the piece's lines where the frame cuts it is a trunk, whatever most of the piece looks like; a map's river
    entering at the frame stays its own width there, and a junction's blob inside is no frame end.
    """
    if not len(ends):
        return False
    held = _held_radius(pts, r, ends, members)
    at_frame = frame_d <= ENTRY_FRAME + ENTRY_RADII * held
    return bool(np.any(at_frame & (held >= max(TRUNK_HELD_RATIO * hi, hi + TRUNK_EXTRA))))


def _even_ends(end_r: np.ndarray, pts: np.ndarray, r: np.ndarray, ends: np.ndarray, members: np.ndarray) -> bool:
    """Whether no end of a piece is much thicker than its median end (:data:`OUTLET_EVEN`), by the
    largest radius near each end (``end_r``) or, failing that, by how thick the line stays near it
    (:func:`_held_radius`: two one-width lines meeting in a V at the frame are no thick end)."""
    if end_r.max() <= OUTLET_EVEN * float(np.median(end_r)) + 0.5:
        return True
    held = _held_radius(pts, r, ends, members)
    return bool(held.max() <= OUTLET_EVEN * float(np.median(held)) + 0.5)


def _frame_entries(cand: np.ndarray, end_r: np.ndarray, frame_d: np.ndarray, pts: np.ndarray,
                   r_med: float, r: np.ndarray | None = None, members: np.ndarray | None = None,
                   radii: float = ENTRY_RADII) -> list[int]:
    """The ends of a piece where thick lines enter the frame, thickest first, each farther than
    4 x its radius from the ones before (empty when none).

    Beyond the paper (issue 23): a root drawing's two 6-px trunks entering from the top among 1-px
    roots read as one piece (the roots cross); rooted at its thickest end, a tie between the trunks'
    frame ends and inner ends beside a trunk, it was rooted inside and the output's trees started in
    the middle and at other sides. A line cut by the frame at its full thickness enters there; every
    such entry roots a tree (the shortest-path tree splits the piece between them).

    With ``r`` and ``members`` (the piece's node radii and nodes; given for pieces of about one
    width), the line must also *stay* that
    thick near the end (:func:`_held_radius` at least :data:`ENTRY_RATIO` x ``r_med``): two lines of
    one width meeting at the frame in a V make a blob there whose largest radius is twice theirs
    (a crossing river network was rooted at such a V on its far side).

    ``radii``: an end lies at the frame within ``ENTRY_FRAME + radii x`` its radius (0 on small
    examples, whose lines :mod:`.small_frames` traced up to the frame: a fork's blob a radius inside
    is no entry there).
    """
    if not len(cand):
        return []
    top = float(end_r.max())
    ok = (frame_d <= ENTRY_FRAME + radii * end_r) & (end_r >= ENTRY_SHARE * top) & \
        (end_r >= ENTRY_RATIO * r_med)
    if r is not None and members is not None and ok.any():
        idx = np.flatnonzero(ok)
        ok[idx] = _held_radius(pts, r, cand[idx], members) >= ENTRY_RATIO * r_med
    out: list[int] = []
    for i in np.flatnonzero(ok)[np.argsort(-end_r[ok], kind="stable")]:
        p = pts[cand[i]]
        if all(np.hypot(*(p - pts[j])) > 4.0 * end_r[i] for j in out):
            out.append(int(cand[i]))
    return out


def _small_frame_key(key: np.ndarray, frame_d: np.ndarray) -> np.ndarray:
    """``root="auto"`` on a small example (long side <= :data:`~.small_frames.SMALL_SIDE` px) whose
    piece neither enters (:func:`_frame_entries`) nor drains (:func:`_frame_outlet`) at the frame by
    those rules: its thickest end is taken among the ends on the frame (within
    :data:`SMALL_FRAME` px) at least :data:`ENTRY_SHARE` x as thick as its thickest end, if any.

    Beyond the paper (issue 23): at 96-256 px radii read in half-pixel steps (a tapering 4-px river
    read 1.7 at its mouth, 1.3 at a bank's spur inside), so "thicker" says little; a 128 px map's
    river entering from the bottom edge was rooted at a spur mid-canvas and its synthesis floated
    there. A line cut by the frame nearly at its full width comes from outside. ``key`` is the
    negated end radius; the result is ``key`` with the other ends pushed behind.
    """
    thick = -key
    on = (frame_d <= SMALL_FRAME) & (thick >= ENTRY_SHARE * float(thick.max()))
    if not on.any():
        return key
    return np.where(on, key, key + float(np.ptp(key)) + 1.0)


def _small_frame_lead(end_r: np.ndarray, frame_d: np.ndarray, pts: np.ndarray, r: np.ndarray,
                      cand: np.ndarray, members: np.ndarray) -> int | None:
    """On a small example, the frame end (within :data:`SMALL_FRAME` px) at least :data:`ENTRY_SHARE` x
    as thick as the piece's thickest end whose line stays :data:`SMALL_LEAD` x as thick near it
    (:func:`_held_radius`) as near any other frame end (``None``: no such end).

    Beyond the paper (issue 23): traced up to the frame (:mod:`.small_frames`), a small vessel's
    side branches leaving the frame became frame ends too, and the fork votes of
    :func:`_frame_outlet` rooted it at a side branch's tip; a line that enters much thicker than the
    others leave comes from there.
    """
    on = np.flatnonzero((frame_d <= SMALL_FRAME) & (end_r >= ENTRY_SHARE * float(end_r.max())))
    if not len(on):
        return None
    at = np.flatnonzero(frame_d <= SMALL_FRAME)
    held = _held_radius(pts, r, cand[at], members)
    best = int(np.argmax(held))
    if at[best] not in on or np.any(np.delete(held, best) * SMALL_LEAD > held[best]):
        return None
    return int(cand[at[best]])


#: ... and the frame end it roots at stays this many times as thick as the line near other frame ends.
SMALL_LEAD = 1.5


#: On a small example a frame end's thickness is read along its line from this many median radii
#: plus :data:`INSIDE_FADE` px past it (:func:`_inside_radius`) ...
INSIDE_FROM = 2.0
#: ... (the last pixels before the border, where the filters' responses fade: the half-contrast radius
#: of a 6-px river read 0.5-0.9 px within 8 px of the frame of a 160 px map, 2.4-2.7 px beyond) ...
INSIDE_FADE = 8.0
#: ... over this many more median radii (plus 8 px).
INSIDE_SPAN = 4.0
#: Frame ends whose lines are within this factor as thick as the thickest frame end's are a tie,
#: which the forks decide (:func:`_small_frame_entry`).
SMALL_TIE = 1.25


def _inside_radius(g, ends: np.ndarray, r: np.ndarray, r_med: float) -> np.ndarray:
    """How thick the line is just inside each end: the median radius of the nodes between
    ``INSIDE_FROM r_med + INSIDE_FADE`` and that plus ``INSIDE_SPAN r_med + 8`` pixels along the
    skeleton from it (of all the nodes within that reach when none is that far: a short spur)."""
    a = INSIDE_FROM * r_med + INSIDE_FADE
    b = a + INSIDE_SPAN * r_med + 8.0
    dist = csgraph.dijkstra(g, directed=False, indices=ends, limit=b)
    out = np.empty(len(ends))
    for i, d in enumerate(np.atleast_2d(dist)):
        near = np.isfinite(d)
        band = near & (d >= a)
        out[i] = float(np.median(r[band] if band.any() else r[near]))
    return out


def _small_frame_entry(g, deg: np.ndarray, cand: np.ndarray, members: np.ndarray, pts: np.ndarray,
                       r: np.ndarray, frame_d: np.ndarray) -> int | None:
    """On a small example (on a larger one when :func:`_frame_outlet` finds none), the frame end
    (within :data:`SMALL_FRAME` px) where the thickest line enters, read just inside the frame
    (:func:`_inside_radius`); ``None`` when no frame end's line is at least :data:`ENTRY_SHARE` x as
    thick as the piece's median radius (only tapering tips leave), or when at least :data:`SMALL_VOTES`
    forks are there and more of them point away from every such end than to it (lines spreading from
    inside, their tips leaving the frame).

    Beyond the paper (issue 23): traced up to the frame (:mod:`.small_frames`), a line's last pixels
    lie where the ridge mask fades against the border, so the radius *at* a frame end says little:
    a 6-px river entering a 160 px map read 0.5 px there, thinner than its tributaries' tips, and the
    map was rooted at a tributary's source 41 px inside; a 96 px river's trunk and a tributary both
    leaving the frame read alike (1.74 px) and the first in pixel order won; a 256 px map of 2-px
    black rivers was rooted at a tip inside, where two lines overlap in a blob twice as thick as
    they are (and a 512 px one, whose four forks split two for the frame end, two against). Inside the
    frame the trunk is the thicker line, and a line entering is no tapering tip.
    Frame ends within :data:`SMALL_TIE` x of the thickest are decided by the forks, as
    :func:`_frame_outlet` does (the arm toward the outlet runs opposite the two others), then by
    thickness.
    """
    at = np.flatnonzero(frame_d <= SMALL_FRAME)
    if not len(at):
        return None
    r_med = float(np.median(r[members]))
    inside = _inside_radius(g, cand[at], r, r_med)
    ok = inside >= ENTRY_SHARE * r_med
    if not ok.any():
        return None
    at, inside = at[ok], inside[ok]
    votes = _junction_trunk_arms(g, deg, members, pts, 6.0 * r_med + 8.0)
    score = np.zeros(len(at))
    if votes:
        dist = csgraph.dijkstra(g, directed=False, indices=cand[at])
        for arms, trunk in votes:
            score += np.where(np.argmin(dist[:, arms], axis=1) == trunk, 1.0, -1.0)
        if len(votes) >= SMALL_VOTES and score.max() < 0:
            return None
    tied = np.flatnonzero(inside * SMALL_TIE >= float(inside.max()))
    return int(cand[at[tied[np.lexsort((-inside[tied], -score[tied]))[0]]]])


#: ... the forks overrule the thickness from this many clear forks on (:func:`_junction_trunk_arms`).
SMALL_VOTES = 3


#: On small examples an end within this many pixels of the frame is on it (see :func:`_small_frame_key`).
SMALL_FRAME = ENTRY_FRAME


def _one_per_line(entries: list[int], g, r: np.ndarray, r_entry: float,
                  side: np.ndarray | None = None) -> list[int]:
    """``entries`` less those joined to an earlier one by a line at least half as thick as the thinnest
    entry: one thick line crossing the frame (a crack's trunk from side to side) enters once, at its
    thickest end (not split into two trees meeting in its middle).

    ``side`` (per node, the frame side it is nearest to; optional): entries on the same side are two
    trunks, never one line (beyond the paper, issue 23, branching84): a line crossing the canvas leaves
    by another side, while two root trunks from the top edge whose children touch are joined by a
    line half as thick as they enter, and were one tree rooted at one trunk whose main branch ran
    down it and up the other (a hairpin the synthesis copied).
    """
    if len(entries) < 2:
        return entries
    thick = np.flatnonzero(r >= 0.5 * r_entry)
    sub = g[thick][:, thick]
    _n, lab = csgraph.connected_components(sub, directed=False)
    where = dict(zip(thick.tolist(), lab.tolist()))
    seen: dict = {}
    out = []
    for e in entries:
        c = where.get(e, -1 - e)
        sides = seen.setdefault(c, set())
        s_e = -1 if side is None else int(side[e])
        # a line already entered here: it may enter once more only by the same side (a second trunk)
        if sides and (side is None or s_e not in sides):
            continue
        sides.add(s_e)
        out.append(e)
    return out


#: ``root="auto"`` on a piece of one width with ends at the frame: an end within this many pixels (plus
#: twice the piece's median radius) of the frame is where the line meets it (:func:`_frame_outlet`).
OUTLET_FRAME = 4.0
#: ... when no end of the piece is more than this many times as thick as its median end (plus half a pixel).
OUTLET_EVEN = 1.5
#: A three-armed junction votes for the arm toward the root when its two narrowest-apart arms are at
#: least this many radians closer together than either is to the third (:func:`_junction_trunk_arms`).
OUTLET_MARGIN = 0.35
#: ... and a frame end is the outlet unless a place inside (the trunk side of one of up to this many
#: forks) gets more fork votes, by more than :data:`OUTLET_INNER_MARGIN` x the number of forks.
OUTLET_INNER = 48
OUTLET_INNER_MARGIN = 0.1
#: A piece of one width reaches the region (the sea) when an end lies within ``OUTLET_FRAME + 2 r_med``
#: plus this many pixels of it (:func:`_region_outlet`).
OUTLET_COAST = 4.0


def _walk_arm(g, deg: np.ndarray, start: int, prev: int, stop: np.ndarray, pts: np.ndarray,
              reach: float) -> tuple[int, float]:
    """Follow the skeleton from ``start`` (``prev`` behind it) along two-neighbour pixels for up to
    ``reach`` pixels (full size); the last node reached and the length walked."""
    cur, back, walked = int(start), int(prev), float(np.hypot(*(pts[start] - pts[prev])))
    while walked < reach and deg[cur] == 2 and not stop[cur]:
        nb = g.indices[g.indptr[cur]:g.indptr[cur + 1]]
        nxt = int(nb[0]) if int(nb[0]) != back else int(nb[1])
        walked += float(np.hypot(*(pts[nxt] - pts[cur])))
        back, cur = cur, nxt
    return cur, walked


def _junction_trunk_arms(g, deg: np.ndarray, members: np.ndarray, pts: np.ndarray,
                         reach: float) -> list[tuple[np.ndarray, int]]:
    """Per clear three-armed junction of a piece: ``(first nodes of its arms, index of its trunk arm)``.

    Where a line forks (a river's tributary joins, a root or a vessel branches), the two arms away from
    the trunk leave at an acute angle and the arm toward the trunk runs opposite both: the trunk arm is
    the one not in the pair of arms closest in direction (by :data:`OUTLET_MARGIN`; each arm's direction
    from the junction to the skeleton ``reach`` pixels along it). Junctions with another number of
    arms (crossings) or an arm shorter than half ``reach`` (the two forks of a crossing, a spur) do
    not vote.
    """
    jn = members[deg[members] >= 3]
    if not len(jn):
        return []
    is_j = np.zeros(len(deg), bool)
    is_j[jn] = True
    sub = g[jn][:, jn]
    _n, lab = csgraph.connected_components(sub, directed=False)
    out = []
    for c in np.unique(lab):
        cl = jn[lab == c]
        centre = pts[cl].mean(0)
        arms, dirs, short = [], [], False
        for v in cl:
            for u in g.indices[g.indptr[v]:g.indptr[v + 1]]:
                if is_j[u]:
                    continue
                end, walked = _walk_arm(g, deg, int(u), int(v), is_j, pts, reach)
                short |= walked < 0.5 * reach
                d = pts[end] - centre
                arms.append(int(u))
                dirs.append(np.arctan2(d[1], d[0]))
        if short or len(arms) != 3:
            continue
        a = np.asarray(dirs)
        pair = np.abs(np.angle(np.exp(1j * (a[:, None] - a[None, :]))))
        ang = np.array([pair[1, 2], pair[0, 2], pair[0, 1]])   # ang[i]: between the two arms other than i
        order = np.argsort(ang)
        if ang[order[1]] - ang[order[0]] < OUTLET_MARGIN:
            continue
        trunk = int(order[0])          # the two others are the close pair: arm i runs opposite both
        out.append((np.asarray(arms, np.int64), trunk))
    return out


def _frame_outlet(g, deg: np.ndarray, cand: np.ndarray, members: np.ndarray, pts: np.ndarray,
                  r: np.ndarray, frame_d: np.ndarray) -> int | None:
    """The end of a piece of one width where it meets the frame and its junctions say it drains
    (``None`` when no end lies at the frame).

    Beyond the paper (issue 23): a line map's rivers all have one width, so the thickest end is any
    end (a river entering from the bottom edge was rooted at its source inside). A network cut by the
    frame drains through the frame at one of its frame ends; at each fork the arm toward the outlet
    runs opposite the two others (:func:`_junction_trunk_arms`), so the frame end the most forks point
    to (its shortest path enters them by their trunk arm) is the outlet; ties go to the thicker end,
    then the one nearer the frame. When the forks point away from every frame end (more disagree than
    agree) or more firmly to a place inside, the lines spread from inside and only their tips leave
    the frame: ``None``.
    """
    r_med = float(np.median(r[members]))
    at = frame_d <= OUTLET_FRAME + 2.0 * r_med
    if not at.any():
        return None
    ends = cand[at]
    votes = _junction_trunk_arms(g, deg, members, pts, 6.0 * r_med + 8.0)
    score = np.zeros(len(ends))
    if votes:
        # the same count inside, at the trunk side of (up to OUTLET_INNER) forks: the forks of lines that
        # spread from inside (a root system drawn whole, its tips leaving the frame) point to a place
        # inside more firmly than to any frame end
        pick = np.unique(np.linspace(0, len(votes) - 1, min(len(votes), OUTLET_INNER)).astype(int))
        inner = np.asarray([votes[i][0][votes[i][1]] for i in pick], np.int64)
        dist = csgraph.dijkstra(g, directed=False, indices=np.r_[ends, inner])
        total = np.zeros(len(dist))
        for arms, trunk in votes:
            total += np.where(np.argmin(dist[:, arms], axis=1) == trunk, 1.0, -1.0)
        score = total[:len(ends)]
        if score.max() <= 0 or total[len(ends):].max() > score.max() + OUTLET_INNER_MARGIN * len(votes):
            return None
    er = _end_radius(pts, r, ends, members)
    key = np.lexsort((frame_d[at], -er, -score))
    return int(ends[key[0]])


def _region_outlet(g, deg: np.ndarray, cand: np.ndarray, members: np.ndarray, pts: np.ndarray,
                   r: np.ndarray, region_d: np.ndarray) -> int | None:
    """The mouth of a piece of one width that reaches the region (the sea) at several ends: the one
    its forks point to, as :func:`_frame_outlet` finds it at the frame (``None``: they point inside).

    Beyond the paper (issue 23): on a paper map whose river network is joined by crossing lines,
    several of its ends meet the coast, and the nearest was a tributary's (a one-pixel line reaches
    a pixel closer to the sea than the trunk's rounded end): the tree was rooted there and the trunk
    hung from the tributary. Ends within ``OUTLET_FRAME + 2 r_med`` px of the nearest one's distance
    to the region are mouths; the forks, then the thickness, choose among them. A piece whose nearest
    end is farther than that plus :data:`OUTLET_COAST` px (a drawn coast line and the blur beside it)
    from the region does not reach it (a fundus's vessels end 15 px inside its matte): ``None``.
    """
    near = OUTLET_FRAME + 2.0 * float(np.median(r[members]))
    if float(np.min(region_d)) > near + OUTLET_COAST:
        return None
    return _frame_outlet(g, deg, cand, members, pts, r, region_d - float(np.min(region_d)))


def _mouth_node(cand: np.ndarray, key: np.ndarray, members: np.ndarray, member_key: np.ndarray,
                scale: float) -> tuple[np.ndarray, np.ndarray]:
    """Root candidates of a piece that drains into a region: its ends, or the node nearest the region
    when that is more than 4 px nearer than every end.

    Going beyond the paper: where a drawn river meets the coast line, removing the coast's outline
    from the skeleton can leave a little loop or junction at the mouth, so the mouth is no end of
    the skeleton and the nearest *end* is the river's source (a tree rooted inland, upstream).
    """
    k = int(np.argmin(member_key))
    if len(key) and member_key[k] + 4.0 * scale < float(np.min(key)):
        return members[k:k + 1], member_key[k:k + 1]
    return cand, key
