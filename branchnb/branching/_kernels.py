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
- :func:`bucket_add` / :func:`first_free`: the crossing test of
  :func:`~branchnb.branching.colonization.crosses_existing` on the segment
  grid of :class:`~branchnb.branching.colonization.SegmentStore`, run over
  the ranked candidates of a step until ``c`` free ones are found.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["bucket_add", "first_free", "pca_directions", "profile_bins"]


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
            bdc[q] = m
            bcr[q] = c
            done[q] = True
        dc[k] = bdc[q]
        cross[k] = bcr[q]
    return dc, cross


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
def _cells(v, cell, n):
    return min(max(int(np.floor(v / cell)), 0), n - 1)


@numba.njit(cache=True)
def bucket_add(head, nxt, seg, n_entries, p0, p1, first, cell):
    """Enter segments ``first ..`` (``p0``/``p1`` rows) into the grid buckets of their bounding box
    (linked lists: ``head[cy, cx]`` -> entry, ``nxt[entry]``, ``seg[entry]``); returns the new entry
    count, or -1 when ``nxt`` is too short (the caller grows it and calls again)."""
    gh, gw = head.shape
    need = n_entries
    for s in range(first, p0.shape[0]):
        x0 = _cells(min(p0[s, 0], p1[s, 0]), cell, gw)
        x1 = _cells(max(p0[s, 0], p1[s, 0]), cell, gw)
        y0 = _cells(min(p0[s, 1], p1[s, 1]), cell, gh)
        y1 = _cells(max(p0[s, 1], p1[s, 1]), cell, gh)
        need += (x1 - x0 + 1) * (y1 - y0 + 1)
    if need > nxt.shape[0]:
        return -1
    e = n_entries
    for s in range(first, p0.shape[0]):
        x0 = _cells(min(p0[s, 0], p1[s, 0]), cell, gw)
        x1 = _cells(max(p0[s, 0], p1[s, 0]), cell, gw)
        y0 = _cells(min(p0[s, 1], p1[s, 1]), cell, gh)
        y1 = _cells(max(p0[s, 1], p1[s, 1]), cell, gh)
        for cy in range(y0, y1 + 1):
            for cx in range(x0, x1 + 1):
                seg[e] = s
                nxt[e] = head[cy, cx]
                head[cy, cx] = e
                e += 1
    return e


@numba.njit(cache=True)
def _orient(px, py, qx, qy, rx, ry):
    return (qx - px) * (ry - py) - (qy - py) * (rx - px)


@numba.njit(cache=True)
def _proper(ax, ay, bx, by, cx, cy, dx, dy, eps):
    return _orient(ax, ay, bx, by, cx, cy) * _orient(ax, ay, bx, by, dx, dy) < -eps and \
        _orient(cx, cy, dx, dy, ax, ay) * _orient(cx, cy, dx, dy, bx, by) < -eps


@numba.njit(cache=True)
def crosses(head, nxt, seg, sp0, sp1, n_store, cell, poly, eps):
    """:func:`~branchnb.branching.colonization.crosses_existing` of polyline ``poly`` (N, 2)."""
    N = poly.shape[0]
    if N < 2:
        return False
    # the polyline's non-degenerate segments
    a0 = np.empty((N - 1, 2))
    a1 = np.empty((N - 1, 2))
    k = 0
    for i in range(N - 1):
        if poly[i, 0] != poly[i + 1, 0] or poly[i, 1] != poly[i + 1, 1]:
            a0[k, 0], a0[k, 1] = poly[i, 0], poly[i, 1]
            a1[k, 0], a1[k, 1] = poly[i + 1, 0], poly[i + 1, 1]
            k += 1
    if k == 0:
        return False
    if n_store > 0:
        lox = hix = a0[0, 0]
        loy = hiy = a0[0, 1]
        for i in range(k):
            lox = min(lox, a0[i, 0], a1[i, 0])
            hix = max(hix, a0[i, 0], a1[i, 0])
            loy = min(loy, a0[i, 1], a1[i, 1])
            hiy = max(hiy, a0[i, 1], a1[i, 1])
        gh, gw = head.shape
        for cy in range(_cells(loy, cell, gh), _cells(hiy, cell, gh) + 1):
            for cx in range(_cells(lox, cell, gw), _cells(hix, cell, gw) + 1):
                e = head[cy, cx]
                while e >= 0:
                    s = seg[e]
                    e = nxt[e]
                    bx0, by0, bx1, by1 = sp0[s, 0], sp0[s, 1], sp1[s, 0], sp1[s, 1]
                    if max(bx0, bx1) < lox or min(bx0, bx1) > hix or max(by0, by1) < loy or min(by0, by1) > hiy:
                        continue
                    for i in range(k):
                        if _proper(a0[i, 0], a0[i, 1], a1[i, 0], a1[i, 1], bx0, by0, bx1, by1, eps):
                            return True
    if k > 2:
        for i in range(k):
            for j in range(k):
                if _proper(a0[i, 0], a0[i, 1], a1[i, 0], a1[i, 1], a0[j, 0], a0[j, 1], a1[j, 0], a1[j, 1], eps):
                    return True
    return False


@numba.njit(cache=True)
def first_free(order, score, tip, pts, lens, head, nxt, seg, sp0, sp1, n_store, cell, cap, c, test, eps):
    """The first ``c`` candidates in ``order`` with a positive finite score whose polyline
    ``[tip] + pts[j, :lens[j]]`` crosses nothing (at most ``cap`` tested; ``test`` False: no test)."""
    out = np.empty(c, np.int64)
    n = 0
    tries = 0
    M = pts.shape[1]
    poly = np.empty((M + 1, 2))
    poly[0, 0], poly[0, 1] = tip[0], tip[1]
    for j in order:
        s = score[j]
        if not (s > 0) or not np.isfinite(s):
            break
        if test:
            tries += 1
            if tries > cap:
                break
            L = lens[j]
            for i in range(L):
                poly[i + 1, 0] = pts[j, i, 0]
                poly[i + 1, 1] = pts[j, i, 1]
            if crosses(head, nxt, seg, sp0, sp1, n_store, cell, poly[:L + 1], eps):
                continue
        out[n] = j
        n += 1
        if n == c:
            break
    return out[:n]
