"""Measure: vine leaves sized to the object, tips following its outline (issue 25), defaults.

``python -m branchnb.dendrite._vine_size_check [widths] [kinds] [fills]`` draws an object (``blob``,
``tree``: a crown on a trunk, ``letter``: an outlined-stroke "E", ``leaf``: a lobed blade on a
stem) dark on white, filling the frame (``big``: ~0.8 of its height) or small in it (``small``:
~0.3), at each image width (200-2000 px), stylizes it with ``metaphor="vines"`` and prints per
case the object's size ``s`` (square root of its area, px), the leaf length drawn (px) over
``s``, the tips drawn and the tips per outline length in leaf lengths (``tips / (P / leaf)``).
Leaves sized to the object keep ``leaf/s`` across widths and fills; tips following the outline
keep ``tips/(P/leaf)`` near one value across kinds. Not a test.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage

WIDTHS = (200, 500, 1000, 2000)
KINDS = ("blob", "tree", "letter", "leaf")
FILLS = ("big", "small")


def shape(kind: str, n: int, fill: str, seed: int = 0) -> np.ndarray:
    """The object's mask in an ``(0.75 n, n)`` frame."""
    h = int(0.75 * n)
    f = 0.8 if fill == "big" else 0.3
    y, x = np.mgrid[0:h, 0:n] / h  # unit: the frame's height
    cx, cy = 0.5 * n / h, 0.5
    u, v = (x - cx) / f, (y - cy) / f  # the object's own frame: [-0.5, 0.5]
    th = np.arctan2(v, u)
    if kind == "blob":
        return np.hypot(u / 0.45, v / 0.4) < 1 + 0.1 * np.sin(3 * th + seed)
    if kind == "tree":
        crown = np.hypot(u / 0.42, (v + 0.15) / 0.3) < 1 + 0.1 * np.sin(5 * th + seed)
        return crown | ((np.abs(u) < 0.05) & (v > 0) & (v < 0.5))
    if kind == "letter":
        bar = 0.07
        e = (np.abs(u + 0.3) < bar) & (np.abs(v) < 0.45)
        for yy in (-0.38, 0.0, 0.38):
            e |= (np.abs(v - yy) < bar) & (u > -0.3) & (u < 0.3 - 0.05 * (yy == 0))
        return e
    if kind == "leaf":
        blade = np.hypot(u / 0.3, (v + 0.1) / 0.38) < 1 + 0.15 * np.cos(5 * th)
        return blade | ((np.abs(u) < 0.015) & (v > 0.2) & (v < 0.5))
    raise ValueError(f"unknown kind {kind!r}")


def main(widths=WIDTHS, kinds=KINDS, fills=FILLS) -> None:
    from . import Stylizer
    from .metaphors import vine_length

    for kind in kinds:
        for fill in fills:
            cells = []
            for n in widths:
                m = shape(kind, n, fill)
                img = np.where(m, 0.3, 1.0).astype(np.float32)
                img = np.repeat(img[..., None], 3, axis=2)
                st = Stylizer(img)
                r = st.run(rng=0, metaphor="vines")
                leaf = getattr(st, "_vine_leaf", None) or vine_length("leaf_length", m.shape)
                s = float(np.sqrt(m.sum()))
                perim = float((m & ~ndimage.binary_erosion(m)).sum())
                tips = len(r.dendrite.tips)
                cells.append(f"{n}: s {s:.0f} leaf/s {leaf / s:.3f} tips {tips} t/(P/l) {tips / (perim / leaf):.2f}")
            print(f"{kind:6s} {fill:5s} | " + " | ".join(cells), flush=True)


if __name__ == "__main__":
    a = sys.argv[1:]
    main(tuple(int(v) for v in a[0].split(",")) if a else WIDTHS,
         tuple(a[1].split(",")) if len(a) > 1 else KINDS,
         tuple(a[2].split(",")) if len(a) > 2 else FILLS)
