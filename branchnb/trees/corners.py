"""Corner-matched contour correspondence for mixes (beyond the paper).

The paper pairs the resampled contours ``C_r`` of the exemplars point by point:
the same index on every contour, the crown ``R -> L`` cut into 1600 equal
chord-length steps. On round crowns that is right. On polygonal or stylised
crowns (tiered firs, zig-zag and star-like crowns, triangular poplars) it is
not: a tip of one crown is paired with the middle of a flank of the other, the
convex combination averages a tip with a flank, and every sharp tip of the mix
turns into a round lump.

Here, before the contours are combined, their **salient corners** are found
and matched, and the crown is re-sampled so that matched corners share an
index:

1. **Corners**: on the crown segment of each ``C_r``, smoothed by a Gaussian
   of ``CORNER_SMOOTH`` of the tree's height (pixel stair-steps are not
   corners), the turning angle between the chords ``CORNER_SPAN`` of the
   height back and ahead of each point; local maxima of at least
   ``CORNER_ANGLE`` degrees are corners, signed (tips turn with the contour,
   notches against it).
2. **Matching**: the tips (corners turning with the contour; the notches
   between them follow by arc length) of each exemplar are matched in order
   with those of the reference (the exemplar of largest shape weight) by
   dynamic programming (an alignment that keeps the order along the crown):
   only corners of the same sign whose positions along the crown (share of its
   arc length) differ by less than ``MATCH_SHIFT`` may match, a match scores
   ``1 - shift / MATCH_SHIFT``, the matching of highest total score wins.
3. **Re-sampling**: a corner matched in several exemplars gets one common
   index, the weighted mean of its indices in them; each exemplar's crown is
   re-sampled piecewise linearly in arc length between its matched corners
   (and the pins ``R``, ``L``), so its corners land exactly on their common
   indices. Trunk sides are left as they are.

4. **Unmatched tips** (issue 24, trees44, :func:`_tip_matched`): crowns with
   different numbers of points (a 5- and a 7-point star, a fir of 4 tiers and
   one of 6, a spiky crown and a round one) leave tips that only some
   exemplars hold. The convex combination scaled them by those exemplars'
   weights: round bumps 0.1-0.6 of the sources' tip length. Such tips are
   kept whole (a tip's offset from the chord between the notches round it is
   carried by the exemplars lacking it, where they run straight there),
   at most as many as the weighted mean of the exemplars' tip counts
   allows, those held by most weight first. The colour transfer keeps the
   kept tips opaque (:func:`_fill_tips`).

5. **Dropped tips** (issue 24, trees46): on plain (not re-inked) mixes a tip
   not kept is flattened to the chord between its notches on every contour
   holding it (and on the rims the colour transfer maps onto), so a fir of 3
   tiers mixed with one of 5 gets whole tiers, never a tier scaled by its
   holders' weight (a bump or dent 0.3-0.5 of a tier; 8-9 corners of 25-60
   degrees on the flanks of 0.7/0.3 mixes, none after). The two ends of a
   tier (tips mirrored across the apex) are kept or dropped together, and a
   dropped top tier is flattened up to the apex. Not on outlined mixes:
   there the cut left specks at the re-inked rim (flecks 0 -> 2.1 per 1000 px).
   How many (issue 24, trees48, :func:`_pick_tips`): units (a tip and its mirror) of the tips
   only some contours hold are kept, most weight then most prominent first, while the kept
   count stays within the weighted mean of the contours' tip counts + 0.5 (units held by more
   than half the weight are always kept), so the tier count follows the weight (3 and 5 tiers:
   3 at 0.2, 4 at 0.5, 5 at 0.8; it took 3 up to 0.5 and 5 from 0.65 on). A kept unit's
   stretch, for the overlap with the others, is the narrowest its holders give it. A dropped
   tip's chord band is filled where the warp still mapped it onto the holder's background
   (:func:`_fill_tips`).

A mix of crowns none of which has a tip (round, lobed, bumpy cartoon crowns
whose corners are all notches) keeps the paper's correspondence exactly.

Pixel art (issue 24, trees42): a sprite's contour is a staircase whose every
step turned more than ``CORNER_ANGLE`` at the default scale, so tips were
matched to stair-steps and mixed firs lost every tier tip. With ``grain`` (the
art-pixel size at the working size) the contour is smoothed over at least
``GRAIN_SMOOTH`` of an art pixel and the turning read over chords of at least
``GRAIN_SPAN`` art pixels, so only the drawing's own corners remain.

Outlined drawings are matched only when every crown is polygonal
(:func:`_polygonal`: its flanks run straight between its corners,
:func:`_flank_bend` at most ``POLYGON_BEND`` of the height). Matching the
frond tips of a drawn palm (curved fronds) to a conifer's tiers raised the
cross-fade of its ``"choose"`` mixes above 3 %, while outlined firs, saw and
star crowns kept no tip without it.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi
from scipy.ndimage import gaussian_filter1d

__all__: list[str] = []

#: Smoothing of the contour before the turning angle, share of the tree's height.
CORNER_SMOOTH = 0.006
#: Half-window of the turning angle (chord back and ahead), share of the tree's height.
CORNER_SPAN = 0.025
#: Least turning angle of a corner, degrees.
CORNER_ANGLE = 50.0
#: Least smoothing of a pixel-art contour, share of its art-pixel size (one stair-step).
GRAIN_SMOOTH = 0.7
#: Least half-window of the turning angle on pixel art, art pixels.
GRAIN_SPAN = 2.0
#: Least turning (degrees) of the corners a flank runs between in :func:`_flank_bend` (shallow
#: corners too: the notches of a saw-toothed crown turn less than :data:`CORNER_ANGLE`).
BEND_KNOT_ANGLE = 25.0
#: Most flank bend (:func:`_flank_bend`, share of the height) of a polygonal crown.
POLYGON_BEND = 0.006
#: Most offset of a contour's own stretch from its chord, share of the tip's height, for an
#: unmatched tip to be carried onto it (:func:`_tip_matched`).
STRAIGHT_RUN = 0.35
#: Largest shift (share of the crown's arc length) between two matched corners.
MATCH_SHIFT = 0.12


def _crown_range(n: int, pins: tuple[int, int, int]) -> tuple[int, int]:
    _, ir, il = pins
    return int(ir), int(il)


def _contour_corners(contour: np.ndarray, pins: tuple[int, int, int],
                     grain: float = 0.0, angle: float = CORNER_ANGLE) -> tuple[np.ndarray, np.ndarray]:
    """Corners on the crown ``R -> L`` of a resampled contour: their indices and signed turning
    angles in degrees (> 0: a tip, turning with the contour; < 0: a notch). ``grain``: the art-pixel
    size (px) of pixel art, whose stair-steps are no corners (smoothing at least ``GRAIN_SMOOTH``
    of it, chords at least ``GRAIN_SPAN`` of it)."""
    c = np.asarray(contour, np.float64)
    n = len(c)
    ir, il = _crown_range(n, pins)
    height = float(np.ptp(c[:, 1])) or 1.0
    step = np.hypot(*np.diff(c[ir:il + 1], axis=0).T)
    step = float(np.median(step[step > 0])) if np.any(step > 0) else 1.0
    sigma = max(CORNER_SMOOTH * height, GRAIN_SMOOTH * grain) / step
    sm = np.stack([gaussian_filter1d(c[:, k], max(sigma, 0.5), mode="wrap") for k in range(2)], axis=1)
    d = max(2, int(round(max(CORNER_SPAN * height, GRAIN_SPAN * grain) / step)))
    back = sm - np.roll(sm, d, axis=0)
    ahead = np.roll(sm, -d, axis=0) - sm
    cross = back[:, 0] * ahead[:, 1] - back[:, 1] * ahead[:, 0]
    dot = (back * ahead).sum(axis=1)
    turn = np.degrees(np.arctan2(cross, dot))
    # Orientation: tips turn like the whole loop.
    x, y = c[:, 0], c[:, 1]
    area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    turn = turn if area >= 0 else -turn
    mag = np.abs(turn)
    # Local maxima within +-d, away from the pins (trunk tops are pinned already).
    idx = np.arange(ir + d, il - d + 1)
    if idx.size == 0:
        return np.zeros(0, int), np.zeros(0)
    win = np.lib.stride_tricks.sliding_window_view(np.pad(mag, d, mode="wrap"), 2 * d + 1)[idx]
    peak = (mag[idx] >= angle) & (mag[idx] >= win.max(axis=1))
    found = idx[peak]
    if found.size > 1:   # a flat-topped maximum: keep its first point
        found = found[np.concatenate([[True], np.diff(found) > d])]
    return found.astype(int), turn[found]


def _flank_bend(contour: np.ndarray, pins: tuple[int, int, int], grain: float = 0.0) -> float:
    """How far the crown ``R -> L`` bends off the straight lines between its corners (tips and
    notches turning at least :data:`BEND_KNOT_ANGLE`): the mean distance of its points to the chord
    of their stretch, as a share of the tree's height. 0.0013-0.0043 on procedural and drawn
    polygonal crowns (firs, saw-toothed and star crowns, poplars, drawn conifers), 0.008-0.34 on
    curved ones (drawn palms' arching fronds, fruit trees, broadleaves, round and lobed crowns)."""
    c = np.asarray(contour, np.float64)
    ir, il = int(pins[1]), int(pins[2])
    idx, _ = _contour_corners(c, pins, grain, BEND_KNOT_ANGLE)
    knots = np.unique(np.concatenate([[ir], idx, [il]]))
    height = float(np.ptp(c[:, 1])) or 1.0
    dev = []
    for a, b in zip(knots[:-1], knots[1:], strict=True):
        p, q = c[a], c[b]
        seg = c[a:b + 1]
        d = q - p
        n = float(np.hypot(*d))
        if n < 1e-9:
            dev.append(np.hypot(*(seg - p).T))
        else:
            dev.append(np.abs(d[0] * (seg[:, 1] - p[1]) - d[1] * (seg[:, 0] - p[0])) / n)
    return float(np.mean(np.concatenate(dev))) / height


def _polygonal(contours, pins: tuple[int, int, int], grains=None) -> bool:
    """Every crown's flanks run straight between its corners (:data:`POLYGON_BEND`)."""
    grains = [0.0] * len(contours) if grains is None else grains
    return all(_flank_bend(c, pins, g or 0.0) <= POLYGON_BEND for c, g in zip(contours, grains, strict=True))


def _match_corners(ua: np.ndarray, sa: np.ndarray, ub: np.ndarray, sb: np.ndarray,
                  shift: float = MATCH_SHIFT) -> list[tuple[int, int]]:
    """Order-keeping matching of two corner lists (positions ``u`` along the crown in [0, 1], signs
    ``s``) of highest total score ``sum 1 - |u_a - u_b| / shift``; returns index pairs."""
    na, nb = len(ua), len(ub)
    if na == 0 or nb == 0:
        return []
    gain = 1.0 - np.abs(ua[:, None] - ub[None, :]) / shift
    gain[(np.sign(sa)[:, None] != np.sign(sb)[None, :]) | (gain <= 0)] = -np.inf
    score = np.zeros((na + 1, nb + 1))
    for i in range(1, na + 1):
        for j in range(1, nb + 1):
            score[i, j] = max(score[i - 1, j], score[i, j - 1], score[i - 1, j - 1] + gain[i - 1, j - 1])
    pairs = []
    i, j = na, nb
    while i > 0 and j > 0:
        if score[i, j] == score[i - 1, j]:
            i -= 1
        elif score[i, j] == score[i, j - 1]:
            j -= 1
        else:
            pairs.append((i - 1, j - 1))
            i, j = i - 1, j - 1
    return pairs[::-1]


def _resample_crown(c: np.ndarray, ir: int, il: int, targets: np.ndarray, own: np.ndarray) -> np.ndarray:
    """``c`` with its crown ``ir..il`` re-sampled so that its point ``own[k]`` lands on index
    ``targets[k]`` (piecewise linear in index, i.e. in arc length, between the knots)."""
    t = np.concatenate([[ir], targets, [il]]).astype(np.float64)
    o = np.concatenate([[ir], own, [il]]).astype(np.float64)
    at = np.interp(np.arange(ir, il + 1, dtype=np.float64), t, o)
    i0 = np.clip(np.floor(at).astype(int), ir, il - 1)
    f = (at - i0)[:, None]
    out = c.copy()
    out[ir:il + 1] = c[i0] * (1 - f) + c[i0 + 1] * f
    return out


def _corner_matched(contours, weights, pins: tuple[int, int, int], grains=None) -> list[np.ndarray]:
    """The contours re-sampled so that their matched crown corners share indices (module doc), and
    their unmatched tips kept or dropped (:func:`_tip_matched`).

    ``contours``: resampled contours ``C_r`` with the same pin indices ``pins`` (B, R, L);
    ``weights``: their shape weights; ``grains``: the art-pixel size of each (pixel art; None or
    0: smooth art). Contours come back unchanged (the same arrays) when no tip is found.
    """
    return _tip_matched(contours, weights, pins, grains)[0]


def _tip_extent(c: np.ndarray, pins: tuple[int, int, int], grain: float, tips: np.ndarray,
                to_tips: bool = False) -> np.ndarray:
    """(k, 3) indices (start, tip, end) of each tip of ``tips`` on contour ``c``: from the notch
    before it to the notch after it (corners turning against the contour by at least
    :data:`BEND_KNOT_ANGLE`, between it and its neighbouring tips), half way to the neighbour
    (or the pin) where there is none, or (``to_tips``) the neighbouring tip itself."""
    ir, il = int(pins[1]), int(pins[2])
    ni, nt = _contour_corners(c, pins, grain, BEND_KNOT_ANGLE)
    notches = ni[nt < 0]
    out = np.zeros((len(tips), 3), int)
    for k, t in enumerate(tips):
        lo = tips[k - 1] if k > 0 else ir
        hi = tips[k + 1] if k + 1 < len(tips) else il
        before = notches[(notches > lo) & (notches < t)]
        after = notches[(notches > t) & (notches < hi)]
        a = int(before[-1]) if before.size else int(lo if to_tips and k > 0 else (lo + t) // 2)
        b = int(after[0]) if after.size else int(hi if to_tips and k + 1 < len(tips) else (t + hi + 1) // 2)
        out[k] = (a, t, b)
    return out


def _tip_profile(c: np.ndarray, a: int, b: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The stretch ``a..b`` of ``c`` in the frame of its chord: (along-chord share, normal offset)
    per point, and the chord vector."""
    seg = c[a:b + 1]
    chord = c[b] - c[a]
    n = float(np.hypot(*chord))
    if n < 1e-9:
        return np.zeros(len(seg)), np.zeros(len(seg)), chord
    u = chord / n
    rel = seg - c[a]
    along = rel @ u / n
    normal = rel[:, 0] * -u[1] + rel[:, 1] * u[0]
    return along, normal, chord


def _tip_matched(contours, weights, pins: tuple[int, int, int], grains=None, drop: bool = True):
    """Corner matching with every tip kept or dropped: (contours to combine, matched contours,
    spans ``(start, end)`` of the kept tips in the common indices, for :func:`_fill_tips`).

    The second list is the corner-matched contours (the module doc's steps 1-3); the first is the
    same with the tips that not every weighted contour holds made whole (beyond the paper): a
    tip held by some contours only came out of the convex combination scaled by their weights, a
    short round bump (tips of a 5- and a 7-point star or of a 4- and a 6-tier fir mixed, tip
    length 0.13-0.4 of the sources'). Such tip groups are **kept**: a tip's offset from the
    chord between the notches round it replaces the same stretch of the contours that lack it
    (on their own chord), so the mix carries it whole; the others are left to the combination
    (flattening them left specks at the cut on outlined mixes). The mix keeps ``round(sum_i w_i n_i)``
    tips (``n_i`` the tips of contour ``i``, within the sources' least and most), the groups
    held by most weight first, none overlapping a kept one. A kept tip is carried only onto
    stretches that run straight (offset from their chord at most :data:`STRAIGHT_RUN` of the
    tip's height); where a contour has its own corners there, it is left to the combination.
    The matched contours (no tip added) are what the rim correction of the colour transfer maps
    onto: a tip added to a source that lacks it lies off its image.
    """
    cs = [np.asarray(c, np.float64) for c in contours]
    w = np.asarray(weights, np.float64)
    live = np.flatnonzero(w > 0)
    if len(live) < 2:
        return cs, cs, []
    ir, il = int(pins[1]), int(pins[2])
    # Tips only: notches between the tips follow by arc length. Matching notches too reshaped
    # bumpy cartoon crowns (notches between round bumps, no tip) for no gain: clip-art rim
    # roughness 0.157 -> 0.169, outline q90/q10 4.87 -> 5.07.
    grains = [0.0] * len(cs) if grains is None else [float(g or 0.0) for g in grains]
    found = [(i[t > 0], t[t > 0]) for i, t in (_contour_corners(c, pins, g) for c, g in zip(cs, grains, strict=True))]
    if all(found[j][0].size == 0 for j in live):
        return cs, cs, []
    span = float(il - ir)
    # Tip groups, the reference's first (largest weight), then each contour's in order of weight:
    # a tip joins the group it matches (order-keeping, MATCH_SHIFT) or opens a new one.
    order = live[np.argsort(-w[live], kind="stable")]
    groups: list[dict[int, int]] = []
    for j in order:
        ib, sb = found[j]
        if ib.size == 0:
            continue
        pos = np.array([np.average(list(g.values()), weights=[w[k] for k in g]) for g in groups])
        srt = np.argsort(pos, kind="stable") if groups else np.zeros(0, int)
        pairs = _match_corners((pos[srt] - ir) / span, np.ones(len(srt)), (ib - ir) / span, sb) if groups else []
        hit = set()
        for a, b in pairs:
            groups[srt[a]][int(j)] = int(ib[b])
            hit.add(b)
        groups += [{int(j): int(ib[b])} for b in range(ib.size) if b not in hit]
    groups.sort(key=lambda g: np.average(list(g.values()), weights=[w[k] for k in g]))
    # Anchors (held by two contours or more) share an index: the weighted mean of theirs.
    anchors = [g for g in groups if len(g) >= 2]
    m = np.full((len(cs), len(anchors)), -1, int)
    for a, g in enumerate(anchors):
        for k, i in g.items():
            m[k, a] = i
    has = m >= 0
    out = list(cs)
    maps = {}
    if anchors:
        wl = np.where(has, w[:, None], 0.0)
        target = np.rint((wl * np.maximum(m, 0)).sum(axis=0) / wl.sum(axis=0)).astype(int)
        for j in live:
            k = has[j]
            # a contour whose own order disagrees with the common one keeps its indices
            ok = k.any() and np.all(np.diff(m[j, k]) > 0) and np.all(np.diff(target[k]) > 0)
            if ok and not np.array_equal(m[j, k], target[k]):
                out[j] = _resample_crown(cs[j], ir, il, target[k], m[j, k])
                maps[int(j)] = (np.concatenate([[ir], m[j, k], [il]]).astype(float),
                                np.concatenate([[ir], target[k], [il]]).astype(float))
    matched = list(out)

    def new_index(j, i):
        if j not in maps:
            return int(i)
        own, tgt = maps[j]
        return int(round(float(np.interp(i, own, tgt))))

    # Each group's stretch (start, tip, end) in the common indices, read on its heaviest holder.
    n_tips = [found[j][0].size for j in live]
    keep_n = int(np.clip(round(float(np.dot(w[live], n_tips) / w[live].sum())), min(n_tips), max(n_tips)))
    ext = {int(j): _tip_extent(cs[j], pins, grains[j], found[j][0]) for j in live if found[j][0].size}
    info = []
    for g in groups:
        donor = max(g, key=lambda k: w[k])
        row = ext[donor][int(np.flatnonzero(found[donor][0] == g[donor])[0])]
        a, t, b = (new_index(donor, i) for i in row)
        held = float(sum(w[k] for k in g)) / float(w[live].sum())
        info.append((g, donor, a, t, b, held))
    full = [x for x in info if all(int(j) in x[0] for j in live)]
    rest = sorted((x for x in info if not all(int(j) in x[0] for j in live)), key=lambda x: -x[5])
    # extents meeting half way between two tips may overlap by the rounding of their midpoint
    slack = max(1, int(0.004 * span)) if drop else 0
    ref = matched[int(order[0])]
    height = float(np.ptp(ref[:, 1])) or 1.0
    apex_x = float(ref[ir + int(np.argmin(ref[ir:il + 1, 1])), 0])
    tip_at = {id(x[0]): matched[x[1]][x[3]] for x in info}

    def mirrored(x, y) -> bool:
        p, q = tip_at[id(x[0])], tip_at[id(y[0])]
        return (y is not x and abs(p[0] - apex_x) >= 0.05 * height and abs(p[1] - q[1]) < 0.04 * height
                and (p[0] - apex_x) * (q[0] - apex_x) < 0
                and abs((p[0] - apex_x) + (q[0] - apex_x)) < 0.15 * abs(p[0] - apex_x))

    if drop:
        kept = _pick_tips(full, rest, info, maps, matched, ext, found, slack, mirrored,
                          float(np.dot(w[live], n_tips) / w[live].sum()))
    else:
        kept = list(full)
        last = None
        for x in rest:
            # Groups held by the same weight go together (the left and right tier ends of a fir).
            if len(kept) >= keep_n and not (last is not None and abs(x[5] - last) < 1e-9
                                            and len(kept) < max(n_tips)):
                break
            if all(x[4] <= y[2] + slack or x[2] >= y[4] - slack for y in kept):
                kept.append(x)
                last = x[5]
    kept_ids = {id(x[0]) for x in kept}
    # Tips mirrored across the apex (the left and right ends of one fir tier) are kept or dropped
    # together: kept on one side only they left a lopsided, flag-like tier (a 3-tier fir mixed
    # 0.1/0.9 with a 5-tier one: 5 tiers on the left, 4 on the right). Dropping is always
    # possible (a flattened tip), so a kept tip whose mirror is dropped is dropped too.
    for x in info if drop else []:
        if id(x[0]) not in kept_ids or len(x[0]) == len(live):
            continue
        if any(id(y[0]) not in kept_ids and mirrored(x, y) for y in info):
            kept_ids.discard(id(x[0]))
    kept = [x for x in kept if id(x[0]) in kept_ids]
    for g, donor, a, _t, b, _ in info:
        if len(g) == len(live) or b - a < 2:
            continue
        if id(g) in kept_ids:
            for j in live:
                if int(j) in g:
                    continue
                # The donor's offset from its chord onto this contour's chord: the tip whole. Only
                # onto a straight run (STRAIGHT_RUN): over this contour's own tier ends and notches
                # the added tip crossed them (zig-zag fir feet; a fir mixed with a saw crown lost
                # 18 deg of tip sharpness); there the tip is left to the combination as before.
                c = out[j].copy()
                _, own_off, _ = _tip_profile(c, a, b)
                _, tip_off, _ = _tip_profile(matched[donor], a, b)
                if np.abs(own_off).max() > STRAIGHT_RUN * np.abs(tip_off).max():
                    continue
                s_ = np.linspace(0.0, 1.0, b - a + 1)[:, None]
                d = matched[donor]
                c[a:b + 1] = c[a] + s_ * (c[b] - c[a]) + d[a:b + 1] - (d[a] + s_ * (d[b] - d[a]))
                out[j] = c
    # A tip not kept is dropped whole: flattened to the chord between its notches on every
    # contour holding it, and on the rims the colour transfer maps onto (left to the combination
    # it came out scaled by its holders' weights, a bump or a half tier: fir mixes of 3 and 5
    # tiers kept tiers 0.3-0.5 of the sources' smallest, and read as dented flanks). The rims
    # are flattened too: the mix's chord maps inside the holder, not onto its cut-off tip's
    # rim (flattening only the mixed contour left specks at the cut, 1.3-1.7 per 1000 px of rim).
    rims = list(matched)
    # Where no notch parts a dropped tip from its neighbour (a fir's top tier and its apex) the
    # chord runs to the neighbour: half way there it pinched the crown below the apex.
    reach = {int(j): _tip_extent(cs[j], pins, grains[j], found[j][0], to_tips=True) for j in ext}
    gone = []
    for g, _donor, _a, _t, _b, _ in info:
        if len(g) == len(live) or id(g) in kept_ids or not drop:
            continue
        for j, i in g.items():
            row = reach[j][int(np.flatnonzero(found[j][0] == i)[0])]
            a_, b_ = new_index(j, row[0]), new_index(j, row[2])
            if b_ - a_ < 2:
                continue
            _, off, _ = _tip_profile(rims[j], a_, b_)
            gone.append((a_, b_, float(np.abs(off).max())))
            s_ = np.linspace(0.0, 1.0, b_ - a_ + 1)[:, None]
            for lst in (out, rims):
                c = lst[j].copy()
                c[a_:b_ + 1] = c[a_] + s_ * (c[b_] - c[a_])
                lst[j] = c
    # every kept tip, matched ones too: a tip matched across a shift (a 5-point star's upper
    # points to a 7-point star's) maps off the rim of the source it moved in
    spans = [(a, b) for g, _, a, _, b, _ in info if id(g) in kept_ids and b - a >= 2]
    return out, rims, spans + gone


def _pick_tips(full, rest, info, maps, matched, ext, found, slack: int,
               mirrored, mean_tips: float) -> list:
    """The tip groups a plain mix keeps (:func:`_tip_matched`, issue 24, trees48): every group all
    contours hold, then units of the others (a tip with its mirror across the apex: the two ends
    of a fir tier) held by most weight first, the most prominent first among equal weights,
    while the kept count stays within ``mean_tips`` (the weighted mean of the contours' tip
    counts) + 0.5 or more than half the weight holds the unit, and it overlaps no kept group.
    A group's stretch, for the overlap, is the narrowest its holders give it: read on the
    heaviest holder only, a 3-tier fir's wide tier (notch to notch) covered the 5-tier fir's
    extra tier ends, so an even mix kept none and took the 3-tier count; the 0.65 mix, read on
    the 5-tier fir, took all 5 (a step, never 4)."""
    def stretch(x):
        a, b = x[2], x[4]
        for j, i in x[0].items():
            row = ext[j][int(np.flatnonzero(found[j][0] == i)[0])]
            if j in maps:
                own, tgt = maps[j]
                row = [int(round(float(np.interp(v, own, tgt)))) for v in row]
            a, b = max(a, int(row[0])), min(b, int(row[2]))
        return a, b

    def prominence(x):
        _, off, _ = _tip_profile(matched[x[1]], x[2], x[4])
        return float(np.abs(off).max()) if off.size else 0.0

    units, seen = [], set()
    for x in rest:
        if id(x[0]) in seen:
            continue
        unit = [x] + [y for y in rest if id(y[0]) not in seen and y is not x and abs(y[5] - x[5]) < 1e-9
                      and mirrored(x, y)][:1]
        seen.update(id(u[0]) for u in unit)
        units.append(unit)
    units.sort(key=lambda u: (-u[0][5], -max(prominence(v) for v in u)))
    kept = list(full)
    where = {id(x[0]): stretch(x) for x in info}
    for unit in units:
        # a unit most of the weight holds is the mix's own (a palm's fronds in its "more like
        # this": cut to the mean count they merged into a blob, half-thickness x1.4)
        if len(kept) + len(unit) > mean_tips + 0.5 + 1e-9 and unit[0][5] <= 0.5 + 1e-9:
            continue
        if all(where[id(x[0])][1] <= where[id(y[0])][0] + slack or where[id(x[0])][0] >= where[id(y[0])][1] - slack
               for x in unit for y in kept):
            kept.extend(unit)
    return kept


def _fill_tips(image: np.ndarray, sources: np.ndarray, trunk: np.ndarray, contour: np.ndarray,
               spans, mask: np.ndarray):
    """Make the kept tips of a mix opaque (:func:`_tip_matched`'s ``spans`` of the mixed contour):
    the colour transfer keeps a pixel where the sources opaque at its mapped point hold half the
    colour weight, and a tip only some sources hold maps onto the others' background, so with
    their colour weight it came out cut off (a 4- and a 6-point star mixed: 1 tip of 3..5; tips
    matched across a shift map off the rim of the source whose tip moved, too). Its
    see-through pixels inside ``mask`` take the nearest opaque pixel's colour, source and trunk."""
    import cv2

    img = np.asarray(image, np.float32)
    opaque = img[..., 3] >= 0.5
    region = np.zeros(opaque.shape, np.uint8)
    band = np.zeros(opaque.shape, np.uint8)
    for span in spans:
        a, b = span[:2]
        if len(span) == 2:
            cv2.fillPoly(region, [np.int32(np.round(contour[a:b + 1]))], 1)
        else:
            # a dropped tip: the interior warp still maps the pixels just inside its chord onto
            # the holder's background under the cut-off tip (holes 3-6 px under a 2- and 5-tier
            # fir mix's top tier); fill within the tip's height of the chord
            cv2.polylines(band, [np.int32(np.round(contour[a:b + 1]))], False, 1,
                          thickness=max(1, int(round(2 * span[2]))))
    # holes only, off the rim: ``mask`` is the fill grown by one pixel (the rim pixels' own alpha
    # is the sources'), and an opaque rim pixel along the chord left a stair-step kink
    inner = cv2.erode(np.asarray(mask, np.uint8), np.ones((5, 5), np.uint8)) > 0
    # and only see-through pockets enclosed by the crown: filling a band that crosses a gap open
    # to the outside (between a palm's fronds) closed it into a hole
    lab, _ = ndi.label(~opaque)
    open_ = np.isin(lab, np.unique(np.concatenate([lab[0], lab[-1], lab[:, 0], lab[:, -1]])))
    hole = ((region > 0) & mask | (band > 0) & inner & ~open_) & ~opaque
    if not hole.any() or not opaque.any():
        return image, sources, trunk
    from scipy.ndimage import distance_transform_edt

    _, (iy, ix) = distance_transform_edt(~opaque, return_indices=True)
    img = img.copy()
    img[hole, :3] = img[iy[hole], ix[hole], :3]
    img[hole, 3] = 1.0
    sources = np.array(sources, copy=True)
    sources[hole] = sources[iy[hole], ix[hole]]
    trunk = np.array(trunk, copy=True)
    trunk[hole] = trunk[iy[hole], ix[hole]]
    return img, sources, trunk
