"""Three multi-part objects of kinds the stroke tests had not seen (issue 25), with multi-part edits.

``cactus``: a candelabra cactus (a ribbed trunk, three arms that leave it
sideways and bend upwards, flowers on two arm tips); ``delta``: a river drawn
as a shape (a channel splitting into distributaries that fan out, a darker
bank line, ripples); ``fern``: a frond (a curved rachis with eight pinnae on
alternating sides, none stroked but two). Each ``edit_*`` returns
``(obj, src, tgt, expect, children)`` like the edits of
``strokes_junction_table.py`` (expect: ``(part, R, t)`` rigid maps of parts
whose pixels must stay covered).

``PYTHONPATH=. python tests/strokes_unseen_objects.py TAG [SIZES...]`` prints the
junction table's figures for the edits and writes PNGs to ``$OUT`` (default
``$TMPDIR/strokes_unseen``).
"""
import os
import sys
import tempfile
import time

import numpy as np

from branchnb.strokes.procedural import _point_at, _square_canvas

sys.path.insert(0, os.path.dirname(__file__))
from strokes_junction_table import measure, rigid_from, rot, turn  # noqa: E402


def _len(pts):
    return float(np.hypot(*np.diff(pts, axis=0).T).sum())


def cactus(size=600, rng=0):
    c, n, k = _square_canvas(size, 600.0, rng)
    green = np.array((0.30, 0.55, 0.25))

    def skin(s, d, hw):
        # vertical ribs (across the part's axis) and dark spine dots
        rib = 0.5 + 0.5 * np.cos(2 * np.pi * (d + hw) / (9 * k))
        rgb = green[None, None] * (0.75 + 0.35 * rib)[..., None] + c.noise(10 * k, 0.03)[..., None]
        spine = (np.abs(((s / (14 * k)) % 1.0) - 0.5) < 0.08) & (rib > 0.9)
        return np.where(spine[..., None], np.array((0.92, 0.9, 0.7)), rgb)

    trunk = np.array([(0.5 * n, 0.96 * n), (0.5 * n, 0.55 * n), (0.5 * n, 0.15 * n)])
    parts = [(trunk, 40 * k, -1)]
    for frac, side, reach, up in ((0.3, -1, 0.17, 0.25), (0.5, 1, 0.17, 0.3), (0.75, -1, 0.15, 0.1)):
        a = _point_at(trunk, frac)
        out = a + np.array([side * reach * n, 0.0])
        parts.append((np.array([a, out, out + np.array([0.0, -0.06 * n]), out + np.array([0.0, -up * n])]),
                      24 * k, 0))
    for i, (pts, hw, parent) in enumerate(parts):
        sdf, s = c.capsule(pts, hw)
        d = np.minimum(sdf + hw, hw)  # distance to the axis (inside)
        c.part(pts, "trunk" if i == 0 else f"arm {i}", parent, hw, (sdf, skin(s, d, hw), 2 if i == 0 else 1))
    for j, arm in enumerate((1, 2)):
        tip = parts[arm][0][-1]
        ctr = tip + np.array([0.0, -0.03 * n])
        pts = np.array([tip, ctr])
        sdf, s = c.capsule(pts, 14 * k)
        c.part(pts, f"flower {j + 1}", arm, 14 * k, (sdf, np.broadcast_to(np.array((0.95, 0.35, 0.55)), (n, n, 3)), 3))
    return c.result()


def delta(size=600, rng=0):
    c, n, k = _square_canvas(size, 600.0, rng)
    blue = np.array((0.25, 0.5, 0.8))

    def water(s, hw):
        rip = 0.5 + 0.5 * np.sin(2 * np.pi * s / (11 * k) + 2 * c.noise(30 * k, 1.0))
        return blue[None, None] * (0.85 + 0.25 * rip)[..., None] + c.noise(6 * k, 0.03)[..., None]

    main = np.array([(0.5 * n, 0.04 * n), (0.47 * n, 0.25 * n), (0.5 * n, 0.45 * n)])
    parts = [(main, 30 * k, -1, 1.0)]
    fan = (-0.8, -0.25, 0.3, 0.85)
    for ang in fan:
        a = main[-1]
        u = np.array([np.sin(ang), np.cos(ang)])
        v = np.array([u[1], -u[0]])
        parts.append((np.array([a, a + 0.2 * n * u + 0.02 * n * v, a + 0.42 * n * u]), 16 * k, 0, 0.55))
    # a side channel of the first distributary
    d1 = parts[1][0]
    a = _point_at(d1, 0.5)
    u = np.array([np.sin(-0.2), np.cos(-0.2)])
    parts.append((np.array([a, a + 0.12 * n * u, a + 0.22 * n * u]), 8 * k, 1, 0.6))
    for i, (pts, hw, parent, taper) in enumerate(parts):
        sdf, s = c.capsule(pts, hw, taper=taper)
        c.part(pts, "river" if i == 0 else f"channel {i}", parent, hw, (sdf, water(s, hw), 2 if i == 0 else 1))
    return c.result()


