"""Refining and tracing the carried-over branches on the exemplar's ridges (step 4 of
:mod:`branchnb.leaves.snapping`: the polar trace, and the smooth displacement refinement)."""

from __future__ import annotations

import numpy as np

from ..core.image import as_mask
from ..core.morphology import _binary_erosion, fill_holes
from ..core.warp import _remap_points
from .snapping_fit import _densify, _pivot_ends, _stamp


def refine_carried(chains, evidence, blade, *, reach: float, nodes: int = 5, iterations: int = 40):
    """Carried-over branches moved by one smooth displacement field onto the exemplar's ridges.

    A registration of outlines and edge keypoints is loose inside the blade:
    a carried-over primary vein of a maple can run 10-25 px (10-20 % of the
    leaf) beside the exemplar's own. The branches are a template of the
    layer: a displacement field on a ``nodes`` x ``nodes`` grid over their
    bounding box (bilinear between nodes, so neighbouring branches move
    together) climbs the evidence blurred at decreasing scales (``reach /
    2``, ``reach / 4``, ``reach / 8``: a wide basin first, then the ridge
    itself); after each step the field is smoothed over the grid and
    clipped to ``reach`` px.

    Returns the moved chains (same order and lengths).

    Parameters
    ----------
    chains : list of (N, 2) array_like
        Carried-over branches ``(x, y)`` on the exemplar.
    evidence : (H, W) float ndarray
        :func:`~branchnb.leaves.snapping_evidence.ridge_evidence` of the exemplar.
    blade : (H, W) bool ndarray
        The exemplar's blade (not used by the field itself).
    reach : float
        Largest displacement in pixels; 0: the chains are returned as they are.
    nodes : int
        Grid nodes per side of the displacement field (default 5).
    iterations : int
        Gradient steps per blur scale (default 40).

    Returns
    -------
    list of (N, 2) float64 ndarray
    """
    import cv2
    ev = np.asarray(evidence, np.float32)
    pts = [np.asarray(c, np.float64) for c in chains]
    if not pts or reach <= 0:
        return pts
    allp = np.concatenate(pts)
    lo, hi = allp.min(0), allp.max(0)
    span = np.maximum(hi - lo, 1.0)
    g = max(2, int(nodes))
    # Bilinear weights of every point on the node grid.
    u = np.clip((allp - lo) / span * (g - 1), 0, g - 1 - 1e-9)
    i0 = np.floor(u).astype(int)
    f = u - i0
    n = len(allp)
    wts = np.zeros((n, g * g))
    rows = np.arange(n)
    for dy in (0, 1):
        for dx in (0, 1):
            k = (i0[:, 1] + dy) * g + (i0[:, 0] + dx)
            wts[rows, k] += (f[:, 0] if dx else 1 - f[:, 0]) * (f[:, 1] if dy else 1 - f[:, 1])
    mass = wts.sum(0)
    disp = np.zeros((g * g, 2))
    for sigma in (reach / 2.0, reach / 4.0, reach / 8.0):
        s = max(float(sigma), 0.7)
        blur = cv2.GaussianBlur(ev, (0, 0), s)
        gy, gx = np.gradient(blur)
        step = max(0.25, s / 4.0)
        for _ in range(int(iterations)):
            q = (allp + wts @ disp).astype(np.float32)
            sx = _remap_points(gx, q[:, 0], q[:, 1], border_mode=cv2.BORDER_CONSTANT)
            sy = _remap_points(gy, q[:, 0], q[:, 1], border_mode=cv2.BORDER_CONSTANT)
            grad = wts.T @ np.column_stack([sx, sy]) / np.maximum(mass, 1e-9)[:, None]
            norm = float(np.abs(grad).max())
            if norm <= 1e-12:
                break
            disp += step * grad / norm
            # Smooth over the grid (a membrane): neighbouring nodes move alike.
            d = disp.reshape(g, g, 2)
            pad = np.pad(d, ((1, 1), (1, 1), (0, 0)), mode="edge")
            nb = (pad[:-2, 1:-1] + pad[2:, 1:-1] + pad[1:-1, :-2] + pad[1:-1, 2:]) / 4.0
            d = 0.5 * d + 0.5 * nb
            length = np.hypot(d[..., 0], d[..., 1])
            d *= np.minimum(1.0, reach / np.maximum(length, 1e-9))[..., None]
            disp = d.reshape(-1, 2)
    moved = allp + wts @ disp
    out, k = [], 0
    for c in pts:
        out.append(moved[k:k + len(c)])
        k += len(c)
    return out





