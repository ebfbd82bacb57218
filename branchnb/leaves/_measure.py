"""Measurements of leaf variations on the procedural families (true answers known), per kind.

Run ``python -m branchnb.leaves._measure registration`` or
``python -m branchnb.leaves._measure induction`` (``--help`` for sizes,
seeds and kinds). Both print one row per pair or leaf and a summary per
kind; they are what the figures in the tests and the docs come from.

Registration
------------
For each kind and seed: a family of ``1 + pairs`` leaves, each other
leaf registered to the first. Errors are mean distances (training px)
between the true corresponding keypoints (the same material point on
every leaf, :attr:`ProceduralLeaf.keypoints`):

* ``affine``: after the affine start of the blade masks alone
  (:func:`start_alignment` with ``start="affine"``: best similarity by
  outline chamfer, refined by trimmed ICP), the issue's reference;
* ``reg``: after :func:`register` (its own start and TPS-RPM);
* ``cut`` = ``1 - reg / affine``;
* ``best_affine``: the least-squares affine map through the true
  keypoints (no registration from masks can be told apart from it
  without non-rigid information);
* ``outline_oracle``: a thin-plate spline through the TRUE outline
  correspondences (150 material points of the margin): what an
  outline-driven registration reaches when it slides nowhere;
* ``slide``: how far the same material margin point lies from its
  arc-length position (mean, px): the along-outline shift an outline
  without corners or teeth cannot reveal.

Measured (8 seeds x 2 pairs, ``--sizes 192,384 --seeds 8``): cut lobed
0.59, trilobed 0.61, elliptic 0.59 at 192 px and 0.60, 0.61, 0.57 at
384 px; with the true outline correspondences 0.63, 0.71, 0.73. With
``lambda1_init`` 10, before: 0.55, 0.60, 0.52 and 0.55, 0.58, 0.49.
(Before the elliptic kind had material serrate teeth and secondaries,
its cut was 0.34-0.36: the same material point lay 3.7 px from its
arc-length position on a margin without corners, and nothing in the
image told where it was.)

Induction
---------
For each kind, size and seed: a family of ``n_leaves``, the training
leaf's true layers as the user's layers, :func:`analyze` with the
registrations (``--truth``: through the true correspondences, which
isolates induction; default: TPS-RPM), IoU of every other exemplar's
induced layer with its true layer, lambda and delta per layer.

Measured (``--truth``, 3 seeds, sizes 256 and 512; min / mean IoU over 9
exemplars), with ``S_e`` in Lab units and veins drawn at least 1.5 px
wide: veins lobed 0.74 / 0.82 and 0.73 / 0.81, trilobed 0.70 / 0.77 and
0.68 / 0.76, elliptic 0.61 / 0.77 and 0.70 / 0.79; spots 0.69-0.95.
Vein lambda 0-0.11 (0.000 on lobed 256 seed 0, a tie with the spots'
0): the secondary veins are grown anew on every leaf, so only the
primaries' liberal layers intersect. (Before: sub-pixel veins, equal
channel weights: veins at 256 px min 0.31-0.55, mean 0.50-0.60.)

Vein systems
------------
``python -m branchnb.leaves._measure veinsystems`` (:func:`vein_system_rows`):
new leaves of 3-leaf families (true registrations), ridge response at
the background exemplar's own true veins over plain blade. Measured (2
seeds x 4 new leaves per kind and size, 192 / 320 px): mean 0.91 / 0.81
lobed, 0.87 / 0.91 trilobed, 1.00 / 1.11 elliptic; single leaves up to
1.52; at the donor's veins 2.5-6.3. The background's residual itself,
carried the same way before any layer is pasted, scored 0.9-1.65 at
those pixels (5 leaves, only the donor's veins left out) and shows no vein by eye (its inpainted strips are smoother
or a shade off the blade around them), so what is left above 1 comes
from the removal, not from pasting; the spots' removal leaves visible
brown rims (not counted here). The second row of the report weighs plain
blade to the same distances from the donor's veins as the background's
vein pixels (a pasted vein's ridge response reaches past the 4 px left
out): 1.06 / 1.08 elliptic, so the donor's halo is not what is above 1.
With the wider ridge extension of the removed veins
(:func:`branchnb.leaves.analysis._ridge_extension`, level 0.15 and reach
0.15 of the leaf size): see the numbers there.

How many pixels each figure rests on (printed with it): at 192 px an
elliptic leaf keeps 0-32 background vein pixels farther than 4 px from the
donor's veins (its per-leaf ratios 0.79-1.54 are noise; pixel-weighted
1.07), at 320 px 111-329 (mean 1.00, weighted 1.00). Tried on the
elliptic family without gain (mean at 192 / 320 px): no texture
correction 0.99 / 1.00, the paper's pasted colours 1.04 / 1.00, bilinear
instead of Lanczos sampling 0.98 / 1.01, the background's lines of the
layer's polarity flattened (grey opening) within two vein widths of its
removed veins 1.00 / 1.02.

Latest (issue 22, ``rel``: see :func:`vein_system_scores`). The ratio to
plain blade above (``bg``) read the donor's veins, not the background's:
every pixel it kept lay 3.6-5.3 px from a donor vein (the same vein of
the other leaf, moved by both registrations and the warps), and in the
exemplars themselves, untouched, the ridge response 3-4 / 4-5 px from a
real vein is 1.4-2.9 / 1.0-1.7 times plain blade's (its side lobes; the
fan's dense forks the most). An exemplar with another exemplar's true
veins carried onto it (one vein system, nothing synthesized) scored
``bg`` 1.95 on the fan family at 320 px, 0.95 on the elliptic. Neither
the donor's true veins pasted instead of its induced layer nor the
one-system step (``one_system`` 0 or 2) moved ``bg`` (elliptic 320
seed 1: 1.08 either way): it was no induction error. The background
residuals keep no tone at their true veins (mean grey minus the
vein-free rendering's -0.0004 to +0.0010, against 0.17-0.20 in the
exemplars; 0 at 1-5 px). ``rel`` divides by the same pixels of the same
leaf made on the background rendered without veins (:func:`plain_exemplars`).
Measured (3 seeds x 4 new leaves, 256 / 320 / 512 px; mean ``bg`` ->
mean ``rel``, ``own_rel`` at 2 px): fan 2.17 / 2.13 / 2.02 -> 1.04 /
1.03 / 0.97, own 1.02 / 1.02 / 0.99; elliptic 0.90 / 0.96 / 0.97 -> 0.99
/ 0.98 / 0.91, own 1.00 / 0.99 / 0.95; lobed 0.79 / 0.76 / 0.84 -> 0.97
/ 0.96 / 0.88, own 0.98 / 0.98 / 0.92; trilobed 0.78 / 0.78 / 0.82 ->
0.98 / 0.94 / 0.87, own 0.99 / 0.96 / 0.92. ``bg`` of the vein-free
leaves themselves: fan 2.08-2.12, the others 0.79-1.06 (single fan
leaves 0.85-1.30 on 10-60 pixels each; fan 320 seed 2's two leaves at 1.10 show no line by eye, and
neither ``one_system`` 0 nor ``correct=False`` changes them: the texture
of the residual's filled strips beside a pasted vein).
Fan 256 / 320 (leaves42, 3 seeds x 4 leaves): ``rel`` rests on 64 / 350
pixels in all (0-23 / 5-62 per leaf; 3 of 12 fan-256 leaves have none):
the fan's background and donor veins are the same veins of one family,
mostly closer than 4 px, so ``rel`` counts only where they part. Per-leaf
``rel`` 0.85-1.30, mean 1.035 / 1.033, standard error 0.037 / 0.029,
bootstrap 95 % of the mean 0.98-1.12 / 0.98-1.09: not distinguishable from
1. The highest (320 seed 2 leaves 0 and 1, background 2 and donor 1,
1.22 / 1.17) sit 3.6-5.4 px from the donor's pasted vein; there the
prepared background (``_Prepared.stage[-1]``) is filled nearly flat (high-
pass grain 0.0018 against 0.0065 on plain blade), the new leaf is 0.004
darker and smoother than the vein-free one (Laplacian variance 1.0e-3
against 3.3e-3) and shows no line by eye; both the low-pass (1.11) and
the high-pass (1.04) part of the difference raise the ratio. Regraining
the analysis' Telea fill of thin strips (``remove_layer``) left every fan
figure unchanged to three decimals (fan 320, rerun; which later fill
replaces it there was not traced);
``flatten_leftover(regrain=True)`` was measured worse on the elliptic
family (above).

Maples
------
Latest (issue 22, :mod:`branchnb.leaves.snapping`: a path far fainter than the leaf's other paths
dropped, ``RELATIVE_EVIDENCE``; widths scaled by the square root of the leaf-size ratio,
``WIDTH_POWER``; both on by default):
mean IoU per training maple 01-07: 0.77 0.74 0.74 0.65 0.69 0.75 0.72, all 42
pairs 0.701 -> 0.723, under 0.6 4 -> 3, all onto maple 07 (03 -> 07 0.59, 04 -> 07 0.49, 05 -> 07
0.41 -> 0.49: traces run on past where 07's torn lobes' veins and its hand trace end; 04 -> 07's
right lateral stops at a hole); 02 -> 04 0.56 -> 0.75. Before it
(the junction's basal veins the snapping lost, found by rays,
:mod:`branchnb.leaves.snapping_basal`): mean IoU per training maple 01-07:
0.74 0.67 0.73 0.64 0.68 0.75 0.70, all 42 pairs 0.690 -> 0.701, under 0.6
7 -> 4 (02 -> 04 0.56: found where they run, drawn wider than 04's traced
veins; 03 -> 07 0.59, 04 -> 07 0.49: maple 07's right lateral lost to a ridge
beside it; 05 -> 07 0.41: false veins beside 07's midrib). Before:

(the registration's own carry as a third template start,
:data:`~branchnb.leaves.snapping.REGISTRATION_START` 1.1, and a speckled
blade's holes keeping their evidence, :func:`~branchnb.leaves.snapping_stray._hole_rim`):
mean IoU per training maple 01-07: 0.71 0.67 0.73 0.64 0.63 0.75 0.70, all 42
pairs mean 0.67 -> 0.69, pairs under 0.6: 10 -> 7 (01 -> 04 0.58, 01 -> 07 0.53,
02 -> 04 0.56, 03 -> 07 0.59, 04 -> 07 0.49, 05 -> 04 0.49, 05 -> 07 0.35; maple
05's hand trace joins its right lateral to the midrib 14 px above the
junction, and maple 07's torn lobes stop its traced veins; tried, not kept:
that short stem between two junctions joined to the branches above it, mean
0.69 -> 0.70 but 8 pairs under 0.6 and procedural trilobed 192 px min 0.75 ->
0.73). Before: 0.70 0.69
0.69 0.61 0.65 0.67 0.70. With the symmetry completion of
:mod:`branchnb.leaves.snapping_mirror` (before it 0.70 0.69 0.69 0.61 0.65 0.60
0.60). Older figures below.

Sketches
--------
``python -m branchnb.leaves._measure sketches`` (:func:`sketch_rows`): the two
sketched maples of ``/work/shared/data/leaves_more`` (never seen by the
tests before issue 22's third pass: green brush strokes with white gaps, a
dashed ink outline, ink veins 6-7 px wide at 360 px), each as the training
leaf with its own ink veins as the user's layer. Vein IoU / recall of the
other's induced veins against its ink veins, 1 -> 2 and 2 -> 1: 0.11 / 0.13
and 0.06 / 0.06 before (the 6.2 px veins were not a thin layer, so nothing
was snapped; maple 2's midrib stayed in its residual), 0.57 / 0.78 with the
leaf-relative thin width (:func:`branchnb.leaves.analysis_snapped.thin_width`)
and 0.41 / 0.63 -> 0.54 / 0.63 once the outline band is the closed blade's
and 0.2 of it inked counts as outline (2 -> 1 had traced long stretches of
the dashed outline as vein and removed them from the residual). Not solved:
the blade is the paint and ink alone (the white gaps inside the outline
are not leaf), and 1 -> 2 still takes short stretches of outline.
With the outline stretches of an inked training outline left out
(:func:`branchnb.leaves.analysis_outline._outline_stretches`): 1 -> 2 IoU
0.57 -> 0.69, share of the 6 px outline band's plain pixels taken as vein
0.170 -> 0.033; 2 -> 1 unchanged (0.54, nothing in the band).

``python -m branchnb.leaves._measure maples``: each hand-traced sample
maple as training leaf, TPS-RPM registrations: induced-vein IoU mean
0.62, per training maple 0.58-0.69, min 0.29 (before the lightness
projection and the polar trace of :mod:`branchnb.leaves.snapping`: mean
0.45, per training maple 0.33-0.55, min 0.16).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy import ndimage as ndi

KINDS_ALL = ("lobed", "trilobed", "elliptic")
#: The kinds :func:`plain_exemplars` can render without veins (the procedural renderer's).
KINDS_PLAIN = ("lobed", "trilobed", "elliptic", "fan")


def _shape_of(leaf, size):
    from .procedural import _Shape

    # procedural_leaf draws the shape first from its seed: the same _Shape again.
    return _Shape(leaf.kind, size, 1.0, 30.0, (0.72, 0.9), np.random.default_rng(leaf.seed))


def _margin(shape, n=150):
    ac = np.linspace(-np.pi, np.pi, n, endpoint=False)
    return shape.to_canvas(shape.material(ac, np.ones(n)))


def _arc_positions(outline):
    closed = np.vstack([outline, outline[:1]])
    seg = np.hypot(*np.diff(closed, axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(seg)])[:-1]
    return s / seg.sum(), float(seg.sum())


def _mean_dist(a, b):
    return float(np.hypot(*(np.asarray(a) - np.asarray(b)).T).mean())


def registration_rows(kinds=KINDS_ALL, seeds=range(4), size: int = 192, pairs: int = 2, params=None):
    """One dict per registered pair (see the module docstring for the columns)."""
    from scipy.interpolate import RBFInterpolator

    from .procedural import leaf_family
    from .registration import register, start_alignment

    out = []
    for kind in kinds:
        for seed in seeds:
            fam = leaf_family(1 + pairs, size=size, kind=kind, rng=seed)
            tr = fam[0]
            sh_t = _shape_of(tr, size)
            m_t = _margin(sh_t)
            arc_t, _ = _arc_positions(_margin(sh_t, 2000))
            for j, ex in enumerate(fam[1:], start=1):
                t0 = time.perf_counter()
                reg = register(ex, tr, params=params)
                sec = time.perf_counter() - t0
                aff, _ = start_alignment(ex.blade, tr.blade, start="affine")
                e_aff = _mean_dist(ex.keypoints @ aff[:, :2].T + aff[:, 2], tr.keypoints)
                e_reg = _mean_dist(reg.forward(ex.keypoints), tr.keypoints)
                a = np.column_stack([ex.keypoints, np.ones(len(ex.keypoints))])
                best = a @ np.linalg.lstsq(a, tr.keypoints, rcond=None)[0]
                sh_e = _shape_of(ex, size)
                m_e = _margin(sh_e)
                oracle = RBFInterpolator(m_e, m_t, kernel="thin_plate_spline", smoothing=1.0)
                arc_e, perim_e = _arc_positions(_margin(sh_e, 2000))
                d = (arc_e - arc_t + 0.5) % 1.0 - 0.5
                out.append(dict(kind=kind, seed=int(seed), pair=j, affine=e_aff, reg=e_reg,
                                cut=1.0 - e_reg / max(e_aff, 1e-9),
                                best_affine=_mean_dist(best, tr.keypoints),
                                outline_oracle=_mean_dist(oracle(ex.keypoints), tr.keypoints),
                                slide=float(np.abs(d).mean() * perim_e), seconds=sec))
    return out


def _print_registration(rows, size):
    cols = ("affine", "reg", "cut", "best_affine", "outline_oracle", "slide", "seconds")
    print(f"registration at {size} px: true-keypoint error (px) per pair")
    print("kind      seed pair " + " ".join(f"{c:>14}" for c in cols))
    for r in rows:
        print(f"{r['kind']:<9} {r['seed']:>4} {r['pair']:>4} " + " ".join(f"{r[c]:>14.2f}" for c in cols))
    print("summary per kind (cut = 1 - mean reg / mean affine; worst = max reg/affine of a pair)")
    for kind in dict.fromkeys(r["kind"] for r in rows):
        rs = [r for r in rows if r["kind"] == kind]
        aff = np.mean([r["affine"] for r in rs])
        reg = np.mean([r["reg"] for r in rs])
        orc = np.mean([r["outline_oracle"] for r in rs])
        worst = max(r["reg"] / r["affine"] for r in rs)
        print(f"{kind:<9} pairs {len(rs):>2}  affine {aff:6.2f}  reg {reg:6.2f}  cut {1 - reg / aff:5.2f}  "
              f"worst {worst:4.2f}  outline-oracle cut {1 - orc / aff:5.2f}  "
              f"slide {np.mean([r['slide'] for r in rs]):5.2f}")


def _family_on_canvas(kind, size, n, seed):
    from .analysis import normalise_exemplars
    from .procedural import leaf_family
    from .procedural_strips import strip_family

    fam = strip_family(n, size=size, rng=seed) if kind == "strips" else leaf_family(n, size=size, kind=kind, rng=seed)
    _, blades, offs = normalise_exemplars(fam)
    shape = blades[0].shape

    def on_canvas(m, o):
        canvas = np.zeros(shape, bool)
        canvas[o[1]:o[1] + m.shape[0], o[0]:o[0] + m.shape[1]] = m
        return canvas
    truth = [{k: on_canvas(leaf.layers[k], o) for k in ("veins", "spots")} for leaf, o in zip(fam, offs)]
    kps = [leaf.keypoints + np.asarray(o) for leaf, o in zip(fam, offs)]
    return fam, truth, kps, shape


class _TrueRegistration:
    """Exemplar -> training warp through the true corresponding keypoints (isolates induction)."""

    def __init__(self, exemplar_points, training_points, shape, step: int = 8):
        import cv2
        from scipy.interpolate import RBFInterpolator

        self._fwd = RBFInterpolator(exemplar_points, training_points, kernel="thin_plate_spline")
        self._inv = RBFInterpolator(training_points, exemplar_points, kernel="thin_plate_spline")
        h, w = shape
        gy, gx = np.arange(0, h + step, step), np.arange(0, w + step, step)
        xx, yy = np.meshgrid(gx, gy)
        grid = np.column_stack([xx.ravel(), yy.ravel()]).astype(float)

        def dense(values):
            coarse = values.reshape(len(gy), len(gx), 2).astype(np.float32)
            big = cv2.resize(coarse, ((len(gx) - 1) * step + 1, (len(gy) - 1) * step + 1),
                             interpolation=cv2.INTER_LINEAR)
            return np.ascontiguousarray(big[:h, :w])
        self.map_to_training = dense(self._inv(grid))
        self.map_from_training = dense(self._fwd(grid))

    def forward(self, points):
        return self._fwd(np.asarray(points, float).reshape(-1, 2))

    def inverse(self, points):
        return self._inv(np.asarray(points, float).reshape(-1, 2))

    def to_training(self, img):
        from ..core.warp import remap

        out = remap(np.asarray(img, np.float32) if np.asarray(img).dtype != bool else img.astype(np.float32),
                    self.map_to_training[..., 0], self.map_to_training[..., 1])[0]
        return out[..., 0] > 0.5 if np.asarray(img).dtype == bool else out

    def from_training(self, img):
        from ..core.warp import remap

        out = remap(np.asarray(img, np.float32) if np.asarray(img).dtype != bool else img.astype(np.float32),
                    self.map_from_training[..., 0], self.map_from_training[..., 1])[0]
        return out[..., 0] > 0.5 if np.asarray(img).dtype == bool else out


def induction_rows(kinds=KINDS_ALL, sizes=(192, 512), seeds=range(2), n_leaves: int = 4, truth: bool = False):
    """One dict per (kind, size, seed, layer, exemplar): IoU with the ground truth, lambda, delta."""
    from ..core.metrics import iou
    from .analysis import analyze

    out = []
    for kind in kinds:
        for size in sizes:
            for seed in seeds:
                fam, gt, kps, shape = _family_on_canvas(kind, size, n_leaves, seed)
                regs = [_TrueRegistration(k, kps[0], shape) for k in kps] if truth else None
                t0 = time.perf_counter()
                a = analyze(fam, 0, {"veins": fam[0].layers["veins"], "spots": fam[0].layers["spots"]},
                            registrations=regs)
                sec = time.perf_counter() - t0
                for name in ("veins", "spots"):
                    layer = a.layer(name)
                    for e in range(1, len(fam)):
                        out.append(dict(kind=kind, size=size, seed=int(seed), layer=name, exemplar=e,
                                        iou=iou(layer.masks[e], gt[e][name]), lam=a.lambdas[name],
                                        delta=a.deltas[name], seconds=sec))
    return out


def _print_induction(rows, truth):
    src = "true correspondences" if truth else "TPS-RPM registrations"
    print(f"induction ({src}): IoU of each exemplar's induced layer with its true layer")
    print("kind      size seed layer  exemplars' IoU            lambda   delta")
    keyf = lambda r: (r["kind"], r["size"], r["seed"], r["layer"])  # noqa: E731
    for key in dict.fromkeys(keyf(r) for r in rows):
        rs = [r for r in rows if keyf(r) == key]
        ious = " ".join(f"{r['iou']:.2f}" for r in rs)
        print(f"{key[0]:<9} {key[1]:>4} {key[2]:>4} {key[3]:<6} {ious:<24} {rs[0]['lam']:7.3f} {rs[0]['delta']:7.3f}")
    print("summary per kind, size and layer (min / mean IoU over seeds and exemplars)")
    keyk = lambda r: (r["kind"], r["size"], r["layer"])  # noqa: E731
    for key in dict.fromkeys(keyk(r) for r in rows):
        v = np.array([r["iou"] for r in rows if keyk(r) == key])
        lam = np.mean([r["lam"] for r in rows if keyk(r) == key])
        print(f"{key[0]:<9} {key[1]:>4} {key[2]:<6} min {v.min():.2f} mean {v.mean():.2f}  mean lambda {lam:.3f}")


class _Perturbed:
    """A registration moved by a smooth random displacement of at most ``amplitude`` px (exemplar frame)."""

    def __init__(self, reg, amplitude, rng):
        from .synthesis import random_warp
        mt = np.asarray(reg.map_to_training, np.float32)
        d = random_warp(mt.shape[:2], amplitude, 0.25 * np.sqrt(mt.shape[0] * mt.shape[1]), rng)
        self.map_to_training = (mt + d).astype(np.float32)
        mf = np.asarray(reg.map_from_training, np.float32)
        # The inverse map, to first order: undo the displacement where each exemplar pixel lands.
        import cv2
        back = cv2.remap(d, mf[..., 0], mf[..., 1], cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        self.map_from_training = (mf - back).astype(np.float32)
        self.error_px = float(amplitude)

    def to_training(self, img):
        return _apply_map(img, self.map_to_training)

    def from_training(self, img):
        return _apply_map(img, self.map_from_training)


def _apply_map(img, mp):
    from ..core.warp import remap
    a = np.asarray(img)
    out = remap(a.astype(np.float32), mp[..., 0], mp[..., 1])[0]
    return out[..., 0] > 0.5 if a.dtype == bool else out


def main_vein_width(mask) -> float:
    """Width of a vein layer's main veins: the 90th percentile of ``2 EDT - 1`` on its skeleton."""
    from scipy import ndimage as ndi
    from skimage.morphology import skeletonize
    sk = skeletonize(mask)
    return float(np.percentile(2 * ndi.distance_transform_edt(mask)[sk] - 1, 90))


