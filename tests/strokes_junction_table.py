"""Junction checks of issue 25 on multi-part procedural objects, as a table (not a test).

``PYTHONPATH=. python tests/strokes_junction_table.py TAG [SIZES...]`` edits a
twig (bent, 4 parts carried, a leaf added), a figure (limbs turned), a
starfish (two arms turned, the disk kept), antlers (two tines turned, one
copied), a coral (a branch turned, one copied), a flower (``flower_bend``:
stem bent, leaves and head carried, petals unstroked; ``flower_half``: stem
shortened 0.5x carrying them; ``flower_add``: a third leaf; ``flower_long``:
a leaf lengthened 1.4x) and a hand (``hand_bend``: palm turned, fingers
carried, thumb unstroked; ``hand_add``: a second thumb; ``hand_turn``: the
thumb turned across; ``hand_long`` / ``hand_half``: a finger 1.4x / 0.5x,
the other fingers unstroked) at 256 / 512 / 1000 px and
prints per edit: the longest gap (px) along a child's stroke, the most
missing px of one part where its rigid map puts it, pieces, fleck px, light
(un-outlined) silhouette px, CPU s
the results go to ``$TMPDIR/strokes_junction_table/TAG_*.png`` (or ``OUT=dir``).
``ONLY=coral,antlers`` picks objects.
"""
import json
import os
import sys
import tempfile
import time

import numpy as np
from scipy import ndimage as ndi

from branchnb.core.image import composite_over
from branchnb.core.io import encode_png
from branchnb.strokes import Stroke, edit_structure
from branchnb.strokes.parts import carry_stroke
from branchnb.strokes.procedural import antlers, coral, figure, starfish, twig
from branchnb.strokes.procedural_more import flower, hand

EIGHT = np.ones((3, 3))

def rot(th):
    c, s = np.cos(th), np.sin(th)
    return np.array([[c, -s], [s, c]])

def turn(st, th, about):
    return (np.asarray(st, float) - about) @ rot(th).T + about

def rigid_from(src, tgt):
    """(R, t) with tgt ~ R src + t (first point and first->last direction)."""
    src, tgt = np.asarray(src, float), np.asarray(tgt, float)
    a = np.arctan2(*(src[-1] - src[0])[::-1])
    b = np.arctan2(*(tgt[-1] - tgt[0])[::-1])
    R = rot(b - a)
    return R, tgt[0] - R @ src[0]

def mapped(obj, part, R, t, shape):
    """Part pixels (eroded) mapped by x -> R x + t into a mask of ``shape``."""
    m = ndi.binary_erosion(obj.labels == part, iterations=int(np.ceil(obj.outline)) + 1)
    yy, xx = np.nonzero(m)
    out = np.zeros(shape, bool)
    # forward splat with 2x supersampling
    for dx in (-0.25, 0.25):
        for dy in (-0.25, 0.25):
            q = np.c_[xx + dx, yy + dy] @ R.T + t
            qi = np.rint(q).astype(int)
            ok = (qi[:, 0] >= 0) & (qi[:, 0] < shape[1]) & (qi[:, 1] >= 0) & (qi[:, 1] < shape[0])
            out[qi[ok, 1], qi[ok, 0]] = True
    return ndi.binary_erosion(out)  # splat holes at the rim

def gap_along(alpha, st, frac=0.8):
    st = Stroke(st)
    s = np.arange(0.0, frac * st.length, 0.5)
    p = np.array([st.point_at(v) for v in s])
    a = ndi.map_coordinates(alpha, [p[:, 1], p[:, 0]], order=1, cval=0)
    off = a < 0.5
    best = run = 0
    for o in off:
        run = run + 1 if o else 0
        best = max(best, run)
    return best * 0.5

# ---- edits: returns obj, src, tgt, expect (list of (part, R, t)), children (list of target strokes)
def ed_twig(n):
    obj = twig(n, rng=3)
    sp = obj.strokes[0]
    h = obj.image.shape[0]
    x0 = sp[0, 0]
    bent = np.c_[sp[:, 0], 0.45 * h + 0.12 * h * np.sin((sp[:, 0] - x0) / (sp[-1, 0] - x0) * np.pi)]
    src, tgt, exp = [sp], [bent], []
    for k in range(1, 5):
        c = carry_stroke(obj.strokes[k], sp, bent)
        src.append(obj.strokes[k])
        tgt.append(c)
        exp.append((k, *rigid_from(obj.strokes[k], c)))
    leaf = carry_stroke(obj.strokes[2], sp, bent)
    bst = Stroke(bent)
    p = bst.point_at(0.85 * bst.length)
    new = p + (leaf - leaf[0]) * [1, -1]
    src.append(obj.strokes[2])
    tgt.append(new)
    # mirrored leaf: not rigid, skip its coverage
    return obj, src, tgt, exp, tgt[1:]

