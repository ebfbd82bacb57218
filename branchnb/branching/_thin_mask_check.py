"""Issue-23 figures on small line masks (1-4 px lines on one plain ground).

``python -m branchnb.branching._thin_mask_check [SEEDS] [KINDS]`` (e.g. ``0,1,2 crack,river,vessel``) runs
3 kinds (random-walk crack networks, thin meandering rivers, bifurcating vessels) x 4 variants (binary or
anti-aliased, black on white or white on black; sizes 200-600 px wide, 2:3) x seeds through the default
workflow (``extract_structure``, ``synthesize_structure``, ``synthesize_image``) and prints per case and
per kind: line pieces per tree, gaps >= 2 px, specks (:func:`~branchnb.branching.measures.relative_line_pieces`),
the strongest ink within one pixel of the thin (r <= 1) centre lines (median, example and output) and
the share of that thin centre line under 90 % of the example's ink (``pale``: broken grey dashes).
PNGs (example | output) go to /tmp/thin_masks/.
"""
# ruff: noqa: E501, E702
from __future__ import annotations

import os
import sys

import cv2
import numpy as np
from scipy import ndimage as ndi

KINDS = ("crack", "river", "vessel")
VARIANTS = (("bin", "bow"), ("aa", "wob"), ("bin", "wob"), ("aa", "bow"))
SIZES = (200, 300, 450, 600)


def thin_mask_example(kind: str, width: int, seed: int, *, aa: bool = False, dark: bool = True) -> np.ndarray:
    """A line mask ``2 width / 3`` x ``width``: lines 1-4 px wide, (H, W, 3) float32.

    ``kind``: ``crack`` (random-walk network, children every 9 steps, one px thinner), ``river``
    (smooth meanders from a trunk at the bottom) or ``vessel`` (a bifurcating tree, 4 -> 1 px);
    ``aa`` draws at 4x and averages down; ``dark``: black lines on white, else white on black.

    Examples
    --------
    >>> img = thin_mask_example("crack", 150, 0)
    >>> img.shape, sorted(np.unique(img).tolist())
    ((100, 150, 3), [0.0, 1.0])
    """
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    rng = np.random.default_rng(seed * 7 + KINDS.index(kind))
    H, W = int(width * 2 / 3), int(width)
    ss = 4 if aa else 1
    m = np.zeros((H * ss, W * ss), np.float32)
    step = 6.0 * W / 450

    def draw(pts, wd):
        q = np.round(np.asarray(pts) * ss * 8).astype(np.int32)
        cv2.polylines(m, [q], False, 1.0, max(1, int(wd * ss)), cv2.LINE_8, 3)

    if kind == "crack":
        def walk(p, a, n, wd):
            pts = [p]
            for i in range(n):
                a += rng.normal(0, 0.25); p = p + step * np.array([np.cos(a), np.sin(a)]); pts.append(p)
                if i % 9 == 5 and wd > 1:
                    walk(p.copy(), a + rng.choice([-1, 1]) * 0.9, n // 2, wd - 1)
            draw(pts, wd)
        walk(np.array([0.05 * W, 0.5 * H]), 0.0, 60, 4)
    elif kind == "river":
        def walk(p, a, n, wd, depth):
            pts = [p]
            for i in range(n):
                a += rng.normal(0, 0.12); p = p + step * np.array([np.cos(a), np.sin(a)]); pts.append(p)
                if not (0 < p[0] < W and 0 < p[1] < H):
                    break
                if i % 10 == 4 and depth < 2:
                    walk(p.copy(), a + rng.choice([-1, 1]) * rng.uniform(0.5, 1.0), int(n * 0.6), max(wd - 1, 1), depth + 1)
            draw(pts, wd)
        walk(np.array([0.5 * W, H - 1.0]), -np.pi / 2, 50, 3, 0)
    else:
        def seg(p, a, ln, wd, depth):
            pts = [p]
            for _ in range(int(ln / step)):
                a += rng.normal(0, 0.08); p = p + step * np.array([np.cos(a), np.sin(a)]); pts.append(p)
            draw(pts, wd)
            if depth < 4:
                for s in (-1, 1):
                    seg(p.copy(), a + s * rng.uniform(0.35, 0.7), ln * 0.75, max(wd - 1, 1), depth + 1)
        seg(np.array([0.1 * W, 0.5 * H]), 0.0, 0.3 * W, 4, 0)
    if aa:
        m = cv2.resize(m, (W, H), interpolation=cv2.INTER_AREA)
    ink = np.clip(m, 0, 1)[..., None] * np.ones(3, np.float32)
    return (1.0 - ink if dark else ink).astype(np.float32)


def thin_ink(img: np.ndarray, structure, dark: bool) -> np.ndarray:
    """The strongest ink within one pixel of every thin (r <= 1) centre-line pixel of ``structure``."""
    from .skeleton_map import SkeletonMap

    g = np.asarray(img, np.float32)[..., :3].mean(-1)
    ink = 1.0 - g if dark else g
    pm = SkeletonMap(structure, 1.0).pixel_map(g.shape)
    sel = np.isfinite(pm.dist) & (pm.dist <= 0.5) & (pm.radius <= 1.0)
    return ndi.maximum_filter(ink, 3)[sel]


def case_rows(kind: str, aa: bool, dark: bool, width: int, seed: int, png: str | None = None) -> dict:
    from . import extract_structure, synthesize_image, synthesize_structure
    from .measures import relative_line_pieces

    img = thin_mask_example(kind, width, seed, aa=aa, dark=dark)
    ex = extract_structure(img)
    res = synthesize_structure(ex, rng=seed)
    out = synthesize_image(img, ex, res, rng=seed).image[..., :3]
    m = relative_line_pieces(img, ex, out, res.structure)
    tx, to = thin_ink(img, ex, dark), thin_ink(out, res.structure, dark)
    ref = float(np.median(tx)) if tx.size else float("nan")
    if png:
        cv2.imwrite(png, (np.hstack([img, out]) * 255).astype(np.uint8)[..., ::-1])
    return {"pieces": m["pieces_per_tree"], "max_pieces": m["max_pieces"], "gaps": m["gaps"], "specks": m["specks"],
            "thin_ex": ref, "thin_out": float(np.median(to)) if to.size else float("nan"),
            "pale": float(np.mean(to < 0.9 * ref)) if to.size else float("nan")}


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    seeds = [int(s) for s in argv[0].split(",")] if argv else [0, 1, 2]
    kinds = argv[1].split(",") if len(argv) > 1 else list(KINDS)
    os.makedirs("/tmp/thin_masks", exist_ok=True)
    for kind in kinds:
        for vi, (aa, pol) in enumerate(VARIANTS):
            rows = []
            for s in seeds:
                size = SIZES[(vi + s) % len(SIZES)]
                r = case_rows(kind, aa == "aa", pol == "bow", size, s, f"/tmp/thin_masks/{kind}_{aa}_{pol}_{size}_{s}.png")
                rows.append(r)
                print(kind, aa, pol, size, s, " ".join(f"{k}={v:.2f}" for k, v in r.items()), flush=True)
            mean = {k: float(np.nanmean([r[k] for r in rows])) for k in rows[0]}
            print("MEAN", kind, aa, pol, " ".join(f"{k}={v:.2f}" for k, v in mean.items()), flush=True)


if __name__ == "__main__":
    main()
