"""Side views of billboard clouds as an engine draws them (issue 24), not run by the tests.

``python -m branchnb.trees._measure_sides [sizes] [yaws] [groups] [names]`` (defaults
``96,200,512``, ``45``, ``rpg,clip,ground,drawn`` and every sample of the groups): for every
tree, the cloud at each size (the image
resized so that its longest side is ``size``; ``BillboardParams(max_size=size)``), the full
level as exported (:func:`~branchnb.trees.lod.bake_side_outline` and
:func:`~branchnb.trees.lod_cards.side_outline_cards`) seen by
:func:`~branchnb.trees.lod.engine_view`, and the in-memory render
(:func:`~branchnb.trees.preview.render_cloud`): the rim ink share
(:func:`~branchnb.trees.outline.rim_ink_share`) of the front view and of each side view (full
and reduced levels), the floating ink fragments of the full and reduced levels' side views
(:func:`~branchnb.trees.outline.floating_ink`, beyond those of the front view),
the billboards, the side cards and the CPU seconds. Trees whose silhouette is not outlined
(:func:`~branchnb.trees.outline.silhouette_outline`) get no side outline and are listed as such.

Groups: ``rpg`` (``tree_rpg_01`` ... ``tree_rpg_14``), ``clip`` (the clip-art samples),
``ground`` (``data/trees_ground``), ``drawn`` (the 8 drawn trees of seed 0 and the 4 of
seed 11, each drawn at the size).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from .. import data

CLIP = ("arbre_modern", "cartoon_tree", "tree_with_fruits", "plain_tree", "evergreen", "palm_silhouette")
GROUND = ("christmas_tree_in_tray", "christmas_tree_root_flare", "conifer_on_base", "palm_island", "tree_on_hill")


def _resized(img: np.ndarray, size: int) -> np.ndarray:
    import cv2

    h, w = img.shape[:2]
    s = size / max(h, w)
    interp = cv2.INTER_AREA if s < 1 else cv2.INTER_CUBIC
    out = cv2.resize(np.ascontiguousarray(img, np.float32), (max(1, round(w * s)), max(1, round(h * s))),
                     interpolation=interp)
    return np.clip(out, 0.0, 1.0)


def trees(groups, size: int, only=None) -> list:
    """``(name, rgba)`` of the groups' trees at ``size`` px (only the names in ``only``, if given)."""
    from .drawn import drawn_trees

    out = []
    names = []
    if "rpg" in groups:
        names += [f"tree_rpg_{i:02d}" for i in range(1, 15)]
    if "clip" in groups:
        names += list(CLIP)
    if "ground" in groups:
        names += list(GROUND)
    if only:
        names = [n for n in names if n in only]
    out += [(n, _resized(data.load(n), size)) for n in names]
    if "drawn" in groups:
        out += drawn_trees(rng=0, size=size)
        out += [(n + "_s11", img) for n, img in drawn_trees((False,), rng=11, size=size)]
    return out


def measure(sizes=(96, 200, 512), yaws=(45.0,), groups=("rpg", "clip", "ground", "drawn"), only=None) -> dict:
    from .billboard import BillboardParams, billboard_cloud
    from .lod import bake_side_outline, engine_view, reduce_cloud
    from .lod_cards import side_outline_cards
    from .outline import floating_ink, rim_ink_share, silhouette_outline
    from .preview import render_cloud

    res = {}
    floats = {}
    for size in sizes:
        for name, img in trees(groups, size, only):
            t0 = time.process_time()
            cloud = billboard_cloud(img, params=BillboardParams(max_size=size), rng=0)
            o = silhouette_outline(cloud.image)
            if not o.outlined:
                own = floating_ink(cloud.image, o.ink)
                loose = sum(max(0, floating_ink(engine_view(c, y), o.ink) - own)
                            for c in (cloud, reduce_cloud(cloud)) for y in yaws)
                floats[name, size] = loose
                print(f"{name:26s} {size:4d} not outlined (outline share {o.share:.2f}) | floating {loose}",
                      flush=True)
                continue
            baked = bake_side_outline(cloud)
            cards = side_outline_cards(cloud, baked=baked)
            red = reduce_cloud(cloud)
            rbaked = bake_side_outline(red)
            rcards = side_outline_cards(red, baked=rbaked)
            row = {"front": rim_ink_share(cloud.image, o.ink)}
            own = floating_ink(cloud.image, o.ink)
            loose = 0
            for y in yaws:
                full = engine_view(baked, y, cards=cards)
                reduced = engine_view(rbaked, y, cards=rcards)
                row[f"engine {y:.0f}"] = rim_ink_share(full, o.ink)
                row[f"reduced {y:.0f}"] = rim_ink_share(reduced, o.ink)
                row[f"render {y:.0f}"] = rim_ink_share(render_cloud(cloud, y), o.ink)
                loose += max(0, floating_ink(full, o.ink) - own) + max(0, floating_ink(reduced, o.ink) - own)
            res[name, size] = row
            floats[name, size] = loose
            print(f"{name:26s} {size:4d} " + " ".join(f"{k} {v:.3f}" for k, v in row.items())
                  + f" | floating {loose}"
                  + f" | billboards {cloud.n_billboards} cards {cards.n} | {time.process_time() - t0:.1f} s cpu",
                  flush=True)
    for key in sorted({k for r in res.values() for k in r}):
        v = [r[key] for r in res.values()]
        worst = min(res, key=lambda n: res[n][key])
        print(f"{key:12s}: mean {np.mean(v):.3f} min {min(v):.3f} ({worst[0]} at {worst[1]} px), "
              f"{sum(x < 0.9 for x in v)} of {len(v)} below 0.9, {sum(x < 0.92 for x in v)} below 0.92")
    print(f"floating ink fragments (full + reduced engine views, beyond the front view's): "
          f"{sum(floats.values())} in {sum(v > 0 for v in floats.values())} of {len(floats)} trees")
    return res


if __name__ == "__main__":
    sizes = tuple(int(s) for s in sys.argv[1].split(",")) if len(sys.argv) > 1 else (96, 200, 512)
    yaws = tuple(float(y) for y in sys.argv[2].split(",")) if len(sys.argv) > 2 else (45.0,)
    groups = tuple(sys.argv[3].split(",")) if len(sys.argv) > 3 else ("rpg", "clip", "ground", "drawn")
    only = tuple(sys.argv[4].split(",")) if len(sys.argv) > 4 else None
    measure(sizes, yaws, groups, only)