def snapping_rows(kinds=KINDS_ALL, sizes=(192, 384), seeds=range(1), n_leaves: int = 4, factor: float = 2.0,
                  snap: bool = True):
    """Every leaf of a family as the training leaf in turn, true registrations perturbed by
    ``factor`` main-vein widths: vein IoU of every other leaf's induced layer with its truth."""
    from ..core.metrics import iou
    from .analysis import analyze
    from .induction import InductionParams

    out = []
    for kind in kinds:
        for size in sizes:
            for seed in seeds:
                fam, gt, kps, shape = _family_on_canvas(kind, size, n_leaves, seed)
                width = float(np.median([main_vein_width(g["veins"]) for g in gt]))
                amp = factor * width
                for t in range(n_leaves):
                    rng = np.random.default_rng((int(seed), t))
                    regs = [_TrueRegistration(k, kps[t], shape) for k in kps]
                    regs = [r if e == t else _Perturbed(r, amp, rng) for e, r in enumerate(regs)]
                    a = analyze(fam, t, {"veins": fam[t].layers["veins"]}, registrations=regs,
                                params=InductionParams(snap=snap))
                    layer = a.layer("veins")
                    for e in range(n_leaves):
                        if e != t:
                            out.append(dict(kind=kind, size=size, seed=int(seed), training=t, exemplar=e,
                                            iou=iou(layer.masks[e], gt[e]["veins"]), shift=amp))
    return out


