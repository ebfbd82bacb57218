"""Numba kernels of the planner (:mod:`.planner`): Dijkstra over a pixel
lattice or a CSR graph with a scalar key (``a * M + S``) or the
lexicographic pair ``(M, S)``.

Every kernel writes its heap operations out in its own body. Calling a
jitted helper that takes arrays makes numba increment and decrement the
arrays' reference counts (atomic operations) on every call, even when the
helper is inlined: in the non-scalar lattice kernel that was a fifth of the
run time (issue 25).
"""

from __future__ import annotations

import numba
import numpy as np
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic


@intrinsic
def _prefetch(typingctx, arr, idx):
    """Ask the CPU to start loading ``arr[idx]`` into the cache (no effect on results).

    The searches that jump across the lattice (non-scalar, blend: the next
    node to settle can be anywhere on a long frontier) spend much of their
    time waiting for the neighbourhood of that node; it is known a little
    before it is needed (the heap root), so its loads can overlap the heap
    work in between.
    """
    sig = types.void(arr, idx)

    def codegen(context, builder, signature, args):
        aryty = signature.args[0]
        ary = context.make_array(aryty)(context, builder, args[0])
        ptr = cgutils.get_item_pointer(context, builder, aryty, ary, [args[1]], wraparound=False)
        i8p = ir.IntType(8).as_pointer()
        i32 = ir.IntType(32)
        fn = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32]), "llvm.prefetch.p0")
        # read access, high temporal locality, data cache
        builder.call(fn, [builder.bitcast(ptr, i8p), i32(0), i32(3), i32(1)])
        return context.get_dummy_value()

    return sig, codegen


# ------------------------------------------------------------------ queue
# An indexed 4-ary min-heap with decrease-key: every unsettled node that has
# been offered a path sits in the heap exactly once (``pos[v]`` is its slot;
# -1 = never offered, -2 = settled), so the heap holds the frontier only, no
# superseded entries, and a pop never has to test an entry for staleness.
# Scalar keys (cumulative: S; blend: a * M + S) live in one float array. The
# non-scalar key (M, S) is kept interleaved ``hk[2 i], hk[2 i + 1]`` and
# compared lexicographically on a sparse graph; on a lattice it is split
# over two single-key heaps (a level heap on S in front of a frontier heap
# on M, see :func:`_lattice_pair`). The heap arrays are sized to the graph
# once per call (the frontier can never hold more than every node). On a
# 512 x 512 lattice this is 1.6 to 3 times as fast as the former bucket
# queue with lazy deletion (issue 25) and settles the nodes in the same
# order. Bucket queues (node-linked lists over quantised keys; a near heap
# in front of an unsorted far list) and a radix heap on the key bits were
# tried again for the non-scalar frontier and were no faster: its time goes
# into waiting for memory, and prefetching is what helped (issue 25).
_ARITY = 4


@numba.njit(cache=True)
def _start(n_nodes, seeds, metric, mmax, total, parent):
    """Heap arrays for one search, with the seeds (label (0, 0)) queued."""
    hk = np.empty((2 if metric == 1 else 1) * n_nodes)
    hn = np.empty(n_nodes, np.int32)  # int32 node indices halve the heap's memory traffic
    pos = np.full(n_nodes, -1, np.int32)
    key = np.full(n_nodes if metric != 1 else 0, np.inf)  # scalar key of every node
    n = 0
    for s in seeds:
        if pos[s] == -1:
            mmax[s] = 0.0
            total[s] = 0.0
            parent[s] = -1
            if metric == 1:
                hk[2 * n] = 0.0
                hk[2 * n + 1] = 0.0
            else:
                key[s] = 0.0
                hk[n] = 0.0
            hn[n] = s  # every seed key is 0: any order is a heap
            pos[s] = n
            n += 1
    return hk, hn, pos, key, n


@numba.njit(cache=True)
def _count_stops(stop_at):
    c = 0
    for i in range(stop_at.shape[0]):
        if stop_at[i]:
            c += 1
    return c


