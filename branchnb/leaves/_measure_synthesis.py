"""Measurements of the synthesis stage (issue 22): sharpness, variety, petioles, margins, veins, speed.

Run ``python -m branchnb.leaves._measure_synthesis WHAT`` with ``WHAT`` one of
``procedural`` (4 kinds, true registrations), ``speed`` (one new leaf at
about 1 MP: CPU seconds and peak memory) or ``pickle PATH`` (an analysis
saved with :mod:`pickle`, e.g. of the sample maples, drawn oaks or grass
photos). Every row is one analysis; the columns:

* ``sharp``: Laplacian variance of the grey level inside the new blades
  (eroded by 3 px; on drawn leaves without the outline ink grown by 3 px,
  :func:`outline_ink`), over the exemplars' mean (target >= 0.8);
* ``iou_new`` / ``iou_ex``: median pairwise blade IoU of the new leaves and
  of the exemplars (target ``iou_new <= iou_ex + 0.05``);
* ``cut``: share of new leaves the canvas edge cuts (target 0);
  ``pet_dev``: largest angle (degrees) between a new leaf's petiole and
  the lamina's axis beyond the largest such angle among the exemplars
  (target 0: petioles attached in the leaf's own direction);
* ``foreign``: share of the new blades' margin band (the 4 px inside the
  outline) whose colour is farther than 0.12 (RGB) from every colour of
  the exemplars' own margin bands (streaks of interior or backdrop colour
  pulled to the margin; exemplars: the same measured leave-one-out);
* ``vein_cont``: vein continuity: share of the donor's vein skeleton,
  carried into the new leaf by the coordinates the synthesis samples it
  with, where the new leaf shows at least half the donor's own median
  contrast (relative: grey level over the blade around it) of the vein
  (target near the exemplars' own, 1 - dashes);
* ``fine``: fine-vein recall (procedural families, whose true veins are
  known): the same share as ``vein_cont``, on the skeleton of the donor's
  *true* veins at most 3 px wide (:func:`fine_veins`, whether or not the
  induction found them), against the donor's median contrast there;
  ``fine_min`` the worst new leaf (the exemplars' own: ``fine_ex``);
* ``ghost``: one vein system (procedural families): ridge response of the
  new leaves at their background exemplar's *true* veins carried into
  the lamina, farther than 2 px from the vein donor's true veins and its pasted
  layer, over plain blade at the same distances from those
  (:func:`ghost_ratio`, pixel-weighted over the new leaves; target <= 1:
  nothing of the background's own vein system shows); ``ghost_max`` the
  worst new leaf, ``ghost_px`` the pixels it is read on (a few dozen at
  128 px, where the two leaves' veins mostly lie within 2 px of each
  other: there it is noise).
"""

from __future__ import annotations

import argparse
import pickle
import resource
import time
import tracemalloc

import cv2
import numpy as np
from scipy import ndimage as ndi

__all__ = ["laplacian_variance", "outline_ink", "median_pair_iou", "petiole_angle", "margin_foreign_share",
           "vein_continuity", "fine_veins", "ghost_ratio", "synthesis_row"]


def _grey(img):
    return np.ascontiguousarray(np.asarray(img, np.float32)[..., :3].mean(-1))


def laplacian_variance(img, blade, erode: int = 3, exclude=None) -> float:
    """Variance of the Laplacian of the grey level inside ``blade`` eroded by ``erode`` px.

    ``exclude``: pixels left out besides (e.g. a drawn outline, :func:`outline_ink`), or None.
    """
    inner = ndi.binary_erosion(blade, iterations=erode)
    if exclude is not None:
        inner &= ~exclude
    if not inner.any():
        return float("nan")
    return float(np.var(cv2.Laplacian(_grey(img), cv2.CV_32F)[inner]))