def maple_rows(snap: bool = True):
    """Each sample maple as the training leaf (its hand-traced veins as the user's layer), TPS-RPM
    registrations: vein IoU of every other maple's induced layer with its hand-traced veins."""
    from .. import data
    from ..core.metrics import iou
    from .analysis import analyze, normalise_exemplars
    from .induction import InductionParams
    from .reference import reference_vein_names, reference_veins

    names = reference_vein_names()
    leaves = [data.load(n) for n in names]
    truth = [reference_veins(n) for n in names]
    _, blades, offs = normalise_exemplars(leaves)
    out = []
    for t in range(len(names)):
        a = analyze(leaves, t, {"veins": truth[t]}, params=InductionParams(snap=snap))
        for e in range(len(names)):
            if e == t:
                continue
            g = np.zeros(blades[0].shape, bool)
            dx, dy = offs[e]
            h, w = truth[e].shape
            g[dy:dy + h, dx:dx + w] = truth[e]
            out.append(dict(training=names[t], exemplar=names[e], iou=iou(a.layer("veins").masks[e], g)))
    return out


def vein_system_rows(kinds=KINDS_ALL, sizes=(192, 320), seeds=range(2), n_leaves: int = 3, n_new: int = 4):
    """One vein system per new leaf: ridge response of each new leaf at its background's true veins.

    True registrations, the training leaf's true veins and spots; every
    new leaf's background exemplar's true veins (and spots) and its vein
    donor's are carried into the new leaf by the same coordinate maps the
    synthesis samples with (:func:`vein_system_scores`).
    """
    from .analysis import analyze

    out = []
    for kind in kinds:
        for size in sizes:
            for seed in seeds:
                fam, gt, kps, shape = _family_on_canvas(kind, size, n_leaves, seed)
                regs = [_TrueRegistration(k, kps[0], shape) for k in kps]
                a = analyze(fam, 0, {"veins": fam[0].layers["veins"], "spots": fam[0].layers["spots"]},
                            registrations=regs)
                plain = plain_exemplars(kind, size, n_leaves, seed) if kind in KINDS_PLAIN else None
                rows = vein_system_scores(a, [g["veins"] for g in gt], [g["spots"] for g in gt],
                                          seeds=[100 * int(seed) + k for k in range(n_new)], plain=plain)
                out += [dict(kind=kind, size=size, seed=int(seed), leaf=k, **r) for k, r in enumerate(rows)]
    return out


