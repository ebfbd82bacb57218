"""Compiled inner loops of structure synthesis (numba, ``cache=True``).

Each kernel computes what a vectorised numpy function of
:mod:`branchnb.branching.colonization` computes, on flat arrays, without the
per-call overhead of some twenty small numpy operations: a Markov step of a
1000 px example spends most of its time there (issue 23). The numpy
versions stay the reference (tests compare them).

- :func:`profile_bins`: :func:`~branchnb.branching.scoring.binned_profile`
  (density profiles along binned directions, bilinear or nearest sampling of
  the grid of a :class:`~branchnb.branching.colonization.DensityMap`);
- :func:`pca_directions`: :func:`~branchnb.branching.colonization.growth_directions`;
- :func:`bucket_add` / :func:`first_free` (in :mod:`._crossing_kernels`, re-exported): the crossing
  test of :func:`~branchnb.branching.colonization.crosses_existing` on the segment
  grid of :class:`~branchnb.branching.colonization.SegmentStore`, run over
  the ranked candidates of a step until ``c`` free ones are found;
- :func:`score_step` / :func:`start_scores`: a Markov step's scores and a new branch's heads;
- :func:`step_factors`: the bend-size, straight-run and winding factors of a step's candidates
  (:class:`~branchnb.branching.straightness.BendHistogram`,
  :class:`~branchnb.branching.straightness.StraightRuns`, :func:`~branchnb.branching.growth.winding_limit`);
- :func:`child_quality`: :meth:`~branchnb.branching.furcation.FurcationModel.child_quality` of the
  input furcations, mirrored too (numpy's summation order: the same numbers to the bit).

With these the structures are the same as the numpy code's, seed for seed; a 1000 px cracked mud
(4.5 k steps, 3.2 k branch starts) took 19.9-25.9 s CPU per seed (3 seeds, a loaded machine) before
the last two and the Python-side savings that came with them (issue 23, branching25), 11.4-13.9 s
after.

- :func:`count_bins` / :func:`element_bins` with :func:`_improve_bins`: the histogram factors of a
  step (angles, thicknesses, bend sizes) and of a branch start read each candidate's few counted
  bins (int16) instead of its ``B``-wide row of counts (float64): the rows of ~1000 random
  candidates out of 17.6 k per step missed the cache. Counts are whole numbers, so every sum is
  the same to the bit (issue 23, branching28; with the Python-side savings of that session a 1000 px
  cracked mud took 18.7 -> 15.2 s CPU for seed 1, old and new code alternated on a loaded machine);
- :func:`inside`: ``_Grower._inside`` (frame and domain test of new vertices).
- :func:`head_rows`: every input head's histogram bins once per model (a branch start read them from
  the heads' elements at every start); :func:`bucket_range`: the segment grid's bucket insert, shared
  with :func:`._loop_kernels.register` (issue 23, branching46).
- :func:`ranked_free`: ``first_free`` over the candidates in the order of a full stable argsort of
  their float32 scores, ranked lazily (the next best of those left; a step takes its ``c`` free
  ones among the first few); :func:`free_direction`: is any direction free (``_room_ahead``,
  ``_room_around``), ending at the first free bin instead of profiling all of them;
  :func:`start_scores` leaves out the histogram factor of heads whose profile crosses (score 0).
  The same structures to the bit on seven kinds at 250/512/1000 px, 3 seeds each (issue 23,
  branching32).
"""

from __future__ import annotations

import numba
import numpy as np

# the segment grid's crossing test, split off to ._crossing_kernels (re-exported)
from ._crossing_kernels import bucket_add, bucket_range, crosses, first_free, ranked_free

__all__ = ["bucket_add", "count_bins", "crosses", "element_bins", "first_free", "free_direction", "inside",
           "pca_directions", "profile_bins", "ranked_free", "score_step", "start_scores", "step_factors",
           "child_quality", "head_rows", "bucket_range"]


