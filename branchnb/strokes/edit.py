"""Structure editing with user strokes: the public entry point.

The user draws strokes along the skeleton of an object (*source strokes*)
and corresponding strokes in the output domain (*target strokes*);
:func:`edit_structure` re-synthesizes the object's texture along the
target strokes:

1. **Strokes** (:mod:`~branchnb.strokes.strokes`): pairs in drawing order,
   control-point pairs (end points plus the user's).
2. **Branching** (:mod:`~branchnb.strokes.junctions`): target strokes that
   start on another one become branches (extended into the
   parent, composed after it).
3. **Fetching** (:mod:`~branchnb.strokes.fetch`): samples every ``h``
   pixels along each target stroke, the texture around the corresponding
   source point copied rotated into place.
4. **Global texture sampling** (:mod:`~branchnb.strokes.sampling`): the
   source points are moved within a search window to minimise the sum of
   the pairwise compositing energies of neighbouring samples, by dynamic
   programming.
5. **Graph-cut composition** (:mod:`~branchnb.strokes.composition`): the
   overlapping patches are stitched along minimum-cost seams.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..core.image import as_float_image, as_rgba, composite_over
from ..core.io import encode_png
from ..core.params import check_params, param
from ..core.random import as_rng
from ..core.validate import Seq, Shape, checked
from .centring import centre_stroke
from .composition import PlacedPatch, compose, labelling_cost, seam_mask
from .display import draw_strokes
from .fetch import fetch, sample_pair, source_index
from .junctions import attach, exit_length, far_side, find_junctions, stroke_order
from .outline import _POCKET, clear_stale_outline, close_cuts, drop_flecks, fill_joints, outline_style, source_depth
from .parts import add_bases, place_part, rigid_frame
from .sampling import candidate_offsets, choose, pair_energies
from .strokes import StrokePair, make_pairs

__all__ = ["FETCH_FIELDS", "EditPatches", "StrokeEditParams", "StrokeEditResult", "StrokeSamples",
           "compose_patches", "edit_structure", "fetch_patches"]


@dataclass
class StrokeEditParams:
    """Parameters of :func:`edit_structure`.

    The paper gives no numbers; the defaults below are the values that
    work on the sample objects (``lizard``, ``rope_loop``, the bare RPG
    trees) and on procedural multi-part objects
    (:mod:`~branchnb.strokes.procedural`). Sizes are in pixels of the
    source image; ``0`` means "automatic" for ``patch_size``, ``spacing``
    and ``junction_tolerance`` (the values used are in
    :attr:`StrokeEditResult.auto`). ``unstroked``, ``close_cuts`` and
    ``centre_strokes`` go beyond the paper (:mod:`~branchnb.strokes.parts`,
    :mod:`~branchnb.strokes.outline`, :mod:`~branchnb.strokes.centring`);
    ``unstroked="drop", close_cuts=False, centre_strokes=False`` is the
    paper's method.

    Parameters
    ----------
    patch_size : int
        Patch diameter ``2 r`` (px); 0 (default) = automatic: ``r = 1.2 w + 4``
        follows the object's half width ``w`` along the source strokes
        (:func:`~branchnb.strokes.fetch.auto_radius`; 24 px radius for opaque
        images).
    spacing : float
        Sample spacing ``h`` along the target strokes (px), at most the local
        patch radius; 0 (default) = ``r / 2``.
    search_window : int
        Global sampling window ``W``: ``p'`` moves up to +-W px along the
        source stroke (``delta``); 8.
    search_across : int
        ``p'`` also moves up to +- this many px across the source stroke
        (``epsilon``); 0.
    search_step : int
        Step (px) of the search window; 2.
    seam_power : float
        Exponent on the colour difference ``d(x)`` in the seam cost
        ``d ** power / G``; 1.
    gradient_weighted : bool
        Divide the seam cost by the edge strength ``G(x, y)`` so seams follow
        edges; True.
    sampling : {"dp", "greedy", "none"}
        Choice of the sample correspondences: the paper's global sampling by
        dynamic programming (default), greedy, or the plain arc-length mapping.
    composition : {"graphcut", "overlay"}
        Stitch overlapping patches along graph-cut seams (the paper's) or
        paint each over the last.
    shift_penalty : float
        ``lambda``: prior pulling ``p'`` towards the arc-length mapping (a
        tie-breaker); 0.01.
    junction_tolerance : float
        A target stroke end this close (px) to another target stroke makes a
        branch; 0 (default) = ``r / 3``.
    extend_branches : bool
        Extend branches whose source end is free into their parent so the end
        cap is hidden; True.
    energy_stride : int
        Evaluate the pairwise energies on every n-th pixel of the overlaps
        (speed); 2.
    unstroked : {"follow", "drop"}
        Parts of the object nobody stroked follow the stroked part they hang
        from rigidly (default, beyond the paper) or are dropped (the paper's
        output).
    close_cuts : bool
        Draw the object's outline over faces the strokes cut (stroke ends,
        dropped parts); True, beyond the paper.
    centre_strokes : bool
        Slide each moved source stroke across itself onto the middle of the
        part it was drawn along (:mod:`~branchnb.strokes.centring`); True,
        beyond the paper (which assumes strokes on the skeleton). Strokes
        within 1 px of the middle, strokes kept in place and pairs with
        control points stay as drawn.

    Examples
    --------
    >>> p = StrokeEditParams(sampling="greedy")
    >>> p.sampling, p.search_window
    ('greedy', 8)
    """

    patch_size: int = param(
        0, min=0, max=256, step=2,
        help="patch diameter 2r (px); 0 = auto: r = 1.2 w + 4 follows the object's half width w "
             "along the source strokes (48 px for opaque images)")
    spacing: float = param(
        0.0, min=0.0, max=128.0, step=1.0,
        help="sample spacing h along the target strokes (px), at most the local patch radius r; "
             "0 = auto (r / 2)")
    search_window: int = param(
        8, min=0, max=64, step=1,
        help="global sampling search window W: p' moves up to +-W px along the source stroke")
    search_across: int = param(
        0, min=0, max=16, step=1,
        help="p' also moves up to +- this many px across the source stroke")
    search_step: int = param(2, min=1, max=16, step=1, help="step of the search window (px)")
    seam_power: float = param(
        1.0, min=0.25, max=4.0, step=0.25,
        help="exponent on the colour difference d(x) in the seam cost d ** power / G")
    gradient_weighted: bool = param(
        True, help="divide the seam cost by the edge strength G(x, y) so seams follow edges")
    sampling: str = param(
        "dp", options=("dp", "greedy", "none"),
        help="choice of sample correspondences: dynamic programming, greedy, or plain "
             "arc-length mapping")
    composition: str = param(
        "graphcut", options=("graphcut", "overlay"),
        help="stitch overlapping patches with graph-cut seams or simply paint them over")
    shift_penalty: float = param(
        0.01, min=0.0, max=10.0, step=0.01,
        help="lambda: prior pulling p' towards the arc-length mapping (a tie-breaker)")
    junction_tolerance: float = param(
        0.0, min=0.0, max=64.0, step=1.0,
        help="a stroke end this close to another target stroke makes a branch (px); "
             "0 = auto (r / 3)")
    extend_branches: bool = param(
        True, help="extend branches whose source end is free into their parent (hides the end cap)")
    energy_stride: int = param(
        2, min=1, max=4, step=1, ui=False,
        help="evaluate the pairwise energies on every n-th pixel (speed)")
    unstroked: str = param(
        "follow", options=("follow", "drop"),
        help="parts of the object nobody stroked: follow the stroked part they hang from (rigidly), "
             "or drop them (the paper's output: the strokes only)")
    close_cuts: bool = param(
        True, help="draw the object's outline over faces the strokes cut (stroke ends, dropped parts)")
    centre_strokes: bool = param(
        True, help="slide each moved source stroke onto the middle of the part it was drawn along "
                   "(hand-drawn strokes off the skeleton fetch background otherwise)")


@dataclass
class StrokeSamples:
    """What happened along one stroke pair.

    Parameters
    ----------
    target : (M, 2) ndarray
        Sample positions ``p`` on the target stroke.
    source : (M, 2) ndarray
        The chosen source points ``p'``.
    source_s : (M,) ndarray
        Their source arc lengths.
    shift : (M, 2) ndarray
        Chosen ``(delta, epsilon)`` relative to the arc-length mapping.
    radius : (M,) ndarray
        Patch radius ``r`` of each sample.
    pinned : (M,) bool ndarray
        Samples at control points.
    energy : float
        Chain energy of the choice (pairwise + shift prior).
    pairwise : float
        Sum of the pairwise compositing energies.
    """

    target: np.ndarray
    source: np.ndarray
    source_s: np.ndarray
    shift: np.ndarray
    radius: np.ndarray
    pinned: np.ndarray
    energy: float
    pairwise: float


@dataclass
class StrokeEditResult:
    """Result of :func:`edit_structure`.

    Parameters
    ----------
    image : (H, W, 4) float32 ndarray
        The synthesized object over the background (transparent if none
        was given), straight (not premultiplied) alpha.
    mask : (H, W) bool ndarray
        Object mask: alpha > 0.5 of the synthesized object.
    seams : (H, W) bool ndarray
        Pixels along the seams between patches (on the object).
    energies : dict
        ``"sampling"``: total chain energy of global sampling (sum over
        strokes); ``"sampling_pairwise"``: its pairwise part;
        ``"seam"``: total seam cost of the final labelling
        (:func:`~branchnb.strokes.composition.labelling_cost`);
        ``"seam_steps"``: sum of the per-patch cut costs.
    layer : (H, W, 4) float32 ndarray
        The object alone on a transparent background.
    labels : (H, W) int ndarray
        Patch each pixel comes from (-1: none).
    samples : list of StrokeSamples
        Per stroke pair, in input order.
    pairs : list of StrokePair
        The stroke pairs used (target strokes extended at junctions).
    junctions : list of Junction
        Where a target stroke starts or ends on another one (branches).
    radius : float
        Typical (median) patch radius ``r`` along the source strokes; the
        radius of every sample is in ``samples[i].radius``.
    source_region : (H_src, W_src) bool ndarray
        The source object pixels the chosen patches copy (the source
        object region the result is made of; compare their colours with
        the result's, e.g. :func:`branchnb.core.histogram.compare_samples`).
    params : StrokeEditParams
        The parameters used.
    auto : dict
        The values used for the parameters left at 0 ("automatic"):
        ``"patch_size"`` (typical ``2 r``), ``"spacing"`` (typical ``h``),
        ``"junction_tolerance"`` (px).

    Examples
    --------
    >>> img = np.zeros((30, 50, 4), np.float32); img[10:20, 5:45] = (0.6, 0.4, 0.2, 1.0)
    >>> res = edit_structure(img, [[(8, 15), (42, 15)]], [[(25, 2), (25, 28)]])  # turned upright
    >>> res.image.shape, bool(res.mask[15, 25]), bool(res.mask[15, 8])
    ((30, 50, 4), True, False)
    >>> sorted(res.auto)
    ['junction_tolerance', 'patch_size', 'spacing']
    """

    image: np.ndarray
    mask: np.ndarray
    seams: np.ndarray
    energies: dict
    layer: np.ndarray
    labels: np.ndarray
    samples: list = field(default_factory=list)
    pairs: list = field(default_factory=list)
    junctions: list = field(default_factory=list)
    radius: float = 0.0
    source_region: np.ndarray | None = None
    params: StrokeEditParams | None = None
    auto: dict = field(default_factory=dict)

    def show(self, *, seams: bool = False, strokes: bool = False, background=(1.0, 1.0, 1.0),
             seam_color=(1.0, 0.0, 0.0)) -> np.ndarray:
        """RGB picture: the image over ``background``, seams and target strokes optionally drawn.

        Target strokes are drawn in their pair colours
        (:func:`~branchnb.strokes.display.draw_strokes`).

        Parameters
        ----------
        seams : bool
            Paint the seam pixels (:attr:`seams`) in ``seam_color``.
        strokes : bool
            Draw the target strokes (extended at junctions) over the result.
        background : RGB triple
            Colour the RGBA result is composited over; white.
        seam_color : RGB triple
            Colour of the seams; red.

        Returns
        -------
        (H, W, 3) float32 ndarray

        Examples
        --------
        >>> img = np.zeros((30, 50, 4), np.float32); img[10:20, 5:45] = (0.6, 0.4, 0.2, 1.0)
        >>> res = edit_structure(img, [[(8, 15), (42, 15)]], [[(8, 15), (42, 15)]])
        >>> pic = res.show(strokes=True)
        >>> pic.shape, pic[2, 2].tolist()
        ((30, 50, 3), [1.0, 1.0, 1.0])
        """
        rgb = composite_over(self.image, background)
        if seams:
            rgb[self.seams] = np.asarray(seam_color, np.float32)
        if strokes and self.pairs:
            rgb = draw_strokes(rgb, [p.target.points for p in self.pairs], width=1.5)
        return rgb

    def _repr_png_(self) -> bytes:
        return encode_png(self.show())

    def __repr__(self) -> str:
        h, w = self.image.shape[:2]
        e = ", ".join(f"{k} {v:.3g}" for k, v in self.energies.items())
        return (f"StrokeEditResult({w} x {h}, {len(self.pairs)} stroke pair(s), {len(self.junctions)} "
                f"junction(s), patch radius ~{self.radius:.0f} px, energies: {e})")


def _sampling_geometry(params: StrokeEditParams, index, k: int, pair: StrokePair):
    """Per target arc length: the patch radius r and the sample step h."""
    def radius(s_t):
        return index.radius(k, pair.source_arc_length(s_t), params.patch_size)

    def step(s_t):
        r = radius(s_t)
        return np.minimum(params.spacing, r) if params.spacing > 0 else np.maximum(r / 2.0, 1.0)

    return radius, step


def _background(background, target_shape, src_shape):
    """Validate ``background``; returns (colour or None, image or None, target shape)."""
    bg_img = None
    if background is not None:
        bg = np.asarray(background)
        if bg.ndim == 1:
            if bg.shape not in ((3,), (4,)) or not np.all(np.isfinite(bg.astype(float))):
                raise ValueError(
                    f"background must be an RGB(A) colour or an image, got shape {bg.shape}")
            if np.any((bg.astype(float) < 0) | (bg.astype(float) > 1)):
                raise ValueError("background colour values must lie in [0, 1]")
        else:
            bg_img = as_rgba(as_float_image(background, name="background"), name="background")
            if target_shape is not None and tuple(target_shape)[:2] != bg_img.shape[:2]:
                raise ValueError(
                    f"target_shape {tuple(target_shape)[:2]} differs from the background image's "
                    f"{bg_img.shape[:2]}")
            target_shape = bg_img.shape[:2]
    if target_shape is None:
        target_shape = src_shape[:2]
    return bg_img, _check_shape(target_shape)


@checked(source_strokes=Seq(), target_strokes=Seq(), control_points=Seq(), target_shape=Shape())
def edit_structure(image, source_strokes, target_strokes, params: StrokeEditParams | None = None,
                   *, control_points=None, target_shape=None, background=None,
                   rng=None) -> StrokeEditResult:
    """Re-synthesize an object along new strokes.

    Parameters
    ----------
    image : (H, W, C) array_like
        Source image: an RGBA object on a transparent background (the
        object region is alpha > 0.5), or an opaque image (the object
        region is then the union of the patches copied around the source
        strokes).
    source_strokes : list of (N, 2) array_like or Stroke
        Strokes along the object's skeleton, on ``image``. The same
        stroke may be given several times (e.g. to grow two branches
        from one example branch).
    target_strokes : list of (N, 2) array_like or Stroke
        One per source stroke (paired in order, same direction of travel):
        where the object's parts go. A target stroke starting or ending on
        another target stroke makes a branch.
    params : StrokeEditParams, optional
        Defaults (``StrokeEditParams()``) if None: automatic patch size,
        spacing and junction tolerance, global sampling, graph cut.
    control_points : list, optional
        Per pair, None or ``(source_points, target_points)``: extra
        control-point pairs, points clicked near the two strokes.
    target_shape : (H, W), optional
        Size of the output domain (default: the background image's, or
        the source image's).
    background : None, RGB(A) colour or (H, W, C) image, optional
        What lies behind the object: None keeps it transparent.
    rng : int or numpy.random.Generator, optional
        Accepted for API uniformity; the method is deterministic.

    Returns
    -------
    StrokeEditResult

    Notes
    -----
    ``edit_structure(...)`` is ``compose_patches(fetch_patches(...),
    params)``: the first stage (strokes, junctions, candidate patches) is
    what the parameters in :data:`FETCH_FIELDS` decide; keep its
    :class:`EditPatches` to re-run only the second stage (global sampling
    and composition) when only the others change (e.g. ``seam_power``).

    Raises
    ------
    ValueError
        Different numbers of source and target strokes, a stroke with
        fewer than two points or zero length, control points out of order,
        a source stroke leaving the image, a target stroke entirely
        outside the output domain (a target stroke partly outside is
        clipped), bad parameters.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 60, 4), np.float32)
    >>> img[15:25, 5:55] = (0.6, 0.4, 0.2, 1.0)
    >>> src = [[(8, 20), (52, 20)]]
    >>> res = edit_structure(img, src, src)          # identity edit
    >>> bool(np.abs(res.image - img)[res.mask].max() < 1e-5)
    True

    The same in two stages (what an app keeps between slider moves):

    >>> patches = fetch_patches(img, src, src)
    >>> again = compose_patches(patches)
    >>> bool(np.array_equal(again.image, res.image))
    True
    """
    params = _check_edit_params(params)
    as_rng(rng)
    patches = fetch_patches(image, source_strokes, target_strokes, params, control_points=control_points,
                            target_shape=target_shape, background=background)
    return compose_patches(patches, params)


#: The parameters the fetched candidate patches depend on (see :class:`EditPatches`); with
#: ``sampling == "none"`` only one candidate per sample is fetched, so whether it is "none" counts too.
FETCH_FIELDS = ("patch_size", "spacing", "search_window", "search_across", "search_step",
                "junction_tolerance", "extend_branches", "unstroked", "centre_strokes")


def _check_edit_params(params) -> StrokeEditParams:
    params = StrokeEditParams() if params is None else params
    if not isinstance(params, StrokeEditParams):
        raise TypeError(f"params must be a StrokeEditParams, got {type(params).__name__}")
    check_params(params)
    return params


def _fetch_key(params: StrokeEditParams) -> tuple:
    return tuple(getattr(params, f) for f in FETCH_FIELDS) + (params.sampling == "none",)


@dataclass
class _StrokeCandidates:
    """The fetched candidates of one stroke pair (in composition order)."""

    index: int
    samples: object  # fetch.Samples
    radii: np.ndarray
    fetched: list
    offsets: list


@dataclass
class EditPatches:
    """The first stage of :func:`edit_structure`: the strokes and every candidate patch, fetched.

    Everything here follows from the image, the strokes and the
    parameters in :data:`FETCH_FIELDS`; :func:`compose_patches` makes the
    result from it for any values of the others (``seam_power``,
    ``gradient_weighted``, ``shift_penalty``, ``sampling``,
    ``composition``, ``energy_stride``) in a fraction of the time.

    Parameters
    ----------
    params : StrokeEditParams
        The parameters it was fetched with.
    pairs : list of StrokePair
        The stroke pairs as given.
    attached : list of StrokePair
        The pairs with target strokes extended at junctions.
    junctions : list of Junction
        The branches among the target strokes.
    target_shape : (int, int)
        ``(H, W)`` of the output domain.
    radius : float
        Typical (median) patch radius along the source strokes.
    n_candidates : int
        Candidate patches fetched (all strokes, all samples).
    """

    params: StrokeEditParams
    pairs: list
    attached: list
    junctions: list
    target_shape: tuple
    radius: float
    n_candidates: int
    _index: object = field(repr=False, default=None)
    _strokes: list = field(repr=False, default_factory=list)
    _extra: list = field(repr=False, default_factory=list)
    _window: float = field(repr=False, default=0.0)
    _scale: float = field(repr=False, default=1.0)
    _background: object = field(repr=False, default=None)
    _bg_img: object = field(repr=False, default=None)
    _carried: list = field(repr=False, default_factory=list)
    _style: object = field(repr=False, default=None)
    _auto: dict = field(repr=False, default_factory=dict)

    def reusable_for(self, params: StrokeEditParams) -> bool:
        """Whether :func:`compose_patches` can use these patches with ``params``.

        Parameters
        ----------
        params : StrokeEditParams
            The parameters of the next composition.

        Returns
        -------
        bool
            True when every field of :data:`FETCH_FIELDS` (and whether
            ``sampling`` is "none") equals the one the patches were fetched with.
        """
        return isinstance(params, StrokeEditParams) and _fetch_key(params) == _fetch_key(self.params)


@checked(source_strokes=Seq(), target_strokes=Seq(), control_points=Seq(), target_shape=Shape())
def fetch_patches(image, source_strokes, target_strokes, params: StrokeEditParams | None = None,
                  *, control_points=None, target_shape=None, background=None) -> EditPatches:
    """Stage 1 of :func:`edit_structure`: pair the strokes, find junctions, fetch the candidate patches.

    Same arguments as :func:`edit_structure` (and the same errors);
    returns the :class:`EditPatches` that :func:`compose_patches` turns
    into the result.

    Parameters
    ----------
    image : (H, W, C) array_like
        Source image (see :func:`edit_structure`).
    source_strokes : list of (N, 2) array_like or Stroke
        Strokes along the object's skeleton, on ``image``.
    target_strokes : list of (N, 2) array_like or Stroke
        One per source stroke, in the output domain.
    params : StrokeEditParams, optional
        Defaults if None; only the fields in :data:`FETCH_FIELDS` matter here.
    control_points : list, optional
        Per pair, None or ``(source_points, target_points)``.
    target_shape : (H, W), optional
        Size of the output domain.
    background : None, RGB(A) colour or (H, W, C) image, optional
        What lies behind the object (kept for :func:`compose_patches`).

    Returns
    -------
    EditPatches

    Raises
    ------
    ValueError
        As :func:`edit_structure` (mismatched or degenerate strokes, control
        points out of order, strokes outside the images, bad parameters).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 60, 4), np.float32); img[15:25, 5:55] = (0.6, 0.4, 0.2, 1.0)
    >>> patches = fetch_patches(img, [[(8, 20), (52, 20)]], [[(30, 5), (30, 35)]])
    >>> patches.reusable_for(StrokeEditParams(seam_power=2.0)), patches.reusable_for(StrokeEditParams(spacing=3))
    (True, False)
    """
    params = _check_edit_params(params)
    src_img = as_rgba(image, name="image")
    bg_img, target_shape = _background(background, target_shape, src_img.shape)
    pairs = make_pairs(source_strokes, target_strokes, control_points,
                       source_shape=src_img.shape, target_shape=target_shape)
    if params.centre_strokes:
        pairs = _centred_pairs(src_img, pairs, control_points, target_shape)
    index = source_index(src_img, [p.source for p in pairs], patch_size=params.patch_size)
    typical = float(np.median(np.concatenate([
        index.radius(k, np.linspace(0, p.source.length, 32), params.patch_size)
        for k, p in enumerate(pairs)])))
    window = max(typical / 2.0, 2.0)  # chord half-length for the stroke directions
    tol = params.junction_tolerance if params.junction_tolerance > 0 else max(typical / 3.0, 2.0)

    # Branching: junctions among the target strokes.
    junctions = find_junctions([p.target for p in pairs], tol)
    attached: list[StrokePair] = list(pairs)
    extra = [{0: 0.0, 1: 0.0} for _ in pairs]
    for i, pair in enumerate(pairs):
        mine = [j for j in junctions if j.child == i]
        if not mine:
            continue
        depth = {}
        for jn in mine:
            end_cut = index.cut_ends[i][jn.end]
            if params.extend_branches and not end_cut:
                # A free end (a tip) glued to the parent: push it under the parent.
                # (A cut end -- also one that starts on another source stroke --
                # ends at the parent's centre line as it is.)
                par = pairs[jn.parent]
                w = float(index.half_width(jn.parent, par.source_arc_length(jn.parent_s)))
                if not index.has_alpha:
                    w = float(index.radius(jn.parent, 0.0, params.patch_size)) / 2.0
                depth[jn.end] = min(w, typical)
        attached[i], extra[i] = attach(pair, mine, [p.target for p in pairs], depth)
    order = stroke_order(len(pairs), junctions)
    if index.has_alpha:
        _align_exits(index, pairs, attached, junctions)
    carried = _carried_parts(index, pairs, attached, window) if params.unstroked == "follow" else []
    for i in range(len(pairs)):
        pins = sorted({(index.parts[pi].s, s_t) for j, pi, s_t in carried
                       if j == i and index.parts[pi].contact})
        if pins:
            attached[i] = _with_pins(attached[i], pins)

    offsets = candidate_offsets(params.search_window, params.search_step, params.search_across)
    if params.sampling == "none":
        offsets = offsets[:1]
    strokes, n_cand = [], 0
    for i in order:
        pair = attached[i]
        radius_of, step_of = _sampling_geometry(params, index, i, pair)
        smp = sample_pair(pair, step_of, window=window)
        radii = radius_of(smp.s)
        fetched, offs = [], []
        for j in range(len(smp)):
            off = offsets[:1] if smp.pinned[j] else offsets
            fetched.append(fetch(index, i, smp.source_s[j] + off[:, 0], off[:, 1],
                                 smp.points[j], smp.angles[j], float(radii[j]), window=window))
            offs.append(off)
            n_cand += len(off)
        strokes.append(_StrokeCandidates(i, smp, radii, fetched, offs))
    return EditPatches(params=dataclasses.replace(params), pairs=pairs, attached=attached,
                       junctions=junctions, target_shape=target_shape, radius=typical,
                       n_candidates=n_cand, _index=index, _strokes=strokes, _extra=extra,
                       _window=window, _scale=max(params.search_window + params.search_across, 1),
                       _background=None if background is None else background, _bg_img=bg_img,
                       _carried=carried, _auto=_auto_values(params, typical, tol),
                       _style=outline_style(index.premult, index.depth) if index.has_alpha else None)


def _auto_values(params: StrokeEditParams, typical: float, tol: float) -> dict:
    """The values used for the parameters left at 0 (automatic)."""
    out = {}
    if params.patch_size == 0:
        out["patch_size"] = round(2.0 * typical, 1)
    if params.spacing == 0:
        out["spacing"] = round(max(typical / 2.0, 1.0), 1)
    if params.junction_tolerance == 0:
        out["junction_tolerance"] = round(tol, 1)
    return out


def _align_exits(index, pairs, attached, junctions) -> None:
    """Make branches drawn from their parent's centre line leave the new parent's silhouette.

    Such a branch copies nothing of its source parent (see
    :func:`~branchnb.strokes.fetch.source_index`): its texture starts where
    its source stroke leaves the source parent's tube. A control pair maps
    that point to where its target stroke leaves the target parent's
    silhouette (the parent as re-synthesized: its source silhouette's width
    at the corresponding place), so the branch starts at the parent's
    edge, wherever it is moved to and however thick the parent is there.
    """
    for jn in junctions:
        i = jn.child
        src_parent = index.joined[i][jn.end] if index.joined else -1
        if src_parent < 0:
            continue
        ppair = attached[jn.parent]
        a = exit_length(pairs[i].source, index.strokes[src_parent],
                        lambda s, k=src_parent: index.half_width(k, s), jn.end)
        b = exit_length(attached[i].target, ppair.target,
                        lambda s, k=jn.parent, pp=ppair: index.edge_width(k, pp.source_arc_length(s)),
                        jn.end)
        if a is None or b is None:
            continue
        pair = attached[i]
        ls, lt = pair.source.length, pair.target.length
        row = (a, b) if jn.end == 0 else (ls - a, lt - b)
        attached[i] = _with_pins(pair, [row])


def _centred_pairs(src_img, pairs, control_points, target_shape) -> list[StrokePair]:
    """``pairs`` with every moved source stroke slid onto the middle of its part (:mod:`.centring`).

    Pairs whose target is the source itself (parts kept in place) and pairs
    with the user's own control points stay as drawn.
    """
    alpha = src_img[..., 3]
    if not bool((alpha < 0.999).any()):
        return pairs  # an opaque image: no silhouette to centre on
    mask = alpha > 0.5
    sources, changed = [], False
    for i, p in enumerate(pairs):
        keep = (control_points is not None and control_points[i] is not None) or (
            p.source.points.shape == p.target.points.shape
            and np.allclose(p.source.points, p.target.points))
        others = [q.source.points for j, q in enumerate(pairs) if j != i]
        pts = p.source.points if keep else centre_stroke(mask, p.source.points, others=others)
        changed |= pts is not p.source.points
        sources.append(pts)
    if not changed:
        return pairs
    return make_pairs(sources, [p.target for p in pairs], control_points,
                      source_shape=src_img.shape, target_shape=target_shape)


def _carried_parts(index, pairs, attached, window: float) -> list[tuple[int, int, float]]:
    """``(pair, part, s_target)``: every pair carries the parts hanging from its source stroke.

    A part touching its own stroke at several places goes only where they
    all move alike; contact with other strokes does not hold it back (it
    follows the stroke it touches most).
    """
    keys = [p.source.points.tobytes() for p in pairs]
    out = []
    for pi, part in enumerate(index.parts):
        _steadiest_anchor(index, part, pairs, attached, keys, window)
        (rs, cs) = part.box
        corners = np.array([[cs.start, rs.start, 1.0], [cs.stop, rs.stop, 1.0],
                            [cs.start, rs.stop, 1.0], [cs.stop, rs.start, 1.0]])
        for i in range(len(pairs)):
            if keys[i] != keys[part.stroke]:
                continue
            s_t = _mapped(attached[i], part.s)
            moved = corners @ rigid_frame(attached[i].source, attached[i].target, part.s, s_t,
                                          window=window).T
            alike = True
            # Only places on the part's own stroke (a loop between two cut ends) must move
            # alike; a part also touching another stroke (a leg at the hip where the tail
            # turns) follows the stroke it touches most, as a limb would, instead of vanishing.
            own = [s_a for j, s_a in part.anchors if keys[j] == keys[i]]
            for s_a in own if len(own) > 1 else ():
                other = corners @ rigid_frame(attached[i].source, attached[i].target, s_a,
                                              _mapped(attached[i], s_a), window=window).T
                alike &= float(np.abs(other - moved).max()) <= 2.0
            if alike:
                out.append((i, pi, s_t))
    return out


def _steadiest_anchor(index, part, pairs, attached, keys, window: float) -> None:
    """Hang ``part`` from the stroke among those it touches that moves it least (in place).

    A part touching two strokes that move apart (a starfish's arm between
    the kept arm and the turned one, both stroked from the centre; a leg at
    the hip where the tail turns) stays with the one that keeps it nearest
    to where it was: an edit changes only what the user touched. Beyond the
    paper.
    """
    strokes = {j for j, _ in part.anchors if keys[j] != keys[part.stroke]}
    if not strokes:
        return
    (rs, cs) = part.box
    corners = np.array([[cs.start, rs.start, 1.0], [cs.stop, rs.stop, 1.0],
                        [cs.start, rs.stop, 1.0], [cs.stop, rs.start, 1.0]])
    src = corners[:, :2]

    def moved(j, s_a):
        i = keys.index(keys[j])  # the first pair with that source stroke
        frame = rigid_frame(attached[i].source, attached[i].target, s_a, _mapped(attached[i], s_a),
                            window=window)
        return float(np.abs(corners @ frame.T - src).max())

    own = [s_a for j, s_a in part.anchors if keys[j] == keys[part.stroke]] or [part.s]
    best, best_d = None, min(moved(part.stroke, s_a) for s_a in own)
    for j in sorted(strokes):
        d = max(moved(j, s_a) for jj, s_a in part.anchors if jj == j)
        if d < best_d - 2.0:
            best, best_d = j, d
    if best is None:
        return
    s_best = [s_a for j, s_a in part.anchors if j == best]
    part.stroke, part.s = best, float(np.median(s_best))
    part.anchors = [(j, s_a) for j, s_a in part.anchors if keys[j] == keys[best]]
    part.box = (slice(part.box[0].start, part.box[0].stop), slice(part.box[1].start, part.box[1].stop))
    add_bases([part], index, window=3.0)


def _mapped(pair: StrokePair, s_source: float) -> float:
    """Target arc length of source arc length ``s_source`` (the pair's control mapping)."""
    return float(np.interp(s_source, pair.control[:, 0], pair.control[:, 1]))


def _with_pins(pair: StrokePair, pins) -> StrokePair:
    """``pair`` with extra control points at ``(s_source, s_target)`` on its own mapping.

    They do not change the mapping; they put a sample exactly where a part
    is attached and pin it there (no shift by global sampling), so the
    parent's texture at the joint is the one the part was cut from.
    """
    ctl = pair.control
    rows = [tuple(r) for r in ctl[1:-1]]
    ls, lt = ctl[-1]
    for a, b in pins:
        if not (1.0 < a < ls - 1.0 and 1.0 < b < lt - 1.0):
            continue
        if any(abs(a - r[0]) < 1.0 or abs(b - r[1]) < 1.0 for r in rows):
            continue
        rows.append((a, b))
    rows.sort(key=lambda r: r[1])
    if len(rows) == len(ctl) - 2:
        return pair
    try:
        return StrokePair(pair.source, pair.target, np.array(rows, float).reshape(-1, 2), name=pair.name)
    except ValueError:
        return pair  # pins out of order (a folded mapping): sample as drawn


def compose_patches(patches: EditPatches, params: StrokeEditParams | None = None) -> StrokeEditResult:
    """Stage 2 of :func:`edit_structure`: choose the correspondences and stitch the patches.

    Parameters
    ----------
    patches : EditPatches
        From :func:`fetch_patches`.
    params : StrokeEditParams, optional
        Default: the parameters ``patches`` were fetched with. Others may
        differ only outside :data:`FETCH_FIELDS` (see
        :meth:`EditPatches.reusable_for`).

    Returns
    -------
    StrokeEditResult
        The same as :func:`edit_structure` with ``params`` gives.
    """
    if not isinstance(patches, EditPatches):
        raise TypeError(f"patches must be EditPatches (from fetch_patches), got {type(patches).__name__}")
    params = patches.params if params is None else _check_edit_params(params)
    if not patches.reusable_for(params):
        changed = [f for f in FETCH_FIELDS if getattr(params, f) != getattr(patches.params, f)]
        raise ValueError(f"params differ from the fetched patches' in {changed or ['sampling (none)']}: "
                         "call fetch_patches again")
    index, window, junctions = patches._index, patches._window, patches.junctions
    attached, extra, target_shape = patches.attached, patches._extra, patches.target_shape
    placed: list[PlacedPatch] = []
    samples: list[StrokeSamples | None] = [None] * len(patches.pairs)
    e_total = e_pair = 0.0
    source_region = np.zeros(index.shape, bool)
    for cand in patches._strokes:
        i, smp, radii, fetched, offs = cand.index, cand.samples, cand.radii, cand.fetched, cand.offsets
        pair = attached[i]
        unaries = [params.shift_penalty * np.abs(off).sum(axis=1) / patches._scale for off in offs]
        pairwise = [pair_energies(fetched[j], fetched[j + 1], power=params.seam_power,
                                  gradient_weighted=params.gradient_weighted,
                                  stride=params.energy_stride)
                    for j in range(len(smp) - 1)]
        res = choose(unaries, pairwise, params.sampling)
        e_total += res.energy
        e_pair += res.pairwise
        # Junction handling for the child's patches near its attached ends.
        mine = [jn for jn in junctions if jn.child == i]
        for j, k in enumerate(res.choice):
            f = fetched[j]
            pin_core, keep = True, None
            for jn in mine:
                end_s = 0.0 if jn.end == 0 else pair.target.length
                near = abs(smp.s[j] - end_s) <= extra[i][jn.end] + f.radius
                if not near:
                    # farther along (a child leaving its parent at a slant), the patch
                    # still may not lay the child's pixels over its parent's interior
                    inside = _inside_parent(index, attached, jn, f.origin, f.valid.shape[1])
                    if inside.any():
                        keep = inside if keep is None else keep | inside
                    continue
                pin_core = False
                step = f.radius if jn.end == 0 else -f.radius
                into = pair.target.point_at(min(max(end_s + step, 0.0), pair.target.length)) \
                    - jn.point
                nrm = np.hypot(*into)
                if nrm > 1e-9:
                    fs = far_side(jn, attached[jn.parent].target, into / nrm, f.origin,
                                  f.valid.shape[1], window=window)
                    fs = fs | _inside_parent(index, attached, jn, f.origin, f.valid.shape[1])
                    keep = fs if keep is None else keep | fs
            placed.append(PlacedPatch(f.pixels[k], f.valid[k], f.origin, pin_core, keep,
                                      _patch_map(f, k), grow=not pin_core))
            rows, cols = f.source_pixels(k, index.shape)
            source_region[rows, cols] = True
        samples[i] = StrokeSamples(
            target=smp.points, source=np.array([fetched[j].source_points[k]
                                                for j, k in enumerate(res.choice)]),
            source_s=np.array([fetched[j].source_s[k] for j, k in enumerate(res.choice)]),
            shift=np.array([offs[j][k] for j, k in enumerate(res.choice)]),
            radius=radii, pinned=smp.pinned, energy=res.energy, pairwise=res.pairwise)

    # Joints (closed after composition): junctions and the attachments of carried parts.
    joints = [(jn.point, 1.5 * float(index.half_width(jn.parent, attached[jn.parent].source_arc_length(
        jn.parent_s))) + 4.0, _pocket(index, jn), jn) for jn in junctions]
    # The parts nobody stroked, each carried rigidly by its stroke (after all strokes).
    for i, pi, s_t in patches._carried:
        part, pair = index.parts[pi], attached[i]
        got = place_part(part, index.premult, rigid_frame(pair.source, pair.target, part.s, s_t,
                                                          window=window), target_shape)
        if got is None:
            continue
        pix, valid, _, origin, inverse = got
        keep = None
        if part.contact and not part.at_end:
            # not over the far side of the parent's centre line
            p, n = pair.target.point_at(s_t), pair.target.normal_at(s_t, window=window)
            yy, xx = np.mgrid[0:valid.shape[0], 0:valid.shape[1]]
            keep = ((xx + origin[0] - p[0]) * n[0] + (yy + origin[1] - p[1]) * n[1]) * part.side < -0.5
        placed.append(PlacedPatch(pix, valid, origin, True, keep, inverse, grow=True))
        source_region[part.box] |= part.mask
        if part.contact:
            joints.append((pair.target.point_at(s_t),
                           1.5 * float(index.half_width(part.stroke, part.s)) + 4.0, None, None))
    comp = compose(placed, target_shape, method=params.composition, power=params.seam_power,
                   gradient_weighted=params.gradient_weighted)
    # For an opaque source the alpha is 1 on every copied pixel (less on the
    # anti-aliased edges of cut ends), 0 elsewhere: the object region is the
    # union of the patches.
    premult = comp.image
    alpha = premult[:, :, 3].copy()
    layer = np.zeros_like(premult)
    nz = alpha > 1e-6
    layer[nz, :3] = np.clip(premult[nz, :3] / alpha[nz, None], 0.0, 1.0)
    layer[:, :, 3] = alpha
    if index.has_alpha:
        style = patches._style if params.close_cuts else None
        wide = [j for j in joints if j[2] is not None]
        filled = None
        if wide:
            # wide joints first, their pockets filled with the parts' inner colours (not
            # the outline's); the new silhouette is then outlined like a cut face
            before = layer[:, :, 3] > 0.5
            old = layer
            layer = fill_joints(layer, [j[0] for j in wide], [j[1] for j in wide],
                                pockets=[j[2] for j in wide],
                                inner=0 if style is None else int(np.ceil(style.width)) + 1)
            if layer is not old:
                # only the wedges along the children (no bridge to a neighbouring part)
                changed = layer[:, :, 3] != old[:, :, 3]
                away = changed & ~_along_children(wide, attached, old.shape[:2], changed)
                layer[away] = old[away]
            filled = (layer[:, :, 3] > 0.5) & ~before
        if style is not None:
            depth = source_depth(comp.labels, [pp.source_map for pp in placed], index.depth)
            if filled is not None and filled.any():
                depth = np.where(filled, np.float32(_FILLED_DEPTH), depth)
            layer = close_cuts(layer, depth, style)
            layer = clear_stale_outline(layer, depth, style, filled=filled)
        if joints:
            layer = fill_joints(layer, [j[0] for j in joints], [j[1] for j in joints])
        layer = drop_flecks(layer, index.premult[:, :, 3])
        alpha = layer[:, :, 3]
    mask = alpha > 0.5
    seams = seam_mask(comp.labels, alpha, min_alpha=0.1)
    energies = {
        "sampling": float(e_total),
        "sampling_pairwise": float(e_pair),
        "seam": labelling_cost(placed, comp.labels, power=params.seam_power,
                               gradient_weighted=params.gradient_weighted),
        "seam_steps": float(comp.step_costs.sum()),
    }
    background, bg_img = patches._background, patches._bg_img
    if background is None:
        out = layer.copy()
    elif bg_img is None:
        colour = np.asarray(background, np.float32)
        bg_rgba = np.broadcast_to(np.append(colour[:3], colour[3] if len(colour) == 4 else 1.0),
                                  (*target_shape, 4))
        out = _over(layer, bg_rgba)
    else:
        out = _over(layer, bg_img)
    return StrokeEditResult(
        image=np.clip(out, 0, 1).astype(np.float32), mask=mask, seams=seams, energies=energies,
        layer=layer, labels=comp.labels, samples=samples, pairs=attached, junctions=junctions,
        radius=patches.radius, source_region=source_region & index.object,
        params=dataclasses.replace(params), auto=dict(patches._auto))


#: Source depth given to pixels filled at joints (deep enough to be outlined as a cut face).
_FILLED_DEPTH = 100.0


def _inside_parent(index, attached, jn, origin, size: int) -> np.ndarray:
    """Pixels of a ``size`` x ``size`` patch at ``origin`` inside the parent's silhouette
    (1.5 px in from its edge, the silhouette's half width at the junction): they keep
    the parent's texture, a child turned far does not lay its cut face over its parent."""
    parent = attached[jn.parent]
    hw = float(index.edge_width(jn.parent, np.array([parent.source_arc_length(jn.parent_s)]))[0])
    # where the child leaves along the parent's normal, the width across is the child's
    hw = min(hw, index.side_width.get((jn.child, jn.end, jn.parent), np.inf) + 1.0)
    pts = parent.target.points
    a, b = pts[:-1], pts[1:]
    centre = np.array([origin[0] + 0.5 * size, origin[1] + 0.5 * size])
    near = _segment_distance(centre[None], a, b)[0] <= hw + 0.75 * size
    if not near.any():
        return np.zeros((size, size), bool)  # the patch's square is nowhere near the parent
    yy, xx = np.mgrid[0:size, 0:size]
    q = np.c_[xx.ravel() + origin[0], yy.ravel() + origin[1]].astype(float)
    d = _segment_distance(q, a[near], b[near]).min(axis=1)
    return (d <= hw - 1.5).reshape(size, size)


def _segment_distance(q: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(N, M) distances of points ``q`` (N, 2) to segments ``a``-``b`` (M, 2)."""
    ab = b - a
    len2 = np.maximum((ab ** 2).sum(axis=1), 1e-12)
    t = np.clip(((q[:, None, :] - a[None]) * ab[None]).sum(axis=2) / len2, 0.0, 1.0)
    p = a[None] + t[..., None] * ab[None]
    return np.hypot(q[:, None, 0] - p[..., 0], q[:, None, 1] - p[..., 1])


def _along_children(wide, attached, shape, where: np.ndarray | None = None) -> np.ndarray:
    """Pixels within ``3 r`` (r: the joint's closing radius, half the child's half width,
    so 1.5 child widths) of a wide joint's child target stroke, near the joint (only
    among the pixels ``where``, if given: the others are False)."""
    h, w = shape
    out = np.zeros((h, w), bool)
    for point, reach, r, jn in wide:
        x, y = point
        m = int(np.ceil(2 * reach)) + 2 + int(np.ceil(r))
        r0, r1, c0, c1 = max(int(y) - m, 0), min(int(y) + m + 1, h), max(int(x) - m, 0), min(int(x) + m + 1, w)
        if r0 >= r1 or c0 >= c1:
            continue
        if where is None:
            yy, xx = np.mgrid[r0:r1, c0:c1]
        else:
            yy, xx = np.nonzero(where[r0:r1, c0:c1])
            yy, xx = yy + r0, xx + c0
        if not yy.size:
            continue
        _, d = attached[jn.child].target.project(np.c_[xx.ravel(), yy.ravel()])
        out[yy, xx] |= d.reshape(yy.shape) <= 3.0 * r
    return out


def _pocket(index, jn) -> float | None:
    """Radius of the closing at junction ``jn``: half the child's half width where
    it leaves its parent's silhouette (None: the usual small closing).

    A child turned far from its source direction (an arm raised by 50
    degrees) has its cut face turned with it, which leaves a wedge between
    the face and the parent's side; a 2-px closing fills only the wedge's
    tip, a closing of half the child's half width rounds the joint like a
    branch collar. (Beyond the paper, whose junctions keep the source angle.)
    """
    child, parent = index.strokes[jn.child], index.strokes[jn.parent]
    t = np.arange(0.0, child.length, 1.0)
    pts = child.point_at(t if jn.end == 0 else child.length - t)
    s_par, d = parent.project(pts)
    out = np.flatnonzero(d > index.edge_width(jn.parent, s_par) + 2.0)
    if not len(out):
        return None
    q = np.rint(pts[out[0]:out[0] + 6]).astype(int)
    h, w = index.shape
    q = q[(q[:, 0] >= 0) & (q[:, 0] < w) & (q[:, 1] >= 0) & (q[:, 1] < h)]
    if not len(q):
        return None
    r = float(index.depth[q[:, 1], q[:, 0]].min()) / 2.0
    return r if r > _POCKET else None


def _patch_map(f, k: int) -> np.ndarray:
    """Target ``(x, y)`` -> source ``(x, y)`` of candidate ``k`` of ``f`` (a rotation about the sample)."""
    th = float(f.source_angles[k]) - float(f.dst_angle)
    c, s = np.cos(th), np.sin(th)
    (cx, cy), (dx, dy) = f.source_points[k], f.dst_point
    return np.array([[c, -s, cx - c * dx + s * dy], [s, c, cy - s * dx - c * dy]])


def _over(layer: np.ndarray, bg: np.ndarray) -> np.ndarray:
    """Straight-alpha RGBA ``layer`` over straight-alpha RGBA ``bg``."""
    a = layer[:, :, 3:4]
    b = bg[:, :, 3:4]
    out_a = a + b * (1 - a)
    rgb = layer[:, :, :3] * a + bg[:, :, :3] * b * (1 - a)
    rgb = np.where(out_a > 1e-6, rgb / np.maximum(out_a, 1e-6), 0.0)
    return np.dstack([rgb, out_a]).astype(np.float32)


def _check_shape(shape) -> tuple[int, int]:
    try:
        h, w = (int(v) for v in tuple(shape)[:2])
    except (TypeError, ValueError) as exc:
        raise TypeError(f"target_shape must be (H, W), got {shape!r}") from exc
    if h < 1 or w < 1:
        raise ValueError(f"target_shape must be positive, got {(h, w)}")
    return h, w
