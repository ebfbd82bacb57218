"""Steps 2-3 of image synthesis: bend a chosen fragment onto the target and compose it.

The displacement constraints (skeleton and edges of the source fragment
after its rigid alignment against the target's, :func:`_constraints`), the
bicubic sampling of the example under the backward map (:func:`_sample`),
and the window helpers of the per-fragment loop.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np

from ..core.polyline import RigidTransform
from .displacement import backward_map, displacement_field
from .fragment_choice import _colour_costs, _Context, _source_windows, _target_window, _thin_penalty, _tip_penalty
from .fragments import Fragment, FragmentLibrary, ShapeBank, choose_among_best, shape_vectors
from .gap_blend import compose_patch
from .skeleton_map import PixelMap

__all__: list[str] = []


def _sample(ex: np.ndarray, mx: np.ndarray, my: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bicubic samples of ``ex`` at ``(mx, my)`` and where they lie inside it.

    Like :func:`branchnb.core.warp.remap` on an already validated image, but
    only the example's region under the maps is handed to OpenCV, and
    bicubic, clipped to that region's range per channel.

    Notes
    -----
    Beyond the paper (issue 23): a fragment lands rotated and bent, at
    random sub-pixel offsets, and bilinear sampling there averages
    neighbouring pixels: it kept 0.28-0.30 of a white-noise texture's
    Laplacian energy (bicubic 0.49-0.55), and the thin, textured branches
    of a small example (64-192 px) came out visibly softer than the
    example's (Laplacian energy on the branches 0.60-0.8 of the example's
    on neurons, cracks, vessels, rivers -> 0.88-1.3). The clip keeps
    bicubic's overshoot beside a step (a dark ring round a bright core) out.
    The colour cost (:mod:`.fragment_choice`) still samples bilinearly: it
    only ranks candidates.
    """
    h, w = ex.shape[:2]
    valid = (mx >= -0.5) & (mx <= w - 0.5) & (my >= -0.5) & (my <= h - 0.5)
    if not valid.any():
        return np.zeros(mx.shape + (ex.shape[2],), np.float32), valid
    # np.clip's values on scalars, without its dispatch (once per fragment)
    x0 = int(min(max(np.floor(mx.min()) - 1, 0), w - 1))
    x1 = int(min(max(np.ceil(mx.max()) + 2, x0 + 1), w))
    y0 = int(min(max(np.floor(my.min()) - 1, 0), h - 1))
    y1 = int(min(max(np.ceil(my.max()) + 2, y0 + 1), h))
    roi = ex[y0:y1, x0:x1]
    out = cv2.remap(roi, mx - np.float32(x0), my - np.float32(y0), interpolation=cv2.INTER_CUBIC,
                    borderMode=cv2.BORDER_REPLICATE)
    if out.ndim == 2:
        out = out[:, :, None]
        roi = roi[:, :, None]
    # bicubic overshoots beside a step (a dark halo beside a bright core): kept in the window's range
    flat = roi.reshape(-1, roi.shape[2])
    np.clip(out, flat.min(0), flat.max(0), out=out)
    return out, valid


