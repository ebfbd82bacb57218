"""Parts overlapped by a neighbour, hung from the stroke whose tip ends in them (issue 25), as a table.

``cherry``: a twig, a leaf lying over a cherry's top, the cherry on a
stalk drawn into it (the leaf turned away, the stalk kept); ``hand``: a
body and an arm whose hand (unstroked, the arm's stroke ends in it) lies
over the body's side (the arm raised); ``flower``: two stems from one
base, the first one's head (unstroked, its stem drawn into it) lying over
the second stem (the first stem turned out). Each ``edit_*`` returns
``(obj, src, tgt, expect, children, part)``: ``expect`` as in
``strokes_junction_table.py``, ``part`` the label of the overlapping part.

``PYTHONPATH=. python tests/strokes_tip_objects.py TAG [SIZES...]`` prints
per edit the part's missing px (where its rigid map puts it), stray px (its
colour anywhere else), pieces and flecks, and writes PNGs to ``$OUT``
(default ``$TMPDIR/strokes_tip``).
"""
import os
import sys
import tempfile

import numpy as np
from scipy import ndimage as ndi

from branchnb.strokes.procedural import _square_canvas

sys.path.insert(0, os.path.dirname(__file__))
from strokes_junction_table import mapped, measure, rot, turn  # noqa: E402

I = (np.eye(2), np.zeros(2))


def _tex(c, k, s, col, period):
    rip = 0.5 + 0.5 * np.sin(2 * np.pi * s / (period * k) + 2 * c.noise(25 * k, 1.0))
    return np.asarray(col)[None, None] * (0.85 + 0.25 * rip)[..., None] + c.noise(6 * k, 0.03)[..., None]


def _draw(c, k, parts):
    for i, (pts, hw, parent, taper, col, z) in enumerate(parts):
        sdf, s = c.capsule(pts, hw, taper=taper)
        c.part(pts, f"part {i}", parent, hw, (sdf, _tex(c, k, s, col, 12), z))


def cherry(size=400, rng=0):
    c, n, k = _square_canvas(size, 400.0, rng)
    twig = np.array([(0.08 * n, 0.3 * n), (0.5 * n, 0.26 * n), (0.92 * n, 0.3 * n)])
    stalk = np.array([(0.45 * n, 0.265 * n), (0.47 * n, 0.4 * n), (0.5 * n, 0.52 * n)])
    leaf = np.array([(0.35 * n, 0.275 * n), (0.48 * n, 0.42 * n), (0.62 * n, 0.5 * n)])
    fruit = np.array([(0.5 * n, 0.52 * n), (0.5 * n, 0.62 * n)])
    _draw(c, k, [(twig, 9 * k, -1, 0.7, (0.45, 0.32, 0.2), 2), (stalk, 2.5 * k, 0, 1.0, (0.4, 0.3, 0.2), 1),
                 (leaf, 14 * k, 0, 0.15, (0.25, 0.55, 0.2), 4), (fruit, 30 * k, 1, 1.0, (0.75, 0.1, 0.15), 3)])
    return c.result()


def hand(size=400, rng=0):
    c, n, k = _square_canvas(size, 400.0, rng)
    body = np.array([(0.45 * n, 0.15 * n), (0.45 * n, 0.5 * n), (0.45 * n, 0.85 * n)])
    arm = np.array([(0.45 * n, 0.25 * n), (0.68 * n, 0.35 * n), (0.6 * n, 0.55 * n)])
    palm = np.array([(0.6 * n, 0.55 * n), (0.56 * n, 0.62 * n)])
    _draw(c, k, [(body, 40 * k, -1, 1.0, (0.3, 0.35, 0.7), 1), (arm, 10 * k, 0, 1.0, (0.3, 0.35, 0.7), 2),
                 (palm, 18 * k, 1, 1.0, (0.9, 0.7, 0.55), 3)])
    return c.result()


