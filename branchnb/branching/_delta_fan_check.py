"""Delta figures over orientations, sizes and seeds for issue 23 (branching47).

``python -m branchnb.branching._delta_fan_check SIDES SIZES N [OUT] [CACHE] [MASKS] [KINDS]`` (e.g.
``bottom,top,left,right 320,512,1000 3 /tmp/b47/after /tmp/b47/cache -,4``; MASKS the mask seeds, ``-`` for
``3 + size``; KINDS ``delta`` (default) and/or kinds of :data:`._delta_examples.FAN_KINDS`, deltas whose trunk
runs at a known bearing off the way down, e.g. ``delta,fan0,fan30,fanm40,fan55``) fits the default workflow
(``extract_structure`` -> ``example_domain`` -> ``fit_model``) on the procedural delta mask
(:func:`._map_examples.delta_mask_example` or :func:`._delta_examples.delta_fan_mask`) turned so its sea lies
on side SIDE, synthesizes seeds 0 .. N - 1 and prints per seed: the fan spread
(:func:`._structure_check.sea_bearings_inland`, degrees), the trunk bearing's error against the example's
(:func:`trunk_bearing`, degrees), the chord deviation (:func:`chord_deviation`), the frame share
(:func:`frame_share`), the trunks' share along the coast
(:func:`coast_share`), crossings, the far share over the example's, the share of branches ending > 2 x thicker
than they start (:func:`.measures.thick_end_share`), the channels reaching the sea, the length-weighted
median radius over the example's, the trunk's sinuosity (:func:`trunk_sinuosity`) and the mouth share
(:func:`mouth_share`); the example's own figures first (with the generator's true bearing for the
FAN_KINDS), a summary line (medians, worst) per case last. Sheets of the example and seeds 0-2 go to
``OUT_kind_side_size_mask.png``.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage as ndi

from ._check_table import cached
from ._delta_coast_check import crossings, median_radius
from ._delta_examples import FAN_KINDS, MEANDER_KINDS, delta_fan_mask
from ._map_examples import delta_mask_example
from ._seed_check import _sheet
from ._structure_check import sea_bearings_inland
from .measures import far_share, thick_end_share


def turned(mask: np.ndarray, side: str) -> np.ndarray:
    """``mask`` (its sea at the bottom) turned so the sea lies on ``side``."""
    out = {"bottom": mask, "top": mask[::-1], "left": mask.T[:, ::-1], "right": mask.T}[side]
    return np.ascontiguousarray(out)


def chord_deviation(s, dom: np.ndarray) -> float:
    """Median over the non-root channels that reach the sea (chord >= 10 % of the diagonal) of their
    largest distance from their chord, as a share of its length (a ruler-straight channel: 0)."""
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    out = []
    for b in s.branches:
        p = np.asarray(b.points, float)
        if b.parent is None or len(p) < 3:
            continue
        ix = np.clip(np.rint(p[-1]).astype(int), 0, [w - 1, h - 1])
        c = p[-1] - p[0]
        L = float(np.hypot(*c))
        if d[ix[1], ix[0]] > 6.0 or L < 0.1 * np.hypot(h, w):
            continue
        out.append(np.abs((p[:, 0] - p[0, 0]) * c[1] - (p[:, 1] - p[0, 1]) * c[0]).max() / L ** 2)
    return float(np.median(out)) if out else 0.0


def frame_share(s, shape, sea_side: str, skip: float = 12.0, margin: float = 8.0) -> float:
    """Share of the branches' length within ``margin`` px of a frame side that is not the sea's (a root's
    first ``skip`` px, where it enters through the frame, not counted); as in test_branching_drawn_maps."""
    h, w = shape
    near = total = 0.0
    for b in s.branches:
        p = np.asarray(b.points, float)
        if len(p) < 2:
            continue
        seg = np.hypot(*np.diff(p, axis=0).T)
        mid = 0.5 * (p[1:] + p[:-1])
        dd = {"top": mid[:, 1], "bottom": h - 1 - mid[:, 1], "left": mid[:, 0], "right": w - 1 - mid[:, 0]}
        fd = np.min([v for k, v in dd.items() if k != sea_side], axis=0)
        keep = np.cumsum(seg) > skip if b.parent is None else np.ones(len(seg), bool)
        near += seg[keep & (fd < margin)].sum()
        total += seg.sum()
    return near / max(total, 1e-9)


def trunk_bearing(s, dom: np.ndarray, tol: float = 6.0) -> float:
    """Bearing (degrees, image x/y) from the start of the longest root to the mean of the ends of the
    branches that reach the sea (within ``tol`` px of it): where the delta runs from its trunk; nan when
    none reaches the sea."""
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    roots = [b for b in s.branches if b.parent is None and len(b.points) >= 2]
    if not roots:
        return float("nan")
    root = max(roots, key=lambda b: float(np.hypot(*np.diff(np.asarray(b.points, float), axis=0).T).sum()))
    ends = []
    for b in s.branches:
        if len(b.points) >= 2:
            x, y = np.clip(np.rint(b.points[-1]).astype(int), 0, [w - 1, h - 1])
            if d[y, x] <= tol:
                ends.append(b.points[-1])
    if not ends:
        return float("nan")
    v = np.mean(np.asarray(ends, float), 0) - np.asarray(root.points[0], float)
    return float(np.degrees(np.arctan2(v[1], v[0])))


def coast_share(s, dom: np.ndarray, near: float = 0.015) -> float:
    """Share of the trunks' (roots') length within ``near`` x the frame's diagonal (at least 4 px) of the sea,
    over the part that is not the mouth's straight approach: the last ``near`` x the diagonal / sin(30 deg)
    of a root's length (a trunk meeting the coast 30 degrees or more off it) not counted. 0 when none runs
    along the coast."""
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    r = max(4.0, near * float(np.hypot(h, w)))
    along = total = 0.0
    for b in s.branches:
        p = np.asarray(b.points, float)
        if b.parent is not None or len(p) < 2:
            continue
        seg = np.hypot(*np.diff(p, axis=0).T)
        mid = 0.5 * (p[1:] + p[:-1])
        ix = np.clip(np.rint(mid).astype(int), 0, [w - 1, h - 1])
        left = seg.sum() - np.cumsum(seg)
        along += seg[(d[ix[:, 1], ix[:, 0]] <= r) & (left > 2.0 * r)].sum()
        total += seg.sum()
    return along / max(total, 1e-9)


def side_share(s, dom: np.ndarray) -> float:
    """The smaller share of the channels' length below the delta's head on one side of the trunk line.

    The head is where the longest root's first child whose subtree reaches the sea (within
    :data:`.delta_fan.SEA_SHARE` x the deepest depth) leaves it; the trunk line runs from the root's start
    through the head. 0.5: as much channel length on either side; 0: a lopsided fan. NaN without a head."""
    from .delta_fan import SEA_SHARE

    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    br = s.branches
    roots = [i for i, b in enumerate(br) if b.parent is None and len(b.points) >= 2]
    if not roots:
        return float("nan")
    r = max(roots, key=lambda i: float(np.hypot(*np.diff(np.asarray(br[i].points, float), axis=0).T).sum()))
    deep = float(d.max())

    def wet(i):
        x, y = np.clip(np.rint(br[i].points[-1]).astype(int), 0, [w - 1, h - 1])
        return d[y, x] < SEA_SHARE * deep

    kids = {}
    for i, b in enumerate(br):
        if b.parent is not None:
            kids.setdefault(int(b.parent), []).append(i)

    def reaches(i):
        todo = [i]
        while todo:
            j = todo.pop()
            if wet(j):
                return True
            todo.extend(kids.get(j, []))
        return False

    verts = [br[c].parent_vertex for c in kids.get(r, []) if br[c].parent_vertex is not None and reaches(c)]
    if not verts:
        return float("nan")
    p = np.asarray(br[r].points, float)
    head = p[min(int(min(verts)), len(p) - 1)]
    u = head - p[0]
    u = u / max(float(np.hypot(*u)), 1e-9)
    ix = np.clip(np.rint(head).astype(int), 0, [w - 1, h - 1])
    d_head = d[ix[1], ix[0]]
    side = np.zeros(2)
    for b in br:
        q = np.asarray(b.points, float)
        if len(q) < 2:
            continue
        mid = 0.5 * (q[1:] + q[:-1])
        seg = np.hypot(*np.diff(q, axis=0).T)
        im = np.clip(np.rint(mid).astype(int), 0, [w - 1, h - 1])
        below = d[im[:, 1], im[:, 0]] < d_head
        cr = (mid[:, 0] - head[0]) * u[1] - (mid[:, 1] - head[1]) * u[0]
        side[0] += seg[below & (cr > 0)].sum()
        side[1] += seg[below & (cr < 0)].sum()
    return float(side.min() / max(side.sum(), 1e-9))


def mouth_share(s, dom: np.ndarray, tol: float = 6.0) -> float:
    """The smaller share of the delta's mouths on one side of its trunk line (issue 23, branching79).

    The mouths are the last vertices of the branches that start inland (over 10 % of the deepest depth
    from the sea) and end within ``tol`` px of it, the trunk's included; the trunk line runs from the
    longest root's start through its first vertex that a child leaves (the delta's head). 0.5: as many
    mouths on either side; 0: all on one. NaN without a child of the trunk."""
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    br = s.branches
    roots = [i for i, b in enumerate(br) if b.parent is None and len(b.points) >= 2]
    if not roots:
        return float("nan")
    r = max(roots, key=lambda i: float(np.hypot(*np.diff(np.asarray(br[i].points, float), axis=0).T).sum()))
    kids = [b.parent_vertex for b in br if b.parent == r and b.parent_vertex is not None]
    if not kids:
        return float("nan")

    def at(q):
        x, y = np.clip(np.rint(q).astype(int), 0, [w - 1, h - 1])
        return float(d[y, x])

    p = np.asarray(br[r].points, float)
    head = p[min(int(min(kids)), len(p) - 1)]
    u = head - p[0]
    deep = float(d.max())
    cnt = np.zeros(2)
    for b in br:
        q = np.asarray(b.points, float)
        if len(q) < 2 or at(q[-1]) > tol or at(q[0]) < 0.1 * deep:
            continue
        e = q[-1] - head
        cnt[int(u[0] * e[1] - u[1] * e[0] < 0)] += 1
    return float(cnt.min() / max(cnt.sum(), 1.0))


def trunk_sinuosity(s, dom: np.ndarray, share: float = 0.5) -> float:
    """Path length over chord of the longest root's upper part, from its start down to where its depth
    (distance to the sea) is ``share`` x its start's: how much the trunk meanders (1: straight); nan
    without a root."""
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    roots = [np.asarray(b.points, float) for b in s.branches if b.parent is None and len(b.points) >= 3]
    if not roots:
        return float("nan")
    p = max(roots, key=lambda q: float(np.hypot(*np.diff(q, axis=0).T).sum()))
    ix = np.clip(np.rint(p).astype(int), 0, [w - 1, h - 1])
    dep = d[ix[:, 1], ix[:, 0]]
    below = np.flatnonzero(dep <= share * dep[0])
    p = p[: (int(below[0]) + 1 if below.size else len(p))]
    if len(p) < 3:
        return 1.0
    chord = float(np.hypot(*(p[-1] - p[0])))
    return float(np.hypot(*np.diff(p, axis=0).T).sum()) / max(chord, 1e-9)


def bearing_error(a: float, b: float) -> float:
    """Absolute difference of two bearings in degrees (0-180)."""
    return float(abs((a - b + 180.0) % 360.0 - 180.0))


def n_to_sea(s, dom: np.ndarray, tol: float = 6.0) -> int:
    """Number of branches whose last vertex lies within ``tol`` px of the sea."""
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    n = 0
    for b in s.branches:
        if len(b.points) >= 2:
            x, y = np.clip(np.rint(b.points[-1]).astype(int), 0, [w - 1, h - 1])
            n += int(d[y, x] <= tol)
    return n


def _kind_args(kind: str) -> tuple[tuple, dict]:
    """``(args, kwargs)`` of :func:`._delta_examples.delta_fan_mask` after its shape and seed for a
    :data:`._delta_examples.FAN_KINDS` or :data:`._delta_examples.MEANDER_KINDS` name."""
    if kind in MEANDER_KINDS:
        t, c, f, n, a = MEANDER_KINDS[kind]
        return (t, c, f, n), {"meander": a}
    if kind in FAN_KINDS:
        return tuple(FAN_KINDS[kind]), {}
    raise ValueError(f"kind: 'delta' or one of {sorted(FAN_KINDS) + sorted(MEANDER_KINDS)}, not {kind!r}")


def mask_of(kind: str, size: int, mask_seed: int) -> np.ndarray:
    """The delta mask (sea at the bottom) of ``kind``: ``delta`` or a :data:`._delta_examples.FAN_KINDS` name."""
    if kind == "delta":
        return delta_mask_example((size, size), mask_seed)[0]
    args, kw = _kind_args(kind)
    return delta_fan_mask((size, size), mask_seed, *args, **kw)[0]


def true_bearing(kind: str, side: str, size: int, mask_seed: int) -> float:
    """The generator's trunk bearing (degrees, from the trunk's entry to the mouths' mean) after turning."""
    if kind == "delta":
        return float("nan")
    args, kw = _kind_args(kind)
    _m, _ch, _sea, entry, mouths = delta_fan_mask((size, size), mask_seed, *args, **kw)
    v = mouths.mean(0) - entry
    # turned() as a map of directions (x, y) -> (x', y')
    v = {"bottom": v, "top": (v[0], -v[1]), "left": (-v[1], v[0]), "right": (v[1], v[0])}[side]
    return float(np.degrees(np.arctan2(v[1], v[0])))


