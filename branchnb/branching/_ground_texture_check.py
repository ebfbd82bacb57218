"""Issue-23 figures of the ground between the lines in ``synthesize_image`` (branching64).

``python -m branchnb.branching._ground_texture_check [SEEDS] [KINDS] [PNG_DIR] [key=value ...]`` (e.g.
``0,1 fields,noise``; ``key=value`` pairs go to :class:`ImageSynthesisParams`). Each kind is a known line tree
(:func:`~._image_examples.random_tree`, dark lines of 1-6 px) drawn over a known ground: ``fields`` (wavy
patches of three tones, 0.1-0.16 of the side), ``noise`` (grain and blotches up to 1/20 of the side),
``stripes`` (ploughed rows), ``plain`` (one colour with grain) and ``disc`` (noise ground with a bright
disc at the root, like a retina's optic disc); sizes 256-1024 px. The example's structure is the true one,
the target another known tree. Per output it prints

- ``hist``: distance of the ground's colour histogram from the example's (1-D Wasserstein per channel over
  the ground's std, mean of the channels; ground = > r + 4 px from every line);
- ``spec``: distance of the ground's gradient-energy spectrum from the example's: mean |log2| of the
  band-energy ratios, bands = differences of Gaussians at 1, 2, 4 ... px up to 1/8 of the side (lines
  filled with their surroundings first); 0 = same texture at every scale, 1 = a factor 2 off per band;
- ``lstd``: mean local std (3 px) of the ground, output over example;
- ``big``: energy of the coarsest two bands (the patches), output over example;
- ``pcs``: dark pieces per target tree (8-connected, :func:`._vessel_check.measure`); ``gap``: runs of
  >= 2 px along the target's centre lines that are not dark;
- ``blob``: the largest bright blob of the output over the example's disc area (``disc`` kind,
  :func:`disc_copy`; 0 = nothing brighter than the example's ground but the disc itself);
- ``sec``: seconds of ``synthesize_image``.
"""
# ruff: noqa: E501
from __future__ import annotations

import sys
import time

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.render import draw_polylines
from ._check_table import image_check_args, print_table, write_pair
from ._image_examples import random_tree

KINDS = ("fields", "noise", "stripes", "plain", "disc")
SIZES = (256, 384, 512, 768, 1024)


def _blur_noise(rng, s, sigma):
    n = ndi.gaussian_filter(rng.normal(0, 1, (s, s)), sigma)
    return n / (n.std() + 1e-9)


def ground(kind: str, size: int, rng) -> np.ndarray:
    """The known ground of ``kind`` (float32 (size, size, 3))."""
    s = size
    yy, xx = np.mgrid[:s, :s].astype(np.float64)
    grain = 0.015 * rng.normal(0, 1, (s, s, 3))
    if kind == "fields":
        warp = _blur_noise(rng, s, 0.033 * s) * 0.07 * s
        cx, cy = rng.uniform(0.11, 0.16) * s, rng.uniform(0.11, 0.16) * s
        f = (np.floor((xx + warp) / cx) + 2 * np.floor((yy + 0.7 * warp) / cy)) % 3
        img = np.stack([0.35 + 0.06 * f, 0.42 + 0.05 * f, 0.22 + 0.03 * f], -1)
        img = img * (1 + 0.04 * _blur_noise(rng, s, 2.0))[..., None]
    elif kind in ("noise", "disc"):
        b = 0.05 * _blur_noise(rng, s, 1.0) + 0.06 * _blur_noise(rng, s, s / 128) + 0.1 * _blur_noise(rng, s, s / 20)
        img = np.array([0.62, 0.52, 0.36]) * (1 + b)[..., None]
    elif kind == "stripes":
        a = rng.uniform(0, np.pi)
        period = rng.uniform(0.02, 0.04) * s
        u = xx * np.cos(a) + yy * np.sin(a) + 0.03 * s * _blur_noise(rng, s, 0.05 * s)
        img = np.array([0.55, 0.5, 0.35]) * (1 + 0.12 * np.sin(2 * np.pi * u / period))[..., None]
    elif kind == "plain":
        img = np.broadcast_to(np.array([0.7, 0.68, 0.6]), (s, s, 3)).copy()
    else:
        raise ValueError(kind)
    return np.clip(img + grain, 0, 1).astype(np.float32)