def _constraints(ctx: _Context, src: Fragment, tgt: Fragment, rot, trans):
    """Target points ``q`` and displacements ``q - (R p + t)`` of the skeleton (and edges)."""
    sm_s, sm_t = ctx.sm_s, ctx.sm_t
    R = tgt.radius
    step = max(1.0, float(ctx.p.displacement_step))
    o = np.arange(-R, R + 1e-9, step)
    o = o[~sm_t.clamped(np.full(len(o), tgt.branch), tgt.arc + o)]
    parts = [(tgt.branch, tgt.arc, src.branch, src.arc, src.sign, o)]
    if tgt.kind == "furcation":
        oc = np.arange(step, R + 1e-9, step)
        oc = oc[~sm_t.clamped(np.full(len(oc), tgt.child), oc)]
        parts.append((tgt.child, 0.0, src.child, 0.0, 1.0, oc))
    parts = [pt for pt in parts if len(pt[5])]
    if not parts:
        return np.zeros((0, 2)), np.zeros((0, 2))
    # All queries of both structures in one batch per map (the skeleton
    # queries are elementwise: same values as one call per part, far
    # fewer calls per fragment).
    bt = np.concatenate([np.full(len(pt[5]), pt[0], np.int64) for pt in parts])
    at = np.concatenate([pt[1] + pt[5] for pt in parts])
    bs = np.concatenate([np.full(len(pt[5]), pt[2], np.int64) for pt in parts])
    sg = np.concatenate([np.full(len(pt[5]), float(pt[4])) for pt in parts])
    as_ = np.concatenate([pt[3] + pt[4] * pt[5] for pt in parts])
    if ctx.p.match_thickness:
        # positions, thicknesses and tangents in one batch per map (the same values)
        q_all, rt_all, tt_all = sm_t._frame(bt, at, 1.0)
        p_all, rs_all, ts_all = sm_s._frame(bs, as_, sg)
    else:
        q_all = sm_t.position(bt, at)
        p_all = sm_s.position(bs, as_)
    qs, ds = [], []
    i0 = 0
    for pt in parts:
        sl = slice(i0, i0 + len(pt[5]))
        i0 += len(pt[5])
        q, pp = q_all[sl], p_all[sl]
        qs.append(q)
        ds.append(q - (pp @ rot.T + trans))
        if ctx.p.match_thickness:
            rt, rs, tt, ts = rt_all[sl], rs_all[sl], tt_all[sl], ts_all[sl]
            nt, ns = np.empty_like(tt), np.empty_like(ts)   # the normals (-t_y, t_x)
            nt[:, 0], nt[:, 1] = -tt[:, 1], tt[:, 0]
            ns[:, 0], ns[:, 1] = -ts[:, 1], ts[:, 0]
            for side in (1.0, -1.0):
                qe = q + side * rt[:, None] * nt
                pe = pp + side * rs[:, None] * ns
                qs.append(qe)
                ds.append(qe - (pe @ rot.T + trans))
    if not qs:
        return np.zeros((0, 2)), np.zeros((0, 2))
    return np.vstack(qs), np.vstack(ds)


def _one_of(arr: np.ndarray, values) -> np.ndarray:
    """``np.isin(arr, values)`` for the one or two branch indices of a fragment (without its sort)."""
    out = arr == values[0]
    for v in values[1:]:
        out |= arr == v
    return out


def _window(canvas, covered, x0, y0, size):
    H, W = covered.shape
    img = np.zeros((size, size, canvas.shape[2]), np.float32)
    cov = np.zeros((size, size), bool)
    r0, r1 = max(y0, 0), min(y0 + size, H)
    c0, c1 = max(x0, 0), min(x0 + size, W)
    if r0 < r1 and c0 < c1:
        img[r0 - y0:r1 - y0, c0 - x0:c1 - x0] = canvas[r0:r1, c0:c1]
        cov[r0 - y0:r1 - y0, c0 - x0:c1 - x0] = covered[r0:r1, c0:c1]
    return img, cov


def _crop(arr, x0, y0, size, fill):
    H, W = arr.shape[:2]
    out = np.full((size, size) + arr.shape[2:], fill, dtype=arr.dtype)
    r0, r1 = max(y0, 0), min(y0 + size, H)
    c0, c1 = max(x0, 0), min(x0 + size, W)
    if r0 < r1 and c0 < c1:
        out[r0 - y0:r1 - y0, c0 - x0:c1 - x0] = arr[r0:r1, c0:c1]
    return out


def _uncover(covered, mask, x0, y0):
    H, W = covered.shape
    size = mask.shape[0]
    r0, r1 = max(y0, 0), min(y0 + size, H)
    c0, c1 = max(x0, 0), min(x0 + size, W)
    if r0 < r1 and c0 < c1:
        covered[r0:r1, c0:c1] &= ~mask[r0 - y0:r1 - y0, c0 - x0:c1 - x0]


@dataclass
class _Canvas:
    """What the fragment loop leaves for gap completion and the result."""

    canvas: np.ndarray       # (H, W, C) float32
    covered: np.ndarray      # (H, W) bool
    source: np.ndarray       # (H, W, 2) example pixel each output pixel was copied from
    frag_index: np.ndarray   # (H, W) int, -1 = none
    seams: np.ndarray        # (H, W) bool
    body: np.ndarray         # (H, W) bool: the target's branch bodies
    matches: list
    total_seam: float


