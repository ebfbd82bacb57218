"""Issue-23 figures of vessel photos through ``synthesize_image`` with the plain defaults (branching59).

``python -m branchnb.branching._vessel_check [SEEDS] [KINDS] [PNG_DIR] [key=value ...]`` (e.g. ``0,1
flat,shaded,matte,vignette``; extra ``key=value`` pairs go to :class:`ImageSynthesisParams`). Each kind is a
procedural photo (:func:`vessel_photo`): dark vessels of 1-6 px on a grainy orange disk, ``flat`` evenly lit,
``shaded`` with a strong light gradient, ``matte`` shaded and vignetted on a black matte, ``vignette`` the
same without the matte; sizes 256-768 px. The example's own structure is known, the target is another
known tree of the same family; per output it prints

- ``pcs``: pieces per target tree in the rendered image (8-connected components of the dark pixels
  inside the target's vessel mask, pieces under 4 px counted too: specks);
- ``gap``: runs of >= 2 px along the target's centre lines that are not dark;
- ``tip``: darkness spread off the vessel (> 2 px beside it, within 5 px) around the target's tips less
  the same 10 px back along the branch, in units of the example's vessel contrast (0 = even; a dark dot at
  the end > 0);
- ``halo``: brightness of a ring 2-4 px beside the vessels above the local ground, in units of the
  example's vessel contrast (0 = none; the example's own is ~0);
- ``sharp``: fine texture of the output's ground (its difference from a 1.5-px blur over its light)
  over the example's;
- ``sec``: seconds of ``synthesize_image``.

"Dark" is a relative darkness ``1 - lum / local ground`` above 0.4 x the example's median on its own
centre lines. PNG_DIR: example | output side by side per case.
"""
# ruff: noqa: E501
from __future__ import annotations

import sys
import time

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.render import draw_polylines
from ..core.structure import Branch, Structure
from ._check_table import image_check_args, print_table, write_pair
from ._image_examples import random_tree, textured_ground

EXTRACTED = True
KINDS = ("flat", "shaded", "vignette", "matte")
SIZES = (256, 384, 512)


def _disk(size, frac=0.47):
    yy, xx = np.mgrid[:size, :size]
    return (xx - size / 2) ** 2 + (yy - size / 2) ** 2 <= (frac * size) ** 2


def _tree(size, seed, dom):
    """A vessel tree of 1-6 px (root r 3, children 1.8, grandchildren ~1) inside ``dom``."""
    s = random_tree((size, size), seed, n_children=6, r_root=2.0 * size / 512 + 1.0, r_child=1.4,
                    grandchildren=3)
    out, keep_ids = [], {}
    for i, b in enumerate(s.branches):
        ij = np.clip(np.round(b.points).astype(int), 0, size - 1)
        inside = dom[ij[:, 1], ij[:, 0]]
        if b.parent is None:
            idx = np.flatnonzero(inside)
            off = idx[0]
            pts, r = b.points[idx[0]:idx[-1] + 1], np.asarray(b.thickness)[idx[0]:idx[-1] + 1]
            keep_ids[i] = (0, off)
            out.append(Branch(pts, r))
            continue
        if b.parent not in keep_ids:
            continue
        cut = np.flatnonzero(~inside)
        n = cut[0] if len(cut) else len(inside)
        pi, poff = keep_ids[b.parent]
        pv = b.parent_vertex - poff
        if n >= 4 and 0 <= pv < len(out[pi].points):
            keep_ids[i] = (len(out), 0)
            out.append(Branch(b.points[:n], np.asarray(b.thickness)[:n], pi, int(pv)))
    return Structure(out, (size, size))


