"""Measure: small inputs look like large ones (issue 25), with the defaults.

``python -m branchnb.dendrite._small_check [sizes] [seeds] [kinds]`` stylizes (``metaphor="plain"``)
the same object drawn at each width (``200,250,400,750,1500`` px by default) and prints, per kind
and size: the mean ink on the object over the 750-px result's (``ink``), the share of solid-ink
pixels (> 0.5) on the object over the 750-px share (``solid``), the ink of an 8-px band inside
the object's outline over the interior's, both shown at ``SHOW`` (``o/i``), and the process CPU
time over the 750-px run's in the same process (``cpu``). Kinds: a wobbly mid-grey blob
(``mid``), the blob with a 6/1000 dark outline and that fill (``outlined``), a light fill
(``light``) or a dark fill (``dark``), a left-to-right grey gradient blob (``gradient``), a shaded textured blob on a
noisy grey ground (``photo``), and two real pictures, the clip-art lizard and the maple-leaf
photo (``lizard``, ``maple``). Procedural shapes vary with the seed; the stylization's ``rng``
is the seed too. Not a test.
"""

from __future__ import annotations

import sys
import time

import numpy as np
from scipy import ndimage
from skimage.transform import resize

SHOW = (300, 400)
SIZES = (200, 250, 400, 750, 1500)
KINDS = ("mid", "outlined", "light", "dark", "gradient", "photo", "lizard", "maple")
_MASTER = 2000


def _shape(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    n, h = _MASTER, _MASTER * 3 // 4
    y, x = np.mgrid[0:h, 0:n] / n
    cx, cy = 0.5 + rng.uniform(-0.04, 0.04), 0.375 + rng.uniform(-0.03, 0.03)
    ax, ay = 0.33 * rng.uniform(0.85, 1.05), 0.24 * rng.uniform(0.85, 1.05)
    th = np.arctan2(y - cy, x - cx)
    rad = np.hypot((x - cx) / ax, (y - cy) / ay)
    ph = rng.uniform(0, 2 * np.pi, 3)
    return rad < 1 + 0.12 * np.sin(3 * th + ph[0]) + 0.06 * np.sin(7 * th + ph[1]) + 0.04 * np.sin(
        5 * th + ph[2])


def master(kind: str, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """The object drawn large (RGB float) and its mask."""
    if kind in ("lizard", "maple"):
        from ..core.image import as_gray, as_rgb

        if kind == "lizard":
            import cv2

            im = cv2.imread("/work/shared/data/skeleton_objects/lizard.png", -1).astype(np.float32) / 255
            rgb = im[..., 2::-1] * im[..., 3:] + (1 - im[..., 3:])
            return rgb, im[..., 3] > 0.5
        from .. import data

        img = as_rgb(data.load("maple_leaf_03"))
        return img, ndimage.binary_fill_holes(as_gray(img) < 0.9)
    body = _shape(seed)
    h, n = body.shape
    y, x = np.mgrid[0:h, 0:n] / n
    if kind == "mid":
        img = np.where(body, 0.45, 1.0)
    elif kind in ("outlined", "light", "dark"):
        img = np.where(body, {"outlined": 0.45, "light": 0.7, "dark": 0.15}[kind], 1.0)
        img[body & ~ndimage.binary_erosion(body, iterations=12)] = 0.05
    elif kind == "gradient":
        img = np.where(body, 0.15 + 0.7 * np.clip((x - 0.15) / 0.7, 0, 1), 1.0)
    elif kind == "photo":
        rng = np.random.default_rng(seed + 100)
        tex = ndimage.gaussian_filter(rng.standard_normal((h // 8, n // 8)), 2.0)
        tex = resize(tex / tex.std(), (h, n), order=1)
        shade = 0.25 + 0.35 * np.hypot(x - 0.4, y - 0.25) / 0.5
        ground = 0.82 + 0.04 * tex
        img = np.where(body, shade + 0.06 * tex, ground)
        img = ndimage.gaussian_filter(img, 3.0)
    else:
        raise ValueError(f"unknown kind {kind!r}")
    img = np.clip(img, 0, 1).astype(np.float32)
    return np.repeat(img[..., None], 3, axis=2), body


def at_width(img: np.ndarray, mask: np.ndarray, width: int) -> tuple[np.ndarray, np.ndarray]:
    h, w = mask.shape
    shape = (round(h * width / w), width)
    small = resize(img, (*shape, 3), order=1, anti_aliasing=True).astype(np.float32)
    return small, resize(mask.astype(float), shape, order=1, anti_aliasing=True) > 0.5


def stats(kind: str, width: int, seed: int = 0, masters=None) -> dict:
    from . import stylize

    big, mask = masters[(kind, seed)] if masters is not None else master(kind, seed)
    img, m = at_width(big, mask, width)
    t = time.process_time()
    out = stylize(img, rng=seed, metaphor="plain").rendering.image
    cpu = time.process_time() - t
    ink = 1.0 - np.asarray(out, np.float32).mean(axis=2)
    show = (SHOW[0], round(SHOW[0] * mask.shape[1] / mask.shape[0]))
    inks = resize(ink, show, order=1, anti_aliasing=True)
    ms = resize(mask.astype(float), show, order=1, anti_aliasing=True) > 0.5
    inner = ndimage.binary_erosion(ms, iterations=8)
    return dict(ink=float(ink[m].mean()), solid=float((ink[m] > 0.5).mean()),
                band=float(inks[ms & ~inner].mean()), inner=float(inks[inner].mean()), cpu=cpu,
                out=out, inkS=inks)


def main(sizes=SIZES, seeds=(0,), kinds=KINDS) -> None:
    from . import stylize

    stylize(np.ones((40, 40)), rng=0)  # compile outside the timings
    for kind in kinds:
        for seed in seeds if kind not in ("lizard", "maple") else (0,):
            masters = {(kind, seed): master(kind, seed)}
            ref = stats(kind, 750, seed, masters)
            cells = []
            for w in sizes:
                r = ref if w == 750 else stats(kind, w, seed, masters)
                cells.append(f"{w}: ink {r['ink'] / ref['ink']:.2f} solid {r['solid'] / max(ref['solid'], 1e-9):.2f} "
                             f"o/i {r['band'] / r['inner']:.2f} cpu {r['cpu'] / ref['cpu']:.2f}")
            print(f"{kind:8s} s{seed} | " + " | ".join(cells), flush=True)


if __name__ == "__main__":
    a = sys.argv[1:]
    main(tuple(int(v) for v in a[0].split(",")) if a else SIZES,
         tuple(int(v) for v in a[1].split(",")) if len(a) > 1 else (0,),
         tuple(a[2].split(",")) if len(a) > 2 else KINDS)
