"""Learning of structure synthesis: everything :func:`fit_model` learns from an example.

The example is resampled at step ``h`` and learnt: the bending model's
element sequences, the global histograms, the furcation SVM, the roots
(:mod:`.roots`), the coverage target and whether it drains (a delta). The
candidates' histogram counts and growth directions are precomputed here
for the vectorised scorer (:mod:`.scoring`). Split from :mod:`branchnb.branching.synthesis`.
"""

from __future__ import annotations

import dataclasses
import math
import threading
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..core.params import check_params
from ..core.structure import Branch, Structure  # noqa: F401  (Branch: the doctest)
from ..core.validate import Real, checked
from .bending import BendingModel
from .colonization import auto_rho, coverage_fraction, growth_directions
from .domains import _drains, _frame, _ground
from .furcation import FurcationModel
from .histogram_matching import HistogramMatcher
from .params import SynthesisParams
from .roots import RootModel, fit_roots
from .strands import join_strands
from .tropism import _fit_tropism

__all__ = ["StructureModel", "fit_model"]

_FIT_FIELDS = ("h", "m", "k", "bins", "svm_C")

#: Smallest step (pixels) :func:`fit_model` falls to on an example too short for ``h``.
MIN_STEP = 1.0



# --------------------------------------------------------------------------
# Learning
# --------------------------------------------------------------------------
def _choice(rng, p: np.ndarray) -> int:
    """``rng.choice(len(p), p=p)`` without its checks of ``p`` (the same draw from the same stream:
    the cdf of ``p`` searched at one uniform number); it ran once per branch start."""
    cdf = np.cumsum(p)
    cdf /= cdf[-1]
    return int(cdf.searchsorted(rng.random(), side="right"))


