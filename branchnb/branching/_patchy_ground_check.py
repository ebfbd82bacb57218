"""Issue-23 figures on photos whose ground is made of patches (fields, tiles, shading steps): extraction.

``python -m branchnb.branching._patchy_ground_check [SEEDS] [KINDS] [PNG_DIR]`` (e.g. ``0,1 river,vessel``)
makes each :func:`patchy_example` at sizes 256-1024 px and traces it with the defaults
(``extract_structure(rgb)``); it prints per case the traced skeleton's precision ``prec`` (share of the
traced centre lines within 3 px of a true line), its recall ``rec`` (share of true line pixels within 3 px
of the traced structure) and the number of traced branches ``nb`` over the true count of line pieces.
PNG_DIR: example | traced structure.
"""
# ruff: noqa: E702
from __future__ import annotations

import sys

import cv2
import numpy as np

from ._check_table import print_table

#: kind -> (line colour, ground colours of the two field tones, line width scale, field step)
KINDS = {
    "river": ((0.12, 0.2, 0.3), ((0.35, 0.42, 0.22), (0.47, 0.52, 0.28)), 1.0),
    "vessel": ((0.45, 0.08, 0.08), ((0.78, 0.42, 0.3), (0.88, 0.55, 0.38)), 0.7),
    "crack": ((0.12, 0.1, 0.08), ((0.55, 0.48, 0.4), (0.66, 0.6, 0.5)), 0.5),
    "grey": ((0.15, 0.15, 0.15), ((0.55, 0.55, 0.55), (0.68, 0.68, 0.68)), 0.6),
}
SIZES = (256, 384, 512, 768, 1024)


def patchy_example(kind: str, size: int, seed: int):
    """A branching line network of ``kind`` on a ground of wavy fields of two tones; returns
    ``(rgb, line_mask)``."""
    colour, (g0, g1), wscale = KINDS[kind]
    rng = np.random.default_rng(seed)
    s = size
    lines = np.zeros((s, s), np.float32)

    def grow(p, ang, width, depth):
        pts = [np.asarray(p, float)]
        a = ang
        length = rng.uniform(0.25, 0.5) * s * 0.7 ** depth
        for _i in range(int(length / 4)):
            a += rng.normal(0, 0.15)
            pts.append(pts[-1] + 4 * np.array([np.cos(a), np.sin(a)]))
        for i in range(len(pts) - 1):
            w = max(1, int(round(width * (1 - 0.5 * i / len(pts)))))
            cv2.line(lines, tuple(np.int32(pts[i])), tuple(np.int32(pts[i + 1])), 1.0, w, cv2.LINE_AA)
        if depth < 3:
            for _ in range(int(rng.integers(2, 4))):
                j = int(rng.integers(len(pts) // 5, max(len(pts) - 3, len(pts) // 5 + 1)))
                d = pts[min(j + 1, len(pts) - 1)] - pts[j]
                grow(pts[j], np.arctan2(d[1], d[0]) + rng.choice([-1, 1]) * rng.uniform(0.5, 1.0),
                     width * 0.65, depth + 1)

    grow((s / 2 + rng.uniform(-0.15, 0.15) * s, s - 1), -np.pi / 2 + rng.normal(0, 0.2),
         max(2.0, 9 * wscale * s / 600), 0)
    lines = cv2.GaussianBlur(lines, (0, 0), 0.8)
    warp = cv2.GaussianBlur(rng.normal(0, 1, (s, s)).astype(np.float32), (0, 0), 0.033 * s) * 0.1 * s
    cell = rng.uniform(0.11, 0.16) * s
    yy, xx = np.mgrid[:s, :s].astype(np.float32)
    fields = ((np.floor((xx + warp) / cell) + np.floor((yy + 0.7 * warp) / (1.25 * cell))) % 2)[..., None]
    texture = cv2.GaussianBlur(rng.normal(0, 1, (s, s)).astype(np.float32), (0, 0), 2.0)[..., None] * 0.05
    ground = np.asarray(g0, np.float32) * (1 - fields) + np.asarray(g1, np.float32) * fields + texture
    rgb = ground * (1 - lines[..., None]) + np.asarray(colour, np.float32) * lines[..., None]
    rgb = np.clip(rgb + rng.normal(0, 0.015, rgb.shape), 0, 1).astype(np.float32)
    return rgb, lines > 0.5


def _case(kind: str, size: int, seed: int, png: str | None) -> dict:
    from .extraction import extract_structure

    rgb, truth = patchy_example(kind, size, seed)
    s, (_resp, _bw, skel) = extract_structure(rgb, return_maps=True)
    traced = s.render(truth.shape)[..., 0] < 0.5
    near_truth = cv2.dilate(truth.astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
    centre = np.zeros(truth.shape, bool)
    for b in s.branches:
        p = np.clip(np.rint(b.points).astype(int), 0, size - 1)
        centre[p[:, 1], p[:, 0]] = True
    near_trace = cv2.dilate(traced.astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
    if png:
        sheet = np.concatenate([rgb, np.repeat(1.0 - traced[..., None], 3, -1).astype(np.float32)], 1)
        cv2.imwrite(png, (np.clip(sheet, 0, 1)[..., ::-1] * 255).astype(np.uint8))
    return {"prec": float(near_truth[centre].mean()) if centre.any() else 0.0,
            "rec": float(near_trace[truth].mean()) if truth.any() else 1.0,
            "nb": float(len(s.branches))}


def main(argv) -> None:
    seeds = [int(v) for v in argv[1].split(",")] if len(argv) > 1 else [0, 1]
    kinds = argv[2].split(",") if len(argv) > 2 else list(KINDS)
    print_table(kinds, seeds, lambda k, s: SIZES[(s + list(KINDS).index(k)) % len(SIZES)], _case,
                ("prec", "rec", "nb"), lambda r: "", argv[3] if len(argv) > 3 else None)


if __name__ == "__main__":
    main(sys.argv)
