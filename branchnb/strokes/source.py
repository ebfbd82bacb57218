"""Preparing the source for fetching: the object's widths along the strokes, each stroke's tube
and the pixels it owns, the cut ends and the parts nobody stroked (:func:`source_index`).

The first step of fetching (:mod:`~branchnb.strokes.fetch`), done once per
edit before any patch is copied; the geometry it is built from is in
:mod:`~branchnb.strokes.tubes`. Split out of :mod:`branchnb.strokes.fetch`;
the names are importable from there too.

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
RGBA image; for an opaque image it is the union of the copied patches
(:func:`~branchnb.strokes.edit.edit_structure` first cuts an object on a
plain or smooth ground out with :func:`~branchnb.core.matte.matte_from_background`,
so only opaque images on busy grounds get here).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.distance import edt as _edt
from ..core.graphcut import gradient_magnitude  # the edge strength G of the seam energy
from ..core.image import as_rgba
from ..core.validate import Array, Int, Real, checked
from .hidden import _own_views, _parts_over
from .outline import outline_style
from .parts import add_bases, find_parts
from .strokes import Stroke
from .tubes import (
    _OPAQUE_MARGIN,
    _beyond_weight,
    _children_beyond_caps,
    _clear_of,
    _connected_to_stroke,
    _distance_map,
    _end_tube,
    _far_half_width,
    _is_cut,
    _joined_ends,
    _parent_side,
    _raw_width,
    _reach_box,
    _smooth_width,
    _tube_margin,
    _wide_ends,
)

__all__ = ["SourceIndex", "source_index", "OPAQUE_RADIUS"]

#: A pixel belongs to every stroke within this many pixels of its nearest stroke.
_SHARE = 2.0
#: Alpha above which a pixel counts as part of the object for the tube margins.
_INKED = 0.02
#: Patch radius for opaque images (no silhouette to measure the width from).
OPAQUE_RADIUS = 24.0


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
    views : dict
        ``stroke -> (premult, depth, grad, filled)``: the source as that
        stroke's patches see it where another part hides its tube (the
        hidden pixels hold its own flesh and outline, see
        :mod:`~branchnb.strokes.hidden`); strokes not in it see the source.
    hidden_by : dict
        ``stroke -> set`` of the strokes whose tubes hide it (``None``: a
        part hides it), for every stroke in ``views``.
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
    views: dict = field(default_factory=dict)
    hidden_by: dict = field(default_factory=dict)

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


def _widths_apart(strokes, raw, joined, keys, obj, edt, caches, ink=None):
    """The raw widths of joined strokes, each measured away from the other's flesh (beyond the paper).

    A parent measured across its children's roots is as wide as they are long
    (a coral's trunk across a branch leaving at 36 degrees: 2.3 times its
    width), and a child measured across its parent as wide as the parent (a
    limb hugging a trunk at a narrow angle: 18.9 px for 6.9, so its tube held
    the trunk's side and a twig in the crotch; a thigh drawn from inside the
    hip). Every stroke is measured away from the flesh of the strokes joined to
    it (its children's and its parents', see
    :func:`~branchnb.strokes.tubes._raw_width`), twice: the second time with
    the widths the first one found.
    """
    n = len(strokes)
    kids_of = [[j for j in range(n) if keys[j] != keys[k] and k in joined[j]] for k in range(n)]
    parents_of = [sorted({p for p in joined[k] if p >= 0 and keys[p] != keys[k]}) for k in range(n)]
    used: dict = {}
    for _ in range(_APART_ROUNDS):
        prev, raw = raw, list(raw)
        for k, st in enumerate(strokes):
            kids = [(strokes[j], _far_half_width(prev[j][1], joined[j], k)) for j in kids_of[k]]
            pars = [(strokes[p], float(prev[p][2])) for p in parents_of[k]]
            if not kids and not pars:
                continue
            if used.get(k, (None,))[0] == [w for _, w in kids + pars]:
                raw[k] = used[k][1]  # the same widths round it: the same result
                continue
            got = _raw_width(st, obj, edt, children=kids + pars, cache=caches[k], ink=_own_ink(ink, keys, k))
            if pars:
                # where its cross-section lies inside the parent's flesh (a limb drawn from
                # the body's centre line) the widths stay the parent's: a cut end's (see
                # _smooth_width)
                ins = np.zeros(len(got[0]), bool)
                pts = st.point_at(got[0])
                own = min(_far_half_width(prev[k][1], joined[k], p) for p in parents_of[k])
                for par, hw in pars:
                    ins |= par.project(pts)[1] <= hw - own
                if ins.any():
                    keep = (_raw_width(st, obj, edt, children=kids, cache=caches[k], ink=_own_ink(ink, keys, k))
                            if kids else prev[k])
                    wv = np.where(ins, keep[1], got[1])
                    got = (got[0], wv, float(max(1, int(np.ceil(np.median(wv))))))
            raw[k] = got
            used[k] = ([w for _, w in kids + pars], got)
    return raw


def _ink(premult: np.ndarray, depth: np.ndarray, strokes: list, keys: list) -> tuple | None:
    """``(ink, rgb, lines)``: the solid pixels of the object's outline colour (within
    :data:`_INK` of it), the straight colours and the strokes drawn 5 px wide (the index
    of their first stroke + 1, 0 off them), or None for an object without an outline
    (:func:`~branchnb.strokes.outline.outline_style`)."""
    style = outline_style(premult, depth)
    if style is None:
        return None
    rgb = premult[..., :3] / np.maximum(premult[..., 3:], 1e-6)
    lines = np.zeros(depth.shape, np.int32)
    for k, st in enumerate(strokes):
        if keys.index(keys[k]) == k:
            cv2.polylines(lines, [np.rint(st.points).astype(np.int32).reshape(-1, 1, 2)], False, k + 1, 5)
    return (premult[..., 3] > 0.5) & (np.linalg.norm(rgb - np.asarray(style.colour), axis=-1) <= _INK), rgb, lines


def _own_ink(ink: tuple | None, keys: list, k: int) -> tuple | None:
    """``ink`` of :func:`_ink` for stroke ``k``: ``(ink, rgb, other)``, ``other`` the other
    strokes' pixels (a part they stroke is not one lying over this one)."""
    if ink is None:
        return None
    mask, rgb, lines = ink
    return mask, rgb, (lines > 0) & (lines != keys.index(keys[k]) + 1)


