"""Thin-plate splines (step 2 of :mod:`branchnb.leaves.registration`): fit, evaluate, Jacobian.

``f(p) = d^T [1, p] + sum_j w_j U(|p - c_j|)``, ``U(r) = r^2 log r``; the
values and Jacobians are compiled (numba), one point at a time, so a
megapixel dense map needs no (N, K) temporaries.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from ..core.validate import COORD_LIMIT, Real, check_finite, checked, real_array

__all__ = ["ThinPlateSpline"]


def _tps_kernel(r2: np.ndarray) -> np.ndarray:
    """``U = r^2 log r = r2 log(r2) / 2`` (0 at r = 0)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        out = 0.5 * r2 * np.log(r2)
    return np.where(r2 > 0, out, 0.0)


def _sqdist(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    # |a|^2 + |b|^2 - 2 a.b: one matrix product instead of an (N, K, 2) temporary.
    d = (a * a).sum(1)[:, None] + (b * b).sum(1)[None, :] - 2.0 * (a @ b.T)
    return np.maximum(d, 0.0)



@numba.njit(cache=True, nogil=True)
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


def _points(points, name, limit: float = COORD_LIMIT):
    """(N, 2) finite real points within ``limit`` (pixel coordinates beyond it are no image's)."""
    p = real_array(points, name, allow_empty=True)
    if p.ndim == 1 and p.shape == (2,):
        p = p[None]
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"{name} must have shape (N, 2), got {p.shape}")
    return check_finite(p, name, limit=limit)
