"""Corner-keeping smoothing of traced pixel paths (issue 23: jagged bolts stay jagged).

A skeleton path runs on pixel centres: its staircase (at most about half a pixel off the true centre
line) would dominate the turning angles, so :func:`~.skeleton_tree.skeleton_to_structure` smooths each
path with a Gaussian along its arc. One Gaussian wide enough to flatten the staircase of a shallow
diagonal (4 px, the paper-era default) also rounds every real corner: a procedural bolt turning 22 deg
per 5 px came out at 9 deg, a 256 px zig-zag at 15 deg of its 33. :func:`keep_corners_smooth` smooths at
that width wherever the path stays within the pixel noise of the smoothed curve and falls back to a
narrow Gaussian where it does not (a corner, a kink, a jag), blending the two along the arc.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

#: Distance (pixels at the skeleton's scale) a pixel path may lie off its wide-smoothed curve and still
#: count as staircase: pixel centres lie within half a pixel of a digital straight line, the skeleton of a
#: line of varying width wobbles a little more.
NOISE_PX = 0.6
#: Whether :func:`~.skeleton_tree.skeleton_to_structure` smooths with :func:`keep_corners_smooth` (True)
#: or with the one wide Gaussian of the paper-era extraction (False, the default for now). Mended for it
#: (branching107; the first two switches belong on with it: LEAVE_FRAME 0, STILLBORN_EVERYWHERE True):
#: children no longer draw a head the frame would cut (``branch_starts.LEAVE_FRAME``;
#: tests/test_branching_unborn.py's crack grew frame stubs, seeds 0-2 [1, 0, 3] -> 0), junction disks stay
#: smoothed wide (``calm``: a delta's trunk copied a junction kink and every channel left on one side,
#: tests/test_branching_delta_tail.py's fan0, side share seeds 0-5 down to 0.0 -> seeds 0-3 0.24-0.50), heads whose
#: first Markov step the density refused are dropped in every tree (``filling.STILLBORN_EVERYWHERE``).
#: test_branching_frame_bolt_bearing's 256 px bolt then runs at 67-68 deg, the bearing of the example's own
#: traced roots (67.0 / 71.2) but 17.8-19 deg off the drawn roots' mean (bound 15; rounded, seeds 0-9 reach
#: 24.8 as well). Still failing with all three on (branching112, attributed by switching each alone):
#: KEEP_CORNERS alone: delta_axis fan55 (seed 1: a channel runs sideways to the frame, fan 0; rounded it
#: does too, 2 of 3 reach the sea), delta_balance's binary delta (smaller side 0.17 in seed 2), radius_fidelity's
#: thick trunks (comb 300, rngs 0-4 thick share 0.17/0.09/0.11/0.11/0.16 of the example's 0.22, rounded
#: 0.10-0.14; hd better 0.12-0.27 against 0.23-0.33; children fewer and longer: nb 0.46-1.0), line_art's
#: 128 px trunk colour, band_strands' core, frame_bolt_bearing (above); LEAVE_FRAME 0 alone: image_style's
#: mud160 pieces (also with corners + STILLBORN_EVERYWHERE) and thick trunks' hd 0.354 > 0.35; corners +
#: LEAVE_FRAME: image_style's 96 px coast. Gone: delta_forks (branching110), style, thin_children,
#: structure's regrown roots and child_start_kernels (their guards counted seeds, branching112). With it on,
#: a 256 px zig-zag keeps 31-33 deg of its 33-34 deg turn per 5 px (15-17 off), see the module notes.
KEEP_CORNERS = False
#: Width of the narrow Gaussian used at corners, as a share of the wide one (4 px -> 1.5 px: still removes
#: the one-pixel steps of a diagonal; a bolt's corner keeps its turn).
NARROW_SHARE = 0.375


def keep_corners_smooth(pts: np.ndarray, sigma: float, *, noise: float = NOISE_PX,
                        narrow_share: float = NARROW_SHARE, calm: np.ndarray | None = None) -> np.ndarray:
    """Smooth a pixel path with a Gaussian of ``sigma`` samples, narrower where it has real corners.

    Parameters
    ----------
    pts : (N, 2) ndarray
        Pixel path (x, y), N >= 3, neighbouring samples about one pixel apart.
    sigma : float
        Wide Gaussian (samples); the staircase of straight and gently curved stretches is smoothed at it.
    noise : float, default NOISE_PX
        Pixels the path may lie off its wide-smoothed curve (within ``sigma`` along it) as pixel noise.
    narrow_share : float, default NARROW_SHARE
        The narrow Gaussian used where the path leaves that band, as a share of ``sigma``.
    calm : (N,) bool ndarray, optional
        Samples that are no corner whatever their offset (within a junction's disk, see Notes); the wide
        Gaussian is kept there and ``sigma`` samples around.

    Returns
    -------
    (N, 2) float ndarray
        The smoothed path; its two end points are the input's.

    Notes
    -----
    Beyond the paper (which smooths every path alike). Per sample, the largest distance of the path
    from its wide-smoothed curve within ``sigma`` samples is compared with ``noise``: up to ``noise``
    the wide curve is kept, from ``2 noise`` the narrow one, in between a blend; the blend weight is
    itself smoothed at the narrow width so that no kink appears where the two meet. A corner of turn
    ``t`` (radians) lies about ``0.4 sigma t`` pixels off the wide curve: with ``sigma`` 4 px a 20 deg
    jag (0.56 px) is partly kept, a 30 deg one (0.84 px) mostly, a 45 deg one wholly. Smooth
    lines (rivers, vessels) stay within the band except in bends tighter than about ``sigma**2 /
    (2 noise)`` px of radius (13 px for 4 px), which the narrow Gaussian follows better anyway.

    A child's skeleton path starts at the junction's centre and bends from its parent's centre line to
    its own within about the parent's radius: a bend of the skeleton at the junction, not of the line
    (the Y of a 300 px delta's trunk and channels: 28 and 32 deg kinks on the channels' second samples,
    15 deg with the one wide Gaussian). Kept, synthesis copied them into new branches' heads (a delta's
    trunk started with a kink and leaned 17 deg to one side, all its channels on the other): ``calm``
    leaves those samples to the wide Gaussian.
    """
    p = np.asarray(pts, np.float64)
    wide = ndi.gaussian_filter1d(p, sigma, axis=0, mode="nearest")
    narrow_sigma = sigma * narrow_share
    if len(p) < 3 or narrow_sigma < 1e-3:
        out = wide
    else:
        off = np.hypot(*(p - wide).T)
        # the end samples of a path are pinned below: their offset is the 'nearest' padding's, not a corner
        reach = max(1, int(round(sigma)))
        off_near = ndi.maximum_filter1d(off, 2 * reach + 1, mode="nearest")
        w = np.clip((off_near - noise) / noise, 0.0, 1.0)
        if calm is not None and np.any(calm):
            w[ndi.maximum_filter1d(np.asarray(calm, bool).astype(np.uint8), 2 * reach + 1) > 0] = 0.0
        if not w.any():
            out = wide
        else:
            w = ndi.gaussian_filter1d(w, narrow_sigma, mode="nearest")
            narrow = ndi.gaussian_filter1d(p, narrow_sigma, axis=0, mode="nearest")
            out = (1.0 - w)[:, None] * wide + w[:, None] * narrow
    out = np.array(out, np.float64)
    out[0], out[-1] = p[0], p[-1]
    return out
