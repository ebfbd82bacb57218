"""Issue-23 figures on the two-country map and the leaf photo (``_border_vein_examples``).

``python -m branchnb.branching._border_vein_check KIND SIZE [SEEDS...]`` (KIND: ``two`` or ``leaf``) prints
the extraction's precision/recall against the true lines, the domain IoU, crop recall, then per seed the
structure's far share, root depth, turning angle, straight run, thick ends and roots, and the image's line
pieces, specks, coast and border drawn; PNGs (image | structure) go to /tmp/branching34/.
"""
# ruff: noqa: E501, E702, E401
import os
import sys
import time

import cv2
import numpy as np
from scipy import ndimage as ndi

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_image, synthesize_structure
from branchnb.branching._border_vein_examples import leaf_vein_example, two_country_map_example
from branchnb.branching._map_examples import line_scores
from branchnb.branching.measures import (
    _line_colour,
    boundary_drawn_share,
    far_share,
    line_contrast,
    line_pieces,
    relative_line_pieces,
    root_boundary_distance,
    straight_runs,
    thick_end_share,
)
from branchnb.core.render import coverage_polylines


def main(kind: str, sz: int, seeds) -> None:
    os.makedirs("/tmp/branching34", exist_ok=True)
    if kind == "two":
        img, truth, land, west, border = two_country_map_example((sz, sz), sz + 1)
    else:
        img, truth, land = leaf_vein_example((sz, sz), sz + 2); west = None
    t0 = time.perf_counter(); ex = extract_structure(img); te = time.perf_counter() - t0
    cov, _ = coverage_polylines(img.shape[:2], [b.points for b in truth.branches], [np.maximum(2 * b.thickness, 2.0) for b in truth.branches])
    P, R, _ = line_scores(ex, cov > 0.3)
    dom = example_domain(img, ex)
    iou = (dom & land).sum() / (dom | land).sum()
    model = fit_model(ex, domain=dom)
    f_ex = far_share(model.example, dom); a_ex, run_ex = straight_runs(ex); te_ex = thick_end_share(ex)
    lc, ground = _line_colour(img, ex, dom)
    print(f"{kind} {sz}: extract {te:.1f}s P {P:.3f} R {R:.3f}; domain IoU {iou:.3f}; ex far {f_ex:.3f} rootdepth "
          f"{np.median(root_boundary_distance(ex, dom)):.1f} angle {a_ex:.1f} run {run_ex:.1f} thick {te_ex:.3f} "
          f"roots {sum(b.parent is None for b in ex.branches)} (true {sum(b.parent is None for b in truth.branches)}); "
          f"ex boundary drawn {boundary_drawn_share(img, dom, lc, ground):.3f} contrast {line_contrast(img, ex):.3f}", flush=True)
    if west is not None:
        print(f"  example border drawn (west) {boundary_drawn_share(img, west, lc, ground):.3f}")
    # crop recall
    h = sz // 2; y0 = x0 = sz // 4
    from skimage.morphology import skeletonize
    ref = skeletonize(cov[y0:y0+h, x0:x0+h] > 0.3); ref[:6] = ref[-6:] = False; ref[:, :6] = ref[:, -6:] = False
    def rec(s, off):
        tr = np.zeros(ref.shape, bool)
        from branchnb.core.polyline import resample_uniform
        p = np.vstack([resample_uniform(b.points, 1.0, include_end=True) for b in s.branches]) - off
        ok = (p.min(1) > -0.5) & (p[:, 0] < h - .5) & (p[:, 1] < h - .5)
        tr[np.rint(p[ok, 1]).astype(int), np.rint(p[ok, 0]).astype(int)] = True
        return float(np.mean(ndi.distance_transform_edt(~tr)[ref] <= 4))
    crop = np.ascontiguousarray(img[y0:y0+h, x0:x0+h])
    print(f"  crop recall {rec(extract_structure(crop), (0, 0)):.3f} vs full {rec(ex, (x0, y0)):.3f}", flush=True)
    for seed in seeds:
        t0 = time.perf_counter(); res = synthesize_structure(model, rng=seed); ts = time.perf_counter() - t0
        s = res.structure; a, run = straight_runs(s)
        t0 = time.perf_counter(); out = synthesize_image(img, ex, res, rng=seed); ti = time.perf_counter() - t0
        lp = line_pieces(out.image, s, lc, ground); rlp = relative_line_pieces(img, ex, out.image, s)
        row = (f"  seed {seed}: struct {ts:.1f}s img {ti:.1f}s far {far_share(s, dom):.3f} ({far_share(s, dom)/max(f_ex,1e-3):.2f}x) "
               f"rootdepth {np.median(root_boundary_distance(s, dom)):.1f} angle {a:.1f} run {run:.1f} thick {thick_end_share(s):.3f} "
               f"roots {sum(b.parent is None for b in s.branches)}; pieces max {lp['max_pieces']} specks {lp['specks']} | rel max {rlp['max_pieces']} gaps {rlp['gaps']} specks {rlp['specks']}; contrast {line_contrast(out.image, s):.3f}")
        if out.labels is not None and res.domain is not None:
            lab = out.labels == np.bincount(out.labels[res.domain]).argmax()
            row += f"; region IoU {(lab & res.domain).sum() / max((lab | res.domain).sum(), 1):.3f}"
        if res.domain is not None:
            row += f"; boundary drawn {boundary_drawn_share(out.image, res.domain, lc, ground):.3f}"
            rd = res.domain
            # land in output: not sea-coloured
            if kind == "two":
                sea = np.linalg.norm(out.image[..., :3] - np.array([0.62, 0.80, 0.93]), axis=2) < 0.08
                landout = ~ndi.binary_opening(sea, iterations=2)
                row += f"; land IoU {(landout & rd).sum() / (landout | rd).sum():.3f}"
                wv = np.linalg.norm(out.image[..., :3] - np.array([0.93, 0.89, 0.76]), axis=2) < 0.06
                ev = np.linalg.norm(out.image[..., :3] - np.array([0.80, 0.90, 0.72]), axis=2) < 0.06
                row += f"; land colours W {wv[rd].mean():.2f} E {ev[rd].mean():.2f}; border drawn(W) {boundary_drawn_share(out.image, ndi.binary_opening(wv, iterations=3) & rd, lc, ground):.3f}"
        print(row, flush=True)
        o = (np.clip(out.image[..., :3], 0, 1) * 255).astype(np.uint8)[..., ::-1]
        sk = np.full_like(o, 255)
        for b in s.branches:
            cv2.polylines(sk, [np.round(b.points).astype(np.int32)], False, (0, 0, 0), 1)
        cv2.imwrite(f"/tmp/branching34/out_{kind}_{sz}_{seed}.png", np.hstack([o, sk]))


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), [int(a) for a in sys.argv[3:]] or [0, 1, 2])
