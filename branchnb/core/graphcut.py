"""Graph-cut seams between two overlapping images (Kwatra et al. 2003), and between many.

Used wherever a technique composes overlapping pieces of texture: the
fragments of branching-structure synthesis, the patches of stroke-based
editing, gap completion. The cut runs where the two images agree and,
with the gradient normalisation, along image edges where it is least
visible.

Energy of a labelling ``L`` (False = take ``a``, True = take ``b``)::

    E(L) = sum over 4-neighbours (s, t) with L(s) != L(t) of
           (d(s) + d(t)) / (G(s, t) + eps)
    d(x) = ||a(x) - b(x)|| ** power
    G(s, t) = |grad a(s)| + |grad b(s)| + |grad a(t)| + |grad b(t)|   (if gradient_weighted)

with hard constraints pinning some pixels to ``a`` or ``b``.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import maxflow
import numba
import numpy as np
from scipy import ndimage as ndi

from .image import as_float_image, as_mask
from .validate import Real, checked, real_array

__all__ = [
    "gradient_magnitude",
    "pair_costs",
    "seam_cut",
    "seam_cost",
    "compose_overlap",
    "SeamComposition",
    "multilabel_seams",
]

_HARD = 1e9

#: Exponent of the colour difference in the seam cost (finite and > 0, or the cut never ends).
_POWER = Real(0, 16, low_open=True)


@numba.njit(cache=True, nogil=True)
def _channel_smoothed_norm(gx, gy):
    """``sqrt(sum_c sx_c^2 + sy_c^2)`` with ``s = [1, 2, 1] / 8`` across the channels (replicated ends),
    in float64: the values of the vectorised expression, without its temporaries."""
    h, w, C = gx.shape
    out = np.empty((h, w))
    for i in range(h):
        for j in range(w):
            acc = 0.0
            for c in range(C):
                cm, cp = max(c - 1, 0), min(c + 1, C - 1)
                sx = (np.float64(gx[i, j, cm]) + 2 * np.float64(gx[i, j, c]) + np.float64(gx[i, j, cp])) / 8.0
                sy = (np.float64(gy[i, j, cm]) + 2 * np.float64(gy[i, j, c]) + np.float64(gy[i, j, cp])) / 8.0
                v = sx * sx + sy * sy
                acc = v if c == 0 else acc + v
            out[i, j] = np.sqrt(acc)
    return out


def gradient_magnitude(img: np.ndarray) -> np.ndarray:
    """Sobel gradient magnitude over all channels (root of the summed squares): the edge strength in ``G(s, t)``.

    Parameters
    ----------
    img : (H, W, C) float ndarray
        An image (any channel count; OpenCV is used for up to 4 channels).

    Returns
    -------
    (H, W) ndarray
        Sobel magnitude (divided by 8, replicated borders).

    Examples
    --------
    >>> import numpy as np
    >>> float(gradient_magnitude(np.zeros((4, 4, 3))).max())
    0.0
    """
    img = np.asarray(img)
    if img.ndim == 3 and img.shape[2] <= 4 and min(img.shape[:2]) >= 2:
        # OpenCV's Sobel (replicated border) gives scipy's mode="nearest" values, several times faster
        # (scipy's n-d sobel also smooths [1, 2, 1] across the channel axis: kept)
        f = np.ascontiguousarray(img, np.float32)
        gx, gy = (cv2.Sobel(f, cv2.CV_32F, dx, dy, ksize=3, borderType=cv2.BORDER_REPLICATE).reshape(img.shape)
                  for dx, dy in ((1, 0), (0, 1)))
        return _channel_smoothed_norm(gx, gy)
    gy = ndi.sobel(img, axis=0, mode="nearest") / 8.0
    gx = ndi.sobel(img, axis=1, mode="nearest") / 8.0
    return np.sqrt((gx**2 + gy**2).sum(axis=2))


@checked(power=_POWER)
def pair_costs(a, b, *, power: float = 1.0, gradient_weighted: bool = True,
               eps: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    """Cost of cutting between horizontal and vertical neighbours.

    Parameters
    ----------
    a, b : (H, W, C) array_like
        The two overlapping images (same shape).
    power : float
        Exponent on the colour difference ``d(x)``.
    gradient_weighted : bool
        Divide by the edge strength ``G(s, t)`` so seams follow edges.
    eps : float
        Regulariser of the division.

    Returns
    -------
    right : (H, W - 1) ndarray
        Cost of separating ``(r, c)`` from ``(r, c + 1)``.
    down : (H - 1, W) ndarray
        Cost of separating ``(r, c)`` from ``(r + 1, c)``.

    Examples
    --------
    >>> import numpy as np
    >>> right, down = pair_costs(np.zeros((4, 5, 3)), np.ones((4, 5, 3)), gradient_weighted=False)
    >>> right.shape, down.shape, round(float(right[0, 0]), 4)          # d = sqrt(3) at both pixels
    ((4, 4), (3, 5), 3.4641)
    """
    a = as_float_image(a, name="a")
    b = as_float_image(b, name="b")
    if a.shape != b.shape:
        raise ValueError(f"a and b must have the same shape, got {a.shape} and {b.shape}")
    if power <= 0:
        raise ValueError(f"power must be > 0, got {power}")
    return _pair_costs(a, b, power, gradient_weighted, eps)


def _pair_costs(a: np.ndarray, b: np.ndarray, power: float = 1.0, gradient_weighted: bool = True,
                eps: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    """:func:`pair_costs` of two float32 ``(H, W, C)`` images already checked (the per-piece inner loop)."""
    if (power == 1.0 and a.dtype == np.float32 and b.dtype == np.float32 and a.ndim == 3
            and a.shape == b.shape and a.shape[0] >= 2 and a.shape[1] >= 2):
        # the per-piece case (float32 pieces, power 1): one compiled pass, the same values
        g = gradient_magnitude(a) + gradient_magnitude(b) if gradient_weighted else np.zeros(a.shape[:2])
        return _pair_costs_f32(a, b, g, bool(gradient_weighted), float(eps))
    d = np.sqrt(((a - b) ** 2).sum(axis=2)) ** power
    right = d[:, :-1] + d[:, 1:]
    down = d[:-1, :] + d[1:, :]
    if gradient_weighted:
        g = gradient_magnitude(a) + gradient_magnitude(b)
        right = right / (g[:, :-1] + g[:, 1:] + eps)
        down = down / (g[:-1, :] + g[1:, :] + eps)
    return right.astype(np.float64), down.astype(np.float64)


@numba.njit(cache=True, nogil=True)
def _pair_costs_f32(a, b, g, weighted, eps):
    """``right, down`` of :func:`_pair_costs` for float32 images and ``power == 1``: the same float32
    colour distances (channels summed in order) and float64 divisions as the vectorised code."""
    h, w, C = a.shape
    d = np.empty((h, w), np.float32)
    for i in range(h):
        for j in range(w):
            acc = np.float32(0.0)
            for c in range(C):
                t = a[i, j, c] - b[i, j, c]
                acc += t * t
            d[i, j] = np.sqrt(acc)
    right = np.empty((h, w - 1))
    down = np.empty((h - 1, w))
    for i in range(h):
        for j in range(w - 1):
            v = d[i, j] + d[i, j + 1]
            right[i, j] = v / (g[i, j] + g[i, j + 1] + eps) if weighted else np.float64(v)
    for i in range(h - 1):
        for j in range(w):
            v = d[i, j] + d[i + 1, j]
            down[i, j] = v / (g[i, j] + g[i + 1, j] + eps) if weighted else np.float64(v)
    return right, down


def _costs(a, b, costs, power, gradient_weighted):
    if costs is None:
        return pair_costs(a, b, power=power, gradient_weighted=gradient_weighted)
    if not isinstance(costs, (tuple, list)) or len(costs) != 2:
        raise TypeError(f"costs must be a (right, down) pair of arrays from pair_costs, got "
                        f"{type(costs).__name__}")
    right, down = (real_array(c, "costs", ndim=2, min=0.0, allow_empty=True) for c in costs)
    h, w = np.shape(a)[:2]
    if right.shape != (h, w - 1) or down.shape != (h - 1, w):
        raise ValueError(f"costs must be (right, down) of shapes {(h, w - 1)} and {(h - 1, w)}, got "
                         f"{right.shape} and {down.shape}")
    return right, down


@checked(power=_POWER)
def seam_cut(a, b, region, pin_a, pin_b, *, power: float = 1.0,
             gradient_weighted: bool = True, costs=None) -> np.ndarray:
    """Minimum-cost labelling of ``region`` between images ``a`` and ``b``.

    Parameters
    ----------
    a, b : (H, W, C) array_like
        The two overlapping images (same shape).
    region : (H, W) bool array_like
        Pixels to label (typically the overlap of the two images).
    pin_a, pin_b : (H, W) bool array_like
        Pixels of ``region`` that must take ``a`` (resp. ``b``), e.g. the
        overlap pixels bordering the part only ``a`` covers.
    power : float
        Exponent on the colour difference (see :func:`pair_costs`).
    gradient_weighted : bool
        Divide by the edge strength so seams follow edges (see :func:`pair_costs`).
    costs : (right, down), optional
        ``pair_costs(a, b, power=power, gradient_weighted=gradient_weighted)``
        when the caller has it already (it is not computed again).

    Returns
    -------
    take_b : (H, W) bool ndarray
        True where the cut assigns the pixel to ``b`` (False outside
        ``region``).

    Examples
    --------
    >>> import numpy as np
    >>> a, b = np.zeros((4, 6, 3)), np.ones((4, 6, 3))
    >>> pin_a = np.zeros((4, 6), bool); pin_a[:, 0] = True
    >>> pin_b = np.zeros((4, 6), bool); pin_b[:, -1] = True
    >>> bool(seam_cut(a, b, np.ones((4, 6), bool), pin_a, pin_b)[:, -1].all())
    True
    """
    right, down = _costs(a, b, costs, power, gradient_weighted)
    shape = right.shape[0], down.shape[1]
    region = as_mask(region, shape=shape, name="region")
    pin_a = as_mask(pin_a, shape=shape, name="pin_a") & region
    pin_b = as_mask(pin_b, shape=shape, name="pin_b") & region
    if (pin_a & pin_b).any():
        raise ValueError("pin_a and pin_b overlap: a pixel cannot be pinned to both images")
    return _seam_cut(right, down, region, pin_a, pin_b)


def _seam_cut(right: np.ndarray, down: np.ndarray, region: np.ndarray, pin_a: np.ndarray,
              pin_b: np.ndarray) -> np.ndarray:
    """:func:`seam_cut` on checked pair costs and bool masks (``pin_a``, ``pin_b`` disjoint, inside ``region``)."""
    shape = right.shape[0], down.shape[1]
    # Pinned pixels keep their side whatever the cut, so only the free pixels and their neighbours
    # make the graph: the same labelling (the pixels that can still reach the sink after the max
    # flow) on a graph a fraction of the size, none at all when every pixel is pinned.
    take_b = pin_b & region
    free = region & ~pin_a & ~pin_b
    if not free.any():
        return take_b
    rows, cols = np.nonzero(free)
    r0, r1 = max(rows.min() - 1, 0), min(rows.max() + 2, shape[0])
    c0, c1 = max(cols.min() - 1, 0), min(cols.max() + 2, shape[1])
    reg = region[r0:r1, c0:c1]
    rgt = right[r0:r1, c0:c1 - 1] if c1 - c0 > 1 else np.zeros((r1 - r0, 0))
    dwn = down[r0:r1 - 1, c0:c1] if r1 - r0 > 1 else np.zeros((0, c1 - c0))

    g = maxflow.Graph[float]()
    ids = g.add_grid_nodes(reg.shape)
    # Edges only between two region pixels; pixels outside the region are
    # isolated nodes whose label we ignore.
    w_right = np.zeros(reg.shape)
    w_right[:, :-1] = np.where(reg[:, :-1] & reg[:, 1:], rgt, 0.0)
    w_down = np.zeros(reg.shape)
    w_down[:-1, :] = np.where(reg[:-1, :] & reg[1:, :], dwn, 0.0)
    st_right = np.array([[0, 0, 0], [0, 0, 1], [0, 0, 0]])
    st_down = np.array([[0, 0, 0], [0, 0, 0], [0, 1, 0]])
    g.add_grid_edges(ids, weights=w_right, structure=st_right, symmetric=True)
    g.add_grid_edges(ids, weights=w_down, structure=st_down, symmetric=True)
    pa = pin_a[r0:r1, c0:c1]
    pb = pin_b[r0:r1, c0:c1]
    # Source side = a, sink side = b.
    g.add_grid_tedges(ids, np.where(pa, _HARD, 0.0), np.where(pb, _HARD, 0.0))
    g.maxflow()
    sink = g.get_grid_segments(ids)
    take_b[r0:r1, c0:c1] = sink & reg
    return take_b


@checked(power=_POWER)
def seam_cost(a, b, take_b, *, region=None, power: float = 1.0,
              gradient_weighted: bool = True, costs=None) -> float:
    """Total cost of the seams of a labelling (sum over cut neighbour pairs).

    Only pairs with both pixels in ``region`` count (everywhere if None),
    since the cost needs both images at both pixels. Use it to compare
    composition strategies on equal terms, e.g. a graph cut against a
    plain overlay.

    Parameters
    ----------
    a, b : (H, W, C) array_like
        The two overlapping images (same shape).
    take_b : (H, W) bool array_like
        The labelling: True where the pixel comes from ``b`` (e.g. the
        result of :func:`seam_cut`).
    region : (H, W) bool array_like, optional
        Pixels where both images are defined; only neighbour pairs with both
        pixels inside count. Default: the whole image.
    power : float
        Exponent on the colour difference (see :func:`pair_costs`).
    gradient_weighted : bool
        Divide by the edge strength so seams follow edges (see :func:`pair_costs`).
    costs : (right, down), optional
        ``pair_costs(a, b, power=power, gradient_weighted=gradient_weighted)``
        if already computed (as in :func:`seam_cut`); not computed again.

    Returns
    -------
    float
        Sum of the pair costs of the neighbour pairs the labelling separates
        (0 for a labelling without a seam).

    Examples
    --------
    >>> import numpy as np
    >>> a, b = np.zeros((4, 4, 3)), np.zeros((4, 4, 3))
    >>> seam_cost(a, b, np.eye(4, dtype=bool))      # identical images: every cut is free
    0.0
    """
    right, down = _costs(a, b, costs, power, gradient_weighted)
    shape = (right.shape[0], down.shape[1])
    lab = as_mask(take_b, shape=shape, name="take_b")
    reg = np.ones(shape, bool) if region is None else as_mask(region, shape=shape, name="region")
    return _seam_cost(right, down, lab, reg)


def _seam_cost(right: np.ndarray, down: np.ndarray, lab: np.ndarray, reg: np.ndarray) -> float:
    """:func:`seam_cost` on checked pair costs and bool masks."""
    cut_r = (lab[:, :-1] != lab[:, 1:]) & reg[:, :-1] & reg[:, 1:]
    cut_d = (lab[:-1, :] != lab[1:, :]) & reg[:-1, :] & reg[1:, :]
    return float(right[cut_r].sum() + down[cut_d].sum())


@dataclass
class SeamComposition:
    """Result of :func:`compose_overlap`.

    Parameters
    ----------
    image : (H, W, C) float32 ndarray
        The composed image.
    mask : (H, W) bool ndarray
        Union of the two coverage masks.
    take_b : (H, W) bool ndarray
        Pixels that come from ``b``.
    seam : (H, W) bool ndarray
        Pixels of ``a``'s side adjacent to ``b``'s side inside the overlap
        (for drawing the seam).
    cost : float
        Seam cost of the chosen labelling.

    Examples
    --------
    >>> import numpy as np
    >>> ma = np.zeros((6, 6), bool); ma[:, :4] = True
    >>> r = compose_overlap(np.zeros((6, 6, 3)), ma, np.zeros((6, 6, 3)), ~ma)
    >>> bool(r.mask.all()), r.cost                  # no overlap: nothing to cut
    (True, 0.0)
    """

    image: np.ndarray
    mask: np.ndarray
    take_b: np.ndarray
    seam: np.ndarray
    cost: float


@checked(power=_POWER)
def compose_overlap(a, mask_a, b, mask_b, *, power: float = 1.0,
                    gradient_weighted: bool = True, method: str = "graphcut") -> SeamComposition:
    """Compose image ``b`` (covering ``mask_b``) onto ``a`` (covering ``mask_a``).

    Pixels only one image covers take that image. In the overlap, the
    pixels bordering the part only ``a`` covers are pinned to ``a``, those
    bordering the part only ``b`` covers are pinned to ``b``, and a graph
    cut labels the rest. With ``method="overlay"`` ``b`` simply covers
    the whole overlap (the baseline the cut is compared with).

    Parameters
    ----------
    a : (H, W, C) array_like
        The image already in place.
    mask_a : (H, W) bool array_like
        Pixels ``a`` covers.
    b : (H, W, C) array_like
        The image composed onto ``a`` (same shape as ``a``).
    mask_b : (H, W) bool array_like
        Pixels ``b`` covers. When ``b`` lies wholly inside ``a``, an inner
        core of ``mask_b`` is pinned to ``b`` so the new piece is not lost.
    power : float
        Exponent on the colour difference (see :func:`pair_costs`).
    gradient_weighted : bool
        Divide by the edge strength so seams follow edges (see :func:`pair_costs`).
    method : {"graphcut", "overlay"}
        ``"graphcut"`` labels the overlap by a minimum cut; ``"overlay"``
        lets ``b`` cover it (all but the ring pinned to ``a``).

    Returns
    -------
    SeamComposition
        The composed image (0 outside both masks), union mask, labelling,
        seam pixels and seam cost.

    Raises
    ------
    ValueError
        If ``a`` and ``b`` differ in shape, a mask has another shape, or
        ``method`` is unknown.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((8, 8, 3)); b = np.ones((8, 8, 3))
    >>> ma = np.zeros((8, 8), bool); ma[:, :6] = True
    >>> mb = np.zeros((8, 8), bool); mb[:, 2:] = True
    >>> r = compose_overlap(a, ma, b, mb)
    >>> bool(r.mask.all() and r.image[0, 0, 0] == 0 and r.image[0, 7, 0] == 1)
    True
    """
    a = as_float_image(a, name="a")
    b = as_float_image(b, name="b")
    if a.shape != b.shape:
        raise ValueError(f"a and b must have the same shape, got {a.shape} and {b.shape}")
    shape = a.shape[:2]
    mask_a = as_mask(mask_a, shape=shape, name="mask_a")
    mask_b = as_mask(mask_b, shape=shape, name="mask_b")
    if method not in ("graphcut", "overlay"):
        raise ValueError(f"method must be 'graphcut' or 'overlay', got {method!r}")
    overlap = mask_a & mask_b
    only_a = mask_a & ~mask_b
    only_b = mask_b & ~mask_a
    near_a = ndi.binary_dilation(only_a) & overlap
    near_b = ndi.binary_dilation(only_b) & overlap & ~near_a
    if overlap.any() and not only_b.any():
        # b lies inside a: keep b's inner core so the new piece is not
        # thrown away, and let the cut find the seam around it.
        core = ndi.binary_erosion(mask_b, iterations=max(1, _inner_depth(mask_b) // 2))
        near_b = core & ~near_a
    if method == "overlay":
        # The trivial labelling with the same constraints: b everywhere
        # except the ring pinned to a.
        take_b = only_b | (overlap & ~near_a)
    else:
        take_b = only_b | seam_cut(a, b, overlap, near_a, near_b, power=power,
                                   gradient_weighted=gradient_weighted)
    image = np.where(take_b[:, :, None], b, a).astype(np.float32)
    image[~(mask_a | mask_b)] = 0.0
    seam = ~take_b & mask_a & ndi.binary_dilation(take_b) & overlap
    cost = seam_cost(a, b, take_b, region=overlap, power=power,
                     gradient_weighted=gradient_weighted)
    return SeamComposition(image, mask_a | mask_b, take_b, seam, cost)


def _inner_depth(mask: np.ndarray) -> int:
    return int(ndi.distance_transform_edt(mask).max())


@numba.njit(cache=True, nogil=True)
def _v(imgs, grads, k, l, py, px, qy, qx, eps, gw):
    """Seam cost ``V_pq(k, l)`` of one neighbour pair (0 when ``k == l``)."""
    if k == l:
        return 0.0
    dp = 0.0
    dq = 0.0
    for c in range(imgs.shape[3]):
        t = imgs[k, py, px, c] - imgs[l, py, px, c]
        dp += t * t
        t = imgs[k, qy, qx, c] - imgs[l, qy, qx, c]
        dq += t * t
    d = np.sqrt(dp) + np.sqrt(dq)
    if gw:
        d /= grads[k, py, px] + grads[l, py, px] + grads[k, qy, qx] + grads[l, qy, qx] + eps
    return d


@numba.njit(cache=True, nogil=True)
def _pairwise_energy(imgs, grads, lab, reg, eps, gw):
    h, w = lab.shape
    e = 0.0
    for y in range(h):
        for x in range(w):
            if not reg[y, x]:
                continue
            if x + 1 < w and reg[y, x + 1]:
                e += _v(imgs, grads, lab[y, x], lab[y, x + 1], y, x, y, x + 1, eps, gw)
            if y + 1 < h and reg[y + 1, x]:
                e += _v(imgs, grads, lab[y, x], lab[y + 1, x], y, x, y + 1, x, eps, gw)
    return e


@numba.njit(cache=True, nogil=True)
def _expansion_terms(imgs, grads, lab, reg, a, smooth, eps, gw, e0, e1, cap_r, cap_d):
    """Add the pairwise terms of the expansion move to label ``a`` (Kolmogorov-Zabih form).

    ``E(x_p, x_q) = A + (C - A) x_p - C x_q + (B + C - A) (1 - x_p) x_q`` with
    ``A = V(l_p, l_q)``, ``B = V(l_p, a)``, ``C = V(a, l_q)`` (``x = 1``: take ``a``);
    ``B + C - A < 0`` (possible without a metric) is truncated to 0.
    """
    h, w = lab.shape
    for y in range(h):
        for x in range(w):
            if not reg[y, x]:
                continue
            for dy, dx in ((0, 1), (1, 0)):
                qy, qx = y + dy, x + dx
                if qy >= h or qx >= w or not reg[qy, qx]:
                    continue
                lp, lq = lab[y, x], lab[qy, qx]
                A = smooth * _v(imgs, grads, lp, lq, y, x, qy, qx, eps, gw)
                B = smooth * _v(imgs, grads, lp, a, y, x, qy, qx, eps, gw)
                C = smooth * _v(imgs, grads, a, lq, y, x, qy, qx, eps, gw)
                e0[y, x] += A
                e1[y, x] += C
                e1[qy, qx] -= C
                cap = max(B + C - A, 0.0)
                if dx == 1:
                    cap_r[y, x] = cap
                else:
                    cap_d[y, x] = cap


def _labelling_energy(unary, imgs, grads, lab, region, smooth, eps, gw):
    e = float(np.take_along_axis(unary, lab[..., None], 2)[..., 0][region].sum())
    return e + smooth * _pairwise_energy(imgs, grads, lab, region, eps, gw)


@checked(smoothness=Real(0, 1e6))
def multilabel_seams(images, unary, *, region=None, smoothness: float = 1.0,
                     gradient_weighted: bool = True, max_cycles: int = 3, eps: float = 1e-3,
                     labels=None) -> np.ndarray:
    """Choose, per pixel, which of ``L`` aligned images it comes from (multi-label graph cut).

    The energy generalises :func:`seam_cut` to ``L`` labels: a data term
    per pixel and label plus the seam cost of Kwatra et al. (2003) between
    neighbours with different labels ``k``, ``l``::

        E(L) = sum_p D_p(L_p) + smoothness * sum_(p, q), L_p != L_q V_pq(L_p, L_q)
        V_pq(k, l) = (|I_k(p) - I_l(p)| + |I_k(q) - I_l(q)|) / (G_k(p) + G_l(p) + G_k(q) + G_l(q) + eps)

    (no division by the gradients ``G`` when ``gradient_weighted`` is
    False), minimised by alpha-expansion (Boykov, Veksler, Zabih 2001): one
    binary graph cut (PyMaxflow) per label and cycle, until a cycle no
    longer lowers the energy or ``max_cycles`` cycles ran. PyMaxflow's own
    ``aexpansion_grid`` only takes label-to-label costs; here the seam cost
    depends on the pixels. With the gradient normalisation ``V`` need not
    be a metric; the few pairs that break the expansion's submodularity are
    truncated, and a move is kept only if it lowers the energy.

    Parameters
    ----------
    images : (L, H, W, C) array_like
        The candidate images, aligned.
    unary : (H, W, L) array_like
        ``D_p(k)``; ``inf`` forbids a label at a pixel.
    region : (H, W) bool array_like, optional
        Pixels to label (default: all); the others get -1. A region pixel
        where every label is forbidden gets -1 too.
    smoothness : float
        Weight of the seam cost.
    gradient_weighted : bool
        Divide by the edge strength so seams follow edges.
    max_cycles : int
        Most expansion cycles over all labels.
    eps : float
        Regulariser of the division by the gradients (the ``eps`` of ``V_pq``).
    labels : (H, W) int array_like, optional
        Initial labelling (default: the cheapest label per pixel).

    Returns
    -------
    (H, W) int ndarray
        The label of each pixel, -1 outside ``region``.

    Examples
    --------
    >>> import numpy as np
    >>> imgs = np.zeros((2, 6, 8, 1)); imgs[1] = 1.0
    >>> u = np.zeros((6, 8, 2)); u[:, :2, 1] = np.inf; u[:, -2:, 0] = np.inf
    >>> lab = multilabel_seams(imgs, u, smoothness=0.1)
    >>> lab[0].tolist()
    [0, 0, 0, 0, 0, 0, 1, 1]
    """
    imgs = np.asarray(images, dtype=np.float64)
    if imgs.ndim == 3:
        imgs = imgs[..., None]
    if imgs.ndim != 4 or imgs.shape[0] < 1:
        raise ValueError(f"images must be (L, H, W, C), got shape {np.shape(images)}")
    L, H, W = imgs.shape[:3]
    if not np.all(np.isfinite(imgs)):
        raise ValueError("images contain NaN or infinite values")
    u = np.asarray(unary, dtype=np.float64)
    if u.shape != (H, W, L):
        raise ValueError(f"unary must have shape {(H, W, L)}, got {u.shape}")
    if np.isnan(u).any() or (u == -np.inf).any():
        raise ValueError("unary contains NaN or -inf")
    if not isinstance(max_cycles, (int, np.integer)) or max_cycles < 1:
        raise ValueError(f"max_cycles must be a positive int, got {max_cycles!r}")
    reg = np.ones((H, W), bool) if region is None else as_mask(region, shape=(H, W), name="region")
    allowed = np.isfinite(u)
    reg = reg & allowed.any(axis=2)
    out = np.full((H, W), -1, np.int64)
    if not reg.any():
        return out
    rows, cols = np.nonzero(reg)
    r0, r1, c0, c1 = rows.min(), rows.max() + 1, cols.min(), cols.max() + 1
    reg = reg[r0:r1, c0:c1]
    imgs = imgs[:, r0:r1, c0:c1]
    finite_max = float(np.abs(u[np.isfinite(u)]).max()) if np.isfinite(u).any() else 0.0
    hard = max(_HARD, 1e3 * finite_max)
    u = np.where(np.isfinite(u), u, hard)[r0:r1, c0:c1]
    smooth = float(smoothness)
    gw = bool(gradient_weighted)
    grads = np.stack([gradient_magnitude(im) for im in imgs]) if gw else np.zeros((L, 1, 1))
    imgs = np.ascontiguousarray(imgs)
    if labels is None:
        lab = np.argmin(u, axis=2)
    else:
        lab = np.asarray(labels)
        if lab.shape != (H, W) or not np.issubdtype(lab.dtype, np.integer):
            raise ValueError(f"labels must be an int array of shape {(H, W)}")
        lab = np.clip(lab[r0:r1, c0:c1], 0, L - 1).astype(np.int64)
    lab = np.where(reg, lab, 0)
    energy = _labelling_energy(u, imgs, grads, lab, reg, smooth, eps, gw)
    st = {1: np.array([[0, 0, 0], [0, 0, 1], [0, 0, 0]]), 0: np.array([[0, 0, 0], [0, 0, 0], [0, 1, 0]])}
    if L > 1:
        for _ in range(int(max_cycles)):
            improved = False
            for a in range(L):
                e1 = u[..., a].copy()                        # cost of switching to a
                e0 = np.take_along_axis(u, lab[..., None], 2)[..., 0]
                caps = {1: np.zeros(lab.shape), 0: np.zeros(lab.shape)}
                _expansion_terms(imgs, grads, lab, reg, a, smooth, eps, gw, e0, e1, caps[1], caps[0])
                g = maxflow.Graph[float]()
                ids = g.add_grid_nodes(lab.shape)
                for axis in (0, 1):
                    g.add_grid_edges(ids, weights=caps[axis], structure=st[axis], symmetric=False)
                m = np.minimum(e0, e1)
                g.add_grid_tedges(ids, np.where(reg, e1 - m, 0.0), np.where(reg, e0 - m, 0.0))
                g.maxflow()
                take = g.get_grid_segments(ids) & reg
                if not take.any():
                    continue
                new = np.where(take, a, lab)
                e_new = _labelling_energy(u, imgs, grads, new, reg, smooth, eps, gw)
                if e_new < energy - 1e-9 * max(1.0, abs(energy)):
                    lab, energy, improved = new, e_new, True
            if not improved:
                break
    lab = np.where(reg & (np.take_along_axis(u, lab[..., None], 2)[..., 0] < hard), lab, -1)
    out[r0:r1, c0:c1] = lab
    return out
