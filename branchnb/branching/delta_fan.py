"""A delta's own axis and fan, learned from the example (beyond the paper; issue 23, branching58).

The paper's Markov chain has no notion of downstream; :class:`.domains._Drain` pulls a delta's
branches toward the sea. Its trunk followed the steepest descent of the land to the sea, so it always
reached the sea straight across the coast, and its channels took bearings off that descent. An
example's trunk may run far off the descent (a river entering through a side of the frame and
fanning toward a coast below): this module reads the delta's *axis* off the example, from where its
trunk enters the land to the mean of its mouths (where its channels meet the sea), and the example's
distribution of channel headings at the sea about that axis; the trunk heads for the example's mouths
and each new channel takes a heading the synthesized channels have used least
(:meth:`.domains._Drain.bearing`).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.structure import Structure

#: A branch reaches the sea when its last vertex is within this share of the land's deepest depth of
#: it (as :func:`.domains._drains` and :func:`.domains.fan_spread`).
SEA_SHARE = 0.1
#: A channel's heading at the sea is taken where it last lies this share of the frame's diagonal from
#: the sea, over the preceding :data:`HEADING_BACK` share (as ``_structure_check.sea_bearings_inland``,
#: the fan's measure): the fan of the channels, not the turns of their mouths along the coast.
HEADING_INLAND = 0.05
HEADING_BACK = 0.03


def _mouths(example: Structure, depth: np.ndarray) -> tuple[list[int], np.ndarray]:
    """Indices and last vertices of the example's branches that reach the sea."""
    h, w = depth.shape
    deep = float(depth.max())
    idx, ends = [], []
    for i, b in enumerate(example.branches):
        if len(b.points) < 2:
            continue
        x, y = np.clip(np.rint(b.points[-1]).astype(int), 0, [w - 1, h - 1])
        if depth[y, x] < SEA_SHARE * deep:
            idx.append(i)
            ends.append(np.asarray(b.points[-1], np.float64))
    return idx, np.asarray(ends, np.float64).reshape(-1, 2)


