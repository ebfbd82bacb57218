"""Pareidolia trees, widths (paper, section 9, "thickness"; beyond it, the tone passes).

The pipe model with the importance emphasis, then inside the crown a tone match of
the widths to the picture (on the lattice, then on the drawing at the output's size),
with tapered twig ends. Split from :mod:`branchnb.dendrite.pareidolia`, which grows the
tree; see its docstring for the measurements behind each step.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy import ndimage

from .dendrite import Dendrite, _accumulate_up
from .thickness import rolling_importance

if TYPE_CHECKING:
    from .pareidolia import PareidoliaParams

def _shrink(a: np.ndarray, f: int) -> np.ndarray:
    """Mean over ``f x f`` blocks (the last partial blocks dropped)."""
    if f == 1:
        return a
    h, w = (a.shape[0] // f) * f, (a.shape[1] // f) * f
    return a[:h, :w].reshape(h // f, f, w // f, f).mean(axis=(1, 3))



def _taper_profile(dist: np.ndarray, taper: float) -> np.ndarray:
    """Width factor along a twig's last ``taper`` px: ``_TIP`` at the tip, 1 from ``taper`` on."""
    return _TIP + (1.0 - _TIP) * np.sqrt(np.clip(dist / taper, 0.0, 1.0))


_TONE_ROUNDS = 3
_TIP = 0.3  # a twig's width at its very end, as a share of its width `taper` px back


def _taper_ends(d: Dendrite, width: np.ndarray, dist: np.ndarray, taper: float) -> np.ndarray:
    """Twig ends that taper whatever widths they were given: within ``taper`` px of a
    branch's end, the width is at most the width ``taper`` px back times
    :func:`_taper_profile` (a tone match that thickens a dark region's twigs widens their
    ends too, and round caps then read as dots)."""
    near = np.flatnonzero(dist < taper)
    if taper <= 0 or near.size == 0:
        return width
    body = near.copy()  # walk up to the first node at least `taper` px from the end
    for _ in range(4 * int(np.ceil(taper)) + 8):  # the nearest tip may switch on the way
        up = d.parent[body]
        move = (dist[body] < taper) & (up >= 0)
        if not move.any():
            break
        body[move] = up[move]
    out = width.copy()
    out[near] = np.minimum(width[near], width[body] * _taper_profile(dist[near], taper))
    return out


_REFINE_SIGMA = 3.0  # px of the output: a little finer than the 4 px at which tone is judged
_REFINE_GAIN = 0.7  # exponent on the correction (damped: neighbours share the blur)


def _refine_tone(d: Dendrite, dark: np.ndarray, bounds: dict, s: float,
                 p: PareidoliaParams) -> Dendrite:
    """Tone match on the drawing itself, at the output's resolution (beyond the paper).

    ``p.refine`` times: draw the coverage of the strokes as they will be rendered
    (smoothed, anti-aliased, overlapping), blur it and the picture's darkness over
    ``_REFINE_SIGMA`` output px, and scale the width of every crown node by the ratio
    (damped, at most 2x either way), within the lattice pass's floor and cap
    (``s`` output px per lattice px; the limbs keep their floor) so limbs stay limbs;
    the crown's mean ink stays.
    The lattice pass matches tone over ``tone_sigma`` lattice px, 10 output px on a
    2000-px picture planned at 1024, and cannot see that round caps, overlaps and the
    smoothing put ink elsewhere than its model; this pass can.
    """
    from ..core.render import _rasterise

    inside = bounds["inside"]
    if not inside.any():
        return d
    width = 2.0 * d.radius
    lo = np.minimum(p.tip_width * 0.4 * s, width)
    # limbs (a floor of at least 0.3 x the trunk's width at the fork) keep the lattice
    # pass's floor; twigs may thin to the tip width (the lattice floor kept the twigs near
    # the fork at their pipe + emphasis width: tone r at 4 px blur 0.68 instead of 0.75 on
    # flat coloured objects at 2000 px; half the floor on the limbs too gave 0.79, but the
    # limbs faded into the crown)
    f = bounds["floor"]
    floor = np.minimum(np.where(f >= 0.3 * bounds["cap"].max(), f, 0.0) * s, width)
    cap = np.maximum(bounds["cap"] * s, width)
    smooth = 3  # render()'s default
    h, w = d.shape
    at = np.rint(d.smoothed_points(smooth)).astype(int)
    row, col = np.clip(at[:, 1], 0, h - 1), np.clip(at[:, 0], 0, w - 1)
    target = ndimage.gaussian_filter(np.asarray(dark, np.float64), _REFINE_SIGMA)[row, col]
    pts = d.smoothed_points(smooth)
    has = np.flatnonzero(d.parent >= 0)
    par = d.parent[has]
    gain = None
    for _ in range(p.refine):
        # the segments render() draws (each branch's consecutive nodes = every node and
        # its parent), packed directly: checking ~50,000 polylines one by one took longer
        # than drawing them
        r = 0.5 * width
        segs = np.column_stack([pts[par], r[par], pts[has], r[has]])
        cov = np.zeros((h, w), np.float32)
        _rasterise(segs, np.zeros(len(segs), np.int64), h, w, cov, np.full((h, w), -1, np.int64))
        have = ndimage.gaussian_filter(cov.astype(np.float64), _REFINE_SIGMA)[row, col]
        if gain is None:  # keep the crown's ink: only where it goes changes
            gain = have[inside].mean() / max(target[inside].mean(), 1e-6)
        ratio = np.clip((gain * target + 1e-3) / (have + 1e-3), 0.5, 2.0) ** _REFINE_GAIN
        width = np.where(inside, np.clip(width * ratio, np.maximum(lo, floor), cap), width)
    if p.taper > 0:
        width = _taper_ends(d, width, bounds["dist"] * s, p.taper * s)
    return d.with_radius(width / 2)


