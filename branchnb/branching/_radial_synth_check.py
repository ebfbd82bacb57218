"""Issue-23 figures of radial synthesis (branching67): per hub, the primaries leaving it and their spread,
and whether the hub is drawn.

``python -m branchnb.branching._radial_synth_check [SEEDS] [KINDS|all] [PNG_DIR]`` makes each
:func:`._radial_examples.radial_example` (sizes as in :mod:`._hub_check`), extracts, fits and synthesizes
it with the defaults and prints per hub: ``ex``/``syn`` the branches starting within 1.1 hub radii of the
centre (example: its true hubs; synthesized: ``structure.hubs``, else every root's start) and the largest
angular gap between them (degrees, read at 1.3 radii); ``hub`` the radius of the disc of line colour at
the synthesized centre (where the ring median falls below half the line contrast) over the example's
(main: 0.16-0.43, no blob). PNG_DIR: example | synthesized image.
"""
# ruff: noqa: E702
from __future__ import annotations

import sys

import cv2
import numpy as np

from ._hub_check import SIZES
from ._radial_examples import KINDS, radial_example


def _gap(a) -> float:
    return float(np.degrees(np.max(np.diff(np.r_[a, a[0] + 2 * np.pi])))) if len(a) >= 2 else 360.0


def primaries(s, centres, r0: float) -> list[tuple[int, float]]:
    """``(count, largest gap)`` per centre ``(x, y[, r])`` (see the module docstring)."""
    out = []
    for c in centres:
        x, y = c[:2]
        r = c[2] if len(c) > 2 else r0
        a = []
        for b in s.branches:
            d = np.hypot(b.points[:, 0] - x, b.points[:, 1] - y)
            far = np.flatnonzero(d > 1.3 * r)
            if d[0] <= 1.1 * r and far.size:
                p = b.points[far[0]]
                a.append(np.arctan2(p[1] - y, p[0] - x) % (2 * np.pi))
        out.append((len(a), _gap(np.sort(a))))
    return out


def blob_radius(gray: np.ndarray, x: float, y: float, ink: float, ground: float) -> int:
    """Radius of the disc of line colour at ``(x, y)`` (1: none)."""
    yy, xx = np.mgrid[:gray.shape[0], :gray.shape[1]]
    d = np.hypot(xx - x, yy - y)
    for rr in range(1, 80):
        if (np.median(gray[(d >= rr - 0.5) & (d < rr + 0.5)]) - ground) / (ink - ground) < 0.5:
            return rr
    return 80


def case(kind: str, size: int, seed: int, png: str | None = None) -> str:
    from . import extract_structure, fit_model, synthesize_image, synthesize_structure

    rgb, _centre, lines, hubs = radial_example(kind, size, seed)
    s = extract_structure(rgb)
    R = float(np.mean([h[2] for h in hubs]))
    ex = primaries(s, list(hubs), R)
    res = synthesize_structure(fit_model(s), rng=seed)
    sh = getattr(res.structure, "hubs", None)
    sc = list(sh) if sh else [tuple(b.points[0]) for b in res.structure.branches if b.parent is None]
    sy = primaries(res.structure, sc, R)
    im = synthesize_image(rgb, s, res, rng=seed).image
    g = rgb.mean(-1)
    ink = float(np.median(g[lines]))
    ground = float(np.median(g[~(cv2.dilate(lines.astype(np.uint8), np.ones((9, 9), np.uint8)) > 0)]))
    rb = float(np.mean([blob_radius(g, x, y, ink, ground) for x, y, _ in hubs]))
    ratio = [round(blob_radius(im.mean(-1), c[0], c[1], ink, ground) / rb, 2) for c in sc]
    if png:
        vis = np.concatenate([rgb, im], 1)
        cv2.imwrite(f"{png}/{kind}_{seed}.png", (np.clip(vis, 0, 1)[..., ::-1] * 255).astype(np.uint8))
    return (f"{kind:13s} {size:5d} s{seed} ex {[e[0] for e in ex]} gap {[round(e[1]) for e in ex]} | "
            f"syn {[e[0] for e in sy]} gap {[round(e[1]) for e in sy]} | hub {ratio}")


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    seeds = [int(v) for v in (argv[0] if argv else "0,1,2").split(",")]
    kinds = KINDS if len(argv) < 2 or argv[1] == "all" else tuple(argv[1].split(","))
    png = argv[2] if len(argv) > 2 else None
    for kind in kinds:
        for seed in seeds:
            print(case(kind, SIZES[(seed + KINDS.index(kind)) % len(SIZES)], seed, png), flush=True)


if __name__ == "__main__":
    main()
