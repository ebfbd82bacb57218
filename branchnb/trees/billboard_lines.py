"""Billboard clouds, step 5: line art (not in the paper, for drawn trees).

The thin dark strokes that outline flat colour in clip art (:func:`line_art`)
mark the drawing's silhouettes as seen from the front. Turned with their
billboards, they would pile up on the axis of a side view and cover its flat
regions with broken black dashes. Every billboard keeps its texture, but its
stroke pixels are drawn in a first pass, behind every fill pixel of the cloud
(the billboard version of the "inverted hull" outline of toon rendering): in
the front view nothing covers a stroke, so it is unchanged; from the side,
strokes show only where no fill is, along the side view's own silhouette.
Rear, interior and core billboards, hidden in the front view, show the image
with its strokes filled in by the nearest fill colour. Photographs have no
such strokes (a stroke must border a flat-coloured region) and are drawn as
before.

Part of :func:`~branchnb.trees.billboard.billboard_cloud` (see
:mod:`branchnb.trees.billboard`).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.image import composite_over, extend_nearest
from .quality import FLAT_COVERAGE, palette_coverage, palette_pixels


def _outer_lines(lines: np.ndarray, opaque: np.ndarray) -> np.ndarray:
    """The line pixels of the outline along the silhouette (within about one stroke of the outside).

    They stay behind the fills in side views, where they would otherwise
    cross the crown as the rim billboards carrying them swing inwards.
    """
    if not lines.any():
        return lines
    half = float(np.percentile(ndi.distance_transform_edt(lines)[lines], 90))
    inside = ndi.distance_transform_edt(np.pad(opaque, 1))[1:-1, 1:-1]
    return lines & (inside <= 2.0 * half + 1.5)


def line_art(rgba, *, width: float = 0.04, contrast: float = 0.12, alpha_threshold: float = 0.5,
             flat_span: float = 0.04) -> np.ndarray:
    """The drawn outlines of a clip-art tree: thin dark strokes that border flat colour.

    A pixel is on a stroke when a grey-level closing with a disc of
    ``width`` times the tree's size (its longer side; the disc spans
    ``width / 2`` each side of a stroke's middle) brightens its luminance
    by more than ``contrast``: it lies on a dark feature thinner than the
    disc, between brighter ones; the transparent surround counts as
    white, so an outline along the silhouette is a stroke too. Only
    strokes within one disc of a flat-coloured region count (pixels whose
    3 x 3 colour span is at most ``flat_span``, in 4-connected pieces at
    least as large as the disc's bounding square): a drawing's outlines
    border its fills, while the dark gaps between the leaves of a
    photograph border no flat colour and are left alone.

    Parameters
    ----------
    rgba : (H, W, 4) array_like
        Straight RGBA image in [0, 1].
    width : float
        Widest stroke, as a fraction of the tree's size.
    contrast : float
        Luminance a stroke is darker than what the closing fills it with.
    alpha_threshold : float
        Opaque where alpha >= this.
    flat_span : float
        Largest per-channel colour range of a flat pixel's 3 x 3 window.

    Returns
    -------
    (H, W) bool ndarray
        Stroke pixels (alpha > 0).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((60, 60, 4), np.float32)
    >>> img[10:50, 10:50] = (0.1, 0.7, 0.2, 1.0)      # a green square
    >>> img[10:50, 10:12, :3] = 0.0                    # outlined on its left
    >>> lines = line_art(img)
    >>> bool(lines[30, 10:12].all()), bool(lines[30, 20:48].any())
    (True, False)
    """
    img = np.asarray(rgba, dtype=np.float32)
    if img.ndim != 3 or img.shape[2] != 4:
        raise ValueError(f"rgba must be an (H, W, 4) array, got shape {img.shape}")
    for name, v in (("width", width), ("contrast", contrast), ("flat_span", flat_span)):
        if not np.isfinite(v) or v < 0:
            raise ValueError(f"{name} must be a finite number >= 0, got {v}")
    a = img[:, :, 3]
    opaque = a >= alpha_threshold
    out = np.zeros(a.shape, bool)
    if not opaque.any() or width <= 0:
        return out
    ys, xs = np.nonzero(opaque)
    size = max(np.ptp(ys), np.ptp(xs)) + 1
    r = max(1, int(round(0.5 * width * size)))
    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    lum = img[:, :, :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    lum = np.where(opaque, lum, 1.0).astype(np.float32)
    pad = 2 * r + 1
    closed = cv2.morphologyEx(np.pad(lum, pad, constant_values=1.0), cv2.MORPH_CLOSE, disc)[pad:-pad, pad:-pad]
    dark = (a > 1e-3) & (closed - lum > contrast)
    if not dark.any():
        return out
    rgb = composite_over(img, (1.0, 1.0, 1.0))
    span = (ndi.maximum_filter(rgb, size=(3, 3, 1)) - ndi.minimum_filter(rgb, size=(3, 3, 1))).max(axis=2)
    flat = (a >= 0.99) & (span <= flat_span)
    lab, _ = ndi.label(flat)
    area = np.bincount(lab.ravel())
    area[0] = 0
    big = area[lab] >= (2 * r + 1) ** 2
    if big.sum() < 0.05 * opaque.sum() and palette_coverage(img) >= FLAT_COVERAGE:
        # Beyond the rule above: fills too thin for flat 3 x 3 windows (outlined
        # palms at 128 px) are found by colour, the few main colours of flat art.
        fill = palette_pixels(img) & ~dark
        lab, _ = ndi.label(fill)
        area = np.bincount(lab.ravel())
        area[0] = 0
        big |= area[lab] >= (2 * r + 1) ** 2
    near = cv2.dilate(big.astype(np.uint8), cv2.getStructuringElement(
        cv2.MORPH_ELLIPSE, (4 * r + 3, 4 * r + 3))) > 0
    return dark & near


#: Least share of a drawing's pixels within 0.03 of its 8 main colours for :func:`flat_slivers`:
#: flat discs (cartoon_tree 0.98-0.99); shaded tiers with gradients and highlight strokes
#: (evergreen 0.89-0.90, plain_tree 0.89, tree_on_hill 0.97) keep their strokes (taken as fill,
#: evergreen's tiers doubled from the side, front PSNR at 512 px 41.8 -> 37.5 dB).
SLIVER_COVERAGE = 0.98


def flat_slivers(rgba, lines: np.ndarray, crown: np.ndarray, *, width: float = 0.04,
                 alpha_threshold: float = 0.5) -> np.ndarray:
    """The crown's :func:`fill_slivers` when the drawing is in a few flat colours (else none).

    Used by :func:`~branchnb.trees.billboard.billboard_cloud` on crowns
    without outlines built from tone cards: at least
    :data:`SLIVER_COVERAGE` of the opaque pixels lie within 0.03 of the 8
    main colours (:func:`~branchnb.trees.quality.palette_coverage`).

    Parameters
    ----------
    rgba : (H, W, 4) array_like
        Straight RGBA image in [0, 1].
    lines, crown : (H, W) bool arrays
        The line art and the crown.
    width, alpha_threshold : float
        As in :func:`line_art`.

    Returns
    -------
    (H, W) bool ndarray
        Line pixels of the crown that are fill.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((40, 40, 4), np.float32)
    >>> img[:, :, :3] = (0.3, 0.8, 0.2)
    >>> img[5:35, 5:35, :3] = (0.1, 0.4, 0.1)
    >>> img[20:35, 8:35, :3] = (0.3, 0.8, 0.2)
    >>> lines = line_art(img, width=0.2)
    >>> bool(flat_slivers(img, lines, np.ones((40, 40), bool), width=0.2)[28, 5:8].all())
    True
    """
    crown = np.asarray(crown, bool)
    if palette_coverage(rgba, n_colours=8, tol=0.03) < SLIVER_COVERAGE:
        return np.zeros(crown.shape, bool)
    return fill_slivers(rgba, lines, width=width, alpha_threshold=alpha_threshold) & crown


#: Largest area of a compact sliver in :func:`fill_slivers`, in squares of its thickness (a 1:4 strip).
SLIVER_ELONGATION = 4.0


def fill_slivers(rgba, lines: np.ndarray, *, width: float = 0.04, alpha_threshold: float = 0.5,
                 flat_span: float = 0.04) -> np.ndarray:
    """Pixels of ``lines`` that are the thin visible parts of wider flat fills, not strokes (beyond the paper).

    A crown of overlapping flat discs in a few tones without outlines
    (cartoon_tree) shows slivers of its darkest discs between lighter
    ones: thin dark features that :func:`line_art` takes for strokes, so
    they were drawn behind every fill and the tone cards
    (:func:`~branchnb.trees.billboard_cards.tone_edges`) lost them from the
    side (inner-outline recall at 90 degrees 0.47 at 512 px, and the tree
    fell back to one flat card). A sliver is one flat region (4-connected
    pixels whose 3 x 3 colour span is at most ``flat_span``) with the wide
    part of its disc: when at least half a flat region's pixels, and at
    least a disc's area (``pi r^2``, ``r`` the closing radius of
    :func:`line_art`), are not ``lines``, the region is a fill and its
    line pixels are fill too; so is a compact flat piece of ``lines`` (its
    area at most :data:`SLIVER_ELONGATION` times the square of its
    thickness; a stroke is long and thin) within 0.06 (RGB) of such a
    fill's colour (a sliver cut off its disc by the discs over it), and
    every 8-connected piece of ``lines`` whose flat pixels are mostly
    such fill (the anti-aliased rows along a sliver). Used only on crowns
    without outlines built from tone cards: on outlined drawings and RPG
    sprites the rule would also take dark shading bands for fill.

    Parameters
    ----------
    rgba : (H, W, 4) array_like
        Straight RGBA image in [0, 1].
    lines : (H, W) bool array
        The line art (:func:`line_art`).
    width, alpha_threshold, flat_span : float
        As in :func:`line_art`.

    Returns
    -------
    (H, W) bool ndarray
        The line pixels that are fill.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((40, 40, 4), np.float32)
    >>> img[:, :, :3] = (0.3, 0.8, 0.2)
    >>> img[5:35, 5:35, :3] = (0.1, 0.4, 0.1)      # a dark square fill
    >>> img[20:35, 8:35, :3] = (0.3, 0.8, 0.2)     # half covered: a 3 px dark sliver below
    >>> lines = line_art(img, width=0.2)
    >>> bool(lines[28, 5:8].all()), bool(fill_slivers(img, lines, width=0.2)[28, 5:8].all())
    (True, True)
    """
    img = np.asarray(rgba, dtype=np.float32)
    if img.ndim != 3 or img.shape[2] != 4:
        raise ValueError(f"rgba must be an (H, W, 4) array, got shape {img.shape}")
    dark = np.asarray(lines, bool)
    if dark.shape != img.shape[:2]:
        raise ValueError(f"lines must have shape {img.shape[:2]}, got {dark.shape}")
    out = np.zeros(dark.shape, bool)
    opaque = img[:, :, 3] >= alpha_threshold
    if not dark.any() or not opaque.any():
        return out
    ys, xs = np.nonzero(opaque)
    r = max(1, int(round(0.5 * width * (max(np.ptp(ys), np.ptp(xs)) + 1))))
    rgb = composite_over(img, (1.0, 1.0, 1.0))
    span = (ndi.maximum_filter(rgb, size=(3, 3, 1)) - ndi.minimum_filter(rgb, size=(3, 3, 1))).max(axis=2)
    flat = (img[:, :, 3] >= 0.99) & (span <= flat_span)
    lab, n = ndi.label(flat)
    if n == 0:
        return out
    size = np.bincount(lab.ravel(), minlength=n + 1)
    n_dark = np.bincount(lab[dark].ravel(), minlength=n + 1)
    light = size - n_dark
    fill = (light >= 0.5 * size) & (light >= np.pi * r * r) & (n_dark > 0)
    fill[0] = False
    if not fill.any():
        return out
    out = dark & fill[lab]
    # Compact dark flat pieces in a fill's colour (cut off their disc).
    rest = (n_dark > 0) & ~fill
    rest[0] = False
    if rest.any():
        idx = np.arange(n + 1)
        cols = np.stack([ndi.mean(rgb[..., c], lab, idx) for c in range(3)], axis=1)
        thick = ndi.maximum(ndi.distance_transform_edt(lab > 0), lab, idx)
        compact = rest & (size <= SLIVER_ELONGATION * (2.0 * np.asarray(thick)) ** 2)
        if compact.any():
            d = np.linalg.norm(cols[compact][:, None] - cols[fill][None], axis=2).min(axis=1)
            compact[np.flatnonzero(compact)[d > 0.06]] = False
            out |= dark & compact[lab]
    # Whole dark pieces whose flat pixels are mostly such fill go with them.
    dlab, m = ndi.label(dark, np.ones((3, 3), bool))
    on_fill = np.bincount(dlab[out].ravel(), minlength=m + 1)
    on_flat = np.bincount(dlab[dark & flat].ravel(), minlength=m + 1)
    whole = on_fill >= np.maximum(0.5 * on_flat, 1)
    whole[0] = False
    return out | whole[dlab]


_LUM3 = np.array([0.2126, 0.7152, 0.0722], np.float32)


def _colour_span3(rgb: np.ndarray) -> np.ndarray:
    """Largest per-channel range of each pixel's 3 x 3 window."""
    return (ndi.maximum_filter(rgb, size=(3, 3, 1)) - ndi.minimum_filter(rgb, size=(3, 3, 1))).max(axis=2)


