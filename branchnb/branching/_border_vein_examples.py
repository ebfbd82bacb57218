"""Two more procedural kinds with known answers (issue 23): a two-country map and leaf veins.

``two_country_map_example`` draws a political map: two land regions of
different flat colours separated by a drawn black border line, a black
coast against a flat sea, and black rivers of one width that cross the
border. ``leaf_vein_example`` draws a leaf: a green blade on a pale grey
table with paler, tapering veins (a midrib from the stalk, secondary veins
and a few tertiary ones) and a mottled, photo-like texture. Private: used
by the tests and the issue-23 figures.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.random import as_rng
from ..core.render import coverage_polylines, draw_polylines
from ..core.structure import Branch, Structure
from ._map_examples import INK, LAND, SEA, _drawn_rivers

__all__ = ["LAND_B", "two_country_map_example", "leaf_vein_example"]

LAND_B = (0.80, 0.90, 0.72)


def _border_curve(land: np.ndarray, rng) -> np.ndarray:
    """A wavy, roughly north-south line through the land's middle: (n, 2) (x, y) points."""
    h, w = land.shape
    ys = np.arange(0, h, 1.0)
    cols = np.flatnonzero(land.any(0))
    x0 = 0.5 * (cols.min() + cols.max()) + rng.normal(0, 0.04 * w)
    xs = x0 + sum(rng.uniform(0.02, 0.05) * w * np.sin(2 * np.pi * k * ys / h + rng.uniform(0, 2 * np.pi))
                  for k in (1, 2, 4))
    return np.c_[xs, ys]


def two_country_map_example(shape=(512, 512), rng=0, *, layout: str = "island", n_trees: int | None = None,
                            line_width: float | None = None):
    """Two countries on one land mass: flat colours, a black border between them, a black coast, rivers.

    Returns
    -------
    image : (H, W, 3) float32
    structure : Structure
        The drawn rivers (one root per river, its first vertex at the mouth).
    land : (H, W) bool
        Both countries (the rivers' domain).
    west : (H, W) bool
        The first country (``land & ~west`` is the second).
    border : (n, 2) float
        The border's centre line inside the land.

    Examples
    --------
    >>> img, s, land, west, border = two_country_map_example((200, 200), 0)
    >>> bool(west.any() and (land & ~west).any())
    True
    """
    rng = as_rng(rng)
    h, w = shape
    land, s, lw = _drawn_rivers(shape, rng, layout, n_trees, line_width)
    curve = _border_curve(land, rng)
    yy, xx = np.mgrid[0:h, 0:w]
    west = land & (xx < np.interp(yy, curve[:, 1], curve[:, 0]))
    ins = land[np.clip(np.rint(curve[:, 1]).astype(int), 0, h - 1),
               np.clip(np.rint(curve[:, 0]).astype(int), 0, w - 1)]
    border = curve[ins]
    img = np.empty(tuple(shape) + (3,), np.float32)
    img[:] = SEA
    img[land] = LAND_B
    img[west] = LAND
    from skimage import measure

    coast = []
    for c in measure.find_contours(land.astype(np.float32), 0.5):
        pts = c[:, ::-1]
        on_frame = (pts[:, 0] <= 0.5) | (pts[:, 1] <= 0.5) | (pts[:, 0] >= w - 1.5) | (pts[:, 1] >= h - 1.5)
        cut = np.flatnonzero(np.diff(on_frame.astype(int)))
        for piece in np.split(np.arange(len(pts)), cut + 1):
            if len(piece) > 2 and not on_frame[piece].all():
                coast.append(pts[piece])
    runs = np.split(np.arange(len(curve)), np.flatnonzero(np.diff(ins.astype(int))) + 1)
    borders = [curve[r] for r in runs if ins[r[0]] and len(r) > 2]
    pls = [b.points for b in s.branches] + coast + borders
    cov, _ = coverage_polylines(tuple(shape), pls, [np.full(len(p), lw) for p in pls])
    img = img * (1 - cov[..., None]) + np.asarray(INK, np.float32) * cov[..., None]
    return img.astype(np.float32), s, land, west, border


def _vein(rng, start, heading, length, step=2.0, wiggle=0.04, curl=0.0):
    pts = [np.asarray(start, float)]
    th = heading
    for _ in range(max(int(length / step), 2)):
        th += curl + rng.normal(0, wiggle)
        pts.append(pts[-1] + step * np.array([np.cos(th), np.sin(th)]))
    return np.array(pts)


