"""Issue-23 figures of radial synthesis (branching67, branching69): per hub, the primaries leaving it and
their spread, how they branch, and how the hub is drawn.

``python -m branchnb.branching._radial_synth_check [SEEDS] [KINDS|all] [PNG_DIR] [CACHE_DIR]`` makes each
:func:`._radial_examples.radial_example` (sizes as in :mod:`._hub_check`; ``mask``: a neuron's line mask,
white on black, 0/1), extracts, fits and synthesizes it with the defaults and prints per case:

- ``ex``/``syn`` the branches starting within 1.1 hub radii of each centre (example: its true hubs;
  synthesized: ``structure.hubs``, else every root's start) and the largest angular gap between them
  (degrees, read at 1.3 radii); ``hub`` the radius of the disc of line colour at the synthesized centre
  (where the ring median falls below half the line contrast) over the example's (main: 0.16-0.43);
- ``bp/p`` branch points (children not at a hub) per primary, example / synthesized; ``bp/L`` the same per
  100 px of the primaries' trees; ``gen`` children per generation below the primaries (1/2/3);
- ``stub`` branches shorter than 2 line widths starting within 2 hub radii of a centre;
- ``nn`` the median nearest-neighbour angle between a hub's primaries read at 2 radii, over the even share
  ``360 / n`` (1: evenly spread; primaries running in pairs read low), example / synthesized;
- ``min`` / ``min3`` (branching75) the smallest gap between neighbouring primaries over the even share,
  read at 2 and 3 radii (primaries running in pairs read low), example / synthesized;
- ``taper`` the median over children (below the primaries) of their mean radius over their last fifth
  over their first fifth, example / synthesized; ``cov`` the share of the frame within 5 % of its
  diagonal of a line, example / synthesized;
- ``stubI`` line-coloured blobs (>= 3 px) between 1.0 and 1.35 hub radii farther than 2 px from the
  structure's lines (drawn at their radii): stubs the image shows by the hub that no branch explains;
- ``joint`` the median over primaries of the lightest line contrast along the primary between 0.9 and 1.6
  hub radii (1: as dark as the line beyond, 0: the ground), example / synthesized image.

branching69 (main -> now, 21 cases): branch points per primary 0.0-1.8 -> 0.8-6.5 (example 1.0-6.0; mean
synthesized / example 0.09 -> 1.01, range 0.62-1.56), joint 0.51-1.00 -> 0.71-1.32 (example 0.97-1.73),
a mask's hub 0.06-0.1 -> 0.9-1.0, primaries per hub and largest gap unchanged; image stubs by the hub 0-12
(example 0-14; drawn from inside the hub, .radial._into_hubs: no dark notches, coral 512 s0 joint 0.92 -> 0.85).

branching75 (main -> now, 21 cases): branch points per primary synthesized / example 0.62-1.56 -> 0.67-1.03
(in 0.8-1.2: 14 -> 19 of 21; children per generation capped at the example's per spoke,
.radial._generation_caps; hub budget per primary; below 0.8: crack_bright 512 s2 0.67, mask 256 s0 0.75, the
length budget runs out first); children's taper (end / start radius) |synthesized - example| mean 0.22 ->
0.06, largest 0.51 -> 0.19 (main 0.95-1.10 where the example's are 0.46-0.86; .radial._taper_profile);
median turn of a primary from the rim to 3 radii 1.7-24.5 -> 0.4-10.3 deg (example 0.6-8.8;
.radial._spoke_goal); smallest neighbour gap at 3 radii over the example's 0.56-1.55 -> 0.79-1.80.

PNG_DIR: example | synthesized image per case. CACHE_DIR: extracted examples kept (pickles) for reruns.
"""
# ruff: noqa: E702
from __future__ import annotations

import os
import pickle
import sys

import cv2
import numpy as np

from ._hub_check import SIZES
from ._radial_examples import KINDS, radial_example

#: the kinds: :data:`._radial_examples.KINDS` and ``mask`` (a neuron's binary line mask)
CHECK_KINDS = KINDS + ("mask",)


def _gap(a) -> float:
    return float(np.degrees(np.max(np.diff(np.r_[a, a[0] + 2 * np.pi])))) if len(a) >= 2 else 360.0