def example(kind: str, size: int, seed: int):
    """(image, structure, disc mask or None) of one case."""
    rng = np.random.default_rng(seed)
    s = random_tree((size, size), 200 + seed, n_children=5, r_root=1.5 + 3.0 * size / 1024, r_child=1.6,
                    grandchildren=2)
    img = ground(kind, size, rng)
    disc = None
    if kind == "disc":
        p = s.branches[0].points[len(s.branches[0].points) // 6]
        yy, xx = np.mgrid[:size, :size]
        rr = np.hypot(xx - p[0], yy - p[1]) / (0.06 * size)
        a = np.clip(1.2 - rr, 0, 1)[..., None]
        img = img * (1 - a) + np.array([0.97, 0.9, 0.7], np.float32) * a
        disc = rr < 0.7
    ink = draw_polylines(np.zeros((size, size, 3), np.float32), [b.points for b in s.branches],
                         widths=[2 * np.asarray(b.thickness) for b in s.branches], colors=(1, 1, 1))[..., :1]
    img = img * (1 - 0.8 * ink) + 0.8 * ink * np.array([0.12, 0.16, 0.2], np.float32)
    return np.clip(cv2.GaussianBlur(img.astype(np.float32), (0, 0), 0.6), 0, 1), s, disc


def _target(size, seed):
    return random_tree((size, size), 700 + seed, n_children=5, r_root=1.5 + 3.0 * size / 1024, r_child=1.6,
                       grandchildren=2)


def _band(s, shape, extra=4):
    from ._vessel_check import _mask

    m = _mask(s, shape)
    return ndi.binary_dilation(m, iterations=extra)


def _filled(lum, band):
    """``lum`` with the band's pixels replaced by the average of the ground around them."""
    keep = (~band).astype(np.float32)
    out = lum.copy()
    for sig in (3.0, 8.0, 24.0):
        num = cv2.GaussianBlur(lum * keep, (0, 0), sig)
        den = cv2.GaussianBlur(keep, (0, 0), sig)
        fill = num / np.maximum(den, 1e-6)
        todo = band & (den > 0.05) if sig < 24 else band
        out[todo] = fill[todo]
        keep = np.maximum(keep, todo.astype(np.float32))
        band = band & ~todo
    return out


def texture_stats(img, s, skip=None):
    """(ground pixels (n, 3), band energies, mean local std) of ``img`` around structure ``s``."""
    H = img.shape[0]
    band = _band(s, img.shape[:2])
    if skip is not None:
        band = band | skip
    lum = np.asarray(img, np.float32)[..., :3].mean(2)
    f = _filled(lum, band)
    bands = []
    sig = 1.0
    while sig <= H / 8:
        d = cv2.GaussianBlur(f, (0, 0), sig) - cv2.GaussianBlur(f, (0, 0), 2 * sig)
        bands.append(float(np.mean(d[~band] ** 2)))
        sig *= 2
    mu = cv2.GaussianBlur(lum, (0, 0), 3.0)
    sd = np.sqrt(np.maximum(cv2.GaussianBlur(lum * lum, (0, 0), 3.0) - mu * mu, 0))
    far = ~ndi.binary_dilation(band, iterations=6)
    return np.asarray(img)[..., :3][~band], np.array(bands), float(np.mean(sd[far]))


def ground_distance(example_img, s_ex, out, s_t, skip_ex=None):
    """``hist``, ``spec``, ``lstd`` and ``big`` of one output (see the module docstring).

    Examples
    --------
    >>> img, s, _ = example("noise", 128, 0)
    >>> d = ground_distance(img, s, img, s)
    >>> round(d["hist"], 3), round(d["spec"], 3), round(d["lstd"], 2)
    (0.0, 0.0, 1.0)
    """
    g_ex, e_ex, l_ex = texture_stats(example_img, s_ex, skip_ex)
    g_o, e_o, l_o = texture_stats(out, s_t)
    q = np.linspace(0.01, 0.99, 99)
    sd = np.maximum(g_ex.std(0), 1e-3)
    hist = float(np.mean(np.abs(np.quantile(g_ex, q, axis=0) - np.quantile(g_o, q, axis=0)).mean(0) / sd))
    n = min(len(e_ex), len(e_o))
    ratio = np.log2(np.maximum(e_o[:n], 1e-12) / np.maximum(e_ex[:n], 1e-12))
    return {"hist": hist, "spec": float(np.mean(np.abs(ratio))), "lstd": l_o / max(l_ex, 1e-6),
            "big": float(np.sum(e_o[n - 2:n]) / max(np.sum(e_ex[n - 2:n]), 1e-12))}


def disc_copy(example_img, s_ex, disc, out) -> float:
    """Largest bright blob of ``out`` over the example's disc area: pixels 0.3 of the way from the
    example ground's brightest pixel (away from the lines and the disc) to the disc's median
    brightness, opened by one pixel."""
    n = example_img.shape[0]
    lum_ex = example_img[..., :3].mean(2)
    far = ~_band(s_ex, example_img.shape[:2]) & ~ndi.binary_dilation(disc, iterations=int(0.1 * n))
    g = float(lum_ex[far].max())
    thr = g + 0.3 * max(float(np.median(lum_ex[disc])) - g, 0.0)
    lab, k = ndi.label(ndi.binary_opening(np.asarray(out)[..., :3].mean(2) > thr, iterations=1))
    return (float(np.bincount(lab.ravel())[1:].max()) if k else 0.0) / max(int(disc.sum()), 1)


def run_case(kind, size, seed, png=None, params=None):
    from ._vessel_check import measure
    from .image_synthesis import _EXAMPLE_CACHE, synthesize_image

    ex, s_ex, disc = example(kind, size, seed)
    tgt = _target(size, seed)
    _EXAMPLE_CACHE.clear()
    t0 = time.perf_counter()
    res = synthesize_image(ex, s_ex, tgt, params, rng=seed)
    sec = time.perf_counter() - t0
    out = np.asarray(res.image)[..., :3]
    r = ground_distance(ex, s_ex, out, tgt, disc)
    v = measure(ex, s_ex, out, tgt)
    r["pcs"] = v["pcs"] / sum(b.parent is None for b in tgt.branches)
    r["gap"] = v["gap"]
    r["blob"] = 0.0 if disc is None else disc_copy(ex, s_ex, disc, out)
    r["sec"] = sec
    if png:
        write_pair(png, ex, out)
    return r


def main(argv):
    seeds, kinds, pngdir, params = image_check_args(argv)
    kinds = kinds or list(KINDS)
    print_table(kinds, seeds, lambda k, s: SIZES[(KINDS.index(k) + 2 * s) % len(SIZES)],
                lambda k, n, s, png: run_case(k, n, s, png, params),
                ("hist", "spec", "lstd", "big", "pcs", "gap", "blob", "sec"), lambda r: "", pngdir)


if __name__ == "__main__":
    main(sys.argv[1:])
