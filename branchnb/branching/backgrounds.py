"""Automatic extraction, step 2 (beyond the paper): what is no branch.

Lines along the image frame, binary (water) masks traced by their medial
axis, large flat regions (a sea) and the outlines of flat regions touching
the border (a coast, a country border); the domain of an example is in
:mod:`.example_domains` (re-exported here).

Split from :mod:`.extraction` (which re-exports every name).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

__all__ = [
    "frame_lines",
    "is_binary",
    "large_flat_regions",
    "binary_channels",
    "border_flat_regions",
    "outline_pixels",
    "region_border_pixels",
    "flat_background",
    "unlike_background",
    "example_domain",
]


def frame_lines(mask, band: int = 4, share: float = 0.5) -> np.ndarray:
    """Pixels of ``mask`` that form a line along the image frame (a drawn border, a map's frame).

    Along each side, the band of ``band`` pixels is a frame line when
    ``mask`` covers at least ``share`` of that side's length there; a
    branch that merely enters the image through a side covers a few pixels.

    Parameters
    ----------
    mask : (H, W) bool array_like
        Line pixels (e.g. a thresholded ridge mask).
    band : int, default 4
        Width of the strip along each side (pixels).
    share : float, default 0.5
        Fraction of a side's length the strip must cover.

    Returns
    -------
    (H, W) bool ndarray
        The frame-line pixels (all False when none).
    """
    m = np.asarray(mask, bool)
    out = np.zeros_like(m)
    h, w = m.shape
    b = int(min(band, h // 4, w // 4))
    if b < 1:
        return out
    for sl, axis in (((slice(0, b), slice(None)), 0), ((slice(h - b, h), slice(None)), 0),
                     ((slice(None), slice(0, b)), 1), ((slice(None), slice(w - b, w)), 1)):
        strip = m[sl]
        if strip.any(axis=axis).mean() < share:
            continue
        # a line, not the edge of a wide region (a sea reaching the border): the
        # next band inwards is mostly free
        r0, r1 = sl[0].start, sl[0].stop
        c0, c1 = sl[1].start, sl[1].stop
        if axis == 0:
            inner = m[b:2 * b] if r0 == 0 else m[h - 2 * b:h - b]
        else:
            inner = m[:, b:2 * b] if c0 == 0 else m[:, w - 2 * b:w - b]
        if inner.any(axis=axis).mean() < 0.5 * share:
            out[r0:r1, c0:c1] = strip
    return out


#: An image is no mask when at least this share of its pixels lies beyond its two levels (the 1st and 99th
#: percentiles) by :data:`THIRD_LEVEL_GAP` of their difference: 2 px navy rivers and coast on a 768 px
#: map of white land and grey sea cover 0.5-0.7 % of it, under the 1 % the percentiles see; a
#: binary mask's anti-aliasing and noise lie between or at its two levels.
THIRD_LEVEL_SHARE = 0.001
#: ... (the distance beyond a level, as a share of the two levels' difference)
THIRD_LEVEL_GAP = 0.5


def is_binary(gray, *, tol: float = 0.1, share: float = 0.97) -> bool:
    """True if at least ``share`` of the pixels lie within ``tol`` (of the range) of the darkest
    or the brightest level, and the two levels differ by at least 0.25 (a mask, maybe anti-aliased).

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1].
    tol : float, default 0.1
        Distance to the 1st / 99th percentile level, as a fraction of their
        difference.
    share : float, default 0.97
        Fraction of the pixels that must lie near one of the two levels.

    Returns
    -------
    bool
        Whether the image is a (near-)binary mask.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((20, 20)); m[5:9] = 1
    >>> is_binary(m), is_binary(np.linspace(0, 1, 400).reshape(20, 20))
    (True, False)
    """
    g = np.asarray(gray, np.float64)
    lo, hi = np.percentile(g, [1, 99])
    if hi - lo < 0.25:
        return False
    # a third level beyond the two, rarer than the percentiles see (thin dark lines on a two-colour map:
    # a map's sea and land read as the mask's two levels, and the sea became the channels, issue 23)
    out = (g < lo - THIRD_LEVEL_GAP * (hi - lo)) | (g > hi + THIRD_LEVEL_GAP * (hi - lo))
    if np.mean(out) >= THIRD_LEVEL_SHARE:
        return False
    t = tol * (hi - lo)
    return bool(np.mean((np.abs(g - lo) <= t) | (np.abs(g - hi) <= t)) >= share)


def large_flat_regions(mask, radius: float, min_area: float = 0.01) -> np.ndarray:
    """Parts of ``mask`` far wider than any branch: a sea, a lake, a flat background.

    The opening of ``mask`` with a disk of ``radius`` keeps what a disk of
    that radius fits into; its connected pieces of at least ``min_area`` of
    the image are returned, grown by one pixel.

    Parameters
    ----------
    mask : (H, W) bool array_like
        Candidate pixels (e.g. a mask's foreground).
    radius : float
        Radius (pixels) of the opening disk: wider than any branch.
    min_area : float, default 0.01
        Smallest piece kept, as a fraction of the image.

    Returns
    -------
    (H, W) bool ndarray
        The large regions (within ``mask``).
    """
    import cv2

    m = np.asarray(mask, bool)
    r = max(int(round(radius)), 1)
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    opened = cv2.morphologyEx(m.astype(np.uint8), cv2.MORPH_OPEN, disk, borderType=cv2.BORDER_REPLICATE) > 0
    lab, n = ndi.label(opened)
    if n == 0:
        return np.zeros_like(m)
    sizes = np.bincount(lab.ravel())
    keep = sizes >= min_area * m.size
    keep[0] = False
    out = keep[lab]
    return ndi.binary_dilation(out) & m if out.any() else out


def binary_channels(gray, polarity: str = "auto", *, flat_regions: bool = True):
    """Foreground channels of a binary mask, the large flat regions removed, and the medial axis.

    The foreground is the bright class (``polarity="bright"``), the dark one
    (``"dark"``), or with ``"auto"`` the class that covers less of the image.
    Foreground regions much wider than the channels (more than 3 x their
    median radius and 1 % of the image, e.g. the sea a delta drains into)
    are no branches: they are returned as ``region``.

    Parameters
    ----------
    gray : (H, W) array_like
        The mask's luminance (two levels, maybe anti-aliased).
    polarity : {"auto", "bright", "dark"}, default "auto"
        Which class is foreground.
    flat_regions : bool, default True
        Set wide foreground regions apart as ``region``; False keeps every
        foreground pixel a channel (a drawn tree's wide trunk is no sea).

    Returns
    -------
    channels : (H, W) bool
        Foreground without the large flat regions (and without a line
        along the image frame).
    region : (H, W) bool
        The large flat foreground regions.
    skeleton : (H, W) bool
        Medial axis of ``channels``.
    radius : (H, W) float
        Distance transform of the whole foreground (the channel's half width
        on its centre line), capped at the flat regions' scale.
    """
    from skimage.morphology import skeletonize

    g = np.asarray(gray, np.float64)
    lo, hi = np.percentile(g, [1, 99])
    bright = g > 0.5 * (lo + hi)
    if polarity == "bright":
        fg = bright
    elif polarity == "dark":
        fg = ~bright
    else:
        fg = bright if bright.mean() <= 0.5 else ~bright
    fg = fg & ~frame_lines(fg, band=8)
    dt = ndi.distance_transform_edt(np.pad(fg, 1, mode="edge"))[1:-1, 1:-1]
    sk0 = skeletonize(fg)
    r_med = float(np.median(dt[sk0])) if sk0.any() else 1.0
    big_r = max(3.0 * r_med, 3.0)
    region = large_flat_regions(fg, big_r) if flat_regions else np.zeros_like(fg)
    if region.any():
        lines = region & ~_no_thick_lines(region, dt)
        if lines.any():
            # thick lines are channels: their radius is read in full (the cap is for a sea's edge)
            region &= ~lines
            big_r = max(big_r, float(dt[lines].max()) + 0.5)
    if not flat_regions:
        big_r = float(dt.max()) + 1.0
    channels = fg & ~region
    skel = skeletonize(channels)
    # Skeleton stubs along the region's edge are outline, not branches.
    if region.any():
        skel &= ndi.distance_transform_edt(~region) > 1.5
    # The distance to the nearest background pixel centre is r + 0.5 on an
    # odd-width channel's centre pixel and r on an even one (the centre line
    # falls between two pixels): -0.25 is unbiased on average.
    radius = np.minimum(dt, big_r) - 0.25
    return channels, region, skel, np.maximum(radius, 0.5)


#: A wide foreground piece longer than this many times its widest radius squared (area / r^2) is a
#: thick line (a trunk), not a flat region (a sea); a sea strip along the frame is ~1-10.
LINE_ELONGATION = 25.0


def _no_thick_lines(region: np.ndarray, dt: np.ndarray) -> np.ndarray:
    """``region`` without its pieces that are thick lines: area over :data:`LINE_ELONGATION` x the
    square of their largest distance ``dt`` to the background.

    Beyond the paper (issue 23): a root drawing's 6-px trunks entering from the top among 1-px roots
    are 3 x the median radius, as wide as a delta's sea in that test; taken for a sea, they left the
    domain and the output's roots started inland and at the left side.

    Examples
    --------
    >>> m = np.zeros((100, 200), bool); m[40:48, 10:190] = True; m[60:100, 150:200] = True
    >>> dt = ndi.distance_transform_edt(m)
    >>> r = _no_thick_lines(m, dt)
    >>> bool(r[44, 50]), bool(r[80, 170])
    (False, True)
    """
    lab, n = ndi.label(region)
    if n == 0:
        return region
    idx = np.arange(1, n + 1)
    area = ndi.sum_labels(region, lab, idx)
    widest = np.asarray(ndi.maximum(dt, lab, idx), np.float64)
    keep = np.r_[False, area <= LINE_ELONGATION * np.maximum(widest, 1.0) ** 2]
    return keep[lab]


def _flat_region_labels(gray, radius: float, tol: float):
    """Labels of the large flat-colour regions (wider than ``radius``) and which of them touch the border."""
    g = np.asarray(gray, np.float64)
    flat = (ndi.maximum_filter(g, 5) - ndi.minimum_filter(g, 5)) < tol
    flat = _fill_marks(flat, radius)
    lab, n = ndi.label(large_flat_regions(flat, radius, min_area=0.02))
    touch = np.zeros(n + 1, bool)
    for edge in (lab[0], lab[-1], lab[:, 0], lab[:, -1]):
        touch[edge] = True
    touch[0] = False
    return lab, n, touch


def _fill_marks(flat: np.ndarray, radius: float) -> np.ndarray:
    """``flat`` with its small enclosed non-flat specks filled: marks printed on a region (a sea's wave
    dashes, a land's tree glyphs, town dots) of at most ``2 radius**2`` pixels each.

    Beyond the paper (issue 23): a sea hatched with wave dashes every ~20 px has no spot a disk of
    ``radius`` fits into between them, so it was no flat region at all, and a drawn map's outside was
    taken for land (its domain a blob bitten by the dashes, the extracted "structure" the sea itself).
    Lines are networks far larger than the bound and stay unfilled.
    """
    # padded with flat pixels: a mark cut by the frame is enclosed too
    holes = ndi.binary_fill_holes(np.pad(flat, 1, constant_values=True))[1:-1, 1:-1] & ~flat
    if not holes.any():
        return flat
    lab, n = ndi.label(holes)
    small = np.bincount(lab.ravel(), minlength=n + 1) <= 2.0 * radius ** 2
    small[0] = False
    return flat | small[lab]


def _ground_regions(gray, branches, lab, n: int, tol: float) -> np.ndarray:
    """Per label of ``lab`` (0..n): True when the region has the colour the ``branches`` lie in: the
    median grey of the pixels 3-8 px beside them, when at least half of those pixels are within
    ``2 tol`` of it (a flat ground, not a relief of greys), and the region's median is too."""
    import cv2

    br = np.asarray(branches, bool)
    out = np.zeros(n + 1, bool)
    if not br.any() or n == 0:
        return out
    b8 = br.astype(np.uint8)
    near = cv2.dilate(b8, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (17, 17))) > 0
    ring = near & ~(cv2.dilate(b8, np.ones((7, 7), np.uint8)) > 0)
    if not ring.any():
        return out
    g = np.asarray(gray, np.float64)
    # Only ring pixels whose mirror across the nearest branch pixel has their grey: a branch lies in
    # its ground (the same colour on both sides); a coast line has land on one side and sea on the
    # other, and on a small densely drawn map its one-sided ring would otherwise outvote the land.
    _d, (iy, ix) = ndi.distance_transform_edt(~br, return_indices=True)
    ry, rx = np.nonzero(ring)
    my = np.clip(2 * iy[ry, rx] - ry, 0, g.shape[0] - 1)
    mx = np.clip(2 * ix[ry, rx] - rx, 0, g.shape[1] - 1)
    two_sided = np.abs(g[my, mx] - g[ry, rx]) <= 2 * tol
    ground = float(np.median(g[ring]))
    if np.mean(np.abs(g[ring] - ground) <= 2 * tol) < 0.5:
        return out
    if np.count_nonzero(two_sided) >= max(20, 0.1 * len(ry)):
        ring2 = np.zeros_like(ring)
        ring2[ry[two_sided], rx[two_sided]] = True
        # the one-sided ring outvoted the ground: few of the two-sided pixels have its grey
        if np.mean(np.abs(g[ring2] - ground) <= 2 * tol) < 0.3:
            ring, ground = ring2, float(np.median(g[ring2]))
    if np.mean(np.abs(g[ring] - ground) <= 2 * tol) < 0.5:
        return out
    med = ndi.median(g, lab, np.arange(1, n + 1))
    out[1:] = np.abs(np.asarray(med, np.float64) - ground) <= 2 * tol
    return out


def border_flat_regions(gray, radius: float, tol: float = 0.02, branches=None) -> np.ndarray:
    """Large flat-colour regions (wider than ``radius``) that touch the image border.

    With ``branches`` ((H, W) bool), regions of the colour the branches lie in are left out: on a
    crop whose land runs off the frame, the land is no outside region (its rivers' junctions would
    otherwise count as the outline of the land pieces between them and be cut).

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1].
    radius : float
        Regions must be wider than a disk of this radius (pixels).
    tol : float, default 0.02
        Largest range of a flat 5 x 5 neighbourhood.
    branches : (H, W) bool array_like, optional
        Branch pixels; None = no such exclusion.

    Returns
    -------
    (H, W) bool ndarray
        The regions' pixels.
    """
    lab, n, touch = _flat_region_labels(gray, radius, tol)
    if branches is not None:
        touch = touch & ~_ground_regions(gray, branches, lab, n, tol)
    return touch[lab]


def outline_pixels(skeleton, outside, reach: float, gray=None, tol: float = 0.04) -> np.ndarray:
    """Skeleton pixels that trace the outline of the ``outside`` regions (a map's country border, a coast line).

    A skeleton pixel within ``reach`` of ``outside`` is outline when, looking
    away from the nearest outside pixel, the other side is no outside: the
    line separates the outside from the rest, and the line runs along the
    outside rather than into it (its direction, from the structure tensor
    of the skeleton, is within 45 degrees of the outside's edge). A branch
    lying *in* a flat region (a lightning bolt in a flat sky) has that
    region on both sides and stays; so does a river mouth meeting the
    coast.

    With ``gray`` (the image the regions were found in), the other side
    counts by its colour: the line is outline when the two sides differ by
    more than ``tol`` (land on one side, sea on the other), whether or not
    the other side is a large flat region itself; rivers close together
    have land on both sides, though the strip between them is too narrow
    to be a region, and stay branches.

    Parameters
    ----------
    skeleton : (H, W) bool array_like
        Centre-line pixels.
    outside : (H, W) bool array_like
        The outside regions (e.g. :func:`border_flat_regions`).
    reach : float
        Largest distance (pixels) of an outline pixel to ``outside``.
    gray : (H, W) array_like, optional
        Luminance the regions were found in; None = judge the other side by
        ``outside`` alone.
    tol : float, default 0.04
        Smallest luminance difference between the two sides of an outline.

    Returns
    -------
    (H, W) bool ndarray
        The outline pixels of ``skeleton``.
    """
    sk = np.asarray(skeleton, bool)
    out = np.asarray(outside, bool)
    if not out.any() or not sk.any():
        return np.zeros_like(sk)
    import cv2

    # Only skeleton pixels within ``reach`` of the outside count, and their nearest outside pixel lies
    # within ``reach`` of them: the distances and the structure tensor are computed in the window round
    # them (the same values; a 1.5 MP photo's colour candidates took 17 s over the whole frame)
    r = int(np.ceil(reach))
    near = cv2.dilate(out.astype(np.uint8), cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 3, 2 * r + 3)))
    cy, cx = np.nonzero(sk & (near > 0))
    if len(cy) == 0:
        return np.zeros_like(sk)
    m = r + 2 + 16  # the nearest outside pixel, and the tensor's two blurs (4 x 1 + 1 + 4 x 2 px)
    y0, y1 = max(int(cy.min()) - m, 0), min(int(cy.max()) + m + 1, sk.shape[0])
    x0, x1 = max(int(cx.min()) - m, 0), min(int(cx.max()) + m + 1, sk.shape[1])
    dist, (iy, ix) = ndi.distance_transform_edt(~out[y0:y1, x0:x1], return_indices=True)
    sk_w = sk[y0:y1, x0:x1]
    ys, xs = np.nonzero(sk_w & (dist <= reach))
    if len(ys) == 0:
        return np.zeros_like(sk)
    d = dist[ys, xs]
    vy, vx = iy[ys, xs] - ys, ix[ys, xs] - xs
    n = np.maximum(np.hypot(vy, vx), 1e-9)
    iy, ix = iy[ys, xs] + y0, ix[ys, xs] + x0
    step = d + 3.0
    ys, xs = ys + y0, xs + x0
    oy = np.clip(np.rint(ys - vy / n * step).astype(int), 0, sk.shape[0] - 1)
    ox = np.clip(np.rint(xs - vx / n * step).astype(int), 0, sk.shape[1] - 1)
    # The line's direction (structure tensor of the blurred skeleton): a line heading into
    # the outside (a river mouth at the coast) is no outline, one running along it is.
    b = ndi.gaussian_filter(sk_w.astype(np.float64), 1.0)
    gy, gx = np.gradient(b)
    wy, wx = ys - y0, xs - x0
    jxx = ndi.gaussian_filter(gx * gx, 2.0)[wy, wx]
    jyy = ndi.gaussian_filter(gy * gy, 2.0)[wy, wx]
    jxy = ndi.gaussian_filter(gx * gy, 2.0)[wy, wx]
    # the tensor's main axis is the line's normal; the tangent is perpendicular to it
    theta = 0.5 * np.arctan2(2 * jxy, jxx - jyy)
    tx, ty = -np.sin(theta), np.cos(theta)
    heads_out = np.abs(tx * vx + ty * vy) / n > 0.7
    res = np.zeros_like(sk)
    if gray is not None:
        g = np.asarray(gray, np.float64)
        other = np.abs(g[oy, ox] - g[iy, ix]) > tol
    else:
        other = ~out[oy, ox]
    res[ys, xs] = other & ~heads_out
    return res


