"""Engraved maps: a sea drawn as parallel hatching or water lines, told apart by its texture.

Beyond the paper (issue 23). An old-atlas map has no flat region colour:
the paper is the same on land and sea, the sea is drawn as parallel
(straight, wavy or coast-following) lines and the land stippled, lightly
hatched or left plain, with the rivers and the coast as black lines. The
flat-colour rules (:func:`~branchnb.branching.backgrounds.flat_background`)
find no sea there, the ridge filter traces every hatching line as a river
(precision 0.06-0.13 on procedural engraved maps) and the domain was the
whole frame. :func:`hatched_background` finds the sea by its texture: ink
dense enough, in lines of one local orientation (the coherence of the
smoothed structure tensor), over wide pieces touching the frame.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

__all__ = ["erase_hatched_sea", "hatched_background", "without_hatched_sea"]

#: Smallest coherence of the structure tensor (smoothed over the texture window) of a hatched sea; a
#: stippled or plain land has 0.2-0.5, a lightly hatched land 0.6-0.75, parallel sea lines 0.88-1.0.
MIN_COHERENCE = 0.82
#: Smallest share of ink in the texture window (a single river crossing the window is no texture).
MIN_DENSITY = 0.05
#: Smallest sea piece, as a share of the image.
MIN_AREA = 0.03
#: Smallest share of a sea corner cut off at the frame that the (unopened) texture covers; such corners of the
#: procedural engraved maps have 0.36-0.61, pieces of land 0.02-0.05.
MIN_CORNER_TEXTURE = 0.25


def hatched_background(gray, branches=None, *, min_coherence: float = MIN_COHERENCE,
                       min_density: float = MIN_DENSITY) -> np.ndarray:
    """The sea of an engraved map: wide pieces of parallel-line texture touching the frame; (H, W) bool.

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1], dark ink on light paper.
    branches : (H, W) bool array_like, optional
        Pixels of lines found so far; a piece is no sea when it holds most of them.
    min_coherence : float, default :data:`MIN_COHERENCE`
        Smallest orientation coherence of the texture.
    min_density : float, default :data:`MIN_DENSITY`
        Smallest share of ink in the texture window.

    Returns
    -------
    (H, W) bool ndarray
        The hatched sea (empty when the image has none).

    Notes
    -----
    The texture window is a Gaussian of ``max(6, 0.024 * min(H, W))``
    pixels (twice the spacing of the hatching the procedural examples
    draw, 4-12 px); a piece of the texture is kept when a disk of that
    radius fits in it, it touches the frame and covers at least
    :data:`MIN_AREA` of the image and its lines repeat at a regular
    spacing (:func:`_periodic_share`, beyond the paper, branching114:
    parallel texture alone was also a grained soil along pale roots, 11-21 %
    of such an image, wood streaks, 94-96 %, and a cartoon tree's bands
    between outlines, 6 %; all now 0, the engraved maps' seas unchanged),
    then eroded by one more window. The
    image is cut along its long ink lines (over 3 windows: the hatching, the
    coast with the rivers joined to it); the pieces between them that this
    texture covers at least half of are the sea, with the long lines that
    lie along them only (the hatching; the coast has land beside it).
    Beyond that (issue 23, branching108): a piece whose eroded core covers
    under half of it still is sea when the core covers half of its part
    deeper than a window (a narrow wedge of sea); beside such a sea, a corner
    or a closed bay too narrow for the opened texture is sea when the raw
    texture covers :data:`MIN_CORNER_TEXTURE` of it and three or more long
    lines lie beside it, and a pocket smaller than the window when its own
    lines are dense and parallel to the sea's hatching (:func:`_pockets`);
    hatching joined to the coast line (one ink piece with it) is sea pixel
    by pixel where no land lies within 2 px.
    Water lines that follow the coast and fade into plain paper far out
    (the "waterlines" kind) leave that paper out of the sea: not handled.

    Examples
    --------
    >>> g = np.full((200, 200), 0.9); g[::5, :] = 0.1; g[40:160, 40:160] = 0.9   # hatched sea, plain land
    >>> sea = hatched_background(g)
    >>> bool(sea[10, 100]), bool(sea[100, 100])
    (True, False)
    """
    import cv2

    g = np.asarray(gray, np.float32)
    if g.ndim != 2:
        raise ValueError(f"gray must be an (H, W) image, got shape {g.shape}")
    h, w = g.shape
    out = np.zeros((h, w), bool)
    if min(h, w) < 32:
        return out
    paper = float(np.percentile(g, 95))
    dark = float(np.percentile(g, 1))
    if paper - dark < 0.3:
        return out
    ink = (g < 0.5 * (paper + dark)).astype(np.float32)
    s = max(6.0, 0.024 * min(h, w))
    dens = cv2.GaussianBlur(ink, (0, 0), s)
    gx = cv2.Sobel(g, cv2.CV_32F, 1, 0)
    gy = cv2.Sobel(g, cv2.CV_32F, 0, 1)
    jxx = cv2.GaussianBlur(gx * gx, (0, 0), s)
    jyy = cv2.GaussianBlur(gy * gy, (0, 0), s)
    jxy = cv2.GaussianBlur(gx * gy, (0, 0), s)
    coh = np.sqrt((jxx - jyy) ** 2 + 4 * jxy ** 2) / (jxx + jyy + 1e-9)
    tex = (coh >= min_coherence) & (dens >= min_density)
    raw = tex
    r = int(round(s))
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    # (eroded by one more window: where the coast runs along the hatching, the window straddling it reads
    # the coast line as one more hatching line, and the texture reaches a window into the land)
    tex = cv2.erode(cv2.morphologyEx(tex.astype(np.uint8), cv2.MORPH_OPEN, disk, borderType=cv2.BORDER_REPLICATE),
                    disk, borderType=cv2.BORDER_REPLICATE) > 0
    lab, n = ndi.label(tex)
    if n == 0:
        return out
    area = np.bincount(lab.ravel(), minlength=n + 1)
    touch = np.zeros(n + 1, bool)
    for edge in (lab[0], lab[-1], lab[:, 0], lab[:, -1]):
        touch[edge] = True
    keep = touch & (area >= MIN_AREA * h * w)
    if branches is not None:
        br = np.asarray(branches, bool)
        if br.shape == (h, w) and br.any():
            held = np.bincount(lab[br], minlength=n + 1)
            keep &= held < 0.5 * br.sum()
    keep[0] = False
    for c in np.flatnonzero(keep):
        # parallel texture alone is also a grained soil's edges along a few pale roots, a wood's streaks or
        # the bands between a drawing's outlines: hatching is lines at a regular spacing
        keep[c] = _periodic_share(g, lab == c, s) >= MIN_PERIODIC_SHARE
    sea = keep[lab]
    if not sea.any():
        return out
    # the smoothing window straddles the coast (and reads a coast running along the hatching as one more
    # hatching line): the sea is cut along the long ink lines (the hatching, the coast with the rivers
    # joined to it) and each piece between them goes to the sea when the texture covers most of it
    ink_b = ink > 0
    lab_i, n_i = ndi.label(ink_b, structure=np.ones((3, 3), bool))
    if n_i == 0:
        return sea
    sl = ndi.find_objects(lab_i)
    long_ = np.r_[False, [max(q[0].stop - q[0].start, q[1].stop - q[1].start) > 3 * s for q in sl]]
    wall = long_[lab_i]
    lab_f, n_f = ndi.label(~wall)
    size = np.bincount(lab_f.ravel(), minlength=n_f + 1)
    core = np.bincount(lab_f[sea], minlength=n_f + 1)
    # the texture was eroded by two windows from the piece's edge: a narrow sea (a wedge between land reaching
    # the frame and the frame, 12 % of a 512 px map) keeps under half its area as core though no land piece
    # keeps any (0.0 on the procedural maps); so half of the piece's part deeper than a window is asked
    # (the core counted in that deep part only: hatching that runs up to a plain land without a coast line
    # joins the strips between its lines to the land, whose deep part is the land alone)
    deep_px = cv2.erode((~wall).astype(np.uint8), disk, borderType=cv2.BORDER_REPLICATE) > 0
    deep = np.bincount(lab_f[deep_px], minlength=n_f + 1)
    core_deep = np.bincount(lab_f[sea & deep_px], minlength=n_f + 1)
    piece = (core >= 0.5 * size) | ((core_deep >= 0.5 * deep) & (deep > 0) & (core >= 0.2 * size))
    piece[0] = False
    # a corner of the sea cut off by land reaching the frame or a bay closed by the land (2-3 % of the map,
    # too narrow for the texture to survive the opening) is sea as well when the texture covers a good part
    # of it and it lies between several long lines (hatching); a piece of land has the texture under 7 % of it
    # (the window reaching over the coast) and only the coast and its rivers beside it
    raw_share = np.bincount(lab_f[raw], minlength=n_f + 1) / np.maximum(size, 1)
    # (only beside a sea found by its core: without one, textured slivers are a delta's channels)
    maybe = ~piece & (raw_share >= MIN_CORNER_TEXTURE)
    # (with no wide untextured interior: a plain land joined to the strips between hatching that runs up to it
    # without a coast line has 0.3 of the piece deeper than a window and untextured, the corners under 0.04)
    maybe &= deep - np.bincount(lab_f[raw & deep_px], minlength=n_f + 1) < 0.2 * size
    maybe[0] = False
    if piece[1:].any() and maybe.any():
        piece |= maybe & (_lines_beside(lab_f, lab_i * wall) >= 3)
    if piece[1:].any():
        piece |= _pockets(lab_f, ink, gx, gy, piece, size, min_density, MIN_AREA * h * w)
    out = piece[lab_f]
    # a long line is hatching when (nearly) all of it lies along those pieces; the coast has land beside it
    near = ndi.binary_dilation(out, iterations=2)
    size_i = np.bincount(lab_i.ravel(), minlength=n_i + 1)
    along = np.bincount(lab_i[near & ink_b], minlength=n_i + 1)
    land_near = ndi.binary_dilation(~out & ~wall, iterations=2)
    beside_land = np.bincount(lab_i[land_near & ink_b], minlength=n_i + 1)
    hatch = long_ & (along >= 0.9 * size_i) & (beside_land <= 0.1 * size_i)
    hatch[0] = False
    # hatching that touches the coast line is one ink piece with it (1000 px maps: all of it): its pixels
    # with the sea on both sides and no land within reach are hatching all the same
    sea = out | hatch[lab_i] | (wall & near & ~land_near)
    # a textured window that survives the cut only in slivers (rivers running side by side in a crop of a
    # drawn map: 0.6 % of it) is no sea; erasing it cost that crop 4 % of its river recall
    return sea if sea.mean() >= MIN_AREA else np.zeros_like(sea)


#: Smallest share of a texture piece's tiles that repeat at a regular spacing (:func:`_periodic_share`): the
#: engraved maps' sea pieces 0.99-1.0, hatching drawn at a spacing jittered by 20-30 % (std) 0.49-0.92; a
#: grained soil beside pale roots, wood streaks, a cartoon tree's bands between outlines 0.0-0.27 (branching114).
MIN_PERIODIC_SHARE = 0.4
#: Smallest autocorrelation of a hatched tile at its lines' spacing (or twice or three times it): the
#: engraved maps' sea tiles 0.71-1.0 (10th percentile), the grounds above' under 0.63 (90th percentile).
MIN_PERIOD_AC = 0.5
#: Gaussian blur (in texture windows) of the tiles before their autocorrelation: lines drawn by hand at a
#: spacing jittered by 20-30 % (std) keep 0.49-0.92 of their tiles periodic with it (0.36-0.94 without),
#: wood streaks 0.14-0.27 (0.08-0.20); a quarter window blurs the lines away (0.26-0.39).
PERIOD_BLUR = 0.125


def _periodic_share(g, piece, s, *, stats=False):
    """Share of the tiles of ``g`` (``4 s`` wide, half overlapping, three quarters in ``piece``, or half
    when none is) that repeat at a regular spacing: the tile's strongest frequency gives the lines'
    spacing and direction, and its autocorrelation (corrected for the Hann window) at that lag, or twice or
    three times it, reaches :data:`MIN_PERIOD_AC`. Straight parallel lines at one spacing do (about 1.0);
    grain, streaks of random spacing and single edges or bands do not. A piece no tile half fits has
    none (0.0); ``stats=True`` returns ``(share, tiles, scores)``."""
    import cv2

    t = max(16, int(round(4 * s)))
    h, w = g.shape
    ys, xs = np.nonzero(piece)
    y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    grid = [(ty, tx) for ty in range(y0, max(y0, y1 - t) + 1, t // 2)
            for tx in range(x0, max(x0, x1 - t) + 1, t // 2) if ty + t <= h and tx + t <= w]
    cover = np.array([piece[ty:ty + t, tx:tx + t].mean() for ty, tx in grid])
    starts = [q for q, c in zip(grid, cover) if c >= 0.75] or [q for q, c in zip(grid, cover) if c >= 0.5]
    if not starts:
        return (0.0, 0, np.zeros(0)) if stats else 0.0
    n = len(starts)
    gb = cv2.GaussianBlur(np.asarray(g, np.float32), (0, 0), PERIOD_BLUR * s)
    tiles = np.stack([gb[ty:ty + t, tx:tx + t] for ty, tx in starts]).astype(np.float32)
    win = np.hanning(t + 2)[1:-1].astype(np.float32)
    win = np.outer(win, win)
    tiles -= (tiles * win).sum(axis=(1, 2), keepdims=True) / win.sum()
    f_t = np.fft.rfft2(tiles * win, s=(2 * t, 2 * t))
    pw = np.abs(f_t) ** 2
    # the spacing from the strongest frequency (zero-padded: half-bins), the regularity from the
    # autocorrelation (corrected for the window) at that spacing and twice and three times it (the strongest
    # frequency of thin lines may be a harmonic)
    ac = np.fft.irfft2(pw, s=(2 * t, 2 * t))
    wac = np.fft.irfft2(np.abs(np.fft.rfft2(win, s=(2 * t, 2 * t))) ** 2, s=(2 * t, 2 * t))
    ac = ac / np.maximum(wac, 1e-3 * wac[0, 0])
    ac = ac / np.maximum(ac[:, :1, :1], 1e-12)
    flat = pw.reshape(n, -1).copy()
    flat[:, 0] = 0
    ky, kx = np.unravel_index(flat.argmax(1), pw.shape[1:])
    fy = np.where(ky > t, ky - 2 * t, ky) / (2 * t)
    fx = kx / (2 * t)
    f2 = fy ** 2 + fx ** 2
    ly, lx = fy / np.maximum(f2, 1e-12), fx / np.maximum(f2, 1e-12)      # one period, in pixels
    score = np.full(n, -1.0)
    idx = np.arange(n)
    for k in (1, 2, 3):
        ok = (k * np.sqrt(ly ** 2 + lx ** 2) <= t / 2) & (f2 > 0)
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                yy = (np.round(k * ly).astype(int) + dy) % (2 * t)
                xx = (np.round(k * lx).astype(int) + dx) % (2 * t)
                score = np.where(ok, np.maximum(score, ac[idx, yy, xx]), score)
    share = float((score >= MIN_PERIOD_AC).mean())
    return (share, n, score) if stats else share


#: Largest angle (degrees) between a small pocket's own lines and the sea's hatching, and smallest coherence
#: of their orientation (:func:`_pockets`; pockets of the procedural maps 0-8 degrees and 0.25-0.7, their
#: stippled or plain land 14-89 degrees, 0.02-0.37, ink density under a third of the pockets').
POCKET_ANGLE = 10.0
POCKET_COHERENCE = 0.2


def _pockets(lab_f, ink, gx, gy, piece, size, min_density, max_area) -> np.ndarray:
    """Pieces (labels of ``lab_f``) under ``max_area`` pixels that are hatched like the sea: their own ink
    twice ``min_density``, in lines of one orientation within :data:`POCKET_ANGLE` of the sea pieces'
    (``piece``). A pocket of the sea between the coast and the frame, smaller than the texture
    window, has no texture of its own (0.1-0.2 % of a map: its few lines were traced as rivers)."""
    n_f = len(size) - 1
    # its own pixels only: the coast line beside it would swamp its lines' orientation (the gradients of the
    # hatching joined to the coast still fall on the paper strips between them)
    lab_d = lab_f.ravel()
    gxx, gyy, gxy = (gx * gx).ravel(), (gy * gy).ravel(), (gx * gy).ravel()
    jxx = np.bincount(lab_d, gxx, minlength=n_f + 1)
    jyy = np.bincount(lab_d, gyy, minlength=n_f + 1)
    jxy = np.bincount(lab_d, gxy, minlength=n_f + 1)
    coh = np.sqrt((jxx - jyy) ** 2 + 4 * jxy ** 2) / (jxx + jyy + 1e-9)
    theta = 0.5 * np.arctan2(2 * jxy, jxx - jyy)
    sea_theta = 0.5 * np.arctan2(2 * jxy[piece].sum(), (jxx[piece] - jyy[piece]).sum())
    diff = np.abs((theta - sea_theta + np.pi / 2) % np.pi - np.pi / 2)
    dens = np.bincount(lab_d, ink.ravel(), minlength=n_f + 1) / np.maximum(np.bincount(lab_d, minlength=n_f + 1), 1)
    out = ~piece & (size < max_area) & (coh >= POCKET_COHERENCE) & (dens >= 2 * min_density) & \
        (diff <= np.radians(POCKET_ANGLE))
    out[0] = False
    return out


def _lines_beside(pieces: np.ndarray, lines: np.ndarray) -> np.ndarray:
    """How many distinct line labels (``lines`` > 0) touch each label of ``pieces`` (8-neighbours)."""
    h, w = pieces.shape
    pp, pl = np.pad(pieces, 1), np.pad(lines, 1)
    pairs = []
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dy or dx:
                a = pp[1:h + 1, 1:w + 1]
                b = pl[1 + dy:h + 1 + dy, 1 + dx:w + 1 + dx]
                k = (a > 0) & (b > 0)
                pairs.append(np.c_[a[k], b[k]])
    pairs = np.unique(np.vstack(pairs), axis=0)
    return np.bincount(pairs[:, 0], minlength=int(pieces.max()) + 1)


def without_hatched_sea(image, gray):
    """``(image, gray)`` with an engraved map's hatched sea (:func:`hatched_background`) painted in the
    paper's colour, or both as given when there is none: its lines are no rivers to trace.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example.
    gray : (H, W) ndarray
        Its luminance in [0, 1] (``gray_for_extraction``).

    Returns
    -------
    image, gray
        The same objects when no hatched sea is found; float32 copies with the sea erased otherwise.
    """
    image, gray, _sea = erase_hatched_sea(image, gray)
    return image, gray


def erase_hatched_sea(image, gray):
    """:func:`without_hatched_sea` that also returns the sea it erased: ``(image, gray, sea)``.

    The sea is what tells the coast from a river afterwards: on an engraved map
    the land's paper is the sea's, so once the hatching is erased the coast
    has the same paper on both sides and no colour test sees it as an outline
    (:func:`~branchnb.branching.backgrounds.outline_pixels` takes the line
    along this mask's edge out instead).

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example.
    gray : (H, W) ndarray
        Its luminance in [0, 1] (``gray_for_extraction``).

    Returns
    -------
    image, gray, sea
        ``image`` and ``gray`` as given and ``sea`` None when no hatched sea is found; float32 copies with
        the sea erased and the sea's (H, W) bool mask otherwise.
    """
    g = np.asarray(gray, np.float32)
    if g.ndim != 2:
        return image, gray, None
    sea = hatched_background(g)
    if not sea.any():
        return image, gray, None
    paper = g >= float(np.percentile(g[sea], 75))
    g2 = np.where(sea, float(np.median(g[paper & sea])), g).astype(np.float32)
    img = np.asarray(image)
    if img.shape[:2] != g.shape:
        return image, g2, sea
    img = img.astype(np.float32)
    if np.issubdtype(np.asarray(image).dtype, np.integer):
        img = img / float(np.iinfo(np.asarray(image).dtype).max)
    if img.ndim == 2:
        return g2, g2, sea
    colour = np.median(img[paper & sea], axis=0)
    return np.where(sea[..., None], colour, img).astype(np.float32), g2, sea