def fern(size=600, rng=0):
    c, n, k = _square_canvas(size, 600.0, rng)
    t = np.linspace(0, 1, 12)
    rachis = np.c_[0.3 * n + 0.35 * n * t + 0.1 * n * np.sin(np.pi * t) ** 2, 0.95 * n - 0.85 * n * t ** 0.9]
    parts = [(rachis, 7 * k, -1, 0.5, (0.35, 0.45, 0.2))]
    for i in range(8):
        frac = 0.12 + 0.1 * i
        a = _point_at(rachis, frac)
        b = _point_at(rachis, frac + 0.02)
        d = (b - a) / np.hypot(*(b - a))
        side = 1 if i % 2 else -1
        u = rot(side * 1.1) @ d
        length = (0.22 - 0.018 * i) * n
        parts.append((np.array([a, a + 0.5 * length * u + side * 0.02 * n * (rot(np.pi / 2) @ u),
                                a + length * u]), (14 - i) * k, 0, 0.25, (0.2, 0.55, 0.2)))
    for i, (pts, hw, parent, taper, col) in enumerate(parts):
        sdf, s = c.capsule(pts, hw, taper=taper)
        vein = np.abs(sdf + hw * (1.0 - 0.75 * np.clip(s / _len(pts), 0, 1))) < 1.2 * max(k, 0.6)
        rgb = np.asarray(col)[None, None] * (0.9 + 0.2 * np.clip(s / _len(pts), 0, 1))[..., None] \
            + c.noise(8 * k, 0.04)[..., None]
        rgb = np.where(vein[..., None] & (i > 0), np.asarray(col) * 0.6, rgb)
        c.part(pts, "rachis" if i == 0 else f"pinna {i}", parent, hw, (sdf, rgb, 2 if i == 0 else 1))
    return c.result()


def berries(size=600, rng=0, with_canvas=False):
    """A curved branch with three tapered leaves and two berries on thin stalks (and the canvas:
    ``with_canvas``)."""
    c, n, k = _square_canvas(size, 600.0, rng)
    t = np.linspace(0, 1, 10)
    branch = np.c_[0.12 * n + 0.76 * n * t, 0.7 * n - 0.25 * n * np.sin(0.5 * np.pi * t)]
    bark = np.array((0.45, 0.32, 0.2))

    def tex(s, col, period):
        rip = 0.5 + 0.5 * np.sin(2 * np.pi * s / (period * k) + 2 * c.noise(25 * k, 1.0))
        return np.asarray(col)[None, None] * (0.85 + 0.25 * rip)[..., None] + c.noise(6 * k, 0.03)[..., None]

    parts = [(branch, 12 * k, -1, 0.6, bark, 9)]
    for frac, side, length in ((0.25, -1, 0.2), (0.5, 1, 0.22), (0.72, -1, 0.18)):
        a = _point_at(branch, frac)
        b = _point_at(branch, frac + 0.02)
        d = (b - a) / np.hypot(*(b - a))
        u = rot(side * 0.9) @ d
        parts.append((np.array([a, a + 0.5 * length * n * u, a + length * n * u]), 16 * k, 0, 0.15,
                      (0.25, 0.55, 0.2), 14))
    for frac in (0.38, 0.62):
        a = _point_at(branch, frac)
        tip = a + np.array([0.01 * n, 0.14 * n])
        parts.append((np.array([a, 0.5 * (a + tip) + [0.01 * n, 0], tip]), 3 * k, 0, 1.0, bark, 9))
    for i, (pts, hw, parent, taper, col, period) in enumerate(parts):
        sdf, s = c.capsule(pts, hw, taper=taper)
        c.part(pts, "branch" if i == 0 else f"part {i}", parent, hw, (sdf, tex(s, col, period), 2 if i == 0 else 1))
    for j, stalk in enumerate((4, 5)):
        tip = parts[stalk][0][-1]
        pts = np.array([tip, tip + np.array([0.0, 0.05 * n])])
        sdf, s = c.capsule(pts, 22 * k)
        c.part(pts, f"berry {j + 1}", stalk, 22 * k, (sdf, tex(s, (0.7, 0.1, 0.25), 30), 3))
    return (c.result(), c) if with_canvas else c.result()


