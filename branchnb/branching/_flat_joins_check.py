"""Issue-23 figures of the flat drawing path (binary masks, drawn maps): is every tree one connected line?

``python -m branchnb.branching._flat_joins_check [KINDS|radial] [CACHE_DIR]`` synthesizes (defaults:
``extract_structure``, ``fit_model``, ``synthesize_structure``, ``synthesize_image``) binary masks of
radial kinds (:func:`._radial_examples.radial_example`'s line mask, white on black and black on white),
thin crack/river/vessel masks (:func:`._thin_mask_check.thin_mask_example`), delta masks
(:func:`._delta_examples.delta_fan_mask`) and river/country maps (:mod:`._map_examples`), 256-1024 px, and
prints :func:`flat_joins` per case and the totals. ``KINDS``: ``neuron,crack,river,vessel,delta,rmap,cmap``;
``radial``: the six radial kinds as masks, two seeds each.

branching73 (main a2dc929; ``all``: 17 cases, ``radial``: 12): every tree one 8-connected piece in all 29
(55 trees, pieces 1.00, 711 children, none detached or starting off its parent, 0 specks); gaps 0 except
``cmap`` 512 s0 (3: river tails cut back short of the coast line on purpose, :func:`.drawing._trim_tail`).
The floating pieces seen in a downscaled sheet (``cmp_mask_2``) are one-pixel
children that vanish when shrunk, not breaks. The textured path on ``_radial_synth_check 0 all``
(:func:`.measures.relative_line_pieces`): 1.0 piece per tree (crack_bright 256: 1.2), 0-3 gaps, 0-1
specks (the examples' own: 1-6 pieces, 0-8 gaps). Not measured here: ``delta`` 512 s1's channels end
~40 px short of the sea (its tree and the sea are two pieces) and the sea's edge has small notches.
"""
# ruff: noqa: E702
from __future__ import annotations

import os
import pickle
import sys

import cv2
import numpy as np
from scipy import ndimage as ndi

from .measures import _line_gaps

#: (kind, size, seed) of the default run
CASES = (("neuron", 256, 0), ("neuron", 384, 1), ("neuron", 512, 2), ("neuron", 1024, 2),
         ("crack_bow", 512, 0), ("crack_wob", 300, 1), ("river_bow", 600, 0), ("river_wob", 450, 2),
         ("vessel_bow", 450, 1), ("vessel_wob", 600, 0), ("delta", 256, 0), ("delta", 512, 1),
         ("delta", 1024, 2), ("rmap", 512, 0), ("rmap", 400, 1), ("cmap", 512, 0), ("cmap", 768, 1))


def _roots(structure) -> list[int]:
    b = structure.branches
    out = list(range(len(b)))
    for i in range(len(b)):
        while b[out[i]].parent is not None:
            out[i] = b[out[i]].parent
    return out


def _centre_ids(lab: np.ndarray, ink: np.ndarray, points) -> np.ndarray:
    m = np.zeros(lab.shape, np.uint8)
    cv2.polylines(m, [np.round(np.asarray(points, np.float64) * 8).astype(np.int32)], False, 1, 1, cv2.LINE_8, 3)
    return lab[(m > 0) & ink]


def _off_parent(structure, i: int) -> float:
    """How far branch ``i`` starts beyond its parent's drawn body (centre-line distance - radius)."""
    b = structure.branches[i]
    p = structure.branches[b.parent]
    P, q = np.asarray(p.points, np.float64), np.asarray(b.points[0], np.float64)
    if len(P) < 2:
        return float(np.hypot(*(P[0] - q)))
    a, d = P[:-1], np.diff(P, axis=0)
    t = np.clip(((q - a) * d).sum(1) / np.maximum((d * d).sum(1), 1e-9), 0.0, 1.0)
    return float(np.min(np.linalg.norm(a + t[:, None] * d - q, axis=1)) - np.max(p.thickness))