def region_border_pixels(skeleton, image, radius: float, tol: float = 0.06, reach: float = 8.0) -> np.ndarray:
    """Skeleton pixels of a drawn line between two flat regions of different colours (a country border).

    Beyond the paper: on a political or relief map a drawn border between
    two inside regions (two countries, two land colours) is no branch,
    though it looks like one to the ridge filter, and traced it joins every
    river that crosses it into one tree. A skeleton pixel is border when,
    across the line (its normal from the structure tensor of the
    skeleton), both sides lie in large flat-colour regions (wider than
    ``radius``) whose colours differ by more than ``tol`` in some channel. A
    river has the same ground on both sides and stays, and so do lines on a
    photograph (no flat regions). The skeleton's stretches between junctions
    go out or stay whole, by the majority of their pixels.

    Parameters
    ----------
    skeleton : (H, W) bool array_like
        Centre-line pixels.
    image : (H, W, 3) array_like
        The colour image the skeleton was traced in, float in [0, 1].
    radius : float
        The flat regions must be as large as a disk of this radius (pixels).
    tol : float, default 0.06
        Smallest colour difference (largest over the channels) between the
        two sides.
    reach : float, default 8.0
        Farthest a side is looked for across the line (pixels).

    Returns
    -------
    (H, W) bool ndarray
        The border pixels of ``skeleton``.

    Examples
    --------
    >>> img = np.ones((60, 60, 3), np.float32); img[:, :30] = (0.9, 0.8, 0.6); img[:, 29:31] = 0.0
    >>> sk = np.zeros((60, 60), bool); sk[5:55, 30] = True
    >>> int(region_border_pixels(sk, img, 6.0).sum())
    50
    """
    sk = np.asarray(skeleton, bool)
    rgb = np.asarray(image, np.float64)[..., :3]
    res = np.zeros_like(sk)
    if not sk.any():
        return res
    rng_c = np.max([ndi.maximum_filter(rgb[..., c], 5) - ndi.minimum_filter(rgb[..., c], 5) for c in range(3)], 0)
    # flat pixels in large connected pieces (not opened by a disk: the pieces must reach the line)
    lab, n = ndi.label(rng_c < 0.02)
    sizes = np.bincount(lab.ravel(), minlength=n + 1)
    big = sizes >= max(np.pi * radius ** 2, 0.002 * sk.size)
    big[0] = False
    flat = big[lab]
    if not flat.any():
        return res
    ys, xs = np.nonzero(sk)
    b = ndi.gaussian_filter(sk.astype(np.float64), 1.0)
    gy, gx = np.gradient(b)
    jxx = ndi.gaussian_filter(gx * gx, 2.0)[ys, xs]
    jyy = ndi.gaussian_filter(gy * gy, 2.0)[ys, xs]
    jxy = ndi.gaussian_filter(gx * gy, 2.0)[ys, xs]
    theta = 0.5 * np.arctan2(2 * jxy, jxx - jyy)      # the line's normal
    nx, ny = np.cos(theta), np.sin(theta)
    h, w = sk.shape
    seen = np.zeros((2, len(ys)), bool)
    col = np.zeros((2, len(ys), 3))
    for d in np.arange(3.0, reach + 0.5, 1.0):
        for k, sgn in enumerate((1.0, -1.0)):
            py = np.clip(np.rint(ys + sgn * d * ny).astype(int), 0, h - 1)
            px = np.clip(np.rint(xs + sgn * d * nx).astype(int), 0, w - 1)
            new = ~seen[k] & flat[py, px]
            col[k, new] = rgb[py[new], px[new]]
            seen[k] |= new
    differ = np.abs(col[0] - col[1]).max(-1) > tol
    res[ys, xs] = seen[0] & seen[1] & differ
    # decided per stretch between junctions, by the majority of its pixels: a river running beside the
    # border for a while (its far side then lies beyond the border) stays whole, a border stays out whole
    nb = ndi.convolve(sk.astype(np.int32), np.ones((3, 3), np.int32), mode="constant") - 1
    runs = sk & (nb <= 2)
    lab, n = ndi.label(runs, structure=np.ones((3, 3)))
    if n:
        share = np.bincount(lab[runs], weights=res[runs], minlength=n + 1) / \
            np.maximum(np.bincount(lab[runs], minlength=n + 1), 1)
        keep = res & ~runs                                  # junction pixels: as judged
        keep |= runs & (share[lab] >= 0.5)
        res = keep
    return res


