"""Issue-23 figures on radial examples (branching62): lines leaving a hub (a soma, a coral's centre, a
crater) are traced with the hub as a region and rooted there.

``python -m branchnb.branching._hub_check [SEEDS] [KINDS|all] [PNG_DIR]`` makes each
:func:`._radial_examples.radial_example` (neurons with 1-3 somas, corals, crack stars; light-on-dark and
dark-on-light) at 256-1024 px and traces it with the defaults (``extract_structure(rgb)``); it prints per
case ``hub`` the share of true hubs with a traced root within the hub's radius of its centre, ``roots``
the traced roots per true hub, ``spurs`` the branch ends inside a hub (should be 0), ``prec`` the
share of the traced centre lines within 3 px of a true line or hub, ``rec`` the share of true centre
line pixels (outside the hubs) within 3 px of the traced structure. PNG_DIR: example | traced
structure (roots red).
"""
# ruff: noqa: E702
from __future__ import annotations

import cv2
import numpy as np

from ._check_table import check_args, print_table
from ._radial_examples import KINDS, radial_example

SIZES = (256, 384, 512, 768, 1024)


def measure(s, centre_lines: np.ndarray, lines: np.ndarray, hubs) -> dict:
    """The figures of one traced structure ``s`` against the truth (see the module docstring)."""
    shape = lines.shape
    roots = [b for b in s.branches if b.parent is None and len(b.points)]
    hit = [any(np.hypot(*(b.points[0] - (x, y))) <= r for b in roots) for x, y, r in hubs]
    spurs = 0
    for b in s.branches:
        for x, y, r in hubs:
            spurs += int(np.hypot(*(b.points[-1] - (x, y))) < r)
    traced = s.render(shape)[..., 0] < 0.5
    near_truth = cv2.dilate(lines.astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
    centre = np.zeros(shape, bool)
    for b in s.branches:
        p = np.clip(np.rint(b.points).astype(int), 0, np.array(shape[::-1]) - 1)
        centre[p[:, 1], p[:, 0]] = True
    near_trace = cv2.dilate(traced.astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
    return {"hub": float(np.mean(hit)), "roots": len(roots) / max(len(hubs), 1), "spurs": float(spurs),
            "prec": float(near_truth[centre].mean()) if centre.any() else 0.0,
            "rec": float(near_trace[centre_lines].mean()) if centre_lines.any() else 1.0}


def _case(kind: str, size: int, seed: int, png: str | None) -> dict:
    from .extraction import extract_structure

    rgb, centre_lines, lines, hubs = radial_example(kind, size, seed)
    s = extract_structure(rgb)
    out = measure(s, centre_lines, lines, hubs)
    if png:
        traced = np.repeat(1.0 - (s.render(lines.shape)[..., :1] < 0.5), 3, -1).astype(np.float32)
        for b in s.branches:
            if b.parent is None:
                cv2.circle(traced, tuple(int(v) for v in np.round(b.points[0])), 5, (0, 0, 1), 2)
        for x, y, r in hubs:
            cv2.circle(traced, (int(x), int(y)), int(r), (0, 0.7, 0), 1)
        sheet = np.concatenate([rgb, traced], 1)
        cv2.imwrite(png, (np.clip(sheet, 0, 1)[..., ::-1] * 255).astype(np.uint8))
    return out


def main(argv=None) -> None:
    seeds, kinds, pngdir = check_args(argv, KINDS, (0, 1, 2))
    print_table(kinds, seeds, lambda k, s: SIZES[(s + KINDS.index(k)) % len(SIZES)], _case,
                ("hub", "roots", "spurs", "prec", "rec"), lambda r: "", pngdir, width=12)


if __name__ == "__main__":
    main()
