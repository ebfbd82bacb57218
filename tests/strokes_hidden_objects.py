"""Parts hidden in the source by another part lying over them, edited so the hidden stretch shows (issue 25).

``leaf``: the berry branch of ``strokes_unseen_objects.py``, whose berry 2
hangs over leaf 2 (``leaf_copy``: leaf 2 copied to the branch's tip half;
``leaf_turn``: leaf 2 turned away from the berry; ``leaf_carry``: the whole
branch turned, every stroke alike, the berries following their stalks);
``body``: a body and an arm whose hand lies over the body's side
(``body_raise``: the arm raised, the body must be whole); ``cactus``: a
trunk and an arm whose flower lies over the trunk (``cactus_turn``: the arm
turned away; ``cactus_copy``: the arm copied to the other side, mirrored
back as a rigid copy). Each ``edit_*`` returns ``(obj, src, tgt, checks)``
where ``checks`` lists ``(alone, R, t, over)``: the hidden part drawn alone
(its own outline, nothing over it), the rigid map ``x -> R x + t`` it must
show at, and the parts (drawn alone, with their maps) that stay over it.

:func:`figures` measures per check: ``notch`` (px of the part's inside,
eroded by its outline, left transparent), ``foreign`` (px of its inside farther
than 0.3 in RGB from the part's median colour), ``ring_gap`` (share of its dark
outline ring that is not dark in the result) and, on the whole result,
``ghost`` (faint px, alpha 0.02-0.5, more than 2 px from the object:
grey arcs of a hidden part's rim).

``PYTHONPATH=. python tests/strokes_hidden_objects.py TAG [SIZES...]`` prints
the table and writes PNGs to ``$OUT`` (default ``$TMPDIR/strokes_hidden``).
"""
import os
import sys
import tempfile
import time

import cv2
import numpy as np
from scipy import ndimage as ndi

from branchnb.strokes.procedural import _Canvas, _point_at, _square_canvas

sys.path.insert(0, os.path.dirname(__file__))
from strokes_junction_table import rot, turn  # noqa: E402
from strokes_unseen_objects import berries  # noqa: E402

I = (np.eye(2), np.zeros(2))


def _tex(c, k, s, col, period):
    rip = 0.5 + 0.5 * np.sin(2 * np.pi * s / (period * k) + 2 * c.noise(25 * k, 1.0))
    return np.asarray(col)[None, None] * (0.85 + 0.25 * rip)[..., None] + c.noise(6 * k, 0.03)[..., None]


def _draw(c, k, parts):
    for i, (pts, hw, parent, taper, col, z) in enumerate(parts):
        sdf, s = c.capsule(pts, hw, taper=taper)
        c.part(pts, f"part {i}", parent, hw, (sdf, _tex(c, k, s, col, 12), z))
    return c.result(), c


def alone(c, i):
    """Part ``i`` of canvas ``c`` drawn by itself (its own outline all round)."""
    one = _Canvas(c.h, c.w, c.outline, np.random.default_rng(0))
    one.add(c.sdf[i], c.colour[i], 0)
    return one.render()[0]


def body(size=600, rng=0):
    c, n, k = _square_canvas(size, 600.0, rng)
    torso = np.array([(0.45 * n, 0.12 * n), (0.45 * n, 0.5 * n), (0.45 * n, 0.88 * n)])
    arm = np.array([(0.45 * n, 0.22 * n), (0.7 * n, 0.33 * n), (0.6 * n, 0.52 * n)])
    hand = np.array([(0.6 * n, 0.52 * n), (0.55 * n, 0.6 * n)])
    return _draw(c, k, [(torso, 42 * k, -1, 1.0, (0.3, 0.35, 0.7), 1),
                        (arm, 10 * k, 0, 1.0, (0.3, 0.35, 0.7), 2),
                        (hand, 20 * k, 1, 1.0, (0.9, 0.7, 0.55), 3)])


def cactus(size=600, rng=0):
    c, n, k = _square_canvas(size, 600.0, rng)
    trunk = np.array([(0.5 * n, 0.95 * n), (0.5 * n, 0.55 * n), (0.5 * n, 0.12 * n)])
    arm = np.array([(0.5 * n, 0.7 * n), (0.68 * n, 0.68 * n), (0.7 * n, 0.5 * n), (0.6 * n, 0.37 * n)])
    flower = np.array([(0.63 * n, 0.4 * n), (0.57 * n, 0.34 * n)])
    return _draw(c, k, [(trunk, 40 * k, -1, 1.0, (0.3, 0.55, 0.25), 1),
                        (arm, 20 * k, 0, 1.0, (0.3, 0.55, 0.25), 2),
                        (flower, 16 * k, 1, 1.0, (0.95, 0.35, 0.55), 3)])


def _moved(st, R, t):
    return np.asarray(st, float) @ R.T + t


def _berry_leaf(n):
    obj, c = berries(n, with_canvas=True)
    return obj, c, obj.strokes[:6]


def edit_leaf_copy(n):
    """The berry branch as it is, leaf 2 (under berry 2's top) copied to the branch's tip half."""
    obj, c, src = _berry_leaf(n)
    leaf = src[2]
    t = _point_at(src[0], 0.85) - leaf[0]
    return obj, src + [leaf], src + [leaf + t], [(alone(c, 2), np.eye(2), t, [(alone(c, 0), *I)])]


def edit_leaf_turn(n):
    """Leaf 2 turned 0.7 rad about its root, away from berry 2 (which stays)."""
    obj, c, src = _berry_leaf(n)
    R = rot(0.7)
    t = src[2][0] - R @ src[2][0]
    tgt = list(src)
    tgt[2] = _moved(src[2], R, t)
    return obj, src, tgt, [(alone(c, 2), R, t, [(alone(c, 7), *I), (alone(c, 5), *I), (alone(c, 0), *I)])]


