"""Translucent tree sources (beyond the paper): watercolour washes, airbrushed crowns, glass trees.

The paper thresholds a source's alpha at 0.5. Scanned watercolours, soft airbrushed game art,
glass or ghost trees and "colour to alpha" cut-outs paint their crowns as wide washes of alpha
0.3-0.45 (more where the pigment pools at the rim): at 0.5 only the pooled rim is the tree and every
variation comes out with a hollow crown, or the whole tree is refused as transparent.

:func:`translucent_level` tells such a source from an opaque one and picks the level its
silhouette is taken at; :func:`to_working_alpha` remaps the alpha so that level becomes 0.5
(every later step keeps the paper's threshold), :func:`from_working_alpha` undoes it so the
exemplar keeps its source's own soft alpha, which the variation carries through the mix
(:func:`~branchnb.trees.variations.make_variation`): a translucent crown stays translucent.

Examples
--------
>>> import numpy as np
>>> a = np.zeros((64, 64), np.float32); a[8:40, 12:52] = 0.35; a[40:60, 30:34] = 1.0
>>> round(translucent_level(a), 3)
0.175
>>> b = np.zeros((64, 64), np.float32); b[8:40, 12:52] = 1.0
>>> translucent_level(b)
0.5
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.validate import Real, checked

__all__ = ["translucent_level", "to_working_alpha", "from_working_alpha", "TRANSLUCENT_SHARE",
           "TRANSLUCENT_WIDTH", "TRANSLUCENT_LEVEL", "TRANSLUCENT_CONTACT"]

#: A source is translucent when its wide soft regions that belong to the tree cover at least this
#: share of the tree (soft regions plus the pixels at or above the threshold).
TRANSLUCENT_SHARE = 0.2
#: Soft pixels count as "wide" when their whole disc of this radius (px) is soft: an anti-aliased
#: edge (1-2 px) or a slightly feathered cut-out never is.
TRANSLUCENT_WIDTH = 2
#: The silhouette is taken at this share of the median alpha of the tree's soft regions (the
#: wash's own level), clipped to [TRANSLUCENT_MIN, threshold - 0.05].
TRANSLUCENT_LEVEL = 0.5
TRANSLUCENT_MIN = 0.05
#: A soft region outside the filled opaque part belongs to the tree when at least this share of
#: its border touches the opaque part (an airbrushed halo round an opaque core: about half; a cast
#: shadow crossed by the trunk foot: a few per cent).
TRANSLUCENT_CONTACT = 0.25
#: Pixels with alpha above this are painted at all.
_PAINTED = 0.02


@checked(threshold=Real(0, 1, low_open=True))
def translucent_level(alpha, threshold: float = 0.5) -> float:
    """The alpha level a source's silhouette is taken at: ``threshold`` for an opaque source, lower
    for a translucent one.

    Parameters
    ----------
    alpha : (H, W) array_like
        The source's alpha in [0, 1].
    threshold : float
        The opacity threshold (paper: 0.5).

    Returns
    -------
    float
        ``threshold`` unless the source is translucent; then ``TRANSLUCENT_LEVEL`` times the
        median alpha of its wide soft regions, within ``[TRANSLUCENT_MIN, threshold - 0.05]``.

    Notes
    -----
    Beyond the paper. Soft pixels (painted, alpha below ``threshold``) form wide regions when they
    survive an erosion by a disc of radius ``TRANSLUCENT_WIDTH``. Such a region belongs to the tree
    when it lies mostly inside the opaque part with its holes filled (a wash inside a pooled rim),
    when at least ``TRANSLUCENT_CONTACT`` of its border touches the opaque part (an airbrushed halo),
    or when nearly nothing is opaque (a glass tree, the largest region). A detached cast-shadow
    ellipse or one crossed only by the trunk foot (a flat region in the bottom fifth of the tree)
    does not belong; any other region touching the opaque part does (a glass crown on an opaque
    trunk). The source is translucent when
    those regions cover at least ``TRANSLUCENT_SHARE`` of the tree.
    """
    a = np.asarray(alpha, np.float32)
    if a.ndim != 2:
        raise ValueError(f"alpha must be (H, W), got shape {a.shape}")
    painted = a > _PAINTED
    opaque = a >= threshold
    soft = painted & ~opaque
    if soft.sum() < TRANSLUCENT_SHARE * max(int(painted.sum()), 1):
        return float(threshold)
    r = TRANSLUCENT_WIDTH
    yy, xx = np.mgrid[-r:r + 1, -r:r + 1]
    disc = yy * yy + xx * xx <= r * r
    wide = ndi.binary_erosion(soft, disc)
    if not wide.any():
        return float(threshold)
    eight = np.ones((3, 3), bool)
    lab, n = ndi.label(soft, structure=eight)
    idx = np.arange(1, n + 1)
    has_wide = np.asarray(ndi.maximum(wide, lab, idx)) > 0
    area = np.asarray(ndi.sum(np.ones_like(soft), lab, idx))
    if opaque.sum() < 0.05 * painted.sum():     # a glass tree: nothing opaque, the largest wash is it
        belong = has_wide & (area == area[has_wide].max()) if has_wide.any() else has_wide
    else:
        inside = np.asarray(ndi.mean(ndi.binary_fill_holes(opaque), lab, idx)) >= 0.5
        border = soft & ~ndi.binary_erosion(soft, eight)
        touch = border & ndi.binary_dilation(opaque, eight)
        contact = np.asarray(ndi.sum(touch, lab, idx)) / np.maximum(np.asarray(ndi.sum(border, lab, idx)), 1)
        # a cast shadow lies at the foot, flat: in the bottom fifth of the tree, wider than tall
        ys = np.nonzero(painted)[0]
        foot = ys.min() + 0.8 * (ys.max() - ys.min())
        cy = np.asarray(ndi.mean(np.indices(a.shape)[0], lab, idx))
        spans = ndi.find_objects(lab)
        flat = np.array([(sl[0].stop - sl[0].start) < 0.5 * (sl[1].stop - sl[1].start) for sl in spans])
        shadow = (cy >= foot) & flat
        belong = has_wide & (inside | (contact >= TRANSLUCENT_CONTACT) | ((contact > 0) & ~shadow))
    if not belong.any():
        return float(threshold)
    region = np.isin(lab, idx[belong])
    if region.sum() < TRANSLUCENT_SHARE * (region.sum() + opaque.sum()):
        return float(threshold)
    level = TRANSLUCENT_LEVEL * float(np.median(a[region]))
    return float(np.clip(level, TRANSLUCENT_MIN, threshold - 0.05))


def _two_piece(alpha: np.ndarray, x0: float, y0: float) -> np.ndarray:
    """``alpha`` mapped piecewise linearly through (0, 0), (x0, y0), (1, 1)."""
    a = np.clip(np.asarray(alpha, np.float32), 0.0, 1.0)
    lo = a * (y0 / x0)
    hi = y0 + (a - x0) * ((1.0 - y0) / (1.0 - x0))
    return np.where(a < x0, lo, hi).astype(np.float32)


def to_working_alpha(alpha: np.ndarray, level: float, threshold: float = 0.5) -> np.ndarray:
    """``alpha`` remapped piecewise linearly so that ``level`` becomes ``threshold`` (0 and 1 stay).

    Parameters
    ----------
    alpha : (H, W) array_like
        A source's alpha, in [0, 1].
    level : float
        The source's silhouette level (:func:`translucent_level`).
    threshold : float, default 0.5
        The working images' opacity threshold.

    Returns
    -------
    (H, W) float32 ndarray
        ``alpha`` itself (clipped) when ``level >= threshold``.

    Examples
    --------
    >>> import numpy as np
    >>> [round(float(v), 3) for v in to_working_alpha(np.array([0.0, 0.1, 0.2, 1.0]), 0.2)]
    [0.0, 0.25, 0.5, 1.0]
    """
    if level >= threshold:
        return np.clip(np.asarray(alpha, np.float32), 0.0, 1.0)
    return _two_piece(alpha, level, threshold)


def from_working_alpha(alpha: np.ndarray, level: float, threshold: float = 0.5) -> np.ndarray:
    """Inverse of :func:`to_working_alpha`.

    Parameters
    ----------
    alpha : (H, W) array_like
        A working alpha, in [0, 1].
    level : float
        The source's silhouette level (:func:`translucent_level`).
    threshold : float, default 0.5
        The working images' opacity threshold.

    Returns
    -------
    (H, W) float32 ndarray

    Examples
    --------
    >>> import numpy as np
    >>> [round(float(v), 3) for v in from_working_alpha(np.array([0.0, 0.25, 0.5, 1.0]), 0.2)]
    [0.0, 0.1, 0.2, 1.0]
    """
    if level >= threshold:
        return np.clip(np.asarray(alpha, np.float32), 0.0, 1.0)
    return _two_piece(alpha, threshold, level)


def _feather_width(exemplar, most: float) -> float:
    """How far (px, 95th percentile) a translucent exemplar's painted alpha reaches outside its
    silhouette (at most ``most``): the widest fall-off a mix of it may continue its alpha by
    (:func:`~branchnb.trees.variations._translucent_alpha`, issue 24, trees48)."""
    soft = exemplar.normalized.soft_alpha
    if soft is None:
        return float(most)
    op = exemplar.image[..., 3] >= 0.5
    if not op.any() or soft.shape != op.shape:
        return float(most)
    dist = ndi.distance_transform_edt(~op)
    ring = ~op & (soft > 0.02) & (dist <= most + 2)
    return float(np.clip(np.percentile(dist[ring], 95), 1.0, most)) if ring.any() else 1.0


#: Share of its sources' most alpha from which a translucent crown counts as its core
#: (:func:`_halo_envelope`).
HALO_CORE = 0.9


def _halo_envelope(exemplars, most: float) -> tuple[float, np.ndarray] | None:
    """(core level, envelope): the sources' soft alpha by whole-pixel distance outside their
    cores (alpha at least :data:`HALO_CORE` of their most), the 95th percentile at each distance
    (upper envelope, non-increasing, 0 where no source reaches), for crowns with an airbrushed
    fall-off (the envelope is above 0.05 beyond 3 px); else None (washes, flat or pooled rims).
    Distances up to ``2 most + 1`` px (issue 24, trees48)."""
    peak = max((float(np.percentile(e.normalized.soft_alpha[e.image[..., 3] >= 0.5], 99))
                for e in exemplars if e.normalized.soft_alpha is not None
                and e.normalized.soft_alpha.shape == e.image.shape[:2] and (e.image[..., 3] >= 0.5).any()),
               default=0.0)
    if peak <= 0.0:
        return None
    core_level = HALO_CORE * peak
    # an airbrushed fall-off only: faint at the silhouette's edge (a glass tree's even alpha or a
    # watercolour's pooled rim round a paler wash are no halo to trim)
    for e in exemplars:
        soft, op = e.normalized.soft_alpha, e.image[..., 3] >= 0.5
        if soft is None or soft.shape != op.shape or not op.any():
            continue
        inside = ndi.distance_transform_edt(op)
        if float(np.median(soft[op & (inside < 2.5)])) > 0.5 * core_level:
            return None
    n = int(2 * most) + 2
    env = np.zeros(n)
    for e in exemplars:
        soft = e.normalized.soft_alpha
        if soft is None or soft.shape != e.image.shape[:2]:
            continue
        core = soft >= core_level
        if not core.any():
            continue
        dc = ndi.distance_transform_edt(~core)
        k = np.floor(dc).astype(int)
        sel = ~core & (k < n) & (soft > 0.0)
        for d in np.unique(k[sel]):
            env[d] = max(env[d], float(np.percentile(soft[sel & (k == d)], 95)))
    env = np.maximum.accumulate(env[::-1])[::-1]      # non-increasing outwards
    if len(env) <= 4 or env[4] <= 0.05:
        return None
    return core_level, env


#: Largest trunk-top slit filled (:func:`_trunk_slit`), as a share of the mixed silhouette's area:
#: the slits measured on 256-400 px watercolour, airbrushed and glass mixes were 0.1-1.5 % of it.
SLIT_MAX = 0.03

#: Least share of crown round a trunk-top gap of an opaque mix for it to be filled (trees59): the
#: notches of 128-256 px opaque watercolour mixes were ringed by 0.57-0.67 crown, the RPG trunks'
#: own knot holes by 0.02-0.05 (a gap under a palm frond by 0.26).
SLIT_CROWN = 0.5


def _trunk_slit(opaque: np.ndarray, mask: np.ndarray, trunk: np.ndarray, crown_share: float = 0.0) -> np.ndarray:
    """The gaps the colour transfer left between a mix's trunk top and its crown: pixels inside the
    mixed silhouette ``mask`` (more than 1 px in) that no source painted (``opaque`` false), in
    pieces touching both the ``trunk`` and the crown (``opaque`` and not trunk), each at most
    :data:`SLIT_MAX` of the silhouette and with at least ``crown_share`` of the pixels round it crown.

    Notes
    -----
    Beyond the paper (issue 24, trees57). A source whose trunk runs up inside its crown maps, under
    the mix's cage, the crown's lower rim beside the trunk onto that source's transparent ground
    next to its trunk, so the mix keeps a slit of bare ground running up from where the trunk
    enters the crown (10-50 rows at 256 px). Opaque mixes keep the same notch in their silhouette;
    a translucent crown shows it as a dark gap in the wash. Holes of the sources inside the crown
    (not touching the trunk) stay. Opaque mixes (trees59) ask for ``crown_share`` =
    :data:`SLIT_CROWN` of crown round a gap, so that the trunk's own holes stay.
    """
    inside = ndi.distance_transform_edt(mask) > 1.5
    miss = inside & ~opaque
    if not miss.any() or not trunk.any():
        return np.zeros_like(opaque)
    crown = opaque & ~trunk
    # between two parts of the tree in its row (a sliver of the silhouette beside the trunk below
    # the crown has ground on one side: filled, it was a crown-coloured strip down the trunk)
    tree = (crown | trunk).astype(np.uint8)
    miss &= (np.maximum.accumulate(tree, axis=1) > 0) & (np.maximum.accumulate(tree[:, ::-1], axis=1)[:, ::-1] > 0)
    lab, n = ndi.label(miss, structure=np.ones((3, 3), bool))
    idx = np.arange(1, n + 1)
    k = np.ones((3, 3), bool)
    at_trunk = np.asarray(ndi.maximum(ndi.binary_dilation(trunk, structure=k), lab, idx)) > 0
    at_crown = np.asarray(ndi.maximum(ndi.binary_dilation(crown, structure=k), lab, idx)) > 0
    area = np.asarray(ndi.sum(miss, lab, idx))
    keep = at_trunk & at_crown & (area <= SLIT_MAX * max(int(mask.sum()), 1))
    if crown_share > 0 and keep.any():
        # opaque mixes (trees59): a hole ringed mostly by trunk is the trunk's own (a knot hole)
        ring = ndi.grey_dilation(lab, footprint=k) * ~(lab > 0)
        with np.errstate(invalid="ignore"):   # a gap with no ring pixel: nan, not kept
            keep &= np.asarray(ndi.mean(crown, ring, idx)) >= crown_share
    return np.isin(lab, idx[keep])
