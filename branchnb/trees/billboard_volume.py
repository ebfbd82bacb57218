"""Billboard clouds, step 3: the volume (biharmonic inflation of the silhouette).

Part of :func:`~branchnb.trees.billboard.billboard_cloud`; the steps are described in
:mod:`branchnb.trees.billboard`.
"""

from __future__ import annotations

import cv2
import numpy as np
import scipy.sparse as sp
from scipy import ndimage as ndi
from scipy.sparse.linalg import splu

from ..core.poisson import grid_laplacian


def inflate_silhouette(mask: np.ndarray, *, max_solve: int = 192) -> np.ndarray:
    """Biharmonic inflation ``Δ²h = 1`` inside ``mask``, ``h = Δh = 0`` on its boundary.

    Solved as two Dirichlet Poisson problems (``-Δu = 1``, ``-Δh = u``)
    with the 5-point Laplacian (:func:`branchnb.core.poisson.grid_laplacian`
    plus the Dirichlet neighbours outside the mask) and one sparse LU
    factorisation, on a grid of at most ``max_solve`` pixels (``h`` is
    smooth), then resized.

    Parameters
    ----------
    mask : (H, W) bool array
        The silhouette to inflate (the crown); may have several pieces.
    max_solve : int
        Longest side in pixels of the grid the equations are solved on
        (a coarser grid for larger masks, then resized to (H, W)).

    Returns
    -------
    h : (H, W) float32
        > 0 inside the mask, 0 outside, normalised to a maximum of 1.

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:41, :41]
    >>> h = inflate_silhouette((xx - 20) ** 2 + (yy - 20) ** 2 < 15 ** 2)
    >>> round(float(h[20, 20]), 3), float(h[0, 0])
    (1.0, 0.0)
    """
    mask = np.asarray(mask, bool)
    H, W = mask.shape
    if not mask.any():
        return np.zeros((H, W), np.float32)
    s = min(1.0, max_solve / max(H, W))
    if s < 1.0:
        small = cv2.resize(mask.astype(np.float32), (max(1, round(W * s)), max(1, round(H * s))),
                           interpolation=cv2.INTER_AREA) >= 0.5
        if small.sum() < 4:
            small = cv2.resize(mask.astype(np.uint8), (small.shape[1], small.shape[0]),
                               interpolation=cv2.INTER_NEAREST) > 0
    else:
        small = mask
    if not small.any():
        small = mask
        s = 1.0
    L, index = grid_laplacian(small)
    deg = np.asarray(L.diagonal()).ravel()
    A = (L + sp.diags(4.0 - deg)).tocsc()   # Dirichlet: outside neighbours are 0
    lu = splu(A)
    u = lu.solve(np.ones(A.shape[0]))
    hv = lu.solve(u)
    hs = np.zeros(small.shape, np.float64)
    hs[small] = hv
    if s < 1.0:
        h = cv2.resize(hs.astype(np.float32), (W, H), interpolation=cv2.INTER_LINEAR)
        # Pixels of the mask that fall outside the small mask get a small positive height.
        floor = 0.5 * float(hv.min()) if len(hv) else 0.0
        h = np.where(mask, np.maximum(h, floor), 0.0)
    else:
        h = hs
    m = float(h.max())
    return (h / m if m > 0 else h).astype(np.float32)


def _working_image(img: np.ndarray, max_size: int) -> tuple[np.ndarray, float]:
    h, w = img.shape[:2]
    s = min(1.0, max_size / max(h, w))
    if s >= 1.0:
        return img, 1.0
    size = (max(1, round(w * s)), max(1, round(h * s)))
    a = cv2.resize(img[:, :, 3], size, interpolation=cv2.INTER_AREA)
    prem = cv2.resize(img[:, :, :3] * img[:, :, 3:4], size, interpolation=cv2.INTER_AREA)
    rgb = np.where(a[..., None] > 1e-4, prem / np.maximum(a[..., None], 1e-4), 0.0)
    return np.dstack([rgb, a]).clip(0, 1).astype(np.float32), s


def _volume_mask(crown: np.ndarray, trunk: np.ndarray | None = None) -> np.ndarray:
    """The silhouette that is inflated: the crown with gaps closed and holes filled.

    Photographed crowns are lacy (sky shows through) and branches drawn
    over a crown cut it into pieces; inflating around every hole would
    flatten the volume. So the trunk pixels inside the crown's convex hull
    join it, then gaps (closing with a disc of 4 % of the crown size) and
    enclosed holes are filled.
    """
    if trunk is not None and trunk.any():
        pts = np.column_stack(np.nonzero(crown)[::-1]).astype(np.int32)
        hull = np.zeros(crown.shape, np.uint8)
        cv2.fillConvexPoly(hull, cv2.convexHull(pts), 1)
        crown = crown | (trunk & (hull > 0))
    ys, xs = np.nonzero(crown)
    D = max(ys.max() - ys.min() + 1, xs.max() - xs.min() + 1)
    r = max(1, int(round(0.04 * D)))
    k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    pad = 2 * r + 1
    m = np.pad(crown.astype(np.uint8), pad)
    m = cv2.morphologyEx(m, cv2.MORPH_CLOSE, k)[pad:-pad, pad:-pad] > 0
    return ndi.binary_fill_holes(m | crown)


def _extend(labels: np.ndarray, support: np.ndarray) -> np.ndarray:
    """Give every pixel of ``support`` the label of its nearest labelled pixel."""
    if not (labels > 0).any():
        return labels
    _, (iy, ix) = ndi.distance_transform_edt(labels == 0, return_indices=True)
    out = labels[iy, ix]
    return np.where(support, out, 0).astype(labels.dtype)


def _majority_parts(opaque, trunk, ground, size):
    """Working-size trunk (ground included) and ground masks: each pixel goes to the part
    (crown, trunk, ground) that covers most of it.

    Thresholding one mask alone at 0.5 after the resize left rim pixels to
    none of the parts or to two: as crown specks on a bare tree, or as trunk
    bits along a hill's rim that the trunk strips then spanned.
    """
    op = opaque.astype(np.float32)
    g = ground & trunk if ground is not None else np.zeros_like(trunk)
    fr = [cv2.resize(op * m, size, interpolation=cv2.INTER_AREA) for m in (~trunk, trunk & ~g, g)]
    best = np.argmax(np.stack(fr), axis=0)
    return best >= 1, best == 2