def fitted(side: str, size: int, cache: str | None = None, mask_seed: int | None = None, kind: str = "delta"):
    """(image, domain, model) of the delta ``kind`` (mask seed ``mask_seed``, ``3 + size`` when None) with
    its sea on ``side`` at ``size`` px (default workflow)."""
    from . import example_domain, extract_structure, fit_model

    mask_seed = 3 + size if mask_seed is None else int(mask_seed)
    name = "delta" if kind == "delta" else f"delta_{kind}"

    def make():
        img = np.dstack([turned(mask_of(kind, size, mask_seed), side)] * 3)
        ex = extract_structure(img)
        dom = example_domain(img, ex)
        return img, dom, fit_model(ex, domain=dom)

    return cached(cache, f"{name}_{side}_{size}_{mask_seed}.pkl", make)


def figures(s, dom, side) -> dict:
    return dict(fan=sea_bearings_inland(s, dom)[0], bear=trunk_bearing(s, dom), dev=chord_deviation(s, dom),
                frame=frame_share(s, dom.shape, side), cross=crossings(s), far=far_share(s, dom),
                thick=thick_end_share(s), sea=n_to_sea(s, dom), rad=median_radius(s), coast=coast_share(s, dom),
                side=side_share(s, dom), sin=trunk_sinuosity(s, dom), mouth=mouth_share(s, dom))


