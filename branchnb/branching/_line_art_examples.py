"""Line-art examples with known answers.

* :func:`drawn_tree_example`: a drawn tree with a crown, a ground line and
  roots, a coloured branching shape among flat areas (extraction must follow
  the tree's colour, however wide, not the crown's rim or the grass);
* :func:`crack_drawing_example`: a network of thin dark lines on white (a
  drawn crack pattern; synthesized drawings must keep their lines whole).
"""
from __future__ import annotations

import numpy as np

from ..core.random import as_rng

TRUNK = (0.48, 0.34, 0.09)
CROWN = (0.01, 0.55, 0.0)
CROWN_RIM = (0.0, 0.35, 0.0)
GRASS = (0.3, 0.75, 0.3)


def drawn_tree_example(size: int = 320, rng=0) -> tuple[np.ndarray, np.ndarray]:
    """A flat-colour tree drawing and the mask of its trunk, branches and roots.

    Parameters
    ----------
    size : int, default 320
        Side of the square image (pixels); every length scales with it.
    rng : int or numpy.random.Generator, default 0
        Seed for the crown's discs and the branch angles.

    Returns
    -------
    image : (size, size, 3) float32
        White ground, a green crown of overlapping discs with a dark rim,
        brown branches drawn over it, a grass line with blades across the
        trunk, roots below.
    tree : (size, size) bool
        The brown pixels (the structure's truth).

    Examples
    --------
    >>> img, tree = drawn_tree_example(160, rng=0)
    >>> img.shape, bool(tree.any())
    ((160, 160, 3), True)
    """
    import cv2

    r = as_rng(rng)
    h = w = int(size)
    s = size / 320
    img = np.ones((h, w, 3), np.float32)
    cx, cy = w / 2, 0.3 * h
    for _ in range(6):
        c = (int(cx + r.uniform(-60, 60) * s), int(cy + r.uniform(-25, 25) * s))
        cv2.circle(img, c, int(r.uniform(35, 50) * s), CROWN_RIM, -1, cv2.LINE_AA)
    crown = np.all(np.abs(img - np.array(CROWN_RIM, np.float32)) < 0.02, -1)
    img[cv2.erode(crown.astype(np.uint8), np.ones((5, 5), np.uint8)) > 0] = CROWN
    ground = int(0.62 * h)
    tree = np.zeros((h, w), np.uint8)

    def limb(p, angle, length, width, depth):
        q = (p[0] + length * np.cos(angle), p[1] + length * np.sin(angle))
        cv2.line(tree, (int(p[0]), int(p[1])), (int(q[0]), int(q[1])), 255, max(1, int(width)), cv2.LINE_AA)
        if depth:
            for turn in (-0.5, 0.45):
                limb(q, angle + turn + r.uniform(-0.15, 0.15), 0.72 * length, 0.6 * width, depth - 1)

    limb((w / 2, ground), -np.pi / 2, 0.16 * h, 12 * s, 3)
    limb((w / 2, ground), np.pi / 2, 0.1 * h, 10 * s, 3)
    a = tree.astype(np.float32)[..., None] / 255
    img = img * (1 - a) + np.asarray(TRUNK, np.float32) * a
    for x in range(4, w - 4, max(3, int(9 * s))):
        tip = (x + int(r.integers(-3, 4)), ground - int(r.uniform(6, 14) * s))
        cv2.line(img, (x, ground), tip, GRASS, 1, cv2.LINE_AA)
    cv2.line(img, (0, ground), (w - 1, ground), GRASS, 2)
    return np.clip(img, 0, 1).astype(np.float32), tree > 127


def crack_drawing_example(size: int = 256, rng=0, *, cells: int = 30, width: int = 2) -> np.ndarray:
    """A crack pattern drawn as thin dark lines on white: the edges of a Voronoi diagram.

    Parameters
    ----------
    size : int, default 256
        Side of the square image (pixels).
    rng : int or numpy.random.Generator, default 0
        Seed for the cell centres.
    cells : int, default 30
        Number of Voronoi cells.
    width : int, default 2
        Line width (pixels).

    Returns
    -------
    (size, size, 3) float32
        The drawing.

    Examples
    --------
    >>> img = crack_drawing_example(128, rng=0)
    >>> img.shape, bool((img < 0.5).any())
    ((128, 128, 3), True)
    """
    import cv2
    from scipy.spatial import Voronoi

    r = as_rng(rng)
    pts = r.uniform(0, size, (int(cells), 2))
    vor = Voronoi(pts)
    img = np.ones((size, size, 3), np.float32)
    for a, b in vor.ridge_vertices:
        if a >= 0 and b >= 0:
            p, q = vor.vertices[a], vor.vertices[b]
            if np.all(np.abs(np.concatenate([p, q])) < 4 * size):
                cv2.line(img, (int(p[0]), int(p[1])), (int(q[0]), int(q[1])), (0.1, 0.1, 0.1), int(width),
                         cv2.LINE_AA)
    return img


