"""Measurements for the notes (not run by the tests): ``python -m branchnb.trees._measure WHAT [size]``.

``pins``: pin errors against the hand-placed references (``data/trees_pins``)
and the procedural truths (24 trees, ``synthetic_trees(3, rng=7)``), with the
ground cut and without (``ground="keep"``).
``pairs``: every pair of the sample library, ``trees_ground`` and 8 procedural
trees mixed 50/50 with colour weights (0.5, 0.5) and (1, 0): soft alpha,
foreign colour, pieces, holes.
``masks``: crown/trunk IoU on the masks made without the segmenter
(:mod:`branchnb.trees.mask_reference`).
``crossfade``: cross-fade shares (dominant-palette measure) of random mixes
and ``variations_of`` on drawn procedural trees (two draws of 8), the
clip-art samples and the RPG sprites, with the paper's blend and with the
default ``colour_mode="auto"``; and the dark-rim share.
``outline``: rim ink share (:func:`~branchnb.trees.outline.rim_ink_share`) of
random mixes of drawn procedural trees (two draws), the RPG sprites and
drawn trees mixed with outlined clip art, with ``outline=False`` and the
default; and of billboard-cloud side views (45 and 90 degrees) of drawn
trees with ``render_cloud(..., outline=False)`` and the default.
``ground``: leaf-pile remnants after the ground cut of 32 drawn trees with
a pile (no ground found, rows wider than 1.6 trunk widths + 4 px in the 20
rows above the foot, tree pixels below it).
``speed``: seconds per ``"choose"`` variation of drawn trees at 512 px
(median of 8), with the seam cut on the full grid and on the coarse grid.
``targets``: ``variations_of`` every exemplar of the RPG sprites, the
clip-art samples and two draws of 8 drawn trees (seeds 2 and 5): mean
contour distance of the 5 results to ``T`` and between them, over the mean
distance between the exemplars.
``sideviews``: billboard clouds of drawn trees of every kind (with and
without a leaf pile, 256 px; another draw at 384 px), three RPG sprites
and three outlined clip-art samples at 45 and 90 degrees:
:func:`~branchnb.trees.quality.side_view_figures` (flecks, stroke
fragments, inner outline ink kept) against the front view's.
``seams``: :func:`~branchnb.trees.quality.bare_seam_share` (share of the
``"choose"`` seams that cross a fill without ink) of 12 random mixes and 4
``variations_of`` per library (two draws of drawn trees, the clip-art
samples, the RPG sprites), with ``outline=False`` (seams as cut) and the
default (seams across fills inked).
``engine``: rim ink share (:func:`~branchnb.trees.outline.rim_ink_share`)
at 45, 90, 135 and 270 degrees of the 12 drawn trees of ``sideviews`` as an engine
draws the exported full and reduced levels
(:func:`~branchnb.trees.lod.engine_view`), without and with
:func:`~branchnb.trees.lod.bake_side_outline` and the side cards
(:func:`~branchnb.trees.lod_cards.side_outline_cards`), beside the in-memory
render's; the ink the cards add inside the crown, the largest change of the
front view, and the cards' triangles.
``palms``: side views (45, 90 degrees) of 10 drawn palms (8 at 256 px,
half with a leaf pile, 2 at 384 px) with merged fronds split as a
background (the former rule), as lobes, as lobes at one depth, with
the hub's strokes taken off the trunk, and with the fan crown as one
billboard (the default): loose stroke bits, flecks and inner ink kept
(:func:`~branchnb.trees.quality.side_view_figures`), and stacked outlines
at 45, 90 and 135 degrees (:func:`~branchnb.trees.stacked.stacked_outline_share`).
``transfer``: histogram transfer of 12 drawn trees (4 kinds, 256 px with
and without a leaf pile, and 128 px) onto 8 flat-art references (4 drawn
trees recoloured to autumn hues, 4 clip-art samples), with the paper's
per-channel rule (``mode="channels"``) and the default: share of the
result's flat trunk (crown) pixels within 0.12 RGB of a main colour of the
reference's trunk (crown), parts from :func:`~branchnb.trees.histogram_transfer.tree_parts`.
``billboards``: billboard clouds of every sample tree and one procedural
tree of each kind seen at 0, 45 and 90 degrees: the share of the opaque
pixels in the largest 8-connected piece (1 = the crown stays on the trunk)
and :func:`~branchnb.trees.quality.flat_region_speckle`.
``flatmix``: flat-art mixes that should read as one drawing (issue 24): the
clip-art trees cartoon_tree, plain_tree, tree_with_fruits, evergreen and
arbre_modern and the drawn procedural trees (seed 0, and one draw of the four
kinds at seed 11) at 96, 200 and 320 px wide, ``tree_variations(lib, T, 4,
rng=0)`` and ``variations_of(T, 3, rng=2)`` of every exemplar ``T``:
outline continuity (:func:`~branchnb.trees.quality.outline_continuity`,
target >= 0.95 when an outlined exemplar is used), stray interior ink
(:func:`~branchnb.trees.quality.stray_ink`, target 0), seam through flat fills
(:func:`~branchnb.trees.quality.seam_through_flat`), small foreign patches
(:func:`~branchnb.trees.quality.foreign_patches`, target 0), mixes with two
crown styles or two trunk sources, the cross-fade share and CPU seconds.
"""

