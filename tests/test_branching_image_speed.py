"""Issue 23 (speed): the batched skeleton queries of image synthesis give the values of the
one-query-at-a-time code they replaced (so the speed-ups leave the images unchanged)."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching._image_examples import random_tree
from branchnb.branching.fragments import Fragment, shape_vectors, target_fragments
from branchnb.branching.image_synthesis import ImageSynthesisParams, _constraints, _Context
from branchnb.branching.skeleton_map import SkeletonMap


def _reference_constraints(sm_s, sm_t, src, tgt, rot, trans, step, match_thickness):
    """The per-part queries of the original ``_constraints`` (one call per query)."""
    R = tgt.radius
    qs, ds = [], []

    def add(bt, st, bs, ss, sign, offsets):
        if len(offsets) == 0:
            return
        q = sm_t.position(bt, st + offsets)
        p = sm_s.position(bs, ss + sign * offsets)
        qs.append(q)
        ds.append(q - (p @ rot.T + trans))
        if match_thickness:
            rt = sm_t.thickness(bt, st + offsets)
            rs = sm_s.thickness(bs, ss + sign * offsets)
            tt = sm_t.tangent(bt, st + offsets, 1.0)
            ts = sm_s.tangent(bs, ss + sign * offsets, sign)
            nt = np.stack([-tt[:, 1], tt[:, 0]], 1)
            ns = np.stack([-ts[:, 1], ts[:, 0]], 1)
            for side in (1.0, -1.0):
                qe = q + side * rt[:, None] * nt
                pe = p + side * rs[:, None] * ns
                qs.append(qe)
                ds.append(qe - (pe @ rot.T + trans))

    o = np.arange(-R, R + 1e-9, step)
    o = o[~sm_t.clamped(np.full(len(o), tgt.branch), tgt.arc + o)]
    add(tgt.branch, tgt.arc, src.branch, src.arc, src.sign, o)
    if tgt.kind == "furcation":
        oc = np.arange(step, R + 1e-9, step)
        oc = oc[~sm_t.clamped(np.full(len(oc), tgt.child), oc)]
        add(tgt.child, 0.0, src.child, 0.0, 1.0, oc)
    if not qs:
        return np.zeros((0, 2)), np.zeros((0, 2))
    return np.vstack(qs), np.vstack(ds)


@pytest.mark.parametrize("seed", [0, 3])
@pytest.mark.parametrize("match_thickness", [True, False])
def test_batched_constraints_equal_per_part_queries(seed, match_thickness):
    sm_s = SkeletonMap(random_tree((160, 160), seed, n_children=3), 1.0)
    sm_t = SkeletonMap(random_tree((200, 140), seed + 10, n_children=4, grandchildren=1), 1.0)
    p = ImageSynthesisParams(match_thickness=match_thickness)
    ctx = _Context(None, sm_s, sm_t, None, None, None, p)
    src_b = target_fragments(sm_s)
    rng = np.random.default_rng(seed)
    n_furc = 0
    for tgt in target_fragments(sm_t):
        src = src_b[int(rng.integers(len(src_b)))]
        if (tgt.kind == "furcation") != (src.kind == "furcation"):
            continue
        n_furc += tgt.kind == "furcation"
        if src.kind == "branch" and rng.random() < 0.5:  # read tip to root
            src = Fragment(src.kind, src.branch, src.arc, src.center, src.radius, -1, src.child)
        th = rng.uniform(-np.pi, np.pi)
        rot = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
        trans = rng.uniform(-50, 50, 2)
        q, d = _constraints(ctx, src, tgt, rot, trans)
        q_ref, d_ref = _reference_constraints(sm_s, sm_t, src, tgt, rot, trans,
                                              max(1.0, float(p.displacement_step)), match_thickness)
        np.testing.assert_array_equal(q, q_ref)
        np.testing.assert_array_equal(d, d_ref)
    assert n_furc > 0  # furcations (two parts per fragment) were exercised


def test_batched_target_shape_vectors_and_scalar_thickness():
    sm = SkeletonMap(random_tree((200, 200), 2, n_children=4, grandchildren=1), 1.0)
    tf = target_fragments(sm)
    furc = [f for f in tf if f.kind == "furcation"]
    R = 7.5
    p, mu = shape_vectors(sm, [f.branch for f in furc], [f.arc for f in furc], np.ones(len(furc)), R, 6,
                          [f.child for f in furc])
    for j, f in enumerate(furc):
        p1, mu1 = shape_vectors(sm, [f.branch], [f.arc], [1.0], R, 6, [f.child])
        np.testing.assert_array_equal(p[j], p1[0])
        np.testing.assert_array_equal(mu[j], mu1[0])
    for b in range(sm.n_branches):
        s = np.linspace(-3.0, sm.lengths[b] + 3.0, 41)
        assert [sm.thickness_at(b, v) for v in s] == sm.thickness(b, s).tolist()


def test_fragment_masks_equal_allowed_rules():
    """A fragment's compiled valid / protect masks are those of ``_allowed`` and the numpy rules."""
    from branchnb.branching.fragment_choice import _allowed, _source_windows, _target_window
    from branchnb.branching.fragment_placement import _NO_LABELS, _crop, _fragment_masks, _one_of
    from branchnb.branching.fragments import source_fragments

    rng = np.random.default_rng(4)
    sm_s = SkeletonMap(random_tree((120, 120), 1, n_children=3), 1.0)
    sm_t = SkeletonMap(random_tree((100, 110), 5, n_children=3), 1.0)
    pm_s, pm_t = sm_s.pixel_map((120, 120)), sm_t.pixel_map((100, 110))
    excluded = pm_s.core(1.5, 2.0) | (rng.random((120, 120)) < 0.05)
    unusable = rng.random((120, 120)) < 0.05
    ctx = _Context(None, sm_s, sm_t, pm_s, excluded, unusable, ImageSynthesisParams())
    lib_b, lib_f = source_fragments(sm_s)
    body = pm_t.core(1.0, 1.0)
    owner = np.where(rng.random((100, 110)) < 0.5, pm_t.branch, -1)
    src_lab = (rng.random((120, 120)) < 0.3).astype(np.int32)
    lab_t = (rng.random((100, 110)) < 0.3).astype(np.int32)
    n = 0
    for tf in target_fragments(sm_t):
        lib = lib_f if tf.kind == "furcation" else lib_b
        if len(lib) == 0:
            continue
        pick = int(rng.integers(len(lib)))
        R, size = tf.radius, int(np.ceil(2 * tf.radius)) + 6
        x0, y0 = int(np.floor(tf.center[0] - R)) - 2, int(np.floor(tf.center[1] - R)) - 2
        yy, xx = np.mgrid[0:size, 0:size]
        mx = (xx + rng.uniform(-10, 110)).astype(np.float32)
        my = (yy + rng.uniform(-10, 110)).astype(np.float32)
        for labels in (None, lab_t):
            mine = [tf.branch] if tf.kind == "branch" else [tf.branch, tf.child]
            b_win, body_win = _crop(pm_t.branch, x0, y0, size, -1), _crop(body, x0, y0, size, False)
            own = body_win & _one_of(b_win, mine)
            lo_o = hi_o = 0.0
            if tf.kind == "branch":
                lo, hi = _target_window(sm_t, tf.branch, tf.arc, R)
                lo_o, hi_o = tf.arc + max(lo, -R) - 1, tf.arc + min(hi, R) + 1
                a_win = _crop(pm_t.arc, x0, y0, size, 0.0)
                own &= (a_win >= lo_o) & (a_win <= hi_o)
            disk = (xx + x0 - tf.center[0]) ** 2 + (yy + y0 - tf.center[1]) ** 2 <= R * R
            inimg = (mx >= -0.5) & (mx <= 119.5) & (my >= -0.5) & (my <= 119.5)
            ix = np.clip(np.rint(mx).astype(np.int64), 0, 119)
            iy = np.clip(np.rint(my).astype(np.int64), 0, 119)
            valid = disk & inimg & (_allowed(ctx, mx[None], my[None], lib, pick, tf)[0] | (own & ~unusable[iy, ix]))
            if labels is not None:
                valid &= (src_lab[iy, ix] == _crop(labels, x0, y0, size, -1)) | own
            ref_pp = own & ~_one_of(_crop(owner, x0, y0, size, -1), mine) & valid
            ref_pc = body_win & ~_one_of(b_win, mine)
            wb, wl, wh = _source_windows(ctx, lib, np.array([pick]), tf)
            b1 = tf.child if tf.kind == "furcation" else tf.branch
            v, pp, pc = _fragment_masks(mx, my, x0, y0, float(tf.center[0]), float(tf.center[1]), R * R, -1.0,
                                        excluded, unusable, pm_s.branch, pm_s.arc, wb[0], wl[0], wh[0],
                                        labels is not None, src_lab if labels is not None else _NO_LABELS,
                                        labels if labels is not None else _NO_LABELS, pm_t.branch, body, pm_t.arc,
                                        owner, tf.branch, b1, tf.kind == "branch", float(lo_o), float(hi_o),
                                        np.ones((100, 110), bool))
            np.testing.assert_array_equal(v, valid)
            np.testing.assert_array_equal(pp, ref_pp)
            np.testing.assert_array_equal(pc, ref_pc)
            n += int(valid.sum() > 0)
    assert n > 10