@numba.njit(cache=True)
def _sample(grid, cell, x, y):
    """:meth:`DensityMap.sample` at one point (float32 result)."""
    gh, gw = grid.shape
    if cell <= 1.0:
        c = int(np.floor((x + 0.5) / cell))
        r = int(np.floor((y + 0.5) / cell))
        if c < 0 or c >= gw or r < 0 or r >= gh:
            return np.float32(0.0)
        return grid[r, c]
    fx = (x + 0.5) / cell - 0.5
    fy = (y + 0.5) / cell - 0.5
    if not (fx >= -0.5 and fx < gw - 0.5 and fy >= -0.5 and fy < gh - 0.5):
        return np.float32(0.0)
    fx = min(max(fx, 0.0), gw - 1.0)
    fy = min(max(fy, 0.0), gh - 1.0)
    c0 = min(int(fx), gw - 2) if gw > 1 else 0
    r0 = min(int(fy), gh - 2) if gh > 1 else 0
    c1 = min(c0 + 1, gw - 1)
    r1 = min(r0 + 1, gh - 1)
    tx, ty = fx - c0, fy - r0
    v = (grid[r0, c0] * (1 - tx) + grid[r0, c1] * tx) * (1 - ty) + \
        (grid[r1, c0] * (1 - tx) + grid[r1, c1] * tx) * ty
    return np.float32(v)


@numba.njit(cache=True)
def _bin_profile(grid, cell, tipx, tipy, q, length, n_samples, tol, nbins, step, prof, pre, post):
    """``(D_c, crossing)`` of the profile along direction bin ``q`` (one bin of :func:`profile_bins`;
    ``prof``, ``pre``, ``post``: float32 work rows of ``n_samples``)."""
    two_pi = 2.0 * np.pi
    ang = q * (two_pi / nbins)
    ux, uy = np.cos(ang), np.sin(ang)
    for i in range(n_samples):
        t = length / n_samples + i * step if i < n_samples - 1 else length
        prof[i] = _sample(grid, cell, tipx + t * ux, tipy + t * uy)
    first = n_samples - 1
    for i in range(n_samples - 1):
        if prof[i + 1] - prof[i] > tol * 0.5:
            first = i
            break
    m = 0.0
    for i in range(first, n_samples):
        if prof[i] > m:
            m = prof[i]
    pre[0] = prof[0]
    for i in range(1, n_samples):
        pre[i] = min(pre[i - 1], prof[i])
    post[n_samples - 1] = prof[n_samples - 1]
    for i in range(n_samples - 2, -1, -1):
        post[i] = min(post[i + 1], prof[i])
    c = False
    for i in range(n_samples):
        if prof[i] - pre[i] > tol and prof[i] - post[i] > tol:
            c = True
            break
    return m, c


@numba.njit(cache=True)
def profile_bins(grid, cell, tipx, tipy, dirs, length, n_samples, tol, nbins):
    """``(D_c, crossing)`` of :func:`~branchnb.branching.colonization.profile_density` along each of
    ``dirs`` (K, 2), each direction replaced by the nearest of ``nbins`` (each bin profiled once)."""
    K = dirs.shape[0]
    dc = np.empty(K)
    cross = np.zeros(K, np.bool_)
    done = np.zeros(nbins, np.bool_)
    bdc = np.zeros(nbins)
    bcr = np.zeros(nbins, np.bool_)
    prof = np.empty(n_samples, np.float32)
    pre = np.empty(n_samples, np.float32)
    post = np.empty(n_samples, np.float32)
    step = (length - length / n_samples) / (n_samples - 1) if n_samples > 1 else 0.0
    two_pi = 2.0 * np.pi
    for k in range(K):
        q = int(np.rint(np.arctan2(dirs[k, 1], dirs[k, 0]) * (nbins / two_pi))) % nbins
        if not done[q]:
            bdc[q], bcr[q] = _bin_profile(grid, cell, tipx, tipy, q, length, n_samples, tol, nbins, step,
                                          prof, pre, post)
            done[q] = True
        dc[k] = bdc[q]
        cross[k] = bcr[q]
    return dc, cross


