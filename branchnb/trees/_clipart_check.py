"""Clip-art mixes: smear and specks along the outline (issue 24, trees26), not run by the tests.

``python -m branchnb.trees._clipart_check [sizes] [seeds]`` (defaults ``128,256,512`` and 3):
procedural clip-art trees (:func:`clipart_tree`: flat-colour crowns, fruit discs touching the
outline, 1 px or 4 px outlines), mixed three at a time; prints per library and size the sources'
and the mixes' smear (:func:`smear_share`), specks (:func:`specks`), outline q90/q10
(:func:`~branchnb.trees.quality.outline_width_spread`) and cross-fade share.
"""

from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage as ndi
from scipy.spatial import cKDTree

_SS = 4
KINDS = ("round", "cloud", "cone")


def _hsv(h, s, v):
    rgb = cv2.cvtColor(np.array([[[h, s, v]]], np.float32), cv2.COLOR_HSV2RGB)[0, 0]
    return tuple(float(c) for c in rgb)


def _draw(size, shapes):
    """Painter's order at 4x, each shape filled and stroked inside its edge, reduced by area."""
    n = size * _SS
    rgb = np.zeros((n, n, 3), np.float32)
    alpha = np.zeros((n, n), bool)
    for mask, fill, ink, width in shapes:
        rgb[mask] = fill
        alpha |= mask
        if width > 0:
            w = max(1, int(round(width * _SS)))
            m8 = mask.astype(np.uint8)
            inner = cv2.erode(m8, np.ones((2 * w + 1, 2 * w + 1), np.uint8)).astype(bool)
            rgb[mask & ~inner] = ink
    img = np.dstack([rgb * alpha[..., None], alpha.astype(np.float32)])
    img = cv2.resize(img, (size, size), interpolation=cv2.INTER_AREA)
    a = img[..., 3:4]
    img[..., :3] = np.where(a > 1e-6, img[..., :3] / np.maximum(a, 1e-6), 0.0) * (a >= 0.5)
    return np.clip(img, 0, 1).astype(np.float32)


def _poly(n, pts):
    m = np.zeros((n, n), np.uint8)
    cv2.fillPoly(m, [np.round(np.asarray(pts) * _SS).astype(np.int32)], 1)
    return m.astype(bool)


def _disc(n, cx, cy, r):
    m = np.zeros((n, n), np.uint8)
    cv2.circle(m, (int(cx * _SS), int(cy * _SS)), max(1, int(r * _SS)), 1, -1)
    return m.astype(bool)


