"""Dark specks at junctions after stroke edits (issue 25), as a table (not a test).

``PYTHONPATH=. python tests/strokes_speck_table.py TAG [SIZES...]`` draws RGBA
multi-part objects with light fills on a transparent background -- ``antler``
(a curved beam with 3-5 tapering tines), ``candelabra`` (a trunk with arms
turning up), ``twig`` (a thin stem with side shoots) -- whose anti-aliased rim
carries no colour of its own (black under a soft alpha, as many matted
cut-outs), bends the main stroke with only it stroked (the others carried) and
prints per object, size and seed the dark speck px: visible px darker by more
than 0.15 than the median of the object px within 3 px (fill and rim alike), in
a dark piece of at most 8 px, within 3 px of a junction (the parent's half
width round the junction point + 3 px). ``JUNCTION=1`` also runs the
edits of ``strokes_junction_table.py``. PNGs go to ``$OUT`` (default
``$TMPDIR/strokes_speck_table``).
"""
import os
import sys
import tempfile
import time

import cv2
import numpy as np
from scipy import ndimage as ndi

from branchnb.core.image import composite_over
from branchnb.core.io import encode_png
from branchnb.strokes import edit_structure
from branchnb.strokes.parts import carry_stroke


def _curve(p0, p1, p2, n=40):
    t = np.linspace(0, 1, n)[:, None]
    return (1 - t) ** 2 * p0 + 2 * (1 - t) * t * p1 + t ** 2 * p2


def _paint(n, strokes, widths, colour, rng):
    """RGBA: ``strokes`` drawn with tapering ``widths``, a grooved fill darker at the rim,
    RGB black outside the hard mask under a blurred alpha."""
    hard = np.zeros((n, n), np.uint8)
    for pts, (w0, w1) in zip(strokes, widths):
        for j in range(len(pts) - 1):
            w = w0 + (w1 - w0) * j / (len(pts) - 1)
            cv2.line(hard, tuple(np.int32(pts[j])), tuple(np.int32(pts[j + 1])), 1, max(1, int(w)))
    a = hard > 0
    k = n / 500
    groove = cv2.GaussianBlur(rng.normal(0, 1, (n, n)).astype(np.float32), (0, 0), 1.2 * k)
    dist = cv2.distanceTransform(hard, cv2.DIST_L2, 3)
    col = np.asarray(colour, np.float32) + 0.05 * groove[..., None]
    col = col * np.clip(0.75 + dist[..., None] / (12 * k), 0.75, 1.05)
    img = np.zeros((n, n, 4), np.float32)
    img[..., :3] = np.where(a[..., None], np.clip(col, 0, 1), 0)
    img[..., 3] = cv2.GaussianBlur(a.astype(np.float32), (0, 0), 0.6)
    return img


def antler(n, seed):
    rng = np.random.default_rng(seed)
    k = n / 500
    beam = _curve(np.array([250, 470]) * k, np.array([120 + 20 * rng.normal(), 300]) * k, np.array([260, 60]) * k)
    tines = []
    for f in np.sort(rng.uniform(0.2, 0.85, rng.integers(3, 6))):
        side = rng.choice([-1, 1])
        i = int(f * (len(beam) - 1))
        p = beam[i]
        tang = beam[i + 1] - beam[i - 1]
        tang /= np.linalg.norm(tang)
        d = rng.uniform(0.7, 0.95) * np.array([-tang[1], tang[0]]) * side + 0.5 * tang
        L = rng.uniform(70, 110)
        tines.append(_curve(p, p + d * L * k * 0.6, p + (d + 0.4 * tang) * L * k))
    img = _paint(n, [beam] + tines, [(34 * k, 14 * k)] + [(18 * k, 4 * k)] * len(tines), (0.78, 0.68, 0.52), rng)
    bent = _curve(np.array([250, 470]) * k, np.array([60, 280]) * k, np.array([150, 50]) * k)
    return img, beam, tines, bent


def candelabra(n, seed):
    rng = np.random.default_rng(seed)
    k = n / 500
    trunk = np.c_[np.full(30, 250.0), np.linspace(480, 60, 30)] * k
    arms = []
    for f, side in zip(np.sort(rng.uniform(0.25, 0.7, 3)), (-1, 1, -1)):
        p = trunk[int(f * 29)]
        out = p + np.array([side * rng.uniform(60, 90), -10]) * k
        arms.append(_curve(p, out, out + np.array([0, -rng.uniform(80, 130)]) * k))
    img = _paint(n, [trunk] + arms, [(40 * k, 36 * k)] + [(20 * k, 18 * k)] * 3, (0.55, 0.75, 0.5), rng)
    bent = _curve(trunk[0], np.array([330, 270]) * k, np.array([230, 60]) * k)
    return img, trunk, arms, bent


