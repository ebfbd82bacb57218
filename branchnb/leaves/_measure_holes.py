"""Measuring induction on leaves with holes whose rims look like veins (issue 22).

``python -m branchnb.leaves._measure_holes [--kinds lobed,trilobed,elliptic,fan] [--sizes 192,320]
[--seeds 0,1] [--where junction,midrib]`` builds each procedural family
(:func:`~branchnb.leaves.procedural.leaf_family`, true veins known) twice: intact, and with
:func:`hole_leaf` applied to every exemplar but the training leaf: holes punched through the blade
(alpha 0) with a rim 2-4 px wide in the veins' own colour (the browned or bleached tissue round a torn
or eaten patch: sample maple_leaf_07's rim 20 px above its petiole junction). ``junction``: a hole
beside the petiole junction, between its primaries; ``midrib``: a hole whose rim runs beside the
midrib half way to the tip. Holes and rims keep clear of the main veins (fine veins may end at a
hole); the truth, intact and holed alike, is the true veins outside the holes and rims. Each family
is analysed with the training leaf's true veins as the user's layer (TPS-RPM registrations, the
defaults); a row prints every exemplar's induced-vein IoU with its true veins, intact -> holed, the
worst drop, and the share of rim pixels taken as vein.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy import ndimage as ndi


def _junction(leaf):
    """Where the petiole meets the lamina (x, y): the petiole polyline's end nearer the blade's centroid."""
    pet = np.asarray(leaf.veins[0], np.float64)
    ys, xs = np.nonzero(leaf.blade)
    c = np.array([xs.mean(), ys.mean()])
    return min((pet[0], pet[-1]), key=lambda e: float(np.hypot(*(e - c))))


def hole_leaf(leaf, rng, *, where=("junction", "midrib"), radius: float = 0.05, rim: float = 0.025):
    """A copy of a procedural leaf's RGBA with holes whose rims look like veins, and their masks.

    Parameters
    ----------
    leaf : ProceduralLeaf
    rng : int or Generator
    where : sequence of {"junction", "midrib"}
        One hole per entry (see the module notes).
    radius, rim : float
        The hole's radius and its rim's width as shares of the leaf size (``sqrt`` of the blade's
        area); at least 2 px each.

    Returns
    -------
    image : (H, W, 4) float32
    holes : (H, W) bool
        The punched pixels.
    rims : (H, W) bool
        The vein-coloured rims (the true veins are ``veins & ~(holes | rims)``).
    """
    rng = np.random.default_rng(rng)
    img = leaf.image.copy()
    blade, veins = leaf.blade, leaf.layers["veins"]
    size = float(np.sqrt(blade.sum()))
    r = max(2.0, radius * size * rng.uniform(0.8, 1.2))
    h, w = blade.shape
    rw = max(2.0, rim * size)
    yy, xx = np.mgrid[:h, :w]
    # Holes keep clear of the main veins (polylines at least 0.2 leaf sizes long); fine veins may run
    # into a hole or under its rim (those pixels leave the truth).
    import cv2
    main = np.zeros((h, w), np.uint8)
    for line, wd in zip(leaf.veins[1:], leaf.vein_widths[1:]):
        line = np.asarray(line, np.float64)
        if np.hypot(*np.diff(line, axis=0).T).sum() >= 0.2 * size:
            cv2.polylines(main, [np.round(line).astype(np.int32)], False, 1, max(1, int(round(float(np.max(wd))))))
    vein_d = ndi.distance_transform_edt(~main.astype(bool))
    edge_d = ndi.distance_transform_edt(blade)
    j = _junction(leaf)
    ys, xs = np.nonzero(blade)
    far = np.argmax(np.hypot(xs - j[0], ys - j[1]))
    tip = np.array([xs[far], ys[far]], np.float64)
    rgb = img[..., :3]
    base = np.median(rgb[blade & ~veins], axis=0)
    vein_c = np.median(rgb[veins], axis=0)
    holes = np.zeros_like(blade)
    rims = np.zeros_like(blade)
    for kind in where:
        clear = r + rw + 1.5
        ok = (vein_d > clear) & (edge_d > clear + 2) & ~ndi.binary_dilation(holes | rims, iterations=int(clear) + 2)
        if kind == "junction":
            d = np.hypot(xx - j[0], yy - j[1])
            score = np.where(ok, d, np.inf)
        elif kind == "midrib":
            target = j + 0.45 * (tip - j)
            beside = ok & (vein_d <= clear + 2.0)
            score = np.where(beside, np.hypot(xx - target[0], yy - target[1]), np.inf)
        else:
            raise ValueError(f"where must hold 'junction' or 'midrib', got {kind!r}")
        if not np.isfinite(score).any():
            continue
        # One of the few best places, so seeds differ.
        flat = np.argsort(score, axis=None)[:12]
        flat = flat[np.isfinite(score.ravel()[flat])]
        cy, cx = np.unravel_index(int(rng.choice(flat)), score.shape)
        ang = np.arctan2(yy - cy, xx - cx)
        harm = rng.normal(0, 0.15, 3)
        ph = rng.uniform(0, 2 * np.pi, 3)
        wob = 1.0 + sum(harm[m] * np.sin((m + 2) * ang + ph[m]) for m in range(3))
        hole = np.hypot(yy - cy, xx - cx) <= r * wob
        ring = (np.hypot(yy - cy, xx - cx) <= r * wob + rw) & ~hole & blade
        holes |= hole & blade
        rims |= ring
    img[holes, 3] = 0.0
    img[holes, :3] = 0.0
    shade = rng.uniform(0.9, 1.1, size=(h, w, 1)).astype(np.float32)
    rim_c = np.clip(vein_c + 0.3 * (vein_c - base), 0, 1)
    img[rims, :3] = np.clip(rim_c * shade[rims], 0, 1)
    return img.astype(np.float32), holes, rims & ~holes


def hole_rows(kinds=("lobed", "trilobed", "elliptic", "fan"), sizes=(192, 320), seeds=range(2),
              where=("junction", "midrib"), n_leaves: int = 4, palette: str = "green"):
    """Yields one dict per (kind, size, seed): intact and holed induced-vein IoU per exemplar, rims taken."""
    from ..core.metrics import iou
    from .analysis import analyze, normalise_exemplars
    from .analysis_normalise import _on_canvas
    from .procedural import leaf_family

    for kind in kinds:
        for size in sizes:
            for seed in seeds:
                fam = leaf_family(n_leaves, size=size, kind=kind, palette=palette, rng=seed)
                hl = [None] + [hole_leaf(leaf, 1000 * int(seed) + i, where=where) for i, leaf in enumerate(fam)
                               if i > 0]
                row = dict(kind=kind, size=size, seed=int(seed))
                holed = [fam[0].image] + [x[0] for x in hl[1:]]
                # The same truth for both: the veins outside the holes and their rims.
                cut = [np.zeros_like(fam[0].blade)] + [x[1] | x[2] for x in hl[1:]]
                for tag, images in (("intact", [leaf.image for leaf in fam]), ("holed", holed)):
                    t0 = time.perf_counter()
                    _, blades, offs = normalise_exemplars(images)

                    a = analyze(images, 0, {"veins": fam[0].layers["veins"]})
                    masks = a.layer("veins").masks
                    truth = [_on_canvas(fam[e].layers["veins"] & ~cut[e], offs[e], blades[0].shape)
                             for e in range(n_leaves)]
                    row[tag] = [iou(masks[e], truth[e] & blades[e]) for e in range(1, n_leaves)]
                    if tag == "holed":
                        rims = [None] + [_on_canvas(x[2], o, blades[0].shape) for x, o in zip(hl[1:], offs[1:])]
                        row["taken"] = float(sum((masks[e] & rims[e]).sum() for e in range(1, n_leaves))
                                             / max(sum(rims[e].sum() for e in range(1, n_leaves)), 1))
                    row[tag + "_s"] = time.perf_counter() - t0
                yield row


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(prog="python -m branchnb.leaves._measure_holes",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--kinds", default="lobed,trilobed,elliptic,fan")
    ap.add_argument("--sizes", default="192,320")
    ap.add_argument("--seeds", default="0,1")
    ap.add_argument("--where", default="junction,midrib")
    ap.add_argument("--palette", default="green")
    args = ap.parse_args(argv)
    rows = []
    print("kind      size seed  intact IoU per exemplar -> holed            min drop  rims taken")
    for r in hole_rows(args.kinds.split(","), [int(s) for s in args.sizes.split(",")],
                       [int(s) for s in args.seeds.split(",")], tuple(args.where.split(",")), palette=args.palette):
        rows.append(r)
        c, s = r["intact"], r["holed"]
        print(f"{r['kind']:<9} {r['size']:>4} {r['seed']:>4}  " + " ".join(f"{x:.2f}" for x in c) + "  ->  "
              + " ".join(f"{x:.2f}" for x in s) + f"  {min(s) - min(c):+.2f}  {r['taken']:.3f}", flush=True)
    c = np.concatenate([r["intact"] for r in rows])
    s = np.concatenate([r["holed"] for r in rows])
    print(f"all: intact min {c.min():.2f} mean {c.mean():.2f}; holed min {s.min():.2f} mean {s.mean():.2f}; "
          f"worst drop {np.min(s - c):+.2f}, mean drop {np.mean(s - c):+.3f}; "
          f"rims taken mean {np.mean([r['taken'] for r in rows]):.3f}")


if __name__ == "__main__":
    main()
