"""Issue-23 figures of hub examples' synthesized images (branching116): bars across the arms and
stray line colour round free ends, example vs output.

``python -m branchnb.branching._hub_image_check [CASES] [PNG_DIR]`` (``CASES``: ``kind:size:seed,...``
of :func:`._radial_examples.radial_example`; default the ten below) extracts, fits and synthesizes
each with the defaults and prints:

- ``seam``: along every branch of median radius >= 1.5 px (away from its ends, 1.5 hub radii from a
  hub and 3 radii from another branch's start) the brightness averaged across the middle of the line
  every pixel, and the share of its length where it changes over 4 px by more than ``T`` (twice the
  example's own 95th percentile, at least 0.08; both over the line contrast), example / synthesized;
- ``tip``: per free end, the line contrast in a disc of max(6, 4 r) px farther than r + 2.5 px from
  every line, over pi r^2 (0: a clean tip), median and 90th percentile, example / synthesized.

branching116 (main -> now, the ten cases): seam 0.08-0.20 -> 0.00-0.02 on the eight with bars (example
0.005-0.026; fragments from the example's hub disc, :func:`.radial._off_hubs`); tip median 0.20-1.13 ->
0.09-0.25, 90th percentile 0.57-2.47 -> 0.19-1.91 (example 0.13-0.90 / 0.27-2.16: its traced tips stop
short of the drawn ones; :data:`.gap_completion.HUB_LINE_MARGIN`).

Also (branching119):

- ``speck``: blobs of the image (3 x 3 mean) brighter or darker than 99.9 % of the example's by 0.02
  (white sparkles at tips and junctions), example / synthesized;
- ``twig``: over the branches of median radius < 2 px, the 10th percentile of their median centre-line
  contrast (1: the example's line colour; 1.5 hub radii from a hub), example / synthesized.

branching119 (main -> now): speck neuron_dark 384 s1 14 -> 4, neuron_dark 512 s0 6 -> 2, neuron_dark
768 s2 34 -> 13, coral 384 s1 4 -> 1, coral 512 s2 6 -> 2, coral_dark 512 s1 14 -> 4, neuron 256 s2
4 -> 0 (example 0 on all), crack_bright 384 s0 20 -> 15 (example 1); twig neuron_dark 384 s1 0.49 ->
0.53 (example 0.74), others within 0.03; tip 90th percentile neuron_dark 384 s1 0.75 -> 0.50, coral
384 s1 1.91 -> 1.77; seam within 0.003, neuron_dark 384 s1 0.006 -> 0.009 (example 0.019). The
fragments' correction no longer takes its boundary from the edges of older lines that the fragment
has as ground (:data:`.gap_completion.HUB_SEAM_MISMATCH`).

Also (branching120):

- ``bins``: per radius bin of :data:`BINS` (0.5-0.75, 0.75-1, 1-1.5 px) the 10th percentile over the
  branches of that median radius of their median peak contrast across the centre line, example /
  synthesized.

branching120: ``twig`` mixes radii. The example's lines of r 0.5-0.75 (its 1-px drawn twigs) have a
contrast of about 0.5, those of 0.75-1 about 0.9; the synthesized structures have more of the thinnest
twigs (neuron_dark 384 s1: 713 px of r < 0.75 against the example's 252), so ``twig`` stays 0.53
(example 0.74) while each bin is near the example's (0.48 / 0.56, 0.82 / 0.95, 0.99 / 0.97). Within a
bin the fragments' source radius decided (:func:`.fragment_choice._thin_penalty`, figures there).
"""
# ruff: noqa: E702
from __future__ import annotations

import sys

import cv2
import numpy as np
from scipy import ndimage as ndi

from ._radial_examples import radial_example

CASES = ("coral:384:1,neuron_dark:384:1,coral:256:0,coral:512:2,coral_dark:768:0,neuron_dark:256:2,"
         "neuron:512:0,neuron_dark:512:0,crack:512:1,crack_bright:384:0")


