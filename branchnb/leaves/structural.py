"""Whether an induced layer is structural, and the warnings :func:`~branchnb.leaves.analysis.analyze` gives.

The paper (Assa & Cohen-Or 2012, sec. 4.2) weighs a layer's place on the
leaf by ``lambda = kappa |cap L~e| / |cup L~e|``: a layer whose liberal
copies overlap after registration is *structural* (its place decides where
it is induced), one whose copies do not is induced by colour alone.
:func:`spatial_reach` and :data:`MIN_STRUCTURAL_LAMBDA` turn ``lambda`` and
``delta`` into that judgement.

For a thin layer (veins, snapped to each exemplar's own ridges) the
paper's rule fails both ways (beyond the paper): registered 1-3 px veins
rarely overlap when the registration error is larger than their width, so
true procedural veins get ``lambda`` 0.000-0.02 although they are induced
on the exemplars' own veins (IoU 0.8-0.9), while a vein layer the user
scribbled on plain blade keeps the training leaf's shape on every exemplar
and gets ``lambda`` 0.05-0.07. A thin layer is judged by what it is made
of instead: it is structural when its masks stand out from the blade
around them, in the median over the exemplars and the training leaf
(:func:`layer_standout`, :data:`MIN_STANDOUT`).

:func:`layer_warnings` says in plain words what went wrong;
:func:`warn_analysis` emits them as :class:`NonStructuralLayerWarning`
(and :class:`ShadowAsLeafWarning` for a grey drop or cast shadow left in
a blade) so a script sees them too.
"""

from __future__ import annotations

import warnings

import cv2
import numpy as np

from ..core.image import as_mask, as_rgb
from ..core.morphology import _binary_dilation
from ..core.validate import check_int, check_real

__all__ = [
    "MAX_STRUCTURAL_REACH", "MIN_STRUCTURAL_LAMBDA", "MIN_STANDOUT", "MIN_FOUND", "MIN_SHADOW_SHARE",
    "LeafAnalysisWarning", "NonStructuralLayerWarning", "ShadowAsLeafWarning",
    "spatial_reach", "is_structural", "layer_standout", "shadow_share", "layer_warnings", "warn_analysis",
]

#: A layer is structural (the paper's rule) when its place on the leaf
#: decides where it is induced: a pixel of the layer's exact colour joins
#: it only within this many ``eps`` of the registered layer
#: (:func:`spatial_reach`) ...
MAX_STRUCTURAL_REACH = 3.0
#: ... and its weight ``lambda`` is above this.
MIN_STRUCTURAL_LAMBDA = 0.05
#: A layer scribbled as lines is structural when its masks' colours differ
#: from the blade within 4 px around them by at least this many of that
#: blade's colour spreads (:func:`layer_standout`), in the median over the
#: exemplars and the training leaf. Measured on the four procedural kinds
#: (green and autumn palettes at 192 px, one each at 160 px, 3 leaves):
#: true veins, scribbled or given as masks, 1.38-2.35; the same vein layer
#: given on the same leaves with their veins painted out 0.02-0.29, and
#: on drawn leaves whose ink veins were left out 0.32; the sample maples'
#: faint veins (their stored scribbles on maple_leaf_01 with 3 or 7
#: maples, or hand tracings with maple_leaf_02 / _04 / _06 as training
#: leaf) 0.43-0.64; drawn ink veins ~6.
#: Since the layer and its ring are measured off the outline band and by the smaller of the mean and
#: median contrasts (issue 22: with the snapping's relative floor and damped widths,
#: :data:`~branchnb.leaves.snapping.RELATIVE_EVIDENCE`, a vein layer on a gradient drawing without
#: veins went 0.38 -> 0.44, on its ink outline, and one scribbled on a painted-out lobed leaf 0.38 ->
#: 0.41, through a brown spot; ``python -m branchnb.leaves._measure_structural``, snapping rules on):
#: true procedural veins 1.64-2.34, drawn ink veins 3.4-4.1; the maples 0.54-0.71; veins painted out
#: 0.00-0.03, scribbled on painted-out leaves 0.11-0.28 (the lobed one of the app test 0.09), given on
#: gradient drawings without veins (5 kinds / sizes, 1 and 2 px outlines) 0.00-0.13.
MIN_STANDOUT = 0.4
#: An exemplar on which a layer scribbled as lines covers less than this
#: share of the blade the training layer covers counts as standing out by
#: 0 (it was not found there: a vein layer given on plain blade kept
#: 7-36 % on some exemplars, its few pixels on dark spots; true veins 75-135 %,
#: the sample maples 57-191 %).
MIN_FOUND = 0.4
#: A blade whose grey, unsaturated rim darker than paper (a drop or cast
#: shadow, :func:`shadow_share`) is at least this share of it is warned about.
MIN_SHADOW_SHARE = 0.01


