"""Colour models of lazy snapping (:func:`branchnb.leaves.layers.grow_layers`, step 2).

The features a pixel is compared by (CIELAB, optionally relative to the
blade around it: :func:`_local_contrast`), the k-means colour centres of a
layer and of the rest (:func:`_kmeans`) and each colour's distance to its
nearest centre (:func:`_nearest`), from which the data costs ``E1`` come.
"""

from __future__ import annotations

import cv2
import numba
import numpy as np

__all__: list[str] = []


def _local_contrast(feat: np.ndarray, blade: np.ndarray, radius: float) -> np.ndarray:
    """Each pixel's colour minus the blade's median colour around it (``radius`` px, blade only).

    A photographed leaf is lit unevenly: a pale vein on the dark side of
    the blade has the colour of plain blade on the bright side, and a
    colour model alone grows the vein layer over the bright side. What
    stays constant is how the vein stands out from the blade next to it.
    A median, not a mean: a layer covering much of a neighbourhood (dense
    ink lines) would make its own surroundings and stand out from nothing.
    The median is taken on a grid reduced so the window is 7 cells wide
    (shading is smooth), over the cells that are mostly blade.
    """
    from ..core.image import extend_nearest

    h, w = blade.shape
    f = max(1.0, float(radius) / 3.0)
    small = (max(1, int(round(w / f))), max(1, int(round(h / f))))
    # Cells of the reduced grid: the blade's mean colour where they are
    # mostly blade; the rest take no part (the backdrop and the outline
    # drawn around a blade are not "the blade around").
    cover = cv2.resize(blade.astype(np.float32), small, interpolation=cv2.INTER_AREA)
    lo = cv2.resize(np.where(blade[..., None], feat, 0).astype(np.float32), small, interpolation=cv2.INTER_AREA)
    inside = cover > 0.5
    if not inside.any():
        return np.zeros_like(feat)
    lo = np.where(inside[..., None], lo / np.maximum(cover, 1e-6)[..., None], np.nan)
    win = np.lib.stride_tricks.sliding_window_view(np.pad(lo, ((3, 3), (3, 3), (0, 0)), constant_values=np.nan),
                                                   (7, 7), axis=(0, 1))
    with np.errstate(all="ignore"):
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            med = np.nanmedian(win.reshape(win.shape[:3] + (-1,)), axis=-1)
    med = extend_nearest(np.nan_to_num(med), np.isfinite(med).all(-1)).astype(np.float32)
    around = cv2.resize(med, (w, h), interpolation=cv2.INTER_LINEAR)
    return np.where(blade[..., None], feat - around, 0).astype(np.float32)


def _kmeans(samples: np.ndarray, k: int, rng: np.random.Generator) -> np.ndarray:
    samples = np.asarray(samples, np.float32)
    if len(samples) > 20000:
        samples = samples[rng.choice(len(samples), 20000, replace=False)]
    # About ten samples per centre at least: with a few hundred scribbled
    # pixels, one centre per pixel would make every stray pixel under a
    # scribble (a brush wider than a vein also covers blade) a colour of the
    # model, and the layer would grow into everything like it.
    k = int(min(k, len(np.unique(samples.round(1), axis=0)), max(1, len(samples) // 10)))
    if k <= 1:
        return samples.mean(axis=0, keepdims=True)
    crit = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 20, 0.1)
    cv2.setRNGSeed(int(rng.integers(2**31)))
    _, _, centres = cv2.kmeans(samples, k, None, crit, 2, cv2.KMEANS_PP_CENTERS)
    return centres


def _nearest(colours: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """Distance of each colour to its nearest centre (compiled, one pixel at a time, no temporaries).

    Summed as ``|c - centre|^2`` in float64: at most ~1e-3 Lab units from
    the ``|c|^2 - 2 c.centre + |centre|^2`` of float32 matrix products it
    replaced (which cancel on bright colours), 10x faster at a megapixel.
    """
    c = np.ascontiguousarray(colours, np.float32).reshape(len(colours), -1)
    k = np.ascontiguousarray(centres, np.float32).reshape(len(centres), -1)
    return _nearest_nb(c, k)


@numba.njit(cache=True, nogil=True)
def _nearest_nb(colours, centres):  # pragma: no cover - compiled
    n, d = colours.shape
    out = np.empty(n, np.float32)
    for i in range(n):
        best = np.inf
        for a in range(centres.shape[0]):
            s = 0.0
            for j in range(d):
                t = np.float64(colours[i, j]) - np.float64(centres[a, j])
                s += t * t
            if s < best:
                best = s
        out[i] = np.sqrt(best)
    return out
