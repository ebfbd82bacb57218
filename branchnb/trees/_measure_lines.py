"""Side views of drawn trees' billboard clouds: inner outlines, smear, rim ink (issue 24), not run by the tests.

``python -m branchnb.trees._measure_lines [sizes] [groups] [drawn_cards] [names]``
(defaults ``96,200,512``, ``rpg,clip,ground,drawn``, ``1``: ``drawn_cards=True``): for every tree
of :func:`~branchnb.trees._measure_sides.trees` at each size, the cloud
(``BillboardParams(max_size=size, drawn_cards=...)``) baked as exported
(:func:`~branchnb.trees.lod.bake_side_outline`), and per side view (45 and
90 degrees, :func:`~branchnb.trees.lod.engine_view`): the inner-outline
recall and smear of :func:`~branchnb.trees.side_lines.side_line_figures`;
for outlined trees the rim ink share at 45 degrees of the full and reduced
levels with their side cards and the floating ink fragments; the front
view's PSNR against the drawing (engine view at 0 degrees); billboards.
"""

from __future__ import annotations

import sys
import time

import numpy as np


def measure(sizes=(96, 200, 512), groups=("rpg", "clip", "ground", "drawn"), drawn_cards=True, only=None):
    from ..core.image import composite_over
    from . import billboard as _bb
    from ._measure_sides import trees
    from .billboard import BillboardParams, billboard_cloud
    from .lod import bake_side_outline, engine_view, reduce_cloud
    from .lod_cards import side_outline_cards
    from .outline import floating_ink, rim_ink_share, silhouette_outline
    from .side_lines import side_line_figures

    held = []
    check = _bb.cards_hold

    def _hold(*a, **k):
        held.append(check(*a, **k))
        return held[-1]

    _bb.cards_hold = _hold
    rows = []
    for size in sizes:
        for name, img in trees(groups, size, only):
            t0 = time.process_time()
            held.clear()
            cloud = billboard_cloud(img, params=BillboardParams(max_size=size, drawn_cards=drawn_cards), rng=0)
            t_build = time.process_time() - t0
            used = "-" if not held else ("cards" if held[-1] else "FALLBACK")
            baked = bake_side_outline(cloud)
            front = composite_over(engine_view(baked, 0.0, crop="image"), (1, 1, 1))
            ref = composite_over(cloud.image, (1, 1, 1))
            psnr = 10 * np.log10(1.0 / max(float(np.mean((front - ref) ** 2)), 1e-10))
            r = {"name": name, "size": size, "psnr": psnr, "bb": cloud.n_billboards, "cards": used,
                 "build": t_build}
            f45, f90 = side_line_figures(baked, 45.0), side_line_figures(baked, 90.0)
            r.update(lines=f45["lines"], rec45=f45["recall"], rec90=f90["recall"], sm45=f45["smear"],
                     sm90=f90["smear"])
            o = silhouette_outline(cloud.image)
            if o.outlined:
                cards = side_outline_cards(cloud, baked=baked)
                red = reduce_cloud(cloud)
                rbaked = bake_side_outline(red)
                rcards = side_outline_cards(red, baked=rbaked)
                full = engine_view(baked, 45.0, cards=cards)
                reduced = engine_view(rbaked, 45.0, cards=rcards)
                own = floating_ink(cloud.image, o.ink)
                r.update(rim=rim_ink_share(full, o.ink), rrim=rim_ink_share(reduced, o.ink),
                         floating=max(0, floating_ink(full, o.ink) - own)
                         + max(0, floating_ink(reduced, o.ink) - own))
            rows.append(r)
            s = (f"{name:26s} {size:4d} bb {r['bb']:4d} front PSNR {psnr:5.1f} | inner {r['lines']:5d} "
                 f"recall 45 {r['rec45']:.3f} 90 {r['rec90']:.3f} smear 45 {r['sm45']:.3f} 90 {r['sm90']:.3f}")
            if "rim" in r:
                s += f" | rim 45 full {r['rim']:.3f} reduced {r['rrim']:.3f} floating {r['floating']}"
            print(s + f" | {used} build {t_build:.1f} s | {time.process_time() - t0:.1f} s", flush=True)
    lined = [r for r in rows if r["lines"] >= 20]
    if lined:
        for k in ("rec45", "rec90", "sm45", "sm90"):
            v = [r[k] for r in lined]
            print(f"{k}: mean {np.mean(v):.3f} min {min(v):.3f} max {max(v):.3f} ({len(v)} trees with inner outlines)")
    rim = [r for r in rows if "rim" in r]
    for k in ("rim", "rrim"):
        v = [r[k] for r in rim]
        if v:
            worst = min(rim, key=lambda r: r[k])
            print(f"{k}: mean {np.mean(v):.3f} min {min(v):.3f} ({worst['name']} {worst['size']}), "
                  f"{sum(x < 0.92 for x in v)} of {len(v)} below 0.92")
    print(f"build CPU {sum(r['build'] for r in rows):.1f} s; "
          f"fallbacks {[(r['name'], r['size']) for r in rows if r['cards'] == 'FALLBACK']}")
    print(f"floating {sum(r.get('floating', 0) for r in rows)}; front PSNR min "
          f"{min(r['psnr'] for r in rows):.1f}")
    return rows


if __name__ == "__main__":
    sizes = tuple(int(s) for s in sys.argv[1].split(",")) if len(sys.argv) > 1 else (96, 200, 512)
    groups = tuple(sys.argv[2].split(",")) if len(sys.argv) > 2 else ("rpg", "clip", "ground", "drawn")
    cards = bool(int(sys.argv[3])) if len(sys.argv) > 3 else True
    only = tuple(sys.argv[4].split(",")) if len(sys.argv) > 4 else None
    measure(sizes, groups, cards, only)
