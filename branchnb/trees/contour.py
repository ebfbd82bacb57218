"""Pin points, resampling and the simplified contour (paper, Sec. "Contour resampling").

Given the tree contour ``C`` of a normalised exemplar:

* **Pin points.** ``B`` is the tree bottom (the lowest contour point, the
  median one if several share the lowest row). ``R`` and ``L`` are the top
  right and top left of the trunk: walking along ``C`` from ``B`` to the
  right and to the left, the first points that belong to the crown. With no
  visible trunk, ``L = R = B``. The trunk/crown split comes from a trunk mask
  (the crown/trunk segmentation, or the geometric fallback
  :func:`stem_trunk_mask`).
* **Resampling.** ``C`` is resampled by chord length to ``N = 2000`` points
  with fixed counts per segment: 200 on the right trunk side (``B -> R``),
  1600 on the crown (``R -> L``) and 200 on the left trunk side
  (``L -> B``). So ``B``, ``R`` and ``L`` sit at the fixed indices
  ``0``, ``200`` and ``1800`` of every resampled contour ``C_r``, and the
  contours of different trees correspond point by point. The shape vector
  is ``C_r`` minus its centroid, flattened to ``2N`` numbers
  ``(x_0, y_0, x_1, y_1, ...)``.
* **Simplified contour.** ``C_s``: the interior of ``C_r`` is filled,
  dilated (8 iterations of a 3 x 3 square), and its outer border resampled
  to ``M = 20`` points with the same proportions per segment (2 / 16 / 2,
  pinned at the border points nearest ``B``, ``R``, ``L``). ``C_s`` is the
  cage of the mean-value-coordinate colour transfer.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import cv2
import numpy as np

from ..core.image import as_mask, as_points, composite_over
from ..core.io import encode_png
from ..core.params import check_params, param
from ..core.polyline import arc_length
from ..core.render import draw_polylines
from ..core.validate import Image, checked
from .contour_pins import PinPoints, pin_points, stem_trunk_mask  # noqa: F401  (re-exported)
from .exemplar import signed_area
from .morph import fill_contour

__all__ = [
    "ContourParams",
    "PinPoints",
    "TreeContour",
    "stem_trunk_mask",
    "pin_points",
    "segment_counts",
    "resample_pinned",
    "shape_vector",
    "simplify_contour",
    "tree_contour",
]


@dataclass
class ContourParams:
    """Contour resampling parameters (defaults: the paper's).

    Parameters
    ----------
    n_points : int
        ``N``, points of the resampled contour ``C_r`` (paper: 2000).
    n_crown : int
        Points on the crown segment ``R -> L`` (paper: 1600); each trunk
        side gets ``(N - n_crown) / 2`` (paper: 200).
    m_points : int
        ``M``, points of the simplified contour ``C_s`` (paper: 20, its
        speed/quality sweet spot).
    dilation : int
        Dilation iterations (3 x 3) before simplification (paper: 8).
    trunk_radius : float
        Radius, as a fraction of the image size, of the window that decides
        whether a contour point is trunk (majority of opaque pixels in the
        window are trunk); it makes the pin points robust to outlines or
        stray labels in the trunk mask.

    Examples
    --------
    >>> p = ContourParams(m_points=30)
    >>> p.n_points, p.n_crown, p.m_points
    (2000, 1600, 30)
    """

    n_points: int = param(2000, min=40, max=8000, step=10, help="N, resampled contour points")
    n_crown: int = param(1600, min=20, max=8000, step=10, help="points on the crown R -> L")
    m_points: int = param(20, min=6, max=200, step=1, help="M, simplified contour points (paper: 20)")
    dilation: int = param(8, min=0, max=64, step=1, help="dilation iterations before simplifying")
    trunk_radius: float = param(0.015, min=0.0, max=0.2, step=0.005,
                                help="window radius (fraction of size) to label contour points",
                                ui=False)


def _check_contour_params(p: ContourParams) -> ContourParams:
    check_params(p)
    if p.n_crown >= p.n_points or (p.n_points - p.n_crown) % 2:
        raise ValueError(
            f"params.n_crown must be < n_points with an even remainder for the two trunk sides, "
            f"got n_points={p.n_points}, n_crown={p.n_crown}"
        )
    return p


def segment_counts(n: int, n_crown: int) -> tuple[int, int, int]:
    """Points per segment ``(B -> R, R -> L, L -> B)`` for ``n`` points, ``n_crown`` on the crown.

    For the simplified contour use the crown share of the full one:
    ``segment_counts(20, round(20 * 1600 / 2000))`` is ``(2, 16, 2)``.

    Parameters
    ----------
    n : int
        Total number of contour points (``N`` for ``C_r``, ``M`` for ``C_s``).
    n_crown : int
        Points on the crown segment ``R -> L``; the rest is split evenly
        between the two trunk sides (an odd remainder goes to the crown).

    Returns
    -------
    (int, int, int)
        Points on ``B -> R``, ``R -> L`` and ``L -> B``; they add up to ``n``.

    Examples
    --------
    >>> segment_counts(2000, 1600)
    (200, 1600, 200)
    >>> segment_counts(20, 15)
    (2, 16, 2)
    """
    t = (n - n_crown) // 2
    return t, n - 2 * t, t



def _sample_closed(points: np.ndarray, s_new: np.ndarray) -> np.ndarray:
    """Points at arc lengths ``s_new`` along a closed polyline starting at points[0]."""
    loop = np.vstack([points, points[:1]])
    s = arc_length(loop)
    keep = np.concatenate([[True], np.diff(s) > 1e-12])
    s, loop = s[keep], loop[keep]
    return np.stack([np.interp(s_new, s, loop[:, 0]), np.interp(s_new, s, loop[:, 1])], axis=1)


def resample_pinned(contour, pins: PinPoints, n_points: int = 2000,
                    n_crown: int = 1600) -> np.ndarray:
    """Resample ``C`` by chord length with fixed point counts between the pin points.

    Parameters
    ----------
    contour : (K, 2) array_like
        The contour the ``pins`` indices refer to.
    pins : PinPoints
        ``B``, ``R``, ``L`` and their indices into ``contour`` (from
        :func:`pin_points`); ``has_trunk=False`` collapses both trunk sides
        onto ``B``.
    n_points, n_crown : int
        ``N`` and the crown's share (paper: 2000 and 1600).

    Returns
    -------
    (N, 2) float64 ndarray
        ``C_r`` with ``B`` at index 0, ``R`` at ``t = (N - n_crown) / 2`` and
        ``L`` at ``t + n_crown``; segments ``B -> R``, ``R -> L``, ``L -> B``
        are each sampled uniformly in arc length. Without a trunk the trunk
        segments collapse onto ``B``.

    Examples
    --------
    >>> import numpy as np
    >>> sq = np.array([(5, 10), (10, 10), (10, 0), (0, 0), (0, 10)], float)
    >>> pins = PinPoints(sq[0], sq[1], sq[4], 0, 1, 4, True)
    >>> cr = resample_pinned(sq, pins, 40, 30)
    >>> cr[[0, 5, 35]].tolist()
    [[5.0, 10.0], [10.0, 10.0], [0.0, 10.0]]
    """
    c = as_points(contour, name="contour", min_points=3)
    k = len(c)
    t_right, n_c, t_left = segment_counts(n_points, n_crown)
    rolled = np.roll(c, -pins.ib, axis=0)
    jr = (pins.ir - pins.ib) % k
    jl = (pins.il - pins.ib) % k
    if not pins.has_trunk:
        jr = jl = 0
    elif not (0 < jr < jl < k):
        raise ValueError("pins are not in the order B -> R -> L along the contour")
    loop = np.vstack([rolled, rolled[:1]])
    s = arc_length(loop)
    s_b, s_end = 0.0, s[-1]
    s_r, s_l = (s[jr], s[jl]) if pins.has_trunk else (0.0, s_end)
    s_new = np.concatenate([
        np.linspace(s_b, s_r, t_right, endpoint=False),
        np.linspace(s_r, s_l, n_c, endpoint=False),
        np.linspace(s_l, s_end, t_left, endpoint=False),
    ])
    return _sample_closed(rolled, s_new)


def shape_vector(resampled) -> np.ndarray:
    """Mean-subtracted ``2N`` shape vector ``(x_0, y_0, x_1, y_1, ...)`` of ``C_r``.

    Parameters
    ----------
    resampled : (N, 2) array_like
        ``C_r``, points (x, y) in pixels; any number of points >= 1.

    Returns
    -------
    (2N,) float64 ndarray
        The points minus their centroid, interleaved x, y. Vectors of trees
        resampled with the same pin layout can be compared or mixed.

    Raises
    ------
    ValueError
        If ``resampled`` is not a list of 2-D points.

    Examples
    --------
    >>> shape_vector([(0, 0), (2, 0), (2, 2), (0, 2)]).tolist()
    [-1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0]
    """
    p = as_points(resampled, name="resampled", min_points=1)
    return (p - p.mean(axis=0)).ravel()


def _crown_span(border: np.ndarray, cr: np.ndarray, t: int, s_pts: np.ndarray) -> tuple[float, float]:
    """Arc lengths along ``border`` (from ``B``) of the first and last point nearest a crown point of ``C_r``."""
    n = len(cr)
    k = np.empty(len(border), np.int64)
    for i in range(0, len(border), 512):
        d = ((border[i:i + 512, None, :] - cr[None, :, :]) ** 2).sum(axis=2)
        k[i:i + 512] = d.argmin(axis=1)
    crown = np.flatnonzero((k >= t) & (k <= n - t))
    if len(crown) < 2:
        return 0.0, 0.0
    return float(s_pts[crown[0]]), float(s_pts[crown[-1]])


def simplify_contour(resampled, n_crown_fraction: float = 0.8, *, m_points: int = 20,
                     dilation: int = 8, n_points_crown: int | None = None) -> np.ndarray:
    """Simplified contour ``C_s``: fill ``C_r``, dilate, resample the border to ``M`` points.

    Parameters
    ----------
    resampled : (N, 2) array_like
        ``C_r`` with the pin layout of :func:`resample_pinned`.
    n_crown_fraction : float
        Crown share of ``C_r`` (``n_crown / N``, paper: 0.8); sets where
        ``R`` and ``L`` are in ``C_r`` and the split of ``C_s``.
    m_points : int
        ``M`` (paper: 20).
    dilation : int
        3 x 3 dilation iterations (paper: 8).
    n_points_crown : int, optional
        Number of crown points of ``C_r`` itself; when given it overrides
        ``n_crown_fraction`` (exact for ``N``, no rounding).

    Returns
    -------
    (M, 2) float64 ndarray
        Counter-clockwise on screen, starting at the border point nearest
        ``B``; the points nearest ``R`` and ``L`` sit at the same fixed
        indices as in ``C_r``'s proportions (2 and 18 for M = 20), so the
        simplified contours of different trees correspond too.

    Raises
    ------
    ValueError
        If ``m_points < 6`` or ``resampled`` has fewer than 6 points.

    Notes
    -----
    Beyond the paper: ``R`` and ``L`` are placed at the border points nearest
    them; where those come in the wrong order (a thin trunk under a wide crown,
    as a palm's, puts both deep inside the dilated shape) the crown spans the
    border points whose nearest point of ``C_r`` is a crown point. The former
    fallback gave the whole border to the crown, so the palm's cage did not
    correspond to its mixes' and every "more like this" of the palm silhouette
    cut its trunk at 0.78 of the height and merged its fronds (now 1.00,
    fronds as thin as the exemplar's: ``tests/test_trees_flatmix.py``), and
    the bent trunks of drawn palms' variations kinked where the cage's
    crown vertices ran down them. Of 63 trees (the samples, 32 drawn trees,
    8 procedural styles at 128 px) only the 5 palms' cages change.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 * np.pi, 100, endpoint=False)
    >>> circle = np.stack([50 + 30 * np.cos(t), 50 + 30 * np.sin(t)], axis=1)
    >>> simplify_contour(circle, m_points=10, dilation=2).shape
    (10, 2)
    """
    cr = as_points(resampled, name="resampled", min_points=6)
    n = len(cr)
    n_crown = int(round(n * n_crown_fraction)) if n_points_crown is None else n_points_crown
    t, _, _ = segment_counts(n, n_crown)
    b, r, l = cr[0], cr[t], cr[n - t]  # noqa: E741
    if m_points < 6:
        raise ValueError(f"m_points must be >= 6, got {m_points}")
    pad = int(dilation) + 3
    lo = np.floor(cr.min(axis=0)).astype(int) - pad
    hi = np.ceil(cr.max(axis=0)).astype(int) + pad
    size = (int(hi[1] - lo[1]) + 1, int(hi[0] - lo[0]) + 1)
    local = cr - lo
    mask = fill_contour(local, size).astype(np.uint8)
    # Thin contours (no pixel centre inside) still get a footprint.
    cv2.polylines(mask, [np.round(local).astype(np.int32)], True, 1)
    if dilation > 0:
        mask = cv2.dilate(mask, np.ones((3, 3), np.uint8), iterations=int(dilation))
    borders, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    border = max(borders, key=cv2.contourArea)[:, 0, :].astype(np.float64) + lo
    if signed_area(border) > 0:
        border = border[::-1]
    ib = int(np.argmin(np.hypot(*(border - b).T)))
    border = np.roll(border, -ib, axis=0)
    loop = np.vstack([border, border[:1]])
    s = arc_length(loop)
    total = s[-1]
    s_pts = s[:-1]
    sr = float(s_pts[np.argmin(np.hypot(*(border - r).T))])
    sl = float(s_pts[np.argmin(np.hypot(*(border - l).T))])
    mt, mc, _ = segment_counts(m_points, int(round(m_points * n_crown / n)))
    gap = 0.5 * total / m_points
    if not (0 < sr < sl < total):
        # Beyond the paper: on a thin trunk under a wide crown (a palm) R and L lie deep
        # inside the dilated shape and the border point nearest R can come after the one
        # nearest L; the former fallback then gave the whole border to the crown, so the
        # cage's crown vertices ran down the trunk in this tree and not in the others and
        # a mix squashed its trunk and fronds. Instead the crown spans the border points
        # whose nearest point of C_r is a crown point (from the first to the last of them).
        sr, sl = _crown_span(border, cr, t, s_pts)
    # Keep the order B -> R -> L and distinct vertices even for a tiny or absent trunk.
    if not (0 < sr < sl < total):
        sr, sl = gap, total - gap
    sr = min(max(sr, gap), total - 3 * gap)
    sl = max(min(sl, total - gap), sr + 2 * gap)
    s_new = np.concatenate([
        np.linspace(0.0, sr, mt, endpoint=False),
        np.linspace(sr, sl, mc, endpoint=False),
        np.linspace(sl, total, mt, endpoint=False),
    ])
    return _sample_closed(border, s_new)


@dataclass
class TreeContour:
    """The contour data of one tree: ``C``, pin points, ``C_r``, shape vector and ``C_s``.

    Parameters
    ----------
    contour : (K, 2) ndarray
        ``C`` (border pixel centres, counter-clockwise on screen).
    pins : PinPoints
        ``B``, ``R``, ``L`` with indices into ``contour``.
    resampled : (N, 2) ndarray
        ``C_r``.
    simplified : (M, 2) ndarray
        ``C_s``.
    params : ContourParams
        The parameters ``C_r`` and ``C_s`` were made with (``N``, the crown
        share and ``M`` give the fixed pin indices).
    shape : (H, W)
        Size of the image the contour lives in.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.trees.exemplar import extract_contours
    >>> alpha = np.zeros((64, 64), bool); alpha[10:50, 12:52] = True; alpha[50:60, 28:36] = True
    >>> tc = tree_contour(extract_contours(alpha).tree, alpha)
    >>> tc.resampled.shape, tc.simplified.shape, tc.pin_indices
    ((2000, 2), (20, 2), (0, 200, 1800))
    """

    contour: np.ndarray
    pins: PinPoints
    resampled: np.ndarray
    simplified: np.ndarray
    params: ContourParams
    shape: tuple[int, int]

    @property
    def pin_indices(self) -> tuple[int, int, int]:
        """Fixed indices of ``B``, ``R``, ``L`` in ``C_r`` (0, 200, 1800 for the paper)."""
        t, c, _ = segment_counts(self.params.n_points, self.params.n_crown)
        return 0, t, t + c

    @property
    def centroid(self) -> np.ndarray:
        """Mean of ``C_r``."""
        return self.resampled.mean(axis=0)

    @property
    def vector(self) -> np.ndarray:
        """Mean-subtracted 2N shape vector."""
        return shape_vector(self.resampled)

    @checked(background=Image())
    def render(self, background=None) -> np.ndarray:
        """RGB picture: ``C_r`` (green), ``C_s`` (orange), ``B``/``R``/``L`` (red/blue/magenta).

        Parameters
        ----------
        background : (H, W[, C]) array_like, optional
            Image drawn faded (half-way to white) under the curves; None
            draws on white.

        Returns
        -------
        (H, W, 3) float32 ndarray
            The picture, in [0, 1], of the contour's image size.
        """
        h, w = self.shape
        bg = np.ones((h, w, 3), np.float32) if background is None else composite_over(
            background, (1.0, 1.0, 1.0)) * 0.5 + 0.5
        lw = max(1.0, h / 300)
        img = draw_polylines(bg, [np.vstack([self.resampled, self.resampled[:1]])],
                             widths=lw, colors=(0.1, 0.6, 0.1))
        img = draw_polylines(img, [np.vstack([self.simplified, self.simplified[:1]])],
                             widths=lw, colors=(0.95, 0.5, 0.0))
        img = draw_polylines(img, [p[None] for p in self.simplified], widths=3 * lw,
                             colors=(0.95, 0.5, 0.0))
        i_b, i_r, i_l = self.pin_indices
        for idx, col in ((i_b, (0.9, 0.0, 0.0)), (i_r, (0.0, 0.2, 0.9)), (i_l, (0.8, 0.0, 0.8))):
            img = draw_polylines(img, [self.resampled[idx][None]], widths=6 * lw, colors=col)
        return img

    def _repr_png_(self) -> bytes:
        return encode_png(self.render())


@checked()
def tree_contour(contour, alpha, trunk_mask=None, params: ContourParams | None = None, *,
                 corners: bool = True, **overrides) -> TreeContour:
    """All contour steps for one tree: pin points, ``C_r`` and ``C_s``.

    Parameters
    ----------
    contour : (K, 2) array_like
        The tree contour ``C``.
    alpha : (H, W) array_like
        Opacity mask of the tree.
    trunk_mask : (H, W) array_like, optional
        Trunk pixels; None uses :func:`stem_trunk_mask`.
    params : ContourParams, optional
        ``N``, crown share, ``M``, dilation and trunk window; None uses the
        paper's defaults (2000 / 1600 / 20 / 8).
    corners : bool
        See :func:`pin_points` (off for pixel art).
    **overrides
        Fields of ``params`` to override (e.g. ``m_points=30``).

    Returns
    -------
    TreeContour
        ``C`` (made counter-clockwise on screen), the pins, ``C_r`` and ``C_s``.

    Raises
    ------
    ValueError
        If ``n_crown >= n_points`` or their difference is odd, or the
        contour has fewer than 3 points.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.trees.exemplar import extract_contours
    >>> alpha = np.zeros((64, 64), bool); alpha[10:50, 12:52] = True; alpha[50:60, 28:36] = True
    >>> tc = tree_contour(extract_contours(alpha).tree, alpha, m_points=12)
    >>> tc.pins.has_trunk, tc.simplified.shape
    (True, (12, 2))
    """
    p = params if params is not None else ContourParams()
    if overrides:
        p = replace(p, **overrides)
    p = _check_contour_params(p)
    opaque = as_mask(alpha, name="alpha")
    c = as_points(contour, name="contour", min_points=3)
    if signed_area(c) > 0:
        c = c[::-1].copy()
    pins = pin_points(c, opaque, trunk_mask, radius=p.trunk_radius, corners=corners)
    cr = resample_pinned(c, pins, p.n_points, p.n_crown)
    cs = simplify_contour(cr, m_points=p.m_points, dilation=p.dilation, n_points_crown=p.n_crown)
    return TreeContour(c, pins, cr, cs, p, opaque.shape)
