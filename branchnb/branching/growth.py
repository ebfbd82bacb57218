"""The growth loop of structure synthesis: roots, Markov steps, furcations, breadth first.

Every root starts with the head of an input branch and is grown step by
step (:meth:`_Grower.step`: all candidates scored by
:func:`.scoring.score_candidates`, one of the ``c`` best drawn); a finished
branch furcates (``furcate``, in :mod:`.generations`), its children start with the
parent's non-causal window (``start_child``, in :mod:`.branch_starts`) and
grow the same way, generation by generation; then the domain is filled
(:class:`.filling._Filling`). Split from :mod:`branchnb.branching.synthesis`; the length cap and
the winding limit are in :mod:`.stopping`; by paper step (issue 23, branching103) the radius and
branch-count bounds are in :mod:`.growth_bounds`, the frame and band rules of a step in
:mod:`.growth_frame`, the candidate factors and draw in :mod:`.growth_selection` and the
generations (roots, furcations, fill rounds) in :mod:`.generations`; every moved name is
re-exported here.
The inner loops of a step and of a branch start (scores, density profiles,
crossing tests) run compiled (:mod:`branchnb.branching._kernels`); a plain step
(no delta, coast, hole or guidance factor) and the bookkeeping of new segments
are one compiled call each (:mod:`branchnb.branching._loop_kernels`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..core.structure import Branch, Structure
from . import _kernels, _loop_kernels
from .branch_starts import LEAVE_BAND, _BranchState, _Starts
from .child_angles import _one_pen
from .colonization import (
    DensityMap,
    SegmentStore,
)
from .domains import MOUTH_SHARE, MOUTH_TURN, _Drain, _Shore, _shore_margin, runs_inland
from .empty_ground import _is_band
from .filling import _Filling
from .frame_band import (
    FRAME_BAND,
    FRAME_END,
    FRAME_EXIT,
    FRAME_HUG_SHARE,
    _frame_ends,
    _frame_share,
    bearing_keep,
    entry_side,
    entry_turn_limit,
)
from .generations import _Generations
from .growth_bounds import (
    CHILD_PROFILE_PULL,
    CORE_SCALE,
    FORK_AREA_EXPONENT,
    FORK_KEEP,
    MIN_BRANCH_SHARE,
    MIN_BRANCHES,
    RADIUS_GROWTH_QUANTILE,
    RADIUS_KEEP_QUANTILE,
    RADIUS_PULL,
    ROOT_PROFILE_PULL,
    TAPER_LIKENESS,
    TAPER_RESOLVED,
    _core,
    _min_branches,
    _pull_radii,
    _radius_growth,
    _radius_keep,
    _thin_below_forks,
)
from .growth_frame import _FrameRules
from .growth_pieces import _grid_pieces
from .growth_selection import _Selection
from .guidance import Guidance
from .meander_hold import example_meander, meander_factor
from .model import StructureModel
from .params import SynthesisParams
from .radial_bearing import _radial_factor
from .scoring import _continue_radii, score_candidates
from .stopping import (
    FILL_LENGTH_FACTOR,
    LENGTH_BOUND,
    LENGTH_FACTOR,
    LENGTH_FLOOR,
    WIND_BOUNDS_DEG,
    WIND_FACTOR,
    example_length,
    length_cap,
    winding,
    winding_limit,
)
from .straightness import RUN_MIN_MEAN, BendHistogram, StraightRuns
from .tropism import _tropism_factor

# the stopping rules' names (split to .stopping) and the bounds' (split to .growth_bounds) stay importable
# from here; step() reads RADIUS_PULL, TAPER_LIKENESS and TAPER_RESOLVED from this module, _share
# MAX_CANDIDATES and _example_bounds winding_limit (so patching growth.NAME still takes effect)
__all__ = ["CHILD_PROFILE_PULL", "CORE_SCALE", "FILL_LENGTH_FACTOR", "FORK_AREA_EXPONENT", "FORK_KEEP",
           "GrowthProgress", "LENGTH_BOUND", "LENGTH_FACTOR", "LENGTH_FLOOR", "MAX_CANDIDATES", "MIN_BRANCHES",
           "MIN_BRANCH_SHARE", "RADIUS_GROWTH_QUANTILE", "RADIUS_KEEP_QUANTILE", "RADIUS_PULL", "ROOT_PROFILE_PULL",
           "TAPER_LIKENESS", "TAPER_RESOLVED", "WIND_BOUNDS_DEG", "WIND_FACTOR", "example_length", "length_cap",
           "winding", "winding_limit"]

#: Beyond the paper, for speed: a Markov step scores at most about this many candidate windows
#: (and a new branch this many input heads), a random share of all of them (every ``s``-th
#: from a random offset, so each candidate is equally likely). A 1000 px crack example has
#: 15.5 k windows and 3.8 k heads: scoring all of them took 50-70 s CPU per seed; smaller
#: examples are scored whole, unchanged (issue 23).
MAX_CANDIDATES = 1024

#: Power of the straight-run factor (:class:`~branchnb.branching.straightness.StraightRuns`) on
#: examples whose mean run is below :data:`~branchnb.branching.straightness.RUN_MIN_MEAN` (beyond
#: the paper). Off there (0), straight runs (512 px, 3 seeds) were 0.73-0.78 x the example's on the
#: Czech map, 0.84-0.91 x on the retina, 0.87-0.88 x on the lightning; at full power 1.06-1.26 x and
#: cracked mud 1.30-1.40 x; at 0.2: Czech 0.91-0.94, retina 0.90-0.94, lightning 0.96-1.00, mud
#: 1.11-1.15 (0.95-0.96 off), with turning angles and histogram distances unchanged (issue 23).
SHORT_RUN_WEIGHT = 0.2


@dataclass
class GrowthProgress:
    """A look at a structure while it grows: what ``synthesize_structure(progress=...)`` receives.

    Parameters
    ----------
    fraction : float
        Estimated progress in [0, 1]: the larger of the total length
        over the length cap (:func:`length_cap`) and the coverage over its target (below
        1 while growing; exactly 1 in the last report).
    steps : int
        Markov steps taken so far in this attempt.
    attempt : int
        Growth attempt (1, 2, ...): an attempt whose root walked out of
        the domain at once is grown again from scratch (see
        :data:`~branchnb.branching.synthesis.MAX_ROOT_ATTEMPTS`), so a later report may show fewer
        branches than an earlier one.
    n_branches : int
        Branches grown so far.
    total_length : float
        Their total length (pixels).
    coverage : float or None
        Fraction of the domain within ``rho`` of a branch (None without
        space colonization).
    done : bool
        True in the one report after synthesis has finished.
    """

    fraction: float
    steps: int
    attempt: int
    n_branches: int
    total_length: float
    coverage: float | None
    done: bool = False
    _grower: object = field(default=None, repr=False)

    def structure(self) -> Structure:
        """The branches grown so far (a copy: growth goes on without changing it)."""
        return self._grower.structure()


def _example_bounds(model: StructureModel) -> tuple[float, float, float]:
    """``(thickest radius, _radius_growth, winding_limit)`` of the model's example, computed once per
    model (a 1000 px crack example has 2.9 k branches: 0.2 s per growth attempt)."""
    key = (id(model.example), len(model.example.branches), winding_limit, _radius_growth)   # (patchable)
    cached = model.__dict__.get("_example_bounds")
    if cached is None or cached[0] != key:
        radii = model.example.thicknesses()
        cached = (key, (float(radii.max()) if radii.size else np.inf, _radius_growth(model.example),
                        winding_limit(model.example)))
        model.__dict__["_example_bounds"] = cached
    return cached[1]


def _example_meander(model: StructureModel, window: float) -> tuple[float, float] | None:
    """:func:`.meander_hold.example_meander` of the model's example, computed once per model."""
    key = (id(model.example), len(model.example.branches), window)
    cached = model.__dict__.get("_example_meander")
    if cached is None or cached[0] != key:
        cached = (key, example_meander(model.example, window))
        model.__dict__["_example_meander"] = cached
    return cached[1]


