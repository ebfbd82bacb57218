"""Issue-23 figures on synthesized trunks that hug the frame (branching82).

``python -m branchnb.branching._frame_hug_check [SEEDS] [KINDS] [PNG_DIR] [SIZES] [DOMAIN]`` paints
procedural trees entering from one frame edge (:func:`hug_example`: 2-3 roots, 3-4 generations, widths
tapering; ``roots`` dark on soil from the top, ``river`` blue on land from the bottom, ``bolt`` bright on
a night sky from the top), runs the default workflow (``extract_structure``, ``fit_model`` with
``domain=example_domain(img, ex)`` when DOMAIN=1, else without, ``synthesize_structure``) and prints per
case: ``fx`` / ``fq`` the example's (truth) / output's share of branch length within :data:`FRAME_PX` px
of the frame (the first 2 radii of each root left out), ``lim`` the bound ``2 fx + 0.01``, ``dev`` the
output's main branch's (longest root's) net bearing off the example's mean root bearing (degrees),
``nb`` the number of output branches.
"""
# ruff: noqa: E501, E702
from __future__ import annotations

import sys

import cv2
import numpy as np

KINDS = ("roots", "river", "bolt")
SIZES = (256, 512, 768)
#: Distance (pixels) to the frame under which a line runs along it.
FRAME_PX = 6.0
_SIDE = {"roots": "top", "river": "bottom", "bolt": "top"}


def _orient_pts(p: np.ndarray, side: str, N: int) -> np.ndarray:
    """Points drawn entering from the top, turned to enter from ``side`` (only top and bottom here)."""
    p = np.asarray(p, np.float64).copy()
    if side == "bottom":
        p[:, 1] = N - 1 - p[:, 1]
    return p


def hug_example(kind: str, N: int, seed: int):
    """``(image (N, N, 3) float32, branches [(points (n, 2), radii (n,), generation)])`` of ``kind``.

    Roots enter from the frame edge and wander gently about their heading into the frame (no line
    comes near another frame edge by design: each is ended 4 % of ``N`` short of the frame); known
    answers: the branches' frame share and the roots' bearings.
    """
    rng = np.random.default_rng(7000 + 97 * seed + 13 * KINDS.index(kind) + N)
    s = N / 512.0
    if kind == "roots":
        ground, col, r0, jit, gens, nroots, step_len = (0.78, 0.68, 0.52), (0.30, 0.18, 0.10), 4.5 * s ** 0.5, 0.07, 4, int(rng.integers(2, 4)), 3.0
    elif kind == "river":
        ground, col, r0, jit, gens, nroots, step_len = (0.55, 0.62, 0.38), (0.18, 0.32, 0.62), 3.5 * s ** 0.5, 0.06, 3, int(rng.integers(2, 4)), 3.0
    else:
        ground, col, r0, jit, gens, nroots, step_len = (0.06, 0.07, 0.15), (0.92, 0.92, 1.0), 1.8 * s ** 0.5, 0.25, 4, 2, 3.0
    noise = cv2.GaussianBlur(rng.normal(0, 1, (N, N)).astype(np.float32), (0, 0), max(N / 80, 1.0))
    noise /= noise.std() + 1e-9
    img = np.stack([g + 0.03 * noise for g in ground], -1).astype(np.float32)
    margin = 0.04 * N
    out: list = []
    occ = np.zeros((N, N), np.int32)

    def grow(x, y, ang, r, gen, length, parent=0):
        a0 = ang
        pts, rad = [(x, y)], [r]
        n = int(length / step_len)
        kids = []
        for i in range(n):
            ang += rng.normal(0, jit) + 0.12 * np.angle(np.exp(1j * (a0 - ang)))
            x += step_len * np.cos(ang); y += step_len * np.sin(ang)
            if not (margin <= x < N - margin and y < N - margin) or (gen > 0 and y < margin):
                break
            if i > 2 and occ[min(int(y), N - 1), min(int(x), N - 1)] not in (0, parent):   # a tree: no crossing
                break
            pts.append((x, y)); rad.append(max(0.7, r * (1.0 - 0.45 * i / max(n, 1))))
            if gen + 1 < gens and i > 4 and rng.random() < 0.035 and len(kids) < 3:
                kids.append((x, y, ang + rng.choice([-1, 1]) * rng.uniform(0.45, 0.9), rad[-1] * 0.65, length * 0.45))
        out.append((np.asarray(pts), np.asarray(rad), gen))
        me = len(out)
        q = np.asarray(pts, np.int32).reshape(-1, 1, 2)
        cv2.polylines(occ, [q], False, me, int(2 * r + 2 * step_len + 6 + 0.03 * N))
        for (kx, ky, ka, kr, kl) in kids:
            grow(kx, ky, ka, kr, gen + 1, kl, me)

    xs = (np.arange(nroots) + 0.5) / nroots
    for i in range(nroots):
        x = N * (0.15 + 0.7 * xs[i]) + rng.normal(0, 0.03 * N)
        grow(x, 0.0, np.pi / 2 + rng.normal(0, 0.06), r0, 0, N * rng.uniform(0.75, 0.9))
    side = _SIDE[kind]
    lines = np.zeros((N, N), np.float32)
    branches = []
    for pts, rad, gen in out:
        p = _orient_pts(pts, side, N)
        branches.append((p, rad, gen))
        for (a, b), rr in zip(zip(p[:-1], p[1:]), rad[1:]):
            cv2.line(lines, (int(round(a[0] * 8)), int(round(a[1] * 8))), (int(round(b[0] * 8)), int(round(b[1] * 8))),
                     1.0, max(1, int(round(2 * rr))), cv2.LINE_AA, shift=3)
    lines = np.clip(lines, 0, 1)[..., None]
    img = img * (1 - lines) + np.asarray(col, np.float32) * lines
    img += rng.normal(0, 0.01, img.shape).astype(np.float32)
    return np.clip(img, 0, 1).astype(np.float32), branches


