"""Measure: vines sized to the object, on the object, the same look at any size (issue 25).

``python -m branchnb.dendrite._vine_size_check [widths] [kinds] [fills] [looks] [seeds]`` draws
an object with the defaults and ``metaphor="vines"`` at each image width (200-2000 px):

* kinds: ``blob``; ``tree`` (a crown on a trunk); ``letter`` (an "E"); ``leaf`` (a lobed blade on
  a stem); ``horse`` (a body on four legs with a neck, head and tail); ``pole`` (a street lamp:
  a pole, an arm and a round head); ``pair`` (a lamp and a toadstool, two separate objects);
  ``word`` (three separate letters "L I T");
* fills: ``big`` (the object ~0.8 of the frame's height) or ``small`` (~0.3);
* looks: ``flat-plain`` (a dark flat fill on white), ``photo-plain`` (a textured, shaded fill
  on white), ``flat-grad`` (flat colours on a dusk gradient sky), ``photo-grad``;
* seeds: the shape's variation and the stylization's ``rng``.

Per case and width it prints ``s`` (the square root of the object's area, px), ``l/s`` (the leaf
length drawn over ``s``), ``tips``, ``t/P`` (tips per 100 px of outline with the image shown
at 1000 px wide: the same object should keep it across widths), ``off`` (share of the vine
ink farther than two leaf lengths from the object) and ``big`` (the largest connected piece of
that ink, its longer side over ``s``), and for kinds with a trunk or pole ``rows`` (share of
its rows with ink on it). The last line per kind gives the ratio of the smallest width's
``l/s`` and ``t/P`` to the largest's. Not a test.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage

WIDTHS = (250, 500, 1000, 2000)
KINDS = ("blob", "tree", "letter", "leaf", "horse", "pole", "pair", "word")
FILLS = ("big", "small")
LOOKS = ("flat-plain",)


def _letter(u, v, ch: str, cx: float, half: float = 0.45, bar: float = 0.07) -> np.ndarray:
    """A block letter ``ch`` (``E L I T``) of height ``2 half`` centred on ``cx``."""
    w = 0.6 * half / 0.45
    left = np.abs(u - (cx - 0.5 * w) - bar) < bar
    tall = np.abs(v) < half
    if ch == "I":
        return (np.abs(u - cx) < bar) & tall
    if ch == "T":
        return ((np.abs(u - cx) < bar) & tall) | ((np.abs(v + half - bar) < bar) & (np.abs(u - cx) < 0.5 * w))
    m = left & tall
    rows = (-half + bar, 0.0, half - bar) if ch == "E" else (half - bar,)
    for yy in rows:
        m |= (np.abs(v - yy) < bar) & (u > cx - 0.5 * w) & (u < cx + 0.5 * w - 0.05 * (yy == 0))
    return m


def shape(kind: str, n: int, fill: str, seed: int = 0) -> np.ndarray:
    """The object's mask in an ``(0.75 n, n)`` frame."""
    return shape_trunk(kind, n, fill, seed)[0]