def _synthesize_fragments(ctx: _Context, pm_t: PixelMap, targets: list, shape, lib_b: FragmentLibrary,
                          lib_f: FragmentLibrary, free_start, free_end, free_t, banks: dict, labels_t,
                          src_labels, use_poisson: bool, rng: np.random.Generator, report,
                          frag_share: float, light=None, neutral_lines=None,
                          neutral_tol: float = 0.0) -> _Canvas:
    """Steps 1-3 for every target fragment, in order: choose, bend and compose (see
    :func:`~branchnb.branching.image_synthesis.synthesize_image`).

    ``light = (example_layout, output_layout)`` (the example's light layout,
    :func:`~branchnb.branching.gap_completion.light_layout`, and the same at the output's size):
    going beyond the paper, each fragment is shifted by the difference of the layouts at its
    target centre and its source centre, so a bolt copied from a bright cloud into a dark
    sky does not carry the cloud along as a glowing tube (its glow above the ground is kept).

    ``neutral_lines`` ((H, W) bool, optional): where the canvas and the fragment differ there by more
    than ``neutral_tol`` in a channel, canvas pixels that are no boundary of the fragment's
    gradient-domain correction (a hub example's lines and their soft edges,
    :data:`~branchnb.branching.gap_completion.HUB_LINE_MARGIN`; beyond the paper, issue 23): where a
    seam ran along an older line's edge that the fragment has as ground (or the other way round),
    that line's colour was spread into the new fragment -- faded thin twigs, light specks at tips
    and junctions. Where both hold the same line it still ties the line's colour across the seam."""
    from .image_result import FragmentMatch

    ex, sm_s, sm_t, p = ctx.ex, ctx.sm_s, ctx.sm_t, ctx.p
    H, W = shape
    C = ex.shape[2]
    canvas = np.zeros((H, W, C), np.float32)
    covered = np.zeros((H, W), bool)
    owner = np.full((H, W), -1, np.int64)  # target branch whose fragment provided the pixel
    source = np.full((H, W, 2), np.nan)
    frag_index = np.full((H, W), -1, np.int64)
    seams = np.zeros((H, W), bool)
    body = pm_t.core(1.0, 1.0)
    matches: list[FragmentMatch] = []
    total_seam = 0.0
    # Shape vectors of the source library depend on the target radius only
    # through the sampling offsets: cache them per radius.
    vec_cache: dict = {}
    # ``banks``: across calls, by exact radius (a call's first radius per key)
    if len(banks) > 512:
        banks.clear()
    # The targets' own shape vectors, one batched query per (kind, radius)
    # (elementwise skeleton queries: the values of one call per fragment).
    tgt_vec: list = [None] * len(targets)
    groups: dict = {}
    for i, tf in enumerate(targets):
        groups.setdefault((tf.kind, tf.radius), []).append(i)
    for (kind, R), ids in groups.items():
        tq, tnu = shape_vectors(sm_t, [targets[i].branch for i in ids], [targets[i].arc for i in ids],
                                np.ones(len(ids)), R, p.k,
                                [targets[i].child for i in ids] if kind == "furcation" else None)
        for j, i in enumerate(ids):
            tgt_vec[i] = (tq[j], tnu[j])
    for i, tf in enumerate(targets):
        if i % 8 == 0:
            report(frag_share * i / max(len(targets), 1), f"fragment {i + 1} / {len(targets)}")
        R = tf.radius
        pad = 2
        x0 = int(np.floor(tf.center[0] - R)) - pad
        y0 = int(np.floor(tf.center[1] - R)) - pad
        size = int(np.ceil(2 * R)) + 2 * pad + 2
        if x0 + size <= 0 or y0 + size <= 0 or x0 >= W or y0 >= H:
            continue
        lib: FragmentLibrary = lib_f if tf.kind == "furcation" else lib_b
        q0, nu0 = tgt_vec[i]
        key = (tf.kind, round(R, 2))
        if key not in vec_cache:
            exact = (tf.kind, float(R))
            if exact not in banks:
                banks[exact] = ShapeBank(*shape_vectors(sm_s, lib.branch, lib.arc, lib.sign, R, p.k,
                                                        lib.child if tf.kind == "furcation" else None))
            vec_cache[key] = banks[exact]
        bank = vec_cache[key]
        S = bank.costs(q0, nu0, p.w_s)
        if tf.kind == "branch":
            S = S + _tip_penalty(sm_t, tf, lib_b, sm_s.lengths, free_start, free_end, free_t)
        # thin lines take a like radius first (beyond the paper; .fragment_choice._thin_penalty)
        rank = S + _thin_penalty(bank.mu, nu0)
        n_short = min(p.shortlist, len(S))
        short = np.argpartition(rank, n_short - 1)[:n_short] if n_short < len(S) else np.arange(len(S))
        short = short[np.argsort(rank[short], kind="stable")]
        rot, trans = bank.fit(short, q0)
        yy, xx = np.arange(size)[:, None], np.arange(size)[None, :]   # (broadcast: no full grids)
        disk = (xx + x0 - tf.center[0]) ** 2 + (yy + y0 - tf.center[1]) ** 2 <= R * R
        # Existing canvas under the window (zero outside the image).
        ex_win, cov_win = _window(canvas, covered, x0, y0, size)
        costs_c = np.zeros(len(short))
        if p.w_c > 0 and cov_win.any():
            costs_c = _colour_costs(ctx, lib, short, rot, trans, tf, (x0, y0), size, disk,
                                    ex_win, cov_win, _crop(body, x0, y0, size, False))
        j = choose_among_best(rank[short] + p.w_c * costs_c, p.c, rng)
        pick = int(short[j])
        src = lib[pick]
        # the shortlist's closed-form alignment (what rigid_align gives, to rounding)
        T = RigidTransform(rotation=rot[j], translation=trans[j])
        fld = None
        max_disp = 0.0
        if p.displacement:
            qc, dc = _constraints(ctx, src, tf, T.rotation, T.translation)
            if len(qc):
                max_disp = float(np.hypot(*dc.T).max())
                fld = displacement_field((size, size), qc - (x0, y0), dc,
                                         step=p.displacement_step)
        mx, my = backward_map((x0, y0), (size, size), T.rotation, T.translation, fld)
        pix, _ = _sample(ex, mx, my)
        if light is not None:
            lx, ly = light
            c = size // 2
            sx = min(max(int(round(float(mx[c, c]))), 0), lx.shape[1] - 1)
            sy = min(max(int(round(float(my[c, c]))), 0), lx.shape[0] - 1)
            tx = min(max(int(round(float(tf.center[0]))), 0), W - 1)
            ty = min(max(int(round(float(tf.center[1]))), 0), H - 1)
            n = ly.shape[2]
            g_s = lx[sy, sx]
            # on the target's branch bodies, light above the ground (a bolt's core) keeps its share of
            # a darkening: a white core stays white (an additive shift would tint it); the rest moves
            # fully, and every pixel brightens fully (a bolt keeps its contrast in a brighter place)
            off = ly[ty, tx] - g_s
            up = ((pix[..., :n] - g_s) / np.maximum(1.0 - g_s, 1e-3)).max(axis=-1)
            keep = (np.clip(up, 0.0, 1.0) * _crop(body, x0, y0, size, False))[..., None]
            pix[..., :n] += np.where(off > 0, 0.0, (1.0 - keep) * off)
        # Which window pixels the fragment may cover and which it must keep / leave, in one compiled
        # pass over the window (the rules of ``_allowed``, the regions, the own body; same values).
        b0 = tf.branch
        b1 = tf.child if tf.kind == "furcation" else b0
        own_lo = own_hi = 0.0
        if tf.kind == "branch":
            lo, hi = _target_window(sm_t, tf.branch, tf.arc, R)
            own_lo, own_hi = tf.arc + max(lo, -R) - 1, tf.arc + min(hi, R) + 1
        win_b, win_lo, win_hi = _source_windows(ctx, lib, np.array([pick]), tf)
        clear_r2 = (p.furcation_clear * R) ** 2 if tf.kind == "furcation" and p.furcation_clear > 0 else -1.0
        valid, protect_piece, protect_canvas = _fragment_masks(
            mx, my, x0, y0, float(tf.center[0]), float(tf.center[1]), R * R, clear_r2, ctx.excluded,
            ctx.unusable, ctx.pm_s.branch, ctx.pm_s.arc, win_b[0], win_lo[0], win_hi[0],
            labels_t is not None, src_labels if labels_t is not None else _NO_LABELS,
            labels_t if labels_t is not None else _NO_LABELS, pm_t.branch, body, pm_t.arc, owner,
            b0, b1, tf.kind == "branch", float(own_lo), float(own_hi), covered)
        comp = compose_patch(canvas, covered, pix, valid, (x0, y0), protect_canvas=protect_canvas,
                             protect_piece=protect_piece, method=p.seams, poisson=use_poisson,
                             anchored=p.anchors, anchor_weight=p.anchor_weight,
                             neutral_canvas=None if neutral_lines is None
                             else _crop(neutral_lines, x0, y0, size, False)
                             & (np.abs(_crop(canvas, x0, y0, size, 0.0) - pix).max(axis=-1) > neutral_tol))
        n_pix = 0
        if comp is not None:
            wr, wc = comp.window
            tk = comp.take
            n_pix = int(tk.sum())
            total_seam += comp.cost
            seams[wr, wc] |= comp.seam
            o_sub = owner[wr, wc]
            if tf.kind == "furcation":
                o_sub[tk] = np.where(pm_t.branch[wr, wc][tk] == tf.child, tf.child, tf.branch)
            else:
                o_sub[tk] = tf.branch
            frag_index[wr, wc][tk] = len(matches)
            sm_x, sm_y = mx[comp.sub], my[comp.sub]
            source[wr, wc, 0][tk] = sm_x[tk]
            source[wr, wc, 1][tk] = sm_y[tk]
        matches.append(FragmentMatch(tf, src, float(S[pick]), float(costs_c[j]), T.angle,
                                     max_disp, n_pix))
    # Pixels a later fragment uncovered (furcation clearing) and nobody retook.
    frag_index[~covered] = -1
    source[~covered] = np.nan
    return _Canvas(canvas, covered, source, frag_index, seams, body, matches, total_seam)


