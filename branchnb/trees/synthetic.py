"""Procedural tree exemplars with known answers (crown/trunk/ground labels and pins).

Flat-coloured clip-art trees of several kinds, drawn with the traits that
break naive tree pipelines: ground clutter at the trunk foot (a pile of
fallen leaves, grass tufts, a cast shadow, rocks), broad flat palm fronds
that hang down beside the trunk, and dark outlines round everything. Each
comes with its true label image (0 background, 1 crown, 2 trunk, 255
ground) and its true pin points, so segmentation and pin placement can be
measured on images nobody tuned them on.

Examples
--------
>>> t = synthetic_tree("leaf_pile", rng=0, size=128)
>>> t.image.shape, sorted(set(t.labels.ravel().tolist()))
((128, 128, 4), [0, 1, 2, 255])
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from ..core.random import as_rng

__all__ = ["SYNTHETIC_KINDS", "SyntheticTree", "synthetic_tree", "synthetic_trees"]

#: Kinds of :func:`synthetic_tree`.
SYNTHETIC_KINDS = ("leaf_pile", "grass", "shadow", "rocks", "palm", "outlined", "palm_outlined",
                   "clean", "leaf_pile_outlined")

BACKGROUND, CROWN, TRUNK, GROUND = 0, 1, 2, 255


@dataclass
class SyntheticTree:
    """A procedural exemplar and its true answers.

    Parameters
    ----------
    image : (S, S, 4) float32 ndarray
        RGBA, binary alpha.
    labels : (S, S) uint8 ndarray
        0 background, 1 crown, 2 trunk, 255 ground clutter.
    pins : dict
        ``{"B": (x, y), "R": (x, y), "L": (x, y)}`` in pixels.
    kind : str
        Which of :data:`SYNTHETIC_KINDS` drew it (the clutter at the foot).

    Examples
    --------
    >>> t = synthetic_tree("clean", rng=0, size=64)
    >>> t.image.shape, sorted(set(t.labels.ravel().tolist())), t.pins["B"]
    ((64, 64, 4), [0, 1, 2], (33.0, 62.0))
    """

    image: np.ndarray
    labels: np.ndarray
    pins: dict
    kind: str


def _hsv(h, s, v) -> tuple[float, float, float]:
    rgb = cv2.cvtColor(np.array([[[h, s, v]]], np.float32), cv2.COLOR_HSV2RGB)[0, 0]
    return tuple(float(c) for c in rgb)


def _trunk_polygon(xb, yb, wb, xt, yt, wt, bend, n=24):
    t = np.linspace(0.0, 1.0, n)
    cx = xb + (xt - xb) * t + bend * np.sin(np.pi * t)
    cy = yb + (yt - yb) * t
    w = wb + (wt - wb) * t
    right = np.stack([cx + w / 2, cy], 1)
    left = np.stack([cx - w / 2, cy], 1)
    return right, left


def _first_inside(edge: np.ndarray, region: np.ndarray) -> tuple[float, float]:
    """First point along a densely sampled edge (from its start) inside ``region``."""
    h, w = region.shape
    dense = []
    for a, b in zip(edge[:-1], edge[1:]):
        k = int(np.ceil(np.hypot(*(b - a)))) + 1
        dense.append(a + (b - a) * np.linspace(0, 1, k, endpoint=False)[:, None])
    dense = np.vstack(dense + [edge[-1:]])
    xi = np.clip(np.round(dense[:, 0]).astype(int), 0, w - 1)
    yi = np.clip(np.round(dense[:, 1]).astype(int), 0, h - 1)
    inside = np.flatnonzero(region[yi, xi])
    p = dense[inside[0]] if inside.size else dense[-1]
    return float(p[0]), float(p[1])


def _poly(mask: np.ndarray, pts) -> None:
    cv2.fillPoly(mask, [np.round(np.asarray(pts) * 8).astype(np.int32)], 1, lineType=cv2.LINE_8,
                 shift=3)


def _cartoon_leaves(cx: float, foot_y: float, wb: float, S: int, rng) -> list:
    """Pointed cartoon leaves round a trunk foot: ``[(polygon, colour), ...]``.

    Most lie in a heap on the ground round the foot, a few lean on the
    trunk above it, and two or three lie apart from the heap.
    """
    u = rng.uniform
    out = []
    n = int(rng.integers(18, 30))
    for i in range(n):
        if i < 3:        # lying apart
            x = cx + rng.choice([-1, 1]) * u(0.2, 0.32) * S
            y = foot_y + u(0.0, 0.03) * S
        elif i < 6:      # leaning on the trunk
            x = cx + rng.choice([-1, 1]) * u(0.3, 0.9) * wb
            y = foot_y - u(0.0, 0.05) * S
        else:
            x = cx + rng.normal(0, 0.09 * S)
            y = foot_y + abs(rng.normal(0.01 * S, 0.012 * S))
        length = S * u(0.06, 0.1)
        width = length * u(0.4, 0.55)
        a = u(0, np.pi) if i >= 3 else u(-0.3, 0.3)
        t = np.linspace(0, 1, 16)
        d = np.array([np.cos(a), np.sin(a)])
        nrm = np.array([-d[1], d[0]])
        spine = np.array([x, min(y, S - 4)]) - 0.5 * length * d + t[:, None] * length * d
        half = 0.5 * width * np.sin(np.pi * t) ** 0.7
        poly = np.vstack([spine + half[:, None] * nrm, (spine - half[:, None] * nrm)[::-1]])
        out.append((poly, _hsv(u(0, 50), u(0.7, 0.95), u(0.55, 0.95))))
    return out


def synthetic_tree(kind: str = "leaf_pile", *, rng=None, size: int = 256) -> SyntheticTree:
    """Draw one procedural tree exemplar of ``kind`` with its labels and pins.

    Parameters
    ----------
    kind : str
        One of :data:`SYNTHETIC_KINDS`: ``"leaf_pile"`` (autumn leaves piled
        round the trunk foot), ``"grass"``, ``"shadow"``, ``"rocks"``,
        ``"palm"`` (broad flat fronds), ``"outlined"`` (a dark outline round
        crown, trunk and a leaf pile), ``"palm_outlined"`` (palm, outline,
        sand mound), ``"clean"`` (no clutter), ``"leaf_pile_outlined"``
        (an outlined tree over a pile of cartoon leaves, each leaf with its
        own dark outline and vein, some leaning on the trunk, a few lying
        apart).
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the random shape, colours and clutter; None
        draws a fresh seed.
    size : int
        Side of the square image (>= 48).

    Returns
    -------
    SyntheticTree
        The RGBA image with its true labels and pins.

    Raises
    ------
    ValueError
        Unknown ``kind`` or ``size`` below 48.

    Examples
    --------
    >>> t = synthetic_tree("leaf_pile", rng=1, size=64)
    >>> bool((t.labels == 255).any())  # the pile is labelled ground
    True
    """
    if kind not in SYNTHETIC_KINDS:
        raise ValueError(f"kind must be one of {list(SYNTHETIC_KINDS)}, got {kind!r}")
    if not isinstance(size, (int, np.integer)) or size < 48:
        raise ValueError(f"size must be an int >= 48, got {size!r}")
    rng = as_rng(rng)
    S = int(size)
    u = rng.uniform
    palm = kind.startswith("palm")
    crown = np.zeros((S, S), np.uint8)
    trunk = np.zeros((S, S), np.uint8)
    ground = np.zeros((S, S), np.uint8)
    img = np.zeros((S, S, 3), np.float32)
    crown_col = _hsv(u(80, 140), u(0.55, 0.9), u(0.45, 0.8))
    trunk_col = _hsv(u(15, 35), u(0.5, 0.8), u(0.25, 0.45))
    cx = S / 2 + u(-0.08, 0.08) * S
    foot_y = S * u(0.78, 0.86) if kind != "clean" else S * 0.96
    wb = S * u(0.05, 0.08)
    if palm:
        top = (cx + u(-0.2, 0.2) * S, S * u(0.28, 0.36))
        wt, bend = wb * 0.7, u(-0.08, 0.08) * S
    else:
        top = (cx + u(-0.03, 0.03) * S, S * u(0.45, 0.55))
        wt, bend = wb * 0.8, u(-0.02, 0.02) * S
    right, left = _trunk_polygon(cx, foot_y, wb, top[0], top[1], wt, bend)
    _poly(trunk, np.vstack([right, left[::-1]]))
    # crown
    if palm:
        hub = np.array(top)
        n_fronds = int(rng.integers(5, 8))
        angles = np.sort(u(0, 2 * np.pi, n_fronds)) if False else \
            np.linspace(-0.15 * np.pi, 1.15 * np.pi, n_fronds) + u(-0.15, 0.15, n_fronds)
        for a in angles:
            length = S * u(0.22, 0.34)
            width = length * u(0.22, 0.32)
            droop = u(0.1, 0.5) * length
            t = np.linspace(0, 1, 20)
            d = np.array([np.cos(a), -np.sin(a)])
            nrm = np.array([-d[1], d[0]])
            spine = hub + t[:, None] * length * d + (droop * t ** 2)[:, None] * np.array([0, 1])
            half = width * np.sin(np.pi * np.clip(t, 0.02, 1)) ** 0.8 / 2
            _poly(crown, np.vstack([spine + half[:, None] * nrm, (spine - half[:, None] * nrm)[::-1]]))
        cv2.circle(crown, (int(hub[0]), int(hub[1])), int(max(2, wt * 0.9)), 1, -1)
    else:
        ccy = top[1] - S * u(0.15, 0.22)
        rx, ry = S * u(0.25, 0.36), S * u(0.2, 0.26)
        for _ in range(int(rng.integers(4, 8))):
            ox, oy = u(-0.6, 0.6) * rx, u(-0.5, 0.5) * ry
            r = min(rx, ry) * u(0.45, 0.7)
            cv2.circle(crown, (int(cx + ox), int(ccy + oy)), int(r), 1, -1)
        cv2.ellipse(crown, (int(cx), int(ccy)), (int(rx * 0.8), int(ry * 0.85)), 0, 0, 360, 1, -1)
        # the trunk must reach into the crown
        bottom = np.flatnonzero(crown[:, int(top[0])])
        if bottom.size and bottom[-1] < top[1]:
            cv2.ellipse(crown, (int(top[0]), int(bottom[-1])), (int(2 * wt), int(top[1] - bottom[-1] + 3)),
                        0, 0, 360, 1, -1)
    crown_b = crown > 0
    trunk_b = (trunk > 0) & ~crown_b
    # true pins: the trunk edges walked up from the foot, first crown pixel
    pins = {"B": (float(cx), float(foot_y)), "R": _first_inside(right, crown_b),
            "L": _first_inside(left, crown_b)}
    # ground clutter
    gcol = None
    if kind in ("leaf_pile", "outlined"):
        gcol = _hsv(u(10, 45), u(0.7, 0.95), u(0.6, 0.9))
        for _ in range(int(rng.integers(25, 45))):
            x = cx + rng.normal(0, 0.12 * S)
            y = foot_y + rng.normal(0.015 * S, 0.018 * S)
            cv2.ellipse(ground, (int(x), int(min(y, S - 3))), (int(S * u(0.015, 0.035)), int(S * u(0.008, 0.018))),
                        float(u(0, 180)), 0, 360, 1, -1)
        cv2.ellipse(ground, (int(cx), int(foot_y + 0.02 * S)), (int(0.16 * S), int(0.025 * S)), 0, 0, 360,
                    1, -1)
    elif kind == "leaf_pile_outlined":
        leaves = _cartoon_leaves(cx, foot_y, wb, S, rng)
        for poly, _ in leaves:
            _poly(ground, poly)
    elif kind == "grass":
        gcol = _hsv(u(90, 130), u(0.6, 0.9), u(0.45, 0.75))
        base = foot_y + 0.01 * S
        cv2.rectangle(ground, (int(cx - 0.3 * S), int(base)), (int(cx + 0.3 * S), int(base + 0.03 * S)), 1, -1)
        for _ in range(60):
            x = cx + u(-0.3, 0.3) * S
            h = S * u(0.03, 0.08)
            lean = u(-0.02, 0.02) * S
            pts = np.array([(x - 1.5, base + 1), (x + 1.5, base + 1), (x + lean, base - h)])
            _poly(ground, pts)
    elif kind == "shadow":
        gcol = (0.18, 0.18, 0.2)
        cv2.ellipse(ground, (int(cx + u(-0.05, 0.1) * S), int(foot_y + 0.01 * S)),
                    (int(u(0.25, 0.35) * S), int(u(0.025, 0.04) * S)), 0, 0, 360, 1, -1)
    elif kind == "rocks":
        gcol = (0.5, 0.5, 0.52)
        for _ in range(int(rng.integers(4, 8))):
            x = cx + u(-0.25, 0.25) * S
            r = S * u(0.025, 0.06)
            cv2.ellipse(ground, (int(x), int(foot_y + 0.02 * S - 0.4 * r)), (int(r * 1.4), int(r)), 0, 0, 360,
                        1, -1)
        cv2.ellipse(ground, (int(cx), int(foot_y + 0.02 * S)), (int(0.2 * S), int(0.02 * S)), 0, 0, 360, 1, -1)
    elif kind == "palm_outlined" or kind == "palm":
        gcol = _hsv(u(40, 55), u(0.5, 0.8), u(0.8, 0.95))
        cv2.ellipse(ground, (int(cx + u(-0.1, 0.1) * S), int(foot_y + 0.03 * S)),
                    (int(u(0.3, 0.42) * S), int(0.05 * S)), 0, 180, 360, 1, -1)
        cv2.rectangle(ground, (int(cx - 0.42 * S), int(foot_y + 0.03 * S)),
                      (int(cx + 0.42 * S), int(foot_y + 0.045 * S)), 1, -1)
    ground_b = (ground > 0)
    # the trunk foot disappears behind the clutter
    ground_b &= ~crown_b
    trunk_b &= ~ground_b
    trunk_b[int(np.ceil(foot_y)) + 1:] = False
    # B is the visible trunk foot: the middle of the trunk's lowest visible row
    rows = np.flatnonzero(trunk_b.any(axis=1))
    if rows.size:
        xs = np.flatnonzero(trunk_b[rows[-1]])
        pins["B"] = (float(0.5 * (xs[0] + xs[-1])), float(rows[-1]))
    labels = np.zeros((S, S), np.uint8)
    labels[crown_b] = CROWN
    labels[trunk_b] = TRUNK
    labels[ground_b] = GROUND
    img[crown_b] = crown_col
    img[trunk_b] = trunk_col
    if gcol is not None:
        img[ground_b] = gcol
        # a few leaves of a different tint in the pile, flat-coloured blobs
        if kind in ("leaf_pile", "outlined"):
            spots = (rng.random((S, S)) < 0.3) & ground_b
            spots = cv2.dilate(spots.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool) & ground_b
            img[spots] = _hsv(u(0, 25), 0.85, 0.7)
    # flat shading blobs on the crown (clip-art highlights)
    if not palm:
        hl = np.zeros((S, S), np.uint8)
        for _ in range(3):
            cv2.circle(hl, (int(cx + u(-0.15, 0.15) * S), int(top[1] - S * u(0.2, 0.32))), int(S * u(0.04, 0.07)),
                       1, -1)
        hlb = (hl > 0) & crown_b
        img[hlb] = np.clip(np.array(crown_col) * 1.25, 0, 1)
    if kind == "leaf_pile_outlined":
        # The tree is outlined like the leaves; the leaves are drawn over it,
        # each with its own outline and vein (later leaves over earlier ones).
        width = max(2, int(round(0.01 * S)))
        inner = cv2.erode((crown_b | trunk_b).astype(np.uint8), np.ones((2 * width + 1,) * 2, np.uint8)) > 0
        img[(crown_b | trunk_b) & ~inner] = (0.05, 0.05, 0.05)
        lw = max(1, int(round(0.005 * S)))
        for poly, col in leaves:
            m = np.zeros((S, S), np.uint8)
            _poly(m, poly)
            edge = (m > 0) & ~(cv2.erode(m, np.ones((2 * lw + 1,) * 2, np.uint8)) > 0)
            img[(m > 0) & ~crown_b] = col
            img[edge & ~crown_b] = (0.08, 0.05, 0.03)
            a, b = poly[0], poly[len(poly) // 2]
            vein = np.zeros((S, S), np.uint8)
            cv2.line(vein, (int(a[0]), int(a[1])), (int(b[0]), int(b[1])), 1, max(1, lw // 2))
            img[(vein > 0) & (m > 0) & ~crown_b] = (0.08, 0.05, 0.03)
    if kind in ("outlined", "palm_outlined"):
        opaque = labels > 0
        width = max(2, int(round(0.012 * S)))
        inner = cv2.erode(opaque.astype(np.uint8), np.ones((2 * width + 1,) * 2, np.uint8)) > 0
        rim = opaque & ~inner
        # crown and trunk meet along an outline too
        cb = cv2.dilate(crown_b.astype(np.uint8), np.ones((width + 1,) * 2, np.uint8)) > 0
        seam = cb & trunk_b & ~crown_b
        img[rim | seam] = (0.05, 0.05, 0.05)
    alpha = (labels > 0).astype(np.float32)
    rgba = np.dstack([img * alpha[..., None], alpha]).astype(np.float32)
    return SyntheticTree(rgba, labels, pins, kind)


def synthetic_trees(n_per_kind: int = 2, *, kinds=SYNTHETIC_KINDS, rng=0,
                    size: int = 256) -> list[SyntheticTree]:
    """``n_per_kind`` trees of every kind (reproducible from ``rng``).

    Parameters
    ----------
    n_per_kind : int
        Trees drawn of each kind.
    kinds : sequence of str
        Kinds to draw (see :func:`synthetic_tree`), in this order; default
        all of :data:`SYNTHETIC_KINDS`.
    rng : int or numpy.random.Generator
        One generator shared by all trees (default seed 0).
    size : int
        Side of each square image (>= 48).

    Returns
    -------
    list of SyntheticTree
        Grouped by kind: ``n_per_kind`` of the first kind, then the next.

    Examples
    --------
    >>> [t.kind for t in synthetic_trees(1, kinds=("grass", "palm"), size=64)]
    ['grass', 'palm']
    """
    rng = as_rng(rng)
    return [synthetic_tree(k, rng=rng, size=size) for k in kinds for _ in range(int(n_per_kind))]
