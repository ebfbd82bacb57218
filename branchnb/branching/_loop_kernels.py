"""Compiled glue of the grow loop (numba, ``cache=True``; issue 23, branching40).

:mod:`branchnb.branching._kernels` holds the compiled inner loops of a step and of a branch start
(scores, density profiles, crossing tests). What is left between them was Python glue: a
1000 px cracked mud spent about half of its 9-12 s CPU per seed in it. The kernels here take over
pieces of that glue, each computing the very numbers (to the bit) of the numpy code it replaces,
which stays the reference (``tests/test_branching_loop_kernels.py`` compares them):

- :func:`register`: ``_Grower._register`` (segment store, density splat, total length, the
  running histograms of angles, thicknesses and bend sizes) in one call;
- :func:`plain_step`: a Markov step without the factors of deltas, coasts, holes and guidance
  (scores, step factors, density stop, ranked crossing test) in one call;
- :func:`child_start`: a child's start without them (the furcations' quality, mirrored heads, the
  heads' scores, the frame and domain test, ranked crossing test) in one call (issue 23, branching46).
"""

from __future__ import annotations

import numba
import numpy as np

from ._kernels import _factor_at, _hist_pre, _improve_bins, _np_sum
from ._kernels import bucket_range as _bucket_range
from ._kernels import child_quality as _child_quality
from ._kernels import inside as _inside
from ._kernels import live_profiles as _live_profiles
from ._kernels import ranked_free as _ranked_free
from ._kernels import start_scores as _start_scores
from .colonization import _splat_segments
from .scoring import _DIRECTION_BINS, _cand_bins

__all__ = ["MAX_REGISTER", "child_start", "plain_step", "register", "register_polyline", "step_call"]

#: Most segments :func:`register` sums like numpy (its pairwise sum splits longer arrays).
MAX_REGISTER = 128


@numba.njit(cache=True)
def _bin(edges, x, nb):
    """``min(max(searchsorted(edges, x, "right") - 1, 0), nb - 1)`` (``histogram_matching._bin_index``)."""
    return min(max(np.searchsorted(edges, x, side="right") - 1, 0), nb - 1)


@numba.njit(cache=True)
def register(poly, angles, radii, sp0, sp1, n_store, head, nxt, seg, n_entries, store_cell,
             use_density, grid, domain, cell, rho, level, edges_a, counts_a, edges_r, counts_r,
             bend_edges, bend_counts):
    """``_Grower._register`` of the polyline ``poly`` (N, 2) and its new elements ``angles``/``radii``.

    Stores the polyline's ``N - 1`` segments (at most :data:`MAX_REGISTER`) at rows ``n_store ..``
    of ``sp0``/``sp1`` (the caller made room) and in the store's grid buckets
    (:func:`._kernels.bucket_range`), splats them into the density ``grid``
    (:func:`.colonization._splat_segments`, when ``use_density``), counts ``angles`` and ``radii``
    in ``counts_a``/``counts_r`` and ``|angles|`` in ``bend_counts``. Returns
    ``(entries, above, length)``: the store's new entry count (-1, and nothing changed but the
    free rows of ``sp0``/``sp1``, when ``nxt`` is too short: the caller grows it and calls again),
    the change in covered domain cells and the polyline's length (numpy's summation order)."""
    N = poly.shape[0]
    k = N - 1 if N > 1 else 0
    for s in range(k):
        sp0[n_store + s, 0] = poly[s, 0]
        sp0[n_store + s, 1] = poly[s, 1]
        sp1[n_store + s, 0] = poly[s + 1, 0]
        sp1[n_store + s, 1] = poly[s + 1, 1]
    e = _bucket_range(head, nxt, seg, n_entries, sp0, sp1, n_store, n_store + k, store_cell)
    if e < 0:
        return -1, 0, 0.0
    above = 0
    length = 0.0
    if k > 0:
        if use_density:
            above = _splat_segments(grid, domain, poly[:-1], poly[1:], cell, rho, level)
        d = np.empty(k)
        for s in range(k):
            d[s] = np.hypot(poly[s + 1, 0] - poly[s, 0], poly[s + 1, 1] - poly[s, 1])
        length = _np_sum(d)
    na, nr = counts_a.shape[0], counts_r.shape[0]
    for i in range(angles.shape[0]):
        counts_a[_bin(edges_a, angles[i], na)] += 1.0
    for i in range(radii.shape[0]):
        counts_r[_bin(edges_r, radii[i], nr)] += 1.0
    nb = bend_counts.shape[0]
    for i in range(angles.shape[0]):
        bend_counts[_bin(bend_edges, abs(angles[i]), nb)] += 1.0
    return e, above, length