def flat_background(gray, branches, radius: float, tol: float = 0.02) -> np.ndarray:
    """Large flat-colour regions without branches (the sea around a river map's land).

    Pixels whose 5 x 5 neighbourhood varies by less than ``tol`` form flat
    regions; those wider than ``radius`` (see :func:`large_flat_regions`)
    that hold (almost) no ``branches`` pixel and touch the image border are
    returned.

    A branch lies *in* a region when the region's closing (a disk of
    ``radius``) covers it: a drawn river is a thin non-flat line with the
    land on both sides, so the land's closing bridges it, while a coast
    line has land on one side only and belongs to neither. A region holds
    no branches when less than 2 % of the branch pixels lie in it (the
    river mouths touching the coast). When more lie in it, only those with
    the region on both sides count (``_two_sided``): where a wavy coast bends,
    the closing of the sea covers stretches of the drawn coast line, which has
    the sea on one side only (beyond the paper).

    Beyond that rule, a region of the colour the branches lie in (the
    median of the flat pixels 3-8 px beside them) is never background:
    on a crop whose land runs off the frame, rivers running from frame to
    frame cut the land into pieces that each touch the frame and hold no
    river (each river lies between two pieces), yet they are land.

    ... unless a drawn line walls the region off (beyond the paper): a
    terrain map's white lowland has the colour of the white outside, and
    the outside is then told by the dark coast line around it (most of its
    edge away from the frame and the river mouths is a line at least 0.5
    darker than the region, see ``_behind_drawn_line``); a crop's land
    pieces are bounded by the rivers and the relief, not by such a line.

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1].
    branches : (H, W) bool array_like
        Branch pixels (e.g. the rendered annotation).
    radius : float
        Regions must be wider than a disk of this radius (pixels).
    tol : float, default 0.02
        Largest range of a flat 5 x 5 neighbourhood.

    Returns
    -------
    (H, W) bool ndarray
        The background regions' pixels.
    """
    import cv2

    lab, n, touch = _flat_region_labels(gray, radius, tol)
    br = np.asarray(branches, bool)
    keep = np.zeros(n + 1, bool)
    n_br = int(br.sum())
    r = max(int(round(radius)), 1)
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    ground = _ground_regions(gray, br, lab, n, tol)
    g = np.asarray(gray, np.float64)
    near_br = cv2.dilate(br.astype(np.uint8), np.ones((5, 5), np.uint8)) > 0 if n_br else br
    for k in np.flatnonzero(touch):
        region = lab == k
        if ground[k] and not _behind_drawn_line(g, region, near_br):
            continue  # the branches' own ground
        closed = cv2.morphologyEx(region.astype(np.uint8), cv2.MORPH_CLOSE, disk,
                                  borderType=cv2.BORDER_REPLICATE) > 0
        covered = closed & br
        if np.count_nonzero(covered) > 0.02 * n_br:
            covered = _two_sided(covered, region, 2.0 * r)
        keep[k] = np.count_nonzero(covered) <= 0.02 * n_br
    keep[0] = False
    return keep[lab]


