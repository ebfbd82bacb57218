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
#: Smallest separate part of the object, as a share of its area, that gets vines of its own
#: (a root of its own: :meth:`_ObjectSteps._vine_seeds`); smaller specks get no tips.
VINE_PART_MIN = 0.02
#: Least share of the picture an object of separate parts covers (the object found on a
#: ground covers 5 %: three small letters on white got vines crossing between them) ...
VINE_PARTS_COVER = 0.005
#: ... and most share of the content (importance above the ground's) off it: on a photo the
#: content is everywhere and a few coloured specks are no object.
VINE_PARTS_SPILL = 0.1
#: Shortest limb (a trunk, a pole, a leg, a letter's stroke), as a share of the object's size,
#: whose far end always gets a vine tip: how far its skeleton runs beyond the inscribed disc
#: where it meets the rest (:func:`_extremities`).
#: Longest side (px) of the copy of the picture the vines' ``hug`` is found on
#: (:meth:`_ObjectSteps._vine_hug`; larger pictures are shrunk for it).
VINE_HUG_SIDE = 1024
VINE_LIMB = 0.12
VINE_LIMB_THIN = 2.0


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
            obj = _object_mask(self.working_image(p), keep_holes=True)
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

    def _vine_parts(self, p: StylizeParams) -> np.ndarray | None:
        """The object found on its ground when it has two or more separate parts (each at
        least ``VINE_PART_MIN`` of its area), covers at least ``VINE_PARTS_COVER`` of the
        picture and holds all but ``VINE_PARTS_SPILL`` of the content, else None.

        Beyond the paper, whose dendrite is one tree from one seed: on a street lamp and a
        toadstool on a dusk sky the vines ran from one to the other through the darkest
        sky (the non-scalar metric takes the path whose costliest step is cheapest, however
        long), a loop far above both (``python -m branchnb.dendrite._vine_size_check``:
        ``pair``, ``word``). Separate parts get vines of their own.
        """
        def make():
            obj = _object_mask(self.working_image(p), min_cover=VINE_PARTS_COVER, keep_holes=True)
            if obj is None or _parts(obj)[1] < 2:
                return None
            imp = self.importance(p)
            content = imp >= _ground_threshold(imp, p.endpoint_threshold)
            r = max(3, int(round(0.02 * float(np.hypot(*imp.shape)))))
            off = content & (ndimage.distance_transform_edt(~obj) > r)
            return obj if off.sum() <= VINE_PARTS_SPILL * max(int(content.sum()), 1) else None
        return self._get(("vine_parts", _subset(p, _IMPORTANCE), p.endpoint_threshold), make)

    def _vine_hug(self, inset: int = 1) -> np.ndarray | None:
        """Where the vines' stems belong (``hug`` of :func:`~branchnb.dendrite.metaphors.vine_curves`):
        the object found on its ground at the image's own size (on a copy at most ``VINE_HUG_SIDE``
        px long, the mask scaled back; covering at least
        ``VINE_PARTS_COVER``, its holes of the ground's colours open) less ``inset`` px along
        its outline where it is wide enough to keep a core, or None (cached).

        Beyond the paper (issue 25): on drawn objects on white the stems, paths along the
        outline smoothed along the tree, ran 1-4 px past it (2-5 % of the stems' pixels off
        the object dilated by 1 px at 750 px), and on a stick figure the vines filled its
        ring head.
        """
        def make():
            import cv2

            h, w = self.shape
            f = min(1.0, VINE_HUG_SIDE / max(h, w))
            # found on a copy of at most VINE_HUG_SIDE px (the colour search took 18 s at 2000 px)
            img = self.image if f == 1.0 else cv2.resize(
                self.image, (max(1, round(w * f)), max(1, round(h * f))), interpolation=cv2.INTER_AREA)
            m = _object_mask(img, min_cover=VINE_PARTS_COVER, keep_holes=True)
            if m is None:
                return None
            if f < 1.0:
                m = cv2.resize(m.astype(np.float32), (w, h), interpolation=cv2.INTER_LINEAR) > 0.5
            # ``inset`` px in from the outline, so a stem's width stays on the object; strokes
            # too thin for that keep their pixels
            core = ndimage.distance_transform_edt(np.pad(m, 1))[1:-1, 1:-1] > inset
            return core | (m & ~ndimage.binary_dilation(core, iterations=inset + 1))
        return self._get(("vine_hug", int(inset)), make)

    def _vine_seeds(self, p: StylizeParams, obj, seed) -> np.ndarray:
        """``seed`` (lattice ``(x, y)``) and the most inner, most important point of every
        other part of ``obj`` (at least ``VINE_PART_MIN`` of its area): one root per part,
        ``(S, 2)``."""
        labels, n = _parts(obj)
        seeds = [np.asarray(seed, float)]
        sx, sy = np.clip(np.round(seeds[0]).astype(int), 0, np.array(obj.shape[::-1]) - 1)
        for i in range(1, n + 1):
            part = labels == i
            if part[sy, sx]:
                continue
            seeds.append(self.to_lattice(p, self._vine_seed(p, part)))
        return np.array(seeds)

    def _vine_seed(self, p: StylizeParams, obj) -> np.ndarray:
        """The object's most important, most inner point, in image pixels."""
        imp = self.importance(p).astype(np.float64)
        labels, n = _parts(obj)
        obj = labels > 0 if n else obj
        inner = ndimage.distance_transform_edt(obj)
        score = ndimage.gaussian_filter(np.where(obj, imp + 0.5, 0.0), 0.04 * np.hypot(*imp.shape))
        score = np.where(inner >= 0.5 * inner.max(), score, -1.0)
        row, col = np.unravel_index(int(np.argmax(score)), score.shape)
        return self.to_image(p, [float(col), float(row)])

    def _vine_dendrite(self, p: StylizeParams, seed, rng_seed: int,
                       obj) -> tuple[Dendrite, np.ndarray]:
        """Tips stippled on the object, paths planned with its outside costly from a root in
        each of its parts (:meth:`_vine_seeds`; cached); the dendrite (a forest when the
        object has separate parts) and its endpoints (lattice ``(x, y)``)."""
        key = ("vine_dendrite", _subset(p, _IMPORTANCE + _LATTICE + _PLAN + _ENDPOINTS),
               tuple(np.round(np.asarray(seed, float), 3)), rng_seed)

        def make():
            imp = self.importance(p)
            labels, n = _parts(obj)
            seeds = self._vine_seeds(p, obj, seed) if n > 1 else seed
            obj_ = labels > 0 if n else obj  # specks off the parts get no tips
            dens = np.where(obj_, np.maximum(imp, VINE_OBJECT_FLOOR * float(imp[obj_].max())), 0.0)
            ends = place_endpoints(dens, p.n_endpoints, gamma=p.endpoint_gamma, floor=0.0,
                                   threshold=0.0, iterations=p.stipple_iterations,
                                   rng=rng_seed + 1)
            # beyond the paper: tips stippled by area left a trunk's foot bare when tips are
            # few (a sky tree's trunk rows reached 1.00 -> 0.77 at 700 px with 61 tips)
            ends = np.vstack([ends, _extremities(obj_)])
            lat = self.lattice(p, rng_seed)
            w = lat.weights + float(np.mean(lat.weights)) * STRIKE_PENALTY * 4 * ~obj
            res = self._plan_on(Lattice(w, lat.factors), p, seeds)
            return build_dendrite(res, ends), ends
        return self._get(key, make)


