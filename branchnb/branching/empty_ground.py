"""The part of a line mask's frame its lines leave empty (issue 23, beyond the paper).

:func:`~branchnb.branching.example_domain` leaves it out of a one-region line mask's domain, and
:func:`~branchnb.branching.fit_model` reads it as ground, not as a coast or a hole
(``StructureModel.ground``, :func:`.domains._ground`). Split from :mod:`.backgrounds`.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

EMPTY_DISK = 0.2     #: a disk this share of the frame's short side fits in the empty part
EMPTY_MARGIN = 0.75  #: the domain reaches this share of the disk's radius beyond the outermost lines
EMPTY_AREA = 0.05    #: an empty part covers at least this share of the frame


def _empty_part(lines) -> np.ndarray:
    """The part of the frame a line network leaves empty: where a large line-free disk fits.

    The union of the disks of radius :data:`EMPTY_DISK` x the frame's short side that lie inside
    the frame and touch no line (the complement of the lines' closing, the frame counted as a
    line), less a margin of :data:`EMPTY_MARGIN` x that radius along the lines; pieces under
    :data:`EMPTY_AREA` of the frame are dropped. Beyond the paper (issue 23): a crack mask that
    covers the lower half of its frame grew over the whole frame (48-75 % of the synthesized
    length more than 8 % of the short side from every example line); a network that fills its
    frame (mud, a retina's vessels, drawn cracks whose cells are smaller than the disk) has none.

    Parameters
    ----------
    lines : (H, W) bool array_like
        The network's pixels.

    Returns
    -------
    (H, W) bool ndarray
        The empty part (all False when there is none).

    Examples
    --------
    >>> m = np.zeros((100, 150), bool); m[70, 5:145] = True; m[60:95, 40] = True
    >>> e = _empty_part(m)
    >>> bool(e[10, 75]), bool(e[70, 75]), bool(e[85, 75])
    (True, False, False)
    """
    lines = np.asarray(lines, bool)
    H, W = lines.shape
    out = np.zeros((H, W), bool)
    if not lines.any():
        return out
    R = EMPTY_DISK * min(H, W)
    pad = np.pad(lines, 1, constant_values=True)        # the frame counts as a line: disks stay inside
    d = ndi.distance_transform_edt(~pad)
    centres = d > R
    if not centres.any():
        return out
    empty = (ndi.distance_transform_edt(~centres) <= R)[1:-1, 1:-1]    # the union of the empty disks
    empty &= ndi.distance_transform_edt(~lines) > EMPTY_MARGIN * R
    lab, n = ndi.label(empty)
    if n:
        size = np.bincount(lab.ravel(), minlength=n + 1)
        keep = size >= EMPTY_AREA * H * W
        keep[0] = False
        out = keep[lab]
    return out


BAND_QUANTILE = 0.9   #: the strand spacing is this quantile of the line-to-line distances
BAND_HITS = 0.3       #: ... read when at least this share of the rays' start points meet another line
BAND_RAYS = 16        #: directions of the rays from each start point
BAND_POINTS = 2000    #: at most this many start points (skeleton pixels, evenly spread)
BAND_MIN = 8.0        #: never a band narrower than this (pixels) beyond the lines
BAND_WIDTH = 1.0      #: the band reaches this x the strand spacing beyond the lines
BAND_DEPTH = 0.16     #: a band's deepest point lies within this x the short side of its edge


def _strand_spacing(lines: np.ndarray, reach: float) -> float | None:
    """The line-to-line distance of a line network (pixels), or None when its lines are far apart.

    From evenly spread skeleton pixels, rays in :data:`BAND_RAYS` directions walk until they meet
    another line (after crossing at least 2 ground pixels) within ``reach``; each point's shortest
    hit is its distance to the neighbouring strand, and the spacing is the :data:`BAND_QUANTILE`
    quantile of those (the widest gaps between interlaced strands, not the crossings).
    """
    from skimage.morphology import skeletonize

    H, W = lines.shape
    ys, xs = np.nonzero(skeletonize(lines))
    if len(xs) < 8 or reach < 2:
        return None
    sel = np.linspace(0, len(xs) - 1, min(len(xs), BAND_POINTS)).astype(np.int64)
    xs, ys = xs[sel].astype(np.float64), ys[sel].astype(np.float64)
    a = np.linspace(0, 2 * np.pi, BAND_RAYS, endpoint=False)
    steps = np.arange(1, int(reach) + 1, dtype=np.float64)
    xi = np.rint(xs[:, None, None] + np.cos(a)[None, :, None] * steps).astype(np.int64)
    yi = np.rint(ys[:, None, None] + np.sin(a)[None, :, None] * steps).astype(np.int64)
    inside = (xi >= 0) & (xi < W) & (yi >= 0) & (yi < H)
    # a ray ends at the frame: everything after its first step outside is outside
    inside = np.minimum.accumulate(inside, axis=2)
    on = np.zeros(xi.shape, bool)
    on[inside] = lines[yi[inside], xi[inside]]
    hit = on & (np.cumsum(~on & inside, axis=2) >= 2)      # left its own line first
    any_hit = hit.any(2)
    first = np.where(any_hit, hit.argmax(2) + 1.0, np.inf).min(1)
    ok = np.isfinite(first)
    if ok.mean() < BAND_HITS:
        return None
    return float(np.quantile(first[ok], BAND_QUANTILE))


def _line_domain(lines) -> np.ndarray:
    """Where a line mask's branches may grow: the frame less its empty part, and within the strand
    spacing of the lines.

    Beyond the paper (issue 23): a vine ornament drawn along two borders of its frame (an L-shaped
    band of interlaced strands) kept everything within :data:`EMPTY_MARGIN` x the empty disk
    (0.15 x the short side) of a line, a region much wider than the band, and the output filled it
    as a bush of short branches. The domain is also held to the band the lines occupy: within the
    example's own line-to-line distance (:func:`_strand_spacing`) of a line. A network that fills its
    frame (mud, drawn cracks) lies within its spacing everywhere and keeps the whole frame; strands
    too far apart for a spacing (a lone line) keep the former rule.

    Parameters
    ----------
    lines : (H, W) bool array_like
        The network's pixels.

    Returns
    -------
    (H, W) bool ndarray

    Examples
    --------
    >>> m = np.zeros((200, 200), bool); m[20, :] = True; m[40, :] = True
    >>> d = _line_domain(m)
    >>> bool(d[30, 100]), bool(d[55, 100]), bool(d[120, 100])
    (True, True, False)
    """
    lines = np.asarray(lines, bool)
    dom = ~_empty_part(lines)
    if not lines.any():
        return dom
    H, W = lines.shape
    s = _strand_spacing(lines, EMPTY_MARGIN * EMPTY_DISK * min(H, W))
    if s is None:
        return dom
    band = dom & (ndi.distance_transform_edt(~lines) <= max(BAND_WIDTH * s, BAND_MIN))
    # a network that covers an area (cracks, vessels, a mesh) keeps the former rule: only a band
    return band if _is_band(band) else dom


def _is_band(domain) -> bool:
    """Is ``domain`` a band: no point deeper than :data:`BAND_DEPTH` x the frame's short side?"""
    domain = np.asarray(domain, bool)
    if not domain.any() or domain.all():
        return False
    depth = ndi.distance_transform_edt(np.pad(domain, 1))   # the frame is no edge of a band
    return bool(depth.max() <= BAND_DEPTH * min(domain.shape))


#: A band's strands (one-pen line art, ``_Grower.strands``) keep within this share of the example's
#: strand spacing of the example's lines (:func:`_strand_core`).
CORE_SHARE = 1.0
#: Margin of the core past the closed lines, in (pen + 2 px) (:func:`_strand_core`). 1 (branching66) left
#: a strand room to run along the core's edge outside the swing (an L band's root 3-4 px beside it at
#: 256 px: 0.16 of that core lay outside the swept band); 0: the closed lines themselves (branching70).
CORE_MARGIN = 0.0


def _strand_core(example, domain) -> np.ndarray | None:
    """Where a band's strands run: the pixels of ``domain`` ((H, W) bool) in the closing of the example's
    lines by a disk of :data:`CORE_SHARE` x the strand spacing (:func:`_strand_spacing`), widened by
    :data:`CORE_MARGIN` x (the pen + 2 px), or None (no spacing, or no core in ``domain``).

    Beyond the paper (issue 23, branching66): the band domain (:func:`_line_domain`) reaches a whole
    spacing beyond the outermost strand to give growth room, and an ornament's margin to its frame is
    part of it. Space colonization finds that margin empty and draws strands and their children into
    it: synthesized interlaced bands ran 0.15-0.35 of their length outside the band the example's
    strands sweep, children pointing off the band to the frame. A closing fills the eyes between
    interlaced strands (and the wedges between a vine's stem and side strands) but adds nothing beyond
    the outermost strands: the swept band with a pen's margin.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> t = np.arange(0.0, 200.0)
    >>> s = Structure([Branch(np.c_[t, np.full(200, 20.0)], 1.0), Branch(np.c_[t, np.full(200, 40.0)], 1.0)])
    >>> core = _strand_core(s, np.ones((200, 200), bool))
    >>> bool(core[30, 100]), bool(core[55, 100]), bool(core[150, 100])
    (True, False, False)
    """
    import cv2

    dom = np.asarray(domain, bool)
    H, W = dom.shape
    lines = np.zeros((H, W), np.uint8)
    pen = 1.0
    for b in example.branches:
        p = np.asarray(b.points, np.float64)
        if len(p) >= 2:
            cv2.polylines(lines, [np.round(p * 4).astype(np.int32)], False, 1, 3, cv2.LINE_8, 2)
            pen = max(pen, float(np.median(b.thickness)))
    lines = lines > 0
    s = _strand_spacing(lines, EMPTY_MARGIN * EMPTY_DISK * min(H, W))
    if s is None:
        return None
    # the closing of the lines by a disk of radius ``CORE_SHARE * s``: the eyes between interlaced strands
    # and a vine's side strands filled, nothing beyond the outermost strands (the frame is no edge)
    r = CORE_SHARE * s
    pad = int(np.ceil(r)) + 2
    near = ndi.distance_transform_edt(~np.pad(lines, pad)) <= r
    closed = (ndi.distance_transform_edt(near) > r - 0.5)[pad:-pad, pad:-pad]
    core = dom & (ndi.distance_transform_edt(~(closed | lines)) <= CORE_MARGIN * (pen + 2.0))
    return core if core.any() else None


def _band_width(mask: np.ndarray) -> float:
    """The width (pixels) of a band ``mask`` ((H, W) bool): twice the median depth on its medial axis."""
    from skimage.morphology import medial_axis

    axis, depth = medial_axis(np.asarray(mask, bool), return_distance=True)
    return 2.0 * float(np.median(depth[axis])) if axis.any() else 0.0


def _painted_core(example_domain, example_core, domain) -> np.ndarray | None:
    """The core of a band ``domain`` ((H, W) bool) the user drew for a band ornament: the middle strip of
    it as wide, in proportion, as the example's strands' band (``example_core``,
    :func:`_strand_core`) is in the example's band domain (``example_domain``); None when it leaves
    nothing.

    Beyond the paper (issue 23, branching70): the example's lines say where its strands run only in
    its own domain; in a band the user paints the strands ran anywhere in it, children out to its
    edges (0.3-0.7 of the length outside the painted band's middle). The painted band is read like an
    example's band domain (a strand spacing of margin either side): with a band ``q`` = core width /
    domain width in the example, the core is where the depth in ``domain`` is at least ``(1 - q)`` of
    its half-width.

    Examples
    --------
    >>> ex = np.zeros((100, 200), bool); ex[20:60] = True
    >>> core = np.zeros((100, 200), bool); core[30:50] = True
    >>> user = np.zeros((120, 120), bool); user[:, 30:90] = True
    >>> c = _painted_core(ex, core, user)
    >>> bool(c[60, 60]), bool(c[60, 35]), int(c[60].sum())
    (True, False, 32)
    """
    dom = np.asarray(domain, bool)
    if not dom.any():
        return None
    q = min(_band_width(example_core) / max(_band_width(example_domain), 1e-9), 1.0)
    depth = ndi.distance_transform_edt(np.pad(dom, 1))[1:-1, 1:-1]
    half = 0.5 * _band_width(dom)
    core = dom & (depth >= (1.0 - q) * half)
    return core if core.any() else None
