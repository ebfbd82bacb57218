"""Large flat-colour regions of an example and its layout without the branches.

A map's land and sea, a mask's two values: :func:`flat_colour_regions`
segments them, :func:`region_layout` removes the branches from them and
:func:`colour_labels` labels any image by the regions' colours. Moved out of
:mod:`branchnb.branching.regions` (which still imports every name).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

__all__ = ["flat_colour_regions", "region_layout", "colour_labels", "two_tone_lines"]

#: Largest colour range (any channel) across one flat piece of a flat-colour region; a wider drift is
#: shading. Drawn maps and masks (noise and JPEG included) stay well below; the retina fundus's
#: smooth ground drifts by 0.3 and more.
SHADED_SPREAD = 0.15


def flat_colour_regions(image: np.ndarray, exclude: np.ndarray | None = None, *, tol: float = 0.03,
                        min_fraction: float = 0.02) -> tuple[np.ndarray, float]:
    """Segment an example into its large flat-colour regions (land and sea of a map, a mask's two values).

    Pixels whose 5 x 5 neighbourhood varies by less than ``tol`` in every
    channel are flat; their connected pieces whose colour drifts by more than
    ``SHADED_SPREAD`` across them are shading, not flat colour (beyond the
    paper: a soft, vignetted photo's ground is locally flat everywhere);
    the others are grouped by mean colour (within ``2 tol``), and every group covering at least ``min_fraction``
    of the image is a region. Every other pixel (texture, branches, the
    ``exclude`` mask, e.g. the annotated branch bodies) takes the label of
    the nearest region pixel, so a branch lies in the region around it.

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example, float in [0, 1] (the first 3 channels are used).
    exclude : (H, W) bool ndarray, optional
        Pixels never taken as flat (e.g. the annotated branch bodies); None =
        none.
    tol : float, default 0.03
        Largest range of a flat 5 x 5 neighbourhood, per channel.
    min_fraction : float, default 0.02
        Smallest share of the image a region covers.

    Returns
    -------
    labels : (H, W) int32 ndarray
        Region index per pixel (all 0 when there are fewer than two regions).
    share : float
        Fraction of the image that is flat and in a region.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 40, 3), np.float32); img[:, 20:] = 0.8
    >>> lab, share = flat_colour_regions(img)
    >>> int(lab[5, 5]), int(lab[5, 35]), share > 0.8
    (0, 1, True)
    """
    img = np.asarray(image, np.float32)
    h, w = img.shape[:2]
    rng_ = np.zeros((h, w), np.float32)
    k = np.ones((5, 5), np.uint8)
    for c in range(min(img.shape[2], 3)):
        ch = np.ascontiguousarray(img[..., c])
        rng_ = np.maximum(rng_, cv2.dilate(ch, k) - cv2.erode(ch, k))
    flat = rng_ < tol
    if exclude is not None:
        flat &= ~np.asarray(exclude, bool)
    lab, n = ndi.label(flat)
    zeros = np.zeros((h, w), np.int32)
    if n == 0:
        return zeros, 0.0
    area = np.bincount(lab.ravel(), minlength=n + 1)
    idx = np.arange(1, n + 1)
    nc = min(img.shape[2], 3)
    means = np.stack([ndi.mean(img[..., c], lab, idx) for c in range(nc)], 1)
    # beyond the paper: a flat piece whose colour drifts across it is smooth shading (a soft,
    # vignetted photo's ground), not a flat colour; a drawn region keeps its colour to within noise
    spread = np.max([ndi.maximum(img[..., c], lab, idx) - ndi.minimum(img[..., c], lab, idx)
                     for c in range(nc)], axis=0)
    area[1:][spread > SHADED_SPREAD] = 0
    order = np.argsort(-area[1:]) + 1
    groups: list[list[int]] = []
    colours: list[np.ndarray] = []
    for i in order:
        if area[i] < 0.0005 * h * w:
            break
        col = means[i - 1]
        for g, c in enumerate(colours):
            if np.max(np.abs(c - col)) <= 2 * tol:
                groups[g].append(int(i))
                break
        else:
            groups.append([int(i)])
            colours.append(col)
    region_of = np.full(n + 1, -1, np.int32)
    k_reg = 0
    for g in groups:
        if area[g].sum() >= min_fraction * h * w:
            region_of[g] = k_reg
            k_reg += 1
    if k_reg < 2:
        share = float(area[[i for g in groups for i in g if region_of[i] >= 0]].sum() / (h * w)) if k_reg else 0.0
        return zeros, share
    labels = region_of[lab]
    share = float(np.mean(labels >= 0))
    _, (iy, ix) = ndi.distance_transform_edt(labels < 0, return_indices=True)
    return labels[iy, ix].astype(np.int32), share


def region_layout(colours: np.ndarray, branches: np.ndarray, body: np.ndarray | None = None) -> np.ndarray:
    """The example's region layout without its branches: what surrounds the branches, not the branches.

    ``colours`` are per-pixel colour labels (:func:`colour_labels`, -1 =
    no region's colour). Pixels of no region's colour (a blue river on a
    map, anti-aliased edges) take the label of the nearest labelled pixel.
    When the branches themselves have a region's colour (the white
    channels of a water mask, white like the sea), the pixels of that
    colour in ``branches`` (the example's branch neighbourhood) are
    relabelled the same way, so the layout holds land and sea only and a
    target laid out on it carries no ghosts of the example's channels.
    ``body`` (default ``branches``) is where the branch colour is read.

    Parameters
    ----------
    colours : (H, W) int ndarray
        Colour labels per pixel, -1 = no region's colour.
    branches : (H, W) bool ndarray
        The example's branch neighbourhood.
    body : (H, W) bool ndarray, optional
        Where the branch colour is read; None = ``branches``.

    Returns
    -------
    (H, W) int ndarray
        The layout: every pixel a region label >= 0 (unless no pixel had
        one).

    Raises
    ------
    ValueError
        If ``branches`` does not have the shape of ``colours``.

    Examples
    --------
    >>> lab = np.zeros((20, 20), np.int32); lab[15:] = 1; lab[:, 9:11] = 1   # a channel into the sea
    >>> zone = np.zeros((20, 20), bool); zone[:15, 8:12] = True
    >>> body = np.zeros((20, 20), bool); body[:15, 9:11] = True
    >>> out = region_layout(lab, zone, body)
    >>> int(out[5, 10]), int(out[18, 10])
    (0, 1)
    """
    colours = np.asarray(colours)
    zone = np.asarray(branches, bool)
    if zone.shape != colours.shape:
        raise ValueError(f"branches must have the labels' shape {colours.shape}, got {zone.shape}")
    body = zone if body is None else np.asarray(body, bool)
    redo = colours < 0
    known = colours[body & ~redo]
    if known.size and np.count_nonzero(body & ~redo) >= 0.5 * np.count_nonzero(body):
        redo |= zone & (colours == np.bincount(known).argmax())
    if not redo.any() or redo.all():
        return colours.copy()
    _, (iy, ix) = ndi.distance_transform_edt(redo, return_indices=True)
    return colours[iy, ix]


def colour_labels(image: np.ndarray, labels: np.ndarray, sample: np.ndarray | None = None, *,
                  tol: float = 0.1) -> np.ndarray:
    """Label every pixel by the region whose mean colour matches its own colour.

    ``flat_colour_regions`` gives a branch and its anti-aliased rim the
    label of the region around it (a white channel lies in black land).
    To copy "land from land" pixel by pixel, the colour decides instead:
    a white rim pixel is water wherever it lies. Region colours are the
    means over ``sample`` (default: every pixel) of each label; a pixel
    farther than ``tol`` (in its most different channel) from every
    region colour gets -1 (a river's own colour, a blend at an edge).

    Parameters
    ----------
    image : (H, W, C) or (H, W) float ndarray
        The example, float in [0, 1] (the first 3 channels are used).
    labels : (H, W) int ndarray
        Region labels, e.g. from :func:`flat_colour_regions`.
    sample : (H, W) bool ndarray, optional
        Pixels whose colours define the region colours (their median); None =
        all.
    tol : float, default 0.1
        Largest per-channel difference to a region colour.

    Returns
    -------
    (H, W) int32 ndarray
        The label of the nearest region colour, -1 where none is within
        ``tol``.

    Examples
    --------
    >>> img = np.zeros((10, 10, 3), np.float32); img[:, 5:] = 1.0; img[2, 2] = 0.95; img[3, 3] = 0.5
    >>> lab = np.zeros((10, 10), np.int32); lab[:, 5:] = 1
    >>> c = colour_labels(img, lab)
    >>> int(c[2, 2]), int(c[2, 3]), int(c[3, 3])
    (1, 0, -1)
    """
    img = np.asarray(image, np.float32)
    img = img[..., :3] if img.ndim == 3 else img[..., None]
    labels = np.asarray(labels)
    use = np.ones(labels.shape, bool) if sample is None else np.asarray(sample, bool)
    ks = np.unique(labels)
    cols = []
    for k in ks:
        m = (labels == k) & use
        cols.append(np.median(img[m], 0) if m.any() else np.median(img[labels == k], 0))
    cols = np.asarray(cols, np.float32)
    d = np.abs(img[:, :, None, :] - cols[None, None]).max(-1)
    out = ks[np.argmin(d, axis=-1)].astype(np.int32)
    out[d.min(-1) > tol] = -1
    return out


def two_tone_lines(image: np.ndarray, *, off_axis: float = 0.06, ground_share: float = 0.5,
                   max_off: float = 0.005, max_inner: float = 0.1) -> bool:
    """Whether an example is a line mask: lines of one colour on a plain ground, nothing else.

    Every pixel is the ground colour, the line colour or (on the lines'
    anti-aliased edges) a mix of the two. Such an example (a binary or
    anti-aliased vessel, crack or river mask, in either polarity) has no
    texture a copied fragment could bring: its lines are best drawn.

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example, float in [0, 1] (the first 3 channels are used).
    off_axis : float, default 0.06
        A pixel farther than this (Euclidean) from the segment between the
        ground and line colours is of another colour.
    ground_share : float, default 0.5
        Smallest share of the image in the ground colour.
    max_off : float, default 0.005
        Largest share of the image in other colours (noise, a third colour).
    max_inner : float, default 0.1
        Largest share of the mixed pixels (10-90 % of the way to the line
        colour) with no ground pixel beside them: mixed pixels of a mask are
        anti-aliased edges, those of a glow or a blur lie inside a halo.

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((40, 60, 3), np.float32); img[18:21, 5:55] = 0.0
    >>> two_tone_lines(img)
    True
    >>> two_tone_lines(np.random.default_rng(0).random((40, 60, 3)).astype(np.float32))
    False
    """
    img = np.asarray(image, np.float32)
    if img.ndim == 2:
        img = img[..., None]
    img = img[..., :3]
    flat_px = img.reshape(-1, img.shape[2])
    # the ground: the most common colour (quantised), the line: the colour farthest from it in the
    # strongest percent of the image
    q = np.round(flat_px * 16).astype(np.int32)
    keys, counts = np.unique(q @ (17 ** np.arange(q.shape[1])), return_counts=True)
    key = keys[counts.argmax()]
    near = (q @ (17 ** np.arange(q.shape[1]))) == key
    if near.mean() < ground_share:
        return False
    g = np.median(flat_px[near], axis=0)
    d = np.linalg.norm(flat_px - g, axis=1)
    far = d >= np.percentile(d, 99.5)
    if float(d.max()) < 0.2:
        return False
    line = np.median(flat_px[far], axis=0)
    v = line - g
    span = float(v @ v)
    t = np.clip((flat_px - g) @ v / span, 0.0, 1.0)
    off = np.linalg.norm(flat_px - g - t[:, None] * v, axis=1) > off_axis
    if off.mean() > max_off:
        return False
    t = t.reshape(img.shape[:2])
    mixed = (t > 0.1) & (t < 0.9)
    if not mixed.any():
        return True
    beside_ground = ndi.binary_dilation(t <= 0.1, structure=np.ones((3, 3), bool))
    return float(np.mean(~beside_ground[mixed])) <= max_inner
