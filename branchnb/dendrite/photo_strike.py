"""A lightning bolt on a photo: where it strikes from, where it goes, what it branches along.

Beyond the papers (Xu & Mould 2007; Long & Mould 2009), for
:meth:`~branchnb.dendrite.stylization.Stylizer.run` with ``metaphor="lightning"`` on a
photo (content everywhere, no object to run down through,
:func:`~branchnb.dendrite.main_channel.strike_weights`):

* **Where the bolt starts** (:func:`strike_origin`). From the top centre of the
  picture a bolt on a lightning photo started in the dark cloud. A photo's own strike is
  a bright structure narrower than ``STRIKE_RIDGE`` of the diagonal (a white top-hat of
  the luminance) standing out of the picture's noise (``STRIKE_NOISE`` robust standard
  deviations, and at least ``STRIKE_MIN_RIDGE`` of luminance); where such bright lines
  are rare (under ``STRIKE_MAX_RIDGE`` of the picture: not a textured photo), the bolt
  starts at the top of the brightest one that spans at least ``STRIKE_MIN_SPAN`` of the
  height and has a bolt's profile (:func:`jaggedness` at least ``STRIKE_MIN_JAG``: a
  straight lit mast is no strike) and does not lie on the picture's long straight edges
  (more than ``STRIKE_MAX_STRAIGHT`` of it on :func:`straight_edges`: a lit launch pad is
  no strike; tested only where the Canny edges resolve the piece's zigzag). Otherwise it
  is the ordinary lightning metaphor: from the top of the picture's content, its main
  channel's straight stretches zigzagging (:func:`jag_channel`).
* **How far it goes** (:func:`photo_channel`). The main channel runs down the picture's
  structure to the deepest end whose cost per pixel of descent is within
  ``STRIKE_PHOTO_SLACK`` of the cheapest (it ended at the nearest cheap place: 0.60 of
  the height on cracked mud whose cracks run to the bottom).
* **What the side branches follow** (:func:`edge_significance`). Stippled on the
  importance, whose darkness term is high all over a night sky, the side branches
  wandered through the dark cloud along noise-level edges, a faint scribble. Their
  endpoints are now stippled on the edges that stand out of the picture's noise, and they
  are planned on a lattice whose cost falls with that significance. On a lightning photo
  (one with a strike) they are the photo's other long bright lines (its other bolts;
  pieces shorter than ``STRIKE_MIN_PIECE`` of the diagonal, specks of cloud and the
  lights on the ground, left out), and between them the lattice is cheaper where the
  picture is bright (``STRIKE_GLOW``: through the lit cloud, not the dark sky); on other
  photos the edges whose gradient stands ``STRIKE_EDGE_NOISE`` robust standard deviations
  above the median.

Measured with the defaults (before -> after): on the NOAA lightning photo at 512 / 1000
px the seed's luminance percentile 0.01 / 0.05 -> 0.99 / 1.00 (on its brightest bolt,
where it leaves the cloud), the share of the side branches' ink within 2 px of an edge
above the noise (gradient above median + 3 robust sd; 0.18-0.19 of the picture) 0.38 /
0.35 -> 0.56 / 0.47, the main channel's ink 0.24 -> 0.32; on a procedural night storm
(240 / 280 px) the seed 0.35 of the height above the strike's top -> on it, the side
branches' share 0.25 / 0.23 -> 0.75 / 0.73; the lowest point of the main channel on
cracked mud, a cat photo and a cup photo 0.60 / 0.65 / 0.82 -> 1.00 of the height
(procedural cracks 0.75 -> 1.00), the side branches' share 0.54 / 0.39 / 0.62 -> 0.62 /
0.61 / 0.85 (procedural cracks 0.78 -> 0.97), on the astronaut and the camera man 0.76 /
0.53 -> 0.88 / 0.63, on a storm with one bolt 0.08-0.11 -> 1.00.

With the bolt's profile (before -> after, with the defaults): the 3 lightning pictures
with a strike keep it at the same origin (the NOAA photo, two procedural storms; the
traced lightning drawing has none, too textured, before and after); of 9 pictures
without lightning only a dusk skyline had one, its lit mast (1 -> 0 strikes); the share
of the main channel straighter than a bolt (spread under 0.05 of a 2 % window) on the
photos without a strike: the rocket 0.59 -> 0.02, the astronaut 0.23 -> 0.00, the camera
man 0.19 -> 0.01, the cup 0.08 -> 0.00, the cat 0.26 -> 0.05, the lightning drawing 0.12
-> 0.00, the skyline 0.35 -> 0.04, procedural cracks 0.32 -> 0.06, cracked mud 0.01 ->
0.01; the channel's share within 2 px of an edge above the noise falls where it ran down
a straight edge (rocket 0.70 -> 0.53, cracks 1.00 -> 0.86, astronaut 0.94 -> 0.85, cat
0.69 -> 0.64, drawing 0.99 -> 0.94, camera man and cup within 0.01); the side branches'
share unchanged (0.54-0.97) but on the skyline (1.00 -> 0.83: along its edges instead of
its bright windows).

With the straight-edge test (before -> after, with the defaults): false strikes on 12
photos without lightning at 240 / 320 / 512 / 800 px and the dusk skyline 3 of 49 -> 0
(the rocket at 240 and 320 px, the zelkova leaf at 240 px), the rocket at 200-480 px 4 of
7 -> 0, a procedural launch pad 6 of 6 -> 0; the NOAA photo at 9 sizes and 20 procedural
storms keep their strike at the same origin; toy zigzags of 60-400 px (periods 6-40 px)
keep 61 of 68 strikes (65 without the test; the lost ones have straight legs longer
than ``STRIKE_STRAIGHT_LENGTH``).

A strike is a light source (``STRIKE_MIN_RANK``): its median luminance is above 0.9 of
the picture's pixels. The zelkova leaf at 200 px had a strike, its midrib (lighter than
the blade, darker than the paper: above 0.34 of the pixels), whose veins' 0.85-px jag
the straight-edge test cannot resolve; so had the white ground between a horse
silhouette's tail and leg (0.34). ``python -m branchnb.dendrite._strike_sweep [--off]``
(before -> after): false strikes on 12 photos at 200 / 240 / 320 / 512 / 800 px and the
skyline 4 of 61 -> 0 (on the 49 without 200 px: 2 -> 0); the 35 lightning pictures (NOAA
at 5 sizes, 10 night storms, 20 storms with a lit cloud and city lights) keep 31 strikes
at the same origins (the bolts' ranks 0.93-0.996). Limit: a bolt under a lit cloud
covering more than a tenth of the picture would be lost.

On a photo without a strike of its own the side branches end in the bolt's region
(:func:`~branchnb.dendrite.photo_side.strike_region`, ``STRIKE_REGION_ANGLE``: a cone of
25 degrees either side of the main channel from its top, as the lightning metaphor's
endpoints lie in a cone 24 degrees wide on a square) and are planned with edges stepping
up twice as long (``STRIKE_PHOTO_UP``), so they fork downwards.
``python -m branchnb.dendrite._side_spread`` (before -> after, 320 / 640 px): the share of
the side branches' length outside a 60-degree cone below their fork on the main channel,
rocket 0.95 / 0.67 -> 0.17 / 0.04, text 0.98 / 0.99 -> 0.76 / 0.85 (its lines of letters
run sideways), clock 0.67 / 0.93 -> 0.17 / 0.10, cup 0.82 / 0.90 -> 0.38 / 0.35, cat 0.79 /
0.76 -> 0.15 / 0.22, astronaut 0.92 / 0.88 -> 0.05 / 0.04, camera man 0.56 / 0.58 -> 0.22 /
0.09, cracked mud 0.86 / 0.82 -> 0.05 / 0.09 (the procedural storms' own side branches
0.14); their mean lateral reach from the fork, share of the diagonal, rocket 0.219 / 0.185
-> 0.115 / 0.110, text 0.239 / 0.255 -> 0.062 / 0.071, clock 0.116 / 0.060 -> 0.069 /
0.072, cup 0.210 / 0.199 -> 0.105 / 0.086, cat 0.138 / 0.107 -> 0.067 / 0.068, astronaut
0.173 / 0.182 -> 0.117 / 0.119, camera man 0.151 / 0.161 -> 0.071 / 0.099, cracked mud
0.194 / 0.184 -> 0.115 / 0.130 (storms 0.029: the branches still reach 2-4x as far as a
bolt's). The NOAA photo, struck, is unchanged (0.82 / 0.88, 0.171 / 0.176).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from .stylize_params import (
    STRIKE_JAG_AMPLITUDE,
    STRIKE_JAG_WINDOW,
    STRIKE_MAX_RIDGE,
    STRIKE_MAX_STRAIGHT,
    STRIKE_MIN_JAG,
    STRIKE_MIN_RANK,
    STRIKE_MIN_RIDGE,
    STRIKE_MIN_SPAN,
    STRIKE_NOISE,
    STRIKE_PHOTO_CONTRAST,
    STRIKE_PHOTO_DEPTH,
    STRIKE_PHOTO_LENGTH,
    STRIKE_PHOTO_SLACK,
    STRIKE_RIDGE,
    STRIKE_STRAIGHT_BAND,
    STRIKE_STRAIGHT_COVER,
    STRIKE_STRAIGHT_LENGTH,
    STRIKE_STRAIGHT_MIN_SPREAD,
)

__all__ = ["bright_ridges", "edge_significance", "jaggedness", "long_pieces", "noise_threshold",
           "jag_channel", "photo_channel", "side_branches", "straight_edges", "strike_origin", "strike_region"]


def noise_threshold(values, k: float = STRIKE_NOISE) -> float:
    """The level ``median + k * 1.4826 * MAD`` of ``values``: what stands above it is
    out of the noise (most pixels of a photo are no edge and no line).

    Parameters
    ----------
    values : array_like
        Any non-empty array (e.g. a gradient strength map).
    k : float
        Robust standard deviations above the median (>= 0).

    Returns
    -------
    float

    Examples
    --------
    >>> v = np.r_[np.zeros(90), np.ones(10)]
    >>> noise_threshold(v)
    0.0
    """
    v = np.asarray(values, np.float64).ravel()
    if v.size == 0:
        raise ValueError("values must not be empty")
    if not k >= 0:
        raise ValueError(f"k must be >= 0, got {k}")
    med = float(np.median(v))
    return med + k * 1.4826 * float(np.median(np.abs(v - med)))


def edge_significance(gradient, k: float = STRIKE_NOISE) -> np.ndarray:
    """How far each pixel's edge stands out of the picture's noise, in [0, 1].

    0 at or below :func:`noise_threshold` of ``gradient``, 1 at its 99.5th
    percentile and above, linear between.

    Parameters
    ----------
    gradient : (h, w) array_like
        Gradient strength (>= 0), e.g.
        :func:`~branchnb.dendrite.importance.gradient_strength`.
    k : float
        As in :func:`noise_threshold`.

    Returns
    -------
    (h, w) float64 ndarray

    Examples
    --------
    >>> g = np.full((20, 20), 0.05); g[:, 10] = 1.0
    >>> e = edge_significance(g); float(e[0, 0]), float(e[0, 10])
    (0.0, 1.0)
    """
    g = np.asarray(gradient, np.float64)
    if g.ndim != 2:
        raise ValueError(f"gradient must be 2-D, got shape {g.shape}")
    t = noise_threshold(g, k)
    top = float(np.percentile(g, 99.5))
    return np.clip((g - t) / max(top - t, 1e-6), 0.0, 1.0)


def bright_ridges(luminance, *, ridge: float = STRIKE_RIDGE, k: float = STRIKE_NOISE,
                  min_ridge: float = STRIKE_MIN_RIDGE) -> tuple[np.ndarray, np.ndarray]:
    """A photo's bright lines: the white top-hat of ``luminance`` with a square of
    ``ridge`` of the diagonal, and where it stands out of the noise
    (:func:`noise_threshold` with ``k``, and at least ``min_ridge``).

    Parameters
    ----------
    luminance : (h, w) array_like
        Luminance in [0, 1].
    ridge, k, min_ridge : float
        As in :func:`strike_origin`.

    Returns
    -------
    top : (h, w) float64 ndarray
        How much brighter than its surroundings each pixel is.
    strong : (h, w) bool ndarray
        The bright lines.

    Examples
    --------
    >>> lum = np.full((40, 40), 0.2); lum[5:35, 20] = 0.9
    >>> top, strong = bright_ridges(lum); int(strong.sum())
    30
    """
    lum = np.asarray(luminance, np.float64)
    if lum.ndim != 2 or min(lum.shape) < 3:
        raise ValueError(f"luminance must be an (h, w) array, got shape {lum.shape}")
    size = max(3, int(round(ridge * float(np.hypot(*lum.shape)))) | 1)
    top = lum - ndimage.grey_opening(lum, size=(size, size), mode="nearest")
    return top, top > max(noise_threshold(top, k), min_ridge)


def long_pieces(mask, min_extent: float) -> np.ndarray:
    """The pieces of ``mask`` (touching within a pixel) whose bounding box's diagonal is at
    least ``min_extent`` of the mask's diagonal.

    Parameters
    ----------
    mask : (h, w) array_like of bool
        Pixels to group into pieces (e.g. a picture's bright lines).
    min_extent : float
        Share (>= 0) of the diagonal.

    Returns
    -------
    (h, w) bool ndarray

    Examples
    --------
    >>> m = np.zeros((50, 50), bool); m[5:40, 10] = True; m[45, 45] = True
    >>> int(long_pieces(m, 0.1).sum())
    35
    """
    m = np.asarray(mask, bool)
    if m.ndim != 2:
        raise ValueError(f"mask must be 2-D, got shape {m.shape}")
    lab, n = ndimage.label(ndimage.binary_dilation(m), np.ones((3, 3), bool))
    if n == 0:
        return m.copy()
    ext = np.array([np.hypot(s[0].stop - s[0].start, s[1].stop - s[1].start)
                    for s in ndimage.find_objects(lab)])
    keep = np.r_[False, ext >= min_extent * float(np.hypot(*m.shape))]
    return m & keep[lab]


def jaggedness(mask, window: float) -> float:
    """How jagged a line is: the median, along its centreline, of the centreline's spread
    across its own direction within a Gaussian window, as a share of the window.

    The centreline is the skeleton of ``mask``; at each of its pixels the second
    moments of the centreline's pixels weighted by a Gaussian of standard deviation
    ``window`` (pixels) give its local direction, and the square root of the smaller
    eigenvalue its spread across it, less the ~0.29 px of a digital straight line's
    pixel steps (in quadrature). A straight line of any slope gives ~0; a lightning
    bolt, which turns every few pixels, 0.07-0.5 in a window of 2 % of the diagonal.

    Parameters
    ----------
    mask : (h, w) array_like of bool
        One line (e.g. a piece of :func:`bright_ridges`).
    window : float
        Standard deviation (> 0, pixels) of the window.

    Returns
    -------
    float
        0 for an empty mask.

    Examples
    --------
    >>> m = np.zeros((80, 80), bool); m[10:70, 40] = True
    >>> jaggedness(m, 8.0) < 0.02
    True
    >>> y = np.arange(10, 70); z = np.zeros((80, 80), bool)
    >>> z[y, 38 + np.abs((y - 10) % 8 - 4)] = True  # a zigzag
    >>> jaggedness(z, 8.0) > 0.05
    True
    """
    from skimage.morphology import skeletonize

    m = np.asarray(mask, bool)
    if m.ndim != 2:
        raise ValueError(f"mask must be 2-D, got shape {m.shape}")
    if not window > 0:
        raise ValueError(f"window must be > 0, got {window}")
    if not m.any():
        return 0.0
    ys, xs = np.nonzero(m)
    pad = int(np.ceil(3 * window)) + 1
    y0, x0 = max(ys.min() - pad, 0), max(xs.min() - pad, 0)
    box = m[y0:ys.max() + pad + 1, x0:xs.max() + pad + 1]
    sk = skeletonize(box).astype(np.float64)
    if not sk.any():
        sk = box.astype(np.float64)
    yy, xx = np.mgrid[0:box.shape[0], 0:box.shape[1]].astype(np.float64)

    def mean(a):
        return ndimage.gaussian_filter(a * sk, window, mode="constant")

    wsum = np.maximum(mean(np.ones_like(sk)), 1e-12)
    mx, my = mean(xx) / wsum, mean(yy) / wsum
    cxx = mean(xx * xx) / wsum - mx ** 2
    cyy = mean(yy * yy) / wsum - my ** 2
    cxy = mean(xx * yy) / wsum - mx * my
    on = sk > 0
    tr, det = (cxx + cyy)[on], (cxx * cyy - cxy ** 2)[on]
    small = tr / 2 - np.sqrt(np.maximum(tr ** 2 / 4 - det, 0.0))
    # less a digital straight line's own pixel steps (uniform in +-0.5 px: variance 1/12)
    return float(np.median(np.sqrt(np.maximum(small - 1.0 / 12.0, 0.0)))) / window


def strike_origin(luminance, *, ridge: float = STRIKE_RIDGE, k: float = STRIKE_NOISE,
                  min_ridge: float = STRIKE_MIN_RIDGE, max_share: float = STRIKE_MAX_RIDGE,
                  min_span: float = STRIKE_MIN_SPAN, window: float = STRIKE_JAG_WINDOW,
                  min_jag: float = STRIKE_MIN_JAG, max_straight: float = STRIKE_MAX_STRAIGHT,
                  cover: float = STRIKE_STRAIGHT_COVER,
                  min_spread: float = STRIKE_STRAIGHT_MIN_SPREAD,
                  min_rank: float = STRIKE_MIN_RANK) -> tuple[int, int] | None:
    """The top of a photo's brightest strike: where a bolt drawn from it starts.

    The bright structures narrower than ``ridge`` of the diagonal (the white
    top-hat of ``luminance`` with a square of that side) that stand out of the
    noise (:func:`noise_threshold` with ``k``, and at least ``min_ridge``) are
    joined into pieces (touching within a pixel). A strike is such a piece that
    spans at least ``min_span`` of the height and has a bolt's profile: its
    :func:`jaggedness` in a window of ``window`` of the diagonal is at least
    ``min_jag`` (beyond the papers: a dusk skyline's lit mast, a ruler-straight
    bright line, was taken for a strike and the bolt ran down it), and at most
    ``max_straight`` of its pixels lie on the picture's long straight edges
    (:func:`straight_edges` with segments that are edges along ``cover`` of their
    length; beyond the papers: a launch tower's lit truss, jagged as a mesh, was a
    strike on the rocket photo at 200-320 px, and a zelkova leaf's veins at 240 px).
    The straight-edge test is scale-aware: it counts only for a piece whose jag
    (:func:`jaggedness` times the window) is at least ``min_spread`` pixels, since a
    line zigzagging within ~1.5 px of its axis is one straight band at the Canny edges'
    resolution, and the cover leaves out the axis Hough finds through a fine zigzag's
    legs. A strike is also a light source (beyond the papers): its median luminance
    is above at least ``min_rank`` of the picture's pixels (a bolt 0.93-0.99; a leaf's
    midrib, lighter than its blade but darker than the paper around the leaf, 0.34: at
    200 px its veins' 0.85-px zigzag is below what the straight-edge test resolves, and
    it was a strike). The brightest
    strike (most top-hat brightness) counts, and its topmost pixel (the
    brightest of its top row) is the origin. None when the bright lines cover
    more than ``max_share`` of the picture (a textured photo: a portrait's
    hair, a lawn) or no piece is a strike (a bright dot, a straight line): then
    the bolt is the ordinary lightning metaphor, from the top of the picture's
    content.

    Parameters
    ----------
    luminance : (h, w) array_like
        Luminance in [0, 1].
    ridge, k, min_ridge, max_share, min_span, window, min_jag, max_straight, cover : float
        As above.
    min_spread : float
        Pixels (>= 0), as above.
    min_rank : float
        Share in [0, 1] of the picture's pixels a strike's median luminance is above.

    Returns
    -------
    (x, y) or None

    Examples
    --------
    >>> lum = np.full((60, 60), 0.2); y = np.arange(12, 55)
    >>> lum[y, 28 + np.abs((y - 12) % 8 - 4)] = 0.9  # a zigzag bright line from row 12 down
    >>> strike_origin(lum)
    (32, 12)
    >>> lum = np.full((60, 60), 0.2); lum[12:55, 30] = 0.9  # a straight one: no strike
    >>> strike_origin(lum) is None
    True
    """
    if not window > 0:
        raise ValueError(f"window must be > 0, got {window}")
    if not min_spread >= 0:
        raise ValueError(f"min_spread must be >= 0, got {min_spread}")
    if not 0 <= min_rank <= 1:
        raise ValueError(f"min_rank must be in [0, 1], got {min_rank}")
    top, strong = bright_ridges(luminance, ridge=ridge, k=k, min_ridge=min_ridge)
    lum = np.asarray(luminance, np.float64)
    h = top.shape[0]
    if not strong.any() or strong.mean() > max_share:
        return None
    lab, n = ndimage.label(ndimage.binary_dilation(strong), np.ones((3, 3), bool))
    lab = np.where(strong, lab, 0)
    score = ndimage.sum(top, lab, np.arange(1, n + 1))
    boxes = ndimage.find_objects(lab, n)
    span = np.array([0 if b is None else b[0].stop - b[0].start for b in boxes])
    sigma = window * float(np.hypot(*top.shape))
    straight = None
    for i in np.argsort(-score, kind="stable"):
        if span[i] < min_span * h:
            continue
        piece = lab[boxes[i]] == i + 1
        if np.mean(lum < np.median(lum[boxes[i]][piece])) < min_rank:
            continue  # darker than much of the picture: no light source (a leaf's vein)
        jag = jaggedness(piece, sigma)
        if jag < min_jag:
            continue
        if jag * sigma >= min_spread:  # its zigzag is resolved by the Canny edges
            if straight is None:
                straight = straight_edges(luminance, cover=cover)
            if straight[boxes[i]][piece].mean() > max_straight:  # a lit truss, not a bolt
                continue
        ys, xs = np.nonzero(piece)
        ys, xs = ys + boxes[i][0].start, xs + boxes[i][1].start
        row = ys == ys.min()
        k_top = int(np.argmax(top[ys[row], xs[row]]))
        return int(xs[row][k_top]), int(ys.min())
    return None


def photo_channel(weights, content, seed, *, length: float = STRIKE_PHOTO_LENGTH,
                  contrast: float = STRIKE_PHOTO_CONTRAST,
                  depth: float = STRIKE_PHOTO_DEPTH,
                  slack: float = STRIKE_PHOTO_SLACK) -> np.ndarray:
    """The path of a lightning bolt's main channel on a photo: from the seed down the picture.

    Beyond the papers: on a photo (content everywhere, no object to go
    through, :func:`~branchnb.dendrite.main_channel.strike_channel`) the bolt's widest
    channel was the child with the most tips, and it wandered along whatever edges led
    to most endpoints (round the border of a lightning photo, across a portrait).
    Here it is planned on its own: the least cumulative cost path on
    ``(g / median(g)) ** contrast``, ``g`` the weights blurred by 1 px (the
    lattice's noise averaged out, the picture's structure made cheaper: a
    lightning photo's bolts weigh ~0.6 of the median, 0.13 after the power),
    plus ``length`` times its mean per pixel of length (so
    it runs along the picture's bright or dark structure where that goes
    down, and straight where nothing does), from ``seed`` to a content pixel in
    the lower ``depth`` of the content below the seed: the deepest whose cost
    per pixel of descent is at most ``1 + slack`` times the least (with the
    least alone, the channel ended at the nearest cheap place: 0.60 of the height
    on cracked mud whose cracks run on to the bottom; where the picture's
    structure stops, going on straight through nothing costs more per pixel and
    the channel ends with it).

    Parameters
    ----------
    weights : (h, w) array_like
        Node weights of the lattice (>= 0).
    content : (h, w) array_like of bool
        Where there is something to draw.
    seed : (x, y)
        Start, in lattice pixels.
    length : float
        Cost (>= 0, in units of the mean weight) of a pixel of length.
    contrast : float
        Power (> 0) the weights are raised to.
    depth : float
        Share in (0, 1] of the content's height below the seed where the channel may end.
    slack : float
        How much more (>= 0) than the least cost per pixel of descent the chosen end
        may cost.

    Returns
    -------
    (K, 2) int64 ndarray
        Lattice ``(x, y)`` from the seed to the end (one row when there is no content below it).

    Examples
    --------
    >>> w = np.ones((60, 60)); w[:, 40] = 0.0  # a cheap line, off the seed's column
    >>> path = photo_channel(w, np.ones((60, 60), bool), (38, 0))
    >>> bool(path[-1, 1] > 55), bool(np.mean(path[:, 0] == 40) > 0.8)
    (True, True)
    """
    from .lattice import Lattice
    from .planner import plan

    w = np.asarray(weights, np.float64)
    c = np.asarray(content, bool)
    if w.ndim != 2 or c.shape != w.shape:
        raise ValueError(f"weights and content must be 2-D of one shape, got {w.shape}, {c.shape}")
    if not length >= 0:
        raise ValueError(f"length must be >= 0, got {length}")
    if not contrast > 0:
        raise ValueError(f"contrast must be > 0, got {contrast}")
    if not 0 < depth <= 1:
        raise ValueError(f"depth must be in (0, 1], got {depth}")
    if not slack >= 0:
        raise ValueError(f"slack must be >= 0, got {slack}")
    sx, sy = (int(round(float(v))) for v in seed)
    w = np.where(np.isfinite(w), w, np.nanmax(np.where(np.isfinite(w), w, np.nan)))
    g = ndimage.gaussian_filter(w, 1.0)
    g = (g / max(float(np.median(g)), 1e-12)) ** contrast
    mean = max(float(np.mean(g)), 1e-12)
    res = plan(Lattice(g + length * mean), (sx, sy), metric="cumulative")
    ys, xs = np.nonzero(c)
    below = ys > sy
    if not below.any():
        return np.array([[sx, sy]], np.int64)
    low = ys.max() - depth * (ys.max() - sy)
    pick = below & (ys >= low)
    ys, xs = ys[pick], xs[pick]
    cost = res.total_cost[ys * w.shape[1] + xs] / (ys - sy)
    cost = np.where(np.isfinite(cost), cost, np.inf)
    ok = np.flatnonzero(cost <= (1.0 + slack) * cost.min())
    k = int(ok[np.lexsort((cost[ok], -ys[ok]))[0]])  # the deepest; the cheapest of its row
    nodes = res.path(int(ys[k]) * w.shape[1] + int(xs[k]))
    return np.column_stack([nodes % w.shape[1], nodes // w.shape[1]]).astype(np.int64)


def straight_edges(luminance, *, length: float = STRIKE_STRAIGHT_LENGTH,
                   band: float = STRIKE_STRAIGHT_BAND, cover: float = 0.0) -> np.ndarray:
    """Where a picture has long straight edges (a mast, a tower, a horizon, a table's rim).

    Beyond the papers: the Canny edges of ``luminance`` (sigma 1 px, hysteresis between
    the 70th and 90th percentile of the gradient, so a dim night photo has edges too),
    their probabilistic Hough segments at least ``length`` of the diagonal long (gaps up
    to 3 px bridged) that are Canny edges along at least ``cover`` of their length (the
    axis Hough finds through a fine zigzag's legs is covered 0.49-0.67), drawn and
    widened by ``band`` of the diagonal (at least 1 px).
    Limits: an edge that lies exactly between two pixel columns (a synthetic, unblurred
    step) alternates between them in Canny and is found only in pieces; a bolt's straight
    legs longer than ``length`` count (on a 512-px lattice the NOAA bolts have 0.00-0.08
    of their pixels on these lines, procedural storms 0.00-0.13; a 60-px toy zigzag,
    blurred into a straight band, all of them; :func:`strike_origin` tells a strike
    with it only where the piece's zigzag is resolved).

    Parameters
    ----------
    luminance : (h, w) array_like
        In [0, 1].
    length : float
        Shortest segment, share of the diagonal (> 0).
    band : float
        Half-width of the band round each segment, share of the diagonal (>= 0).
    cover : float
        Least share (in [0, 1]) of a segment's pixels that are Canny edges; 0 keeps
        every segment (the side branches' use).

    Returns
    -------
    (h, w) bool ndarray

    Examples
    --------
    >>> lum = np.full((80, 80), 0.2); lum[:, 40:] = 0.8
    >>> m = straight_edges(lum)
    >>> bool(m[5:-5, 39:42].all()), bool(m[:, :36].any())
    (True, False)
    """
    from skimage.draw import line as draw_line
    from skimage.feature import canny
    from skimage.transform import probabilistic_hough_line

    lum = np.asarray(luminance, np.float64)
    if lum.ndim != 2:
        raise ValueError(f"luminance must be 2-D, got shape {lum.shape}")
    if not length > 0:
        raise ValueError(f"length must be > 0, got {length}")
    if not band >= 0:
        raise ValueError(f"band must be >= 0, got {band}")
    if not 0 <= cover <= 1:
        raise ValueError(f"cover must be in [0, 1], got {cover}")
    out = np.zeros(lum.shape, bool)
    if min(lum.shape) < 8 or np.ptp(lum) <= 1e-6:
        return out
    diag = float(np.hypot(*lum.shape))
    edges = canny(lum, sigma=1.0, low_threshold=0.7, high_threshold=0.9, use_quantiles=True)
    segs = probabilistic_hough_line(edges, threshold=10, line_length=max(int(length * diag), 10),
                                    line_gap=3, rng=0)
    for (x0, y0), (x1, y1) in segs:
        rr, cc = draw_line(y0, x0, y1, x1)
        if edges[rr, cc].mean() >= cover:
            out[rr, cc] = True
    r = max(int(round(band * diag)), 1)
    if out.any():
        out = ndimage.binary_dilation(out, ndimage.generate_binary_structure(2, 1), iterations=r)
    return out


def _path_spread(xy: np.ndarray, window: float) -> np.ndarray:
    """Per point of an ordered path, its spread (px) across its own direction within a
    Gaussian window of ``window`` px of arc length, less a digital line's pixel steps."""
    step = np.r_[0.0, np.hypot(*np.diff(xy, axis=0).T)]
    sig = window / max(float(np.mean(step[1:])), 1e-9)

    def mean(a):
        return ndimage.gaussian_filter1d(a, sig, mode="nearest")

    x, y = xy[:, 0] - xy[:, 0].mean(), xy[:, 1] - xy[:, 1].mean()
    mx, my = mean(x), mean(y)
    cxx, cyy, cxy = mean(x * x) - mx ** 2, mean(y * y) - my ** 2, mean(x * y) - mx * my
    tr, det = cxx + cyy, cxx * cyy - cxy ** 2
    small = tr / 2 - np.sqrt(np.maximum(tr ** 2 / 4 - det, 0.0))
    return np.sqrt(np.maximum(small - 1.0 / 12.0, 0.0))


def jag_channel(path, shape, *, window: float = STRIKE_JAG_WINDOW, min_jag: float = STRIKE_MIN_JAG,
                amplitude: float = STRIKE_JAG_AMPLITUDE, rng: int = 0) -> np.ndarray:
    """A lightning channel's straight stretches given a bolt's profile.

    Beyond the papers: on a photo without a strike of its own (no bolt to follow,
    :func:`strike_origin`) the main channel (:func:`photo_channel`) runs along the
    picture's structure, and where that is a straight man-made line (a rocket on its
    pad, a mast) or nothing at all (a clear sky), it came out ruler-straight, no bolt.
    Where the channel's spread across its direction within a window of ``window`` of
    the diagonal (as :func:`jaggedness` measures a line) is under ``min_jag`` of the
    window, it is displaced across its direction by a zigzag of up to three octaves
    (vertices every three windows, every window and every third of it along the
    channel, each shifted uniformly within ``amplitude`` of its spacing; an octave only
    where the straight stretch is at least one of its spacings long, so a short straight
    piece of a crack keeps near the crack and a rocket's full height wanders like a bolt),
    as the ordinary lightning metaphor's bolts turn at every scale; its jagged
    stretches, its start and its end stay where they are. The result is a chain of 8-neighbouring pixels, none twice.

    Parameters
    ----------
    path : (K, 2) array_like of int
        Lattice ``(x, y)``, start first (e.g. :func:`photo_channel`).
    shape : (h, w)
        The lattice's shape.
    window, min_jag : float
        As in :func:`strike_origin`.
    amplitude : float
        Largest shift (>= 0) of a zigzag vertex, as a share of the vertices' spacing.
    rng : int or numpy.random.Generator
        Seed of the zigzag.

    Returns
    -------
    (K', 2) int64 ndarray

    Examples
    --------
    >>> line = np.column_stack([np.full(150, 60), np.arange(150)])
    >>> bolt = jag_channel(line, (150, 120), rng=0)
    >>> mask = np.zeros((150, 120), bool); mask[bolt[:, 1], bolt[:, 0]] = True
    >>> bool(jaggedness(mask, 0.02 * np.hypot(150, 120)) > 0.05), bolt[0].tolist(), bolt[-1].tolist()
    (True, [60, 0], [60, 149])
    """
    from skimage.draw import line as draw_line

    q = np.asarray(path, np.int64).reshape(-1, 2)
    h, w = (int(v) for v in shape)
    if not amplitude >= 0:
        raise ValueError(f"amplitude must be >= 0, got {amplitude}")
    if not window > 0:
        raise ValueError(f"window must be > 0, got {window}")
    if len(q) < 4:
        return q.copy()
    rng = np.random.default_rng(rng)
    xy = q.astype(np.float64)
    sig = window * float(np.hypot(h, w))
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
    straight = _path_spread(xy, sig) < min_jag * sig
    per = max(float(s[-1]) / (len(s) - 1), 1e-9)
    lab, n = ndimage.label(straight)
    if n == 0:
        return q.copy()
    first = ndimage.minimum(s, lab, np.arange(1, n + 1))
    last = ndimage.maximum(s, lab, np.arange(1, n + 1))
    run = np.r_[0.0, last - first][lab]  # the length of the straight stretch a point is in
    ends = np.clip(np.minimum(s, s[-1] - s) / sig, 0.0, 1.0)  # start and end stay
    off = np.zeros(len(s))
    for spacing in (3.0 * sig, sig, sig / 3.0):
        # an octave where the straight stretch holds one of its spacings (a short straight
        # piece of a crack keeps near it; a rocket's full height wanders like a bolt)
        on = (run >= spacing).astype(np.float64)
        weight = np.clip(ndimage.gaussian_filter1d(on, 0.25 * sig / per, mode="nearest") * 2 - 0.5,
                         0.0, 1.0) * ends
        knots = np.arange(0.0, s[-1] + spacing, spacing)
        off += weight * np.interp(s, knots, rng.uniform(-1, 1, knots.size) * amplitude * spacing)
    if not off.any():
        return q.copy()
    tx = ndimage.gaussian_filter1d(xy[:, 0], sig / per, mode="nearest", order=1)
    ty = ndimage.gaussian_filter1d(xy[:, 1], sig / per, mode="nearest", order=1)
    norm = np.maximum(np.hypot(tx, ty), 1e-9)
    new = xy + (off / norm)[:, None] * np.column_stack([-ty, tx])
    new = np.rint(new).astype(np.int64)
    new[:, 0] = np.clip(new[:, 0], 0, w - 1)
    new[:, 1] = np.clip(new[:, 1], 0, h - 1)
    chain = [tuple(new[0])]
    for a, b in zip(new[:-1], new[1:]):
        rr, cc = draw_line(int(a[1]), int(a[0]), int(b[1]), int(b[0]))
        chain.extend(zip(cc[1:].tolist(), rr[1:].tolist()))
    out, seen = [], {}
    for px in chain:  # cut the loops: a pixel met again closes one
        if px in seen:
            for old in out[seen[px] + 1:]:
                del seen[old]
            del out[seen[px] + 1:]
            continue
        seen[px] = len(out)
        out.append(px)
    return np.asarray(out, np.int64)


# the side branches (split off by paper step; imported here for the old import path)
from .photo_side import side_branches, strike_region  # noqa: E402
