"""Small examples (long side <= :data:`SMALL_SIDE` px): lines cut by the frame are traced up to it.

Beyond the paper (issue 23): the medial axis of a ridge mask stops about a line width short of the
frame where the line leaves the image (the mask's blunt end), and the ridge filter's response fades
within a few pixels of the border. At 512 px that gap is small against the frame tolerances of
:mod:`.skeleton_tree` (``ENTRY_FRAME``, ``OUTLET_FRAME``, 4 px); on a 128 px map a 4-px river
entering from the bottom edge ended 5 px from it, was rooted in the middle of the canvas and its
synthesis floated there. :func:`_reach_frame` runs such ends on to the frame, straight along their
last few pixels, through the line's own mask. Larger examples are left as they are.

How far short of the frame the axis stops grows with the line's width (a 6-px river's axis on a
160 px map ended 9 px from the frame, past a fixed 8 px reach, and the map was rooted at a spur
beside it): the reach is :data:`REACH` plus :data:`REACH_RADII` x the line's radius at the end,
at most :data:`REACH_SHARE` of the example's short side.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi
from skimage.morphology import thin

#: Examples whose long side is at most this many pixels get their frame ends extended.
SMALL_SIDE = 256
#: How far (pixels) a skeleton end of a thin line may lie from the frame and still be run on to it ...
REACH = 8.0
#: ... plus this many times the line's radius at the end (its mask's distance transform there) ...
REACH_RADII = 2.0
#: ... but never more than this share of the example's short side.
REACH_SHARE = 0.125
#: How many pixels back along the skeleton the end's direction is read.
BACK = 5
#: The frame point an end runs on to lies within this cosine of the end's direction.
MIN_COS = 0.5


def _end_path(skel: np.ndarray, y: int, x: int, n: int) -> list[tuple[int, int]]:
    """The skeleton pixels from the end ``(y, x)`` back along the one-pixel line, up to ``n + 1`` of them."""
    h, w = skel.shape
    prev, cur, path = None, (y, x), [(y, x)]
    for _ in range(n):
        nxt = None
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                q = (cur[0] + dy, cur[1] + dx)
                if (dy or dx) and 0 <= q[0] < h and 0 <= q[1] < w and skel[q] and q != prev and q not in path:
                    nxt = q
                    break
            if nxt is not None:
                break
        if nxt is None:
            break
        prev, cur = cur, nxt
        path.append(cur)
    return path


def _direction(a, b) -> np.ndarray | None:
    d = np.asarray(a, np.float64) - np.asarray(b, np.float64)
    n = float(np.hypot(*d))
    return d / n if n >= 2.0 else None


def _reach_frame(skel: np.ndarray, bw: np.ndarray, reach: float = REACH) -> np.ndarray:
    """``skel`` with its ends near the frame run on to it through ``bw`` (small examples only).

    An end within ``reach + REACH_RADII r`` pixels of the frame (``r`` the line's radius there, the
    whole at most :data:`REACH_SHARE` x the short side) is joined by a straight segment to the nearest
    frame pixel of ``bw`` (dilated by one) that lies ahead of it (within 60 degrees of its last
    :data:`BACK` pixels' direction, at most 1.5 x that reach away) and whose segment lies in that mask:
    the line itself goes on to the frame (a tip that ends inside the image stays). When none does (the
    axis bends into a corner of the cut), the same from :data:`BACK` pixels behind the end. The new
    pixels and their neighbours are thinned again (a rounded segment beside the axis's last pixels
    made three-pixel cycles there, and the frame end was no end point of the skeleton's graph).
    Examples whose long side exceeds :data:`SMALL_SIDE` come back unchanged.

    Parameters
    ----------
    skel : ndarray of bool, shape (H, W)
        One-pixel skeleton.
    bw : ndarray of bool, shape (H, W)
        The line mask the skeleton came from.
    reach : float
        Largest distance (pixels) from the end of a thin line to the frame (see above for thick ones).

    Returns
    -------
    ndarray of bool, shape (H, W)

    Examples
    --------
    >>> sk = np.zeros((64, 64), bool); sk[10:58, 30] = True
    >>> bw = np.zeros((64, 64), bool); bw[8:, 28:33] = True
    >>> int(np.flatnonzero(_reach_frame(sk, bw)[:, 30]).max())
    63
    """
    skel = np.asarray(skel, bool)
    h, w = skel.shape
    if max(h, w) > SMALL_SIDE or not skel.any():
        return skel
    nb = ndi.convolve(skel.astype(np.uint8), np.ones((3, 3), np.uint8), mode="constant") - 1
    ey, ex = np.nonzero(skel & (nb == 1))
    fd = np.minimum(np.minimum(ey, h - 1 - ey), np.minimum(ex, w - 1 - ex))
    bw = np.asarray(bw, bool)
    # the line's radius at the end: the largest distance to its mask's edge within a pixel of it (the
    # end itself sits a radius from the blunt cut, where the distance transform has fallen)
    rad = ndi.maximum_filter(ndi.distance_transform_edt(bw), size=3)[ey, ex]
    ends_reach = np.minimum(reach + REACH_RADII * rad, max(reach, REACH_SHARE * min(h, w)))
    keep = (fd > 0) & (fd <= ends_reach)
    if not keep.any():
        return skel
    inside = ndi.binary_dilation(bw, np.ones((3, 3), bool))
    ring = np.zeros_like(inside)
    ring[0], ring[-1], ring[:, 0], ring[:, -1] = True, True, True, True
    fy, fx = np.nonzero(ring & inside)
    out = skel.copy()
    for y0, x0, reach in zip(ey[keep], ex[keep], ends_reach[keep]):
        path = _end_path(skel, int(y0), int(x0), 2 * BACK)
        # from the end, or (its axis bent into a corner of the cut, a medial axis's Y at a blunt end)
        # from BACK pixels behind it along the stretch before the bend
        for i in (0, BACK):
            if i >= len(path) or (d := _direction(path[i], path[min(i + BACK, len(path) - 1)])) is None:
                break
            y, x = path[i]
            vy, vx = fy - float(y), fx - float(x)
            dist = np.hypot(vy, vx)
            # the frame pixels of the line's mask ahead (within 60 deg of its direction), nearest first
            ok = (dist <= 1.5 * reach) & (vy * d[0] + vx * d[1] >= MIN_COS * dist)
            done = False
            for k in np.flatnonzero(ok)[np.argsort(dist[ok], kind="stable")]:
                n = int(np.ceil(dist[k])) + 1
                t = np.linspace(0.0, 1.0, n + 1)[1:]
                py = np.rint(y + t * vy[k]).astype(int)
                px = np.rint(x + t * vx[k]).astype(int)
                if inside[py, px].all():
                    out[py, px] = True
                    done = True
                    if i and all(nb[q] == 2 for q in path[1:i]):
                        # the bent tip goes: the line now leaves the frame straight
                        qy, qx = np.asarray(path[:i]).T
                        out[qy, qx] = False
                    break
            if done:
                break
    added = out & ~skel
    if added.any():
        near = ndi.binary_dilation(added, np.ones((3, 3), bool), iterations=2)
        out = np.where(near, thin(out), out)
    return out