def _resample(b, step: float = 1.0):
    p, r = b.points, b.thickness
    d = np.r_[0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
    t = np.arange(0, max(d[-1], 1e-6), step)
    return np.c_[np.interp(t, d, p[:, 0]), np.interp(t, d, p[:, 1])], np.interp(t, d, r)


def along_jumps(gray: np.ndarray, s, hubs) -> np.ndarray:
    """Changes over 4 px of the brightness along the branches (see the module docstring)."""
    out = []
    H, W = gray.shape
    for b in s.branches:
        q, r = _resample(b)
        if len(q) < 12 or np.median(r) < 1.5:
            continue
        tang = np.gradient(q, axis=0); tang /= np.maximum(np.hypot(*tang.T), 1e-6)[:, None]
        nrm = np.c_[-tang[:, 1], tang[:, 0]]
        across = [q + nrm * (f * r)[:, None] for f in (-0.5, -0.25, 0, 0.25, 0.5)]
        prof = np.mean([ndi.map_coordinates(gray, [a[:, 1], a[:, 0]], order=1, mode="nearest") for a in across], 0)
        keep = (q[:, 0] > 2) & (q[:, 1] > 2) & (q[:, 0] < W - 3) & (q[:, 1] < H - 3)
        edge = int(np.ceil(max(3, 2 * r.max())))
        keep[:edge] = False; keep[-edge:] = False
        for hx, hy, hr in hubs:
            keep &= np.hypot(q[:, 0] - hx, q[:, 1] - hy) > 1.5 * hr
        for c in s.branches:
            if c is not b:
                near = 3 * max(c.thickness[0], r.mean()) + 2
                keep &= np.hypot(q[:, 0] - c.points[0, 0], q[:, 1] - c.points[0, 1]) > near
        k = keep[2:-2] & keep[4:] & keep[:-4]
        out.append(np.abs(prof[4:] - prof[:-4])[k])
    return np.concatenate(out) if out else np.zeros(0)


def tip_stray(gray: np.ndarray, s, ink: float, ground: float) -> np.ndarray:
    """Per free end: stray line contrast round it over pi r^2 (see the module docstring)."""
    from .skeleton_map import SkeletonMap

    H, W = gray.shape
    c = np.clip((gray - ground) / (ink - ground), 0, 1) * ~SkeletonMap(s, 1.0).pixel_map((H, W)).core(1.0, 2.5)
    yy, xx = np.mgrid[:H, :W]
    out = []
    for i, b in enumerate(s.branches):
        (x, y), r = b.points[-1], float(b.thickness[-1])
        if not s.children(i) and 8 < x < W - 9 and 8 < y < H - 9:
            out.append(float(c[np.hypot(xx - x, yy - y) <= max(6.0, 4 * r)].sum()) / (np.pi * max(r, 1.0) ** 2))
    return np.array(out) if out else np.zeros(1)


def specks(out: np.ndarray, ex: np.ndarray) -> int:
    """Blobs of ``out`` (3 x 3 mean) brighter or darker than 99.9 % of ``ex`` by 0.02 (grey images)."""
    hi, lo = np.percentile(cv2.blur(ex, (3, 3)), [99.9, 0.1])
    sm = cv2.blur(out, (3, 3))
    return cv2.connectedComponents(((sm > hi + 0.02) | (sm < lo - 0.02)).astype(np.uint8))[0] - 1


def twig_contrast(gray: np.ndarray, s, ink: float, ground: float, hubs) -> float:
    """10th percentile of the thin branches' median centre-line contrast (see the module docstring)."""
    H, W = gray.shape
    out = []
    for b in s.branches:
        q, r = _resample(b)
        q, r = q[3:-3], r[3:-3]
        if len(q) < 2 or np.median(r) >= 2.0:
            continue
        ok = (q[:, 0] > 2) & (q[:, 1] > 2) & (q[:, 0] < W - 3) & (q[:, 1] < H - 3)
        for hx, hy, hr in hubs:
            ok &= np.hypot(q[:, 0] - hx, q[:, 1] - hy) > 1.5 * hr
        if ok.sum() >= 4:
            v = ndi.map_coordinates(gray, [q[ok, 1], q[ok, 0]], order=1)
            out.append(float(np.median((v - ground) / (ink - ground))))
    return float(np.percentile(out, 10)) if out else float("nan")


#: radius bins (px) of :func:`radius_bins`: the example's 1-px drawn lines, its 2-px lines, 3-px lines
BINS = ((0.5, 0.75), (0.75, 1.0), (1.0, 1.5))


def radius_bins(gray: np.ndarray, s, ink: float, ground: float, hubs) -> list[float]:
    """Per bin of :data:`BINS`: the 10th percentile over the branches whose median radius falls in it of
    their median peak contrast (largest within 1 px across the centre line; 1.5 hub radii from a hub)."""
    H, W = gray.shape
    per: list[list[float]] = [[] for _ in BINS]
    for b in s.branches:
        q, r = _resample(b)
        q = q[2:-2]
        if len(q) < 4:
            continue
        ok = (q[:, 0] > 3) & (q[:, 1] > 3) & (q[:, 0] < W - 4) & (q[:, 1] < H - 4)
        for hx, hy, hr in hubs:
            ok &= np.hypot(q[:, 0] - hx, q[:, 1] - hy) > 1.5 * hr
        if ok.sum() < 4:
            continue
        tang = np.gradient(q, axis=0); tang /= np.maximum(np.hypot(*tang.T), 1e-6)[:, None]
        nrm = np.c_[-tang[:, 1], tang[:, 0]][ok]
        across = np.array([ndi.map_coordinates(gray, [(q[ok] + f * nrm)[:, 1], (q[ok] + f * nrm)[:, 0]], order=1)
                           for f in np.linspace(-1, 1, 9)])
        pk = across.min(0) if ink < ground else across.max(0)
        c = float(np.median((pk - ground) / (ink - ground)))
        for i, (lo, hi) in enumerate(BINS):
            if lo <= np.median(r) < hi:
                per[i].append(c)
    return [float(np.percentile(v, 10)) if v else float("nan") for v in per]


def case(kind: str, size: int, seed: int, png: str | None = None) -> str:
    from . import extract_structure, fit_model, synthesize_image, synthesize_structure

    rgb, _centre, lines, _hubs = radial_example(kind, size, seed)
    s = extract_structure(rgb)
    res = synthesize_structure(fit_model(s), rng=seed)
    im = np.asarray(synthesize_image(rgb, s, res, rng=seed).image)[..., :3]
    g, gi = rgb.mean(-1), im.mean(-1)
    ink = float(np.median(g[lines]))
    ground = float(np.median(g[~(cv2.dilate(lines.astype(np.uint8), np.ones((9, 9), np.uint8)) > 0)]))
    C = abs(ink - ground)
    je = along_jumps(g, s, list(getattr(s, "hubs", None) or [])) / C
    jo = along_jumps(gi, res.structure, list(getattr(res.structure, "hubs", None) or [])) / C
    T = max(0.08, 2 * float(np.percentile(je, 95))) if len(je) else 0.08
    te, to = tip_stray(g, s, ink, ground), tip_stray(gi, res.structure, ink, ground)
    if png:
        cv2.imwrite(f"{png}/{kind}_{size}_{seed}.png",
                    (np.clip(np.concatenate([rgb, im], 1), 0, 1)[..., ::-1] * 255).astype(np.uint8))
    share = lambda j: float((j > T).mean()) if len(j) else 0.0  # noqa: E731
    return (f"{kind:13s} {size:5d} s{seed} T {T:.3f} seam {share(je):.3f}/{share(jo):.3f} "
            f"tip {np.median(te):.2f}/{np.median(to):.2f} "
            f"tip90 {np.percentile(te, 90):.2f}/{np.percentile(to, 90):.2f} "
            f"speck {specks(g, g)}/{specks(gi, g)} "
            f"twig {twig_contrast(g, s, ink, ground, list(getattr(s, 'hubs', None) or [])):.2f}/"
            f"{twig_contrast(gi, res.structure, ink, ground, list(getattr(res.structure, 'hubs', None) or [])):.2f} "
            "bins " + " ".join(f"{a:.2f}/{b:.2f}" for a, b in zip(
                radius_bins(g, s, ink, ground, list(getattr(s, "hubs", None) or [])),
                radius_bins(gi, res.structure, ink, ground, list(getattr(res.structure, "hubs", None) or [])))))


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    png = argv[1] if len(argv) > 1 else None
    for c in (argv[0] if argv and argv[0] != "-" else CASES).split(","):
        kind, size, seed = c.split(":")
        print(case(kind, int(size), int(seed), png), flush=True)


if __name__ == "__main__":
    main()