@numba.njit(cache=True)
def live_profiles(grid, cell, tipx, tipy, dirs, t, cont_len, length, n_samples, tol, nbins):
    """Density profile bins and crossing flags of the candidates whose template continues.

    A candidate whose template ends here (``cont_len[t[j]] == 0``) has no
    profile of its own: it takes the best non-crossing candidate's value
    (1 when there is none) and never counts as crossing.

    Parameters
    ----------
    grid, cell, tipx, tipy, length, n_samples, tol, nbins
        As for :func:`profile_bins`.
    dirs : (J, 2) float ndarray
        Unit directions of all candidates.
    t : (J,) int ndarray
        Template index of each candidate.
    cont_len : (T,) int ndarray
        Continuation length of each template.

    Returns
    -------
    D_c : (J,) float ndarray
    cross : (J,) bool ndarray
    """
    J = len(t)
    D_c = np.zeros(J)
    cross = np.zeros(J, np.bool_)
    live = np.empty(J, np.int64)
    nl = 0
    for j in range(J):
        if cont_len[t[j]] > 0:
            live[nl] = j
            nl += 1
    if nl > 0:
        dc, cr = profile_bins(grid, cell, tipx, tipy, dirs[live[:nl]], length, n_samples, tol, nbins)
        best = np.inf
        for i in range(nl):
            D_c[live[i]] = dc[i]
            cross[live[i]] = cr[i]
            if not cr[i] and dc[i] < best:
                best = dc[i]
        if nl < J:
            fill = best if np.isfinite(best) else 1.0
            for j in range(J):
                if cont_len[t[j]] == 0:
                    D_c[j] = fill
    return D_c, cross


@numba.njit(cache=True)
def free_direction(grid, cell, tipx, tipy, dirs, theta, rotate, length, n_samples, tol, nbins, stop):
    """Does any of ``dirs`` (K, 2; turned by ``theta`` when ``rotate``, as ``scoring._rotate``) lead on:
    its bin's profile (:func:`profile_bins`) without a crossing and with ``D_c < stop``? Bins are
    profiled in the order the directions first reach them, and the search ends at the first free one
    (``_Grower._room_ahead`` and ``_room_around``: the same answer as ``profile_bins`` over all of them)."""
    K = dirs.shape[0]
    done = np.zeros(nbins, np.bool_)
    n_done = 0
    prof = np.empty(n_samples, np.float32)
    pre = np.empty(n_samples, np.float32)
    post = np.empty(n_samples, np.float32)
    step = (length - length / n_samples) / (n_samples - 1) if n_samples > 1 else 0.0
    two_pi = 2.0 * np.pi
    c, s = np.cos(theta), np.sin(theta)
    for k in range(K):
        x, y = dirs[k, 0], dirs[k, 1]
        if rotate:
            x, y = c * dirs[k, 0] - s * dirs[k, 1], s * dirs[k, 0] + c * dirs[k, 1]
        q = int(np.rint(np.arctan2(y, x) * (nbins / two_pi))) % nbins
        if done[q]:
            continue
        done[q] = True
        m, cr = _bin_profile(grid, cell, tipx, tipy, q, length, n_samples, tol, nbins, step, prof, pre, post)
        if not cr and m < stop:
            return True
        n_done += 1
        if n_done == nbins:   # every bin profiled and none free: the other directions cannot change that
            return False
    return False


@numba.njit(cache=True)
def pca_directions(tipx, tipy, new_points, n_valid):
    """:func:`~branchnb.branching.colonization.growth_directions` (principal axis of the tip and the
    ``n_valid`` first new vertices, oriented toward the last one)."""
    J, m, _ = new_points.shape
    out = np.empty((J, 2))
    for j in range(J):
        nv = n_valid[j]
        sx = sy = sxx = syy = sxy = 0.0
        for i in range(min(nv, m)):
            x = new_points[j, i, 0] - tipx
            y = new_points[j, i, 1] - tipy
            sx += x
            sy += y
            sxx += x * x
            syy += y * y
            sxy += x * y
        n = nv + 1.0
        mx, my = sx / n, sy / n
        a = 0.5 * np.arctan2(2 * (sxy - n * mx * my), (sxx - n * mx * mx) - (syy - n * my * my))
        vx, vy = np.cos(a), np.sin(a)
        li = max(nv - 1, 0)
        lx = new_points[j, li, 0] - tipx
        ly = new_points[j, li, 1] - tipy
        if vx * lx + vy * ly < 0:
            vx, vy = -vx, -vy
        out[j, 0] = vx
        out[j, 1] = vy
    return out


