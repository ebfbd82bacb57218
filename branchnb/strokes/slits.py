"""Narrow pockets of background closed off inside the object after an edit (beyond the paper).

Where an edit lays two parts side by side (a tine added beside its
neighbour on a small outlined antler), their anti-aliased rims touch
farther out and close the slit between them into a pocket of background
enclosed by the object: a white sliver lined with ink. A crack torn into
flesh (a white tick in a palm under a bent finger's crotch) is another.
The pinhole pass (:func:`~branchnb.strokes.outline.fill_pinholes`) sees
enclosed regions at the alpha <= 0.98 level only, and these still reach the
background round the object through their half-transparent rims.

:func:`_select_slits` finds the pockets enclosed at the silhouette's level
(alpha > 0.5) that are narrow (none of their pixels more than the outline's
width + 1 px from the silhouette) and small, and keeps those that are
defects: on an object with a detected outline all of them; otherwise those
lined with ink and reaching a joint (two parts touching, drawn as a dark
line, :func:`_fill_lined`) and those lined with flesh from deep inside the
source (tears). A pocket the source has itself stays, and so does a slit
lined with flesh from the parts' rims on an object with no outline: there
it is all that keeps the two parts apart.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

__all__: list[str] = []

_EIGHT = np.ones((3, 3), bool)

#: A slit holds at most this many times a pinhole's area ``(2 width + 2) ** 2`` (as a crack does).
_AREA = 4.0
#: A slit (see :func:`_enclosed_slits`) is at most this many px wider (half width, from its
#: middle to the nearest pixel of alpha > 0.5) than the outline.
_SLIT = 1.0
#: A slit is lined with ink where its lining is this much darker (luminance) than the flesh.
_LINED = 0.15


def _enclosed_slits(alpha: np.ndarray, width: float, rgb: np.ndarray | None = None) -> np.ndarray | None:
    """Narrow background pockets enclosed at the silhouette's level, lined with ink (None if none).

    An enclosed region of alpha <= 0.5 (4-connected, not reaching the box's
    border) of at most :data:`_AREA` ``(2 width + 2) ** 2`` px whose open
    pixels all lie within ``width +`` :data:`_SLIT` px of the silhouette
    (alpha > 0.5), lined with ink (a quarter of the silhouette's pixels within
    2 px of it darker by :data:`_LINED` than the median of the pixels deeper
    than ``width + 2`` px inside), with the half-transparent pixels (alpha <=
    0.98) round it: the slit left between a new tine and its neighbour on an
    outlined object where their rims touch farther out (a 150 px antler:
    24-59 px of background enclosed). Pockets wider than that (a finger bent
    into a loop) and pockets lined with flesh (an object with no outline: the
    slit is all that keeps the two parts apart) are not slits. Without
    ``rgb`` (straight colours) the lining is not looked at.

    Examples
    --------
    >>> a = np.zeros((20, 20), np.float32); a[3:17, 3:17] = 1.0; a[6:14, 9] = 0.0
    >>> int(_enclosed_slits(a, 1.0).sum())
    8
        """
    obj = alpha > 0.5
    rs, cs = np.nonzero(obj)
    if not len(rs):
        return None
    r0, r1, c0, c1 = rs.min(), rs.max() + 1, cs.min(), cs.max() + 1
    lab, n = ndi.label(~obj[r0:r1, c0:c1])
    if n == 0:
        return None
    sizes = np.bincount(lab.ravel())
    edge = np.unique(np.concatenate([lab[0], lab[-1], lab[:, 0], lab[:, -1]]))
    cand = sizes <= _AREA * (2.0 * float(width) + 2.0) ** 2
    cand[0] = False
    cand[edge] = False
    if not cand.any():
        return None
    depth = ndi.distance_transform_edt(lab > 0)
    widest = np.asarray(ndi.maximum(depth, lab, index=np.arange(len(sizes))))
    cand &= widest <= float(width) + _SLIT
    if not cand.any():
        return None
    a = alpha[r0:r1, c0:c1]
    if rgb is not None:
        lum = rgb[r0:r1, c0:c1] @ np.array([0.299, 0.587, 0.114], np.float32)
        inner = ndi.distance_transform_edt(obj[r0:r1, c0:c1]) > float(width) + 2.0
        if not inner.any():
            return None
        flesh = float(np.median(lum[inner]))
    out = np.zeros(alpha.shape, bool)
    for i in np.flatnonzero(cand):
        slit = lab == i
        if rgb is not None:
            # (the silhouette's pixels round it, half-transparent ones too: on a small
            # object the one-pixel ink lining is the anti-aliased rim itself)
            lining = ndi.binary_dilation(slit, structure=np.ones((3, 3), bool), iterations=2) & obj[r0:r1, c0:c1]
            if not lining.any() or float(np.percentile(lum[lining], 25)) > flesh - _LINED:
                continue
        slit |= ndi.binary_dilation(slit, structure=np.ones((3, 3), bool)) & (a <= 0.98)
        out[r0:r1, c0:c1] |= slit
    return out if out.any() else None


def _select_slits(layer: np.ndarray, width: float, *, outlined: bool = False,
                  zones: np.ndarray | None = None, depth: np.ndarray | None = None,
                  source_alpha: np.ndarray | None = None) -> tuple:
    """``(lined, torn)``: the slits of ``layer`` (straight RGBA) to fill with their lining
    (:func:`_fill_lined`) and those to fill like pinholes (each a bool mask, or None).

    ``outlined``: every slit, as ``lined`` (the caller fills them like pinholes and
    repaints the lining as stale outline). Otherwise ``lined``: slits lined with ink
    reaching into ``zones`` (anywhere if None); ``torn``: slits whose lining's median
    source ``depth`` (per result pixel) exceeds ``width + 2``. Slits within ``2 width + 2``
    px of a slit of ``source_alpha`` (any, if the canvas is not the source's size) are
    the source's own and left.
    """
    alpha = layer[..., 3]
    torn = None
    if not outlined and depth is not None:
        every = _enclosed_slits(alpha, width)
        if every is not None:
            lab, n = ndi.label(every, structure=_EIGHT)
            lining = ndi.binary_dilation(every, structure=_EIGHT, iterations=2) & ~every & (alpha > 0.5)
            # (each lining pixel to its slit: the label of the nearest slit pixel)
            _, (iy, ix) = ndi.distance_transform_edt(lab == 0, return_indices=True)
            med = ndi.median(depth, np.where(lining, lab[iy, ix], 0), index=np.arange(1, n + 1))
            deep = np.r_[False, np.asarray(med, float) > float(width) + 2.0]
            torn = _some(deep[lab] & every)
    lined = _enclosed_slits(alpha, width, None if outlined else layer[..., :3])
    if lined is not None and not outlined and zones is not None:
        lab, _ = ndi.label(lined, structure=_EIGHT)
        lined = _some(np.isin(lab, np.unique(lab[zones & lined])) & lined)
    if torn is not None and lined is not None:
        torn = _some(torn & ~lined)
    if (lined is not None or torn is not None) and source_alpha is not None:
        own = _enclosed_slits(source_alpha, width)
        if own is not None:
            if own.shape != alpha.shape:
                return None, None
            near = ndi.binary_dilation(own, iterations=int(np.ceil(2.0 * float(width) + 2.0)))
            lined, torn = _not_near(lined, near), _not_near(torn, near)
    return lined, torn


def _some(mask: np.ndarray) -> np.ndarray | None:
    return mask if mask.any() else None


def _not_near(mask: np.ndarray | None, near: np.ndarray) -> np.ndarray | None:
    """``mask`` without its (8-connected) pieces touching ``near``."""
    if mask is None:
        return None
    lab, _ = ndi.label(mask, structure=_EIGHT)
    return _some(np.isin(lab, np.unique(lab[near]), invert=True) & mask)


def _fill_lined(out: np.ndarray, layer: np.ndarray, lined: np.ndarray, width: float) -> None:
    """Fill the slits ``lined`` of ``layer`` into ``out`` (in place): open pixels (alpha
    <= 0.5) take their nearest silhouette pixel's colour (the lining: the ink of a thin
    outline is the anti-aliased rim, half transparent), the middle of a slit wider than
    2 px the flesh beyond (two outlined parts touching, each with its own outline, not a
    band of ink); the slit's rim is made opaque as it is.

    Notes
    -----
    Beyond the paper (and the rule above): where the ink lining a slit is itself
    :data:`_THICK` px or more thick (:func:`_lining_thickness`: a heavy outline on
    a small object, too thin for :func:`~branchnb.strokes.outline.outline_style`
    to find at 150-200 px), each lining already is a line keeping the two parts
    apart; filled with that ink too, the slit and its two linings read as one
    dark band three outline widths wide (a pocket of ink between a new tine and
    its neighbour). Its open pixels then take the colour of the nearest flesh
    (opaque pixels not darker than the flesh by :data:`_LINED`), all but those
    within the lining's thickness of the background round the object (the
    outline carried on across the slit's mouth).
    """
    a = layer[..., 3]
    fill = lined & (a <= 0.5)
    out[lined & (a > 0.5), 3] = 1.0
    if not fill.any():
        return
    rs, cs = np.nonzero(fill)
    g = int(np.ceil(2.0 * float(width) + 2.0)) + 1 + _THICK_REACH
    r0, r1 = max(rs.min() - g, 0), rs.max() + g + 1
    c0, c1 = max(cs.min() - g, 0), cs.max() + g + 1
    hs = fill[r0:r1, c0:c1]
    sub = layer[r0:r1, c0:c1]
    _, (ir, ic) = ndi.distance_transform_edt(~((a[r0:r1, c0:c1] > 0.5) & ~hs), return_indices=True)
    win = out[r0:r1, c0:c1]
    win[hs, :3] = sub[ir[hs], ic[hs], :3]
    win[hs, 3] = 1.0
    mid = hs & (ndi.distance_transform_edt(hs) > 1.0)
    if mid.any():
        _, (jr, jc) = ndi.distance_transform_edt(~(a[r0:r1, c0:c1] > 0.98), return_indices=True)
        win[mid, :3] = sub[jr[mid], jc[mid], :3]
    flesh_lum = _flesh_lum(layer, width)
    if flesh_lum is not None:
        _flesh_fill(win, sub, lined[r0:r1, c0:c1], hs, flesh_lum)


def _flesh_lum(layer: np.ndarray, width: float) -> float | None:
    """Median luminance of ``layer``'s pixels deeper than ``width + 2`` px inside its silhouette
    (the flesh; None if there are none), as :func:`_enclosed_slits` measures it."""
    obj = layer[..., 3] > 0.5
    rs, cs = np.nonzero(obj)
    if not len(rs):
        return None
    box = (slice(rs.min(), rs.max() + 1), slice(cs.min(), cs.max() + 1))
    inner = ndi.distance_transform_edt(np.pad(obj[box], 1))[1:-1, 1:-1] > float(width) + 2.0
    if not inner.any():
        return None
    lum = layer[box][..., :3] @ np.array([0.299, 0.587, 0.114], np.float32)
    return float(np.median(lum[inner]))


#: A slit's ink lining this many px thick or more is a line of its own (see :func:`_fill_lined`).
_THICK = 2
#: How far (px) from a slit its lining's thickness is looked for.
_THICK_REACH = 6


def _lining_thickness(dark: np.ndarray, slit: np.ndarray, obj: np.ndarray) -> int:
    """Thickness (px) of the dark band round ``slit``: the last ring (1 px steps out from
    the slit, within ``obj``) of which at least half is ``dark``, counting from the first."""
    d = ndi.distance_transform_edt(~slit)
    k = 0
    for ring in range(1, _THICK_REACH + 1):
        on = obj & (d > ring - 1) & (d <= ring)
        if not on.any() or 2 * int((dark & on).sum()) < int(on.sum()):
            break
        k = ring
    return k


def _flesh_fill(win: np.ndarray, layer: np.ndarray, lined: np.ndarray, hs: np.ndarray, flesh_lum: float) -> None:
    """Repaint the open pixels ``hs`` of slits with a thick ink lining with the nearest
    flesh's colour (in place, ``win`` the output window over ``layer``; ``flesh_lum`` the
    object's median luminance deep inside; see :func:`_fill_lined`)."""
    a = layer[..., 3]
    obj = a > 0.5
    lum = layer[..., :3] @ np.array([0.299, 0.587, 0.114], np.float32)
    flesh = (a > 0.98) & ~lined & (lum > flesh_lum - _LINED)
    if not flesh.any():
        return
    dark = obj & ~lined & (lum <= flesh_lum - _LINED)
    # (a slit with its half-transparent rim, which lies on the lining)
    lab, n = ndi.label(lined, structure=_EIGHT)
    paint = np.zeros(hs.shape, bool)
    outside = ~obj & ~lined
    for i in range(1, n + 1):
        whole = lab == i
        slit = whole & hs
        if not slit.any():
            continue
        thick = _lining_thickness(dark, whole, obj & ~lined)
        if thick < _THICK:
            continue
        # (the slit's mouth: its pixels within the lining's thickness of the ground outside
        # carry the outline on across it)
        mouth = ndi.distance_transform_edt(~outside) <= thick if outside.any() else np.zeros_like(slit)
        paint |= slit & ~mouth
    if not paint.any():
        return
    _, (fr, fc) = ndi.distance_transform_edt(~flesh, return_indices=True)
    win[paint, :3] = layer[fr[paint], fc[paint], :3]


