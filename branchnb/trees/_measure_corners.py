"""Sharp crown tips and rim flecks of flat-art mixes (issue 24), not run by the tests.

``python -m branchnb.trees._measure_corners [size] [seeds] [libs]`` (defaults 384, 3, all): for
libraries of three procedural flat trees (``KINDS``: tiered firs, zig-zag and star-like crowns,
triangular poplars, round and lobed crowns; flat two-tone fills with or without a dark outline;
drawn 200-1000 px tall), ``seeds`` random mixes each at working size ``size``, with the paper's
arc-length correspondence (``old``) and the corner-matched one (``new``), interleaved. Prints per
library: the mean turning angle at the k sharpest tips of the sources and of the mixes (k: the
fewest tips of a mixed source), the tips of the mixes over the mean tips of their sources
(:func:`tip_stats`), flecks per 1000 px of crown rim (:func:`rim_flecks` plus
:func:`hanging_specks`) and the CPU-time ratio new/old (new: corners matched and rim flecks
repainted; old: neither).
"""

from __future__ import annotations

import sys
import time

import cv2
import numpy as np

KINDS = ("fir", "zigzag", "star", "poplar", "round", "lobed")

LIBS = {
    "fir": ("fir", "fir", "fir"),
    "zigzag": ("zigzag", "zigzag", "zigzag"),
    "star": ("star", "star", "star"),
    "poplar": ("poplar", "poplar", "fir"),
    "poly": ("fir", "zigzag", "poplar"),
    "round": ("round", "round", "lobed"),
    "lobed": ("lobed", "lobed", "round"),
}

#: Outlined drawn-tree libraries (:func:`~branchnb.trees.drawn.drawn_tree` kind, seed).
DRAWN = {"drawnA": (("broadleaf", 10), ("fruit", 13), ("conifer", 12)),
         "drawnB": (("palm", 21), ("broadleaf", 22), ("fruit", 23))}


def _crown_polygon(kind: str, r, w: int, h: int) -> list[np.ndarray]:
    """Crown polygons (x, y) of ``kind`` in a ``w`` x ``h`` image."""
    cx, top, bottom = 0.5 * w, 0.05 * h, 0.78 * h
    if kind == "fir":
        n = int(r.integers(3, 6))
        out = []
        for k in range(n):
            t0 = top + (bottom - top) * k / n * 0.85
            t1 = top + (bottom - top) * (k + 1.6) / n * 0.85
            half = w * (0.16 + 0.3 * (k + 1) / n) * r.uniform(0.9, 1.05)
            out.append(np.array([[cx, t0], [cx - half, t1], [cx + half, t1]]))
        return out
    if kind == "poplar":
        half = w * r.uniform(0.18, 0.3)
        return [np.array([[cx + r.uniform(-0.03, 0.03) * w, top], [cx - half, bottom], [cx + half, bottom]])]
    if kind == "zigzag":       # a leaf-shaped crown whose sides are saw-toothed
        n = int(r.integers(4, 8))
        half = w * r.uniform(0.3, 0.42)
        ys = np.linspace(top, bottom, 2 * n + 1)
        prof = np.clip(np.sin(np.pi * (ys - top) / (bottom - top)), 0, 1) ** 0.7
        amp = np.where(np.arange(2 * n + 1) % 2 == 1, 1.0, r.uniform(0.6, 0.75))
        right = np.stack([cx + half * prof * amp, ys], 1)
        left = right[::-1] * [-1, 1] + [2 * cx, 0]
        return [np.vstack([right, left[1:-1]])]
    if kind == "star":         # spiky crown: star polygon round a centre
        n = int(r.integers(6, 11))
        cy = 0.5 * (top + bottom)
        ro, ri = 0.5 * (bottom - top), 0.5 * (bottom - top) * r.uniform(0.5, 0.65)
        a = -np.pi / 2 + np.arange(2 * n) * np.pi / n + r.uniform(-0.15, 0.15)
        rad = np.where(np.arange(2 * n) % 2 == 0, ro, ri) * r.uniform(0.9, 1.05, 2 * n)
        return [np.stack([cx + rad * np.cos(a) * min(1.0, 0.45 * w / ro), cy + rad * np.sin(a)], 1)]
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    cy, rx, ry = 0.42 * (top + bottom), 0.38 * w, 0.5 * (bottom - top) * 0.8
    if kind == "round":
        return [np.stack([cx + rx * np.cos(t), cy + ry * np.sin(t)], 1)]
    out = [np.stack([cx + 0.75 * rx * np.cos(t), cy + 0.75 * ry * np.sin(t)], 1)]
    for a in np.linspace(-np.pi, 0, int(r.integers(4, 7))):
        lr = r.uniform(0.3, 0.4) * rx
        out.append(np.stack([cx + 0.75 * rx * np.cos(a) + lr * np.cos(t),
                             cy + 0.75 * ry * np.sin(a) + lr * np.sin(t)], 1))
    return out