@dataclass
class StructureModel:
    """Everything learnt from an example structure.

    Parameters
    ----------
    source : Structure
        The example as given.
    example : Structure
        The example resampled at ``params.h`` (what the models see).
    bending : BendingModel
        The Markov chain over (turning angle, thickness) elements.
    furcation : FurcationModel
        Where branches split and how children start.
    params : SynthesisParams
        The parameters the model was fitted with.
    cum_a, cum_r : (T + 1, B) ndarray
        Cumulative one-hot histogram bins of the elements' angles and
        thicknesses (row ``i`` counts elements ``0 .. i-1``).
    cand_counts_a, cand_counts_r : (T, B) ndarray
        Bin counts of the followers each candidate would append.
    cand_sq_a, cand_sq_r : (T,) ndarray
        Their squared row norms (for the histogram factor).
    local_dirs : (T, 2) ndarray
        Growth direction (PCA) of each candidate in the frame of a tip
        heading along +x.
    head_start : (n_branches,) int ndarray
        Index of each input branch's first element.
    edges_a, edges_r : (B + 1,) ndarray
        Bin edges of the angle (radians) and thickness (pixels)
        histograms.
    first_a, first_r : (n_branches, m) ndarray
        The first ``m`` elements of every input branch (a new branch's
        first piece), 0-padded.
    first_len : (n_branches,) int ndarray
        How many of them exist.
    max_branch_length : float, default 0.0
        Length of the longest input branch (pixels).
    rho : float, default 8.0
        The automatic density radius (pixels; used when ``params.rho == 0``).
    r_min : float, default 0.5
        Smallest thickness of the input (pixels).
    branch_generation, branch_length, branch_r0 : (n_branches,) ndarray
        Generation, length (pixels) and starting thickness (mean of the
        first 3 radii) of every input branch, for drawing branch lengths.
    domain : (H, W) bool ndarray, optional
        Where the example's branches may grow; None = its whole frame.
    roots : RootModel, optional
        Where and how the example's roots start.
    coverage : float, default 0.0
        Fraction of the example's domain within ``rho`` of a branch.
    drains : bool, default False
        The example drains: its roots start far inland and its branches
        end at the region outside the domain (a delta).
    ground : (H, W) bool ndarray, optional
        The parts outside ``domain`` no example branch comes near (a line
        mask's empty part, see :func:`~branchnb.branching.example_domain`):
        no branch grows there, but it is no coast or sea to fill or reach;
        coverage, holes, roots and the length cap count :attr:`region`.
    tropism : (16,) ndarray, optional
        Bearing weights of an example that enters from one side of a free
        frame and runs away from it (a root system hanging from the top),
        beyond the paper: see :mod:`.tropism`. None otherwise.
    requested_h : float, optional
        The step asked for when the example was too short for it and
        :func:`fit_model` fitted at the finer ``params.h`` (a small
        example, beyond the paper); None otherwise.
    """

    source: Structure
    example: Structure
    bending: BendingModel
    furcation: FurcationModel
    params: SynthesisParams
    cum_a: np.ndarray = field(repr=False, default=None)
    cum_r: np.ndarray = field(repr=False, default=None)
    cand_counts_a: np.ndarray = field(repr=False, default=None)
    cand_counts_r: np.ndarray = field(repr=False, default=None)
    cand_sq_a: np.ndarray = field(repr=False, default=None)
    cand_sq_r: np.ndarray = field(repr=False, default=None)
    local_dirs: np.ndarray = field(repr=False, default=None)
    head_start: np.ndarray = field(repr=False, default=None)
    edges_a: np.ndarray = field(repr=False, default=None)
    edges_r: np.ndarray = field(repr=False, default=None)
    first_a: np.ndarray = field(repr=False, default=None)
    first_r: np.ndarray = field(repr=False, default=None)
    first_len: np.ndarray = field(repr=False, default=None)
    max_branch_length: float = 0.0
    rho: float = 8.0  #: the automatic density radius (used when params.rho == 0)
    r_min: float = 0.5
    branch_generation: np.ndarray = field(repr=False, default=None)
    branch_length: np.ndarray = field(repr=False, default=None)
    branch_r0: np.ndarray = field(repr=False, default=None)
    #: Where the example's branches may grow ((H, W) bool), None = its whole frame.
    domain: np.ndarray | None = field(repr=False, default=None)
    roots: RootModel | None = None
    #: Fraction of the example's domain within ``rho`` of a branch.
    coverage: float = 0.0
    #: The example drains: its roots start far inland and its branches end at the region outside the
    #: domain (a delta's trunk enters from inland, its distributaries reach the sea).
    drains: bool = False
    #: The parts of the frame outside ``domain`` the example's branches keep away from ((H, W) bool, or
    #: None): a line mask's empty ground (:func:`~branchnb.branching.example_domain`), no coast or sea.
    ground: np.ndarray | None = field(repr=False, default=None)
    _coverage_rho: float = field(repr=False, default=-1.0)
    #: Bearing weights of a structure entering from one side of a free frame (:mod:`.tropism`), or None.
    tropism: np.ndarray | None = field(repr=False, default=None)
    #: The step asked for when the example was too short for it and :func:`fit_model` took a finer
    #: one (``params.h``); None when the step asked for was used.
    requested_h: float | None = None

    @property
    def region(self) -> np.ndarray | None:
        """The domain with its :attr:`ground`: what coverage, holes, roots and the length cap count
        (None = the whole frame). Branches grow in :attr:`domain` only."""
        if self.ground is None or self.domain is None:
            return self.domain
        c = self.__dict__.get("_region")
        if c is None or c[0] is not self.domain or c[1] is not self.ground:
            reg = self.domain | self.ground
            c = self.__dict__["_region"] = (self.domain, self.ground, None if reg.all() else reg)
        return c[2]

    def sample_length(self, generation: int, r_start: float, rng, bandwidth: float = 0.5) -> float:
        """Target length of a new branch: the length of an input branch of the same
        generation (the deepest available if deeper), chosen with weights
        ``exp(-log(r / r_b)^2 / (2 bw^2))`` on the starting thickness.

        Parameters
        ----------
        generation : int
            Generation of the new branch (0 = root).
        r_start : float
            Its starting thickness (pixels).
        rng : numpy.random.Generator
            Random generator.
        bandwidth : float, default 0.5
            Width ``bw`` of the thickness kernel in log units.

        Returns
        -------
        float
            The target length (pixels).
        """
        cache = self.__dict__.setdefault("_length_pools", {})
        if generation not in cache:   # the input branches of each generation, found once
            g = min(int(generation), int(self.branch_generation.max()))
            idx = np.flatnonzero(self.branch_generation == g)
            if len(idx) == 0:
                idx = np.arange(len(self.branch_length))
            cache[generation] = (idx, np.maximum(self.branch_r0[idx], 1e-6))
        idx, r = cache[generation]
        w = np.exp(-np.log(max(r_start, 1e-6) / r) ** 2 / (2 * bandwidth ** 2)) + 1e-12
        j = idx[_choice(rng, w / w.sum())]
        return float(self.branch_length[j])

    def matcher(self, wG: float) -> HistogramMatcher:
        """A fresh global histogram matcher over the example's angles and thicknesses.

        Parameters
        ----------
        wG : float
            Global histogram weight ``wG`` (0 switches matching off).

        Returns
        -------
        HistogramMatcher
            With the model's ``bins`` and ``m`` and no synthesized counts yet.
        """
        # the example's angles and thicknesses are measured once (30 ms on a retina: a slider's
        # re-synthesis started with them before its first partial skeleton)
        # keyed on the example like stopping.example_length, so a model given another example
        # measures that one
        key = (id(self.example), len(self.example.branches))
        cached = self.__dict__.get("_matcher_data")
        if cached is None or cached[0] != key:
            cached = (key, self.example.angles(), self.example.thicknesses())
            self.__dict__["_matcher_data"] = cached
        return HistogramMatcher(cached[1], cached[2], bins=self.params.bins, wG=wG, m=self.params.m)

    @checked(rho=Real(0, 1e4, low_open=True))
    def coverage_at(self, rho: float) -> float:
        """Fraction of the example's domain within ``rho`` of one of its branches.

        Parameters
        ----------
        rho : float
            Distance (pixels), > 0.

        Returns
        -------
        float
            The covered fraction in [0, 1] (cached for the last ``rho``).
        """
        if abs(rho - self._coverage_rho) > 1e-9:
            self.coverage = coverage_fraction(self.example, _frame(self.source), rho, self.region)
            self._coverage_rho = float(rho)
        return self.coverage

    def compatible(self, params: SynthesisParams) -> bool:
        """Whether ``params`` could have been fitted by this model (same ``h``, ``m``, ``k``, ``bins``, ``svm_C``).

        Parameters
        ----------
        params : SynthesisParams
            The parameters a synthesis wants to use.

        Returns
        -------
        bool
            True when the fitted fields agree (the other fields only steer
            synthesis).
        """
        return all(getattr(params, f) == getattr(self.params, f) for f in _FIT_FIELDS) or (
            self.requested_h is not None and params.h == self.requested_h
            and all(getattr(params, f) == getattr(self.params, f) for f in _FIT_FIELDS if f != "h"))