def leaf_vein_example(shape=(512, 512), rng=0):
    """A leaf photo-like image: a mottled green blade on a pale table, paler tapering veins.

    Returns
    -------
    image : (H, W, 3) float32
    structure : Structure
        The veins (one root: the midrib, entering at the stalk near the bottom).
    blade : (H, W) bool
        The leaf blade (the veins' domain).

    Examples
    --------
    >>> img, s, blade = leaf_vein_example((160, 160), 0)
    >>> bool(blade.mean() > 0.2), sum(b.parent is None for b in s.branches)
    (True, 1)
    """
    rng = as_rng(rng)
    h, w = shape
    size = min(h, w)
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float64)
    # blade: an ovate outline along the vertical axis, base at the bottom, tip at the top
    y0, y1 = 0.9 * h, 0.06 * h
    cx = 0.5 * w + rng.normal(0, 0.02 * w)
    t = np.clip((y0 - yy) / (y0 - y1), 0, 1)
    half = 0.40 * w * np.sin(np.pi * t ** 0.8) ** 1.1 * (1 + 0.04 * np.sin(2 * np.pi * 5 * t + rng.uniform(0, 6)))
    blade = (np.abs(xx - cx) < half) & (yy < y0) & (yy > y1)
    r0 = max(1.2, 4.0 * size / 512)
    # midrib from the stalk (below the blade) to near the tip
    mid = _vein(rng, (cx, min(h - 2.0, y0 + 0.06 * h)), -np.pi / 2, (y0 - y1) * 1.02, wiggle=0.015)
    inside = np.ones(len(mid), bool)
    branches = [Branch(mid, np.linspace(r0, 0.35 * r0, len(mid)))]
    step_v = max(6, int(0.08 * size))
    for side in (-1, 1):
        for v in range(int(0.12 * len(mid)) + rng.integers(0, 4), int(0.9 * len(mid)), step_v // 2):
            if not inside[v]:
                continue
            head = -np.pi / 2 + side * rng.uniform(0.75, 1.0)
            length = 0.6 * w * np.sin(np.pi * min(v / len(mid), 0.95)) + 0.05 * w
            sec = _vein(rng, mid[v], head, length, wiggle=0.05, curl=-side * 0.006)
            ok = blade[np.clip(np.rint(sec[:, 1]).astype(int), 0, h - 1),
                       np.clip(np.rint(sec[:, 0]).astype(int), 0, w - 1)]
            stop = int(np.argmin(ok[1:])) + 1 if not ok[1:].all() else len(sec)
            sec = sec[:max(stop - int(0.02 * size), 2)]
            if len(sec) < 6:
                continue
            rs = 0.55 * branches[0].thickness[v]
            k = len(branches)
            branches.append(Branch(sec, np.linspace(rs, 0.3 * rs + 0.3, len(sec)), 0, int(v)))
            for u in range(len(sec) // 3, len(sec) - 4, max(5, len(sec) // 3)):
                hd = np.arctan2(*(sec[u + 1] - sec[u - 1])[::-1]) + side * rng.uniform(0.6, 1.0)
                ter = _vein(rng, sec[u], hd, rng.uniform(0.04, 0.08) * size, wiggle=0.1)
                ok = blade[np.clip(np.rint(ter[:, 1]).astype(int), 0, h - 1),
                           np.clip(np.rint(ter[:, 0]).astype(int), 0, w - 1)]
                if ok.all() and len(ter) >= 4:
                    rt = 0.6 * branches[k].thickness[u]
                    branches.append(Branch(ter, np.linspace(rt, 0.5 * rt + 0.2, len(ter)), k, int(u)))
    s = Structure(branches, image_shape=tuple(shape))
    # photo-like: a pale table with soft shading, a mottled blade, a darker rim, paler veins
    table = 0.86 - 0.08 * yy / h + 0.02 * ndi.gaussian_filter(rng.normal(0, 1, (h, w)), 3)
    img = np.repeat(table[..., None], 3, axis=2) * np.array([1.0, 0.99, 0.96])
    mott = sum(a * ndi.gaussian_filter(rng.normal(0, 1, (h, w)), sg * size / 512) for sg, a in ((2, 0.5), (10, 2.5)))
    mott = 0.05 * mott / (mott.std() + 1e-9)
    green = np.array([0.22, 0.45, 0.12])[None, None] * (1 + mott[..., None])
    soft = ndi.gaussian_filter(blade.astype(float), 1.0)[..., None]
    rim = ndi.distance_transform_edt(blade)
    green = green * (0.8 + 0.2 * np.clip(rim / (0.05 * size), 0, 1))[..., None]
    img = img * (1 - soft) + green * soft
    img = draw_polylines(img.astype(np.float32), [b.points for b in branches],
                         widths=[2 * b.thickness for b in branches], colors=(0.55, 0.70, 0.30))
    img = img + rng.normal(0, 0.012, img.shape)
    return np.clip(img, 0, 1).astype(np.float32), s, blade
