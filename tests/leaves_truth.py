"""Registration through TRUE correspondences, for measuring induction independently of registration.

A thin-plate spline through the procedural leaves' keypoints (the same
material point on every leaf) with the interface of
:class:`branchnb.leaves.registration.Registration`.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import RBFInterpolator

from branchnb.core.warp import remap


class TrueRegistration:
    """Exemplar -> training warp through known corresponding points."""

    def __init__(self, exemplar_points, training_points, shape):
        self.shape = tuple(shape)
        e = np.asarray(exemplar_points, float)
        t = np.asarray(training_points, float)
        self._fwd = RBFInterpolator(e, t, kernel="thin_plate_spline", smoothing=0.0)
        self._inv = RBFInterpolator(t, e, kernel="thin_plate_spline", smoothing=0.0)
        # The splines are smooth: evaluate on an 8-px grid, interpolate bilinearly.
        h, w = self.shape
        step = 8
        gy, gx = np.arange(0, h + step, step), np.arange(0, w + step, step)
        xx, yy = np.meshgrid(gx, gy)
        grid = np.column_stack([xx.ravel(), yy.ravel()]).astype(float)
        self.map_to_training = self._dense(self._inv(grid), len(gy), len(gx), step)
        self.map_from_training = self._dense(self._fwd(grid), len(gy), len(gx), step)

    def _dense(self, values, gh, gw, step):
        import cv2
        h, w = self.shape
        coarse = values.reshape(gh, gw, 2).astype(np.float32)
        big = cv2.resize(coarse, ((gw - 1) * step + 1, (gh - 1) * step + 1), interpolation=cv2.INTER_LINEAR)
        return np.ascontiguousarray(big[:h, :w])

    def forward(self, points):
        return self._fwd(np.asarray(points, float).reshape(-1, 2))

    def inverse(self, points):
        return self._inv(np.asarray(points, float).reshape(-1, 2))

    def to_training(self, img):
        m = self.map_to_training
        return remap(img, m[..., 0], m[..., 1])[0]

    def from_training(self, img):
        m = self.map_from_training
        return remap(img, m[..., 0], m[..., 1])[0]


def true_registrations(leaves, training_index):
    t = leaves[training_index].keypoints
    shape = leaves[0].image.shape[:2]
    return [TrueRegistration(leaf.keypoints, t, shape) for leaf in leaves]



def normalised_true_registrations(leaves, training_index=0):
    """True registrations on the canvas :func:`~branchnb.leaves.analysis.normalise_exemplars` puts the leaves on."""
    from branchnb.leaves.analysis import normalise_exemplars
    _, blades, offs = normalise_exemplars(leaves)
    kps = [leaf.keypoints + np.array(o) for leaf, o in zip(leaves, offs)]
    return [TrueRegistration(k, kps[training_index], blades[0].shape) for k in kps]


def perturbed(registration, amplitude, rng):
    """``registration`` with its maps moved by a smooth random field of at most ``amplitude`` px."""
    from branchnb.leaves._measure import _Perturbed
    return _Perturbed(registration, amplitude, rng)
