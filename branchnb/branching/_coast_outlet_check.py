"""Issue-23 figures on roots at the outlets of line maps (branching57).

``python -m branchnb.branching._coast_outlet_check [SEEDS] [KINDS] [PNG_DIR]`` runs the default workflow
(``extract_structure``, ``fit_model(ex, domain=example_domain(img, ex))``, ``synthesize_structure``) on
procedural line maps with known outlets and prints per case (and per kind, mean):

- ``at``: the share of the extracted trees (by length) rooted within 2 strand widths of a true outlet,
  and ``n`` how many of the trees are;
- ``out``: the share of the output's roots within ``max(2 widths, 4 % of the short side)`` of where
  the example drains (the coast, or the frame side of the outlet);
- ``cov``: the coverage gap of :mod:`._coverage_check`, the output's share of the domain within
  ``rho`` of a branch over the example's.

Kinds: ``island``, ``coast``, ``bay`` (:func:`._map_examples.country_map_example`: drawn maps, flat land
and sea, black rivers of one width meeting a black coastline; every river mouth is an outlet),
``paper`` (:func:`._river_outlet_check.river_drawing` with a coast: one river network of one width on
white paper, a flat blue sea below a drawn coast; tributaries crossing one another), ``frame`` (the same
network leaving the bottom or left edge of the frame) and ``crossing`` (:func:`._root_sides_check.root_drawing`
``river``: a one-width network entering from the bottom edge, its tributaries crossing).
Written with absolute imports so that ``PYTHONPATH=/path/to/main python .../_coast_outlet_check.py``
measures another checkout with the same cases.
"""
# ruff: noqa: E501, E702
from __future__ import annotations

import os
import sys

import numpy as np
from scipy import ndimage as ndi

KINDS = ("island", "coast", "bay", "paper", "frame", "crossing")
SIZES = {"island": (400, 800), "coast": (800, 400), "bay": (600, 1000), "paper": (512, 768),
         "frame": (300, 600), "crossing": (320, 420)}


def example(kind: str, size: int, seed: int):
    """``(image, outlets (k, 2), strand width, drain mask)``: the drain mask holds the pixels the
    example drains to (the sea, or a 1-px band along the outlet's frame side)."""
    from branchnb.branching._map_examples import country_map_example
    from branchnb.branching._river_outlet_check import river_drawing
    from branchnb.branching._root_sides_check import root_drawing

    if kind in ("island", "coast", "bay"):
        img, s, land = country_map_example((size, size), seed, layout=kind)
        outlets = np.array([b.points[0] for b in s.branches if b.parent is None])
        return img, outlets, 2.0 * float(s.branches[0].thickness[0]), ~land
    if kind == "paper":
        width = ("even", "taper")[seed % 2]
        img, (ox, oy), coast = river_drawing(width, "coast", size, seed)
        return img, np.array([[ox, oy]]), 2.0 if width == "even" else 5.0, coast
    if kind == "frame":
        edge = ("bottom", "left")[seed % 2]
        img, (ox, oy), _ = river_drawing("even", edge, size, seed)
    else:
        img, ent = root_drawing("river", size, seed)
        ox, oy = ent[0][:2]
    h, w = img.shape[:2]
    drain = np.zeros((h, w), bool)
    d = {"top": oy, "bottom": h - 1 - oy, "left": ox, "right": w - 1 - ox}
    side = min(d, key=d.get)
    {"top": lambda: drain.__setitem__((0, slice(None)), True),
     "bottom": lambda: drain.__setitem__((-1, slice(None)), True),
     "left": lambda: drain.__setitem__((slice(None), 0), True),
     "right": lambda: drain.__setitem__((slice(None), -1), True)}[side]()
    return img, np.array([[ox, oy]]), 2.0, drain


def _tree_lengths(s) -> dict[int, float]:
    out: dict[int, float] = {}
    for i, b in enumerate(s.branches):
        t = i
        while s.branches[t].parent is not None:
            t = int(s.branches[t].parent)
        seg = float(np.hypot(*np.diff(b.points, axis=0).T).sum()) if len(b.points) > 1 else 0.0
        out[t] = out.get(t, 0.0) + seg
    return out


def case(kind: str, size: int, seed: int, png: str | None = None) -> dict:
    from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
    from branchnb.branching.colonization import coverage_fraction

    img, outlets, lw, drain = example(kind, size, seed)
    h, w = img.shape[:2]
    ex = extract_structure(img)
    lengths = _tree_lengths(ex)
    tot = sum(lengths.values())
    at = 0.0
    for t, L in lengths.items():
        p = ex.branches[t].points[0]
        if np.min(np.hypot(*(outlets - p).T)) <= 2.0 * lw:
            at += L
    model = fit_model(ex, domain=example_domain(img, ex))
    res = synthesize_structure(model, rng=seed)
    out = res.structure
    dd = ndi.distance_transform_edt(~drain)
    lim = max(2.0 * lw, 0.04 * min(h, w))
    roots = [b.points[0] for b in out.branches if b.parent is None and len(b.points) >= 2]
    near = [dd[int(np.clip(round(p[1]), 0, h - 1)), int(np.clip(round(p[0]), 0, w - 1))] <= lim for p in roots]
    target = coverage_fraction(model.example, ex.image_shape, model.rho, model.domain)
    cov = coverage_fraction(out, ex.image_shape, model.rho, model.domain) / max(target, 1e-9)
    if png:
        import cv2

        from branchnb.branching._thin_children_check import _draw

        exi, oi = _draw(ex, (h, w)), _draw(out, (h, w))
        for o in outlets:
            cv2.circle(exi, tuple(int(v) for v in np.round(o)), 9, (0.0, 0.7, 0.0), 2)
        for t in lengths:
            cv2.circle(exi, tuple(int(v) for v in np.round(ex.branches[t].points[0])), 6, (1.0, 0.0, 0.0), 2)
        for p in roots:
            cv2.circle(oi, tuple(int(v) for v in np.round(p)), 6, (1.0, 0.0, 0.0), 2)
        cv2.imwrite(png, (np.clip(np.hstack([img[..., :3], exi, oi]), 0, 1) * 255).astype(np.uint8)[..., ::-1])
    return {"at": at / max(tot, 1e-9), "n": len(lengths), "out": float(np.mean(near)) if near else 0.0, "cov": cov}


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    seeds = [int(s) for s in argv[0].split(",")] if argv else [0, 1]
    kinds = argv[1].split(",") if len(argv) > 1 and argv[1] != "all" else list(KINDS)
    pngdir = argv[2] if len(argv) > 2 else None
    if pngdir:
        os.makedirs(pngdir, exist_ok=True)
    for kind in kinds:
        rows = []
        for k, seed in enumerate(seeds):
            size = SIZES[kind][k % len(SIZES[kind])]
            png = os.path.join(pngdir, f"{kind}_{size}_{seed}.png") if pngdir else None
            r = case(kind, size, seed, png)
            rows.append(r)
            print(f"{kind:8s} {size:4d} {seed}  trees {r['n']:2d} at={r['at']:.2f} out={r['out']:.2f} cov={r['cov']:.2f}", flush=True)
        print(f"MEAN {kind:8s} " + " ".join(f"{k}={np.mean([r[k] for r in rows]):.2f}" for k in ("at", "out", "cov")), flush=True)


if __name__ == "__main__":
    main()
