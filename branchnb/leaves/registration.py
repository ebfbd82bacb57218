"""Non-rigid registration of an exemplar leaf to the training leaf: TPS-RPM.

The paper registers every exemplar to the training leaf with TPS-RPM
(Chui & Rangarajan 2003) on about 100 keypoints per leaf
(:func:`branchnb.leaves.keypoints.edge_keypoints`). No maintained Python 3
implementation exists; this is one, in numpy.

Steps
-----
1. **Start** (:func:`start_candidates`): a similarity of the exemplar's
   blade onto the training blade from their moments (centroids matched,
   scale from the areas). The rotation (the principal axes have a sign
   ambiguity, and round leaves such as maple have no reliable axis) is
   searched over the whole circle in ``rotation_step`` steps, optionally
   mirrored, scored by the symmetric chamfer distance of the outlines and
   of the thin parts; ``start="affine"`` refines each candidate to an
   affine map by trimmed ICP on the outlines.
2. **TPS-RPM**. Source points ``v_i`` (the exemplar's keypoints after the
   start map) and target points ``x_a`` (the training leaf's), in
   coordinates normalised by the training blade (centroid at 0, radius
   ``sqrt(area / pi)`` = 1), so the parameters do not depend on image size.
   Deterministic annealing from ``T_init`` (largest squared distance
   between the point sets) down to ``T_final`` (mean squared
   nearest-neighbour distance of the targets) at rate ``r``; at every
   temperature, ``iterations`` rounds of

   * softassign: ``m_ai = exp(-|x_a - f(v_i)|^2 / 2T) / T``, with an
     outlier row and column (``exp(-|x - centre|^2 / 2 T_init) / T_init``,
     the paper's outlier cluster at the centre of mass), points of
     different labels (outline / interior) never matched, then Sinkhorn
     normalisation of the inlier rows and columns;
   * the thin-plate spline ``f(v) = d^T [1, v] + sum_j w_j U(|v - v_j|)``,
     ``U(r) = r^2 log r``, fitted to the virtual targets
     ``y_i = sum_a m_ai x_a / sum_a m_ai`` with weights
     ``sum_a m_ai`` by minimising
     ``sum_i c_i |y_i - f(v_i)|^2 + lambda1 tr(w^T Phi w) + lambda2 |D - I|^2``
     (D: the linear part of ``d``; the translation is free), with the
     regularisers annealed as in the paper: ``lambda = lambda_init K T``.

   **Stages.** TPS-RPM runs first on ``outline_points`` samples of the
   two *laminae* outlines (the blade without thin parts such as the
   petiole, which bends and varies in length from leaf to leaf and is no
   shared shape), once from each of the ``n_starts`` best start maps; the
   run whose registered lamina outline lies closest to the training
   leaf's wins (this settles rotations that the outline cannot: a
   five-lobed blade looks alike every 72 degrees). When both leaves have
   a petiole, its root (the base) is a landmark of its own label, and so
   is the apex (the lamina outline point farthest from the base) when
   both have a clear one (15 % farther than any point a quarter of the
   outline away: an elliptic blade's tip, not one of a palmate blade's
   near-equal lobes).

   **Vein stage** (``veins=True``; off by default, see below). An outline without
   corners does not tell where a material point went along it; a leaf's
   main veins do (a pinnate blade's midrib and secondaries, a palmate
   blade's primaries: shared by every leaf of a kind, unlike the fine
   reticulum between them). :func:`~branchnb.leaves.keypoints.vein_keypoints`
   samples ``vein_points`` points along the long, nearly straight ridges
   of each lamina; TPS-RPM then refines the outline stage's spline with
   the outline samples and the vein points, each matched only to its own
   kind, from ``vein_t_init`` times the mean squared nearest-neighbour
   distance, ``vein_stiffness`` times stiffer, and with a softassign cost
   ``vein_orientation * sin^2`` of the angle between two vein points'
   directions (a secondary's point must not match a crossing fine vein).
   A leaf with fewer than 8 vein points keeps its outline registration.
   An optional further stage (``refine=True``) refines with all edge
   keypoints, interior edges included, from a low temperature and stiffer.

   **Measured defaults** (``python -m branchnb.leaves._measure
   registration``: mean true-keypoint error cut against the affine start,
   8 seeds x 2 pairs). The edge keypoints of the interior made the
   registration *worse* (elliptic 0.36 with ``refine``, against 0.51
   without): they lie on spots and fine veins that differ from leaf to
   leaf (figures in this paragraph with ``lambda1_init`` 10). The vein
   stage without the orientation cost did not help either
   (0.48: a fine vein's point pulled a secondary's); with it, at 192 px,
   elliptic 0.52 -> 0.55, trilobed 0.60 -> 0.61, lobed 0.55 -> 0.55, but
   at 384 px elliptic 0.49 -> 0.40 (two pairs locked onto the neighbouring
   secondaries; with ``lambda1_init`` 3, elliptic 0.59 -> 0.51 at 192 px
   and 0.57 -> 0.43 at 384 px, trilobed 0.61 -> 0.64, lobed 0.59 -> 0.57).
   So both ``veins`` and ``refine`` are off by default; the
   elliptic kind's serrate teeth make its outline observable instead.
   Because the points are normalised by the blade radius (Chui's data lie
   in the unit square), ``lambda1_init`` is measured, not Chui's: 3
   (cut at 192 / 384 px: lobed 0.59 / 0.60, trilobed 0.61 / 0.61,
   elliptic 0.59 / 0.57; with 10, the best before the teeth became
   material, 0.55 / 0.55, 0.60 / 0.59, 0.52 / 0.49; with 1, as good on
   the procedural leaves but one of six maples folded); ``T_final`` is a
   tenth of the mean squared nearest-neighbour distance (with Chui's
   value the final matches stay too soft and the outlines shrink
   inwards). A spline that still folds the lamina is refitted stiffer
   (``fold_retries``).

   **Speed** (beyond the paper; issue 22). The annealing loop is compiled
   (numba; the numpy loop ``_anneal`` stays as the fallback and the
   reference). While ``T >= (0.7 * stride * spacing)^2`` it runs on every
   ``stride``-th point (8, 4, 2) of each label: the softassign blurs over
   ``sqrt(T)``, so closer points add nothing but cost. Sinkhorn stops
   when the rows sum to 1 within 1 %, and a temperature ends early once
   the spline moves less than ``0.01 sqrt(T_final)``. Measured (``python
   -m branchnb.leaves._measure registration``: identical summary; 6
   procedural and 12 maple pairs: maps within 0.03 px mean, 0.1 px at most,
   of the plain loop's, blade IoU unchanged to 3 decimals): 3.5 -> 0.7 s
   CPU per pair at ~250-370 px. The splines' values and Jacobians (the
   dense maps' Newton inverse) are compiled too: two registrations with
   the dense map to the training frame at 1000 px, 13.0 -> 4.2 s CPU.
   The first call compiles for ~15 s CPU (cached on disk afterwards).

3. **Dense maps**. ``forward`` (exemplar -> training) is the start map
   followed by the splines. ``inverse`` is a thin-plate spline fitted
   to forward-mapped samples of the exemplar, refined by Newton steps on
   the exact forward map, so ``inverse(forward(p))`` returns ``p``. Both
   are evaluated on a grid of ``grid_step`` pixels and interpolated
   bilinearly, which is fast at a megapixel and exact to a small
   fraction of a pixel for a smooth spline.

References
----------
H. Chui, A. Rangarajan, "A new point matching algorithm for non-rigid
registration", Computer Vision and Image Understanding 89 (2003) 114-141.
"""

from __future__ import annotations

import hashlib
import threading
from dataclasses import dataclass, field, replace

import cv2
import numba
import numpy as np
from scipy.ndimage import binary_fill_holes as ndi_fill_holes
from scipy.ndimage import label as ndi_label
from scipy.spatial import cKDTree
from threadpoolctl import threadpool_limits

from ..core.image import as_float_image, as_mask
from ..core.params import check_params, param
from ..core.validate import COORD_LIMIT, Choice, Instance, Int, Real, check_finite, check_int, checked, real_array
from ..core.warp import remap
from .exemplar import Exemplar, leaf_exemplar
from .keypoints import OUTLINE, VEIN, Keypoints, edge_keypoints, vein_keypoints

__all__ = ["RegistrationParams", "Registration", "register", "start_alignment", "start_candidates", "tps_rpm",
           "draw_registration", "ThinPlateSpline", "split_petiole"]


