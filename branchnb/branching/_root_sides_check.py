"""Issue-23 figures on where line drawings' roots enter (branching51).

``python -m branchnb.branching._root_sides_check [SEEDS] [KINDS] [PNG_DIR]`` draws procedural root
drawings (:func:`root_drawing`: one or two root systems of 6-px trunks with 1-4 px roots, anti-aliased
dark lines on paper) entering from a known place, runs the default workflow (``extract_structure``,
``fit_model(ex, domain=example_domain(img, ex))``, ``synthesize_structure``) and prints per case (and
per kind, mean): ``side`` the share of the output's roots starting within 4 % of the short side of a
frame side the example enters from (inside roots: farther than that from every side, for the inside
kind), ``pos`` the mean distance of each output root to the nearest true entry (share of the frame's
diagonal), ``near`` the output's share of length within a quarter of the frame of the entry side(s)
over the example's (1 = as dense near the entry), ``len`` / ``nb`` length and branch ratios, ``out``
the share of the output's length more than 8 % of the short side from every example line. Kinds:
``top``, ``bottom``, ``left``, ``right`` (two systems entering there), ``topleft`` (one from the top,
one from the left), ``inside`` (one system spreading from inside), ``river`` (a one-width river
network entering from the bottom edge).
"""
# ruff: noqa: E501, E702
from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from ._check_table import check_args, length_share, print_table

KINDS = ("top", "bottom", "left", "right", "topleft", "inside", "river")
SIZES = (320, 420, 520)
_SIDE_ANGLE = {"top": np.pi / 2, "bottom": -np.pi / 2, "left": 0.0, "right": np.pi}


def _entries(kind: str, H: int, W: int, rng) -> list[tuple[float, float, float, str]]:
    """(x, y, heading, side) of every system's entry."""
    out = []
    sides = {"topleft": ("top", "left"), "river": ("bottom",)}.get(kind, (kind, kind))
    if kind == "inside":
        return [(W * rng.uniform(0.4, 0.6), H * rng.uniform(0.4, 0.6), rng.uniform(-np.pi, np.pi), "inside")]
    for i, side in enumerate(sides):
        f = rng.uniform(0.2, 0.4) if i == 0 else rng.uniform(0.6, 0.8)
        if len(sides) == 1:
            f = rng.uniform(0.35, 0.65)
        if side in ("top", "bottom"):
            x, y = f * W, (0.0 if side == "top" else H - 1.0)
        else:
            x, y = (0.0 if side == "left" else W - 1.0), f * H
        out.append((x, y, _SIDE_ANGLE[side] + rng.normal(0, 0.15), side))
    return out


def root_drawing(kind: str, width: int, seed: int):
    """``(image (H, W, 3) float32, entries)``: a root drawing of ``kind`` ``3 width / 4`` x ``width``."""
    rng = np.random.default_rng(500 + 31 * seed + KINDS.index(kind))
    H, W = int(0.75 * width), int(width)
    img = np.ones((H, W), np.float32)
    s = width / 420.0
    river = kind == "river"

    def grow(x, y, ang, wd, depth, n=None):
        pts = [(x, y)]
        a0 = ang
        n = int((60 + 40 * rng.random()) * s) if n is None else n
        for _ in range(n):
            # wander about the start heading (a trunk heads into the frame, a root away from its parent)
            ang += rng.normal(0, 0.12 if not river else 0.06) + 0.08 * np.angle(np.exp(1j * (a0 - ang)))
            x += 2 * np.cos(ang); y += 2 * np.sin(ang)
            if not (0 <= x < W and 0 <= y < H):
                break
            pts.append((x, y))
            if depth < 3 and rng.random() < (0.045 if not river else 0.03):
                grow(x, y, ang + rng.choice([-1, 1]) * rng.uniform(0.4, 0.9),
                     wd if river else max(1.0, wd * 0.6), depth + 1)
        for (a, b), (c, d) in zip(pts[:-1], pts[1:]):
            cv2.line(img, (int(a), int(b)), (int(c), int(d)), 0.15, int(max(1, wd)), cv2.LINE_AA)

    ent = _entries(kind, H, W, rng)
    for x, y, a, side in ent:
        if side == "inside":
            for k in range(4):   # arms that end inside the frame
                grow(x, y, a + k * np.pi / 2 + rng.normal(0, 0.2), 4, 1, n=int(35 * s))
        else:
            grow(x, y, a, 2 if river else 6, 0, n=int(120 * s))
    rgb = np.dstack([img * 0.95, img * 0.9, img * 0.8]).astype(np.float32)
    return rgb, ent