class LeafAnalysisWarning(UserWarning):
    """Base class of the warnings :func:`~branchnb.leaves.analysis.analyze` emits about its result.

    Examples
    --------
    >>> issubclass(NonStructuralLayerWarning, LeafAnalysisWarning), issubclass(LeafAnalysisWarning, UserWarning)
    (True, True)
    """


class NonStructuralLayerWarning(LeafAnalysisWarning):
    """A layer scribbled as a structure (thin lines) came out non-structural.

    Its message names the layer and its ``lambda``. Silence it with
    ``warnings.simplefilter("ignore", NonStructuralLayerWarning)``, or make
    it an error with ``-W error::branchnb.leaves.NonStructuralLayerWarning``.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     warnings.warn("'veins' ...", NonStructuralLayerWarning)
    >>> caught[0].category.__name__
    'NonStructuralLayerWarning'
    """


class ShadowAsLeafWarning(LeafAnalysisWarning):
    """An exemplar's blade holds a grey, unsaturated rim darker than paper: a shadow taken as leaf.

    Examples
    --------
    >>> issubclass(ShadowAsLeafWarning, UserWarning)
    True
    """


def spatial_reach(lam: float, delta: float) -> float:
    """How far from the registered layer, in units of ``eps``, the layer can be induced (the delta criterion).

    A pixel joins the layer where ``D = lambda F + S_e < delta`` with
    ``F = exp(d^2 / (eps^2 (1 - S_e)))``; for a perfect colour match
    (``S_e = 0``) that is ``d < eps sqrt(ln(delta / lambda))``. ``inf``
    when ``lambda`` is 0 or ``F`` (clipped at ``exp(60)``) never reaches
    ``delta / lambda``: the layer's place does not matter, it is
    induced by colour alone (non-structural).

    Parameters
    ----------
    lam, delta : float
        The layer's ``lambda`` and ``delta`` (eqs. 3-4).

    Returns
    -------
    float

    Examples
    --------
    >>> round(spatial_reach(0.5, 1.0), 3), spatial_reach(0.0, 1.0), round(spatial_reach(1e-9, 5.93e6), 2)
    (0.833, inf, 6.03)
    """
    lam = check_real(lam, "lam", min=0.0)
    delta = check_real(delta, "delta", min=0.0, allow_inf=True)
    if not lam > 0 or not np.isfinite(delta):
        return float("inf")
    if delta <= lam:
        return 0.0
    ratio = np.log(delta / lam)
    return float("inf") if ratio >= 60.0 else float(np.sqrt(ratio))


def is_structural(layer) -> bool:
    """Whether an induced layer leans on its place on the leaf.

    A layer scribbled as thin lines (one with ``standout`` figures) is
    structural when its masks stand out from their blades by at least
    :data:`MIN_STANDOUT` in the median over the exemplars, the training
    leaf included (beyond the paper, see the module notes). Any other layer by
    the paper's rule: ``lambda`` above :data:`MIN_STRUCTURAL_LAMBDA` and
    :func:`spatial_reach` at most :data:`MAX_STRUCTURAL_REACH` (in ``eps``).

    Parameters
    ----------
    layer : LayerInduction
        One induced layer of a :class:`~branchnb.leaves.analysis.LeafAnalysis`
        (its ``lam``, ``delta`` and, for a thin layer, ``standout``).

    Returns
    -------
    bool

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> is_structural(NS(lam=0.5, delta=1.0, standout=None)), is_structural(NS(lam=0.0, delta=1.0, standout=None))
    (True, False)
    >>> is_structural(NS(lam=0.0, delta=0.2, standout=[1.4, 1.2, 0.9])), is_structural(NS(lam=0.3, standout=[0.2, 0.1]))
    (True, False)
    """
    if not hasattr(layer, "lam"):
        raise TypeError(f"layer must be a LayerInduction (with its lam and delta), got {type(layer).__name__}")
    standout = getattr(layer, "standout", None)
    if standout is not None:
        values = [s for s in standout if s is not None]
        return bool(values) and float(np.median(values)) >= MIN_STANDOUT
    return layer.lam > MIN_STRUCTURAL_LAMBDA and spatial_reach(layer.lam, layer.delta) <= MAX_STRUCTURAL_REACH