def _tone_matcher(d: Dendrite, dark: np.ndarray, sigma: float, strength: float,
                  black: float = 0.7):
    """:func:`~branchnb.dendrite.thickness.tone_thickness` for repeated use on one tree:
    the target is blurred once, and the blurs run on a grid ``f = sigma // 2.5`` times
    coarser (block sums; a Gaussian of ``sigma / f``), 4-8x faster on a grown lattice
    for the same widths within a few per cent. Returns ``match(width, lo, hi, iterations)``."""
    h, w = d.shape
    f = max(1, int(sigma // 2.5))
    hs, ws = -(-h // f), -(-w // f)
    ys, xs = np.divmod(d.nodes, w)
    cell = (ys // f) * ws + xs // f
    pad = np.pad(np.clip(dark, 0.0, 1.0), ((0, hs * f - h), (0, ws * f - w)), mode="edge")
    target = ndimage.gaussian_filter(_shrink(pad, f), sigma / f)
    need = -np.log1p(-np.clip(black * target, 0.0, 0.95)).ravel()[cell]
    has = d.parent >= 0
    seg = np.zeros(d.n_nodes)
    step = d.points[has] - d.points[d.parent[has]]
    seg[has] = np.hypot(step[:, 0], step[:, 1])
    tiny = 1e-4

    def match(width, lo, hi, iterations=4):
        width = np.asarray(width, np.float64)
        for _ in range(iterations):
            ink = np.bincount(cell, weights=width * seg, minlength=hs * ws).reshape(hs, ws)
            have = ndimage.gaussian_filter(ink / (f * f), sigma / f).ravel()[cell]
            width = np.clip(width * ((need + tiny) / (have + tiny)) ** strength, lo, hi)
        return width

    return match


def _stretch(dark: np.ndarray, crown: np.ndarray, contrast: float) -> np.ndarray:
    """The darkness stretched so its 1st-99th percentiles in the crown span [0, 1]
    (gain at most 5), blended with the original by ``contrast``."""
    if contrast <= 0 or not crown.any():
        return dark
    lo, hi = np.percentile(dark[crown], [1.0, 99.0])
    full = np.clip((dark - lo) / max(hi - lo, 0.2), 0.0, 1.0)
    return ((1.0 - contrast) * dark + contrast * full).astype(np.float32)


def _thickness(d: Dendrite, p: PareidoliaParams, imp, dark, crown, n_trunk: int,
               bounds: dict | None = None) -> Dendrite:
    """Pipe model + importance emphasis; tone-matched under a limb cap inside the crown;
    tapered twig ends."""
    leaf = np.zeros(d.n_nodes)
    leaf[d.tips] = 1.0
    tips = np.maximum(_accumulate_up(d.parent, leaf), 1.0)
    width = p.tip_width + p.pipe * np.sqrt(tips - 1.0) + p.increment * (p.iterations - d.iteration)
    dist = d.tip_distance()
    if p.thickness == "branch":
        return d.with_radius(_taper_ends(d, width, dist, p.taper) / 2)
    emph = rolling_importance(d, imp, p.window)
    ref = max(float(np.percentile(imp, 99.0)), 1e-3)
    width = width + p.emphasis * np.clip(emph / ref, 0, 1) ** 1.5
    inside = crown.ravel()[d.nodes]
    inside[:n_trunk] = False  # the trunk keeps its pipe width up to the fork
    if p.tone <= 0 or not inside.any():
        return d.with_radius(_taper_ends(d, width, dist, p.taper) / 2)
    # limb cap: the fork's pipe width, thinning to max_width along the path from the fork
    arc = d.arc_depth()
    fork_arc = arc[n_trunk - 1] if n_trunk > 0 else 0.0
    from_fork = np.maximum(arc - fork_arc, 0.0)
    if p.taper > 0:
        # taper before the tone match too, which then puts the ink back along the
        # twigs instead of losing it
        width = width * _taper_profile(dist, p.taper)
    cap = np.maximum(p.max_width, width * np.exp(-from_fork / p.limb_length))
    floor = np.minimum(width * np.exp(-from_fork / p.limb_length), cap)
    w_tone = width
    match = _tone_matcher(d, dark, p.tone_sigma, p.tone)
    for _ in range(_TONE_ROUNDS if p.taper > 0 else 1):
        # the tone match thickens a dark region's twig ends as much as their bodies (more:
        # less ink around an end): taper them again and match again, so the ink taken
        # from the ends goes back into the bodies
        w_tone = np.clip(match(w_tone, p.tip_width * 0.4, float(cap.max())), floor, cap)
        if p.taper > 0:
            w_tone = _taper_ends(d, w_tone, dist, p.taper)
    # a slight flare at the foot of the trunk
    height = d.points[:, 1].max() - d.points[:, 1]
    flare = 1.0 + 0.35 * np.clip(1.0 - height / (0.12 * d.shape[0]), 0.0, 1.0) ** 2
    flare[n_trunk:] = 1.0
    out = np.where(inside, w_tone, width * flare)
    if p.taper > 0:
        out = _taper_ends(d, out, dist, p.taper)
    if bounds is not None:  # what the output-resolution pass may change, and how far
        bounds.update(inside=inside, floor=floor, cap=cap, dist=dist)
    return d.with_radius(out / 2)
