"""Measure: pareidolia crowns on wide photos and dark photos that read, before -> after.

``python -m branchnb.dendrite._dome_check [sizes] [seeds] [names]`` grows a pareidolia tree
with the defaults on each picture (long side ``size`` px) with the domed crown
(``pareidolia_crown._DOME``) and the dark photos' tone map (``pareidolia._TONE_MEAN``) off
and on, and prints: the share of the crown's width whose top lies within 1 % of its height
of its top (``flat``: a crown cut flat by the frame), the drop of its top at 1/6 and 5/6 of
its width (share of the frame's height, ``dome``) and tone r inside the crown at 2 / 4 / 8
px blur. Pictures: skimage's coffee, chelsea, the astronaut cropped to 3:2, the rocket (a
night photo), the camera man, a procedural portrait (4:5), the Hubble deep field, coins and
the astronaut darkened (gamma 2.2, half exposure). Not a test.
"""

from __future__ import annotations

import sys

import numpy as np

NAMES = ("coffee", "chelsea", "astro_wide", "rocket", "camera", "face", "hubble", "coins",
         "astro_dark")


def picture(name: str, n: int) -> np.ndarray:
    """One of :data:`NAMES`, float32 RGB with its long side ``n`` px."""
    import skimage.data as skd

    from ._pareidolia_sweep import face
    from ._strike_sweep import fit

    if name == "face":
        return fit(face(400, 0), n)
    if name == "astro_wide":
        img = skd.astronaut()[60:400]
    elif name == "astro_dark":
        img = (skd.astronaut() / 255.0) ** 2.2 * 0.5
    elif name == "hubble":
        img = skd.hubble_deep_field()
    else:
        img = getattr(skd, name)()
    img = np.asarray(img, np.float32)
    if img.max() > 1:
        img = img / 255.0
    if img.ndim == 2:
        img = np.repeat(img[..., None], 3, axis=2)
    return fit(img[..., :3], n)


def top_shape(c: np.ndarray) -> tuple[float, float]:
    """(share of the crown's columns whose top is within 1 % of its height of its top, the
    mean drop of its top at 1/6 and 5/6 of its width as a share of the frame's height)."""
    cols = np.flatnonzero(c.any(axis=0))
    top = np.argmax(c[:, cols], axis=0)
    bot = c.shape[0] - 1 - np.argmax(c[::-1][:, cols], axis=0)
    near = float((top <= top.min() + max(1.0, 0.01 * (bot.max() - top.min() + 1))).mean())
    n = len(cols)
    return near, float((top[[n // 6, 5 * n // 6]] - top.min()).mean() / c.shape[0])


def main(argv=None) -> None:
    from . import pareidolia as pa
    from . import pareidolia_crown as pc
    from ._twig_ends import tone_r

    argv = list(argv or [])
    sizes = [int(v) for v in argv[0].split(",")] if argv else [300, 700]
    seeds = [int(v) for v in argv[1].split(",")] if len(argv) > 1 else [0]
    names = argv[2].split(",") if len(argv) > 2 else NAMES
    keep = pc._DOME, pa._TONE_MEAN
    try:
        for name in names:
            for n in sizes:
                img = picture(name, n)
                for seed in seeds:
                    row = []
                    for on in (False, True):
                        pc._DOME, pa._TONE_MEAN = keep if on else (0.0, 0.0)
                        t = pa.pareidolia_tree(img, rng=seed)
                        flat, drop = top_shape(t.crown_on_canvas())
                        r = [tone_r(t, s) for s in (2.0, 4.0, 8.0)]
                        row.append(f"flat {flat:.2f} dome {drop:.2f} r {r[0]:.3f} {r[1]:.3f} {r[2]:.3f}")
                    print(f"{name:11s} {img.shape[1]:4d}x{img.shape[0]:<4d} {seed}  {row[0]}  ->  {row[1]}",
                          flush=True)
    finally:
        pc._DOME, pa._TONE_MEAN = keep


if __name__ == "__main__":
    main(sys.argv[1:])
