"""Outline pen of mixes against their sources (issue 24), not run by the tests.

``python -m branchnb.trees._measure_pen [libs] [mixes]``: libraries of three procedural drawn
trees stroked with one known pen (:func:`pen_tree`: 1, 2, 3 or 5 px, black or coloured ink,
200-500 px, flat or gradient fills), ``mixes`` random mixes each (and one ``variations_of``);
prints the outline thickness at the inked rim pixels
(:func:`~branchnb.trees.quality_mix.outline_width_spread`: distance from the rim to the
nearest pixel that is not ink) of the sources and of the mixes: mean, q90/q10, and the mixes'
crown and trunk medians, and the ink per rim pixel (:func:`ink_per_rim`) of sources and mixes.
"""

from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage as ndi

#: (pen px, ink RGB, gradient fill, drawing height px)
LIBS = {
    "p1-black-flat-200": (1, (0.02, 0.02, 0.02), False, 200),
    "p2-green-flat-320": (2, (0.05, 0.2, 0.05), False, 320),
    "p3-black-grad-320": (3, (0.02, 0.02, 0.02), True, 320),
    "p5-black-flat-500": (5, (0.02, 0.02, 0.02), False, 500),
    "p3-brown-grad-400": (3, (0.22, 0.1, 0.03), True, 400),
    "p2-black-grad-256": (2, (0.02, 0.02, 0.02), True, 256),
    "p5-blue-grad-480": (5, (0.05, 0.08, 0.3), True, 480),
    "p1-red-flat-300": (1, (0.35, 0.03, 0.03), False, 300),
}


def _stroke(img: np.ndarray, mask: np.ndarray, pen: int, ink) -> None:
    cn, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    lay = np.zeros(img.shape[:2], np.float32)
    cv2.drawContours(lay, cn, -1, 1.0, pen, cv2.LINE_AA)
    a = lay[..., None]
    bare = img[..., 3:4] < 1e-3
    img[..., :3] = np.where(bare, np.asarray(ink, np.float32), img[..., :3] * (1 - a) + np.asarray(ink) * a)
    img[..., 3] = np.maximum(img[..., 3], lay)


