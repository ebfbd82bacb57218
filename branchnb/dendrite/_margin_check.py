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
Hubble deep field, and procedural ones (``edge_towers``: dark towers by the frame's sides,
``face``: a portrait). ``name@3:2`` crops a picture to that aspect (also 1:1, 2:3). Not a
test.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage

NAMES = ("coffee", "chelsea", "astronaut", "rocket", "camera", "coins", "immunohistochemistry",
         "horse", "hubble_deep_field", "edge_towers", "face")


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


def picture(spec: str, n: int, seed: int = 0) -> np.ndarray:
    """``name`` or ``name@aspect`` (``1:1``, ``3:2``, ``2:3``), long side ``n`` px."""
    import skimage.data as skd

    from ._pareidolia_sweep import face
    from ._strike_sweep import fit

    name, _, aspect = spec.partition("@")
    if name == "edge_towers":
        img = edge_towers(400, 1.5, seed)
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
