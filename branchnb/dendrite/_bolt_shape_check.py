"""Measure: a lightning bolt's main channel on an object is as jagged as on a plain canvas (issue 25).

``python -m branchnb.dendrite._bolt_shape_check [sizes] [seeds] [kinds]`` stylizes, with the
defaults and ``metaphor="lightning"``, procedural objects (``sky``/``dark``/``white``: a tree with a
lobed textured crown on a leaning trunk, :func:`~branchnb.dendrite._trunk_check.tree`; ``blob``:
a dark blob on white; ``letter``: an outlined-stroke "E"; ``flat``: a uniformly filled tree on
white) and a plain canvas (``plain``: a white picture, the no-object reference) and prints per
case the main channel's tortuosity (path length / chord), its mean absolute turning angle (deg)
on samples every 10 px and every 5 % of the object's size (the square root of its bounding
box's area; the picture's for ``plain``), and the share of the channel's pixels inside the
object's mask (``in``) and inside the trunk of a tree below its crown (``trunk``). With
``vines`` as a fourth argument it prints instead the share of the vines' ink (darkness > 0.3)
farther than 2 % of the width off the object (``off``; a tree's ground drawn as a stem). Not a
test.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage

SIZES = (250, 500, 1000)
KINDS = ("plain", "sky", "dark", "white", "flat", "blob", "letter")


def _resample(pts: np.ndarray, step: float) -> np.ndarray:
    seg = np.hypot(*np.diff(pts, axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    if s[-1] < 2 * step:
        return pts[[0, -1]]
    t = np.arange(0.0, s[-1], step)
    return np.column_stack([np.interp(t, s, pts[:, 0]), np.interp(t, s, pts[:, 1])])


def turning(pts: np.ndarray, step: float) -> float:
    """Mean absolute turning angle (deg) of the polyline resampled every ``step`` px."""
    q = _resample(np.asarray(pts, float), step)
    d = np.diff(q, axis=0)
    if len(d) < 2:
        return 0.0
    a = np.arctan2(d[:, 1], d[:, 0])
    return float(np.degrees(np.abs(np.angle(np.exp(1j * np.diff(a))))).mean())


def tortuosity(pts: np.ndarray) -> float:
    pts = np.asarray(pts, float)
    chord = float(np.hypot(*(pts[-1] - pts[0])))
    return float(np.hypot(*np.diff(pts, axis=0).T).sum()) / max(chord, 1e-9)


def case(kind: str, n: int, seed: int):
    """RGB image, object mask (None on the plain canvas), trunk mask (or None)."""
    from ._trunk_check import tree
    from ._vine_size_check import shape

    if kind == "plain":
        return np.ones((int(0.8 * n), n, 3), np.float32), None, None
    if kind in ("sky", "dark", "white"):
        return tree(n, seed, kind)
    if kind == "flat":
        img, obj, trunk = tree(n, seed, "white")
        img[obj] = (0.2, 0.45, 0.15)
        return img, obj, trunk
    obj = shape("blob" if kind == "blob" else "letter", n, "big", seed)
    rng = np.random.default_rng(seed)
    tex = ndimage.gaussian_filter(rng.standard_normal(obj.shape), n / 200)
    img = np.ones(obj.shape + (3,), np.float32)
    img[obj] = np.clip(0.25 + 0.1 * tex[obj] / max(tex.std(), 1e-9), 0, 1)[:, None]
    return img, obj, None


def measure(kind: str, n: int, seed: int) -> dict:
    from . import stylize
    from .main_channel import main_path

    img, obj, trunk = case(kind, n, seed)
    d = stylize(img, rng=seed, metaphor="lightning").dendrite
    pts = d.points[main_path(d)]
    if obj is None:
        size = float(np.sqrt(img.shape[0] * img.shape[1]))
    else:
        ys, xs = np.nonzero(obj)
        size = float(np.sqrt(np.ptp(xs + 1) * np.ptp(ys + 1)))
    q = _resample(pts, 1.0)
    ix = np.clip(np.rint(q[:, 0]).astype(int), 0, img.shape[1] - 1)
    iy = np.clip(np.rint(q[:, 1]).astype(int), 0, img.shape[0] - 1)
    out = {"tort": tortuosity(pts), "t10": turning(pts, 10.0), "t5": turning(pts, 0.05 * size),
           "in": float("nan"), "trunk": float("nan")}
    if obj is not None:
        out["in"] = float(obj[iy, ix].mean())
    if trunk is not None:
        below = iy > np.flatnonzero((obj & ~trunk).any(axis=1)).max()
        if below.any():
            near = ndimage.binary_dilation(trunk, iterations=1)
            out["trunk"] = float(near[iy[below], ix[below]].mean())
    return out


def vine_off(kind: str, n: int, seed: int) -> float:
    """Share of the vines' ink farther than 2 % of the width off the object."""
    from . import stylize

    img, obj, _ = case(kind, n, seed)
    out = np.asarray(stylize(img, rng=seed, metaphor="vines").rendering.image, np.float32)
    ink = out[..., :3].mean(axis=2) < 0.7
    near = ndimage.distance_transform_edt(~obj) <= 0.02 * n
    return float((ink & ~near).sum()) / max(int(ink.sum()), 1)


def main(sizes=SIZES, seeds=(0, 1), kinds=KINDS, vines: bool = False) -> None:
    if vines:
        for kind in kinds:
            for n in sizes:
                cells = [f"s{seed} off {vine_off(kind, n, seed):.3f}" for seed in seeds]
                print(f"{kind:6s} {n:5d} | " + " | ".join(cells), flush=True)
        return
    for kind in kinds:
        for n in sizes:
            cells = []
            for seed in seeds:
                m = measure(kind, n, seed)
                cells.append(f"s{seed} tort {m['tort']:.2f} t10 {m['t10']:4.1f} t5% {m['t5']:4.1f} "
                             f"in {m['in']:.2f} trunk {m['trunk']:.2f}")
            print(f"{kind:6s} {n:5d} | " + " | ".join(cells), flush=True)


if __name__ == "__main__":
    a = sys.argv[1:]
    main(tuple(int(v) for v in a[0].split(",")) if a else SIZES,
         tuple(int(v) for v in a[1].split(",")) if len(a) > 1 else (0, 1),
         tuple(a[2].split(",")) if len(a) > 2 else KINDS, len(a) > 3 and a[3] == "vines")