@dataclass
class RegistrationParams:
    """Parameters of :func:`register`; defaults are the papers' values.

    Where a default is measured rather than a paper's, the entry says so
    (:mod:`branchnb.leaves.registration` has the figures).

    Parameters
    ----------
    n_keypoints : int
        Keypoints per leaf (Assa & Cohen-Or: about 100).
    outline_fraction : float
        Fraction of them on the blade outline (default 0.35).
    anneal_rate : float
        Chui & Rangarajan's ``r`` (0.93).
    lambda1_init, lambda2_init : float
        Initial bending / affine regularisation (Chui & Rangarajan: 1 and
        0.01), multiplied by the number of points and the temperature.
        ``lambda1_init`` defaults to 3, measured for points normalised by
        the blade radius (Chui's data lie in the unit square).
    iterations : int
        Softassign / spline rounds per temperature (Chui & Rangarajan: 5).
    sinkhorn_iterations : int
        Row/column normalisation rounds per softassign (default 10; fewer
        once the rows sum to 1 within 1 %).
    t_final_scale : float
        ``T_final`` = this times the mean squared nearest-neighbour
        distance of the training keypoints (Chui & Rangarajan: 1; default
        0.1, measured: with 1 the final matches stay too soft and the
        outlines shrink inwards).
    use_labels : bool
        Match outline points only with outline points and interior points
        with interior points (default True).
    outline_points : int
        Lamina outline samples per leaf in the outline stage (default 150).
    n_starts : int
        Start maps tried by the outline stage; the best registered outline
        fit wins (default 3).
    fold_retries : int
        How many times an outline spline that folds the lamina (Jacobian
        determinant <= 0 somewhere on it) is refitted with ``lambda1``
        three times larger (default 3).
    apex : bool
        Also match the apexes as landmarks when both leaves have a clear
        one (default True).
    veins : bool
        Run the vein stage: refine with outline and main-vein points, each
        matched to its own kind (default False: it did not help on the
        measured families).
    vein_points : int
        Points along the main veins per leaf (default 60).
    vein_orientation : float
        Softassign cost of crossed vein directions, ``vein_orientation *
        sin^2`` of the angle, in squared blade radii (default 0.02).
    vein_t_init : float
        Vein stage start temperature over the mean squared
        nearest-neighbour distance (default 16).
    vein_stiffness : float
        ``lambda1`` of the vein stage over that of the outline stage
        (default 10).
    refine : bool
        Refine with all edge keypoints, interior ones included (default
        False: interior edge keypoints made registration worse).
    refine_t_init : float
        Refinement start temperature over the mean squared
        nearest-neighbour distance (default 16).
    refine_stiffness : float
        ``lambda1`` of the refinement over that of the outline stage
        (default 10).
    start : {"similarity", "affine"}
        Family of start maps (default ``"similarity"``; ``"affine"``
        refines each by trimmed ICP on the outlines).
    rotation_step : float
        Degrees between the start rotations tried (default 5).
    mirror : bool
        Also try mirrored starts (leaves photographed from the back).
    grid_step : int
        Spacing (pixels) of the grid the dense maps are evaluated on
        (default 8).
    """

    n_keypoints: int = param(100, min=10, max=400, help="keypoints per leaf (paper: about 100)")
    outline_fraction: float = param(0.35, min=0.0, max=1.0, step=0.05, help="share of keypoints on the outline")
    anneal_rate: float = param(0.93, min=0.5, max=0.99, step=0.01, help="annealing rate r (Chui: 0.93)")
    lambda1_init: float = param(3.0, min=1e-4, max=1000.0, log=True,
                                help="bending regulariser lambda1 (Chui: 1 for unit-square data)")
    lambda2_init: float = param(0.01, min=0.0, max=100.0, help="affine regulariser lambda2 (Chui: 0.01)")
    iterations: int = param(5, min=1, max=50, help="rounds per temperature (Chui: 5)")
    sinkhorn_iterations: int = param(10, min=1, max=500, help="Sinkhorn normalisation rounds")
    t_final_scale: float = param(0.1, min=0.01, max=100.0, log=True,
                                 help="T_final / mean squared nearest-neighbour distance")
    use_labels: bool = param(True, help="match outline with outline, interior with interior")
    outline_points: int = param(150, min=10, max=400, help="outline samples of the outline stage")
    n_starts: int = param(3, min=1, max=12, help="start maps tried (the best outline fit wins)")
    fold_retries: int = param(3, min=0, max=10, help="stiffer refits (lambda1 x 3 each) of a folding spline")
    apex: bool = param(True, help="match the apexes too, when both leaves have a clear one")
    veins: bool = param(False, help="refine with the main veins: outline and vein points, each matched to its own kind")
    vein_points: int = param(60, min=8, max=400, help="points along the main veins per leaf")
    vein_orientation: float = param(0.02, min=0.0, max=10.0,
                                    help="cost of crossed vein directions (squared blade radii)")
    vein_t_init: float = param(16.0, min=1.0, max=1000.0, log=True,
                               help="vein stage start temperature / mean squared nearest-neighbour distance")
    vein_stiffness: float = param(10.0, min=0.01, max=1000.0, log=True,
                                  help="lambda1 of the vein stage / lambda1 of the outline stage")
    refine: bool = param(False, help="refine the outline registration with all keypoints")
    refine_t_init: float = param(16.0, min=1.0, max=1000.0, log=True,
                                 help="refinement start temperature / mean squared nearest-neighbour distance")
    refine_stiffness: float = param(10.0, min=0.01, max=1000.0, log=True,
                                    help="lambda1 of the refinement / lambda1 of the outline stage")
    start: str = param("similarity", options=("similarity", "affine"), help="start map family")
    rotation_step: float = param(5.0, min=0.5, max=90.0, help="degrees between start rotations")
    mirror: bool = param(False, help="also try mirrored starts")
    grid_step: int = param(8, min=1, max=64, help="grid spacing of the dense maps (px)")


# ---------------------------------------------------------------------------
# thin-plate spline

def _tps_kernel(r2: np.ndarray) -> np.ndarray:
    """``U = r^2 log r = r2 log(r2) / 2`` (0 at r = 0)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        out = 0.5 * r2 * np.log(r2)
    return np.where(r2 > 0, out, 0.0)


def _sqdist(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    # |a|^2 + |b|^2 - 2 a.b: one matrix product instead of an (N, K, 2) temporary.
    d = (a * a).sum(1)[:, None] + (b * b).sum(1)[None, :] - 2.0 * (a @ b.T)
    return np.maximum(d, 0.0)



@numba.njit(cache=True)
def _tps_eval_nb(p, c, w, d, jac):  # pragma: no cover
    """``f(p)`` and (if ``jac``) its Jacobian, one point at a time (no (N, K) temporaries at a megapixel)."""
    n, k = p.shape[0], c.shape[0]
    out = np.empty((n, 2))
    j = np.empty((n if jac else 0, 2, 2))
    for i in range(n):
        x, y = p[i, 0], p[i, 1]
        fx = d[0, 0] + x * d[1, 0] + y * d[2, 0]
        fy = d[0, 1] + x * d[1, 1] + y * d[2, 1]
        j00, j01, j10, j11 = d[1, 0], d[2, 0], d[1, 1], d[2, 1]
        for a in range(k):
            dx, dy = x - c[a, 0], y - c[a, 1]
            r2 = dx * dx + dy * dy
            if r2 > 0:
                lg = np.log(r2)
                u = 0.5 * r2 * lg  # U = r^2 log r
                fx += u * w[a, 0]
                fy += u * w[a, 1]
                if jac:
                    g = lg + 1.0  # dU/dp = (log r2 + 1) (p - c)
                    j00 += g * dx * w[a, 0]
                    j01 += g * dy * w[a, 0]
                    j10 += g * dx * w[a, 1]
                    j11 += g * dy * w[a, 1]
        out[i, 0], out[i, 1] = fx, fy
        if jac:
            j[i, 0, 0], j[i, 0, 1], j[i, 1, 0], j[i, 1, 1] = j00, j01, j10, j11
    return out, j


@dataclass
class ThinPlateSpline:
    """``f(p) = d^T [1, p] + sum_j w_j U(|p - c_j|)`` in 2-D.

    ``U(r) = r^2 log r``; call the spline on ``(N, 2)`` points to map them.

    Parameters
    ----------
    centres : (K, 2) ndarray
        The kernel centres ``c_j`` (the source points of a fit).
    w : (K, 2) ndarray
        Non-affine coefficients (``P^T w = 0``).
    d : (3, 2) ndarray
        Affine part: rows translation, x, y.
    """

    centres: np.ndarray
    w: np.ndarray
    d: np.ndarray

    @classmethod
    def identity(cls, centres) -> ThinPlateSpline:
        """The identity map on these centres (``w = 0``, ``d`` the identity).

        Parameters
        ----------
        centres : (K, 2) array_like
            Kernel centres.

        Returns
        -------
        ThinPlateSpline
        """
        c = _points(centres, "centres", limit=COORD_LIMIT)
        return cls(c, np.zeros_like(c), np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))

    @classmethod
    @checked(lambda1=Real(0.0, 1e12), lambda2=Real(0.0, 1e12))
    def fit(cls, source, target, *, weights=None, lambda1: float = 0.0,
            lambda2: float = 0.0) -> ThinPlateSpline:
        """The spline ``source -> target`` minimising TPS-RPM's regularised energy.

        Minimises ``sum_i c_i |target_i - f(source_i)|^2 + lambda1 tr(w^T Phi w)
        + lambda2 |D - I|^2`` (``D``: the linear part of ``d``; the
        translation is free).

        Parameters
        ----------
        source : (K, 2) array_like
            Source points, which become the centres.
        target : (K, 2) array_like
            Where each source point should go.
        weights : (K,) array_like, optional
            Non-negative weight ``c_i`` of each pair; None: all 1.
        lambda1 : float
            Bending regularisation (0: interpolate exactly).
        lambda2 : float
            Pull of the linear part towards the identity (0: free).

        Returns
        -------
        ThinPlateSpline

        Examples
        --------
        >>> import numpy as np
        >>> src = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0.5, 0.5]])
        >>> f = ThinPlateSpline.fit(src, src + (2, 3))
        >>> bool(np.allclose(f(src), src + (2, 3)))
        True
        """
        source = _points(source, "source", limit=COORD_LIMIT)
        target = _points(target, "target", limit=COORD_LIMIT)
        if target.shape != source.shape:
            raise ValueError(f"target must have the shape of source {source.shape}, got {target.shape}")
        if weights is not None:
            weights = real_array(weights, "weights", ndim=1, min=0.0, max=1e12)
            if weights.shape != (len(source),):
                raise ValueError(f"weights must have shape ({len(source)},), got {weights.shape}")
        return _SplineSystem(source).fit(target, weights=weights, lambda1=lambda1, lambda2=lambda2)

    def __call__(self, points) -> np.ndarray:
        return self._eval(points, False)[0]

    def _eval(self, points, jac: bool):
        p = np.ascontiguousarray(np.asarray(points, np.float64).reshape(-1, 2))
        return _tps_eval_nb(p, np.ascontiguousarray(self.centres, np.float64),
                            np.ascontiguousarray(self.w, np.float64), np.ascontiguousarray(self.d, np.float64),
                            jac)

    def jacobian(self, points) -> np.ndarray:
        """(N, 2, 2) ``J[n, i, j] = d f_i / d p_j``.

        Parameters
        ----------
        points : (N, 2) array_like
            Where to evaluate the Jacobian.

        Returns
        -------
        (N, 2, 2) float ndarray
        """
        p = np.ascontiguousarray(_points(points, "points", limit=COORD_LIMIT), np.float64)
        return _tps_eval_nb(p, np.ascontiguousarray(self.centres, np.float64),
                            np.ascontiguousarray(self.w, np.float64), np.ascontiguousarray(self.d, np.float64),
                            True)[1]


class _SplineSystem:
    """What a spline fit on fixed centres can precompute (TPS-RPM refits hundreds of times)."""

    def __init__(self, source):
        v = np.asarray(source, np.float64)
        if v.ndim != 2 or v.shape[1] != 2:
            raise ValueError(f"source must have shape (K, 2), got {v.shape}")
        self.v = v
        k = len(v)
        p = np.column_stack([np.ones(k), v])
        q, _ = np.linalg.qr(p, mode="complete")
        self.q2 = q[:, 3:]
        phi = _tps_kernel(_sqdist(v, v))
        np.fill_diagonal(phi, 0.0)
        self.phi = phi
        self.a = np.hstack([p, phi @ self.q2])
        self.bend = self.q2.T @ phi @ self.q2

    def fit(self, target, *, weights=None, lambda1=0.0, lambda2=0.0) -> ThinPlateSpline:
        y = np.asarray(target, np.float64)
        k = len(self.v)
        if y.shape != (k, 2):
            raise ValueError(f"target must have shape {(k, 2)}, got {y.shape}")
        c = np.ones(k) if weights is None else np.clip(np.asarray(weights, np.float64), 1e-6, None)
        ca = c[:, None] * self.a
        h = self.a.T @ ca
        rhs = ca.T @ y
        h[1, 1] += lambda2
        h[2, 2] += lambda2
        rhs[1:3] += lambda2 * np.eye(2)
        if k > 3:
            h[3:, 3:] += lambda1 * self.bend
        z = _solve(h, rhs)
        w = self.q2 @ z[3:] if k > 3 else np.zeros_like(self.v)
        return ThinPlateSpline(self.v, w, z[:3])


    def at_centres(self, f: ThinPlateSpline) -> np.ndarray:
        """``f(v)`` at the system's own centres (the kernel matrix is precomputed)."""
        return f.d[0] + self.v @ f.d[1:] + self.phi @ f.w