def _extremities(obj) -> np.ndarray:
    """The far ends of the object's limbs, lattice ``(x, y)`` ``(E, 2)``: ends of its skeleton
    whose branch runs at least ``VINE_LIMB`` of the object's size and ``VINE_LIMB_THIN``
    times its own half-width beyond the inscribed disc at the junction where it meets the
    rest (a lobe's spur or the end of a blob's axis does not; a thin part with no junction
    gives both its ends).

    >>> m = np.zeros((60, 80), bool); m[10:40, 10:70] = True; m[40:58, 38:42] = True
    >>> np.round(_extremities(m)).astype(int).tolist()  # the stem's foot, not the box's corners
    [[39, 56]]
    """
    from skimage.morphology import skeletonize

    obj = np.asarray(obj, bool)
    if not obj.any():
        return np.zeros((0, 2))
    edt = ndimage.distance_transform_edt(obj)
    skel = skeletonize(obj)
    nb = ndimage.convolve(skel.astype(np.uint8), np.ones((3, 3), np.uint8), mode="constant") - 1
    tips = skel & (nb == 1)
    junc = skel & (nb >= 3)
    near_junc = ndimage.binary_dilation(junc, np.ones((3, 3), bool))
    labels, n = ndimage.label(skel & ~near_junc, np.ones((3, 3), bool))
    if n == 0:
        return np.zeros((0, 2))
    length = np.bincount(labels.ravel(), minlength=n + 1).astype(float)
    # the inscribed radius where a branch meets a junction (0 for a branch with none)
    meet = ndimage.binary_dilation(near_junc, np.ones((3, 3), bool)) & (labels > 0)
    radius = np.zeros(n + 1)
    np.maximum.at(radius, labels[meet], edt[meet])
    # ... and is a limb: thin, at least VINE_LIMB_THIN times its own half-width long
    half = np.asarray(ndimage.median(edt, labels, np.arange(n + 1)), float)
    out = length - radius
    limb = (out >= VINE_LIMB * float(np.sqrt(obj.sum()))) & (out >= VINE_LIMB_THIN * half)
    ty, tx = np.nonzero(tips & (labels > 0))
    keep = limb[labels[ty, tx]]
    ends = []
    for y, x in zip(ty[keep], tx[keep]):
        # a skeleton ends a half-width short of its limb's end: carry on along the branch
        # to a pixel short of the outline (a trunk's foot, not a half-width above it)
        r = max(2.0, 2.0 * half[labels[y, x]])
        by, bx = np.nonzero(labels == labels[y, x])
        close = np.hypot(by - y, bx - x) <= r
        d = np.array([x - bx[close].mean(), y - by[close].mean()])
        p = np.array([x, y], float)
        if np.hypot(*d) > 0:
            d /= np.hypot(*d)
            for _ in range(int(np.ceil(2 * r + 2))):
                q = p + 0.5 * d
                qx, qy = int(round(q[0] + d[0])), int(round(q[1] + d[1]))
                if not (0 <= qy < obj.shape[0] and 0 <= qx < obj.shape[1] and obj[qy, qx]):
                    break
                p = q
        ends.append(p)
    return np.array(ends, float).reshape(-1, 2)


def _parts(obj) -> tuple[np.ndarray, int]:
    """The object's parts of at least ``VINE_PART_MIN`` of its area, labelled 1..n."""
    labels, n = ndimage.label(obj)
    if n < 2:
        return labels, n
    sizes = np.bincount(labels.ravel())[1:]
    keep = np.flatnonzero(sizes >= VINE_PART_MIN * sizes.sum())
    lut = np.zeros(n + 1, np.int64)
    lut[keep + 1] = np.arange(1, keep.size + 1)
    return lut[labels], int(keep.size)
