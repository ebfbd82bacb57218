"""Where a delta comes from: the end of a skeleton piece from which its channels fan out to the sea.

Beyond the paper (issue 23, branching83), whose roots are clicked. A river drains to the sea at one mouth;
a delta reaches it at several (its distributaries) and comes from one channel inland. Rooted at a mouth,
the whole example is learnt backwards (the synthesis grows its trunk from the sea). Widths alone do not
tell the source: on balanced binary deltas whose trunk is 2-6 px the ends are too alike in width (a
2-px trunk's end read no thicker than a mouth's 1-px channel, whose end the sea widens), and 4 of 8
such masks were rooted at a mouth. The whole tree's shape does tell it:

- at each fork the two distributaries leave at an acute angle and the arm toward the source runs
  opposite both (:func:`~.skeleton_tree._junction_trunk_arms`): the source is the end the most forks
  point to (its shortest path enters them by their trunk arm); where the angles do not tell (a channel
  leaving a bent trunk's head at a right angle), the fork's thickest arm is its trunk arm;
- among ends the forks point to alike (the trunk's own spurs), the source is the one farthest from
  where the sea ends' paths meet (the trunk's whole length away; a spur on the trunk is nearer);
- but a tributary joining the trunk upstream of the fan is tied with the trunk's source (its confluence
  has every mouth down its trunk arm and does not vote) and may lie farther: an inland end
  :data:`FORK_WIDER` x thinner than another tied one is no source (branching85: 3 of 8 deltas with 1-3
  tributaries were rooted at a tributary's source, up to 130 radii from the trunk's entry; a confluence
  voted against the trunk's source once per tributary).

Split from :mod:`.skeleton_tree`, which calls :func:`_fan_root` and :func:`_delta_source_key` (this module
imports from it inside its functions: it imports this module).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csgraph

__all__ = ["fan_source"]

#: An end lies at the sea (or the frame) within this many pixels plus :data:`SEA_RADII` x its radius.
SEA_FRAME = 4.0
SEA_RADII = 2.0
#: Ends whose fork score is within this share of the number of voting forks of the best are a tie (an
#: exact tie under ten forks: with two forks a mouth beside the other's channel scores 0 to the source's
#: 2), decided by how far the end lies from where the sea ends' paths meet.
FAN_TIE = 0.1
#: The source's fork score must be at least this share of the number of voting forks: most forks fan
#: out from it (a network whose forks disagree, tributaries joining as much as channels split, keeps
#: the caller's rule).
FAN_AGREE = 0.5


#: A fork whose arms' angles do not tell its trunk arm (by ``OUTLET_MARGIN``: a channel leaving a bent
#: trunk's head at a right angle) votes for the arm whose line is at least this many times as thick as
#: either other arm's (the median radius along it): a channel splits into thinner ones, and tributaries
#: join into a thicker one, so the thickest arm runs toward the root either way.
FORK_WIDER = 1.3


def _arm_radius(g, deg: np.ndarray, start: int, prev: int, stop: np.ndarray, pts: np.ndarray, r: np.ndarray,
                reach: float) -> tuple[float, float, int]:
    """Follow an arm as :func:`~.skeleton_tree._walk_arm` does: (median radius past its first 2 px,
    length walked, last node)."""
    cur, back = int(start), int(prev)
    walked = float(np.hypot(*(pts[start] - pts[prev])))
    seen = [cur]
    while walked < reach and deg[cur] == 2 and not stop[cur]:
        nb = g.indices[g.indptr[cur]:g.indptr[cur + 1]]
        nxt = int(nb[0]) if int(nb[0]) != back else int(nb[1])
        walked += float(np.hypot(*(pts[nxt] - pts[cur])))
        back, cur = cur, nxt
        seen.append(cur)
    rr = r[seen[2:]] if len(seen) > 4 else r[seen]
    return float(np.median(rr)), walked, cur


def _fork_votes(g, deg: np.ndarray, members: np.ndarray, pts: np.ndarray, r: np.ndarray,
                reach: float) -> list[tuple[np.ndarray, int]]:
    """Per three-armed fork: ``(first nodes of its arms, index of its trunk arm)``, by the arms' angles as
    :func:`~.skeleton_tree._junction_trunk_arms` reads them, else by their widths (:data:`FORK_WIDER`)."""
    from .skeleton_tree import OUTLET_MARGIN

    jn = members[deg[members] >= 3]
    if not len(jn):
        return []
    is_j = np.zeros(len(deg), bool)
    is_j[jn] = True
    _n, lab = csgraph.connected_components(g[jn][:, jn], directed=False)
    out = []
    for c in np.unique(lab):
        cl = jn[lab == c]
        centre = pts[cl].mean(0)
        arms, dirs, wide, short = [], [], [], False
        for v in cl:
            for u in g.indices[g.indptr[v]:g.indptr[v + 1]]:
                if is_j[u]:
                    continue
                rad, walked, end = _arm_radius(g, deg, int(u), int(v), is_j, pts, r, reach)
                short |= walked < 0.5 * reach
                d = pts[end] - centre
                arms.append(int(u))
                dirs.append(np.arctan2(d[1], d[0]))
                wide.append(rad)
        if short or len(arms) != 3:
            continue
        a = np.asarray(dirs)
        pair = np.abs(np.angle(np.exp(1j * (a[:, None] - a[None, :]))))
        ang = np.array([pair[1, 2], pair[0, 2], pair[0, 1]])
        order = np.argsort(ang)
        if ang[order[1]] - ang[order[0]] >= OUTLET_MARGIN:
            out.append((np.asarray(arms, np.int64), int(order[0])))
            continue
        wide = np.asarray(wide)
        k = int(np.argmax(wide))
        if np.all(wide[k] >= FORK_WIDER * np.delete(wide, k)):
            out.append((np.asarray(arms, np.int64), k))
    return out


def _steiner_distance(dist_c: np.ndarray, dist_mm: np.ndarray) -> float:
    """How far an end lies from where the paths between the sea ends meet: the least, over pairs of sea
    ends (m, m'), of the Gromov product ``(d(c, m) + d(c, m') - d(m, m')) / 2`` (on a tree, the
    distance from the end to the path joining m and m')."""
    k = len(dist_c)
    if k < 2:
        return float(dist_c.min()) if k else 0.0
    iu = np.triu_indices(k, 1)
    prod = 0.5 * (dist_c[:, None] + dist_c[None, :] - dist_mm)[iu]
    prod = prod[np.isfinite(prod)]
    return float(prod.min()) if len(prod) else 0.0


def fan_source(g, deg: np.ndarray, cand: np.ndarray, members: np.ndarray, pts: np.ndarray, r: np.ndarray,
               sea_d: np.ndarray, end_r: np.ndarray) -> tuple[int, bool] | None:
    """The end of a piece from which it fans out to the sea, and whether that end lies at the sea.

    Parameters
    ----------
    g : sparse matrix
        The skeleton graph (:func:`~.skeleton_tree._skeleton_graph`).
    deg : (N,) int array
        Each node's number of neighbours.
    cand : (K,) int array
        The piece's ends.
    members : (M,) int array
        The piece's nodes.
    pts, r : (N, 2), (N,) arrays
        Node positions (x, y) and radii, full-size pixels.
    sea_d : (K,) array
        Each end's distance to the sea (the region, or the frame when there is none), full-size pixels.
    end_r : (K,) array
        Each end's radius (:func:`~.skeleton_tree._end_radius`).

    Returns
    -------
    (int, bool) or None
        The source node and whether it lies at the sea itself (a river draining there, or, with the frame
        for the sea, a trunk entering through it); ``None`` when fewer than two ends lie at the sea, no
        fork votes, or the best end gets fewer than :data:`FAN_AGREE` of the votes.
    """
    if len(cand) < 3:
        return None
    at = sea_d <= SEA_FRAME + SEA_RADII * end_r
    if at.sum() < 2:
        return None
    r_med = float(np.median(r[members]))
    votes = _fork_votes(g, deg, members, pts, r, 6.0 * r_med + 8.0)
    if not votes:
        return None
    dist = csgraph.dijkstra(g, directed=False, indices=cand)
    score = np.zeros(len(cand))
    n_votes = 0
    for arms, trunk in votes:
        arm = np.argmin(dist[:, arms], axis=1)
        # a confluence (a tributary joining upstream of the fan) has every mouth down its trunk arm: it
        # tells nothing of the source and would vote against the trunk's, once per tributary
        if np.all(arm[at] == trunk):
            continue
        score += np.where(arm == trunk, 1.0, -1.0)
        n_votes += 1
    if n_votes == 0:
        return None
    best = float(score.max())
    if best < FAN_AGREE * n_votes:
        return None
    tied = np.flatnonzero(score >= best - FAN_TIE * n_votes)
    # a tributary joining the trunk upstream of the fan scores as its trunk's source does (the confluence
    # votes against both); it is the thinner: inland ends tied with one FORK_WIDER x thicker are out
    inland = tied[~at[tied]]
    if len(inland) > 1:
        tied = np.setdiff1d(tied, inland[FORK_WIDER * end_r[inland] < end_r[inland].max()])
    sea = np.flatnonzero(at)
    dist_mm = dist[np.ix_(sea, cand[sea])]
    far = []
    for i in tied:
        others = sea[sea != i]
        keep = np.isin(sea, others)
        far.append(_steiner_distance(dist[i, cand[others]], dist_mm[np.ix_(keep, keep)]))
    # the farthest from the sea ends' meeting; then the better voted, the thicker
    k = tied[np.lexsort((-end_r[tied], -score[tied], -np.asarray(far)))[0]]
    return int(cand[k]), bool(at[k])


def _fan_root(g, deg: np.ndarray, cand: np.ndarray, members: np.ndarray, pts: np.ndarray, r: np.ndarray,
              sea_d: np.ndarray) -> int | None:
    """The end away from the sea from which a piece fans out to it (:func:`fan_source`),
    ``None`` when there is none (fewer than two ends at the sea, the forks disagree, or they point to an
    end at the sea: a river draining there)."""
    from .skeleton_tree import _end_radius

    if len(cand) < 3:
        return None
    src = fan_source(g, deg, cand, members, pts, r, sea_d, _end_radius(pts, r, cand, members))
    return None if src is None or src[1] else src[0]


def _delta_source_key(key: np.ndarray, pts: np.ndarray, r: np.ndarray, ends: np.ndarray,
                      members: np.ndarray, scale: float, g=None, deg=None, has_region: bool = True) -> np.ndarray:
    """Root key of a piece that reaches the region at several mouths: a delta roots at its source.

    A river drains to the sea at one mouth; a delta reaches it at several
    (its distributaries) and comes from one channel inland. With the
    skeleton graph ``g`` (and ``deg``), the end the piece fans out from
    (:func:`fan_source`: the end its forks point to, the
    farthest from where its sea ends' paths meet) becomes the root (key
    -1): away from the region, or anywhere when there is no region and the
    frame is the sea (``has_region`` False: a trunk entering through the
    frame, its channels leaving it). Else, with a region, when two or more
    ends of the piece lie at the region (within ``3 + 2 r`` pixels of it)
    and the thickest end away from it is at least 1.5 x thicker than every
    mouth, that end becomes the root; else ``key`` is kept. Going beyond
    the paper, whose roots are clicked: rooted at a mouth, a delta's tree
    runs upstream and the synthesis grows its trunk from the sea.

    Notes
    -----
    The forks before the widths (issue 23, branching83): on balanced
    binary deltas the ends are too alike in width for the 1.5 x rule
    (a 2-px trunk beside 1-px channels the sea widens at their mouths).
    """
    from .skeleton_tree import _end_radius

    if len(ends) < 3:
        return key
    er = _end_radius(pts, r, ends, members)
    if g is not None:
        src = fan_source(g, deg, ends, members, pts, r, np.asarray(key, np.float64) / scale, er)
        if src is not None and (not src[1] or not has_region):
            out = np.asarray(key, np.float64).copy()
            out[ends == src[0]] = -1.0
            return out
    if not has_region:
        return key
    near = key * 1.0 / scale <= 3.0 + 2.0 * er
    if near.sum() < 2 or near.all():
        return key
    far = np.flatnonzero(~near)
    best = far[np.argmax(er[far])]
    if er[best] < 1.5 * er[near].max():
        return key
    out = np.asarray(key, np.float64).copy()
    out[best] = -1.0
    return out
