"""Measure: which pictures the lightning metaphor takes for a lightning photo (a strike).

``python -m branchnb.dendrite._strike_sweep [--off]`` prints, for 12 photos without lightning at
200 / 240 / 320 / 512 / 800 px (long side) and a procedural dusk skyline, which ones have
a strike (false strikes), and for the NOAA lightning photo at 5 sizes, 10 procedural
night storms and 20 storms of :mod:`~branchnb.branching._storm_examples` (1 or 3 bolts, 2
sizes) whether there is a strike and where (lattice pixels). ``--off``: the light-source
rule (``STRIKE_MIN_RANK``) off, as before it. Not a test: the
figures go into :mod:`~branchnb.dendrite.photo_strike`'s docstring.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage

PHOTOS = ("rocket", "text", "clock", "coffee", "chelsea", "astronaut", "camera", "horse",
          "cracked_mud", "retina", "zelkova_leaf", "maple_leaf_01")
SIZES = (200, 240, 320, 512, 800)
NOAA_SIZES = (240, 320, 512, 800, 1024)


def load(name: str) -> np.ndarray:
    """A photo as float32 RGB (skimage's sample pictures or the project's data)."""
    import skimage.data as skdata

    from .. import data
    from ..core import as_rgb

    if name in ("rocket", "text", "clock", "horse"):
        img = np.asarray(getattr(skdata, name)(), np.float32)
        img = img / max(float(img.max()), 1.0)
    else:
        img = data.load(name)
    return np.asarray(as_rgb(img), np.float32)


def fit(img: np.ndarray, n: int) -> np.ndarray:
    """``img`` resized so its long side is ``n`` px."""
    from skimage.transform import resize

    s = n / max(img.shape[:2])
    shape = (max(int(round(img.shape[0] * s)), 8), max(int(round(img.shape[1] * s)), 8))
    return np.clip(resize(img, shape + img.shape[2:], anti_aliasing=s < 1), 0, 1).astype(np.float32)


def _walk(rng, x0, y0, y1, n):
    ys = np.arange(int(y0 * n), int(y1 * n))
    xs = x0 * n + np.cumsum(rng.choice([-2, -1, 0, 1, 2], ys.size)) * 0.35
    return ys, np.clip(np.round(xs).astype(int), 0, n - 1)


def night(n: int = 240, seed: int = 0) -> np.ndarray:
    """A procedural night storm (as in ``tests/test_dendrite_photo_strike.py``)."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:n, 0:n] / n
    sky = 0.08 + 0.35 * np.exp(-((xx - 0.5) / 0.3) ** 2 - ((yy - 0.3) / 0.12) ** 2)
    sky = sky + 0.04 * ndimage.gaussian_filter(rng.random((n, n)), 2) + 0.02 * rng.random((n, n))
    bolt = np.zeros((n, n), bool)
    ys, xs = _walk(rng, 0.42, 0.35, 0.97, n)
    bolt[ys, xs] = True
    bolt = ndimage.binary_dilation(bolt)
    img = np.where(bolt, 0.95, sky)
    for x0, y0, y1 in ((0.7, 0.45, 0.9), (0.22, 0.5, 0.85)):
        ys, xs = _walk(rng, x0, y0, y1, n)
        img[ys, xs] = np.maximum(img[ys, xs], 0.7)
    img = np.clip(img, 0, 1).astype(np.float32)
    return np.dstack([img * 0.9, img * 0.75, img])


def skyline(n: int = 300, seed: int = 0) -> np.ndarray:
    """A dusk skyline with a lit mast (as in ``tests/test_dendrite_photo_strike.py``)."""
    rng = np.random.default_rng(seed)
    h, w = n, int(n * 1.3)
    sky = 0.25 + 0.55 * np.mgrid[0:h, 0:w][0] / h
    img = np.dstack([sky, sky * 0.6, sky * 0.5])
    x = 0
    while x < w:
        bw, top = rng.integers(w // 12, w // 5), int(h * rng.uniform(0.35, 0.75))
        img[top:, x:x + bw] = 0.06
        for r in range(top + 6, h - 4, 8):
            for c in range(x + 4, x + bw - 4, 7):
                if rng.random() < 0.4:
                    img[r:r + 3, c:c + 3] = (0.9, 0.8, 0.5)
        x += bw
    img[int(0.08 * h):int(0.55 * h), w // 2] = 0.97
    img[int(0.08 * h):int(0.55 * h), w // 2 + 1] = 0.85
    return np.clip(img + 0.015 * rng.standard_normal(img.shape), 0, 1).astype(np.float32)


def strike(img: np.ndarray, **kw):
    """The strike :meth:`~branchnb.dendrite.stylization.Stylizer.strike` finds, with
    :func:`~branchnb.dendrite.photo_strike.strike_origin`'s keywords ``kw`` (e.g.
    ``min_rank=0.0``: the light-source rule off)."""
    from ..core import as_gray
    from .photo_strike import strike_origin
    from .stylization import StylizeParams, Stylizer

    return strike_origin(as_gray(Stylizer(img).working_image(StylizeParams())), **kw)


def main(argv=None) -> None:
    kw = {"min_rank": 0.0} if "--off" in (argv or []) else {}
    false, total = [], 0
    for name in PHOTOS:
        big = load(name)
        row = []
        for n in SIZES:
            at = strike(fit(big, n), **kw)
            row.append("S" if at is not None else ".")
            if n != 200:
                total += 1
            if at is not None:
                false.append(f"{name}@{n}")
        print(f"{name:14s} {' '.join(row)}", flush=True)
    at = strike(skyline(), **kw)
    total += 1
    if at is not None:
        false.append("skyline")
    print(f"false strikes (240-800 px + skyline): {sum('@200' not in f for f in false)}/{total}; "
          f"with 200 px: {len(false)}; {false}")
    kept = []
    noaa = load("lightning_noaa")
    for n in NOAA_SIZES:
        kept.append((f"noaa@{n}", strike(fit(noaa, n), **kw)))
    for n in (240, 280):
        for seed in range(5):
            kept.append((f"night{n}s{seed}", strike(night(n, seed), **kw)))
    from ..branching._storm_examples import storm_example

    for nb in (1, 3):
        for shape in ((288, 384), (200, 260)):
            for seed in range(5):
                img = storm_example(shape, seed, n_bolts=nb)[0]
                kept.append((f"storm{nb}b{shape[0]}s{seed}", strike(img, **kw)))
    print(f"lightning struck: {sum(a is not None for _, a in kept)}/{len(kept)}")
    for k, a in kept:
        print(f"  {k:14s} {a}")


if __name__ == "__main__":
    main(sys.argv[1:])
