"""Line contrast of a synthesized image: the example's line profile on every target branch.

Going beyond the paper. Its image synthesis copies fragments of the example
along the target skeleton; each is bent onto the target, sampled bilinearly,
seamed in and gap completion fills around it. On thin lines (cracks in mud,
capillaries of a retina, 1-2 px wide) every step softens the line a little,
a fragment that lands half a pixel beside the target centre line leaves it
pale, and where no fragment brought the line (a junction cleared for a
furcation, a disk whose source held another branch) the branch has a gap.
The result reads as weak, broken lines next to the example.

This module measures how the example's lines stand out from their local
ground, as a function of the radius ``r`` and of the normalised distance
``u = d / r`` to the centre line (:func:`line_profile`), and then gives every
target line pixel *at least* a share of that profile
(:func:`restore_line_contrast`): only pixels that fall short move, along
the example's line colour direction, so the fragments' texture stays
wherever they already carry the line, and gaps are drawn in.

A last step (:func:`match_line_contrast`) then keeps the lines from standing
out *more* than the example's (or much less): the fragments are bent so
that their centre lines fall exactly on the target's, while an example
extracted from a photo has centre lines a fraction of a pixel off its
vessels and thin lines blurred by its resolution, so a 128 px retina's
lines came out 1.3-3.3x as contrasted as its own (median centre-line colour
against the median ground beside the lines, :func:`centre_ring_contrast`).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from .skeleton_map import PixelMap

__all__ = ["LineProfile", "line_profile", "local_ground", "restore_line_contrast", "centre_ring_contrast",
           "centre_ring_colours", "match_line_contrast"]

#: Normalised distances ``u = d / r`` at which the profile is measured.
_U = np.array([0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5])


@dataclass
class LineProfile:
    """How an example's lines stand out from their ground (see :func:`line_profile`).

    Parameters
    ----------
    direction : (C,) ndarray
        Unit colour direction from the ground to the lines.
    radii : (K,) ndarray
        Radii (pixels) at which ``amplitude`` is measured (increasing).
    amplitude : (K,) ndarray
        Median projection (colour units along ``direction``) of the centre-line
        pixels' difference to the local ground, per radius.
    u : (M,) ndarray
        Normalised distances ``d / r`` of ``shape``.
    shape : (M,) ndarray
        Median projection at ``u`` over the amplitude at the centre (1 at
        ``u = 0``, falling off across the edge).
    """

    direction: np.ndarray
    radii: np.ndarray
    amplitude: np.ndarray
    u: np.ndarray
    shape: np.ndarray

    def target(self, dist: np.ndarray, radius: np.ndarray) -> np.ndarray:
        """Projection a pixel at ``dist`` from a centre line of ``radius`` has in the example (median).

        Parameters
        ----------
        dist : ndarray
            Distance (px) of each pixel from its centre line.
        radius : ndarray
            Radius (px) of that centre line there, same shape as ``dist``.

        Returns
        -------
        ndarray
            The example's median projection, same shape.
        """
        r = np.maximum(radius, 0.5)
        amp = np.interp(r, self.radii, self.amplitude)
        return amp * np.interp(dist / r, self.u, self.shape, right=0.0)


def local_ground(image: np.ndarray, exclude: np.ndarray, sigma: float) -> np.ndarray:
    """Smooth estimate of the ground under ``exclude`` (normalised convolution of the other pixels).

    Parameters
    ----------
    image : (H, W, C) float32 ndarray
        The image.
    exclude : (H, W) bool ndarray
        Pixels that are no ground (the lines, an unusable matte).
    sigma : float
        Gaussian scale (pixels) of the estimate.

    Returns
    -------
    (H, W, C) float32 ndarray
        The ground colour at every pixel (the image's mean where no ground
        pixel lies within a few ``sigma``).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((32, 32, 3), 0.8, np.float32); img[15:17] = 0.1
    >>> g = local_ground(img, img[..., 0] < 0.5, 3.0)
    >>> bool(np.allclose(g[16, 16], 0.8, atol=1e-3))
    True
    """
    img = np.asarray(image, np.float32)
    w = (~np.asarray(exclude, bool)).astype(np.float32)
    k = (0, 0)
    num = cv2.GaussianBlur(img * w[..., None], k, sigma, borderType=cv2.BORDER_REFLECT)
    den = cv2.GaussianBlur(w, k, sigma, borderType=cv2.BORDER_REFLECT)
    if num.ndim == 2:
        num = num[..., None]
    fallback = img[w > 0].mean(0) if w.any() else img.reshape(-1, img.shape[2]).mean(0)
    ok = den > 1e-3
    out = np.where(ok[..., None], num / np.maximum(den, 1e-6)[..., None], fallback)
    return out.astype(np.float32)


def _ground_sigma(radius: np.ndarray) -> float:
    r = float(np.median(radius)) if radius.size else 1.0
    return max(3.0, 2.0 * r + 2.0)


def line_profile(image, pm: PixelMap, valid=None) -> LineProfile | None:
    """Measure an example's line profile: colour direction, amplitude per radius, shape across.

    Parameters
    ----------
    image : (H, W, C) array_like
        The example, float in [0, 1].
    pm : PixelMap
        Its structure's pixel map on the image.
    valid : (H, W) bool array_like, optional
        Pixels to use (e.g. not an unusable matte); None = all.

    Returns
    -------
    LineProfile or None
        None when the lines do not stand out from their ground (under
        0.02 in colour), or there are too few centre-line pixels.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching.skeleton_map import SkeletonMap
    >>> img = np.full((40, 40, 3), 0.8, np.float32); img[19:21, 2:38] = 0.2
    >>> s = Structure([Branch([(2, 19.5), (37, 19.5)], 1.0)])
    >>> prof = line_profile(img, SkeletonMap(s, 1.0).pixel_map((40, 40)))
    >>> round(float(prof.amplitude[0]), 2)
    1.04
    """
    img = np.asarray(image, np.float32)
    if img.ndim == 2:
        img = img[..., None]
    ok = np.ones(img.shape[:2], bool) if valid is None else np.asarray(valid, bool)
    finite = np.isfinite(pm.dist) & (pm.radius > 0)
    r = np.where(finite, pm.radius, 0.0)
    body = finite & (pm.dist <= 1.5 * np.maximum(r, 0.5) + 1.5)
    centre = finite & (pm.dist <= 0.5) & ok
    if np.count_nonzero(centre) < 10:
        return None
    ground = local_ground(img, body | ~ok, _ground_sigma(r[centre]))
    dev = img - ground
    d_c = np.median(dev[centre], axis=0)
    amp0 = float(np.linalg.norm(d_c))
    if amp0 < 0.02:
        return None
    e = (d_c / amp0).astype(np.float32)
    proj = dev @ e
    rc = r[centre]
    qs = np.unique(np.quantile(rc, np.linspace(0.0, 1.0, 6)))
    radii, amps = [], []
    for lo, hi in zip(qs[:-1], qs[1:]) if len(qs) > 1 else [(qs[0], qs[0])]:
        sel = (rc >= lo) & (rc <= hi)
        if np.count_nonzero(sel) >= 5:
            radii.append(float(np.median(rc[sel])))
            amps.append(max(float(np.median(proj[centre][sel])), 0.0))
    radii, amps = np.asarray(radii), np.asarray(amps)
    order = np.argsort(radii)
    radii, amps = radii[order], amps[order]
    # shape across the line, relative to the centre amplitude at the pixel's radius
    u = np.where(finite, pm.dist / np.maximum(r, 0.5), np.inf)
    amp_px = np.interp(np.maximum(r, 0.5), radii, amps)
    rel = np.where(amp_px > 1e-3, proj / np.maximum(amp_px, 1e-3), 0.0)
    shape = np.full(len(_U), np.nan)
    for i, uu in enumerate(_U):
        sel = ok & (np.abs(u - uu) <= 0.125)
        if np.count_nonzero(sel) >= 5:
            shape[i] = float(np.median(rel[sel]))
    shape[0] = 1.0
    have = np.isfinite(shape)
    # bins no pixel falls in (thin lines: d / r takes few values) interpolated from their neighbours
    shape = np.interp(_U, _U[have], shape[have])
    # a profile falls off across the edge: monotone, in [0, 1]
    shape = np.minimum.accumulate(np.clip(shape, 0.0, 1.0))
    return LineProfile(e, radii, amps, _U.copy(), shape)


def restore_line_contrast(image, pm: PixelMap, profile: LineProfile, share: float = 0.85, *,
                          valid=None) -> tuple[np.ndarray, int]:
    """Give every target line pixel at least ``share`` of the example's line profile.

    A pixel at distance ``d`` of a centre line of radius ``r`` should stand
    out from the local ground by ``share * profile.target(d, r)`` along the
    profile's colour direction; a pixel that falls short is moved along it
    by the shortfall (never away), so stronger pixels and the fragments'
    texture stay as they are. On wide lines (radius 1.5 -> 3 px and more,
    blended in) a pixel is raised by at most the share of the wanted
    profile its neighbourhood misses (Gaussian, half a radius): a speckled line's dim
    pixels are its texture, not a gap (beyond the paper, issue 23: a 512 px
    fluorescent neuron's branch texture, Laplacian energy, 0.53 -> 0.77 of
    the example's; thin lines keep the per-pixel rule).

    Parameters
    ----------
    image : (H, W, C) array_like
        The synthesized image, float in [0, 1].
    pm : PixelMap
        The target structure's pixel map on the output.
    profile : LineProfile
        The example's (:func:`line_profile`).
    share : float, default 0.85
        Share of the example's median profile every line pixel reaches (0 =
        nothing changes).
    valid : (H, W) bool array_like, optional
        Pixels that may change; None = all.

    Returns
    -------
    image : (H, W, C) float32 ndarray
        A new image.
    n_changed : int
        Number of pixels moved.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching.skeleton_map import SkeletonMap
    >>> img = np.full((40, 40, 3), 0.8, np.float32); img[19:21, 2:38] = 0.2
    >>> s = Structure([Branch([(2, 19.5), (37, 19.5)], 1.0)])
    >>> pm = SkeletonMap(s, 1.0).pixel_map((40, 40))
    >>> prof = line_profile(img, pm)
    >>> faded = img.copy(); faded[19:21, 10:30] = 0.7                 # a pale gap
    >>> out, n = restore_line_contrast(faded, pm, prof)
    >>> bool(out[19, 20, 0] < 0.35), bool(np.allclose(out[5], 0.8))
    (True, True)
    """
    if not 0.0 <= float(share) <= 2.0:
        raise ValueError(f"share must lie in [0, 2], got {share}")
    img = np.array(image, dtype=np.float32, copy=True)
    if img.ndim == 2:
        img = img[..., None]
    if share == 0:
        return img, 0
    finite = np.isfinite(pm.dist) & (pm.radius > 0)
    r = np.where(finite, pm.radius, 0.0)
    # the line and its anti-aliased rim, not the glow or halo around it (the ground stays the fragments')
    reach = finite & (pm.dist <= np.minimum(profile.u[-1] * np.maximum(r, 0.5), r + 1.5))
    if valid is not None:
        reach &= np.asarray(valid, bool)
    if not reach.any():
        return img, 0
    body = finite & (pm.dist <= 1.5 * np.maximum(r, 0.5) + 1.5)
    ground = local_ground(img, body, _ground_sigma(r[reach]))
    e = profile.direction
    ys, xs = np.nonzero(reach)
    proj = (img[ys, xs] - ground[ys, xs]) @ e
    want = share * profile.target(pm.dist[ys, xs], r[ys, xs])
    short = np.maximum(want - proj, 0.0)
    rr = r[ys, xs]
    wide = np.clip((rr - 1.5) / 1.5, 0.0, 1.0)
    if wide.any():
        # On wide lines (r >= 3 px: a 192 px neuron's dendrites) a pixel is raised by no more than the
        # share its neighbourhood misses (Gaussian, half a radius): a gap still comes back in full, but the
        # line's own texture (speckle under the median) is no gap; raised pixel by pixel, a speckled
        # dendrite lost half its texture. Thin lines (r <= 1.5 px: cracks, capillaries) keep the
        # per-pixel rule: half a pixel off their centre line, one side is pale and must be drawn in.
        # (the share of ``want`` missing around, not the shortfall, is averaged: across a faded line
        # the centre wants more than the rim, and an averaged shortfall left a gap's centre pale)
        sp = np.zeros(reach.shape, np.float32)
        wp = np.zeros(reach.shape, np.float32)
        sp[ys, xs], wp[ys, xs] = short, want
        sigma = max(0.5 * float(np.median(rr[wide > 0])), 1.0)
        missing = cv2.GaussianBlur(sp, (0, 0), sigma) / np.maximum(cv2.GaussianBlur(wp, (0, 0), sigma), 1e-6)
        local = np.clip(missing[ys, xs], 0.0, 1.0) * want
        short = (1.0 - wide) * short + wide * np.minimum(short, local)
    move = short > 1e-3
    img[ys[move], xs[move]] += short[move, None] * e[None, :]
    np.clip(img, 0.0, 1.0, out=img)
    return img, int(np.count_nonzero(move))


def _centre_ring(pm: PixelMap) -> tuple[np.ndarray, np.ndarray]:
    r = np.where(np.isfinite(pm.radius), pm.radius, 1.0)
    line = pm.dist <= np.maximum(0.5, 0.4 * r)
    ring = (pm.dist >= r + 3) & (pm.dist <= r + 7)
    return line, ring


def centre_ring_contrast(image, pm: PixelMap) -> float:
    """Colour distance between the median centre-line pixel and the median ground pixel beside the lines.

    Centre-line pixels lie within ``max(0.5, 0.4 r)`` of the centre lines,
    ground pixels ``r + 3`` to ``r + 7`` from them (the measure of
    :func:`~branchnb.branching.measures.line_contrast`).

    Parameters
    ----------
    image : (H, W, C) array_like
        Image, float in [0, 1] (the first 3 channels are used).
    pm : PixelMap
        The structure's pixel map on the image.

    Returns
    -------
    float
        Euclidean distance of the two median colours (0 when either set is empty).

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching.skeleton_map import SkeletonMap
    >>> img = np.full((30, 30, 3), 0.8, np.float32); img[14:16, 2:28] = 0.3
    >>> pm = SkeletonMap(Structure([Branch([(2, 14.5), (27, 14.5)], 1.0)]), 1.0).pixel_map((30, 30))
    >>> round(centre_ring_contrast(img, pm), 2)
    0.87
    """
    colours = centre_ring_colours(image, pm)
    return 0.0 if colours is None else float(np.linalg.norm(colours[0] - colours[1]))


def centre_ring_colours(image, pm: PixelMap) -> tuple[np.ndarray, np.ndarray] | None:
    """Median colours of the centre-line pixels and of the ground beside the lines.

    The two sets of :func:`centre_ring_contrast` (whose value is the distance
    between these two colours).

    Parameters
    ----------
    image : (H, W, C) array_like
        Image, float in [0, 1] (the first 3 channels are used).
    pm : PixelMap
        The structure's pixel map on the image.

    Returns
    -------
    (line, ground) : pair of (C,) ndarrays, or None
        The median colours; None when either set is empty.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching.skeleton_map import SkeletonMap
    >>> img = np.full((30, 30, 3), 0.8, np.float32); img[14:16, 2:28] = 0.3
    >>> pm = SkeletonMap(Structure([Branch([(2, 14.5), (27, 14.5)], 1.0)]), 1.0).pixel_map((30, 30))
    >>> [[round(float(v), 2) for v in c] for c in centre_ring_colours(img, pm)]
    [[0.3, 0.3, 0.3], [0.8, 0.8, 0.8]]
    """
    img = np.asarray(image, np.float32)
    rgb = img[..., None] if img.ndim == 2 else img[..., :3]
    line, ring = _centre_ring(pm)
    if not line.any() or not ring.any():
        return None
    return np.median(rgb[line], 0), np.median(rgb[ring], 0)


def match_line_contrast(image, pm: PixelMap, reference: float, *, low: float = 0.85, high: float = 1.18,
                        k_range: tuple[float, float] = (0.2, 3.0), valid=None,
                        colours=None) -> tuple[np.ndarray, float]:
    """Scale the lines' difference to their local ground so they stand out as much as the example's.

    When the image's :func:`centre_ring_contrast` lies outside
    ``[low, high] * reference``, every pixel of the lines' bodies (within
    ``r + 1.5`` of a centre line) becomes ``ground + k (pixel - ground)``,
    ``ground`` the local ground (:func:`local_ground`), with the ``k`` in
    ``k_range`` that brings the contrast back to ``reference`` (bisection;
    the ground beside the lines does not move). Inside the band nothing
    changes.

    Parameters
    ----------
    image : (H, W, C) array_like
        The synthesized image, float in [0, 1].
    pm : PixelMap
        The target structure's pixel map on it.
    reference : float
        The example's :func:`centre_ring_contrast` (> 0).
    low, high : float, default 0.85, 1.18
        The accepted band of contrast ratios.
    k_range : (float, float), default (0.2, 3.0)
        Bounds of the scale ``k``.
    valid : (H, W) bool array_like, optional
        Pixels that may change; None = all.
    colours : (line, ground) pair of (C,) array_like, optional
        The example's median centre-line and ground colours
        (:func:`centre_ring_colours`). Beyond the paper: light lines on a
        darker ground (lightning, glowing filaments: they read by their
        core's brightness, not by their contrast) are never faded past the
        example's centre colour (``k`` stays at or above the scale that
        brings their median centre colour nearest to it). A bolt from a
        bright cloud relit into a dark sky stands out more because its ground
        changed; fading it to the example's contrast squashed its bright core
        into its glow (a flat tube). Dark lines (vessels, cracks, ink) are
        matched by contrast as before. None = no such floor.

    Returns
    -------
    image : (H, W, C) float32 ndarray
        A new image.
    k : float
        The scale applied (1 = unchanged).

    Raises
    ------
    ValueError
        If ``reference`` is not finite and >= 0, or the band or range is not increasing and positive.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching.skeleton_map import SkeletonMap
    >>> img = np.full((30, 30, 3), 0.8, np.float32); img[14:16, 2:28] = 0.3
    >>> pm = SkeletonMap(Structure([Branch([(2, 14.5), (27, 14.5)], 1.0)]), 1.0).pixel_map((30, 30))
    >>> out, k = match_line_contrast(img, pm, 0.5)
    >>> round(centre_ring_contrast(out, pm) / 0.5, 1)
    1.0
    """
    if not (np.isfinite(reference) and reference >= 0):
        raise ValueError(f"reference must be finite and >= 0, got {reference}")
    if not 0 < low <= 1.0 <= high:
        raise ValueError(f"low and high must satisfy 0 < low <= 1 <= high, got {low}, {high}")
    if not 0 < k_range[0] <= 1.0 <= k_range[1]:
        raise ValueError(f"k_range must satisfy 0 < k_range[0] <= 1 <= k_range[1], got {k_range}")
    img = np.array(image, dtype=np.float32, copy=True)
    if img.ndim == 2:
        img = img[..., None]
    nc = min(img.shape[2], 3)
    line, ring = _centre_ring(pm)
    if reference <= 0 or not line.any() or not ring.any():
        return img, 1.0
    rgb = img[..., :nc]
    ring_med = np.median(rgb[ring], 0)
    ratio = float(np.linalg.norm(np.median(rgb[line], 0) - ring_med)) / reference
    if low <= ratio <= high:
        return img, 1.0
    finite = np.isfinite(pm.dist) & (pm.radius > 0)
    r = np.where(finite, pm.radius, 0.0)
    body = finite & (pm.dist <= r + 1.5)
    if valid is not None:
        body &= np.asarray(valid, bool)
    if not body.any():
        return img, 1.0
    ground = local_ground(rgb, body, _ground_sigma(r[body]))
    ys, xs = np.nonzero(body)
    g, d = ground[ys, xs], rgb[ys, xs] - ground[ys, xs]
    on_line = line[ys, xs]
    g_l, d_l = g[on_line], d[on_line]

    def contrast(k):
        return float(np.linalg.norm(np.median(np.clip(g_l + k * d_l, 0.0, 1.0), 0) - ring_med)) / reference

    lo, hi = (k_range[0], 1.0) if ratio > high else (1.0, k_range[1])
    if colours is not None and ratio > high:
        c_line = np.asarray(colours[0], np.float32).ravel()[:nc]
        if float(c_line.mean()) > float(np.asarray(colours[1], np.float32).ravel()[:nc].mean()):
            ks = np.geomspace(lo, 1.0, 24)
            err = [float(np.linalg.norm(np.median(np.clip(g_l + k * d_l, 0.0, 1.0), 0) - c_line)) for k in ks]
            lo = float(ks[int(np.argmin(err))])
            if lo >= 1.0:
                return img, 1.0
    if (contrast(lo) - 1.0) * (contrast(hi) - 1.0) > 0:
        # the band cannot be reached (e.g. lines as pale as their ground): the nearer bound
        k = lo if ratio > high else hi
    else:
        for _ in range(14):
            mid = float(np.sqrt(lo * hi))
            if (contrast(mid) > 1.0) == (contrast(lo) > 1.0):
                lo = mid
            else:
                hi = mid
        k = float(np.sqrt(lo * hi))
    rgb[ys, xs] = np.clip(g + k * d, 0.0, 1.0)
    return img, k
