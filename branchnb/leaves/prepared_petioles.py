"""Each exemplar's own petiole, carried onto new leaves (step 5; a part of :class:`branchnb.leaves.prepared._Prepared`).

The registration is of the laminae; a new leaf gets one exemplar's own
petiole attached at its base (:meth:`_PetioleSteps.petiole_layer`).
"""

from __future__ import annotations

import numpy as np

from ..core.image import extend_nearest
from ..core.morphology import _binary_dilation, _binary_erosion
from .shaping import _map_jacobian, _remap_values, _sample

__all__: list[str] = []


class _PetioleSteps:
    """The petiole steps of :class:`branchnb.leaves.prepared._Prepared` (which holds the state they read)."""

    def _prepare_petioles(self):
        """Each exemplar's own petiole (RGBA, exemplar frame), its base and how its lamina meets the base.

        The registration is of the laminae (a petiole bends and varies in
        length: no shared shape), so the shape blend would carry the training
        leaf's petiole onto every new leaf. Instead the training petiole is
        cut from the alpha and a new leaf gets one exemplar's own petiole,
        attached at the new leaf's base as it is attached to its own lamina.
        """
        from .registration import split_petiole

        a = self.analysis
        t = a.training_index
        self.petiole_rgba, self.petiole_base, self.petiole_jac = [], [], []
        # Each exemplar's size: the square root of its lamina's area, and its lamina's centroid.
        laminae = [split_petiole(b)[0] for b in a.blades]
        self.lamina_size = [float(np.sqrt(lam.sum())) for lam in laminae]
        self.lamina_centre = [np.array([np.nonzero(lam)[1].mean(), np.nonzero(lam)[0].mean()])
                              if lam.any() else None for lam in laminae]
        _, pet_t, base_t = split_petiole(a.blades[t])
        self.base_t = base_t
        if base_t is not None:
            rim = _binary_dilation(pet_t, iterations=2) & ~_binary_erosion(
                a.blades[t] & ~pet_t, iterations=1)
            # With the faint alpha off the blade whose nearest blade pixel is
            # petiole (a photo's shadow and fringe along the stalk), which
            # the rim misses and which traced the old petiole faintly beside
            # the new one.
            rim |= extend_nearest(pet_t, a.blades[t]) & ~a.blades[t]
            self.alpha_t = self.alpha_t * ~rim
        for e in range(self.n):
            _, pet, base = split_petiole(a.blades[e])
            if base_t is None or base is None:
                self.petiole_rgba.append(None)
                self.petiole_base.append(None)
                self.petiole_jac.append(None)
                continue
            keep = _binary_dilation(pet, iterations=2)
            # Only the petiole's box (plus a 2 px transparent rim) is kept: a
            # whole RGBA exemplar per petiole was 50 MB at 1 MP.
            ys, xs = np.nonzero(keep)
            y0, x0 = max(0, ys.min() - 2), max(0, xs.min() - 2)
            y1, x1 = ys.max() + 3, xs.max() + 3
            img = np.asarray(a.exemplars[e], np.float32)[y0:y1, x0:x1].copy()
            img[..., 3] *= keep[y0:y1, x0:x1]
            img = np.pad(img, ((1, 1), (1, 1), (0, 0)))  # transparent beyond the box (edges are replicated)
            self.petiole_rgba.append((img, np.array([x0 - 1, y0 - 1], np.float32)))
            self.petiole_base.append(base)
            self.petiole_jac.append(_map_jacobian(self.from_exemplar[e], base))
        self.petiole_exemplars = [e for e in range(self.n) if self.petiole_rgba[e] is not None]

    def petiole_layer(self, e: int, m: np.ndarray):
        """Exemplar ``e``'s petiole (RGBA) in the output frame of the shape map ``m``, or None.

        The new leaf's base ``y_b`` is where ``m`` reaches the training
        base; the petiole is moved there by a similarity whose scale is that
        of the polar decomposition of ``J_m(y_b)^-1 J_e(base_e)`` (how
        exemplar ``e``'s frame relates to the new leaf's at the base) and
        whose rotation turns exemplar ``e``'s lamina axis (base to lamina
        centroid) onto the new leaf's: the petiole keeps the angle it makes
        with its own lamina. (The rotation of the local Jacobian followed
        the blend's bending of the lamina right at the base: new maples'
        petioles came out up to 18-20 degrees farther from the lamina's
        axis than any exemplar's.)
        """
        if self.base_t is None or self.petiole_rgba[e] is None:
            return None
        d = np.hypot(m[..., 0] - self.base_t[0], m[..., 1] - self.base_t[1])
        yb = np.array(np.unravel_index(int(np.argmin(d)), d.shape)[::-1], np.float64)
        if d[int(yb[1]), int(yb[0])] > 0.05 * self.size:
            return None  # the new leaf's base is off the canvas
        jm = _map_jacobian(m, yb)
        lin = np.linalg.solve(jm, self.petiole_jac[e]) if abs(np.linalg.det(jm)) > 1e-9 else np.eye(2)
        u, sv, vt = np.linalg.svd(lin)
        rot = u @ vt
        if np.linalg.det(rot) < 0:  # no mirrored petiole
            u[:, -1] *= -1
            rot = u @ vt
        axis_n = self._lamina_axis(m, yb)
        c_e = self.lamina_centre[e]
        if axis_n is not None and c_e is not None:
            v_e = c_e - np.asarray(self.petiole_base[e], float)
            if np.hypot(*v_e) > 1e-6:
                t = float(np.arctan2(axis_n[1], axis_n[0]) - np.arctan2(v_e[1], v_e[0]))
                rot = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
        sim = rot * float(np.sqrt(sv.prod()))
        inv = np.linalg.inv(sim)
        img, off = self.petiole_rgba[e]
        # Only the output box the petiole's own box lands in is sampled: beyond it the sample reads
        # the box's transparent rim (replicated), 0 (a whole-canvas map per petiole was a tenth of
        # a new leaf's time at 1 MP).
        ph, pw = img.shape[:2]
        corners = (np.array([[0, 0], [pw - 1, 0], [0, ph - 1], [pw - 1, ph - 1]], np.float64) + off
                   - self.petiole_base[e]) @ sim.T + yb
        h, w = self.shape
        x0, y0 = (max(0, int(np.floor(v)) - 2) for v in corners.min(0))
        x1, y1 = min(w, int(np.ceil(corners[:, 0].max())) + 3), min(h, int(np.ceil(corners[:, 1].max())) + 3)
        out = np.zeros(self.shape + (img.shape[2],), np.float32)
        if x0 < x1 and y0 < y1:
            box = (slice(y0, y1), slice(x0, x1))
            q = (np.stack([self.xx[box], self.yy[box]], -1) - yb) @ inv.T + self.petiole_base[e]
            out[box] = _sample(img, (q - off).astype(np.float32))
        return out

    def _lamina_axis(self, m: np.ndarray, yb) -> np.ndarray | None:
        """The new lamina's axis (from the base ``yb`` to its centroid) under the shape map ``m``, or None.

        Measured on a grid of about 64 steps across the leaf (a centroid).
        """
        step = max(1, int(self.size // 64))
        sub = np.ascontiguousarray(m[::step, ::step])
        lam = _remap_values(self.alpha_t, sub)
        inside = (sub[..., 0] >= 0) & (sub[..., 0] <= self.shape[1] - 1) & (sub[..., 1] >= 0) & (
            sub[..., 1] <= self.shape[0] - 1)
        lam = np.where(inside, lam, 0.0)
        tot = float(lam.sum())
        if tot <= 0:
            return None
        ys, xs = np.mgrid[0:self.shape[0]:step, 0:self.shape[1]:step]
        v = np.array([(lam * xs).sum() / tot, (lam * ys).sum() / tot]) - np.asarray(yb, float)
        return v if np.hypot(*v) > 1e-6 else None
