"""Marks at random places: when a layer keeps no positional tie (beyond the paper, issue 22).

The paper's ``lambda = kappa |cap L~e| / |cup L~e|`` is meant to be 0 for
a layer whose marks sit anywhere (spots) and large for one at the same
place on every leaf (veins). But one spot of each exemplar falling by
chance near one of the training leaf's makes the intersection non-empty,
and any ``lambda > 0`` lets ``F`` (up to ``e^60``) forbid every pixel away
from the registered training layer: on birch-like leaves a chance
``lambda = 0.086`` lost half of the spots of ordinary leaves.

A layer loses its tie (``lambda = 0``) only when both hold:

* :func:`scattered_layer`: the user's layer on the training leaf is made
  of several small compact marks, no piece of it spanning a sizeable
  part of the leaf. Veins, a midrib or a margin are one long connected
  network (or long strokes), so they never pass and their induction is
  the paper's, unchanged;
* :func:`positional_tie` under :data:`TIE_LEVEL`: the exemplars' pixels of
  the layer's colour sit no nearer the registered layer than chance
  (measured within the liberal radius widened by the registration error).

* the layer's colour singles it out on the training leaf
  (:data:`~branchnb.leaves.analysis_combine.SINGLES_OUT`): marks of nearly
  the blade's colour have only their place to go by.

The first test alone guards structural layers; the second keeps the tie
of marks that do sit at one place on every leaf (a gall at the base of
each blade). Measured on procedural families with one mark at the same
place on every leaf (4-6 leaves, 200-400 px): spots ``lambda`` 0.006-0.17
-> 0, worst exemplar's spot IoU 0.11-0.32 -> 0.76-0.91; vein masks of
the procedural lobed / trilobed / elliptic families unchanged.

How a scattered layer is induced (leaves73, :func:`~branchnb.leaves.analysis_induce.induce`):

* it is never snapped as a thin layer: blotches cut by veins and hole
  rims are thin, and snapping drew ridges at the training marks'
  registered places on every exemplar;
* its colour is read on the residual the layer above left outside its
  induced mask: that layer's removal grows the mask (its anti-aliasing
  rim, and the ridge extension that takes faint vein ends for the
  background), which ate pale dots, the pale inside of hole rims and the
  marks' pixels touching a vein;
* on the exemplars its colour windows leave out the pixels the layers
  above took: their removal filled them from around, beside a vein with
  the marks' own colour.

Measured on procedural families of 4-6 toothed leaves with veins and
marks at random places (160-600 px), worst exemplar's IoU before ->
after: blotches 240 px 0.00 -> 0.99, 450 px 0.71 -> 1.00; hole rims
300 px 0.00 -> 1.00, 500 px 0.00 -> 0.79; lichen dots 240 px 0.10 ->
0.69 (the vein layer took a third of one leaf's dots), 400 px 0.12 ->
0.91; rust spots 160 px 0.63 -> 0.99, 600 px 0.14 -> 1.00. The layers
above (veins) are induced exactly as before.

Where the marks' own colour tells them from the blade on the training
leaf (:func:`layer_coloured` reproduces the user's layer with IoU at
least :data:`~branchnb.leaves.analysis_induce.MARKS_SINGLED`; the sample
maples' spots of nearly the blade's colour: 0.02, left as they were),
two more steps (leaves75, beyond the paper):

* the mark's one-pixel edge is decided by each pixel's own colour
  (:func:`refine_edges`): the windowed colour term drew a fringe of blade
  round every dark hole rim and left the soft edges of spots;
* the marks the layers above took by their colour come back where both
  claim a piece and its shape is a mark's (:func:`reclaim_marks`: compact
  and no larger than the training marks), and leave those layers' masks.

Worst exemplar before -> after: lichen dots 240 px 0.69 -> 1.00, hole
rims 500 px 0.79 -> 0.97, the procedural elliptic family's spots (256
px) 0.66 -> 0.90; vein masks of the procedural lobed, trilobed and
elliptic families unchanged but for 1 px (a spot's) on 3 of 12 leaves.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_mask

__all__ = ["LOCAL_BLADE", "RECLAIM_SLACK", "TIE_LEVEL", "SCATTER_SPAN", "positional_tie", "reclaim_marks",
           "scattered_layer"]

#: :func:`positional_tie` below which a scattered layer gets no positional tie (``lambda = 0``). Measured on
#: procedural families: veins 0.9-1.0; rust spots of which one sits at the same place on every leaf 0.23.
TIE_LEVEL = 0.5

#: The largest piece of a scattered layer spans (bounding-box diagonal) less than this share of the leaf
#: size ``sqrt(blade area)``. Spots, blotches, hole rims and lichen dots of the procedural families:
#: at most 0.2, two blotches that touch 0.31 (0.3 took them for a structure: 0.00 IoU on two of four
#: exemplars); the training vein layers of every leaves test: at least 0.5 (a vein system is one piece).
SCATTER_SPAN = 0.4


def scattered_layer(user, blade, *, span: float = SCATTER_SPAN, min_marks: int = 2) -> bool:
    """Whether a training layer is marks at random places: several small pieces, none spanning the leaf.

    Parameters
    ----------
    user : (H, W) bool array_like
        The user's layer on the training leaf.
    blade : (H, W) bool array_like
        The training leaf's blade.
    span : float
        Each 8-connected piece's bounding-box diagonal must stay under
        ``span * sqrt(blade area)`` (:data:`SCATTER_SPAN`).
    min_marks : int
        At least this many pieces (one mark alone has nothing to be
        scattered among).

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> b = np.ones((100, 100), bool)
    >>> spots = np.zeros_like(b); spots[10:14, 10:14] = spots[60:64, 70:74] = spots[80:83, 20:23] = True
    >>> scattered_layer(spots, b)
    True
    >>> vein = np.zeros_like(b); vein[50, 5:95] = True
    >>> scattered_layer(vein | spots, b)
    False
    """
    user = as_mask(user, name="user")
    blade = as_mask(blade, shape=user.shape, name="blade")
    if not np.isfinite(span) or span <= 0:
        raise ValueError(f"span must be a positive number, got {span}")
    lab, n = ndi.label(user, structure=np.ones((3, 3)))
    if n < min_marks or not blade.any():
        return False
    size = np.sqrt(float(blade.sum()))
    for sl in ndi.find_objects(lab):
        if np.hypot(sl[0].stop - sl[0].start, sl[1].stop - sl[1].start) >= span * size:
            return False
    return True


def positional_tie(colour_in_blades, distances, blades, training_index: int, radius_px) -> float:
    """How much more than by chance an exemplar's layer-coloured pixels sit near the registered layer.

    Each exemplar ``e`` is asked which share ``p_e`` of its layer-coloured
    pixels (``{S_e < threshold}`` on its blade) lie within ``radius_px`` of
    the registered layer, against the share ``a_e`` of its blade that does
    (what ``p_e`` would be were the layer placed without regard to
    position); the tie is the median over the exemplars of
    ``(p_e - a_e) / (1 - a_e)`` (Cohen's kappa-like): near 1 for marks at
    one place on every leaf, near 0 for marks at random places.

    Parameters
    ----------
    colour_in_blades : sequence of (H, W) bool array_like
        ``{S_e < threshold}`` on each exemplar's blade, in its own frame.
    distances : sequence of (H, W) array_like
        ``||x, c||``, distance to the registered layer on each exemplar.
    blades : sequence of (H, W) bool array_like
        The exemplars' blades.
    training_index : int
        The training leaf (left out).
    radius_px : float or sequence of float
        The radius (per exemplar or one for all), in pixels: the liberal
        radius widened to the registration error.

    Returns
    -------
    float
        The median discounted share, at most 1; 1 when there is no other
        exemplar. An exemplar without layer-coloured pixels counts 0.

    Examples
    --------
    >>> import numpy as np
    >>> b = np.ones((40, 40), bool); a = np.zeros_like(b); a[20, 5:35] = True
    >>> d = np.abs(np.arange(40) - 20.0)[:, None] * np.ones((1, 40))
    >>> round(positional_tie([a, a], [d, d], [b, b], 0, 1.0), 2)
    1.0
    """
    n = len(blades)
    if not 0 <= training_index < n:
        raise ValueError(f"training_index must be in [0, {n}), got {training_index}")
    if len(colour_in_blades) != n or len(distances) != n:
        raise ValueError("colour_in_blades, distances and blades must have one entry per exemplar")
    radii = np.broadcast_to(np.asarray(radius_px, np.float64), (n,))
    ties = []
    for e in range(n):
        if e == training_index:
            continue
        blade = as_mask(blades[e], name=f"blades[{e}]")
        matches = as_mask(colour_in_blades[e], shape=blade.shape, name=f"colour_in_blades[{e}]") & blade
        near = np.asarray(distances[e]) < float(radii[e])
        if not matches.any() or not blade.any():
            ties.append(0.0)
            continue
        share = float(near[matches].mean())
        chance = float(near[blade].mean())
        ties.append(1.0 if chance >= 1.0 else (share - chance) / (1.0 - chance))
    return float(min(np.median(ties), 1.0)) if ties else 1.0


#: A piece the layers above took is a mark when it is no larger than this many times the training layer's
#: largest mark and no more elongated than this many times its most elongated one (:func:`reclaim_marks`).
RECLAIM_SLACK = 1.5


def _piece_shapes(labels, n):
    """Per 8-connected piece (1..n): pixel count and elongation (the ratio of the principal axes' spreads)."""
    ys, xs = np.nonzero(labels)
    lab = labels[ys, xs]
    cnt = np.bincount(lab, minlength=n + 1).astype(np.float64)
    c = np.maximum(cnt, 1.0)
    mx, my = np.bincount(lab, xs, n + 1) / c, np.bincount(lab, ys, n + 1) / c
    # A pixel is a unit square: its own spread (1/12) keeps a one-pixel line's minor axis above 0.
    sxx = np.bincount(lab, xs * xs, n + 1) / c - mx * mx + 1.0 / 12
    syy = np.bincount(lab, ys * ys, n + 1) / c - my * my + 1.0 / 12
    sxy = np.bincount(lab, xs * ys, n + 1) / c - mx * my
    root = np.sqrt(np.maximum((sxx - syy) ** 2 / 4 + sxy ** 2, 0.0))
    big, small = (sxx + syy) / 2 + root, np.maximum((sxx + syy) / 2 - root, 1.0 / 12)
    return cnt, np.sqrt(big / small)


def reclaim_marks(claims, mask, taken, user, *, slack: float = RECLAIM_SLACK) -> np.ndarray:
    """The pixels the layers above took that belong to a scattered layer's marks, by their shape.

    The layers above are induced first and take what their colour term
    finds: pale lichen dots beside a pale vein, or touching it, went to the
    vein layer (a third of one leaf's dots), and its removal wiped them
    before the marks were read. Where both claim a piece, the shape
    decides (beyond the paper): a mark is compact, a vein elongated. Each
    8-connected piece of the marks found (``mask``) joined with the taken
    pixels of the marks' colour (``claims & taken``) that holds taken
    pixels goes to the marks when it is no larger than ``slack`` times
    the training layer's largest mark (pixels) and no more elongated
    than ``slack`` times its most elongated one; a vein claimed whole, or
    a dot merged with a stretch of vein, is neither.

    Parameters
    ----------
    claims : (H, W) bool array_like
        Pixels of the marks' colour (their ``{D < delta}``) read before
        the layers above were removed.
    mask : (H, W) bool array_like
        The marks induced outside ``taken``.
    taken : (H, W) bool array_like
        What the layers above took.
    user : (h, w) bool array_like
        The user's (scattered) layer on the training leaf: its marks' sizes and shapes.
    slack : float
        Allowance over the training marks' largest size and elongation (:data:`RECLAIM_SLACK`).

    Returns
    -------
    (H, W) bool ndarray
        Pixels of ``taken`` to give to the marks.

    Examples
    --------
    >>> import numpy as np
    >>> user = np.zeros((40, 40), bool); user[5:9, 5:9] = user[20:24, 30:34] = True
    >>> taken = np.zeros((40, 40), bool); taken[20, :] = True          # a vein
    >>> claims = np.zeros((40, 40), bool); claims[18:22, 10:14] = True  # a dot across it
    >>> mask = claims & ~taken
    >>> int(reclaim_marks(claims, mask, taken, user).sum())
    4
    >>> int(reclaim_marks(claims | taken, mask, taken, user).sum())  # the whole vein claimed: no mark
    0
    """
    mask = as_mask(mask, name="mask")
    claims = as_mask(claims, shape=mask.shape, name="claims")
    taken = as_mask(taken, shape=mask.shape, name="taken")
    user = as_mask(user, name="user")
    if not np.isfinite(slack) or slack <= 0:
        raise ValueError(f"slack must be a positive number, got {slack}")
    out = np.zeros(mask.shape, bool)
    extra = claims & taken
    ulab, un = ndi.label(user, structure=np.ones((3, 3)))
    if not extra.any() or un == 0:
        return out
    ucnt, uelong = _piece_shapes(ulab, un)
    lab, n = ndi.label(mask | extra, structure=np.ones((3, 3)))
    cnt, elong = _piece_shapes(lab, n)
    ok = (cnt <= slack * ucnt[1:].max()) & (elong <= slack * uelong[1:].max())
    ok[0] = False
    ok &= np.bincount(lab[extra], minlength=n + 1) > 0
    return ok[lab] & extra


#: :func:`layer_coloured` ``local``: the Gaussian scale of the blade's colour round each pixel, as a share of
#: the square root of the blade's area (about a twentieth of its width: wider than the marks, narrower
#: than the blade's mottling).
LOCAL_BLADE = 0.05


def layer_coloured(lab, blade, layer_colour, taken=None, above=None, local: bool = False) -> np.ndarray:
    """Pixels of ``blade`` whose own colour is nearer the layer's than the blade's (CIELAB distance).

    The blade's colour is the median over the blade outside ``taken`` (the
    layers above); marks are a small share of it.

    Parameters
    ----------
    lab : (H, W, 3) float array_like
        The exemplar's CIELAB.
    blade : (H, W) bool array_like
        Its blade.
    layer_colour : (3,) array_like
        The layer's CIELAB colour (the training layer's median).
    taken : (H, W) bool array_like, optional
        What the layers above took (left out of the blade's colour).
    above : sequence of (3,) array_like, optional
        The colours of the layers above (their training medians): a pixel
        must also be nearer the layer's colour than each of them.
    local : bool
        Compare with the exemplar's own marks' colour (the median of the
        pixels the first comparison calls the layer's) and the blade's
        colour round each pixel (:data:`LOCAL_BLADE`) instead.

    Returns
    -------
    (H, W) bool ndarray

    Notes
    -----
    With ``above`` (beyond the paper): where a pale vein crosses or skirts
    a dark spot, its soft edge mixes the two colours; against the blade
    alone half-vein pixels are nearer the spot, and the spot's edge
    (:func:`refine_edges`) grew a fringe along the vein wherever the vein
    layer's mask missed it. Nearest of the layer's, the blade's and the
    layers above's colours cuts a two-colour mix at half coverage, where
    the marks' truth is cut. Procedural lobed family (160 px, rng 3),
    exemplar 1's spots IoU 0.898 -> 0.911. Not enough alone: exemplar 2's
    fringe stayed (0.772), as the training spots' median (edge pixels and
    a lighter leaf: a* 9) lies far from this leaf's spots (a* 50) and its
    global blade colour from the mottled blade beside the spot; a fringe
    pixel a third spot, the rest blade, was nearer the training colour.

    With ``local`` (beyond the paper, for the exemplars' edges): the
    exemplar's own marks' colour and the blade's colour round each pixel.
    Spots IoU of the procedural families (``leaf_family(3, size, kind,
    rng=3)``, exemplars 0..2) before -> after: lobed 160 px [0.907, 0.898,
    0.772] -> [0.907, 0.920, 0.897], 240 px [0.944, 0.939, 0.796] ->
    [0.944, 0.938, 0.943], 400 px [0.953, 0.947, 0.885] -> [0.953, 0.981,
    0.982]; elliptic 240 px exemplar 2 0.882 -> 0.938, 400 px 0.914 ->
    0.984, but 160 px (spots of 18-25 px, one pixel is 0.04) [0.933,
    0.905, 0.818] -> [0.933, 0.887, 0.783]. An unmixing of each pixel in
    the plane of the blade's, the layer's and the vein's CIELAB colours
    lost true spot pixels (lobed 160 px exemplar 2 0.627).
    """
    lab = np.asarray(lab, np.float64)
    if lab.ndim != 3 or lab.shape[2] != 3:
        raise ValueError(f"lab must be (H, W, 3), got shape {lab.shape}")
    blade = as_mask(blade, shape=lab.shape[:2], name="blade")
    c_l = np.asarray(layer_colour, np.float64).reshape(-1)
    if c_l.shape != (3,) or not np.all(np.isfinite(c_l)):
        raise ValueError(f"layer_colour must be 3 finite numbers, got {layer_colour!r}")
    free = blade if taken is None else blade & ~as_mask(taken, shape=blade.shape, name="taken")
    if not free.any():
        return np.zeros(blade.shape, bool)
    c_b = np.median(lab[free], axis=0)
    d_l = np.linalg.norm(lab - c_l, axis=-1)
    out = blade & (d_l < np.linalg.norm(lab - c_b, axis=-1))
    if local:
        # The exemplar's own marks' colour (the median of the pixels the training colour calls the
        # layer's) and the blade's colour round each pixel: the pixels the whole blade's colour calls
        # blade, averaged with a Gaussian weight (normalised), where there are enough of them.
        own = out & free
        if np.count_nonzero(own) >= 4:
            d_l = np.linalg.norm(lab - np.median(lab[own], axis=0), axis=-1)
        sigma = LOCAL_BLADE * np.sqrt(float(np.count_nonzero(blade)))
        rest = (free & ~out).astype(np.float64)
        w = ndi.gaussian_filter(rest, sigma)
        near = np.stack([ndi.gaussian_filter(lab[..., k] * rest, sigma) for k in range(3)], axis=-1)
        enough = w > 0.05
        c_near = np.where(enough[..., None], near / np.maximum(w, 1e-9)[..., None], c_b)
        out = blade & (d_l < np.linalg.norm(lab - c_near, axis=-1))
    for i, c in enumerate(above or ()):
        c = np.asarray(c, np.float64).reshape(-1)
        if c.shape != (3,) or not np.all(np.isfinite(c)):
            raise ValueError(f"above[{i}] must be 3 finite numbers, got {above[i]!r}")
        out &= d_l < np.linalg.norm(lab - c, axis=-1)
    return out


def refine_edges(mask, coloured, free) -> np.ndarray:
    """``mask`` with its one-pixel inner and outer rim decided pixel by pixel by ``coloured``.

    ``{D < delta}`` reads colours over a window: at a mark's edge it took
    blade pixels beside a dark hole rim (a one-pixel fringe round every
    rim: 500 px leaves, 50-105 of 400-700 px wrong) and left the soft edge
    of a spot. There the pixel's own colour decides (:func:`layer_coloured`);
    the mark's inside stays as found. Beyond the paper.

    Parameters
    ----------
    mask : (H, W) bool array_like
        The marks found.
    coloured : (H, W) bool array_like
        Pixels of the layer's colour (:func:`layer_coloured`).
    free : (H, W) bool array_like
        Where the marks may lie (the blade outside the layers above).

    Returns
    -------
    (H, W) bool ndarray
    """
    mask = as_mask(mask, name="mask")
    coloured = as_mask(coloured, shape=mask.shape, name="coloured")
    free = as_mask(free, shape=mask.shape, name="free")
    if not mask.any():
        return mask.copy()
    cross = ndi.generate_binary_structure(2, 1)
    core = ndi.binary_erosion(mask, cross)
    rim = ndi.binary_dilation(mask, cross) & ~core
    return (core | (rim & coloured)) & free
