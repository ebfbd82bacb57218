"""Fetching source texture: samples along the target strokes, rotated patches from the source.

Each target stroke is sampled every ``h`` pixels of arc length, and every
control point is a sample too. A sample ``p`` between target control
points ``c_i`` and ``c_i+1`` maps to the point ``p'`` at the same
arc-length fraction between the corresponding source control points
(:meth:`~branchnb.strokes.strokes.StrokePair.source_arc_length`). The
texture around ``p'`` is copied to ``p``, rotated so that the source
stroke direction at ``p'`` lines up with the target stroke direction at
``p`` (:func:`branchnb.core.warp.transfer_patch`, circular patches of
radius ``r``).

Global texture sampling (:mod:`branchnb.strokes.sampling`) may move
``p'`` a little along (and across) the source stroke; the moves are the
*candidates* fetched here.

Patch size
----------
For an RGBA object the patch radius follows the object: ``r(s') = 1.2
w(s') + 4`` where ``w`` is the object's half width across the source
stroke at ``p'`` (measured along the stroke normal, robust to strokes
drawn a little off-centre and to crossings, smoothed along the stroke),
so a patch always spans the whole width plus a margin of background, and
a tapering branch gets smaller patches towards its tip. A fixed
``patch_size`` overrides it; opaque images use 48 px.

Which source pixels a patch may copy
------------------------------------
Each source stroke ``k`` owns the pixels that are (within 2 px) as near
to it as to any other source stroke: a patch fetched on stroke ``k``
never drags along the part of the object another stroke draws (the same
stroke given twice, e.g. to grow two branches from one example branch,
shares its pixels). For an RGBA object it owns them only within a tube
around the stroke: the object's half width ``w`` plus 2 px, and for
background pixels a wider margin (``0.15 w + 3`` px, where the seams can
run around the silhouette). So parts of the object nobody stroked (a
crossing strand, a side branch, the trunk a branch was drawn from) are
not dragged along. Among those, a patch centred at arc length ``s'``
copies only pixels whose nearest stroke point lies within ``1.5 r`` of
``s'``, so it does not copy a part of the same stroke that folds back
nearby (a loop of rope). The transparent pixels around an RGBA object
belong to the patches too: they carry the silhouette, and the graph cut
decides between "object" and "background" like between any two textures.

Stroke ends
-----------
A stroke end lying on another source stroke (a branch drawn from the
trunk) is a *joined* end: the object there belongs to the other stroke,
and it is cut straight across like below. Where the object ends shortly after a stroke end (a tail tip, a branch
tip: the object goes on for less than ``max(2 w, 8)`` px along the
stroke direction, ``w`` the stroke's median half width), the patches copy the tip as it is. Where the stroke
ends in the middle of a longer object (a piece of rope, a branch drawn
from the trunk), the object is cut straight across the stroke at its end
point, within the tube (a tail stroked from inside a wider body takes the
tail's width, not the body's), so the synthesized piece has a clean cut end (hidden inside the
parent for a branch) instead of a round bite out of the source.

The *object region* is where the source is opaque (alpha > 0.5) for an
RGBA image; for an opaque image it is the union of the copied patches.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.graphcut import gradient_magnitude  # the edge strength G of the seam energy
from ..core.image import as_rgba
from ..core.validate import COORD_LIMIT, MAX_COUNT, Array, Int, Real, Shape, check_real, checked
from ._distance import edt as _edt
from .parts import add_bases, find_parts
from .strokes import Stroke, StrokePair

__all__ = ["SourceIndex", "Samples", "Fetched", "source_index", "sample_pair", "fetch",
           "OPAQUE_RADIUS"]

#: A patch copies pixels owned by its stroke within this many radii of its arc length.
_REACH = 1.5
#: A pixel belongs to every stroke within this many pixels of its nearest stroke.
_SHARE = 2.0
#: Opaque pixels are copied up to this far beyond the half width (px).
_OPAQUE_MARGIN = 2.0
#: Alpha above which a pixel counts as part of the object for the tube margins.
_INKED = 0.02
#: Patch radius for opaque images (no silhouette to measure the width from).
OPAQUE_RADIUS = 24.0
#: Longest distance the width measurement walks from the stroke (px).
_MAX_WIDTH = 256


#: Arc lengths and offsets along/across a stroke: finite and within the coordinate limit.
_OFFSETS = Array(ndim=(0, 1), min=-COORD_LIMIT, max=COORD_LIMIT)


def _SPACING(value, name, allow_none):
    """A step ``h > 0`` in pixels, or a function of the arc length giving one."""
    return value if callable(value) else check_real(value, name, 0, 1e5, low_open=True)


def auto_radius(half_width):
    """Patch radius ``r = 1.2 w + 4`` for the object's half width ``w`` (px).

    Parameters
    ----------
    half_width : float or array_like
        Half width ``w`` of the object (pixels) at the sample.

    Returns
    -------
    float64 ndarray
        ``r`` in pixels, of the shape of ``half_width``: the patch reaches 20 %
        past the silhouette plus 4 px of background.

    Examples
    --------
    >>> float(auto_radius(10.0))
    16.0
    """
    return 1.2 * np.asarray(half_width, float) + 4.0


@dataclass
class SourceIndex:
    """The source image prepared for fetching.

    Parameters
    ----------
    premult : (H, W, 4) float32 ndarray
        Premultiplied RGBA (so that interpolation and colour differences
        treat transparent pixels consistently).
    grad : (H, W) float32 ndarray
        Gradient magnitude ``|grad|`` of ``premult`` (Sobel, summed over
        channels): the edge strength of the seam energy.
    object : (H, W) bool ndarray
        The object region (alpha > 0.5; everything for opaque images).
    has_alpha : bool
        Whether the object region came from an alpha channel.
    strokes : list of Stroke
        The source strokes.
    s_map : list of (H, W) float32 ndarray
        Per stroke: arc length of the stroke point nearest to each pixel.
    allowed : list of (H, W) bool ndarray
        Per stroke: the pixels its patches may copy (owned by it, inside
        its tube, not beyond a cut end). Identical strokes share their
        arrays.
    weight : list of (H, W) float32 ndarray
        Per stroke: 1 inside the tube and before cut ends, 0 outside, with
        a one-pixel ramp: the copied pixels are multiplied by it, so the
        edges where a patch cuts through the object are anti-aliased.
    width_s, width : list of (n,) ndarray
        Per stroke: the object's half width ``w`` (px) along the stroke,
        sampled at arc lengths ``width_s`` (smoothed; 0 for opaque images).
    cut_ends : list of (bool, bool)
        Per stroke: whether the object is cut straight at its start / end.
    parts : list of Part
        The parts of the object nobody stroked (:mod:`~branchnb.strokes.parts`),
        each with the stroke it hangs from.
    depth : (H, W) float32 ndarray
        Distance of every object pixel to the background (px; 0 for
        opaque images): where the source's outline is.
    part_mask : (H, W) bool ndarray
        The pixels of all unstroked parts.
    joined : list of (int, int)
        Per stroke: the stroke its start / end lies on (a branch drawn from
        its parent's centre line), or -1.
    edge : list of (n,) ndarray
        Per stroke: the half width of the silhouette itself along the
        stroke (at ``width_s``; median filtered, without the running
        maximum of ``width``).
    side_width : dict
        ``(child, end, parent) -> w``: the parent's own half width on the
        side a joined child leaves it (the silhouette's run along the
        parent's normal on the child's flanks; the tube's width there is
        the child's run when the child leaves along that normal).
    """

    premult: np.ndarray
    grad: np.ndarray
    object: np.ndarray
    has_alpha: bool
    strokes: list
    s_map: list
    allowed: list
    weight: list
    width_s: list
    width: list
    cut_ends: list
    parts: list = field(default_factory=list)
    depth: np.ndarray | None = None
    part_mask: np.ndarray | None = None
    joined: list = field(default_factory=list)
    edge: list = field(default_factory=list)
    side_width: dict = field(default_factory=dict)

    @property
    def shape(self) -> tuple[int, int]:
        return self.object.shape

    def _stroke(self, k: int, name: str = "k") -> None:
        if not 0 <= k < len(self.strokes):
            raise ValueError(f"{name} = {k} is not a source stroke index (there are {len(self.strokes)})")

    @checked(k=Int(0), s=Array(ndim=(0, 1)))
    def half_width(self, k: int, s) -> np.ndarray:
        """Half width ``w`` of the object at arc lengths ``s`` of source stroke ``k`` (px).

        Parameters
        ----------
        k : int
            Source stroke index (into ``strokes``).
        s : float or (M,) array_like
            Arc lengths (pixels) along that stroke.

        Returns
        -------
        float64 ndarray
            ``w`` in pixels, of the shape of ``s``; 0 for opaque images.

        Raises
        ------
        ValueError
            If ``k`` is not a stroke index.
        """
        self._stroke(k)
        return np.interp(np.asarray(s, float), self.width_s[k], self.width[k])

    @checked(k=Int(0), s=Array(ndim=(0, 1)))
    def edge_width(self, k: int, s) -> np.ndarray:
        """Half width of the silhouette at arc lengths ``s`` of source stroke ``k`` (px).

        Parameters
        ----------
        k : int
            Source stroke index.
        s : float or (M,) array_like
            Arc lengths (pixels) along that stroke.

        Returns
        -------
        float64 ndarray
            Of the shape of ``s``.
        """
        self._stroke(k)
        return np.interp(np.asarray(s, float), self.width_s[k], self.edge[k])

    @checked(k=Int(0), s=Array(ndim=(0, 1)), patch_size=Real(0, 1e4))
    def radius(self, k: int, s, patch_size: float = 0.0) -> np.ndarray:
        """Patch radius ``r`` at arc lengths ``s`` of source stroke ``k``.

        ``patch_size > 0`` gives ``r = patch_size / 2`` everywhere;
        otherwise :func:`auto_radius` of the largest half width within
        half a patch radius along the stroke (so that neighbouring
        patches, half a radius apart, cover the whole tube) for RGBA, or
        :data:`OPAQUE_RADIUS` (opaque images).

        Parameters
        ----------
        k : int
            Source stroke index.
        s : (M,) array_like
            Arc lengths (pixels) along that stroke.
        patch_size : float
            Fixed patch diameter (pixels, ``StrokeEditParams.patch_size``); 0 for
            the automatic radius.

        Returns
        -------
        (M,) float64 ndarray

        Examples
        --------
        >>> img = np.zeros((30, 60, 4), np.float32); img[10:20, 5:55] = 1.0
        >>> idx = source_index(img, [Stroke([(5, 15), (50, 15)])])
        >>> idx.radius(0, np.array([20.0])).tolist(), idx.radius(0, np.array([20.0]), 10).tolist()
        ([10.6], [5.0])
        """
        self._stroke(k)
        if patch_size > 0:
            return np.full(s.shape, patch_size / 2.0)
        if not self.has_alpha:
            return np.full(s.shape, OPAQUE_RADIUS)
        wv = self.width[k]
        reach = int(np.ceil(float(auto_radius(wv.max())) / 2.0))
        cover = ndi.maximum_filter1d(wv, size=2 * reach + 1, mode="nearest")
        return auto_radius(np.interp(s, self.width_s[k], cover))


@checked(patch_size=Real(0, 1e4))
def source_index(image, source_strokes: list[Stroke], *, patch_size: float = 0.0) -> SourceIndex:
    """Prepare ``image`` for fetching along ``source_strokes``.

    Parameters
    ----------
    image : (H, W, C) array_like
        The source image (RGBA objects on a transparent background, or opaque).
    source_strokes : list of Stroke
        Inside the image (see :func:`~branchnb.strokes.strokes.make_pairs`).
    patch_size : float
        The patch diameter ``2 r`` the strokes are fetched with (0: automatic):
        what a stroke's patches reach beyond a free end.

    Examples
    --------
    >>> img = np.zeros((30, 60, 4), np.float32); img[10:20, 5:55] = 1.0
    >>> idx = source_index(img, [Stroke([(5, 15), (30, 15)])])
    >>> float(idx.half_width(0, 10.0)), idx.cut_ends[0]
    (5.5, (False, True))
    """
    rgba = as_rgba(image)
    source_strokes = list(source_strokes)
    if not source_strokes:
        raise ValueError("source_strokes is empty: give at least one stroke along the object")
    if not all(isinstance(st, Stroke) for st in source_strokes):
        raise TypeError("source_strokes must be Stroke instances (see make_pairs)")
    h, w = rgba.shape[:2]
    alpha = rgba[:, :, 3]
    has_alpha = bool((alpha < 0.999).any())
    premult = rgba.copy()
    premult[:, :, :3] *= alpha[:, :, None]
    grad = gradient_magnitude(premult).astype(np.float32)
    obj = alpha > 0.5 if has_alpha else np.ones((h, w), bool)
    # Pixels with any coverage: the narrow margin applies to them, so that a
    # silhouette cut by the tube loses its anti-aliased rim with it (no ghost
    # line of faint pixels beyond a gap).
    inked = alpha > _INKED
    # Distance to the background (the image border counts as background).
    edt = _edt(np.pad(obj, 1))[1:-1, 1:-1] if has_alpha else None

    # Widths along every stroke (first: they bound how far from a stroke anything is needed).
    raw = [_raw_width(st, obj, edt) if has_alpha else
           (np.array([0.0, st.length]), np.zeros(2), 0.0) for st in source_strokes]

    # Per distinct stroke: distance and arc length of the nearest stroke point, within
    # what its patches can reach (a patch's radius, a candidate's offset across, the tube).
    keys, uniq = [], {}
    for k, st in enumerate(source_strokes):
        key = st.points.tobytes()
        keys.append(key)
        if key not in uniq:
            wmax = float(raw[k][1].max()) if has_alpha else 0.0
            r = patch_size / 2.0 if patch_size > 0 else (float(auto_radius(wmax)) if has_alpha else OPAQUE_RADIUS)
            uniq[key] = _distance_map(st, (h, w), reach=max(r, 2.0 * wmax) + 24.0)
    d_min = np.min(np.stack([d for d, _ in uniq.values()]), axis=0) if len(uniq) > 1 else None
    # pixel coordinates as a row and a column (broadcast: no full-image grids)
    yy, xx = np.arange(h, dtype=np.float32)[:, None], np.arange(w, dtype=np.float32)[None, :]

    # Ends joined to another stroke, cut ends.
    joined = _joined_ends(source_strokes, raw, keys)
    cuts = [tuple(joined[k][end] >= 0 or _is_cut(st, obj, raw[k][2], end) for end in (0, 1))
            for k, st in enumerate(source_strokes)]
    widths = [_smooth_width(raw[k][1], raw[k][2], _wide_ends(st, cuts[k], edt, raw[k][2])) if has_alpha
              else raw[k][1] for k, st in enumerate(source_strokes)]
    width_s = [raw[k][0] for k in range(len(source_strokes))]
    # The silhouette's own half width (median over a few widths, no running maximum).
    edge = [ndi.median_filter(raw[k][1], size=4 * int(raw[k][2]) + 1, mode="nearest") if has_alpha
            else raw[k][1] for k in range(len(source_strokes))]
    # Pass 1, per distinct stroke (and cut ends): the tube proper -- the
    # object pixels within the half width (no margin), up to the cut lines,
    # and a free tip's cap -- and the weights of the cut ends.
    tubes: dict = {}
    dboxes: dict = {}  # per distinct stroke: the box of its distance map
    for k, st in enumerate(source_strokes):
        key = (keys[k], cuts[k])
        if key in tubes:
            continue
        d, s_map = uniq[keys[k]]
        ws, wv = width_s[k], widths[k]
        endw = np.ones((h, w), np.float32)
        for end, is_cut in enumerate(cuts[k]):
            if is_cut:
                endw *= _beyond_weight(st, end, s_map, xx, yy)
                if has_alpha:
                    # The cut line itself: only across the tube.
                    w_end = float(np.interp(0.0 if end == 0 else st.length, ws, wv))
                    endw *= _end_tube(st, end, s_map, xx, yy, w_end, inked)
        tube = interior = core = None
        if has_alpha:
            # the half width at every pixel's nearest stroke point (beyond the distance
            # map's box the arc length is 0: the first width)
            tube = np.full((h, w), np.float32(np.interp(0.0, ws, wv)), np.float32)
            box = dboxes.setdefault(keys[k], _reach_box(d))
            tube[box] = np.interp(s_map[box], ws, wv)
            interior = (s_map > 1.0) & (s_map < st.length - 1.0)
            # beyond a free end the object may go on for a tip's length (see _is_cut), as far
            # as the patch at the end reaches (the rest is a part)
            reach = patch_size / 2.0 if patch_size > 0 else auto_radius(tube)
            cap = np.minimum(np.maximum(2.0 * tube, 8.0) + 2.0, reach - 2.0)
            core = inked & (endw > 0.5) & (d <= np.where(interior, tube + 0.5, cap))
            core[box] = _connected_to_stroke(core[box], d[box] <= 0.5 * tube[box] + 1.5)
        tubes[key] = (d, s_map, tube, interior, endw, core)
    tube_keys = list(tubes)
    beyond_cap = _children_beyond_caps(source_strokes, keys, cuts, joined, tubes) if has_alpha else {}
    near_parent, side_width = {}, {}
    if has_alpha:
        for k, st in enumerate(source_strokes):
            for end, parent in enumerate(joined[k]):
                if parent < 0:
                    continue
                # A branch drawn from its parent's centre line starts at the
                # parent's silhouette: the parent's tube is the parent's.
                pkey = (keys[parent], cuts[parent])
                s_map = tubes[(keys[k], cuts[k])][1]
                reach = max(2.5 * float(tubes[pkey][2].max()) + 4.0,
                            _clear_of(st, end, source_strokes[parent], width_s[parent], widths[parent],
                                      raw[k][2]) + 4.0)
                near = (s_map <= reach) if end == 0 else (s_map >= st.length - reach)
                cut = near & tubes[pkey][5]
                cut, side_width[(k, end, parent)] = _parent_side(
                    cut, st, end, source_strokes[parent], tubes[pkey][1], obj, raw[k][2],
                    tubes[pkey][0], tubes[(keys[k], cuts[k])][0],
                    float(np.interp(source_strokes[parent].project(st.points[:1] if end == 0 else st.points[-1:])[0][0],
                                    width_s[parent], widths[parent])))
                near_parent[k] = near_parent[k] | cut if k in near_parent else cut
        for k, cut in near_parent.items():
            tubes[(keys[k], cuts[k])][5][cut] = False
            # the branch's patches still copy the two pixels of the parent's tube next to
            # the branch, so that the two overlap at the joint (no holes along the seam)
            # (dilated on the cut's box grown by 3 px only: the same pixels on the cut)
            rs, cs = np.nonzero(cut)
            if not len(rs):
                continue
            box = (slice(max(rs.min() - 3, 0), rs.max() + 4), slice(max(cs.min() - 3, 0), cs.max() + 4))
            grown = np.zeros_like(cut)
            grown[box] = ndi.binary_dilation(tubes[(keys[k], cuts[k])][5][box], iterations=2)
            near_parent[k] = cut & ~grown
    parts, part_mask = [], None
    if has_alpha:
        # Object pixels no stroke's tube holds: the parts nobody stroked.
        claimed = np.zeros((h, w), bool)
        for key in tube_keys:
            claimed |= tubes[key][5]
        parts, part_mask = find_parts(alpha, inked, claimed, [tubes[key][5] for key in tube_keys],
                                      [tubes[key][1] for key in tube_keys],
                                      [tubes[key][0] for key in tube_keys])
        for part in parts:  # tube index -> the first stroke with that tube
            part.stroke = [(keys[k], cuts[k]) for k in range(len(source_strokes))].index(
                tube_keys[part.stroke])

    # Pass 2: the pixels each stroke may copy and their weights.
    s_maps, allowed, weights = [], [], []
    done: dict = {}
    for k in range(len(source_strokes)):
        key = (keys[k], cuts[k])
        d, s_map, tube, interior, endw, _ = tubes[key]
        if key not in done:
            others = [tubes[o][5] for o in tube_keys if o[0] != keys[k]] if has_alpha else []
            if d_min is None:
                own = np.ones((h, w), bool)
            else:
                # Pixels in one stroke's tube only are that stroke's; where
                # tubes overlap (junctions, crossings) the nearest stroke's,
                # within _SHARE px (so a part lying near another stroke is not
                # cut along the line half-way between the two strokes).
                own = d <= d_min + _SHARE
                if others:
                    held = np.zeros((h, w), bool)
                    for o in others:
                        held |= o
                    own |= ~held
            if k in near_parent:
                own &= ~near_parent[k]
            if key in beyond_cap:
                own &= ~beyond_cap[key]
            weight = endw.copy()
            if has_alpha:
                # The tube of the object's half width around the stroke, plus
                # a margin: of background (where the seams can run around the
                # silhouette), and of object pixels that nothing else holds
                # (the stroke's own anti-aliased rim) -- not of another
                # stroke's tube or of an unstroked part, so that no stump of
                # a side branch is copied with the stroke. A one-pixel ramp
                # gives cut-off parts an anti-aliased edge. The object beyond
                # the stroke ends is handled by the end weights.
                # (on the distance map's box: beyond it no pixel is interior)
                b = dboxes[keys[k]]
                held = part_mask[b].copy()
                for o in others:
                    held |= o[b]
                margin = np.where(inked[b], np.where(held, 0.0, _OPAQUE_MARGIN), _tube_margin(tube[b]))
                ramp = np.where(tubes[key][5][b], 1.0, np.clip(tube[b] + margin - d[b] + 0.5, 0.0, 1.0))
                weight[b] *= np.where(interior[b], ramp, 1.0).astype(np.float32)
            done[key] = (own & (weight > 0), weight)
        s_maps.append(s_map)
        allowed.append(done[key][0])
        weights.append(done[key][1])
    depth = edt.astype(np.float32) if has_alpha else np.zeros((h, w), np.float32)
    index = SourceIndex(premult, grad, obj, has_alpha, list(source_strokes), s_maps, allowed,
                        weights, width_s, widths, cuts, parts=parts, depth=depth, joined=joined, edge=edge,
                        part_mask=part_mask if part_mask is not None else np.zeros((h, w), bool),
                        side_width=side_width)
    add_bases(parts, index, window=3.0)
    return index


def _children_beyond_caps(strokes, keys, cuts, joined, tubes) -> dict:
    """Per tube with a free end that children join: the pixels of its tip's cap
    (beyond a round cap of the end's half width) inside a child's tube.

    A free end's cap reaches a tip's length beyond the stroke (a pointed tip
    drawn short), but where children start under a rounded end (a figure's legs
    under its body's lower dome) the object beyond the round cap is the
    children's tops: copied with the parent they stay put while the children
    turn, and peek out below the parent as teeth. They are taken out of the
    parent's tube (its core and the pixels it may copy), so the children's
    patches copy them and turn them with the children. Beyond the paper.
    The cores in ``tubes`` are changed in place.
    """
    out: dict = {}
    for k, st in enumerate(strokes):
        key = (keys[k], cuts[k])
        d, s_map, tube, interior, _, core = tubes[key]
        free_ends = [end for end in (0, 1) if not cuts[k][end]]
        if not free_ends:
            continue
        kids = [j for j in range(len(strokes)) if keys[j] != keys[k] and k in joined[j]]
        if not kids:
            continue
        at_cap = ~interior & (d > tube + 0.5)
        ends = np.zeros_like(at_cap)
        for end in free_ends:
            ends |= (s_map <= 1.0) if end == 0 else (s_map >= st.length - 1.0)
        at_cap &= ends
        if not at_cap.any():
            continue
        theirs = np.zeros_like(at_cap)
        for j in kids:
            dj, _, tj, _, _, _ = tubes[(keys[j], cuts[j])]
            theirs |= dj <= tj + 0.5
        taken = at_cap & theirs
        if taken.any():
            core[taken] = False
            out[key] = out[key] | taken if key in out else taken
    return out


def _reach_box(d: np.ndarray) -> tuple[slice, slice]:
    """The box of the pixels a distance map reaches (``d < 1e6``; see :func:`_distance_map`)."""
    near = d < 1e6
    rows, cols = np.flatnonzero(near.any(axis=1)), np.flatnonzero(near.any(axis=0))
    if not len(rows):
        return slice(0, 0), slice(0, 0)
    return slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1)


def _tube_margin(half_width):
    """Background kept around the silhouette: ``0.15 w + 3`` px."""
    return 0.15 * half_width + 3.0


def _distance_map(stroke: Stroke, shape, reach: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
    """Distance to ``stroke`` and arc length of its nearest point, for every pixel.

    Computed within ``reach`` px of the stroke's bounding box only (farther
    pixels get the distance ``1e6`` and the arc length 0: nothing of the stroke reaches them).
    """
    h, w = shape
    s = np.linspace(0.0, stroke.length, max(2, int(np.ceil(stroke.length * 2)) + 1))
    p = stroke.point_at(s)
    c = np.clip(np.round(p[:, 0]).astype(int), 0, w - 1)
    r = np.clip(np.round(p[:, 1]).astype(int), 0, h - 1)
    pad = int(min(np.ceil(reach), max(h, w))) + 1
    r0, r1 = max(int(r.min()) - pad, 0), min(int(r.max()) + pad + 1, h)
    c0, c1 = max(int(c.min()) - pad, 0), min(int(c.max()) + pad + 1, w)
    seeds = np.ones((r1 - r0, c1 - c0), bool)
    seed_s = np.zeros((r1 - r0, c1 - c0), np.float32)
    seeds[r - r0, c - c0] = False
    seed_s[r - r0, c - c0] = s
    d_in, (ir, ic) = ndi.distance_transform_edt(seeds, return_indices=True)
    if (r0, r1, c0, c1) == (0, h, 0, w):
        return d_in.astype(np.float32), seed_s[ir, ic]
    d = np.full((h, w), 1e6, np.float32)
    s_map = np.zeros((h, w), np.float32)
    d[r0:r1, c0:c1] = d_in
    s_map[r0:r1, c0:c1] = seed_s[ir, ic]
    return d, s_map


def _lookup(mask: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """``mask`` at the nearest pixels of ``pts`` (False outside the image)."""
    h, w = mask.shape
    c = np.round(pts[..., 0]).astype(np.int64)
    r = np.round(pts[..., 1]).astype(np.int64)
    inside = (c >= 0) & (c < w) & (r >= 0) & (r < h)
    out = np.zeros(pts.shape[:-1], bool)
    out[inside] = mask[r[inside], c[inside]]
    return out


def _run_length(inside: np.ndarray) -> np.ndarray:
    """Number of leading True values along the last axis."""
    first_out = np.argmin(inside, axis=-1)
    return np.where(inside.all(axis=-1), inside.shape[-1], first_out)


def _raw_width(stroke: Stroke, obj: np.ndarray, edt: np.ndarray):
    """Half width a patch centred on ``stroke`` needs, every pixel of arc length (unsmoothed).

    Along the normal at each stroke point ``p``, the run of object pixels
    containing ``p`` (or the nearest run, for a stroke drawn a little off
    the object) spans ``[t0, t1]``; a patch centred on ``p`` needs
    ``max(|t0|, |t1|)``. Where the normal runs along another part of the
    object (a crossing), the run is capped by ``2 m + 2`` with ``m`` the
    largest distance to the background within ``edt(p) + 2`` px of ``p``
    (the object's half width at its medial axis, also for a stroke up to
    half a width off-centre).

    Returns the arc lengths, the widths and their median (at least 1).
    """
    s = np.linspace(0.0, stroke.length, max(2, int(np.ceil(stroke.length)) + 1))
    p = stroke.point_at(s)
    n = stroke.normal_at(s, window=3.0)
    t = np.arange(-_MAX_WIDTH, _MAX_WIDTH + 1, dtype=float)
    inside = _lookup(obj, p[:, None, :] + t[None, :, None] * n[:, None, :])
    near = np.argmin(np.where(inside, np.abs(t)[None], np.inf), axis=1)
    # the run of object pixels through the nearest one: from after the last gap
    # before it to before the first gap after it
    col = np.arange(len(t))[None]
    gap = ~inside
    start = np.where(gap & (col < near[:, None]), col, -1).max(axis=1) + 1
    stop = np.where(gap & (col > near[:, None]), col, len(t)).min(axis=1) - 1
    has = inside[np.arange(len(s)), near]
    wv = np.where(has, np.maximum(np.abs(t[start]), np.abs(t[stop])) + 0.5, 0.0)
    wv = np.minimum(wv, 2.0 * _local_max(edt, p) + 2.0)
    return s, wv, float(max(1, int(np.ceil(np.median(wv)))))


def _connected_to_stroke(core: np.ndarray, seed: np.ndarray) -> np.ndarray:
    """The pixels of ``core`` in a piece (8-connected) that touches ``seed`` (the stroke's middle).

    A tube or a free end's cap reaching across the background onto another
    limb (a lizard's hind-leg stroke ending next to its front foot at 100 px)
    would copy that limb with the stroke: a loose piece moved with it. Such
    pixels stay unstroked parts (they follow the stroke they touch).
    """
    n, lab = cv2.connectedComponents(core.view(np.uint8), connectivity=8)
    if n <= 2:
        return core
    hit = np.zeros(n, bool)
    hit[lab[seed & core]] = True
    hit[0] = False
    return hit[lab]


def _parent_side(cut: np.ndarray, child: Stroke, end: int, parent: Stroke, s_map: np.ndarray,
                 obj: np.ndarray, half_width: float, d_parent: np.ndarray,
                 d_child: np.ndarray, tube_width: float) -> tuple[np.ndarray, float]:
    """The pixels of ``cut`` (the parent's tube about a child's joined ``end``) that are the parent's.

    The parent's tube is as wide as the parent is anywhere across it; where a
    limb leaves along the parent's normal (a lizard's thigh at the hip), the
    run measured along that normal is the limb, so the tube swallows the
    limb's base. On the child's side, the parent keeps only the pixels within
    its own silhouette there: the run of object pixels along the normal on
    either flank of the child (``1.5 w + 4`` px away along the parent, ``w``
    the child's half width), the smaller of the two, plus a pixel, and the
    pixels nearer to the parent's stroke (``d_parent``) than to the child's
    (``d_child``) -- only where the parent's tube at the joint (``tube_width``)
    is wider than 1.5 times that run (else the tube is the parent's own
    width and stays). Beyond the paper (which assumes strokes with clean tubes).

    Returns those pixels and the parent's half width on the child's side
    (``inf`` where it cannot be measured).
    """
    s_j, _ = parent.project(child.points[:1] if end == 0 else child.points[-1:])
    s_j = float(s_j[0])
    p_j, n_j = parent.point_at(s_j), parent.normal_at(s_j, window=3.0)
    t = np.arange(0.0, child.length + 0.5, 1.0)
    pts = child.point_at(t if end == 0 else child.length - t)
    side = float(np.sign(np.mean((pts - p_j) @ n_j)))
    if side == 0.0:
        return cut, np.inf
    runs = []
    for s_f in (s_j - 1.5 * half_width - 4.0, s_j + 1.5 * half_width + 4.0):
        if not 0.0 <= s_f <= parent.length:
            continue
        q, n = parent.point_at(s_f), parent.normal_at(s_f, window=3.0)
        ray = _lookup(obj, q[None] + side * np.arange(0.0, _MAX_WIDTH)[:, None] * n[None])
        if ray[0]:
            runs.append(_run_length(ray))
    if not runs or tube_width <= 1.5 * min(runs) + 2.0:
        return cut, np.inf  # a tube about as wide as the parent: the existing rule holds
    rs, cs = np.nonzero(cut)
    if not len(rs):
        return cut, float(min(runs))
    s_px = s_map[rs, cs]
    foot, normal = parent.point_at(s_px), parent.normal_at(s_px, window=3.0)
    signed = side * ((cs - foot[:, 0]) * normal[:, 0] + (rs - foot[:, 1]) * normal[:, 1])
    keep = (signed <= min(runs) + 1.0) | (d_parent[rs, cs] <= d_child[rs, cs])
    out = np.zeros_like(cut)
    out[rs[keep], cs[keep]] = True
    return out, float(min(runs))


def _clear_of(child: Stroke, end: int, parent: Stroke, ws, wv, half_width: float) -> float:
    """How far along ``child`` from its ``end`` its silhouette (``half_width``) is clear of
    the parent's (``wv`` at ``ws``): a branch leaving at a narrow angle runs along its
    parent's side for several parent widths."""
    t = np.arange(0.0, child.length + 0.5, 1.0)
    s_par, d = parent.project(child.point_at(t if end == 0 else child.length - t))
    out = np.flatnonzero(d > np.interp(s_par, ws, wv) + half_width)
    return float(t[out[0]]) if len(out) else 0.0


def _wide_ends(stroke: Stroke, cut, edt: np.ndarray, typical: float) -> tuple[bool, bool]:
    """Per end: cut, or inside a body wider than the stroke's part (its depth over 1.5
    times the typical half width: a starfish's arm stroked from the centre of its disk).

    There the widths are the body's, not the stroke's own: :func:`_smooth_width`
    replaces them as at a cut end, so that the stroke's tube does not swallow the
    body and the parts round it (which then stay unstroked parts, held whole). Else
    whether the median filter trimmed that bulge depended on the image's size
    (kept at 400 px, swallowed at 150). Beyond the paper.
    """
    h, w = edt.shape
    out = []
    for end in (0, 1):
        x, y = np.rint(stroke.points[0 if end == 0 else -1]).astype(int)
        deep = 0 <= x < w and 0 <= y < h and float(edt[y, x]) > 1.5 * typical
        out.append(bool(cut[end] or deep))
    return out[0], out[1]


def _smooth_width(wv: np.ndarray, typical: float, cut) -> np.ndarray:
    """The width profile used for the tube and the patch radius.

    At a cut end (the stroke runs into a longer object: a branch drawn
    from the trunk, a tail drawn from the body) the widths above 1.5
    times the median are the parent's and are replaced by the first width
    of the stroke's own. A median filter along the stroke then removes
    short outliers, a running maximum keeps the patches over local bulges
    and a Gaussian smooths the profile, so that the tube's edge has no
    steps where the width changes.
    """
    wv = wv.copy()
    for end in (0, 1):
        if cut[end]:
            w = wv if end == 0 else wv[::-1]
            free = np.flatnonzero(w <= 1.5 * typical)
            if len(free):
                w[:free[0]] = w[free[0]]
    n = int(typical)
    wv = ndi.median_filter(wv, size=2 * n + 1, mode="nearest")
    wv = ndi.maximum_filter1d(wv, size=2 * n + 1, mode="nearest")
    return ndi.gaussian_filter1d(wv, sigma=typical / 2.0, mode="nearest").astype(float)


def _joined_ends(strokes, raw, keys) -> list[tuple[int, int]]:
    """Per stroke and end: the (different) stroke the end lies on, within half its local width + 3 px, or -1.

    Two ends meeting (each on the other near its end) join as in
    :func:`~branchnb.strokes.junctions.find_junctions`: the later-drawn stroke
    is the child.
    """
    out = []
    for k, st in enumerate(strokes):
        flags = []
        for end in (0, 1):
            q = st.points[0 if end == 0 else -1][None]
            hit, best = -1, np.inf
            for j, other in enumerate(strokes):
                if j == k or keys[j] == keys[k]:
                    continue
                s, d = other.project(q)
                tol = 0.5 * float(np.interp(s[0], raw[j][0], raw[j][1])) + 3.0
                if d[0] <= tol and 1.0 < s[0] < other.length - 1.0 and d[0] < best:
                    if j > k and min(s[0], other.length - s[0]) <= tol:
                        # two ends meeting (a body's end where two legs start): the
                        # later-drawn stroke is the child, as in find_junctions --
                        # else each would be the other's child and the pixels round
                        # the meeting point nobody's (a hole in the body)
                        continue
                    hit, best = j, float(d[0])
            flags.append(hit)
        out.append(tuple(flags))
    return out


def _local_max(edt: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Largest ``edt`` within ``edt(p) + 2`` px of each point ``p``.

    Evaluated every few points (a quarter of the typical half width) and
    interpolated in between: the widths are smoothed over several half
    widths afterwards anyway.
    """
    h, w = edt.shape
    e_all = edt[np.clip(np.round(p[:, 1]).astype(int), 0, h - 1),
                np.clip(np.round(p[:, 0]).astype(int), 0, w - 1)]
    step = max(1, int(np.median(e_all) // 4))
    pick = np.unique(np.r_[np.arange(0, len(p), step), len(p) - 1])
    e0 = e_all[pick]
    rho = int(np.ceil(min(float(e0.max()), _MAX_WIDTH))) + 2
    out = np.zeros(len(pick))
    pts = np.round(p[pick]).astype(np.int64)
    for i, ((x, y), e) in enumerate(zip(pts, e0)):
        # the disk of radius e + 2 (at most rho) about the point, cut to the image
        rr = min(int(np.floor(e + 2.0)), rho)
        r0, r1, c0, c1 = max(y - rr, 0), min(y + rr + 1, h), max(x - rr, 0), min(x + rr + 1, w)
        if r0 >= r1 or c0 >= c1:
            continue
        oy, ox = np.ogrid[r0 - y:r1 - y, c0 - x:c1 - x]
        disk = np.hypot(ox, oy) <= e + 2.0
        out[i] = max(float(edt[r0:r1, c0:c1][disk].max(initial=0.0)), 0.0)
    return np.interp(np.arange(len(p)), pick, out)


def _end_direction(stroke: Stroke, end: int, window: float) -> tuple[np.ndarray, np.ndarray]:
    s_end = 0.0 if end == 0 else stroke.length
    a = float(stroke.angle_at(s_end, window=window))
    u = np.array([np.cos(a), np.sin(a)])
    return stroke.point_at(s_end), (-u if end == 0 else u)


def _is_cut(stroke: Stroke, obj: np.ndarray, half_width: float, end: int) -> bool:
    """Whether the object goes on for more than ``max(2 w, 8)`` px beyond the stroke end.

    ``w`` is the stroke's typical (median) half width.
    """
    p, u = _end_direction(stroke, end, window=max(3.0, half_width))
    limit = max(2.0 * half_width, 8.0)
    t = np.arange(1.0, np.ceil(limit) + 2.0)
    run = _run_length(_lookup(obj, p[None] + t[:, None] * u[None]))
    return bool(run > limit)


def _beyond_weight(stroke: Stroke, end: int, s_map: np.ndarray, xx: np.ndarray,
                   yy: np.ndarray) -> np.ndarray:
    """0 past the straight cut at a stroke end, 1 before it, a one-pixel ramp between.

    "Past" = the nearest stroke point is the end point and the pixel lies
    ahead of it along the stroke direction.
    """
    p, u = _end_direction(stroke, end, window=3.0)
    at_end = s_map <= 1.0 if end == 0 else s_map >= stroke.length - 1.0
    ahead = (xx - p[0]) * u[0] + (yy - p[1]) * u[1]
    return np.where(at_end, np.clip(0.5 - ahead, 0.0, 1.0), 1.0).astype(np.float32)


def _end_tube(stroke: Stroke, end: int, s_map: np.ndarray, xx: np.ndarray, yy: np.ndarray,
              half_width: float, inked: np.ndarray) -> np.ndarray:
    """The tube of :func:`source_index` continued over the pixels nearest to a cut end.

    Those pixels lie on the half plane behind the end point; the tube
    bounds them laterally (distance from the stroke's end line), with the
    same margins and one-pixel ramp as along the stroke.
    """
    p, u = _end_direction(stroke, end, window=3.0)
    at_end = s_map <= 1.0 if end == 0 else s_map >= stroke.length - 1.0
    lateral = np.abs((xx - p[0]) * u[1] - (yy - p[1]) * u[0])
    margin = np.where(inked, _OPAQUE_MARGIN, _tube_margin(half_width))
    ramp = np.clip(half_width + margin - lateral + 0.5, 0.0, 1.0)
    return np.where(at_end, ramp, 1.0).astype(np.float32)


@dataclass
class Samples:
    """Samples along one target stroke.

    Parameters
    ----------
    s : (M,) ndarray
        Target arc lengths.
    points : (M, 2) ndarray
        Target positions ``p``.
    angles : (M,) ndarray
        Target stroke direction at ``p`` (radians).
    source_s : (M,) ndarray
        Nominal source arc lengths of ``p'`` (arc-length fraction between
        control points).
    pinned : (M,) bool ndarray
        Samples at control points (their correspondence is fixed).
    """

    s: np.ndarray
    points: np.ndarray
    angles: np.ndarray
    source_s: np.ndarray
    pinned: np.ndarray

    def __len__(self) -> int:
        return len(self.s)


@checked(spacing=_SPACING, window=Real(0, 1e4))
def sample_pair(pair: StrokePair, spacing, *, window: float) -> Samples:
    """Sample the target stroke of ``pair`` every ``spacing`` pixels (about).

    Each stretch between consecutive target control points is divided
    into the fewest equal-count steps no longer than ``spacing``, so the
    control points themselves are samples (and are pinned).

    Parameters
    ----------
    pair : StrokePair
        The pair whose target stroke is sampled; its control points are
        samples.
    spacing : float or callable
        The step ``h`` (px), or a function of the target arc length
        giving the local step (e.g. half the local patch radius): the
        samples are then spread so that each step is about ``h`` where it
        starts.
    window : float
        Chord half-length for the target directions.

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke, StrokePair
    >>> pair = StrokePair(Stroke([(0, 0), (20, 0)]), Stroke([(0, 0), (0, 10)]))
    >>> smp = sample_pair(pair, 4.0, window=2.0)
    >>> smp.s.tolist(), smp.source_s.tolist()
    ([0.0, 3.3333333333333335, 6.666666666666667, 10.0], [0.0, 6.666666666666667, 13.333333333333334, 20.0])
    """
    ct = pair.control[:, 1]
    if callable(spacing):
        grid = np.linspace(0.0, pair.target.length, max(2, int(np.ceil(pair.target.length * 2)) + 1))
        h = np.asarray(spacing(grid), float)
        if h.shape != grid.shape or not np.all(np.isfinite(h) & (h > 0)):
            raise ValueError("spacing(s) must return finite steps > 0")
        # N(s) = integral of ds / h: samples at equal steps of N.
        n_of_s = np.concatenate([[0.0], np.cumsum(np.diff(grid) * 0.5 * (1 / h[1:] + 1 / h[:-1]))])
    else:
        if pair.target.length / spacing > MAX_COUNT:
            raise ValueError(f"spacing {spacing:g} would make more than {MAX_COUNT} samples along the target stroke")
        grid = np.array([0.0, pair.target.length])
        n_of_s = grid / float(spacing)
    parts = [np.array([ct[0]])]
    pinned = [True]
    for t0, t1 in zip(ct[:-1], ct[1:]):
        n0, n1 = np.interp([t0, t1], grid, n_of_s)
        n = max(1, int(np.ceil(n1 - n0 - 1e-9)))
        inner = np.interp(np.linspace(n0, n1, n + 1)[1:-1], n_of_s, grid)
        parts.append(np.concatenate([inner, [t1]]))
        pinned.extend([False] * (n - 1) + [True])
    s = np.concatenate(parts)
    return Samples(
        s=s,
        points=pair.target.point_at(s),
        angles=pair.target.angle_at(s, window=window),
        source_s=pair.source_arc_length(s),
        pinned=np.array(pinned, bool),
    )


@dataclass
class Fetched:
    """Candidate patches for one target sample, stacked.

    Parameters
    ----------
    pixels : (K, S, S, 4) float32 ndarray
        Premultiplied RGBA, in the target frame.
    valid : (K, S, S) bool ndarray
        Pixels the patch may contribute (inside the disk of radius ``r``,
        on the source image and allowed for the stroke near ``s'``).
    grad : (K, S, S) float32 ndarray
        Edge strength at the source location of each pixel.
    origin : (int, int)
        Target ``(x, y)`` of pixel ``[0, 0]``.
    source_points : (K, 2) ndarray
        ``p'`` of each candidate.
    source_s : (K,) ndarray
        Source arc length of each candidate.
    source_angles : (K,) ndarray
        Source stroke direction at each ``p'``.
    dst_point : (2,) ndarray
        The target sample ``p``.
    dst_angle : float
        Target direction at ``p``.
    radius : float
        Patch radius ``r``.
    """

    pixels: np.ndarray
    valid: np.ndarray
    grad: np.ndarray
    origin: tuple[int, int]
    source_points: np.ndarray
    source_s: np.ndarray
    source_angles: np.ndarray
    dst_point: np.ndarray
    dst_angle: float
    radius: float = 0.0

    def _candidate(self, k: int) -> None:
        if not 0 <= k < len(self.pixels):
            raise ValueError(f"k = {k} is not a candidate index (there are {len(self.pixels)})")

    @checked(k=Int(0))
    def take(self, k: int) -> Fetched:
        """The stack reduced to candidate ``k``.

        Parameters
        ----------
        k : int
            Candidate index in ``[0, K)``.

        Returns
        -------
        Fetched
            A stack of one (views into this one's arrays).
        """
        self._candidate(k)
        sl = slice(k, k + 1)
        return Fetched(self.pixels[sl], self.valid[sl], self.grad[sl], self.origin,
                       self.source_points[sl], self.source_s[sl], self.source_angles[sl],
                       self.dst_point, self.dst_angle, self.radius)

    @checked(k=Int(0), shape=Shape())
    def source_pixels(self, k: int, shape) -> tuple[np.ndarray, np.ndarray]:
        """``(rows, cols)`` of the source pixels candidate ``k`` copies (its valid pixels).

        Parameters
        ----------
        k : int
            Candidate index in ``[0, K)``.
        shape : tuple of int
            Source image shape ``(H, W, ...)``; indices are clipped to it.

        Returns
        -------
        rows, cols : (N,) int64 ndarray
            Nearest source pixel of each valid patch pixel.
        """
        self._candidate(k)
        sx, sy = _source_coords(self.source_points[k], self.source_angles[k], self.dst_point,
                                self.dst_angle, self.origin, self.valid.shape[1])
        v = self.valid[k]
        h, w = shape[:2]
        return (np.clip(np.rint(sy[v]).astype(np.int64), 0, h - 1),
                np.clip(np.rint(sx[v]).astype(np.int64), 0, w - 1))


def _source_coords(centre, angle: float, dst_point, dst_angle: float, origin, n: int):
    """Source ``(x, y)`` of every pixel of an ``n`` x ``n`` patch at ``origin``.

    The inverse of the rotation :func:`~branchnb.core.warp.transfer_patch`
    applies: ``p = R(angle - dst_angle) (q - p_dst) + p'``.
    """
    th = float(angle) - float(dst_angle)
    u, v = np.meshgrid(np.arange(n) + origin[0] - float(dst_point[0]),
                       np.arange(n) + origin[1] - float(dst_point[1]))
    sx = np.cos(th) * u - np.sin(th) * v + centre[0]
    sy = np.sin(th) * u + np.cos(th) * v + centre[1]
    return sx, sy


@checked(stroke_id=Int(0), source_s=_OFFSETS, across=_OFFSETS,
         dst_point=Array(ndim=1, min=-COORD_LIMIT, max=COORD_LIMIT), radius=Real(0, 1e4, low_open=True),
         window=Real(0, 1e4))
def fetch(index: SourceIndex, stroke_id: int, source_s, across, dst_point, dst_angle: float,
          radius: float, *, window: float) -> Fetched:
    """Fetch candidate patches for one target sample.

    Parameters
    ----------
    index : SourceIndex
        The prepared source image (:func:`source_index`).
    stroke_id : int
        Which source stroke (index into ``index.strokes``).
    source_s : (K,) array_like
        Source arc lengths ``s'`` of the candidates (clamped to the stroke).
    across : (K,) array_like
        Offsets of the candidates along the source normal (pixels).
    dst_point : (x, y)
        Target sample ``p``.
    dst_angle : float
        Target direction at ``p``.
    radius : float
        Patch radius ``r``.
    window : float
        Chord half-length used for the source orientation.

    Returns
    -------
    Fetched
        ``K`` candidates stacked on one ``(2 ceil(r) + 1)``-pixel square
        centred on ``p``.

    Examples
    --------
    >>> img = np.zeros((30, 60, 4), np.float32); img[10:20, 5:55] = (0.6, 0.4, 0.2, 1.0)
    >>> idx = source_index(img, [Stroke([(5, 15), (54, 15)])])
    >>> f = fetch(idx, 0, [20.0, 24.0], [0.0, 0.0], np.array([30.0, 30.0]), np.pi / 2, 8.0, window=4.0)
    >>> f.pixels.shape, f.origin
    ((2, 17, 17, 4), (22, 22))
    """
    index._stroke(stroke_id, "stroke_id")
    if dst_point.shape != (2,):
        raise ValueError(f"dst_point must be one (x, y) point, got shape {dst_point.shape}")
    stroke = index.strokes[stroke_id]
    s = np.clip(np.atleast_1d(np.asarray(source_s, float)), 0.0, stroke.length)
    e = np.broadcast_to(np.asarray(across, float), s.shape)
    centres = stroke.point_at(s) + e[:, None] * stroke.normal_at(s, window=window)
    angles = stroke.angle_at(s, window=window)
    h, w = index.shape
    s_map, allowed = index.s_map[stroke_id], index.allowed[stroke_id]
    # All candidates at once: target pixel q -> source p = R(a_k - dst_angle) (q - p_dst) + c_k
    # (the rotation of core.warp.transfer_patch), bilinear, one remap for the whole stack.
    r = int(np.ceil(radius))
    dx, dy = float(dst_point[0]), float(dst_point[1])
    x0, y0 = int(round(dx)) - r, int(round(dy)) - r
    size = 2 * r + 1
    uu, vv = np.meshgrid(np.arange(size, dtype=np.float32) + np.float32(x0 - dx),
                         np.arange(size, dtype=np.float32) + np.float32(y0 - dy))
    disk = uu**2 + vv**2 <= radius**2
    th = np.asarray(angles, float) - float(dst_angle)
    cos = np.cos(th).astype(np.float32)[:, None, None]
    sin = np.sin(th).astype(np.float32)[:, None, None]
    k = len(s)
    mx = (cos * uu - sin * vv + centres[:, 0, None, None].astype(np.float32)).reshape(k * size, size)
    my = (sin * uu + cos * vv + centres[:, 1, None, None].astype(np.float32)).reshape(k * size, size)
    pix = cv2.remap(index.premult, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    wt = cv2.remap(index.weight[stroke_id], mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    pix = pix.reshape(k, size, size, 4)
    pix *= wt.reshape(k, size, size, 1)
    inside = (mx >= -0.5) & (mx <= w - 0.5) & (my >= -0.5) & (my <= h - 0.5)
    flat = (np.clip(np.rint(my), 0, h - 1).astype(np.intp) * w
            + np.clip(np.rint(mx), 0, w - 1).astype(np.intp)).reshape(k, size, size)
    ok = disk[None] & inside.reshape(k, size, size) & allowed.ravel().take(flat)
    ok &= np.abs(s_map.ravel().take(flat) - s[:, None, None].astype(np.float32)) <= _REACH * radius
    return Fetched(pix, ok, index.grad.ravel().take(flat),
                   (x0, y0), centres, s, np.asarray(angles, float),
                   np.asarray(dst_point, float), float(dst_angle), float(radius))
