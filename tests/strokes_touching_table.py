"""Multi-limb objects whose limbs touch or cross, edited with several strokes (issue 25), as a table (not a test).

``octopus``: a round head with eyes and 5-7 tapered outlined tentacles with
light suckers that touch near their roots and cross near their tips (the
outline runs round the union only); edits ``oct_lead`` (one tentacle curled
across the others, another straightened), ``oct_curl``, ``oct_spread`` (two
middle tentacles turned apart). The junction table's ``starfish``,
``hand_turn`` (thumb across the palm), ``hand_bend`` and ``figure`` are
measured alike.

Per edit: ``crack`` (transparent px inside the anti-aliased rim: alpha < 0.1
between two opposite neighbours with alpha >= 0.15, one of them >= 0.5 -- a
light streak in the outline), ``fleck`` (px of pieces not joined to the
object), ``dots`` (small dark pieces inside the flesh, eroded by twice the
outline width + 2, result minus source), ``blob`` (dark px deeper than the outline's
half width + 1 inside a dark region, result minus source), ``light_edge``
(light silhouette px, the junction table's), ``hair`` (outline-coloured px farther than
the outline's width + 2 px inside the silhouette, result minus source: ink hairs and trails), CPU s.

``PYTHONPATH=. python tests/strokes_touching_table.py TAG [SIZES...]`` prints the table
(default sizes 300 500 800; ``SEEDS=0,1``, ``ONLY=oct_lead,...``) and writes PNGs to
``$OUT`` (default ``$TMPDIR/strokes_touching``).
"""
import os
import sys
import tempfile
import time

import cv2
import numpy as np
from scipy import ndimage as ndi

sys.path.insert(0, os.path.dirname(__file__))
from strokes_junction_table import EDITS as JT  # noqa: E402

EIGHT = np.ones((3, 3), bool)


def octopus(S=500, seed=0):
    """(image, strokes, outline width): strokes[0] the head's spine, then one per tentacle."""
    rng = np.random.default_rng(seed)
    k = S / 500
    n_t = int(rng.integers(5, 8))
    body = np.zeros((S, S), np.uint8)
    cx, cy = int(250 * k), int((165 + 10 * rng.uniform()) * k)
    rx, ry = int((85 + 10 * rng.uniform()) * k), int((95 + 10 * rng.uniform()) * k)
    cv2.ellipse(body, (cx, cy), (rx, ry), 0, 0, 360, 255, -1, cv2.LINE_AA)
    strokes = []
    for i in range(n_t):
        a = np.pi * (0.15 + 0.7 * i / (n_t - 1)) + rng.uniform(-0.05, 0.05)
        p0 = np.array([cx + 70 * k * np.cos(a), cy + 60 * k + 30 * k * np.sin(a)])
        pts = [p0]
        d = np.array([np.cos(a), np.sin(a) + 0.6])
        ang = np.arctan2(d[1], d[0])
        bend = rng.uniform(0.02, 0.04) * (1 if i < n_t / 2 else -1)
        for j in range(30):
            ang += bend * (j / 10)
            pts.append(pts[-1] + 8 * k * np.array([np.cos(ang), np.sin(ang)]))
        pts = np.array(pts)
        pts = pts[(pts[:, 0] > 10 * k) & (pts[:, 0] < S - 10 * k) & (pts[:, 1] < S - 10 * k)]
        w0 = rng.uniform(22, 28) * k
        for j in range(len(pts) - 1):
            w = int(max(3, w0 * (1 - j / len(pts))))
            cv2.line(body, tuple(np.int32(pts[j])), tuple(np.int32(pts[j + 1])), 255, w, cv2.LINE_AA)
        strokes.append(pts[::3])
    m = body > 127
    img = np.zeros((S, S, 4), np.float32)
    img[m] = (0.85, 0.35, 0.45, 1)
    yy, xx = np.mgrid[:S, :S]
    shade = np.clip(1 - ((xx - cx + 30 * k) ** 2 + (yy - cy + 40 * k) ** 2) / (150 * k) ** 2, 0, 1)
    img[..., :3][m] *= (0.8 + 0.3 * shade[m])[:, None]
    for pts in strokes:
        for j in range(2, len(pts) - 1):
            rad = max(1, int(5 * k * (1 - j / len(pts))))
            cv2.circle(img, tuple(np.int32(pts[j])), rad, (0.98, 0.8, 0.8, 1), -1, cv2.LINE_AA)
    for ex in (-35, 35):
        cv2.circle(img, (int(cx + ex * k), int(cy - 10 * k)), int(18 * k), (1, 1, 1, 1), -1, cv2.LINE_AA)
        cv2.circle(img, (int(cx + ex * k), int(cy - 6 * k)), int(8 * k), (0.05, 0.05, 0.1, 1), -1, cv2.LINE_AA)
    ow = max(1, int(round(2 * k)))
    edge = m & ~cv2.erode(m.astype(np.uint8), np.ones((2 * ow + 1, 2 * ow + 1), np.uint8)).astype(bool)
    img[edge] = (0.35, 0.08, 0.15, 1)
    img[..., 3] = cv2.GaussianBlur(m.astype(np.float32), (0, 0), 0.7)
    spine = np.array([[cx, cy - 80 * k], [cx, cy + 40 * k]])
    return img, [spine] + strokes, ow


