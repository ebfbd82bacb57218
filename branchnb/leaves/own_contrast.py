"""The contrast a thin layer makes on each exemplar, learnt from the exemplar itself (beyond the paper).

The paper induces a layer by its colour on the training leaf. A vein plays
the same *role* on every leaf (a thin line standing out from the blade
around it, where the warped training layer says it runs), but its colour is
the leaf's own: pale on a photographed maple, red on a clip-art oak, black
ink on a sketch. Projected on the training leaf's contrast direction
(:func:`~branchnb.leaves.snapping_evidence.contrast_direction`), red veins on green
answer nothing when the training veins are pale, and induction found none
of them (``python -m branchnb.leaves._measure_colours``: IoU 0.00 on every
pale -> red / dark pair).

:func:`exemplar_direction` re-estimates the direction on the exemplar: in
a band around the warped layer (the blade's outline band left out, the
outline is the blade's edge, never a vein), the blade's local high-pass
colour (colour minus its blurred surroundings); its strongest pixels, as
many as the warped layer covers, give the direction in which the
exemplar's own thin structures stand out. It replaces the training
direction only when its ridges stand out clearly more (``gain``), so a
leaf whose veins look like the training leaf's keeps the training direction.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_mask
from ..core.morphology import _binary_dilation, _binary_erosion, _binary_opening

__all__ = ["exemplar_direction", "without_blobs", "trim_to_ridges", "trim_by_contrast", "high_pass"]

#: The exemplar's own direction replaces the training leaf's when its ridge score is this much higher.
GAIN = 1.3
#: ... or when it turns at least this far from the training direction (cosine below) and scores no lower.
SAME_COLOUR = 0.7
#: An exemplar's own layer pixel (``exemplar_direction(..., return_pixels=True)``) stands out along the
#: direction at least this share of the median of the band's strongest pixels (leaves81).
STANDS_OUT = 0.3


def _score(proj: np.ndarray, n: int) -> float:
    """Mean of the ``n`` largest projections over their spread: how much a thin minority stands out."""
    top = np.partition(proj, len(proj) - n)[len(proj) - n:]
    return float(top.mean() / (proj.std() + 1e-6))


def exemplar_direction(lab, blade, prior, width: float, training_direction, *, radius: float,
                       gain: float = GAIN, same_colour: float = SAME_COLOUR,
                       return_pixels: bool = False):
    """The CIELAB direction in which exemplar ``lab``'s own thin layer stands out near ``prior``.

    Parameters
    ----------
    lab : (H, W, 3) float ndarray
        The exemplar's CIELAB colours.
    blade : (H, W) bool array_like
        Its blade.
    prior : (H, W) bool array_like
        The training layer carried onto the exemplar (warped).
    width : float
        The layer's typical width (px).
    training_direction : (3,) array_like
        The training leaf's contrast direction (unit).
    radius : float
        Band around ``prior`` searched (px; the registration error to tolerate).
    gain : float
        The exemplar's direction is taken when its ridge score is at least
        ``gain`` times the training direction's (default :data:`GAIN`), or
        when the cosine between the two is below ``same_colour`` (default
        :data:`SAME_COLOUR`: the exemplar's layer stands out in another
        colour) and it scores no lower.
    same_colour : float
        Cosine between the two directions below which the exemplar's layer
        counts as another colour (default :data:`SAME_COLOUR`).
    return_pixels : bool
        Also return the band's pixels that stand out most along the
        returned direction (at most as many as ``prior`` covers inside the
        band, see Notes): the exemplar's own layer pixels, for its colour model.

    Returns
    -------
    direction : (3,) ndarray
        Unit vector: the exemplar's own, or ``training_direction``.
    own : bool
        Whether the exemplar's own direction was taken.
    pixels : (H, W) bool ndarray
        Only with ``return_pixels``.

    Notes
    -----
    Beyond the paper (leaves81): of the ``n`` strongest pixels only those standing out at least
    :data:`STANDS_OUT` times the median of the ``n`` are returned. Where the exemplar's veins cover
    less than the warped layer (a lighter leaf of a family), the count was made up with blade texture
    specks, the pale insides of insect holes and their dark rims; as the exemplar's own colour model
    (:func:`~branchnb.leaves.analysis_own._under_induced`) they took blade along every vein. Vein IoU of
    the worst exemplars, birch-like families with marks (``tests/leaves_marks.py``): hole rims 500 px
    0.55 / 0.22 -> 0.94 / 0.90, rust spots 160 px 0.83 / 0.73 -> 0.94 / 0.97, blotches 450 px 0.58 ->
    0.87; hole rims 300 px 0.73 / 0.77 -> 0.71 / 0.71 and 320 px 0.71 -> 0.69 (the losses measured); the sample maples'
    masks unchanged. The rule needs the veins to be at least half of the ``n``: a vein far narrower
    than the warped layer still gets blade texture (a noise floor on the band's projections fixed
    that, but moved the sample maples' retuned masks: not taken).

    leaves88: a pixel's projection counts only as far as it stands above both its sides (the
    projection of its colour less its grey opening, wider than the layer's median width and the
    carried layer's thickest part): the pale side of a step edge is no line. Procedural variegated
    leaves with a dark margin band round a pale centre (``tests/test_leaves_dark_band.py``, seeds
    40-43): vein IoU of exemplars 1-3 at 256 px 0.533 / 0.868 / 0.892 -> 0.841 / 0.866 / 0.908, at
    192 px 0.554 / 0.700 / 0.255 -> 0.794 / 0.818 / 0.396; band IoU there 0.938 -> 0.923 (256 px),
    0.929 / 0.897 -> 0.900 / 0.883 (192 px); cream bands (240 px seeds 40-43, 320 px seeds 44-47)
    unchanged. At the median width alone the midribs stood above nothing (cream 320 px 0.96 -> 0.66).

    Examples
    --------
    >>> import numpy as np
    >>> lab = np.zeros((40, 40, 3)); lab[..., 0] = 50; lab[..., 1] = -30
    >>> lab[:, 19:21, 1] = 40                     # a red line on a green blade
    >>> blade = np.ones((40, 40), bool); prior = np.zeros((40, 40), bool); prior[:, 17:19] = True
    >>> d, own = exemplar_direction(lab, blade, prior, 2.0, [1.0, 0, 0], radius=4.0)
    >>> own, bool(d[1] > 0.9)
    (True, True)
    """
    lab = np.asarray(lab, np.float64)
    if lab.ndim != 3 or lab.shape[2] != 3:
        raise ValueError(f"lab must be (H, W, 3), got shape {lab.shape}")
    blade = as_mask(blade, shape=lab.shape[:2], name="blade")
    prior = as_mask(prior, shape=lab.shape[:2], name="prior")
    td = np.asarray(training_direction, np.float64).ravel()
    if td.shape != (3,) or not np.all(np.isfinite(td)):
        raise ValueError(f"training_direction must be 3 finite numbers, got {training_direction!r}")
    if not np.isfinite(width) or width <= 0:
        raise ValueError(f"width must be positive, got {width!r}")
    if not np.isfinite(radius) or radius < 0:
        raise ValueError(f"radius must be non-negative, got {radius!r}")
    if not np.isfinite(gain) or gain < 1:
        raise ValueError(f"gain must be at least 1, got {gain!r}")
    if not np.isfinite(same_colour) or not -1 <= same_colour <= 1:
        raise ValueError(f"same_colour must be in [-1, 1], got {same_colour!r}")

    def out(d, took, proj=None, n=0):
        if not return_pixels:
            return d, took
        pix = np.zeros(blade.shape, bool)
        if proj is not None and n > 0:
            # A line stands above both its sides; the pale side of a step (a dark margin band's inner
            # edge) stands out of the high-pass as much, and was taken as the exemplar's vein (leaves88).
            # The opening is wider than the carried layer's thickest part: at the median width the
            # midribs stood above nothing (cream band 320 px, vein IoU 0.96 -> 0.66).
            wide = 2 * max(int(np.ceil(w)), _thickest(prior) + 2) + 3
            proj = np.minimum(proj, _line_part(lab @ d, wide)[band])
        if proj is not None and n > 0:
            keep = np.zeros(len(proj), bool)
            top = np.argpartition(proj, len(proj) - n)[len(proj) - n:]
            # Where the exemplar's own layer covers less than the warped one, the count is made up
            # with blade texture and marks (see Notes): only the pixels that stand out clearly.
            top = top[proj[top] >= STANDS_OUT * float(np.median(proj[top]))]
            keep[top] = True
            pix[band] = keep
        return d, took, pix
    td = td / max(float(np.linalg.norm(td)), 1e-9)
    w = max(1.0, float(width))
    size = 2 * int(np.ceil(w)) + 3
    # The outline band: a blade's edge (and ink drawn along it) is never a vein.
    inner = _binary_erosion(blade, iterations=int(np.ceil(w)) + 2)
    band = _binary_dilation(prior, iterations=max(1, int(round(radius)))) & inner
    n = int(min((prior & inner).sum(), 0.3 * band.sum()))
    if n < 10:
        return out(td, False)
    sigma = w + 1.0
    b = blade.astype(np.float64)
    norm = ndi.gaussian_filter(b, sigma)
    hp = np.empty_like(lab)
    for c in range(3):
        hp[..., c] = lab[..., c] - ndi.gaussian_filter(lab[..., c] * b, sigma) / np.maximum(norm, 1e-6)
    mag = np.sqrt(np.einsum("ijk,ijk->ij", hp, hp))
    # Lines, not blobs: what a grey opening wider than the layer removes
    # (a spot's colour would otherwise pull the direction towards it).
    line = mag - ndi.grey_opening(mag, size=(size, size))
    v = hp[band]
    lv = line[band]
    top = np.argpartition(lv, len(lv) - n)[len(lv) - n:]
    d = v[top].mean(0)
    nd = float(np.linalg.norm(d))
    if nd < 1e-6:
        return out(td, False, v @ td, n)
    d = d / nd
    s_own, s_t = _score(v @ d, n), _score(v @ td, n)
    if s_own >= gain * s_t or (float(d @ td) < same_colour and s_own >= s_t):
        return out(d, True, v @ d, n)
    return out(td, False, v @ td, n)


def _line_part(q, size: int):
    """``q`` minus its grey opening by a ``size`` square: what stands above both sides of a line."""
    return q - ndi.grey_opening(q, size=(size, size))


def _thickest(mask) -> int:
    """Radius of the largest disk an opening of ``mask`` keeps 5 % of it with (0: none)."""
    from skimage.morphology import disk
    total = max(int(mask.sum()), 1)
    r = 0
    while r < 20 and _binary_opening(mask, structure=disk(r + 1)).sum() >= 0.05 * total:
        r += 1
    return r


def without_blobs(m, user, blade_t, blade_e):
    """A thin layer's induced mask on an exemplar without its blobs (beyond the paper).

    The exemplar's own colour model of a thin layer (its own layer pixels,
    chosen in :mod:`branchnb.leaves.analysis`) also matches spots of a
    like colour (red veins and brown spots): the vein layer took the spots
    of a red-veined procedural leaf, and the spots layer lost them. A part
    of the induced mask that holds a disk wider than any the user's layer
    holds (scaled by the blades' sizes), grown by the disk, is no vein and
    is left out.

    Parameters
    ----------
    m : (H, W) bool ndarray
        The induced mask on the exemplar.
    user : (H, W) bool ndarray
        The user's layer on the training leaf.
    blade_t, blade_e : (H, W) bool ndarray
        The training leaf's and the exemplar's blades.

    Returns
    -------
    (H, W) bool ndarray
        ``m`` without its blobs.
    """
    from skimage.morphology import disk
    r = int(np.ceil((_thickest(user) + 1) * np.sqrt(float(blade_e.sum()) / max(float(blade_t.sum()), 1.0))))
    blobs = _binary_opening(m, structure=disk(r + 1))
    if not blobs.any():
        return m
    return m & ~_binary_dilation(blobs, structure=disk(r + 1))


#: A thin layer's pixel stays when its own contrast along the layer's
#: direction is at least this share of the median on the layer's centre line.
TRIM_LEVEL = 0.35


def high_pass(lab, blade, sigma: float) -> np.ndarray:
    """Each blade pixel's CIELAB minus the blade's Gaussian mean around it (``sigma`` px).

    Parameters
    ----------
    lab : (H, W, 3) float ndarray
        CIELAB image.
    blade : (H, W) bool ndarray
        The blade; pixels off it do not enter the mean.
    sigma : float
        Standard deviation (px) of the Gaussian mean.

    Returns
    -------
    (H, W, 3) float64 ndarray
    """
    lab = np.asarray(lab, np.float64)
    b = np.asarray(blade, bool).astype(np.float64)
    norm = np.maximum(ndi.gaussian_filter(b, sigma), 1e-6)
    hp = np.empty_like(lab)
    for c in range(3):
        hp[..., c] = lab[..., c] - ndi.gaussian_filter(lab[..., c] * b, sigma) / norm
    return hp


def trim_to_ridges(mask, lab, blade, direction, width: float, *, level: float = TRIM_LEVEL):
    """A thin layer's induced ``mask`` cut to the pixels that stand out themselves (beyond the paper).

    ``S_e`` compares the colours of an ``n x n`` neighbourhood, so the blade
    next to a vein, whose neighbourhood holds the vein, is induced with it:
    a 1-2 px dark vein came out 4-6 px wide (procedural pale -> dark
    veins, IoU 0.56). A pixel of ``mask`` stays when its high-pass colour
    (:func:`high_pass`, ``sigma`` = width + 1) projected on ``direction`` is
    at least ``level`` times the median of that projection on the mask's
    skeleton; the skeleton always stays (the layer keeps its connections).

    Parameters
    ----------
    mask : (H, W) bool array_like
        The induced layer on the exemplar.
    lab : (H, W, 3) array_like
        The exemplar's CIELAB colours.
    blade : (H, W) bool array_like
        Its blade.
    direction : (3,) array_like
        The CIELAB direction the layer stands out in on this exemplar.
    width : float
        The layer's typical width (px).
    level : float
        Share of the skeleton's median contrast (default :data:`TRIM_LEVEL`).

    Returns
    -------
    (H, W) bool ndarray

    Examples
    --------
    >>> import numpy as np
    >>> lab = np.zeros((30, 30, 3)); lab[..., 0] = 60; lab[:, 14:16, 0] = 30   # a dark 2 px line
    >>> m = np.zeros((30, 30), bool); m[:, 11:19] = True                      # induced 8 px wide
    >>> int(trim_to_ridges(m, lab, np.ones((30, 30), bool), [-1.0, 0, 0], 2.0)[15].sum())
    2
    """
    mask = as_mask(mask, name="mask")
    blade = as_mask(blade, shape=mask.shape, name="blade")
    d = np.asarray(direction, np.float64).ravel()
    if d.shape != (3,) or not np.all(np.isfinite(d)) or np.linalg.norm(d) < 1e-9:
        raise ValueError(f"direction must be 3 finite numbers, not all 0, got {direction!r}")
    if not mask.any():
        return mask
    d = d / np.linalg.norm(d)
    return trim_by_contrast(mask, high_pass(lab, blade, max(1.0, float(width)) + 1.0) @ d, level=level)


def trim_by_contrast(mask, contrast, *, level: float = TRIM_LEVEL):
    """:func:`trim_to_ridges` with each pixel's contrast along the layer's direction given (``contrast``).

    Parameters
    ----------
    mask : (H, W) bool ndarray
        A thin layer's induced mask.
    contrast : (H, W) float ndarray
        Each pixel's high-pass colour projected on the layer's direction.
    level : float, optional
        Share of the median contrast on the mask's skeleton a pixel keeps.

    Returns
    -------
    (H, W) bool ndarray
    """
    from skimage.morphology import skeletonize
    mask = as_mask(mask, name="mask")
    p = np.asarray(contrast)
    if p.shape != mask.shape:
        raise ValueError(f"contrast must have the mask's shape {mask.shape}, got {p.shape}")
    if not mask.any():
        return mask
    skel = skeletonize(mask)
    ref = float(np.median(p[skel])) if skel.any() else 0.0
    if ref <= 0:
        return mask
    return mask & ((p >= level * ref) | skel)
