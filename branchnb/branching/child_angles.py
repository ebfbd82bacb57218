"""The angle at which children leave their parent, measured past the parent's stroke (beyond the paper).

The paper starts a child with the input furcation's angle ``beta`` between the parent's tangent and the
child's first segment, and scores the copied head by space colonization. On line art both go wrong for
shallow children: a skeleton's child leaves the parent's centre line almost at a right angle inside the
stroke and bends to its true heading outside it (a border vine's 15-40 degree side strands measure 60-90
degrees on their first 4 px segment), and colonization scores a head that runs near its parent, as a
shallow child does for its first 10-20 px, as crowded. Synthesized children of ornaments came out 10-15
degrees steeper than the example's in the median (issue 23, branching60).

:func:`_child_angles` measures each child's heading where it has left the parent's stroke: the chord from
the parent's radius + 1 px of the child's arc to :data:`REACH` px farther, against the parent's chord over
8 px either side of the junction (0-180 degrees). :class:`_AngleMatch` keeps the synthesized children's
angles and scores a candidate head by how much its angle's bin is still short of the example's share (the
paper's global histogram matching, for the child's heading).

Examples
--------
>>> import numpy as np
>>> from branchnb.core.structure import Branch, Structure
>>> t = np.arange(0, 80.0)
>>> par = Branch(np.c_[t, np.full(80, 50.0)], 2.0)
>>> kid = Branch(np.c_[40 + t[:30] * np.cos(0.5), 50 + t[:30] * np.sin(0.5)], 1.0, parent=0, parent_vertex=40)
>>> np.round(_child_angles(Structure([par, kid])), 1).tolist()
[28.6]
"""

from __future__ import annotations

import numpy as np

__all__: list[str] = []

#: Length (px) of the chord a child's heading is measured on, past the parent's stroke.
REACH = 12.0
#: Histogram bins of child angles (degrees).
ANGLE_EDGES = np.arange(0.0, 181.0, 15.0)
#: Weight of the child-angle histogram factor ``exp(W (p_example - p_synthesized))`` of a child's head.
ANGLE_WEIGHT = 12.0
#: Score factor of a head whose angle bin is full: it already holds more children than the example's
#: share of the children so far, :data:`ANGLE_SPARE` to spare (a bin holds its share rounded; none in a
#: bin the example leaves empty; with 1 a bin of share 1/11 held 2 of 12 children).
#: Beyond the paper (issue 23, branching70): the exponential factor alone let heads whose furcation and
#: density scores were 10-30 x the others' fill a bin past its share; children leaving backward
#: (105-135 degrees) made 0.36-0.5 of an interlaced U or S band's children against the example's
#: 0.2-0.27, the mean child angle 10-20 degrees above the example's. (The angle read 13 px past the
#: parent on a 16-20 px head was no cause: the heads' angles and the grown children's differ by 1-2.5
#: degrees on the mean.)
ANGLE_FULL = 1e-4
ANGLE_SPARE = 0.5


#: The children rules of a band (this module's and ``FurcationModel.sample_d(generation=)`` /
#: ``_child_quota``) hold for line art drawn with about one pen: the 90th over the 10th percentile of the
#: example's vertex radii at most this. Ornaments measured 1.1-1.7 (the Celtic vine with its leaves 2.1);
#: binary masks of rivers, vessels, cracks and roots, whose side branches taper, 3.2-4.3 (a river mask
#: can lie in a band of its frame too: with the rules its output lost 0.2 of its length).
ONE_PEN = 2.5


def _one_pen(example) -> bool:
    """Is ``example`` (resampled: every vertex stands for the same length) drawn with about one pen
    (:data:`ONE_PEN`)?"""
    r = example.thicknesses()
    r = r[np.isfinite(r) & (r > 0)]
    if not len(r):
        return False
    lo, hi = np.percentile(r, [10.0, 90.0])
    return bool(hi <= ONE_PEN * max(lo, 1e-9))


