"""Tree variations: a library of processed exemplars and new trees made from them.

This module strings the paper's steps together:

1. every library image is **processed once** (:func:`process_exemplar`):
   normalised, its tree contour ``C`` extracted, the pin points found from
   the crown/trunk split, resampled to ``C_r`` (``N = 2000``) and simplified
   to the cage ``C_s`` (``M = 20``);
2. a **variation** (:func:`make_variation`) combines the ``C_r`` of some
   exemplars (their sharp crown corners matched first, beyond the paper:
   :mod:`~branchnb.trees.corners`) with convex weights (user weights or a Dirichlet draw), fills
   the combined contour for the new alpha mask, simplifies it to the target
   cage, and colours it from the exemplars through mean value coordinates;
   an optional reference tree recolours the result by histogram transfer
   (on flat art part to part, crown to crown and trunk to trunk);
3. **variations of one tree** ``T`` (:func:`tree_variations`) keep ``T``
   recognisable by giving it a guaranteed share ``keep`` of both the shape
   and the colour weights, the rest going to random other exemplars.

:class:`TreeLibrary` holds the processed exemplars and offers the same
operations as methods. Results are :class:`Variation` objects that show
themselves in a notebook.

The steps live in their own modules, all re-exported here: step 1 in
:mod:`~branchnb.trees.processing`, step 3 and morphs in
:mod:`~branchnb.trees.variety`, the library in :mod:`~branchnb.trees.library`
and what drawn trees need beyond the paper (outlines, flatness, one piece,
parts) in :mod:`~branchnb.trees.flat_art`; step 2 stays here.

Examples
--------
>>> from branchnb.trees import TreeLibrary
>>> lib = TreeLibrary.from_data(["tree_rpg_01", "tree_rpg_03"], size=256)
>>> v = lib.variation([0.5, 0.5], rng=1)
>>> v.image.shape, v.names
((256, 256, 4), ('tree_rpg_01', 'tree_rpg_03'))
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace

import cv2
import numpy as np
from scipy import ndimage as ndi

from .. import data as _data
from ..core.image import as_float_image, composite_over
from ..core.io import encode_png
from ..core.params import check_params, param
from ..core.random import as_rng
from ..core.validate import Int, Seq, checked
from .bare import bare_mix, is_bare_alpha, soft_image
from .contour import simplify_contour
from .corners import _fill_tips, _polygonal, _tip_matched
from .flat_art import (
    FLAT_ART_SHARE,
    _drawing_group,
    _exemplar_facets,
    _facet_mix,
    _ink_outline,
    _one_piece,
    _own_holes,
    _pixel_arts,
    _pixel_mix,
    _straight_trunk_mix,
    exemplar_largest_hole,
    exemplar_outline,
    exemplar_parts,
    flat_share,
    one_piece,
    resolve_colour_mode,
)
from .histogram_transfer import _remember_parts, histogram_transfer
from .morph import check_weights, combine_shapes, dirichlet_weights, fill_contour
from .mvc import transfer_colour
from .processing import GROUND_METHODS, TRUNK_METHODS, Exemplar, exemplar_trunk, process_exemplar
from .rim_alpha import exemplar_rim_width, soft_rim
from .sticker import _sticker_mix
from .translucent import SLIT_CROWN, _feather_width, _halo_envelope, _trunk_slit

__all__ = [
    "RPG_TREES",
    "Exemplar",
    "process_exemplar",
    "exemplar_trunk",
    "exemplar_parts",
    "TRUNK_METHODS",
    "GROUND_METHODS",
    "VariationParams",
    "Variation",
    "TreeLibrary",
    "make_variation",
    "variation_weights",
    "nearby_weights",
    "similar_variations",
    "contour_distance",
    "mean_pairwise_distance",
    "tree_variations",
    "morph_sequence",
    "tile_images",
    "one_piece",
    "exemplar_largest_hole",
    "resolve_colour_mode",
    "flat_share",
    "FLAT_ART_SHARE",
    "small_library_keep",
    "exemplar_outline",
    "exemplar_trunk",
]

#: The 14 RPG map sprites of ``branchnb.data``: one consistent drawing style
#: (broadleaf, conifer, bare and palm trees), the default library.
RPG_TREES = tuple(f"tree_rpg_{i:02d}" for i in range(1, 15))


#: Most variations one call makes (a size guard: each is a full-resolution image).
MAX_VARIATIONS = 10_000


# ----------------------------------------------------------------------------- variations


@dataclass
class VariationParams:
    """Parameters of variation synthesis (defaults: the paper's).

    Parameters
    ----------
    m_points : int
        ``M``, vertices of the simplified contours (cages) used by the
        colour transfer (paper: 20, its speed/quality sweet spot).
    n_mix : int
        Random variations mix this many exemplars, picked at random from
        the selection (0: all of them). The paper draws random convex
        weights without naming a distribution; mixing all of a dozen trees
        at once averages them into the same blob every time, while two or
        three per draw give distinct trees in the style of the library.
    concentration : float
        Dirichlet parameter ``alpha`` of random shape weights over the
        mixed exemplars (1: uniform on the simplex).
    colour_concentration : float
        Dirichlet parameter of the random colour weights (the paper's
        "random convex combination"). The default 0.3 usually lets one
        exemplar dominate the colour, which keeps drawn details (outlines,
        branches) from ghosting; raise it for smoother mixes.
    keep : float
        Variations of one tree ``T``: share of the weights ``T`` keeps.
    colour_mode : {"auto", "blend", "choose"}
        How the exemplars' colours combine (:func:`~branchnb.trees.mvc.transfer_colour`):
        ``"blend"`` is the paper's convex combination per pixel, right for
        photographs; ``"choose"`` (beyond the paper) gives every region the
        colour of one exemplar, with graph-cut seams along the outlines, so
        drawn trees keep flat colours instead of cross-fading into
        half-transparent overlays; ``"auto"`` chooses when the mixed
        exemplars are drawn: when on average at least :data:`FLAT_ART_SHARE`
        of their opaque pixels lie in flat colour areas
        (:func:`~branchnb.trees.quality.flat_pixels`; drawn trees measure
        0.05-0.9, photographs about 0.01).
    region_scale : float
        ``"choose"``: size of the colour regions as a share of the tree.
    seam : float
        ``"choose"``: weight of the seam cost (0: regions as drawn, no cut).
    choose_by : {"parts", "regions"}
        ``"choose"`` (beyond the paper): ``"parts"`` takes the whole crown
        from one exemplar and the whole trunk from one exemplar (drawn with
        probabilities the colour weights), so a mix reads as one drawing:
        the crown's clumps, layers and fruits whole and in one style, its
        outline continuous, one trunk colour. ``"regions"`` cuts the tree
        into random regions of several exemplars with graph-cut seams
        (``region_scale``, ``seam``): on clip art such mixes read as
        collages (stroke fragments inside the crown, a patch of another
        style, a fruit alone on a conifer).
    outline : bool
        Beyond the paper: when the exemplars holding at least half the
        colour weight have an outlined silhouette
        (:func:`~branchnb.trees.outline.silhouette_outline`, drawn trees),
        ink the variation's silhouette where the mix cut the outline off
        (:func:`~branchnb.trees.outline.ink_silhouette`), in the ink colour
        and stroke width of the outlined exemplar with the most colour
        weight. Photographs and unoutlined art are left as they are.

    Examples
    --------
    >>> p = VariationParams(n_mix=2)
    >>> p.m_points, p.colour_mode, p.colour_concentration
    (20, 'auto', 0.3)
    """

    m_points: int = param(20, min=6, max=100, step=1, help="M, cage vertices (paper: 20)")
    n_mix: int = param(3, min=0, max=50, step=1,
                       help="exemplars mixed per random variation (0: all)")
    concentration: float = param(1.0, min=0.05, max=20.0, step=0.05, log=True,
                                 help="Dirichlet concentration of random shape weights")
    colour_concentration: float = param(0.3, min=0.05, max=20.0, step=0.05, log=True,
                                        help="Dirichlet concentration of random colour weights")
    keep: float = param(0.5, min=0.0, max=1.0, step=0.05,
                        help="variations of T: minimum weight of T")
    colour_mode: str = param("auto", options=("auto", "blend", "choose"),
                             help="blend colours (paper, photographs) or choose one exemplar "
                                  "per region (drawn trees); auto: by flatness")
    region_scale: float = param(0.15, min=0.02, max=1.0, step=0.01,
                                help="choose: size of the colour regions (share of the tree)")
    seam: float = param(20.0, min=0.0, max=1000.0, step=0.1, log=True,
                        help="choose: weight of the seam cost between regions")
    choose_by: str = param("parts", options=("parts", "regions"),
                           help="choose: whole crown and trunk from one exemplar each (parts) or "
                                "random regions with seams (regions)")
    outline: bool = param(True, help="ink the silhouette of outlined (drawn) trees where the mix "
                                     "cut their outline off")


@dataclass(eq=False)
class Variation:
    """A synthesised tree.

    Parameters
    ----------
    image : (S, S, 4) float32 ndarray
        Straight RGBA with binary alpha (opaque where an exemplar with
        colour weight is opaque inside the new contour), one piece: stray
        islands are dropped and holes larger than the exemplars' own are
        filled (:func:`one_piece`).
    names : tuple of str
        The exemplars combined.
    weights : (k,) ndarray
        Convex shape weights, one per exemplar in ``names``.
    colour_weights : (k,) ndarray
        Convex colour weights.
    resampled : (N, 2) ndarray
        The combined contour ``C_r``.
    cage : (M, 2) ndarray
        Its simplified contour ``C_s`` (the target cage).
    mask : (S, S) bool ndarray
        The filled combined contour.
    reference : str or None
        Name of the histogram-transfer reference, if any.
    colour_mode : str
        How the colours were combined: ``"blend"`` or ``"choose"``
        (``VariationParams.colour_mode`` resolved).
    sources : (S, S) int ndarray or None
        Index into ``names`` of the exemplar each pixel's colour comes from
        (``"choose"``; in ``"blend"`` the one with the most colour weight
        there), -1 where transparent.
    parts : (S, S) uint8 ndarray or None
        0 background, 1 crown, 2 trunk: each pixel's part in the exemplar
        its colour comes from (the exemplars' trunk masks carried through
        the warp), so recolouring (:func:`~branchnb.trees.histogram_transfer.histogram_transfer`)
        needs no new segmentation.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> v = make_variation(lib, [0.7, 0.3], rng=0)
    >>> v.image.shape, v.label(1), v.colour_mode
    ((128, 128, 4), '0.7 tree_rpg_05 + 0.3 tree_rpg_06', 'choose')
    """

    image: np.ndarray
    names: tuple
    weights: np.ndarray
    colour_weights: np.ndarray
    resampled: np.ndarray
    cage: np.ndarray
    mask: np.ndarray
    reference: str | None = None
    colour_mode: str = "blend"
    sources: np.ndarray | None = field(default=None, repr=False)
    parts: np.ndarray | None = field(default=None, repr=False)

    @property
    def rgb(self) -> np.ndarray:
        """The tree over a white background, ``(S, S, 3)``."""
        return composite_over(self.image, (1.0, 1.0, 1.0))

    @checked(digits=Int(0, 12))
    def label(self, digits: int = 2) -> str:
        """Short text: the nonzero weights, e.g. ``"0.6 tree_rpg_01 + 0.4 tree_rpg_03"``.

        Parameters
        ----------
        digits : int
            Decimals of each shape weight (0 to 12).

        Returns
        -------
        str
            ``"<weight> <name>"`` of every exemplar with shape weight > 0,
            joined by ``" + "``.
        """
        return " + ".join(f"{w:.{digits}f} {n}" for n, w in zip(self.names, self.weights) if w > 0)

    def _repr_png_(self) -> bytes:
        return encode_png(self.rgb)


def _as_exemplars(library) -> list[Exemplar]:
    out = _exemplar_list(library)
    if not out:
        raise ValueError("library is empty: add exemplars (TreeLibrary.add) before making variations")
    return out


def _exemplar_list(library) -> list[Exemplar]:
    if isinstance(library, TreeLibrary):
        return list(library.exemplars)
    if isinstance(library, Exemplar):
        return [library]
    if isinstance(library, Sequence) and all(isinstance(e, Exemplar) for e in library):
        return list(library)
    raise TypeError("library must be a TreeLibrary or a sequence of Exemplar, "
                    f"got {type(library).__name__}")


def _select(exemplars: list[Exemplar], use, labels=None) -> list[Exemplar]:
    if use is None:
        return exemplars
    names = [e.name for e in exemplars]
    out = []
    for i, u in enumerate(use):
        label = labels[i] if labels is not None else "use"
        if isinstance(u, (int, np.integer)) and not isinstance(u, bool):
            if not -len(exemplars) <= u < len(exemplars):
                raise ValueError(f"{label}: index {u} out of range for {len(exemplars)} exemplars")
            out.append(exemplars[int(u)])
        elif isinstance(u, str):
            if u not in names:
                raise ValueError(f"{label}: no exemplar named {u!r}; the library has {names}")
            out.append(exemplars[names.index(u)])
        else:
            raise TypeError(f"{label}: entries must be names or indices, got {u!r}")
    if not out:
        raise ValueError("use selects no exemplar")
    return out


def _check_compatible(exemplars: list[Exemplar]) -> None:
    e0 = exemplars[0]
    for e in exemplars[1:]:
        if e.size != e0.size:
            raise ValueError(f"exemplars must share the working size: {e0.name!r} is {e0.size}, "
                             f"{e.name!r} is {e.size}")
        if e.resampled.shape != e0.resampled.shape or e.contour.pin_indices != e0.contour.pin_indices:
            raise ValueError(f"exemplars must share N and the crown share: {e0.name!r} and "
                             f"{e.name!r} differ")


def _random_weights(k: int, n_mix: int, concentration: float, rng) -> np.ndarray:
    """Dirichlet weights over ``n_mix`` exemplars picked at random among ``k`` (0: all)."""
    rng = as_rng(rng)
    m = k if n_mix <= 0 or n_mix >= k else int(n_mix)
    w = np.zeros(k)
    idx = np.sort(rng.choice(k, size=m, replace=False)) if m < k else np.arange(k)
    w[idx] = dirichlet_weights(m, concentration, rng=rng)
    return w


def _weights_from(weights, exemplars, rng, concentration, name="weights", n_mix=0):
    if isinstance(weights, dict):
        names = [e.name for e in exemplars]
        unknown = set(weights) - set(names)
        if unknown:
            raise ValueError(f"{name}: unknown exemplar(s) {sorted(unknown)}")
        weights = [float(weights.get(n, 0.0)) for n in names]
    if weights is None:
        return _random_weights(len(exemplars), n_mix, concentration, rng)
    return check_weights(weights, len(exemplars), name=name)


def _check_overrides(overrides: dict) -> None:
    """``**overrides`` must name VariationParams fields (a typo must not end in a dataclass TypeError)."""
    known = {f.name for f in fields(VariationParams)}
    unknown = sorted(set(overrides) - known)
    if unknown:
        raise TypeError(f"unknown keyword argument(s) {unknown}: overrides must be VariationParams fields "
                        f"({sorted(known)})")


@checked(use=Seq())
def make_variation(library, weights=None, params: VariationParams | None = None, *,
                   use=None, colour_weights=None, reference=None, rng=None,
                   **overrides) -> Variation:
    """Synthesise a new tree as a convex combination of exemplars.

    Parameters
    ----------
    library : TreeLibrary or sequence of Exemplar
        The processed exemplars (same working size and contour layout).
    weights : (k,) array_like or dict, optional
        Convex shape weights ``w_i`` (>= 0, summing to 1), one per selected
        exemplar, or ``{name: weight}`` (missing names get 0). None picks
        ``params.n_mix`` exemplars at random and draws their weights from a
        Dirichlet distribution (``params.concentration``).
    params : VariationParams, optional
        ``m_points`` (M = 20), concentrations, ``keep``.
    use : sequence of str or int, optional
        The exemplars to combine (default: all of ``library``).
    colour_weights : (k,) array_like, dict or "shape", optional
        Convex weights of the exemplars' colours. None draws a random
        convex combination (the paper), ``"shape"`` reuses ``weights``
        (a morph).
    reference : str, Exemplar or (H, W, 4) array_like, optional
        Recolour the result by histogram transfer to this tree
        (:func:`~branchnb.trees.histogram_transfer.histogram_transfer`,
        default ``mode="auto"``: part to part on flat art, per channel on
        photographs).
    rng : int or numpy.random.Generator, optional
        Random weights, the colour regions of ``"choose"`` and its seam
        noise; None draws a fresh seed.
    **overrides
        Fields of ``params``.

    Returns
    -------
    Variation

    Raises
    ------
    ValueError
        Weights negative or not summing to 1, wrong count, exemplars of
        different working sizes, an empty selection.

    Notes
    -----
    Exemplars with zero shape weight take no part (so weights ``(1, 0)``
    return the first exemplar itself). A single exemplar is allowed and
    reproduces it: its only convex combination is itself.

    Beyond the paper: before the contours are combined, their sharp crown
    corners (tier tips, zig-zag and star points, notches; turning at least
    50 degrees) are matched in order and made to share an index
    (:mod:`~branchnb.trees.corners`), so a tip meets a tip instead of the
    middle of a flank: with the paper's arc-length correspondence mixes of
    tiered firs and zig-zag crowns turned their sharp tips into round lumps.
    Crowns without tips (round ones) keep the paper's correspondence, and so
    do outlined mixes of curved crowns (flanks bending off the lines between
    their corners, :func:`~branchnb.trees.corners._flank_bend`: a palm's
    frond tips matched to a conifer's tiers raised the cross-fade); outlined
    polygonal crowns and pixel art (corners at the art-pixel grain, so
    stair-steps are no corners) are matched too. A tip only some exemplars
    hold (crowns with different numbers of points) is kept whole or dropped,
    never scaled into a bump (:func:`~branchnb.trees.corners._tip_matched`).
    ``python -m branchnb.trees._measure_corners`` measures it.

    Beyond the paper: when the dominant exemplar is a bare (leafless) tree
    and the others are at least loosely so (thin limbs, an open crown, no
    leafy blob; :func:`~branchnb.trees.bare.is_bare_alpha`), contour
    combination cannot mix a lattice of 1 px twigs (the contours trace
    every twig and do not correspond: limbs were cut off the trunk, twigs
    turned into clumps). The crowns' envelopes are mixed instead and the
    exemplars' branches warped whole into the mix, with their anti-aliased
    edges; the mix has the dominant's trunk and whole limbs of each
    exemplar by its weight (:mod:`~branchnb.trees.bare`).

    Beyond the paper: when a mixed exemplar is translucent (watercolour,
    airbrushed or glass crowns; :mod:`~branchnb.trees.translucent`), its
    source's own alpha is carried through the colour transfer like the
    colour, and the result's silhouette takes it (its fall-off continued
    just outside): the crown is as translucent as the sources, not an
    opaque cut-out of un-premultiplied colour (much darker on paper).

    Beyond the paper: when every mixed exemplar is pixel art (hard edges,
    at most 32 colours, alpha 0/1, art pixels at least 2 working pixels
    across; :mod:`~branchnb.trees.pixel_art`) and the colours are chosen
    (``colour_mode`` ``"auto"`` or ``"choose"``), the mix is put back on the
    sources' art-pixel grid in their palette, with a one-art-pixel outline
    where they are outlined: pixel art in, pixel art out.

    Beyond the paper: when the crown of a ``"choose"`` mix comes from low-poly exemplars
    (flat-shaded polygon facets tiling an unoutlined crown,
    :func:`~branchnb.trees.lowpoly.facet_palette`), the warp's bent facet edges and the
    mixed contour's lumps are redrawn: every facet as a straight-edged polygon through the
    corners where it meets its neighbours, the silhouette through the crown's own outer
    corners (:func:`~branchnb.trees.lowpoly.straighten_facets`). A hard-edged mix (pixel art on a
    1-px grid, or aliased sources without outline) whose sources all stand on straight trunks
    has its trunk's sides redrawn straight where no crown covers them
    (:func:`~branchnb.trees.trunk_lines.straighten_trunk`).

    Beyond the paper: when every mixed exemplar's source was anti-aliased (not pixel art, not
    hard-edged), the mix's rim is anti-aliased too, its opaque set (alpha >= 0.5) unchanged
    (:func:`~branchnb.trees.rim_alpha.soft_rim`): the edge's pixels take alpha from their
    sub-pixel distance to the silhouette's smoothed edge, on the sources' own ramp, and soft
    pixels outside the nearest opaque colour. ``python -m branchnb.trees._measure_soft_rim``
    measures it.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> v = make_variation(lib, {"tree_rpg_05": 0.3, "tree_rpg_06": 0.7}, rng=0)
    >>> v.weights.tolist()
    [0.3, 0.7]
    """
    p = params if params is not None else VariationParams()
    if overrides:
        _check_overrides(overrides)
        p = replace(p, **overrides)
    check_params(p)
    rng = as_rng(rng)
    exemplars = _select(_as_exemplars(library), use)
    _check_compatible(exemplars)
    w = _weights_from(weights, exemplars, rng, p.concentration, n_mix=p.n_mix)
    if isinstance(colour_weights, str):
        if colour_weights != "shape":
            raise ValueError(f"colour_weights must be weights, None or 'shape', got {colour_weights!r}")
        cw = w.copy()
    elif colour_weights is None:
        cw = np.zeros(len(exemplars))
        idx = np.flatnonzero(w > 0)
        cw[idx] = dirichlet_weights(len(idx), p.colour_concentration, rng=rng)
    else:
        cw = _weights_from(colour_weights, exemplars, rng, p.colour_concentration,
                           name="colour_weights")
    used = np.flatnonzero((w > 0) | (cw > 0))
    s = exemplars[0].size
    mode = resolve_colour_mode(p.colour_mode, [exemplars[i] for i in used])
    pixel = mode == "choose" and len(used) > 1 and _pixel_arts([exemplars[i] for i in used]) is not None
    # low-poly crowns drawn without anti-aliasing pass for pixel art (hard edges, few flat colours);
    # their facets are redrawn straight below instead of re-gridded (trees50, issue 24)
    pixel = pixel and not all(_exemplar_facets(exemplars[i]) is not None for i in used)
    # Outlined and pixel-art mixes are coloured without the rim correction (below).
    inked = pixel or any(_drawing_group(exemplars[i]) & 1 for i in used)
    # Beyond the paper: matched crown tips share an index, so tips meet tips (corners.py). On
    # outlined mixes only when every crown is polygonal: a palm's frond tips matched to a
    # conifer's tiers raised the cross-fade share of variations_of(palm) 0 -> 3.1 %, while outlined
    # firs and stars lost their tips without it (tips per mix x0.00-0.82 -> x0.55-1.09 of the sources').
    shapes = [exemplars[i].resampled for i in used]
    grains = ([a.block * exemplars[i].normalized.scale for a, i in zip(_pixel_arts([exemplars[i] for i in used]), used)]
              if pixel else None)
    pins = exemplars[0].contour.pin_indices
    # Tips held by some sources only are kept whole or dropped (corners._tip_matched); the rim
    # correction maps onto the matched contours, which lie on the sources' own rims.
    rims, spans = shapes, []
    if pixel or not inked or _polygonal([c for c, wi in zip(shapes, w[used], strict=True) if wi > 0], pins):
        # tips not kept are dropped on plain mixes only: flattened on outlined ones they left
        # specks at the re-inked cut (_measure_corners fir_ol flecks 0 -> 2.1 per 1000 px of rim)
        keep = {"drop": False} if inked else {}
        shapes, rims, spans = (_tip_matched(shapes, w[used], pins, **keep) if grains is None
                               else _tip_matched(shapes, w[used], pins, grains, **keep))
    cr = combine_shapes(shapes, w[used])
    # C runs through the border pixel centres: grow the fill by one pixel so
    # the border pixels are coloured too (alpha comes from the samples).
    mask = fill_contour(cr, (s, s))
    mask = cv2.dilate(mask.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    cparams = exemplars[0].contour.params
    cage = simplify_contour(cr, m_points=p.m_points, dilation=cparams.dilation,
                            n_points_crown=cparams.n_crown)
    # bare trees (beyond the paper): the dominant one bare, the others at least loosely so
    bare = (len(used) > 1 and w[used].max() > 0
            and is_bare_alpha(exemplars[used[np.argmax(w[used])]].image[..., 3])
            and all(is_bare_alpha(exemplars[i].image[..., 3], loose=True) for i in used))
    if bare:    # bare trees: envelopes mixed, the dominant's limbs warped whole (bare.py)
        # hard-edged (pixel-art) bare trees stay hard-edged: a soft mix of them would look blurred
        image, sources, trunk = bare_mix([exemplars[i].image if pixel else
                                          soft_image(exemplars[i].image, exemplars[i].normalized.soft_alpha)
                                          for i in used], w[used], cw[used],
                                         [exemplars[i].trunk for i in used], hard=pixel, rng=rng)
    else:
        # Beyond the paper: translucent sources' own alpha rides along (translucent.py).
        clear = [i for i in used if exemplars[i].normalized.alpha_level < 0.5]
        alphas = ([exemplars[i].normalized.soft_alpha if exemplars[i].normalized.soft_alpha is not None
                   else exemplars[i].image[..., 3] for i in used] if clear else None)
        image, sources, trunk, *carried = transfer_colour([exemplars[i].image for i in used],
                                                [exemplars[i].cage(p.m_points) for i in used],
                                                cage, mask, colour_weights=cw[used] / cw[used].sum(),
                                                mode="parts" if mode == "choose" and p.choose_by == "parts" else mode,
                                                region_scale=p.region_scale, seam=p.seam, rng=rng,
                                                return_sources=True, layers=[exemplars[i].trunk for i in used],
                                                groups=[_drawing_group(exemplars[i]) for i in used]
                                                if mode == "choose" else None,
                                                contours=None if inked else (cr, rims), alphas=alphas,
                                                _maps=[exemplars[i]._cages for i in used])
        if spans and not inked:     # outlined and pixel-art mixes are re-inked and re-gridded below
            image, sources, trunk = _fill_tips(image, sources, trunk, cr, spans, mask)
    # Rim correction (beyond the paper) only without an ink outline. On outlined mixes it stretched
    # the sources' strokes where it mapped them onto the mixed rim into bands thicker than
    # 2 width + 2, which _drop_excess kept as dark fills (pen q90/q10 1.58); that is fixed
    # (_has_dark_fill, trees33: a dark region is a fill only when a source has one), but the
    # correction still leaves dark flecks just inside a crown's rim by its fruit and trunk
    # (clip-art close-ups), so it stays off there. Not on pixel art either (back on its grid).
    # "parts": the alpha is the chosen parts' own; a crown's gaps between its branches grow with
    # the warp beyond the exemplars' largest hole and stay open (the cage maps them into a hole
    # of an exemplar); other holes larger than the exemplars' are filled as in the other modes.
    parts_mode = mode == "choose" and p.choose_by == "parts" and len(used) > 1
    own = (_own_holes(image[..., 3] >= 0.5, [exemplars[i] for i in used], cage, p.m_points)
           if parts_mode and not bare else None)
    if not bare and not pixel and mode == "choose" and len(used) > 1:
        # low-poly crowns (beyond the paper): facets redrawn straight, the silhouette through
        # the chosen crown's own corners (lowpoly.py)
        image, sources = _facet_mix(image, [exemplars[i] for i in used], sources, trunk)
    if not bare:    # a bare mix is one piece already (a one-to-one warp of one exemplar)
        image = _one_piece(image, [exemplars[i] for i in used], own_holes=own)
    if not bare and not pixel and not inked and len(used) > 1:
        # hard-edged (aliased, off any art grid) trunks: the warp's bends are steps (trunk_lines.py)
        image, sources, trunk = _straight_trunk_mix(image, [exemplars[i] for i in used], sources, trunk)
    unlined = image     # (an outline or sticker ring drawn below runs round a trunk-top notch)
    if bare:        # no outline, sticker or palette step: its soft alpha and colours stay
        pass
    elif pixel:       # pixel art stays on its grid, in its palette, with a 1-art-pixel outline
        image, sources, trunk = _pixel_mix(image, [exemplars[i] for i in used], cw[used], sources, trunk,
                                           outline=p.outline)
        # a straight trunk side re-gridded after the warp's bend is a staircase (trunk_lines.py)
        image, sources, trunk = _straight_trunk_mix(image, [exemplars[i] for i in used], sources, trunk, grains)
    elif p.outline and len(used) > 1 and (st := _sticker_mix(
            image, [exemplars[i] for i in used], cw[used], w[used],
            np.where(image[..., 3] >= 0.5, sources, -1) if mode == "choose" else None)) is not None:
        image = st                         # sticker trees: border ring, outline ring, fill (sticker.py)
    elif p.outline and len(used) > 1:      # one exemplar: its own shape, its outline intact
        image = _ink_outline(image, [exemplars[i] for i in used], cw[used],
                             np.where(image[..., 3] >= 0.5, sources, -1) if mode == "choose" else None)
    lined = inked or image is not unlined
    sources = used[np.maximum(sources, 0)] * (sources >= 0) - (sources < 0)
    opaque = image[..., 3] >= 0.5
    parts = np.where(opaque, np.where(trunk >= 0.5, 2, 1), 0).astype(np.uint8)
    ref_name = None
    if reference is not None:
        ref_img, ref_name = _reference_image(reference, library)
        ref_ex = _reference_exemplar(reference, library)
        image = histogram_transfer(image, ref_img, labels=parts,
                                   reference_labels=None if ref_ex is None else exemplar_parts(ref_ex))
    if not bare and (clear or not lined):
        # the slit between the trunk's top and the crown is crown: its colour and carried alpha
        # (translucent.py, trees57); opaque mixes keep it as a notch in their silhouette (trees59).
        # Not on outlined or pixel-art mixes: their ink already runs round the notch.
        gap = _trunk_slit(image[..., 3] >= 0.5, mask, parts == 2, 0.0 if clear else SLIT_CROWN)
        if gap.any():
            # ... of the crown nearest it, off the trunk's colour (the sources' trunk runs on
            # inside their crowns, opaque: taken there the slit came out a trunk-coloured bar)
            bark = np.median(image[..., :3][parts == 2], axis=0)
            crown = (parts == 1) & (np.linalg.norm(image[..., :3] - bark, axis=2) > 0.2)
            inner = ndi.binary_erosion(crown, iterations=2)
            if not clear and inner.any():   # opaque: off the crown's rim, whose blended colours no
                crown = inner               # source has (test_trees_ground foreign colour 0.005 -> 0.013)
            _, (iy, ix) = ndi.distance_transform_edt(~(crown if crown.any() else parts == 1),
                                                     return_indices=True)
            image = image.copy()
            image[gap, :3], image[gap, 3] = image[iy[gap], ix[gap], :3], 1.0
            if clear:
                soft = carried[0].copy()
                soft[gap], carried[0] = soft[iy[gap], ix[gap]], soft
            parts[gap], sources[gap] = 1, sources[iy[gap], ix[gap]]
    if not bare and not clear and not pixel:
        # anti-aliased rim (beyond the paper, rim_alpha.py): the opaque set stays as it is
        image = soft_rim(image, [exemplar_rim_width(exemplars[i]) for i in used], w[used] + cw[used])
    sources = np.where(image[..., 3] >= 0.5, sources, -1)
    _remember_parts(image, parts)
    if not bare and clear:
        image = _translucent_alpha(image, carried[0], min(exemplars[i].normalized.alpha_level for i in clear),
                                   max(_feather_width(exemplars[i], FEATHER_MAX) for i in clear),
                                   _halo_envelope([exemplars[i] for i in clear], FEATHER_MAX))
    return Variation(image, tuple(e.name for e in exemplars), w, cw, cr, cage, mask, ref_name, mode, sources,
                     parts)


#: Widest fall-off (px) a translucent mix's alpha is continued by outside its silhouette.
FEATHER_MAX = 24.0


def _translucent_alpha(image: np.ndarray, soft: np.ndarray, level: float,
                       reach_max: float = FEATHER_MAX, envelope=None) -> np.ndarray:
    """``image`` with the carried soft alpha of translucent sources inside its silhouette.

    Beyond the paper: the mix of translucent sources (:mod:`~branchnb.trees.translucent`) keeps
    their alpha instead of an opaque cut-out (whose straight colour, shown opaque, looks much
    darker than the wash on paper). Pixels the carried alpha misses (mapped outside a source's
    silhouette, tips and holes filled after the colour transfer) take the mean carried alpha of
    their 7 x 7 neighbourhood, else of the whole silhouette.

    The fall-off outside the silhouette reaches at most ``reach_max`` px (the widest of the
    sources', :func:`~branchnb.trees.translucent._feather_width`; issue 24, trees48): read from
    the slope just inside alone, a mix whose carried alpha rose slowly there (a warp stretching
    an airbrushed rim) got a halo up to :data:`FEATHER_MAX` px wide. With ``envelope``
    (:func:`~branchnb.trees.translucent._halo_envelope`: airbrushed sources), the alpha outside
    the mix's core is at most the sources' at the same distance from their cores: the warp
    stretched an airbrushed fall-off inside the silhouette too (halo 25 px against the sources'
    11-14 at 256 px). Raising the faint alpha to the sources' profile by distance from the rim
    instead left pale valleys inside the crown where the stretch ran deeper than that profile.
    """
    op = image[..., 3] >= 0.5
    if not op.any():
        return image
    a = np.where(op, soft, 0.0).astype(np.float32)
    miss = op & (a < level)
    if miss.any():
        good = op & ~miss
        fill = float(np.median(a[good])) if good.any() else level
        num = cv2.boxFilter(np.where(good, a, 0.0).astype(np.float32), -1, (7, 7), normalize=False)
        den = cv2.boxFilter(good.astype(np.float32), -1, (7, 7), normalize=False)
        local = np.where(den > 0, num / np.maximum(den, 1e-6), fill)
        a = np.where(miss, np.maximum(local, level), a)
    # The silhouette cuts the sources' fall-off at ``level``: continue it outside at the slope the
    # carried alpha rises with just inside (an airbrushed halo fades out; a pooled or flat rim, which
    # does not rise inwards, keeps a 1 px edge).
    inside = cv2.distanceTransform(op.astype(np.uint8), cv2.DIST_L2, 5)
    band = op & (inside >= 1.5) & (inside <= 4.5)
    slope = float(np.median((a[band] - level) / inside[band])) if band.any() else 0.0
    reach = float(np.clip(level / slope, 1.0, min(FEATHER_MAX, max(reach_max, 1.0)))) if slope > 0 else 1.0
    dist, idx = ndi.distance_transform_edt(~op, return_indices=True)
    ring = ~op & (dist < reach + 1e-6)
    out = image.copy()
    out[..., 3] = np.clip(a, 0.0, 1.0)
    out[..., 3][ring] = level * np.clip(1.0 - (dist[ring] - 0.5) / reach, 0.0, 1.0)
    out[..., :3][ring] = image[..., :3][idx[0][ring], idx[1][ring]]
    if envelope is not None:
        core_level, env = envelope
        core = out[..., 3] >= core_level
        if core.any():
            dc = ndi.distance_transform_edt(~core)
            cap = np.interp(dc, np.arange(len(env)), env, right=0.0)
            out[..., 3] = np.where(core, out[..., 3], np.minimum(out[..., 3], cap))
    return out


def _reference_exemplar(reference, library):
    """The library exemplar a reference names (or is), else None."""
    if isinstance(reference, Exemplar):
        return reference
    if isinstance(reference, str) and isinstance(library, TreeLibrary) and reference in library.names:
        return library[reference]
    return None


def _reference_image(reference, library) -> tuple[np.ndarray, str]:
    if isinstance(reference, Exemplar):
        return reference.image, reference.name
    if isinstance(reference, str):
        if isinstance(library, TreeLibrary) and reference in library.names:
            return library[reference].image, reference
        try:
            return _data.load(reference), reference
        except (KeyError, ValueError, FileNotFoundError) as exc:
            raise ValueError(f"reference: no library tree or sample named {reference!r}") from exc
    return as_float_image(reference, name="reference"), "image"


def tile_images(images: Sequence[np.ndarray], cols: int = 4, *, pad: int = 2,
                background=(1.0, 1.0, 1.0)) -> np.ndarray:
    """Lay same-sized RGB(A) images out in a grid (RGBA composited over ``background``).

    Parameters
    ----------
    images : sequence of (h, w, 3) or (h, w, 4) array_like
        Images of one size, floats in [0, 1]; filled row by row.
    cols : int
        Images per row (at most ``len(images)``).
    pad : int
        Pixels between neighbours.
    background : RGB tuple
        Colour of the gaps and of the empty cells, and under RGBA images.

    Returns
    -------
    (H, W, 3) float32 ndarray
        ``rows * h + (rows - 1) * pad`` by ``cols * w + (cols - 1) * pad``.

    Raises
    ------
    ValueError
        If ``images`` is empty or the sizes differ.

    Examples
    --------
    >>> import numpy as np
    >>> tile_images([np.zeros((4, 4, 3))] * 3, cols=2, pad=1).shape
    (9, 9, 3)
    """
    if not images:
        raise ValueError("images is empty")
    ims = [composite_over(im, background) if np.asarray(im).shape[-1] == 4
           else np.asarray(im, dtype=np.float32) for im in images]
    h, w = ims[0].shape[:2]
    if any(im.shape[:2] != (h, w) for im in ims):
        raise ValueError("images must all have the same size")
    cols = max(1, min(int(cols), len(ims)))
    rows = -(-len(ims) // cols)
    out = np.empty((rows * h + (rows - 1) * pad, cols * w + (cols - 1) * pad, 3), np.float32)
    out[:] = np.asarray(background, np.float32)
    for i, im in enumerate(ims):
        r, c = divmod(i, cols)
        out[r * (h + pad):r * (h + pad) + h, c * (w + pad):c * (w + pad) + w] = im[:, :, :3]
    return out


# The steps that build on make_variation live in their own modules (re-exported here).
from .library import TreeLibrary  # noqa: E402
from .variety import (  # noqa: E402
    contour_distance,
    mean_pairwise_distance,
    morph_sequence,
    nearby_weights,
    similar_variations,
    small_library_keep,
    tree_variations,
    variation_weights,
)

