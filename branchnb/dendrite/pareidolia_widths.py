"""Pareidolia trees, widths (paper, section 9, "thickness"; beyond it, the tone passes).

The pipe model with the importance emphasis, then inside the crown a tone match of
the widths to the picture (on the lattice, then on the drawing at the output's size),
with tapered twig ends. Split from :mod:`branchnb.dendrite.pareidolia`, which grows the
tree; see its docstring for the measurements behind each step.

Limbs narrow in the lighter parts of the crown's own range of tone (beyond the paper,
``pareidolia_widths._LIMB_RELATIVE``): on a picture dark all over they kept nearly
their full pipe width, and on the rocket photo at 600 px the 3 px round the limbs (7 %
of the crown) held 25-30 % of the tone error. Tone r at 4 px blur on a portrait, the
camera man, a cat, a cup, the rocket, a maple leaf, a horse and a clock at 300 / 600 px
unchanged (within 0.001) but the rocket 0.803 / 0.601 -> 0.813 / 0.610; a procedural
night sky 0.735 / 0.726 -> 0.752 / 0.742 (seeds 0 / 1). The rest of the limbs' excess
ink (limb cores +0.15 darker than the fitted tone) is their pipe width and the trunk's
entry into the crown; narrowing them further (``_LIMB_LIGHT`` 0.15, the base ramp over
0.1 instead of 0.25 of ``limb_length``) moved r by <= 0.008.

The limbs' ink budgeted against the tone (beyond the paper, ``_LIMB_BUDGET``): the output-
size pass held every limb at its lattice floor (``limb_width`` or its pipe width), so where
limbs crossed a crown darker than they could leave room for (the rocket's night sky) their
4-px band held a third of the tone error. Past ``_LIMB_SPAN`` of ``limb_length`` from the
fork that floor now falls (the pipe width beyond ``limb_width`` fully, ``limb_width`` itself
to ``_LIMB_MIN`` of it) and the pass narrows a limb where the drawing is darker than the
picture; near the fork and on the blank ground of a crown round an object the limbs and the
trunk keep their widths. Only on a picture dark all over (the crown's mean darkness from
0.6, fully from 0.7): on a portrait the limbs narrowed to a twig's width in the light face
and no longer reached into the crown (reach 0.76 -> 0.00). Figures in
:mod:`~branchnb.dendrite.pareidolia`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numba
import numpy as np
from scipy import ndimage

from .dendrite import Dendrite, _accumulate_up
from .thickness import rolling_importance

if TYPE_CHECKING:
    from .pareidolia import PareidoliaParams

def _soft_cap(x: np.ndarray, cover) -> np.ndarray:
    """``x`` (an ink coverage to aim at) below ``0.6 cover`` as it is, above it
    bending smoothly (tanh) toward ``cover``, which it never reaches: darker stays
    darker, but a black region keeps gaps between its twigs. ``cover >= 1``: ``x``.
    ``cover`` may be an array (one per value of ``x``: small features get more)."""
    x = np.asarray(x, np.float64)
    cover = np.asarray(cover, np.float64)
    if np.all(cover >= 1.0):
        return x
    knee = 0.6 * cover
    span = np.maximum(cover - knee, 1e-9)
    capped = np.where(x <= knee, x, knee + span * np.tanh((x - knee) / span))
    return np.where(cover >= 1.0, x, capped)


#: Small dark features (eyes, a mouth, nostrils: narrower than ``_FEATURE_SPAN`` twig
#: spacings or ``_FEATURE_SIZE`` of the crown) may be drawn up to solid ink, by twigs
#: as short as ``_FEATURE_ASPECT`` times their width (beyond the paper).
_FEATURE_SPAN = 2.0
_FEATURE_SIZE = 0.1  # ... or than this share of the crown's size (its area's root)
_FEATURE_FULL = 0.25  # a feature this much darker than around it may be solid ink


def _features(dark: np.ndarray, spacing: float, size: float = 0.0) -> np.ndarray:
    """How much darker than its surroundings each pixel of a small dark feature is:
    the white top-hat of ``dark`` with a square ``_FEATURE_SPAN x spacing`` px wide
    (a feature narrower than that vanishes under the opening), in [0, 1].

    Beyond the paper: twigs ``spacing`` px apart draw a feature narrower than their
    spacing as a twig or two crossing it, or as its outline, and the tone match over a
    blur of a few spacings spreads its darkness over the face around it (a
    portrait's eyes at 0.3-0.4 of the picture's contrast at 4 px blur).
    """
    from skimage.morphology import reconstruction

    k = max(3, int(round(max(_FEATURE_SPAN * spacing, _FEATURE_SIZE * size))) | 1)
    a = np.asarray(dark, np.float64)
    opened = ndimage.grey_opening(a, size=(k, k), mode="nearest")
    # by reconstruction: a thin part of a large dark region (the hair round a light face,
    # joined to a dark coat) grows back from the region and is no feature
    opened = reconstruction(np.minimum(opened, a), a, method="dilation")
    return np.clip(ndimage.gaussian_filter(a - opened, 0.5), 0.0, 1.0)


def _feature_cover(feat: np.ndarray, cover: float) -> np.ndarray:
    """The ink cover per pixel: ``cover``, rising to 1 (solid ink allowed) with the
    depth ``feat`` of a small dark feature (:func:`_features`), full at ``_FEATURE_FULL``.

    Raising the features' darkness itself (an unsharp mask at their scale) made them
    read more but lowered tone r on a portrait (0.86 -> 0.81 at half gain): it darkens
    every fine dark texture (hair, folds) as well."""
    return cover + (1.0 - cover) * np.clip(np.asarray(feat, np.float64) / _FEATURE_FULL, 0.0, 1.0)


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


@numba.njit(cache=True)
def _pav_down(start, nodes, width, weight):
    """Non-increasing least-squares fit (pool adjacent violators) of ``width`` along
    each run ``nodes[start[k]:start[k + 1]]``, weighted by ``weight``; in place."""
    m = nodes.size
    val = np.empty(m)
    wt = np.empty(m)
    cnt = np.empty(m, np.int64)
    for k in range(start.size - 1):
        a, b = start[k], start[k + 1]
        top = 0
        for i in range(a, b):
            v = nodes[i]
            val[top] = width[v]
            wt[top] = weight[v]
            cnt[top] = 1
            top += 1
            # a later block wider than the one before it: pool them (weighted mean)
            while top > 1 and val[top - 1] > val[top - 2]:
                ws = wt[top - 2] + wt[top - 1]
                val[top - 2] = (val[top - 2] * wt[top - 2] + val[top - 1] * wt[top - 1]) / ws
                wt[top - 2] = ws
                cnt[top - 2] += cnt[top - 1]
                top -= 1
        i = a
        for j in range(top):
            for _ in range(cnt[j]):
                width[nodes[i]] = val[j]
                i += 1


def _slim_twigs(d: Dendrite, width: np.ndarray, aspect=0.0, floor: float = 0.0,
                fork_cap: float = 0.0) -> np.ndarray:
    """Twigs never wider toward their ends (beyond the paper): along every terminal
    twig (a branch with no side branch) the widths become the closest non-increasing
    profile, weighted by the segments' lengths, so each twig keeps its ink; with
    ``fork_cap`` > 0 no wider than ``fork_cap`` times the branch at their fork (down to
    ``floor``), which drops the ink beyond.

    The tone match widens a node by the ink missing around it: the base of a twig,
    next to its parent branch, had ink enough and stayed thin while the twig's end
    in a dark region grew wide, and such club-shaped twigs (a stalk ending in a
    round blob) read as dots or leaves rather than twigs: 15 % of the twigs of a
    500-px portrait and a 750-px night photo had their last third 1.25x wider than
    their first. See :mod:`branchnb.dendrite.pareidolia` for the measurements.
    """
    bp = d.branch_parent
    if d.n_nodes == 0 or bp.size == 0:
        return width
    n_child = np.bincount(bp[bp >= 0], minlength=len(bp))
    sel = [b for b in np.flatnonzero((n_child == 0) & (bp >= 0)) if len(d.branches[b]) > 2]
    runs = [d.branches[b][1:] for b in sel]
    if not runs:
        return width
    nodes = np.concatenate(runs).astype(np.int64)
    start = np.concatenate([[0], np.cumsum([len(r) for r in runs])]).astype(np.int64)
    has = d.parent >= 0
    seg = np.zeros(d.n_nodes)
    step = d.points[has] - d.points[d.parent[has]]
    seg[has] = np.hypot(step[:, 0], step[:, 1])
    out = np.array(width, np.float64, copy=True)
    _pav_down(start, nodes, out, seg + 1e-6)
    if fork_cap > 0:
        # nor wider than the branch they hang from at the fork (the pipe model's rule):
        # in a light region the tone match thinned a twig to a pale line and left its
        # end twigs 2x as wide, dark flecks along it (a third of the end twigs of a
        # 600-px portrait were > 0.5 px wider than their fork)
        fork = np.repeat(np.array([d.branches[b][0] for b in sel]), np.diff(start))
        out[nodes] = np.minimum(out[nodes], np.maximum(fork_cap * out[fork], floor))
    asp = np.asarray(aspect, np.float64)
    if asp.ndim:  # per node: each twig takes the mean over its nodes
        asp = np.add.reduceat(asp[nodes], start[:-1]) / np.diff(start)
    if np.any(asp > 0):  # a twig at least `aspect` times as long as it is wide (no beans)
        length = np.add.reduceat(seg[nodes], start[:-1])
        lim = np.repeat(np.where(asp > 0, length / np.maximum(asp, 1e-9), np.inf), np.diff(start))
        out[nodes] = np.minimum(out[nodes], np.maximum(lim, floor))
    return out


_FORK_CAP = 1.0  # a terminal twig at most this times its fork's width (0: off)
_TWIG_ASPECT = 3.0  # a twig at least this many times as long as it is wide (slim) ...
_DARK_ASPECT = 6.0  # ... and this many times in the picture's dark parts (beyond the paper)
_FEATURE_ASPECT = 1.5  # ... and this many times in a small dark feature (an eye, a mouth)


def _feature_share(cover, base: float):
    """How much of a small dark feature (0-1) a node is in, from the cover it was given."""
    return np.clip((np.asarray(cover, np.float64) - base) / max(1.0 - base, 1e-9), 0.0, 1.0)


def _twig_aspect(dark: np.ndarray, feature=0.0) -> np.ndarray:
    """The least length / width of a twig at darkness ``dark`` (its blurred target):
    ``_TWIG_ASPECT`` up to 0.5, rising to ``_DARK_ASPECT`` at 0.8 and above. In a dark
    region the tone match made twigs about 5x as long as wide, short strokes in a mass;
    capped at 6x, their ink goes into the branches they hang from (a pipe-model look).
    In the light and mid tones the twigs' ends draw the picture's small features (eyes,
    a mouth) and keep the paper's 3x: capped at 6x everywhere, tone r at 4 px blur on a
    portrait fell 0.87 -> 0.85. In a small dark feature (``feature`` 1, see
    :func:`_features`) it falls to ``_FEATURE_ASPECT``: a mouth a few twig spacings
    wide has no twig 6x as long as the mouth must be wide, and was drawn blank."""
    t = np.clip((np.asarray(dark, np.float64) - 0.5) / 0.3, 0.0, 1.0)
    a = _TWIG_ASPECT + (_DARK_ASPECT - _TWIG_ASPECT) * t
    return a + (_FEATURE_ASPECT - a) * np.asarray(feature, np.float64)


_REFINE_SIGMA = 3.0  # px of the output: a little finer than the 4 px at which tone is judged
_LIMB_BUDGET = 1.0
_LIMB_SPAN = 0.25
_LIMB_MIN = 0.5
_REFINE_GAIN = 0.7  # exponent on the correction (damped: neighbours share the blur)


def _refine_tone(d: Dendrite, dark: np.ndarray, bounds: dict, s: float,
                 p: PareidoliaParams, cover: np.ndarray | None = None) -> Dendrite:
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
    floor = np.where(f >= 0.3 * bounds["cap"].max(), f, 0.0)
    # the limbs' pipe widths scale with the drawing, their limb_width (2x a twig, which
    # stays about as fine in output px at every size) does not
    limb = np.asarray(bounds.get("limb", np.zeros_like(f)))
    base = np.minimum(limb, p.limb_width)
    ramp = np.asarray(bounds.get("ramp", np.zeros_like(f)))
    keep = 1.0 - _LIMB_BUDGET * ramp
    floor = np.minimum(np.maximum(floor * s * keep, base * min(s, 1.0) * (1.0 - (1.0 - _LIMB_MIN) * (1.0 - keep))
                                  + (limb - base) * s * keep), width)
    cap = np.maximum(bounds["cap"] * s, width)
    smooth = 3  # render()'s default
    h, w = d.shape
    at = np.rint(d.smoothed_points(smooth)).astype(int)
    row, col = np.clip(at[:, 1], 0, h - 1), np.clip(at[:, 0], 0, w - 1)
    target = ndimage.gaussian_filter(np.asarray(dark, np.float64), _REFINE_SIGMA)[row, col]
    cover_n = p.cover if cover is None else np.maximum(ndimage.gaussian_filter(
        np.asarray(cover, np.float64), _REFINE_SIGMA)[row, col], p.cover)
    fshare = _feature_share(cover_n, p.cover)
    aspect = _twig_aspect(target, fshare)
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
        # a small feature aims at its own darkness, not the crown's compressed tone
        want = _soft_cap(gain * target * (1.0 + fshare * (1.0 / max(gain, 1e-6) - 1.0)), cover_n)
        ratio = np.clip((want + 1e-3) / (have + 1e-3), 0.5, 2.0) ** _REFINE_GAIN
        width = np.where(inside, np.clip(width * ratio, np.maximum(lo, floor), cap), width)
        if p.slim:  # in the loop, so the next pass puts the ink it takes back elsewhere
            width = _slim_twigs(d, width, aspect, p.tip_width * 0.4 * s, _FORK_CAP)
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
    if np.ndim(black):  # per pixel (small features may be solid), block means like dark
        bpad = np.pad(np.asarray(black, np.float64), ((0, hs * f - h), (0, ws * f - w)), mode="edge")
        black = ndimage.gaussian_filter(_shrink(bpad, f), sigma / f)
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


#: Share of histogram equalisation in :func:`_stretch` (the rest: the linear stretch).
_EQUALIZE = 0.5


def _stretch(dark: np.ndarray, crown: np.ndarray, contrast: float,
             equalize: float = _EQUALIZE) -> np.ndarray:
    """The darkness stretched so its 1st-99th percentiles in the crown span [0, 1]
    (gain at most 5), half of it equalised over the crown's histogram, blended with
    the original by ``contrast``.

    Equalising (beyond the paper) spreads the tones most of the crown has: a night
    photo's sky (darkness 0.6-0.85 over 95 % of the crown) got nearly even ink, its
    gradient lost in the twigs' texture and the lit rocket hardly lighter (tone r at 4
    px blur 0.50 at 500 px, 0.53 at 2000 px); with half the map equalised 0.62 / 0.64.
    On a portrait, a cup photo, a dark camera photo, a dimmed cat photo and a dark drawn
    portrait r went from 0.87 0.89 0.83 0.85 0.87 to 0.87 0.90 0.84 0.88 0.87 (fully
    equalised the drawn portrait's few flat tones fell to 0.81). The limbs are planned
    on the linear stretch only (``equalize=0``): on the equalised map they reached
    less far into a portrait's crown.
    """
    if contrast <= 0 or not crown.any():
        return dark
    inside = dark[crown]
    lo, hi = np.percentile(inside, [1.0, 99.0])
    full = np.clip((dark - lo) / max(hi - lo, 0.2), 0.0, 1.0)
    if hi - lo > 1e-3 and equalize > 0:  # a flat picture stays flat
        # mid-ranks (ties share one), the crown's lightest tone at 0 and its darkest at 1
        vals = np.sort(inside[:: max(1, inside.size // 200_000)])
        rank = np.searchsorted(vals, dark, "left") + np.searchsorted(vals, dark, "right")
        r0, r1 = (np.searchsorted(vals, v, "left") + np.searchsorted(vals, v, "right")
                  for v in (vals[0], vals[-1]))
        eq = np.clip((rank - r0) / max(r1 - r0, 1), 0.0, 1.0)
        # a nearly flat picture (range < 0.1) keeps the linear stretch's gain of 5 at most
        share = equalize * float(np.clip((hi - lo - 0.1) / 0.1, 0.0, 1.0))
        full = (1.0 - share) * full + share * eq
    return ((1.0 - contrast) * dark + contrast * full).astype(np.float32)


def _tone_map(dark: np.ndarray, crown: np.ndarray, mean: float = 0.5) -> np.ndarray:
    """The (stretched) darkness raised to the power ``g >= 1`` that brings its mean in
    the crown to ``mean`` (unchanged where it is lighter already).

    Beyond the paper: a photo dark all over (a night sky) kept most of its crown in the
    darkest tones even after the stretch (mean 0.64 on the night photo of a rocket), where
    ``cover`` bends the ink toward its cap: the sky and the towers against it got nearly
    the same ink and the picture read only as a lighter column (the lit rocket). The
    power lightens the bulk of the tones and keeps the darkest dark, so what stands out
    against a dark ground (towers, a figure) stays darker than it. Ranks are kept. On a
    procedural wide night picture (dark sky, two darker towers, a lit column) the towers'
    ink over the sky's next to them at 4 px blur went 0.27 -> 0.37, tone r at 4 px 0.80 ->
    0.73; the rocket at 300 / 700 px 0.880 / 0.772 -> 0.857 / 0.761 (with the domed crown),
    a darkened astronaut 0.921 -> 0.929 (``python -m branchnb.dendrite._dome_check``). A
    linear scale to the same mean kept the tone scale straight but drew the towers worse
    (0.22, r 0.78).
    """
    if mean <= 0 or not crown.any():
        return dark
    inside = np.clip(np.asarray(dark, np.float64)[crown], 0.0, 1.0)
    inside = inside[:: max(1, inside.size // 100_000)]
    if inside.mean() <= mean:
        return dark
    lo, hi = 1.0, 8.0
    if (inside ** hi).mean() > mean:
        g = hi
    else:
        for _ in range(30):  # the mean falls with the power: bisect
            g = 0.5 * (lo + hi)
            lo, hi = (g, hi) if (inside ** g).mean() > mean else (lo, g)
        g = 0.5 * (lo + hi)
    return (np.clip(dark, 0.0, 1.0) ** g).astype(np.float32)


def _blurred_at(d: Dendrite, a: np.ndarray, sigma: float) -> np.ndarray:
    """``a`` blurred over ``sigma`` px at each node of ``d``, on a grid ``sigma // 2.5``
    times coarser (block means, a Gaussian of ``sigma / f``)."""
    h, w = a.shape
    f = max(1, int(sigma // 2.5))
    pad = np.pad(np.asarray(a, np.float64), ((0, -h % f), (0, -w % f)), mode="edge")
    g = ndimage.gaussian_filter(_shrink(pad, f), sigma / f)
    ys, xs = np.divmod(d.nodes, w)
    return g[ys // f, xs // f]


_LIMB_BODY = 0.8  # share of a limb's length at which it reaches w_end
_LIMB_LIGHT = 0.3  # a limb's width in the crown's white parts, as a share of its pipe width
_LIMB_DARK = 1.0  # darkness from which a limb in the crown has its full pipe width
_LIMB_RELATIVE = True  # ... and only in the darkest parts of the crown's own range of tone


def _limb_widths(d: Dendrite, first_seed: int, w0: float, w_end: float,
                 w_tip: float) -> np.ndarray:
    """Widths of the trunk and main limbs (the nodes of iteration 1) by the pipe model
    over their ends (beyond the paper's pipe model over all twigs, whose widths fall
    soon after the fork because the twigs hang mostly from the limbs' lower parts).

    Each end ``e`` of the iteration-1 tree (a limb's end, or the trunk's own top) owns a
    pipe of cross-section ``a_e`` that falls linearly along its path from ``w0 ** 2 / E``
    at the first limb's departure (node ``first_seed``) to ``w_end ** 2`` at
    ``_LIMB_BODY`` of its length, then to ``w_tip ** 2`` at the end; a
    node's width is ``sqrt`` of the sum over the ends it carries. A parent's width squared
    is the sum of its children's (Leonardo's rule) at every junction, the trunk tapers
    above each departure, its top (where no limb continues) ends at ``w_end`` instead of
    a round cap of the trunk's width (a knob), and every limb stays at least ``w_end``
    wide over most of its length. 0 off iteration 1.
    """
    n = d.n_nodes
    out = np.zeros(n)
    is1 = d.iteration == 1
    if not is1.any():
        return out
    par = d.parent
    child1 = np.zeros(n, bool)
    child1[par[is1 & (par >= 0)]] = True
    ends = np.flatnonzero(is1 & ~child1)
    arc = d.arc_depth()
    arc0 = arc[min(max(first_seed, 0), n - 1)]
    a0 = w0 ** 2 / len(ends)
    a1 = min(w_end ** 2, a0)
    for e in ends:
        path = [e]
        while par[path[-1]] >= 0:
            path.append(par[path[-1]])
        path = np.asarray(path)
        t = np.clip((arc[path] - arc0) / max(arc[e] - arc0, 1e-6), 0.0, 1.0)
        # linear from a0 to a1 over the first _LIMB_BODY of the path, then to a twig's
        # width at the end (a limb that tapers, not a blunt stub)
        body = np.minimum(t / _LIMB_BODY, 1.0)
        end = np.clip((t - _LIMB_BODY) / (1.0 - _LIMB_BODY), 0.0, 1.0)
        out[path] += (a0 + (a1 - a0) * body) * (1.0 - end) + w_tip ** 2 * end
    out = np.sqrt(out)
    out[~is1] = 0.0
    return out


def _thickness(d: Dendrite, p: PareidoliaParams, imp, dark, crown, n_trunk: int,
               bounds: dict | None = None, first_seed: int | None = None,
               cover: np.ndarray | None = None, ground: np.ndarray | None = None) -> Dendrite:
    """Pipe model + importance emphasis; tone-matched under a limb cap inside the crown,
    the trunk and main limbs at least their :func:`_limb_widths`; tapered twig ends.
    ``ground``: the blank ground inside a tree crown round an object, where the trunk and
    limbs keep their pipe widths (it is no part of the picture to keep light)."""
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
    if p.tone <= 0 or not inside.any():
        inside[:n_trunk] = False
        return d.with_radius(_taper_ends(d, width, dist, p.taper) / 2)
    if first_seed is None:
        first_seed = max(1, round(n_trunk * 0.75)) - 1
    limb = _limb_widths(d, first_seed, float(width[first_seed]), p.limb_width, p.tip_width)
    is1 = d.iteration == 1
    # in the crown's light parts the limbs narrow (their width beyond limb_width to
    # _LIMB_LIGHT at no darkness): at full width they crossed a light chin as dark bands
    shade = _blurred_at(d, dark, 2.0 * p.tone_sigma)
    full = np.clip(shade / _LIMB_DARK, 0.0, 1.0)
    if _LIMB_RELATIVE and crown.any():
        # ... and in the crown's lighter parts relative to its own range of tone: on a
        # picture dark all over (a night sky) the limbs kept their full pipe width
        # everywhere, dark bands across it that held 46 % of the tone error
        lo, hi = np.percentile(np.asarray(dark)[crown], [5.0, 95.0])
        full = np.minimum(full, np.clip((shade - lo) / max(hi - lo, 1e-3), 0.0, 1.0))
    light = _LIMB_LIGHT + (1.0 - _LIMB_LIGHT) * full
    arc = d.arc_depth()
    fork_arc = arc[n_trunk - 1] if n_trunk > 0 else 0.0
    from_fork = np.maximum(arc - fork_arc, 0.0)
    # ... gradually over a quarter of limb_length from the fork (so the limbs' bases stay
    # as wide as the pipe model says), and outside the crown too (a limb crossing the
    # blank between two objects had its full pipe width, then stepped down at the crown)
    ramp = np.clip(from_fork / (0.25 * p.limb_length), 0.0, 1.0)
    gnd = np.zeros(d.n_nodes, bool) if ground is None else np.asarray(ground, bool).ravel()[d.nodes]
    # the trunk's top narrows likewise from where it enters the crown (the picture in it:
    # not the blank ground round an object, where it stepped down as it met the object)
    pic = inside & ~gnd
    if pic[:n_trunk].any():
        entry = arc[int(np.argmax(pic[:n_trunk]))]
        ramp[:n_trunk] = np.clip((arc[:n_trunk] - entry) / (0.25 * p.limb_length), 0.0, 1.0)
    light = np.where(gnd, 1.0, 1.0 - (1.0 - light) * ramp)
    budget = np.clip(from_fork / (_LIMB_SPAN * p.limb_length), 0.0, 1.0)
    if pic[:n_trunk].any():
        budget[:n_trunk] = np.clip((arc[:n_trunk] - entry) / (_LIMB_SPAN * p.limb_length), 0.0, 1.0)
    budget[gnd] = 0.0
    thin = np.minimum(limb, p.limb_width)  # the limbs keep limb_width, the rest narrows
    limb = thin + (limb - thin) * light
    structural = is1 & (np.arange(d.n_nodes) >= first_seed)
    # inside the crown, the trunk's top (above the limbs' departures) narrows with its
    # limb widths instead of ending in a round cap of the trunk's width (a knob)
    # twigs' cap: the fork's pipe width, thinning to max_width along the path from the fork
    if p.taper > 0:
        # taper before the tone match too, which then puts the ink back along the
        # twigs instead of losing it
        width = width * _taper_profile(dist, p.taper)
    cap = np.maximum(p.max_width, width * np.exp(-from_fork / p.limb_length))
    floor = np.minimum(width * np.exp(-from_fork / p.limb_length), cap)
    cap = np.where(is1, np.maximum(p.max_width, limb), cap)
    floor = np.where(is1, limb, floor)
    w_tone = width
    aspect = _twig_aspect(_blurred_at(d, dark, p.tone_sigma), 0.0 if cover is None else
                          _feature_share(_blurred_at(d, cover, p.tone_sigma), p.cover))
    black = min(0.7, p.cover)
    if cover is not None:  # small features may be solid: black rises to 1 with the cover
        black = black + (1.0 - black) * np.clip((cover - p.cover) / max(1.0 - p.cover, 1e-9),
                                                0.0, 1.0)
    match = _tone_matcher(d, dark, p.tone_sigma, p.tone, black)
    for _ in range(_TONE_ROUNDS if p.taper > 0 else 1):
        # the tone match thickens a dark region's twig ends as much as their bodies (more:
        # less ink around an end): taper them again and match again, so the ink taken
        # from the ends goes back into the bodies
        w_tone = np.clip(match(w_tone, p.tip_width * 0.4, float(cap.max())), floor, cap)
        if p.slim:
            w_tone = _slim_twigs(d, w_tone, aspect, p.tip_width * 0.4, _FORK_CAP)
        if p.taper > 0:
            w_tone = _taper_ends(d, w_tone, dist, p.taper)
    # a slight flare at the foot of the trunk
    height = d.points[:, 1].max() - d.points[:, 1]
    flare = 1.0 + 0.35 * np.clip(1.0 - height / (0.12 * d.shape[0]), 0.0, 1.0) ** 2
    flare[n_trunk:] = 1.0
    # outside the crown, the trunk above the limbs' departures and the limbs have their
    # limb widths (the pipe over all twigs made a step where they entered the crown)
    # ... and so does the trunk on the blank ground inside a tree crown round an object
    # (there it stepped from the pipe over all twigs down to the limbs' pipe, 13 -> 6 px)
    inside = inside & ~(gnd & (np.arange(d.n_nodes) < n_trunk))
    out = np.where(inside, w_tone, np.where(structural, limb, width * flare))
    if p.taper > 0:
        out = _taper_ends(d, out, dist, p.taper)
    if bounds is not None:  # what the output-resolution pass may change, and how far
        bounds.update(inside=inside, floor=floor, cap=cap, dist=dist, limb=limb, ramp=budget * inside)
    return d.with_radius(out / 2)
