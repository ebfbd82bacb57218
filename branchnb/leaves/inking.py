"""Drawn leaves finished (step 6 of :mod:`branchnb.leaves.synthesis`): palette colours, a new outline.

Going beyond the paper, which works on photographs; what is found on the
exemplars (outline width and colour, palette) is
:func:`branchnb.leaves.flatart.flat_art`'s.
"""

from __future__ import annotations

import cv2
import numpy as np


def _ink_outline(rgb: np.ndarray, alpha: np.ndarray, fa):
    """A drawn leaf finished: colours snapped to the exemplars' palette (hard-edged art) and a new outline.

    The outline (the exemplars' median colour and width) runs along the
    new blade's own boundary, anti-aliased by the distance inside; the
    blade's soft fringe (alpha <= 0.5) takes the outline's colour, so no
    fill shows outside it, and the alpha is cut at 0.5 (the exemplars'
    edges show paper right outside their outline; a ring of
    part-transparent ink or fill was a halo: 20-40 % of the 3 px ring
    outside new blades against 0-7 % for the exemplars). Going beyond the paper (see
    :mod:`branchnb.leaves.flatart`). Returns ``(rgb, alpha)``.
    """
    rgb = np.asarray(rgb, np.float32)
    blade = alpha > 0.5
    if not blade.any():
        return rgb, alpha
    if len(fa.palette):
        rgb = rgb.copy()
        rgb[blade] = _to_palette(rgb[blade], fa.palette, fa.hard)
    d_in = cv2.distanceTransform(blade.astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    o = np.clip(fa.outline_width + 1.0 - d_in, 0.0, 1.0).astype(np.float32)  # edt: 1 on the outermost pixels
    if fa.hard:
        o = np.round(o)
    o[(alpha > 0) & ~blade] = 1.0
    alpha = blade.astype(np.float32)
    return rgb * (1 - o[..., None]) + fa.outline_colour[None, None, :] * o[..., None], alpha


def _to_palette(px: np.ndarray, pal: np.ndarray, hard: bool) -> np.ndarray:
    """Colours ``px`` (N, 3) moved onto the drawing's palette.

    Hard-edged art: the nearest palette colour (resampled one-pixel ink
    turned into grey two-pixel lines). Anti-aliased art: a colour off the
    palette (more than 0.04 from every colour) goes to the nearest mixture
    of two palette colours (a point on a segment between them), which keeps
    the anti-aliasing but removes the tints the resampling's overshoot made
    between colours (cyan specks between dark green and paper on the
    sketched maples).
    """
    px = np.asarray(px, np.float32)
    pal = np.asarray(pal, np.float32)
    pn = (pal ** 2).sum(1)
    out = px.copy()
    pairs = np.array([(i, j) for i in range(len(pal)) for j in range(i + 1, len(pal))], int).reshape(-1, 2)
    a = pal[pairs[:, 0]] if len(pairs) else pal[:0]
    d = pal[pairs[:, 1]] - a if len(pairs) else pal[:0]
    dn = np.maximum((d ** 2).sum(1), 1e-9)
    ad = (a * d).sum(1)
    for s0 in range(0, len(px), 65536):
        c = px[s0:s0 + 65536]
        d2 = (c ** 2).sum(1)[:, None] - 2 * c @ pal.T + pn[None]
        near = np.argmin(d2, 1)
        if hard or not len(pairs):
            out[s0:s0 + 65536] = pal[near]
            continue
        off = np.flatnonzero(d2[np.arange(len(c)), near] > 0.04 ** 2)
        if not len(off):
            continue
        co = c[off]
        t = np.clip((co @ d.T - ad[None]) / dn[None], 0.0, 1.0)  # (M, P)
        q = a[None] + t[..., None] * d[None]  # (M, P, 3)
        k = np.argmin(((co[:, None, :] - q) ** 2).sum(-1), 1)
        out[s0 + off] = q[np.arange(len(off)), k]
    return out
