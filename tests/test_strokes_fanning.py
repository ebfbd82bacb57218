"""Carried parts fanned apart where a stroke bends their parent towards them (issue 25).

A stem with seven long leaves on one side, bent into an arc towards them:
carried rigidly, the leaves converge and their tips pile into one mass;
fanned (turned about their attachments, evenly along the chain), each
leaf stays apart from its neighbours and joined to the stem.
"""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.strokes import edit_structure
from branchnb.strokes.edit import fetch_patches
from branchnb.strokes.fanning import _fanned_maps
from branchnb.strokes.parts import rigid_frame
from branchnb.strokes.procedural import _Canvas, _leaf, twig


def _comb(size=260, n=7, rng=0):
    c = _Canvas(size, size, outline=1.5, rng=np.random.default_rng(rng))
    x = 0.15 * size
    stem = np.c_[np.full(40, x), np.linspace(0.92 * size, 0.12 * size, 40)]
    sdf, _ = c.capsule(stem, 4.0)
    c.part(stem, "stem", -1, 4.0, (sdf, np.broadcast_to(np.array([0.35, 0.3, 0.15]), (size, size, 3)).copy(), 3))
    u = np.array([np.cos(-0.25), np.sin(-0.25)])
    for j in range(n):
        a = np.array([x, 0.85 * size - j * 0.1 * size])
        base = a + 6 * u
        _leaf(c, base, base + 0.42 * size * u, 0.025 * size, a, 2.5, 1)
        c.part([a, base + 0.42 * size * u], f"leaf {j}", 0, 6.0)
    return c.result()


@pytest.fixture(scope="module")
def bent_comb():
    obj = _comb()
    st = obj.strokes[0]
    length = float(np.hypot(*np.diff(st, axis=0).T).sum())
    turn = 1.5
    r = length / turn
    th = np.linspace(0.0, turn, 40)
    bent = np.c_[st[0, 0] + r * (1 - np.cos(th)), st[0, 1] - r * np.sin(th)]
    res = edit_structure(obj.image, [st], [bent], rng=0)
    return obj, st, bent, res, np.array([st[0, 0] + r, st[0, 1]]), r


def _leaves_across(alpha, centre, radius, turn=1.5):
    """Runs of opaque pixels along an arc of ``radius`` round ``centre`` (the leaves it crosses)."""
    th = np.linspace(-0.1, turn + 0.4, 4000)
    xs, ys = centre[0] - radius * np.cos(th), centre[1] - radius * np.sin(th)
    on = ndi.map_coordinates(alpha, [ys, xs], order=1, cval=0.0) > 0.5
    return int((on[1:] & ~on[:-1]).sum() + on[0])


def test_bent_leaves_stay_apart(bent_comb):
    obj, st, bent, res, centre, r = bent_comb
    alpha = res.image[..., 3]
    # across the leaves' outer halves (where rigid ones converge) all seven are told apart
    runs = [_leaves_across(alpha, centre, f * r) for f in (0.45, 0.55, 0.65)]
    assert min(runs) == 7, runs


def test_bent_leaves_stay_joined(bent_comb):
    obj, st, bent, res, centre, r = bent_comb
    lab, n = ndi.label(res.image[..., 3] > 0.5, structure=np.ones((3, 3)))
    assert n == 1
    # every leaf's root lies on the object from the stem's centre line into the leaf (no gap at a joint)
    patches = fetch_patches(obj.image, [st], [bent])
    maps = _fanned_maps(patches._index, patches.attached, patches._carried, patches._window)
    for (i, pi, s_t), m in zip(patches._carried, maps):
        part = patches._index.parts[pi]
        ys, xs = np.nonzero(part.mask)
        c = m[:, :2] @ [xs.mean() + part.box[1].start, ys.mean() + part.box[0].start] + m[:, 2]
        p = patches.attached[i].target.point_at(s_t)
        u = (c - p) / np.hypot(*(c - p))
        ray = p + np.outer(np.arange(0.0, 12.0, 0.5), u)
        a = ndi.map_coordinates(res.image[..., 3], [ray[:, 1], ray[:, 0]], order=1)
        assert (a > 0.5).all(), (pi, np.round(a, 2))


def test_no_collision_keeps_the_rigid_maps():
    obj = twig(300, rng=3)
    sp = obj.strokes[0]
    bent = sp + np.c_[np.zeros(len(sp)), 8.0 * np.sin(np.linspace(0, np.pi, len(sp)))]
    patches = fetch_patches(obj.image, [sp], [bent])
    assert patches._carried
    maps = _fanned_maps(patches._index, patches.attached, patches._carried, patches._window)
    for (i, pi, s_t), m in zip(patches._carried, maps):
        pair, part = patches.attached[i], patches._index.parts[pi]
        assert np.array_equal(m, rigid_frame(pair.source, pair.target, part.s, s_t, window=patches._window))