def _solve(a, b):
    try:
        return np.linalg.solve(a, b)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(a, b, rcond=None)[0]


# ---------------------------------------------------------------------------
# TPS-RPM

def _softassign(x, fv, lab_x, lab_v, t, t0, cx, cv, sinkhorn, pair_cost=None):
    n, k = len(x), len(fv)
    m = np.zeros((n + 1, k + 1))
    d2 = _sqdist(x, fv)
    if pair_cost is not None:
        d2 = d2 + pair_cost
    # Work in log space relative to the best entry so small T does not underflow.
    logm = -d2 / (2 * t) - np.log(t)
    if lab_x is not None:
        logm = np.where(lab_x[:, None] == lab_v[None, :], logm, -np.inf)
    log_out_col = -((x - cv) ** 2).sum(1) / (2 * t0) - np.log(t0)
    log_out_row = -((fv - cx) ** 2).sum(1) / (2 * t0) - np.log(t0)
    top = max(float(np.max(logm)), float(log_out_col.max()), float(log_out_row.max()))
    m[:n, :k] = np.exp(logm - top)
    m[:n, k] = np.exp(log_out_col - top)
    m[n, :k] = np.exp(log_out_row - top)
    for _ in range(sinkhorn):
        m[:n] /= np.maximum(m[:n].sum(1, keepdims=True), 1e-300)
        m[:, :k] /= np.maximum(m[:, :k].sum(0, keepdims=True), 1e-300)
    return m[:n, :k]


@checked(t_init=Real(0.0, 1e6, low_open=True))
def tps_rpm(source, target, *, source_labels=None, target_labels=None,
            params: RegistrationParams | None = None,
            t_init: float | None = None, pair_cost=None) -> tuple[ThinPlateSpline, np.ndarray]:
    """Match two point sets and fit a thin-plate spline ``source -> target`` (Chui & Rangarajan).

    Parameters
    ----------
    source : (K, 2) array_like
        Moving points ``v_i`` (already roughly aligned).
    target : (N, 2) array_like
        Fixed points ``x_a``.
    source_labels, target_labels : (K,), (N,) int array_like, optional
        Points are only matched to points with the same label.
    params : RegistrationParams, optional
        Annealing and regularisation (``anneal_rate``, ``lambda1_init``,
        ...); None: ``RegistrationParams()``.
    t_init : float, optional
        Start temperature; default (Chui & Rangarajan) the largest squared
        distance between the two sets. A refinement of a good alignment
        starts lower.
    pair_cost : (N, K) array_like, optional
        Non-negative cost added to the squared distance of every
        (target, source) pair in the softassign (e.g. an orientation
        difference), in squared normalised units.

    Returns
    -------
    spline : ThinPlateSpline
        ``source -> target``.
    match : (N, K) ndarray
        The final soft correspondence matrix (inlier part).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-1, 1, (60, 2))
    >>> v = x + 0.08 * np.sin(3 * x[:, ::-1])
    >>> f, m = tps_rpm(v, x)
    >>> float(np.abs(f(v) - x).mean()) < 0.02
    True
    """
    prm = check_params(params if params is not None else RegistrationParams(), name="params")
    v = _points(source, "source", limit=COORD_LIMIT)
    x = _points(target, "target", limit=COORD_LIMIT)
    if v.ndim != 2 or v.shape[1] != 2 or len(v) < 4:
        raise ValueError(f"source must be an (K, 2) array with K >= 4, got shape {v.shape}")
    if x.ndim != 2 or x.shape[1] != 2 or len(x) < 4:
        raise ValueError(f"target must be an (N, 2) array with N >= 4, got shape {x.shape}")
    if not (np.isfinite(v).all() and np.isfinite(x).all()):
        raise ValueError("source and target must be finite")
    lab_v = lab_x = None
    if source_labels is not None or target_labels is not None:
        if source_labels is None or target_labels is None:
            raise ValueError("give both source_labels and target_labels, or neither")
        lab_v, lab_x = np.asarray(source_labels), np.asarray(target_labels)
        if lab_v.shape != (len(v),) or lab_x.shape != (len(x),):
            raise ValueError("labels must have one entry per point")
    if pair_cost is not None:
        pair_cost = real_array(pair_cost, "pair_cost", ndim=2, min=0.0, max=1e12)
        if pair_cost.shape != (len(x), len(v)):
            raise ValueError(f"pair_cost must have shape {(len(x), len(v))}, got {pair_cost.shape}")
    nn = cKDTree(x).query(x, k=2)[0][:, 1]
    t_final = max(prm.t_final_scale * float(np.mean(nn ** 2)), 1e-12)
    t_init = float(_sqdist(x, v).max()) if t_init is None else max(float(t_init), t_final)
    cx = x.mean(0)
    f = ThinPlateSpline.identity(v)
    t = t_init
    # Hundreds of small solves: BLAS threads only add overhead (and stall on a busy machine).
    with threadpool_limits(1):
        system = _SplineSystem(v)
        try:
            return _anneal_compiled(x, v, system, lab_x, lab_v, t, t_init, t_final, prm, pair_cost)
        except (np.linalg.LinAlgError, ZeroDivisionError, ValueError):  # a singular system: the numpy loop copes
            return _anneal(x, v, f, system, lab_x, lab_v, t, t_init, t_final, cx, prm, pair_cost)


def _subsample_levels(x, v, lab_x, lab_v, t_init):
    """Point subsets for the high temperatures: ``(stride, t_end)``, coarsest first.

    At temperature ``T`` the softassign blurs over ``sqrt(T)``; points
    closer than that add little, so every ``stride``-th point
    (of each label, in the given order, e.g. along an outline) stands in
    for them while ``T >= (0.7 * stride * spacing)^2`` (measured: the registered
    maps moved by a few thousandths of a pixel).
    """
    if _SUB_MARGIN <= 0:
        return []
    nn = cKDTree(x).query(x, k=2)[0][:, 1]
    nn2 = float(np.mean(nn ** 2))
    out = []
    for stride in (8, 4, 2):
        t_end = _SUB_MARGIN ** 2 * stride ** 2 * nn2
        if t_init >= t_end and min(len(x), len(v)) >= 8 * stride:
            out.append((stride, t_end))
    return out


def _every(n, labels, stride):
    """Every ``stride``-th index of each label (all of a label with fewer than 4 * stride points)."""
    if labels is None:
        return np.arange(0, n, stride)
    keep = np.zeros(n, bool)
    for lab in np.unique(labels):
        idx = np.flatnonzero(labels == lab)
        keep[idx if len(idx) < 4 * stride else idx[::stride]] = True
    return np.flatnonzero(keep)


def _anneal_compiled(x, v, system, lab_x, lab_v, t, t_init, t_final, prm, pair_cost=None):
    use_lab = lab_x is not None
    lx, lv = np.zeros(len(x), np.int64), np.zeros(len(v), np.int64)
    if use_lab:  # any labels that compare equal -> integer codes
        codes = np.unique(np.concatenate([lab_x, lab_v]), return_inverse=True)[1].ravel()
        lx, lv = codes[:len(x)].astype(np.int64), codes[len(x):].astype(np.int64)
    x = np.ascontiguousarray(x, np.float64)
    v = np.ascontiguousarray(v, np.float64)
    cost = np.ascontiguousarray(pair_cost if pair_cost is not None else np.zeros((1, 1)), np.float64)
    cx = x.mean(0)
    fv = v.copy()
    levels = _subsample_levels(x, v, lab_x, lab_v, t)
    for stride, t_end in levels + [(1, 0.0)]:
        if stride == 1:
            xs, vs, lxs, lvs, cs, sys_ = x, v, lx, lv, cost, system
        else:
            ix, iv = _every(len(x), lab_x, stride), _every(len(v), lab_v, stride)
            xs, vs, lxs, lvs = x[ix], v[iv], lx[ix], lv[iv]
            cs = np.ascontiguousarray(cost[np.ix_(ix, iv)]) if pair_cost is not None else cost
            sys_ = _SplineSystem(vs)
        fvs = np.ascontiguousarray(fv if stride == 1 else fv[_every(len(v), lab_v, stride)])
        d, w, m, t, done = _anneal_nb(xs, vs, lxs, lvs, use_lab, cs, pair_cost is not None, sys_.phi,
                                      np.ascontiguousarray(sys_.a), np.ascontiguousarray(sys_.bend),
                                      np.ascontiguousarray(sys_.q2), float(t), float(t_init), float(t_final),
                                      float(prm.anneal_rate), int(prm.iterations), int(prm.sinkhorn_iterations),
                                      float(prm.lambda1_init), float(prm.lambda2_init), _SINK_TOL,
                                      _MOVE_TOL * np.sqrt(t_final), _COUNTS, fvs, cx, float(t_end))
        f = ThinPlateSpline(sys_.v, w, d)
        if done:
            break
        fv = f(v)  # the coarse spline at every point: where the denser stage starts
    if not done or stride != 1:  # t_final reached on a subset: finish on all points
        d, w, m, t, done = _anneal_nb(x, v, lx, lv, use_lab, cost, pair_cost is not None, system.phi,
                                      np.ascontiguousarray(system.a), np.ascontiguousarray(system.bend),
                                      np.ascontiguousarray(system.q2), float(t_final), float(t_init),
                                      float(t_final), float(prm.anneal_rate), int(prm.iterations),
                                      int(prm.sinkhorn_iterations), float(prm.lambda1_init),
                                      float(prm.lambda2_init), _SINK_TOL, _MOVE_TOL * np.sqrt(t_final),
                                      _COUNTS, np.ascontiguousarray(f(v)), cx, 0.0)
        f = ThinPlateSpline(system.v, w, d)
    return f, m


