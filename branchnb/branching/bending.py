"""Bending model: a Markov chain over (turning angle, thickness) sequences.

Every branch of the example, resampled at step ``h``, becomes a sequence
of *elements*: element ``i`` is the pair ``(alpha_i, r_{i+1})`` of the
turning angle at vertex ``i`` and the thickness of the following vertex,
so appending one element to a branch turns it by ``alpha`` at its tip and
adds a vertex ``h`` further on with radius ``r``.

Synthesis keeps the history of the last ``k + 1`` elements of the growing
branch. Every sub-sequence of ``k + 1`` consecutive input elements is a
candidate; its quality is

    Q = dist(alpha_H, alpha_W) * dist(r_H, r_W),
    dist(X, Y) = 1 / (||X - Y|| + 1) + 1,

and one of the ``c`` best candidates (probability proportional to Q)
contributes the ``m`` elements that follow it in the input. A candidate
that ends its input branch with fewer than ``m`` followers ends the
synthesized branch too: that is how the Markov chain learns where
branches stop. All candidates are scored at once with numpy.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.polyline import tangents
from ..core.structure import Structure

__all__ = ["BendingModel", "branch_elements", "markov_dist"]


def markov_dist(x, y, axis: int = -1) -> np.ndarray:
    """The paper's similarity ``dist(X, Y) = 1 / (||X - Y|| + 1) + 1`` (in (1, 2]).

    Parameters
    ----------
    x, y : array_like
        Two element sequences X and Y (broadcast against each other), e.g.
        windows of turning angles (radians) or of thicknesses (pixels).
    axis : int, default -1
        Axis along which the Euclidean norm ``||X - Y||`` is taken.

    Returns
    -------
    ndarray
        ``dist(X, Y)`` with ``axis`` reduced: 2 for equal sequences, tending
        to 1 as they move apart.

    Examples
    --------
    >>> float(markov_dist([0.0, 0.0], [3.0, 4.0]))
    1.1666666666666667
    """
    d = np.asarray(x, np.float64) - np.asarray(y, np.float64)
    return 1.0 / (np.sqrt(np.sum(d * d, axis=axis)) + 1.0) + 1.0


def branch_elements(points: np.ndarray, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Elements ``(alpha_i, r_{i+1})``, i = 1 .. N-2, of one resampled branch.

    Returns ``(angles (N-2,), radii (N-2,))``; empty for N < 3.

    Parameters
    ----------
    points : (N, 2) array_like
        Vertices (x, y) of one branch resampled at step h (pixels).
    radii : (N,) array_like
        Thickness r of each vertex (pixels).

    Returns
    -------
    angles : (N-2,) ndarray
        Turning angle alpha_i at each inner vertex (radians in (-pi, pi],
        positive when turning from +x towards +y).
    radii : (N-2,) ndarray
        Thickness r_{i+1} of the vertex following each turn.

    Examples
    --------
    >>> a, r = branch_elements([[0, 0], [1, 0], [1, 1]], [3.0, 2.0, 1.0])
    >>> round(float(a[0]), 4), r.tolist()
    (1.5708, [1.0])
    """
    p = np.asarray(points, np.float64)
    r = np.asarray(radii, np.float64)
    if len(p) < 3:
        return np.zeros(0), np.zeros(0)
    d = np.diff(p, axis=0)
    u, v = d[:-1], d[1:]
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    dot = np.einsum("ij,ij->i", u, v)
    return np.arctan2(cross, dot), r[2:].copy()


def _angle_between(u: np.ndarray, v: np.ndarray) -> float:
    return float(np.arctan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1]))


