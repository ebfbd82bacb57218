"""Procedural radial examples with known answers (issue 23): lines radiating from a hub.

A hub is a blob much wider than the lines that leave it: a neuron's soma with its dendrites, a coral
or star's centre with its arms, the crater of an impact with its star of cracks. Each kind comes
light-on-dark and dark-on-light (``*_dark``: dark lines on a light ground). Private (used by
:mod:`._hub_check` and the tests).
"""
# ruff: noqa: E702
from __future__ import annotations

import cv2
import numpy as np

#: kind -> (hub radius, first line width, both as fractions of the side; arms per hub (lo, hi);
#: kinks: straight segments with turns (a crack) instead of smooth wandering)
_SHAPES = {
    "neuron": (0.034, 0.010, (4, 9), False),
    "coral": (0.055, 0.014, (5, 8), False),
    "crack": (0.022, 0.006, (5, 9), True),
}
KINDS = ("neuron", "neuron_dark", "coral", "coral_dark", "crack", "crack_bright")
#: a kind's lines are bright on a dark ground (else dark on a light one)
_BRIGHT = {"neuron": True, "neuron_dark": False, "coral": True, "coral_dark": False, "crack": False,
           "crack_bright": True}


def radial_example(kind: str, size: int, seed: int, n_hubs: int | None = None):
    """``(rgb, centre_lines, lines, hubs)``: an image of ``kind`` (``size`` px square) with its true
    one-pixel centre lines (hub discs excluded), its line mask (hub discs included) and its hubs
    ``[(x, y, radius), ...]``.

    Neurons have 1-3 somas (``n_hubs``; default by the seed), every other kind one hub.
    """
    base = kind.split("_")[0]
    r_hub, w0, (a_lo, a_hi), kinked = _SHAPES[base]
    rng = np.random.default_rng(1000 + 17 * seed + KINDS.index(kind))
    S = int(size)
    k = 8  # sub-pixel drawing
    ink = np.zeros((S, S), np.float32)
    centre = np.zeros((S, S), np.uint8)
    if n_hubs is None:
        n_hubs = 1 + seed % 3 if base == "neuron" else 1
    hubs: list[tuple[float, float, float]] = []
    for _ in range(200):
        if len(hubs) == n_hubs:
            break
        span = 0.5 if n_hubs == 1 else 0.78
        p = S * (0.5 + span * (rng.random(2) - 0.5))
        if all(np.hypot(p[0] - q[0], p[1] - q[1]) > 0.38 * S for q in hubs):
            hubs.append((float(p[0]), float(p[1]), float(r_hub * S * rng.uniform(0.85, 1.15))))
    reach = S * (0.42 if n_hubs == 1 else 0.3)

    def line(p, q, w):
        cv2.line(ink, tuple(np.int32(np.round(p * k))), tuple(np.int32(np.round(q * k))), 1.0,
                 max(1, int(round(w))), cv2.LINE_AA, 3)
        cv2.line(centre, tuple(np.int32(np.round(p * k))), tuple(np.int32(np.round(q * k))), 1, 1, cv2.LINE_8, 3)

    def grow(p, ang, w, depth, budget):
        length = budget * rng.uniform(0.45, 0.65)
        step = max(2.0, 0.006 * S)
        n = max(2, int(length / step))
        pts = [np.asarray(p, float)]
        a = ang
        for _i in range(n):
            if kinked:
                if rng.random() < 0.12:
                    a += rng.normal(0, 0.35)
            else:
                a += rng.normal(0, 0.1)
            pts.append(pts[-1] + step * np.array([np.cos(a), np.sin(a)]))
        for i in range(len(pts) - 1):
            line(pts[i], pts[i + 1], max(1.0, w * (1 - 0.35 * i / len(pts))))
        if depth < 3 and w > 1.3:
            for s in (-1, 1):
                grow(pts[-1], a + s * rng.uniform(0.3, 0.7), w * 0.7, depth + 1, budget - length)

    for x, y, r in hubs:
        n_arms = int(rng.integers(a_lo, a_hi + 1))
        a0 = rng.uniform(0, 2 * np.pi)
        for j in range(n_arms):
            ang = a0 + 2 * np.pi * j / n_arms + rng.normal(0, 0.15)
            start = np.array([x, y]) + 0.8 * r * np.array([np.cos(ang), np.sin(ang)])
            grow(start, ang, w0 * S * rng.uniform(0.8, 1.2), 0, reach * rng.uniform(0.8, 1.1))
    for x, y, r in hubs:
        if base == "crack":       # a crater: a rough blob
            t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
            rr = r * (1 + 0.15 * rng.normal(size=40))
            poly = np.stack([x + rr * np.cos(t), y + rr * np.sin(t)], -1)
            cv2.fillPoly(ink, [np.int32(np.round(poly * k))], 1.0, cv2.LINE_AA, 3)
        else:
            cv2.circle(ink, (int(round(x * k)), int(round(y * k))), int(round(r * k)), 1.0, -1, cv2.LINE_AA, 3)
    lines = ink > 0.5
    disc = np.zeros((S, S), bool)
    yy, xx = np.mgrid[:S, :S]
    for x, y, r in hubs:
        disc |= np.hypot(xx - x, yy - y) <= r
    centre_lines = (centre > 0) & ~disc
    ink = cv2.GaussianBlur(ink, (0, 0), 0.8)
    ground = cv2.GaussianBlur(rng.normal(0, 1, (S, S)).astype(np.float32), (0, 0), 0.012 * S) * 0.05
    if _BRIGHT[kind]:
        g = np.array((0.10, 0.11, 0.14), np.float32) if base != "coral" else np.array((0.05, 0.18, 0.3), np.float32)
        c = np.array((0.55, 0.9, 0.45), np.float32) if base == "neuron" else \
            np.array((0.95, 0.65, 0.5), np.float32) if base == "coral" else np.array((0.85, 0.9, 0.95), np.float32)
    else:
        g = np.array((0.92, 0.88, 0.8), np.float32) if base != "crack" else np.array((0.7, 0.72, 0.74), np.float32)
        c = np.array((0.25, 0.12, 0.3), np.float32) if base == "neuron" else \
            np.array((0.45, 0.15, 0.12), np.float32) if base == "coral" else np.array((0.12, 0.12, 0.13), np.float32)
    rgb = (g + ground[..., None]) * (1 - ink[..., None]) + c * ink[..., None]
    rgb = np.clip(rgb + rng.normal(0, 0.02, rgb.shape), 0, 1).astype(np.float32)
    return rgb, centre_lines, lines, hubs
