"""Measure: a lightning bolt over several separate objects runs no straight line through
the background (issue 25).

``python -m branchnb.dendrite._multi_bolt_check [sizes] [seeds] [kinds] [outdir]`` stylizes,
with the defaults and ``metaphor="lightning"``, pictures of 2-4 separate objects (``lamp``: a
street lamp and a toadstool on a dusk sky; ``poles``: poles of several heights with round
heads, flat dark on a sky; ``blobs``: textured blobs on white; ``letters``: thick letters on a
sky; ``trees``: textured trees on white) and prints per case, for the main channel: its longest
*straight* run outside the objects (``run``: px, and ``run%``: share of the channel's length;
straight = staying within 0.5 % of the diagonal of its chord, outside = farther than 2 px off
every object), its tortuosity and its mean turn per 10 px against a bolt on a plain canvas of
the same size and seed (``t10/pl``), and its share inside the objects (``in``); and the longest
straight run outside the objects of any branch of the bolt (``brun``, px; a branch is a chain
between forks). With ``outdir`` it writes ``<kind>_<n>_<seed>.png`` (picture | bolt). Not a test.
"""

from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage

from ._bolt_shape_check import _resample, tortuosity, turning

SIZES = (250, 500, 1000)
KINDS = ("lamp", "poles", "blobs", "letters", "trees")


def _sky(h: int, w: int, top, bottom) -> np.ndarray:
    t = np.linspace(0, 1, h)[:, None, None]
    return ((1 - t) * np.array(top) + t * np.array(bottom)) * np.ones((h, w, 3))