def ed_figure(n):
    obj = figure(n, rng=0)
    body = obj.strokes[0]
    src, tgt, exp = [body], [body], [(0, np.eye(2), np.zeros(2)), (1, np.eye(2), np.zeros(2))]
    for k, ang in ((2, 0.9), (3, -1.0), (4, 0.3), (5, -0.3)):
        st = obj.strokes[k]
        src.append(st)
        t = turn(st, ang, st[0])
        tgt.append(t)
        exp.append((k, rot(ang), st[0] - rot(ang) @ st[0]))
    return obj, src, tgt, exp, tgt[1:]

def ed_starfish(n):
    obj = starfish(n, rng=0)
    c = obj.strokes[1][0]
    src = [obj.strokes[0], obj.strokes[3], obj.strokes[1]]
    tgt = [src[0], turn(src[1], -0.6, c), turn(src[2], 0.35, c)]
    I = (np.eye(2), np.zeros(2))
    exp = [(0, *I), (2, *I), (4, *I), (5, *I), (3, rot(-0.6), c - rot(-0.6) @ c), (1, rot(0.35), c - rot(0.35) @ c)]
    return obj, src, tgt, exp, tgt[1:]

def ed_antlers(n):
    obj = antlers(n, rng=0)
    beam = obj.strokes[0]
    I = (np.eye(2), np.zeros(2))
    t2, t3 = obj.strokes[2], obj.strokes[3]
    bst = Stroke(beam)
    p = bst.point_at(0.3 * bst.length)
    # a new tine: tine 2 copied to 30 % of the beam
    new = p + (t2 - t2[0])
    src = [beam, obj.strokes[1], t2, t3, t2]
    tgt = [beam, obj.strokes[1], turn(t2, -0.35, t2[0]), turn(t3, 0.3, t3[0]), new]
    exp = [(0, *I), (1, *I), (4, *I), (2, rot(-0.35), t2[0] - rot(-0.35) @ t2[0]),
           (3, rot(0.3), t3[0] - rot(0.3) @ t3[0])]
    return obj, src, tgt, exp, tgt[1:]

def ed_coral(n):
    obj = coral(n, rng=0)
    trunk, b1, b2, b3 = obj.strokes[:4]
    I = (np.eye(2), np.zeros(2))
    ts = Stroke(trunk)
    p = ts.point_at(0.35 * ts.length)
    new = p + (b3 - b3[0]) @ rot(0.25).T
    R1 = rot(-0.3)
    t1 = b1[0] - R1 @ b1[0]
    src = [trunk, b1, b2, b3, b3]
    tgt = [trunk, turn(b1, -0.3, b1[0]), b2, b3, new]
    exp = [(0, *I), (2, *I), (3, *I), (5, *I), (6, *I), (1, R1, t1), (4, R1, t1)]
    return obj, src, tgt, exp, tgt[1:]

def scaled(st, f):
    st = np.asarray(st, float)
    return st[0] + f * (st - st[0])

def carried(obj, src, tgt, exp, kids, parent_k, parent_tgt, strokes_of, follow=()):
    """Children ``strokes_of`` carried by strokes along part ``parent_k`` moved to ``parent_tgt``;
    ``follow``: (part, carrier part) pairs of unstroked parts expected to move with the carrier."""
    rig = {}
    for k in strokes_of:
        c = carry_stroke(obj.strokes[k], obj.strokes[parent_k], parent_tgt)
        src.append(obj.strokes[k])
        tgt.append(c)
        kids.append(c)
        rig[k] = rigid_from(obj.strokes[k], c)
        exp.append((k, *rig[k]))
    for part, carrier in follow:
        exp.append((part, *rig[carrier]))

def ed_flower_bend(n):
    obj = flower(n, rng=0)
    st = obj.strokes[0]
    y = (st[0, 1] - st[:, 1]) / (st[0, 1] - st[-1, 1])
    bent = st + np.c_[0.15 * n * y ** 2, 0.02 * n * y]
    src, tgt, exp, kids = [st], [bent], [], []
    carried(obj, src, tgt, exp, kids, 0, bent, (1, 2, 3), [(p, 3) for p in range(4, 10)])
    return obj, src, tgt, exp, kids

def ed_flower_half(n):
    obj = flower(n, rng=0)
    st = obj.strokes[0]
    short = scaled(st, 0.5)
    src, tgt, exp, kids = [st], [short], [], []
    carried(obj, src, tgt, exp, kids, 0, short, (1, 2, 3), [(p, 3) for p in range(4, 10)])
    return obj, src, tgt, exp, kids

def ed_flower_add(n):
    obj = flower(n, rng=0)
    st, l2 = obj.strokes[0], obj.strokes[2]
    p = Stroke(st).point_at(0.72 * Stroke(st).length)
    new = p + (l2 - l2[0]) @ rot(0.35).T
    I = (np.eye(2), np.zeros(2))
    return obj, [st, l2, l2], [st, l2, new], [(k, *I) for k in range(10)], [l2, new]

