"""Measure: pareidolia crowns that keep a margin from the frame, before -> after.

``python -m branchnb.dendrite._margin_check [sizes] [seeds] [names]`` grows a pareidolia tree
with the defaults on each picture (long side ``size`` px) with the crown's margin
(``pareidolia_crown._MARGIN``) and the dear picture outside the crown
(``pareidolia._OFF_CROWN``) off and on, and prints: the share of the frame's left / right
edge rows and top edge columns whose 1 %-band holds ink (darker than 0.3), the ink's
closest margin from the left or right edge (share of the width), tone r inside the crown at
4 px blur, the share of the picture's high-contrast quarter (local contrast over 1 % of the
long side) inside the crown and the crown's area. Pictures: skimage's coffee, chelsea, the
astronaut, the rocket, the camera man, coins, immunohistochemistry, the horse silhouette, the
Hubble deep field, and procedural ones (:func:`blob_face`, :func:`tall`, :func:`landscape`,
a portrait ``_pareidolia_sweep.face``, :func:`low_wide`, :func:`edge_towers`: dark towers by
the frame's sides). ``name@3:2`` crops a picture to that aspect (also 1:1, 2:3). Not a
test.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage

NAMES = ("coffee", "chelsea", "astronaut", "rocket", "camera", "coins", "immunohistochemistry",
         "horse", "hubble_deep_field", "blob_face", "tall", "landscape", "face", "low_wide", "edge_towers")


def edge_towers(n: int = 300, aspect: float = 1.5, seed: int = 0) -> np.ndarray:
    """A procedural picture whose strongest edges lie by the frame's sides: a light ground
    darker downward with three dark towers, two of them 4 % of the width from the sides."""
    rng = np.random.default_rng(seed)
    h, w = int(round(n / aspect)), n
    yy, xx = np.mgrid[0:h, 0:w] / w
    lum = 0.75 - 0.25 * yy * aspect + 0.05 * np.sin(9 * xx + rng.uniform(0, 6))
    for x0 in (0.04, 0.5, 0.96):
        x0 += rng.uniform(-0.01, 0.01)
        lum = np.where((np.abs(xx - x0) < 0.025) & (yy * aspect > 0.1), 0.08, lum)
    lum = ndimage.gaussian_filter(lum, 0.6) + 0.03 * rng.standard_normal((h, w))
    return np.repeat(np.clip(lum, 0, 1)[..., None], 3, axis=2).astype(np.float32)


def _grey(img: np.ndarray, n: int, rng, noise: float = 0.02, blur: float = 0.003) -> np.ndarray:
    img = ndimage.gaussian_filter(img, blur * n) + noise * rng.standard_normal(img.shape)
    return np.repeat(np.clip(img, 0, 1)[..., None], 3, axis=2).astype(np.float32)


def blob_face(n: int = 400, seed: int = 0) -> np.ndarray:
    """A face-like blob layout filling a square frame: two dark eyes and a mouth."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:n, 0:n] / n
    img = 0.75 - 0.1 * yy
    for cx, cy, rx, ry in ((0.33, 0.38, 0.09, 0.07), (0.67, 0.38, 0.09, 0.07), (0.5, 0.72, 0.18, 0.05)):
        cx += rng.uniform(-0.02, 0.02)
        img = np.where(((xx - cx) / rx) ** 2 + ((yy - cy) / ry) ** 2 < 1, 0.1, img)
    return _grey(img, n, rng, 0.03, 0.004)


def tall(n: int = 400, seed: int = 0) -> np.ndarray:
    """A tall narrow dark subject with a spire on a light ground (2:3)."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:int(1.5 * n), 0:n] / n
    img = 0.85 - 0.1 * yy / 1.5 + 0.02 * np.sin(xx * 40)
    cx = 0.5 + rng.uniform(-0.04, 0.04)
    body = (np.abs(xx - cx) < 0.07 * (1 - 0.3 * (yy - 0.2))) & (yy > 0.15) & (yy < 1.45)
    img = np.where(body, 0.15 + 0.1 * np.sin(yy * 20), img)
    img = np.where((np.abs(xx - cx) < 0.02) & (yy > 0.05) & (yy <= 0.15), 0.2, img)
    return _grey(img, n, rng)


def landscape(n: int = 400, seed: int = 0) -> np.ndarray:
    """A wide landscape (2.2:1): sky, a hill line, dark tree clumps up to the sides."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:int(n / 2.2), 0:n] / n
    hill = 0.28 + 0.04 * np.sin(xx * 9 + rng.uniform(0, 6)) + 0.02 * np.sin(xx * 23)
    img = np.where(yy > hill, 0.45 + 0.2 * (yy - hill), 0.85 - 0.3 * yy)
    for x0 in rng.uniform(0.03, 0.97, 7):
        img = np.where(np.hypot((xx - x0) / 0.035, (yy - hill + 0.05) / 0.06) < 1, 0.12, img)
    return _grey(img, n, rng)


