"""Bare (leafless) trees: a thin-structure mix path (beyond the paper; issue 24).

A bare winter tree is a lattice of tapering limbs and 1 px twigs. The paper
mixes trees by combining their silhouette contours and filling the mixed
contour with colours carried by mean value coordinates: on a bare tree the
contour traces every twig, the contours of different trees do not correspond,
and the carried limbs break where the cage folds (3-10 px gaps where a limb
leaves the trunk), the twigs turn into clumps and the edges lose their
anti-aliasing.

Here the crowns' *envelopes* are mixed instead: each exemplar's reach from
its trunk foot in every direction (a smooth radial profile ``r(theta)``) is
combined with the shape weights, and the branch image of every exemplar is
warped, as one smooth star-shaped map, from its own envelope to the mixed
one, resampled bilinearly (premultiplied alpha). The map is continuous and
one-to-one, so each warped tree keeps every limb joined to its trunk, its
twigs as thin as the source's (the local scale is limited to 0.8-1.25) and
its anti-aliased edges. Colours are the colour-weighted mix of the
exemplars' mean bark colours, applied as a gain to the warped bark (so a lit
side stays lit).

Limbs of every tree (issue 24, trees46; before, the dominant tree's limbs
only, so a mix of two bare trees looked like one of them): each warped tree
is parted into its stem (the trunk, pixels at least :data:`LIMB_STEM` as
deep as the trunk near the foot, grown back by :data:`LIMB_GROW` depths)
and its limbs, flooded from where they leave the stem (a watershed on the
depth: twigs of two limbs that cross are parted where they cross). The mix
has the dominant tree's trunk; the tree furthest below its share (shape
weight) of the weighted mean limb length gives a limb, with its own stem,
when that brings it nearer its share and the limb does not lie over the
limbs taken (:data:`LIMB_OVERLAP`). Measured on procedural bare trees
(round, weeping, one-sided, 256 and 512 px): 50/50 mixes take 41-59 % of
their limb length from each tree, one piece (largest piece 1.0 of the
area); a tree of weight 0.1-0.2 gives no limb.

Examples
--------
>>> import cv2, numpy as np
>>> a = np.zeros((64, 64), np.float32)
>>> for tip in ((8, 4), (24, 2), (40, 2), (56, 4)):
...     _ = cv2.line(a, (32, 62), tip, 1.0, 1)
>>> bool(is_bare_alpha(a))
True
>>> bool(is_bare_alpha(np.pad(np.ones((40, 40), np.float32), 12)))
False
"""

from __future__ import annotations

from collections.abc import Sequence

import cv2
import numpy as np
from scipy import ndimage as ndi
from skimage.morphology import skeletonize
from skimage.segmentation import watershed

__all__ = ["is_bare_alpha", "bare_mix", "soft_image", "BARE_FILL", "BARE_THIN", "BARE_THICK", "BARE_FILL_LOOSE",
           "BARE_THIN_LOOSE", "BARE_THICK_LOOSE", "BARE_SCALE"]

#: Largest share of its closed crown envelope a bare tree's opaque pixels cover.
BARE_FILL = 0.8
BARE_FILL_LOOSE = 0.9
#: Least share of a bare tree's skeleton length in thin limbs (see :func:`is_bare_alpha`).
BARE_THIN = 0.6
BARE_THIN_LOOSE = 0.5
#: Largest share of a bare tree's opaque area in thick parts (see :func:`is_bare_alpha`).
BARE_THICK = 0.12
BARE_THICK_LOOSE = 0.3
#: Least and most local scale of the envelope warp (twig widths stay 0.8-1.25x).
BARE_SCALE = (0.8, 1.25)
_BINS = 180
#: Alpha cut of a hard-edged (pixel-art) mix: below 0.5, because a bilinearly sampled 1 px
#: diagonal line can fall under 0.5 all across (at 0.5 the hard mixes of 1 px-twig trees broke
#: into 19-46 pieces, at 0.4 into 1-10 with twigs 1.06-1.2x the sources', at 0.3 twigs 1.25-1.4x).
HARD_CUT = 0.4
#: A tree's stem (split off before its limbs are shared out): pixels at least this share as deep
#: as its deepest pixel (a trunk 1, its first limbs 0.65 of its width in the procedural trees).
LIMB_STEM = 0.8
#: The stem grown back by this many times its depth: the fork where its limbs leave it (its
#: limbs touched each other just past a trunk grown back by its depth only: one limb).
LIMB_GROW = 2.5
#: Most share of a limb lying near the limbs already taken (within :data:`LIMB_GAP` of the
#: tree's extent) for the mix to take it too: limbs of two trees do not pile up.
LIMB_OVERLAP = 0.25
LIMB_GAP = 0.01
#: Least share of the weighted mean limb length a mix keeps (the dominant tree fills it up).
LIMB_FILL = 0.8