from __future__ import annotations

import itertools
import sys
import time

import numpy as np

from .. import data
from .pin_reference import load_reference_pins, pin_errors, source_pins
from .quality import foreign_colour_fraction, large_holes, pieces, soft_alpha_fraction
from .synthetic import synthetic_trees
from .variations import TreeLibrary, exemplar_largest_hole, make_variation, process_exemplar


def measure_pins(size: int = 256) -> None:
    refs = load_reference_pins()
    synth = synthetic_trees(3, rng=7, size=256)
    for ground in ("keep", "cut"):
        ok_h = 0
        for name, ref in refs.items():
            img = data.load(name)
            e = pin_errors(source_pins(process_exemplar(img, name, size=size, ground=ground)), ref,
                           img[..., 3])
            ok_h += max(e.values()) <= 0.05
            print(f"  {ground:4s} {name:28s} B {e['B']:.3f} R {e['R']:.3f} L {e['L']:.3f}")
        ok_s = 0
        for t in synth:
            e = pin_errors(source_pins(process_exemplar(t.image, t.kind, size=size, ground=ground)),
                           {k: np.asarray(v) for k, v in t.pins.items()}, t.image[..., 3])
            ok_s += max(e.values()) <= 0.05
        print(f"ground={ground}: hand-placed within 5 %: {ok_h}/{len(refs)}, procedural: {ok_s}/{len(synth)}")


def measure_pairs(size: int = 128) -> None:
    t0 = time.perf_counter()
    lib = TreeLibrary(size=size)
    for n in data.names("trees") + data.names("trees_ground"):
        lib.add(data.load(n), n)
    for t in synthetic_trees(1, rng=3, size=256):
        lib.add(t.image, f"synth_{t.kind}")
    holes = {e.name: exemplar_largest_hole(e) for e in lib}
    own = {e.name: pieces(e.alpha) for e in lib}
    soft, foreign0, extra, holey, n = [], [], [], 0, 0
    for a, b in itertools.combinations(lib.names, 2):
        for cw in ([0.5, 0.5], [1.0, 0.0]):
            v = make_variation(lib, [0.5, 0.5], use=[a, b], colour_weights=cw, rng=0)
            soft.append(soft_alpha_fraction(v.image))
            if cw[1] == 0:
                foreign0.append(foreign_colour_fraction(v.image, [lib[a].image]))
            if pieces(v.image[..., 3]) > max(own[a], own[b]):
                extra.append((a, b))
            holey += large_holes(v.image[..., 3], max(holes[a], holes[b])) > 0
            n += 1
    print(f"{len(lib)} exemplars, {n} variations in {time.perf_counter() - t0:.0f} s")
    print(f"soft alpha (0.1..0.9 inside): max {max(soft):.4f}")
    print(f"foreign colour at colour weights (1, 0): mean {np.mean(foreign0):.5f}, max {max(foreign0):.5f}")
    print(f"more pieces than the exemplars: {len(extra)} {sorted(set(x for p in extra for x in p))}")
    print(f"holes larger than the exemplars': {holey}")


def measure_masks(_size: int = 0) -> None:
    from .mask_reference import evaluate_independent

    scores = evaluate_independent()
    for name, v in scores.items():
        if name != "mean":
            print(f"  {name:20s} crown {v['crown']:.3f} trunk {v['trunk']:.3f} mean {v['mean']:.3f}")
    print(f"mean IoU on {len(scores) - 1} masks made without the segmenter: {scores['mean']:.3f}")


def billboard_figures(image, *, size: int = 256, yaws=(0.0, 45.0, 90.0), rng=0) -> dict:
    """``{yaw: (largest piece share, flat-region speckle)}`` of one exemplar's billboard cloud."""
    from .billboard import BillboardParams, billboard_cloud
    from .preview import render_cloud
    from .quality import flat_region_speckle, largest_piece_share

    cloud = billboard_cloud(image, params=BillboardParams(max_size=size), rng=rng)
    return {y: (largest_piece_share(render_cloud(cloud, y)[..., 3]), flat_region_speckle(cloud, y))
            for y in yaws}


