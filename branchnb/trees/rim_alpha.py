"""Anti-aliased rims on tree mixes (beyond the paper, issue 24).

The paper thresholds the exemplars' alpha at 0.5, so a mix's silhouette is
binary and its rim a staircase at 96-512 px, while anti-aliased sources had
soft rims. :func:`soft_rim` puts a soft rim back on a mix of anti-aliased
sources without moving its opaque set (``alpha >= 0.5`` stays exactly the
same set, so every measure taken on it is unchanged):

* the rim's sub-pixel position is read off the binary silhouette itself:
  the 0.5 level line of the silhouette blurred by :data:`RIM_SIGMA`
  averages the staircase into the edge it quantised, and the signed
  distance ``d`` of a pixel to that line is ``sigma Phi^-1(B)``;
* the sources' own rim profile sets the ramp: each source's soft alpha
  (:attr:`~branchnb.trees.exemplar.Normalized.soft_alpha`) against the same
  distance on its own thresholded silhouette gives its ramp width ``W``
  (:func:`rim_width`; 1 px for box-filtered drawings, wider for blurred
  rims); the mix takes the shape-weighted mean, and ``alpha = 0.5 + d / W``
  on the pixels either side of the silhouette's edge, clamped to its side
  of 0.5;
* rim pixels outside the silhouette take the nearest opaque pixel's colour
  (no dark or light fringe over any backdrop).

Hard-edged sources stay hard: pixel art (no soft alpha), aliased low-poly
crowns and hard-edged drawings (under :data:`SOFT_RIM_SHARE` of the rim
pixels of the source's own alpha partial,
:attr:`~branchnb.trees.exemplar.Normalized.rim_softness`; a smooth resize
softens them at the working size).
"""

from __future__ import annotations

from collections.abc import Sequence

import cv2
import numpy as np
from scipy import ndimage as ndi
from scipy.special import ndtri

__all__ = ["RIM_SIGMA", "RIM_WIDTH_MAX", "SOFT_RIM_SHARE", "edge_distance", "exemplar_rim_width", "rim_width",
           "soft_rim"]

#: Blur (px) of a binary silhouette whose 0.5 level line stands for its edge. 0.7-1.0 averaged
#: 1-px stair-steps of 128-512 px mixes; a 1-px line keeps a level line (peak 0.52 at 0.7 px).
RIM_SIGMA = 0.8
#: Widest ramp (px) a mix's rim takes: only the pixel either side of the edge is soft (a blurred
#: source's 3 px fall-off is cut there to keep the rest of the crown opaque).
RIM_WIDTH_MAX = 3.0
#: Least share of a source's rim pixels (either side of its thresholded edge) with partial alpha
#: for it to count as anti-aliased: box-filtered drawings, photos and sample clip art 0.35-0.9,
#: pixel art and aliased drawings 0 (as :func:`~branchnb.trees.flat_art._hard_edged`).
SOFT_RIM_SHARE = 0.05


def edge_distance(opaque, sigma: float = RIM_SIGMA) -> np.ndarray:
    """Signed sub-pixel distance (px, positive inside) of every pixel to a binary silhouette's edge.

    Parameters
    ----------
    opaque : (H, W) array_like of bool
        The silhouette.
    sigma : float
        Blur (px) whose 0.5 level line is taken as the edge.

    Returns
    -------
    (H, W) float32 ndarray
        ``sigma Phi^-1(B)`` (B the blurred silhouette: exact on a straight
        edge), clipped to [-3, 3].

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((9, 9), bool); m[:, :4] = True
    >>> d = edge_distance(m); round(float(d[4, 3]), 2), round(float(d[4, 4]), 2)
    (0.54, -0.54)
    """
    m = np.asarray(opaque, bool)
    if m.ndim != 2:
        raise ValueError(f"opaque must be 2-D, got shape {m.shape}")
    if not sigma > 0:
        raise ValueError(f"sigma must be > 0, got {sigma}")
    b = cv2.GaussianBlur(m.astype(np.float32), (0, 0), float(sigma), borderType=cv2.BORDER_CONSTANT)
    # a straight edge blurred by a Gaussian reads B = Phi(d / sigma)
    return np.clip(float(sigma) * ndtri(np.clip(b, 1e-6, 1.0 - 1e-6)), -3.0, 3.0).astype(np.float32)


def _rim_band(opaque: np.ndarray) -> np.ndarray:
    k = np.ones((3, 3), np.uint8)
    u = opaque.astype(np.uint8)
    return (cv2.dilate(u, k) > 0) & ~(cv2.erode(u, k, borderType=cv2.BORDER_CONSTANT, borderValue=0) > 0)


def rim_width(opaque, soft_alpha) -> float:
    """Ramp width (px) of a source's anti-aliased rim, 0 when it is hard-edged.

    Parameters
    ----------
    opaque : (H, W) array_like of bool
        The source's thresholded silhouette.
    soft_alpha : (H, W) array_like or None
        Its own alpha resampled alike (None: pixel art, hard).

    Returns
    -------
    float
        ``W`` of ``soft_alpha ~ clip(0.5 + d / W, 0, 1)`` on the rim (``d``
        from :func:`edge_distance`; least squares, 0.25 to
        :data:`RIM_WIDTH_MAX` by 0.05); 0 when under
        :data:`SOFT_RIM_SHARE` of the rim pixels are partial.

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:64, :64]
    >>> soft = np.clip(20.5 - np.hypot(xx - 32, yy - 32), 0, 1)
    >>> 1.0 < rim_width(soft >= 0.5, soft) < 2.5, rim_width(soft >= 0.5, soft >= 0.5)
    (True, 0.0)
    """
    if soft_alpha is None:
        return 0.0
    m = np.asarray(opaque, bool)
    sa = np.asarray(soft_alpha, np.float32)
    if sa.shape != m.shape:
        return 0.0
    band = _rim_band(m)
    if not band.any():
        return 0.0
    part = (sa[band] > 0.02) & (sa[band] < 0.98)
    if float(part.mean()) < SOFT_RIM_SHARE:
        return 0.0
    # least squares over all rim pixels, hard ones too (fitted on the partial ones alone, the
    # ramp came out 1.7-2.4 px and the mixes' rims softer than the sources': 0.75-0.91 of the rim
    # pixels partial against 0.45-0.69)
    d, a = edge_distance(m)[band], sa[band]
    grid = np.arange(0.25, RIM_WIDTH_MAX + 1e-6, 0.05)
    err = ((np.clip(0.5 + d[None] / grid[:, None], 0.0, 1.0) - a[None]) ** 2).mean(axis=1)
    return float(grid[int(np.argmin(err))])


