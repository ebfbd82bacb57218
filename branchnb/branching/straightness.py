"""Bend-size matching: the synthesized branches bend as often as the example's (beyond the paper).

The paper's global histogram matching (:mod:`.histogram_matching`) bins the
turning angles in 16 equal bins over the example's min..max. On a drawn map
(straight polyline pieces with a corner every 10-30 px) or a delta, that
range is +-40 to +-90 degrees, so one bin holds every angle from -3 to +8
degrees: a straight step and a small bend look the same to it, and space
colonization, which favours candidates that turn away from other branches,
made the synthesized branches bend 1.0-1.8 x as often per length as the
example's (bends >= 6 degrees at 4 px).

:class:`BendHistogram` keeps a second histogram of the *size* of the turns,
``|alpha|``, in bins that resolve small angles (:data:`BEND_EDGES_DEG`), and
favours the candidates that bring it closer to the example's with the
paper's own rule, ``exp(g wG dB n_t / m)``, ``dB`` the improvement of
``(1/B) sum (p - q)^2``, at ``g = 8`` times the paper's weight
(:data:`BEND_GAIN`; colonization's ``1 / (D + eps)`` spans three orders of
magnitude and outweighs the paper's), within ``exp(+-1)`` (:data:`BEND_CAP`).
Bends per length of the synthesized branches over the example's (see the
final figures in the report of issue 23): drawn maps 256-512 px about
0.95-1.29 (before 0.86-1.26; 1.29 is a 256 px island seed whose coast
rule switches the nudge off), deltas 0.98-1.17 (1.02-1.84), river maps
1.00-1.08 (1.06-1.24), cracks and vessel trees about 1.0-1.2.

Examples
--------
>>> import numpy as np
>>> bh = BendHistogram(np.zeros(90).tolist() + [0.5] * 10, wG=50, m=4)
>>> bh.add([0.5, 0.5, 0.5, 0.5])          # so far only bends, the example has 10 %
>>> f = bh.factors(np.array([[4, 0, 0, 0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 4, 0, 0]]))
>>> bool(f[0] > 1.0), float(f[1])          # a straight candidate is favoured, more bends are not
(True, 1.0)
"""

from __future__ import annotations

import numpy as np

from .histogram_matching import HistogramMatcher

__all__ = ["BEND_EDGES_DEG", "BendHistogram", "StraightRuns"]

#: Bin edges of the turn sizes ``|alpha|`` (degrees): fine near 0, where a straight line
#: (0-1.5), the staircase of a traced line (1.5-3) and a visible bend (>= 6) differ.
BEND_EDGES_DEG = (0.0, 1.5, 3.0, 6.0, 10.0, 15.0, 25.0, 40.0, 70.0, 180.0001)

#: Weight of the bend-size histogram relative to the paper's ``wG``. Measured on drawn maps,
#: smooth river maps, deltas, cracks and vessel trees (256-512 px, 3 seeds each, uncapped),
#: bends per length over the example's: 1 x ``wG`` 0.95-1.40, 4 x 0.97-1.33, 8 x 0.95-1.25,
#: 16 x 0.96-1.25 but coverage gaps up to 1.35 x the example's (1.14 x at 8).
BEND_GAIN = 8.0

#: The factor stays within ``exp(+-BEND_CAP)`` (like the Markov quality's own range, 1-4): a
#: steady nudge at every step, never outweighing the rules that keep a delta's channels off the
#: image frame (``exp(-10)``) and pull them to the sea (at ``exp(+-4)`` a 192 px delta's channels
#: stopped 26 px short of it and a trunk ran along the frame; at ``exp(+-1)``, 6 seeds each:
#: bends per length deltas 0.98-1.17 x, maps 1.03-1.14 x, river maps 1.00-1.08 x).
BEND_CAP = 1.0