def _joint_zones(shape, disks, width: float) -> np.ndarray:
    """Pixels within twice the joint disks' radii + 4 px + the outline's ``width`` of their
    centres (where a slit closed off between a new child and its neighbour starts); ``disks``
    from :func:`~branchnb.strokes.joints.joint_disks`."""
    zones = np.zeros(shape, bool)
    h, w = shape
    for centre, _inv, r, *_ in disks:
        g = 2.0 * float(r) + 4.0 + float(width)
        cx, cy = float(centre[0]), float(centre[1])
        r0, r1 = max(int(cy - g), 0), min(int(cy + g) + 2, h)
        c0, c1 = max(int(cx - g), 0), min(int(cx + g) + 2, w)
        if r0 >= r1 or c0 >= c1:
            continue
        yy, xx = np.mgrid[r0:r1, c0:c1]
        zones[r0:r1, c0:c1] |= (xx - cx) ** 2 + (yy - cy) ** 2 <= g * g
    return zones


#: Widest slit (px) of the source that :func:`_carried_slits` follows onto the result (a
#: closing by a disc of half this radius finds it).
_CARRIED_SLIT = 4
#: A source pixel is open in a slit below this alpha.
_SLIT_OPEN = 0.9
#: Least background px of a source slit (a 2 px notch along a 256-px flower's petal ~30; the
#: corner of a crotch the closing fills 1-8).
_SLIT_LEAST = 16


