"""Procedural ornaments whose lines occupy a band of the frame, with known answers (issue 23, branching53).

:func:`band_example` draws, black on white, a pair of interlaced strands (or a few parallel wavy strands)
along a centre path: ``L`` (the left and top borders), ``U`` (left, top, right), ``frame`` (all four),
``wavy`` (three parallel wavy strands across the middle of the frame), ``ring`` (a circle), and (branching70)
``S`` (an S-curve across the frame), ``spiral`` (one and a half turns out from the centre), ``knot`` (a
closed trefoil path crossing itself three times) and ``border`` (a straight band along the top, its width
from 0.04 to 0.2 of the side by the seed), optionally with small leaf stubs at the strands' crests. It returns the image and the known strand spacing (the largest
distance between neighbouring strands), the answer the band's width is measured against.
"""
# ruff: noqa: E501
from __future__ import annotations

import cv2
import numpy as np

KINDS = ("L", "U", "frame", "wavy", "ring", "S", "spiral", "knot", "border")
#: kinds drawn on a square frame
_SQUARE = ("ring", "spiral", "knot")


def _centre_path(kind: str, H: int, W: int, inset: float) -> tuple[np.ndarray, bool]:
    """Dense points (x, y) of the band's centre line, and whether it is closed."""
    a, b = inset, inset
    if kind == "L":
        corners = [(a, H - 1.0), (a, b), (W - 1.0, b)]
    elif kind == "U":
        corners = [(a, H - 1.0), (a, b), (W - 1 - a, b), (W - 1 - a, H - 1.0)]
    elif kind == "frame":
        corners = [(a, b), (W - 1 - a, b), (W - 1 - a, H - 1 - b), (a, H - 1 - b), (a, b)]
    elif kind == "wavy":
        corners = [(0.0, 0.5 * H), (W - 1.0, 0.5 * H)]
    elif kind == "ring":
        t = np.linspace(0, 2 * np.pi, 721)
        r = 0.33 * min(H, W)
        return np.c_[0.5 * W + r * np.cos(t), 0.5 * H + r * np.sin(t)], True
    elif kind == "S":
        x = np.arange(inset, W - inset, 1.0)
        return np.c_[x, 0.5 * H - (0.5 * H - 1.5 * inset) * np.sin(2 * np.pi * (x - inset) / (W - 2 * inset))], False
    elif kind == "spiral":
        t = np.linspace(0.0, 3 * np.pi, 4000)
        r = min(H, W) * (0.1 + 0.33 * t / (3 * np.pi))
        return np.c_[0.5 * W + r * np.cos(t), 0.5 * H + r * np.sin(t)], False
    elif kind == "knot":
        t = np.linspace(0, 2 * np.pi, 3001)
        x, y = np.sin(t) + 2 * np.sin(2 * t), np.cos(t) - 2 * np.cos(2 * t)
        f = (0.5 * min(H, W) - 1.2 * inset) / 3.0
        return np.c_[0.5 * W + f * x, 0.5 * H + f * y], True
    elif kind == "border":
        corners = [(0.0, b), (W - 1.0, b)]
    else:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    c = np.asarray(corners, float)
    seg = np.hypot(*np.diff(c, axis=0).T)
    s = np.r_[0, np.cumsum(seg)]
    # round the corners: a radius of one inset (an ornament turns smoothly round a corner)
    u = np.arange(0, s[-1], 1.0)
    pts = np.c_[np.interp(u, s, c[:, 0]), np.interp(u, s, c[:, 1])]
    k = max(int(inset), 3)
    ker = np.ones(2 * k + 1) / (2 * k + 1)
    mode = "wrap" if kind == "frame" else "nearest"
    from scipy import ndimage as ndi
    pts = np.c_[ndi.convolve1d(pts[:, 0], ker, mode=mode), ndi.convolve1d(pts[:, 1], ker, mode=mode)]
    return pts, kind == "frame"


