"""What every new leaf of one analysis shares (see :mod:`branchnb.leaves.synthesis`).

The stage images of every exemplar (steps 1-2: the residual and each
layer's image, bled outside the blade), the layer masks and weights, the
colour ranges a layer's contrast is clipped to, the maps between the
training frame and every exemplar's (with the exemplar's pose taken out,
step 3), each exemplar's own petiole (step 5) and the median registration
error (:func:`registration_errors`) the random warps are measured in.
Built once per analysis and cached on it.

The helpers live in :mod:`branchnb.leaves.prepared_fill` (bleeding,
smooth fills, completed masks), :mod:`branchnb.leaves.prepared_layers`
(the layers' extensions and rims) and
:mod:`branchnb.leaves.prepared_petioles` (step 5); their names are
importable from here as before.
"""
from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.image import extend_nearest  # noqa: F401  (importable from here as before)
from ..core.morphology import _binary_dilation, _binary_erosion
from .flatart import _layer_lines, _replace_from_blade, drawn_outline, flat_art
from .leftover import flatten_leftover, layer_strength, own_lines, parallel_lines

# The steps' helpers, one module each; every name importable from here as before.
from .prepared_fill import _SOFT_RIM, _bleed, _clear_of, _completed, _smooth_fill, _soft_rim, _stored, _without_knobs  # noqa: F401
from .prepared_layers import (  # noqa: F401
    _SPECK_SIDE,
    _completeness,
    _leftover_layer,
    _refilled_rims,
    _removed_extension,
    _without_specks,
)
from .prepared_petioles import _PetioleSteps
from .shaping import _affine_grid, _grid, _map_jacobian, _remap_map, _remap_values, _sample  # noqa: F401

__all__ = ["registration_errors"]


#: Drop side knobs from the completed mask of the most structural layer on photographs (see :func:`_completed`).
_LINE_KNOBS = True

#: Refill the rims of every layer but the most structural one in the background (see :func:`_refilled_rims`).
_REFILL_RIMS = True

#: Level (share of the layer's own ridge strength) at which the background's lines right beside the most
#: structural layer's induced (and registered) mask, grown by the layer's width and 2 px, are flattened,
#: whatever their length (None: not done). Going beyond the paper (issue 22, one vein system): the first
#: pass (level 0.5, pieces of 4 % of the leaf size, in the registration corridor) left the stubs and rims of
#: veins the induction cut short, and once new leaves keep their leading exemplar's pose
#: (``SynthesisParams.pose_kernel`` 0.15) they were resampled sharper beside the donor's pasted veins.
#: Under-induced lobed family of ``tests/test_leaves_synthesis_onesystem.py`` (ridge response at the
#: backgrounds' own true veins over plain blade, 6 new leaves), pose kernel 1 / 0.15: 1.065 / 1.150
#: without, 1.044 / 1.119 at 0.5, 1.017 / 1.071 at 0.3, 1.010 / 1.054 at 0.2 (corridor grown 3 px; the
#: first pass's 4 % length kept at 0.3: 1.083).
_NEAR_LEVEL = 0.2


#: Paste a layer's ridge extension (what the residual removed beyond its induced mask) back with it
#: (see :func:`_removed_extension`).
_PASTE_EXTENSIONS = True


def _boundary(mask):
    return mask & ~_binary_erosion(mask)


def registration_errors(analysis) -> list[float]:
    """Per exemplar: mean distance (px) between the training blade's outline and the registered exemplar's.

    A registration-independent measure (it only uses ``to_training``); 0 for the training leaf.

    Parameters
    ----------
    analysis : LeafAnalysis
        Gives the blades, the training index and the registrations.

    Returns
    -------
    list of float
        One symmetric mean outline distance per exemplar, in training-leaf
        pixels; NaN where the warped blade is empty.
    """
    from .analysis import warp_mask
    t = analysis.training_index
    bt = analysis.blades[t]
    dt_t = ndi.distance_transform_edt(~_boundary(bt))
    out = []
    for e, reg in enumerate(analysis.registrations):
        if e == t:
            out.append(0.0)
            continue
        be = warp_mask(reg, analysis.blades[e], to_training=True)
        if not be.any():
            out.append(float("nan"))
            continue
        dt_e = ndi.distance_transform_edt(~_boundary(be))
        out.append(float(0.5 * (dt_t[_boundary(be)].mean() + dt_e[_boundary(bt)].mean())))
    return out


