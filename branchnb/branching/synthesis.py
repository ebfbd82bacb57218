"""Structure synthesis: grow a new branching structure like an example.

Putting the paper's models together (see the modules of the same names):

1. the example is resampled at step ``h`` and learnt: the bending model's
   element sequences, the global histograms, the furcation SVM;
2. every root starts with the head of an input root branch and is grown
   step by step: all candidate sub-sequences are scored at once
   (``Q`` of the bending model, times the histogram factor, divided by
   the density ``D_c + eps`` of space colonization and by the guidance
   ``G_c + eps``), crossing candidates get ``Q = 0``, and one of the ``c``
   best is chosen with probability proportional to its score; its ``m``
   following elements are appended. Beyond the paper, the sizes of the
   turns are matched to the example's too (:mod:`.straightness`: the
   paper's 16 angle bins cannot tell a straight step from a small bend, and
   colonization favours turning candidates, so branches bent up to 1.8 x as
   often per length as the example's), and a river leaving a coast may not
   curl back over the first ``MOUTH_SHARE`` of its length (a hook at its
   mouth);
3. a finished branch receives ``d`` furcations at the vertices of highest
   SVM probability; each child's first segment is chosen by the parent's
   non-causal window, then the child is grown the same way (breadth
   first, generation by generation);
4. synthesis stops at the maximum generation, the maximum total length,
   or when the density covers the domain as much as the example's
   (the fraction within ``rho`` of a branch). When every branch has
   stopped before that, the free space is filled round after round (at
   most ``fill_rounds``): the distance transform of the uncovered domain
   says where room is left; tips that ended at their drawn length with
   room ahead grow on, and branches with room beside them furcate once
   more at their most probable vertex there (not with guidance). Beyond
   the paper, holes the example does not have (domain farther than 5 % of
   its diameter from every branch, such as the lobes of a coast) are
   filled last, past the coverage target (``_Grower._fill_holes``); in a
   free frame (no coast) a root
   reads the frame ahead as density (``colonization.frame_density``), so
   its trunk turns into the image instead of walking out of the nearest
   side. A single
   branch stops when the Markov chain reaches the end of an input branch,
   when every candidate
   is blocked (crossing or too dense), when it leaves the domain, or
   when it gets longer than ``max_branch_factor`` x the longest input
   branch.

Everything random goes through ``rng``: the same seed gives the same
structure.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np

from ..core.io import encode_png
from ..core.params import check_params
from ..core.polyline import tangents
from ..core.random import as_rng
from ..core.structure import Branch, Structure
from ..core.validate import Array, Int, Real, Shape, checked
from .bending import BendingModel, branch_elements
from .colonization import (
    DensityMap,
    SegmentStore,
    auto_rho,
    coverage_fraction,
    crosses_existing,
    frame_density,
    growth_directions,
    profile_density,
)
from .furcation import FurcationModel, vertex_angles, window_features
from .guidance import Guidance
from .histogram_matching import HistogramMatcher, histogram_distances
from .params import SynthesisParams
from .roots import RootModel, fit_roots, outlet_starts
from .straightness import BendHistogram

__all__ = [
    "CandidateScores",
    "GrowthProgress",
    "StructureModel",
    "SynthesisResult",
    "extend_branch",
    "fit_model",
    "score_candidates",
    "synthesize_structure",
]

_FIT_FIELDS = ("h", "m", "k", "bins", "svm_C")
#: Directions a density profile is computed for per step (candidates share the nearest).
_DIRECTION_BINS = 512


# --------------------------------------------------------------------------
# Learning
# --------------------------------------------------------------------------
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
    _coverage_rho: float = field(repr=False, default=-1.0)

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
        g = min(int(generation), int(self.branch_generation.max()))
        idx = np.flatnonzero(self.branch_generation == g)
        if len(idx) == 0:
            idx = np.arange(len(self.branch_length))
        r = np.maximum(self.branch_r0[idx], 1e-6)
        w = np.exp(-np.log(max(r_start, 1e-6) / r) ** 2 / (2 * bandwidth ** 2)) + 1e-12
        j = idx[rng.choice(len(idx), p=w / w.sum())]
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
        return HistogramMatcher(self.example.angles(), self.example.thicknesses(),
                                bins=self.params.bins, wG=wG, m=self.params.m)

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
            self.coverage = coverage_fraction(self.example, _frame(self.source), rho, self.domain)
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
        return all(getattr(params, f) == getattr(self.params, f) for f in _FIT_FIELDS)


def _frame(s: Structure) -> tuple[int, int]:
    if s.image_shape is not None:
        return tuple(int(v) for v in s.image_shape[:2])
    _x0, _y0, x1, y1 = s.bounds()
    return int(np.ceil(y1)) + 2, int(np.ceil(x1)) + 2


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
              domain=None) -> StructureModel:
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

    Raises
    ------
    ValueError
        Empty example, or no branch with at least ``k + m + 2`` vertices
        after resampling (a full history of ``k + 1`` elements plus a
        continuation is needed somewhere). Shorter branches are kept: they
        feed the histograms, the furcation model and the candidates for
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
    dom = None
    if domain is not None:
        from ..core.image import as_mask

        if example.image_shape is None:
            raise ValueError("domain needs example.image_shape (the frame the domain covers)")
        dom = as_mask(domain, shape=example.image_shape, name="domain")
        if not dom.any():
            raise ValueError("domain is empty: no pixel where branches may grow")
    ex = example.resampled(p.h)
    longest = max(len(b.points) for b in ex.branches)
    need = p.k + p.m + 2
    if longest < need:
        raise ValueError(
            f"every branch of example is shorter than k + m: the longest has {longest} vertices at "
            f"step h = {p.h}, need k + m + 2 = {need}. Lower k or m, lower h, or annotate longer branches")
    bending = BendingModel.fit(ex, p.m, p.k, p.h)
    furc = FurcationModel.fit(ex, p.k, p.svm_C)
    hm = HistogramMatcher(ex.angles(), ex.thicknesses(), bins=p.bins, wG=p.wG, m=p.m)
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
    cover = coverage_fraction(ex, frame, p.rho if p.rho > 0 else rho, dom)
    return StructureModel(source=example, example=ex, bending=bending, furcation=furc, params=p,
                          cum_a=cum_a, cum_r=cum_r, cand_counts_a=cca, cand_counts_r=ccr,
                          cand_sq_a=np.einsum("ij,ij->i", cca, cca),
                          cand_sq_r=np.einsum("ij,ij->i", ccr, ccr),
                          local_dirs=ldirs,
                          head_start=np.array([hd["start"] for hd in bending.heads], np.int64),
                          edges_a=hm.edges_a, edges_r=hm.edges_r,
                          first_a=fa, first_r=fr, first_len=fl,
                          max_branch_length=max(b.length for b in ex.branches),
                          r_min=float(ex.thicknesses().min()),
                          rho=rho, domain=dom, coverage=cover, _coverage_rho=p.rho if p.rho > 0 else rho,
                          roots=fit_roots(ex, dom, shape=frame), drains=_drains(ex, dom),
                          branch_generation=np.array([ex.generation(i) for i in range(nb)]),
                          branch_length=np.array([b.length for b in ex.branches]),
                          branch_r0=np.array([np.mean(b.thickness[:3]) for b in ex.branches]))


def _drains(ex: Structure, domain: np.ndarray | None) -> bool:
    """True when the example's roots lie far inland (over 30 % of the deepest distance to the
    region outside the domain) and at least a third of its tips end at that region (within 10 %;
    braided channels cut into a tree have other tips where the cycles were cut)."""
    if domain is None or domain.all() or not domain.any():
        return False
    from scipy import ndimage as ndi

    depth = ndi.distance_transform_edt(domain)
    deepest = float(depth.max())
    h, w = domain.shape

    def at(p):
        x, y = np.clip(np.rint(p).astype(int), 0, [w - 1, h - 1])
        return depth[y, x]

    kids = {b.parent for b in ex.branches}
    # a tree rooted at a source whose one end at the coast is its mouth drains there (a river map
    # traced the wrong way round, see roots.outlet_starts), its mouth is no tip
    mouths = outlet_starts(ex, domain)
    roots = [at(q) for q in mouths]
    mouth_px = {tuple(np.rint(q).astype(int)) for q in mouths}
    tips = [at(b.points[-1]) for i, b in enumerate(ex.branches)
            if i not in kids and tuple(np.rint(b.points[-1]).astype(int)) not in mouth_px]
    return bool(roots and tips and np.median(roots) > 0.3 * deepest
                and np.mean(np.asarray(tips) < 0.1 * deepest) >= 1 / 3)


#: Strength of the pull toward the sea of an example that drains (``exp(kappa cos)``).
DRAIN_KAPPA = 2.0
#: An example that drains: a step heading back inland (cosine to the way down below this) is forbidden.
UPSTREAM_COS = -0.25


class _Drain:
    """Downstream pull for examples that drain (a delta, see ``StructureModel.drains``).

    A candidate heading at angle ``phi`` to the way down to the region
    outside the domain (the steepest descent of the distance to it) gets
    its score times ``exp(kappa cos phi)``: heading to the sea is
    ``e^(2 kappa)`` ~ 55 x likelier than heading back inland, sideways
    ``e^kappa`` less than straight down. Going beyond the paper, whose
    Markov chain alone has no notion of downstream: without it a delta's
    trunk wanders and rarely reaches the sea. The pull alone still let
    side channels head back inland (a delta with its sea on the left or
    top: 5-26 % of the branch length in some seeds), so a step heading
    back inland (cosine below ``UPSTREAM_COS``) or bringing a branch's tip
    upstream of its start is forbidden, children's first steps included.

    Also beyond the paper, the image frame where it cuts the land (every
    side of the frame but the sea's) is no place for a channel: a
    candidate that ends within ``margin`` pixels of such a side
    (``max(8, 6 %`` of the image's smaller side``)``) gets its score times
    ``exp(-10 (1 - d / margin))`` (``d`` the distance of its end), so of two
    candidates the one farther from the frame wins, and none that touches
    it (any new point within 3 px) is kept. New roots are exempt (they
    start at the frame and head inward).
    Without it the sea's pull drags branches along or into the frame where
    it runs downstream (a delta whose sea is on the left: branches along
    the bottom edge); the example's channels only leave through it where
    they enter (the trunk), and a root heading inward moves away from it.
    """

    def __init__(self, domain: np.ndarray, kappa: float = DRAIN_KAPPA):
        from scipy import ndimage as ndi

        dom = np.asarray(domain, bool)
        depth = ndi.gaussian_filter(ndi.distance_transform_edt(dom), 4.0)
        gy, gx = np.gradient(-depth)
        n = np.hypot(gx, gy) + 1e-12
        self.down = np.stack([gx / n, gy / n], -1).astype(np.float32)
        self.kappa = float(kappa)
        h, w = dom.shape
        self.shape = (h, w)
        self.margin = max(8.0, 0.06 * min(h, w))
        # the sides of the frame that cut the land (most of the side in the domain), not the sea's
        sides = (dom[0], dom[-1], dom[:, 0], dom[:, -1])
        self.cut = tuple(bool(side.mean() >= 0.5) for side in sides)

    def frame_distance(self, pts: np.ndarray) -> np.ndarray:
        """Distance of ``pts`` ((..., 2) x, y) to the nearest side of the frame that cuts the land."""
        h, w = self.shape
        x, y = pts[..., 0], pts[..., 1]
        d = np.full(x.shape, np.inf)
        for cut, v in zip(self.cut, (y, h - 1 - y, x, w - 1 - x)):
            if cut:
                d = np.minimum(d, v)
        return d

    def frame_factor(self, tip, points: np.ndarray, n_new: np.ndarray) -> np.ndarray:
        """Score factor of candidates ``points`` ((C, M, 2), the first ``n_new`` new) from ``tip``."""
        if not any(self.cut):
            return np.ones(len(points))
        fd = self.frame_distance(points)
        n = np.maximum(n_new, 1)
        valid = np.arange(points.shape[1])[None, :] < n[:, None]
        closest = np.where(valid, fd, np.inf).min(1)
        end = fd[np.arange(len(points)), n - 1]
        f = np.exp(-10.0 * np.clip(1.0 - end / self.margin, 0.0, 1.0))
        return np.where(closest < 3.0, 0.0, f)

    def _cos(self, at, vec: np.ndarray) -> np.ndarray:
        h, w = self.down.shape[:2]
        x, y = np.clip(np.rint(np.asarray(at, np.float64)).astype(int), 0, [w - 1, h - 1])
        return (vec @ self.down[y, x]) / np.maximum(np.hypot(vec[:, 0], vec[:, 1]), 1e-9)

    def factor(self, tip, points: np.ndarray, n_new: np.ndarray, start=None) -> np.ndarray:
        """Score factor of candidates ``points`` ((C, M, 2), the first ``n_new`` new) from ``tip``.

        ``start`` (the branch's first point): a candidate that heads back
        inland (over ``UPSTREAM_COS`` off the way down) or brings the
        branch's tip back upstream of its start is forbidden (0).
        """
        tip = np.asarray(tip, np.float64)
        end = points[np.arange(len(points)), np.maximum(n_new, 1) - 1]
        cos = self._cos(tip, end - tip)
        f = np.exp(self.kappa * cos) * self.frame_factor(tip, points, n_new)
        f = np.where(cos < UPSTREAM_COS, 0.0, f)
        if start is not None:
            net = end - np.asarray(start, np.float64)
            far = np.hypot(net[:, 0], net[:, 1]) > 4.0
            f = np.where(far & (self._cos(start, net) < 0.0), 0.0, f)
        return f


#: A map's rivers keep off the coast: the margin is this quantile of the depths (distance to the region
#: outside the domain) of the example's vertices past the first ``SHORE_SKIP`` px of its roots.
SHORE_QUANTILE = 0.05
SHORE_SKIP = 12.0
#: No hooks at a mouth (beyond the paper): over the first ``MOUTH_SHARE`` of a coast root's
#: length its heading may span at most ``MOUTH_TURN`` radians (a candidate that would turn it
#: further is taken only when nothing else is left). Without it 2 of 3 rivers of a 1000 px coast
#: map curled back by > 120 degrees just before their mouth.
MOUTH_SHARE = 0.12
MOUTH_TURN = float(np.radians(105.0))


def _shore_margin(model: StructureModel) -> float:
    """Distance the example's branches keep from its domain's edge (0: none to keep).

    Used on examples whose roots start at the domain's edge (rivers from a
    coast); 0 when the example has no domain, drains, its roots lie inland
    (median depth over 15 % of the deepest), or its branches run along the
    edge themselves (the margin is under 3 px).
    """
    dom = model.domain
    if dom is None or dom.all() or not dom.any() or model.drains:
        return 0.0
    cached = model.__dict__.get("_shore_margin")
    if cached is not None and cached[0] is dom:
        return cached[1]
    margin = _shore_margin_of(model, dom)
    model.__dict__["_shore_margin"] = (dom, margin)
    return margin


def _shore_margin_of(model: StructureModel, dom: np.ndarray) -> float:
    from scipy import ndimage as ndi

    depth = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    roots = [b.points[0] for b in model.example.branches if b.parent is None]
    if not roots:
        return 0.0
    x, y = np.clip(np.rint(np.asarray(roots)).astype(int), 0, [w - 1, h - 1]).T
    if np.median(depth[y, x]) > 0.15 * depth.max():     # roots inland (vessels from a disc): no coast
        return 0.0
    vals = []
    for b in model.example.branches:
        p = b.points
        if b.parent is None:
            arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
            p = p[arc > SHORE_SKIP]
        if len(p):
            x, y = np.clip(np.rint(p).astype(int), 0, [w - 1, h - 1]).T
            vals.append(depth[y, x])
    if not vals:
        return 0.0
    margin = float(np.quantile(np.concatenate(vals), SHORE_QUANTILE))
    return min(margin, 0.08 * min(h, w)) if margin >= 3.0 else 0.0


class _Shore:
    """Rivers of a map keep off its coast (beyond the paper).

    A candidate that comes closer to the edge of the domain (the coast)
    or runs along it, and ends within ``margin`` px of it (see
    :func:`_shore_margin`, the distance the example's rivers keep) gets
    its score times ``exp(-8 (1 - d / margin))``, and is forbidden when one
    of its new points comes within ``margin / 2``: such a river ends
    there. Heading inland
    (a root leaving the coast) is free. Without it a river that met the coast turned and ran
    along it (islands of 256 px: 5-20 % of the river length within 6 px
    of the coast against 1-1.5 % in the example).
    """

    def __init__(self, domain: np.ndarray, margin: float):
        from scipy import ndimage as ndi

        self.depth = ndi.distance_transform_edt(np.asarray(domain, bool)).astype(np.float32)
        self.margin = float(margin)

    def _at(self, pts: np.ndarray) -> np.ndarray:
        h, w = self.depth.shape
        ix = np.clip(np.rint(pts[..., 0]).astype(np.int64), 0, w - 1)
        iy = np.clip(np.rint(pts[..., 1]).astype(np.int64), 0, h - 1)
        return self.depth[iy, ix]

    def factor(self, tip, points: np.ndarray, n_new: np.ndarray) -> np.ndarray:
        """Score factor of candidates ``points`` ((C, M, 2), the first ``n_new`` new) from ``tip``."""
        n = np.maximum(n_new, 1)
        d = self._at(points)
        valid = np.arange(points.shape[1])[None, :] < n[:, None]
        closest = np.where(valid, d, np.inf).min(1)
        end = d[np.arange(len(points)), n - 1]
        tip = np.asarray(tip, np.float64)
        d_tip = float(self._at(tip))
        chord = np.hypot(*(points[np.arange(len(points)), n - 1] - tip).T)
        leaving = end - d_tip >= 0.5 * chord      # heading inland (within 60 degrees of straight)
        f = np.where(leaving, 1.0, np.exp(-8.0 * np.clip(1.0 - end / self.margin, 0.0, 1.0)))
        return np.where(~leaving & (closest < 0.5 * self.margin), 0.0, f)


# --------------------------------------------------------------------------
# Candidate scoring (vectorised over all candidates)
# --------------------------------------------------------------------------
@dataclass
class CandidateScores:
    """Scores of all candidates of one step.

    Parameters
    ----------
    t : (J,) int ndarray
        Candidate windows (index of their last input element).
    Q : (J,) ndarray
        Markov quality ``Q``.
    score : (J,) ndarray
        Final score ``Q***`` used for the choice (0 = forbidden).
    points : (J, m, 2) ndarray
        Vertices each candidate would append.
    n_new : (J,) int ndarray
        Real number of appended vertices.
    hist_factor, D_c, G_c : (J,) ndarray
        Global histogram factor ``exp(wG (dA + dR) n_t / m)``, density
        ``D_c`` ahead (0 without colonization) and guidance ``G_c`` ahead
        (1 without guidance).
    crossing : (J,) bool ndarray
        The density profile shows a crossing of another branch.
    """

    t: np.ndarray
    Q: np.ndarray
    score: np.ndarray
    points: np.ndarray
    n_new: np.ndarray
    hist_factor: np.ndarray
    D_c: np.ndarray
    G_c: np.ndarray
    crossing: np.ndarray


def _continue_radii(rad: np.ndarray, r_tip: float, r_src: float, r_min: float, r_max: float) -> np.ndarray:
    """Copied radii scaled to continue from the tip (thickness continuity).

    ``r_src`` is the input radius that precedes the copied elements: the
    copy keeps the input's relative change (its taper) from the tip's own
    radius, ``rad * r_tip / r_src``, within the input's range
    ``[r_min, r_max]``. (Copying absolute radii, or fading a shift back to
    them, makes the radius jump at every step whenever the matched input
    piece is thicker or thinner than the tip: beads along the branch.)
    """
    return np.clip(rad * (r_tip / max(r_src, 1e-9)), r_min, r_max)


def _rank_key(score: np.ndarray) -> np.ndarray:
    """Scores rounded to float32 for ranking: equal scores computed in a
    different order (last-bit differences) tie and fall back to the
    candidate index, so every scorer ranks identically."""
    return np.asarray(score, np.float64).astype(np.float32)


def _rotate(v: np.ndarray, theta: float) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    out = np.empty_like(v)
    out[..., 0] = c * v[..., 0] - s * v[..., 1]
    out[..., 1] = s * v[..., 0] + c * v[..., 1]
    return out


@dataclass
class _Base:
    """Everything about the candidates of one step except the density."""

    t: np.ndarray
    Q: np.ndarray
    n_new: np.ndarray
    points: np.ndarray
    dirs: np.ndarray
    hist_factor: np.ndarray
    G_c: np.ndarray
    base: np.ndarray


def _base_scores(model: StructureModel, hist_a, hist_r, tip, theta: float, params: SynthesisParams,
                 matcher: HistogramMatcher | None, guidance: Guidance | None) -> _Base:
    bm = model.bending
    t, Q = bm.quality(hist_a, hist_r)
    n_new = bm.cont_len[t]
    pts = bm.continuation_points(t, tip, theta)
    dirs = _rotate(model.local_dirs[t], theta)
    J = len(t)
    base = Q.copy()
    if matcher is not None and matcher.wG > 0 and matcher.n_nodes > 0:
        hf = matcher.factors(model.cand_counts_a[t], model.cand_counts_r[t],
                             model.cand_sq_a[t], model.cand_sq_r[t])
        base *= hf
    else:
        hf = np.ones(J)
    G_c = np.ones(J)
    if guidance is not None:
        g = guidance.along(tip, dirs, 3.0 * params.m * params.h)
        G_c = np.where(n_new == 0, float(guidance.sample(np.asarray(tip, float)[None])[0]), g)
        base = base / (G_c + params.eps)
    return _Base(t=t, Q=Q, n_new=n_new, points=pts, dirs=dirs, hist_factor=hf, G_c=G_c, base=base)


def score_candidates(model: StructureModel, hist_a, hist_r, tip, theta: float, *,
                     params: SynthesisParams, matcher: HistogramMatcher | None = None,
                     density: DensityMap | None = None,
                     guidance: Guidance | None = None) -> CandidateScores:
    """Score every candidate continuation of a branch tip (vectorised).

    ``score = Q * exp(wG (dA + dR) n_t / m) / (D_c + eps) / (G_c + eps)``
    with the colonization and guidance factors only when ``density`` /
    ``guidance`` are given; candidates whose density profile shows a
    crossing get 0. Candidates that end the branch (no followers in the
    input) get the best continuing candidate's density and the tip's
    guidance, so colonization neither favours nor prevents stopping.

    Per step the work is a handful of ``(J, L)``, ``(J, m)``, ``(J, B)`` and
    ``(J, n_samples)`` array operations over all ``J`` candidates; the
    candidates' vertices, PCA directions and histogram counts are
    precomputed in the tip's frame by :func:`fit_model`.

    Parameters
    ----------
    model : StructureModel
        The fitted example.
    hist_a, hist_r : (L0,) array_like
        The growing branch's elements so far: turning angles (radians) and
        thicknesses (pixels).
    tip : (2,) array_like
        Position (x, y) of the branch tip (pixels).
    theta : float
        Heading of the tip (radians).
    params : SynthesisParams
        ``m``, ``h``, ``eps`` and the other synthesis parameters.
    matcher : HistogramMatcher, optional
        Running histograms of the synthesis; None = no histogram factor.
    density : DensityMap, optional
        Density of the branches so far; None = no colonization factor.
    guidance : Guidance, optional
        Guidance map; None = no guidance factor.

    Returns
    -------
    CandidateScores
        Every candidate's factors and final score.
    """
    b = _base_scores(model, hist_a, hist_r, tip, theta, params, matcher, guidance)
    J = len(b.t)
    term = b.n_new == 0
    D_c = np.zeros(J)
    crossing = np.zeros(J, bool)
    score = b.base.copy()
    if density is not None:
        live = ~term
        if live.any():
            # Many candidates head the same way: profile each direction (to 0.7 degrees, well
            # under a pixel over the ray) once.
            d = b.dirs[live]
            q = np.rint(np.arctan2(d[:, 1], d[:, 0]) * (_DIRECTION_BINS / (2 * np.pi))).astype(np.int64)
            q %= _DIRECTION_BINS
            uq, inv = np.unique(q, return_inverse=True)
            ang = uq * (2 * np.pi / _DIRECTION_BINS)
            dc, cross, _ = profile_density(density, tip, np.c_[np.cos(ang), np.sin(ang)],
                                           3.0 * params.m * params.h)
            dc, cross = dc[inv], cross[inv]
            D_c[live] = dc
            crossing[live] = cross
            ok = live.copy()
            ok[live] = ~cross
            D_c[term] = D_c[ok].min() if ok.any() else 1.0
        score = np.where(crossing, 0.0, score / (D_c + params.eps))
    return CandidateScores(t=b.t, Q=b.Q, score=score, points=b.points, n_new=b.n_new,
                           hist_factor=b.hist_factor, D_c=D_c, G_c=b.G_c, crossing=crossing)


# --------------------------------------------------------------------------
# Result
# --------------------------------------------------------------------------
@dataclass
class SynthesisResult:
    """A synthesized structure with its diagnostics.

    Parameters
    ----------
    structure : Structure
        The synthesized branches.
    example : Structure
        The example resampled at ``h`` (what the result is compared with).
    diagnostics : dict
        ``time_s``, ``steps``, ``candidates_per_step``, ``stop_reason``,
        ``branch_stops`` (count per reason), ``n_branches``, ``n_vertices``,
        ``total_length``, ``coverage``, ``hist_distance`` (angle,
        thickness, sum), ``furcation_probability``.
    density : (H, W) ndarray or None
        Final density map (space colonization on).
    domain : (H, W) bool ndarray or None
        Where the structure was allowed to grow (None: the whole frame).
        Pass the result itself to :func:`~branchnb.branching.synthesize_image`
        and a flat-colour example's regions follow this domain.
    sources : list of (N_i,) int ndarray
        Per branch and vertex, the input element it was copied from (an
        index into ``StructureModel.bending``'s ``branch`` / ``local``
        arrays; -1 for a branch's first piece, taken from an input branch
        head, and for given branches). Consecutive indices are a stretch
        of the input copied verbatim (the paper's Fig. 3).
    """

    structure: Structure
    example: Structure
    diagnostics: dict
    density: np.ndarray | None = None
    domain: np.ndarray | None = field(default=None, repr=False)
    sources: list | None = field(default=None, repr=False)

    def histogram_distances(self, bins: int = 16, metric: str = "l2sq") -> dict:
        """Angle and thickness histogram distances of the result to its example (see
        :func:`~branchnb.branching.histogram_matching.histogram_distances`).

        Parameters
        ----------
        bins : int, default 16
            Number of bins B (16 in the paper).
        metric : str, default "l2sq"
            ``"l2sq"`` (the paper's), ``"l1"``, ``"chi2"`` or ``"emd"``.

        Returns
        -------
        dict
            ``{"angle": dA, "thickness": dR, "sum": dA + dR}``.
        """
        return histogram_distances(self.example, self.structure, bins=bins, metric=metric)

    def render(self, **kw) -> np.ndarray:
        """Draw the synthesized structure (``Structure.render``).

        Parameters
        ----------
        **kw
            Keyword arguments of ``Structure.render``.

        Returns
        -------
        ndarray
            The rendered image.
        """
        return self.structure.render(**kw)

    def _repr_png_(self) -> bytes | None:
        if not self.structure.branches:
            return None
        return encode_png(self.structure.render())


# --------------------------------------------------------------------------
# Growth
# --------------------------------------------------------------------------
@dataclass
class GrowthProgress:
    """A look at a structure while it grows: what ``synthesize_structure(progress=...)`` receives.

    Parameters
    ----------
    fraction : float
        Estimated progress in [0, 1]: the larger of the total length
        over ``max_total_length`` and the coverage over its target (below
        1 while growing; exactly 1 in the last report).
    steps : int
        Markov steps taken so far in this attempt.
    attempt : int
        Growth attempt (1, 2, ...): an attempt whose root walked out of
        the domain at once is grown again from scratch (see
        :data:`MAX_ROOT_ATTEMPTS`), so a later report may show fewer
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


@dataclass
class _BranchState:
    points: list
    radii: list
    elem_a: list
    elem_r: list
    theta: float
    parent: int | None
    parent_vertex: int | None
    generation: int
    stop: str = ""
    target: float = np.inf
    #: input element each vertex appended by a Markov step was copied from (the last ones)
    src: list = field(default_factory=list)
    #: a coast root near its mouth: (lowest, highest) heading so far (radians); None = no limit
    mouth: tuple | None = None


#: A hole is domain farther than this share of the domain's diameter from every branch (issue 23).
HOLE_DISTANCE = 0.05


def _hole_map(polylines, domain: np.ndarray, cell: float) -> tuple[float, np.ndarray, float]:
    """(share of ``domain`` in holes, distance to the nearest branch per grid cell, hole distance).

    Computed on a grid of ``cell`` pixels: the cells holding a branch vertex
    are the branches; a hole is a domain cell farther than
    :data:`HOLE_DISTANCE` x the domain's diameter from all of them.
    """
    from scipy import ndimage as ndi

    dom = np.asarray(domain, bool)
    k = max(int(cell), 1)
    grid = dom[::k, ::k]
    gh, gw = grid.shape
    occ = np.zeros((gh, gw), bool)
    for pts in polylines:
        pts = np.asarray(pts, np.float64)
        if len(pts):
            c = np.clip(np.floor((pts[:, 0] + 0.5) / k).astype(np.int64), 0, gw - 1)
            r = np.clip(np.floor((pts[:, 1] + 0.5) / k).astype(np.int64), 0, gh - 1)
            occ[r, c] = True
    ys, xs = np.nonzero(dom)
    diam = float(np.hypot(np.ptp(xs), np.ptp(ys))) if len(ys) else 0.0
    gap = HOLE_DISTANCE * diam
    if not occ.any() or not grid.any():
        return 1.0, np.full((gh, gw), np.inf), gap
    dist = ndi.distance_transform_edt(~occ) * k
    return float(np.mean(dist[grid] > gap)), dist, gap


class _Grower:
    def __init__(self, model: StructureModel, params: SynthesisParams, rng, shape,
                 guidance: Guidance | None, scorer=None, domain: np.ndarray | None = None):
        self.model, self.p, self.rng = model, params, rng
        scorer = scorer or score_candidates
        self.shape = (int(shape[0]), int(shape[1]))
        self.guidance = guidance
        self.drain = _Drain(domain) if guidance is None and model.drains and domain is not None \
            and not domain.all() else None
        margin = _shore_margin(model) if guidance is None and domain is not None \
            and not domain.all() and self.drain is None else 0.0
        self.shore = _Shore(domain, margin) if margin > 0 else None
        self.scorer = scorer
        self.matcher = model.matcher(params.wG)
        # beyond the paper: the sizes of the turns follow the example's too (see .straightness)
        bm = model.bending
        self.bends = BendHistogram(bm.angles, wG=params.wG, m=params.m)
        self.bend_counts = self.bends.candidate_counts(bm.cont_angles, bm.cont_len) if params.wG > 0 else None
        self.rho = params.rho if params.rho > 0 else model.rho
        self.domain = domain
        # a root reads the frame ahead as density (a free frame only: a map's domain has its own rules)
        self.frame = params.colonization and guidance is None and (domain is None or bool(domain.all()))
        # coverage = fraction of the domain within rho of a branch (D > exp(-1))
        self.density = DensityMap(self.shape, self.rho, domain=domain, level=float(np.exp(-1.0))) \
            if params.colonization else None
        self.coverage_target = params.max_coverage if params.max_coverage > 0 else \
            min(model.coverage_at(self.rho), 1.0)
        self.store = SegmentStore()
        self.branches: list[_BranchState] = []
        self.total_length = 0.0
        self.steps = 0
        self.n_candidates = 0
        self.stop_reason = ""
        self.max_branch_len = params.max_branch_factor * model.max_branch_length
        radii = model.example.thicknesses()
        self.r_max = float(radii.max()) if radii.size else np.inf
        self.fill_rounds = 0
        self._empty_dt: np.ndarray | None = None
        self.attempt = 1
        self.progress = None  # progress(GrowthProgress) after every Markov step

    def report(self, done: bool = False) -> None:
        if self.progress is None:
            return
        cov = self.density.coverage() if self.density is not None else None
        frac = self.total_length / max(self.p.max_total_length, 1e-9)
        if cov is not None and self.coverage_target < 1:
            frac = max(frac, cov / max(self.coverage_target, 1e-9))
        frac = 1.0 if done else min(frac, 0.99)
        self.progress(GrowthProgress(fraction=float(frac), steps=self.steps, attempt=self.attempt,
                                     n_branches=len(self.branches), total_length=self.total_length,
                                     coverage=cov, done=done, _grower=self))

    # -- bookkeeping ------------------------------------------------------
    def _inside(self, pts: np.ndarray) -> np.ndarray:
        h, w = self.shape
        ok = (pts[:, 0] >= -0.5) & (pts[:, 0] <= w - 0.5) & (pts[:, 1] >= -0.5) & (pts[:, 1] <= h - 0.5)
        if self.domain is not None and ok.any():
            ix = np.clip(np.rint(pts[:, 0]).astype(np.int64), 0, w - 1)
            iy = np.clip(np.rint(pts[:, 1]).astype(np.int64), 0, h - 1)
            ok &= self.domain[iy, ix]
        return ok

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
        poly = np.asarray(polyline, np.float64)
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
        if self.total_length >= self.p.max_total_length - 1e-6:  # tolerance: summation order
            self.stop_reason = "total length"
        elif self.density is not None and self.coverage_target < 1 and \
                self.density.coverage() >= self.coverage_target:
            self.stop_reason = "density (coverage)"
        return bool(self.stop_reason)

    # -- selection --------------------------------------------------------
    def _cap(self) -> int:
        return 64 + 4 * self.p.c

    def _pick(self, score: np.ndarray, polylines_fn) -> int | None:
        """Among the c best valid candidates, choose one with probability ~ score."""
        order = np.lexsort((np.arange(len(score)), -_rank_key(score)))
        chosen: list[int] = []
        tries = 0
        for j in order:
            if score[j] <= 0 or not np.isfinite(score[j]):
                break
            if self.density is not None:
                tries += 1
                if tries > self._cap():
                    break
                if crosses_existing(self.store, polylines_fn(j)):
                    continue
            chosen.append(int(j))
            if len(chosen) == self.p.c:
                break
        return self._draw(score, chosen)

    def _draw(self, score, chosen) -> int | None:
        if not chosen:
            return None
        w = score[chosen]
        return chosen[int(self.rng.choice(len(chosen), p=w / w.sum()))]

    # -- starting branches ------------------------------------------------
    def _start_branch(self, x0, theta0, heads, Q, parent, parent_vertex, generation,
                      betas=None, mirror=None, r_cap: float | None = None) -> int | None:
        """Start a branch at ``x0`` with one of the candidate input heads (vectorised).

        ``r_cap`` (a child: the parent's radius at the junction) bounds the
        copied head's radii: a head taken from a thicker input branch is
        scaled down so the child never starts thicker than its parent.
        """
        model, p = self.model, self.p
        heads = np.asarray(heads, np.int64)
        if len(heads) == 0:
            return None
        x0 = np.asarray(x0, np.float64)
        H = len(heads)
        th0 = theta0 + (np.zeros(H) if betas is None else np.asarray(betas, np.float64))
        n = model.first_len[heads]
        # vertices after x0: x1 (first edge, no turn) then the n first elements
        sign = np.where(mirror, -1.0, 1.0) if mirror is not None else np.ones(H)
        turns = np.concatenate([np.zeros((H, 1)), model.first_a[heads] * sign[:, None]], axis=1)
        valid = np.arange(p.m + 1)[None, :] <= n[:, None]
        th = th0[:, None] + np.cumsum(turns * valid, axis=1)
        steps = p.h * valid
        new = np.stack([x0[0] + np.cumsum(np.cos(th) * steps, axis=1),
                        x0[1] + np.cumsum(np.sin(th) * steps, axis=1)], axis=-1)

        def poly(j):
            return np.vstack([x0, new[j, : n[j] + 1]])

        score = np.asarray(Q, np.float64).copy()
        if self.matcher.wG > 0 and self.matcher.n_nodes > 0:
            st0 = model.head_start[heads]
            # mirrored heads have negated angles: bin them directly
            ok = np.arange(p.m)[None, :] < n[:, None]
            bins_a = self.matcher.bin_angles(model.first_a[heads] * sign[:, None])
            flat = (bins_a + p.bins * np.arange(H)[:, None])[ok]
            ca = np.bincount(flat, minlength=H * p.bins).reshape(H, p.bins).astype(np.float64)
            cr = model.cum_r[st0 + n] - model.cum_r[st0]
            score *= self.matcher.factors(ca, cr)
        dirs = growth_directions(x0, new, n + 1)
        if self.guidance is not None:
            score = score / (self.guidance.along(x0, dirs, 3.0 * p.m * p.h) + p.eps)
        if self.density is not None:
            dc, cross, _ = profile_density(self.density, x0, dirs, 3.0 * p.m * p.h)
            score = np.where(cross, 0.0, score / (dc + p.eps))
            if self.frame and parent is None:
                score = score * self._frame_factor(x0, dirs, dc)
        inside = self._inside(new[:, 0])
        score = np.where(inside, score, 0.0)
        if self.drain is not None and parent is not None:  # downstream, not along or into the land's frame
            score = score * self.drain.factor(x0, new, n + 1, start=x0)
        if self.shore is not None:
            score = score * self.shore.factor(x0, new, n + 1)
        mouth = self.shore is not None and parent is None
        if mouth:
            span = np.where(valid, th, th[:, :1])
            score = np.where(np.ptp(span, axis=1) > MOUTH_TURN, score * 1e-9, score)
        j = self._pick(score, poly)
        if j is None:
            return None
        hd = int(heads[j])
        full = poly(j)
        ok = self._inside(full)
        cut = len(full) if ok.all() else int(np.argmin(ok))
        pl = full[:cut]
        head = model.bending.heads[hd]
        ne = max(cut - 2, 0)
        ea = list(sign[j] * model.first_a[hd, :ne])
        er = list(model.first_r[hd, :ne])
        radii = [head["r0"], head["r1"]] + er
        if r_cap is not None:
            f = min(1.0, r_cap / max(max(radii[:3]), 1e-9))
            if f < 1.0:
                radii = [max(r * f, model.r_min) for r in radii]
                er = radii[2:]
        d = pl[-1] - pl[-2]
        st = _BranchState(points=list(pl), radii=radii, elem_a=ea, elem_r=er,
                          theta=float(np.arctan2(d[1], d[0])), parent=parent,
                          parent_vertex=parent_vertex, generation=generation)
        if p.branch_end == "length":
            st.target = model.sample_length(generation, float(np.mean(radii[:3])), self.rng)
        if mouth:
            hs = th[j, : max(cut - 1, 1)]
            st.mouth = (float(hs.min()), float(hs.max()))
        if cut < len(full):
            st.stop = "left the domain"
        elif n[j] < p.m and p.branch_end == "markov":
            st.stop = "end of input branch"
        self._register(pl, ea, radii)
        self.branches.append(st)
        return len(self.branches) - 1

    def start_root(self, x, y, theta) -> int | None:
        model = self.model
        nb = len(model.example.branches)
        usable = [i for i in range(nb) if model.first_len[i] > 0]
        roots = [i for i in usable if model.example.branches[i].parent is None]
        # With fewer than 3 input roots every new root would start with the same
        # copied head; then any input branch's head may start a root.
        pool = roots if len(roots) >= 3 else usable
        Q = np.ones(len(pool))
        return self._start_branch(np.array([x, y], float), float(theta), pool, Q, None, None, 0)

    def start_child(self, parent: int, vertex: int) -> int | None:
        model, fm = self.model, self.model.furcation
        st = self.branches[parent]
        pts = np.asarray(st.points)
        rad = np.asarray(st.radii)
        wa, wr = window_features(vertex_angles(pts), rad, fm.k)
        Q = fm.child_quality(wa[vertex], wr[vertex])
        heads = fm.child_index
        usable = model.first_len[heads] > 0
        heads, Q = heads[usable], Q[usable]
        if len(heads) == 0:
            return None
        betas = np.array([model.bending.heads[h]["beta"] or 0.0 for h in heads])
        mirror = np.zeros(len(heads), bool)
        if self.p.mirror_children:
            # the same furcations reflected: parent window and child angles negated
            Qm = fm.child_quality(-wa[vertex], wr[vertex])[usable]
            heads = np.concatenate([heads, heads])
            Q = np.concatenate([Q, Qm])
            betas = np.concatenate([betas, -betas])
            mirror = np.concatenate([mirror, ~mirror])
        tg = tangents(pts)[vertex]
        return self._start_branch(pts[vertex], float(np.arctan2(tg[1], tg[0])), heads, Q, parent,
                                  vertex, st.generation + 1, betas=betas, mirror=mirror,
                                  r_cap=float(rad[vertex]))

    # -- growing ----------------------------------------------------------
    def step(self, bi: int) -> bool:
        """One Markov step of branch ``bi``; False when the branch stops."""
        st, p = self.branches[bi], self.p
        if st.stop:
            return False
        if not st.elem_a:
            st.stop = "no history"
            return False
        tip = np.asarray(st.points[-1])
        self.steps += 1
        cs = self.scorer(self.model, st.elem_a, st.elem_r, tip, st.theta, params=p,
                         matcher=self.matcher, density=self.density, guidance=self.guidance)
        pts, n_arr, t_arr = cs.points, cs.n_new, cs.t
        self.n_candidates += len(t_arr)

        def poly(j):
            return np.vstack([tip, pts[j, : max(n_arr[j], 0)]])

        score = cs.score
        fb = self.bends.factors(self.bend_counts[t_arr]) if self.bend_counts is not None else None
        if self.frame and st.parent is None:
            live = n_arr > 0
            if live.any():
                end = pts[np.arange(len(n_arr)), np.maximum(n_arr, 1) - 1] - tip
                dirs = end / np.maximum(np.hypot(end[:, 0], end[:, 1]), 1e-9)[:, None]
                score = np.where(live, score * self._frame_factor(tip, dirs, cs.D_c), score)
        if self.drain is not None:
            score = score * self.drain.factor(tip, pts, n_arr, start=st.points[0])
        if self.shore is not None:
            fs = self.shore.factor(tip, pts, n_arr)
            score = score * fs
            if fb is not None:   # near the coast the shore decides alone
                fb = np.where(fs < 1.0, 1.0, fb)
        if fb is not None:
            score = score * fb
        if p.branch_end == "length":
            score = np.where(n_arr > 0, score, 0.0)
        heads = None
        if st.mouth is not None:
            if (len(st.points) - 1) * p.h < MOUTH_SHARE * min(st.target, self.max_branch_len):
                heads = st.theta + np.cumsum(self.model.bending.cont_angles[t_arr], axis=1)
                span = np.maximum(heads.max(1), st.mouth[1]) - np.minimum(heads.min(1), st.mouth[0])
                score = np.where(span > MOUTH_TURN, score * 1e-9, score)
            else:
                st.mouth = None
        if self.density is not None:
            free = (~cs.crossing) & (n_arr > 0)
            if not free.any() or cs.D_c[free].min() >= p.stop_density:
                st.stop = "density"
                return False
        j = self._pick(score, poly)
        if j is None:
            st.stop = "blocked"
            return False
        t, n = int(t_arr[j]), int(n_arr[j])
        if heads is not None and n:
            st.mouth = (min(st.mouth[0], float(heads[j, :n].min())), max(st.mouth[1], float(heads[j, :n].max())))
        bm = self.model.bending
        new_pts = pts[j, :n]
        ang = bm.cont_angles[t, :n]
        rad = bm.cont_radii[t, :n]
        if p.thickness_blend and n:
            rad = _continue_radii(rad, st.radii[-1], bm.radii[t], self.model.r_min, self.r_max)
        ok = self._inside(new_pts)
        if not ok.all():
            cut = int(np.argmin(ok))
            new_pts, ang, rad = new_pts[:cut], ang[:cut], rad[:cut]
            st.stop = "left the domain"
        if len(new_pts):
            self._register(np.vstack([tip, new_pts]), ang, rad)
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
        k = 0
        while max_steps is None or k < max_steps:
            if self.global_stop():
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
        pts = np.asarray(st.points)
        rad = np.asarray(st.radii)
        length = (len(pts) - 1) * p.h
        weights = None
        if extra:
            d = 1
            existing = [b.parent_vertex for b in self.branches if b.parent == bi]
            weights = self._room(pts) if self._empty_dt is not None else None
            if weights is not None and not weights.any():
                return []
        else:
            d = p.d if p.d >= 0 else self.model.furcation.sample_d(length, self.rng)
            existing = ()
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

    # -- filling the domain -------------------------------------------------
    def _update_room(self) -> None:
        """Distance (pixels) from every density cell to the nearest covered cell (D > level)."""
        from scipy import ndimage as ndi

        dm = self.density
        empty = dm.domain & (dm.grid <= dm.level)
        self._empty_dt = ndi.distance_transform_edt(empty).astype(np.float32) * dm.cell

    def _room(self, pts: np.ndarray) -> np.ndarray:
        """Free space beside each vertex, ``(N,)`` pixels (0 = none).

        A child starting at a vertex grows into the space beside its
        parent: the room on a side is the free radius of the uncovered
        region ``2 rho`` away along the normal (one example gap further),
        kept only while that point is still uncovered and the region there
        is at least ``rho / 2`` wide; the larger of the two sides counts.
        """
        dm, dt = self.density, self._empty_dt
        if len(pts) < 3:
            return np.zeros(len(pts))
        tg = tangents(pts)
        nrm = np.c_[-tg[:, 1], tg[:, 0]]
        best = np.zeros(len(pts))
        gh, gw = dt.shape
        for side in (-1.0, 1.0):
            q = pts + side * 2.0 * self.rho * nrm
            c = np.floor((q[:, 0] + 0.5) / dm.cell).astype(np.int64)
            r = np.floor((q[:, 1] + 0.5) / dm.cell).astype(np.int64)
            ok = (c >= 0) & (c < gw) & (r >= 0) & (r < gh)
            room = np.zeros(len(pts))
            room[ok] = dt[r[ok], c[ok]]
            room[dm.sample(q) > dm.level] = 0.0
            best = np.maximum(best, room)
        best[best < 0.5 * self.rho] = 0.0
        return best

    def _reopen_tips(self) -> list[int]:
        """Branches that stopped at their drawn length with uncovered space ahead, reopened.

        Each gets a new length target: its length plus one more draw for its
        generation (still bounded by ``max_branch_factor``).
        """
        dm, dt = self.density, self._empty_dt
        out = []
        for bi, st in enumerate(self.branches):
            if st.stop != "branch length" or len(st.points) < 2:
                continue
            tip = np.asarray(st.points[-1])
            q = tip + 2.0 * self.rho * np.array([np.cos(st.theta), np.sin(st.theta)])
            c, r = int(np.floor((q[0] + 0.5) / dm.cell)), int(np.floor((q[1] + 0.5) / dm.cell))
            if not (0 <= r < dt.shape[0] and 0 <= c < dt.shape[1]) or dt[r, c] < 0.5 * self.rho:
                continue
            length = (len(st.points) - 1) * self.p.h
            if length >= self.max_branch_len:
                continue
            st.stop = ""
            st.target = length + self.model.sample_length(st.generation, float(st.radii[-1]), self.rng)
            out.append(bi)
        return out

    def _drain(self, queue: list[int]) -> None:
        """Grow the queued branches breadth first, queueing their children."""
        qi = 0
        while qi < len(queue):
            bi = queue[qi]
            qi += 1
            if self.global_stop():
                return
            self.grow(bi)
            if self.global_stop():
                return
            queue.extend(self.furcate(bi))

    def _holes(self) -> tuple[float, np.ndarray, float]:
        dom = self.domain if self.domain is not None else np.ones(self.shape, bool)
        return _hole_map([st.points for st in self.branches], dom, self.density.cell)

    def _example_holes(self) -> float:
        m = self.model
        dom = m.domain if m.domain is not None else np.ones(_frame(m.source), bool)
        return _hole_map([b.points for b in m.example.branches], dom, self.density.cell)[0]

    def _fill_holes(self) -> None:
        """Grow into holes the example does not have (beyond the paper).

        The coverage target counts the domain within ``rho`` of a branch, not
        where the rest lies: a forest can reach it with branches crowded in
        the middle and wide empty lobes along a coast. When the share of
        the domain farther than :data:`HOLE_DISTANCE` x its diameter from
        every branch exceeds the example's, branches beside the holes
        furcate once more toward them (one child each, grown without
        further furcations) and tips ending before a hole grow on, past the
        coverage target, until the share is the example's or no branch can
        reach a hole (at most ``fill_rounds`` rounds; coverage at most
        1.25 x the target). Only in a domain of the user's (a map's land, a
        mask's region; a free image frame has no coast to reach: there the
        roots read the frame as density instead, see ``_frame_factor``;
        filling its holes too pushed coverage to 1.1-1.3 x the target on
        the retina, lightning and crack samples), not with a
        ``max_coverage`` of the user's, guidance, or ``fill_rounds = 0``.
        """
        if self.guidance is not None or self.density is None or not self.branches or \
                self.domain is None or self.domain.all() or \
                self.p.fill_rounds == 0 or self.p.max_coverage > 0 or \
                self.stop_reason not in ("", "density (coverage)", "no branch can grow"):
            return
        share, dist, gap = self._holes()
        target = self._example_holes() + 1e-3
        if share <= target:
            return
        saved, reason = self.coverage_target, self.stop_reason
        # past the target, within bounds: 25 % more coverage at most
        self.coverage_target, self.stop_reason = min(1.0, 1.25 * saved), ""
        dm = self.density
        for _ in range(self.p.fill_rounds):
            before = len(self.branches)
            self._update_room()
            # room counts only in and around the holes
            gd = dm.grid
            k = max(int(dm.cell), 1)
            # the hole grid (step k) and the density grid (step cell) differ: sample by position
            ry = np.minimum((np.arange(gd.shape[0]) * dm.cell / k).astype(np.int64), dist.shape[0] - 1)
            rx = np.minimum((np.arange(gd.shape[1]) * dm.cell / k).astype(np.int64), dist.shape[1] - 1)
            near = dist[np.ix_(ry, rx)] > 0.5 * gap
            self._empty_dt = np.where(near, self._empty_dt, 0.0).astype(np.float32)
            for bi in self._reopen_tips():
                self.grow(bi)
            rooms = [float(self._room(np.asarray(b.points)).max(initial=0.0)) for b in self.branches]
            for bi in np.argsort(rooms, kind="stable")[::-1]:
                if rooms[bi] <= 0 or self.stop_reason:
                    break
                for c in self.furcate(int(bi), extra=True):
                    self.grow(c)
                share, dist, gap = self._holes()
                if share <= target:
                    break
            self._empty_dt = None
            share, dist, gap = self._holes()
            if share <= target or len(self.branches) == before or self.stop_reason:
                break
        self.coverage_target = saved
        if not self.stop_reason or self.stop_reason == "density (coverage)":
            self.stop_reason = reason

    def run(self, starts) -> None:
        queue = []
        for (x, y, th) in starts:
            if self.global_stop():
                break
            r = self.start_root(x, y, th)
            if r is not None:
                queue.append(r)
        self._drain(queue)
        # Everything stopped before the domain is as dense as the example:
        # furcate the grown branches once more (highest furcation probability
        # away from their children), round after round.
        # (Not in guided synthesis: the user's path, not the domain, says where to grow.)
        for _ in range(self.p.fill_rounds if self.guidance is None else 0):
            if self.global_stop() or self.density is None or not self.branches:
                break
            before = len(self.branches)
            self._update_room()
            rooms = [float(self._room(np.asarray(b.points)).max(initial=0.0)) for b in self.branches]
            # tips that ended at their drawn length with free space ahead grow on
            self._drain(self._reopen_tips())
            for bi in np.argsort(rooms, kind="stable")[::-1]:
                if self.global_stop() or rooms[bi] <= 0:
                    break
                self._drain(self.furcate(int(bi), extra=True))
            self._empty_dt = None
            if len(self.branches) == before:
                break
            self.fill_rounds += 1
        if not self.stop_reason:
            self.stop_reason = "no branch can grow" if queue else "no root could start"

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
            "fill_rounds": self.fill_rounds,
        }


# --------------------------------------------------------------------------
# Public entry points
# --------------------------------------------------------------------------
def _resolve(example, params) -> tuple[StructureModel, SynthesisParams]:
    p = check_params(params if params is not None else SynthesisParams())
    if isinstance(example, StructureModel):
        model = example if example.compatible(p) else fit_model(example.source, p, domain=example.domain)
    else:
        model = fit_model(_check_example(example), p)
    return model, p


def _domain(model: StructureModel, shape) -> tuple[int, int]:
    if shape is not None:
        if len(shape) < 2 or int(shape[0]) <= 0 or int(shape[1]) <= 0:
            raise ValueError(f"shape must be a positive (H, W), got {shape}")
        return int(shape[0]), int(shape[1])
    if model.source.image_shape is not None:
        return tuple(int(v) for v in model.source.image_shape[:2])
    _x0, _y0, x1, y1 = model.source.bounds()
    return int(np.ceil(y1)) + 2, int(np.ceil(x1)) + 2


def _default_starts(model: StructureModel, shape, guidance, params: SynthesisParams | None = None,
                    domain=None, rng=None) -> list[tuple[float, float, float]]:
    if guidance is not None and guidance.start() is not None:
        return [guidance.start()]
    if params is not None and params.roots == "learned" and model.roots is not None and model.roots.n_roots:
        dom = domain if domain is not None else np.ones(tuple(shape), bool)
        n = params.n_roots if params.n_roots >= 0 else None
        return model.roots.sample(dom, rng, n)
    src = model.example
    sy, sx = 1.0, 1.0
    if src.image_shape is not None:
        sy, sx = shape[0] / src.image_shape[0], shape[1] / src.image_shape[1]
    out = []
    for b in src.branches:
        if b.parent is None and len(b.points) >= 2:
            d = b.points[1] - b.points[0]
            out.append((float(b.points[0, 0] * sx), float(b.points[0, 1] * sy),
                        float(np.arctan2(d[1], d[0]))))
    return out


def _lift_child_heads(s: Structure) -> Structure:
    """Branches start no thinner than they run on (beyond the paper).

    An extracted child's first radii are measured where it leaves its parent,
    where the distance transform reads short (a drawn map's rivers of one
    width start at half their width and end 2 x thicker); copied heads carry
    that dip into every synthesized child. The first vertices of a child (up
    to a third of it, at most 5) are raised to the smaller of the radius it
    runs on next (median of the following as many vertices) and its
    parent's radius at the junction. A root's head is raised the same way
    (a river traced to a coast line, a channel cut by the frame, ends
    thin); thicker heads are kept.
    """
    out = []
    changed = False
    for b in s.branches:
        r = b.thickness
        n = len(r)
        if n < 3:
            out.append(b)
            continue
        k = min(5, max(1, n // 3))
        floor = float(np.median(r[k:2 * k + 1]))
        if b.parent is not None:
            pr = s.branches[b.parent].thickness
            floor = min(floor, float(pr[int(np.clip(b.parent_vertex or 0, 0, len(pr) - 1))]))
        if np.all(r[:k] >= floor):
            out.append(b)
            continue
        r = r.copy()
        r[:k] = np.maximum(r[:k], floor)
        changed = True
        out.append(Branch(b.points, r, b.parent, b.parent_vertex))
    return Structure(out, image_shape=s.image_shape) if changed else s


#: Attempts at growing the roots before the largest result is kept.
MAX_ROOT_ATTEMPTS = 8


#: A forest drawn from the root model that ends below this share of the coverage target is grown again.
MIN_COVERAGE_SHARE = 0.7


def _fullness(g: _Grower) -> tuple[float, int]:
    """(share of the coverage target reached, vertices): how an attempt ranks."""
    share = 1.0
    if g.density is not None and 0 < g.coverage_target < 1:
        share = min(g.density.coverage() / g.coverage_target, 1.0)
    return share, sum(len(b.points) for b in g.branches)


def _root_escaped(g: _Grower, min_root_length: float) -> bool:
    """True if a root left the domain before growing ``min_root_length``."""
    for st in g.branches:
        if st.parent is None and st.stop == "left the domain":
            pts = np.asarray(st.points, np.float64)
            if len(pts) < 2 or np.hypot(*np.diff(pts, axis=0).T).sum() < min_root_length:
                return True
    return False


def _grow_with_retries(model, p, rng, shp, guidance, starts, scorer, domain=None,
                       progress=None) -> _Grower:
    """Grow, restarting when a root walks out of the domain at once.

    A root starts at an example root's head with its heading; near the
    image border the first copied pieces often lead straight out, which
    ends the whole synthesis after a few steps (the paper's user simply
    places the seed again). When a root leaves the domain before growing
    half the example's median root length (at most a quarter of the
    domain's short side), synthesis restarts with the next draws of the
    same generator, so results stay reproducible, up to
    :data:`MAX_ROOT_ATTEMPTS` times; the attempt closest to the coverage
    target (then the one with the most vertices) is kept. With starts drawn from the root model, a result shorter than a
    quarter of the example's total length (scaled by the domain's area),
    or that covers less than :data:`MIN_COVERAGE_SHARE` of the coverage
    target (its roots walked out before the forest could fill the domain),
    is grown again the same way (new starts); the attempt closest to the
    target is kept. A forest of 3 or more trees that reached the coverage
    target keeps a root that walked out (a short river at a coast). Guided
    synthesis is never restarted.
    """
    roots = [b.length for b in model.example.branches if b.parent is None and len(b.points) > 1]
    n_roots = len(starts) if isinstance(starts, (list, tuple)) else len(roots)
    min_len = min(0.5 * float(np.median(roots)), 0.25 * min(shp)) if roots else 0.0
    # A forest that died young (its roots blocked or ended at once) is grown again too.
    frame = _frame(model.source)
    area_ratio = (shp[0] * shp[1]) / max(frame[0] * frame[1], 1)
    if domain is not None and model.domain is not None:
        area_ratio = float(np.count_nonzero(domain)) / max(float(np.count_nonzero(model.domain)), 1.0)
    min_total = 0.0
    if starts is None or callable(starts):
        min_total = min(0.25 * model.example.total_length * area_ratio, 0.5 * p.max_total_length)
    # A guided root follows the user's path, out of the domain if the path goes there.
    attempts = 1 if guidance is not None else MAX_ROOT_ATTEMPTS
    best = None
    for attempt in range(1, attempts + 1):
        g = _Grower(model, p, rng, shp, guidance, scorer=scorer, domain=domain)
        g.attempt, g.progress = attempt, progress
        g.run(starts(rng) if callable(starts) else starts)
        if best is None or _fullness(g) > _fullness(best):
            best = g
        # a forest of many trees that reached the coverage target keeps a root that walked out
        # (a short river at the coast); growing all of it again cost 4-8 x the time on 1000 px maps
        escaped = _root_escaped(g, min_len) and not (n_roots >= 3 and _fullness(g)[0] >= 1.0)
        if not escaped and g.total_length >= min_total and \
                (not min_total or _fullness(g)[0] >= MIN_COVERAGE_SHARE):
            best = g
            break
    best._fill_holes()   # on the kept attempt only
    return best


def _check_domain(domain, model: StructureModel, shape):
    import cv2

    from ..core.image import as_mask

    if domain is None:
        if model.domain is None:
            return None
        d = model.domain
        if d.shape != tuple(shape):
            d = cv2.resize(d.astype(np.uint8), (shape[1], shape[0]), interpolation=cv2.INTER_NEAREST) > 0
        return d
    d = as_mask(domain, shape=tuple(shape), name="domain")
    if not d.any():
        raise ValueError("domain is empty: no pixel where branches may grow")
    return d


def _check_guidance(guidance, shape):
    if guidance is None:
        return None
    if not isinstance(guidance, Guidance):
        try:
            guidance = Guidance(guidance)
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"guidance: {exc}") from None
    if guidance.shape != tuple(shape):
        raise ValueError(f"guidance map has shape {guidance.shape}, the domain is {tuple(shape)}")
    return guidance


@checked(shape=Shape(), starts=Array(ndim=2))
def synthesize_structure(example, params: SynthesisParams | None = None, *, rng=None,
                         guidance=None, shape=None, starts=None, domain=None,
                         progress=None, _scorer=None) -> SynthesisResult:
    """Synthesize a new branching structure that looks like ``example``.

    Parameters
    ----------
    example : Structure or StructureModel
        The source structure, or a model from :func:`fit_model` (refitted
        automatically if ``params`` changes ``h``, ``m``, ``k``, ``bins``
        or ``svm_C``).
    params : SynthesisParams, optional
        The paper's defaults if omitted.
    rng : int or numpy.random.Generator, optional
        Seed: the same seed gives the same structure.
    guidance : Guidance or (H, W) array_like, optional
        Guidance map ``G`` (see :mod:`~branchnb.branching.guidance`); with
        a path and no ``starts``, the root starts at the path's start.
    shape : (H, W), optional
        Output domain (default: the example's ``image_shape``).
    starts : sequence of (x, y, angle), optional
        Root start points and initial directions (radians, image
        coordinates). Default (``params.roots = "learned"``): ``n_roots``
        starts (default: as many as the example has trees) drawn from the
        learnt root model (:mod:`.roots`): on the same kind of boundary as
        the example's roots (an image side, the domain's edge such as a
        coast, or inside), heading into the domain; ``roots = "example"``
        uses the example's own root starts (scaled to ``shape``).
    domain : (H, W) bool array_like, optional
        Where branches may grow (a branch stops where it would leave it);
        default: the model's domain (resized to ``shape``) or the whole frame.
    progress : callable, optional
        ``progress(growth)`` with a :class:`GrowthProgress` after every
        Markov step and once at the end (``growth.done``, whose
        ``structure()`` is the result); ``growth.structure()`` is the
        partial skeleton of the current attempt: the result grows on from
        it unless a later attempt starts again (see
        :class:`GrowthProgress`). For previews (show a partial skeleton while the
        rest grows) and for stopping: an exception raised by ``progress``
        ends synthesis and propagates. Reports do not change the result.

    Returns
    -------
    SynthesisResult
        ``.structure`` plus ``.diagnostics``.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 12, 400)
    >>> trunk = np.c_[10 + 20 * t, 100 + 8 * np.sin(2 * t)]
    >>> ex = Structure([Branch(trunk, 3.0)], image_shape=(200, 260))
    >>> res = synthesize_structure(ex, rng=1)
    >>> res.structure.n_vertices > 20
    True

    Watching it grow: every partial skeleton is a part of the final one.

    >>> seen = []
    >>> res = synthesize_structure(ex, rng=1, progress=lambda g: seen.append(g.structure().n_vertices))
    >>> seen[-1] == res.structure.n_vertices and seen[0] < seen[-1]
    True
    """
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable or None, got {type(progress).__name__}")
    t0 = time.perf_counter()
    model, p = _resolve(example, params)
    rng = as_rng(rng)
    shp = _domain(model, shape)
    guidance = _check_guidance(guidance, shp)
    dom = _check_domain(domain, model, shp)
    if starts is None:
        if guidance is not None or p.roots != "learned":
            starts = _default_starts(model, shp, guidance, p, dom, rng)
        else:
            # drawn again at every attempt (a root that walked out gets a new start)
            def starts(r):
                return _default_starts(model, shp, None, p, dom, r)
    else:
        st = np.asarray(starts, np.float64)
        if st.ndim != 2 or st.shape[1] != 3 or not np.all(np.isfinite(st)):
            raise ValueError("starts must be a sequence of finite (x, y, angle) triples")
        h, w = shp
        bad = (st[:, 0] < -0.5) | (st[:, 0] > w - 0.5) | (st[:, 1] < -0.5) | (st[:, 1] > h - 0.5)
        if bad.any():
            raise ValueError(f"starts[{int(np.flatnonzero(bad)[0])}] lies outside the {w} x {h} domain")
        starts = [tuple(map(float, s)) for s in st]
    g = _grow_with_retries(model, p, rng, shp, guidance, starts, _scorer, dom, progress)
    g.report(done=True)
    s = _lift_child_heads(g.structure())
    diag = g.diagnostics(t0)
    diag["attempts"] = g.attempt
    if s.branches and s.angles().size:
        diag["hist_distance"] = histogram_distances(model.example, s, bins=p.bins)
    dens = g.density.image() if g.density is not None else None
    return SynthesisResult(structure=s, example=model.example, diagnostics=diag, density=dens, domain=g.domain,
                           sources=g.sources())


@checked(index=Int(0), n_steps=Int(1, 100_000), shape=Shape())
def extend_branch(structure: Structure, index: int, example, params: SynthesisParams | None = None,
                  *, n_steps: int | None = None, rng=None, guidance=None,
                  shape=None) -> SynthesisResult:
    """Grow one branch of an existing structure further with the learnt model.

    The branch's last elements are its history; all other branches count
    for space colonization and the histograms. Children keep their
    furcation vertices (vertices are only appended).

    Parameters
    ----------
    structure : Structure
        The structure to extend (e.g. a synthesis result).
    index : int
        The branch to extend; it needs at least 3 vertices.
    example : Structure or StructureModel
        What to learn from.
    params : SynthesisParams, optional
        Synthesis parameters; None = the defaults. A model fitted with
        another ``h``, ``m``, ``k``, ``bins`` or ``svm_C`` is fitted again.
    n_steps : int, optional
        Number of Markov steps (``m`` vertices each); until the branch
        stops by default.
    rng : int or numpy.random.Generator, optional
        Seed: the same seed gives the same extension.
    guidance : Guidance or (H, W) array_like, optional
        Guidance map ``G`` (see :mod:`~branchnb.branching.guidance`).
    shape : (H, W), optional
        Domain size (default: ``structure.image_shape``, else the
        example's).

    Returns
    -------
    SynthesisResult
        The whole structure with the branch extended;
        ``diagnostics["added_vertices"]`` counts the new vertices.

    Raises
    ------
    ValueError
        If ``structure`` is empty, ``index`` is out of range, the branch
        has fewer than 3 vertices or ``n_steps`` is not a positive int.
    """
    t0 = time.perf_counter()
    if not isinstance(structure, Structure):
        raise TypeError(f"structure must be a Structure, got {type(structure).__name__}")
    if not structure.branches:
        raise ValueError("structure is empty")
    if not isinstance(index, (int, np.integer)) or not 0 <= index < len(structure.branches):
        raise ValueError(f"index must be a branch index in [0, {len(structure.branches)}), got {index!r}")
    if n_steps is not None and (not isinstance(n_steps, (int, np.integer)) or n_steps < 1):
        raise ValueError(f"n_steps must be a positive int or None, got {n_steps!r}")
    b = structure.branches[index]
    if len(b.points) < 3:
        raise ValueError(f"branch {index} has {len(b.points)} vertices; extending needs >= 3 for a history")
    model, p = _resolve(example, params)
    rng = as_rng(rng)
    shp = tuple(structure.image_shape) if shape is None and structure.image_shape else _domain(model, shape)
    guidance = _check_guidance(guidance, shp)
    g = _Grower(model, p, rng, shp, guidance, domain=_check_domain(None, model, shp))
    g.add_existing(structure)
    if p.max_coverage <= 0:
        # extending is an explicit request: the automatic coverage target does not stop it
        g.coverage_target = 1.0
    for i, br in enumerate(structure.branches):
        ea, er = branch_elements(br.points, br.thickness)
        d = br.points[-1] - br.points[-2] if len(br.points) > 1 else np.array([1.0, 0.0])
        g.branches.append(_BranchState(points=list(br.points), radii=list(br.thickness),
                                       elem_a=list(ea), elem_r=list(er),
                                       theta=float(np.arctan2(d[1], d[0])), parent=br.parent,
                                       parent_vertex=br.parent_vertex,
                                       generation=structure.generation(i), stop="existing"))
    g.branches[index].stop = ""
    g.max_branch_len = np.inf
    g.grow(index, n_steps)
    if not g.stop_reason:
        g.stop_reason = g.branches[index].stop or "n_steps"
    s = g.structure()
    diag = g.diagnostics(t0)
    diag["added_vertices"] = len(s.branches[index].points) - len(b.points)
    dens = g.density.image() if g.density is not None else None
    return SynthesisResult(structure=s, example=model.example, diagnostics=diag, density=dens, domain=g.domain,
                           sources=g.sources())


def replace_params(params: SynthesisParams, **changes) -> SynthesisParams:
    """``dataclasses.replace`` plus validation.

    Parameters
    ----------
    params : SynthesisParams
        The parameters to start from (unchanged).
    **changes
        Fields to replace.

    Returns
    -------
    SynthesisParams
        A checked copy with the changes.

    Raises
    ------
    ValueError
        If a changed value is out of its field's range.

    Examples
    --------
    >>> replace_params(SynthesisParams(), c=3).c
    3
    """
    return check_params(dataclasses.replace(params, **changes))