def run(side: str, size: int, seeds, out: str | None = None, cache: str | None = None,
        mask_seed: int | None = None, kind: str = "delta") -> list[dict]:
    from . import synthesize_structure

    img, dom, model = fitted(side, size, cache, mask_seed, kind)
    ex = figures(model.example, dom, side)
    ms = 3 + size if mask_seed is None else int(mask_seed)
    print(f"{kind} {side} {size} mask {mask_seed} example: fan {ex['fan']:.1f} bearing {ex['bear']:.0f} "
          f"(true {true_bearing(kind, side, size, ms):.0f}) dev {ex['dev']:.3f} frame {ex['frame']:.3f} "
          f"far {ex['far']:.3f} thick {ex['thick']:.3f} sea {ex['sea']} rad {ex['rad']:.2f} coast {ex['coast']:.3f} "
          f"side {ex['side']:.2f} sin {ex['sin']:.3f} mouth {ex['mouth']:.2f}",
          flush=True)
    rows = []
    for seed in seeds:
        s = synthesize_structure(model, rng=seed).structure
        f = figures(s, dom, side)
        f["berr"] = bearing_error(f["bear"], ex["bear"])
        f["far"] /= max(ex["far"], 1e-3)
        f["rad"] /= ex["rad"]
        f["nch"] = f["sea"] / max(ex["sea"], 1)
        f["struct"] = s
        rows.append(f)
        print(f"  seed {seed}: fan {f['fan']:.1f} bearing err {f['berr']:.1f} dev {f['dev']:.3f} "
              f"frame {f['frame']:.3f} cross {f['cross']} far x{f['far']:.2f} thick {f['thick']:.3f} "
              f"sea {f['sea']} rad x{f['rad']:.2f} coast {f['coast']:.3f} "
              f"side {f['side']:.2f} sin {f['sin']:.3f} mouth {f['mouth']:.2f} nch x{f['nch']:.2f}", flush=True)
    keys = ("fan", "berr", "dev", "frame", "far", "thick", "rad", "coast", "side", "sin", "nch", "mouth")
    med = {k: float(np.median([r[k] for r in rows])) for k in keys}
    print(f"  SUMMARY {kind} {side} {size} mask {mask_seed}: fan med {med['fan']:.1f} "
          f"min {min(r['fan'] for r in rows):.1f} (ex {ex['fan']:.1f}) bearing err med {med['berr']:.1f} "
          f"max {max(r['berr'] for r in rows):.1f} thick med {med['thick']:.3f} "
          f"max {max(r['thick'] for r in rows):.3f} "
          f"(ex {ex['thick']:.3f}) dev med {med['dev']:.3f} (ex {ex['dev']:.3f}) frame med {med['frame']:.3f} "
          f"max {max(r['frame'] for r in rows):.3f} cross {sum(r['cross'] for r in rows)} far med x{med['far']:.2f} "
          f"max x{max(r['far'] for r in rows):.2f} sea min {min(r['sea'] for r in rows)} rad med x{med['rad']:.2f} "
          f"max x{max(r['rad'] for r in rows):.2f} coast med {med['coast']:.3f} "
          f"max {max(r['coast'] for r in rows):.3f} "
          f"(ex {ex['coast']:.3f}) side med {med['side']:.2f} min {min(r['side'] for r in rows):.2f} "
          f"(ex {ex['side']:.2f}) sin med {med['sin']:.3f} (ex {ex['sin']:.3f}) nch med x{med['nch']:.2f} "
          f"min x{min(r['nch'] for r in rows):.2f} mouth med {med['mouth']:.2f} (ex {ex['mouth']:.2f})", flush=True)
    if out:
        tag = "" if kind == "delta" else f"_{kind}"
        _sheet(img, dom, model.example, rows[:3], f"{out}{tag}_{side}_{size}_{mask_seed}.png")
    return rows


if __name__ == "__main__":
    sides = sys.argv[1].split(",")
    sizes = [int(v) for v in sys.argv[2].split(",")]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    out = sys.argv[4] if len(sys.argv) > 4 else None
    cache = sys.argv[5] if len(sys.argv) > 5 else None
    masks = [None] if len(sys.argv) <= 6 else [None if v == "-" else int(v) for v in sys.argv[6].split(",")]
    kinds = sys.argv[7].split(",") if len(sys.argv) > 7 else ["delta"]
    for kd in kinds:
        for sz in sizes:
            for sd in sides:
                for ms in masks:
                    run(sd, sz, range(n), out, cache, ms, kd)
