"""Drawn (flat-colour, outlined) procedural trees: test material for flat-art mixing.

Clip-art trees as an illustrator draws them: every shape filled with one
flat colour and stroked with a dark outline, shapes painted over each other
(leaf clumps over the crown, fruits over the leaves, tiers of a conifer
over the tier behind), anti-aliased edges, an optional pile of fallen
leaves at the trunk foot. Four kinds (``"broadleaf"``, ``"palm"``,
``"conifer"``, ``"fruit"``), each with its own palette drawn at random, so a
mix of two of them shows at once whether colours were blended (olive veils,
half-transparent fruits) or chosen.

Unlike :mod:`branchnb.trees.synthetic` (known crown/trunk labels and pins),
these trees are for measuring the *colours* of variations
(:func:`~branchnb.trees.quality.crossfade_fraction`) and the inner outlines
of billboard clouds.

Examples
--------
>>> t = drawn_tree("fruit", rng=0, size=128)
>>> t.shape, t.dtype.name
((128, 128, 4), 'float32')
"""

from __future__ import annotations

import cv2
import numpy as np

from ..core.random import as_rng
from ..core.validate import Choice, Int, Seq, checked

__all__ = ["DRAWN_KINDS", "drawn_tree", "drawn_trees"]

#: Kinds of :func:`drawn_tree`.
DRAWN_KINDS = ("broadleaf", "palm", "conifer", "fruit")

_SS = 4  # supersampling of the drawing (anti-aliased edges after the reduction)


def _hsv(h, s, v) -> tuple[float, float, float]:
    rgb = cv2.cvtColor(np.array([[[h, s, v]]], np.float32), cv2.COLOR_HSV2RGB)[0, 0]
    return tuple(float(c) for c in rgb)


class _Canvas:
    """Painter's-order canvas at ``_SS`` times the size: fill + outline per shape."""

    def __init__(self, size: int, line: float, ink):
        self.n = size * _SS
        self.rgb = np.zeros((self.n, self.n, 3), np.float32)
        self.alpha = np.zeros((self.n, self.n), bool)
        self.line = max(1, int(round(line * _SS)))
        self.ink = np.asarray(ink, np.float32)

    def _pts(self, pts):
        return [np.round(np.asarray(pts, float) * _SS).astype(np.int32)]

    def shape(self, pts, colour, *, outline: bool = True) -> None:
        m = np.zeros((self.n, self.n), np.uint8)
        cv2.fillPoly(m, self._pts(pts), 1)
        mb = m > 0
        self.rgb[mb] = colour
        self.alpha |= mb
        if outline:
            e = np.zeros_like(m)
            cv2.polylines(e, self._pts(pts), True, 1, self.line)
            self.rgb[e > 0] = self.ink
            self.alpha |= e > 0

    def stroke(self, pts, width: float | None = None) -> None:
        e = np.zeros((self.n, self.n), np.uint8)
        w = self.line if width is None else max(1, int(round(width * _SS)))
        cv2.polylines(e, self._pts(pts), False, 1, w)
        self.rgb[e > 0] = self.ink
        self.alpha |= e > 0

    def image(self) -> np.ndarray:
        a = self.alpha.astype(np.float32)
        prem = self.rgb * a[..., None]
        small = cv2.resize(np.dstack([prem, a]), None, fx=1 / _SS, fy=1 / _SS,
                           interpolation=cv2.INTER_AREA)
        al = small[..., 3:4]
        out = np.where(al > 1e-6, small[..., :3] / np.maximum(al, 1e-6), 0.0)
        return np.dstack([np.clip(out, 0, 1) * (al >= 0.5), al]).astype(np.float32)


def _ellipse(cx, cy, rx, ry, n=48, wobble=0.0, rng=None):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = 1.0 + (wobble * rng.uniform(-1, 1, n) if wobble else 0.0)
    return np.stack([cx + rx * r * np.cos(t), cy + ry * r * np.sin(t)], 1)


def _trunk(cx, foot, top_x, top_y, wb, wt, bend):
    t = np.linspace(0, 1, 20)
    x = cx + (top_x - cx) * t + bend * np.sin(np.pi * t)
    y = foot + (top_y - foot) * t
    w = wb + (wt - wb) * t
    return np.vstack([np.stack([x + w / 2, y], 1), np.stack([x - w / 2, y], 1)[::-1]])


