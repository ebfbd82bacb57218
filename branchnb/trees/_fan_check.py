"""Side views of fan-like drawn crowns before and after the radial-strokes fan rule (issue 24); not run by the tests.

``python -m branchnb.trees._fan_check [sizes] [seeds] [groups]`` (defaults ``128,256``, ``0,1``,
``fans,controls``): for every tree of :func:`~branchnb.trees._fan_family.fan_crown_trees`
(``fans``) and the drawn broadleaf, conifer, fruit and palm trees of
:func:`~branchnb.trees.drawn.drawn_tree` (``controls``) at each size, whether the crown is a fan by
the convex-hull share alone (``_RADIAL`` off, the rule before) and with the radial strokes
(:func:`~branchnb.trees.billboard_shapes._radial_lines`); where the two differ, both clouds baked
as exported (:func:`~branchnb.trees.lod.bake_side_outline`) and, at 45 and 90 degrees
(:func:`~branchnb.trees.lod.engine_view`), the inner-outline recall and smear
(:func:`~branchnb.trees.side_lines.side_line_figures`), the rim ink share at 45 degrees with the
side cards and the floating ink fragments beyond the front view's. Where they agree the cloud is
the same (the decision is the only change) and only the decision is listed.
"""

from __future__ import annotations

import sys
import time

import numpy as np


def _figures(cloud) -> dict:
    from .lod import bake_side_outline, engine_view
    from .lod_cards import side_outline_cards
    from .outline import floating_ink, rim_ink_share, silhouette_outline
    from .side_lines import side_line_figures

    baked = bake_side_outline(cloud)
    f45, f90 = side_line_figures(baked, 45.0), side_line_figures(baked, 90.0)
    out = {"rec45": f45["recall"], "rec90": f90["recall"], "sm45": f45["smear"], "sm90": f90["smear"]}
    o = silhouette_outline(cloud.image)
    if o.outlined:
        view = engine_view(baked, 45.0, cards=side_outline_cards(cloud, baked=baked))
        out["rim45"] = rim_ink_share(view, o.ink)
        out["float"] = max(0, floating_ink(view, o.ink) - floating_ink(cloud.image, o.ink))
    return out


def items(sizes, seeds, groups) -> list:
    from ._fan_family import fan_crown_trees
    from .drawn import drawn_tree

    out = []
    for size in sizes:
        if "fans" in groups:
            out += [(n, size, im, True) for n, im in fan_crown_trees(size, seeds=seeds)]
        if "controls" in groups:
            out += [(f"{k}_{s}", size, drawn_tree(k, rng=s, size=size), k == "palm")
                    for s in seeds for k in ("broadleaf", "conifer", "fruit", "palm")]
    return out


def measure(sizes=(128, 256), seeds=(0, 1), groups=("fans", "controls")) -> list:
    from . import billboard as bb
    from . import billboard_shapes as bs
    from .billboard import BillboardParams, billboard_cloud

    rows = []
    for name, size, img, fan in items(sizes, seeds, groups):
        t0 = time.process_time()
        seen = []
        real = bs._fan_crown

        def spy(crown, lines=None, opaque=None, _real=real, _seen=seen):
            bs._RADIAL = False
            before = _real(crown)
            bs._RADIAL = True
            _seen.append((before, _real(crown, lines, opaque)))
            return _seen[-1][1]

        bb._fan_crown = spy
        try:
            after = billboard_cloud(img, params=BillboardParams(max_size=size), rng=0)
        finally:
            bb._fan_crown = real
            bs._RADIAL = True
        dec = seen[-1] if seen else (False, False)
        row = {"name": name, "size": size, "fan": fan, "before": dec[0], "after": dec[1]}
        if dec[0] != dec[1]:
            bs._RADIAL = False
            try:
                before = billboard_cloud(img, params=BillboardParams(max_size=size), rng=0)
            finally:
                bs._RADIAL = True
            fb, fa = _figures(before), _figures(after)
            row.update({k + "_b": v for k, v in fb.items()})
            row.update({k + "_a": v for k, v in fa.items()})
            figs = " ".join(f"{k} {fb[k]:.3f} -> {fa[k]:.3f}" if isinstance(fb[k], float) else f"{k} {fb[k]} -> {fa[k]}"
                            for k in fb if k in fa)
        else:
            figs = "same cloud"
        rows.append(row)
        print(f"{name:20s} {size:4d} {'fan' if fan else 'no fan':6s} fan decision {dec[0]!s:5s} -> {dec[1]!s:5s} | "
              f"{figs} | {time.process_time() - t0:.1f} s", flush=True)
    ch = [r for r in rows if "rec45_b" in r]
    for k in ("rec45", "rec90", "sm45", "sm90", "rim45", "float"):
        b = [r[k + "_b"] for r in ch if k + "_b" in r]
        a = [r[k + "_a"] for r in ch if k + "_a" in r]
        if b:
            print(f"{k}: mean {np.mean(b):.3f} -> {np.mean(a):.3f}, min {min(b):.3f} -> {min(a):.3f}, "
                  f"max {max(b):.3f} -> {max(a):.3f} ({len(b)} changed trees)")
    wrong = [(r["name"], r["size"]) for r in rows if r["after"] != r["fan"]]
    print(f"fans taken as fans: {sum(r['after'] for r in rows if r['fan'])} of {sum(r['fan'] for r in rows)} "
          f"(before {sum(r['before'] for r in rows if r['fan'])}); controls taken as fans: "
          f"{sum(r['after'] for r in rows if not r['fan'])} of {sum(not r['fan'] for r in rows)}; wrong {wrong}")
    return rows


if __name__ == "__main__":
    sizes = tuple(int(s) for s in sys.argv[1].split(",")) if len(sys.argv) > 1 else (128, 256)
    seeds = tuple(int(s) for s in sys.argv[2].split(",")) if len(sys.argv) > 2 else (0, 1)
    groups = tuple(sys.argv[3].split(",")) if len(sys.argv) > 3 else ("fans", "controls")
    measure(sizes, seeds, groups)
