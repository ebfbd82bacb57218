"""Training layers: scribbles on one leaf grown into layer masks by lazy snapping.

The user scribbles each layer (veins, spots, ...) on the training leaf with a
few short strokes. Each layer grows into a mask by lazy snapping (Li, Sun,
Tang & Shum 2004), the tool the paper names for this step:

1. the blade is over-segmented into small superpixels (SLIC in CIELAB,
   :func:`skimage.segmentation.slic` restricted to the blade);
2. a colour model of the layer (k-means centres of the colours under its
   scribbles, only those of its pixels that stand out from the blade
   around it: a brush wider than a vein also covers blade; colours are
   CIELAB, with ``local_contrast > 0`` also each pixel's difference from
   the blade around it, so uneven lighting does not make bright plain
   blade look like a pale vein) and
   one of the rest (colours under the other layers' and the blade's
   scribbles, plus the blade without the ``max_layer_fraction`` (15 %) of
   it most like the layer) give each superpixel the data
   costs ``E1(fg) = d_F / (d_F + d_B)``, ``E1(bg) = d_B / (d_F + d_B)``
   (``d`` = distance to the nearest centre);
3. neighbouring superpixels pay ``E2 = exp(-beta |C_i - C_j|^2)`` per pixel
   of shared border for taking different labels; a graph cut (PyMaxflow)
   with the scribbled superpixels pinned finds the labelling;
4. a pixel-level graph cut over the blade (lazy snapping's boundary
   editing, here automatic) with the pixels' own colour costs plus a
   ``prior`` for the superpixel labelling: superpixels steady the result,
   and a layer thinner than a superpixel (a one-pixel vein) is still found.

Layers have a user-set ``order`` (0 = top). Where two grown layers overlap
the upper one keeps the pixel; the background (blade) is what remains.

The steps live in their own modules: the scribbles in
:mod:`branchnb.leaves.layers_scribbles`, the colour models in
:mod:`branchnb.leaves.layers_colours`, the graph cuts in
:mod:`branchnb.leaves.layers_cuts`, thin line layers in
:mod:`branchnb.leaves.layers_lines`; this module runs them
(:func:`grow_layers`) and re-exports their names.
"""

from __future__ import annotations

from dataclasses import dataclass

import maxflow
import numpy as np
from skimage.color import rgb2lab
from skimage.segmentation import slic

from ..core.image import as_mask, as_rgb
from ..core.morphology import _binary_dilation
from ..core.params import check_params, param
from ._lines import _NETWORK, _line_channel, _network, _ridges
from .analysis_outline import _unscribbled_outline

# Lazy snapping's steps, one module each; every name importable from here as before.
from .layers_colours import _kmeans, _local_contrast, _nearest, _nearest_nb  # noqa: F401
from .layers_cuts import _HARD, _LINE_PENALTY, _beta, _refine, _superpixel_graph  # noqa: F401
from .layers_lines import (  # noqa: F401
    _ALONG_NETWORK,
    _DENSE_LINES,
    _NARROW_LONG,
    _OFF_LINE,
    _OFF_LINE_REACH,
    _OFF_LINE_SIDES,
    _ON_LINE,
    _ON_LINE_ABOVE,
    _ON_LINE_KEEP,
    _along_lines,
    _elongation,
    _line_kind,
    _off_lines,
    _on_line_pins,
)
from .layers_scribbles import (  # noqa: F401
    _RING_SPLIT,
    MAX_SCRIBBLES,
    _check_scribbles,
    _on_layer,
    scribble_mask,
    simulate_scribbles,
)
from .margin_band import layer_colours, layer_share, scribbled_band

# The user's scribbles and layers (the data model) live in .scribbles; importable from here as before.
from .scribbles import Layer, LayerSet, Scribble, _as_scribble, _check_dict, _check_list  # noqa: F401

__all__ = ["Scribble", "Layer", "LayerSet", "SnapParams", "TrainingLayers",
           "scribble_mask", "grow_layers", "simulate_scribbles"]

#: A thin line layer's scribbled pixels between its lines left unpinned (:func:`_on_line_pins`).
_ON_LINE_PINS = True
#: Thin line layers grow along their fainter lines (:func:`branchnb.leaves.layers_lines._along_lines`).
_ALONG = True