@dataclass
class BendingModel:
    """The example's element sequences, ready for vectorised candidate scoring.

    Build it with :meth:`fit` from a structure already resampled at ``h``.

    Parameters
    ----------
    m, k : int
        Elements appended per step, history length ``k + 1``.
    h : float
        Resampling step h of the example (pixels).
    angles, radii : (T,) ndarray
        All elements of all branches, concatenated: turning angles alpha
        (radians, positive when turning from +x towards +y) and thicknesses r
        (pixels).
    branch, local : (T,) int ndarray
        Branch of each element and its index inside the branch sequence.
    cont_angles, cont_radii : (T, m) ndarray
        The (up to) ``m`` elements following each element (0 beyond).
    cont_len : (T,) int ndarray
        How many followers exist (< m near the end of a branch).
    starts : (n_branches,) int ndarray
        Index of each branch's first element in ``angles``.
    heads : list of dict
        Per input branch: first radii ``r0``, ``r1``, branching angle
        ``beta`` (children), number of elements.
    local_points : (T, m, 2) ndarray, optional
        The vertices each element's followers would append, in the frame of
        a tip at the origin heading along +x (pixels); set by :meth:`fit`.
    """

    m: int
    k: int
    h: float
    angles: np.ndarray
    radii: np.ndarray
    branch: np.ndarray
    local: np.ndarray
    cont_angles: np.ndarray
    cont_radii: np.ndarray
    cont_len: np.ndarray
    starts: np.ndarray
    heads: list = field(default_factory=list)
    local_points: np.ndarray = field(default=None, repr=False)
    _windows: dict = field(default_factory=dict, repr=False)

    @classmethod
    def fit(cls, structure: Structure, m: int, k: int, h: float) -> BendingModel:
        """Collect the elements of every branch of a structure resampled at ``h``.

        Parameters
        ----------
        structure : Structure
            The example, every branch resampled at step ``h``.
        m : int
            Elements appended per synthesis step (m = s / h).
        k : int
            History length: candidates are windows of up to ``k + 1`` elements.
        h : float
            The resampling step h (pixels) of ``structure``.

        Returns
        -------
        BendingModel
            All elements, their followers and per-branch heads.
        """
        angs, rads, br, loc, starts, heads = [], [], [], [], [], []
        total = 0
        for i, b in enumerate(structure.branches):
            a, r = branch_elements(b.points, b.thickness)
            beta = None
            if b.parent is not None and len(b.points) >= 2:
                par = structure.branches[b.parent]
                if len(par.points) >= 2:
                    t = tangents(par.points)[b.parent_vertex]
                    beta = _angle_between(t, b.points[1] - b.points[0])
            heads.append({
                "r0": float(b.thickness[0]),
                "r1": float(b.thickness[1]) if len(b.thickness) > 1 else float(b.thickness[0]),
                "beta": beta, "n": len(a), "start": total,
                "step": float(np.hypot(*(b.points[1] - b.points[0]))) if len(b.points) > 1 else 0.0,
            })
            starts.append(total)
            angs.append(a)
            rads.append(r)
            br.append(np.full(len(a), i))
            loc.append(np.arange(len(a)))
            total += len(a)
        A = np.concatenate(angs) if angs else np.zeros(0)
        R = np.concatenate(rads) if rads else np.zeros(0)
        B = np.concatenate(br).astype(np.int64) if br else np.zeros(0, np.int64)
        Lc = np.concatenate(loc).astype(np.int64) if loc else np.zeros(0, np.int64)
        T = len(A)
        ends = np.zeros(T, np.int64)  # index one past the last element of each element's branch
        for hd in heads:
            ends[hd["start"]: hd["start"] + hd["n"]] = hd["start"] + hd["n"]
        j = np.arange(T)[:, None] + 1 + np.arange(m)[None, :]
        ok = j < ends[:, None]
        jj = np.where(ok, j, 0)
        ca = np.where(ok, A[jj] if T else 0.0, 0.0)
        cr = np.where(ok, R[jj] if T else 0.0, 0.0)
        model = cls(m=int(m), k=int(k), h=float(h), angles=A, radii=R, branch=B, local=Lc,
                    cont_angles=ca, cont_radii=cr, cont_len=ok.sum(axis=1).astype(np.int64),
                    starts=np.asarray(starts, np.int64), heads=heads)
        # Each candidate's appended vertices in the tip's frame (tip at 0, heading +x):
        # at synthesis time they only need a rotation and a translation.
        th = np.cumsum(ca, axis=1)
        step = float(h) * ok
        model.local_points = np.stack([np.cumsum(np.cos(th) * step, axis=1),
                                       np.cumsum(np.sin(th) * step, axis=1)], axis=-1)
        return model

    @property
    def n_elements(self) -> int:
        return len(self.angles)

    def windows(self, L: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """All candidates for a history of length ``L``.

        Returns ``(t, WA, WR)``: the index ``t`` of the last element of each
        window and the ``(J, L)`` windows of angles and radii.

        Parameters
        ----------
        L : int
            History length (number of elements per window), >= 1.

        Returns
        -------
        t : (J,) int ndarray
            Index of the last element of each window (windows never straddle two
            branches).
        WA, WR : (J, L) ndarray
            The windows of turning angles (radians) and of thicknesses (pixels),
            oldest element first.
        """
        if L in self._windows:
            return self._windows[L]
        t = np.flatnonzero(self.local >= L - 1)
        off = np.arange(L - 1, -1, -1)
        idx = t[:, None] - off[None, :]
        out = (t, self.angles[idx], self.radii[idx])
        self._windows[L] = out
        return out

    def max_history(self) -> int:
        """Longest history for which candidates exist (<= k + 1; computed once, read at every step)."""
        out = self.__dict__.get("_max_history")
        if out is None:
            longest = int(self.local.max()) + 1 if self.n_elements else 0
            out = self.__dict__["_max_history"] = min(self.k + 1, longest)
        return out

    def quality(self, hist_angles, hist_radii, subset=None) -> tuple[np.ndarray, np.ndarray]:
        """Markov quality ``Q`` of every candidate for a history.

        Parameters
        ----------
        hist_angles, hist_radii : (L0,) array_like
            The growing branch's elements so far; the last
            ``min(L0, k + 1, max_history)`` are used.
        subset : int array_like, optional
            Positions in the list of all windows (:meth:`windows`) to score;
            None = all.

        Returns
        -------
        t : (J,) int ndarray
            Candidate windows (index of their last element).
        Q : (J,) ndarray
            ``dist(alpha) * dist(r)``.
        """
        ha, hr, t, WA, WR = self.history_windows(hist_angles, hist_radii, subset)
        q = markov_dist(WA, ha) * markov_dist(WR, hr)
        return t, q

    def history_windows(self, hist_angles, hist_radii, subset=None):
        """The used end of a history and the candidate windows it is compared with.

        Parameters
        ----------
        hist_angles, hist_radii : (L0,) array_like
            The growing branch's elements so far.
        subset : int array_like, optional
            Positions in the list of all windows (:meth:`windows`); None = all.

        Returns
        -------
        ha, hr : (L,) ndarray
            The last ``L = min(L0, max_history)`` angles and radii.
        t : (J,) int ndarray
            Candidate windows (index of their last element).
        WA, WR : (J, L) ndarray
            The windows' angles and radii.

        Raises
        ------
        ValueError
            If the history is empty.
        """
        ha = np.asarray(hist_angles, np.float64)
        hr = np.asarray(hist_radii, np.float64)
        L = min(len(ha), self.max_history())
        if L < 1:
            raise ValueError("the history is empty: a branch needs at least one element")
        t, WA, WR = self.windows(L)
        if subset is not None:
            t, WA, WR = t[subset], WA[subset], WR[subset]
        return ha[-L:], hr[-L:], t, WA, WR

    def continuation_points(self, t: np.ndarray, tip, theta: float) -> np.ndarray:
        """Vertices each candidate would append: ``(J, m, 2)``.

        Positions beyond a candidate's ``cont_len`` repeat its last vertex.

        Parameters
        ----------
        t : (J,) int ndarray
            Candidate windows (index of their last element), as from :meth:`quality`.
        tip : (2,) array_like
            Position (x, y) of the growing branch's tip (pixels).
        theta : float
            Heading of the tip (radians, the angle of its last segment from +x).

        Returns
        -------
        (J, m, 2) ndarray
            The ``m`` vertices (x, y) each candidate appends, ``h`` apart.
        """
        rel = self.local_points[t]
        c, s = np.cos(theta), np.sin(theta)
        tip = np.asarray(tip, np.float64)
        out = np.empty_like(rel)
        out[..., 0] = tip[0] + c * rel[..., 0] - s * rel[..., 1]
        out[..., 1] = tip[1] + s * rel[..., 0] + c * rel[..., 1]
        return out
