"""Compiled crossing test of structure synthesis (numba, ``cache=True``): the segment grid of
:class:`~branchnb.branching.colonization.SegmentStore` (linked-list buckets, :func:`bucket_range` /
:func:`bucket_add`) and the tests of candidate polylines against it (:func:`crosses`,
:func:`first_free`, :func:`ranked_free`: the ``c`` best candidates that cross no stored segment).
Split from :mod:`branchnb.branching._kernels` (issue 23, branching46), which re-exports every name.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["bucket_add", "bucket_range", "crosses", "first_free", "ranked_free"]

@numba.njit(cache=True)
def _cells(v, cell, n):
    return min(max(int(np.floor(v / cell)), 0), n - 1)


@numba.njit(cache=True)
def _segment_cells(p0, p1, s, cell, gw, gh):
    """First and last grid column and row of segment ``s``'s bounding box."""
    return (_cells(min(p0[s, 0], p1[s, 0]), cell, gw), _cells(max(p0[s, 0], p1[s, 0]), cell, gw),
            _cells(min(p0[s, 1], p1[s, 1]), cell, gh), _cells(max(p0[s, 1], p1[s, 1]), cell, gh))


@numba.njit(cache=True)
def bucket_range(head, nxt, seg, n_entries, p0, p1, first, last, cell):
    """Enter segments ``first .. last - 1`` (``p0``/``p1`` rows) into the grid buckets of their bounding
    box (linked lists: ``head[cy, cx]`` -> entry, ``nxt[entry]``, ``seg[entry]``); returns the new entry
    count, or -1 (nothing entered) when ``nxt`` is too short (the caller grows it and calls again).
    Shared by :func:`bucket_add` and :func:`._loop_kernels.register`."""
    gh, gw = head.shape
    need = n_entries
    for s in range(first, last):
        x0, x1, y0, y1 = _segment_cells(p0, p1, s, cell, gw, gh)
        need += (x1 - x0 + 1) * (y1 - y0 + 1)
    if need > nxt.shape[0]:
        return -1
    e = n_entries
    for s in range(first, last):
        x0, x1, y0, y1 = _segment_cells(p0, p1, s, cell, gw, gh)
        for cy in range(y0, y1 + 1):
            for cx in range(x0, x1 + 1):
                seg[e] = s
                nxt[e] = head[cy, cx]
                head[cy, cx] = e
                e += 1
    return e


@numba.njit(cache=True)
def bucket_add(head, nxt, seg, n_entries, p0, p1, first, cell):
    """Enter segments ``first ..`` (``p0``/``p1`` rows) into the grid buckets of their bounding box
    (:func:`bucket_range` up to the last row); returns the new entry count, or -1 when ``nxt`` is
    too short (the caller grows it and calls again)."""
    return bucket_range(head, nxt, seg, n_entries, p0, p1, first, p0.shape[0], cell)


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


_STOP, _SKIP, _KEEP = 0, 1, 2


@numba.njit(cache=True)
def _verdict(j, score, tries, pts, lens, poly, head, nxt, seg, sp0, sp1, n_store, cell, cap, test, eps):
    """What the selection loops do with candidate ``j`` (``_STOP``: no positive finite score left or ``cap``
    tests spent; ``_SKIP``: it crosses a stored segment; ``_KEEP``), and the tests spent so far."""
    s = score[j]
    if not (s > 0) or not np.isfinite(s):
        return _STOP, tries
    if test:
        tries += 1
        if tries > cap:
            return _STOP, tries
        if _candidate_crosses(j, pts, lens, poly, head, nxt, seg, sp0, sp1, n_store, cell, eps):
            return _SKIP, tries
    return _KEEP, tries


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
        verdict, tries = _verdict(j, score, tries, pts, lens, poly, head, nxt, seg, sp0, sp1, n_store, cell, cap,
                                  test, eps)
        if verdict == _STOP:
            break
        if verdict == _SKIP:
            continue
        out[n] = j
        n += 1
        if n == c:
            break
    return out[:n]


@numba.njit(cache=True)
def _candidate_crosses(j, pts, lens, poly, head, nxt, seg, sp0, sp1, n_store, cell, eps):
    """Does ``poly[0] + pts[j, :lens[j]]`` (``poly[0]`` the tip; ``poly`` a work buffer) cross a stored segment?"""
    L = lens[j]
    for i in range(L):
        poly[i + 1, 0] = pts[j, i, 0]
        poly[i + 1, 1] = pts[j, i, 1]
    return crosses(head, nxt, seg, sp0, sp1, n_store, cell, poly[:L + 1], eps)


@numba.njit(cache=True)
def _ranks_before(key, i, j):
    """Does candidate ``i`` rank before ``j``: ``np.argsort(-key, kind="stable")`` order (higher
    float32 key first, ties by index, NaN last)?"""
    a, b = key[i], key[j]
    if np.isnan(a):
        return np.isnan(b) and i < j
    if np.isnan(b):
        return True
    return a > b or (a == b and i < j)


@numba.njit(cache=True)
def ranked_free(score, tip, pts, lens, head, nxt, seg, sp0, sp1, n_store, cell, cap, c, test, eps):
    """:func:`first_free` over the candidates ranked by their scores rounded to float32
    (``scoring._rank_key``; ``np.argsort(-key, kind="stable")``: ties by index), ranked lazily: each next
    candidate is the best of those left, so a step that finds its ``c`` free ones among the first few
    does not sort all of them (the same candidates as ``first_free(np.argsort(...), ...)``)."""
    J = score.shape[0]
    key = np.empty(J, np.float32)
    for j in range(J):
        key[j] = np.float32(score[j])
    used = np.zeros(J, np.bool_)
    out = np.empty(c, np.int64)
    n = 0
    tries = 0
    M = pts.shape[1]
    poly = np.empty((M + 1, 2))
    poly[0, 0], poly[0, 1] = tip[0], tip[1]
    for _ in range(J):
        j = -1
        for i in range(J):
            if not used[i] and (j < 0 or _ranks_before(key, i, j)):
                j = i
        used[j] = True
        verdict, tries = _verdict(j, score, tries, pts, lens, poly, head, nxt, seg, sp0, sp1, n_store, cell, cap,
                                  test, eps)
        if verdict == _STOP:
            break
        if verdict == _SKIP:
            continue
        out[n] = j
        n += 1
        if n == c:
            break
    return out[:n]
