"""The object of a picture on a ground: what differs from the colours along its frame.

Beyond the papers, which find the object as what is dark or edged (the importance): on a
sky gradient, a grass strip, a dark ground or a textured one the whole frame passed the
importance threshold, so a lightning bolt took the picture for a photo and drew one
generic bolt down the middle, nothing of the object. A picture's ground is what touches
its frame: the object is what differs in colour from every common colour along the frame,
not what is darker.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage
from scipy.spatial import cKDTree
from skimage.color import rgb2lab

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
    b = max(1, int(round(GROUND_RING * max(h, w))))
    if 2 * b >= min(h, w):
        return None
    lab = rgb2lab(rgb).astype(np.float32)
    ring = np.ones((h, w), bool)
    ring[b:-b, b:-b] = False
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