def _at_arc(p: np.ndarray, s: float) -> np.ndarray:
    """The point of polyline ``p`` at arc length ``s`` (clipped to its ends)."""
    arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
    s = float(np.clip(s, 0.0, arc[-1]))
    return np.array([np.interp(s, arc, p[:, 0]), np.interp(s, arc, p[:, 1])])


def _angle(t: np.ndarray, d: np.ndarray) -> float:
    c = float(t @ d) / max(float(np.hypot(*t) * np.hypot(*d)), 1e-9)
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def _child_angles(s, reach: float = REACH) -> np.ndarray:
    """Angle (degrees, 0-180) between every child's heading past its parent's stroke and the parent's
    heading at the junction, in the order of the branches (roots and one-vertex branches skipped)."""
    out = []
    for b in s.branches:
        if b.parent is None or len(b.points) < 2:
            continue
        par = s.branches[b.parent]
        pp = np.asarray(par.points, np.float64)
        if len(pp) < 2:
            continue
        v = int(np.clip(b.parent_vertex or 0, 0, len(pp) - 1))
        arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(pp, axis=0).T))]
        t = _at_arc(pp, arc[v] + 8.0) - _at_arc(pp, arc[v] - 8.0)
        rp = np.broadcast_to(np.asarray(par.thickness, np.float64), (len(pp),))
        p = np.asarray(b.points, np.float64)
        a0 = float(rp[v]) + 1.0
        d = _at_arc(p, a0 + reach) - _at_arc(p, a0)
        if np.hypot(*d) < 1e-6:
            d = p[-1] - p[0]
        out.append(_angle(t, d))
    return np.asarray(out, np.float64)


def _head_angles(x0, theta0: float, new: np.ndarray, n: np.ndarray, r_parent: float,
                 reach: float = REACH) -> np.ndarray:
    """The :func:`_child_angles` measure of candidate heads: head ``j`` runs from ``x0`` through
    ``new[j, :n[j]]`` off a parent heading ``theta0`` (radians) of radius ``r_parent``."""
    x0 = np.asarray(x0, np.float64)
    t = np.array([np.cos(theta0), np.sin(theta0)])
    out = np.zeros(len(new))
    for j in range(len(new)):
        p = np.vstack([x0, new[j, : max(int(n[j]), 1)]])
        a0 = min(r_parent + 1.0, 0.5 * float(np.hypot(*np.diff(p, axis=0).T).sum()))
        d = _at_arc(p, a0 + reach) - _at_arc(p, a0)
        out[j] = _angle(t, d) if np.hypot(*d) > 1e-6 else 90.0
    return out


class _AngleMatch:
    """The example's child-angle histogram and the synthesized children's so far."""

    def __init__(self, example):
        a = _child_angles(example)
        self.p_ex = np.histogram(a, ANGLE_EDGES)[0] / max(len(a), 1)
        self.counts = np.zeros(len(ANGLE_EDGES) - 1)
        self.ok = len(a) >= 3

    def bins(self, angles: np.ndarray) -> np.ndarray:
        return np.clip(np.searchsorted(ANGLE_EDGES, angles, side="right") - 1, 0, len(ANGLE_EDGES) - 2)

    def factor(self, angles: np.ndarray) -> np.ndarray:
        """``exp(W (p_example - p_synthesized))`` of each candidate's angle bin, times :data:`ANGLE_FULL`
        where the bin is full (all 1 without an example of at least 3 children)."""
        if not self.ok:
            return np.ones(len(angles))
        n = self.counts.sum()
        q = self.counts / n if n else np.zeros_like(self.counts)
        b = self.bins(angles)
        # a bin that already holds more than its share of the children so far (rounded) is full (beyond
        # the paper, branching70): see ANGLE_FULL
        full = self.counts + 1.0 > self.p_ex * (n + 1.0) + np.where(self.p_ex > 0, ANGLE_SPARE, 0.0)
        return np.exp(ANGLE_WEIGHT * (self.p_ex - q)[b]) * np.where(full[b], ANGLE_FULL, 1.0)

    def add(self, angle: float) -> None:
        self.counts[self.bins(np.array([angle]))[0]] += 1
