"""Layers that sit along the blade's outline as a band (a variegated leaf's pale margin): regions, not veins.

Beyond the paper. Lazy snapping (Li et al. 2004), as the paper uses it to
grow the training layers, caps a layer at a share of the blade
(``SnapParams.max_layer_fraction``, 15 %), and this package routes a layer
of thin curves to the vein snapping (:func:`~branchnb.leaves.snapping.is_thin_layer`).
A variegated leaf's cream (white, dark green) margin band is neither: it
covers 35-45 % of the blade, and a band 5-30 px wide round the outline is
a ring of "curve" to those tests. Measured on procedural variegated leaves
(ovate, toothed, a band of irregular width ~5 % of the image round a green
centre, pale pinnate veins; margin and veins scribbled on leaf 0, 4
exemplars, 160-600 px) before this module: training margin IoU 0.16-1.0
(its outer half was taken for blade: the 15 % most like the layer left out
of the background model leave the rest of the band in it), induced IoU down
to 0.01 (the band scribbled as a thin line layer, then snapped onto the
green centre's edge as if it were a vein).

Here:

* :func:`outline_region`: a layer that covers most of the blade's outline
  and the blade next to it to a depth of :data:`BAND_DEPTH` of the leaf
  size is a band along the outline, a region layer (it is structural: it
  sits along the outline), never a thin one (an inked outline, 2-8 px on
  120-1000 px leaves, covers 0.14-0.49 of that strip, a margin band 0.9-1.0);
* :func:`scribbled_band`: before growing, the scribbles of a layer lie in
  such a band of their own colour (then the layer is no thin line layer,
  whatever the ridge filter says of its texture);
* :func:`layer_colours`, :func:`layer_share`: the share of the blade a
  region layer covers, estimated from its colours, lifts
  ``max_layer_fraction`` for it;
* :func:`band_extent`, :func:`band_threshold`: on each exemplar the band
  induced by the paper's test (its place) grows over the parts of its
  colour it touches (the band's inner edge wanders farther than the
  spatial term's reach);
* :func:`band_coloured`, :func:`band_rim`: the rim the windowed colour term leaves at the band's inner
  edge is taken by each pixel's own colour (else it stayed in the residual, and new leaves showed
  cream threads in their green centre).

After (the leaves of ``tests/test_leaves_margin_band.py``, 4-6 exemplars, several seeds): training margin
IoU 0.97-1.00; induced 0.81-0.98 on every exemplar at 160-600 px (cream,
white and dark green bands); the veins layer unchanged. With :func:`band_rim`
(leaves78; the variegated leaves of ``tests/test_leaves_variegated.py``, seeds 40-45):
induced 0.81-0.82 -> 0.87-0.92 at 160 px, 0.86-0.90 -> 0.94-0.96 at 240 px (6 exemplars),
0.84-0.94 -> 0.86-0.95 at 600 px; cream share of new leaves' green cores (eroded 3 px; the
exemplars 0) 0.0043 -> 0.0032 at 160 px, 0.0048 -> 0.0022 at 240 px, 0.015 -> 0.008 at 400 px,
unchanged (0.018) at 600 px: long threads along the pasted band's edge there, on main too, whose
source is not the residual's rim (open).

leaves83 (the veins' parts across the band and along its edge given to it: the crossed cut a quarter of
the way from the veins' colour to the band's, :data:`CROSSED_EDGE`): vein pixels in the true band,
exemplars 1..n, 240 px 2/10/4 -> 0/0/0, 400 px 23/46/0/28 -> 0, 600 px 49/25/469/48/14 -> 0/0/1/0/0;
worst vein IoU at 600 px 0.838 -> 0.913. New leaves (6 per rng, rngs 0-1): cream flecks (components of
2 px or more of cream in the green core) per leaf 4.8 -> 0.25 at 400 px, 6.4 -> 3.1 at 600 px; cream
share of the core mean / max 0.0021 / 0.024 -> 0.0001 / 0.0006 at 400 px, 0.0017 / 0.0076 -> 0.0009 /
0.0025 at 600 px. What is left at 600 px: a donor's vein fork at the green centre's apex (green between
its branches) pasted over the new leaf's band, and the blurred band edge of the background (open).

leaves86: the pasted band hides the other layers under it (``synthesis_layers._is_band``: the donor's vein
forks and green-rimmed vein tips across the band are gone) and its small holes are its own
(:func:`band_holes`: spots tinted by the band were removed as blade and came back as green discs). New
leaves (12 per case, rngs 0-1), pieces of the centre's colours in the band per leaf: 240 px 2.6 -> 0.17,
600 px 5.8 -> 2.0 (paste alone), 400 px with a band of 8 % of the image 4.5 -> 0.67 (band IoU 0.947-0.988
-> 0.978-0.994, cream flecks in the green centre 3.1 -> 0.25 per leaf). (The leaves of
``tests/test_leaves_variegated.py`` at 240-900 px, 4-6 exemplars, cream and dark bands.)

leaves88 (dark bands at 256 px, vein IoU 0.49 / 0.55 on exemplars 1 and 3): the exemplar's own delta
reached only beside its own ridge pixels, not the snapped midrib (``analysis_masks._exemplar_mask``),
and those pixels took the pale side of the band's inner edge, a step and no line
(:func:`~branchnb.leaves.own_contrast.exemplar_direction`); now 0.84 / 0.91
(``tests/test_leaves_dark_band.py``). Open: the midrib's last 10 % at a narrow apex (exemplar 1), a
pale strip where the background's removed band is wider than the pasted one; bands of 10 % of a
256-px image (most of the blade) are
not grown as a band on the training leaf (margin IoU 0.39).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

#: The strip next to the outline a band must cover, in leaf sizes (``sqrt`` of the blade's area), ...
BAND_DEPTH = 0.04
#: ... and in pixels at least (the line filter's widest line is 5 px: a band is wider).
BAND_MIN_DEPTH = 3.0
#: A band holds at least this share of the outline (its outermost pixels) ...
RING_COVER = 0.5
#: ... and of the strip from there to :data:`BAND_DEPTH` (an inked outline 0.14-0.49, measured).
STRIP_COVER = 0.75
#: ... and at most this share of the blade's core (pixels deeper than half the deepest): a band, not the blade.
CORE_COVER = 0.5
#: The scribbled pixels of a layer lying in its colour's band, at least this share: it was scribbled as a band.
SCRIBBLES_IN_BAND = 0.7
#: Largest share of the blade a region layer's estimated cover lifts ``max_layer_fraction`` to.
MAX_SHARE = 0.6
#: A pixel within this many times the held-out 90th-percentile distance of the layer's colours is of them.
REACH = 3.0
#: The estimated cover stands when the blade within twice that distance is at most this many times
#: as much (a layer whose colours shade into the blade's has no clear cover: left at the default).
SEPARATE = 1.15
#: Least layer pixels for the held-out estimate.
MIN_SAMPLES = 40


def _depth(blade):
    from .analysis_outline import _closed_distance
    return _closed_distance(blade)


def outline_region(blade, mask, *, depth=None) -> bool:
    """Whether ``mask`` is a band along the blade's outline (a variegated margin), wider than an inked outline.

    It covers at least :data:`RING_COVER` of the blade's outermost pixels
    (within 1.5 px of the outline of the blade with its holes and paint
    gaps closed), at least :data:`STRIP_COVER` of the strip from there to
    ``max(BAND_MIN_DEPTH, BAND_DEPTH * size)`` px deep (``size``: the square
    root of the blade's area) and at most :data:`CORE_COVER` of the blade's
    core (deeper than half its deepest pixel).

    Parameters
    ----------
    blade : (H, W) bool ndarray
        The leaf's blade.
    mask : (H, W) bool ndarray
        The layer.
    depth : (H, W) float ndarray, optional
        Each pixel's distance to the outline (computed if None).

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:120, :120]
    >>> blade = np.hypot(yy - 60, xx - 60) < 50
    >>> band = blade & (np.hypot(yy - 60, xx - 60) >= 40)
    >>> ink = blade & (np.hypot(yy - 60, xx - 60) >= 48)
    >>> outline_region(blade, band), outline_region(blade, ink), outline_region(blade, blade)
    (True, False, False)
    """
    blade = np.asarray(blade, bool)
    mask = np.asarray(mask, bool) & blade
    if not mask.any() or blade.sum() < 16:
        return False
    d = _depth(blade) if depth is None else depth
    size = float(np.sqrt(blade.sum()))
    ring = blade & (d <= 1.5)
    strip = blade & (d > 1.5) & (d <= max(BAND_MIN_DEPTH, BAND_DEPTH * size))
    core = blade & (d > 0.5 * float(d[blade].max()))
    if not ring.any() or not strip.any() or not core.any():
        return False
    return bool(mask[ring].mean() >= RING_COVER and mask[strip].mean() >= STRIP_COVER
                and mask[core].mean() <= CORE_COVER)


def _held_out(feat_px: np.ndarray, blade_feat: np.ndarray, clusters: int, seed: int):
    """Distances of the blade's colours to half the layer's colours' k-means centres, and the other half's."""
    from .layers import _kmeans, _nearest
    rng = np.random.default_rng(seed)
    order = rng.permutation(len(feat_px))
    fit, test = feat_px[order[::2]], feat_px[order[1::2]]
    centres = _kmeans(fit, clusters, rng)
    return _nearest(blade_feat, centres), _nearest(test, centres)


def layer_colours(feat, blade, fg_px, clusters: int = 32, *, seed: int = 0):
    """The blade pixels of the layer's colours, and the share of the blade they are: ``(near, share)``.

    A pixel is of the layer's colours when it is within :data:`REACH`
    times the 90th percentile of the held-out distances of the k-means
    centres of half the scribbled layer pixels to the other half (fitted
    pixels are closer to their own centres than the layer's unscribbled
    ones, and the scribbled pixels kept for the colour model are a wide
    layer's texture extremes, :func:`branchnb.leaves.layers._on_layer`:
    at 1 times, 0.5-0.7 of a margin band's pixels; at 3, all). ``share`` is
    that part of the blade, or 0 when the layer's colours shade into the
    blade's (the blade within twice that distance is more than
    :data:`SEPARATE` times as much) or cover more than :data:`MAX_SHARE`
    of it: its cover is then unclear. ``near``
    is None when there are fewer than :data:`MIN_SAMPLES` layer pixels.

    The colour model draws from its own generator (``seed``): the
    caller's stays as it was for the layers grown after this one.

    Parameters
    ----------
    feat : (H, W, C) float ndarray
        Per-pixel colour features (lazy snapping's).
    blade : (H, W) bool ndarray
        The leaf's blade.
    fg_px : (H, W) bool ndarray
        The scribbled layer pixels kept for the layer's colour model.
    clusters : int
        k-means centres per half of the layer's pixels.
    seed : int
        Seed of the k-means.

    Returns
    -------
    near : (H, W) bool ndarray or None
    share : float
    """
    px = feat[fg_px]
    if len(px) < MIN_SAMPLES:
        return None, 0.0
    blade_feat = feat[blade]
    d_blade, d_test = _held_out(px, blade_feat, clusters, seed)
    tau = REACH * max(float(np.percentile(d_test, 90)), 1e-4)
    near = np.zeros(blade.shape, bool)
    near[blade] = d_blade <= tau
    share = float(near[blade].mean())
    wider = float(np.mean(d_blade <= 2.0 * tau))
    # A cover over MAX_SHARE is no layer's: its colours are the blade's (50 scribbled pixels of
    # anti-aliased 3-px spots on a 256-px leaf reached the whole blade, and the spots grew 28 % wider).
    return near, (share if wider <= SEPARATE * share and share <= MAX_SHARE else 0.0)


def layer_share(share: float, default: float) -> float:
    """The ``max_layer_fraction`` of a region layer of estimated cover ``share``: the default, lifted to it.

    Lifted to ``share`` (at most :data:`MAX_SHARE`) and never lowered:
    a layer of small cover keeps lazy snapping's rule.

    Parameters
    ----------
    share : float
        The layer's estimated cover of the blade (:func:`layer_colours`).
    default : float
        ``SnapParams.max_layer_fraction``.

    Returns
    -------
    float

    Examples
    --------
    >>> layer_share(0.42, 0.15), layer_share(0.05, 0.15), layer_share(0.9, 0.15)
    (0.42, 0.15, 0.6)
    """
    return float(max(default, min(float(share), MAX_SHARE)))


def scribbled_band(blade, near, marks) -> bool:
    """Whether a layer's scribbles (``marks``) lie in a band of its colours (``near``) along the outline.

    The parts of ``near`` that reach the outline must be an
    :func:`outline_region` and hold :data:`SCRIBBLES_IN_BAND` of the
    scribbled pixels. A vein layer's scribbles lie inside the blade (a
    ginkgo's veins run into a rim of their hue, but are scribbled off it);
    an inked outline scribbled as a layer is too thin for the strip.

    Parameters
    ----------
    blade : (H, W) bool ndarray
        The leaf's blade.
    near : (H, W) bool ndarray or None
        The blade pixels of the layer's colours (:func:`layer_colours`).
    marks : (H, W) bool ndarray
        The layer's scribbled pixels.

    Returns
    -------
    bool
    """
    if near is None or not marks.any():
        return False
    d = _depth(blade)
    lab, n = ndi.label(near, structure=np.ones((3, 3), bool))
    if n == 0:
        return False
    touch = np.zeros(n + 1, bool)
    touch[np.unique(lab[near & (d <= 1.5)])] = True
    touch[0] = False
    along = touch[lab]
    if float(along[marks].mean()) < SCRIBBLES_IN_BAND:
        return False
    return outline_region(blade, along, depth=d)


def band_threshold(colour_t, user, blade_t) -> float:
    """The colour term's threshold that best gives the band on the training leaf (IoU, as ``delta`` is chosen).

    The colour term is read over a window (``n`` px): at the band's inner
    edge it mixes in the centre's colour, and the paper's ``lambda + S <
    delta`` left a 1-2 px rim of it out (induced IoU 0.78-0.82 on 160-px
    leaves whose band is 5-7 px wide). Chosen on the training leaf, the
    threshold takes that rim as the user's band did.

    Parameters
    ----------
    colour_t : (H, W) float ndarray
        The colour term ``S`` on the training leaf.
    user : (H, W) bool ndarray
        The user's band on the training leaf.
    blade_t : (H, W) bool ndarray
        The training leaf's blade.

    Returns
    -------
    float
    """
    from .induction import choose_threshold
    return float(choose_threshold(np.asarray(colour_t, np.float32), user, blade_t)[0])


def band_extent(mask, colour, threshold: float, free) -> np.ndarray:
    """A band layer's induced ``mask`` grown over the parts of the layer's colour it touches.

    The paper's ``D = lambda F + S_e < delta`` holds a structural layer
    within ``eps sqrt(ln(delta / lambda))`` of the registered training
    layer (5-8 px on 250-450 px leaves); a variegated margin's inner edge
    wanders 10-50 px from leaf to leaf, and the induced band stopped where
    the training band's edge was carried (IoU 0.70-0.80 on 600-px
    exemplars). Its place says which parts of the exemplar's colour are the
    band; its colour says how far they reach: the pixels of ``free`` (the
    blade less the layers above) with ``S_e`` under ``threshold``
    (:func:`band_threshold`) joined to ``mask`` (8-connected) are added.
    Beyond the paper, as snapping is for veins.

    Parameters
    ----------
    mask : (H, W) bool ndarray
        The band induced on an exemplar by the paper's test.
    colour : (H, W) float ndarray
        The exemplar's colour term ``S_e``.
    threshold : float
        :func:`band_threshold`.
    free : (H, W) bool ndarray
        The exemplar's blade less the layers above.

    Returns
    -------
    (H, W) bool ndarray

    Examples
    --------
    >>> import numpy as np
    >>> colour = np.ones((1, 10)); colour[0, 2:8] = 0.0
    >>> m = np.zeros((1, 10), bool); m[0, 2:4] = True
    >>> band_extent(m, colour, 0.3, np.ones((1, 10), bool)).astype(int).tolist()
    [[0, 0, 1, 1, 1, 1, 1, 1, 0, 0]]
    """
    mask = np.asarray(mask, bool)
    like = np.asarray(free, bool) & (np.asarray(colour, np.float32) < np.float32(threshold))
    lab, n = ndi.label(like | mask, structure=np.ones((3, 3), bool))
    if n == 0:
        return mask
    keep = np.zeros(n + 1, bool)
    keep[np.unique(lab[mask])] = True
    keep[0] = False
    return mask | (like & keep[lab])


#: A pixel whose own colour lies at least this share of the way from the blade's colour to the band's
#: is of the band (:func:`band_coloured`): its anti-aliased edge pixels too.
BAND_MIX = 0.25


#: ``crossed`` pixels (:func:`band_rim`) within this many px of the band join it wherever they lie. Beyond the
#: paper (leaves83): the veins' masks ran along the band's inner edge and ended in star-shaped blobs of it,
#: 1-2 px off the band's mask, outside what the band's closing covers; new leaves carried them as cream
#: flecks at their veins' ends and threads along the old band's edge. Procedural variegated leaves
#: (``tests/test_leaves_variegated.py``), vein IoU of the exemplars 1-5 at 600 px: 0.934 / 0.979 / 0.880 /
#: 0.978 / 0.932 -> 0.941 / 0.983 / 0.914 / 0.980 / 0.933 (1 px: 0.905 on exemplar 3); 400 px exemplar 2
#: 0.975 -> 0.989, 240 px 0.977 -> 0.990; no band or vein IoU lower.
CROSSED_EDGE = 2


def band_coloured(lab, blade, layer_colour, blade_colour) -> np.ndarray:
    """The blade pixels whose own CIELAB lies :data:`BAND_MIX` of the way from ``blade_colour`` to ``layer_colour``.

    Its edge pixels, mixed with the centre's colour (anti-aliased, or
    resampled onto the common canvas), count: at half the way they were
    left, and a 1-px pale line traced the band's inner edge in the
    residual (procedural variegated leaves at 400 px) and in new leaves.

    Parameters
    ----------
    lab : (H, W, 3) float ndarray
        The exemplar's CIELAB (in the colours its colour term was read in).
    blade : (H, W) bool ndarray
        Its blade (less the layers above).
    layer_colour, blade_colour : (3,) array_like
        The band's and the rest of the blade's median colour on the training leaf.

    Returns
    -------
    (H, W) bool ndarray
    """
    return np.asarray(blade, bool) & (band_share(lab, layer_colour, blade_colour) > np.float32(BAND_MIX))


def band_share(lab, layer_colour, blade_colour) -> np.ndarray:
    """How far each pixel's CIELAB lies on the way from ``blade_colour`` (0) to ``layer_colour`` (1).

    Parameters
    ----------
    lab : (H, W, 3) float ndarray
        An exemplar's CIELAB.
    layer_colour, blade_colour : (3,) array_like
        The band's and the rest of the blade's median colour on the training leaf.

    Returns
    -------
    (H, W) float32 ndarray
        All zeros when the two colours are the same.
    """
    lab = np.asarray(lab, np.float32)
    b = np.asarray(blade_colour, np.float32)
    axis = np.asarray(layer_colour, np.float32) - b
    span = float(axis @ axis)
    if span <= 1e-6:
        return np.zeros(lab.shape[:2], np.float32)
    return ((lab - b) @ axis) / np.float32(span)


def band_rim(mask, coloured, free, reach: int, *, claimed=None, crossed=None) -> np.ndarray:
    """A band ``mask`` with the pixels of its own colour within ``reach`` px of it, joined to it.

    The colour term ``S_e`` is read over a window of ``n`` px: at the
    band's inner edge it mixes in the centre's colour over about half a
    window, and :func:`band_extent` (a threshold on ``S_e``) stopped short
    of the edge on the exemplars whose band is wider or more ragged than the
    training leaf's. The rim left was removed with the blade: the cream rim
    stayed in the exemplar's residual, and wherever a new leaf's pasted
    band (another exemplar's) left that place in its green centre, it came
    out as thin cream threads (procedural variegated leaves, 240 px, 4
    exemplars, 12 new leaves: 0.5 % of the green core cream on average, up
    to 1.1 %; the exemplars 0 %). Each pixel's own colour decides there:
    ``coloured`` (:func:`band_coloured`) pixels of ``free`` within ``reach``
    px of the mask (8-connected to it) join it. Beyond the paper.

    The band's pale-to-green inner edge reads like a pale vein: the
    vein's removal (its ridge extension) took a ring along it on the
    exemplars, outside the vein's mask, before the band was read; the band
    stopped at that ring, and new leaves pasting that donor's veins (with
    their removed extension) carried cream strips of the ring into their
    green centre (procedural variegated leaves, 600 px, 6 exemplars: up to
    2.2 % of the green core cream). ``claimed`` (the pixels of the band's
    colour, read in the exemplar's own pixels, that the removals above took
    outside their layers' masks) join the band wherever they are
    8-connected to it (beyond the paper). The veins' tips crossing into the
    band (of its colour there) stayed with the veins and came out as cream
    flecks at the ends of new leaves' veins: ``crossed`` pixels (nearer the
    band's colour than the layer's own, taken by the layers above) that a
    closing of the band as wide as they are covers join it too.

    Parameters
    ----------
    mask : (H, W) bool ndarray
        The band induced on an exemplar (after :func:`band_extent`).
    coloured : (H, W) bool ndarray
        :func:`band_coloured` on that exemplar.
    free : (H, W) bool ndarray
        The exemplar's blade less the layers above.
    reach : int
        How far from the mask (px): the colour term's window side.
    claimed : (H, W) bool ndarray, optional
        Pixels that join as well wherever they are 8-connected to the mask, at any distance: the band's
        colour in the exemplar's own pixels where the removal of a layer above took them.
    crossed : (H, W) bool ndarray, optional
        Pixels of the layers above nearer the band's colour than their layer's (in the exemplar's own
        pixels; see ``band_claimed`` of :class:`~branchnb.leaves.analysis_masks._MaskSteps`): those that lie
        across the band (covered by its closing by their own half-width plus one px) or within
        :data:`CROSSED_EDGE` px of it join it.

    Returns
    -------
    (H, W) bool ndarray

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((1, 10), bool); m[0, :3] = True
    >>> c = np.zeros((1, 10), bool); c[0, 3:5] = True; c[0, 8] = True
    >>> band_rim(m, c, np.ones((1, 10), bool), 3).astype(int).tolist()
    [[1, 1, 1, 1, 1, 0, 0, 0, 0, 0]]
    """
    mask = np.asarray(mask, bool)
    reach = int(reach)
    if reach < 1 or not mask.any():
        return mask
    near = ndi.binary_dilation(mask, structure=np.ones((3, 3), bool), iterations=reach)
    like = np.asarray(coloured, bool) & np.asarray(free, bool) & near
    if claimed is not None:
        claimed = np.asarray(claimed, bool)
        if claimed.shape != mask.shape:
            raise ValueError(f"claimed has shape {claimed.shape}, the mask {mask.shape}")
        # Wherever it reaches: the removal's ring is as wide as the vein's ridge extension.
        like = like | claimed
    if crossed is not None:
        crossed = np.asarray(crossed, bool)
        if crossed.shape != mask.shape:
            raise ValueError(f"crossed has shape {crossed.shape}, the mask {mask.shape}")
        if crossed.any():
            half = ndi.distance_transform_edt(crossed)
            k = int(np.ceil(np.percentile(half[crossed], 95))) + 1
            # Padded: the closing's erosion would eat the band at the canvas's edge.
            closed = ndi.binary_closing(np.pad(mask | like, k), structure=np.ones((3, 3), bool),
                                        iterations=k)[k:-k, k:-k]
            # And those touching the band's edge (its pale rim a vein's mask ran along or ended in: 0.77-0.80
            # of the way to its colour, 1-2 px off its mask; see CROSSED_EDGE).
            edge = ndi.binary_dilation(mask | like, structure=np.ones((3, 3), bool), iterations=CROSSED_EDGE)
            like = like | (crossed & (closed | edge))
    lab, n = ndi.label(like | mask, structure=np.ones((3, 3), bool))
    if n == 0:
        return mask
    keep = np.zeros(n + 1, bool)
    keep[np.unique(lab[mask])] = True
    keep[0] = False
    return mask | (like & keep[lab])


#: A hole of a band's mask (:func:`band_holes`) under this share of the blade is the band's. Beyond the paper
#: (leaves86): a spot in a variegated band (tinted by it, its colour neither the band's nor the blade's) stayed a
#: hole of the band, was removed as blade and filled from the green centre's texture, and new leaves showed green
#: discs in their band. The spots of the procedural leaves cover 0.1-0.4 % of the blade; the green centre, the
#: band's one large hole, 40-65 %.
BAND_HOLE = 0.01


def band_holes(mask, free) -> np.ndarray:
    """A band ``mask`` with its holes under :data:`BAND_HOLE` of the blade (pixels of ``free``) filled.

    The largest hole (the centre the band runs round) is never filled.

    Parameters
    ----------
    mask : (H, W) bool ndarray
        The band induced on an exemplar.
    free : (H, W) bool ndarray
        The exemplar's blade less the layers above: only these pixels are filled.

    Returns
    -------
    (H, W) bool ndarray

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((40, 40), bool); m[2:38, 2:38] = True; m[10:30, 10:30] = False
    >>> m[4:6, 4:6] = False  # a spot in the band
    >>> out = band_holes(m, np.ones((40, 40), bool))
    >>> bool(out[4:6, 4:6].all()), bool(out[10:30, 10:30].any())
    (True, False)
    """
    mask = np.asarray(mask, bool)
    free = np.asarray(free, bool)
    holes = ndi.binary_fill_holes(mask) & ~mask
    lab, n = ndi.label(holes)
    if n < 2:
        return mask
    size = ndi.sum(np.ones(mask.shape), lab, np.arange(1, n + 1))
    small = np.zeros(n + 1, bool)
    small[1:] = size < BAND_HOLE * max(float(free.sum() + mask.sum()), 1.0)
    small[1 + int(np.argmax(size))] = False
    return mask | (small[lab] & free)