# ------------------------------------------------------------------- kernels
# One kernel per graph kind and key kind (scalar key a * M + S, a = 0 for the
# cumulative metric; the lexicographic pair (M, S)), so that no metric test
# runs inside the relaxation loop.
@numba.njit(cache=True)
def _lattice_scalar(w, height, width, drow, dcol, factor, mfactor, seeds, a,
                    mmax, total, parent, order, stop_at):
    # mfactor: the direction factors of the bottleneck term M (``factor`` for the
    # paper's max edge cost; ``factor`` / step length for a cost per unit length)
    # the heap operations are written out here: through the (inlined)
    # helpers this kernel ran about 25 % slower
    hk, hn, pos, key, n = _start(height * width, seeds, 0, mmax, total, parent)
    remaining = _count_stops(stop_at)
    count = 0
    while n > 0:
        u = hn[0]
        pos[u] = -2
        n -= 1
        if n > 0:
            lk = hk[n]
            ln = hn[n]
            i = 0
            while True:
                c0 = _ARITY * i + 1
                if c0 >= n:
                    break
                c = c0
                b = hk[c0]
                for j in range(c0 + 1, min(c0 + _ARITY, n)):
                    if hk[j] < b:
                        c = j
                        b = hk[j]
                if b < lk:
                    x = hn[c]
                    hk[i] = b
                    hn[i] = x
                    pos[x] = i
                    i = c
                else:
                    break
            hk[i] = lk
            hn[i] = ln
            pos[ln] = i
        if n > 0:  # the next node to settle, most likely
            r0 = hn[0] // width
            c0 = hn[0] - r0 * width
            for dr in range(-1, 2):
                if 0 <= r0 + dr < height:
                    q = (r0 + dr) * width + max(c0 - 1, 0)
                    q2 = min(q + 2, height * width - 1)  # the row's 3 nodes may span two lines
                    _prefetch(pos, q)
                    _prefetch(w, q)
                    _prefetch(w, q2)
                    _prefetch(key, q)
                    _prefetch(key, q2)
            _prefetch(mmax, hn[0])  # read for the node itself only
            _prefetch(total, hn[0])
        order[count] = u
        count += 1
        if remaining > 0 and stop_at[u]:  # no lookup (a cache miss) without targets
            remaining -= 1
            if remaining == 0:
                break
        r = u // width
        c = u - r * width
        wu = w[u]
        mu = mmax[u]
        su = total[u]
        for k in range(8):
            rr = r + drow[k]
            cc = c + dcol[k]
            if rr < 0 or rr >= height or cc < 0 or cc >= width:
                continue
            v = rr * width + cc
            pv = pos[v]
            if pv == -2:
                continue
            wv = w[v]
            if not wv < np.inf:
                continue
            wm = 0.5 * (wu + wv)
            e = wm * factor[k]
            m = max(mu, wm * mfactor[k])
            s = su + e
            nk = a * m + s
            if nk < key[v]:
                mmax[v] = m
                total[v] = s
                parent[v] = u
                key[v] = nk
                if pv < 0:
                    i = n
                    n += 1
                else:
                    i = pv
                while i > 0:
                    p = (i - 1) >> 2
                    if nk < hk[p]:
                        x = hn[p]
                        hk[i] = hk[p]
                        hn[i] = x
                        pos[x] = i
                        i = p
                    else:
                        break
                hk[i] = nk
                hn[i] = v
                pos[v] = i
    return count


