"""Issue-23 figures on masks with thick trunks and many thin children (branching48, branching52).

``python -m branchnb.branching._thin_children_check [SEEDS] [KINDS] [PNG_DIR]`` (e.g. ``0,1,2
comb,partial,crack,vessel,river,roots``; ``crack``, ``vessel`` and ``river`` are
:func:`._thin_mask_check.thin_mask_example`'s binary masks, ``roots`` :func:`roots_drawing`) runs each kind
at sizes 200-600 px through the default workflow (``extract_structure``, ``fit_model(ex,
domain=example_domain(img, ex))``, ``synthesize_structure``) and prints, per case and per kind (output
over example): branch count ratio ``nb``, length ratio ``len``, share of the length at radius <= 1 px
``thin`` and >= 2 px ``thick`` and at or above the example's length-weighted 90th-percentile radius
``top`` (example -> output), L1 distance of the length-weighted radius histograms ``hd`` (0 = equal,
2 = disjoint) and the share of the output's length farther than 8 % of the frame's short side from
every example line ``out`` (``out15``: 15 %; the part of the frame the example leaves empty).
PNG_DIR: per case the example and the output structure drawn at its radii.
"""
# ruff: noqa: E501, E702
from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage as ndi

from ._check_table import length_share, print_table

KINDS = ("comb", "partial", "crack", "vessel", "river", "roots")
SIZES = (200, 300, 380, 450, 600)
R_EDGES = np.array([0.0, 1.0, 1.5, 2.0, 3.0, 1e9])


def comb_mask(width: int, seed: int, *, partial: bool = False) -> np.ndarray:
    """A random-walk crack mask ``2 width / 3`` x ``width`` (H, W) float32 in {0, 1} (1 = line).

    A few thick trunks (3-4 px) wander across the frame; many 1-px side cracks (and a few 2-px ones, with
    their own 1-px side cracks) leave them every few steps. ``partial``: the network lives in the lower
    ~55 % of the frame and the upper part is empty (the unseen finding).
    """
    rng = np.random.default_rng(1000 + seed * 13 + (7 if partial else 0))
    H, W = int(width * 2 / 3), int(width)
    m = np.zeros((H, W), np.uint8)
    step = 5.0 * W / 380
    top = 0.45 * H if partial else 0.0

    def walk(p, a, n, wd, depth):
        pts = [p.copy()]
        for i in range(n):
            a += rng.normal(0, 0.15)
            q = p + step * np.array([np.cos(a), np.sin(a)])
            if q[1] < top + 3 or q[1] > H - 3:       # off the empty part and the frame: turn back
                a = -a; q = p + step * np.array([np.cos(a), np.sin(a)])
            if not (1 < q[0] < W - 2 and 1 < q[1] < H - 2):
                break
            p = q; pts.append(p.copy())
            if depth < 2 and i > 1 and rng.random() < (0.2 if wd >= 3 else 0.2):
                cw = 2 if (wd >= 3 and rng.random() < 0.2) else 1
                ln = int(rng.integers(4, 12)) if cw == 1 else int(rng.integers(12, 25))
                walk(p.copy(), a + rng.choice([-1, 1]) * rng.uniform(0.6, 1.3), ln, cw, depth + 1)
        if len(pts) > 1:
            cv2.polylines(m, [np.round(np.asarray(pts) * 8).astype(np.int32)], False, 1, wd, cv2.LINE_8, 3)

    n_trunks = int(rng.integers(2, 4))
    for _ in range(n_trunks):
        y0 = rng.uniform(max(top, 0.15 * H) + 0.1 * H, 0.85 * H)
        walk(np.array([2.0, y0]), rng.normal(0, 0.3), int(1.1 * W / step), int(rng.integers(3, 5)), 0)
    return m.astype(np.float32)


def roots_drawing(width: int, seed: int) -> np.ndarray:
    """(H, W, 3) float32 plant roots drawn dark on a cream background, ``3 width / 4`` x ``width``: 2-3
    trunks 5-7 px wide from the top edge, whose children are 0.6 x as wide as their parent (down to
    1-px hairlines, 3 generations), anti-aliased."""
    rng = np.random.default_rng(5000 + seed)
    H, W = int(width * 3 / 4), int(width)
    img = np.ones((H, W), np.float32)
    step = 2.0 * W / 420

    def grow(x, y, ang, wd, depth):
        pts = []
        for _ in range(int((60 + 40 * rng.random()) * (0.8 if depth else 1.0))):
            ang += rng.normal(0, 0.12)
            x += step * np.cos(ang); y += step * np.sin(ang)
            if not (0 <= x < W and 0 <= y < H):
                break
            pts.append((x, y))
            if depth < 3 and rng.random() < 0.035:
                grow(x, y, ang + rng.choice([-1, 1]) * rng.uniform(0.4, 0.9), max(1.0, wd * 0.6), depth + 1)
        for (a, b), (c, d) in zip(pts[:-1], pts[1:]):
            cv2.line(img, (int(a), int(b)), (int(c), int(d)), 0.15, int(max(1, wd)), cv2.LINE_AA)

    for x0 in np.linspace(0.2, 0.8, int(rng.integers(2, 4))) * W:
        grow(x0, 0.0, np.pi / 2 + rng.normal(0, 0.2), float(rng.uniform(5, 7)), 0)
    return np.dstack([img * 0.95, img * 0.9, img * 0.8]).astype(np.float32)