@numba.njit(cache=True)
def _hist_pre(p, counts):
    """``(N, d_old, C.C, p.C, p.p)`` of a running histogram ``counts`` against the example's ``p``."""
    B = p.shape[0]
    n = 0.0
    for b in range(B):
        n += counts[b]
    d_old = CC = pC = pp = 0.0
    for b in range(B):
        q = counts[b] / n if n > 0 else 0.0
        d_old += (q - p[b]) ** 2
        CC += counts[b] * counts[b]
        pC += p[b] * counts[b]
        pp += p[b] * p[b]
    return n, d_old / B, CC, pC, pp


@numba.njit(cache=True)
def _improve(pre, p, counts, row):
    """``d_old - d_new`` of :meth:`HistogramMatcher._improvement` for one candidate's counts ``row``."""
    n, d_old, CC, pC, pp = pre
    B = p.shape[0]
    nc = cC = cp = sq = 0.0
    for b in range(B):
        nc += row[b]
        cC += row[b] * counts[b]
        cp += row[b] * p[b]
        sq += row[b] * row[b]
    nn = n + nc
    if nn <= 0:
        return 0.0
    return d_old - ((CC + 2 * cC + sq) / nn ** 2 - 2 * (pC + cp) / nn + pp) / B


@numba.njit(cache=True)
def _improvements(p, counts, cc, cc_sq, t):
    """:meth:`HistogramMatcher._improvement` for the candidate rows ``t`` of ``cc``."""
    pre = _hist_pre(p, counts)
    out = np.zeros(t.shape[0])
    for j in range(t.shape[0]):
        out[j] = _improve(pre, p, counts, cc[t[j]])
    return out


def count_bins(cc: np.ndarray) -> np.ndarray:
    """The bins of every candidate's counted values, ``(T, M)`` int16, each row ascending and padded
    with 32767: a row of ``cc`` (T, B) counting ``2`` in bin 3 and ``1`` in bin 5 becomes ``[3, 3, 5, pad]``.

    The kernels read these few bins (:func:`_improve_bins`) instead of the ``B`` columns of ``cc``: a
    Markov step of a 1000 px crack example reads the rows of some 1000 random candidates out of
    17.6 k, and ``cc``'s 128-byte rows missed the cache (issue 23). Counts are whole numbers, so
    every sum comes out as with ``cc`` to the bit.
    """
    cc = np.asarray(cc, np.float64)
    T, B = cc.shape
    k = np.rint(cc).astype(np.int64)
    if not np.array_equal(k, cc) or (k < 0).any() or B >= 32767:
        raise ValueError("cc must hold non-negative whole counts in fewer than 32767 bins")
    tot = k.sum(axis=1)
    out = np.full((T, max(int(tot.max()) if T else 0, 1)), 32767, np.int16)
    rows = np.repeat(np.arange(T), tot)
    bins = np.repeat(np.tile(np.arange(B), T), k.ravel())
    starts = np.r_[0, np.cumsum(tot)[:-1]] if T else np.zeros(0, np.int64)
    out[rows, np.arange(len(rows)) - np.repeat(starts, tot)] = bins
    return out


