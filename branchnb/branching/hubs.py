"""Automatic extraction (beyond the paper): hubs, blobs much wider than the lines that leave them.

A neuron's soma with its dendrites, a coral's or a star's centre with its arms, the crater an impact
leaves with its star of cracks: the lines radiate from a blob of their own colour several times wider
than they are. Skeletonised like a line, the blob became a tangle of spurs (or, under a ridge filter,
which answers only at its rim, a ring), and the tree was rooted at the thickest *end*, a line's tip,
so the learnt model grew from the wrong place. Here such a blob is found as a region
(:func:`find_hubs`), its skeleton replaced by straight spokes from its centre to every line that
leaves it (:func:`hub_skeleton`), and the default root rule (``root="auto"``,
:func:`~branchnb.branching.skeleton_tree.skeleton_to_structure`) roots the piece at the hub's centre:
several hubs in one piece make a forest, split where the shortest paths from the hubs meet.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

#: A hub is at least this many times as wide (its inscribed radius) as the widest line leaving it.
HUB_RATIO = 2.0
#: ... at least this many lines leave it (a thick stretch of one line has two).
HUB_ARMS = 3
#: ... and it is round: its area at most this many times that of its inscribed disc (an ellipse up to
#: 1.6 : 1; radial examples' hubs 1.02-1.51; where lightning strands, a photo's glow or crowded
#: dendrite tips merge 1.74-4.3, a wide channel or a sea strip far more).
HUB_ROUND = 1.6
#: ... and at least this many times the lines' median radius.
HUB_REL = 3.5
#: Smallest hub radius (pixels at the working scale).
HUB_MIN_R = 3.0
#: Largest hub radius as a share of the image's short side (:func:`blob_contrast`).
HUB_MAX = 0.1
#: ... and the contrast of three quarters of its inside (within 0.8 ``R`` of its centre) at least this
#: share of the lines' (:func:`blob_contrast`).
HUB_SOLID = 0.8
#: ... and that (its lower quartile) at least this share of the upper quartile of its middle (within
#: 0.4 ``R``).
HUB_EVEN = 0.75


@dataclass
class Hub:
    """One hub at the working scale (found by :func:`find_hubs`).

    Parameters
    ----------
    centre : (int, int)
        Its centre pixel (y, x): the deepest point of its inscribed disc.
    radius : float
        The inscribed disc's radius (pixels).
    region : (H, W) bool ndarray
        Its pixels.
    arms : list of (int, int)
        The (y, x) skeleton pixel where each line leaving it starts.
    arm_radius : float
        The median radius of those lines (in the blob mask).
    arm_radii : list of float, optional
        Each line's traced radius beside the hub.
    """

    centre: tuple[int, int]
    radius: float
    region: np.ndarray
    arms: list[tuple[int, int]]
    arm_radius: float
    arm_radii: list[float] | None = None


def blob_contrast(gray: np.ndarray, skeleton: np.ndarray, polarity: str) -> np.ndarray:
    """Every pixel's contrast against its local ground as a share of the lines' (1 = as far from the
    ground as the lines' median, 0 = ground): ``>= 0.5`` holds the lines *and* the blobs of their colour
    (the ridge mask has only a blob's rim).

    The ground is a grey opening (a disc of :data:`HUB_MAX` x the short side) of a 4 x smaller copy,
    smoothed: it takes away every line and blob narrower than that disc (an average around them
    counted a large blob's inside as ground). The lines' level is the median on ``skeleton``.

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1] at the working scale.
    skeleton : (H, W) bool array_like
        The traced centre lines.
    polarity : {"bright", "dark"}
        Lines lighter or darker than their ground.

    Returns
    -------
    (H, W) ndarray
        The contrast share of every pixel.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.full((200, 200), 0.2); g[99:102, 5:195] = 0.8; g[88:112, 88:112] = 0.8
    >>> sk = np.zeros(g.shape, bool); sk[100, 5:195] = True        # a line through a blob
    >>> c = blob_contrast(g, sk, "bright")
    >>> round(float(c[100, 100]), 1), round(float(c[20, 20]), 1)
    (1.1, 0.0)
    """
    import cv2

    f = np.asarray(gray, np.float32)
    if polarity == "dark":
        f = 1.0 - f
    sk = np.asarray(skeleton, bool)
    if not sk.any():
        return np.zeros(f.shape)
    h, w = f.shape
    small = cv2.resize(f, (max(w // 4, 1), max(h // 4, 1)), interpolation=cv2.INTER_AREA)
    k = max(int(round(HUB_MAX * min(h, w) / 4.0)), 1)
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * k + 1, 2 * k + 1))
    ground = cv2.morphologyEx(small, cv2.MORPH_OPEN, disk, borderType=cv2.BORDER_REFLECT)
    ground = cv2.resize(ndi.gaussian_filter(ground, 0.5 * k, mode="nearest"), (w, h),
                        interpolation=cv2.INTER_LINEAR)
    con = ndi.gaussian_filter(f, 1.0) - ground
    line = float(np.median(con[sk]))
    return con / max(line, 1e-6)


def find_hubs(blobs: np.ndarray, skeleton: np.ndarray, radius: np.ndarray,
              contrast: np.ndarray | None = None) -> list[Hub]:
    """The hubs of a traced image at the working scale.

    Parameters
    ----------
    blobs : (H, W) bool array_like
        The lines' and blobs' pixels (a binary mask's foreground, or :func:`blob_contrast` ``>= 0.5``).
    skeleton : (H, W) bool array_like
        The traced centre lines.
    radius : (H, W) array_like
        The lines' radius on the skeleton (where ``blobs`` is wider, its inscribed radius counts).
    contrast : (H, W) array_like, optional
        :func:`blob_contrast`: a hub is solid, its median contrast at least :data:`HUB_SOLID` (a glow
        around a light, faint strands crossing are not).

    Returns
    -------
    list of Hub
        Pieces of ``blobs`` whose inscribed radius ``R`` is at least :data:`HUB_MIN_R`,
        :data:`HUB_REL` x the lines' median radius and :data:`HUB_RATIO` x that of every line
        leaving them; from which at least :data:`HUB_ARMS` lines leave (on ``blobs``' medial axis
        and on ``skeleton``: of one piece with the blob, running outward); whose area (the blob
        opened by a disc of ``R / 2``) is at most :data:`HUB_ROUND` x ``pi R^2``; that do not touch
        the frame; and, with ``contrast``, solid and even (:data:`HUB_SOLID`, :data:`HUB_EVEN`).
        Thresholds set on 6 radial kinds x 3 seeds (:mod:`._hub_check`) against 69 other
        procedural examples and the retina, mud, lightning and NOAA samples (no hub found there).

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((100, 100), bool); yy, xx = np.mgrid[:100, :100]
    >>> m |= np.hypot(yy - 50, xx - 50) <= 10                       # a soma ...
    >>> sk = np.zeros_like(m); sk[50, 5:95] = sk[50:95, 50] = True   # ... and three lines
    >>> m |= ndi.binary_dilation(sk)
    >>> [(h.centre, len(h.arms)) for h in find_hubs(m, sk, np.where(sk, 1.0, 0.0))]
    [((50, 50), 3)]
    """
    import cv2
    from skimage.morphology import skeletonize

    fg = np.asarray(blobs, bool)
    sk = np.asarray(skeleton, bool)
    rad = np.asarray(radius, np.float64)
    if not sk.any() or not fg.any():
        return []
    dt = ndi.distance_transform_edt(np.pad(fg, 1))[1:-1, 1:-1]
    if dt.max() < HUB_MIN_R:
        return []
    # the lines' widths read in the mask the hubs are found in, on its own medial axis (the traced
    # skeleton and radius may see the lines thinner or off their middle in it)
    axis = skeletonize(fg)
    line_r = float(np.median(dt[axis]))
    lo = max(HUB_MIN_R, 2.0 * line_r)
    lab, n = ndi.label(dt >= lo)
    H, W = fg.shape
    out: list[Hub] = []
    for k, sl in enumerate(ndi.find_objects(lab), start=1):
        core = lab[sl] == k
        vals = np.where(core, dt[sl], 0.0)
        iy, ix = np.unravel_index(int(np.argmax(vals)), vals.shape)
        R = float(vals[iy, ix])
        cy, cx = sl[0].start + iy, sl[1].start + ix
        # work in a box around the core, wide enough for the arms' first stretch
        pad = int(np.ceil(3 * R)) + 8
        y0, y1 = max(sl[0].start - pad, 0), min(sl[0].stop + pad, H)
        x0, x1 = max(sl[1].start - pad, 0), min(sl[1].stop + pad, W)
        box = fg[y0:y1, x0:x1]
        rr = max(int(round(0.5 * R)), 1)
        disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * rr + 1, 2 * rr + 1))
        opened = cv2.morphologyEx(box.astype(np.uint8), cv2.MORPH_OPEN, disk) > 0
        plab, _ = ndi.label(opened)
        own = plab[cy - y0, cx - x0]
        if own == 0:
            continue
        region = plab == own
        touches = y0 == 0 and region[0].any() or x0 == 0 and region[:, 0].any() or \
            y1 == H and region[-1].any() or x1 == W and region[:, -1].any()
        roundness = region.sum() / (np.pi * R * R)
        solid, even = 1.0, 1.0
        if contrast is not None:
            # inside its rim (where the blur falls off), a hub is as dark/light as its lines all over: a
            # soft spot (a fundus's fovea, a glow) fades from its middle
            yy, xx = np.ogrid[y0 - cy:y1 - cy, x0 - cx:x1 - cx]
            inner = region & (yy * yy + xx * xx <= (0.8 * R) ** 2)
            con = np.asarray(contrast)[y0:y1, x0:x1]
            solid = float(np.percentile(con[inner], 25))
            # ... and even: a soft spot's middle is far darker/lighter than its outer part
            mid = float(np.percentile(con[region & (yy * yy + xx * xx <= (0.4 * R) ** 2)], 75))
            even = solid / max(mid, 1e-6)
        if touches or roundness > HUB_ROUND or solid < HUB_SOLID or even < HUB_EVEN:
            continue
        dreg = ndi.distance_transform_edt(~region)
        a = 2.0 + 0.2 * R
        band = (dreg > a) & (dreg <= a + 2.0 * R)
        c = (cy - y0, cx - x0)
        # lines leaving a hub are of one piece with it (a fundus's vessels stop short of its dark fovea)
        blab, _ = ndi.label(box, np.ones((3, 3), bool))
        joined = ndi.binary_dilation(blab == blab[c], iterations=2)
        widths = [float(np.median(dt[y0:y1, x0:x1][pix])) for pix, _ in
                  _arms(axis[y0:y1, x0:x1] & band & joined, dreg, a, c)]
        traced = _arms(sk[y0:y1, x0:x1] & band & joined, dreg, a, c)
        arms = [st for _, st in traced]
        # each spoke carries its line's radius over the band (at the blob's foot the line flares)
        arm_radii = [float(np.median(rad[y0:y1, x0:x1][pix])) for pix, _ in traced]
        if min(len(widths), len(arms)) < HUB_ARMS or R < HUB_RATIO * (max(widths) + 0.5) or R < HUB_REL * line_r:
            continue
        full = np.zeros(fg.shape, bool)
        full[y0:y1, x0:x1] = region
        out.append(Hub((int(cy), int(cx)), R, full, [(y0 + y, x0 + x) for y, x in arms],
                       float(np.median(widths)), arm_radii))
    return out


def _arms(ring: np.ndarray, dreg: np.ndarray, a: float, centre) -> list[tuple[np.ndarray, tuple[int, int]]]:
    """``(pixels, start)`` of every piece of ``ring`` (skeleton pixels beside a hub) that leaves the
    hub: it reaches within 2 px of the ring's inner edge ``a`` (a line passing by does not) and runs
    outward, its outermost pixel at least half its span farther from the hub's ``centre`` (y, x) than
    its innermost (a vessel curving round a dark spot does not)."""
    lab, n = ndi.label(ring, np.ones((3, 3), bool))
    out = []
    for j in range(1, n + 1):
        pix = lab == j
        d = np.where(pix, dreg, np.inf)
        if d.min() > a + 2.0:
            continue
        i_in = np.unravel_index(int(np.argmin(d)), d.shape)
        i_out = np.unravel_index(int(np.argmax(np.where(pix, dreg, -np.inf))), d.shape)
        r_in = float(np.hypot(i_in[0] - centre[0], i_in[1] - centre[1]))
        r_out = float(np.hypot(i_out[0] - centre[0], i_out[1] - centre[1]))
        span = float(np.hypot(i_out[0] - i_in[0], i_out[1] - i_in[1]))
        if r_out - r_in >= 0.5 * span and span >= 2.0:
            out.append((pix, (int(i_in[0]), int(i_in[1]))))
    return out


def hub_skeleton(skeleton: np.ndarray, radius: np.ndarray, hubs: list[Hub]) -> tuple[np.ndarray, np.ndarray]:
    """``(skeleton, radius)`` with each hub's skeleton (its spurs, the ring a ridge filter leaves)
    replaced by straight spokes from its centre to its arms.

    A spoke carries its arm's radius to the centre: the hub's own width is not put on the tree (drawn
    as the root's radius at its start, the synthesis grew roots starting as long fat smears; a
    synthesized hub would need its own step, not taken here).

    Parameters
    ----------
    skeleton : (H, W) bool array_like
        The traced centre lines.
    radius : (H, W) array_like
        The lines' radius on the skeleton.
    hubs : list of Hub
        From :func:`find_hubs`.

    Returns
    -------
    skeleton, radius : (H, W) ndarrays
        New copies.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((100, 100), bool); yy, xx = np.mgrid[:100, :100]
    >>> m |= np.hypot(yy - 50, xx - 50) <= 10
    >>> sk = np.zeros_like(m); sk[50, 5:95] = sk[50:95, 50] = True
    >>> m |= ndi.binary_dilation(sk); sk[45:56, 45:56] = True           # a tangle in the soma
    >>> hubs = find_hubs(m, sk, np.where(sk, 1.0, 0.0))
    >>> sk2, r2 = hub_skeleton(sk, np.where(sk, 1.0, 0.0), hubs)
    >>> int(sk2[45:56, 45:56].sum()), float(r2[50, 50])                # 121 px of tangle -> three spokes
    (16, 1.0)
    """
    from skimage.draw import line as draw_line

    sk = np.asarray(skeleton, bool).copy()
    rad = np.asarray(radius, np.float64).copy()
    for hub in hubs:
        a = 2.0 + 0.2 * hub.radius
        near = ndi.distance_transform_edt(~hub.region) <= a
        sk &= ~near
    for hub in hubs:
        cy, cx = hub.centre
        top = 0.0
        for i, (ay, ax) in enumerate(hub.arms):
            yy, xx = draw_line(cy, cx, ay, ax)
            r_arm = hub.arm_radii[i] if hub.arm_radii else float(rad[ay, ax])
            rad[yy, xx] = r_arm
            sk[yy, xx] = True
            top = max(top, r_arm)
        rad[cy, cx] = top
    return sk, rad
