"""Measure: a lightning bolt on a thin object (a pole, a lamp post with a head, a mast with
arms, a forked stem, letters T/L) branches like on a wide one and reaches the object's parts
(issue 25, dendrite38).

``python -m branchnb.dendrite._thin_branch_check [sizes] [seeds] [kinds] [outdir]`` stylizes,
with the defaults and ``metaphor="lightning"``, the thin objects of
:mod:`~branchnb.dendrite._thin_check` on a dusk gradient (kinds ``pole``, ``lamp``, ``mast``,
``stem``, ``T``, ``L``, the ``wide`` blob as the control) plus ``fork`` (a stem forking in two
arms, each with a small head) and prints per case: ``t10`` (mean turn, degrees per 10 px, of
the bolt's branches inside the object, :func:`~branchnb.dendrite._thin_check.thin_turn`), ``t1%``
(the turn of all its paths inside the object per 1.04 % of the diagonal,
:func:`~branchnb.dendrite._thin_check.bolt_turn`: the same measure at every picture size),
``main`` (the main channel's turn per 10 px), ``side`` (side branches at least 2 % of the
diagonal long leaving the main channel, per 100 px of it), ``tips`` (the dendrite's tips) and
``reach`` (share of the object's parts, the lamp's head, the mast's and the T's arm ends, the
fork's heads, that the bolt's paths enter: :func:`parts`). The last line prints the same on
a plain canvas (``plain``) for the ratio. With ``outdir`` it writes
``tb_<kind>_<n>_<seed>.png`` (picture | bolt). Not a test.
"""

from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage

from ._bolt_shape_check import _resample, turning
from ._thin_check import bolt_turn, thin_turn
from ._thin_check import case as thin_case

SIZES = (250, 500, 1000)
KINDS = ("pole", "lamp", "mast", "stem", "fork", "T", "L", "wide")


