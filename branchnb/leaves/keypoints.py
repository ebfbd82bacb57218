"""Keypoints for registration: about 100 points on strong edges, spread over the leaf.

The paper places about 100 feature points on strong edges: the Sobel
gradient magnitude of a bilateral-filtered image (the filter keeps the
veins' and the outline's edges and removes texture noise). Points are
taken greedily by decreasing edge strength with a minimum spacing, so
they spread over the whole leaf instead of clumping on the strongest
edge. The blade outline is the strongest and most reliable structure a
set of leaves of one kind shares, so a fixed fraction of the points is
placed evenly along it (by arc length) and carries the label
``OUTLINE``; the rest, on interior edges (veins, spots), is labelled
``INTERIOR``. Registration matches points of one label with each other.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.distance import edt as _edt
from ..core.image import as_float_image, as_mask
from ..core.validate import Int, Real, checked

__all__ = ["Keypoints", "edge_keypoints", "edge_strength", "vein_keypoints", "vein_strength",
           "OUTLINE", "INTERIOR", "VEIN"]

OUTLINE = 0
INTERIOR = 1
VEIN = 2


@dataclass
class Keypoints:
    """Points ``(x, y)`` with a label each (:data:`OUTLINE` or :data:`INTERIOR`).

    Parameters
    ----------
    points : (K, 2) float ndarray
        Keypoint positions ``(x, y)`` in image pixels.
    labels : (K,) int64 ndarray
        :data:`OUTLINE` (0), :data:`INTERIOR` (1) or :data:`VEIN` (2) per
        point; registration matches points of one label with each other.
    strength : (K,) float ndarray
        The edge (:func:`edge_strength`) or vein (:func:`vein_strength`)
        strength at each point.
    orientation : (K,) float ndarray, optional
        Radians mod pi (image axes) of the vein through each :data:`VEIN`
        point; None for edge keypoints.
    """

    points: np.ndarray
    labels: np.ndarray
    strength: np.ndarray
    orientation: np.ndarray | None = None  # radians mod pi, of the vein through a VEIN point

    def __len__(self) -> int:
        return len(self.points)


def _same_shape(mask, shape, name):
    if np.shape(mask) != tuple(shape):
        raise ValueError(f"{name} has shape {np.shape(mask)}, but image is {tuple(shape)} (they must match)")
    return mask


@checked(diameter=Int(1, 64), sigma_color=Real(0.0, 1e3, low_open=True),
         sigma_space=Real(0.0, 1e3, low_open=True))
def edge_strength(image, mask=None, *, diameter: int | None = None, sigma_color: float = 0.1,
                  sigma_space: float | None = None) -> np.ndarray:
    """Sobel gradient magnitude of the bilateral-filtered luminance.

    Parameters
    ----------
    image : (H, W, C) array_like
        The leaf, float in [0, 1] (or uint8); reduced to its luminance.
    mask : (H, W) bool array_like, optional
        Outside the mask the image is replaced by the mean colour inside it
        first, so the background does not create edges of its own.
    diameter : int, optional
        Bilateral filter diameter; default ``max(5, min(H, W) // 60)`` (odd).
    sigma_color : float
        Bilateral range sigma (in [0, 1] intensity units).
    sigma_space : float, optional
        Bilateral spatial sigma; default ``diameter / 2``.

    Returns
    -------
    (H, W) float32 ndarray

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((20, 20)); img[:, 10:] = 1
    >>> e = edge_strength(img)
    >>> int(np.argmax(e[10]))  in (9, 10)
    True
    """
    img = as_float_image(image)
    h, w = img.shape[:2]
    if img.shape[2] >= 3:
        gray = cv2.cvtColor(np.ascontiguousarray(img[:, :, :3]), cv2.COLOR_RGB2GRAY)
    else:
        gray = np.ascontiguousarray(img[:, :, 0])
    if mask is not None:
        m = as_mask(_same_shape(mask, (h, w), "mask"), shape=(h, w), name="mask")
        if m.any():
            gray = np.where(m, gray, float(gray[m].mean())).astype(np.float32)
    d = int(diameter) if diameter is not None else max(5, min(h, w) // 60)
    if d < 1:
        raise ValueError(f"diameter must be >= 1, got {diameter}")
    d |= 1
    ss = float(sigma_space) if sigma_space is not None else d / 2.0
    smooth = cv2.bilateralFilter(gray.astype(np.float32), d, float(sigma_color), ss)
    gx = cv2.Sobel(smooth, cv2.CV_32F, 1, 0, ksize=3)
    gy = cv2.Sobel(smooth, cv2.CV_32F, 0, 1, ksize=3)
    return np.hypot(gx, gy).astype(np.float32)


def _outline_points(blade: np.ndarray, n: int) -> np.ndarray:
    """``n`` points evenly spaced (arc length) along the outer contours of ``blade``."""
    contours, _ = cv2.findContours(blade.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    contours = [c[:, 0, :].astype(np.float64) for c in contours if len(c) >= 3]
    if not contours or n <= 0:
        return np.zeros((0, 2))
    lengths = []
    for c in contours:
        seg = np.diff(np.vstack([c, c[:1]]), axis=0)
        lengths.append(np.hypot(seg[:, 0], seg[:, 1]).sum())
    total = float(sum(lengths))
    out = []
    for c, length in zip(contours, lengths):
        k = int(round(n * length / total))
        if k == 0:
            continue
        closed = np.vstack([c, c[:1]])
        seg = np.hypot(*np.diff(closed, axis=0).T)
        s = np.concatenate([[0.0], np.cumsum(seg)])
        t = (np.arange(k) + 0.5) * s[-1] / k
        out.append(np.column_stack([np.interp(t, s, closed[:, 0]), np.interp(t, s, closed[:, 1])]))
    return np.vstack(out) if out else np.zeros((0, 2))


@checked(n_points=Int(1, 10_000), outline_fraction=Real(0.0, 1.0), min_distance=Real(0.0, 1e5),
         margin=Real(0.0, 1e5), relative_threshold=Real(0.0, 1.0))
def edge_keypoints(image, blade, n_points: int = 100, *, outline_fraction: float = 0.35,
                   min_distance: float | None = None, margin: float | None = None,
                   relative_threshold: float = 0.15, **edge_kwargs) -> Keypoints:
    """About ``n_points`` keypoints on strong edges of a leaf, spread over it.

    Parameters
    ----------
    image : (H, W, C) array_like
        The leaf, float in [0, 1] (or uint8).
    blade : (H, W) bool array_like
        The leaf's mask; points lie on its outline or inside it.
    n_points : int
        Target number of points (the paper: about 100). Fewer come back
        when the leaf has too few strong interior edges at the spacing.
    outline_fraction : float
        Fraction of the points placed evenly along the blade outline.
    min_distance : float, optional
        Minimum spacing of interior points; default
        ``0.6 sqrt(blade area / n_interior)``, so the points can cover the blade.
    margin : float, optional
        Interior points stay this far inside the outline (pixels); default
        ``min_distance / 2``, so they do not duplicate the outline points.
    relative_threshold : float
        Interior points need an edge strength of at least this fraction of
        the 99th percentile of the strength inside the blade.
    **edge_kwargs
        Passed to :func:`edge_strength` (bilateral filter settings).

    Returns
    -------
    Keypoints

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((64, 64, 3)); blade = np.zeros((64, 64), bool); blade[8:56, 8:56] = True
    >>> img[blade] = 0.4; img[30:34, 10:54] = 0.1
    >>> kp = edge_keypoints(img, blade, 40)
    >>> bool((kp.labels == 0).sum() >= 10), bool((kp.labels == 1).sum() >= 4)
    (True, True)
    """
    img = as_float_image(image)
    h, w = img.shape[:2]
    m = as_mask(_same_shape(blade, (h, w), "blade"), shape=(h, w), name="blade")
    if m.sum() < 16:
        raise ValueError(f"blade has only {int(m.sum())} pixels: no leaf to place keypoints on")
    if isinstance(n_points, bool) or not isinstance(n_points, (int, np.integer)) or n_points < 4:
        raise ValueError(f"n_points must be an int >= 4, got {n_points!r}")
    if not 0.0 <= outline_fraction <= 1.0:
        raise ValueError(f"outline_fraction must be in [0, 1], got {outline_fraction}")
    if not 0.0 <= relative_threshold < 1.0:
        raise ValueError(f"relative_threshold must be in [0, 1), got {relative_threshold}")
    n_out = int(round(n_points * outline_fraction))
    n_in = n_points - n_out
    outline = _outline_points(m, n_out)
    strength = edge_strength(img, m, **edge_kwargs)
    area = float(m.sum())
    md = float(min_distance) if min_distance is not None else 0.6 * np.sqrt(area / max(n_in, 1))
    if md <= 0:
        raise ValueError(f"min_distance must be > 0, got {min_distance}")
    mg = float(margin) if margin is not None else md / 2.0
    inner = _edt(m) > mg
    interior = np.zeros((0, 2))
    s_in = np.zeros(0)
    if n_in > 0 and inner.any():
        s = np.where(inner, strength, 0.0)
        ref = float(np.percentile(strength[m], 99)) if m.any() else 0.0
        # Local maxima of the edge strength, strongest first.
        peak = (s == ndi.maximum_filter(s, size=3)) & (s > relative_threshold * ref) & (s > 1e-6)
        ys, xs = np.nonzero(peak)
        order = np.argsort(-s[ys, xs], kind="stable")
        ys, xs = ys[order], xs[order]
        # Greedy minimum spacing on a coarse occupancy grid (cell = md / sqrt 2,
        # so at most one point per cell and the 5 x 5 neighbourhood covers md).
        chosen = _spaced(xs, ys, md, n_in, h, w)
        if chosen:
            interior = np.asarray(chosen, np.float64)
            s_in = strength[interior[:, 1].astype(int), interior[:, 0].astype(int)].astype(np.float64)
    pts = np.vstack([outline, interior])
    labels = np.concatenate([np.full(len(outline), OUTLINE), np.full(len(interior), INTERIOR)]).astype(np.int64)
    s_out = strength[np.clip(np.round(outline[:, 1]).astype(int), 0, h - 1),
                     np.clip(np.round(outline[:, 0]).astype(int), 0, w - 1)].astype(np.float64)
    return Keypoints(pts, labels, np.concatenate([s_out, s_in]))


def _luminance(img: np.ndarray) -> np.ndarray:
    if img.shape[2] >= 3:
        return cv2.cvtColor(np.ascontiguousarray(img[:, :, :3]), cv2.COLOR_RGB2GRAY)
    return np.ascontiguousarray(img[:, :, 0])


def _line_average(r: np.ndarray, length: int, n_orientations: int = 12) -> tuple[np.ndarray, np.ndarray]:
    """Largest mean of ``r`` along a straight segment of ``length`` px centred on each pixel, and its angle."""
    size = max(int(length), 3) | 1
    c = size // 2
    best = np.zeros_like(r)
    angle = np.zeros(r.shape, np.float32)
    # Zero beyond the box of r's non-zero pixels grown by the kernel's
    # reach (the border is constant 0): filter that window only (a blade
    # covers about half of its canvas; 12 large filters were ~0.2 s a megapixel).
    ys, xs = np.nonzero(r.any(1))[0], np.nonzero(r.any(0))[0]
    if not len(ys):
        return best, angle
    y0, y1 = max(0, ys[0] - c - 1), min(r.shape[0], ys[-1] + c + 2)
    x0, x1 = max(0, xs[0] - c - 1), min(r.shape[1], xs[-1] + c + 2)
    win = np.ascontiguousarray(r[y0:y1, x0:x1])
    best_w, angle_w = best[y0:y1, x0:x1], angle[y0:y1, x0:x1]
    for k in range(n_orientations):
        th = np.pi * k / n_orientations
        ker = np.zeros((size, size), np.float32)
        dx, dy = c * np.cos(th), c * np.sin(th)
        cv2.line(ker, (int(round(c - dx)), int(round(c - dy))), (int(round(c + dx)), int(round(c + dy))),
                 1.0, 1, cv2.LINE_AA)
        ker /= ker.sum()
        resp = cv2.filter2D(win, -1, ker, borderType=cv2.BORDER_CONSTANT)
        better = resp > best_w
        best_w[better] = resp[better]
        angle_w[better] = th
    return best, angle


@checked(sigma=Real(0.0, 100.0, low_open=True), length=Real(0.0, 1e4, low_open=True))
def vein_strength(image, blade, *, sigma: float | None = None, length: float | None = None,
                  return_orientation: bool = False):
    """How much each pixel lies on a long, nearly straight vein (a ridge of the luminance).

    The ridge measure is the larger Hessian eigenvalue magnitude across
    the ridge less the gradient magnitude over ``sigma`` (bright veins:
    ``max(-lambda_2 - |grad| / sigma, 0)``; dark veins:
    ``max(lambda_1 - |grad| / sigma, 0)``; the polarity with the stronger
    response inside the blade wins), at scale ``sigma``: the gradient term
    removes the ridge-like response beside a step edge (a spot's rim). Main veins (a midrib and its
    secondaries, a palmate leaf's primaries) run long and nearly straight,
    the fine reticulum between them in short random pieces: the geometric
    mean of the ridge measure and its largest mean along a straight
    segment of ``length`` pixels (12 orientations) keeps the first and
    weakens the second. Pixels within ``2 sigma + 2`` of the outline are 0.

    Parameters
    ----------
    image : (H, W, C) array_like
        The leaf, float in [0, 1] (or uint8); reduced to its luminance.
    blade : (H, W) bool array_like
        The leaf's mask (at least 16 pixels); the response is 0 outside it.
    sigma : float, optional
        Ridge scale in pixels; default ``max(1, 0.012 R)`` with
        ``R = sqrt(blade area / pi)`` (main veins are about 1 % of a leaf wide).
    length : float, optional
        Segment length; default ``0.35 R``.

    return_orientation : bool
        Also return the angle (radians in ``[0, pi)``, image axes) of the
        best segment at each pixel: the vein's direction.

    Returns
    -------
    (H, W) float32 ndarray, or (strength, orientation)

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((64, 64, 3), 0.3); blade = np.zeros((64, 64), bool); blade[4:60, 4:60] = True
    >>> img[30:34, 8:56] = 0.8  # a long bright vein
    >>> v = vein_strength(img, blade, sigma=1.5)
    >>> bool(v[30:34, 32].max() > 5 * v[20, 32])
    True
    """
    from skimage.feature import hessian_matrix, hessian_matrix_eigvals

    img = as_float_image(image)
    h, w = img.shape[:2]
    m = as_mask(_same_shape(blade, (h, w), "blade"), shape=(h, w), name="blade")
    if m.sum() < 16:
        raise ValueError(f"blade has only {int(m.sum())} pixels: no leaf to find veins on")
    radius = float(np.sqrt(m.sum() / np.pi))
    s = float(sigma) if sigma is not None else max(1.0, 0.012 * radius)
    gray = _luminance(img)
    gray = np.where(m, gray, float(gray[m].mean())).astype(np.float32)
    l1, l2 = hessian_matrix_eigvals(hessian_matrix(gray, sigma=s, order="rc", use_gaussian_derivatives=False))
    inner = _edt(m) > 2 * s + 2
    if not inner.any():
        z = np.zeros((h, w), np.float32)
        return (z, z.copy()) if return_orientation else z
    # The bright side of a step edge (a dark spot's rim) curves like a ridge
    # too, but only a ridge is flat across its centre: at the curvature
    # peak of a smoothed step |grad| / sigma equals the curvature, so
    # subtracting it removes edges and keeps ridges.
    grad = ndi.gaussian_gradient_magnitude(gray, s) / s
    bright = np.where(inner, np.clip(-l2 - grad, 0, None), 0.0).astype(np.float32)
    dark = np.where(inner, np.clip(l1 - grad, 0, None), 0.0).astype(np.float32)
    # A bright ridge has weaker dark side bands (and vice versa): compare the peaks.
    r = bright if np.percentile(bright[inner], 99) >= np.percentile(dark[inner], 99) else dark
    seg = float(length) if length is not None else 0.35 * radius
    mean, angle = _line_average(r, int(round(seg)))
    out = np.sqrt(r * mean).astype(np.float32)
    return (out, angle) if return_orientation else out


@checked(n_points=Int(1, 10_000), quantile=Real(0.0, 1.0, high_open=True))
def vein_keypoints(image, blade, n_points: int = 60, *, quantile: float = 0.9, **strength_kwargs) -> Keypoints:
    """About ``n_points`` points spread along the main veins (label :data:`VEIN`).

    The pixels of the blade whose :func:`vein_strength` is above its
    ``quantile`` inside the blade are thinned to centre lines
    (skeletonised); points are taken strongest first with a minimum
    spacing of the centre lines' length over ``n_points``, so they cover
    the veins evenly. Not in the paper, which places its points on edges
    only (:func:`edge_keypoints`).

    Parameters
    ----------
    image : (H, W, C) array_like
        The leaf, float in [0, 1] (or uint8).
    blade : (H, W) bool array_like
        The leaf's mask (at least 16 pixels).
    n_points : int
        Target number of points (default 60); fewer come back on short veins.
    quantile : float
        Pixels above this quantile of the vein strength inside the blade
        count as vein (default 0.9: the strongest 10 %).
    **strength_kwargs
        Passed to :func:`vein_strength` (``sigma``, ``length``).

    Returns
    -------
    Keypoints
        Label :data:`VEIN`, with ``orientation``; empty when the blade has no
        vein response.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((64, 64, 3), 0.3); blade = np.zeros((64, 64), bool); blade[4:60, 4:60] = True
    >>> img[30:34, 8:56] = 0.8
    >>> kp = vein_keypoints(img, blade, 10, sigma=1.5)
    >>> bool(np.abs(kp.points[:, 1] - 31.5).max() <= 3), set(kp.labels.tolist())
    (True, {2})
    """
    from skimage.morphology import skeletonize

    img = as_float_image(image)
    h, w = img.shape[:2]
    m = as_mask(_same_shape(blade, (h, w), "blade"), shape=(h, w), name="blade")
    v, angle = vein_strength(img, m, return_orientation=True, **strength_kwargs)
    inside = v[m]
    empty = Keypoints(np.zeros((0, 2)), np.zeros(0, np.int64), np.zeros(0), np.zeros(0))
    if not inside.size or inside.max() <= 0:
        return empty
    thr = max(float(np.quantile(inside, quantile)), 1e-6 * float(inside.max()))
    skel = skeletonize(v > thr)
    ys, xs = np.nonzero(skel)
    if not len(xs):
        return empty
    order = np.argsort(-v[ys, xs], kind="stable")
    ys, xs = ys[order], xs[order]
    md = max(2.0, len(xs) / float(n_points))
    chosen = _spaced(xs, ys, md, n_points, h, w)
    pts = np.asarray(chosen, np.float64).reshape(-1, 2)
    iy, ix = pts[:, 1].astype(int), pts[:, 0].astype(int)
    return Keypoints(pts, np.full(len(pts), VEIN, np.int64), v[iy, ix].astype(np.float64),
                     angle[iy, ix].astype(np.float64))


def _spaced(xs, ys, md: float, n_max: int, h: int, w: int) -> list:
    """Greedy selection in the given order with a minimum spacing ``md`` (coarse occupancy grid)."""
    cell = md / np.sqrt(2.0)
    gh, gw = int(h / cell) + 1, int(w / cell) + 1
    grid = -np.ones((gh, gw), np.int64)
    chosen = []
    md2 = md * md
    for y, x in zip(ys, xs):
        gy, gx = int(y / cell), int(x / cell)
        near = grid[max(gy - 2, 0):min(gy + 3, gh), max(gx - 2, 0):min(gx + 3, gw)]
        idx = near[near >= 0]
        if len(idx):
            pts = np.asarray([chosen[i] for i in idx], np.float64)
            if (((pts[:, 0] - x) ** 2 + (pts[:, 1] - y) ** 2) < md2).any():
                continue
        grid[gy, gx] = len(chosen)
        chosen.append((float(x), float(y)))
        if len(chosen) >= n_max:
            break
    return chosen
