"""The object of a picture on a ground: what differs from the colours along its frame.

Beyond the papers, which find the object as what is dark or edged (the importance): on a
sky gradient, a grass strip, a dark ground or a textured one the whole frame passed the
importance threshold, so a lightning bolt took the picture for a photo and drew one
generic bolt down the middle, nothing of the object. A picture's ground is what touches
its frame: the object is what differs in colour from every common colour along the frame,
not what is darker.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from scipy.spatial import cKDTree
from skimage.color import rgb2lab

from ..core.image import as_gray

__all__: list[str] = []

#: Width of the frame's ring whose colours are the ground, as a share of the long side.
GROUND_RING = 0.03
#: Colour distance (CIE Lab, Delta E 76) from the nearest ground colour that is object.
GROUND_DELTA_E = 18.0
#: Share of the ring a colour must take (within ``GROUND_DELTA_E / 2``) to be ground: an
#: object touching the frame for a short stretch does not make its colours ground.
GROUND_MIN_SHARE = 0.02
#: Object cover of the picture outside which there is no object on a ground (a photo
#: filling the frame, or only specks: on the astronaut photo, whose frame holds most of
#: its colours, a 2 % speck).
OBJECT_COVER = (0.05, 0.8)
#: Largest share of the ring the object may take (more: the frame cuts through a photo).
OBJECT_MAX_RING = 0.35
#: A thin object (a pole, a mast, a flower stem, a letter I) covers less than
#: ``OBJECT_COVER[0]`` and is still the object when it covers at least ``THIN_COVER`` of the
#: picture, spans at least ``THIN_EXTENT`` of the frame's height or width, and the pixels far
#: from the ground's colours outside it (dilated by 1 % of the long side) are at most
#: ``THIN_STRAY`` of its area: the ground explains the rest of the picture. On the astronaut
#: photo the 2 % speck has as many far pixels again around it (1.06), the retina's disc spans
#: 0.16 of the frame; a pole on a gradient has none (0.00) and spans 0.84-0.94.
THIN_COVER = 0.005
THIN_EXTENT = 0.4
THIN_STRAY = 0.1


def _frame_ring(h: int, w: int) -> np.ndarray | None:
    """The frame's ring (``GROUND_RING`` of the long side wide) whose colours are the ground; None
    when the picture is too small to have an inside."""
    b = max(1, int(round(GROUND_RING * max(h, w))))
    if 2 * b >= min(h, w):
        return None
    ring = np.ones((h, w), bool)
    ring[b:-b, b:-b] = False
    return ring


def _ground_palette(lab: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """The ring's common colours: ring pixels with at least ``GROUND_MIN_SHARE`` of the
    ring within half the object's distance (a sky gradient keeps all its shades)."""
    cols = lab[ring]
    if len(cols) > 1500:
        cols = cols[np.linspace(0, len(cols) - 1, 1500).astype(int)]
    counts = cKDTree(cols).query_ball_point(cols, GROUND_DELTA_E / 2, return_length=True)
    return cols[counts >= GROUND_MIN_SHARE * len(cols)]


#: Least share of the picture a hole in the object takes to be kept open by
#: ``_object_mask(keep_holes=True)`` when at most ``HOLE_FAR`` of it is far from the ground's
#: colours (a stick figure's ring head, a letter A's counter); smaller holes, and holes of a
#: textured fill, are filled.
HOLE_MIN = 0.001
HOLE_FAR = 0.5


