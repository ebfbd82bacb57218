"""Issue-23 figures on structures that enter from the frame (branching72).

``python -m branchnb.branching._entry_check [SEEDS] [KINDS] [PNG_DIR] [SIZES] [IMAGE]`` draws procedural
structures entering from a known place (:func:`entry_example`), runs the default workflow
(``extract_structure``, ``fit_model``, ``synthesize_structure``, with IMAGE=1 ``synthesize_image``) and
prints per case: ``entry`` the distance of the traced root nearest to the true entry (share of the
short side), ``side`` the mean distance of the output's roots to the entry side (share of the short
side), ``inx`` / ``inq`` the example's / output's share of length running away from the entry side
(segments whose inward component is positive), ``cov`` the output's share of the frame within 5 % of
the diagonal of a line over the example's, ``glow`` the number of glow dots in the output image (local
maxima of the lines' polarity beyond the line colour by > 0.1; -1 without IMAGE). Kinds: ``roots``
(light tapering roots on dark soil from a crown at the top edge), ``tree`` (a dark tree on a light
ground from the bottom edge), ``bolt`` (lightning with a glow from the top), ``river`` (a river network
leaving through the right side, on textured land).
"""
# ruff: noqa: E501, E702
from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage as ndi

from ._check_table import check_args, print_table

KINDS = ("roots", "tree", "bolt", "river")
_SIDE = {"roots": "top", "tree": "bottom", "bolt": "top", "river": "right"}
_INWARD = {"top": (0.0, 1.0), "bottom": (0.0, -1.0), "left": (1.0, 0.0), "right": (-1.0, 0.0)}


def _orient(a: np.ndarray, side: str) -> np.ndarray:
    """A picture drawn entering from the top, turned to enter from ``side``."""
    if side == "bottom":
        return a[::-1].copy()
    if side == "left":
        return np.rot90(a, 1).copy()
    if side == "right":
        return np.rot90(a, -1).copy()
    return a.copy()


def entry_example(kind: str, N: int, seed: int):
    """``(image, truth mask, entry (x, y), side, bright lines)`` of a procedural ``kind`` at ``N`` px."""
    rng = np.random.default_rng(1000 + seed)
    noise = cv2.GaussianBlur(rng.normal(0, 1, (N, N)).astype(np.float32), (0, 0), N / 90)
    noise /= noise.std()
    if kind == "roots":
        ground, col, w0, jit, pull, nprim, spread, bright = (0.28, 0.20, 0.13), (0.88, 0.80, 0.64), 0.02, 0.11, 0.05, 3, 0.55, True
    elif kind == "tree":
        ground, col, w0, jit, pull, nprim, spread, bright = (0.80, 0.84, 0.70), (0.25, 0.17, 0.10), 0.03, 0.09, 0.02, 2, 0.35, False
    elif kind == "bolt":
        ground, col, w0, jit, pull, nprim, spread, bright = (0.08, 0.08, 0.16), (0.95, 0.95, 1.0), 0.008, 0.22, 0.08, 1, 0.2, True
    else:
        ground, col, w0, jit, pull, nprim, spread, bright = (0.42, 0.50, 0.30), (0.15, 0.25, 0.45), 0.015, 0.10, 0.0, 1, 0.3, False
    amp = 0.05 if kind != "bolt" else 0.02
    img = np.stack([g + amp * noise for g in ground], -1).astype(np.float32)
    img += rng.normal(0, 0.015, (N, N, 1)).astype(np.float32)
    lines = np.zeros((N, N, 3), np.float32)
    truth = np.zeros((N, N), np.uint8)
    entry = np.array([N * rng.uniform(0.4, 0.6), 0.0])

    def grow(p, ang, length, w, depth):
        pts = [np.array(p, float)]
        step = max(2.0, N / 160)
        for i in range(int(length / step)):
            ang += rng.normal(0, jit) + pull * np.sin(np.pi / 2 - ang)
            pts.append(pts[-1] + step * np.array([np.cos(ang), np.sin(ang)]))
            if depth < 2 and i > 4 and rng.random() < (0.03 if kind != "river" else 0.05):
                grow(pts[-1], ang + rng.choice([-1, 1]) * rng.uniform(0.5, 1.1), length * 0.5, w * 0.6, depth + 1)
        for k, (a, b) in enumerate(zip(pts[:-1], pts[1:])):
            t = 1 - k / max(1, len(pts))
            ww = max(1, int(round(w * (0.35 + 0.65 * t))))
            cv2.line(lines, tuple(np.int32(a)), tuple(np.int32(b)), (1.0, 1.0, 1.0), ww, cv2.LINE_AA)
            cv2.line(truth, tuple(np.int32(a)), tuple(np.int32(b)), 1, ww)

    for k in range(nprim):
        off = (k - (nprim - 1) / 2) * spread
        grow(entry + (rng.normal(0, N * 0.01), 0), np.pi / 2 + off + rng.normal(0, 0.1), N * 0.8, max(2.0, N * w0), 0)
    cover = lines[..., :1]
    if kind == "bolt":   # a glow round the bolt
        cover = np.maximum(cover, 0.5 * cv2.GaussianBlur(cover[..., 0], (0, 0), 4.0)[..., None])
    img = img * (1 - cover) + np.asarray(col, np.float32) * cover
    img = np.clip(img, 0, 1)
    side = _SIDE[kind]
    mark = np.zeros((N, N), np.uint8)
    mark[0, int(entry[0])] = 1
    mark = _orient(mark, side)
    ey, ex = np.argwhere(mark)[0]
    return _orient(img, side), _orient(truth, side), (float(ex), float(ey)), side, bright


