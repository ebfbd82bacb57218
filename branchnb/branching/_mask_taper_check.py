"""Issue-23 figures on binary masks whose branches taper (branching80): no blunt children, no stubs.

``python -m branchnb.branching._mask_taper_check [SEEDS] [KINDS] [SIZES] [PNG_DIR]`` (e.g. ``0,1,2
vessel,crack,delta,comb,dfan 128,256,512``) runs each kind through the default workflow
(``extract_structure``, ``fit_model(ex, domain=example_domain(img, ex))``, ``synthesize_structure``,
``synthesize_image``) and prints per case, measured on the image (the distance transform of the ink
mask sampled along every branch of the structure, example and output alike): ``thick_end`` the share of
branches whose end radius is more than 2 x their start radius (start: just past the parent's body),
``tip`` the median radius over the last 2 px of the free ends, ``stubs`` the drawn children (ink along at
least half their length from a pixel past the parent's ink) sticking out of it by less than 3 of their radii
(at least 1 px each) with their ink ending at their tip (not a short child under a sibling drawn on from
the same vertex) over ``children``, ``pieces`` the most 8-connected ink
pieces one tree's centre lines touch (1 = every tree one piece).

Kinds: :func:`taper_mask`'s ``vessel`` (white bifurcating tree, radius falling 0.7x per generation, round
tips), ``crack`` (black tapering trunk with side children, pointed tips) and ``delta`` (white trunk from
the bottom splitting into thinning distributaries); ``comb`` (:func:`._thin_children_check.comb_mask`),
``tcrack`` (:func:`._thin_mask_check.thin_mask_example`) and ``dfan``
(:func:`._delta_examples.delta_fan_mask`, square).
"""
# ruff: noqa: E501
from __future__ import annotations

import os
import sys

import cv2
import numpy as np
from scipy import ndimage as ndi

TAPER_KINDS = ("vessel", "crack", "delta")
KINDS = (*TAPER_KINDS, "comb", "tcrack", "dfan")


def _disc_line(m: np.ndarray, pts, rads, ss: int) -> None:
    """Draw the union of discs of radii ``rads`` along ``pts`` (every 0.25 px) into ``m`` at ``ss`` x."""
    pts, rads = np.asarray(pts, float), np.asarray(rads, float)
    t = np.r_[0, np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]
    s = np.arange(0, t[-1] + 1e-9, 0.25)
    for x, y, r in zip(np.interp(s, t, pts[:, 0]), np.interp(s, t, pts[:, 1]), np.interp(s, t, rads)):
        cv2.circle(m, (int(round(x * ss * 16)), int(round(y * ss * 16))), int(round(max(r, 0.5) * ss * 16)), 1, -1,
                   cv2.LINE_8, 4)


def taper_mask(kind: str, width: int, seed: int = 0) -> np.ndarray:
    """A binary mask ``2 width / 3`` x ``width`` of a tree whose radius falls along every branch, (H, W, 3).

    ``vessel``: white on black, bifurcating (4 generations), each child starting at 0.85 x its parent's end
    radius and ending at 0.7 x its start, round tips; ``crack``: black on white, a trunk with 4 side
    children each with 2 of their own, starting at 0.6 x the parent's radius, pointed (0.5 px) tips;
    ``delta``: white on black, a trunk from the bottom splitting 3 times, round then pointed tips.

    Examples
    --------
    >>> img = taper_mask("vessel", 128)
    >>> img.shape, sorted(np.unique(img).tolist())
    ((85, 128, 3), [0.0, 1.0])
    """
    if kind not in TAPER_KINDS:
        raise ValueError(f"kind must be one of {TAPER_KINDS}, got {kind!r}")
    rng = np.random.default_rng(seed * 11 + TAPER_KINDS.index(kind))
    W, H = int(width), int(width * 2 / 3)
    ss = 2
    m = np.zeros((H * ss, W * ss), np.uint8)
    sc = W / 256.0

    def grow(p, a, ln, r0, r1, step, wob, pointed):
        pts = [p.copy()]
        for _ in range(max(int(ln / step), 2)):
            a += rng.normal(0, wob)
            p = p + step * np.array([np.cos(a), np.sin(a)])
            if not (2 < p[0] < W - 3 and 2 < p[1] < H - 3):
                break
            pts.append(p.copy())
        if len(pts) < 3:
            return None
        pts = np.array(pts)
        f = np.linspace(0, 1, len(pts))
        rads = r0 + ((0.5 if pointed else r1) - r0) * f ** (1.5 if pointed else 1.0)
        _disc_line(m, pts, rads, ss)
        return pts, rads, a

    if kind == "vessel":
        def rec(p, a, ln, r0, depth):
            out = grow(p, a, ln, r0, max(0.7 * r0, 0.9), 2.0 * sc, 0.06, False)
            if out is None or depth >= 3:
                return
            pts, rads, a2 = out
            for s in (-1, 1):
                rec(pts[-1].copy(), a2 + s * rng.uniform(0.45, 0.8), ln * 0.68, max(0.85 * rads[-1], 1.0), depth + 1)
        rec(np.array([0.06 * W, 0.5 * H]), 0.0, 0.32 * W, 4.5 * sc ** 0.5, 0)
    elif kind == "crack":
        def rec(p, a, ln, r0, depth):
            out = grow(p, a, ln, r0, 0.5, 2.5 * sc, 0.12, True)
            if out is None or depth >= 2:
                return
            pts, rads, _ = out
            k = 4 if depth == 0 else 2
            for j in range(k):
                v = min(int(len(pts) * (0.15 + 0.7 * (j + rng.uniform(0.2, 0.8)) / k)), len(pts) - 2)
                ang = np.arctan2(*(pts[v + 1] - pts[v])[::-1])
                rec(pts[v].copy(), ang + (1 if (j + depth) % 2 else -1) * rng.uniform(0.6, 1.0), ln * 0.35,
                    max(0.6 * rads[v], 1.0), depth + 1)
        rec(np.array([0.04 * W, 0.45 * H]), 0.0, 0.95 * W, 3.5 * sc ** 0.5, 0)
    else:
        def rec(p, a, ln, r0, depth):
            out = grow(p, a, ln, r0, max(0.6 * r0, 0.9), 2.0 * sc, 0.1, depth >= 3)
            if out is None or depth >= 3:
                return
            pts, rads, a2 = out
            for s in (-1, 1):
                rec(pts[-1].copy(), a2 + s * rng.uniform(0.3, 0.6), ln * 0.75, max(0.8 * rads[-1], 1.0), depth + 1)
        rec(np.array([0.5 * W, H - 3.5]), -np.pi / 2, 0.3 * H, 4.0 * sc ** 0.5, 0)
    ink = cv2.resize(m.astype(np.float32), (W, H), interpolation=cv2.INTER_AREA) >= 0.5
    ink = ink.astype(np.float32)[..., None] * np.ones(3, np.float32)
    return (1.0 - ink if kind == "crack" else ink).astype(np.float32)