def _source_slits(source_alpha: np.ndarray) -> np.ndarray | None:
    """Open pixels (alpha < :data:`_SLIT_OPEN`) of the source's slits at most
    :data:`_CARRIED_SLIT` px wide (background inside its silhouette's closing, in pieces of
    at least :data:`_SLIT_LEAST` px, with their anti-aliased sides), as float32, or None
    when it has none."""
    from .parts import _closed_by_disk

    obj = source_alpha > 0.5
    rows, cols = np.flatnonzero(obj.any(axis=1)), np.flatnonzero(obj.any(axis=0))
    if not len(rows):
        return None
    # (on the object's box: the closing adds nothing beyond it)
    box = (slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1))
    r = _CARRIED_SLIT // 2
    closed = _closed_by_disk(np.pad(obj[box], r + 1), r)[r + 1:-r - 1, r + 1:-r - 1]
    # a slit is long: a crotch's corner, which the closing also fills, holds a few px only
    lab, n = ndi.label(closed & ~obj[box], structure=_EIGHT)
    if n == 0:
        return None
    size = np.bincount(lab.ravel(), minlength=n + 1)
    core = (size >= _SLIT_LEAST)[lab] & (lab > 0)
    if not core.any():
        return None
    # (with its anti-aliased sides)
    slit = ndi.binary_dilation(core, structure=_EIGHT) & closed & (source_alpha[box] < _SLIT_OPEN)
    out = np.zeros(source_alpha.shape, np.float32)
    out[box] = slit
    return out