def _anneal(x, v, f, system, lab_x, lab_v, t, t_init, t_final, cx, prm, pair_cost=None):
    k = len(v)
    m = np.zeros((len(x), k))
    while True:
        for _ in range(prm.iterations):
            fv = system.at_centres(f)
            m = _softassign(x, fv, lab_x, lab_v, t, t_init, cx, fv.mean(0), prm.sinkhorn_iterations, pair_cost)
            mass = m.sum(0)
            y = np.where(mass[:, None] > 1e-9, (m.T @ x) / np.maximum(mass[:, None], 1e-300), fv)
            f = system.fit(y, weights=np.clip(mass, 1e-3, 1.0),
                           lambda1=prm.lambda1_init * k * t, lambda2=prm.lambda2_init * k * t)
        if t <= t_final:
            break
        t = max(t * prm.anneal_rate, t_final)
    return f, m


# ---------------------------------------------------------------------------
# compiled annealing loop (the same arithmetic as _softassign and _SplineSystem.fit)

_SINK_TOL = 1e-2
#: Training px: :meth:`Registration.inverse` stops refining a point whose residual is below this.
_NEWTON_TOL = 1e-4
_MOVE_TOL = 1e-2
_COUNTS = np.zeros(2, np.int64)
_SUB_MARGIN = 0.7


@numba.njit(cache=True, fastmath={"reassoc", "contract", "arcp", "nsz"})
def _softassign_nb(x, fv, lab_x, lab_v, use_lab, cost, use_cost, t, t0, cx, cv, sinkhorn, tol):  # pragma: no cover
    n, k = x.shape[0], fv.shape[0]
    m = np.zeros((n + 1, k + 1))
    logt, logt0 = np.log(t), np.log(t0)
    top = -np.inf
    for a in range(n):
        for i in range(k):
            if use_lab and lab_x[a] != lab_v[i]:
                m[a, i] = -np.inf
                continue
            dx, dy = x[a, 0] - fv[i, 0], x[a, 1] - fv[i, 1]
            d2 = max(dx * dx + dy * dy, 0.0)
            if use_cost:
                d2 += cost[a, i]
            v = -d2 / (2 * t) - logt
            m[a, i] = v
            if v > top:
                top = v
    for a in range(n):
        dx, dy = x[a, 0] - cv[0], x[a, 1] - cv[1]
        v = -(dx * dx + dy * dy) / (2 * t0) - logt0
        m[a, k] = v
        top = max(top, v)
    for i in range(k):
        dx, dy = fv[i, 0] - cx[0], fv[i, 1] - cx[1]
        v = -(dx * dx + dy * dy) / (2 * t0) - logt0
        m[n, i] = v
        top = max(top, v)
    m[n, k] = -np.inf
    for a in range(n + 1):
        for i in range(k + 1):
            m[a, i] = np.exp(m[a, i] - top)
    colsum = np.empty(k)
    rowsum = np.empty(n)
    for it in range(sinkhorn):
        err = 0.0
        for a in range(n):
            s = 0.0
            for i in range(k + 1):
                s += m[a, i]
            rowsum[a] = s
            err = max(err, abs(s - 1.0))
        if it > 0 and err < tol:  # the rows already sum to 1: converged
            break
        for a in range(n):
            r = 1.0 / max(rowsum[a], 1e-300)
            for i in range(k + 1):
                m[a, i] *= r
        colsum[:] = 0.0
        for a in range(n + 1):
            for i in range(k):
                colsum[i] += m[a, i]
        for i in range(k):
            colsum[i] = 1.0 / max(colsum[i], 1e-300)
        for a in range(n + 1):
            for i in range(k):
                m[a, i] *= colsum[i]
    return m[:n, :k].copy()


@numba.njit(cache=True)
def _anneal_nb(x, v, lab_x, lab_v, use_lab, cost, use_cost, phi, amat, bend, q2, t, t_init, t_final,
               rate, iterations, sinkhorn, lam1, lam2, sink_tol, move_tol, counts, fv0, cx_in,
               t_end):  # pragma: no cover
    n, k = x.shape[0], v.shape[0]
    d = np.zeros((3, 2))
    d[1, 0] = 1.0
    d[2, 1] = 1.0
    w = np.zeros((k, 2))
    m = np.zeros((n, k))
    cx = cx_in.copy()
    cv = np.empty(2)
    y = np.empty((k, 2))
    ca = np.empty_like(amat)
    fv = fv0.copy()
    while True:
        for _ in range(iterations):
            cv[0], cv[1] = fv[:, 0].mean(), fv[:, 1].mean()
            m = _softassign_nb(x, fv, lab_x, lab_v, use_lab, cost, use_cost, t, t_init, cx, cv, sinkhorn,
                               sink_tol)
            counts[0] += 1
            mx = np.dot(m.T, x)
            c = np.empty(k)
            for i in range(k):
                s = 0.0
                for a in range(n):
                    s += m[a, i]
                if s > 1e-9:
                    y[i, 0], y[i, 1] = mx[i, 0] / s, mx[i, 1] / s
                else:
                    y[i, 0], y[i, 1] = fv[i, 0], fv[i, 1]
                c[i] = min(max(s, 1e-3), 1.0)
            for i in range(k):
                ca[i] = c[i] * amat[i]
            h = np.dot(amat.T, ca)
            rhs = np.dot(ca.T, y)
            l1, l2 = lam1 * k * t, lam2 * k * t
            h[1, 1] += l2
            h[2, 2] += l2
            rhs[1, 0] += l2
            rhs[2, 1] += l2
            h[3:, 3:] += l1 * bend
            z = np.linalg.solve(h, rhs)
            w = np.dot(q2, np.ascontiguousarray(z[3:]))
            d = z[:3].copy()
            fv_new = np.dot(v, d[1:]) + np.dot(phi, w)
            fv_new[:, 0] += d[0, 0]
            fv_new[:, 1] += d[0, 1]
            move = np.abs(fv_new - fv).max()
            fv = fv_new
            if move < move_tol:  # the spline stopped moving: the next round would repeat this one
                break
        if t <= t_final:
            return d, w, m, t, True
        t = max(t * rate, t_final)
        if t < t_end:  # the next temperature belongs to the next (denser) point set
            return d, w, m, t, False


# ---------------------------------------------------------------------------
# start alignment

def _moments(mask: np.ndarray):
    ys, xs = np.nonzero(mask)
    pts = np.column_stack([xs, ys]).astype(np.float64)
    mu = pts.mean(0)
    cov = np.cov((pts - mu).T) + 1e-6 * np.eye(2)
    return mu, cov, float(len(pts))


def _sqrtm(c, inverse=False):
    vals, vecs = np.linalg.eigh(c)
    vals = np.maximum(vals, 1e-9)
    p = -0.5 if inverse else 0.5
    return (vecs * vals ** p) @ vecs.T


def _rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def _contour_points(mask: np.ndarray, n: int = 600) -> np.ndarray:
    contours, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    pts = np.vstack([c[:, 0, :] for c in contours]).astype(np.float64)
    if len(pts) > n:
        pts = pts[np.linspace(0, len(pts) - 1, n).astype(int)]
    return pts


class _Chamfer:
    """Mean distance of mapped points to a mask's outline (distance transform lookup)."""

    def __init__(self, mask: np.ndarray, region: bool = False):
        edge = np.ones(mask.shape, np.uint8)
        if region:  # distance to the region itself
            edge[mask] = 0
        else:  # distance to its outline
            edge[cv2.morphologyEx(mask.astype(np.uint8), cv2.MORPH_GRADIENT, np.ones((3, 3), np.uint8)) > 0] = 0
        self.dt = cv2.distanceTransform(edge, cv2.DIST_L2, 3)
        self.h, self.w = mask.shape

    def __call__(self, pts: np.ndarray) -> float:
        x, y = pts[:, 0], pts[:, 1]
        xc, yc = np.clip(x, 0, self.w - 1), np.clip(y, 0, self.h - 1)
        d = self.dt[np.round(yc).astype(int), np.round(xc).astype(int)]
        d = d + np.hypot(x - xc, y - yc)  # outside the image: at least this far
        return float(np.sqrt(np.mean(d * d)))


def _opening_radius(mask: np.ndarray) -> int:
    return max(1, int(round(0.05 * np.sqrt(mask.sum()))))


_THIN_CACHE: dict = {}
_THIN_LOCK = threading.Lock()  # batch runs register leaves on several threads


def _thin_parts(mask: np.ndarray) -> np.ndarray:
    """:func:`_thin_parts_of`, remembered for the last few masks (a registration asks ~12 times per leaf)."""
    m = np.ascontiguousarray(mask, bool)
    key = (m.shape, hashlib.blake2b(np.packbits(m).tobytes(), digest_size=16).digest())
    with _THIN_LOCK:
        hit = _THIN_CACHE.get(key)
    if hit is None:
        hit = _thin_parts_of(m)
        with _THIN_LOCK:
            while len(_THIN_CACHE) >= 8:
                _THIN_CACHE.pop(next(iter(_THIN_CACHE)))
            _THIN_CACHE[key] = hit
    return hit.copy()


def _thin_parts_of(mask: np.ndarray) -> np.ndarray:
    """Thin protrusions of a blade (petiole, drawn-out tips): what an opening removes.

    Holes (insect damage) are filled first: the pixels around a hole are
    no protrusion of the outline.
    """
    filled = ndi_fill_holes(mask)
    r = _opening_radius(filled)
    k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    # The opening of the blade's bounding box (r + 1 beyond it, clipped to
    # the image): outside it the mask is empty and stays so.
    ys, xs = np.nonzero(filled.any(1))[0], np.nonzero(filled.any(0))[0]
    opened = np.zeros(mask.shape, bool)
    if len(ys):
        y0, y1 = max(0, ys[0] - r - 1), min(mask.shape[0], ys[-1] + r + 2)
        x0, x1 = max(0, xs[0] - r - 1), min(mask.shape[1], xs[-1] + r + 2)
        opened[y0:y1, x0:x1] = cv2.morphologyEx(filled[y0:y1, x0:x1].astype(np.uint8), cv2.MORPH_OPEN, k) > 0
    thin = mask & ~opened
    return thin if thin.sum() >= max(8, 0.002 * mask.sum()) else np.zeros_like(mask)


