"""Radii along a synthesized branch follow the example's widths (issue 23, branching37): a trunk that
starts at a thick head does not keep that radius along its whole length."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import branchnb.branching.growth as growth
from branchnb.branching import Structure, fit_model, synthesize_structure
from branchnb.branching.measures import thick_end_share


def bolt_example(seed: int, shape=(400, 400)) -> Structure:
    """Four bolts, each thick (3 px) for its first 25 px, tapering to 0.6 px within 20 px and thin
    after, with thin (0.6 px) children: length-weighted 90th-percentile radius 0.63 px."""
    rng = np.random.default_rng(seed)
    h = 4.0
    s = Structure([], image_shape=shape)
    for k in range(4):
        n = 80
        th = np.pi / 2 + np.cumsum(rng.normal(0, 0.25, n)) * 0.3
        x0 = 60.0 + 90 * k
        pts = np.vstack([[x0, 5.0], np.c_[x0 + np.cumsum(h * np.cos(th)), 5 + np.cumsum(h * np.sin(th))]])
        pts = np.clip(pts, 0, np.array(shape[::-1]) - 1)
        t = np.arange(len(pts)) * h
        r = np.where(t < 25, 3.0, np.maximum(0.6, 3.0 - (t - 25) * 0.12)) * rng.uniform(0.95, 1.05, len(pts))
        s.add_branch(pts, r)
        root = len(s.branches) - 1
        for v in (25, 45, 65):
            m = 15
            a = th[v] + rng.choice([-1, 1]) * 0.7 + np.cumsum(rng.normal(0, 0.1, m))
            c = pts[v] + np.c_[np.cumsum(h * np.cos(a)), np.cumsum(h * np.sin(a))]
            c = np.clip(np.vstack([pts[v], c]), 0, np.array(shape[::-1]) - 1)
            s.add_branch(c, np.full(len(c), 0.6) * rng.uniform(0.95, 1.05, len(c)), parent=root, parent_vertex=v)
    return s


def weighted_quantile(s: Structure, q: float) -> float:
    r, w = [], []
    for b in s.branches:
        p = np.asarray(b.points, float)
        if len(p) > 1:
            r.append(0.5 * (b.thickness[1:] + b.thickness[:-1]))
            w.append(np.hypot(*np.diff(p, axis=0).T))
    r, w = np.concatenate(r), np.concatenate(w)
    o = np.argsort(r)
    return float(r[o][np.searchsorted(np.cumsum(w[o]) / w.sum(), q)])


@pytest.mark.parametrize("seed", [0, 1])
def test_synthesized_trunks_taper_like_the_example(seed, monkeypatch):
    ex = bolt_example(seed)
    model = fit_model(ex)
    q_ex = weighted_quantile(ex, 0.9)
    # The pull's own effect is compared with the entry tropism off on both sides: the bolt enters
    # from the top, and the tropism (which directions grow) moves the thick-radius quantile by
    # itself (max/min 0.72 without it, 0.79 with it on seed 1); the checks below run with the defaults.
    plain = dataclasses.replace(model, tropism=None)
    out, q = {}, {}
    for pull in (0.0, growth.RADIUS_PULL):
        monkeypatch.setattr(growth, "RADIUS_PULL", pull)
        out[pull] = [synthesize_structure(model, rng=k).structure for k in range(3)]
        q[pull] = [weighted_quantile(synthesize_structure(plain, rng=k).structure, 0.9) / q_ex for k in range(3)]
    q_old, q_new = q[0.0], q[growth.RADIUS_PULL]
    # the example's trunks are thin after their first ~60 px: so are the synthesized ones
    # (before: 3 px along the whole trunk, 90th percentile ~ 5 x the example's; after ~ 3 x)
    for s in out[growth.RADIUS_PULL]:
        trunk = max(s.branches, key=lambda b: b.length)
        assert np.median(trunk.thickness[len(trunk.thickness) // 2:]) <= 1.5 * 0.6
    assert max(q_new) <= 0.75 * min(q_old)
    te = thick_end_share(ex)
    assert all(thick_end_share(s) <= te + 0.05 for s in out[growth.RADIUS_PULL])


def test_pull_radii_bounded_jump_and_convergence():
    cont, copied = np.full(40, 3.0), np.full(40, 0.6)
    r = growth._pull_radii(cont, copied, 0.05)
    gap = np.log(3.0 / 0.6)
    assert np.log(3.0 / r[0]) == pytest.approx(0.05 * gap)
    assert np.all(np.diff(r) < 0) and r[-1] < 1.2
    assert np.array_equal(growth._pull_radii(cont, copied, 0.0), cont)
