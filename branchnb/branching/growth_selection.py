"""Candidate selection of a Markov step (mixin of :class:`.growth._Grower`).

The paper's step draws one of the ``c`` best valid candidates with probability ~ score
(:meth:`_Selection._pick`, crossing tests compiled in :func:`._kernels.ranked_free`); the bend-size
and straight-run factors (:mod:`.straightness`) and the winding limit are one compiled pass
(:meth:`_Selection._step_factors`), a plain step one compiled call (:meth:`_Selection._plain_step`).
The random share of candidates (``_share``, read against ``growth.MAX_CANDIDATES``) stays in
:mod:`.growth`. Split from :mod:`branchnb.branching.growth` (issue 23, branching103).
"""

from __future__ import annotations

import numpy as np

from . import _kernels, _loop_kernels
from .model import _choice
from .scoring import _DIRECTION_BINS, score_candidates
from .straightness import BEND_CAP, RUN_CAP, RUN_GAIN


class _Selection:
    """Scoring factors and the draw of :class:`.growth._Grower` (a mixin: it uses the grower's state)."""

    def _cap(self) -> int:
        return 64 + 4 * self.p.c

    def _room_ahead(self, st, tip) -> bool:
        """Does any of all the candidates (their directions) lead on below the density stop?"""
        bm, p = self.model.bending, self.p
        L = min(len(st.elem_a), bm.max_history())
        dirs = self._live_dirs.get(L)
        if dirs is None:   # the directions of the windows that go on, per history length (found once)
            t = bm.windows(L)[0]
            t = t[bm.cont_len[t] > 0]
            dirs = self._live_dirs[L] = np.ascontiguousarray(self.model.local_dirs[t])
        if not len(dirs):
            return False
        # compiled, ending at the first free direction (the answer of binned_profile over all of them)
        length = 3.0 * p.m * p.h
        dens = self.density
        n_samples = int(min(max(np.ceil(length / (dens.rho / 2.0)), 8), 48))
        return bool(_kernels.free_direction(dens.grid, dens.cell, float(tip[0]), float(tip[1]), dirs,
                                            float(st.theta), True, length, n_samples, 0.02, _DIRECTION_BINS,
                                            float(p.stop_density)))

    def _pick(self, score: np.ndarray, tip, pts: np.ndarray, lens: np.ndarray) -> int | None:
        """Among the c best valid candidates, choose one with probability ~ score.

        Candidate ``j``'s polyline is ``[tip] + pts[j, :lens[j]]``; the crossing test
        runs compiled over the ranked candidates (:func:`._kernels.ranked_free`)."""
        st = self.store
        # ranked as np.argsort(-_rank_key(score), kind="stable") (ties by index), lazily
        chosen = _kernels.ranked_free(np.asarray(score, np.float64), np.asarray(tip, np.float64),
                                     np.ascontiguousarray(pts, np.float64), np.asarray(lens, np.int64),
                                     st._head, st._next, st._seg, st.p0, st.p1, st.n, st.cell,
                                     self._cap(), int(self.p.c), self.density is not None, 1e-9)
        return self._draw(score, chosen.tolist())

    def _draw(self, score, chosen) -> int | None:
        if not chosen:
            return None
        w = score[chosen]
        return chosen[_choice(self.rng, w / w.sum())]   # rng.choice(len(chosen), p=...), the same draw

    def _step_factors(self, st, t_arr: np.ndarray) -> tuple[np.ndarray | None, np.ndarray]:
        """``(fb, zero)`` of a step's candidates ``t_arr`` (:func:`._kernels.step_factors`): the bend-size
        factor times the straight-run factor (None when neither applies) and the candidates a branch
        may not take (they end it under ``branch_end = "length"``, or sweep past the winding limit)."""
        args, use_fb = self._factor_args(st)
        fb, zero = _kernels.step_factors(t_arr, *args)
        return (fb if use_fb else None), zero

    def _plain(self, st) -> bool:
        """Is branch ``st``'s next step a plain one (:func:`._loop_kernels.plain_step`): the default
        scorer, no guidance, drain, shore, frame factor (a root on a free frame), goal, mouth
        or meander hold?"""
        return (self.scorer is score_candidates and self.guidance is None and self.drain is None
                and self.shore is None and st.goal is None and st.mouth is None
                and not (self.frame and st.parent is None) and not self.keep_in and self.tropism is None
                and self.meander is None and self.radial_bearing is None)

    def _plain_step(self, st, tip, t: np.ndarray, L: int):
        """``(stopped, score, points, chosen)`` of a plain step over the candidate windows ``t``
        (:func:`._loop_kernels.plain_step`; the reference is the general path of :meth:`step`)."""
        fargs, use_fb = self._factor_args(st)
        return _loop_kernels.step_call(self.model, self.p, self.matcher, self.density, self.store, st, tip, t, L,
                                       fargs, use_fb, self._cap())

    def _factor_args(self, st) -> tuple[tuple, bool]:
        """The arguments of :func:`._kernels.step_factors` after the candidates, and whether its
        factor applies (the bend-size or the straight-run factor is on)."""
        bends, runs = self.bends, self.runs
        use_bend = self.bend_counts is not None
        n_bent = float(bends.counts.sum()) if use_bend else 0.0
        lo, hi = st.heads if st.heads is not None else (st.theta, st.theta)
        bm = self.model.bending
        if runs is not None:
            r = runs.run_length(st.elem_a[-(runs.max_run + 1):])
            if self._run_logs is None:
                self._run_logs = (np.log(runs.hazard), np.log1p(-runs.hazard), float(np.log(runs.q)),
                                  float(np.log1p(-runs.q)))
            lh, l1h, lq, l1q = self._run_logs
            # beyond the rule of .straightness: half of it against the overall bend rate, not
            # only against each candidate's own context (relative alone, the mean straight run
            # of a 1000 px drawn map was 0.74-0.92 x the example's and of 1000 px drawn cracks
            # 0.80-0.91 x with turns 1.8-2.0 x; blended 0.82-0.84 x and 0.88-1.02 x; issue 23);
            # a delta's channel turns toward the sea: there the drain decides first (square root)
            # where the example's runs are long (drawn maps, line art) a quarter against the candidate's
            # own context and three quarters against the overall rate (the geometric mean bent a 1000 px
            # drawn map's rivers in clusters, a bend one element after another: median straight run 4 px
            # against the example's 20, mean 0.73-0.78 x; now 0.86-0.94 x; issue 23, branching27)
            mode = (3 if self.run_weight == 1.0 else 0) if self.drain is None else 1
            state, tol, max_run = runs.state, runs.tol, runs.max_run
        else:
            r, lh, l1h, lq, l1q, mode, state, tol, max_run = 0, self._e1, self._e1, 0.0, 0.0, 2, self._ei, 0.0, 0
        args = (bm.cont_angles, bm.cont_len, use_bend and bends.wG > 0 and n_bent > 0,
                bends.p, bends.counts, self._bend_bins if use_bend else self._e2i, bends.wG * n_bent / bends.m,
                BEND_CAP, runs is not None, lh, l1h, lq, l1q, state, int(r), float(tol), int(max_run), mode,
                float(self.run_weight), RUN_GAIN, RUN_CAP, float(st.theta), float(lo), float(hi),
                float(self.wind_max), self.p.branch_end == "length")
        return args, use_bend or runs is not None
