"""What the example bounds in a grown structure: radii, branch counts, a band's strand core.

Beyond the paper (issue 23): how much thicker (:func:`_radius_growth`) or, in a delta, thinner
(:func:`_radius_keep`) than at its start a synthesized branch may get, the pull of continued radii
back to the copied ones (:func:`_pull_radii`), how many branches a small example's output grows
before the density stop (:func:`_min_branches`) and the core of a band of one-pen strands
(:func:`_core`). Split from :mod:`branchnb.branching.growth` (issue 23, branching103), which
re-exports every name and reads the patchable ones (``RADIUS_PULL``, ``TAPER_LIKENESS``,
``TAPER_RESOLVED``) from its own namespace at each step.
"""

from __future__ import annotations

import numpy as np

from .child_angles import _one_pen
from .empty_ground import _is_band, _painted_core, _strand_core
from .model import StructureModel

#: Quantile of the example's branches' (thickest radius / first radius) that bounds a synthesized branch's.
RADIUS_GROWTH_QUANTILE = 0.9


def _radius_growth(example) -> float:
    """How much thicker than at its start a branch may get: the example's branches'
    ``max(r) / max(r_0, r_1)`` at :data:`RADIUS_GROWTH_QUANTILE`, at least 1."""
    ratios = [float(np.max(b.thickness)) / max(float(np.max(b.thickness[:2])), 1e-9)
              for b in example.branches if len(b.thickness) > 1]
    return max(1.0, float(np.quantile(ratios, RADIUS_GROWTH_QUANTILE))) if ratios else np.inf


#: The density (coverage) stop waits until the output has at least this many branches, or as many as
#: the example has of at least :data:`MIN_BRANCH_SHARE` x its longest branch's length (:func:`_min_branches`).
MIN_BRANCHES = 3
MIN_BRANCH_SHARE = 0.1


def _min_branches(model: StructureModel) -> tuple[int, float]:
    """How many branches the output grows, each at least how long (pixels), before the density stop
    may end it.

    Beyond the paper (issue 23): on a small example (a 128 px river map: a 100 px trunk and
    tributaries of 17-62 px) the coverage of the example's domain is reached by a trunk and one
    child (the trunk ran on past the example's, to the far side of the frame), and the output was a
    line with one side branch where the example has a trunk with two or three. Small examples only
    (long side <= :data:`~.small_frames.SMALL_SIDE` px, else ``(0, 0.0)``): a larger example's output
    has far more branches when its coverage is reached, and its first fill round may still come with
    fewer than three (a 512 px crack's did: starting children before re-opening tips then gave 21
    branches instead of 29), so larger examples are left as they were. Spurs (shorter than
    :data:`MIN_BRANCH_SHARE` x the longest branch) are not counted, in the example or in the output.
    """
    from .small_frames import SMALL_SIDE

    shape = model.example.image_shape
    lengths = np.asarray([b.length for b in model.example.branches], np.float64)
    if not len(lengths) or shape is None or max(shape) > SMALL_SIDE:
        return 0, 0.0
    need = MIN_BRANCH_SHARE * float(lengths.max())
    return int(min(MIN_BRANCHES, int(np.sum(lengths >= need)))), need


#: element (:func:`_pull_radii`); 0 = the pure relative continuation.
RADIUS_PULL = 0.05
#: A copied piece passes on its taper in proportion to how alike its input radius and the tip's are,
#: to this power (:func:`~branchnb.branching.scoring._continue_radii` ``like``; beyond the paper,
#: issue 23). 0 = the input's relative change copied whole. Not in a delta (its channels keep their
#: width). Known cost: a child whose head starts at the extraction's blurred junction width tapers off
#: it more slowly; on roots only, children copied whole tapers and 5 of a crack mask's leaf children
#: stopped as bare heads. Off by default (branching54; 2 = branching52's rule): its two failures are mended
#: (:data:`TAPER_RESOLVED`; a fill child stopping short no longer rules out a whole hole,
#: ``filling.PART_GROWN``), but with it the partial comb mask's placement bound is missed on its test
#: seed (0.216 vs 0.2) and a 450-px comb's roots still thin to 0.8 px, pulled to their input root's
#: profile (a frame-entry root that starts on a 1-px tooth, ``ROOT_PROFILE_PULL``).
TAPER_LIKENESS = 0.0
#: Radii are alike below this (pixels) for :data:`TAPER_LIKENESS` (``_continue_radii`` ``resolved``):
#: a line up to ~1.6 px wide (a 1-px line measures 0.75 px) has no width the extraction resolves, its
#: radius differences are blur and light (a 1.6-px bolt measures 0.84 px in a bright cloud, 0.62 px in
#: the dark sky), so such lines keep the paper's whole tapers. Without it the bolt's cloud-lit radius
#: was kept along the output and its fragments were matched from the cloud (20 % of the fragment
#: pixels against 2 %): a glowing tube of cloud (``test_branching_image_unseen``). At 1.0 px the comb
#: and crack masks' 1-px side lines lost part of the rule's gain (radius-histogram L1 0.32 -> 0.38).
TAPER_RESOLVED = 0.8