def layer_standout(image, blade, mask, *, ring: int = 4, margin: float = 2.0) -> float | None:
    """How much a layer stands out from the blade around it, in units of that blade's colour spread.

    ``min(|mean(layer) - mean(ring)|, |median(layer) - median(ring)|) / |std(ring)|``
    in CIELAB (medians per channel), the ring being
    the blade pixels within ``ring`` px of the layer (not the layer), both
    taken more than ``margin`` px inside the blade's outline (of the blade
    with the gaps between its paint strokes closed). A vein stands out
    (procedural veins 1.3-2.4, faint maple veins 0.4-1.4); lines drawn on
    plain blade do not (0.02-0.45). Beyond the paper.

    The outline band is left out because a blade's edge is no vein but is
    often dark (a drawing's ink outline, a photo's shaded rim): a vein
    layer given on a gradient-filled drawing without veins was snapped
    onto its ink outline in long stretches, and measured with the band its
    masks stood out by 0.38-0.55 (above :data:`MIN_STANDOUT` once the
    snapping dropped its faint inner paths); without it, by 0.07-0.17.
    :func:`~branchnb.leaves.analysis.analyze` stores it for each exemplar
    in ``LayerInduction.standout`` (0 where the layer covers under
    :data:`MIN_FOUND` of the training leaf's share of the blade).

    Parameters
    ----------
    image : (H, W, 3) float array_like
        RGB in [0, 1].
    blade : (H, W) bool array_like
        The leaf's blade.
    mask : (H, W) bool array_like
        The layer.
    ring : int
        Width of the blade ring around the layer, in pixels (default 4).
    margin : float
        Pixels of the layer and of its ring within this distance of the
        blade's outline are left out (default 2; 0: none).

    Returns
    -------
    float or None
        None when the layer or its ring is empty.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> img = np.full((40, 40, 3), 0.4, np.float32) + rng.normal(0, 0.01, (40, 40, 3)).astype(np.float32)
    >>> line = np.zeros((40, 40), bool); line[20, 5:35] = True
    >>> blade = np.ones((40, 40), bool)
    >>> round(layer_standout(img, blade, line), 1) < 0.5
    True
    >>> img[line] = 0.2
    >>> layer_standout(img, blade, line) > 3
    True
    >>> edge = np.zeros((40, 40), bool); edge[1:39, 1] = True   # a dark line along the outline only
    >>> img[edge] = 0.05
    >>> layer_standout(img, blade, edge), layer_standout(img, blade, edge, margin=0) > 3
    (None, True)
    """
    img = as_rgb(image, name="image")
    ring = check_int(ring, "ring", min=1, max=1000)
    margin = check_real(margin, "margin", min=0.0, max=1e6)
    blade = as_mask(blade, shape=img.shape[:2], name="blade", like="image")
    mask = as_mask(mask, shape=img.shape[:2], name="mask", like="image") & blade
    if margin > 0 and mask.any():
        from ..core.distance import edt_boxed
        from .analysis_outline import _closed_blade
        # The canvas's own edge counts as outside the blade.
        inner = edt_boxed(np.pad(_closed_blade(blade), 1))[1:-1, 1:-1] > margin
    else:
        inner = np.ones(mask.shape, bool)
    whole = mask
    mask = mask & inner
    if not mask.any():
        return None
    ys, xs = np.nonzero(mask)
    y0, y1 = max(ys.min() - ring - 1, 0), ys.max() + ring + 2
    x0, x1 = max(xs.min() - ring - 1, 0), xs.max() + ring + 2
    m, b = mask[y0:y1, x0:x1], blade[y0:y1, x0:x1] & inner[y0:y1, x0:x1]
    around = _binary_dilation(m, iterations=int(ring)) & b & ~whole[y0:y1, x0:x1]
    if around.sum() < 2:
        return None
    lab = cv2.cvtColor(np.ascontiguousarray(np.clip(img[y0:y1, x0:x1, :3], 0, 1)), cv2.COLOR_RGB2Lab)
    inside, ring_px = lab[m], lab[around]
    # Both the layer's mean and its median pixel must differ: a mean can come from a few of its pixels
    # on a spot, a median from a skewed few (the smaller of the two contrasts).
    d = min(float(np.linalg.norm(inside.mean(0) - ring_px.mean(0))),
            float(np.linalg.norm(np.median(inside, 0) - np.median(ring_px, 0))))
    spread = float(np.linalg.norm(ring_px.std(0)))
    return d / max(spread, 0.5)