@numba.njit(cache=True)
def _lattice_pair(w, height, width, drow, dcol, factor, seeds,
                  mmax, total, parent, order, stop_at):
    # The non-scalar key (M, S): nodes whose M equals the current level (the
    # M of the node last settled: the flood of one basin) wait in a level
    # heap keyed by S alone; the others in a frontier heap keyed by M alone.
    # Frontier nodes that tie the new level move to the level heap when it
    # is opened, so pops follow (M, S) exactly, while most pops and pushes
    # touch only the small level heap. pos[v]: >= 0 frontier slot, -3 - i
    # level slot i, -1 never offered, -2 settled. Both heaps are indexed
    # 4-ary heaps, written out (see the module docstring).
    n_nodes = height * width
    bk = np.empty(n_nodes)
    bn = np.empty(n_nodes, np.int32)
    lk = np.empty(n_nodes)
    ln = np.empty(n_nodes, np.int32)
    pos = np.full(n_nodes, -1, np.int32)
    nb = 0
    nl = 0
    level = 0.0
    for s in seeds:
        if pos[s] == -1:
            mmax[s] = 0.0
            total[s] = 0.0
            parent[s] = -1
            lk[nl] = 0.0  # all seed keys are 0: any order is a heap
            ln[nl] = s
            pos[s] = -3 - nl
            nl += 1
    remaining = _count_stops(stop_at)
    count = 0
    while True:
        if nl == 0:
            if nb == 0:
                break
            # open the next level: every frontier node whose M ties the
            # smallest moves to the level heap
            # the neighbourhood of the node that opens the level
            r0 = bn[0] // width
            c0 = bn[0] - r0 * width
            for dr in range(-1, 2):
                if 0 <= r0 + dr < height:
                    q = (r0 + dr) * width + max(c0 - 1, 0)
                    q2 = min(q + 2, height * width - 1)  # the row's 3 nodes may span two lines
                    _prefetch(pos, q)
                    _prefetch(w, q)
                    _prefetch(w, q2)
                    _prefetch(mmax, q)
                    _prefetch(mmax, q2)
                    _prefetch(total, q)
                    _prefetch(total, q2)
            level = bk[0]
            while nb > 0 and bk[0] == level:
                v = bn[0]
                # pop the frontier root
                nb -= 1
                if nb > 0:
                    k = bk[nb]
                    x = bn[nb]
                    i = 0
                    while True:
                        c0 = _ARITY * i + 1
                        if c0 >= nb:
                            break
                        c = c0
                        b = bk[c0]
                        for j in range(c0 + 1, min(c0 + _ARITY, nb)):
                            if bk[j] < b:
                                c = j
                                b = bk[j]
                        if b < k:
                            y = bn[c]
                            bk[i] = b
                            bn[i] = y
                            pos[y] = i
                            i = c
                        else:
                            break
                    bk[i] = k
                    bn[i] = x
                    pos[x] = i
                # push v on the level heap
                k = total[v]
                i = nl
                nl += 1
                while i > 0:
                    p = (i - 1) >> 2
                    if k < lk[p]:
                        y = ln[p]
                        lk[i] = lk[p]
                        ln[i] = y
                        pos[y] = -3 - i
                        i = p
                    else:
                        break
                lk[i] = k
                ln[i] = v
                pos[v] = -3 - i
            if nb > 0:  # the node that will most likely open the next level
                r0 = bn[0] // width
                c0 = bn[0] - r0 * width
                for dr in range(-1, 2):
                    if 0 <= r0 + dr < height:
                        q = (r0 + dr) * width + max(c0 - 1, 0)
                        q2 = min(q + 2, height * width - 1)  # the row's 3 nodes may span two lines
                        _prefetch(pos, q)
                        _prefetch(w, q)
                        _prefetch(w, q2)
                        _prefetch(mmax, q)
                        _prefetch(mmax, q2)
                        _prefetch(total, q)
                        _prefetch(total, q2)
        # pop the level root
        u = ln[0]
        su = lk[0]
        pos[u] = -2
        nl -= 1
        if nl > 0:
            k = lk[nl]
            x = ln[nl]
            i = 0
            while True:
                c0 = _ARITY * i + 1
                if c0 >= nl:
                    break
                c = c0
                b = lk[c0]
                for j in range(c0 + 1, min(c0 + _ARITY, nl)):
                    if lk[j] < b:
                        c = j
                        b = lk[j]
                if b < k:
                    y = ln[c]
                    lk[i] = b
                    ln[i] = y
                    pos[y] = -3 - i
                    i = c
                else:
                    break
            lk[i] = k
            ln[i] = x
            pos[x] = -3 - i
        if nl > 0:  # the next node of this level
            r0 = ln[0] // width
            c0 = ln[0] - r0 * width
            for dr in range(-1, 2):
                if 0 <= r0 + dr < height:
                    q = (r0 + dr) * width + max(c0 - 1, 0)
                    q2 = min(q + 2, height * width - 1)
                    _prefetch(pos, q)
                    _prefetch(w, q)
                    _prefetch(w, q2)
                    _prefetch(mmax, q)
                    _prefetch(mmax, q2)
        order[count] = u
        count += 1
        if remaining > 0 and stop_at[u]:  # no lookup (a cache miss) without targets
            remaining -= 1
            if remaining == 0:
                break
        r = u // width
        c = u - r * width
        wu = w[u]
        for kk in range(8):
            rr = r + drow[kk]
            cc = c + dcol[kk]
            if rr < 0 or rr >= height or cc < 0 or cc >= width:
                continue
            v = rr * width + cc
            pv = pos[v]
            if pv == -2:
                continue
            wv = w[v]
            if not wv < np.inf:
                continue
            e = 0.5 * (wu + wv) * factor[kk]
            s = su + e
            om = mmax[v]  # >= level for every unsettled node
            if e <= level:  # label (level, s)
                if level < om:
                    if pv >= 0:
                        # remove v from the frontier heap (slot pv)
                        nb -= 1
                        if pv < nb:
                            k = bk[nb]
                            x = bn[nb]
                            i = pv
                            if i > 0 and k < bk[(i - 1) >> 2]:
                                while i > 0:
                                    p = (i - 1) >> 2
                                    if k < bk[p]:
                                        y = bn[p]
                                        bk[i] = bk[p]
                                        bn[i] = y
                                        pos[y] = i
                                        i = p
                                    else:
                                        break
                            else:
                                while True:
                                    c0 = _ARITY * i + 1
                                    if c0 >= nb:
                                        break
                                    ch = c0
                                    b = bk[c0]
                                    for j in range(c0 + 1, min(c0 + _ARITY, nb)):
                                        if bk[j] < b:
                                            ch = j
                                            b = bk[j]
                                    if b < k:
                                        y = bn[ch]
                                        bk[i] = b
                                        bn[i] = y
                                        pos[y] = i
                                        i = ch
                                    else:
                                        break
                            bk[i] = k
                            bn[i] = x
                            pos[x] = i
                    mmax[v] = level
                    i = nl
                    nl += 1
                elif s < total[v]:
                    i = -3 - pv
                else:
                    continue
                total[v] = s
                parent[v] = u
                # sift v up the level heap from slot i
                while i > 0:
                    p = (i - 1) >> 2
                    if s < lk[p]:
                        y = ln[p]
                        lk[i] = lk[p]
                        ln[i] = y
                        pos[y] = -3 - i
                        i = p
                    else:
                        break
                lk[i] = s
                ln[i] = v
                pos[v] = -3 - i
            elif e < om:  # label (e, s), v new or on the frontier
                mmax[v] = e
                total[v] = s
                parent[v] = u
                if pv == -1:
                    i = nb
                    nb += 1
                else:
                    i = pv
                while i > 0:
                    p = (i - 1) >> 2
                    if e < bk[p]:
                        y = bn[p]
                        bk[i] = bk[p]
                        bn[i] = y
                        pos[y] = i
                        i = p
                    else:
                        break
                bk[i] = e
                bn[i] = v
                pos[v] = i
            elif e == om and s < total[v]:  # same frontier key, shorter path
                total[v] = s
                parent[v] = u
    return count


