"""Clip-art mixes: smear and specks along the outline (issue 24, trees26), not run by the tests.

``python -m branchnb.trees._clipart_check [sizes] [seeds]`` (defaults ``128,256,512`` and 3):
procedural clip-art trees (:func:`clipart_tree`: flat-colour crowns, fruit discs touching the
outline, 1 px or 4 px outlines), mixed three at a time; prints per library and size the sources'
and the mixes' smear (:func:`smear_share`), specks (:func:`specks`), outline q90/q10
(:func:`~branchnb.trees.quality.outline_width_spread`) and cross-fade share.

``python -m branchnb.trees._clipart_check stretch [sizes] [seeds] [png dir]`` (defaults ``128,256``
and 2): the same trees warped by known stretches against the stretched drawing
(:func:`measure_stretch`, trees27).
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


def _draw(size, shapes, stretch=(1.0, 1.0), pen: bool = False):
    """Painter's order at 4x, each shape filled and stroked inside its edge, reduced by area
    (to ``size`` times ``stretch`` (x, y): the same drawing stretched, a warp's known answer;
    ``pen``: the shapes stretched, then stroked with the same pen, a narrower or flatter tree)."""
    if pen:
        big = (int(round(size * stretch[0])) * _SS, int(round(size * stretch[1])) * _SS)
        shapes = [(cv2.resize(m.astype(np.uint8), big, interpolation=cv2.INTER_NEAREST) > 0, f, k, w)
                  for m, f, k, w in shapes]
    hh, ww = shapes[0][0].shape
    rgb = np.zeros((hh, ww, 3), np.float32)
    alpha = np.zeros((hh, ww), bool)
    for mask, fill, ink, width in shapes:
        rgb[mask] = fill
        alpha |= mask
        if width > 0:
            w = max(1, int(round(width * _SS)))
            m8 = mask.astype(np.uint8)
            inner = cv2.erode(m8, np.ones((2 * w + 1, 2 * w + 1), np.uint8)).astype(bool)
            rgb[mask & ~inner] = ink
    img = np.dstack([rgb * alpha[..., None], alpha.astype(np.float32)])
    out = (int(round(size * stretch[0])), int(round(size * stretch[1])))
    img = cv2.resize(img, out, interpolation=cv2.INTER_AREA)
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


def clipart_tree(kind: str = "round", *, line: float = 1.0, rng=0, size: int = 256,
                 stretch=(1.0, 1.0), pen: bool = False, bark=None) -> np.ndarray:
    """A flat clip-art tree: one flat crown colour, a thick or thin outline, fruit touching the rim.

    ``kind``: ``"round"`` (an ellipse crown), ``"cloud"`` (a union of discs drawn as one fill),
    ``"cone"`` (a triangle crown with baubles). ``line`` is the outline width in pixels at
    ``size`` (1 or 4 in the check). Half the fruits lie tangent to the crown's outline inside
    (their outlines merge with it), the others inside the crown. ``stretch`` (x, y) draws the
    same tree stretched (its strokes too, unless ``pen``), ``size * stretch`` pixels. ``bark``:
    the trunk's RGB (default a random mid brown).
    """
    rng = np.random.default_rng(rng)
    u = rng.uniform
    S = float(size)
    n = size * _SS
    ink = _hsv(u(0, 120), u(0.2, 0.7), u(0.03, 0.15))
    green = _hsv(u(80, 150), u(0.55, 0.95), u(0.45, 0.8))
    drawn = _hsv(u(15, 35), u(0.5, 0.8), u(0.3, 0.55))      # drawn either way: the same tree otherwise
    bark = drawn if bark is None else tuple(bark)
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
    return _draw(size, shapes, stretch, pen)


def libraries(size: int, line_sets=((1.0, 1.0, 1.0), (4.0, 4.0, 4.0), (1.0, 4.0, 4.0)), narrow: bool = False):
    """Three libraries of three clip-art trees (one per kind): 1 px, 4 px and mixed outlines.
    ``narrow``: two more (1 px and 4 px outlines) where the first tree is drawn at 0.45 of its
    width and the cone at 0.6 of its height, so a mix stretches them 1.5-2 times (trees27)."""
    out = {}
    for li, lines in enumerate(line_sets):
        trees = [clipart_tree(k, line=ln * size / 256, rng=100 * li + ki, size=size)
                 for ki, (k, ln) in enumerate(zip(KINDS, lines))]
        out["lines " + "/".join(str(int(x)) for x in lines)] = trees
    if narrow:
        for li, ln in enumerate((1.0, 4.0)):
            stretch = ((0.45, 1.0), (1.0, 1.0), (1.0, 0.6))
            trees = [clipart_tree(k, line=ln * size / 256, rng=300 + 100 * li + ki, size=size, stretch=f,
                                  pen=True)
                     for ki, (k, f) in enumerate(zip(KINDS, stretch))]
            out[f"narrow {int(ln)}/{int(ln)}/{int(ln)}"] = trees
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


def measure(sizes=(128, 256, 512), seeds: int = 3, show: str | None = None, narrow: bool = True) -> dict:
    from .quality import crossfade_fraction, outline_width_spread
    from .variations import TreeLibrary, make_variation

    res = {}
    for size in sizes:
        for name, trees in libraries(size, narrow=narrow).items():
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


#: Stretches of the direct check (x, y): the target this many times the source.
STRETCHES = ((1.5, 1.0), (2.0, 1.0), (2.0, 2.0), (3.0, 1.5))


def stretched(kind: str, line: float, seed: int, size: int, f) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A clip-art tree warped by a known stretch ``f`` (x, y) with ``transfer_colour`` (flat
    sampling), and the answer: the same tree drawn stretched. Returns (source, warped, reference).

    The cage is the source's frame (pixel edges), so the mean value coordinates map is linear and
    a target pixel centre maps to the centre of the source area it covers, as in the drawing's own
    area reduction."""
    from .mvc import transfer_colour

    src = clipart_tree(kind, line=line, rng=seed, size=size)
    ref = clipart_tree(kind, line=line, rng=seed, size=size, stretch=f)
    h, w = src.shape[:2]
    cage = np.array([(-0.5, -0.5), (w - 0.5, -0.5), (w - 0.5, h - 0.5), (-0.5, h - 0.5)])
    tcage = (cage + 0.5) * np.asarray(f, float) - 0.5
    mask = np.ones(ref.shape[:2], bool)
    out = transfer_colour([src], [cage], tcage, mask, colour_weights=[1.0], mode="choose")
    return src, out, ref