def edit_leaf_carry(n):
    """The whole branch turned 0.15 rad about its base, every stroke alike (berries follow)."""
    obj, c, src = _berry_leaf(n)
    R = rot(-0.15)
    t = src[0][0] - R @ src[0][0]
    return obj, src, [_moved(st, R, t) for st in src], [
        (alone(c, 2), R, t, [(alone(c, 7), R, t), (alone(c, 5), R, t), (alone(c, 0), R, t)])]


def edit_body_raise(n):
    obj, c = body(n)
    torso, arm = obj.strokes[:2]
    R = rot(-0.9)
    at = turn(arm, -0.9, arm[0])
    return obj, [torso, arm], [torso, at], [(alone(c, 0), *I, [(alone(c, 1), R, arm[0] - R @ arm[0]),
                                                               (alone(c, 2), R, arm[0] - R @ arm[0])])]


def edit_cactus_turn(n):
    obj, c = cactus(n)
    trunk, arm = obj.strokes[:2]
    R = rot(-0.5)
    return obj, [trunk, arm], [trunk, turn(arm, -0.5, arm[0])], [
        (alone(c, 0), *I, [(alone(c, 1), R, arm[0] - R @ arm[0]), (alone(c, 2), R, arm[0] - R @ arm[0])])]


def edit_cactus_copy(n):
    obj, c = cactus(n)
    trunk, arm = obj.strokes[:2]
    t = np.array([0.0, -0.3 * n])
    return obj, [trunk, arm, arm], [trunk, arm, arm + t], [(alone(c, 1), np.eye(2), t, [(alone(c, 2), np.eye(2), t)])]


EDITS = {"leaf_copy": edit_leaf_copy, "leaf_turn": edit_leaf_turn, "leaf_carry": edit_leaf_carry,
         "body_raise": edit_body_raise, "cactus_turn": edit_cactus_turn, "cactus_copy": edit_cactus_copy}


def _warp(img, R, t, shape):
    m = np.c_[R, t].astype(np.float64)
    return cv2.warpAffine(img, m, (shape[1], shape[0]), flags=cv2.INTER_LINEAR, borderValue=0)


def figures(obj, res, checks):
    out = res.image if res.image.shape[2] == 4 else None
    a = res.layer[..., 3]
    rgb = res.layer[..., :3]
    shape = a.shape
    ow = int(np.ceil(obj.outline))
    r = {"notch": 0, "foreign": 0, "ring_gap": 0.0}
    for img, R, t, over in checks:
        exp = _warp(img, R, t, shape)
        # (registered within 3 px: a copy is attached to its parent, which may shift it a little)
        obj_m = a > 0.5
        best = max((int((np.roll(exp[..., 3] > 0.5, (dy, dx), axis=(0, 1)) & obj_m).sum()), dy, dx)
                    for dy in range(-3, 4) for dx in range(-3, 4))
        exp = np.roll(exp, best[1:], axis=(0, 1))
        ea = exp[..., 3]
        cover = np.zeros(shape, bool)
        for oimg, oR, ot in over:
            cover |= ndi.binary_dilation(_warp(oimg, oR, ot, shape)[..., 3] > 0.02, iterations=ow + 2)
        inside = ndi.binary_erosion(ea > 0.5, iterations=ow + 2) & ~cover
        r["notch"] = max(r["notch"], int((inside & (a < 0.5)).sum()))
        # (against the part's own colour: the copy's texture may come from elsewhere along it)
        core = ndi.binary_erosion(img[..., 3] > 0.5, iterations=ow + 2)
        diff = np.linalg.norm(rgb - np.median(img[..., :3][core], axis=0), axis=2)
        r["foreign"] = max(r["foreign"], int((inside & (a >= 0.5) & (diff > 0.3)).sum()))
        lum = exp[..., :3].mean(axis=2)
        ring = (ea > 0.5) & (lum < 0.25) & ~ndi.binary_erosion(ea > 0.5, iterations=ow + 2) & ~cover
        # (1 px of slack for a copy landing half a pixel off)
        dark = ndi.grey_erosion(np.where(a > 0.5, rgb.mean(axis=2), 1.0), size=3) < 0.35
        r["ring_gap"] = max(r["ring_gap"], round(float((ring & ~dark).sum() / max(ring.sum(), 1)), 3))
    near = ndi.binary_dilation(a >= 0.5, iterations=2)
    r["ghost"] = int(((a > 0.02) & (a < 0.5) & ~near).sum())
    del out
    return r


if __name__ == "__main__":
    from branchnb.core.image import composite_over
    from branchnb.core.io import encode_png
    from branchnb.strokes import edit_structure

    tag = sys.argv[1]
    sizes = [int(v) for v in sys.argv[2:]] or [300, 600, 1000]
    folder = os.environ.get("OUT") or os.path.join(tempfile.gettempdir(), "strokes_hidden")
    os.makedirs(folder, exist_ok=True)
    only = os.environ.get("ONLY")
    for name in (only.split(",") if only else EDITS):
        for n in sizes:
            obj, src, tgt, checks = EDITS[name](n)
            t0 = time.process_time()
            res = edit_structure(obj.image, src, tgt)
            dt = time.process_time() - t0
            r = figures(obj, res, checks)
            print(f"{name:11s} {n:5d} " + " ".join(f"{kk}={v}" for kk, v in r.items()) + f" cpu={dt:.2f}",
                  flush=True)
            with open(os.path.join(folder, f"{tag}_{name}_{n}.png"), "wb") as f:
                f.write(encode_png(composite_over(res.image)))
            with open(os.path.join(folder, f"src_{name}_{n}.png"), "wb") as f:
                f.write(encode_png(composite_over(obj.image)))