def outline_ink(img, blade, flat, grow: int = 3):
    """A drawn leaf's outline ink, grown by ``grow`` px (what :func:`laplacian_variance` leaves out).

    Pixels within 0.25 (RGB) of ``flat.outline_colour`` (a
    :class:`branchnb.leaves.flatart.FlatArt`) and within twice its width
    plus 2 px of the boundary of ``blade``. The outline of a new drawn leaf
    is drawn anew along its boundary, and where its ink lies against the
    alpha mask differs by a pixel between an exemplar (whose blade holds the
    outline's anti-aliased outer rim) and a new leaf; eroded by 3 px only,
    the blade of drawn oaks kept the ink's inner edge in the exemplars and
    not in the new leaves, and the Laplacian variance ratio read 0.25
    for blades whose veins were as sharp as the exemplars'.
    """
    rgb = np.asarray(img, np.float32)[..., :3]
    near = np.linalg.norm(rgb - np.asarray(flat.outline_colour, np.float32), axis=-1) < 0.25
    reach = int(np.ceil(2 * flat.outline_width)) + 2
    band = blade & ~ndi.binary_erosion(blade, iterations=reach)
    return ndi.binary_dilation(near & band, iterations=grow)


def median_pair_iou(blades) -> float:
    """Median IoU over all pairs of blades."""
    v = [(x & y).sum() / max((x | y).sum(), 1) for i, x in enumerate(blades) for y in blades[i + 1:]]
    return float(np.median(v)) if v else float("nan")


def petiole_angle(blade):
    """Angle (degrees) between the petiole (base -> its far end) and the lamina's direction away from the base.

    None when the blade has no petiole.
    """
    from .registration import split_petiole
    lam, pet, base = split_petiole(blade)
    if base is None or not pet.any() or not lam.any():
        return None
    ys, xs = np.nonzero(pet)
    far = np.argmax(np.hypot(xs - base[0], ys - base[1]))
    v_p = np.array([xs[far] - base[0], ys[far] - base[1]], float)
    ly, lx = np.nonzero(lam)
    v_l = np.array([lx.mean() - base[0], ly.mean() - base[1]], float)
    if np.hypot(*v_p) < 1e-6 or np.hypot(*v_l) < 1e-6:
        return None
    c = float(np.dot(-v_l, v_p) / (np.hypot(*v_l) * np.hypot(*v_p)))
    return float(np.degrees(np.arccos(np.clip(c, -1, 1))))


def _band(blade, width=4):
    return blade & ~ndi.binary_erosion(blade, iterations=width)


def margin_foreign_share(img, blade, refs, tol: float = 0.12, width: int = 4) -> float:
    """Share of ``img``'s margin band (``width`` px inside ``blade``) farther than ``tol`` from every
    colour of the reference margin bands ``refs`` (list of (image, blade))."""
    band = _band(blade, width)
    if not band.any():
        return float("nan")
    ref = np.concatenate([np.asarray(r, np.float32)[..., :3][_band(b, width)] for r, b in refs])
    q = np.round(ref / 0.04).astype(np.int32)
    ref = np.unique(q, axis=0).astype(np.float32) * 0.04
    px = np.asarray(img, np.float32)[..., :3][band]
    from scipy.spatial import cKDTree
    d, _ = cKDTree(ref).query(px, k=1)
    return float((d > tol).mean())


def _contrast(img, blade, sigma=3.0):
    """Grey level over its blur inside the blade, minus 1 (relative: a vein pasted as a ratio keeps it)."""
    g = _grey(img)
    b = blade.astype(np.float32)
    blur = cv2.GaussianBlur(g * b, (0, 0), sigma) / np.maximum(cv2.GaussianBlur(b, (0, 0), sigma), 1e-6)
    return g / np.maximum(blur, 0.02) - 1.0


def vein_continuity(img, blade, skeleton, target: float) -> float:
    """Share of ``skeleton`` pixels (inside ``blade``) where the signed contrast reaches half ``target``."""
    sk = skeleton & ndi.binary_erosion(blade, iterations=3)
    if not sk.any() or target == 0:
        return float("nan")
    c = _contrast(img, blade)
    # the best of the pixel and its 8 neighbours (a vein moved by a pixel is still a vein)
    c = ndi.maximum_filter(c * np.sign(target), size=3)
    return float((c[sk] >= 0.5 * abs(target)).mean())


def fine_veins(veins, width: float = 3.0):
    """Skeleton pixels of the vein mask ``veins`` where the vein is at most ``width`` px wide."""
    sk = _skeleton(veins)
    dt = ndi.distance_transform_edt(np.asarray(veins, bool))
    return sk & (2.0 * dt - 1.0 <= width)


