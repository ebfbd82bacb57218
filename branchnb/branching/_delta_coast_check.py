"""Per-seed figures of deltas and coast maps for issue 23 (branching29).

``python -m branchnb.branching._delta_coast_check KINDS SIZES N OUT [CACHE]`` (kinds of :mod:`._seed_check`,
e.g. ``delta,river 250,512,1000 5 /tmp/out /tmp/cache``) prints, per kind, size and seed: total length and far
share (:func:`.measures.far_share`) over the example's, the share of the length within 2 % of the frame's diagonal
of the domain's edge (the coast; output / example), the share within 5 % of it that runs along it (chord within
60 degrees of parallel), the length-weighted median radius of all branches and of the non-root ones (output /
example), the thick-end share (:func:`.measures.thick_end_share`), the spread of the sea-reaching channels'
headings 5 % of the diagonal inland (:func:`._structure_check.sea_bearings_inland`), the largest winding, the
number of roots and crossings and the CPU time. Sheets (example and seeds 0-2) go to ``OUT_kind_size.png``.
"""

from __future__ import annotations

import sys
import time

import numpy as np
from scipy import ndimage as ndi

from ..core.polyline import segments_intersect
from ..core.structure import Structure
from ._seed_check import _sheet, fitted_example
from ._structure_check import sea_bearings_inland, winding
from .measures import far_share, thick_end_share


def median_radius(s: Structure, children: bool = False) -> float:
    """Length-weighted median radius (of the non-root branches when ``children``); nan when none."""
    r, w = [], []
    for b in s.branches:
        if children and b.parent is None:
            continue
        p = np.asarray(b.points, float)
        if len(p) < 2:
            continue
        t = np.asarray(b.thickness, float)
        r.append(0.5 * (t[1:] + t[:-1]))
        w.append(np.hypot(*np.diff(p, axis=0).T))
    if not r:
        return float("nan")
    r, w = np.concatenate(r), np.concatenate(w)
    o = np.argsort(r)
    c = np.cumsum(w[o])
    return float(r[o][np.searchsorted(c, c[-1] / 2)])


def coast_shares(s: Structure, dom: np.ndarray, near: float = 0.02, band: float = 0.05) -> tuple[float, float]:
    """(share of the length within ``near`` x the diagonal of the domain's edge, share within ``band`` x
    the diagonal that runs along the edge)."""
    depth = ndi.distance_transform_edt(dom)
    gy, gx = np.gradient(ndi.gaussian_filter(depth, 4.0))
    n = np.hypot(gx, gy) + 1e-12
    h, w = dom.shape
    diag = float(np.hypot(h, w))
    tot = close = along = 0.0
    for b in s.branches:
        p = np.asarray(b.points, float)
        if len(p) < 2:
            continue
        v = np.diff(p, axis=0)
        seg = np.hypot(*v.T)
        ix = np.clip(np.rint(0.5 * (p[1:] + p[:-1])).astype(int), 0, [w - 1, h - 1])
        d = depth[ix[:, 1], ix[:, 0]]
        c = np.abs(v[:, 0] * gx[ix[:, 1], ix[:, 0]] + v[:, 1] * gy[ix[:, 1], ix[:, 0]]) / n[ix[:, 1], ix[:, 0]]
        c = c / np.maximum(seg, 1e-9)
        tot += seg.sum()
        close += seg[d <= near * diag].sum()
        along += seg[(d <= band * diag) & (c < 0.5)].sum()
    return close / max(tot, 1e-9), along / max(tot, 1e-9)


def crossings(s: Structure) -> int:
    p0, p1, _ = s.segments()
    return int(np.triu(segments_intersect(p0, p1, p0, p1), 1).sum()) if len(p0) <= 6000 else -1


def figures(s: Structure, dom: np.ndarray) -> dict:
    close, along = coast_shares(s, dom)
    fan, n_fan = sea_bearings_inland(s, dom)
    return dict(L=s.total_length, far=far_share(s, dom), coast=close, along=along, rad=median_radius(s),
                radc=median_radius(s, True), thick=thick_end_share(s), fan=fan, n_fan=n_fan, wind=winding(s),
                roots=int(sum(b.parent is None for b in s.branches)), cross=crossings(s))


def run(kind: str, size: int, seeds, out: str, cache: str | None = None) -> list[dict]:
    from . import synthesize_structure

    img, dom, model = fitted_example(kind, size, cache)
    ex = figures(model.example, dom)
    print(f"{kind} {size} example: " + " ".join(f"{k} {v:.3g}" for k, v in ex.items()), flush=True)
    rows = []
    for seed in seeds:
        t0 = time.process_time()
        s = synthesize_structure(model, rng=seed).structure
        f = figures(s, dom)
        f["cpu"], f["struct"] = time.process_time() - t0, s
        rows.append(f)
        print(f"  seed {seed}: L x{f['L'] / ex['L']:.2f} far x{f['far'] / max(ex['far'], 1e-3):.2f} "
              f"coast {f['coast']:.3f} (ex {ex['coast']:.3f}) along {f['along']:.3f} (ex {ex['along']:.3f}) "
              f"radius x{f['rad'] / ex['rad']:.2f} channels x{f['radc'] / ex['radc']:.2f} "
              f"thick {f['thick']:.3f} (ex {ex['thick']:.3f}) fan {f['fan']:.0f}/{f['n_fan']} (ex {ex['fan']:.0f}) "
              f"wind {f['wind']:.0f} roots {f['roots']} crossings {f['cross']} cpu {f['cpu']:.1f}s", flush=True)
    _sheet(img, dom, model.example, rows[:3], f"{out}_{kind}_{size}.png")
    return rows


if __name__ == "__main__":
    kinds = sys.argv[1].split(",")
    sizes = [int(v) for v in sys.argv[2].split(",")]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    out = sys.argv[4] if len(sys.argv) > 4 else "/tmp/delta_coast"
    cache = sys.argv[5] if len(sys.argv) > 5 else None
    for k in kinds:
        for sz in sizes:
            run(k, sz, range(n), out, cache)
