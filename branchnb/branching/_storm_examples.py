"""Procedural night storms with known bolts (tests and checks of photo extraction, issue 23).

A graded night sky, a soft bright cloud with a hard upper edge (a dark cloud band over a lit one),
a row of city lights (separate bright dots) along the bottom and 2-3 branching bolts running top-down,
whose centre lines are known. Private: used by the tests and ``_storm_check``.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi


def _bolt(rng, start, length, heading, step=3.0):
    """A jagged polyline from ``start`` going ``heading`` (radians, y down) for ``length`` pixels."""
    pts = [np.asarray(start, float)]
    a = heading
    for _ in range(int(length / step)):
        a = heading + 0.9 * (a - heading) + rng.normal(0, 0.35)
        pts.append(pts[-1] + step * np.array([np.cos(a), np.sin(a)]))
    return np.array(pts)


def storm_example(shape=(288, 384), seed=0, *, n_bolts=3, dots=True, cloud=True, core=0.8, glow=4.0):
    """A night storm image and its bolts' centre lines (``core``, ``glow``: the blur of the bolts'
    bright core and of their glow in px; the defaults give bolts ~4-5 px wide).

    Returns
    -------
    image : (H, W, 3) float32 in [0, 1]
    bolts : list of (n, 2) arrays, (x, y) centre lines (trunks and side branches)
    """
    rng = np.random.default_rng(seed)
    h, w = shape
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    sky = 0.05 + 0.10 * y / h
    lum = sky.copy()
    if cloud:
        cx, cy = w * rng.uniform(0.35, 0.65), h * rng.uniform(0.35, 0.5)
        blob = np.exp(-(((x - cx) / (0.35 * w)) ** 2 + ((y - cy) / (0.22 * h)) ** 2))
        top = h * rng.uniform(0.2, 0.3) + 6 * np.sin(x / rng.uniform(25, 50))      # hard upper edge
        lit = 1.0 / (1.0 + np.exp(-(y - top) / 1.2))
        lum = lum + 0.6 * blob * lit
        # cloud layers: soft steps (a lit layer under a darker one) fading out at both ends
        for _ in range(2):
            yy = h * rng.uniform(0.12, 0.4)
            lum = lum + 0.2 / (1.0 + np.exp(-(y - yy) / 1.5)) * np.exp(-((x - rng.uniform(0.2, 0.8) * w)
                                                                        / (0.18 * w)) ** 2) * (y < yy + 25)
    bolts = []
    lines = np.zeros((h, w))
    for k in range(n_bolts):
        x0 = w * (0.2 + 0.6 * (k + rng.uniform(0.2, 0.8)) / n_bolts)
        trunk = _bolt(rng, (x0, h * rng.uniform(0.25, 0.35)), h * rng.uniform(0.5, 0.62), np.pi / 2)
        bolts.append(trunk)
        for _ in range(rng.integers(2, 4)):
            i = rng.integers(3, len(trunk) * 2 // 3)
            side = _bolt(rng, trunk[i], rng.uniform(30, 60), np.pi / 2 + rng.choice([-1, 1]) * rng.uniform(0.5, 0.9))
            bolts.append(side)
    from skimage.draw import line_aa

    for k, b in enumerate(bolts):
        amp = rng.uniform(0.5, 0.8) if k < n_bolts else rng.uniform(0.3, 0.55)
        for p, q in zip(b[:-1], b[1:]):
            rr, cc, v = line_aa(int(round(p[1])), int(round(p[0])), int(round(q[1])), int(round(q[0])))
            ok = (rr >= 0) & (rr < h) & (cc >= 0) & (cc < w)
            lines[rr[ok], cc[ok]] = np.maximum(lines[rr[ok], cc[ok]], amp * v[ok])
    core = ndi.gaussian_filter(lines, core) * 1.6
    glow = ndi.gaussian_filter(lines, glow) * 0.8
    lum = lum + np.clip(core, 0, 0.6) + glow
    if dots:
        yb = h - rng.uniform(16, 30)
        xs = np.arange(rng.uniform(3, 8), w - 3, rng.uniform(5, 9))
        xs = xs[rng.random(len(xs)) < 0.8]
        for xd in xs:
            r = rng.uniform(1.2, 2.2)
            lum = lum + 0.8 * np.exp(-((x - xd) ** 2 + (y - yb - rng.normal(0, 1)) ** 2) / (2 * r * r))
    lum = lum + rng.normal(0, 0.01, lum.shape)
    lum = np.clip(lum, 0, 1)
    tint = np.array([0.85, 0.55, 0.9])
    img = np.clip(lum[..., None] * tint + (lum[..., None] ** 2) * (1 - tint) * 0.9, 0, 1)
    return img.astype(np.float32), [b[(b[:, 0] >= 0) & (b[:, 0] < w) & (b[:, 1] >= 0) & (b[:, 1] < h)]
                                     for b in bolts]


def bolt_scores(structure, bolts, shape, tol: float = 4.0):
    """(precision, recall): traced vertices within ``tol`` px of a bolt; bolt points within ``tol`` of a trace."""
    from ..core.polyline import resample_uniform

    h, w = shape
    truth = np.ones((h, w), bool)
    for b in bolts:
        q = resample_uniform(b, 1.0) if len(b) > 1 else b
        ij = np.round(q[:, ::-1]).astype(int)
        ok = (ij[:, 0] >= 0) & (ij[:, 0] < h) & (ij[:, 1] >= 0) & (ij[:, 1] < w)
        truth[ij[ok, 0], ij[ok, 1]] = False
    d_truth = ndi.distance_transform_edt(truth)
    traced = np.ones((h, w), bool)
    pts = []
    for br in structure.branches:
        q = resample_uniform(br.points, 1.0) if len(br.points) > 1 else br.points
        pts.append(q)
    if not pts:
        return 0.0, 0.0
    p = np.concatenate(pts)
    ij = np.clip(np.round(p[:, ::-1]).astype(int), 0, [h - 1, w - 1])
    traced[ij[:, 0], ij[:, 1]] = False
    d_tr = ndi.distance_transform_edt(traced)
    prec = float(np.mean(d_truth[ij[:, 0], ij[:, 1]] <= tol))
    bp = np.concatenate([resample_uniform(b, 1.0) for b in bolts if len(b) > 1])
    bij = np.clip(np.round(bp[:, ::-1]).astype(int), 0, [h - 1, w - 1])
    rec = float(np.mean(d_tr[bij[:, 0], bij[:, 1]] <= tol))
    return prec, rec


def city_row_example(shape=(384, 512), seed=0, *, spacing: float = 5.0, radius: float = 1.4, amp: float = 0.9,
                     curve: float = 0.0, jitter: float = 0.5):
    """A night storm (no cloud dots) with a row of warm city lights of a chosen density along the bottom.

    Dots every ``spacing`` px (15 % missing) of about ``radius`` px, brightness up to ``amp``, on a row
    bending up by ``curve`` px in the middle, each ``jitter`` px off it. Close dots merge into one
    ridge whose brightness still rises and falls at every dot.

    Returns
    -------
    image : (H, W, 3) float32
    bolts : list of (n, 2) arrays (as :func:`storm_example`)
    row : (m, 2) float array
        The row's centre line, one point per pixel column from its first dot to its last.
    """
    rng = np.random.default_rng(100 + seed)
    img, bolts = storm_example(shape, seed, dots=False)
    h, w = shape
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    lum = np.zeros((h, w))
    yb = h - rng.uniform(14, 26)
    xs = np.arange(rng.uniform(3, 8), w - 3, spacing)
    xs = xs[rng.random(len(xs)) < 0.85]

    def row(xx):
        return yb - curve * np.sin(np.pi * xx / w)

    for xd in xs:
        r = radius * rng.uniform(0.7, 1.3)
        lum += amp * rng.uniform(0.6, 1.0) * np.exp(-((x - xd) ** 2 + (y - row(xd) - rng.normal(0, jitter)) ** 2)
                                                    / (2 * r * r))
    img = np.clip(img + lum[..., None] * np.array([1.0, 0.85, 0.55]), 0, 1).astype(np.float32)
    xr = np.arange(xs.min(), xs.max())
    return img, bolts, np.c_[xr, row(xr)]


def row_traced_share(structure, row, tol: float = 4.0) -> float:
    """Share of a light row's points within ``tol`` px of the traced structure."""
    from ..core.polyline import resample_uniform

    if not structure.branches:
        return 0.0
    p = np.vstack([resample_uniform(b.points, 1.0) if len(b.points) > 1 else b.points for b in structure.branches])
    from scipy.spatial import cKDTree

    d, _ = cKDTree(p).query(np.asarray(row, np.float64))
    return float(np.mean(d <= tol))