def shadow_share(image, blade) -> float:
    """Share of a blade that is a grey drop or cast shadow taken as leaf.

    The test :func:`~branchnb.leaves.exemplar.leaf_exemplar` cuts shadows
    with (grey, unsaturated, darker than the white paper, one-sided, 2 px
    or more out from the leaf's coloured part), run on the exemplar over
    white: 0 for an exemplar made by ``leaf_exemplar``, a drawn maple's
    kept drop shadow ~0.07.

    Parameters
    ----------
    image : (H, W, 3 or 4) float array_like
        The exemplar, RGB or RGBA in [0, 1] (RGBA is put over white).
    blade : (H, W) bool array_like
        Its blade.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((60, 60, 3), np.float32); blade = np.zeros((60, 60), bool)
    >>> blade[10:40, 10:40] = True; img[blade] = (0.3, 0.6, 0.2)
    >>> shadow_share(img, blade)
    0.0
    >>> blade[14:46, 14:46] = True; img[40:46, 14:46] = img[14:46, 40:46] = 0.6   # a grey drop shadow
    >>> round(shadow_share(img, blade), 2)
    0.28
    """
    from .exemplar import _cast_shadow
    rgb = as_rgb(image, name="image")
    blade = as_mask(blade, shape=rgb.shape[:2], name="blade", like="image")
    if not blade.any():
        return 0.0
    ys, xs = np.nonzero(blade)
    pad = 8
    y0, y1 = max(ys.min() - pad, 0), ys.max() + pad + 1
    x0, x1 = max(xs.min() - pad, 0), xs.max() + pad + 1
    lab = cv2.cvtColor(np.ascontiguousarray(np.clip(rgb[y0:y1, x0:x1], 0, 1)), cv2.COLOR_RGB2Lab)
    paper = np.broadcast_to(np.array([100.0, 0.0, 0.0], np.float32), lab.shape)
    shadow = _cast_shadow(blade[y0:y1, x0:x1], lab, paper)
    return float(shadow.sum()) / float(blade.sum())


def _delta_text(delta: float) -> str:
    """``delta`` for a table: F is an exponential, so past 10 it only says "any distance"."""
    return f"{delta:.3f}" if delta < 10 else "> 10 (any distance)"


def _reach_text(layer) -> str:
    r = spatial_reach(layer.lam, layer.delta)
    return "anywhere" if not np.isfinite(r) else f"{r:.1f} ε"


def _standout_text(layer) -> str:
    s = getattr(layer, "standout", None)
    values = [] if s is None else [v for v in s if v is not None]
    if not values:
        return ""
    return (f"; its masks stand out from their blades by {np.median(values):.2f} colour spreads in the median, "
            f"a structure by ≥ {MIN_STANDOUT}")


def _scribbled_as_structure(x) -> bool:
    """Whether layer ``x`` was scribbled as a structure (thin lines; snapped or given ``standout``)."""
    return x.snapped is not None or getattr(x, "standout", None) is not None


