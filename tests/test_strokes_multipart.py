"""Junctions on multi-part objects: antlers, a coral and the bent twig (issue 25).

Antlers (:func:`~branchnb.strokes.procedural.antlers`): tines leave the beam at
29-52 degrees; two are turned about their roots, one is copied to a new place
on the beam, one nobody strokes. A coral (:func:`~branchnb.strokes.procedural.coral`):
parts of parts; a branch is turned about its root (its sub-branch, unstroked,
must turn with it) and a branch is copied to a new place on the trunk. The twig
(:func:`~branchnb.strokes._examples.twig_parts_edit`, shared with
test_strokes_slit_mouths.py): bent, its leaves and fruits carried along, a leaf added.

Every answer is known: each part's pixels moved by its rigid map must be
opaque in the result, each child's target stroke runs through opaque pixels
from its parent to its tip (no gap), the result is one piece with no flecks.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.strokes import Stroke, edit_structure
from branchnb.strokes._examples import twig_parts_edit
from branchnb.strokes.procedural import antlers, coral

EIGHT = np.ones((3, 3))


def _rot(th):
    c, s = np.cos(th), np.sin(th)
    return np.array([[c, -s], [s, c]])


def _turn(st, th, about):
    return (np.asarray(st, float) - about) @ _rot(th).T + about


def _moved(obj, part, rot, shift):
    """The part's pixels (1 px in from the outline) moved by ``x -> rot x + shift``."""
    m = ndi.binary_erosion(obj.labels == part, iterations=int(np.ceil(obj.outline)) + 1)
    yy, xx = np.nonzero(m)
    out = np.zeros(m.shape, bool)
    for dx in (-0.25, 0.25):
        for dy in (-0.25, 0.25):
            q = np.rint(np.c_[xx + dx, yy + dy] @ rot.T + shift).astype(int)
            ok = (q[:, 0] >= 0) & (q[:, 0] < m.shape[1]) & (q[:, 1] >= 0) & (q[:, 1] < m.shape[0])
            out[q[ok, 1], q[ok, 0]] = True
    return ndi.binary_erosion(out)


def _gap(alpha, points):
    """Longest run (px) of alpha < 0.5 along a stroke, from its start to 80 % of its length."""
    st = Stroke(points)
    p = st.point_at(np.arange(0.0, 0.8 * st.length, 0.5))
    off = ndi.map_coordinates(alpha, [p[:, 1], p[:, 0]], order=1) < 0.5
    runs = np.diff(np.flatnonzero(np.diff(np.r_[0, off.astype(int), 0])))[::2]
    return 0.5 * (runs.max() if len(runs) else 0)


def _antlers_edit(size):
    obj = antlers(size, rng=0)
    beam, t1, t2, t3 = obj.strokes[:4]
    st = Stroke(beam)
    new = st.point_at(0.3 * st.length) + (t2 - t2[0])  # tine 2 copied to 30 % of the beam
    src = [beam, t1, t2, t3, t2]
    tgt = [beam, t1, _turn(t2, -0.35, t2[0]), _turn(t3, 0.3, t3[0]), new]
    ident = (np.eye(2), np.zeros(2))
    moves = {0: ident, 1: ident, 4: ident,   # tine 4: nobody stroked it
             2: (_rot(-0.35), t2[0] - _rot(-0.35) @ t2[0]), 3: (_rot(0.3), t3[0] - _rot(0.3) @ t3[0])}
    return obj, src, tgt, moves


def _coral_edit(size):
    obj = coral(size, rng=0)
    trunk, b1, b2, b3 = obj.strokes[:4]
    st = Stroke(trunk)
    new = st.point_at(0.35 * st.length) + (b3 - b3[0]) @ _rot(0.25).T  # branch 3 copied lower
    src = [trunk, b1, b2, b3, b3]
    tgt = [trunk, _turn(b1, -0.3, b1[0]), b2, b3, new]
    ident = (np.eye(2), np.zeros(2))
    turned = (_rot(-0.3), b1[0] - _rot(-0.3) @ b1[0])
    moves = {0: ident, 2: ident, 3: ident, 5: ident, 6: ident, 1: turned, 4: turned}  # 4: branch 1's tip
    return obj, src, tgt, moves


def _twig_edit(size):
    """The twig bent, its leaves and fruits carried along, a leaf added (the builder
    test_strokes_slit_mouths.py shares)."""
    return twig_parts_edit(size, add_leaf=True)


@pytest.mark.parametrize("make", [_antlers_edit, _coral_edit, _twig_edit])
@pytest.mark.parametrize("size", [200, 360])
def test_parts_stay_attached_whole_and_clean(make, size):
    obj, src, tgt, moves = make(size)
    res = edit_structure(obj.image, src, tgt)
    a = res.image[..., 3]
    # one piece, no flecks
    assert ndi.label(a > 0.5, structure=EIGHT)[1] == 1
    assert ndi.label(a > 0.02, structure=EIGHT)[1] == 1
    # every stroked child joined to its parent (no gap >= 1 px along its stroke)
    assert max(_gap(a, t) for t in tgt[1:]) < 1.0
    # every part where its rigid map puts it (the coral's sub-branch too: it turns with its
    # branch, see below)
    for part, (rot, shift) in moves.items():
        want = _moved(obj, part, rot, shift)
        assert (want & (a < 0.5)).sum() <= 0.02 * want.sum(), obj.names[part]
    # the silhouette is outlined (as dark as the source's)
    def dark(img):
        m = img[..., 3] > 0.5
        edge = m & ~ndi.binary_erosion(m)
        return float((img[..., :3].mean(axis=2)[edge] < 0.35).mean())
    assert dark(res.image) >= dark(obj.image) - 0.05


@pytest.mark.parametrize("size", [360, 512])
def test_an_unstroked_sub_branch_leaves_with_its_branch_and_lands_in_place(size):
    """The coral's branch 1 turned by -0.3 rad: its tip (a sub-branch nobody stroked) goes
    with it and lands where the branch's rotation puts it. Before, the trunk's width was
    measured across the branch leaving it at 36 degrees (52 px instead of 22.5 at 512 px):
    the trunk's tube held the branch's root, the branch's texture started 85 px along it
    instead of ~45 and the tip landed 8-24 px too near the trunk (missing px of the turned
    tip: 1.0 of it at 360 and 512 px before the parts followed, then 136 / 746 / 2992 px of
    the whole edit at 256 / 512 / 1000). Now the trunk is measured away from its children:
    at most 2 % of the turned tip is missing and its old place is empty."""
    obj, src, tgt, moves = _coral_edit(size)
    res = edit_structure(obj.image, src, tgt)
    a = res.image[..., 3] > 0.5
    tip = obj.labels == 4
    far = tip & ~ndi.binary_dilation(obj.labels == 1, iterations=int(0.05 * size))
    assert a[far].mean() < 0.2
    rot, shift = moves[4]
    want = _moved(obj, 4, rot, shift)
    assert (want & ~a).sum() <= 0.02 * want.sum()
    end = obj.strokes[4][-1] @ rot.T + shift  # where the turned tip ends
    d = ndi.distance_transform_edt(~a)
    assert d[int(end[1]), int(end[0])] <= 1.0
