"""Per-seed structure figures for issue 23 (branching17): length per area, far share, straight runs,
turning angle, delta sea reach, CPU time. ``python -m branchnb.branching._structure_check KINDS SIZES N TAG``
(kinds of :mod:`._seed_check`, e.g. ``retina,delta 250,512,1000 2 after [CACHE]``; PNG sheets to /tmp,
or to TAG_kind_size.png when TAG is a path; fitted examples pickled in the folder CACHE when given)."""
import sys
import time

import numpy as np
from scipy import ndimage as ndi

from branchnb.branching import synthesize_structure
from branchnb.branching._seed_check import _sheet, fitted_example
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

def winding(s):
    """Largest net turn (degrees) along any piece of any branch (a spiral winds past 360)."""
    out = 0.0
    for b in s.branches:
        if len(b.points) > 2:
            c = np.cumsum(np.r_[0.0, b.angles()])
            out = max(out, float(np.degrees(np.ptp(c))))
    return out

def sea_bearings(s, dom, tol=6.0, back=30.0):
    """(circular spread in degrees, count) of the headings of the branches that reach the sea, over the
    last ``back`` px: a fan from one trunk spreads them, parallel channels do not."""
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    ang = []
    for b in s.branches:
        if len(b.points) < 3:
            continue
        x, y = np.clip(np.rint(b.points[-1]).astype(int), 0, [w - 1, h - 1])
        if d[y, x] > tol:
            continue
        seg = np.hypot(*np.diff(b.points, axis=0).T)
        back_len = np.cumsum(seg[::-1])
        i = len(b.points) - 2 - int(np.searchsorted(back_len, back))
        v = b.points[-1] - b.points[max(i, 0)]
        ang.append(np.arctan2(v[1], v[0]))
    if len(ang) < 2:
        return 0.0, len(ang)
    R = np.hypot(np.mean(np.cos(ang)), np.mean(np.sin(ang)))
    return float(np.degrees(np.sqrt(-2 * np.log(max(R, 1e-9))))), len(ang)

def sea_bearings_inland(s, dom, tol=6.0, inland=0.05, back=0.03):
    """(circular spread in degrees, count) of the headings of the branches that reach the sea, taken
    where each last crosses ``inland`` x the frame's diagonal from the sea (over the ``back`` x the
    diagonal before that point): the fan of the channels, not the turns of their mouths along the
    coast (an outer channel of the example bends parallel to the coast at its end)."""
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    diag = float(np.hypot(h, w))
    D, B = inland * diag, back * diag
    ang = []
    for b in s.branches:
        if len(b.points) < 3:
            continue
        p = np.asarray(b.points, np.float64)
        ix = np.clip(np.rint(p).astype(int), 0, [w - 1, h - 1])
        dv = d[ix[:, 1], ix[:, 0]]
        if dv[-1] > tol:
            continue
        far = np.flatnonzero(dv >= D)
        if not len(far):
            continue
        i = int(far[-1])
        seg = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p[: i + 1], axis=0).T))]
        j = int(np.searchsorted(seg, seg[-1] - B))
        if j >= i:
            continue
        v = p[i] - p[j]
        ang.append(np.arctan2(v[1], v[0]))
    if len(ang) < 2:
        return 0.0, len(ang)
    R = np.hypot(np.mean(np.cos(ang)), np.mean(np.sin(ang)))
    return float(np.degrees(np.sqrt(-2 * np.log(max(R, 1e-9))))), len(ang)


def run(kind, size, seeds, png=None, params=None, cache=None):
    img, dom, model = fitted_example(kind, size, cache)
    exs = model.example
    f_ex = far_share(exs, dom)
    a_ex, run_ex = straight_runs(exs)
    L_ex = exs.total_length
    sr_ex = sea_reach(exs, dom)
    bl_ex = seg_stats(exs)
    fan_ex = sea_bearings(exs, dom)
    fin_ex = sea_bearings_inland(exs, dom)
    print(f"{kind:9s} {size:4d} {img.shape[:2]} ex: L {L_ex:.0f} far {f_ex:.3f} run {run_ex:.1f} ang {a_ex:.1f} "
          f"sea {sr_ex:.2f} brlen {bl_ex:.0f} dom {dom.mean():.2f} wind {winding(exs):.0f} "
          f"fan {fan_ex[0]:.0f}/{fan_ex[1]} inland {fin_ex[0]:.0f}/{fin_ex[1]}", flush=True)
    rows = []
    for seed in seeds:
        t0 = time.process_time()
        r = synthesize_structure(model, params, rng=seed)
        t = time.process_time() - t0
        s = r.structure
        a, rn = straight_runs(s)
        row = dict(seed=seed, L=s.total_length / L_ex, far=far_share(s, dom) / max(f_ex, 1e-3),
                   run=rn / max(run_ex, 1e-6), ang=a / max(a_ex, 1e-6), sea=sea_reach(s, dom), cpu=t,
                   brlen=seg_stats(s) / max(bl_ex, 1e-6), stop=r.diagnostics.get("stop_reason"), struct=s)
        row["wind"] = winding(s)
        row["fan"] = sea_bearings(s, dom)
        row["fin"] = sea_bearings_inland(s, dom)
        rows.append(row)
        print(f"   seed {seed}: L x{row['L']:.2f} far x{row['far']:.2f} run x{row['run']:.2f} ang x{row['ang']:.2f} "
              f"brlen x{row['brlen']:.2f} sea {row['sea']:.2f} cpu {t:.1f}s wind {row['wind']:.0f} "
              f"fan {row['fan'][0]:.0f}/{row['fan'][1]} inland {row['fin'][0]:.0f}/{row['fin'][1]} "
              f"roots {sum(b.parent is None for b in s.branches)} "
              f"hd {r.diagnostics.get('hist_distance', {}).get('sum', 0):.4f} stop {row['stop']}", flush=True)
    if png:
        _sheet(img, dom, exs, rows[:3], png)
    return rows

if __name__ == "__main__":
    kinds = sys.argv[1].split(",")
    sizes = [int(v) for v in sys.argv[2].split(",")]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    tag = sys.argv[4] if len(sys.argv) > 4 else "base"
    cache = sys.argv[5] if len(sys.argv) > 5 else None
    prefix = tag if "/" in tag else f"/tmp/{tag}"
    for k in kinds:
        for sz in sizes:
            run(k, sz, range(n), png=f"{prefix}_{k}_{sz}.png", cache=cache)