def trace_branches(chains, maps, blade, *, max_angle: float = 30.0, step_deg: float = 1.0, r0: float = 3.0,
                   slope: float = 0.3, prior: float = 0.15, overlap_px: float = 3.0, extend: float = 1.5,
                   keep_level: float = 0.25):
    """Each branch re-traced from its junction along the exemplar's ridge (beyond the paper).

    A primary vein runs from its junction (the petiole junction of a maple's
    star, or the midrib for a pinnate leaf's laterals) outwards, nearly
    straight. A template pose (:func:`~branchnb.leaves.snapping_fit.fit_branches`) keeps the training
    leaf's angles between the branches, but a narrow maple's steep laterals
    open 15-30 degrees wider on a broad one. So each branch is traced
    anew in polar coordinates about its junction: at every radius
    ``r`` (1 px steps, out to ``extend`` times the branch's carried chord)
    an angle within
    ``max_angle`` degrees of the carried direction, by dynamic programming
    maximising the summed oriented ridge score along the radial direction
    (``maps``, :func:`~branchnb.leaves.snapping_fit._oriented_maps`), the angle changing by at most
    ``slope`` px sideways per px outwards (so a path bends as a vein bends
    but cannot zig-zag along texture), minus ``prior`` times the final
    angle's deviation over ``max_angle``. Branches are traced longest
    first; pixels within ``overlap_px`` of a traced branch (beyond 6 px
    from its junction) score -0.5 for the next: two branches never take one
    vein. The trace ends (at least half the carried chord out) where its
    summed score less ``keep_level`` times its mean score over the carried
    chord is largest: a vein is followed as far as it shows on this leaf,
    not as far as the user traced it on the training leaf. A hole in the
    blade is crossed (its pixels score 0); the trace ends only where it
    leaves the blade's outline.
    **Damage across a vein** (:func:`_crease_end`): where the trace comes
    within :data:`CREASE_TOUCH` px of a crease or tear (a hole, or a line of
    holes, spanning :data:`CREASE_EXTENT` of the leaf size; pinholes and
    specks are not damage) and its score beyond the damage stays under
    :data:`CREASE_RATIO` of its mean before, it ends there: sample maple
    07's midrib fades past a crease of 1-2 px holes, and the trace ran on
    along blade texture to the training vein's length. ``_measure
    maples``: 01 -> 07 0.647 -> 0.726, 02 -> 07 0.629 -> 0.692, 03 -> 06
    0.700 -> 0.809, the other 39 pairs identical (without the extent
    rule, the ratio 0.5 cut maple 03's laterals at pinholes: 01 -> 03
    0.842 -> 0.777; with a ratio of 0.75, maple 05's veins past its
    cracks: 03 -> 05 0.786 -> 0.694).

    Measured on the sample maples (``_measure maples``, each as training
    leaf): mean induced-vein IoU 0.57 with ``keep_level`` 0.5 and 0.62 with
    0.25 (0.62 at 0.15 too); ``max_angle`` 40 gave no gain (0.56),
    ``extend`` 2 lost (0.59 against 0.60 at 0.35). Once ``slope`` was
    honoured far from the junction (it used to allow one angular step per
    radius, 3.5 px sideways per px at r = 200, and a trace across a grass
    blade's parallel veins climbed from vein to vein in a staircase):
    mean 0.63 at 0.5, 0.61 at 1.0, 0.64 at 0.3 (every maple as training
    leaf 0.59-0.71, procedural min 0.70-0.75 unchanged).

    Parameters
    ----------
    chains : list of (N, 2) ndarray
        Branches already posed on the exemplar (x, y).
    maps : (K, H, W) ndarray
        Ridge score per tangent direction ``pi k / K`` (:func:`~branchnb.leaves.snapping_fit._oriented_maps`).
    blade : (H, W) bool ndarray
        The exemplar's blade; a trace ends where it leaves it.
    max_angle : float
        Largest turn (degrees) of a branch about its junction.
    step_deg : float
        Angular step (degrees) of the polar grid.
    r0 : float
        First radius (px) scored: the junction's own blob is skipped.
    slope : float
        Largest sideways move (px) per px outwards.
    prior : float
        Penalty of the final angle's deviation (over ``max_angle``) against the mean score.
    overlap_px : float
        Radius (px) around a traced branch the next ones avoid.
    extend : float
        How far out (times the carried chord) a branch may be followed.
    keep_level : float
        The trace ends where its score stays below this fraction of its mean.

    Returns
    -------
    list of (M, 2) float ndarray
        The traced branches, each from its junction outwards (a branch
        without a junction, or shorter than 8 px, is returned unchanged).

    Examples
    --------
    >>> import numpy as np
    >>> def ray(deg, n):                                 # n px from the junction (40, 75)
    ...     r = np.arange(n)[:, None]
    ...     return np.array([40.0, 75.0]) + r * [np.cos(np.radians(deg)), np.sin(np.radians(deg))]
    >>> maps = np.zeros((16, 80, 80), np.float32)
    >>> v = np.round(ray(-70, 60)).astype(int); maps[:, v[:, 1], v[:, 0]] = 1.0   # the exemplar's vein
    >>> out = trace_branches([ray(-95, 60), ray(180, 20), ray(0, 20)], maps, np.ones((80, 80), bool))
    >>> tip = out[0][-1]; round(float(np.degrees(np.arctan2(tip[1] - 75, tip[0] - 40))))
    -70
    """
    from ._snapkernels import polar_dp  # compiled DP over radius
    maps = np.asarray(maps, np.float32)
    k_dirs, h, w = maps.shape
    blade = as_mask(blade, shape=(h, w), name="blade")
    cs = [np.asarray(c, np.float64) for c in chains]
    if len(cs) < 2:
        return cs
    pe = _pivot_ends(cs)
    lengths = [float(np.hypot(*np.diff(c, axis=0).T).sum()) if len(c) > 1 else 0.0 for c in cs]
    out = list(cs)
    placed = np.zeros((h, w), bool)
    inner = _binary_erosion(blade)
    whole = fill_holes(blade)
    crease = _crease_distance(blade, whole)
    da = np.radians(step_deg)
    offs = np.arange(-max_angle, max_angle + 1e-9, step_deg)
    for i in np.argsort(lengths)[::-1]:
        pivot, far = pe[i]
        radius = float(np.hypot(*(far - pivot)))
        if lengths[i] < 8 or radius < 8:
            continue
        # The branch's carried extent along its chord (a curved vein's chord is shorter than its length).
        n_r = int(np.ceil(extend * radius))
        rs = np.arange(r0, n_r + 1e-9, 1.0)
        phi0 = np.arctan2(far[1] - pivot[1], far[0] - pivot[0])
        ang = phi0 + np.radians(offs)
        px = pivot[0] + rs[:, None] * np.cos(ang)[None]
        py = pivot[1] + rs[:, None] * np.sin(ang)[None]
        ix, iy = np.round(px).astype(int), np.round(py).astype(int)
        ok = (ix >= 0) & (ix < w) & (iy >= 0) & (iy < h)
        ix, iy = np.clip(ix, 0, w - 1), np.clip(iy, 0, h - 1)
        kk = (np.round(np.mod(ang, np.pi) / (np.pi / k_dirs)).astype(int) % k_dirs)[None].repeat(len(rs), 0)
        s = np.where(ok & inner[iy, ix], maps[kk, iy, ix], 0.0)
        near = ok & placed[iy, ix] & (rs[:, None] > 6.0)
        s = np.where(near, -0.5, s)
        # DP over radius: the angle index may change by m(r) steps per radial step.
        # Sideways budget: ``slope`` px per px outwards. Far out one angular
        # step is wider than that (1 deg is 3.5 px at r = 200), so the step
        # is only allowed once the budget since the last allowed step covers
        # it; a budget of one step per radius let a trace across parallel
        # veins climb from one to the next in a staircase.
        v, back, single = polar_dp(np.ascontiguousarray(s, np.float32), np.ascontiguousarray(rs, np.float64),
                                   float(da), float(slope))
        if single:
            v = v.astype(np.float32)  # never a step: summed in float32, as NumPy did
        final = v / len(rs) - prior * np.abs(offs) / max(max_angle, 1e-9)
        a = int(np.argmax(final))
        path = np.empty(len(rs), np.int32)
        for j in range(len(rs) - 1, -1, -1):
            path[j] = a
            a = back[j, a]
        jj = np.arange(len(rs))
        # Where the vein ends: the length (at least half the carried one)
        # that maximises the summed score less keep_level times the score's
        # mean over the carried length (a vein fades out; texture beyond it
        # scores below half a vein).
        sp = s[jj, path]
        inner_n = max(1, int(np.searchsorted(rs, radius)))
        tau = keep_level * max(float(sp[:inner_n].mean()), 1e-3)
        gain = np.cumsum(sp - tau)
        lo = int(np.searchsorted(rs, 0.5 * radius))
        end = lo + int(np.argmax(gain[lo:])) + 1 if lo < len(rs) else len(rs)
        if crease is not None:
            end = _crease_end(sp, crease[iy[jj, path], ix[jj, path]], lo, end)
        jj = jj[:end]
        path = path[:end]
        tr = np.column_stack([px[jj, path], py[jj, path]])
        tr = np.vstack([pivot, tr])
        # Stop where the trace leaves the blade (a junction in the blade's
        # notch may start just outside it); a hole in the blade (a damaged
        # leaf) is crossed, not an end: a vein runs on past it.
        tx = np.clip(np.round(tr[:, 0]).astype(int), 0, w - 1)
        ty = np.clip(np.round(tr[:, 1]).astype(int), 0, h - 1)
        inside = whole[ty, tx]
        first = int(np.argmax(inside)) if inside.any() else len(tr)
        after = ~inside[first:]
        stop = first + int(np.argmax(after)) if after.any() else len(tr)
        tr = tr[:max(stop, 2)]
        out[i] = tr if np.allclose(cs[i][0], pivot) else tr[::-1]
        d, _ = _densify(tr)
        _stamp(placed, np.clip(np.round(d[:, 1]).astype(int), 0, h - 1),
               np.clip(np.round(d[:, 0]).astype(int), 0, w - 1), int(round(overlap_px)))
    return out