def _carried_slits(index, labels: np.ndarray, placed: list, alpha: np.ndarray) -> np.ndarray | None:
    """Result pixels whose source place (through the patch that laid them) lies in one of the
    source's own slits (:func:`_source_slits`): a notched petal's notch wherever the petal was
    turned or moved (looked up where the result's ``alpha`` is short of opaque). None when the
    source has no slit or no pixel lands in one.

    Beyond the papers (strokes40): the hairline and pinhole passes knew a source's own slits
    only where the result's frame is the source's (the same pixel), so a turned petal's
    notch, a one-pixel line between opaque sides, was closed like a hairline (of 20 gaps of
    a flower whose notched head is turned, 12 were closed).
    """
    slits = index.__dict__.get("_slits", False)
    if slits is False:
        slits = _source_slits(index.premult[:, :, 3])
        index.__dict__["_slits"] = slits
    if slits is None:
        return None
    # (only pixels short of opaque can be a slit's: the object's inside is not looked up)
    h, w = labels.shape
    idx = np.flatnonzero((alpha < _SLIT_OPEN).ravel() & (labels.ravel() >= 0))
    lab = labels.ravel()[idx]
    order = np.argsort(lab, kind="stable")
    idx, lab = idx[order], lab[order]
    bounds = np.searchsorted(lab, np.arange(len(placed) + 1))
    got = np.zeros(h * w, bool)
    for i, pp in enumerate(placed):
        sub = idx[bounds[i]:bounds[i + 1]]
        m = pp.source_map
        if not len(sub) or m is None:
            continue
        ys, xs = np.divmod(sub, w)
        sx = m[0, 0] * xs + m[0, 1] * ys + m[0, 2]
        sy = m[1, 0] * xs + m[1, 1] * ys + m[1, 2]
        # (bilinear: a turned notch's middle falls between the source's pixels)
        got[sub] = ndi.map_coordinates(slits, [sy, sx], order=1, mode="nearest") > 0.5
    got = got.reshape(h, w)
    return got if got.any() else None


