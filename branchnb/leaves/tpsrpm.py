"""TPS-RPM (Chui & Rangarajan 2003), step 2 of :mod:`branchnb.leaves.registration`.

Deterministic annealing of a softassign between two point sets and a
thin-plate spline fitted to the virtual targets; the annealing loop is
compiled (numba), with the numpy loop ``_anneal`` as fallback and reference.
See the registration module's docstring for the parameters and measurements.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numba
import numpy as np
from scipy.spatial import cKDTree
from threadpoolctl import threadpool_limits

from ..core.params import check_params
from ..core.validate import COORD_LIMIT, Real, checked, real_array
from .tps import ThinPlateSpline, _points, _SplineSystem, _sqdist

if TYPE_CHECKING:  # pragma: no cover
    from .registration import RegistrationParams

__all__ = ["tps_rpm"]


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
    from .registration import RegistrationParams  # the parameters of the whole registration

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
                                      _MOVE_TOL * np.sqrt(t_final), _COUNTS, fvs, cx, float(t_end),
                                      *_fit_space(sys_, prm))
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
                                      _COUNTS, np.ascontiguousarray(f(v)), cx, 0.0, *_fit_space(system, prm))
        f = ThinPlateSpline(system.v, w, d)
    return f, m


#: Fit in the spline's values at the centres (:func:`_fit_space`) unless A^-1 is
#: this ill-conditioned (then the normal equations in z, as before).
_VALUES_COND = 1e8
_NO_VALUES = (np.zeros((0, 0)), np.zeros((0, 0)))


def _fit_space(system, prm):
    """``(A^-1, A^-T R0 A^-1)`` of a spline system for the compiled annealing, or empty arrays.

    Each annealing round solves ``(A^T C A + k T R0) z = A^T C y + k T r0``
    for the spline's coefficients ``z`` (``A = [P | Phi Q2]`` the centres'
    basis, ``C`` the match masses, ``R0`` the bending and affine
    regularisers per unit temperature). ``A`` is square and invertible for
    distinct centres, so with ``u = A z`` (the spline at its centres) the
    same equations read ``(C + k T A^-T R0 A^-1) u = C y + k T A^-T r0``:
    the matrix is a diagonal plus a fixed one scaled, and the ``(K, K)``
    product ``A^T C A`` of every round (a third of a round) is gone. The
    two differ by rounding only (maps within ~1e-9 of the blade radius).
    Beyond the paper (an implementation detail of its linear solve).
    """
    a = np.ascontiguousarray(system.a)
    k = a.shape[0]
    if k < 4 or a.shape[1] != k:
        return _NO_VALUES
    try:
        if not np.isfinite(a).all() or np.linalg.cond(a) > _VALUES_COND:
            return _NO_VALUES
        ainv = np.linalg.inv(a)
    except np.linalg.LinAlgError:
        return _NO_VALUES
    r0 = np.zeros((k, k))
    r0[3:, 3:] = prm.lambda1_init * system.bend
    r0[1, 1] += prm.lambda2_init
    r0[2, 2] += prm.lambda2_init
    reg0 = ainv.T @ r0 @ ainv
    reg0 = 0.5 * (reg0 + reg0.T)  # symmetric to the last bit: the Cholesky reads one triangle
    return ainv, np.ascontiguousarray(reg0)


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
_MOVE_TOL = 1e-2
_COUNTS = np.zeros(2, np.int64)
_SUB_MARGIN = 0.7


_LN2_HI = 6.93147180369123816490e-01  # ln 2 in two parts (fdlibm): q * _LN2_HI is exact for |q| < 2^20
_LN2_LO = 1.90821492927058770002e-10
_INV_LN2 = 1.44269504088896338700e+00
#: exp(r) on |r| <= ln(2) / 2: Taylor to r^13 (the next term is < 1e-17 relative).
_EXP_TAYLOR = tuple(1.0 / float(np.prod(np.arange(1, j + 1))) for j in range(13, -1, -1))


@numba.njit(cache=True, nogil=True, fastmath={"contract"})
def _exp_row(z, out):  # pragma: no cover
    """``out = exp(z)`` for ``z <= 0``, 0 where ``z <= -708``; within 1 ulp of ``np.exp``.

    Branch-free, so LLVM vectorises it: the libm ``exp`` call per weight was
    ~60 % of a softassign (the 2-core machine has no SVML); this runs ~5x
    faster. ``2^q`` is built from its exponent bits.
    """
    n = z.shape[0]
    bits = np.empty(n, np.int64)
    for j in range(n):
        zz = max(z[j], -708.0)
        q = np.floor(zz * _INV_LN2 + 0.5)
        r = (zz - q * _LN2_HI) - q * _LN2_LO
        p = _EXP_TAYLOR[0]
        for c in _EXP_TAYLOR[1:]:
            p = p * r + c
        out[j] = p
        bits[j] = (np.int64(q) + 1023) << 52
    scale = bits.view(np.float64)
    for j in range(n):
        out[j] = out[j] * scale[j] if z[j] > -708.0 else 0.0


@numba.njit(cache=True, nogil=True, fastmath={"reassoc", "contract", "arcp", "nsz"})
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
    # Below exp(-708) a weight is subnormal (< 1e-307 of the largest): 0 instead, or every
    # Sinkhorn round multiplies subnormals, ~10x slower. Each row's sum is taken while it is
    # still in cache, and every later row sum with the column normalisation (two passes over
    # the matrix per Sinkhorn round instead of four).
    rowsum = np.empty(n)
    zrow = np.empty(k + 1)
    for a in range(n + 1):
        for i in range(k + 1):
            zrow[i] = m[a, i] - top
        _exp_row(zrow, m[a])
        if a < n:
            s = 0.0
            for i in range(k + 1):
                s += m[a, i]
            rowsum[a] = s
    colsum = np.empty(k)
    for it in range(sinkhorn):
        err = 0.0
        for a in range(n):
            err = max(err, abs(rowsum[a] - 1.0))
        if it > 0 and err < tol:  # the rows already sum to 1: converged
            break
        colsum[:] = 0.0
        for a in range(n):
            r = 1.0 / max(rowsum[a], 1e-300)
            for i in range(k + 1):
                m[a, i] *= r
            for i in range(k):
                colsum[i] += m[a, i]
        for i in range(k):
            colsum[i] = 1.0 / max(colsum[i] + m[n, i], 1e-300)
        for i in range(k):
            m[n, i] *= colsum[i]
        for a in range(n):
            s = 0.0
            for i in range(k):
                m[a, i] *= colsum[i]
                s += m[a, i]
            rowsum[a] = s + m[a, k]
    return m[:n, :k].copy()


@numba.njit(cache=True, nogil=True)
def _spd_solve_nb(h, rhs):  # pragma: no cover
    """``h^-1 rhs`` for a symmetric positive definite ``h`` (Cholesky, then two triangular solves).

    The spline's normal equations ``A^T C A + lambda B`` are SPD: half the
    work of the LU solve, ~20 % of the annealing. Raises LinAlgError when
    ``h`` is not positive definite (the numpy loop then takes over).
    """
    low = np.linalg.cholesky(h)
    k, c = rhs.shape
    z = np.empty_like(rhs)
    for j in range(c):
        for r in range(k):
            s = rhs[r, j]
            for q in range(r):
                s -= low[r, q] * z[q, j]
            z[r, j] = s / low[r, r]
        for r in range(k - 1, -1, -1):
            s = z[r, j]
            for q in range(r + 1, k):
                s -= low[q, r] * z[q, j]
            z[r, j] = s / low[r, r]
    return z


@numba.njit(cache=True, nogil=True)
def _anneal_nb(x, v, lab_x, lab_v, use_lab, cost, use_cost, phi, amat, bend, q2, t, t_init, t_final,
               rate, iterations, sinkhorn, lam1, lam2, sink_tol, move_tol, counts, fv0, cx_in,
               t_end, ainv, reg0):  # pragma: no cover
    n, k = x.shape[0], v.shape[0]
    # With ``ainv`` (A^-1, (K, K)) the fit is solved for the spline's values at
    # the centres, u = A z (see _fit_space): no (K, K) product per round.
    values = ainv.shape[0] == k
    kz = np.empty((k, k))
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
            if values:
                # (C + k t A^-T R0 A^-1) u = C y + k t lambda2 A^-T E: the normal
                # equations below multiplied by A^-T, with z = A^-1 u.
                tk = k * t
                for i in range(k):
                    for j in range(k):
                        kz[i, j] = tk * reg0[i, j]
                    kz[i, i] += c[i]
                rhs = np.empty((k, 2))
                l2 = lam2 * tk
                for i in range(k):
                    rhs[i, 0] = c[i] * y[i, 0] + l2 * ainv[1, i]
                    rhs[i, 1] = c[i] * y[i, 1] + l2 * ainv[2, i]
                fv_new = _spd_solve_nb(kz, rhs)
                z = np.dot(ainv, fv_new)
                w = np.dot(q2, np.ascontiguousarray(z[3:]))
                d = z[:3].copy()
            else:
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
                z = _spd_solve_nb(h, rhs)
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