@dataclass
class SnapParams:
    """Lazy-snapping parameters (Li, Sun, Tang & Shum 2004): this package's defaults, lazy snapping's noted.

    Parameters
    ----------
    superpixel_size : float
        Mean SLIC superpixel side in pixels (default 5); keep it below the
        thinnest layer's width.
    compactness : float
        SLIC compactness in CIELAB units (default 4; low: superpixels
        follow colour edges).
    clusters : int
        k-means colour centres per colour model (default 32; lazy snapping
        uses 64).
    smoothness : float
        Weight of the boundary term ``E2`` against the data term ``E1``
        (lazy snapping's ``lambda``, default 1).
    refine : bool
        Run the pixel-level graph cut after the superpixel one (default True).
    max_layer_fraction : float
        Largest fraction of the blade a layer covers (default 0.15): the
        background colour model leaves out this share of the blade most
        like the layer. A region layer (not a thin line layer) whose
        colours clearly cover more lifts it to that cover, at most 0.6
        (:func:`branchnb.leaves.margin_band.layer_colours`; beyond the paper).
    prior : float
        Weight of the superpixel labelling in the pixel-level cut (default 0.3).
    local_contrast : float
        Weight of each pixel's colour relative to the blade around it
        (default 0: off, it lowers drawn ink layers; unevenly lit photos: 1).
        Not in the paper.
    shading_scale : float
        Radius of "the blade around it" (a median) for ``local_contrast``,
        in superpixel sides (default 3).
    line_weight : float
        Weight of the ridge (or valley) strength of the lightness for a
        thin line layer (default 1; 0: off): a layer whose scribbled
        pixels are ridges stronger than 85 % of the blade's (a 1-5 px vein,
        pale or dark) adds it, with this weight, to the pixel cut's data
        term (``E1`` in [0, 1]): ``line_weight * s`` to the cost of blade,
        ``0.3 * line_weight * (1 - s)`` to the cost of layer, ``s`` in
        [0, 1] the ridge strength relative to the faintest scribbled line;
        and its pixel cut leaves out the superpixel ``prior`` (superpixels
        wider than the vein made blocks of blade). Not in the paper: on a streaked grass blade the
        colours of a thin vein and of the blade beside it overlap.
    """

    superpixel_size: float = param(5.0, min=2.0, max=40.0, step=0.5,
                                   help="mean superpixel side (px); smaller than the thinnest layer")
    compactness: float = param(4.0, min=0.1, max=40.0,
                               help="SLIC compactness in CIELAB units (low: follows colour edges)")
    clusters: int = param(32, min=2, max=64, help="k-means colour centres per model (lazy snapping: 64)")
    smoothness: float = param(1.0, min=0.0, max=20.0, help="weight of E2 against E1 (lazy snapping's lambda)")
    refine: bool = param(True, help="pixel-level graph cut after the superpixel one")
    max_layer_fraction: float = param(0.15, min=0.01, max=0.9, step=0.01,
                                      help="largest fraction of the blade a layer covers (background model)")
    prior: float = param(0.3, min=0.0, max=2.0, step=0.05,
                         help="weight of the superpixel labelling in the pixel-level cut")
    local_contrast: float = param(0.0, min=0.0, max=4.0, step=0.1,
                                  help="weight of each pixel's colour relative to the blade around it "
                                       "(unevenly lit photos: 1; off by default, it lowers drawn ink layers)")
    shading_scale: float = param(3.0, min=1.0, max=20.0, step=0.5,
                                 help="radius of 'the blade around it' (median), in superpixel sides")
    line_weight: float = param(1.0, min=0.0, max=4.0, step=0.05,
                               help="weight of the ridge strength for thin line layers (veins of 1-5 px; 0: off)")


