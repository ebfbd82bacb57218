"""Measure lazy snapping on thin veins (issue 22): procedural blades with known vein masks.

Parallel (grass) and palmate venation, pale and dark veins, thin veins 1-3 px
and a 5-px main vein, two sizes, streaked and unevenly lit blades, radius-1
scribbles on the main vein and three thin veins over 40 % of their length.
Prints the grown layer's IoU with the true veins, ``line_weight=0`` (lazy
snapping's colour model alone) against the default, and the CPU time::

    python -m branchnb.leaves._measure_lines
"""

from __future__ import annotations

import time

import cv2
import numpy as np

from ..core.metrics import iou
from .layers import Layer, LayerSet, Scribble, SnapParams, grow_layers

CASES = [(k, light, hw, t) for k in ("parallel", "palmate") for light in (True, False)
         for hw in ((160, 420), (240, 600)) for t in (1, 2, 3)]


def _noise(shape, cell, rng):
    h, w = shape
    g = rng.standard_normal((int(h / cell) + 2, int(w / cell) + 2)).astype(np.float32)
    return cv2.resize(g, (w, h), interpolation=cv2.INTER_CUBIC)


def thin_vein_case(kind="parallel", light=True, h=160, w=420, thin=1, mid=5, rng=0, ss=4):
    """One procedural blade: ``(image, blade, true veins, scribbles)``.

    Parameters
    ----------
    kind : {"parallel", "palmate"}
        Venation.
    light : bool
        Veins paler (True) or darker than the blade.
    h, w : int
        Image size.
    thin, mid : float
        Widths (px) of the thin veins and of the main vein.
    rng : int
        Seed.
    ss : int
        Supersampling of the drawn veins.

    Returns
    -------
    tuple

    Examples
    --------
    >>> img, blade, veins, scribbles = thin_vein_case(h=60, w=120)
    >>> img.shape, len(scribbles)
    ((60, 120, 3), 4)
    """
    rng = np.random.default_rng(rng)
    lines = []
    if kind == "parallel":
        cy = h / 2
        spacing = rng.uniform(9, 14)
        ys = np.unique(np.round(np.concatenate([np.arange(cy % spacing + 4, h - 4, spacing), [cy]]), 1))
        xs = np.linspace(8, w - 8, 60)
        for y in ys:
            if 1 <= abs(y - cy) < spacing * 0.6:
                continue
            yy = y + 1.5 * np.sin(xs / w * 2 * np.pi * rng.uniform(0.3, 1) + rng.uniform(0, 6))
            lines.append((np.stack([xs, yy], 1), mid if abs(y - cy) < 1 else thin))
        blade = np.zeros((h, w), bool)
        blade[6:h - 6, 6:w - 6] = True
    else:
        bx, by = w * 0.15, h * 0.5
        b = np.zeros((h, w), np.uint8)
        cv2.ellipse(b, (int(w * 0.5), int(h / 2)), (int(w * 0.46), int(h * 0.46)), 0, 0, 360, 1, -1)
        blade = b.astype(bool)
        for k, a in enumerate(np.linspace(-0.9, 0.9, 7)):
            s = np.linspace(0, w * 0.8 if k == 3 else w * 0.5, 60)
            lines.append((np.stack([bx + s * np.cos(a * 0.6), by + s * np.sin(a * 0.6) * (h / w) * 2.2], 1),
                          mid if k == 3 else thin))
    cov = np.zeros((h * ss, w * ss), np.uint8)
    main = np.zeros_like(cov)
    for pts, wid in lines:
        p = (pts * ss).round().astype(np.int32)
        cv2.polylines(main if wid == mid else cov, [p], False, 255, thickness=max(1, int(round(wid * ss))))
    c = cv2.resize(np.maximum(cov, main).astype(np.float32) / 255, (w, h), interpolation=cv2.INTER_AREA)
    cm = cv2.resize(main.astype(np.float32) / 255, (w, h), interpolation=cv2.INTER_AREA)
    truth = (c > 0.5) & blade
    shade = 1 + 0.10 * _noise((h, w), 60, rng) + 0.08 * np.linspace(-1, 1, w)[None]
    st = rng.standard_normal((h, w)).astype(np.float32)
    st = cv2.GaussianBlur(st, (0, 0), sigmaX=8, sigmaY=0.7) * 4 if kind == "parallel" else \
        cv2.GaussianBlur(st, (0, 0), 1.2) * 2
    tex = 0.02 * rng.standard_normal((h, w)).astype(np.float32) + 0.03 * st
    img = np.array([0.42, 0.52, 0.33], np.float32) * shade[..., None] + tex[..., None]
    sgn = 1 if light else -1
    img = img + np.array([0.07, 0.07, 0.04], np.float32) * sgn * (c - cm)[..., None] \
        + np.array([0.2, 0.2, 0.1], np.float32) * sgn * cm[..., None]
    img = cv2.GaussianBlur(img.astype(np.float32), (0, 0), 0.6)
    img = np.clip(np.where(blade[..., None], img, 1.0), 0, 1).astype(np.float32)
    order = np.argsort([-wid for _, wid in lines], kind="stable")
    scribbles = []
    for i in [order[0]] + list(rng.choice(order[1:], 3, replace=False)):
        pts = lines[i][0]
        q = pts[int(len(pts) * 0.3):int(len(pts) * 0.7)]
        q = q[blade[q[:, 1].astype(int).clip(0, h - 1), q[:, 0].astype(int).clip(0, w - 1)]]
        scribbles.append(Scribble(q, 1.0))
    return img, blade, truth, scribbles


def main() -> None:
    for lw in (0.0, SnapParams().line_weight):
        out, cpu = [], 0.0
        for i, (k, light, (h, w), t) in enumerate(CASES):
            img, blade, truth, scr = thin_vein_case(k, light, h, w, thin=t, rng=i)
            t0 = time.process_time()
            m = grow_layers(img, blade, LayerSet([Layer("veins", scribbles=scr)]),
                            SnapParams(line_weight=lw)).masks["veins"]
            cpu += time.process_time() - t0
            out.append(iou(m, truth))
        print(f"line_weight={lw}: IoU mean {np.mean(out):.3f} min {np.min(out):.3f} "
              f"(parallel {np.mean(out[:12]):.3f}, palmate {np.mean(out[12:]):.3f}); CPU {cpu:.1f} s")


if __name__ == "__main__":
    main()
