"""Tip rings on small objects after stroke edits (issue 25), as a table (not a test).

``PYTHONPATH=. python tests/strokes_small_table.py [SIZES...]`` draws the RGBA
objects of ``strokes_speck_table.py`` (antler, candelabra, twig; thin parts
tapering to 1-3 px, a blurred alpha over black RGB) at small sizes and seeds 0-2,
edits them two ways -- the identity (every stroke kept) and a bend of the main
stroke with the others carried -- and prints per object, size and seed the
ring px: faint pixels (0.05 < alpha < 0.5) within 3 px of a target tip with no
solid pixel (alpha > 0.5) among their 8 neighbours (the faint rim of a tip whose
solid core was lost: a grey ring round a hole) beyond the source's own count at its
tips, and for the identity edit the
PSNR against the source (straight RGBA times alpha).
"""
import os
import sys

import numpy as np
from scipy import ndimage as ndi

sys.path.insert(0, os.path.dirname(__file__))
from strokes_speck_table import OBJECTS  # noqa: E402

from branchnb.strokes import edit_structure  # noqa: E402
from branchnb.strokes.parts import carry_stroke  # noqa: E402


def ring_px(layer, tips, radius=3.0):
    """Faint px within ``radius`` of ``tips`` with no solid 8-neighbour."""
    a = layer[..., 3]
    solid_near = ndi.binary_dilation(a > 0.5, structure=np.ones((3, 3)))
    yy, xx = np.mgrid[:a.shape[0], :a.shape[1]]
    near = np.zeros(a.shape, bool)
    for x, y in tips:
        near |= np.hypot(xx - x, yy - y) <= radius
    return int((near & (a > 0.05) & (a < 0.5) & ~solid_near).sum())


def psnr(a, b):
    pa, pb = a[..., :3] * a[..., 3:], b[..., :3] * b[..., 3:]
    mse = float(np.mean((np.concatenate([pa, a[..., 3:]], -1) - np.concatenate([pb, b[..., 3:]], -1)) ** 2))
    return 99.0 if mse == 0 else 10 * np.log10(1.0 / mse)


def main():
    sizes = [int(v) for v in sys.argv[1:]] or [100, 150, 200, 250]
    tot_id = tot_bend = 0
    for name, make in OBJECTS.items():
        for n in sizes:
            for seed in (0, 1, 2):
                img, main_st, kids, bent = make(n, seed)
                src = [main_st] + kids
                r = edit_structure(img, src, src)
                base = ring_px(img, [k[-1] for k in kids])
                ring_id = ring_px(r.layer, [k[-1] for k in kids]) - base
                tgt = [bent] + [carry_stroke(c, main_st, bent) for c in kids]
                rb = edit_structure(img, src, tgt)
                ring_b = ring_px(rb.layer, [t[-1] for t in tgt[1:]]) - base
                tot_id += ring_id
                tot_bend += ring_b
                print(f"{name:10s} {n:4d} seed={seed} ring_identity={ring_id:3d} ring_bend={ring_b:3d} "
                      f"psnr_identity={psnr(r.layer, img):5.1f}", flush=True)
    print(f"total ring px: identity {tot_id} bend {tot_bend}")


if __name__ == "__main__":
    main()
