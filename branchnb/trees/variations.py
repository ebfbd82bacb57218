"""Tree variations: a library of processed exemplars and new trees made from them.

This module strings the paper's steps together:

1. every library image is **processed once** (:func:`process_exemplar`):
   normalised, its tree contour ``C`` extracted, the pin points found from
   the crown/trunk split, resampled to ``C_r`` (``N = 2000``) and simplified
   to the cage ``C_s`` (``M = 20``);
2. a **variation** (:func:`make_variation`) combines the ``C_r`` of some
   exemplars with convex weights (user weights or a Dirichlet draw), fills
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

Examples
--------
>>> from branchnb.trees import TreeLibrary
>>> lib = TreeLibrary.from_data(["tree_rpg_01", "tree_rpg_03"], size=256)
>>> v = lib.variation([0.5, 0.5], rng=1)
>>> v.image.shape, v.names
((256, 256, 4), ('tree_rpg_01', 'tree_rpg_03'))
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace

import cv2
import numpy as np
from scipy import ndimage as ndi

from .. import data as _data
from ..core.image import as_float_image, as_mask, composite_over, extend_nearest
from ..core.io import encode_png
from ..core.params import check_params, param
from ..core.random import as_rng
from ..core.render import draw_polylines
from ..core.validate import Array, Choice, Int, Real, Seq, check_int, checked
from .contour import ContourParams, TreeContour, simplify_contour, stem_trunk_mask, tree_contour
from .exemplar import (
    ContourSet,
    ExemplarParams,
    Normalized,
    extract_contours,
    normalize_exemplar,
    tree_rgba,
)
from .ground import split_ground
from .histogram_transfer import _remember_parts, histogram_transfer
from .morph import check_weights, combine_shapes, dirichlet_weights, fill_contour
from .mvc import transfer_colour

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
]

#: The 14 RPG map sprites of ``branchnb.data``: one consistent drawing style
#: (broadleaf, conifer, bare and palm trees), the default library.
RPG_TREES = tuple(f"tree_rpg_{i:02d}" for i in range(1, 15))

#: ``colour_mode="auto"`` chooses instead of blending when the mixed exemplars
#: have on average at least this share of their opaque pixels in flat colour
#: areas (:func:`~branchnb.trees.quality.flat_pixels`). Drawn trees measure
#: 0.45-0.83 at 128-256 px (a thin outlined palm at 128 px: 0.047, its
#: outlines take most pixels); the photographed ``tree_cutout_broadleaf``
#: 0.006-0.014: photographs have texture in every 3 x 3 window.
FLAT_ART_SHARE = 0.04

#: Most variations one call makes (a size guard: each is a full-resolution image).
MAX_VARIATIONS = 10_000


# ----------------------------------------------------------------------------- exemplars


@dataclass(eq=False)
class Exemplar:
    """A processed library tree.

    Parameters
    ----------
    name : str
        Label of the exemplar in its library (unique there).
    image : (S, S, 4) float32 ndarray
        The normalised exemplar (binary alpha, black background).
    trunk : (S, S) bool ndarray
        Trunk pixels used for the pin points.
    contours : ContourSet
        Exterior/interior borders; ``contours.tree`` is ``C``.
    contour : TreeContour
        Pin points, ``C_r`` and ``C_s`` (with the default ``M``).
    normalized : Normalized
        The crop/scale that maps the source image to the working image.
    trunk_source : str
        ``"mask"`` (given), ``"segmentation"``
        (:func:`~branchnb.trees.segmentation.segment_tree`) or ``"stem"``
        (the geometric :func:`~branchnb.trees.contour.stem_trunk_mask`).
    ground : (H, W) bool ndarray or None
        Ground clutter cut off the source image before normalisation
        (:func:`~branchnb.trees.ground.split_ground`), in source pixels;
        None when nothing was cut.

    Examples
    --------
    >>> from branchnb import data
    >>> ex = process_exemplar(data.load("tree_rpg_05"), "rpg_05", size=128)
    >>> ex.size, ex.trunk_source, ex.cage(12).shape
    (128, 'segmentation', (12, 2))
    """

    name: str
    image: np.ndarray
    trunk: np.ndarray
    contours: ContourSet
    contour: TreeContour
    normalized: Normalized
    trunk_source: str = "stem"
    ground: np.ndarray | None = field(default=None, repr=False)
    _cages: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def size(self) -> int:
        """Working size ``S``."""
        return int(self.image.shape[0])

    @property
    def alpha(self) -> np.ndarray:
        """Binary opacity ``(S, S)``."""
        return self.image[:, :, 3] >= 0.5

    @property
    def resampled(self) -> np.ndarray:
        """``C_r`` (N, 2)."""
        return self.contour.resampled

    @property
    def vector(self) -> np.ndarray:
        """Mean-subtracted 2N shape vector."""
        return self.contour.vector

    @checked(m_points=Int(3, 100_000))
    def cage(self, m_points: int | None = None) -> np.ndarray:
        """Simplified contour ``C_s`` with ``M = m_points`` vertices (cached).

        Parameters
        ----------
        m_points : int, optional
            ``M`` (>= 3); None uses the exemplar's ``ContourParams.m_points``
            (paper: 20), whose ``C_s`` is ``contour.simplified``. Other
            values are computed from ``C_r`` once and cached.

        Returns
        -------
        (M, 2) float64 ndarray
            The cage, pinned like ``C_r`` (see
            :func:`~branchnb.trees.contour.simplify_contour`).
        """
        p = self.contour.params
        m = p.m_points if m_points is None else int(m_points)
        if m == p.m_points:
            return self.contour.simplified
        if m not in self._cages:
            self._cages[m] = simplify_contour(self.contour.resampled, m_points=m,
                                              dilation=p.dilation, n_points_crown=p.n_crown)
        return self._cages[m]

    @checked()
    def with_trunk(self, trunk, source: str = "mask") -> Exemplar:
        """The same exemplar with another trunk mask (working-image pixels): new pin
        points, ``C_r`` and ``C_s``. Used to apply a corrected segmentation.

        Parameters
        ----------
        trunk : (S, S) array_like
            Trunk pixels in the working image; cut to the opaque pixels. An
            all-False mask means no trunk (``L = R = B``).
        source : str
            Recorded as ``trunk_source`` (default ``"mask"``).

        Returns
        -------
        Exemplar
            A new exemplar; this one is not changed.

        Raises
        ------
        ValueError
            If ``trunk`` is not an (S, S) mask.
        """
        t = as_mask(trunk, shape=self.alpha.shape, name="trunk") & self.alpha
        tc = tree_contour(self.contours.tree, self.alpha, t, self.contour.params)
        return Exemplar(self.name, self.image, t, self.contours, tc, self.normalized, source,
                        self.ground)

    def render(self) -> np.ndarray:
        """RGB: the exemplar with ``C_r``, ``C_s`` and the pin points drawn on it."""
        return self.contour.render(self.image)

    def render_trunk(self) -> np.ndarray:
        """RGB: the exemplar with the trunk tinted red and ``B``, ``R``, ``L`` marked."""
        img = composite_over(self.image, (1.0, 1.0, 1.0))
        img[self.trunk] = 0.45 * img[self.trunk] + 0.55 * np.array([0.9, 0.1, 0.1], np.float32)
        lw = max(1.0, self.size / 300)
        p = self.contour.pins
        for pt, col in ((p.b, (0.9, 0.0, 0.0)), (p.r, (0.0, 0.2, 0.9)), (p.l, (0.8, 0.0, 0.8))):
            img = draw_polylines(img, [np.asarray(pt, float)[None]], widths=8 * lw, colors=col)
        return img

    def _repr_png_(self) -> bytes:
        return encode_png(self.render())


#: How :func:`process_exemplar` finds the trunk when no mask is given.
TRUNK_METHODS = ("auto", "segmentation", "stem")
#: What :func:`process_exemplar` does with clutter at the trunk foot.
GROUND_METHODS = ("cut", "keep")


def exemplar_trunk(image, method: str = "auto", *, rng=0) -> tuple[np.ndarray, str]:
    """Trunk mask of a normalised exemplar and the method that produced it.

    Parameters
    ----------
    image : (S, S, 4) array_like
        A normalised exemplar.
    method : {"auto", "segmentation", "stem"}
        ``"segmentation"``: the crown/trunk segmenter
        (:func:`~branchnb.trees.segmentation.segment_tree`); ``"stem"``: the
        geometric stem estimate (:func:`~branchnb.trees.contour.stem_trunk_mask`);
        ``"auto"``: the segmentation, unless it leaves (almost) no crown (a
        bare tree is all wood), where the pin points would collapse onto
        ``B``; then the stem estimate, so a bare tree's trunk still lines
        up with the trunks of leafy trees. The segmenter adds the narrow
        neck between the crown and the foot when colour missed the trunk
        (``SegmentParams.neck_trunk``).
    rng : int
        Seed of the segmenter's random forest.

    Returns
    -------
    trunk : (S, S) bool ndarray
    source : str
        ``"segmentation"`` or ``"stem"``.

    Examples
    --------
    >>> from branchnb.trees.exemplar import normalize_exemplar
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> norm = normalize_exemplar(synthetic_tree("clean", rng=0, size=64).image, size=64)
    >>> trunk, source = exemplar_trunk(norm.image, "stem")
    >>> bool(trunk[60].any()), source
    (True, 'stem')
    """
    if method not in TRUNK_METHODS:
        raise ValueError(f"trunk must be one of {list(TRUNK_METHODS)}, got {method!r}")
    img = as_float_image(image, name="image")
    alpha = img[:, :, 3] >= 0.5
    if method == "stem":
        return stem_trunk_mask(alpha), "stem"
    from .segmentation import SegmentParams, segment_tree

    # The ground decision was made on the source image (process_exemplar).
    trunk = segment_tree(img, params=SegmentParams(ground=False), rng=rng).trunk & alpha
    crown = alpha & ~trunk
    if method == "auto" and crown.sum() < 0.02 * alpha.sum():
        return stem_trunk_mask(alpha), "stem"
    return trunk, "segmentation"


@checked(trunk_mask=Array(ndim=2))
def process_exemplar(image, name: str = "", *, trunk_mask=None, trunk: str = "auto",
                     ground: str = "cut", exemplar_params: ExemplarParams | None = None,
                     contour_params: ContourParams | None = None, **overrides) -> Exemplar:
    """Process one tree image for the library (normalise, contour, pins, ``C_r``, ``C_s``).

    Parameters
    ----------
    image : (H, W, 4) array_like
        RGBA tree with a transparent background (an RGB picture needs an
        alpha first: :func:`~branchnb.trees.exemplar.alpha_from_background`).
    name : str
        Label of the exemplar.
    trunk_mask : (H, W) array_like, optional
        Trunk pixels in ``image`` (e.g. a hand-corrected segmentation).
    trunk : {"auto", "segmentation", "stem"}
        How to find the trunk without ``trunk_mask`` (see
        :func:`exemplar_trunk`; default: the crown/trunk segmentation, the
        stem estimate for trees without crown).
    ground : {"cut", "keep"}
        ``"cut"``: ground clutter at the trunk foot (leaf piles, grass,
        shadows, rocks, a hill or a stand) is cut off before anything else
        (:func:`~branchnb.trees.ground.split_ground`), so ``B`` is the trunk
        foot, the tree stands on the bottom edge like every other exemplar
        and no variation maps a trunk onto a leaf pile; ``"keep"``: the
        whole silhouette is the tree (the paper's clean cut-outs).
    exemplar_params : ExemplarParams, optional
        Normalisation (``size`` S = 1024, alpha threshold 0.5, components).
    contour_params : ContourParams, optional
        ``N``, crown share, ``M``, dilation.
    **overrides
        Fields of either parameter set, e.g. ``size=512`` or ``m_points=30``.

    Returns
    -------
    Exemplar

    Raises
    ------
    ValueError
        No alpha channel, fully transparent/opaque image, several trees
        with ``components="error"``, a bad trunk mask.

    Examples
    --------
    >>> from branchnb import data
    >>> ex = process_exemplar(data.load("tree_rpg_05"), "rpg_05", size=256)
    >>> ex.resampled.shape, ex.cage().shape, ex.contour.pin_indices
    ((2000, 2), (20, 2), (0, 200, 1800))
    """
    ep = exemplar_params if exemplar_params is not None else ExemplarParams()
    cp = contour_params if contour_params is not None else ContourParams()
    e_fields = {f for f in ExemplarParams.__dataclass_fields__}
    c_fields = {f for f in ContourParams.__dataclass_fields__}
    unknown = set(overrides) - e_fields - c_fields
    if unknown:
        raise TypeError(f"unknown parameter(s) {sorted(unknown)}; "
                        f"ExemplarParams: {sorted(e_fields)}, ContourParams: {sorted(c_fields)}")
    ep = replace(ep, **{k: v for k, v in overrides.items() if k in e_fields})
    cp = replace(cp, **{k: v for k, v in overrides.items() if k in c_fields})
    if ground not in GROUND_METHODS:
        raise ValueError(f"ground must be one of {list(GROUND_METHODS)}, got {ground!r}")
    cut = None
    if ground == "cut":
        img, opaque = tree_rgba(image, alpha_threshold=ep.alpha_threshold)
        split = split_ground(img)
        if split.has_ground:
            cut = split.ground
            image = split.cut(img)
    norm = normalize_exemplar(image, ep)
    if trunk_mask is None:
        tmask, source = exemplar_trunk(norm.image, trunk)
    else:
        tmask, source = norm.warp_mask(trunk_mask) & norm.alpha, "mask"
    contours = extract_contours(norm.alpha)
    tc = tree_contour(contours.tree, norm.alpha, tmask, cp)
    return Exemplar(str(name), norm.image, tmask, contours, tc, norm, source, cut)


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
    cr = combine_shapes([exemplars[i].resampled for i in used], w[used])
    # C runs through the border pixel centres: grow the fill by one pixel so
    # the border pixels are coloured too (alpha comes from the samples).
    mask = fill_contour(cr, (s, s))
    mask = cv2.dilate(mask.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    cparams = exemplars[0].contour.params
    cage = simplify_contour(cr, m_points=p.m_points, dilation=cparams.dilation,
                            n_points_crown=cparams.n_crown)
    mode = resolve_colour_mode(p.colour_mode, [exemplars[i] for i in used])
    image, sources, trunk = transfer_colour([exemplars[i].image for i in used],
                                            [exemplars[i].cage(p.m_points) for i in used],
                                            cage, mask, colour_weights=cw[used] / cw[used].sum(),
                                            mode="parts" if mode == "choose" and p.choose_by == "parts" else mode,
                                            region_scale=p.region_scale, seam=p.seam, rng=rng,
                                            return_sources=True, layers=[exemplars[i].trunk for i in used],
                                            groups=[int(exemplar_outline(exemplars[i]).outlined) for i in used]
                                            if mode == "choose" else None)
    # "parts": the alpha is the chosen parts' own, holes included (a crown's gaps between its
    # branches grow with the warp beyond the exemplars' largest hole and must not be filled).
    parts_mode = mode == "choose" and p.choose_by == "parts" and len(used) > 1
    image = _one_piece(image, [exemplars[i] for i in used], fill_holes=not parts_mode)
    if p.outline and len(used) > 1:      # one exemplar: its own shape, its outline intact
        image = _ink_outline(image, [exemplars[i] for i in used], cw[used],
                             np.where(image[..., 3] >= 0.5, sources, -1) if mode == "choose" else None)
    sources = used[np.maximum(sources, 0)] * (sources >= 0) - (sources < 0)
    opaque = image[..., 3] >= 0.5
    parts = np.where(opaque, np.where(trunk >= 0.5, 2, 1), 0).astype(np.uint8)
    ref_name = None
    if reference is not None:
        ref_img, ref_name = _reference_image(reference, library)
        ref_ex = _reference_exemplar(reference, library)
        image = histogram_transfer(image, ref_img, labels=parts,
                                   reference_labels=None if ref_ex is None else exemplar_parts(ref_ex))
    sources = np.where(image[..., 3] >= 0.5, sources, -1)
    _remember_parts(image, parts)
    return Variation(image, tuple(e.name for e in exemplars), w, cw, cr, cage, mask, ref_name, mode, sources,
                     parts)


def exemplar_outline(exemplar: Exemplar):
    """:func:`~branchnb.trees.outline.silhouette_outline` of an exemplar (cached on it).

    Parameters
    ----------
    exemplar : Exemplar
        A processed exemplar; the measure is stored on it and reused.

    Returns
    -------
    SilhouetteOutline
        Ink share, colour and stroke width along the silhouette.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> exemplar_outline(lib["tree_rpg_05"]).outlined  # a drawn sprite
    True
    """
    if "outline" not in exemplar._cages:
        from .outline import silhouette_outline

        exemplar._cages["outline"] = silhouette_outline(exemplar.image)
    return exemplar._cages["outline"]


def _ink_outline(image: np.ndarray, exemplars: Sequence[Exemplar], cw: np.ndarray,
                 sources: np.ndarray | None = None) -> np.ndarray:
    """Ink the silhouette when outlined exemplars hold at least half the colour weight, and
    (``sources``: the ``"choose"`` mode's source per pixel) the seams that cross a fill."""
    from .outline import ink_seams, ink_silhouette

    outl = [exemplar_outline(e) for e in exemplars]
    on = np.array([o.outlined for o in outl])
    if sources is not None:
        # "choose": what the pixels show decides (a crown from an outlined tree is outlined
        # whatever its colour weight), not the weights.
        cw = np.bincount(sources[sources >= 0], minlength=len(exemplars)).astype(np.float64)
    if cw[on].sum() < 0.5 * cw.sum() - 1e-9 or not on.any():
        return image
    best = outl[int(np.argmax(np.where(on, cw, -1.0)))]
    if sources is not None:
        image = ink_seams(image, sources, best.ink, best.width)
    return ink_silhouette(image, best.ink, best.width)


def flat_share(exemplar: Exemplar) -> float:
    """Share of an exemplar's opaque pixels in flat colour areas (cached on the exemplar).

    Parameters
    ----------
    exemplar : Exemplar
        A processed exemplar.

    Returns
    -------
    float
        :func:`~branchnb.trees.quality.flat_pixels` over the opaque pixels,
        in [0, 1]: drawn trees measure 0.05-0.9, photographs about 0.01.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> flat_share(lib["tree_rpg_05"]) > FLAT_ART_SHARE
    True
    """
    if "flat_share" not in exemplar._cages:
        from .quality import flat_pixels

        n = max(int(exemplar.alpha.sum()), 1)
        exemplar._cages["flat_share"] = float(flat_pixels(exemplar.image).sum() / n)
    return exemplar._cages["flat_share"]


def resolve_colour_mode(mode: str, exemplars: Sequence[Exemplar]) -> str:
    """``"blend"`` or ``"choose"`` for ``mode`` (``"auto"``: by the exemplars' :func:`flat_share`).

    Parameters
    ----------
    mode : {"auto", "blend", "choose"}
        ``VariationParams.colour_mode``; ``"blend"`` and ``"choose"`` are
        returned as they are.
    exemplars : sequence of Exemplar
        The exemplars mixed; ``"auto"`` chooses when their mean flat share
        is at least :data:`FLAT_ART_SHARE` (an empty list blends).

    Returns
    -------
    str
        ``"blend"`` or ``"choose"``.

    Raises
    ------
    ValueError
        Unknown ``mode``.

    Examples
    --------
    >>> resolve_colour_mode("blend", []), resolve_colour_mode("auto", [])
    ('blend', 'blend')
    """
    if mode not in ("auto", "blend", "choose"):
        raise ValueError(f"colour_mode must be 'auto', 'blend' or 'choose', got {mode!r}")
    if mode != "auto":
        return mode
    share = float(np.mean([flat_share(e) for e in exemplars])) if exemplars else 0.0
    return "choose" if share >= FLAT_ART_SHARE else "blend"


def _holes(alpha: np.ndarray) -> tuple[np.ndarray, int]:
    """Transparent regions not connected to the image border, and their count."""
    lab, n = ndi.label(~alpha)
    border = np.unique(np.concatenate([lab[0], lab[-1], lab[:, 0], lab[:, -1]]))
    holes = (lab > 0) & ~np.isin(lab, border)
    return holes, int(n - np.count_nonzero(border > 0))


def exemplar_largest_hole(exemplar: Exemplar) -> int:
    """Area (pixels) of the largest interior transparent hole of an exemplar.

    Parameters
    ----------
    exemplar : Exemplar
        A processed exemplar (its binary alpha at the working size).

    Returns
    -------
    int
        Pixels of the largest transparent 4-connected region that does not
        touch the image border (0 without holes); :func:`one_piece` fills
        larger holes in a variation.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> exemplar_largest_hole(lib["tree_rpg_05"]) >= 0
    True
    """
    holes, _ = _holes(exemplar.alpha)
    if not holes.any():
        return 0
    lab, _ = ndi.label(holes)
    return int(np.bincount(lab.ravel())[1:].max())


def one_piece(image, exemplars: Sequence[Exemplar]) -> np.ndarray:
    """Keep a variation in one piece, like its exemplars.

    The largest opaque component (8-connected) is kept; other components
    are kept only if some exemplar has several pieces and they are at least
    as large as that exemplar's smallest piece, and never more pieces than
    the most broken-up exemplar has (the largest ones). Interior transparent holes
    larger than the largest hole of the exemplars are filled, with the
    colour of the nearest opaque pixel.

    Parameters
    ----------
    image : (S, S, 4) array_like
        Straight RGBA with binary alpha.
    exemplars : sequence of Exemplar
        The exemplars that were mixed.

    Returns
    -------
    (S, S, 4) float32 ndarray

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> ex = process_exemplar(synthetic_tree("clean", rng=0, size=64).image, size=64, trunk="stem")
    >>> img = ex.image.copy(); img[0, 0] = (0.0, 0.6, 0.0, 1.0)     # a stray speck
    >>> float(one_piece(img, [ex])[0, 0, 3])
    0.0
    """
    return _one_piece(image, exemplars)


def _one_piece(image, exemplars: Sequence[Exemplar], fill_holes: bool = True) -> np.ndarray:
    img = np.array(image, dtype=np.float32, copy=True)
    alpha = img[:, :, 3] >= 0.5
    if not alpha.any():
        return img
    lab, n = ndi.label(alpha, structure=np.ones((3, 3), bool))
    if n > 1:
        areas = np.bincount(lab.ravel())
        areas[0] = 0
        keep = areas >= areas.max()
        pieces = [np.bincount(ndi.label(e.alpha, structure=np.ones((3, 3), bool))[0].ravel())[1:]
                  for e in exemplars]
        multi = [p.min() for p in pieces if len(p) > 1]
        if multi:
            keep |= areas >= min(multi)
            # Never more pieces than the most broken-up exemplar: a warp can
            # split its thin parts into crumbs, which are no pieces of its own.
            most = max(len(p) for p in pieces)
            order = np.argsort(areas)[::-1]
            keep[order[most:]] = False
        keep[0] = False
        alpha = keep[lab]
    holes, _ = _holes(alpha)
    if holes.any() and fill_holes:
        limit = max((exemplar_largest_hole(e) for e in exemplars), default=0)
        hl, _ = ndi.label(holes)
        sizes = np.bincount(hl.ravel())
        sizes[0] = 0
        fill = (sizes > limit)[hl] & holes
        if fill.any():
            img[fill, :3] = extend_nearest(img[:, :, :3], alpha)[fill]
            alpha = alpha | fill
    img[~alpha] = 0.0
    img[:, :, 3] = alpha
    return img


def exemplar_parts(exemplar: Exemplar) -> np.ndarray:
    """An exemplar's parts as :func:`~branchnb.trees.histogram_transfer.tree_parts` labels its image.

    Parameters
    ----------
    exemplar : Exemplar
        A processed exemplar; its stored trunk mask splits the opaque pixels.

    Returns
    -------
    (S, S) uint8 ndarray
        0 background, 1 crown, 2 trunk.

    Examples
    --------
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> img = synthetic_tree("clean", rng=0, size=64).image
    >>> ex = process_exemplar(img, "t", exemplar_params=ExemplarParams(size=64))
    >>> sorted(np.unique(exemplar_parts(ex)).tolist())
    [0, 1, 2]
    """
    if not isinstance(exemplar, Exemplar):
        raise TypeError(f"exemplar must be an Exemplar, got {type(exemplar).__name__}")
    opaque = exemplar.image[..., 3] >= 0.5
    return np.where(opaque, np.where(exemplar.trunk & opaque, 2, 1), 0).astype(np.uint8)


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


def nearby_weights(centre, keep: float = 0.6, *, concentration=1.0, n_mix: int = 0,
                   rng=None) -> np.ndarray:
    """Random convex weights near ``centre``: ``keep centre + (1 - keep) d``.

    ``d`` is a Dirichlet draw over ``n_mix`` exemplars picked at random (0:
    all). Every exemplar keeps at least ``keep`` times its weight in
    ``centre``, so the result stays recognisably like the centre mix.

    Parameters
    ----------
    centre : (k,) array_like
        Convex weights of the centre mix (>= 0, summing to 1).
    keep : float
        Share of ``centre`` kept, in [0, 1] (1: the centre itself).
    concentration : float or (m,) array_like
        Dirichlet parameter ``alpha`` of ``d`` (1: uniform on the simplex).
    n_mix : int
        Exemplars ``d`` spreads over, picked at random (0: all ``k``).
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the picks and the draw.

    Returns
    -------
    (k,) float64 ndarray
        Convex weights.

    Raises
    ------
    ValueError
        If ``centre`` is not convex or ``keep`` is outside [0, 1].

    Examples
    --------
    >>> w = nearby_weights([0.5, 0.5, 0.0], 0.8, rng=0)
    >>> bool(w[0] >= 0.4 and w[1] >= 0.4 and abs(w.sum() - 1) < 1e-12)
    True
    """
    c = check_weights(centre, name="centre")
    if not 0.0 <= float(keep) <= 1.0:
        raise ValueError(f"keep must lie in [0, 1], got {keep}")
    w = keep * c + (1.0 - keep) * _random_weights(len(c), n_mix, concentration, rng)
    return w / w.sum()


def variation_weights(k: int, index: int, keep: float = 0.5, *, concentration=1.0,
                      n_mix: int = 0, rng=None) -> np.ndarray:
    """Random convex weights in which exemplar ``index`` keeps at least ``keep``.

    ``w = keep e_index + (1 - keep) d`` with ``d`` a Dirichlet draw over
    ``n_mix`` exemplars picked at random (0: all ``k``): ``T = index`` keeps
    ``keep`` plus its share of the rest, so it stays recognisable while the
    others vary (:func:`nearby_weights` around a corner of the simplex).

    Parameters
    ----------
    k : int
        Number of exemplars (>= 1).
    index : int
        ``T``, the exemplar kept (negative counts from the end).
    keep : float
        ``T``'s guaranteed share, in [0, 1].
    concentration : float or (m,) array_like
        Dirichlet parameter of ``d``.
    n_mix : int
        Exemplars ``d`` spreads over, picked at random (0: all ``k``, ``T``
        included).
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the picks and the draw.

    Returns
    -------
    (k,) float64 ndarray
        Convex weights with ``w[index] >= keep``.

    Raises
    ------
    ValueError
        If ``k`` is not a positive int or ``index`` is out of range.

    Examples
    --------
    >>> w = variation_weights(4, 2, 0.6, rng=0)
    >>> bool(w[2] >= 0.6 and abs(w.sum() - 1) < 1e-12)
    True
    """
    if not isinstance(k, (int, np.integer)) or k < 1:
        raise ValueError(f"k must be a positive int, got {k!r}")
    if not -k <= index < k:
        raise ValueError(f"index {index} out of range for {k} exemplars")
    return nearby_weights(np.eye(k)[index], keep, concentration=concentration, n_mix=n_mix,
                          rng=rng)


def contour_distance(a, b) -> float:
    """Mean distance (pixels) between corresponding points of two resampled contours ``C_r``.

    Parameters
    ----------
    a, b : (N, 2) array_like
        Two contours with the same pin layout (point ``i`` of one
        corresponds to point ``i`` of the other), in working pixels.

    Returns
    -------
    float
        Mean Euclidean distance of corresponding points, in pixels.

    Raises
    ------
    ValueError
        If the shapes differ or are not (N, 2).

    Examples
    --------
    >>> import numpy as np
    >>> round(contour_distance(np.zeros((4, 2)), np.full((4, 2), 3.0)), 3)
    4.243
    """
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape or a.ndim != 2 or a.shape[1] != 2:
        raise ValueError(f"contours must be (N, 2) arrays of the same shape, got {a.shape} and {b.shape}")
    return float(np.linalg.norm(a - b, axis=1).mean())


def mean_pairwise_distance(contours) -> float:
    """Mean :func:`contour_distance` over all pairs of a list of ``C_r`` (0 for fewer than two).

    Parameters
    ----------
    contours : sequence of (N, 2) array_like
        Resampled contours with the same pin layout.

    Returns
    -------
    float
        Mean over the ``n (n - 1) / 2`` pairs, in pixels; the measure of
        how varied a set of variations (or a library) is.

    Examples
    --------
    >>> import numpy as np
    >>> round(mean_pairwise_distance([np.zeros((3, 2)), np.full((3, 2), 3.0), np.zeros((3, 2))]), 3)
    2.828
    """
    c = [np.asarray(x, float) for x in contours]
    d = [contour_distance(c[i], c[j]) for i in range(len(c)) for j in range(i + 1, len(c))]
    return float(np.mean(d)) if d else 0.0


def _spread(candidates: np.ndarray, shapes: np.ndarray, n: int, centre: np.ndarray,
            first: int | None = None) -> np.ndarray:
    """Indices of ``n`` candidate weight vectors whose contours lie far apart (farthest-point
    sampling on the combined contours ``candidates @ shapes``, starting with candidate
    ``first`` or, if None, the one farthest from the centre's contour)."""
    vec = candidates @ shapes                      # (c, 2N)
    n_pts = shapes.shape[1] // 2
    if first is None:
        d = np.linalg.norm((vec - centre @ shapes).reshape(len(vec), n_pts, 2), axis=2).mean(axis=1)
        first = int(np.argmax(d))
    chosen = [first]
    d = np.linalg.norm((vec - vec[first]).reshape(len(vec), n_pts, 2), axis=2).mean(axis=1)
    while len(chosen) < min(n, len(candidates)):
        nxt = int(np.argmax(d))
        chosen.append(nxt)
        d = np.minimum(d, np.linalg.norm((vec - vec[nxt]).reshape(len(vec), n_pts, 2),
                                         axis=2).mean(axis=1))
    return np.asarray(chosen)


#: "More like this" draws this many candidate mixes per result and keeps the most different.
SPREAD_CANDIDATES = 16


def small_library_keep(k: int, keep: float = 0.3) -> float:
    """Default ``keep`` of :func:`similar_variations` for ``k`` exemplars: ``keep min(1, (k - 1) / 4)``.

    With few exemplars the results can only spread over ``1 - keep`` of
    the exemplars' simplex, so the centre's share shrinks: 0.15 for three
    trees, 0.225 for four, ``keep`` from five on.

    Parameters
    ----------
    k : int
        Number of exemplars in the library.
    keep : float, optional
        The centre's share for five exemplars or more (default 0.3).

    Returns
    -------
    float

    Examples
    --------
    >>> small_library_keep(3), small_library_keep(8)
    (0.15, 0.3)
    """
    return float(keep) * min(1.0, (int(k) - 1) / 4.0)


def _extreme_candidates(centre: np.ndarray, keep: float, n_mix: int) -> np.ndarray:
    """``keep c + (1 - keep) v`` for ``v`` the corners of the simplex and (up to 16
    exemplars) its edge midpoints: the farthest a nearby mix can go."""
    k = len(centre)
    eye = np.eye(k)
    verts = list(eye)
    if k <= 16 and (n_mix <= 0 or n_mix >= 2):
        verts += [(eye[i] + eye[j]) / 2 for i, j in itertools.combinations(range(k), 2)]
    return np.stack([keep * centre + (1.0 - keep) * v for v in verts])


@checked(n=Int(1, MAX_VARIATIONS), keep=Real(0, 1))
def similar_variations(library, variation: Variation, n: int = 6,
                       params: VariationParams | None = None, *, keep: float | None = None,
                       rng=None, **overrides) -> list[Variation]:
    """"More like this": random variations around an existing variation's weights.

    Parameters
    ----------
    library : TreeLibrary or sequence of Exemplar
        Must contain the exemplars of ``variation``.
    variation : Variation
        The centre; its exemplars, shape and colour weights and reference
        are reused.
    n : int
        Number of variations.
    params : VariationParams, optional
        ``n_mix`` and the concentrations of the random part; None uses the
        defaults.
    keep : float, optional
        Share of the centre's weights every new variation keeps
        (:func:`nearby_weights`); the rest is a random Dirichlet mix of
        ``params.n_mix`` exemplars of the same set. None (default): 0.3,
        less for fewer than five exemplars (:func:`small_library_keep`).
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the candidate weights and the colour transfer.
    **overrides
        Fields of ``params`` (e.g. ``n_mix=2``).

    Returns
    -------
    list of Variation
        ``n`` variations, far apart from each other (see Notes).

    Raises
    ------
    ValueError
        If ``library`` lacks one of the variation's exemplars, or the
        variation's reference was an array.
    TypeError
        If ``variation`` is not a Variation or an override is unknown.

    Notes
    -----
    Beyond the paper: independent draws around one centre often land
    close together, so six results look alike. ``SPREAD_CANDIDATES``
    times ``n`` candidate shape weights are drawn and ``n`` of them kept by
    farthest-point sampling on their combined contours (cheap: a contour is
    the weights times the exemplars' ``C_r``), so the results differ as
    much as ``keep`` allows. The candidates also include the farthest
    mixes ``keep`` allows (``keep c + (1 - keep) v`` for every corner and
    edge midpoint ``v`` of the simplex), which random Dirichlet draws
    rarely reach. Still, six results can spread over only ``1 - keep`` of
    the exemplars' simplex: with three trees and ``keep`` = 0.3 at most
    about 0.47 of the exemplars' mean distance (without duplicates), so
    small libraries get a smaller ``keep`` by default
    (:func:`small_library_keep`). Mean pairwise contour distance of six
    results over the mean distance between the library's exemplars, six
    centres each (``python -m branchnb.trees._measure variety 128``):
    four libraries of three trees (three drawn, three RPG sprites) 0.54-0.59,
    worst centre 0.54 (formerly 0.39-0.41, worst 0.36); 8 drawn trees 0.72;
    14 RPG sprites 0.86. The app passes its ``keep`` slider (0.3) as it is,
    so it gets the corner candidates but not the smaller ``keep``.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> v = make_variation(lib, [0.5, 0.5], rng=0)
    >>> len(similar_variations(lib, v, 2, rng=0))
    2
    """
    p = params if params is not None else VariationParams()
    if overrides:
        _check_overrides(overrides)
        p = replace(p, **overrides)
    check_params(p)
    if not isinstance(variation, Variation):
        raise TypeError(f"variation must be a Variation, got {type(variation).__name__}")
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n must be a positive int, got {n!r}")
    chosen = _select(_as_exemplars(library), list(variation.names))
    rng = as_rng(rng)
    ref = variation.reference
    if ref == "image":
        raise ValueError("the variation's reference was an array; give similar variations "
                         "a named reference")
    if keep is None:
        keep = small_library_keep(len(chosen))
    centre = np.asarray(variation.weights, float)
    cands = np.stack([nearby_weights(variation.weights, keep, concentration=p.concentration,
                                     n_mix=p.n_mix, rng=rng)
                      for _ in range(SPREAD_CANDIDATES * int(n))])
    cands = np.vstack([cands, _extreme_candidates(centre / centre.sum(), keep, p.n_mix)])
    shapes = np.stack([e.resampled.ravel() for e in chosen])
    out = []
    for i in _spread(cands, shapes, int(n), np.asarray(variation.weights, float)):
        cw = nearby_weights(variation.colour_weights, keep, concentration=p.colour_concentration,
                            n_mix=p.n_mix, rng=rng)
        out.append(make_variation(chosen, cands[i], p, colour_weights=cw, reference=ref, rng=rng))
    return out


@checked(n=Int(1, MAX_VARIATIONS), use=Seq())
def tree_variations(library, target, n: int = 6, params: VariationParams | None = None, *,
                    use=None, rng=None, reference=None, **overrides) -> list[Variation]:
    """Variations of one tree ``T`` that keep it recognisable.

    Parameters
    ----------
    library : TreeLibrary or sequence of Exemplar
        Must contain ``target`` and at least one other exemplar.
    target : str or int
        ``T``: the name or index of the user's tree in the library (add a
        new tree with :meth:`TreeLibrary.add` first).
    n : int
        Number of variations.
    params : VariationParams, optional
        ``keep`` (0.5) is ``T``'s shape weight and its minimum colour
        weight; the rest of the shape weight goes to ``n_mix`` random
        exemplars other than ``T`` with Dirichlet weights.
    use : sequence, optional
        The exemplars to mix with (default: all; ``T`` is always used).
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the partners, weights and colour transfer.
    reference : optional
        Histogram-transfer reference (see :func:`make_variation`).
    **overrides
        Fields of ``params`` (e.g. ``keep=0.7``).

    Returns
    -------
    list of Variation
        ``n`` variations in which ``T`` has shape weight ``keep``.

    Raises
    ------
    ValueError
        ``target`` not in the library, or no other exemplar to mix with.

    Notes
    -----
    Beyond the paper, against results that are near copies of ``T``: drawn
    independently, with the partners picked among all exemplars, ``T``
    often won part of the rest as well (weight up to 0.9) and results often
    landed close to ``T`` and to each other. Now ``T`` keeps exactly
    ``keep``, the partners are other exemplars, and ``SPREAD_CANDIDATES``
    times ``n`` candidate weights are drawn and, starting from the first
    (random) one, the ``n`` whose combined contours lie farthest apart are
    kept (farthest-point sampling, as :func:`similar_variations`).
    Mean contour distance of 5 results to ``T`` over the mean distance
    between the exemplars (every exemplar as ``T``, seeds 2 and 5, 128 px;
    ``python -m branchnb.trees._measure targets 128``), before -> now:
    RPG sprites min 0.21 mean 0.39 -> min 0.45 mean 0.52, clip art
    0.21/0.39 -> 0.32/0.45, two sets of 8 drawn trees 0.17-0.18/0.37-0.41
    -> 0.33-0.36/0.46-0.47 (max 0.66); between the results themselves
    mean 0.26-0.32 -> 0.40-0.52.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_01", "tree_rpg_02", "tree_rpg_03"], size=128)
    >>> vs = tree_variations(lib, "tree_rpg_02", 2, rng=0, keep=0.7)
    >>> [bool(v.weights[1] >= 0.7) for v in vs]
    [True, True]
    """
    p = params if params is not None else VariationParams()
    if overrides:
        _check_overrides(overrides)
        p = replace(p, **overrides)
    check_params(p)
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n must be a positive int, got {n!r}")
    exemplars = _as_exemplars(library)
    names = [e.name for e in exemplars]
    if isinstance(target, str):
        if target not in names:
            raise ValueError(f"target {target!r} is not in the library ({names}); add it first")
        t = names.index(target)
    else:
        t = check_int(target, "target")
        if not -len(names) <= t < len(names):
            raise ValueError(f"target index {t} out of range for {len(names)} exemplars")
        t %= len(names)
    chosen = _select(exemplars, use)
    if exemplars[t] not in chosen:
        chosen = [exemplars[t]] + chosen
    if len(chosen) < 2:
        raise ValueError("variations of a tree need at least one other exemplar to mix with")
    ti = chosen.index(exemplars[t])
    rng = as_rng(rng)
    k = len(chosen)
    others = np.delete(np.arange(k), ti)
    # Beyond the paper (see Notes): T keeps exactly ``keep``, the rest goes to
    # partners other than T, and the n most different of many candidates are kept.
    cands = np.zeros((SPREAD_CANDIDATES * int(n), k))
    cands[:, ti] = p.keep
    for c in cands:
        c[others] += (1.0 - p.keep) * _random_weights(len(others), p.n_mix, p.concentration, rng)
    shapes = np.stack([e.resampled.ravel() for e in chosen])
    centre = np.eye(k)[ti]
    out = []
    # Start from a random draw (not the extreme one), so a single variation (batch jobs
    # draw one per item) is an unbiased draw and n > 1 spread out from it.
    for i in _spread(cands, shapes, int(n), centre, first=0):
        w = cands[i]                    # T keeps exactly ``keep``; the rest sums to 1 - keep
        cw = np.zeros_like(w)
        mixed = np.flatnonzero(w > 0)
        cw[mixed] = variation_weights(len(mixed), int(np.flatnonzero(mixed == ti)[0]), p.keep,
                                      concentration=p.colour_concentration, rng=rng)
        out.append(make_variation(chosen, w, p, colour_weights=cw, reference=reference, rng=rng))
    return out


@checked(steps=Int(2, MAX_VARIATIONS), colour=Choice("shape", "random"))
def morph_sequence(library, a, b, steps: int = 5, params: VariationParams | None = None, *,
                   colour: str = "shape", rng=None, **overrides) -> list[Variation]:
    """Morph from tree ``a`` to tree ``b``: weights ``(1 - t, t)`` for ``t`` in ``[0, 1]``.

    Parameters
    ----------
    library : TreeLibrary or sequence of Exemplar
        Holds ``a`` and ``b``.
    a, b : str or int
        The two trees.
    steps : int
        Number of frames (>= 2), ``t = 0 ... 1``.
    params : VariationParams, optional
        ``M``, colour mode and outline options of every frame; None uses
        the defaults.
    colour : {"shape", "random"}
        Colour weights follow the shape weights (a morph) or are random.
    rng : {numpy.random.Generator, int}, optional
        Used only with ``colour="random"``: the default morph is fully
        determined by ``a``, ``b`` and ``steps`` (every frame uses the same
        fixed seam noise, so chosen colour regions do not flicker).
    **overrides
        Fields of ``params``.

    Returns
    -------
    list of Variation
        ``steps`` frames; the first is ``a`` itself, the last ``b``.

    Raises
    ------
    ValueError
        ``steps < 2``, an unknown ``colour``, or ``a``/``b`` not in the
        library.

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> frames = morph_sequence(lib, "tree_rpg_05", "tree_rpg_06", 3)
    >>> [f.weights.tolist() for f in frames]
    [[1.0, 0.0], [0.5, 0.5], [0.0, 1.0]]
    """
    if not isinstance(steps, (int, np.integer)) or steps < 2:
        raise ValueError(f"steps must be an int >= 2, got {steps!r}")
    if colour not in ("shape", "random"):
        raise ValueError(f"colour must be 'shape' or 'random', got {colour!r}")
    pair = _select(_as_exemplars(library), [a, b], labels=("a", "b"))
    if colour == "random":
        rng = as_rng(rng)
        return [make_variation(pair, [1.0 - t, t], params, rng=rng, **overrides)
                for t in np.linspace(0.0, 1.0, int(steps))]
    # Every frame draws the same seam noise (the "choose" colour mode), so the
    # regions a frame takes from each tree stay put from frame to frame.
    return [make_variation(pair, [1.0 - t, t], params, rng=0, colour_weights="shape", **overrides)
            for t in np.linspace(0.0, 1.0, int(steps))]


# ----------------------------------------------------------------------------- library


class TreeLibrary:
    """Processed exemplars that variations are made from.

    Parameters
    ----------
    exemplars : sequence of Exemplar, optional
        Processed exemplars to start with (:func:`process_exemplar`); they
        must share the working size and contour layout.
    size : int
        Working size ``S`` of trees added later (paper: 1024).
    contour_params : ContourParams, optional
        For trees added later.
    trunk : {"auto", "segmentation", "stem"}
        How trees added later find their trunk (:func:`exemplar_trunk`).
    ground : {"cut", "keep"}
        Whether trees added later have ground clutter at the trunk foot
        cut off (:func:`process_exemplar`).

    Examples
    --------
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> len(lib), lib.names
    (2, ['tree_rpg_05', 'tree_rpg_06'])
    """

    @checked(exemplars=Seq(), size=Int(16, 8192))
    def __init__(self, exemplars: Sequence[Exemplar] = (), *, size: int = 1024,
                 contour_params: ContourParams | None = None, trunk: str = "auto",
                 ground: str = "cut"):
        if trunk not in TRUNK_METHODS:
            raise ValueError(f"trunk must be one of {list(TRUNK_METHODS)}, got {trunk!r}")
        if ground not in GROUND_METHODS:
            raise ValueError(f"ground must be one of {list(GROUND_METHODS)}, got {ground!r}")
        self.exemplars: list[Exemplar] = []
        self.trunk = trunk
        self.ground = ground
        self.size = int(size)
        self.contour_params = contour_params if contour_params is not None else ContourParams()
        check_params(ExemplarParams(size=self.size), name="size")
        for i, e in enumerate(exemplars):
            if not isinstance(e, Exemplar):
                raise TypeError(f"exemplars[{i}] must be an Exemplar (see process_exemplar), got {type(e).__name__}")
            self.add_exemplar(e)

    @classmethod
    def from_data(cls, names: Sequence[str] | None = None, *, size: int = 1024,
                  contour_params: ContourParams | None = None, trunk: str = "auto",
                  ground: str = "cut") -> TreeLibrary:
        """A library of sample trees from ``branchnb.data`` (default: :data:`RPG_TREES`).

        Parameters
        ----------
        names : sequence of str, optional
            Sample names (``branchnb.data.names("trees")``); None takes
            :data:`RPG_TREES`.
        size : int
            Working size ``S`` (paper: 1024; 128-256 is enough to try things
            quickly).
        contour_params : ContourParams, optional
            ``N``, crown share, ``M``, dilation.
        trunk : {"auto", "segmentation", "stem"}
            How each tree finds its trunk (:func:`exemplar_trunk`).
        ground : {"cut", "keep"}
            Whether ground clutter at the trunk foot is cut off.

        Returns
        -------
        TreeLibrary
            The processed samples, in the order of ``names``.

        Examples
        --------
        >>> lib = TreeLibrary.from_data(["tree_rpg_05"], size=128)
        >>> lib.names, lib.size
        (['tree_rpg_05'], 128)
        """
        lib = cls(size=size, contour_params=contour_params, trunk=trunk, ground=ground)
        for n in (RPG_TREES if names is None else names):
            lib.add(_data.load(n), n)
        return lib

    # -- contents
    @property
    def names(self) -> list[str]:
        return [e.name for e in self.exemplars]

    def __len__(self) -> int:
        return len(self.exemplars)

    def __iter__(self):
        return iter(self.exemplars)

    def __contains__(self, name) -> bool:
        return name in self.names

    def __getitem__(self, key) -> Exemplar:
        return _select(self.exemplars, [key])[0]

    @checked()
    def index(self, name: str) -> int:
        """Position of the exemplar called ``name``.

        Parameters
        ----------
        name : str
            An exemplar's name.

        Returns
        -------
        int
            Its index in the library's ``exemplars`` list (and in weight vectors).

        Raises
        ------
        ValueError
            If no exemplar has that name.
        """
        if name not in self.names:
            raise ValueError(f"no exemplar named {name!r}; the library has {self.names}")
        return self.names.index(name)

    @checked(trunk_mask=Array(ndim=2))
    def add(self, image, name: str | None = None, *, trunk_mask=None) -> Exemplar:
        """Process an RGBA tree image and add it (see :func:`process_exemplar`).

        Parameters
        ----------
        image : (H, W, 4) array_like
            RGBA tree on a transparent background, any size; normalised to
            the library's working size.
        name : str, optional
            Its name; None gives ``"tree_<i>"``. An exemplar of the same name
            is replaced.
        trunk_mask : (H, W) array_like, optional
            Trunk pixels of ``image``; None finds the trunk with the
            library's ``trunk`` method.

        Returns
        -------
        Exemplar
            The processed exemplar, now in the library.

        Examples
        --------
        >>> from branchnb.trees.synthetic import synthetic_tree
        >>> lib = TreeLibrary(size=64)
        >>> lib.add(synthetic_tree("clean", rng=0, size=64).image).name, len(lib)
        ('tree_0', 1)
        """
        name = f"tree_{len(self)}" if name is None else str(name)
        ex = process_exemplar(image, name, trunk_mask=trunk_mask, trunk=self.trunk,
                              ground=self.ground, exemplar_params=ExemplarParams(size=self.size),
                              contour_params=self.contour_params)
        return self.add_exemplar(ex)

    @checked()
    def set_trunk(self, name: str, trunk, source: str = "mask") -> Exemplar:
        """Replace the trunk mask (working-image pixels) of exemplar ``name``,
        e.g. with a segmentation corrected by scribbles; pins and contours follow.

        Parameters
        ----------
        name : str
            The exemplar to change.
        trunk : (S, S) array_like
            New trunk pixels in its working image.
        source : str
            Recorded as the exemplar's ``trunk_source``.

        Returns
        -------
        Exemplar
            The new exemplar (replacing the old one in the library).
        """
        return self.add_exemplar(self[name].with_trunk(trunk, source))

    def add_exemplar(self, exemplar: Exemplar) -> Exemplar:
        """Add (or replace, by name) an already processed exemplar.

        Parameters
        ----------
        exemplar : Exemplar
            From :func:`process_exemplar`; it must share the working size
            and contour layout of the exemplars already in the library (the
            first one sets the library's ``size``).

        Returns
        -------
        Exemplar
            ``exemplar``.

        Raises
        ------
        TypeError
            If ``exemplar`` is not an Exemplar.
        ValueError
            If its size or contour layout differs from the library's.
        """
        if not isinstance(exemplar, Exemplar):
            raise TypeError(f"exemplar must be an Exemplar, got {type(exemplar).__name__}")
        if self.exemplars:
            _check_compatible([self.exemplars[0], exemplar])
        elif exemplar.size != self.size:
            self.size = exemplar.size
        if exemplar.name in self.names:
            self.exemplars[self.index(exemplar.name)] = exemplar
        else:
            self.exemplars.append(exemplar)
        # Recolouring against (or of) this tree reuses its stored parts instead of segmenting it.
        _remember_parts(exemplar.image, exemplar_parts(exemplar))
        return exemplar

    # -- operations
    @checked()
    def variation(self, weights=None, params: VariationParams | None = None, **kwargs) -> Variation:
        """:func:`make_variation` on this library.

        Parameters
        ----------
        weights : (k,) array_like or dict, optional
            Convex shape weights, one per exemplar or ``{name: weight}``;
            None draws random ones.
        params : VariationParams, optional
            Synthesis parameters; None uses the defaults.
        **kwargs
            Further arguments of :func:`make_variation` (``use``,
            ``colour_weights``, ``reference``, ``rng``, parameter overrides).

        Returns
        -------
        Variation

        Examples
        --------
        >>> from branchnb.trees import TreeLibrary
        >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
        >>> lib.variation([0.5, 0.5], rng=0).label(1)
        '0.5 tree_rpg_05 + 0.5 tree_rpg_06'
        """
        return make_variation(self, weights, params, **kwargs)

    @checked(n=Int(1, MAX_VARIATIONS))
    def variations_of(self, target, n: int = 6, params: VariationParams | None = None,
                      **kwargs) -> list[Variation]:
        """:func:`tree_variations` on this library.

        Parameters
        ----------
        target : str or int
            ``T``, the tree to vary.
        n : int
            Number of variations.
        params : VariationParams, optional
            ``keep`` is ``T``'s shape weight; None uses the defaults.
        **kwargs
            Further arguments of :func:`tree_variations` (``use``, ``rng``,
            ``reference``, parameter overrides).

        Returns
        -------
        list of Variation
        """
        return tree_variations(self, target, n, params, **kwargs)

    @checked(n=Int(1, MAX_VARIATIONS))
    def similar(self, variation: Variation, n: int = 6, params: VariationParams | None = None,
                **kwargs) -> list[Variation]:
        """:func:`similar_variations` on this library.

        Parameters
        ----------
        variation : Variation
            The centre ("more like this").
        n : int
            Number of variations.
        params : VariationParams, optional
            Synthesis parameters; None uses the defaults.
        **kwargs
            Further arguments of :func:`similar_variations` (``keep``,
            ``rng``, parameter overrides).

        Returns
        -------
        list of Variation
        """
        return similar_variations(self, variation, n, params, **kwargs)

    @checked(steps=Int(2, MAX_VARIATIONS))
    def morph(self, a, b, steps: int = 5, params: VariationParams | None = None,
              **kwargs) -> list[Variation]:
        """:func:`morph_sequence` on this library.

        Parameters
        ----------
        a, b : str or int
            The two trees.
        steps : int
            Number of frames (>= 2).
        params : VariationParams, optional
            Synthesis parameters; None uses the defaults.
        **kwargs
            Further arguments of :func:`morph_sequence` (``colour``, ``rng``,
            parameter overrides).

        Returns
        -------
        list of Variation
        """
        return morph_sequence(self, a, b, steps, params, **kwargs)

    @checked(size=Int(8, 4096))
    def thumbnails(self, size: int = 96) -> list[np.ndarray]:
        """Each exemplar over white, ``(size, size, 3)``.

        Parameters
        ----------
        size : int
            Side of each thumbnail in pixels (area-averaged from ``S``).

        Returns
        -------
        list of (size, size, 3) float32 ndarray
            In library order.
        """
        return [cv2.resize(composite_over(e.image, (1.0, 1.0, 1.0)), (size, size),
                           interpolation=cv2.INTER_AREA) for e in self.exemplars]

    @checked(size=Int(8, 4096), cols=Int(1, 1000))
    def contact_sheet(self, size: int = 96, cols: int = 7) -> np.ndarray:
        """All thumbnails in a grid.

        Parameters
        ----------
        size : int
            Side of each thumbnail in pixels.
        cols : int
            Thumbnails per row (fewer when the library is smaller).

        Returns
        -------
        (H, W, 3) float32 ndarray
            :func:`tile_images` of :meth:`thumbnails`, 2 px white gaps.

        Examples
        --------
        >>> from branchnb.trees import TreeLibrary
        >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
        >>> lib.contact_sheet(32, cols=2).shape
        (32, 66, 3)
        """
        return tile_images(self.thumbnails(size), cols=cols)

    def __repr__(self) -> str:
        return f"TreeLibrary({len(self)} exemplars, size={self.size}: {', '.join(self.names)})"

    def _repr_png_(self) -> bytes | None:
        return encode_png(self.contact_sheet()) if self.exemplars else None


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