class _Grower(_FrameRules, _Selection, _Generations, _Starts, _Filling):
    def __init__(self, model: StructureModel, params: SynthesisParams, rng, shape,
                 guidance: Guidance | None, scorer=None, domain: np.ndarray | None = None,
                 region: np.ndarray | None = None):
        self.model, self.p, self.rng = model, params, rng
        # branches grow in ``domain``; the rest reads ``region``, the domain with the ground the example
        # keeps away from (StructureModel.ground: a line mask's empty part is no coast)
        self.region = region = domain if region is None else (None if region.all() else region)
        scorer = scorer or score_candidates
        self.shape = (int(shape[0]), int(shape[1]))
        self.guidance = guidance
        self.drain = _Drain(region) if guidance is None and model.drains and region is not None \
            and not region.all() else None
        if self.drain is not None and model.domain is not None:
            self.drain.set_axis(model.example, model.domain)
        margin = _shore_margin(model) if guidance is None and region is not None \
            and not region.all() and self.drain is None else 0.0
        self.shore = _Shore(region, margin, inland=runs_inland(model)) if margin > 0 else None
        # a meandering example's swings, longer than the Markov window, held by a sine (.meander_hold)
        self.meander = _example_meander(model, params.m * params.h) if guidance is None and self.drain is None \
            else None
        self.scorer = scorer
        self.matcher = model.matcher(params.wG)
        # beyond the paper: the sizes of the turns follow the example's too (see .straightness)
        bm = model.bending
        self.bends = BendHistogram(bm.angles, wG=params.wG, m=params.m)
        self.bend_counts = self.bends.candidate_counts(bm.cont_angles, bm.cont_len) if params.wG > 0 else None
        self._bend_bins = _kernels.count_bins(self.bend_counts) if self.bend_counts is not None else None
        # and where the turns fall: straight runs as long as the example's (see .straightness)
        self.runs = StraightRuns(bm.angles, bm.branch) if params.wG > 0 else None
        # only where the example's runs are long (drawn maps, deltas). On deltas it was once left out
        # (it halved the channels reaching the sea at 192 px before the drain rules); without it their
        # straight runs were 0.54-0.60 x the example's (512 px, issue 23)
        # where runs are short (lightning, cracks, retina, the Czech map) at the power SHORT_RUN_WEIGHT
        self.run_weight = 1.0 if self.runs is None or self.runs.mean_run >= RUN_MIN_MEAN else SHORT_RUN_WEIGHT
        if self.run_weight <= 0:
            self.runs = None
        self.rho = params.rho if params.rho > 0 else model.rho
        self.domain = domain
        # a line mask's domain with ground round it (.empty_ground._line_domain): its edge is no coast,
        # a branch turns along it (LEAVE_BAND)
        self.keep_in = guidance is None and domain is not None and model.ground is not None \
            and _is_band(domain)
        # and drawn with about one pen (an ornament, not a river mask in a band): its children follow the
        # example's per generation, length and angle (.child_angles, FurcationModel._child_quota)
        self.strands = self.keep_in and _one_pen(model.example)
        # strands keep to the band the example's sweep, in the example's own domain (.empty_ground._strand_core)
        self.core = _core(model, domain) if self.strands else None
        self.quota_off = False   # _Filling._more_strands found no room for a strand: fill as the paper
        self._e_dom = np.zeros((1, 1), bool)
        # a root reads the frame ahead as density (a free frame only: a map's domain has its own rules)
        self.frame = params.colonization and guidance is None and (region is None or bool(region.all()))
        self.tropism = model.tropism if self.frame else None   # hanging from one side (.tropism)
        # coverage = fraction of the domain within rho of a branch (D > exp(-1))
        self.density = DensityMap(self.shape, self.rho, domain=region, level=float(np.exp(-1.0))) \
            if params.colonization else None
        self.coverage_target = params.max_coverage if params.max_coverage > 0 else \
            min(model.coverage_at(self.rho), 1.0)
        # a domain of separate pieces (islands) is covered piece by piece (.growth_pieces)
        self.pieces = _grid_pieces(region, self.density) if guidance is None else None
        # the density stop waits for as many branches as the example has, up to MIN_BRANCHES (_min_branches)
        self.min_branches, self._min_branch_len = _min_branches(model) if params.max_coverage <= 0 else (0, 0.0)
        self.store = SegmentStore(shape=self.shape)
        self.branches: list[_BranchState] = []
        self.total_length = 0.0
        self.max_total = length_cap(model, params, self.shape, region)
        self.steps = 0
        self.n_candidates = 0
        self.stop_reason = ""
        self.max_branch_len = params.max_branch_factor * model.max_branch_length
        if self.drain is not None:   # a channel from far inland may need more than the example's longest
            self.max_branch_len = max(self.max_branch_len, 2.0 * float(np.hypot(*self.shape)))
        self.r_max, self.r_grow, self.wind_max = _example_bounds(model)
        self.r_keep = _radius_keep(model.example) if self.drain is not None else 0.0
        self.fill_rounds = 0
        # a branch that left the frame's band does not come back to run along the frame (.frame_band);
        # in an example that drains its channels also end at the sea, wherever it meets the frame: the
        # coast is one more side they may head out by (_band_ok)
        self.frame_band = FRAME_BAND if _frame_share(model.example, FRAME_BAND) <= FRAME_HUG_SHARE else 0.0
        # and where no line of the example ends at its frame, none heads out of it either
        # (per side: a river network leaving through the bottom of its example leaves only through the bottom)
        self.frame_exit = np.where(_frame_ends(model.example, FRAME_END), FRAME_EXIT, np.inf)
        self._left_band: set = set()
        self._par_run: dict = {}   # per branch, the length run along a side of the frame (_along_frame)
        # roots entering from the frame keep their bearing within the example's roots' turns (.frame_band)
        self.turn_limit = entry_turn_limit(model.example) if self.frame_band > 0 and self.drain is None \
            else float("inf")
        self.radial = False   # roots are hub primaries (set by run)
        self.radial_bearing: np.ndarray | None = None   # radial: outward bearing weights (.radial_bearing)
        self.hub_array: np.ndarray | None = None   # radial: the hubs (x, y, r) the primaries leave
        self._gen_cap: dict = {}   # radial: children per generation at most (.radial._generation_caps)
        self._empty_dt: np.ndarray | None = None
        self.attempt = 1
        self.progress = None  # progress(GrowthProgress) after every Markov step
        self._child_pool: tuple[np.ndarray, np.ndarray] | None = None
        self._run_logs: tuple | None = None
        self._all_dirs: np.ndarray | None = None
        self._kids_of: tuple | None = None
        self._live_dirs: dict = {}
        self._e1, self._e2, self._ei = np.zeros(1), np.zeros((1, 1)), np.zeros(1, np.int64)
        self._e2i = np.zeros((1, 1), np.int16)
        self._head: float | None = None
        #: a delta's channels that left its trunk below the head so far, (left, right) of it
        self._fan_count = (0, 0)

    def report(self, done: bool = False) -> None:
        if self.progress is None:
            return
        cov = self.density.coverage() if self.density is not None else None
        frac = self.total_length / max(self.max_total, 1e-9)
        if cov is not None and self.coverage_target < 1:
            frac = max(frac, cov / max(self.coverage_target, 1e-9))
        frac = 1.0 if done else min(frac, 0.99)
        self.progress(GrowthProgress(fraction=float(frac), steps=self.steps, attempt=self.attempt,
                                     n_branches=len(self.branches), total_length=self.total_length,
                                     coverage=cov, done=done, _grower=self))

    # -- bookkeeping ------------------------------------------------------
    def _register(self, polyline: np.ndarray, angles=(), radii=()) -> None:
        poly = np.ascontiguousarray(polyline, np.float64)
        length = _loop_kernels.register_polyline(self.store, self.density, self.matcher, self.bends, poly,
                                                 angles, radii)
        if length is not None:   # compiled, the same numbers (the numpy code below stays the reference)
            self.total_length += length
            return
        if len(poly) > 1:
            self.store.add_polyline(poly)
            if self.density is not None:
                self.density.add_segments(poly[:-1], poly[1:])
            self.total_length += float(np.hypot(*np.diff(poly, axis=0).T).sum())
        self.matcher.add(angles, radii)
        self.bends.add(angles)

    def add_existing(self, structure: Structure) -> None:
        for b in structure.branches:
            self._register(b.points, b.angles(), b.thickness)

    def global_stop(self) -> bool:
        if self.stop_reason:
            return True
        if self.total_length >= self.max_total - 1e-6:  # tolerance: summation order
            self.stop_reason = "total length"
        elif self.density is not None and self.coverage_target < 1 and \
                self.density.coverage() >= self.coverage_target and self._enough_branches():
            self.stop_reason = "density (coverage)"
        return bool(self.stop_reason)

    def _enough_branches(self) -> bool:
        """Whether :attr:`min_branches` branches have grown (a Markov step at least) to the example's
        spur length (:func:`_min_branches`); once true, true (branches only grow)."""
        if self.min_branches <= 0:
            return True
        if len(self.branches) < self.min_branches:
            return False
        # a head never grown is dropped at the end (filling._drop_unborn): a child counts once it took a
        # Markov step
        h, need = self.p.h, self._min_branch_len
        grown = sum(not st.unborn and (st.parent is None or bool(st.src)) and (len(st.points) - 1) * h >= need
                    for st in self.branches)
        if grown >= self.min_branches:
            self.min_branches = 0
        return self.min_branches <= 0

    # -- selection --------------------------------------------------------
    def _share(self, n: int, cap: int | None = None) -> np.ndarray | None:
        """Positions of a random share of ``n`` candidates (None: score them all), at most ``cap``
        (default :data:`MAX_CANDIDATES`, read at each call)."""
        if cap is None:
            cap = MAX_CANDIDATES
        if n <= cap:
            return None
        s = -(-n // cap)
        return np.arange(int(self.rng.integers(s)), n, s)


    # -- growing ----------------------------------------------------------
    def step(self, bi: int, full: bool = False) -> bool:
        """One Markov step of branch ``bi``; False when the branch stops (``full``: score every candidate)."""
        st, p = self.branches[bi], self.p
        if st.stop:
            return False
        if self.pieces is not None and self.coverage_target < 1:
            k = self.pieces.at(st.points[-1])
            if k and self.pieces.full(self.coverage_target)[k]:
                st.stop = "density"
                return False
        if not st.elem_a:
            st.stop = "no history"
            return False
        tip = np.asarray(st.points[-1])
        if not full:   # a retry with every candidate is the same step
            self.steps += 1
        bm = self.model.bending
        L = min(len(st.elem_a), bm.max_history())
        t_all = bm.windows(L)[0]
        sub = None if full else self._share(len(t_all))
        heads = None
        if self._plain(st):   # the common case in one compiled call (the same numbers as below)
            t_arr = t_all if sub is None else t_all[sub]
            n_arr = bm.cont_len[t_arr]
            self.n_candidates += len(t_arr)
            stopped, score, pts, chosen = self._plain_step(st, tip, t_arr, L)
            if stopped:
                if sub is not None and self._room_ahead(st, tip):   # the share missed the way out
                    return self.step(bi, full=True)
                st.stop = "density"
                return False
            j = self._draw(score, chosen.tolist())
        else:
            cs = self.scorer(self.model, st.elem_a, st.elem_r, tip, st.theta, params=p,
                             matcher=self.matcher, density=self.density, guidance=self.guidance,
                             **({} if sub is None else {"subset": sub}))
            pts, n_arr, t_arr = cs.points, cs.n_new, cs.t
            self.n_candidates += len(t_arr)

            score = cs.score
            if self.frame and st.parent is None:
                live = n_arr > 0
                if live.any():
                    end = pts[np.arange(len(n_arr)), np.maximum(n_arr, 1) - 1] - tip
                    dirs = end / np.maximum(np.hypot(end[:, 0], end[:, 1]), 1e-9)[:, None]
                    score = np.where(live, score * self._frame_factor(tip, dirs, cs.D_c), score)
            if self.tropism is not None:
                score = score * _tropism_factor(self.tropism, tip, pts, n_arr)
            if self.radial_bearing is not None:
                score = score * _radial_factor(self.radial_bearing, self.hub_array, tip, pts, n_arr)
            if self.drain is not None:
                score = score * self.drain.factor(
                    tip, pts, n_arr, start=st.points[0], fan=st.fan,
                    hold_from=None if st.fan is None else self.drain.hold_from(st.points, p.h))
            if self.meander is not None and len(t_arr):
                s_now = (len(st.points) - 1) * p.h
                if st.meander is None:   # from the heading it starts with, a crossing of the sine
                    om, lam = self.meander
                    side = np.pi * int(self.rng.integers(2))
                    st.meander = (st.theta, om, lam, -2.0 * np.pi * s_now / lam + side)
                score = score * meander_factor(st.meander, st.theta, s_now, p.h, bm.cont_angles[t_arr], n_arr)
            if st.goal is not None:
                score = score * self._goal_factor(st, tip, pts, n_arr)
            # the bend-size factor (see .straightness), the straight-run factor (below) and the winding
            # limit in one compiled pass (_kernels.step_factors)
            fb, zero = self._step_factors(st, t_arr)
            if self.shore is not None:
                fs = self.shore.factor(tip, pts, n_arr)
                score = score * fs * self.shore.along_factor(tip, pts, n_arr)
                if fb is not None:   # near the coast the shore decides alone
                    fb = np.where(fs < 1.0, 1.0, fb)
            if fb is not None:
                score = score * fb
            if self.keep_in and len(pts):
                inside = self._inside(pts.reshape(-1, 2)).reshape(pts.shape[:2])
                live = np.arange(pts.shape[1])[None, :] < n_arr[:, None]
                leave = (live & ~inside).any(1)
                score = np.where(leave, score * LEAVE_BAND, score)
                # a band's strands, children too, keep to the band its example's strands sweep
                score = score * self._core_factor(pts, live)
            # beyond the paper: no spirals. A candidate that would take the branch's heading range past the
            # winding limit is forbidden; the branch stops when nothing else is left (issue 23)
            score = np.where(zero, 0.0, score)
            heads = None
            if st.mouth is not None:
                if (len(st.points) - 1) * p.h < MOUTH_SHARE * min(st.target, self.max_branch_len):
                    heads = st.theta + np.cumsum(bm.cont_angles[t_arr], axis=1)
                    span = np.maximum(heads.max(1), st.mouth[1]) - np.minimum(heads.min(1), st.mouth[0])
                    score = np.where(span > MOUTH_TURN, score * 1e-9, score)
                else:
                    st.mouth = None
            if self.density is not None:
                free = (~cs.crossing) & (n_arr > 0)
                if not free.any() or cs.D_c[free].min() >= p.stop_density:
                    if sub is not None and self._room_ahead(st, tip):   # the share missed the way out
                        return self.step(bi, full=True)
                    st.stop = "density"
                    return False
            j = self._pick(score, tip, pts, np.maximum(n_arr, 0))
        if j is None:
            if sub is not None:
                return self.step(bi, full=True)
            st.stop = "blocked"
            return False
        t, n = int(t_arr[j]), int(n_arr[j])
        if n:
            th_j = st.theta + np.cumsum(bm.cont_angles[t, :n])
            lo, hi = st.heads if st.heads is not None else (st.theta, st.theta)
            st.heads = (min(lo, float(th_j.min())), max(hi, float(th_j.max())))
        if heads is not None and n:
            st.mouth = (min(st.mouth[0], float(heads[j, :n].min())), max(st.mouth[1], float(heads[j, :n].max())))
        new_pts = pts[j, :n]
        ang = bm.cont_angles[t, :n]
        rad = bm.cont_radii[t, :n]
        if p.thickness_blend and n:
            cont = _continue_radii(rad, st.radii[-1], bm.radii[t], self.model.r_min, self.r_max,
                                   0.0 if self.drain is not None else TAPER_LIKENESS, TAPER_RESOLVED)
            # a delta's channels keep the width they started at (_channel_radius, _radius_keep): no pull
            if st.profile is not None:   # a root: toward its input root's radius there (_root_profile)
                at = np.interp((len(st.points) - 1 + np.arange(1, n + 1)) * p.h, *st.profile)
                # (a hub's child: toward its generation's taper, .radial._taper_profile)
                rad = _pull_radii(cont, at, ROOT_PROFILE_PULL if st.parent is None else CHILD_PROFILE_PULL)
            else:
                # RADIUS_PULL passed from here: the name tests and users patch is this module's
                rad = cont if self.drain is not None else _pull_radii(cont, rad, RADIUS_PULL)
            # beyond the paper: the taper's ratios multiply step after step, a random walk that ended
            # 12-22 % of a delta's branches (example 7-11 %) > 2 x thicker than they start (issue 23)
            rad = np.minimum(rad, self.r_grow * max(float(st.radii[0]), float(st.radii[1])))
            if self.r_keep > 0:   # and a delta's channels keep their width (see _radius_keep)
                rad = np.maximum(rad, self.r_keep * max(float(st.radii[0]), float(st.radii[1])))
        ok = self._inside(new_pts)
        if self.frame_band > 0 and len(new_pts):
            ok &= self._off_frame(bi, st, tip, new_pts)
            if self.drain is None:   # a delta's channels end at the sea, which parallel_keep does not know
                ok &= self._along_frame(bi, st, tip, new_pts)
                if st.parent is None and np.isfinite(self.turn_limit) and len(st.points) > 1:
                    side = entry_side(st.points[0], float(st.radii[0]), self.shape)
                    kept = bearing_keep(st.points, new_pts, side, self.turn_limit, self.shape)
                    st.bearing_cut = st.bearing_cut or not kept.all()
                    ok &= kept
        if not ok.all():
            cut = int(np.argmin(ok))
            new_pts, ang, rad = new_pts[:cut], ang[:cut], rad[:cut]
            st.stop = "left the domain"
        if len(new_pts):
            self._register(np.vstack([tip, new_pts]), ang, rad)
            if st.parent is not None:
                self._child_count(rad)
            st.src.extend(range(t + 1, t + 1 + len(new_pts)))
            st.points.extend(new_pts)
            st.radii.extend(rad.tolist())
            st.elem_a.extend(ang.tolist())
            st.elem_r.extend(rad.tolist())
            st.theta += float(ang.sum())
        if st.stop:
            return False
        if n < p.m and p.branch_end == "markov":
            st.stop = "end of input branch"
            return False
        length = (len(st.points) - 1) * p.h
        if length >= st.target - 1e-9:
            st.stop = "branch length"
            return False
        if length >= self.max_branch_len:
            st.stop = "max branch length"
            return False
        return True

    def grow(self, bi: int, max_steps: int | None = None) -> None:
        """Markov steps of branch ``bi`` until it stops (or ``max_steps``).

        Beyond the paper, in an example that drains (a delta, :class:`.domains._Drain`) a
        branch, once started, runs on to the sea (or until blocked) past the global stops
        (coverage, total length): cut there it ended in the middle of the land, where
        the example's distributaries all reach the sea.
        """
        k = 0
        finish = self.drain is not None and max_steps is None
        while max_steps is None or k < max_steps:
            if self.global_stop() and not finish:
                return
            if not self.step(bi):
                return
            k += 1
            self.report()

    def structure(self) -> Structure:
        radii = [np.asarray(st.radii, np.float64) for st in self.branches]
        if self.drain is not None:   # a delta's channels narrow below their forks (_thin_below_forks)
            radii = _thin_below_forks(radii, [st.parent for st in self.branches],
                                      [st.parent_vertex for st in self.branches],
                                      [st.fork_ratio for st in self.branches])
        out = []
        for st, r in zip(self.branches, radii):
            out.append(Branch(np.asarray(st.points, np.float64), r, st.parent, st.parent_vertex))
        return Structure(out, image_shape=self.shape)

    def sources(self) -> list[np.ndarray]:
        out = []
        for st in self.branches:
            src = np.asarray(st.src, np.int64)
            out.append(np.r_[np.full(len(st.points) - len(src), -1, np.int64), src])
        return out

    def diagnostics(self, t0: float) -> dict:
        stops: dict[str, int] = {}
        for st in self.branches:
            stops[st.stop or "not finished"] = stops.get(st.stop or "not finished", 0) + 1
        return {
            "time_s": time.perf_counter() - t0,
            "steps": self.steps,
            "candidates_per_step": self.n_candidates / max(self.steps, 1),
            "stop_reason": self.stop_reason,
            "branch_stops": stops,
            "n_branches": len(self.branches),
            "n_vertices": int(sum(len(st.points) for st in self.branches)),
            "total_length": self.total_length,
            "coverage": self.density.coverage() if self.density is not None else None,
            "furcation_probability": self.model.furcation.probability_method,
            "rho": self.rho,
            "coverage_target": self.coverage_target,
            "max_total_length": self.max_total,
            "fill_rounds": self.fill_rounds,
        }