@numba.njit(cache=True)
def plain_step(t, angles, radii, ha, hr, local_points, local_dirs, cont_len, tipx, tipy, theta,
               use_hist, p_a, counts_a, bins_a, p_r, counts_r, bins_r, hist_scale,
               use_density, grid, cell, length, n_samples, tol, nbins, eps,
               cont_angles, use_bend, bend_p, bend_counts, bend_bins, bend_scale, bend_cap,
               use_runs, log_h, log_1h, log_q, log_1q, state, run, run_tol, max_run, mode, weight, run_gain,
               run_cap, lo, hi, wind_max, end_zero, use_fb, stop_density,
               head, nxt, seg, sp0, sp1, n_store, store_cell, cap, c, cross_eps):
    """A Markov step of ``_Grower.step`` without guidance, drain, shore, goal, mouth or frame factor,
    up to the draw: the scores of :func:`._kernels.score_step` (arguments up to ``eps``) times the
    step factors (:func:`._kernels.step_factors`, arguments ``cont_angles`` .. ``end_zero``; multiplied
    in when ``use_fb``, the forbidden candidates set to 0), both computed only for the candidates
    whose density profile crosses no branch (the others score 0 whatever their factors; 0 in
    ``points`` too), the density stop (no free candidate, or the
    least density ahead of the free ones at ``stop_density`` or more) and the ``c`` best candidates
    that cross no stored segment (:func:`._kernels.ranked_free`, arguments ``head`` ..).

    Returns ``(stopped, score, points, chosen)``: ``stopped`` the density stop (then ``chosen`` is
    empty), the final scores, the candidates' vertices (J, m, 2) and the chosen positions."""
    J, L = t.shape[0], ha.shape[0]
    m = local_points.shape[1]
    c_, s_ = np.cos(theta), np.sin(theta)
    # directions first (score_step's order of operations, candidate by candidate): a candidate whose
    # density profile crosses a branch scores 0 whatever its other factors, so only its direction is
    # needed (most candidates of a dense 1000 px cracked mud)
    dirs = np.empty((J, 2))
    for j in range(J):
        x, y = local_dirs[t[j], 0], local_dirs[t[j], 1]
        dirs[j, 0] = c_ * x - s_ * y
        dirs[j, 1] = s_ * x + c_ * y
    D_c = np.zeros(J)
    cross = np.zeros(J, np.bool_)
    if use_density:
        D_c, cross = _live_profiles(grid, cell, tipx, tipy, dirs, t, cont_len, length, n_samples, tol, nbins)
    pa = _hist_pre(p_a, counts_a) if use_hist else (0.0, 0.0, 0.0, 0.0, 0.0)
    pr = _hist_pre(p_r, counts_r) if use_hist else (0.0, 0.0, 0.0, 0.0, 0.0)
    pb = _hist_pre(bend_p, bend_counts) if use_bend else (0.0, 0.0, 0.0, 0.0, 0.0)
    pts = np.zeros((J, m, 2))
    out = np.zeros(J)
    lens = np.empty(J, np.int64)
    for j in range(J):
        r = t[j]
        lens[j] = max(cont_len[r], 0)
        if cross[j]:
            continue
        da = dr = 0.0
        e0 = r - L + 1
        for i in range(L):
            da += (angles[e0 + i] - ha[i]) ** 2
            dr += (radii[e0 + i] - hr[i]) ** 2
        q = (1.0 / (np.sqrt(da) + 1.0) + 1.0) * (1.0 / (np.sqrt(dr) + 1.0) + 1.0)
        for i in range(m):
            x, y = local_points[r, i, 0], local_points[r, i, 1]
            pts[j, i, 0] = tipx + c_ * x - s_ * y
            pts[j, i, 1] = tipy + s_ * x + c_ * y
        if use_hist:
            ia = _improve_bins(pa, p_a, counts_a, bins_a[r])
            ir = _improve_bins(pr, p_r, counts_r, bins_r[r])
            q *= np.exp(min(max(hist_scale * (ia + ir), -50.0), 50.0))
        sc = q / (D_c[j] + eps) if use_density else q
        d = _improve_bins(pb, bend_p, bend_counts, bend_bins[r]) if use_bend else 0.0
        f, z = _factor_at(r, d, cont_angles, cont_len, use_bend, bend_scale, bend_cap, use_runs, log_h, log_1h,
                          log_q, log_1q, state, run, run_tol, max_run, mode, weight, run_gain, run_cap, theta, lo,
                          hi, wind_max, end_zero)
        if use_fb:
            sc = sc * f
        out[j] = 0.0 if z else sc
    if use_density:
        best = np.inf
        anyfree = False
        for j in range(J):
            if not cross[j] and cont_len[t[j]] > 0:
                anyfree = True
                best = min(best, D_c[j])
        if not anyfree or best >= stop_density:
            return True, out, pts, np.empty(0, np.int64)
    tip = np.empty(2)
    tip[0], tip[1] = tipx, tipy
    chosen = _ranked_free(out, tip, pts, lens, head, nxt, seg, sp0, sp1, n_store, store_cell, cap, c,
                          use_density, cross_eps)
    return False, out, pts, chosen


