"""Issue 23: a single tree synthesized with the defaults spans the image like its example.

Procedural single trees with a known structure (a trunk rooted near a frame edge, long children and
grandchildren spreading across the image); measured: the share of the frame farther than 5 % of its
diagonal from every branch ("far share"), synthesized / example, and the root's length.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching.colonization import frame_density
from branchnb.branching.synthesis import fit_model, synthesize_structure
from branchnb.core.render import coverage_polylines
from branchnb.core.structure import Branch, Structure


def _far_share(s: Structure, shape) -> float:
    cov, _ = coverage_polylines(shape, [b.points for b in s.branches], 1.0)
    d = ndi.distance_transform_edt(cov < 0.5)
    return float(np.mean(d > 0.05 * np.hypot(*shape)))


def _walk(rng, start, heading, length, wiggle=0.15, pull=None):
    pts, hd = [np.asarray(start, float)], heading
    for _ in range(int(length / 4.0)):
        hd += rng.normal(0, wiggle)
        if pull is not None:
            hd += 0.1 * np.angle(np.exp(1j * (pull - hd)))
        pts.append(pts[-1] + 4.0 * np.array([np.cos(hd), np.sin(hd)]))
    return np.array(pts)


def _clip(w, size, m=2):
    ins = np.all((w > m) & (w < size - m), axis=1)
    bad = np.flatnonzero(~ins)
    return w[: bad[0]] if len(bad) else w


def _tree(kind: str, size: int, seed: int) -> Structure:
    """One tree: "hook" starts inside near the top-right corner heading down, then hooks left
    across the image (like the traced lightning sample); "side" enters from the left side."""
    rng = np.random.default_rng(seed)
    if kind == "hook":
        head = _walk(rng, (0.84 * size, 0.08 * size), 1.35, 12, wiggle=0.0)
        trunk = np.vstack([head, _clip(_walk(rng, head[-1], 2.75, 1.1 * size, 0.08, pull=2.3), size)[1:]])
    else:
        trunk = _clip(_walk(rng, (3.0, 0.5 * size), 0.0, 1.1 * size, 0.08), size)
    br = [Branch(trunk, np.linspace(4, 2.5, len(trunk)))]
    for j, v in enumerate(np.sort(rng.choice(np.arange(2, len(trunk) * 4 // 5), 7, replace=False))):
        t = trunk[min(v + 1, len(trunk) - 1)] - trunk[max(v - 1, 0)]
        c = _clip(_walk(rng, trunk[v], np.arctan2(t[1], t[0]) + (-1) ** j * rng.uniform(0.7, 1.3),
                        rng.uniform(0.5, 0.9) * size, 0.12), size)
        if len(c) < 4:
            continue
        br.append(Branch(c, np.linspace(2.5, 1.2, len(c)), 0, int(v)))
        ci = len(br) - 1
        for k in range(3):
            u = rng.integers(2, max(3, len(c) - 2))
            tt = c[min(u + 1, len(c) - 1)] - c[max(u - 1, 0)]
            g = _clip(_walk(rng, c[u], np.arctan2(tt[1], tt[0]) + (-1) ** (k + j) * 0.9, 0.25 * size), size)
            if len(g) >= 4:
                br.append(Branch(g, np.linspace(1.5, 0.8, len(g)), ci, int(u)))
    return Structure(br, (size, size))


def test_root_spans_the_image_like_the_example():
    # before issue 23 the root walked out of the nearest side in seeds 2 and 4
    # (0.26 and 0.29 x the example's trunk length): the tree filled one corner
    s = _tree("hook", 256, 260)
    m = fit_model(s)
    ex_root, ex_far = s.branches[0].length, _far_share(s, s.image_shape)
    for seed in range(6):
        r = synthesize_structure(m, rng=seed).structure
        root = max(b.length for b in r.branches if b.parent is None)
        assert root > 0.6 * ex_root, (seed, root / ex_root)
        assert _far_share(r, s.image_shape) < 1.5 * ex_far, seed


def test_tree_from_a_side_spans_the_image():
    # a tree entering from the left side: seed 0 left 1.68 x the example's far share before issue 23;
    # issue 23's bound is 1.5 x in every seed (seeds 0-3 measure 1.39, 0.74, 1.07, 1.00 with the bend histogram)
    s = _tree("side", 400, 404)
    m = fit_model(s)
    for seed in range(4):
        r = synthesize_structure(m, rng=seed)
        ratio = _far_share(r.structure, s.image_shape) / _far_share(s, s.image_shape)
        assert ratio < 1.5, (seed, ratio)
        if seed == 0:
            assert r.diagnostics["stop_reason"] == "density (coverage)"


def test_frame_density_reads_the_frame_ahead():
    dirs = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0]])
    d = frame_density((100, 200), (180, 50), dirs, 30.0, 8.0)
    assert d[0] == pytest.approx(1.0) and d[1] < 1e-6 and d[2] < 0.01
    # ray end 10 px from the right side
    assert frame_density((100, 200), (160, 50), dirs[:1], 29.5, 8.0)[0] == pytest.approx(np.exp(-100 / 64))