def vessel_photo(kind: str, size: int, seed: int):
    """(image, structure, disk) of one procedural vessel photo (see the module docstring)."""
    rng = np.random.default_rng(seed)
    dom = _disk(size) if kind in ("matte", "vignette") else np.ones((size, size), bool)
    s = _tree(size, 100 + seed, dom)
    ground = textured_ground((size, size), rng, colour=(0.85, 0.42, 0.2))
    ground = 0.4 * ground + 0.6 * ground.reshape(-1, 3).mean(axis=0)      # a fundus's fine grain
    # vessels absorb: their darkness is a share of the local light, drawn before the shading
    # thin vessels are paler (a capillary absorbs less), the photo is slightly soft
    dark = draw_polylines(np.zeros((size, size, 3), np.float32), [b.points for b in s.branches],
                          widths=[2 * np.asarray(b.thickness) for b in s.branches],
                          colors=[(a, a, a) for a in (np.clip(0.5 + 0.15 * np.mean(b.thickness), 0, 0.85)
                                                      for b in s.branches)])[..., :1]
    img = ground * (1 - dark) + dark * np.array([0.5, 0.12, 0.07], np.float32)
    img = cv2.GaussianBlur(img.astype(np.float32), (0, 0), 0.7)
    yy, xx = np.mgrid[:size, :size].astype(np.float32) / size
    if kind == "flat":
        shade = np.ones_like(xx)
    else:
        a = rng.uniform(0, 2 * np.pi)
        shade = 0.75 + 0.5 * ((xx - 0.5) * np.cos(a) + (yy - 0.5) * np.sin(a))
        if kind in ("vignette", "matte"):
            rr = np.hypot(xx - 0.5, yy - 0.5) / 0.47
            shade = shade * np.clip(1.0 - 0.7 * rr ** 3, 0.05 if kind == "matte" else 0.3, 1.0)
    img = img * shade[..., None]
    if kind == "matte":
        a = ndi.gaussian_filter(dom.astype(np.float32), 1.0)[..., None]
        img = img * a
    return np.clip(img, 0, 1).astype(np.float32), s, dom


def _lum(img):
    return np.asarray(img, np.float32)[..., :3].mean(axis=2)


def _darkness(img, mask):
    """Relative darkness ``1 - lum / local ground``, the ground read > 3 px off ``mask``."""
    lum = _lum(img)
    far = ~ndi.binary_dilation(mask, iterations=3)
    sig = max(4.0, mask.shape[0] / 64)
    num = cv2.GaussianBlur((lum * far).astype(np.float32), (0, 0), sig)
    den = cv2.GaussianBlur(far.astype(np.float32), (0, 0), sig)
    ground = num / np.maximum(den, 1e-3)
    return 1.0 - lum / np.maximum(ground, 1e-3), ground, lum


def _mask(s, shape):
    m = draw_polylines(np.zeros(shape + (3,), np.float32), [b.points for b in s.branches],
                       widths=[2 * np.asarray(b.thickness) for b in s.branches], colors=(1, 1, 1))
    return m[..., 0] > 0.3