@numba.njit(cache=True)
def child_start(usable, betas_u, child_index, wa, wr, win_a, win_r, mirror, theta0, straight,
                x0x, x0y, first_a, first_len, h, use_hist, rows_a, p_a, counts_a, rows_r, p_r, counts_r, hist_scale,
                use_density, grid, cell, length, n_samples, tol, nbins, eps, frame_h, frame_w, domain, use_domain,
                head, nxt, seg, sp0, sp1, n_store, store_cell, cap, c, cross_eps, r_scale=-1.0):
    """``start_child`` of a child with no guidance, drain or shore factor, up to the draw: the quality
    ``Q`` of the input furcations ``usable`` (:func:`._kernels.child_quality`, the parent's window
    ``win_a``/``win_r``; then, when ``mirror``, the same mirrored: heads again with their turns and
    furcation angles ``betas_u`` negated), the heads ``child_index[usable]`` started at ``theta0`` +
    their angle (0 when ``straight``: a child toward a hole), scored by :func:`._kernels.start_scores`
    (arguments ``x0x`` .. ``eps``, ``r_scale``), 0 where their first vertex leaves the frame or domain
    (:func:`._kernels.inside`), and the ``c`` best that cross no stored segment
    (:func:`._kernels.ranked_free`, arguments ``head`` ..).

    Returns ``(heads, n, new, th, sign, score, chosen)``: the candidate heads, their copied element
    counts, first vertices and headings, sign (-1 mirrored), final scores and the chosen positions:
    the same numbers as ``_Starts._start_branch``'s (the reference)."""
    F = usable.shape[0]
    Q = _child_quality(wa, wr, usable, win_a, win_r, mirror)
    H = F * (2 if mirror else 1)
    heads = np.empty(H, np.int64)
    th0 = np.empty(H)
    sign = np.empty(H)
    for half in range(2 if mirror else 1):
        for j in range(F):
            k = half * F + j
            heads[k] = child_index[usable[j]]
            b = 0.0 if straight else (-betas_u[j] if half == 1 else betas_u[j])
            th0[k] = theta0 + b
            sign[k] = -1.0 if half == 1 else 1.0
    n = np.empty(H, np.int64)
    for k in range(H):
        n[k] = first_len[heads[k]]
    new, th, score, _dirs, _dc = _start_scores(
        heads, th0, sign, first_a, n, x0x, x0y, h, Q, use_hist, rows_a, p_a, counts_a, rows_r, p_r, counts_r,
        hist_scale, use_density, grid, cell, length, n_samples, tol, nbins, eps, r_scale)
    first = np.empty((H, 2))
    for k in range(H):
        first[k, 0] = new[k, 0, 0]
        first[k, 1] = new[k, 0, 1]
    ok = _inside(first, frame_h, frame_w, domain, use_domain)
    for k in range(H):
        if not ok[k]:
            score[k] = 0.0
    tip = np.empty(2)
    tip[0], tip[1] = x0x, x0y
    lens = n + 1
    chosen = _ranked_free(score, tip, new, lens, head, nxt, seg, sp0, sp1, n_store, store_cell, cap, c,
                          use_density, cross_eps)
    return heads, n, new, th, sign, score, chosen