def delta_axis(example: Structure, domain: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The delta's axis: (start, target), both (x, y).

    ``start`` is the first vertex of the example's longest root (where its trunk enters the land) and
    ``target`` the mean of the last vertices of its branches that reach the sea (within
    :data:`SEA_SHARE` x the deepest depth of it): the direction from the inland root to the sea-side
    spread of the channels, not the descent of the land. A trunk entering through a side of the frame
    runs far off the descent (55 degrees on the ``fan55`` kind of :mod:`._delta_fan_check`).

    Parameters
    ----------
    example : Structure
        The example's structure.
    domain : (H, W) array_like of bool
        Where it may grow (the land); the sea lies outside it.

    Returns
    -------
    tuple of two (2,) ndarray or None
        None when no root starts inland of the target (at least a tenth of the deepest depth deeper)
        or no branch reaches the sea.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> dom = np.zeros((100, 100), bool); dom[:80] = True
    >>> s = Structure([Branch([(0, 20), (40, 50)], 2.0), Branch([(40, 50), (20, 79)], 1.0, 0, 1),
    ...                Branch([(40, 50), (80, 79)], 1.0, 0, 1)])
    >>> start, target = delta_axis(s, dom)
    >>> start.tolist(), target.tolist()
    ([0.0, 20.0], [50.0, 79.0])
    """
    dom = np.asarray(domain, bool)
    if dom.all() or not dom.any():
        return None
    depth = ndi.distance_transform_edt(dom)
    roots = [b for b in example.branches if b.parent is None and len(b.points) >= 2]
    if not roots:
        return None
    root = max(roots, key=lambda b: float(np.hypot(*np.diff(np.asarray(b.points, np.float64), axis=0).T).sum()))
    _idx, ends = _mouths(example, depth)
    if not len(ends):
        return None
    start = np.asarray(root.points[0], np.float64)
    target = ends.mean(0)
    h, w = dom.shape

    def at(p):
        x, y = np.clip(np.rint(p).astype(int), 0, [w - 1, h - 1])
        return float(depth[y, x])

    if at(start) < at(target) + 0.1 * float(depth.max()) or np.hypot(*(target - start)) < 1.0:
        return None
    return start, target


def fan_offsets(example: Structure, domain: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Signed angles (radians, image frame: positive clockwise on screen) of the headings of the example's
    channels at the sea off the delta's ``axis`` (unit x, y, :func:`delta_axis`), one per branch that
    reaches the sea, the trunk's included.

    The heading is a channel's direction over the :data:`HEADING_BACK` x the diagonal before the point
    where it last lies :data:`HEADING_INLAND` x the diagonal from the sea (its chord when shorter).

    Parameters
    ----------
    example : Structure
        The example's structure.
    domain : (H, W) array_like of bool
        Where it may grow (the land).
    axis : (2,) array_like
        The delta's axis direction (x, y).

    Returns
    -------
    (K,) ndarray
        Sorted; empty when no branch reaches the sea.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> dom = np.zeros((100, 100), bool); dom[:80] = True
    >>> s = Structure([Branch([(50, 0), (50, 40)], 2.0), Branch([(50, 40), (10, 80)], 1.0, 0, 1),
    ...                Branch([(50, 40), (90, 80)], 1.0, 0, 1)])
    >>> np.round(np.degrees(fan_offsets(s, dom, (0.0, 1.0)))).tolist()
    [-45.0, 45.0]
    """
    dom = np.asarray(domain, bool)
    depth = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    diag = float(np.hypot(h, w))
    ax = np.asarray(axis, np.float64)
    a0 = float(np.arctan2(ax[1], ax[0]))
    idx, _ends = _mouths(example, depth)
    return np.sort(np.asarray([v for v in (_heading_off(example, i, depth, diag, a0) for i in idx) if v is not None],
                              np.float64))


def root_offset(example: Structure, domain: np.ndarray, axis: np.ndarray) -> float | None:
    """The heading at the sea (radians off ``axis``, as :func:`fan_offsets`) of the example's longest root.

    Parameters
    ----------
    example : Structure
        The example's structure.
    domain : (H, W) array_like of bool
        Where it may grow (the land).
    axis : (2,) array_like
        The delta's axis direction (x, y).

    Returns
    -------
    float or None
        None when the root does not reach the sea (the trunk ends at the delta's head).

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> dom = np.zeros((100, 100), bool); dom[:80] = True
    >>> s = Structure([Branch([(50, 0), (50, 79)], 2.0)])
    >>> round(float(np.degrees(root_offset(s, dom, (0.0, 1.0)))))
    0
    """
    dom = np.asarray(domain, bool)
    depth = ndi.distance_transform_edt(dom)
    ax = np.asarray(axis, np.float64)
    roots = [i for i, b in enumerate(example.branches) if b.parent is None and len(b.points) >= 2]
    idx, _ends = _mouths(example, depth)
    if not roots:
        return None
    r = max(roots, key=lambda i: float(np.hypot(*np.diff(np.asarray(example.branches[i].points, np.float64),
                                                        axis=0).T).sum()))
    if r not in idx:
        return None
    return _heading_off(example, r, depth, float(np.hypot(*dom.shape)), float(np.arctan2(ax[1], ax[0])))


def _heading_off(example: Structure, i: int, depth: np.ndarray, diag: float, a0: float) -> float | None:
    """Branch ``i``'s heading at the sea (radians off the axis at angle ``a0``; see :func:`fan_offsets`)."""
    h, w = depth.shape
    p = np.asarray(example.branches[i].points, np.float64)
    ix = np.clip(np.rint(p).astype(int), 0, [w - 1, h - 1])
    dv = depth[ix[:, 1], ix[:, 0]]
    far = np.flatnonzero(dv >= HEADING_INLAND * diag)
    k = int(far[-1]) if len(far) else len(p) - 1
    seg = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p[: k + 1], axis=0).T))]
    j = int(np.searchsorted(seg, seg[-1] - HEADING_BACK * diag))
    v = p[k] - p[j] if j < k else p[-1] - p[0]
    if np.hypot(*v) < 1e-9:
        return None
    return float(np.angle(np.exp(1j * (np.arctan2(v[1], v[0]) - a0))))


