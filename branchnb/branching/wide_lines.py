"""Lines wider than the ridge filter's scales (thick trunks, roots, rivers, vessels), beyond the paper.

The paper's input is clicked by the user; the automatic extraction
(:func:`~branchnb.branching.extraction.extract_structure`) runs a ridge
filter at scales ``sigma_min .. sigma_max`` (1-4 px by default). A line much
wider than ``2 sigma_max`` (a painted root system's 20 px trunk at 640 px, a
wide river, a vessel at high resolution) has a flat interior the filter does
not see: it answers on the line's two edges or not at all, so the trunk
is missing and each root starts where its children leave it.

Running the same filter at coarser scales is no cure (tried, issue 23):
there, clusters of thin roots merge into wide blobs that look like trunks.
A wide line is instead checked against the image itself: it is *uniformly
dark* (or bright) across its whole width, against a background estimated
far wider than it. :func:`wide_line_mask` finds those regions cheaply (the
background by a morphological closing / opening on the image shrunk by 4,
the contrast thresholded at half the fine lines' own contrast, a disk
wider than the filter's lines must fit in, the region elongated and of one
piece with the fine ridge mask) and they are added to the ridge mask, so
the skeleton runs along their centre and the radius comes from their own
distance transform.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.morphology import disk as _disk

__all__ = ["wide_line_mask", "frame_reaching_skeleton", "region_arms"]

#: A region is a wide line when a disk of radius ``WIDE_DISK x sigma_max`` fits in it everywhere
#: (opening): narrower lines are the ridge filter's own (a 4-px sigma_max traces lines up to ~12 px).
WIDE_DISK = 1.5
#: ... when its contrast to the far background is at least this share of the fine lines' contrast ...
WIDE_CONTRAST = 0.5
#: ... and when its centre line is at least this many times its mean width (a line, not a patch).
WIDE_ELONGATION = 3.0
#: ... and when it is uniformly dark across: half-way to its edges at least this share of its axis' contrast.
WIDE_FLAT = 0.85

#: Largest median contrast 2-4 px outside a wide line's dark area, as a share of the dark threshold:
#: a line's edge is a step to its ground, a shaded patch's edge fades (see :func:`_sharp_edged`).
WIDE_EDGE = 0.5

#: A wide line's colour continues into a region of its colour (within this, per channel) ...
ARM_TOL = 0.06
#: ... this many times wider (largest inscribed disk) than the line: it is an arm of that region (a sea
#: strait between two islands, 40 px wide on a 768 px map, opening into the sea), not a line.
ARM_WIDER = 2.5


def region_arms(wide: np.ndarray, rgb: np.ndarray) -> np.ndarray:
    """The pieces of the wide-line mask ``wide`` that are arms of a wider flat region of their colour.

    Beyond the paper (issue 23): between two islands of a drawn map the
    sea's strait is darker than the land round it, flat across and walled
    by the coast lines, so :func:`wide_line_mask` took it for a 40-60 px
    river (768-1024 px maps: 7-10 % of the traced length in the sea, radius
    23-39 px). A wide line's own colour does not go on, uninterrupted, into
    a region far wider than the line (:data:`ARM_WIDER`); a strait's does
    (the open sea). Colour, not luminance: a trunk of a crown's luminance
    is still another colour.

    Parameters
    ----------
    wide : (H, W) bool ndarray
        The wide lines (:func:`wide_line_mask`).
    rgb : (H, W, 3) ndarray
        The image's colours in [0, 1], at the mask's scale.

    Returns
    -------
    (H, W) bool ndarray
        The pieces of ``wide`` to drop.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((120, 200, 3)); img[:, 150:] = 0.5; img[50:70, :150] = 0.5   # a sea, an arm of it
    >>> w = np.zeros((120, 200), bool); w[52:68, 10:140] = True
    >>> bool(region_arms(w, img).any()), bool(region_arms(w, np.where(w[..., None], 0.5, 1.0)).any())
    (True, False)
    """
    out = np.zeros(wide.shape, bool)
    lab, n = ndi.label(wide)
    if n == 0:
        return out
    rgb = np.asarray(rgb, np.float32)[..., :3]
    for i in range(1, n + 1):
        piece = lab == i
        colour = np.median(rgb[piece], axis=0)
        same = np.abs(rgb - colour).max(-1) <= ARM_TOL
        comp, _ = ndi.label(same)
        ids = np.unique(comp[piece & same])
        ids = ids[ids > 0]
        if not ids.size:
            continue
        region = np.isin(comp, ids)
        width = float(ndi.distance_transform_edt(piece).max())
        if float(ndi.distance_transform_edt(np.pad(region, 1))[1:-1, 1:-1].max()) >= ARM_WIDER * max(width, 1.0):
            out |= piece
    return out


def _far_contrast(gray: np.ndarray, polarity: str, radius: float) -> np.ndarray:
    """How much darker (``polarity="dark"``) or brighter than a background ``radius`` px wide every pixel is.

    The background is a closing (opening) by a disk of ``radius`` computed on the image shrunk
    by up to 4 (cheap at any size), brought back to full size.
    """
    import cv2

    g = np.ascontiguousarray(gray, np.float32)
    h, w = g.shape
    f = 4 if min(h, w) >= 256 else 2 if min(h, w) >= 96 else 1
    small = cv2.resize(g, (max(w // f, 1), max(h // f, 1)), interpolation=cv2.INTER_AREA) if f > 1 else g
    op = cv2.MORPH_CLOSE if polarity == "dark" else cv2.MORPH_OPEN
    bg = cv2.morphologyEx(small, op, _disk(int(np.ceil(radius / f))), borderType=cv2.BORDER_REFLECT)
    # a little smoothing against the ground's noise, both for the background and for the pixel
    bg = cv2.GaussianBlur(bg, (0, 0), 1.0)
    if f > 1:
        bg = cv2.resize(bg, (w, h), interpolation=cv2.INTER_LINEAR)
    gs = cv2.GaussianBlur(g, (0, 0), 1.5)
    return (bg - gs) if polarity == "dark" else (gs - bg)


def wide_line_mask(gray, ridge: np.ndarray, polarity: str, sigma_max: float) -> np.ndarray:
    """The pixels of lines wider than the ridge filter's scales, checked against the image.

    Beyond the paper (see the module's docstring). A pixel is *dark* when
    it is darker (``polarity="dark"``) than a background estimated over a
    disk far wider than any line (radius ``max(6 sigma_max, 0.06 min(H,
    W))``) by at least :data:`WIDE_CONTRAST` x the median contrast of the
    fine ridge mask's centre line (the lines' own contrast, so the
    ground's texture does not pass) and by more than 3 x the ground's
    noise. The dark pixels a disk of radius :data:`WIDE_DISK` x
    ``sigma_max`` fits in (binary opening) form candidate regions; one is a
    wide line when it is elongated (:data:`WIDE_ELONGATION`), covers less
    than a third of the image, touches the fine ridge mask (a wide
    line's children, or its edges, are there) and is uniformly dark across
    (:data:`WIDE_FLAT`; a bright line's glow fades from its core). The black
    outside a fundus's circular view is left out as in the ridge response. A cluster of thin lines
    is not dark between its lines, so it does not merge into one region
    as it does in a coarse ridge filter.

    Parameters
    ----------
    gray : (H, W) array_like
        Luminance in [0, 1] at the working scale.
    ridge : (H, W) bool array_like
        The fine ridge mask (:func:`~branchnb.branching.ridges.ridge_mask`).
    polarity : {"dark", "bright"}
        Lines darker or brighter than their ground.
    sigma_max : float
        The ridge filter's largest scale (pixels).

    Returns
    -------
    (H, W) bool ndarray
        The wide lines' pixels (empty when the image has none).

    Raises
    ------
    ValueError
        If ``gray`` and ``ridge`` are not 2-D arrays of one shape, or ``polarity`` is unknown.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.full((200, 200), 0.8, np.float32); g[:, 90:110] = 0.2     # a 20 px trunk
    >>> g[100:102, 110:190] = 0.2                                         # a thin child
    >>> ridge = np.zeros((200, 200), bool); ridge[99:103, 110:190] = True
    >>> m = wide_line_mask(g, ridge, "dark", 4.0)
    >>> bool(m[100, 100]), bool(m[100, 60])
    (True, False)
    """
    import cv2
    from skimage.morphology import skeletonize

    g = np.asarray(gray, np.float32)
    bw = np.asarray(ridge, bool)
    if g.ndim != 2 or bw.shape != g.shape:
        raise ValueError(f"gray and ridge must be 2-D arrays of one shape, got {g.shape} and {bw.shape}")
    if polarity not in ("dark", "bright"):
        raise ValueError(f"polarity must be 'dark' or 'bright', got {polarity!r}")
    out = np.zeros(g.shape, bool)
    h, w = g.shape
    r_in = max(WIDE_DISK * float(sigma_max), 2.0)
    if not bw.any() or min(h, w) < 8 * r_in:
        return out
    con = _far_contrast(g, polarity, max(6.0 * float(sigma_max), 0.06 * min(h, w)))
    sk = skeletonize(bw)
    if not sk.any():
        return out
    ref = float(np.median(con[sk]))
    ground = ~cv2.dilate(bw.astype(np.uint8), _disk(3)).astype(bool)
    noise = 1.4826 * float(np.median(np.abs(con[ground] - np.median(con[ground])))) if ground.any() else 0.0
    thr = max(WIDE_CONTRAST * ref, 3.0 * noise, 0.02)
    dark = con >= thr
    if polarity == "dark":
        from .ridges import _outside_field_of_view

        # the black outside a fundus's circular view is no line, as the ridge response says too
        dark &= ~_outside_field_of_view(g, 2.5 * float(sigma_max) + 2, float(sigma_max))
    dark = dark.astype(np.uint8)
    core = cv2.morphologyEx(dark, cv2.MORPH_OPEN, _disk(int(np.ceil(r_in)))).astype(bool)
    if not core.any():
        return out
    lab, n = ndi.label(core, np.ones((3, 3), bool))
    dark_lab, _ = ndi.label(dark.astype(bool), np.ones((3, 3), bool))
    touch = np.bincount(lab[cv2.dilate(bw.astype(np.uint8), _disk(2)).astype(bool)], minlength=n + 1)
    area = np.bincount(lab.ravel(), minlength=n + 1)
    rings = None
    for i, sl in enumerate(ndi.find_objects(lab), start=1):
        if sl is None or touch[i] == 0 or area[i] > h * w / 3.0:
            continue
        reg = lab[sl] == i
        axis = skeletonize(reg)
        length = float(axis.sum())
        width = float(area[i]) / max(length, 1.0)
        if length < WIDE_ELONGATION * width or not _flat_across(reg, axis, con[sl]):
            continue
        if rings is None:
            rings = _edge_rings(dark_lab)
        if not _sharp_edged(dark_lab, lab == i, con, thr, rings):
            continue
        out[sl] |= reg
    return out


def _edge_rings(dark_lab: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pixels 2-4 px outside the dark areas ``dark_lab`` (labelled), each with the label of its nearest
    dark area: ``(rows, cols, labels)``. One labelled distance transform serves every candidate region of
    :func:`_sharp_edged` (a full-image transform per candidate cost seconds on a cracked-mud photo)."""
    d, (iy, ix) = ndi.distance_transform_edt(dark_lab == 0, return_indices=True)
    rows, cols = np.nonzero((d >= 2.0) & (d <= 4.0))
    return rows, cols, dark_lab[iy[rows, cols], ix[rows, cols]]


def _sharp_edged(dark_lab: np.ndarray, reg: np.ndarray, con: np.ndarray, thr: float, rings=None) -> bool:
    """Whether the dark area holding ``reg`` ends in a step: a painted line or a river has ground
    next to its edge (contrast under half the threshold 2-4 px outside it, :data:`WIDE_EDGE`); a
    shaded patch of a photograph (a darker stretch of cracked mud round a junction, traced as a
    36 px blob) fades out gradually.

    ``rings`` is :func:`_edge_rings` of ``dark_lab`` (computed here when not given). A ring pixel
    counts for the dark areas holding ``reg`` when one of them is its nearest dark area: the same
    ring as that area's own distance transform gives, but for the pixels closer to another dark
    area, which are that area's edge rather than this one's.
    """
    ids = np.unique(dark_lab[reg])
    ids = ids[ids > 0]
    if not ids.size:
        return False
    rows, cols, near = _edge_rings(dark_lab) if rings is None else rings
    ring = np.isin(near, ids)
    if not ring.any():
        return True
    return float(np.median(con[rows[ring], cols[ring]])) <= WIDE_EDGE * thr


def _flat_across(reg: np.ndarray, axis: np.ndarray, con: np.ndarray) -> bool:
    """Whether the region ``reg`` is as dark (bright) half-way to its edges as on its ``axis``
    (:data:`WIDE_FLAT`): a painted wide line is; the glow around a thin bright line (a lightning
    bolt's halo) fades from its core and is no line of its own (0.76 on the lightning example,
    0.93-1.01 on painted lines 14-30 px wide)."""
    if not axis.any():
        return False
    dt = ndi.distance_transform_edt(np.pad(reg, 1))[1:-1, 1:-1]
    _d, (iy, ix) = ndi.distance_transform_edt(~axis, return_indices=True)
    rel = dt / np.maximum(dt[iy, ix], 1e-6)
    half = reg & (rel >= 0.35) & (rel <= 0.65)
    on_axis = float(np.median(con[axis]))
    if not half.any() or on_axis <= 0:
        return False
    return float(np.median(con[half])) >= WIDE_FLAT * on_axis


def frame_reaching_skeleton(mask: np.ndarray, skel: np.ndarray, near: np.ndarray) -> np.ndarray:
    """``skel`` where the medial axis of ``mask`` runs on to the frame inside the region ``near``.

    A wide line cut by the frame continues beyond it; the skeleton of the
    cut shape stops about a radius short of the frame (or forks into the
    cut's corners), so the root would start inside. With the edge rows
    repeated outward the axis runs on straight to the frame. Only pixels
    in ``near`` (the wide lines, a little dilated) change: thin lines keep
    their skeleton.

    Parameters
    ----------
    mask : (H, W) bool ndarray
        The ridge mask with the wide lines.
    skel : (H, W) bool ndarray
        Its skeleton.
    near : (H, W) bool ndarray
        Where the skeleton may change.

    Returns
    -------
    (H, W) bool ndarray
        The skeleton, reaching the frame along wide lines.
    """
    from skimage.morphology import skeletonize

    m = np.asarray(mask, bool)
    if not near.any():
        return skel
    dt_max = float(ndi.distance_transform_edt(m)[near].max()) if (m & near).any() else 1.0
    pad = int(np.ceil(2.0 * dt_max)) + 2
    full = skeletonize(np.pad(m, pad, mode="edge"))[pad:-pad, pad:-pad] & m
    return np.where(near, full, skel)