def is_bare_alpha(alpha: np.ndarray, loose: bool = False) -> bool:
    """Whether an alpha matte is a bare (leafless) tree: thin limbs, an open crown.

    Parameters
    ----------
    alpha : (H, W) array_like
        Alpha in [0, 1].
    loose : bool
        The looser test for the other trees of a bare mix (thick share up
        to :data:`BARE_THICK_LOOSE`, thin skeleton share from
        :data:`BARE_THIN_LOOSE`, envelope share up to
        :data:`BARE_FILL_LOOSE`): a small, tall bare tree whose forks
        merge into a wider trunk.

    Returns
    -------
    bool
        True when all three hold (``e``: the opaque extent):

        - the opaque pixels (alpha >= 0.5) cover at most :data:`BARE_FILL`
          of their envelope (closed with a disc of ``e / 12``, holes filled);
        - at least :data:`BARE_THIN` of the skeleton's length lies in limbs
          at most ``max(5, e / 30)`` px wide;
        - at most :data:`BARE_THICK` of the opaque area is in parts wider
          than ``e / 10`` (a leafy crown's blob: a tree drawn with its roots
          under a green crown is no bare tree).

    Notes
    -----
    Measured on procedural bare trees (round, tall, weeping, asymmetric,
    128-512 px, one or two colours: envelope share 0.35-0.84, thin skeleton
    share 0.64-0.98; all pass, but a 128 px tall tree only the loose test)
    and the library's sample trees (none passes the strict test: leafy
    crowns cover 0.86-1.0 of their envelope and hold thick blobs, the
    palm's fronds are thin on 0.46 of the skeleton, a tree drawn with its
    roots has 0.84 of its area in its crown's blob; the photographed
    broadleaf passes the loose one only).
    """
    a = np.asarray(alpha, dtype=np.float32)
    if a.ndim != 2:
        raise ValueError(f"alpha must be (H, W), got shape {a.shape}")
    op = a >= 0.5
    if op.sum() < 20:
        return False
    ys, xs = np.nonzero(op)
    ext = max(np.ptp(ys), np.ptp(xs)) + 1

    # discs by distance transforms (a 1/12-extent disc kernel took seconds at 1024 px)
    y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    r = ext / 24
    pad = int(r) + 2
    crop = np.pad(op[y0:y1, x0:x1], pad)
    grown = ndi.distance_transform_edt(~crop) <= r
    env = ndi.binary_fill_holes(ndi.distance_transform_edt(grown) > r)
    if crop.sum() > (BARE_FILL_LOOSE if loose else BARE_FILL) * max(env.sum(), 1):
        return False
    inner = ndi.distance_transform_edt(crop)
    sk = skeletonize(crop)
    if not sk.any():
        return False
    if (inner[sk] <= max(2.5, ext / 60)).mean() < (BARE_THIN_LOOSE if loose else BARE_THIN):
        return False
    thick = ndi.distance_transform_edt(~(inner > ext / 20)) <= ext / 20
    return bool((thick & crop).sum() <= (BARE_THICK_LOOSE if loose else BARE_THICK) * crop.sum())


def _foot(alpha: np.ndarray) -> tuple[float, float]:
    """Trunk foot (x, y): the middle of the lowest opaque rows."""
    op = alpha >= 0.5
    rows = np.flatnonzero(op.any(axis=1))
    yb = rows[-1]
    xs = np.nonzero(op[max(yb - 2, 0):yb + 1])[1]
    return float(xs.mean()), float(yb)