def spoke_angles(s, x: float, y: float, r: float) -> np.ndarray:
    """Sorted angles of the branches starting within 1.1 r of (x, y), read where they pass 1.3 r."""
    a = []
    for b in s.branches:
        d = np.hypot(b.points[:, 0] - x, b.points[:, 1] - y)
        far = np.flatnonzero(d > 1.3 * r)
        if d[0] <= 1.1 * r and far.size:
            p = b.points[far[0]]
            a.append(np.arctan2(p[1] - y, p[0] - x) % (2 * np.pi))
    return np.sort(a)


def _read_at(s, x: float, y: float, r: float, at: float) -> np.ndarray:
    """Sorted angles of the branches starting within 1.1 r of (x, y), read where they pass ``at`` r."""
    a = []
    for b in s.branches:
        d = np.hypot(b.points[:, 0] - x, b.points[:, 1] - y)
        far = np.flatnonzero(d > at * r)
        if d[0] <= 1.1 * r and far.size:
            p = b.points[far[0]]
            a.append(np.arctan2(p[1] - y, p[0] - x) % (2 * np.pi))
    return np.sort(a)


def _centre_r(c, r0):
    return c[0], c[1], (c[2] if len(c) > 2 else r0)


def primaries(s, centres, r0: float) -> list[tuple[int, float]]:
    """``(count, largest gap)`` per centre ``(x, y[, r])`` (see the module docstring)."""
    out = []
    for c in centres:
        x, y, r = _centre_r(c, r0)
        a = spoke_angles(s, x, y, r)
        out.append((len(a), _gap(a)))
    return out