def stickman(size=600, rng=0):
    """A stick figure with elbowed arms and knees: torso, head, two arms, two legs."""
    c, n, k = _square_canvas(size, 600.0, rng)
    cloth = np.array((0.3, 0.35, 0.7))

    def tex(s, col):
        st = 0.5 + 0.5 * np.sign(np.sin(2 * np.pi * s / (16 * k)))
        return np.asarray(col)[None, None] * (0.8 + 0.25 * st)[..., None] + c.noise(8 * k, 0.03)[..., None]

    torso = np.array([(0.5 * n, 0.3 * n), (0.5 * n, 0.45 * n), (0.5 * n, 0.62 * n)])
    parts = [(torso, 26 * k, -1, cloth)]
    sh = _point_at(torso, 0.12)
    for side in (-1, 1):
        elbow = sh + np.array([side * 0.16 * n, 0.04 * n])
        parts.append((np.array([sh, elbow, elbow + np.array([side * 0.04 * n, -0.14 * n])]), 11 * k, 0,
                      (0.85, 0.65, 0.5)))
    hip = torso[-1]
    for side in (-1, 1):
        knee = hip + np.array([side * 0.08 * n, 0.14 * n])
        parts.append((np.array([hip, knee, knee + np.array([0.0, 0.16 * n])]), 14 * k, 0, (0.25, 0.25, 0.3)))
    for i, (pts, hw, parent, col) in enumerate(parts):
        sdf, s = c.capsule(pts, hw)
        c.part(pts, "torso" if i == 0 else f"limb {i}", parent, hw, (sdf, tex(s, col), 2 if i == 0 else 1))
    neck = torso[0]
    pts = np.array([neck, neck + np.array([0.0, -0.12 * n])])
    sdf, s = c.capsule(pts, 30 * k, taper=1.0)
    c.part(pts, "head", 0, 30 * k, (sdf, tex(s, (0.85, 0.65, 0.5)), 3))
    return c.result()


I = (np.eye(2), np.zeros(2))


def edit_cactus(n):
    """Trunk and arm 2 kept; arm 1 turned up 0.3 rad about its root carrying its flower (strokes); arm 3
    lengthened 1.3x; arm 3 copied, mirrored, low on the trunk's other side (a new arm)."""
    obj = cactus(n)
    trunk, a1, a2, a3, f1 = obj.strokes[:5]
    R1 = rot(-0.3)
    t1 = turn(a1, -0.3, a1[0])
    f1t = (f1 - a1[0]) @ R1.T + a1[0]
    a3l = a3[0] + 1.3 * (a3 - a3[0])
    p = _point_at(trunk, 0.25)
    new = p + (a3 - a3[0]) * [-1, 1]
    src = [trunk, a1, f1, a2, a3, a3]
    tgt = [trunk, t1, f1t, a2, a3l, new]
    exp = [(0, *I), (2, *I), (5, *I), (1, R1, a1[0] - R1 @ a1[0]), (4, R1, a1[0] - R1 @ a1[0])]
    return obj, src, tgt, exp, tgt[1:]


def edit_delta(n):
    """The river bent; the four distributaries carried along by strokes, the outer one turned 0.25 rad
    farther out; its side channel unstroked."""
    obj = delta(n)
    main = obj.strokes[0]
    y = (main[:, 1] - main[0, 1]) / (main[-1, 1] - main[0, 1])
    bent = main + np.c_[0.12 * n * np.sin(np.pi * y) , 0 * y]
    bent[-1] = main[-1]  # the fan stays where it was
    src, tgt, exp = [main], [bent], []
    for kk in range(1, 5):
        st = obj.strokes[kk]
        t = turn(st, 0.25, st[0]) if kk == 1 else st
        src.append(st)
        tgt.append(t)
        R, tt = rigid_from(st, t)
        exp.append((kk, R, tt))
    exp.append((5, *exp[0][1:]))
    return obj, src, tgt, exp, tgt[1:]