def _clip(strokes, S):
    for tg in strokes:
        tg[:, 0] = np.clip(tg[:, 0], 2, S - 3)
        tg[:, 1] = np.clip(tg[:, 1], 2, S - 3)
    return strokes


def _curl(t, amount):
    base, rel = t[0], t - t[0]
    ang = np.linspace(0, amount, len(t))
    return base + np.stack([rel[:, 0] * np.cos(ang) - rel[:, 1] * np.sin(ang),
                            rel[:, 0] * np.sin(ang) + rel[:, 1] * np.cos(ang)], 1)


def _straight(t):
    L = np.hypot(*np.diff(t, axis=0).T).sum()
    d = (t[3] - t[0]) / np.linalg.norm(t[3] - t[0])
    return t[0] + np.linspace(0, L, len(t))[:, None] * d


def _turn(t, th):
    c, s = np.cos(th), np.sin(th)
    return (t - t[0]) @ np.array([[c, -s], [s, c]]).T + t[0]


def oct_edit(kind, S, seed):
    img, src, ow = octopus(S, seed)
    tgt = [s.copy() for s in src]
    n = len(src) - 1
    if kind in ("oct_lead", "oct_curl"):
        tgt[1] = _curl(src[1], 1.6)
    if kind == "oct_lead":
        tgt[n] = _straight(src[n])
    if kind == "oct_spread":
        a, b = n // 2, n // 2 + 1
        tgt[a] = _turn(src[a], 0.3)
        tgt[b] = _turn(src[b], -0.3)
    return img, src, _clip(tgt, S), ow


def _lum(img):
    return img[..., :3].mean(axis=2)


def _dark_parts(img, ow, thr):
    """(dots px, dots count, blob px) of an RGBA image (see the module's docstring)."""
    a = img[..., 3]
    obj = a > 0.5
    dark = obj & (_lum(img) < thr)
    inner = ndi.binary_erosion(obj, iterations=2 * ow + 2)
    lab, n = ndi.label(dark & inner, structure=EIGHT)
    sizes = np.bincount(lab.ravel())[1:]
    small = sizes <= (3 * ow + 2) ** 2
    # dark pieces touching the inner rim are outline bits reaching in (a stick), counted too
    blob = ndi.binary_erosion(dark, iterations=int(np.ceil(ow / 2)) + 1)
    return int(sizes[small].sum()), int(small.sum()), int(blob.sum())