def flat_tree(kind: str, rng, height: int = 420, outline: bool = False) -> np.ndarray:
    """A flat two-tone tree of ``kind`` (RGBA float32, ``height`` px), optionally outlined."""
    r = np.random.default_rng(rng)
    h = int(height)
    w = int(round(h * 0.75))
    ss = 4                                       # drawn 4x and area-averaged: clean anti-aliasing
    big = np.zeros((h * ss, w * ss, 4), np.float32)
    polys = [p * ss for p in _crown_polygon(kind, r, w, h)]
    tw = w * r.uniform(0.04, 0.07)
    trunk = np.array([[0.5 * w - tw, 0.6 * h], [0.5 * w + tw, 0.6 * h], [0.5 * w + tw, 0.97 * h],
                      [0.5 * w - tw, 0.97 * h]]) * ss
    dark = np.array([0.1, 0.38, 0.22]) * r.uniform(0.8, 1.2, 3)
    light = np.clip(dark * 1.45, 0, 1)
    ink = max(1, int(round(0.006 * h * ss))) if outline else 0
    brown = (0.42, 0.27, 0.15, 1.0)
    crown = np.zeros(big.shape[:2], np.uint8)
    for p in polys:
        cv2.fillPoly(crown, [np.int32(p)], 1)
    tr = np.zeros_like(crown)
    cv2.fillPoly(tr, [np.int32(trunk)], 1)
    tr &= 1 - crown
    big[tr > 0] = brown
    xs = np.arange(big.shape[1])[None, :]
    big[crown > 0] = (*dark, 1.0)
    shade = (crown > 0) & (xs > 0.5 * w * ss) & np.ones_like(crown, bool)
    big[shade] = (*light, 1.0)
    if outline:
        for m in (crown, tr):
            cs, _ = cv2.findContours(m, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
            cv2.drawContours(big, cs, -1, (0.05, 0.05, 0.05, 1.0), 2 * ink)
    small = cv2.resize(big, (w, h), interpolation=cv2.INTER_AREA)
    a = small[..., 3:]
    rgb = np.where(a > 1e-4, small[..., :3] / np.maximum(a, 1e-4), 1.0)
    return np.dstack([np.clip(rgb, 0, 1), a]).astype(np.float32)


def _turns(alpha: np.ndarray) -> tuple[np.ndarray, float]:
    """Signed turning angles (tips > 0) at the corners of the largest silhouette's contour."""
    from .corners import _contour_corners
    cs, _ = cv2.findContours((alpha >= 0.5).astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    c = max(cs, key=cv2.contourArea)[:, 0].astype(np.float64)
    c = np.roll(c, -int(np.argmax(c[:, 1])), axis=0)       # start at the foot, away from any tip
    seg = np.hypot(*np.diff(np.vstack([c, c[:1]]), axis=0).T)
    s = np.concatenate([[0], np.cumsum(seg)])
    u = np.linspace(0, s[-1], 1600, endpoint=False)
    cc = np.vstack([c, c[:1]])
    pts = np.stack([np.interp(u, s, cc[:, 0]), np.interp(u, s, cc[:, 1])], 1)
    # only the part above the trunk: the crown's own corners (the trunk's feet are corners too)
    i, t = _contour_corners(pts, (0, 0, len(pts) - 1))
    top = pts[:, 1].min()
    keep = pts[i, 1] < top + 0.7 * np.ptp(pts[:, 1])
    return t[keep], float(s[-1])


def tip_stats(mix_alpha, source_alphas) -> tuple[float, float, float]:
    """(mean turning of the sources' k sharpest tips, the same for the mix, tips kept); k is the
    fewest tips of a source (at least 1); tips kept: the mix's tips at least 0.8 as sharp as the
    sources' median tip, over the mean count of such tips in the sources (0 with no tip)."""
    src = [np.sort(t[t > 0])[::-1] for t, _ in (_turns(a) for a in source_alphas)]
    k = max(1, min(len(t) for t in src))
    mt, _ = _turns(mix_alpha)
    mt = np.sort(mt[mt > 0])[::-1]
    s_mean = float(np.mean([np.pad(t, (0, max(0, k - len(t))))[:k].mean() for t in src]))
    m_mean = float(np.pad(mt, (0, max(0, k - len(mt))))[:k].mean())
    every = np.concatenate(src)
    if every.size == 0:
        return s_mean, m_mean, 0.0
    sharp = 0.8 * float(np.median(every))
    return s_mean, m_mean, float((mt >= sharp).sum() / max(np.mean([(t >= sharp).sum() for t in src]), 1e-9))


def rim_flecks(image, band: int = 6, biggest: int = 6) -> float:
    """Flecks per 1000 px of silhouette rim: specks of at most ``biggest`` px within ``band`` px
    inside the rim that are see-through (alpha < 0.5 inside the silhouette) or pixels with an
    opaque 3 x 3 neighbourhood off its median by more than 0.25 whose colour is outline-dark (max channel < 0.3) or
    background-light (min channel > 0.8)."""
    from scipy.ndimage import median_filter

    img = np.asarray(image, np.float32)
    a = img[..., 3] >= 0.5
    cs, _ = cv2.findContours(a.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    filled = cv2.drawContours(np.zeros(a.shape, np.uint8), cs, -1, 1, -1).astype(bool)
    inner = cv2.erode(filled.astype(np.uint8), np.ones((3, 3), np.uint8), iterations=band).astype(bool)
    zone = filled & ~cv2.erode(filled.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    rim_len = max(int(zone.sum()), 1)
    near = filled & ~inner
    rgb = img[..., :3]
    med = median_filter(rgb, size=(3, 3, 1))
    solid = cv2.erode(a.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)   # no see-through neighbour
    odd = solid & (np.abs(rgb - med).max(axis=2) > 0.25)
    tone = (rgb.max(axis=2) < 0.3) | (rgb.min(axis=2) > 0.8)
    count = 0
    for m in (filled & ~a, odd & tone):
        n, lab, st, _ = cv2.connectedComponentsWithStats(m.astype(np.uint8), connectivity=8)
        small = np.flatnonzero(st[1:, cv2.CC_STAT_AREA] <= biggest) + 1
        if small.size:
            hit = np.unique(lab[near & np.isin(lab, small)])
            count += int((hit > 0).sum())
    return 1000.0 * count / rim_len


def hanging_specks(image) -> float:
    """Dark specks hanging inside the outline, per 1000 px of rim: the outline's thickness ``w`` is
    the median depth of its inner edge (dark pixels next to an opaque lighter one, at most 15 px
    deep); the dark pixels deeper than ``w + 1`` form pieces, and those reaching past ``w + 3`` px,
    at most ``3 w + 1`` deep, ``2 w^2`` px and ``3 w + 1`` across are counted (the rule of
    :func:`~branchnb.trees.flat_art._drop_rim_flecks`, with ``w`` read off the image)."""
    from scipy import ndimage as ndi

    img = np.asarray(image, np.float32)
    a = img[..., 3] >= 0.5
    dark = a & (img[..., :3].max(axis=2) < 0.3)
    filled = ndi.binary_fill_holes(a)
    depth = ndi.distance_transform_edt(np.pad(filled, 1))[1:-1, 1:-1]
    rim_len = max(int((filled & (depth <= 1)).sum()), 1)
    edge = dark & ndi.binary_dilation(a & ~dark, np.ones((3, 3), bool)) & (depth <= 15)
    if not edge.any():
        return 0.0
    w = float(np.median(depth[edge]))
    lab, n = ndi.label(dark & (depth > w + 1.0), structure=np.ones((3, 3), bool))
    if n == 0:
        return 0.0
    idx = np.arange(1, n + 1)
    far = ndi.maximum(depth, lab, idx)
    area = ndi.sum(np.ones_like(depth), lab, idx)
    span = np.array([max(b[0].stop - b[0].start, b[1].stop - b[1].start) for b in ndi.find_objects(lab)])
    hit = (far > w + 3) & (far <= 3 * w + 1) & (area <= max(2 * w * w, 4)) & (span <= 3 * w + 1)
    return 1000.0 * int(hit.sum()) / rim_len


def libraries(outline: bool) -> dict:
    out = {}
    for li, (name, kinds) in enumerate(LIBS.items()):
        r = np.random.default_rng(li + 50 * outline)
        out[name + ("_ol" if outline else "")] = [
            (f"{k}{i}", flat_tree(k, 7 * li + i + 100 * outline, int(r.integers(200, 1001)), outline))
            for i, k in enumerate(kinds)]
    return out


def measure(size: int = 384, seeds: int = 3, only=None) -> dict:
    from . import flat_art as FA
    from . import variations as V
    from .drawn import drawn_tree
    from .variations import TreeLibrary, make_variation

    libs = {**libraries(False), **libraries(True)}
    for name, spec in DRAWN.items():        # outlined drawn trees (as _measure_outline's)
        libs[name] = [(f"{k}{s}", drawn_tree(k, rng=s, size=2 * size)) for k, s in spec]
    if only:
        libs = {k: v for k, v in libs.items() if k in only}
    new_cm, new_fl = V._tip_matched, FA._drop_rim_flecks
    old_cm = lambda cs, w, pins, grains=None, drop=True: ([np.asarray(c, np.float64) for c in cs],) * 2 + ([],)  # noqa: E731
    old_fl = lambda image, ink, width: image  # noqa: E731
    out = {}
    for name, srcs in libs.items():
        lib = TreeLibrary(size=size)
        for n, img in srcs:
            lib.add(img, n)
        row = {"old": [], "new": []}
        cpu = {"old": 0.0, "new": 0.0}
        make_variation(lib, rng=99)                    # warm the caches (stroke maps) for both
        for seed in range(seeds):
            for tag, fn in (("old", old_cm), ("new", new_cm)) if seed % 2 == 0 else (("new", new_cm),
                                                                                     ("old", old_cm)):
                V._tip_matched = fn
                FA._drop_rim_flecks = new_fl if fn is new_cm else old_fl
                t = time.process_time()
                v = make_variation(lib, rng=seed)
                cpu[tag] += time.process_time() - t
                used = [lib.exemplars[i].alpha for i in np.flatnonzero(v.weights > 0)]
                row[tag].append((*tip_stats(v.image[..., 3], used), rim_flecks(v.image) + hanging_specks(v.image),
                                 v.image))
        V._tip_matched, FA._drop_rim_flecks = new_cm, new_fl
        def f(tag, row=row):
            r = row[tag]
            return (f"src {np.mean([x[0] for x in r]):5.1f} mix {np.mean([x[1] for x in r]):5.1f} deg, "
                    f"tips {np.mean([x[2] for x in r]):.2f}, flecks {np.mean([x[3] for x in r]):.2f}")
        same = sum(np.array_equal(a[4], b[4]) for a, b in zip(row["old"], row["new"], strict=True))
        print(f"{name:10s} old: {f('old')} | new: {f('new')} | same {same}/{seeds} | "
              f"cpu new/old {cpu['new'] / cpu['old']:.2f}",
              flush=True)
        out[name] = row
    return out


if __name__ == "__main__":
    measure(int(sys.argv[1]) if len(sys.argv) > 1 else 384, int(sys.argv[2]) if len(sys.argv) > 2 else 3,
            sys.argv[3].split(",") if len(sys.argv) > 3 else None)