def _leaf_pile(cv: _Canvas, cx, foot, S, rng) -> None:
    u = rng.uniform
    for _ in range(int(rng.integers(10, 18))):
        x = cx + rng.normal(0, 0.1 * S)
        y = min(foot + abs(rng.normal(0.0, 0.012 * S)), S - 0.04 * S)
        length, a = S * u(0.05, 0.08), u(0, np.pi)
        t = np.linspace(0, 1, 12)
        d, nrm = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
        spine = np.array([x, y]) + (t[:, None] - 0.5) * length * d
        half = 0.25 * length * np.sin(np.pi * t) ** 0.7
        cv.shape(np.vstack([spine + half[:, None] * nrm, (spine - half[:, None] * nrm)[::-1]]),
                 _hsv(u(0, 45), u(0.75, 0.95), u(0.6, 0.95)))


@checked(kind=Choice(*DRAWN_KINDS), size=Int(48, 4096))
def drawn_tree(kind: str = "broadleaf", *, pile: bool = False, rng=None, size: int = 256) -> np.ndarray:
    """Draw one flat-colour, outlined tree.

    Parameters
    ----------
    kind : {"broadleaf", "palm", "conifer", "fruit"}
        Broadleaf: outlined leaf clumps over a crown; palm: outlined fronds
        with a midrib on a bent trunk; conifer: three to five outlined
        tiers; fruit: a broadleaf crown with outlined fruits.
    pile : bool
        A pile of outlined fallen leaves round the trunk foot.
    rng : int or numpy.random.Generator, optional
        Source of the random shapes, hues and placements (seed or
        Generator); None draws a fresh seed, so pass one to repeat a tree.
    size : int
        Side of the square image (>= 48).

    Returns
    -------
    (size, size, 4) float32 ndarray
        Straight RGBA, black where transparent, anti-aliased alpha.

    Examples
    --------
    >>> float(drawn_tree("palm", pile=True, rng=1, size=96)[..., 3].max())
    1.0
    """
    rng = as_rng(rng)
    S = float(size)
    u = rng.uniform
    ink = _hsv(u(0, 40), u(0.2, 0.6), u(0.04, 0.12))
    cv = _Canvas(int(size), line=max(1.0, u(0.008, 0.014) * S), ink=ink)
    cx = S / 2 + u(-0.06, 0.06) * S
    foot = S * (u(0.86, 0.9) if pile else u(0.93, 0.97))
    wb = S * u(0.05, 0.08)
    bark = _hsv(u(15, 35), u(0.45, 0.8), u(0.3, 0.55))
    green = _hsv(u(85, 140), u(0.55, 0.9), u(0.4, 0.7))
    light = tuple(min(1.0, c * u(1.25, 1.45)) for c in green)
    if kind == "palm":
        top = (cx + u(-0.18, 0.18) * S, S * u(0.3, 0.38))
        cv.shape(_trunk(cx, foot, top[0], top[1], wb * 0.8, wb * 0.55, u(-0.06, 0.06) * S), bark)
        for y in np.linspace(foot, top[1], 7)[1:-1]:   # trunk rings
            f = (y - foot) / (top[1] - foot)
            x = cx + (top[0] - cx) * f
            cv.stroke([(x - 0.35 * wb, y), (x + 0.35 * wb, y + 0.01 * S)], width=cv.line / _SS * 0.7)
        hub = np.array(top)
        for k, a in enumerate(np.linspace(-0.1 * np.pi, 1.1 * np.pi, int(rng.integers(5, 8)))):
            a += u(-0.15, 0.15)
            length, width = S * u(0.22, 0.32), S * u(0.06, 0.09)
            t = np.linspace(0, 1, 24)
            d, nrm = np.array([np.cos(a), -np.sin(a)]), np.array([np.sin(a), np.cos(a)])
            spine = hub + t[:, None] * length * d + (u(0.2, 0.5) * length * t ** 2)[:, None] * [0, 1]
            half = width * np.sin(np.pi * np.clip(t, 0.03, 1)) ** 0.8 / 2
            cv.shape(np.vstack([spine + half[:, None] * nrm, (spine - half[:, None] * nrm)[::-1]]),
                     green if k % 2 else light)
            cv.stroke(spine[2:-2], width=cv.line / _SS * 0.7)
    elif kind == "conifer":
        top_y = S * u(0.06, 0.12)
        base_y = foot - S * u(0.1, 0.16)
        cv.shape(_trunk(cx, foot, cx, base_y - 0.05 * S, wb * 0.8, wb * 0.7, 0.0), bark)
        n = int(rng.integers(3, 6))
        half_w = S * u(0.28, 0.36)
        for i in range(n):                       # bottom tier first, the next one over it
            y0 = base_y - i * (base_y - top_y) / (n + 0.6)
            y1 = y0 - 1.6 * (base_y - top_y) / (n + 0.6)
            w = half_w * (1 - 0.75 * i / n)
            xs = np.linspace(-w, w, 7)
            bottom = np.stack([cx + xs, y0 + 0.03 * S * (np.arange(7) % 2)], 1)
            cv.shape(np.vstack([bottom, [(cx, max(y1, top_y))]]), green if i % 2 == 0 else light)
    else:
        top = (cx + u(-0.03, 0.03) * S, S * u(0.45, 0.55))
        cv.shape(_trunk(cx, foot, top[0], top[1] - 0.08 * S, wb, wb * 0.7, u(-0.02, 0.02) * S), bark)
        for side in (-1, 1):                     # two branch stubs into the crown
            b0 = np.array([top[0], top[1] + 0.02 * S])
            b1 = b0 + [side * u(0.08, 0.14) * S, -u(0.06, 0.1) * S]
            cv.shape(np.array([b0 + [0, 0.02 * S], b1, b0 - [0, 0.02 * S]]), bark)
        ccx, ccy = cx, top[1] - S * u(0.16, 0.22)
        rx, ry = S * u(0.28, 0.38), S * u(0.2, 0.26)
        cv.shape(_ellipse(ccx, ccy, rx, ry, wobble=0.05, rng=rng), green)
        clumps = [(ccx + u(-0.55, 0.55) * rx, ccy + u(-0.5, 0.5) * ry, min(rx, ry) * u(0.35, 0.5))
                  for _ in range(int(rng.integers(4, 8)))]
        for x, y, r in sorted(clumps, key=lambda c: c[1]):
            cv.shape(_ellipse(x, y, r, r * u(0.75, 0.95), wobble=0.04, rng=rng),
                     light if rng.random() < 0.5 else green)
        if kind == "fruit":
            fruit = _hsv(u(0, 40), u(0.8, 1.0), u(0.8, 1.0))
            for _ in range(int(rng.integers(6, 12))):
                a, r = u(0, 2 * np.pi), np.sqrt(u(0, 0.8))
                x, y = ccx + r * rx * np.cos(a), ccy + r * ry * np.sin(a)
                cv.shape(_ellipse(x, y, 0.03 * S, 0.03 * S, n=20), fruit)
    if pile:
        _leaf_pile(cv, cx, foot, S, rng)
    return cv.image()


