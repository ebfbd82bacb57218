"""Step 1 of image synthesis (paper: "fragments"): which source fragment goes where.

For each target fragment every source fragment gets the shape cost ``S``
(:mod:`.fragments`); this module adds the rules and the colour cost ``C``
of :func:`~branchnb.branching.image_synthesis.synthesize_image`: free tips
(a target tip is never copied from a source end that runs into another
branch), the source pixels a fragment may copy (no other branch, no matte,
its own branch only where it lands on the target skeleton) and ``C`` on
the overlap with what is already synthesised.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np

from .fragments import Fragment, FragmentLibrary
from .skeleton_map import PixelMap, SkeletonMap

if TYPE_CHECKING:
    from .image_params import ImageSynthesisParams

__all__: list[str] = []


@dataclass
class _Context:
    ex: np.ndarray
    sm_s: SkeletonMap
    sm_t: SkeletonMap
    pm_s: PixelMap
    excluded: np.ndarray   # example pixels of some branch (body or branch-like)
    unusable: np.ndarray   # example pixels never copied
    p: ImageSynthesisParams

def _free_ends(sm: SkeletonMap, pm: PixelMap) -> tuple[np.ndarray, np.ndarray]:
    """Which branch ends of the example are free tips.

    An end is *joined* (no tip) when it is a furcation (a child's start)
    or when another branch's body lies within ``2 r + 4`` pixels of it: the
    annotation (or the extraction) stopped the branch where it runs into
    another one. A target tip must not be copied from a joined end, or it
    would carry a piece of junction instead of a tip.
    """
    n = sm.n_branches
    h, w = pm.dist.shape
    other_body = pm.dist <= pm.radius + 1.0
    free = np.zeros((n, 2), bool)
    for b in range(n):
        for k, arc in enumerate((0.0, float(sm.lengths[b]))):
            if k == 0 and sm.parent(b) is not None:
                continue
            x, y = sm.position(b, arc)
            rad = 2.0 * float(sm.thickness(b, arc)) + 4.0
            x0, x1 = max(int(x - rad), 0), min(int(x + rad) + 2, w)
            y0, y1 = max(int(y - rad), 0), min(int(y + rad) + 2, h)
            if x0 >= x1 or y0 >= y1:
                continue
            yy, xx = np.mgrid[y0:y1, x0:x1]
            disk = (xx - x) ** 2 + (yy - y) ** 2 <= rad * rad
            blk = (y0, y1, x0, x1)
            others = other_body[blk[0]:blk[1], blk[2]:blk[3]] & (pm.branch[blk[0]:blk[1], blk[2]:blk[3]] != b)
            free[b, k] = not (disk & others).any()
    return free[:, 0], free[:, 1]


def _joined_at_region_edge(sm: SkeletonMap, labels: np.ndarray, free_start: np.ndarray,
                           free_end: np.ndarray) -> None:
    """An example end where the branch meets another flat region (a channel's mouth at the
    sea) is no tip either: copied as one it would carry a piece of that region (a blob)."""
    h, w = labels.shape
    for b in range(sm.n_branches):
        xm, ym = sm.position(b, 0.5 * float(sm.lengths[b]))
        own = labels[int(np.clip(round(ym), 0, h - 1)), int(np.clip(round(xm), 0, w - 1))]
        for arr, arc in ((free_start, 0.0), (free_end, float(sm.lengths[b]))):
            if not arr[b]:
                continue
            x, y = sm.position(b, arc)
            rad = 2.0 * float(sm.thickness(b, arc)) + 4.0
            x0, x1 = max(int(x - rad), 0), min(int(x + rad) + 2, w)
            y0, y1 = max(int(y - rad), 0), min(int(y + rad) + 2, h)
            if x0 < x1 and y0 < y1 and np.any(labels[y0:y1, x0:x1] != own):
                arr[b] = False


def _tip_penalty(sm_t: SkeletonMap, tf: Fragment, lib: FragmentLibrary, lengths: np.ndarray,
                 free_start: np.ndarray, free_end: np.ndarray, free_t) -> np.ndarray:
    """Rule out source windows that end at a joined end where the target window ends at a free tip."""
    R = tf.radius
    L_t = float(sm_t.lengths[tf.branch])
    pen = np.zeros(len(lib))
    tip_fwd = tf.arc + R > L_t and free_t[1][tf.branch]
    tip_bwd = tf.arc - R < 0 and free_t[0][tf.branch]
    if not (tip_fwd or tip_bwd):
        return pen
    L = lengths[lib.branch]
    fwd = lib.sign > 0
    # Ends reached when reading forward / backward from the candidate's centre.
    end_fwd_free = np.where(fwd, free_end[lib.branch], free_start[lib.branch])
    end_bwd_free = np.where(fwd, free_start[lib.branch], free_end[lib.branch])
    clamps_fwd = np.where(fwd, lib.arc + R > L, lib.arc - R < 0)
    clamps_bwd = np.where(fwd, lib.arc - R < 0, lib.arc + R > L)
    bad = np.zeros(len(lib), bool)
    if tip_fwd:
        bad |= clamps_fwd & ~end_fwd_free
    if tip_bwd:
        bad |= clamps_bwd & ~end_bwd_free
    pen[bad] = 1e6
    return pen


#: Target lines thinner than this (mean radius over the shape vector, px) take fragments of a like
#: radius only (:func:`_thin_penalty`): below about 1.5 px the example's own centre-line contrast still
#: rises with the radius (procedural cracks and neurons: 0.42-0.50 at r 0.5-0.75, 0.88-0.91 at 0.75-1,
#: 0.91-0.94 at 1-1.5, 0.99 above; 1 = the thick lines' colour).
THIN_MATCH_RADIUS = 1.5
#: Largest ratio of source to target mean radius (either way) a thin target accepts while any source
#: within it exists (0 = off, the paper's thickness term only). 1.2 splits the example's 1-px drawn
#: lines (traced r 0.5-0.75) from its 2-px ones (0.75-1).
THIN_MATCH_RATIO = 1.2
#: Added to ``S`` of a source outside the ratio: above any shape cost a usable candidate has (a 6 px disk
#: of nine samples), below the tip rule's 1e6.
THIN_MISMATCH = 1e4


def _thin_penalty(mu: np.ndarray, nu: np.ndarray) -> np.ndarray | float:
    """``THIN_MISMATCH`` for sources ``mu`` (N, K) whose mean radius is off a thin target's ``nu`` (K,).

    Beyond the paper (issue 23): its thickness term ``wS |mu - nu|^2`` hardly tells a 0.6 px line from a
    0.9 px one (0.2-1.6 in ``S``, next to shape residuals of several px^2), but on the example these are a
    pale 1-px line and a dark 2-px one; a thin target drawn from the wrong one came out at 0.49-0.62 of
    the line colour where the example's lines of its radius have 0.84-0.92 (or darker than the example's
    thinnest). A source whose mean radius is more than ``THIN_MATCH_RATIO`` off is ranked behind every
    one within it; with none within, the order is the paper's. Targets of ``THIN_MATCH_RADIUS`` and
    more are unchanged (0).

    Measured (branching120; ``python -m branchnb.branching._hub_image_check``, ``bins``: per radius bin
    the 10th percentile over branches of their centre-line contrast, example / output): target fragments
    of r 0.75-1 copied from a 1-px line, crack 512 s1 24 % -> 12 %; the 0.75-1 bin, crack 512 s1 0.64 ->
    1.06 (example 0.99), neuron 384 s1 0.74 -> 0.81 (0.74), crack 768 s3 0.92 -> 0.95 (0.98), but
    neuron_dark 256 s2 1.10 -> 0.71 (1.09: a target of r 0.8 still takes a 0.7 px source, inside the
    ratio); the thinnest lines no longer darker than the example's (median centre contrast at r
    0.5-0.75, neuron 384 s1 0.68 -> 0.52, example 0.48; crack 768 s3 0.67 -> 0.61, 0.45); a night
    storm's bolts (384 px) at r 0.75-1.5 0.48-0.57 -> 1.04-1.08 (1.09-1.11). Thick lines, flat-drawn
    examples and lightning traced at r >= 1.5: unchanged.
    """
    r_t = float(np.mean(nu))
    if THIN_MATCH_RATIO <= 1.0 or r_t >= THIN_MATCH_RADIUS or r_t <= 0:
        return 0.0
    r_s = np.maximum(mu.mean(axis=1), 1e-6)
    off = np.abs(np.log(r_s / r_t)) > np.log(THIN_MATCH_RATIO)
    if off.all():
        return 0.0
    return np.where(off, THIN_MISMATCH, 0.0)


def _target_window(sm: SkeletonMap, branch: int, arc: float, radius: float):
    """Offsets range ``[lo, hi]`` of the target disk that lies on ``branch``."""
    L = float(sm.lengths[branch])
    lo = -arc if arc - 1.5 * radius < 0 else -np.inf
    hi = L - arc if arc + 1.5 * radius > L else np.inf
    return lo, hi


def _allowed(ctx: _Context, mx, my, lib: FragmentLibrary, idx, tgt: Fragment) -> np.ndarray:
    """Source pixels fragments may copy: not the matte, not any other branch
    (annotated body or branch-like), nor their own branch beyond the part
    that lands on the target skeleton.

    ``mx, my`` are ``(N, h, w)`` source coordinates of candidates ``idx`` of ``lib``.
    """
    h, w = ctx.pm_s.dist.shape
    ix = np.clip(np.rint(mx).astype(np.int64), 0, w - 1)
    iy = np.clip(np.rint(my).astype(np.int64), 0, h - 1)
    excl = ctx.excluded[iy, ix]
    owner = ctx.pm_s.branch[iy, ix]
    arc = ctx.pm_s.arc[iy, ix]
    slack = 0.5
    idx = np.atleast_1d(idx)

    def in_window(branch_s, centre_s, sign, lo, hi):
        a, b = centre_s + sign * lo, centre_s + sign * hi
        lo_s = np.minimum(a, b)[:, None, None] - slack
        hi_s = np.maximum(a, b)[:, None, None] + slack
        return (owner == branch_s[:, None, None]) & (arc >= lo_s) & (arc <= hi_s)

    lo, hi = _target_window(ctx.sm_t, tgt.branch, tgt.arc, tgt.radius)
    ok = in_window(lib.branch[idx], lib.arc[idx], lib.sign[idx], lo, hi)
    if tgt.kind == "furcation":
        Lc = float(ctx.sm_t.lengths[tgt.child])
        zero = np.zeros(len(idx))
        ok |= in_window(lib.child[idx], zero, zero + 1.0, -np.inf,
                        Lc if Lc < 1.5 * tgt.radius else np.inf)
    return (~excl | ok) & ~ctx.unusable[iy, ix]


@numba.njit(cache=True)
def _colour_cost_kernel(ex, xs, ys, rot, trans, excluded, owner, arcmap, unusable, win_b, win_lo, win_hi,
                        ref, on_body):
    """Colour cost of every candidate on the overlap pixels ``(xs, ys)`` (see :func:`_colour_costs`).

    Per candidate and pixel: the rigid backward map (float32, as :func:`~.displacement.backward_map`),
    the rules of :func:`_allowed` and bilinear sampling with a replicated border (as ``cv2.remap``),
    without building the ``(candidates, pixels)`` arrays.
    """
    h, w, C = ex.shape
    n, P = rot.shape[0], xs.shape[0]
    out = np.zeros(n)
    for k in range(n):
        s_on, s_off, n_on, n_off = 0.0, 0.0, 0, 0
        for p in range(P):
            X = np.float64(xs[p]) - trans[k, 0]
            Y = np.float64(ys[p]) - trans[k, 1]
            mx = np.float32(rot[k, 0, 0] * X + rot[k, 1, 0] * Y)
            my = np.float32(rot[k, 0, 1] * X + rot[k, 1, 1] * Y)
            if not (mx >= -0.5 and mx <= w - 0.5 and my >= -0.5 and my <= h - 0.5):
                continue
            ix = min(max(int(np.rint(mx)), 0), w - 1)
            iy = min(max(int(np.rint(my)), 0), h - 1)
            if unusable[iy, ix]:
                continue
            if excluded[iy, ix]:
                ok = False
                for t in range(win_b.shape[1]):
                    if owner[iy, ix] == win_b[k, t] and win_lo[k, t] <= arcmap[iy, ix] <= win_hi[k, t]:
                        ok = True
                if not ok:
                    continue
            fx0, fy0 = np.floor(mx), np.floor(my)
            x0, y0 = int(fx0), int(fy0)
            fx, fy = mx - fx0, my - fy0
            xa, xb = min(max(x0, 0), w - 1), min(max(x0 + 1, 0), w - 1)
            ya, yb = min(max(y0, 0), h - 1), min(max(y0 + 1, 0), h - 1)
            d = 0.0
            for c in range(C):
                v = ((1 - fy) * ((1 - fx) * ex[ya, xa, c] + fx * ex[ya, xb, c])
                     + fy * ((1 - fx) * ex[yb, xa, c] + fx * ex[yb, xb, c]))
                e = v - ref[p, c]
                d += e * e
            if on_body[p]:
                s_on += d
                n_on += 1
            else:
                s_off += d
                n_off += 1
        if n_on > 0 and n_off > 0:
            out[k] = 0.5 * (s_on / n_on + s_off / n_off)
        elif n_on > 0:
            out[k] = s_on / n_on
        elif n_off > 0:
            out[k] = s_off / n_off
    return out


def _source_windows(ctx: _Context, lib: FragmentLibrary, idx: np.ndarray, tgt: Fragment):
    """The source windows of :func:`_allowed` for candidates ``idx`` (own branch; for a furcation
    also the child): ``(branch, lo, hi)``, each ``(n, 1 or 2)``, arc lengths with the slack."""
    n = len(idx)
    slack = 0.5
    lo, hi = _target_window(ctx.sm_t, tgt.branch, tgt.arc, tgt.radius)
    wins = [(lib.branch[idx], lib.arc[idx], lib.sign[idx], lo, hi)]
    if tgt.kind == "furcation":
        Lc = float(ctx.sm_t.lengths[tgt.child])
        zero = np.zeros(n)
        wins.append((lib.child[idx], zero, zero + 1.0, -np.inf, Lc if Lc < 1.5 * tgt.radius else np.inf))
    win_b = np.empty((n, len(wins)), np.int64)
    win_lo = np.empty((n, len(wins)))
    win_hi = np.empty((n, len(wins)))
    for t, w in enumerate(wins):
        a, b = w[1] + w[2] * w[3], w[1] + w[2] * w[4]
        win_b[:, t] = w[0]
        win_lo[:, t] = np.minimum(a, b) - slack
        win_hi[:, t] = np.maximum(a, b) + slack
    return win_b, win_lo, win_hi


def _colour_costs(ctx: _Context, lib: FragmentLibrary, idx, rot, trans, tgt: Fragment,
                  origin, size: int, disk, ex_win, cov_win, body_win) -> np.ndarray:
    """Colour cost ``C`` of candidates ``idx`` (rigidly placed by ``rot, trans``) on the overlap.

    The mean over the overlap pixels on the target branch body and the
    mean over the others count half each, so that the few branch pixels
    weigh as much as the background around them: a candidate whose
    branch does not continue the previous fragment's is not outscored by
    a blank one that merely matches the background.

    Only the window pixels inside the disk that are already synthesised
    can be in an overlap: the candidates are sampled there only, each
    source pixel under the rules of :func:`_allowed`.
    """
    idx = np.atleast_1d(idx)
    n = len(idx)
    rr, cc = np.nonzero(disk & cov_win)
    if n == 0 or len(rr) == 0:
        return np.zeros(n)
    win_b, win_lo, win_hi = _source_windows(ctx, lib, idx, tgt)
    ex = ctx.ex if ctx.ex.flags.c_contiguous else np.ascontiguousarray(ctx.ex)
    return _colour_cost_kernel(ex, cc.astype(np.float32) + np.float32(origin[0]),
                               rr.astype(np.float32) + np.float32(origin[1]),
                               np.ascontiguousarray(rot, np.float64), np.ascontiguousarray(trans, np.float64),
                               ctx.excluded, ctx.pm_s.branch, ctx.pm_s.arc, ctx.unusable, win_b, win_lo, win_hi,
                               np.ascontiguousarray(ex_win[rr, cc], np.float32), body_win[rr, cc])