def _check_example(example) -> Structure:
    if isinstance(example, StructureModel):
        return example.source
    if not isinstance(example, Structure):
        raise TypeError(f"example must be a Structure or StructureModel, got {type(example).__name__}")
    if not example.branches:
        raise ValueError("example structure is empty: annotate or extract at least one branch")
    example.check_inside(name="example")
    return example


@checked()
def fit_model(example: Structure, params: SynthesisParams | None = None, *,
              domain=None, progress=None) -> StructureModel:
    """Learn the bending, histogram and furcation models from an example.

    Parameters
    ----------
    example : Structure
        The source structure (any vertex spacing; it is resampled at ``h``).
    params : SynthesisParams, optional
        Uses ``h``, ``m``, ``k``, ``bins``, ``svm_C``.
    domain : (H, W) bool array_like, optional
        Where the example's branches live (e.g. the land of a river map,
        see :func:`~branchnb.branching.example_domain`); default
        the whole ``image_shape``. The root model (:mod:`.roots`) learns
        where roots start relative to its boundary, and the coverage
        target is measured inside it.
    progress : callable, optional
        ``progress(fraction, text)`` before each fitting step (bending,
        furcations, roots and coverage); an exception raised there stops
        the fit (apps use it for "cancel"). The furcation SVM, about half of
        the time, is one call into liblinear: while it runs, ``progress`` is
        asked again every 0.1 s, so a cancel stops the fit within ~0.2 s
        (the SVM then finishes unseen in its worker thread).

    Raises
    ------
    ValueError
        Empty example, or no branch with at least ``k + m + 2`` vertices
        after resampling even at the finest step :data:`MIN_STEP` (a full
        history of ``k + 1`` elements plus a continuation is needed
        somewhere). An example too short for ``h`` but not for
        :data:`MIN_STEP` is fitted at a finer step, with a ``UserWarning``
        (beyond the paper; :attr:`StructureModel.requested_h` keeps ``h``).
        Shorter branches are kept: they feed the histograms, the furcation
        model and the candidates for
        short histories (the start of a branch).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 6, 200)
    >>> ex = Structure([Branch(np.c_[20 * t, 10 * np.sin(t)] + 50, 2.0)])
    >>> fit_model(ex).bending.n_elements
    31
    """
    example = _check_example(example)
    p = check_params(params if params is not None else SynthesisParams())
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable or None, got {type(progress).__name__}")
    report = progress if progress is not None else (lambda fraction, text: None)
    dom = None
    if domain is not None:
        from ..core.image import as_mask

        if example.image_shape is None:
            raise ValueError("domain needs example.image_shape (the frame the domain covers)")
        dom = as_mask(domain, shape=example.image_shape, name="domain")
        if not dom.any():
            raise ValueError("domain is empty: no pixel where branches may grow")
    # beyond the paper: a strand cut where another passes over it (line art) is one branch again
    joined = join_strands(example)
    ex = joined.resampled(p.h)
    longest = max(len(b.points) for b in ex.branches)
    need = p.k + p.m + 2
    requested_h = None
    if longest < need:
        h = _small_example_step(joined, need)
        if h < MIN_STEP or h >= p.h:
            raise ValueError(
                f"every branch of example is shorter than k + m: the longest has {longest} vertices at "
                f"step h = {p.h}, need k + m + 2 = {need}. Lower k or m, lower h, or annotate longer branches")
        warnings.warn(
            f"the example's longest branch ({max(b.length for b in joined.branches):.0f} px) is too short for "
            f"k + m = {p.k + p.m} steps of h = {p.h} px: fitted at step h = {h:.2f} px (a small example)",
            UserWarning, stacklevel=3)
        requested_h, p = p.h, dataclasses.replace(p, h=h)
        ex = joined.resampled(p.h)
    report(0.0, "bending model")
    bending = BendingModel.fit(ex, p.m, p.k, p.h)
    report(0.1, "furcation model (SVM)")
    furc = _fit_furcations(ex, p, report if progress is not None else None)
    report(0.8, "histograms, roots and coverage")
    ex_angles, ex_radii = ex.angles(), ex.thicknesses()
    hm = HistogramMatcher(ex_angles, ex_radii, bins=p.bins, wG=p.wG, m=p.m)
    T, B = bending.n_elements, p.bins
    oa = np.zeros((T + 1, B))
    orr = np.zeros((T + 1, B))
    if T:
        oa[1:][np.arange(T), hm.bin_angles(bending.angles)] = 1
        orr[1:][np.arange(T), hm.bin_radii(bending.radii)] = 1
    cum_a, cum_r = np.cumsum(oa, axis=0), np.cumsum(orr, axis=0)
    nb = len(ex.branches)
    fa, fr = np.zeros((nb, p.m)), np.zeros((nb, p.m))
    fl = np.zeros(nb, np.int64)
    for i, hd in enumerate(bending.heads):
        n = min(p.m, hd["n"])
        s = hd["start"]
        fa[i, :n] = bending.angles[s:s + n]
        fr[i, :n] = bending.radii[s:s + n]
        fl[i] = n
    tt = np.arange(T)
    nn = bending.cont_len
    cca = cum_a[tt + 1 + nn] - cum_a[tt + 1] if T else np.zeros((0, B))
    ccr = cum_r[tt + 1 + nn] - cum_r[tt + 1] if T else np.zeros((0, B))
    ldirs = growth_directions(np.zeros(2), bending.local_points, nn) if T else np.zeros((0, 2))
    rho = auto_rho(ex, p.h)
    frame = _frame(example)
    ground = _ground(ex, dom)
    # the ground the example keeps away from is no coast: everything but growth reads the frame there
    reg = dom if ground is None else (None if (dom | ground).all() else dom | ground)
    cover = coverage_fraction(ex, frame, p.rho if p.rho > 0 else rho, reg)
    roots = fit_roots(ex, reg, shape=frame)
    drains = _drains(ex, reg)
    # a structure hanging from one side of a free frame keeps its global direction (.tropism)
    trop = _fit_tropism(ex, roots.sides) if reg is None or bool(np.all(reg)) else None
    report(1.0, "fitted")
    model = StructureModel(source=example, example=ex, bending=bending, furcation=furc, params=p,
                          cum_a=cum_a, cum_r=cum_r, cand_counts_a=cca, cand_counts_r=ccr,
                          cand_sq_a=np.einsum("ij,ij->i", cca, cca),
                          cand_sq_r=np.einsum("ij,ij->i", ccr, ccr),
                          local_dirs=ldirs,
                          head_start=np.array([hd["start"] for hd in bending.heads], np.int64),
                          edges_a=hm.edges_a, edges_r=hm.edges_r,
                          first_a=fa, first_r=fr, first_len=fl,
                          max_branch_length=max(b.length for b in ex.branches),
                          r_min=float(ex_radii.min()),
                          rho=rho, domain=dom, coverage=cover, _coverage_rho=p.rho if p.rho > 0 else rho,
                          roots=roots, drains=drains, ground=ground, tropism=trop, requested_h=requested_h,
                          branch_generation=np.array([ex.generation(i) for i in range(nb)]),
                          branch_length=np.array([b.length for b in ex.branches]),
                          branch_r0=np.array([np.mean(b.thickness[:3]) for b in ex.branches]))
    if getattr(example, "hubs", None):   # a hub's spokes are its primaries (.radial._hub_view)
        from .radial import _hub_view

        _hub_view(model, example.hubs)
    # the matcher's example measures, taken once here (see StructureModel.matcher)
    model.__dict__["_matcher_data"] = ((id(ex), len(ex.branches)), ex_angles, ex_radii)
    return model