#: A trace that passes within this many px of a hole in the blade (a crease or tear across the vein) ...
CREASE_TOUCH = 3.0
#: ... ends there when its score beyond (outwards) is below this share of its mean score before (0: off) ...
CREASE_RATIO = 0.5
#: ... over at least this many px beyond.
CREASE_MIN = 8
#: Damage is a hole, or a line of holes within 2 px of each other, spanning at least this share of the leaf
#: size (``sqrt`` of the blade's area); smaller ones are pinholes and specks.
CREASE_EXTENT = 0.05


def _crease_distance(blade, whole):
    """Distance (px) of every pixel to a hole in the blade, or None: no holes, or holes that are texture.

    Holes whose :data:`~branchnb.leaves.snapping_maps.HOLE_RIM` rims cover more than
    :data:`~branchnb.leaves.snapping_maps.HOLE_SHARE` of the blade are a speckled blade's texture
    (maple 04's 334 specks), not damage: None.
    """
    from scipy import ndimage as ndi

    from .snapping_maps import HOLE_RIM, HOLE_SHARE
    if CREASE_RATIO <= 0:
        return None
    holes = whole & ~blade
    if not holes.any():
        return None
    rim = ndi.binary_dilation(holes, iterations=max(1, int(HOLE_RIM))) & blade
    if rim.sum() > HOLE_SHARE * max(int(blade.sum()), 1):
        return None
    # A crease of 1-2 px holes in a line is one piece of damage.
    groups, n = ndi.label(ndi.binary_dilation(holes, iterations=2))
    boxes = ndi.find_objects(np.where(holes, groups, 0), max_label=n)
    need = CREASE_EXTENT * np.sqrt(float(blade.sum()))
    big = [k + 1 for k, bx in enumerate(boxes)
           if bx is not None and np.hypot(bx[0].stop - bx[0].start, bx[1].stop - bx[1].start) >= need]
    if not big:
        return None
    return ndi.distance_transform_edt(~(holes & np.isin(groups, big)))


