"""The colour term ``S_e`` of layer induction (Assa & Cohen-Or 2012, section 4): CIELAB
quantisation shared by all exemplars and the local cumulative histograms of every pixel's
neighbourhood against a layer's (see :mod:`branchnb.leaves.induction` for the variant used).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np
from skimage.color import rgb2lab

from ..core.image import as_mask, as_rgb

__all__ = ["ColourSpace", "blade_lab_stats", "colour_space", "quantise", "layer_cdfs", "colour_similarity"]


@dataclass(frozen=True)
class ColourSpace:
    """CIELAB quantisation shared by all exemplars.

    Parameters
    ----------
    lo, hi : (3,) ndarray
        Per-channel range (1st / 99th percentile of the exemplars' blades).
    bins : int
        Bins per channel.
    """

    lo: np.ndarray
    hi: np.ndarray
    bins: int

    @property
    def weights(self) -> np.ndarray:
        """Each channel's share of the summed span (Lab units): channel weights of ``S_e``."""
        span = np.asarray(self.hi, np.float64) - np.asarray(self.lo, np.float64)
        return span / span.sum()


def _lab(image) -> np.ndarray:
    return rgb2lab(as_rgb(image, name="image")).astype(np.float32)


def colour_space(images, blades, bins: int = 32, *, labs=None) -> ColourSpace:
    """The CIELAB range of the blades of ``images`` (robust: 1st to 99th percentile).

    Parameters
    ----------
    images : sequence of (H, W, 3|4) array_like
        The exemplars, RGB(A) in [0, 1].
    blades : sequence of (H, W) bool array_like
        Their blades; only blade pixels count.
    bins : int
        Bins per channel, ``>= 2`` (default 32).
    labs : sequence of (H, W, 3) float32 ndarray, optional
        The images' CIELAB when already converted (the same values; one
        conversion fewer per exemplar).

    Returns
    -------
    ColourSpace
        A channel without spread still gets a range of 2 Lab units.

    Examples
    --------
    >>> import numpy as np
    >>> cs = colour_space([np.full((4, 4, 3), 0.5)], [np.ones((4, 4), bool)], bins=8)
    >>> cs.bins, bool(np.all(cs.hi > cs.lo))
    (8, True)
    """
    if not isinstance(bins, (int, np.integer)) or bins < 2:
        raise ValueError(f"bins must be an int >= 2, got {bins!r}")
    samples = []
    for i, (img, b) in enumerate(zip(images, blades)):
        lab = _lab(img) if labs is None else labs[i]
        b = as_mask(b, shape=lab.shape[:2], name=f"blades[{i}]")
        px = lab[b]
        if len(px) > 200000:
            px = px[:: len(px) // 200000 + 1]
        samples.append(px)
    if not samples or sum(len(s) for s in samples) == 0:
        raise ValueError("blades select no pixel")
    allpx = np.concatenate(samples)
    lo = np.percentile(allpx, 1, axis=0)
    hi = np.percentile(allpx, 99, axis=0)
    # A channel without spread still gets a range of a few Lab units.
    span = np.maximum(hi - lo, 2.0)
    mid = 0.5 * (hi + lo)
    return ColourSpace(mid - span / 2, mid + span / 2, int(bins))



def blade_lab_stats(image, blade, *, lab=None) -> tuple[np.ndarray, np.ndarray]:
    """Mean and standard deviation of the CIELAB channels over a blade.

    Parameters
    ----------
    image : (H, W, 3|4) array_like
        The leaf, RGB(A) in [0, 1].
    blade : (H, W) bool array_like
        Its blade.
    lab : (H, W, 3) float32 ndarray, optional
        The image's CIELAB when already converted (the same values).

    Returns
    -------
    mean, std : (3,) float32 ndarray
        ``std`` at least 1e-3.
    """
    px = (_lab(image) if lab is None else lab)[as_mask(blade, name="blade")]
    return px.mean(0), np.maximum(px.std(0), 1e-3)


def quantise(image, space: ColourSpace, *, stats=None, reference=None) -> np.ndarray:
    """Per-channel CIELAB bin index of every pixel: (H, W, 3) uint8 in ``[0, bins)``.

    With ``stats`` (this leaf's blade mean and std, :func:`blade_lab_stats`)
    and ``reference`` (the training leaf's), the channels are first moved
    affinely onto the reference's, so leaves of one kind whose overall
    colour differs (autumn leaves: yellow, orange, brown) compare by their
    pattern rather than their hue.

    Parameters
    ----------
    image : (H, W, 3|4) array_like
        The leaf, RGB(A) in [0, 1].
    space : ColourSpace
        The shared range and bin count.
    stats : (mean, std), optional
        This leaf's blade statistics; None: no colour matching.
    reference : (mean, std), optional
        The training leaf's; used only together with ``stats``.

    Returns
    -------
    (H, W, 3) uint8 ndarray
    """
    lab = _lab(image)
    if stats is not None and reference is not None:
        lab = (lab - stats[0]) / stats[1] * reference[1] + reference[0]
    return _quantise_lab(lab, space)


def _quantise_lab(lab, space: ColourSpace) -> np.ndarray:
    """:func:`quantise` of colours already in CIELAB (and already colour-matched, if wanted).

    Parameters
    ----------
    lab : (H, W, 3) array_like
        CIELAB colours.
    space : ColourSpace
        The shared range and bin count.

    Returns
    -------
    (H, W, 3) uint8 ndarray

    Examples
    --------
    >>> import numpy as np
    >>> cs = ColourSpace(np.zeros(3), np.full(3, 100.0), 4)
    >>> _quantise_lab(np.full((1, 2, 3), 60.0), cs)[0, 0].tolist()
    [2, 2, 2]
    """
    lab = np.asarray(lab)
    if lab.ndim != 3 or lab.shape[2] != 3:
        raise ValueError(f"lab must be an (H, W, 3) array, got shape {lab.shape}")
    t = (lab - space.lo) / (space.hi - space.lo)
    q = np.floor(np.clip(t, 0.0, 1.0 - 1e-6) * space.bins)
    return q.astype(np.uint8)


def layer_cdfs(q: np.ndarray, mask, bins: int) -> np.ndarray:
    """Cumulative histograms (3, bins) of the quantised colours under ``mask``.

    Parameters
    ----------
    q : (H, W, 3) uint8 ndarray
        Quantised colours (:func:`quantise`).
    mask : (H, W) bool array_like
        The layer's pixels (not empty).
    bins : int
        Bins per channel (``space.bins``).

    Returns
    -------
    (3, bins) float ndarray
        Per channel, rising to 1.
    """
    mask = as_mask(mask, shape=q.shape[:2], name="mask")
    if not mask.any():
        raise ValueError("mask selects no pixel: the layer is empty")
    out = np.empty((3, bins))
    for ch in range(3):
        h = np.bincount(q[..., ch][mask], minlength=bins).astype(np.float64)
        out[ch] = np.cumsum(h) / h.sum()
    return out


def colour_similarity(q: np.ndarray, blade, cdfs: np.ndarray, size: int, weights=None) -> np.ndarray:
    """``S_e(x, c)`` for every pixel and layer: normalised per-channel EMD, averaged over L, a, b.

    Parameters
    ----------
    q : (H, W, 3) uint8
        Quantised colours (:func:`quantise`).
    blade : (H, W) bool
        Pixels that count in a neighbourhood.
    cdfs : (K, 3, bins) or (3, bins) ndarray
        Cumulative histograms of the K user layers (:func:`layer_cdfs`).
    size : int
        Neighbourhood side ``n``.
    weights : (3,) array_like, optional
        Weight of each channel's normalised EMD (summing to 1); equal by
        default. :attr:`ColourSpace.weights` (each channel's span in Lab
        units) makes ``S_e`` the EMD in Lab units over the largest possible.

    Returns
    -------
    S : (K, H, W) (or (H, W) for one layer) float32 ndarray in [0, 1]
        1 outside the blade and where a neighbourhood holds no blade pixel.

    Examples
    --------
    >>> import numpy as np
    >>> q = np.zeros((6, 6, 3), np.uint8); q[:, 3:] = 3
    >>> blade = np.ones((6, 6), bool)
    >>> s = colour_similarity(q, blade, layer_cdfs(q, q[..., 0] == 0, 4), 2)
    >>> float(s[0, 0]), float(s[0, 5])
    (0.0, 1.0)
    """
    blade = as_mask(blade, shape=q.shape[:2], name="blade")
    cdfs = np.asarray(cdfs, np.float64)
    single = cdfs.ndim == 2
    if single:
        cdfs = cdfs[None]
    k, _, bins = cdfs.shape
    if not isinstance(size, (int, np.integer)) or size < 1:
        raise ValueError(f"size must be a positive int, got {size!r}")
    size = int(size)
    if weights is None:
        w = np.full(3, 1.0 / 3.0)
    else:
        w = np.asarray(weights, np.float64).reshape(-1)
        if w.shape != (3,) or not np.all(np.isfinite(w)) or np.any(w < 0) or w.sum() <= 0:
            raise ValueError(f"weights must be 3 non-negative finite numbers, got {weights!r}")
        w = w / w.sum()
    wch = (w / (bins - 1)).astype(np.float32)
    rows, cols = np.flatnonzero(blade.any(1)), np.flatnonzero(blade.any(0))
    y0, y1 = (int(rows[0]), int(rows[-1]) + 1) if len(rows) else (0, blade.shape[0])
    x0, x1 = (int(cols[0]), int(cols[-1]) + 1) if len(cols) else (0, blade.shape[1])
    if (y1 - y0, x1 - x0) != blade.shape:
        # Pixels off the blade count in no neighbourhood: on the blade's box
        # the sums are the same (a padded canvas is 2-5x larger), 1 elsewhere.
        out = np.ones((k,) + q.shape[:2], np.float32)
        out[:, y0:y1, x0:x1] = colour_similarity(np.ascontiguousarray(q[y0:y1, x0:x1]), blade[y0:y1, x0:x1],
                                                 cdfs, size, weights=w)
        return out[0] if single else out
    bf = blade.astype(np.float32)
    ksize = (size, size)

    def box(a):
        return cv2.boxFilter(a, -1, ksize, normalize=False, borderType=cv2.BORDER_CONSTANT)

    if size == 1:
        # A one-pixel window: the EMD of a point mass at bin k against the
        # layer is a lookup, sum_{b<k} G(b) + sum_{k<=b<B-1} (1 - G(b)).
        total = np.zeros((k,) + q.shape[:2], np.float32)
        for ch in range(3):
            for j in range(k):
                g = cdfs[j, ch, :bins - 1]
                below = np.concatenate([[0.0], np.cumsum(g)])  # sum_{b<k} G(b), k = 0..B-1
                above = np.concatenate([np.cumsum((1.0 - g)[::-1])[::-1], [0.0]])  # sum_{b>=k} (1 - G(b))
                lut = (below + above).astype(np.float32)
                total[j] += wch[ch] * lut[q[..., ch]]
        s = total
        s[:, ~blade] = 1.0
        np.clip(s, 0.0, 1.0, out=s)
        return s[0] if single else s
    count = box(bf)
    inv = np.where(count > 0.5, 1.0 / np.maximum(count, 1e-6), 0.0).astype(np.float32)
    total = np.zeros((k,) + q.shape[:2], np.float32)
    g = cdfs.astype(np.float32)
    for ch in range(3):
        # Off the blade a bin no b reaches (b < bins - 1 <= 255): (qb <= b) == ((q <= b) & blade).
        qb = np.where(blade, q[..., ch], np.uint8(255))
        for b in range(bins - 1):  # the last cumulative bin is 1 for both
            # Counts of 0/1 pixels are exact in float32 from a uint8 box as from a float one.
            counts = cv2.boxFilter((qb <= b).view(np.uint8), cv2.CV_32F, ksize, normalize=False,
                                   borderType=cv2.BORDER_CONSTANT)
            _add_emd_terms(total, counts, inv, np.ascontiguousarray(g[:, ch, b]), wch[ch])
    s = total
    s[:, ~blade | (count < 0.5)] = 1.0
    np.clip(s, 0.0, 1.0, out=s)
    return s[0] if single else s



@numba.njit(cache=True, nogil=True)
def _add_emd_terms(total, counts, inv, g, w):  # pragma: no cover - compiled
    """``total[j] += |counts * inv - g[j]| * w`` for every layer ``j``, in float32 (NumPy's operations, fused).

    One pass per cumulative bin instead of four NumPy passes per layer; the
    same float32 operations in the same order, so the same sums.
    """
    k = total.shape[0]
    h, wd = counts.shape
    for j in range(k):
        gj = g[j]
        for y in range(h):
            for x in range(wd):
                total[j, y, x] += abs(counts[y, x] * inv[y, x] - gj) * w
