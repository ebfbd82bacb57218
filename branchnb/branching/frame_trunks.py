"""Automatic extraction (beyond the paper, issue 23, branching84): the trunks a piece enters the frame by.

``root="auto"`` (:func:`~branchnb.branching.skeleton_tree.skeleton_to_structure`) roots a piece at
every end where a line enters the frame at full thickness (``_frame_entries``): at least twice the
piece's median radius. A river network entering at the bottom edge tapers less than that: its
trunks (3.5 px) were 1.5-1.8 x the median radius (2.3 px, the tributaries'), so no end entered; its
axis also stops about a radius short of the frame (5 px, past the 4 px of the small-example rules),
and the piece was rooted at its thickest *end*, a skeleton spur at an inner junction's blob. The
learnt main branch then ran from mid-canvas down to the frame and up a tributary, and the output's
trunks pointed the wrong way (``_frame_hug_check``: 9 of 15 river examples rooted inside). Two
trunks of one piece (their tips touch) also got one root between them.

:func:`frame_trunks` finds those entries by what a trunk cut by the frame looks like from inside:
just inside the frame the line is clearly thicker than the piece's median line (a tapering tip
leaving the frame is thinner than it), about as thick as the thickest such line, and the forks
of the part of the piece nearest to it point to it (a vessel tree whose thick vessels leave the
frame, grown from its disc inside, has its forks pointing away).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csgraph

#: An end lies at the frame within this many pixels plus :data:`TRUNK_FRAME_RADII` x its radius.
TRUNK_FRAME = 4.0
#: ... (a thick line's medial axis stops about a radius short of the frame that cuts it).
TRUNK_FRAME_RADII = 1.0
#: A trunk enters at least this many times as thick (just inside the frame) as the piece's median radius
#: (the rivers of ``_frame_hug_check``: 1.5-1.8, its roots 1.25-1.5; a tapering tip leaving the
#: frame: under 1).
TRUNK_RATIO = 1.2
#: ... and at least this share of the thickest frame end's thickness.
TRUNK_SHARE = 0.75
#: The forks of an entry's part of the piece overrule it (pointing away from it) from this many on.
TRUNK_VOTES = 3
#: Two entries are one line (a trunk crossing the canvas enters once) when a path of nodes at least
#: this share of the thinner entry's radius joins them.
TRUNK_LINE = 0.75


def _trunk_votes(g, deg, members: np.ndarray, pts: np.ndarray, r: np.ndarray,
                 ends: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per end in ``ends``: ``(score, count)`` of the fork votes (``+1`` a fork whose trunk arm leads to
    it, ``-1`` else) of the forks nearer to it along the skeleton than to the other ends (its own tree
    once the piece is split)."""
    from .skeleton_tree import _junction_trunk_arms

    r_med = float(np.median(r[members]))
    votes = _junction_trunk_arms(g, deg, members, pts, 6.0 * r_med + 8.0)
    score = np.zeros(len(ends))
    count = np.zeros(len(ends))
    if not votes:
        return score, count
    dist = csgraph.dijkstra(g, directed=False, indices=ends)
    dist = np.atleast_2d(dist)
    for arms, trunk in votes:
        to_arm = dist[:, arms]
        own = int(np.argmin(to_arm.min(1)))
        if not np.isfinite(to_arm[own]).any():
            continue
        score[own] += 1.0 if int(np.argmin(to_arm[own])) == trunk else -1.0
        count[own] += 1.0
    return score, count


def frame_trunks(g, deg: np.ndarray, cand: np.ndarray, members: np.ndarray, pts: np.ndarray,
                 r: np.ndarray, frame_d: np.ndarray, end_r: np.ndarray,
                 side: np.ndarray | None = None) -> list[int]:
    """The ends of a piece where its trunks enter the frame (empty: none).

    Parameters
    ----------
    g : scipy.sparse matrix
        The skeleton graph (edge weights in full-size pixels).
    deg : (n,) ndarray
        Every node's degree.
    cand : (k,) ndarray of int
        The piece's end nodes.
    members : (m,) ndarray of int
        The piece's nodes.
    pts, r : (n, 2), (n,) ndarray
        Every node's position and radius (full-size pixels).
    frame_d : (k,) ndarray
        Each end's distance to the frame (full-size pixels).
    end_r : (k,) ndarray
        Each end's radius (the largest near it, ``skeleton_tree._end_radius``).
    side : (n,) ndarray of int, optional
        Every node's nearest frame side (``skeleton_tree._one_per_line``).

    Returns
    -------
    list of int
        Nodes (from ``cand``), thickest first: each roots a tree.

    Notes
    -----
    An end within :data:`TRUNK_FRAME` + :data:`TRUNK_FRAME_RADII` x its radius of the frame enters
    there when the line just inside it (``skeleton_tree._inside_radius``) is at least
    :data:`TRUNK_RATIO` x the piece's median radius and :data:`TRUNK_SHARE` x the thickest frame end's,
    and the forks of its part of the piece do not point away from it (:func:`_trunk_votes`: from
    :data:`TRUNK_VOTES` forks on, score ``>= 0``). Entries joined by a line of at least
    :data:`TRUNK_LINE` x their radius are one line crossing the canvas: it enters once, at the
    thickest (unless they enter by the same side: two trunks whose children touch).
    """
    from .skeleton_tree import _inside_radius

    at = np.flatnonzero(frame_d <= TRUNK_FRAME + TRUNK_FRAME_RADII * end_r)
    if not len(at):
        return []
    r_med = float(np.median(r[members]))
    inside = _inside_radius(g, cand[at], r, r_med)
    ok = (inside >= TRUNK_RATIO * r_med) & (inside >= TRUNK_SHARE * float(inside.max()))
    if not ok.any():
        return []
    at, inside = at[ok], inside[ok]
    score, count = _trunk_votes(g, deg, members, pts, r, cand[at])
    # (a fork or two may be where two trees' lines touch: the touching line's arms both lead inward)
    keep = (score >= 0) | (count < TRUNK_VOTES)
    at, inside = at[keep], inside[keep]
    if not len(at):
        return []
    from .skeleton_tree import _one_per_line

    out: list[int] = []
    for i in np.argsort(-inside, kind="stable"):
        p = pts[cand[at[i]]]
        if all(np.hypot(*(p - pts[j])) > 4.0 * inside[i] for j in out):
            out.append(int(cand[at[i]]))
    # one line crossing the canvas (a crack's trunk from side to side) enters once
    return _one_per_line(out, g, r, 2.0 * TRUNK_LINE * float(inside.min()), side)
