"""Dendritic stylization, vines on an object found on its ground (split from
:mod:`~branchnb.dendrite.stylization`, whose :class:`~branchnb.dendrite.stylization.Stylizer`
has these methods).

Beyond the paper, whose importance takes what is dark as the object: on a dark ground a
lighter object got vines along its outline only, and on a textured ground the vines
spread over the ground. There the object is what differs in colour from the picture's
frame (:func:`~branchnb.dendrite.foreground._object_mask`), and the vines grow on it.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from ..core.image import as_gray
from .dendrite import Dendrite, build_dendrite
from .endpoints import place_endpoints
from .foreground import GROUND_RING, _object_mask
from .lattice import Lattice
from .stylize_params import STRIKE_PENALTY, StylizeParams, _ground_threshold
from .stylize_seed import _ENDPOINTS, _IMPORTANCE, _LATTICE, _PLAN, _subset

__all__: list[str] = []

#: Share of the vines' content off the object beyond which they grow on the object found
#: (0.25 until dendrite33: a ground's horizon behind a tree, 3 % of the content, drew a
#: long stem along the ground).
VINE_MIN_SPILL = 0.01
#: Largest piece of the content off the object, as a share of the object's area, that
#: is ground texture rather than a part of the object the colour test missed.
VINE_MISSED_PART = 0.2
#: How much lighter (luminance) than its frame an object is for the vines to grow on it
#: (the importance, darkness, took the dark ground as the object).
VINE_LIGHTER = 0.1
#: Floor of the vines' tip density on the object, as a share of its importance's maximum
#: (a flat, light fill has no importance of its own).
VINE_OBJECT_FLOOR = 0.3


class _ObjectSteps:
    """:class:`~branchnb.dendrite.stylization.Stylizer`'s vine-on-object methods (they use
    its cached stages: ``importance``, ``lattice``, ``working_image`` ...)."""

    def _vine_object(self, p: StylizeParams) -> np.ndarray | None:
        """The object the vines grow on, or None for the paper's content (cached).

        The object found on its ground where more than ``VINE_MIN_SPILL`` of the content
        (importance above the ground's, :func:`_ground_threshold`) lies off it, or where
        it is ``VINE_LIGHTER`` lighter than its frame; not where the content off the object
        holds a piece larger than ``VINE_MISSED_PART`` of the object (its own part the
        colour test missed).
        """
        def make():
            imp = self.importance(p)
            obj = _object_mask(self.working_image(p))
            if obj is None:
                return None
            content = imp >= _ground_threshold(imp, p.endpoint_threshold)
            r = max(3, int(round(0.02 * float(np.hypot(*imp.shape)))))
            near = ndimage.distance_transform_edt(~obj) <= r
            lum = as_gray(self.working_image(p))
            b = max(1, int(round(GROUND_RING * max(lum.shape))))
            ring = np.ones(lum.shape, bool)
            ring[b:-b, b:-b] = False
            if float(lum[obj].mean()) - float(np.median(lum[ring & ~obj])) > VINE_LIGHTER:
                return obj
            off = content & ~near
            spill = float(off.sum()) / max(int(content.sum()), 1)
            if spill <= VINE_MIN_SPILL:
                return None
            # a ground's texture spills in specks; one large piece off the object is the
            # object's own part the colour test missed (a grey bottle's side on a grey wall)
            pieces, n = ndimage.label(ndimage.binary_closing(off, iterations=2))
            largest = np.bincount(pieces.ravel())[1:].max() if n else 0
            return obj if largest < VINE_MISSED_PART * obj.sum() else None
        return self._get(("vine_object", _subset(p, _IMPORTANCE), p.endpoint_threshold), make)

    def _vine_seed(self, p: StylizeParams, obj) -> np.ndarray:
        """The object's most important, most inner point, in image pixels."""
        imp = self.importance(p).astype(np.float64)
        inner = ndimage.distance_transform_edt(obj)
        score = ndimage.gaussian_filter(np.where(obj, imp + 0.5, 0.0), 0.04 * np.hypot(*imp.shape))
        score = np.where(inner >= 0.5 * inner.max(), score, -1.0)
        row, col = np.unravel_index(int(np.argmax(score)), score.shape)
        return self.to_image(p, [float(col), float(row)])

    def _vine_dendrite(self, p: StylizeParams, seed, rng_seed: int,
                       obj) -> tuple[Dendrite, np.ndarray]:
        """Tips stippled on the object, paths planned with its outside costly (cached);
        the dendrite and its endpoints (lattice ``(x, y)``)."""
        key = ("vine_dendrite", _subset(p, _IMPORTANCE + _LATTICE + _PLAN + _ENDPOINTS),
               tuple(np.round(np.asarray(seed, float), 3)), rng_seed)

        def make():
            imp = self.importance(p)
            dens = np.where(obj, np.maximum(imp, VINE_OBJECT_FLOOR * float(imp[obj].max())), 0.0)
            ends = place_endpoints(dens, p.n_endpoints, gamma=p.endpoint_gamma, floor=0.0,
                                   threshold=0.0, iterations=p.stipple_iterations,
                                   rng=rng_seed + 1)
            lat = self.lattice(p, rng_seed)
            w = lat.weights + float(np.mean(lat.weights)) * STRIKE_PENALTY * 4 * ~obj
            res = self._plan_on(Lattice(w, lat.factors), p, seed)
            return build_dendrite(res, ends), ends
        return self._get(key, make)