def _two_sided(pixels: np.ndarray, region: np.ndarray, reach: float) -> np.ndarray:
    """The ``pixels`` outside ``region`` with it on both sides: the region again within ``reach``
    beyond each, straight across from its nearest region pixel.

    Beyond the paper (issue 23): a river lies *in* its land, which the closing of the land bridges;
    a drawn coast line has the sea on one side only, yet where the coast bends (and where river
    mouths meet it) the closing of the sea covers stretches of it: on a paper map with a wavy coast
    the sea held 2.2 % of the line pixels and was taken for land (the rivers rooted inland)."""
    py, px = np.nonzero(pixels)
    if not len(py):
        return pixels
    _d, (iy, ix) = ndi.distance_transform_edt(~region, return_indices=True)
    v = np.stack([py - iy[py, px], px - ix[py, px]], axis=1).astype(np.float64)
    n = np.hypot(v[:, 0], v[:, 1])
    ok = n > 0
    v[ok] /= n[ok, None]
    out = np.zeros_like(pixels)
    h, w = region.shape
    # (pixels in the region itself are the branch mask's rim over its edge, on one side of a line)
    hit = np.zeros(len(py), bool)
    for t in np.arange(1.0, reach + 1.0, 1.0):
        yy = np.clip(np.rint(py + v[:, 0] * t).astype(int), 0, h - 1)
        xx = np.clip(np.rint(px + v[:, 1] * t).astype(int), 0, w - 1)
        hit |= region[yy, xx] & ok
    out[py[hit], px[hit]] = True
    return out


