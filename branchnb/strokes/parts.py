"""Parts nobody stroked: found in the source, carried along by the stroke they hang from.

The paper re-synthesizes the object along the target strokes only: every
part of the object without a stroke (a leaf on a stroked twig, the
branches of a tree when one branch is added) disappears, and where it
left its parent a stump with a straight cut remains. Here (beyond the
paper) those parts stay, so an edit changes only what the user touched:

1. **Finding the parts.** Each source stroke holds a *tube*: the object
   pixels within its half width (and a free tip's cap, up to its cut
   lines). The object pixels no tube holds fall into connected pieces;
   thin slivers lying along a tube (its silhouette's rim where the
   measured width is a little short) are not parts.
2. **Attachment.** A part hangs from the stroke whose tube it touches
   along most pixels, at the arc length ``s'`` where it touches (the
   median over the contact); a part touching nothing hangs from the
   nearest stroke. A part touching its own stroke at two places (a loop
   of rope between the two cut ends of the stroked piece) follows only
   where the two places move alike (within 2 px); otherwise it cannot
   follow rigidly and is left out. A part that also touches another
   stroke (a leg at the hip where the tail turns, a limb between two
   stroked branches) follows the stroke it touches most.
3. **Following.** Every target stroke paired with that source stroke
   carries the part rigidly: the frame of the source stroke at ``s'``
   (point and direction) goes to the frame of the target stroke at the
   corresponding arc length. The part brings a *base* along, the parent's
   object pixels near the contact, so that the graph cut stitches it into
   the parent like any patch. A part hanging between two stroked parts
   follows the one it touches more (rigidly; it is not bent). Where the
   target bends the parent so that carried siblings would collide (a
   fern's pinnae on the inner side of the bend), they are turned apart
   about their attachments, as evenly as the chain of siblings allows
   (:mod:`~branchnb.strokes.fanning`).

``StrokeEditParams.unstroked = "drop"`` keeps the paper's output: parts
nobody stroked are left out (their cut faces get the object's outline,
see :mod:`~branchnb.strokes.outline`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.distance import edt as _edt

__all__ = ["Part", "find_parts", "place_part", "rigid_frame", "carry_frame", "carry_stroke"]

#: A piece touching a tube along at least this share of its pixels is a sliver of the tube's rim.
_SLIVER = 0.4
#: Pieces with fewer opaque pixels than this are crumbs, not parts.
_MIN_AREA = 4
#: A second place a part touches counts if it holds this share of the contact.
_ANCHOR = 0.15
#: How far (px) a piece held at both ends reaches into the tubes' rims (see find_parts' rims).
_RIM = 6
#: Two strokes' contacts this share of a piece's extent apart hold it at both ends.
_ENDS = 0.75
#: A piece thinner than this share of the half width of the tubes holding it is their rim.
_THIN = 0.2
#: A piece held at both ends lies within this many half widths of one holding stroke.
_ALONG_SIDE = 2.0
#: Contact pixels further apart than this along a stroke (px) touch it at two places.
_GAP = 10.0
#: A ring pixel counts as touching a stroke within this much (px) of its nearest stroke.
_OWN = 2.0
#: Share of the pixels round a stroke's free tip (in the piece or the background) a piece holds to enclose it.
_TIP_INSIDE = 0.75
#: Radius (px) beyond a free tip's half width of the disk looked at round it.
_TIP_RING = 4.0
#: Least share of that disk in the piece or the background for it to decide.
_TIP_LEAST = 0.15
#: A pixel within this share of the squared colour distance between a tip-held part and
#: another tube looks like the tube.
_RECLAIM_OTHER = 0.25
#: How far (px) round its reclaimed pixels a tip-held part takes ink looking like neither (its outline).
_RECLAIM_RIM = 3


@dataclass
class Part:
    """An unstroked part of the source object.

    Parameters
    ----------
    box : (slice, slice)
        Its bounding box in the source image (rows, columns), grown to
        hold its base.
    mask : (h, w) bool ndarray
        Its pixels within ``box``.
    base : (h, w) bool ndarray
        The parent's object pixels near the contact, within ``box``: the
        overlap the graph cut stitches the part in.
    stroke : int
        The source stroke it hangs from.
    s : float
        Arc length of the attachment on that stroke.
    contact : int
        Pixels touching the stroke's tube (0: the part is loose).
    side : float
        +1 or -1: which side of the stroke (along its normal) the part lies on.
    area : int
        Its opaque pixels.
    at_end : bool
        Attached at an end of the stroke (beyond it, not on one side).
    anchors : list of (int, float)
        Every place it touches a tube: ``(stroke, s)``; a part touching
        two places (a loop of rope between the two cut ends of a stroke)
        follows only if they move alike.
    ends : list of (int, float)
        ``(stroke, s)`` of two strokes holding the part at both ends (their
        contacts farther apart than half the part's extent: a twig in a
        crotch, its root on a limb and its tip against the trunk); empty
        otherwise. It follows only if the two move it alike.
    tip : (x, y, r) or None
        The free tip (point, half width) of the stroke it hangs from when
        that tip ends inside it (see :func:`_tip_holder`): it hangs from
        that stroke, not from the one it touches most.
    body : bool
        The body the stroke grows out of (see :func:`carry_frame`): it is
        moved with the stroke's start, never turned by it.
    over : (h, w) bool ndarray or None
        Its pixels (within ``box``, also in ``mask``) lying over the
        stroke it hangs from, taken from that stroke's tube (a leaf's base
        drawn across its stem, see
        :func:`~branchnb.strokes.hidden._parts_over`); None: it lies over
        none.
    shift : (2,) ndarray or None
        A body's move: how the user moved its stroke's start, as drawn
        (before the source stroke was centred on its part; see
        :func:`carry_frame`); None: the start's move of the strokes given.
    """

    box: tuple
    mask: np.ndarray
    base: np.ndarray
    stroke: int
    s: float
    contact: int
    side: float
    area: int
    at_end: bool = False
    anchors: list = field(default_factory=list)
    ends: list = field(default_factory=list)
    tip: tuple | None = None
    body: bool = False
    over: np.ndarray | None = None
    shift: np.ndarray | None = None


def find_parts(alpha: np.ndarray, inked: np.ndarray, claimed: np.ndarray, cores: list,
               s_maps: list, d_maps: list, *, rims: list | None = None,
               tips: list | None = None, colour: np.ndarray | None = None) -> tuple[list[Part], np.ndarray]:
    """The unstroked parts of an RGBA object.

    Parameters
    ----------
    alpha : (H, W) ndarray
        Opacity of the source object in [0, 1]; pieces with fewer than 4
        pixels of alpha > 0.5 are crumbs, not parts.
    inked : (H, W) bool ndarray
        Pixels with any coverage.
    claimed : (H, W) bool ndarray
        The union of the strokes' tubes.
    cores : list of (H, W) bool ndarray
        Each stroke's tube (one per distinct stroke).
    s_maps, d_maps : list of (H, W) ndarray
        Arc length of, and distance to, the nearest point of each stroke.
    rims : list of (H, W) bool ndarray, optional
        Each tube's pixels beyond its stroke's silhouette half width. A
        piece touching two tubes (a twig in a crotch, its root on one
        limb and its tip against the trunk) takes the pixels of these
        rims that join it, and ``cores`` and ``claimed`` give them up:
        held at both ends, it was torn into three (each end re-synthesized
        with its tube, the middle carried) and came out in fragments.
    tips : list of list of (x, y, r), optional
        Per tube: the free tips of its strokes (the end of a stroke joined
        to a parent at its other end) and the strokes' half widths. A piece
        enclosing exactly one tube's tip hangs from that tube, whatever
        touches it along more pixels (see :func:`_tip_holder`).
    colour : (H, W, 3) ndarray, optional
        The source's colours (not premultiplied). With ``tips``, such a
        piece takes back its own pixels from the tubes of other strokes
        lying over it (see :func:`_reclaim`).

    Returns
    -------
    parts : list of Part
        ``Part.stroke`` indexes ``cores``.
    mask : (H, W) bool ndarray
        All parts' pixels.
    """
    h, w = alpha.shape
    rest = inked & ~claimed
    labels, n = ndi.label(rest, structure=np.ones((3, 3)))
    mask = np.zeros((h, w), bool)
    parts: list[Part] = []
    if n == 0:
        return parts, mask
    boxes = ndi.find_objects(labels)
    for lab, box in enumerate(boxes, start=1):
        grow = 3
        r0, r1 = max(box[0].start - grow, 0), min(box[0].stop + grow, h)
        c0, c1 = max(box[1].start - grow, 0), min(box[1].stop + grow, w)
        sub = (slice(r0, r1), slice(c0, c1))
        comp = labels[sub] == lab
        area = int((comp & (alpha[sub] > 0.5)).sum())
        if area < _MIN_AREA:
            continue
        ring, touch, touching, contacts, k = _contacts(comp, sub, cores, d_maps)
        if contacts[k] and (touch & ndi.binary_dilation(cores[k][sub])).sum() >= _SLIVER * comp.sum():
            continue  # a sliver along the tube's rim
        least = max(3, _ANCHOR * sum(contacts))
        if rims is not None and contacts[k] and _ends(touching, contacts, least, comp, [d[sub] for d in d_maps]):
            # held at both ends: the piece takes the tubes' rims joining it
            big = (slice(max(r0 - _RIM, 0), min(r1 + _RIM, h)), slice(max(c0 - _RIM, 0), min(c1 + _RIM, w)))
            seed = labels[big] == lab
            loose = np.zeros_like(seed)
            for j, c in enumerate(contacts):
                if c >= least:
                    loose |= rims[j][big]
            extra = ndi.binary_propagation(seed, structure=np.ones((3, 3), bool),
                                           mask=seed | (loose & inked[big])) & ~seed
            if extra.any():
                for core in cores:
                    core[big] &= ~extra
                claimed[big] &= ~extra
                sub, comp = big, seed | extra
                area = int((comp & (alpha[sub] > 0.5)).sum())
                ring, touch, touching, contacts, k = _contacts(comp, sub, cores, d_maps)
                least = max(3, _ANCHOR * sum(contacts))
        anchors, ends = [], []
        held = _tip_holder(comp, sub, alpha, tips) if tips is not None else None
        if held is not None and colour is not None:
            sub, comp, grown = _reclaim(comp, sub, held[0], cores, claimed, d_maps, colour, inked)
            if grown:
                area = int((comp & (alpha[sub] > 0.5)).sum())
                ring, touch, touching, contacts, k = _contacts(comp, sub, cores, d_maps)
                least = max(3, _ANCHOR * sum(contacts))
        if held is not None:
            k = held[0]
            if not contacts[k]:
                # the tube round the tip also lies nearer an overlapping part's stroke (a leaf
                # over the berry): its contact is every ring pixel in it
                touching[k] = ring & cores[k][sub]
                contacts[k] = int(touching[k].sum())
        if contacts[k]:
            s = float(np.median(s_maps[k][sub][touching[k]]))
            for j, c in enumerate(contacts):
                if c >= least:
                    anchors += [(j, a) for a in _clusters(s_maps[j][sub][touching[j]], least)]
            ends = [] if held is not None else [
                (j, float(np.median(s_maps[j][sub][touching[j]])))
                for j in _ends(touching, contacts, least, comp, [d[sub] for d in d_maps])]
        else:
            dist = [float(d[sub][comp].min()) for d in d_maps]
            k = int(np.argmin(dist))
            s = float(s_maps[k][sub][comp][np.argmin(d_maps[k][sub][comp])])
        mask[sub] |= comp
        parts.append(Part(box=sub, mask=comp, base=np.zeros_like(comp), stroke=k, s=s,
                          contact=contacts[k], side=0.0, area=area, anchors=anchors, ends=ends,
                          tip=held[1] if held is not None else None))
    return parts, mask


def _tip_holder(comp: np.ndarray, sub: tuple, alpha: np.ndarray, tips: list) -> tuple | None:
    """``(tube, (x, y, r))``: the one tube whose stroke's free tip ends inside the piece ``comp`` (or None).

    A tip is inside when, in the disk of radius ``r +`` :data:`_TIP_RING`
    px round it (``r`` the tip's half width: 2 px beyond its tube), the piece
    holds at least :data:`_TIP_INSIDE` of the pixels that are the piece's
    or background (pixels of the tubes, the tip's own and those of parts
    lying over it, count for neither). Where those are fewer than
    :data:`_TIP_LEAST` of the disk (tubes cover it), a disk twice as wide
    decides. A berry on a stalk drawn into it hangs from the stalk, even
    when a leaf lying over it touches it along many more pixels (it was
    carried by the leaf: a slot in its top where the stalk had been, a copy
    under a copied leaf). Beyond the paper.
    """
    h, w = alpha.shape
    (r0, r1), (c0, c1) = (sub[0].start, sub[0].stop), (sub[1].start, sub[1].stop)
    found = []
    for j, points in enumerate(tips):
        for x, y, r in points:
            if not (c0 <= x < c1 and r0 <= y < r1):
                continue
            for rad in (r + _TIP_RING, 2.0 * r + 2.0 * _TIP_RING):
                y0, y1 = max(int(y - rad), 0), min(int(y + rad) + 2, h)
                x0, x1 = max(int(x - rad), 0), min(int(x + rad) + 2, w)
                yy, xx = np.mgrid[y0:y1, x0:x1]
                disk = (xx - x) ** 2 + (yy - y) ** 2 <= rad * rad
                mine = np.zeros(disk.shape, bool)
                a0, a1, b0, b1 = max(y0, r0), min(y1, r1), max(x0, c0), min(x1, c1)
                mine[a0 - y0:a1 - y0, b0 - x0:b1 - x0] = comp[a0 - r0:a1 - r0, b0 - c0:b1 - c0]
                n_mine = int((mine & disk).sum())
                n_seen = n_mine + int((disk & (alpha[y0:y1, x0:x1] <= 0.5)).sum())
                if n_seen < _TIP_LEAST * int(disk.sum()):
                    continue  # the disk lies in tubes (the tip's own, a leaf's over the part): look wider
                if n_mine >= _TIP_INSIDE * n_seen:
                    found.append((j, (float(x), float(y), float(r))))
                break
            if found and found[-1][0] == j:
                break
    return found[0] if len(found) == 1 else None


def _reclaim(comp: np.ndarray, sub: tuple, own: int, cores: list, claimed: np.ndarray, d_maps: list,
             colour: np.ndarray, inked: np.ndarray) -> tuple:
    """``(sub, comp, grown)``: a tip-held piece with its pixels taken back from other tubes.

    Another stroke's tube measured across the piece (a leaf lying along a
    berry's top: its width runs on into the berry) holds pixels of the
    piece; carried with that stroke, they left a bite out of the piece and
    a copy of it wherever the stroke went. Pixels of other tubes (not the
    tip's own) joined to the piece, nearer its mean colour than the mean
    colour of that tube's pixels near its stroke, are the piece's, and the
    tubes give them up (``cores`` and ``claimed`` are changed in place),
    with the ink within :data:`_RECLAIM_RIM` px round them that looks like
    neither (the part's outline: left behind, it hung as loose arcs).
    Beyond the paper.
    """
    h, w = claimed.shape
    ys, xs = np.nonzero(comp)
    grow = int(max(ys.max() - ys.min(), xs.max() - xs.min()) // 2) + 3
    r0, r1 = max(sub[0].start - grow, 0), min(sub[0].stop + grow, h)
    c0, c1 = max(sub[1].start - grow, 0), min(sub[1].stop + grow, w)
    big = (slice(r0, r1), slice(c0, c1))
    seed = np.zeros((r1 - r0, c1 - c0), bool)
    seed[sub[0].start - r0:sub[0].stop - r0, sub[1].start - c0:sub[1].stop - c0] = comp
    rgb = colour[big]
    mine = rgb[seed].mean(axis=0)
    take = np.zeros_like(seed)
    other = np.zeros_like(seed)  # pixels that look like another tube's stroke
    for j, core in enumerate(cores):
        if j == own:
            continue
        cj = core[big] & inked[big]
        if not cj.any():
            continue
        dj = d_maps[j][big]
        near = cj & (dj <= max(1.5, 0.5 * float(np.median(dj[cj]))))
        if not near.any():
            continue
        theirs = rgb[near].mean(axis=0)
        d_mine, d_theirs = ((rgb - mine) ** 2).sum(axis=2), ((rgb - theirs) ** 2).sum(axis=2)
        take |= cj & (d_mine < d_theirs)
        other |= cj & (d_theirs <= _RECLAIM_OTHER * float(((mine - theirs) ** 2).sum()))
    if not take.any():
        return sub, comp, False
    got = ndi.binary_propagation(seed, structure=np.ones((3, 3), bool), mask=seed | take) & ~seed
    if not got.any():
        return sub, comp, False
    # and the part's outline round them: ink like neither colour, within a few px
    rim = ndi.binary_dilation(seed | got, iterations=_RECLAIM_RIM) & ~(seed | got) & ~other
    for j, core in enumerate(cores):
        if j != own:
            got |= rim & core[big] & inked[big]
    for core in cores:
        core[big] &= ~got
    claimed[big] &= ~got
    return big, seed | got, True


def _contacts(comp: np.ndarray, sub: tuple, cores: list, d_maps: list) -> tuple:
    """``(ring, touch, touching, contacts, k)`` of a piece ``comp`` on the box ``sub``.

    ``ring``: the pixels round it; ``touch``: its pixels next to the ring;
    ``touching[j]``: the ring's pixels in tube ``j``; ``contacts[j]``: how
    many; ``k``: the tube touched most.
    """
    ring = ndi.binary_dilation(comp) & ~comp
    touch = ndi.binary_dilation(ring) & comp  # the part's pixels next to its ring
    # a part touches a stroke where its ring meets that stroke's tube nearer that stroke
    # than any other (within _OWN px): a trunk's tube measured across a branch leaving
    # at a narrow angle covers the branch's root, and a sub-branch there was anchored to
    # the trunk too (a coral's branch turned: its sub-branch stayed behind with the trunk)
    # (nearest among the tubes that hold the ring pixel: a finger's root on the palm's
    # cap, beyond the palm stroke's end, lies nearer the next finger's stroke than the
    # palm's, yet only the palm's tube holds it; it was a loose part carried by the
    # next finger)
    near = np.minimum.reduce([np.where(core[sub], d[sub], np.inf) for core, d in zip(cores, d_maps)])
    touching = [ring & core[sub] & (d[sub] <= near + _OWN) for core, d in zip(cores, d_maps)]
    contacts = [int(t.sum()) for t in touching]
    return ring, touch, touching, contacts, int(np.argmax(contacts))


def _ends(touching: list, contacts: list, least: float, comp: np.ndarray, d_sub: list) -> list[int]:
    """``[j, k]``: two tubes holding a piece at its two ends (or ``[]``).

    Some contact pixel of one lies farther than :data:`_ENDS` times the
    piece's extent (the diagonal of its pixels' box) from some contact
    pixel of the other (a twig in a crotch: its root on a limb, its tip
    against the trunk); a leg touching the body and the tail at its root
    is held at one end only. A piece thinner (its area over its extent)
    than :data:`_THIN` times the thinner tube's half width (the median
    distance of its contact to that stroke) is a sliver of the tubes'
    rims, not held (a palm's rim along the forearm it turns on, 1000 px:
    4 px against 57; a twig in a crotch: 2-4 px against 4-7). Only a piece
    lying along one of the two (within :data:`_ALONG_SIDE` times its half
    width of its centre line) is held: a long branch reaching out of a
    fork it touches at two places is carried as a whole.
    """
    held = [j for j, c in enumerate(contacts) if c >= least]
    if len(held) < 2:
        return []
    ys, xs = np.nonzero(comp)
    extent = float(np.hypot(xs.max() - xs.min() + 1, ys.max() - ys.min() + 1))
    hw = {j: float(np.median(d_sub[j][touching[j]])) for j in held}
    if len(ys) < _THIN * extent * min(hw.values()):
        return []
    if not any(float(d_sub[j][comp].max()) <= _ALONG_SIDE * hw[j] for j in held):
        return []
    pts = {j: np.argwhere(touching[j]).astype(float) for j in held}
    best, pair = _ENDS * extent, []
    for a in held:
        for b in held:
            if a < b:
                d = float(np.sqrt(((pts[a][:, None] - pts[b][None]) ** 2).sum(axis=2).max()))
                if d > best:
                    best, pair = d, [a, b]
    return pair


def _clusters(s: np.ndarray, least: float) -> list[float]:
    """Median arc length of each run of contact (gaps over :data:`_GAP` px split runs) with ``least`` pixels."""
    s = np.sort(np.asarray(s, float))
    cuts = np.flatnonzero(np.diff(s) > _GAP) + 1
    return [float(np.median(run)) for run in np.split(s, cuts) if len(run) >= least]


def add_bases(parts: list[Part], index, window: float) -> None:
    """Give every attached part its base (the parent's pixels near the contact) and its side.

    Parameters
    ----------
    parts : list of Part
        From :func:`find_parts`; modified in place (``box``, ``mask``,
        ``base``, ``at_end`` and ``side`` are set).
    index : SourceIndex
        The source index the parts were found in (strokes, half widths, arc
        length maps, premultiplied image).
    window : float
        Half-length (pixels) of the chord the stroke's normal is taken from.

    Returns
    -------
    None
    """
    h, w = index.shape
    for part in parts:
        st = index.strokes[part.stroke]
        half = float(index.half_width(part.stroke, part.s))
        reach = int(np.ceil(max(2.0, 0.6 * half))) + 1
        r0, c0 = part.box[0].start, part.box[1].start
        R0, R1 = max(r0 - reach, 0), min(part.box[0].stop + reach, h)
        C0, C1 = max(c0 - reach, 0), min(part.box[1].stop + reach, w)
        big = (slice(R0, R1), slice(C0, C1))
        comp = np.zeros((R1 - R0, C1 - C0), bool)
        comp[r0 - R0:r0 - R0 + part.mask.shape[0], c0 - C0:c0 - C0 + part.mask.shape[1]] = part.mask
        base = np.zeros_like(comp)
        part.at_end = not 1.0 < part.s < st.length - 1.0
        if part.contact:
            near = _edt(~comp) <= reach
            # only the parent's pixels on the part's side, away from its centre line
            foot = st.point_at(index.s_map[part.stroke][big].ravel()).reshape(*comp.shape, 2)
            yy, xx = np.mgrid[R0:R1, C0:C1]
            off = np.hypot(xx - foot[..., 0], yy - foot[..., 1])
            base = near & index.allowed[part.stroke][big] & (index.weight[part.stroke][big] > 0.5) \
                & (index.premult[big][..., 3] > 0.02) & ~comp & ((off > 0.35 * half) | part.at_end)
        if part.tip is not None:
            # the tip's own tube inside the part (a stalk drawn into its berry) goes with it:
            # the part's patch covers the slot the stalk's cut end leaves there
            rad = int(np.ceil(part.tip[2])) + 3
            closed = _closed_by_disk(np.pad(comp, rad + 1), rad)[rad + 1:-rad - 1, rad + 1:-rad - 1]
            base |= closed & ~comp & (index.premult[big][..., 3] > 0.02)
        part.box, part.mask, part.base = big, comp, base
        ys, xs = np.nonzero(comp)
        p = st.point_at(part.s)
        n = st.normal_at(part.s, window=window)
        part.side = 1.0 if float(np.mean((xs + C0 - p[0]) * n[0] + (ys + R0 - p[1]) * n[1])) >= 0 else -1.0


def rigid_frame(source, target, s_source: float, s_target: float, *, window: float) -> np.ndarray:
    """The 2 x 3 rigid map taking the source stroke's frame at ``s_source`` to the target's at ``s_target``.

    ``x_t = P_t + R(theta_t - theta_s) (x_s - P_s)`` with ``P`` the stroke
    points and ``theta`` the stroke directions there.

    Parameters
    ----------
    source : Stroke
        The source stroke.
    target : Stroke
        The target stroke.
    s_source : float
        Arc length (pixels) of the frame on ``source``.
    s_target : float
        Arc length (pixels) of the frame on ``target``.
    window : float
        Half-length (pixels) of the chords the directions ``theta`` are taken
        from (:meth:`~branchnb.strokes.strokes.Stroke.angle_at`).

    Returns
    -------
    (2, 3) float64 ndarray
        Affine map: ``x_t = M[:, :2] @ x_s + M[:, 2]``.

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke
    >>> m = rigid_frame(Stroke([(0, 0), (10, 0)]), Stroke([(5, 5), (5, 15)]), 4.0, 4.0, window=1.0)
    >>> np.round(m @ [4.0, 1.0, 1.0], 6).tolist()
    [4.0, 9.0]
    """
    # (the strokes' unchecked accessors: called for every carried part, the same values)
    ps, pt = source._point_at(s_source), target._point_at(s_target)
    th = float(target._angle_at(s_target, window)) - float(source._angle_at(s_source, window))
    c, s = np.cos(th), np.sin(th)
    rot = np.array([[c, -s], [s, c]])
    return np.hstack([rot, (pt - rot @ ps)[:, None]])


def carry_frame(part: Part, source, target, s_source: float, s_target: float, *, window: float) -> np.ndarray:
    """The 2 x 3 map carrying an unstroked ``part`` from its source stroke to its target stroke.

    :func:`rigid_frame` at the attachment, except for the *body* a stroke
    grows out of (``part.body``: attached at the stroke's start and larger
    than the stroke's own piece, e.g. a lizard's trunk when only its
    tail is stroked): that is moved as the stroke's start moves, never
    turned. Beyond the paper (which drops unstroked parts): turned with the
    tail's first direction, bending a tail swung the whole lizard round its
    hip and off the canvas, where a user expects only what they stroked to
    move.

    Parameters
    ----------
    part : Part
        The part carried.
    source, target : Stroke
        Its stroke and that stroke's target.
    s_source, s_target : float
        Arc lengths of the attachment on the two strokes (unused for a body).
    window : float
        Half-length of the chords directions are taken from.

    Returns
    -------
    (2, 3) float64 ndarray
        Affine map: ``x_t = M[:, :2] @ x_s + M[:, 2]``.

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke
    >>> body = Part((slice(0, 4), slice(0, 4)), np.ones((4, 4), bool), np.zeros((4, 4), bool),
    ...             0, 0.0, 4, 1.0, 16, at_end=True, body=True)
    >>> m = carry_frame(body, Stroke([(0, 0), (10, 0)]), Stroke([(2, 0), (2, 10)]), 0.0, 0.0, window=1.0)
    >>> m.round(6).tolist()
    [[1.0, 0.0, 2.0], [0.0, 1.0, 0.0]]
    """
    if not part.body:
        return rigid_frame(source, target, s_source, s_target, window=window)
    # the start's move, not the attachment's: where the part touches the stroke a little past its start,
    # a bent target carries that point elsewhere and shifted the whole body by it
    shift = np.asarray(target._point_at(0.0), np.float64) - np.asarray(source._point_at(0.0), np.float64)
    if part.shift is not None:
        # the start as the user drew it: a source stroke centred on its part moved its start off the
        # drawn one, and a body the user left in place slid by that (a 1000-px twig, only its leaf
        # stroked: 2.9 px, every pixel of the twig and fruits changed)
        shift = np.asarray(part.shift, np.float64)
    return np.array([[1.0, 0.0, shift[0]], [0.0, 1.0, shift[1]]])


def carry_stroke(child, parent_source, parent_target, *, window: float = 5.0) -> np.ndarray:
    """Where a child's stroke goes when its parent's stroke is edited (moved rigidly with it).

    The child's first point is projected on the parent's source stroke;
    the parent maps by arc-length fraction (as a stroke pair without
    control points), and the child follows the parent's frame there
    (:func:`rigid_frame`). Use it to draw target strokes for the parts
    you want to stroke along with their parent.

    Parameters
    ----------
    child : (N, 2) array_like
        The child's source stroke (starting on or near the parent).
    parent_source, parent_target : (M, 2) array_like
        The parent's source and target strokes.
    window : float
        Chord half-length for the parent's directions (px).

    Examples
    --------
    >>> twig = [(0, 0), (100, 0)]
    >>> bent = [(0, 0), (0, 100)]                     # the twig turned by 90 degrees
    >>> carry_stroke([(50, 0), (50, -20)], twig, bent).round(6).tolist()
    [[0.0, 50.0], [20.0, 50.0]]
    """
    from .strokes import Stroke

    pts = np.asarray(child, float)
    src = parent_source if isinstance(parent_source, Stroke) else Stroke(parent_source, name="parent_source")
    tgt = parent_target if isinstance(parent_target, Stroke) else Stroke(parent_target, name="parent_target")
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 1 or not np.all(np.isfinite(pts)):
        raise ValueError(f"child must be an (N, 2) array of finite points, got shape {pts.shape}")
    s, _ = src.project(pts[:1])
    m = rigid_frame(src, tgt, float(s[0]), float(s[0]) / src.length * tgt.length, window=window)
    return pts @ m[:, :2].T + m[:, 2]


def _thin(alpha: np.ndarray) -> np.ndarray:
    """Solid pixels of stretches at most ~3 px wide (no pixel deeper than 2 px within 2 px)."""
    solid = alpha > 0.5
    depth = ndi.distance_transform_edt(np.pad(solid, 1))[1:-1, 1:-1]
    return solid & (ndi.maximum_filter(depth, size=5) <= 2.0)


def place_part(part: Part, premult: np.ndarray, forward: np.ndarray, shape) -> tuple | None:
    """The part (and its base) moved by the rigid map ``forward`` (source -> target).

    Returns ``(pixels, valid, base, origin, inverse)`` on a square box in
    the target (``pixels`` premultiplied RGBA; ``inverse`` maps target
    ``(x, y)`` to source ``(x, y)``), or None when it lands outside ``shape``.

    Parameters
    ----------
    part : Part
        The part with its base (:func:`add_bases`).
    premult : (H, W, 4) ndarray
        Premultiplied RGBA source image.
    forward : (2, 3) ndarray
        Rigid map from source to target (:func:`rigid_frame`).
    shape : tuple of int
        Target shape ``(H, W, ...)``.

    Returns
    -------
    tuple or None
        ``(pixels (S, S, 4) float32, valid (S, S) bool, base (S, S) bool,
        origin (x, y), inverse (2, 3))``, bilinearly resampled; on
        stretches at most ~3 px wide the nearest source pixel where it is
        solid and the interpolation is not (a thin tip stays whole; beyond
        the paper).
    """
    (rs, cs) = part.box
    crop = premult[rs, cs]
    region = (part.mask | part.base).astype(np.float32)
    hh, ww = region.shape
    corners = np.array([[cs.start, rs.start], [cs.stop, rs.start], [cs.start, rs.stop],
                        [cs.stop, rs.stop]], float)
    moved = corners @ forward[:, :2].T + forward[:, 2]
    x0, y0 = np.floor(moved.min(axis=0)).astype(int) - 1
    x1, y1 = np.ceil(moved.max(axis=0)).astype(int) + 1
    H, W = shape[:2]
    if x1 <= 0 or y1 <= 0 or x0 >= W or y0 >= H:
        return None
    size = int(max(x1 - x0, y1 - y0))
    # target pixel (x0 + u, y0 + v) -> source (crop coordinates)
    rot = forward[:, :2]
    inv_rot = rot.T
    inv_t = -inv_rot @ forward[:, 2]
    inverse = np.hstack([inv_rot, inv_t[:, None]])
    m = inverse.copy()
    m[:, 2] = inverse[:, 2] + inv_rot @ np.array([x0, y0], float) - np.array([cs.start, rs.start], float)
    flags = cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP
    pix = cv2.warpAffine(crop, m, (size, size), flags=flags, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    stack = np.dstack([part.mask, part.base]).astype(np.float32)
    lab = cv2.warpAffine(stack, m, (size, size), flags=flags, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    valid = (lab[..., 0] + lab[..., 1]) > 0.5
    # A part's thin end (1-2 px under a soft alpha) interpolated between pixel centres fell
    # under alpha 0.5 and out of ``valid``: a carried tine ended cut square at 150 px. On
    # thin stretches the nearest source pixel is kept where it is solid (as in fetch).
    near_flags = cv2.INTER_NEAREST | cv2.WARP_INVERSE_MAP
    thin = _thin(crop[..., 3]) & (region > 0)
    if thin.any():
        nthin = cv2.warpAffine(thin.view(np.uint8), m, (size, size), flags=near_flags,
                               borderMode=cv2.BORDER_CONSTANT, borderValue=0) > 0
        near = cv2.warpAffine(crop, m, (size, size), flags=near_flags, borderMode=cv2.BORDER_CONSTANT,
                              borderValue=0)
        keep = nthin & (near[..., 3] > 0.5) & (pix[..., 3] < 0.5)
        pix[keep] = near[keep]
        valid |= keep
    base = valid & (lab[..., 1] > lab[..., 0])
    del hh, ww
    return pix.astype(np.float32), valid, base, (int(x0), int(y0)), inverse


def _eroded_by_disk(mask: np.ndarray, r: int) -> np.ndarray:
    """``ndi.binary_erosion(mask, disk(r))`` (outside the array counts as False), exactly: a
    pixel stays when no False pixel lies within ``r`` px (distance transforms, whose cost does
    not grow with ``r``: a palm's ~57 px disk took SciPy 4 s on a 600 px hand)."""
    if not mask.any():
        return np.zeros(mask.shape, bool)
    return _edt(np.pad(mask, 1))[1:-1, 1:-1] > r


def _dilated_by_disk(mask: np.ndarray, r: int) -> np.ndarray:
    """``ndi.binary_dilation(mask, disk(r))``, exactly: within ``r`` px of a True pixel."""
    if not mask.any():
        return np.zeros(mask.shape, bool)
    if mask.all():
        return np.ones(mask.shape, bool)
    return _edt(~mask) <= r


def _opened_by_disk(mask: np.ndarray, r: int) -> np.ndarray:
    """``ndi.binary_opening(mask, structure=disk(r))``, exactly."""
    return _dilated_by_disk(_eroded_by_disk(mask, r), r)


def _closed_by_disk(mask: np.ndarray, r: int) -> np.ndarray:
    """``ndi.binary_closing(mask, structure=disk(r))``, exactly."""
    return _eroded_by_disk(_dilated_by_disk(mask, r), r)
