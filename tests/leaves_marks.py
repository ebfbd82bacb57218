"""Birch-like procedural leaves with marks at chance places (shared by the scattered-marks tests).

An ovate, toothed, tilted blade with a midrib and pinnate side veins lighter than the blade, and marks of
one fixed colour: rust spots, dark blotches cut by the veins, dark rims round pale insect holes, or pale
lichen dots. The truth of the marks and of the veins comes back with the image.
"""

import cv2
import numpy as np

#: The marks' colour by kind (their texture is the blade's).
MARK_COLOUR = {"spots": (0.48, 0.26, 0.08), "blotch": (0.30, 0.18, 0.10), "lichen": (0.85, 0.85, 0.75),
               "rims": (0.25, 0.15, 0.08)}
#: The pale inside of an insect hole (``kind="rims"``).
HOLE_COLOUR = (0.80, 0.78, 0.55)


def marked_leaf(seed, size, kind="spots", count=(4, 10), *, margin=0.08, chance_spot=False, blade_colour=None):
    """A leaf image (RGBA, alpha the blade) with its marks and veins as bool masks.

    Parameters
    ----------
    seed : int
        Seeds the leaf's shape, veins, marks and texture.
    size : int
        Side of the square image (px).
    kind : {"spots", "blotch", "rims", "lichen"}
        The marks. ``"spots"`` leaves are doubly toothed and draw their green before their texture;
        the others singly toothed, texture first (the orders the tests' leaves were made in).
    count : int or (int, int)
        How many marks, or the range ``rng.integers`` draws it from (after the veins).
    margin : float
        The marks' centres keep this share of ``size`` from the outline (0: anywhere on the blade).
    chance_spot : bool
        The first mark sits at the same place of every leaf (a chance overlap of the exemplars).
    blade_colour : sequence of 3 floats, optional
        The blade's RGB (default: a green varying by +-10 % between leaves, drawn from the seed).

    Returns
    -------
    img : (size, size, 4) float32 ndarray
    marks, veins : (size, size) bool ndarray
    """
    rng = np.random.default_rng(seed)
    s = size
    length, tilt = s * rng.uniform(0.6, 0.72), rng.uniform(-0.25, 0.25)
    width = length * rng.uniform(0.45, 0.62)
    base = np.array([s / 2, s * 0.85])
    ax = np.array([np.sin(tilt), -np.cos(tilt)])
    nx = np.array([-ax[1], ax[0]])
    t = np.linspace(0, 1, 400)
    half = width / 2 * np.sin(np.pi * t ** 0.8) ** 0.9
    teeth = 1 + 0.04 * np.abs(np.sin(t * np.pi * 22))
    if kind == "spots":
        teeth = teeth + 0.025 * np.abs(np.sin(t * np.pi * 44))
    poly = np.r_[base + (t * length)[:, None] * ax + (half * teeth)[:, None] * nx,
                 (base + (t * length)[:, None] * ax - (half * teeth)[:, None] * nx)[::-1]]
    blade = np.zeros((s, s), np.uint8)
    cv2.fillPoly(blade, [(poly * 4).astype(np.int32)], 1, cv2.LINE_8, shift=2)
    veins = np.zeros((s, s), np.uint8)
    mid = np.r_[[base - ax * s * 0.08], base + (t * length)[:, None] * ax][::20]
    cv2.polylines(veins, [(mid * 4).astype(np.int32)], False, 1, max(2, s // 100), cv2.LINE_8, shift=2)
    n_sec = rng.integers(7, 10)
    for k in range(1, n_sec + 1):
        tt = k / (n_sec + 1.5)
        p0 = base + tt * length * ax
        tt2 = min(tt + 0.16, 0.98)
        for side in (-1, 1):
            p1 = base + tt2 * length * ax + side * width / 2 * np.sin(np.pi * tt2 ** 0.8) ** 0.9 * nx * 0.93
            cv2.line(veins, tuple((p0 * 4).astype(int)), tuple((p1 * 4).astype(int)), 1, max(1, s // 200),
                     cv2.LINE_8, shift=2)
    veins &= blade
    marks = np.zeros((s, s), np.uint8)
    inner = np.zeros((s, s), np.uint8)
    ys, xs = np.nonzero(cv2.erode(blade, np.ones((int(s * margin) | 1,) * 2, np.uint8)))
    n_marks = int(rng.integers(*count)) if isinstance(count, tuple) else int(count)
    for k in range(n_marks):
        i = rng.integers(len(xs))
        c = (int(xs[i]), int(ys[i]))
        if kind == "spots":
            r = max(2, int(rng.uniform(0.012, 0.03) * s))
            if chance_spot and k == 0:
                c = tuple(int(v) for v in base + 0.45 * length * ax + 0.2 * width * nx)
            cv2.circle(marks, c, r, 1, -1)
        elif kind == "blotch":
            a, b = rng.uniform(0.03, 0.06) * s, rng.uniform(0.015, 0.035) * s
            cv2.ellipse(marks, c, (int(a), int(b)), rng.uniform(0, 180), 0, 360, 1, -1)
        elif kind == "rims":  # a dark rim around a pale insect hole
            r = max(3, int(rng.uniform(0.015, 0.03) * s))
            cv2.circle(marks, c, r, 1, -1)
            cv2.circle(inner, c, r - max(1, r // 3), 1, -1)
        elif kind == "lichen":
            cv2.circle(marks, c, max(1, int(rng.uniform(0.006, 0.012) * s)), 1, -1)
        else:
            raise ValueError(f"kind must be one of {sorted(MARK_COLOUR)}, got {kind!r}")
    marks &= blade & (1 - veins)  # the veins cut the marks
    inner &= marks
    marks &= 1 - inner
    img = np.zeros((s, s, 4), np.float32)
    if kind == "spots":
        green = np.array([0.36, 0.52, 0.18]) * rng.uniform(0.9, 1.1) if blade_colour is None else np.asarray(
            blade_colour)
        tex = cv2.GaussianBlur(rng.normal(0, 0.05, (s, s)).astype(np.float32), (0, 0), 1.2)
    else:
        tex = cv2.GaussianBlur(rng.normal(0, 0.05, (s, s)).astype(np.float32), (0, 0), 1.2)
        green = np.array([0.36, 0.52, 0.18]) * rng.uniform(0.9, 1.1) if blade_colour is None else np.asarray(
            blade_colour)
    img[..., :3] = green + tex[..., None]
    img[veins > 0, :3] = (0.62, 0.72, 0.38)
    img[marks > 0, :3] = np.array(MARK_COLOUR[kind]) + tex[marks > 0, None]
    img[inner > 0, :3] = HOLE_COLOUR
    img[..., :3] = np.clip(img[..., :3], 0, 1)
    img[..., 3] = blade
    return img, marks > 0, veins > 0