_NO_LABELS = np.zeros((1, 1), np.int32)


@numba.njit(cache=True)
def _fragment_masks(mx, my, x0, y0, cx, cy, r2, clear_r2, excluded, unusable, owner_s, arc_s, win_b, win_lo,
                    win_hi, use_labels, src_labels, labels_t, branch_t, body_t, arc_t, owner_t, b0, b1,
                    check_arc, own_lo, own_hi, covered):
    """``valid``, ``protect_piece`` and ``protect_canvas`` of one fragment window, in one pass.

    Per window pixel: inside the disk (``r2``), sampled inside the example, and a source pixel
    that :func:`~.fragment_choice._allowed` allows (windows ``win_b/lo/hi``), or one of the
    fragment's own target body (``b0``, ``b1``; on a branch within ``[own_lo, own_hi]``) from a
    usable source pixel; with ``use_labels``, background only from the pixel's own region.
    With ``clear_r2 >= 0`` (a furcation) the pixels within that squared radius that the
    fragment covers and that are no other branch's body are uncovered in ``covered`` first.
    The values of the former per-array numpy code (same comparisons, same float types).
    """
    size_h, size_w = mx.shape
    h, w = excluded.shape
    H, W = branch_t.shape
    valid = np.zeros((size_h, size_w), np.bool_)
    protect_piece = np.zeros((size_h, size_w), np.bool_)
    protect_canvas = np.zeros((size_h, size_w), np.bool_)
    n_win = win_b.shape[0]
    for r in range(size_h):
        Y = y0 + r
        for c in range(size_w):
            X = x0 + c
            inside = Y >= 0 and Y < H and X >= 0 and X < W
            bt = branch_t[Y, X] if inside else -1
            body = body_t[Y, X] if inside else False
            mine = bt == b0 or bt == b1
            own_body = body and mine
            if check_arc:
                at = arc_t[Y, X] if inside else 0.0
                own_body = own_body and at >= own_lo and at <= own_hi
            dx = np.float64(X) - cx
            dy = np.float64(Y) - cy
            d2 = dx * dx + dy * dy
            u = mx[r, c]
            v = my[r, c]
            ok = d2 <= r2 and u >= -0.5 and u <= w - 0.5 and v >= -0.5 and v <= h - 0.5
            if ok:
                ix = min(max(int(np.rint(u)), 0), w - 1)
                iy = min(max(int(np.rint(v)), 0), h - 1)
                usable = not unusable[iy, ix]
                allowed = usable
                if allowed and excluded[iy, ix]:
                    allowed = False
                    for t in range(n_win):
                        if owner_s[iy, ix] == win_b[t] and arc_s[iy, ix] >= win_lo[t] and arc_s[iy, ix] <= win_hi[t]:
                            allowed = True
                ok = allowed or (own_body and usable)
                if ok and use_labels:
                    lt = labels_t[Y, X] if inside else -1
                    ok = src_labels[iy, ix] == lt or own_body
            valid[r, c] = ok
            ow = owner_t[Y, X] if inside else -1
            protect_piece[r, c] = own_body and not (ow == b0 or ow == b1) and ok
            pc = body and not mine
            protect_canvas[r, c] = pc
            if clear_r2 >= 0.0 and inside and ok and not pc and d2 <= clear_r2:
                covered[Y, X] = False
    return valid, protect_piece, protect_canvas
