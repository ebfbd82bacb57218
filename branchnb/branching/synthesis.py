"""Structure synthesis: grow a new branching structure like an example.

Putting the paper's models together (see the modules of the same names):

1. strands cut where another passes over them (over-and-under line art)
   are joined again (:mod:`.strands`, beyond the paper), the example is
   resampled at step ``h`` and learnt: the bending model's
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
   often per length as the example's), where the bends fall too (a hazard
   over the length of the straight run so far, ``StraightRuns``: the Markov
   chain remembers ``k + 1`` elements, a drawn map's straight pieces are
   longer), and a river leaving a coast may not
   curl back over the first ``MOUTH_SHARE`` of its length (a hook at its
   mouth); no branch winds further than its example's most winding one
   allows (``growth.winding_limit``, never a full turn: no spirals);
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
   filled last, past the coverage target: children are grown into the
   largest remaining hole one after another until the holes are as rare
   as the example's (``_Grower._fill_far``, also in a free frame), then
   branches beside the holes left furcate once more toward them
   (``_Grower._fill_holes``). The total length stops at the example's
   length per domain area x 1.15 (``growth.length_cap``; the paper's fixed
   cap stopped 1000 px examples short), x 1.3 while holes are filled. A delta's channels run on to the
   sea; channels blocked inland are dropped (``_Grower._prune_dry``); in a
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
from ..core.random import as_rng
from ..core.structure import Branch, Structure
from ..core.validate import Array, Int, Shape, checked
from .bending import branch_elements
from .domains import (  # noqa: F401  (re-exported: split from this module)
    DRAIN_KAPPA,
    MOUTH_SHARE,
    MOUTH_TURN,
    SHORE_QUANTILE,
    SHORE_SKIP,
    UPSTREAM_COS,
    _Drain,
    _drains,
    _frame,
    _Shore,
    _shore_margin,
    _shore_margin_of,
)
from .filling import HOLE_DISTANCE, _hole_map  # noqa: F401
from .growth import FILL_LENGTH_FACTOR, GrowthProgress, _BranchState, _Grower, example_length, length_cap
from .guidance import Guidance
from .histogram_matching import _distances, histogram_distances
from .model import _FIT_FIELDS, StructureModel, _check_example, fit_model  # noqa: F401
from .params import SynthesisParams
from .scoring import (  # noqa: F401
    _DIRECTION_BINS,
    CandidateScores,
    _Base,
    _base_scores,
    _continue_radii,
    _rank_key,
    _rotate,
    score_candidates,
)

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
# Public entry points
# --------------------------------------------------------------------------
def _resolve(example, params) -> tuple[StructureModel, SynthesisParams]:
    p = check_params(params if params is not None else SynthesisParams())
    if isinstance(example, StructureModel):
        model = example if example.compatible(p) else fit_model(example.source, p, domain=example.domain)
    else:
        model = fit_model(_check_example(example), p)
    if model.requested_h is not None and p.h == model.requested_h:
        # a small example was fitted at a finer step: synthesis walks at the step the models know
        p = dataclasses.replace(p, h=model.params.h)
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
        from .growth import _core

        core = _core(model, dom)
        if core is not None:   # a band's strands start where the example's run (beyond the paper, issue 23)
            return _in_core(model.roots.sample(dom, rng, n), core[1])
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


def _in_core(starts, dist: np.ndarray) -> list[tuple[float, float, float]]:
    """Root ``starts`` of a band's strands moved to the nearest pixel of the band's core (``dist``: the
    distance outside it, :func:`.growth._core`; beyond the paper, issue 23, branching66).

    A strand root is drawn on the band domain's boundary at the example root's depth, but that domain
    reaches a strand spacing past the strands: 2 of 2 seeds of a 256 px L band started their root
    beside the band and ran the whole strand along its inner edge.
    """
    from scipy import ndimage as ndi

    h, w = dist.shape
    _d, (iy, ix) = ndi.distance_transform_edt(dist > 0, return_indices=True)
    out = []
    for x, y, a in starts:
        yi, xi = int(np.clip(round(y), 0, h - 1)), int(np.clip(round(x), 0, w - 1))
        out.append((float(ix[yi, xi]), float(iy[yi, xi]), a))
    return out


def _radial_starts(model: StructureModel, starts, shape, domain, hubs: list):
    """``starts`` (a list or a function of the attempt's rng) with every root start made a hub of
    several primaries when the example has hubs (:func:`.radial._hub_starts`; the hubs of each
    attempt appended to ``hubs``); ``starts`` itself otherwise (no rng drawn: output unchanged)."""
    from .radial import _hub_model, _hub_starts, _HubStarts

    hm = _hub_model(model)
    if hm is None:
        return starts
    src = model.source.image_shape
    scale = 1.0 if src is None else 0.5 * (shape[0] / src[0] + shape[1] / src[1])
    dom = None if domain is None else np.asarray(domain, bool)

    def radial(r):
        base = starts(r) if callable(starts) else starts
        new, hh = _hub_starts(hm, base, scale, shape, r, dom)
        hubs.append(hh)
        out = _HubStarts(new)
        out.hubs, out.scale = hh, scale
        return out

    if callable(starts):
        return radial
    out = radial(np.random.default_rng(len(starts)))
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
                       progress=None, region=None) -> _Grower:
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
    reg = domain if region is None else region
    if reg is not None and model.region is not None:
        area_ratio = float(np.count_nonzero(reg)) / max(float(np.count_nonzero(model.region)), 1.0)
    min_total = 0.0
    if starts is None or callable(starts):
        min_total = min(0.25 * example_length(model) * area_ratio,
                        0.5 * length_cap(model, p, shp, reg))
    # A guided root follows the user's path, out of the domain if the path goes there.
    attempts = 1 if guidance is not None else MAX_ROOT_ATTEMPTS
    best = None
    for attempt in range(1, attempts + 1):
        g = _Grower(model, p, rng, shp, guidance, scorer=scorer, domain=domain, region=region)
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
    # on the kept attempt only. Targeted growth into the largest holes first: furcating beside every
    # hole first (``_fill_holes``) spent 0.25 x the example's length (retina 512: 1.4 x its length per
    # area, against 1.24-1.29 x this way round, with far shares 0.81-0.93 x against 0.72-1.41 x)
    best._drop_unborn()   # heads queued when the growth stopped, their length grown on elsewhere
    auto = p.max_total_length <= 0
    cut = auto and best.stop_reason == "total length"
    if auto and not best.radial:   # (a hub's forest keeps its length, .radial._hub_budget)
        # holes the example does not have may still be filled past the auto cap, up to
        # FILL_LENGTH_FACTOR x the example's length per area
        best.max_total = length_cap(model, p, shp, reg, factor=FILL_LENGTH_FACTOR)
    if cut:
        best.stop_reason = ""
    best._fill_far()
    best._fill_holes()
    best._more_strands(starts)
    if cut and not best.stop_reason:
        best.stop_reason = "total length"
    best._drop_unborn(resume=False)
    best._prune_dry()
    return best


def _resized(d: np.ndarray, shape) -> np.ndarray:
    import cv2

    if d.shape != tuple(shape):
        d = cv2.resize(d.astype(np.uint8), (shape[1], shape[0]), interpolation=cv2.INTER_NEAREST) > 0
    return d


def _region(domain, model: StructureModel, shape):
    """The model's domain with its ground (``StructureModel.region``) at ``shape``, when synthesis grows
    in the model's own domain (``domain`` not given) and it has ground; else None (the domain itself)."""
    if domain is not None or model.ground is None or model.domain is None:
        return None
    reg = model.region
    return np.ones(tuple(shape), bool) if reg is None else _resized(reg, shape)


def _check_domain(domain, model: StructureModel, shape):
    from ..core.image import as_mask

    if domain is None:
        if model.domain is None:
            return None
        return _resized(model.domain, shape)
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
        coordinates); when the example has hubs (:mod:`.radial`), each start is
        a hub's centre with primaries all round it. Default (``params.roots = "learned"``): ``n_roots``
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
    hubs: list = []
    if guidance is None:   # the user's starts too: each the centre of a hub when the example has hubs
        starts = _radial_starts(model, starts, shp, dom, hubs)
    reg = _region(domain, model, shp)
    g = _grow_with_retries(model, p, rng, shp, guidance, starts, _scorer, dom, progress, reg)
    g.report(done=True)
    s = _lift_child_heads(g.structure())
    if hubs:   # the hubs of the attempt kept (one list per attempt drawn)
        s.hubs = list(hubs[min(g.attempt, len(hubs)) - 1])
    diag = g.diagnostics(t0)
    diag["attempts"] = g.attempt
    sa = s.angles() if s.branches else np.zeros(0)
    if sa.size:   # histogram_distances(model.example, s), the example's values read once per model
        ex = model.__dict__.get("_example_values")
        if ex is None or ex[0] is not model.example:
            ex = model.__dict__["_example_values"] = (model.example, model.example.angles(),
                                                     model.example.thicknesses())
        diag["hist_distance"] = _distances(ex[1], ex[2], sa, s.thicknesses(), bins=p.bins)
    dens = g.density.image() if g.density is not None else None
    # the output's regions (synthesize_image) follow the region: a line mask's empty ground is no sea
    return SynthesisResult(structure=s, example=model.example, diagnostics=diag, density=dens,
                           domain=g.domain if reg is None else reg, sources=g.sources())


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
    g = _Grower(model, p, rng, shp, guidance, domain=_check_domain(None, model, shp),
                region=_region(None, model, shp))
    g.add_existing(structure)
    if p.max_total_length <= 0:
        # the auto cap counts what is added (a long structure is not stopped at once)
        g.max_total += g.total_length
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
