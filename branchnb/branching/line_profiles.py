"""Automatic extraction, beyond the paper: traced ridges that are no lines (photographs).

In a photograph the ridge filter also answers where no branch is: along the
edge of a lit region (a bright cloud layer under a dark one; one side of the
"line" is as bright as the line) and along a row of separate bright dots
(city lights under a storm; the line's brightness falls to the ground
between the dots). :func:`false_ridge_pixels` finds both on the skeleton, by
the profile across each skeleton stretch and the Hessian's shape along it,
so :func:`~branchnb.branching.extraction.extract_structure` drops them.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy import ndimage as ndi

__all__ = ["false_ridge_pixels"]

_NEIGH = np.ones((3, 3), np.int32)


def _skeleton_adjacency(sy: np.ndarray, sx: np.ndarray, shape) -> sp.csr_matrix:
    """(n, n) CSR matrix over the skeleton pixels ``(sy, sx)`` (raster order): 1 where two pixels are
    8-neighbours or the same pixel. Each row's columns are sorted, i.e. in the raster order of the 3 x 3
    neighbourhood, so ``adj @ x`` adds a pixel's values in the order a 3 x 3 convolution of the image
    would (the same sums to the last bit)."""
    h, w = shape
    n = len(sy)
    index = np.full((h + 2, w + 2), -1, np.int64)
    index[sy + 1, sx + 1] = np.arange(n)
    rows, cols = [], []
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            j = index[sy + 1 + dy, sx + 1 + dx]
            ok = j >= 0
            rows.append(np.flatnonzero(ok))
            cols.append(j[ok])
    adj = sp.csr_matrix((np.ones(sum(len(r) for r in rows)), (np.concatenate(rows), np.concatenate(cols))),
                        shape=(n, n))
    adj.sort_indices()
    return adj


def _hessian_across(gray: np.ndarray, sigmas, at: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, ...]:
    """At the pixels ``at = (rows, cols)``, at the scale where the ridge is strongest
    (``sigma^2 |lambda_across|``): the across-line eigenvalue, the along-line eigenvalue and the
    unit normal (nx, ny). The eigen-analysis runs on those pixels only (a skeleton's: about 1 % of a
    photo), the blur and derivatives on the whole image."""
    yy, xx = at
    best = np.full(len(yy), -1.0)
    l_a = np.zeros(len(yy))
    l_b = np.zeros(len(yy))
    nx = np.ones(len(yy))
    ny = np.zeros(len(yy))
    for s in sigmas:
        g = ndi.gaussian_filter(gray, s)
        gy, gx = np.gradient(g)
        hyy, hyx = (d[yy, xx] for d in np.gradient(gy))
        hxx = np.gradient(gx, axis=1)[yy, xx]
        tr = 0.5 * (hxx + hyy)
        disc = np.sqrt(0.25 * (hxx - hyy) ** 2 + hyx ** 2)
        l1, l2 = tr + disc, tr - disc                       # l1 >= l2
        big = np.where(np.abs(l1) >= np.abs(l2), l1, l2)    # across the line: the larger magnitude
        small = np.where(np.abs(l1) >= np.abs(l2), l2, l1)
        # eigenvector of ``big``: (hyx, big - hxx) or (big - hyy, hyx)
        vx = np.where(np.abs(hxx - big) < np.abs(hyy - big), big - hyy, hyx)
        vy = np.where(np.abs(hxx - big) < np.abs(hyy - big), hyx, big - hxx)
        n = np.hypot(vx, vy)
        ok = n > 1e-12
        vx = np.where(ok, vx / np.where(ok, n, 1), 1.0)
        vy = np.where(ok, vy / np.where(ok, n, 1), 0.0)
        st = s * s * np.abs(big)
        upd = st > best
        best = np.where(upd, st, best)
        l_a = np.where(upd, big, l_a)
        l_b = np.where(upd, small, l_b)
        nx = np.where(upd, vx, nx)
        ny = np.where(upd, vy, ny)
    return l_a, l_b, nx, ny


def false_ridge_pixels(gray, skeleton, polarity: str, *, sigma_min: float = 1.0, sigma_max: float = 4.0,
                       two_sided: float = 0.3, dotted: float = 0.3, beads: float = 0.3,
                       min_run: int = 10, local: float = 0.0, dot_reach: float = 0.0) -> np.ndarray:
    """Skeleton pixels on stretches that are an edge or a row of dots, not a line.

    The skeleton is cut at its junctions into stretches; a stretch of at least ``min_run`` pixels
    is dropped when, in the median over its pixels,

    * *one-sided*: the line stands out from both sides by less than ``two_sided`` x what it
      stands out from the darker side (bright polarity), at every pair of neighbouring
      distances across (2, 3, 4.5, 6, 8, 12 px up to 3 ``sigma_max``; a line of any width is
      two-sided just beyond its edges): an edge of a lit region, not a line;
    * *dotted*: its contrast over the darker side (``2 sigma_max`` across) falls below half
      its 90th percentile on at least a ``dotted`` share of the stretch, and varies along it
      by a coefficient of variation of at least ``dotted``, bright in three or more separate
      pieces: a row of separate dots whose brightness drops to the ground between them, not
      a continuous line (nor one fading towards its tip). The contrast is read at the brightest
      point within ``dot_reach`` px across the stretch: at 128 px the skeleton of a jagged
      bolt's merged ridge mask cuts across its zigzags, and read at the pixel itself the bolt was
      dotted (beyond the paper, issue 23; a row of dots is dark between them along the stretch);
    * *beaded* (beyond the paper): dots so close that their glows merge into one ridge, whose
      contrast never falls to half: along the stretch its brightness peaks (the brightest skeleton
      pixel within 3 px) at least 8 times, once every 8 px or closer, each peak rising by at least
      ``beads`` x the stretch's 90th-percentile contrast over the darkest skeleton pixel within
      4 px. A jagged bolt peaks at a few of its bends only, a line's noise by far less.

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1] at the skeleton's scale.
    skeleton : (H, W) bool array_like
        One-pixel-wide ridge skeleton.
    polarity : {"bright", "dark"}
        Lines brighter or darker than their ground.
    sigma_min, sigma_max : float
        Scales of the ridge filter (pixels).
    two_sided, dotted, beads : float
        Thresholds of the three tests above; ``0`` / ``inf`` switch ``two_sided`` / ``dotted`` off,
        ``beads=0`` switches the beaded test off.
    min_run : int
        Shorter stretches (at junctions, at bends) are always kept; the one-sided test
        needs at least ``5 sigma_max`` pixels (short links in the glow between two bright
        lines stand out from one side only).
    local : float, default 0.0
        If > 0, the one-sided test also runs on every skeleton pixel with the medians taken
        over the skeleton pixels within ``local`` pixels instead of over its stretch: the
        skeleton of an edge between two noisy fields has a spur every few pixels, so its
        stretches are all shorter than ``min_run`` (beyond the paper; meant for dark lines,
        which have no glow). There a pixel is one-sided when its ratio is low at *every*
        distance (a step's darker side is as dark as the line all the way across; a line in a
        dense network sees ground on both sides at some distance), and only runs of at least
        ``2 local`` such pixels are dropped (a shorter one is where lines meet).
    dot_reach : float, default 0.0
        Reach (px, across the stretch) of the brightness the dotted test reads at a skeleton
        pixel; 0 = the pixel itself. :func:`~branchnb.branching.extraction.extract_structure`
        uses 1 px on examples of at most ``SMALL_SIDE`` px whose traced lines are bright on a
        dark ground (their ridge masks merge a bolt's zigzags; on larger ones it kept an extra
        storm twig, on a 128 px fundus photo it moved the traced vessels).

    Returns
    -------
    (H, W) bool ndarray
        The skeleton pixels to drop.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((40, 60), 0.1); img[20, 5:55] = 1.0      # a line
    >>> img[30:, :] = 0.8                                        # the edge of a bright region
    >>> sk = np.zeros(img.shape, bool); sk[20, 5:55] = True; sk[29, 5:55] = True
    >>> bad = false_ridge_pixels(img, sk, "bright")
    >>> int(bad[20].sum()), int(bad[29].sum()) > 40
    (0, True)
    """
    g = np.asarray(gray, np.float64)
    sk = np.asarray(skeleton, bool)
    if g.ndim != 2 or sk.shape != g.shape:
        raise ValueError(f"gray and skeleton must be 2-D of one shape, got {g.shape} and {sk.shape}")
    if polarity not in ("bright", "dark"):
        raise ValueError(f"polarity must be 'bright' or 'dark', got {polarity!r}")
    out = np.zeros(sk.shape, bool)
    if not sk.any():
        return out
    sign = 1.0 if polarity == "bright" else -1.0
    n_s = max(2, int(np.ceil(sigma_max - sigma_min)) + 1)
    # stretches between junctions
    nb = ndi.convolve(sk.astype(np.int32), _NEIGH, mode="constant") - 1
    runs = sk & (nb <= 2)
    lab, n = ndi.label(runs, structure=np.ones((3, 3)))
    if n == 0:
        return out
    yy, xx = np.nonzero(runs)
    ll = lab[yy, xx]
    sk_y, sk_x = np.nonzero(sk)
    nx, ny = np.ones(sk.shape), np.zeros(sk.shape)
    _l_a, _l_b, nx[sk_y, sk_x], ny[sk_y, sk_x] = _hessian_across(g, np.linspace(sigma_min, sigma_max, n_s),
                                                                 (sk_y, sk_x))
    ux, uy = nx[yy, xx], ny[yy, xx]
    gs = ndi.gaussian_filter(g, 0.7)
    c = gs[yy, xx] * sign
    idx = np.arange(1, n + 1)
    meds = []
    ratio_d = [d for d in (2.0, 3.0, 4.5, 6.0, 8.0, 12.0) if d <= max(3.0, 3.0 * sigma_max) + 1e-9]
    for d in ratio_d:
        a = ndi.map_coordinates(gs, [yy + d * uy, xx + d * ux], order=1, mode="nearest") * sign
        b = ndi.map_coordinates(gs, [yy - d * uy, xx - d * ux], order=1, mode="nearest") * sign
        t = c - np.maximum(a, b)
        o = c - np.minimum(a, b)
        meds.append(np.asarray(ndi.median(np.where(o > 1e-3, t / np.maximum(o, 1e-3), -1.0), ll, idx)))
    meds = np.array(meds)
    if local > 0:
        # each pixel's ratio averaged with its neighbours *along the skeleton* (a diffusion on its
        # pixels, about ``local`` px each way): a window would mix in the parallel lines nearby
        sy, sx = np.nonzero(sk)
        nxs, nys = nx[sy, sx], ny[sy, sx]
        adj = _skeleton_adjacency(sy, sx, sk.shape)
        den = np.diff(adj.indptr).astype(np.float64)[:, None]
        dd = np.asarray(ratio_d)[:, None]
        a = ndi.map_coordinates(gs, [(sy + dd * nys).ravel(), (sx + dd * nxs).ravel()], order=1,
                                mode="nearest").reshape(len(ratio_d), -1) * sign
        b = ndi.map_coordinates(gs, [(sy - dd * nys).ravel(), (sx - dd * nxs).ravel()], order=1,
                                mode="nearest").reshape(len(ratio_d), -1) * sign
        cc = gs[sy, sx] * sign
        t = cc - np.maximum(a, b)
        o = cc - np.minimum(a, b)
        rat = np.ascontiguousarray(np.clip(np.where(o > 1e-3, t / np.maximum(o, 1e-3), -1.0), -1.0, 1.0).T)
        for _ in range(int(np.ceil(local))):
            rat = (adj @ rat) / den
        loc = rat.T
        # one-sided at *every* distance: the darker side of a step is as dark as the line all the way across,
        # a line among others (a dense network) sees ground on both sides at some distance
        loc_score = np.max(np.array(loc), axis=0)
        low = np.zeros(sk.shape, bool)
        low[sy[loc_score < two_sided], sx[loc_score < two_sided]] = True
        # a short low run is where a line meets or crosses another (its ratio sees the other line):
        # dropped, it would cut the line into pieces too short to keep
        lab_low, n_low = ndi.label(low, structure=np.ones((3, 3)))
        long_run = np.bincount(lab_low.ravel(), minlength=n_low + 1) >= 2.0 * local
        long_run[0] = False
        out |= long_run[lab_low]
    # two-sided at two neighbouring distances (just beyond the line's own width, whatever it is)
    med_score = np.zeros(n + 1)
    med_score[1:] = np.max(np.minimum(meds[:-1], meds[1:]), axis=0)
    # along the stretch: its contrast over the darker side, far across (beyond a line's glow)
    d = max(3.0, 2.0 * sigma_max)
    a = ndi.map_coordinates(gs, [yy + d * uy, xx + d * ux], order=1, mode="nearest") * sign
    b = ndi.map_coordinates(gs, [yy - d * uy, xx - d * ux], order=1, mode="nearest") * sign
    # (the brightest point within dot_reach px *across* the stretch: the skeleton of a small jagged bolt's
    # merged mask cuts across its zigzags and read it dotted; a row of dots stays dark between its dots,
    # whose gaps lie along the stretch -- a 3 x 3 max bridged a city-lights row of 5-9 px spacing)
    cm = c
    for t in (-dot_reach, dot_reach) if dot_reach > 0 else ():
        cm = np.maximum(cm, ndi.map_coordinates(gs, [yy + t * uy, xx + t * ux], order=1, mode="nearest") * sign)
    con = cm - np.minimum(a, b)
    size = np.bincount(ll, minlength=n + 1)
    p90 = np.zeros(n + 1)
    p90[1:] = ndi.labeled_comprehension(con, ll, idx, lambda v: np.percentile(v, 90), float, 0.0)
    dip = np.bincount(ll, weights=con < 0.5 * p90[ll], minlength=n + 1) / np.maximum(size, 1)
    mean = np.bincount(ll, weights=con, minlength=n + 1) / np.maximum(size, 1)
    sq = np.bincount(ll, weights=con * con, minlength=n + 1) / np.maximum(size, 1)
    cv = np.sqrt(np.maximum(sq - mean ** 2, 0.0)) / np.maximum(mean, 1e-3)
    # a row of dots is bright in several separate pieces; a line fading towards its tip in one
    high = np.zeros(sk.shape, bool)
    high[yy, xx] = con >= 0.5 * p90[ll]
    hl, _ = ndi.label(high, structure=np.ones((3, 3)))
    pairs = np.unique(np.stack([ll, hl[yy, xx]], 1)[hl[yy, xx] > 0], axis=0)
    pieces = np.bincount(pairs[:, 0], minlength=n + 1)
    dots = (dip >= dotted) & (cv >= dotted) & (pieces >= 3)
    if beads > 0:
        # dots close enough to merge into one ridge: the brightness along the stretch still rises and
        # falls at every dot, by much more than a line's noise; count its peaks (beyond the paper)
        vals = np.full(sk.shape, -np.inf)
        vals[yy, xx] = c
        lo = np.full(sk.shape, np.inf)
        lo[yy, xx] = c
        peak = (c >= ndi.maximum_filter(vals, 7)[yy, xx] - 1e-9)
        prom = c - ndi.minimum_filter(lo, 9)[yy, xx]
        peak &= prom >= beads * np.maximum(p90[ll], 1e-3)
        n_peaks = np.bincount(ll, weights=peak, minlength=n + 1)
        # at least 8 dots, one every 8 px or closer; a jagged bolt peaks at a few of its bends only
        dots |= (n_peaks >= 8) & (n_peaks * 8.0 >= size)
    # short stretches in a glow between two bright lines are one-sided too: only long edges count
    drop = ((size >= max(min_run, 5.0 * sigma_max)) & (med_score < two_sided)) | ((size >= min_run) & dots)
    drop[0] = False
    out[yy, xx] |= drop[ll]
    return out
