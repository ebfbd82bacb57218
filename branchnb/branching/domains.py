"""Domain handling of structure synthesis: deltas that drain, maps whose rivers keep off the coast.

Beyond the paper, whose Markov chain has no notion of a domain: an example
whose roots lie far inland and whose tips end at the region outside its
domain *drains* (a delta, :func:`_drains`; its branches are pulled downstream,
:class:`_Drain`); an example whose roots start at its domain's edge (rivers
from a coast) keeps its branches off that edge (:class:`_Shore`), and its
roots may not hook back at their mouth (``MOUTH_SHARE``, ``MOUTH_TURN``).
Used by :mod:`~branchnb.branching.growth`; split from :mod:`~branchnb.branching.synthesis`.
This module builds the domain's ground and tells a delta that drains; the drain's pull lives in
:mod:`.drain`, the shore's rules in :mod:`.shore` (re-exported here).
"""

from __future__ import annotations

import numpy as np

from ..core.structure import Structure
from .delta_fan import head_share  # noqa: F401  (moved; read from here by the growers and tests)
from .roots import outlet_starts


def _frame(s: Structure) -> tuple[int, int]:
    if s.image_shape is not None:
        return tuple(int(v) for v in s.image_shape[:2])
    _x0, _y0, x1, y1 = s.bounds()
    return int(np.ceil(y1)) + 2, int(np.ceil(x1)) + 2


#: An outside part of a domain no example vertex comes this close to (share of the frame's short side) is
#: ground the example keeps away from, not a coast (:func:`_ground`).
GROUND_DISTANCE = 0.06
#: ... and so is an outside part whose edge keeps within this share of its median distance from the
#: example's vertices everywhere, and at least :data:`BAND_GAP` pixels: a band drawn round its lines
#: (its margin is at least ``empty_ground.BAND_MIN``; a coast traced as a line runs closer)
BAND_STEADY = 0.5
BAND_GAP = 7.0


def _ground(ex: Structure, domain: np.ndarray | None) -> np.ndarray | None:
    """The parts outside ``domain`` that every vertex of ``ex`` keeps farther than
    :data:`GROUND_DISTANCE` x the frame's short side from, or None.

    Beyond the paper (issue 23): :func:`~branchnb.branching.example_domain` leaves the empty part of a
    line mask (cracks over the lower half of the frame) out of the domain, so no branch grows there.
    It is no coast and no sea, though: a river reaches its coast, a delta's channels the sea, a leaf's
    veins its margin. Counted as a region outside, the domain became a band shaped by the example's own
    lines; any new layout left holes in it, far-hole filling grew into them and a wavy vine came out
    1.10-1.31 x the example's length (the whole frame: 0.96-1.04). Coverage, holes, roots, the length
    cap and the drain read the domain plus this ground (:attr:`.model.StructureModel.region`).
    An outside part whose edge keeps a steady distance (:data:`BAND_STEADY`, :data:`BAND_GAP`) from
    the example's lines is ground too: the band :func:`.empty_ground._line_domain` draws round a vine
    ornament's strands, which no strand reaches (a coast is reached by its rivers; branching53).

    Examples
    --------
    >>> from branchnb.core.structure import Branch
    >>> ex = Structure([Branch(np.c_[np.linspace(2, 97, 40), np.full(40, 80.0)], 1.0)], image_shape=(100, 100))
    >>> dom = np.ones((100, 100), bool); dom[:40] = False          # the top, far from the line
    >>> int(_ground(ex, dom).sum())
    4000
    >>> dom[:, :] = True; dom[85:] = False                          # the line runs along it: a coast
    >>> _ground(ex, dom) is None
    True
    """
    if domain is None or domain.all() or not ex.branches:
        return None
    from scipy import ndimage as ndi

    out = ~np.asarray(domain, bool)
    h, w = out.shape
    near = np.zeros((h, w), bool)
    pts = np.concatenate([np.asarray(b.points, np.float64).reshape(-1, 2) for b in ex.branches])
    xi = np.clip(np.rint(pts[:, 0]).astype(np.int64), 0, w - 1)
    yi = np.clip(np.rint(pts[:, 1]).astype(np.int64), 0, h - 1)
    near[yi, xi] = True
    d = ndi.distance_transform_edt(~near)
    lab, n = ndi.label(out)
    if n == 0:
        return None
    idx = np.arange(1, n + 1)
    closest = np.asarray(ndi.minimum(d, lab, index=idx))
    keep = closest > GROUND_DISTANCE * min(h, w)
    # a band round the example's lines (:func:`.empty_ground._line_domain`): its edge keeps a steady
    # distance from them, where a coast is touched by the rivers it drains
    rim = out & ndi.binary_dilation(~out)
    if rim.any():
        rim_min = np.asarray(ndi.minimum(d, lab * rim, index=idx))
        rim_med = np.asarray(ndi.median(d, lab * rim, index=idx))
        keep |= (rim_min >= BAND_STEADY * rim_med) & (rim_min >= BAND_GAP)
    if keep.any() and _coast_reached(ex, out):
        # a map's rivers start at a coast: its other sea pieces (a bay cut off by land running to the
        # frame) are sea no river drains to, not ground (beyond the paper, issue 23: read as ground,
        # the domain took that sea in, the output's land covered it and roots started at the frame's
        # edge of it, 60-137 px inland of the example's coast)
        keep[:] = False
    keep = np.r_[False, keep]
    g = keep[lab]
    return g if g.any() else None