@numba.njit(cache=True)
def _improve_bins(pre, p, counts, bins):
    """:func:`_improve` of the candidate whose counted bins are ``bins`` (a row of :func:`count_bins`):
    the same sums in the same (ascending bin) order, the zero columns left out."""
    n, d_old, CC, pC, pp = pre
    B = p.shape[0]
    M = bins.shape[0]
    nc = cC = cp = sq = 0.0
    i = 0
    while i < M:
        b = bins[i]
        if b >= B:
            break
        v = 1.0
        while i + 1 < M and bins[i + 1] == b:
            v += 1.0
            i += 1
        i += 1
        nc += v
        cC += v * counts[b]
        cp += v * p[b]
        sq += v * v
    nn = n + nc
    if nn <= 0:
        return 0.0
    return d_old - ((CC + 2 * cC + sq) / nn ** 2 - 2 * (pC + cp) / nn + pp) / B


@numba.njit(cache=True)
def _improvements_bins(p, counts, bins, t):
    """:func:`_improvements` from the rows ``t`` of :func:`count_bins` (the same numbers to the bit)."""
    pre = _hist_pre(p, counts)
    out = np.zeros(t.shape[0])
    for j in range(t.shape[0]):
        out[j] = _improve_bins(pre, p, counts, bins[t[j]])
    return out


def element_bins(cum: np.ndarray) -> np.ndarray:
    """The bin of every element, ``(T,)`` int16, from the running one-hot counts ``cum`` (T + 1, B)
    (``model.cum_r``: ``cum[e + 1] - cum[e]`` counts element ``e`` in its bin)."""
    d = np.diff(np.asarray(cum, np.float64), axis=0)
    b = np.argmax(d, axis=1) if len(d) else np.zeros(0, np.int64)
    if len(d) and (not np.array_equal(d.sum(axis=1), np.ones(len(d))) or
                   not np.array_equal(d[np.arange(len(d)), b], np.ones(len(d))) or d.shape[1] >= 32767):
        raise ValueError("cum must hold running one-hot counts")
    return b.astype(np.int16)


@numba.njit(cache=True)
def _insert_sorted(buf, k, b):
    """Insert ``b`` into the ascending ``buf[:k]`` (insertion sort step)."""
    i = k
    while i > 0 and buf[i - 1] > b:
        buf[i] = buf[i - 1]
        i -= 1
    buf[i] = b


@numba.njit(cache=True)
def head_rows(first_a, first_len, edges_a, elem_bins_r, head_start):
    """The histogram bins of every input head's first elements, for :func:`start_scores`: ``rows_a``
    (2, n_branches, W) the bins of its ``min(first_len, m)`` angles (``edges_a``; index 1 with the
    angles negated, a mirrored head), ``rows_r`` (n_branches, W) the thickness bins of its
    ``first_len`` elements (``elem_bins_r`` from ``head_start``), each row ascending and padded with
    32767 (:func:`count_bins`' rows). A head's rows do not change during a synthesis: computed once
    per model instead of at every branch start (issue 23, branching46)."""
    nh, m = first_a.shape
    W = max(m, first_len.max() if nh else 0) + 1
    nb = edges_a.shape[0] - 1
    rows_a = np.full((2, nh, W), 32767, np.int16)
    rows_r = np.full((nh, W), 32767, np.int16)
    for hd in range(nh):
        k = min(first_len[hd], m)
        for s in range(2):
            sg = -1.0 if s == 1 else 1.0
            for i in range(k):
                b = np.searchsorted(edges_a, first_a[hd, i] * sg, side="right") - 1
                _insert_sorted(rows_a[s, hd], i, min(max(b, 0), nb - 1))
        s0 = head_start[hd]
        for i in range(first_len[hd]):
            _insert_sorted(rows_r[hd], i, elem_bins_r[s0 + i])
    return rows_a, rows_r


