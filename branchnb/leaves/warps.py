"""The registration result: point maps and dense warps (step 3 of :mod:`branchnb.leaves.registration`).

:class:`Registration` maps exemplar pixels to training pixels
(:meth:`~Registration.forward`: the start map, then the splines) and back
(:meth:`~Registration.inverse`: Newton steps on the forward map from a
fitted spline), and resamples images both ways through dense maps
evaluated on a ``grid_step`` grid and interpolated bilinearly.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from threadpoolctl import threadpool_limits

from ..core.image import as_float_image
from ..core.validate import check_int
from ..core.warp import remap
from .keypoints import Keypoints
from .tps import ThinPlateSpline, _points, _solve, _sqdist, _tps_kernel

__all__ = ["Registration"]


#: Training px: :meth:`Registration.inverse` stops refining a point whose residual is below this.
_NEWTON_TOL = 1e-4


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
        with threadpool_limits(1):  # one dense solve: BLAS threads only stall on a busy machine
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
