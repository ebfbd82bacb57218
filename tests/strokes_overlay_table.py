"""Multi-part objects edited so that a moved part ends over another part (issue 25), as a table (not a test).

Kinds (procedural, a base nobody stroked and 3-5 stroked tubes, skin-like
shading, with or without a 3 px outline round the union): ``hand`` (palm, four
fingers, thumb), ``trident`` (handle and crossbar, three tines), ``starfish``
(disc, five arms), ``candela`` (a candelabra: stem, a bar, four upright arms).
Edit: one tube bent (its first 45 % kept) so that its tip lies over the
neighbouring tube's end; the others stay.

Per case: ``cover`` (outlined only: share of the moved tube's own outline ring --
as an artist draws it over the neighbour -- that lies over the neighbour's flesh
and is outline-coloured in the result within 1 px), ``ticks`` (px lighter than
the source's lightest flesh + 0.04 over a white background, 1.5 px or more inside
the result's silhouette), ``psnr`` (dB, over white, px farther than two tube widths
from the moved tube's source and target), CPU s.

``PYTHONPATH=. python tests/strokes_overlay_table.py TAG [SIZES...]`` prints the table
(default sizes 300 600; ``SEEDS=0,1``, ``ONLY=hand,...``) and writes PNGs to
``$OUT`` (default ``$TMPDIR/strokes_overlay``).
"""
import os
import sys
import tempfile
import time

import cv2
import numpy as np
from scipy import ndimage as ndi

INK = np.array([0.35, 0.2, 0.12])
SKIN = np.array([0.96, 0.78, 0.62])
KINDS = ("hand", "trident", "starfish", "candela")


def _line(pts, n=24):
    pts = np.asarray(pts, float)
    t = np.linspace(0, 1, n)
    seg = np.r_[0, np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]
    return np.stack([np.interp(t * seg[-1], seg, pts[:, c]) for c in (0, 1)], 1)


def _tube(mask, pts, width):
    for a, b in zip(pts[:-1], pts[1:]):
        cv2.line(mask, tuple(np.int32(np.rint(a))), tuple(np.int32(np.rint(b))), 1, int(width))
    return mask


def layout(kind, S, seed):
    """(base mask, tubes [(points, width)], moved index, neighbour index) at S px."""
    rng = np.random.default_rng(seed)
    k = S / 400
    j = lambda v: v * (1 + 0.06 * rng.standard_normal())  # noqa: E731
    base = np.zeros((S, S), np.uint8)
    tubes = []
    if kind == "hand":
        cv2.ellipse(base, (int(200 * k), int(270 * k)), (int(j(75) * k), int(j(85) * k)), 0, 0, 360, 1, -1)
        for i, bx in enumerate([140, 175, 210, 245]):
            L = j([95, 115, 120, 100][i]) * k
            ang = -np.pi / 2 + (i - 1.5) * 0.12
            p0 = np.array([bx, 210]) * k
            tubes.append((_line([p0, p0 + L * np.array([np.cos(ang), np.sin(ang)])]), j(26) * k))
        tubes.append((_line(np.array([[125, 290], [70, 205]]) * k), 30 * k))
        moved, nb = 1, 0
    elif kind == "trident":
        cv2.rectangle(base, (int(188 * k), int(240 * k)), (int(212 * k), S - 1), 1, -1)
        cv2.rectangle(base, (int(j(110) * k), int(228 * k)), (int(j(290) * k), int(252 * k)), 1, -1)
        for bx in (125, 200, 275):
            p0 = np.array([bx, 240]) * k
            tubes.append((_line([p0, p0 - np.array([0, j(150) * k])]), j(20) * k))
        moved, nb = 0, 1
    elif kind == "starfish":
        c = np.array([200, 200]) * k
        cv2.circle(base, tuple(np.int32(c)), int(j(48) * k), 1, -1)
        a0 = rng.uniform(0, 2 * np.pi)
        for i in range(5):
            a = a0 + 2 * np.pi * i / 5
            d = np.array([np.cos(a), np.sin(a)])
            tubes.append((_line([c + 25 * k * d, c + j(165) * k * d]), j(32) * k))
        moved, nb = 0, 1
    else:
        cv2.rectangle(base, (int(190 * k), int(260 * k)), (int(210 * k), S - 1), 1, -1)
        cv2.rectangle(base, (int(80 * k), int(250 * k)), (int(320 * k), int(270 * k)), 1, -1)
        for bx in (95, 165, 235, 305):
            p0 = np.array([bx, 260]) * k
            tubes.append((_line([p0, p0 - np.array([0, j(170) * k])]), j(22) * k))
        moved, nb = 1, 2
    return base, tubes, moved, nb