@numba.njit(cache=True)
def start_scores(heads, th0, sign, first_a, n, x0x, x0y, h, Q, use_hist, rows_a, p_a, counts_a,
                 rows_r, p_r, counts_r, hist_scale, use_density, grid, cell, length, n_samples,
                 tol, nbins, eps, r_scale=-1.0):
    """The vectorised part of ``_Grower._start_branch``: every candidate head's first vertices
    ``new (H, m + 1, 2)`` and headings ``th (H, m + 1)``, its score ``Q`` x histogram factor, with
    colonization ``/ (D_c + eps)`` (0 where the profile crosses), its PCA direction and ``D_c``.
    ``rows_a`` (2, n_branches, W): every input head's angle bins, ascending and padded (index 0 as
    copied, 1 mirrored), ``rows_r`` (n_branches, W) its thickness bins (:func:`head_rows`): a head's
    counts are read as its few bins (:func:`_improve_bins`), the same sums as from its ``B``-wide row
    of counts. The histogram factor is left out of heads whose profile crosses a branch (their score
    is 0 all the same; up to 80-100 % of a start's heads in a dense 1000 px cracked mud). ``r_scale`` >= 0:
    the thickness term's weight instead of ``hist_scale`` (``p_r``/``counts_r`` then a child's own
    histograms, ``branch_starts.CHILD_RADIUS_HISTOGRAM``)."""
    H = heads.shape[0]
    m = first_a.shape[1]
    th = np.empty((H, m + 1))
    new = np.empty((H, m + 1, 2))
    score = Q.copy()
    pa = _hist_pre(p_a, counts_a) if use_hist else (0.0, 0.0, 0.0, 0.0, 0.0)
    pr = _hist_pre(p_r, counts_r) if use_hist else (0.0, 0.0, 0.0, 0.0, 0.0)
    for j in range(H):
        hd = heads[j]
        a = th0[j]
        x, y = x0x, x0y
        for i in range(m + 1):
            ok = i <= n[j]
            if i > 0 and ok:
                a += first_a[hd, i - 1] * sign[j]
            th[j, i] = a
            if ok:
                x += np.cos(a) * h
                y += np.sin(a) * h
            new[j, i, 0] = x
            new[j, i, 1] = y
    dirs = pca_directions(x0x, x0y, new, n + 1)
    dc = np.zeros(H)
    cross = np.zeros(H, np.bool_)
    if use_density:
        dc, cross = profile_bins(grid, cell, x0x, x0y, dirs, length, n_samples, tol, nbins)
    for j in range(H):
        if use_density and cross[j]:   # a crossing head scores 0: its histogram factor is not needed
            score[j] = 0.0
            continue
        hd = heads[j]
        if use_hist:
            da = _improve_bins(pa, p_a, counts_a, rows_a[1 if sign[j] < 0 else 0, hd])
            dr = _improve_bins(pr, p_r, counts_r, rows_r[hd])
            x = hist_scale * (da + dr) if r_scale < 0.0 else hist_scale * da + r_scale * dr
            score[j] *= np.exp(min(max(x, -50.0), 50.0))
        if use_density:
            score[j] = score[j] / (dc[j] + eps)
    return new, th, score, dirs, dc