def pick_offset(offsets: np.ndarray, used: np.ndarray, off: float, a_p: float, trunk: bool,
                split: float) -> int | None:
    """Index of the example's heading (``offsets``, off the axis) a new channel takes.

    The channel leaves with heading ``off`` a parent whose way down is ``a_p`` (both radians off the
    axis); the heading must lie at least ``split`` off ``a_p`` on the side the channel leaves on (a
    channel's channel, ``trunk`` False, whose parent runs ``split`` or more off the axis: toward the axis,
    between its parent and the trunk, as the example's do); of those, the one given least often so far
    (``used``), the closest to ``off`` among equals.

    Parameters
    ----------
    offsets : (K,) ndarray
        The example's headings at the sea off the axis (:func:`fan_offsets`).
    used : (K,) ndarray
        How often each was given so far.
    off : float
        The channel's heading where it leaves its parent.
    a_p : float
        The parent's way down there.
    trunk : bool
        The parent is the trunk.
    split : float
        The least angle between the channel's heading and ``a_p``.

    Returns
    -------
    int or None
        None when no heading fits.

    Examples
    --------
    >>> o = np.radians([-50.0, 0.0, 55.0])
    >>> pick_offset(o, np.array([0.0, 1.0, 0.0]), 0.3, 0.0, True, np.radians(25.0))
    2
    >>> pick_offset(o, np.array([0.0, 1.0, 1.0]), -0.3, 0.0, True, np.radians(25.0))
    0
    """
    o = np.asarray(offsets, np.float64)
    rel = o - a_p
    ok = np.abs(rel) >= split
    if trunk or abs(a_p) < split:
        ok &= np.sign(rel) == (1.0 if off - a_p >= 0 else -1.0)
    else:
        ok &= (np.sign(rel) == -np.sign(a_p)) & ((np.sign(o) == np.sign(a_p)) | (np.abs(o) < split))
    if not ok.any():
        return None
    cand = np.flatnonzero(ok)
    u = np.asarray(used)[cand]
    cand = cand[u == u.min()]
    return int(cand[np.argmin(np.abs(o[cand] - off))])


def _tail_share(example: Structure, domain: np.ndarray) -> float:
    """Where a delta's trunk ends and turns into one of its channels, as a share of its depth.

    Beyond the paper (issue 23, branching65): the example's longest root runs on past its first
    furcation (often a dry side arm, :func:`head_share`) to the delta's head, where its first channel
    that reaches the sea parts; below it the root is one of the fan's channels, not a trunk carrying on
    in the fan's middle.

    Parameters
    ----------
    example : Structure
        The example's structure.
    domain : (H, W) array_like of bool
        Where it may grow (the land); depth is the distance to its boundary.

    Returns
    -------
    float
        Depth of the longest root's first child that reaches the sea (its subtree within
        :data:`SEA_SHARE` x the deepest depth of it) over the depth of that root's start; 0 when the root
        does not reach the sea or no child of it does.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> dom = np.zeros((100, 100), bool); dom[:80] = True
    >>> s = Structure([Branch([(50, 0), (50, 40), (20, 79)], 2.0), Branch([(50, 40), (80, 79)], 1.0, 0, 1)])
    >>> round(_tail_share(s, dom), 2)
    0.5
    """
    dom = np.asarray(domain, bool)
    if dom.all() or not dom.any():
        return 0.0
    depth = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    roots = [i for i, b in enumerate(example.branches) if b.parent is None and len(b.points) >= 2]
    idx, _ends = _mouths(example, depth)
    if not roots:
        return 0.0
    r = max(roots, key=lambda i: float(np.hypot(*np.diff(np.asarray(example.branches[i].points, np.float64),
                                                        axis=0).T).sum()))
    wet = set(idx)
    if r not in wet:
        return 0.0
    kids: dict[int, list[int]] = {}
    for i, b in enumerate(example.branches):
        if b.parent is not None:
            kids.setdefault(int(b.parent), []).append(i)

    def reaches(i: int) -> bool:
        todo = [i]
        while todo:
            j = todo.pop()
            if j in wet:
                return True
            todo.extend(kids.get(j, []))
        return False

    verts = [example.branches[c].parent_vertex for c in kids.get(r, [])
             if example.branches[c].parent_vertex is not None and reaches(c)]
    if not verts:
        return 0.0
    p = np.asarray(example.branches[r].points, np.float64)
    ix = np.clip(np.rint(p).astype(np.int64), 0, [w - 1, h - 1])
    d = depth[ix[:, 1], ix[:, 0]]
    if d[0] <= 0:
        return 0.0
    return float(d[min(int(min(verts)), len(d) - 1)] / d[0])


#: A channel leaving a straight delta's head carries its trunk on when it heads at most this far off the
#: trunk's heading just above the head (:func:`_trunk_turns`; :data:`.domains.FAN_SPLIT`, the least angle
#: at which channels part).
CONTINUE_MAX = float(np.radians(25.0))
#: ... and the trunk turns into the thickest channel instead only when that is at least this many times as
#: wide as the one carrying it on (:func:`_trunk_turns`).
TURN_WIDTH = 1.7