def measure_billboards(size: int = 256) -> None:
    t0 = time.perf_counter()
    items = [(n, data.load(n)) for n in data.names("trees") + data.names("trees_ground")]
    items += [(f"synth_{t.kind}", t.image) for t in synthetic_trees(1, rng=3, size=256)]
    rows = []
    print(f"{'exemplar':28s}  piece 0/45/90        speckle 45/90")
    for name, img in items:
        f = billboard_figures(img, size=size)
        rows.append(f)
        print(f"  {name:26s} {f[0.0][0]:.2f} {f[45.0][0]:.2f} {f[90.0][0]:.2f}"
              f"       {f[45.0][1]:.2f} {f[90.0][1]:.2f}")
    drop = [r[0.0][0] - min(r[45.0][0], r[90.0][0]) for r in rows]
    sp = [max(r[45.0][1], r[90.0][1]) for r in rows]
    print(f"{len(rows)} exemplars at {size} px in {time.perf_counter() - t0:.0f} s; "
          f"largest-piece drop from yaw 0: max {max(drop):.2f}, >0.05 on {sum(d > 0.05 for d in drop)}; "
          f"speckle: max {max(sp):.2f}, mean {np.mean(sp):.2f}, >0.25 on {sum(s > 0.25 for s in sp)}")


#: The drawn clip-art samples of mixed styles (``data/trees``, not the RPG sprites).
CLIPART = ("arbre_modern", "cartoon_tree", "evergreen", "palm_silhouette", "plain_tree",
           "tree_with_fruits", "poplar_tree_with_branches")


def _sources(lib, v):
    return [lib[n].image for n, w, c in zip(v.names, v.weights, v.colour_weights) if w > 0 or c > 0]


def crossfade_figures(lib, *, n_random: int = 20, per_target: int = 2, rng=0, **params) -> dict:
    """Cross-fade shares (:func:`~branchnb.trees.quality.crossfade_fraction`) of random mixes
    and of ``variations_of`` every exemplar, plus the dark-rim share, on one library."""
    from .quality import crossfade_fraction, dark_rim_fraction

    gen = np.random.default_rng(rng)
    out = {"random": [], "variations_of": [], "rim": []}
    for _ in range(n_random):
        v = make_variation(lib, rng=gen, **params)
        out["random"].append(crossfade_fraction(v.image, _sources(lib, v)))
        out["rim"].append(dark_rim_fraction(v.image, v.mask))
    for t in lib.names:
        for v in lib.variations_of(t, per_target, rng=gen, **params):
            out["variations_of"].append(crossfade_fraction(v.image, _sources(lib, v)))
            out["rim"].append(dark_rim_fraction(v.image, v.mask))
    return out


def measure_crossfade(size: int = 256) -> None:
    from .drawn import drawn_trees

    libs = {}
    libs["drawn"] = TreeLibrary(size=size)
    for name, img in drawn_trees(rng=0, size=size):
        libs["drawn"].add(img, name)
    libs["drawn_b"] = TreeLibrary(size=size)
    for name, img in drawn_trees(rng=11, size=size):
        libs["drawn_b"].add(img, name)
    libs["clipart"] = TreeLibrary.from_data(CLIPART, size=size)
    libs["rpg"] = TreeLibrary.from_data(size=size)
    for mode in ("blend", "auto"):
        for name, lib in libs.items():
            t0 = time.perf_counter()
            f = crossfade_figures(lib, colour_mode=mode)
            r, w = np.array(f["random"]), np.array(f["variations_of"])
            print(f"{mode:6s} {name:8s} random mixes: mean {r.mean():.3f} max {r.max():.3f} | "
                  f"variations_of: mean {w.mean():.3f} max {w.max():.3f} | dark rim max "
                  f"{max(f['rim']):.4f} | {time.perf_counter() - t0:.0f} s")


