"""Thin line layers for lazy snapping: ridge strength of 1-5 px veins, pale or dark.

Not in the paper. Lazy snapping (Li et al. 2004) labels pixels by colour;
on a streaked grass blade the colours of a pale 1-px vein and of the blade
beside it overlap, and superpixels wider than the vein make blocks. A
scribbled layer whose pixels are ridges (or valleys) of the lightness
gets, in :func:`branchnb.leaves.layers.grow_layers`, a data term from an
oriented line filter (:func:`_ridges`, :func:`_line_channel`).
"""

from __future__ import annotations

import cv2
import numpy as np

#: Median line-likeness (``1 - weakest / strongest`` answer over orientations) of a line layer's scribbled pixels.
_LINE_LIKE = 0.99
#: ... or at least this, where the scribbled pixels lie in a network of standing-out pixels
#: (:func:`_network`) of at least _NETWORK squares of its widest half width per piece: 128-px lobed
#: and fan leaves' scribbled veins measured 0.943-0.979 (strokes over junctions) and 33.8-61;
#: scribbled procedural spots 0.90-0.99 with at most 24.2 (a round spot: about 3).
_LINE_LIKE_LOW = 0.93
_NETWORK = 30.0
#: Pixels this far (px) from any pixel standing out as the scribbled lines do are plain blade for sure.
_PLAIN_REACH = 3
#: ... and they set the plain level when they are at least this share of the blade.
_PLAIN_SHARE = 0.1
#: ... whose level is this percentile of their ridge strength (the far blade is the plainer part: a high one).
_FAR_PCT = 99.0
#: ... on a blade whose far grain (that percentile) stays under this share of the scribbled lines' strength.
_FLAT_GRAIN = 0.25


def _ridges(lightness: np.ndarray, blade: np.ndarray) -> np.ndarray:
    """Bright-ridge and dark-valley strength of the CIELAB lightness for lines 1-5 px wide, (H, W, 6).

    Oriented line filters (a matched filter, as for retinal vessels): the
    second derivative of a Gaussian of ``sigma`` = 1, 1.5, 2 px across a
    line times a Gaussian of 3 px along it, scale-normalised (``sigma^2``),
    the strongest over 12 orientations and the scales; channel 0 for a line
    lighter than the blade on both sides, 1 for a darker one. Averaging
    along the line keeps a long thin vein and drops the shorter streaks
    of a grass blade's texture. Channels 2 and 3: how much lighter
    (darker) than the blade around it (an 11-px box mean) each pixel is;
    4 and 5: how line-like the answer of 0 (1) is, ``1 - weakest / strongest``
    over the orientations at its scale (a blob answers every orientation).
    """
    from ..core.image import extend_nearest

    rows, cols = np.nonzero(blade)
    pad = 9
    r0, r1 = max(rows.min() - pad, 0), rows.max() + pad + 1
    c0, c1 = max(cols.min() - pad, 0), cols.max() + pad + 1
    L = np.asarray(lightness[r0:r1, c0:c1], np.float32) / 100.0
    # Outside the blade (paper, background) the lightness jumps: hold the
    # blade's own values there so the rim is no ridge.
    L = extend_nearest(L, blade[r0:r1, c0:c1]).astype(np.float32)
    bright = np.zeros(L.shape, np.float32)
    dark = np.zeros(L.shape, np.float32)
    # The same scale's weakest answer over the orientations: about 0 for
    # a line (a filter laid across it), as strong as the best for a blob.
    bright_any = np.zeros(L.shape, np.float32)
    dark_any = np.zeros(L.shape, np.float32)
    r = np.arange(-pad, pad + 1, dtype=np.float32)
    xx, yy = np.meshgrid(r, r)
    for sigma in (1.0, 1.5, 2.0):
        hi = np.full(L.shape, -np.inf, np.float32)
        lo = np.full(L.shape, np.inf, np.float32)
        for theta in np.arange(12) * np.pi / 12:
            u = xx * np.cos(theta) + yy * np.sin(theta)    # along the line
            v = -xx * np.sin(theta) + yy * np.cos(theta)   # across it
            k = (1.0 - v**2 / sigma**2) * np.exp(-v**2 / (2 * sigma**2) - u**2 / (2 * 3.0**2))
            k -= k.mean()
            k *= sigma**2 / np.abs(k).sum()
            resp = cv2.filter2D(L, -1, k, borderType=cv2.BORDER_REPLICATE)
            np.maximum(hi, resp, out=hi)
            np.minimum(lo, resp, out=lo)
        up = hi > bright
        bright_any[up] = lo[up]
        bright[up] = hi[up]
        up = -lo > dark
        dark_any[up] = -hi[up]
        dark[up] = -lo[up]
    # How much lighter each pixel is than the blade around it (11 px box):
    # a line filter also answers beside a line (its blur), this does not.
    above = L - cv2.blur(L, (11, 11), borderType=cv2.BORDER_REPLICATE)
    full = np.zeros(blade.shape + (6,), np.float32)
    full[r0:r1, c0:c1, 0] = bright
    full[r0:r1, c0:c1, 1] = dark
    full[r0:r1, c0:c1, 2] = above
    full[r0:r1, c0:c1, 3] = -above
    # How line-like (not blob-like) the answer is: 1 - weakest / strongest.
    full[r0:r1, c0:c1, 4] = 1.0 - np.clip(bright_any, 0, None) / np.maximum(bright, 1e-6)
    full[r0:r1, c0:c1, 5] = 1.0 - np.clip(dark_any, 0, None) / np.maximum(dark, 1e-6)
    full[~blade] = 0
    return full


