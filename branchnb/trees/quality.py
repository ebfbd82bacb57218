"""Quality measures of tree variations: ghosting, soft alpha, islands and holes.

What a reader of the paper checks by eye, as numbers:

* :func:`soft_alpha_fraction`: share of opaque-ish pixels with alpha between
  0.1 and 0.9 away from the silhouette rim (a clean cut-out has none);
* :func:`foreign_colour_fraction`: share of a variation's opaque pixels
  whose colour is far from every colour of the exemplars that have colour
  weight (colour of a zero-weight exemplar, or black slivers);
* :func:`pieces` and :func:`large_holes`: opaque components and interior
  transparent holes larger than a given area;
* :func:`flat_region_speckle`: of a billboard cloud, the share of the
  front view's large flat-coloured regions that turn busy in a side view.

Examples
--------
>>> import numpy as np
>>> a = np.zeros((9, 9, 4), np.float32); a[2:7, 2:7] = (0.2, 0.6, 0.1, 1.0)
>>> soft_alpha_fraction(a), pieces(a[..., 3]), large_holes(a[..., 3], 0)
(0.0, 1, 0)
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi
from scipy.spatial import cKDTree

__all__ = ["soft_alpha_fraction", "foreign_colour_fraction", "pieces", "large_holes", "hole_sizes",
           "flat_region_speckle", "colour_span", "largest_piece_share"]


def soft_alpha_fraction(image, *, rim: int = 1) -> float:
    """Share of pixels with 0.1 < alpha < 0.9 more than ``rim`` pixels inside the silhouette."""
    a = np.asarray(image, dtype=np.float32)[..., 3]
    inside = a >= 0.5
    core = ndi.binary_erosion(inside, iterations=rim) if rim > 0 else inside
    soft = (a > 0.1) & (a < 0.9)
    n = max(int(inside.sum()), 1)
    return float(np.count_nonzero(soft & core) / n)


def foreign_colour_fraction(image, sources, *, tol: float = 0.12, max_colours: int = 20000,
                            rng=0) -> float:
    """Share of opaque pixels whose RGB is farther than ``tol`` from every source colour.

    Parameters
    ----------
    image : (H, W, 4) array_like
        The variation (straight RGBA).
    sources : sequence of (H, W, 4) array_like
        The exemplars with colour weight > 0 (straight or black-background
        RGBA; only their opaque pixels count).
    tol : float
        Euclidean RGB distance.
    """
    img = np.asarray(image, dtype=np.float32)
    op = img[..., 3] >= 0.5
    if not op.any():
        return 0.0
    gen = np.random.default_rng(rng)
    cols = []
    for s in sources:
        s = np.asarray(s, dtype=np.float32)
        cols.append(s[s[..., 3] >= 0.5][:, :3])
    palette = np.unique(np.round(np.vstack(cols), 3), axis=0)
    if len(palette) > max_colours:
        palette = palette[gen.choice(len(palette), max_colours, replace=False)]
    d, _ = cKDTree(palette).query(img[op][:, :3], k=1)
    return float(np.mean(d > tol))


def pieces(alpha, *, min_area: int = 1) -> int:
    """Opaque 8-connected components of at least ``min_area`` pixels."""
    m = np.asarray(alpha) >= 0.5
    lab, n = ndi.label(m, structure=np.ones((3, 3), bool))
    if n == 0:
        return 0
    areas = np.bincount(lab.ravel())[1:]
    return int(np.count_nonzero(areas >= min_area))


def largest_piece_share(alpha) -> float:
    """Share of the opaque pixels in the largest 8-connected opaque piece (1 for one piece)."""
    m = np.asarray(alpha) >= 0.5
    lab, n = ndi.label(m, structure=np.ones((3, 3), bool))
    if n == 0:
        return 0.0
    areas = np.bincount(lab.ravel())[1:]
    return float(areas.max() / areas.sum())


def hole_sizes(alpha) -> np.ndarray:
    """Areas of the interior transparent holes (not connected to the border), 4-connected."""
    m = np.asarray(alpha) >= 0.5
    lab, n = ndi.label(~m)
    if n == 0:
        return np.zeros(0, int)
    border = np.unique(np.concatenate([lab[0], lab[-1], lab[:, 0], lab[:, -1]]))
    sizes = np.bincount(lab.ravel(), minlength=n + 1)
    sizes[0] = 0
    sizes[border] = 0
    return sizes[sizes > 0]


def large_holes(alpha, limit: int) -> int:
    """Interior holes larger than ``limit`` pixels."""
    return int(np.count_nonzero(hole_sizes(alpha) > limit))


def colour_span(rgb, size: int = 5) -> np.ndarray:
    """Largest per-channel colour range in each ``size`` x ``size`` window, (H, W)."""
    rgb = np.asarray(rgb, dtype=np.float32)[..., :3]
    win = (size, size, 1)
    return (ndi.maximum_filter(rgb, size=win) - ndi.minimum_filter(rgb, size=win)).max(axis=2)


def flat_region_speckle(cloud, yaw: float, *, min_area: float = 0.01, busy: float = 0.15,
                        margin: int = 2) -> float:
    """Share of the front view's large flat regions that are busy in the view from ``yaw``.

    The flat regions are the crown pixels of the working image whose 5 x 5
    colour span is at most ``busy``, in 4-connected pieces of at least
    ``min_area`` times the crown's area, shrunk by ``margin`` pixels. Each
    such pixel is carried to the side view with the front billboard that
    shows it in the front view (axial billboards move as a whole); there
    it counts as speckled when the side view (over white, so sky showing
    through counts) spans more than ``busy`` in its 5 x 5 window. Both
    spans are measured over white, so a cloud that reproduces its input
    scores 0 at yaw 0. Pixels carried out of the frame are left out.

    Examples
    --------
    >>> from branchnb import data
    >>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
    >>> c = billboard_cloud(data.load("cartoon_tree"), params=BillboardParams(max_size=128), rng=0)
    >>> flat_region_speckle(c, 0.0) < 0.02
    True
    """
    from ..core.image import composite_over
    from .billboard import FRONT
    from .preview import project, render_cloud

    img = cloud.image
    H, W = img.shape[:2]
    crown = (cloud.superpixels > 0) & (img[..., 3] >= 0.99)
    if not crown.any():
        return 0.0
    # Flat as seen over white, like the side view: a soft rim pixel whose
    # straight colour matches its neighbours still shows as a grey edge.
    flat = crown & (colour_span(composite_over(img, (1.0, 1.0, 1.0))) <= busy)
    lab, n = ndi.label(flat)
    area = np.bincount(lab.ravel(), minlength=n + 1)
    big = np.flatnonzero(area >= min_area * crown.sum())
    big = big[big > 0]
    flat = np.isin(lab, big)
    if margin > 0:
        flat = ndi.binary_erosion(flat, iterations=margin)
    if not flat.any():
        return 0.0
    # Which front billboard shows each pixel in the front view (the nearest one).
    x0s, _ = project(cloud, 0.0)
    xs, _ = project(cloud, yaw)
    shift = np.full((H, W), np.nan)
    front = np.flatnonzero(cloud.layer == FRONT)
    for i in front[np.argsort(cloud.centers[front, 2], kind="stable")]:
        t = cloud.textures[cloud.texture[i]]
        h, w = t.shape[:2]
        bx, by = int(round(x0s[i] - 0.5 * w)), int(round(cloud.centers[i, 1] - 0.5 * h))
        on = t[..., 3] >= 0.5
        ys, xx = np.nonzero(on)
        ys, xx = ys + by, xx + bx
        ok = (ys >= 0) & (ys < H) & (xx >= 0) & (xx < W)
        dx = int(round(xs[i] - 0.5 * w)) - bx
        shift[ys[ok], xx[ok]] = dx
    ys, xx = np.nonzero(flat & np.isfinite(shift))
    if len(ys) == 0:
        return 0.0
    xx = xx + shift[ys, xx].astype(int)
    inside = (xx >= 0) & (xx < W)
    ys, xx = ys[inside], xx[inside]
    if len(ys) == 0:
        return 0.0
    side = composite_over(render_cloud(cloud, yaw, crop="image"), (1.0, 1.0, 1.0))
    return float((colour_span(side)[ys, xx] > busy).mean())