def measure_sideviews(size: int = 256) -> None:
    from .billboard import BillboardParams, billboard_cloud
    from .drawn import drawn_trees
    from .quality import side_view_figures

    items = [(n, img, size) for n, img in drawn_trees(rng=0, size=size)]
    items += [(n + "@384", img, 384) for n, img in drawn_trees((False,), rng=11, size=384)]
    items += [(n, data.load(n), size) for n in ("tree_rpg_02", "tree_rpg_05", "tree_rpg_07",
                                                "tree_with_fruits", "cartoon_tree", "arbre_modern")]
    t0 = time.perf_counter()
    rows = []
    print(f"{'tree':22s} flecks 0/45/90     fragments 0/45/90   inner ink 45/90")
    for name, img, s in items:
        cloud = billboard_cloud(img, params=BillboardParams(max_size=s), rng=0)
        f = {y: side_view_figures(cloud, y) for y in (45.0, 90.0)}
        rows.append((name, f))
        print(f"  {name:20s} {f[45.0]['flecks0']:.3f} {f[45.0]['flecks']:.3f} {f[90.0]['flecks']:.3f}"
              f"    {f[45.0]['fragments0']:.3f} {f[45.0]['fragments']:.3f} {f[90.0]['fragments']:.3f}"
              f"    {f[45.0]['inner_ink']:.2f} {f[90.0]['inner_ink']:.2f}")
    for label, sel in (("drawn", [r for r in rows if not r[0].startswith(("tree_", "cartoon", "arbre"))]),
                       ("samples", [r for r in rows if r[0].startswith(("tree_", "cartoon", "arbre"))])):
        fl = [max(f[y]["flecks"] - f[y]["flecks0"] for y in f) for _, f in sel]
        fr = [max(f[y]["fragments"] - f[y]["fragments0"] for y in f) for _, f in sel]
        ii = [min(f[y]["inner_ink"] for y in f) for _, f in sel]
        print(f"{label:8s} ({len(sel)}): flecks over the front view's: mean {np.mean(fl):.3f} max {max(fl):.3f} | "
              f"fragments over the front view's: mean {np.mean(fr):.3f} max {max(fr):.3f} | "
              f"inner ink kept: mean {np.mean(ii):.2f} min {min(ii):.2f}")
    print(f"{len(rows)} clouds in {time.perf_counter() - t0:.0f} s")


def measure_engine(size: int = 256) -> None:
    from scipy import ndimage as ndi

    from .billboard import BillboardParams, billboard_cloud
    from .drawn import drawn_trees
    from .lod import bake_side_outline, engine_view, reduce_cloud
    from .lod_cards import side_outline_cards
    from .outline import _depth, rim_ink_share, silhouette_outline
    from .preview import render_cloud

    items = drawn_trees(rng=0, size=size) + drawn_trees((False,), rng=11, size=384)
    res: dict = {}
    stray: dict = {}
    front = 0.0
    tris = []
    for _, img in items:
        cloud = billboard_cloud(img, params=BillboardParams(max_size=img.shape[0]), rng=0)
        o = silhouette_outline(cloud.image)
        red = reduce_cloud(cloud)
        fb, rb = bake_side_outline(cloud), bake_side_outline(red)
        fc, rc = side_outline_cards(cloud, baked=fb), side_outline_cards(red, baked=rb)
        tris.append((2 * cloud.n_billboards, 2 * fc.n, 2 * red.n_billboards, 2 * rc.n))
        levels = {"in-memory": None, "full": (cloud, None), "full baked": (fb, None),
                  "full + cards": (fb, fc), "reduced": (red, None), "reduced baked": (rb, None),
                  "reduced + cards": (rb, rc)}
        for label, c in levels.items():
            for y in (45.0, 90.0, 135.0, 270.0):
                view = render_cloud(cloud, y) if c is None else engine_view(c[0], y, cards=c[1])
                res.setdefault((label, y), []).append(rim_ink_share(view, o.ink))
                if c is not None and c[1] is not None:
                    # Ink the cards add deeper than 2 w + 1 inside the silhouette, per opaque pixel.
                    bare = engine_view(c[0], y)
                    op = view[..., 3] >= 0.5
                    deep = _depth(ndi.binary_fill_holes(op)) > 2 * o.width + 1
                    new = (np.abs(view - bare).max(axis=2) > 0) & deep
                    stray.setdefault((label, y), []).append(new.sum() / max(op.sum(), 1))
        for a, b in ((cloud, (fb, fc)), (red, (rb, rc))):
            front = max(front, float(np.abs(engine_view(a, 0.0) - engine_view(b[0], 0.0, cards=b[1])).max()))
    for (label, y), v in sorted(res.items(), key=lambda kv: (kv[0][1], kv[0][0])):
        extra = ""
        if (label, y) in stray:
            extra = f" | ink added inside the crown: mean {np.mean(stray[label, y]):.4f} max {max(stray[label, y]):.4f}"
        print(f"{label:16s} {y:3.0f} deg: rim ink share mean {np.mean(v):.2f} min {min(v):.2f}{extra}")
    t = np.array(tris, float)
    print(f"{len(items)} drawn trees; largest change of the front view by bake and cards: {front:.4f}")
    print(f"side cards' triangles over the level's billboards': full {t[:, 1].sum() / t[:, 0].sum():.2f} "
          f"(per tree max {np.max(t[:, 1] / t[:, 0]):.2f}), reduced {t[:, 3].sum() / t[:, 2].sum():.2f}")