def vein_system_scores(a, veins, spots=None, seeds=range(4), near: int = 4, params=None, plain=None):
    """Ridge response of new leaves at their background exemplar's true veins, over plain blade.

    ``veins`` (and ``spots``, optional): every exemplar's true masks in the
    analysis frame. For each leaf seed, the background's and the vein
    donor's masks are carried into the new leaf by the coordinate maps the
    synthesis samples with. ``bg`` is the mean ridge response (scikit-image
    ``sato``, both polarities, sigmas 1 and 2, of the grey level) at the
    background's vein pixels farther than 4 px from the donor's veins and
    from any spot (a removed spot's rim is the spots' business) over that
    on plain blade (4 px from any vein or spot); ``bg_matched`` the same
    over plain blade at the same distances from the donor's veins;
    ``donor_ratio`` the same at the donor's veins (the vein system the leaf
    should show); ``bg_own`` (``n_own`` pixels) the background's veins
    farther than 2 px from the donor's true veins *and* from its pasted
    layer, over plain blade at the same distances from them. ``near``: the 4 px above (with ``bg_matched``, veins
    doubled closer than 4 px count too); ``params``: the synthesis
    parameters (None: the defaults).

    ``plain`` (optional): every exemplar rendered without its veins
    (:func:`plain_exemplars`, analysis frame). Then ``bg_rel`` is the
    ridge response at the same pixels as ``bg`` over that at those pixels
    of the same new leaf (same seed, coordinates, donors and warps) built
    on the background exemplar's plain rendering (its true spots taken
    from its residual): the leaf the synthesis would make if the
    background had never had veins. ``bg`` divides by plain blade
    elsewhere, but its pixels lie 4-6 px from the donor's veins (the same
    vein of two leaves, moved by the registrations and warps), where a
    real vein's own ridge response (sigma 2, both polarities: its side
    lobes) is 1.2-2.9 times plain blade's in the exemplars themselves; on
    the fan kind, whose veins fork densely, ``bg`` read 1.5-2.4 for a real
    leaf with one vein system (an exemplar with another exemplar's true
    veins carried onto it), so ``bg`` above 1 there did not show veins left
    over. ``bg_null`` is ``bg`` of that counterfactual leaf; ``own_rel``
    the same as ``bg_rel`` at the ``n_own`` pixels of ``bg_own`` (2 px
    from the donor's veins and pasted layer: the counterfactual carries the
    donor's halo too, so no wider exclusion is needed; more pixels).
    """
    from .synthesis import _canvas_coords, _prepared, generate_leaf

    excl = int(near)
    p = _prepared(a)
    vk = next((k for k, L in enumerate(a.layers) if L.name == "veins"), 0)
    shape = p.shape
    spots = spots if spots is not None else [np.zeros(shape, bool)] * len(veins)
    calls = []
    orig = p.source_coords

    def spy(e, m, disp):
        c = orig(e, m, disp)
        calls.append((e, _canvas_coords(p, c)))
        return c
    p.source_coords = spy
    out = []
    try:
        for s in seeds:
            calls.clear()
            leaf = generate_leaf(a, int(s), params)
            bg, cbg = calls[0]
            e_v = leaf.layers.get("veins", -1)
            cv = next((c for e, c in calls[1:] if e == e_v), None)
            bg_v, bg_s = _apply_coords(veins[bg], cbg), _apply_coords(spots[bg], cbg)
            # The donor's masks at a low level: a 1 px vein carried bilinearly
            # falls below 0.5 on many pixels, and the gaps of a dashed mask
            # counted its pasted ridges as the background's.
            d_v = _apply_coords(veins[e_v], cv, 0.25) if cv is not None else np.zeros(shape, bool)
            e_s = leaf.layers.get("spots", -1)
            cs = next((c for e, c in calls[1:] if e == e_s), None)
            d_s = _apply_coords(spots[e_s], cs, 0.25) if cs is not None else np.zeros(shape, bool)
            blade = ndi.binary_erosion(leaf.image[..., 3] > 0.5, iterations=3)
            r = _ridge(leaf.image)
            others = ndi.binary_dilation(d_v | d_s | bg_s, iterations=excl)
            at_bg = blade & bg_v & ~others
            plain_blade = blade & ~ndi.binary_dilation(bg_v | bg_s | d_v | d_s, iterations=4)
            base = float(r[plain_blade].mean()) if plain_blade.any() else np.nan
            # The same over plain blade at the same distances from the
            # donor's veins (their ridge response's halo reaches past 4 px).
            near = blade & ~ndi.binary_dilation(bg_v | bg_s | d_s, iterations=4) & ~others
            matched = _distance_matched(r, at_bg, near, ndi.distance_transform_edt(~d_v))
            # The background's own veins apart from everything the donor's
            # layer brought (its true veins and its pasted, induced, mask:
            # where the induction put the donor's layer off its true veins,
            # the pasted pieces lay on or beside the background's veins and
            # counted as the background's), 2 px, over plain blade as far
            # from all of it.
            d_all = d_v
            if cv is not None and e_v >= 0:
                d_all = d_v | _apply_coords(p.layer_masks[vk][e_v].astype(np.float32), cv, 0.25)
            at_own = blade & bg_v & ~ndi.binary_dilation(d_all | d_s | bg_s, iterations=2)
            plain_own = blade & ~ndi.binary_dilation(bg_v | bg_s | d_s, iterations=4) \
                & ~ndi.binary_dilation(d_all | d_s | bg_s, iterations=2)
            own = _distance_matched(r, at_own, plain_own, ndi.distance_transform_edt(~d_all))
            rel = null = own_rel = np.nan
            if plain is not None and (at_bg.any() or at_own.any()):
                r0 = _ridge(_counterfactual(a, p, int(s), params, bg, cbg, plain[bg], spots[bg]))
                if at_bg.any():
                    rel = float(r[at_bg].mean() / max(float(r0[at_bg].mean()), 1e-12))
                    null = float(r0[at_bg].mean() / r0[plain_blade].mean()) if plain_blade.any() else np.nan
                if at_own.any():
                    own_rel = float(r[at_own].mean() / max(float(r0[at_own].mean()), 1e-12))
            out.append(dict(background=bg, donor=e_v, bg=float(r[at_bg].mean()) / base if at_bg.any() else np.nan,
                            bg_rel=rel, bg_null=null, own_rel=own_rel,
                            n_bg=int(at_bg.sum()), bg_matched=matched, bg_own=own, n_own=int(at_own.sum()),
                            donor_ratio=float(r[blade & d_v].mean()) / base if (blade & d_v).any() else np.nan))
    finally:
        p.source_coords = orig
    return out


