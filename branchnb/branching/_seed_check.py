"""Per-seed structure figures of the default workflow on six kinds at two sizes (issue 23).

``python -m branchnb.branching._seed_check [kinds] [n_seeds] [sizes]`` runs, for
each kind and size, ``extract_structure`` -> ``example_domain`` -> ``fit_model``
-> ``synthesize_structure`` on seeds 0 .. n_seeds - 1 with the defaults and
prints, per kind: the far share (:func:`.measures.far_share`, synthesized /
example; target <= 1.5 x on every seed), the mean straight-run length
(:func:`.measures.straight_runs`, synthesized / example), the median turning
angle, the thick-end share (:func:`.measures.thick_end_share`, synthesized
minus example; target <= + 0.05) and the CPU time per synthesis.

Kinds: retina (``retina_fundus``), lightning (``lightning_trace``), mud
(``cracked_mud``), czech (``czech_rivers_map``), at the sample's size x 0.5
and x 1 ("512" and "1000"); river (a procedural drawn country map, uniform
width lines and a coast, :func:`._map_examples.country_map_example`) and delta
(a procedural binary delta mask, :func:`._map_examples.delta_mask_example`) at
512 and 1000 px, also with its sea on the left (delta_side) and in a frame 1.5 x wider than high
(delta_wide); lineart (drawn cracks, thin dark lines on white,
:func:`._line_art_examples.crack_drawing_example`). The default workflow up
to the model is :func:`fitted_example` (also used by :mod:`._structure_check`).
"""

from __future__ import annotations

import sys
import time

import numpy as np

__all__ = ["KINDS", "example", "fitted_example", "seed_rows"]

KINDS = ("retina", "lightning", "mud", "river", "delta", "czech", "lineart", "delta_side", "delta_wide")

#: Root rule per kind for :func:`~branchnb.branching.extract_structure` (default otherwise).
ROOTS = {"lightning": "top"}