def _profile(alpha: np.ndarray, foot: tuple[float, float]) -> np.ndarray:
    """Smooth radial reach ``r(theta)`` (``_BINS`` bins over the full turn) from the foot."""
    ys, xs = np.nonzero(alpha >= 0.5)
    dx, dy = xs - foot[0], foot[1] - ys
    th = np.arctan2(dy, dx)
    b = ((th + np.pi) / (2 * np.pi) * _BINS).astype(int) % _BINS
    r = np.zeros(_BINS)
    np.maximum.at(r, b, np.hypot(dx, dy))
    # an envelope, not the tips: a hull-like max over +-6 degrees, then smoothed over +-8
    r = ndi.maximum_filter1d(r, 7, mode="wrap")
    r = np.maximum(r, 0.15 * r.max())
    return ndi.gaussian_filter1d(r, 4.0, mode="wrap")


def _mean_colour(image: np.ndarray) -> np.ndarray:
    a = image[..., 3]
    m = a >= 0.5
    if not m.any():
        return np.full(3, 0.5, np.float32)
    return (image[..., :3][m] * a[m, None]).sum(0) / a[m].sum()


def soft_image(image: np.ndarray, soft_alpha: np.ndarray | None) -> np.ndarray:
    """An exemplar's working image with its source's anti-aliased edge put back.

    Parameters
    ----------
    image : (S, S, 4) ndarray
        Working RGBA with binary alpha (:class:`~branchnb.trees.exemplar.Normalized`).
    soft_alpha : (S, S) ndarray or None
        The source's alpha resampled alike (None: ``image`` is returned as it is).

    Returns
    -------
    (S, S, 4) float32 ndarray
        Opaque pixels keep their colour and take the soft alpha (at least
        0.5); the soft pixels one pixel around them take the soft alpha and
        the nearest opaque pixel's colour; everything else stays transparent.
    """
    img = np.asarray(image, dtype=np.float32)
    if soft_alpha is None or np.shape(soft_alpha) != img.shape[:2]:
        return img
    op = img[..., 3] >= 0.5
    if not op.any():
        return img
    sa = np.clip(np.asarray(soft_alpha, np.float32), 0.0, 1.0)
    ring = cv2.dilate(op.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool) & ~op
    a = np.where(op, np.maximum(sa, 0.5), np.where(ring, np.minimum(sa, 0.499), 0.0))
    idx = ndi.distance_transform_edt(~op, return_distances=False, return_indices=True)
    rgb = img[..., :3][idx[0], idx[1]]
    return np.dstack([rgb, a]).astype(np.float32)


