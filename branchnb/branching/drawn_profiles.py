"""A drawn map's coast as the example draws it, and its region textures carried to new shapes.

Beyond the paper (issue 23). :func:`~branchnb.branching.drawing.draw_in_style`
drew a map's coast as one line of one colour and width, and filled a region
that is not one flat colour with the example's pixels at the same place,
smeared (nearest kept pixel) wherever the example's region did not reach.
A fantasy map's double coast (a thick line and a thin line a few pixels off
shore) became one line, and a sea hatched with wave dashes or a land with
tree glyphs lost its marks or showed streaks where the output's region lies
on the example's other region.

- :func:`coast_profile` measures the colour across the coast as a function
  of the signed distance to the branch region's edge (median of the
  example's pixels at every half pixel of distance, away from the branches
  and the frame); :func:`paint_coast` paints that profile along the
  output's own region edge, so every line parallel to the coast (a double
  line, a halo of shallow water) is drawn at the example's offsets.
- :func:`quilt_fill` fills the pixels of a texture that the example's region
  does not cover with blocks copied whole from where it does (no smear: a
  wave dash stays a dash).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from .skeleton_map import PixelMap

__all__: list[str] = []

#: Half-pixel bins of signed distance to the coast, measured this far on either side (pixels).
_PROFILE_REACH = 14.0
#: A bin is drawn ink when its colour is this far (Euclidean) from its side's region colour.
_INK = 0.05


def _signed_distance(inside: np.ndarray) -> np.ndarray:
    """Distance to the edge of ``inside``: negative inside (about -1 on its outermost pixels), positive outside.

    Smoothed by a Gaussian of one pixel: a raster edge's staircase made every line
    parallel to it a staircase too (the example is read the same way, so the
    offsets stay the example's)."""
    m = np.asarray(inside, bool)
    sd = np.where(m, -ndi.distance_transform_edt(m), ndi.distance_transform_edt(~m)).astype(np.float32)
    return ndi.gaussian_filter(sd, 1.0, mode="nearest")


def coast_profile(image: np.ndarray, inside: np.ndarray, pm: PixelMap, margin: float,
                  ground_in: np.ndarray, ground_out: np.ndarray, min_count: int = 20):
    """The example's colour across the edge of ``inside`` (the land), or None when no ink is drawn there.

    Parameters
    ----------
    image : (H, W, C) float32
        The example.
    inside : (H, W) bool
        Its branch region.
    pm : PixelMap
        Its structure's pixel map (pixels within ``margin`` of a branch are not read).
    margin : float
        Distance from the branches (pixels) within which nothing is read.
    ground_in, ground_out : (C,) arrays
        The region colours inside and outside.
    min_count : int
        Bins with fewer pixels are not read.

    Returns
    -------
    (distances, colours) or None
        ``distances`` (N,) increasing signed distances (negative inland) and
        ``colours`` (N, C); the profile spans from the innermost to the
        outermost bin drawn in ink (plus one bin of ground on either side),
        None when no bin is ink.
    """
    img = np.asarray(image, np.float32)
    m = np.asarray(inside, bool)
    if not m.any() or m.all():
        return None
    sd = _signed_distance(m)
    ok = (np.abs(sd) <= _PROFILE_REACH) & (pm.dist > margin)
    ok[:2] = ok[-2:] = False
    ok[:, :2] = ok[:, -2:] = False
    if np.count_nonzero(ok) < 10 * min_count:
        return None
    b = np.rint(sd[ok] * 2).astype(int)
    px = img[ok]
    order = np.argsort(b, kind="stable")
    b, px = b[order], px[order]
    keys, start, count = np.unique(b, return_index=True, return_counts=True)
    dists, colours = [], []
    for k, s, n in zip(keys, start, count):
        if n >= min_count:
            dists.append(k / 2.0)
            colours.append(np.median(px[s:s + n], axis=0))
    if not dists:
        return None
    d = np.asarray(dists, np.float32)
    c = np.asarray(colours, np.float32)
    ground = np.where((d < 0)[:, None], np.asarray(ground_in, np.float32)[None],
                      np.asarray(ground_out, np.float32)[None])
    ink = np.linalg.norm(c - ground, axis=-1) > _INK
    if not ink.any():
        return None
    i0, i1 = int(np.flatnonzero(ink)[0]), int(np.flatnonzero(ink)[-1])
    i0, i1 = max(i0 - 1, 0), min(i1 + 1, len(d) - 1)
    return d[i0:i1 + 1], c[i0:i1 + 1]


def paint_coast(img: np.ndarray, inside: np.ndarray, profile, ground_in, ground_out) -> np.ndarray:
    """``img`` with ``profile`` (:func:`coast_profile`) painted across the edge of ``inside`` (not the frame).

    Only the profile's ink is painted, as a blend by how far each bin's colour
    lies from its ground (the region texture shows through between the lines).

    Parameters
    ----------
    img : (H, W, C) float ndarray
        The drawn output so far.
    inside : (H, W) bool array_like
        The land (the coast is its edge).
    profile : (distances, colours)
        From :func:`coast_profile`.
    ground_in, ground_out : (C,) array_like
        The land's and the sea's own colours.

    Returns
    -------
    (H, W, C) ndarray
        A copy of ``img`` with the coast painted (``img`` itself when there is no edge).
    """
    d, c = profile
    m = np.asarray(inside, bool)
    if not m.any() or m.all():
        return img
    sd = _signed_distance(m)
    sel = (sd >= d[0]) & (sd <= d[-1])
    if not sel.any():
        return img
    s = sd[sel]
    col = np.stack([np.interp(s, d, c[:, j]) for j in range(c.shape[1])], axis=-1)
    ground = np.where((s < 0)[:, None], np.asarray(ground_in, np.float32)[None],
                      np.asarray(ground_out, np.float32)[None])
    # share of ink: 1 where the profile is far from its ground, fading to 0 at the ground itself
    a = np.clip(np.linalg.norm(col - ground, axis=-1) / (2 * _INK), 0.0, 1.0)[:, None]
    out = img.copy()
    out[sel] = (1 - a) * img[sel] + a * col
    return out


def _box(sat: np.ndarray, y: np.ndarray, x: np.ndarray, n: int) -> np.ndarray:
    """Sums of the ``n`` x ``n`` boxes at top-left corners (``y``, ``x``) from the summed-area table ``sat``."""
    return sat[y + n, x + n] - sat[y, x + n] - sat[y + n, x] + sat[y, x]


def quilt_fill(tex: np.ndarray, keep: np.ndarray, block: int = 16, seed: int = 0,
               marks: np.ndarray | None = None) -> np.ndarray | None:
    """``tex`` with every pixel outside ``keep`` taken from blocks copied whole from inside it.

    The blocks lie on a grid of ``block`` pixels; each one that holds a pixel
    outside ``keep`` gets a randomly chosen source block that lies wholly in
    ``keep`` (smaller blocks when none fits, down to 4 px). None when not even
    a 4 px block fits. ``marks``: pixels of marks on the ground (dashes,
    glyphs); source blocks whose rim crosses one are not used while others
    exist (a glyph cut by a block's edge left half a tree or a dark speck).

    Parameters
    ----------
    tex : (H, W, C) ndarray
        The region's texture.
    keep : (H, W) bool ndarray
        Where ``tex`` is the region's own.
    block : int, default 16
        Largest block side (pixels).
    seed : int, default 0
        Seed of the block choice.
    marks : (H, W) bool ndarray, optional
        Pixels of marks on the ground.

    Returns
    -------
    (H, W, C) ndarray or None

    Notes
    -----
    The core's quilting (:func:`branchnb.core.completion.complete_gaps` with
    ``forbidden = ~keep``, no gradient-domain correction) was tried in its
    place on hatched seas (wave dashes, 256-1000 px, the region a disk
    covering 38 % of the texture): 20-60 times slower (45 s against 1.7 s
    at 1000 px) and it cut more marks (its graph-cut seams run through the
    dashes: 9-13 % of the marks in the filled part were fragments under a
    full dash's size, against 3-6 % here and 2-6 % in the example). A flat
    ground with sparse marks needs no matching: whole blocks whose rim
    crosses no mark suffice.
    """
    h, w = keep.shape
    rng = np.random.default_rng(seed)
    out = tex.copy()
    while block >= 4:
        inner = ndi.binary_erosion(keep, np.ones((block, block), bool), border_value=0)
        # (the erosion's origin is the block's centre: shift to its top-left corner)
        ys, xs = np.nonzero(inner)
        ys, xs = ys - block // 2, xs - block // 2
        good = (ys >= 0) & (xs >= 0) & (ys + block <= h) & (xs + block <= w)
        ys, xs = ys[good], xs[good]
        if len(ys) and marks is not None:
            # marks on a block's rim: the whole block's marks minus its interior's (summed-area table)
            sat = np.pad(np.asarray(marks, np.int64), ((1, 0), (1, 0))).cumsum(0).cumsum(1)

            rim = _box(sat, ys, xs, block) - _box(sat, ys + 1, xs + 1, block - 2)
            if (rim == 0).any():
                ys, xs = ys[rim == 0], xs[rim == 0]
        if len(ys):
            break
        block //= 2
    else:
        return None
    for y0 in range(0, h, block):
        for x0 in range(0, w, block):
            hole = ~keep[y0:y0 + block, x0:x0 + block]
            if not hole.any():
                continue
            j = int(rng.integers(len(ys)))
            bh, bw = hole.shape
            src = tex[ys[j]:ys[j] + bh, xs[j]:xs[j] + bw]
            out[y0:y0 + bh, x0:x0 + bw][hole] = src[hole]
    return out
