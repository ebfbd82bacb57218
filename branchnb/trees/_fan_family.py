"""Fan-like drawn crowns with a known answer (issue 24), for the side-view checks; not run by the tests.

Every crown here radiates from one hub: palms of 5-11 fronds (narrow and
spaced, or broad and touching each other, smooth or spiky, with or without
midribs), fan palms' leaves (wedge segments that close into a half disc:
their convex hull is nearly filled) and agave / yucca rosettes (lanceolate
leaves from a point at the foot, or on a short stem). :func:`fan_crown_trees`
draws them with :class:`~branchnb.trees.drawn._Canvas`, the painter of
:func:`~branchnb.trees.drawn.drawn_tree`, with random palettes, so a side view
of each should keep the crown's radial drawing as drawn (one billboard about
the hub). The controls (crowns that are no fan) are
:func:`~branchnb.trees.drawn.drawn_tree`'s broadleaf, conifer and fruit trees.

>>> [n for n, _ in fan_crown_trees(96, seeds=(0,))][:3]
['palm_narrow_0', 'palm_broad_0', 'palm_spiky_0']
"""

from __future__ import annotations

import numpy as np

from ..core.random import as_rng
from .drawn import _SS, _Canvas, _hsv, _trunk

FAN_KINDS = ("palm_narrow", "palm_broad", "palm_spiky", "fan", "agave", "yucca")


def _leaf(hub, a, length, width, droop, t, *, spiky=False, wedge=False):
    d, nrm = np.array([np.cos(a), -np.sin(a)]), np.array([np.sin(a), np.cos(a)])
    spine = hub + t[:, None] * length * d + (droop * length * t ** 2)[:, None] * [0, 1]
    if wedge:
        half = width * np.clip(t, 0.02, 1) / 2
    else:
        half = width * np.sin(np.pi * np.clip(t, 0.03, 1)) ** 0.8 / 2
    if spiky:
        half = half * np.where(np.arange(len(t)) % 2, 1.0, 0.55)
    return spine, np.vstack([spine + half[:, None] * nrm, (spine - half[:, None] * nrm)[::-1]])


def fan_crown(kind: str, *, rng=0, size: int = 256) -> np.ndarray:
    """One drawn crown of ``kind`` (one of ``FAN_KINDS``), RGBA ``size`` x ``size``."""
    rng = as_rng(rng)
    S = float(size)
    u = rng.uniform
    ink = _hsv(u(0, 40), u(0.2, 0.6), u(0.04, 0.12))
    cv = _Canvas(int(size), line=max(1.0, u(0.008, 0.014) * S), ink=ink)
    cx = S / 2 + u(-0.05, 0.05) * S
    foot = S * u(0.93, 0.97)
    wb = S * u(0.05, 0.08)
    bark = _hsv(u(15, 35), u(0.45, 0.8), u(0.3, 0.55))
    green = _hsv(u(70, 150), u(0.55, 0.9), u(0.4, 0.7))
    light = tuple(min(1.0, c * u(1.2, 1.45)) for c in green)
    if kind == "agave":
        hub = np.array([cx, foot - 0.03 * S])
    elif kind == "yucca":
        hub = np.array([cx + u(-0.05, 0.05) * S, S * u(0.5, 0.6)])
    else:
        hub = np.array([cx + u(-0.15, 0.15) * S, S * u(0.3, 0.4)])
    if kind != "agave":
        cv.shape(_trunk(cx, foot, hub[0], hub[1] + 0.01 * S, wb * 0.8, wb * 0.55, u(-0.05, 0.05) * S), bark)
        for y in np.linspace(foot, hub[1], 7)[1:-1]:
            f = (y - foot) / (hub[1] - foot)
            x = cx + (hub[0] - cx) * f
            cv.stroke([(x - 0.3 * wb, y), (x + 0.3 * wb, y + 0.01 * S)], width=cv.line / _SS * 0.7)
    t = np.linspace(0, 1, 24)
    if kind == "fan":
        n = int(rng.integers(7, 12))
        lo, hi = np.deg2rad(u(-15, 5)), np.deg2rad(u(175, 195))
        length = S * u(0.26, 0.32)
        step = (hi - lo) / (n - 1)
        for k, a in enumerate(np.linspace(lo, hi, n)):
            # Wedges as wide as their angular step: the segments close into a half disc.
            w = 2 * length * np.tan(0.5 * step) * 1.05
            _, pts = _leaf(hub, a, length, w, 0.0, t, wedge=True)
            cv.shape(pts, green if k % 2 else light)
        return cv.image()
    if kind in ("agave", "yucca"):
        n = int(rng.integers(7, 12))
        lo, hi = np.deg2rad(u(-10, 10)), np.deg2rad(u(170, 190))
        for k, a in enumerate(np.linspace(lo, hi, n)):
            a += u(-0.06, 0.06)
            up = np.sin(a)
            length = S * (u(0.3, 0.4) if kind == "agave" else u(0.22, 0.3)) * (0.7 + 0.3 * up)
            width = S * u(0.05, 0.08)
            _, pts = _leaf(hub, a, length, width, u(0.0, 0.25) * (1 - up), t)
            cv.shape(pts, green if k % 2 else light)
        return cv.image()
    n = int(rng.integers(5, 12))
    lo, hi = np.deg2rad(u(-20, 0)), np.deg2rad(u(180, 200))
    broad = kind != "palm_narrow"
    step = (hi - lo) / (n - 1)
    for k, a in enumerate(np.linspace(lo, hi, n)):
        a += u(-0.05, 0.05)
        length = S * u(0.24, 0.32)
        # Broad fronds as wide as their spacing at mid-length: neighbours touch.
        width = (2.1 * 0.5 * length * np.tan(0.5 * step) * u(1.0, 1.3)) if broad else S * u(0.05, 0.08)
        spine, pts = _leaf(hub, a, length, width, u(0.05, 0.3), t, spiky=kind == "palm_spiky")
        cv.shape(pts, green if k % 2 else light)
        if rng.random() < 0.5:
            cv.stroke(spine[2:-2], width=cv.line / _SS * 0.7)
    return cv.image()


def fan_crown_trees(size: int = 256, *, seeds=(0, 1, 2), kinds=FAN_KINDS) -> list:
    """``[(f"{kind}_{seed}", rgba), ...]`` for every kind and seed at ``size`` px."""
    return [(f"{k}_{s}", fan_crown(k, rng=1000 * s + i, size=size)) for s in seeds for i, k in enumerate(kinds)]