def touch_measure(src_img, out, ow):
    a = out[..., 3]
    thr = 0.5 * float(np.median(_lum(src_img)[ndi.binary_erosion(src_img[..., 3] > 0.5, iterations=ow + 2)]))
    lo = a < 0.1
    crack = np.zeros(a.shape, bool)
    for ax in (0, 1):
        p, q = np.roll(a, 1, ax), np.roll(a, -1, ax)
        crack |= lo & (np.minimum(p, q) >= 0.15) & (np.maximum(p, q) >= 0.5)
    crack[[0, -1], :] = crack[:, [0, -1]] = False
    lab, npc = ndi.label(a > 0.02, structure=EIGHT)
    sizes = np.bincount(lab.ravel())[1:]
    fleck = int(sizes.sum() - sizes.max()) if npc else 0
    d_r, n_r, b_r = _dark_parts(out, ow, thr)
    d_s, n_s, b_s = _dark_parts(src_img, ow, thr)
    m = a > 0.5
    edge = m & ~ndi.binary_erosion(m)
    light = edge & (_lum(out) > 0.35)
    return dict(crack=int(crack.sum()), fleck=fleck, dots=d_r - d_s, ndots=n_r - n_s, blob=b_r - b_s,
                light_edge=int(light.sum()), hair=_hairs(out, src_img, ow) - _hairs(src_img, src_img, ow))


def _hairs(img, src_img, ow):
    """Outline-coloured px (within 0.12 per channel of the source's rim colour) farther than
    the outline's width + 2 px inside the silhouette: ink hairs and trails on no outline."""
    sa = src_img[..., 3]
    e_s = ndi.distance_transform_edt(sa > 0.5)
    ring = (sa > 0.9) & (e_s <= ow + 0.5)
    if ring.sum() < 10:
        ring = (sa > 0.5) & (e_s <= ow + 0.5)
    col = np.median(src_img[..., :3][ring], axis=0)
    a = img[..., 3]
    ink = (a > 0.5) & (np.abs(img[..., :3] - col).max(axis=2) < 0.12)
    return int((ink & (ndi.distance_transform_edt(a > 0.5) > ow + 2)).sum())


def cases(sizes, seeds, only=None):
    for kind in ("oct_lead", "oct_curl", "oct_spread"):
        for S in sizes:
            for seed in seeds:
                if only is None or kind in only:
                    yield f"{kind} {S} s{seed}", lambda kind=kind, S=S, seed=seed: oct_edit(kind, S, seed)
    for name in ("starfish", "hand_turn", "hand_bend", "figure"):
        for S in sizes:
            if only is None or name in only:
                def make(name=name, S=S):
                    obj, src, tgt, _, _ = JT[name](S)
                    return obj.image, src, tgt, int(np.ceil(obj.outline))
                yield f"{name} {S}", make


if __name__ == "__main__":
    from branchnb.core.image import composite_over
    from branchnb.core.io import encode_png
    from branchnb.strokes import edit_structure

    tag = sys.argv[1]
    sizes = [int(v) for v in sys.argv[2:]] or [300, 500, 800]
    seeds = [int(v) for v in os.environ.get("SEEDS", "0,1").split(",")]
    only = os.environ.get("ONLY")
    only = only.split(",") if only else None
    folder = os.environ.get("OUT") or os.path.join(tempfile.gettempdir(), "strokes_touching")
    os.makedirs(folder, exist_ok=True)
    tot = {}
    for name, make in cases(sizes, seeds, only):
        img, src, tgt, ow = make()
        t0 = time.process_time()
        res = edit_structure(img, src, tgt)
        dt = time.process_time() - t0
        r = touch_measure(img, res.image, ow)
        r["cpu"] = round(dt, 2)
        for key, v in r.items():
            if key != "cpu":
                tot[key] = tot.get(key, 0) + v
        print(f"{name:22s} " + " ".join(f"{key}={v}" for key, v in r.items()), flush=True)
        with open(os.path.join(folder, f"{tag}_{name.replace(' ', '_')}.png"), "wb") as f:
            f.write(encode_png(composite_over(res.image)))
    print("total " + " ".join(f"{key}={v}" for key, v in tot.items()))