def _behind_drawn_line(gray: np.ndarray, region: np.ndarray, near_branches: np.ndarray, *,
                       contrast: float = 0.5, share: float = 0.6) -> bool:
    """Whether a drawn dark line (a coast) walls ``region`` off: of the pixels 1-6 px outside it,
    away from the frame (3 px) and from the branches (their mouths cross the coast), at least 65 %
    remain and ``share`` of those are ``contrast`` darker than the region's median. (The outside of
    a terrain map has 4-24 % of its edge by river mouths; a crop's land piece cut off by a river
    running into the coast has half.)"""
    import cv2

    r8 = region.astype(np.uint8)
    ring = (cv2.dilate(r8, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (13, 13))) > 0) & ~region
    ring[:3] = ring[-3:] = False
    ring[:, :3] = ring[:, -3:] = False
    n_ring = int(np.count_nonzero(ring))
    if n_ring == 0:
        return False
    rest = ring & ~near_branches
    n_rest = int(np.count_nonzero(rest))
    if n_rest < 0.65 * n_ring:
        return False    # branches run along a third of its edge or more: a piece of land they cut
    med = float(np.median(gray[region]))
    # the ring is 6 px wide and the line ~2 px: a ring pixel counts as on the line when a line pixel
    # lies across it (the darkest of its 7 x 7 neighbourhood), not only when it is one
    darkest = cv2.erode(gray.astype(np.float32), np.ones((7, 7), np.uint8))
    return bool(np.mean(darkest[rest] < med - contrast) >= share)