def _band_params(kind: str, size: int, seed: int, leaves: bool):
    """``(rng, H, W, amp, period, lw)`` of a :func:`band_example` (the same draws for its envelope)."""
    rng = np.random.default_rng(5300 + seed * 31 + KINDS.index(kind) * 7 + (1 if leaves else 0))
    W = int(size)
    H = int(size * rng.uniform(0.75, 1.0)) if kind not in _SQUARE else W
    amp = size * rng.uniform(0.03, 0.05)               # strands swing this far off the centre line
    period = size * rng.uniform(0.25, 0.45)
    lw = max(2, int(round(size / rng.uniform(110, 150))))
    if kind == "border":   # borders of different widths: 0.04-0.2 of the side
        amp = size * (0.02 + 0.08 * ((seed * 0.618) % 1.0))
        period = max(period, 6.0 * amp)
    elif kind == "spiral":   # the turns 0.22 of the side apart: room for the band and its margin
        amp = min(amp, 0.035 * size)
    return rng, H, W, amp, period, lw


def band_example(kind: str, size: int, seed: int, *, leaves: bool = False) -> tuple[np.ndarray, float]:
    """An ornament of ``kind`` (see :data:`KINDS`), ``size`` px wide, as (H, W, 3) float32 black on white,
    and its strand spacing (px)."""
    rng, H, W, amp, period, lw = _band_params(kind, size, seed, leaves)
    inset = amp + size * 0.04
    centre, closed = _centre_path(kind, H, W, inset)
    d = np.gradient(centre, axis=0)
    d /= np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-9)[:, None]
    nrm = np.c_[-d[:, 1], d[:, 0]]
    s = np.r_[0, np.cumsum(np.hypot(*np.diff(centre, axis=0).T))]
    if closed:        # a whole number of periods round a closed path
        period = s[-1] / max(round(s[-1] / period), 2)
    img = np.zeros((H, W), np.uint8)
    strands = []
    if kind == "wavy":
        gap = 2.6 * amp
        spacing = gap + 2 * amp
        for j in (-1, 0, 1):
            ph = rng.uniform(0, 2 * np.pi)
            strands.append(centre + nrm * (j * gap + amp * np.sin(2 * np.pi * s / period + ph))[:, None])
    else:
        spacing = 2 * amp
        ph = rng.uniform(0, 2 * np.pi)
        for sign in (1, -1):
            strands.append(centre + nrm * (sign * amp * np.sin(2 * np.pi * s / period + ph))[:, None])
    for p in strands:
        cv2.polylines(img, [np.round(p * 8).astype(np.int32)], closed, 255, lw, cv2.LINE_AA, 3)
    if leaves:
        ls = max(3.0, 0.012 * size)
        for p in strands:
            q = np.gradient(p, axis=0)
            step = int(period / 2)
            for i in range(int(rng.integers(0, step)), len(p), step):
                if rng.random() < 0.35:
                    continue
                t = q[i] / max(np.hypot(*q[i]), 1e-9)
                side = rng.choice([-1, 1])
                n = np.array([-t[1], t[0]]) * side
                c = p[i] + n * ls * 1.4
                ang = np.degrees(np.arctan2(n[1], n[0]))
                cv2.ellipse(img, (int(c[0] * 8), int(c[1] * 8)), (int(ls * 1.4 * 8), int(ls * 0.7 * 8)), ang, 0, 360, 255, -1, cv2.LINE_AA, 3)
    out = 1.0 - img.astype(np.float32) / 255.0
    return np.repeat(out[..., None], 3, axis=2), float(spacing)


def band_envelope(kind: str, size: int, seed: int, *, leaves: bool = False) -> np.ndarray:
    """The known band of :func:`band_example` (same arguments): (H, W) bool, the pixels the strands
    sweep (within their swing plus the pen of the centre path; with ``leaves`` plus the stubs' length).
    Synthesized ornament lines are judged against it (:mod:`._child_check`)."""
    from scipy import ndimage as ndi

    _rng, H, W, amp, _period, lw = _band_params(kind, size, seed, leaves)
    centre, _closed = _centre_path(kind, H, W, amp + size * 0.04)
    reach = amp + lw + (2.6 * amp if kind == "wavy" else 0.0) + (2.8 * max(3.0, 0.012 * size) if leaves else 0.0)
    line = np.ones((H, W), bool)
    q = np.round(centre).astype(np.int64)
    ok = (q[:, 0] >= 0) & (q[:, 0] < W) & (q[:, 1] >= 0) & (q[:, 1] < H)
    line[q[ok, 1], q[ok, 0]] = False
    return ndi.distance_transform_edt(line) <= reach