def _network(above: np.ndarray, fg_px: np.ndarray, blade: np.ndarray) -> float:
    """How far the scribbled pixels lie in a thin network: area over squared widest half width of the
    pieces of blade standing out as they do (at least half as much) that they touch, the median piece."""
    from scipy import ndimage as ndi

    stand = blade & (above >= 0.5 * float(np.median(above[fg_px])))
    lab, _ = ndi.label(stand, structure=np.ones((3, 3), bool))
    ids = np.unique(lab[fg_px & stand])
    ids = ids[ids > 0]
    if not len(ids):
        return 0.0
    dist = ndi.distance_transform_edt(stand)
    area = np.asarray(ndi.sum(stand, lab, ids), float)
    half = np.maximum(np.asarray(ndi.maximum(dist, lab, ids), float), 1.0)
    return float(np.median(area / half**2))


def _plain_level(ridge: np.ndarray, blade: np.ndarray, on: float, above: np.ndarray | None = None,
                 lift: float = 0.0) -> float:
    """The ridge strength of plain blade: its percentile ``1 - share``, ``share`` the part of the blade
    answering at least half as strongly as the scribbled lines (``on``), in [0.15, 0.5].

    A fixed 85th percentile took the veins for plain blade where they cover
    more than 15 % of it: pale parallel veins of a grass-type strip cover
    35-37 % (procedural strips) and their scribbles were no line layer
    (their median strength 0.055 under the 85th percentile 0.059); lazy
    snapping then grew one vein or a block of blade (vein IoU 0.21-0.26).
    Sparse venation (lobed, elliptic families: 13-17 %) keeps the 85th.
    """
    vals = ridge[blade]
    share = float(np.mean(vals >= 0.5 * on)) if on > 0 else 0.0
    level = float(np.percentile(vals, 100.0 * (1.0 - float(np.clip(share, 0.15, 0.5)))))
    if above is None or lift <= 0:
        return level
    # Plain blade for sure: farther than the filter's reach from any pixel
    # standing out as the scribbled lines do. On a small leaf (96-128 px)
    # veins 1-2 px wide and the filter's blur around them cover a quarter
    # of the blade or more; the percentile above then lands on the veins'
    # own flanks (0.14 against 0.26 on the scribbled midribs of a 128-px
    # lobed leaf) and the fainter 1-px laterals fell under it.
    near = cv2.dilate((above >= 0.5 * lift).astype(np.uint8), np.ones((2 * _PLAIN_REACH + 1,) * 2, np.uint8))
    far = blade & (near == 0)
    if far.sum() >= _PLAIN_SHARE * blade.sum():
        far_level = float(np.percentile(ridge[far], _FAR_PCT))
        # Only on a flat blade (its grain well under the lines): on the
        # photographed sample maple (far grain 0.33 of the scribbled
        # veins', against 0.08-0.14 on flat drawn leaves) the lower level
        # let spots and vein nodes into the vein layer.
        if far_level < _FLAT_GRAIN * on:
            level = min(level, far_level)
    return level


