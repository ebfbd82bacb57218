"""Induced-vein IoU on families whose veins differ in colour from leaf to leaf (every leaf as training leaf).

Run ``python -m branchnb.leaves._measure_colours`` (``--sizes``, ``--seeds``,
``--kinds``, ``--factor``). Families of :func:`~branchnb.leaves.procedural_colours.vein_colour_family`
(pale, red and dark veins in turn), each leaf as the training leaf with its
true vein layer, the other leaves registered through the true keypoints and
perturbed by ``factor`` main-vein widths (as ``_measure snapping``); IoU of
every other leaf's induced vein layer with its true veins.

Measured (3 kinds at 192 px, seed 0, 18 training -> exemplar pairs): IoU
min 0.05, mean 0.61 (pale -> red 0.66-0.70, pale -> dark 0.56-0.77,
red -> pale 0.61-0.66, dark -> pale 0.70-0.82, dark -> red 0.48-0.71,
red -> dark 0.05-0.67: red and dark veins both stand out darker, the
contrast test takes them for one colour and the red colour model misses
the dark veins). Before (the training leaf's contrast direction, colour
model and ``delta`` on every exemplar): min 0.00, mean 0.12 (0.00 on every
pale -> red / dark pair). Re-choosing ``delta`` on every exemplar whose
ridge pixels the training ``delta`` finds under half of gave min 0.48,
mean 0.67 but cost a lobed leaf's spots 0.70 -> 0.38 (``_measure induction``);
taking the exemplar's own colour model wherever the training model's colour
term on its ridge pixels exceeded 1.8x the training layer's fixed red ->
dark (0.05 -> 0.69, min 0.48, mean 0.68) but fired on same-coloured lobed
and trilobed leaves (spots mean 0.75 -> 0.25, 0.84 -> 0.63): not kept.
Kept (leaves18): an exemplar whose ``{D < delta}`` under the training
colour model covers under half the layer's expected area takes its own
colour model (vein networks only, not spot clusters); the contrast test
compares contrasts in each leaf's own CIELAB (matched onto a red training
leaf's statistics a dark-green vein's contrast turned within 0.87-0.98 of
the red one's; in their own colours 0.47-0.49); where the exemplar's own
model is used its thin layer loses blobs wider than the user's layer and
is trimmed to pixels that stand out themselves (the ``n x n`` window drew
1-2 px veins 4-6 px wide); side ridges leaving the snapped network.
Measured (same run as above): min 0.05 -> 0.63, mean 0.61 -> 0.74; red ->
dark 0.05-0.67 -> 0.70-0.78, dark -> red 0.48-0.71 -> 0.72-0.73, pale ->
dark 0.56-0.77 -> 0.63-0.76. Same-coloured 3-leaf families (192 px, 2 vein
widths off, every leaf as training leaf): veins unchanged (mean 0.76 ->
0.77), spots 0.53 -> 0.80 and 0.01 -> 0.65 on two pairs, the rest the same.
With a 1.5 px ink outline in the vein colour (``--colours dark --outline
1.5``): min 0.53 -> 0.80, mean 0.62 -> 0.83 with the outline band left out.
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy import ndimage as ndi

from ._measure import KINDS_ALL, _Perturbed, _TrueRegistration, main_vein_width


def _on_canvas(fam):
    from .analysis import normalise_exemplars
    _, blades, offs = normalise_exemplars(fam)
    shape = blades[0].shape

    def put(m, o):
        c = np.zeros(shape, bool)
        c[o[1]:o[1] + m.shape[0], o[0]:o[0] + m.shape[1]] = m
        return c
    truth = [put(leaf.layers["veins"], o) for leaf, o in zip(fam, offs)]
    kps = [leaf.keypoints + np.asarray(o) for leaf, o in zip(fam, offs)]
    return truth, kps, shape


def outline_precision(induced, truth, blade, outline: float = 0.0, tol: int = 1):
    """Vein precision near the outline: (share of induced pixels in the outline band on a true vein,
    share of the band's non-vein pixels induced).

    The band is the blade's edge ``outline + 2`` px deep (the ink outline of a
    sketch and a vein-width beyond). A vein reaching the margin counts as
    vein within ``tol`` px of the truth. Precision is NaN when nothing in the
    band was induced (nothing taken: the best answer).
    """
    from ..core.distance import edt
    from .analysis_induce import _closed_blade  # a sketch's gaps between paint strokes are inside it
    band = blade & (edt(_closed_blade(blade)) <= float(outline) + 2.0)
    near_truth = ndi.binary_dilation(truth, iterations=tol) if tol > 0 else truth
    got = induced & band
    prec = float((got & near_truth).sum() / got.sum()) if got.any() else float("nan")
    plain = band & ~near_truth
    return prec, float((got & plain).sum() / max(plain.sum(), 1))


def colour_rows(kinds=KINDS_ALL, sizes=(192,), seeds=range(1), n_leaves: int = 3, factor: float = 2.0,
                colours=("pale", "red", "dark"), outline: float = 0.0):
    """One dict per (kind, size, seed, training leaf, exemplar): vein IoU with the truth."""
    from ..core.metrics import iou
    from .analysis import analyze
    from .procedural_colours import vein_colour_family

    out = []
    for kind in kinds:
        for size in sizes:
            for seed in seeds:
                fam = vein_colour_family(n_leaves, size=size, kind=kind, colours=colours, outline=outline, rng=seed)
                gt, kps, shape = _on_canvas(fam)
                amp = factor * float(np.median([main_vein_width(g) for g in gt]))
                for t in range(n_leaves):
                    rng = np.random.default_rng((int(seed), t))
                    regs = [_TrueRegistration(k, kps[t], shape) for k in kps]
                    regs = [r if e == t or amp <= 0 else _Perturbed(r, amp, rng) for e, r in enumerate(regs)]
                    a = analyze(fam, t, {"veins": fam[t].layers["veins"]}, registrations=regs)
                    layer = a.layer("veins")
                    for e in range(n_leaves):
                        if e != t:
                            prec, band_share = outline_precision(layer.masks[e], gt[e], a.blades[e], outline)
                            out.append(dict(kind=kind, size=size, seed=int(seed), training=t, exemplar=e,
                                            pair=f"{colours[t % len(colours)]}->{colours[e % len(colours)]}",
                                            iou=iou(layer.masks[e], gt[e]), lam=a.lambdas["veins"],
                                            outline_precision=prec, outline_taken=band_share))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m branchnb.leaves._measure_colours",
                                 description=__doc__.split("\n")[0])
    ap.add_argument("--kinds", default=",".join(KINDS_ALL))
    ap.add_argument("--sizes", default="192")
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--factor", type=float, default=2.0)
    ap.add_argument("--outline", type=float, default=0.0, help="ink outline width (px) in the vein colour")
    ap.add_argument("--colours", default="pale,red,dark")
    args = ap.parse_args(argv)
    rows = colour_rows(tuple(args.kinds.split(",")), tuple(int(s) for s in args.sizes.split(",")),
                       range(args.seeds), factor=args.factor,
                       colours=tuple(args.colours.split(",")), outline=args.outline)
    for r in rows:
        print(f"{r['kind']:<9} {r['size']:>4} {r['seed']:>2} {r['pair']:<12} IoU {r['iou']:.2f} lambda {r['lam']:.3f}"
              f"  outline band: precision {r['outline_precision']:.2f} taken {r['outline_taken']:.3f}")
    v = np.array([r["iou"] for r in rows])
    p = np.array([r["outline_precision"] for r in rows])
    b = np.array([r["outline_taken"] for r in rows])
    print(f"all: min {v.min():.2f} mean {v.mean():.2f}; outline band precision min {np.nanmin(p):.2f} "
          f"mean {np.nanmean(p):.2f} (NaN: nothing taken, {int(np.isnan(p).sum())} of {len(p)}), "
          f"share of the band's plain pixels taken max {b.max():.3f} mean {b.mean():.3f}")


if __name__ == "__main__":
    main()