def fork_case(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """A stem forking in two arms, a small round head on each, on a dusk gradient."""
    rng = np.random.default_rng(seed)
    h, w = int(0.8 * n), n
    m = np.zeros((h, w), np.uint8)
    sw = max(2, int(round(rng.uniform(0.02, 0.05) * n)))
    cx, foot = int(rng.uniform(0.4, 0.6) * w), int(0.95 * h)
    fy = int(rng.uniform(0.5, 0.6) * h)
    cv2.line(m, (cx, foot), (cx, fy), 1, sw)
    for side in (-1, 1):
        tx = cx + side * int(rng.uniform(0.15, 0.25) * n)
        ty = int(rng.uniform(0.15, 0.3) * h)
        cv2.line(m, (cx, fy), (tx, ty), 1, max(2, int(0.8 * sw)))
        cv2.circle(m, (tx, ty), int(max(0.03 * n, 1.3 * sw)), 1, -1)
    obj = m > 0
    t = np.linspace(0, 1, h)[:, None, None]
    img = ((1 - t) * np.array([0.25, 0.2, 0.45]) + t * np.array([0.95, 0.6, 0.4])) * np.ones((h, w, 3))
    img[obj] = (0.12, 0.12, 0.14)
    return img.astype(np.float32), obj


def parts(kind: str, obj: np.ndarray) -> list[np.ndarray]:
    """The object's parts off its main stem, each the farther half of a component of the
    object with the stem's column band (2 stroke widths about its fullest column) taken out
    (the lamp's head, the mast's and the T's arm ends, the L's foot); for ``stem`` and
    ``fork`` the heads (the object's pixels that are deep, i.e. wider than the stem)."""
    if kind in ("pole", "wide", "I", "plain") or not obj.any():
        return []
    if kind in ("stem", "fork"):
        depth = ndimage.distance_transform_edt(obj)
        core = depth >= 0.75 * depth.max()
        lab, k = ndimage.label(core)
        return [ndimage.binary_dilation(lab == i, iterations=2) & obj for i in range(1, k + 1)]
    cols = obj.sum(0)
    cx = int(np.argmax(cols))
    rows = np.flatnonzero(obj[:, cx])
    sw = max(2, int(obj[rows[int(0.75 * (len(rows) - 1))]].sum()))  # the stem's width low down
    x = np.arange(obj.shape[1])[None, :]
    rest = obj & (np.abs(x - cx) > sw)
    lab, k = ndimage.label(rest)
    out = []
    for i in range(1, k + 1):
        comp = lab == i
        if comp.sum() < 4:
            continue
        dx = np.abs(np.nonzero(comp)[1] - cx)
        far = comp & (np.abs(x - cx) >= 0.5 * (dx.min() + dx.max()))
        out.append(far)
    return out


def side_branches(d, main: np.ndarray, least: float) -> int:
    """Subtrees leaving ``main`` (tree indices) whose farthest tip lies at least ``least``
    px (along the tree) from the fork."""
    parent = d.parent
    seg = np.zeros(d.n_nodes)
    has = parent >= 0
    seg[has] = np.hypot(*(d.points[has] - d.points[parent[has]]).T)
    order = np.argsort(_depth(parent))[::-1]
    height = np.zeros(d.n_nodes)
    for i in order:
        p = parent[i]
        if p >= 0:
            height[p] = max(height[p], height[i] + seg[i])
    on = np.zeros(d.n_nodes, bool)
    on[main] = True
    kids = np.flatnonzero(has & on[np.maximum(parent, 0)] & ~on)
    return int(((height[kids] + seg[kids]) >= least).sum())


def _depth(parent: np.ndarray) -> np.ndarray:
    dep = np.zeros(parent.size, int)
    cur = parent.copy()
    while (cur >= 0).any():
        up = cur >= 0
        dep[up] += 1
        cur[up] = parent[cur[up]]
    return dep


def measure(kind: str, n: int, seed: int, outdir: str | None = None) -> dict:
    from . import stylize
    from .main_channel import main_path

    if kind == "plain":
        img, obj = np.ones((int(0.8 * n), n, 3), np.float32), np.zeros((int(0.8 * n), n), bool)
    elif kind == "fork":
        img, obj = fork_case(n, seed)
    else:
        img, obj = thin_case(kind, n, "grad", "flat", seed)
    r = stylize(img, rng=seed, metaphor="lightning")
    d = r.dendrite
    diag = float(np.hypot(*obj.shape))
    main = main_path(d)
    pts = d.points[main]
    length = float(np.hypot(*np.diff(pts, axis=0).T).sum())
    side = side_branches(d, main, 0.02 * diag)
    q = np.concatenate([_resample(d.points[[i, d.parent[i]]], 1.0)
                        for i in np.flatnonzero(d.parent >= 0)]) if d.n_nodes > 1 else d.points
    ix = np.clip(np.rint(q[:, 0]).astype(int), 0, obj.shape[1] - 1)
    iy = np.clip(np.rint(q[:, 1]).astype(int), 0, obj.shape[0] - 1)
    hit = np.zeros(obj.shape, bool)
    hit[iy, ix] = True
    ps = parts(kind, obj)
    reach = float(np.mean([bool((hit & pm).any()) for pm in ps])) if ps else float("nan")
    if outdir:
        bolt = np.asarray(r.rendering.image, np.float32)[..., :3]
        cv2.imwrite(f"{outdir}/tb_{kind}_{n}_{seed}.png",
                    (np.clip(np.concatenate([img, bolt], 1), 0, 1)[..., ::-1] * 255).astype(np.uint8))
    return {"t10": thin_turn(d, obj) if obj.any() else turning(pts, 10.0),
            "t1%": bolt_turn(d, obj if obj.any() else np.ones(obj.shape, bool)),
            "main": turning(pts, 10.0), "side": 100.0 * side / max(length, 1e-9),
            "tips": int(len(d.tips)), "reach": reach}


def main(sizes=SIZES, seeds=(0, 1), kinds=KINDS, outdir=None) -> None:
    for n in sizes:
        for kind in (*kinds, "plain"):
            for seed in seeds:
                m = measure(kind, n, seed, outdir)
                print(f"{n:5d} {kind:5s} s{seed} t10 {m['t10']:5.1f} t1% {m['t1%']:5.1f} main {m['main']:5.1f} "
                      f"side {m['side']:4.2f} tips {m['tips']:3d} reach {m['reach']:.2f}", flush=True)


if __name__ == "__main__":
    a = sys.argv[1:]
    main(tuple(int(v) for v in a[0].split(",")) if a else SIZES,
         tuple(int(v) for v in a[1].split(",")) if len(a) > 1 else (0, 1),
         tuple(a[2].split(",")) if len(a) > 2 else KINDS,
         a[3] if len(a) > 3 else None)