def case(kind: str, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """RGB image (``0.8 n`` x ``n``) and the objects' mask."""
    rng = np.random.default_rng(seed)
    h, w = int(0.8 * n), n
    s = n / 480.0
    img = _sky(h, w, (0.25, 0.2, 0.45), (0.95, 0.6, 0.4))
    if kind == "blobs" or kind == "trees":
        img = np.ones((h, w, 3))
    obj = np.zeros((h, w), np.uint8)

    def put(draw, colour):
        m = np.zeros((h, w), np.uint8)
        draw(m)
        img[m > 0] = colour
        obj[m > 0] = 1
        return m > 0

    if kind == "lamp":
        px = int((110 + rng.integers(-30, 30)) * s)
        top = int((120 + rng.integers(-30, 30)) * s)
        dark = (0.12, 0.12, 0.14)
        put(lambda m: cv2.rectangle(m, (px, top), (px + int(12 * s), h - int(10 * s)), 1, -1), dark)
        put(lambda m: cv2.line(m, (px + int(6 * s), top + int(10 * s)),
                               (px + int(60 * s), top - int(20 * s)), 1, max(1, int(8 * s))), dark)
        put(lambda m: cv2.circle(m, (px + int(70 * s), top - int(10 * s)), int(22 * s), 1, -1),
            (0.95, 0.9, 0.5))
        mx, my = int((330 + rng.integers(-20, 40)) * s), int((250 + rng.integers(-20, 20)) * s)
        put(lambda m: cv2.ellipse(m, (mx, my), (int(90 * s), int(55 * s)), 0, 180, 360, 1, -1),
            (0.75, 0.15, 0.1))
        put(lambda m: cv2.rectangle(m, (mx - int(18 * s), my), (mx + int(18 * s), h - int(10 * s)), 1, -1),
            (0.92, 0.88, 0.8))
    elif kind == "poles":
        k = int(rng.integers(2, 5))
        xs = np.linspace(0.15, 0.85, k) * w + rng.uniform(-0.04, 0.04, k) * w
        for x in xs:
            top = int(rng.uniform(0.2, 0.6) * h)
            r = int(rng.uniform(10, 22) * s)
            hw = max(1, int(rng.uniform(3, 8) * s))
            put(lambda m, x=x, top=top, hw=hw: cv2.rectangle(
                m, (int(x) - hw, top), (int(x) + hw, h - int(8 * s)), 1, -1), (0.1, 0.1, 0.12))
            put(lambda m, x=x, top=top, r=r: cv2.circle(m, (int(x), top), r, 1, -1), (0.1, 0.1, 0.12))
    elif kind == "blobs":
        k = int(rng.integers(2, 5))
        y, x = np.mgrid[0:h, 0:w]
        cells = np.linspace(0, w, k + 1)
        for i in range(k):
            cx = 0.5 * (cells[i] + cells[i + 1]) + rng.uniform(-0.05, 0.05) * w
            cy = rng.uniform(0.3, 0.7) * h
            rx = 0.36 * (cells[1] - cells[0]) * rng.uniform(0.7, 1.0)
            ry = min(0.3 * h, rx * rng.uniform(0.8, 1.6))
            th = np.arctan2(y - cy, x - cx)
            m = np.hypot((x - cx) / rx, (y - cy) / ry) < 1 + 0.12 * np.sin(3 * th + rng.uniform(0, 6))
            tex = ndimage.gaussian_filter(rng.standard_normal((h, w)), n / 200)
            grey = np.clip(0.3 + 0.1 * tex / max(tex.std(), 1e-9), 0, 1)
            img[m] = grey[m][:, None] * np.array([1.0, 0.8, 0.6])
            obj[m] = 1
    elif kind == "letters":
        word = "".join(rng.choice(list("AHKMNTXYZ"), int(rng.integers(2, 4))))
        scale = w / (len(word) * 28.0)
        thick = max(2, int(scale * 3))
        (tw, th_), _ = cv2.getTextSize(word, cv2.FONT_HERSHEY_SIMPLEX, scale, thick)
        # spread the letters apart so they are separate objects
        gap = (w - tw) // (len(word) + 1)
        x0 = gap // 2
        for ch in word:
            (cw, _), _ = cv2.getTextSize(ch, cv2.FONT_HERSHEY_SIMPLEX, scale, thick)
            put(lambda m, ch=ch, x0=x0: cv2.putText(m, ch, (x0, (h + th_) // 2), cv2.FONT_HERSHEY_SIMPLEX,
                                                    scale, 1, thick), (0.08, 0.06, 0.05))
            x0 += cw + gap
    elif kind == "trees":
        k = int(rng.integers(2, 4))
        y, x = np.mgrid[0:h, 0:w]
        cells = np.linspace(0, w, k + 1)
        for i in range(k):
            cx = 0.5 * (cells[i] + cells[i + 1]) + rng.uniform(-0.03, 0.03) * w
            foot = 0.95 * h
            height = rng.uniform(0.5, 0.85) * h
            rx = 0.4 * (cells[1] - cells[0]) * rng.uniform(0.7, 1.0)
            ry = min(0.3 * height, 1.3 * rx)
            cy = foot - height + ry
            th = np.arctan2(y - cy, x - cx)
            crown = np.hypot((x - cx) / rx, (y - cy) / ry) < 1 + 0.1 * np.sin(5 * th + rng.uniform(0, 6))
            trunk = (np.abs(x - cx) < 0.1 * rx) & (y > cy) & (y < foot)
            tex = ndimage.gaussian_filter(rng.standard_normal((h, w)), n / 300)
            leaf = np.array([0.25, 0.5, 0.15]) + 0.25 * tex[..., None] / max(tex.std(), 1e-9)
            img[crown] = leaf[crown]
            img[trunk & ~crown] = (0.3, 0.2, 0.12)
            obj[crown | trunk] = 1
    else:
        raise ValueError(f"unknown kind {kind!r}")
    return np.clip(img, 0, 1).astype(np.float32), obj > 0


def straight_run(pts: np.ndarray, outside: np.ndarray, tol: float) -> float:
    """Longest stretch (px) of the polyline ``pts`` outside (``outside`` mask, sampled every
    2 px) that stays within ``tol`` of its chord."""
    q = _resample(np.asarray(pts, float), 2.0)
    if len(q) < 2:
        return 0.0
    ix = np.clip(np.rint(q[:, 0]).astype(int), 0, outside.shape[1] - 1)
    iy = np.clip(np.rint(q[:, 1]).astype(int), 0, outside.shape[0] - 1)
    out = outside[iy, ix]
    best = 0.0
    lab, k = ndimage.label(out)
    for r in range(1, k + 1):
        seg = q[lab == r]
        arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(seg, axis=0).T))])
        j = 0
        for i in range(len(seg)):
            j = max(j, i)
            while j + 1 < len(seg):
                a, b = seg[i], seg[j + 1]
                d = b - a
                ln = max(float(np.hypot(*d)), 1e-9)
                mid = seg[i:j + 2] - a
                dev = np.abs(mid[:, 0] * d[1] - mid[:, 1] * d[0]) / ln
                if dev.max() > tol:
                    break
                j += 1
            best = max(best, float(arc[j] - arc[i]))
    return best


