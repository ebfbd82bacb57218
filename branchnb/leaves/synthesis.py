"""Layered synthesis of new leaves (Assa & Cohen-Or 2012, section 5).

A new leaf is built in the training leaf's frame, then given a new shape:

1. **Background**: the residual (every layer removed) of one exemplar,
   brought into the training frame by its registration and moved by a
   small smooth random warp whose magnitude stays below the registration
   error (``background_warp`` times the median registration error), so
   the warp adds variation the registration could not tell from noise.
2. **Layers**, bottom first: each from another exemplar (the image at the
   stage where that layer was induced, i.e. with the layers above it
   removed), with its own smooth random warp: the background's plus
   ``layer_warp * eps`` scaled by ``1 - lambda_c / max lambda``, so the
   most structural layer (veins, largest ``lambda``) moves no more than
   the background and a colour layer (spots, ``lambda ~ 0``) the most.
   Each layer covers the warped induced mask (bilinear, so edges stay
   anti-aliased); where several cover a pixel their colours are mixed
   with the per-pixel weights ``delta_c - D_c`` normalised to sum 1.
   With ``layer_colour="contrast"`` (the default) a layer brings its
   ratio to its own leaf without it (its residual), per channel, rather
   than its colours: autumn leaves of one kind differ in overall hue (yellow,
   orange), and copied colours turn a yellow leaf's veins into yellow
   stripes on an orange one. ``"copy"`` pastes the colours as the paper does.
3. **Shape**: a convex per-pixel blend of the inverse registration warps,
   ``W^-1(x) = sum_i a_i(x) W_i^-1(x)``, each seen in the training leaf's
   pose (its start map's rotation taken out), the blend then turned to the
   pose of one exemplar drawn at random (leaves lying at different angles
   blend into a leaf, not a swirl). ``a_i`` (:func:`shape_weights`): per
   leaf one draw from a symmetric Dirichlet of ``shape_concentration`` (a
   few exemplars dominate each leaf), times a ``shape_grid`` x
   ``shape_grid`` grid of random factors (``shape_spread``), smoothed by a
   Gaussian of ``shape_sigma`` times the leaf size and normalised per
   pixel. Going beyond the paper: independent random weights per pixel
   average every leaf to the mean shape, and a convex blend averages the
   sizes, so with ``own_size`` each leaf takes the size of one exemplar
   drawn at random (that exemplar also gives the background, seen at its
   own scale) and is kept whole on the canvas. Measured with
   ``generate(a, 16)`` on 5-leaf families (lobed, trilobed, elliptic,
   256 px) and 5 photographed maples: median pairwise blade IoU of new
   leaves 0.50-0.56 against the exemplars' 0.51-0.54 (maples 0.64-0.72
   against 0.63; 0.86 with per-cell weights).
4. **Texture correction** where the composed warp stretches or squeezes
   (:func:`branchnb.leaves.correction.correct_texture`), applied to the
   background before the layers go on (so no vein or spot is replaced by
   plain texture), and the alpha of the training leaf's lamina carried by
   the shape warp. All maps are composed first, so every image is
   resampled once.
5. **Petiole**: the registration is of the laminae (a petiole bends and
   varies in length from leaf to leaf), so instead of the training leaf's
   petiole carried by the shape warp, a new leaf gets one exemplar's own
   petiole (:func:`branchnb.leaves.registration.split_petiole`), placed at
   the new leaf's base by the rotation and scale relating that exemplar's
   frame to the new leaf's there, under the lamina.

6. **Drawn leaves** (going beyond the paper, which works on photographs):
   when :func:`branchnb.leaves.flatart.flat_art` finds the exemplars are
   clip art (an ink rim around most of every blade, a fill of few
   colours), the outline is not texture. It is removed from every stage
   image and drawn anew along the new blade's own boundary in the
   exemplars' median width and colour; the background keeps no ink of
   its own (strokes the induction missed stayed beside the donor's: two
   vein systems); a donor layer brings whole ink strokes (its mask followed
   through the ink it touches); colours are snapped to the exemplars'
   palette (hard-edged art) or to mixtures of two of its colours
   (anti-aliased art); and the alpha is cut at 0.5 (a soft fringe of fill
   outside the outline was a halo). Measured on drawn families (lobed,
   trilobed, elliptic; 256-512 px; 1-3 px outlines; four fills), 4 new
   leaves each: share of the new blade's boundary with outline ink
   0.11-0.96 -> 1.00 (exemplars 1.00); fill or grey in the 3 px ring
   outside 33-38 % -> 0 %; ridge response at the background's own moved
   veins (0 plain blade, 1 a pasted vein) 0.04-0.40 -> 0.00; Laplacian
   variance 5 px inside the outline 0.44-0.55 -> 1.12-1.20 of the
   exemplars'. Photographs are untouched (same pixels).

Every leaf keeps the seed that made it, the exemplars it used and the mean
shape weights; :func:`save_leaves` writes RGBA PNGs and a strict-JSON record.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.image import extend_nearest
from ..core.io import encode_png
from ..core.jsonio import dumps_strict
from ..core.params import check_params, param
from ..core.random import as_rng
from ..core.validate import check_callback
from ..core.warp import remap
from .flatart import drawn_outline, flat_art

__all__ = ["SynthesisParams", "GeneratedLeaf", "generate", "generate_leaf", "save_leaves",
           "random_warp", "shape_weights", "registration_errors", "leaf_distance",
           "colour_range_fraction"]


@dataclass
class SynthesisParams:
    """Layered-synthesis parameters (Assa & Cohen-Or 2012, section 5; see :mod:`branchnb.leaves.synthesis`).

    Parameters
    ----------
    background_warp : float
        Largest displacement of the background's random warp, as a fraction
        of the median registration error (default 0.5; kept below 1 so the
        warp stays within what the registration cannot tell from noise).
    layer_warp : float
        Extra warp of a layer, in units of its ``eps`` (the spatial
        tolerance), scaled by ``1 - lambda_c / max lambda`` (default 0.5):
        structural layers (large ``lambda``) move least.
    warp_scale : float
        Correlation length of the random warps, as a fraction of the leaf
        size (default 0.25).
    shape_grid : int
        Random shape coefficients per side and exemplar (default 3; 1: one
        blend over the whole leaf).
    shape_sigma : float
        Gaussian blur of the shape coefficients, as a fraction of the leaf
        size (default 0.15).
    shape_concentration : float
        Symmetric Dirichlet concentration of each leaf's exemplar weights
        (default 0.3; small: one or two exemplars dominate). Not in the paper.
    shape_spread : float
        Coefficient of variation of the per-cell shape factors (default
        0.75; 0: one blend everywhere). Not in the paper.
    own_size : bool
        Each new leaf takes the size of one exemplar drawn at random
        (default True; False: the convex blend's averaged size). Not in the paper.
    correct : bool
        Texture correction where the shape warp stretches or squeezes
        (default True).
    layer_colour : {"contrast", "copy"}
        A layer brings its ratio to its own residual leaf (``"contrast"``,
        default; not in the paper) or pastes its colours (``"copy"``, the paper).
    """

    background_warp: float = param(0.5, min=0.0, max=1.0, step=0.05,
                                   help="background warp, as a fraction of the registration error (< 1)")
    layer_warp: float = param(0.5, min=0.0, max=3.0, step=0.05,
                              help="extra warp of non-structural layers, in units of eps")
    warp_scale: float = param(0.25, min=0.05, max=1.0, step=0.05,
                              help="correlation length of the random warps (fraction of the leaf size)")
    shape_grid: int = param(3, min=1, max=8, help="random shape coefficients per side and exemplar")
    shape_sigma: float = param(0.15, min=0.02, max=2.0, step=0.01,
                               help="Gaussian blur of the shape coefficients (fraction of the leaf size)")
    shape_concentration: float = param(0.3, min=0.05, max=10.0, step=0.05,
                                       help="per-leaf Dirichlet concentration (small: one exemplar dominates)")
    shape_spread: float = param(0.75, min=0.0, max=2.0, step=0.05,
                                help="variation of the shape weights over the leaf (0: one blend everywhere)")
    own_size: bool = param(True, help="each new leaf is as large as one exemplar drawn at random")
    correct: bool = param(True, help="texture correction where the shape warp stretches")
    layer_colour: str = param("contrast", options=("contrast", "copy"),
                              help="a layer brings its contrast to its own leaf (contrast) or its colours (copy)")


@dataclass
class GeneratedLeaf:
    """One synthesised leaf.

    Parameters
    ----------
    image : (H, W, 4) float32 ndarray
        RGBA.
    seed : int
        :func:`generate_leaf` with this seed gives the same leaf again.
    background : int
        Exemplar whose residual is the background.
    layers : dict of str -> int
        Exemplar each layer came from.
    shape_weights : list of float
        Mean ``a_i`` of each exemplar over the leaf.
    warps : dict of str -> float
        Maximum displacement (px) of each random warp (``"background"`` and one per layer).
    petiole : int
        Exemplar whose own petiole the leaf got (-1: no petiole was found
        on the training leaf or the exemplars; the shape warp then carries
        the training leaf's).
    """

    image: np.ndarray
    seed: int
    background: int
    layers: dict
    shape_weights: list
    warps: dict = field(default_factory=dict)
    petiole: int = -1

    @property
    def blade(self) -> np.ndarray:
        return self.image[..., 3] > 0.5

    def on_white(self) -> np.ndarray:
        a = self.image[..., 3:]
        return (self.image[..., :3] * a + (1 - a)).astype(np.float32)

    def record(self) -> dict:
        return {"seed": int(self.seed), "background": int(self.background),
                "layers": {k: int(v) for k, v in self.layers.items()},
                "shape_weights": [round(float(w), 6) for w in self.shape_weights],
                "warps": {k: round(float(v), 4) for k, v in self.warps.items()},
                "petiole": int(self.petiole)}

    def _repr_png_(self) -> bytes:
        return encode_png(self.on_white())


def random_warp(shape, amplitude: float, correlation: float, rng) -> np.ndarray:
    """A smooth random displacement field (H, W, 2) whose largest displacement is ``amplitude`` px.

    Random vectors on a grid of spacing ``correlation`` px, interpolated
    bicubically.

    Parameters
    ----------
    shape : (int, int)
        ``(H, W)`` of the field.
    amplitude : float
        Largest displacement length in pixels, ``>= 0`` (0: no warp).
    correlation : float
        Grid spacing of the random vectors in pixels, ``> 0``: the length
        over which displacements are alike.
    rng : {numpy.random.Generator, int}
        Draws the random vectors.

    Returns
    -------
    (H, W, 2) float32 ndarray
        Displacement ``(dx, dy)`` per pixel.

    Examples
    --------
    >>> d = random_warp((40, 50), 2.0, 20.0, 0)
    >>> d.shape, round(float(np.hypot(d[..., 0], d[..., 1]).max()), 3)
    ((40, 50, 2), 2.0)
    """
    rng = as_rng(rng)
    h, w = int(shape[0]), int(shape[1])
    if not (np.isfinite(amplitude) and amplitude >= 0):
        raise ValueError(f"amplitude must be finite and >= 0, got {amplitude}")
    if not (np.isfinite(correlation) and correlation > 0):
        raise ValueError(f"correlation must be > 0, got {correlation}")
    gh = max(2, int(np.ceil(h / correlation)) + 1)
    gw = max(2, int(np.ceil(w / correlation)) + 1)
    coarse = rng.standard_normal((gh, gw, 2)).astype(np.float32)
    d = cv2.resize(coarse, (w, h), interpolation=cv2.INTER_CUBIC)
    m = float(np.hypot(d[..., 0], d[..., 1]).max())
    if amplitude == 0 or m == 0:
        return np.zeros((h, w, 2), np.float32)
    return (d * np.float32(amplitude / m)).astype(np.float32)


def shape_weights(shape, n: int, grid: int, sigma_px: float, rng, concentration: float = 0.3,
                  spread: float = 0.75) -> np.ndarray:
    """Per-pixel convex weights ``a_i(x)`` (n, H, W): random coefficients, blurred, normalised.

    One draw per leaf decides which exemplars its shape comes from: global
    weights ``g ~ Dirichlet(concentration)`` (small concentration: one or
    two exemplars dominate). Each of the ``grid`` x ``grid`` cells then
    multiplies them by its own Gamma noise of mean 1 and coefficient of
    variation ``spread`` (so the weights vary smoothly over the leaf), and
    the coefficients are blurred by a Gaussian of ``sigma_px`` and
    normalised per pixel.

    Going beyond the paper: a Dirichlet drawn independently per cell (as a
    literal reading of "random convex weights per pixel" suggests), once
    blurred, averages nearly evenly over all exemplars at every pixel, so
    every new leaf came out close to the mean shape (median pairwise
    blade IoU 0.86 among new maples against the exemplars' 0.63).

    Parameters
    ----------
    shape : (int, int)
        ``(H, W)`` of the fields.
    n : int
        Number of exemplars.
    grid : int
        Random coefficients per side.
    sigma_px : float
        Blur of the coefficients (px).
    rng : {numpy.random.Generator, int}
        Draws the per-leaf weights and the per-cell factors.
    concentration : float
        Symmetric Dirichlet concentration of the per-leaf weights.
    spread : float
        Coefficient of variation of the per-cell factors (0: the same
        weights everywhere).

    Returns
    -------
    (n, H, W) float32 ndarray
        Non-negative, summing to 1 at every pixel.

    Examples
    --------
    >>> a = shape_weights((30, 30), 3, 2, 5.0, 0)
    >>> a.shape, bool(np.allclose(a.sum(0), 1)), bool(a.min() >= 0)
    ((3, 30, 30), True, True)
    """
    rng = as_rng(rng)
    h, w = int(shape[0]), int(shape[1])
    if not (np.isfinite(concentration) and concentration > 0):
        raise ValueError(f"concentration must be > 0, got {concentration}")
    if not (np.isfinite(spread) and spread >= 0):
        raise ValueError(f"spread must be >= 0, got {spread}")
    g = rng.dirichlet(np.full(n, float(concentration)))
    g = np.maximum(np.nan_to_num(g, nan=0.0), 0.0)
    if g.sum() <= 0:  # a degenerate draw (all alphas tiny): one exemplar
        g = np.eye(n)[int(rng.integers(n))]
    g = g / g.sum()
    if spread > 0:
        k = 1.0 / float(spread) ** 2
        noise = rng.gamma(k, 1.0 / k, size=(grid, grid, n))
    else:
        noise = np.ones((grid, grid, n))
    coeff = (g * noise).astype(np.float32)  # (g, g, n)
    coeff /= np.maximum(coeff.sum(-1, keepdims=True), 1e-12)
    # The fields are smooth: blur on a reduced grid, then interpolate up.
    f = max(1, int(sigma_px // 4))
    hs, ws = max(2, int(np.ceil(h / f))), max(2, int(np.ceil(w / f)))
    out = np.empty((n, h, w), np.float32)
    for i in range(n):
        c = cv2.resize(coeff[..., i], (ws, hs), interpolation=cv2.INTER_LINEAR)
        c = cv2.GaussianBlur(c, (0, 0), max(float(sigma_px) / f, 0.5), borderType=cv2.BORDER_REFLECT)
        out[i] = cv2.resize(c, (w, h), interpolation=cv2.INTER_LINEAR)
    out = np.maximum(out, 0)
    out /= np.maximum(out.sum(0, keepdims=True), 1e-12)
    return out


def _remove(img: np.ndarray, blade: np.ndarray, remove: np.ndarray) -> np.ndarray:
    """``img`` with ``remove`` (grown by one pixel) given the nearest other blade colour."""
    gone = ndi.binary_dilation(remove) & blade
    keep = blade & ~gone
    if not gone.any() or not keep.any():
        return img
    out = img.copy()
    out[gone] = extend_nearest(img, keep)[gone]
    return out


def _bleed(img: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Colours of ``mask`` extended outwards (nearest mask pixel), so warps never pull in the backdrop."""
    return extend_nearest(img, mask)


def _grid(shape):
    h, w = shape
    xx, yy = np.meshgrid(np.arange(w, dtype=np.float32), np.arange(h, dtype=np.float32))
    return xx, yy


def _boundary(mask):
    return mask & ~ndi.binary_erosion(mask)


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


class _Prepared:
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

        def stage_image(k, e):
            img = np.asarray(a.residuals[k][e], np.float32)
            if fa is not None:
                # No outline in any stage (it is drawn anew along the new
                # blade), and no ink at all in the background: ink the
                # induction missed stayed beside the donor's veins.
                img = fa.clean(img, a.blades[e], fa.ink[e] if k == last else fa.outline[e])
            elif outlines[e].any():
                # An ink outline around a leaf that is not flat art (a
                # gradient-filled drawing) is taken out too (drawn_outline).
                img = _remove(img, a.blades[e], outlines[e])
            return _bleed(img, a.blades[e])

        outlines = [drawn_outline(a.exemplars[e], a.blades[e]) if fa is None else None for e in range(self.n)]

        # Stage k image of exemplar e (layers above k removed), bled outside the blade.
        self.stage = [[stage_image(k, e) for e in range(self.n)] for k in range(len(a.residuals))]
        # What a layer's contrast is taken against: the next stage, without
        # any ink on drawn leaves (a stroke the induction missed is still in
        # the next stage, so its ratio was 1 and the pasted vein had gaps).
        self.under = [[_bleed(fa.clean(np.asarray(a.residuals[k][e], np.float32), a.blades[e], fa.ink[e]),
                              a.blades[e]) for e in range(self.n)] if fa is not None and 0 < k < last
                      else self.stage[k] for k in range(len(a.residuals))]
        # Layer masks grown by the pixel the residual also removed: the
        # exemplar's own anti-aliased rim comes back with the layer.
        self.layer_masks, self.layer_weights = [], []
        for L in a.layers:
            ms, ws = [], []
            for e in range(self.n):
                mk = L.masks[e]
                if fa is not None and mk.any():
                    # Whole strokes: the ink the layer's mask touches, followed
                    # through the ink (not the outline, drawn anew).
                    strokes = fa.ink[e] & ~fa.outline[e]
                    mk = (mk | ndi.binary_propagation(mk & strokes, mask=strokes)) & ~fa.outline[e]
                ms.append(ndi.binary_dilation(mk).astype(np.float32) * a.blades[e])
                wgt = np.where(a.blades[e], np.maximum(L.delta - L.combined[e], 0.0) / max(L.delta, 1e-6), 0.0)
                ws.append(ndi.grey_dilation(wgt.astype(np.float32), size=3))
            self.layer_masks.append(ms)
            self.layer_weights.append(ws)
        # The colours each layer takes in the exemplars (0.5th-99.5th
        # percentile per channel): a layer brought as contrast onto another
        # leaf stays inside them (a vein never darker than any exemplar's).
        # Within the exemplars' blade colours as well (same percentiles).
        blade_px = np.concatenate([np.asarray(a.exemplars[e], np.float32)[..., :3][a.blades[e]]
                                   for e in range(self.n)])
        b_lo, b_hi = np.percentile(blade_px, 0.5, axis=0), np.percentile(blade_px, 99.5, axis=0)
        self.blade_range = (b_lo.astype(np.float32), b_hi.astype(np.float32))
        self.layer_range = []
        for k, L in enumerate(a.layers):
            px = [np.asarray(a.residuals[k][e], np.float32)[..., :3][L.masks[e]] for e in range(self.n)]
            px = np.concatenate([x for x in px if len(x)] or [np.zeros((1, 3), np.float32)])
            lo = np.clip(np.percentile(px, 0.5, axis=0), b_lo, b_hi)
            hi = np.clip(np.percentile(px, 99.5, axis=0), lo, b_hi)
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
        self.alpha_t = a.exemplars[t][..., 3].astype(np.float32)
        self._prepare_petioles()
        errs = np.array(registration_errors(a), float)
        others = errs[np.arange(self.n) != t]
        others = others[np.isfinite(others)]
        self.registration_error = float(np.median(others)) if len(others) else 1.0
        lams = np.array([L.lam for L in a.layers], float)
        top = float(lams.max()) if len(lams) and lams.max() > 0 else 1.0
        self.structural = [float(x / top) for x in lams]

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
        q = (np.stack([self.xx, self.yy], -1).astype(np.float64) - self.centre_t) @ rot + self.centre_t
        return _remap_map(self.from_exemplar[e], q.astype(np.float32))

    def posed(self, upright: np.ndarray, weights) -> np.ndarray:
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
        theta = float(np.arctan2((w * np.sin(ang)).sum(), (w * np.cos(ang)).sum()))
        if abs(theta) < 1e-6:
            return upright
        c, s = np.cos(theta), np.sin(theta)
        back = np.array([[c, s], [-s, c]])  # rotation by -theta: output pose -> upright frame
        q = (np.stack([self.xx, self.yy], -1).astype(np.float64) - self.centre_t) @ back.T + self.centre_t
        return _remap_map(upright, q.astype(np.float32))

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
        # Each exemplar's size: the square root of its lamina's area.
        self.lamina_size = [float(np.sqrt(split_petiole(b)[0].sum())) for b in a.blades]
        _, pet_t, base_t = split_petiole(a.blades[t])
        self.base_t = base_t
        if base_t is not None:
            rim = ndi.binary_dilation(pet_t, iterations=2) & ~ndi.binary_erosion(
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
            img = np.asarray(a.exemplars[e], np.float32).copy()
            keep = ndi.binary_dilation(pet, iterations=2)
            img[..., 3] *= keep
            self.petiole_rgba.append(img)
            self.petiole_base.append(base)
            self.petiole_jac.append(_map_jacobian(self.from_exemplar[e], base))
        self.petiole_exemplars = [e for e in range(self.n) if self.petiole_rgba[e] is not None]

    def petiole_layer(self, e: int, m: np.ndarray):
        """Exemplar ``e``'s petiole (RGBA) in the output frame of the shape map ``m``, or None.

        The new leaf's base ``y_b`` is where ``m`` reaches the training
        base; the petiole is moved there by the similarity (the rotation and
        scale of the polar decomposition) of ``J_m(y_b)^-1 J_e(base_e)``:
        how exemplar ``e``'s frame relates to the new leaf's at the base.
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
        sim = rot * float(np.sqrt(sv.prod()))
        inv = np.linalg.inv(sim)
        q = (np.stack([self.xx, self.yy], -1) - yb) @ inv.T + self.petiole_base[e]
        return _sample(self.petiole_rgba[e], q.astype(np.float32))

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


def _map_jacobian(field: np.ndarray, point) -> np.ndarray:
    """2 x 2 Jacobian of a dense coordinate map ``field`` (H, W, 2) at ``point`` (x, y), by central differences."""
    h, w = field.shape[:2]
    x, y = float(point[0]), float(point[1])
    step = 3.0
    pts = np.array([[x + step, y], [x - step, y], [x, y + step], [x, y - step]], np.float32)
    pts[:, 0] = np.clip(pts[:, 0], 0, w - 1)
    pts[:, 1] = np.clip(pts[:, 1], 0, h - 1)
    v = _remap_values(field, pts[None])[0]
    dx = (v[0] - v[1]) / max(float(pts[0, 0] - pts[1, 0]), 1e-6)
    dy = (v[2] - v[3]) / max(float(pts[2, 1] - pts[3, 1]), 1e-6)
    return np.column_stack([dx, dy]).astype(np.float64)


def _linear_part(field: np.ndarray) -> np.ndarray:
    """The 2 x 2 linear part of the least-squares affine fit of a coordinate map (H, W, 2)."""
    h, w = field.shape[:2]
    step = max(1, int(np.sqrt(h * w / 4096)))
    ys, xs = np.mgrid[0:h:step, 0:w:step]
    src = np.column_stack([xs.ravel(), ys.ravel(), np.ones(xs.size)]).astype(np.float64)
    dst = field[::step, ::step].reshape(-1, 2).astype(np.float64)
    coef, *_ = np.linalg.lstsq(src, dst, rcond=None)
    return coef[:2].T


def _remap_map(field, c):
    """A coordinate map resampled at ``c``, continued past the canvas by its affine fit.

    Off the canvas the map is its edge value plus the fit's linear part
    times the step beyond the edge, so far points keep going away (the
    replicated edge value drew straight streaks from a leaf to the canvas
    edge). A sentinel "off" value instead was blended into other maps with
    a small weight, and bilinearly into its neighbours, giving finite
    coordinates that landed on the lamina: stray fragments of leaf far
    from the new one.
    """
    h, w = field.shape[:2]
    c = np.asarray(c, np.float32)
    inside = np.empty_like(c)
    inside[..., 0] = np.clip(c[..., 0], 0, w - 1)
    inside[..., 1] = np.clip(c[..., 1], 0, h - 1)
    out = _remap_values(field, inside)
    beyond = c - inside
    if np.any(beyond):
        out = out + (beyond @ _linear_part(field).T.astype(np.float32))
    return out.astype(np.float32)


def _remap_values(field, c):
    """Bilinear samples of any float field (coordinates, displacements) at ``c``; edges replicated."""
    out = cv2.remap(np.ascontiguousarray(field, np.float32), np.ascontiguousarray(c[..., 0]),
                    np.ascontiguousarray(c[..., 1]), cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    return out


def _sample(img, c):
    return remap(img, c[..., 0], c[..., 1])[0]


def _sample_sharp(img, c):
    """Colours sampled bicubically (clipped to [0, 1]).

    Bilinear resampling at fractional offsets averages neighbours: a new
    leaf came out with half its exemplars' high-frequency energy
    (Laplacian variance inside the blade 0.49 of theirs on a 384 px
    procedural family). Bicubic keeps veins and texture crisp.
    """
    img = np.ascontiguousarray(img, np.float32)
    out = cv2.remap(img, np.ascontiguousarray(c[..., 0], np.float32), np.ascontiguousarray(c[..., 1], np.float32),
                    cv2.INTER_LANCZOS4, borderMode=cv2.BORDER_REPLICATE)
    if out.ndim == 2:
        out = out[..., None]
    return np.clip(out, 0.0, 1.0)


def _sample_sharp_at(img, c, where):
    """:func:`_sample_sharp` at the pixels of ``where`` only (0 elsewhere).

    The same values where computed (remapping is per pixel), at the cost
    of the pixels that are used: the blade, a layer's footprint. Lanczos
    resampling of every channel over the whole canvas was half the time of
    a new leaf at a megapixel.
    """
    img = np.ascontiguousarray(img, np.float32)
    ch = img.shape[2] if img.ndim == 3 else 1
    out = np.zeros(where.shape + (ch,), np.float32)
    idx = np.flatnonzero(where)
    if idx.size == 0:
        return out
    # The picked coordinates as a (rows, 1024) map (OpenCV maps are < 32767 on a side), padded.
    n = idx.size
    rows = -(-n // 1024)
    maps = []
    for i in (0, 1):
        v = np.zeros(rows * 1024, np.float32)
        v[:n] = c[..., i].reshape(-1)[idx]
        maps.append(v.reshape(rows, 1024))
    vals = cv2.remap(img, maps[0], maps[1], cv2.INTER_LANCZOS4, borderMode=cv2.BORDER_REPLICATE)
    out.reshape(-1, ch)[idx] = np.clip(vals.reshape(-1, ch)[:n], 0.0, 1.0)
    return out


def _border_alpha(alpha: np.ndarray) -> float:
    """Opacity on the canvas border (0: nothing is cut by the canvas edge)."""
    return float(alpha[0].sum() + alpha[-1].sum() + alpha[:, 0].sum() + alpha[:, -1].sum())


def _fit_size(p, m, size_from: int, shrink: float = 1.0) -> np.ndarray:
    """The shape map ``m`` scaled (to one exemplar's size) and moved so the lamina stays on the canvas.

    Going beyond the paper: a convex blend of warps averages the
    exemplars' sizes, so new leaves came out nearly one size (size is most
    of the variation among photographed maples: pairwise blade IoU 0.78
    among new leaves against the exemplars' 0.63). With ``size_from >= 0``
    the blend gives the shape and the size (square root of the lamina's
    area) is that of exemplar ``size_from`` (-1: the blend's size). A
    leaf that would then cross the canvas edge (a large exemplar's size on
    the training leaf's place) is moved inwards, and shrunk only if it
    cannot fit; ``shrink`` scales it further (room for a
    petiole).
    """
    # The lamina on a coarse grid reaching half a canvas past each edge
    # (the map continues past the canvas), so a leaf the canvas already
    # cuts is measured whole.
    h, w = p.shape
    st = max(1.0, p.size / 100.0)
    gx = np.arange(-0.5 * w, 1.5 * w, st, dtype=np.float32)
    gy = np.arange(-0.5 * h, 1.5 * h, st, dtype=np.float32)
    gxx, gyy = np.meshgrid(gx, gy)
    mc = _remap_map(m, np.stack([gxx, gyy], -1))
    lam = _remap_values(p.alpha_t, mc)
    lam = np.where((mc[..., 0] >= 0) & (mc[..., 0] <= w - 1) & (mc[..., 1] >= 0) & (mc[..., 1] <= h - 1), lam, 0.0)
    inside = lam > 0.5
    if not inside.any():
        return m
    area = float(lam.sum()) * st * st
    k = 1.0
    if size_from >= 0 and p.lamina_size[size_from] > 0:
        k = p.lamina_size[size_from] / np.sqrt(area)
    ctr = np.array([(lam * gxx).sum(), (lam * gyy).sum()]) / float(lam.sum())
    lo = np.array([gxx[inside].min(), gyy[inside].min()], float)
    hi = np.array([gxx[inside].max(), gyy[inside].max()], float)
    margin = 2.0 + 0.02 * p.size
    room = np.array([w - 1.0, h - 1.0]) - 2 * margin
    ext = np.maximum(hi - lo, 1.0)
    k = float(min(k, *(room / ext))) if np.all(room > 0) else k
    k *= float(shrink)
    lo_k, hi_k = ctr + (lo - ctr) * k, ctr + (hi - ctr) * k
    shift = np.maximum(margin - lo_k, 0.0) - np.maximum(hi_k - (np.array([w - 1.0, h - 1.0]) - margin), 0.0)
    if abs(k - 1.0) < 1e-6 and not np.any(shift):
        return m
    q = (np.stack([p.xx, p.yy], -1) - (ctr + shift).astype(np.float32)) / np.float32(k) + ctr.astype(np.float32)
    return _remap_map(m, q.astype(np.float32))


def generate_leaf(analysis, seed: int, params: SynthesisParams | None = None) -> GeneratedLeaf:
    """One new leaf from ``analysis``, fully determined by ``seed``.

    Every image is resampled once: the shape blend, the random warps and
    the registration are composed as coordinate maps first.

    Parameters
    ----------
    analysis : LeafAnalysis
        The exemplars, their registrations to the training leaf and the
        induced layers (:func:`branchnb.leaves.analyze`).
    seed : int
        Non-negative; the same seed and analysis give the same leaf.
    params : SynthesisParams, optional
        None: ``SynthesisParams()`` (the defaults).

    Returns
    -------
    GeneratedLeaf
        The leaf, with its seed, the exemplars it used and the warp sizes.
    """
    params = check_params(params if params is not None else SynthesisParams(), name="params")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative int, got {seed!r}")
    p = _prepared(analysis)
    a = analysis
    rng = np.random.default_rng(int(seed))
    n, shape = p.n, p.shape
    corr = params.warp_scale * p.size
    eps_px = float(np.median(a.layers[0].eps_px)) if a.layers else 0.0
    # The shape first: a convex blend of the inverse registration warps.
    wts = shape_weights(shape, n, params.shape_grid, params.shape_sigma * p.size, rng,
                        params.shape_concentration, params.shape_spread)
    m = np.zeros(shape + (2,), np.float32)
    for i in range(n):
        m += wts[i][..., None] * p.shape_maps[i]
    # The pose of one exemplar drawn at random: new leaves lie as variously
    # as the exemplars do (the weighted mean pose gave every new leaf
    # nearly the same angle: median pairwise blade IoU 0.80 against the
    # exemplars' 0.58 on a procedural family). Independent of the shape (how
    # a leaf lies on the paper has nothing to do with its outline): drawn by
    # the shape's weights, leaves of one dominant exemplar all lay alike
    # (IoU 0.76 against 0.51 on 3 trilobed exemplars). From a stream of its
    # own, so the other draws do not depend on it.
    pose_from = int(np.random.default_rng((int(seed), 2)).integers(n))
    m = p.posed(m, np.eye(n)[pose_from])
    # One exemplar's own petiole, drawn from a stream of its own (the main
    # one's use depends on the data: texture correction draws per replaced
    # patch). A petiole the canvas would cut is exchanged for the next
    # donor's (seeded order) that stays inside; if every one is cut, the
    # leaf is made a little smaller (at most three times).
    order = [int(e) for e in np.random.default_rng((int(seed), 1)).permutation(p.petiole_exemplars)]
    # The size of one exemplar, drawn from a stream of its own, independently
    # of the shape (see _fit_size); that exemplar gives the background too,
    # so its texture is seen at its own scale (a small exemplar's residual
    # blown up to a large one's size came out blurred).
    size_from = int(np.random.default_rng((int(seed), 3)).integers(n)) if params.own_size and n > 1 else -1
    m0, pet, pet_j = m, None, -1
    for attempt in range(4):
        m = _fit_size(p, m0, size_from, 0.9 ** attempt)
        pet, pet_j, best = None, -1, np.inf
        for cand in order:
            layer = p.petiole_layer(cand, m)
            if layer is None:
                continue
            cut = _border_alpha(layer[..., 3])
            if cut < best:
                pet, pet_j, best = layer, cand, cut
            if cut == 0:
                break
        if pet is None or best == 0:
            break
    # Background: one exemplar's residual, a warp below the registration error.
    bg = int(rng.integers(n))
    if size_from >= 0:
        bg = size_from
    base_amp = params.background_warp * p.registration_error
    d0 = random_warp(shape, base_amp, corr, rng)
    c_bg = p.source_coords(bg, m, d0)
    alpha = _sample(p.alpha_t, m)[..., 0]
    # Colours where the new leaf is, and a rim of a patch side around it: the
    # texture correction matches patches against the canvas there.
    rim = 2 * (max(8, min(shape) // 24) + 2) + 1
    shown = cv2.dilate((alpha > 0).astype(np.uint8), cv2.getStructuringElement(cv2.MORPH_RECT, (rim, rim))) > 0
    rgb = _sample_sharp_at(p.stage[-1][bg][..., :3], c_bg, shown)
    if params.correct:
        # Texture correction where the composed warp stretches or squeezes,
        # from the background exemplar's unwarped residual (before the layers
        # go on, so no vein or spot is replaced by plain texture).
        # From a stream of its own: how many draws the quilting takes depends
        # on the pixels, and the layers' donors drawn after it changed with
        # any change of the correction (two of four test leaves took the same ones).
        rgb = _correct(rgb, alpha > 0.5, c_bg, p.stage[-1][bg], a.blades[bg],
                       np.random.default_rng((int(seed), 4)))
    warps = {"background": base_amp}
    used = {bg}
    chosen = {}
    # Layers, bottom first, each from another exemplar with its own warp.
    cover = np.zeros(shape, np.float32)
    mix = np.zeros(shape + (3,), np.float32)
    wsum = np.zeros(shape, np.float32)
    for k in reversed(range(len(a.layers))):
        L = a.layers[k]
        cands = [e for e in range(n) if L.masks[e].any()]
        if not cands:
            continue
        fresh = [e for e in cands if e not in used]
        e = int(rng.choice(fresh if fresh else cands))
        used.add(e)
        chosen[L.name] = e
        amp = base_amp + params.layer_warp * eps_px * (1.0 - p.structural[k])
        warps[L.name] = amp
        c = p.source_coords(e, m, random_warp(shape, amp, corr, rng))
        a_k = np.clip(_sample(p.layer_masks[k][e], c)[..., 0], 0, 1)
        on = a_k > 0  # the layer's colours are needed under its footprint only
        col = _sample_sharp_at(p.stage[k][e][..., :3], c, on)
        if params.layer_colour == "contrast":
            # The layer relative to the same leaf without it (the next
            # residual): a vein of a yellow leaf darkens an orange
            # background as it darkened its own leaf, instead of painting a
            # yellow stripe on it.
            # As a ratio (a pigment multiplies the light the leaf under it
            # reflects), so black ink stays black whatever it lies on.
            # Clipped to the layer's colours in the exemplars, widened to
            # the background's own colour: a pixel the layer leaves as it
            # was (ratio ~1, the mask's anti-aliased rim) keeps the
            # background's colour. (Clipped to the layer's range alone, the
            # rim of a light vein was lifted to the vein's colour: veins
            # widened and blurred, new leaves had about half their
            # exemplars' Laplacian variance on procedural families.)
            under = _sample_sharp_at(p.under[k + 1][e][..., :3], c, on)
            lo, hi = p.layer_range[k]
            own = np.clip(rgb, *p.blade_range)
            col = np.clip(rgb * col / np.maximum(under, 0.02), np.minimum(lo, own), np.maximum(hi, own))
        wgt = (np.clip(_sample(p.layer_weights[k][e], c)[..., 0], 0, None) + 1e-6) * a_k
        cover = np.maximum(cover, a_k)
        mix += wgt[..., None] * col
        wsum += wgt
    layer_rgb = mix / np.maximum(wsum, 1e-12)[..., None]
    rgb = rgb * (1 - cover[..., None]) + layer_rgb * cover[..., None]
    alpha = np.clip(alpha, 0, 1)
    pet_from = -1
    if pet is not None:
        # Attached at the new leaf's base, under the lamina.
        pet_from = pet_j
        ap = np.clip(pet[..., 3], 0, 1)
        out_a = alpha + ap * (1 - alpha)
        rgb = (rgb * alpha[..., None] + pet[..., :3] * (ap * (1 - alpha))[..., None]) / np.maximum(
            out_a, 1e-6)[..., None]
        alpha = out_a
    if p.flat is not None:
        rgb, alpha = _ink_outline(rgb, alpha, p.flat)
    img = np.dstack([np.clip(rgb, 0, 1) * (alpha[..., None] > 0), alpha]).astype(np.float32)
    inside = alpha > 0.5
    sw = [float(wts[i][inside].mean()) if inside.any() else float(wts[i].mean()) for i in range(n)]
    return GeneratedLeaf(img, int(seed), bg, chosen, sw, warps, pet_from)


def _ink_outline(rgb: np.ndarray, alpha: np.ndarray, fa):
    """A drawn leaf finished: colours snapped to the exemplars' palette (hard-edged art) and a new outline.

    The outline (the exemplars' median colour and width) runs along the
    new blade's own boundary, anti-aliased by the distance inside; the
    blade's soft fringe (alpha <= 0.5) takes the outline's colour, so no
    fill shows outside it, and the alpha is cut at 0.5 (the exemplars'
    edges show paper right outside their outline; a ring of
    part-transparent ink or fill was a halo: 20-40 % of the 3 px ring
    outside new blades against 0-7 % for the exemplars). Going beyond the paper (see
    :mod:`branchnb.leaves.flatart`). Returns ``(rgb, alpha)``.
    """
    rgb = np.asarray(rgb, np.float32)
    blade = alpha > 0.5
    if not blade.any():
        return rgb, alpha
    if len(fa.palette):
        rgb = rgb.copy()
        rgb[blade] = _to_palette(rgb[blade], fa.palette, fa.hard)
    d_in = cv2.distanceTransform(blade.astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    o = np.clip(fa.outline_width + 1.0 - d_in, 0.0, 1.0).astype(np.float32)  # edt: 1 on the outermost pixels
    if fa.hard:
        o = np.round(o)
    o[(alpha > 0) & ~blade] = 1.0
    alpha = blade.astype(np.float32)
    return rgb * (1 - o[..., None]) + fa.outline_colour[None, None, :] * o[..., None], alpha


def _to_palette(px: np.ndarray, pal: np.ndarray, hard: bool) -> np.ndarray:
    """Colours ``px`` (N, 3) moved onto the drawing's palette.

    Hard-edged art: the nearest palette colour (resampled one-pixel ink
    turned into grey two-pixel lines). Anti-aliased art: a colour off the
    palette (more than 0.04 from every colour) goes to the nearest mixture
    of two palette colours (a point on a segment between them), which keeps
    the anti-aliasing but removes the tints the resampling's overshoot made
    between colours (cyan specks between dark green and paper on the
    sketched maples).
    """
    px = np.asarray(px, np.float32)
    pal = np.asarray(pal, np.float32)
    pn = (pal ** 2).sum(1)
    out = px.copy()
    pairs = np.array([(i, j) for i in range(len(pal)) for j in range(i + 1, len(pal))], int).reshape(-1, 2)
    a = pal[pairs[:, 0]] if len(pairs) else pal[:0]
    d = pal[pairs[:, 1]] - a if len(pairs) else pal[:0]
    dn = np.maximum((d ** 2).sum(1), 1e-9)
    ad = (a * d).sum(1)
    for s0 in range(0, len(px), 65536):
        c = px[s0:s0 + 65536]
        d2 = (c ** 2).sum(1)[:, None] - 2 * c @ pal.T + pn[None]
        near = np.argmin(d2, 1)
        if hard or not len(pairs):
            out[s0:s0 + 65536] = pal[near]
            continue
        off = np.flatnonzero(d2[np.arange(len(c)), near] > 0.04 ** 2)
        if not len(off):
            continue
        co = c[off]
        t = np.clip((co @ d.T - ad[None]) / dn[None], 0.0, 1.0)  # (M, P)
        q = a[None] + t[..., None] * d[None]  # (M, P, 3)
        k = np.argmin(((co[:, None, :] - q) ** 2).sum(-1), 1)
        out[s0 + off] = q[np.arange(len(off)), k]
    return out


def _masked_blur(img, mask, sigma):
    """Gaussian blur of ``img`` over ``mask`` only (normalised convolution); ``img`` outside it."""
    w = cv2.GaussianBlur(mask.astype(np.float32), (0, 0), sigma)
    b = cv2.GaussianBlur(np.ascontiguousarray(img * mask[..., None], np.float32), (0, 0), sigma)
    return np.where(mask[..., None], b / np.maximum(w, 1e-6)[..., None], img).astype(np.float32)


def _correct(rgb, blade, mapping, source, source_blade, rng):
    """Texture correction of the warped background, on its detail only.

    The distorted pixels get quilted *detail* (each image minus its blur
    at half a patch side) of the unwarped source over the warped image's
    own blur: the patches bring back grain and fine veins but not colours
    from elsewhere on the leaf. (Beyond the paper; quilting whole colours,
    a leaf with a smooth large-scale gradient, drawn or lit, came out with
    blocky patches of the wrong shade: a drawn maple's shape over two
    drawn oaks' fill. On a gradient with grain, stretched 3.3x over half
    its width: mean change of the blurred colour of the corrected pixels
    0.039-0.046 -> 0.004-0.005, their Laplacian variance unchanged; see
    the test.)
    """
    try:
        from .correction import correct_texture
    except ImportError:  # pragma: no cover - the correction module is another part of the package
        return rgb
    if not blade.any():
        return rgb
    src = np.asarray(source, np.float32)[..., :3]
    sigma = max(8, min(blade.shape) // 24) / 2.0
    low = _masked_blur(rgb, blade, sigma)
    src_low = _masked_blur(src, np.asarray(source_blade, bool), sigma)
    detail = np.clip(rgb - low + 0.5, 0, 1)
    src_detail = np.clip(src - src_low + 0.5, 0, 1)
    try:
        res = correct_texture(detail, mapping, src_detail, mask=blade, source_mask=source_blade, rng=rng)
    except ValueError:
        return rgb  # nothing to copy from: keep the warped texture
    out = rgb.copy()
    rep = res.replaced
    out[rep] = np.clip(low[rep] + res.image[rep] - 0.5, 0, 1)
    return out


def generate(analysis, n: int = 8, *, rng=None, params: SynthesisParams | None = None,
             progress=None) -> list[GeneratedLeaf]:
    """``n`` new leaves from an analysis; reproducible from ``rng``.

    Parameters
    ----------
    analysis : LeafAnalysis
        The exemplars, registrations and induced layers
        (:func:`branchnb.leaves.analyze`).
    n : int
        Number of new leaves, 1 to 100000 (default 8).
    rng : int or Generator
        Each leaf's seed is drawn from it (kept on the leaf).
    params : SynthesisParams, optional
        None: ``SynthesisParams()`` (the defaults).
    progress : callable(fraction, text), optional
        Called before each leaf with the fraction done and a label, and
        with ``(1.0, "done")`` at the end.

    Returns
    -------
    list of GeneratedLeaf

    Examples
    --------
    >>> from branchnb.leaves import analyze, leaf_family
    >>> leaves = leaf_family(2, size=128, rng=0)
    >>> a = analyze(leaves, 0, {"veins": leaves[0].layers["veins"]})  # finished layer masks
    >>> new = generate(a, 3, rng=1)
    >>> len(new), new[0].image.dtype, bool(0.5 < new[0].blade.sum() / a.blades[0].sum() < 2)
    (3, dtype('float32'), True)
    """
    from .analysis import LeafAnalysis
    if not isinstance(analysis, LeafAnalysis):
        raise TypeError(f"analysis must be a LeafAnalysis, got {type(analysis).__name__}")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= 100000:
        raise ValueError(f"n must be an int in [1, 100000], got {n!r}")
    if params is not None and not isinstance(params, SynthesisParams):
        raise TypeError(f"params must be a branchnb.leaves.SynthesisParams, got {type(params).__module__}."
                        f"{type(params).__name__}")
    params = check_params(params if params is not None else SynthesisParams(), name="params")
    check_callback(progress, "progress")
    gen = as_rng(rng)
    seeds = gen.integers(0, 2**31 - 1, size=int(n))
    out = []
    for i, s in enumerate(seeds):
        if progress is not None:
            progress(i / n, f"leaf {i + 1}/{n}")
        out.append(generate_leaf(analysis, int(s), params))
    if progress is not None:
        progress(1.0, "done")
    return out


def save_leaves(leaves, outdir, *, prefix: str = "leaf") -> list[str]:
    """Write each leaf as an RGBA PNG plus ``leaves.json``, a strict-JSON record of what made each.

    Returns the paths written (PNGs, then the JSON).

    Parameters
    ----------
    leaves : list of GeneratedLeaf
        The leaves, e.g. from :func:`generate`.
    outdir : str or path-like
        Output folder (created if needed; existing files are overwritten).
    prefix : str
        File names are ``<prefix>_0000.png``, ... and ``<prefix>s.json``
        (default ``"leaf"``: ``leaves.json``).

    Returns
    -------
    list of str
    """
    if isinstance(leaves, (str, bytes, dict)) or not isinstance(leaves, (list, tuple)):
        raise TypeError(f"leaves must be a list of GeneratedLeaf, got {type(leaves).__name__}")
    leaves = list(leaves)
    if not isinstance(outdir, (str, os.PathLike)) or not str(outdir).strip():
        raise TypeError(f"outdir must be a non-empty folder path, got {outdir!r:.60}")
    if os.path.exists(outdir) and not os.path.isdir(outdir):
        raise ValueError(f"outdir {str(outdir)!r} is a file, not a folder")
    for i, leaf in enumerate(leaves):
        if not isinstance(leaf, GeneratedLeaf):
            raise TypeError(f"leaves[{i}] must be a GeneratedLeaf, got {type(leaf).__name__}")
    if not isinstance(prefix, str) or not prefix or os.sep in prefix:
        raise ValueError(f"prefix must be a plain file-name prefix, got {prefix!r}")
    os.makedirs(outdir, exist_ok=True)
    paths, records = [], []
    for i, leaf in enumerate(leaves):
        name = f"{prefix}_{i:04d}.png"
        path = os.path.join(outdir, name)
        with open(path, "wb") as f:
            f.write(encode_png(leaf.image))
        rec = leaf.record()
        rec["file"] = name
        records.append(rec)
        paths.append(path)
    jpath = os.path.join(outdir, f"{prefix}s.json")
    text = dumps_strict({"version": 1, "leaves": records}, name="leaves", indent=1)
    with open(jpath, "w") as f:
        f.write(text)
    paths.append(jpath)
    return paths


def _align_moments(mask):
    ys, xs = np.nonzero(mask)
    c = np.array([xs.mean(), ys.mean()])
    cov = np.cov(np.stack([xs - c[0], ys - c[1]]))
    evals, evecs = np.linalg.eigh(cov)
    return c, evecs[:, ::-1], float(np.sqrt(mask.sum()))


def leaf_distance(a, b) -> float:
    """Image distance of two RGBA leaves after aligning ``b`` to ``a`` (similarity from blade moments).

    Mean absolute RGB difference (0..1) over the union of the two blades,
    on white (so shape differences count), after moving ``b``'s blade onto
    ``a``'s by centroid, principal axes and area (the better of the two
    axis signs and of mirroring).

    Parameters
    ----------
    a : (H, W, 4) array_like
        RGBA leaf, float in [0, 1]; its blade is ``alpha > 0.5``.
    b : (h, w, 4) array_like
        RGBA leaf moved onto ``a``'s frame.

    Returns
    -------
    float
        0 for identical leaves; up to 1.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.zeros((20, 20, 4), np.float32); x[5:15, 4:12] = (0.2, 0.6, 0.1, 1)
    >>> leaf_distance(x, x)
    0.0
    """
    a = np.asarray(a, np.float32)
    b = np.asarray(b, np.float32)
    for nm, v in (("a", a), ("b", b)):
        if v.ndim != 3 or v.shape[2] != 4:
            raise ValueError(f"{nm} must be an RGBA (H, W, 4) image, got shape {v.shape}")
        if not (v[..., 3] > 0.5).any():
            raise ValueError(f"{nm} has no leaf pixel (alpha > 0.5)")
    ma, mb = a[..., 3] > 0.5, b[..., 3] > 0.5
    ca, ra, sa = _align_moments(ma)
    cb, rb, sb = _align_moments(mb)
    wa = a[..., :3] * a[..., 3:] + (1 - a[..., 3:])
    wb = b[..., :3] * b[..., 3:] + (1 - b[..., 3:])
    h, w = a.shape[:2]
    best = np.inf
    for sx in (1, -1):
        for sy in (1, -1):
            rbs = rb * np.array([sx, sy])
            for mirror in (False, True):
                r = rbs.copy()
                if mirror:
                    r = r @ np.diag([1, -1])
                # x_b = cb + (sb / sa) R_b R_a^T (x_a - ca)
                lin = (sb / sa) * r @ ra.T
                off = cb - lin @ ca
                mat = np.hstack([lin, off[:, None]]).astype(np.float64)
                wbw = cv2.warpAffine(wb, mat, (w, h), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                     borderMode=cv2.BORDER_CONSTANT, borderValue=(1, 1, 1))
                mbw = cv2.warpAffine(mb.astype(np.float32), mat, (w, h),
                                     flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP) > 0.5
                u = ma | mbw
                dist = float(np.abs(wa - wbw)[u].mean()) if u.any() else 0.0
                best = min(best, dist)
    return float(best)


def colour_range_fraction(leaf_image, exemplars, blades=None, *, percentiles=(0.5, 99.5)) -> float:
    """Fraction of a leaf's blade pixels whose RGB lies inside the exemplars' range on every channel.

    The range per channel is the ``percentiles`` of all exemplar blade pixels.

    Parameters
    ----------
    leaf_image : (H, W, 4) array_like
        RGBA leaf, float in [0, 1] (e.g. a :class:`GeneratedLeaf`'s image).
    exemplars : sequence of (h, w, 4) array_like
        RGBA exemplar leaves.
    blades : sequence of (h, w) bool array_like, optional
        The exemplars' blades; None: each exemplar's ``alpha > 0.5``.
    percentiles : (float, float)
        Low and high percentile of the range (default ``(0.5, 99.5)``).

    Returns
    -------
    float
        In [0, 1]; 1: every blade pixel has exemplar colours.
    """
    img = np.asarray(leaf_image, np.float32)
    inside = img[..., 3] > 0.5
    if not inside.any():
        raise ValueError("leaf_image has no leaf pixel")
    px = []
    for i, ex in enumerate(exemplars):
        ex = np.asarray(ex, np.float32)
        m = ex[..., 3] > 0.5 if blades is None else np.asarray(blades[i], bool)
        px.append(ex[..., :3][m])
    allpx = np.concatenate(px)
    lo = np.percentile(allpx, percentiles[0], axis=0)
    hi = np.percentile(allpx, percentiles[1], axis=0)
    c = img[..., :3][inside]
    ok = np.all((c >= lo) & (c <= hi), axis=1)
    return float(ok.mean())
