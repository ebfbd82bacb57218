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

__all__ = ["hatched_background", "without_hatched_sea"]

#: Smallest coherence of the structure tensor (smoothed over the texture window) of a hatched sea; a
#: stippled or plain land has 0.2-0.5, a lightly hatched land 0.6-0.75, parallel sea lines 0.88-1.0.
MIN_COHERENCE = 0.82
#: Smallest share of ink in the texture window (a single river crossing the window is no texture).
MIN_DENSITY = 0.05
#: Smallest sea piece, as a share of the image.
MIN_AREA = 0.03


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
    :data:`MIN_AREA` of the image, then eroded by one more window. The
    image is cut along its long ink lines (over 3 windows: the hatching, the
    coast with the rivers joined to it); the pieces between them that this
    texture covers at least half of are the sea, with the long lines that
    lie along them only (the hatching; the coast has land beside it).
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
    piece = core >= 0.5 * size
    piece[0] = False
    out = piece[lab_f]
    # a long line is hatching when (nearly) all of it lies along those pieces; the coast has land beside it
    near = ndi.binary_dilation(out, iterations=2)
    size_i = np.bincount(lab_i.ravel(), minlength=n_i + 1)
    along = np.bincount(lab_i[near & ink_b], minlength=n_i + 1)
    beside_land = np.bincount(lab_i[ndi.binary_dilation(~out & ~wall, iterations=2) & ink_b], minlength=n_i + 1)
    hatch = long_ & (along >= 0.9 * size_i) & (beside_land <= 0.1 * size_i)
    hatch[0] = False
    sea = out | hatch[lab_i]
    # a textured window that survives the cut only in slivers (rivers running side by side in a crop of a
    # drawn map: 0.6 % of it) is no sea; erasing it cost that crop 4 % of its river recall
    return sea if sea.mean() >= MIN_AREA else np.zeros_like(sea)


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
    g = np.asarray(gray, np.float32)
    if g.ndim != 2:
        return image, gray
    sea = hatched_background(g)
    if not sea.any():
        return image, gray
    paper = g >= float(np.percentile(g[sea], 75))
    g2 = np.where(sea, float(np.median(g[paper & sea])), g).astype(np.float32)
    img = np.asarray(image)
    if img.shape[:2] != g.shape:
        return image, g2
    img = img.astype(np.float32)
    if np.issubdtype(np.asarray(image).dtype, np.integer):
        img = img / float(np.iinfo(np.asarray(image).dtype).max)
    if img.ndim == 2:
        return g2, g2
    colour = np.median(img[paper & sea], axis=0)
    return np.where(sea[..., None], colour, img).astype(np.float32), g2