def _thin_roots(mask: np.ndarray, thin: np.ndarray, lamina: np.ndarray) -> np.ndarray:
    """Where the thin parts leave the lamina (within one opening radius of it).

    A petiole's length and bend vary from leaf to leaf (a long curved
    petiole would pull a whole-shape score towards a rotation that aligns
    petioles instead of blades), but where it joins the blade, the base of
    the leaf, is shared by every leaf of a kind; so are the roots of the
    lobe tips.
    """
    r = _opening_radius(mask)
    # Only the dilation at the thin pixels counts: dilate the window around
    # them (2 r beyond their bounding box), the same values as the whole image.
    ys, xs = np.nonzero(thin)
    near = np.zeros(mask.shape, bool)
    if len(ys):
        y0, y1 = max(0, ys.min() - 2 * r - 1), min(mask.shape[0], ys.max() + 2 * r + 2)
        x0, x1 = max(0, xs.min() - 2 * r - 1), min(mask.shape[1], xs.max() + 2 * r + 2)
        k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (4 * r + 1, 4 * r + 1))
        near[y0:y1, x0:x1] = cv2.dilate(lamina[y0:y1, x0:x1].astype(np.uint8), k) > 0
    roots = thin & near
    return roots if roots.sum() >= 4 else thin


def _base_point(mask: np.ndarray, thin: np.ndarray, lamina: np.ndarray):
    """Where the dominant thin part (the petiole) joins the lamina, or None.

    The thin part must be at least twice as large as any other (lobe tips),
    so a leaf without a clear petiole gives no base point.
    """
    if not thin.any():
        return None
    lab, n = ndi_label(thin, structure=np.ones((3, 3)))
    sizes = np.sort(np.bincount(lab.ravel())[1:])[::-1]
    if n == 0 or (n > 1 and sizes[0] < 2 * sizes[1]):
        return None
    big = lab == int(np.argmax(np.bincount(lab.ravel())[1:]) + 1)
    roots = _thin_roots(mask, big, lamina)
    ys, xs = np.nonzero(roots)
    return np.array([xs.mean(), ys.mean()])


def split_petiole(blade) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """A blade's lamina, its petiole (the dominant thin protrusion) and the base where they meet.

    Parameters
    ----------
    blade : (H, W) bool array_like
        The leaf's silhouette (lamina and petiole).

    Returns
    -------
    lamina, petiole : (H, W) bool ndarray
        ``petiole`` is empty (and ``lamina`` the blade without thin parts)
        when no thin part is at least twice as large as any other.
    base : (2,) ndarray or None
        ``(x, y)`` where the petiole joins the lamina.

    Examples
    --------
    >>> import numpy as np
    >>> b = np.zeros((60, 40), bool); b[5:35, 5:35] = True; b[35:58, 19:21] = True
    >>> lam, pet, base = split_petiole(b)
    >>> bool(pet[50, 20]), bool(lam[20, 20]), base is not None
    (True, True, True)
    """
    mask = as_mask(blade, name="blade")
    thin = _thin_parts(mask)
    lamina = _lamina(mask)
    base = _base_point(mask, thin, lamina)
    if base is None:
        return lamina, np.zeros_like(mask), None
    lab, _ = ndi_label(thin, structure=np.ones((3, 3)))
    pet = lab == int(np.argmax(np.bincount(lab.ravel())[1:]) + 1)
    return lamina, pet, base