def measure_palms(size: int = 256) -> None:
    from . import billboard as bb
    from . import billboard_shapes as bb_shapes
    from .drawn import drawn_tree
    from .quality import side_view_figures
    from .stacked import stacked_outline_share

    items = [(s, size, s % 2 == 1) for s in range(8)] + [(s, 384, False) for s in (20, 21)]
    sky = bb_shapes._SKY_HULL
    rules = [("split as a background", -1.0, False, False, False), ("lobes", sky, False, False, False),
             ("lobes, one depth", sky, True, False, False), ("+ hub strokes", sky, True, True, False),
             ("+ fan crown (default)", sky, True, True, True)]
    try:
        for label, value, join, hub, fan in rules:
            bb_shapes._SKY_HULL, bb._JOIN_STARS, bb._HUB_STROKES, bb._STAR_ONE = value, join, hub, fan
            fr, fl, ii, st = [], [], [], []
            for seed, s, pile in items:
                cloud = bb.billboard_cloud(drawn_tree("palm", pile=pile, rng=seed, size=s),
                                           params=bb.BillboardParams(max_size=s), rng=0)
                f = {y: side_view_figures(cloud, y) for y in (45.0, 90.0)}
                fr.append(max(f[y]["fragments"] - f[y]["fragments0"] for y in f))
                fl.append(max(f[y]["flecks"] - f[y]["flecks0"] for y in f))
                ii.append(min(f[y]["inner_ink"] for y in f))
                st.append(max(stacked_outline_share(cloud, y) for y in (45.0, 90.0, 135.0)))
            print(f"{label:24s} {len(items)} palms: stroke bits over the front view's mean {np.mean(fr):.3f} "
                  f"max {max(fr):.3f} | flecks mean {np.mean(fl):.3f} max {max(fl):.3f} | inner ink kept "
                  f"mean {np.mean(ii):.2f} min {min(ii):.2f} | stacked outlines (45/90/135) max "
                  f"{max(st):.3f}, > 0.01 on {sum(x > 0.01 for x in st)}")
    finally:
        bb_shapes._SKY_HULL, bb._JOIN_STARS, bb._HUB_STROKES, bb._STAR_ONE = sky, True, True, True


def measure_seams(size: int = 192) -> None:
    from .drawn import drawn_trees
    from .quality import bare_seam_share

    libs = {}
    for seed in (0, 11):
        libs[f"drawn{seed}"] = TreeLibrary(size=size)
        for name, img in drawn_trees(rng=seed, size=2 * size):
            libs[f"drawn{seed}"].add(img, name)
    libs["clipart"] = TreeLibrary.from_data(CLIPART, size=size)
    libs["rpg"] = TreeLibrary.from_data(size=size)
    for name, lib in libs.items():
        out = {}
        for outline in (False, True):
            g = np.random.default_rng(3)
            mixes = [make_variation(lib, rng=g, colour_mode="choose", outline=outline) for _ in range(12)]
            t = lib.names[int(g.integers(len(lib.names)))]
            mixes += lib.variations_of(t, 4, rng=g, colour_mode="choose", outline=outline)
            out[outline] = [bare_seam_share(v.image, v.sources) for v in mixes]
        print(f"{name:8s} seams across fills, share of seam length (16 choose mixes): outline=False mean "
              f"{np.mean(out[False]):.3f} max {max(out[False]):.3f} | default mean {np.mean(out[True]):.3f} "
              f"max {max(out[True]):.3f}")


def measure_variety(size: int = 256) -> None:
    """"More like this": mean pairwise contour distance of the results over the mean distance
    between the exemplars mixed (target: >= 0.5)."""
    from .drawn import drawn_trees
    from .variations import mean_pairwise_distance

    libs = {"drawn": TreeLibrary(size=size), "rpg": TreeLibrary.from_data(size=size)}
    for name, img in drawn_trees(rng=0, size=size):
        libs["drawn"].add(img, name)
    # small libraries: three trees of different kinds / three sprites
    for i, (seed, kinds) in enumerate(((3, ("broadleaf", "palm", "conifer")), (4, ("fruit", "palm", "broadleaf")),
                                       (5, ("conifer", "fruit", "broadleaf")))):
        libs[f"drawn3-{i}"] = TreeLibrary(size=size)
        for name, img in drawn_trees((i % 2 == 1,), kinds=kinds, rng=seed, size=size):
            libs[f"drawn3-{i}"].add(img, name)
    libs["rpg3"] = TreeLibrary.from_data(["tree_rpg_02", "tree_rpg_07", "tree_rpg_11"], size=size)
    for name, lib in libs.items():
        for keep in (None,):
            gen = np.random.default_rng(0)
            r_lib, r_mix = [], []
            between = mean_pairwise_distance([e.resampled for e in lib])
            for _ in range(6):
                centre = make_variation(lib, rng=gen)
                mixed = [lib[n].resampled for n, w in zip(centre.names, centre.weights) if w > 0]
                more = lib.similar(centre, 6, keep=keep, rng=gen)
                d = mean_pairwise_distance([v.resampled for v in more])
                r_lib.append(d / between)
                r_mix.append(d / max(mean_pairwise_distance(mixed), 1e-9))
            print(f"{name:8s} keep {keep}: more like this / between all exemplars: min {min(r_lib):.2f} "
                  f"mean {np.mean(r_lib):.2f}; / between the exemplars mixed: min {min(r_mix):.2f} "
                  f"mean {np.mean(r_mix):.2f}")


