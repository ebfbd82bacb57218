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
from ..core.matte import matte_from_background
from ..core.params import check_params, param
from ..core.random import as_rng
from ..core.validate import Seq, Shape, checked
from .attachment import _align_exits, _carried_parts, _centred_pairs, _under_parent, _with_pins
from .display import draw_strokes
from .elbows import add_elbow_pins
from .fetch import _fetch, sample_pair
from .junctions import attach, find_junctions, stroke_order
from .outline import outline_style
from .sampling import candidate_offsets
from .source import source_index
from .strokes import StrokePair, make_pairs
from .touched import _still_pairs, _typical_radius

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
        (:func:`~branchnb.strokes.source.auto_radius`; 24 px radius for opaque
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
        output). The body a stroke grows out of (the larger part at its
        start: a lizard's trunk when only the tail is stroked) is moved with
        the stroke's start only, never turned
        (:func:`~branchnb.strokes.parts.carry_frame`).
    close_cuts : bool
        Draw the object's outline over faces the strokes cut (stroke ends,
        dropped parts); True, beyond the paper.
    centre_strokes : bool
        Slide each moved source stroke across itself onto the middle of the
        part it was drawn along (:mod:`~branchnb.strokes.centring`); True,
        beyond the paper (which assumes strokes on the skeleton). Strokes
        within 1 px of the middle, strokes kept in place and pairs with
        control points stay as drawn.
    separate_ground : bool
        An opaque image whose ground is plain or smooth (white, a flat
        colour, a vertical or diagonal gradient, light paper texture) is
        split into the object (a soft alpha matte,
        :func:`~branchnb.core.matte.matte_from_background`) and its ground,
        and edited as an RGBA object: unstroked parts stay, and the result is
        painted over the photo's own ground with the vacated area filled by
        the smooth ground model (plus its grain); True, beyond the paper.
        With a ``background`` given, or an output domain of another size,
        the cut-out object goes over that (or stays on transparent). A busy ground (or
        False) keeps the opaque behaviour: the object is the union of the
        patches copied around the strokes.

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
    separate_ground: bool = param(
        True, help="opaque image on a plain or smooth ground (white, a flat colour, a gradient, paper): "
                   "cut the object out with a soft matte and paint the result over the photo's own ground")


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
        was given; for an opaque image on a smooth ground, that image's own
        ground with the vacated area filled), straight (not premultiplied)
        alpha.
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
        object region is alpha > 0.5), or an opaque image: on a plain or
        smooth ground the object is cut out with a soft matte and the
        result is painted over that ground (``params.separate_ground``);
        on a busy ground the object region is the union of the patches
        copied around the source strokes.
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
        What lies behind the object: None keeps it transparent (for an
        opaque image on a smooth ground: the image's own ground, the
        vacated area filled with its smooth model).
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

    Beyond the paper: a target stroke that bends the other way than its
    source (a bent arm copied to the other side of its trunk, drawn as its
    mirror image; both turning by over 0.5 rad) is drawn with mirror-image
    patches -- rotated ones would put the outer side of the elbow inside.
    Where a target stroke is not its source moved rigidly (lengthened,
    bent), a patch's pixels reached across a bend of the source stroke (the
    upright of an L-shaped arm seen from its horizontal leg) are kept only
    where they land about as far from the target stroke as they lay from
    the source stroke; a lengthened arm got a staircase of stale uprights.
    Where another part lies over a stroke's tube in the source (a berry
    hanging over a leaf), the stroke's patches see that stretch filled in
    with its own flesh and outline from farther along it
    (:mod:`~branchnb.strokes.hidden`), and those pixels stay under any other
    part's opaque pixels in the result: a copied or turned leaf is whole
    (no notch, no grey arcs of the berry's rim), a carried one stays under
    its berry.
    Where a part nobody stroked surrounds the roots of strokes that leave it
    (an octopus's head round its tentacles) and a stroke turns its limb away,
    the part's own source pixels close the notch the root leaves (no
    transparent wedge drawn as a dark blob); ink-tinted pixels from just
    inside the source's rim are repainted with a stale rim, and one-pixel
    cracks in the soft rim between two patches are closed (beyond the paper).
    Strokes that cross in the source and stay where they were, hidden only
    by strokes that stay too, copy their crossing as it is (two untouched
    tentacles crossing: no smear of each one's filled-in texture).
    A stroke touching other strokes with both ends hangs from the first and
    only lies on (or under) the second: the part it lies under keeps its
    outline there (a copy of an arm laid across the arm's own tip), and ink
    a joint's closing copies beyond the outline's band is repainted (no
    doubled hair where a curled tentacle leaves its head).
    A stroke's tip moved onto another stroke joins nothing: a part moved
    over another part it was apart from in the source is drawn over it,
    with its own outline across the other's flesh (a finger bent over its
    neighbour's tip); the stroke that moved more there lies on top.
    A stroke crossing its own path (a rope re-stroked into a loop) or another
    stroke on its way (neither ending on the other) passes over it, outline
    and all (:mod:`~branchnb.strokes.crossings`): the later pass by arc length
    lies on top of a self-crossing, the stroke given later on top of another
    (unless the source shows it lying under that one); crossings crowded by
    a third pass or stroke, and of strokes left where they were, stay as laid.
    Half-transparent pixels deeper inside the result than the source's own
    anti-aliased rim are made opaque (no light ticks in crotches).

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
                "junction_tolerance", "extend_branches", "unstroked", "centre_strokes", "separate_ground")


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


def _still_crossings(index, pairs):
    """``index`` without the own views of strokes left where they were and hidden only by
    other strokes left where they were (``index`` itself if none).

    Two strokes crossing in the source (an octopus's tentacle tips) each see the
    other as lying over them and fill the crossing from farther along
    themselves (:mod:`~branchnb.strokes.hidden`): that keeps a moved stroke from
    dragging its neighbour's pixels along, but where neither moves both filled
    patches meet at the crossing, a smear of each one's texture (suckers'
    colour), where the source's own pixels were right. Beyond the paper.
    """
    still = _still_pairs(pairs)
    drop = [k for k in index.views if k in still and index.hidden_by.get(k) is not None
            and index.hidden_by[k] <= still]
    if not drop:
        return index
    return dataclasses.replace(index, views={k: v for k, v in index.views.items() if k not in drop})


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
    src_img, background = _separate_ground(src_img, params, background, target_shape)
    bg_img, target_shape = _background(background, target_shape, src_img.shape)
    pairs = make_pairs(source_strokes, target_strokes, control_points,
                       source_shape=src_img.shape, target_shape=target_shape)
    drawn = pairs
    if params.centre_strokes:
        pairs = _centred_pairs(src_img, pairs, control_points, target_shape)
    index = _still_crossings(source_index(src_img, [p.source for p in pairs], patch_size=params.patch_size),
                             pairs)
    typical = _typical_radius(index, pairs, params.patch_size)
    window = max(typical / 2.0, 2.0)  # chord half-length for the stroke directions
    tol = params.junction_tolerance if params.junction_tolerance > 0 else max(typical / 3.0, 2.0)

    # Branching: junctions among the target strokes.
    junctions = find_junctions([p.target for p in pairs], tol, [p.source for p in pairs])
    attached: list[StrokePair] = list(pairs)
    extra = [{0: 0.0, 1: 0.0} for _ in pairs]
    for i, pair in enumerate(pairs):
        mine = [j for j in junctions if j.child == i]
        if not mine:
            continue
        depth = {}
        for jn in mine:
            end_cut = index.cut_ends[i][jn.end] or _under_parent(index, i, jn)
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
    elbows = add_elbow_pins(pairs, attached, window, _mirrored)
    carried = _carried_parts(index, pairs, attached, window, drawn) if params.unstroked == "follow" else []
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
        mirror = _mirrored(pairs[i], window)
        radius_of, step_of = _sampling_geometry(params, index, i, pair)
        smp = sample_pair(pair, step_of, window=window)
        if i in elbows:  # an elbow's sample is free to move (global sampling): see elbows.add_elbow_pins
            smp.pinned[np.abs(smp.s - elbows[i]) < 1e-6] = False
        radii = radius_of(smp.s)
        fetched, offs = [], []
        for j in range(len(smp)):
            off = offsets[:1] if smp.pinned[j] else offsets
            # (fetch's checks skipped: float arc lengths and offsets, one target point)
            fetched.append(_fetch(index, i, smp.source_s[j] + off[:, 0], off[:, 1],
                                  np.asarray(smp.points[j], float), float(smp.angles[j]), float(radii[j]),
                                  float(window), mirror))
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


def _separate_ground(src_img: np.ndarray, params: StrokeEditParams, background, target_shape):
    """An opaque ``src_img`` on a smooth ground as (RGBA object, its ground as the background).

    Returns ``(src_img, background)`` unchanged for RGBA objects, busy
    grounds and ``separate_ground=False``. The photo's own ground (its
    smooth model where the object lay) becomes the background only when
    the caller gave none and the output domain has the source's size.
    """
    if not params.separate_ground or bool((src_img[..., 3] < 0.999).any()):
        return src_img, background
    matte = matte_from_background(src_img[..., :3])
    if matte is None:
        return src_img, background
    same = target_shape is None or tuple(int(v) for v in tuple(target_shape)[:2]) == src_img.shape[:2]
    if background is None and same:
        background = matte.background
    return matte.image, background


#: A pair is mirrored when its source and target strokes turn opposite ways, each by more than this (rad).
_MIRROR_TURN = 0.5


def _turning(stroke, window: float) -> float:
    """Total signed turning of ``stroke`` (rad; directions over chords of ``window``)."""
    if stroke.length < 1e-9:
        return 0.0
    s = np.linspace(0.0, stroke.length, max(8, int(np.ceil(2.0 * stroke.length / max(window, 1.0)))))
    a = np.unwrap(stroke._angle_at(s, window))
    return float(a[-1] - a[0])


def _mirrored(pair: StrokePair, window: float) -> bool:
    """Whether the target stroke bends the other way than the source (a bent arm copied to the
    other side of its trunk, drawn as its mirror image): its patches are then mirror images.

    Rotated patches (the paper's) cannot follow such a bend: the outer side of the
    source's elbow lands on the inner side of the target's, an X of two cut faces
    across the elbow (a cactus arm copied to the trunk's other side). Beyond the
    paper; only when both strokes turn by more than :data:`_MIRROR_TURN`.
    """
    a, b = _turning(pair.source, window), _turning(pair.target, window)
    return a * b < 0 and min(abs(a), abs(b)) > _MIRROR_TURN


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



def _check_shape(shape) -> tuple[int, int]:
    try:
        h, w = (int(v) for v in tuple(shape)[:2])
    except (TypeError, ValueError) as exc:
        raise TypeError(f"target_shape must be (H, W), got {shape!r}") from exc
    if h < 1 or w < 1:
        raise ValueError(f"target_shape must be positive, got {(h, w)}")
    return h, w


# stage 2 lives in its own module (it needs the classes above)
from .synthesis import compose_patches  # noqa: E402
