"""A lateral of the petiole junction re-aimed by its ridge evidence along its length (step 4b of
:mod:`branchnb.leaves.snapping`, beyond the paper).

The template fit (:func:`~branchnb.leaves.snapping_fit.fit_branches`) turns each branch at most
10 degrees on its own, and the polar trace (:func:`~branchnb.leaves.snapping_trace.trace_branches`)
follows the best ridge near where the template put it. When the registration squeezes one side of a
leaf (a torn lobe changes its outline: sample maple 07's left lobe), a lateral is carried 25-30
degrees off its vein, and the trace follows a secondary vein or blade texture there: training maple
04 onto 07 put its left lateral 20 degrees from 07's midrib, on a faint ridge, while 07's own left
lateral, a strong straight ridge, left the junction 48 degrees from it.

So each lateral leaving the exemplar's junction (the training star's branches but the midrib,
:func:`~branchnb.leaves.snapping_basal.junction_star`) is scored the way a vein shows: the mean
oriented ridge score along a ray from the junction over the first half of its length
(:func:`~branchnb.leaves.snapping_basal.ray_scores`), from the junction and the pixels about it.
Where a ray within :data:`AIM_WINDOW` degrees of it, on the same side of the midrib and at least
:data:`~branchnb.leaves.snapping_basal.RAY_APART` from every other branch of the star, scores at
least :data:`AIM_RATIO` times its own, the lateral is traced anew from that ray. Basal veins (at
least :data:`~branchnb.leaves.snapping_basal.BASAL_ANGLE` from the midrib) are left to
:func:`~branchnb.leaves.snapping_basal.basal_branches`: turned up to a lateral, one landed on its
secondaries (training 04 -> maple 05).

Measured (``python -m branchnb.leaves._measure maples``, 42 pairs, each sample maple as training
leaf): 04 -> 07 0.443 -> 0.544 (its left lateral on 07's own vein), 01 -> 07 0.664 -> 0.647 (the same
lateral re-aimed, ray score 2.3 times its own: its path lay on 07's vein before and after, the new
trace ends in a wider hook at the torn lobe's notch), the other 40 pairs identical; mean 0.7326 ->
0.7346, least 0.443 -> 0.493. The ratio separates: the two re-aims scored 1.53 and 2.26 times their
own, the next lateral 1.41 (07 -> 02, not re-aimed). Procedural families (``_measure snapping``):
their traced layers' primaries seldom make a star (elliptic 384 px seeds 0-1 min / mean 0.73 / 0.82
before and after).

Tried, not kept: a star path's outer tail fainter as a whole than 0.65 of the leaf's median path
evidence cut (07's hand trace stops where its midrib fades past a crease of small holes): 02 -> 07
+0.06, 06 -> 07 +0.05, 05 -> 07 +0.03, but 01 -> 02 0.825 -> 0.650, mean 0.735 -> 0.674 (the other
maples' tracings follow their veins to the lobe tips, where they fade too). Damaged tissue (holes,
rims, one-sided rims) scored as unknown (0.2) in the trace and the path search instead of 0: 04 -> 07
0.443 -> 0.418, 05 -> 07 0.493 -> 0.419 (05's right lateral joins its traced midrib 14 px above the
junction, next to 07's hole: a template matter, not the rim's).
"""

from __future__ import annotations

import numpy as np

from .snapping_basal import BASAL_ANGLE, RAY_APART, _junction_of, _wrap, ray_scores

#: A lateral is re-aimed when a ray of its window scores at least this many times its own (0: off).
AIM_RATIO = 1.5

#: Half-width (degrees) of the window of angles searched about a lateral's own direction.
AIM_WINDOW = 35.0

#: Rays start within this share of the leaf size of the template's junction (it lies a few px off).
AIM_REACH = 0.06

#: Least mean ridge score of the ray a lateral is re-aimed to (a vein, not texture).
AIM_FLOOR = 0.2


def _from_junction(c, jc):
    """The chain ordered from its end nearer ``jc``, and whether it was turned."""
    turned = np.hypot(*(c[-1] - jc)) < np.hypot(*(c[0] - jc))
    return (c[::-1] if turned else c), bool(turned)


def _direction(c, jc, r1: float) -> float:
    """Direction (radians) from ``jc`` to the first point of ``c`` at least ``r1`` from it (or its far end)."""
    r = np.hypot(*(c - jc).T)
    k = int(np.argmax(r >= r1)) if (r >= r1).any() else len(c) - 1
    return float(np.arctan2(c[k, 1] - jc[1], c[k, 0] - jc[0]))