def bare_mix(images: Sequence[np.ndarray], weights: np.ndarray, colour_weights: np.ndarray,
             trunks: Sequence[np.ndarray] | None = None, hard: bool = False,
             rng: int | np.random.Generator | None = None
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mix bare trees by their envelopes: the exemplars warped into the mixed envelope, limbs shared.

    Parameters
    ----------
    images : sequence of (S, S, 4) ndarray
        The exemplars' working RGBA images (all the same size).
    weights : (k,) array_like
        Convex shape weights (the envelopes' combination, each tree's share
        of the limbs; the largest gives the trunk).
    colour_weights : (k,) array_like
        Convex colour weights (the bark colour's combination).
    trunks : sequence of (S, S) bool ndarray, optional
        The exemplars' trunk masks (warped along; default: none).
    hard : bool
        Hard-edged sources (pixel art): the warped alpha is thresholded at
        :data:`HARD_CUT` (hard edges in, hard edges out).
    rng : int or numpy.random.Generator, optional
        Which limbs each exemplar gives (drawn by their length); None: the
        longest first.

    Returns
    -------
    image : (S, S, 4) float32 ndarray
        The mix, premultiplied-resampled and anti-aliased like the sources.
    sources : (S, S) int ndarray
        Index (into ``images``) of the exemplar each opaque pixel comes from, -1 elsewhere.
    trunk : (S, S) float32 ndarray
        The warped trunk masks of the exemplars, each where its pixels are taken (0-1).

    Raises
    ------
    ValueError
        Images of different shapes, weights of the wrong length.

    Notes
    -----
    Beyond the paper (see the module docstring): the paper's contour
    combination cannot mix a lattice of 1 px twigs. The limbs are whole
    limbs of the exemplars, shared out by weight (module docstring); the
    crown's reach in every direction, the foot and the colour are mixed.
    """
    imgs = [np.asarray(im, dtype=np.float32) for im in images]
    if not imgs or any(im.shape != imgs[0].shape or im.ndim != 3 or im.shape[2] != 4 for im in imgs):
        raise ValueError("images must be one or more RGBA images of one shape")
    w = np.asarray(weights, dtype=np.float64)
    cw = np.asarray(colour_weights, dtype=np.float64)
    if w.shape != (len(imgs),) or cw.shape != (len(imgs),):
        raise ValueError(f"weights and colour_weights must have {len(imgs)} entries")
    h, wd = imgs[0].shape[:2]
    feet = [_foot(im[..., 3]) for im in imgs]
    profs = [_profile(im[..., 3], f) for im, f in zip(imgs, feet, strict=True)]
    d = int(np.argmax(w))
    ws = w / w.sum()
    foot_m = np.sum([wi * np.array(f) for wi, f in zip(ws, feet, strict=True)], axis=0)
    prof_m = np.sum([wi * p for wi, p in zip(ws, profs, strict=True)], axis=0)
    yy, xx = np.mgrid[0:h, 0:wd].astype(np.float32)
    dx, dy = xx - foot_m[0], foot_m[1] - yy
    th = np.arctan2(dy, dx)
    pos = (th + np.pi) / (2 * np.pi) * _BINS - 0.5
    cws = cw / cw.sum() if cw.sum() > 0 else ws
    target = np.sum([ci * _mean_colour(im) for ci, im in zip(cws, imgs, strict=True)], axis=0)
    live = [i for i in range(len(imgs)) if w[i] > 0] or [d]
    warped = {}
    for i in live:      # every exemplar warped from its own envelope into the mixed one
        k = np.clip(profs[i] / prof_m, *BARE_SCALE)
        kk = np.interp(pos.ravel(), np.arange(-1, _BINS + 1), np.r_[k[-1], k, k[0]]).reshape(h, wd)
        mx = (feet[i][0] + kk * dx).astype(np.float32)
        my = (feet[i][1] - kk * dy).astype(np.float32)
        src = imgs[i]
        pre = np.dstack([src[..., :3] * src[..., 3:], src[..., 3]])
        out = cv2.remap(pre, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        a = np.clip(out[..., 3], 0, 1)
        rgb = out[..., :3] / np.maximum(a, 1e-6)[..., None]
        if hard:
            a = (a >= HARD_CUT).astype(np.float32)
        rgb = np.clip(rgb * (target / np.maximum(_mean_colour(src), 1e-3)), 0, 1)
        tr = (cv2.remap(np.asarray(trunks[i], np.float32), mx, my, cv2.INTER_LINEAR,
                        borderMode=cv2.BORDER_CONSTANT, borderValue=0) if trunks is not None
              else np.zeros((h, wd), np.float32))
        warped[i] = (rgb, a, tr)
    cut = HARD_CUT if hard else 0.5
    if len(live) > 1 and all(np.abs(warped[i][1] - warped[d][1]).max() < 1e-3 for i in live):
        live = [d]           # one tree several times: nothing to share out
    ext = float(np.hypot(*np.ptp(np.argwhere(warped[d][1] >= cut), axis=0))) if (warped[d][1] >= cut).any() else 1.0
    own = _share_limbs({i: warped[i][1] >= cut for i in live}, d, ws, ext,
                       None if rng is None else np.random.default_rng(rng))
    # each exemplar's chosen limbs with their anti-aliased fringe; the most opaque one wins
    alpha = np.zeros((h, wd), np.float32)
    sources = np.full((h, wd), -1)
    for i in live:
        sel = cv2.dilate(own[i].astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
        ai = np.where(sel, warped[i][1], 0.0)
        win = ai > alpha
        alpha = np.where(win, ai, alpha)
        sources = np.where(win, i, sources)
    rgb = np.full((h, wd, 3), target, np.float32)
    trunk = np.zeros((h, wd), np.float32)
    for i in live:
        m = sources == i
        rgb[m] = warped[i][0][m]
        trunk[m] = warped[i][2][m]
    a = alpha.astype(np.float32)
    # transparent pixels keep the mean colour (no black fringe when composited unpremultiplied)
    rgb = np.where(a[..., None] > 1e-4, rgb, target)
    image = np.dstack([rgb, a]).astype(np.float32)
    sources = np.where(a >= 0.5, sources, -1)
    return image, sources, trunk


def _pieces(mask: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, float]]:
    """A tree's limbs as ``(stem, limb, skeleton length)``: the stem is the trunk (pixels at least
    :data:`LIMB_STEM` as deep as the trunk near the foot, grown back by :data:`LIMB_GROW` depths),
    the limbs what leaves it."""
    dt = ndi.distance_transform_edt(mask)
    rows = np.flatnonzero(mask.any(axis=1))
    if rows.size == 0:
        return []
    # the trunk's own depth, read near the foot: the forks, where strokes overlap, run deeper
    low = dt[rows[-1] - max(1, int(0.1 * (rows[-1] - rows[0]))):rows[-1] + 1]
    deep = float(np.median(low.max(axis=1)))
    if deep <= 0:
        return []
    seeds = dt >= LIMB_STEM * deep
    stem = (ndi.distance_transform_edt(~seeds) <= LIMB_GROW * deep + 1.0) & mask
    # Limbs: flooded from where they leave the stem, through the mask, thick parts first (a
    # watershed on the depth); crowns whose twigs cross are parted where they cross (as
    # connected pieces, all the limbs of a round crown were one).
    rest = mask & ~stem
    base = rest & (ndi.distance_transform_edt(~stem) <= 2.0)
    markers, n = ndi.label(base, structure=np.ones((3, 3)))
    if n == 0:
        return []
    lab = watershed(-dt, markers, mask=rest, connectivity=2)
    length = ndi.sum(skeletonize(mask), lab, np.arange(1, n + 1))
    return [(stem, lab == j + 1, float(length[j])) for j in range(n) if length[j] >= 2]


def _share_limbs(masks: dict, d: int, ws: np.ndarray, extent: float, rng=None) -> dict:
    """Which pixels of each warped exemplar the mix takes (beyond the paper's single-tree warp):
    the trunk of the dominant ``d``; the limbs of all, shared out by their shape weights ``ws``
    (the exemplar furthest below its share of the limb length takes its longest limb that does
    not lie over the limbs taken so far), up to their weighted mean limb length."""
    own = {i: np.zeros_like(m) for i, m in masks.items()}
    if len(masks) == 1:
        own[d] = masks[d].copy()
        return own
    pieces = {i: p for i, m in masks.items() if (p := _pieces(m))}
    if d not in pieces:         # no trunk to part the limbs from: the dominant tree whole
        own[d] = masks[d].copy()
        return own
    taken = pieces[d][0][0].copy()
    own[d] |= taken
    goal = sum(ws[i] * sum(q[2] for q in p) for i, p in pieces.items())
    got = {i: 0.0 for i in pieces}
    left = {i: sorted(p, key=lambda q: -q[2]) for i, p in pieces.items()}
    near = max(2.0, LIMB_GAP * extent)
    spare = []
    def take(i, limb, stem, length) -> bool:
        grown = ndi.distance_transform_edt(~taken) <= near
        if (grown & limb).sum() > LIMB_OVERLAP * limb.sum():
            return False
        own[i] |= limb | stem
        taken[...] |= limb | stem
        got[i] += length
        return True

    while sum(got.values()) < goal and any(left.values()):
        i = max((i for i in left if left[i]), key=lambda i: ws[i] * goal - got[i])
        pick = 0 if rng is None else int(rng.choice(len(left[i]), p=(q := np.array([x[2] for x in left[i]])) / q.sum()))
        stem, limb, length = left[i].pop(pick)
        # only a limb that brings its tree nearer its share: a tree of weight 0.16 gave half
        # the limbs of a two-limbed mix
        if abs(got[i] + length - ws[i] * goal) < abs(got[i] - ws[i] * goal):
            take(i, limb, stem, length)
        else:
            spare.append((i, stem, limb, length))
    # a crown left short (a limb would overshoot its tree's share; limbs lay over others): the
    # limbs passed over fill it, the heaviest tree's first (a one-limbed mix otherwise)
    spare += [(i, *q) for i in left for q in left[i]]
    for i, stem, limb, length in sorted(spare, key=lambda q: (-ws[q[0]], -q[3])):
        if sum(got.values()) >= LIMB_FILL * goal:
            break
        take(i, limb, stem, length)
    return own
