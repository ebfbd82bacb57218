"""Measure: pareidolia trees that read as the picture and as a tree, before -> after.

``python -m branchnb.dendrite._pareidolia_sweep [sizes] [seeds] [names]`` grows a pareidolia
tree with the defaults on each picture (long side ``size`` px) with this session's rules off
and on (interleaved: more twigs on dark pictures ``pareidolia._DARK_TWIGS``, the limbs' ink
budgeted against the tone ``pareidolia_widths._LIMB_BUDGET``, a tree crown round an object
on a blank ground ``pareidolia_crown._AROUND`` with light twigs on that ground
``pareidolia._GROUND_TONE``, ``_GROUND_TWIGS``) and prints tone r inside the crown at 2 / 4
/ 8 px blur, the same at 4 px on the crown's part inside the picture's silhouette
(``obj``), the share of the crown outside the picture's silhouette (``out``) and the
crown's solidity (area over its convex hull's). Pictures: portraits (the astronaut, a
procedural face), objects on photos (coffee, cat), the night photo of a rocket, the camera
man, objects on white (a procedural clip-art apple, a maple-leaf photo, a procedural logo).
Not a test.
"""

from __future__ import annotations

import sys
import time

import numpy as np
from scipy import ndimage

NAMES = ("astronaut", "face", "coffee", "chelsea", "rocket", "camera", "apple", "maple_leaf_01",
         "logo")


def face(n: int = 400, seed: int = 0) -> np.ndarray:
    """A procedural portrait filling the frame: a mid-grey ground, dark hair, a light face
    with dark eyes, brows and mouth, a dark coat (4:5)."""
    rng = np.random.default_rng(seed)
    h, w = int(1.25 * n), n
    yy, xx = np.mgrid[0:h, 0:w] / n
    cx = 0.5 + rng.uniform(-0.05, 0.05)
    img = 0.55 + 0.1 * yy
    img = np.where(((xx - cx) / 0.3) ** 2 + ((yy - 0.5) / 0.38) ** 2 < 1, 0.12, img)  # hair
    img = np.where(((xx - cx) / 0.45) ** 2 + ((yy - 1.3) / 0.4) ** 2 < 1, 0.2, img)  # coat
    fc = ((xx - cx) / 0.23) ** 2 + ((yy - 0.58) / 0.3) ** 2 < 1
    img = np.where(fc, 0.85, img)
    for sx in (-1, 1):
        ex = cx + sx * 0.09
        img = np.where(((xx - ex) / 0.04) ** 2 + ((yy - 0.52) / 0.022) ** 2 < 1, 0.1, img)
        img = np.where((np.abs(xx - ex) < 0.05) & (np.abs(yy - 0.46) < 0.008), 0.25, img)
    img = np.where(((xx - cx) / 0.08) ** 2 + ((yy - 0.72) / 0.02) ** 2 < 1, 0.3, img)
    img = ndimage.gaussian_filter(img, 0.004 * n) + 0.03 * rng.standard_normal((h, w))
    return np.repeat(np.clip(img, 0, 1)[..., None], 3, axis=2).astype(np.float32)


def apple(n: int = 400, seed: int = 0) -> np.ndarray:
    """A procedural clip-art apple on white: a red body with a dark outline, a shading
    crescent, a brown stem and a green leaf (square)."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:n, 0:n] / n
    cx, cy, r = 0.5 + rng.uniform(-0.05, 0.05), 0.55, 0.3 + rng.uniform(-0.03, 0.03)
    img = np.ones((n, n, 3))
    rr = np.hypot((xx - cx) / 1.08, yy - cy)
    body = rr < r
    img[body] = (0.85, 0.12, 0.1)
    shade = body & (np.hypot(xx - cx - 0.08, yy - cy - 0.06) > r * 0.9)
    img[shade] = (0.55, 0.05, 0.05)
    img[np.abs(rr - r) < 0.012] = (0.1, 0.05, 0.05)
    stem = (np.abs(xx - cx - 0.01) < 0.012) & (yy > cy - r - 0.08) & (yy < cy - r + 0.03)
    img[stem] = (0.35, 0.2, 0.1)
    leaf = ((xx - cx - 0.09) / 0.08) ** 2 + ((yy - cy + r + 0.03) / 0.03) ** 2 < 1
    img[leaf] = (0.2, 0.6, 0.2)
    return np.clip(ndimage.gaussian_filter(img, (0.6, 0.6, 0)), 0, 1).astype(np.float32)


def logo(n: int = 400, seed: int = 0) -> np.ndarray:
    """A procedural logo on white: a thick dark ring round a bar letter ``T`` and a
    coloured bar under it (3:4, wider than tall)."""
    rng = np.random.default_rng(seed)
    h, w = int(0.75 * n), n
    yy, xx = np.mgrid[0:h, 0:w] / n
    cx, cy = 0.5 + rng.uniform(-0.04, 0.04), 0.33
    img = np.ones((h, w, 3))
    ring = np.abs(np.hypot(xx - cx, yy - cy) - 0.22) < 0.035
    img[ring] = (0.1, 0.15, 0.4)
    tee = ((np.abs(xx - cx) < 0.11) & (np.abs(yy - cy + 0.08) < 0.03)) | \
          ((np.abs(xx - cx) < 0.03) & (yy > cy - 0.1) & (yy < cy + 0.13))
    img[tee] = (0.05, 0.05, 0.05)
    img[(np.abs(xx - cx) < 0.3) & (np.abs(yy - 0.66) < 0.025)] = (0.9, 0.5, 0.1)
    return np.clip(ndimage.gaussian_filter(img, (0.6, 0.6, 0)), 0, 1).astype(np.float32)


def picture(name: str, n: int, seed: int = 0) -> np.ndarray:
    """One of :data:`NAMES` with its long side ``n`` px."""
    from ._strike_sweep import fit, load

    if name in ("face", "apple", "logo"):
        img = globals()[name](400, seed)
    else:
        img = load(name)
    return fit(img, n)


def silhouette(image: np.ndarray) -> np.ndarray:
    """The picture's object: darkness above 0.08 (blurred 1 px), holes filled."""
    from ..core import as_gray

    dk = ndimage.gaussian_filter(1.0 - as_gray(image).astype(np.float64), 1.0)
    return ndimage.binary_fill_holes(dk > 0.08)