def vine_example(size: int = 512, rng=0, *, leaves: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """A border vine: one wavy stem along the top of the frame with side strands that leave it at
    shallow angles (15-40 degrees) and curl at their ends, optionally with leaf stubs (issue 23).

    Parameters
    ----------
    size : int, default 512
        Width of the image (pixels); the height is 0.6-0.9 x the width and every length scales with it.
    rng : int or numpy.random.Generator, default 0
        Seed for the stem's waves, the side strands and the leaves.
    leaves : bool, default False
        Small filled leaves on short stalks along the stem.

    Returns
    -------
    image : (H, size, 3) float32
        Black lines on white.
    angles : (n,) float64 ndarray
        The known answer: the angle (degrees) at which each side strand leaves the stem.

    Examples
    --------
    >>> img, ang = vine_example(256, rng=0)
    >>> img.shape[1], bool((img < 0.5).any()), bool(((ang >= 15) & (ang <= 40)).all())
    (256, True, True)
    """
    import cv2

    r = as_rng(rng)
    W = int(size)
    H = int(size * r.uniform(0.6, 0.9))
    lw = max(2, int(round(size / r.uniform(120, 160))))
    y0 = size * r.uniform(0.15, 0.18)
    amp = size * r.uniform(0.012, 0.022)
    period = size * r.uniform(0.3, 0.45)
    ph = r.uniform(0, 2 * np.pi)
    x = np.arange(0.0, W, 1.0)
    stem = np.c_[x, y0 + amp * np.sin(2 * np.pi * x / period + ph)]
    img = np.zeros((H, W), np.uint8)
    cv2.polylines(img, [np.round(stem * 8).astype(np.int32)], False, 255, lw, cv2.LINE_AA, 3)
    angles = []
    gap = size * r.uniform(0.1, 0.14)
    s = r.uniform(0.3, 0.7) * gap
    side = 1 if r.random() < 0.5 else -1
    while s < W - 0.12 * size:
        i = int(s)
        t = stem[min(i + 3, W - 1)] - stem[max(i - 3, 0)]
        a0 = np.arctan2(t[1], t[0])
        beta = np.radians(r.uniform(15, 40))
        ln = size * r.uniform(0.08, 0.14)
        n = int(ln)
        curl = np.linspace(0, 1, n) ** 3 * r.uniform(2.5, 4.0)     # curls only toward its end
        head = a0 + side * (beta + curl)
        pts = stem[i] + np.cumsum(np.c_[np.cos(head), np.sin(head)], axis=0)
        pts[:, 1] = np.clip(pts[:, 1], 2, H - 3)
        cv2.polylines(img, [np.round(pts * 8).astype(np.int32)], False, 255, max(1, lw - 1), cv2.LINE_AA, 3)
        angles.append(np.degrees(beta))
        if leaves and r.random() < 0.7:
            k = int(r.uniform(0.3, 0.6) * gap)
            j = min(i + k, W - 1)
            nrm = np.array([-np.sin(a0), np.cos(a0)]) * -side
            ls = max(3.0, 0.012 * size)
            c = stem[j] + nrm * ls * 1.6
            ang = float(np.degrees(np.arctan2(nrm[1], nrm[0])))
            cv2.ellipse(img, (int(c[0] * 8), int(c[1] * 8)), (int(ls * 1.4 * 8), int(ls * 0.7 * 8)), ang, 0, 360,
                        255, -1, cv2.LINE_AA, 3)
        s += gap * r.uniform(0.8, 1.2)
        side = -side
    out = 1.0 - img.astype(np.float32) / 255.0
    return np.repeat(out[..., None], 3, axis=2), np.asarray(angles, np.float64)


def vine_envelope(size: int = 512, rng=0, *, leaves: bool = False) -> np.ndarray:
    """The known band of :func:`vine_example` (same arguments): (H, W) bool, the rows between the
    highest and lowest ink of the vine (its stem runs along the frame's width), plus the pen."""
    img = vine_example(size, rng=rng, leaves=leaves)[0]
    rows = np.flatnonzero((img[..., 0] < 0.5).any(1))
    lw = max(2, int(round(size / 120)))
    out = np.zeros(img.shape[:2], bool)
    out[max(rows.min() - lw, 0): rows.max() + lw + 1] = True
    return out