#: Colour distance (RGB in [0, 1]) within which a pixel is the outline's ink (half the least
#: rim-interior contrast an outline has, see outline._CONTRAST).
_INK = 0.1
#: A parent's tube's last px (from its edge inwards) that a joined child's flesh takes (0: none).
_CHILD_RIM = 1.0
#: ... along the parent's side: the sine of the angle between the two strokes below this.
_ALONG = np.sin(np.radians(60.0))
#: Rounds of :func:`_widths_apart` (each from the widths the last one measured).
_APART_ROUNDS = 2


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
    caches = [{} for _ in source_strokes]  # per stroke: its rays and runs, measured once
    keys = [st.points.tobytes() for st in source_strokes]
    ink = _ink(premult, edt, source_strokes, keys) if has_alpha else None
    raw = [_raw_width(st, obj, edt, cache=caches[k], ink=_own_ink(ink, keys, k)) if has_alpha else
           (np.array([0.0, st.length]), np.zeros(2), 0.0) for k, st in enumerate(source_strokes)]

    # Ends joined to another stroke, cut ends.
    joined = _joined_ends(source_strokes, raw, keys)
    if has_alpha:
        raw = _widths_apart(source_strokes, raw, joined, keys, obj, edt, caches, ink)
    cuts = [tuple(joined[k][end] >= 0 or _is_cut(st, obj, raw[k][2], end) for end in (0, 1))
            for k, st in enumerate(source_strokes)]
    widths = [_smooth_width(raw[k][1], raw[k][2], _wide_ends(st, cuts[k], edt, raw[k][2])) if has_alpha
              else raw[k][1] for k, st in enumerate(source_strokes)]
    width_s = [raw[k][0] for k in range(len(source_strokes))]

    # Per distinct stroke: distance and arc length of the nearest stroke point, within
    # what its patches can reach (a patch's radius, a candidate's offset across, the tube).
    # (bounded by the smoothed widths the tubes and the patch radii are made of, not the
    # raw ones: a limb drawn from inside a body measures the body's width at its root,
    # which made every distance map cover ~80 % of a 1000-px figure)
    uniq: dict = {}
    for k, st in enumerate(source_strokes):
        if keys[k] in uniq:
            continue
        wmax = max(float(widths[j].max()) for j in range(len(keys)) if keys[j] == keys[k]) if has_alpha else 0.0
        r = patch_size / 2.0 if patch_size > 0 else (float(auto_radius(wmax)) if has_alpha else OPAQUE_RADIUS)
        uniq[keys[k]] = _distance_map(st, (h, w), reach=max(r, 2.0 * wmax) + 24.0)
    # (pairwise minimum: no (N, H, W) stack; the same values)
    d_min = functools.reduce(np.minimum, [d for d, _ in uniq.values()]) if len(uniq) > 1 else None
    # pixel coordinates as a row and a column (broadcast: no full-image grids)
    yy, xx = np.arange(h, dtype=np.float32)[:, None], np.arange(w, dtype=np.float32)[None, :]

    # The silhouette's own half width (median over a few widths, no running maximum).
    edge = [ndi.median_filter(raw[k][1], size=4 * int(raw[k][2]) + 1, mode="nearest") if has_alpha
            else raw[k][1] for k in range(len(source_strokes))]
    # Pass 1, per distinct stroke (and cut ends): the tube proper -- the
    # object pixels within the half width (no margin), up to the cut lines,
    # and a free tip's cap -- and the weights of the cut ends.
    tubes: dict = {}
    rims: dict = {}  # per distinct stroke: its core's pixels beyond the silhouette's own width
    dboxes: dict = {}  # per distinct stroke: the box of its distance map
    for k, st in enumerate(source_strokes):
        key = (keys[k], cuts[k])
        if key in tubes:
            continue
        d, s_map = uniq[keys[k]]
        ws, wv = width_s[k], widths[k]
        # (the end weights on the distance map's box only: no patch of the stroke reaches
        # beyond it, see _distance_map's reach)
        box = dboxes.setdefault(keys[k], _reach_box(d))
        endw = np.ones((h, w), np.float32)
        for end, is_cut in enumerate(cuts[k]):
            if is_cut:
                bx, by = xx[:, box[1]], yy[box[0]]
                endw[box] *= _beyond_weight(st, end, s_map[box], bx, by)
                if has_alpha:
                    # The cut line itself: only across the tube.
                    w_end = float(np.interp(0.0 if end == 0 else st.length, ws, wv))
                    endw[box] *= _end_tube(st, end, s_map[box], bx, by, w_end, inked[box])
        tube = interior = core = None
        if has_alpha:
            # the half width at every pixel's nearest stroke point (beyond the distance
            # map's box the arc length is 0: the first width)
            tube = np.full((h, w), np.float32(np.interp(0.0, ws, wv)), np.float32)
            tube[box] = np.interp(s_map[box], ws, wv)
            # (on the distance map's box only: beyond it s_map is 0 and d is 1e6, so no
            # pixel there is interior or in the core)
            sb, tb, db = s_map[box], tube[box], d[box]
            interior = np.zeros((h, w), bool)
            interior[box] = (sb > 1.0) & (sb < st.length - 1.0)
            # beyond a free end the object may go on for a tip's length (see _is_cut), as far
            # as the patch at the end reaches (the rest is a part)
            reach = patch_size / 2.0 if patch_size > 0 else auto_radius(tb)
            cap = np.minimum(np.maximum(2.0 * tb, 8.0) + 2.0, reach - 2.0)
            core = np.zeros((h, w), bool)
            core_b = inked[box] & (endw[box] > 0.5) & (db <= np.where(interior[box], tb + 0.5, cap))
            core[box] = _connected_to_stroke(core_b, db <= 0.5 * tb + 1.5)
            # the core's pixels beyond the silhouette's own half width (the running
            # maximum of the tube's width reaches over a neighbour lying along it)
            loose = np.zeros((h, w), bool)
            loose[box] = core[box] & (db > np.interp(sb, ws, edge[k]) + 0.5)
            rims[key] = loose
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
                if _CHILD_RIM and keys.count(keys[k]) == 1:
                    # but the parent's rim (its last px) in the child's flesh, nearer the child,
                    # is the child's: a thigh drawn along the hip's edge left its upper edge
                    # behind on the body when it turned (a lizard at 100 px)
                    # (where the child's stroke itself runs outside the parent's tube: not at
                    # the root of a leaf's petiole drawn from the twig's centre line; not for a
                    # stroke drawn twice: its copy lands on another stretch of the parent, where
                    # that rim is a fleck)
                    dk, dp = tubes[(keys[k], cuts[k])][0], tubes[pkey][0]
                    rim = cut & (dk < dp) & (dk <= raw[k][2] + 0.5) & (dp > tubes[pkey][2] - _CHILD_RIM)
                    if rim.any():
                        par = source_strokes[parent]
                        q = st.point_at(tubes[(keys[k], cuts[k])][1][rim])
                        sq, dq = par.project(q)
                        # (and where it runs along the parent's side, within 60 degrees of it: a
                        # limb leaving at a wide angle takes none of the parent's shoulder)
                        sk = tubes[(keys[k], cuts[k])][1][rim]
                        along = np.abs(np.sin(st.angle_at(sk, window=3.0) - par.angle_at(sq, window=3.0)))
                        rim[rim] = (dq > np.interp(sq, width_s[parent], widths[parent]) + 0.5) & (
                            along < _ALONG)
                        cut &= ~rim
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
    parts, part_mask, given = [], None, None
    if has_alpha:
        # Object pixels no stroke's tube holds: the parts nobody stroked.
        claimed = np.zeros((h, w), bool)
        for key in tube_keys:
            claimed |= tubes[key][5]
        claimed_before = claimed.copy()
        # a stroke joined to a parent at one end only ends in a free tip at the other
        tips = [[(*source_strokes[k].points[-1 if joined[k][0] >= 0 else 0], float(raw[k][2]))
                 for k in range(len(source_strokes))
                 if (keys[k], cuts[k]) == key and (joined[k][0] >= 0) != (joined[k][1] >= 0)]
                for key in tube_keys]
        parts, part_mask = find_parts(alpha, inked, claimed, [tubes[key][5] for key in tube_keys],
                                      [tubes[key][1] for key in tube_keys],
                                      [tubes[key][0] for key in tube_keys],
                                      rims=[rims[key] for key in tube_keys],
                                      tips=tips,
                                      colour=premult[..., :3] / np.maximum(premult[..., 3:], 1e-6))
        # a tip-held part's pixels taken back from other tubes (see parts._reclaim) are no
        # stroke's: the tube's width measured across the part would let it copy them again
        given = np.zeros((h, w), bool)
        for part in parts:
            if part.tip is not None:
                given[part.box] |= part.mask & claimed_before[part.box]
        first = [(keys[k], cuts[k]) for k in range(len(source_strokes))]
        for part in parts:  # tube index -> the first stroke with that tube
            part.stroke = first.index(tube_keys[part.stroke])
            part.ends = [(first.index(tube_keys[j]), s_a) for j, s_a in part.ends]

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
                # Beyond the ends, no unstroked part farther than a tip's length (the
                # cap of pass 1): a free end's patch (radius ~1.2 w) reaches past the
                # tip onto a neighbouring part (a lizard's hind leg ending next to its
                # front foot, 150 px: the foot was copied with the turned leg and left
                # floating). Such a part is carried or dropped as a whole instead.
                tb = tube[b]
                cap = np.minimum(np.maximum(2.0 * tb, 8.0) + 2.0,
                                 (patch_size / 2.0 if patch_size > 0 else auto_radius(tb)) - 2.0)
                beyond = part_mask[b] & ~interior[b]
                ramp = np.where(interior[b], ramp, np.where(beyond, np.clip(cap - d[b] + 0.5, 0.0, 1.0), 1.0))
                weight[b] *= ramp.astype(np.float32)
                if given is not None:
                    weight[b][given[b]] = 0.0
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
    if has_alpha:
        _parts_over(index, tubes, keys, cuts, joined)
        index.views = _own_views(index, tubes, keys, cuts, joined, by=index.hidden_by)
        for k, (_, _, _, filled) in index.views.items():
            # (identical strokes share these arrays: the same pixels either way)
            allowed[k][filled] = True
            weight = weights[k]
            weight[filled] = np.maximum(weight[filled], tubes[(keys[k], cuts[k])][4][filled])
    return index
