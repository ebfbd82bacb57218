"""Rim roughness of mixes of smooth-crowned trees (issue 24), not run by the tests.

``python -m branchnb.trees._measure_rim [size] [seeds]`` (defaults 384, 4): for libraries of four
procedural smooth-blob trees (crowns round, lobed, tall, wide, off-centre; smooth or lightly noisy
outlines; flat, gradient or watercolour fills; drawn at 200-1024 px) and two sample libraries,
``seeds`` random mixes each at working size ``size``; prints per library the rim roughness
(:func:`rim_roughness`) of the roughest source and of each mix, and each mix's largest IoU with a
source (1: a copy of that source).
"""

from __future__ import annotations

import sys

import cv2
import numpy as np

KINDS = ("round", "lobed", "tall", "wide", "offcentre")
FILLS = ("flat", "gradient", "watercolour")


def rim_roughness(alpha, radius: int = 4) -> float:
    """Sawtooth of a silhouette: pixels removed by an opening plus pixels added by a closing with a
    disk of ``radius`` (spikes and notches narrower than ``2 radius``), per pixel of rim."""
    a = (np.asarray(alpha) >= 0.5).astype(np.uint8)
    k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1, 2 * radius + 1))
    a = np.pad(a, 2 * radius)
    spikes = a & ~cv2.morphologyEx(a, cv2.MORPH_OPEN, k)
    notches = cv2.morphologyEx(a, cv2.MORPH_CLOSE, k) & ~a
    rim = a & ~cv2.erode(a, np.ones((3, 3), np.uint8))
    return float((spikes.sum() + notches.sum()) / max(int(rim.sum()), 1))


def blob_tree(kind: str, fill: str, rng, height: int = 420) -> np.ndarray:
    """A tree with a smooth crown of ``kind`` and a trunk, RGBA float32, ``height`` px tall."""
    r = np.random.default_rng(rng)
    h, w = int(height), int(round(height * 0.75))
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    cx, cy = 0.5 * w, 0.33 * h
    rx, ry = {"round": (0.3, 0.22), "lobed": (0.22, 0.15), "tall": (0.2, 0.3), "wide": (0.44, 0.17),
              "offcentre": (0.26, 0.2)}[kind]
    rx, ry = rx * w, ry * h
    if kind == "offcentre":
        cx += r.choice([-1, 1]) * 0.15 * w
    ang = np.arctan2(yy - cy, xx - cx)
    rad = np.hypot((xx - cx) / rx, (yy - cy) / ry)
    noisy = r.random() < 0.5
    phase = r.uniform(0, 2 * np.pi, 3)
    wob = sum(0.03 * noisy / (i + 1) * np.sin((5 + 4 * i) * ang + phase[i]) for i in range(3))
    crown = rad < 1 + wob
    if kind == "lobed":
        for _ in range(int(r.integers(3, 6))):
            a = r.uniform(-np.pi, 0.3)
            lx, ly = cx + 1.0 * rx * np.cos(a), cy + 1.0 * ry * np.sin(a)
            lr = r.uniform(0.45, 0.65) * rx
            crown |= np.hypot(xx - lx, yy - ly) < lr
    crown &= yy < 0.72 * h
    tw = r.uniform(0.04, 0.07) * w
    trunk = (np.abs(xx - 0.5 * w) < tw) & (yy > cy) & (yy < 0.97 * h) & ~crown
    green = np.array([0.25, 0.55, 0.2]) * r.uniform(0.8, 1.2, 3)
    brown = np.array([0.45, 0.3, 0.15])
    if fill == "flat":
        col = np.broadcast_to(green, (h, w, 3))
    elif fill == "gradient":
        t = np.clip((yy - (cy - ry)) / (2 * ry), 0, 1)[..., None]
        col = green * (1.25 - 0.5 * t)
    else:
        wash = cv2.GaussianBlur(r.normal(0, 1, (h, w)).astype(np.float32), (0, 0), 0.03 * h) * 2.5
        edge = crown & ~cv2.erode(crown.astype(np.uint8), np.ones((7, 7), np.uint8)).astype(bool)
        dens = np.clip(0.55 + 0.25 * wash + 0.6 * cv2.GaussianBlur(edge.astype(np.float32), (0, 0), 2.0), 0, 1.2)
        col = (1 - dens[..., None] * (1 - green)) * (1 + 0.05 * r.normal(0, 1, (h, w, 1)))
    rgb = np.where(crown[..., None], col, np.where(trunk[..., None], brown, 1.0))
    alpha = (crown | trunk).astype(np.float32)
    if fill == "watercolour":
        alpha = cv2.GaussianBlur(alpha, (0, 0), 1.2)
    return np.dstack([np.clip(rgb, 0, 1), alpha]).astype(np.float32)


def libraries() -> dict:
    """Name -> list of (name, RGBA) sources: one library per fill, trees of mixed kinds and sizes."""
    out = {}
    for f, fill in enumerate(FILLS):
        for g in range(2):
            r = np.random.default_rng(100 * f + g)
            kinds = r.choice(KINDS, 4, replace=False)
            out[f"{fill}{g}"] = [(f"{k}{i}", blob_tree(k, fill, 10 * f + i + 4 * g, int(r.integers(200, 1025))))
                                 for i, k in enumerate(kinds)]
    return out


def measure(size: int = 384, seeds: int = 4, samples: bool = True) -> dict:
    from .. import data
    from .variations import TreeLibrary, make_variation

    libs = libraries()
    if samples:
        libs["rpg"] = [(n, data.load(n)) for n in ("tree_rpg_05", "tree_rpg_06", "tree_rpg_13")]
        libs["clip"] = [(n, data.load(n)) for n in ("cartoon_tree", "tree_with_fruits", "evergreen")]
    out = {}
    for name, srcs in libs.items():
        lib = TreeLibrary(size=size)
        for n, img in srcs:
            lib.add(img, n)
        rs = max(rim_roughness(e.alpha) for e in lib.exemplars)
        rows = []
        for seed in range(seeds):
            v = make_variation(lib, rng=seed)
            a = v.image[..., 3] >= 0.5
            iou = max(float((a & e.alpha).sum() / max((a | e.alpha).sum(), 1)) for e in lib.exemplars)
            rows.append((rim_roughness(a), iou))
        print(f"{name:12s} roughest source {rs:.3f} | mixes " + " ".join(f"{q:.3f}" for q, _ in rows)
              + f" | max {max(q for q, _ in rows):.3f} | IoU with nearest source "
              + " ".join(f"{i:.2f}" for _, i in rows), flush=True)
        out[name] = (rs, rows)
    return out


if __name__ == "__main__":
    measure(int(sys.argv[1]) if len(sys.argv) > 1 else 384, int(sys.argv[2]) if len(sys.argv) > 2 else 4)