def _ridge(img):
    """Ridge response (scikit-image ``sato``, both polarities, sigmas 1 and 2) of an RGBA image's grey level."""
    from skimage.filters import sato
    g = np.asarray(img, np.float32)[..., :3].mean(-1)
    return np.maximum(sato(g, sigmas=[1, 2], black_ridges=True), sato(g, sigmas=[1, 2], black_ridges=False))


def _counterfactual(a, p, seed, params, bg, c_bg, plain_img, spots):
    """Leaf ``seed`` again, its background exemplar ``bg`` replaced by ``plain_img`` (no veins).

    The plain rendering takes the background's residual at its true
    ``spots`` (grown by 2 px), so only the veins differ; the exemplar has
    no lines left to remove (``own_lines``). Asserts the background is
    carried by the same coordinates ``c_bg``.
    """
    from .prepared import _bleed, _stored
    from .synthesis import _canvas_coords, generate_leaf

    blade = a.blades[bg]
    res = np.asarray(p.stage[-1][bg], np.float32)[..., :3]
    near_spots = ndi.binary_dilation(spots, iterations=2)
    img = np.where(near_spots[..., None], res, np.asarray(plain_img, np.float32)[..., :3])
    cf = _stored(_bleed(img, blade))
    stage, own, det = p.stage[-1], dict(p._own), dict(p.__dict__.get("_details", {}))
    calls = []
    orig = p.source_coords

    def spy(e, m, disp):
        c = orig(e, m, disp)
        calls.append(_canvas_coords(p, c))
        return c
    try:
        p.stage[-1] = list(stage)
        p.stage[-1][bg] = cf
        p._own[bg] = (None, None)
        p.__dict__.get("_details", {}).pop(bg, None)
        p.source_coords = spy
        leaf = generate_leaf(a, seed, params)
    finally:
        p.stage[-1] = stage
        p._own.clear()
        p._own.update(own)
        if "_details" in p.__dict__:
            p._details.clear()
            p._details.update(det)
        p.source_coords = orig
    assert np.array_equal(calls[0], c_bg), "the counterfactual leaf was carried otherwise"
    return leaf.image


