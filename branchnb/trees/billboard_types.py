"""Billboard clouds: the parameters, the result and its layers.

:class:`BillboardParams` (the paper's values as defaults) and :class:`BillboardCloud`
(the billboards of one tree) of :func:`~branchnb.trees.billboard.billboard_cloud`; split
from :mod:`branchnb.trees.billboard`, where every name is importable too.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.image import composite_over
from ..core.io import encode_png
from ..core.params import param
from ..core.validate import Real, checked

__all__ = ["BillboardParams", "BillboardCloud", "FRONT", "REAR", "INTERIOR", "TRUNK_LAYER", "CORE",
           "LAYER_NAMES"]

FRONT, REAR, INTERIOR, TRUNK_LAYER, CORE = 0, 1, 2, 3, 4
LAYER_NAMES = {FRONT: "front", REAR: "rear", INTERIOR: "interior", TRUNK_LAYER: "trunk", CORE: "core"}


@dataclass
class BillboardParams:
    """Parameters of :func:`~branchnb.trees.billboard.billboard_cloud` (defaults: the paper's values).

    Parameters
    ----------
    n_segments : int
        Approximate number of SLIC superpixels on the crown, one front
        billboard each (paper: 256).
    compactness : float
        SLIC compactness on colours scaled to [0, 1] (paper: 0.35);
        scikit-image receives ``100 * compactness`` (CIELAB scale).
    replace_edges : bool
        Replace near-straight superpixel edges by pieces of the silhouette
        (paper, step 2), so billboards have natural outlines from the side.
    straightness : float
        An edge is near-straight when it deviates from its chord by less
        than this fraction of its length (or 1.5 px).
    min_edge_length : float
        Shorter edges are kept as they are (working pixels).
    chord_tolerance : float
        Relative mismatch of chord lengths allowed between an edge and the
        silhouette piece that replaces it.
    depth_scale : float
        Maximum of the inflation height ``h`` over half the crown's width
        (1: the crown is as deep as it is wide; 0: a flat cloud).
    darkness_depth : float
        ``δ``: a front billboard sits at ``z = h̄ (1 - δ (1 - ℓ))``, so the
        darkest (``ℓ = 0``) sits at ``(1 - δ)`` of its mean height ``h̄``.
    rear_layer : bool
        Add the rear layer: front positions mirrored about the crown's axis
        at ``z < 0`` (paper).
    n_interior : int
        Extra billboards at blue-noise positions inside the volume (paper);
        0 adds none.
    interior_darkening : float
        Colour factor lost by the deepest interior billboard, times the
        crown's own shading (flat-coloured clip art is not darkened).
    core_layer : bool
        Beyond the paper: the whole crown as one flat billboard on the image
        plane behind the front layer, so side views show crown colour in
        the gaps instead of sky and the crown stays on the trunk.
    overlap : float
        Beyond the paper: front billboards grow over neighbouring pixels of
        their own colour, up to this fraction of the mean superpixel size,
        so flat regions stay flat in side views; the front view is
        unchanged. 0 turns it off.
    overlap_tolerance : float
        Largest per-channel colour difference of a pixel a billboard grows
        over.
    line_art : bool
        Beyond the paper: drawn outlines (:func:`~branchnb.trees.billboard_lines.line_art`) are drawn behind
        every fill, so from the side they show only along the silhouette.
    drawn_regions : bool
        Beyond the paper: on drawn trees (line art found) each fill region
        bounded by outlines is one billboard with its whole outline
        (:func:`~branchnb.trees.billboard_shapes.drawn_regions`); only the crown's base fill is split.
    drawn_cards : bool
        Beyond the paper (issue 24), with ``drawn_regions``: a crown drawn
        with inner outlines (:func:`~branchnb.trees.billboard_cards.has_inner_outlines`),
        or a flat fill in a thick outline band without inner strokes (an RPG
        sprite, :func:`~branchnb.trees.billboard_cards.flat_fill_cards`),
        is built from whole cards only (:mod:`branchnb.trees.billboard_cards`),
        without rear, interior or core copies, so side views keep the inner
        outlines and show no smeared fill. Cards do not suit every drawing:
        shapes in a notch of the silhouette or between pieces of a split
        base fill leave sky when they move in depth (rim ink 0.97 -> 0.87
        at 45 degrees on a fruit tree with a leaf pile). So the card cloud
        is kept only when it is good from the side, or no worse there than
        the superpixel cloud of the same tree
        (:func:`~branchnb.trees.billboard_cards.cards_hold`: inner-outline
        recall at 45 and 90 degrees, rim ink of the full and reduced levels
        at 45 degrees, front PSNR >= 30 dB); otherwise the superpixel cloud
        is returned, exactly as with ``drawn_cards=False``. The check draws
        the card cloud from the side; the superpixel cloud is built and
        drawn too only when the cards are not good outright.
    tone_cards : bool
        Beyond the paper (issue 24), with ``drawn_cards``: a drawn crown
        without outlines (clumps in a few tones, gradients;
        :func:`~branchnb.trees.billboard_cards.shaded_cards`) is built from
        cards too. With ``tone_cards`` its clumps, split by their sharp tone
        edges (:func:`~branchnb.trees.billboard_cards.tone_edges`), are cards
        of their own, in depth; where those lose inner outlines from the
        side (recall below 0.95 at 45 or 90 degrees) or open sky, and with
        ``tone_cards=False``, the crown's fill regions are the cards (a crown
        without strokes is one card, its side views the drawing itself).
    line_width : float
        Widest stroke taken for line art, as a fraction of the tree's size
        (0 disables line art).
    max_size : int
        Long side of the working image in pixels (paper: 1024); larger
        inputs are downsampled, ``BillboardCloud.scale`` records by how much.
    alpha_threshold : float
        Pixels with alpha >= this are opaque (paper: 0.5).

    Examples
    --------
    >>> BillboardParams(n_segments=64).compactness
    0.35
    """

    n_segments: int = param(256, min=8, max=2048, log=True,
                            help="SLIC superpixels on the crown (paper: 256)")
    compactness: float = param(0.35, min=0.01, max=2.0, step=0.01,
                               help="SLIC compactness on [0, 1] colours (paper: 0.35); "
                                    "scikit-image gets 100x this (CIELAB scale)")
    replace_edges: bool = param(True, help="replace near-straight superpixel edges by silhouette pieces")
    straightness: float = param(0.08, min=0.0, max=0.5, step=0.01,
                                help="an edge is near-straight if it deviates from its chord "
                                     "by less than this fraction of its length (or 1.5 px)")
    min_edge_length: float = param(8.0, min=2.0, max=200.0,
                                   help="shorter edges are kept (working pixels)")
    chord_tolerance: float = param(0.1, min=0.01, max=0.5, step=0.01,
                                   help="relative chord-length mismatch allowed for a silhouette piece")
    depth_scale: float = param(1.0, min=0.0, max=3.0, step=0.05,
                               help="max inflation height / half the crown width (1: as deep as wide)")
    darkness_depth: float = param(0.5, min=0.0, max=1.0, step=0.05,
                                  help="delta: the darkest billboard sits at (1 - delta) of its height")
    rear_layer: bool = param(True, help="add the rear layer (mirrored positions)")
    n_interior: int = param(128, min=0, max=4096, log=True,
                            help="extra billboards at blue-noise positions inside the volume")
    interior_darkening: float = param(0.6, min=0.0, max=1.0, step=0.05,
                                      help="colour factor lost by the deepest interior billboard "
                                           "(times the crown's shading, 0 for flat colour)")
    core_layer: bool = param(True, help="a flat crown billboard on the image plane (not in the paper): "
                                        "no sky through the gaps of side views, crown stays on the trunk")
    overlap: float = param(1.0, min=0.0, max=2.0, step=0.05,
                           help="front billboards grow over neighbouring pixels of their own colour, "
                                "up to this fraction of the mean superpixel size (not in the paper): "
                                "flat regions stay flat in side views; the front view is unchanged")
    overlap_tolerance: float = param(0.06, min=0.0, max=0.5, step=0.01,
                                     help="per-channel colour difference a grown pixel may have")
    line_art: bool = param(True, help="drawn outlines (thin dark strokes bordering flat colour) are drawn "
                                      "behind every fill in side views, so they show only along the side "
                                      "view's silhouette (not in the paper); the front view is unchanged")
    drawn_regions: bool = param(True, help="on drawn trees (line art found), the billboards follow the drawn "
                                           "shapes: each fill region bounded by outlines is one billboard "
                                           "with its whole outline, only the crown's base fill is split; hidden "
                                           "layers show the base fill, so side views keep the inner outlines "
                                           "and scatter no fruit (not in the paper)")
    drawn_cards: bool = param(True, help="a crown drawn with inner outlines is built from its drawn shapes "
                                         "as whole cards, without hidden copies, where that holds up from "
                                         "the side (checked against the superpixel cloud): side views keep "
                                         "the inner outlines, no smear (not in the paper)")
    tone_cards: bool = param(True, help="a drawn crown without outlines is split into cards by its tones "
                                        "(clumps in depth) where that holds up from the side (not in the paper)")
    line_width: float = param(0.04, min=0.0, max=0.2, step=0.005,
                              help="widest stroke taken for line art, as a fraction of the tree's size")
    max_size: int = param(1024, min=64, max=4096, step=64,
                          help="long side of the working image (paper: 1024)")
    alpha_threshold: float = param(0.5, min=0.0, max=1.0, step=0.05,
                                   help="opaque where alpha >= this (paper: 0.5)")


@dataclass
class BillboardCloud:
    """Billboards of one tree.

    Parameters
    ----------
    centers : (K, 3) float64
        Quad centres ``(x, y, z)`` in working pixels (``y`` down, ``z``
        towards the viewer).
    sizes : (K, 2) float64
        Quad ``(width, height)`` in pixels (= its texture size).
    texture : (K,) int
        Index into ``textures`` of each billboard.
    tint : (K,) float
        Colour factor (1 = as in the image; interior billboards are darker).
    layer : (K,) int
        ``FRONT``, ``REAR``, ``INTERIOR``, ``TRUNK_LAYER`` or ``CORE``.
    source : (K,) int
        Index of the front billboard a rear/interior billboard copies (its
        own index for front and trunk billboards).
    textures : list of (h, w, 4) float32
        Straight (not premultiplied) RGBA textures.
    axis : float
        ``x`` of the vertical axis the cloud turns about (crown centre).
    image : (H, W, 4) float32
        The working image.
    superpixels : (H, W) int32
        Final crown superpixel labels (0 outside the crown), after edge
        replacement.
    depth : (H, W) float32
        Inflation height ``h`` of the crown (0 outside).
    replaced : list of (N, 2) float arrays
        The silhouette pieces that replaced straight edges (for pictures).
    scale : float
        Working image size / input size.
    lines : (H, W) bool
        The line art of the working image (:func:`~branchnb.trees.billboard_lines.line_art`; all False
        when ``line_art`` is off).
    line_masks : list of (h, w) bool arrays or None
        Per texture, its pixels that lie on the line art in the front view
        (None: none). The preview draws them in a first pass, behind every
        other pixel of the cloud.

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> cloud.counts()["trunk"] >= 1, cloud.render(90.0).shape[0]
    (True, 64)
    """

    centers: np.ndarray
    sizes: np.ndarray
    texture: np.ndarray
    tint: np.ndarray
    layer: np.ndarray
    source: np.ndarray
    textures: list = field(repr=False)
    axis: float = 0.0
    image: np.ndarray = field(default=None, repr=False)
    superpixels: np.ndarray = field(default=None, repr=False)
    depth: np.ndarray = field(default=None, repr=False)
    replaced: list = field(default_factory=list, repr=False)
    scale: float = 1.0
    lines: np.ndarray = field(default=None, repr=False)
    line_masks: list = field(default_factory=list, repr=False)

    @property
    def n_billboards(self) -> int:
        return int(len(self.centers))

    def counts(self) -> dict[str, int]:
        """Number of billboards per layer name.

        Examples
        --------
        >>> from branchnb.trees.billboard import billboard_cloud
        >>> from branchnb.trees.synthetic import synthetic_tree
        >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
        >>> sum(cloud.counts().values()) == cloud.n_billboards
        True
        """
        return {name: int((self.layer == v).sum()) for v, name in LAYER_NAMES.items()}

    @checked(yaw=Real(-1e6, 1e6))
    def render(self, yaw: float = 0.0, **kwargs) -> np.ndarray:
        """Software preview from ``yaw`` degrees; see :func:`branchnb.trees.preview.render_cloud`.

        Parameters
        ----------
        yaw : float
            Camera angle about the vertical axis, degrees (0 = the input
            view, 180 = from behind).
        **kwargs
            Further arguments of :func:`~branchnb.trees.preview.render_cloud`
            (``facing``, ``crop``, ``background``, ``height``, ``outline``).

        Returns
        -------
        ndarray
            RGBA (RGB with ``background``) float32 image in [0, 1].
        """
        from .preview import render_cloud

        return render_cloud(self, yaw, **kwargs)

    def _repr_png_(self) -> bytes:
        from .preview import render_views

        return encode_png(render_views(self, (0.0, 60.0, 120.0), height=256))


def _front_overlay(cloud: BillboardCloud) -> np.ndarray:
    """RGB picture of the superpixels (random tints) and the replaced edges."""
    from skimage.segmentation import find_boundaries

    rgb = composite_over(cloud.image, (1.0, 1.0, 1.0)).copy()
    b = find_boundaries(cloud.superpixels, mode="inner") & (cloud.superpixels > 0)
    rgb[b] = (0.1, 0.1, 0.1)
    if cloud.replaced:
        from ..core.render import draw_polylines

        rgb = draw_polylines(rgb, cloud.replaced, widths=1.5, colors=(0.95, 0.2, 0.1))
    return rgb