def frame_share(branches, shape, px: float = FRAME_PX) -> float:
    """Share of the length of ``branches`` ((points, radii, parent or generation) triples; roots have 0 /
    None) within ``px`` of the frame, the first 2 radii (arc length) of each root left out."""
    H, W = shape
    near = total = 0.0
    for pts, rad, par in branches:
        p = np.asarray(pts, np.float64)
        if len(p) < 2:
            continue
        seg = np.hypot(*np.diff(p, axis=0).T)
        mid = (p[:-1] + p[1:]) / 2
        keep = np.ones(len(seg), bool)
        if par is None:
            arc = np.concatenate([[0.0], np.cumsum(seg)])[:-1]
            keep = arc >= 2.0 * float(np.asarray(rad).ravel()[0])
        d = np.minimum.reduce([mid[:, 0], mid[:, 1], W - 1 - mid[:, 0], H - 1 - mid[:, 1]])
        near += float(seg[keep & (d < px)].sum()); total += float(seg.sum())
    return near / max(total, 1e-9)


def _bearing(p) -> float:
    p = np.asarray(p, np.float64)
    d = p[-1] - p[0]
    return float(np.arctan2(d[1], d[0]))


def _dev(a: float, b: float) -> float:
    return float(abs(np.degrees(np.angle(np.exp(1j * (a - b))))))


def case(kind: str, N: int, seed: int, use_domain: bool = True, png: str | None = None) -> dict:
    from . import example_domain, extract_structure, fit_model, synthesize_structure

    img, truth = hug_example(kind, N, seed)
    ex = extract_structure(img)
    m = fit_model(ex, domain=example_domain(img, ex) if use_domain else None)
    t = synthesize_structure(m, rng=seed).structure
    fx = frame_share([(p, r, None if g == 0 else 1) for p, r, g in truth], (N, N))
    fq = frame_share([(b.points, b.thickness, b.parent) for b in t.branches], (N, N))
    roots = [b for b in t.branches if b.parent is None]
    main = max(roots, key=lambda b: b.length)
    ex_b = np.angle(np.mean([np.exp(1j * _bearing(p)) for p, r, g in truth if g == 0]))
    if png:
        from ..core import draw_polylines  # noqa: F401
        canvas = np.ones((N, 2 * N + 8, 3), np.float32)
        canvas[:, :N] = img
        out = np.ones((N, N, 3), np.float32)
        for b in t.branches:
            q = np.asarray(b.points)
            c = (0.8, 0.0, 0.0) if b is main else ((0.0, 0.0, 0.0) if b.parent is None else (0.1, 0.3, 0.9))
            for a, bb in zip(q[:-1], q[1:]):
                cv2.line(out, (int(a[0]), int(a[1])), (int(bb[0]), int(bb[1])), c, 2 if b.parent is None else 1, cv2.LINE_AA)
        cv2.rectangle(out, (0, 0), (N - 1, N - 1), (0.5, 0.5, 0.5), 1)
        canvas[:, N + 8:] = out
        cv2.imwrite(png, (np.clip(canvas[..., ::-1], 0, 1) * 255).astype(np.uint8))
    return {"fx": fx, "fq": fq, "lim": 2 * fx + 0.01, "dev": _dev(_bearing(main.points), float(ex_b)),
            "nb": float(len(t.branches))}


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    seeds = [int(x) for x in argv[0].split(",")] if len(argv) > 0 and argv[0] else list(range(5))
    kinds = argv[1].split(",") if len(argv) > 1 and argv[1] else list(KINDS)
    pngdir = argv[2] if len(argv) > 2 and argv[2] else None
    sizes = [int(x) for x in argv[3].split(",")] if len(argv) > 3 and argv[3] else list(SIZES)
    dom = (argv[4] != "0") if len(argv) > 4 else True
    import os
    if pngdir:
        os.makedirs(pngdir, exist_ok=True)
    for kind in kinds:
        for N in sizes:
            rows = []
            for s in seeds:
                png = os.path.join(pngdir, f"{kind}_{N}_{s}_{int(dom)}.png") if pngdir else None
                r = case(kind, N, s, dom, png)
                rows.append(r)
                bad = "!" if r["fq"] > r["lim"] or r["dev"] > 25 else " "
                print(f"{kind:6s} {N:4d} {s} {bad} " + " ".join(f"{k}={v:.3f}" for k, v in r.items()), flush=True)
            fails = sum(r["fq"] > r["lim"] or r["dev"] > 25 for r in rows)
            print(f"MEAN {kind:6s} {N:4d} fails={fails}/{len(rows)} " + " ".join(f"{k}={np.mean([r[k] for r in rows]):.3f}" for k in rows[0]), flush=True)


if __name__ == "__main__":
    main()