#: A root starting within this share of the frame's short side (and 3 px) of an outside part starts at
#: its edge: the example's rivers drain to that coast (:func:`_coast_reached`).
COAST_REACH = 0.03


def _coast_reached(ex: Structure, out: np.ndarray) -> bool:
    """Whether a root of ``ex`` starts at the edge of ``out`` (the parts outside the domain; within
    :data:`COAST_REACH` of the frame's short side): the outside is a sea its rivers drain to."""
    from scipy import ndimage as ndi

    h, w = out.shape
    starts = np.array([b.points[0] for b in ex.branches if b.parent is None and len(b.points)], np.float64)
    if not len(starts):
        return False
    d = ndi.distance_transform_edt(~out)
    xi = np.clip(np.rint(starts[:, 0]).astype(np.int64), 0, w - 1)
    yi = np.clip(np.rint(starts[:, 1]).astype(np.int64), 0, h - 1)
    return bool(np.any(d[yi, xi] <= max(COAST_REACH * min(h, w), 3.0)))


def _drains(ex: Structure, domain: np.ndarray | None) -> bool:
    """True when the example's roots lie far inland (over 30 % of the deepest distance to the
    region outside the domain) and at least a third of its branches end at that region (within 10 %;
    braided channels cut into a tree have other ends where the cycles were cut).

    Every branch's end counts, a parent's too: a child leaves its parent at one of its vertices, so
    the parent's last point is an end of the network like any tip. Counted on childless branches
    only, a delta whose trunk and first channel reach the sea but carry children (a 1000 x 1500 px
    delta mask cut into 6 branches: 3 of 6 ends at the sea, 1 of 4 childless ones) was not seen to
    drain, and its synthesized channels wandered inland (0-1 of them reached the sea in 5 of 5 seeds).
    """
    if domain is None or domain.all() or not domain.any():
        return False
    from scipy import ndimage as ndi

    depth = ndi.distance_transform_edt(domain)
    deepest = float(depth.max())
    h, w = domain.shape

    def at(p):
        x, y = np.clip(np.rint(p).astype(int), 0, [w - 1, h - 1])
        return depth[y, x]

    # a tree rooted at a source whose one end at the coast is its mouth drains there (a river map
    # traced the wrong way round, see roots.outlet_starts), its mouth is no tip
    mouths = outlet_starts(ex, domain)
    roots = [at(q) for q in mouths]
    mouth_px = {tuple(np.rint(q).astype(int)) for q in mouths}
    tips = [at(b.points[-1]) for b in ex.branches
            if len(b.points) and tuple(np.rint(b.points[-1]).astype(int)) not in mouth_px]
    return bool(roots and tips and np.median(roots) > 0.3 * deepest
                and np.mean(np.asarray(tips) < 0.1 * deepest) >= 1 / 3)


# split by step (issue split19): the drain's pull and fan (.drain), the shore (.shore); every name stays
# importable from here, and the growers and tests read them from here
from .drain import (  # noqa: E402,F401
    AXIS_MIN,
    BEARING_WEIGHT,
    DRAIN_KAPPA,
    FAN_CHILD,
    FAN_FRAME_GUARD,
    FAN_HOLD,
    FAN_KAPPA_GAIN,
    FAN_MAX,
    FAN_SPLIT,
    FAN_SPLIT_MIN,
    FAN_STRAIGHT,
    FAN_WEIGHT,
    FAN_WHOLE,
    FAN_WINDOW,
    FRAME_POWER,
    HEAD_PULL,
    STRAIGHT_TAIL,
    TAIL_MAX,
    TRUNK_HOLD,
    TRUNK_TAIL,
    UPSTREAM_COS,
    _Drain,
    fan_spread,
)
from .shore import (  # noqa: E402,F401
    ALONG_BAND,
    ALONG_EXAMPLE_MAX,
    ALONG_KAPPA,
    MOUTH_SHARE,
    MOUTH_TURN,
    SHORE_QUANTILE,
    SHORE_SKIP,
    _along_share,
    _Shore,
    _shore_margin,
    _shore_margin_of,
    runs_inland,
)
