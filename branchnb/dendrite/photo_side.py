"""A lightning bolt on a photo: what its side branches follow, and where they may go.

Split from :mod:`~branchnb.dendrite.photo_strike` (where the bolt starts and how its main
channel runs); see its docstring for the measurements. Beyond the papers:
:func:`side_branches` gives the lattice and the endpoints of the side branches (the
edges that stand out of the picture's noise, or its other bolts; no highway along long
straight edges) and :func:`strike_region` the cone about the main channel they end in
on a photo without a strike of its own.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from .photo_strike import bright_ridges, edge_significance, long_pieces, straight_edges
from .stylize_params import (
    STRIKE_BAND,
    STRIKE_EDGE_NOISE,
    STRIKE_GLOW,
    STRIKE_MIN_PIECE,
    STRIKE_PENALTY,
    STRIKE_REGION_ANGLE,
    STRIKE_REGION_MARGIN,
    STRIKE_STRAIGHT_MAX_SHARE,
    STRIKE_STRAIGHT_PENALTY,
)

__all__ = ["side_branches", "strike_region"]


def strike_region(path, shape, *, angle: float = STRIKE_REGION_ANGLE,
                  margin: float = STRIKE_REGION_MARGIN) -> np.ndarray:
    """Where a lightning bolt's side branches may go: a cone about its main channel.

    Beyond the papers: each row at or below the channel's top holds the pixels within
    ``tan(angle) * (row - top) + margin * diagonal`` of the channel's column in that row
    (below the channel's end, of its last column), as a bolt's branches fork downwards
    and spread from where it starts; nothing above its top.

    Parameters
    ----------
    path : (K, 2) array_like of int
        The main channel, lattice ``(x, y)`` (e.g. :func:`~branchnb.dendrite.photo_strike.photo_channel`).
    shape : (h, w)
        The lattice's shape.
    angle : float
        Half-angle in degrees, in [0, 90).
    margin : float
        Share of the diagonal (>= 0) added to the half-width in every row.

    Returns
    -------
    (h, w) bool ndarray

    Examples
    --------
    >>> path = np.column_stack([np.full(50, 30), np.arange(10, 60)])
    >>> r = strike_region(path, (80, 60), angle=45.0, margin=0.0)
    >>> bool(r[9].any()), bool(r[20, 30]), bool(r[20, 41]), bool(r[20, 39]), bool(r[75, 0])
    (False, True, False, True, True)
    """
    q = np.asarray(path, np.int64).reshape(-1, 2)
    h, w = (int(v) for v in shape)
    if not 0 <= angle < 90:
        raise ValueError(f"angle must be in [0, 90), got {angle}")
    if not margin >= 0:
        raise ValueError(f"margin must be >= 0, got {margin}")
    if q.size == 0:
        return np.ones((h, w), bool)
    rows = np.arange(h)
    top = int(q[:, 1].min())
    sums = np.bincount(q[:, 1], q[:, 0].astype(np.float64), minlength=h)[:h]
    cnt = np.bincount(q[:, 1], minlength=h)[:h]
    have = cnt > 0
    cx = np.interp(rows, rows[have], sums[have] / cnt[have])  # flat past both ends
    half = np.tan(np.radians(angle)) * (rows - top) + margin * float(np.hypot(h, w))
    out = np.abs(np.arange(w)[None, :] - cx[:, None]) <= half[:, None]
    out[:top] = False
    return out


def side_branches(luminance, edges, weights, content, params, *, struck: bool,
                  rng: int = 0, region=None) -> tuple[np.ndarray, np.ndarray | None]:
    """The lattice weights and the endpoints of a lightning bolt's side branches on a photo.

    Beyond the papers (stippled on the importance, whose darkness term is high all
    over a night sky, the side branches wandered through the dark cloud, a faint
    scribble). On a lightning photo (``struck``: it has a strike,
    :func:`~branchnb.dendrite.photo_strike.strike_origin`) the endpoints are stippled on its long bright lines
    (:func:`~branchnb.dendrite.photo_strike.bright_ridges` in pieces of at least ``STRIKE_MIN_PIECE`` of the
    diagonal, :func:`~branchnb.dendrite.photo_strike.long_pieces`: its other bolts) and between them the lattice
    costs less where the picture is bright (``STRIKE_GLOW`` of the blurred
    luminance: through the lit cloud, not the dark sky); on other photos they are
    stippled on the edges that stand out of the picture's noise
    (:func:`~branchnb.dendrite.photo_strike.edge_significance` with ``STRIKE_EDGE_NOISE``). Where fewer than four
    pixels per endpoint qualify, the lattice and the endpoints stay as they were.
    The picture's long straight edges (:func:`~branchnb.dendrite.photo_strike.straight_edges`: a launch tower, a mast,
    a tripod's legs) hold no endpoint and cost ``STRIKE_STRAIGHT_PENALTY`` times the
    mean weight more, unless more than ``STRIKE_STRAIGHT_MAX_SHARE`` of the edges that
    stand out lie on them (a network of straight cracks is the structure to follow);
    the share of the side branches within 2 px of such lines fell on the rocket photo
    from 0.23 to 0.01 at 640 px (0.21 -> 0.14 at 320), on a launch pad 0.54-0.64 ->
    0.00-0.07, on text 0.50/0.36 -> 0.12/0.01.
    The picture's border band (``STRIKE_BAND``) costs ``STRIKE_PENALTY`` times the
    mean weight more, as a drawn object's outline does.

    Parameters
    ----------
    luminance : (h, w) array_like
        The picture's luminance on the lattice, in [0, 1].
    edges : (h, w) array_like
        Gradient strength on the lattice
        (:meth:`~branchnb.dendrite.stylization.Stylizer.edge_map`).
    weights : (h, w) array_like
        The lattice's node weights.
    content : (h, w) array_like of bool
        Where there is something to draw.
    params : StylizeParams
        Uses ``n_endpoints``, ``endpoint_gamma``, ``stipple_iterations``,
        ``cost_weight``, ``epsilon`` and ``noise``.
    struck : bool
        Whether the photo has a strike.
    rng : int
        Seed (>= 0): of the lattice noise (``rng``) and of the stippling (``rng + 1``).
    region : (h, w) array_like of bool, optional
        Where the side branches may end (:func:`strike_region`): no endpoint outside it.

    Returns
    -------
    weights : (h, w) float64 ndarray
        Node weights to plan the side branches on.
    ends : (E, 2) float64 ndarray or None
        Endpoints ``(x, y)`` on the lattice; None to keep the ones stippled on the importance.

    Examples
    --------
    >>> from branchnb.dendrite import StylizeParams
    >>> yy, xx = np.mgrid[0:64, 0:64]
    >>> lum = np.where(np.hypot(xx - 32, yy - 32) < 12, 0.9, 0.1)
    >>> w, ends = side_branches(lum, np.abs(np.gradient(lum)[1]), np.ones((64, 64)),
    ...                         np.ones((64, 64), bool), StylizeParams(n_endpoints=5), struck=False)
    >>> w.shape, ends.shape
    ((64, 64), (5, 2))
    """
    from .endpoints import place_endpoints
    from .lattice import node_weights
    from .main_channel import outline_band

    lum = np.asarray(luminance, np.float64)
    base = np.asarray(weights, np.float64)
    c = np.asarray(content, bool)
    if lum.ndim != 2 or base.shape != lum.shape or c.shape != lum.shape:
        raise ValueError(f"luminance, weights and content must be 2-D of one shape, got "
                         f"{lum.shape}, {base.shape}, {c.shape}")
    n = int(params.n_endpoints)
    if struck:
        top, strong = bright_ridges(lum)
        strong = long_pieces(strong, STRIKE_MIN_PIECE)
        sig = np.where(strong, np.clip(top / max(float(top[strong].max(initial=0.0)), 1e-6),
                                       0.0, 1.0), 0.0)
        if (sig > 0).sum() >= 4 * n:
            glow = STRIKE_GLOW * ndimage.gaussian_filter(lum, 0.01 * np.hypot(*lum.shape))
            base = node_weights(params.cost_weight * (1.0 - np.maximum(np.sqrt(sig), glow)),
                                epsilon=params.epsilon, noise=params.noise, rng=rng)
    else:
        sig = edge_significance(edges, STRIKE_EDGE_NOISE)
    # long straight edges (a launch tower, a mast) neither hold endpoints nor make a
    # cheap highway: the branches ran ruler-straight down them (beyond the paper)
    line = straight_edges(lum)
    edge = sig > 0
    # unless they are most of what stands out (a network of straight cracks): then
    # they are the picture's structure to follow
    if line.any() and (line & edge).sum() <= STRIKE_STRAIGHT_MAX_SHARE * max(edge.sum(), 1):
        sig = np.where(line, 0.0, sig)
        base = base + float(np.mean(base)) * STRIKE_STRAIGHT_PENALTY * line
    if region is not None:
        reg = np.asarray(region, bool)
        if reg.shape != lum.shape:
            raise ValueError(f"region must have the luminance's shape {lum.shape}, got {reg.shape}")
        sig = np.where(reg, sig, 0.0)
    ends = None
    if (sig > 0).sum() >= 4 * n:
        ends = place_endpoints(sig, n, gamma=params.endpoint_gamma, floor=0.0, threshold=1e-6,
                               iterations=params.stipple_iterations, rng=rng + 1)
    near = outline_band(c, STRIKE_BAND)[1]
    return base + float(np.mean(base)) * STRIKE_PENALTY * near, ends