def measure_targets(size: int = 256) -> None:
    """``variations_of``: mean contour distance of the results to ``T`` and between the
    results, over the mean distance between the exemplars (target: 0.3-0.8 to ``T``)."""
    from .drawn import drawn_trees
    from .variations import contour_distance, mean_pairwise_distance

    libs = {"rpg": TreeLibrary.from_data(size=size), "clipart": TreeLibrary.from_data(CLIPART, size=size)}
    for seed in (0, 11):
        libs[f"drawn{seed}"] = TreeLibrary(size=size)
        for name, img in drawn_trees(rng=seed, size=size):
            libs[f"drawn{seed}"].add(img, name)
    for name, lib in libs.items():
        between = mean_pairwise_distance([e.resampled for e in lib])
        to_t, among = [], []
        for t in lib.names:
            for seed in (2, 5):
                vs = lib.variations_of(t, 5, rng=seed)
                to_t.append(np.mean([contour_distance(v.resampled, lib[t].resampled) for v in vs]))
                among.append(mean_pairwise_distance([v.resampled for v in vs]))
        to_t, among = np.array(to_t) / between, np.array(among) / between
        print(f"{name:8s} to T / between exemplars: min {to_t.min():.2f} mean {to_t.mean():.2f} "
              f"max {to_t.max():.2f} | among results: min {among.min():.2f} mean {among.mean():.2f}")


def measure_outline(size: int = 192) -> None:
    from .billboard import BillboardParams, billboard_cloud
    from .drawn import drawn_trees
    from .outline import rim_ink_share
    from .preview import render_cloud
    from .variations import exemplar_outline

    libs = {}
    for seed in (0, 11):
        libs[f"drawn{seed}"] = TreeLibrary(size=size)
        for name, img in drawn_trees(rng=seed, size=2 * size):
            libs[f"drawn{seed}"].add(img, name)
    libs["rpg"] = TreeLibrary.from_data([f"tree_rpg_{i:02d}" for i in range(1, 11)], size=size)
    libs["drawn+clip"] = TreeLibrary.from_data(["tree_with_fruits", "arbre_modern"], size=size)
    for name, img in drawn_trees(kinds=("broadleaf", "fruit"), rng=5, size=2 * size):
        libs["drawn+clip"].add(img, name)
    for name, lib in libs.items():
        row = []
        for outline in (False, True):
            gen = np.random.default_rng(2)
            share = []
            for _ in range(10):
                v = make_variation(lib, rng=gen, outline=outline)
                ink = exemplar_outline(lib[v.names[int(np.argmax(v.colour_weights))]]).ink
                share.append(rim_ink_share(v.image, ink))
            row.append(f"min {min(share):.2f} mean {np.mean(share):.2f}")
        print(f"{name:10s} mixes' rim ink share: outline=False {row[0]} | default {row[1]}")
    for yaw in (45.0, 90.0):
        row = {False: [], True: []}
        for name, img in drawn_trees((False,), rng=0, size=256) + drawn_trees((False,), rng=11, size=256):
            cloud = billboard_cloud(img, params=BillboardParams(max_size=256), rng=0)
            ink = exemplar_outline(process_exemplar(cloud.image, name, size=256)).ink
            for outline in (False, True):
                row[outline].append(rim_ink_share(render_cloud(cloud, yaw, outline=outline), ink))
        print(f"side view {yaw:.0f} deg, 8 drawn trees, rim ink share: outline=False mean "
              f"{np.mean(row[False]):.2f} | default mean {np.mean(row[True]):.2f} min {min(row[True]):.2f}")


def measure_ground(size: int = 192) -> None:
    from .drawn import drawn_tree
    from .ground import split_ground

    bad = []
    for seed in range(8):
        for kind in ("broadleaf", "palm", "conifer", "fruit"):
            img = drawn_tree(kind, pile=True, rng=seed, size=2 * size)
            sp = split_ground(img)
            if not sp.has_ground:
                bad.append((kind, seed, "no ground"))
                continue
            y_f = int(sp.foot[1])
            width = int(sp.tree[max(0, y_f - 20):y_f + 1].sum(axis=1).max())
            below = int(sp.tree[y_f + 2:].sum())
            if width > 1.6 * sp.trunk_width + 4 or below > 0:
                bad.append((kind, seed, width, round(float(sp.trunk_width), 1), below))
    print(f"drawn trees with a pile, remnants after the ground cut: {len(bad)}/32 {bad}")