def twig(n, seed):
    rng = np.random.default_rng(seed)
    k = n / 500
    stem = _curve(np.array([60, 420]) * k, np.array([250, 300]) * k, np.array([450, 120]) * k)
    shoots = []
    for f in np.sort(rng.uniform(0.2, 0.8, 4)):
        i = int(f * (len(stem) - 1))
        p = stem[i]
        tang = stem[i + 1] - stem[i - 1]
        tang /= np.linalg.norm(tang)
        side = rng.choice([-1, 1])
        d = 0.8 * np.array([-tang[1], tang[0]]) * side + 0.6 * tang
        shoots.append(_curve(p, p + d * 40 * k, p + (d + 0.3 * tang) * 70 * k))
    img = _paint(n, [stem] + shoots, [(14 * k, 8 * k)] + [(8 * k, 3 * k)] * len(shoots), (0.85, 0.8, 0.7), rng)
    bent = _curve(stem[0], np.array([200, 200]) * k, stem[-1])
    return img, stem, shoots, bent


OBJECTS = {"antler": antler, "candelabra": candelabra, "twig": twig}


def specks(res, points, radii, *, level=0.15, maxsize=8):
    """Dark speck px of ``res`` (RGBA or RGB over white) within ``radii`` px of ``points``."""
    a = res[..., 3] if res.shape[-1] == 4 else np.ones(res.shape[:2], np.float32)
    rgb = res[..., :3] * a[..., None] + (1 - a[..., None]) if res.shape[-1] == 4 else res[..., :3]
    lum = rgb @ np.array([0.299, 0.587, 0.114], np.float32)
    obj = a > 0.5
    yy, xx = np.mgrid[:a.shape[0], :a.shape[1]]
    near = np.zeros(a.shape, bool)
    for (x, y), r in zip(points, radii):
        near |= np.hypot(xx - x, yy - y) <= r
    cand = near & (a > 0.05)
    pad = np.pad(np.where(obj, lum, np.nan), 3, constant_values=np.nan)
    win = np.lib.stride_tricks.sliding_window_view(pad, (7, 7))
    ys, xs = np.nonzero(cand)
    dark = np.zeros(a.shape, bool)
    if len(ys):
        with np.errstate(all="ignore"):
            import warnings
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                med = np.nanmedian(win[ys, xs].reshape(len(ys), -1), axis=1)
        dark[ys, xs] = lum[ys, xs] < med - level
    lab, npc = ndi.label(dark, np.ones((3, 3)))
    sizes = np.bincount(lab.ravel())[1:]
    return int(sizes[sizes <= maxsize].sum())


def junction_specks(res):
    a = res.layer[..., 3]
    e = ndi.distance_transform_edt(a > 0.5)
    pts, radii = [], []
    for j in res.junctions:
        x, y = np.asarray(j.point, float)
        yi, xi = int(np.clip(round(y), 0, a.shape[0] - 1)), int(np.clip(round(x), 0, a.shape[1] - 1))
        pts.append((x, y))
        radii.append(float(e[yi, xi]) + 3.0)
    return specks(res.layer, pts, radii)


def main():
    tag = sys.argv[1]
    sizes = [int(v) for v in sys.argv[2:]] or [300, 600, 1000]
    folder = os.environ.get("OUT") or os.path.join(tempfile.gettempdir(), "strokes_speck_table")
    os.makedirs(folder, exist_ok=True)
    total = 0
    for name, make in OBJECTS.items():
        for n in sizes:
            for seed in (0, 1):
                img, main_st, kids, bent = make(n, seed)
                src = [main_st] + kids
                tgt = [bent] + [carry_stroke(c, main_st, bent) for c in kids]
                t0 = time.process_time()
                res = edit_structure(img, src, tgt)
                dt = time.process_time() - t0
                s = junction_specks(res)
                total += s
                print(f"{name:10s} {n:5d} seed={seed} specks={s} cpu={dt:.2f}", flush=True)
                with open(os.path.join(folder, f"{tag}_{name}_{n}_{seed}.png"), "wb") as f:
                    f.write(encode_png(composite_over(res.image)))
    if os.environ.get("JUNCTION"):
        sys.path.insert(0, os.path.dirname(__file__))
        from strokes_junction_table import EDITS
        for name, ed in EDITS.items():
            for n in sizes:
                obj, src, tgt, _, _ = ed(n)
                res = edit_structure(obj.image, src, tgt)
                s = junction_specks(res)
                total += s
                print(f"{name:10s} {n:5d} specks={s}", flush=True)
    print(f"total specks={total}")


if __name__ == "__main__":
    main()
