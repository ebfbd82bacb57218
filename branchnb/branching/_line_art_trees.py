"""Procedural line art with a known tree (issue 23, stroke joins): broken drawings, interlace vines.

Used by the tests and by :func:`measure_line_art` to check that extraction
gives connected trees on drawn line art (issue 23): the strokes of a drawn
tree stop 1-3 px short of the stroke they branch from, and the strand
passing under a crossing is cut by a white gap on each side of the one
passing over. Each example returns the image and the true polylines with
their parents, so the number of trees, the junctions and the centre lines
are known.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..core.structure import Structure


def _draw(img: np.ndarray, pts: np.ndarray, width: float, value: int = 0) -> None:
    cv2.polylines(img, [np.rint(pts * 16).astype(np.int32)], False, value, max(1, int(round(width))),
                  cv2.LINE_AA, shift=4)


def _outline(img: np.ndarray, strokes: list[tuple[np.ndarray, float]], line: float) -> np.ndarray:
    """Strokes drawn as outlines: black ink of ``line`` px around white insides."""
    ink = np.full(img.shape, 255, np.uint8)
    for pts, w in strokes:
        _draw(ink, pts, w)
    inside = np.full(img.shape, 255, np.uint8)
    for pts, w in strokes:
        _draw(inside, pts, max(w - 2 * line, 1))
    return np.where(inside < 128, 255, ink).astype(np.uint8)


def _walk(rng, start, heading, length, wiggle, bounds, step=1.0):
    h, w = bounds
    n = max(int(length / step), 2)
    turn = np.cumsum(rng.normal(0, wiggle, n))
    turn = np.convolve(turn, np.ones(9) / 9, "same")
    ang = heading + turn
    pts = start + np.cumsum(np.c_[np.cos(ang), np.sin(ang)] * step, 0)
    inside = (pts[:, 0] > 6) & (pts[:, 0] < w - 7) & (pts[:, 1] > 6) & (pts[:, 1] < h - 7)
    stop = int(np.argmin(inside)) if not inside.all() else n
    return np.vstack([start, pts[:stop]])


def branching_drawing(size: int = 400, rng=0, *, gap: float = 2.0, width: float | None = None,
                      outlined: bool = False, depth: int = 3):
    """A drawn tree: a trunk with side branches (recursively), each stopping ``gap`` px short of its parent.

    Returns ``(image, truth, junctions)``: a float32 RGB image, the true
    :class:`Structure` (one tree, centre lines) and the (x, y) points where
    the children leave their parents.
    """
    rng = np.random.default_rng(rng)
    h = w = int(size)
    lw = float(width) if width is not None else max(2.0, size / 130)
    from ..core.structure import Branch

    start = np.array([w * 0.5 + rng.uniform(-0.1, 0.1) * w, h - 8.0])
    trunk = _walk(rng, start, -np.pi / 2, 0.85 * h, 0.04, (h, w))
    branches = [Branch(trunk, lw / 2)]
    junctions = []
    todo = [(0, 1, 0.55 * h)]
    while todo:
        bi, gen, length = todo.pop()
        pts = branches[bi].points
        n_kids = rng.integers(2, 4) if gen <= depth else 0
        arc = np.r_[0, np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]
        if arc[-1] < 60:
            continue
        for k in range(n_kids):
            s = arc[-1] * (0.25 + 0.6 * (k + rng.uniform(0.2, 0.8)) / n_kids)
            v = int(np.searchsorted(arc, s))
            v = int(np.clip(v, 3, len(pts) - 4))
            tang = pts[v + 3] - pts[v - 3]
            dev = rng.uniform(0.7, 1.1)
            th = np.arctan2(tang[1], tang[0]) + rng.choice([-1, 1]) * dev
            d = np.array([np.cos(th), np.sin(th)])
            # the child stroke (its round cap) starts `gap` px of paper beyond the parent's ink
            off = (lw + gap) / np.sin(dev) + 0.5
            kid = _walk(rng, pts[v] + d * off, th, length * rng.uniform(0.5, 0.8), 0.05, (h, w))
            if len(kid) < 25:
                continue
            # no crossing of earlier strokes
            ok = True
            for b in branches:
                k0 = int(4 * lw + gap + 10)
                if len(kid) <= k0:
                    ok = False
                    break
                dd = np.hypot(kid[k0:, None, 0] - b.points[None, :, 0], kid[k0:, None, 1] - b.points[None, :, 1])
                if dd.min() < 3 * lw + gap + 4:
                    ok = False
                    break
            if not ok:
                continue
            branches.append(Branch(np.vstack([pts[v], kid]), lw / 2, parent=bi, parent_vertex=v))
            junctions.append(pts[v].copy())
            todo.append((len(branches) - 1, gen + 1, length * 0.6))
    img = np.full((h, w), 255, np.uint8)
    strokes = [(b.points if b.parent is None else b.points[1:], lw) for b in branches]
    if outlined:
        img = _outline(img, strokes, max(1.0, lw / 4))
    else:
        for pts, lwi in strokes:
            _draw(img, pts, lwi)
    g = img.astype(np.float32) / 255
    return np.dstack([g] * 3), Structure(branches, image_shape=(h, w)), np.array(junctions).reshape(-1, 2)


def interlace_vine(size: int = 500, rng=0, *, loops: int = 3, width: float | None = None,
                   outlined: bool = False, gap: float | None = None):
    """One long stem looping over and under itself, with leafy side shoots touching it or 2 px short.

    Where the stem crosses itself the later pass goes over: the earlier one
    is cut by a white gap (``gap`` px, default about the line's width) on
    each side. Returns ``(image, truth, junctions)`` as :func:`branching_drawing`.
    """
    from ..core.structure import Branch

    rng = np.random.default_rng(rng)
    h, w = int(0.62 * size), int(size)
    lw = float(width) if width is not None else max(3.0, size / 90)
    gp = float(gap) if gap is not None else 0.8 * lw
    t = np.linspace(0, 1, 6000)
    a, wv = 0.11 * h * 1.4, 2 * np.pi * loops
    x = 0.1 * w + 0.8 * w * t - 1.3 * a * np.sin(wv * t)
    y = 0.5 * h - a * np.cos(wv * t) + 0.1 * h * np.sin(2.3 * t + rng.uniform(0, 6))
    arc = np.r_[0, np.cumsum(np.hypot(np.diff(x), np.diff(y)))]
    s = np.arange(0, arc[-1], 1.0)
    p = np.c_[np.interp(s, arc, x), np.interp(s, arc, y)]
    n = len(p)
    keep = np.ones(n, bool)
    cut = int(np.ceil(lw / 2 + gp + lw / 2))
    d = np.hypot(p[:, None, 0] - p[None, :, 0], p[:, None, 1] - p[None, :, 1])
    under, _over = np.nonzero((d < 1.0) & (np.arange(n)[None, :] - np.arange(n)[:, None] > 4 * lw + 20))
    for i in under:
        keep[max(i - cut, 0): i + cut + 1] = False
    branches = [Branch(p, lw / 2)]
    junctions = []
    strokes = []
    for pc in np.split(np.arange(n), np.flatnonzero(np.diff(keep.astype(int))) + 1):
        if keep[pc[0]] and len(pc) > 1:
            strokes.append((p[pc], lw))
    near_cut = np.convolve(~keep, np.ones(int(6 * cut) + 1), "same") > 0
    leaves = []
    step = int(max(60, 0.18 * w))
    for s0 in np.arange(step // 2, n - step // 2, step):
        if near_cut[s0]:
            continue
        tg = p[min(s0 + 3, n - 1)] - p[s0 - 3]
        side = rng.choice([-1, 1])
        th = np.arctan2(tg[1], tg[0]) + side * rng.uniform(0.7, 1.0)
        g0 = rng.choice([0.0, 2.0])
        dvec = np.array([np.cos(th), np.sin(th)])
        k = np.arange(0, rng.uniform(5, 7) * lw, 1.0)
        ang = th - side * 0.02 * k
        q = p[s0] + dvec * (lw * 0.75 + g0) + np.c_[np.cumsum(np.cos(ang)), np.sin(ang).cumsum()]
        if (q < 8).any() or (q[:, 0] > w - 8).any() or (q[:, 1] > h - 8).any():
            continue
        dd = np.hypot(q[:, None, 0] - p[None, :, 0], q[:, None, 1] - p[None, :, 1])
        if dd[int(len(q) * 0.6):].min() < 2.5 * lw:
            continue
        sw = 0.7 * lw
        strokes.append((q, sw))
        leaves.append((q[-1], ang[-1]))
        branches.append(Branch(np.vstack([p[s0], q]), sw / 2, parent=0, parent_vertex=int(s0)))
        junctions.append(p[s0].copy())
    img = np.full((h, w), 255, np.uint8)
    if outlined:
        img = _outline(img, strokes, max(1.0, lw / 4))
    else:
        for pts, lwi in strokes:
            _draw(img, pts, lwi)
    for c, ang in leaves:
        cv2.ellipse(img, (int(c[0]), int(c[1])), (int(1.6 * lw), int(0.9 * lw)), float(np.degrees(ang)),
                    0, 360, 0, -1 if not outlined else max(1, int(lw / 4)), cv2.LINE_AA)
    g = img.astype(np.float32) / 255
    return np.dstack([g] * 3), Structure(branches, image_shape=(h, w)), np.array(junctions).reshape(-1, 2)


def _samples(s: Structure, step: float = 1.0) -> np.ndarray:
    out = []
    for b in s.branches:
        pts = b.points
        arc = np.r_[0, np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]
        t = np.arange(0, arc[-1] + 1e-9, step)
        out.append(np.c_[np.interp(t, arc, pts[:, 0]), np.interp(t, arc, pts[:, 1])])
    return np.vstack(out) if out else np.zeros((0, 2))


def measure_line_art(truth: Structure, junctions: np.ndarray, found: Structure, *, tol: float = 3.0,
                     junction_tol: float | None = None) -> dict:
    """Trees, junctions recovered and centre-line recall of an extraction against the truth.

    A true junction counts as recovered when a child branch of ``found``
    starts within ``junction_tol`` (default ``max(8, 3 r)``: the child starts at a
    vertex of its parent, 4 px apart) of it; recall is
    the share of the true centre line (1 px samples) within ``tol`` px of
    ``found``'s centre lines.
    """
    from scipy.spatial import cKDTree

    ts, fs = _samples(truth), _samples(found, 0.5)
    r = float(np.median(np.concatenate([b.thickness for b in truth.branches])))
    jt = junction_tol if junction_tol is not None else max(8.0, 3.0 * r)
    recall = float((cKDTree(fs).query(ts)[0] <= tol).mean()) if len(fs) else 0.0
    starts = np.array([b.points[0] for b in found.branches if b.parent is not None]).reshape(-1, 2)
    if len(junctions) and len(starts):
        jr = float((cKDTree(starts).query(junctions)[0] <= jt).mean())
    else:
        jr = 1.0 if not len(junctions) else 0.0
    return {"trees": sum(b.parent is None for b in found.branches),
            "true_trees": sum(b.parent is None for b in truth.branches),
            "junctions": jr, "recall": recall}


def _main(argv=None) -> None:
    """``python -m branchnb.branching._line_art_trees [--no-joins]``: the line-art table (24 cases)."""
    import argparse
    import time

    from .extraction import extract_structure

    ap = argparse.ArgumentParser(description=_main.__doc__)
    ap.add_argument("--no-joins", action="store_true", help="extract with join_gaps=0 (before issue 23)")
    a = ap.parse_args(argv)
    kw = {"join_gaps": 0.0} if a.no_joins else {}
    rows, cpu = [], 0.0
    for kind in ("drawing", "vine"):
        for size in (200, 500, 1000):
            for outlined in (False, True):
                for seed in (0, 1):
                    if kind == "drawing":
                        img, truth, junctions = branching_drawing(size, seed, gap=(1.0, 3.0)[seed], outlined=outlined)
                    else:
                        img, truth, junctions = interlace_vine(size, seed, outlined=outlined)
                    t0 = time.process_time()
                    found = extract_structure(img, **kw)
                    cpu += time.process_time() - t0
                    m = measure_line_art(truth, junctions, found)
                    rows.append((outlined, m))
                    print(f"{kind:8s} {size:5d} {'outlined' if outlined else 'solid':8s} seed {seed}: trees "
                          f"{m['trees']}/{m['true_trees']}  junctions {m['junctions']:.2f}  recall {m['recall']:.2f}")
    for o in (False, True):
        sel = [m for oo, m in rows if oo == o]
        print(f"{'outlined' if o else 'solid':8s}: exact tree count {sum(m['trees'] == m['true_trees'] for m in sel)}"
              f"/{len(sel)}, mean trees {np.mean([m['trees'] for m in sel]):.1f}, junctions "
              f"{np.mean([m['junctions'] for m in sel]):.2f}, recall {np.mean([m['recall'] for m in sel]):.3f}")
    print(f"extraction CPU {cpu:.1f} s")


if __name__ == "__main__":
    _main()
