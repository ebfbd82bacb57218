"""The main channel of a dendrite: find it, measure its loops, cut them.

A lightning bolt drawn from an image (:meth:`~branchnb.dendrite.stylization.Stylizer.run`
with ``metaphor="lightning"``) is widest along its *main channel*: from the seed,
always down the child that carries the most tips. Least-cost paths follow the
picture's edges, so where the seed sits in a thin, ragged part (the tip leaflets
of a fern frond) the main channel zigzags back and forth along the outline in
hairpins a few pixels apart: drawn 6 px wide, a bright knot. Beyond the papers
(Xu & Mould 2007; Long & Mould 2009), :func:`shortcut_loops` joins the two legs of
every such hairpin on the main channel by a short straight step, so the channel
runs on and the hairpin, if other branches still use it, becomes a thin fork.
Cut short, the main channel held less of the ink, so :func:`widen_main_path`
keeps it bright down to its last fork, as a strike's return stroke is.

On a drawn object on a plain background (a clip-art tree, a filled shape) the
tips sit on the outline and the widest channel ran round the silhouette;
:func:`strike_channel` plans the main channel down through the object, off its
outline (:func:`outline_band`), and the stylization makes it a highway the
other branches fork off.
"""
from __future__ import annotations

import dataclasses

import numpy as np
from scipy import ndimage

from .channel_jag import CHANNEL_JAG, OUTLINE_JAG, _ground, _rough, _taut, _thin, _thin_rough
from .dendrite import Dendrite, build_dendrite
from .photo_strike import photo_channel  # noqa: F401  (re-exported: it was defined here)
from .planner import PlanResult
from .strike_part import STEM_MAX_WIDTH, STEM_MIN_DEPTH, _seed_part, _stem_end  # noqa: F401
from .stylize_params import (
    LIGHTNING_MAIN_EXPONENT,
    LIGHTNING_SEED_BLUR,
    LIGHTNING_SEED_DENSITY,
    STRIKE_BAND,
    STRIKE_MAX_COVER,
    STRIKE_PENALTY,
)

__all__ = ["main_path", "path_loops", "outline_band", "shortcut_loops", "silhouette", "straighten",
           "channel_plan", "with_channel", "strike_channel", "strike_weights",
           "wide_top", "widen_main_path"]


def main_path(dendrite: Dendrite) -> np.ndarray:
    """Tree indices of the main channel: from the root down the child with most tips.

    A dendrite whose main channel was planned on its own (``dendrite.main``,
    :func:`channel_plan`) returns that channel as it is.

    The walk stops at its node farthest from the root, and before a last hook:
    where, in its last fifth, it heads more than 120 degrees away from its
    overall direction (root to end) over 3 % of the diagonal (read on samples
    every 0.5 % of the diagonal), it ends at the hook's start, up to 4 times
    (beyond the
    papers: the child with most tips can turn back at the end, e.g. from a
    lightning bolt's foot up the other side of a drawn object's outline or at a
    tripod's foot; on 16 of 18 test inputs it turned by more than 120 degrees
    in its last fifth).

    Parameters
    ----------
    dendrite : Dendrite
        A tree with one root (the first root is used otherwise).

    Returns
    -------
    (K,) int64 ndarray
        Node indices, root first.

    Examples
    --------
    >>> from branchnb.dendrite import build_dendrite, make_lattice, plan
    >>> d = build_dendrite(plan(make_lattice(np.zeros((30, 30)), rng=0), (15, 0)),
    ...                    [(3, 29), (5, 28), (27, 29)])
    >>> p = main_path(d); int(p[0]), bool(d.points[p[-1], 0] < 15)
    (0, True)
    """
    if isinstance(dendrite, Dendrite) and dendrite.main is not None and dendrite.main.size:
        return dendrite.main.copy()  # planned on its own (a bolt on a photo)
    path = _walk(dendrite)
    if path.size == 0:
        return path
    # up to the node farthest from the root: past it the channel turns back (up the
    # other side of a silhouette from its foot)
    pts = dendrite.points[path]
    far = int(np.argmax(np.hypot(*(pts - pts[0]).T)))
    path, pts = path[:far + 1], pts[:far + 1]
    # and without a last hook against its overall direction (at a tripod's foot)
    size = dendrite.shape if dendrite.shape is not None else np.ptp(pts, axis=0)[::-1] + 1
    diag = float(np.hypot(*size))
    for _ in range(_HOOK_ROUNDS):
        cut = _hook(pts, diag)
        if cut is None:
            break
        path, pts = path[:cut + 1], pts[:cut + 1]
    return path