def _reaim_laterals(chains, star, maps, blade, *, overlap_px: float = 3.0, details: dict | None = None):
    """The traced ``chains`` with the star's laterals re-aimed where a ray nearby shows a far stronger vein.

    Parameters
    ----------
    chains : list of (N, 2) ndarray
        The training layer's branches traced on the exemplar (x, y), in the training layer's order
        (``star["index"]`` indexes them).
    star : dict
        :func:`~branchnb.leaves.snapping_basal.junction_star` of the training layer.
    maps : (K, H, W) ndarray
        Oriented ridge scores of the exemplar (:func:`~branchnb.leaves.snapping_fit._oriented_maps`).
    blade : (H, W) bool ndarray
        The exemplar's blade.
    overlap_px : float
        Passed to :func:`~branchnb.leaves.snapping_trace.trace_branches`.
    details : dict, optional
        Filled with what was measured (for inspection).

    Returns
    -------
    list of (N, 2) ndarray
        The same list with re-aimed laterals replaced (each in its own end order).
    """
    from .snapping_trace import trace_branches
    out = [np.asarray(c, np.float64) for c in chains]
    if AIM_RATIO <= 0 or star is None:
        return out
    idx = [i for i in star["index"] if i < len(out) and len(out[i]) >= 2]
    if len(idx) < 3:
        return out
    b = np.asarray(blade, bool)
    size = float(np.sqrt(b.sum()))
    jc = _junction_of(out, star)
    r0 = 0.06 * size
    lengths = {i: float(np.hypot(*np.diff(out[i], axis=0).T).sum()) for i in idx}
    dirs = {i: _direction(_from_junction(out[i], jc)[0], jc, max(r0 + 4.0, 0.5 * lengths[i])) for i in idx}
    # The midrib: the training star's branch nearest the leaf's axis.
    pos = {i: k for k, i in enumerate(star["index"])}
    mid = min(idx, key=lambda i: abs(float(star["angles"][pos[i]])))
    rj = max(2, int(round(AIM_REACH * size)))
    gy, gx = np.mgrid[-rj:rj + 1, -rj:rj + 1]
    disk = np.hypot(gx, gy) <= rj
    starts = [jc + [x, y] for x, y in zip(gx[disk], gy[disk])]
    apart = np.radians(RAY_APART)
    own_offs = np.radians(np.arange(-4.0, 4.0 + 1e-9, 1.0))
    # Laterals only: a basal vein (at least BASAL_ANGLE from the midrib) turned 30 degrees up lands
    # beside a lateral, on its secondaries (training 04 -> maple 05).
    mid_angle = float(star["angles"][pos[mid]])
    laterals = [i for i in idx if i != mid
                and abs(float(_wrap(star["angles"][pos[i]] - mid_angle))) < np.radians(BASAL_ANGLE)]
    for i in sorted(laterals, key=lambda i: -lengths[i]):
        r1 = max(r0 + 4.0, 0.5 * lengths[i])
        own = max(float(ray_scores(maps, b, p, dirs[i] + own_offs, r0, r1).max()) for p in starts)
        cand = dirs[i] + np.radians(np.arange(-AIM_WINDOW, AIM_WINDOW + 1e-9, 1.0))
        side = np.sign(_wrap(dirs[i] - dirs[mid]))
        ok = np.sign(_wrap(cand - dirs[mid])) == side
        for j in idx:
            if j != i:
                ok &= np.abs(_wrap(cand - dirs[j])) >= apart
        if not ok.any():
            continue
        best = (-np.inf, 0, jc)
        for p in starts:
            sc = np.where(ok, ray_scores(maps, b, p, cand, r0, r1), -np.inf)
            k = int(np.argmax(sc))
            if sc[k] > best[0]:
                best = (float(sc[k]), k, p)
        score, k, start = best
        if details is not None:
            details.setdefault("laterals", []).append((i, float(np.degrees(dirs[i])), own,
                                                       float(np.degrees(cand[k])), score))
        if not np.isfinite(score) or score < AIM_FLOOR or score < AIM_RATIO * own:
            continue
        phi = float(cand[k])
        c, turned = _from_junction(out[i], jc)
        radius = float(np.hypot(*(c[-1] - c[0])))
        ray = start + np.arange(0.0, max(radius, 9.0) + 1.0)[:, None] * [np.cos(phi), np.sin(phi)]
        # Traced on from the junction (a second short chain at the junction makes it the pivot).
        axis = phi + np.pi
        stub = start + np.arange(0.0, 10.0)[:, None] * [np.cos(axis), np.sin(axis)]
        traced = trace_branches([ray, stub], maps, b, overlap_px=overlap_px)[0]
        out[i] = traced[::-1] if turned else traced
        dirs[i] = phi
        if details is not None:
            details.setdefault("aimed", []).append(i)
    return out
