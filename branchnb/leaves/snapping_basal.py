"""Branches of the petiole junction the snapping lost, found by rays from the junction (step 6b of
:mod:`branchnb.leaves.snapping`, beyond the paper).

A palmate leaf's primaries leave one junction (a maple's star: the midrib,
two laterals and two basal veins). The template fit and the trace place the
training layer's branches near where the registration carries them; a basal
vein that runs at a wider angle on the exemplar (nearly at right angles to
the midrib on sample maples 04 and 07) lies farther from its carried place
than the path tube reaches, and the snapping finds nothing there: the vein
is lost.

By topology: the training layer's branches leaving its junction
(:func:`junction_star`) are counted per side of the leaf's axis (the
junction towards the blade's centroid); on the exemplar, the snapped
network's branches leaving the carried junction are counted the same way
(:func:`leaving_directions`). Where a side has fewer, the missing training
branch is searched for by rays from the exemplar's junction
(:func:`ray_scores`: the oriented ridge score along each ray, within
:data:`RAY_WINDOW` degrees of its angle to the axis on the training leaf and
away from the branches found), traced on from the best ray
(:func:`~branchnb.leaves.snapping_trace.trace_branches`) and snapped by the
path search (:func:`~branchnb.leaves.snapping.snap_layer`). A ray is taken
only when it scores at least :data:`RAY_LEVEL` of the exemplar's found
branches' own rays: a vein, not blade texture. Rays start about the junction
and along the network within :data:`~branchnb.leaves.snapping_basal.basal_branches`'s
``shift`` of it (training maple 05's basal veins join its midrib 14 px above
the junction, so the junction found on an exemplar moves by as much). Only
branches at least :data:`BASAL_ANGLE` degrees from the midrib (basal veins)
are searched for, and only beside a found lateral of their side. Nothing is
searched where the training layer has no branch: no vein is invented.

Measured (``python -m branchnb.leaves._measure maples``, 42 pairs, each sample
maple as training leaf): mean IoU 0.690 -> 0.701, pairs under 0.6 7 -> 4;
01 -> 04 0.58 -> 0.65, 01 -> 07 0.53 -> 0.66, 05 -> 04 0.49 -> 0.68, 05 -> 07
0.35 -> 0.41, every other pair unchanged (to 0.005). ``_measure snapping``
(procedural lobed, trilobed, elliptic at 192 / 384 px): unchanged, min / mean
0.74-0.79 / 0.80-0.85 - their traced layers' primaries are cut into short
branches by the secondaries, so no star is found and the step does not run.
Tried: the centroid direction as the frame (a torn lobe tilts it: 01 -> 07
matched the left lateral to the basal vein), the laterals searched too
(02 -> 07 0.60 -> 0.56), :data:`RAY_LEVEL` 0.5 with rays from the junction alone (02 -> 07 0.60 -> 0.53, 06 -> 07
0.67 -> 0.63).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

#: A branch whose ray scores at least this share of the median ray score of the branches found at the
#: exemplar's junction is taken (0: the step is off).
RAY_LEVEL = 0.9

#: Half-width (degrees) of the window of angles searched about a missing branch's angle on the training leaf.
RAY_WINDOW = 35.0

#: Only training branches at least this far (degrees) from the midrib are searched for (basal veins);
#: a missing lateral (sample maple 07's torn lobe) is searched for on a found network too poor to
#: measure against (training maple 02 -> 07: IoU 0.60 -> 0.56 with laterals searched too).
BASAL_ANGLE = 60.0

#: Rays closer than this (degrees) to a branch found at the junction are not searched.
RAY_APART = 15.0


def _angle(v) -> np.ndarray:
    return np.arctan2(np.asarray(v)[..., 1], np.asarray(v)[..., 0])


def _wrap(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def junction_star(chains, blade, *, reach: float = 0.12, leave: float = 0.2):
    """The training layer's petiole junction and the branches that leave it.

    The junction is the mean of the densest cluster of branch ends (ends
    within ``reach`` of the leaf size of one another); a branch leaves it
    when one of its ends lies in the cluster and it reaches ``leave`` of the
    leaf size beyond it (a short stem between two nearby junctions does not).

    Parameters
    ----------
    chains : list of (N, 2) ndarray
        The layer's main branches (x, y), e.g. from :func:`~branchnb.leaves.snapping.main_branches`.
    blade : (H, W) bool ndarray
        The leaf's blade.
    reach, leave : float
        Cluster radius and the least reach beyond it, as fractions of the leaf size.

    Returns
    -------
    dict or None
        ``centre`` (x, y), ``axis`` (angle of the junction -> blade centroid
        direction, radians), ``index`` (the leaving branches), ``angles``
        (their directions relative to the axis, radians, in ``(-pi, pi]``),
        ``lengths`` (their lengths, px). None when fewer than three branches
        leave one point (no star: a pinnate leaf's midrib base).

    Examples
    --------
    >>> import numpy as np
    >>> b = np.zeros((100, 100), bool); b[10:80, 10:90] = True
    >>> def ray(deg, n):
    ...     r = np.arange(n)[:, None]
    ...     return np.array([50.0, 75.0]) + r * [np.cos(np.radians(deg)), np.sin(np.radians(deg))]
    >>> s = junction_star([ray(-90, 60), ray(-45, 40), ray(-135, 40), ray(180, 35)], b)
    >>> len(s["index"]), np.round(np.degrees(s["angles"] - s["angles"][0])).astype(int).tolist()   # about the midrib
    (4, [0, 45, -45, -90])
    """
    cs = [np.asarray(c, np.float64) for c in chains if len(c) >= 2]
    b = np.asarray(blade, bool)
    if len(cs) < 3 or not b.any():
        return None
    size = float(np.sqrt(b.sum()))
    ends = np.array([[c[0], c[-1]] for c in cs]).reshape(-1, 2)
    d = np.hypot(*(ends[:, None] - ends[None]).transpose(2, 0, 1))
    near = d <= reach * size
    centre = ends[near[int(np.argmax(near.sum(1)))]].mean(0)
    ys, xs = np.nonzero(b)
    axis = float(np.arctan2(ys.mean() - centre[1], xs.mean() - centre[0]))
    idx, angles, lengths = [], [], []
    for i, c in enumerate(cs):
        de = np.hypot(*(c[[0, -1]] - centre).T)
        if de.min() > reach * size:
            continue
        c = c if de[0] <= de[1] else c[::-1]
        r = np.hypot(*(c - centre).T)
        if r.max() < (reach + leave) * size:
            continue
        # The branch's direction where it leaves the junction's neighbourhood.
        k = int(np.argmax(r >= min(leave * size, r.max())))
        idx.append(i)
        angles.append(float(_wrap(_angle(c[k] - centre) - axis)))
        lengths.append(float(np.hypot(*np.diff(c, axis=0).T).sum()))
    if len(idx) < 3:
        return None
    return dict(centre=centre, axis=axis, index=idx, angles=np.array(angles), lengths=np.array(lengths))


def leaving_directions(found, centre, axis: float, size: float, *, ring=(0.12, 0.22), min_px: int = 3,
                       gap: float = 10.0) -> np.ndarray:
    """Directions (relative to ``axis``, radians) of the branches of ``found`` that leave ``centre``.

    The pixels of ``found`` in a ring (``ring``, fractions of the leaf size)
    about the junction, connected to it through ``found``, grouped by angle
    (split at gaps wider than ``gap`` degrees); each group of at least ``min_px``
    pixels is one branch.

    Parameters
    ----------
    found : (H, W) bool ndarray
        The snapped network on the exemplar.
    centre : (2,) array_like
        The exemplar's junction (x, y).
    axis : float
        The leaf's axis angle (radians).
    size : float
        The leaf size (px).
    ring : (2,) tuple of float
        Inner and outer radius of the ring, as fractions of ``size``.
    min_px : int
        Fewest pixels of a branch's group.
    gap : float
        Angle gap (degrees) that splits two branches.

    Returns
    -------
    (K,) float ndarray
        One angle per branch (its group's pixel-weighted mean).
    """
    f = np.asarray(found, bool)
    # A window about the junction: the ring and a margin.
    rad = int(np.ceil(ring[1] * size)) + 2
    x0, y0 = max(int(centre[0]) - rad, 0), max(int(centre[1]) - rad, 0)
    f = f[y0:int(centre[1]) + rad + 1, x0:int(centre[0]) + rad + 1]
    h, w = f.shape
    cx, cy = float(centre[0]) - x0, float(centre[1]) - y0
    yy, xx = np.mgrid[0:h, 0:w]
    r = np.hypot(xx - cx, yy - cy)
    # Connected to the junction: the piece of found touching a small disk about it.
    lab, n = ndi.label(f, structure=np.ones((3, 3)))
    disk = r <= max(3.0, 0.06 * size)
    ids = np.unique(lab[disk & f])
    conn = np.isin(lab, ids[ids > 0])
    sel = conn & (r >= ring[0] * size) & (r <= ring[1] * size)
    if sel.sum() < min_px:
        return np.zeros(0)
    a = np.sort(_wrap(np.arctan2(yy[sel] - cy, xx[sel] - cx) - axis))
    # Groups of angles split at gaps wider than ``gap`` (on the circle: start after the widest gap).
    gaps = np.diff(np.concatenate([a, a[:1] + 2 * np.pi]))
    if gaps.max() <= np.radians(gap):
        return np.zeros(0)
    s0 = int(np.argmax(gaps)) + 1
    a = np.roll(a, -s0)
    cut = np.flatnonzero(np.mod(np.diff(a), 2 * np.pi) > np.radians(gap)) + 1
    out = []
    for g in np.split(a, cut):
        if len(g) >= min_px:
            out.append(float(np.arctan2(np.sin(g).mean(), np.cos(g).mean())))
    return np.array(out)


def ray_scores(maps, blade, centre, angles, r0: float, r1: float) -> np.ndarray:
    """Mean oriented ridge score along rays from ``centre`` (absolute angles, radians), radii ``r0..r1``.

    Each ray is scored along its own direction, 0 outside the blade.

    Parameters
    ----------
    maps : (K, H, W) ndarray
        Ridge scores per tangent direction
        (:func:`~branchnb.leaves.snapping_fit._oriented_maps`).
    blade : (H, W) bool ndarray
        The exemplar's blade.
    centre : (2,) array_like
        Where the rays start (x, y).
    angles : (N,) array_like
        Absolute ray angles (radians).
    r0, r1 : float
        First and last radius (px) sampled along each ray.

    Returns
    -------
    (N,) float ndarray
        Mean score per ray.
    """
    k_dirs, h, w = maps.shape
    ang = np.asarray(angles, np.float64)
    rs = np.arange(max(r0, 1.0), max(r1, r0 + 2.0), 1.0)
    px = centre[0] + rs[:, None] * np.cos(ang)[None]
    py = centre[1] + rs[:, None] * np.sin(ang)[None]
    ix, iy = np.round(px).astype(int), np.round(py).astype(int)
    ok = (ix >= 0) & (ix < w) & (iy >= 0) & (iy < h)
    ix, iy = np.clip(ix, 0, w - 1), np.clip(iy, 0, h - 1)
    kk = (np.round(np.mod(ang, np.pi) / (np.pi / k_dirs)).astype(int) % k_dirs)[None].repeat(len(rs), 0)
    s = np.where(ok & blade[iy, ix], maps[kk, iy, ix], 0.0)
    return s.mean(0)


def exemplar_junction(found, carried_centre, size: float, axis_point, *, reach: float = 0.12, n_max: int = 40):
    """The exemplar's junction: where most branches of ``found`` leave, near the carried training junction.

    Candidates: the skeleton junctions of ``found`` within ``reach`` of the
    leaf size of ``carried_centre`` (the ``n_max`` nearest) and the nearest
    pixel of ``found``; the one most branches leave
    (:func:`leaving_directions`) wins, the nearest of a tie.

    Parameters
    ----------
    found : (H, W) bool ndarray
        The snapped network on the exemplar.
    carried_centre : (2,) array_like
        The training junction carried into the exemplar (x, y).
    size : float
        The leaf size (px).
    axis_point : (2,) array_like
        The blade's centroid (x, y); the axis runs from a candidate to it.
    reach : float
        Largest distance of a candidate from ``carried_centre``, as a share of ``size``.
    n_max : int
        Most skeleton junctions tried (the nearest).

    Returns
    -------
    (2,) float ndarray or None
        The junction (x, y); None when no pixel of ``found`` lies that near.
    """
    from skimage.morphology import skeletonize
    f = np.asarray(found, bool)
    if not f.any():
        return None
    sk = skeletonize(f)
    nb = ndi.convolve(sk.astype(np.int32), np.ones((3, 3), np.int32), mode="constant") - 1
    c = np.asarray(carried_centre, np.float64)
    cands = []
    for cand, n_take in ((sk & (nb >= 3), n_max), (f, 1)):
        ys, xs = np.nonzero(cand)
        if not len(ys):
            continue
        d = np.hypot(xs - c[0], ys - c[1])
        for k in np.argsort(d)[:n_take]:
            if d[k] <= reach * size:
                cands.append((float(d[k]), np.array([xs[k], ys[k]], np.float64)))
    best = None
    for d, p in cands:
        axis = float(np.arctan2(axis_point[1] - p[1], axis_point[0] - p[0]))
        n = len(leaving_directions(f, p, axis, size))
        if best is None or n > best[0] or (n == best[0] and d < best[1]):
            best = (n, d, p)
    return None if best is None else best[2]


def basal_branches(found, star, carried_centre, maps, fine, blade, widths, scale: float, tube: float, *,
                   min_evidence: float = 0.2, level: float | None = None, window: float | None = None,
                   apart: float | None = None, overlap_px: float = 3.0, match: float = 50.0, shift: float = 0.12,
                   details: dict | None = None):
    """The training junction's branches missing from the exemplar's snapped network, found by rays.

    Parameters
    ----------
    found : (H, W) bool ndarray
        The snapped network on the exemplar.
    star : dict
        :func:`junction_star` of the training layer.
    carried_centre : (2,) array_like
        The training junction carried into the exemplar (x, y).
    maps : (K, H, W) ndarray
        Oriented ridge scores of the exemplar (:func:`~branchnb.leaves.snapping_fit._oriented_maps`).
    fine : (H, W) float ndarray
        One-pixel ridge evidence the paths are searched on (:func:`~branchnb.leaves.snapping.snap_layer`).
    blade : (H, W) bool ndarray
        The exemplar's blade.
    widths : list of float
        Width (px, on the exemplar) of each of ``star``'s leaving branches.
    scale : float
        Exemplar leaf size over the training leaf's.
    tube : float
        Radius (px) of the path search's tube.
    min_evidence : float
        Least mean evidence of a kept path.
    level, window, apart : float, optional
        :data:`RAY_LEVEL`, :data:`RAY_WINDOW`, :data:`RAY_APART` (None: those).
    overlap_px : float
        A new branch lies mostly (half) farther than this from ``found``.
    match : float
        Largest angle (degrees) between a found branch and the training branch it stands for.
    shift : float
        Rays start at the junction and at the network's skeleton pixels within this share of the leaf
        size of it.
    details : dict, optional
        Filled with what was measured (for inspection).

    Returns
    -------
    (H, W) bool ndarray
        The new branches (no pixel of ``found`` need be among them).
    """
    from .snapping import snap_layer
    from .snapping_trace import trace_branches
    level = RAY_LEVEL if level is None else float(level)
    window = np.radians(RAY_WINDOW if window is None else window)
    apart = np.radians(RAY_APART if apart is None else apart)
    b = np.asarray(blade, bool)
    out = np.zeros(b.shape, bool)
    if level <= 0 or star is None or not found.any():
        return out
    size = float(np.sqrt(b.sum()))
    ys, xs = np.nonzero(b)
    centre = exemplar_junction(found, carried_centre, size, (xs.mean(), ys.mean()))
    if centre is None:
        return out
    axis = float(np.arctan2(ys.mean() - centre[1], xs.mean() - centre[0]))
    have = leaving_directions(found, centre, axis, size)
    want = np.asarray(star["angles"])
    if details is not None:
        details.update(centre=centre, axis=axis, have=have, want=want)
    if len(have) < 3:
        return out  # no star found on the exemplar: nothing to measure the missing branches against
    # Angles about the midrib (the branch nearest the axis on either leaf): the centroid of a leaf
    # with one lobe torn or larger lies off its midrib, so the axis tilts from leaf to leaf.
    mid = float(have[int(np.argmin(np.abs(have)))])
    have = _wrap(have - mid)
    want = _wrap(want - want[int(np.argmin(np.abs(want)))])
    axis = axis + mid
    # The found branches matched to the training ones by angle (no pair farther apart than
    # ``match``); the training branches left over are missing.
    from scipy.optimize import linear_sum_assignment
    cost = np.abs(_wrap(want[:, None] - np.asarray(have)[None]))
    ri, ci = linear_sum_assignment(np.where(cost <= np.radians(match), cost, 1e3))
    matched = {int(i) for i, j in zip(ri, ci) if cost[i, j] <= np.radians(match)}
    missing = [i for i in range(len(want)) if i not in matched]
    if not missing:
        return out
    r0 = 0.06 * size
    from skimage.morphology import skeletonize
    fy, fx = np.nonzero(skeletonize(found))
    near = np.hypot(fx - centre[0], fy - centre[1]) <= shift * size
    # ... and about the junction itself (a network's skeleton stops short of where its veins meet).
    rj = max(2, int(round(0.04 * size)))
    gy, gx = np.mgrid[-rj:rj + 1, -rj:rj + 1]
    disk = np.hypot(gx, gy) <= rj
    starts = ([centre + [x, y] for x, y in zip(gx[disk], gy[disk])]
              + [np.array([x, y], np.float64) for x, y in zip(fx[near], fy[near])])
    # The found branches' own rays, scored the same way: what a vein of this leaf scores.
    ref = []
    for a in have:
        offs = np.radians(np.arange(-8, 9, 1.0))
        ref.append(max(float(ray_scores(maps, b, p, axis + a + offs, r0, 0.35 * size).max()) for p in starts))
    ref_score = float(np.median(ref))
    if details is not None:
        details.update(missing=[float(want[i]) for i in missing], ref=ref)
    taken = []
    for i in missing:
        if abs(want[i]) < np.radians(BASAL_ANGLE):
            continue  # the midrib and the laterals: within the trace's reach, never searched
        side = [j for j in range(len(want)) if np.sign(want[j]) == np.sign(want[i])
                and 0 < abs(want[j]) < np.radians(BASAL_ANGLE)]
        if side and not any(j in matched for j in side):
            # No lateral of its side leaves the exemplar's junction either: the junction is not
            # where the network's branches meet on that side (training maple 02 -> 01 took the
            # base's margin beside the petiole for a basal vein).
            continue
        length = star["lengths"][i] * scale
        offs = np.arange(-window, window + 1e-9, np.radians(1.0))
        cand = want[i] + offs
        ok = np.ones(len(cand), bool)
        for a in list(have) + taken:
            ok &= np.abs(_wrap(cand - a)) >= apart
        # Same side of the axis as the training branch.
        ok &= np.sign(_wrap(cand)) == np.sign(want[i])
        if not ok.any():
            continue
        r1 = max(r0 + 4.0, 0.5 * length)
        # From the junction and from the network's pixels near it: a training branch joined a few
        # pixels off the junction (maple 05's basal veins, 14 px up its midrib) moves the found one.
        best = (-np.inf, 0, centre)
        for p in starts:
            sc = np.where(ok, ray_scores(maps, b, p, axis + cand, r0, r1), -np.inf)
            k = int(np.argmax(sc))
            if sc[k] > best[0]:
                best = (float(sc[k]), k, p)
        score, k, start = best
        if details is not None:
            details.setdefault("rays", []).append((float(cand[k]), score, ref_score))
        if not np.isfinite(score) or score < level * ref_score:
            continue
        phi = axis + cand[k]
        rs = np.arange(0.0, length + 1.0)
        ray = start + rs[:, None] * [np.cos(phi), np.sin(phi)]
        # Traced on from the junction (a second short chain at the junction makes it the pivot).
        stub = start + np.arange(0.0, 10.0)[:, None] * [np.cos(axis), np.sin(axis)]
        traced = trace_branches([ray, stub], maps, b, overlap_px=overlap_px)[0]
        got = snap_layer(fine, b, [traced], [widths[i]], tube, min_evidence=min_evidence)[0]
        if not got.any():
            continue
        ring = ndi.binary_dilation(found | out, iterations=max(1, int(np.ceil(overlap_px))))
        if (got & ~ring).sum() < 0.5 * got.sum():
            continue
        out |= got
        taken.append(cand[k])
        if details is not None:
            details.setdefault("added", []).append(float(cand[k]))
    return out


#: A training junction within this share of the leaf size of its petiole base is held at the exemplar's
#: (:func:`_petiole_anchor`): a fourth start of the template fit, shifted by at most ANCHOR_REACH of the
#: leaf size, taken when it scores at least ANCHOR_SHARE of the best of the others (0: off).
ANCHOR_NEAR = 0.2
#: ... and only when the best of the others put the junction farther than this share of the leaf size away.
ANCHOR_MOVE = 0.08
ANCHOR_REACH = 0.05
ANCHOR_SHARE = 0.9


def _petiole_anchor(star, blade_t, blade_e, registration):
    """The petiole bases of the training leaf and an exemplar, ``(base_t, base_e)`` (x, y), or None.

    The primaries of a palmate leaf meet where its petiole joins the blade. When the training
    layer's junction (:func:`~branchnb.leaves.snapping_basal.junction_star`) lies within
    :data:`ANCHOR_NEAR` of the leaf size of the training leaf's petiole base
    (:func:`~branchnb.leaves.starts.split_petiole`), the template fit also starts with the training
    base carried onto the exemplar's own: an outline registration is least sure inside the blade,
    and the fit put training maple 04's junction 17 px above maple 07's, on a browned hole rim
    whose ridges fitted its laterals (beyond the paper). None when either leaf has no petiole.
    """
    from .starts import split_petiole
    base_t = split_petiole(blade_t)[2]
    if base_t is None:
        return None
    c = np.asarray(star["centre"], np.float64)
    if np.hypot(*(c - base_t)) > ANCHOR_NEAR * np.sqrt(float(np.count_nonzero(blade_t))):
        return None
    base_e = split_petiole(blade_e)[2]
    if base_e is None:
        return None
    return np.asarray(base_t, np.float64), np.asarray(base_e, np.float64)


def _junction_of(chains, star) -> np.ndarray:
    """Where the star's branches (``star["index"]``) meet in ``chains``: the mean of their ends nearer the others'."""
    cs = [np.asarray(chains[i], np.float64) for i in star["index"] if i < len(chains) and len(chains[i])]
    pts = []
    for k, c in enumerate(cs):
        others = np.array([q for j, o in enumerate(cs) if j != k for q in (o[0], o[-1])]).reshape(-1, 2)
        if not len(others):
            return c[0]
        pts.append(min((c[0], c[-1]), key=lambda q: float(np.hypot(*(others - q).T).min())))
    return np.mean(pts, axis=0)