#: Length (share of the diagonal) over which :func:`main_path` reads the direction of its end.
_HOOK_WINDOW = 0.03
#: Most hooks :func:`main_path` cuts off its end (a cut moves the end, and the new end can hook).
_HOOK_ROUNDS = 4
#: Spacing (share of the diagonal) of the samples :func:`main_path` reads its end's direction on.
_HOOK_STEP = 0.005


def _hook(pts: np.ndarray, diag: float) -> int | None:
    """The node where a polyline's last hook starts, or None.

    On samples every ``_HOOK_STEP`` of ``diag`` along the polyline, the
    direction over ``_HOOK_WINDOW`` of ``diag`` of every sample in the last
    fifth against the direction from the first sample to the last: the
    first that heads more than 120 degrees away starts the hook, which is
    cut at the node at or before that sample's window start.
    """
    arc = _arc(pts)
    step = _HOOK_STEP * diag
    k = int(round(_HOOK_WINDOW / _HOOK_STEP))
    if len(pts) < 3 or not step > 0 or arc[-1] <= 2 * _HOOK_WINDOW * diag:
        return None
    s = np.arange(0.0, arc[-1], step)
    q = np.column_stack([np.interp(s, arc, pts[:, 0]), np.interp(s, arc, pts[:, 1])])
    over = q[-1] - q[0]
    if len(q) <= k or not np.hypot(*over) > 0:
        return None
    v = q[k:] - q[:-k]
    cos = (v @ over) / np.maximum(np.hypot(*v.T) * np.hypot(*over), 1e-12)
    first = max(int(0.8 * len(q)) - k, 0)
    against = np.flatnonzero(cos[first:] < -0.5)
    if against.size == 0:
        return None
    start = s[first + int(against[0])]
    return max(int(np.searchsorted(arc, start, side="right")) - 1, 1)


def _walk(dendrite: Dendrite) -> np.ndarray:
    """From the root down the child with most tips, to a tip (:func:`main_path` uncut)."""
    if not isinstance(dendrite, Dendrite):
        raise TypeError(f"dendrite must be a Dendrite, got {type(dendrite).__name__}")
    if dendrite.n_nodes == 0:
        return np.zeros(0, np.int64)
    parent = dendrite.parent
    n = dendrite.leaf_count()
    # the child with the most tips of every node (ties: the first child)
    best = np.full(dendrite.n_nodes, -1, np.int64)
    child = np.flatnonzero(parent >= 0)
    order = child[np.lexsort((-child, n[child]))]  # ascending tips: the best child is written last
    best[parent[order]] = order
    node = int(np.flatnonzero(parent < 0)[0])
    path = [node]
    while best[node] >= 0:
        node = int(best[node])
        path.append(node)
    return np.asarray(path, np.int64)


def _arc(points: np.ndarray) -> np.ndarray:
    return np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(points, axis=0).T))])


def path_loops(points, *, reach: float) -> tuple[float, float]:
    """How much a polyline loops: its worst detour and its tortuosity.

    Parameters
    ----------
    points : (K, 2) array_like
        The polyline, ``(x, y)``.
    reach : float
        Distance (> 0) under which two points count as close; e.g. 1 % of
        the image's diagonal.

    Returns
    -------
    detour : float
        The largest ``arc(i, j) / max(chord(i, j), reach)`` over pairs of
        points: the length of the way round between two points, in units of
        how close they are (about 1-2 for a jagged but straight path, 5 or
        more for a hairpin or a loop).
    tortuosity : float
        Length over the distance between the ends (1 for a straight line).

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 50)
    >>> ring = np.column_stack([10 * np.cos(t), 10 * np.sin(t)])
    >>> [round(v, 1) for v in path_loops(np.array([[0, 0], [0, 10], [0, 20]]), reach=1.0)]
    [1.0, 1.0]
    >>> path_loops(ring, reach=1.0)[0] > 30
    True
    """
    p = np.asarray(points, np.float64)
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"points must be (K, 2), got shape {p.shape}")
    if not reach > 0:
        raise ValueError(f"reach must be > 0, got {reach}")
    if len(p) < 2:
        return 1.0, 1.0
    arc = _arc(p)
    worst = 1.0
    for i in range(len(p) - 1):  # rows of the pair matrix, one at a time (memory stays O(K))
        chord = np.hypot(*(p[i + 1:] - p[i]).T)
        worst = max(worst, float(np.max((arc[i + 1:] - arc[i]) / np.maximum(chord, reach))))
    end = float(np.hypot(*(p[-1] - p[0])))
    return worst, float(arc[-1] / max(end, 1e-9))


