"""Per-seed structure figures for issue 23 (branching17): length per area, far share, straight runs,
turning angle, delta sea reach, CPU time. ``python -m branchnb.branching._structure_check KINDS SIZES N TAG``
(kinds of :mod:`._seed_check`, e.g. ``retina,delta 250,512,1000 2 after``; PNG sheets to /tmp)."""
import sys
import time

import numpy as np
from scipy import ndimage as ndi

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._seed_check import _sheet, example
from branchnb.branching.measures import far_share, straight_runs


def seg_stats(s, h=4.0):
    L = []
    for b in s.branches:
        if len(b.points) > 2:
            L.append(b.length)
    return float(np.median(L)) if L else 0.0

def sea_reach(s, dom, tol=6.0):
    """share of leaf branches (no children) whose last vertex lies within tol px of outside-domain."""
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    has_child = {b.parent for b in s.branches if b.parent is not None}
    ends = []
    for i, b in enumerate(s.branches):
        if i in has_child or len(b.points) < 2:
            continue
        x, y = np.clip(np.rint(b.points[-1]).astype(int), 0, [w - 1, h - 1])
        ends.append(d[y, x] <= tol)
    return float(np.mean(ends)) if ends else 0.0

def run(kind, size, seeds, png=None):
    img = example(kind, size)
    root = {"lightning": "top"}.get(kind)
    ex = extract_structure(img, root=root) if root else extract_structure(img)
    dom = example_domain(img, ex)
    model = fit_model(ex, domain=dom)
    exs = model.example
    f_ex = far_share(exs, dom)
    a_ex, run_ex = straight_runs(exs)
    L_ex = exs.total_length
    sr_ex = sea_reach(exs, dom)
    bl_ex = seg_stats(exs)
    print(f"{kind:9s} {size:4d} {img.shape[:2]} ex: L {L_ex:.0f} far {f_ex:.3f} run {run_ex:.1f} ang {a_ex:.1f} "
          f"sea {sr_ex:.2f} brlen {bl_ex:.0f} dom {dom.mean():.2f}", flush=True)
    rows = []
    for seed in seeds:
        t0 = time.process_time()
        r = synthesize_structure(model, rng=seed)
        t = time.process_time() - t0
        s = r.structure
        a, rn = straight_runs(s)
        row = dict(seed=seed, L=s.total_length / L_ex, far=far_share(s, dom) / max(f_ex, 1e-3),
                   run=rn / max(run_ex, 1e-6), ang=a / max(a_ex, 1e-6), sea=sea_reach(s, dom), cpu=t,
                   brlen=seg_stats(s) / max(bl_ex, 1e-6), stop=r.diagnostics.get("stop_reason"), struct=s)
        rows.append(row)
        print(f"   seed {seed}: L x{row['L']:.2f} far x{row['far']:.2f} run x{row['run']:.2f} ang x{row['ang']:.2f} "
              f"brlen x{row['brlen']:.2f} sea {row['sea']:.2f} cpu {t:.1f}s "
              f"hd {r.diagnostics.get('hist_distance', {}).get('sum', 0):.4f} stop {row['stop']}", flush=True)
    if png:
        _sheet(img, dom, exs, rows[:3], png)
    return rows

if __name__ == "__main__":
    kinds = sys.argv[1].split(",")
    sizes = [int(v) for v in sys.argv[2].split(",")]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    tag = sys.argv[4] if len(sys.argv) > 4 else "base"
    for k in kinds:
        for sz in sizes:
            run(k, sz, range(n), png=f"/tmp/{tag}_{k}_{sz}.png")
