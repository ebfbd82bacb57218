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
        h, w = self.shape
        ys, xs = np.mgrid[0:h, 0:w]
        grid = np.column_stack([xs.ravel(), ys.ravel()]).astype(float)
        self.map_to_training = self._inv(grid).reshape(h, w, 2).astype(np.float32)
        self.map_from_training = self._fwd(grid).reshape(h, w, 2).astype(np.float32)

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
