"""Billboard cloud from a single tree image.

A frontal RGBA tree image becomes a cloud of small textured quads
("billboards") spread in a 3-D volume, which gives parallax when the
camera turns around the tree. The steps follow the paper:

1. **Superpixels** (:func:`crown_superpixels`): SLIC on the crown pixels,
   ``n_segments = 256`` and compactness 0.35 (paper). The paper's
   compactness is measured with colours scaled to [0, 1]; scikit-image
   measures colour distances in CIELAB, whose ``L`` runs over 0..100, so
   the value passed to :func:`skimage.segmentation.slic` is
   ``100 * compactness`` (= 35). Each superpixel is one billboard.
2. **Natural outlines** (:func:`replace_straight_edges`): in flat-coloured
   areas SLIC cuts the crown with nearly straight edges, which would show
   as polygonal billboard outlines from the side. Every near-straight edge
   between two superpixels is replaced by a piece of the tree silhouette
   whose end points are at a similar distance (the piece is mapped onto
   the edge's end points by a similarity) and which stays on one side of
   its chord (it does not cross the straight edge). The pixels between the
   straight edge and the new curve change owner, so the superpixels still
   tile the crown exactly.
3. **Volume** (:func:`inflate_silhouette`): the crown silhouette is
   inflated into a height field ``h`` solving the biharmonic equation
   ``Δ²h = 1`` with ``h = 0`` (and ``Δh = 0``) on the silhouette: the
   boundary stays on the image plane. ``h`` is scaled so that its maximum
   is ``depth_scale`` times half the crown's width: trees are roughly
   symmetric about their vertical axis, so the crown is about as deep as
   it is wide (a round crown becomes a sphere). The volume spans ``-h <= z <= h``.
4. **Layers**: front billboards at ``z = h̄ (1 - δ (1 - ℓ))`` where ``h̄``
   is the mean height over the superpixel and ``ℓ`` in [0, 1] its
   brightness rank (darker billboards are pushed deeper, ``δ`` =
   ``darkness_depth``); a rear layer with the positions mirrored
   horizontally about the crown's axis at ``z < 0`` (the texture itself is
   not mirrored); ``n_interior`` extra billboards at blue-noise positions
   inside the volume (weighted Voronoi stippling with density ``h``, the
   volume's half thickness, so the points spread evenly in 3-D; depth
   uniform between the front and back layers), each with the outline of
   the superpixel under it, darkened with its depth (in proportion to the
   crown's own shading: flat-coloured clip art is not darkened, so its
   flat regions stay flat from the side); rear and interior billboards show
   the input colours under their own front-view footprint; the trunk (with
   any ground clutter at its foot, which is no crown to inflate, as a
   second one) on the image plane ``z = 0``, a leaning trunk cut into
   horizontal strips so that it stays under the crown in side views.
   Not in the paper: a *core* billboard, the whole crown flat on the
   image plane behind the front layer (hidden in the front view), so that
   the gaps that open between billboards in side views show crown colour
   rather than sky and the crown stays joined to the trunk top.
5. **Line art** (not in the paper, for drawn trees): the thin dark strokes
   that outline flat colour in clip art (:func:`line_art`) mark the
   drawing's silhouettes as seen from the front. Turned with their
   billboards, they would pile up on the axis of a side view and cover its
   flat regions with broken black dashes. Every billboard keeps its
   texture, but its stroke pixels are drawn in a first pass, behind every
   fill pixel of the cloud (the billboard version of the "inverted hull"
   outline of toon rendering): in the front view nothing covers a stroke,
   so it is unchanged; from the side, strokes show only where no fill is,
   along the side view's own silhouette. Rear, interior and core
   billboards, hidden in the front view, show the image with its strokes
   filled in by the nearest fill colour. Photographs have no such strokes
   (a stroke must border a flat-coloured region) and are drawn as before.
6. **Drawn shapes** (not in the paper, :func:`drawn_regions`): SLIC cuts
   across the shapes of a drawing, and a side view then scatters pieces of
   every inner outline and fruit at different depths (smeared outlines,
   loose stroke bits, red flecks). On drawn trees every fill region bounded
   by the line art is a shape and one billboard with its whole outline;
   only the *background* (the largest region, when it lies under shapes
   drawn over it) is split for depth. Shapes drawn over it (*decorations*:
   fruits, clumps) sit on the crown's surface, in front of the background
   pieces round them; shapes spanning the crown from rim to rim (a
   conifer's tiers) are *cards* placed to fit in the volume (a tier as wide
   as the crown stays on the axis) without rear or interior copies (with no
   decoration, the background is a card too). Rear, interior and core
   billboards show the background's fill in place of the decorations (the
   underpainting), so each fruit exists once. On 12 drawn trees of every
   kind (``python -m branchnb.trees._measure sideviews``) loose stroke bits
   at 45/90 degrees went from 3.6 % (max 10.6 %) of the ink to 0.5 % (max
   3.2 %); the hidden layers of 5 drawn fruit trees held 4-14 times as many
   fruit-coloured texels as the fruits have pixels, now none. Palm fronds
   whose outlines leave gaps at the hub merge into one region in the line
   art; as the largest region it was taken for the background and cut into
   pieces, which from the side made one green umbrella with comb-like
   streaks of the midribs. A region whose convex hull is mostly sky (less
   than 0.8 crown; a crown's base fill has crown all round it) is split at
   its necks into lobes, one card each (:func:`_merged_lobes`): on 10
   drawn palms (8 at 256 px, 2 at 384 px, half with a leaf pile) the loose
   stroke bits at 45/90 degrees over the front view's went from 2.6 % (max
   7.4 %) of the ink to 0.3 % (max 0.8 %), and the inner ink kept from
   0.20 to at least 0.54; the other kinds do not change. Cards of one fill
   colour that meet across a stroke (a frond's halves either side of its
   midrib) share one depth, so they do not part; so do the lobes of one
   star. The segmenter calls a palm's dark midribs, radiating from the
   hub, trunk, and the one-row trunk strips at the hub then showed them
   from the side as ink whiskers across it: on a star crown the trunk
   mask's thin arms into the crown go to the crown
   (:func:`_stray_trunk_strokes`). On the 10 palms loose stroke bits went
   from 0.3 % to 0.2 % (max 0.8 %), inner ink kept from 0.73 to 0.76 (min
   0.54); the 256 px palm of ``sideviews`` from 1.0 % stroke bits at 90
   degrees to 0, inner ink from 0.56 to 0.77, and the other 17 trees of
   ``sideviews`` do not change. Whiskers remain on about 3 of the 10 palms
   at 90 degrees (midribs the arms rule does not reach).
   Even so, fronds on cards at (mostly) one depth gather on the axis from
   the side: left and right fronds cross in an X, fronds of one slant
   pile up with their outlines drawn twice a few pixels apart
   (:func:`~branchnb.trees.stacked.stacked_outline_share` up to 0.095 of
   the stroke length at 45/90/135 degrees, above 0.01 on all 10 palms,
   above 0.03 on 9). A crown with sky between its fronds, covering less
   than 0.66 of its convex hull (:func:`_fan_crown`: drawn palms
   0.47-0.63, the other drawn kinds 0.84-0.97, the clip-art and RPG
   samples 0.74-0.98 but two palm sprites, 0.45 and 0.50, whose
   silhouettes are not outlined), of an outlined drawing is one billboard whose turning axis is the trunk's top (a
   palm's crown is near round about the trunk, so every side view shows
   the drawn fan on the trunk): stacked outlines, loose stroke bits and
   flecks 0 on all 10 palms, inner ink kept 1.0; such crowns have no
   parallax of their own.

Billboards are *axial* billboards (each quad turns about its vertical
axis to face the camera, the usual way trees are drawn with billboards),
so the front view (yaw 0) puts every billboard back where it came from:
front billboards tile the crown, the trunk billboard covers the trunk
and the rear/interior billboards, which are trimmed to the crown
silhouette, lie behind them. The front view reproduces the input image.

Coordinates: pixels of the working image, ``x`` right, ``y`` down, ``z``
towards the viewer. :mod:`branchnb.trees.export` writes glTF / OBJ
(y up, metres) and :mod:`branchnb.trees.preview` renders any yaw.

Examples
--------
>>> from branchnb import data
>>> cloud = billboard_cloud(data.load("tree_rpg_01"), rng=0)
>>> cloud.n_billboards > 256
True
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np
import scipy.sparse as sp
from scipy import ndimage as ndi
from scipy.sparse.linalg import splu

from ..core.image import composite_over, extend_nearest
from ..core.io import encode_png
from ..core.params import check_params, param
from ..core.poisson import grid_laplacian
from ..core.random import as_rng
from ..core.sampling import stipple
from ..core.validate import Real, checked
from .exemplar import tree_rgba
from .outline import silhouette_outline
from .quality import FLAT_COVERAGE, palette_coverage, palette_pixels
from .segmentation import Segmentation, segment_tree

__all__ = [
    "BillboardParams",
    "BillboardCloud",
    "billboard_cloud",
    "crown_superpixels",
    "replace_straight_edges",
    "inflate_silhouette",
    "FRONT",
    "REAR",
    "INTERIOR",
    "TRUNK_LAYER",
    "CORE",
    "LAYER_NAMES",
    "line_art",
    "drawn_regions",
]

FRONT, REAR, INTERIOR, TRUNK_LAYER, CORE = 0, 1, 2, 3, 4
LAYER_NAMES = {FRONT: "front", REAR: "rear", INTERIOR: "interior", TRUNK_LAYER: "trunk", CORE: "core"}


@dataclass
class BillboardParams:
    """Parameters of :func:`billboard_cloud` (defaults: the paper's values where it gives them).

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
        Beyond the paper: drawn outlines (:func:`line_art`) are drawn behind
        every fill, so from the side they show only along the silhouette.
    drawn_regions : bool
        Beyond the paper: on drawn trees (line art found) each fill region
        bounded by outlines is one billboard with its whole outline
        (:func:`drawn_regions`); only the crown's base fill is split.
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
        The line art of the working image (:func:`line_art`; all False
        when ``line_art`` is off).
    line_masks : list of (h, w) bool arrays or None
        Per texture, its pixels that lie on the line art in the front view
        (None: none). The preview draws them in a first pass, behind every
        other pixel of the cloud.

    Examples
    --------
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


# ---------------------------------------------------------------------------
# 1. Superpixels
# ---------------------------------------------------------------------------


def crown_superpixels(rgb: np.ndarray, crown: np.ndarray, *, n_segments: int = 256,
                      compactness: float = 0.35) -> np.ndarray:
    """SLIC superpixels of the crown pixels.

    Parameters
    ----------
    rgb : (H, W, 3) float array
        Colours in [0, 1] (straight, not premultiplied).
    crown : (H, W) bool array
        The pixels to segment; the rest gets label 0. An empty crown gives
        all zeros.
    n_segments : int
        Approximate number of superpixels (paper: 256).
    compactness : float
        On colours scaled to [0, 1] (paper: 0.35); scikit-image receives
        ``100 * compactness`` because it measures colour in CIELAB.

    Returns
    -------
    labels : (H, W) int32
        1..K on the crown (each label one 4-connected piece), 0 elsewhere.

    Examples
    --------
    >>> import numpy as np
    >>> rgb = np.zeros((32, 32, 3)); rgb[:, 16:] = (0.1, 0.6, 0.1)
    >>> lab = crown_superpixels(rgb, np.ones((32, 32), bool), n_segments=4)
    >>> int(lab.min()) >= 1, len(np.unique(lab)) >= 2
    (True, True)
    """
    from skimage.segmentation import slic

    crown = np.asarray(crown, bool)
    if not crown.any():
        return np.zeros(crown.shape, np.int32)
    n = max(1, min(int(n_segments), int(crown.sum()) // 4))
    lab = slic(np.asarray(rgb, np.float64), n_segments=n, compactness=100.0 * compactness,
               mask=crown, start_label=1, enforce_connectivity=True, channel_axis=-1)
    lab = np.where(crown, lab, 0).astype(np.int32)
    # Split labels that came out in several pieces; relabel 1..K.
    out = np.zeros_like(lab)
    k = 0
    for sl_i, sl in enumerate(ndi.find_objects(lab)):
        if sl is None:
            continue
        comp, nc = ndi.label(lab[sl] == sl_i + 1)
        for c in range(1, nc + 1):
            k += 1
            out[sl][comp == c] = k
    # Pixels of the crown missed by SLIC (tiny specks) join their nearest label.
    miss = crown & (out == 0)
    if miss.any() and k:
        _, (iy, ix) = ndi.distance_transform_edt(out == 0, return_indices=True)
        out[miss] = out[iy[miss], ix[miss]]
    return out


def _outer_lines(lines: np.ndarray, opaque: np.ndarray) -> np.ndarray:
    """The line pixels of the outline along the silhouette (within about one stroke of the outside).

    They stay behind the fills in side views, where they would otherwise
    cross the crown as the rim billboards carrying them swing inwards.
    """
    if not lines.any():
        return lines
    half = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
    inside = ndi.distance_transform_edt(np.pad(opaque, 1))[1:-1, 1:-1]
    return lines & (inside <= 2.0 * half + 1.5)


def drawn_regions(rgb: np.ndarray, crown: np.ndarray, lines: np.ndarray, *, n_segments: int = 256,
                  compactness: float = 0.35, min_area: int = 6, background_share: float = 0.25) -> np.ndarray:
    """Superpixels of a drawn crown that follow its drawn shapes (beyond the paper).

    SLIC cuts across the shapes of clip art, so a side view scatters pieces
    of every outline and fruit. Here each fill region bounded by the line
    art (4-connected crown pixels off the lines) is a *shape* and stays one
    superpixel, whatever its size: a fruit, a leaf clump, a frond or a tier
    moves as a whole in a side view, with its outline closed round it. Only
    the *background*, the largest region when it covers at least
    ``background_share`` of the crown (the crown's base fill under the
    clumps and fruits), is split by SLIC into pieces as large as the
    ``n_segments`` superpixels of the crown would be on average, so that it
    still gets depth variation. Regions smaller than ``min_area`` join a
    neighbour. Line pixels are left to the caller (the billboard cloud
    gives each shape its whole outline).

    Parameters
    ----------
    rgb : (H, W, 3) float array
        Colours in [0, 1].
    crown : (H, W) bool array
        The crown pixels.
    lines : (H, W) bool array
        The line art (:func:`line_art`); its pixels get label 0 and split
        the crown into regions.
    n_segments : int
        Superpixels the whole crown would get (sets the size of the
        background's pieces: crown area / ``n_segments``).
    compactness : float
        SLIC compactness for the background split, on [0, 1] colours.
    min_area : int
        Regions smaller than this (pixels) are dropped (label 0; the
        caller joins them to a neighbour).
    background_share : float
        Smallest share of the crown the largest region must cover to count
        as the background and be split.

    Returns
    -------
    labels : (H, W) int32
        1..K on the crown off the lines, 0 elsewhere.

    Examples
    --------
    >>> import numpy as np
    >>> crown = np.zeros((40, 40), bool); crown[5:35, 5:35] = True
    >>> lines = np.zeros_like(crown); lines[5:35, 19:21] = True
    >>> rgb = np.zeros((40, 40, 3), np.float32)
    >>> int(drawn_regions(rgb, crown, lines, n_segments=2).max())
    2
    """
    return _drawn_regions(rgb, crown, lines, n_segments=n_segments, compactness=compactness,
                          min_area=min_area, background_share=background_share)[0]


def _drawn_regions(rgb, crown, lines, *, n_segments=256, compactness=0.35, min_area=6,
                   background_share=0.25, stars: list | None = None):
    """:func:`drawn_regions` and the background mask (pixels of the split region; all False if none).

    ``stars``: a list that receives, per region split into lobes (:func:`_merged_lobes`), the
    array of its lobes' labels.
    """
    from skimage.segmentation import slic

    crown = np.asarray(crown, bool)
    lines = np.asarray(lines, bool)
    free = crown & ~lines
    lab, n = ndi.label(free)
    out = np.zeros(crown.shape, np.int32)
    background = np.zeros(crown.shape, bool)
    if n == 0:
        return out, background
    areas = np.bincount(lab.ravel(), minlength=n + 1)
    areas[0] = 0
    target = max(float(crown.sum()) / max(int(n_segments), 1), 1.0)
    big = int(np.argmax(areas))
    if areas[big] < background_share * crown.sum():
        big = -1
    k = 0
    for i, sl in enumerate(ndi.find_objects(lab), start=1):
        if sl is None or areas[i] < min_area:
            continue
        m = lab[sl] == i
        if i == big:
            lobes = _merged_lobes(m, crown[sl])
            if lobes is not None:
                # Shapes merged through gaps in their outlines (palm fronds meeting at the
                # hub): one shape per lobe, no background.
                first = k + 1
                for j in range(1, int(lobes.max()) + 1):
                    k += 1
                    out[sl][lobes == j] = k
                if stars is not None and k > first:
                    stars.append(np.arange(first, k + 1))
                continue
        pieces = int(round(areas[i] / target)) if i == big else 1
        if i == big:
            background[sl] |= m
        if pieces >= 2:
            sub = slic(np.asarray(rgb[sl], np.float64), n_segments=pieces, compactness=100.0 * compactness,
                       mask=m, start_label=1, enforce_connectivity=True, channel_axis=-1)
            sub = np.where(m, sub, 0)
            ids = np.unique(sub[sub > 0])
            fill = np.median(rgb[sl][m], axis=0)
            # One flat fill (most of it within 0.06 of its median): a piece of another colour,
            # mostly outlined, is a shape in it whose outline is open (a fruit drawn over the
            # crown's rim).
            one_fill = np.mean(np.linalg.norm(rgb[sl][m] - fill, axis=1) <= 0.06) >= 0.8
            for j in ids:
                k += 1
                piece = sub == j
                out[sl][piece] = k
                if (i == big and one_fill and np.linalg.norm(rgb[sl][piece].mean(axis=0) - fill) > 0.15
                        and _outlined(piece, lines[sl])):
                    background[sl] &= ~piece
            rest = m & (sub == 0)
            if rest.any():
                out[sl][rest] = k
        else:
            k += 1
            out[sl][m] = k
    return out, background


#: A fill region whose convex hull (holes filled) is less than this share crown is no
#: base fill under other shapes but drawn shapes merged through gaps in their outlines
#: (:func:`_merged_lobes`). Crown bases measure 0.96-1.0 (drawn broadleaf, fruit and
#: conifer trees, the clip-art and RPG samples at least 0.85); merged palm fronds 0.48-0.77.
_SKY_HULL = 0.8

#: Lobes of one star (:func:`_merged_lobes`) share one depth, and thin arms of the trunk mask
#: that run into the crown go to the crown (:func:`_stray_trunk_strokes`); ``_measure palms``
#: turns them off to compare.
_JOIN_STARS = True
_HUB_STROKES = True
#: A fan crown (:func:`_fan_crown`) of an outlined drawing is one billboard turning about the
#: trunk's top (``_measure palms`` compares it with the cards and lobes rule).
_STAR_ONE = True
_FAN_HULL = 0.66


def _merged_lobes(m: np.ndarray, crown: np.ndarray, *, necks=(0.5, 0.4, 0.3), min_share: float = 0.03):
    """One label per lobe of a fill region made of shapes merged at narrow necks, or None.

    Beyond the paper. Drawn palm fronds meet at the hub, where their
    outlines converge and leave gaps, so the line art encloses several
    fronds as one region: a star of lobes with sky between them. Split into
    pieces for depth like a crown's base fill, it shows from the side as one
    umbrella of fill with comb-like streaks of the midribs; each lobe is a
    drawn shape (a card) instead. A region is such a star when its convex
    hull (holes filled) is less than ``_SKY_HULL`` crown; a base fill has
    crown all round it (clumps and fruits drawn over it), and is left to
    the caller (None). The lobes are the pieces of the region deeper than
    ``neck`` times its ridge depth (95th percentile of the distance to its
    border) holding at least ``min_share`` of that deep area, for the first
    of ``necks`` that gives two or more, grown back over the region (each
    pixel to the nearest lobe); one label for the whole region if none does.
    """
    from skimage.morphology import convex_hull_image

    hull = convex_hull_image(ndi.binary_fill_holes(m))
    if (hull & crown).sum() >= _SKY_HULL * hull.sum():
        return None
    d = ndi.distance_transform_edt(np.pad(m, 1))[1:-1, 1:-1]
    ridge = float(np.percentile(d[m], 95))
    for neck in necks:
        lab, n = ndi.label(d > neck * ridge)
        area = np.bincount(lab.ravel(), minlength=n + 1)
        area[0] = 0
        keep = area >= min_share * area.sum()
        if int(keep.sum()) >= 2:
            seeds = np.where(keep[lab], lab, 0)
            _, (iy, ix) = ndi.distance_transform_edt(seeds == 0, return_indices=True)
            _, ids = np.unique(seeds[iy, ix], return_inverse=True)
            return np.where(m, ids.reshape(m.shape) + 1, 0).astype(np.int32)
    return m.astype(np.int32)


def _decorations(labels, shapes, background, crown, outline: float, *, rows: float = 0.5,
                 span: float = 0.9) -> np.ndarray:
    """Shapes drawn over the background (bool per label): fruits, clumps, a clump's fruits.

    Without a background every shape is a card. With one, a shape is a
    decoration unless it spans the crown: in at least ``rows`` of its rows it
    runs (with its outline, ``outline`` px) from the crown's left rim to its
    right rim, over at least ``span`` of the crown's width there, as the tiers
    of a drawn conifer do, stacked rather than drawn over a base.
    """
    deco = np.zeros(len(shapes), bool)
    if not background.any():
        return deco
    for k, sl in enumerate(ndi.find_objects(labels), start=1):
        if sl is None or k >= len(shapes) or not shapes[k]:
            continue
        m = labels[sl[0]] == k
        on = m.any(axis=1)
        m, cr = m[on], crown[sl[0]][on]
        W = m.shape[1]
        idx = np.arange(W)
        c0, c1 = np.where(m, idx, W).min(axis=1), np.where(m, idx, -1).max(axis=1) + 1
        k0, k1 = np.where(cr, idx, W).min(axis=1), np.where(cr, idx, -1).max(axis=1) + 1
        wide = np.minimum(c1 + outline, k1) - np.maximum(c0 - outline, k0) >= span * np.maximum(k1 - k0, 1)
        deco[k] = wide.mean() < rows
    return deco


def _fit_cards(z, labels, cards, crown, hmap, axis: float, outline: float = 0.0) -> np.ndarray:
    """Depths of the cards (shapes that are no decorations) capped so that each fits in the volume.

    A flat card reaching ``e`` from the axis in a row where the crown reaches
    ``R`` from the axis on that side, in rows where the crown is ``D`` deep
    (its largest height there), fits in the volume when it lies at most
    ``D sqrt(1 - (e / R)^2)`` off the image plane (``e / R`` the 90th
    percentile over the card's rows; the card's outline, ``outline`` px
    wide, counts as part of it): a conifer's tier spanning the crown,
    or a frond drawn out to the silhouette, stays on the axis (it would
    swing off the trunk in side views and its mirror copy would show as a
    second tree).
    """
    z = z.copy()
    for k, sl in enumerate(ndi.find_objects(labels), start=1):
        if sl is None or k >= len(cards) or not cards[k] or k >= len(z):
            continue
        m = labels[sl[0]] == k
        rows = m.any(axis=1) & crown[sl[0]].any(axis=1)
        if not rows.any():
            continue
        m, cr = m[rows], crown[sl[0]][rows]
        W = m.shape[1]
        idx = np.arange(W)
        # Per row: how far the card reaches towards the crown's rim on each side of the axis.
        c0, c1 = np.where(m, idx, W).min(axis=1), np.where(m, idx, -1).max(axis=1) + 1
        k0, k1 = np.where(cr, idx, W).min(axis=1), np.where(cr, idx, -1).max(axis=1) + 1
        left = (axis - c0 + outline) / np.maximum(axis - k0, 1.0)
        right = (c1 + outline - axis) / np.maximum(k1 - axis, 1.0)
        e = float(np.percentile(np.maximum(left, right), 90))
        depth = float(hmap[sl[0]].max())
        z[k] = min(z[k], depth * np.sqrt(max(0.0, 1.0 - min(1.0, e) ** 2)))
    return z


def _join_cards(z, labels, cards, rgb, reach: float, tol: float = 0.06) -> np.ndarray:
    """One depth for the cards of one fill colour that meet across a stroke.

    A stroke drawn inside a shape (a frond's midrib) cuts it into two cards;
    at different depths they part in side views and open a sliver. Cards of
    the same fill colour (mean colours within ``tol``) within ``reach + 1``
    pixels of each other form a group that takes its least depth (cards of
    different colours, a conifer's alternating tiers, keep theirs).
    """
    ks = np.flatnonzero(cards)
    ks = ks[ks < len(z)]
    if len(ks) < 2:
        return z
    z = z.copy()
    n = len(z)
    idx = labels.ravel()
    cnt = np.maximum(np.bincount(idx, minlength=n), 1).astype(np.float64)
    mean = np.stack([np.bincount(idx, weights=rgb[..., c].ravel(), minlength=n) / cnt for c in range(3)], 1)
    parent = {int(k): int(k) for k in ks}

    def find(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    r = int(np.ceil(reach)) + 1
    H, W = labels.shape
    objs = ndi.find_objects(labels)
    for k in ks:
        sl = objs[k - 1] if k - 1 < len(objs) else None
        if sl is None:
            continue
        win = (slice(max(sl[0].start - r, 0), min(sl[0].stop + r, H)),
               slice(max(sl[1].start - r, 0), min(sl[1].stop + r, W)))
        lab = labels[win]
        near = np.unique(lab[ndi.distance_transform_edt(lab != k) <= reach + 1])
        for j in near:
            j = int(j)
            if j != k and j in parent and np.abs(mean[j] - mean[k]).max() <= tol:
                parent[find(j)] = find(int(k))
    groups = {}
    for k in ks:
        groups.setdefault(find(int(k)), []).append(int(k))
    for g in groups.values():
        if len(g) > 1:
            z[g] = z[g].min()
    return z


def _lift_decorations(z, labels, deco, background, mean_h, reach: float, passes: int = 4) -> np.ndarray:
    """Depths of the decorations: on the crown's surface, over what they are drawn on.

    A fruit darker than the crown would sink behind the crown's pieces round
    it (darker billboards are pushed deeper) and vanish from side views. A
    decoration lies at least where the background would at its place (its
    mean height times the background pieces' median depth factor) and half a
    pixel in front of any larger decoration next to it (a fruit on a clump
    moves with the clump).
    """
    z = z.copy()
    bg = np.unique(labels[background])
    bg = bg[(bg > 0) & (bg < len(z))]
    ok = bg[mean_h[bg] > 0] if len(bg) else bg
    factor = float(np.median(z[ok] / mean_h[ok])) if len(ok) else 1.0
    ks = np.flatnonzero(deco)
    ks = ks[ks < len(z)]
    z[ks] = np.maximum(z[ks], factor * mean_h[ks])
    r = int(np.ceil(reach)) + 4
    H, W = labels.shape
    objs = ndi.find_objects(labels)
    area = np.bincount(labels.ravel(), minlength=len(z))
    for _ in range(passes):
        changed = False
        for k in ks:
            if k > len(objs) or objs[k - 1] is None:
                continue
            sl = objs[k - 1]
            win = (slice(max(sl[0].start - r, 0), min(sl[0].stop + r, H)),
                   slice(max(sl[1].start - r, 0), min(sl[1].stop + r, W)))
            lab = labels[win]
            d = ndi.distance_transform_edt(lab != k)
            near = np.unique(lab[(d > 0) & (d <= reach + 3)])
            near = near[(near > 0) & (near < len(z))]
            near = near[deco[near] & (area[near] > area[k])] if len(near) else near
            if len(near) and z[near].max() + 0.5 > z[k]:
                z[k] = z[near].max() + 0.5
                changed = True
        if not changed:
            break
    return z


def _outlined(piece: np.ndarray, lines: np.ndarray, share: float = 0.1) -> bool:
    """At least ``share`` of the pixels just outside ``piece`` (3 x 3 ring) are line pixels."""
    ring = (cv2.dilate(piece.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0) & ~piece
    return bool(ring.any() and lines[ring].mean() >= share)


def _shape_lines(labels: np.ndarray, shapes: np.ndarray, lines: np.ndarray, reach: float) -> dict:
    """Per shape label (``shapes[k]`` True), the line pixels within ``reach`` of it: its whole outline.

    A line between two shapes goes to both (their billboards overlap on it in
    the front view, with the same pixels), so each keeps a closed outline
    when a side view moves them apart.
    """
    out = {}
    r = int(np.ceil(reach)) + 1
    H, W = labels.shape
    for k, sl in enumerate(ndi.find_objects(labels), start=1):
        if sl is None or k >= len(shapes) or not shapes[k]:
            continue
        ya, yb = max(sl[0].start - r, 0), min(sl[0].stop + r, H)
        xa, xb = max(sl[1].start - r, 0), min(sl[1].stop + r, W)
        win = (slice(ya, yb), slice(xa, xb))
        d = ndi.distance_transform_edt(labels[win] != k)
        m = lines[win] & (d <= reach)
        if m.any():
            out[k] = (win, m)
    return out


# ---------------------------------------------------------------------------
# 2. Near-straight edges -> silhouette pieces
# ---------------------------------------------------------------------------


def _silhouette_contours(mask: np.ndarray, min_len: int = 16) -> list[np.ndarray]:
    cs, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    return [c[:, 0, :].astype(np.float64) for c in cs if len(c) >= min_len]


def _edges(labels: np.ndarray):
    """Shared boundaries of 4-adjacent labels: {(a, b): (points (N, 2), dir a->b (2,))}."""
    out = {}
    pts, keys, dirs = [], [], []
    h, w = labels.shape
    ys, xs = np.mgrid[0:h, 0:w]
    for dy, dx in ((0, 1), (1, 0)):
        a = labels[: h - dy, : w - dx]
        b = labels[dy:, dx:]
        ok = (a != b) & (a > 0) & (b > 0)
        la, lb = a[ok], b[ok]
        px = xs[: h - dy, : w - dx][ok] + 0.5 * dx
        py = ys[: h - dy, : w - dx][ok] + 0.5 * dy
        swap = la > lb
        k1 = np.where(swap, lb, la)
        k2 = np.where(swap, la, lb)
        sgn = np.where(swap, -1.0, 1.0)
        keys.append(np.stack([k1, k2], 1))
        pts.append(np.stack([px, py], 1))
        dirs.append(np.stack([sgn * dx, sgn * dy], 1))
    if not keys:
        return out
    keys = np.concatenate(keys)
    if len(keys) == 0:
        return out
    pts = np.concatenate(pts)
    dirs = np.concatenate(dirs)
    uk, inv = np.unique(keys, axis=0, return_inverse=True)
    inv = inv.ravel()
    order = np.argsort(inv, kind="stable")
    bounds = np.searchsorted(inv[order], np.arange(len(uk) + 1))
    for i, (ka, kb) in enumerate(uk):
        sel = order[bounds[i]: bounds[i + 1]]
        out[(int(ka), int(kb))] = (pts[sel], dirs[sel].mean(axis=0))
    return out


def _straight_edge(p: np.ndarray, straightness: float, min_len: float):
    """End points of a near-straight edge, or None."""
    if len(p) < 3:
        return None
    c = p.mean(axis=0)
    q = p - c
    _, _, vt = np.linalg.svd(q, full_matrices=False)
    d = vt[0]
    t = q @ d
    p0, p1 = p[np.argmin(t)], p[np.argmax(t)]
    length = float(np.hypot(*(p1 - p0)))
    if length < min_len:
        return None
    u = (p1 - p0) / length
    dev = np.abs((p - p0) @ np.array([-u[1], u[0]]))
    if dev.max() > max(1.5, straightness * length):
        return None
    # One connected run of crack points (no gap longer than 2 px along the chord).
    s = np.sort((p - p0) @ u)
    if np.diff(s).max(initial=0.0) > 2.0:
        return None
    return p0, p1, length


def _find_piece(contours, lengths_cache, length: float, tol: float, rng):
    """A silhouette piece (M, 2) with chord ~ length, all on one side of its chord."""
    kmin = max(3, int(np.ceil(1.05 * length)))
    kmax = max(kmin + 1, int(np.ceil(2.5 * length)))
    order = rng.permutation(len(contours))
    for ci in order:
        c = contours[ci]
        n = len(c)
        if n < kmin + 2:
            continue
        starts = rng.choice(n, size=min(n, 96), replace=False)
        ks = np.arange(kmin, min(kmax, n - 1) + 1)
        if len(ks) == 0:
            continue
        ends = (starts[:, None] + ks[None, :]) % n
        chord = np.hypot(*(c[ends] - c[starts][:, None, :]).transpose(2, 0, 1))
        good = np.argwhere(np.abs(chord - length) <= tol * length)
        if len(good) == 0:
            continue
        good = good[rng.permutation(len(good))[:24]]
        for gi, gk in good:
            i, k = int(starts[gi]), int(ks[gk])
            idx = (i + np.arange(k + 1)) % n
            piece = c[idx]
            a, b = piece[0], piece[-1]
            ch = b - a
            L = float(np.hypot(*ch))
            if L < 1e-6:
                continue
            nrm = np.array([-ch[1], ch[0]]) / L
            dist = (piece - a) @ nrm
            lo, hi = dist.min(), dist.max()
            bulge = max(hi, -lo)
            if not (lo >= -0.5 or hi <= 0.5):
                continue           # crosses its chord
            if bulge < 1.0 or bulge > 0.6 * L:
                continue
            return piece
    return None


def replace_straight_edges(labels: np.ndarray, silhouette: np.ndarray, *, straightness: float = 0.08,
                           min_edge_length: float = 8.0, chord_tolerance: float = 0.1,
                           rng=None) -> tuple[np.ndarray, list[np.ndarray]]:
    """Replace near-straight superpixel edges by pieces of the silhouette.

    Parameters
    ----------
    labels : (H, W) int array
        Superpixels (0 = outside).
    silhouette : (H, W) bool array
        The tree (or crown) silhouette whose contour supplies the pieces.
    straightness, min_edge_length, chord_tolerance : float
        See :class:`BillboardParams`.
    rng : int or numpy.random.Generator
        Picks the pieces and the side they bulge to.

    Returns
    -------
    labels : (H, W) int32
        New labels: the pixels between each replaced edge and its new curve
        moved to the other superpixel (still a partition of the same pixels).
    curves : list of (M, 2) float arrays
        The new curves, in pixel coordinates.

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:80, :80]
    >>> disc = (xx - 40) ** 2 + (yy - 40) ** 2 < 35 ** 2
    >>> halves = np.where(disc, 1 + (xx >= 40), 0)        # cut by a straight vertical edge
    >>> new, curves = replace_straight_edges(halves, disc, rng=0)
    >>> len(curves), bool(((new > 0) == disc).all()), sorted(np.unique(new).tolist())
    (1, True, [0, 1, 2])
    """
    rng = as_rng(rng)
    lab = np.array(labels, dtype=np.int32, copy=True)
    contours = _silhouette_contours(np.asarray(silhouette, bool))
    if not contours:
        return lab, []
    curves = []
    H, W = lab.shape
    count = np.bincount(lab.ravel()).astype(np.int64)
    for (a, b), (pts, dir_ab) in sorted(_edges(lab).items()):
        st = _straight_edge(pts, straightness, min_edge_length)
        if st is None:
            continue
        p0, p1, length = st
        piece = _find_piece(contours, None, length, chord_tolerance, rng)
        if piece is None:
            continue
        # Similarity taking the piece's chord onto the edge (p0 -> p1).
        s0, s1 = piece[0], piece[-1]
        v_src, v_dst = s1 - s0, p1 - p0
        ang = np.arctan2(v_dst[1], v_dst[0]) - np.arctan2(v_src[1], v_src[0])
        sc = np.hypot(*v_dst) / np.hypot(*v_src)
        R = sc * np.array([[np.cos(ang), -np.sin(ang)], [np.sin(ang), np.cos(ang)]])
        curve = (piece - s0) @ R.T + p0
        u = v_dst / np.hypot(*v_dst)
        nrm = np.array([-u[1], u[0]])
        if rng.random() < 0.5:             # bulge to the other side: reflect across the chord
            d = (curve - p0) @ nrm
            curve = curve - 2.0 * d[:, None] * nrm[None, :]
        side = float(np.mean((curve - p0) @ nrm))
        # The bulge lies in b when it points along a -> b.
        into = b if side * float(dir_ab @ nrm) > 0 else a
        other = a if into == b else b
        poly = np.round(np.vstack([curve, [p1, p0]]) - 0.5).astype(np.int32)
        x0, y0 = np.maximum(poly.min(axis=0) - 1, 0)
        x1, y1 = np.minimum(poly.max(axis=0) + 2, [W, H])
        if x1 <= x0 or y1 <= y0:
            continue
        region = np.zeros((y1 - y0, x1 - x0), np.uint8)
        cv2.fillPoly(region, [poly - [x0, y0]], 1)
        sub = lab[y0:y1, x0:x1]
        move = (region > 0) & (sub == into)
        n_move = int(move.sum())
        if n_move == 0 or n_move >= count[into]:
            continue                       # never swallow a whole superpixel
        sub[move] = other
        count[into] -= n_move
        count[other] += n_move
        curves.append(curve)
    if curves:
        lab = _merge_fragments(lab)
    return lab, curves


def _merge_fragments(lab: np.ndarray) -> np.ndarray:
    """Keep each label's largest 4-connected piece; stray pieces join their nearest other label.

    Curves of neighbouring edges can overlap and cut a few pixels off a
    superpixel; such islands would stretch its billboard's bounding box.
    """
    out = lab.copy()
    stray = np.zeros(lab.shape, bool)
    for k, sl in enumerate(ndi.find_objects(lab), start=1):
        if sl is None:
            continue
        comp, nc = ndi.label(lab[sl] == k)
        if nc <= 1:
            continue
        sizes = np.bincount(comp.ravel())
        sizes[0] = 0
        stray[sl] |= (comp > 0) & (comp != int(np.argmax(sizes)))
    if not stray.any():
        return out
    out[stray] = 0
    _, (iy, ix) = ndi.distance_transform_edt(out == 0, return_indices=True)
    out[stray] = out[iy[stray], ix[stray]]
    return out


# ---------------------------------------------------------------------------
# 3. Inflation
# ---------------------------------------------------------------------------


def inflate_silhouette(mask: np.ndarray, *, max_solve: int = 192) -> np.ndarray:
    """Biharmonic inflation ``Δ²h = 1`` inside ``mask``, ``h = Δh = 0`` on its boundary.

    Solved as two Dirichlet Poisson problems (``-Δu = 1``, ``-Δh = u``)
    with the 5-point Laplacian (:func:`branchnb.core.poisson.grid_laplacian`
    plus the Dirichlet neighbours outside the mask) and one sparse LU
    factorisation, on a grid of at most ``max_solve`` pixels (``h`` is
    smooth), then resized.

    Parameters
    ----------
    mask : (H, W) bool array
        The silhouette to inflate (the crown); may have several pieces.
    max_solve : int
        Longest side in pixels of the grid the equations are solved on
        (a coarser grid for larger masks, then resized to (H, W)).

    Returns
    -------
    h : (H, W) float32
        > 0 inside the mask, 0 outside, normalised to a maximum of 1.

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:41, :41]
    >>> h = inflate_silhouette((xx - 20) ** 2 + (yy - 20) ** 2 < 15 ** 2)
    >>> round(float(h[20, 20]), 3), float(h[0, 0])
    (1.0, 0.0)
    """
    mask = np.asarray(mask, bool)
    H, W = mask.shape
    if not mask.any():
        return np.zeros((H, W), np.float32)
    s = min(1.0, max_solve / max(H, W))
    if s < 1.0:
        small = cv2.resize(mask.astype(np.float32), (max(1, round(W * s)), max(1, round(H * s))),
                           interpolation=cv2.INTER_AREA) >= 0.5
        if small.sum() < 4:
            small = cv2.resize(mask.astype(np.uint8), (small.shape[1], small.shape[0]),
                               interpolation=cv2.INTER_NEAREST) > 0
    else:
        small = mask
    if not small.any():
        small = mask
        s = 1.0
    L, index = grid_laplacian(small)
    deg = np.asarray(L.diagonal()).ravel()
    A = (L + sp.diags(4.0 - deg)).tocsc()   # Dirichlet: outside neighbours are 0
    lu = splu(A)
    u = lu.solve(np.ones(A.shape[0]))
    hv = lu.solve(u)
    hs = np.zeros(small.shape, np.float64)
    hs[small] = hv
    if s < 1.0:
        h = cv2.resize(hs.astype(np.float32), (W, H), interpolation=cv2.INTER_LINEAR)
        # Pixels of the mask that fall outside the small mask get a small positive height.
        floor = 0.5 * float(hv.min()) if len(hv) else 0.0
        h = np.where(mask, np.maximum(h, floor), 0.0)
    else:
        h = hs
    m = float(h.max())
    return (h / m if m > 0 else h).astype(np.float32)


# ---------------------------------------------------------------------------
# 4. The cloud
# ---------------------------------------------------------------------------


def _working_image(img: np.ndarray, max_size: int) -> tuple[np.ndarray, float]:
    h, w = img.shape[:2]
    s = min(1.0, max_size / max(h, w))
    if s >= 1.0:
        return img, 1.0
    size = (max(1, round(w * s)), max(1, round(h * s)))
    a = cv2.resize(img[:, :, 3], size, interpolation=cv2.INTER_AREA)
    prem = cv2.resize(img[:, :, :3] * img[:, :, 3:4], size, interpolation=cv2.INTER_AREA)
    rgb = np.where(a[..., None] > 1e-4, prem / np.maximum(a[..., None], 1e-4), 0.0)
    return np.dstack([rgb, a]).clip(0, 1).astype(np.float32), s


def _volume_mask(crown: np.ndarray, trunk: np.ndarray | None = None) -> np.ndarray:
    """The silhouette that is inflated: the crown with gaps closed and holes filled.

    Photographed crowns are lacy (sky shows through) and branches drawn
    over a crown cut it into pieces; inflating around every hole would
    flatten the volume. So the trunk pixels inside the crown's convex hull
    join it, then gaps (closing with a disc of 4 % of the crown size) and
    enclosed holes are filled.
    """
    if trunk is not None and trunk.any():
        pts = np.column_stack(np.nonzero(crown)[::-1]).astype(np.int32)
        hull = np.zeros(crown.shape, np.uint8)
        cv2.fillConvexPoly(hull, cv2.convexHull(pts), 1)
        crown = crown | (trunk & (hull > 0))
    ys, xs = np.nonzero(crown)
    D = max(ys.max() - ys.min() + 1, xs.max() - xs.min() + 1)
    r = max(1, int(round(0.04 * D)))
    k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    pad = 2 * r + 1
    m = np.pad(crown.astype(np.uint8), pad)
    m = cv2.morphologyEx(m, cv2.MORPH_CLOSE, k)[pad:-pad, pad:-pad] > 0
    return ndi.binary_fill_holes(m | crown)


def _extend(labels: np.ndarray, support: np.ndarray) -> np.ndarray:
    """Give every pixel of ``support`` the label of its nearest labelled pixel."""
    if not (labels > 0).any():
        return labels
    _, (iy, ix) = ndi.distance_transform_edt(labels == 0, return_indices=True)
    out = labels[iy, ix]
    return np.where(support, out, 0).astype(labels.dtype)


def _cut(image: np.ndarray, keep: np.ndarray, pivot: float | None = None):
    """Bounding box texture of ``keep``: (x0, y0, rgba) or None.

    With ``pivot``, the box is widened with transparent columns so that its
    centre (the axis an axial billboard turns about) is at ``x = pivot``.
    """
    ys, xs = np.nonzero(keep)
    if len(ys) == 0:
        return None
    y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    tex = image[y0:y1, x0:x1].copy()
    tex[:, :, 3] *= keep[y0:y1, x0:x1]
    if pivot is not None:
        c2 = int(round(2.0 * pivot))            # twice the wanted centre, in pixel edges
        left = max(0, (x0 + x1) - c2)           # columns to add on the left / right
        right = max(0, c2 - (x0 + x1))
        if left or right:
            tex = np.pad(tex, ((0, 0), (left, right), (0, 0)))
            x0 -= left
    return int(x0), int(y0), tex


def _majority_parts(opaque, trunk, ground, size):
    """Working-size trunk (ground included) and ground masks: each pixel goes to the part
    (crown, trunk, ground) that covers most of it.

    Thresholding one mask alone at 0.5 after the resize left rim pixels to
    none of the parts or to two: as crown specks on a bare tree, or as trunk
    bits along a hill's rim that the trunk strips then spanned.
    """
    op = opaque.astype(np.float32)
    g = ground & trunk if ground is not None else np.zeros_like(trunk)
    fr = [cv2.resize(op * m, size, interpolation=cv2.INTER_AREA) for m in (~trunk, trunk & ~g, g)]
    best = np.argmax(np.stack(fr), axis=0)
    return best >= 1, best == 2


def _star_crown(crown: np.ndarray, lines: np.ndarray, background_share: float = 0.25) -> bool:
    """Whether the crown's largest fill region is a star of merged shapes (:func:`_merged_lobes`)."""
    from skimage.morphology import convex_hull_image

    lab, n = ndi.label(crown & ~lines)
    if n == 0:
        return False
    areas = np.bincount(lab.ravel(), minlength=n + 1)
    areas[0] = 0
    big = int(np.argmax(areas))
    if areas[big] < background_share * crown.sum():
        return False
    sl = ndi.find_objects(lab)[big - 1]
    hull = convex_hull_image(ndi.binary_fill_holes(lab[sl] == big))
    return bool((hull & crown[sl]).sum() < _SKY_HULL * hull.sum())


def _fan_crown(crown: np.ndarray) -> bool:
    """Whether the crown (holes filled) covers less than ``_FAN_HULL`` of its convex hull: a fan
    of fronds with sky between them (drawn palms 0.47-0.63; the other drawn kinds 0.84-0.97)."""
    from skimage.morphology import convex_hull_image

    if not crown.any():
        return False
    f = ndi.binary_fill_holes(crown)
    hull = convex_hull_image(f)
    return bool(f.sum() < _FAN_HULL * hull.sum())


def _stray_trunk_strokes(trunk: np.ndarray, crown: np.ndarray, lines: np.ndarray) -> np.ndarray:
    """Thin arms of the trunk mask that run off into the crown: they belong to the crown.

    Beyond the paper. The segmenter calls a palm's dark frond midribs, which
    radiate from the hub, trunk; cut into one-row trunk strips they turn
    about the stem and show from the side as whiskers of ink across the hub.
    The trunk's body is the mask opened by a disc of ``2 w + 1`` px (``w``
    the strokes' half width); a piece of the rest that reaches farther than
    ``2 w + 1.5`` px from the body and touches the crown goes to the crown
    (bark ticks on the stem and the trunk's outline stay). Applied where the
    crown is such a star (:func:`_star_crown`): a broadleaf's branches drawn
    as strokes into its crown stay trunk.
    """
    half = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
    r = int(np.ceil(2.0 * half + 1.0))
    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    body = cv2.morphologyEx(trunk.astype(np.uint8), cv2.MORPH_OPEN, disc) > 0
    if not body.any():
        return np.zeros_like(trunk)
    arms = trunk & ~body
    lab, n = ndi.label(arms, structure=np.ones((3, 3)))
    if n == 0:
        return arms
    far = ndi.distance_transform_edt(~body) > 2.0 * half + 1.5
    near_crown = cv2.dilate(crown.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    reach = np.bincount(lab[far & arms], minlength=n + 1) > 0
    touch = np.bincount(lab[near_crown & arms], minlength=n + 1) > 0
    keep = reach & touch
    keep[0] = False
    return keep[lab]


def _trunk_strips(trunk: np.ndarray, height: int, max_strips: int = 64):
    """Horizontal strips of a trunk mask and the ``x`` each turns about.

    The pivot line runs through the trunk's middle (the per-row centre,
    smoothed over 10 % of the trunk's height, so branches and forks do not
    jerk it about); a new strip starts where the pivot has drifted by
    ``step`` pixels (0.5 % of the image height, at least 1 px; more if
    ``max_strips`` would be exceeded). Neighbouring strips then part by at
    most ``step`` in a side view, and a branching trunk keeps its branches:
    every strip turns about the stem, not about its own bounding box, whose
    centre jumps from row to row with the branches it holds.
    """
    rows = np.flatnonzero(trunk.any(axis=1))
    yy, xx = np.nonzero(trunk)
    cnt = np.bincount(yy, minlength=rows[-1] + 1)[rows]
    centre = np.bincount(yy, weights=xx, minlength=rows[-1] + 1)[rows] / cnt
    span = rows[-1] - rows[0] + 1
    sigma = max(1.0, 0.1 * span / 2.355)
    wts = ndi.gaussian_filter1d(cnt.astype(np.float64), sigma, mode="nearest")
    pivot = ndi.gaussian_filter1d(centre * cnt, sigma, mode="nearest") / np.maximum(wts, 1e-9)
    variation = float(np.abs(np.diff(pivot)).sum())
    step = max(1.0, 0.005 * height, variation / max_strips)
    out, start = [], 0
    for i in range(1, len(rows) + 1):
        if i == len(rows) or abs(pivot[i] - pivot[start]) >= step:
            strip = np.zeros_like(trunk)
            a, b = rows[start], rows[i - 1] + 1
            strip[a:b] = trunk[a:b]
            out.append((strip, float(np.mean(pivot[start:i]))))
            start = i
    return out


def _trim(tex: np.ndarray, x0: float, y0: float, allowed: np.ndarray) -> np.ndarray:
    """Multiply ``tex`` alpha by ``allowed`` under its front-view footprint (integer placement)."""
    h, w = tex.shape[:2]
    H, W = allowed.shape
    xi, yi = int(round(x0)), int(round(y0))
    win = np.zeros((h, w), np.float32)
    ax0, ay0 = max(xi, 0), max(yi, 0)
    ax1, ay1 = min(xi + w, W), min(yi + h, H)
    if ax1 > ax0 and ay1 > ay0:
        win[ay0 - yi: ay1 - yi, ax0 - xi: ax1 - xi] = allowed[ay0:ay1, ax0:ax1]
    out = tex.copy()
    out[:, :, 3] *= win
    return out


def _recolour(tex: np.ndarray, x0: float, y0: float, image: np.ndarray) -> np.ndarray:
    """``tex`` with the colours of ``image`` under its front-view footprint.

    A rear or interior billboard keeps the outline of the superpixel it was
    copied from but shows what lies in front of it in the input: a large
    flat-coloured region then stays flat coloured from the side instead of
    being speckled with colours carried over from elsewhere.
    """
    h, w = tex.shape[:2]
    H, W = image.shape[:2]
    xi, yi = int(round(x0)), int(round(y0))
    ys = np.clip(np.arange(h) + yi, 0, H - 1)
    xs = np.clip(np.arange(w) + xi, 0, W - 1)
    out = tex.copy()
    out[:, :, :3] = image[np.ix_(ys, xs)][:, :, :3]
    return out


def _same_colour_overlap(image, labels, k, sl, allowed, radius, tol):
    """Footprint of superpixel ``k`` grown by up to ``radius`` px over pixels of its own colour.

    Seen from the side, neighbouring billboards at different depths part and
    leave gaps in a flat-coloured region; grown over the neighbours' pixels
    of the same colour (within ``tol`` of the nearest own pixel, per
    channel), they overlap there and the region stays one colour. The
    texture shows the image's own colours on the grown pixels, so the front
    view is unchanged; nothing grows across a colour edge (an outline's
    pixels stay with the outline's billboards).

    Returns the grown window (slices) and its footprint mask.
    """
    H, W = labels.shape
    ya, yb = max(sl[0].start - radius, 0), min(sl[0].stop + radius, H)
    xa, xb = max(sl[1].start - radius, 0), min(sl[1].stop + radius, W)
    win = (slice(ya, yb), slice(xa, xb))
    own = labels[win] == k
    dist, (iy, ix) = ndi.distance_transform_edt(~own, return_indices=True)
    rgb = image[win][:, :, :3]
    near = rgb[iy, ix]
    grow = (~own & (dist <= radius) & allowed[win]
            & (np.abs(rgb - near).max(axis=2) <= tol))
    keep = own | grow
    ys, xs = np.nonzero(keep)
    tight = (slice(ya + ys.min(), ya + ys.max() + 1), slice(xa + xs.min(), xa + xs.max() + 1))
    return tight, keep[ys.min(): ys.max() + 1, xs.min(): xs.max() + 1]


def _shading(image: np.ndarray, labels: np.ndarray) -> float:
    """How much a crown is shaded, in [0, 1]: the median colour spread inside its superpixels.

    0 for flat-coloured clip art (every superpixel one colour), 1 for a
    photograph; scales the darkening of interior billboards, which would
    otherwise speckle flat colour regions seen from the side.
    """
    n = int(labels.max())
    if n == 0:
        return 0.0
    lum = image[:, :, :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    idx = labels.ravel()
    cnt = np.bincount(idx, minlength=n + 1).astype(np.float64)
    m1 = np.bincount(idx, weights=lum.ravel(), minlength=n + 1) / np.maximum(cnt, 1)
    m2 = np.bincount(idx, weights=lum.ravel() ** 2, minlength=n + 1) / np.maximum(cnt, 1)
    std = np.sqrt(np.maximum(m2 - m1 ** 2, 0.0))[1:][cnt[1:] > 0]
    return float(np.clip(np.median(std) / 0.05, 0.0, 1.0)) if std.size else 0.0


@checked()
def billboard_cloud(rgba, trunk=None, params: BillboardParams | None = None, *,
                    rng=0) -> BillboardCloud:
    """Turn one RGBA tree image into a billboard cloud.

    Parameters
    ----------
    rgba : (H, W, 4) array_like
        Frontal tree image on a transparent background, any size.
    trunk : (H, W) bool array, Segmentation, or None
        Trunk pixels (one billboard). ``None`` runs :func:`segment_tree`;
        an all-False mask means "no trunk" (every opaque pixel is crown).
    params : BillboardParams, optional
        Superpixels, edge replacement, volume, layers and the drawn-tree
        options; None uses the defaults (the paper's where it has them).
    rng : int or numpy.random.Generator
        Edge pieces, interior positions and depths.

    Returns
    -------
    BillboardCloud
        The billboards (front, rear, interior, trunk, core layers) in
        working-image pixels, with the working image and its superpixels.

    Raises
    ------
    ValueError
        No alpha channel, fully transparent image, trunk mask of the wrong
        shape.

    Examples
    --------
    >>> from branchnb import data
    >>> cloud = billboard_cloud(data.load("tree_rpg_05"), rng=1)
    >>> sorted(cloud.counts())
    ['core', 'front', 'interior', 'rear', 'trunk']
    """
    p = check_params(params if params is not None else BillboardParams())
    img, opaque_full = tree_rgba(rgba, alpha_threshold=p.alpha_threshold, min_pixels=16, name="rgba")
    rng = as_rng(rng)
    H0, W0 = opaque_full.shape
    if trunk is None or isinstance(trunk, Segmentation):
        seg = segment_tree(img, rng=rng) if trunk is None else trunk
        # Ground clutter at the foot (a leaf pile, an island, a stand) joins
        # the trunk billboard: it is no crown to inflate and looks alike from
        # every side.
        trunk_full = seg.trunk if seg.ground is None else seg.trunk | seg.ground
        ground_full = seg.ground
    else:
        trunk_full = np.asarray(trunk)
        if trunk_full.shape != (H0, W0):
            raise ValueError(f"trunk must be an (H, W) mask of shape {(H0, W0)}, got {trunk_full.shape}")
        trunk_full = trunk_full.astype(bool)
    if trunk is not None and not isinstance(trunk, Segmentation):
        ground_full = None
    work, s = _working_image(img, p.max_size)
    H, W = work.shape[:2]
    alpha = work[:, :, 3]
    opaque = alpha >= p.alpha_threshold
    if opaque.sum() < 4:
        raise ValueError("rgba has too few opaque pixels at the working size")
    if s < 1.0:
        # Each working pixel goes to the part that covers more of it: thresholding
        # the trunk alone at 0.5 left rim pixels of a bare tree to the crown, as
        # specks that the crown layer then scattered in side views.
        trunk_w, ground_w = _majority_parts(opaque_full, trunk_full, ground_full, (W, H))
    else:
        trunk_w = trunk_full
        ground_w = ground_full if ground_full is not None else np.zeros((H, W), bool)
    trunk_w = trunk_w & opaque
    ground_w = ground_w & trunk_w
    crown = opaque & ~trunk_w
    # Parts: 1 crown, 2 trunk, extended to the soft (0 < alpha < threshold) rim.
    part = np.where(crown, 1, np.where(trunk_w, 2, 0)).astype(np.int32)
    part_ext = _extend(part, alpha > 1e-3)
    crown_ext = part_ext == 1
    trunk_ext = part_ext == 2

    # 5. Line art, and the image with it filled in for the hidden billboards.
    if p.line_art and p.line_width > 0:
        lines = line_art(work, width=p.line_width, alpha_threshold=p.alpha_threshold)
    else:
        lines = np.zeros((H, W), bool)
    filled = _fill_lines(work, lines, alpha > 1e-3) if lines.any() else work
    star_crown = bool(lines.any() and crown.any() and _star_crown(crown, lines))
    if _HUB_STROKES and star_crown:
        stray = _stray_trunk_strokes(trunk_w & ~ground_w, crown, lines)
        if stray.any():
            trunk_w = trunk_w & ~stray
            crown = opaque & ~trunk_w
            part = np.where(crown, 1, np.where(trunk_w, 2, 0)).astype(np.int32)
            part_ext = _extend(part, alpha > 1e-3)
            crown_ext = part_ext == 1
            trunk_ext = part_ext == 2

    # 1-2. Superpixels with natural outlines; on drawn trees the drawn shapes.
    regions = p.drawn_regions and lines.any()
    if regions:
        stars: list = []
        sp_lab, background = _drawn_regions(work[:, :, :3], crown, lines & crown, n_segments=p.n_segments,
                                            compactness=p.compactness, stars=stars)
        if background.any():
            # A background beside shapes spanning the crown (tiers, together at least half
            # its size) is one more card (a conifer's lowest tier); otherwise (a crown with
            # clumps and fruits drawn over it, or no inner outlines) it is split as before.
            shapes = np.ones(int(sp_lab.max()) + 1, bool)
            shapes[0] = False
            shapes[np.unique(sp_lab[background])] = False
            half = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
            spans = shapes & ~_decorations(sp_lab, shapes, background, crown, 2.0 * half + 1.5)
            if int(np.isin(sp_lab, np.flatnonzero(spans)).sum()) >= 0.5 * background.sum():
                stars = []
                sp_lab, background = _drawn_regions(work[:, :, :3], crown, lines & crown,
                                                    n_segments=p.n_segments, compactness=p.compactness,
                                                    background_share=2.0, stars=stars)
    else:
        background = np.zeros((H, W), bool)
        sp_lab = crown_superpixels(work[:, :, :3], crown, n_segments=p.n_segments, compactness=p.compactness)
    curves: list[np.ndarray] = []
    if p.replace_edges and sp_lab.max() > 1:
        sp_lab, curves = replace_straight_edges(sp_lab, opaque, straightness=p.straightness,
                                                min_edge_length=p.min_edge_length,
                                                chord_tolerance=p.chord_tolerance, rng=rng)
    sp_ext = _extend(sp_lab, crown_ext)

    # Drawn shapes (every fill region but the background) carry their whole outline; the
    # background's pieces none of it. The hidden billboards (rear, interior, core) show the
    # background's fill under the shapes (the underpainting): the shapes drawn over it exist
    # once each, on their own billboards, instead of being scattered in depth as flecks.
    shape_lines, under = {}, filled
    owned = np.zeros((H, W), bool)
    base = crown_ext
    card = np.zeros(int(sp_lab.max()) + 1, bool)
    if regions:
        # The background's labels (most of their pixels in it: the straight-edge replacement
        # moves a few pixels between neighbours).
        n_lab = int(sp_lab.max()) + 1
        in_bg = np.bincount(sp_lab[background], minlength=n_lab)
        shapes = in_bg <= 0.5 * np.bincount(sp_lab.ravel(), minlength=n_lab)
        shapes[0] = False
        background = crown & ~np.isin(sp_lab, np.flatnonzero(shapes)) & (sp_lab > 0)
        half = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
        shape_lines = _shape_lines(sp_lab, shapes, lines & crown_ext, 2.0 * half + 1.5)
        for win, m in shape_lines.values():
            owned[win] |= m
        deco = _decorations(sp_lab, shapes, background, crown, 2.0 * half + 1.5)
        base = crown_ext & (background | np.isin(sp_ext, np.flatnonzero(deco | ~shapes)))
        card = shapes & ~deco
        if deco.any():
            under = filled.copy()
            # Everything but the cards and the background's own fill (its median colour,
            # within 0.15; a fruit left in the background, its outline open, or the lines
            # round a fruit filled with its colour would spread it otherwise).
            fill = np.median(filled[background][:, :3], axis=0)
            src = background & (np.linalg.norm(filled[:, :, :3] - fill, axis=2) <= 0.15)
            paint = crown_ext & ~src & ~np.isin(sp_ext, np.flatnonzero(card))
            under[paint, :3] = extend_nearest(filled[:, :, :3], src if src.any() else background)[paint]

    # 3. Volume.
    if crown.any():
        vol = _volume_mask(crown, trunk_w)
        hn = inflate_silhouette(vol)
        xs_c = np.nonzero(crown)[1]
        half_width = 0.5 * float(xs_c.max() - xs_c.min() + 1)
        hmap = (hn * p.depth_scale * half_width).astype(np.float32)
    else:
        hmap = np.zeros((H, W), np.float32)
    axis = float(np.nonzero(crown)[1].mean()) if crown.any() else float(np.nonzero(opaque)[1].mean())

    centers, sizes, tex_idx, tints, layers, sources, textures = [], [], [], [], [], [], []

    def add(x0, y0, tex, z, tint, layer, source=None, tex_id=None):
        h, w = tex.shape[:2]
        if tex_id is None:
            textures.append(tex.astype(np.float32))
            tex_id = len(textures) - 1
        centers.append((x0 + 0.5 * w, y0 + 0.5 * h, z))
        sizes.append((w, h))
        tex_idx.append(tex_id)
        tints.append(tint)
        layers.append(layer)
        sources.append(len(sources) if source is None else source)
        return len(sources) - 1

    # 4a. Front layer.
    n_sp = int(sp_ext.max())
    lum_img = work[:, :, :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    idx = sp_lab.ravel()
    cnt = np.bincount(idx, minlength=n_sp + 1).astype(np.float64)
    mean_h = np.bincount(idx, weights=hmap.ravel(), minlength=n_sp + 1) / np.maximum(cnt, 1)
    mean_l = np.bincount(idx, weights=lum_img.ravel(), minlength=n_sp + 1) / np.maximum(cnt, 1)
    valid = np.arange(n_sp + 1) > 0
    valid &= cnt > 0
    rank = np.zeros(n_sp + 1)
    if valid.sum() > 1:
        order = np.argsort(np.argsort(mean_l[valid]))
        rank[valid] = order / (valid.sum() - 1)
    elif valid.any():
        rank[valid] = 1.0
    z_front = mean_h * (1.0 - p.darkness_depth * (1.0 - rank))
    if regions:
        z_front = _fit_cards(z_front, sp_lab, card, crown, hmap, axis, 2.0 * half + 1.5)
        z_front = _join_cards(z_front, sp_lab, card, work[:, :, :3], 2.0 * half + 1.5)
        if _JOIN_STARS:
            # Lobes of one star (palm fronds merged at the hub) at one depth, their least: at
            # different depths the fronds tear apart at the hub from the side, and the hub's
            # converging strokes scatter into shards (beyond the paper).
            for g in stars:
                g = g[g < len(z_front)]
                if len(g) > 1:
                    z_front[g] = z_front[g].min()
        z_front = _lift_decorations(z_front, sp_lab, deco, background, mean_h, 2.0 * half + 1.5)
    zf_map = np.zeros((H, W), np.float32)
    front_tex = {}
    objs = ndi.find_objects(sp_ext)
    same_ok = crown_ext & (alpha >= 0.99)
    grows = valid.copy()
    if regions:
        # Shapes are whole: only the background's pieces grow, and not over the shapes.
        grows &= ~shapes
        same_ok &= ~owned & ~np.isin(sp_lab, np.flatnonzero(shapes))
    r_over = int(round(p.overlap * np.sqrt(cnt[grows].mean()))) if grows.any() else 0
    for k, sl in enumerate(objs, start=1):
        if sl is None or not valid[k]:
            continue
        if k in shape_lines:
            win, m = shape_lines[k]
            ya, yb = min(sl[0].start, win[0].start), max(sl[0].stop, win[0].stop)
            xa, xb = min(sl[1].start, win[1].start), max(sl[1].stop, win[1].stop)
            sl = (slice(ya, yb), slice(xa, xb))
            keep = sp_ext[sl] == k
            keep[win[0].start - ya: win[0].stop - ya, win[1].start - xa: win[1].stop - xa] |= m
        elif r_over > 0 and grows[k]:
            sl, keep = _same_colour_overlap(work, sp_ext, k, sl, same_ok, r_over, p.overlap_tolerance)
        else:
            keep = sp_ext[sl] == k
        if regions and not shapes[k]:
            keep = keep & ~owned[sl]
            if not keep.any():
                continue
        y0, x0 = sl[0].start, sl[1].start
        tex = work[sl].copy()
        tex[:, :, 3] *= keep
        bid = add(x0, y0, tex, float(z_front[k]), 1.0, FRONT)
        front_tex[k] = (x0, y0, bid, tex_idx[bid])
        zf_map[sl][keep] = z_front[k]

    # 4b. Rear layer: mirrored positions about the axis, behind the image plane.
    # Behind the front layer only where it is fully opaque, so nothing shows through
    # its soft edges in the front view.
    allowed = (crown_ext & (alpha >= 0.99)).astype(np.float32)
    if p.rear_layer:
        for k, (x0, y0, bid, tid) in front_tex.items():
            tex = textures[tid]
            h, w = tex.shape[:2]
            cx = 2.0 * axis - (x0 + 0.5 * w)
            rx0 = round(cx - 0.5 * w)
            if regions and card[k]:
                continue                       # a card's mirror image would cover the cards in side views
            t = _recolour(_trim(tex, rx0, y0, allowed), rx0, y0, under)
            a = t[:, :, 3]
            if a.sum() < 1.0:
                continue
            ys, xs = np.nonzero(a > 0)
            hh = hmap[np.clip(ys + y0, 0, H - 1), np.clip(xs + rx0, 0, W - 1)]
            z = -float(hh.mean()) * (1.0 - p.darkness_depth * (1.0 - rank[k]))
            add(rx0, y0, t, min(z, -1e-3), 1.0, REAR, source=bid)

    # 4c. Interior billboards at blue-noise positions, darkened with depth.
    if p.n_interior > 0 and n_sp > 0 and hmap.max() > 0:
        shade = _shading(filled, sp_lab)
        pts = stipple(hmap * crown, int(p.n_interior), iterations=10, rng=rng)
        for px, py in pts:
            xi = int(np.clip(round(px), 0, W - 1))
            yi = int(np.clip(round(py), 0, H - 1))
            k = int(sp_ext[yi, xi])
            if k == 0 or k not in front_tex:
                continue
            if regions and card[k]:
                continue
            x0, y0, bid, tid = front_tex[k]
            tex = textures[tid]
            h, w = tex.shape[:2]
            ix0, iy0 = round(px - 0.5 * w), round(py - 0.5 * h)
            t = _recolour(_trim(tex, ix0, iy0, allowed), ix0, iy0, under)
            a = t[:, :, 3]
            if a.sum() < 1.0:
                continue
            ys, xs = np.nonzero(a > 0)
            zcap = float(zf_map[np.clip(ys + iy0, 0, H - 1), np.clip(xs + ix0, 0, W - 1)].min())
            zcap = max(zcap, 1e-3)
            z = float(rng.uniform(-0.9, 0.9)) * zcap
            depth01 = (0.9 * zcap - z) / (1.8 * zcap)
            add(ix0, iy0, t, z, 1.0 - p.interior_darkening * shade * depth01, INTERIOR, source=bid)

    # 4d. The core (not in the paper): the whole crown as one flat billboard
    # on the image plane, behind the front layer (hidden in the front view).
    # Seen from the side the front and rear billboards spread apart in depth
    # and leave gaps; through them the sky would show as speckle in flat
    # colour, and the crown would come loose from the trunk top, which also
    # stays on the image plane.
    if p.core_layer and crown.any():
        # Without the crown's rim: a drawn outline runs along it, and it would
        # cross the middle of every side view.
        ys_c, xs_c = np.nonzero(crown)
        r = max(1, int(round(0.02 * max(np.ptp(ys_c), np.ptp(xs_c)))))
        core = cv2.erode(crown_ext.astype(np.uint8), cv2.getStructuringElement(
            cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))) > 0
        if regions:
            # Under the background and its decorations only: the other shapes (tiers,
            # fronds) are cards of their own, which a flat crown on the axis would cover
            # in side views.
            core &= base
        cut = _cut(under, core if core.any() else crown_ext) if core.any() or not regions else None
        if cut is not None:
            x0, y0, tex = cut
            tex = _trim(tex, x0, y0, allowed)
            if tex[:, :, 3].sum() >= 1.0:
                add(x0, y0, tex, 0.0, 1.0, CORE)

    # 4e. The trunk: one billboard on the image plane; ground clutter at its
    # foot another one (in one quad, a wide island would pull the trunk off
    # the crown's axis in side views).
    ground_ext = np.zeros_like(trunk_ext)
    if ground_w.any():
        g = ground_w
        # Labelled on the opaque pixels, then extended: the soft rim of the
        # ground goes with the ground, or trunk strips would span it and
        # turn about the ground's middle in side views.
        ground_ext = _extend(np.where(trunk_w & g, 1, np.where(trunk_w, 2, 0)).astype(np.int32),
                             trunk_ext) == 1
    # A leaning trunk is cut into horizontal strips, each its own axial
    # billboard: turned sideways, one flat quad would swing its top away from
    # the crown by half the lean; strips follow the crown's axis.
    # The ground turns about the trunk's foot, so the trunk stays standing
    # where it stood on it (about its own middle, a wide island would slide
    # under the trunk).
    trunk_only = trunk_ext & ~ground_ext
    pieces = []
    if trunk_only.any() and not crown.any():
        xs_t = np.nonzero(trunk_only)[1]
        pieces.append((trunk_only, 0.5 * (xs_t.min() + xs_t.max() + 1)))
    elif trunk_only.any():
        pieces += _trunk_strips(trunk_only, H)
    # pieces[-1] holds the trunk's foot.
    pieces.insert(0, (ground_ext, pieces[-1][1] if pieces else None))
    n_crown = len(centers)
    for piece, pivot in pieces:
        cut = _cut(work, piece, pivot)
        if cut is not None:
            x0, y0, tex = cut
            add(x0, y0, tex, 0.0, 1.0, TRUNK_LAYER)
    if _STAR_ONE and regions and n_crown and _fan_crown(crown) and silhouette_outline(work).outlined:
        # A palm's crown (a star of fronds meeting at the hub) as one billboard turning about
        # the trunk's top: see :func:`_one_star`.
        top = next((pv for pc, pv in pieces[1:] if pc.any() and pv is not None), None)
        cut = _cut(work, crown_ext, top)
        if cut is not None:
            keep = list(range(n_crown, len(centers)))
            centers, sizes, tints, layers = ([a[i] for i in keep] for a in (centers, sizes, tints, layers))
            used = sorted({tex_idx[i] for i in keep})
            remap = {t: j for j, t in enumerate(used)}
            textures = [textures[t] for t in used]
            tex_idx = [remap[tex_idx[i]] for i in keep]
            sources = list(range(len(keep)))
            x0, y0, tex = cut
            add(x0, y0, tex, 1e-3, 1.0, FRONT)

    # With drawn regions the crown's outlines travel on their shapes' billboards; only the
    # trunk's outlines are still drawn behind the fills.
    behind = lines & (~crown_ext | _outer_lines(lines, opaque)) if regions else lines
    if regions and silhouette_outline(work).outlined:
        # With them, the anti-aliased fringe of an outlined silhouette's outline (pixels next
        # to it darker than the fill beyond them): on the rim pieces it would pile up in dark
        # fans where a side view stacks them.
        flat = _colour_span3(work[:, :, :3]) <= 0.04
        ref = extend_nearest(work[:, :, :3], flat & crown_ext & ~lines) if (flat & crown_ext).any() else work
        lum_w = work[:, :, :3] @ _LUM3
        ring = cv2.dilate(behind.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
        behind = behind | (ring & crown_ext & ~lines & (lum_w < ref[:, :, :3] @ _LUM3 - 0.03))
    line_masks = _line_masks(behind, textures, tex_idx, centers, sizes)

    return BillboardCloud(
        centers=np.asarray(centers, np.float64).reshape(-1, 3),
        sizes=np.asarray(sizes, np.float64).reshape(-1, 2),
        texture=np.asarray(tex_idx, np.int64),
        tint=np.asarray(tints, np.float64),
        layer=np.asarray(layers, np.int64),
        source=np.asarray(sources, np.int64),
        textures=textures, axis=axis, image=work, superpixels=sp_lab,
        depth=hmap, replaced=curves, scale=s, lines=lines, line_masks=line_masks,
    )


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


# ---------------------------------------------------------------------------
# 5. Line art
# ---------------------------------------------------------------------------


def line_art(rgba, *, width: float = 0.04, contrast: float = 0.12, alpha_threshold: float = 0.5,
             flat_span: float = 0.04) -> np.ndarray:
    """The drawn outlines of a clip-art tree: thin dark strokes that border flat colour.

    A pixel is on a stroke when a grey-level closing with a disc of
    ``width`` times the tree's size (its longer side; the disc spans
    ``width / 2`` each side of a stroke's middle) brightens its luminance
    by more than ``contrast``: it lies on a dark feature thinner than the
    disc, between brighter ones; the transparent surround counts as
    white, so an outline along the silhouette is a stroke too. Only
    strokes within one disc of a flat-coloured region count (pixels whose
    3 x 3 colour span is at most ``flat_span``, in 4-connected pieces at
    least as large as the disc's bounding square): a drawing's outlines
    border its fills, while the dark gaps between the leaves of a
    photograph border no flat colour and are left alone.

    Parameters
    ----------
    rgba : (H, W, 4) array_like
        Straight RGBA image in [0, 1].
    width : float
        Widest stroke, as a fraction of the tree's size.
    contrast : float
        Luminance a stroke is darker than what the closing fills it with.
    alpha_threshold : float
        Opaque where alpha >= this.
    flat_span : float
        Largest per-channel colour range of a flat pixel's 3 x 3 window.

    Returns
    -------
    (H, W) bool ndarray
        Stroke pixels (alpha > 0).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((60, 60, 4), np.float32)
    >>> img[10:50, 10:50] = (0.1, 0.7, 0.2, 1.0)      # a green square
    >>> img[10:50, 10:12, :3] = 0.0                    # outlined on its left
    >>> lines = line_art(img)
    >>> bool(lines[30, 10:12].all()), bool(lines[30, 20:48].any())
    (True, False)
    """
    img = np.asarray(rgba, dtype=np.float32)
    if img.ndim != 3 or img.shape[2] != 4:
        raise ValueError(f"rgba must be an (H, W, 4) array, got shape {img.shape}")
    for name, v in (("width", width), ("contrast", contrast), ("flat_span", flat_span)):
        if not np.isfinite(v) or v < 0:
            raise ValueError(f"{name} must be a finite number >= 0, got {v}")
    a = img[:, :, 3]
    opaque = a >= alpha_threshold
    out = np.zeros(a.shape, bool)
    if not opaque.any() or width <= 0:
        return out
    ys, xs = np.nonzero(opaque)
    size = max(np.ptp(ys), np.ptp(xs)) + 1
    r = max(1, int(round(0.5 * width * size)))
    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    lum = img[:, :, :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    lum = np.where(opaque, lum, 1.0).astype(np.float32)
    pad = 2 * r + 1
    closed = cv2.morphologyEx(np.pad(lum, pad, constant_values=1.0), cv2.MORPH_CLOSE, disc)[pad:-pad, pad:-pad]
    dark = (a > 1e-3) & (closed - lum > contrast)
    if not dark.any():
        return out
    rgb = composite_over(img, (1.0, 1.0, 1.0))
    span = (ndi.maximum_filter(rgb, size=(3, 3, 1)) - ndi.minimum_filter(rgb, size=(3, 3, 1))).max(axis=2)
    flat = (a >= 0.99) & (span <= flat_span)
    lab, _ = ndi.label(flat)
    area = np.bincount(lab.ravel())
    area[0] = 0
    big = area[lab] >= (2 * r + 1) ** 2
    if big.sum() < 0.05 * opaque.sum() and palette_coverage(img) >= FLAT_COVERAGE:
        # Beyond the rule above: fills too thin for flat 3 x 3 windows (outlined
        # palms at 128 px) are found by colour, the few main colours of flat art.
        fill = palette_pixels(img) & ~dark
        lab, _ = ndi.label(fill)
        area = np.bincount(lab.ravel())
        area[0] = 0
        big |= area[lab] >= (2 * r + 1) ** 2
    near = cv2.dilate(big.astype(np.uint8), cv2.getStructuringElement(
        cv2.MORPH_ELLIPSE, (4 * r + 3, 4 * r + 3))) > 0
    return dark & near


_LUM3 = np.array([0.2126, 0.7152, 0.0722], np.float32)


def _colour_span3(rgb: np.ndarray) -> np.ndarray:
    """Largest per-channel range of each pixel's 3 x 3 window."""
    return (ndi.maximum_filter(rgb, size=(3, 3, 1)) - ndi.minimum_filter(rgb, size=(3, 3, 1))).max(axis=2)


def _fill_lines(image: np.ndarray, lines: np.ndarray, support: np.ndarray) -> np.ndarray:
    """``image`` with every line pixel given the colour of the nearest non-line pixel of ``support``."""
    keep = support & ~lines
    if not keep.any():
        return image
    out = image.copy()
    out[lines, :3] = extend_nearest(image[:, :, :3], keep)[lines]
    return out


def _line_masks(lines, textures, tex_idx, centers, sizes) -> list:
    """Per texture, its pixels on ``lines`` where the front view puts it (None: none)."""
    out = [None] * len(textures)
    if not lines.any():
        return out
    H, W = lines.shape
    for i, tid in enumerate(tex_idx):
        if out[tid] is not None:
            continue
        w, h = sizes[i]
        x0 = int(round(centers[i][0] - 0.5 * w))
        y0 = int(round(centers[i][1] - 0.5 * h))
        m = np.zeros((int(h), int(w)), bool)
        ax0, ay0, ax1, ay1 = max(x0, 0), max(y0, 0), min(x0 + int(w), W), min(y0 + int(h), H)
        if ax1 > ax0 and ay1 > ay0:
            m[ay0 - y0: ay1 - y0, ax0 - x0: ax1 - x0] = lines[ay0:ay1, ax0:ax1]
        m &= textures[tid][:, :, 3] > 0
        if m.any():
            out[tid] = m
    return out
