"""Processing the library trees once (paper, step 1): :class:`Exemplar` and :func:`process_exemplar`.

Every library image is normalised, its tree contour ``C`` extracted, the
pin points found from the crown/trunk split, resampled to ``C_r``
(``N = 2000``) and simplified to the cage ``C_s`` (``M = 20``). Split out of
:mod:`branchnb.trees.variations`, which re-exports every name.

Examples
--------
>>> from branchnb import data
>>> ex = process_exemplar(data.load("tree_rpg_05"), "rpg_05", size=96)
>>> ex.size
96
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..core.image import as_float_image, as_mask, composite_over
from ..core.io import encode_png
from ..core.render import draw_polylines
from ..core.validate import Array, Int, checked
from .contour import ContourParams, TreeContour, simplify_contour, stem_trunk_mask, tree_contour
from .detached_trunk import _join_detached_trunk
from .exemplar import (
    ContourSet,
    ExemplarParams,
    Normalized,
    extract_contours,
    normalize_exemplar,
    tree_rgba,
)
from .ground import split_ground
from .translucent import from_working_alpha, to_working_alpha, translucent_level

__all__ = ["Exemplar", "exemplar_trunk", "process_exemplar", "TRUNK_METHODS", "GROUND_METHODS"]


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
        tc = tree_contour(self.contours.tree, self.alpha, t, self.contour.params,
                          corners=self.normalized.pixel_art is None)
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

    Notes
    -----
    Beyond the paper (its exemplars are one region): a trunk drawn apart
    from the crown, as icon-style trees often are (a gap of a few pixels
    under a round crown), would be dropped as a second region; a narrow,
    upright region under the crown's centre, at most 10 % of the tree's
    height below it, is drawn on up into the crown first
    (:func:`~branchnb.trees.detached_trunk._join_detached_trunk`), while a sun, a
    ground disc, a leaf pile or a pebble is still dropped or cut.

    Beyond the paper: a translucent source (watercolour washes of alpha
    ~0.4, an airbrushed halo, a glass tree of alpha 0.3) would come out
    with a hollow crown (only the pooled rim at alpha >= 0.5) or be refused
    as transparent. Its silhouette is taken at its wash's own level
    (:func:`~branchnb.trees.translucent.translucent_level`; the alpha is
    remapped so that level is the threshold for every step), and the
    exemplar keeps its source's soft alpha (``normalized.soft_alpha``,
    ``normalized.alpha_level``), which the variations carry through the mix.

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
    # Beyond the paper: a translucent source (watercolour wash, airbrushed or glass crown) is taken
    # at its wash's own level, remapped to the threshold so every step below keeps it, and keeps
    # its own soft alpha for the mix (translucent.py).
    level = ep.alpha_threshold
    src = np.asarray(image)
    if src.ndim == 3 and src.shape[2] == 4:
        img0 = as_float_image(src, name="image")
        level = translucent_level(img0[..., 3], ep.alpha_threshold)
        if level < ep.alpha_threshold:
            image = np.dstack([img0[..., :3], to_working_alpha(img0[..., 3], level, ep.alpha_threshold)])
    # An icon's trunk drawn apart from the crown is the tree's, no clutter.
    image = _join_detached_trunk(image, ep.alpha_threshold)
    if ground == "cut":
        img, opaque = tree_rgba(image, alpha_threshold=ep.alpha_threshold)
        split = split_ground(img)
        if split.has_ground:
            cut = split.ground
            image = split.cut(img)
    # a translucent source's soft alpha is its paint's coverage, no matted-in background: the
    # defringe recoloured 5 % of a watercolour crown's pixels (pink specks in the wash)
    norm = normalize_exemplar(image, ep, defringe=level >= ep.alpha_threshold)
    if level < ep.alpha_threshold and norm.soft_alpha is not None:
        norm = replace(norm, soft_alpha=from_working_alpha(norm.soft_alpha, level, ep.alpha_threshold),
                       alpha_level=level)
    if trunk_mask is None:
        tmask, source = exemplar_trunk(norm.image, trunk)
    else:
        given = as_mask(trunk_mask, shape=norm.source_shape, name="trunk_mask")
        tmask, source = norm.warp_mask(given) & norm.alpha, "mask"
    contours = extract_contours(norm.alpha)
    tc = tree_contour(contours.tree, norm.alpha, tmask, cp, corners=norm.pixel_art is None)
    return Exemplar(str(name), norm.image, tmask, contours, tc, norm, source, cut)