def _object_mask(image, min_cover: float = OBJECT_COVER[0], *,
                 keep_holes: bool = False) -> np.ndarray | None:
    """Where a picture's object is: its pixels far in colour from every ground colour.

    Parameters
    ----------
    image : (h, w, 3) float ndarray
        RGB in [0, 1].
    min_cover : float
        Least share of the picture the object covers (``OBJECT_COVER[0]`` by default).
    keep_holes : bool
        Keep the holes of the ground's colours open (at least ``HOLE_MIN`` of the picture, at
        most ``HOLE_FAR`` of them far from the ground's colours); False fills every hole.
        The cover tests count the filled silhouette either way.

    Returns
    -------
    (h, w) bool ndarray or None
        The object's filled silhouette (its holes filled, specks under 0.1 % of the
        picture dropped); None when the frame has no common colour, or the object
        covers less than ``min_cover`` or more than ``OBJECT_COVER[1]`` of the picture or more than
        ``OBJECT_MAX_RING`` of the frame (a photo, or nothing on the ground).

    Examples
    --------
    >>> img = np.zeros((60, 60, 3)); img[15:45, 20:40] = (0.9, 0.2, 0.1)
    >>> int(_object_mask(img).sum())  # the 20 x 30 box, its corners rounded
    596
    """
    rgb = np.clip(np.asarray(image, np.float32)[..., :3], 0.0, 1.0)
    h, w = rgb.shape[:2]
    ring = _frame_ring(h, w)
    if ring is None:
        return None
    lab = rgb2lab(rgb).astype(np.float32)
    palette = _ground_palette(lab, ring)
    if len(palette) == 0:
        return None
    dist, _ = cKDTree(palette).query(lab.reshape(-1, 3), distance_upper_bound=GROUND_DELTA_E)
    far = ~np.isfinite(dist.reshape(h, w))
    # a textured ground's odd pixels are specks: opened away before the holes are filled
    r = max(1, int(round(0.004 * max(h, w))))
    disk = np.hypot(*np.mgrid[-r:r + 1, -r:r + 1]) <= r
    m = ndimage.binary_opening(far, disk)
    m = ndimage.binary_closing(np.pad(m, 2 * r), disk, iterations=2)[2 * r:-2 * r, 2 * r:-2 * r]
    unfilled = m
    m = ndimage.binary_fill_holes(m)
    lab_cc, n = ndimage.label(m)
    if n == 0:
        return None
    sizes = np.bincount(lab_cc.ravel())[1:]
    m = np.isin(lab_cc, 1 + np.flatnonzero(sizes >= 0.001 * h * w))
    cover = float(m.mean())
    if cover > OBJECT_COVER[1] or m[ring].mean() > OBJECT_MAX_RING:
        return None
    if cover < min_cover and not _is_thin_object(m, far):
        return None
    if keep_holes:
        holes, k = ndimage.label(m & ~unfilled)
        if k:
            size = np.bincount(holes.ravel(), minlength=k + 1)
            far_n = np.bincount(holes.ravel(), weights=far.ravel(), minlength=k + 1)
            open_ = (size >= HOLE_MIN * h * w) & (far_n <= HOLE_FAR * size)
            open_[0] = False
            m = m & ~open_[holes]
    return m


def _is_thin_object(m: np.ndarray, far: np.ndarray) -> bool:
    """Whether ``m``, covering less than ``OBJECT_COVER[0]``, is a thin object on a ground the
    frame's colours explain (``THIN_COVER``, ``THIN_EXTENT``, ``THIN_STRAY``), not a speck of
    a photo.

    Beyond the paper and the 5 % cover floor: a street lamp's pole or a flower stem 2-4 % of
    the width covers 1.5-4 % of the picture and was taken for a photo's speck.
    """
    h, w = m.shape
    if m.mean() < THIN_COVER:
        return False
    ys, xs = np.nonzero(m)
    if max(np.ptp(ys) / h, np.ptp(xs) / w) < THIN_EXTENT:
        return False
    reach = max(2, int(round(0.01 * max(h, w))))
    near = ndimage.binary_dilation(m, iterations=reach)
    return float((far & ~near).sum()) <= THIN_STRAY * float(m.sum())



#: Largest luminance of a ground the plain metaphor draws on as dark paper (scratchboard).
DARK_GROUND = 0.3
#: Smallest luminance of a ground taken as white paper (the paper's case: left as it is).
WHITE_GROUND = 0.85
#: Least margin by which the object's mean luminance differs from its ground's.
GROUND_LIFT = 0.15
#: Percentile of the ground's luminance (the frame's ring outside the object) taken as the
#: edge of its grain: beyond it (lighter on a dark ground, darker on a light one) is drawing.
GROUND_GRAIN = 95.0