def layer_warnings(analysis) -> list[str]:
    """Plain-language warnings about an analysis: a thin layer that came out non-structural, a layer not found.

    Parameters
    ----------
    analysis : LeafAnalysis
        The result of :func:`~branchnb.leaves.analysis.analyze` (its
        ``layers`` with their ``lam``, ``delta``, ``snapped``, ``standout``
        and ``empty`` fields).

    Returns
    -------
    list of str
        One sentence per problem; empty when all is well.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> layer_warnings(NS(layers=[NS(name="veins", lam=0.0, delta=1.0, snapped=[None, None], masks=[1, 1],
    ...                              empty=[])]))[0][:33]
    "'veins' was scribbled as thin lin"
    """
    _check_analysis(analysis)
    out = []
    for x in analysis.layers:
        if _scribbled_as_structure(x) and not is_structural(x):
            out.append(_message(x))
        if x.empty:
            out.append(f"'{x.name}' was not found on exemplar(s) {', '.join('#' + str(e) for e in x.empty)}; "
                       "new leaves take it from the others.")
    return out


def _check_analysis(analysis) -> None:
    """TypeError naming ``analysis`` unless it has the layers of a LeafAnalysis."""
    layers = getattr(analysis, "layers", None)
    if layers is None or isinstance(layers, (str, bytes)) or not hasattr(layers, "__iter__"):
        raise TypeError(f"analysis must be a LeafAnalysis (with its induced layers), got {type(analysis).__name__}")


def _message(x) -> str:
    """The warning about layer ``x``, scribbled as thin lines and come out non-structural."""
    return (f"'{x.name}' was scribbled as thin lines (a structure) but came out non-structural "
            f"(λ = {x.lam:.3f}, δ {'= ' if x.delta < 10 else ''}{_delta_text(x.delta)}: reach "
            f"{_reach_text(x)}{_standout_text(x)}): the exemplars show no lines where it was induced. "
            "Check that the scribbles lie on the training leaf's own veins, and the registration overlays.")


def warn_analysis(analysis, *, stacklevel: int = 2) -> list[str]:
    """Emit :func:`layer_warnings`'s non-structural layers and shadowed blades as warnings.

    One :class:`NonStructuralLayerWarning` per layer scribbled as a
    structure that came out non-structural (naming the layer and its
    ``lambda``), one :class:`ShadowAsLeafWarning` per exemplar whose blade
    holds a shadow (:func:`shadow_share` at least :data:`MIN_SHADOW_SHARE`).
    :func:`~branchnb.leaves.analysis.analyze` calls it.

    Parameters
    ----------
    analysis : LeafAnalysis
        A finished analysis.
    stacklevel : int
        Passed to :func:`warnings.warn` (2: the caller of this function).

    Returns
    -------
    list of str
        The messages emitted.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> import numpy as np, warnings
    >>> a = NS(layers=[NS(name="veins", lam=0.0, delta=1.0, snapped=[None, None], masks=[1, 1], empty=[])],
    ...        exemplars=[], blades=[])
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     _ = warn_analysis(a)
    >>> [w.category.__name__ for w in caught]
    ['NonStructuralLayerWarning']
    """
    _check_analysis(analysis)
    stacklevel = check_int(stacklevel, "stacklevel", min=1, max=100)
    out = []
    for x in analysis.layers:
        if _scribbled_as_structure(x) and not is_structural(x):
            msg = _message(x)
            warnings.warn(msg, NonStructuralLayerWarning, stacklevel=stacklevel + 1)
            out.append(msg)
    for e, (im, b) in enumerate(zip(analysis.exemplars, analysis.blades)):
        share = shadow_share(im, b)
        if share >= MIN_SHADOW_SHARE:
            msg = (f"exemplar #{e}: {share:.1%} of its blade is a grey, unsaturated rim darker than paper (a drop "
                   "or cast shadow taken as leaf); it will show as grey rims on new leaves. Cut it with "
                   "branchnb.leaves.leaf_exemplar or a cleaner alpha.")
            warnings.warn(msg, ShadowAsLeafWarning, stacklevel=stacklevel + 1)
            out.append(msg)
    return out

