"""Issue-23 figures on ornaments and border bands (branching53): bands of long strands, not bushes.

``python -m branchnb.branching._band_check [SEEDS] [KINDS] [PNG_DIR]`` (e.g. ``0,1,2 L,U,frame,wavy,ring``;
a kind with ``+`` has leaf stubs, e.g. ``L+``) runs each :func:`._band_examples.band_example` at sizes
256-768 px through the default workflow (``extract_structure``, ``fit_model(ex, domain=example_domain(img,
ex))``, ``synthesize_structure``) and prints per case and per kind: ``out`` the share of the output's length
farther than the example's strand spacing from every example line, branch count ratio ``nb`` and mean branch
length ratio ``ml`` (output over example), total length ratio ``len``, and the mean absolute turn per 10 px of
the output over the example's ``turn``. PNG_DIR: sheets example | seed s | seed s + 1.
"""
# ruff: noqa: E501, E702
from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ._band_examples import KINDS, band_example
from ._check_table import check_args, length_share, print_table, write_sheet

SIZES = (256, 384, 512, 640, 768)


def _turn(s, step: float = 10.0) -> float:
    """Mean absolute turn (radians) between successive ``step``-px chords of every branch of ``s``."""
    tot, n = 0.0, 0
    for b in s.branches:
        p = np.asarray(b.points, float)
        if len(p) < 2:
            continue
        arc = np.r_[0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
        if arc[-1] < 3 * step:
            continue
        u = np.arange(0, arc[-1], step)
        q = np.c_[np.interp(u, arc, p[:, 0]), np.interp(u, arc, p[:, 1])]
        a = np.arctan2(*np.diff(q, axis=0).T[::-1])
        da = np.abs((np.diff(a) + np.pi) % (2 * np.pi) - np.pi)
        tot += float(da.sum()); n += len(da)
    return tot / max(n, 1)


def figures(img, spacing: float, ex, out) -> dict:
    """The figures of one case (example structure ``ex``, synthesized structure ``out``)."""
    ink = img[..., :3].mean(-1) < 0.5
    far = ndi.distance_transform_edt(~ink) > spacing
    outside, tot = length_share(out, far)
    nb_e, nb_o = max(len(ex.branches), 1), max(len(out.branches), 1)
    return {"nb_ex": len(ex.branches), "nb_out": len(out.branches), "out": outside / max(tot, 1e-9),
            "nb": nb_o / nb_e, "ml": (out.total_length / nb_o) / max(ex.total_length / nb_e, 1e-9),
            "len": out.total_length / max(ex.total_length, 1e-9), "turn": _turn(out) / max(_turn(ex), 1e-9)}


def case(kind: str, size: int, seed: int, png: str | None = None) -> dict:
    from . import example_domain, extract_structure, fit_model, synthesize_structure

    leaves = kind.endswith("+")
    img, spacing = band_example(kind.rstrip("+"), size, seed, leaves=leaves)
    ex = extract_structure(img)
    model = fit_model(ex, domain=example_domain(img, ex))
    res = synthesize_structure(model, rng=seed)
    f = figures(img, spacing, ex, res.structure)
    if png:
        write_sheet(png, img, res.structure, synthesize_structure(model, rng=seed + 1).structure)
    return f


def main(argv=None) -> None:
    seeds, kinds, pngdir = check_args(argv, list(KINDS) + [k + "+" for k in KINDS], (0, 1, 2))
    keys = ("out", "nb", "ml", "len", "turn")
    print_table(kinds, seeds, lambda kind, s: SIZES[(s + KINDS.index(kind.rstrip("+"))) % len(SIZES)], case, keys,
                lambda r: f"nb {r['nb_ex']:3d}->{r['nb_out']:3d}", pngdir, width=6)


if __name__ == "__main__":
    main()