def _fill_lines(image: np.ndarray, lines: np.ndarray, support: np.ndarray) -> np.ndarray:
    """``image`` with every line pixel given the colour of the nearest non-line pixel of ``support``."""
    keep = support & ~lines
    if not keep.any():
        return image
    out = image.copy()
    out[lines, :3] = extend_nearest(image[:, :, :3], keep)[lines]
    return out


def _line_masks(lines, textures, tex_idx, centers, sizes) -> list:
    """Per texture, its pixels on ``lines`` where the front view puts it (None: none)."""
    out = [None] * len(textures)
    if not lines.any():
        return out
    H, W = lines.shape
    for i, tid in enumerate(tex_idx):
        if out[tid] is not None:
            continue
        w, h = sizes[i]
        x0 = int(round(centers[i][0] - 0.5 * w))
        y0 = int(round(centers[i][1] - 0.5 * h))
        m = np.zeros((int(h), int(w)), bool)
        ax0, ay0, ax1, ay1 = max(x0, 0), max(y0, 0), min(x0 + int(w), W), min(y0 + int(h), H)
        if ax1 > ax0 and ay1 > ay0:
            m[ay0 - y0: ay1 - y0, ax0 - x0: ax1 - x0] = lines[ay0:ay1, ax0:ax1]
        m &= textures[tid][:, :, 3] > 0
        if m.any():
            out[tid] = m
    return out