def ghost_ratio(img, bg_veins, donor, spots=None):
    """Ridge response of ``img`` at ``bg_veins`` apart from ``donor`` over plain blade as far from it.

    ``bg_veins``: the background exemplar's true veins carried into the new
    leaf; ``donor``: the vein donor's true veins and pasted layer carried
    the same way; ``spots``: spots to leave out (or None). Pixels of
    ``bg_veins`` farther than 2 px from ``donor`` and ``spots``, inside the
    lamina (:func:`branchnb.leaves.registration.split_petiole`) eroded by
    3 px, over plain blade (4 px from every vein and spot)
    weighted to the same distances from ``donor``
    (:func:`branchnb.leaves._measure.vein_system_scores`' ``bg_own``).
    Returns ``(ratio, pixels)``; ratio NaN when no pixel is left.
    """
    from ._measure import _distance_matched, _ridge
    from .registration import split_petiole
    blade = np.asarray(img)[..., 3] > 0.5
    lam, _, base = split_petiole(blade)
    # The lamina only: the pasted petiole is another exemplar's, and the background's veins carried by the
    # lamina's maps past the base lay along its rims (fan leaves: every pixel the column counted).
    blade = ndi.binary_erosion(lam if base is not None and lam.any() else blade, iterations=3)
    sp = np.zeros(blade.shape, bool) if spots is None else spots
    away = ~ndi.binary_dilation(donor | sp, iterations=2)
    at = blade & bg_veins & away
    plain = blade & away & ~ndi.binary_dilation(bg_veins | sp, iterations=4)
    if not at.any() or not plain.any():
        return float("nan"), 0
    r = _ridge(img)
    return _distance_matched(r, at, plain, ndi.distance_transform_edt(~donor)), int(at.sum())


def _skeleton(mask):
    from skimage.morphology import skeletonize
    return skeletonize(np.asarray(mask, bool))