def shortcut_loops(plan_result: PlanResult, dendrite: Dendrite, *, reach: float,
                   ratio: float = 2.5) -> PlanResult:
    """Cut the hairpins of the main channel out of the planner's path tree.

    Walking the main channel (:func:`main_path`, past its farthest node) from the root, at each node
    ``i`` the farthest later node ``j`` within ``reach`` of it is taken as a
    hairpin's other leg when the channel's way round is long, ``arc(i, j) >
    ratio * chord(i, j)`` and ``arc(i, j) - chord(i, j) > reach``; then ``j``'s
    parent becomes ``i`` (a straight step of at most ``reach``) and the walk
    goes on from ``j``. Every endpoint below ``j`` now runs through the step;
    the hairpin stays only where other endpoints still use it, as a fork.

    Parameters
    ----------
    plan_result : PlanResult
        The planner's output the dendrite was traced in
        (:func:`~branchnb.dendrite.dendrite.build_dendrite`).
    dendrite : Dendrite
        The dendrite traced from it.
    reach : float
        Longest straight step (lattice px, > 0).
    ratio : float
        How much longer than the step the way round must be (> 1).

    Returns
    -------
    PlanResult
        A copy with a new ``parent`` array (the same object when nothing is
        cut); trace the same endpoints in it again.

    Examples
    --------
    >>> from branchnb.dendrite import build_dendrite, make_lattice, plan
    >>> w = np.full((30, 30), 50.0); w[2:28, 14:16] = 0.0; w[27, 14:22] = 0.0; w[2:28, 21] = 0
    >>> res = plan(make_lattice(w, rng=0), (21, 2))  # a U: down one leg, up the other
    >>> d = build_dendrite(res, [(14, 2)])
    >>> cut = build_dendrite(shortcut_loops(res, d, reach=8.0), [(14, 2)])
    >>> int(d.n_nodes) > 40, int(cut.n_nodes) < 12
    (True, True)
    """
    if not isinstance(plan_result, PlanResult):
        raise TypeError(f"plan_result must be a PlanResult, got {type(plan_result).__name__}")
    if not isinstance(dendrite, Dendrite):
        raise TypeError(f"dendrite must be a Dendrite, got {type(dendrite).__name__}")
    if not reach > 0:
        raise ValueError(f"reach must be > 0, got {reach}")
    if not ratio > 1:
        raise ValueError(f"ratio must be > 1, got {ratio}")
    path = _walk(dendrite)  # the whole walk: a hairpin's second leg climbs back
    p = dendrite.points[path]
    arc = _arc(p)
    parent = None
    i = 0
    while i < len(path) - 2:
        chord = np.hypot(*(p[i + 2:] - p[i]).T)
        near = np.flatnonzero(chord <= reach)
        if near.size:
            k = int(near[-1])
            j = i + 2 + k
            way = arc[j] - arc[i]
            if way > ratio * chord[k] and way - chord[k] > reach:
                if parent is None:
                    parent = plan_result.parent.copy()
                parent[dendrite.nodes[path[j]]] = dendrite.nodes[path[i]]
                i = j
                continue
        i += 1
    if parent is None:
        return plan_result
    return dataclasses.replace(plan_result, parent=parent)


def straighten(plan_result: PlanResult, dendrite: Dendrite, endpoints, *, reach: float,
               ratio: float = 2.5, rounds: int = 4) -> Dendrite:
    """:func:`shortcut_loops` and trace ``endpoints`` again, up to ``rounds`` times
    (a cut can make another child the widest, whose channel may loop too).

    Parameters
    ----------
    plan_result : PlanResult
        The planner's output ``dendrite`` was traced in.
    dendrite : Dendrite
        Traced from ``endpoints`` in ``plan_result``.
    endpoints : array_like
        The endpoints it was traced from (:func:`~branchnb.dendrite.dendrite.build_dendrite`).
    reach, ratio : float
        As in :func:`shortcut_loops`.
    rounds : int
        Most rounds (>= 1).

    Returns
    -------
    Dendrite
        ``dendrite`` itself when its main channel has no hairpin.

    Examples
    --------
    >>> from branchnb.dendrite import build_dendrite, make_lattice, plan
    >>> res = plan(make_lattice(np.zeros((30, 30)), rng=0), (15, 0))
    >>> d = build_dendrite(res, [(15, 29)])
    >>> straighten(res, d, [(15, 29)], reach=8.0) is d
    True
    """
    if int(rounds) < 1:
        raise ValueError(f"rounds must be >= 1, got {rounds}")
    for _ in range(int(rounds)):
        cut = shortcut_loops(plan_result, dendrite, reach=reach, ratio=ratio)
        if cut is plan_result:
            break
        plan_result, dendrite = cut, build_dendrite(cut, endpoints)
    return dendrite