def shape_trunk(kind: str, n: int, fill: str, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """The object's mask in an ``(0.75 n, n)`` frame and its trunk (pole, legs) mask (may be
    empty)."""
    h = int(0.75 * n)
    f = 0.8 if fill == "big" else 0.3
    y, x = np.mgrid[0:h, 0:n] / h  # unit: the frame's height
    cx, cy = 0.5 * n / h, 0.5
    u, v = (x - cx) / f, (y - cy) / f  # the object's own frame: [-0.5, 0.5]
    th = np.arctan2(v, u)
    none = np.zeros((h, n), bool)
    if kind == "blob":
        return np.hypot(u / 0.45, v / 0.4) < 1 + 0.1 * np.sin(3 * th + seed), none
    if kind == "tree":
        crown = np.hypot(u / 0.42, (v + 0.15) / 0.3) < 1 + 0.1 * np.sin(5 * th + seed)
        trunk = (np.abs(u - 0.03 * seed * v) < 0.05) & (v > 0) & (v < 0.5)
        return crown | trunk, trunk & ~crown
    if kind == "letter":
        return _letter(u, v, "E", 0.0), none
    if kind == "leaf":
        blade = np.hypot(u / 0.3, (v + 0.1) / 0.38) < 1 + 0.15 * np.cos(5 * th + 0.2 * seed)
        return blade | ((np.abs(u) < 0.015) & (v > 0.2) & (v < 0.5)), none
    if kind == "horse":
        a = 0.02 * seed
        body = np.hypot((u + 0.05) / 0.33, (v + 0.05) / 0.14) < 1
        neck = (np.abs((u - 0.3) + 0.6 * (v + 0.15)) < 0.07) & (v > -0.38) & (v < -0.02)
        head = np.hypot((u - 0.44) / 0.12, (v + 0.36 - a) / 0.06) < 1
        legs = np.zeros_like(body)
        for lx in (-0.3, -0.2, 0.1, 0.2):
            legs |= (np.abs(u - lx - 0.1 * (v - 0.05) * (lx < 0)) < 0.03) & (v > 0.0) & (v < 0.45)
        tail = (np.abs(u + 0.4 + 0.3 * (v + 0.05) ** 2 / 0.3) < 0.025) & (v > -0.1) & (v < 0.3)
        return body | neck | head | legs | tail, legs & ~body
    if kind in ("pole", "pair"):
        px = -0.25 if kind == "pair" else 0.0
        pole = (np.abs(u - px) < 0.025) & (v > -0.35) & (v < 0.5)
        arm = (np.abs((v + 0.38) + 0.45 * (u - px - 0.1)) < 0.015) & (u > px) & (u < px + 0.2)
        head = np.hypot(u - px - 0.2, v + 0.45 + 0.015 * seed) < 0.05
        m = pole | arm | head
        if kind == "pair":
            mx = 0.35 + 0.02 * seed
            cap = (np.hypot((u - mx) / 0.2, (v - 0.1) / 0.13) < 1) & (v < 0.1)
            stem = (np.abs(u - mx) < 0.04) & (v >= 0.1) & (v < 0.5)
            m = m | cap | stem
        return m, pole & (v > -0.3)
    if kind == "word":
        return (_letter(u, v, "L", -0.55, 0.3, 0.05) | _letter(u, v, "I", -0.1 + 0.02 * seed, 0.3, 0.05)
                | _letter(u, v, "T", 0.35, 0.3, 0.05)), none
    raise ValueError(f"unknown kind {kind!r}")


def picture(mask: np.ndarray, look: str, seed: int = 0) -> np.ndarray:
    """The object drawn with ``look`` (``{flat,photo}-{plain,grad}``), RGB float32."""
    h, w = mask.shape
    fill, ground = look.split("-")
    if ground == "plain":
        img = np.ones((h, w, 3))
        col = np.array([0.3, 0.3, 0.3])
    else:  # a dusk sky: dark violet at the top, light orange at the bottom
        t = np.linspace(0, 1, h)[:, None, None]
        img = (1 - t) * np.array([0.25, 0.2, 0.45]) + t * np.array([0.95, 0.6, 0.4]) * np.ones((h, w, 3))
        col = np.array([0.12, 0.12, 0.14])
    if fill == "photo":
        rng = np.random.default_rng(seed)
        tex = ndimage.gaussian_filter(rng.standard_normal((h, w)), w / 300)
        shade = np.linspace(0.8, 1.2, w)[None, :]
        obj = col[None, None] * shade[..., None] + 0.12 * (tex / max(tex.std(), 1e-9))[..., None]
        img[mask] = obj[mask]
    else:
        img[mask] = col
    return np.clip(img, 0, 1).astype(np.float32)


def off_ink(out: np.ndarray, mask: np.ndarray, leaf: float, background=None) -> tuple[float, float]:
    """Share of the vine ink farther than two leaf lengths from ``mask`` and the largest such
    connected piece's longer side (px)."""
    out = np.asarray(out, np.float32)[..., :3]
    ref = np.ones_like(out) if background is None else background
    ink = np.abs(out - ref).max(axis=2) > 0.15
    far = ndimage.distance_transform_edt(~mask) > 2.0 * leaf + 2.0
    off = ink & far
    share = float(off.sum()) / max(int(ink.sum()), 1)
    lab, n = ndimage.label(off, structure=np.ones((3, 3)))
    big = 0.0
    for sl in ndimage.find_objects(lab) if n else []:
        big = max(big, float(max(sl[0].stop - sl[0].start, sl[1].stop - sl[1].start)))
    return share, big


def rows_reached(out: np.ndarray, trunk: np.ndarray) -> float:
    """Share of the trunk's rows with vine ink on it (within 2 % of the width)."""
    lum = np.asarray(out, np.float32)[..., :3].mean(axis=2)
    near = ndimage.binary_dilation(trunk, iterations=max(1, int(0.02 * trunk.shape[1])))
    rows = np.flatnonzero(trunk.any(axis=1))
    return float(((lum < 0.7) & near)[rows].any(axis=1).mean()) if rows.size else float("nan")


def measure(img: np.ndarray, mask: np.ndarray, trunk: np.ndarray, rng: int = 0) -> dict:
    """One case's figures (see the module docstring)."""
    from . import Stylizer

    st = Stylizer(img)
    r = st.run(rng=rng, metaphor="vines")
    out = r.rendering.image
    leaf = float(st._vine_leaf)
    s = float(np.sqrt(mask.sum()))
    perim = float((mask & ~ndimage.binary_erosion(mask)).sum()) * 1000.0 / mask.shape[1]
    off, big = off_ink(out, mask, leaf)
    return {"s": s, "ls": leaf / s, "tips": len(r.dendrite.tips), "tP": 100.0 * len(r.dendrite.tips) / perim,
            "off": off, "big": big / s, "rows": rows_reached(out, trunk) if trunk.any() else float("nan")}


def main(widths=WIDTHS, kinds=KINDS, fills=FILLS, looks=LOOKS, seeds=(0,)) -> None:
    for kind in kinds:
        for fill in fills:
            for look in looks:
                for seed in seeds:
                    cells, first, last = [], None, None
                    for n in widths:
                        m, trunk = shape_trunk(kind, n, fill, seed)
                        f = measure(picture(m, look, seed), m, trunk, seed)
                        first = first or f
                        last = f
                        rows = "" if np.isnan(f["rows"]) else f" rows {f['rows']:.2f}"
                        cells.append(f"{n}: s {f['s']:.0f} l/s {f['ls']:.3f} tips {f['tips']} t/P {f['tP']:.2f} "
                                     f"off {f['off']:.3f} big {f['big']:.2f}{rows}")
                    ratio = f"l/s {first['ls'] / last['ls']:.2f} t/P {first['tP'] / last['tP']:.2f}"
                    print(f"{kind:6s} {fill:5s} {look:11s} s{seed} | " + " | ".join(cells)
                          + f" || {widths[0]}/{widths[-1]}: {ratio}", flush=True)


if __name__ == "__main__":
    a = sys.argv[1:]
    main(tuple(int(v) for v in a[0].split(",")) if a else WIDTHS,
         tuple(a[1].split(",")) if len(a) > 1 and a[1] != "all" else KINDS,
         tuple(a[2].split(",")) if len(a) > 2 and a[2] != "all" else FILLS,
         tuple(a[3].split(",")) if len(a) > 3 else LOOKS,
         tuple(int(v) for v in a[4].split(",")) if len(a) > 4 else (0,))