def example(kind: str, width: int, seed: int = 0) -> np.ndarray:
    """The example image of ``kind`` (see the module)."""
    if kind in TAPER_KINDS:
        return taper_mask(kind, width, seed)
    if kind == "comb":
        from ._thin_children_check import comb_mask

        return (1.0 - comb_mask(width, seed))[..., None] * np.ones(3, np.float32)
    if kind == "tcrack":
        from ._thin_mask_check import thin_mask_example

        return thin_mask_example("crack", width, seed)
    if kind == "dfan":
        from ._delta_examples import delta_fan_mask

        return np.asarray(delta_fan_mask((width, width), seed)[0], np.float32)[..., None] * np.ones(3, np.float32)
    raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")


def ink_mask(img: np.ndarray) -> np.ndarray:
    """The pixels off the majority (ground) colour of a binary mask image."""
    g = np.asarray(img, np.float32)[..., :3].mean(-1)
    ground = 1.0 if np.mean(g > 0.5) > 0.5 else 0.0
    return np.abs(g - ground) > 0.5


def _dense(pts) -> np.ndarray:
    """Points every half pixel along the polyline ``pts`` (the samples of :func:`_along`)."""
    p = np.asarray(pts, float)
    t = np.r_[0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
    s = np.arange(0, t[-1] + 1e-9, 0.5)
    return np.c_[np.interp(s, t, p[:, 0]), np.interp(s, t, p[:, 1])]


def _along(dt: np.ndarray, pts) -> tuple[np.ndarray, np.ndarray]:
    p = np.asarray(pts, float)
    t = np.r_[0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
    s = np.arange(0, t[-1] + 1e-9, 0.5)
    return s, ndi.map_coordinates(dt, [np.interp(s, t, p[:, 1]), np.interp(s, t, p[:, 0])], order=1, mode="nearest")


def _under_other(i: int, branches, tree, owner: np.ndarray, pts: np.ndarray) -> bool:
    """Whether most points ``pts`` of branch ``i`` lie within a pixel of another branch's centre line (not
    its parent's): a child drawn over by a sibling leaving the same vertex is that sibling's line."""
    if tree is None or not len(pts):
        return False
    skip = {i, branches[i].parent}
    near = tree.query_ball_point(pts, 1.0)
    return float(np.mean([any(owner[j] not in skip for j in js) for js in near])) > 0.5


def _ink_runs_on(m: np.ndarray, pts, r_end: float) -> bool:
    """Whether the ink ``m`` goes on 1.5 px past the round cap (radius ``r_end`` + 0.5) at the end of the
    polyline ``pts``, along its last heading."""
    p = np.asarray(pts, float)
    d = p[-1] - p[-2]
    n = float(np.hypot(*d))
    if n < 1e-9:
        return False
    x, y = p[-1] + (max(float(r_end), 0.0) + 2.0) * d / n
    h, w = m.shape
    xi, yi = int(round(x)), int(round(y))
    return 0 <= xi < w and 0 <= yi < h and bool(m[yi, xi])


def figures(img: np.ndarray, structure, min_len: float = 6.0) -> dict:
    """``thick_end``, ``tip``, ``stubs``, ``children`` and ``pieces`` of ``img`` along ``structure`` (see the module).

    Radii are read from the ink's distance transform minus half a pixel (a 1-px line: 0.5, a 3-px
    line's centre: 1.5).
    """
    m = ink_mask(img)
    h, w = m.shape
    r_img = np.maximum(ndi.distance_transform_edt(m) - 0.5, 0.0)
    ends, tips, stubs, kids = [], [], 0, 0
    bs = structure.branches
    from scipy.spatial import cKDTree

    dense = [(_dense(b.points), k) for k, b in enumerate(bs) if len(b.points) > 1]
    tree = cKDTree(np.vstack([d for d, _ in dense])) if dense else None
    owner = np.concatenate([np.full(len(d), k) for d, k in dense]) if dense else np.zeros(0, int)
    for i, b in enumerate(bs):
        if len(b.points) < 2:
            continue
        s, v = _along(r_img, b.points)
        length = s[-1]
        a = float(v[0]) if b.parent is not None else 0.0
        body = v[s >= a] if np.any(s >= a) else v[-1:]
        # drawn: ink (a quarter pixel inside it) along at least half of the child from a pixel past the
        # parent's edge, over a pixel at least (the distance transform at the start is the parent's
        # narrowest half width, its round end reaches further). The interpolated distance transform is slightly positive for a pixel along the
        # outside of that edge, which a child left out of the drawing at a shallow angle follows
        clear = v[s >= a + 1.0]
        if b.parent is not None and clear.size >= 3 and np.mean(clear >= 0.25) >= 0.5:
            # (a child with no ink beyond its parent is not drawn: no stub to see)
            kids += 1
            # a stub ends where its ink ends; a short child whose ink runs on past its tip (a sibling
            # drawn over it from the same vertex) shows no end of its own
            if length - a < 3.0 * max(float(np.median(body)), 1.0):
                past = _dense(b.points)[s >= a]
                stubs += int(not _ink_runs_on(m, b.points, float(v[-1])) and not _under_other(i, bs, tree, owner, past))
        if length - a < min_len:
            continue
        span = max(2.0, 0.15 * (length - a))
        start = float(np.median(v[(s >= a) & (s <= a + span)]))
        ends.append(float(np.median(v[s >= length - span])) > 2.0 * max(start, 0.5))
        x, y = b.points[-1]
        if min(x, y, w - 1 - x, h - 1 - y) >= 3:
            tips.append(float(np.max(v[s >= length - 2.0])))
    lab, _ = ndi.label(m, structure=np.ones((3, 3)))
    touched: dict[int, set] = {}
    for i, b in enumerate(structure.branches):
        j, seen = i, set()
        while structure.branches[j].parent is not None and j not in seen:
            seen.add(j)
            j = structure.branches[j].parent
        p = np.asarray(b.points, float)
        ls = lab[np.clip(np.rint(p[:, 1]).astype(int), 0, h - 1), np.clip(np.rint(p[:, 0]).astype(int), 0, w - 1)]
        touched.setdefault(j, set()).update(ls[ls > 0].tolist())
    return {"thick_end": float(np.mean(ends)) if ends else 0.0, "tip": float(np.median(tips)) if tips else 0.0,
            "stubs": stubs, "children": kids, "pieces": max((len(t) for t in touched.values()), default=0)}


def case(kind: str, width: int, seed: int, png: str | None = None) -> tuple[dict, dict]:
    """(example figures, output figures) of one case through the default workflow."""
    from . import example_domain, extract_structure, fit_model, synthesize_image, synthesize_structure

    img = example(kind, width)
    ex = extract_structure(img)
    res = synthesize_structure(fit_model(ex, domain=example_domain(img, ex)), rng=seed)
    out = synthesize_image(img, ex, res, rng=seed).image[..., :3]
    if png:
        cv2.imwrite(png, (np.hstack([img, np.full((img.shape[0], 4, 3), 0.5), out]) * 255).astype(np.uint8)[..., ::-1])
    return figures(img, ex), figures(out, res.structure)


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    seeds = [int(s) for s in argv[0].split(",")] if argv else [0, 1, 2]
    kinds = argv[1].split(",") if len(argv) > 1 else list(KINDS)
    sizes = [int(s) for s in argv[2].split(",")] if len(argv) > 2 else [128, 256, 512]
    pngdir = argv[3] if len(argv) > 3 else None
    if pngdir:
        os.makedirs(pngdir, exist_ok=True)
    for kind in kinds:
        for size in sizes:
            for seed in seeds:
                fx, fo = case(kind, size, seed, pngdir and os.path.join(pngdir, f"{kind}_{size}_{seed}.png"))
                print(f"{kind:7s} {size:4d} s{seed}: thick_end {fo['thick_end']:.3f} (ex {fx['thick_end']:.3f}) "
                      f"tip {fo['tip']:.2f} (ex {fx['tip']:.2f}) stubs {fo['stubs']}/{fo['children']} "
                      f"(ex {fx['stubs']}/{fx['children']}) pieces {fo['pieces']}", flush=True)


if __name__ == "__main__":
    main()