def chains(d) -> list[np.ndarray]:
    """The dendrite's branches: point chains between forks (or root/tips)."""
    parent = d.parent
    kids = np.bincount(parent[parent >= 0], minlength=d.n_nodes)
    out = []
    for tip in np.flatnonzero(kids != 1):  # tips and forks end a chain
        if parent[tip] < 0:
            continue
        chain = [tip]
        node = int(parent[tip])
        while node >= 0:
            chain.append(node)
            if kids[node] != 1 or parent[node] < 0:
                break
            node = int(parent[node])
        out.append(d.points[chain])
    return out


def measure(kind: str, n: int, seed: int, outdir: str | None = None) -> dict:
    from . import stylize
    from .main_channel import main_path

    img, obj = case(kind, n, seed) if kind != "plain" else (
        np.ones((int(0.8 * n), n, 3), np.float32), np.zeros((int(0.8 * n), n), bool))
    r = stylize(img, rng=seed, metaphor="lightning")
    d = r.dendrite
    pts = d.points[main_path(d)]
    diag = float(np.hypot(*obj.shape))
    tol = max(2.0, 0.005 * diag)
    outside = ndimage.distance_transform_edt(~obj) > 2
    length = float(np.hypot(*np.diff(pts, axis=0).T).sum())
    run = straight_run(pts, outside, tol)
    q = _resample(pts, 1.0)
    ix = np.clip(np.rint(q[:, 0]).astype(int), 0, obj.shape[1] - 1)
    iy = np.clip(np.rint(q[:, 1]).astype(int), 0, obj.shape[0] - 1)
    brun = max([straight_run(c, outside, tol) for c in chains(d)] + [0.0])
    if outdir:
        bolt = np.asarray(r.rendering.image, np.float32)[..., :3]
        sheet = np.concatenate([img, bolt], 1)
        cv2.imwrite(f"{outdir}/{kind}_{n}_{seed}.png",
                    (np.clip(sheet, 0, 1)[..., ::-1] * 255).astype(np.uint8))
    return {"run": run, "share": run / max(length, 1e-9), "tort": tortuosity(pts),
            "t10": turning(pts, 10.0), "in": float(obj[iy, ix].mean()), "brun": brun}


def main(sizes=SIZES, seeds=(0, 1), kinds=KINDS, outdir=None) -> None:
    plain = {}
    for n in sizes:
        for seed in seeds:
            plain[n, seed] = measure("plain", n, seed)
            m = plain[n, seed]
            print(f"plain   {n:5d} s{seed} run {m['run']:5.0f} tort {m['tort']:.2f} t10 {m['t10']:4.1f} "
                  f"brun {m['brun']:5.0f}", flush=True)
    for kind in kinds:
        for n in sizes:
            cells = []
            for seed in seeds:
                m = measure(kind, n, seed, outdir)
                cells.append(f"s{seed} run {m['run']:4.0f} {100 * m['share']:3.0f}% tort {m['tort']:.2f} "
                             f"t10/pl {m['t10'] / max(plain[n, seed]['t10'], 1e-9):.2f} in {m['in']:.2f} "
                             f"brun {m['brun']:4.0f}")
            print(f"{kind:7s} {n:5d} | " + " | ".join(cells), flush=True)


if __name__ == "__main__":
    a = sys.argv[1:]
    main(tuple(int(v) for v in a[0].split(",")) if a else SIZES,
         tuple(int(v) for v in a[1].split(",")) if len(a) > 1 else (0, 1),
         tuple(a[2].split(",")) if len(a) > 2 else KINDS,
         a[3] if len(a) > 3 else None)