_E1, _E2 = np.zeros(1), np.zeros((1, 1), np.int16)
_E_GRID, _E_DOM = np.zeros((1, 1), np.float32), np.zeros((1, 1), bool)


def register_polyline(store, density, matcher, bends, polyline, angles=(), radii=()) -> float | None:
    """``_Grower._register`` through :func:`register`: the polyline's segments into ``store``
    (:class:`~branchnb.branching.colonization.SegmentStore`, its buffers grown as needed) and
    ``density`` (a :class:`~branchnb.branching.colonization.DensityMap` or None), the elements into
    ``matcher`` and ``bends`` (running histograms). Returns the polyline's length, or None (nothing
    done) for a polyline of more than :data:`MAX_REGISTER` vertices or not ``(N, 2)``: the caller
    takes the numpy path.
    """
    poly = np.ascontiguousarray(polyline, np.float64)
    if len(poly) > MAX_REGISTER or poly.ndim != 2 or poly.shape[1] != 2:
        return None
    a = np.ascontiguousarray(angles, np.float64).ravel()
    r = np.ascontiguousarray(radii, np.float64).ravel()
    k = max(len(poly) - 1, 0)
    while store.n + k > len(store.p0):
        store.p0 = np.vstack([store.p0, np.zeros_like(store.p0)])
        store.p1 = np.vstack([store.p1, np.zeros_like(store.p1)])
    dens = density
    while True:
        e, above, length = register(
            poly, a, r, store.p0, store.p1, store.n, store._head, store._next, store._seg, store._n_entries,
            store.cell, dens is not None, dens.grid if dens is not None else _E_GRID,
            dens.domain if dens is not None else _E_DOM, dens.cell if dens is not None else 1.0,
            dens.rho if dens is not None else 1.0, dens.level if dens is not None else 0.0,
            matcher.edges_a, matcher.counts_a, matcher.edges_r, matcher.counts_r, bends.edges, bends.counts)
        if e >= 0:
            break
        store._next = np.r_[store._next, np.zeros_like(store._next)]
        store._seg = np.r_[store._seg, np.zeros_like(store._seg)]
    store._n_entries = int(e)
    store.n += k
    if k and dens is not None:
        dens._n_above += int(above)
        dens.n_updates += 1
    matcher.n_nodes += int(r.size)
    return float(length) if k else 0.0


def step_call(model, p, matcher, density, store, st, tip, t, L: int, fargs: tuple, use_fb: bool, cap: int):
    """:func:`plain_step` of branch state ``st`` at ``tip`` over the candidate windows ``t`` (history
    length ``L``), with ``_Grower``'s model, parameters, running histograms, density and segment
    store; ``fargs``/``use_fb`` from ``_Grower._factor_args``, ``cap`` the crossing tests' cap."""
    bm = model.bending
    ha = np.asarray(st.elem_a[-L:], np.float64)
    hr = np.asarray(st.elem_r[-L:], np.float64)
    hm = matcher
    use_hist = hm.wG > 0 and hm.n_nodes > 0
    length = 3.0 * p.m * p.h
    dens = density
    if dens is not None:
        grid, cell = dens.grid, dens.cell
        n_samples = int(min(max(np.ceil(length / (dens.rho / 2.0)), 8), 48))
    else:
        grid, cell, n_samples = _E_GRID, 1.0, 8
    return plain_step(
        t, bm.angles, bm.radii, ha, hr, bm.local_points, model.local_dirs, bm.cont_len,
        float(tip[0]), float(tip[1]), float(st.theta),
        use_hist, hm.p_a if use_hist else _E1, hm.counts_a if use_hist else _E1,
        _cand_bins(model, "a") if use_hist else _E2, hm.p_r if use_hist else _E1,
        hm.counts_r if use_hist else _E1, _cand_bins(model, "r") if use_hist else _E2,
        hm.wG * hm.n_nodes / hm.m if use_hist else 0.0,
        dens is not None, grid, cell, length, n_samples, 0.02, _DIRECTION_BINS, float(p.eps),
        fargs[0], *fargs[2:21], *fargs[22:], use_fb, float(p.stop_density),
        store._head, store._next, store._seg, store.p0, store.p1, store.n, store.cell, cap, int(p.c), 1e-9)