@numba.njit(cache=True)
def score_step(t, angles, radii, ha, hr, local_points, local_dirs, cont_len, tipx, tipy, theta,
               use_hist, p_a, counts_a, bins_a, p_r, counts_r, bins_r, hist_scale,
               use_density, grid, cell, length, n_samples, tol, nbins, eps):
    """One Markov step's scores (:func:`~branchnb.branching.scoring.score_candidates` without
    guidance) of the candidate windows ``t`` (the ``L`` input elements ``angles``/``radii`` up to
    each, :meth:`~branchnb.branching.bending.BendingModel.windows`) against the history
    ``ha``/``hr`` (L,), the candidates' histogram counts as :func:`count_bins` rows: returns
    ``Q, score, points (J, m, 2), hist_factor, D_c, crossing``."""
    J, L = t.shape[0], ha.shape[0]
    m = local_points.shape[1]
    Q = np.empty(J)
    c, s = np.cos(theta), np.sin(theta)
    pts = np.empty((J, m, 2))
    dirs = np.empty((J, 2))
    for j in range(J):
        da = dr = 0.0
        e0 = t[j] - L + 1
        for i in range(L):
            da += (angles[e0 + i] - ha[i]) ** 2
            dr += (radii[e0 + i] - hr[i]) ** 2
        Q[j] = (1.0 / (np.sqrt(da) + 1.0) + 1.0) * (1.0 / (np.sqrt(dr) + 1.0) + 1.0)
        r = t[j]
        for i in range(m):
            x, y = local_points[r, i, 0], local_points[r, i, 1]
            pts[j, i, 0] = tipx + c * x - s * y
            pts[j, i, 1] = tipy + s * x + c * y
        x, y = local_dirs[r, 0], local_dirs[r, 1]
        dirs[j, 0] = c * x - s * y
        dirs[j, 1] = s * x + c * y
    hf = np.ones(J)
    base = Q.copy()
    if use_hist:
        ia = _improvements_bins(p_a, counts_a, bins_a, t)
        ir = _improvements_bins(p_r, counts_r, bins_r, t)
        for j in range(J):
            hf[j] = np.exp(min(max(hist_scale * (ia[j] + ir[j]), -50.0), 50.0))
            base[j] *= hf[j]
    D_c = np.zeros(J)
    cross = np.zeros(J, np.bool_)
    score = base
    if use_density:
        D_c, cross = live_profiles(grid, cell, tipx, tipy, dirs, t, cont_len, length, n_samples, tol, nbins)
        score = np.empty(J)
        for j in range(J):
            score[j] = 0.0 if cross[j] else base[j] / (D_c[j] + eps)
    return Q, score, pts, hf, D_c, cross


@numba.njit(cache=True)
def step_factors(t, cont_angles, cont_len, use_bend, bend_p, bend_counts, bend_bins, bend_scale, bend_cap,
                 use_runs, log_h, log_1h, log_q, log_1q, state, run, tol, max_run, mode, weight, run_gain,
                 run_cap, theta, lo, hi, wind_max, end_zero):
    """The per-candidate factors of ``_Grower.step`` after the scores, in one pass over the candidate
    windows ``t`` (their bend counts as :func:`count_bins` rows ``bend_bins``): returns ``(fb, zero)``,
    ``fb`` the bend-size factor
    (:meth:`~branchnb.branching.straightness.BendHistogram.factors_at`) times the straight-run factor
    (:meth:`~branchnb.branching.straightness.StraightRuns.factors` against the candidate's own run,
    ``mode`` 0: blended (geometric mean) with the one against the overall bend rate, 1: its square
    root alone, 2: as is, 3: its fourth root times the one against the overall rate to the power 3/4;
    to the power ``weight``), ``zero`` the candidates a branch may not take
    (``end_zero``: those that end it; those whose headings would sweep past ``wind_max``)."""
    J = t.shape[0]
    fb = np.ones(J)
    zero = np.zeros(J, np.bool_)
    d = _improvements_bins(bend_p, bend_counts, bend_bins, t) if use_bend else np.zeros(J)
    for j in range(J):
        fb[j], zero[j] = _factor_at(t[j], d[j], cont_angles, cont_len, use_bend, bend_scale,
                                    bend_cap, use_runs, log_h, log_1h, log_q, log_1q, state, run, tol, max_run,
                                    mode, weight, run_gain, run_cap, theta, lo, hi, wind_max, end_zero)
    return fb, zero