def edit_fern(n):
    """The rachis kept; pinna 3 turned 0.4 rad toward the tip; pinna 6 copied to the rachis's base
    (a new pinna); the other pinnae unstroked."""
    obj = fern(n)
    r = obj.strokes[0]
    p3, p6 = obj.strokes[3], obj.strokes[6]
    side = 1  # pinna 3 (i = 2) sits on side -1; its turn toward the tip is +
    t3 = turn(p3, 0.4 * side, p3[0])
    a = _point_at(r, 0.05)
    new = a + (p6 - p6[0])
    src = [r, p3, p6]
    tgt = [r, t3, new]
    R3 = rot(0.4 * side)
    exp = [(kk, *I) for kk in (0, 1, 2, 4, 5, 6, 7, 8)] + [(3, R3, p3[0] - R3 @ p3[0])]
    return obj, src, tgt, exp, tgt[1:]


def edit_berries(n):
    """The branch bent (its far half raised 0.2 rad about its middle); the leaves and berry
    stalks carried by strokes, the berries unstroked; leaf 2 copied to the branch's tip half
    (a new leaf)."""
    obj = berries(n)
    br = obj.strokes[0]
    mid = _point_at(br, 0.5)
    cum = np.r_[0, np.cumsum(np.hypot(*np.diff(br, axis=0).T))]
    w = np.clip((cum / cum[-1] - 0.5) / 0.5, 0, 1)[:, None]
    R = rot(-0.2)
    bent = (1 - w) * br + w * ((br - mid) @ R.T + mid)
    src, tgt, exp = [br], [bent], []
    for kk, frac in zip(range(1, 6), (0.25, 0.5, 0.72, 0.38, 0.62)):
        st = obj.strokes[kk]
        # the part keeps its place and angle on the bent branch
        d0 = _point_at(br, frac + 0.01) - _point_at(br, frac - 0.01)
        d1 = _point_at(bent, frac + 0.01) - _point_at(bent, frac - 0.01)
        Rk = rot(np.arctan2(d1[1], d1[0]) - np.arctan2(d0[1], d0[0]))
        tk = _point_at(bent, frac) - Rk @ _point_at(br, frac)
        src.append(st)
        tgt.append(st @ Rk.T + tk)
        exp.append((kk, Rk, tk))
    exp += [(6, *exp[3][1:]), (7, *exp[4][1:])]
    leaf = obj.strokes[2]
    a = _point_at(bent, 0.85)
    src.append(leaf)
    tgt.append(a + (leaf - leaf[0]))
    return obj, src, tgt, exp, tgt[1:]


def edit_stickman(n):
    """Torso kept; the right arm raised 0.5 rad about the shoulder; the left leg lengthened
    1.15x; the left arm copied, mirrored, to the hip (a third arm, a new part); the head
    unstroked."""
    obj = stickman(n)
    torso, la, ra, ll, rl = obj.strokes[:5]
    R = rot(-0.5)
    ra_t = turn(ra, -0.5, ra[0])
    ll_t = ll[0] + 1.15 * (ll - ll[0])
    p = _point_at(torso, 0.8)
    new = p + (la - la[0]) * [-1, 1]
    src = [torso, la, ra, ll, rl, la]
    tgt = [torso, la, ra_t, ll_t, rl, new]
    exp = [(0, *I), (1, *I), (4, *I), (5, *I), (2, R, ra[0] - R @ ra[0])]
    return obj, src, tgt, exp, tgt[1:]


EDITS = {"cactus": edit_cactus, "delta": edit_delta, "fern": edit_fern, "berries": edit_berries,
         "stickman": edit_stickman}

if __name__ == "__main__":
    from branchnb.core.image import composite_over
    from branchnb.core.io import encode_png
    from branchnb.strokes import edit_structure

    tag = sys.argv[1]
    sizes = [int(v) for v in sys.argv[2:]] or [300, 600, 1000]
    folder = os.environ.get("OUT") or os.path.join(tempfile.gettempdir(), "strokes_unseen")
    os.makedirs(folder, exist_ok=True)
    only = os.environ.get("ONLY")
    for name in (only.split(",") if only else EDITS):
        for n in sizes:
            obj, src, tgt, exp, kids = EDITS[name](n)
            t0 = time.process_time()
            res = edit_structure(obj.image, src, tgt)
            dt = time.process_time() - t0
            r = measure(obj, res, exp, kids)
            print(f"{name:7s} {n:5d} " + " ".join(f"{kk}={v}" for kk, v in r.items()) + f" cpu={dt:.2f}", flush=True)
            with open(os.path.join(folder, f"{tag}_{name}_{n}.png"), "wb") as f:
                f.write(encode_png(composite_over(res.image)))
            with open(os.path.join(folder, f"src_{name}_{n}.png"), "wb") as f:
                f.write(encode_png(composite_over(obj.image)))
