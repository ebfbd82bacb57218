"""Trees by iterative growth (paper, section 8).

A tree is grown in a few iterations on a randomly weighted lattice:

1. **Trunk and main branches**: the cumulative metric (smooth paths). The
   trunk is the path from the seed at the bottom centre to a fork point at
   the bottom of the crown; the main branches are planned from the upper
   part of the trunk to a handful of well-spaced endpoints in the crown.
2. **Later iterations**: the *whole structure so far* is the seed set. New
   endpoints are chosen by rejection sampling: uniform random points are
   kept only if their brushfire distance to the structure (the Euclidean
   distance transform of the structure's pixels) is at most ``R_i``; the
   radius shrinks every iteration (``R_i = radius * radius_decay ** (i - 2)``)
   while the number of endpoints grows, so each generation adds more,
   shorter twigs close to the previous one. The metric moves from
   cumulative toward the non-scalar-like blend ``a * max + total``
   (``a = blend_weight`` = 1000 in the paper, reached at the last iteration,
   ``a_i = blend_weight * ((i - 1) / (n - 1)) ** mix_power``) over the
   iterations, so the twigs get more erratic than the limbs.
3. **Thickness**: after every iteration all existing nodes get thicker
   (``+ increment``), so the oldest parts, the trunk and main limbs, end up
   thickest. ``pipe > 0`` adds the pipe model (radius growing with the
   square root of the number of tips carried) so the trunk is also thicker
   than the limbs that grew in the same iteration.

**Occlusion** (:func:`grow_layers`): several trees grown from the same
trunk with different noise, drawn back to front in lighter to darker
shades, read as a full crown with depth.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ..core.image import as_mask, as_points
from ..core.io import encode_png
from ..core.params import check_params, param
from ..core.random import as_rng
from ..core.render import draw_polylines
from ..core.sampling import stipple
from ..core.svg import polylines_to_svg
from ..core.validate import Colour, Int, as_point, check_callback, check_shape, checked, real_array
from .dendrite import Dendrite, _accumulate_up, build_dendrite
from .lattice import Lattice, node_weights
from .planner import plan
from .render import Rendering, _canvas, svg_document

__all__ = [
    "GrownTree",
    "TreeParams",
    "crown_mask",
    "grow_layers",
    "grow_tree",
    "iteration_metric",
    "rejection_endpoints",
    "render_layers",
    "render_tree",
]

#: Largest canvas (H x W) a tree grows on: the lattice, its planner and the brushfire
#: distances grow with the area (8192 x 8192, the batch jobs' limit, takes minutes and
#: gigabytes already); larger sizes are refused at once instead of failing deep in numpy.
MAX_TREE_PIXELS = 8192 * 8192
#: Most trees :func:`grow_layers` grows (each is a full growth on the canvas).
MAX_LAYERS = 64
#: Most endpoints one iteration adds (the parameters' ranges allow 100 x 10 ** 7).
_MAX_ENDPOINTS = 200_000


def _tree_shape(value, name, allow_none):
    """The canvas ``(H, W)`` of a growth, at least 8 x 8 and at most :data:`MAX_TREE_PIXELS`."""
    h, w = check_shape(value, name, max_pixels=MAX_TREE_PIXELS)
    if h < 8 or w < 8:
        raise ValueError(f"{name} must be at least 8 x 8, got {h} x {w}")
    return h, w


@dataclass
class TreeParams:
    """Iterative tree growth. Defaults: the paper's where it gives them, else ours.

    Parameters
    ----------
    iterations : int
        Growth iterations ``n`` (1-8); 4. Iteration 1 grows trunk and main
        branches.
    trunk_endpoints : int
        Endpoints of iteration 1 (the main branches); 7.
    endpoint_growth : float
        Iteration ``i`` has ``trunk_endpoints * endpoint_growth ** (i - 1)``
        endpoints; 4.
    radius : float
        ``R_2``, the rejection radius of iteration 2 (px of brushfire
        distance to the structure); 70.
    radius_decay : float
        ``R_(i+1) = R_i * radius_decay``: twigs get shorter; 0.55.
    min_distance : float
        Endpoints closer to the structure than this fraction of ``R_i`` are
        rejected too; 0.3.
    blend_weight : float
        ``a`` of the last iteration's blend metric ``a M + S`` (paper: 1000).
    mix_power : float
        ``a_i = a ((i - 1) / (n - 1)) ** mix_power`` (0: full blend from
        iteration 2 on); 2.
    noise : float
        Amplitude of the random node weight; 1.
    epsilon : float
        Constant node weight ``epsilon``; 0.5.
    tip_width : float
        Width (px) of new twigs; 0.8.
    increment : float
        Width (px) added to every existing node after each later iteration, so
        the oldest parts are thickest; 1.
    pipe : float
        Extra width ``pipe * sqrt(tips carried - 1)`` (pipe model; 0 = widths
        from the iterations only); 0.5.
    fork_jitter : float
        Standard deviation of the fork point's horizontal offset, as a
        fraction of W; 0.08.
    trunk_share : float
        Upper share of the trunk the main branches may leave from; 0.35.
    crown_top : float
        Top of the elliptic crown (fraction of the height); 0.04.
    crown_bottom : float
        Bottom of the crown and height of the fork point (fraction of the
        height); 0.62.
    crown_width : float
        Crown width (fraction of the image width); 0.9.
    scale_lengths : bool
        Beyond the paper: ``radius``, ``tip_width``, ``increment`` and ``pipe``
        are pixels of a 512 x 512 canvas and scale with the canvas's diagonal
        (:func:`~branchnb.dendrite.scale.length_scale`), so a 200-px and a
        2000-px canvas grow the same tree at their own resolution; True. Taken
        as pixels of any canvas, a 2000-px tree was a thin pole with hairline
        limbs and twigs hugging them (mean ink 0.016 against 0.235 at 200 px),
        a 200-px one a dark blob. Scaled, the mean ink of a 3-iteration tree
        is 0.045-0.048 from 128 to 768 px. The twigs are not kept at 1 px on
        small canvases: that gave a 128-px tree twice the ink of a 768-px one
        (their anti-aliased sub-pixel lines read a little paler instead).
        False: pixels of the canvas itself, as in the paper.

    Examples
    --------
    >>> p = TreeParams()
    >>> p.radius * p.radius_decay  # R_3 in pixels of a 512 x 512 canvas
    38.5
    """

    iterations: int = param(4, min=1, max=8, help="growth iterations")
    trunk_endpoints: int = param(7, min=1, max=100,
                                 help="endpoints of iteration 1 (trunk and main branches)")
    endpoint_growth: float = param(4.0, min=1.0, max=10.0, step=0.5,
                                   help="endpoint count multiplies by this every iteration")
    radius: float = param(70.0, min=2.0, max=500.0, step=1.0,
                          help="R_2: rejection radius of iteration 2 (px, brushfire distance)")
    radius_decay: float = param(0.55, min=0.1, max=1.0, step=0.05,
                                help="R_(i+1) = R_i * decay: twigs get shorter")
    min_distance: float = param(0.3, min=0.0, max=0.95, step=0.05,
                                help="reject endpoints closer than this fraction of R_i")
    blend_weight: float = param(1000.0, min=0.0, max=10000.0, log=True,
                                help="a of the last iteration's blend metric (paper: 1000)")
    mix_power: float = param(2.0, min=0.0, max=6.0, step=0.25,
                             help="metric mix per iteration: a_i = a ((i-1)/(n-1)) ** power")
    noise: float = param(1.0, min=0.0, max=5.0, step=0.05, help="random node weight amplitude")
    epsilon: float = param(0.5, min=0.0, max=5.0, step=0.05, help="constant node weight")
    tip_width: float = param(0.8, min=0.1, max=10.0, step=0.1, help="width of new twigs (px)")
    increment: float = param(1.0, min=0.0, max=20.0, step=0.1,
                             help="width added to existing nodes after each iteration (px)")
    pipe: float = param(0.5, min=0.0, max=5.0, step=0.05,
                        help="extra width * sqrt(tips carried) (0 = iterations only)")
    fork_jitter: float = param(0.08, min=0.0, max=0.5, step=0.01,
                               help="random offset of the trunk's fork point (fraction of W)")
    trunk_share: float = param(0.35, min=0.05, max=1.0, step=0.05,
                               help="upper part of the trunk the main branches may leave from")
    crown_top: float = param(0.04, min=0.0, max=0.9, step=0.01,
                             help="top of the crown (fraction of the height)")
    crown_bottom: float = param(0.62, min=0.1, max=1.0, step=0.01,
                                help="bottom of the crown (fraction of the height)")
    crown_width: float = param(0.9, min=0.1, max=1.0, step=0.05,
                               help="crown width (fraction of the image width)")
    scale_lengths: bool = param(True, help="radius and widths are px of 512 x 512 and scale "
                                           "with the canvas's diagonal")


@dataclass
class GrownTree:
    """A grown tree: the dendrite and what each iteration did.

    Parameters
    ----------
    dendrite : Dendrite
        All branches; ``dendrite.iteration`` tells which iteration added a node.
    endpoints : list of (E_i, 2) arrays
        Endpoints of each iteration.
    metrics : list of (str, float)
        ``(metric, blend_weight)`` used by each iteration.
    radii : list of float
        Rejection radius of each iteration (nan for iteration 1).
    params : TreeParams
        A copy of the parameters used.

    Examples
    --------
    >>> t = grow_tree((80, 60), TreeParams(iterations=2, radius=15), rng=0)
    >>> len(t.endpoints), t.metrics[0], bool(np.isnan(t.radii[0]))
    (2, ('cumulative', 0.0), True)
    """

    dendrite: Dendrite
    endpoints: list
    metrics: list
    radii: list
    params: TreeParams

    def render(self, **options) -> Rendering:
        """:func:`render_tree` of this tree.

        Parameters
        ----------
        **options
            Keyword arguments of :func:`render_tree` (``background``, ``color``,
            ``smooth``).

        Returns
        -------
        Rendering
        """
        return render_tree(self.dendrite, **options)

    def _repr_png_(self) -> bytes:
        return encode_png(self.render().image)


def iteration_metric(i: int, params: TreeParams) -> tuple[str, float]:
    """``(metric, a)`` of iteration ``i`` (1-based): cumulative first, then the blend
    ``a_i * M + S`` with ``a_i = blend_weight * ((i - 1) / (n - 1)) ** mix_power``
    (``mix_power = 0``: the full blend from iteration 2 on; 1: linear; 2: quadratic).

    Parameters
    ----------
    i : int
        Iteration number, 1-based.
    params : TreeParams
        Gives ``iterations``, ``blend_weight`` and ``mix_power``.

    Returns
    -------
    (str, float)
        ``("cumulative", 0.0)`` for iteration 1 (or ``blend_weight = 0``),
        else ``("blend", a_i)``.

    Examples
    --------
    >>> iteration_metric(1, TreeParams()), iteration_metric(4, TreeParams())
    (('cumulative', 0.0), ('blend', 1000.0))
    """
    if i <= 1 or params.blend_weight == 0:
        return "cumulative", 0.0
    n = max(params.iterations, 2)
    power = getattr(params, "mix_power", 2.0)
    return "blend", float(params.blend_weight * ((i - 1) / (n - 1)) ** power)


def crown_mask(shape, params: TreeParams) -> np.ndarray:
    """The crown region: an ellipse spanning ``crown_top..crown_bottom`` of the height.

    Parameters
    ----------
    shape : (int, int)
        ``(H, W)`` of the canvas.
    params : TreeParams
        ``crown_top``, ``crown_bottom`` (fractions of H) and ``crown_width``
        (fraction of W); the ellipse is centred horizontally.

    Returns
    -------
    (H, W) bool ndarray

    Raises
    ------
    ValueError
        If ``crown_bottom`` is not below ``crown_top``.

    Examples
    --------
    >>> m = crown_mask((100, 80), TreeParams())
    >>> bool(m[33, 40]), bool(m[90, 40])
    (True, False)
    """
    h, w = int(shape[0]), int(shape[1])
    top, bot = params.crown_top * h, params.crown_bottom * h
    if bot <= top:
        raise ValueError("params.crown_bottom must be below params.crown_top")
    cy, ry = (top + bot) / 2, (bot - top) / 2
    rx = params.crown_width * w / 2
    yy, xx = np.mgrid[0:h, 0:w]
    return ((xx - (w - 1) / 2) / rx) ** 2 + ((yy - cy) / ry) ** 2 <= 1.0


def rejection_endpoints(structure_mask, n_endpoints: int, radius: float, *,
                        min_distance: float = 0.0, region=None, rng=None,
                        max_tries: int = 50) -> np.ndarray:
    """Endpoints within brushfire distance ``radius`` of a structure, by rejection sampling.

    Uniform random pixels (of ``region`` if given) are kept when their
    Euclidean distance to the nearest structure pixel lies in
    ``[min_distance, radius]``.

    Parameters
    ----------
    structure_mask : (H, W) bool array_like
        Pixels of the structure grown so far (non-empty).
    n_endpoints : int
        Number of endpoints wanted (>= 1).
    radius : float
        ``R_i`` in pixels.
    min_distance : float
        Lower bound of the accepted distance (pixels).
    region : (H, W) bool array_like, optional
        Where endpoints may go.
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed of the candidate draws.
    max_tries : int
        Rounds of candidate draws before giving up with what was found.

    Returns
    -------
    (E, 2) float64 (x, y), E <= n_endpoints (fewer only if the band is tiny)

    Raises
    ------
    ValueError
        If ``structure_mask`` is empty, ``n_endpoints < 1`` or not
        ``0 <= min_distance <= radius``.

    Examples
    --------
    >>> m = np.zeros((50, 50), bool); m[25, 5:45] = True
    >>> pts = rejection_endpoints(m, 20, 6.0, min_distance=2.0, rng=0)
    >>> from scipy import ndimage
    >>> d = ndimage.distance_transform_edt(~m)[pts[:, 1].astype(int), pts[:, 0].astype(int)]
    >>> len(pts), bool(d.max() <= 6), bool(d.min() >= 2)
    (20, True, True)
    """
    m = as_mask(structure_mask, name="structure_mask")
    if not m.any():
        raise ValueError("structure_mask is empty")
    if radius <= 0 or min_distance < 0 or min_distance > radius:
        raise ValueError("need 0 <= min_distance <= radius and radius > 0")
    if n_endpoints < 1:
        raise ValueError(f"n_endpoints must be >= 1, got {n_endpoints}")
    rng = as_rng(rng)
    dist = ndimage.distance_transform_edt(~m)
    h, w = m.shape
    ok = (dist <= radius) & (dist >= min_distance)
    if region is not None:
        ok &= as_mask(region, shape=m.shape, name="region")
    out = []
    need = int(n_endpoints)
    for _ in range(max_tries):
        cand = np.column_stack([rng.integers(0, w, 4 * need + 16), rng.integers(0, h, 4 * need + 16)])
        keep = cand[ok[cand[:, 1], cand[:, 0]]]
        out.append(keep[:need])
        need -= len(out[-1])
        if need <= 0:
            break
    pts = np.vstack(out).astype(np.float64) if out else np.zeros((0, 2))
    return pts


def _pipe_width(d: Dendrite, tip_width: float, pipe: float) -> np.ndarray:
    leaf = np.zeros(d.n_nodes)
    leaf[d.tips] = 1.0
    return pipe * np.sqrt(np.maximum(_accumulate_up(d.parent, leaf), 1.0) - 1.0)


@checked(shape=_tree_shape, start_iteration=Int(1, 8))
def grow_tree(shape, params: TreeParams | None = None, *, base=None, weights=None, rng=None,
              start_iteration: int = 1) -> GrownTree:
    """Grow a tree in ``params.iterations`` iterations.

    Parameters
    ----------
    shape : (H, W)
        Canvas size; the trunk starts at the bottom centre.
    params : TreeParams, optional
        Defaults (``TreeParams()``) if None.
    base : (x, y) or GrownTree, optional
        The trunk base point (bottom centre by default), or a tree whose
        structure continues to grow (with ``start_iteration`` > 1; used for
        occlusion layers).
    weights : callable, optional
        ``weights(i, rng) -> (H, W)`` node weights of iteration ``i``
        (random ``epsilon + noise * U`` by default); pareidolia trees use it.
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed of the weights, fork point and endpoints.
    start_iteration : int
        First iteration to run.

    Returns
    -------
    GrownTree

    Raises
    ------
    TypeError
        If an argument is of the wrong kind (``weights`` not callable, ``base``
        neither a point nor a :class:`GrownTree`).
    ValueError
        If ``shape`` is smaller than 8 x 8 or larger than
        :data:`MAX_TREE_PIXELS`, ``base`` lies outside it (or is a tree of
        another shape), ``start_iteration`` does not fit ``base``, or
        ``weights`` returns another shape, NaN, inf or negative weights.

    Examples
    --------
    >>> t = grow_tree((120, 100), TreeParams(iterations=2, radius=20), rng=0)
    >>> d = t.dendrite
    >>> d.is_tree(), int(d.iteration.max()), bool(d.radius[0] == d.radius.max())
    (True, 2, True)
    """
    p = check_params(params if params is not None else TreeParams())
    h, w = shape
    weights = check_callback(weights, "weights")
    if isinstance(base, GrownTree):
        if tuple(base.dendrite.shape or ()) != (h, w):
            raise ValueError(f"base is a tree of shape {base.dendrite.shape}, expected {(h, w)}")
    elif base is not None:
        base = as_points(as_point(base, "base")[None], name="base", image_shape=(h, w))[0]
    rng = as_rng(rng)
    crown = crown_mask((h, w), p)
    user = p
    p = _scaled_lengths(p, (h, w))

    def default_weights(i, r):
        return node_weights(np.zeros((h, w)), epsilon=p.epsilon, noise=p.noise, rng=r)

    weights = default_weights if weights is None else weights
    if isinstance(base, GrownTree):
        d = base.dendrite
        endpoints, metrics, radii = list(base.endpoints), list(base.metrics), list(base.radii)
        if start_iteration < 2:
            raise ValueError("continuing a tree needs start_iteration >= 2")
    else:
        root = np.array([(w - 1) / 2.0, h - 1.0]) if base is None else base
        d = None
        endpoints, metrics, radii = [], [], []
        if start_iteration != 1:
            raise ValueError(f"start_iteration must be 1 for a new tree (base is not a GrownTree), "
                             f"got {start_iteration}")

    for i in range(start_iteration, p.iterations + 1):
        metric, a = iteration_metric(i, p)
        wts = real_array(weights(i, rng), f"weights({i})", ndim=2, min=0.0)
        if wts.shape != (h, w):
            raise ValueError(f"weights({i}) returned shape {wts.shape}, expected {(h, w)}")
        lat = Lattice(wts)
        # no more endpoints than pixels: the largest counts the fields allow (100 x 10 ** 7)
        # would only make the rejection sampling run out of memory
        n_i = min(round(p.trunk_endpoints * p.endpoint_growth ** (i - 1)), h * w, _MAX_ENDPOINTS)
        if i == 1:
            # the trunk: root -> fork point at the bottom of the crown
            fork = np.array([np.clip((w - 1) / 2 + rng.normal(0, p.fork_jitter * w), 0, w - 1),
                             np.clip(p.crown_bottom * h, 0, root[1] - 1)])
            res = plan(lat, root, metric=metric, blend_weight=a)
            trunk = build_dendrite(res, fork[None], radius=p.tip_width / 2, iteration=1)
            # main branches: from the upper part of the trunk to sparse, well-spaced
            # endpoints in the upper crown
            k = max(1, round(trunk.n_nodes * (1 - p.trunk_share)))
            seeds = np.zeros(h * w, bool)
            seeds[trunk.nodes[k - 1:]] = True
            split = h * (p.crown_top + 0.7 * (p.crown_bottom - p.crown_top))
            upper = crown & (np.arange(h)[:, None] < split)
            ends = stipple(upper.astype(float), n_i, iterations=15, rng=rng)
            res = plan(lat, seeds.reshape(h, w), metric=metric, blend_weight=a)
            d = build_dendrite(res, ends, base=trunk, radius=p.tip_width / 2, iteration=1)
            ends = np.vstack([fork[None], ends])
            radii.append(float("nan"))
        else:
            r_i = p.radius * p.radius_decay ** (i - 2)
            mask = np.zeros(h * w, bool)
            mask[d.nodes] = True
            mask = mask.reshape(h, w)
            region = ndimage.binary_dilation(crown, iterations=max(int(r_i / 2), 1))
            ends = rejection_endpoints(mask, n_i, r_i, min_distance=p.min_distance * r_i,
                                       region=region, rng=rng)
            radii.append(r_i)
            if len(ends) == 0:
                endpoints.append(ends)
                metrics.append((metric, a))
                continue
            res = plan(lat, mask, metric=metric, blend_weight=a)
            grown = d.with_radius(d.radius + p.increment / 2)  # existing nodes thicken
            d = build_dendrite(res, ends, base=grown, radius=p.tip_width / 2, iteration=i)
        endpoints.append(ends)
        metrics.append((metric, a))
    if p.pipe > 0:
        d = d.with_radius(d.radius + _pipe_width(d, p.tip_width, p.pipe) / 2)
    return GrownTree(d, endpoints, metrics, radii, dataclasses.replace(user))


def _scaled_lengths(p: TreeParams, shape) -> TreeParams:
    """``p`` with its lengths (px of a 512 x 512 canvas) scaled to ``shape`` when
    ``p.scale_lengths`` (not checked against the fields' ranges: a large canvas
    may need a radius beyond the slider's)."""
    if not p.scale_lengths:
        return p
    from .scale import length_scale

    k = length_scale(shape)
    return dataclasses.replace(p, radius=p.radius * k, increment=p.increment * k, pipe=p.pipe * k,
                               tip_width=p.tip_width * k)


@checked(color=Colour(), smooth=Int(0, 10_000))
def render_tree(dendrite: Dendrite, *, background=None, color=(0.24, 0.16, 0.09),
                smooth: int = 4) -> Rendering:
    """Draw a tree: brown branches, smoothed a little (see :func:`render_plain`).

    Parameters
    ----------
    dendrite : Dendrite
        The tree, drawn with widths ``2 * radius``.
    background : (H, W, C) array_like, optional
        Image to draw on; white by default.
    color : RGB triple
        Bark colour in [0, 1] (dark brown).
    smooth : int
        Averaging passes along the branches; 4.

    Returns
    -------
    Rendering

    Examples
    --------
    >>> t = grow_tree((60, 50), TreeParams(iterations=1), rng=0)
    >>> render_tree(t.dendrite).image.shape
    (60, 50, 3)
    """
    from .render import render_plain

    return render_plain(dendrite, background=background, color=color, smooth=smooth)


@checked(shape=_tree_shape, layers=Int(1, MAX_LAYERS))
def grow_layers(shape, params: TreeParams | None = None, *, layers: int = 3, rng=None,
                base=None) -> list[GrownTree]:
    """Occlusion: ``layers`` trees sharing one trunk (iteration 1), each grown further
    with its own noise. Draw them with :func:`render_layers` (first = farthest).

    Parameters
    ----------
    shape : (int, int)
        ``(H, W)`` of the canvas.
    params : TreeParams, optional
        Growth parameters of every layer (defaults if None).
    layers : int
        Number of trees (>= 1); 3.
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed; each layer gets its own stream drawn from it.
    base : (x, y), optional
        Trunk base point; bottom centre by default.

    Returns
    -------
    list of GrownTree
        ``layers`` trees, all containing the same iteration-1 trunk.

    Raises
    ------
    TypeError
        If an argument is of the wrong kind.
    ValueError
        If ``layers`` is not in ``1..MAX_LAYERS``, ``shape`` is not a canvas
        :func:`grow_tree` accepts or ``base`` lies outside it.

    Examples
    --------
    >>> ts = grow_layers((60, 50), TreeParams(iterations=2, radius=12), layers=2, rng=0)
    >>> len(ts), bool((ts[0].dendrite.nodes[:5] == ts[1].dendrite.nodes[:5]).all())
    (2, True)
    """
    p = check_params(params if params is not None else TreeParams())
    if isinstance(base, GrownTree):
        raise TypeError("base must be an (x, y) point (the trunk's base), got a GrownTree")
    rng = as_rng(rng)
    trunk = grow_tree(shape, dataclasses.replace(p, iterations=1, pipe=0.0), base=base, rng=rng)
    out = []
    for _ in range(layers):
        sub = np.random.default_rng(rng.integers(2**63))
        out.append(grow_tree(shape, p, base=trunk, rng=sub, start_iteration=2)
                   if p.iterations >= 2 else trunk)
    return out


@checked(near=Colour(channels=(3,)), far=Colour(channels=(3,)), smooth=Int(0, 10_000))
def render_layers(trees, *, background=None, near=(0.2, 0.13, 0.07), far=(0.72, 0.68, 0.62),
                  smooth: int = 4) -> Rendering:
    """Draw trees back to front, from the ``far`` colour to the ``near`` colour.

    Parameters
    ----------
    trees : sequence of GrownTree or Dendrite
        Back (far) to front (near); all of one shape (one tree alone is drawn
        in the ``far`` colour, as a list of one is).
    background : (H, W, 3) array_like, optional
        Image to draw on (RGB, or grey / RGBA converted as
        :func:`~branchnb.core.image.as_rgb` does); white by default.
    near : RGB triple
        Colour of the last (front) tree.
    far : RGB triple
        Colour of the first (back) tree; the ones between are interpolated.
    smooth : int
        Averaging passes along the branches; 4.

    Returns
    -------
    Rendering

    Raises
    ------
    TypeError
        If ``trees`` is not a sequence of :class:`GrownTree` or
        :class:`~branchnb.dendrite.dendrite.Dendrite`.
    ValueError
        If ``trees`` is empty or its trees differ in shape, or ``background``
        is not an RGB(A) image of their shape.

    Examples
    --------
    >>> ts = grow_layers((60, 50), TreeParams(iterations=2, radius=12), layers=2, rng=0)
    >>> render_layers(ts).image.shape
    (60, 50, 3)
    """
    if isinstance(trees, (GrownTree, Dendrite)):
        trees = [trees]  # one tree drawn in the near colour
    if isinstance(trees, (str, bytes, dict)) or not hasattr(trees, "__iter__"):
        raise TypeError(f"trees must be a sequence of GrownTree or Dendrite, got {type(trees).__name__}")
    trees = [t.dendrite if isinstance(t, GrownTree) else t for t in trees]
    if not trees:
        raise ValueError("trees is empty")
    for k, d in enumerate(trees):
        if not isinstance(d, Dendrite):
            raise TypeError(f"trees[{k}] must be a GrownTree or a Dendrite, got {type(d).__name__}")
        if d.shape is None or tuple(d.shape) != tuple(trees[0].shape or ()):
            raise ValueError(f"trees[{k}] has shape {d.shape}, expected {trees[0].shape} (one canvas)")
    shape = tuple(trees[0].shape)
    img = np.ones((*shape, 3), np.float32) if background is None else _canvas(trees[0], background)
    n = len(trees)
    cols = [tuple(np.asarray(far) + (np.asarray(near) - np.asarray(far)) * (k / max(n - 1, 1)))
            for k in range(n)]
    layers = []
    for d, c in zip(trees, cols):
        lines = d.polylines(smooth)
        widths = d.widths()
        img = draw_polylines(img, lines, widths=widths, colors=c)
        layers.append((lines, widths, c))
    h, w = shape

    def svg():
        return svg_document((w, h), [(polylines_to_svg(lines, widths=wd, colors=c, size=(w, h)), "")
                                     for lines, wd, c in layers], background=(1, 1, 1))

    return Rendering(img, svg)