def edge_error(out, ref, *, tol: float = 0.2) -> tuple[float, float]:
    """How far a warped drawing is from its answer: PSNR over pixels opaque in both, and the
    pixels off by more than ``tol`` (RGB norm) per pixel of the answer's outline zone (opaque pixels
    within 1 px of an edge between flat colours): a 1 px anti-aliasing error is ~1 per edge pixel
    at most, a smear adds its width."""
    from ..core.metrics import psnr

    both = (out[..., 3] >= 0.5) & (ref[..., 3] >= 0.5)
    err = np.linalg.norm(out[..., :3] - ref[..., :3], axis=2) * both
    rgb = ref[..., :3]
    varies = (ndi.maximum_filter(rgb, (3, 3, 1)) - ndi.minimum_filter(rgb, (3, 3, 1))).max(2) > 0.06
    zone = varies & both
    return float(psnr(out, ref, both)), float((err > tol).sum() / max(zone.sum(), 1))


def measure_stretch(sizes=(128, 256), seeds: int = 2, show: str | None = None) -> dict:
    """Clip-art trees (3 kinds x 1/4 px outlines x ``seeds``) warped by :data:`STRETCHES`: per
    size and stretch the mean PSNR against the stretched drawing, wrong pixels per outline-zone
    pixel (:func:`edge_error`), smear, fruit spill and outline q90/q10 (warped; the answer's).
    trees27 (128/256 px, 2 seeds, mean over 12 trees): PSNR 1.5x1 28.6/31.1 -> 30.6/33.1 dB,
    2x2 27.0/30.0 -> 29.7/33.0, 3x1.5 27.0/30.4 -> 30.2/34.2; wrong pixels per edge pixel
    2x2 0.21/0.20 -> 0.10/0.07; smear 2x2 0.013/0.013 -> 0.002/0.001 (max 0.077 -> 0.007); spill
    as the answer's (2x2 0.030 -> 0.035, answer 0.030, 256 px)."""
    from .quality import outline_width_spread

    res = {}
    for size in sizes:
        for f in STRETCHES:
            ps, wr, sm, fr, fr0, sp, sp0 = [], [], [], [], [], [], []
            crops = []
            for line in (1.0, 4.0):
                for kind in KINDS:
                    for seed in range(seeds):
                        ln = line * size / 256
                        src, out, ref = stretched(kind, ln, 100 * seed + KINDS.index(kind), size, f)
                        p, e = edge_error(out, ref)
                        ps.append(p)
                        wr.append(e)
                        sm.append(smear_share(out, [src]))
                        fr.append(spill(out, ln * min(f)))
                        fr0.append(spill(ref, ln * min(f)))
                        q, q0 = outline_width_spread(out), outline_width_spread(ref)
                        sp.append(q[2] / q[0])
                        sp0.append(q0[2] / q0[0])
                        if show and seed == 0 and kind == "round":
                            crops.append(np.concatenate([ref, out], 1))
            res[(size, f)] = dict(psnr=ps, wrong=wr, smear=sm, spill=fr, spread=sp)
            print(f"{size:4d} stretch {f[0]:.1f}x{f[1]:.1f}  psnr {np.mean(ps):5.2f} (min {min(ps):5.2f}) "
                  f"wrong/edge {np.mean(wr):.3f} (max {max(wr):.3f}) smear {np.mean(sm):.4f} "
                  f"(max {max(sm):.4f}) spill {np.mean(fr):.4f} (answer {np.mean(fr0):.4f}) "
                  f"q90/q10 {np.nanmean(sp):.2f} "
                  f"(answer {np.nanmean(sp0):.2f})", flush=True)
            if show:
                for li, row in enumerate(crops):
                    a = row[..., 3:]
                    row = row[..., :3] * a + (1 - a) * np.array([0.8, 0.8, 1.0])
                    cv2.imwrite(f"{show}/stretch_{size}_{f[0]:.1f}x{f[1]:.1f}_{'14'[li]}px.png",
                                (row[..., ::-1] * 255).astype(np.uint8))
    return res


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "stretch":
        a = sys.argv[2:]
        measure_stretch(tuple(int(x) for x in a[0].split(",")) if a else (128, 256),
                        int(a[1]) if len(a) > 1 else 2, a[2] if len(a) > 2 else None)
        sys.exit()
    sz = tuple(int(x) for x in sys.argv[1].split(",")) if len(sys.argv) > 1 else (128, 256, 512)
    measure(sz, int(sys.argv[2]) if len(sys.argv) > 2 else 3, sys.argv[3] if len(sys.argv) > 3 else None)