def low_wide(n: int = 400, seed: int = 0) -> np.ndarray:
    """A wide picture (3:2) whose subject sits low: a tall tower over dark shrubs."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:int(n / 1.5), 0:n] / n
    img = 0.8 - 0.15 * yy
    cx = 0.5 + rng.uniform(-0.05, 0.05)
    img = np.where((np.abs(xx - cx) < 0.03) & (yy > 0.12), 0.2, img)
    for x0 in rng.uniform(0.05, 0.95, 9):
        img = np.where(np.hypot((xx - x0) / 0.06, (yy - 0.6) / 0.05) < 1, 0.15 + 0.2 * rng.random(), img)
    return _grey(np.where(yy > 0.62, 0.35, img), n, rng, 0.03)


_PROCEDURAL = {"edge_towers": lambda s: edge_towers(400, 1.5, s), "blob_face": lambda s: blob_face(400, s),
               "tall": lambda s: tall(400, s), "landscape": lambda s: landscape(400, s),
               "low_wide": lambda s: low_wide(400, s)}


def picture(spec: str, n: int, seed: int = 0) -> np.ndarray:
    """``name`` or ``name@aspect`` (``1:1``, ``3:2``, ``2:3``), long side ``n`` px."""
    import skimage.data as skd

    from ._pareidolia_sweep import face
    from ._strike_sweep import fit

    name, _, aspect = spec.partition("@")
    if name in _PROCEDURAL:
        img = _PROCEDURAL[name](seed)
    elif name == "face":
        img = face(400, seed)
    else:
        img = np.asarray(getattr(skd, name)(), np.float32)
        img = img / 255.0 if img.max() > 1 else img
        img = np.repeat(img[..., None], 3, axis=2) if img.ndim == 2 else img[..., :3]
    if aspect:
        a, b = (float(v) for v in aspect.split(":"))
        h, w = img.shape[:2]
        if w / h > a / b:
            k = int(round(h * a / b))
            img = img[:, (w - k) // 2:(w - k) // 2 + k]
        else:
            k = int(round(w * b / a))
            img = img[(h - k) // 2:(h - k) // 2 + k]
    return fit(img, n)


def measures(t, shape) -> dict:
    """The edge bands' ink, the ink's side margin, tone r, the high-contrast share in the
    crown and the crown's area of a :class:`~branchnb.dendrite.pareidolia.PareidoliaTree`
    (``shape``: the picture's ``(H, W)``)."""
    from ..core import as_gray
    from ._twig_ends import tone_r

    hh, ww = shape
    ink = 1.0 - as_gray(t.render().image).astype(np.float64)[:hh] > 0.3
    crown = t.crown_on_canvas()[:hh]
    b = max(2, round(0.01 * min(hh, ww)))
    cols = np.flatnonzero(ink.any(axis=0))
    g = as_gray(t.image).astype(np.float64)[:hh]
    s = 0.01 * max(hh, ww)
    mu = ndimage.gaussian_filter(g, s)
    con = ndimage.gaussian_filter(np.sqrt(np.maximum(ndimage.gaussian_filter(g * g, s) - mu * mu, 0)), 2 * s)
    sal = con >= np.quantile(con, 0.75)
    return {"L": ink[:, :b].any(axis=1).mean(), "R": ink[:, -b:].any(axis=1).mean(),
            "T": ink[:b].any(axis=0).mean(), "margin": min(cols.min(), ww - 1 - cols.max()) / ww,
            "r4": tone_r(t, 4.0), "subject": (sal & crown).sum() / max(sal.sum(), 1),
            "area": crown.mean()}


def main(argv=None) -> None:
    from . import pareidolia as pa
    from . import pareidolia_crown as pc
    from .pareidolia import pareidolia_tree

    argv = list(argv or [])
    sizes = [int(v) for v in argv[0].split(",")] if argv else [300, 700]
    seeds = [int(v) for v in argv[1].split(",")] if len(argv) > 1 else [0]
    names = argv[2].split(",") if len(argv) > 2 else NAMES
    keep = pc._MARGIN, pa._OFF_CROWN
    try:
        for name in names:
            for n in sizes:
                for seed in seeds:
                    img = picture(name, n, seed)
                    row = []
                    for on in (False, True):
                        pc._MARGIN, pa._OFF_CROWN = keep if on else (0.0, 0.0)
                        m = measures(pareidolia_tree(img, rng=seed), img.shape[:2])
                        row.append("L/R/T {L:.2f}/{R:.2f}/{T:.2f} margin {margin:.3f} r4 {r4:.3f} "
                                   "subject {subject:.2f} area {area:.2f}".format(**m))
                    print(f"{name:22s} {n:5d} {seed}  {row[0]}  ->  {row[1]}", flush=True)
    finally:
        pc._MARGIN, pa._OFF_CROWN = keep


if __name__ == "__main__":
    main(sys.argv[1:])
