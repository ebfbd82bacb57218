"""Radius figures of synthesized structures against their examples (issue 23, branching39).

``python -m branchnb.branching._radius_check [KINDS] [N_SEEDS]`` prints, per kind and seed, the
length-weighted 90th-percentile radius of the synthesized structure over the example's, and the
thick-end share (:func:`.measures.thick_end_share`) against the example's. Kinds: ``noaa`` (the NOAA
storm photo at 512 px), ``retina`` and ``river`` (:func:`._seed_check.fitted_example` at 512 px) and
procedural storms ``storm{1,2,3}{thick,thin}`` (:func:`._storm_examples.storm_example` with 1-3
bolts; ``thin``: a sharp core and a narrow glow). Default: all.
"""

from __future__ import annotations

import sys
import time

import numpy as np

STORMS = [f"storm{n}{w}" for n in (1, 2, 3) for w in ("thick", "thin")]
KINDS = ["noaa", "retina", "river", *STORMS]


def weighted_quantile(s, q: float) -> float:
    """Length-weighted ``q`` quantile of the segment radii of structure ``s``."""
    r, w = [], []
    for b in s.branches:
        p = np.asarray(b.points, float)
        if len(p) > 1:
            t = np.asarray(b.thickness, float)
            r.append(0.5 * (t[1:] + t[:-1]))
            w.append(np.hypot(*np.diff(p, axis=0).T))
    r, w = np.concatenate(r), np.concatenate(w)
    o = np.argsort(r)
    return float(r[o][min(np.searchsorted(np.cumsum(w[o]) / w.sum(), q), len(r) - 1)])


def storm_image(kind: str, seed: int = 0) -> np.ndarray:
    """The procedural storm ``storm{n}{thick|thin}``."""
    from ._storm_examples import storm_example

    n, w = int(kind[5]), kind[6:]
    return storm_example(seed=seed, n_bolts=n, **({} if w == "thick" else {"core": 0.35, "glow": 1.5}))[0]


def fitted(kind: str, cache: str | None = None):
    """``(image, domain, model)`` of ``kind`` (the default workflow)."""
    from . import example_domain, extract_structure, fit_model
    from ._check_table import cached
    from ._seed_check import fitted_example

    if kind in ("retina", "river"):
        return fitted_example(kind, 512, cache)

    def make():
        if kind == "noaa":
            import cv2

            bgr = cv2.imread("/work/shared/data/photos/branching/lightning_noaa.jpg", cv2.IMREAD_COLOR)
            s = 512 / max(bgr.shape[:2])
            bgr = cv2.resize(bgr, None, fx=s, fy=s, interpolation=cv2.INTER_AREA)
            img = cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB).astype(np.float32) / 255
        else:
            img = storm_image(kind)
        ex = extract_structure(img)
        dom = example_domain(img, ex)
        return img, dom, fit_model(ex, domain=dom)

    return cached(cache, f"{kind}.pkl", make)


def run(kind: str, seeds, cache: str | None = None, png: str | None = None) -> list[float]:
    from . import synthesize_structure
    from .measures import thick_end_share

    img, dom, model = fitted(kind, cache)
    q_ex, te_ex = weighted_quantile(model.example, 0.9), thick_end_share(model.example)
    rows, structs = [], []
    for seed in seeds:
        t0 = time.process_time()
        s = synthesize_structure(model, rng=seed).structure
        structs.append(s)
        rows.append(weighted_quantile(s, 0.9))
        print(f"  {kind} seed {seed}: q90 {rows[-1]:.2f} (x{rows[-1] / q_ex:.2f}) thick-end "
              f"{thick_end_share(s):.3f} (ex {te_ex:.3f}) cpu {time.process_time() - t0:.1f}s", flush=True)
    print(f"{kind}: example q90 {q_ex:.2f}, output {min(rows):.2f}-{max(rows):.2f} "
          f"(x{min(rows) / q_ex:.2f}-{max(rows) / q_ex:.2f})", flush=True)
    if png:
        from ._seed_check import _sheet

        _sheet(img, dom, model.example, [{"struct": s} for s in structs[:3]], f"{png}_{kind}.png")
    return rows


if __name__ == "__main__":
    kinds = sys.argv[1].split(",") if len(sys.argv) > 1 and sys.argv[1] != "all" else KINDS
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    cache = sys.argv[3] if len(sys.argv) > 3 else None
    png = sys.argv[4] if len(sys.argv) > 4 else None
    for k in kinds:
        run(k, range(n), cache, png)