def ed_flower_long(n):
    obj = flower(n, rng=0)
    st, l1 = obj.strokes[0], obj.strokes[1]
    I = (np.eye(2), np.zeros(2))
    return obj, [st, l1], [st, scaled(l1, 1.4)], [(k, *I) for k in (0, 2, 3, 4, 5, 6, 7, 8, 9)], [scaled(l1, 1.4)]

def ed_hand_bend(n):
    obj = hand(n, rng=0)
    fore, palm = obj.strokes[0], obj.strokes[1]
    tp = turn(palm, 0.45, palm[0])
    I = (np.eye(2), np.zeros(2))
    src, tgt, exp, kids = [fore, palm], [fore, tp], [(0, *I), (1, rot(0.45), palm[0] - rot(0.45) @ palm[0])], [tp]
    carried(obj, src, tgt, exp, kids, 1, tp, (2, 3, 4, 5), [(6, 2)])
    return obj, src, tgt, exp, kids

def ed_hand_add(n):
    obj = hand(n, rng=0)
    palm, th = obj.strokes[1], obj.strokes[6]
    x = th[0, 0]
    new = np.c_[2 * x - th[:, 0], th[:, 1]]
    I = (np.eye(2), np.zeros(2))
    return obj, [palm, th, th], [palm, th, new], [(k, *I) for k in range(7)], [th, new]

def ed_hand_turn(n):
    obj = hand(n, rng=0)
    palm, th = obj.strokes[1], obj.strokes[6]
    I = (np.eye(2), np.zeros(2))
    new = turn(th, -2.4, th[0])
    return obj, [palm, th], [palm, new], [(k, *I) for k in range(6)], [new]

def ed_hand_long(n):
    obj = hand(n, rng=0)
    palm, f2 = obj.strokes[1], obj.strokes[3]
    I = (np.eye(2), np.zeros(2))
    return obj, [palm, f2], [palm, scaled(f2, 1.4)], [(k, *I) for k in (0, 1, 2, 4, 5, 6)], [scaled(f2, 1.4)]

def ed_hand_half(n):
    obj = hand(n, rng=0)
    palm, f3 = obj.strokes[1], obj.strokes[4]
    I = (np.eye(2), np.zeros(2))
    return obj, [palm, f3], [palm, scaled(f3, 0.5)], [(k, *I) for k in (0, 1, 2, 3, 5, 6)], [scaled(f3, 0.5)]

EDITS = {"twig": ed_twig, "figure": ed_figure, "starfish": ed_starfish, "antlers": ed_antlers, "coral": ed_coral,
         "flower_bend": ed_flower_bend, "flower_half": ed_flower_half, "flower_add": ed_flower_add,
         "flower_long": ed_flower_long, "hand_bend": ed_hand_bend, "hand_add": ed_hand_add, "hand_turn": ed_hand_turn,
         "hand_long": ed_hand_long, "hand_half": ed_hand_half}

def measure(obj, res, exp, children):
    img = res.image
    a = img[..., 3]
    shape = a.shape
    gaps = [gap_along(a, c) for c in children]
    want = np.zeros(shape, bool)
    missing = []
    for part, R, t in exp:
        m = mapped(obj, part, R, t, shape)
        want |= m
        missing.append(int((m & (a < 0.5)).sum()))
    lab, npc = ndi.label(a > 0.02, structure=EIGHT)
    sizes = np.bincount(lab.ravel())[1:]
    fleck = int(sizes.sum() - sizes.max()) if npc else 0
    m = a > 0.5
    edge = m & ~ndi.binary_erosion(m)
    light = edge & (img[..., :3].mean(axis=2) > 0.35)
    return dict(gap=max(gaps), missing=max(missing), pieces=int(npc), fleck_px=fleck,
                light_edge=int(light.sum()), edge=int(edge.sum()))

if __name__ == "__main__":
    tag = sys.argv[1]
    sizes = [int(v) for v in sys.argv[2:]] or [256, 512, 1000]
    names = [v for v in EDITS]
    only = os.environ.get("ONLY")
    if only:
        names = only.split(",")
    folder = os.environ.get("OUT") or os.path.join(tempfile.gettempdir(), "strokes_junction_table")
    os.makedirs(folder, exist_ok=True)
    out = {}
    for name in names:
        for n in sizes:
            obj, src, tgt, exp, children = EDITS[name](n)
            t0 = time.process_time()
            res = edit_structure(obj.image, src, tgt)
            dt = time.process_time() - t0
            r = measure(obj, res, exp, children)
            r["cpu"] = round(dt, 2)
            out[f"{name} {n}"] = r
            print(f"{name:9s} {n:5d} " + " ".join(f"{k}={v}" for k, v in r.items()), flush=True)
            with open(os.path.join(folder, f"{tag}_{name}_{n}.png"), "wb") as f:
                f.write(encode_png(composite_over(res.image)))
    with open(os.path.join(folder, f"{tag}.json"), "w") as f:
        json.dump(out, f, indent=1)