def crown_shape(t) -> tuple[float, float]:
    """(share of the crown outside the picture's silhouette, the crown's solidity)."""
    from skimage.morphology import convex_hull_image

    c = t.crown_on_canvas()
    sil = silhouette(t.image)  # the blank trunk strip is white: no part of it
    out = float((c & ~sil).sum() / max(c.sum(), 1))
    return out, float(c.sum() / max(convex_hull_image(c).sum(), 1))


def object_r(t, sigma: float = 4.0) -> float:
    """Tone r at ``sigma`` px blur on the crown's part inside the picture's silhouette
    (a tree crown round an object adds blank ground, whose white is easy to match)."""
    from ..core import as_gray

    m = t.crown_on_canvas() & silhouette(t.image)
    x = ndimage.gaussian_filter(1.0 - as_gray(t.image).astype(np.float64), sigma)[m]
    y = ndimage.gaussian_filter(1.0 - as_gray(t.render().image).astype(np.float64), sigma)[m]
    return float(np.corrcoef(x, y)[0, 1])


def tone_rs(t, sigmas=(2.0, 4.0, 8.0)) -> list[float]:
    from ._twig_ends import tone_r

    return [tone_r(t, s) for s in sigmas]


def _switch(on: bool) -> None:
    from . import pareidolia as pa
    from . import pareidolia_crown as pc
    from . import pareidolia_widths as pw

    pa._DARK_TWIGS = _KEEP[0] if on else 0.0
    pw._LIMB_BUDGET = _KEEP[1] if on else 0.0
    pc._AROUND = _KEEP[2] if on else 0.0
    pa._GROUND_TONE = _KEEP[3] if on else 0.0
    pa._GROUND_TWIGS = _KEEP[4] if on else 0.0


def _keep():
    from . import pareidolia as pa
    from . import pareidolia_crown as pc
    from . import pareidolia_widths as pw

    return pa._DARK_TWIGS, pw._LIMB_BUDGET, pc._AROUND, pa._GROUND_TONE, pa._GROUND_TWIGS


_KEEP = None


def main(argv=None) -> None:
    global _KEEP
    from .pareidolia import pareidolia_tree

    argv = list(argv or [])
    sizes = [int(v) for v in argv[0].split(",")] if argv else [300, 600]
    seeds = [int(v) for v in argv[1].split(",")] if len(argv) > 1 else [0]
    names = argv[2].split(",") if len(argv) > 2 else NAMES
    _KEEP = _keep()
    try:
        for name in names:
            for n in sizes:
                for seed in seeds:
                    img = picture(name, n, seed)
                    row = []
                    for on in (False, True):
                        _switch(on)
                        t0 = time.process_time()
                        t = pareidolia_tree(img, rng=seed)
                        dt = time.process_time() - t0
                        r = tone_rs(t)
                        out, solid = crown_shape(t)
                        ro = object_r(t)
                        row.append(f"r {r[0]:.3f} {r[1]:.3f} {r[2]:.3f} obj {ro:.3f} out {out:.2f} "
                                   f"solid {solid:.2f} {dt:4.1f}s")
                    print(f"{name:14s} {n:5d} {seed}  {row[0]}  ->  {row[1]}", flush=True)
    finally:
        _switch(True)


if __name__ == "__main__":
    main(sys.argv[1:])