def _side_dist(p, side: str, N: int) -> float:
    x, y = p
    return {"top": y, "bottom": N - 1 - y, "left": x, "right": N - 1 - x}[side]


def _inward_share(s, side: str) -> float:
    n = np.asarray(_INWARD[side])
    d = np.concatenate([np.diff(np.asarray(b.points, float), axis=0) for b in s.branches if len(b.points) >= 2])
    ln = np.hypot(d[:, 0], d[:, 1])
    return float(ln[(d @ n) > 0].sum() / max(ln.sum(), 1e-9))


def _cover(s, N: int) -> float:
    m = np.zeros((N, N), np.uint8)
    for b in s.branches:
        cv2.polylines(m, [np.int32(np.round(b.points))], False, 1, 1)
    return float((ndi.distance_transform_edt(m == 0) <= 0.05 * np.hypot(N, N)).mean())


def glow_dots(image, line_colour, bright: bool) -> int:
    """Blobs of local maxima (5 x 5) of the lines' polarity beyond ``line_colour``'s grey by > 0.1."""
    g = np.asarray(image, np.float32)[..., :3].mean(-1)
    lc = float(np.mean(line_colour))
    v = g if bright else -g
    lv = lc if bright else -lc
    peak = (v >= ndi.maximum_filter(v, 5)) & (v > lv + 0.1)
    return int(ndi.label(ndi.binary_dilation(peak, iterations=2))[1])


def case(kind: str, N: int, seed: int, png, image: bool = False) -> dict:
    from . import extract_structure, fit_model, synthesize_image, synthesize_structure
    img, truth, entry, side, bright = entry_example(kind, N, seed)
    s = extract_structure(img)
    roots = [b for b in s.branches if b.parent is None]
    ent = min(float(np.hypot(*(np.asarray(b.points[0]) - entry))) for b in roots) / N if roots else 1.0
    t = synthesize_structure(fit_model(s), rng=seed).structure
    troots = [b for b in t.branches if b.parent is None]
    sd = float(np.mean([_side_dist(b.points[0], side, N) for b in troots])) / N if troots else 1.0
    out = {"entry": ent, "side": sd, "inx": _inward_share(s, side), "inq": _inward_share(t, side),
           "cov": _cover(t, N) / max(_cover(s, N), 1e-9), "glow": -1.0}
    res = None
    if image:
        res = synthesize_image(img, s, t, rng=seed)
        col = np.median(img[truth > 0], axis=0)
        out["glow"] = float(glow_dots(np.asarray(res.image), col, bright))
    if png:
        sk = np.zeros((N, N, 3), np.float32) + 0.1
        for b in t.branches:
            cv2.polylines(sk, [np.int32(b.points)], False, (0.9, 0.3, 0.3) if b.parent is None else (0.3, 0.6, 1.0), 2)
        for b in troots:
            cv2.circle(sk, tuple(np.int32(b.points[0])), 6, (0, 0.9, 0), -1)
        parts = [img, sk] + ([np.asarray(res.image)[..., :3]] if res is not None else [])
        cv2.imwrite(png, (np.clip(np.concatenate(parts, 1), 0, 1)[..., ::-1] * 255).astype(np.uint8))
    return out


if __name__ == "__main__":
    seeds, kinds, pngdir = check_args(sys.argv[1:4], KINDS, (0, 1, 2))
    sizes = [int(v) for v in sys.argv[4].split(",")] if len(sys.argv) > 4 else [256, 512, 1024]
    image = len(sys.argv) > 5 and sys.argv[5] == "1"
    for size in sizes:
        print_table(kinds, seeds, lambda k, s, n=size: n, lambda k, n, s, png: case(k, n, s, png, image),
                    ("entry", "side", "inx", "inq", "cov", "glow"), lambda r: "", pngdir=pngdir)