def clipart_tree(kind: str = "round", *, line: float = 1.0, rng=0, size: int = 256) -> np.ndarray:
    """A flat clip-art tree: one flat crown colour, a thick or thin outline, fruit touching the rim.

    ``kind``: ``"round"`` (an ellipse crown), ``"cloud"`` (a union of discs drawn as one fill),
    ``"cone"`` (a triangle crown with baubles). ``line`` is the outline width in pixels at
    ``size`` (1 or 4 in the check). Half the fruits lie tangent to the crown's outline inside
    (their outlines merge with it), the others inside the crown.
    """
    rng = np.random.default_rng(rng)
    u = rng.uniform
    S = float(size)
    n = size * _SS
    ink = _hsv(u(0, 120), u(0.2, 0.7), u(0.03, 0.15))
    green = _hsv(u(80, 150), u(0.55, 0.95), u(0.45, 0.8))
    bark = _hsv(u(15, 35), u(0.5, 0.8), u(0.3, 0.55))
    fruitc = _hsv(u(0, 50), u(0.8, 1.0), u(0.85, 1.0))
    cx = S / 2 + u(-0.04, 0.04) * S
    foot = S * u(0.93, 0.97)
    wb = S * u(0.06, 0.09)
    if kind == "cone":
        top_y, base_y = S * u(0.05, 0.1), S * u(0.7, 0.76)
        hw = S * u(0.3, 0.38)
        crown = _poly(n, [(cx, top_y), (cx + hw, base_y), (cx - hw, base_y)])
        trunk = _poly(n, [(cx - wb / 2, base_y - 0.02 * S), (cx + wb / 2, base_y - 0.02 * S),
                          (cx + wb / 2, foot), (cx - wb / 2, foot)])
    else:
        ccy = S * u(0.36, 0.42)
        rx, ry = S * u(0.3, 0.38), S * u(0.24, 0.3)
        t0 = ccy + 0.6 * ry
        trunk = _poly(n, [(cx - 0.4 * wb, t0), (cx + 0.4 * wb, t0), (cx + 0.6 * wb, foot), (cx - 0.6 * wb, foot)])
        if kind == "round":
            m = np.zeros((n, n), np.uint8)
            cv2.ellipse(m, (int(cx * _SS), int(ccy * _SS)), (int(rx * _SS), int(ry * _SS)), 0, 0, 360, 1, -1)
            crown = m.astype(bool)
        else:
            crown = np.zeros((n, n), bool)
            for k in range(int(rng.integers(5, 9))):
                a = 2 * np.pi * k / 7 + u(-0.3, 0.3)
                r = min(rx, ry) * u(0.45, 0.6)
                crown |= _disc(n, cx + 0.6 * rx * np.cos(a), ccy + 0.55 * ry * np.sin(a), r)
            crown |= _disc(n, cx, ccy, 0.6 * min(rx, ry))
    shapes = [(trunk, bark, ink, line), (crown, green, ink, line)]
    # fruit: tangent to the crown outline inside (found on the crown's distance map) and inside
    dist = ndi.distance_transform_edt(crown[::_SS, ::_SS])
    fr = S * u(0.035, 0.05)
    ys, xs = np.nonzero(crown[::_SS, ::_SS])
    rim = (np.abs(dist[ys, xs] - fr - line) < 0.7) & (ys < foot - 0.2 * S)
    inner = dist[ys, xs] > 2 * fr + line
    placed = []
    pools = ((np.flatnonzero(rim), int(rng.integers(3, 5))), (np.flatnonzero(inner), int(rng.integers(2, 5))))
    for pool, count in pools:
        for _ in range(count * 8):
            if count == 0 or len(pool) == 0:
                break
            j = pool[int(rng.integers(len(pool)))]
            x, y = xs[j] + 0.5, ys[j] + 0.5
            if all(np.hypot(x - px, y - py) > 2.3 * fr for px, py in placed):
                placed.append((x, y))
                shapes.append((_disc(n, x, y, fr), fruitc, ink, max(1.0, 0.75 * line)))
                count -= 1
    return _draw(size, shapes)


def libraries(size: int, line_sets=((1.0, 1.0, 1.0), (4.0, 4.0, 4.0), (1.0, 4.0, 4.0))):
    """Three libraries of three clip-art trees (one per kind): 1 px, 4 px and mixed outlines."""
    out = {}
    for li, lines in enumerate(line_sets):
        trees = [clipart_tree(k, line=ln * size / 256, rng=100 * li + ki, size=size)
                 for ki, (k, ln) in enumerate(zip(KINDS, lines))]
        out["lines " + "/".join(str(int(x)) for x in lines)] = trees
    return out


def _palette(sources):
    from .quality import dominant_palette

    return dominant_palette(sources)


