"""The whole leaf workflow with the defaults on four kinds nobody tuned for (issue 22).

``python -m branchnb.leaves._measure_unseen [--kinds willow,cordate,oak,clipart] [--sizes ...] [--seeds 0,1]
[--save DIR] [--induce-only]`` builds, per kind, size and seed, four leaves of
:mod:`branchnb.leaves._unseen_kinds` (RGB on paper, as a user's photos or
clip art), scribbles on the first programmatically as a user would (short
radius-1 strokes on the midrib and the main veins, a blade blob, dabs on
spots), runs ``leaf_exemplar`` -> ``analyze`` -> ``generate`` as notebook 04
does, and prints one row:

* ``blade``: worst IoU of ``leaf_exemplar``'s blade with the true one
  (drop and soft shadows taken as leaf lower it);
* ``iou``: induced vein IoU with the true veins per exemplar (the
  training leaf's grown layer first);
* ``spots``: the same for the spots (kinds with spots);
* ``bg_rel`` / ``own_rel``: one vein system
  (:func:`branchnb.leaves._measure.vein_system_scores` with the plain
  renderings): ridge response at the background's true veins in the new
  leaf over that of the same leaf built on the background's vein-free
  rendering (1: nothing of the background's veins left);
* ``sharp``, ``iou_new``/``iou_ex``, ``pet_dev``, ``cut``, ``ghost``: from
  :func:`branchnb.leaves._measure_synthesis.synthesis_row`;
* ``t_an`` / ``t_gen``: CPU seconds of the analysis and per new leaf.

A kind ``SHAPE-STYLE-WIDTH`` (e.g. ``maple-colour-2``) is a drawn leaf of
:func:`branchnb.leaves._clipart_kinds.clip_leaf` (shapes maple, oak, elm,
palmate; vein styles pale, colour, black; vein width in px), 512 px by
default.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy import ndimage as ndi

from ._unseen_kinds import KINDS44, unseen_leaf

SIZES = {"willow": 480, "cordate": 640, "oak": 360, "clipart": 260}


def _leaf(kind: str, size: int, seed: int):
    """A leaf of :mod:`._unseen_kinds` or, for ``SHAPE-STYLE-WIDTH``, of :mod:`._clipart_kinds`."""
    if "-" in kind:
        from ._clipart_kinds import clip_leaf
        shape, style, width = kind.split("-")
        return clip_leaf(shape, size, seed, float(width), style)
    return unseen_leaf(kind, size, seed)


def _stroke(line, f0, f1, n=8):
    """Points of ``line`` between the fractions ``f0`` and ``f1`` of its arc length."""
    line = np.asarray(line, float)
    s = np.concatenate([[0], np.cumsum(np.hypot(*np.diff(line, axis=0).T))])
    t = np.linspace(f0, f1, n) * s[-1]
    return np.stack([np.interp(t, s, line[:, 0]), np.interp(t, s, line[:, 1])], 1)


def user_scribbles(leaf, n_main: int = 6, rng=0):
    """A LayerSet as a user would scribble ``leaf``: short strokes on the midrib and main veins, a blade blob."""
    from .scribbles import Layer, LayerSet, Scribble

    r = np.random.default_rng(rng)
    veins = [Scribble(_stroke(leaf.main[0], a, a + 0.1), 1.0) for a in (0.15, 0.45, 0.7)]
    others = leaf.main[1:]
    order = np.argsort([-np.hypot(*np.diff(np.asarray(v)[[0, -1]], axis=0)[0]) for v in others])
    for k in order[:n_main]:
        a = r.uniform(0.2, 0.4)
        veins.append(Scribble(_stroke(others[k], a, a + 0.25), 1.0))
    layers = [Layer("veins", "#d62728", 0, veins)]
    if leaf.spots.any():
        lab, n = ndi.label(leaf.spots)
        com = ndi.center_of_mass(leaf.spots, lab, range(1, n + 1))
        layers.append(Layer("spots", "#1f77b4", 1, [Scribble([(x, y)], 1.5) for y, x in com[:4]]))
    # the blade blob: a dab on plain blade far from veins, spots and the margin
    far = ndi.distance_transform_edt(leaf.blade & ~leaf.veins & ~leaf.spots)
    y, x = np.unravel_index(np.argmax(far), far.shape)
    rad = float(max(2.0, min(6.0, 0.5 * far[y, x])))
    return LayerSet(layers, [Scribble([(x - rad, y), (x + rad, y)], rad)])


def _on_canvas(m, offset, shape, mirrored):
    out = np.zeros(shape + m.shape[2:], m.dtype)
    dx, dy = offset
    h, w = m.shape[:2]
    out[dy:dy + h, dx:dx + w] = m
    return out[:, ::-1].copy() if mirrored else out


def run(kind: str, size: int, seed: int, n: int = 4, n_new: int = 6, save: str | None = None,
        induce_only: bool = False) -> dict:
    """One row of the module docstring (``induce_only``: blade, vein IoU and lambda only, no synthesis)."""
    from ..core.metrics import iou
    from ._measure import vein_system_scores
    from ._measure_synthesis import synthesis_row
    from .analysis import analyze
    from .exemplar import leaf_exemplar

    leaves = [_leaf(kind, size, 10 * seed + k) for k in range(n)]
    ex = [leaf_exemplar(x.image) for x in leaves]
    blade_iou = min(iou(e.blade, x.blade) for e, x in zip(ex, leaves))
    ls = user_scribbles(leaves[0], rng=seed)
    t0 = time.process_time()
    a = analyze(ex, 0, ls)
    t_an = time.process_time() - t0
    shape = a.blades[0].shape
    veins = [_on_canvas(x.veins, o, shape, m) for x, o, m in zip(leaves, a.offsets, a.mirrored)]
    spots = [_on_canvas(x.spots, o, shape, m) for x, o, m in zip(leaves, a.offsets, a.mirrored)]
    plain = [_on_canvas(x.plain, o, shape, m) for x, o, m in zip(leaves, a.offsets, a.mirrored)]
    L = a.layer("veins")
    ious = [iou(L.masks[e], veins[e]) for e in range(n)]
    spot_iou = [iou(a.layer("spots").masks[e], spots[e]) for e in range(n)] if leaves[0].spots.any() else []
    if save:
        _sheet(a, veins, f"{save}/{kind}_{size}_{seed}_induced.png")
    if induce_only:
        return dict(name=f"{kind}_{size}_{seed}", blade=blade_iou, iou=ious, spot_iou=spot_iou, lam=L.lam,
                    t_an=t_an)
    t0 = time.process_time()
    row = synthesis_row(a, n_new, truth=veins, spots=spots if leaves[0].spots.any() else None,
                        name=f"{kind}_{size}_{seed}",
                        save=f"{save}/{kind}_{size}_{seed}_new.png" if save else None)
    t_gen = time.process_time() - t0
    vs = vein_system_scores(a, veins, spots if leaves[0].spots.any() else None,
                            seeds=[100 * seed + k for k in range(3)], plain=plain)
    return dict(name=f"{kind}_{size}_{seed}", blade=blade_iou, iou=ious, spot_iou=spot_iou, lam=L.lam,
                bg_rel=float(np.nanmean([v["bg_rel"] for v in vs])),
                own_rel=float(np.nanmean([v["own_rel"] for v in vs])),
                sharp=row["sharp"], iou_new=row["iou_new"], iou_ex=row["iou_ex"], pet_dev=row["pet_dev"],
                cut=row["cut"], ghost=row["ghost"], t_an=t_an, t_gen=t_gen / n_new)


def _sheet(a, veins, path):
    """Each exemplar: induced veins red, true veins missed blue, both yellow."""
    from ..core.io import encode_png
    L = a.layer("veins")
    tiles = []
    for e in range(len(a.exemplars)):
        img = a.exemplars[e]
        rgb = img[..., :3] * img[..., 3:] + (1 - img[..., 3:])
        rgb = rgb.copy()
        m, t = L.masks[e], veins[e]
        rgb[m & ~t] = (0.9, 0.1, 0.1)
        rgb[t & ~m] = (0.1, 0.2, 0.9)
        rgb[m & t] = (0.95, 0.85, 0.1)
        tiles.append(np.pad(rgb, ((0, 0), (0, 4), (0, 0)), constant_values=1))
    with open(path, "wb") as f:
        f.write(encode_png(np.hstack(tiles)))


def _print(r):
    if "sharp" not in r:
        print(f"{r['name']:<24} blade {r['blade']:.2f}  vein IoU {' '.join(f'{v:.2f}' for v in r['iou'])}  "
              f"mean {np.mean(r['iou']):.3f}  lam {r['lam']:.3f}  analysis {r['t_an']:.1f} s", flush=True)
        return
    print(f"{r['name']:<16} blade {r['blade']:.2f}  vein IoU {' '.join(f'{v:.2f}' for v in r['iou'])}  "
          f"{'spots ' + ' '.join(f'{v:.2f}' for v in r['spot_iou']) + '  ' if r['spot_iou'] else ''}"
          f"lam {r['lam']:.3f}  bg_rel {r['bg_rel']:.2f} own_rel {r['own_rel']:.2f}  sharp {r['sharp']:.2f}  "
          f"iou new {r['iou_new']:.2f} ex {r['iou_ex']:.2f}  pet_dev {r['pet_dev']:.1f} cut {r['cut']:.2f}  "
          f"ghost {r['ghost']:.2f}  "
          f"analysis {r['t_an']:.1f} s, {r['t_gen']:.2f} s/leaf", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m branchnb.leaves._measure_unseen", description=__doc__.split("\n")[0])
    ap.add_argument("--kinds", default=",".join(KINDS44))
    ap.add_argument("--sizes", default=None, help="comma list; default one size per kind")
    ap.add_argument("--seeds", default="0,1")
    ap.add_argument("--save", default=None)
    ap.add_argument("--induce-only", action="store_true", help="stop after the induced layers (fast)")
    args = ap.parse_args(argv)
    for kind in args.kinds.split(","):
        sizes = [int(s) for s in args.sizes.split(",")] if args.sizes else [SIZES.get(kind, 512)]
        for size in sizes:
            for seed in (int(s) for s in args.seeds.split(",")):
                _print(run(kind, size, seed, save=args.save, induce_only=args.induce_only))


if __name__ == "__main__":
    main()