def measure_speed(size: int = 512) -> None:
    from . import mvc_pick
    from .drawn import drawn_trees

    lib = TreeLibrary(size=size)
    for name, img in drawn_trees(rng=0, size=size):
        lib.add(img, name)
    make_variation(lib, rng=0, colour_mode="choose")
    side = mvc_pick.CHOOSE_CUT_SIDE
    try:
        for label, s in (("full grid", 10 ** 9), (f"coarse grid ({side} px)", side)):
            mvc_pick.CHOOSE_CUT_SIDE = s
            ts = []
            for r in range(8):
                t0 = time.perf_counter()
                make_variation(lib, rng=r, colour_mode="choose")
                ts.append(time.perf_counter() - t0)
            print(f"choose, {size} px, {label}: median {np.median(ts):.3f} s, min {min(ts):.3f} s")
    finally:
        mvc_pick.CHOOSE_CUT_SIDE = side


def autumn(image, shift: float = -80.0) -> np.ndarray:
    """Test reference: the green hues of a drawn tree turned towards orange/brown."""
    import cv2

    hsv = cv2.cvtColor(np.ascontiguousarray(image[..., :3]), cv2.COLOR_RGB2HSV)
    g = (hsv[..., 0] > 60) & (hsv[..., 0] < 180) & (hsv[..., 1] > 0.3)
    hsv[..., 0] = np.where(g, (hsv[..., 0] + shift) % 360, hsv[..., 0])
    out = image.copy()
    out[..., :3] = cv2.cvtColor(hsv, cv2.COLOR_HSV2RGB)
    return out


def transfer_figures(out, labels, ref, ref_labels, *, tol: float = 0.12) -> dict:
    """Share of the flat pixels of each part of ``out`` near a main colour of the reference's part."""
    from scipy.spatial import cKDTree

    from .histogram_transfer import part_palette
    from .quality import flat_pixels

    flat = flat_pixels(out)
    res = {}
    for part, name in ((1, "crown"), (2, "trunk")):
        sel = flat & (labels == part)
        rpx = ref[(ref[..., 3] >= 0.5) & (ref_labels == part)][:, :3]
        if sel.sum() < 10 or len(rpx) < 20:
            continue
        d, _ = cKDTree(part_palette(rpx)[0]).query(out[sel][:, :3])
        res[name] = float(np.mean(d <= tol))
    return res


