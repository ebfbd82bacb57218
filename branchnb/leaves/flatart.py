"""Drawn leaves (flat fill, ink outline and veins): what synthesis does differently on them.

Going beyond the paper, which works on photographs: on clip art the
outline is ink drawn along the blade's boundary, not texture. Carried in
the warped background it came out as a dotted rim with gaps inside the new
blade and a soft halo of fill outside it; the background's own ink veins
stayed beside the donor's (two vein systems), and resampled one-pixel ink
turned grey and blurred. :func:`flat_art` decides from the exemplars'
colour statistics whether they are drawn (an ink rim around most of every
blade, ink much darker than the fill, a fill of few colours) and measures
the outline (width, colour) and the palette; synthesis then removes all ink
from the background, pastes whole ink strokes of the donor's layers, snaps
colours to the palette and draws a new outline along the new blade's
boundary.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..core.image import extend_nearest
from ..core.morphology import _binary_dilation, _binary_erosion, _binary_opening

__all__ = ["FlatArt", "flat_art", "drawn_outline"]

#: Ink: brightest channel below this fraction of the fill's (and below INK_MAX).
INK_RATIO = 0.6
INK_MAX = 0.45
#: Share of the blade's outermost pixels that must be ink (dashed outlines reach 0.7-0.8).
MIN_RIM_INK = 0.6
#: Share of the non-ink blade pixels that must lie within FLAT_TOL of the fill's two main colours
#: (bins of 1/8 per channel) or of a mixture of them with each other or with the ink.
MIN_FLAT = 0.85
FLAT_TOL = 0.05


def _replace_from_blade(img: np.ndarray, blade: np.ndarray, remove: np.ndarray) -> np.ndarray:
    """``img`` with ``remove`` (grown by one pixel: anti-aliased rims) given the nearest other blade colour."""
    gone = _binary_dilation(remove) & blade
    keep = blade & ~gone
    if not gone.any() or not keep.any():
        return img
    out = img.copy()
    out[gone] = extend_nearest(img, keep)[gone]
    return out


@dataclass
class FlatArt:
    """What :func:`flat_art` found on drawn exemplars.

    Parameters
    ----------
    outline_colour : (3,) float32 ndarray
        Median colour of the exemplars' outline ink.
    outline_width : float
        Median outline width (px) over the exemplars.
    ink : list of (H, W) bool ndarray
        Each exemplar's ink pixels (outline and strokes) in its blade.
    outline : list of (H, W) bool ndarray
        Each exemplar's outline ink (the ink within the outline width of its boundary).
    palette : (K, 3) float32 ndarray
        The exemplars' few colours (fill, ink, paper between strokes): the
        mean colour of each bin (1/8 per channel) holding >= 1 % of their
        blade pixels, at most 8.
    hard : bool
        The exemplars are drawn without anti-aliasing (almost every blade
        pixel is a palette colour): new leaves are snapped to the palette.
    rim_ink, flatness : float
        The measures the decision used (smallest over the exemplars).
    """

    outline_colour: np.ndarray
    outline_width: float
    ink: list
    outline: list
    palette: np.ndarray
    hard: bool
    rim_ink: float
    flatness: float

    def clean(self, img: np.ndarray, blade: np.ndarray, remove: np.ndarray) -> np.ndarray:
        """``img`` with ``remove`` (grown by one pixel: anti-aliased rims) given the nearest other blade colour.

        Parameters
        ----------
        img : (H, W, C) float32 ndarray
            An exemplar's image (not modified).
        blade : (H, W) bool ndarray
            Its blade: the colours come from blade pixels outside ``remove``.
        remove : (H, W) bool ndarray
            The pixels to replace (ink).

        Returns
        -------
        (H, W, C) float32 ndarray
        """
        return _replace_from_blade(img, blade, remove)


def drawn_outline(img, blade) -> np.ndarray:
    """The ink outline drawn around one blade (empty when its rim is not mostly ink).

    The same rule as :func:`flat_art` for one exemplar, whatever its fill
    (a gradient-filled clip-art leaf with a dark outline is not flat art):
    ink is darker than ``INK_RATIO`` of the fill's median brightest channel
    and than ``INK_MAX``; when at least ``MIN_RIM_INK`` of the blade's
    outermost pixels are ink, the ink joined to them within 8 px of the
    boundary is the outline. Synthesis takes it out of the background
    (beyond the paper): carried by the shape warp it drew dark curves
    inside new leaves, and bled outwards it filled new blades past the
    background exemplar's own with near-black (a drawn maple with two
    oaks: 11-14 % of two new leaves' blades).

    Parameters
    ----------
    img : (H, W, 3 or 4) float ndarray
        The exemplar's colours in [0, 1] (alpha ignored).
    blade : (H, W) bool ndarray
        Its blade.

    Returns
    -------
    (H, W) bool ndarray

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((40, 40, 3), np.float32); blade = np.zeros((40, 40), bool)
    >>> blade[8:32, 8:32] = True; img[8:32, 8:32] = np.linspace(0.5, 0.9, 24)[None, :, None]
    >>> img[blade & ~np.pad(np.ones((20, 20), bool), 10)] = 0.05  # a 2 px outline
    >>> int(drawn_outline(img, blade).sum())
    176
    """
    rgb = np.asarray(img, np.float32)[..., :3]
    blade = np.asarray(blade, bool)
    out = np.zeros(blade.shape, bool)
    if blade.sum() < 64:
        return out
    v = rgb.max(2)
    ink = blade & (v < INK_RATIO * float(np.median(v[blade]))) & (v < INK_MAX)
    rim = blade & ~_binary_erosion(blade, structure=np.ones((3, 3), bool))
    if float(ink[rim].mean()) < MIN_RIM_INK:
        return out
    return ndi.binary_propagation(ink & rim, mask=ink & (ndi.distance_transform_edt(blade) <= 8))


def _segment_distance(c: np.ndarray, ends) -> np.ndarray:
    """Euclidean distance of colours ``c`` (N, 3) to the nearest of the segments ``ends`` [(a, b), ...]."""
    best = np.full(len(c), np.inf, np.float32)
    for a, b in ends:
        a = np.asarray(a, np.float32)
        d = np.asarray(b, np.float32) - a
        t = np.clip(((c - a) @ d) / max(float(d @ d), 1e-9), 0.0, 1.0)
        best = np.minimum(best, np.sqrt(((c - a - t[:, None] * d) ** 2).sum(1)))
    return best


def flat_art(exemplars, blades) -> FlatArt | None:
    """Decide whether exemplars are drawn (flat fill, ink outline) and measure their outline; None if not.

    Parameters
    ----------
    exemplars : list of (H, W, 3 or 4) float ndarray
        The exemplars' images (colours in [0, 1]; an alpha channel is ignored).
    blades : list of (H, W) bool ndarray
        Their blades (leaf pixels).

    Returns
    -------
    FlatArt or None
        None for photographs (or any exemplar without an ink rim around
        most of its blade, or with a fill of many colours).

    Notes
    -----
    Not in the paper. Measured: drawn procedural families (lobed,
    trilobed, elliptic; 256-512 px; 1-3 px outlines; also reduced 2x,
    anti-aliased) rim ink 0.72-1.0, flatness 1.0; the two sketched maples
    (dashed brush outline) rim ink 0.70-0.75, flatness 1.0; photographed
    maples rim ink 0.06, flatness 0.71; photo-like procedural families
    (green, autumn) rim ink 0.0, flatness 0.34-0.66.
    The width is the ink's share summed over whole-pixel Euclidean depths
    (a 4-connected 2 px outline reads 1.6 px: it is thinner on
    diagonals); new leaves read back within 0.2 px of their exemplars.
    A dashed outline is drawn continuous on new leaves.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((40, 40, 3), np.float32); blade = np.zeros((40, 40), bool)
    >>> blade[8:32, 8:32] = True; img[blade] = (0.4, 0.7, 0.3)
    >>> img[blade & ~np.pad(np.ones((20, 20), bool), 10)] = 0.05  # a 2 px outline
    >>> fa = flat_art([img], [blade])
    >>> fa.outline_width, fa.hard
    (2.0, True)
    >>> flat_art([np.full((40, 40, 3), 0.5, np.float32)], [blade]) is None  # no ink rim
    True
    """
    inks, outlines, widths, cols, rims, flats, px = [], [], [], [], [], [], []
    for img, blade in zip(exemplars, blades):
        rgb = np.asarray(img, np.float32)[..., :3]
        blade = np.asarray(blade, bool)
        if blade.sum() < 64:
            return None
        v = rgb.max(2)
        fill_v = float(np.median(v[blade]))
        ink = blade & (v < INK_RATIO * fill_v) & (v < INK_MAX)
        rim = blade & ~_binary_erosion(blade, structure=np.ones((3, 3), bool))
        rim_ink = float(ink[rim].mean())
        if rim_ink < MIN_RIM_INK:
            return None  # not drawn whatever the others are (a photo: decided on its first exemplar)
        # The width from the ink's share at each (Euclidean) depth, as the
        # outline is drawn (3 x 3 erosions read a 3 px outline as 1.9 px).
        dist = np.floor(ndi.distance_transform_edt(blade) + 0.5).astype(np.int16)  # bins [j - 0.5, j + 0.5)
        base = float(ink[dist > 12].mean()) if (dist > 12).any() else 0.0
        frac = np.array([ink[dist == j].mean() if (dist == j).any() else 0.0 for j in range(1, 13)])
        width = 0.0
        for f in frac:
            if f - base < 0.5 * (frac[0] - base):
                break
            width += float(np.clip((f - base) / max(frac[0] - base, 1e-6), 0, 1))
        width = max(width, 1.0)
        # The ink joined to the rim within one pixel past the width (a
        # donor's outline on a diagonal reached past it and was pasted as
        # a vein along the new leaf's margin).
        outline = ndi.binary_propagation(ink & rim, mask=ink & (dist <= int(np.ceil(width)) + 1))
        rest = blade & ~_binary_dilation(ink) & ~rim
        if rest.sum() < 16:
            return None
        # Flat: the pixels off the ink are the fill's two main colours or
        # mixtures of them with each other or with the ink (anti-aliased
        # strokes: a 2x-reduced drawing read 0.67-0.77 by the two colours alone).
        c = rgb[rest]
        q = np.minimum((c * 8).astype(np.int16), 7)
        code = q[:, 0] * 64 + q[:, 1] * 8 + q[:, 2]
        counts = np.bincount(code, minlength=512)
        modes = [c[code == b].mean(0) for b in np.argsort(counts)[::-1][:2] if counts[b]]
        ink_col = np.median(rgb[ink], 0) if ink.any() else np.zeros(3, np.float32)
        ends = [(m, ink_col) for m in modes] + ([(modes[0], modes[1])] if len(modes) > 1 else [])
        flat = float(np.mean(_segment_distance(c, ends) < FLAT_TOL))
        if flat < MIN_FLAT:
            return None
        inks.append(ink)
        outlines.append(outline)
        widths.append(width)
        cols.append(np.median(rgb[outline], 0) if outline.any() else np.zeros(3))
        rims.append(rim_ink)
        flats.append(flat)
        px.append(rgb[blade])
    allpx = np.concatenate(px)
    q = np.minimum((allpx * 8).astype(np.int16), 7)
    code = q[:, 0] * 64 + q[:, 1] * 8 + q[:, 2]
    counts = np.bincount(code, minlength=512)
    big = [b for b in np.argsort(counts)[::-1][:8] if counts[b] >= 0.01 * len(allpx)]  # at most 8 colours
    palette = np.array([allpx[code == b].mean(0) for b in big], np.float32)
    near = np.min(np.abs(allpx[:, None, :] - palette[None]).max(-1), 1) if len(palette) else np.ones(len(allpx))
    hard = bool(np.mean(near < 0.04) > 0.97)
    return FlatArt(np.median(np.array(cols), 0).astype(np.float32), float(np.median(widths)), inks, outlines,
                   palette, hard, float(min(rims)), float(min(flats)))


#: A drawn line joins a layer's lines when it is this close to the layer's colour, as a share of the distance
#: between the layer's colour and the fill's (0.5: closer to the layer's than to the fill).
LINE_COLOUR = 0.5
#: ... and no wider than this many times the layer's widest lines (plus 2 px).
LINE_WIDTH = 2.0


def _layer_lines(img, blade, mask, ink, outline) -> np.ndarray:
    """The whole drawn lines a layer's induced ``mask`` is part of: same colour and width, joined to it.

    Beyond the paper. On a drawing a vein is one line of one colour; the
    induction can miss stretches of it (a lateral of a drawn leaf lost to
    the registration error), which then stay in the background and show
    beside the donor's pasted veins (two vein systems, issue 22). A pixel
    belongs to the layer's lines when its colour lies within
    ``LINE_COLOUR`` of the layer-fill colour distance from the layer's
    colour (median of the mask's pixels farther from the fill than half
    its pixels; the fill is the blade's median off the mask and the ink),
    where those lines are no wider than ``LINE_WIDTH`` times the layer's
    widest (90th percentile of twice the distance to their edge on their
    skeleton) plus 2 px (a patch of that colour is not a line), and when it
    is joined to the mask through such pixels (gaps of one pixel bridged).
    The outline is never part of it (black veins are the outline's ink).

    Returns the lines (including the mask's own pixels of that colour),
    inside ``blade``; empty when the layer's colour is not set apart from
    the fill (less than 0.08 away).
    """
    from skimage.morphology import disk, skeletonize

    rgb = np.asarray(img, np.float32)[..., :3]
    blade = np.asarray(blade, bool)
    if blade.any():
        # On the blade's box only (a leaf fills a fifth of its canvas).
        ys, xs = np.nonzero(blade)
        box = (slice(max(int(ys.min()) - 2, 0), int(ys.max()) + 3), slice(max(int(xs.min()) - 2, 0), int(xs.max()) + 3))
        if blade[box].size < 0.8 * blade.size:
            out = np.zeros(blade.shape, bool)
            out[box] = _layer_lines(rgb[box], blade[box], np.asarray(mask, bool)[box], np.asarray(ink, bool)[box],
                                    np.asarray(outline, bool)[box])
            return out
    outline = np.asarray(outline, bool)
    # (A vein layer induced partly along the outline must not take the outline's ink for its colour.)
    mask = np.asarray(mask, bool) & blade & ~outline
    out = np.zeros(blade.shape, bool)
    rest = blade & ~_binary_dilation(mask, iterations=2) & ~np.asarray(ink, bool)
    if mask.sum() < 4 or rest.sum() < 16:
        return out
    fill = np.median(rgb[rest], 0)
    d_fill = np.sqrt(((rgb[mask] - fill) ** 2).sum(-1))
    far = d_fill >= np.median(d_fill)
    col = np.median(rgb[mask][far], 0)
    gap = float(np.sqrt(((col - fill) ** 2).sum()))
    if gap < 0.08:
        return out
    cand = blade & ~outline & (np.sqrt(((rgb - col) ** 2).sum(-1)) <= LINE_COLOUR * gap)
    own = cand & mask
    if not own.any():
        return out
    sk = skeletonize(own)
    wmax = float(np.percentile(2.0 * ndi.distance_transform_edt(own)[sk] - 1.0, 90)) if sk.any() else 1.0
    r = int(np.ceil(0.5 * (LINE_WIDTH * max(wmax, 1.0) + 2.0)))
    thick = _binary_opening(cand, structure=disk(r))
    if thick.any():
        cand &= ~_binary_dilation(thick)
    joined = ndi.binary_propagation(own & cand, structure=np.ones((3, 3), bool),
                                    mask=_binary_dilation(cand, structure=np.ones((3, 3), bool)))
    return joined & cand
