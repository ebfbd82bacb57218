"""The petiole junction's star re-seated on the exemplar's own veins (step 4a of
:mod:`branchnb.leaves.snapping`, beyond the paper).

The template fit (:func:`~branchnb.leaves.snapping_fit.fit_branches`) poses the training layer's
branches as one template, then each on its own, on the ridges that fit them best. On a palmate leaf
the primaries leave one junction 35-50 degrees apart, about the angle the template may turn, so the
whole star can land *one vein slot over*: training maple 05 onto maple 07 put its left lateral on 07's
midrib, its left basal vein on 07's left lateral and its midrib on a faint ridge beside 07's midrib,
starting 20 px above 07's junction; the trace (:func:`~branchnb.leaves.snapping_trace.trace_branches`)
then follows each branch from the wrong start, and the re-aim
(:func:`~branchnb.leaves.snapping_aim._reaim_laterals`) scores rays from the junction, where the
misplaced branches do not start.

So the star is scored as a whole, the way its veins show on the exemplar: about every candidate
junction within :data:`STAR_REACH` of the leaf size of the placed one (and :data:`STAR_DEPTH` px inside
the blade), the mean oriented ridge score along rays (:func:`~branchnb.leaves.snapping_basal.ray_scores`,
from :data:`STAR_R0` of the leaf size out to half each branch's length, at least :data:`STAR_FLOOR` of
the longest) is taken for every whole degree; the training star (its branches' angles about its
midrib, :func:`~branchnb.leaves.snapping_basal.junction_star`) is turned through every angle within
:data:`STAR_TURN` degrees of the placed midrib's and :data:`STAR_AXIS` of the leaf's axis, each branch
taking the best ray within :data:`STAR_SLACK` degrees of its slot (a broad leaf's laterals open
wider). The best (junction, turn) sums its branches' best rays. When that sum is at least
:data:`STAR_RATIO` times the placed branches' own (each branch's ray from its own start along its own
direction), the branches off their veins are traced anew from the new junction along their rays (all
together, so no two take one vein; at least half way to the margin), and the branches already on a
vein of their own (:data:`STAR_KEEP`) are joined to the new junction. A star already on its veins
scores about its own sum and is left as it is. Only a whole star is re-seated (as many branches on
either side of the midrib): one short of a branch fits as well one slot over.

Measured (``python -m branchnb.leaves._measure maples``, 42 pairs, each sample maple as training leaf,
hand-traced veins): 04 -> 07 0.544 -> 0.659, 05 -> 07 0.493 -> 0.723, training 05 onto 01 / 02 / 03 /
04 / 06 +0.02 to +0.06, 01 -> 04 +0.02, 03 -> 04 / 06 +0.01, 01 -> 07 0.726 -> 0.703 (the one drop), the
other 29 pairs identical; mean 0.741 -> 0.754, least 0.493 -> 0.620. Procedural pinnate leaves
(``tests/leaves_pinnate.py``, a midrib and 4-8 laterals, 128-512 px): no star, unchanged (min 0.83).
Before the whole-star rule and the axis bound, training maples 06 and 07 (06's trace lacks a basal
vein, 07's left lateral stops at its torn lobe) re-seated stars one slot over: 06 -> 07 0.673 -> 0.522,
07 -> 05 0.658 -> 0.471. Tried: :data:`STAR_SLACK` 20 (two-leaf 04 -> 07 0.519 -> 0.503).
What is left on maple 07 is not the junction: the midrib traced on past the crease where its hand trace
stops (a crease ratio of 0.65 instead of 0.5 cut it, but lost 0.05-0.09 on maple 06 as exemplar) and
the right basal vein followed along blade texture.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from .snapping_basal import RAY_APART, _junction_of, _wrap, ray_scores

#: The star is re-seated when its best seat scores at least this many times the placed branches' own
#: (0: off).
STAR_RATIO = 1.25

#: Candidate junctions lie within this share of the leaf size of the placed junction.
STAR_REACH = 0.1

#: Largest turn (degrees) of the whole star from the placed midrib's direction.
STAR_TURN = 50.0

#: Largest angle (degrees) of the re-seated midrib from its training angle to the leaf's axis.
STAR_AXIS = 20.0

#: Each branch takes the best ray within this many degrees of its slot.
STAR_SLACK = 15.0

#: A placed branch whose own ray scores at least this share of its new ray's (and that points along no
#: other branch's new ray) is kept as placed, joined to the new junction.
STAR_KEEP = 0.9

#: Candidate junctions lie at least this many px inside the blade.
STAR_DEPTH = 2

#: Rays are scored out to at least this share of the star's longest placed branch.
STAR_FLOOR = 0.25

#: Rays are scored from this share of the leaf size out (the junction's own blob is skipped).
STAR_R0 = 0.06


def _toward_out(c, jc):
    """``c`` from its end nearer ``jc`` outwards, and whether it was turned."""
    c = np.asarray(c, np.float64)
    turned = np.hypot(*(c[-1] - jc)) < np.hypot(*(c[0] - jc))
    return (c[::-1] if turned else c), bool(turned)


def _ray_table(maps, blade, p, r0, r1s):
    """(n_branches, 360) mean ray scores from ``p`` per whole degree, one row per outer radius in ``r1s``."""
    ang = np.radians(np.arange(360.0))
    return np.stack([ray_scores(maps, blade, p, ang, r0, r1) for r1 in r1s])


def _circular_max(row, half: int):
    """Max of ``row`` (360 bins) over a window of ``2 half + 1`` degrees, and the degree it is at."""
    idx = (np.arange(360)[:, None] + np.arange(-half, half + 1)[None]) % 360
    vals = row[idx]
    k = np.argmax(vals, axis=1)
    return vals[np.arange(360), k], idx[np.arange(360), k]


def _to_margin(whole, p, phi) -> float:
    """Distance (px) from ``p`` along direction ``phi`` to where the ray leaves the (hole-filled) blade."""
    h, w = whole.shape
    r = np.arange(0.0, float(h + w))
    x = np.round(p[0] + r * np.cos(phi)).astype(int)
    y = np.round(p[1] + r * np.sin(phi)).astype(int)
    ok = (x >= 0) & (x < w) & (y >= 0) & (y < h)
    ok[ok] = whole[y[ok], x[ok]]
    inside = np.flatnonzero(ok)
    if not len(inside):
        return 0.0
    gone = np.flatnonzero(~ok[inside[0]:])
    return float(r[inside[0] + gone[0]]) if len(gone) else float(r[-1])


def reseat_star(chains, star, maps, blade, *, overlap_px: float = 3.0, details: dict | None = None):
    """The placed ``chains`` with the training star re-seated on the exemplar's veins where it fits far better.

    Parameters
    ----------
    chains : list of (N, 2) ndarray
        The training layer's branches posed (and traced) on the exemplar (x, y), in the training
        layer's order (``star["index"]`` indexes them).
    star : dict or None
        :func:`~branchnb.leaves.snapping_basal.junction_star` of the training layer (None: unchanged).
    maps : (K, H, W) ndarray
        Oriented ridge scores of the exemplar (:func:`~branchnb.leaves.snapping_fit._oriented_maps`).
    blade : (H, W) bool ndarray
        The exemplar's blade (its box).
    overlap_px : float
        Passed to :func:`~branchnb.leaves.snapping_trace.trace_branches`.
    details : dict, optional
        Filled with what was measured (``own``, ``best``, ``centre``, ``turn``, ``placed_centre``;
        when re-seated ``owns``, ``each`` and the ``moved`` branches).

    Returns
    -------
    list of (N, 2) ndarray
        ``chains`` with the star's branches traced anew from the new junction (each in its own end
        order), or unchanged.
    """
    from .snapping_trace import trace_branches
    out = [np.asarray(c, np.float64) for c in chains]
    if STAR_RATIO <= 0 or star is None:
        return out
    idx = [i for i in star["index"] if i < len(out) and len(out[i]) >= 2]
    if len(idx) < 3:
        return out
    maps = np.asarray(maps)
    b = np.asarray(blade, bool)
    if maps.ndim != 3 or maps.shape[1:] != b.shape:
        raise ValueError(f"maps must be (K, H, W) with blade's shape {b.shape}, got {maps.shape}")
    size = float(np.sqrt(b.sum()))
    jc = _junction_of(out, star)
    r0 = STAR_R0 * size
    pos = {i: k for k, i in enumerate(star["index"])}
    ang_t = np.array([float(star["angles"][pos[i]]) for i in idx])
    mid = int(np.argmin(np.abs(ang_t)))
    rel = np.degrees(_wrap(ang_t - ang_t[mid]))
    side = np.sign(np.delete(rel, mid))
    if (side > 0).sum() != (side < 0).sum():
        # A star short of a branch on one side (maple 06's trace has no left basal vein) fits as well one
        # slot over, its midrib on a lateral (06 -> maple 07 0.67 -> 0.52): only a whole star is re-seated.
        return out
    oriented = [_toward_out(out[i], jc) for i in idx]
    lengths = np.array([float(np.hypot(*np.diff(c, axis=0).T).sum()) for c, _ in oriented])
    # A branch traced short on the training leaf (maple 07's lateral stops at its torn lobe) is scored
    # over a quarter of the star's longest branch at least: near the junction every ridge looks alike.
    r1s = np.maximum(r0 + 4.0, np.maximum(0.5 * lengths, STAR_FLOOR * lengths.max()))
    # The placed star's own score: each branch along its own first half, from its own start.
    dirs, owns = [], []
    for (c, _), r1 in zip(oriented, r1s):
        r = np.hypot(*(c - c[0]).T)
        k = int(np.argmax(r >= r1)) if (r >= r1).any() else len(c) - 1
        phi = float(np.arctan2(c[k, 1] - c[0, 1], c[k, 0] - c[0, 0]))
        dirs.append(phi)
        owns.append(float(ray_scores(maps, b, c[0], [phi], r0, r1)[0]))
    own = float(np.sum(owns))
    mid0 = int(round(np.degrees(dirs[mid])))
    turns = mid0 + np.arange(-int(STAR_TURN), int(STAR_TURN) + 1)
    half = int(round(STAR_SLACK))
    rj = max(2.0, STAR_REACH * size)
    step = max(1, int(round(rj / 6.0)))
    gy, gx = np.mgrid[-int(rj):int(rj) + 1:step, -int(rj):int(rj) + 1:step]
    disk = np.hypot(gx, gy) <= rj
    # A junction at least STAR_DEPTH px inside the blade: from the edge of the petiole's notch a basal
    # vein's ray runs along the blade's edge and its trace leaves the blade (05 -> maple 04).
    inside = ndi.binary_erosion(ndi.binary_fill_holes(b), iterations=STAR_DEPTH)
    ys, xs = np.nonzero(b)
    cy, cx = float(ys.mean()), float(xs.mean())
    best = (-np.inf, None, None, None, None)
    for dx, dy in zip(gx[disk], gy[disk]):
        p = jc + [dx, dy]
        ix, iy = int(round(p[0])), int(round(p[1]))
        if not (0 <= ix < b.shape[1] and 0 <= iy < b.shape[0] and inside[iy, ix]):
            continue
        table = _ray_table(maps, b, p, r0, r1s)
        total = np.zeros(len(turns))
        picks = np.zeros((len(idx), len(turns)), int)
        for k in range(len(idx)):
            m, at = _circular_max(table[k], half)
            slot = (turns + int(round(rel[k]))) % 360
            total += m[slot]
            picks[k] = at[slot]
        # The midrib stays along the leaf: within STAR_AXIS of its training angle to the axis (junction
        # -> blade centroid). A training star short of a branch (maple 06's trace has no left basal
        # vein) fits as well one slot over, its midrib on a lateral (06 -> maple 05 0.70 -> 0.60).
        axis = np.degrees(np.arctan2(cy - p[1], cx - p[0])) + np.degrees(ang_t[mid])
        total = np.where(np.abs(_wrap(np.radians(turns - axis))) <= np.radians(STAR_AXIS), total, -np.inf)
        j = int(np.argmax(total))
        if total[j] > best[0]:
            best = (float(total[j]), p, int(turns[j]), picks[:, j], table[np.arange(len(idx)), picks[:, j]])
    score, p, turn, picks, each = best
    if details is not None:
        details.update(own=own, best=score, centre=None if p is None else p.tolist(), turn=turn,
                       placed_centre=jc.tolist())
    if p is None or score < STAR_RATIO * max(own, 1e-6):
        return out
    # A branch already on its vein (its own ray about as strong as its new one) stays:
    # a basal vein along the blade's edge re-started a few px off ran out of the blade (05 -> maple 04).
    # A branch on another slot's vein (05's left lateral on maple 07's midrib) is moved however strong.
    pk = np.radians(picks.astype(float))
    moved = [k for k in range(len(idx))
             if owns[k] < STAR_KEEP * each[k]
             or any(abs(float(_wrap(dirs[k] - pk[j]))) < np.radians(RAY_APART) for j in range(len(idx)) if j != k)]
    if details is not None:
        details.update(owns=np.round(owns, 2).tolist(), each=np.round(each, 2).tolist())
    if not moved:
        return out
    # The moved branches traced anew from the new junction along their rays (together: no two on one
    # vein; a short stub backwards makes the junction the pivot of a single one).
    rays = []
    whole = ndi.binary_fill_holes(b)
    for k in moved:
        c = oriented[k][0]
        phi = np.radians(float(picks[k]))
        # At least half way to the margin: a branch placed on a faint ridge was cut short there.
        radius = max(float(np.hypot(*(c[-1] - c[0]))), 0.5 * _to_margin(whole, p, phi), 9.0)
        rays.append(p + np.arange(0.0, radius + 1.0)[:, None] * [np.cos(phi), np.sin(phi)])
    if len(rays) == 1:
        phi = np.radians(float(picks[moved[0]])) + np.pi
        rays.append(p + np.arange(0.0, 10.0)[:, None] * [np.cos(phi), np.sin(phi)])
    traced = trace_branches(rays, maps, b, overlap_px=overlap_px)
    star_set = set(idx)
    rest = [np.asarray(out[j], np.float64) for j in range(len(out)) if j not in star_set and len(out[j])]
    rest_ends = np.array([q for c in rest for q in (c[0], c[-1])]).reshape(-1, 2)
    for n, k in enumerate(moved):
        t = traced[n]
        tip = oriented[k][0][-1]
        if len(rest_ends) and float(np.hypot(*(rest_ends - tip).T).min()) <= 2.0:
            # A branch that carries others at its outer end (a lateral cut at a secondary's junction, the
            # rest of it a chain of its own) keeps that end: only its junction moves.
            gap = float(np.hypot(*(tip - p)))
            t = p + np.linspace(0.0, 1.0, max(2, int(np.ceil(gap)) + 1))[:, None] * (tip - p)
        out[idx[k]] = t[::-1] if oriented[k][1] else t
    # A kept branch joins the new junction: it started at the old one (up to STAR_REACH away), and the
    # vein between them (maple 07's right lateral, training 04) was left out.
    for k in set(range(len(idx))) - set(moved):
        c, turned = oriented[k]
        gap = float(np.hypot(*(c[0] - p)))
        if gap > 1.0:
            joint = p + np.linspace(0.0, 1.0, int(np.ceil(gap)) + 1)[:-1, None] * (c[0] - p)
            c = np.vstack([joint, c])
            out[idx[k]] = c[::-1] if turned else c
    if details is not None:
        details["moved"] = [idx[k] for k in moved]
    return out