@numba.njit(cache=True)
def _csr_scalar(indptr, indices, data, seeds, a, mmax, total, parent, order, stop_at):
    hk, hn, pos, key, n = _start(indptr.shape[0] - 1, seeds, 0, mmax, total, parent)
    remaining = _count_stops(stop_at)
    count = 0
    while n > 0:
        u = hn[0]
        pos[u] = -2
        n -= 1
        if n > 0:
            lk = hk[n]
            ln = hn[n]
            i = 0
            while True:
                c0 = _ARITY * i + 1
                if c0 >= n:
                    break
                c = c0
                b = hk[c0]
                for j in range(c0 + 1, min(c0 + _ARITY, n)):
                    if hk[j] < b:
                        c = j
                        b = hk[j]
                if b < lk:
                    x = hn[c]
                    hk[i] = b
                    hn[i] = x
                    pos[x] = i
                    i = c
                else:
                    break
            hk[i] = lk
            hn[i] = ln
            pos[ln] = i
        order[count] = u
        count += 1
        if remaining > 0 and stop_at[u]:  # no lookup (a cache miss) without targets
            remaining -= 1
            if remaining == 0:
                break
        mu = mmax[u]
        su = total[u]
        for jj in range(indptr[u], indptr[u + 1]):
            v = indices[jj]
            pv = pos[v]
            if pv == -2:
                continue
            e = data[jj]
            if not e < np.inf:
                continue
            m = max(mu, e)
            s = su + e
            nk = a * m + s
            if nk < key[v]:
                mmax[v] = m
                total[v] = s
                parent[v] = u
                key[v] = nk
                if pv < 0:
                    i = n
                    n += 1
                else:
                    i = pv
                while i > 0:
                    p = (i - 1) >> 2
                    if nk < hk[p]:
                        x = hn[p]
                        hk[i] = hk[p]
                        hn[i] = x
                        pos[x] = i
                        i = p
                    else:
                        break
                hk[i] = nk
                hn[i] = v
                pos[v] = i
    return count


