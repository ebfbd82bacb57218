"""Carried parts where a stroke bends their parent: overlap, joints and time, as a table (not a test).

``python -m branchnb.strokes._fan_check [KINDS] [SIZES] [SEEDS] [--png DIR]`` builds
procedural multi-part objects (``frond``: a curved rachis with leaflets on both
sides; ``twig``: a twig with broad leaves on petioles, alternating), bends
their one stroke strongly one way and the other (``+``, ``-``) and prints per
edit: how many parts are carried, the overlap between carried parts (the
share of their pixels lying on another carried part, where the parts are
placed; the source's own share in brackets), the joints (carried parts
whose placed pixels come within 1 px of the parent's target silhouette, and
the result's pieces) and the CPU time of the edit. ``fern`` (a real frond,
``shared/data/leaves_more/fern_frond.png``) is measured when it exists.
"""

from __future__ import annotations

import os
import sys
import time

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.random import as_rng
from .edit import edit_structure, fetch_patches
from .procedural import PartObject, _Canvas, _leaf

__all__: list[str] = []

_FERN = os.environ.get("FERN", "/work/shared/data/leaves_more/fern_frond.png")


def _frond(size: int, n: int, rng, *, kind: str = "frond") -> PartObject:
    """A frond (``n`` narrow leaflets, both sides) or a twig (``n`` broad leaves, alternating)."""
    rng = as_rng(rng)
    h = int(size)
    w = int(size)
    k = size / 1000.0
    c = _Canvas(h, w, outline=max(1.0, 2.0 * k), rng=rng)
    t = np.linspace(0.0, 1.0, 60)
    bow = rng.uniform(-0.08, 0.08)
    spine = np.c_[0.5 * w + bow * w * np.sin(np.pi * t), (0.95 - 0.88 * t) * h]
    hw = (7.0 if kind == "frond" else 11.0) * k
    sdf, s = c.capsule(spine, hw, taper=0.5)
    rgb = np.broadcast_to(np.array([0.30, 0.45, 0.15]), (h, w, 3)) + c.noise(30 * k, 0.03)[..., None]
    c.part(spine, "rachis", -1, hw, (sdf, rgb, 3))
    seg = np.diff(spine, axis=0)
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*seg.T))])
    fr = np.linspace(0.12, 0.93, n)
    for j, f in enumerate(fr):
        side = (1 if j % 2 else -1)
        a = np.array([np.interp(f * arc[-1], arc, spine[:, 0]), np.interp(f * arc[-1], arc, spine[:, 1])])
        i = min(int(np.searchsorted(arc, f * arc[-1])), len(seg) - 1)
        d = seg[i] / np.hypot(*seg[i])
        nrm = np.array([-d[1], d[0]]) * side
        gap = 0.81 * arc[-1] / (n / 2.0)  # between leaflets on one side
        if kind == "frond":
            ang = np.radians(rng.uniform(55, 70))
            length = (0.36 - 0.22 * f) * h * rng.uniform(0.9, 1.1)
            stalk = 3 * k
        else:
            ang = np.radians(rng.uniform(40, 55))
            length = 0.20 * h * rng.uniform(0.85, 1.1)
            stalk = 25 * k
        # narrow enough that neighbours on one side stay apart in the source
        half = min((0.13 if kind == "frond" else 0.3) * length, 0.3 * gap * np.sin(ang))
        u = np.cos(ang) * d + np.sin(ang) * nrm
        base = a + (hw + stalk) * u
        _, st = _leaf(c, base, base + length * u, half, a, max(1.5, 3.0 * k), 1)
        c.part(st, f"leaf {j + 1}", 0, half)
    return c.result()


def _bent(spine: np.ndarray, turn: float) -> np.ndarray:
    """``spine`` (same length and start) turning steadily by ``turn`` rad more along its length."""
    seg = np.diff(spine, axis=0)
    ang = np.unwrap(np.arctan2(seg[:, 1], seg[:, 0])) + turn * np.linspace(0.0, 1.0, len(seg)) ** 1.5
    ln = np.hypot(*seg.T)
    step = np.c_[np.cos(ang), np.sin(ang)] * ln[:, None]
    return np.vstack([spine[:1], spine[0] + np.cumsum(step, axis=0)])


def _fern(size: int):
    img = cv2.imread(_FERN, cv2.IMREAD_UNCHANGED)
    if img is None:
        return None
    img = img.astype(np.float32) / 255.0
    h0, w0 = img.shape[:2]
    f = size / h0
    img = cv2.resize(img, (int(round(w0 * f)), int(size)), interpolation=cv2.INTER_AREA)
    rgba = np.concatenate([img[..., 2::-1], img[..., 3:]], -1)
    g = size / 511.0
    src = np.array([(213, 455), (190, 380), (163, 280), (160, 200), (175, 80), (205, 8)], float) * g
    tgt = np.array([(213, 455), (225, 380), (230, 280), (215, 190), (180, 90), (130, 20)], float) * g
    return rgba, src, tgt