def _line_channel(ridges: np.ndarray, fg_px: np.ndarray, blade: np.ndarray, strokes: list,
                  plain: np.ndarray | None = None):
    """The ridge (or valley) strength of a thin line layer, 1 from its faintest scribbled line up; None if not a line.

    A layer is a line layer when its scribbled pixels are ridges (or
    valleys) stronger than 85 % of the blade and line-like (a filter laid
    across them does not answer: median ``1 - weakest / strongest`` over
    the orientations of at least 0.99): a vein is; a spot is not (round,
    every orientation answers: 0.66-0.96 measured on maple and procedural
    spots, 1.0 on veins), nor the flat inside of a blob wider than 5 px. The strength is
    measured against the faintest scribbled line (the median under each
    scribble, the least of them), so a faint 1-px vein scribbled beside a
    bold midrib counts as fully a line too. Strokes over the junctions of a
    dense small venation (128-px leaves) answer several orientations there
    (median 0.94-0.98): they still make a line layer at
    :data:`_LINE_LIKE_LOW` when the blade standing out around them is a thin
    network (:func:`_network`). Not in the paper: lazy
    snapping's colour model cannot tell a pale 1-px vein from the pale
    streaks of a grass blade beside it.
    """
    if fg_px.sum() < 4:
        return None
    best = None
    for k in (0, 1):
        on = float(np.median(ridges[..., k][fg_px]))
        ref = _plain_level(ridges[..., k], blade, on, ridges[..., 2 + k], float(np.median(ridges[..., 2 + k][fg_px])))
        like = float(np.median(ridges[..., 4 + k][fg_px]))
        # Strokes over the junctions of a dense small venation answer several orientations there
        # (beyond the paper): a thin network of standing-out pixels around them still makes a line.
        line_like = like >= _LINE_LIKE or (like >= _LINE_LIKE_LOW and on > max(ref, 1e-6)
                                           and _network(ridges[..., 2 + k], fg_px, blade) >= _NETWORK)
        if line_like and on > max(ref, 1e-6) and (best is None or on / ref > best[1]):
            best = (k, on / max(ref, 1e-9))
    if best is None:
        return None
    k = best[0]
    ref = _plain_level(ridges[..., k], blade, float(np.median(ridges[..., k][fg_px])), ridges[..., 2 + k],
                       float(np.median(ridges[..., 2 + k][fg_px])))
    plain = None if plain is None else plain & blade & ~fg_px
    if plain is not None and plain.sum() >= 4:
        # The user's blade scribbles say what plain blade is. Parallel
        # veins 4-5 px apart (a 128-px strip) leave no blade beyond the
        # filter's reach, and the percentile rule lands on the veins'
        # flanks (0.109; the anti-aliased half of a 1-px vein 0.10, its
        # scribbled half 0.12). Plain blade's own lines are the pixels
        # under them standing out as the layer's lines do (a textured
        # blade's grain: the strongest of them); beside a vein they stand
        # out the other way (the filter's blur, which ``above`` below
        # drops anyway): then their median.
        grain = plain & (ridges[..., 2 + k] > 0)
        ref = min(ref, float(ridges[..., k][grain].max()) if grain.sum() >= 2
                  else float(np.median(ridges[..., k][plain])))
    each = [float(np.median(ridges[..., k][m & fg_px])) for m in strokes if (m & fg_px).sum() >= 3]
    each = [v for v in each if v > ref]
    on = min(each) if each else float(np.median(ridges[..., k][fg_px]))
    strength = np.clip((ridges[..., k] - ref) / max(on - ref, 1e-6), 0.0, 1.0)
    # Only pixels lighter (darker) than the blade around them: the filter's
    # blur also answers a pixel or two beside a thin vein (the layer grew
    # 3 px wide around 1-px veins) and on the dark flanks of a pale vein.
    above = ridges[..., 2 + k]
    lift = float(np.median(above[fg_px]))
    # Only line-like pixels: a dark dot (a spot) beside a dark vein answers
    # the valley filter too, but every orientation of it.
    coherent = np.clip((ridges[..., 4 + k] - 0.6) / 0.35, 0.0, 1.0)
    return strength * coherent * np.clip(above / max(0.5 * lift, 1e-6), 0.0, 1.0)