@numba.njit(cache=True)
def _factor_at(r, d, cont_angles, cont_len, use_bend, bend_scale, bend_cap, use_runs, log_h, log_1h, log_q,
               log_1q, state, run, tol, max_run, mode, weight, run_gain, run_cap, theta, lo, hi, wind_max,
               end_zero):
    """``(fb, zero)`` of :func:`step_factors` for the candidate window ``r`` whose bend-size
    improvement is ``d``."""
    M = cont_angles.shape[1]
    n = cont_len[r]
    f = 1.0
    if use_bend:
        f = np.exp(min(max(bend_scale * d, -bend_cap), bend_cap))
    if use_runs:
        L = run
        Lb = state[r]
        ll = 0.0
        la = 0.0
        for i in range(M):
            if i >= n:
                break
            bent = abs(cont_angles[r, i]) >= tol
            if L > 0:
                jl = min(L, max_run)
                jb = min(Lb, max_run)
                if bent:
                    ll += log_h[jl] - log_h[jb]
                    la += log_h[jl] - log_q
                else:
                    ll += log_1h[jl] - log_1h[jb]
                    la += log_1h[jl] - log_1q
            if bent:
                L = 0
                Lb = 0
            else:
                L += 1
                Lb += 1
        fr = np.exp(min(max(run_gain * ll, -run_cap), run_cap))
        if mode == 0:
            fr = np.sqrt(fr * np.exp(min(max(run_gain * la, -run_cap), run_cap)))
        elif mode == 1:
            fr = np.sqrt(fr)
        elif mode == 3:
            fr = fr ** 0.25 * np.exp(0.75 * min(max(run_gain * la, -run_cap), run_cap))
        if weight != 1.0:
            fr = fr ** weight
        f = f * fr if use_bend else fr
    z = end_zero and n <= 0
    a = theta
    amax = hi
    amin = lo
    for i in range(M):
        a += cont_angles[r, i]
        amax = max(amax, a)
        amin = min(amin, a)
    if amax - amin > wind_max:
        z = True
    return f, z


@numba.njit(cache=True)
def _np_sum(a):
    """``numpy.sum(x, axis=-1)`` of one short row of a 2-d array, in numpy's order (below 8 values
    one after another, else its pairwise sum with eight partial sums), so results match numpy's to
    the bit."""
    n = a.shape[0]
    if n < 8:
        out = 0.0
        for i in range(n):
            out = out + a[i] if i else a[0]
        return out
    r0, r1, r2, r3, r4, r5, r6, r7 = a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]
    i = 8
    while i < n - (n % 8):
        r0 += a[i]
        r1 += a[i + 1]
        r2 += a[i + 2]
        r3 += a[i + 3]
        r4 += a[i + 4]
        r5 += a[i + 5]
        r6 += a[i + 6]
        r7 += a[i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[i]
        i += 1
    return res


@numba.njit(cache=True)
def child_quality(wa, wr, rows, win_a, win_r, mirror):
    """:meth:`~branchnb.branching.furcation.FurcationModel.child_quality` of the input furcations
    ``rows`` (``markov_dist`` of the angle windows times that of the thickness windows), followed,
    when ``mirror``, by the same with the angle window negated: ``(len(rows) x (1 + mirror),)``."""
    F = rows.shape[0]
    K = wa.shape[1]
    out = np.empty(F * (2 if mirror else 1))
    d = np.empty(K)
    for half in range(2 if mirror else 1):
        sgn = -1.0 if half == 1 else 1.0
        for j in range(F):
            r = rows[j]
            for i in range(K):
                x = wa[r, i] - sgn * win_a[i]
                d[i] = x * x
            qa = 1.0 / (np.sqrt(_np_sum(d)) + 1.0) + 1.0
            for i in range(K):
                x = wr[r, i] - win_r[i]
                d[i] = x * x
            qr = 1.0 / (np.sqrt(_np_sum(d)) + 1.0) + 1.0
            out[half * F + j] = qa * qr
    return out


@numba.njit(cache=True)
def inside(pts, h, w, domain, use_domain):
    """``_Grower._inside``: which points ``(N, 2)`` lie in the ``h x w`` frame (to half a pixel past
    its border pixels) and, when ``use_domain``, on a ``domain`` pixel (the nearest, ``np.rint``)."""
    N = pts.shape[0]
    ok = np.zeros(N, np.bool_)
    for i in range(N):
        x, y = pts[i, 0], pts[i, 1]
        o = x >= -0.5 and x <= w - 0.5 and y >= -0.5 and y <= h - 0.5
        if o and use_domain:
            ix = min(max(int(np.rint(x)), 0), w - 1)
            iy = min(max(int(np.rint(y)), 0), h - 1)
            o = domain[iy, ix]
        ok[i] = o
    return ok
