"""The frame, band and core rules of a Markov step (mixin of :class:`.growth._Grower`).

Which of a step's new points a branch may keep near the frame (:mod:`.frame_band`), the roots'
frame-ahead factor (:func:`.colonization.frame_density`) and a band strand's core factor
(:data:`.growth_bounds.CORE_SCALE`), all beyond the paper (issue 23). Split from
:mod:`branchnb.branching.growth` (issue 23, branching103).
"""

from __future__ import annotations

import numpy as np

from . import _kernels
from .colonization import frame_density
from .frame_band import PARALLEL_BAND, PARALLEL_BAND_SHARE, _frame_sides, band_keep, parallel_keep
from .growth_bounds import CORE_SCALE


class _FrameRules:
    """Frame and band tests of :class:`.growth._Grower` (a mixin: it uses the grower's state)."""

    def _inside(self, pts: np.ndarray) -> np.ndarray:
        h, w = self.shape
        dom = self.domain
        return _kernels.inside(np.ascontiguousarray(pts, np.float64), h, w,
                               self._e_dom if dom is None else dom, dom is not None)

    def _off_frame(self, bi: int, st, tip, new_pts: np.ndarray) -> np.ndarray:
        """Which of a step's new points ``new_pts`` branch ``bi`` may keep under the frame band rule
        (:data:`.frame_band.FRAME_BAND`, :meth:`_band_ok`); a child that started out of the band has left it."""
        off = bi in self._left_band or (st.parent is not None and len(st.points) > 1
                                        and self._frame_dist(st.points[0]) >= self.frame_band)
        ok, off = self._band_ok(tip, new_pts, off)
        if off:
            self._left_band.add(bi)
        return ok

    def _along_frame(self, bi: int, st, tip, new_pts: np.ndarray) -> np.ndarray:
        """Which of a step's new points ``new_pts`` branch ``bi`` may keep before it has run along a side of
        the frame for long (:func:`.frame_band.parallel_keep`; the side it starts near not counted)."""
        d0, s0 = _frame_sides(st.points[0], self.shape)
        skip = int(s0[0]) if d0[0] < max(PARALLEL_BAND, PARALLEL_BAND_SHARE * min(self.shape[:2])) else -1
        ok, self._par_run[bi] = parallel_keep(tip, new_pts, self._par_run.get(bi, 0.0), self.shape, skip)
        return ok

    def _band_ok(self, tip, new_pts: np.ndarray, off: bool) -> tuple[np.ndarray, bool]:
        """:func:`.frame_band.band_keep` of points ``new_pts`` after ``tip`` in this grower's frame."""
        return band_keep(tip, new_pts, off, self.shape, self.frame_band, self.frame_exit,
                         None if self.drain is None else self.drain.depth)

    def _frame_dist(self, pt) -> float:
        return float(_frame_sides(pt, self.shape)[0][0])

    def _core_factor(self, pts: np.ndarray, live: np.ndarray) -> np.ndarray | float:
        """``exp(-d / CORE_SCALE)`` of candidates (points ``pts`` (N, K, 2), ``live`` (N, K) the real ones),
        ``d`` the mean distance (pixels) of their points outside a band's core
        (:func:`.empty_ground._strand_core`): 1 inside it, and a strand that is out heads back in."""
        if self.core is None or not len(pts):
            return 1.0
        h, w = self.shape
        q = np.rint(pts.reshape(-1, 2)).astype(np.int64)
        d = self.core[1][np.clip(q[:, 1], 0, h - 1), np.clip(q[:, 0], 0, w - 1)].reshape(pts.shape[:2])
        k = min(d.shape[1], live.shape[1])
        lv = live[:, :k]
        mean = (d[:, :k] * lv).sum(1) / np.maximum(lv.sum(1), 1)
        return np.exp(-mean / CORE_SCALE)

    def _frame_factor(self, tip, dirs: np.ndarray, D_c: np.ndarray) -> np.ndarray:
        """Score factor ``(D_c + eps) / (max(D_c, D_frame) + eps)`` of a root's candidates (issue 23).

        Beyond the paper: the frame ahead counts as density
        (:func:`~.colonization.frame_density`), so a root started near a
        side or a corner turns into the image instead of walking out
        through the nearest side after a fifth of the example's trunk length
        (a lightning rooted top right: every seed's tree then filled only the right
        half). Roots only: on children it made them run along the frame.
        """
        p = self.p
        Df = frame_density(self.shape, tip, dirs, 3.0 * p.m * p.h, self.rho)
        return (D_c + p.eps) / (np.maximum(D_c, Df) + p.eps)

