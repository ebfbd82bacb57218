"""The crown of a pareidolia tree and where its trunk enters it (paper, section 9).

Split from :mod:`branchnb.dendrite.pareidolia`: the crown's outline
(:func:`tree_crown`), the picture's content as a crown (:func:`content_crown`),
the one-sided picture's ramp (:func:`side_ramp`) and the trunk's entry point
(``_fork_point``). Every name stays importable from
:mod:`branchnb.dendrite.pareidolia`.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from ..core.random import as_rng

__all__ = ["content_crown", "side_ramp", "tree_crown"]

def side_ramp(shape, side: str = "left") -> np.ndarray:
    """0 on the image side edge, 1 on the opposite edge, linear in x: an (H, W) array.

    Parameters
    ----------
    shape : (int, int, ...)
        ``(H, W)`` of the ramp.
    side : {"left", "right"}
        The image side, where the ramp is 0.

    Returns
    -------
    (H, W) float64 ndarray
        Values in [0, 1], constant along y.

    Raises
    ------
    ValueError
        If ``side`` is neither "left" nor "right".

    Examples
    --------
    >>> side_ramp((2, 3), "right").tolist()
    [[1.0, 0.5, 0.0], [1.0, 0.5, 0.0]]
    """
    h, w = int(shape[0]), int(shape[1])
    t = np.linspace(0.0, 1.0, w)
    if side == "right":
        t = t[::-1]
    elif side != "left":
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    return np.broadcast_to(t, (h, w)).copy()


def tree_crown(shape, *, lobes: int = 9, roughness: float = 0.1, rng=None) -> np.ndarray:
    """A tree-crown silhouette filling an (H, W) frame: an egg-shaped ellipse with a
    scalloped, lobed outline (cumulus-like clumps of foliage).

    The outline's radius (relative to the inscribed ellipse) is ``1 -
    roughness + roughness * |sin(lobes theta / 2 + phi)|`` plus a slow random
    wobble, and the crown is a little narrower below its widest line than above,
    as a broadleaf crown is.

    Beyond the paper (issue 25): the widest line lies half the frame's width below
    its top, within 0.5-``_DOME`` (0.62) of its height, the outline stays inside the
    frame, and ``theta`` is the share of the ellipse's perimeter in px, so the
    scallops are as long on a wide crown's top as on its sides. The frame's ellipse
    had its top cut flat by the frame and, on a wide frame, a top scallop stretched
    over a third of its width: a rounded rectangle. Share of the crown's width whose
    top lies within 1 % of its height of its top (3 seeds; ``tests/test_dendrite_pareidolia_dome.py``):
    0.21-0.29 -> 0.07-0.10 on 3:2 and 2:1 frames, 0.21-0.30 -> 0.11-0.19 on square and
    3:4 ones; the frame's top row in the crown 18-21 % -> 0 %; the area the same (0.72 ->
    0.71 of the frame).

    Beyond the paper (issue 25): the outline keeps ``_MARGIN`` (4 %) of the frame's
    shorter side from its sides and top, as the paper's trees keep white round their
    crowns; filling the frame, the side scallops touched its left and right edges. The
    crown's area 0.71 -> 0.62-0.66 of the frame (see :mod:`branchnb.dendrite.pareidolia`
    for the drawings' figures).

    Parameters
    ----------
    shape : (int, int)
        ``(H, W)`` of the frame (at least 2 x 2); the crown spans it but for its margin.
    lobes : int
        Number of scallops around the outline; 9.
    roughness : float
        Depth of the scallops as a share of the radius, in [0, 0.5); 0.1.
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed of the lobes' phase and the wobble.

    Returns
    -------
    (H, W) bool ndarray
        True inside the crown.

    Raises
    ------
    ValueError
        If ``shape`` is smaller than 2 x 2 or ``roughness`` out of range.

    Examples
    --------
    >>> c = tree_crown((100, 80), rng=0)
    >>> bool(c[50, 40]), bool(c[0, 0]), bool(c[99, 79]), bool(0.55 < c.mean() < 0.8)
    (True, False, False, True)
    """
    h, w = int(shape[0]), int(shape[1])
    if h < 2 or w < 2:
        raise ValueError(f"shape must be at least 2 x 2, got {shape}")
    if not 0 <= roughness < 0.5:
        raise ValueError(f"roughness must be in [0, 0.5), got {roughness}")
    r = as_rng(rng)
    yy, xx = np.mgrid[0:h, 0:w]
    # the outline keeps a margin from the frame's sides and top (its foot meets the trunk
    # strip): filling the frame, the side scallops and their twigs ran into its edges
    m = _margin(h, w)
    wc, hc = w - 2 * m, h - m
    u = (xx - (w - 1) / 2) / (wc / 2)
    # the widest line sits as far below the top as half the crown's width (a round dome),
    # within half and _DOME of the frame's height; the outline never reaches past the
    # frame's top, so it is not cut into a straight edge there
    above = float(np.clip(0.5 * wc, 0.5 * hc, _DOME * hc)) if _DOME > 0 else 0.5 * hc
    below = hc - above
    v = (yy + 0.5 - m - above) / np.where(yy + 0.5 - m < above, above, below)
    if _DOME <= 0:  # the former egg: fuller above (cut by the frame), narrower below
        v = v * np.where(v < 0, 0.95, 1.0)
    v = v * np.where(v < 0, 1.0, 1.1)  # narrower toward the trunk
    theta = np.arctan2(v, u)
    if _DOME > 0:
        # the scallops are spaced evenly along the outline in px: spaced by angle, a wide
        # crown's top scallop stretched over a third of its width (a flat top again)
        theta = _arc_angle(theta, 0.5 * wc, above, below / 1.1)
    phase = r.uniform(0, 2 * np.pi, 3)
    wobble = 0.35 * np.sin(2 * theta + phase[1]) + 0.25 * np.sin(3 * theta + phase[2])
    edge = 1.0 - roughness + roughness * np.abs(np.sin(lobes * theta / 2 + phase[0])) ** 0.7 \
        + roughness * 0.3 * wobble
    return np.hypot(u, v) <= np.minimum(edge, 1.0)


#: Most share of the frame's height above a crown's widest line (:func:`tree_crown`). A
#: crown filling a wide frame (3:2) was the frame's ellipse, its top cut flat by the frame
#: over 31 % of its width: a rounded rectangle. With its widest line lower, a wide crown
#: is a dome on a flatter base (0: the former egg, centred and cut by the frame).
_DOME = 0.62


#: Margin of a crown's outline from the frame's sides and top, as a share of the frame's
#: shorter side (:func:`tree_crown`, :func:`_crown_around`; 0: the crown touches the sides).
#: Filling the frame, a crown's side scallops touched its left and right edges (ink in 1-16 %
#: of their rows on 10 photos and 4 procedural pictures at 300-1000 px), none now, the ink
#: 2-5 % of the width from them (``python -m branchnb.dendrite._margin_check``).
_MARGIN = 0.04


def _margin(h: int, w: int) -> float:
    """The crown's margin (px) in an ``h x w`` frame: ``_MARGIN`` of its shorter side,
    at most a quarter of it (so a tiny frame keeps a crown)."""
    return float(min(_MARGIN * min(h, w), 0.25 * min(h, w)))


def _arc_angle(theta: np.ndarray, a: float, b_up: float, b_down: float) -> np.ndarray:
    """``theta`` (the angle on the unit circle of an ellipse's frame) as the share of the
    ellipse's perimeter from ``theta = -pi``, times ``2 pi``: semi-axes ``a`` across,
    ``b_up`` above and ``b_down`` below its centre (px)."""
    t = np.linspace(-np.pi, np.pi, 2049)
    b = np.where(t < 0, b_up, b_down)
    speed = np.hypot(a * np.sin(t), b * np.cos(t))
    s = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))])
    return np.interp(theta, t, 2 * np.pi * s / s[-1]) - np.pi


def content_crown(importance, *, blur: float = 10.0, threshold: float = 0.05,
                  outline: np.ndarray | None = None) -> np.ndarray:
    """The crown of a picture: where it has something to draw, filled and smoothed.

    Pixels whose importance reaches ``threshold`` are blurred over ``blur``
    pixels; the crown is where that fraction exceeds 0.25, with holes filled,
    specks (below 2 % of the largest part) dropped. Content that fills the
    frame (covering over a fifth of its border: a portrait, a landscape) is clipped to ``outline`` (a
    tree-crown silhouette of the frame, :func:`tree_crown`, by default) so the
    picture reads as a tree's crown, not as the image's rectangle; an object on
    a blank ground gets a tree crown round it (beyond the paper): ``outline`` (less the
    crown's margin) scaled to 1.3 times the object's bounding box (its height within 0.6-1.5 of
    its width, moved and shrunk into the frame less the crown's margin from its sides)
    joined with the object, so a leaf or a logo
    is held in a tree's crown instead of drawing a leaf- or logo-shaped tree.

    Parameters
    ----------
    importance : (H, W) array_like
        Importance map of the picture (at least 2 x 2).
    blur : float
        Gaussian sigma (px) smoothing the content; 10.
    threshold : float
        Importance from which a pixel counts as content; 0.05.
    outline : (H, W) bool array_like, optional
        Silhouette that frame-filling content is clipped to; :func:`tree_crown`
        of the frame (``rng=0``) by default.

    Returns
    -------
    (H, W) bool ndarray
        The crown; ``outline`` itself when the picture has no content.

    Raises
    ------
    ValueError
        If ``importance`` is not 2-D or ``outline`` has another shape.

    Examples
    --------
    >>> imp = np.zeros((60, 80)); imp[10:50, 30:50] = 1.0
    >>> c = content_crown(imp, blur=3)
    >>> bool(c[30, 40]), bool(c[30, 5]), bool(c[30, 28])
    (True, False, True)
    """
    imp = np.asarray(importance, dtype=np.float64)
    if imp.ndim != 2 or min(imp.shape) < 2:
        raise ValueError(f"importance must be an (H, W) array, got shape {imp.shape}")
    box = tree_crown(imp.shape, rng=0) if outline is None else np.asarray(outline, bool)
    if box.shape != imp.shape:
        raise ValueError(f"outline has shape {box.shape}, expected {imp.shape}")
    mask = _content(imp, blur, threshold)
    h, w = imp.shape
    band = max(1, round(0.02 * min(h, w)))
    frame = np.zeros_like(mask)
    frame[:band], frame[-band:], frame[:, :band], frame[:, -band:] = True, True, True, True
    if (mask & frame).sum() > 0.2 * frame.sum():
        # the content fills the frame (not an object touching it at one spot):
        # cut it to a crown's outline
        mask &= box
    elif mask.any() and _AROUND > 0:
        mask = _crown_around(mask, box)
    if not mask.any():  # nothing to draw: the crown outline itself
        mask = box
    return mask


def _content(imp: np.ndarray, blur: float, threshold: float = 0.05) -> np.ndarray:
    """Where the picture has something to draw: importance from ``threshold`` blurred over
    ``blur`` px above 0.25, holes filled, specks (< 2 % of the largest part) dropped."""
    frac = ndimage.gaussian_filter((np.asarray(imp, np.float64) >= threshold).astype(np.float64), blur)
    mask = ndimage.binary_fill_holes(frac > 0.25)
    lab, n = ndimage.label(mask)
    if n > 1:
        sizes = np.bincount(lab.ravel())[1:]
        mask = np.isin(lab, 1 + np.flatnonzero(sizes >= 0.02 * sizes.max()))
    return mask


#: An object on a blank ground gets a tree crown this much larger than its bounding box
#: (each way, about its centre; 0: the object's own outline, as before).
_AROUND = 1.3
#: ... whose height is at most / at least this many times its width.
_CROWN_ASPECT = (0.6, 1.5)


def _crown_around(mask: np.ndarray, outline: np.ndarray) -> np.ndarray:
    """A tree crown round an object on a blank ground (beyond the paper): ``outline``
    (a crown silhouette of the frame, less its margin) scaled to ``_AROUND`` times the object's
    bounding box, its aspect kept within ``_CROWN_ASPECT``, moved and shrunk into the frame
    less the crown's margin (``_MARGIN``) from its sides, joined with
    the object's own mask (so none of the picture is lost).

    The object's silhouette as the crown drew a maple leaf or a logo as a leaf- or
    letter-shaped tree; a tree crown holding the picture reads as a tree first, and the
    ground round the object gets light twigs (the random endpoints).
    """
    from skimage.transform import resize

    h, w = mask.shape
    ys, xs = np.nonzero(mask)
    cy, cx = 0.5 * (ys.min() + ys.max()), 0.5 * (xs.min() + xs.max())
    bh = _AROUND * (ys.max() - ys.min() + 1)
    bw = _AROUND * (xs.max() - xs.min() + 1)
    bh, bw = max(bh, _CROWN_ASPECT[0] * bw), max(bw, bh / _CROWN_ASPECT[1])
    # inside the frame (moved in, then shrunk): clipped by it, the crown had straight sides
    # ... and its margin from the frame's sides (the top's too cramped a portrait's face:
    # tone r at 4 px blur on a 250-px drawn face 0.849-0.871 -> 0.840-0.855 over 4 seeds)
    m = _margin(h, w)
    bh, bw = min(bh, h), min(bw, w - 2 * m)
    cy = float(np.clip(cy, bh / 2, h - bh / 2))
    cx = float(np.clip(cx, m + bw / 2, w - m - bw / 2))
    y0, y1 = int(round(cy - bh / 2)), int(round(cy + bh / 2))
    x0, x1 = int(round(cx - bw / 2)), int(round(cx + bw / 2))
    if y1 - y0 < 2 or x1 - x0 < 2:
        return mask
    # the frame less the crown's margin (or the outline's own box, if larger) scaled to the
    # crown's box: the same crown round an object as without the margin
    outline = np.asarray(outline)
    oy, ox = np.nonzero(outline)
    if oy.size:
        mi = int(round(m))
        outline = outline[min(oy.min(), mi):, min(ox.min(), mi):max(ox.max() + 1, w - mi)]
    crown = resize(np.asarray(outline, np.float64), (y1 - y0, x1 - x0), order=1) > 0.5
    out = np.zeros_like(mask)
    cy0, cx0 = max(y0, 0), max(x0, 0)
    cy1, cx1 = min(y1, h), min(x1, w)
    out[cy0:cy1, cx0:cx1] = crown[cy0 - y0:cy1 - y0, cx0 - x0:cx1 - x0]
    return out | mask


#: Share of the crown's width, about its middle, where the trunk may enter it.
_FORK_SPAN = 0.3


def _fork_point(crown: np.ndarray, dark: np.ndarray | None = None,
                blur: float = 10.0) -> np.ndarray:
    """Where the trunk enters the crown: a little inside its lower edge, below the
    crown's centre of mass, or (with ``dark``) at the darkest such point (blurred over
    ``blur``) within ``_FORK_SPAN`` of the crown's width about its middle.

    Beyond the paper: the trunk and the limbs' bases are the widest strokes, and
    below the middle of a picture there is often something light (a lit rocket on its
    pad, a white collar), drawn over as a black trunk.
    """
    ys, xs = np.nonzero(crown)
    cx = float(np.clip(np.median(xs), xs.min(), xs.max()))
    cands = [int(round(cx))]
    if dark is not None:
        half = 0.5 * _FORK_SPAN * (xs.max() - xs.min())
        cands = list(range(int(np.ceil(cx - half)), int(np.floor(cx + half)) + 1)) or cands
    pts, score = [], []
    g = ndimage.gaussian_filter(np.asarray(dark, np.float64), blur) if dark is not None else None
    for c in cands:
        rows = np.flatnonzero(crown[:, c])
        if rows.size == 0:
            continue
        bottom, top = rows.max(), rows.min()
        y = bottom - 0.08 * (bottom - top)
        pts.append((float(c), y))
        # the darkness a little above the entry, where the trunk's top and limbs' bases are
        score.append(0.0 if g is None else g[int(round(y - 0.1 * (bottom - top))), c]
                     - 0.05 * abs(c - cx) / max(0.5 * _FORK_SPAN * (xs.max() - xs.min()), 1.0))
    if not pts:  # a concave crown: the nearest crown pixel below the centre
        k = int(np.argmin(np.abs(xs - cx) - 1e-3 * ys))
        return np.array([float(xs[k]), float(ys[k])])
    return np.array(pts[int(np.argmax(score))])