def plain_exemplars(kind, size, n, seed):
    """The exemplars of :func:`_family_on_canvas` rendered without their veins (same blade, texture, spots).

    The procedural renderer is run again with the veins' coverage zero
    (the petiole, drawn as blade, keeps its outline), and the images are
    put on the analysis canvas with the same shifts.
    """
    from . import procedural
    from .analysis import normalise_exemplars
    from .procedural import leaf_family

    real = procedural.coverage_polylines

    def no_veins(shape, lines, widths, *args, **kw):
        cov, extra = real(shape, lines, widths, *args, **kw)
        return (np.zeros_like(cov), extra) if len(lines) > 1 else (cov, extra)
    procedural.coverage_polylines = no_veins
    try:
        fam = leaf_family(n, size=size, kind=kind, rng=seed)
    finally:
        procedural.coverage_polylines = real
    imgs, _, _ = normalise_exemplars(fam)
    return [np.asarray(x, np.float32) for x in imgs]


def _distance_matched(r, at, plain, dist, bins: float = 1.0):
    """Mean of ``r`` at ``at`` over its mean on ``plain`` pixels weighted to ``at``'s distances ``dist``.

    Pixels of ``at`` in a distance bin (``bins`` px) with no ``plain`` pixel are left out.
    """
    if not at.any() or not plain.any():
        return np.nan
    ka = np.floor(dist[at] / bins).astype(int)
    kp = np.floor(dist[plain] / bins).astype(int)
    n = int(max(ka.max(), kp.max())) + 1
    cnt_p = np.bincount(kp, minlength=n)
    mean_p = np.bincount(kp, weights=r[plain], minlength=n) / np.maximum(cnt_p, 1)
    ok = cnt_p[ka] > 0
    if not ok.any():
        return np.nan
    return float(r[at][ok].mean() / mean_p[ka[ok]].mean())