def pen_tree(seed: int, height: int = 320, pen: int = 3, ink=(0.02, 0.02, 0.02), gradient: bool = False):
    """A drawn tree (blobby crown of ellipses over a tapered trunk), each part stroked with ``pen``."""
    rng = np.random.default_rng(seed)
    H, W = height, int(height * 0.85)
    img = np.zeros((H, W, 4), np.float32)
    cx = W // 2 + int(rng.integers(-H // 20, H // 20 + 1))
    tw = max(6, int(H * rng.uniform(0.05, 0.09)))
    top, bot = int(H * rng.uniform(0.35, 0.5)), H - int(H * 0.04)
    taper = int(tw * rng.uniform(0, 0.3))
    tmask = np.zeros((H, W), np.uint8)
    poly = np.array([[cx - tw // 2 + taper, top], [cx + tw // 2 - taper, top], [cx + tw // 2 + taper, bot],
                     [cx - tw // 2 - taper, bot]], np.int32)
    cv2.fillPoly(tmask, [poly], 1)
    cmask = np.zeros((H, W), np.uint8)
    ccy = max(int(top * rng.uniform(0.75, 0.95)), int(0.3 * H))
    for _ in range(int(rng.integers(3, 7))):
        c = (int(cx + rng.uniform(-0.22, 0.22) * W), int(ccy + rng.uniform(-0.1, 0.12) * H))
        ax = (int(rng.uniform(0.14, 0.26) * W), int(rng.uniform(0.08, 0.16) * H))
        cv2.ellipse(cmask, c, ax, float(rng.uniform(0, 180)), 0, 360, 1, -1)
    yy, xx = np.mgrid[:H, :W]
    trunk = np.array([0.45, 0.28, 0.12]) * rng.uniform(0.9, 1.2)
    crown = [np.array([0.25, 0.6, 0.2]), np.array([0.5, 0.65, 0.15]), np.array([0.2, 0.55, 0.35])][seed % 3]
    t, m = tmask.astype(bool), cmask.astype(bool)
    s = np.clip(0.8 + 0.4 * (xx - cx + tw / 2) / tw, 0.7, 1.25)[..., None] if gradient else 1.0
    img[t, :3] = (s * trunk * np.ones((H, W, 1)))[t]
    img[t, 3] = 1
    _stroke(img, tmask, pen, ink)
    shade = np.clip(1.25 - np.hypot(xx - cx + 0.15 * W, yy - 0.15 * H) / (0.9 * H), 0.5, 1.2)[..., None] \
        if gradient else 1.0
    img[m, :3] = (shade * crown * np.ones((H, W, 1)))[m]
    img[m, 3] = 1
    _stroke(img, cmask, pen, ink)
    return np.clip(img, 0, 1)


def pen_widths(image, ink=None, parts=None):
    """Outline thickness at the inked rim pixels (as ``outline_width_spread``), and their parts."""
    from .outline import _LUM, _depth, silhouette_outline

    a = image[..., 3] >= 0.5
    o = silhouette_outline(image)
    ink = o.ink if ink is None else np.asarray(ink, np.float32)
    lum = image[..., :3] @ _LUM
    il = float(ink @ _LUM)
    inked = a & (lum <= il + 0.35 * (np.median(lum[a]) - il))
    d = ndi.distance_transform_edt(~(a & ~inked))
    at = (_depth(a) == 1) & inked
    w = d[at]
    keep = w <= 4 * max(o.width, 1) + 2
    p = parts[at][keep] if parts is not None else None
    return w[keep], p


def ink_per_rim(image, ink) -> float:
    """Ink of the outline per rim pixel: the summed ink coverage (between the nearest fill deeper
    than 6 px and ``ink``) of the pixels within 4 px of the silhouette, per rim pixel. Unlike the
    thresholded width it counts a half-inked inner ring as half a pixel (trees33: a 1-px pen's
    mixes read 1.04 against 1.28 in width, the same ink per rim pixel)."""
    from .outline_pen import _coverage, _depth_edt

    a = image[..., 3] >= 0.5
    d = _depth_edt(a)
    deep, band = a & (d > 6), a & (d <= 4)
    if not deep.any() or not band.any():
        return float("nan")
    idx = ndi.distance_transform_edt(~deep, return_distances=False, return_indices=True)
    ys, xs = np.nonzero(band)
    fill = image[idx[0][ys, xs], idx[1][ys, xs], :3].astype(np.float64)
    c, ok = _coverage(image[ys, xs, :3].astype(np.float64), fill, np.asarray(ink, np.float64))
    rim = (d[ys, xs] < 1.5) & ok
    return float(c[ok].sum() / max(int(rim.sum()), 1))


def _fmt(w) -> str:
    if len(w) < 10:
        return "   nan"
    q10, q90 = np.quantile(w, [0.1, 0.9])
    return f"mean {w.mean():.2f} q90/q10 {q90 / q10:.2f}"


def measure(libs=None, mixes: int = 3) -> dict:
    from .variations import TreeLibrary

    out = {}
    for name in libs or LIBS:
        pen, ink, grad, h = LIBS[name]
        lib = TreeLibrary(size=256)
        for k in range(3):
            lib.add(pen_tree(10 * k + len(name), h, pen, ink, grad), f"t{k}")
        src = [pen_widths(e.image)[0] for e in lib.exemplars]
        vs = [lib.variation(rng=s) for s in range(mixes)] + list(lib.variations_of("t0", 1, rng=7))
        ws = [pen_widths(v.image, parts=v.parts) for v in vs]
        sw = np.concatenate(src)
        mw = np.concatenate([w for w, _ in ws])
        crown = np.concatenate([w[p == 1] for w, p in ws])
        trunk = np.concatenate([w[p == 2] for w, p in ws])
        lr = [np.quantile(w, 0.9) / np.quantile(w, 0.1) for w, _ in ws if len(w) >= 10]
        ink_s = np.nanmean([ink_per_rim(e.image, ink) for e in lib.exemplars])
        ink_m = np.nanmean([ink_per_rim(v.image, ink) for v in vs])
        print(f"{name:18s} sources {_fmt(sw)} | mixes {_fmt(mw)} (worst {max(lr):.2f}) | mixes crown median "
              f"{np.median(crown):.2f} trunk {np.median(trunk) if len(trunk) else float('nan'):.2f} | ink per rim px "
              f"sources {ink_s:.2f} mixes {ink_m:.2f}", flush=True)
        out[name] = (sw, mw, crown, trunk)
    return out


if __name__ == "__main__":
    measure(sys.argv[1].split(",") if len(sys.argv) > 1 and sys.argv[1] != "all" else None,
            int(sys.argv[2]) if len(sys.argv) > 2 else 3)