@dataclass
class TrainingLayers:
    """Result of :func:`grow_layers`.

    Parameters
    ----------
    masks : dict of str -> (H, W) bool ndarray
        The grown layer masks (disjoint, inside the blade).
    blade : (H, W) bool ndarray
        The leaf's blade mask it was grown in.
    background : (H, W) bool ndarray
        The blade minus every layer.
    order : list of str
        Layer names, top first.
    superpixels : (H, W) int ndarray
        SLIC labels (0 outside the blade).
    along : dict of str -> (H, W) bool ndarray, optional
        Per thin line layer, the pixels of its mask it took by growing along
        fainter unscribbled lines (:func:`branchnb.leaves.layers_lines._along_lines`);
        None or a missing name: none.
    """

    masks: dict
    blade: np.ndarray
    background: np.ndarray
    order: list
    superpixels: np.ndarray
    along: dict | None = None


def grow_layers(image, blade, layer_set: LayerSet, params: SnapParams | None = None, *,
                rng=0) -> TrainingLayers:
    """Grow the scribbled layers of the training leaf into masks by lazy snapping.

    Parameters
    ----------
    image : (H, W, 3|4) array_like
        The training leaf (alpha, if any, is ignored: ``blade`` says where the leaf is).
    blade : (H, W) bool array_like
        The leaf's blade mask.
    layer_set : LayerSet
        The user's layers; every layer needs at least one scribble.
    params : SnapParams, optional
        Lazy-snapping parameters; None: ``SnapParams()`` (the defaults).
    rng : int or Generator
        Seeds the k-means colour models.

    Returns
    -------
    TrainingLayers

    Raises
    ------
    ValueError
        No layers; a layer without scribbles; a scribble outside the image
        or the leaf (each message names the layer and the scribble).

    Notes
    -----
    Beyond the paper: on a drawn leaf (its rim inked,
    :func:`branchnb.leaves.flatart.drawn_outline`) a thin layer does not
    grow along the ink outline unless its scribbles lie there
    (:func:`branchnb.leaves.analysis_outline._unscribbled_outline`); the
    outline, a dark line like a vein, was otherwise grown from vein
    scribbles and then induced as vein on every exemplar.

    Beyond the paper too: for a thin line layer (see ``SnapParams.line_weight``)
    the background colour model keeps every blade pixel that cannot be on a
    line (off every line, not standing out as the scribbled lines do, more
    than 3 px from either: :func:`_off_lines`), even where its colour is
    the layer's; lazy snapping leaves out the ``max_layer_fraction`` of the
    blade most like the layer whatever it is. On small leaves (96-200 px)
    with 1-px veins running into a rim of the veins' hue (a ginkgo's yellow
    rim) the rim fell in that share and the layer grew over it (training
    vein IoU 0.47 at 128 px; the induced layer then followed the rim).

    Beyond the paper too (:mod:`branchnb.leaves.margin_band`): a layer
    scribbled in a band of its own colours along the outline (a variegated
    leaf's margin) is never a thin line layer, and a region layer's
    ``max_layer_fraction`` is lifted to its colours' cover; a cream band of
    35-45 % of the blade lost its outer half (training IoU 0.16-0.84 at
    160-600 px, now 0.97-1.00).

    Small leaves (96-128 px, veins 1-2 px wide) beyond the paper as well:
    a thin line layer's plain-blade level comes from the blade far from any
    line where that blade is flat, and from the user's blade scribbles
    (:func:`branchnb.leaves._lines._plain_level`, ``_line_channel``); a
    stroke's ring crowded by close parallel veins is read by its
    blade-like half (:func:`_on_layer`). Before, the 1-px laterals of a
    128-px lobed leaf and the blade between a 96-px strip's veins went
    wrong (training IoU 0.67-0.72 and 0.49-0.58 at 96 px; now 0.85-0.86
    and 0.63-0.65, ``tests/test_leaves_small_training.py``). Fainter veins
    (20 % darker than the blade, not 40 %) packed 3-5 px apart on a 96-px
    strip still grow badly (IoU 0.32-0.54).

    Beyond the paper too (issue 22): a thin line layer grows on along the
    fainter lines running out of it, the secondaries and tertiaries nobody
    scribbled (:func:`branchnb.leaves.layers_lines._along_lines`: pixels
    standing out from the blade around them by 40 % of what the scribbled
    pixels do, joined to the cut's layer; a hysteresis, as Canny's), when
    the layer grew into or was scribbled in a network of lines (not a spot
    layer); the lines it grows along never take another layer's pixels. And
    strokes over the junctions of a dense small venation (median
    line-likeness 0.94-0.98) still make a line layer when they lie in a thin
    network (:func:`branchnb.leaves._lines._network`). Procedural
    ``leaf_family`` leaves (lobed, trilobed, elliptic, fan; 128-400 px;
    seeds 0-5; training leaves 0 and 2; twelve :func:`simulate_scribbles`
    strokes per layer, ``python -m branchnb.leaves._measure_grown``): vein
    IoU mean 0.79 -> 0.86, precision 0.93 -> 0.92 (worst 0.86), spots 0.89
    either way; cases under 0.75: 51 of 192 -> 10 (128-px elliptic leaves
    0.61-0.69, and two 128-px leaves, 0.24 and 0.31, whose strokes make no
    line layer). A grown layer never takes most of the blade this way, nor the
    blade within 5 px of a line of the other kind (a drawn leaf's ink
    outline: the fill beside it stood out and pale veins grew round the rim).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((40, 40, 3), (0.8, 0.7, 0.2), np.float32)
    >>> img[:, 19:22] = (0.4, 0.2, 0.1)
    >>> ls = LayerSet([Layer("veins")])
    >>> ls.add_scribble("veins", [(20, 5), (20, 15)], radius=1)
    >>> r = grow_layers(img, np.ones((40, 40), bool), ls)
    >>> bool(r.masks["veins"][:, 19:22].mean() > 0.95), bool(r.masks["veins"][:, :17].any())
    (True, False)
    """
    params = check_params(params if params is not None else SnapParams(), name="params")
    rgb = as_rgb(image, name="image")
    if np.ndim(image) == 3 and np.shape(image)[2] == 4:
        # The colours as they are (as the induction sees them): composited
        # over white, a background-model exemplar's feathered rim turned its
        # dark outline grey, and the grey joined the ink layer.
        rgb = as_rgb(np.asarray(image)[..., :3], name="image")
    if np.shape(blade) != rgb.shape[:2]:
        raise ValueError(f"blade has shape {np.shape(blade)}, but image is {rgb.shape[:2]} (they must match)")
    blade = as_mask(blade, shape=rgb.shape[:2], name="blade")
    if not isinstance(layer_set, LayerSet):
        raise TypeError(f"layer_set must be a LayerSet, got {type(layer_set).__name__}")
    if not layer_set.layers:
        raise ValueError("layer_set has no layers: add at least one layer with scribbles")
    if blade.sum() < 16:
        raise ValueError("blade is (almost) empty: the training leaf has no blade pixels")
    marks, each = _check_scribbles(layer_set, blade)
    for layer in layer_set.layers:
        if not layer.scribbles:
            raise ValueError(f"layer_set layer {layer.name!r} has no scribbles: scribble it or remove it")
    from ..core.random import as_rng
    rng = as_rng(rng)
    lab = rgb2lab(rgb).astype(np.float32)
    # L in 0..100, a/b roughly -80..80: scale so the three weigh alike.
    feat = lab / np.float32(100.0)
    if params.local_contrast > 0:
        feat = np.concatenate([feat, params.local_contrast * _local_contrast(
            feat, blade, params.shading_scale * params.superpixel_size)], axis=2)
    h, w = blade.shape
    # SLIC on the blade's bounding box without a mask (the masked variant
    # seeds by k-means and is an order of magnitude slower), cut to the blade.
    rows, cols = np.nonzero(blade)
    r0, r1, c0, c1 = rows.min(), rows.max() + 1, cols.min(), cols.max() + 1
    box = slic(lab[r0:r1, c0:c1], n_segments=max(16, int((r1 - r0) * (c1 - c0) / params.superpixel_size**2)),
               compactness=params.compactness, start_label=1, channel_axis=-1,
               enforce_connectivity=True, convert2lab=False)
    sp = np.zeros((h, w), np.int64)
    sp[r0:r1, c0:c1] = box
    # The labels the blade keeps, renumbered 1..n in their order (np.unique's inverse, without its sort).
    vals = sp[blade]
    present = np.zeros(int(vals.max()) + 1, bool)
    present[vals] = True
    sp = np.zeros((h, w), np.int64)
    sp[blade] = np.cumsum(present)[vals]
    n = int(sp.max())
    idx = sp[blade]
    area = np.bincount(idx, minlength=n + 1).astype(np.float64)
    mean = np.stack([np.bincount(idx, feat[..., k][blade], minlength=n + 1) for k in range(feat.shape[2])], 1)
    mean /= np.maximum(area, 1)[:, None]
    edges, border = _superpixel_graph(sp, n)
    d2 = ((mean[edges[:, 0]] - mean[edges[:, 1]]) ** 2).sum(1)
    beta = _beta(d2)
    ridges = _ridges(lab[..., 0], blade) if params.line_weight > 0 else None

    masks = {}
    along = {}
    ink = None
    for layer in layer_set.ordered():
        fg_px = _on_layer(each[layer.name], feat, blade)
        others = np.zeros_like(fg_px)
        for name, m in marks.items():
            if name != layer.name:
                others |= m
        others &= ~fg_px
        line = _line_channel(ridges, fg_px, blade, each[layer.name], marks["blade"]) if ridges is not None else None
        # The blade of the layer's own colours, and its share (its own colour model, its own generator).
        near, cover = layer_colours(feat, blade, fg_px, params.clusters)
        if line is not None and scribbled_band(blade, near, marks[layer.name]):
            # A band of the layer's colour along the outline (a variegated margin) is a region: its
            # scribbled texture answers the ridge filter (on a 7-12 px band, the band itself), and grown
            # as a line it kept only the stretches of it the filter took (training IoU 0.16-0.84).
            line = None
        if line is not None and _ON_LINE_PINS:
            fg_px = _on_line_pins(fg_px, line, ridges, blade)
        prior = params.prior
        if line is not None:
            # A thin line layer (a vein narrower than a few pixels): how
            # much a pixel is a ridge (or valley) of the scribbled kind
            # joins the pixel cut's data term (line_weight), and the
            # superpixels, wider than the line, no longer steady the pixel
            # cut (they made blocks of blade beside a 5-px midrib).
            prior = 0.0
        blade_feat = feat[blade]
        fg_c = _kmeans(feat[fg_px], params.clusters, rng)
        d_f_blade = _nearest(blade_feat, fg_c)
        # The blade without the part most like the layer (a layer covers at
        # most max_layer_fraction of it), plus the other scribbles.
        # A region layer covering more of the blade than that (a margin band: 35-45 %) is all left out:
        # with 15 % the rest of its colour stayed "blade" and the band lost its outer half.
        share = params.max_layer_fraction if line is not None else layer_share(cover, params.max_layer_fraction)
        k_near = int(len(d_f_blade) * share)
        far = np.argpartition(d_f_blade, k_near)[k_near:]
        if line is not None:
            # A thin line layer can only be where a line is: plain blade
            # off every line stays in the background model even where its
            # colour is the layer's (beyond lazy snapping). On a small leaf
            # (128 px ginkgo) 1-px veins running into a yellow rim put the
            # rim's own colour in the 15 % left out, and the layer grew
            # into the rim (training vein IoU 0.47, induced 0.41-0.49).
            # (np.union1d's sorted indices, by a mask: the union's sort was a tenth of the layer at 1 MP.)
            keep = _off_lines(line, ridges, fg_px, blade)[blade]
            keep[far] = True
            far = np.flatnonzero(keep)
        bg_samples = np.concatenate([blade_feat[far], feat[others]])
        bg_c = _kmeans(bg_samples, params.clusters, rng)
        d_b_blade = _nearest(blade_feat, bg_c)
        # Per-superpixel data costs (sums over its pixels).
        tot = d_f_blade + d_b_blade + 1e-6
        e_fg = np.bincount(idx, d_f_blade / tot, minlength=n + 1)
        e_bg = np.bincount(idx, d_b_blade / tot, minlength=n + 1)
        # A superpixel is pinned to the layer only when the scribble's layer
        # pixels fill most of it: a 1-px vein crossing a 5-px superpixel
        # would pin 24 px of blade, and the cut grows the layer from there
        # over the blade (the pixel-level cut pins the layer pixels themselves).
        marked = np.bincount(sp[fg_px], minlength=n + 1)
        pin_fg = marked >= 0.5 * np.maximum(area, 1)
        pin_fg[0] = False
        pin_bg = np.zeros(n + 1, bool)
        pin_bg[np.unique(sp[others])] = True
        pin_bg &= ~pin_fg
        g = maxflow.Graph[float]()
        nodes = g.add_nodes(n + 1)
        wgt = params.smoothness * border * np.exp(-beta * d2)
        g.add_edges(nodes[edges[:, 0]], nodes[edges[:, 1]], wgt, wgt)
        # Source side = layer: cost of "layer" goes to the sink capacity.
        src = e_bg + np.where(pin_fg, _HARD, 0.0)
        snk = e_fg + np.where(pin_bg, _HARD, 0.0)
        src[0], snk[0] = 0.0, _HARD
        g.add_grid_tedges(nodes, src, snk)
        g.maxflow()
        is_fg = ~g.get_grid_segments(nodes)
        is_fg[0] = False
        mask = is_fg[sp] & blade
        if params.refine:
            # The superpixel labelling weighs in as far as its own colour
            # evidence was clear: |E1(fg) - E1(bg)| per pixel of the superpixel.
            conf = np.abs(e_fg - e_bg) / np.maximum(area, 1.0)
            mask = _refine(mask, feat, blade, fg_px, others, fg_c, bg_c, prior * conf[sp],
                           params.smoothness, line, params.line_weight, distances=(d_f_blade, d_b_blade))
        if line is not None and _ALONG and (_elongation(mask, fg_px) >= _ALONG_NETWORK or _network(
                ridges[..., 2 + _line_kind(ridges, fg_px)], fg_px, blade) >= _NETWORK):
            # Only a layer grown into, or scribbled in, a network of lines (veins; a spot layer taken
            # for a line layer grew along the dark flanks of pale veins: spots IoU 0.50 -> 0.19 on a
            # 400-px elliptic leaf).
            layers_px = np.zeros_like(fg_px)
            for name, m in marks.items():
                if name not in (layer.name, "blade"):
                    layers_px |= m
            exclude = None
            if layers_px.any():
                # The other layers' scribbled colours themselves (evenly thinned, no k-means: the
                # shared generator stays as it was for the layers after this one).
                oc = feat[layers_px]
                oc = oc[np.linspace(0, len(oc) - 1, min(len(oc), 8 * params.clusters)).astype(int)]
                exclude = np.zeros_like(blade)
                exclude[blade] = _nearest(blade_feat, oc) < d_f_blade
            grown = _along_lines(mask, ridges, fg_px, blade, exclude)
            along[layer.name] = grown & ~mask
            mask = grown
        if line is not None:
            # A drawn leaf's ink outline is a line like a vein: not grown into a thin layer nobody scribbled there.
            if ink is None:
                from .flatart import drawn_outline
                ink = drawn_outline(rgb, blade)
            mask = mask & ~_unscribbled_outline(mask, blade, marks[layer.name], ink)
        masks[layer.name] = mask
    # The fainter lines a thin layer grew along never take another layer's own pixels (an upper vein
    # layer grew into pale spots it touched: spots IoU 0.50 -> 0.22 on a 400-px elliptic leaf).
    for name, extra in along.items():
        core = np.zeros((h, w), bool)
        for other, m in masks.items():
            if other != name:
                core |= m & ~along[other] if other in along else m
        # nor the rim round them (a dark spot's pale rim stands out as a pale vein does)
        masks[name] = masks[name] & ~(extra & _binary_dilation(core, iterations=2))
    # Overlaps go to the upper layer.
    taken = np.zeros((h, w), bool)
    for name in [x.name for x in layer_set.ordered()]:
        masks[name] = masks[name] & ~taken
        taken |= masks[name]
    return TrainingLayers(masks, blade, blade & ~taken, [x.name for x in layer_set.ordered()], sp,
                          along={name: extra & masks[name] for name, extra in along.items()})