def flat_joins(ink: np.ndarray, structure) -> dict:
    """Connectivity of a drawn ``structure`` in the line mask ``ink`` ((H, W) bool, the output's line pixels).

    Returns ``trees`` (roots; the roots leaving one hub, within 1.2 radii + 2 px of its centre, count as
    one tree), ``pieces`` (mean 8-connected pieces of ``ink`` under a tree's centre lines), ``max_pieces``,
    ``kids`` (branches with a parent), ``detached`` (children whose centre line lies mostly in another
    piece than their parent's), ``off`` (children starting > 1 px beyond their parent's drawn body),
    ``gaps`` (runs of >= 2 px along a branch with no line pixel within 1 px) and ``specks`` (pieces < 10 px).

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> s = Structure([Branch([(2, 10), (16, 10), (30, 10)], 1.0), Branch([(16, 10), (16, 30)], 1.0, 0, 1)])
    >>> ink = np.zeros((40, 40), bool); ink[9:12, 2:31] = True; ink[14:31, 15:18] = True
    >>> d = flat_joins(ink, s); d["pieces"], d["detached"], d["off"]
    (2.0, 1, 0)
    """
    ink = np.asarray(ink, bool)
    lab, n = ndi.label(ink, structure=np.ones((3, 3)))
    sizes = np.bincount(lab.ravel(), minlength=n + 1)
    B = structure.branches
    root = _roots(structure)
    hubs = list(getattr(structure, "hubs", None) or [])
    groups: dict = {}
    for i in range(len(B)):
        g = r0 = root[i]
        for k, (x, y, r) in enumerate(hubs):
            if np.hypot(B[r0].points[0, 0] - x, B[r0].points[0, 1] - y) <= 1.2 * r + 2:
                g = ("hub", k)
        groups.setdefault(g, []).append(i)
    ids = [_centre_ids(lab, ink, b.points) for b in B]
    pieces = [int(np.count_nonzero(np.unique(np.concatenate([ids[i] for i in idx])))) for idx in groups.values()]
    kids = [i for i, b in enumerate(B) if b.parent is not None]
    detached = sum(1 for i in kids if ids[i].size and ids[B[i].parent].size
                   and np.bincount(ids[i]).argmax() != np.bincount(ids[B[i].parent]).argmax())
    off = sum(1 for i in kids if _off_parent(structure, i) > 1.0)
    gaps = _line_gaps(B, ink)
    return {"trees": len(pieces), "pieces": float(np.mean(pieces)) if pieces else 0.0,
            "max_pieces": max(pieces) if pieces else 0, "kids": len(kids), "detached": int(detached),
            "off": int(off), "gaps": gaps, "specks": int(np.sum((sizes[1:] > 0) & (sizes[1:] < 10)))}


def example(kind: str, size: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(image, line colour, ground colour)`` of a flat example of ``kind`` (see the module docstring;
    ``R<radial kind>[-bow]``: a radial kind's line mask, ``-bow`` black on white)."""
    if kind.startswith("R") or kind == "neuron":
        from ._radial_examples import radial_example

        k, _, pol = (kind[1:] if kind.startswith("R") else kind).partition("-")
        lines = np.asarray(radial_example(k, size, seed)[2], np.float32)
        img = np.repeat(lines[..., None], 3, -1)
        return (1.0 - img, np.zeros(3), np.ones(3)) if pol == "bow" else (img, np.ones(3), np.zeros(3))
    if kind == "delta":
        from ._delta_examples import delta_fan_mask

        img = np.repeat(np.asarray(delta_fan_mask((size, size), seed)[0], np.float32)[..., None], 3, -1)
        return img, np.ones(3), np.zeros(3)
    if kind in ("rmap", "cmap"):
        from ._map_examples import INK, LAND, RIVER, country_map_example, river_map_example

        img = (river_map_example if kind == "rmap" else country_map_example)((size, size), seed)[0]
        return img, np.array(RIVER if kind == "rmap" else INK), np.array(LAND)
    from ._thin_mask_check import thin_mask_example

    k, pol = kind.split("_")
    img = thin_mask_example(k, size, seed, dark=pol == "bow")
    return (img, np.zeros(3), np.ones(3)) if pol == "bow" else (img, np.ones(3), np.zeros(3))


def case(kind: str, size: int, seed: int, cache: str | None = None, png: str | None = None) -> dict:
    """:func:`flat_joins` of the default workflow's output on :func:`example` (``png``: example | output)."""
    from . import extract_structure, fit_model, synthesize_image, synthesize_structure

    img, line, ground = example(kind, size, seed)
    f = f"{cache}/{kind}_{size}_{seed}.pkl" if cache else None
    if f and os.path.exists(f):
        with open(f, "rb") as fh:
            ex = pickle.load(fh)
    else:
        ex = extract_structure(img)
        if f:
            with open(f, "wb") as fh:
                pickle.dump(ex, fh)
    res = synthesize_structure(fit_model(ex), rng=seed)
    out = np.asarray(synthesize_image(img, ex, res, rng=seed).image, np.float32)[..., :3]
    ink = np.linalg.norm(out - line, axis=-1) < np.linalg.norm(out - ground, axis=-1)
    if png:
        cv2.imwrite(png, (np.clip(np.hstack([img, out]), 0, 1) * 255).astype(np.uint8)[..., ::-1])
    return flat_joins(ink, res.structure)


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    cases = CASES
    if argv and argv[0] == "radial":
        from ._radial_examples import KINDS

        cases = tuple(("R" + k + ("-bow" if j % 2 else ""), (256, 384, 512, 768)[(j + s) % 4], s)
                      for j, k in enumerate(KINDS) for s in (0, 1))
    elif argv and argv[0] != "all":
        cases = tuple(c for c in CASES if c[0].split("_")[0] in argv[0].split(","))
    cache = argv[1] if len(argv) > 1 else None
    total: dict = {}
    for kind, size, seed in cases:
        m = case(kind, size, seed, cache)
        for k, v in m.items():
            total[k] = total.get(k, 0) + v
        print(f"{kind:18s} {size:5d} s{seed} " + " ".join(f"{k}={v:.2f}" if isinstance(v, float) else f"{k}={v}"
                                                        for k, v in m.items()), flush=True)
    print("TOTAL", " ".join(f"{k}={v:.0f}" for k, v in total.items()))


if __name__ == "__main__":
    main()
