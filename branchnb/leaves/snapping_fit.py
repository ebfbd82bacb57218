"""Template fit of the training layer's main branches onto the exemplar's oriented ridges (step 3 of
:mod:`branchnb.leaves.snapping`)."""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_mask, extend_nearest
from ..core.morphology import _binary_dilation, _binary_erosion


def _densify(c):
    seg = np.hypot(*np.diff(c, axis=0).T)
    t = np.concatenate([[0.0], np.cumsum(seg)])
    s = np.linspace(0.0, t[-1], max(2, int(np.ceil(t[-1])) + 1))
    return np.column_stack([np.interp(s, t, c[:, 0]), np.interp(s, t, c[:, 1])]), float(t[-1])


def ridge_hessian(lab, blade, direction, width: float) -> np.ndarray:
    """Hessian ``(Hxx, Hxy, Hyy)`` of the colours projected on ``direction``, for oriented ridge scores.

    At scale ``sigma = max(1, width / 2)`` (times ``sigma**2``), divided by
    the 99th percentile inside the blade of the bright-ridge strength
    ``max(0, -lambda_min)``. :func:`oriented_response` then scores a ridge
    *along a given direction* only: the mottled texture of a photographed
    blade (secondary veins, spots, hole rims) crosses a primary vein's
    direction and no longer counts for it.

    Parameters
    ----------
    lab : (H, W, 3) float ndarray
        CIELAB colours of the exemplar.
    blade : (H, W) bool array_like
        Its blade; 0 outside (and two pixels inside) its outline.
    direction : (3,) ndarray
        :func:`~branchnb.leaves.snapping_evidence.contrast_direction`.
    width : float
        The layer's typical width in pixels.

    Returns
    -------
    (3, H, W) float32 ndarray
    """
    blade = as_mask(blade, shape=lab.shape[:2], name="blade")
    p = (np.asarray(lab, np.float32) @ np.asarray(direction, np.float32)).astype(np.float32)
    p = extend_nearest(p, blade)
    s = max(1.0, 0.5 * float(width))
    hxx = ndi.gaussian_filter(p, s, order=(0, 2)) * s * s
    hxy = ndi.gaussian_filter(p, s, order=(1, 1)) * s * s
    hyy = ndi.gaussian_filter(p, s, order=(2, 0)) * s * s
    lam_min = 0.5 * (hxx + hyy) - np.sqrt(0.25 * (hxx - hyy) ** 2 + hxy ** 2)
    inner = _binary_erosion(blade, iterations=2)
    strength = np.maximum(-lam_min, 0.0)[inner]
    scale = float(np.percentile(strength, 99)) if strength.size else 0.0
    out = np.stack([hxx, hxy, hyy]).astype(np.float32) / max(scale, 1e-12)
    out[:, ~inner] = 0.0
    return out


def oriented_response(hess, ix, iy, tangent) -> np.ndarray:
    """Bright-ridge score (0..1) at pixels ``(ix, iy)`` for a ridge running along ``tangent`` (unit x, y).

    The curvature across the ridge, ``-n^T H n``, less the curvature along
    it (a blob curves both ways, a vein one way only), clipped to ``[0, 1]``.

    Parameters
    ----------
    hess : (3, H, W) ndarray
        :func:`ridge_hessian`.
    ix, iy : int ndarray
        Pixel columns and rows (same shape).
    tangent : (..., 2) ndarray
        Unit direction ``(x, y)`` of the ridge at each pixel.

    Returns
    -------
    ndarray
        The shape of ``ix``.
    """
    hxx, hxy, hyy = (hh[iy, ix] for hh in hess)
    tx, ty = tangent[..., 0], tangent[..., 1]
    across = ty * ty * hxx - 2.0 * tx * ty * hxy + tx * tx * hyy
    along = tx * tx * hxx + 2.0 * tx * ty * hxy + ty * ty * hyy
    return np.clip(-across - np.abs(along), 0.0, 1.0)


def _tangents(p):
    """Unit tangents of an ordered point chain."""
    if len(p) < 2:
        return np.tile([1.0, 0.0], (len(p), 1))
    g = np.gradient(np.asarray(p, np.float64), axis=0)
    return g / np.maximum(np.hypot(*g.T), 1e-9)[:, None]


N_ORIENTATIONS = 16


