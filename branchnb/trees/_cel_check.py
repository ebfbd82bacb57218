"""Outlined cel-shaded game trees with a soft cast shadow (issue 24, beyond the paper), not run by
the tests: do mixes keep the outline round crown and trunk, at the sources' width?

``python -m branchnb.trees._cel_check [SIZES] [OUTLINES]`` builds libraries of three
:func:`cel_tree` per size and outline width (with and without shadow; hard-edged, and drawn 4x
larger and reduced: anti-aliased), makes three random variations and two ``variations_of`` with the
defaults and prints the outline coverage of crown and trunk (:func:`outline_figures`) and the
mixes' outline width over the sources'.
"""

from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage as ndi

INK = np.array((0.07, 0.06, 0.05), np.float32)
BARK = np.array((0.5, 0.33, 0.18), np.float32)


def cel_tree(size: int = 256, outline: int = 1, shadow: bool = True, rng=0, aa: bool = False) -> np.ndarray:
    """A ``size`` px RGBA game tree: 3-5 overlapping crown circles in three cel tones split along a
    diagonal, a two-tone trunk, an ``outline`` px dark outline round both and (``shadow``) a soft
    cast-shadow ellipse (alpha <= 0.3) at the foot. ``aa``: drawn 4x larger and reduced (anti-aliased)."""
    if aa:
        big = cel_tree(size * 4, outline * 4, shadow, rng)
        pre = np.dstack([big[..., :3] * big[..., 3:], big[..., 3]])
        sm = cv2.resize(pre, (size, size), interpolation=cv2.INTER_AREA)
        a = sm[..., 3]
        rgb = np.where(a[..., None] > 1e-4, sm[..., :3] / np.maximum(a, 1e-4)[..., None], 0.0)
        return np.dstack([np.clip(rgb, 0, 1), a]).astype(np.float32)
    r = np.random.default_rng(rng)
    H = W = int(size)
    cx = W / 2 + r.uniform(-0.05, 0.05) * W
    tw, top, foot = W * r.uniform(0.05, 0.08), H * r.uniform(0.42, 0.48), H * 0.9
    trunk = np.zeros((H, W), np.uint8)
    crown = np.zeros((H, W), np.uint8)
    cv2.fillPoly(trunk, [np.round([[cx - tw, top], [cx + tw, top], [cx + tw * 1.15, foot],
                                   [cx - tw * 1.15, foot]]).astype(np.int32)], 1)
    for _ in range(int(r.integers(3, 6))):
        c = (int(cx + r.uniform(-0.2, 0.2) * W), int(H * r.uniform(0.25, 0.45)))
        cv2.circle(crown, c, int(W * r.uniform(0.14, 0.22)), 1, -1)
    m = (trunk | crown).astype(bool)
    yy, xx = np.mgrid[0:H, 0:W].astype(np.float32)
    base = np.array((0.2, 0.55 + 0.1 * r.random(), 0.2), np.float32)
    rgb = np.zeros((H, W, 3), np.float32)
    crn = crown > 0
    s = (xx - cx) + (yy - H * 0.35)
    rgb[crn] = base
    rgb[crn & (s < -0.08 * W)] = np.minimum(base * 1.35 + 0.05, 1)
    rgb[crn & (s > 0.12 * W)] = base * 0.6
    tr = (trunk > 0) & ~crn
    rgb[tr] = BARK
    rgb[tr & (xx > cx + tw * 0.2)] = BARK * 0.7
    depth = ndi.distance_transform_cdt(np.pad(m, 1), metric="chessboard")[1:-1, 1:-1]
    rgb[m & (depth <= outline)] = INK
    out = np.dstack([rgb * m[..., None], m.astype(np.float32)]).astype(np.float32)
    if shadow:
        sh = np.zeros((H, W), np.float32)
        cv2.ellipse(sh, (int(cx), int(foot)), (int(W * r.uniform(0.2, 0.3)), max(2, int(H * 0.04))),
                    0, 0, 360, 1.0, -1)
        sh = cv2.GaussianBlur(sh, (0, 0), max(1.0, W * 0.01))
        out[..., 3] = np.maximum(out[..., 3], 0.3 * sh * ~m)
    return out


def outline_figures(image, outline: int, tol: float = 0.12) -> dict:
    """Outline figures of a tree drawn by :func:`cel_tree` (or a mix of such trees).

    ``crown``/``trunk``: share of the silhouette's rim pixels (opaque, 8-adjacent to a transparent
    pixel or the frame) within 1.5 px of an ink pixel (within ``tol`` of :data:`INK`), split by the
    colour of the fill beside them (reddish: trunk); ``width``: ink pixels near the rim per rim
    pixel (1.0: a 1 px outline); ``soft``: pixels with 0 < alpha < 1.
    """
    img = np.asarray(image, np.float32)
    al = img[..., 3]
    sil = al >= 0.5
    rgb = img[..., :3]
    ink = sil & (np.abs(rgb - INK).max(-1) <= tol)
    rim = sil & ~ndi.binary_erosion(sil, np.ones((3, 3), bool), border_value=0)
    covered = ndi.distance_transform_edt(~ink) <= 1.5
    inside = ndi.distance_transform_edt(np.pad(sil, 1))[1:-1, 1:-1]
    fill = sil & ~ink & (inside > outline + 0.5)
    iy, ix = ndi.distance_transform_edt(~fill, return_distances=False, return_indices=True)
    fc = rgb[iy, ix]
    is_trunk = fc[..., 0] > fc[..., 1]
    rc, rt = rim & ~is_trunk, rim & is_trunk
    return dict(crown=float(covered[rc].mean()) if rc.any() else float("nan"),
                trunk=float(covered[rt].mean()) if rt.any() else float("nan"),
                width=float((ink & (inside <= 2 * outline + 2)).sum() / max(rim.sum(), 1)),
                soft=int(((al > 1e-3) & (al < 1 - 1e-3)).sum()))


def run(sizes=(96, 160, 256), outlines=(1, 2, 3)) -> None:
    from .library import TreeLibrary

    for size in sizes:
        for ow in outlines:
            for shadow in (True, False):
                for aa in (False, True):
                    lib = TreeLibrary()
                    for i in range(3):
                        lib.add(cel_tree(size, ow, shadow, rng=size + 10 * ow + i, aa=aa), f"t{i}")
                    tol = 0.25 if aa else 0.12
                    src = [outline_figures(e.image, ow, tol) for e in lib.exemplars]
                    outs = [lib.variation(rng=k).image for k in range(3)]
                    outs += [v.image for v in lib.variations_of(0, n=2, rng=7)]
                    mix = [outline_figures(o, ow, tol) for o in outs]
                    w = np.mean([s["width"] for s in src])
                    print(f"{size:4d} ow{ow} shadow{int(shadow)} aa{int(aa)} crown "
                          f"{min(m['crown'] for m in mix):.2f} trunk {np.nanmin([m['trunk'] for m in mix]):.2f} "
                          f"width/src {min(m['width'] for m in mix) / w:.2f}-{max(m['width'] for m in mix) / w:.2f}",
                          flush=True)


if __name__ == "__main__":
    run(tuple(int(x) for x in sys.argv[1].split(",")) if len(sys.argv) > 1 else (96, 160, 256),
        tuple(int(x) for x in sys.argv[2].split(",")) if len(sys.argv) > 2 else (1, 2, 3))