@checked(pile=Seq(), kinds=Seq(), n=Int(1, 1000), size=Int(48, 4096))
def drawn_trees(pile=(False, True), *, kinds=DRAWN_KINDS, n: int = 1, rng=0,
                size: int = 256) -> list[tuple[str, np.ndarray]]:
    """``n`` trees of every kind, with and without a leaf pile: ``[(label, image), ...]``.

    Parameters
    ----------
    pile : sequence of bool
        Leaf-pile settings to draw, outermost loop (default: both, without
        first).
    kinds : sequence of str
        Kinds to draw (see :func:`drawn_tree`), in this order; default all
        four.
    n : int
        Trees per kind and pile setting (1 to 1000).
    rng : int or numpy.random.Generator
        One generator shared by all trees, so the list is reproducible for
        a fixed seed (default 0).
    size : int
        Side of each square image (>= 48).

    Returns
    -------
    list of (str, (size, size, 4) float32 ndarray)
        Label ``"<kind>[_pile]_<i>"`` and the straight RGBA image, in the
        order pile -> kind -> i.

    Examples
    --------
    >>> [name for name, _ in drawn_trees((False,), kinds=("palm", "fruit"), size=64)]
    ['palm_0', 'fruit_0']
    """
    rng = as_rng(rng)
    out = []
    for p in pile:
        for k in kinds:
            for i in range(int(n)):
                out.append((f"{k}{'_pile' if p else ''}_{i}", drawn_tree(k, pile=p, rng=rng, size=size)))
    return out