class BendHistogram:
    """Histogram of the example's turn sizes and running counts of the synthesized ones.

    Parameters
    ----------
    input_angles : array_like
        All turning angles alpha (radians) of the example, resampled at h.
    wG : float, default 50.0
        The paper's global histogram weight ``wG`` (0 = off); the factor uses
        :data:`BEND_GAIN` times it.
    m : int, default 4
        Elements appended per synthesis step.

    Examples
    --------
    >>> bh = BendHistogram([0.0, 0.0, 0.3], wG=50, m=4)
    >>> bh.p.round(2).tolist()
    [0.67, 0.0, 0.0, 0.0, 0.0, 0.33, 0.0, 0.0, 0.0]
    """

    def __init__(self, input_angles, *, wG: float = 50.0, m: int = 4):
        a = np.abs(np.asarray(input_angles, np.float64).ravel())
        self.edges = np.radians(np.asarray(BEND_EDGES_DEG))
        self.bins = len(self.edges) - 1
        self.wG, self.m = float(wG) * BEND_GAIN, int(m)
        counts = np.bincount(self.bin_angles(a), minlength=self.bins).astype(np.float64)
        self.p = counts / counts.sum() if counts.sum() > 0 else np.full(self.bins, 1.0 / self.bins)
        self.counts = np.zeros(self.bins)

    def bin_angles(self, a) -> np.ndarray:
        """Bin of each turn size ``|alpha|``.

        Parameters
        ----------
        a : array_like
            Turning angles alpha (radians; the sign is ignored).

        Returns
        -------
        int ndarray
            Bin index in ``0 .. bins - 1``, same shape as ``a``.
        """
        x = np.abs(np.asarray(a, np.float64))
        return np.minimum(np.maximum(np.searchsorted(self.edges, x, side="right") - 1, 0), self.bins - 1)

    def add(self, angles=()) -> None:
        """Count synthesized turning angles.

        Parameters
        ----------
        angles : array_like, default ()
            Turning angles alpha (radians) of the newly synthesized elements.
        """
        a = np.asarray(angles, np.float64).ravel()
        if a.size:
            self.counts += np.bincount(self.bin_angles(a), minlength=self.bins)

    def candidate_counts(self, angles: np.ndarray, lengths: np.ndarray) -> np.ndarray:
        """Bin counts of each candidate's appended turns.

        Parameters
        ----------
        angles : (J, m) ndarray
            The turning angles each candidate appends (radians).
        lengths : (J,) int ndarray
            How many of them are real (the rest is padding).

        Returns
        -------
        (J, bins) ndarray
            Counts per candidate.
        """
        a = np.asarray(angles, np.float64)
        J, M = a.shape
        ok = np.arange(M)[None, :] < np.asarray(lengths)[:, None]
        flat = (self.bin_angles(a) + self.bins * np.arange(J)[:, None])[ok]
        return np.bincount(flat, minlength=J * self.bins).reshape(J, self.bins).astype(np.float64)

    def factors(self, cand_counts: np.ndarray) -> np.ndarray:
        """``exp(g wG dB n_t / m)`` for every candidate (1 before anything is counted).

        Parameters
        ----------
        cand_counts : (J, bins) ndarray
            Bin counts of each candidate's appended turns.

        Returns
        -------
        (J,) ndarray
            The factor of each candidate (> 1 when it brings the turn sizes
            closer to the example's).
        """
        cc = np.asarray(cand_counts, np.float64)
        n = float(self.counts.sum())
        if self.wG == 0 or n == 0:
            return np.ones(len(cc))
        d = HistogramMatcher._improvement(self.p, self.counts, cc)
        return np.exp(np.clip(self.wG * d * n / self.m, -BEND_CAP, BEND_CAP))

    def factors_at(self, cand_counts: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """:meth:`factors` of the rows ``rows`` of ``cand_counts`` (compiled, no copy of the rows).

        Parameters
        ----------
        cand_counts : (T, bins) ndarray
            Bin counts of the turns of every candidate of the example.
        rows : (J,) int ndarray
            The candidates to score.

        Returns
        -------
        (J,) ndarray
            The factor of each candidate, as :meth:`factors` gives it.
        """
        from ._kernels import _improvements

        n = float(self.counts.sum())
        if self.wG == 0 or n == 0:
            return np.ones(len(rows))
        d = _improvements(np.asarray(self.p, np.float64), np.asarray(self.counts, np.float64),
                          np.asarray(cand_counts, np.float64), np.zeros(0), np.asarray(rows, np.int64))
        return np.exp(np.clip(self.wG * d * n / self.m, -BEND_CAP, BEND_CAP))


#: A turn of at least this size (degrees, at step h) ends a straight run (a visible bend, see
#: :data:`BEND_EDGES_DEG`; a traced straight line's staircase turns by 1.5-3 degrees).
RUN_TOL_DEG = 6.0

#: The run-length factor stays within ``exp(+-RUN_CAP)``. At ``exp(+-1.5)`` a 256 px delta's
#: branches bent 1.32 x as often per length as the example's in one seed of 6 (bends cluster at
#: a polyline's corners, and a bend favours the next); at ``exp(+-1)`` 0.96-1.16 x on deltas, coast
#: maps and cracks, straight runs (mean, turns < 6 degrees at 4 px) 0.91-1.47 x on drawn maps,
#: 1.04-1.21 x on a 512 px delta, 1.09-1.17 x on the lightning sample.
RUN_CAP = 1.0

#: Weight of the run-length log-likelihood ratio.
RUN_GAIN = 1.0

#: The run-length factor is used only on examples whose straight runs last this many elements
#: on average (:attr:`StraightRuns.mean_run`): drawn maps 8-14 (32-56 px at h = 4). Where runs are
#: short (the lightning sample 4.7, cracks 4.5, smooth river maps 4.8) it lengthened runs a little
#: but moved the angle histogram away from the example's (lightning, wG = 50: 0.00091 against
#: 0.00118 without matching, the paper's figure needs < 0.7 x).
RUN_MIN_MEAN = 6.0


class StraightRuns:
    """Where the example bends along a branch: a hazard over the length of the straight run so far.

    Beyond the paper. Its Markov chain remembers the last ``k + 1``
    elements and the histograms (:class:`BendHistogram`) count how many
    turns there are, not where they fall: candidates are switched every
    ``m`` elements and colonization favours turning ones, so bends were
    spread evenly and the straight runs of the output were 0.65-0.9 x the
    example's on drawn maps (straight polyline pieces 25-100 px long with
    a corner between them; issue 23). This keeps, from the example's
    branches resampled at ``h``, the *hazard* ``H(L)``: the share of the
    straight runs that have lasted ``L`` elements and bend at the next one
    (a turn of at least :data:`RUN_TOL_DEG`), smoothed toward the overall
    bend rate ``q``. A candidate that appends turns ``a_1 .. a_n`` to a
    tip whose straight run has lasted ``L`` elements gets its score times
    ``prod_i H(L_i) / q`` for a bend and ``(1 - H(L_i)) / (1 - q)`` for a
    straight step (``L_i`` updated along the candidate), to the power
    :data:`RUN_GAIN`, within ``exp(+-RUN_CAP)``: short runs continue
    straight, long runs bend, as in the example. With ``cand_runs`` the
    ratio is taken against the run each candidate followed in the input
    (a candidate copied from the same context gets 1). Synthesis uses it
    only on examples whose mean run is at least :data:`RUN_MIN_MEAN`
    elements and that do not drain (on deltas it halved the channels
    reaching the sea). Mean straight run output / example (turns < 6
    degrees at 4 px, seeds 0-5): drawn maps 512 px island 0.74-0.84 ->
    0.73-0.92, 1000 px coast 0.75-0.81 -> 0.86-0.98, 256 px bay
    0.77-0.99 -> 0.84-1.08.

    Parameters
    ----------
    angles : array_like
        Turning angles alpha (radians) of the example's elements, branch
        after branch (``BendingModel.angles``).
    branch : array_like of int
        The input branch of each element (``BendingModel.branch``).
    tol_deg : float, optional
        Smallest turn (degrees) that ends a straight run; default
        :data:`RUN_TOL_DEG`.
    max_run : int, default 48
        Runs of this many elements or longer share one hazard.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.tile(np.r_[np.zeros(9), 0.5], 20)           # a bend every 10th element
    >>> sr = StraightRuns(a, np.zeros(len(a), int))
    >>> f = sr.factors([2, 9], np.array([[0.0, 0.0], [0.5, 0.0]]), np.array([2, 2]))
    >>> bool(f[0] > 1.0 and f[1] > 1.0)                     # straight early, bend when due
    True
    """

    def __init__(self, angles, branch, *, tol_deg: float | None = None, max_run: int = 48):
        a = np.abs(np.asarray(angles, np.float64).ravel())
        br = np.asarray(branch).ravel()
        if len(br) != len(a):
            raise ValueError(f"branch has {len(br)} entries, angles {len(a)}")
        self.tol = float(np.radians(RUN_TOL_DEG if tol_deg is None else tol_deg))
        self.max_run = int(max_run)
        bent = a >= self.tol
        at_risk = np.zeros(self.max_run + 1)
        ends = np.zeros(self.max_run + 1)
        #: straight elements at the end of the input up to and including each element (a candidate
        #: ``t`` continues the input after element ``t``: its run so far in the input)
        self.state = np.zeros(len(a), np.int64)
        run, prev = 0, None
        for e, (b, is_bent) in enumerate(zip(br, bent)):
            if b != prev:
                run, prev = 0, b
            i = min(run, self.max_run)
            at_risk[i] += 1
            if is_bent:
                ends[i] += 1
                run = 0
            else:
                run += 1
            self.state[e] = run
        self.q = float(np.clip(bent.mean() if len(a) else 0.5, 0.02, 0.98))
        # mean length (elements) of the straight runs between two bends or a bend and a branch end
        runs = np.diff(np.r_[0, np.flatnonzero(self.state == 0), len(a)]) - 1
        runs = runs[runs > 0]
        #: Mean straight run of the example (elements; 0 without any).
        self.mean_run = float(runs.mean()) if len(runs) else 0.0
        prior = 4.0
        self.hazard = np.clip((ends + prior * self.q) / (at_risk + prior), 0.01, 0.99)

    def run_length(self, angles) -> int:
        """Straight elements at the end of ``angles`` (the current run of a branch).

        Parameters
        ----------
        angles : array_like
            A branch's turning angles so far (radians).

        Returns
        -------
        int
            How many of the last angles are below the tolerance.
        """
        a = np.abs(np.asarray(angles, np.float64).ravel())
        bent = np.flatnonzero(a >= self.tol)
        return int(len(a) - 1 - bent[-1]) if len(bent) else len(a)

    def factors(self, run, cand_angles, lengths, cand_runs=None, memory: int = 0) -> np.ndarray:
        """Score factor of every candidate given the current run.

        Parameters
        ----------
        run : int or array_like of int
            Straight elements so far at the tip (one value, or one per
            candidate).
        cand_angles : (J, M) array_like
            Turning angles each candidate appends (radians).
        lengths : (J,) array_like of int
            How many of them are real (the rest is padding).
        cand_runs : (J,) array_like of int, optional
            The run each candidate followed in the input (``state[t]``):
            the likelihood is then relative to that context (a candidate
            copied from the same run length as the tip's gets 1), so the
            Markov chain, which already sees the last ``k + 1`` elements, is
            only corrected where its memory ends. None = relative to
            bends at the overall rate ``q``.
        memory : int, default 0
            Steps whose run so far is at most this long are left out (the
            Markov chain's history of ``k + 1`` elements sees the whole run
            there).

        Returns
        -------
        (J,) ndarray
            ``exp(clip(RUN_GAIN * log-likelihood ratio, -RUN_CAP, RUN_CAP))``.
        """
        ca = np.abs(np.asarray(cand_angles, np.float64))
        J, M = ca.shape
        n = np.asarray(lengths)
        L = np.broadcast_to(np.asarray(run, np.int64), (J,)).copy()
        lh, l1h = np.log(self.hazard), np.log1p(-self.hazard)
        if cand_runs is None:
            Lb = None
            lq, l1q = np.log(self.q), np.log1p(-self.q)
        else:
            Lb = np.asarray(cand_runs, np.int64).copy()
        ll = np.zeros(J)
        for i in range(M):
            bent = ca[:, i] >= self.tol
            valid = (i < n) & (L > memory)
            j = np.minimum(L, self.max_run)
            if Lb is None:
                ll += np.where(valid, np.where(bent, lh[j] - lq, l1h[j] - l1q), 0.0)
            else:
                jb = np.minimum(Lb, self.max_run)
                ll += np.where(valid, np.where(bent, lh[j] - lh[jb], l1h[j] - l1h[jb]), 0.0)
                Lb = np.where(i < n, np.where(bent, 0, Lb + 1), Lb)
            L = np.where(i < n, np.where(bent, 0, L + 1), L)
        return np.exp(np.clip(RUN_GAIN * ll, -RUN_CAP, RUN_CAP))