def _small_example_step(example: Structure, need: int) -> float:
    """The step at which the example's longest branch has ``need + 1`` vertices.

    Beyond the paper: its step ``h`` = 4 px suits examples of a few hundred
    pixels; a small image (an icon, a thumbnail, a 128 px map) may have no
    branch of ``(k + m + 1) h`` pixels. Rather than refuse it, the models are
    fitted at the finer step that gives the longest branch one full history
    plus a continuation and a spare vertex (the bending model then learns the
    same number of steps over the shorter branch, as if the example had been
    drawn larger).
    """
    return max(b.length for b in example.branches) / need


#: Seconds between progress calls while the furcation SVM runs (see :func:`_fit_furcations`).
SVM_POLL = 0.1


def _fit_furcations(ex: Structure, p: SynthesisParams, report=None) -> FurcationModel:
    """``FurcationModel.fit`` of the example; with ``report``, in a worker thread polled by it.

    A 1000 px cracked mud's SVM takes 2-5 s in one C call that no callback
    can enter, so an app's "cancel" had to wait for it. liblinear releases the
    GIL, so a worker thread fits while this thread calls ``report`` every
    :data:`SVM_POLL` s; an exception from ``report`` (the app's cancel) is
    raised at once and the abandoned fit's result is dropped.
    """
    if report is None:
        return FurcationModel.fit(ex, p.k, p.svm_C)
    box: dict = {}

    def work():
        try:
            box["model"] = FurcationModel.fit(ex, p.k, p.svm_C)
        except BaseException as exc:  # re-raised in the caller's thread
            box["error"] = exc

    worker = threading.Thread(target=work, name="branchnb-furcation-svm", daemon=True)
    start = time.monotonic()
    worker.start()
    while True:
        worker.join(SVM_POLL)
        if not worker.is_alive():
            break
        # a fraction that keeps growing toward the next step's 0.8 however long the fit takes
        report(0.1 + 0.7 * (1.0 - math.exp(-(time.monotonic() - start) / 3.0)), "furcation model (SVM)")
    if "error" in box:
        raise box["error"]
    return box["model"]