def example(kind: str, size: int) -> np.ndarray:
    """The example image of ``kind`` at about ``size`` px (512 or 1000)."""
    import cv2

    from .. import data
    from ._map_examples import country_map_example, delta_mask_example

    if kind == "river":
        return country_map_example((size, size), size + 7, layout=("island", "coast", "bay")[size % 3])[0]
    if kind == "delta":
        m, _ch, _sea = delta_mask_example((size, size), 3 + size)
        return np.dstack([m] * 3)
    if kind == "delta_side":   # the sea on the left
        m = np.rot90(delta_mask_example((size, size), 5 + size)[0], 1)[:, ::-1]
        return np.ascontiguousarray(np.dstack([m] * 3))
    if kind == "delta_wide":   # a frame 1.5 x wider than high
        m, _ch, _sea = delta_mask_example((size, size * 3 // 2), 7 + size)
        return np.dstack([m] * 3)
    if kind == "lineart":
        from ._line_art_examples import crack_drawing_example

        img = crack_drawing_example(size, 11 + size, cells=max(8, size // 20), width=max(2, size // 250))
        return np.dstack([img] * 3) if img.ndim == 2 else img[..., :3]
    name = {"retina": "retina_fundus", "lightning": "lightning_trace", "mud": "cracked_mud",
            "czech": "czech_rivers_map"}[kind]
    img = np.asarray(data.load(name), np.float32)
    if img.shape[-1] == 4:
        img = img[..., :3] * img[..., 3:] + (1 - img[..., 3:])
    if size < 900:
        f = 0.5 if size >= 400 else 0.25
        img = cv2.resize(img, (round(img.shape[1] * f), round(img.shape[0] * f)), interpolation=cv2.INTER_AREA)
    return np.clip(img, 0, 1).astype(np.float32)


def fitted_example(kind: str, size: int, cache: str | None = None):
    """The default workflow up to the model: ``(image, domain, model)`` of ``kind`` at ``size`` px.

    ``extract_structure`` (root rule :data:`ROOTS`) -> ``example_domain`` ->
    ``fit_model``, shared by this module and :mod:`._structure_check`.
    ``cache``: a folder where the result is pickled and read again (the
    1000 px extractions take most of a check's time).
    """
    from . import example_domain, extract_structure, fit_model
    from ._check_table import cached

    def make():
        img = example(kind, size)
        root = ROOTS.get(kind)
        ex = extract_structure(img, root=root) if root else extract_structure(img)
        dom = example_domain(img, ex)
        return img, dom, fit_model(ex, domain=dom)

    return cached(cache, f"{kind}_{size}.pkl", make)


def seed_rows(kind: str, size: int, seeds=range(10), params=None, out_png: str | None = None):
    """Figures per seed (dicts) and the example's, for one kind and size."""
    from . import synthesize_structure
    from .measures import far_share, straight_runs, thick_end_share

    img, dom, model = fitted_example(kind, size)
    exs = model.example
    f_ex = far_share(exs, dom)
    a_ex, run_ex = straight_runs(exs)
    te_ex = thick_end_share(exs)
    head = dict(far=f_ex, angle=a_ex, run=run_ex, thick=te_ex, shape=img.shape[:2])
    rows = []
    for seed in seeds:
        t0 = time.process_time()
        r = synthesize_structure(model, params, rng=seed)
        t = time.process_time() - t0
        s = r.structure
        a, run = straight_runs(s)
        rows.append(dict(seed=seed, far=far_share(s, dom) / max(f_ex, 1e-3), angle=a,
                         run=run / max(run_ex, 1e-6), thick=thick_end_share(s) - te_ex, cpu=t,
                         stop=r.diagnostics.get("stop_reason"), struct=s))
    if out_png:
        _sheet(img, dom, exs, rows[:4], out_png)
    return head, rows


def _sheet(img, dom, ex, rows, path):
    """Example and up to 4 seeds side by side (branches drawn black on white, domain grey)."""
    from ..core.io import imsave
    from ..core.render import coverage_polylines

    def draw(s):
        cov, _ = coverage_polylines(dom.shape, [b.points for b in s.branches],
                                    [np.maximum(b.thickness, 0.7) for b in s.branches])
        base = np.where(dom, 1.0, 0.8).astype(np.float32)
        return np.clip(base * (1 - cov), 0, 1)

    tiles = [np.asarray(img, np.float32)[..., :3], np.dstack([draw(ex)] * 3)]
    tiles += [np.dstack([draw(r["struct"])] * 3) for r in rows]
    sep = np.ones((dom.shape[0], 4, 3), np.float32) * 0.5
    out = np.concatenate(sum([[t, sep] for t in tiles], [])[:-1], axis=1)
    imsave(path, out)


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    kinds = argv[0].split(",") if argv and argv[0] != "all" else KINDS
    n = int(argv[1]) if len(argv) > 1 else 10
    sizes = [int(v) for v in argv[2].split(",")] if len(argv) > 2 else [512, 1000]
    png = argv[3] if len(argv) > 3 else None
    for kind in kinds:
        for size in sizes:
            head, rows = seed_rows(kind, size, range(n), out_png=f"{png}_{kind}_{size}.png" if png else None)
            far = np.array([r["far"] for r in rows])
            run = np.array([r["run"] for r in rows])
            th = np.array([r["thick"] for r in rows])
            cpu = np.array([r["cpu"] for r in rows])
            print(f"{kind:9s} {size:4d} {head['shape']}: ex far {head['far']:.3f} run {head['run']:.1f} px "
                  f"angle {head['angle']:.1f} thick {head['thick']:.3f}", flush=True)
            fabs = far.max() * max(head["far"], 1e-3)
            print("   far x  " + " ".join(f"{v:.2f}" for v in far) + f"  max {far.max():.2f} (abs {fabs:.3f})",
                  flush=True)
            print("   run x  " + " ".join(f"{v:.2f}" for v in run) + f"  min {run.min():.2f}", flush=True)
            print("   angle  " + " ".join(f"{r['angle']:.1f}" for r in rows), flush=True)
            print("   thick+ " + " ".join(f"{v:+.2f}" for v in th) + f"  max {th.max():+.2f}", flush=True)
            print(f"   cpu s  max {cpu.max():.2f} median {np.median(cpu):.2f}   stops "
                  + ",".join(sorted({str(r['stop'])[:14] for r in rows})), flush=True)


if __name__ == "__main__":
    main()
