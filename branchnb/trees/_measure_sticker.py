"""Sticker trees (dark outline inside a light die-cut border) in mixes: before -> after (issue 24, trees41).

``python -m branchnb.trees._measure_sticker [size] [--png DIR]`` builds procedural sticker exemplars
(white, cream and coloured borders 2-12 px; dark and coloured outlines 1-5 px; flat, dotted, striped
and gradient fills; round, triangle and cloud crowns; 200-1000 px), mixes them with
``TreeLibrary(size).variation`` with the sticker rebuild off (before) and on (after), and prints per
library: the share of the mix's rim inside the border with the outline colour within 1 px, the border
width (area / rim length) against the exemplars' and the outline width, and the dark specks per mix
(ink-coloured pieces under 12 px off the outline ring). Plain outlined and borderless
libraries are mixed too: they must come out byte-identical.
"""

from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage as ndi

from . import variations as _V
from .library import TreeLibrary
from .sticker import _sticker_border

_INKS = [(0.1, 0.08, 0.08), (0.15, 0.1, 0.35), (0.45, 0.1, 0.1)]
_BORDERS = [(1.0, 1.0, 1.0), (0.97, 0.93, 0.8), (0.7, 0.85, 1.0)]
_CROWNS = [(0.85, 0.3, 0.25), (0.2, 0.55, 0.35), (0.95, 0.7, 0.2), (0.35, 0.45, 0.75)]