def _apply_coords(mask, c, level: float = 0.5):
    import cv2
    m = np.asarray(mask, np.float32)
    c = np.asarray(c, np.float32)
    return cv2.remap(m, c[..., 0], c[..., 1], cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT) > level


SKETCHES = "/work/shared/data/leaves_more"


def _sketch(path, size: int = 360):
    from PIL import Image
    im = Image.open(path).convert("RGBA")
    s = size / max(im.size)
    im = im.resize((round(im.width * s), round(im.height * s)), Image.LANCZOS)
    return np.asarray(im, np.float32) / 255


def _ink_veins(img, inset: int = 10):
    """A sketch's black ink at least ``inset`` px inside its filled outline (its drawn veins), in pieces of 30 px+."""
    a = img[..., 3] > 0.5
    filled = ndi.binary_fill_holes(ndi.binary_closing(a, iterations=6))
    dark = (img[..., :3].max(-1) < 0.15) & a & ndi.binary_erosion(filled, iterations=inset)
    lab, n = ndi.label(dark)
    sizes = ndi.sum(dark, lab, range(1, n + 1))
    return np.isin(lab, 1 + np.flatnonzero(np.asarray(sizes) >= 30))


def sketch_rows(folder: str = SKETCHES):
    """The two sketched maples of ``leaves_more`` (brush strokes, dashed ink outline, ink veins), each
    as the training leaf with its ink veins as the user's layer: the other's induced veins against its
    ink veins (IoU, recall)."""
    import os

    from ..core.metrics import iou
    from .analysis import analyze

    leaves = [_sketch(os.path.join(folder, f"maple_sketch_leaf_{k}.png")) for k in (1, 2)]
    out = []
    for t in (0, 1):
        order = [leaves[t], leaves[1 - t]]
        a = analyze(order, 0, {"veins": _ink_veins(order[0])})
        m = a.layer("veins").masks[1]
        g = _ink_veins(np.asarray(a.exemplars[1], np.float32)) & a.blades[1]
        from ._measure_colours import outline_precision
        prec, taken = outline_precision(m, g, a.blades[1], outline=4.0, tol=2)
        out.append(dict(training=t + 1, exemplar=2 - t, iou=iou(m, g), recall=float((m & g).sum() / max(g.sum(), 1)),
                        induced=int(m.sum()), ink=int(g.sum()), outline_precision=prec, outline_taken=taken))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m branchnb.leaves._measure", description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=("registration", "induction", "snapping", "maples", "veinsystems",
                                           "sketches"))
    ap.add_argument("--no-snap", action="store_true", help="the paper's induction (no ridge snapping)")
    ap.add_argument("--kinds", default=None, help="comma-separated kinds (default: lobed, trilobed, elliptic; "
                    "veinsystems: and fan)")
    ap.add_argument("--seeds", type=int, default=None, help="number of seeds (0, 1, ...)")
    ap.add_argument("--sizes", default=None, help="comma-separated canvas sizes")
    ap.add_argument("--truth", action="store_true", help="induction through the true correspondences")
    ap.add_argument("--start", type=int, default=None, choices=(0, 1, 2),
                    help="maples: force the template fit's start (0 affine, 1 moments, 2 registration)")
    args = ap.parse_args(argv)
    kinds = tuple(args.kinds.split(",")) if args.kinds else (KINDS_PLAIN if args.what == "veinsystems" else KINDS_ALL)
    if args.what == "snapping":
        sizes = tuple(int(s) for s in (args.sizes or "192,384").split(","))
        rows = snapping_rows(kinds, sizes, range(args.seeds or 1), snap=not args.no_snap)
        print("vein IoU, every leaf as training leaf, true registration perturbed by 2 main-vein widths")
        for key in dict.fromkeys((r["kind"], r["size"]) for r in rows):
            v = np.array([r["iou"] for r in rows if (r["kind"], r["size"]) == key])
            shift = rows[[(r["kind"], r["size"]) for r in rows].index(key)]["shift"]
            print(f"{key[0]:<9} {key[1]:>4}  shift {shift:4.1f} px  min {v.min():.2f}  mean {v.mean():.2f}")
        return
    if args.what == "veinsystems":
        sizes = tuple(int(s) for s in (args.sizes or "256,320,512").split(","))
        rows = vein_system_rows(kinds, sizes, range(args.seeds or 2))
        print("ridge response in new leaves at the background's own true veins (4 px from the donor's): over the "
              "same pixels of the same leaf made on the background rendered without veins (rel, target <= 1), "
              "over plain blade (bg), at the donor's veins (donor)")
        for key in dict.fromkeys((r["kind"], r["size"]) for r in rows):
            rs = [r for r in rows if (r["kind"], r["size"]) == key]
            rel = np.array([r["bg_rel"] for r in rs])
            nr = np.array([r["n_bg"] for r in rs], float)
            okr = np.isfinite(rel) & (nr > 0)
            if okr.any():
                print(f"{key[0]:<9} {key[1]:>4}  rel " + " ".join(f"{x:.2f}" for x in rel)
                      + f"  pixel-weighted {np.average(rel[okr], weights=nr[okr]):.2f} max {np.nanmax(rel):.2f}"
                      + f"  (bg of the vein-free leaf {np.nanmean([r['bg_null'] for r in rs]):.2f})")
            orl = np.array([r["own_rel"] for r in rs])
            no = np.array([r["n_own"] for r in rs], float)
            oko = np.isfinite(orl) & (no > 0)
            if oko.any():
                print(f"{'':<9} {'':>4}  rel at 2 px from the donor's veins and layer, pixel-weighted "
                      f"{np.average(orl[oko], weights=no[oko]):.2f} max {np.nanmax(orl):.2f} ({int(no.sum())} px)")
            bgs = np.array([r["bg"] for r in rs])
            print(f"{key[0]:<9} {key[1]:>4}  bg " + " ".join(f"{x:.2f}" for x in bgs)
                  + f"  mean {np.nanmean(bgs):.2f} max {np.nanmax(bgs):.2f}"
                  + f"  donor mean {np.nanmean([r['donor_ratio'] for r in rs]):.2f}")
            nb = np.array([r["n_bg"] for r in rs], float)
            ok = np.isfinite(bgs) & (nb > 0)
            print(f"{'':<9} {'':>4}  pixels per leaf " + " ".join(str(int(x)) for x in nb)
                  + f"  pixel-weighted bg {np.average(bgs[ok], weights=nb[ok]):.2f}")
            bm = np.array([r["bg_matched"] for r in rs])
            print(f"{'':<9} {'':>4}  bg over plain blade as far from the donor's veins: "
                  + " ".join(f"{x:.2f}" for x in bm) + f"  mean {np.nanmean(bm):.2f} max {np.nanmax(bm):.2f}")
        return
    if args.what == "sketches":
        for r in sketch_rows():
            print(f"maple sketch {r['training']} -> {r['exemplar']}: vein IoU {r['iou']:.2f} recall {r['recall']:.2f} "
                  f"({r['induced']} px induced, {r['ink']} px of ink veins); outline band (6 px): precision "
                  f"{r['outline_precision']:.2f}, plain band taken {r['outline_taken']:.3f}")
        return
    if args.what == "maples":
        from . import snapping
        snapping._ONLY_START = args.start
        try:
            rows = maple_rows(snap=not args.no_snap)
        finally:
            snapping._ONLY_START = None
        for name in dict.fromkeys(r["training"] for r in rows):
            v = [r["iou"] for r in rows if r["training"] == name]
            scores = " ".join(f"{x:.2f}" for x in v)
            print(f"{name} as training: {scores}  min {min(v):.2f} mean {np.mean(v):.2f}")
        v = [r["iou"] for r in rows]
        print(f"all: min {min(v):.2f} mean {np.mean(v):.2f}")
        return
    if args.what == "registration":
        sizes = [int(s) for s in (args.sizes or "192").split(",")]
        for size in sizes:
            rows = registration_rows(kinds, range(args.seeds or 4), size=size)
            _print_registration(rows, size)
    else:
        sizes = tuple(int(s) for s in (args.sizes or "192,512").split(","))
        rows = induction_rows(kinds, sizes, range(args.seeds or 2), truth=args.truth)
        _print_induction(rows, args.truth)


if __name__ == "__main__":
    main()