def wide_top(content, blur: float, density: float) -> tuple[int, int] | None:
    """The top of the wide part of a content mask: where a lightning bolt starts.

    Content pixels count where their neighbourhood (a Gaussian of ``blur`` times
    the mask's diagonal) holds at least ``density`` of the densest one's share
    of content; among those within 5 % of the mask's height below the topmost,
    the one nearest their median column (beyond the paper: the topmost content
    pixel was often a thin tip, a fern's leaflets or an ear, and the widest
    channel started with a knot in it).

    Parameters
    ----------
    content : (h, w) array_like of bool
        Where there is something to draw.
    blur : float
        Blur (> 0) as a share of the mask's diagonal.
    density : float
        Share in [0, 1] of the largest blurred content.

    Returns
    -------
    (x, y) or None
        A content pixel; None when the mask is empty.

    Examples
    --------
    >>> m = np.zeros((100, 100), bool); m[50:90, 20:80] = True; m[5:50, 48:51] = True
    >>> wide_top(m, 0.03, 0.5)[1] >= 45
    True
    """
    c = np.asarray(content, bool)
    if c.ndim != 2:
        raise ValueError(f"content must be 2-D, got shape {c.shape}")
    if not blur > 0 or not 0.0 <= density <= 1.0:
        raise ValueError(f"blur must be > 0 and density in [0, 1], got {blur}, {density}")
    ys, xs = np.nonzero(c)
    if ys.size == 0:
        return None
    mass = ndimage.gaussian_filter(c.astype(np.float32), blur * float(np.hypot(*c.shape)),
                                   mode="constant")
    wide = mass[ys, xs] >= density * float(mass.max())
    if wide.any():  # the maximum is on or next to content, but a 1-px mask may miss it
        ys, xs = ys[wide], xs[wide]
    band = ys <= ys.min() + 0.05 * c.shape[0]
    xb, yb = xs[band], ys[band]
    k = int(np.argmin(np.abs(xb - np.median(xb)) + 1e-3 * yb))  # on a content pixel
    return int(xb[k]), int(yb[k])


def widen_main_path(dendrite: Dendrite, min_width: float, max_width: float, *,
                    exponent: float = LIGHTNING_MAIN_EXPONENT, side: float = 1.0) -> Dendrite:
    """Widths of the main channel from its share of the tips, with a larger exponent.

    Beyond the papers: with widths from the share of the tips a channel
    carries (:func:`~branchnb.dendrite.thickness.branch_thickness`,
    ``mode="share"``, ``width = min_width + (max_width - min_width) * q ** (1 / 2)``,
    ``q = (n_tips - 1) / (N - 1)``) the main channel (:func:`main_path`) thinned
    at every fork, and on a busy picture (a camera man, 54 tips) it faded into
    its side branches a third of the way down, holding under a third of the
    ink once :func:`shortcut_loops` had cut its hairpins. A strike's return
    stroke stays bright far down: along the main channel, from the root to
    its node farthest from the root, the width is at least ``min_width +
    (max_width - min_width) * q ** (1 / exponent)``; its last twig (one tip,
    ``q = 0``) stays thin, and so does any stretch past the farthest node,
    where the channel turns back (a hook at its end, a climb up a rocket
    beside a portrait); side branches keep their widths.

    Parameters
    ----------
    dendrite : Dendrite
        The tree with its widths (``radius``); not modified.
    min_width, max_width : float
        Widths (``0 <= min_width <= max_width``) of a tip and of the root, as
        given to :func:`~branchnb.dendrite.thickness.branch_thickness`.
    exponent : float
        Exponent (> 0) of the main channel's share;
        ``LIGHTNING_MAIN_EXPONENT`` = 8 by default (2 is the share rule of
        every other channel: no change). With 4 the camera man's main path
        held 0.34 of the ink (256 px), with 8 0.35, at full width to its tip
        0.39 (with its last twig lit too).
    side : float
        Factor in [0, 1] on the side branches' width above ``min_width``
        (1: unchanged; a bolt on a photo, whose planned channel has many
        long side branches, uses ``STRIKE_PHOTO_SIDE``).

    Returns
    -------
    Dendrite
        A copy with the main channel's radius raised where it was below that.

    Examples
    --------
    >>> from branchnb.dendrite import branch_thickness, build_dendrite, make_lattice, plan
    >>> d = build_dendrite(plan(make_lattice(np.zeros((30, 30)), rng=0), (15, 0)),
    ...                    [(3, 29), (5, 28), (27, 29), (25, 29), (15, 29)])
    >>> d = branch_thickness(d, mode="share", min_width=1.0, max_width=5.0)
    >>> w = widen_main_path(d, 1.0, 5.0)
    >>> bool(np.all(w.radius >= d.radius)), bool(w.radius.sum() > d.radius.sum())
    (True, True)
    """
    if not isinstance(dendrite, Dendrite):
        raise TypeError(f"dendrite must be a Dendrite, got {type(dendrite).__name__}")
    if not (np.isfinite(min_width) and np.isfinite(max_width) and 0 <= min_width <= max_width):
        raise ValueError(f"min_width and max_width must satisfy 0 <= min_width <= max_width, "
                         f"got {min_width}, {max_width}")
    if not (np.isfinite(exponent) and exponent > 0):
        raise ValueError(f"exponent must be > 0, got {exponent}")
    if not 0.0 <= side <= 1.0:
        raise ValueError(f"side must be in [0, 1], got {side}")
    path = main_path(dendrite)
    if path.size < 2:
        return dendrite
    n = np.maximum(dendrite.leaf_count()[path], 1.0)
    q = (n - 1.0) / max(float(n.max()) - 1.0, 1.0)
    floor = 0.5 * (min_width + (max_width - min_width) * q ** (1.0 / exponent))
    # up to the node farthest from the root: where the channel turns back (up a rocket
    # beside a portrait, a hook at a tripod's foot) it keeps the share rule's width
    far = int(np.argmax(np.hypot(*(dendrite.points[path] - dendrite.points[path[0]]).T)))
    path, floor = path[:far + 1], floor[:far + 1]
    radius = dendrite.radius.astype(np.float64, copy=True)
    if side < 1.0:
        off = np.ones(dendrite.n_nodes, bool)
        off[path] = False
        lo = 0.5 * min_width
        radius[off] = np.where(radius[off] > lo, lo + side * (radius[off] - lo), radius[off])
    radius[path] = np.maximum(radius[path], floor)
    return dendrite.with_radius(radius)