def sticker_tree(
    size: int,
    seed: int,
    *,
    border: int | None = 6,
    outline: int | None = 3,
    border_colour=(1.0, 1.0, 1.0),
    ink=(0.1, 0.08, 0.08),
    fill: str = "dots",
) -> np.ndarray:
    """A procedural sticker tree (straight RGBA): ``border``/``outline`` None leave that ring out."""
    r = np.random.default_rng(seed)
    h = w = size
    rgb = np.ones((h, w, 3), np.float32)
    m = np.zeros((h, w), np.uint8)
    cx = w // 2 + int(r.integers(-w // 30, w // 30 + 1))
    tw = int(w * r.uniform(0.035, 0.06))
    cv2.rectangle(m, (cx - tw, int(h * 0.55)), (cx + tw, h - 12 - (border or 0)), 1, -1)
    kind = seed % 3
    cy = int(h * r.uniform(0.34, 0.4))
    if kind == 0:
        cv2.ellipse(m, (cx, cy), (int(w * r.uniform(0.25, 0.34)), int(h * r.uniform(0.22, 0.3))), 0, 0, 360, 2, -1)
    elif kind == 1:
        top = int(h * 0.06) + (border or 0) + (outline or 0)
        sp = int(w * r.uniform(0.22, 0.32))
        cv2.fillPoly(m, [np.int32([[cx, top], [cx - sp, int(h * 0.68)], [cx + sp, int(h * 0.68)]])], 2)
    else:
        rr = r.uniform(0.11, 0.15)
        for a in np.linspace(0, 2 * np.pi, 7)[:-1]:
            cv2.circle(m, (int(cx + w * 0.17 * np.cos(a)), int(cy + h * 0.14 * np.sin(a))), int(w * rr), 2, -1)
        cv2.circle(m, (cx, cy), int(w * 0.18), 2, -1)
    col = np.array(_CROWNS[seed % 4], np.float32)
    rgb[m == 1] = (0.45, 0.28, 0.15)
    rgb[m == 2] = col
    yy, xx = np.mgrid[:h, :w]
    if fill == "dots":
        dots = ((xx % (w // 12) - w // 24) ** 2 + (yy % (h // 12) - h // 24) ** 2) < (w // 60) ** 2
        rgb[(m == 2) & dots] = np.clip(col * 1.35 + 0.1, 0, 1)
    elif fill == "stripes":
        rgb[(m == 2) & (((xx + yy) // (w // 16)) % 2 == 0)] = np.clip(col * 0.75, 0, 1)
    elif fill == "gradient":
        t = (yy / h)[..., None].astype(np.float32)
        rgb = np.where((m == 2)[..., None], np.clip(col * (1.2 - 0.5 * t), 0, 1), rgb)
    obj = (m > 0).astype(np.uint8)
    k = np.ones((3, 3), np.uint8)
    full = obj
    if outline:
        full = cv2.dilate(obj, k, iterations=outline)
        rgb[(full > 0) & (obj == 0)] = ink
    alpha_m = full
    if border:
        alpha_m = cv2.dilate(full, k, iterations=border)
        rgb[(alpha_m > 0) & (full == 0)] = border_colour
    a = cv2.GaussianBlur(alpha_m.astype(np.float32), (0, 0), 0.7)
    return np.dstack([rgb, a]).astype(np.float32)


def _libraries():
    """(name, kind, [exemplars], ink, border colour): stickers of varied rings, and controls."""
    libs = []
    fills = ["dots", "stripes", "flat", "gradient"]
    specs = [  # size, border, outline, border colour, ink
        (400, 8, 3, 0, 0),
        (200, 3, 1, 1, 0),
        (700, 12, 5, 2, 1),
        (1000, 10, 3, 0, 2),
        (300, 2, 2, 1, 1),
    ]
    for j, (size, b, o, bc, ik) in enumerate(specs):
        ex = [
            sticker_tree(
                size,
                10 * j + s,
                border=b,
                outline=o,
                border_colour=_BORDERS[bc],
                ink=_INKS[ik],
                fill=fills[(j + s) % 4],
            )
            for s in range(3)
        ]
        libs.append((f"sticker{size}_b{b}_o{o}", "sticker", ex, _INKS[ik], _BORDERS[bc]))
    libs.append(
        ("outlined400", "control", [sticker_tree(400, s, border=None, outline=3) for s in range(3)], None, None)
    )
    libs.append(
        ("borderless400", "control", [sticker_tree(400, s, border=None, outline=None) for s in range(3)], None, None)
    )
    return libs


def _rings(img: np.ndarray, ink, border_colour) -> tuple[float, float, float]:
    """(outline coverage of the rim inside the border, border width, outline width) of an RGBA image."""
    alpha = img[..., 3] >= 0.5
    depth = ndi.distance_transform_edt(alpha)
    rim = alpha & (depth < 1.5)
    rgb = img[..., :3]
    near_b = alpha & (np.linalg.norm(rgb - np.asarray(border_colour), axis=2) <= 0.2)
    lab, _ = ndi.label(near_b, structure=np.ones((3, 3), bool))
    ids = np.unique(lab[rim & near_b])
    ring = np.isin(lab, ids[ids > 0])
    # the anti-aliased step between border and outline belongs to neither
    ring = ndi.binary_dilation(ring, structure=np.ones((3, 3), bool)) & alpha
    inner = alpha & ~ring
    di = ndi.distance_transform_edt(inner)
    irim = inner & (di < 1.5)
    ink_px = inner & (np.linalg.norm(rgb - np.asarray(ink), axis=2) <= 0.25)
    # covered: ink 2-3 px deep within 2 px (a 1 px dark fringe of the old mixes does not count)
    deep = ink_px & (di >= 1.5) & (di < 3.5)
    near_ink = ndi.binary_dilation(deep, structure=np.ones((5, 5), bool))
    cover = float(near_ink[irim].mean()) if irim.any() else 0.0
    n_rim = max(int(rim.sum()), 1)
    bw = float(ring.sum()) / n_rim
    lab2, _ = ndi.label(ink_px & (di <= 12), structure=np.ones((3, 3), bool))
    ids2 = np.unique(lab2[ink_px & irim])
    ow = float(np.isin(lab2, ids2[ids2 > 0]).sum()) / max(int(irim.sum()), 1)
    return cover, bw, ow


def _inner(img: np.ndarray, border_colour) -> tuple[np.ndarray, np.ndarray]:
    """The mix without its border ring (and the anti-aliased step next to it), and the depth inside that."""
    alpha = img[..., 3] >= 0.5
    depth = ndi.distance_transform_edt(alpha)
    rgb = img[..., :3]
    near_b = alpha & (np.linalg.norm(rgb - np.asarray(border_colour), axis=2) <= 0.2)
    lab, _ = ndi.label(near_b, structure=np.ones((3, 3), bool))
    ids = np.unique(lab[alpha & (depth < 1.5) & near_b])
    ring = ndi.binary_dilation(np.isin(lab, ids[ids > 0]), structure=np.ones((3, 3), bool)) & alpha
    inner = alpha & ~ring
    return inner, ndi.distance_transform_edt(inner)


def _specks(img: np.ndarray, ink, border_colour) -> int:
    """Dark (ink-coloured, within 0.3) pieces under 12 px inside the border not touching the outline
    ring: the warped outline's remnants at the crown's notches and sides (trees55)."""
    inner, di = _inner(img, border_colour)
    dark = inner & (np.linalg.norm(img[..., :3] - np.asarray(ink), axis=2) <= 0.3)
    lab, n = ndi.label(dark, structure=np.ones((3, 3), bool))
    if not n:
        return 0
    idx = np.arange(1, n + 1)
    sizes = np.asarray(ndi.sum(dark, lab, idx))
    on = np.asarray(ndi.maximum(ndi.binary_dilation(inner & (di < 1.5), structure=np.ones((3, 3), bool)), lab, idx))
    return int(((sizes < 12) & (on == 0)).sum())


def _bands(img: np.ndarray, ink, border_colour, width: float) -> tuple[float, float]:
    """(share of the pixels less than ``width`` deep in the border colour, share of the 1 px band
    2 px inside the border in the ink colour): the two rings rebuilt where they belong."""
    alpha = img[..., 3] >= 0.5
    depth = ndi.distance_transform_edt(alpha)
    rgb = img[..., :3]
    outer = alpha & (depth < width - 0.5)
    band = alpha & (depth > width + 1.5) & (depth <= width + 2.5)
    b = float((np.linalg.norm(rgb[outer] - np.asarray(border_colour), axis=1) <= 0.2).mean())
    k = float((np.linalg.norm(rgb[band] - np.asarray(ink), axis=1) <= 0.3).mean())
    return b, k


def main(size: int = 256, n_mix: int = 3, png: str | None = None) -> None:
    orig = _V._sticker_mix
    print(f"TreeLibrary(size={size}), {n_mix} mixes per library (means; min over mixes in brackets)")
    print("ring = border-coloured share of the border ring; band = ink share 2 px inside the border;")
    print("cover = inner rim share with ink 2-3 px deep within 2 px; widths: area / rim length")
    for name, kind, exs, ink, bc in _libraries():
        lib = TreeLibrary(size=size)
        for i, e in enumerate(exs):
            lib.add(e, f"{name}_{i}")
        res = {}
        for tag, fn in (("old", lambda *a, **k: None), ("new", orig)):
            _V._sticker_mix = fn
            res[tag] = [np.asarray(lib.variation(rng=s).image, np.float32) for s in range(n_mix)]
        _V._sticker_mix = orig
        same = all(np.array_equal(a, b) for a, b in zip(res["old"], res["new"], strict=True))
        if kind == "control":
            det = sum(_sticker_border(lib[n].image) is not None for n in lib.names)
            print(f"{name:22s} control: detected {det} of {len(exs)}, mixes byte-identical {same}")
            continue
        bw = float(np.mean([_sticker_border(lib[n].image).width for n in lib.names]))
        line = [f"{name:22s}"]
        for tag in ("old", "new"):
            bands = np.array([_bands(v, ink, bc, bw) for v in res[tag]])
            rings = np.array([_rings(v, ink, bc) for v in res[tag]])
            line.append(f"{tag}: ring {bands[:, 0].mean():.3f} ({bands[:, 0].min():.3f}) band {bands[:, 1].mean():.3f}"
                        f" ({bands[:, 1].min():.3f}) cover {rings[:, 0].mean():.3f} border {rings[:, 1].mean():.2f}"
                        f" outline {rings[:, 2].mean():.2f}"
                        f" specks {np.mean([_specks(v, ink, bc) for v in res[tag]]):.1f}")
        ex = np.array([_rings(lib[n].image, ink, bc) for n in lib.names]).mean(0)
        line.append(f"exemplars: border {ex[1]:.2f} outline {ex[2]:.2f}")
        print("\n    ".join(line))
        if png:
            def on(a):
                return a[..., :3] * a[..., 3:] + 0.7 * (1 - a[..., 3:])
            rows = [np.concatenate([on(v) for v in res[t]], 1) for t in ("old", "new")]
            cv2.imwrite(f"{png}/{name}.png", (np.clip(np.concatenate(rows, 0), 0, 1)[..., ::-1] * 255).astype(np.uint8))


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    out = sys.argv[sys.argv.index("--png") + 1] if "--png" in sys.argv else None
    if out in args:
        args.remove(out)
    main(int(args[0]) if args else 256, png=out)
