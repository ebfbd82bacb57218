"""Layer induction: the user's training layers found again in every exemplar.

The paper's terms (Assa & Cohen-Or 2012, section 4), for a pixel ``x`` of an
exemplar and a user layer ``c``:

``S_e(x, c)``
    the normalised earth mover's distance between the colour histogram of
    layer ``c`` (on the training leaf) and that of the ``n x n``
    neighbourhood of ``x`` (``n = 8`` at the paper's resolution).
    **EMD variant used here**: colours in CIELAB, each channel quantised
    into ``bins`` equal bins over the exemplars' joint blade range (the 1st
    to 99th percentile, values outside clipped into the end bins); the
    per-channel 1-D EMD is the L1 distance of the two cumulative
    histograms times the bin width; each channel's EMD is divided by its
    largest possible value (``(bins - 1) / bins`` of the range) and the
    three are averaged with weights proportional to each channel's span in
    Lab units (``lab_units=True``, the default: the EMD measured in CIELAB
    units, so a narrow chroma channel's noise is not blown up to the
    lightness channel's scale; measured on procedural veins this raised the
    training overlap, e.g. 0.735 -> 0.770), so ``S_e`` lies in [0, 1] (0: the same colour
    distribution, 1: all mass at opposite ends of every channel). The local
    cumulative histograms are box filters of the indicator maps
    ``[q(x) <= b]`` over the blade (one OpenCV box filter per bin and
    channel, accumulated on the fly: no per-pixel loop, memory
    ``O(H W)``). Only blade pixels count in a neighbourhood.
``F(x, c) = exp(||x, c||^2 / (eps^2 (1 - S_t(x, c))))``
    the spatial term: ``||x, c||`` is the Euclidean distance transform of
    the user layer registered onto the exemplar. We read ``S_t`` as the
    colour term of the same exemplar at ``x`` (``S_e``): where the colour
    matches, the spatial tolerance widens. The exponent is clipped at 60
    (``F`` at most ``e^60``) so it stays finite.
``D(x, c) = lambda_c F(x, c) + S_e(x, c)``
    the induced layer is ``{x in blade : D(x, c) < delta_c}``.
``delta_c``
    the threshold whose layer ``{D < delta}`` on the training leaf best
    reproduces the user's layer: the maximum of the overlap (IoU, the
    paper's eq. 4), found exactly over all thresholds (:func:`choose_threshold`).
``lambda_c = kappa |cap_e L~e| / |cup_e L~e|``
    with the liberal layers ``L~e = {x : S_e < 0.1 and ||x, c||^2 < 2 eps}``
    brought into the training frame: a structural layer (veins) sits at
    the same place in every exemplar, so its liberal layers overlap and it
    leans on space; a non-structural one (spots) leans on colour.
    **Beyond the paper** (issue 22): a chance overlap of marks at random
    places gives a small ``lambda > 0`` that forbids every mark away from
    the training leaf's; ``lambda = 0`` for a layer of scattered small
    marks whose colour sits no nearer the registered layer than chance
    (:mod:`branchnb.leaves.induction_scatter`, applied in
    :func:`branchnb.leaves.analysis_induce.induce`); veins never count as
    scattered and keep the paper's ``lambda``.

**Scale.** ``eps = 40`` px and ``n = 8`` are the paper's values for leaves
photographed at about 2 MP (1633 x 1225): a leaf filling such a frame
spans about 1100 px and its blade covers about half of its bounding box,
``reference_area = 6e5`` px. Every length is scaled by the leaf's linear
size against that, ``s = sqrt(blade area / reference_area)``:
``eps_px = eps s`` and ``n_px = max(1, round(n s))`` (and at most the
layer's own width, see :func:`layer_neighbourhood`). The liberal radius
``||x, c||^2 < 2 eps`` is read in the paper's pixels
(``||x, c|| < sqrt(80) = 8.9`` px at 2 MP) and scaled the same way:
``||x, c|| < eps_px sqrt(2 / eps)``.

**Residuals** (the paper's Fig. 7): after a layer is induced its pixels are
filled from the rest of the same leaf (:func:`~branchnb.leaves.induction_residual.remove_layer`) and the next
layer is induced on that residual.

**Modules**, by step: the colour term ``S_e`` lives in
:mod:`branchnb.leaves.induction_colour`, the residuals in
:mod:`branchnb.leaves.induction_residual`; every name stays importable from here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.distance import edt as _edt
from ..core.image import as_mask
from ..core.params import param
from .induction_colour import (  # noqa: F401  (importable from here)
    ColourSpace,
    _lab,
    _quantise_lab,
    blade_lab_stats,
    colour_similarity,
    colour_space,
    layer_cdfs,
    quantise,
)
from .induction_residual import remove_layer, telea  # noqa: F401

__all__ = [
    "InductionParams",
    "blade_lab_stats",
    "ColourSpace",
    "colour_space",
    "leaf_scale",
    "scaled_lengths",
    "layer_width",
    "layer_neighbourhood",
    "neighbourhood_candidates",
    "quantise",
    "layer_cdfs",
    "colour_similarity",
    "spatial_term",
    "combined_term",
    "choose_threshold",
    "liberal_layer",
    "layer_weight",
    "remove_layer",
    "telea",
]

_MAX_EXPONENT = 60.0


@dataclass
class InductionParams:
    """Layer-induction parameters; defaults are the paper's.

    Lengths are in pixels of the paper's ~2 MP photographs and are scaled
    with each leaf (:func:`scaled_lengths`).

    Parameters
    ----------
    eps : float
        ``eps``, the spatial tolerance of ``F`` (paper: 40 px at ~2 MP).
    kappa : float
        ``kappa`` of ``lambda_c = kappa |cap L~e| / |cup L~e|`` (paper: 1.5).
    neighbourhood : int
        ``n``, side of the neighbourhood whose colour histogram ``S_e``
        compares with the layer's (paper: 8 px at ~2 MP).
    liberal_threshold : float
        ``S_e`` bound of the liberal layers ``L~e`` (paper: 0.1).
    bins : int
        Histogram bins per CIELAB channel (default 32; the paper gives none).
    reference_area : float
        Blade area in pixels of a leaf at the paper's resolution (6e5): the
        leaf scale is ``sqrt(blade area / reference_area)``.
    match_colours : bool
        Move each exemplar's blade colour statistics onto the training
        leaf's before comparing colours (default True; not in the paper:
        leaves of one kind differ in overall hue).
    lab_units : bool
        ``S_e`` as the EMD in CIELAB units, channels weighted by their span
        (default True; False: the three channels weigh alike).
    min_neighbourhood : int
        When the scaled window is smaller, this window is tried as well and
        the training overlap picks (default 3 px; see
        :func:`neighbourhood_candidates`). Not in the paper.
    snap : bool
        Thin layers (veins) follow each exemplar's own ridges, the
        registered layer being a prior (default True; beyond the paper,
        see :mod:`branchnb.leaves.snapping`).
    snap_radius : float
        Search tube around a registered thin layer, in layer widths
        (default 3; at least 1.5 times the registration error).
    """

    eps: float = param(40.0, min=1.0, max=200.0, step=1.0,
                       help="eps: spatial tolerance (px at the paper's ~2 MP; scaled with the leaf)")
    kappa: float = param(1.5, min=0.0, max=10.0, step=0.05,
                         help="kappa: lambda = kappa |cap L~| / |cup L~|")
    neighbourhood: int = param(8, min=1, max=32,
                               help="n: side of the neighbourhood of S_e (px at ~2 MP; scaled)")
    liberal_threshold: float = param(0.1, min=0.0, max=1.0, step=0.01,
                                     help="S_e bound of the liberal layers L~e (paper: 0.1)")
    bins: int = param(32, min=4, max=128, help="histogram bins per CIELAB channel")
    reference_area: float = param(6.0e5, min=1.0e3, max=1.0e8, log=True, ui=False,
                                  help="blade area (px) of a leaf at the paper's resolution")
    match_colours: bool = param(True, help="match each exemplar's blade colour statistics to the "
                                             "training leaf's before comparing colours")
    lab_units: bool = param(True, help="S_e as the EMD in CIELAB units (channels weighted by their span)")
    min_neighbourhood: int = param(3, min=1, max=16, ui=False,
                                   help="a smaller scaled window is tried against this one (px)")
    snap: bool = param(True, help="thin layers (veins) follow each exemplar's own ridges "
                                  "(beyond the paper: the registered layer is a prior)")
    snap_radius: float = param(3.0, min=0.5, max=20.0, step=0.5,
                               help="search tube around a registered thin layer, in layer widths "
                                    "(at least 1.5x the registration error)")



def leaf_scale(blade, reference_area: float = 6.0e5) -> float:
    """``s = sqrt(blade area / reference_area)``: the leaf's size against the paper's.

    Parameters
    ----------
    blade : (H, W) bool array_like
        The leaf's blade (not empty).
    reference_area : float
        Blade area in pixels of a leaf at the paper's ~2 MP (default 6e5).

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> round(leaf_scale(np.ones((300, 200), bool)), 4)
    0.3162
    """
    area = float(np.count_nonzero(blade))
    if area <= 0:
        raise ValueError("blade is empty")
    return float(np.sqrt(area / reference_area))


def scaled_lengths(params: InductionParams, blade) -> tuple[float, int, float]:
    """``(eps_px, n_px, liberal_radius_px)`` for a leaf with this ``blade``.

    Parameters
    ----------
    params : InductionParams
        Gives ``eps``, ``neighbourhood`` and ``reference_area``.
    blade : (H, W) bool array_like
        The leaf's blade, whose area sets the scale ``s``.

    Returns
    -------
    eps_px : float
        ``eps s``.
    n_px : int
        ``max(1, round(n s))``.
    liberal_radius_px : float
        ``eps_px sqrt(2 / eps)``, the liberal layers' ``||x, c||`` bound.
    """
    s = leaf_scale(blade, params.reference_area)
    eps_px = params.eps * s
    n_px = max(1, int(round(params.neighbourhood * s)))
    liberal = eps_px * np.sqrt(2.0 / params.eps)
    return float(eps_px), int(n_px), float(liberal)


def layer_width(mask) -> float:
    """Typical width of a layer in pixels: the median of ``2 EDT - 1`` on its skeleton.

    Parameters
    ----------
    mask : (H, W) bool array_like
        The layer (not empty).

    Returns
    -------
    float
        At least 1.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((20, 40), bool); m[8:11, 5:35] = True
    >>> layer_width(m)
    3.0
    """
    from skimage.morphology import skeletonize
    mask = as_mask(mask, name="mask")
    if not mask.any():
        raise ValueError("mask is empty")
    # On the mask's box grown by 1 px within the image: the same EDT and skeleton (the frame is
    # background, or the image's own edge), a fraction of the canvas (called per layer and exemplar).
    ys, xs = np.flatnonzero(mask.any(1)), np.flatnonzero(mask.any(0))
    mask = mask[max(ys[0] - 1, 0):ys[-1] + 2, max(xs[0] - 1, 0):xs[-1] + 2]
    edt = _edt(mask).astype(np.float64)
    skel = skeletonize(mask)
    vals = edt[skel] if skel.any() else edt[mask]
    return float(max(1.0, np.median(2.0 * vals - 1.0)))


def layer_neighbourhood(params: InductionParams, blade, layer_mask) -> int:
    """The neighbourhood side ``n`` of ``S_e`` for one layer on one leaf (odd, centred).

    The paper's 8 px window at ~2 MP is about as wide as a main vein of its
    leaves. Scaled to a smaller leaf (``8 s``) it can grow wider than the
    layer itself, and a window mostly outside a thin layer no longer tells
    the layer's colour: so ``n`` is also capped by the layer's typical width
    (:func:`layer_width`), and rounded to an odd size so the window is
    centred on ``x``.

    Parameters
    ----------
    params : InductionParams
        Gives ``neighbourhood`` (``n``) and the scale.
    blade : (H, W) bool array_like
        The leaf's blade.
    layer_mask : (H, W) bool array_like
        The layer (on the training leaf).

    Returns
    -------
    int
        Odd, at least 1.
    """
    _, n_scaled, _ = scaled_lengths(params, blade)
    n = min(float(n_scaled), layer_width(layer_mask))
    n = int(np.floor(n))
    if n % 2 == 0:
        n -= 1
    return max(1, n)


def neighbourhood_candidates(params: InductionParams, blade, layer_mask) -> list[int]:
    """The window sides ``n`` the induction tries for one layer; the training overlap picks one.

    The paper's window, scaled (:func:`layer_neighbourhood`), and, when
    that is below ``params.min_neighbourhood`` (3), also the 3 x 3 window.
    A one-pixel "neighbourhood" is a point mass, whose EMD to a layer's
    colour distribution is at least that distribution's spread: for a
    layer of crisp colour (a procedural vein) it still separates, for a
    faint one (a 1-2 px maple vein in a ~250 px photo) ``S_e`` becomes
    per-pixel noise that no threshold (the liberal layers' 0.1 above all)
    can read, and a 3 x 3 window is the smallest with a histogram. Which of
    the two holds is the data's: :func:`branchnb.leaves.analysis.induce`
    keeps the one whose layer ``{D < delta}`` best reproduces the user's
    layer on the training leaf, the paper's own criterion for ``delta``
    (eq. 4). Measured: procedural veins at 640 px, training IoU 0.87 at
    n = 1 against 0.71 at n = 3 (IoU with the truth 0.77-0.79 against
    0.52-0.56); maple veins, 0.30 at n = 1 against 0.50 at n = 3.

    Parameters
    ----------
    params : InductionParams
        Gives ``neighbourhood`` and ``min_neighbourhood``.
    blade : (H, W) bool array_like
        The training leaf's blade.
    layer_mask : (H, W) bool array_like
        The user's layer on it.

    Returns
    -------
    list of int
        One or two odd window sides, the scaled paper window first.
    """
    n0 = layer_neighbourhood(params, blade, layer_mask)
    out = [n0]
    if n0 < params.min_neighbourhood:
        m = int(params.min_neighbourhood)
        out.append(m if m % 2 else m + 1)
    return out



def spatial_term(dist, s_e, eps_px: float) -> np.ndarray:
    """``F = exp(||x, c||^2 / (eps^2 (1 - S)))``, exponent clipped at 60.

    Parameters
    ----------
    dist : (H, W) array_like
        ``||x, c||``, distance in pixels to the registered user layer.
    s_e : (H, W) array_like
        ``S_e(x, c)``, the colour term in [0, 1] (clipped below 1).
    eps_px : float
        ``eps`` scaled to the leaf, in pixels.

    Returns
    -------
    (H, W) float32 ndarray
        1 on the layer, growing with the distance; at most ``e^60``.

    Examples
    --------
    >>> import numpy as np
    >>> f = spatial_term(np.array([0.0, 10.0]), np.zeros(2), 10.0)
    >>> [round(float(v), 4) for v in f]
    [1.0, 2.7183]
    """
    d = np.asarray(dist, np.float32)
    s = np.clip(np.asarray(s_e, np.float32), 0.0, 1.0 - 1e-3)
    expo = np.minimum(d * d / (np.float32(eps_px) ** 2 * (1.0 - s)), _MAX_EXPONENT)
    return np.exp(expo).astype(np.float32)


def combined_term(lam: float, f, s_e) -> np.ndarray:
    """``D = lambda F + S_e``.

    Parameters
    ----------
    lam : float
        ``lambda_c``, the layer's weight of space against colour.
    f : (H, W) array_like
        ``F(x, c)`` (:func:`spatial_term`).
    s_e : (H, W) array_like
        ``S_e(x, c)`` (:func:`~branchnb.leaves.induction_colour.colour_similarity`).

    Returns
    -------
    (H, W) float32 ndarray
    """
    return (np.float32(lam) * np.asarray(f, np.float32) + np.asarray(s_e, np.float32)).astype(np.float32)


def choose_threshold(d, target, blade) -> tuple[float, float]:
    """The ``delta`` maximising IoU(``{D < delta}``, ``target``) over the blade (eq. 4).

    Exact: every cut between distinct values of ``D`` on the blade is a
    candidate; only cuts just above a value of the layer can win, and those
    are evaluated at once (a sort of the layer's values, a binary search of
    the blade's, cumulative counts).

    Parameters
    ----------
    d : (H, W) array_like
        ``D(x, c)`` on the training leaf.
    target : (H, W) bool array_like
        The user's layer (at least one blade pixel).
    blade : (H, W) bool array_like
        The training leaf's blade; only its pixels count.

    Returns
    -------
    delta : float
    overlap : float
        The IoU reached.

    Examples
    --------
    >>> import numpy as np
    >>> d = np.array([[0.1, 0.2, 0.9, 0.8]]); t = np.array([[1, 1, 0, 0]], bool)
    >>> delta, o = choose_threshold(d, t, np.ones((1, 4), bool))
    >>> round(delta, 3), o
    (0.5, 1.0)
    """
    blade = as_mask(blade, name="blade")
    target = as_mask(target, shape=blade.shape, name="target")
    v = np.asarray(d, np.float64)[blade]
    y = target[blade]
    n_t = int(y.sum())
    if n_t == 0:
        raise ValueError("target selects no blade pixel: the user layer is empty")
    # The best cut keeps every value up to one of the layer's own (a cut
    # after a blade-only value loses to the one before it), so only the
    # layer's distinct values are candidates: sort those (few) and count the
    # blade pixels at or below each by a binary search, not one sort of
    # the whole blade (a slider's preview at 1 MP).
    vt = np.unique(v[y])
    vb = v[~y]
    inter = np.cumsum(np.bincount(np.searchsorted(vt, v[y]), minlength=len(vt)))
    below = np.cumsum(np.bincount(np.searchsorted(vt, vb), minlength=len(vt) + 1))[:len(vt)]
    iou = inter / (below + n_t)
    i = int(np.argmax(iou))
    # The next value of the whole blade above the cut.
    up = vb[vb > vt[i]]
    nxt = min(vt[i + 1] if i + 1 < len(vt) else np.inf, up.min() if len(up) else np.inf)
    delta = 0.5 * (vt[i] + nxt) if np.isfinite(nxt) else vt[i] + 1e-6
    return float(delta), float(iou[i])


def liberal_layer(s_e, dist, threshold: float, radius_px: float, blade) -> np.ndarray:
    """``L~e = {x : S_e < threshold and ||x, c|| < radius}`` inside the blade.

    Parameters
    ----------
    s_e : (H, W) array_like
        ``S_e(x, c)``.
    dist : (H, W) array_like
        ``||x, c||`` in pixels.
    threshold : float
        ``S_e`` bound (the paper's 0.1, ``liberal_threshold``).
    radius_px : float
        Distance bound in pixels (the paper's ``||x, c||^2 < 2 eps``, scaled:
        :func:`scaled_lengths`).
    blade : (H, W) bool array_like
        The exemplar's blade.

    Returns
    -------
    (H, W) bool ndarray
    """
    return (np.asarray(s_e) < threshold) & (np.asarray(dist) < radius_px) & np.asarray(blade, bool)


def layer_weight(liberal_in_training, kappa: float) -> tuple[float, float]:
    """``lambda = kappa |cap L~e| / |cup L~e|`` from liberal layers in one frame.

    Returns ``(lambda, overlap)``; ``overlap = 0`` when every liberal layer is empty.

    Parameters
    ----------
    liberal_in_training : sequence of (H, W) bool array_like
        The liberal layers ``L~e`` of all exemplars, brought into the
        training frame (at least one).
    kappa : float
        The paper's ``kappa`` (1.5).

    Returns
    -------
    lambda : float
    overlap : float
        ``|cap L~e| / |cup L~e|``.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.array([1, 1, 0], bool); b = np.array([0, 1, 1], bool)
    >>> layer_weight([a, b], 1.5)
    (0.5, 0.3333333333333333)
    """
    masks = [np.asarray(m, bool) for m in liberal_in_training]
    if not masks:
        raise ValueError("liberal_in_training is empty: need at least one exemplar")
    inter = np.logical_and.reduce(masks)
    union = np.logical_or.reduce(masks)
    nu = int(union.sum())
    overlap = 0.0 if nu == 0 else float(inter.sum() / nu)
    return float(kappa * overlap), overlap