def _side_dist(p, H, W) -> tuple[str, float]:
    d = {"top": p[1], "bottom": H - 1 - p[1], "left": p[0], "right": W - 1 - p[0]}
    k = min(d, key=d.get)
    return k, float(d[k])


def _near_share(s, ent, H, W) -> float:
    """Share of the length of ``s`` within a quarter of the frame of an entry's side (or of the entry
    point inside)."""
    tot = near = 0.0
    for b in s.branches:
        p = np.asarray(b.points, float)
        if len(p) < 2:
            continue
        mid = 0.5 * (p[1:] + p[:-1]); sl = np.hypot(*np.diff(p, axis=0).T)
        ok = np.zeros(len(mid), bool)
        for x, y, _a, side in ent:
            if side == "top":
                ok |= mid[:, 1] < 0.25 * H
            elif side == "bottom":
                ok |= mid[:, 1] > 0.75 * H
            elif side == "left":
                ok |= mid[:, 0] < 0.25 * W
            elif side == "right":
                ok |= mid[:, 0] > 0.75 * W
            else:
                ok |= np.hypot(mid[:, 0] - x, mid[:, 1] - y) < 0.25 * min(H, W)
        tot += sl.sum(); near += sl[ok].sum()
    return near / max(tot, 1e-9)


def figures(img, ent, ex, out) -> dict:
    H, W = img.shape[:2]
    lim = 0.04 * min(H, W)
    sides = {e[3] for e in ent}
    roots = [np.asarray(b.points[0], float) for b in out.branches if b.parent is None and len(b.points) >= 2]
    hit, pos = [], []
    diag = float(np.hypot(H, W))
    for p in roots:
        k, d = _side_dist(p, H, W)
        hit.append((d <= lim and k in sides) or ("inside" in sides and d > lim))
        pos.append(min(np.hypot(p[0] - e[0], p[1] - e[1]) for e in ent) / diag)
    ink = img[..., :3].mean(-1) < 0.5
    far = ndi.distance_transform_edt(~ink) > 0.08 * min(H, W)
    o, tot = length_share(out, far)
    return {"side": float(np.mean(hit)) if hit else 0.0, "pos": float(np.mean(pos)) if pos else 1.0,
            "near": _near_share(out, ent, H, W) / max(_near_share(ex, ent, H, W), 1e-9),
            "len": out.total_length / max(ex.total_length, 1e-9),
            "nb": len(out.branches) / max(len(ex.branches), 1), "out": o / max(tot, 1e-9),
            "n_ex": sum(b.parent is None for b in ex.branches), "n_out": len(roots)}


def case(kind: str, width: int, seed: int, png: str | None = None) -> dict:
    from . import example_domain, extract_structure, fit_model, synthesize_structure
    from ._thin_children_check import _draw

    img, ent = root_drawing(kind, width, seed)
    ex = extract_structure(img)
    model = fit_model(ex, domain=example_domain(img, ex))
    res = synthesize_structure(model, rng=seed)
    f = figures(img, ent, ex, res.structure)
    if png:
        out = _draw(res.structure, img.shape[:2])
        for b in res.structure.branches:
            if b.parent is None:
                cv2.circle(out, tuple(int(v) for v in np.round(b.points[0])), 6, (1.0, 0.0, 0.0), 2)
        cv2.imwrite(png, (np.hstack([img, out]) * 255).astype(np.uint8)[..., ::-1])
    return f


def main(argv=None) -> None:
    seeds, kinds, pngdir = check_args(argv, KINDS)
    keys = ("side", "pos", "near", "len", "nb", "out")
    print_table(kinds, seeds, lambda kind, s: SIZES[(s + KINDS.index(kind)) % len(SIZES)], case, keys,
                lambda r: f"roots {r['n_ex']}->{r['n_out']}", pngdir)


if __name__ == "__main__":
    main()
