"""Issue-23 figures on where river drawings are rooted (branching55).

``python -m branchnb.branching._river_outlet_check [SEEDS] [SIZES] [PNG_DIR]`` draws procedural river
networks (:func:`river_drawing`: black lines on paper, one width (``even``) or tapered from the outlet
(``taper``), their outlet on the bottom / top / left / right edge of the frame or on a coast (``coast``: a
flat sea below a drawn coast line); tributaries may leave the frame) and runs the default workflow
(``extract_structure``, ``fit_model(ex, domain=example_domain(img, ex))``, ``synthesize_structure``). Per
case it prints ``ex`` 1 when the extracted tree holding the most length is rooted within 4 % of the
frame's diagonal of the true outlet, ``side`` the share of the output's roots within 4 % of the short side
of the outlet's edge (for the coast: of the coast line), ``pos`` the mean distance of the output's roots
to the outlet (share of the diagonal) and ``len`` the length ratio; a mean per (width, edge) last.
"""
# ruff: noqa: E501, E702
from __future__ import annotations

import os
import sys

import cv2
import numpy as np

EDGES = ("bottom", "top", "left", "right", "coast")
WIDTHS = ("even", "taper")


def river_drawing(width: str, edge: str, size: int, seed: int):
    """``(image (H, W, 3) float32, outlet (x, y), coast mask or None)`` of a river network of ``size`` px."""
    rng = np.random.default_rng(900 + 17 * seed + 5 * EDGES.index(edge) + WIDTHS.index(width))
    H = W = int(size)
    s = size / 400.0
    img = np.ones((H, W), np.float32)
    coast = None
    y0 = H - 1.0
    if edge == "coast":
        xs = np.arange(W)
        cy = H * (0.8 + 0.04 * np.sin(xs / W * 2 * np.pi * rng.uniform(0.5, 1.5) + rng.uniform(0, 6)))
        coast = np.arange(H)[:, None] > cy[None, :]
    x0 = W * rng.uniform(0.35, 0.65)
    if coast is not None:
        y0 = float(np.argmax(coast[:, int(x0)])) - 1.0
    lines = []

    def grow(x, y, ang, wd, depth, n):
        pts = [(x, y)]
        a0 = ang
        for _ in range(n):
            ang += rng.normal(0, 0.07) + 0.1 * np.angle(np.exp(1j * (a0 - ang)))
            x += 2 * np.cos(ang); y += 2 * np.sin(ang)
            if not (0 <= x < W and 0 <= y < H) or (coast is not None and coast[int(y), int(x)]):
                break
            pts.append((x, y))
            if depth < 3 and len(pts) > 8 and rng.random() < 0.035:
                side = rng.choice([-1, 1])
                grow(x, y, ang + side * rng.uniform(0.5, 0.9), wd if width == "even" else max(1.0, 0.65 * wd),
                     depth + 1, int(rng.uniform(40, 90) * s))
        lines.append((pts, wd))

    grow(x0, y0, -np.pi / 2 + rng.normal(0, 0.1), 2.0 if width == "even" else 5.0, 0, int(150 * s))
    if coast is not None:
        img[coast] = 0.55
        cnt, _ = cv2.findContours(coast.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
        cv2.drawContours(img, cnt, -1, 0.1, 2)
    for pts, wd in lines:
        p = np.round(np.asarray(pts)).astype(np.int32)
        cv2.polylines(img, [p], False, 0.1, int(max(1, round(wd))), cv2.LINE_AA)
    rgb = np.dstack([img, img, img]).astype(np.float32)
    if coast is not None:
        rgb[coast] = (0.55, 0.7, 0.9)
    outlet = (x0, y0)
    turn = {"bottom": 0, "right": 1, "top": 2, "left": 3, "coast": 0}[edge]
    for _ in range(turn):            # rotate counter-clockwise: (x, y) -> (y, W - 1 - x)
        rgb = np.ascontiguousarray(np.rot90(rgb))
        outlet = (outlet[1], W - 1 - outlet[0])
    return rgb, outlet, coast


def case(width: str, edge: str, size: int, seed: int, png: str | None = None) -> dict:
    from . import example_domain, extract_structure, fit_model, synthesize_structure
    from ._thin_children_check import _draw

    img, (ox, oy), coast = river_drawing(width, edge, size, seed)
    H, W = img.shape[:2]
    diag = float(np.hypot(H, W))
    ex = extract_structure(img)
    # the tree holding the most length
    tree_len: dict[int, float] = {}
    for i, b in enumerate(ex.branches):
        t = i
        while ex.branches[t].parent is not None:
            t = int(ex.branches[t].parent)
        tree_len[t] = tree_len.get(t, 0.0) + float(np.hypot(*np.diff(b.points, axis=0).T).sum())
    main = max(tree_len, key=tree_len.get) if tree_len else None
    ok_ex = main is not None and float(np.hypot(*(ex.branches[main].points[0] - (ox, oy)))) < 0.04 * diag
    model = fit_model(ex, domain=example_domain(img, ex))
    res = synthesize_structure(model, rng=seed)
    roots = [np.asarray(b.points[0], float) for b in res.structure.branches if b.parent is None and len(b.points) >= 2]
    lim = 0.04 * min(H, W)
    if edge == "coast":
        from scipy import ndimage as ndi
        dc = ndi.distance_transform_edt(~coast)
        hit = [dc[int(np.clip(p[1], 0, H - 1)), int(np.clip(p[0], 0, W - 1))] <= lim for p in roots]
    else:
        d = {"top": lambda p: p[1], "bottom": lambda p: H - 1 - p[1], "left": lambda p: p[0], "right": lambda p: W - 1 - p[0]}[edge]
        hit = [d(p) <= lim for p in roots]
    pos = [float(np.hypot(p[0] - ox, p[1] - oy)) / diag for p in roots]
    if png:
        out = _draw(res.structure, img.shape[:2])
        exi = _draw(ex, img.shape[:2])
        for b in ex.branches:
            if b.parent is None:
                cv2.circle(exi, tuple(int(v) for v in np.round(b.points[0])), 6, (1.0, 0.0, 0.0), 2)
        for p in roots:
            cv2.circle(out, tuple(int(v) for v in np.round(p)), 6, (1.0, 0.0, 0.0), 2)
        cv2.imwrite(png, (np.hstack([img, exi, out]) * 255).astype(np.uint8)[..., ::-1])
    return {"ex": float(ok_ex), "side": float(np.mean(hit)) if hit else 0.0, "pos": float(np.mean(pos)) if pos else 1.0,
            "len": res.structure.total_length / max(ex.total_length, 1e-9), "n": len(roots)}


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    seeds = [int(s) for s in argv[0].split(",")] if argv else [0, 1]
    sizes = [int(s) for s in argv[1].split(",")] if len(argv) > 1 else [256, 512, 768]
    pngdir = argv[2] if len(argv) > 2 else None
    if pngdir:
        os.makedirs(pngdir, exist_ok=True)
    keys = ("ex", "side", "pos", "len")
    for width in WIDTHS:
        for edge in EDGES:
            rows = []
            for k, seed in enumerate(seeds):
                size = sizes[(k + EDGES.index(edge)) % len(sizes)]
                png = os.path.join(pngdir, f"{width}_{edge}_{size}_{seed}.png") if pngdir else None
                r = case(width, edge, size, seed, png)
                rows.append(r)
                print(f"{width:5s} {edge:6s} {size:4d} {seed}  roots {r['n']} " + " ".join(f"{k}={r[k]:.2f}" for k in keys), flush=True)
            print(f"MEAN {width:5s} {edge:6s} " + " ".join(f"{k}={np.mean([r[k] for r in rows]):.2f}" for k in keys), flush=True)


if __name__ == "__main__":
    main()