def synthesis_row(a, n_new: int = 6, seed: int = 0, name: str = "", save: str | None = None,
                  truth=None, spots=None) -> dict:
    """Every column of the module docstring for one analysis ``a`` and ``n_new`` new leaves.

    ``truth``: the exemplars' true vein masks (analysis frame) for the ``fine`` and ``ghost`` columns, or
    None; ``spots``: their true spot masks (left out of ``ghost``), or None.
    """
    from . import synthesis
    from .synthesis import _canvas_coords, _prepared, generate

    p = _prepared(a)
    calls = []
    orig = p.source_coords
    orig_leaf = synthesis.generate_leaf

    def spy(e, m, disp):
        c = orig(e, m, disp)
        calls.append((e, _canvas_coords(p, c)))
        return c

    coords = []

    def spy_leaf(*args, **kw):
        calls.clear()
        out = orig_leaf(*args, **kw)
        coords.append(list(calls))
        return out
    p.source_coords = spy
    synthesis.generate_leaf = spy_leaf
    t0 = time.process_time()
    try:
        # One batch, as a user makes them (generate stratifies the exemplar draws over it).
        leaves = generate(a, n_new, rng=seed)
    finally:
        p.source_coords = orig
        synthesis.generate_leaf = orig_leaf
    sec = (time.process_time() - t0) / n_new
    ex, bl = a.exemplars, a.blades
    ink = (lambda img, b: outline_ink(img, b, p.flat)) if p.flat is not None else (lambda img, b: None)
    lv_ex = np.nanmean([laplacian_variance(e, b, exclude=ink(e, b)) for e, b in zip(ex, bl)])
    lv_new = np.nanmean([laplacian_variance(x.image, x.blade, exclude=ink(x.image, x.blade)) for x in leaves])
    cut = np.mean([max(x.image[..., 3][0].max(), x.image[..., 3][-1].max(), x.image[..., 3][:, 0].max(),
                       x.image[..., 3][:, -1].max()) >= 0.5 for x in leaves])
    ang_ex = [petiole_angle(b) for b in bl]
    ang_ex = [v for v in ang_ex if v is not None]
    ang_new = [petiole_angle(x.blade) for x in leaves]
    ang_new = [v for v in ang_new if v is not None]
    pet_dev = max([0.0] + [v - max(ang_ex) for v in ang_new]) if ang_ex and ang_new else float("nan")
    refs = [(e, b) for e, b in zip(ex, bl)]
    f_ex = np.mean([margin_foreign_share(e, b, refs[:i] + refs[i + 1:]) for i, (e, b) in enumerate(refs)]) \
        if len(refs) > 1 else float("nan")
    f_new = [margin_foreign_share(x.image, x.blade, refs) for x in leaves]
    # Vein continuity along the donor's induced veins carried into the new leaf.
    cont, cont_ex = [], []
    vk = next((k for k, L in enumerate(a.layers) if L.name == "veins"), 0 if a.layers else None)
    if vk is not None:
        L = a.layers[vk]
        tgt = []
        for e in range(len(ex)):
            sk = _skeleton(L.masks[e])
            if sk.sum() < 10:
                tgt.append(0.0)
                continue
            c = _contrast(ex[e], bl[e])
            tgt.append(float(np.median(c[sk & ndi.binary_erosion(bl[e], iterations=3)])) if sk.any() else 0.0)
            cont_ex.append(vein_continuity(ex[e], bl[e], sk, tgt[-1]))
        for x, calls_x in zip(leaves, coords):
            d = x.layers.get(L.name, -1)
            c = next((c for e, c in calls_x[1:] if e == d), None)
            if d < 0 or c is None or tgt[d] == 0:
                continue
            carried = cv2.remap(L.masks[d].astype(np.float32), c[..., 0], c[..., 1], cv2.INTER_LINEAR) > 0.5
            cont.append(vein_continuity(x.image, x.blade, _skeleton(carried), tgt[d]))
    ghost, ghost_n = [], []
    if truth is not None and vk is not None:
        from ._measure import _apply_coords
        name_v = a.layers[vk].name
        for x, calls_x in zip(leaves, coords):
            if not calls_x:
                continue
            bg_e, cbg = calls_x[0]
            d = x.layers.get(name_v, -1)
            c = next((c for e, c in calls_x[1:] if e == d), None)
            donor = np.zeros(bl[0].shape, bool)
            if d >= 0 and c is not None:
                donor = _apply_coords(truth[d], c, 0.25) | _apply_coords(
                    p.layer_masks[vk][d].astype(np.float32), c, 0.25)
            sp = None
            if spots is not None:
                sp = _apply_coords(spots[bg_e], cbg)
                d_s = x.layers.get("spots", -1)
                cs = next((c for e, c in calls_x[1:] if e == d_s), None)
                if cs is not None:
                    sp = sp | _apply_coords(spots[d_s], cs, 0.25)
            v, k = ghost_ratio(x.image, _apply_coords(truth[bg_e], cbg), donor, sp)
            if k:
                ghost.append(v)
                ghost_n.append(k)
    fine, fine_ex = [], []
    if truth is not None and vk is not None:
        fv = [fine_veins(t) & ndi.binary_erosion(b, iterations=3) for t, b in zip(truth, bl)]
        ftg = [float(np.median(_contrast(ex[e], bl[e])[fv[e]])) if fv[e].sum() >= 10 else 0.0
               for e in range(len(ex))]
        fine_ex = [vein_continuity(ex[e], bl[e], fv[e], ftg[e]) for e in range(len(ex)) if ftg[e] != 0]
        for x, calls_x in zip(leaves, coords):
            d = x.layers.get(a.layers[vk].name, -1)
            c = next((c for e, c in calls_x[1:] if e == d), None)
            if d < 0 or c is None or ftg[d] == 0:
                continue
            carried = cv2.remap(fv[d].astype(np.float32), c[..., 0], c[..., 1], cv2.INTER_LINEAR) > 0.25
            fine.append(vein_continuity(x.image, x.blade, _skeleton(carried), ftg[d]))
    if save:
        from ..core.io import encode_png
        h = max(x.image.shape[0] for x in leaves)
        row = np.hstack([np.pad(x.on_white(), ((0, h - x.image.shape[0]), (0, 4), (0, 0)), constant_values=1)
                         for x in leaves])
        with open(save, "wb") as f:
            f.write(encode_png(row))
    return dict(name=name, sharp=lv_new / lv_ex, iou_new=median_pair_iou([x.blade for x in leaves]),
                iou_ex=median_pair_iou(list(bl)), cut=float(cut), pet_dev=pet_dev,
                foreign=float(np.nanmean(f_new)), foreign_ex=float(f_ex),
                vein_cont=float(np.nanmean(cont)) if cont else float("nan"),
                vein_cont_min=float(np.nanmin(cont)) if cont else float("nan"),
                vein_cont_ex=float(np.nanmean(cont_ex)) if cont_ex else float("nan"),
                fine=float(np.nanmean(fine)) if fine else float("nan"),
                fine_min=float(np.nanmin(fine)) if fine else float("nan"),
                fine_ex=float(np.nanmean(fine_ex)) if fine_ex else float("nan"),
                ghost=float(np.average(ghost, weights=ghost_n)) if ghost else float("nan"),
                ghost_max=float(np.nanmax(ghost)) if ghost else float("nan"), ghost_px=int(sum(ghost_n)),
                cpu_s=sec)


