"""Dendritic stylization of an image: the whole pipeline of the paper.

1. importance map ``I`` of the image (darkness + 3 x gradient);
2. lattice weights ``w = c (1 - I) + epsilon + noise * U``: important
   pixels are cheap, so the structure grows along dark regions and edges;
3. Dijkstra from the seed with the chosen metric;
4. endpoints stippled on ``I`` (none where ``I`` is below a threshold:
   flat paper stays clean);
5. paths traced back from the endpoints into one dendrite;
6. thickness from the rolling importance along the branches, then
   rescaled so the local ink follows the image's darkness (``tone``);
7. rendering with a metaphor (plain lines, vines or lightning).

Before the stages run, the parameters are adapted to the image's size
(:func:`effective_params`: no stroke thinner than a pixel, fewer endpoints
on small images) and to the metaphor (:func:`metaphor_params`: vines and
lightning set their own endpoint counts and widths); both live in
:mod:`~branchnb.dendrite.stylize_params`.

:class:`Stylizer` caches every stage keyed by the parameters it depends
on, so changing only rendering or thickness parameters does not re-plan
and changing the metric does not re-stipple: sliders stay live.

By step: the working image, its scale and the seed are in
:mod:`~branchnb.dendrite.stylize_seed`, the lightning metaphor's main
channel and strike in :mod:`~branchnb.dendrite.stylize_strike`
(:class:`Stylizer` inherits their methods), vines on an object found on a dark or
textured ground in :mod:`~branchnb.dendrite.stylize_object`; the parameters in
:mod:`~branchnb.dendrite.stylize_params`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage

from ..core.image import as_float_image, as_points, as_rgb
from ..core.io import encode_png
from ..core.params import check_params
from ..core.random import as_seed
from ..core.validate import Int, Point, checked
from .dendrite import Dendrite, build_dendrite
from .endpoints import place_endpoints
from .foreground import PaperGround, _on_paper, _paper_ground
from .importance import ImportanceParams, _to_paper_white, darkness, gradient_strength, importance_map
from .lattice import Lattice, node_weights
from .main_channel import (
    widen_main_path,
)
from .planner import PlanResult, plan
from .render import Rendering
from .strike_outline import thin_on_ground
from .stylize_object import _ObjectSteps
from .stylize_params import (  # noqa: F401  (re-exported; the spacings too)
    LIGHTNING_LOOP_REACH,
    LIGHTNING_MAIN_EXPONENT,
    LIGHTNING_SEED_BLUR,
    LIGHTNING_SEED_DENSITY,
    LIGHTNING_SPACING,
    STRIKE_BAND,
    STRIKE_EDGE_NOISE,
    STRIKE_GLOW,
    STRIKE_MAIN_EXPONENT,
    STRIKE_MAX_COVER,
    STRIKE_MIN_PIECE,
    STRIKE_PENALTY,
    STRIKE_PHOTO_SIDE,
    STRIKE_PHOTO_UP,
    STRIKE_SIDE,
    VINE_MIN_LEAF,
    VINE_SPACING,
    StylizeParams,
    _ground_threshold,
    _spacing_growth,
    _vine_sizes,
    _within_range,
    effective_params,
    metaphor_params,
    on_lattice,
)
from .stylize_seed import _ENDPOINTS, _IMPORTANCE, _LATTICE, _PLAN, _PRUNE_ROUNDS, _SeedSteps, _subset
from .stylize_strike import _StrikeSteps
from .thickness import (
    _tone_fit,
    branch_thickness,
    importance_thickness,
    rolling_importance,
    twigs_within_ink,
)
from .ties import refine_ties

__all__ = ["effective_params", "metaphor_params", "Stylization", "StylizeParams", "Stylizer", "stylize"]

#: Darkness a drawn line stands above its surroundings to count fully as a line
#: (:meth:`Stylizer._line_share`).
LINE_CONTRAST = 0.3
#: How far past the object (as a share of a leaf's length) the vines' leaves may reach
#: (:meth:`Stylizer._vine_within`).
VINE_LEAF_MARGIN = 0.25


@dataclass
class Stylization:
    """Everything the stylization computed.

    ``importance``, ``lattice`` and ``plan`` live on the planning lattice;
    ``endpoints``, ``seed``, ``dendrite`` and ``rendering`` are in image
    pixels (``dendrite.nodes`` still index the lattice).

    Parameters
    ----------
    image : (H, W, 3) float32 ndarray
        The input image (RGB, at its own size).
    importance : (h, w) float32 ndarray
        Importance ``I`` on the planning lattice.
    lattice : Lattice
        The weighted lattice ``w = c (1 - I) + epsilon + noise U``.
    plan : PlanResult
        The planner's result from the seed.
    endpoints : (E, 2) float64 ndarray
        Stippled endpoints ``(x, y)`` in image pixels.
    dendrite : Dendrite
        The traced dendrite with its widths, in image coordinates.
    rendering : Rendering or None
        The metaphor's drawing (None when ``metaphor=None``).
    params : StylizeParams
        The parameters used: the ones given, adapted to the image's size by
        :func:`effective_params`.
    seed : (2,) float64 ndarray
        Start ``(x, y)`` of the dendrite in image pixels.
    scale : (2,) float64
        Image pixels per lattice pixel in x and y.

    Examples
    --------
    >>> img = np.ones((40, 40)); img[10:30, 10:30] = 0.0
    >>> out = stylize(img, StylizeParams(n_endpoints=30, lattice_size=20), rng=0)
    >>> out.importance.shape, out.dendrite.shape, out.scale.tolist()
    ((20, 20), (40, 40), [2.0, 2.0])
    """

    image: np.ndarray
    importance: np.ndarray
    lattice: Lattice
    plan: PlanResult
    endpoints: np.ndarray
    dendrite: Dendrite
    rendering: Rendering | None
    params: StylizeParams
    seed: np.ndarray
    scale: np.ndarray = dataclasses.field(default_factory=lambda: np.ones(2))

    def _repr_png_(self) -> bytes:
        if self.rendering is not None:
            return encode_png(self.rendering.image)
        return encode_png(self.dendrite.render())


#: Long side (pixels) of the copy a picture's paper ground is judged on.
PAPER_GROUND_SIZE = 256
#: Ink of the plain metaphor on a dark ground (scratchboard white).
SCRATCH_INK = (0.97, 0.96, 0.92)


class Stylizer(_SeedSteps, _StrikeSteps, _ObjectSteps):
    """The stylization pipeline on one image, with each stage cached.

    Parameters
    ----------
    image : array_like
        Grey or colour image in [0, 1] (alpha ignored); stored as RGB
        float32.

    Examples
    --------
    >>> img = np.ones((48, 48)); img[12:36, 12:36] = 0.0
    >>> st = Stylizer(img)
    >>> out = st.run(StylizeParams(n_endpoints=2000), rng=0)
    >>> out.params.n_endpoints  # a 48-px image: fewer endpoints (effective_params)
    104
    >>> out.dendrite.is_tree(), len(out.dendrite.tips) > 20
    (True, True)
    """

    def __init__(self, image):
        self.image = as_rgb(as_float_image(image, name="image"), name="image")
        self._cache: dict = {}

    @property
    def shape(self) -> tuple[int, int]:
        return self.image.shape[:2]

    #: Cached results kept per stage (e.g. both metrics of a side-by-side view).
    cache_size = 3

    def _get(self, key, fn):
        if key in self._cache:
            self._cache[key] = self._cache.pop(key)  # most recently used last
            return self._cache[key]
        same = [k for k in self._cache if k[0] == key[0]]
        for k in same[: max(0, len(same) - self.cache_size + 1)]:
            del self._cache[k]
        self._cache[key] = value = fn()
        return value


    @checked()
    def importance(self, p: StylizeParams) -> np.ndarray:
        """Importance map on the lattice.

        Parameters
        ----------
        p : StylizeParams
            Uses ``lattice_size``, ``intensity_weight``, ``gradient_weight`` and
            ``sigma``.

        Returns
        -------
        (h, w) float32 ndarray
            ``I`` in [0, 1] (:func:`~branchnb.dendrite.importance.importance_map`), cached.
        """
        # sigma is in pixels of the lattice_size lattice (a small picture's is smaller)
        return self._get(("importance", _subset(p, _IMPORTANCE)), lambda: importance_map(
            self.working_image(p), ImportanceParams(p.intensity_weight, p.gradient_weight,
                                                    p.sigma * self.lattice_factor(p))))

    @checked()
    def edge_map(self, p: StylizeParams) -> np.ndarray:
        """The gradient strength ``G`` in [0, 1] on the lattice (the edge part of the importance).

        Parameters
        ----------
        p : StylizeParams
            Uses ``lattice_size`` and ``sigma``.

        Returns
        -------
        (h, w) float32 ndarray
        """
        return self._get(("edges", p.lattice_size, p.sigma), lambda: gradient_strength(
            self.working_image(p), sigma=p.sigma * self.lattice_factor(p)))

    def _paper_image(self, p: StylizeParams) -> np.ndarray:
        # the working image with its lightest tone as paper (importance._to_paper_white): the
        # tone match sees a low-key picture's object apart from its ground. Only the tone
        # target: the importance (stippling, lightning's strike search) keeps the picture's own
        # luminance, levelled it sent bolts off the camera man's and a crack picture's edges
        return self._get(("paper", p.lattice_size), lambda: _to_paper_white(self.working_image(p)))

    @checked()
    def darkness(self, p: StylizeParams) -> np.ndarray:
        """The tone target ``1 - luminance`` on the lattice, the picture's lightest tone as
        paper (beyond the paper: a low-key picture's ground no longer takes the object's ink).

        Parameters
        ----------
        p : StylizeParams
            Uses ``lattice_size``.

        Returns
        -------
        (h, w) float32 ndarray
        """
        return self._get(("darkness", p.lattice_size), lambda: darkness(self._paper_image(p)))

    @checked(rng_seed=Int(0))
    def lattice(self, p: StylizeParams, rng_seed: int) -> Lattice:
        """The weighted lattice ``w = c (1 - I) + epsilon + noise U`` (cached).

        Parameters
        ----------
        p : StylizeParams
            Uses the importance fields, ``cost_weight``, ``epsilon`` and ``noise``.
        rng_seed : int
            Seed (>= 0) of the noise ``U``.

        Returns
        -------
        Lattice
        """
        def make():
            imp = self.importance(p)
            w = node_weights(p.cost_weight * (1.0 - imp.astype(np.float64)),
                             epsilon=p.epsilon, noise=p.noise, rng=rng_seed)
            return Lattice(w)
        return self._get(("lattice", _subset(p, _IMPORTANCE + _LATTICE), rng_seed), make)

    @checked(seed=Point(), rng_seed=Int(0))
    def plan(self, p: StylizeParams, seed, rng_seed: int) -> PlanResult:
        """Dijkstra from ``seed`` on :meth:`lattice` with ``p.metric`` (cached).

        Parameters
        ----------
        p : StylizeParams
            Uses the lattice fields, ``metric``, ``blend_weight`` and
            ``break_ties`` (large non-scalar ties re-planned).
        seed : (x, y)
            Start point in *lattice* pixels (:meth:`to_lattice`).
        rng_seed : int
            Seed (>= 0) of the lattice noise.

        Returns
        -------
        PlanResult
        """
        seed = tuple(np.round(np.asarray(seed, float), 3))
        return self._get(
            ("plan", _subset(p, _IMPORTANCE + _LATTICE + _PLAN), seed, rng_seed),
            lambda: self._plan(p, seed, rng_seed))

    def _plan(self, p: StylizeParams, seed, rng_seed: int) -> PlanResult:
        return self._plan_on(self.lattice(p, rng_seed), p, seed)

    @staticmethod
    def _plan_on(lat: Lattice, p: StylizeParams, seed) -> PlanResult:
        res = plan(lat, seed, metric=p.metric, blend_weight=p.blend_weight)
        if p.metric == "nonscalar" and p.break_ties:
            res = refine_ties(lat, res)
        return res

    @checked(rng_seed=Int(0))
    def endpoints(self, p: StylizeParams, rng_seed: int) -> np.ndarray:
        """Endpoints stippled on the importance (cached).

        A blank image (nothing at or above the threshold) gets evenly spread
        endpoints instead.

        Parameters
        ----------
        p : StylizeParams
            Uses the importance fields, ``n_endpoints``, ``endpoint_gamma``,
            ``endpoint_threshold``, ``endpoint_floor`` and ``stipple_iterations``.
        rng_seed : int
            Seed (>= 0); the stippling uses ``rng_seed + 1``.

        Returns
        -------
        (n_endpoints, 2) float64 ndarray
            ``(x, y)`` in lattice pixels.
        """
        def make():
            imp = self.importance(p)
            floor, threshold = p.endpoint_floor, p.endpoint_threshold
            if floor <= 0 and not (imp >= threshold).any() or not (imp > 0).any():
                floor, threshold = 1.0, 0.0  # nothing important (a blank image): spread evenly
            return place_endpoints(imp, p.n_endpoints, gamma=p.endpoint_gamma, floor=floor,
                                   threshold=threshold, iterations=p.stipple_iterations,
                                   rng=rng_seed + 1)
        return self._get(("endpoints", _subset(p, _IMPORTANCE + _ENDPOINTS), rng_seed), make)

    @checked(seed=Point(), rng_seed=Int(0))
    def dendrite(self, p: StylizeParams, seed, rng_seed: int) -> Dendrite:
        """The endpoints traced back into one dendrite, before thickness (cached).

        Parameters
        ----------
        p : StylizeParams
            Parameters of every stage up to the endpoints.
        seed : (x, y)
            Start point in lattice pixels.
        rng_seed : int
            Seed (>= 0) of the lattice noise and the stippling.

        Returns
        -------
        Dendrite
            On the lattice, every radius 1.
        """
        seed_key = tuple(np.round(np.asarray(seed, float), 3))
        key = ("dendrite", _subset(p, _IMPORTANCE + _LATTICE + _PLAN + _ENDPOINTS),
               seed_key, rng_seed)
        return self._get(key, lambda: build_dendrite(self.plan(p, seed, rng_seed),
                                                     self.endpoints(p, rng_seed)))

    def _widths(self, d: Dendrite, p: StylizeParams, lo: float, hi: float) -> Dendrite:
        """The widths of ``d`` (lattice px, within ``[lo, hi]``) by ``p.thickness``;
        ``self._pinned`` marks the nodes held at ``lo`` after the tone match."""
        if p.thickness != "importance":
            d = branch_thickness(d, mode=p.thickness, min_width=lo, max_width=hi)
            self._pinned = d.radius <= 0.5 * lo * 1.001
            return d
        imp = self.importance(p)
        ref = max(float(np.percentile(imp, 99.0)), 1e-3)
        d = importance_thickness(d, imp, window=p.window, min_width=lo, max_width=hi,
                                 contrast=p.contrast, reference=ref)
        if p.hierarchy > 0:
            r = d.radius * np.maximum(d.leaf_count(), 1.0) ** p.hierarchy
            d = d.with_radius(np.clip(r, lo / 2, hi / 2))
        if p.tone > 0:
            # the target at the 512-px picture's blur (thickness._tone_fit)
            grow = self._growth(p)
            keep = self._line_share(p, d.nodes, filled=True) if grow > 1.0 else None
            d = _tone_fit(d, self.darkness(p), p.tone_sigma, lo, hi, p.tone, 0.7, 4,
                          target_sigma=p.tone_sigma / grow if keep is not None else None,
                          keep=keep)
        # nodes the floor holds wider than the tone asks (before the edges' extra width)
        self._pinned = d.radius <= 0.5 * lo * 1.001
        if p.edges > 0:
            # the tone match spreads ink evenly over a region; the outline and the
            # veins of a drawing should still read as its strongest lines
            e = np.clip(rolling_importance(d, self.edge_map(p), p.window), 0.0, 1.0)
            gain = self._edge_gain(p)
            if gain < 1.0:  # a drawn line round a fill keeps its whole boost (_line_share)
                gain = gain + (1.0 - gain) * self._line_share(p, d.nodes, filled=True)
            d = d.with_radius(np.clip(d.radius * (1.0 + p.edges * gain * e ** 2),
                                      lo / 2, hi / 2))
        return d

    def _edge_gain(self, p: StylizeParams) -> float:
        """The share of ``p.edges`` an edge gets: 1, or on an image smaller than the lattice
        ``1 / _spacing_growth`` (beyond the paper). There fewer endpoints space the texture
        wider and the tone match widens its strokes by as much; an outline keeps its length,
        so the extra width ``edges`` gives it, grown with the texture's, made the outline
        the heaviest line of a small input (ink of an 8-px band inside the outline over the
        interior's at one display size, mid-grey blob 250 px 1.31 against 1.12 at 750 px).
        Scaled back, the outline's extra ink per unit of its length is the 512-px drawing's
        (``python -m branchnb.dendrite._small_check``). A drawn line keeps its whole boost
        (:meth:`_line_share`)."""
        return 1.0 / self._growth(p)

    def _line_share(self, p: StylizeParams, nodes, filled: bool = False) -> np.ndarray:
        """How much of a drawn line each node lies on, in [0, 1]: the darkness standing
        above its opening by a disk of half the 512-px tone blur (a line thinner than the
        branch spacing), over ``LINE_CONTRAST`` (beyond the paper).

        On a small input the tone match's wider blur spread a drawn outline's darkness
        over the fill, and the outline's edge boost was scaled back for a step between
        regions (:meth:`_edge_gain`): a light fill in a dark outline at 250 px had an
        outline band 1.6-1.75x as inked as its interior against 2.2x at 750 px. On a
        line round a fill (``filled``: the darkness under the opening at least
        ``LINE_CONTRAST``) both keep the 512-px picture's (on every line, a thin outline
        on white, sharper than its wider ink blur, got 1.17x the ink of the same star at
        750 px against 0.95x): 250 against 750 px, that ratio 0.81 / 0.72 ->
        0.96 / 0.87 (two seeds); a mid-grey, outlined, dark or gradient fill stays within
        0.05 of its former 0.95-1.04, the maple photo 0.91 -> 0.92
        (``python -m branchnb.dendrite._small_check``).
        """
        def make():
            dark = self.darkness(p).astype(np.float32)
            r = max(1, int(round(0.5 * p.tone_sigma / self._growth(p))))
            disk = np.hypot(*np.mgrid[-r:r + 1, -r:r + 1]) <= r
            opened = ndimage.grey_opening(dark, footprint=disk)
            line = np.clip((dark - opened) / LINE_CONTRAST, 0.0, 1.0)
            return line, line * np.clip(opened / LINE_CONTRAST, 0.0, 1.0)
        maps = self._get(("line_share", p.lattice_size, p.tone_sigma, p.output_width), make)
        return maps[int(filled)].ravel()[np.asarray(nodes, np.int64)]

    def _growth(self, p: StylizeParams) -> float:
        if p.output_width <= 0:  # the size adaptation is off (effective_params)
            return 1.0
        return _spacing_growth(self.size_scale(p))

    def _vine_sizes(self, p: StylizeParams, given: StylizeParams, obj, content, share: float,
                    k: float, options: dict) -> dict:
        """The vines' render options with leaf lengths sized to the object, and (in
        ``self._vine_p``) ``p`` with its tip count following the object's outline
        (:func:`~branchnb.dendrite.stylize_params._vine_sizes`); lengths the caller gave
        are kept."""
        from .main_channel import silhouette
        from .metaphors import VINE_MIN_PIXELS, _vine_smooth, vine_length

        area = share * self.shape[0] * self.shape[1]
        f, _ = _vine_sizes(self.shape, area, 0.0)
        # the outline at the stems' spacing: a textured ground's specks that pass the
        # threshold have outlines of their own (a cat on a dark ground got 700 tips)
        leaf = vine_length("leaf_length", self.shape) * f
        sil = ndimage.gaussian_filter(silhouette(obj if obj is not None else content)
                                      .astype(np.float32), 0.5 * VINE_SPACING * leaf / k) > 0.5
        pieces, count = ndimage.label(sil)
        if count:
            sizes = np.bincount(pieces.ravel())[1:]
            sil = np.isin(pieces, 1 + np.flatnonzero(sizes >= 0.1 * sizes.sum()))
        outline = float((sil & ~ndimage.binary_erosion(sil)).sum()) * k
        f, n = _vine_sizes(self.shape, area, outline)
        # the stems thin with the leaves (at least 1.8 image px, as metaphor_params has it)
        hi = max(p.max_width * min(f, 1.0), 1.8 / k, p.min_width)
        self._vine_p = _within_range(p, n_endpoints=int(np.clip(n, min(8, given.n_endpoints),
                                                                 given.n_endpoints)),
                                     max_width=hi if f < 1.0 else p.max_width)
        # every length follows the leaf's; their floors keep the leaf's floor's proportions
        floor = VINE_MIN_LEAF / VINE_MIN_PIXELS["leaf_length"]
        self._vine_leaf = vine_length("leaf_length", self.shape) * f
        options = dict(options)
        for name in ("curl_length", "leaf_spacing", "leaf_length", "leaf_width"):
            if options.get(name) is None:
                options[name] = max(vine_length(name, self.shape) * f, VINE_MIN_PIXELS[name] * floor)
        if options.get("smooth") is None:
            # the stems are paths on the lattice: smoothed over as many of its nodes at every
            # image size (by the image's diagonal a 300-px picture's vines were jagged steps
            # and a 700-px one's soft curves)
            options["smooth"] = _vine_smooth(None, self.working_image(p).shape[:2])
        return options

    def _vine_within(self, obj, leaf: float) -> np.ndarray:
        """Where the vines' leaves may lie: the object (or the content's silhouette; a lattice
        mask) at the image's size,
        grown by ``VINE_LEAF_MARGIN`` of a leaf's length (the stems hug its outline from
        either side).

        Beyond the paper: leaves grown to the object's size on its outline hung past it at
        1000 px (half of them on the outside of the stem).
        """
        import cv2

        m = cv2.resize(np.asarray(obj, np.uint8), self.shape[::-1], interpolation=cv2.INTER_NEAREST) > 0
        return ndimage.distance_transform_edt(~m) <= max(2.0, VINE_LEAF_MARGIN * leaf)

    def _metaphor_setup(self, p: StylizeParams, metaphor, render_options: dict, with_options: bool = True):
        """:meth:`run`'s parameters for the image size and the metaphor: ``(given, p, k, obj,
        render_options)`` (``obj`` the vines' object or None); ``with_options=False`` skips the
        vines' render-only outline band."""
        # the size adaptation reads the scale against the lattice_size lattice, and the lengths
        # it returns are then put on the (smaller) lattice a small picture is planned on
        k, f = self.size_scale(p), self.lattice_factor(p)
        k_lat = k / f  # image px per planning-lattice px
        given, p = p, on_lattice(effective_params(p, k), f)
        obj = None
        if metaphor in ("vines", "lightning"):
            # the metaphors size their own strokes from the given parameters
            # vines: the object is what stands out from the picture's own ground (on a
            # grey wall or a dark textured ground the whole frame passed the threshold);
            # its tips are stippled there too
            imp = self.importance(p)
            thr = (_ground_threshold(imp, p.endpoint_threshold) if metaphor == "vines"
                   else p.endpoint_threshold)
            share = float((imp >= thr).mean())
            if metaphor == "lightning":  # an object found on its ground: tips for its area
                content, found = self._lightning_content(p)
                share = _strike_share(content) if found else share
            else:  # vines on an object lighter than its ground, or the ground textured
                obj = self._vine_object(p)
                obj = obj if obj is not None else self._vine_parts(p)
                share = float(obj.mean()) if obj is not None else share
            # the metaphors' widths are image pixels over the planning lattice's scale
            p = on_lattice(metaphor_params(given, metaphor, self.shape, share, k_lat), f, widths=False)
            if metaphor == "vines":  # leaves sized to the object, tips along its outline
                render_options = self._vine_sizes(p, given, obj, imp >= thr, share, k_lat,
                                                  render_options)
                p = self._vine_p
                if with_options and render_options.get("within") is None:
                    from .main_channel import silhouette

                    render_options["within"] = self._vine_within(
                        obj if obj is not None else silhouette(imp >= thr), render_options["leaf_length"])
            if thr > p.endpoint_threshold:
                p = _within_range(p, endpoint_threshold=thr)
        obj = obj if metaphor == "vines" else None
        return given, p, k, obj, render_options

    @checked(seed=Point())
    def run(self, params: StylizeParams | None = None, *, seed=None, rng: int | np.random.Generator = 0,
            metaphor: str | None = "plain", **render_options) -> Stylization:
        """Run (or reuse) every stage and render.

        Parameters
        ----------
        params : StylizeParams, optional
            Paper defaults if None. They are adapted to the image's size
            (:func:`effective_params`) and, for vines and lightning, to the
            metaphor (:func:`metaphor_params`).
        seed : (x, y), optional
            Where the dendrite starts, in image pixels; the centre of the
            most important region by default (:meth:`default_seed`).
        rng : int
            Seed of the lattice noise and the stippling (an int, so stages
            can be cached).
        metaphor : {"plain", "vines", "lightning", None}
            Rendering; None skips it.
        **render_options
            Passed to the metaphor's render function.

        Returns
        -------
        Stylization
            Every stage's result; ``params`` holds the parameters really used.

        Raises
        ------
        ValueError
            If ``params.max_width < params.min_width`` or ``seed`` lies outside
            the image.
        """
        p = check_params(params if params is not None else StylizeParams())
        rng = as_seed(rng)  # stages are cached by an int seed; a Generator gives one
        if p.max_width < p.min_width:
            raise ValueError(f"params.max_width ({p.max_width}) < params.min_width ({p.min_width})")
        if metaphor in ("plain", None):
            ground = self._get(("paper_ground",), self._find_paper_ground)
            if ground is not None:
                return self._on_ground(ground, p, seed, rng, metaphor, render_options)
        given, p, k, obj, render_options = self._metaphor_setup(p, metaphor, render_options)
        if seed is None:
            seed = (self.top_seed(p) if metaphor == "lightning" else self._vine_seed(p, obj)
                    if obj is not None else self.default_seed(p, metaphor=metaphor))
        else:
            seed = as_points(np.reshape(np.asarray(seed, float), (1, 2)), name="seed",
                             image_shape=self.shape)[0]
        seed_lat = self.to_lattice(p, seed)
        lat = self.lattice(p, rng)
        ends = self.endpoints(p, rng)
        res, d, struck, grounded = (
            self._strike(p, seed_lat, rng) if metaphor == "lightning" else
            (self.plan(p, seed_lat, rng), self.dendrite(p, seed_lat, rng), False, False))
        if obj is not None:
            d, ends = self._vine_dendrite(p, seed_lat, rng, obj)
        imp = self.importance(p)
        d = self._widths(d, p, p.min_width, p.max_width)
        if metaphor == "lightning":  # a planned channel stays bright down to its last fork
            d = widen_main_path(d, p.min_width, p.max_width,
                                exponent=STRIKE_MAIN_EXPONENT if struck else LIGHTNING_MAIN_EXPONENT,
                                side=(STRIKE_PHOTO_SIDE if d.main is not None and not grounded
                                      else STRIKE_SIDE if struck else 1.0))
            if grounded:
                d = _to_ground(d)
            objs = self._traced_outlines(p) if struck else None
            if objs is not None:
                d = thin_on_ground(d, objs)
        pinned = self._pinned
        if k < 1.0 and p.output_width > 0 and p.thickness == "importance" and metaphor in (
                "plain", None):
            # the floor keeps strokes a pixel wide; where that carries more ink than the
            # 512-px picture's floor would, drop twigs until it does not (twigs_within_ink)
            ref_lo = min(p.min_width, max(given.min_width, p.output_width) * self.lattice_factor(p))
            ref_hi = p.max_width
            full = d0 = self.dendrite(p, seed_lat, rng)
            keep = np.ones(len(full.tips), bool)
            for i in range(_PRUNE_ROUNDS):  # a round drops the outermost twigs only
                # the reference differs only where the floor binds (elsewhere the partial
                # tone match, started from other widths, would count as excess)
                ref = np.where(pinned, self._widths(d0, p, ref_lo, ref_hi).radius, d.radius)
                k_i = twigs_within_ink(d, ref, sigma=p.tone_sigma, rng=rng + 2 + i)
                if k_i.mean() > 0.98:
                    break
                keep &= ~np.isin(full.nodes[full.tips], d0.nodes[d0.tips[~k_i]])
                d0 = self._dendrite_pruned(p, seed_lat, rng, keep)
                d = self._widths(d0, p, p.min_width, p.max_width)
                pinned = self._pinned
        scale = self.scale(p)
        if not np.allclose(scale, 1.0):
            d = d.rescaled(self.shape)
            # the dendrite starts exactly at the seed (a forest's other roots stay put)
            roots = np.flatnonzero(d.parent < 0)
            d.points[roots[np.argmin(np.hypot(*(d.points[roots] - seed).T))]] = seed
        rendering = None
        if metaphor == "vines" and render_options.get("hug") is None:
            # the stems kept in from the outline by their width less the pixel they may reach
            # past it (_vine_hug): 1 px at 250-750 px, more on larger pictures' wider stems
            wide = float(np.percentile(d.radius, 90)) if d.n_nodes else 1.0
            render_options = {**render_options,
                              "hug": self._vine_hug(max(1, int(np.ceil(wide - 1.0))))}
        if metaphor is not None:
            from .metaphors import render as render_metaphor

            rendering = render_metaphor(d, metaphor, **render_options)
        ends_image = ends if np.allclose(scale, 1.0) else self._get(
            ("endpoints_image", _subset(p, _IMPORTANCE + _ENDPOINTS), rng),
            lambda: self.to_image(p, ends))
        return Stylization(self.image, imp, lat, res, ends_image, d, rendering,
                           dataclasses.replace(p), np.asarray(seed, float), scale)

    def _find_paper_ground(self) -> PaperGround | None:
        # judged on a copy of at most 256 px: the ground's colours and the object's cover
        # do not need more, and a slider's first move should not wait for a 1-MP Lab map
        h, w = self.shape
        f = min(1.0, PAPER_GROUND_SIZE / max(h, w))
        small = self.image if f == 1.0 else cv2.resize(
            self.image, (max(1, round(w * f)), max(1, round(h * f))), interpolation=cv2.INTER_AREA)
        return _paper_ground(small)

    def _levelled(self, ground: PaperGround) -> Stylizer:
        """A stylizer of the picture levelled to its paper ``ground`` (cached)."""
        return self._get(("on_paper",), lambda: Stylizer(_on_paper(self.image, ground)))

    def _on_ground(self, ground: PaperGround, p, seed, rng, metaphor, render_options) -> Stylization:
        """The plain metaphor on a picture whose ground is its paper (beyond the paper, see
        :func:`~branchnb.dendrite.foreground._paper_ground`): every stage runs on the picture
        levelled to its ground (:func:`~branchnb.dendrite.foreground._on_paper`), so the
        ground and its grain stay clean; on a dark ground the strokes are light ink on the
        ground's colour (a scratchboard)."""
        levelled = self._levelled(ground)
        res = levelled.run(p, seed=seed, rng=rng, metaphor=None)
        rendering = None
        if metaphor == "plain":
            from .metaphors import render as render_metaphor

            options = dict(render_options)
            if ground.dark:
                options.setdefault("background", np.broadcast_to(ground.colour, self.image.shape).copy())
                options.setdefault("color", SCRATCH_INK)
            rendering = render_metaphor(res.dendrite, "plain", **options)
        return dataclasses.replace(res, image=self.image, rendering=rendering)

#: Tips per ``LIGHTNING_SPACING`` of a found object's medial axis (:func:`_strike_share`).
THIN_TIPS = 3.0


def _strike_share(content: np.ndarray) -> float:
    """The share of the picture a lightning bolt's tips are counted for on an object found on
    its ground (:func:`~branchnb.dendrite.stylize_params.metaphor_params`: one tip per
    ``(LIGHTNING_SPACING x diagonal)**2``): its area's share, or, if more, as many tips as
    ``THIN_TIPS`` per ``LIGHTNING_SPACING`` of the diagonal along its medial axis.

    Beyond the paper (dendrite38): counted by area alone, a pole, a mast or a forked stem
    2-6 % of the picture wide got the floor of 8 tips, about one per 35-60 px of its length
    against one per 25-30 px of a wide blob's main channel, so its bolt was one channel with
    a stub or two and missed the mast's arms and the fork's heads.

    >>> m = np.zeros((100, 100), bool); m[10:90, 48:52] = True
    >>> round(_strike_share(m), 3), float(m.mean())
    (0.302, 0.032)
    """
    from skimage.morphology import skeletonize

    c = np.asarray(content, bool)
    area = float(c.mean())
    axis = float(skeletonize(c).sum())
    spacing = LIGHTNING_SPACING * float(np.hypot(*c.shape))
    return max(area, THIN_TIPS * axis * spacing / float(c.size))


def _to_ground(d: Dendrite) -> Dendrite:
    """A bolt down an object's stem (a tree's trunk) as bright to its foot as where it last
    forked (beyond the paper: below its last fork the channel is one tip's twig, drawn thin
    and dim, and the strike faded out halfway down the trunk)."""
    path = d.main
    n = d.leaf_count()[path]
    forks = np.flatnonzero(n > 1)
    if path.size < 2 or forks.size == 0:
        return d
    r = d.radius.astype(np.float64, copy=True)
    last = int(forks[-1])
    r[path[last:]] = np.maximum(r[path[last:]], r[path[last]])
    return d.with_radius(r)


def stylize(image, params: StylizeParams | None = None, *, seed=None, rng: int | np.random.Generator = 0,
            metaphor: str | None = "plain", **render_options) -> Stylization:
    """Dendritic stylization of ``image`` (one-shot :class:`Stylizer`).

    Parameters
    ----------
    image : array_like
        Grey or colour image in [0, 1] (alpha ignored).
    params : StylizeParams, optional
        Paper defaults (``StylizeParams()``) if None; adapted to the image's
        size and the metaphor, see :meth:`Stylizer.run`.
    seed : (x, y), optional
        Where the dendrite starts, in image pixels; the centre of the most
        important region by default (:meth:`Stylizer.default_seed`).
    rng : int or numpy.random.Generator
        Seed of the lattice noise and the stippling; 0 by default, so a call
        is reproducible.
    metaphor : {"plain", "vines", "lightning", None}
        Rendering metaphor; None skips rendering.
    **render_options
        Passed to the metaphor's render function (e.g. ``background``).

    Returns
    -------
    Stylization

    Examples
    --------
    >>> img = np.ones((40, 40)); img[10:30, 10:30] = 0.0
    >>> out = stylize(img, StylizeParams(n_endpoints=30), rng=0)
    >>> out.rendering.image.shape
    (40, 40, 3)
    """
    return Stylizer(image).run(params, seed=seed, rng=rng, metaphor=metaphor, **render_options)