def _pull_radii(cont: np.ndarray, copied: np.ndarray, pull: float | None = None) -> np.ndarray:
    """Continued radii drawn back toward the copied input radii (beyond the paper, issue 23).

    The relative continuation (:func:`~branchnb.branching.scoring._continue_radii`) multiplies the
    input's tapers step after step: a random walk with no memory of the example's widths, so a trunk
    that starts at the example's thickest head stays that thick along its whole length (NOAA
    lightning: length-weighted 90th-percentile radius 2.2-2.3 px against 1.29 in the example). Element
    ``k`` of a step moves the fraction ``1 - (1 - pull) ** (k + 1)`` of the log gap to the copied
    radius: the radius never jumps by more than ``pull`` of the gap, and over a few steps the
    branch's widths follow the copied pieces' (the example's distribution). ``pull`` = 0.05 (default
    :data:`RADIUS_PULL`): NOAA lightning at 512 px, 6 seeds, 90th percentile 0.73-2.30 -> 0.73-1.15 px
    (example 1.29), thick-end share no higher; 0.1 or a pull that only thins overshot (thick-end share
    + 0.07-0.14 on NOAA, retina far share up to 1.9 x). Not applied in a delta, whose channels keep the
    width they start at (:func:`_radius_keep`, ``_Starts._channel_radius``).

    Examples
    --------
    >>> _pull_radii(np.array([2.0, 2.0]), np.array([0.5, 0.5]), 0.5).round(2)
    array([1.  , 0.71])
    """
    a = RADIUS_PULL if pull is None else float(pull)
    if a <= 0 or len(cont) == 0:
        return cont
    w = 1.0 - (1.0 - a) ** np.arange(1, len(cont) + 1)
    return cont * (np.maximum(copied, 1e-9) / np.maximum(cont, 1e-9)) ** w


#: :data:`RADIUS_PULL` of a root toward its input root's radius at the same arc length
#: (:meth:`~branchnb.branching.branch_starts._Starts._root_profile`).
ROOT_PROFILE_PULL = 0.05
#: The same for a hub's child toward its generation's taper (:func:`.radial._taper_profile`): children
#: are short (tens of elements), and at 0.05 the pull lagged the taper by half their length.
CHILD_PROFILE_PULL = 0.5


#: An example that drains (a delta): quantile of its branches' (thinnest radius over their first 90 % /
#: first radius) below which a synthesized channel may not thin.
RADIUS_KEEP_QUANTILE = 0.5



def _radius_keep(example) -> float:
    """How much thinner than at its start a delta's channel may get (beyond the paper, issue 23).

    The example's branches' ``min(r) / max(r_0, r_1)`` over their first 90 % (their last vertices
    thin where the mask meets the sea) at :data:`RADIUS_KEEP_QUANTILE`, at most 1. The copied tapers
    multiply step after step (``_continue_radii``) and the cap on thickening (:func:`_radius_growth`)
    left only the thinning: every channel of a 512-1000 px delta fell to the example's thinnest radius
    (length-weighted median radius 0.13-0.78 x the example's; after 0.8-1.2 x).
    """
    ratios = []
    for b in example.branches:
        t = np.asarray(b.thickness, np.float64)
        if len(t) > 2:
            ratios.append(float(t[: max(2, int(0.9 * len(t)))].min()) / max(float(t[:2].max()), 1e-9))
    return min(1.0, float(np.quantile(ratios, RADIUS_KEEP_QUANTILE))) if ratios else 0.0

#: A band strand's candidate scores ``exp(-d / CORE_SCALE)``, ``d`` its mean distance (pixels) outside the
#: band the example's strands sweep (:func:`.empty_ground._strand_core`; beyond the paper, issue 23,
#: branching66), roots and children alike (branching70): 7 px out weighs like ``LEAVE_BAND``. At 2 px on
#: roots only, children ran out to the frame and into the eye of the band: 0.36-0.48 of the length of
#: interlaced bands (L, U, frame, ring, S, spiral, knot, border; 256-1024 px, 3 seeds) outside the swept
#: band. At 0.5 px the strands kinked to stay in (turn per 10 px 1.06-1.34 x the example's on U and S
#: bands, against 0.82-1.12 x at 1 px, for 0-0.09 less length outside); a hard wall (the core as the
#: growth domain) ended an L band's root after 20-40 px (length 0.28 x).
CORE_SCALE = 1.0