def _procedural(kind, size, seed, n=4, with_truth=False):
    from ._measure import _family_on_canvas, _TrueRegistration
    from .analysis import analyze
    fam, truth, kps, shape = _family_on_canvas(kind, size, n, seed)
    regs = [_TrueRegistration(k, kps[0], shape) for k in kps]
    a = analyze(fam, 0, {"veins": fam[0].layers["veins"], "spots": fam[0].layers["spots"]}, registrations=regs)
    return (a, [t["veins"] for t in truth], [t["spots"] for t in truth]) if with_truth else a


def speed(size: int = 1000, n: int = 2):
    """CPU seconds and peak memory (tracemalloc, ru_maxrss) of ``generate_leaf`` at ``size`` px."""
    from .synthesis import _prepared, generate_leaf
    a = _procedural("lobed", size, 0, 3)
    mp = a.blades[0].size / 1e6
    t0 = time.process_time()
    _prepared(a)
    prep = time.process_time() - t0
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    secs = []
    for s in range(n):
        t0 = time.process_time()
        generate_leaf(a, s)
        secs.append(time.process_time() - t0)
    rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    tracemalloc.start()
    generate_leaf(a, n)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return dict(mp=mp, prepare_s=prep, leaf_s=float(np.median(secs)), peak_mb=peak / 2**20,
                maxrss_mb=rss1 / 1024, maxrss_growth_mb=(rss1 - rss0) / 1024)


def _print(r):
    print(f"{r['name']:<22} sharp {r['sharp']:.2f}  iou new {r['iou_new']:.2f} ex {r['iou_ex']:.2f}  "
          f"cut {r['cut']:.2f}  pet_dev {r['pet_dev']:5.1f}  foreign {r['foreign']:.3f} (ex {r['foreign_ex']:.3f})  "
          f"vein_cont {r['vein_cont']:.2f} min {r['vein_cont_min']:.2f} (ex {r['vein_cont_ex']:.2f})  "
          f"fine {r['fine']:.2f} min {r['fine_min']:.2f} (ex {r['fine_ex']:.2f})  "
          f"ghost {r.get('ghost', np.nan):.2f} max {r.get('ghost_max', np.nan):.2f} ({r.get('ghost_px', 0)} px)  "
          f"{r['cpu_s']:.2f} s/leaf", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m branchnb.leaves._measure_synthesis",
                                 description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=("procedural", "speed", "pickle"))
    ap.add_argument("path", nargs="?")
    ap.add_argument("--n", type=int, default=6)
    ap.add_argument("--sizes", default="192,320")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--kinds", default="lobed,trilobed,elliptic,fan")
    ap.add_argument("--save", default=None, help="folder for a PNG row of the new leaves per analysis")
    args = ap.parse_args(argv)
    if args.what == "speed":
        print(speed())
        return
    if args.what == "pickle":
        with open(args.path, "rb") as f:
            a = pickle.load(f)
        name = args.path.rsplit("/", 1)[-1].split(".")[0]
        _print(synthesis_row(a, args.n, name=name, save=f"{args.save}/{name}.png" if args.save else None))
        return
    for kind in args.kinds.split(","):
        for size in (int(s) for s in args.sizes.split(",")):
            for seed in range(args.seeds):
                a, truth, spots = _procedural(kind, size, seed, with_truth=True)
                name = f"{kind}_{size}_{seed}"
                _print(synthesis_row(a, args.n, name=name, truth=truth, spots=spots,
                                     save=f"{args.save}/{name}.png" if args.save else None))


if __name__ == "__main__":
    main()