def smear_share(image, sources, *, tol: float = 0.12, palette=None) -> float:
    """Share of the ink pixels' neighbourhood (within 3 px of ink) that is off the sources' palette
    and not next to an on-palette pixel: a smear 2 px or more wide (an anti-aliased edge, 1 px,
    touches both colours it blends)."""
    from .outline import _ink_threshold, _is_ink

    img = np.asarray(image, np.float32)
    op = img[..., 3] >= 0.5
    pal = _palette(sources) if palette is None else palette
    d, _ = cKDTree(pal).query(img[..., :3].reshape(-1, 3))
    on = (d.reshape(op.shape) <= tol) & op
    rgb = img[..., :3]
    ink = _is_ink(rgb, _ink_threshold(rgb, op)) & op
    off = op & ~on & ~ink
    near_on = cv2.dilate(on.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    near_ink = cv2.dilate(ink.astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
    zone = op & near_ink & ~ink
    return float((off & ~near_on & zone).sum() / max(zone.sum(), 1))


def spill(image, width: float) -> float:
    """Fruit colour (hue < 55 deg, saturation > 0.7, value > 0.75: no crown, bark or ink of
    :func:`clipart_tree` is) within ``1.75 width + 1`` of the silhouette, per rim pixel. The drawings
    keep a fruit's ring and the outline between its fill and the edge (depth >= 1.75 width), so a
    fruit's colour there has run across both strokes: the smear where a fruit touches the outline."""
    from .outline import _depth

    img = np.asarray(image, np.float32)
    op = img[..., 3] >= 0.5
    hsv = cv2.cvtColor(np.ascontiguousarray(img[..., :3]), cv2.COLOR_RGB2HSV)
    fruit = op & (hsv[..., 0] < 55) & (hsv[..., 1] > 0.7) & (hsv[..., 2] > 0.75)
    depth = _depth(op)
    return float((fruit & (depth <= 1.75 * width + 1)).sum() / max((depth == 1).sum(), 1))


def specks(image, *, max_area: float = 4e-4, return_mask: bool = False):
    """Specks: light (fill-coloured) 8-connected pieces of at most ``max_area`` of the opaque
    pixels (>= 2 px), cut off from every fill by ink: flecks of fill left in a thinned stroke.
    Light as in :func:`~branchnb.trees.outline.even_outline`: above half-way from the ink to the
    median colour."""
    from .outline import _LUM, silhouette_outline

    img = np.asarray(image, np.float32)
    op = img[..., 3] >= 0.5
    ink = silhouette_outline(img).ink
    il = float(ink @ _LUM)
    lum = img[..., :3] @ _LUM
    light = op & (lum > il + 0.5 * (np.median(lum[op]) - il))
    cl, k = ndi.label(light, np.ones((3, 3), bool))
    area = np.bincount(cl.ravel(), minlength=k + 1)
    small = area <= max(2.0, max_area * op.sum())
    small[0] = False
    return (int(small.sum()), small[cl]) if return_mask else int(small.sum())


def measure(sizes=(128, 256, 512), seeds: int = 3, show: str | None = None) -> dict:
    from .quality import crossfade_fraction, outline_width_spread
    from .variations import TreeLibrary, make_variation

    res = {}
    for size in sizes:
        for name, trees in libraries(size).items():
            lib = TreeLibrary(size=size)
            for i, t in enumerate(trees):
                lib.add(t, f"clip{i}")
            src = [e.image for e in lib.exemplars]
            pal = _palette(src)
            s_sm = [smear_share(s, src, palette=pal) for s in src]
            s_sp = [specks(s) for s in src]
            lines = [float(x) * size / 256 for x in name.split()[1].split('/')]
            wmin = min(lines)
            s_fr = [spill(s, w) for s, w in zip(src, lines)]
            sm, sp, wr, cf, ims, fr = [], [], [], [], [], []
            for seed in range(seeds):
                v = make_variation(lib, rng=seed)
                sm.append(smear_share(v.image, src, palette=pal))
                sp.append(specks(v.image))
                fr.append(spill(v.image, wmin))
                q = outline_width_spread(v.image)
                wr.append(q[2] / q[0])
                cf.append(crossfade_fraction(v.image, src, palette=pal))
                ims.append(v.image)
            res[(size, name)] = dict(spill=fr, smear=sm, specks=sp, spread=wr, crossfade=cf)
            print(f"{size:4d} {name:12s} src spill {max(s_fr):.4f} smear {max(s_sm):.4f} specks {max(s_sp)} | "
                  f"mixes spill {np.mean(fr):.4f} (max {max(fr):.4f}) smear "
                  f"{np.mean(sm):.4f} (max {max(sm):.4f}) specks {np.mean(sp):.1f} (max {max(sp)}) "
                  f"q90/q10 {np.nanmean(wr):.2f} (max {np.nanmax(wr):.2f}) cross-fade {max(cf):.4f}", flush=True)
            if show:
                row = np.concatenate([*src, *ims], 1)
                a = row[..., 3:]
                row = row[..., :3] * a + (1 - a) * np.array([0.8, 0.8, 1.0])
                tag = name.replace(" ", "_").replace("/", "-")
                cv2.imwrite(f"{show}/clip_{size}_{tag}.png", (row[..., ::-1] * 255).astype(np.uint8))
    return res


if __name__ == "__main__":
    sz = tuple(int(x) for x in sys.argv[1].split(",")) if len(sys.argv) > 1 else (128, 256, 512)
    measure(sz, int(sys.argv[2]) if len(sys.argv) > 2 else 3, sys.argv[3] if len(sys.argv) > 3 else None)
