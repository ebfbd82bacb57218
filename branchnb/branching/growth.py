"""The growth loop of structure synthesis: roots, Markov steps, furcations, breadth first.

Every root starts with the head of an input branch and is grown step by
step (:meth:`_Grower.step`: all candidates scored by
:func:`.scoring.score_candidates`, one of the ``c`` best drawn); a finished
branch furcates (:meth:`_Grower.furcate`), its children start with the
parent's non-causal window (``start_child``, in :mod:`.branch_starts`) and
grow the same way, generation by generation; then the domain is filled
(:class:`.filling._Filling`). Split from :mod:`branchnb.branching.synthesis`; the length cap and
the winding limit are in :mod:`.stopping`.
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
    frame_density,
)
from .domains import MOUTH_SHARE, MOUTH_TURN, _Drain, _Shore, _shore_margin, runs_inland
from .empty_ground import _is_band, _painted_core, _strand_core
from .filling import _Filling
from .frame_band import (
    FRAME_BAND,
    FRAME_END,
    FRAME_EXIT,
    FRAME_HUG_SHARE,
    PARALLEL_BAND,
    PARALLEL_BAND_SHARE,
    _frame_ends,
    _frame_share,
    _frame_sides,
    band_keep,
    bearing_keep,
    entry_side,
    entry_turn_limit,
    parallel_keep,
)
from .guidance import Guidance
from .model import StructureModel, _choice
from .params import SynthesisParams
from .scoring import _DIRECTION_BINS, _continue_radii, score_candidates
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
from .straightness import BEND_CAP, RUN_CAP, RUN_GAIN, RUN_MIN_MEAN, BendHistogram, StraightRuns
from .tropism import _tropism_factor

# the stopping rules' names (split to .stopping) stay importable from here
__all__ = ["FILL_LENGTH_FACTOR", "GrowthProgress", "LENGTH_BOUND", "LENGTH_FACTOR", "LENGTH_FLOOR", "WIND_BOUNDS_DEG",
           "WIND_FACTOR", "example_length", "length_cap", "winding", "winding_limit"]

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



#: Quantile of the example's branches' (thickest radius / first radius) that bounds a synthesized branch's.
RADIUS_GROWTH_QUANTILE = 0.9


def _radius_growth(example) -> float:
    """How much thicker than at its start a branch may get: the example's branches'
    ``max(r) / max(r_0, r_1)`` at :data:`RADIUS_GROWTH_QUANTILE`, at least 1."""
    ratios = [float(np.max(b.thickness)) / max(float(np.max(b.thickness[:2])), 1e-9)
              for b in example.branches if len(b.thickness) > 1]
    return max(1.0, float(np.quantile(ratios, RADIUS_GROWTH_QUANTILE))) if ratios else np.inf


#: The density (coverage) stop waits until the output has at least this many branches, or as many as
#: the example has of at least :data:`MIN_BRANCH_SHARE` x its longest branch's length (:func:`_min_branches`).
MIN_BRANCHES = 3
MIN_BRANCH_SHARE = 0.1


def _min_branches(model: StructureModel) -> tuple[int, float]:
    """How many branches the output grows, each at least how long (pixels), before the density stop
    may end it.

    Beyond the paper (issue 23): on a small example (a 128 px river map: a 100 px trunk and
    tributaries of 17-62 px) the coverage of the example's domain is reached by a trunk and one
    child (the trunk ran on past the example's, to the far side of the frame), and the output was a
    line with one side branch where the example has a trunk with two or three. Small examples only
    (long side <= :data:`~.small_frames.SMALL_SIDE` px, else ``(0, 0.0)``): a larger example's output
    has far more branches when its coverage is reached, and its first fill round may still come with
    fewer than three (a 512 px crack's did: starting children before re-opening tips then gave 21
    branches instead of 29), so larger examples are left as they were. Spurs (shorter than
    :data:`MIN_BRANCH_SHARE` x the longest branch) are not counted, in the example or in the output.
    """
    from .small_frames import SMALL_SIDE

    shape = model.example.image_shape
    lengths = np.asarray([b.length for b in model.example.branches], np.float64)
    if not len(lengths) or shape is None or max(shape) > SMALL_SIDE:
        return 0, 0.0
    need = MIN_BRANCH_SHARE * float(lengths.max())
    return int(min(MIN_BRANCHES, int(np.sum(lengths >= need)))), need


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


#: Share of the log gap between the continued radius and the copied input radius closed per copied
#: element (:func:`_pull_radii`); 0 = the pure relative continuation.
RADIUS_PULL = 0.05
#: A copied piece passes on its taper in proportion to how alike its input radius and the tip's are,
#: to this power (:func:`~branchnb.branching.scoring._continue_radii` ``like``; beyond the paper,
#: issue 23). 0 = the input's relative change copied whole. Not in a delta (its channels keep their
#: width). Known cost: a child whose head starts at the extraction's blurred junction width tapers off
#: it more slowly; on roots only, children copied whole tapers and 5 of a crack mask's leaf children
#: stopped as bare heads. Off by default (branching54; 2 = branching52's rule): its two failures are mended
#: (:data:`TAPER_RESOLVED`; a fill child stopping short no longer rules out a whole hole,
#: ``filling.PART_GROWN``), but with it the partial comb mask's placement bound is missed on its test
#: seed (0.216 vs 0.2) and a 450-px comb's roots still thin to 0.8 px, pulled to their input root's
#: profile (a frame-entry root that starts on a 1-px tooth, ``ROOT_PROFILE_PULL``).
TAPER_LIKENESS = 0.0
#: Radii are alike below this (pixels) for :data:`TAPER_LIKENESS` (``_continue_radii`` ``resolved``):
#: a line up to ~1.6 px wide (a 1-px line measures 0.75 px) has no width the extraction resolves, its
#: radius differences are blur and light (a 1.6-px bolt measures 0.84 px in a bright cloud, 0.62 px in
#: the dark sky), so such lines keep the paper's whole tapers. Without it the bolt's cloud-lit radius
#: was kept along the output and its fragments were matched from the cloud (20 % of the fragment
#: pixels against 2 %): a glowing tube of cloud (``test_branching_image_unseen``). At 1.0 px the comb
#: and crack masks' 1-px side lines lost part of the rule's gain (radius-histogram L1 0.32 -> 0.38).
TAPER_RESOLVED = 0.8


def _pull_radii(cont: np.ndarray, copied: np.ndarray, pull: float | None = None) -> np.ndarray:
    """Continued radii drawn back toward the copied input radii (beyond the paper, issue 23).

    The relative continuation (:func:`~branchnb.branching.scoring._continue_radii`) multiplies the
    input's tapers step after step: a random walk with no memory of the example's widths, so a trunk
    that starts at the example's thickest head stays that thick along its whole length (NOAA
    lightning: length-weighted 90th-percentile radius 2.2-2.3 px against 1.29 in the example). Element
    ``k`` of a step moves the fraction ``1 - (1 - pull) ** (k + 1)`` of the log gap to the copied
    radius: the radius never jumps by more than ``pull`` of the gap, and over a few steps the
    branch's widths follow the copied pieces' (the example's distribution). ``pull`` = 0.05 (default
    :data:`RADIUS_PULL`): NOAA lightning at 512 px, 6 seeds, 90th percentile 0.73-2.30 -> 0.73-1.15 px
    (example 1.29), thick-end share no higher; 0.1 or a pull that only thins overshot (thick-end share
    + 0.07-0.14 on NOAA, retina far share up to 1.9 x). Not applied in a delta, whose channels keep the
    width they start at (:func:`_radius_keep`, ``_Starts._channel_radius``).

    Examples
    --------
    >>> _pull_radii(np.array([2.0, 2.0]), np.array([0.5, 0.5]), 0.5).round(2)
    array([1.  , 0.71])
    """
    a = RADIUS_PULL if pull is None else float(pull)
    if a <= 0 or len(cont) == 0:
        return cont
    w = 1.0 - (1.0 - a) ** np.arange(1, len(cont) + 1)
    return cont * (np.maximum(copied, 1e-9) / np.maximum(cont, 1e-9)) ** w


#: :data:`RADIUS_PULL` of a root toward its input root's radius at the same arc length
#: (:meth:`~branchnb.branching.branch_starts._Starts._root_profile`).
ROOT_PROFILE_PULL = 0.05
#: The same for a hub's child toward its generation's taper (:func:`.radial._taper_profile`): children
#: are short (tens of elements), and at 0.05 the pull lagged the taper by half their length.
CHILD_PROFILE_PULL = 0.5


#: An example that drains (a delta): quantile of its branches' (thinnest radius over their first 90 % /
#: first radius) below which a synthesized channel may not thin.
RADIUS_KEEP_QUANTILE = 0.5



def _radius_keep(example) -> float:
    """How much thinner than at its start a delta's channel may get (beyond the paper, issue 23).

    The example's branches' ``min(r) / max(r_0, r_1)`` over their first 90 % (their last vertices
    thin where the mask meets the sea) at :data:`RADIUS_KEEP_QUANTILE`, at most 1. The copied tapers
    multiply step after step (``_continue_radii``) and the cap on thickening (:func:`_radius_growth`)
    left only the thinning: every channel of a 512-1000 px delta fell to the example's thinnest radius
    (length-weighted median radius 0.13-0.78 x the example's; after 0.8-1.2 x).
    """
    ratios = []
    for b in example.branches:
        t = np.asarray(b.thickness, np.float64)
        if len(t) > 2:
            ratios.append(float(t[: max(2, int(0.9 * len(t)))].min()) / max(float(t[:2].max()), 1e-9))
    return min(1.0, float(np.quantile(ratios, RADIUS_KEEP_QUANTILE))) if ratios else 0.0


#: A band strand's candidate scores ``exp(-d / CORE_SCALE)``, ``d`` its mean distance (pixels) outside the
#: band the example's strands sweep (:func:`.empty_ground._strand_core`; beyond the paper, issue 23,
#: branching66), roots and children alike (branching70): 7 px out weighs like ``LEAVE_BAND``. At 2 px on
#: roots only, children ran out to the frame and into the eye of the band: 0.36-0.48 of the length of
#: interlaced bands (L, U, frame, ring, S, spiral, knot, border; 256-1024 px, 3 seeds) outside the swept
#: band. At 0.5 px the strands kinked to stay in (turn per 10 px 1.06-1.34 x the example's on U and S
#: bands, against 0.82-1.12 x at 1 px, for 0-0.09 less length outside); a hard wall (the core as the
#: growth domain) ended an L band's root after 20-40 px (length 0.28 x).
CORE_SCALE = 1.0


def _core(model: StructureModel, domain) -> tuple[np.ndarray, np.ndarray] | None:
    """``(core, distance outside it)`` of a band of one-pen strands (:func:`.empty_ground._strand_core`),
    once per model and domain; else None (any other example or domain).

    In the model's own domain the example's lines say where the band is; in a band domain of the user's
    (another mask, or another size) the core is its middle strip in the example's proportions
    (:func:`.empty_ground._painted_core`; beyond the paper, issue 23, branching70)."""
    if domain is None or model.domain is None or model.ground is None or not _is_band(domain) \
            or not _one_pen(model.example):
        return None
    from scipy import ndimage as ndi

    got = model.__dict__.get("_strand_core")
    if got is None or got[0] is not model.domain:
        core = _strand_core(model.example, model.domain)
        got = model.__dict__["_strand_core"] = (
            model.domain, None if core is None else (core, ndi.distance_transform_edt(~core)), {})
    if got[1] is None or (domain.shape == model.domain.shape and np.array_equal(domain, model.domain)):
        return got[1]
    key = (domain.shape, hash(np.packbits(domain).tobytes()))
    if key not in got[2]:
        core = _painted_core(model.domain, got[1][0], domain)
        got[2][key] = None if core is None else (core, ndi.distance_transform_edt(~core))
    return got[2][key]


class _Grower(_Starts, _Filling):
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

    def _share(self, n: int, cap: int | None = None) -> np.ndarray | None:
        """Positions of a random share of ``n`` candidates (None: score them all), at most ``cap``
        (default :data:`MAX_CANDIDATES`, read at each call)."""
        if cap is None:
            cap = MAX_CANDIDATES
        if n <= cap:
            return None
        s = -(-n // cap)
        return np.arange(int(self.rng.integers(s)), n, s)

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

    def _child_vertices(self, bi: int) -> list:
        """The parent vertices of branch ``bi``'s children, in the order they were started (an index
        kept up to date as branches are added, rebuilt when the list is replaced)."""
        if self._kids_of is None or self._kids_of[0] is not self.branches:
            self._kids_of = (self.branches, 0, {})
        lst, done, kids = self._kids_of
        for b in lst[done:]:
            if b.parent is not None:
                kids.setdefault(b.parent, []).append(b.parent_vertex)
        self._kids_of = (lst, len(lst), kids)
        return list(kids.get(bi, ()))

    def _step_factors(self, st, t_arr: np.ndarray) -> tuple[np.ndarray | None, np.ndarray]:
        """``(fb, zero)`` of a step's candidates ``t_arr`` (:func:`._kernels.step_factors`): the bend-size
        factor times the straight-run factor (None when neither applies) and the candidates a branch
        may not take (they end it under ``branch_end = "length"``, or sweep past the winding limit)."""
        args, use_fb = self._factor_args(st)
        fb, zero = _kernels.step_factors(t_arr, *args)
        return (fb if use_fb else None), zero

    def _plain(self, st) -> bool:
        """Is branch ``st``'s next step a plain one (:func:`._loop_kernels.plain_step`): the default
        scorer, no guidance, drain, shore, frame factor (a root on a free frame), goal or mouth?"""
        return (self.scorer is score_candidates and self.guidance is None and self.drain is None
                and self.shore is None and st.goal is None and st.mouth is None
                and not (self.frame and st.parent is None) and not self.keep_in and self.tropism is None)

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

    # -- growing ----------------------------------------------------------
    def step(self, bi: int, full: bool = False) -> bool:
        """One Markov step of branch ``bi``; False when the branch stops (``full``: score every candidate)."""
        st, p = self.branches[bi], self.p
        if st.stop:
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
            if self.drain is not None:
                score = score * self.drain.factor(
                    tip, pts, n_arr, start=st.points[0], fan=st.fan,
                    hold_from=None if st.fan is None else self.drain.hold_from(st.points, p.h))
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
                rad = cont if self.drain is not None else _pull_radii(cont, rad)
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

    def furcate(self, bi: int, extra: bool = False) -> list[int]:
        st, p = self.branches[bi], self.p
        if st.generation >= p.max_generations or not self.model.furcation.can_branch:
            return []
        if st.stop == "existing":
            return []
        if self.strands and st.generation > int(self.model.branch_generation.max(initial=0)):
            # a band's strands: no generation deeper than the example's + 1, even when the fill rounds
            # fill past the child quota (quota_off; with the roots in the band's core a 512 px vine grew
            # twigs 3 deep where the example has 1)
            return []
        pts = np.asarray(st.points)
        rad = np.asarray(st.radii)
        length = (len(pts) - 1) * p.h
        weights = None
        head = self._below_head(bi)
        # a band's strands (one-pen line art): d among the example's branches of the same generation, and the fill
        # rounds never take a branch past its generation's children per length (child_quota; issue 23)
        # a hub's branches too (radial): drawn among all, a dendrite twig took a primary's count and
        # its children twigs of their own (.radial._hub_view; issue 23)
        fm, gen = self.model.furcation, (st.generation if self.strands or self.radial else None)
        if extra:
            d = 1
            existing = self._child_vertices(bi)
            if gen is not None and not self.quota_off and len(existing) >= fm._child_quota(length, gen):
                return []
            weights = self._room(pts) if self._empty_dt is not None else None
            if head is not None:
                weights = head * (1.0 if weights is None else weights)
            if weights is not None and not weights.any():
                return []
        else:
            d = p.d if p.d >= 0 else fm.sample_d(length, self.rng, generation=gen)
            existing = ()
            if head is not None and head.any():
                weights = head.astype(np.float64)
        if self.radial:   # a hub's branches fork where the example's do along them (.radial._fork_weights)
            from .radial import _fork_weights

            fw = _fork_weights(self.model, st.generation, len(pts))
            if fw is not None:
                weights = fw if weights is None else weights * fw
        if self.frame_band > 0:   # no child starts in the frame's band, where it could only run along it
            clear = _frame_sides(pts, self.shape)[0] >= self.frame_band
            if not clear.all():
                weights = clear.astype(np.float64) if weights is None else weights * clear
        verts = self.model.furcation.choose(pts, rad, d, min_spacing=p.min_spacing, existing=existing,
                                            weights=weights)
        kids = []
        for v in verts:
            if self.global_stop():
                break
            c = self.start_child(bi, v)
            if c is not None:
                kids.append(c)
        return kids

    def run(self, starts) -> None:
        if getattr(starts, "hubs", None) and self.p.max_total_length <= 0 and self.p.max_coverage <= 0:
            # a hub's primaries: the example's length per hub, not its coverage (.radial._hub_budget)
            from .radial import _generation_caps, _hub_budget

            self.max_total = _hub_budget(self.model, len(starts.hubs), starts.scale, len(starts))
            self.coverage_target, self.radial = 1.0, True
            self._gen_cap = _generation_caps(self.model, len(starts))
        queue = []
        for (x, y, th) in starts:
            if self.global_stop():
                break
            r = self.start_root(x, y, th)
            if r is not None:
                if self.radial:   # a hub's primary heads out along its spoke first (.radial._spoke_goal)
                    from .radial import SPOKE_KAPPA, _spoke_goal

                    self.branches[r].goal = _spoke_goal(starts.hubs, x, y)
                    self.branches[r].goal_kappa = SPOKE_KAPPA
                queue.append(r)
        self._drain(queue)
        self._fill_rounds()
        if not self.stop_reason:
            self.stop_reason = "no branch can grow" if queue else "no root could start"

    def _fill_rounds(self) -> None:
        # Everything stopped before the domain is as dense as the example:
        # furcate the grown branches once more (highest furcation probability
        # away from their children), round after round.
        # (Not in guided synthesis: the user's path, not the domain, says where to grow.)
        for _ in range(self.p.fill_rounds if self.guidance is None else 0):
            if self.global_stop() or self.density is None or not self.branches:
                break
            before = len(self.branches)
            self._update_room()
            rooms = self._max_rooms()
            # tips that ended at their drawn length with free space ahead grow on; in an output with
            # fewer branches than the example (_min_branches) after new children, not before (a small
            # example's trunk ran on across the frame and took the length the children needed)
            few = len(self.branches) < self.min_branches
            if not few:
                self._drain(self._reopen_tips())
            for bi in np.argsort(rooms, kind="stable")[::-1]:
                if self.global_stop() or rooms[bi] <= 0:
                    break
                self._drain(self.furcate(int(bi), extra=True))
            if few and not self.global_stop():
                self._drain(self._reopen_tips())
            self._empty_dt = None
            if len(self.branches) == before:
                break
            self.fill_rounds += 1

    def structure(self) -> Structure:
        out = []
        for st in self.branches:
            pts = np.asarray(st.points, np.float64)
            out.append(Branch(pts, np.asarray(st.radii, np.float64), st.parent, st.parent_vertex))
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