def _core(model: StructureModel, domain) -> tuple[np.ndarray, np.ndarray] | None:
    """``(core, distance outside it)`` of a band of one-pen strands (:func:`.empty_ground._strand_core`),
    once per model and domain; else None (any other example or domain).

    In the model's own domain the example's lines say where the band is; in a band domain of the user's
    (another mask, or another size) the core is its middle strip in the example's proportions
    (:func:`.empty_ground._painted_core`; beyond the paper, issue 23, branching70)."""
    if domain is None or model.domain is None or model.ground is None or not _is_band(domain) \
            or not _one_pen(model.example):
        return None
    from scipy import ndimage as ndi

    got = model.__dict__.get("_strand_core")
    if got is None or got[0] is not model.domain:
        core = _strand_core(model.example, model.domain)
        got = model.__dict__["_strand_core"] = (
            model.domain, None if core is None else (core, ndi.distance_transform_edt(~core)), {})
    if got[1] is None or (domain.shape == model.domain.shape and np.array_equal(domain, model.domain)):
        return got[1]
    key = (domain.shape, hash(np.packbits(domain).tobytes()))
    if key not in got[2]:
        core = _painted_core(model.domain, got[1][0], domain)
        got[2][key] = None if core is None else (core, ndi.distance_transform_edt(~core))
    return got[2][key]



#: A delta's channel below a fork carries what its child does not (beyond the paper, issue 23,
#: branching103): its radius ``R`` drops to ``(R ** a - r ** a) ** (1 / a)`` for a child of start radius
#: ``r``, ``a`` this exponent. 2 = the channel's width grows as the square root of its discharge
#: (Leopold's hydraulic geometry), discharge conserved at the fork.
FORK_AREA_EXPONENT = 2.0
#: ... but never below this share of ``R`` at one fork (an even split leaves 0.71 x; a child as thick as
#: its parent, which the child's start rule allows, would leave none).
FORK_KEEP = 0.7
#: The drop runs over this many of the parent's vertices after the fork (the radius stays smooth).
FORK_SPAN = 6


def _thin_below_forks(radii: list[np.ndarray], parents: list, verts: list,
                      ratios: list | None = None) -> list[np.ndarray]:
    """Radii of a delta's channels thinned downstream of every fork (beyond the paper, issue 23).

    A copied taper keeps a channel's width along it (``_radius_keep``: the tapers once thinned every
    channel to the example's thinnest), so the trunk ran to the sea as wide as it entered, where the
    example's trunk narrows at each fork: a braided delta's output covered 1.4-1.9 x the example's
    channel area at 256-512 px. At each child (in order along the parent) the parent's radius from the
    fork on is scaled so ``R_after ** a + r_child ** a = R ** a`` (:data:`FORK_AREA_EXPONENT`), at
    least :data:`FORK_KEEP` x ``R``, the drop spread over :data:`FORK_SPAN` vertices.

    Parents come before their children (branching110): a child whose start ``max(r[:2])`` is more than
    ``ratios[i]`` (its fork ratio, ``branch_starts.fork_ratios``; 1 when None or not given) x its
    parent's radius at the fork once the parent is thinned by the forks above is scaled down as a whole,
    so no child starts thicker than its parent (children started where the parent had not yet thinned
    below an earlier fork came out up to 1.8 x their parent's radius on a 512 px bird-foot delta).

    Examples
    --------
    >>> out = _thin_below_forks([np.full(8, 4.0), np.full(3, 3.0)], [None, 0], [None, 2])
    >>> out[0].round(2).tolist()
    [4.0, 4.0, 4.0, 3.8, 3.6, 3.4, 3.2, 3.0]
    >>> out = _thin_below_forks([np.full(8, 4.0), np.full(3, 3.0), np.full(3, 4.0)], [None, 0, 0], [None, 2, 6])
    >>> round(float(out[2][0] / out[0][6]), 2)
    1.0
    """
    out = [np.asarray(r, np.float64).copy() for r in radii]
    kids: dict = {}
    for i, (p, v) in enumerate(zip(parents, verts)):
        if p is not None and v is not None and len(out[i]):
            kids.setdefault(int(p), []).append((int(v), i))
    a = FORK_AREA_EXPONENT
    # parents before children (roots first, then down the tree), each parent's forks in order along it
    order = [i for i, p in enumerate(parents) if p is None]
    seen = set(order)
    k = 0
    while k < len(order):
        for _v, c in sorted(kids.get(order[k], [])):
            if c not in seen:
                seen.add(c)
                order.append(c)
        k += 1
    order += [i for i in kids if i not in seen]
    for p in order:
        r = out[p]
        for v, c in sorted(kids.get(p, [])):
            R = float(r[min(v, len(r) - 1)])
            rc = float(np.max(out[c][:2]))
            q = 1.0 if ratios is None or ratios[c] is None else min(float(ratios[c]), 1.0)
            if rc > q * R > 0:
                out[c] *= q * R / rc
                rc = q * R
            if v >= len(r) - 1:
                continue
            after = max((max(R ** a - rc ** a, 0.0)) ** (1.0 / a), FORK_KEEP * R)
            f = after / max(R, 1e-9)
            n = len(r) - v - 1
            ramp = np.minimum(np.arange(1, n + 1) / FORK_SPAN, 1.0)
            r[v + 1:] *= 1.0 - (1.0 - f) * ramp
    return out