def _open_stretches(carried: np.ndarray | None, alpha: np.ndarray) -> np.ndarray | None:
    """The pixels of ``carried`` (:func:`_carried_slits`) where the slit opens onto the
    background round the object in ``alpha`` (and the pixel beside that): a stretch of a
    slit closed off (a notch's tapering inner end, in pieces) is a pinhole, still closed."""
    if carried is None:
        return None
    got = carried.copy()
    lab, _ = ndi.label(alpha < 0.5)
    outside = np.unique(np.r_[lab[0], lab[-1], lab[:, 0], lab[:, -1]])
    open_ = np.isin(lab, outside[outside > 0])
    got &= ndi.binary_dilation(open_ & got, structure=_EIGHT)
    return got if got.any() else None


def _fill_closed_off(layer: np.ndarray, carried: np.ndarray | None, width: float) -> np.ndarray:
    """``layer`` with the background pockets (alpha < 0.5, 4-connected) of at most
    ``(2 width + 2) ** 2`` px that touch ``carried`` (:func:`_carried_slits`) and no longer
    reach the background round the object made opaque (the nearest opaque pixel's colour):
    the stretches of a carried slit the later closings shut off, pinholes otherwise."""
    if carried is None:
        return layer
    lab, n = ndi.label(layer[..., 3] < 0.5)
    if n < 2:
        return layer
    size = np.bincount(lab.ravel(), minlength=n + 1)
    outside = np.unique(np.r_[lab[0], lab[-1], lab[:, 0], lab[:, -1]])
    small = size <= (2.0 * float(width) + 2.0) ** 2
    small[outside] = False
    small[0] = False
    touch = np.zeros(n + 1, bool)
    touch[np.unique(lab[ndi.binary_dilation(carried, structure=_EIGHT)])] = True
    hole = (small & touch)[lab]
    if not hole.any():
        return layer
    out = layer.copy()
    _, (iy, ix) = ndi.distance_transform_edt(layer[..., 3] < 0.98, return_indices=True)
    out[hole, :3] = layer[iy[hole], ix[hole], :3]
    out[hole, 3] = 1.0
    return out