def example_mask(kind: str, width: int, seed: int) -> np.ndarray:
    """(H, W, 3) float32 black lines on white for ``kind`` (see :data:`KINDS`)."""
    if kind == "roots":
        return roots_drawing(width, seed)
    if kind in ("comb", "partial"):
        m = comb_mask(width, seed, partial=kind == "partial")
        return (1.0 - m)[..., None] * np.ones(3, np.float32)
    from ._thin_mask_check import thin_mask_example
    return thin_mask_example(kind, width, seed)


def radius_length(s) -> tuple[np.ndarray, np.ndarray]:
    """Per segment: mean radius and length of every branch of ``s``."""
    r, ln = [], []
    for b in s.branches:
        p = np.asarray(b.points, float)
        if len(p) < 2:
            continue
        t = np.broadcast_to(np.asarray(b.thickness, float), (len(p),))
        r.append(0.5 * (t[1:] + t[:-1])); ln.append(np.hypot(*np.diff(p, axis=0).T))
    return (np.concatenate(r), np.concatenate(ln)) if r else (np.zeros(0), np.zeros(0))


def figures(img, ex, out) -> dict:
    """The figures of one case (example structure ``ex``, synthesized structure ``out``)."""
    re_, le = radius_length(ex)
    ro, lo = radius_length(out)
    top = re_[np.argsort(re_)][min(np.searchsorted(np.cumsum(le[np.argsort(re_)]) / max(le.sum(), 1e-9), 0.9), len(re_) - 1)]
    he = np.histogram(re_, R_EDGES, weights=le)[0] / max(le.sum(), 1e-9)
    ho = np.histogram(ro, R_EDGES, weights=lo)[0] / max(lo.sum(), 1e-9)
    ink = img[..., :3].mean(-1) < 0.5
    d = ndi.distance_transform_edt(~ink)
    far = d > 0.08 * min(ink.shape)
    far15 = d > 0.15 * min(ink.shape)
    H, W = ink.shape
    outside, tot = length_share(out, far)
    outside15, _ = length_share(out, far15)
    return {"nb_ex": len(ex.branches), "nb_out": len(out.branches), "nb": len(out.branches) / max(len(ex.branches), 1),
            "len": lo.sum() / max(le.sum(), 1e-9),
            "thin_ex": float(le[re_ <= 1.0].sum() / max(le.sum(), 1e-9)),
            "thin_out": float(lo[ro <= 1.0].sum() / max(lo.sum(), 1e-9)),
            "thick_ex": float(le[re_ >= 2.0].sum() / max(le.sum(), 1e-9)),
            "thick_out": float(lo[ro >= 2.0].sum() / max(lo.sum(), 1e-9)),
            "top_ex": float(le[re_ >= top].sum() / max(le.sum(), 1e-9)),
            "top_out": float(lo[ro >= top].sum() / max(lo.sum(), 1e-9)),
            "hd": float(np.abs(he - ho).sum()), "out": outside / max(tot, 1e-9),
            "out15": outside15 / max(tot, 1e-9)}


def case(kind: str, width: int, seed: int, png: str | None = None, image: bool = False) -> dict:
    from . import example_domain, extract_structure, fit_model, synthesize_image, synthesize_structure

    img = example_mask(kind, width, seed)
    ex = extract_structure(img)
    model = fit_model(ex, domain=example_domain(img, ex))
    res = synthesize_structure(model, rng=seed)
    f = figures(img, ex, res.structure)
    from .measures import far_share, thick_end_share
    reg = model.region if model.region is not None else np.ones(img.shape[:2], bool)
    f.update(tend_ex=thick_end_share(ex), tend_out=thick_end_share(res.structure),
             far_ex=far_share(ex, reg), far_out=far_share(res.structure, reg))
    if png:
        panels = [img]
        if image:
            panels.append(synthesize_image(img, ex, res, rng=seed).image[..., :3])
        panels.append(_draw(res.structure, img.shape[:2]))
        cv2.imwrite(png, (np.hstack(panels) * 255).astype(np.uint8)[..., ::-1])
    return f


def _draw(s, shape) -> np.ndarray:
    """The structure drawn at its radii, black on white, (H, W, 3)."""
    canvas = np.ones(tuple(shape) + (3,), np.float32)
    for b in s.branches:
        p = np.asarray(b.points, float)
        t = np.broadcast_to(np.asarray(b.thickness, float), (len(p),))
        for i in range(len(p) - 1):
            w = max(1, int(round(t[i] + t[i + 1])))
            cv2.line(canvas, tuple(np.round(p[i] * 8).astype(int)), tuple(np.round(p[i + 1] * 8).astype(int)),
                     (0, 0, 0), w, cv2.LINE_8, 3)
    return canvas


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    seeds = [int(s) for s in argv[0].split(",")] if argv else [0, 1, 2]
    kinds = argv[1].split(",") if len(argv) > 1 else list(KINDS)
    pngdir = argv[2] if len(argv) > 2 else None
    keys = ("nb", "len", "thin_ex", "thin_out", "thick_ex", "thick_out", "top_ex", "top_out", "hd", "out", "out15",
            "tend_ex", "tend_out", "far_ex", "far_out")
    print_table(kinds, seeds, lambda kind, s: SIZES[(s + KINDS.index(kind)) % len(SIZES)], case, keys,
                lambda r: f"nb {r['nb_ex']:3d}->{r['nb_out']:3d}", pngdir)


if __name__ == "__main__":
    main()