def _centre(s, step=1.0):
    """Per branch: (points at ``step`` px along it, radii)."""
    out = []
    for b in s.branches:
        p = np.asarray(b.points, float)
        d = np.r_[0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
        t = np.arange(0, d[-1], step)
        r = np.interp(t, d, np.broadcast_to(np.asarray(b.thickness, float), d.shape))
        out.append((np.c_[np.interp(t, d, p[:, 0]), np.interp(t, d, p[:, 1])], r))
    return out


def measure(example, s_ex, out, s_t, dom=None):
    """The figures of one output (see the module docstring)."""
    H, W = out.shape[:2]
    m_ex = _mask(s_ex, example.shape[:2])
    dk_ex, _, _ = _darkness(example, m_ex)
    c_ex = _centre(s_ex)
    ij = np.vstack([np.round(p).astype(int) for p, _ in c_ex])
    ok = (ij[:, 0] >= 0) & (ij[:, 0] < example.shape[1]) & (ij[:, 1] >= 0) & (ij[:, 1] < example.shape[0])
    contrast = float(np.median(dk_ex[ij[ok, 1], ij[ok, 0]]))
    thr = 0.4 * contrast
    m_t = _mask(s_t, (H, W))
    dk, ground, lum = _darkness(out, m_t)
    # darkest within 1 px of the centre line (a centre line half a pixel off is no gap)
    dk_max = ndi.maximum_filter(dk, size=3)
    dark = (dk > thr) & ndi.binary_dilation(m_t, iterations=1)
    lab, n = ndi.label(dark, structure=np.ones((3, 3)))
    pcs = n
    gaps = 0
    tips = []
    for p, r in _centre(s_t):
        q = np.round(p).astype(int)
        inb = (q[:, 0] >= 0) & (q[:, 0] < W) & (q[:, 1] >= 0) & (q[:, 1] < H)
        v = dk_max[q[inb, 1], q[inb, 0]] > thr
        # runs of not-dark samples
        runs = np.diff(np.r_[0, (~v).astype(int), 0])
        starts, ends = np.flatnonzero(runs == 1), np.flatnonzero(runs == -1)
        gaps += int(np.sum(ends - starts >= 2))
        if len(p) > 14 and inb[-1] and inb[-11]:
            tips.append((q[-1], q[-11], float(r[-1])))
    # tip dot: darkness spread off the vessel around its tip, less the same 10 px back along it
    off = ~ndi.binary_dilation(m_t, iterations=2)
    yy, xx = np.mgrid[-6:7, -6:7]
    disk = np.hypot(xx, yy) <= 5

    def spread(c):
        y0, x0 = c[1] - 6, c[0] - 6
        if y0 < 0 or x0 < 0 or y0 + 13 > H or x0 + 13 > W:
            return np.nan
        win = disk & off[y0:y0 + 13, x0:x0 + 13]
        return float(np.mean(np.clip(dk[y0:y0 + 13, x0:x0 + 13][win], 0, None))) if win.any() else np.nan

    tip_d = [spread(a) - spread(b) for a, b, _ in tips]
    tip_d = [t for t in tip_d if np.isfinite(t)]
    # halo: ring 2-4 px beyond the vessel edge vs the local ground, in units of the vessel contrast
    dist = ndi.distance_transform_edt(~m_t)
    ring = (dist >= 2) & (dist <= 4)
    if dom is not None:
        ring &= ndi.binary_erosion(dom, iterations=6)
    rel = lum / np.maximum(ground, 1e-3) - 1.0
    halo = abs(float(np.mean(rel[ring]))) / max(contrast, 1e-3)
    # sharpness: the ground's fine texture relative to its light (so lighting it evenly is no loss),
    # output over example (both away from vessels and matte)
    def grad(img, m, d):
        g = _lum(img)
        fine = np.abs(g - cv2.GaussianBlur(g, (0, 0), 1.5)) / np.maximum(cv2.GaussianBlur(g, (0, 0), 8.0), 1e-2)
        keep = ~ndi.binary_dilation(m, iterations=3)
        if d is not None:
            keep &= ndi.binary_erosion(d, iterations=6)
        return float(np.mean(fine[keep]))

    sharp = grad(out, m_t, dom) / max(grad(example, m_ex, dom), 1e-6)
    return {"pcs": float(pcs), "gap": float(gaps), "tip": float(np.mean(tip_d)) / max(contrast, 1e-3) if tip_d else 0.0,
            "halo": halo, "sharp": sharp}


def _target(size, seed, dom):
    return _tree(size, 500 + seed, dom)


def run_case(kind, size, seed, png=None, params=None):
    from .image_synthesis import _EXAMPLE_CACHE, synthesize_image

    ex, s_ex, dom = vessel_photo(kind, size, seed)
    tgt = _target(size, seed, dom)
    if EXTRACTED:
        # what a user has: the example's extracted structure (centres and radii a fraction off)
        from .extraction import extract_structure

        s_ex = extract_structure(ex)
    _EXAMPLE_CACHE.clear()
    t0 = time.perf_counter()
    res = synthesize_image(ex, s_ex, tgt, params, rng=seed, target_domain=dom if kind == "matte" else None)
    sec = time.perf_counter() - t0
    out = np.asarray(res.image)[..., :3]
    r = measure(ex, s_ex, out, tgt, dom if kind in ("matte", "vignette") else None)
    r["sec"] = sec
    if png:
        write_pair(png, ex, out)
    return r


def main(argv):
    seeds, kinds, pngdir, params = image_check_args(argv)
    kinds = kinds or list(KINDS)
    print_table(kinds, seeds, lambda k, s: SIZES[(KINDS.index(k) + s) % len(SIZES)],
                lambda k, n, s, png: run_case(k, n, s, png, params),
                ("pcs", "gap", "tip", "halo", "sharp", "sec"), lambda r: "", pngdir)


if __name__ == "__main__":
    main(sys.argv[1:])