def measure_transfer(size: int = 256) -> None:
    from .drawn import drawn_trees
    from .histogram_transfer import histogram_transfer, tree_parts

    srcs = drawn_trees(rng=0, size=size) + drawn_trees((False,), rng=11, size=size // 2)
    refs = [(f"autumn {n}", autumn(i)) for n, i in drawn_trees((False,), rng=5, size=size)]
    refs += [(n, data.load(n)) for n in ("cartoon_tree", "tree_with_fruits", "arbre_modern", "tree_rpg_05")]
    lab = {id(i): tree_parts(i) for _, i in srcs + refs}
    for mode in ("channels", "auto"):
        figs: dict = {"crown": [], "trunk": []}
        for _, s in srcs:
            for _, r in refs:
                out = histogram_transfer(s, r, mode=mode, labels=lab[id(s)], reference_labels=lab[id(r)])
                for k, v in transfer_figures(out, lab[id(s)], r, lab[id(r)]).items():
                    figs[k].append(v)
        print(f"{mode:8s} {len(srcs)} x {len(refs)}: flat pixels within the reference part's palette: "
              + " | ".join(f"{k} mean {np.mean(v):.2f} min {min(v):.2f} (n={len(v)})" for k, v in figs.items()))


FLATMIX_CLIPART = ("cartoon_tree", "plain_tree", "tree_with_fruits", "evergreen", "arbre_modern")


def _resized(img: np.ndarray, width: int) -> np.ndarray:
    import cv2

    h = int(round(img.shape[0] * width / img.shape[1]))
    return cv2.resize(img, (width, h), interpolation=cv2.INTER_AREA)


def flatmix_libraries(widths=(96, 200, 320)) -> dict:
    """The libraries of ``flatmix``: clip art and drawn trees at each width."""
    from .drawn import drawn_trees

    libs = {}
    for w in widths:
        lib = TreeLibrary(size=w)
        for n in FLATMIX_CLIPART:
            lib.add(_resized(data.load(n), w), n)
        libs[f"clipart{w}"] = lib
        lib = TreeLibrary(size=w)
        for name, img in drawn_trees(rng=0, size=2 * w) + drawn_trees((False,), rng=11, size=2 * w):
            lib.add(img, name if name not in lib else name + "b")
        libs[f"drawn{w}"] = lib
    return libs


def flatmix_figures(lib, v) -> dict:
    """One mix's flat-art figures (see ``flatmix``)."""
    from .outline import silhouette_outline
    from .quality import (
        crossfade_fraction,
        crown_sources,
        foreign_patches,
        outline_continuity,
        seam_through_flat,
        stray_ink,
    )
    from .variations import exemplar_outline

    op = v.image[..., 3] >= 0.5
    used = [k for k in np.unique(v.sources[op]) if k >= 0]
    px = {k: int(np.count_nonzero(v.sources == k)) for k in used}
    outl = [k for k in used if exemplar_outline(lib[v.names[k]]).outlined]
    cont = partial = None
    if outl:
        best = max(outl, key=lambda k: px[k])
        c = outline_continuity(v.image, exemplar_outline(lib[v.names[best]]).ink)
        if sum(px[k] for k in outl) >= 0.5 * sum(px.values()):
            cont = c                   # mostly outlined sources: the outline must be continuous
        else:
            partial = c > 0.25         # mostly unoutlined: an outline on part of the rim is a collage
    trunk = v.parts == 2
    tsrc = np.bincount(v.sources[trunk & op], minlength=len(v.names)) if trunk.any() else np.zeros(1)
    width = max(silhouette_outline(lib[v.names[k]].image).width for k in used)
    return {"outline": cont, "partial": partial, "stray": stray_ink(v.image, width=width),
            "through_flat": seam_through_flat(v.image, v.sources),
            "foreign": foreign_patches(v.sources, v.parts),
            "styles": crown_sources(v.sources, v.parts, share=0.05),
            "trunks": int(np.count_nonzero(tsrc >= 0.05 * max(tsrc.sum(), 1))),
            "crossfade": crossfade_fraction(v.image, _sources(lib, v))}


def measure_flatmix(_size: int = 0) -> None:
    from .outline import silhouette_outline
    from .quality import stray_ink

    allf = []
    for name, lib in flatmix_libraries().items():
        own = sum(stray_ink(e.image, width=silhouette_outline(e.image).width) for e in lib)
        t0 = time.process_time()
        vs = []
        for t in lib.names:
            vs += lib.variations_of(t, 4, rng=0) + lib.variations_of(t, 3, rng=2)
        dt = time.process_time() - t0
        f = [flatmix_figures(lib, v) for v in vs]
        allf += f
        cont = [x["outline"] for x in f if x["outline"] is not None]
        print(f"{name:10s} {len(vs):3d} mixes ({dt / len(vs):.2f} s cpu each) | outline continuity mean "
              f"{np.mean(cont):.3f} min {min(cont):.3f} >=0.95 {np.mean(np.array(cont) >= 0.95):.2f} "
              f"(partial outlines {sum(bool(x['partial']) for x in f)}) | "
              f"stray ink {sum(x['stray'] for x in f)} in {sum(x['stray'] > 0 for x in f)} mixes "
              f"(exemplars {own}) | seam through flat {np.mean([x['through_flat'] for x in f]):.3f} | "
              f"foreign patches {sum(x['foreign'] for x in f)} in {sum(x['foreign'] > 0 for x in f)} | "
              f"2+ crown styles {sum(x['styles'] > 1 for x in f)} | 2+ trunk sources "
              f"{sum(x['trunks'] > 1 for x in f)} | cross-fade max {max(x['crossfade'] for x in f):.3f}")
    cont = [x["outline"] for x in allf if x["outline"] is not None]
    print(f"ALL {len(allf)} mixes: outline continuity mean {np.mean(cont):.3f} >=0.95 "
          f"{np.mean(np.array(cont) >= 0.95):.2f} (partial {sum(bool(x['partial']) for x in allf)}) "
          f"| stray ink {sum(x['stray'] for x in allf)} | seam through flat "
          f"{np.mean([x['through_flat'] for x in allf]):.3f} | foreign patches {sum(x['foreign'] for x in allf)} | "
          f"2+ crown styles {sum(x['styles'] > 1 for x in allf)} | 2+ trunks {sum(x['trunks'] > 1 for x in allf)}"
          f" | cross-fade max {max(x['crossfade'] for x in allf):.3f}")


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "pins"
    size = int(sys.argv[2]) if len(sys.argv) > 2 else (
        256 if what in ("pins", "billboards", "sideviews", "crossfade", "variety", "targets", "engine", "palms",
                   "transfer") else
        512 if what == "speed" else 192 if what in ("outline", "ground", "seams") else 128)
    {"pins": measure_pins, "pairs": measure_pairs, "masks": measure_masks,
     "billboards": measure_billboards, "crossfade": measure_crossfade,
     "variety": measure_variety, "sideviews": measure_sideviews, "seams": measure_seams,
     "targets": measure_targets, "outline": measure_outline, "ground": measure_ground,
     "speed": measure_speed, "engine": measure_engine, "palms": measure_palms,
     "transfer": measure_transfer, "flatmix": measure_flatmix}[what](size)