def _oriented_maps(ev, hess, n: int = N_ORIENTATIONS) -> np.ndarray:
    """Pose scores per tangent direction ``pi k / n``: the weighted oriented response and evidence, (n, H, W)."""
    from ._snapkernels import oriented_maps  # compiled: the same float64 sums, one pass
    tx = np.array([np.cos(np.pi * k / n) for k in range(n)])
    ty = np.array([np.sin(np.pi * k / n) for k in range(n)])
    return oriented_maps(np.ascontiguousarray(hess, np.float32), np.ascontiguousarray(ev, np.float32), tx, ty,
                         float(ORIENTED_WEIGHT))


def _stamp(placed, iy, ix, iterations: int) -> None:
    """``placed |= binary_dilation(pixels (iy, ix), iterations)``, dilated in their bounding box only."""
    h, w = placed.shape
    if iterations < 1 or not len(iy):
        stamp = np.zeros((h, w), bool)
        stamp[iy, ix] = True
        placed |= _binary_dilation(stamp, iterations=iterations)
        return
    y0, y1 = max(int(iy.min()) - iterations, 0), min(int(iy.max()) + iterations + 1, h)
    x0, x1 = max(int(ix.min()) - iterations, 0), min(int(ix.max()) + iterations + 1, w)
    stamp = np.zeros((y1 - y0, x1 - x0), bool)
    stamp[iy - y0, ix - x0] = True
    placed[y0:y1, x0:x1] |= _binary_dilation(stamp, iterations=iterations)


def _sample(ev, maps, q, shifts, tangent):
    """Mean score of points ``q`` moved by each shift: evidence, or the oriented maps along ``tangent``."""
    from ._snapkernels import sample_scores  # compiled: the same sums, ~10x faster
    q = np.ascontiguousarray(q, np.float64)
    shifts = np.ascontiguousarray(shifts, np.float64).reshape(-1, 2)
    if maps is None:
        src, k = np.asarray(ev, np.float32)[None], np.zeros(len(q), np.int32)
    else:
        n = len(maps)
        src = np.asarray(maps, np.float32)
        k = np.round(np.mod(np.arctan2(tangent[:, 1], tangent[:, 0]), np.pi) / (np.pi / n)).astype(np.int32) % n
    return sample_scores(src, k, q, shifts)


def _sample_many(ev, maps, qs, shifts, tangents):
    """:func:`_sample` for a stack of point sets ``qs`` (A, P, 2) and their tangents: (A, S) scores."""
    from ._snapkernels import sample_scores_many
    qs = np.ascontiguousarray(qs, np.float64)
    shifts = np.ascontiguousarray(shifts, np.float64).reshape(-1, 2)
    if maps is None:
        src, k = np.asarray(ev, np.float32)[None], np.zeros(qs.shape[:2], np.int32)
    else:
        n = len(maps)
        src = np.asarray(maps, np.float32)
        t = np.asarray(tangents)
        k = np.round(np.mod(np.arctan2(t[..., 1], t[..., 0]), np.pi) / (np.pi / n)).astype(np.int32) % n
    whole = np.rint(shifts)
    if len(shifts) and np.array_equal(whole, shifts) and np.abs(whole).max() < 2**30:
        # Whole-pixel shifts (every pose search's): integer addressing, the same sums.
        from ._snapkernels import sample_scores_int
        return sample_scores_int(np.ascontiguousarray(src), k, qs, whole.astype(np.int64))
    return sample_scores_many(src, k, qs, shifts)


#: Weight of the oriented ridge response (:func:`oriented_response`) against
#: the isotropic evidence when a template's pose is scored.
ORIENTED_WEIGHT = 0.5


