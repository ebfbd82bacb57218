"""A lightning bolt on a photo: what its side branches follow, and where they may go.

Split from :mod:`~branchnb.dendrite.photo_strike` (where the bolt starts and how its main
channel runs); see its docstring for the measurements. Beyond the papers:
:func:`side_branches` gives the lattice and the endpoints of the side branches (the
edges that stand out of the picture's noise, or its other bolts; no highway along long
straight edges) and :func:`strike_region` the cone about the main channel they end in
on a photo without a strike of its own.

Side branches as short as a real bolt's (beyond the papers; ``STRIKE_SIDE_LENGTH``,
``STRIKE_SIDE_ANGLE``, :func:`_short_sides`): on a photo without a strike each side
branch is cut back to 0.3 of the main channel's length (and to the channel's length
below its fork), and a tip more than 60 degrees off straight down from its fork is
dropped; forking at the channel's top, branches ran down beside it to the ground.
``python -m branchnb.dendrite._side_spread`` (320 / 640 px, before -> after): longest
side branch over the main channel's length, rocket 1.31 / 1.52 -> 0.30 / 0.30, text
0.64 / 1.23 -> 0.21 / 0.21, clock 0.68 / 0.93 -> 0.30, cup 0.83 / 0.97 -> 0.30, cat
0.71 / 0.76 -> 0.30, astronaut 1.28 / 0.90 -> 0.30, camera man 0.92 / 1.17 -> 0.30,
cracked mud 1.22 / 1.20 -> 0.30 (the procedural storms' 0.19-0.37); mean lateral reach
(share of the diagonal) 0.115 / 0.110 -> 0.035 / 0.029, 0.062 / 0.071 -> 0.022 / 0.020,
0.069 / 0.072 -> 0.053 / 0.039, 0.105 / 0.086 -> 0.040 / 0.037, 0.067 / 0.068 -> 0.042 /
0.046, 0.117 / 0.119 -> 0.044 / 0.049, 0.071 / 0.099 -> 0.047 / 0.044, 0.115 / 0.130 ->
0.053 / 0.052 (a bolt ~0.03); the share outside a 60-degree cone below the fork moved
both ways (text 0.76 / 0.85 -> 0.14 / 0.24, cup 0.38 / 0.35 -> 0.22 / 0.21; clock 640
0.10 -> 0.37, cracked mud 0.05 / 0.09 -> 0.18 / 0.30: a cut branch keeps its sideways
start). Lightning photos (a strike) are unchanged: there the side branches follow the
picture's own bolts.
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
    STRIKE_SIDE_ANGLE,
    STRIKE_SIDE_LENGTH,
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


def _path_lengths(parent: np.ndarray, shape) -> tuple[np.ndarray, np.ndarray]:
    """Per lattice node, the length (px) of its planned path back to its seed, and that seed.

    Pointer doubling: log2(depth) passes over the nodes.
    """
    w = int(shape[1])
    par = np.asarray(parent, np.int64)
    idx = np.arange(len(par))
    up = np.maximum(par, 0)
    acc = np.where(par >= 0, np.hypot(idx % w - up % w, idx // w - up // w), 0.0)
    root = np.where(par >= 0, par, idx)
    anc = par.copy()
    while (anc >= 0).any():
        live = anc >= 0
        a = np.maximum(anc, 0)
        acc = acc + np.where(live, acc[a], 0.0)
        root = np.where(live, root[a], root)
        anc = np.where(live, anc[a], -1)
    return acc, root


def _short_sides(plan_result, ends, path, length: float = STRIKE_SIDE_LENGTH,
                 angle: float = STRIKE_SIDE_ANGLE) -> np.ndarray:
    """Tips of side branches as a real bolt's: short, forking downwards (beyond the papers).

    ``plan_result`` was planned with every pixel of the channel ``path`` a seed, so an
    endpoint's path there is its side branch, from its fork on the channel. Each is cut
    back to at most ``length`` times the channel's length, and to no more than the
    channel's length below its fork (a bolt's branches shorten toward the ground); tips
    more than ``angle`` degrees off straight down from their fork, or within 2 px of it,
    are dropped.

    Returns
    -------
    (F, 2) float64 ndarray
        The new tips ``(x, y)`` (lattice), unique.
    """
    q = np.asarray(path, np.int64).reshape(-1, 2)
    e = np.asarray(ends, np.float64).reshape(-1, 2)
    h, w = plan_result.shape
    arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(q, axis=0).T))]
    along = np.full(h * w, arc[-1])
    along[q[:, 1] * w + q[:, 0]] = arc  # arc length of each channel pixel from the top
    ex, ey = np.clip(np.rint(e[:, 0]), 0, w - 1), np.clip(np.rint(e[:, 1]), 0, h - 1)
    node = (ey * w + ex).astype(np.int64)
    acc, root = _path_lengths(plan_result.parent, (h, w))
    cap = np.minimum(length * max(arc[-1], 1.0), arc[-1] - along[root[node]])
    par = np.asarray(plan_result.parent, np.int64)
    while True:  # walk each tip back until its branch is short enough
        far = (acc[node] > cap) & (par[node] >= 0)
        if not far.any():
            break
        node = np.where(far, par[node], node)
    dx, dy = node % w - root[node] % w, node // w - root[node] // w
    keep = (np.degrees(np.arctan2(np.abs(dx), dy)) <= angle) & (np.hypot(dx, dy) > 2.0)
    tip = np.unique(node[keep])
    return np.column_stack([tip % w, tip // w]).astype(np.float64)


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