@numba.njit(cache=True)
def _csr_pair(indptr, indices, data, seeds, mmax, total, parent, order, stop_at):
    hk, hn, pos, _, n = _start(indptr.shape[0] - 1, seeds, 1, mmax, total, parent)
    remaining = _count_stops(stop_at)
    count = 0
    while n > 0:
        u = hn[0]
        pos[u] = -2
        n -= 1
        if n > 0:
            l1 = hk[2 * n]
            l2 = hk[2 * n + 1]
            ln = hn[n]
            i = 0
            while True:
                c0 = _ARITY * i + 1
                if c0 >= n:
                    break
                c = c0
                b1 = hk[2 * c0]
                b2 = hk[2 * c0 + 1]
                for j in range(c0 + 1, min(c0 + _ARITY, n)):
                    x1 = hk[2 * j]
                    if x1 < b1 or (x1 == b1 and hk[2 * j + 1] < b2):
                        c = j
                        b1 = x1
                        b2 = hk[2 * j + 1]
                if b1 < l1 or (b1 == l1 and b2 < l2):
                    x = hn[c]
                    hk[2 * i] = b1
                    hk[2 * i + 1] = b2
                    hn[i] = x
                    pos[x] = i
                    i = c
                else:
                    break
            hk[2 * i] = l1
            hk[2 * i + 1] = l2
            hn[i] = ln
            pos[ln] = i
        order[count] = u
        count += 1
        if remaining > 0 and stop_at[u]:  # no lookup (a cache miss) without targets
            remaining -= 1
            if remaining == 0:
                break
        mu = mmax[u]
        su = total[u]
        for jj in range(indptr[u], indptr[u + 1]):
            v = indices[jj]
            pv = pos[v]
            if pv == -2:
                continue
            e = data[jj]
            if not e < np.inf:
                continue
            m = max(mu, e)
            s = su + e
            om = mmax[v]
            if m < om or (m == om and s < total[v]):
                mmax[v] = m
                total[v] = s
                parent[v] = u
                if pv < 0:
                    i = n
                    n += 1
                else:
                    i = pv
                while i > 0:
                    p = (i - 1) >> 2
                    p1 = hk[2 * p]
                    if m < p1 or (m == p1 and s < hk[2 * p + 1]):
                        x = hn[p]
                        hk[2 * i] = p1
                        hk[2 * i + 1] = hk[2 * p + 1]
                        hn[i] = x
                        pos[x] = i
                        i = p
                    else:
                        break
                hk[2 * i] = m
                hk[2 * i + 1] = s
                hn[i] = v
                pos[v] = i
    return count