#: A layer's paste mask grows (:func:`_completed`, the ridge extension) no nearer than this (px) to a
#: band along the outline of another layer (:func:`~branchnb.leaves.margin_band.outline_region`).
#: Beyond the paper (leaves80). A variegated leaf's cream-to-green band edge stands out as a pale
#: vein does: a vein layer's completion and ridge extension grew along it, and pasted onto a new
#: leaf whose band lies elsewhere that rim drew long cream threads through its green centre. The
#: band's mask stops 1-2 px short of its colour's edge (the windowed colour term's rim), so the
#: 2 px kept from other layers left the rim to the veins. Cream share of new leaves' green cores
#: (eroded 3 px; the leaves of ``tests/test_leaves_variegated.py``, 6 new leaves, rng 0): 240 px
#: (4 exemplars) mean 0.0027 -> 0.0006; 400 px (5) 0.0008-0.0069 on five of six -> 0.0003-0.0008 (the
#: sixth's 0.025 are its pasted pale veins, unchanged); 600 px (6) mean 0.018 -> 0.011, max 0.034 ->
#: 0.022: the rest are cream strips cut off the pasted band by a ring the vein induction itself took
#: along the donor's band edge (open).
_BAND_EDGE = 4


class _Prepared(_PetioleSteps):
    """What every generated leaf of one analysis shares (exemplar-frame images and maps)."""

    def __init__(self, analysis):
        a = analysis
        self.analysis = a
        t = a.training_index
        self.shape = a.blades[t].shape
        self.n = len(a.exemplars)
        self.size = float(np.sqrt(a.blades[t].sum()))
        self.xx, self.yy = _grid(self.shape)
        # Drawn exemplars (flat fill, ink outline): see branchnb.leaves.flatart.
        self.flat = flat_art(a.exemplars, a.blades)
        fa = self.flat
        last = len(a.residuals) - 1

        leftover = _leftover_layer(a) if fa is None else None
        # On drawings, each layer's whole drawn lines (branchnb.leaves.flatart._layer_lines):
        # the stretches of a line the induction missed are the same vein, so
        # they leave the later stages (the background above all: they stayed
        # beside the donor's pasted veins) and come with the layer when pasted.
        self.lines = [[_layer_lines(a.residuals[k][e], a.blades[e], L.masks[e], fa.ink[e], fa.outline[e])
                       for e in range(self.n)] for k, L in enumerate(a.layers)] if fa is not None else None

        def drawn_removed(k, e, base):
            # What a drawing's stage k lacks: ``base`` and the lines of every layer above it.
            out = base
            for j in range(min(k, len(self.lines))):
                out = out | self.lines[j][e]
            return out

        def stage_image(k, e):
            img = np.asarray(a.residuals[k][e], np.float32)
            if fa is not None:
                # No outline in any stage (it is drawn anew along the new
                # blade), and no ink at all in the background: ink the
                # induction missed stayed beside the donor's veins.
                img = fa.clean(img, a.blades[e], drawn_removed(k, e, fa.ink[e] if k == last else fa.outline[e]))
            elif outlines[e].any():
                # An ink outline around a leaf that is not flat art (a
                # gradient-filled drawing) is taken out too (drawn_outline).
                img = _replace_from_blade(img, a.blades[e], outlines[e])
            if fa is None and k == last and k > 0 and _REFILL_RIMS:
                img = _refilled_rims(img, a, e, None if leftover is None else leftover[0])
            if leftover is not None and k == last and k > 0:
                # One vein system: what the induction left of the most
                # structural layer is flattened (branchnb.leaves.leftover),
                # once any ink outline is gone (lines found along it were
                # filled with its ink: dark pixels inside new blades).
                top, sign, width = leftover
                L = a.layers[top]
                reg = getattr(L, "registered", None)
                corridor = None
                if reg is not None and reg[e] is not None and np.asarray(reg[e]).any():
                    corridor = _binary_dilation(np.asarray(reg[e], bool),
                                                   iterations=max(1, int(np.ceil(L.eps_px[e]))))
                src = np.asarray(a.exemplars[e], np.float32)
                if outlines[e].any():
                    src = _replace_from_blade(src, a.blades[e], outlines[e])
                img = flatten_leftover(img, a.blades[e], src, a.residuals[top][e], L.masks[e],
                                       sign, width, corridor=corridor)
                # Then what is left right beside the induced layer (its strip
                # grown by its width and 2 px), at a lower level and any
                # length: the stubs and rims of veins the induction cut short
                # (see _NEAR_LEVEL).
                near = np.asarray(L.masks[e], bool)
                if reg is not None and reg[e] is not None:
                    near = near | np.asarray(reg[e], bool)
                if near.any() and _NEAR_LEVEL is not None:
                    near = _binary_dilation(near, iterations=int(np.ceil(width)) + 2)
                    img = flatten_leftover(img, a.blades[e], src, a.residuals[top][e], L.masks[e], sign, width,
                                           corridor=near, level=_NEAR_LEVEL, min_length=0.0)
            return _stored(_bleed(img, a.blades[e]))

        outlines = [drawn_outline(a.exemplars[e], a.blades[e]) if fa is None else None for e in range(self.n)]

        # Stage k image of exemplar e (layers above k removed), bled outside the blade.
        self.stage = [[stage_image(k, e) for e in range(self.n)] for k in range(len(a.residuals))]
        # What a layer's contrast is taken against: the next stage, without
        # any ink on drawn leaves (a stroke the induction missed is still in
        # the next stage, so its ratio was 1 and the pasted vein had gaps).
        self.under = [[_stored(_bleed(fa.clean(np.asarray(a.residuals[k][e], np.float32), a.blades[e],
                                               drawn_removed(k, e, fa.ink[e])),
                                      a.blades[e])) for e in range(self.n)] if fa is not None and 0 < k < last
                      else self.stage[k] for k in range(len(a.residuals))]
        # Layer masks grown by the pixel the residual also removed: the
        # exemplar's own anti-aliased rim comes back with the layer.
        # On photographs (and gradient drawings) a layer's contrast is taken
        # against the same stage image with the layer's pixels filled
        # smoothly from the blade around them, and the mask is completed
        # first by the pixels right beside it that stand out as the layer
        # does (:func:`_completed`).
        self.layer_masks, self.layer_weights, self.layer_under = [], [], []
        # The pasted masks without their ridge extensions, where they have one (for _agreement).
        cores = [[None] * self.n for _ in a.layers]
        # The ridge extensions pasted back (None: none), kept inside the exemplars' blade colours when pasted.
        self.layer_ext = exts = [[None] * self.n for _ in a.layers]

        def others(k, e):
            # Every other layer's pixels on exemplar e, grown by 2 px: a vein's ridge extension reaching
            # into a spot's rim brought rims of the donor's spots onto new leaves without spots there.
            # A band along the outline by _BAND_EDGE px (its colour's rim lies beyond its mask).
            out = np.zeros(a.blades[e].shape, bool)
            band = np.zeros_like(out)
            for j, Lj in enumerate(a.layers):
                if j != k:
                    if Lj.steps is not None and Lj.steps.band:
                        band |= np.asarray(Lj.masks[e], bool)
                    else:
                        out |= np.asarray(Lj.masks[e], bool)
            if band.any():
                out |= _binary_dilation(band, iterations=_BAND_EDGE - 2)
            return _binary_dilation(out, iterations=2) if out.any() else out
        for k, L in enumerate(a.layers):
            ms, ws, us = [], [], []
            for e in range(self.n):
                mk = L.masks[e]
                line = False
                if fa is not None and mk.any():
                    # Whole strokes: the ink the layer's mask touches, followed
                    # through the ink (not the outline, drawn anew).
                    strokes = fa.ink[e] & ~fa.outline[e]
                    mk = (mk | ndi.binary_propagation(mk & strokes, mask=strokes) | self.lines[k][e]) & ~fa.outline[e]
                    us.append(self.under[k + 1][e])
                elif mk.any():
                    line = _LINE_KNOBS and leftover is not None and k == leftover[0]
                    induced = mk
                    mk, under = _completed(self.stage[k][e], a.blades[e], mk, line=line)
                    if mk is not induced:
                        # Not into another layer's pixels (as the ridge extension below): see _BAND_EDGE.
                        mk = induced | (mk & ~others(k, e))
                    ext = _removed_extension(a, k, e, mk) if _PASTE_EXTENSIONS else None
                    if ext is not None:
                        ext = _without_specks(ext & ~others(k, e))
                    if ext is not None:
                        exts[k][e] = _stored(ext)
                        cores[k][e] = _binary_dilation(mk) & a.blades[e]
                        # The layer's ridge extension comes back with it (see _removed_extension).
                        mk = mk | ext
                        under = _smooth_fill(np.asarray(self.stage[k][e], np.float32)[..., :3],
                                             _clear_of(a.blades[e], mk))
                    us.append(_stored(under))
                else:
                    us.append(self.under[k + 1][e])
                ms.append(_stored(_binary_dilation(mk) & a.blades[e]))
                wgt = np.where(a.blades[e], np.maximum(L.delta - L.combined[e], 0.0) / max(L.delta, 1e-6), 0.0)
                ws.append(_stored(ndi.grey_dilation(wgt.astype(np.float32), size=3)))
            self.layer_masks.append(ms)
            self.layer_weights.append(ws)
            self.layer_under.append(us)
        # Whether each exemplar's layer stands out from the leaf under it as
        # the training leaf's does (lighter or darker: the median of its
        # ratio to the leaf under it, minus 1, of the training leaf's sign).
        # A layer of the other sign is another structure (dark dots induced
        # as a grass strip's pale veins): synthesis passes it over as a donor.
        self.layer_agrees = [self._agreement(k, cores[k]) for k in range(len(a.layers))]
        del cores
        # How complete each exemplar's induced layer is: its skeleton's
        # length over that of the training layer carried onto it (the
        # registered mask), at most 1, over the median of the exemplars'
        # (see synthesis: donors far below it are passed over). Only for the
        # most structural layer (largest lambda, the first on a tie): its
        # layout corresponds from leaf to leaf, so the carried training layer
        # predicts how much of it an exemplar has; spots do not (each leaf
        # has its own), and passing over the exemplars with fewer spots cost
        # procedural lobed leaves 0.03-0.05 of their Laplacian variance ratio.
        top_k = int(np.argmax([L.lam for L in a.layers])) if a.layers else -1
        self.layer_complete = [_completeness(L) if k == top_k else [1.0] * self.n
                               for k, L in enumerate(a.layers)]
        # The colours each layer takes in the exemplars (0.5th-99.5th
        # percentile per channel): a layer brought as contrast onto another
        # leaf stays inside them (a vein never darker than any exemplar's).
        # Within the exemplars' blade colours as well (their whole range:
        # the blade's own 0.5th-99.5th percentiles cut the layer's extremes
        # off whenever the layer is the blade's lightest or darkest part,
        # e.g. light veins covering more than 0.5 % of it: pasted veins lost
        # their crests, new leaves had 0.77-0.80 of the exemplars' Laplacian
        # variance on procedural families).
        blade_px = np.concatenate([np.asarray(a.exemplars[e], np.float32)[..., :3][a.blades[e]]
                                   for e in range(self.n)])
        b_lo, b_hi = np.percentile(blade_px, 0.5, axis=0), np.percentile(blade_px, 99.5, axis=0)
        self.blade_range = (b_lo.astype(np.float32), b_hi.astype(np.float32))
        b_min, b_max = blade_px.min(0), blade_px.max(0)
        self.layer_range = []
        for k, L in enumerate(a.layers):
            px = [np.asarray(a.residuals[k][e], np.float32)[..., :3][L.masks[e]] for e in range(self.n)]
            px = np.concatenate([x for x in px if len(x)] or [np.zeros((1, 3), np.float32)])
            lo = np.clip(np.percentile(px, 0.5, axis=0), b_min, b_max)
            hi = np.clip(np.percentile(px, 99.5, axis=0), lo, b_max)
            self.layer_range.append((lo.astype(np.float32), hi.astype(np.float32)))
        ident = np.stack([self.xx, self.yy], -1)
        # Training frame -> exemplar e, and exemplar e's frame -> training.
        self.to_exemplar = [ident if e == t else np.asarray(a.registrations[e].map_to_training, np.float32)
                            for e in range(self.n)]
        self.from_exemplar = [ident if e == t else np.asarray(a.registrations[e].map_from_training, np.float32)
                              for e in range(self.n)]
        self.pose_angles = [0.0] * self.n
        ys, xs = np.nonzero(a.blades[t])
        self.centre_t = np.array([xs.mean(), ys.mean()])
        self.shape_maps = [ident if e == t else self._upright_map(e) for e in range(self.n)]
        self.alpha_t = _soft_rim(a.exemplars[t][..., 3].astype(np.float32))
        self._prepare_petioles()
        errs = np.array(registration_errors(a), float)
        others = errs[np.arange(self.n) != t]
        others = others[np.isfinite(others)]
        self.registration_error = float(np.median(others)) if len(others) else 1.0
        # Bandwidth (Silverman's rule, 1.06 sigma n^-1/5) of the pose angle:
        # a new leaf's pose is one exemplar's turned by a Gaussian of it (a
        # smoothed bootstrap). Capped at 12 degrees: leaves lying across and
        # along the paper (grass strips at 0 and 90 degrees) gave 35 degrees
        # and strips at every slant between.
        silver = 1.06 * self.n ** -0.2 if self.n > 1 else 0.0
        ang = np.asarray(self.pose_angles, float)
        self.pose_bandwidth = float(min(silver * np.std(np.angle(np.exp(1j * (ang - ang.mean())))),
                                        np.radians(12.0)))
        # The same for the log lamina size (a new leaf's size is one
        # exemplar's times exp of a Gaussian of it), at most 10 %.
        ls = np.log(np.maximum(np.asarray(self.lamina_size, float), 1e-6))
        self.size_bandwidth = float(min(silver * np.std(ls), np.log(1.1))) if self.n > 1 else 0.0
        lams = np.array([L.lam for L in a.layers], float)
        top = float(lams.max()) if len(lams) and lams.max() > 0 else 1.0
        self.structural = [float(x / top) for x in lams]
        # One vein system (see own_lines): the background's own lines of the
        # most structural layer, found once per exemplar when first needed.
        self.leftover = leftover
        self._own = {}

    def _agreement(self, k: int, cores=None) -> list[bool]:
        """Per exemplar: layer ``k`` stands out from the leaf under it with the training leaf's sign.

        Read on ``cores[e]`` where given (the pasted mask without its faint
        ridge extension, whose pixels barely stand out), else on the pasted mask.
        """
        sign = []
        for e in range(self.n):
            core = None if cores is None else cores[e]
            mk = self.layer_masks[k][e] > 0.5 if core is None else core
            if not mk.any():
                sign.append(0.0)
                continue
            st = np.asarray(self.stage[k][e], np.float32)[mk].mean(-1)
            un = np.asarray(self.layer_under[k][e], np.float32)[mk].mean(-1)
            sign.append(float(np.sign(np.median(st / np.maximum(un, 0.02) - 1.0))))
        t = sign[self.analysis.training_index]
        return [t == 0 or s_e == t for s_e in sign]

    def _upright_map(self, e: int) -> np.ndarray:
        """Exemplar ``e``'s map to the training frame, seen in the training leaf's pose.

        ``from_exemplar[e](P_e(y))`` with ``P_e`` the rigid part (rotation
        about the blade centroid) taking the training pose to exemplar
        ``e``'s: the least-squares rotation (Kabsch) of the whole map over
        the training blade. (The start map's rotation is not that: on a
        palmate leaf the start may sit a lobe away, about 47 degrees off
        on a procedural family, which the spline then turns back; blending
        such an "upright" map with the others gave malformed lobes.)
        Leaves photographed at different angles (a strip lying across the
        paper, another along it) give maps that agree up to their non-rigid
        part and their size, so their convex blend is a leaf shape; blending
        the raw maps mixed a rotation with its opposite and
        swirled the blade into blobs. Size differences stay (they are shape
        variation).
        """
        field = self.from_exemplar[e]
        ys, xs = np.nonzero(self.analysis.blades[self.analysis.training_index])
        step = max(1, len(xs) // 20000)
        y = np.column_stack([xs[::step], ys[::step]]).astype(np.float64)
        z = field[ys[::step], xs[::step]].astype(np.float64)
        c_t, c_e = y.mean(0), z.mean(0)
        u, _, vt = np.linalg.svd((z - c_e).T @ (y - c_t))
        if np.linalg.det(u @ vt) < 0:  # a rotation, never a reflection
            u[:, -1] *= -1
        to_exemplar = u @ vt  # rotation of the map: training pose -> exemplar pose
        # The exemplar's pose relative to the training leaf's (radians).
        self.pose_angles[e] = -float(np.arctan2(to_exemplar[1, 0], to_exemplar[0, 0]))
        rot = to_exemplar
        # About the training centroid, the centre `posed` turns about, so a
        # blend of one exemplar gives back its own map.
        return _remap_map(self.from_exemplar[e], _affine_grid(self.shape, rot.T, self.centre_t))

    def posed(self, upright: np.ndarray, weights, offset: float = 0.0) -> np.ndarray:
        """The blended upright map turned to the exemplars' mean pose (circular mean, ``weights``).

        New leaves lie as the exemplars that made them lie, like the blend
        of the raw maps for leaves photographed at nearly one angle; but
        the angles are averaged as angles, so a leaf across the paper and
        one along it give a leaf at 45 degrees, not a swirl. (The pose of
        the exemplar weighing most instead tilted new maples by their
        donors' few degrees and turned their petioles askew.)
        """
        w = np.asarray(weights, float)
        ang = np.asarray(self.pose_angles)
        theta = float(np.arctan2((w * np.sin(ang)).sum(), (w * np.cos(ang)).sum())) + float(offset)
        if abs(theta) < 1e-6:
            return upright
        c, s = np.cos(theta), np.sin(theta)
        back = np.array([[c, s], [-s, c]])  # rotation by -theta: output pose -> upright frame
        return _remap_map(upright, _affine_grid(self.shape, back, self.centre_t))

    def source_detail(self, e: int) -> np.ndarray:
        """Exemplar ``e``'s background detail for texture correction (cached; see ``correction._correct``)."""
        cache = self.__dict__.setdefault("_details", {})
        if e not in cache:
            from .correction import _detail
            sigma = max(8, min(self.shape) // 24) / 2.0
            cache[e] = _detail(self.stage[-1][e], self.analysis.blades[e], sigma)
        return cache[e]

    def compatible(self, lead: int, limit: float) -> np.ndarray:
        """Which exemplars' upright shape maps lie within ``limit`` leaf sizes of exemplar ``lead``'s.

        The distance is the median over the training blade of the distance
        between the two maps (cached per analysis), over the leaf size.
        """
        if getattr(self, "_map_dist", None) is None:
            b = self.analysis.blades[self.analysis.training_index]
            step = max(1, int(np.sqrt(b.sum() / 4000)))
            pts = [mp[::step, ::step][b[::step, ::step]] for mp in self.shape_maps]
            self._map_dist = np.array([[np.median(np.hypot(*(pts[i] - pts[j]).T)) / self.size
                                        for j in range(self.n)] for i in range(self.n)])
        return self._map_dist[lead] <= limit

    def carried_anisotropy(self, e: int, m: np.ndarray, blade: np.ndarray) -> float:
        """How much more exemplar ``e`` is stretched one way than across to cover the new blade of ``m``.

        The median over ``blade`` (output frame) of ``log sqrt(s1 / s2)``,
        ``s1 >= s2`` the singular values of the Jacobian of ``W_e^-1(m(y))``
        (exemplar pixels per output pixel): 0 for any similarity,
        ``log(k) / 2`` for a stretch ``k`` one way only (a narrow grass
        strip's layer spread over a wide one's shape). Taken on a grid of
        about 48 steps across the leaf.
        """
        step = max(1, int(self.size // 48))
        sub = np.ascontiguousarray(m[::step, ::step])
        inside = np.asarray(blade, bool)[::step, ::step]
        if inside.sum() < 4 or min(sub.shape[:2]) < 3:
            return 0.0
        c = _remap_values(self.to_exemplar[e], sub).astype(np.float64)
        jx = np.gradient(c, axis=1) / step  # d(source)/dx: columns of the Jacobian
        jy = np.gradient(c, axis=0) / step
        sv = np.linalg.svd(np.stack([jx[inside], jy[inside]], -1), compute_uv=False)
        ls = np.log(np.maximum(sv, 1e-6))
        return float(np.median(0.5 * (ls[:, 0] - ls[:, 1])))

    def own_lines(self, e: int):
        """``(labels, filled)`` of exemplar ``e``'s background (:func:`branchnb.leaves.leftover.own_lines`).

        None on drawn leaves (their background keeps no ink) or without a
        structural layer. The reference strength of an exemplar without
        the layer is the median of the others'.
        """
        if self.leftover is None or self.flat is not None:
            return None
        if e not in self._own:
            a = self.analysis
            top, sign, width = self.leftover
            L = a.layers[top]
            ref = None
            if not np.asarray(L.masks[e]).any():
                refs = [layer_strength(a.residuals[top][j], np.asarray(L.masks[j], bool) & a.blades[j], sign, width)
                        for j in range(self.n) if np.asarray(L.masks[j]).any()]
                ref = float(np.median(refs)) if refs else 0.0
            lab, filled, _ = own_lines(np.asarray(self.stage[-1][e], np.float32), a.blades[e],
                                       a.residuals[top][e], L.masks[e], sign, width, ref_level=ref)
            self._own[e] = (lab, _stored(filled)) if lab.any() else (None, None)
        lab, filled = self._own[e]
        return None if lab is None else (lab, filled)

    def beside_lines(self, bg: int, c_bg: np.ndarray, footprint: np.ndarray, blade: np.ndarray, reach: float):
        """New-leaf pixels of background ``bg``'s own lines beside ``footprint`` (None: none).

        :func:`branchnb.leaves.leftover.parallel_lines` of the background
        exemplar's lines (:meth:`own_lines`) carried into the new leaf by
        its coordinates ``c_bg``, inside ``blade``.
        """
        own = self.own_lines(bg)
        if own is None or not footprint.any():
            return None
        lab = cv2.remap(own[0].astype(np.float32), np.ascontiguousarray(c_bg[..., 0], np.float32),
                        np.ascontiguousarray(c_bg[..., 1], np.float32), cv2.INTER_NEAREST,
                        borderMode=cv2.BORDER_CONSTANT, borderValue=0).astype(np.int32)
        lab[~blade] = 0
        gone = parallel_lines(lab, footprint, reach, width=self.leftover[2])
        return gone if gone.any() else None

    def source_coords(self, e: int, m: np.ndarray, disp: np.ndarray) -> np.ndarray:
        """Exemplar ``e`` pixel for every output pixel: ``W_e^-1(m(y) + d(m(y)))`` (maps composed, one resampling)."""
        q = m + _remap_values(disp, m)
        return _remap_values(self.to_exemplar[e], q)


_CACHE_KEY = "_synthesis_prepared"


def _prepared(analysis) -> _Prepared:
    p = getattr(analysis, _CACHE_KEY, None)
    if p is None or p.analysis is not analysis:
        p = _Prepared(analysis)
        object.__setattr__(analysis, _CACHE_KEY, p)
    return p
