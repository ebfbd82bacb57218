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
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import maxflow
import numba
import numpy as np
from scipy import ndimage as ndi
from skimage.color import rgb2lab
from skimage.segmentation import slic

from ..core.image import as_mask, as_rgb
from ..core.morphology import _binary_dilation, _binary_opening, fill_holes
from ..core.params import check_params, param
from ..core.validate import brief, check_int, check_real, check_shape
from ._lines import _line_channel, _ridges
from .analysis_outline import _unscribbled_outline
from .margin_band import layer_colours, layer_share, scribbled_band

# The user's scribbles and layers (the data model) live in .scribbles; importable from here as before.
from .scribbles import Layer, LayerSet, Scribble, _as_scribble, _check_dict, _check_list  # noqa: F401

__all__ = ["Scribble", "Layer", "LayerSet", "SnapParams", "TrainingLayers",
           "scribble_mask", "grow_layers", "simulate_scribbles"]

_HARD = 1e9
#: Cost of "layer" off a line, relative to the cost of "blade" on one (thin line layers).
_LINE_PENALTY = 0.3
#: Line strength below which a pixel of a thin line layer's blade is off every line (background model).
_OFF_LINE = 0.05
#: Pixels this close (px, 4-connected steps) to a possible line pixel may still be layer (background model).
_OFF_LINE_REACH = 3
#: ... or within the square root of the blade's area over this many px (a large leaf's wide veins).
_OFF_LINE_SIDES = 25.0
#: A narrow part of the blade (a petiole) covers at least this many squares of its half width.
_NARROW_LONG = 6.0
#: A ring around a scribble splits in two (blade, other veins) when its halves' medians are this many
#: times the blade half's spread apart (its 90th percentile, its median; :func:`_on_layer`).
_RING_SPLIT = (2.5, 6.0)
#: Scribbles one call of :func:`simulate_scribbles` may make (a user draws 10-15 per layer).
MAX_SCRIBBLES = 10_000


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
    """

    masks: dict
    blade: np.ndarray
    background: np.ndarray
    order: list
    superpixels: np.ndarray


def scribble_mask(scribbles, shape) -> np.ndarray:
    """Rasterise scribbles (capsules of their brush radius) into an (H, W) bool mask.

    Parameters
    ----------
    scribbles : iterable of Scribble or (N, 2) array_like
        The strokes (an array is a Scribble of radius 2).
    shape : (int, int)
        ``(H, W)`` of the mask.

    Returns
    -------
    (H, W) bool ndarray
        True under some stroke; parts outside the image are clipped.

    Examples
    --------
    >>> m = scribble_mask([Scribble([(2, 2), (8, 2)], 1.0)], (5, 12))
    >>> bool(m[2, 2:9].all()), bool(m[4].any())
    (True, False)
    """
    h, w = check_shape(shape, "shape")
    if scribbles is None or isinstance(scribbles, (str, bytes)) or not hasattr(scribbles, "__iter__"):
        raise TypeError(f"scribbles must be an iterable of Scribble or (N, 2) point arrays, got {brief(scribbles)}")
    out = np.zeros((h, w), np.uint8)
    for s in scribbles:
        s = _as_scribble(s, "scribbles")
        pts = np.round(s.points * 16).astype(np.int32)
        # OpenCV refuses strokes over 32767 px thick (a radius changed after the Scribble checked it)
        thick = min(max(1, int(round(2 * s.radius))), 32767)
        if len(pts) == 1:
            cv2.circle(out, tuple(int(v) for v in pts[0]), int(round(min(s.radius, 1e6) * 16)), 1, -1,
                       lineType=cv2.LINE_8, shift=4)
        else:
            cv2.polylines(out, [pts.reshape(-1, 1, 2)], False, 1, thickness=thick,
                          lineType=cv2.LINE_8, shift=4)
    return out.astype(bool)


def _check_scribbles(layer_set: LayerSet, blade: np.ndarray) -> tuple[dict, dict]:
    """Rasterise and validate every scribble: name -> union mask, and name -> one mask per scribble."""
    shape = blade.shape
    out, each = {}, {}
    groups = [(x.name, f"layer_set.layers[{x.name!r}]", x.scribbles) for x in layer_set.layers]
    groups.append(("blade", "layer_set.background", layer_set.background))
    seen: dict = {}
    silhouette = None
    for name, label, scribbles in groups:
        m = np.zeros(shape, bool)
        each[name] = []
        for i, s in enumerate(scribbles):
            p = s.points
            key = (np.round(p, 3).tobytes(), round(float(s.radius), 3))
            if key in seen and seen[key][0] != name:
                raise ValueError(f"{label}.scribbles[{i}] is the same stroke as {seen[key][1]}: one stroke cannot "
                                 "mark two layers (or a layer and the background)")
            seen.setdefault(key, (name, f"{label}.scribbles[{i}]"))
            if (p[:, 0] < -0.5).any() or (p[:, 0] > shape[1] - 0.5).any() or \
                    (p[:, 1] < -0.5).any() or (p[:, 1] > shape[0] - 0.5).any():
                raise ValueError(f"{label}.scribbles[{i}] leaves the image ({shape[1]} x {shape[0]} px)")
            si = scribble_mask([s], shape)
            # Inside the leaf's outline counts as on the leaf: a stroke along a vein the blade
            # mask left out (a hole) is no mistake. A stroke mostly off the leaf is one (another
            # image's coordinates, a forgotten offset): refused with its name, not clipped to a
            # few pixels the user did not mean. The off-blade part of the others is dropped.
            if silhouette is None:
                silhouette = fill_holes(blade)
            on = (si & silhouette).sum()
            if on < 0.5 * si.sum():
                raise ValueError(f"{label}.scribbles[{i}] lies outside the leaf "
                                 f"({int(on)} of {int(si.sum())} pixels on the leaf)")
            m |= si & blade
            each[name].append(si & blade)
        out[name] = m
    return out, each


def _on_layer(each: list, feat: np.ndarray, blade: np.ndarray) -> np.ndarray:
    """The pixels of each scribble that mark its layer.

    A scribble drawn with a brush wider than its layer (a 3-px stroke on a
    1-px vein) covers plain blade as well: its pixels unlike a ring of
    blade 2-5 px around it (farther from the ring's median than 90 % of
    the ring's own pixels) are what it marks. (Half of its pixels, the
    rule before, put a third of plain blade into a thin vein's colour
    model.) Scribbles too short for a ring keep every pixel; a scribble
    inside a layer wider than the ring (a big spot) stands out from
    nothing and keeps the half most unlike the ring.
    """
    out = np.zeros(blade.shape, bool)
    h, w = blade.shape
    whole = np.median(feat[blade], axis=0)
    for m in each:
        ys, xs = np.nonzero(m)
        if len(ys) < 4:
            out |= m
            continue
        # The ring on the scribble's window (6 px beyond it: the 5-step
        # dilation reaches 5), the same pixels as on the whole image.
        y0, y1 = max(ys.min() - 6, 0), min(ys.max() + 7, h)
        x0, x1 = max(xs.min() - 6, 0), min(xs.max() + 7, w)
        mc, fc = m[y0:y1, x0:x1], feat[y0:y1, x0:x1]
        ring = _binary_dilation(mc, iterations=5) & ~_binary_dilation(mc, iterations=2) & blade[y0:y1, x0:x1]
        if ring.sum() < 4:
            out |= m
            continue
        rc = fc[ring]
        ref = np.median(rc, axis=0)
        spread = float(np.percentile(np.sqrt(((rc - ref) ** 2).sum(1)), 90))
        # Parallel veins 3-5 px apart (a 96-px strip) fill half of a ring:
        # its median colour lay between vein and blade, its spread reached
        # the veins, and half of a stroke, plain blade, joined the layer's
        # colours (the layer grew over the blade between the veins). Where
        # the ring splits in two clearly apart (its half nearer the whole
        # blade's median colour, and the rest), that half is the blade
        # around. A streaked, shaded blade's ring varies smoothly: no split.
        to_blade = ((rc - whole) ** 2).sum(1)
        near = to_blade <= np.median(to_blade)
        if near.sum() >= 4 and (~near).sum() >= 4:
            ref_near = np.median(rc[near], axis=0)
            d_near = np.sqrt(((rc[near] - ref_near) ** 2).sum(1))
            gap = float(np.sqrt(((np.median(rc[~near], axis=0) - ref_near) ** 2).sum()))
            # Measured gap / spread (90th percentile, median): a 96-px
            # strip's rings 2.8-4.3 and 6.9-11.7; streaked, shaded grass
            # blades (tests/test_leaves_layers.py) 1.1-2.5 and 2.3-5.5.
            if gap > _RING_SPLIT[0] * max(float(np.percentile(d_near, 90)), 1e-3) and \
                    gap > _RING_SPLIT[1] * max(float(np.median(d_near)), 1e-3):
                ref, spread = ref_near, float(np.percentile(d_near, 90))
        px = fc[mc]  # row-major, as np.nonzero(m)
        d = np.sqrt(((px - ref) ** 2).sum(1))
        keep = d > spread
        if keep.sum() < max(2, 0.1 * len(d)):
            keep = d >= np.median(d)
        out[ys[keep], xs[keep]] = True
    return out


def _local_contrast(feat: np.ndarray, blade: np.ndarray, radius: float) -> np.ndarray:
    """Each pixel's colour minus the blade's median colour around it (``radius`` px, blade only).

    A photographed leaf is lit unevenly: a pale vein on the dark side of
    the blade has the colour of plain blade on the bright side, and a
    colour model alone grows the vein layer over the bright side. What
    stays constant is how the vein stands out from the blade next to it.
    A median, not a mean: a layer covering much of a neighbourhood (dense
    ink lines) would make its own surroundings and stand out from nothing.
    The median is taken on a grid reduced so the window is 7 cells wide
    (shading is smooth), over the cells that are mostly blade.
    """
    from ..core.image import extend_nearest

    h, w = blade.shape
    f = max(1.0, float(radius) / 3.0)
    small = (max(1, int(round(w / f))), max(1, int(round(h / f))))
    # Cells of the reduced grid: the blade's mean colour where they are
    # mostly blade; the rest take no part (the backdrop and the outline
    # drawn around a blade are not "the blade around").
    cover = cv2.resize(blade.astype(np.float32), small, interpolation=cv2.INTER_AREA)
    lo = cv2.resize(np.where(blade[..., None], feat, 0).astype(np.float32), small, interpolation=cv2.INTER_AREA)
    inside = cover > 0.5
    if not inside.any():
        return np.zeros_like(feat)
    lo = np.where(inside[..., None], lo / np.maximum(cover, 1e-6)[..., None], np.nan)
    win = np.lib.stride_tricks.sliding_window_view(np.pad(lo, ((3, 3), (3, 3), (0, 0)), constant_values=np.nan),
                                                   (7, 7), axis=(0, 1))
    with np.errstate(all="ignore"):
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            med = np.nanmedian(win.reshape(win.shape[:3] + (-1,)), axis=-1)
    med = extend_nearest(np.nan_to_num(med), np.isfinite(med).all(-1)).astype(np.float32)
    around = cv2.resize(med, (w, h), interpolation=cv2.INTER_LINEAR)
    return np.where(blade[..., None], feat - around, 0).astype(np.float32)


def _kmeans(samples: np.ndarray, k: int, rng: np.random.Generator) -> np.ndarray:
    samples = np.asarray(samples, np.float32)
    if len(samples) > 20000:
        samples = samples[rng.choice(len(samples), 20000, replace=False)]
    # About ten samples per centre at least: with a few hundred scribbled
    # pixels, one centre per pixel would make every stray pixel under a
    # scribble (a brush wider than a vein also covers blade) a colour of the
    # model, and the layer would grow into everything like it.
    k = int(min(k, len(np.unique(samples.round(1), axis=0)), max(1, len(samples) // 10)))
    if k <= 1:
        return samples.mean(axis=0, keepdims=True)
    crit = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 20, 0.1)
    cv2.setRNGSeed(int(rng.integers(2**31)))
    _, _, centres = cv2.kmeans(samples, k, None, crit, 2, cv2.KMEANS_PP_CENTERS)
    return centres


def _nearest(colours: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """Distance of each colour to its nearest centre (compiled, one pixel at a time, no temporaries).

    Summed as ``|c - centre|^2`` in float64: at most ~1e-3 Lab units from
    the ``|c|^2 - 2 c.centre + |centre|^2`` of float32 matrix products it
    replaced (which cancel on bright colours), 10x faster at a megapixel.
    """
    c = np.ascontiguousarray(colours, np.float32).reshape(len(colours), -1)
    k = np.ascontiguousarray(centres, np.float32).reshape(len(centres), -1)
    return _nearest_nb(c, k)


@numba.njit(cache=True, nogil=True)
def _nearest_nb(colours, centres):  # pragma: no cover - compiled
    n, d = colours.shape
    out = np.empty(n, np.float32)
    for i in range(n):
        best = np.inf
        for a in range(centres.shape[0]):
            s = 0.0
            for j in range(d):
                t = np.float64(colours[i, j]) - np.float64(centres[a, j])
                s += t * t
            if s < best:
                best = s
        out[i] = np.sqrt(best)
    return out


def _superpixel_graph(labels: np.ndarray, n: int):
    """Pairs of 4-adjacent superpixels and the length of their shared border."""
    pairs = []
    for a, b in ((labels[:, :-1], labels[:, 1:]), (labels[:-1, :], labels[1:, :])):
        m = (a != b) & (a > 0) & (b > 0)
        pairs.append(np.stack([a[m], b[m]], 1))
    p = np.concatenate(pairs)
    p.sort(axis=1)
    key = p[:, 0].astype(np.int64) * (n + 1) + p[:, 1]
    uniq, counts = np.unique(key, return_counts=True)
    return np.stack([uniq // (n + 1), uniq % (n + 1)], 1), counts.astype(np.float64)


def _beta(diff2: np.ndarray) -> float:
    m = float(np.mean(diff2)) if diff2.size else 1.0
    return 1.0 / (2.0 * max(m, 1e-6))


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
    _, inv = np.unique(sp[blade], return_inverse=True)
    sp = np.zeros((h, w), np.int64)
    sp[blade] = inv.ravel() + 1
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
            far = np.union1d(far, np.flatnonzero(_off_lines(line, ridges, fg_px, blade)[blade]))
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
                           params.smoothness, line, params.line_weight)
        if line is not None:
            # A drawn leaf's ink outline is a line like a vein: not grown into a thin layer nobody scribbled there.
            if ink is None:
                from .flatart import drawn_outline
                ink = drawn_outline(rgb, blade)
            mask = mask & ~_unscribbled_outline(mask, blade, marks[layer.name], ink)
        masks[layer.name] = mask
    # Overlaps go to the upper layer.
    taken = np.zeros((h, w), bool)
    for name in [x.name for x in layer_set.ordered()]:
        masks[name] = masks[name] & ~taken
        taken |= masks[name]
    return TrainingLayers(masks, blade, blade & ~taken, [x.name for x in layer_set.ordered()], sp)


#: A thin line layer's scribbled pixels between its lines left unpinned (:func:`_on_line_pins`).
_ON_LINE_PINS = True
#: ... kept where its strength is at least this or the pixel stands out at least
#: _ON_LINE_ABOVE times as much as the scribbled pixels do.
_ON_LINE = 0.25
_ON_LINE_ABOVE = 0.5
#: ... unless fewer than this share of the scribbled layer pixels are left (then all are kept).
_ON_LINE_KEEP = 0.3
#: ... and only where the lines (strength 0.5 or more) cover at least this share of the blade.
_DENSE_LINES = 0.15


def _on_line_pins(fg_px: np.ndarray, line: np.ndarray, ridges: np.ndarray, blade: np.ndarray) -> np.ndarray:
    """The scribbled layer pixels of a thin line layer, without those between its lines (beyond lazy snapping).

    Radius-1 strokes over parallel veins 3-5 px apart (a 96-px strip)
    leave plain blade between the veins among the pixels :func:`_on_layer`
    keeps: its ring around each stroke is mostly other veins. Pinned to the
    layer, those pixels took the blade between the scribbled veins into it
    and into its colour model (faint veins, 20 % darker than the blade:
    training IoU 0.32-0.48, 9-16 % of the layer more than 1 px off every
    vein; induced on the other leaves 0.44-0.49). Kept: pixels on a line
    (strength at least :data:`_ON_LINE`) or standing out from the blade
    around them at least :data:`_ON_LINE_ABOVE` as much as the scribbled
    pixels do (the inside of a vein wider than the line filter). Only
    where the lines are dense (at least :data:`_DENSE_LINES` of the blade
    at half strength or more: small leaves, 14-29 % measured on 96-128 px
    strips, lobed and elliptic leaves): on a sparse venation
    the scribbles' off-line pixels are the flanks of wider veins the user
    meant (the sample maple, 8 %: its vein layer lost a quarter of its
    pixels and the induced veins' IoU with the hand tracing fell 0.48 ->
    0.32 without this). All are kept when under :data:`_ON_LINE_KEEP` of
    them would be left, or when the scribbles do not lie on lines (their
    median line strength under 0.5: strokes over a plain blade).
    """
    if float(np.count_nonzero((np.asarray(line) >= 0.5) & blade)) < _DENSE_LINES * max(np.count_nonzero(blade), 1):
        return fg_px
    # only scribbles that lie on the lines: strokes along veins painted out of a plain blade (median
    # line strength 0.00 on them, 0.70-1.00 on real veins) would keep only the grain's ridges they cross,
    # and the layer grew along those into one that stands out (structural where it is not)
    if float(np.median(np.asarray(line)[fg_px])) < 0.5:
        return fg_px
    k = 1 if np.median(ridges[..., 3][fg_px]) > np.median(ridges[..., 2][fg_px]) else 0
    above = ridges[..., 2 + k]
    lift = max(float(np.median(above[fg_px])), 1e-6)
    on = fg_px & ((np.asarray(line) >= _ON_LINE) | (above >= _ON_LINE_ABOVE * lift))
    if on.sum() < max(4, _ON_LINE_KEEP * fg_px.sum()):
        return fg_px
    return on


def _off_lines(line: np.ndarray, ridges: np.ndarray, fg_px: np.ndarray, blade: np.ndarray) -> np.ndarray:
    """Pixels that cannot be part of a thin line layer: off every line and not standing out as its lines do.

    Off a line: line strength below ``_OFF_LINE``. Standing out: at least
    half as much darker (lighter) than the blade around it (11 px) as the
    scribbled pixels are; the inside of a vein wider than the line filter
    (a 4-px midrib) answers no line filter but stands out, a pale rim of
    the layer's hue does neither.
    """
    k = 1 if np.median(ridges[..., 3][fg_px]) > np.median(ridges[..., 2][fg_px]) else 0
    above = ridges[..., 2 + k]
    lift = max(float(np.median(above[fg_px])), 1e-6)
    possible = (np.asarray(line) >= _OFF_LINE) | (above >= 0.5 * lift)
    # A vein fading below the line filter (its tip, a faint stretch) keeps
    # its colour out of the background model where it continues a line.
    # The reach grows with the leaf: a large leaf's main veins are wider
    # than the line filter, and their insides stand out less.
    reach = max(_OFF_LINE_REACH, int(round(np.sqrt(blade.sum()) / _OFF_LINE_SIDES)))
    # Narrow parts of the blade (a petiole, as wide as a vein and with no
    # blade around it to stand out from) are not sure either.
    half = max(2, reach // 2)
    disk = np.hypot(*np.mgrid[-half:half + 1, -half:half + 1]) <= half
    narrow = blade & ~_binary_opening(blade, disk)
    # Only long narrow parts: a sharp corner of the blade leaves a small
    # tip here (and a pale rim grown from it was the fault this rule mends).
    lab, n = ndi.label(narrow)
    if n:
        area = np.bincount(lab.ravel(), minlength=n + 1)
        long = area >= _NARROW_LONG * half * half
        long[0] = False
        narrow = long[lab]
    return ~(_binary_dilation(possible, iterations=reach) | narrow)


def _refine(mask, feat, blade, fg_px, bg_px, fg_c, bg_c, prior, smoothness: float, line=None,
            line_weight: float = 0.0) -> np.ndarray:
    """Pixel-level graph cut over the whole blade (lazy snapping's second step).

    Data term: the pixel's own colour costs plus ``prior`` (per pixel:
    the weight times the superpixel's colour confidence) for the
    superpixel labelling (so the superpixels steady the cut, while a layer
    thinner than a superpixel, a one-pixel vein, can still be found).
    """
    rows, cols = np.nonzero(blade)
    r0, r1, c0, c1 = rows.min(), rows.max() + 1, cols.min(), cols.max() + 1
    f = feat[r0:r1, c0:c1]
    reg = blade[r0:r1, c0:c1]
    shp = reg.shape
    flat = f.reshape(-1, f.shape[2])
    d_f = _nearest(flat, fg_c).reshape(shp)
    d_b = _nearest(flat, bg_c).reshape(shp)
    tot = d_f + d_b + 1e-6
    m = mask[r0:r1, c0:c1]
    pr = np.broadcast_to(np.asarray(prior, float), mask.shape)[r0:r1, c0:c1]
    cost_fg = d_f / tot + pr * (~m)
    cost_bg = d_b / tot + pr * m
    if line is not None:
        # A thin line layer: a pixel pays for being on a line as blade, and
        # less (_LINE_PENALTY) for being off one as layer: a vein wider than
        # the filter (a petiole) or fainter than the scribbled ones still
        # joins the layer by its colour.
        lc = np.asarray(line, np.float32)[r0:r1, c0:c1]
        cost_fg = cost_fg + _LINE_PENALTY * line_weight * (1.0 - lc)
        cost_bg = cost_bg + line_weight * lc
    pin_f = fg_px[r0:r1, c0:c1]
    pin_b = (~reg | bg_px[r0:r1, c0:c1]) & ~pin_f
    g = maxflow.Graph[float]()
    ids = g.add_grid_nodes(shp)
    dr = ((f[:, 1:] - f[:, :-1]) ** 2).sum(2)
    dd = ((f[1:] - f[:-1]) ** 2).sum(2)
    beta = _beta(np.concatenate([dr[reg[:, 1:] & reg[:, :-1]], dd[reg[1:] & reg[:-1]]]))
    wr = np.zeros(shp)
    wr[:, :-1] = smoothness * np.exp(-beta * dr)
    wd = np.zeros(shp)
    wd[:-1] = smoothness * np.exp(-beta * dd)
    g.add_grid_edges(ids, weights=wr, structure=np.array([[0, 0, 0], [0, 0, 1], [0, 0, 0]]), symmetric=True)
    g.add_grid_edges(ids, weights=wd, structure=np.array([[0, 0, 0], [0, 0, 0], [0, 1, 0]]), symmetric=True)
    src = np.where(reg, cost_bg, 0.0) + np.where(pin_f, _HARD, 0.0)
    snk = np.where(reg, cost_fg, 0.0) + np.where(pin_b, _HARD, 0.0)
    g.add_grid_tedges(ids, src, snk)
    g.maxflow()
    fg = ~g.get_grid_segments(ids)
    out = np.zeros_like(mask)
    out[r0:r1, c0:c1] = fg & reg
    return out


def simulate_scribbles(mask, n: int = 12, *, length: float = 20.0, radius: float | None = None,
                       rng=None) -> list[Scribble]:
    """Short scribbles along a known layer mask: a stand-in user for measuring.

    Each scribble follows the mask's skeleton (junctions removed) for about
    ``length`` pixels from a random skeleton pixel, with a brush radius of
    at most half the local width (so it stays on the layer), as a user
    tracing a vein or dabbing a spot would.

    Parameters
    ----------
    mask : (H, W) bool array_like
        The layer (e.g. a procedural leaf's ground-truth veins).
    n : int
        Number of scribbles (the paper: 10-15 per layer).
    length : float
        Scribble length in pixels.
    radius : float, optional
        Brush radius; by default half the local width, clipped to [0.5, 3].
    rng : int or Generator
        Picks each scribble's start pixel on the skeleton.

    Returns
    -------
    list of Scribble
        ``n`` scribbles on ``mask``.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((30, 60), bool); m[14:17, 5:55] = True
    >>> ss = simulate_scribbles(m, 3, length=10, rng=0)
    >>> len(ss), bool(scribble_mask(ss, m.shape)[~m].sum() == 0)
    (3, True)
    """
    from skimage.morphology import skeletonize

    from ..core.random import as_rng
    mask = as_mask(mask, name="mask")
    if not mask.any():
        raise ValueError("mask is empty: nothing to scribble on")
    n = check_int(n, "n", 1, MAX_SCRIBBLES)
    length = check_real(length, "length", 0.0, 1e6, low_open=True)
    radius = check_real(radius, "radius", 0.0, 1e6, low_open=True, allow_none=True)
    rng = as_rng(rng)
    skel = skeletonize(mask)
    if not skel.any():
        skel = mask.copy()
    nb = ndi.convolve(skel.astype(np.int32), np.ones((3, 3), np.int32), mode="constant") - 1
    path = skel & (nb <= 2)
    if not path.any():
        path = skel
    dist = ndi.distance_transform_edt(mask)
    lab, _ = ndi.label(path, structure=np.ones((3, 3)))
    ys, xs = np.nonzero(path)
    out = []
    for _ in range(int(n)):
        i = int(rng.integers(len(xs)))
        x0, y0 = xs[i], ys[i]
        near = (lab[ys, xs] == lab[y0, x0]) & ((xs - x0) ** 2 + (ys - y0) ** 2 <= (length / 2) ** 2)
        px, py = xs[near].astype(float), ys[near].astype(float)
        r = radius
        if r is None:
            r = float(np.clip(0.5 * dist[py.astype(int), px.astype(int)].min(), 0.5, 3.0))
        if len(px) < 2:
            out.append(Scribble([(x0, y0)], r))
            continue
        pts = np.stack([px, py], 1)
        c = pts - pts.mean(0)
        axis = np.linalg.svd(c, full_matrices=False)[2][0]
        pts = pts[np.argsort(c @ axis)]
        out.append(Scribble(pts[:: max(1, len(pts) // 8)] if len(pts) > 8 else pts, r))
    return out