def unlike_background(image, branches, radius: float = 12.0, k: float = 4.0, min_diff: float = 0.12,
                      min_area: float = 0.02) -> np.ndarray:
    """Large branch-free regions of another colour than the ground the branches lie in (beyond the paper).

    :func:`flat_background` needs a flat colour; on a photograph the
    outside is textured (a table round a leaf, a wall round a tile). The
    ground the branches lie in is the colour of the pixels 3-8 px beside
    them (median of a 2 px blur); a pixel is unlike it when some channel
    differs by more than ``k`` robust spreads of the ground and at least
    ``min_diff``. The unlike pixels wider than ``radius`` (an opening with a
    disk), in pieces of at least ``min_area`` of the image that touch the
    image border and hold (almost) no branch pixel, are returned.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example, float in [0, 1] (RGBA is composited over white).
    branches : (H, W) bool array_like
        Branch pixels.
    radius : float, default 12.0
        The regions must be wider than a disk of this radius (pixels).
    k : float, default 4.0
        Spreads (1.4826 x the median absolute deviation) of the ground's colour a pixel must differ by.
    min_diff : float, default 0.12
        Smallest colour difference counted.
    min_area : float, default 0.02
        Smallest region kept, as a fraction of the image.

    Returns
    -------
    (H, W) bool ndarray
        The outside regions.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> img = 0.8 + 0.03 * rng.normal(size=(80, 80, 3)); img[10:70, 10:70] = (0.2, 0.45, 0.1)
    >>> br = np.zeros((80, 80), bool); br[40, 15:65] = True
    >>> bg = unlike_background(img, br, 4.0)
    >>> bool(bg[2, 2]), bool(bg[40, 40])
    (True, False)
    """
    import cv2

    from ..core.image import as_rgb

    rgb = as_rgb(image).astype(np.float32)
    br = np.asarray(branches, bool)
    out = np.zeros(br.shape, bool)
    if not br.any() or rgb.shape[:2] != br.shape:
        return out
    sm = cv2.GaussianBlur(rgb, (0, 0), 2.0)
    b8 = br.astype(np.uint8)
    ring = (cv2.dilate(b8, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (17, 17))) > 0) & \
        ~(cv2.dilate(b8, np.ones((3, 3), np.uint8)) > 0)
    # only ring pixels whose mirror across the nearest branch pixel has their colour: the ground the
    # branches lie *in* (the outermost veins of a leaf have the table on one side)
    _d, (iy, ix) = ndi.distance_transform_edt(~br, return_indices=True)
    ry, rx = np.nonzero(ring)
    my = np.clip(2 * iy[ry, rx] - ry, 0, br.shape[0] - 1)
    mx = np.clip(2 * ix[ry, rx] - rx, 0, br.shape[1] - 1)
    two = (np.abs(sm[my, mx] - sm[ry, rx]).max(-1) <= min_diff) & ~br[my, mx]
    if np.count_nonzero(two) < 20:
        return out
    ring = np.zeros_like(ring)
    ring[ry[two], rx[two]] = True
    ground = np.median(sm[ring], axis=0)
    d = np.abs(sm - ground).max(-1)
    spread = 1.4826 * float(np.median(d[ring]))
    unlike = d > max(k * spread, min_diff)
    r = max(int(round(radius)), 1)
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    unlike = cv2.morphologyEx(unlike.astype(np.uint8), cv2.MORPH_OPEN, disk, borderType=cv2.BORDER_REPLICATE) > 0
    lab, n = ndi.label(unlike)
    if n == 0:
        return out
    sizes = np.bincount(lab.ravel(), minlength=n + 1)
    hits = np.bincount(lab[br], minlength=n + 1)
    touch = np.zeros(n + 1, bool)
    for edge in (lab[0], lab[-1], lab[:, 0], lab[:, -1]):
        touch[edge] = True
    keep = touch & (sizes >= min_area * br.size) & (hits <= 0.01 * sizes)
    keep[0] = False
    return keep[lab]


# split by step: the domain of an example lives in .example_domains (re-exported here)
from .example_domains import _opaque_part, example_domain  # noqa: E402,F401
