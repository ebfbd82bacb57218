"""The stylization's parameters and their adaptation to the image's size and to the metaphor.

:class:`StylizeParams` holds the paper's parameters (and ours where it prints
none). Before the pipeline of :mod:`~branchnb.dendrite.stylization` runs, they
are adapted to the image's size (:func:`effective_params`: no stroke thinner
than a pixel, fewer endpoints on small images) and to the metaphor
(:func:`metaphor_params`: vines and lightning set their own endpoint counts and
widths).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..core.params import param
from .planner import METRICS
from .scale import length_scale

__all__ = ["StylizeParams", "effective_params", "metaphor_params", "on_lattice"]

@dataclass
class StylizeParams:
    """Parameters of the dendritic stylization.

    From the paper: the gradient weighted 3x the intensity in the importance
    map, the non-scalar metric, about 3,000 endpoints (its examples use 2,000
    - 3,800) placed by stippling, thickness from a rolling average of
    importance. The paper does not print the remaining numbers (weight
    constant and noise amplitude, stippling contrast, window, widths, tone);
    those defaults are ours, measured on photos, drawings, leaves and night
    scenes of 256 - 1024 px.

    **Scale.** The dendrite is planned on a lattice of ``lattice_size``
    (the image resampled so its diagonal is that of a ``lattice_size`` square,
    512 x 512 by default) and drawn back on the image at its own size, so a
    256-px and a 1024-px input give the same picture. Lengths (``sigma``,
    ``window``, ``tone_sigma``, ``min_width``, ``max_width``) are in lattice
    pixels, i.e. pixels of a 512 x 512 image. The non-scalar metric is not
    scale-free (on a bigger random lattice a larger share of the nodes ties
    at the percolation bottleneck and the branches straighten into a radial
    burst), which is why the lattice, not only the lengths, keeps one size.
    ``lattice_size=0`` plans on the image's own pixels. A picture smaller than
    ``lattice_size / 2.4`` (under ~215 px) is planned on a lattice 2.4 times its size
    (:func:`~branchnb.dendrite.scale.planning_size`, beyond the paper: a 64-px picture took
    as long as a 500-px one) with these lengths converted to it (:func:`on_lattice`), so it
    keeps the 512-lattice drawing's look. Drawn back on a small
    image, lattice widths would shrink below a pixel: ``output_width`` keeps
    every stroke at least that many image pixels wide, a smaller image
    gets fewer endpoints and a larger one keeps the 512-px widths scaled up
    (:func:`effective_params`), so the same object at 200 and at 2000 px
    carries the same ink. The vine and
    lightning metaphors choose their own endpoint counts
    (:func:`metaphor_params`).

    Parameters
    ----------
    intensity_weight : float
        ``w_I``, weight of darkness in the importance map; 1.
    gradient_weight : float
        ``w_G``, weight of the gradient; 3 (paper: 3 ``w_I``).
    sigma : float
        Gaussian smoothing before the gradient (lattice px); 1.5.
    cost_weight : float
        ``c`` in the node weight ``w = c (1 - I) + epsilon + noise U``; 1.
    epsilon : float
        Constant ``epsilon`` added to every node weight; 0.5.
    noise : float
        Amplitude of the uniform random node weight ``U``; 1.
    metric : {"cumulative", "nonscalar", "blend"}
        Path metric of the planner; the paper's non-scalar one by default.
    blend_weight : float
        ``a`` in ``a M + S`` (``metric="blend"`` only); 1000.
    break_ties : bool
        Re-plan the large ties of the non-scalar metric
        (:func:`~branchnb.dendrite.ties.refine_ties`; beyond the paper), else
        they fill with smooth radial paths. True.
    n_endpoints : int
        Stippled endpoints (paper: 2,000 - 3,800); 3000. Fewer on images
        smaller than the lattice (:func:`effective_params`).
    endpoint_gamma : float
        Endpoint density ``I ** gamma``; 1.
    endpoint_threshold : float
        Importance below which a pixel is empty paper with no endpoints; 0.05.
    endpoint_floor : float
        Density added everywhere (endpoints in empty regions too); 0.
    stipple_iterations : int
        Lloyd iterations of the weighted Voronoi stippling; 10.
    thickness : {"importance", "subtree", "share", "distance"}
        "importance" (default): rolling importance, hierarchy, tone and edges;
        otherwise :func:`~branchnb.dendrite.thickness.branch_thickness` with
        that mode.
    window : int
        Rolling-average window along the branches (nodes); 15.
    contrast : float
        Exponent on the normalised rolling importance; 1.5.
    tone : float
        0 = importance emphasis only, 1 = ink matches the image's darkness
        (:func:`~branchnb.dendrite.thickness.tone_thickness`); 0.5.
    tone_sigma : float
        Scale (lattice px) over which ink is matched to darkness; 8.
    hierarchy : float
        Widths times ``(tips carried) ** hierarchy``: trunks thicker than
        twigs; 0.25.
    edges : float
        Extra width on the image's edges after the tone match (outlines,
        veins): ``r (1 + edges G**2)``; 1.
    min_width : float
        Narrowest stroke (lattice px); 0.2, raised on small images.
    max_width : float
        Widest stroke (lattice px); 4.
    lattice_size : int
        Plan on a lattice with the diagonal of this square; 512 (0: the
        image's own pixels; a smaller one for a small picture, see **Scale**).
    output_width : float
        Narrowest stroke at the image's own size (px; lattice px on images
        larger than the lattice); 1. Smaller images also get fewer endpoints;
        0 turns the adaptation off.

    Examples
    --------
    >>> p = StylizeParams(metric="cumulative")
    >>> p.n_endpoints, p.gradient_weight / p.intensity_weight
    (3000, 3.0)
    """

    # importance (section 4)
    intensity_weight: float = param(1.0, min=0.0, max=10.0, step=0.1,
                                    help="w_I: weight of darkness in the importance map")
    gradient_weight: float = param(3.0, min=0.0, max=10.0, step=0.1,
                                   help="w_G: weight of the gradient (paper: 3 x w_I)")
    sigma: float = param(1.5, min=0.0, max=8.0, step=0.25,
                         help="Gaussian smoothing before the gradient (lattice px)")
    # lattice (section 3)
    cost_weight: float = param(1.0, min=0.0, max=10.0, step=0.1,
                               help="c: weight of (1 - importance) in the node weights")
    epsilon: float = param(0.5, min=0.0, max=5.0, step=0.05,
                           help="constant added to every node weight")
    noise: float = param(1.0, min=0.0, max=5.0, step=0.05,
                         help="amplitude of the uniform random node weight")
    # planner
    metric: str = param("nonscalar", options=METRICS,
                        help="path metric: cumulative, non-scalar (max edge, then sum), or blend")
    blend_weight: float = param(1000.0, min=0.0, max=10000.0, log=True,
                                help="a in a * max_edge + total (metric='blend')")
    break_ties: bool = param(True, help="re-plan large ties of the non-scalar metric "
                                        "(else they fill with smooth radial paths)")
    # endpoints (section 5)
    n_endpoints: int = param(3000, min=1, max=20000, step=50,
                             help="number of stippled endpoints (paper: 2,000 - 3,800)")
    endpoint_gamma: float = param(1.0, min=0.25, max=4.0, step=0.05,
                                  help="endpoint density = importance ** gamma")
    endpoint_threshold: float = param(0.05, min=0.0, max=0.5, step=0.01,
                                      help="importance below this is empty paper: no endpoints")
    endpoint_floor: float = param(0.0, min=0.0, max=1.0, step=0.01,
                                  help="density added everywhere: endpoints in empty regions too")
    stipple_iterations: int = param(10, min=0, max=50,
                                    help="Lloyd iterations of the weighted Voronoi stippling")
    # thickness (section 6)
    thickness: str = param("importance", options=("importance", "subtree", "share", "distance"),
                           help="importance emphasis, or branch thickness from the tree")
    window: int = param(15, min=1, max=101, step=2,
                        help="rolling-average window along the branches (nodes)")
    contrast: float = param(1.5, min=0.25, max=4.0, step=0.05,
                            help="exponent on the normalised rolling importance")
    tone: float = param(0.5, min=0.0, max=1.0, step=0.05,
                        help="tone vs edges: 0 = importance emphasis only, 1 = ink matches darkness")
    tone_sigma: float = param(8.0, min=1.0, max=40.0, step=0.5,
                              help="scale over which ink is matched to darkness (lattice px)")
    hierarchy: float = param(0.25, min=0.0, max=1.0, step=0.05,
                             help="width x (tips carried) ** hierarchy: trunks thicker than twigs")
    edges: float = param(1.0, min=0.0, max=4.0, step=0.05,
                         help="extra width on the image's edges after the tone match (outline, veins)")
    min_width: float = param(0.2, min=0.0, max=10.0, step=0.1,
                             help="narrowest stroke (lattice px)")
    max_width: float = param(4.0, min=0.0, max=30.0, step=0.1,
                             help="widest stroke (lattice px)")
    lattice_size: int = param(512, min=0, max=4096, step=64,
                              help="plan on a lattice with the diagonal of this square (0 = image)")
    output_width: float = param(1.0, min=0.0, max=5.0, step=0.1,
                                help="narrowest stroke at the image's own size (px; on images larger than "
                                     "the lattice: lattice px); smaller images get fewer endpoints (0 = off)")


def _within_range(p: StylizeParams, **values) -> StylizeParams:
    """``dataclasses.replace(p, **values)`` with each value clipped to its field's range
    (so a derived parameter set still validates, e.g. on a tiny image)."""
    meta = {f.name: f.metadata for f in dataclasses.fields(p)}
    for k, v in values.items():
        lo, hi = meta[k].get("min"), meta[k].get("max")
        v = v if hi is None else min(v, hi)
        values[k] = type(getattr(p, k))(v if lo is None else max(v, lo))
    return dataclasses.replace(p, **values)


#: On an image smaller than the lattice (``scale < 1``) the endpoint count falls by
#: ``scale ** SMALL_ENDPOINT_POWER`` and ``max_width`` grows by ``scale ** -SMALL_WIDTH_POWER``
#: (:func:`effective_params`; beyond the paper). 1.5 and 0.75 (the branch spacing's growth)
#: gave a 250-px object a 3-4 px outline round a sparse interior scribble where the same
#: object at 750 px is a dense texture with a thin outline.
SMALL_ENDPOINT_POWER = 1.25
SMALL_WIDTH_POWER = 0.45


def _spacing_growth(scale: float) -> float:
    """How much wider than on the 512-px picture the branches are spaced, in lattice px, on an
    image of ``scale`` image px per lattice px: ``n_endpoints`` falls by ``scale **
    SMALL_ENDPOINT_POWER`` below 1, and tips spread over the same area are spaced by the
    square root of the count. 1 at ``scale >= 1``."""
    return float(min(scale, 1.0) ** (-0.5 * SMALL_ENDPOINT_POWER))


def effective_params(p: StylizeParams, scale: float) -> StylizeParams:
    """The parameters a stylization drawn at ``scale`` image px per lattice px really uses.

    Lattice widths below ``p.output_width / scale`` would be drawn thinner than
    ``output_width`` image pixels, as pale grey hairlines: ``min_width`` is raised
    to that and ``max_width`` to at least twice it. On an image larger than the
    lattice (``scale > 1``) the floor stays at ``output_width`` *lattice* pixels,
    the 512-px picture's, so a 1000-px or a 2000-px input gives the 512-px
    drawing scaled up (same ink, same look at one display size) rather than
    hairlines a quarter as wide that read paler and paler as the input grows.
    On an image smaller than the lattice (``scale < 1``) the branches would no
    longer fit between one another, so the endpoint count falls to
    ``n_endpoints * scale ** 1.25`` (``SMALL_ENDPOINT_POWER``), ``tone_sigma``
    grows as the branch spacing does, by ``scale ** -0.625`` (``_spacing_growth``;
    with ``-0.75`` the tone match averaged a 250-px object's outline with a wider
    share of its interior than at 750 px), and ``max_width``
    by ``scale ** -0.45`` (``SMALL_WIDTH_POWER``; 0.3 left a 224-px night
    scene too pale, tone r 0.58). With the earlier 1.5 and
    0.75 the widest strokes, the object's outline, grew with the spacing: a
    250-px object read as a heavy 3-4 px outline round a sparse interior
    scribble, the same object at 750 px as a dense texture with a thin outline
    (ink of an 8-px band along the outline over the interior's, both shown at
    400 px, 250 against 750 px: mid-grey body 1.37 against 1.07, now 1.25;
    dark outlined 1.09 -> 1.01 against 1.00). The rest of that excess was the
    outline's extra width (``edges``), grown with the texture's strokes:
    :meth:`Stylizer._edge_gain` scales it back (mid-grey 1.31 -> 1.16 against
    1.12, outlined 1.40 -> 1.26 against 1.31, gradient 1.38 -> 1.25 against 1.21;
    ``python -m branchnb.dendrite._small_check``).
    Falling with ``scale`` alone left small inputs too dark (a maple leaf at
    200 px carried 1.44x the ink of the same leaf at 1000 px: the 1-px floor
    kept most strokes wider than the tone match asked for); falling with the
    area, ``scale ** 2``, keeps the 512-px spacing in image pixels but breaks a
    200-px leaf's shading into coarse blobs. With ``scale ** 1.5`` a procedural
    leaf, a drawn fish and a maple photo stylized at 200 - 2000 px keep their
    mean ink within 18 % of the 500-px result, and their share of solid ink
    within 19 %. This goes beyond the paper, whose examples are all drawn at
    about the lattice's size.

    The floor alone still over-inks thin features: a star outlined by a
    1.5-px line at 250 px was traced by several parallel 1-px strokes and
    carried 1.8x the ink of the same star at 750 px (rope 1.47x at 150 px).
    :meth:`Stylizer.run` therefore compares, on a small image, the ink of the
    floored widths with that of the widths at the 512-px floor, on the nodes the
    floor holds wider than the tone match asks, and drops twigs where the floor
    adds ink, up to four rounds
    (:func:`~branchnb.dendrite.thickness.twigs_within_ink`; lone long lines
    such as a leaf's stem are kept). Measured against 750 px (mean ink in the
    object, 150 / 250 px): thin-outlined star 1.62 / 1.04 (before 2.6 / 1.82,
    the star's line under 1 px at 150), rope 1.12 / 1.13 (1.47 / 1.18), maple
    photo 1.03 / 0.97 (1.27 / 1.10), lizard 1.09 / 1.03 (1.16 / 1.09), clip-art
    tree 1.05 / 1.01, filled star 0.97 / 0.96, coffee photo 1.02 / 1.02, a night
    photo 1.04 / 1.03; 1500 px within 1 % of 750 px. The ink maps of the
    tone match and the pruning are blurred on a grid ``sigma / 4`` times coarser
    (:func:`~branchnb.dendrite.thickness._smooth_at`), so a 200-250 px image
    takes 0.9-1.25x the CPU of the same picture at 750 px (1.3-1.6x with the full
    blurs, same runs).

    Parameters
    ----------
    p : StylizeParams
        The parameters as given (not modified).
    scale : float
        Image pixels per lattice pixel (geometric mean of x and y); a
        non-positive or non-finite value returns ``p``.

    Returns
    -------
    StylizeParams
        ``p`` itself when ``p.output_width`` is 0, else an adapted copy whose
        values stay within each field's range.

    Examples
    --------
    >>> q = effective_params(StylizeParams(), 0.5)
    >>> q.n_endpoints, q.min_width, round(q.max_width, 2)
    (1261, 2.0, 5.46)
    >>> effective_params(StylizeParams(), 2.0).min_width
    1.0
    >>> effective_params(StylizeParams(output_width=0.0), 0.5) == StylizeParams(output_width=0.0)
    True
    """
    if p.output_width <= 0 or not np.isfinite(scale) or scale <= 0:
        return p
    lo = min(max(p.min_width, p.output_width / min(scale, 1.0)), 10.0)
    if scale >= 1.0:
        return _within_range(p, min_width=lo, max_width=max(p.max_width, 2.0 * lo))
    grow = _spacing_growth(scale)  # the branch spacing, in lattice px, grows by this
    # the widest strokes (the outline: most important) must not outgrow the branch
    # spacing, or a small input reads as a heavy outline round a sparse scribble
    return _within_range(
        p, min_width=lo, max_width=max(p.max_width * scale ** -SMALL_WIDTH_POWER, lo),
        tone_sigma=p.tone_sigma * grow,
        n_endpoints=max(1, int(round(p.n_endpoints * scale ** SMALL_ENDPOINT_POWER))))


def on_lattice(p: StylizeParams, factor: float, widths: bool = True) -> StylizeParams:
    """``p`` with its lengths along the lattice (``window``, ``tone_sigma`` and with ``widths``
    ``min_width`` and ``max_width``) in pixels of a lattice ``factor`` times the size of the
    ``p.lattice_size`` one they are given for (``p`` itself at 1).

    A small picture is planned on a smaller lattice
    (:func:`~branchnb.dendrite.scale.planning_size`): the same drawing needs the same lengths
    in image pixels. ``sigma`` stays: :meth:`~branchnb.dendrite.stylization.Stylizer.importance`
    and ``edge_map`` convert it themselves, so the importance a seed is found on
    (:meth:`~branchnb.dendrite.stylization.Stylizer.default_seed`, given the parameters as the
    user set them) is the one :meth:`~branchnb.dendrite.stylization.Stylizer.run` plans on.

    Parameters
    ----------
    p : StylizeParams
        Lengths in pixels of the ``p.lattice_size`` lattice.
    factor : float
        Planning lattice's pixels per pixel of the ``p.lattice_size`` lattice, in (0, 1].
    widths : bool
        Convert the widths too (False: they are in the planning lattice's pixels already).

    Returns
    -------
    StylizeParams

    Examples
    --------
    >>> q = on_lattice(StylizeParams(), 0.5)
    >>> q.window, q.tone_sigma, q.min_width, q.max_width
    (7, 4.0, 0.1, 2.0)
    """
    if factor == 1.0:
        return p
    window = max(1, 2 * int(round(0.5 * (p.window * factor - 1))) + 1)  # odd: centred
    values = dict(window=window, tone_sigma=p.tone_sigma * factor)
    if widths:
        values.update(min_width=p.min_width * factor, max_width=p.max_width * factor)
    return _within_range(p, **values)


#: Vine stems are this many leaf lengths apart on average (:func:`metaphor_params`).
VINE_SPACING = 2.5
#: Vine leaf length, as a share of the object's size (the square root of its area): the
#: same at every image size, so an object looks the same drawn at 250 and 1000 px
#: (:func:`_vine_sizes`).
VINE_LEAF_PER_SIZE = 0.055
#: Shortest vine leaf sized to an object (image px; its other lengths follow it): below,
#: leaves read as green specks.
VINE_MIN_LEAF = 5.5
#: Fewest vine tips per leaf length of the object's outline (:func:`_vine_sizes`).
VINE_OUTLINE_TIPS = 1.0
#: ... but at most this many times the tips for its area (the outline of content strewn
#: over a textured ground is no object's: a cat on a dark ground got 154 tips for 92).
VINE_OUTLINE_CAP = 2.0


def _vine_sizes(shape, area: float, outline: float) -> tuple[float, int]:
    """The vines' length factor on their image-diagonal lengths and their tip count, for an
    object of ``area`` (px^2) and ``outline`` length (px) in an image of ``shape``.

    Beyond the paper (issue 25): leaves scaled with the image's diagonal, so an object
    filling a third of the frame's height got leaves 2.7x as long for its size as one
    filling it, and tips for its area alone, so a thin letter got a third of a blob's tips
    along its outline. Then (dendrite32) a leaf was ``0.035`` of the object's size up to the
    diagonal's length and at least 6.5 px: on a 250-px image that floor made leaves twice
    as long for the object as at 1000 px, and with tips for the floored leaf the 250-px
    blob got a quarter of the 1000-px blob's tips (leaf / size 250 against 1000 px 2.2x on
    objects filling the frame; tips per outline 0.26-0.37x; ``python -m
    branchnb.dendrite._vine_size_check``). Now a leaf is ``VINE_LEAF_PER_SIZE`` of the
    object's size at every image size (at least ``VINE_MIN_LEAF`` px: readable leaves win
    on objects under ~100 px); the tips are one per ``(VINE_SPACING x leaf)**2`` of its
    area, at least ``VINE_OUTLINE_TIPS`` per leaf length of its outline, up to
    ``VINE_OUTLINE_CAP`` times the area's count, the same for the same object at any size.

    >>> from branchnb.dendrite.metaphors import vine_length
    >>> for shape, size in (((750, 1000), 500.0), ((375, 500), 250.0)):  # one picture, two sizes
    ...     f, n = _vine_sizes(shape, size ** 2, 3.6 * size)
    ...     print(round(f * vine_length("leaf_length", shape) / size, 3), n)  # leaf / size, tips
    0.055 65
    0.055 65
    """
    from .metaphors import vine_length

    full = vine_length("leaf_length", shape)
    leaf = max(VINE_LEAF_PER_SIZE * float(np.sqrt(max(area, 0.0))), VINE_MIN_LEAF)
    n_area = area / (VINE_SPACING * leaf) ** 2
    n = max(n_area, min(VINE_OUTLINE_TIPS * outline / leaf, VINE_OUTLINE_CAP * n_area))
    return leaf / full, int(round(n))

#: The vines' object is what stands out from the picture's own ground (beyond the
#: paper, :func:`_ground_threshold`): importance at least ``endpoint_threshold`` above the
#: ``VINE_GROUND_QUANTILE`` quantile of the importance in a ring ``VINE_GROUND_RING``
#: of the long side wide along the frame. On white paper that level is ~0 and the share
#: is the paper's (importance above the threshold); on a grey wall and table or a dark
#: textured ground the whole frame passed the threshold and vines got 3-7x the tips the
#: object's area asks for.
VINE_GROUND_QUANTILE = 0.75
VINE_GROUND_RING = 0.03

#: Lightning branches are this share of the image diagonal apart on average.
LIGHTNING_SPACING = 0.09

#: Thinnest lightning twig (image px); thinner ones, drawn anti-aliased, vanish.
LIGHTNING_MIN_TWIG = 0.4

#: Narrowest widest lightning channel (image px), on images below ~170 px.
LIGHTNING_MIN_CORE = 2.0

#: Longest straight step that cuts a hairpin out of a lightning bolt's main channel,
#: as a share of the lattice's diagonal (beyond the paper: through a fern's ragged tip
#: the widest channel doubled back in hairpins a few pixels apart).
LIGHTNING_LOOP_REACH = 0.015

#: Blur (share of the lattice's diagonal) and share of the densest content a lightning
#: seed's neighbourhood must reach (beyond the paper: the topmost content pixel was often
#: a thin tip, a leaflet or an ear, and the widest channel started with a knot in it).
LIGHTNING_SEED_BLUR = 0.03
LIGHTNING_SEED_DENSITY = 0.5

#: Depth (share of the diagonal) of the outline band a lightning bolt's main channel
#: keeps out of, and the extra weight (units of the mean weight) on the outline itself
#: (:func:`~branchnb.dendrite.main_channel.strike_channel`).
STRIKE_BAND = 0.03
STRIKE_PENALTY = 2.0

#: Largest share of the picture an object's silhouette covers for a lightning bolt to
#: plan its main channel through it (drawn objects 0.19-0.61, photos 0.96-1).
STRIKE_MAX_COVER = 0.85

#: On a photo (silhouette over ``STRIKE_MAX_COVER``), the cost of a pixel of length (units
#: of the mean weight) of a lightning bolt's main channel, the power its weights are
#: raised to, and the lower share of the content's height where it ends
#: (:func:`~branchnb.dendrite.photo_strike.photo_channel`).
STRIKE_PHOTO_LENGTH = 0.3
STRIKE_PHOTO_CONTRAST = 4.0
STRIKE_PHOTO_DEPTH = 0.4
#: ... and how much more than the least cost per pixel of descent its end may cost, the
#: deepest such end taken (beyond the paper: with the least alone it ended at the nearest
#: cheap place, 0.60 of the height on cracked mud whose cracks run to the bottom).
STRIKE_PHOTO_SLACK = 0.25

#: A photo's strike (:func:`~branchnb.dendrite.photo_strike.strike_origin`): bright
#: structures narrower than ``STRIKE_RIDGE`` of the diagonal, ``STRIKE_NOISE`` robust
#: standard deviations above the picture's noise and at least ``STRIKE_MIN_RIDGE`` of
#: luminance; none where they cover more than ``STRIKE_MAX_RIDGE`` of the picture (a
#: textured photo: 0.09-0.19 on a portrait, a cat, a cup and a camera man, 0.01-0.03 on
#: lightning photos) or span less than ``STRIKE_MIN_SPAN`` of its height.
STRIKE_RIDGE = 0.02
STRIKE_NOISE = 4.0
STRIKE_MIN_RIDGE = 0.08
STRIKE_MAX_RIDGE = 0.06
STRIKE_MIN_SPAN = 0.2
#: A strike has a bolt's profile: along its centreline (its skeleton), within a Gaussian
#: window of ``STRIKE_JAG_WINDOW`` of the diagonal, the centreline's spread across its own
#: direction is at least ``STRIKE_MIN_JAG`` of the window (median over the centreline;
#: :func:`~branchnb.dendrite.photo_strike.jaggedness`). Measured on the 512-px lattice:
#: straight lines of any slope 0, a dusk skyline's lit mast 0.017, a curve of radius 0.5
#: of the diagonal 0.027, the bolts of the NOAA photo 0.27-0.54, procedural storms
#: 0.07-0.12 (beyond the papers: the mast was taken for a strike and the bolt ran down it).
STRIKE_JAG_WINDOW = 0.02
STRIKE_MIN_JAG = 0.05
#: Where a lightning bolt's main channel on a photo without a strike is straighter than
#: that, it zigzags: vertices every window and every third of it, each shifted within this
#: share of its spacing (:func:`~branchnb.dendrite.photo_strike.jag_channel`).
STRIKE_JAG_AMPLITUDE = 0.35
#: Robust standard deviations above the median gradient from which an edge stands out of
#: a photo's noise for a lightning bolt's side branches
#: (:func:`~branchnb.dendrite.photo_strike.edge_significance`).
STRIKE_EDGE_NOISE = 3.0
#: Shortest piece of a lightning photo's bright lines (its extent, share of the diagonal)
#: its side branches run along (specks of cloud and the lights on the ground are shorter).
STRIKE_MIN_PIECE = 0.05
#: ... and between those lines they cost less where the picture is bright (a lit cloud,
#: not the dark sky): the importance there is this share of the blurred luminance.
STRIKE_GLOW = 0.6
#: On a photo without a strike, the long straight edges (Hough segments of the Canny
#: edges, at least ``STRIKE_STRAIGHT_LENGTH`` of the diagonal) and a band of
#: ``STRIKE_STRAIGHT_BAND`` of the diagonal round them cost this many mean weights more for
#: the side branches, and no endpoint is stippled there
#: (:func:`~branchnb.dendrite.photo_strike.straight_edges`; beyond the paper: the side
#: branches ran ruler-straight down a rocket's launch towers).
STRIKE_STRAIGHT_LENGTH = 0.06
STRIKE_STRAIGHT_BAND = 0.005
STRIKE_STRAIGHT_PENALTY = 1.0
#: ... unless more than this share of the edges that stand out of the noise lie on them:
#: then they are the picture's structure (procedural straight cracks 0.74; a launch pad
#: 0.57, text 0.40-0.42, the rocket photo 0.26-0.33, the camera man 0.26, photos 0.04-0.16).
STRIKE_STRAIGHT_MAX_SHARE = 0.65
#: A bright piece (:func:`~branchnb.dendrite.photo_strike.strike_origin`) with more than
#: ``STRIKE_MAX_STRAIGHT`` of its pixels on those straight edges, counting only segments
#: that are Canny edges along at least ``STRIKE_STRAIGHT_COVER`` of their length, is no
#: strike (a launch tower's lit truss,
#: jagged as a 2-D mesh, was a strike on the rocket photo at 200-320 px: 0.08-0.42 of it on
#: them; the zelkova leaf's veins at 240 px 0.68; the NOAA bolts and procedural storms
#: 0.00). The segments' cover leaves out the axis of a fine zigzag, which Hough finds
#: through its legs' crossings (cover 0.49-0.67). The rule counts only for a piece whose
#: jag (:func:`~branchnb.dendrite.photo_strike.jaggedness` times the window) is at least
#: ``STRIKE_STRAIGHT_MIN_SPREAD`` pixels: a line zigzagging within ~1.5 px of its axis is
#: one straight band at the Canny edges' resolution (sigma 1 px), so they say nothing
#: about it (toy zigzags of 60-160 px with a period of 6-10 px: 0.3-1.4 px).
STRIKE_MAX_STRAIGHT = 0.05
STRIKE_STRAIGHT_COVER = 0.75
STRIKE_STRAIGHT_MIN_SPREAD = 1.5
#: A strike is a light source: the median luminance of its piece
#: (:func:`~branchnb.dendrite.photo_strike.strike_origin`) is above at least
#: ``STRIKE_MIN_RANK`` of the picture's pixels (beyond the papers). Measured: the NOAA
#: bolt at 200-1024 px 0.987-0.992, procedural storms 0.93-0.996 (the lowest under a lit
#: cloud brighter than the bolt); a zelkova leaf's midrib, lighter than its blade but
#: darker than the paper, 0.34 (a strike at 200 px, where its veins' 0.85-px jag is below
#: what the straight-edge test resolves), on a crop of the blade with a paper corner
#: 0.88; the white ground between a horse silhouette's tail and leg 0.34.
STRIKE_MIN_RANK = 0.9
#: On a photo without a strike of its own, the side branches of the bolt end in its
#: region (:func:`~branchnb.dendrite.photo_side.strike_region`, beyond the papers): a cone
#: about the main channel from its top, ``STRIKE_REGION_ANGLE`` degrees either side of the
#: channel, plus ``STRIKE_REGION_MARGIN`` of the diagonal, as the lightning metaphor's
#: side-branch endpoints lie in a cone 0.45 of the width wide at the bottom (24 degrees on
#: a square; :class:`~branchnb.dendrite.metaphors.LightningParams`, ``spread``); and they
#: are planned with edges stepping up ``STRIKE_PHOTO_UP`` times as long (the metaphor's 6x,
#: with sideways 1.6x, kept the side branches off a crack picture's cracks: their share
#: near the cracks 0.97 -> 0.66; 3x / 1.2x 0.80; 2x 0.99). Without them a bolt down the
#: middle of a night photo (the rocket at 640 px) sent branches from its top across the
#: whole sky to the lights on the ground; side branches' length outside a 60-degree cone
#: below their fork, rocket / astronaut at 640 px: 0.67 / 0.88 without, 0.53 / 0.79 with
#: the region, 0.04 / 0.04 with the region and up 2x (0.00 / 0.06 at 6x).
STRIKE_REGION_ANGLE = 25.0
STRIKE_REGION_MARGIN = 0.03
#: And they are as short as a real bolt's (beyond the papers): each is cut back to
#: ``STRIKE_SIDE_LENGTH`` of the main channel's length (and to the channel's length below
#: its fork), and a tip more than ``STRIKE_SIDE_ANGLE`` degrees off straight down from its
#: fork is dropped (:func:`~branchnb.dendrite.photo_side._short_sides`). Forking at the
#: channel's top they ran down beside it to the ground: side branches as long as the
#: channel, mean lateral reach 0.06-0.12 of the diagonal against ~0.03 for a bolt (the
#: procedural storms' side branches are 0.19-0.37 of their trunk, 29-52 degrees off
#: the vertical). ``python -m branchnb.dendrite._side_spread``.
STRIKE_SIDE_LENGTH = 0.3
STRIKE_SIDE_ANGLE = 60.0
STRIKE_PHOTO_UP = 2.0

#: Factor on the width (above the thinnest) of the side branches of a lightning bolt on a
#: photo (:func:`~branchnb.dendrite.main_channel.widen_main_path`, ``side``; beyond the
#: paper: the planned channel forks into long branches that held 0.65-0.8 of the ink, a
#: glowing scribble round the channel).
STRIKE_PHOTO_SIDE = 0.25
#: The same for a bolt through a drawn object (beyond the paper: down the middle of a
#: body with thin prongs on top, the channel held 0.340 of the ink at full side widths).
STRIKE_SIDE = 0.8

#: Exponent of the share of the tips that sets the width of a main channel planned
#: through an object (``LIGHTNING_MAIN_EXPONENT`` otherwise): down the middle of a
#: body with thin prongs on top it is short, and with 8 it held 0.31 of the ink; 1000 keeps it
#: at practically full width down to its last fork (0.34).
STRIKE_MAIN_EXPONENT = 1000.0

#: Exponent of the share of the tips that sets a lightning bolt's main channel's width
#: (:func:`~branchnb.dendrite.main_channel.widen_main_path`; the other channels keep the
#: share rule's 2; beyond the paper: thinned at every fork, the main channel faded into
#: its side branches on busy pictures).
LIGHTNING_MAIN_EXPONENT = 8.0


def _ground_threshold(importance: np.ndarray, threshold: float) -> float:
    """The importance threshold of what stands out from the picture's own ground (vines).

    The ground's level is a high quantile (``VINE_GROUND_QUANTILE``) of the importance
    along the frame (a ring ``VINE_GROUND_RING`` of the long side wide): the dominant
    ground, also where an object or a table touches the frame. Content is importance at
    least ``threshold`` above it. A ground below half the threshold is paper and the
    paper's rule holds (``threshold`` itself: the same count and endpoints on white, bit
    for bit); between half the threshold and the threshold the shift ramps up, so the
    count never jumps as a ground darkens. Beyond the paper: on a grey wall and table or
    a dark textured ground the whole frame passed the paper's threshold, and vines got
    5-7x the tips the object's area asks for, spread over the ground.
    """
    imp = np.asarray(importance, np.float32)
    b = max(1, int(round(VINE_GROUND_RING * max(imp.shape))))
    ring = np.ones(imp.shape, bool)
    ring[b:-b, b:-b] = False
    level = float(np.quantile(imp[ring], VINE_GROUND_QUANTILE)) if ring.any() else 0.0
    ramp = float(np.clip(2.0 * level / threshold - 1.0, 0.0, 1.0)) if threshold > 0 else 1.0
    return float(threshold + ramp * level)


def metaphor_params(p: StylizeParams, metaphor: str, shape, object_share: float,
                    scale: float) -> StylizeParams:
    """The parameters of a stylization drawn with ``metaphor`` (plain: ``p`` itself).

    The paper's ~3,000 endpoints fill a picture with ink. Drawn as vines,
    every tip carries a curl and leaves along its stem, and 3,000 of them
    make an overgrown mass that hides the object; drawn as lightning, they
    make a glowing scribble. Both metaphors therefore set their own endpoint
    count from the area with something to draw (``object_share`` of the
    image, ``shape``) and a spacing between branches, never more than
    ``p.n_endpoints``:

    * **vines**: one tip per ``(VINE_SPACING x leaf length)**2``, the leaf
      length following the image's diagonal
      (:func:`~branchnb.dendrite.metaphors.vine_length`); stems from 1 image
      pixel to 2 px at 512 x 512 (scaled with the diagonal, at least 1.8 px)
      wide by their importance alone (no tone match: the leaves and the
      stems' layout carry the picture).
    * **lightning**: one tip per ``(LIGHTNING_SPACING x diagonal)**2``,
      stippled on importance squared (``endpoint_gamma = 2``: the bolts run
      along the strongest edges), and widths from the tree alone
      (``thickness = "share"``: growing with the square root of the share of
      the tips a channel carries) from 1 px to 6 px at 512 x 512 (both scaled with the
      diagonal, at least ``LIGHTNING_MIN_TWIG`` = 0.4 and
      ``LIGHTNING_MIN_CORE`` = 2 px): a few bright main channels that fork
      into thin, dim branches, the same look from 200 to 2000 px
      (:func:`~branchnb.dendrite.metaphors.render_lightning` dims a stroke
      with its width; a twig thinner than a pixel is drawn dim, as the
      larger bolt would be when shown small). Beyond the paper: with floors
      of 1 and 3 px a 200-px bolt had twigs as wide as its core, a scribble
      (on a portrait, a cup, a camera man and a horse at 200 px, the mean
      brightness was 0.22-0.29 against 0.13-0.18 for the 600-px bolt shown
      at 200 px, and 5-10 % of the pixels bright against 2.4-2.8 %; now
      0.13-0.19 and 1.9-2.9 %).

    Lightning beyond the paper, a main bolt with a few forks: with branches
    0.045 of the diagonal apart (~230 tips) and the pipe model clipped at the
    widest channel, every channel carrying more than ~36 tips burned as white as
    the main one, so a photo became a glowing outline over a busy scribble. Now
    the branches are ``LIGHTNING_SPACING`` = 0.09 of the diagonal apart (~4x
    fewer tips), the widths follow each channel's share of all the tips
    (``thickness = "share"``: only the channel that carries them all is the
    widest) and the bolt starts at the top of the picture's content
    (:meth:`~branchnb.dendrite.stylization.Stylizer.top_seed`), so it runs down
    and forks like a strike. On a portrait (250 px), a cup photo (500), a horse
    silhouette (400), a camera man (800), a drawn lizard (600), a drawn tree (300)
    and dark beans (1200) the share of the ink on the main path (from the seed
    down the child that carries the most ink) went from 0.18 0.22 0.81 0.21 0.80
    0.65 0.34 to 0.45 0.52 0.78 0.40 0.55 0.38 0.68 and the tips from 231 211 87
    210 44 116 46 to 59 51 23 54 10 33 11. The seed sits where the content is
    wide and the main channel's hairpins are cut
    (:func:`~branchnb.dendrite.main_channel.shortcut_loops`): from the topmost
    pixel, on a fern frond's thin tip, the widest channel began with a tight
    zigzag knot through the tip's leaflets. On the fern (300 / 700 / 1400 px), a
    star, a spire and a body with two thin prongs on top (250 / 600 / 1200), a
    camera man (256 / 800), a horse (400) and a cup photo (500) the longest way
    round between two points of the main path closer than 1.5 % of the diagonal
    went from 0.007-2.6 (0.07 / 0.21 / 0.21 on the fern) to 0.009-0.020 diagonals
    and the fern's main path's tortuosity from 1.7-2.1 to 1.3-1.6; the ink on the
    main path from 0.34-0.82 to 0.31-0.82 (the camera man 0.34 -> 0.31): cut short,
    the main channel thinned at every fork and faded into its side branches. Its
    width now follows its share of the tips with the exponent
    ``LIGHTNING_MAIN_EXPONENT`` = 8 instead of 2 down to its node farthest from the
    seed (:func:`~branchnb.dendrite.main_channel.widen_main_path`): bright down to
    its last fork, its last twig and any turn back thin. On the camera man (256 /
    512 / 800 px), a fern photo (600), a spire (400), and a portrait, a cat, a cup,
    cracked mud, a retina and a tree photo the ink on the main path went from 0.31 /
    0.43 / 0.32, 0.41, 0.30 and 0.36-0.67 to 0.35 / 0.47 / 0.36, 0.46, 0.38 and
    0.39-0.68 (silhouettes 0.72-0.91 to 0.72-0.92), the paths and loops unchanged.

    ``scale`` is image pixels per lattice pixel; the widths are returned in
    lattice pixels like every length of :class:`StylizeParams`.

    Parameters
    ----------
    p : StylizeParams
        The parameters as given (after :func:`effective_params`, or not).
    metaphor : str
        "vines" or "lightning"; any other name returns ``p``.
    shape : (int, int)
        ``(H, W)`` of the image (pixels).
    object_share : float
        Share of the image with something to draw (importance at or above the
        threshold), in [0, 1]. For vines :meth:`Stylizer.run` passes the share
        standing out from the picture's own ground (:func:`_ground_threshold`) and
        stipples the tips there.
    scale : float
        Image pixels per lattice pixel.

    Returns
    -------
    StylizeParams
        A copy with the metaphor's endpoint count, widths and thickness mode.

    Examples
    --------
    >>> q = metaphor_params(StylizeParams(), "vines", (1000, 1000), 0.5, 1000 / 512)
    >>> q.n_endpoints, q.tone
    (428, 0.0)
    >>> metaphor_params(StylizeParams(), "lightning", (512, 512), 1.0, 1.0).n_endpoints
    62
    """
    if metaphor not in ("vines", "lightning"):
        return p
    h, w = int(shape[0]), int(shape[1])
    lo = max(p.min_width, 1.0 / scale)
    if metaphor == "vines":
        from .metaphors import vine_length

        spacing = VINE_SPACING * vine_length("leaf_length", (h, w))
        hi = max(1.8, 2.0 * length_scale((h, w))) / scale
        changes = dict(tone=0.0, edges=0.0)
    else:
        spacing = LIGHTNING_SPACING * float(np.hypot(h, w))
        # widths as at 512 x 512 scaled with the diagonal, also below 512 px (beyond the
        # paper): with a floor of 1 px for the twigs and 3 px for the main channel, a
        # 200-px bolt's twigs were as bright and wide as its core (twice the mean
        # brightness of the 600-px bolt shown at 200 px, a scribble); thinner than a
        # pixel, a twig is drawn dim (anti-aliased coverage), as it would be downscaled
        hi = max(LIGHTNING_MIN_CORE, 6.0 * length_scale((h, w))) / scale
        # the thinnest branch too follows the diagonal above 512 px: with 1-px twigs the
        # pipe model never reached the widest channel on a 2000-px image (all dim)
        lo = max(p.min_width, max(LIGHTNING_MIN_TWIG, length_scale((h, w))) / scale)
        changes = dict(tone=0.0, edges=0.0, thickness="share", endpoint_gamma=2.0)
    n = int(round(float(np.clip(object_share, 0.0, 1.0)) * h * w / spacing ** 2))
    return _within_range(p, n_endpoints=int(np.clip(n, min(8, p.n_endpoints), p.n_endpoints)),
                         min_width=min(lo, 10.0), max_width=max(lo, hi), **changes)