def _pose_search(p, pivot, ev, reach, angles, scales, shifts, a0, s0, d0, penalty, tang=None, hess=None):
    """Best (angle, scale, shift) of points ``p`` about ``pivot`` by mean evidence minus a shift penalty."""
    h, w = ev.shape
    best = (-np.inf, a0, s0, d0)
    dist = np.hypot(*(d0 + shifts).T)
    ok = dist <= reach
    sh = (d0 + shifts)[ok]
    pen = penalty * dist[ok] / max(reach, 1e-9)
    if not len(sh):
        return best
    # Every pose's points at once (the same arithmetic per pose), scored in one compiled call.
    qs, ts, poses = [], [], []
    for a in angles:
        ca, sa = np.cos(np.radians(a0 + a)), np.sin(np.radians(a0 + a))
        rot = (p - pivot) @ np.array([[ca, sa], [-sa, ca]])
        tr = tang @ np.array([[ca, sa], [-sa, ca]]) if tang is not None else None
        for sc in scales:
            qs.append(rot * (s0 * sc) + pivot)
            ts.append(tr)
            poses.append((a, sc))
    vals = _sample_many(ev, hess, np.stack(qs), sh, np.stack(ts) if hess is not None else None)
    for (a, sc), val in zip(poses, vals):
        score = val - pen
        k = int(np.argmax(score))
        if score[k] > best[0]:
            best = (float(score[k]), a0 + a, s0 * sc, sh[k])
    return best


def _apply_pose(c, pivot, a, sc, d):
    ca, sa = np.cos(np.radians(a)), np.sin(np.radians(a))
    return (c - pivot) @ np.array([[ca, sa], [-sa, ca]]) * sc + pivot + d


def _grid(r, step):
    g = np.arange(-r, r + 1e-9, step, dtype=float)
    return np.array([(x, y) for y in g for x in g])


def fit_branches(chains, evidence, blade, *, reach: float, max_angle: float = 25.0,
                 penalty: float = 0.1, return_score: bool = False, branch_angle: float = 10.0,
                 overlap: float = 0.3, hessian=None, maps=None):
    """Carried-over branches moved onto the exemplar's ridges that fit them best: all together, then each.

    A layer's main veins keep their pattern from leaf to leaf (a star of
    nearly straight primaries on a maple) while the registration turns,
    shifts and bends them: on the sample maples a carried primary vein lies
    10-25 px and up to 15-20 degrees beside the exemplar's own, and a path
    search in a tube that wide wanders along the texture. So the branches,
    as one template, are first placed by the rotation (within
    ``max_angle`` degrees about their centroid), scale (0.85-1.15) and
    shift (within ``reach`` px) that maximise their mean evidence minus
    ``penalty`` times the shift over ``reach`` (the registration is a weak
    prior); then each branch by a smaller rotation (10 degrees) about the
    end it shares with the others (its junction) and shift (``reach / 3``,
    8 px at most).

    ``hessian`` (:func:`ridge_hessian`), when given, makes every pose score
    half the oriented ridge response along the branch's direction (beyond
    the paper). Branches are posed one at a time, the best scoring first;
    a pose with more than ``overlap`` of its points (beyond 6 px from its
    pivot) within 3 px of a placed branch is skipped for the branch's next
    best (two branches never share one vein).

    Returns the moved chains (same order and lengths). Branches shorter than
    8 px only follow the template.
    ``return_score=True`` also returns the template's score (its mean
    evidence less the shift penalty).

    Parameters
    ----------
    chains : list of (N, 2) array_like
        Carried-over branches ``(x, y)`` on the exemplar.
    evidence : (H, W) float ndarray
        :func:`~branchnb.leaves.snapping_evidence.ridge_evidence` of the exemplar.
    blade : (H, W) bool array_like
        Its blade; evidence outside it is 0.
    reach : float
        Largest template shift in pixels; 0: nothing moves.
    max_angle : float
        Largest template rotation in degrees (default 25).
    penalty : float
        Score lost per ``reach`` of shift (default 0.1).
    return_score : bool
        Also return the template's score.
    branch_angle : float
        Largest rotation of a single branch about its junction, degrees
        (default 10).
    overlap : float
        Largest fraction of a branch's pose on an already placed branch
        (default 0.3).
    hessian : (3, H, W) ndarray, optional
        :func:`ridge_hessian`, for oriented pose scores; None: evidence only.
    maps : (K, H, W) ndarray, optional
        ``_oriented_maps`` of the blurred evidence and ``hessian``, when the
        caller has them already (several fits on one exemplar); None:
        computed here.

    Returns
    -------
    list of (N, 2) float64 ndarray, or (chains, score)

    Examples
    --------
    >>> import numpy as np
    >>> ev = np.zeros((80, 80), np.float32); ev[40, 10:70] = 1.0
    >>> chain = np.column_stack([np.arange(10, 70), 33 + 0.1 * np.arange(60)])  # shifted and turned
    >>> moved = fit_branches([chain], ev, np.ones((80, 80), bool), reach=12.0)[0]
    >>> bool(np.abs(moved[:, 1] - 40).max() < 1.0)
    True
    """
    fit = _fit_template(chains, evidence, blade, reach=reach, max_angle=max_angle, penalty=penalty,
                        hessian=hessian, maps=maps)
    out = _fit_each(fit, branch_angle=branch_angle, overlap=overlap)
    return (out, fit.score) if return_score else out