def soft_rim(image, widths: Sequence[float], weights=None) -> np.ndarray:
    """A binary-alpha mix with an anti-aliased rim, its opaque set (alpha >= 0.5) unchanged.

    Parameters
    ----------
    image : (H, W, 4) array_like
        Straight RGBA whose alpha is 0 / 1 at the silhouette's edge.
    widths : sequence of float
        The mixed sources' :func:`rim_width`; any 0 (a hard-edged source)
        leaves ``image`` hard.
    weights : (k,) array_like, optional
        Their shape weights (default equal).

    Returns
    -------
    (H, W, 4) float32 ndarray
        The edge's pixels with alpha ``0.5 + d / W``: opaque ones beside a
        transparent one in [0.5, 1], transparent ones touching an opaque one
        in [0, 0.5); 1-px lines and spikes stay opaque; soft pixels outside
        take the nearest opaque colour.

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:48, :48]
    >>> img = np.zeros((48, 48, 4), np.float32); img[np.hypot(xx - 24, yy - 24) < 15.3] = (0, .5, 0, 1)
    >>> out = soft_rim(img, [1.0])
    >>> bool(((out[..., 3] >= 0.5) == (img[..., 3] >= 0.5)).all()), bool(((out[..., 3] % 1) > 0).any())
    (True, True)
    """
    img = np.asarray(image, np.float32)
    if img.ndim != 3 or img.shape[2] != 4:
        raise ValueError(f"image must be (H, W, 4), got shape {img.shape}")
    w = np.asarray(widths, float).ravel()
    if len(w) == 0 or not (w > 0).all():
        return img
    wt = np.ones(len(w)) if weights is None else np.asarray(weights, float).ravel()
    if wt.shape != w.shape or (wt < 0).any() or wt.sum() <= 0:
        raise ValueError(f"weights must be {len(w)} non-negative values, not all 0, got {weights!r}")
    width = float((w * wt).sum() / wt.sum())
    a = img[..., 3]
    op = a >= 0.5
    if not op.any() or op.all():
        return img
    band = _rim_band(op)
    # 1-px lines and spikes (in no opaque 2 x 2 block) blur under 0.5: they keep their alpha
    u = op.astype(np.uint8)
    thin = op & ~(cv2.dilate(cv2.erode(u, np.ones((2, 2), np.uint8), anchor=(0, 0)),
                             np.ones((2, 2), np.uint8), anchor=(1, 1)) > 0)
    ramp = 0.5 + edge_distance(op) / width
    out = img.copy()
    alpha = out[..., 3]
    # opaque pixels only beside (not diagonal to) a transparent one: the silhouette's interior past
    # its edge stays opaque, as quality.soft_alpha_fraction reads a clean cut-out
    cross = np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], np.uint8)
    inner = op & ~(cv2.erode(u, cross, borderType=cv2.BORDER_CONSTANT, borderValue=0) > 0) & ~thin
    alpha[inner] = np.clip(ramp[inner], 0.5, 1.0)
    outer = band & ~op
    alpha[outer] = np.clip(ramp[outer], 0.0, 0.499)
    if outer.any():
        iy, ix = ndi.distance_transform_edt(~op, return_distances=False, return_indices=True)
        out[..., :3][outer] = img[..., :3][iy[outer], ix[outer]]
    return out


def exemplar_rim_width(exemplar) -> float:
    """:func:`rim_width` of an exemplar (its soft alpha against its silhouette; cached on it).

    Parameters
    ----------
    exemplar : Exemplar
        A processed exemplar.

    Returns
    -------
    float
        0 for pixel art and for sources whose own rim had under
        :data:`SOFT_RIM_SHARE` of partial pixels
        (:attr:`~branchnb.trees.exemplar.Normalized.rim_softness`).

    Examples
    --------
    >>> from branchnb.trees import TreeLibrary
    >>> lib = TreeLibrary.from_data(["cartoon_tree"], size=96)
    >>> 1.0 < exemplar_rim_width(lib.exemplars[0]) < 2.0
    True
    """
    cache = getattr(exemplar, "_cages", None)
    if cache is not None and "rim_width" in cache:
        return cache["rim_width"]
    n = exemplar.normalized
    # hard-edged sources (pixel art; aliased drawings and low-poly crowns, which a smooth resize
    # softens at the working size) are judged on their own alpha
    hard = n.pixel_art is not None or (getattr(n, "rim_softness", None) is not None
                                       and n.rim_softness < SOFT_RIM_SHARE)
    w = 0.0 if hard else rim_width(exemplar.image[..., 3] >= 0.5, n.soft_alpha)
    if cache is not None:
        cache["rim_width"] = w
    return w