def _trunk_turns(example: Structure, domain: np.ndarray) -> bool:
    """Does a straight delta's trunk turn into one of its channels at its head, or carry on straight?

    Beyond the paper (issue 23, branching68). The head is where the longest root's first child whose
    subtree reaches the sea parts (:func:`_tail_share`); the channels leaving it are the root below it
    and every branch of those subtrees starting within 6 % of the frame's diagonal of it. Each one's
    heading is taken over its first 5 % of the diagonal, the trunk's over the 5 % above the head, and each
    one's width as its median thickness over 2-10 % of the diagonal from its start. The trunk carries on
    straight when a channel heads within :data:`CONTINUE_MAX` of the trunk and no channel is
    :data:`TURN_WIDTH` x as wide as it; it turns otherwise, unless its two widest channels part evenly
    about it (:func:`_even_fork`, branching79). Which of the channels the skeleton's root
    follows says nothing: on a delta with a straight trunk and a channel fanning off on each side
    (``fan0`` of :mod:`._delta_fan_check`) the root takes one of the outer channels, and the synthesized
    trunk that followed it bunched every channel on one side. ``python -m branchnb.branching._delta_fan_check``
    examples (width of the thickest over the continuing channel): ``delta`` (the wide distributary
    parts 55 degrees off the trunk, the middle one is half as wide) 1.84-2.06, ``fan0`` (widths 4.5 / 3.05
    / 1.6 px from the left) 1.40-1.56, at 300/512/1024 px: the threshold lies between, set on these two
    generators.

    Parameters
    ----------
    example : Structure
        The example's structure.
    domain : (H, W) array_like of bool
        Where it may grow (the land).

    Returns
    -------
    bool
        False also when the root does not reach the sea or has no child reaching it.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> dom = np.zeros((100, 100), bool); dom[:80] = True
    >>> bent = Structure([Branch([(50, 0), (50, 40), (20, 79)], 4.0), Branch([(50, 40), (80, 79)], 1.0, 0, 1)])
    >>> _trunk_turns(bent, dom)
    True
    >>> straight = Structure([Branch([(50, 0), (50, 40), (20, 79)], 4.0), Branch([(50, 40), (80, 79)], 3.0, 0, 1),
    ...                       Branch([(50, 40), (50, 79)], 3.0, 1, 0)])
    >>> _trunk_turns(straight, dom)
    False
    """
    dom = np.asarray(domain, bool)
    if dom.all() or not dom.any():
        return False
    depth = ndi.distance_transform_edt(dom)
    diag = float(np.hypot(*dom.shape))
    br = example.branches
    roots = [i for i, b in enumerate(br) if b.parent is None and len(b.points) >= 2]
    if not roots:
        return False

    def arc(q):
        return np.r_[0.0, np.cumsum(np.hypot(*np.diff(q, axis=0).T))]

    r = max(roots, key=lambda i: float(arc(np.asarray(br[i].points, np.float64))[-1]))
    idx, _ends = _mouths(example, depth)
    wet = set(idx)
    if r not in wet:
        return False
    kids: dict[int, list[int]] = {}
    for i, b in enumerate(br):
        if b.parent is not None:
            kids.setdefault(int(b.parent), []).append(i)

    def subtree(i: int) -> list[int]:
        out, todo = [], [i]
        while todo:
            j = todo.pop()
            out.append(j)
            todo.extend(kids.get(j, []))
        return out

    trees = [subtree(c) for c in kids.get(r, []) if br[c].parent_vertex is not None]
    trees = [(br[t[0]].parent_vertex, t) for t in trees if wet.intersection(t)]
    if not trees:
        return False
    p = np.asarray(br[r].points, np.float64)
    k = min(int(min(v for v, _t in trees)), len(p) - 1)
    s = arc(p)
    step, near = 0.05 * diag, 0.06 * diag

    def heading(q, sq, at):
        e = min(int(np.searchsorted(sq, sq[at] + step)), len(q) - 1)
        v = q[e] - q[at]
        return float(np.arctan2(v[1], v[0])) if np.hypot(*v) > 1e-9 else None

    def width(b, sq, at):
        t = np.broadcast_to(np.asarray(b.thickness, np.float64), (len(sq),))
        sel = (sq >= sq[at] + 0.02 * diag) & (sq <= sq[at] + 0.1 * diag)
        return float(np.median(t[sel])) if sel.any() else float(np.median(t[at:]))

    v_in = p[k] - p[max(0, int(np.searchsorted(s, s[k] - step, side="right")) - 1)]
    if np.hypot(*v_in) < 1e-9:
        return False
    a_in = float(np.arctan2(v_in[1], v_in[0]))
    chans = [(heading(p, s, k), width(br[r], s, k))] if k < len(p) - 1 else []
    for _v, t in trees:
        for i in t:
            q = np.asarray(br[i].points, np.float64)
            if len(q) < 2 or np.hypot(*(q[0] - p[k])) > near:
                continue
            sq = arc(q)
            chans.append((heading(q, sq, 0), width(br[i], sq, 0)))
    chans = [(a, wd) for a, wd in chans if a is not None]
    if not chans:
        return False
    signed = np.angle(np.exp(1j * (np.array([a for a, _w in chans]) - a_in)))
    off = np.abs(signed)
    wd = np.array([w_ for _a, w_ in chans])
    c = int(np.argmin(off))
    if _even_fork(signed, wd):
        return False
    if off[c] > CONTINUE_MAX:
        return True
    return bool(wd.max() >= TURN_WIDTH * wd[c])