def flower(size=400, rng=0):
    c, n, k = _square_canvas(size, 400.0, rng)
    base = np.array((0.5 * n, 0.92 * n))
    s1 = np.array([base, (0.45 * n, 0.6 * n), (0.5 * n, 0.35 * n)])
    s2 = np.array([base, (0.62 * n, 0.6 * n), (0.66 * n, 0.2 * n)])
    head = np.array([(0.5 * n, 0.35 * n), (0.53 * n, 0.3 * n)])
    ground = np.array([(0.3 * n, 0.93 * n), (0.5 * n, 0.92 * n), (0.7 * n, 0.93 * n)])
    _draw(c, k, [(ground, 8 * k, -1, 1.0, (0.4, 0.3, 0.2), 1), (s1, 5 * k, 0, 0.8, (0.2, 0.5, 0.2), 1),
                 (s2, 5 * k, 0, 0.8, (0.2, 0.5, 0.2), 1), (head, 38 * k, 1, 1.0, (0.95, 0.75, 0.1), 3)])
    return c.result()


def edit_cherry(n):
    obj = cherry(n)
    twig, stalk, leaf = obj.strokes[:3]
    R = rot(-0.5)
    tl = turn(leaf, -0.5, leaf[0])
    exp = [(0, *I), (1, *I), (3, *I), (2, R, leaf[0] - R @ leaf[0])]
    return obj, [twig, stalk, leaf], [twig, stalk, tl], exp, [stalk, tl], 3


def edit_hand(n):
    obj = hand(n)
    body, arm = obj.strokes[:2]
    R = rot(-0.6)
    ta = turn(arm, -0.6, arm[0])
    exp = [(0, *I), (1, R, arm[0] - R @ arm[0]), (2, R, arm[0] - R @ arm[0])]
    return obj, [body, arm], [body, ta], exp, [ta], 2


def edit_flower(n):
    obj = flower(n)
    ground, s1, s2 = obj.strokes[:3]
    R = rot(-0.35)
    t1 = turn(s1, -0.35, s1[0])
    exp = [(0, *I), (2, *I), (1, R, s1[0] - R @ s1[0]), (3, R, s1[0] - R @ s1[0])]
    return obj, [ground, s1, s2], [ground, t1, s2], exp, [t1, s2], 3


EDITS = {"cherry": edit_cherry, "hand": edit_hand, "flower": edit_flower}


def figures(obj, res, exp, children, part):
    """``measure``'s figures plus the overlapping part's missing and stray px."""
    r = measure(obj, res, exp, children)
    img, a = res.image, res.image[..., 3]
    R, t = next((R, t) for p, R, t in exp if p == part)
    want = mapped(obj, part, R, t, a.shape)
    r["part_missing"] = int((want & (a < 0.5)).sum())
    # its colour (the source part's median, premultiplied) anywhere beyond its place
    m = ndi.binary_erosion(obj.labels == part, iterations=3)
    col = np.median(obj.image[..., :3][m] * obj.image[..., 3:][m], axis=0)
    like = (np.abs(img[..., :3] - col).max(axis=2) < 0.12) & (a > 0.5)
    r["stray"] = int((like & ~ndi.binary_dilation(want, iterations=int(obj.outline) + 4)).sum())
    return r


if __name__ == "__main__":
    from branchnb.core.image import composite_over
    from branchnb.core.io import encode_png
    from branchnb.strokes import edit_structure

    tag = sys.argv[1]
    sizes = [int(v) for v in sys.argv[2:]] or [300, 600, 1000]
    folder = os.environ.get("OUT") or os.path.join(tempfile.gettempdir(), "strokes_tip")
    os.makedirs(folder, exist_ok=True)
    for name, ed in EDITS.items():
        for n in sizes:
            obj, src, tgt, exp, kids, part = ed(n)
            res = edit_structure(obj.image, src, tgt)
            r = figures(obj, res, exp, kids, part)
            print(f"{name:7s} {n:5d} " + " ".join(f"{kk}={v}" for kk, v in r.items()), flush=True)
            for t, im in ((tag, res.image), ("src", obj.image)):
                with open(os.path.join(folder, f"{t}_{name}_{n}.png"), "wb") as f:
                    f.write(encode_png(composite_over(im)))