def silhouette(content) -> np.ndarray:
    """The filled outline of a content mask: what a drawn object covers.

    Closed over 1 % of the mask's diagonal (a line drawing's gaps) and with its
    holes filled (a star drawn as an outline covers its inside too).

    Parameters
    ----------
    content : (h, w) array_like of bool
        Where there is something to draw.

    Returns
    -------
    (h, w) bool ndarray

    Examples
    --------
    >>> m = np.zeros((40, 40), bool); m[5:35, 5] = m[5:35, 34] = m[5, 5:35] = m[34, 5:35] = True
    >>> int(silhouette(m).sum())
    900
    """
    c = np.asarray(content, bool)
    if c.ndim != 2:
        raise ValueError(f"content must be 2-D, got shape {c.shape}")
    r = max(1, int(round(0.01 * float(np.hypot(*c.shape)))))
    disk = np.hypot(*np.mgrid[-r:r + 1, -r:r + 1]) <= r
    closed = ndimage.binary_closing(np.pad(c, r), disk)[r:-r, r:-r] | c
    return ndimage.binary_fill_holes(closed)


def outline_band(content, band: float = STRIKE_BAND) -> tuple[np.ndarray, np.ndarray, float]:
    """A drawn object's silhouette, the band inside its outline, and how filled it is.

    Parameters
    ----------
    content : (h, w) array_like of bool
        Where there is something to draw.
    band : float
        Depth of the band (share of the diagonal, >= 0).

    Returns
    -------
    sil : (h, w) bool ndarray
        The :func:`silhouette`.
    near : (h, w) float64 ndarray
        1 on the silhouette's outline and outside it, falling linearly to 0 at
        depth ``band`` inside it.
    fill : float
        Share of the silhouette deeper than ``band`` that is content: ~1 for a
        filled shape, ~0 for an outline drawing (a star drawn as a line).

    Examples
    --------
    >>> m = np.zeros((60, 60), bool); m[10:50, 10:50] = True
    >>> sil, near, fill = outline_band(m, 0.05)
    >>> float(near[10, 30]), float(near[30, 30]), float(near[0, 0]), fill
    (1.0, 0.0, 1.0, 1.0)
    """
    if not band >= 0:
        raise ValueError(f"band must be >= 0, got {band}")
    c = np.asarray(content, bool)
    sil = silhouette(c)
    depth = ndimage.distance_transform_edt(np.pad(sil, 1))[1:-1, 1:-1]
    reach = max(band * float(np.hypot(*c.shape)), 1e-9)
    near = np.where(sil, np.clip(1.0 - (depth - 1.0) / reach, 0.0, 1.0), 1.0)
    inner = sil & (depth > reach)
    return sil, near, float(c[inner].mean()) if inner.any() else 0.0


def _channel_end(sil: np.ndarray) -> tuple[tuple[int, int] | None, bool]:
    """Where the main channel through a silhouette ends, and whether that is a stem's foot:
    the bottom of its wide part (:func:`wide_top` upside down), or :func:`_stem_end` below it."""
    end = wide_top(sil[::-1], LIGHTNING_SEED_BLUR, LIGHTNING_SEED_DENSITY)
    if end is None:
        return None, False
    end = (end[0], sil.shape[0] - 1 - end[1])
    foot = _stem_end(sil, end)
    return foot, foot != end