class _TemplateFit:
    """The template stage of :func:`fit_branches` (its score decides between starts), for :func:`_fit_each`."""

    __slots__ = ("cs", "score", "ev", "good", "dense", "hess", "centre", "pose", "penalty", "reach")

    def __init__(self, cs, score, ev=None, good=None, dense=None, hess=None, centre=None, pose=None,
                 penalty=0.0, reach=0.0):
        self.cs, self.score, self.ev, self.good, self.dense = cs, score, ev, good, dense
        self.hess, self.centre, self.pose, self.penalty, self.reach = hess, centre, pose, penalty, reach


def _fit_template(chains, evidence, blade, *, reach: float, max_angle: float = 25.0, penalty: float = 0.1,
                  hessian=None, maps=None) -> _TemplateFit:
    """:func:`fit_branches`' first stage: the branches moved as one template, and its score.

    Split off so that several starts are compared on their template scores and only the winner pays
    for the per-branch stage (:func:`_fit_each`; the same numbers as :func:`fit_branches`).
    """
    import cv2
    ev = np.asarray(evidence, np.float32)
    blade = as_mask(blade, shape=ev.shape, name="blade")
    ev = cv2.GaussianBlur(np.where(blade, ev, 0.0).astype(np.float32), (0, 0), 0.7)
    reach = max(0.0, float(reach))
    cs = [np.asarray(c, np.float64) for c in chains]
    good = [len(c) >= 2 and bool(np.all(np.isfinite(c))) for c in cs]
    if reach <= 0 or not any(good):
        return _TemplateFit(cs, -np.inf)
    dense = [_densify(c) if g else (None, 0.0) for c, g in zip(cs, good)]
    allp = np.concatenate([d for d, _ in dense if d is not None])
    tang = [_tangents(d) for d, _ in dense if d is not None]
    allt = np.concatenate(tang)
    hess = None if hessian is None else (maps if maps is not None else _oriented_maps(ev, hessian))
    centre = allp.mean(0)
    r = float(np.ceil(reach))
    z = np.zeros(2)
    # Coarse: at most 300 template points, shifts in steps of reach / 8 (2 px at least).
    sub = allp[::max(1, len(allp) // 300)]
    subt = allt[::max(1, len(allp) // 300)]
    step = max(2.0, float(round(reach / 8.0)))
    _, a, sc, d = _pose_search(sub, centre, ev, reach, np.arange(-max_angle, max_angle + 1e-9, 2.5),
                               (0.85, 0.92, 1.0, 1.08, 1.15), _grid(step * np.floor(r / step), step), 0.0, 1.0, z,
                               penalty, subt, hess)
    _, a, sc, d = _pose_search(sub, centre, ev, reach, np.arange(-1.5, 1.5 + 1e-9, 0.75),
                               (0.97, 1.0, 1.03), _grid(step, 1.0), a, sc, d, penalty, subt, hess)
    score, a, sc, d = _pose_search(allp, centre, ev, reach, (0.0,), (1.0,), _grid(1.0, 1.0), a, sc, d, penalty,
                                   allt, hess)
    cs = [_apply_pose(c, centre, a, sc, d) for c in cs]
    return _TemplateFit(cs, score, ev, good, dense, hess, centre, (a, sc, d), penalty, reach)


def _fit_each(fit: _TemplateFit, *, branch_angle: float = 10.0, overlap: float = 0.3) -> list:
    """:func:`fit_branches`' second stage: each branch of the posed template moved about its junction."""
    cs = fit.cs
    if fit.ev is None:
        return cs
    ev, good, dense, hess, centre, penalty, reach = fit.ev, fit.good, fit.dense, fit.hess, fit.centre, \
        fit.penalty, fit.reach
    a, sc, d = fit.pose
    ends = np.array([[c[0], c[-1]] for c, g in zip(cs, good) if g]).reshape(-1, 2)
    out = list(cs)
    rb = min(reach / 3.0, 8.0)
    cands = []
    for i, (c, g, (p, length)) in enumerate(zip(cs, good, dense)):
        if not g or length < 8:
            continue
        # The branch's pivot: its end nearest another branch's end (a junction).
        dists = [np.sort(np.hypot(*(ends - e).T))[1] if len(ends) > 1 else 0.0 for e in (c[0], c[-1])]
        pivot = c[0] if dists[0] <= dists[1] else c[-1]
        p2 = _apply_pose(p, centre, a, sc, d)
        k2 = max(1, len(p2) // 150)
        sub2, t2 = p2[::k2], _tangents(p)[::k2]
        ca, sa = np.cos(np.radians(a)), np.sin(np.radians(a))
        t2 = t2 @ np.array([[ca, sa], [-sa, ca]])
        # Every pose of the branch about its junction, best first (several
        # candidates: a branch must not take the ridge another one took).
        poses = _branch_poses(sub2, pivot, ev, rb, branch_angle, penalty, tang=t2, hess=hess)
        cands.append((i, pivot, poses))
    # Greedy, most confident branch first: a pose whose points mostly lie on
    # an already placed branch (two laterals on one vein) is skipped.
    cands.sort(key=lambda x: -x[2][0][0] if x[2] else np.inf)
    placed = np.zeros(ev.shape, bool)
    h, w = ev.shape
    for i, pivot, poses in cands:
        chosen = None
        for _sco, a2, s2, d2 in poses:
            q = _apply_pose(dense[i][0], pivot, a2, s2, d2)
            ix = np.clip(np.round(q[:, 0]).astype(int), 0, w - 1)
            iy = np.clip(np.round(q[:, 1]).astype(int), 0, h - 1)
            far = np.hypot(*(q - pivot).T) > 6.0
            if not far.any() or placed[iy[far], ix[far]].mean() <= overlap:
                chosen = (a2, s2, d2, ix, iy)
                break
        if chosen is None:
            continue
        a2, s2, d2, ix, iy = chosen
        out[i] = _apply_pose(cs[i], pivot, a2, s2, d2)
        _stamp(placed, iy, ix, 3)
    return out


def _branch_poses(p, pivot, ev, reach, max_angle, penalty, keep: int = 12, tang=None, hess=None):
    """Poses (score, angle, scale, shift) of one branch about its pivot, best first, distinct angles."""
    h, w = ev.shape
    sh = _grid(np.ceil(reach), 1.0)
    dist = np.hypot(*sh.T)
    ok = dist <= max(reach, 1e-9)
    sh, pen = sh[ok], penalty * dist[ok] / max(reach, 1e-9)
    rows = []
    qs, ts, angs = [], [], np.arange(-max_angle, max_angle + 1e-9, 1.0)
    for ang in angs:
        ca, sa = np.cos(np.radians(ang)), np.sin(np.radians(ang))
        qs.append((p - pivot) @ np.array([[ca, sa], [-sa, ca]]) * 1.0 + pivot)
        ts.append(tang @ np.array([[ca, sa], [-sa, ca]]) if tang is not None else None)
    vals = _sample_many(ev, hess, np.stack(qs), sh, np.stack(ts) if hess is not None else None)
    for ang, val in zip(angs, vals):
        score = val - pen
        k = int(np.argmax(score))
        rows.append((float(score[k]), float(ang), 1.0, sh[k]))
    rows.sort(key=lambda r: -r[0])
    out = []
    for r in rows:
        if all(abs(r[1] - o[1]) >= 3.0 for o in out):
            out.append(r)
        if len(out) >= keep:
            break
    return out


def _pivot_ends(chains):
    """For each chain: (pivot, far end), the pivot being the end nearest another chain's end (a junction)."""
    ends = np.array([[c[0], c[-1]] for c in chains]).reshape(-1, 2)
    out = []
    for i, c in enumerate(chains):
        if len(ends) <= 2:
            out.append((c[0], c[-1]))
            continue
        others = np.delete(ends, [2 * i, 2 * i + 1], axis=0)
        d0 = np.hypot(*(others - c[0]).T).min()
        d1 = np.hypot(*(others - c[-1]).T).min()
        out.append((c[0], c[-1]) if d0 <= d1 else (c[-1], c[0]))
    return out


