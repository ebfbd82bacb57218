"""The table the branching check scripts print: one row per kind and seed, then each kind's means.

Shared by :mod:`._root_sides_check`, :mod:`._thin_children_check` and :mod:`._band_check`
(private measurement scripts, not part of the API); :func:`cached` keeps the fitted examples of
:mod:`._delta_fan_check`, :mod:`._delta_tree_check`, :mod:`._radius_check` and :mod:`._seed_check`.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Sequence

import numpy as np


def print_table(kinds, seeds, size_of: Callable, case: Callable, keys, head: Callable,
                pngdir: str | None = None, width: int = 8) -> None:
    """Run ``case(kind, size_of(kind, seed), seed, png)`` for every kind and seed and print its
    figures ``keys`` (after ``head(row)``), then the mean of each figure per kind.

    Examples
    --------
    >>> print_table(["a"], [0], lambda k, s: 8, lambda k, n, s, png: {"x": n + s}, ("x",),
    ...             lambda r: "row")
    a           8 0  row x=8.00
    MEAN a        x=8.00
    """
    if pngdir:
        os.makedirs(pngdir, exist_ok=True)
    for kind in kinds:
        rows = []
        for s in seeds:
            size = size_of(kind, s)
            png = os.path.join(pngdir, f"{kind}_{size}_{s}.png") if pngdir else None
            r = case(kind, size, s, png)
            rows.append(r)
            print(f"{kind:{width}s} {size:4d} {s}  {head(r)} " + " ".join(f"{k}={r[k]:.2f}" for k in keys),
                  flush=True)
        print(f"MEAN {kind:{width}s} " + " ".join(f"{k}={np.mean([r[k] for r in rows]):.2f}" for k in keys),
              flush=True)


def cached(cache: str | None, name: str, make: Callable):
    """``make()``, pickled as ``cache/name`` and read from there the next time (the 1000 px extractions
    take most of a check's time); just ``make()`` when ``cache`` is None.

    Examples
    --------
    >>> import tempfile
    >>> d = tempfile.mkdtemp()
    >>> cached(d, "x.pkl", lambda: 3), cached(d, "x.pkl", lambda: 4), cached(None, "x.pkl", lambda: 5)
    (3, 3, 5)
    """
    import pickle

    path = os.path.join(cache, name) if cache else None
    if path and os.path.exists(path):
        with open(path, "rb") as f:
            return pickle.load(f)
    out = make()
    if path:
        os.makedirs(cache, exist_ok=True)
        with open(path, "wb") as f:
            pickle.dump(out, f)
    return out


def check_args(argv, kinds: Sequence[str], seeds: Sequence[int] = (0, 1)):
    """``(seeds, kinds, png_dir)`` from a check script's ``[SEEDS] [KINDS|all] [PNG_DIR]`` arguments.

    Examples
    --------
    >>> check_args(["0,2", "a"], ["a", "b"])
    ([0, 2], ['a'], None)
    >>> check_args([], ["a", "b"], (1,))
    ([1], ['a', 'b'], None)
    """
    argv = sys.argv[1:] if argv is None else argv
    seeds = [int(s) for s in argv[0].split(",")] if argv else list(seeds)
    kinds = argv[1].split(",") if len(argv) > 1 and argv[1] != "all" else list(kinds)
    return seeds, kinds, (argv[2] if len(argv) > 2 else None)


def image_check_args(argv):
    """``(seeds, kinds or None, png_dir, params)`` from an image check's ``[SEEDS] [KINDS|all] [PNG_DIR]
    [name=value ...]`` arguments: ``params`` an :class:`.image_params.ImageSynthesisParams` with the
    named fields set (None when none is), ``kinds`` None for all.

    Examples
    --------
    >>> image_check_args(["0,1", "all", "flatten_shading=0.1"])[3].flatten_shading
    0.1
    """
    from .image_params import ImageSynthesisParams

    seeds = [int(s) for s in argv[0].split(",")] if argv else [0, 1]
    kinds = argv[1].split(",") if len(argv) > 1 and argv[1] != "all" else None
    pngdir = argv[2] if len(argv) > 2 and "=" not in argv[2] else None
    kw = {}
    for a in argv[2:]:
        if "=" in a:
            k, v = a.split("=", 1)
            kw[k] = type(getattr(ImageSynthesisParams(), k))(v == "True" if v in ("True", "False") else float(v))
    return seeds, kinds, pngdir, (ImageSynthesisParams(**kw) if kw else None)


def write_pair(png: str, example, output) -> None:
    """Write the example's RGB and the output side by side (an image check's sheet)."""
    import cv2

    sheet = np.concatenate([np.asarray(example)[..., :3], output], axis=1)
    cv2.imwrite(png, (np.clip(sheet, 0, 1)[..., ::-1] * 255).astype(np.uint8))


def write_sheet(png: str, img, *structures) -> None:
    """Write ``img`` and each structure drawn on its own panel (:func:`._thin_children_check._draw`) side
    by side, grey lines between the panels."""
    import cv2
    import numpy as np

    from ._thin_children_check import _draw

    sheet = np.hstack([img] + [_draw(s, img.shape[:2]) for s in structures])
    sheet[:, img.shape[1]::img.shape[1]] = 0.5
    cv2.imwrite(png, (sheet * 255).astype(np.uint8)[..., ::-1])


def length_share(structure, mask) -> tuple[float, float]:
    """``(length on mask, total length)`` of ``structure``'s branches: each segment counted where its
    midpoint's pixel (clipped to the frame) is True in ``mask`` ((H, W) bool).

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> m = np.zeros((10, 10), bool); m[:, 5:] = True
    >>> length_share(Structure([Branch([(x, 2) for x in range(10)], 1.0)]), m)
    (4.0, 9.0)
    """
    import numpy as np

    h, w = mask.shape
    on = tot = 0.0
    for b in structure.branches:
        p = np.asarray(b.points, float)
        if len(p) < 2:
            continue
        mid = 0.5 * (p[1:] + p[:-1])
        sl = np.hypot(*np.diff(p, axis=0).T)
        xi = np.clip(np.round(mid[:, 0]).astype(int), 0, w - 1)
        yi = np.clip(np.round(mid[:, 1]).astype(int), 0, h - 1)
        on += float(sl[mask[yi, xi]].sum())
        tot += float(sl.sum())
    return on, tot