def tree_stats(s, centres, r0: float) -> dict:
    """Branch points per primary and per 100 px, children per generation, stubs by the hubs and the
    nearest-neighbour angle of the primaries (see the module docstring)."""
    n = len(s.branches)
    spoke = np.zeros(n, bool)
    near = np.zeros(n, bool)
    for c in centres:
        x, y, r = _centre_r(c, r0)
        for i, b in enumerate(s.branches):
            d0 = np.hypot(b.points[0, 0] - x, b.points[0, 1] - y)
            spoke[i] |= d0 <= 1.1 * r
            near[i] |= d0 <= 2.0 * r
    gen = np.full(n, -1)

    def g(i):
        if gen[i] < 0:
            par = s.branches[i].parent
            gen[i] = 0 if spoke[i] or par is None else g(par) + 1
        return gen[i]

    for i in range(n):
        g(i)
    lengths = np.array([b.length for b in s.branches])
    width = 2.0 * float(np.median([np.median(s.branches[i].thickness[:5]) for i in np.flatnonzero(spoke)])) \
        if spoke.any() else 2.0
    n_sp = max(int(spoke.sum()), 1)
    kids = int((gen > 0).sum())
    nn = []
    for c in centres:
        x, y, r = _centre_r(c, r0)
        a = []
        for i in np.flatnonzero(spoke):
            b = s.branches[i]
            d = np.hypot(b.points[:, 0] - x, b.points[:, 1] - y)
            if d[0] > 1.1 * r:
                continue
            far = np.flatnonzero(d > 2.0 * r)
            if far.size:
                p = b.points[far[0]]
                a.append(np.arctan2(p[1] - y, p[0] - x) % (2 * np.pi))
        if len(a) >= 2:
            a = np.sort(a)
            gaps = np.diff(np.r_[a, a[0] + 2 * np.pi])
            nn.extend(np.minimum(gaps, np.roll(gaps, 1)) / (2 * np.pi / len(a)))
    m3 = []   # the smallest gap between neighbouring primaries read at 3 radii, over the even share
    for c in centres:
        x, y, r = _centre_r(c, r0)
        a = [t for t in _read_at(s, x, y, r, 3.0)]
        if len(a) >= 2:
            gaps = np.diff(np.r_[a, a[0] + 2 * np.pi])
            m3.append(float(gaps.min() / (2 * np.pi / len(a))))
    tp = []   # a child's taper: its mean radius over its last fifth / its first fifth
    for i in np.flatnonzero(gen > 0):
        r = np.asarray(s.branches[i].thickness, np.float64)
        if r.size >= 5:
            q = max(r.size // 5, 1)
            tp.append(float(np.mean(r[-q:]) / max(np.mean(r[:q]), 1e-9)))
    return {"taper": float(np.median(tp)) if tp else float("nan"),
            "min": float(np.min(nn)) if nn else 0.0, "min3": float(np.min(m3)) if m3 else 0.0,
            "bp": kids / n_sp, "bpL": 100.0 * kids / max(lengths.sum(), 1e-9),
            "gen": [int((gen == k).sum()) for k in (1, 2, 3)],
            "stub": int((near & (lengths < 2 * width)).sum()), "nn": float(np.median(nn)) if nn else 0.0}


def coverage(s, shape, share: float = 0.05) -> float:
    """Share of the frame within ``share`` x its diagonal of a branch's centre line."""
    h, w = shape
    m = np.ones((h, w), np.uint8)
    for b in s.branches:
        cv2.polylines(m, [np.int32(np.round(b.points))], False, 0, 1)
    return float((cv2.distanceTransform(m, cv2.DIST_L2, 5) <= share * np.hypot(h, w)).mean())


def joint_contrast(gray, s, centres, r0: float, ink: float, ground: float) -> float:
    """Median over the primaries of the lightest contrast along them between 0.9 and 1.6 hub radii."""
    h, w = gray.shape
    out = []
    for c in centres:
        x, y, r = _centre_r(c, r0)
        for b in s.branches:
            p = np.asarray(b.points, np.float64)
            if np.hypot(p[0, 0] - x, p[0, 1] - y) > 1.1 * r or len(p) < 2:
                continue
            # resampled at 0.5 px so a long step cannot skip the joint
            t = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
            q = np.c_[np.interp(np.arange(0, t[-1], 0.5), t, p[:, 0]), np.interp(np.arange(0, t[-1], 0.5), t, p[:, 1])]
            d = np.hypot(q[:, 0] - x, q[:, 1] - y)
            q = q[(d >= 0.9 * r) & (d <= 1.6 * r)]
            if not len(q):
                continue
            ix, iy = np.clip(np.rint(q[:, 0]).astype(int), 0, w - 1), np.clip(np.rint(q[:, 1]).astype(int), 0, h - 1)
            out.append(float(np.min((gray[iy, ix] - ground) / (ink - ground))))
    return float(np.median(out)) if out else float("nan")


def image_stubs(gray, s, centres, r0: float, ink: float, ground: float) -> int:
    """Line-coloured blobs by the hubs that none of ``s``'s lines explains (see the module docstring)."""
    h, w = gray.shape
    lines = np.zeros((h, w), np.uint8)
    for b in s.branches:
        p = np.asarray(b.points, np.float64)
        r = np.asarray(b.thickness, np.float64)
        for i in range(len(p) - 1):
            cv2.line(lines, tuple(np.int32(np.round(p[i]))), tuple(np.int32(np.round(p[i + 1]))), 1,
                     int(2 * max(r[i], 1.0) + 4))
    yy, xx = np.mgrid[:h, :w]
    ann = np.zeros((h, w), bool)
    for c in centres:
        x, y, r = _centre_r(c, r0)
        d = np.hypot(xx - x, yy - y)
        ann |= (d >= 1.0 * r) & (d <= 1.35 * r)
    blob = ann & ((gray - ground) / (ink - ground) > 0.5) & (lines == 0)
    n, _lab, st, _c = cv2.connectedComponentsWithStats(blob.astype(np.uint8), connectivity=8)
    return int((st[1:, cv2.CC_STAT_AREA] >= 3).sum())


def blob_radius(gray: np.ndarray, x: float, y: float, ink: float, ground: float) -> int:
    """Radius of the disc of line colour at ``(x, y)`` (1: none)."""
    yy, xx = np.mgrid[:gray.shape[0], :gray.shape[1]]
    d = np.hypot(xx - x, yy - y)
    for rr in range(1, 80):
        if (np.median(gray[(d >= rr - 0.5) & (d < rr + 0.5)]) - ground) / (ink - ground) < 0.5:
            return rr
    return 80


def _example(kind: str, size: int, seed: int, cache: str | None):
    from . import extract_structure

    f = f"{cache}/{kind}_{size}_{seed}.pkl" if cache else None
    if f and os.path.exists(f):
        with open(f, "rb") as fh:
            return pickle.load(fh)
    rgb, _centre, lines, hubs = radial_example("neuron" if kind == "mask" else kind, size, seed)
    if kind == "mask":
        rgb = np.repeat(lines[..., None], 3, -1).astype(np.float32)
    got = (rgb, lines, hubs, extract_structure(rgb))
    if f:
        with open(f, "wb") as fh:
            pickle.dump(got, fh)
    return got


def case(kind: str, size: int, seed: int, png: str | None = None, cache: str | None = None) -> str:
    from . import fit_model, synthesize_image, synthesize_structure

    rgb, lines, hubs, s = _example(kind, size, seed, cache)
    R = float(np.mean([h[2] for h in hubs]))
    ex = primaries(s, list(hubs), R)
    res = synthesize_structure(fit_model(s), rng=seed)
    sh = getattr(res.structure, "hubs", None)
    sc = list(sh) if sh else [tuple(b.points[0]) for b in res.structure.branches if b.parent is None]
    sy = primaries(res.structure, sc, R)
    im = synthesize_image(rgb, s, res, rng=seed).image
    g = rgb.mean(-1)
    ink = float(np.median(g[lines]))
    ground = float(np.median(g[~(cv2.dilate(lines.astype(np.uint8), np.ones((9, 9), np.uint8)) > 0)]))
    rb = float(np.mean([blob_radius(g, x, y, ink, ground) for x, y, _ in hubs]))
    gi = np.asarray(im)[..., :3].mean(-1)
    ratio = [round(blob_radius(gi, c[0], c[1], ink, ground) / rb, 2) for c in sc]
    te, ts = tree_stats(s, list(hubs), R), tree_stats(res.structure, sc, R)
    ie, is_ = image_stubs(g, s, list(hubs), R, ink, ground), image_stubs(gi, res.structure, sc, R, ink, ground)
    je, js = joint_contrast(g, s, list(hubs), R, ink, ground), joint_contrast(gi, res.structure, sc, R, ink, ground)
    if png:
        vis = np.concatenate([rgb, np.asarray(im)[..., :3]], 1)
        cv2.imwrite(f"{png}/{kind}_{seed}.png", (np.clip(vis, 0, 1)[..., ::-1] * 255).astype(np.uint8))
    return (f"{kind:13s} {size:5d} s{seed} ex {[e[0] for e in ex]} gap {[round(e[1]) for e in ex]} | "
            f"syn {[e[0] for e in sy]} gap {[round(e[1]) for e in sy]} | hub {ratio} | "
            f"bp/p {te['bp']:.1f}/{ts['bp']:.1f} bp/L {te['bpL']:.2f}/{ts['bpL']:.2f} "
            f"gen {'/'.join(map(str, te['gen']))}|{'/'.join(map(str, ts['gen']))} stub {te['stub']}/{ts['stub']} "
            f"nn {te['nn']:.2f}/{ts['nn']:.2f} min {te['min']:.2f}/{ts['min']:.2f} "
            f"min3 {te['min3']:.2f}/{ts['min3']:.2f} taper {te['taper']:.2f}/{ts['taper']:.2f} "
            f"cov {coverage(s, g.shape):.2f}/{coverage(res.structure, g.shape):.2f} "
            f"stubI {ie}/{is_} joint {je:.2f}/{js:.2f}")


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    seeds = [int(v) for v in (argv[0] if argv else "0,1,2").split(",")]
    kinds = CHECK_KINDS if len(argv) < 2 or argv[1] == "all" else tuple(argv[1].split(","))
    png = argv[2] if len(argv) > 2 and argv[2] != "-" else None
    cache = argv[3] if len(argv) > 3 else None
    for kind in kinds:
        for seed in seeds:
            i = CHECK_KINDS.index(kind) % len(KINDS)
            print(case(kind, SIZES[(seed + i) % len(SIZES)], seed, png, cache), flush=True)


if __name__ == "__main__":
    main()
