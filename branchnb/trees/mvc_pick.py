"""Colour transfer, the ``"choose"`` and ``"parts"`` modes: one exemplar per pixel (not in the paper, issue 24).

Part of :func:`~branchnb.trees.mvc.transfer_colour` (moved here from
:mod:`~branchnb.trees.mvc` unchanged): the smooth Gumbel fields that draw
each exemplar's regions (:func:`smooth_gumbel`), the seam cut that moves
their borders onto the outlines (``_choose``, ``_coarse_cut``) and the
whole-part pick of ``"parts"`` (``_choose_parts``).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.random import as_rng

__all__ = ["smooth_gumbel"]

#: Regulariser of the seam cost's gradient normalisation in ``"choose"``: small,
#: so a seam across a flat fill costs far more than one along an outline.
SEAM_EPS = 0.01

#: ``"choose"`` runs its graph cut on a grid whose longer side is at most this
#: many pixels (the tree's bounding box reduced by a whole factor ``f``), and
#: brings the labels back to full size: at 512 px one variation takes about
#: 0.2 s instead of 1 s, the seams land within ``f / 2`` pixels of where the
#: full-size cut puts them, and the colours still come from the full-size
#: sources (no pixel is blended).
CHOOSE_CUT_SIDE = 160

#: ``"parts"``: a crown source whose warped drawing keeps at least this share of its pixels in one
#: piece (else the next source in the draw gives the crown).
ONE_PIECE = 0.97
#: ``"parts"``: ... and covers at least this share of what the best-covering source covers of
#: the mixed contour.
COVERS = 0.75

#: ``"parts"``: another exemplar's trunk replaces the crown source's own only when the two
#: overlap (below the crown) by at least this intersection over union; a thinner or wider trunk
#: left a black core, bare gaps or loose fork tips (clip art: cartoon_tree's stroke trunk
#: under tree_with_fruits's crown).
TRUNK_IOU = 0.5


def smooth_gumbel(shape: tuple[int, int], k: int, scale: float, *, rng=None) -> np.ndarray:
    """``k`` spatially smooth random fields whose value at every pixel is standard-Gumbel distributed.

    White noise blurred with a Gaussian of ``scale`` pixels, rescaled to
    unit variance, pushed through the normal CDF (uniform marginals) and
    then through ``-log(-log u)``. With these fields the Gumbel-max rule
    ``argmax_i log c_i + g_i(p)`` picks source ``i`` at every pixel with
    probability exactly ``c_i``, and neighbouring pixels pick alike, so the
    picks form regions about ``scale`` pixels across.

    Parameters
    ----------
    shape : (H, W)
        Size of each field in pixels.
    k : int
        Number of independent fields (one per source exemplar).
    scale : float
        Standard deviation of the Gaussian blur in pixels: the correlation
        length, roughly the radius of the regions a Gumbel-max pick forms.
        Below 0.5 px the fields are nearly white noise.
    rng : int or numpy.random.Generator, optional
        Seed or Generator of the noise; None draws a fresh seed.

    Returns
    -------
    (k, H, W) float64 ndarray
        Standard-Gumbel marginals (mean ~0.577) at every pixel.

    Examples
    --------
    >>> import numpy as np
    >>> g = smooth_gumbel((64, 64), 2, 8.0, rng=0)
    >>> g.shape, bool(np.corrcoef(g[0, :, :-1].ravel(), g[0, :, 1:].ravel())[0, 1] > 0.9)
    ((2, 64, 64), True)
    """
    from scipy.special import ndtr

    gen = as_rng(rng)
    h, w = int(shape[0]), int(shape[1])
    # The blur is done on a grid about scale / 4 coarser (the fields are smooth anyway).
    f = max(1, int(scale // 4))
    hs, ws = -(-h // f) + 2, -(-w // f) + 2
    sig = max(scale / f, 0.5)
    out = np.empty((k, h, w))
    for i in range(k):
        n = cv2.GaussianBlur(gen.standard_normal((hs, ws)), (0, 0), sig, borderType=cv2.BORDER_REFLECT)
        # The variance of blurred unit white noise is 1 / (4 pi sigma^2) in the continuum; the
        # empirical std is used so the marginals are standard normal on small grids too.
        n = n / max(float(n.std()), 1e-12)
        big = cv2.resize(n, ((ws - 2) * f, (hs - 2) * f), interpolation=cv2.INTER_LINEAR)[:h, :w] \
            if f > 1 else n[1:h + 1, 1:w + 1]
        u = np.clip(ndtr(big), 1e-12, 1 - 1e-12)
        out[i] = -np.log(-np.log(u))
    return out


def _choose(cols, on, opaque, c, ys, xs, shape, region_scale, seam, gen) -> np.ndarray:
    """Colour of the ``"choose"`` mode: one source per pixel (Gumbel-max regions, then seams),
    and each pixel's source (index into ``c``)."""
    from ..core.graphcut import multilabel_seams

    k = len(c)
    r0, r1, c0, c1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    h, w = r1 - r0, c1 - c0
    g = smooth_gumbel((h, w), k, max(2.0, region_scale * max(shape)), rng=gen)
    yy, xx = ys - r0, xs - c0
    score = np.log(c)[:, None] + g[:, yy, xx]               # (k, P)
    score = np.where(on, score, -np.inf)
    best = score.max(axis=0)
    imgs = np.zeros((k, h, w, 3), np.float32)
    imgs[:, yy, xx] = cols
    unary = np.full((h, w, k), np.inf)
    # Data term: how far below the pixel's best Gumbel-max score a source
    # is (0 for the drawn region's owner), forbidden where it is transparent.
    with np.errstate(invalid="ignore"):
        gap = np.where(on, best[None] - score, np.inf)
    unary[yy, xx] = np.where(np.isfinite(gap), np.minimum(gap, 8.0), np.inf).T
    region = np.zeros((h, w), bool)
    region[yy[opaque], xx[opaque]] = True
    li = np.argmax(score, axis=0)
    f = -(-max(h, w) // CHOOSE_CUT_SIDE)
    if seam > 0 and f == 1:
        lab = multilabel_seams(imgs, unary, region=region, smoothness=seam, eps=SEAM_EPS)[yy, xx]
        li = np.where(lab >= 0, lab, li)
    elif seam > 0:
        li = _coarse_cut(imgs, unary, region, on, yy, xx, li, f, seam)
    return cols[li, np.arange(len(li))], li



def _check_groups(groups, k: int) -> np.ndarray:
    if groups is None:
        return np.zeros(k, np.int64)
    if isinstance(groups, (str, bytes, dict)) or not hasattr(groups, "__len__"):
        raise TypeError(f"groups must be a sequence of ints (one per source), got {type(groups).__name__}")
    g = np.asarray(groups)
    if g.shape != (k,) or not (np.issubdtype(g.dtype, np.integer) or np.issubdtype(g.dtype, np.bool_)):
        raise ValueError(f"groups must hold one int per source ({k}), got {g.dtype} of shape {g.shape}")
    return g.astype(np.int64)


def _largest(m: np.ndarray) -> np.ndarray:
    """The largest 8-connected component of a boolean image (empty stays empty)."""
    lab, n = ndi.label(m, structure=np.ones((3, 3), bool))
    if n <= 1:
        return m
    return lab == np.argmax(np.bincount(lab.ravel())[1:]) + 1


def _choose_parts(cols, on, trunk, c, ys, xs, groups, gen):
    """Colour of the ``"parts"`` mode: the crown from one source, the trunk from one source.

    The crown's source ``a`` is the one source with half or more of the
    colour weight if there is one (and the warp leaves it in one piece,
    :data:`ONE_PIECE`), else drawn with probabilities ``c`` among the
    sources the warp leaves in one piece and covering the mixed contour
    (:data:`COVERS`), if any; the trunk's source ``b`` is drawn with
    probabilities ``c``; ``b`` must be of ``a``'s group (outlined or not),
    its trunk must overlap ``a``'s own trunk (below the crown) by an IoU of
    at least 1/2 (a thin stroke trunk does not replace a wide one, nor the
    reverse: a black core or bare holes), join the crown's main body in
    one piece and leave no hole where ``a`` was opaque, else the next in
    the draw, down to ``a`` itself. A pixel is
    ``a``'s where ``a`` is opaque and not trunk there, and wherever ``a``'s
    trunk lies inside ``a``'s crown (its branches); else ``b``'s where
    ``b``'s trunk is; else transparent. So the crown keeps its own drawing
    (outline, clumps, fruits whole) and the trunk one colour.
    Returns (rgb, source per point, opaque per point).
    """
    k, n = on.shape
    p = c / c.sum()
    with np.errstate(divide="ignore"):
        rank = np.argsort(-(np.log(p) + gen.gumbel(size=k)))     # Gumbel-max order: P(first) = p
    rank = rank[p[rank] > 0]
    r0, c0 = ys.min(), xs.min()
    h, w = ys.max() - r0 + 1, xs.max() - c0 + 1
    yy, xx = ys - r0, xs - c0

    def grid(v):
        g = np.zeros((h, w), bool)
        g[yy, xx] = v
        return g

    def whole(i):
        return _largest(grid(on[i]))[yy, xx].sum() / max(int(on[i].sum()), 1)

    major = int(np.argmax(p)) if p.max() >= 0.5 and (p == p.max()).sum() == 1 else None
    if major is not None and whole(major) >= ONE_PIECE:
        # a source holding the majority of the colour ("more like this" keeps >= 1/2 of the
        # target's) draws the crown: a variation of a tree keeps that tree's drawing
        a = major
    else:
        # The shown tree is the crown source's own drawing, so a source the warp leaves far
        # short of the mixed contour (a palm pulled into an even palm/fruit-tree mix covers
        # 40 % of it and its curved trunk ends half way down) or tears apart cannot give the
        # whole tree: the next source in the draw that covers the contour and stays in one
        # piece gives the crown, else the one that comes closest.
        cover = on.mean(axis=1)
        score = []
        for cand in rank:
            ok = whole(cand) >= ONE_PIECE and cover[cand] >= COVERS * cover[rank].max()
            score.append(min(whole(cand) / ONE_PIECE, cover[cand] / (COVERS * cover[rank].max())))
            if ok:
                break
        a = int(rank[len(score) - 1] if score[-1] >= 1.0 else rank[int(np.argmax(score))])
    crown = on[a] & ~trunk[a]

    inside = ndi.binary_fill_holes(grid(crown))[yy, xx]
    mine = crown | (on[a] & trunk[a] & inside)
    body = _largest(grid(mine))[yy, xx]
    li, opaque = np.full(n, a), on[a].copy()
    # The trunk: drawn again with probabilities p (the crown's own trunk included); a source
    # whose trunk does not join the crown or covers less than half of it is passed over.
    with np.errstate(divide="ignore"):
        order = np.argsort(-(np.log(p) + gen.gumbel(size=k)))
    own = on[a] & trunk[a] & ~inside
    for b in order[(p[order] > 0) & (groups[order] == groups[a])]:
        if b == a:
            break
        # b's trunk below its own crown (its branches inside its crown stay behind).
        theirs = ~mine & on[b] & trunk[b] & ~ndi.binary_fill_holes(grid(on[b] & ~trunk[b]))[yy, xx]
        if (theirs & own).sum() < TRUNK_IOU * (theirs | own).sum() or \
                (theirs & _largest(grid(body | theirs))[yy, xx]).sum() < 0.9 * theirs.sum():
            continue
        both = grid(mine | theirs)
        if (ndi.binary_fill_holes(both)[yy, xx] & ~(mine | theirs) & on[a]).any():
            continue                # a gap where a's own trunk was: no hole a drawing has
        li = np.where(mine, a, b)
        opaque = mine | theirs
        break
    return cols[li, np.arange(n)], li, opaque


def _blocks(a: np.ndarray, f: int) -> np.ndarray:
    """Means over ``f`` x ``f`` blocks of the first two axes of ``a`` (zero-padded to a multiple of ``f``)."""
    h, w = a.shape[:2]
    hs, ws = -(-h // f), -(-w // f)
    pad = np.zeros((hs * f, ws * f) + a.shape[2:], np.float32)
    pad[:h, :w] = a
    flat = pad.reshape(hs * f, ws * f, -1)
    # INTER_AREA with a whole factor is the block mean (several times faster than numpy's).
    out = np.concatenate([cv2.resize(np.ascontiguousarray(flat[:, :, i:i + 4]), (ws, hs),
                                     interpolation=cv2.INTER_AREA).reshape(hs, ws, -1)
                          for i in range(0, flat.shape[2], 4)], axis=2)
    return out.reshape((hs, ws) + a.shape[2:]).astype(np.float64)


def _coarse_cut(imgs, unary, region, on, yy, xx, li, f, seam) -> np.ndarray:
    """The seam cut of ``"choose"`` on an ``f`` times coarser grid, labels brought back smoothly.

    Sources' colours and the region are block means (outlines stay visible
    as darker blocks), the data term is the block mean of the finite costs
    times ``f`` (a block holds ``f^2`` pixels but its seams only ``f``, so
    data and seam cost keep their balance). The coarse labels come back as
    bilinearly upsampled one-hot maps, so the seams stay smooth instead of
    stair-stepped; a pixel takes the strongest label among the sources
    opaque there, else its own Gumbel-max pick.
    """
    from ..core.graphcut import multilabel_seams

    k, h, w = imgs.shape[:3]
    allowed = np.isfinite(unary)
    cnt = _blocks(allowed.astype(np.float64), f)
    u_c = np.where(cnt >= 0.5, _blocks(np.where(allowed, unary, 0.0), f) / np.maximum(cnt, 1e-9),
                   np.inf) * f
    imgs_c = np.stack([_blocks(im, f) for im in imgs])
    reg_c = _blocks(region.astype(np.float64), f) >= 0.5
    lab_c = multilabel_seams(imgs_c, u_c, region=reg_c, smoothness=seam, eps=SEAM_EPS)
    hs, ws = lab_c.shape
    vote = np.empty((k, len(yy)))
    for i in range(k):
        up = cv2.resize((lab_c == i).astype(np.float32), (ws * f, hs * f), interpolation=cv2.INTER_LINEAR)
        vote[i] = up[yy, xx]
    vote = np.where(on, vote, -1.0)
    best = np.argmax(vote, axis=0)
    return np.where(vote.max(axis=0) > 0, best, li)