def _crease_end(score, dist, lo: int, end: int) -> int:
    """Where a trace ends when it meets damage: the first radius (from ``lo`` on, before ``end``) within
    :data:`CREASE_TOUCH` px of a hole beyond which the trace's ``score`` stays below :data:`CREASE_RATIO`
    of its mean before (beyond the paper).

    A vein broken by a crease or tear of the blade (a line of 1-2 px holes across it: sample maple
    07's midrib half way up) fades past it, yet a trace, ending where its summed score is largest,
    runs on along the faint blade texture to the carried length. A vein running beside a hole (07's
    right lateral, 2 px from a crack along it) keeps its score beyond the hole and runs on. ``score``
    and ``dist`` are per radius along the trace, from the junction out.

    >>> import numpy as np
    >>> s = np.r_[np.full(30, 0.6), np.full(20, 0.1)]
    >>> d = np.full(50, 9.0); d[30] = 1.0
    >>> _crease_end(s, d, 10, 50), _crease_end(np.full(50, 0.6), d, 10, 50)
    (30, 50)
    """
    dist = np.asarray(dist)
    touch = dist[:end] <= CREASE_TOUCH
    for j in np.flatnonzero(touch[lo:]) + lo:
        if j < 1 or (j > lo and touch[j - 1]):
            continue
        # Beyond: from where the trace has left the damage (its dark rim scores as a ridge).
        off = np.flatnonzero(~touch[j:])
        k = j + int(off[0]) if len(off) else end
        if end - k < CREASE_MIN:
            continue
        if float(np.mean(score[k:end])) < CREASE_RATIO * float(np.mean(score[:j])):
            return int(j)
    return end