def trunk_outline(trunk: np.ndarray, opaque: np.ndarray, lines: np.ndarray, band: float) -> np.ndarray:
    """The trunk mask grown over its own drawn outline and the fill it was cut from (beyond the paper).

    A drawn trunk's segmentation often stops at its fill: its side strokes
    (and a sliver of its fill cut off where it enters the crown) are left
    to the crown, whose billboards sit in front of the trunk's, so from the
    side the strokes slide off the trunk and its edges show no outline
    (issue 24). Here every fill region (an 8-connected piece of
    ``opaque & ~lines``) at most :data:`TRUNK_SLIVER` outside ``trunk``
    joins it, and so does every line pixel within ``band`` of it whose
    nearest fill pixel is trunk and which lies farther than ``band`` from
    any other fill (the crown's strokes over the trunk stay the crown's).
    ``python -m branchnb.trees._measure_lines 512 ground 1
    christmas_tree_root_flare``: full level's rim ink at 45 degrees 0.851 ->
    0.878 (the drawing's own front view: 0.796, its soft rim and the star's
    own outline colour); the 37 trees at 256 px unchanged or better
    (conifer_on_base 0.986 -> 0.994), no card fallback.

    Parameters
    ----------
    trunk, opaque, lines : (H, W) bool arrays
        The trunk, the opaque pixels and the line art.
    band : float
        Stroke band in pixels (about a stroke's width).

    Returns
    -------
    (H, W) bool
        The grown trunk (a superset of ``trunk & opaque``).

    Examples
    --------
    >>> import numpy as np
    >>> op = np.zeros((9, 9), bool); op[1:8, 2:7] = True
    >>> ln = op & ~np.pad(np.ones((5, 3), bool), ((2, 2), (3, 3)))
    >>> tr = np.zeros((9, 9), bool); tr[2:7, 3:6] = True
    >>> int(trunk_outline(tr, op, ln, 2.0).sum()), int(op.sum())
    (35, 35)
    """
    trunk = np.asarray(trunk, bool) & np.asarray(opaque, bool)
    opaque = np.asarray(opaque, bool)
    lines = np.asarray(lines, bool) & opaque
    fill = opaque & ~lines
    if not trunk.any() or not fill.any() or not lines.any():
        return trunk
    lab, n = ndi.label(fill, np.ones((3, 3), bool))
    in_t = np.bincount(lab[trunk & fill], minlength=n + 1)
    size = np.bincount(lab.ravel(), minlength=n + 1)
    mostly = in_t >= (1.0 - TRUNK_SLIVER) * size
    mostly[0] = False
    out = trunk | mostly[lab]
    other = fill & ~out
    near = ndi.distance_transform_edt(~fill, return_distances=False, return_indices=True)
    nearest_trunk = out[near[0], near[1]]
    far = ndi.distance_transform_edt(~other) > band if other.any() else np.ones_like(fill)
    close = ndi.distance_transform_edt(~out) <= band
    return out | (lines & nearest_trunk & far & close)


#: Largest share of a fill region outside the trunk for :func:`trunk_outline` to give it to the
#: trunk: a sliver cut off where the trunk enters the crown (christmas_tree_root_flare at 512 px:
#: under 2 %); tree_rpg_14's trunk shares its brown with the crown's thick outline band (one fill
#: region, half of it crown), which stays the crown's.
TRUNK_SLIVER = 0.15
