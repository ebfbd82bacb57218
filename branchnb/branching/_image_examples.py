"""Small procedural examples with a known structure (tests, bench, gallery).

``river_example`` draws a branching river on a textured ground, so the
exact source structure is known; ``random_tree`` makes structures of the
same family to use as targets.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.random import as_rng
from ..core.render import draw_polylines
from ..core.structure import Branch, Structure


def _walk(rng, start, heading, length, step=4.0, wiggle=0.18):
    pts = [np.asarray(start, float)]
    h = heading
    for _ in range(int(length / step)):
        h += rng.normal(0, wiggle)
        pts.append(pts[-1] + step * np.array([np.cos(h), np.sin(h)]))
    return np.array(pts)


def random_tree(shape=(256, 256), rng=0, *, n_children: int = 3, r_root: float = 4.0,
                r_child: float = 2.5, grandchildren: int = 0) -> Structure:
    """A root crossing the image from the left plus children (and grandchildren)."""
    rng = as_rng(rng)
    h, w = shape
    margin = 8.0
    y = rng.uniform(0.35, 0.65) * h
    root = _walk(rng, (margin, y), rng.normal(0, 0.15), w - 2 * margin, wiggle=0.12)
    root = root[(root[:, 0] < w - margin) & (root[:, 1] > margin) & (root[:, 1] < h - margin)]
    branches = [Branch(root, np.linspace(r_root, r_root * 0.8, len(root)))]

    def grow(parent, n, r0, length):
        pts = branches[parent].points
        idx = np.sort(rng.choice(np.arange(len(pts) // 6, len(pts) * 5 // 6), n, replace=False))
        for v in idx:
            t = pts[min(v + 1, len(pts) - 1)] - pts[max(v - 1, 0)]
            base = np.arctan2(t[1], t[0])
            side = rng.choice([-1, 1])
            walk = _walk(rng, pts[v], base + side * rng.uniform(0.5, 1.0), length)
            inside = (walk[:, 0] > margin) & (walk[:, 0] < w - margin) & \
                     (walk[:, 1] > margin) & (walk[:, 1] < h - margin)
            stop = np.flatnonzero(~inside)
            walk = walk[: stop[0]] if len(stop) else walk
            if len(walk) < 4:
                continue
            r = np.linspace(r0, max(r0 * 0.45, 0.8), len(walk))
            branches.append(Branch(walk, r, parent, int(v)))

    grow(0, n_children, r_child, 0.45 * min(h, w))
    if grandchildren:
        for b in range(1, len(branches)):
            grow(b, grandchildren, r_child * 0.6, 0.2 * min(h, w))
    return Structure(branches, (h, w))


def textured_ground(shape=(256, 256), rng=0, colour=(0.62, 0.52, 0.36)) -> np.ndarray:
    """A grainy, blotchy ground texture."""
    rng = as_rng(rng)
    h, w = shape
    base = np.zeros((h, w))
    for sigma, amp in ((1.0, 0.05), (4.0, 0.06), (12.0, 0.08)):
        n = ndi.gaussian_filter(rng.normal(0, 1, (h, w)), sigma)
        base += amp * n / (n.std() + 1e-9)
    img = np.asarray(colour)[None, None, :] * (1.0 + base[:, :, None])
    img += 0.02 * rng.normal(0, 1, (h, w, 3))
    return np.clip(img, 0, 1).astype(np.float32)


def river_example(shape=(256, 256), rng=0, **tree_kw) -> tuple[np.ndarray, Structure]:
    """A branching river (pale banks, dark water) on textured ground, with its structure."""
    rng = as_rng(rng)
    s = random_tree(shape, rng, **tree_kw)
    img = textured_ground(shape, rng)
    lines = [b.points for b in s.branches]
    img = draw_polylines(img, lines, widths=[2 * b.thickness + 4 for b in s.branches],
                         colors=(0.78, 0.72, 0.58))
    water = draw_polylines(np.zeros(shape + (3,), np.float32), lines,
                           widths=[2 * b.thickness for b in s.branches], colors=(1, 1, 1))[:, :, 0]
    ripple = ndi.gaussian_filter(rng.normal(0, 1, shape), 1.5)
    ripple = 0.06 * ripple / (ripple.std() + 1e-9)
    blue = np.array([0.16, 0.28, 0.42])[None, None, :] * (1 + ripple[:, :, None])
    img = img * (1 - water[:, :, None]) + blue * water[:, :, None]
    return np.clip(img, 0, 1).astype(np.float32), s


def cracked_mud_example(shape=(256, 256), rng=0, *, cells: int | None = None,
                        width: float = 2.5) -> tuple[np.ndarray, np.ndarray]:
    """Cracked mud: dark Voronoi cracks (with a darker core) on a blotchy mud texture.

    Parameters
    ----------
    shape : (H, W), default (256, 256)
        Image size.
    rng : int or numpy.random.Generator, default 0
        Seed.
    cells : int, optional
        Number of mud cells; default one per ~48 x 48 px.
    width : float, default 2.5
        Crack width (pixels).

    Returns
    -------
    image : (H, W, 3) float32
        The example.
    cracks : (H, W) bool
        The crack pixels (where the crack covers at least half a pixel).

    Examples
    --------
    >>> img, cracks = cracked_mud_example((96, 96), 0)
    >>> img.shape, bool(img[cracks].mean() < 0.6 * img[~cracks].mean())
    ((96, 96, 3), True)
    """
    from scipy.spatial import Voronoi

    rng = as_rng(rng)
    h, w = shape
    n = int(cells) if cells is not None else max(6, round(h * w / 48 ** 2))
    pts = rng.uniform(0, 1, (n, 2)) * (w, h)
    # mirror the centres across the frame so every cell is closed
    allp = np.vstack([pts, pts * (-1, 1), pts * (1, -1), (2 * w, 0) + pts * (-1, 1), (0, 2 * h) + pts * (1, -1)])
    vor = Voronoi(allp)
    lines = [vor.vertices[[a, b]] for a, b in vor.ridge_vertices if a >= 0 and b >= 0]
    lines = [pl for pl in lines if np.all(pl > -w) and np.all(pl < 2 * max(h, w))]
    img = textured_ground(shape, rng, colour=(0.66, 0.53, 0.38))
    cov = draw_polylines(np.zeros((h, w, 3), np.float32), lines, widths=width, colors=(1, 1, 1))[..., 0]
    core = draw_polylines(np.zeros((h, w, 3), np.float32), lines, widths=max(width - 1.5, 1.0),
                          colors=(1, 1, 1))[..., 0]
    crack = np.array([0.30, 0.22, 0.15], np.float32)
    img = img * (1 - cov[..., None]) + crack * cov[..., None]
    img = img * (1 - 0.5 * core[..., None])
    return np.clip(img, 0, 1).astype(np.float32), cov >= 0.5
