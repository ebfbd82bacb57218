"""Benchmarks of image-based tree variations.

``rows(quick)`` times one full 1024 x 1024 variation (M = 20) against the
paper's figure, a repeated flat-art variation (stroke maps kept on the
exemplars) against the first call that makes them, the mean-value-coordinate kernel against a vectorised numpy
formulation of the same formula, histogram transfer against scikit-image's
``match_histograms``, and includes the billboard-cloud rows of
``_bench_cloud`` when that module is present.
"""

from __future__ import annotations

import importlib.util

import numpy as np

from ..bench import BenchRow, timeit

#: The paper's time for one 1024 x 1024 variation with M = 20.
PAPER_VARIATION_SECONDS = 5.5


def _mvc_numpy(x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Hormann-Floater mean value coordinates, vectorised numpy (points off the cage)."""
    s = v[None, :, :] - x[:, None, :]
    r = np.sqrt(s[..., 0] ** 2 + s[..., 1] ** 2)
    sn = np.roll(s, -1, axis=1)
    a = s[..., 0] * sn[..., 1] - s[..., 1] * sn[..., 0]
    d = s[..., 0] * sn[..., 0] + s[..., 1] * sn[..., 1]
    t = a / (r * np.roll(r, -1, axis=1) + d)
    w = (np.roll(t, 1, axis=1) + t) / r
    return w / w.sum(axis=1, keepdims=True)


def rows(quick: bool = False) -> list[BenchRow]:
    from skimage.exposure import match_histograms

    from .histogram_transfer import histogram_transfer, opaque_pixels
    from .mvc import mean_value_coordinates
    from .variations import TreeLibrary, make_variation

    names = ["tree_rpg_01", "tree_rpg_03"] if quick else ["tree_rpg_01", "tree_rpg_03", "tree_rpg_06"]
    lib = TreeLibrary.from_data(names, size=1024)
    w = np.full(len(names), 1.0 / len(names))
    v = make_variation(lib, w, rng=0)
    n_px = int(v.mask.sum())
    t_var = timeit(lambda: make_variation(lib, w, rng=0), repeat=2 if quick else 3)
    out = [BenchRow(
        f"one 1024x1024 variation, M = 20, {len(names)} exemplars ({n_px / 1e3:.0f}k pixels)",
        t_var, "paper: 5.5 s for one 1024x1024 variation, M = 20", PAPER_VARIATION_SECONDS,
        "paper, other machine; contour combination, fill, cage, MVC transfer, bilinear RGBA",
    )]

    def first_call():
        for e in lib.exemplars:
            e._cages.pop("stroke_maps", None)
        make_variation(lib, w, rng=0)

    t_first = timeit(first_call, repeat=1 if quick else 2)
    out.append(BenchRow(
        f"flat-art ({v.colour_mode}) 1024x1024 variation, repeated: per-source stroke maps kept",
        timeit(lambda: make_variation(lib, w, rng=0), repeat=2),
        "the same variation making the maps (first call; every call before trees37)", t_first,
        "ink, pure fills, unmixed fills, coverage made once per exemplar; bit-identical results",
    ))

    rng = np.random.default_rng(0)
    n = 200_000 if quick else 1_000_000
    pts = rng.uniform(0, 1024, (n, 2))
    cage = lib[names[0]].cage(20)
    out.append(BenchRow(
        f"mean value coordinates, {n // 1000}k points, M = 20",
        timeit(lambda: mean_value_coordinates(pts, cage), repeat=2),
        "numpy vectorised (same formula, no on-cage limits)",
        timeit(lambda: _mvc_numpy(pts, cage), repeat=2),
        "numba loop over points vs (P, M) numpy temporaries",
    ))

    src, ref = v.image, lib[names[-1]].image
    out.append(BenchRow(
        f"histogram transfer 1024x1024, {len(opaque_pixels(src)) / 1e3:.0f}k opaque pixels",
        timeit(lambda: histogram_transfer(src, ref), repeat=2),
        "skimage.exposure.match_histograms on the opaque pixels",
        timeit(lambda: match_histograms(opaque_pixels(src), opaque_pixels(ref), channel_axis=-1),
               repeat=2),
        "ours also maps the semi-transparent edge pixels",
    ))

    if importlib.util.find_spec(f"{__package__}._bench_cloud") is not None:
        from . import _bench_cloud

        out.extend(_bench_cloud.bench_rows(quick))
    return out