@dataclass(frozen=True)
class PaperGround:
    """A picture's ground taken as the paper of a plain stylization.

    Parameters
    ----------
    dark : bool
        True for a light object on a dark ground (drawn in light ink on it).
    level : float
        The luminance at the edge of the ground's grain (``GROUND_GRAIN``).
    colour : (3,) float32 ndarray
        The ground's median colour.
    """

    dark: bool
    level: float
    colour: np.ndarray


def _paper_ground(image) -> PaperGround | None:
    """The ground of ``image`` when it is the paper of a drawing that is not on white.

    Beyond the paper, whose tone target ``1 - L`` inks what is dark: on a coloured or grainy
    paper (a drawing on pink card, chalk on a blackboard, a neon sign, a white logo on
    black) the ground's own tone and grain drew a dense tangle over the whole ground, and
    on a dark ground the object vanished in it. The ground found along the frame
    (:func:`_object_mask`) is paper: the picture is levelled to it (:func:`_on_paper`), and
    a light object on a dark ground is drawn the way a scratchboard artist would, light
    lines whose density follows the lightness.

    Parameters
    ----------
    image : (h, w, 3) float ndarray
        RGB in [0, 1].

    Returns
    -------
    PaperGround or None
        None when there is no object on a ground (:func:`_object_mask`), when the ground is
        white paper (median luminance at least ``WHITE_GROUND``: the paper's own case), or
        when the object's mean luminance is not ``GROUND_LIFT`` away from the ground's on
        the side of a drawing (darker on a light ground, lighter on a dark one).

    Examples
    --------
    >>> img = np.full((80, 80, 3), 0.05); img[20:60, 30:50] = 0.9
    >>> g = _paper_ground(img); g.dark, round(g.level, 2)
    (True, 0.05)
    >>> _paper_ground(1 - img) is None  # a dark object on white: the paper's case
    True
    """
    rgb = np.clip(np.asarray(image, np.float32)[..., :3], 0.0, 1.0)
    ring = _frame_ring(*rgb.shape[:2])
    if ring is None:
        return None
    lum = as_gray(rgb)
    ground_lum = float(np.median(lum[ring]))
    if ground_lum >= WHITE_GROUND:
        return None
    m = _object_mask(rgb, keep_holes=True)
    if m is None:
        return None
    ground = ring & ~m
    if not ground.any():
        return None
    obj_lum = float(lum[m].mean())
    dark = ground_lum <= DARK_GROUND and obj_lum >= ground_lum + GROUND_LIFT
    if not dark and obj_lum > ground_lum - GROUND_LIFT:
        return None
    level = float(np.percentile(lum[ground], GROUND_GRAIN if dark else 100.0 - GROUND_GRAIN))
    return PaperGround(dark, level, np.median(rgb[ground], axis=0).astype(np.float32))


def _on_paper(image, ground: PaperGround) -> np.ndarray:
    """``image`` as a grey drawing on white paper: its ground and the ground's grain white,
    the drawing's tone relative to the ground (inverted on a dark ground).

    Examples
    --------
    >>> img = np.full((4, 4, 3), 0.1, np.float32); img[1, 1] = 0.7
    >>> [round(float(v), 2) for v in _on_paper(img, PaperGround(True, 0.1, img[0, 0]))[1:3, 1]]
    [0.33, 1.0]
    """
    lum = as_gray(np.clip(np.asarray(image, np.float32)[..., :3], 0.0, 1.0))
    if ground.dark:
        ink = (lum - ground.level) / max(1.0 - ground.level, 1e-6)
    else:
        ink = 1.0 - lum / max(ground.level, 1e-6)
    return (1.0 - np.clip(ink, 0.0, 1.0)).astype(np.float32)