def _render(mask, outlined, k):
    dist = cv2.distanceTransform(mask, cv2.DIST_L2, 3)
    rgb = np.where(mask[..., None] > 0, SKIN * np.clip(0.8 + dist[..., None] / (40 * k), 0.8, 1.05), 0)
    if outlined:
        edge = mask - cv2.erode(mask, np.ones((3, 3), np.uint8), iterations=max(1, int(round(1.5 * k))))
        rgb[edge > 0] = INK
    out = np.zeros((*mask.shape, 4), np.float32)
    out[..., :3] = np.clip(rgb, 0, 1)
    out[..., 3] = mask
    return out


def _bent(src, end):
    p0, p1 = src[0], src[int(0.45 * (len(src) - 1))]
    ctrl = 2 * p1 - 0.5 * (p0 + end)
    t = np.linspace(0, 1, len(src))[:, None]
    return (1 - t) ** 2 * p0 + 2 * t * (1 - t) * ctrl + t ** 2 * end


def case(kind, S, seed, outlined=True):
    """(image, source strokes, target strokes, truth) for one case."""
    base, tubes, moved, nb = layout(kind, S, seed)
    k = S / 400
    mask = base.copy()
    for pts, w in tubes:
        _tube(mask, pts, w)
    img = _render(mask, outlined, k)
    src = [p for p, _ in tubes]
    end = tubes[nb][0][int(0.85 * (len(tubes[nb][0]) - 1))]
    tgt = [p.copy() for p in src]
    tgt[moved] = np.clip(_bent(src[moved], end), 2, S - 3)
    w = tubes[moved][1]
    M = _tube(np.zeros((S, S), np.uint8), tgt[moved], w)
    N = _tube(np.zeros((S, S), np.uint8), src[nb], tubes[nb][1])
    ow = max(1, int(round(1.5 * k)))
    ring = (M > 0) & ~(cv2.erode(M, np.ones((3, 3), np.uint8), iterations=ow) > 0)
    under = cv2.erode(N, np.ones((3, 3), np.uint8), iterations=ow + 1) > 0
    far = np.ones((S, S), np.uint8)
    for p in (src[moved], tgt[moved]):
        cv2.polylines(far, [np.int32(p)], False, 0, 1)
    far = cv2.distanceTransform(far, cv2.DIST_L2, 3) > 2 * w + 4
    return img, src, tgt, dict(ring=ring & under & (base == 0), far=far, outlined=outlined)


def _flat(x):
    return x[..., :3] * x[..., 3:] + (1 - x[..., 3:])


def measure(img, res, truth):
    lay = res.layer
    a = lay[..., 3]
    ink = (a > 0.5) & (np.abs(lay[..., :3] - INK).max(axis=2) < 0.15)
    ring = truth["ring"]
    cover = float((ring & ndi.binary_dilation(ink)).sum() / max(ring.sum(), 1)) if truth["outlined"] else np.nan
    lum = _flat(lay).mean(axis=2)
    top = float(np.percentile(img[..., :3].mean(axis=2)[img[..., 3] > 0.5], 99.5))
    inside = ndi.distance_transform_edt(a > 0.02) >= 1.5
    ticks = int((inside & (lum > top + 0.04)).sum())
    far = truth["far"]
    mse = float(np.mean((_flat(lay)[far] - _flat(img)[far]) ** 2))
    psnr = 99.0 if mse < 1e-10 else 10 * np.log10(1 / mse)
    return cover, ticks, psnr


if __name__ == "__main__":
    from branchnb.strokes import edit_structure

    tag = sys.argv[1]
    sizes = [int(v) for v in sys.argv[2:]] or [300, 600]
    seeds = [int(v) for v in os.environ.get("SEEDS", "0,1").split(",")]
    only = os.environ.get("ONLY")
    kinds = only.split(",") if only else KINDS
    folder = os.environ.get("OUT") or os.path.join(tempfile.gettempdir(), "strokes_overlay")
    os.makedirs(folder, exist_ok=True)
    print(f"{'case':28s} cover ticks  psnr   cpu")
    for kind in kinds:
        for S in sizes:
            for seed in seeds:
                for outlined in (True, False):
                    img, src, tgt, truth = case(kind, S, seed, outlined)
                    t0 = time.process_time()
                    res = edit_structure(img, src, tgt, rng=0)
                    cpu = time.process_time() - t0
                    cover, ticks, psnr = measure(img, res, truth)
                    name = f"{kind}_{S}_{seed}_{'ol' if outlined else 'plain'}"
                    print(f"{name:28s} {cover:5.2f} {ticks:5d} {psnr:5.1f} {cpu:5.1f}", flush=True)
                    sheet = np.concatenate([_flat(img), _flat(res.layer)], 1)
                    cv2.imwrite(os.path.join(folder, f"{tag}_{name}.png"),
                                (np.clip(sheet, 0, 1)[..., ::-1] * 255).astype(np.uint8))