def _even_fork(signed: np.ndarray, wd: np.ndarray) -> bool:
    """Do the two widest channels leaving a delta's head (headings ``signed`` radians off the trunk's,
    widths ``wd``) part evenly: one on each side of the trunk, as wide as each other (within
    :data:`TURN_WIDTH`), their bisector within :data:`CONTINUE_MAX` / 2 of the trunk's heading?

    Beyond the paper (issue 23, branching79): at an even fork the skeleton's root follows one of the two
    arms as it happens; taken for a turn (:func:`_trunk_turns`), the synthesized trunk ran down that arm's
    side of the fan and the other channels bunched beside it. An even fork is no turn: the trunk carries on
    between the arms, held to the example's mouths (:data:`.drain.STRAIGHT_HOLD`), its channels on both
    sides. On the even binary deltas of :func:`._delta_examples.delta_tree_mask` (2-4 orders, 60-140 degree
    fans, 256-1024 px, four sea sides; 5 seeds each) the trunk bearing error, mean over the seeds, was
    10.2-19.7 degrees on main and is 2.1-4.2 with this and the hold (``python -m
    branchnb.branching._delta_tree_check 5``, 7 of its 8 cases; the mouths on the smaller side of the trunk,
    :func:`._delta_fan_check.mouth_share`, mean 0.02-0.36 -> 0.36-0.43). A fork whose arms' bisector lies more
    than :data:`CONTINUE_MAX` / 2 off the trunk's heading is still a turn (a 150 degree fan at 512 px:
    arms 36 and -63 degrees off it; bearing error as main, 21.6).

    Examples
    --------
    >>> bool(_even_fork(np.radians([30.0, -35.0]), np.array([3.0, 2.6])))
    True
    >>> bool(_even_fork(np.radians([30.0, -35.0]), np.array([3.0, 1.0])))   # one arm much thinner
    False
    """
    if len(wd) < 2:
        return False
    i, j = np.argsort(-wd)[:2]
    return bool(signed[i] * signed[j] < 0 and wd[i] < TURN_WIDTH * wd[j]
                and abs(signed[i] + signed[j]) <= CONTINUE_MAX)  # bisector within CONTINUE_MAX / 2


def head_share(example, domain) -> float:
    """Where a delta's channels part, as a share of its trunk's depth.

    Beyond the paper (issue 23): the example's distributaries fan out from its head, not from where
    its trunk enters the image. Fanned from the trunk's start, the channels of a 1000 px delta reached the
    sea 1-15 degrees apart (circular spread of their last 30 px), against the example's 71.

    Parameters
    ----------
    example : Structure
        The example's structure.
    domain : (H, W) array_like of bool
        Where it may grow (the land); depth is the distance to its boundary.

    Returns
    -------
    float
        Depth of the example's first furcation on a root over the depth of that root's start
        (1 = at the start, 0 at the sea); 0 when no root has a child.
    """

    dom = np.asarray(domain, bool)
    depth = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    best = 0.0
    for i, b in enumerate(example.branches):
        if b.parent is not None or len(b.points) < 2:
            continue
        kids = [c.parent_vertex for c in example.branches if c.parent == i and c.parent_vertex is not None]
        if not kids:
            continue
        p = np.asarray(b.points, np.float64)
        ix = np.clip(np.rint(p[:, 0]).astype(np.int64), 0, w - 1)
        iy = np.clip(np.rint(p[:, 1]).astype(np.int64), 0, h - 1)
        d = depth[iy, ix]
        if d[0] <= 0:
            continue
        best = max(best, float(d[min(int(min(kids)), len(d) - 1)] / d[0]))
    return best