def strike_channel(weights, content, seed, *, band: float = STRIKE_BAND,
                   penalty: float = STRIKE_PENALTY, jag: float = CHANNEL_JAG,
                   rng=None) -> np.ndarray:
    """The path of a lightning bolt's main channel: from the seed down through the object.

    Beyond the papers: a bolt's widest channel was the child with the most tips,
    and on a flat-shaded drawing (a clip-art poplar, a filled ellipse) the tips
    sit on the outline, the cheapest way along the picture's edges, so the
    bright channel ran round the whole silhouette instead of down through it.
    Here the main channel is planned on its own: the least cumulative cost
    path on ``weights`` from ``seed`` to the bottom of the object's wide part
    (:func:`wide_top` of the mask turned upside down), or the foot of a thin stem
    hanging below it (:func:`_stem_end`: a tree's trunk), inside the object's
    :func:`silhouette`, with ``penalty`` times the mean weight added within
    ``band`` of the diagonal of its outline (:func:`outline_band`), so it keeps
    off the outline and follows the object's middle in thin parts; outside the
    silhouette every weight is 10 times the mean. Beyond the papers (dendrite33):
    inside the silhouette the weights are multiplied by log-normal noise of equal
    strength at every scale from 1 px to 4 % of the diagonal (``jag`` the std of its
    log, fading out towards the outline): the lattice's per-pixel noise averages out
    along a long path, and the channel through a crown was a ruler-straight line
    (tortuosity 1.08, 10-12 deg mean turn per 10 px against 35-39 for a bolt on a
    plain canvas; ``python -m branchnb.dendrite._bolt_shape_check``). Beyond the papers
    (dendrite34): on a picture of several separate objects the channel runs through the
    one the seed lies over (:func:`~branchnb.dendrite.strike_part._seed_part`; the others
    count as ground), in thin parts (a pole) the outline band keeps ``OUTLINE_JAG`` of the
    noise, and the ground costs :func:`~branchnb.dendrite.channel_jag._ground` times more
    (rough at every scale, growing off the objects): the channel ran from a street lamp
    straight across the sky to a toadstool's foot (``python -m
    branchnb.dendrite._multi_bolt_check``). Beyond the papers (dendrite38): in thin parts
    (:func:`~branchnb.dendrite.channel_jag._thin`) the whole cost carries noise whose scales
    follow the part's width
    (:func:`~branchnb.dendrite.channel_jag._thin_rough`): down a pole or a mast the channel
    turned 17-24 deg per 10 px against 35-40 in a wide blob (``python -m
    branchnb.dendrite._thin_branch_check``).

    Parameters
    ----------
    weights : (h, w) array_like
        Node weights of the lattice (>= 0).
    content : (h, w) array_like of bool
        Where there is something to draw (importance at or above the threshold).
    seed : (x, y)
        Start, in lattice pixels.
    band : float
        Depth (share of the diagonal, >= 0) of the outline band the channel avoids.
    penalty : float
        Extra weight (>= 0, in units of the mean weight) on the outline itself.
    jag : float
        Strength (>= 0) of the multi-scale noise on the weights; 0 gives the least-cost
        (straight) path.
    rng : {numpy.random.Generator, int}, optional
        Seed of that noise.

    Returns
    -------
    (K, 2) int64 ndarray
        Lattice ``(x, y)`` from the seed to the end (one row when there is no content).

    Examples
    --------
    >>> m = np.zeros((60, 60), bool); m[5:55, 20:40] = True
    >>> path = strike_channel(np.ones((60, 60)), m, (30, 5), rng=0)
    >>> bool(path[-1, 1] > 45 and m[path[:, 1], path[:, 0]].all())
    True
    >>> straight = strike_channel(np.ones((60, 60)), m, (30, 5), jag=0.0)
    >>> bool(np.abs(straight[:, 0] - 29.5).max() < 6)
    True
    """
    from .lattice import Lattice
    from .planner import plan

    w = np.asarray(weights, np.float64)
    c = np.asarray(content, bool)
    if w.ndim != 2 or c.shape != w.shape:
        raise ValueError(f"weights and content must be 2-D of one shape, got {w.shape}, {c.shape}")
    if not penalty >= 0:
        raise ValueError(f"penalty must be >= 0, got {penalty}")
    if not jag >= 0:
        raise ValueError(f"jag must be >= 0, got {jag}")
    sx, sy = (int(round(float(v))) for v in seed)
    sil, near, _ = outline_band(c, band)
    sil = _seed_part(sil, (sx, sy))  # the object the seed lies over: the others are ground
    end, _ = _channel_end(sil)
    if end is None:
        return np.array([[sx, sy]], np.int64)
    mean = float(np.mean(w[np.isfinite(w)])) if np.isfinite(w).any() else 1.0
    # the lattice's noise is per pixel and averages out along a long path: inside the
    # object the least-cost path was a ruler-straight line; noise at every scale (on the
    # weights only: the outline band and the outside keep their full cost) makes it turn
    # at every scale, as the bolt's branches do
    # fading out towards the outline, so the channel still keeps off it in thin parts
    gen = np.random.default_rng(rng)
    rough = _rough(w.shape, jag, gen)
    # the noise on the weights fades out towards the outline, but in thin parts the outline
    # band's cost keeps OUTLINE_JAG of it: all within the band, the channel ran ruler-straight
    # down a thin pole (and on the ground too, should the channel cross it: a seed off the object)
    thin = _thin(sil, band)
    cost = np.where(sil, (w * rough ** (1.0 - near) + mean * penalty * near)
                    * rough ** (OUTLINE_JAG * near * thin),
                    (w + 10.0 * mean) * _ground(sil, jag, gen))
    if thin.any():
        # in thin parts the noise's scales follow the part's width (dendrite38); the band's
        # depth still pulls the channel off the outline (flat, it ran along a thin trunk's
        # edge, off a tree at 250 px)
        cost = np.where(thin, (w + mean * penalty * near) * _thin_rough(thin, jag, gen), cost)
    res = plan(Lattice(cost), (sx, sy), metric="cumulative")
    nodes = res.path(int(end[1]) * w.shape[1] + int(end[0]))
    return _taut(np.column_stack([nodes % w.shape[1], nodes // w.shape[1]]).astype(np.int64))


def strike_weights(weights, content, seed, *, band: float = STRIKE_BAND,
                   penalty: float = STRIKE_PENALTY,
                   max_cover: float = STRIKE_MAX_COVER, jag: float = CHANNEL_JAG,
                   rng=None) -> tuple[np.ndarray, np.ndarray] | None:
    """Lattice weights for a lightning bolt that runs down through a drawn object.

    Beyond the papers: the main channel (:func:`strike_channel`) becomes a
    highway (its weights 0), and a filled object's outline band and its
    outside cost ``penalty`` times the mean weight more, times the object's
    ``fill`` (:func:`outline_band`: a line drawing keeps its cheap lines), so
    the branches planned from the seed fork off the channel inside the object
    instead of running round its outline. Only for an object on a
    background: None where its silhouette covers more than ``max_cover`` of
    the picture (photos: 0.96-1; drawn objects 0.19-0.61). Beyond the papers (dendrite34):
    the ground between objects costs :func:`~branchnb.dendrite.channel_jag._ground` times
    more, so branches jump from object to object where they are close, along jagged paths.
    Beyond the papers (dendrite38): in thin parts the outline band's constant is left off and
    the weights carry :func:`~branchnb.dendrite.channel_jag._thin_rough`'s noise (the
    branches along a mast's arms were straight lines round their outline).

    Parameters
    ----------
    weights : (h, w) array_like
        Node weights of the lattice (>= 0).
    content : (h, w) array_like of bool
        Where there is something to draw.
    seed : (x, y)
        Start, in lattice pixels.
    band, penalty : float
        As in :func:`strike_channel`.
    max_cover : float
        Largest share in [0, 1] of the picture the silhouette may cover.
    jag : float
        As in :func:`strike_channel`.
    rng : {numpy.random.Generator, int}, optional
        As in :func:`strike_channel`.

    Returns
    -------
    (weights, path) or None
        The new ``(h, w)`` weights and the channel's ``(K, 2)`` lattice ``(x, y)``.

    Examples
    --------
    >>> m = np.zeros((60, 60), bool); m[5:55, 20:40] = True
    >>> w, path = strike_weights(np.ones((60, 60)), m, (30, 5), rng=0)
    >>> float(np.median(w[m])), float(w[30, 20]) > 2, float(w[path[5, 1], path[5, 0]])
    (1.0, True, 0.0)
    >>> strike_weights(np.ones((60, 60)), np.ones((60, 60), bool), (30, 5)) is None
    True
    """
    if not 0.0 <= max_cover <= 1.0:
        raise ValueError(f"max_cover must be in [0, 1], got {max_cover}")
    w = np.asarray(weights, np.float64)
    sil, near, fill = outline_band(content, band)
    if sil.mean() > max_cover:
        return None
    gen = np.random.default_rng(rng)
    path = strike_channel(w, content, seed, band=band, penalty=penalty, jag=jag, rng=gen)
    if len(path) < 2:
        return None
    out = w + float(np.mean(w[np.isfinite(w)])) * penalty * fill * near
    # the ground between objects rough at every scale: the branches jumping from one object
    # to another crossed it in straight lines
    out[~sil] *= _ground(sil, jag, gen)[~sil]
    thin = _thin(sil, band)
    if thin.any():
        # thin parts: noise at the part's width's scales on the branches' costs, the lattice's
        # per-pixel noise drowned in the outline band's constant (straight stubs; dendrite38)
        out[thin] = w[thin] * _thin_rough(thin, jag, gen)[thin]
    out[path[:, 1], path[:, 0]] = 0.0
    return out, path


def channel_plan(plan_result: PlanResult, path) -> PlanResult:
    """A plan from a whole channel made one tree: the channel's pixels chained from its start.

    ``plan_result`` was planned from every pixel of ``path`` as a seed, so each
    node's path runs to the nearest (cheapest) pixel of the channel; here each
    channel pixel but the first gets the one before it as parent, so every
    endpoint traced in it (:func:`~branchnb.dendrite.dendrite.build_dendrite`)
    forks off the channel and runs down it to ``path[0]``; :func:`with_channel`
    then makes the channel the dendrite's main path (:func:`main_path`: the
    child with most tips would leave it where a side branch holds more tips
    than the rest of the channel).

    Parameters
    ----------
    plan_result : PlanResult
        A lattice plan whose seeds are the pixels of ``path``.
    path : (K, 2) array_like of int
        The channel's lattice ``(x, y)``, start first, no pixel twice.

    Returns
    -------
    PlanResult
        A copy with the new ``parent`` and ``seeds = [path[0]]``.

    Examples
    --------
    >>> from branchnb.dendrite import build_dendrite, make_lattice, plan
    >>> lat = make_lattice(np.ones((20, 20)), rng=0)
    >>> line = np.column_stack([np.full(20, 10), np.arange(20)])
    >>> seeds = np.zeros((20, 20), bool); seeds[:, 10] = True
    >>> res = channel_plan(plan(lat, seeds, metric="cumulative"), line)
    >>> d = build_dendrite(res, [(2, 15), (18, 5), (10, 19)])
    >>> bool(np.isin(line[:, 1] * 20 + 10, d.nodes).all()), d.points[d.parent < 0].tolist()
    (True, [[10.0, 0.0]])
    """
    if not isinstance(plan_result, PlanResult):
        raise TypeError(f"plan_result must be a PlanResult, got {type(plan_result).__name__}")
    if plan_result.shape is None:
        raise ValueError("plan_result must be planned on a lattice")
    q = np.asarray(path, np.int64).reshape(-1, 2)
    nodes = q[:, 1] * plan_result.shape[1] + q[:, 0]
    if np.unique(nodes).size != nodes.size:
        raise ValueError("path must not visit a pixel twice")
    parent = plan_result.parent.copy()
    parent[nodes[0]] = -1
    parent[nodes[1:]] = nodes[:-1]
    return dataclasses.replace(plan_result, parent=parent, seeds=nodes[:1].copy())


def with_channel(dendrite: Dendrite, path) -> Dendrite:
    """``dendrite`` with ``main`` set to the tree nodes of the lattice ``path``
    (traced in a :func:`channel_plan` with ``path``'s end among the endpoints).

    Parameters
    ----------
    dendrite : Dendrite
        Traced in the plan ``path`` was chained into.
    path : (K, 2) array_like of int
        The channel's lattice ``(x, y)``, start first.

    Returns
    -------
    Dendrite
        A copy; :func:`main_path` returns the channel.

    Examples
    --------
    >>> from branchnb.dendrite import build_dendrite, make_lattice, plan
    >>> lat = make_lattice(np.ones((20, 20)), rng=0)
    >>> line = np.column_stack([np.full(20, 10), np.arange(20)])
    >>> seeds = np.zeros((20, 20), bool); seeds[:, 10] = True
    >>> res = channel_plan(plan(lat, seeds, metric="cumulative"), line)
    >>> d = with_channel(build_dendrite(res, [(2, 3), (10, 19)]), line)
    >>> len(main_path(d))
    20
    """
    if not isinstance(dendrite, Dendrite):
        raise TypeError(f"dendrite must be a Dendrite, got {type(dendrite).__name__}")
    if dendrite.shape is None:
        raise ValueError("dendrite must be traced on a lattice")
    q = np.asarray(path, np.int64).reshape(-1, 2)
    nodes = q[:, 1] * dendrite.shape[1] + q[:, 0]
    where = {int(v): i for i, v in enumerate(dendrite.nodes)}
    if any(int(v) not in where for v in nodes):
        raise ValueError("path must lie on the dendrite (trace its end too)")
    return dataclasses.replace(dendrite, main=np.array([where[int(v)] for v in nodes], np.int64))
