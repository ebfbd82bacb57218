"""Crown/trunk segmentation, steps 1-2: the cues of every pixel and the confident seeds.

Split out of :mod:`branchnb.trees.segmentation` (which re-exports every name):
:func:`tree_features` (CIELAB colour and silhouette geometry per opaque pixel)
and :func:`automatic_seeds` (the stem's and the foliage's confident pixels).

Examples
--------
>>> from branchnb import data
>>> cues = tree_features(data.load("tree_rpg_01"))
>>> int(automatic_seeds(cues).max()) <= TRUNK
True
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage as ndi
from skimage.color import rgb2hsv, rgb2lab

from .exemplar import tree_rgba

__all__ = ["tree_features", "automatic_seeds", "BACKGROUND", "CROWN", "TRUNK", "IGNORE"]

BACKGROUND, CROWN, TRUNK, IGNORE = 0, 1, 2, 255
LABEL_NAMES = {"crown": CROWN, "trunk": TRUNK}


FEATURE_NAMES = (
    "L", "a", "b",                     # CIELAB colour / 100
    "L_near", "a_near", "b_near",      # masked Gaussian means, sigma = 0.03 D
    "green_near", "green_far",         # foliage-colour fraction, sigma = 0.03 D / 0.1 D
    "height",                          # 0 at the top of the tree, 1 at its bottom
    "axis_dist",                       # |x - stem axis| / half the tree width
    "run_width",                       # horizontal run length / tree width
    "run_height",                      # vertical run length / tree height
    "dt",                              # distance to background / its max
    "thickness",                       # local thickness (dilated distance) / max
    "d_green",                         # distance to foliage colour / D
    "d_green_bg",                      # (d_green + d_background) / D: outline bands
    "stem_colour",                     # CIELAB distance to the stem colour / 100
    "opaque_near",                     # opaque fraction, sigma = 0.05 D
)




# ---------------------------------------------------------------------------
# Cues
# ---------------------------------------------------------------------------


def _foliage_colour(rgb: np.ndarray) -> np.ndarray:
    """Green-ish pixels: hue 65..190 degrees, saturated and not black."""
    hsv = rgb2hsv(rgb)
    hue = hsv[..., 0] * 360.0
    return (hue >= 65) & (hue <= 190) & (hsv[..., 1] >= 0.2) & (hsv[..., 2] >= 0.12)


def _woody_colour(rgb: np.ndarray) -> np.ndarray:
    """Brown pixels: hue 0..50 degrees (or > 330), saturated, not bright."""
    hsv = rgb2hsv(rgb)
    hue = hsv[..., 0] * 360.0
    return ((hue <= 50) | (hue >= 330)) & (hsv[..., 1] >= 0.25) & (hsv[..., 2] <= 0.75)


def _masked_blur(values: np.ndarray, mask: np.ndarray, sigma: float) -> np.ndarray:
    m = mask.astype(np.float32)
    k = max(3, int(6 * sigma) | 1)
    num = cv2.GaussianBlur(values.astype(np.float32) * (m if values.ndim == 2 else m[..., None]),
                           (k, k), sigma)
    den = cv2.GaussianBlur(m, (k, k), sigma)
    den = np.maximum(den, 1e-6)
    return num / (den if values.ndim == 2 else den[..., None])


def _run_lengths(mask: np.ndarray, axis: int) -> np.ndarray:
    """Length of the run of True pixels along ``axis`` containing each pixel."""
    structure = np.zeros((3, 3), bool)
    if axis == 1:
        structure[1, :] = True
    else:
        structure[:, 1] = True
    lab, n = ndi.label(mask, structure=structure)
    sizes = np.bincount(lab.ravel(), minlength=n + 1)
    sizes[0] = 0
    return sizes[lab]


@dataclass
class _Stem:
    rows: tuple[int, int] | None      # (top, bottom) rows of the stem band (inclusive)
    axis: float                       # x of the stem axis
    colour: np.ndarray                # mean CIELAB colour of the stem
    region: np.ndarray | None = None  # stem pixels: the band's component at the bottom


def _stem_piece(mask: np.ndarray, top: int, bot: int) -> np.ndarray:
    """The piece of the rows ``top..bot`` of ``mask`` standing on row ``bot``.

    A frond or branch hanging down beside the stem is not part of it.
    """
    band = np.zeros_like(mask)
    band[top: bot + 1] = mask[top: bot + 1]
    comp, n_comp = ndi.label(band, structure=np.ones((3, 3)))
    if n_comp > 1:
        bottom = np.bincount(comp[bot], minlength=n_comp + 1)
        bottom[0] = 0
        if bottom.max() == 0:
            bottom = np.bincount(comp.ravel(), minlength=n_comp + 1)
            bottom[0] = 0
        band = comp == int(np.argmax(bottom))
    return band


def _find_stem(mask: np.ndarray, foliage: np.ndarray, lab: np.ndarray, stem_width: float) -> _Stem:
    rows = np.nonzero(mask.any(axis=1))[0]
    y0, y1 = int(rows[0]), int(rows[-1])
    height = y1 - y0 + 1
    widths = mask.sum(axis=1).astype(float)
    narrow = widths < stem_width * widths.max()
    narrow[: y0] = False
    narrow[y1 + 1:] = False
    # Runs of narrow rows, lowest first, within the lower 60 % of the tree.
    lab_rows, n = ndi.label(narrow)
    xs = np.nonzero(mask)[1]
    best, band = None, None
    for k in range(n, 0, -1):
        ys = np.nonzero(lab_rows == k)[0]
        top, bot = int(ys[0]), int(ys[-1])
        if bot < y0 + 0.4 * height:
            continue
        if bot - top + 1 < max(3, 0.03 * height):
            continue
        piece = _stem_piece(mask, top, bot)
        # A stem stands upright: at least half as tall as it is wide (this
        # rejects e.g. the tapering bottom of a ground patch).
        row_w = piece.sum(axis=1)
        if bot - top + 1 < 0.5 * np.median(row_w[row_w > 0]):
            continue
        best, band = (top, bot), piece
        break
    if best is None:
        return _Stem(None, float(np.median(xs)), np.full(3, np.nan))
    pix = band & ~foliage
    if pix.sum() < 4:
        return _Stem(None, float(np.median(xs)), np.full(3, np.nan))
    axis = float(np.median(np.nonzero(pix)[1]))
    return _Stem(best, axis, np.median(lab[pix], axis=0), band)


def tree_features(rgba, *, stem_width: float = 0.45, alpha_threshold: float = 0.5) -> dict:
    """Per-pixel colour and geometry cues of a tree image.

    Parameters
    ----------
    rgba : (H, W, 4) array_like
        Tree on a transparent background.
    stem_width : float
        Stem rows are narrower than this fraction of the widest row.
    alpha_threshold : float
        Pixels with alpha >= this are opaque (at least 16 are needed).

    Returns
    -------
    dict
        ``features`` (H, W, F) float32 (names in ``FEATURE_NAMES``), ``mask``
        (opaque pixels), ``foliage`` and ``woody`` colour masks, ``stem``
        (band rows, axis, colour) and ``D`` (tree size in pixels).

    Raises
    ------
    ValueError
        No alpha channel, fewer than 16 opaque pixels or no transparent one.

    Examples
    --------
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> tree = synthetic_tree("clean", rng=0, size=64)
    >>> cues = tree_features(tree.image)
    >>> cues["features"].shape == (64, 64, len(FEATURE_NAMES))
    True
    """
    img, mask = tree_rgba(rgba, alpha_threshold=alpha_threshold, min_pixels=16, name="rgba")
    rgb = img[:, :, :3]
    h, w = mask.shape
    lab = rgb2lab(rgb).astype(np.float32)
    foliage = _foliage_colour(rgb) & mask
    woody = _woody_colour(rgb) & mask
    ys, xs = np.nonzero(mask)
    th, tw = ys.max() - ys.min() + 1, xs.max() - xs.min() + 1
    D = float(max(th, tw))
    stem = _find_stem(mask, foliage, lab, stem_width)

    s1, s2, s3 = max(1.0, 0.03 * D), max(1.5, 0.1 * D), max(1.0, 0.05 * D)
    near = _masked_blur(lab, mask, s1)
    green = foliage.astype(np.float32)
    green_near = _masked_blur(green, mask, s1)
    green_far = _masked_blur(green, mask, s2)
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    height = (yy - ys.min()) / max(th - 1, 1)
    axis_dist = np.abs(xx - stem.axis) / max(0.5 * tw, 1)
    run_w = _run_lengths(mask, 1) / tw
    run_h = _run_lengths(mask, 0) / th
    dt = ndi.distance_transform_edt(np.pad(mask, 1))[1:-1, 1:-1].astype(np.float32)
    dtmax = max(float(dt.max()), 1.0)
    k = max(3, int(0.05 * D) | 1)
    thick = ndi.grey_dilation(dt, size=(k, k)) * mask
    if foliage.any():
        d_green = ndi.distance_transform_edt(~foliage).astype(np.float32)
    else:
        d_green = np.full(mask.shape, D, np.float32)
    d_green_bg = np.minimum(d_green + dt, D) / D
    if np.all(np.isfinite(stem.colour)):
        stem_delta = np.linalg.norm(lab - stem.colour, axis=2)
    else:
        stem_delta = np.full(mask.shape, 50.0, np.float32)
    stem_col = stem_delta / 100.0
    opaque_near = cv2.GaussianBlur(mask.astype(np.float32), (0, 0), s3)
    feats = np.stack([
        lab[..., 0] / 100, lab[..., 1] / 100, lab[..., 2] / 100,
        near[..., 0] / 100, near[..., 1] / 100, near[..., 2] / 100,
        green_near, green_far, height, axis_dist, run_w, run_h,
        dt / dtmax, thick / dtmax, np.minimum(d_green, D) / D, d_green_bg, stem_col, opaque_near,
    ], axis=2).astype(np.float32)
    return {"features": feats, "mask": mask, "foliage": foliage, "woody": woody,
            "stem": stem, "D": D, "dt": dt, "d_green": d_green,
            "stem_delta": stem_delta}


# ---------------------------------------------------------------------------
# Seeds
# ---------------------------------------------------------------------------


def automatic_seeds(cues: dict) -> np.ndarray:
    """Confident crown/trunk pixels derived from the cues of one image.

    Parameters
    ----------
    cues : dict
        Output of :func:`tree_features`.

    Returns
    -------
    seeds : (H, W) uint8
        0 unknown, 1 crown, 2 trunk.

    Examples
    --------
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> seeds = automatic_seeds(tree_features(synthetic_tree("clean", rng=0, size=64).image))
    >>> sorted(set(seeds.ravel().tolist()))
    [0, 1, 2]
    """
    mask, foliage, stem, D = cues["mask"], cues["foliage"], cues["stem"], cues["D"]
    dt, d_green = cues["dt"], cues["d_green"]
    seeds = np.zeros(mask.shape, np.uint8)
    ys = np.nonzero(mask.any(axis=1))[0]
    top_row = int(ys[0])
    has_foliage = foliage.sum() >= 0.02 * mask.sum()
    band = np.zeros_like(mask)
    if stem.rows is not None:
        t, b = stem.rows
        # Leave the upper 10 % of the band (where the crown begins) unseeded.
        t = t + int(0.1 * (b - t + 1))
        band[t: b + 1] = stem.region[t: b + 1]
        trunk = ndi.binary_erosion(band & ~foliage, iterations=1, border_value=0)
        if trunk.sum() < 4:
            trunk = band & ~foliage
        seeds[trunk] = TRUNK
    if has_foliage:
        crown = ndi.binary_erosion(foliage, iterations=1, border_value=0)
        if crown.sum() < 4:
            crown = foliage
        # Outlines of drawn crowns: thin bands between foliage and background.
        outline = mask & ~foliage & (d_green + dt <= max(3.0, 0.045 * D))
        if stem.rows is not None:
            outline[stem.rows[0]:] = False
        seeds[(crown | outline) & (seeds == 0)] = CROWN
        if stem.rows is not None and (seeds == TRUNK).any():
            # Wood: stem-coloured pixels (outside the outline bands) connected to the stem.
            wood = mask & ~foliage & ~outline & (cues["stem_delta"] < 20.0)
            wood = ndi.binary_opening(wood, iterations=1)
            lab_w, _ = ndi.label(wood, structure=np.ones((3, 3)))
            ids = np.unique(lab_w[seeds == TRUNK])
            ids = ids[ids > 0]
            if len(ids):
                seeds[np.isin(lab_w, ids) & (seeds != CROWN)] = TRUNK
        if stem.rows is None:
            # No narrow stem: woody pixels far from the foliage in the lower part are trunk.
            low = np.zeros_like(mask)
            low[int(top_row + 0.6 * (ys[-1] - top_row)):] = True
            woody = cues["woody"] & low & (d_green > max(3.0, 0.03 * D))
            seeds[woody] = TRUNK
    elif stem.rows is not None:
        hsv_woody = cues["woody"][band].mean() >= 0.5 if band.any() else False
        if not hsv_woody:
            # A silhouette (black/grey): everything clearly above the stem is crown.
            above = mask.copy()
            above[stem.rows[0] - max(2, int(0.02 * D)):] = False
            seeds[above & (seeds == 0)] = CROWN
        # A brown stem and no foliage anywhere: a bare tree, all trunk.
    elif cues["woody"].sum() >= 0.5 * mask.sum():
        # No foliage colour and no narrow stem, but mostly wood: bare wood, all trunk.
        seeds[mask] = TRUNK
    return seeds