class _StartScore:
    """Symmetric RMS chamfer distance of the laminae outlines (+ of the thin parts' roots) under an affine map.

    When both leaves have a dominant thin part (a petiole), the distance
    between their base points (where it joins the lamina) is added: a
    palmate blade fits itself well at every lobe's rotation, its base
    tells which one is right. Base distances below 0.3 blade radii are free.
    """

    def __init__(self, me: np.ndarray, mt: np.ndarray):
        le, lt = _lamina(me), _lamina(mt)
        self.out_e, self.out_t = _contour_points(le), _contour_points(lt)
        self.cham_e, self.cham_t = _Chamfer(le), _Chamfer(lt)
        te, tt = _thin_parts(me), _thin_parts(mt)
        self.thin = te.any() and tt.any()
        if self.thin:
            te, tt = _thin_roots(me, te, le), _thin_roots(mt, tt, lt)
            self.thin_e = np.column_stack(np.nonzero(te)[::-1]).astype(np.float64)
            self.thin_t = np.column_stack(np.nonzero(tt)[::-1]).astype(np.float64)
            self.thin_e = self.thin_e[:: max(1, len(self.thin_e) // 300)]
            self.thin_t = self.thin_t[:: max(1, len(self.thin_t) // 300)]
            self.dt_te, self.dt_tt = _Chamfer(te, region=True), _Chamfer(tt, region=True)
        te, tt = _thin_parts(me), _thin_parts(mt)
        self.base_e, self.base_t = _base_point(me, te, le), _base_point(mt, tt, lt)
        self.radius_t = float(np.sqrt(lt.sum() / np.pi))

    def __call__(self, mat: np.ndarray) -> float:
        lin, off = mat[:, :2], mat[:, 2]
        inv = np.linalg.inv(lin)
        scale = np.sqrt(abs(np.linalg.det(lin)))
        c = self.cham_t(self.out_e @ lin.T + off) + self.cham_e((self.out_t - off) @ inv.T) * scale
        if self.thin:
            c += self.dt_tt(self.thin_e @ lin.T + off) + self.dt_te((self.thin_t - off) @ inv.T) * scale
        if self.base_e is not None and self.base_t is not None:
            # Only a gross mismatch counts (another lobe's rotation moves the
            # base by about a blade radius): the fine angle is the outlines'.
            c += max(0.0, float(np.hypot(*(self.base_e @ lin.T + off - self.base_t))) - 0.3 * self.radius_t)
        return c


def _affine_icp(mat: np.ndarray, src: np.ndarray, dst: np.ndarray, iterations: int = 15) -> np.ndarray:
    """Refine an affine map of outline points ``src`` onto ``dst`` (symmetric nearest points, trimmed)."""
    tree_d, tree_s = cKDTree(dst), None
    for _ in range(iterations):
        lin, off = mat[:, :2], mat[:, 2]
        ms = src @ lin.T + off
        d1, i1 = tree_d.query(ms)
        tree_s = cKDTree(ms)
        d2, i2 = tree_s.query(dst)
        a = np.vstack([src, src[i2]])
        b = np.vstack([dst[i1], dst])
        d = np.concatenate([d1, d2])
        keep = d <= np.percentile(d, 90)
        a_h = np.column_stack([a[keep], np.ones(keep.sum())])
        sol, *_ = np.linalg.lstsq(a_h, b[keep], rcond=None)
        new = sol.T
        if np.abs(new - mat).max() < 1e-4:
            mat = new
            break
        mat = new
    return mat


@checked(rotation_step=Real(0.5, 90.0), n=Int(1, 1000), start=Choice("similarity", "affine"))
def start_candidates(exemplar_blade, training_blade, *, start: str = "similarity",
                     rotation_step: float = 5.0, mirror: bool = False,
                     n: int = 3) -> list[tuple[np.ndarray, float]]:
    """The ``n`` best distinct start maps (2 x 3, exemplar px -> training px), best first, with their scores.

    Every candidate maps the exemplar blade's centroid onto the training
    blade's and scales it by the square root of the area ratio; rotations
    cover the circle ``rotation_step`` apart (optionally mirrored). The
    score is the symmetric RMS chamfer distance of the two outlines (in
    training pixels) plus that of their thin parts (petiole, drawn-out
    tips: what a morphological opening removes), which tell base from tip
    on an almost symmetric blade. Local minima of the score more than 30
    degrees apart are refined in steps of a tenth of ``rotation_step``;
    with ``start="affine"`` each is then refined to an affine map by
    trimmed symmetric ICP on the outlines.

    Parameters
    ----------
    exemplar_blade : (H_e, W_e) bool array_like
        The moving leaf's blade (at least 16 pixels).
    training_blade : (H_t, W_t) bool array_like
        The training leaf's blade (at least 16 pixels).
    start : {"similarity", "affine"}
        Family of start maps (default ``"similarity"``).
    rotation_step : float
        Degrees between the rotations tried, 0.5 to 90 (default 5).
    mirror : bool
        Also try mirrored maps (a leaf photographed from the back).
    n : int
        Number of candidates returned, at most (default 3).

    Returns
    -------
    list of ((2, 3) ndarray, float)
        Start maps and their chamfer scores (training pixels, lower is
        better), best first.
    """
    me = as_mask(exemplar_blade, name="exemplar_blade")
    mt = as_mask(training_blade, name="training_blade")
    for nm, m in (("exemplar_blade", me), ("training_blade", mt)):
        if m.sum() < 16:
            raise ValueError(f"{nm} has only {int(m.sum())} pixels: no leaf to align")
    if start not in ("similarity", "affine"):
        raise ValueError(f"start must be 'similarity' or 'affine', got {start!r}")
    if not 0 < rotation_step <= 180:
        raise ValueError(f"rotation_step must be in (0, 180], got {rotation_step}")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n must be a positive int, got {n!r}")
    # Centroids and areas of the laminae: a long petiole would shift them.
    mu_e, _, a_e = _moments(_lamina(me))
    mu_t, _, a_t = _moments(_lamina(mt))
    score = _StartScore(me, mt)
    sc = np.sqrt(a_t / a_e)

    def matrix(th, fl):
        lin = sc * _rot(th) @ fl
        return np.hstack([lin, (mu_t - lin @ mu_e)[:, None]])

    flips = [np.eye(2)] + ([np.diag([1.0, -1.0])] if mirror else [])
    step = np.deg2rad(rotation_step)
    thetas = np.arange(0, 2 * np.pi, step)
    found = []
    for fl in flips:
        costs = np.array([score(matrix(th, fl)) for th in thetas])
        m = len(costs)
        for idx in np.argsort(costs):
            # Keep local minima that are far from the ones kept.
            if costs[idx] > min(costs[(idx - 1) % m], costs[(idx + 1) % m]):
                continue
            th = thetas[idx]
            if any(f is fl and abs(_wrap_angle(th - t0)) < np.deg2rad(30) for _, f, t0 in found):
                continue
            found.append((costs[idx], fl, th))
    found.sort(key=lambda c: c[0])
    out = []
    for c, fl, th in found[:n]:
        best_c, best_th = c, th
        for dth in np.linspace(-step, step, 21):
            c2 = score(matrix(th + dth, fl))
            if c2 < best_c:
                best_c, best_th = c2, th + dth
        mat = matrix(best_th, fl)
        if start == "affine":
            mat = _affine_icp(mat, score.out_e, score.out_t)
            best_c = score(mat)
        out.append((mat, float(best_c)))
    out.sort(key=lambda c: c[1])
    return out


def _lamina(mask: np.ndarray) -> np.ndarray:
    """The blade without its thin parts (largest remaining component)."""
    lam = mask & ~_thin_parts(mask)
    lab, n = ndi_label(lam)
    if n > 1:
        sizes = np.bincount(lab.ravel())[1:]
        lam = lab == (int(np.argmax(sizes)) + 1)
    # An opening that eats much of the blade (a leaf riddled with holes) is
    # no petiole removal: keep the blade then.
    return lam if lam.sum() >= 0.75 * mask.sum() else mask


def _outline_samples(mask: np.ndarray, n: int) -> np.ndarray:
    """``n`` points evenly spaced along a blade's outer outline."""
    from .keypoints import _outline_points

    return _outline_points(mask, n)


def _interior_samples(mask: np.ndarray, n: int = 2000) -> np.ndarray:
    """About ``n`` pixel centres (x, y) spread evenly over ``mask``."""
    ys, xs = np.nonzero(mask)
    step = max(1, len(xs) // n)
    return np.column_stack([xs[::step], ys[::step]]).astype(np.float64)


def _jacobian_det(spline, points: np.ndarray) -> np.ndarray:
    """Determinant of ``spline``'s Jacobian at ``points`` (<= 0 where it turns orientation)."""
    jac = spline.jacobian(points)
    return jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]


def _outline_fit(mapped: np.ndarray, target: np.ndarray) -> float:
    """Symmetric RMS nearest-point distance of two point sets."""
    d1, _ = cKDTree(target).query(mapped)
    d2, _ = cKDTree(mapped).query(target)
    return float(np.sqrt(np.mean(d1 ** 2)) + np.sqrt(np.mean(d2 ** 2)))


def _wrap_angle(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


@checked(rotation_step=Real(0.5, 90.0), start=Choice("similarity", "affine"))
def start_alignment(exemplar_blade, training_blade, *, start: str = "similarity", rotation_step: float = 5.0,
                    mirror: bool = False) -> tuple[np.ndarray, float]:
    """The best start map (2 x 3, exemplar pixels -> training pixels) and its blade overlap (IoU).

    See :func:`start_candidates` for how it is found.

    Parameters
    ----------
    exemplar_blade : (H_e, W_e) bool array_like
        The moving leaf's blade.
    training_blade : (H_t, W_t) bool array_like
        The training leaf's blade.
    start : {"similarity", "affine"}
        Family of start maps (default ``"similarity"``).
    rotation_step : float
        Degrees between the rotations tried (default 5).
    mirror : bool
        Also try mirrored maps.

    Returns
    -------
    matrix : (2, 3) ndarray
    iou : float
        Blade overlap after the map.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((60, 60), bool); a[10:50, 25:35] = True; a[10:20, 35:45] = True
    >>> b = np.rot90(a).copy()
    >>> m, score = start_alignment(a, b)
    >>> score > 0.9
    True
    """
    mat, _ = start_candidates(exemplar_blade, training_blade, start=start, rotation_step=rotation_step,
                              mirror=mirror, n=1)[0]
    return mat, _blade_iou(mat, as_mask(exemplar_blade), as_mask(training_blade))


def _blade_iou(mat, me, mt) -> float:
    warped = cv2.warpAffine(me.astype(np.float32), mat, mt.shape[::-1], flags=cv2.INTER_LINEAR) > 0.5
    union = np.logical_or(warped, mt).sum()
    return float(np.logical_and(warped, mt).sum() / union) if union else 0.0


# ---------------------------------------------------------------------------
# result

def _bilinear_upsample(coarse: np.ndarray, step: int, shape: tuple[int, int]) -> np.ndarray:
    """Values at every pixel of ``shape`` from samples at ``(j * step, i * step)``.

    Separable: along x on the coarse rows first, then along y (the same
    bilinear values as the four-corner formula, without four full-size
    float64 temporaries per channel).
    """
    h, w = shape
    ys = np.arange(h) / step
    xs = np.arange(w) / step
    y0 = np.minimum(np.floor(ys).astype(int), coarse.shape[0] - 2)
    x0 = np.minimum(np.floor(xs).astype(int), coarse.shape[1] - 2)
    fy = (ys - y0)[:, None, None]
    fx = (xs - x0)[None, :, None]
    rows = coarse[:, x0] * (1 - fx) + coarse[:, x0 + 1] * fx  # (gh, W, C)
    out = np.empty((h, w) + coarse.shape[2:], np.float32)
    for i0 in range(0, h, 256):  # row blocks keep the float64 temporaries small
        sl = slice(i0, i0 + 256)
        out[sl] = rows[y0[sl]] * (1 - fy[sl]) + rows[y0[sl] + 1] * fy[sl]
    return out


def _coarse_grid(shape, step):
    h, w = shape
    gy = np.arange(int(np.ceil((h - 1) / step)) + 2) * step
    gx = np.arange(int(np.ceil((w - 1) / step)) + 2) * step
    xx, yy = np.meshgrid(gx, gy)
    return np.column_stack([xx.ravel(), yy.ravel()]).astype(np.float64), (len(gy), len(gx))


@dataclass
class Registration:
    """An exemplar registered to the training leaf.

    Made by :func:`register`.

    Parameters
    ----------
    start : (2, 3) ndarray
        Affine start map, exemplar pixels -> training pixels.
    start_iou : float
        Blade overlap after the start map.
    splines : list of ThinPlateSpline
        Applied in turn, in normalised training coordinates
        (``(p - centre) / radius``): the outline stage, then the refinement
        with all keypoints.
    centre : (2,) ndarray
        Training blade centroid ``(x, y)``: the origin of normalised coordinates.
    radius : float
        Training blade radius ``sqrt(area / pi)`` in pixels: the unit of
        normalised coordinates.
    exemplar_keypoints, training_keypoints : Keypoints
        The points matched (pixels of each leaf).
    match : (N, K) ndarray
        Soft correspondences (rows: training keypoints, columns: exemplar keypoints).
    exemplar_shape, training_shape : (int, int)
        ``(H, W)`` of the two leaves' images.
    grid_step : int
        Grid spacing (pixels) of the dense maps (default 8).
    """

    start: np.ndarray
    start_iou: float
    splines: list
    centre: np.ndarray
    radius: float
    exemplar_keypoints: Keypoints
    training_keypoints: Keypoints
    match: np.ndarray
    exemplar_shape: tuple[int, int]
    training_shape: tuple[int, int]
    grid_step: int = 8
    _inverse_init: ThinPlateSpline | None = field(default=None, repr=False)
    _map_to: np.ndarray | None = field(default=None, repr=False)
    _map_from: np.ndarray | None = field(default=None, repr=False)

    # point maps ------------------------------------------------------------------
    def _normalise(self, p):
        return (p - self.centre) / self.radius

    def _start_map(self, p):
        return p @ self.start[:, :2].T + self.start[:, 2]

    def forward(self, points) -> np.ndarray:
        """Exemplar pixels (x, y) -> training pixels.

        Parameters
        ----------
        points : (N, 2) array_like
            ``(x, y)`` on the exemplar.

        Returns
        -------
        (N, 2) float ndarray
        """
        p = _points(points, "points")
        q = self._normalise(self._start_map(p))
        for f in self.splines:
            q = f(q)
        return q * self.radius + self.centre

    def forward_jacobian(self, points) -> np.ndarray:
        """(N, 2, 2) Jacobian of :meth:`forward`.

        Parameters
        ----------
        points : (N, 2) array_like
            ``(x, y)`` on the exemplar.

        Returns
        -------
        (N, 2, 2) float ndarray
            ``J[n, i, j] = d forward_i / d p_j`` (training px per exemplar px).
        """
        p = _points(points, "points")
        q = self._normalise(self._start_map(p))
        j = np.broadcast_to(self.start[:, :2], (len(p), 2, 2)).copy()
        for f in self.splines:
            j = f.jacobian(q) @ j
            q = f(q)
        return j

    def inverse(self, points, *, newton_steps: int = 6) -> np.ndarray:
        """Training pixels (x, y) -> exemplar pixels (Newton-refined inverse of :meth:`forward`).

        Parameters
        ----------
        points : (N, 2) array_like
            ``(x, y)`` on the training leaf.
        newton_steps : int
            Newton steps on the exact forward map after the fitted inverse,
            0 to 100 (default 6).

        Returns
        -------
        (N, 2) float ndarray
        """
        newton_steps = check_int(newton_steps, "newton_steps", 0, 100)
        y = _points(points, "points")
        if self._inverse_init is None:
            self._fit_inverse()
        p = self._inverse_init(self._normalise(y))
        # Points whose residual is below _NEWTON_TOL px are done (a further
        # step would move them by less than that); the rest take every step.
        active = np.arange(len(p))
        for _ in range(newton_steps):
            if not len(active):
                break
            f, j = self._forward_and_jacobian(p[active])
            r = f - y[active]
            det = j[:, 0, 0] * j[:, 1, 1] - j[:, 0, 1] * j[:, 1, 0]
            ok = np.abs(det) > 1e-9
            step = np.zeros_like(r)
            jinv = np.stack([np.stack([j[:, 1, 1], -j[:, 0, 1]], -1),
                             np.stack([-j[:, 1, 0], j[:, 0, 0]], -1)], 1) / np.where(ok, det, 1.0)[:, None, None]
            step[ok] = np.einsum("nij,nj->ni", jinv[ok], r[ok])
            # Damped where a full step would not reduce the residual much (fold-overs far outside).
            p[active] = p[active] - np.clip(step, -self.radius, self.radius)
            active = active[np.hypot(*r.T) >= _NEWTON_TOL]
        return p

    def _forward_and_jacobian(self, p):
        """:meth:`forward` and :meth:`forward_jacobian` of (N, 2) float points in one pass per spline."""
        q = self._normalise(self._start_map(p))
        j = np.broadcast_to(self.start[:, :2], (len(p), 2, 2)).copy()
        for f in self.splines:
            fq, jf = f._eval(q, True)
            j = jf @ j
            q = fq
        return q * self.radius + self.centre, j

    def _fit_inverse(self):
        """A thin-plate spline through forward-mapped samples: the start of :meth:`inverse`'s Newton steps.

        The interpolant ``sum_j w_j U(|y - c_j|) + affine(y)`` with a
        smoothing of 1e-6 on the kernel's diagonal (what
        ``scipy.interpolate.RBFInterpolator(kernel="thin_plate_spline",
        smoothing=1e-6, degree=1)`` fits), evaluated compiled.
        """
        he, we = self.exemplar_shape
        n = 28
        gx, gy = np.meshgrid(np.linspace(-0.1 * we, 1.1 * we, n), np.linspace(-0.1 * he, 1.1 * he, n))
        samples = np.vstack([np.column_stack([gx.ravel(), gy.ravel()]), self.exemplar_keypoints.points])
        src = self._normalise(self.forward(samples))
        m = len(src)
        lhs = np.zeros((m + 3, m + 3))
        lhs[:m, :m] = _tps_kernel(_sqdist(src, src))
        lhs[np.arange(m), np.arange(m)] += 1e-6
        poly = np.column_stack([np.ones(m), src])
        lhs[:m, m:] = poly
        lhs[m:, :m] = poly.T
        rhs = np.vstack([samples, np.zeros((3, 2))])
        sol = _solve(lhs, rhs)
        self._inverse_init = ThinPlateSpline(src, sol[:m], sol[m:])

    # dense maps ------------------------------------------------------------------
    @property
    def map_to_training(self) -> np.ndarray:
        """(H_t, W_t, 2) float32: the exemplar (x, y) each training pixel comes from."""
        if self._map_to is None:
            grid, gshape = _coarse_grid(self.training_shape, self.grid_step)
            coarse = self.inverse(grid).reshape(gshape + (2,))
            self._map_to = _bilinear_upsample(coarse, self.grid_step, self.training_shape)
        return self._map_to

    @property
    def map_from_training(self) -> np.ndarray:
        """(H_e, W_e, 2) float32: the training (x, y) each exemplar pixel goes to."""
        if self._map_from is None:
            grid, gshape = _coarse_grid(self.exemplar_shape, self.grid_step)
            coarse = self.forward(grid).reshape(gshape + (2,))
            self._map_from = _bilinear_upsample(coarse, self.grid_step, self.exemplar_shape)
        return self._map_from

    def to_training(self, image_or_mask) -> np.ndarray:
        """The exemplar image (or mask) resampled into the training frame (training-sized).

        Bool masks come back as bool (False outside the exemplar); images as
        float32 ``(H_t, W_t, C)`` (border colours replicated outside the exemplar).

        Parameters
        ----------
        image_or_mask : (H_e, W_e[, C]) array_like
            On the exemplar.

        Returns
        -------
        ndarray
            Training-sized.
        """
        return _apply(image_or_mask, self.map_to_training, self.exemplar_shape, "image_or_mask")

    def from_training(self, image_or_mask) -> np.ndarray:
        """A training-frame image (or mask) resampled into the exemplar frame.

        Parameters
        ----------
        image_or_mask : (H_t, W_t[, C]) array_like
            On the training leaf (bool masks come back as bool).

        Returns
        -------
        ndarray
            Exemplar-sized.
        """
        return _apply(image_or_mask, self.map_from_training, self.training_shape, "image_or_mask")

    @property
    def matches(self) -> np.ndarray:
        """(M, 2) int: ``(exemplar index, training index)`` pairs of mutual best soft matches."""
        if self.match.size == 0:
            return np.zeros((0, 2), np.int64)
        best_t = np.argmax(self.match, axis=0)  # for each exemplar point
        best_e = np.argmax(self.match, axis=1)  # for each training point
        ex = np.arange(self.match.shape[1])
        mutual = (best_e[best_t] == ex) & (self.match[best_t, ex] > 0.5)
        return np.column_stack([ex[mutual], best_t[mutual]])

    @property
    def error_px(self) -> float:
        """Median distance (training px) between matched points after the warp: the registration error."""
        mt = self.matches
        if not len(mt):
            return float("nan")
        a = self.forward(self.exemplar_keypoints.points[mt[:, 0]])
        b = self.training_keypoints.points[mt[:, 1]]
        return float(np.median(np.hypot(*(a - b).T)))


def _points(points, name, limit: float = COORD_LIMIT):
    """(N, 2) finite real points within ``limit`` (pixel coordinates beyond it are no image's)."""
    p = real_array(points, name, allow_empty=True)
    if p.ndim == 1 and p.shape == (2,):
        p = p[None]
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"{name} must have shape (N, 2), got {p.shape}")
    return check_finite(p, name, limit=limit)


def _apply(image_or_mask, mp: np.ndarray, src_shape, name):
    arr = np.asarray(image_or_mask)
    if arr.ndim not in (2, 3):
        raise ValueError(f"{name} must be 2-D (H, W) or 3-D (H, W, C), got shape {arr.shape}")
    if arr.shape[:2] != tuple(src_shape):
        raise ValueError(f"{name} must have height and width {tuple(src_shape)}, got {arr.shape[:2]}")
    if arr.dtype == bool:
        out, valid = remap(arr.astype(np.float32), mp[..., 0], mp[..., 1])
        return (out[..., 0] > 0.5) & valid if arr.ndim == 2 else (out > 0.5) & valid[..., None]
    img = as_float_image(arr, name=name)
    out, _ = remap(img, mp[..., 0], mp[..., 1])
    return out[..., 0] if arr.ndim == 2 else out


def _as_leaf(leaf, blade, name):
    if blade is not None:
        img = as_float_image(leaf.image if hasattr(leaf, "image") else leaf, name=name)
        m = as_mask(blade, shape=img.shape[:2], name=f"{name}_blade")
        if m.sum() < 16:
            raise ValueError(f"{name}_blade has only {int(m.sum())} pixels: no leaf to register")
        rgb = np.repeat(img, 3, axis=2) if img.shape[2] == 1 else img[:, :, :3]
        alpha = img[:, :, 3] if img.shape[2] == 4 else m.astype(np.float32)
        return Exemplar(np.ascontiguousarray(rgb), alpha, m, "given", name)
    if isinstance(leaf, Exemplar):
        return leaf
    if hasattr(leaf, "image") and hasattr(leaf, "blade"):  # ProceduralLeaf
        return _as_leaf(leaf.image, leaf.blade, name)
    return leaf_exemplar(leaf, name=name)


@checked()
def register(exemplar, training, exemplar_blade=None, training_blade=None, *,
             params: RegistrationParams | None = None, rng=None,
             exemplar_keypoints: Keypoints | None = None,
             training_keypoints: Keypoints | None = None) -> Registration:
    """Register ``exemplar`` to ``training`` (TPS-RPM on edge keypoints from a blade-moment start).

    Parameters
    ----------
    exemplar, training : Exemplar, ProceduralLeaf or image array_like
        Leaves (images without a blade are normalised by
        :func:`branchnb.leaves.exemplar.leaf_exemplar`).
    exemplar_blade, training_blade : (H, W) bool array_like, optional
        The leaves' blade masks, when known (they override the alpha).
    params : RegistrationParams, optional
        None: ``RegistrationParams()`` (the papers' and measured defaults).
    rng : optional
        Accepted for a uniform signature; registration is deterministic.
    exemplar_keypoints, training_keypoints : Keypoints, optional
        Precomputed keypoints (e.g. the training leaf's, shared by all exemplars).

    Returns
    -------
    Registration

    Examples
    --------
    >>> from branchnb.leaves import leaf_family
    >>> a, b = leaf_family(2, size=96, rng=0)
    >>> reg = register(b, a)
    >>> reg.map_to_training.shape
    (96, 96, 2)
    """
    prm = check_params(params if params is not None else RegistrationParams(), name="params")
    ex = _as_leaf(exemplar, exemplar_blade, "exemplar")
    tr = _as_leaf(training, training_blade, "training")
    kp_e = exemplar_keypoints or edge_keypoints(ex.rgb, ex.blade, prm.n_keypoints,
                                                outline_fraction=prm.outline_fraction)
    kp_t = training_keypoints or edge_keypoints(tr.rgb, tr.blade, prm.n_keypoints,
                                                outline_fraction=prm.outline_fraction)
    for nm, kp in (("exemplar", kp_e), ("training", kp_t)):
        if len(kp) < 8:
            raise ValueError(f"{nm} has only {len(kp)} keypoints; registration needs at least 8")
    ys, xs = np.nonzero(tr.blade)
    centre = np.array([xs.mean(), ys.mean()])
    radius = float(np.sqrt(tr.blade.sum() / np.pi))

    def norm(p):
        return (p - centre) / radius

    # Stage 1: the outlines alone (the structure every leaf of a kind
    # shares), from each of the best start maps; the one whose registered
    # outline fits best wins.
    # The lamina's outline: thin protrusions (the petiole above all) bend
    # and vary in length from leaf to leaf and are no shared shape.
    lam_e, lam_t = _lamina(ex.blade), _lamina(tr.blade)
    cont_e = _outline_samples(lam_e, prm.outline_points)
    cont_t = _outline_samples(lam_t, prm.outline_points)
    dense_lam_t = _contour_points(lam_t, 2000)
    cands = start_candidates(ex.blade, tr.blade, start=prm.start, rotation_step=prm.rotation_step,
                             mirror=prm.mirror, n=prm.n_starts)
    base_e = _base_point(ex.blade, _thin_parts(ex.blade), lam_e)
    base_t = _base_point(tr.blade, _thin_parts(tr.blade), lam_t)
    # Landmarks when both leaves have a petiole: its root (the base) and the
    # lamina outline point farthest from it (the apex). They are matched
    # only to each other (their own labels), so an outline without corners
    # (an elliptic blade) cannot slide along itself.
    land_e = land_t = None
    if base_e is not None and base_t is not None:
        land_e, land_t = base_e[None], base_t[None]
        apex_e, apex_t = (_apex_point(lam, b) for lam, b in ((lam_e, base_e), (lam_t, base_t)))
        if prm.apex and apex_e is not None and apex_t is not None:
            land_e, land_t = np.vstack([land_e, apex_e]), np.vstack([land_t, apex_t])
        lab_src = np.r_[np.zeros(len(cont_e), int), 1 + np.arange(len(land_e))]
        lab_dst = np.r_[np.zeros(len(cont_t), int), 1 + np.arange(len(land_t))]
    def outline_spline(mat, prm_fit):
        ce = norm(cont_e @ mat[:, :2].T + mat[:, 2])
        if land_e is not None:
            src = np.vstack([ce, norm(land_e @ mat[:, :2].T + mat[:, 2])])
            return tps_rpm(src, np.vstack([norm(cont_t), norm(land_t)]), source_labels=lab_src,
                           target_labels=lab_dst, params=prm_fit)[0]
        return tps_rpm(ce, norm(cont_t), params=prm_fit)[0]

    best = None
    for mat, _ in cands:
        f1 = outline_spline(mat, prm)
        dense_e = norm(_contour_points(lam_e, 2000) @ mat[:, :2].T + mat[:, 2])
        fit = _outline_fit(f1(dense_e), norm(dense_lam_t))
        if not prm.mirror:
            # A near-symmetric outline also fits its mirror image, and the
            # spline's affine part can turn into that reflection from an
            # unmirrored start; a mirrored map is no registration of an
            # unmirrored leaf (and its inverse cannot be blended with the
            # others' in synthesis), so it loses to any orientation-keeping one.
            if np.median(_jacobian_det(f1, dense_e)) <= 0:
                fit += 1e3
        if base_e is not None and base_t is not None:
            # The outline alone fits a palmate blade at another lobe's
            # rotation too; the base (petiole root) must land near the base.
            fb = f1(norm(base_e[None] @ mat[:, :2].T + mat[:, 2]))[0]
            fit += max(0.0, float(np.hypot(*(fb - norm(base_t)))) - 0.3)
        if best is None or fit < best[0]:
            best = (fit, mat, f1)
    _, start, f1 = best
    # A spline that folds the lamina over itself (Jacobian determinant <= 0)
    # is no correspondence and has no inverse: refit it stiffer until it
    # does not (seen on long grass strips at the paper's lambda1 scale).
    inner = norm(_interior_samples(lam_e) @ start[:, :2].T + start[:, 2])
    stiffer = prm
    for _ in range(prm.fold_retries):
        if (_jacobian_det(f1, inner) > 0).all():
            break
        stiffer = replace(stiffer, lambda1_init=stiffer.lambda1_init * 3.0)
        f1 = outline_spline(start, stiffer)
    start_iou = _blade_iou(start, ex.blade, tr.blade)
    splines = [f1]
    if prm.veins:
        f2 = _vein_stage(ex, tr, lam_e, lam_t, cont_e, cont_t, start, f1, norm, prm)
        if f2 is not None:
            splines.append(f2)
            f1 = _Composed(f1, f2)
    v = f1(norm(kp_e.points @ start[:, :2].T + start[:, 2]))
    x = norm(kp_t.points)
    labels = (kp_e.labels, kp_t.labels) if prm.use_labels else (None, None)
    if prm.refine:
        # Stage 2: all keypoints (interior edges too), a local refinement:
        # it starts at a few times the final temperature, stiffer.
        nn = cKDTree(x).query(x, k=2)[0][:, 1]
        t2 = prm.refine_t_init * float(np.mean(nn ** 2))
        stiff = replace(prm, lambda1_init=prm.lambda1_init * prm.refine_stiffness)
        f2, match = tps_rpm(v, x, source_labels=labels[0], target_labels=labels[1], params=stiff, t_init=t2)
        splines.append(f2)
    else:
        match = _softassign(x, v, labels[1], labels[0], 1e-2, 1.0, x.mean(0), v.mean(0), prm.sinkhorn_iterations)
    return Registration(start, start_iou, splines, centre, radius, kp_e, kp_t, match,
                        ex.blade.shape, tr.blade.shape, prm.grid_step)


def _apex_point(lamina: np.ndarray, base: np.ndarray, margin: float = 1.15):
    """The lamina outline point farthest from the base, when it is a clear apex (else None).

    Clear: at least ``margin`` times farther from the base than any outline
    point a quarter of the outline away from it (a palmate blade whose
    lobes reach about as far has no single apex).
    """
    pts = _contour_points(lamina, 720)
    d = np.hypot(*(pts - base).T)
    i = int(np.argmax(d))
    k = len(pts)
    far = np.abs(((np.arange(k) - i + k // 2) % k) - k // 2) > k // 8
    if not far.any() or d[i] < margin * d[far].max():
        return None
    return pts[i]


class _Composed:
    """Two splines in turn (the outline stage, then the vein stage)."""

    def __init__(self, first, second):
        self.first, self.second = first, second

    def __call__(self, p):
        return self.second(self.first(p))


def _vein_stage(ex, tr, lam_e, lam_t, cont_e, cont_t, start, f1, norm, prm):
    """Stage 2: refine the outline registration with outline and main-vein points, each matched to its own kind.

    The margin alone cannot pin material points that slide along a
    smooth outline; a leaf's main veins (midrib and secondaries of a
    pinnate blade, the primaries of a palmate one) are shared by every
    leaf of a kind and fix them. Returns None when either leaf has too
    few vein points (a leaf without visible veins keeps its outline fit).
    """
    ve = vein_keypoints(ex.rgb, lam_e, prm.vein_points)
    vt = vein_keypoints(tr.rgb, lam_t, prm.vein_points)
    if len(ve) < 8 or len(vt) < 8:
        return None
    src = f1(norm(np.vstack([cont_e, ve.points]) @ start[:, :2].T + start[:, 2]))
    dst = norm(np.vstack([cont_t, vt.points]))
    lab_s = np.r_[np.full(len(cont_e), OUTLINE), np.full(len(ve), VEIN)]
    lab_d = np.r_[np.full(len(cont_t), OUTLINE), np.full(len(vt), VEIN)]
    nn = cKDTree(dst).query(dst, k=2)[0][:, 1]
    t0 = prm.vein_t_init * float(np.mean(nn ** 2))
    stiff = replace(prm, lambda1_init=prm.lambda1_init * prm.vein_stiffness)
    cost = None
    if prm.vein_orientation > 0:
        # A vein point matches a vein point running the same way: the fine
        # reticulum between the main veins runs across them.
        u = np.column_stack([np.cos(ve.orientation), np.sin(ve.orientation)]) @ start[:, :2].T
        th_e = np.arctan2(u[:, 1], u[:, 0])
        sin2 = np.sin(vt.orientation[:, None] - th_e[None, :]) ** 2
        cost = np.zeros((len(dst), len(src)))
        cost[len(cont_t):, len(cont_e):] = prm.vein_orientation * sin2
    f2, _ = tps_rpm(src, dst, source_labels=lab_s, target_labels=lab_d, params=stiff, t_init=t0, pair_cost=cost)
    return f2


@checked(grid=Int(2, 256), registration=Instance("Registration"))
def draw_registration(registration: Registration, exemplar_image, training_image, *,
                      grid: int = 12, blade=None) -> np.ndarray:
    """A picture of a registration: the exemplar with the training grid warped onto it, and the training leaf.

    Left: the exemplar, its keypoints (red: outline, blue: interior) and
    the lines of a regular grid of the training frame mapped into it by
    :meth:`Registration.inverse`. Right: the training leaf with its
    keypoints (hollow) and the exemplar's keypoints mapped by
    :meth:`Registration.forward` (filled), matched pairs joined.

    Parameters
    ----------
    registration : Registration
        The registration to show.
    exemplar_image, training_image : array_like
        RGB(A) images of the two leaves (RGBA is shown over white).
    grid : int
        Number of grid lines across the training leaf's larger side.
    blade : (H_t, W_t) bool array_like, optional
        Only grid points inside this training mask (dilated) are drawn.

    Returns
    -------
    (max(H_e, H_t), W_e + W_t, 3) float32 ndarray
    """
    from ..core.image import as_rgb
    from ..core.render import draw_polylines

    reg = registration
    ex = as_rgb(exemplar_image, name="exemplar_image")
    tr = as_rgb(training_image, name="training_image")
    if ex.shape[:2] != tuple(reg.exemplar_shape) or tr.shape[:2] != tuple(reg.training_shape):
        raise ValueError("exemplar_image and training_image must have the registered leaves' shapes")
    ht, wt = reg.training_shape
    scale = max(ht, wt) / 512.0
    lw = max(1.0, 1.5 * scale)
    keep = None
    if blade is not None:
        keep = _dilate(as_mask(blade, shape=(ht, wt), name="blade"), int(max(ht, wt) / grid))
    lines = []
    ticks = np.linspace(0, 1, 4 * grid + 1)
    for g in np.linspace(0, 1, grid + 1):
        for pts in (np.column_stack([ticks * (wt - 1), np.full_like(ticks, g * (ht - 1))]),
                    np.column_stack([np.full_like(ticks, g * (wt - 1)), ticks * (ht - 1)])):
            if keep is not None:
                inside = keep[np.round(pts[:, 1]).astype(int), np.round(pts[:, 0]).astype(int)]
                # Split the line where it leaves the mask.
                runs = np.split(np.arange(len(pts)), np.flatnonzero(np.diff(inside.astype(int)) != 0) + 1)
                for r in runs:
                    if len(r) >= 2 and inside[r[0]]:
                        lines.append(reg.inverse(pts[r]))
            else:
                lines.append(reg.inverse(pts))
    left = draw_polylines(ex * 0.6 + 0.4, lines, widths=lw, colors=(0.1, 0.5, 0.1))
    kpe = reg.exemplar_keypoints
    cols = [(0.85, 0.1, 0.1) if lab == 0 else (0.1, 0.2, 0.85) for lab in kpe.labels]
    left = draw_polylines(left, [p[None] for p in kpe.points], widths=4 * lw, colors=cols)
    right = tr * 0.6 + 0.4
    kpt = reg.training_keypoints
    fwd = reg.forward(kpe.points)
    mt = reg.matches
    if len(mt):
        right = draw_polylines(right, [np.vstack([fwd[i], kpt.points[j]]) for i, j in mt],
                               widths=lw * 0.8, colors=(0.4, 0.4, 0.4))
    right = draw_polylines(right, [p[None] for p in kpt.points], widths=5 * lw, colors=(0.1, 0.1, 0.1))
    right = draw_polylines(right, [p[None] for p in kpt.points], widths=3 * lw, colors=(1.0, 1.0, 1.0))
    right = draw_polylines(right, [p[None] for p in fwd], widths=3 * lw, colors=cols)
    h = max(left.shape[0], right.shape[0])
    canvas = np.ones((h, left.shape[1] + right.shape[1], 3), np.float32)
    canvas[:left.shape[0], :left.shape[1]] = left
    canvas[:right.shape[0], left.shape[1]:] = right
    return canvas


def _dilate(mask: np.ndarray, radius: int) -> np.ndarray:
    k = 2 * max(radius, 0) + 1
    return cv2.dilate(mask.astype(np.uint8), np.ones((k, k), np.uint8)) > 0
