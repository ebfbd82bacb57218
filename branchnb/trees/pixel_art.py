"""Pixel-art trees stay pixel art (beyond the paper; issue 24).

The paper works on photographs: exemplars are resampled smoothly and a mix's
colour is sampled bilinearly through the warp. A sprite drawn on a pixel grid
(hard edges, no anti-aliasing, every pixel one of a few palette colours,
alpha 0 or 1) came out as a smooth painting: anti-aliased curves for its
stair-steps, crown tops wobbling by less than one art pixel, blended colours
no palette has. A user of pixel art expects pixel art out.

:func:`_detect` tells such a source apart (at most :data:`MAX_COLOURS` colours
over the opaque pixels, alpha 0/1, and its art-pixel size: the largest block
its colour runs are multiples of, e.g. 2 for a sprite enlarged x2 nearest);
the exemplar is then resized nearest (:func:`~branchnb.trees.exemplar.normalize_exemplar`)
and a mix of such exemplars is put back on an art-pixel grid of the sources'
block size (:func:`_pixelate`): one colour per block, snapped to the sources'
palette, alpha 0/1, and a 1-block outline re-inked where the sources are
outlined (their outline is the 8-connected rim of the silhouette, as sprites are drawn).

Small sprites (32-256 px) are worked on at about their own size
(:class:`~branchnb.trees.library.TreeLibrary`'s automatic size, beyond the paper's 1024): their
art pixels are then 1-1.5 working pixels, kept hard (:data:`~branchnb.trees.exemplar.SPRITE_SIZE`)
and mixed on the working pixel grid. An outline is also found from the rim alone
(:func:`_rim_ink`), 1-2 pixel bumps hanging off a straight edge are taken off (:func:`_drop_bumps`:
re-inked they were outline stubs beside a trunk), and when no source inks anything inside its rim
(:func:`_inner_ink`), no ink is left inside a mix.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import gcd

import numpy as np
from scipy import ndimage as ndi

#: A source with more distinct opaque colours than this is not pixel art (drawn art is
#: anti-aliased: hundreds of colours along every edge).
MAX_COLOURS = 32

#: Ink-coloured pieces inside a pixel-art mix of at most this many art pixels are specks of a
#: warped outline or seam (sprites draw no ink dots inside; their inner lines are longer).
SPECK_BLOCKS = 3

#: Colours are compared at this precision (8-bit sources, and float sources written from them).
_QUANT = 255.0


@dataclass(frozen=True)
class PixelArt:
    """What makes a source pixel art.

    Parameters
    ----------
    block : int
        Source pixels per art pixel (1: drawn at its own size; 2: enlarged x2 nearest).
    palette : (k, 3) float32 ndarray
        The distinct colours of the opaque pixels.

    Examples
    --------
    >>> img = np.zeros((8, 8, 4), np.float32)
    >>> img[2:6, 2:6] = (0.2, 0.6, 0.2, 1.0); img[2:4, 2:4, :3] = 0.0
    >>> art = _detect(img)
    >>> art.block, len(art.palette)
    (2, 2)
    """

    block: int
    palette: np.ndarray


def _runs_gcd(lab: np.ndarray) -> int:
    """GCD of the lengths of equal-label runs along rows and columns (runs cut by the border
    excluded: a sprite need not start on its block grid at the image edge)."""
    g = 0
    for a in (lab, lab.T):
        change = np.ones((a.shape[0], a.shape[1] + 1), bool)
        change[:, 1:-1] = a[:, 1:] != a[:, :-1]
        for row in change:
            idx = np.flatnonzero(row)
            runs = np.diff(idx)[1:-1]           # inner runs only
            for r in np.unique(runs):
                g = gcd(g, int(r))
                if g == 1:
                    return 1
    return max(g, 1)


def _detect(rgba: np.ndarray) -> PixelArt | None:
    """:class:`PixelArt` of a straight RGBA source, or None when it is not pixel art.

    Pixel art: every alpha is 0 or 1 (within 1/255) and the opaque pixels take at most
    :data:`MAX_COLOURS` colours (anti-aliased drawings have hundreds along their edges).
    """
    a = np.asarray(rgba, np.float32)
    if a.ndim != 3 or a.shape[2] != 4:
        return None
    alpha = a[..., 3]
    if np.any((alpha > 1.0 / _QUANT) & (alpha < 1.0 - 1.0 / _QUANT)):
        return None
    opaque = alpha >= 0.5
    if opaque.sum() < 16 or opaque.all():
        return None
    q = np.round(np.clip(a[..., :3], 0, 1) * _QUANT).astype(np.int32)
    key = (q[..., 0] << 16) | (q[..., 1] << 8) | q[..., 2]
    cols, first = np.unique(key[opaque], return_index=True)
    if len(cols) > MAX_COLOURS:
        return None
    lab = np.where(opaque, key, -1)
    block = _runs_gcd(lab)
    pal = np.clip(a[..., :3][opaque][first], 0, 1)        # the colours as given, not rounded
    return PixelArt(int(block), pal)


#: A pixel-art source is outlined when at least this share of its rim (the 8-connected rim of its
#: silhouette) is its darkest palette colour.
RIM_INK_SHARE = 0.6
#: ... and that colour is at most this dark (Rec. 601 luma).
RIM_INK_LUMA = 0.35


def _rim_ink(image: np.ndarray, palette: np.ndarray):
    """The outline colour of a pixel-art image when its rim is inked in its darkest palette
    colour (see :data:`RIM_INK_SHARE`), else None.

    The stroke-width measure of drawn art misses outlines enlarged by a non-integer factor
    (rows doubled here and there) and on thin shapes (palm fronds); on a pixel grid the rim
    itself says it.
    """
    img = np.asarray(image, np.float32)
    op = img[..., 3] >= 0.5
    rim = op & ~ndi.binary_erosion(np.pad(op, 1), np.ones((3, 3), bool))[1:-1, 1:-1]
    pal = np.asarray(palette, np.float32)
    if not rim.any() or len(pal) < 2:
        return None
    dark = pal[int(np.argmin(pal @ np.float32([0.299, 0.587, 0.114])))]
    if float(dark @ np.float32([0.299, 0.587, 0.114])) > RIM_INK_LUMA:
        return None
    share = float(np.mean(np.abs(img[rim, :3] - dark).max(axis=1) <= 1.5 / _QUANT))
    return dark if share >= RIM_INK_SHARE else None


def _inner_ink(image: np.ndarray, ink, block: float) -> bool:
    """Whether a pixel-art image has ink-coloured pixels inside, off its rim (the rim taken
    ``block`` + 1 pixels deep: enlarged art doubles some rows of its outline)."""
    img = np.asarray(image, np.float32)
    op = img[..., 3] >= 0.5
    deep = ndi.binary_erosion(np.pad(op, 1), np.ones((3, 3), bool),
                              iterations=int(np.ceil(block)) + 1)[1:-1, 1:-1]
    k = deep & (np.abs(img[..., :3] - np.asarray(ink, np.float32)).max(axis=2) <= 1.5 / _QUANT)
    return int(k.sum()) > 2 * block * block


def _blocks(n: int, g: float, from_end: bool) -> np.ndarray:
    """Art-block index of each of ``n`` pixels (blocks of ``g`` px; ``from_end``: counted from the end)."""
    i = np.arange(n, dtype=np.float64)
    return (np.floor((n - 0.5 - i) / g) if from_end else np.floor((i + 0.5) / g)).astype(np.int64)


def _block_mode(bid: np.ndarray, labels: np.ndarray, valid: np.ndarray, n_blocks: int, n_labels: int) -> np.ndarray:
    """Most common of ``labels`` (0..n_labels-1) per block over ``valid`` pixels (-1: none)."""
    key = bid[valid] * n_labels + labels[valid]
    cnt = np.bincount(key, minlength=n_blocks * n_labels).reshape(n_blocks, n_labels)
    return np.where(cnt.max(axis=1) > 0, cnt.argmax(axis=1), -1)


def _clean_blocks(bo: np.ndarray) -> np.ndarray:
    """Art pixels hanging on by one side go, notches open on one side fill: a warp's sub-block
    wobble on the rim, which a pixel artist would not draw (two rounds)."""
    st = np.array([[0, 1, 0], [1, 0, 1], [0, 1, 0]])
    for _ in range(2):
        nb = ndi.convolve(bo.astype(np.int8), st, mode="constant")
        bo = (bo & ((nb >= 2) | _spike_ends(bo, nb))) | (~bo & (nb >= 3))
    for k in range(4):          # the same for bumps 2 art pixels wide, on each side
        bo = np.rot90(_drop_bumps(np.rot90(bo, k)), -k)
    return bo


def _spike_ends(bo: np.ndarray, nb: np.ndarray) -> np.ndarray:
    """Art pixels hanging on by one side that end a spike (a crown's tip) rather than stick out of
    a flat edge: the one neighbour they hang on has an open side across the direction of the spike.
    A wobble on a straight edge hangs on a pixel of that edge, closed on both sides."""
    p = np.pad(bo, 1)
    h, w = bo.shape
    out = np.zeros_like(bo)
    one = bo & (nb == 1)
    for dy, dx in ((-1, 0), (1, 0), (0, -1), (0, 1)):
        at = p[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]            # the neighbour in this direction
        # its two sides across (dy, dx)
        s1 = p[1 + dy + dx:1 + dy + dx + h, 1 + dx + dy:1 + dx + dy + w]
        s2 = p[1 + dy - dx:1 + dy - dx + h, 1 + dx - dy:1 + dx - dy + w]
        out |= one & at & ~(s1 & s2)
    return out


#: Widest bump (art pixels) one art pixel tall on a straight edge that :func:`_clean_blocks` takes off.
BUMP_BLOCKS = 2


def _drop_bumps(bo: np.ndarray) -> np.ndarray:
    """Take off runs of at most :data:`BUMP_BLOCKS` art pixels hanging one art pixel below a straight
    bottom edge (the edge goes on at both ends): re-inked, they show as outline stubs (e.g. under a
    crown beside the trunk), which sprites do not draw."""
    p = np.pad(bo, 1)
    above = np.zeros_like(p)
    above[1:] = p[:-1]
    below = np.zeros_like(p)
    below[:-1] = p[1:]
    cand = p & above & ~below
    lab, _ = ndi.label(cand, np.array([[0, 0, 0], [1, 1, 1], [0, 0, 0]]))
    out = p.copy()
    for sl in ndi.find_objects(lab):
        if sl is None:
            continue
        r, c0, c1 = sl[0].start, sl[1].start, sl[1].stop - 1
        if c1 - c0 + 1 > BUMP_BLOCKS or c0 < 1 or c1 > p.shape[1] - 2:
            continue
        if not p[r, c0 - 1] and not p[r, c1 + 1] and above[r, c0 - 1] and above[r, c1 + 1]:
            out[r, c0:c1 + 1] = False
    return out[1:-1, 1:-1]


def _pixelate(image: np.ndarray, arts: list[PixelArt], blocks: list[float], *, ink=None,
              layers: tuple = (), inner_ink: bool = True, ink_blocks: int = 1) -> tuple[np.ndarray, tuple]:
    """Put a mix of pixel-art sources back on their art-pixel grid.

    ``blocks`` are the sources' art-pixel sizes at the working size (their mean is the grid,
    aligned with the bottom edge, where the tree stands). A block is opaque when most of its
    pixels are (then single art pixels hanging on by one side go and one-block notches fill);
    its colour is the most common palette colour of its pixels (each snapped to the nearest
    colour of the sources' palettes); integer ``layers`` (e.g. the source per pixel) take their
    most common value, float ones (a trunk mask) their mean. With ``ink`` (the sources are
    outlined) the 8-connected rim of art pixels is inked with the palette colour nearest
    ``ink``, and ink-coloured art pixels just inside it (the warped old outline) or alone
    inside (specks of a warped seam) take the colour of the nearest art pixel that is neither;
    without ``inner_ink`` (no source inks anything but its rim) every ink art pixel inside does
    (stubs of a source's rim where a trunk meets a crown). ``ink_blocks``: the outline's width in
    art pixels (sprites outlined 2-3 px wide keep that width instead of a 1 px rim).
    """
    img = np.asarray(image, np.float32)
    h, w = img.shape[:2]
    g = max(1.0, float(np.mean(blocks)))
    if g < 1.5:     # sprites at about their own size (enlarged < 1.5x): the working pixel grid
        g = 1.0
    by, bx = _blocks(h, g, True), _blocks(w, g, False)
    nby, nbx = int(by.max()) + 1, int(bx.max()) + 1
    bid = by[:, None] * nbx + bx[None, :]
    nb = nby * nbx
    opaque = img[..., 3] >= 0.5
    cnt = np.bincount(bid.ravel(), minlength=nb)
    bo = (np.bincount(bid.ravel(), weights=opaque.ravel().astype(np.float64), minlength=nb)
          >= 0.5 * cnt).reshape(nby, nbx)
    bo = _clean_blocks(bo)
    pal = np.unique(np.concatenate([a.palette for a in arts]), axis=0).astype(np.float32)
    idx = np.zeros((h, w), np.int64)
    if opaque.any():
        idx[opaque] = np.argmin(((img[opaque, None, :3] - pal[None]) ** 2).sum(axis=2), axis=1)
    bcol = _block_mode(bid, idx, opaque, nb, len(pal)).reshape(nby, nbx)
    if ink is not None and bo.any():
        k_ink = int(np.argmin(((pal - np.asarray(ink, np.float32)) ** 2).sum(axis=1)))
        pad = np.pad(bo, 1)
        k = max(1, int(ink_blocks))
        inner = ndi.binary_erosion(pad, np.ones((3, 3), bool), iterations=k)[1:-1, 1:-1]
        rim = bo & ~inner
        ring = inner & ~ndi.binary_erosion(pad, np.ones((3, 3), bool), iterations=k + 1)[1:-1, 1:-1]
        bcol[rim] = k_ink
        is_ink = bo & (bcol == k_ink)
        deep, n = ndi.label(is_ink & inner & ~ring, np.ones((3, 3), bool))
        speck = (np.bincount(deep.ravel(), minlength=n + 1) <= SPECK_BLOCKS)[deep] & (deep > 0)
        stray = (ring & is_ink) | speck
        if not inner_ink:       # the sources ink only their rims: any ink inside is a warped rim
            stray = is_ink & ~rim
        good = bo & ~rim & (bcol >= 0) & (bcol != k_ink)
        if stray.any() and good.any():
            near = ndi.distance_transform_edt(~good, return_distances=False, return_indices=True)
            bcol[stray] = bcol[near[0][stray], near[1][stray]]
    # an opaque block none of whose pixels was opaque: the nearest coloured block's colour
    miss = bo & (bcol < 0)
    if miss.any() and (bcol >= 0).any():
        near = ndi.distance_transform_edt(bcol < 0, return_distances=False, return_indices=True)
        bcol[miss] = bcol[near[0][miss], near[1][miss]]
    out = np.zeros((h, w, 4), np.float32)
    bo_px = bo[by[:, None], bx[None, :]]
    out[bo_px, :3] = pal[np.maximum(bcol, 0)][by[:, None], bx[None, :]][bo_px]
    out[..., 3] = bo_px
    lay = []
    for x in layers:
        x = np.asarray(x)
        if np.issubdtype(x.dtype, np.integer):
            lo = int(x.min())
            m = _block_mode(bid, x - lo, opaque, nb, int(x.max()) - lo + 1)
            v = np.where(m >= 0, m + lo, -1).reshape(nby, nbx)
            if (v >= 0).any():
                near = ndi.distance_transform_edt(v < 0, return_distances=False, return_indices=True)
                v = v[near[0], near[1]]
            v = np.where(bo, v, -1)
        else:
            sm = np.bincount(bid[opaque], weights=x[opaque].astype(np.float64), minlength=nb)
            v = (sm / np.maximum(np.bincount(bid[opaque], minlength=nb), 1)).reshape(nby, nbx)
            v = np.where(bo, v, 0.0).astype(x.dtype)
        lay.append(v[by[:, None], bx[None, :]])
    return out, tuple(lay)