def _measure(image, src, tgt, *, fan: bool = True) -> dict:
    """Overlap of the carried parts, joints and CPU time of one edit."""
    from . import synthesis

    saved = synthesis._fanned_maps
    if not fan:
        synthesis._fanned_maps = _rigid_maps
    try:
        t0 = time.process_time()
        res = edit_structure(image, [src], [tgt])
        cpu = time.process_time() - t0
        patches = fetch_patches(image, [src], [tgt])
        maps = synthesis._fanned_maps(patches._index, patches.attached, patches._carried, patches._window)
    finally:
        synthesis._fanned_maps = saved
    index = patches._index
    shape = res.image.shape[:2]
    count = np.zeros(shape, np.int32)
    count_src = np.zeros(index.shape, np.int32)
    area = 0
    masks = []
    for (_, pi, _), m in zip(patches._carried, maps):
        part = index.parts[pi]
        (rs, cs) = part.box
        mm = m.copy()
        mm[:, 2] += mm[:, :2] @ np.array([cs.start, rs.start], float)
        placed = cv2.warpAffine(part.mask.astype(np.uint8), mm, (shape[1], shape[0]),
                                flags=cv2.INTER_NEAREST).astype(bool)
        count += placed
        count_src[rs, cs] += part.mask
        area += int(part.mask.sum())
        masks.append(placed)
    over = float((count - 1).clip(0).sum() / max(area, 1))
    over_src = float((count_src - 1).clip(0).sum() / max(area, 1))
    alpha = res.image[..., 3] > 0.5
    pieces = int(ndi.label(alpha, structure=np.ones((3, 3)))[1])
    # a part is joined when its placed pixels lie within 1 px of the parent's silhouette
    # (the result without any carried part's own pixels: the rachis and the strokes' patches)
    others = alpha & ~(count > 0)
    near = ndi.binary_dilation(others, iterations=2)
    joined = sum(bool((m & near).any()) for m in masks)
    return dict(parts=len(masks), overlap=over, overlap_src=over_src, joined=joined, pieces=pieces, cpu=cpu,
                image=res.image)


def _rigid_maps(index, attached, carried, window):
    from .parts import rigid_frame

    return [rigid_frame(attached[i].source, attached[i].target, index.parts[pi].s, s_t, window=window)
            for i, pi, s_t in carried]


def _cases(kinds, sizes, seeds):
    for kind in kinds:
        for size in sizes:
            if kind == "fern":
                got = _fern(size)
                if got is not None:
                    yield f"fern {size}", got[0], got[1], got[2]
                continue
            for seed in seeds:
                n = {"frond": 16 + 8 * seed, "twig": 8 + 2 * seed}[kind]
                obj = _frond(size, n, seed, kind=kind)
                for sign in (1, -1):
                    yield (f"{kind} {size} n{n} s{seed} {'+-'[sign < 0]}", obj.image, obj.strokes[0],
                           _bent(obj.strokes[0], sign * np.radians(100.0)))


def main(argv=None) -> None:
    argv = list(sys.argv[1:] if argv is None else argv)
    png = None
    if "--png" in argv:
        j = argv.index("--png")
        png = argv[j + 1]
        del argv[j:j + 2]
        os.makedirs(png, exist_ok=True)
    kinds = argv[0].split(",") if argv else ["frond", "twig", "fern"]
    sizes = [int(v) for v in argv[1].split(",")] if len(argv) > 1 else [300, 600, 1000]
    seeds = [int(v) for v in argv[2].split(",")] if len(argv) > 2 else [0, 1]
    print("case | parts | overlap rigid -> fanned (source) | joined rigid -> fanned | pieces | cpu rigid, fanned")
    for name, img, src, tgt in _cases(kinds, sizes, seeds):
        a = _measure(img, src, tgt, fan=False)
        b = _measure(img, src, tgt, fan=True)
        print(f"{name:24s} | {a['parts']:3d} | {a['overlap']:.3f} -> {b['overlap']:.3f} ({a['overlap_src']:.3f}) | "
              f"{a['joined']}/{a['parts']} -> {b['joined']}/{b['parts']} | {a['pieces']} -> {b['pieces']} | "
              f"{a['cpu']:.2f}, {b['cpu']:.2f}", flush=True)
        if png:
            from ..core.image import composite_over

            def rgb(x):
                return (np.clip(composite_over(x)[..., :3], 0, 1) * 255).astype(np.uint8)[..., ::-1]

            row = np.concatenate([rgb(img), rgb(a["image"]), rgb(b["image"])], 1)
            cv2.imwrite(os.path.join(png, name.replace(" ", "_").replace("+", "p").replace("-", "m") + ".png"),
                        row)


if __name__ == "__main__":
    main()
