"""Glowing lines (lightning, neon, fluorescence) of a flat-ground example: their glow measured and redrawn.

Beyond the paper (issue 23). A bolt with a white core and a violet glow on a
smooth night sky over a black skyline counts as a flat drawing (the sky
drifts by less than ``SHADED_SPREAD``, the skyline is flat), so
:func:`~branchnb.branching.image_synthesis.synthesize_image` draws its
output in the example's style. Drawn that way the output's lines had no
glow, and the example's glow, left in the sky's region texture, showed as a
ghost of the example's bolt. Glowing lines differ from drawn ones beside
them: the ring ``1.5 r + 3 .. + max(4, 2 r)`` px from a glowing line's
centre is non-flat (5 x 5 range over ``tol``) in 86-100 % of its pixels,
that of a drawn map, mask or line art in 0-46 % (:func:`glow_model`).

For a glowing example, :class:`GlowModel` holds

- ``ground``: the example without its lines and glow (every pixel within
  ``reach`` of a line refilled, region by region, by a normalised
  convolution of the region's pixels outside it: smooth grounds stay
  smooth, a black skyline does not bleed into the sky), from which the
  drawing style's region colours and textures are measured;
- ``excess``: the colour the lines add to their ground, the median of
  ``example - ground`` per distance ``d = 0 .. reach`` to the centre line
  and per class of line radius (a trunk glows wider than a twig),

and :meth:`GlowModel.paint` adds that excess to the output's ground around
its lines (light adds), so the output's core and glow have the example's
profile across them. Glowing lines on one plain ground (a fluorescent cell
on black, neon on a plain wall; one flat region, so no flat drawing) are
drawn the same way: copied fragment by fragment (disks of ``3 r``, ``r``
the core's radius) their glow ended 3-4 px from the centre line.

A grainy ground (noise, film grain, stars; :func:`ground_noise` over
:data:`NOISY`) is non-flat everywhere, so the glow tests look at the
example smoothed (:func:`calm_example`); its ground keeps the grain
(drawn into the refilled zone) and its lines' core keeps theirs
(``GlowModel.grain``). A glow the extracted radius took in (a neon tube's
``r`` 3 px for a 2 px core) is seen by the ring just outside the line's
rim (:func:`near_glowing_share`). The profile is measured in half-pixel
bins, so a thin core drawn off the pixel grid peaks as the example's.

A thin glow (a 1-2 px core, a glow of sigma 1.25-2 px: a bolt photo shrunk
to 128 px) leaves only part of those rings non-flat (0.3-0.9); it is told
apart from an anti-aliased drawn line by the light it casts 2 px past its
rim (:func:`glow_tail`, :data:`THIN_TAIL`).

Limits: a textured ground (not grain) keeps the textured path; a glow
of sigma about 1 px around a 1 px core is a soft line (its tail is under
:data:`THIN_TAIL`) and is drawn flat; an output radius
under the example's thinnest class takes that class's profile.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from .skeleton_map import PixelMap

__all__ = ["GlowModel", "calm_example", "glow_model", "glow_tail", "glowing_share", "ground_noise",
           "near_glowing_share"]

#: Pixel noise (robust sigma, :func:`ground_noise`) above which a ground counts as grainy and the glow
#: tests look at it smoothed (:func:`calm_example`). A clean render or a drawn map: 0-0.002; the
#: NOAA-like procedural storms 0.01; a grainy night sky 0.02-0.05.
NOISY = 0.006

#: Distance between the samples of a measured glow profile (px).
_STEP = 0.5


def _local_range(image: np.ndarray) -> np.ndarray:
    """Largest 5 x 5 range of any of the first three channels, per pixel."""
    img = np.asarray(image, np.float32)
    img = img if img.ndim == 3 else img[..., None]
    k = np.ones((5, 5), np.uint8)
    out = np.zeros(img.shape[:2], np.float32)
    for c in range(min(img.shape[2], 3)):
        ch = np.ascontiguousarray(img[..., c])
        out = np.maximum(out, cv2.dilate(ch, k) - cv2.erode(ch, k))
    return out


def ground_noise(image: np.ndarray, pm: PixelMap | None = None) -> float:
    """Robust per-pixel noise sigma of the ground (largest over the first three channels).

    The MAD of the differences between horizontal and between vertical neighbours (divided by
    ``sqrt 2``), over the pixels more than ``2 r + 4`` px from the lines of ``pm``: a smooth gradient
    or sparse stars barely move it, grain does.

    Parameters
    ----------
    image : (H, W[, C]) float ndarray
        The example, float in [0, 1].
    pm : PixelMap, optional
        Its structure's pixel map; None = every pixel.

    Returns
    -------
    float
        0 for an image under 3 px either way.
    """
    img = np.asarray(image, np.float32)
    img = img if img.ndim == 3 else img[..., None]
    if img.shape[0] < 3 or img.shape[1] < 3:
        return 0.0
    far = np.ones(img.shape[:2], bool)
    if pm is not None:
        r = np.where(np.isfinite(pm.radius), pm.radius, 0.0)
        far = ~(np.isfinite(pm.dist) & (pm.dist <= 2.0 * r + 4.0))
    best = 0.0
    for c in range(min(img.shape[2], 3)):
        ch = img[..., c]
        dx = (ch[:, 1:] - ch[:, :-1])[far[:, 1:] & far[:, :-1]]
        dy = (ch[1:] - ch[:-1])[far[1:] & far[:-1]]
        d = np.concatenate([dx, dy])
        if d.size >= 50:
            best = max(best, 1.4826 * float(np.median(np.abs(d - np.median(d)))) / np.sqrt(2.0))
    return best


def calm_example(image: np.ndarray, pm: PixelMap | None = None, tol: float = 0.03) -> np.ndarray | None:
    """The example smoothed until its ground's grain lies under the flatness threshold, or None when
    its ground is not grainy (:data:`NOISY`).

    Beyond the paper (issue 23): a night sky with grain, noise or stars is non-flat everywhere, so a
    bolt's glow was not told apart from it and the example went the textured path, whose output broke
    the bolts into dim pieces. Smoothed by a Gaussian of ``sigma = 4 noise / (tol sqrt(pi))`` (in 1-3
    px; the grain's 5 x 5 range falls under ``tol``), the sky is as flat as a clean one and the glow,
    wider than that, is kept.

    Parameters
    ----------
    image : (H, W[, C]) float ndarray
        The example, float in [0, 1].
    pm : PixelMap, optional
        Its structure's pixel map (the noise is measured away from its lines).
    tol : float, default 0.03
        The flatness threshold of :func:`glowing_share`.

    Returns
    -------
    (H, W, C) float32 ndarray or None
    """
    noise = ground_noise(image, pm)
    if noise < NOISY:
        return None
    img = np.asarray(image, np.float32)
    img = img if img.ndim == 3 else img[..., None]
    sigma = float(np.clip(4.0 * noise / (tol * np.sqrt(np.pi)), 1.0, 3.0))
    out = cv2.GaussianBlur(img, (0, 0), sigma, borderType=cv2.BORDER_REFLECT)
    return (out if out.ndim == 3 else out[..., None]).astype(np.float32)


def glowing_share(image: np.ndarray, pm: PixelMap, tol: float = 0.03) -> float:
    """Share of the ring ``1.5 r + 3 .. 1.5 r + 3 + max(4, 2 r)`` px beside the lines that is not flat.

    Parameters
    ----------
    image : (H, W[, C]) float ndarray
        The example, float in [0, 1].
    pm : PixelMap
        Its structure's pixel map.
    tol : float, default 0.03
        A pixel is flat when its 5 x 5 neighbourhood varies by less (every channel).

    Returns
    -------
    float
        In [0, 1]; 0 when the ring holds no pixel. Glowing lines give 0.86-1,
        drawn lines 0-0.46.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching.skeleton_map import SkeletonMap
    >>> img = np.full((60, 60, 3), 0.1, np.float32); img[29:31, 5:55] = 1.0
    >>> pm = SkeletonMap(Structure([Branch([(5, 29.5), (54, 29.5)], 1.0)]), 1.0).pixel_map((60, 60))
    >>> glowing_share(img, pm) < 0.5
    True
    """
    finite = np.isfinite(pm.dist) & np.isfinite(pm.radius)
    r = np.where(finite, pm.radius, 0.0)
    lo = 1.5 * r + 3.0
    ring = finite & (pm.dist >= lo) & (pm.dist <= lo + np.maximum(4.0, 2.0 * r))
    if not ring.any():
        return 0.0
    return float(np.mean(_local_range(image)[ring] >= tol))


def near_glowing_share(image: np.ndarray, pm: PixelMap, tol: float = 0.03) -> float:
    """Share of the ring ``r + 2.5 .. r + 4.5`` px beside the lines whose 3 x 3 range reaches ``tol``.

    Beyond the paper (issue 23): where the extracted radius ``r`` takes in part of the glow (a neon
    tube's or a glowing vein's halo read as line body, ``r`` 3 px for a 2 px core), the ring of
    :func:`glowing_share` lies ``1.5 r + 3`` = 7-8 px out, past most of the glow (0.34-0.47 on such
    examples); this ring, just outside an anti-aliased line's rim (a 3 x 3 window at ``r + 2.5`` does
    not reach the rim at ``r + 0.7``), reads 0.98-1 on them and 0-0.01 on drawn lines (1-3 px,
    anti-aliased, 128-256 px).

    Parameters
    ----------
    image : (H, W[, C]) float ndarray
        The example, float in [0, 1].
    pm : PixelMap
        Its structure's pixel map.
    tol : float, default 0.03
        A pixel is flat when its 3 x 3 neighbourhood varies by less (every channel).

    Returns
    -------
    float
        In [0, 1]; 0 when the ring holds no pixel.
    """
    img = np.asarray(image, np.float32)
    img = img if img.ndim == 3 else img[..., None]
    finite = np.isfinite(pm.dist) & np.isfinite(pm.radius)
    r = np.where(finite, pm.radius, 0.0)
    ring = finite & (pm.dist >= r + 2.5) & (pm.dist <= r + 4.5)
    if not ring.any():
        return 0.0
    k = np.ones((3, 3), np.uint8)
    rng_ = np.zeros(img.shape[:2], np.float32)
    for c in range(min(img.shape[2], 3)):
        ch = np.ascontiguousarray(img[..., c])
        rng_ = np.maximum(rng_, cv2.dilate(ch, k) - cv2.erode(ch, k))
    return float(np.mean(rng_[ring] >= tol))


#: A thin glow (a 1-2 px core with a glow of sigma 1-1.5 px, a bolt photo shrunk to 128 px) leaves only
#: 0.3-0.9 of :func:`near_glowing_share`'s ring non-flat (drawn anti-aliased lines 0-0.41, a cased road
#: the most): glow_model takes such lines as glowing from this share on when :func:`glow_tail` tells
#: them apart (beyond the paper, issue 23).
THIN_RING = 0.2
#: Smallest :func:`glow_tail` of a thin glow: procedural 128 px glows of sigma 1.25-2 px around 1-2 px
#: cores 0.031-0.305 (sigma 1 px around a 2 px core 0.039-0.042); drawn lines (1-3 px, anti-aliased,
#: shrunk from 3x, JPEG q75, cased, on a gradient ground) 0.000-0.010. (Drawn trees of tapering strokes
#: reach 0.055, but their ring does not brighten towards the lines all round: ``_towards_lines`` 0.03-0.31.)
THIN_TAIL = 0.02


def glow_tail(image: np.ndarray, pm: PixelMap, near: float = 2.0, far: float = 4.0) -> float:
    """How much light a line casts past its rim: the median luminance ``near`` px beyond each line's
    radius, less the one ``far`` px beyond (when above the ground), over the core's contrast.

    Beyond the paper (issue 23). An anti-aliased drawn line meets its ground within a pixel of its rim
    (its radius ``r`` from the pixel map): 2 px beyond it the median is the ground's whatever its
    width (shrunk, JPEG-compressed, cased: 0.000; on a gradient ground at most 0.010); a glow still
    lights it (0.03-0.3 of the core's contrast for glows of sigma 1.25-2 px), and fades further out.
    Measured against ``d - r`` per pixel, lines of many widths (a drawn tree) pool alike.

    Parameters
    ----------
    image : (H, W[, C]) float ndarray
        The example, float in [0, 1].
    pm : PixelMap
        Its structure's pixel map.
    near, far : float
        Distances beyond the radius (pixels) of the lit ring and of the faded one; the ground is the
        median ``far + 2 .. far + 6`` px beyond it.

    Returns
    -------
    float
        The share of the core's contrast (0 when the lit ring is not lit towards the core's side, when
        the core barely stands out, or when too few pixels are measured).

    Examples
    --------
    >>> import numpy as np, cv2
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching.skeleton_map import SkeletonMap
    >>> core = np.zeros((60, 80), np.float32); core[29:31, 5:75] = 1.0
    >>> pm = SkeletonMap(Structure([Branch([(5, 29.5), (74, 29.5)], 1.0)]), 1.0).pixel_map((60, 80))
    >>> glow = 0.1 + 0.8 * core + 1.2 * cv2.GaussianBlur(core, (0, 0), 1.5)
    >>> drawn = 0.1 + 0.8 * core
    >>> bool(glow_tail(glow, pm) > 0.02), bool(glow_tail(drawn, pm) < 0.01)
    (True, True)
    """
    img = np.asarray(image, np.float32)
    lum = img[..., :3].mean(axis=2) if img.ndim == 3 else img
    fin = np.isfinite(pm.dist) & np.isfinite(pm.radius)
    d = pm.dist[fin]
    u = d - pm.radius[fin]
    v = lum[fin]
    core = v[d <= 0.5]
    ground = (u >= far + 2.0) & (u <= far + 6.0)
    if core.size < 10 or np.count_nonzero(ground) < 10:
        return 0.0
    g = float(np.median(v[ground]))
    c = float(np.median(core)) - g
    if abs(c) < 0.05:
        return 0.0

    def at(x: float) -> float:
        # a one-pixel window: an axis-aligned line's pixels lie at whole-and-a-half distances only
        m = np.abs(u - x) <= 0.5
        return float(np.median(v[m]) - g) / c if np.count_nonzero(m) >= 10 else 0.0

    a = at(near)
    return a - max(at(far), 0.0) if a > 0 else 0.0


def _towards_lines(image: np.ndarray, pm: PixelMap) -> float:
    """How consistently the luminance beside the lines (the ring of :func:`glowing_share`) changes
    towards them: ``|mean sign(grad lum . direction to the line)|`` over its pixels that are not flat.
    A glow rises (a dark line's halo falls) towards its line all round: ~1; the relief shading of a
    terrain map along its rivers is lit on one slope and shaded on the other: ~0 (its ring is as
    non-flat as a glow's, 0.99)."""
    lum = cv2.GaussianBlur(np.asarray(image, np.float32)[..., :3].mean(axis=2), (0, 0), 1.0)
    gy, gx = np.gradient(lum)
    dist = np.where(np.isfinite(pm.dist), pm.dist, 0.0).astype(np.float32)
    dy, dx = np.gradient(dist)
    r = np.where(np.isfinite(pm.radius), pm.radius, 0.0)
    lo = 1.5 * r + 3.0
    ring = np.isfinite(pm.dist) & (pm.dist >= lo) & (pm.dist <= lo + np.maximum(4.0, 2.0 * r))
    dot = -(gx * dx + gy * dy)
    sel = ring & (np.hypot(gx, gy) > 0.002) & (np.hypot(dx, dy) > 0.5)
    if np.count_nonzero(sel) < 20:
        return 0.0
    return float(abs(np.mean(np.sign(dot[sel]))))


def _glow_reach(lum: np.ndarray, dist: np.ndarray, cap: int, floor: float = 0.01) -> int:
    """First distance (px, from 2) from which the mean luminance no longer moves towards the ground:
    the mean at ``d`` differs from the one 4-8 px farther out by under ``floor`` (a smooth sky's drift
    over 6 px is far less), plus a 2 px margin."""
    d = np.round(dist).astype(np.int64)
    ok = d <= cap + 8
    sums = np.bincount(d[ok], lum[ok], minlength=cap + 9)
    counts = np.bincount(d[ok], minlength=cap + 9)
    # (means, not medians, per ring: one bincount; the lines' neighbourhood is what they light)
    prof = np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)
    for k in range(1, cap + 1):
        out = prof[k + 4:k + 9]
        out = out[np.isfinite(out)]
        # (either way: a dark line's bright halo rises outwards before it falls to the ground)
        if k >= 2 and np.isfinite(prof[k]) and out.size and abs(prof[k] - out.mean()) < floor:
            return min(k + 2, cap)
    return cap


def _fill_regions(image: np.ndarray, hole: np.ndarray, labels: np.ndarray, sigma: float) -> np.ndarray:
    """``image`` with ``hole`` refilled per label by a normalised convolution of that label's other pixels
    (wider scales where a narrow one finds none)."""
    out = np.array(image, np.float32, copy=True)
    for k in np.unique(labels[hole]):
        reg = labels == k
        src = (reg & ~hole).astype(np.float32)
        todo = reg & hole
        if not src.any():
            continue
        s = sigma
        while todo.any():
            den = cv2.GaussianBlur(src, (0, 0), s, borderType=cv2.BORDER_REFLECT)
            num = cv2.GaussianBlur(out * src[..., None], (0, 0), s, borderType=cv2.BORDER_REFLECT)
            num = num if num.ndim == 3 else num[..., None]
            ok = todo & (den > 0.05)
            out[ok] = num[ok] / den[ok, None]
            todo &= ~ok
            s *= 2.0
            if s > 4 * max(image.shape[:2]):
                out[todo] = out[reg & ~hole].mean(0)
                break
    return out


def _regrain(image: np.ndarray, calm: np.ndarray, ground: np.ndarray, hole: np.ndarray,
             labels: np.ndarray) -> np.ndarray:
    """``ground`` with the example's grain put back into ``hole``: each hole pixel takes the grain (the
    example about its local mean outside the hole) of a pixel of its region outside the hole, drawn by a
    fixed seed. Refilled by a normalised convolution, a grainy sky had smooth streaks where the example's
    lines were (ghosts of them in the output's sky); mirrored across the hole's edge, the grain came out
    as flat shards where the mirror fell back into a wide hole (between two strands of a bolt)."""
    img = np.asarray(image, np.float32)
    # the local mean blurred over the pixels outside the hole only: ``calm`` blurs the lines' light
    # across the hole's edge, and that residual made dark blotches
    keep = (~hole).astype(np.float32)
    den = cv2.GaussianBlur(keep, (0, 0), 1.5, borderType=cv2.BORDER_REFLECT)
    num = cv2.GaussianBlur(img * keep[..., None], (0, 0), 1.5, borderType=cv2.BORDER_REFLECT)
    num = num if num.ndim == 3 else num[..., None]
    mean = np.where(den[..., None] > 1e-3, num / np.maximum(den, 1e-3)[..., None], np.asarray(calm, np.float32))
    grain = (img - mean).reshape(-1, img.shape[2])
    out = np.array(ground, np.float32, copy=True)
    flat = out.reshape(-1, out.shape[2])
    lab = np.asarray(labels).ravel()
    hv = hole.ravel()
    rng = np.random.default_rng(0)
    for k in np.unique(lab[hv]):
        dst = np.flatnonzero(hv & (lab == k))
        src = np.flatnonzero(~hv & (lab == k))
        if src.size == 0:
            src = np.flatnonzero(~hv)
        if src.size:
            flat[dst] += grain[src[rng.integers(0, src.size, dst.size)]]
    return np.clip(out, 0.0, 1.0)


def _smooth_regions(lum: np.ndarray, labels: np.ndarray, sigma: float) -> np.ndarray:
    """``lum`` blurred (Gaussian ``sigma``) within each label: the ground's slow drift, no thin line."""
    out = np.zeros(lum.shape, np.float32)
    for k in np.unique(labels):
        reg = (labels == k).astype(np.float32)
        den = cv2.GaussianBlur(reg, (0, 0), sigma, borderType=cv2.BORDER_REFLECT)
        num = cv2.GaussianBlur(lum.astype(np.float32) * reg, (0, 0), sigma, borderType=cv2.BORDER_REFLECT)
        sel = reg > 0
        out[sel] = num[sel] / np.maximum(den[sel], 1e-6)
    return out


@dataclass
class GlowModel:
    """How an example's glowing lines light their ground (see :func:`glow_model`).

    Parameters
    ----------
    ground : (H, W, C) float32 ndarray
        The example without its lines and glow.
    reach : int
        Distance (px) from a centre line out to which the lines light the ground.
    radii : (K,) ndarray
        Median line radius of each radius class (increasing).
    excess : (K, reach / step + 1, C) ndarray
        Median colour ``example - ground`` at each distance ``0, step, .. reach`` per radius class.
    step : float, default 1.0
        Distance between the samples of ``excess`` (px); :func:`glow_model` measures at 0.5 px.
    grain : (M, C) ndarray, optional
        A grainy example's lines' own grain: ``example - ground - excess`` at its core's pixels
        (distance bins where the excess is at least half its peak); None = smooth lines.
    grain_bin : (M,) int ndarray, optional
        The distance bin (``round(d / step)``) of each ``grain`` sample.
    """

    ground: np.ndarray
    reach: int
    radii: np.ndarray
    excess: np.ndarray
    step: float = 1.0
    grain: np.ndarray | None = None
    grain_bin: np.ndarray | None = None

    def region_textures(self, layout: np.ndarray) -> dict:
        """``{label: (H, W, C) image}``: the ground of every region of ``layout``, each pixel outside the
        region taking the colour of the nearest pixel inside (for :class:`~.drawing.DrawingStyle`: a
        night sky keeps its gradient, drawn in one flat colour it lost it).

        Parameters
        ----------
        layout : (H, W) int ndarray
            Region labels.

        Returns
        -------
        dict
        """
        from scipy import ndimage as ndi

        lay = np.asarray(layout)
        out = {}
        for k in np.unique(lay):
            _d, (iy, ix) = ndi.distance_transform_edt(lay != k, return_indices=True)
            out[int(k)] = self.ground[iy, ix]
        return out

    def light(self, pm: PixelMap) -> np.ndarray:
        """The colour the lines of ``pm`` add to their ground, (H, W, C) float32 (0 beyond ``reach``).

        Parameters
        ----------
        pm : PixelMap
            The output structure's pixel map.

        Returns
        -------
        (H, W, C) float32 ndarray
        """
        h, w = pm.dist.shape
        c = self.excess.shape[2]
        out = np.zeros((h, w, c), np.float32)
        finite = np.isfinite(pm.dist) & np.isfinite(pm.radius)
        near = finite & (pm.dist <= self.reach)
        if not near.any():
            return out
        d = pm.dist[near]
        r = pm.radius[near]
        # per radius class, the profile interpolated at the pixel's distance (looked up at the rounded
        # distance, as it is measured, a thin bolt's core fell apart into dashes); between classes linearly
        grid = np.arange(self.excess.shape[1], dtype=np.float64) * float(self.step)
        per_class = np.stack([np.stack([np.interp(d, grid, self.excess[k, :, ch]) for ch in range(c)], -1)
                              for k in range(len(self.radii))])
        if len(self.radii) == 1:
            val = per_class[0]
        else:
            t = np.interp(r, self.radii, np.arange(len(self.radii), dtype=np.float64))
            lo = np.floor(t).astype(int)
            hi = np.minimum(lo + 1, len(self.radii) - 1)
            f = (t - lo)[:, None]
            idx = np.arange(len(d))
            val = (1 - f) * per_class[lo, idx] + f * per_class[hi, idx]
        out[near] = val
        if self.grain is not None and len(self.grain):
            # the core takes the grain of the example's core at its distance (samples drawn by a fixed
            # seed: the same output for the same lines); painted smooth, a speckled fluorescent cell's
            # lines kept 0.56 of the example's fine detail
            q = np.round(d / float(self.step)).astype(np.int64)
            order = np.argsort(self.grain_bin, kind="stable")
            gb = self.grain_bin[order]
            start = np.searchsorted(gb, q, "left")
            count = np.searchsorted(gb, q, "right") - start
            ok = count > 0
            pick = start[ok] + (np.random.default_rng(0).random(int(ok.sum())) * count[ok]).astype(np.int64)
            rows = np.flatnonzero(near.ravel())[ok]
            flat = out.reshape(-1, c)
            flat[rows] += self.grain[order][pick]
        return out

    def paint(self, ground: np.ndarray, pm: PixelMap) -> np.ndarray:
        """``ground`` (the output without lines) with the lines of ``pm`` and their glow added, in [0, 1].

        Parameters
        ----------
        ground : (H, W, C) array_like
            The output without lines.
        pm : PixelMap
            The output structure's pixel map.

        Returns
        -------
        (H, W, C) float32 ndarray
        """
        g = np.asarray(ground, np.float32)
        return np.clip(g + self.light(pm)[..., :g.shape[2]], 0.0, 1.0).astype(np.float32)


def glow_model(image: np.ndarray, pm: PixelMap, labels: np.ndarray | None = None, *, tol: float = 0.03,
               share: float = 0.8, max_reach: int | None = None) -> GlowModel | None:
    """Measure an example's glowing lines, or None when its lines do not glow.

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example, float in [0, 1].
    pm : PixelMap
        Its structure's pixel map.
    labels : (H, W) int ndarray, optional
        Its ground regions (a sky and a skyline); the ground under the glow is
        refilled from its own region only. None = one region.
    tol : float, default 0.03
        Flatness threshold of :func:`glowing_share`.
    share : float, default 0.8
        Smallest ring share (the larger of :func:`glowing_share` and
        :func:`near_glowing_share`) of glowing lines; from :data:`THIN_RING`
        on when :func:`glow_tail` reaches :data:`THIN_TAIL` (a thin glow).
    max_reach : int, optional
        Largest glow reach (px); None = 1/8 of the example's smaller side, at least 8.

    Returns
    -------
    GlowModel or None

    Examples
    --------
    >>> import numpy as np, cv2
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching.skeleton_map import SkeletonMap
    >>> core = np.zeros((80, 80), np.float32); core[39:41, 5:75] = 1.0
    >>> img = np.clip(0.1 + core[..., None] * 0.8 + 1.5 * cv2.GaussianBlur(core, (0, 0), 3.0)[..., None]
    ...               * np.array([0.6, 0.3, 1.0]), 0, 1).astype(np.float32)
    >>> pm = SkeletonMap(Structure([Branch([(5, 39.5), (74, 39.5)], 1.0)]), 1.0).pixel_map((80, 80))
    >>> m = glow_model(img, pm)
    >>> m is not None and 6 <= m.reach <= 12, bool(abs(m.ground[10, 40, 0] - 0.1) < 0.01)
    (True, True)
    """
    img = np.asarray(image, np.float32)
    if img.ndim == 2:
        img = img[..., None]
    h, w = img.shape[:2]
    cap = int(max_reach) if max_reach is not None else max(8, min(h, w) // 8)
    # a grainy sky (noise, stars) is judged smoothed: its grain made it non-flat everywhere
    calm = calm_example(img, pm, tol)
    test = img if calm is None else calm
    ring = max(glowing_share(test, pm, tol), near_glowing_share(test, pm, tol))
    far = np.isfinite(pm.dist) & (pm.dist > cap)
    # a textured ground is non-flat beside the lines as everywhere else: no glow is told apart
    rest = float(np.mean(_local_range(test)[far] >= tol)) if far.any() else 0.0
    if ring - rest < (0.5 if ring >= share else THIN_RING) or ring < THIN_RING or _towards_lines(test, pm) < 0.7:
        return None
    if ring < share and glow_tail(test, pm) < THIN_TAIL:
        # a ring this flat is an anti-aliased drawn line's unless the light fades beyond its rim
        return None
    lum = test[..., :3].mean(axis=2)
    finite = np.isfinite(pm.dist) & np.isfinite(pm.radius)
    dist = np.where(finite, pm.dist, np.inf)
    reach = _glow_reach(lum, dist, cap)
    hole = dist <= reach
    if hole.all() or not hole.any():
        return None
    lab = np.zeros((h, w), np.int64) if labels is None else np.asarray(labels)
    ground = _fill_regions(img, hole, lab, max(2.0, reach / 2.0))
    # lines the structure does not hold (twigs the extraction missed) glow too: pixels that stand out
    # from the refilled ground by half the glow at half its reach, with their own glow, are refilled
    # as well (left in, they were ghosts of the example's twigs in the output's sky)
    over = lum - _smooth_regions(ground[..., :3].mean(axis=2), lab, float(max(4, reach)))
    prof_d = np.round(dist[hole]).astype(np.int64)
    half = over[hole][prof_d == max(1, reach // 2)]
    level = max(0.02, 0.5 * float(np.median(half))) if half.size else 0.02
    stray = (over > level) & ~hole
    if stray.any():
        grown = cv2.dilate(stray.astype(np.uint8), cv2.getStructuringElement(
            cv2.MORPH_ELLIPSE, (2 * (reach // 2) + 1, 2 * (reach // 2) + 1))) > 0
        hole = hole | grown
        if hole.all():
            return None
        ground = _fill_regions(img, hole, lab, max(2.0, reach / 2.0))
    dev = img - ground
    d = np.round(dist[hole]).astype(np.int64)
    r = pm.radius[hole]
    centre = finite & (pm.dist <= 0.5)
    rc = pm.radius[centre]
    if rc.size < 10:
        return None
    # radius classes by the centre line's radius (up to 3 with >= 20 % of the centre pixels each)
    qs = np.unique(np.quantile(rc, [0.0, 1 / 3, 2 / 3, 1.0]))
    edges = qs if len(qs) > 1 else np.array([qs[0], qs[0]])
    radii, profiles = [], []
    devs = dev[hole]
    # the profile in half-pixel bins: in whole-pixel ones the centre bin held pixels up to 0.5 px off
    # the line (a 1 px core's anti-aliased halves) and was interpolated again at the output's distances,
    # so a thin line's drawn core peaked 25 % under the example's (0.40 for 0.55 on a 128 px vein)
    q = np.round(dist[hole] / _STEP).astype(np.int64)
    n_bins = int(round(reach / _STEP)) + 1
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (r >= lo) & (r <= hi)
        if np.count_nonzero(sel & (d == 0)) < 5:
            continue
        prof = np.zeros((n_bins, img.shape[2]), np.float32)
        for k in range(n_bins):
            m = sel & (q == k)
            if np.count_nonzero(m) >= 3:
                prof[k] = np.median(devs[m], axis=0)
            elif k:
                prof[k] = prof[k - 1]
        radii.append(float(np.median(rc[(rc >= lo) & (rc <= hi)])))
        profiles.append(prof)
    if not radii:
        return None
    order = np.argsort(radii, kind="stable")
    radii_a = np.asarray(radii)[order]
    excess = np.stack([profiles[i] for i in order])
    # classes of one radius (few distinct radii) are one class: np.interp needs increasing radii
    keep = np.concatenate([[True], np.diff(radii_a) > 1e-6])
    radii_a, excess = radii_a[keep], excess[keep]
    # the light fades to nothing at the reach (no step where the glow zone meets the ground)
    fade = np.clip((reach - _STEP * np.arange(n_bins)) / 2.0, 0.0, 1.0).astype(np.float32)
    excess *= fade[None, :, None]
    grain = grain_bin = None
    if calm is not None:
        # the lines' own grain (a speckled cell's lines, a noisy photo's bolt) at the core's distances
        peak = excess[..., :3].mean(axis=2)
        core_bins = int(np.argmax(np.all(peak < 0.5 * peak.max(axis=1, keepdims=True), axis=0))) or 1
        inner = q < core_bins
        model = np.zeros_like(devs)
        for lo, hi in zip(edges[:-1], edges[1:]):
            sel = (r >= lo) & (r <= hi)
            k = int(np.argmin(np.abs(radii_a - np.median(rc[(rc >= lo) & (rc <= hi)])))) if sel.any() else 0
            model[sel] = excess[k][np.minimum(q[sel], n_bins - 1)]
        grain = (devs - model)[inner].astype(np.float32)
        grain_bin = q[inner]
        ground = _regrain(img, calm, ground, hole, lab)
    return GlowModel(ground.astype(np.float32), int(reach), radii_a, excess.astype(np.float32), _STEP,
                     grain, grain_bin)
